"""The independent harness, JJF 2014: the other items a lab certifies from a calibration campaign.

Run: nice -n 10 .venv/bin/python benchmarks/independent_jjf2014_more.py [--devices 30]
     [--variants A,B] [--seed 1] [--json F] [--keep DIR]

benchmarks/independent_campaigns.py scores JJF 2014 7.2.1 K, 7.2.4 K_r and 7.2.13 B₀. This module
adds, with the same shared pieces (noise, outputs, campaign writer, scoring), devices and campaigns
for 7.2.2 K_n and range, 7.2.3 K_a, 7.2.5 K_t, 7.2.6 K_g, 7.2.15 B_r, 7.2.16 B_t, 7.2.17 B_g, 7.2.20
(ARW and the other Allan terms) and 7.2.11 / 7.2.12 (misalignment and its repeatability). As there,
the generators were written from the documentation (docs/data-format.md, ``metro plan -s jjf2014 -i
…``'s segment list) and the standard's clauses only; numpy makes the samples, no part of metro's
instruments or simulators is imported (tests/plugins/jjf2014/test_independent_more.py checks it).

The device (every variant; parameters drawn per device):

    output(Ω, condition) = K · k_on · k(T, g) · [ g(Ω) + (B(T, g) + earth + wander + noise)/3600 ]

with Ω the rate the table really turned at (°/s), g(Ω) = Ω·(1 ± a/2) + c₂·Ω²/Ω_m + c₃·Ω³/Ω_m²
(asymmetry a, quadratic and cubic nonlinearity), k_on the power-on's K factor (1σ σ_K), k(T, g) =
1 + κ₁ΔT + κ₂ΔT² + κ_g·g_IRA (K's temperature and axial-acceleration sensitivity), B = b_on +
β₁ΔT + β₂ΔT² + Σ_j β_g,j·g_j (°/h; bias turn-on scatter σ_b, temperature and g-sensitivity on
any axis and sign), noise white (ARW) + flicker (an Allan plateau) in °/h, output in mV or a
ratiometric mV/V of a declared supply, optionally rounded.

What the truth is (the standard's measurand on the constructed device, noise-free; the rate
table's set points, not its errors):

* 7.2.1 K, 7.2.2 K_n (eqs. (6)–(8)), 7.2.3 K_a (eq. (9)): eqs. (4), (7)–(9) applied to the device's
  noise-free mean outputs at the nominal rates of the campaign, with the K of that power-on.
* 7.2.2 range: the largest nominal rate whose symmetric span's noise-free K_n meets the device's
  ``nonlinearity_spec`` (as 7.2.2.2's last sentence reads).
* 7.2.5 K_t (eq. (11)): max_i |K_i/K_m − 1|/|T_i − T_m| of the noise-free K_i (one power-on
  through the chamber, 7.2.5.1 d)); 7.2.6 K_g: (K_up − K_down)/2 g noise-free (one power-on,
  7.2.6.1).
* 7.2.16 B_t (eq. (31)), 7.2.17 B_g: the bias of each record as the equivalent input rate (the
  device's own K at that record: its power-on and temperature) — bias + the wander's record mean
  — then eq. (31) / (B_up − B_down)/2 g per axis, the largest |·|; B_g with Ω_e·sin φ in the
  IRA's own pair when metro says the earth rate is ``included``.  The last column of the table
  (alt) counts each record's flicker mean as bias too.
* 7.2.15 B_r (eq. (30)): √ of the expectation of eq. (30)'s square: the variance over power-ons
  of F̄_i/K_cal, i.e. (K/K_cal)²·[σ_b² + (b + earth)²·σ_K² + Var(one record's noise mean)], the
  last term ARW²/T for white noise plus the flicker mean's variance (Monte Carlo of the generator).
* 7.2.20: ARW = the generator's white noise (°/√h); B = plateau/√(2 ln 2/π) when the device has
  flicker; Q, K_rrw, R are 0 (no angle quantization, rate random walk or ramp is made).
* 7.2.11 γ_m (eq. (25)): 10800/π·√(α² + β²) of the device's input axis; 7.2.12 γ_mr (eq. (26)):
  √E[s²] of the Q runs' γ_m, by Monte Carlo of the generator (noise, fixture re-seating).

Scored as in independent_campaigns.py: E_n = (result − truth)/U; not reportable counts as covered.
"""

from __future__ import annotations

import functools
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from independent_campaigns import (  # noqa: E402  (the shared pieces of the harness)
                                   DMM, OMEGA_E_DEG_H, RATE_TABLE, UNIT_ALIASES, Campaign, Noise,
                                   Output, Variant, build_with, flicker, run_variant, score, text,
                                   variants)

# the units of the items scored here, as metro may spell them
UNIT_ALIASES.setdefault("°/s", {"°/s", "deg/s", "degree / second", "(°)/s"})
UNIT_ALIASES.setdefault("1/°C", {"1/°C", "1 / delta_degree_Celsius", "1/delta_degC", "1/K", "/°C"})
UNIT_ALIASES.setdefault("°/h/°C", {"°/h/°C", "degree / hour / delta_degree_Celsius",
                                   "deg/h/delta_degC",
                                   "(°/h)/°C", "°/°C/h"})
UNIT_ALIASES.setdefault("°/h/g", {"°/h/g", "degree / hour / standard_gravity", "deg/h/gn",
                                  "(°/h)/g"})
UNIT_ALIASES.setdefault("mV/(°/s)/g", {"mV/(°/s)/g",
                                       "millivolt * second / degree / standard_gravity",
                                       "mV/(deg/s)/gn",
                                       "millivolt / degree * second / standard_gravity",
                                       "mV·s/°/g"})
UNIT_ALIASES.setdefault("°/√h", {"°/√h", "degree / hour ** 0.5", "deg/hour**0.5", "(°)/√h"})
UNIT_ALIASES.setdefault("°/h", set()).update({"degree / hour"})
UNIT_ALIASES.setdefault("′", {"′", "arcminute", "arcmin"})

BI_FACTOR = math.sqrt(2 * math.log(2) / math.pi)  # σ_A plateau = 0.664·B (IEEE Std 952)
R5_SETS = {  # 7.2.1.1 b): ≥ 11 R5 rates per direction including the largest
    100: (0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100),
    200: (0.16, 0.4, 1, 2.5, 6.3, 10, 25, 40, 63, 100, 160, 200),
    400: (0.25, 0.63, 1.6, 4, 10, 25, 40, 63, 100, 160, 250, 400),
    50: (0.1, 0.16, 0.25, 0.4, 0.63, 1, 2.5, 6.3, 16, 25, 40, 50),
}
TEMP_SETS = ((-40, -10, 20, 40, 60), (-20, 0, 20, 45, 70), (-40, 20, 60), (-10, 5, 20, 35, 50, 65))


# --------------------------------------------------------------------------------------------
# eqs. (4), (7)–(9), (11), (31), (25), written again here from the clauses (not metro's code)
# --------------------------------------------------------------------------------------------

def lsq(om: np.ndarray, F: np.ndarray) -> tuple[float, float]:
    """eq. (4), (5): K, F₀ by least squares."""
    n = om.size
    K = (n * (om * F).sum() - om.sum() * F.sum()) / (n * (om ** 2).sum() - om.sum() ** 2)
    return float(K), float(F.mean() - K * om.mean())


def kn_eq7_8(om: np.ndarray, F: np.ndarray) -> float:
    K, F0 = lsq(om, F)
    span = abs(om.max() - om.min())
    return float(np.max(np.abs((K * om + F0 - F) / (K * span))))


def range_722(om: np.ndarray, F: np.ndarray, limit: float) -> float | None:
    """The largest Ω_m whose points |Ω| ≤ Ω_m have K_n ≤ limit (7.2.2.2, last sentence)."""
    for top in sorted(set(np.abs(om).tolist()), reverse=True):
        sel = np.abs(om) <= top
        if sel.sum() < 3 or not (np.any(om[sel] > 0) and np.any(om[sel] < 0)):
            return None
        if kn_eq7_8(om[sel], F[sel]) <= limit:
            return float(top)
    return None


# --------------------------------------------------------------------------------------------
# the device
# --------------------------------------------------------------------------------------------

class Device:
    """A vibratory rate gyro with an analog output (module docstring)."""

    def __init__(self, rng, *, kind: str, q: float, K_range=(0.5, 200.0), neg=True, asym=1e-3,
                 c2=5e-4, c3=5e-4, shapes=("none", "quadratic", "cubic", "both"), arw=(0.05, 0.5),
                 flick=0.0, sigma_b=(1.0, 10.0), sigma_K=(5e-5, 4e-4), kt=(-3e-4, 3e-4), kt2=2e-6,
                 kg=(-5e-4, 5e-4), bt=(-0.5, 0.5), bt2=5e-3, bg=(-20.0, 20.0), wander=0.0,
                 orientation_sign: float = 1.0):
        self.rng = rng
        self.lat = float(rng.uniform(-80, 80))
        # °/h along a vertical IRA (up)
        self.earth = OMEGA_E_DEG_H * math.sin(math.radians(self.lat))
        mag = float(np.exp(rng.uniform(math.log(K_range[0]), math.log(K_range[1]))))
        self.K = -mag if neg and rng.uniform() < 0.5 else mag           # mV/(°/s)
        self.a = asym * float(rng.uniform(-1, 1))
        shape = shapes[int(rng.integers(len(shapes)))]
        self.shape = shape
        self.c2 = c2 * float(rng.uniform(-1, 1)) if shape in ("quadratic", "both") else 0.0
        self.c3 = c3 * float(rng.uniform(-1, 1)) if shape in ("cubic", "both") else 0.0
        self.noise = Noise(float(rng.uniform(*arw)), flicker=flick * float(rng.uniform(0.5, 1.5)),
                           wander_amp=wander * float(rng.uniform(0.5, 1.5)),
                           wander_period=float(rng.uniform(900, 3600)))
        self.sigma_b = float(rng.uniform(*sigma_b))
        self.sigma_K = float(rng.uniform(*sigma_K))
        self.b_mean = float(rng.uniform(-360, 360))
        self.kt1 = float(rng.uniform(*kt))
        self.kt2 = kt2 * float(rng.uniform(-1, 1))
        self.kg = float(rng.uniform(*kg))                                # per g along the IRA
        self.bt1 = float(rng.uniform(*bt))                               # °/h/°C
        self.bt2 = bt2 * float(rng.uniform(-1, 1))                       # °/h/°C²
        # bias g-sensitivity on each axis, any sign and size: one dominant axis, or all alike
        scale = float(rng.uniform(*bg))
        self.bg = {a: scale * float(rng.uniform(-1, 1)) for a in "XYZ"}
        self.supply = float(rng.uniform(4.5, 5.5))
        self.out = Output(kind, K=self.K, q=q, supply=self.supply)
        self.Om = 100.0

    def g(self, om):
        om = np.asarray(om, dtype=float)
        lin = np.where(om > 0, 1 + self.a / 2, 1 - self.a / 2) * om
        return lin + self.c2 * om ** 2 / self.Om + self.c3 * om ** 3 / self.Om ** 2

    def kfac(self, dT: float = 0.0, g_ira: float = 0.0) -> float:
        return 1 + self.kt1 * dT + self.kt2 * dT ** 2 + self.kg * g_ira

    def bias(self, dT: float = 0.0, gvec: dict | None = None) -> float:
        b = self.bt1 * dT + self.bt2 * dT ** 2
        for a, gv in (gvec or {}).items():
            b += self.bg[a] * gv
        return b

    def mean_out(self, om, k_on: float, dT=0.0, g_ira=0.0, b_on=0.0, earth=0.0) -> np.ndarray:
        """Noise-free mean output (mV) at the rates ``om`` (°/s)."""
        return self.K * k_on * self.kfac(dT, g_ira) * (self.g(om) + (b_on + earth) / 3600.0)

    def record(self, om_actual: float, n: int, dt: float, k_on: float, *, dT=0.0, g_ira=0.0,
               b=0.0, earth=0.0):
        """One record: (samples in the column's unit, wander mean °/h, flicker mean °/h)."""
        wh, fl, w = self.noise.draw3(n, dt, self.rng)
        sensed = (float(self.g(om_actual)) * 3600.0 + b + earth + wh + fl + w)   # °/h of input
        vals = self.out.record(sensed, dt, K_scale=k_on * self.kfac(dT, g_ira), rng=self.rng)
        return vals, float(w.mean()), float(fl.mean())

    def power_on(self) -> tuple[float, float]:
        """(k_on, b_on) of a new power-on: the K factor (1σ σ_K) and the bias (°/h, 1σ σ_b)."""
        return (1 + self.sigma_K * float(self.rng.standard_normal()),
                self.b_mean + self.sigma_b * float(self.rng.standard_normal()))

    def manifest_device(self, name: str, extra: dict | None = None) -> dict:
        d = {"id": name, "technology": "vibratory", "output": "analog"}
        if self.out.kind == "mV/V":
            d["supply_voltage"] = f"{self.supply!r} V"
        return d | (extra or {})


def _rate_cal(camp: Campaign, dev: Device, rates, terr, *, prefix: str, kind: str, n: int,
              dt: float,
              k_on: float, b_on: float, earth: float, cond: dict | None = None, dT=0.0,
              g_ira=0.0) -> None:
    """One 7.2.1.1 calibration: each rate forward then reverse, ``n`` samples at ``dt``."""
    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            actual = sgn * r * (1 + terr[r])
            vals, _, _ = dev.record(actual, n, dt, k_on, dT=dT, g_ira=g_ira, b=b_on, earth=earth)
            c = {"rate": f"{sgn * r!r} deg/s"} | (cond or {})
            camp.add(f"{prefix}{tag}{r}", kind, vals, dt, c)


def _signed_rates(rates) -> np.ndarray:
    return np.array([s * r for r in rates for s in (1, -1)], dtype=float)


def _table_errors(rng, rates) -> dict:
    """The table errs within its certificate (U = 1×10⁻⁴, k = 2): a fixed error per set point."""
    return {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * 0.5e-4 for r in rates}


# --------------------------------------------------------------------------------------------
# 7.2.1, 7.2.2, 7.2.3: nonlinearity, range, asymmetry
# --------------------------------------------------------------------------------------------

def build_nonlin(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str, flick: float = 0.0,
                 quick: bool = False, top: int | None = None) -> dict:
    dev = Device(rng, kind=kind, q=q, flick=flick)
    top = top or int(rng.choice(list(R5_SETS)))
    rates = R5_SETS[top]
    dev.Om = float(top)
    om = _signed_rates(rates)
    k_on, b_on = dev.power_on()
    F = dev.mean_out(om, k_on, b_on=b_on, earth=dev.earth)
    # a requirement between the noise-free K_n of two successive spans: the range is one of them
    kns = [kn_eq7_8(om[np.abs(om) <= t], F[np.abs(om) <= t]) for t
           in sorted(rates, reverse=True)[:8]]
    lo, hi = max(min(kns), 1e-7), max(max(kns), 2e-7)
    limit = float(np.exp(rng.uniform(math.log(lo), math.log(hi) + 0.7)))
    limit = float(f"{limit:.2g}")
    device = dev.manifest_device(folder.name, {"nonlinearity_spec": f"{limit!r}"})
    camp = Campaign(folder, device, dev.lat, [RATE_TABLE, DMM], fmt=fmt, output=dev.out)
    n = int(round((10.0 if not quick else 5.0) / dt))
    _rate_cal(camp, dev, rates, _table_errors(rng, rates), prefix="rate", kind="rate", n=n, dt=dt,
              k_on=k_on, b_on=b_on, earth=dev.earth)
    camp.write_manifest()
    K, _ = lsq(om, F)
    pos, neg = om > 0, om < 0
    Ka = abs(lsq(om[pos], F[pos])[0] - lsq(om[neg], F[neg])[0]) / abs(K)
    # (an mV/V column is read as mV at the declared supply: K in mV/(°/s) either way)
    truth = {("7.2.1", "K"): (K, "mV/(°/s)", ""),
             ("7.2.2", "Kn"): (kn_eq7_8(om, F), "", ""),
             ("7.2.3", "Ka"): (Ka, "", "")}
    rg = range_722(om, F, limit)
    if rg is not None:
        truth[("7.2.2", "range")] = (rg, "°/s", "")
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.5, 7.2.6, 7.2.16, 7.2.17: temperature and acceleration sensitivities
# --------------------------------------------------------------------------------------------

AXES = ("X", "Y", "Z")


def build_temp_g(folder: Path, rng, *, kind: str, q: float, dt_rate: float, dt_static: float,
                 fmt: str,
                 flick: float = 0.0, wander: float = 0.0, ira_axis: str = "Z", quick: bool = False,
                 repeats: bool = False) -> dict:
    """7.2.1 (K for every item dividing by it), 7.2.5 (K at each chamber point, one power-on), 7.2.6
    (K with the IRA up and down, one power-on), 7.2.16 (B₀ at each chamber point, one power-on),
    7.2.17 (X, Y, Z each up and down, one power-on); the IRA is ``ira_axis`` of the case (X/Y
    records with it horizontal, east–west)."""
    dev = Device(rng, kind=kind, q=q, flick=flick, wander=wander)
    rates = R5_SETS[100]
    om = _signed_rates(rates)
    temps = TEMP_SETS[int(rng.integers(len(TEMP_SETS)))]
    room = 20.0
    extra = {} if ira_axis == "Z" else {"ira_axis": ira_axis}
    camp = Campaign(folder, dev.manifest_device(folder.name, extra), dev.lat,
                    [RATE_TABLE, DMM, {"id": "CH-X", "role": "chamber",
                                       "calibration": {"certificate": "IND-CH-1", "U": "0.5 degC",
                                                       "k": 2}},
                     {"id": "PT-X", "role": "position_table"}],
                    fmt=fmt, output=dev.out)
    terr = _table_errors(rng, rates)
    n_rate = int(round((10.0 if not quick else 5.0) / dt_rate))
    n_t = int(round((3600.0 if not quick else 300.0) / dt_static))
    n_g = int(round((1800.0 if not quick else 240.0) / dt_static))
    e = dev.earth

    # 7.2.1 at room temperature: its own power-on
    k_cal, b_cal = dev.power_on()
    _rate_cal(camp, dev, rates, terr, prefix="rate", kind="rate", n=n_rate, dt=dt_rate, k_on=k_cal,
              b_on=b_cal, earth=e)
    K_cal = lsq(om, dev.mean_out(om, k_cal, b_on=b_cal, earth=e))[0]
    # 7.2.5: one power-on through the chamber
    k5, b5 = dev.power_on()
    Ks = []
    for T in temps:
        dT = T - room
        _rate_cal(camp, dev, rates, terr, prefix=f"rate-temperature@{T:g}C",
                  kind="rate-temperature",
                  n=n_rate, dt=dt_rate, k_on=k5, b_on=b5 + dev.bias(dT), earth=e,
                  cond={"temperature": f"{T!r} degC"}, dT=dT)
        Ks.append(lsq(om, dev.mean_out(om, k5, dT=dT, b_on=b5 + dev.bias(dT), earth=e))[0])
    m = temps.index(room)
    kt = max(abs((Ks[i] - Ks[m]) / (Ks[m] * (temps[i] - temps[m]))) for i in range(len(temps)) if i
             != m)
    # 7.2.6: IRA up (+1 g along the IRA) and down, one power-on
    k6, b6 = dev.power_on()
    Kud = {}
    for o, gi in (("IRA up", 1.0), ("IRA down", -1.0)):
        gvec = {ira_axis: gi}
        _rate_cal(camp, dev, rates, terr, prefix=f"rate-accel[{o.split()[1]}]", kind="rate-accel",
                  n=n_rate,
                  dt=dt_rate, k_on=k6, b_on=b6 + dev.bias(0.0, gvec), earth=gi * e,
                  cond={"orientation": o}, g_ira=gi)
        Kud[o] = lsq(om, dev.mean_out(om, k6, g_ira=gi, b_on=b6 + dev.bias(0.0, gvec), earth=gi
                                      * e))[0]
    kg = (Kud["IRA up"] - Kud["IRA down"]) / 2.0
    # 7.2.16: B₀ at each chamber point (IRA up), one power-on
    k16, b16 = dev.power_on()
    B = []
    Balt = []
    for T in temps:
        dT = T - room
        b = b16 + dev.bias(dT)
        vals, wm, fm = dev.record(0.0, n_t, dt_static, k16, dT=dT, b=b, earth=e)
        camp.add(f"static-temperature@{T:g}C", "static-temperature", vals, dt_static,
                 {"temperature": f"{T!r} degC", "orientation": "IRA up"})
        B.append(b + wm)
        Balt.append(b + wm + fm)

    def bt_of(x):
        return max(abs((x[i] - x[m]) / (temps[i] - temps[m])) for i in range(len(temps)) if i != m)

    # 7.2.17: each axis up and down (specific force +1 g / −1 g along it), one power-on; the IRA's
    # own pair sees ±Ω_e·sin φ, the others have the IRA horizontal east–west (no earth rate)
    k17, b17 = dev.power_on()
    per, per_alt = {}, {}
    for a in AXES:
        bb = {}
        for o, gi in (("up", 1.0), ("down", -1.0)):
            gvec = {a: gi}
            b = b17 + dev.bias(0.0, gvec)
            earth = gi * e if a == ira_axis else 0.0
            g_ira = gi if a == ira_axis else 0.0
            vals, wm, fm = dev.record(0.0, n_g, dt_static, k17, g_ira=g_ira, b=b, earth=earth)
            camp.add(f"static-accel[{a}-{o}]", "static-accel", vals, dt_static,
                     {"axis": a, "orientation": o})
            bb[o] = (b + wm, b + wm + fm)
        per[a] = (bb["up"][0] - bb["down"][0]) / 2.0
        per_alt[a] = (bb["up"][1] - bb["down"][1]) / 2.0
    bg_removed = max(abs(v) for v in per.values())
    bg_included = max(abs(per[a] + (e if a == ira_axis else 0.0)) for a in AXES)
    bg_alt_incl = max(abs(per_alt[a] + (e if a == ira_axis else 0.0)) for a in AXES)
    if repeats:
        _repeats(camp, dev, rates, terr, n_rate, dt_rate, n_t, dt_static, e)
    camp.write_manifest()
    return {("7.2.1", "K"): (K_cal, "mV/(°/s)", ""),
            ("7.2.5", "Kt"): (kt, "1/°C", ""),
            ("7.2.6", "Kg"): (kg, "mV/(°/s)/g", ""),
            ("7.2.16", "Bt"): (bt_of(B), "°/h/°C", "", bt_of(Balt)),
            ("7.2.17", "Bg"): ({"included": bg_included, "removed": bg_removed,
                                "not applicable": bg_included}, "°/h/g", "", bg_alt_incl)}


def _repeats(camp, dev, rates, terr, n_rate, dt_rate, n_t, dt_static, e, Q=6):
    """7.2.4 (Q calibrations) and 7.2.15 (Q static records), each a power-on of its own."""
    for i in range(1, Q + 1):
        k_on, b_on = dev.power_on()
        _rate_cal(camp, dev, rates, terr, prefix=f"rate-repeat#{i}", kind="rate-repeat", n=n_rate,
                  dt=dt_rate,
                  k_on=k_on, b_on=b_on, earth=e, cond={"run": i})
    for i in range(1, Q + 1):
        k_on, b_on = dev.power_on()
        vals, _, _ = dev.record(0.0, n_t, dt_static, k_on, b=b_on, earth=e)
        camp.add(f"static-repeat#{i}", "static-repeat", vals, dt_static,
                 {"run": i, "orientation": "IRA up"})


# --------------------------------------------------------------------------------------------
# 7.2.4, 7.2.13, 7.2.15, 7.2.20: power-on repeats and the Allan terms
# --------------------------------------------------------------------------------------------

def _flicker_mean_var(dev: Device, T: float, draws: int) -> float:
    """Var of one record's flicker mean (°/h²), by Monte Carlo of the generator at ≤ 1 Hz (the mean
    of a 1/f record is set by its lowest frequencies)."""
    if dev.noise.flicker == 0:
        return 0.0
    dt = 1.0 if T >= 600 else 0.1
    n = int(round(T / dt))
    return float(np.var([flicker(n, dt, dev.noise.flicker, dev.rng).mean() for _ in range(draws)],
                        ddof=1))


def build_repeat_allan(folder: Path, rng, *, kind: str, q: float, dt_rate: float, dt_static: float,
                       fmt: str, flick: float, static_s: float = 3600.0, Q: int = 6,
                       quick: bool = False,
                       sigma_b=(0.5, 20.0), arw=(0.05, 0.5)) -> dict:
    dev = Device(rng, kind=kind, q=q, flick=flick, sigma_b=sigma_b, arw=arw, shapes=("none",),
                 asym=0.0)
    rates = R5_SETS[100]
    om = _signed_rates(rates)
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    terr = _table_errors(rng, rates)
    n_rate = int(round((10.0 if not quick else 5.0) / dt_rate))
    T = static_s if not quick else 300.0
    n_t = int(round(T / dt_static))
    e = dev.earth
    k_cal, b_cal = dev.power_on()
    _rate_cal(camp, dev, rates, terr, prefix="rate", kind="rate", n=n_rate, dt=dt_rate, k_on=k_cal,
              b_on=b_cal, earth=e)
    K_cal = lsq(om, dev.mean_out(om, k_cal, b_on=b_cal, earth=e))[0]
    # 7.2.4 runs and 7.2.15 records: each its own power-on
    _repeats(camp, dev, rates, terr, n_rate, dt_rate, n_t, dt_static, e, Q=Q)
    # 7.2.13 / 7.2.20: one static record
    k_on, b_on = dev.power_on()
    vals, wm, fm = dev.record(0.0, n_t, dt_static, k_on, b=b_on, earth=e)
    camp.add("static", "static", vals, dt_static, {"orientation": "IRA up"})
    camp.write_manifest()
    K = dev.K  # the device's K at k_on = 1 (its mean over power-ons)
    ratio = K / K_cal
    white = (dev.noise.arw * 60.0) ** 2 / T
    var_rec = white + _flicker_mean_var(dev, T, 60 if quick else 200)
    quant = 0.0
    if q:
        step = q * (dev.supply if kind == "mV/V" else 1.0)             # mV
        quant = (step * 3600.0 / abs(K)) ** 2 / 12.0 / n_t           # dithered rounding, °/h²
    br = abs(ratio) * math.sqrt(dev.sigma_b ** 2 + (dev.b_mean + e) ** 2 * dev.sigma_K ** 2
                                + var_rec + quant)
    truth = {("7.2.15", "Br"): (br, "°/h", ""),
             ("7.2.13", "B0"): (b_on + wm, "°/h", ("earth", e), b_on + wm + fm),
             ("7.2.20", "ARW"): (dev.noise.arw, "°/√h", "")}
    if dev.noise.flicker:
        truth[("7.2.20", "BI")] = (dev.noise.flicker / BI_FACTOR, "°/h", "")
    else:
        truth[("7.2.20", "BI")] = (0.0, "°/h", "")
    truth[("7.2.20", "RRW")] = (0.0, "°/h/√h", "")
    truth[("7.2.20", "RR")] = (0.0, "°/h²", "")
    return truth


def build_allan(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str,
                static_s: float = 7200.0,
                quick: bool = False) -> dict:
    """7.2.1 (K) and 7.2.20 on one static record with each of flicker, rate random walk and a rate
    ramp present or not (drawn per device), ARW 0.01–0.1 °/√h: every coefficient of eq. (38)
    exercised."""
    dev = Device(rng, kind=kind, q=q, shapes=("none",), asym=0.0, arw=(0.01, 0.1))
    rates = R5_SETS[100]
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    e = dev.earth
    k_cal, b_cal = dev.power_on()
    _rate_cal(camp, dev, rates, _table_errors(rng, rates), prefix="rate", kind="rate", n=10, dt=1.0,
              k_on=k_cal, b_on=b_cal, earth=e)
    T = static_s if not quick else 900.0
    n = int(round(T / dt))
    fl = float(rng.uniform(0.3, 3.0)) if rng.uniform() < 0.6 else 0.0      # plateau °/h
    rrw = float(rng.uniform(1.0, 10.0)) if rng.uniform() < 0.5 else 0.0    # °/h/√h
    ramp = float(rng.uniform(2.0, 20.0)) * (1 if rng.uniform() < 0.5 else
                                            -1) if rng.uniform() < 0.4 else 0.0  # °/h²
    white = rng.standard_normal(n) * dev.noise.arw * 60.0 / math.sqrt(dt)
    flick = flicker(n, dt, fl, rng)
    walk = np.cumsum(rng.standard_normal(n)) * rrw * math.sqrt(dt / 3600.0)
    t_h = dt * (np.arange(n) + 0.5) / 3600.0
    b_on = dev.b_mean + dev.sigma_b * float(rng.standard_normal())
    sensed = b_on + e + white + flick + walk + ramp * t_h
    vals = dev.out.record(sensed, dt, K_scale=1 + dev.sigma_K * float(rng.standard_normal()),
                          rng=rng)
    camp.add("static", "static", vals, dt, {"orientation": "IRA up"})
    camp.write_manifest()
    # the sampled 1/f record's own short-τ excess (its Allan variance is 1.19 × the plateau² at τ =
    # t₀, 1.09 × at 2t₀, 1.01 × at 8t₀: measured on this generator) looks like white noise: the
    # alternative truth counts e = 0.19 of the plateau² at t₀ into A₋₁
    # (docs/independent-campaigns.md)
    arw_alt = math.sqrt(dev.noise.arw ** 2 + 0.19 * fl ** 2 * dt / 3600.0)
    return {("7.2.20", "ARW"): (dev.noise.arw, "°/√h", "", arw_alt),
            ("7.2.20", "BI"): (fl / BI_FACTOR, "°/h", ""),
            ("7.2.20", "RRW"): (rrw, "°/h/√h", ""),
            ("7.2.20", "RR"): (abs(ramp), "°/h²", ""),
            ("7.2.20", "Q"): (0.0, "″", "")}


# --------------------------------------------------------------------------------------------
# 7.2.11, 7.2.12: input-axis misalignment and its repeatability
# --------------------------------------------------------------------------------------------

ARCMIN = math.pi / 10800.0


def _gamma_eq25(F: dict, om: float, K: float) -> float:
    """eqs. (19)–(25) on the eight mean outputs F[(p, '+'/'-')] (mV), Ω(+) in °/s: γ_m in ′."""
    d = {p: (F[(p, "+")] - F[(p, "-")]) / (2 * om * K) for p in (1, 2, 3, 4)}
    return 10800.0 / math.pi * math.hypot((d[1] - d[2]) / 2, (d[3] - d[4]) / 2)


def build_misalignment(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str, runs: int,
                       quick: bool = False, fixture: bool = False) -> dict:
    """7.2.1 and 7.2.11 (four mountings, table ±Ω(+) for 1 min each), ``runs`` times (7.2.12, each
    mounting re-seated). The device's input axis leans α (in yoz) and β (in xoz), 0–30′ in any
    direction; the fixture errs by ε (common to the 180° pair, cancelled by eqs. (21)/(24)) and each
    re-seating by η (1σ 0.2–3′): the position's δ_p = ±α + ε + η_p. The table turns at Ω(+) 100–400
    °/s, so the earth rate's horizontal component averages out over the minute. ``fixture``: on half
    the devices the manifest gives a `fixture` with its `reseat_tilt` (docs/data-format.md's
    role)."""
    dev = Device(rng, kind=kind, q=q, shapes=("none", "cubic"), asym=2e-4)
    rates = R5_SETS[100]
    eta_sd = float(rng.uniform(0.2, 3.0)) * ARCMIN
    equipment = [RATE_TABLE, DMM]
    if fixture and rng.uniform() < 0.5:  # the fixture's re-seating, stated as a half-width: √3·σ
        equipment.append({"id": "FX-X", "role": "fixture",
                          "reseat_tilt": f"{math.sqrt(3) * eta_sd / ARCMIN!r}′"})
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, equipment, fmt=fmt,
                    output=dev.out)
    e = dev.earth
    k_cal, b_cal = dev.power_on()
    _rate_cal(camp, dev, rates, _table_errors(rng, rates), prefix="rate", kind="rate", n=10, dt=1.0,
              k_on=k_cal, b_on=b_cal, earth=e)
    mag = float(rng.uniform(0.0, 30.0)) * ARCMIN
    phi = float(rng.uniform(0, 2 * math.pi))
    alpha, beta = mag * math.cos(phi), mag * math.sin(phi)
    eps = {1: float(rng.normal(0, 5)) * ARCMIN, 3: float(rng.normal(0, 5)) * ARCMIN}
    om = float(rng.choice([100.0, 200.0, 360.0, 400.0]))
    n = int(round((60.0 if not quick else 20.0) / dt))
    for run in range(1, runs + 1):
        # each run a power-on of its own
        k_on, b_on = dev.power_on()
        for p in (1, 2, 3, 4):
            lean = (alpha if p in (1, 2) else beta) * (1 if p in (1, 3) else -1)
            delta = lean + eps[1 if p in (1, 2) else 3] + eta_sd * float(rng.standard_normal())
            for sgn, tag in ((1, "+"), (-1, "-")):
                wh, fl, w = dev.noise.draw3(n, dt, rng)
                # °/h along the IA
                sensed = sgn * om * 3600.0 * math.sin(delta) + b_on + wh + fl + w
                vals = dev.out.record(sensed, dt, K_scale=k_on, rng=rng)
                camp.add(f"misalignment#{run}p{p}{tag}", "misalignment", vals, dt,
                         {"position": str(p), "rate": f"{sgn * om!r} deg/s", "run": str(run)})
    camp.write_manifest()
    gamma = 10800.0 / math.pi * math.hypot(alpha, beta)
    # what eq. (26) measures: Var of one run's γ̂ under re-seating and the minute means' noise
    # (Monte Carlo) rad, one minute's mean
    sd_mean = dev.noise.arw * 60.0 / math.sqrt(n * dt) / (om * 3600.0)
    draws = 4000
    z = rng.standard_normal((draws, 4))
    a_hat = alpha + (eta_sd * (z[:, 0] - z[:, 1]) + sd_mean * rng.standard_normal(draws)) / 2
    b_hat = beta + (eta_sd * (z[:, 2] - z[:, 3]) + sd_mean * rng.standard_normal(draws)) / 2
    g_hat = 10800.0 / math.pi * np.hypot(a_hat, b_hat)
    truth = {("7.2.11", "gamma"): (gamma, "′", "")}
    if runs >= 7:
        truth[("7.2.12", "gamma_r")] = (float(np.std(g_hat, ddof=1)), "′", "")
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.9, 7.2.10: threshold and resolution
# --------------------------------------------------------------------------------------------

TH_LEVELS = (0.1, 0.05, 0.03, 0.02, 0.015, 0.01, 0.007, 0.005, 0.003)          # °/s, `metro plan`'s
# °/s, `metro plan`'s
RES_INCREMENTS = (0.05, 0.02, 0.01, 0.007, 0.005, 0.003, 0.002, 0.001)


def build_threshold(folder: Path, rng, *, kind: str, q: float, fmt: str, dt: float = 1.0,
                    flick: float = 0.0,
                    quick: bool = False) -> dict:
    """7.2.1, 7.2.9 and 7.2.10 (the levels `metro plan` lists, 200 s each). The device's response to
    a small rate is soft: K·Ω³/(Ω² + Ω_th²) near zero, Ω_th drawn per direction (0.004–0.06 °/s), so
    eq. (17) holds exactly from Ω_th up; an increment ΔΩ on the base rate gives K·ΔΩ³/(ΔΩ² + r²), r
    per direction (0.0015–0.03 °/s). Truth: max over the directions of Ω_th (7.2.9.1 f)) and of r
    (7.2.10.1 g))."""
    dev = Device(rng, kind=kind, q=q, flick=flick, shapes=("none",), asym=2e-4, arw=(0.05, 0.3))
    rates = R5_SETS[100]
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    e = dev.earth
    th = {1: float(rng.uniform(0.004, 0.06)), -1: float(rng.uniform(0.004, 0.06))}
    rr = {1: float(rng.uniform(0.0015, 0.03)), -1: float(rng.uniform(0.0015, 0.03))}
    k_on, b_on = dev.power_on()
    _rate_cal(camp, dev, rates, _table_errors(rng, rates), prefix="rate", kind="rate", n=10, dt=1.0,
              k_on=k_on, b_on=b_on, earth=e)
    n = int(round((200.0 if not quick else 60.0) / dt))

    def rec(sensed_dps: float):
        wh, fl, w = dev.noise.draw3(n, dt, rng)
        return dev.out.record(sensed_dps * 3600.0 + b_on + e + wh + fl + w, dt, K_scale=k_on,
                              rng=rng)

    camp.add("threshold-0", "threshold", rec(0.0), dt, {"rate": "0 deg/s"})
    for r in TH_LEVELS:
        for sgn in (1, -1):
            om = sgn * r
            camp.add(f"threshold{'+' if sgn > 0 else '-'}{r:g}", "threshold",
                     rec(om ** 3 / (om ** 2 + th[sgn] ** 2)), dt, {"rate": f"{om!r} deg/s"})
    base = 0.3
    for sgn in (1, -1):
        camp.add(f"resolution{'+' if sgn > 0 else '-'}base", "resolution", rec(sgn * base), dt,
                 {"base_rate": f"{sgn * base!r} deg/s", "increment": "0 deg/s"})
        for d in RES_INCREMENTS:
            x = sgn * d
            camp.add(f"resolution{'+' if sgn > 0 else '-'}{d:g}", "resolution",
                     rec(sgn * base + x ** 3 / (x ** 2 + rr[sgn] ** 2)), dt,
                     {"base_rate": f"{sgn * base!r} deg/s", "increment": f"{x!r} deg/s"})
    camp.write_manifest()
    return {("7.2.9", "threshold"): (max(th.values()), "°/s", ""),
            ("7.2.10", "resolution"): (max(rr.values()), "°/s", "")}


UNIT_ALIASES.setdefault("°/h/√h", {"°/h/√h", "degree / hour / hour ** 0.5", "deg/h/hour**0.5",
                                   "°/h¹⋅⁵"})
UNIT_ALIASES.setdefault("°/h²", {"°/h²", "degree / hour ** 2", "deg/h**2"})
UNIT_ALIASES.setdefault("″", {"″", "arcsec", "arcsecond"})


# --------------------------------------------------------------------------------------------
# scoring: truths that depend on what metro says it did with the earth rate (B_g's maximum)
# --------------------------------------------------------------------------------------------

def score_more(truth: dict, doc: dict) -> list[dict]:
    plain = {}
    for (item, key), (value, unit, earth, *alt) in truth.items():
        if isinstance(value, dict):
            r = [x for x in doc.get("results", []) if x.get("key") == key
                 and str(x.get("item", "")) == item]
            value = value.get(r[0].get("earth_rate", ""),
                              value["included"]) if r else value["included"]
        plain[(item, key)] = (value, unit, earth, *alt)
    return score(plain, doc)


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

VARIANTS = variants(
    Variant("jjf-nonlin-mV-1Hz", "jjf2014", "7.2.1,7.2.2,7.2.3",
            text("""
                mV, K ±(0.5 … 200) mV/(°/s) log-uniform, nonlinearity none/quadratic/cubic/both
                up to 5×10⁻⁴ of full scale, asymmetry up to ±1×10⁻³, R5 sets to 50/100/200/400
                °/s, 10 × 1 s per rate, CSV; nonlinearity_spec between the noise-free K_n of
                the spans"""),
            build_with(build_nonlin, kind="mV", q=0.0, dt=1.0, fmt="csv")),
    Variant("jjf-nonlin-mVV-200Hz-q", "jjf2014", "7.2.1,7.2.2,7.2.3",
            text("""
                as jjf-nonlin-mV-1Hz, ratiometric mV/V rounded to 0.002 mV/V, 10 s per rate at
                200 Hz (.npy), flicker plateau ≈ 2 °/h"""),
            build_with(build_nonlin, kind="mV/V", q=0.002, dt=0.005, fmt="npy", flick=2.0)),
    Variant("jjf-temp-g-mV-1Hz", "jjf2014", "7.2.1,7.2.5,7.2.6,7.2.16,7.2.17",
            text("""
                mV, K of either sign; K temperature coefficient ±3×10⁻⁴/°C (+ quadratic),
                axial-g ±5×10⁻⁴/g; bias ±0.5 °/h/°C (+ quadratic), g-sensitivity up to ±20
                °/h/g on each axis; chamber sets 3–6 points incl. 20 °C; one power-on per item;
                1 Hz CSV, white noise"""),
            build_with(build_temp_g, kind="mV", q=0.0, dt_rate=1.0, dt_static=1.0, fmt="csv")),
    Variant("jjf-temp-g-mVV-10Hz-flicker-IRAx", "jjf2014",
            "7.2.1,7.2.4,7.2.5,7.2.6,7.2.15,7.2.16,7.2.17",
            text("""
                as jjf-temp-g-mV-1Hz, mV/V rounded to 0.001 mV/V, static records at 10 Hz
                (.npy), flicker ≈ 1 °/h, wander 2 °/h, the IRA is the case's X axis
                (device.ira_axis), with 7.2.4 / 7.2.15 repeats (6 power-ons each)"""),
            build_with(build_temp_g, kind="mV/V", q=0.001, dt_rate=1.0, dt_static=0.1, fmt="npy",
                       flick=1.0, wander=2.0, ira_axis="X", repeats=True)),
    Variant("jjf-repeat-allan-mV-10Hz", "jjf2014", "7.2.1,7.2.4,7.2.13,7.2.15,7.2.20",
            text("""
                mV, either sign; bias turn-on σ 0.5–20 °/h, K power-on σ 5×10⁻⁵–4×10⁻⁴, 6
                power-ons each for 7.2.4 and 7.2.15, static 1 h at 10 Hz (CSV), white noise
                only"""),
            build_with(build_repeat_allan, kind="mV", q=0.0, dt_rate=1.0, dt_static=0.1, fmt="csv",
                       flick=0.0)),
    Variant("jjf-repeat-allan-mVV-100Hz-flicker-q", "jjf2014", "7.2.1,7.2.4,7.2.13,7.2.15,7.2.20",
            text("""
                as jjf-repeat-allan-mV-10Hz, mV/V rounded to 0.0005 mV/V, every record at 100
                Hz (.npy), flicker plateau ≈ 1.5 °/h, ARW 0.1–1 °/√h"""),
            build_with(build_repeat_allan, kind="mV/V", q=0.0005, dt_rate=0.01, dt_static=0.01,
                       fmt="npy", flick=1.5, arw=(0.1, 1.0))),
    Variant("jjf-allan-terms-mV-10Hz", "jjf2014", "7.2.1,7.2.20",
            text("""
                mV, either sign, static 2 h at 10 Hz (CSV), ARW 0.01–0.1 °/√h and, each drawn
                present or not, flicker plateau 0.3–3 °/h, rate random walk 1–10 °/h/√h, rate
                ramp ±(2–20) °/h²"""),
            build_with(build_allan, kind="mV", q=0.0, dt=0.1, fmt="csv")),
    Variant("jjf-allan-terms-mVV-400Hz-q", "jjf2014", "7.2.1,7.2.20",
            text("""
                as jjf-allan-terms-mV-10Hz, mV/V rounded to 0.0002 mV/V, 1 h at 400 Hz (.npy)"""),
            build_with(build_allan, kind="mV/V", q=0.0002, dt=0.0025, fmt="npy", static_s=3600.0)),
    Variant("jjf-misalignment-mV-Q7", "jjf2014", "7.2.1,7.2.11,7.2.12",
            text("""
                mV, either sign; input axis leaning 0–30′ in any direction, fixture error 5′
                (1σ), each re-seating 0.2–3′ (1σ); table Ω(+) 100/200/360/400 °/s; Q = 7 runs,
                each a power-on; 1 Hz CSV"""),
            build_with(build_misalignment, kind="mV", q=0.0, dt=1.0, fmt="csv", runs=7)),
    Variant("jjf-misalignment-mVV-50Hz-one-run", "jjf2014", "7.2.1,7.2.11",
            text("""
                as jjf-misalignment-mV-Q7 with one run only (7.2.11 alone), mV/V at 50 Hz
                (.npy); on half the devices a fixture with its reseat_tilt (√3 × the re-seating
                σ)"""),
            build_with(build_misalignment, kind="mV/V", q=0.0, dt=0.02, fmt="npy", runs=1,
                       fixture=True)),
    Variant("jjf-threshold-mV-1Hz", "jjf2014", "7.2.1,7.2.9,7.2.10",
            text("""
                mV, either sign; soft threshold Ω_th 0.004–0.06 °/s and resolution r
                0.0015–0.03 °/s per direction; the levels and increments `metro plan` lists,
                200 s at 1 s (CSV), white noise"""),
            build_with(build_threshold, kind="mV", q=0.0, fmt="csv")),
    Variant("jjf-threshold-mVV-10Hz-flicker", "jjf2014", "7.2.1,7.2.9,7.2.10",
            text("""
                as jjf-threshold-mV-1Hz, mV/V rounded to 0.0005 mV/V at 10 Hz (.npy), flicker
                plateau ≈ 3 °/h (the bias moves between the zero record and the levels)"""),
            build_with(build_threshold, kind="mV/V", q=0.0005, fmt="npy", dt=0.1, flick=3.0)),
)


#: run_variant with the earth-rate-aware scoring of this module
run_more = functools.partial(run_variant, scorer=score_more)


def main(argv=None) -> int:
    from independent_campaigns import cli

    return cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-jjf-", alt_label="alt",
               scorer=score_more)

if __name__ == "__main__":
    sys.exit(main())

"""The independent harness, JJF 2014: shock, vibration, stability and the dynamic items.

Run: nice -n 10 .venv/bin/python benchmarks/independent_jjf2014_dyn.py [--devices 30]
     [--variants A,B] [--seed 1] [--json F] [--keep DIR]

The items no other harness module covers: 7.2.7 ΔK after shock, 7.2.8 ΔK after vibration, 7.2.14
bias stability B_s, 7.2.18 ΔB after shock, 7.2.19 ΔB after vibration, 7.2.21 bandwidth B_w, 7.2.22
output delay T_d and 7.2.23 start-up time. As in the other modules, the generators were written from
the documentation (docs/data-format.md, docs/instruments.md, ``metro plan -s jjf2014 -i …``'s
segment list and columns) and the standard's clauses only; numpy makes the samples and only the
shared pieces of ``independent_campaigns.py`` (noise, outputs, campaign writer, scoring,
``run_variant``, ``cli``) are imported — no part of metro's instruments or simulators
(tests/plugins/jjf2014/test_independent_dynamic.py checks it).

The device (every variant; parameters drawn per device): a vibratory rate gyro with an analog
output,

    output = K · k_rec · [ Ω + (b_rec + earth + wander + white + flicker)/3600 ]      (mV, or mV/V)

K ±(1 … 100) mV/[(°)/s] log-uniform, either sign; k_rec the record's power-on K factor (1σ σ_K)
times the shifts the shocks and vibrations left (7.2.7/7.2.8); b_rec the record's bias: the device's
mean bias ±360 °/h, + a turn-on draw (σ_b) for each power-on, + the shifts (7.2.18/7.2.19). The
dynamic items add a real frequency response H(f) — first order with a pure delay (eq. (46)), or
second order (ω_n, ζ) with a delay — and the start-up item a power-on transient (exponential, two
exponentials, ringing, a dead time with the output at 0 mV, a drive amplitude building up that
scales K).

What the truth is (the standard's measurand on the records actually written; noise and the
equipment's errors are measurement error):

* 7.2.7 / 7.2.8 ΔK (eqs. (12)–(15)): max_j |K_j2 − K_j1| of the noise-free K of each calibration
  (K·k_rec: each calibration's own power-on when the device is powered off between them).
  Alt: max_j |K·δ_j| — the change the shock / vibration itself made (turn-on scatter left out).
* 7.2.18 / 7.2.19 ΔB (eqs. (32), (33)): max_j |B_j2 − B_j1| of each record's bias as the equivalent
  input rate (b_rec + the wander's record mean; the earth rate cancels: IRA up in both).
  Alt: max_j |β_j|, the shift the test made.
* 7.2.14 B_s (eq. (29), P = metro's default 10 s): √E[s²]/|K_rec| over Monte Carlo repeats of the
  generator's own record (white, flicker, wander with a random phase, the rounding of the output).
* 7.2.21 B_w: the frequency at which the device's true |H(f)|/|H(0)| is 0.707 (7.2.21.2 as printed);
  alt: the −3 dB point (1/√2).
* 7.2.22 T_d: eq. (50) applied to the true phases arg H(f_i) at the campaign's frequencies with
  T = 1/(2π·B_w) (eq. (47)), B_w the true −3 dB point; for a first-order device that is its delay.
  Alt: the device's pure delay.
* 7.2.23 start-up time: the largest over the trials of the time of the first sample after the last
  sample at which the noise-free output is outside the band — position trials: ± bias_tolerance
  (0.05 °/s, metro's documented default) about that power-on's settled output; rate trials: the
  noise-free output less the position trials' mean settled output, over K, outside Ω ± 1 % (metro's
  default rate_tolerance).  Alt: the same on the noise-free output averaged over metro's documented
  1 s window (option ``window``).

Scored as in independent_campaigns.py: E_n = (result − truth)/U; not reportable counts as covered.
"""

from __future__ import annotations

import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))

from independent_campaigns import (  # noqa: E402  (the shared pieces of the harness)
                                   DMM, OMEGA_E_DEG_H, RATE_TABLE, UNIT_ALIASES, Campaign, Noise,
                                   Output, Variant, build_with, cli, run_variant, text, variants)

UNIT_ALIASES.setdefault("Hz", {"Hz", "hertz"})
UNIT_ALIASES.setdefault("s", {"s", "second"})
UNIT_ALIASES.setdefault("°/h", set()).update({"degree / hour"})
UNIT_ALIASES.setdefault("mV/(°/s)", set()).update({"mV/(deg/s)", "millivolt / (degree / second)"})

R5_100 = (0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100)  # 7.2.1.1 b), metro plan's default set
AXES = ("X", "Y", "Z")
AVT_U = 5e-3          # the angular vibration table's reference sensor: relative amplitude U (k = 2)
AVT_PHASE_U = 0.2     # its phase U, degrees (k = 2)


# --------------------------------------------------------------------------------------------
# the device
# --------------------------------------------------------------------------------------------

class Device:
    """A vibratory rate gyro with an analog output (module docstring)."""

    def __init__(self, rng, *, kind: str, q: float, arw=(0.05, 0.5), flick: float = 0.0,
                 wander: float = 0.0,
                 sigma_b=(1.0, 10.0), sigma_K=(5e-5, 4e-4)):
        self.rng = rng
        self.lat = float(rng.uniform(-80, 80))
        self.earth = OMEGA_E_DEG_H * math.sin(math.radians(self.lat))      # °/h, IRA up
        mag = float(np.exp(rng.uniform(math.log(1.0), math.log(100.0))))
        self.K = -mag if rng.uniform() < 0.5 else mag                     # mV/(°/s)
        self.noise = Noise(float(rng.uniform(*arw)), flicker=flick * float(rng.uniform(0.5, 1.5)),
                           wander_amp=wander * float(rng.uniform(0.5, 1.5)),
                           wander_period=float(rng.uniform(600, 3600)))
        self.sigma_b = float(rng.uniform(*sigma_b))
        self.sigma_K = float(rng.uniform(*sigma_K))
        self.b_mean = float(rng.uniform(-360, 360))
        self.supply = float(rng.uniform(4.5, 5.5))
        self.out = Output(kind, K=self.K, q=q, supply=self.supply)

    def power_on(self) -> tuple[float, float]:
        """(k_on, b_on) of a new power-on."""
        return (1.0 + self.sigma_K * float(self.rng.standard_normal()),
                self.b_mean + self.sigma_b * float(self.rng.standard_normal()))

    def record(self, om: float | np.ndarray, n: int, dt: float, k: float, b: float, *, extra=None):
        """Samples of one record at the (true) rate ``om`` °/s with K factor ``k`` and bias ``b``
        °/h (+ ``extra`` °/h per sample): (values, wander mean, flicker mean), both °/h."""
        wh, fl, w = self.noise.draw3(n, dt, self.rng)
        sensed = np.asarray(om, dtype=float) * 3600.0 + b + self.earth + wh + fl + w
        if extra is not None:
            sensed = sensed + extra
        return self.out.record(sensed, dt, K_scale=k,
                               rng=self.rng), float(w.mean()), float(fl.mean())

    def manifest_device(self, name: str, extra: dict | None = None) -> dict:
        d = {"id": name, "technology": "vibratory", "output": "analog"}
        if self.out.kind == "mV/V":
            d["supply_voltage"] = f"{self.supply!r} V"
        return d | (extra or {})


def _table_errors(rng, rates) -> dict:
    """The rate table errs within its certificate (U = 1×10⁻⁴, k = 2): a fixed error per set
    point."""
    return {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * 0.5e-4 for r in rates}


def _calibration(camp: Campaign, dev: Device, rates, terr, *, prefix: str, kind: str, n: int,
                 dt: float,
                 k: float, b: float, cond: dict | None = None) -> None:
    """One 7.2.1.1 calibration: each rate forward then reverse, ``n`` samples at ``dt``."""
    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            vals, _, _ = dev.record(sgn * r * (1 + terr[r]), n, dt, k, b)
            camp.add(f"{prefix}{tag}{r}", kind, vals, dt, {"rate": f"{sgn * r!r} deg/s"}
                     | (cond or {}))


def _shifts(rng, big: float, small: float) -> dict:
    """What a shock / vibration does on each axis: nothing, one axis, or every axis."""
    profile = ("none", "one", "all")[int(rng.integers(3))]
    d = {a: small * float(rng.standard_normal()) for a in AXES}
    if profile == "one":
        a = AXES[int(rng.integers(3))]
        d[a] = big * float(rng.uniform(0.2, 1.0)) * float(rng.choice([-1, 1]))
    elif profile == "all":
        d = {a: big * float(rng.uniform(-1, 1)) for a in AXES}
    return d


# --------------------------------------------------------------------------------------------
# 7.2.7, 7.2.8: K before and after shock and vibration
# --------------------------------------------------------------------------------------------

def build_change_k(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str,
                   flick: float = 0.0,
                   power_off: bool | None = None, repeats: bool = False,
                   quick: bool = False) -> dict:
    """Per test (shock, then vibration) and axis X, Y, Z: a 7.2.1 calibration before, the test, one
    after (7.2.7.1 d), 7.2.8.1 e)). The device is powered off between calibrations on half the
    devices (each its own power-on) or stays on through the campaign; the tests' shifts
    accumulate."""
    dev = Device(rng, kind=kind, q=q, flick=flick)
    power_off = bool(rng.uniform() < 0.5) if power_off is None else power_off
    rates = R5_100 if not quick else (0.63, 4, 25, 100)
    terr = _table_errors(rng, rates)
    n = int(round((10.0 if not quick else 4.0) / dt))
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    k_session, b_session = dev.power_on()
    state = 1.0
    truth = {}
    for item, key, kind_, big in (("7.2.7", "dK_shock", "rate-shock", 3e-3),
                                  ("7.2.8", "dK_vib", "rate-vibration", 2e-3)):
        shifts = _shifts(rng, big, 2e-5)
        dk, dk_alt = [], []
        for a in AXES:
            ks = []
            for phase in ("before", "after"):
                if phase == "after":
                    k_before_state = state
                    state *= 1 + shifts[a]
                k_on, b_on = dev.power_on() if power_off else (k_session, b_session)
                k = state * k_on
                ks.append(k)
                _calibration(camp, dev, rates, terr, prefix=f"{kind_}[{a}-{phase}]", kind=kind_,
                             n=n, dt=dt, k=k,
                             b=b_on, cond={"axis": a, "phase": phase})
            dk.append(abs(dev.K * (ks[1] - ks[0])))
            dk_alt.append(abs(dev.K * k_before_state * shifts[a]))
        truth[(item, key)] = (max(dk), "mV/(°/s)", None, max(dk_alt))
    if repeats:  # 7.2.4: six calibrations, each a power-on (K_r for the budgets)
        for run in range(1, 7):
            k_on, b_on = dev.power_on()
            _calibration(camp, dev, rates, terr, prefix=f"rate-repeat#{run}", kind="rate-repeat",
                         n=n, dt=dt,
                         k=state * k_on, b=b_on, cond={"run": str(run)})
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.18, 7.2.19: bias before and after shock and vibration
# --------------------------------------------------------------------------------------------

def build_change_b(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str,
                   flick: float = 0.0,
                   wander: float = 0.0, minutes: float = 30.0, power_off: bool | None = None,
                   repeats: bool = False, quick: bool = False) -> dict:
    """A 7.2.1 calibration (K), then per test and axis a 7.2.13 record before and after (7.2.18.1
    c)–e), 7.2.19.1 d)–f)), IRA up; powered off between records on half the devices."""
    dev = Device(rng, kind=kind, q=q, flick=flick, wander=wander)
    power_off = bool(rng.uniform() < 0.5) if power_off is None else power_off
    rates = R5_100 if not quick else (0.63, 4, 25, 100)
    terr = _table_errors(rng, rates)
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    k_cal, b_cal = dev.power_on()
    _calibration(camp, dev, rates, terr, prefix="rate", kind="rate", n=int(round(10.0 / 1.0)),
                 dt=1.0, k=k_cal,
                 b=b_cal)
    n = int(round(60.0 * (minutes if not quick else 5.0) / dt))
    k_session, b_session = dev.power_on()
    shift_b = 0.0
    truth = {}
    for item, key, kind_, big in (("7.2.18", "dB_shock", "static-shock", 30.0),
                                  ("7.2.19", "dB_vib", "static-vibration", 20.0)):
        shifts = _shifts(rng, big, 0.02)
        db, db_alt = [], []
        for a in AXES:
            bs = []
            for phase in ("before", "after"):
                if phase == "after":
                    shift_b += shifts[a]
                k_on, b_on = dev.power_on() if power_off else (k_session, b_session)
                vals, wmean, _ = dev.record(0.0, n, dt, k_on, b_on + shift_b)
                bs.append(b_on + shift_b + wmean)
                camp.add(f"{kind_}[{a}-{phase}]", kind_, vals, dt,
                         {"axis": a, "phase": phase, "orientation": "IRA up"})
            db.append(abs(bs[1] - bs[0]))
            db_alt.append(abs(shifts[a]))
        truth[(item, key)] = (max(db), "°/h", None, max(db_alt))
    if repeats:  # 7.2.15: six power-ons at rest (B_r for the budgets)
        for run in range(1, 7):
            k_on, b_on = dev.power_on()
            vals, _, _ = dev.record(0.0, n, dt, k_on, b_on + shift_b)
            camp.add(f"static-repeat#{run}", "static-repeat", vals, dt,
                     {"run": str(run), "orientation": "IRA up"})
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.14: bias stability
# --------------------------------------------------------------------------------------------

def bs_eq29(x: np.ndarray, P: int) -> float:
    """Eq. (29) without the 1/K: the Bessel standard deviation of the N/P averages of P samples."""
    m = x.size // P
    return float(np.std(x[: m * P].reshape(m, P).mean(axis=1), ddof=1))


def build_stability(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str,
                    flick: float = 0.0,
                    wander: float = 0.0, ramp: float = 0.0, hours: float = 1.0, mc: int = 100,
                    quick: bool = False) -> dict:
    """A 7.2.1 calibration and one 7.2.13.1 record (IRA up), P = 10 s (metro's default)."""
    dev = Device(rng, kind=kind, q=q, flick=flick, wander=wander)
    rates = R5_100 if not quick else (0.63, 4, 25, 100)
    terr = _table_errors(rng, rates)
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM], fmt=fmt,
                    output=dev.out)
    k_cal, b_cal = dev.power_on()
    _calibration(camp, dev, rates, terr, prefix="rate", kind="rate", n=10, dt=1.0, k=k_cal, b=b_cal)
    n = int(round(3600.0 * (hours if not quick else 0.1) / dt))
    P = int(round(10.0 / dt))
    k_on, b_on = dev.power_on()
    r = ramp * float(rng.uniform(-1, 1))                                  # °/h², a rate ramp
    t_h = dt * (np.arange(n) + 0.5) / 3600.0
    vals, _, _ = dev.record(0.0, n, dt, k_on, b_on, extra=r * (t_h - t_h.mean()))
    camp.add("static", "static", vals, dt, {"orientation": "IRA up"})
    # column unit per °/h
    scale = abs(dev.K * k_on) / 3600.0 / (dev.supply if kind == "mV/V" else 1.0)
    s2 = []
    for _ in range(mc if not quick else 20):
        v, _, _ = dev.record(0.0, n, dt, k_on, b_on, extra=r * (t_h - t_h.mean()))
        s2.append(bs_eq29(v, P) ** 2)
    truth = {("7.2.14", "Bs"): (math.sqrt(float(np.mean(s2))) / scale, "°/h", None)}
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.21, 7.2.22: bandwidth and output delay
# --------------------------------------------------------------------------------------------

class Response:
    """H(f) relative to the DC gain: first order (corner f_c) or second order (f_n, ζ), times
    e^{−sT_d}."""

    def __init__(self, order: int, fc: float, td: float, zeta: float = 0.7):
        self.order, self.fc, self.td, self.zeta = order, fc, td, zeta

    def __call__(self, f):
        s = 2j * math.pi * np.asarray(f, dtype=float)
        if self.order == 1:
            h = 1.0 / (1.0 + s / (2 * math.pi * self.fc))
        else:
            wn = 2 * math.pi * self.fc
            h = wn ** 2 / (s ** 2 + 2 * self.zeta * wn * s + wn ** 2)
        return h * np.exp(-s * self.td)

    def level_point(self, level: float) -> float:
        """The lowest frequency at which |H| falls to ``level`` (bisection on a fine grid)."""
        f = np.geomspace(1e-3 * self.fc, 100 * self.fc, 200001)
        a = np.abs(self(f))
        i = int(np.flatnonzero(a <= level)[0])
        lo, hi = f[i - 1], f[i]
        for _ in range(80):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if abs(self(mid)) > level else (lo, mid)
        return 0.5 * (lo + hi)


def td_eq50(freqs: np.ndarray, P: np.ndarray, bw: float) -> float:
    """Eqs. (47)–(50): T = 1/(2πB_w), T_d = Σω_i(−P_i − atan(ω_iT))/Σω_i²."""
    w = 2 * math.pi * np.asarray(freqs, dtype=float)
    T = 1.0 / (2 * math.pi * bw)
    y = -np.asarray(P) - np.arctan(w * T)
    return float(w @ y / (w @ w))


def build_dynamic(folder: Path, rng, *, kind: str, q: float, order: int, fs: float,
                  records: int = 10,
                  nfreq=(10, 14), flick: float = 0.0, quick: bool = False) -> dict:
    """A 7.2.1 calibration (S₀ = K) and the 7.2.21.1 records: N log-spaced frequencies from 10 Hz to
    2× the lab's estimate of B_w (within ±30 % of the truth), n records of 1 s each at ``fs``,
    amplitude 10–30 % of a range of 100–500 °/s; columns ``output`` and ``reference`` (the reference
    sensor: °/s, with a fixed amplitude error and phase error within its certificate, and its own
    noise)."""
    dev = Device(rng, kind=kind, q=q, flick=flick)
    if order == 1:
        resp = Response(1, float(np.exp(rng.uniform(math.log(20), math.log(250)))),
                        float(rng.uniform(0.0, 2e-3)))
    else:
        resp = Response(2, float(np.exp(rng.uniform(math.log(30), math.log(250)))),
                        float(rng.uniform(0.0, 1e-3)),
                        zeta=float(rng.uniform(0.45, 1.0)))
    bw707, bw3 = resp.level_point(0.707), resp.level_point(1 / math.sqrt(2))
    rates = R5_100 if not quick else (0.63, 4, 25, 100)
    terr = _table_errors(rng, rates)
    avt = {"id": "AVT-X", "role": "angular_vibration_table", "phase_U": f"{AVT_PHASE_U!r} deg",
           "calibration": {"certificate": "IND-AVT-1", "U": f"{AVT_U!r}", "k": 2}}
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM, avt],
                    fmt="npy",
                    output=dev.out)
    k_on, b_on = dev.power_on()
    _calibration(camp, dev, rates, terr, prefix="rate", kind="rate", n=10, dt=1.0, k=k_on, b=b_on)
    est = min(bw707 * float(rng.uniform(0.8, 1.3)), fs / 40.0)
    N = int(rng.integers(nfreq[0], nfreq[1] + 1)) if not quick else 6
    freqs = [float(x) for x in np.round(np.geomspace(10.0, 2 * est, N), 1)]
    rng_ = float(rng.choice([100.0, 200.0, 300.0, 500.0]))
    amp = rng_ * float(rng.uniform(0.1, 0.3))
    # the reference sensor's amplitude error
    eA = float(rng.normal(0.0, AVT_U / 2))
    ePh = math.radians(float(rng.normal(0.0, AVT_PHASE_U / 2)))  # and its phase error
    dt = 1.0 / fs
    n = int(round((1.0 if not quick else 0.25) * fs))
    t = dt * np.arange(n)
    unit = dev.out.unit
    for f in freqs:
        h = complex(resp(f))
        for j in range(1, (records if not quick else 3) + 1):
            ph = float(rng.uniform(0, 2 * math.pi))
            ang = 2 * math.pi * f * t + ph
            true_rate = amp * np.sin(ang)                                   # °/s
            dev_rate = amp * abs(h) * np.sin(ang + np.angle(h))             # what the dynamics pass
            vals, _, _ = dev.record(dev_rate, n, dt, k_on, b_on)
            ref = amp * (1 + eA) * np.sin(ang + ePh) + 0.002 * amp * rng.standard_normal(n)
            sid = f"angvib-{f:g}Hz#{j}"
            arr = np.zeros(n, dtype=[(f"output [{unit}]", "f8"), ("reference [°/s]", "f8")])
            arr[f"output [{unit}]"] = vals
            arr["reference [°/s]"] = ref
            np.save(folder / f"{sid}.npy", arr)
            camp.segments.append((sid, "angular-vibration", f"{sid}.npy", dt,
                                  {"frequency": f"{f!r} Hz", "amplitude": f"{amp!r} deg/s",
                                   "repeat": str(j)}, ""))
            del true_rate
    freqs = np.array(freqs)
    P = np.unwrap(np.angle(resp(freqs)))
    truth = {("7.2.21", "Bw"): (bw707, "Hz", None, bw3),
             ("7.2.22", "Td"): (td_eq50(freqs, P, bw3), "s", None, resp.td)}
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# 7.2.23: start-up time
# --------------------------------------------------------------------------------------------

def transient(rng, shape: str, t: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(additive rate °/s, K factor, dead time s) of a power-on at times ``t`` (s)."""
    add = np.zeros_like(t)
    kf = np.ones_like(t)
    dead = 0.0
    sign = float(rng.choice([-1, 1]))
    if shape in ("exp", "dead"):
        add = sign * float(rng.uniform(0.2, 3.0)) * np.exp(-t / float(rng.uniform(0.3, 6.0)))
        if shape == "dead":
            dead = float(rng.uniform(0.5, 3.0))
    elif shape == "2exp":
        add = (sign * float(rng.uniform(0.3, 3.0)) * np.exp(-t / float(rng.uniform(0.3, 3.0)))
               + float(rng.choice([-1, 1])) * float(rng.uniform(0.05,
                                                                0.2)) * np.exp(-t / float(
                                                                    rng.uniform(5.0, 12.0))))
    elif shape == "ring":
        add = (sign * float(rng.uniform(0.3, 3.0)) * np.exp(-t / float(rng.uniform(0.5, 4.0)))
               * np.cos(2 * math.pi * float(rng.uniform(0.2, 2.0)) * t))
    elif shape == "drive":  # the drive amplitude builds up: K (and the bias) scale with it
        kf = 1.0 - np.exp(-t / float(rng.uniform(0.2, 2.0)))
    return add, kf, dead


def _settle(t: np.ndarray, x: np.ndarray, target: float, tol: float) -> float:
    """The time of the first sample after the last one outside target ± tol (t[0] if none is)."""
    out = np.flatnonzero(np.abs(x - target) > tol)
    if out.size == 0:
        return float(t[0])
    if out[-1] == t.size - 1:
        raise ValueError("never settles")
    return float(t[out[-1] + 1])


def _smooth(t: np.ndarray, x: np.ndarray, window: float,
            dt: float) -> tuple[np.ndarray, np.ndarray]:
    """The documented moving average (option ``window``) placed at its centre."""
    k = max(1, int(round(window / dt)))
    c = np.convolve(x, np.ones(k) / k, mode="valid")
    return t[0] - dt + (np.arange(c.size) + (k + 1) / 2.0) * dt, c


def build_startup(folder: Path, rng, *, kind: str, q: float, dt: float, fmt: str,
                  flick: float = 0.0,
                  shapes=("exp", "2exp", "ring", "dead", "drive"), arw=(0.05, 0.5),
                  quick: bool = False) -> dict:
    """A 7.2.1 calibration, three position trials at rest and three rate trials (100, 10, 1 °/s),
    each a power-on recorded from t = 0 for 60 s at ``dt`` (``metro plan``'s steps), IRA up."""
    dev = Device(rng, kind=kind, q=q, flick=flick, arw=arw)
    rates = R5_100 if not quick else (0.63, 4, 25, 100)
    terr = _table_errors(rng, rates)
    timer = {"id": "TMR-X", "role": "timer", "calibration": {"certificate": "IND-TMR-1",
                                                             "U": "1e-5", "k": 2}}
    camp = Campaign(folder, dev.manifest_device(folder.name), dev.lat, [RATE_TABLE, DMM, timer],
                    fmt=fmt,
                    output=dev.out)
    k_cal, b_cal = dev.power_on()
    _calibration(camp, dev, rates, terr, prefix="rate", kind="rate", n=10, dt=1.0, k=k_cal, b=b_cal)
    K_cal = dev.K * k_cal
    n = int(round(60.0 / dt))
    t = dt * np.arange(1, n + 1)   # sample i at (i + 1)·dt from power-on (the time column)
    shape = shapes[int(rng.integers(len(shapes)))]
    btol, rtol, win = 0.05, 0.01, 1.0
    trials = []   # (id, trial, rate, noise-free output mV)
    for run in (1, 2, 3):
        trials.append((f"startup-position#{run}", "position", 0.0, str(run)))
    for frac in (1.0, 0.1, 0.01):
        trials.append((f"startup-rate{frac:g}FS", "rate", 100.0 * frac, "1"))
    nf = {}
    for sid, trial, om, run in trials:
        k_on, b_on = dev.power_on()
        add, kf, dead = transient(rng, shape, t)
        om_true = om * (1 + float(rng.uniform(-1, 1)) * math.sqrt(3) * 0.5e-4)
        sensed_nf = om_true + add + (b_on + dev.earth) / 3600.0          # °/s
        kk = k_on * kf
        live = t >= dead
        free = dev.K * kk * sensed_nf * live                               # mV, noise-free
        extra = add * 3600.0
        vals, _, _ = dev.record(om_true, n, dt, kk, b_on, extra=extra)
        if dead > 0:
            vals = np.where(live, vals, 0.0)
        nf[sid] = (trial, om, free, dev.K * k_on * ((b_on + dev.earth) / 3600.0 + om_true))
        camp.add(sid, "startup", vals, dt, {"trial": trial, "rate": f"{om!r} deg/s", "run": run})
    z = float(np.mean([v[3] for v in nf.values() if v[0] == "position"])) / K_cal
    res, res_alt = [], []
    for trial, om, free, final in nf.values():
        for store, (tt, xx) in ((res, (t, free)), (res_alt, _smooth(t, free, win, dt))):
            if trial == "position":
                store.append(_settle(tt, xx / K_cal, final / K_cal, btol))
            else:
                store.append(_settle(tt, xx / K_cal - z, om, rtol * om))
    truth = {("7.2.23", "t_startup"): (max(res), "s", None, max(res_alt))}
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

VARIANTS = variants(
    Variant("jjf-dK-shock-vib-mV-1Hz", "jjf2014", "7.2.7,7.2.8",
            text("""
                mV, K ±(1 … 100) mV/(°/s) of either sign; per test a shift of K on no axis, one
                axis (0.2–1 × 3×10⁻³ / 2×10⁻³) or every axis; powered off between calibrations
                on half the devices (K power-on σ 5×10⁻⁵ … 4×10⁻⁴), no 7.2.4 runs; R5 rates to
                100 °/s, 10 × 1 s (CSV), white noise"""),
            build_with(build_change_k, kind="mV", q=0.0, dt=1.0, fmt="csv")),
    Variant("jjf-dK-shock-vib-mVV-10Hz-q-repeats", "jjf2014", "7.2.4,7.2.7,7.2.8",
            text("""
                as jjf-dK-shock-vib-mV-1Hz, mV/V rounded to 0.001 mV/V, 10 s at 10 Hz per rate
                (.npy), flicker ≈ 2 °/h, with six 7.2.4 power-ons (K_r)"""),
            build_with(build_change_k, kind="mV/V", q=0.001, dt=0.1, fmt="npy", flick=2.0,
                       repeats=True)),
    Variant("jjf-dB-shock-vib-mV-1Hz", "jjf2014", "7.2.18,7.2.19",
            text("""
                mV, either sign; per test a bias shift on no axis, one axis (0.2–1 × 30 / 20
                °/h) or every axis; powered off between records on half the devices (turn-on σ
                1–10 °/h), no 7.2.15 runs; records 30 min at 1 s (CSV, `metro plan`'s), white
                noise ARW 0.05–0.5 °/√h"""),
            build_with(build_change_b, kind="mV", q=0.0, dt=1.0, fmt="csv")),
    Variant("jjf-dB-shock-vib-mVV-10Hz-flicker-q-repeats", "jjf2014", "7.2.1,7.2.15,7.2.18,7.2.19",
            text("""
                as jjf-dB-shock-vib-mV-1Hz, mV/V rounded to 0.0005 mV/V at 10 Hz (.npy),
                flicker ≈ 1.5 °/h, wander 1 °/h, six 7.2.15 power-ons (B_r)"""),
            build_with(build_change_b, kind="mV/V", q=0.0005, dt=0.1, fmt="npy", flick=1.5,
                       wander=1.0, repeats=True)),
    Variant("jjf-Bs-mV-10Hz-white", "jjf2014", "7.2.14",
            text("""
                mV, either sign, static 1 h at 10 Hz (CSV), white noise ARW 0.05–0.5 °/√h only"""),
            build_with(build_stability, kind="mV", q=0.0, dt=0.1, fmt="csv")),
    Variant("jjf-Bs-mVV-10Hz-flicker-wander-q", "jjf2014", "7.2.14",
            text("""
                mV/V rounded to 0.0005 mV/V, 1 h at 10 Hz (.npy), flicker plateau ≈ 2 °/h,
                wander ≈ 2 °/h (period 10–60 min), ramp ±(0–20) °/h²"""),
            build_with(build_stability, kind="mV/V", q=0.0005, dt=0.1, fmt="npy", flick=2.0,
                       wander=2.0, ramp=20.0)),
    Variant("jjf-Bw-Td-first-order-mV", "jjf2014", "7.2.1,7.2.21,7.2.22",
            text("""
                mV, either sign; first order + delay (eq. (46)): corner 20–250 Hz, delay 0–2
                ms; N = 10–14 frequencies 10 Hz … 2 × the lab's estimate of B_w, n = 10 records
                of 1 s at 10 kHz (.npy, columns output and reference), amplitude 10–30 % of a
                100–500 °/s range; reference sensor U 0.5 %, phase U 0.2°"""),
            build_with(build_dynamic, kind="mV", q=0.0, order=1, fs=10000.0)),
    Variant("jjf-Bw-Td-second-order-mVV-q", "jjf2014", "7.2.1,7.2.21,7.2.22",
            text("""
                mV/V rounded to 0.001 mV/V; second order (f_n 30–250 Hz, ζ 0.45–1) + delay 0–1
                ms; otherwise as jjf-Bw-Td-first-order-mV"""),
            build_with(build_dynamic, kind="mV/V", q=0.001, order=2, fs=10000.0)),
    Variant("jjf-startup-mV-10Hz", "jjf2014", "7.2.23",
            text("""
                mV, either sign; power-on transients: exponential (0.2–3 °/s, τ 0.3–6 s), two
                exponentials (+ 0.05–0.2 °/s with τ 5–12 s), ringing (0.2–2 Hz), a dead time of
                0.5–3 s at 0 mV, or the drive amplitude building up (τ 0.2–2 s, K scales with
                it); 3 position + 3 rate trials (100, 10, 1 °/s), 60 s at 0.1 s (CSV), each a
                power-on (turn-on σ 1–10 °/h); white noise ARW 0.05–0.5 °/√h"""),
            build_with(build_startup, kind="mV", q=0.0, dt=0.1, fmt="csv")),
    Variant("jjf-startup-mVV-10Hz-quiet-q", "jjf2014", "7.2.23",
            text("""
                as jjf-startup-mV-10Hz, ARW 0.005–0.05 °/√h (the 1 °/s trial's ±1 %
                resolvable), mV/V rounded to 0.0002 mV/V (.npy)"""),
            build_with(build_startup, kind="mV/V", q=0.0002, dt=0.1, fmt="npy", arw=(0.005, 0.05))),
)


#: these variants are scored as the shared harness scores
run_dyn = run_variant


def main(argv=None) -> int:
    return cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-jjfdyn-", alt_label="alt")


if __name__ == "__main__":
    sys.exit(main())

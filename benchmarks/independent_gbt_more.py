"""More of the independent harness: GB/T 45570's scale-factor items and the Allan item.

Run:  nice -n 10 .venv/bin/python benchmarks/independent_gbt_more.py [--devices 30]
      [--variants A,B] [--seed 1] [--json F] [--keep DIR]

benchmarks/independent_campaigns.py scores D.5.1, D.5.3, D.1.1 and D.2.1 on devices metro's
simulators do not make.  This module adds what a lab certifies from the same kind of campaign:
D.1.2 K_n, D.1.3 K_a, D.1.4 K_r (angle method), D.2.2 K_n, D.2.3 K_a, D.2.4 K_r (rate method)
and D.5.6 RWC.  As there, the generators were written from the documentation (docs/data-format.md,
``metro plan``'s step list) and from the standard's clauses (GB/T 45570 D.1.1–D.1.4, D.2.1–D.2.4,
D.5.1, D.5.2, D.5.6); numpy makes every sample; nothing here imports metro (the campaigns are
evaluated through the sibling module's ``run_metro``, which calls ``metro run --json``).

The truth of each result is the clause's measurand on the constructed device:

* K_n, K_a (D.7, D.10, D.24–D.27): the clause's own formula applied to the device's noise-free
  response at the nominal rates — K_i of D.2 (or the F_kj of D.19) without noise, counter or
  table error, then the D.5 / D.21 fits exactly as printed.  The table's error at each set point
  (within its certificate), noise, flicker and the counter are measurement error.
* K (D.5, D.21), scored as well: the same noise-free fit on the power-on the sweep was made on.
* K_r (D.11, D.28): what the Bessel standard deviation of 7 K_j divided by K̄ measures in
  expectation of its square, √(σ_K² + Var(K̂_j)/K²): σ_K the device's relative power-on scatter
  of K, Var(K̂_j) the spread one run's estimate has from noise, counter and rounding, by Monte
  Carlo of this generator in the same layout (as the sibling module does for D.5.3).
* RWC (D.45, D.46): the device's angle random walk, the white rate noise's coefficient in
  °/√h — what α1 is for white noise; the output's rounding and the counter are error.

Devices (none of them metro's): nonlinearity shapes quadratic (g ∝ Ω²), cubic (∝ |Ω|³), odd
(∝ Ω, an even term in the output, which D.2 cancels), linear in |Ω| and a low-rate (lock-in like)
exponential, of either sign; asymmetry of either sign; K different at every power-on; undithered
pulse counters coarse and fine, LSB words coarse and fine, °/h and °/s rate outputs; flicker and
thermal wander; revolutions m = 3 … 8, maximum rates 100 … 500 °/s (R5 below it, D.1.1.2 e)),
sample intervals 5 ms … 1 s, rate tables of U = 1×10⁻⁵ … 1×10⁻⁴.
"""

from __future__ import annotations

import json
import math
import sys
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from independent_campaigns import (  # noqa: E402  (the sibling module: shared writers and scoring)
    COUNTER, OMEGA_E_DEG_H, PLATFORM, R5_GBT, Campaign, Noise, Output, Variant, build_with,
    marine_gyro, score, text, variants)

REV = 1296000.0  # ″ in one revolution (D.2: 360 × 3 600)


# --------------------------------------------------------------------------------------------
# the device's scale factor against rate
# --------------------------------------------------------------------------------------------

def nonlinearity(shape: str, c: float, omega_max: float, omega0: float = 5.0):
    """g(Ω): the relative deviation of the scale factor at the signed rate Ω (°/s), so the output
    is K·Ω·(1 + g(Ω)).  Shapes: 'quadratic' c·(Ω/Ω_m)², 'cubic' c·|Ω/Ω_m|³, 'odd' c·Ω/Ω_m (an
    even, Ω² term in the output), 'abs' c·|Ω|/Ω_m, 'lowrate' c·exp(−|Ω|/Ω₀) (lock-in like)."""
    def g(w):
        x = np.asarray(w, dtype=float) / omega_max
        if shape == "quadratic":
            return c * x ** 2
        if shape == "cubic":
            return c * np.abs(x) ** 3
        if shape == "odd":
            return c * x
        if shape == "abs":
            return c * np.abs(x)
        if shape == "lowrate":
            return c * np.exp(-np.abs(np.asarray(w, dtype=float)) / omega0)
        raise ValueError(shape)
    return g


SHAPES = ("quadratic", "cubic", "odd", "abs", "lowrate")


def r5_points(max_rate: float) -> list[float]:
    """R5 points below the maximum input rate, and the maximum (D.1.1.2 e), D.2.1.2 e))."""
    return [r for r in R5_GBT if r < max_rate * (1 - 1e-9)] + [float(max_rate)]


def line(x, y):
    """Least squares y = a + b·x (D.5/D.6, D.21/D.22 closed forms): (intercept, slope)."""
    x, y = np.asarray(x, float), np.asarray(y, float)
    n = x.size
    den = n * (x * x).sum() - x.sum() ** 2
    b = (n * (x * y).sum() - x.sum() * y.sum()) / den
    a = (y.sum() - b * x.sum()) / n
    return float(a), float(b)


# --------------------------------------------------------------------------------------------
# angle method: D.1.1 – D.1.4
# --------------------------------------------------------------------------------------------

def revolution_counts(rng, *, sign: int, rate: float, m: int, scale: float, K: float, bias: float,
                      noise: Noise, table_err: float, edge: float, clock: list | None = None,
                      phase: float | None = None) -> tuple[np.ndarray, np.ndarray]:
    """m whole revolutions at ``sign``·``rate`` °/s: the pulses counted between revolution pulses
    (an undithered counter: floor of the cumulative angle × K, random start phase) and each
    revolution's duration.  ``scale`` the device's relative scale factor in this direction and at
    this rate, ``bias`` (°/h = ″/s) bias + earth rate, ``table_err`` the table's relative rate
    error, ``edge`` the revolution pulse's position error (uniform ±edge ″); ``clock`` = [t] the
    campaign's time (s), advanced by the revolutions, and ``phase`` the power-on's wander phase,
    so a thermal wander runs on through the whole sweep."""
    T = 360.0 / (rate * (1 + table_err))
    k = max(4, int(math.ceil(T)))
    dt = T / k
    t0 = clock[0] if clock is not None else 0.0
    e, w = noise.draw(m * k, dt, rng, t0=t0, phase=phase)
    if clock is not None:
        clock[0] = t0 + m * T + 60.0  # a minute to reverse or change the rate
    noise_angle = ((e + w) * dt).reshape(m, k).sum(axis=1)            # ″ per revolution
    edges = rng.uniform(-edge, edge, m + 1)
    table_angle = REV + np.diff(edges)
    sensed = sign * table_angle * scale + bias * T + noise_angle
    cum = np.floor(np.cumsum(np.concatenate([[rng.uniform(0, 1)], sensed * K])))
    return np.diff(cum), np.full(m, T)


def write_revolutions(camp: Campaign, sid: str, kind: str, counts, durations, T: float,
                      cond: dict) -> None:
    name = camp.folder / f"{sid}.csv"
    rows = "\n".join(f"{c!r},{d!r}" for c, d in zip(counts.tolist(), durations.tolist()))
    name.write_text(f"count [P],duration [s]\n{rows}\n", encoding="utf-8")
    camp.segments.append((sid, kind, name.name, T, cond, None))


def build_angle(folder: Path, rng, *, K_range=(0.3, 3.0), c_range=(1e-6, 2e-5), asym=2e-5,
                sigma_K_range=(1e-6, 2e-5), flick=0.0, wander=0.0, quick=False) -> dict:
    """A laser gyro (pulse output) on the angle method: the D.1.1 sweep (R5 up to a maximum of
    100 … 500 °/s, m whole revolutions each way), the zero-rate counts of D.1.3.2 a) at the start
    and the end (300 s at τ = 1 s), and 7 power-ons at 30 °/s (D.1.4.2)."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    K = float(rng.uniform(*K_range))                                     # P/″
    max_rate = float(rng.choice([100.0, 250.0, 300.0, 400.0, 500.0]))
    rates = r5_points(max_rate)
    if quick:
        rates = rates[-11:]
    m = int(rng.choice([3, 5, 8])) if not quick else 3
    shape = str(rng.choice(SHAPES))
    c = float(rng.uniform(*c_range)) * (1 if rng.uniform() < 0.5 else -1)
    g = nonlinearity(shape, c, max_rate, float(rng.uniform(2, 10)))
    a = asym * float(rng.uniform(-1, 1))                                 # (K+ − K−)/K
    sigma_K = float(rng.uniform(*sigma_K_range))
    arw = float(rng.uniform(0.001, 0.005))
    noise = Noise(arw, flicker=flick * float(rng.uniform(0.5, 1.5)), wander_amp=wander
                  * float(rng.uniform(0.5, 1.5)),
                  wander_period=float(rng.uniform(3600, 3 * 3600)))
    b_mean = float(rng.uniform(-1, 1))
    U_table = float(rng.choice([1e-5, 3e-5, 1e-4]))
    table = {"id": "RT-X", "role": "rate_table", "revolution_pulse_accuracy": "2″",
             "calibration": {"certificate": "IND-RT-2", "U": repr(U_table), "k": 2}}
    device = {"id": folder.name, "technology": "laser", "application": "aviation",
              "output": "pulse",
              "scale_factor": f"{K!r} P/″", "scale_factor_U": "10 ppm"}
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt="csv", output=Output("pulse", K=K))
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates + [30.0]}

    def scale(sign, r, eps):
        return (1 + eps) * (1 + sign * a / 2) * (1 + float(g(sign * r)))

    # the D.1.1 sweep's power-on
    eps0 = sigma_K * float(rng.standard_normal())
    b0 = b_mean + 0.005 * float(rng.standard_normal())
    zero_out = Output("pulse", K=K)
    clock, phase = [0.0], float(rng.uniform(0, 2 * math.pi))
    n_zero = 300 if not quick else 100

    def zero(tag):
        e, w = noise.draw(n_zero, 1.0, rng, t0=clock[0], phase=phase)
        clock[0] += n_zero + 60.0
        camp.add(f"zero-{tag}", "static-zero", zero_out.record(b0 + earth + e + w, 1.0, rng=rng),
                 1.0,
                 {"orientation": "IRA up"})

    zero("start")
    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            cnt, dur = revolution_counts(rng, sign=sgn, rate=r, m=m, scale=scale(sgn, r, eps0), K=K,
                                         bias=b0 + earth,
                                         noise=noise, table_err=terr[r], edge=2.0, clock=clock,
                                         phase=phase)
            write_revolutions(camp, f"rate{tag}{r:g}", "rate-revolutions", cnt, dur, 360.0 / r,
                              {"rate": f"{sgn * r!r} deg/s", "turns": m})
    zero("end")
    # D.1.4: seven power-ons at 30 °/s, each with its own K and bias
    for j in range(1, 8):
        eps = sigma_K * float(rng.standard_normal())
        bj = b_mean + 0.005 * float(rng.standard_normal())
        for sgn, tag in ((1, "+"), (-1, "-")):
            cnt, dur = revolution_counts(rng, sign=sgn, rate=30.0, m=m, scale=scale(sgn, 30.0, eps),
                                         K=K,
                                         bias=bj + earth, noise=noise, table_err=terr[30.0],
                                         edge=2.0)
            write_revolutions(camp, f"run{j}-rate{tag}30", "revolutions-repeat", cnt, dur, 12.0,
                              {"rate": f"{sgn * 30.0!r} deg/s", "turns": m, "run": j})
    camp.write_manifest()

    # truth: the clause's formulas on the noise-free K_i of this power-on
    w_ = np.array(rates)
    kp = K * np.array([scale(1, r, eps0) for r in rates])                 # K_+i (D.8 without noise)
    km = K * np.array([scale(-1, r, eps0) for r in rates])                # K_−i (D.9)
    ki = (kp + km) / 2                                                     # D.2
    K_fit, _ = line(w_, ki)                                                # D.5
    Kn = float(np.max(np.abs(ki - K_fit)) / K_fit)                         # D.7
    Kp_fit, Km_fit = line(w_, kp)[0], line(w_, km)[0]
    Ka = abs(Kp_fit - Km_fit) / ((Kp_fit + Km_fit) / 2)                    # D.10
    # D.11 in expectation: the power-on scatter and one run's K_j spread from noise and counter
    draws = 80 if quick else 300
    kj = []
    for _ in range(draws):
        n_p, _d = revolution_counts(rng, sign=1, rate=30.0, m=m, scale=scale(1, 30.0, 0.0), K=K,
                                    bias=b_mean + earth,
                                    noise=noise, table_err=terr[30.0], edge=2.0)
        n_m, _d = revolution_counts(rng, sign=-1, rate=30.0, m=m, scale=scale(-1, 30.0, 0.0), K=K,
                                    bias=b_mean + earth, noise=noise, table_err=terr[30.0],
                                    edge=2.0)
        kj.append((n_p.mean() - n_m.mean()) / (2 * REV))
    kbar = K * (scale(1, 30.0, 0.0) + scale(-1, 30.0, 0.0)) / 2
    Kr = math.sqrt(sigma_K ** 2 + float(np.var(kj, ddof=1)) / kbar ** 2)
    meta = {"shape": shape, "c": c, "a": a, "sigma_K": sigma_K, "m": m, "max_rate": max_rate,
            "U_table": U_table}
    (folder / "truth.json").write_text(json.dumps(meta))
    return {("D.1.1", "K"): (K_fit, "P/″", ""),
            ("D.1.2", "Kn"): (Kn, "", ""),
            ("D.1.3", "Ka"): (Ka, "", ""),
            ("D.1.4", "Kr"): (Kr, "", "")}


def kt_ppm(kT, temps, actual: dict) -> float:
    """The K_t truth of D.1.5 / D.2.5 (ppm/°C) on the noise-free K(T): the largest
    |K(T_i) − K(T_0)|/(K(T_0)·|T_i − T_0|) over the chamber's actual temperatures, T_0 the point
    set nearest 20 °C."""
    i0 = int(np.argmin([abs(T - 20.0) for T in temps]))
    T0 = actual[temps[i0]]
    Kt = max(abs((kT(actual[T]) - kT(T0)) / (kT(T0) * (actual[T] - T0))) for i, T
             in enumerate(temps) if i != i0)
    return Kt * 1e6


def build_kt_angle(folder: Path, rng, *, sigma_K_range=(1e-6, 2e-5), repeats: bool = True,
                   quick=False) -> dict:
    """D.1.5 (and D.1.4) on a laser gyro, pulse output (undithered counter): the D.1.1 sweep (R5 up
    to 100 … 400 °/s, m whole revolutions each way) at 3 points (both limits and room temperature,
    D.1.5.2 b)) or 5, each a power-on of its own (D.1.5.2 c): off while the chamber changes), with
    its own K (power-on scatter σ_K 1–20 ppm) and bias; K(T) = K·(1 + k₁(T − 20) + k₂(T − 20)²), k₁
    up to ±5×10⁻⁶/°C of either sign; ``repeats``: D.1.4's 7 power-ons at 30 °/s at room temperature.
    Truth: D.12 on the noise-free K(T_i) at the temperatures the chamber held (± 0.25 °C), the D.5
    intercept of each point's noise-free K_i (the nonlinearity does not change with T, so
    K(T_i)/K(T₀) is kT(T_i)/kT(T₀)); the power-on scatter, noise and counter are error."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    K = float(rng.uniform(0.3, 3.0))
    max_rate = float(rng.choice([100.0, 250.0, 400.0]))
    rates = r5_points(max_rate)[-11:] if quick else r5_points(max_rate)
    m = 3 if quick else int(rng.choice([3, 5]))
    shape = str(rng.choice(SHAPES))
    g = nonlinearity(shape, float(rng.uniform(1e-6, 2e-5)) * (1 if rng.uniform() < 0.5 else -1),
                     max_rate,
                     float(rng.uniform(2, 10)))
    a = 2e-5 * float(rng.uniform(-1, 1))
    sigma_K = float(rng.uniform(*sigma_K_range))
    k1 = float(rng.uniform(-1, 1)) * float(rng.choice([2e-7, 1e-6, 5e-6]))
    k2 = float(rng.uniform(-1, 1)) * 1e-8
    noise = Noise(float(rng.uniform(0.001, 0.005)))
    U_table = float(rng.choice([1e-5, 3e-5, 1e-4]))
    table = {"id": "RT-X", "role": "rate_table", "revolution_pulse_accuracy": "2″",
             "calibration": {"certificate": "IND-RT-2", "U": repr(U_table), "k": 2}}
    chamber = {
        "id": "CH-X",
        "role": "chamber",
        "calibration": {"certificate": "IND-CH-1", "U": "0.5 K", "k": 2},
    }
    device = {"id": folder.name, "technology": "laser", "application": "aviation",
              "output": "pulse",
              "scale_factor": f"{K!r} P/″", "scale_factor_U": "10 ppm"}
    camp = Campaign(folder, device, lat, [table, COUNTER, chamber], fmt="csv",
                    output=Output("pulse", K=K))
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates + [30.0]}
    room = float(rng.uniform(18, 25))
    temps = [-40.0, room, 60.0] if rng.uniform() < 0.5 else [-40.0, -10.0, room, 40.0, 70.0]

    def kT(T):
        return 1 + k1 * (T - 20) + k2 * (T - 20) ** 2

    def scale(sign, r, rel):
        return rel * (1 + sign * a / 2) * (1 + float(g(sign * r)))

    actual = {}
    for i, T in enumerate(temps):
        Ta = T + 0.25 * float(rng.standard_normal())
        actual[T] = Ta
        rel = kT(Ta) * (1 + sigma_K * float(rng.standard_normal()))      # this power-on's K
        b_on = float(rng.uniform(-1, 1)) + earth
        for r in rates:
            for sgn, tag in ((1, "+"), (-1, "-")):
                cnt, dur = revolution_counts(rng, sign=sgn, rate=r, m=m, scale=scale(sgn, r, rel),
                                             K=K, bias=b_on,
                                             noise=noise, table_err=terr[r], edge=2.0)
                write_revolutions(camp, f"T{i + 1}-rate{tag}{r:g}", "revolutions-temperature", cnt,
                                  dur, 360.0 / r,
                                  {"rate": f"{sgn * r!r} deg/s", "turns": m,
                                   "temperature": f"{T!r} °C"})
    if repeats:
        for j in range(1, 8):
            rel = kT(room) * (1 + sigma_K * float(rng.standard_normal()))
            b_on = float(rng.uniform(-1, 1)) + earth
            for sgn, tag in ((1, "+"), (-1, "-")):
                cnt, dur = revolution_counts(rng, sign=sgn, rate=30.0, m=m,
                                             scale=scale(sgn, 30.0, rel), K=K,
                                             bias=b_on, noise=noise, table_err=terr[30.0], edge=2.0)
                write_revolutions(camp, f"run{j}-rate{tag}30", "revolutions-repeat", cnt, dur, 12.0,
                                  {"rate": f"{sgn * 30.0!r} deg/s", "turns": m, "run": j})
    camp.write_manifest()
    (folder / "truth.json").write_text(json.dumps({"sigma_K": sigma_K, "k1": k1, "k2": k2,
                                                   "temps": temps,
                                                   "m": m, "shape": shape}))
    return {("D.1.5", "Kt"): (kt_ppm(kT, temps, actual), "ppm/°C", "")}


# --------------------------------------------------------------------------------------------
# rate method: D.2.1 – D.2.4
# --------------------------------------------------------------------------------------------

def build_rate(folder: Path, rng, *, kind: str, dt: float, seconds: float, q: float,
               fmt: str = "npy",
               c_range=(2e-5, 5e-4), asym=3e-4, sigma_K_range=(5e-6, 1e-4), flick=0.005,
               wander=0.02,
               arw_range=(0.002, 0.02), quick=False) -> dict:
    """A fibre gyro on the rate method: the D.2.1 sweep (rest at start and end, R5 rates up to a
    maximum of 100 … 500 °/s both ways, ``seconds`` at each) and 7 more power-ons of it (D.2.4.2).
    ``kind``: 'LSB' (K in LSB/[(°)/s] of about 3600/q, rounded to whole LSB), 'deg/h' or 'deg/s'
    (a rate output rounded to ``q`` in its unit, K then a ratio)."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    max_rate = float(rng.choice([100.0, 200.0, 300.0, 400.0, 500.0]))
    rates = r5_points(max_rate)
    if quick:
        rates = rates[-11:]
    shape = str(rng.choice(SHAPES))
    c = float(rng.uniform(*c_range)) * (1 if rng.uniform() < 0.5 else -1)
    g = nonlinearity(shape, c, max_rate, float(rng.uniform(2, 10)))
    a = asym * float(rng.uniform(-1, 1))
    sigma_K = float(rng.uniform(*sigma_K_range))
    noise = Noise(float(rng.uniform(*arw_range)), flicker=flick * float(rng.uniform(0.5, 1.5)),
                  wander_amp=wander * float(rng.uniform(0.5, 1.5)),
                  wander_period=float(rng.uniform(1200, 5400)))
    b_mean = float(rng.uniform(-2, 2))
    U_table = float(rng.choice([1e-5, 3e-5, 1e-4]))
    table = {"id": "RT-X", "role": "rate_table",
             "calibration": {"certificate": "IND-RT-3", "U": repr(U_table), "k": 2}}
    device = {"id": folder.name, "technology": "fibre", "application": "marine",
              "nonlinearity": "100 ppm"}
    if kind == "LSB":
        Kout = 3600.0 / q * float(rng.uniform(0.8, 1.25))               # LSB/(°/s)
        out = Output("LSB", K=Kout)
        device |= {"output": "digital", "scale_factor": f"{Kout!r} LSB/(°/s)",
                   "scale_factor_U": "50 ppm"}
        to_out = Kout / 3600.0                                             # output per °/h
        unit = "LSB/(°/s)"
    else:
        out = Output("deg/h", q=q * (3600.0 if kind == "deg/s" else 1.0))
        device |= {"output": "rate", "resolution": f"{q!r} {'°/s' if kind == 'deg/s' else '°/h'}"}
        to_out = 1.0 / 3600.0 if kind == "deg/s" else 1.0                 # output per °/h
        unit = ""
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt=fmt, output=out)
    if kind == "deg/s":
        camp.output = _RateSeconds(q)
    n = int(round((seconds if not quick else min(seconds, 20.0)) / dt))
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates}

    def sweep(prefix: str, eps: float, run: int | None, write: bool = True):
        """One D.2.1 test; returns the mean outputs (rest removed) it wrote."""
        b_on = b_mean + 0.01 * float(rng.standard_normal())
        phase = float(rng.uniform(0, 2 * math.pi))
        t0 = 0.0
        means = {}

        def seg(rate_dps: float, true_rate: float):
            nonlocal t0
            e, w = noise.draw(n, dt, rng, t0=t0, phase=phase)
            t0 += n * dt + 30.0
            s = 0 if rate_dps == 0 else (1 if rate_dps > 0 else -1)
            sc = 1.0 if s == 0 else (1 + eps) * (1 + s * a / 2) * (1 + float(g(rate_dps)))
            sensed = true_rate * 3600.0 * sc + b_on + earth + e + w        # °/h
            return camp.output.record(sensed, dt, rng=rng)

        extra = {} if run is None else {"run": run}
        v = seg(0.0, 0.0)
        if write:
            camp.add(f"{prefix}rest-start", "rate-static", v, dt, {"when": "start", **extra})
        rest = [float(v.mean())]
        for r in rates:
            for sgn, tag in ((1, "+"), (-1, "-")):
                v = seg(sgn * r, sgn * r * (1 + terr[r]))
                if write:
                    camp.add(f"{prefix}rate{tag}{r:g}", "rate-output", v, dt,
                             {"rate": f"{sgn * r!r} deg/s", **extra})
                means[sgn * r] = float(v.mean())
        v = seg(0.0, 0.0)
        if write:
            camp.add(f"{prefix}rest-end", "rate-static", v, dt, {"when": "end", **extra})
        rest.append(float(v.mean()))
        fr = sum(rest) / 2
        return {k: x - fr for k, x in means.items()}

    eps0 = sigma_K * float(rng.standard_normal())
    sweep("", eps0, None)
    for j in range(1, 8):
        sweep(f"run{j}-", sigma_K * float(rng.standard_normal()), j)
    camp.write_manifest()

    # truth: D.19–D.27 on the noise-free F_kj at the nominal rates (this power-on's K)
    w_ = np.array([s * r for r in rates for s in (1, -1)])
    Kunit = Kout if kind == "LSB" else to_out * 3600.0                    # output per °/s
    F = Kunit * w_ * (1 + eps0) * (1 + np.sign(w_) * a / 2) * (1 + g(w_))
    F0, Ks = line(w_, F)                                                  # D.21, D.22
    Fhat = Ks * w_ + F0                                                   # D.23
    top = np.abs(w_) == np.abs(w_).max()
    Fm = float(np.max(np.abs(F[top])))
    Kn = float(np.max(np.abs(Fhat - F)) / Fm)                             # D.24, D.25
    pos, neg = w_ > 0, w_ < 0
    Kp, Km = line(w_[pos], F[pos])[1], line(w_[neg], F[neg])[1]
    Ka = abs(Kp - Km) / ((Kp + Km) / 2)                                   # D.26, D.27
    # D.28 in expectation: σ_K² + Var(K̂_j)/K² (this generator, this layout, Monte Carlo)
    draws = 20 if quick else 60
    kj = []
    for _ in range(draws):
        mm = sweep("", 0.0, None, write=False)
        x = np.array(list(mm.keys()))
        y = np.array(list(mm.values()))
        kj.append(line(x, y)[1])
    kbar = Kunit * (1 + 0.0)
    Kr = math.sqrt(sigma_K ** 2 + float(np.var(kj, ddof=1)) / kbar ** 2)
    meta = {"shape": shape, "c": c, "a": a, "sigma_K": sigma_K, "max_rate": max_rate,
            "U_table": U_table,
            "Kr_noise": float(np.std(kj, ddof=1) / kbar)}
    (folder / "truth.json").write_text(json.dumps(meta))
    # K of a rate output is a ratio (output rate per table rate): the slope per °/s in °/s
    return {("D.2.1", "K"): (Ks if kind == "LSB" else Ks / (to_out * 3600.0), unit, ""),
            ("D.2.2", "Kn"): (Kn, "", ""),
            ("D.2.3", "Ka"): (Ka, "", ""),
            ("D.2.4", "Kr"): (Kr, "", "")}


def build_kt(folder: Path, rng, *, dt: float = 1.0, seconds: float = 100.0, q: float = 0.05,
             sigma_K_range=(5e-6, 1e-4), repeats: bool = True, quick=False) -> dict:
    """D.2.5 (and D.2.4) on a fibre gyro, LSB output: the D.2.1 sweep at 5 or 6 temperatures
    (D.2.5.2 b), R5 points evenly spread, room temperature among them), each a power-on of its own
    (D.2.5.2 c): off while the chamber changes), K(T) = K·(1 + k₁(T − 20) + k₂(T − 20)²), k₁ up to
    ±5×10⁻⁵/°C of either sign, K's power-on scatter σ_K; ``repeats``: D.2.4's 7 power-ons at room
    temperature in the campaign.  Truth: D.29 on the noise-free K(T_i) (the D.21 slope of the
    noise-free F_kj of each point's sweep, without the power-on scatter)."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    max_rate = float(rng.choice([100.0, 200.0, 300.0]))
    rates = r5_points(max_rate)[-11:] if quick else r5_points(max_rate)
    sigma_K = float(rng.uniform(*sigma_K_range))
    k1 = float(rng.uniform(-1, 1)) * float(rng.choice([1e-6, 1e-5, 5e-5]))
    k2 = float(rng.uniform(-1, 1)) * 2e-7
    noise = Noise(float(rng.uniform(0.002, 0.02)))
    U_table = float(rng.choice([1e-5, 3e-5, 1e-4]))
    table = {"id": "RT-X", "role": "rate_table",
             "calibration": {"certificate": "IND-RT-3", "U": repr(U_table), "k": 2}}
    chamber = {
        "id": "CH-X",
        "role": "chamber",
        "calibration": {"certificate": "IND-CH-1", "U": "0.5 K", "k": 2},
    }
    Kout = 3600.0 / q * float(rng.uniform(0.8, 1.25))
    out = Output("LSB", K=Kout)
    device = {"id": folder.name, "technology": "fibre", "application": "marine",
              "nonlinearity": "100 ppm",
              "output": "digital", "scale_factor": f"{Kout!r} LSB/(°/s)",
              "scale_factor_U": "50 ppm"}
    camp = Campaign(folder, device, lat, [table, COUNTER, chamber], fmt="npy", output=out)
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates}
    n = int(round((seconds if not quick else 20.0) / dt))
    room = float(rng.uniform(18, 25))
    temps = [-40.0, -20.0, 0.0, room, 40.0,
             60.0] if rng.uniform() < 0.5 else [-40.0, -10.0, room, 40.0, 70.0]

    def kT(T):
        return 1 + k1 * (T - 20) + k2 * (T - 20) ** 2

    def sweep(prefix, rel, cond):
        b_on = float(rng.uniform(-2, 2))
        def seg(true_rate):
            e, _w = noise.draw(n, dt, rng)
            return out.record(true_rate * 3600.0 * rel + b_on + earth + e, dt, rng=rng)
        camp.add(f"{prefix}rest-start", "rate-static", seg(0.0), dt, {"when": "start", **cond})
        for r in rates:
            for sgn, tag in ((1, "+"), (-1, "-")):
                camp.add(f"{prefix}rate{tag}{r:g}", "rate-output", seg(sgn * r * (1 + terr[r])), dt,
                         {"rate": f"{sgn * r!r} deg/s", **cond})
        camp.add(f"{prefix}rest-end", "rate-static", seg(0.0), dt, {"when": "end", **cond})

    actual = {}
    for i, T in enumerate(temps):
        Ta = T + 0.25 * float(rng.standard_normal())
        actual[T] = Ta
        sweep(f"T{i + 1}-", kT(Ta) * (1 + sigma_K * float(rng.standard_normal())),
              {"temperature": f"{T!r} °C"})
    if repeats:
        for j in range(1, 8):
            sweep(f"run{j}-", kT(room) * (1 + sigma_K * float(rng.standard_normal())), {"run": j})
    camp.write_manifest()
    (folder / "truth.json").write_text(json.dumps({"sigma_K": sigma_K, "k1": k1, "k2": k2,
                                                   "temps": temps}))
    return {("D.2.5", "Kt"): (kt_ppm(kT, temps, actual), "ppm/°C", "")}


class _RateSeconds(Output):
    """A rate output in °/s rounded to ``q`` °/s (the device's sensed rate arrives in °/h)."""

    def __init__(self, q: float):
        super().__init__("deg/h", q=q)

    @property
    def unit(self) -> str:
        return "°/s"

    def record(self, rate_deg_h, dt, K_scale=1.0, rng=None):
        y = np.asarray(rate_deg_h) * K_scale / 3600.0
        return np.round(y / self.q) * self.q if self.q else y


# --------------------------------------------------------------------------------------------
# D.5.6 angle random walk
# --------------------------------------------------------------------------------------------

def build_arw(folder: Path, rng, *, kind: str, dt: float, hours: float, q: float = 0.0,
              flick: float = 0.0,
              wander: float = 0.0, arw_range=(0.001, 0.005), fmt: str = "npy", quick=False) -> dict:
    """D.5.6 (with D.5.1 on the same record): one static record, IRA up, warm-up 30 min, of
    ``hours`` at ``dt`` (D.5.6.2 asks for 8 h at τ = 1 s).  ``kind``: 'pulse' (dithered
    readout), 'pulse-undithered', 'LSB' (1 LSB = q °/h), 'deg/h' (rounded to q)."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    arw = float(rng.uniform(*arw_range))
    noise = Noise(arw, flicker=flick * float(rng.uniform(0.5, 1.5)), wander_amp=wander
                  * float(rng.uniform(0.5, 1.5)),
                  wander_period=float(rng.uniform(1200, 5400)))
    b = float(rng.uniform(-0.5, 0.5))
    # a dithered readout for 'pulse' (D.45's α2 term: white angle noise)
    device, out = marine_gyro(folder, rng, kind, q=q, K_range=(0.5, 3.0), dithered=kind == "pulse")
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER], fmt=fmt, output=out)
    n = int(round((hours if not quick else 1.0) * 3600 / dt))
    e, w = noise.draw(n, dt, rng)
    camp.add("static-8h", "static", out.record(b + earth + e + w, dt, rng=rng), dt,
             {"orientation": "IRA up", "warmup": "30 min"})
    camp.write_manifest()
    return {("D.5.6", "RWC"): (arw, "°/√h", "")}


# --------------------------------------------------------------------------------------------
# D.5.4 bias temperature sensitivity, D.5.5 bias magnetic sensitivity
# --------------------------------------------------------------------------------------------

def build_bias_env(folder: Path, rng, *, kind: str, dt: float, q: float = 0.0, flick: float = 0.0,
                   repeats: bool = True, field_power_ons: bool = False, fmt: str = "npy",
                   quick=False) -> dict:
    """D.5.4 and D.5.5 on one device.  D.5.4.2 c): the gyro is off while the chamber changes
    temperature, so each point is a power-on of its own — its bias carries the device's turn-on
    scatter σ_on (D.5.3).  Bias against temperature: B(T) = b + c₁(T − 20) + c₂(T − 20)², either
    sign, the chamber within ±0.5 °C of its set point (its certificate: U = 0.5 °C, k = 2).
    D.5.5: ±H_b (0.5–2 mT) along IRA, XRA, YRA, 10 min each, the bias b + S_ax·H (+ an even term
    that D.44 cancels), the field within ±5 % of its setting (D.5.5.1 b)); ``field_power_ons``:
    each of the six biases is a power-on of its own ("as D.5.1.2", which powers on and off).
    ``repeats``: the campaign also holds D.5.3's 7 power-ons at room temperature."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    arw = float(rng.uniform(0.001, 0.005))
    noise = Noise(arw, flicker=flick * float(rng.uniform(0.5, 1.5)))
    sigma_on = float(rng.uniform(0.002, 0.01))
    b = float(rng.uniform(-0.5, 0.5))
    c1 = float(rng.uniform(-1, 1)) * float(rng.choice([2e-5, 2e-4, 2e-3]))        # °/h/°C
    c2 = float(rng.uniform(-1, 1)) * 2e-5                                         # °/h/°C²
    S = {ax: float(rng.uniform(-1, 1)) * float(rng.choice([1e-4, 1e-3, 1e-2])) for ax
         in ("IRA", "XRA", "YRA")}
    # °/h/mT², cancels in D.44
    even = float(rng.uniform(-1, 1)) * 1e-3
    device, out = marine_gyro(folder, rng, kind, q=q, K_range=(0.5, 3.0))
    chamber = {
        "id": "CH-X",
        "role": "chamber",
        "calibration": {"certificate": "IND-CH-1", "U": "0.5 K", "k": 2},
    }
    Hb = float(rng.choice([0.5, 1.0, 2.0]))
    gen = {"id": "FG-X", "role": "field_generator", "uniformity": "5 %",
           "calibration": {"certificate": "IND-FG-1", "U": "0.02", "k": 2}}
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER, chamber, gen], fmt=fmt, output=out)
    lo, hi = [(-40.0, 60.0), (-55.0, 70.0), (-20.0, 50.0)][int(rng.integers(0, 3))]
    room = float(rng.uniform(18, 25))
    temps = [lo, room, hi] if rng.uniform() < 0.5 else [lo, (lo + room) / 2, room, (room + hi) / 2,
                                                        hi]
    n_h = int(round((3600 if not quick else 600) / dt))

    def B(T):
        return b + c1 * (T - 20) + c2 * (T - 20) ** 2

    actual = {}
    for i, T in enumerate(temps):
        Ta = T + 0.25 * float(rng.standard_normal())
        actual[T] = Ta
        e, w = noise.draw(n_h, dt, rng)
        b_on = B(Ta) + sigma_on * float(rng.standard_normal())
        camp.add(f"temperature-{i + 1}", "static-temperature",
                 out.record(b_on + earth + e + w, dt, rng=rng), dt,
                 {"orientation": "IRA up", "temperature": f"{T!r} °C"})
    if repeats:
        for j in range(1, 8):
            e, w = noise.draw(n_h, dt, rng)
            b_on = B(room) + sigma_on * float(rng.standard_normal())
            camp.add(f"repeat-{j}", "static-repeat", out.record(b_on + earth + e + w, dt, rng=rng),
                     dt,
                     {"orientation": "IRA up", "run": j, "warmup": "30 min"})
    n_f = int(round(600 / dt))
    b_field = B(20.0) + sigma_on * float(rng.standard_normal())
    for ax in ("IRA", "XRA", "YRA"):
        for sgn, tag in ((1, "plus"), (-1, "minus")):
            H = sgn * Hb * (1 + float(rng.uniform(-0.05, 0.05)))
            e, w = noise.draw(n_f, dt, rng)
            b_on = (B(20.0) + sigma_on
                    * float(rng.standard_normal())) if field_power_ons else b_field
            rate = b_on + S[ax] * H + even * H ** 2 + earth + e + w
            camp.add(f"field-{ax}-{tag}", "static-field", out.record(rate, dt, rng=rng), dt,
                     {"orientation": "IRA up", "field_axis": ax, "field": f"{sgn * Hb!r} mT"})
    camp.write_manifest()
    # truth: D.43 on the noise-free B(T) at the temperatures the chamber held (the nearest to
    # 20 °C is room temperature, as D.5.4 takes it); D.44 on the noise-free biases ±H_b
    i0 = int(np.argmin([abs(T - 20.0) for T in temps]))
    T0 = actual[temps[i0]]
    Bt = max(abs((B(actual[T]) - B(T0)) / (actual[T] - T0)) for i, T in enumerate(temps) if i != i0)
    meta = {"sigma_on": sigma_on, "c1": c1, "c2": c2, "S": S, "temps": temps, "arw": arw}
    (folder / "truth.json").write_text(json.dumps(meta))
    truth = {("D.5.4", "Bt"): (Bt, "°/h/°C", "")}
    for ax in ("IRA", "XRA", "YRA"):
        truth[("D.5.5", f"Bh_{ax}")] = (abs(S[ax]), "°/h/mT", "")
    return truth


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

ANGLE_ITEMS = "D.1.1,D.1.2,D.1.3,D.1.4"
RATE_ITEMS = "D.2.1,D.2.2,D.2.3,D.2.4"

VARIANTS = variants(
    Variant("angle-pulse-fine", "gbt45570", ANGLE_ITEMS,
            text("""
                laser gyro, pulse 0.3–3 P/″ (undithered counter), nonlinearity 1–20 ppm of the
                five shapes, either sign, asymmetry ±20 ppm, K power-on σ 1–20 ppm, m = 3/5/8,
                max rate 100–500 °/s, table U 1e-5–1e-4"""),
            build_with(build_angle)),
    Variant("angle-pulse-coarse-flicker", "gbt45570", ANGLE_ITEMS,
            text("""
                as angle-pulse-fine with a coarse pulse (0.05–0.2 P/″: 1 P = 5–20″), flicker
                0.01 °/h, nonlinearity 5–50 ppm, asymmetry ±50 ppm, K power-on σ 2–40 ppm"""),
            build_with(build_angle, K_range=(0.05, 0.2), c_range=(5e-6, 5e-5), asym=5e-5,
                       sigma_K_range=(2e-6, 4e-5), flick=0.01)),
    Variant("angle-pulse-drift", "gbt45570", ANGLE_ITEMS,
            text("""
                as angle-pulse-fine with a slow thermal bias wander of 0.005–0.045 °/h
                amplitude (period 1–3 h) running through the whole sweep, the zero-rate counts
                at its start and end"""),
            build_with(build_angle, wander=0.03)),
    Variant("rate-lsb-10Hz", "gbt45570", RATE_ITEMS,
            text("""
                fibre gyro, LSB word 1 LSB ≈ 0.05 °/h (finer than the noise), 10 Hz, 100 s per
                point, .npy; nonlinearity 20–500 ppm of five shapes, asymmetry ±300 ppm, K
                power-on σ 5–100 ppm, flicker, wander"""),
            build_with(build_rate, kind="LSB", dt=0.1, seconds=100.0, q=0.05)),
    Variant("rate-lsb-coarse-1Hz", "gbt45570", RATE_ITEMS,
            text("""
                LSB word 1 LSB ≈ 2 °/h (coarser than the 1 Hz noise of 0.1–0.6 °/h), 1 Hz, 100
                s per point, CSV"""),
            build_with(build_rate, kind="LSB", dt=1.0, seconds=100.0, q=2.0, fmt="csv",
                       arw_range=(0.002, 0.01))),
    Variant("rate-degh-200Hz", "gbt45570", RATE_ITEMS,
            text("""
                rate output in °/h rounded to 0.1 °/h, 200 Hz, 10 s per point (.npy),
                nonlinearity 20–500 ppm"""),
            build_with(build_rate, kind="deg/h", dt=0.005, seconds=10.0, q=0.1)),
    Variant("rate-degs-1Hz", "gbt45570", RATE_ITEMS,
            text("""
                rate output in °/s rounded to 1e-5 °/s (0.036 °/h), 1 Hz, 60 s per point, CSV"""),
            build_with(build_rate, kind="deg/s", dt=1.0, seconds=60.0, q=1e-5, fmt="csv")),
    Variant("kt-rate-lsb-1Hz", "gbt45570", "D.2.5",
            text("""
                fibre gyro, LSB 0.05 °/h, 1 Hz, 100 s per point; D.2.1 sweeps at 5 or 6
                temperatures −40 … 70 °C, each a power-on with K's scatter σ_K 5–100 ppm; K(T)
                slope up to ±50 ppm/°C with a curvature; D.2.4's 7 runs"""),
            build_with(build_kt)),
    Variant("kt-angle-pulse", "gbt45570", "D.1.5",
            text("""
                laser gyro, pulse 0.3–3 P/″ (undithered counter); the D.1.1 sweep at 3 or 5
                temperatures −40 … 70 °C (room 18–25 °C), each a power-on with K's scatter σ_K
                1–20 ppm (D.1.5.2 c)); K(T) slope up to ±5 ppm/°C with a curvature; D.1.4's 7
                runs at 30 °/s"""),
            build_with(build_kt_angle)),
    Variant("arw-pulse-dithered-1Hz", "gbt45570", "D.5.6",
            text("""
                pulse 0.5–3 P/″ read at a random phase (dithered), 8 h at 1 Hz, ARW 0.001–0.005
                °/√h, white only"""),
            build_with(build_arw, kind="pulse", dt=1.0, hours=8.0)),
    Variant("arw-pulse-dithered-flicker", "gbt45570", "D.5.6",
            text("""
                as above with a flicker plateau 0.002 °/h and a thermal wander 0.003 °/h"""),
            build_with(build_arw, kind="pulse", dt=1.0, hours=8.0, flick=0.002, wander=0.003)),
    Variant("arw-lsb-fine-10Hz", "gbt45570", "D.5.6",
            text("""
                LSB word 1 LSB = 0.05 °/h (finer than the 10 Hz noise), 8 h at 10 Hz (.npy)"""),
            build_with(build_arw, kind="LSB", dt=0.1, hours=8.0, q=0.05)),
    Variant("arw-rate-degh-5Hz", "gbt45570", "D.5.6",
            text("""
                rate output in °/h rounded to 0.2 °/h (≈ the 5 Hz noise), 8 h at 5 Hz, ARW
                0.002–0.01 °/√h"""),
            build_with(build_arw, kind="deg/h", dt=0.2, hours=8.0, q=0.2, arw_range=(0.002, 0.01))),
    Variant("bt-bh-pulse-1Hz", "gbt45570", "D.5.4,D.5.5",
            text("""
                pulse 0.5–3 P/″ (undithered), 1 Hz CSV; bias against T linear ±(2e-5…2e-3)
                °/h/°C plus a curvature, 3 or 5 points with limits −55…70 °C, turn-on σ
                0.002–0.01 °/h per power-on, D.5.3's 7 repeats in the campaign; field ±0.5–2
                mT, S up to 0.01 °/h/mT per axis, the six field biases in one power-on"""),
            build_with(build_bias_env, kind="pulse", dt=1.0, fmt="csv")),
    Variant("bt-bh-lsb-10Hz-flicker", "gbt45570", "D.5.4,D.5.5",
            text("""
                LSB 1 LSB = 0.05 °/h, 10 Hz (.npy), flicker 0.003 °/h, D.5.3's repeats, the six
                field biases in one power-on"""),
            build_with(build_bias_env, kind="LSB", dt=0.1, q=0.05, flick=0.003)),
    Variant("bt-bh-lsb-10Hz-flicker-no-repeats", "gbt45570", "D.5.4,D.5.5",
            text("""
                LSB 1 LSB = 0.05 °/h, 10 Hz (.npy), flicker 0.003 °/h, no D.5.3 repeats, each
                field bias its own power-on"""),
            build_with(build_bias_env, kind="LSB", dt=0.1, q=0.05, flick=0.003, repeats=False,
                       field_power_ons=True)),
    Variant("arw-pulse-undithered-1Hz", "gbt45570", "D.5.6",
            text("""
                undithered pulse counter 0.5–3 P/″, 8 h at 1 Hz (the sawtooth issue 13 names)"""),
            build_with(build_arw, kind="pulse-undithered", dt=1.0, hours=8.0)),
)

#: results whose unit metro may state as ppm (dimensionless in the truth)
_PPM_KEYS = ("Kn", "Ka", "Kr")
_UNITS = {"°/√h": {"°/√h", "deg/h⁰⋅⁵", "deg/hour**0.5", "degree / hour ** 0.5", "°/h⁰⋅⁵", "(°)/√h"},
          "°/h/°C": {"°/h/°C", "°/°C/h", "deg/h/delta_degC", "deg/h/Δ°C", "deg/hour/delta_degC",
                     "degree / hour / delta_degree_Celsius"},
          "ppm/°C": {"ppm/°C", "ppm/Δ°C", "ppm/delta_degC", "1e-06/delta_degC"},
          "°/h/mT": {"°/h/mT", "deg/h/mT", "deg/hour/mT", "degree / hour / millitesla"}}


def score_more(truth: dict, doc: dict) -> list[dict]:
    """The sibling module's score, after K_n/K_a/K_r in ppm or % are made ratios and RWC's unit
    spellings are accepted."""
    doc = dict(doc)
    res = []
    for r in doc.get("results", []):
        r = dict(r)
        if r.get("key") in _PPM_KEYS and r.get("unit") in ("ppm", "%"):
            f = 1e-6 if r["unit"] == "ppm" else 1e-2
            r["value"] = None if r.get("value") is None else r["value"] * f
            r["U"] = None if r.get("U") is None else r["U"] * f
            r["unit"] = ""
        for canon, spellings in _UNITS.items():
            if r.get("unit") in spellings:
                r["unit"] = canon
        res.append(r)
    doc["results"] = res
    return score(truth, doc)


def main(argv=None) -> int:
    """The shared command line (``independent_campaigns.cli``), scoring through
    :func:`score_more`."""
    import independent_campaigns as ic

    return ic.cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-more-",
                  run=lambda v, a, work: ic.run_variant(v, a.devices, a.seed, work, a.subprocess,
                                                        quick=a.quick,
                                                        keep=a.keep is not None, scorer=score_more))


if __name__ == "__main__":
    sys.exit(main())

"""The independent harness on the rest of GB/T 45570: environment, polarity, set-up, power, D.3,
D.4, D.6.

Run:  nice -n 10 .venv/bin/python benchmarks/independent_gbt_env.py [--devices 30]
      [--variants A,B] [--seed 1] [--json F] [--keep DIR]

benchmarks/independent_campaigns.py and independent_gbt_more.py score D.1.1–D.2.5 and D.5.1–D.5.6.
This module covers what no harness did: 6.2.6 polarity, 6.2.7.7 set-up time, 6.2.7.8 power
consumption, the 6.2.8 environmental tests done elsewhere (ΔB₀ and ΔK/K before/after; the
angle-method and the rate-method scale factor), D.3 maximum input rate, D.4 threshold and
D.6.1–D.6.4 (bias at the low and high temperature, vibration, mechanical shock). As in the sibling
modules the generators were written from the documentation (docs/data-format.md,
docs/standards/gbt45570.md, ``metro plan -s gbt45570 -i ITEM``) and the clauses (6.2.6, 6.2.7.7,
6.2.7.8, 6.2.8, D.3, D.4, D.6 read in full); numpy makes every sample and nothing here imports metro
(the campaigns are evaluated through the sibling module's ``run_metro``).

The truth of each result is the clause's measurand on the constructed device and the records
written:

* 6.2.6 r: the device's response over the applied rate, s·K_true/K_declared (s = ±1 its polarity;
  for a rate output s·(1 + its scale error)); the table's rate error, noise and the counter are
  error. The polarity sign is scored as exact.
* 6.2.7.7 t_s: the instant the noise-free 1 s trailing mean of the output enters ±5 °/h of the
  settled bias for good (interpretations.md "6.2.7.7 — reaches the required performance", metro's
  defaults); the alternative column is the instant the noise-free output itself does.
* 6.2.7.8 P: Σ over the supplies of the record mean of the true U·I; the meters' errors (drawn
  within their certificates, the same instrument on every supply) are error.
* 6.2.8 ΔB₀, ΔK/K: the shift the test gave the device's bias and scale factor (signed, after −
  before). The before and after records are power-ons of their own: the turn-on scatter of bias and
  K is error (the campaign holds D.5.3's and D.1.4's / D.2.4's repeats that measure it, except where
  said).
* D.3 Ω_max: the largest tested rate whose range meets the K_n limit (D.23–D.25 on the noise-free
  outputs of the range), the device's nonlinearity limit given as ``[device] nonlinearity_limit``.
* D.4 Ω_i: the smallest tested input Ω_e·cos Ψ_i whose noise-free response is ≥ 50 % of the input
  with the right sign (D.39); the device has a dead band d (response x/(1 + (d/x)⁴)); the
  alternative column scores against d itself.
* D.6.1/D.6.2: T_low/T_high the temperature the chamber held; B₀ the bias of that power-on (turn-on
  and the record mean of the wander), earth rate removed.
* D.6.3/D.6.4: ΔB = |true change of the bias| between the phases (vibration rectification during, a
  permanent shift after); endurance vibration and shock are unpowered, so before and after are two
  power-ons and the turn-on scatter is error.  Levels: the level the table applied (its error within
  its certificate).
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

REV = 1296000.0  # ″ per revolution


# --------------------------------------------------------------------------------------------
# outputs and devices
# --------------------------------------------------------------------------------------------

def make_output(rng, kind: str, folder: Path, *, q: float = 0.05,
                sf_U: float = 20e-6) -> tuple[dict, Output]:
    """(device table, output) of one device. ``kind``: 'pulse' (undithered counter, 0.3–3 P/″),
    'pulse-fine' (dithered readout, 2–10 P/″), 'pulse-coarse' (undithered, 0.05–0.2 P/″), 'LSB' (1
    LSB ≈ q °/h), 'rate' (°/h rounded to q). K is declared with U = sf_U (k = 2)."""
    K_range = {"pulse-fine": (2.0, 10.0), "pulse-coarse": (0.05, 0.2)}.get(kind, (0.3, 3.0))
    device, out = marine_gyro(folder, rng, kind, q=q, K_range=K_range,
                              sf_U=f"{sf_U * 1e6:g} ppm", dithered=kind == "pulse-fine")
    if kind.startswith("pulse"):
        device["technology"] = "laser"  # (the key keeps its place in the table)
    elif kind != "LSB" and q:
        device["resolution"] = f"{q!r} °/h"
    return device, out


def earth_up(lat: float, orientation: str = "IRA up") -> float:
    o = orientation.lower()
    if "down" in o:
        return -OMEGA_E_DEG_H * math.sin(math.radians(lat))
    if "up" in o:
        return OMEGA_E_DEG_H * math.sin(math.radians(lat))
    return 0.0  # IRA east: the earth rate has no east component


def add_records(manifest: Path, text: str) -> None:
    with open(manifest, "a", encoding="utf-8") as fh:
        fh.write("\n" + text.strip() + "\n")


def write_table(camp: Campaign, sid: str, kind: str, columns: dict, dt: float, cond: dict) -> None:
    """A samples file with several columns (CSV, ``time [s]`` first) — for the power records."""
    name = camp.folder / f"{sid}.csv"
    n = len(next(iter(columns.values())))
    t = dt * np.arange(1, n + 1)
    head = "time [s]," + ",".join(columns)
    body = "\n".join(",".join([repr(float(t[i]))] + [repr(float(v[i])) for v in columns.values()])
                     for i in range(n))
    name.write_text(f"{head}\n{body}\n", encoding="utf-8")
    camp.segments.append((sid, kind, name.name, dt, cond, None))


def write_revolutions(camp: Campaign, sid: str, kind: str, counts, durations, T: float,
                      cond: dict) -> None:
    name = camp.folder / f"{sid}.csv"
    rows = "\n".join(f"{c!r},{d!r}" for c, d in zip(np.asarray(counts).tolist(),
                                                    np.asarray(durations).tolist()))
    name.write_text(f"count [P],duration [s]\n{rows}\n", encoding="utf-8")
    camp.segments.append((sid, kind, name.name, T, cond, None))


def revolutions(rng, *, sign: int, rate: float, m: int, K: float, scale: float, bias: float,
                noise: Noise,
                table_err: float = 0.0, edge: float = 2.0):
    """m whole revolutions at sign·rate °/s counted by an undithered counter between revolution
    pulses (±edge ″): (counts, durations). ``bias`` °/h (= ″/s) includes the earth rate."""
    T = 360.0 / (rate * (1 + table_err))
    k = max(4, int(math.ceil(T)))
    dt = T / k
    e, w = noise.draw(m * k, dt, rng)
    noise_angle = ((e + w) * dt).reshape(m, k).sum(axis=1)
    edges = rng.uniform(-edge, edge, m + 1)
    sensed = sign * (REV + np.diff(edges)) * scale + bias * T + noise_angle
    cum = np.floor(np.cumsum(np.concatenate([[rng.uniform(0, 1)], sensed * K])))
    return np.diff(cum), np.full(m, T)


def line(x, y):
    x, y = np.asarray(x, float), np.asarray(y, float)
    n = x.size
    den = n * (x * x).sum() - x.sum() ** 2
    b = (n * (x * y).sum() - x.sum() * y.sum()) / den
    return float((y.sum() - b * x.sum()) / n), float(b)


# --------------------------------------------------------------------------------------------
# 6.2.6 polarity
# --------------------------------------------------------------------------------------------

def build_polarity(folder: Path, rng, *, kind: str, q: float = 0.05, p_negative: float = 0.3,
                   flick: float = 0.0,
                   quick=False) -> dict:
    """20 s at rest and 20 s turning counter-clockwise about +IA (IRA up) at 10 °/s (or 2–30 °/s),
    0.1 s (the plan's steps); the device's polarity is negative with probability ``p_negative``."""
    lat = float(rng.uniform(-65, 70))
    device, out = make_output(rng, kind, folder, q=q, sf_U=50e-6)
    s = -1.0 if rng.uniform() < p_negative else 1.0
    dK = (
        25e-6 * float(rng.standard_normal()) if kind != "rate" else 2e-4
        * float(rng.standard_normal())
    )
    noise = Noise(float(rng.uniform(0.002, 0.02)), flicker=flick)
    U_table = float(rng.choice([1e-5, 1e-4, 1e-3]))
    table = {"id": "RT-X", "role": "rate_table",
             "calibration": {"certificate": "IND-RT-P", "U": repr(U_table), "k": 2}}
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt="csv", output=out)
    dt = 0.1
    n = int(round(20.0 / dt))
    omega = float(rng.choice([10.0, 10.0, 2.0, 5.0, 30.0]))
    bias = float(rng.uniform(-2, 2)) + earth_up(lat)
    terr = float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2
    e, w = noise.draw(2 * n, dt, rng)
    rest = out.record(bias + e[:n] + w[:n], dt, rng=rng)
    turn = out.record(s * (1 + dK) * omega * 3600.0 * (1 + terr) + bias + e[n:] + w[n:], dt,
                      rng=rng)
    camp.add("polarity-rest", "polarity", rest, dt, {"rate": "0 deg/s", "orientation": "IRA up"})
    camp.add("polarity-turn", "polarity", turn, dt,
             {"rate": f"{omega:g} deg/s", "orientation": "IRA up"})
    camp.write_manifest()
    return {("6.2.6", "polarity_ratio"): (s * (1 + dK), "", ""),
            ("6.2.6", "polarity"): (s, "exact", "")}


# --------------------------------------------------------------------------------------------
# 6.2.7.7 set-up time
# --------------------------------------------------------------------------------------------

def build_setup(folder: Path, rng, *, kind: str, q: float = 0.05, ringing: bool = False,
                blank: float = 0.0,
                quick=False) -> dict:
    """120 s at 0.1 s from the switch-on (IRA up): the bias settles as A·e^(−t/T_c) (A ±20 … 300
    °/h, T_c 2 … 12 s), or, ``ringing``, as A·e^(−t/T_c)·cos(2πt/P) (P 4 … 15 s: the output passes
    through the band before it stays in it); ``blank`` s: the output reads 0 before the electronics
    start."""
    lat = float(rng.uniform(-65, 70))
    device, out = make_output(rng, kind, folder, q=q)
    timer = {"id": "TMR-X", "role": "timer", "calibration": {"certificate": "IND-TMR-1",
                                                             "U": "1e-4", "k": 2}}
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER, timer], fmt="csv", output=out)
    dt, n = 0.1, 1200
    t = dt * (np.arange(n) + 0.5)
    A = float(rng.uniform(20, 300)) * (1 if rng.uniform() < 0.5 else -1)
    Tc = float(rng.uniform(2, 12))
    P = float(rng.uniform(4, 15))
    settled = float(rng.uniform(-1, 1)) + earth_up(lat)

    def transient(tt):
        env = A * np.exp(-tt / Tc)
        return env * np.cos(2 * math.pi * tt / P) if ringing else env

    arw = float(rng.uniform(0.002, 0.02))
    e, _ = Noise(arw).draw(n, dt, rng)
    rate = settled + transient(t) + e
    vals = out.record(rate, dt, rng=rng)
    if blank:
        vals[: int(round(blank / dt))] = 0.0
    camp.add("power-on", "power-on", vals, dt, {"orientation": "IRA up"})
    camp.write_manifest()
    # truth: the noise-free 1 s trailing mean enters ±5 °/h of the settled bias for good (fine time
    # grid)
    fine = np.arange(0.0, 60.0, 0.001)
    dev = transient(fine)
    if blank:
        dev = np.where(fine < blank, -settled, dev)
    c = np.concatenate([[0.0], np.cumsum(dev) * 0.001])
    tt = fine[1000:] + 0.001
    mean1 = (c[1000:] - c[:-1000]) / 1.0
    out_band = np.abs(mean1) > 5.0
    idx = np.flatnonzero(out_band)
    t_s = float(tt[idx[-1] + 1]) if idx.size else 1.0
    inst = np.flatnonzero(np.abs(dev) > 5.0)
    t_inst = float(fine[inst[-1] + 1]) if inst.size else 0.0
    return {("6.2.7.7", "setup_time"): (t_s, "s", "", t_inst)}


# --------------------------------------------------------------------------------------------
# 6.2.7.8 power consumption
# --------------------------------------------------------------------------------------------

def build_power(folder: Path, rng, *, supplies=(5.0, 15.0, -15.0), pulsed: bool = False,
                absolute: bool = False,
                quick=False) -> dict:
    """One ``power`` record per supply, 60 s at 1 s, columns voltage [V] and current [A] (a negative
    rail: both negative). Each rail's voltage within ±2 % of nominal with noise, its current
    0.05–0.8 A with noise; ``pulsed``: a heater switching with duty 30–70 % (period 3–9 s) and the
    supply's source resistance (0.05–0.3 Ω) pulling the voltage down while it draws, so mean(U·I) ≠
    mean(U)·mean(I). Meters: relative U (voltmeter 5×10⁻⁴, ammeter 2×10⁻³, k = 2) or, ``absolute``,
    5 mV and 2 mA; their errors are drawn within them, the same on every rail."""
    lat = float(rng.uniform(-65, 70))
    device = {"id": folder.name, "technology": "fibre", "application": "marine", "output": "rate"}
    # meters' U: absolute (5 mV, 2 mA) or relative; their errors drawn within U/2
    (u_v, u_i), (s_v, s_i) = ((("0.005 V", "0.002 A"), (0.0025, 0.001)) if absolute
                              else (("5e-4", "2e-3"), (2.5e-4, 1e-3)))
    vm = {"id": "VM-X", "role": "voltmeter",
          "calibration": {"certificate": "IND-VM-1", "U": u_v, "k": 2}}
    am = {"id": "AM-X", "role": "ammeter",
          "calibration": {"certificate": "IND-AM-1", "U": u_i, "k": 2}}
    ev, ei = s_v * float(rng.standard_normal()), s_i * float(rng.standard_normal())
    camp = Campaign(folder, device, lat, [vm, am], fmt="csv", output=Output("deg/h"))
    n, dt = 60, 1.0
    P = 0.0
    for V in supplies:
        s = 1.0 if V > 0 else -1.0
        I0 = float(rng.uniform(0.05, 0.8))
        t = np.arange(n) * dt
        if pulsed:
            duty, per = float(rng.uniform(0.3, 0.7)), float(rng.uniform(3, 9))
            on = ((t / per) % 1.0) < duty
            i_sup = I0 * (0.3 + 1.4 * on) + 0.002 * rng.standard_normal(n)
            R = float(rng.uniform(0.05, 0.3))
        else:
            period = float(rng.uniform(5, 30))
            i_sup = I0 * (1 + 0.01 * np.sin(2 * math.pi * t / period)) \
                + 0.001 * rng.standard_normal(n)
            R = 0.02
        U = abs(V) * (1 + 0.02 * float(rng.uniform(-1, 1))) - R * i_sup \
            + 0.002 * rng.standard_normal(n)
        P += float(np.mean(U * i_sup))
        if absolute:
            Um, Im = U + ev, i_sup + ei
        else:
            Um, Im = U * (1 + ev), i_sup * (1 + ei)
        write_table(camp, f"power{V:+g}V", "power", {"voltage [V]": s * Um, "current [A]": s * Im},
                    dt, {"supply": f"{V:g} V"})
    camp.write_manifest()
    return {("6.2.7.8", "P"): (P, "W", "")}


# --------------------------------------------------------------------------------------------
# D.6.1 / D.6.2 operation at the low and high temperature
# --------------------------------------------------------------------------------------------

CHAMBER = {"id": "CH-X", "role": "chamber", "uniformity": "0.5 K",
           "calibration": {"certificate": "IND-CH-1", "U": "0.3 K", "k": 2}}


def build_temperature(folder: Path, rng, *, kind: str, dt: float = 1.0, q: float = 0.05,
                      flick: float = 0.0,
                      wander: float = 0.0, quick=False) -> dict:
    """D.6.1 and D.6.2: 1 h at the low and at the high temperature (each a power-on after its soak,
    IRA up); B(T) = b + c₁(T − 20) (±0.01 … 0.1 °/h over the range) + turn-on scatter; the chamber
    holds its set point within its certificate (0.3 K, k = 2) and uniformity (±0.5 K)."""
    lat = float(rng.uniform(-65, 70))
    device, out = make_output(rng, kind, folder, q=q)
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER, CHAMBER], fmt="npy" if dt < 1
                    else "csv", output=out)
    noise = Noise(float(rng.uniform(0.001, 0.005)), flicker=flick, wander_amp=wander,
                  wander_period=float(rng.uniform(1200, 5400)))
    b = float(rng.uniform(-0.5, 0.5))
    c1 = float(rng.uniform(-1, 1)) * 1e-3
    sigma_on = float(rng.uniform(0.002, 0.01))
    n = int(round((3600 if not quick else 900) / dt))
    truth = {}
    for tag, item, kseg, Tset in (("low", "D.6.1", "low-temperature",
                                   float(rng.choice([-40.0, -45.0, -55.0]))),
                                  ("high", "D.6.2", "high-temperature",
                                   float(rng.choice([60.0, 70.0, 85.0])))):
        Ta = Tset + 0.15 * float(rng.standard_normal()) + float(rng.uniform(-0.5, 0.5))
        b_on = b + c1 * (Ta - 20) + sigma_on * float(rng.standard_normal())
        wh, fl, w = noise.draw3(n, dt, rng)
        camp.add(kseg, kseg, out.record(b_on + w + wh + fl + earth_up(lat), dt, rng=rng), dt,
                 {"orientation": "IRA up", "temperature": f"{Tset:g} °C", "warmup": "2 h"})
        truth[(item, f"T_{tag}")] = (Ta, "°C", "")
        truth[(item, f"B0_{tag}")] = (b_on + float(w.mean()), "°/h", "", b_on
                                      + float(w.mean() + fl.mean()))
    camp.write_manifest()
    return truth


# --------------------------------------------------------------------------------------------
# D.6.3 vibration, D.6.4 mechanical shock
# --------------------------------------------------------------------------------------------

def static_repeats(camp: Campaign, rng, out: Output, noise: Noise, *, b: float, sigma_on: float,
                   earth: float,
                   dt: float, seconds: float, Q: int = 7) -> None:
    """D.5.3's Q power-ons at rest (``static-repeat``, run = 1 … Q): what measures σ_on on the
    campaign."""
    n = int(round(seconds / dt))
    for j in range(1, Q + 1):
        e, w = noise.draw(n, dt, rng)
        camp.add(
            f"repeat-{j}",
            "static-repeat",
            out.record(b + sigma_on * float(rng.standard_normal()) + earth + e + w, dt, rng=rng),
            dt,
            {"orientation": "IRA up", "run": j, "warmup": "30 min"},
        )


def build_vibration_shock(folder: Path, rng, *, kind: str, dt: float = 1.0, q: float = 0.05,
                          flick: float = 0.0,
                          repeats: bool = True, sigma_on_range=(0.002, 0.01), quick=False) -> dict:
    """D.6.3 and D.6.4 along IRA, XRA, YRA (IRA up for IRA, IRA east for the others, as the plan),
    10 min per phase at τ = 1 s. Performance vibration (powered throughout, one power-on): the bias
    moves by Δ₁₂ (±0 … 0.03 °/h, rectification) while vibrating, with 1.5–3× the white noise, and by
    Δ₁₃ (±0 … 0.01 °/h) after. Endurance vibration and shock: unpowered, so after is a power-on of
    its own: b + Δ + σ_on·z. ``repeats``: D.5.3's 7 power-ons at rest (20 min each) are in the
    campaign."""
    lat = float(rng.uniform(-65, 70))
    device, out = make_output(rng, kind, folder, q=q)
    U_vib, U_sh = float(rng.choice([0.03, 0.05, 0.1])), float(rng.choice([0.05, 0.1]))
    vib = {"id": "VT-X", "role": "vibration_table",
           "calibration": {"certificate": "IND-VT-1", "U": repr(U_vib), "k": 2}}
    shock = {"id": "ST-X", "role": "shock_table", "duration_accuracy": "1 ms",
             "calibration": {"certificate": "IND-ST-1", "U": repr(U_sh), "k": 2}}
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER, vib, shock], fmt="csv" if dt >= 1
                    else "npy", output=out)
    arw = float(rng.uniform(0.001, 0.005))
    noise = Noise(arw, flicker=flick)
    loud = Noise(arw * float(rng.uniform(1.5, 3.0)), flicker=flick)
    b = float(rng.uniform(-0.5, 0.5))
    sigma_on = float(rng.uniform(*sigma_on_range))
    n = int(round((600 if not quick else 300) / dt))
    lv_perf, lv_end = float(rng.choice([5.0, 6.06, 6.6])), float(rng.choice([8.0, 9.0, 10.0]))
    lv_sh, pulse = float(rng.choice([30.0, 40.0, 50.0])), float(rng.choice([6.0, 11.0, 20.0]))
    e_vib = U_vib / 2 * float(rng.standard_normal())       # the table's own level error, common
    e_sh = U_sh / 2 * float(rng.standard_normal())
    e_dur = float(rng.uniform(-1, 1))                      # ms, within the duration accuracy

    def rec(sid, kind_, bias, cond, nz=noise):
        e, w = nz.draw(n, dt, rng)
        camp.add(sid, kind_, out.record(bias + e + w, dt, rng=rng), dt, cond)

    truth = {}
    for ax in ("IRA", "XRA", "YRA"):
        orient = "IRA up" if ax == "IRA" else "IRA east"
        ea = earth_up(lat, orient)
        base = {"orientation": orient, "axis": ax}
        # performance: one power-on
        b1 = b + sigma_on * float(rng.standard_normal())
        d12 = float(rng.uniform(-1, 1)) * float(rng.choice([0.0, 0.005, 0.03]))
        d13 = float(rng.uniform(-1, 1)) * float(rng.choice([0.0, 0.003, 0.01]))
        cp = base | {"test": "performance", "level": f"{lv_perf:g} gn"}
        rec(f"vib-perf-{ax}-before", "vibration", b1 + ea, cp
            | {"phase": "before", "warmup": "10 min"})
        rec(f"vib-perf-{ax}-during", "vibration", b1 + d12 + ea, cp | {"phase": "during"}, nz=loud)
        rec(f"vib-perf-{ax}-after", "vibration", b1 + d13 + ea, cp | {"phase": "after"})
        truth[("D.6.3", f"dBV12_{ax}")] = (abs(d12), "°/h", "")
        truth[("D.6.3", f"dBV13_{ax}")] = (abs(d13), "°/h", "")
        # endurance: unpowered while vibrating
        d = float(rng.uniform(-1, 1)) * float(rng.choice([0.0, 0.005, 0.02]))
        b1 = b + sigma_on * float(rng.standard_normal())
        b3 = b + d + sigma_on * float(rng.standard_normal())
        ce = base | {"test": "endurance", "level": f"{lv_end:g} gn"}
        rec(f"vib-endu-{ax}-before", "vibration", b1 + ea, ce
            | {"phase": "before", "warmup": "10 min"})
        rec(f"vib-endu-{ax}-after", "vibration", b3 + ea, ce
            | {"phase": "after", "warmup": "10 min"})
        truth[("D.6.3", f"dBV13end_{ax}")] = (abs(d), "°/h", "")
        # shock: unpowered
        d = float(rng.uniform(-1, 1)) * float(rng.choice([0.0, 0.005, 0.02]))
        b1 = b + sigma_on * float(rng.standard_normal())
        b3 = b + d + sigma_on * float(rng.standard_normal())
        cs = base | {"level": f"{lv_sh:g} gn", "pulse": f"{pulse:g} ms"}
        rec(f"shock-{ax}-before", "shock", b1 + ea, cs | {"phase": "before", "warmup": "10 min"})
        rec(f"shock-{ax}-after", "shock", b3 + ea, cs | {"phase": "after", "warmup": "10 min"})
        truth[("D.6.4", f"dBshock_{ax}")] = (abs(d), "°/h", "")
    if repeats:
        static_repeats(camp, rng, out, noise, b=b, sigma_on=sigma_on, earth=earth_up(lat), dt=dt,
                       seconds=1200 if not quick else 300)
    camp.write_manifest()
    truth[("D.6.3", "vib_perf_level")] = (lv_perf * (1 + e_vib), "gn", "")
    truth[("D.6.3", "vib_end_level")] = (lv_end * (1 + e_vib), "gn", "")
    truth[("D.6.4", "shock_level")] = (lv_sh * (1 + e_sh), "gn", "")
    truth[("D.6.4", "shock_duration")] = (pulse + e_dur, "ms", "")
    (folder / "truth.json").write_text(json.dumps({"sigma_on": sigma_on, "arw": arw}))
    return truth


# --------------------------------------------------------------------------------------------
# 6.2.8 environmental tests done elsewhere: ΔB₀ and ΔK/K
# --------------------------------------------------------------------------------------------

ENV_TESTS = {  # tag: (record test name, item, severity TOML lines)
    "lts": ("low-temperature storage", "6.2.8.2", 'temperature = "-55 degC"\nduration = "16 h"'),
    "tsh": ("temperature shock", "6.2.8.5",
            'low_temperature = "-55 degC"\nhigh_temperature = "85 degC"\n'
            'transfer_time = "1 min"\ncycles = 5'),
    "acc": ("acceleration", "6.2.8.7", 'acceleration = "18 gn"\nduration = "1 min"'),
}


def build_type_env(folder: Path, rng, *, kind: str, method: str, dt: float = 1.0, q: float = 0.05,
                   repeats: bool = True, shift_b=0.02, shift_K=30e-6, sigma_K_range=(2e-6, 20e-6),
                   sigma_on_range=(0.002, 0.01), quick=False) -> dict:
    """6.2.8.2, 6.2.8.5, 6.2.8.7 on one device: for each test, before and after it (each a power-on
    of its own) 10 min at rest (``type-env``) and the scale factor — ``method`` 'angle': 3 whole
    revolutions at ±10 and ±100 °/s (``type-env-revolutions``); 'rate': the output at ±10 and ±100
    °/s and at rest (100 s each, ``type-env-rate-output`` / ``type-env-rate-static``). The test
    shifts the bias by ΔB (±0 … shift_b °/h) and K by ΔK/K (±0 … shift_K); every power-on draws its
    own turn-on bias (σ_on) and K (σ_K). ``repeats``: D.5.3's 7 power-ons (20 min) and D.1.4's 7
    runs at ±30 °/s (5 revolutions) or D.2.4's 7 short D.2.1 tests (±10, ±100 °/s, 100 s each) are
    in the campaign."""
    lat = float(rng.uniform(-65, 70))
    earth = earth_up(lat)
    device, out = make_output(rng, kind, folder, q=q)
    U_table = float(rng.choice([1e-5, 1e-4]))
    table = {"id": "RT-X", "role": "rate_table", "revolution_pulse_accuracy": "2″",
             "calibration": {"certificate": "IND-RT-E", "U": repr(U_table), "k": 2}}
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER, table], fmt="csv" if dt >= 1
                    else "npy", output=out)
    arw = float(rng.uniform(0.001, 0.005))
    noise = Noise(arw)
    b = float(rng.uniform(-0.5, 0.5))
    sigma_on = float(rng.uniform(*sigma_on_range))
    sigma_K = float(rng.uniform(*sigma_K_range))
    K = out.K
    n_b = int(round((600 if not quick else 300) / dt))
    n_r = int(round((100 if not quick else 40) / dt))
    rates = (10.0, 100.0)
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates + (30.0,)}

    def power_on(prefix: str, cond: dict, bias: float, rel: float, static: bool = True,
                 sf_rates=rates, turns=3):
        if static:
            e, w = noise.draw(n_b, dt, rng)
            camp.add(prefix, "type-env", out.record(bias + earth + e + w, dt, rng=rng), dt,
                     cond | {"orientation": "IRA up", "warmup": "10 min"})
        for r in sf_rates:
            for sgn, tag in ((1, "+"), (-1, "-")):
                if method == "angle":
                    cnt, dur = revolutions(rng, sign=sgn, rate=r, m=turns, K=K, scale=rel,
                                           bias=bias + earth,
                                           noise=noise, table_err=terr[r])
                    write_revolutions(camp, f"{prefix}-rev{tag}{r:g}", "type-env-revolutions", cnt,
                                      dur, 360.0 / r,
                                      cond | {"rate": f"{sgn * r:g} deg/s", "turns": turns})
                else:
                    e, w = noise.draw(n_r, dt, rng)
                    v = out.record(sgn * r * 3600.0 * rel * (1 + terr[r]) + bias + earth + e + w,
                                   dt, rng=rng)
                    camp.add(f"{prefix}-rate{tag}{r:g}", "type-env-rate-output", v, dt,
                             cond | {"rate": f"{sgn * r:g} deg/s"})
        if method == "rate":
            for when in ("start", "end"):
                e, w = noise.draw(n_r, dt, rng)
                camp.add(f"{prefix}-rest-{when}", "type-env-rate-static",
                         out.record(bias + earth + e + w, dt, rng=rng),
                         dt, cond | {"when": when})

    truth, recs = {}, []
    for tag, (name, item, severity) in ENV_TESTS.items():
        dB = float(rng.uniform(-1, 1)) * shift_b * float(rng.choice([0.0, 0.3, 1.0]))
        dK = float(rng.uniform(-1, 1)) * shift_K * float(rng.choice([0.0, 0.3, 1.0]))
        for phase, sb, sk in (("before", 0.0, 0.0), ("after", dB, dK)):
            bias = b + sb + sigma_on * float(rng.standard_normal())
            rel = (1 + sk) * (1 + sigma_K * float(rng.standard_normal()))
            power_on(f"{tag}-{phase}", {"test": tag, "phase": phase}, bias, rel)
        recs.append(f'[[environmental_tests]]\ntest = "{name}"\nstandard = "GB/T 2423"\nlab = '
                    f'"independent lab"\nfunctional_check = true\nbefore = "{tag}-before"\nafter = '
                    f'"{tag}-after"\n[environmental_tests.severity]\n{severity}\n')
        truth[(item, f"{tag}_dB0")] = (dB, "°/h", "")
        truth[(item, f"{tag}_dK")] = (dK * 1e6, "ppm", "")
    if repeats:
        static_repeats(camp, rng, out, noise, b=b, sigma_on=sigma_on, earth=earth, dt=dt,
                       seconds=1200 if not quick else 300)
        for j in range(1, 8):
            bias = b + sigma_on * float(rng.standard_normal())
            rel = 1 + sigma_K * float(rng.standard_normal())
            if method == "angle":
                for sgn, tg in ((1, "+"), (-1, "-")):
                    cnt, dur = revolutions(rng, sign=sgn, rate=30.0, m=5, K=K, scale=rel, bias=bias
                                           + earth,
                                           noise=noise, table_err=terr[30.0])
                    write_revolutions(camp, f"run{j}-rate{tg}30", "revolutions-repeat", cnt, dur,
                                      12.0,
                                      {"rate": f"{sgn * 30.0!r} deg/s", "turns": 5, "run": j})
            else:
                for r in rates:
                    for sgn, tg in ((1, "+"), (-1, "-")):
                        e, w = noise.draw(n_r, dt, rng)
                        v = out.record(sgn * r * 3600.0 * rel * (1 + terr[r]) + bias + earth + e
                                       + w, dt, rng=rng)
                        camp.add(f"run{j}-rate{tg}{r:g}", "rate-output", v, dt,
                                 {"rate": f"{sgn * r:g} deg/s", "run": j})
                for when in ("start", "end"):
                    e, w = noise.draw(n_r, dt, rng)
                    camp.add(f"run{j}-rest-{when}", "rate-static",
                             out.record(bias + earth + e + w, dt, rng=rng), dt,
                             {"when": when, "run": j})
    path = camp.write_manifest()
    add_records(path, "\n".join(recs))
    (folder / "truth.json").write_text(json.dumps({"sigma_on": sigma_on, "sigma_K": sigma_K,
                                                   "arw": arw}))
    return truth


# --------------------------------------------------------------------------------------------
# D.3 maximum input rate (rate method)
# --------------------------------------------------------------------------------------------

def kn_range(w: np.ndarray, F: np.ndarray, upto: float) -> float:
    """D.23–D.25 over the rate points |Ω| ≤ upto: max |F̂_j − F_j| / |F_m|, F_m the larger |output|
    at upto."""
    sel = np.abs(w) <= upto * (1 + 1e-12)
    x, y = w[sel], F[sel]
    a, bb = line(x, y)
    top = np.abs(x) == np.abs(x).max()
    return float(np.max(np.abs(a + bb * x - y)) / np.max(np.abs(y[top])))


def build_maxrate(folder: Path, rng, *, kind: str, dt: float, seconds: float, q: float,
                  fmt: str = "npy",
                  quick=False) -> dict:
    """D.3 by the rate method: the D.2.1 sweep (rest at start and end, R5 rates up to 400 °/s, both
    ways) of a fibre gyro whose output compresses at high rate, K·Ω·(1 − c·(|Ω|/Ω_s)⁴) (Ω_s 100 …
    600 °/s, c 1×10⁻⁴ … 2×10⁻³), the limit ``[device] nonlinearity_limit`` 20/50/100 ppm; the table
    errs within its certificate."""
    lat = float(rng.uniform(-65, 70))
    earth = earth_up(lat)
    device, out = make_output(rng, kind, folder, q=q, sf_U=50e-6)
    limit = float(rng.choice([20e-6, 50e-6, 100e-6]))
    device |= {"nonlinearity": "100 ppm", "nonlinearity_limit": f"{limit * 1e6:g} ppm"}
    U_table = float(rng.choice([1e-5, 3e-5]))
    table = {"id": "RT-X", "role": "rate_table",
             "calibration": {"certificate": "IND-RT-3", "U": repr(U_table), "k": 2}}
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt=fmt, output=out)
    rates = list(R5_GBT) if not quick else list(R5_GBT[-11:])
    Om_s, c = float(rng.uniform(100, 600)), float(rng.uniform(1e-4, 2e-3))
    noise = Noise(float(rng.uniform(0.002, 0.02)), flicker=0.003)
    b = float(rng.uniform(-2, 2))
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * U_table / 2 for r in rates}
    n = int(round((seconds if not quick else 20.0) / dt))
    per = out.K / 3600.0 if kind == "LSB" else 1.0  # output units per °/h

    def g(w):
        return 1 - c * (np.abs(w) / Om_s) ** 4

    def seg(true_rate_dps, nominal):
        e, w = noise.draw(n, dt, rng)
        return out.record(true_rate_dps * 3600.0 * float(g(nominal)) + b + earth + e + w, dt,
                          rng=rng)

    camp.add("rest-start", "rate-static", seg(0.0, 0.0), dt, {"when": "start"})
    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            camp.add(f"rate{tag}{r:g}", "rate-output", seg(sgn * r * (1 + terr[r]), r), dt,
                     {"rate": f"{sgn * r!r} deg/s"})
    camp.add("rest-end", "rate-static", seg(0.0, 0.0), dt, {"when": "end"})
    camp.write_manifest()
    w_ = np.array([s * r for r in rates for s in (1, -1)])
    F = per * 3600.0 * w_ * g(w_)
    curve = [(r, kn_range(w_, F, r)) for r in rates[2:]]
    passing = [r for r, kn in curve if kn <= limit]
    om = max(passing) if passing else float("nan")
    (folder / "truth.json").write_text(json.dumps({"curve": curve, "limit": limit, "Om_s": Om_s,
                                                   "c": c}))
    return {("D.3", "Omega_max"): (om, "°/s", "")}


def build_maxrate_angle(folder: Path, rng, *, quick=False) -> dict:
    """D.3 by the angle method: the D.1.1 sweep (5 whole revolutions each way at R5 rates to 400
    °/s, ``rate-revolutions``) of a laser gyro whose scale factor compresses at high rate, K·(1 −
    c(|Ω|/Ω_s)⁴) (Ω_s 100 … 600 °/s, c 2×10⁻⁶ … 5×10⁻⁵), limit ``[device] nonlinearity_limit``
    2/5/10 ppm. Truth: the largest tested rate whose range meets the limit by D.7 on the noise-free
    K_i (D.2) and the D.5 intercept."""
    lat = float(rng.uniform(-65, 70))
    earth = earth_up(lat)
    device, out = make_output(rng, "pulse", folder)
    limit = float(rng.choice([2e-6, 5e-6, 10e-6]))
    device |= {"nonlinearity_limit": f"{limit * 1e6:g} ppm"}
    table = {"id": "RT-X", "role": "rate_table", "revolution_pulse_accuracy": "2″",
             "calibration": {"certificate": "IND-RT-A", "U": "1e-5", "k": 2}}
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt="csv", output=out)
    rates = list(R5_GBT) if not quick else list(R5_GBT[-11:])
    Om_s, c = float(rng.uniform(100, 600)), float(rng.uniform(2e-6, 5e-5))
    noise = Noise(float(rng.uniform(0.001, 0.005)))
    b = float(rng.uniform(-1, 1))
    m = 5 if not quick else 3

    def g(w):
        return 1 - c * (abs(w) / Om_s) ** 4

    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            cnt, dur = revolutions(rng, sign=sgn, rate=r, m=m, K=out.K, scale=g(r), bias=b + earth,
                                   noise=noise)
            write_revolutions(camp, f"rate{tag}{r:g}", "rate-revolutions", cnt, dur, 360.0 / r,
                              {"rate": f"{sgn * r!r} deg/s", "turns": m})
    camp.write_manifest()
    Ki = np.array([g(r) for r in rates])
    curve = []
    for j in range(2, len(rates)):
        K0, _ = line(rates[:j + 1], Ki[:j + 1])
        curve.append((rates[j], float(np.max(np.abs(Ki[:j + 1] - K0)) / K0)))
    passing = [r for r, kn in curve if kn <= limit]
    (folder / "truth.json").write_text(json.dumps({"curve": curve, "limit": limit}))
    return {("D.3", "Omega_max"): (max(passing) if passing else float("nan"), "°/s", "")}


# --------------------------------------------------------------------------------------------
# D.4 threshold
# --------------------------------------------------------------------------------------------

LEVELS = (0.002, 0.004, 0.006, 0.008, 0.01, 0.012, 0.015, 0.02, 0.03, 0.05)  # °/h, metro plan's


def build_threshold(folder: Path, rng, *, kind: str, arw_range=(0.0002, 0.0006), dead=(0.003, 0.03),
                    q: float = 0.01,
                    flick: float = 0.0, seconds: float = 600.0, quick=False) -> dict:
    """D.4: the reference at Ψ = 90° and the tilt positions of ``metro plan``'s levels (0.002 … 0.05
    °/h), 600 s at τ = 1 s each (D.4.2 d), e)), all one power-on (D.4.2 c)); the device responds to
    an input x along IRA as x/(1 + (d/x)⁴) (a dead band of d, 50 % at x = d); the tilt table sets
    each Ψ within ±2″."""
    lat = float(rng.uniform(-65, 70))
    device, out = make_output(rng, kind, folder, q=q)
    tilt = {"id": "TT-X", "role": "tilt_table", "position_accuracy": "2″"}
    camp = Campaign(folder, device, lat, [tilt, COUNTER], fmt="csv", output=out)
    d = float(rng.uniform(*dead))
    noise = Noise(float(rng.uniform(*arw_range)), flicker=flick)
    b = float(rng.uniform(-0.5, 0.5))
    n = int(round(seconds if not quick else 300))

    def resp(x):
        return 0.0 if x == 0 else x / (1 + (d / abs(x)) ** 4)

    def position(sid, psi):
        psi_true = psi + float(rng.uniform(-2, 2)) / 3600.0
        x = OMEGA_E_DEG_H * math.cos(math.radians(psi_true))
        e, w = noise.draw(n, 1.0, rng)
        camp.add(sid, "tilt", out.record(b + resp(x) + e + w, 1.0, rng=rng), 1.0,
                 {"psi": f"{psi:.7f} deg"})

    position("tilt-ref", 90.0)
    truth_th = float("nan")
    for x in LEVELS:
        psi = math.degrees(math.acos(x / OMEGA_E_DEG_H))
        position(f"tilt-{x:g}", psi)
        if math.isnan(truth_th) and resp(x) / x >= 0.5:
            truth_th = x
    camp.write_manifest()
    (folder / "truth.json").write_text(json.dumps({"dead": d}))
    return {("D.4", "threshold"): (truth_th, "°/h", "", d)}


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

V = Variant
VARIANTS = variants(
    V("pol-pulse", "gbt45570", "6.2.6",
      text("""
          pulse, undithered 0.3–3 P/″, 0.1 s, rest 20 s and turning 2–30 °/s, 30 % of devices
          negative, K declared U 50 ppm (true within it), table U 1e-5…1e-3"""),
      build_with(build_polarity, kind="pulse")),
    V("pol-pulse-coarse", "gbt45570", "6.2.6",
      text("""
          coarse pulse 0.05–0.2 P/″, otherwise as pol-pulse"""),
      build_with(build_polarity, kind="pulse-coarse")),
    V("pol-lsb", "gbt45570", "6.2.6",
      text("""
          LSB word 1 LSB ≈ 0.05 °/h, flicker 0.01 °/h"""),
      build_with(build_polarity, kind="LSB", flick=0.01)),
    V("pol-rate", "gbt45570", "6.2.6",
      text("""
          rate output °/h rounded to 0.5 °/h, scale error σ 200 ppm"""),
      build_with(build_polarity, kind="rate", q=0.5)),
    V("setup-rate-exp", "gbt45570", "6.2.7.7",
      text("""
          rate output °/h (0.01 °/h), 120 s at 0.1 s from switch-on, exponential settling
          ±20…300 °/h, T_c 2–12 s, ARW 0.002–0.02 °/√h"""),
      build_with(build_setup, kind="rate", q=0.01)),
    V("setup-lsb-ringing", "gbt45570", "6.2.7.7",
      text("""
          LSB 0.05 °/h, a damped oscillation (period 4–15 s) that passes through the band
          before it stays in it"""),
      build_with(build_setup, kind="LSB", ringing=True)),
    V("setup-pulse-blank", "gbt45570", "6.2.7.7",
      text("""
          dithered pulse 2–10 P/″, the output reads 0 for the first 0.3–1.5 s, then exponential"""),
      lambda f, rng, quick: build_setup(f, rng, kind="pulse-fine",
                                        blank=float(rng.uniform(0.3, 1.5)), quick=quick)),
    V("power-3rails", "gbt45570", "6.2.7.8",
      text("""
          +5, +15, −15 V (negative rail: U, I < 0), 60 s at 1 s, relative meter certificates"""),
      build_with(build_power)),
    V("power-28V-pulsed-abs", "gbt45570", "6.2.7.8",
      text("""
          one 28 V rail and a 5 V rail, heater duty cycle with source resistance (mean U·I ≠
          mean U·mean I), absolute meter certificates (5 mV, 2 mA)"""),
      build_with(build_power, supplies=(28.0, 5.0), pulsed=True, absolute=True)),
    V("temp-pulse", "gbt45570", "D.6.1,D.6.2",
      text("""
          pulse 0.3–3 P/″ undithered, 1 h at 1 s CSV, turn-on σ 0.002–0.01 °/h"""),
      build_with(build_temperature, kind="pulse")),
    V("temp-lsb-flicker", "gbt45570", "D.6.1,D.6.2",
      text("""
          LSB 0.05 °/h at 10 Hz (.npy), flicker 0.004 °/h, wander 0.01 °/h"""),
      build_with(build_temperature, kind="LSB", dt=0.1, flick=0.004, wander=0.01)),
    V("vibshock-pulse", "gbt45570", "D.6.3,D.6.4",
      text("""
          pulse 0.3–3 P/″ undithered, 10 min per phase at 1 s, turn-on σ 0.002–0.01 °/h,
          D.5.3's 7 repeats in the campaign"""),
      build_with(build_vibration_shock, kind="pulse")),
    V("vibshock-lsb-no-repeats", "gbt45570", "D.6.3,D.6.4",
      text("""
          LSB 0.05 °/h at 1 s, flicker 0.003 °/h, no D.5.3 repeats"""),
      build_with(build_vibration_shock, kind="LSB", flick=0.003, repeats=False)),
    V("vibshock-rate-quiet-on", "gbt45570", "D.6.3,D.6.4",
      text("""
          rate output °/h (0.001 °/h), turn-on σ 0.0005–0.002 °/h (small against 10 min of
          noise), D.5.3's repeats"""),
      build_with(build_vibration_shock, kind="rate", q=0.001, sigma_on_range=(0.0005, 0.002))),
    V("env-angle-pulse", "gbt45570", "6.2.8.2,6.2.8.5,6.2.8.7",
      text("""
          pulse 0.3–3 P/″ undithered; before/after each test 10 min at rest and 3 revolutions
          at ±10, ±100 °/s, each a power-on (σ_on 0.002–0.01 °/h, σ_K 2–20 ppm); D.5.3 and
          D.1.4 repeats"""),
      build_with(build_type_env, kind="pulse", method="angle")),
    V("env-angle-pulse-no-repeats", "gbt45570", "6.2.8.2,6.2.8.5,6.2.8.7",
      text("""
          as env-angle-pulse without the repeats"""),
      build_with(build_type_env, kind="pulse", method="angle", repeats=False)),
    V("env-rate-lsb", "gbt45570", "6.2.8.2,6.2.8.5,6.2.8.7",
      text("""
          LSB 0.05 °/h at 1 s; the scale factor by D.2.1 at ±10, ±100 °/s and rest (100 s
          each); D.5.3 and D.2.4 (short) repeats"""),
      build_with(build_type_env, kind="LSB", method="rate")),
    V("maxrate-lsb-10Hz", "gbt45570", "D.3",
      text("""
          LSB 0.05 °/h at 10 Hz, 100 s per point, R5 1–400 °/s, compression c(|Ω|/Ω_s)⁴, limit
          20/50/100 ppm"""),
      build_with(build_maxrate, kind="LSB", dt=0.1, seconds=100.0, q=0.05)),
    V("maxrate-rate-1Hz", "gbt45570", "D.3",
      text("""
          rate output °/h rounded to 0.01 °/h at 1 Hz, 100 s per point (CSV)"""),
      build_with(build_maxrate, kind="rate", dt=1.0, seconds=100.0, q=0.01, fmt="csv")),
    V("maxrate-angle-pulse", "gbt45570", "D.3",
      text("""
          laser gyro, undithered pulse 0.3–3 P/″, 5 revolutions each way at R5 rates 1–400 °/s,
          K compressing at high rate, limit 2/5/10 ppm"""),
      build_with(build_maxrate_angle)),
    V("setup-pulse-coarse", "gbt45570", "6.2.7.7",
      text("""
          coarse undithered pulse 0.05–0.2 P/″ (1 P over 1 s ≥ 5 °/h: the band cannot be read)"""),
      build_with(build_setup, kind="pulse-coarse")),
    V("temp-rate-coarse", "gbt45570", "D.6.1,D.6.2",
      text("""
          °/h output rounded to 0.5 °/h (coarser than the 1 s noise), 1 h at 1 s"""),
      build_with(build_temperature, kind="rate", q=0.5)),
    V("vibshock-lsb-coarse", "gbt45570", "D.6.3,D.6.4",
      text("""
          LSB ≈ 1 °/h (coarser than the 1 s noise), D.5.3's repeats"""),
      build_with(build_vibration_shock, kind="LSB", q=1.0)),
    V("env-rate-lsb-coarse", "gbt45570", "6.2.8.2,6.2.8.5,6.2.8.7",
      text("""
          as env-rate-lsb with 1 LSB ≈ 1 °/h"""),
      build_with(build_type_env, kind="LSB", method="rate", q=1.0)),
    V("env-angle-pulse-coarse", "gbt45570", "6.2.8.2,6.2.8.5,6.2.8.7",
      text("""
          as env-angle-pulse with coarse pulses 0.05–0.2 P/″"""),
      build_with(build_type_env, kind="pulse-coarse", method="angle")),
    V("thr-lsb-coarse", "gbt45570", "D.4",
      text("""
          LSB 0.05 °/h, rounded, ARW 0.0002–0.0006 °/√h (the rounding coarser than the inputs)"""),
      build_with(build_threshold, kind="LSB", q=0.05)),
    V("thr-pulse-quiet", "gbt45570", "D.4",
      text("""
          dithered pulse 2–10 P/″, ARW 0.0002–0.0006 °/√h, dead band 0.003–0.03 °/h, 600 s per
          position"""),
      build_with(build_threshold, kind="pulse-fine")),
    V("thr-lsb-quiet-flicker", "gbt45570", "D.4",
      text("""
          LSB 0.01 °/h, ARW 0.0002–0.0006 °/√h, flicker 0.0005 °/h, dead band 0.003–0.03 °/h"""),
      build_with(build_threshold, kind="LSB", q=0.01, flick=0.0005)),
    V("thr-pulse-typical", "gbt45570", "D.4",
      text("""
          undithered pulse 0.3–3 P/″, ARW 0.001–0.003 °/√h (a typical gyro: mostly not
          resolvable)"""),
      build_with(build_threshold, kind="pulse", arw_range=(0.001, 0.003))),
)

_UNITS = {"°/h": {"°/h", "deg/h", "degree / hour", "degree/hour", "(°)/h"},
          "°C": {"°C", "degC", "degree_Celsius", "℃"},
          "gn": {"gn", "g₀", "g_n", "standard_gravity", "g"},
          "ms": {"ms", "millisecond"}, "s": {"s", "second"}, "W": {"W", "watt"},
          "°/s": {"°/s", "deg/s", "degree / second", "(°)/s"}, "ppm": {"ppm"},
          "": {"", "1", "dimensionless"}}


def score_env(truth: dict, doc: dict) -> list[dict]:
    """The sibling module's score after unit spellings are made canonical; the polarity sign is
    scored as exact (E_n 0 when it matches, ±∞ when not); a truth of NaN (no tested level meets the
    clause) expects a refusal or a not-reportable result."""
    doc = dict(doc)
    res = []
    for r in doc.get("results", []):
        r = dict(r)
        for canon, spellings in _UNITS.items():
            if r.get("unit") in spellings:
                r["unit"] = canon
        res.append(r)
    doc["results"] = res
    exact = {k: v for k, v in truth.items() if v[1] == "exact"}
    rest = {k: v for k, v in truth.items() if v[1] != "exact"}
    rows = score(rest, doc)
    for (item, key), (value, _, _) in exact.items():
        m = [r for r in res if r.get("key") == key and str(r.get("item", "")).upper()
             == item.upper()]
        if not m:
            rows.append({"item": item, "key": key, "status": "missing"})
        else:
            ok = m[0].get("value") == value
            rows.append({"item": item, "key": key, "status": "ok", "value": m[0].get("value"),
                         "truth": value,
                         "U": None, "En": 0.0 if ok
                         else math.copysign(math.inf, m[0].get("value", 0) - value)})
    return rows


def main(argv=None) -> int:
    """The shared command line (``independent_campaigns.cli``), scoring through
    :func:`score_env`."""
    import independent_campaigns as ic

    return ic.cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-env-",
                  alt_label="alternative truth",
                  run=lambda v, a, work: ic.run_variant(v, a.devices, a.seed, work, a.subprocess,
                                                        quick=a.quick,
                                                        keep=a.keep is not None, scorer=score_env))


if __name__ == "__main__":
    sys.exit(main())

"""An independent harness: devices metro's simulators do not make, written as campaigns.

Run: nice -n 10 .venv/bin/python benchmarks/independent_campaigns.py [--devices 30] [--variants A,B]
                                                                     [--keep DIR] [--subprocess]

Issue 13 asks that an independent harness, with its own device generators, score |E_n| on
campaigns written in the documented format.  This is our own version of it, kept apart from
metro's code: the generators below were written from the documentation only
(docs/data-format.md, docs/instruments.md, README.md, ``metro plan``'s segment list) and from the
standards' clauses (/work/shared/standards/); they import neither ``metro.instruments`` nor any
of metro's simulators, and use numpy alone to make the samples.  Each device is written as a
complete campaign (``manifest.toml`` plus one samples file per segment, CSV or a structured
``.npy``), evaluated by ``metro run --data <campaign> --json`` (in-process through
``metro.core.cli.app.main``, or ``--subprocess``), and every result is scored against the truth the
generator knows by construction: E_n = (result − truth)/U.

What the truth is (the standard's measurand over the records actually written):

* GB/T 45570 D.5.1 B₀ (eq. D.40): the device's bias during that power-on — its turn-on bias plus
  the mean over the record of the slow thermal (sinusoidal) wander — with the earth rate's
  vertical component removed as D.40 does.  White noise, flicker (1/f) noise and quantization
  are measurement error, not bias: the budget has to cover what they leave in a 1 h mean.
* GB/T 45570 D.5.3 B_r (eq. D.42): the Bessel standard deviation of Q measured biases measures,
  in expectation of its square, σ_on² + Var(one record's B₀ error), where the second term (white
  noise, flicker, the wander's record mean, quantization) is computed by Monte Carlo from this
  generator's own noise model, record length and sample rate.  Truth = √ of that sum.
* GB/T 45570 D.2.1 K (eq. D.21) and JJF 2014 7.2.1 K (eq. (4)): the LSQ slope over a set of rates
  symmetric about zero; with a scale-factor asymmetry (K₊ for positive, K₋ for negative rates)
  that slope is (K₊ + K₋)/2 whatever the noise, so truth K = (K₊ + K₋)/2 of the power-on the
  calibration was made on.  F₀ is not scored (with asymmetry it depends on the fit, not a device
  constant).
* JJF 2014 7.2.4 K_r (eq. (10)): as for B_r, truth = √(σ_K,rel² + Var(K̂)/K²) with Var(K̂) the
  scatter of eq. (4)'s slope under this generator's noise (Monte Carlo of the same record layout).
* JJF 2014 7.2.13 B₀ (eqs. (27), (28)): the bias of the static record's power-on plus the record
  mean of the wander, plus Ω_e·sin φ when metro's result says the earth rate is ``included`` (the
  standard prints no earth-rate term), minus nothing when it says ``removed``.

Device variety (none of it in metro's stations): sample rates 1 Hz / 10 Hz (GB/T) and 100 Hz /
400 Hz / 2 kHz (JJF), flicker noise, a sinusoidal thermal bias wander with a random phase per
power-on, scale-factor asymmetry, outputs pulse (P, undithered counter), LSB, °/h, mV and mV/V,
coarse quantization, K of both signs (JJF, fitted) and of different magnitudes, latitudes from
−65° to 70°, record lengths at the documented minimums (1 h bias records, 10 samples per rate
point for JJF 7.2.1, 100 s per rate point for D.2.1).

Not a test: the figures go to docs/independent-campaigns.md.  tests/test_independent_campaigns.py
runs a few devices through the same generators.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import math
import subprocess
import sys
import tempfile
import time
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

OMEGA_E_DEG_H = 15.041  # GB/T 45570 eq. (D.40)'s constant, °/h (JJF 2014 prints none)
R5_JJF = (0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100)  # °/s, 7.2.1.1 b), 11 per direction
R5_GBT = (1, 1.6, 2.5, 4, 6.3, 10, 16, 25, 40, 63, 100, 160, 250, 400)  # °/s, D.2.1.2 e)


# --------------------------------------------------------------------------------------------
# noise (numpy only)
# --------------------------------------------------------------------------------------------

def flicker(n: int, dt: float, sigma_flat: float, rng: np.random.Generator) -> np.ndarray:
    """1/f noise whose Allan deviation plateau is about ``sigma_flat`` (one-sided PSD h/f with
    σ_A² = 2 ln 2 · h), synthesised over 8× the record and cut to a random window, so the record
    sees frequencies down to 1/(8T)."""
    if sigma_flat == 0 or n == 0:
        return np.zeros(n)
    m = 1 << int(math.ceil(math.log2(8 * n)))
    f = np.fft.rfftfreq(m, dt)
    h = sigma_flat ** 2 / (2 * math.log(2))
    amp = np.zeros_like(f)
    amp[1:] = np.sqrt(h / f[1:] / (m * dt)) / 2 * m
    spec = amp * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size))
    x = np.fft.irfft(spec, m)
    start = int(rng.integers(0, m - n + 1))
    return x[start:start + n]


@dataclass
class Noise:
    """Rate noise in °/h: white (ARW, °/√h), flicker plateau (°/h), thermal wander (°/h, period
    s)."""
    arw: float
    flicker: float = 0.0
    wander_amp: float = 0.0
    wander_period: float = 3600.0

    def draw(self, n: int, dt: float, rng, t0: float = 0.0, phase: float | None = None):
        """(noise, wander) in °/h: the wander is part of the bias (truth), the rest is error."""
        white, fl, wander = self.draw3(n, dt, rng, t0, phase)
        return white + fl, wander

    def draw3(self, n: int, dt: float, rng, t0: float = 0.0, phase: float | None = None):
        """(white, flicker, wander) in °/h."""
        white = rng.standard_normal(n) * self.arw * 60.0 / math.sqrt(dt)
        fl = flicker(n, dt, self.flicker, rng)
        if self.wander_amp:
            ph = rng.uniform(0, 2 * math.pi) if phase is None else phase
            t = t0 + dt * (np.arange(n) + 0.5)
            wander = self.wander_amp * np.sin(2 * math.pi * t / self.wander_period + ph)
        else:
            wander = np.zeros(n)
        return white, fl, wander


# --------------------------------------------------------------------------------------------
# outputs: what the documented columns hold (data-format.md "Samples files")
# --------------------------------------------------------------------------------------------

@dataclass
class Output:
    """How the device's rate (°/h, as sensed) becomes the recorded column.

    kind: 'pulse' (P accumulated per interval, undithered counter: floor of the cumulative angle ×
    K), 'LSB' (K in LSB/[(°)/s], rounded to whole LSB), 'deg/h' (rate output, rounded to ``q``),
    'mV' (K in mV/[(°)/s], rounded to ``q`` mV), 'mV/V' (mV / supply, rounded to ``q`` mV/V)."""
    kind: str
    K: float = 1.0            # P/″, LSB/(°/s), mV/(°/s); ignored for deg/h
    q: float = 0.0            # quantization step in the column's unit (LSB: 1)
    supply: float = 5.0       # V, for mV/V

    @property
    def unit(self) -> str:
        return {"pulse": "P", "LSB": "LSB", "deg/h": "°/h", "mV": "mV", "mV/V": "mV/V"}[self.kind]

    def record(self, rate_deg_h: np.ndarray, dt: float, K_scale: np.ndarray | float = 1.0,
               rng=None) -> np.ndarray:
        """``K_scale``: the device's scale factor relative to ``K`` at each sample (asymmetry,
        power-on variation)."""
        if self.kind == "pulse":
            angle_arcsec = np.cumsum(rate_deg_h * dt)  # 1 °/h = 1 ″/s
            phase0 = rng.uniform(0, 1) if rng is not None else 0.0
            counts = np.floor(angle_arcsec * self.K * K_scale + phase0)
            return np.diff(np.concatenate([[math.floor(phase0)], counts]))
        if self.kind == "deg/h":
            y = rate_deg_h * K_scale
        else:
            y = self.K * K_scale * rate_deg_h / 3600.0
            if self.kind == "mV/V":
                y = y / self.supply
        step = 1.0 if self.kind == "LSB" else self.q
        if step:
            y = np.round(y / step) * step
        return y


class DitheredPulse(Output):
    """Pulse counts read at a random phase every sample (a dithered readout): the quantization
    error of each sample's count is independent, white angle noise."""

    def __init__(self, K: float):
        super().__init__("pulse", K=K)

    def record(self, rate_deg_h, dt, K_scale=1.0, rng=None):
        angle = np.cumsum(np.asarray(rate_deg_h) * dt) * self.K * K_scale
        u = rng.uniform(0, 1, angle.size)
        cum = np.floor(np.concatenate([[0.0], angle]) + np.concatenate([[rng.uniform(0, 1)], u]))
        return np.diff(cum)


def marine_gyro(folder: Path, rng, kind: str, *, q: float = 0.0, K_range=(0.3, 3.0),
                sf_U: str = "5 ppm", dithered: bool = False) -> tuple[dict, Output]:
    """(device table, output) of a GB/T 45570 marine fibre gyro. ``kind``: 'pulse…' (K drawn in
    ``K_range`` P/″, read by an undithered counter or, with ``dithered``, a dithered readout),
    'LSB' (1 LSB ≈ ``q`` °/h), anything else a rate output in °/h rounded to ``q``; the declared
    scale factor's U is ``sf_U``."""
    device = {"id": folder.name, "technology": "fibre", "application": "marine"}
    if kind.startswith("pulse"):
        K = float(rng.uniform(*K_range))
        out = DitheredPulse(K) if dithered else Output("pulse", K=K)
        device |= {"output": "pulse", "scale_factor": f"{K!r} P/″", "scale_factor_U": sf_U}
    elif kind == "LSB":
        K = 3600.0 / q * float(rng.uniform(0.8, 1.25))
        out = Output("LSB", K=K)
        device |= {"output": "digital", "scale_factor": f"{K!r} LSB/(°/s)",
                   "scale_factor_U": sf_U}
    else:
        out = Output("deg/h", q=q)
        device |= {"output": "rate"}
    return device, out


# --------------------------------------------------------------------------------------------
# writing campaigns (data-format.md)
# --------------------------------------------------------------------------------------------

def _q(value: float, unit: str) -> str:
    return f"{value!r} {unit}" if unit else repr(value)


def write_samples(path: Path, column: str, values: np.ndarray, dt: float, fmt: str) -> str:
    """One samples file: CSV with ``time [s]`` and ``output [unit]``, or a structured .npy."""
    if fmt == "csv":
        name = path.parent / (path.name + ".csv")  # not with_suffix: "rate+1.6" has a dot
        n = values.size
        t = dt * np.arange(1, n + 1)
        with open(name, "w", encoding="utf-8", newline="\n") as fh:
            fh.write("# written by benchmarks/independent_campaigns.py\n")
            fh.write(f"time [s],{column}\n")
            fh.write("\n".join(f"{ti!r},{vi!r}" for ti, vi in zip(t.tolist(), values.tolist())))
            fh.write("\n")
    else:
        name = path.parent / (path.name + ".npy")
        arr = np.zeros(values.size, dtype=[(column, "f8")])
        arr[column] = values
        np.save(name, arr)
    return name.name


@dataclass
class Campaign:
    folder: Path
    device: dict
    site_latitude: float
    equipment: list = field(default_factory=list)
    segments: list = field(default_factory=list)  # (id, kind, file, dt, conditions, unit)
    fmt: str = "csv"
    output: Output | None = None

    def add(self, seg_id: str, kind: str, values: np.ndarray, dt: float, conditions: dict) -> None:
        col = f"output [{self.output.unit}]"
        fname = write_samples(self.folder / seg_id, col, values, dt, self.fmt)
        self.segments.append((seg_id, kind, fname, dt, conditions, self.output.unit))

    def write_manifest(self) -> Path:
        lines = ['format = "metro-campaign/1"', "", "[campaign]", f'id = "{self.folder.name}"',
                 'operator = "independent harness"', "", "[device]"]
        for k, v in self.device.items():
            lines.append(f"{k} = {json.dumps(v, ensure_ascii=False)}")
        lines += ["", "[environment]", 'temperature = "20.5 °C"', 'humidity = "45 %"', "",
                  "[site]", f'latitude = "{self.site_latitude!r}°"', ""]
        for eq in self.equipment:
            lines += ["[[equipment]]"]
            cal = eq.get("calibration")
            for k, v in eq.items():
                if k != "calibration":
                    lines.append(f"{k} = {json.dumps(v, ensure_ascii=False)}")
            if cal:
                lines.append("[equipment.calibration]")
                for k, v in cal.items():
                    lines.append(f"{k} = {json.dumps(v, ensure_ascii=False)}")
            lines.append("")
        for seg_id, kind, fname, dt, cond, unit in self.segments:
            lines += ["[[segments]]", f'id = "{seg_id}"', f'kind = "{kind}"', f'file = "{fname}"',
                      f'sample_interval = "{dt!r} s"', "[segments.conditions]"]
            for k, v in cond.items():
                lines.append(f"{k} = {json.dumps(v, ensure_ascii=False)}")
            lines += (["[segments.units]", f'output = "{unit}"', ""] if unit else [""])
        path = self.folder / "manifest.toml"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return path


PLATFORM = {"id": "PLAT-X", "role": "platform", "levelness": "2″"}
COUNTER = {"id": "CNT-X", "role": "counter",
           "calibration": {"certificate": "IND-CNT-1", "U": "2e-7", "k": 2}}
RATE_TABLE = {"id": "RT-X", "role": "rate_table",
              "calibration": {"certificate": "IND-RT-1", "U": "1e-4", "k": 2}}
DMM = {"id": "DMM-X", "role": "dmm", "calibration": {"certificate": "IND-DMM-1", "U": "2e-5",
                                                     "k": 2}}


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

@dataclass
class Variant:
    name: str
    standard: str
    items: str
    describe: str
    build: object  # callable(folder, rng, quick) -> truth dict {key: (value, unit, earth)}


def build_with(builder, **options):
    """A variant's ``build(folder, rng, quick)``: ``builder(folder, rng, quick=quick,
    **options)``."""
    return lambda folder, rng, quick: builder(folder, rng, quick=quick, **options)


def variants(*table) -> dict:
    """{name: variant} of the variants given, in their order."""
    return {v.name: v for v in table}


def text(block: str) -> str:
    """A variant's description written as a wrapped block: its words joined by single spaces."""
    return " ".join(block.split())


def build_gbt_bias(folder: Path, rng, *, kind: str, dt: float, fmt: str, flick: float,
                   wander: float, lsb_deg_h: float, q_deg_h: float, quick: bool = False,
                   Q: int = 7, orientation: str = "IRA up") -> dict:
    """GB/T 45570 D.5.1 + D.5.3 on one device: a 1 h `static` record and Q `static-repeat`
    power-ons (D.5.3.2), IRA up, at ``dt``."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat)) * (-1.0 if "down" in orientation.lower()
                                                           else 1.0)
    arw = float(rng.uniform(0.001, 0.004))                      # °/√h
    noise = Noise(arw, flicker=flick * float(rng.uniform(0.5, 1.5)),
                  wander_amp=wander * float(rng.uniform(0.5, 1.5)),
                  wander_period=float(rng.uniform(1200, 5400)))
    sigma_on = float(rng.uniform(0.002, 0.01))                  # °/h, turn-on scatter
    b_mean = float(rng.uniform(-0.5, 0.5))                      # °/h
    device, out = marine_gyro(folder, rng, kind, q=lsb_deg_h if kind == "LSB" else q_deg_h)
    camp = Campaign(folder, device, lat, [PLATFORM, COUNTER], fmt=fmt, output=out)
    n = int(round(3600 / dt)) if not quick else int(round(600 / dt))
    biases = []
    for idx in range(Q + 1):
        b_on = b_mean + sigma_on * rng.standard_normal()
        wh, fl, w = noise.draw3(n, dt, rng)
        rate = b_on + w + wh + fl + earth
        vals = out.record(rate, dt, rng=rng)
        truth_b0 = b_on + float(w.mean())
        if idx == 0:
            camp.add("static-1h", "static", vals, dt,
                     {"orientation": orientation, "warmup": "30 min"})
            b0_truth = truth_b0
            b0_alt = truth_b0 + float(fl.mean())
        else:
            camp.add(f"repeat-{idx}", "static-repeat", vals, dt,
                     {"orientation": orientation, "run": idx, "warmup": "30 min"})
            biases.append(truth_b0)
    camp.write_manifest()
    # what D.42 measures: turn-on scatter, the wander's record-mean scatter (random phase per
    # power-on), and each record's mean error from noise and quantization.
    draws = 60 if quick else 200
    sims = []
    for _ in range(draws):
        e, w = noise.draw(n, dt, rng)
        rate = b_mean + w + e + earth
        vals = out.record(rate, dt, rng=rng)
        if kind == "pulse":
            meas = vals.mean() / dt / out.K
        elif kind == "LSB":
            meas = vals.mean() / out.K * 3600.0
        else:
            meas = vals.mean()
        sims.append(meas - earth - b_mean)
    var_rec = float(np.var(sims, ddof=1))
    br_truth = math.sqrt(sigma_on ** 2 + var_rec)
    return {("D.5.1", "B0"): (b0_truth, "°/h", "removed", b0_alt),
            ("D.5.3", "Br"): (br_truth, "°/h", "")}


def build_gbt_rate(folder: Path, rng, *, dt: float, fmt: str, lsb_deg_h: float, asym: float,
                   flick: float, wander: float, quick: bool = False, rates=R5_GBT) -> dict:
    """GB/T 45570 D.2.1 (rate method), LSB output: rest at start and end, then each rate of the R5
    series counter-clockwise (+) and clockwise (−), 100 s each (D.2.1.2)."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    K = 3600.0 / lsb_deg_h * float(rng.uniform(0.8, 1.25))      # LSB/(°/s)
    a = asym * float(rng.uniform(-1, 1))                         # (K+ − K−)/K
    Kp, Km = 1 + a / 2, 1 - a / 2
    noise = Noise(float(rng.uniform(0.002, 0.01)), flicker=flick, wander_amp=wander,
                  wander_period=float(rng.uniform(1200, 5400)))
    b = float(rng.uniform(-2, 2))
    out = Output("LSB", K=K)
    device = {"id": folder.name, "technology": "fibre", "application": "marine",
              "output": "digital",
              "scale_factor": f"{K!r} LSB/(°/s)", "scale_factor_U": "50 ppm",
              "nonlinearity": "20 ppm"}
    camp = Campaign(folder, device, lat, [RATE_TABLE, COUNTER], fmt=fmt, output=out)
    n = int(round(100 / dt))
    # fixed table error per set point, uniform within ±√3·U/k (the table errs as its certificate
    # says)
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * 0.5e-4 for r in rates}
    phase = float(rng.uniform(0, 2 * math.pi))
    t0 = 0.0

    def seg(rate_dps: float):
        nonlocal t0
        e, w = noise.draw(n, dt, rng, t0=t0, phase=phase)
        t0 += n * dt + 60.0
        scale = Kp if rate_dps > 0 else (Km if rate_dps < 0 else 1.0)
        sensed = rate_dps * 3600.0 * scale + b + w + e + earth
        return out.record(sensed, dt, rng=rng)

    camp.add("rest-start", "rate-static", seg(0.0), dt, {"when": "start"})
    for r in rates:
        for sgn, tag in ((1, "+"), (-1, "-")):
            actual = sgn * r * (1 + terr[r])
            camp.add(f"rate{tag}{r}", "rate-output", seg(actual), dt,
                     {"rate": f"{sgn * r!r} deg/s"})
    camp.add("rest-end", "rate-static", seg(0.0), dt, {"when": "end"})
    camp.write_manifest()
    return {("D.2.1", "K"): (K * (Kp + Km) / 2, "LSB/(°/s)", "")}


def build_gbt_angle(folder: Path, rng, *, asym: float, columns: str = "count", quick: bool = False,
                    turns: int = 5) -> dict:
    """GB/T 45570 D.1.1 (angle method), pulse output: at each R5 rate, ``turns`` whole revolutions
    counter-clockwise (+) then clockwise (−), the pulses counted between revolution pulses
    (D.1.1.2 g)); one row per revolution.  ``columns``: "count" writes ``count [P]`` and
    ``duration [s]`` (what ``metro plan`` lists for a `rate-revolutions` segment), "output" the
    documented single ``output [P]`` column."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    K = float(rng.uniform(0.3, 3.0))                             # P/″
    a = asym * float(rng.uniform(-1, 1))
    Kp, Km = 1 + a / 2, 1 - a / 2
    arw = float(rng.uniform(0.001, 0.004))
    b = float(rng.uniform(-1, 1))
    device = {"id": folder.name, "technology": "laser", "application": "aviation",
              "output": "pulse",
              "scale_factor": f"{K!r} P/″", "scale_factor_U": "10 ppm"}
    table = dict(RATE_TABLE, revolution_pulse_accuracy="2″")
    camp = Campaign(folder, device, lat, [table, COUNTER], fmt="csv", output=Output("pulse", K=K))
    rates = R5_GBT[:11] if quick else R5_GBT
    for r in rates:
        T = 360.0 / r
        for sgn, tag in ((1, "+"), (-1, "-")):
            scale = Kp if sgn > 0 else Km
            # angle of each revolution as the table turned it (″), the pulse positions err by ±2″
            edges = np.cumsum(np.concatenate([[0.0], np.full(turns, 1296000.0)]))
            edges = edges + rng.uniform(-2.0, 2.0, edges.size)
            sensed = sgn * np.diff(edges) * scale + (b + earth) * T \
                + rng.standard_normal(turns) * arw * 60.0 * math.sqrt(T)
            cum = np.floor(np.cumsum(np.concatenate([[rng.uniform(0, 1)], sensed * K])))
            counts = np.diff(cum)
            sid = f"rate{tag}{r}"
            if columns == "count":
                name = folder / f"{sid}.csv"
                rows = "\n".join(f"{c!r},{T!r}" for c in counts.tolist())
                name.write_text(f"count [P],duration [s]\n{rows}\n", encoding="utf-8")
                camp.segments.append((sid, "rate-revolutions", name.name, T,
                                      {"rate": f"{sgn * r!r} deg/s", "turns": turns}, None))
            else:
                camp.add(sid, "rate-revolutions", counts, T,
                         {"rate": f"{sgn * r!r} deg/s", "turns": turns})
    camp.write_manifest()
    return {("D.1.1", "K"): (K * (Kp + Km) / 2, "P/″", "")}


def _jjf_noise_mc_K_rel(noise: Noise, dt: float, n_per_rate: int, K: float, out: Output, rng,
                        draws: int, asym_scale, rate_set=R5_JJF) -> float:
    """Relative standard deviation of eq. (4)'s slope from noise alone (this generator's noise,
    record layout and quantization), by Monte Carlo."""
    rates = np.array([s * r for r in rate_set for s in (1, -1)])
    ks = []
    for _ in range(draws):
        F = []
        for r in rates:
            e, w = noise.draw(n_per_rate, dt, rng)
            sensed = r * 3600.0 + w + e
            F.append(out.record(sensed, dt, K_scale=asym_scale(r), rng=rng).mean())
        F = np.asarray(F)
        nn = rates.size
        k_hat = (nn * (rates * F).sum() - rates.sum() * F.sum()) / (
            nn * (rates**2).sum() - rates.sum() ** 2
        )
        ks.append(k_hat)
    ks = np.asarray(ks)
    if out.kind == "mV/V":
        ks = ks * out.supply
    return float(np.std(ks, ddof=1) / abs(K))


def build_jjf(folder: Path, rng, *, dt_static: float, dt_rate: float, fmt: str, kind: str,
              flick: float, wander: float, q: float, asym: float, neg: bool, static_s: float,
              quick: bool = False, runs: int = 6, rates=R5_JJF, orientation: str = "IRA up",
              sigma_K_range: tuple[float, float] = (5e-5, 4e-4),
              static_quick: float | None = None) -> dict:
    """JJF 2014 7.2.1, 7.2.4, 7.2.13: ±11 R5 rates (7.2.1.1), `runs` repeats of them (7.2.4.1,
    each a power-on of its own), and a static record IRA up (7.2.13.1) of ``static_s`` seconds
    (``static_quick`` with ``quick``), analog output."""
    lat = float(rng.uniform(-65, 70))
    earth = OMEGA_E_DEG_H * math.sin(math.radians(lat))
    Kmag = float(rng.uniform(5, 60))                                   # mV/(°/s)
    K = -Kmag if neg and rng.uniform() < 0.5 else Kmag
    a = asym * float(rng.uniform(-1, 1))
    Kp, Km = 1 + a / 2, 1 - a / 2
    sigma_K = float(rng.uniform(*sigma_K_range))                       # 1σ relative, power-on
    arw = float(rng.uniform(0.05, 0.3))                                # °/√h
    noise = Noise(arw, flicker=flick * float(rng.uniform(0.5, 1.5)), wander_amp=wander,
                  wander_period=float(rng.uniform(900, 3600)))
    b_mean = float(rng.uniform(-360, 360))                             # °/h
    sigma_b = float(rng.uniform(1, 10))                                # °/h turn-on scatter
    supply = float(rng.uniform(4.5, 5.5))
    out = Output(kind, K=K, q=q, supply=supply)
    device = {"id": folder.name, "technology": "vibratory", "output": "analog"}
    if kind == "mV/V":
        device["supply_voltage"] = f"{supply!r} V"
    camp = Campaign(folder, device, lat, [RATE_TABLE, DMM], fmt=fmt, output=out)
    terr = {r: float(rng.uniform(-1, 1)) * math.sqrt(3) * 0.5e-4 for r in rates}
    n_rate = int(round(10 / dt_rate))

    def asym_scale(r):
        return Kp if r > 0 else Km

    def calibration(prefix: str, kind_: str, run: int | None) -> float:
        k_rel = 1 + sigma_K * rng.standard_normal()
        b_on = b_mean + sigma_b * rng.standard_normal()
        for r in rates:
            for sgn, tag in ((1, "+"), (-1, "-")):
                actual = sgn * r * (1 + terr[r]) * 3600.0              # °/h
                e, w = noise.draw(n_rate, dt_rate, rng)
                sensed = actual * (Kp if sgn > 0 else Km) + b_on + earth + w + e
                vals = out.record(sensed, dt_rate, K_scale=k_rel, rng=rng)
                cond = {"rate": f"{sgn * r!r} deg/s"}
                if run is not None:
                    cond["run"] = run
                camp.add(f"{prefix}{tag}{r}", kind_, vals, dt_rate, cond)
        return K * k_rel * (Kp + Km) / 2

    K0 = calibration("rate", "rate", None)
    for i in range(1, runs + 1):
        calibration(f"rate-repeat#{i}", "rate-repeat", i)
    if quick and static_quick is not None:
        static_s = static_quick
    n_static = int(round(static_s / dt_static))
    b_on = b_mean + sigma_b * rng.standard_normal()
    k_rel = 1 + sigma_K * rng.standard_normal()
    wh, fl, w = noise.draw3(n_static, dt_static, rng)
    # the IRA's vertical earth-rate component
    e_sign = -1.0 if "down" in orientation.lower() else 1.0
    vals = out.record(b_on + e_sign * earth + w + wh + fl, dt_static, K_scale=k_rel, rng=rng)
    camp.add("static", "static", vals, dt_static, {"orientation": orientation})
    camp.write_manifest()
    b0 = b_on + float(w.mean())
    # B₀ = F̄/K with the K of 7.2.1 (another power-on): F̄ = K·k_rel·(b + earth) → the static
    # power-on's own K differs from K0 by its turn-on scatter, which is the device's K_r; the
    # measurand is the static record's rate, so truth divides by that power-on's K, as a lab that
    # knew it would.
    kr_noise = _jjf_noise_mc_K_rel(noise, dt_rate, n_rate, K, out, rng, 30 if quick else 80,
                                   asym_scale, rates)
    kr_truth = math.sqrt(sigma_K ** 2 + kr_noise ** 2)
    unitK = "mV/(°/s)"
    return {("7.2.1", "K"): (K0, unitK, ""),
            ("7.2.4", "Kr"): (kr_truth, "", ""),
            ("7.2.13", "B0"): (b0, "°/h", ("earth", e_sign * earth), b0 + float(fl.mean()))}


VARIANTS = variants(
    Variant("gbt-pulse-1Hz-flicker", "gbt45570", "D.5.1,D.5.3",
            text("""
                pulse output (undithered counter, K 0.3–3 P/″), 1 Hz, CSV, ARW 0.001–0.004
                °/√h, flicker plateau ≈ 0.004 °/h, 1 h records, latitude −65°…70°"""),
            build_with(build_gbt_bias, kind="pulse", dt=1.0, fmt="csv", flick=0.004, wander=0.0,
                       lsb_deg_h=0, q_deg_h=0)),
    Variant("gbt-pulse-1Hz-strong-flicker", "gbt45570", "D.5.1,D.5.3",
            text("""
                as gbt-pulse-1Hz-flicker with a flicker plateau ≈ 0.02 °/h (5–20 × the white
                noise's 1 h mean)"""),
            build_with(build_gbt_bias, kind="pulse", dt=1.0, fmt="csv", flick=0.02, wander=0.0,
                       lsb_deg_h=0, q_deg_h=0)),
    Variant("gbt-pulse-10Hz-IRAdown-Q10", "gbt45570", "D.5.1,D.5.3",
            text("""
                pulse output at 10 Hz (a few pulses per sample: the counter's ±1 P matters),
                IRA down (the earth rate's sign flips), Q = 10 power-ons, thermal wander 0.005
                °/h, no flicker"""),
            build_with(build_gbt_bias, kind="pulse", dt=0.1, fmt="npy", flick=0.0, wander=0.005,
                       lsb_deg_h=0, q_deg_h=0, Q=10, orientation="IRA down")),
    Variant("gbt-lsb-10Hz-coarse-thermal", "gbt45570", "D.5.1,D.5.3",
            text("""
                LSB output, 1 LSB ≈ 1 °/h (coarser than the 10 Hz noise), 10 Hz, .npy,
                sinusoidal thermal wander ≈ 0.01 °/h (period 20–90 min, random phase per
                power-on), flicker 0.002 °/h"""),
            build_with(build_gbt_bias, kind="LSB", dt=0.1, fmt="npy", flick=0.002, wander=0.01,
                       lsb_deg_h=1.0, q_deg_h=0)),
    Variant("gbt-rate-1Hz-quantized", "gbt45570", "D.5.1,D.5.3",
            text("""
                rate output in °/h rounded to 0.5 °/h (coarser than the 1 Hz noise), 1 Hz, CSV,
                flicker 0.003 °/h"""),
            build_with(build_gbt_bias, kind="rate", dt=1.0, fmt="csv", flick=0.003, wander=0.0,
                       lsb_deg_h=0, q_deg_h=0.5)),
    Variant("gbt-rate-method-lsb-asym", "gbt45570", "D.2.1",
            text("""
                D.2.1 rate method, LSB output (1 LSB ≈ 0.2–0.5 °/h), 10 Hz, .npy, K asymmetry
                up to ±200 ppm, thermal wander 0.05 °/h between start and end rest"""),
            build_with(build_gbt_rate, dt=0.1, fmt="npy", lsb_deg_h=0.3, asym=2e-4, flick=0.01,
                       wander=0.05)),
    Variant("gbt-angle-method-pulse-asym", "gbt45570", "D.1.1",
            text("""
                D.1.1 angle method, pulse output (K 0.3–3 P/″), 5 whole revolutions each way at
                14 R5 rates (1–400 °/s), revolution pulse within ±2″, K asymmetry up to ±20
                ppm, count/duration CSV"""),
            build_with(build_gbt_angle, asym=2e-5)),
    Variant("jjf-mV-1Hz-IRAdown-17rates", "jjf2014", "7.2.1,7.2.4,7.2.13",
            text("""
                mV output, either sign, 17 R5 rates 0.16 … 250 °/s (not metro's default set), 8
                repeat calibrations, static 1 h at 1 Hz IRA down, white noise only (CSV)"""),
            build_with(build_jjf, dt_static=1.0, dt_rate=1.0, fmt="csv", kind="mV", flick=0.0,
                       wander=0.0, q=0.0, asym=0.0, neg=True, static_s=3600, static_quick=300,
                       runs=8, orientation="IRA down",
                       rates=(0.16, 0.25, 0.4, 0.63, 1, 1.6, 2.5, 4, 6.3, 10, 16, 25, 40, 63, 100,
                              160, 250))),
    Variant("jjf-mV-100Hz-flicker-negK", "jjf2014", "7.2.1,7.2.4,7.2.13",
            text("""
                mV output, K ±(5–60) mV/(°/s) (either sign), rate points at 1 s (10 samples),
                static 1 h at 100 Hz (.npy), flicker plateau ≈ 3 °/h, no quantization"""),
            build_with(build_jjf, dt_static=0.01, dt_rate=1.0, fmt="npy", kind="mV", flick=3.0,
                       wander=0.0, q=0.0, asym=0.0, neg=True, static_s=3600, static_quick=300)),
    Variant("jjf-mV-10Hz-white-negK", "jjf2014", "7.2.1,7.2.4,7.2.13",
            text("""
                mV output, K ±(5–60) mV/(°/s) (either sign), white noise and a thermal wander
                of 5 °/h only (no flicker), rate points at 1 s, static 1 h at 10 Hz (CSV)"""),
            build_with(build_jjf, dt_static=0.1, dt_rate=1.0, fmt="csv", kind="mV", flick=0.0,
                       wander=5.0, q=0.0, asym=0.0, neg=True, static_s=3600, static_quick=300)),
    Variant("jjf-mVV-400Hz-thermal-coarse", "jjf2014", "7.2.1,7.2.4,7.2.13",
            text("""
                ratiometric mV/V output (supply 4.5–5.5 V) rounded to 0.01 mV/V, rate points at
                400 Hz (10 s), static 1 h at 400 Hz (.npy), thermal wander 5 °/h, flicker 2 °/h"""),
            build_with(build_jjf, dt_static=0.0025, dt_rate=0.0025, fmt="npy", kind="mV/V",
                       flick=2.0, wander=5.0, q=0.01, asym=0.0, neg=False, static_s=3600,
                       static_quick=300)),
    Variant("jjf-mV-2kHz-asym", "jjf2014", "7.2.1,7.2.4,7.2.13",
            text("""
                mV output rounded to 0.1 mV, K asymmetry up to ±500 ppm, either sign, rate
                points at 1 s, static 15 min at 2 kHz (.npy), CSV rate files"""),
            build_with(build_jjf, dt_static=0.0005, dt_rate=1.0, fmt="csv", kind="mV", flick=1.0,
                       wander=0.0, q=0.1, asym=5e-4, neg=True, static_s=900, static_quick=120)),
)


# --------------------------------------------------------------------------------------------
# running metro and scoring
# --------------------------------------------------------------------------------------------

def run_metro(manifest: Path, standard: str, items: str, use_subprocess: bool = False,
              options=(), main=None) -> tuple[int, dict, str]:
    """``metro run --json`` on one campaign (``options``: item options, each ``-o`` once):
    (exit code, the JSON document, stderr). In-process, ``main`` is the command line called
    (default metro's ``cli.app.main``)."""
    argv = ["run", "-s", standard, "-i", items, "--data", str(manifest), "--json", "--no-report",
            "--quiet"]
    for o in options:
        argv += ["-o", o]
    if use_subprocess:
        exe = Path(sys.executable).with_name("metro")
        proc = subprocess.run([str(exe), *argv], capture_output=True, text=True)
        out, err, code = proc.stdout, proc.stderr, proc.returncode
    else:
        if main is None:
            from metro.core.cli.app import main

        so, se = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(so), contextlib.redirect_stderr(se):
            try:
                code = main(argv)
            except Exception:  # a traceback is itself a finding
                import traceback

                code, se = 1, io.StringIO(traceback.format_exc())
        out, err = so.getvalue(), se.getvalue()
    try:
        doc = json.loads(out) if out.strip() else {}
    except json.JSONDecodeError:
        doc = {}
    return code, doc, err


UNIT_ALIASES = {
    "°/h": {"°/h", "deg/h", "degree / hour", "degree/hour", "(°)/h"},
    "mV/(°/s)": {"mV/(°/s)", "mV/[(°)/s]", "millivolt / degree * second", "mV·s/°", "mV/((°)/s)",
                 "millivolt * second / degree", "mV s/°"},
    "LSB/(°/s)": {"LSB/(°/s)", "LSB/[(°)/s]", "LSB/((°)/s)", "LSB s/°", "LSB·s/°",
                  "least_significant_bit * second / degree"},
    "P/″": {"P/″", "P/arcsec", "pulse / arcsecond", "P/(″)"},
    "": {"", "1", "dimensionless"},
}


def score(truth: dict, doc: dict) -> list[dict]:
    rows = []
    results = doc.get("results", [])
    for (item, key), (value, unit, earth, *alt) in truth.items():
        match = [r for r in results if r.get("key") == key and str(r.get("item", "")).upper()
                 == item.upper()]
        if not match:
            rows.append({"item": item, "key": key, "status": "missing"})
            continue
        r = match[0]
        t = value
        t_alt = alt[0] if alt else None
        # JJF B₀: truth follows what metro says it did with the earth rate
        if isinstance(earth, tuple):
            if r.get("earth_rate") == "included":
                t = value + earth[1]
                t_alt = None if t_alt is None else t_alt + earth[1]
            elif r.get("earth_rate") not in ("removed", "not applicable"):
                rows.append({"item": item, "key": key,
                             "status": f"earth_rate={r.get('earth_rate')!r}"})
                continue
        runit = r.get("unit") or ""
        val, U = r.get("value"), r.get("U")
        if key in ("Kr",) and runit in ("ppm",):
            val, U = val * 1e-6, U * 1e-6
            runit = ""
        elif key == "Kr" and runit == "%":
            val, U = val * 1e-2, U * 1e-2
            runit = ""
        if runit not in UNIT_ALIASES.get(unit, {unit}):
            rows.append({"item": item, "key": key, "status": f"unit {runit!r} (expected {unit})",
                         "value": val, "truth": t})
            continue
        if not r.get("reportable", True):
            rows.append({"item": item, "key": key, "status": "not reportable",
                         "reason": r.get("reason", ""),
                         "value": val, "truth": t, "U": U})
            continue
        if U is None or not U > 0:
            rows.append({"item": item, "key": key, "status": f"U={U!r}", "value": val, "truth": t})
            continue
        en = (val - t) / U
        row = {"item": item, "key": key, "status": "ok", "value": val, "truth": t, "U": U, "En": en}
        if t_alt is not None:  # the record's flicker mean counted as bias, not as error
            row["En_alt"] = (val - t_alt) / U
        rows.append(row)
    return rows


def run_variant(variant: Variant, devices: int, seed0: int, workdir: Path,
                use_subprocess: bool = False,
                quick: bool = False, keep: bool = False, metro=None, scorer=None) -> list[dict]:
    """Build and evaluate ``devices`` campaigns of ``variant`` (seeds seed0, seed0 + 1, …) and score
    them: one row per result, or one ``exit N`` row with metro's message. ``metro(manifest)`` runs
    metro (default :func:`run_metro` with the variant's standard and items), ``scorer(truth, doc)``
    scores (default :func:`score`) — a harness module passes its own."""
    metro = metro or (lambda m: run_metro(m, variant.standard, variant.items, use_subprocess))
    scorer = scorer or score
    out = []
    for i in range(devices):
        seed = seed0 + i
        rng = np.random.default_rng([seed, zlib.crc32(variant.name.encode())])
        folder = workdir / f"{variant.name}-{seed}"
        folder.mkdir(parents=True)
        t0 = time.perf_counter()
        truth = variant.build(folder, rng, quick)
        t1 = time.perf_counter()
        code, doc, err = metro(folder / "manifest.toml")
        t2 = time.perf_counter()
        if code not in (0, 3, 4) or not doc.get("results"):
            out.append({"variant": variant.name, "seed": seed, "status": f"exit {code}",
                        "error": (doc.get("message") or (err.strip().splitlines()
                                                         or [""])[-1])[:400]})
        else:
            for row in scorer(truth, doc):
                out.append({"variant": variant.name, "seed": seed, **row, "t_gen": t1 - t0,
                            "t_run": t2 - t1})
        if not keep:
            import shutil

            shutil.rmtree(folder, ignore_errors=True)
    return out


def summarise(rows: list[dict]) -> list[dict]:
    table: dict[tuple, dict] = {}
    for r in rows:
        if "item" not in r:
            k = (r["variant"], "(all)", "(run)")
        else:
            k = (r["variant"], r["item"], r["key"])
        s = table.setdefault(k, {"devices": 0, "ok": 0, "within": 0, "nr": 0, "en": [], "alt": [],
                                 "other": []})
        s["devices"] += 1
        st = r.get("status")
        if st == "ok":
            s["ok"] += 1
            s["en"].append(r["En"])
            if "En_alt" in r:
                s["alt"].append(r["En_alt"])
            s["within"] += abs(r["En"]) <= 1
        elif st == "not reportable":
            s["nr"] += 1
        else:
            s["other"].append(f"{st}: {r.get('error', '')}".strip(": "))
    res = []
    for (v, item, key), s in table.items():
        en = np.asarray(s["en"])
        res.append({"variant": v, "item": item, "key": key, "devices": s["devices"],
                    "reportable": s["ok"],
                    "not_reportable": s["nr"],
                    "within": (s["within"] + s["nr"]) / s["devices"] if s["devices"]
                    else float("nan"),
                    "mean_En": float(en.mean()) if en.size else float("nan"),
                    "rms_En": float(np.sqrt((en ** 2).mean())) if en.size else float("nan"),
                    "max_abs_En": float(np.abs(en).max()) if en.size else float("nan"),
                    "within_alt": float(np.mean(np.abs(s["alt"]) <= 1)) if s["alt"] else None,
                    "mean_En_alt": float(np.mean(s["alt"])) if s["alt"] else None,
                    "other": sorted(set(s["other"]))})
    return res


def table_row(s: dict, *, label: str = "", alt: bool = True, other_chars: int | None = None) -> str:
    """One summary row ``s`` of a harness table: variant (after ``label``), item, result (with its
    other outcomes, cut to ``other_chars``), devices, not reportable, within U, the E_n columns and,
    with ``alt``, the alternative truth's within U and mean E_n; "—" where there is no value."""
    def f(x, fmt):
        return "—" if x is None or (isinstance(x, float) and math.isnan(x)) else format(x, fmt)
    other = f" ({'; '.join(s['other'])[:other_chars]})" if s["other"] else ""
    row = (f"| {label}{s['variant']} | {s['item']} | {s['key']}{other} | {s['devices']} | "
           f"{s['not_reportable']} | {100 * s['within']:.1f} % | {f(s['mean_En'], '+.2f')} "
           f"| {f(s['rms_En'], '.2f')} | {f(s['max_abs_En'], '.2f')} |")
    if alt:
        row += (f" {100 * s['within_alt']:.1f} %, {s['mean_En_alt']:+.2f} |"
                if s["within_alt"] is not None else " — |")
    return row


def markdown(rows: list[dict]) -> str:
    """The table of docs/independent-campaigns.md from the rows of one or more sweeps."""
    out = ["| variant | item | result | devices | not reportable | within U (or not reportable) | "
           "mean E_n | rms E_n | max abs E_n | flicker mean as bias: within U, mean E_n |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    out += [table_row(s) for s in summarise(rows)]
    return "\n".join(out)


def cli(argv, variants: dict, description: str, *, run=None, summary=None, table=None,
        prefix: str = "indep-", alt_label: str = "flicker mean as bias",
        quick_help: str = "short records (a smoke run, not the measurand)",
        add_arguments=None, scorer=None) -> int:
    """The command line every harness module shares: ``--devices --seed --variants --keep
    --subprocess --quick --json --markdown`` (and the module's own ``add_arguments(ap)``).
    ``run(variant, args, work)`` evaluates one variant's devices (default :func:`run_variant` with
    ``scorer``),
    ``summary(rows, args)`` gives the printed lines' dicts (default :func:`summarise`),
    ``table(rows, args)`` the ``--markdown`` table (default :func:`markdown`)."""
    ap = argparse.ArgumentParser(description=description)
    ap.add_argument("--devices", type=int, default=30)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--variants", default=",".join(variants))
    ap.add_argument("--keep", type=Path, default=None, help="keep the campaigns under this folder")
    ap.add_argument("--subprocess", action="store_true",
                    help="run the metro command, not cli.main in-process")
    ap.add_argument("--quick", action="store_true", help=quick_help)
    ap.add_argument("--json", type=Path, default=None, help="write every row to this file")
    ap.add_argument("--markdown", nargs="+", type=Path, default=None,
                    help="print the table of these --json files and exit")
    if add_arguments is not None:
        add_arguments(ap)
    args = ap.parse_args(argv)
    run = run or (lambda v, a, work: run_variant(v, a.devices, a.seed, work, a.subprocess,
                                                 quick=a.quick, keep=a.keep is not None,
                                                 scorer=scorer))
    summary = summary or (lambda rows, a: summarise(rows))
    table = table or (lambda rows, a: markdown(rows))
    if args.markdown:
        print(table([r for p in args.markdown for r in json.loads(p.read_text())], args))
        return 0
    names = [v.strip() for v in args.variants.split(",") if v.strip()]
    unknown = [n for n in names if n not in variants]
    if unknown:
        ap.error(f"unknown variants {unknown}; known: {list(variants)}")
    all_rows = []
    with tempfile.TemporaryDirectory(prefix=prefix) as tmp:
        work = args.keep or Path(tmp)
        for name in names:
            t0 = time.perf_counter()
            rows = run(variants[name], args, work)
            all_rows += rows
            print(f"# {name}: {args.devices} devices in {time.perf_counter() - t0:.0f} s",
                  file=sys.stderr)
            for s in summary(rows, args):
                print(f"{s['variant']:36s} {s['item']:7s} {s['key']:17s} n={s['devices']:4d} "
                      f"nr={s['not_reportable']:3d} within={100 * s['within']:5.1f} % "
                      f"mean_En={s['mean_En']:+.2f} rms={s['rms_En']:.2f} "
                      f"max|En|={s['max_abs_En']:.2f} "
                      + (f"[{alt_label}: within={100 * s['within_alt']:.1f} % "
                         f"mean_En={s['mean_En_alt']:+.2f}] "
                         if s.get("within_alt") is not None else "")
                      + f"{'; '.join(s['other'])[:300]}", flush=True)
            if args.json:  # after each variant: a long sweep keeps what it has
                args.json.write_text(json.dumps(all_rows, indent=1, default=float))
    return 0


def main(argv=None) -> int:
    return cli(argv, VARIANTS, __doc__.split("\n\n")[0])


if __name__ == "__main__":
    sys.exit(main())

"""An independent harness for the draft JJF 光学陀螺测角仪 (ogam): instruments metro's simulator
does not make.

Run:  nice -n 10 .venv/bin/python benchmarks/independent_ogam.py [--devices 30] [--variants A,B]
                                                                [--seed 1] [--json F] [--keep DIR]
                                                                [--quick]

Issue 13's independent harness for the optical-gyro angle-measuring instrument (draft JJF, file 004
of the standards folder). The generators here were written from the documentation only
(docs/standards/ogam.md's data table, docs/data-format.md, ``metro plan -s ogam --all``'s steps and
columns) and from the draft's clauses 7.1–7.7 and appendix A; they import neither
``metro.instruments`` nor any of metro's simulators (numpy alone). The shared pieces (the manifest
writer, running metro, scoring, the tables) come from ``independent_campaigns.py`` next to this
file.

The instrument (all angles in ″ unless said):

* a gyro that emits pulses, K_true(v) = K·(1 + κ(v)) per degree at table rate v, while the
  instrument turns counts into its angle reading with its own K (the manifest's ``scale_factor``):
  κ(v) = κ₆₀ + s_lin·(v − 60)/240 + s_low·(60/v − 1)/59 (a scale-factor error at the reference rate,
  a linear and a low-rate rate dependence: clause 4's "不同速度的会引入计算误差");
* harmonic angle errors Σ a_k·[sin(kθ + φ_k) − sin φ_k] (zero at the zeroed start), orders and sizes
  per variant;
* a residual rate after the instrument's own earth-rate compensation (clause 7): b₀ (its bias
  residual) + η·Ω_e·(the earth rate's component on the axis: sin φ up, ±cos φ north/south, 0
  east/west) + b_g on the vertical axis only (a g-dependent bias), constant over the session;
* a random rate (Gauss–Markov, σ_b, correlation time τ_c 5–30 min), angle random walk (ARW), reading
  noise;
* the reading rounded to the instrument's resolution (zeroed with the turntable: no random phase);
  the 7.1 counts are ⌊K_true·angle + φ₀⌋ with a random counter phase φ₀;
* the sensing plane tilted by ψ (within the turntable's declared ``parallelism``) at an azimuth α to
  the zero position: appendix A's model (eqs. (2)–(5), numerically integrated here), Δ(θ + α) −
  Δ(α);
* the turntable's positioning error, a fixed function of angle (harmonics of orders 1–4 and 12)
  whose largest value over the stops is within its certificate (the uniform half-width, or U at k =
  2);
* the time from zeroing to each reading: ``from-zero`` (the draft's tables: every stop is turned to
  from 0°, turning time θ/v + 2 s, read within the 60 s stop, about 0.5 min as appendix A 1 says) or
  ``sequential`` (``metro plan``'s wording: 30°, 60°, … in one run, 60 s at each, up to 12 min).

Truth (docs/independent-campaigns.md, "ogam: the angle-measuring instrument"):

* 7.4 E: max_i |e_i| over the stops of the first 60 °/s axis-up round, e_i the instrument's
  deterministic reading error at S_i under the campaign's conditions: κ₆₀·S_i + harmonics + the
  residual rate × the time to that reading.  Noise (random walk, the random rate, reading noise, the
  reading's rounding), the turntable's error and the tilt (appendix A's u(P) and u(θ_ψ)) are
  measurement error.
* 7.6 C_v, 7.7 C_g: (max E − min E)/E_ref × 100 % of those E at each rate (κ(v), times at that rate)
  or axis direction (the residual rate of that direction).
* 7.1 K: the mean of K_i = C_i/θ_i on the noise-free counts (harmonics and the residual rate in,
  counter rounding, turntable error, tilt out); 7.2 K_l: (max − min)/K of those K_i, in %.
* 7.3 B_s: √E[s²(M)]/T, E over 4 000 Monte Carlo repeats of the generator's own 7.3 record (the
  residual rate, the random rate, random walk, reading noise, rounding), T = (n − 1)·Δt as the
  clause.
* 7.5 R: max_i σ_i, σ_i the standard deviation of E_ij at stop i over 4 000 Monte Carlo rounds of
  the generator (clause 3.7: the standard deviation of repeated measurements of the same position).
"""

from __future__ import annotations

import functools
import math
import sys
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
import independent_campaigns as IC  # noqa: E402
from independent_campaigns import Campaign, Variant, summarise  # noqa: E402

OMEGA_E_DEG_H = 15.041  # °/h
RATES = (1.0, 10.0, 60.0, 100.0, 150.0, 200.0, 250.0, 300.0)  # clause 7.6's reference values

IC.UNIT_ALIASES.update({
    "P/°": {"P/°", "P/deg", "pulse / degree", "P/(°)", "count / degree"},
    "%": {"%", "percent"},
    "″": {"″", "arcsec", "arcsecond", '"'},
})


# --------------------------------------------------------------------------------------------
# the instrument (numpy only)
# --------------------------------------------------------------------------------------------

@functools.lru_cache(maxsize=64)
def tilt_curve(psi_deg: float, n: int = 14401) -> tuple[np.ndarray, np.ndarray]:
    """Appendix A 4.2, eqs. (2)–(5): θ (rad) on 0…2π and the error θ_ψ(θ) − θ in ″, with
    r(θ) = cos ψ / √(cos²ψ cos²θ + sin²θ) and the reading 2π·∫₀^θ r / ∮ r (trapezoid sums)."""
    th = np.linspace(0.0, 2 * math.pi, n)
    c = math.cos(math.radians(psi_deg))
    r = c / np.sqrt(c * c * np.cos(th) ** 2 + np.sin(th) ** 2)
    cum = np.concatenate([[0.0], np.cumsum(0.5 * (r[1:] + r[:-1]) * np.diff(th))])
    return th, np.degrees(2 * math.pi * cum / cum[-1] - th) * 3600.0


@dataclass
class Instrument:
    K: float                      # P/°, the instrument's own (manifest scale_factor)
    kappa60: float                # relative scale-factor error at 60 °/s
    s_lin: float
    s_low: float
    harmonics: list               # (order, amplitude ″, phase)
    b0: float                     # °/h residual bias after compensation
    eta: float                    # relative earth-rate compensation error
    b_g: float                    # °/h, axis vertical only
    sigma_b: float                # °/h, the random rate (Gauss–Markov)
    arw: float                    # °/√h
    read_noise: float             # ″
    resolution: float             # ″ (0: none)
    psi: float                    # ° tilt
    alpha: float                  # rad, tilt azimuth
    latitude: float               # °
    tt_half: float                # ″ turntable: largest |error| allowed by its certificate
    tt_coef: list = field(default_factory=list)  # (order, amp, phase) of the turntable error
    tt_scale: float = 1.0
    layout: str = "from-zero"
    settle: float = 20.0          # s into the 60 s stop when the reading is taken (from-zero)
    tau: float = 900.0            # s, correlation time of the random rate

    def wander(self, t: np.ndarray, repeats: int, rng) -> np.ndarray:
        """(repeats × t.size) angle (″) the random rate x(t) adds by each time t (s from zeroing): a
        Gauss–Markov rate of standard deviation σ_b (°/h = ″/s) and correlation time τ_c, started
        in its stationary state at zeroing, integrated on steps of at most 10 s."""
        fine = np.unique(np.concatenate([np.arange(0.0, float(t.max()) + 10.0, 10.0), [0.0], t]))
        fine = fine[fine <= t.max()]
        x = rng.standard_normal(repeats) * self.sigma_b
        ang = np.zeros((repeats, fine.size))
        for k in range(1, fine.size):
            h = fine[k] - fine[k - 1]
            a = math.exp(-h / self.tau)
            x_new = a * x + self.sigma_b * math.sqrt(1 - a * a) * rng.standard_normal(repeats)
            ang[:, k] = ang[:, k - 1] + 0.5 * (x + x_new) * h
            x = x_new
        return ang[:, np.searchsorted(fine, t)]

    def kappa(self, v: float) -> float:
        return self.kappa60 + self.s_lin * (v - 60.0) / 240.0 + self.s_low * (60.0 / v - 1.0) / 59.0

    def harm(self, theta_deg: np.ndarray) -> np.ndarray:
        th = np.radians(theta_deg)
        return sum(a * (np.sin(k * th + p) - math.sin(p)) for k, a, p in self.harmonics) + 0.0 * th

    def rate_on(self, axis: str) -> float:
        """Residual rate (°/h) after the instrument's compensation, axis pointing ``axis``."""
        s, c = math.sin(math.radians(self.latitude)), math.cos(math.radians(self.latitude))
        comp = {"up": s, "north": c, "south": -c, "east": 0.0, "west": 0.0}[axis]
        return self.b0 + self.eta * OMEGA_E_DEG_H * comp + (self.b_g if axis == "up" else 0.0)

    def turntable(self, theta_deg: np.ndarray) -> np.ndarray:
        th = np.radians(theta_deg)
        return self.tt_scale * sum(a * (np.sin(k * th + p) - math.sin(p)) for k, a, p
                                   in self.tt_coef)

    def tilt(self, theta_deg: np.ndarray) -> np.ndarray:
        if self.psi == 0:
            return np.zeros_like(theta_deg, dtype=float)
        th, d = tilt_curve(self.psi)
        x = np.mod(np.radians(theta_deg) + self.alpha, 2 * math.pi)
        return np.interp(x, th, d) - float(np.interp(self.alpha % (2 * math.pi), th, d))

    def times(self, theta_deg: np.ndarray, v: float) -> np.ndarray:
        """Seconds from zeroing to each reading."""
        if self.layout == "from-zero":
            return theta_deg / v + 2.0 + self.settle
        step = np.diff(np.concatenate([[0.0], theta_deg]))
        return np.cumsum(step / v + 2.0 + 60.0) - 60.0 + self.settle

    def deterministic(self, S: np.ndarray, v: float, axis: str) -> np.ndarray:
        """The reading error (″) the truth holds: κ(v)·S + harmonics + residual rate × time."""
        return self.kappa(v) * S * 3600.0 + self.harm(S) + self.rate_on(axis) * self.times(S, v)

    def readings(self, S: np.ndarray, v: float, axis: str, rounds: int, rng) -> np.ndarray:
        """(rounds × stops) readings M_ij in ″ with everything: the turntable at S + p, tilt,
        the round's random bias, random walk over the times, reading noise, rounding."""
        t = self.times(S, v)
        true = S * 3600.0 + self.turntable(S)
        base = true + self.kappa(v) * true + self.harm(true / 3600.0) + self.tilt(true / 3600.0) \
            + self.rate_on(axis) * t
        b = self.wander(t, rounds, rng)
        dt = np.diff(np.concatenate([[0.0], t]))
        rw = np.cumsum(rng.standard_normal((rounds, t.size)) * self.arw * 60.0
                       * np.sqrt(dt / 3600.0), axis=1)
        m = base + b + rw + rng.standard_normal((rounds, t.size)) * self.read_noise
        if self.resolution:
            m = np.round(m / self.resolution) * self.resolution
        return m

    def zero_record(self, n: int, dt_s: float, repeats: int, rng) -> np.ndarray:
        """(repeats × n) 7.3 readings in ″ at rest, axis vertical."""
        t = dt_s * np.arange(n)
        b = self.rate_on("up") * t + self.wander(t, repeats, rng)
        rw = np.cumsum(np.concatenate([np.zeros((repeats, 1)),
                                       rng.standard_normal((repeats, n - 1)) * self.arw * 60.0
                                       * math.sqrt(dt_s / 3600.0)],
                                      axis=1), axis=1)
        m = b + rw + rng.standard_normal((repeats, n)) * self.read_noise
        if self.resolution:
            m = np.round(m / self.resolution) * self.resolution
        # the angle the instrument itself drifted through (no readout error)
        self.last_path = b + rw
        return m

    def counts(self, theta_deg: np.ndarray, rng, noisy: bool = True) -> np.ndarray:
        """7.1 counts C_i of each round 0 → θ_i at 60 °/s (axis up); noise-free (continuous) when
        ``noisy`` is false."""
        t = self.times(theta_deg, 60.0) if self.layout == "from-zero" else \
            theta_deg / 60.0 + 2.0 + 60.0  # each 7.1 round starts at 0 (the draft's table)
        if noisy:
            true = theta_deg * 3600.0 + self.turntable(theta_deg)
            ang = true + self.kappa(60.0) * true + self.harm(true
                                                             / 3600.0) + self.tilt(true / 3600.0) \
                + (self.rate_on("up") + rng.standard_normal(theta_deg.size) * self.sigma_b) * t \
                + rng.standard_normal(theta_deg.size) * self.arw * 60.0 * np.sqrt(t / 3600.0)
            return np.floor(self.K * ang / 3600.0 + rng.uniform(0, 1, theta_deg.size))
        ang = theta_deg * 3600.0 * (1
                                    + self.kappa(60.0)) + self.harm(theta_deg) + self.rate_on(
                                        "up") * t
        return self.K * ang / 3600.0


# --------------------------------------------------------------------------------------------
# campaigns (docs/standards/ogam.md "Data", docs/data-format.md)
# --------------------------------------------------------------------------------------------

def write_table(path: Path, columns: list[tuple[str, np.ndarray]], fmt: str = "csv") -> str:
    if fmt == "npy":
        name = path.parent / (path.name + ".npy")
        arr = np.zeros(columns[0][1].size, dtype=[(c, "f8") for c, _ in columns])
        for c, v in columns:
            arr[c] = v
        # a field name such as "reading [″]" is not Latin-1: the header needs .npy format 3.0, asked
        # for by name (np.save guesses it and warns "Stored array in format 3.0")
        latin1 = all(ord(ch) < 256 for c, _ in columns for ch in c)
        with open(name, "wb") as fh:
            np.lib.format.write_array(fh, arr, version=None if latin1 else (3, 0),
                                      allow_pickle=False)
        return name.name
    name = path.parent / (path.name + ".csv")
    with open(name, "w", encoding="utf-8", newline="\n") as fh:
        fh.write("# written by benchmarks/independent_ogam.py\n")
        fh.write(",".join(c for c, _ in columns) + "\n")
        for row in zip(*[v.tolist() for _, v in columns]):
            fh.write(",".join(repr(x) for x in row) + "\n")
    return name.name


@dataclass
class Spec:
    """What a variant draws (ranges are uniform unless said)."""
    K: tuple = (2e4, 2e5)                 # P/°, log-uniform
    kappa: float = 3e-7                   # |κ₆₀| ≤
    s_lin: float = 2e-7
    s_low: float = 3e-7
    orders: tuple = (1, 2, 3, 4)
    harm_amp: tuple = (0.0, 0.15)         # ″
    n_harm: tuple = (1, 3)
    b0: float = 0.003                     # °/h, |b₀| ≤
    eta: float = 3e-4
    b_g: float = 0.0
    sigma_b: tuple = (2e-4, 1e-3)         # °/h, the random rate's standard deviation
    tau: tuple = (300.0, 1800.0)          # s, its correlation time
    arw: tuple = (1e-4, 4e-4)             # °/√h
    read_noise: tuple = (0.005, 0.03)     # ″
    resolution: tuple = (0.001, 0.002, 0.005, 0.01)  # ″, one of (a display's decimal steps)
    parallelism: tuple = (0.05, 0.1)      # ° declared (appendix A 1: better than 0.1°); ψ within it
    tt_U: tuple = (0.05, 0.2)             # ″ certificate
    tt_dist: str = "uniform"              # or "normal" (U at k = 2)
    layout: str = "from-zero"
    zero: tuple = (13, 300.0)             # 7.3: readings, interval s
    zero_unit: str = "deg"
    reading_unit: str = "deg"
    rates: tuple = RATES
    south_west: bool = False
    fmt: str = "csv"
    technology: str = "laser"


def _loguni(rng, lo, hi):
    return float(math.exp(rng.uniform(math.log(lo), math.log(hi))))


def draw_instrument(spec: Spec, rng) -> tuple[Instrument, dict]:
    n_h = int(rng.integers(spec.n_harm[0], spec.n_harm[1] + 1))
    orders = rng.choice(spec.orders, size=min(n_h, len(spec.orders)), replace=False)
    harmonics = [(int(k), float(rng.uniform(*spec.harm_amp)), float(rng.uniform(0, 2 * math.pi)))
                 for k in orders]
    par = float(rng.uniform(*spec.parallelism))
    tt_U = float(rng.uniform(*spec.tt_U))
    tt_coef = [(k, float(rng.uniform(0, 1)), float(rng.uniform(0, 2 * math.pi))) for k
               in (1, 2, 3, 4, 12)]
    inst = Instrument(
        K=_loguni(rng, *spec.K), kappa60=float(rng.uniform(-spec.kappa, spec.kappa)),
        s_lin=float(rng.uniform(-spec.s_lin, spec.s_lin)),
        s_low=float(rng.uniform(-spec.s_low, spec.s_low)),
        harmonics=harmonics, b0=float(rng.uniform(-spec.b0, spec.b0)),
        eta=float(rng.uniform(-spec.eta, spec.eta)),
        b_g=float(rng.uniform(-spec.b_g, spec.b_g)), sigma_b=float(rng.uniform(*spec.sigma_b)),
        arw=float(rng.uniform(*spec.arw)), read_noise=float(rng.uniform(*spec.read_noise)),
        resolution=float(rng.choice(spec.resolution)) if spec.resolution else 0.0,
        psi=par * float(rng.uniform(0, 1)), alpha=float(rng.uniform(0, 2 * math.pi)),
        latitude=float(rng.uniform(-85, 85)), tau=float(rng.uniform(*spec.tau)), tt_half=tt_U,
        tt_coef=tt_coef, layout=spec.layout,
        settle=float(rng.uniform(5, 25)))
    # the turntable's error: largest |p| over a fine grid = tt_U × U(0.3, 1) (within the
    # certificate)
    grid = np.linspace(0, 360, 3601)
    p = inst.turntable(grid)
    inst.tt_scale = tt_U * float(rng.uniform(0.3, 1.0)) / float(np.max(np.abs(p)))
    # a spec the manufacturer states: the zero drift (appendix A 4.3) no smaller than the drift seen
    spec_drift = 1.5 * (abs(inst.rate_on("up")) + 2 * inst.sigma_b)
    return inst, {"parallelism": par, "tt_U": tt_U, "zero_stability": spec_drift}


def _fmt_deg(x_arcsec: np.ndarray, unit: str) -> np.ndarray:
    return x_arcsec / 3600.0 if unit == "deg" else x_arcsec


def build_ogam(folder: Path, rng, spec: Spec, quick: bool = False) -> dict:
    inst, meta = draw_instrument(spec, rng)
    device = {"id": folder.name, "technology": spec.technology, "output": "pulse",
              "scale_factor": f"{inst.K!r} P/°",
              "zero_stability": f"{meta['zero_stability']!r} °/h"}
    tt = {"id": "TT-X", "role": "turntable", "parallelism": f"{meta['parallelism']!r}°",
          "calibration": {"certificate": "IND-TT-1", "U": f"{meta['tt_U']!r}″",
                          "k": 2 if spec.tt_dist == "normal" else 1.7320508075688772,
                          "distribution": spec.tt_dist}}
    if spec.tt_dist == "uniform":
        del tt["calibration"]["k"]
    timer = {"id": "TIMER-X", "role": "timer"}
    camp = Campaign(folder, device, inst.latitude, [tt, timer])
    seg = camp.segments

    def add(seg_id, kind, cols, dt, cond):
        seg.append((seg_id, kind, write_table(folder / seg_id, cols, spec.fmt), dt, cond, ""))

    truth: dict = {}
    # 7.1 / 7.2
    theta = 60.0 * np.arange(1, 7)
    C = inst.counts(theta, rng)
    add("sf-60-up", "scale-factor", [("angle [°]", theta), ("counts [P]", C)], 60.0,
        {"axis": "up", "rate": "60 °/s"})
    k_true = inst.counts(theta, rng, noisy=False) / theta
    K_true = float(k_true.mean())
    truth[("7.1", "K")] = (K_true, "P/°", None)
    truth[("7.2", "Kl")] = (100.0 * float(k_true.max() - k_true.min()) / K_true, "%", None)
    # 7.3
    n_z, dt_z = spec.zero
    z = inst.zero_record(n_z, dt_z, 1, rng)[0]
    path = inst.last_path[0]
    add("zero-1h", "zero", [(f"reading [{'°' if spec.zero_unit == 'deg' else '″'}]",
                             _fmt_deg(z, spec.zero_unit))],
        dt_z, {"axis": "up"})
    mc = inst.zero_record(n_z, dt_z, 1000 if quick else 4000, rng)
    T_h = (n_z - 1) * dt_z / 3600.0
    # the expectation over repeated hours; and, second, this hour's own drift (reading noise and
    # rounding the only error: the reading of JJF 2014 7.2.13's "this record's bias",
    # interpretations.md)
    truth[("7.3", "Bs")] = (math.sqrt(float(np.mean(np.var(mc, axis=1, ddof=1)))) / 3600.0 / T_h,
                            "°/h", None,
                            float(np.std(path, ddof=1)) / 3600.0 / T_h)
    # 7.4 / 7.5: ten rounds at 60 °/s axis up
    S = 30.0 * np.arange(1, 13)
    rcol = f"reading [{'°' if spec.reading_unit == 'deg' else '″'}]"
    scol = f"standard [{'°' if spec.reading_unit == 'deg' else '″'}]"

    def pos(seg_id, v, axis, rnd, m):
        add(seg_id, "positioning", [(scol, _fmt_deg(S * 3600.0, spec.reading_unit)),
                                    (rcol, _fmt_deg(m, spec.reading_unit))],
            60.0, {"axis": axis, "rate": f"{v:g} °/s", "round": rnd})

    M = inst.readings(S, 60.0, "up", 10, rng)
    for j in range(10):
        pos(f"pos-60-up-r{j + 1:02d}", 60.0, "up", j + 1, M[j])
    E_true = {}

    def e_true(v, axis):
        return float(np.max(np.abs(inst.deterministic(S, v, axis))))

    E_true[(60.0, "up")] = e_true(60.0, "up")
    truth[("7.4", "E")] = (E_true[(60.0, "up")], "″", None)
    mcr = inst.readings(S, 60.0, "up", 1000 if quick else 4000, rng) - S * 3600.0
    truth[("7.5", "R")] = (float(np.max(np.std(mcr, axis=0, ddof=1))), "″", None)
    # 7.6
    for v in spec.rates:
        if v == 60.0:
            continue
        pos(f"pos-{v:g}-up-r01", v, "up", 1, inst.readings(S, v, "up", 1, rng)[0])
        E_true[(v, "up")] = e_true(v, "up")
    ev = [E_true[(v, "up")] for v in spec.rates]
    truth[("7.6", "Cv")] = (100.0 * (max(ev) - min(ev)) / E_true[(60.0, "up")], "%", None)
    # 7.7
    axes = ["up", "south" if spec.south_west else "north", "west" if spec.south_west else "east"]
    for a in axes[1:]:
        pos(f"pos-60-{a}-r01", 60.0, a, 1, inst.readings(S, 60.0, a, 1, rng)[0])
        E_true[(60.0, a)] = e_true(60.0, a)
    eg = [E_true[(60.0, a)] for a in axes]
    truth[("7.7", "Cg")] = (100.0 * (max(eg) - min(eg)) / E_true[(60.0, "up")], "%", None)
    camp.write_manifest()
    return truth


SPECS = {
    "rlg-fine-fromzero": (
        Spec(),
        "ring-laser, K 20 000–200 000 P/° (0.18–0.018″ a pulse), reading resolution 0.001, 0.002, "
        "0.005 or 0.01″, ARW 1–4×10⁻⁴ °/√h, harmonics of orders 1–4 up to 0.15″, |κ₆₀| ≤ 0.3 ppm, "
        "residual bias ≤ 0.003 °/h, |η| ≤ 3×10⁻⁴, every stop turned to from 0° (the draft’s "
        "tables), turntable ±0.05–0.2″ uniform, declared parallelism 0.05–0.1° (tilt within it, "
        "any azimuth), latitude −85…85°"),
    "fog-coarse-reading": (
        Spec(K=(500, 3000), resolution=(0.2, 0.5, 1.0), arw=(2e-4, 8e-4), read_noise=(0.01, 0.05),
             orders=(1, 2, 3),
             harm_amp=(0, 0.3), technology="fibre", reading_unit="arcsec", zero_unit="arcsec",
             fmt="npy"),
        "fibre, K 500–3 000 P/° (7.2–1.2″ a pulse), reading rounded to 0.2, 0.5 or 1″, ARW "
        "2–8×10⁻⁴ °/√h, reading noise 0.01–0.05″, harmonics orders 1–3 up to 0.3″, readings in ″ "
        "columns, `.npy`"),
    "rlg-sequential-drifting": (
        Spec(layout="sequential", b0=0.01, eta=2e-3, b_g=0.005, zero=(15, 300.0), south_west=True,
             rates=(2.0, 5.0, 20.0, 60.0, 120.0, 180.0, 240.0, 300.0)),
        "stops in one run 30°, 60°, … 60 s each (`metro plan`'s wording; the last reading ≈ 12 min "
        "after zeroing), residual bias ≤ 0.01 °/h, |η| ≤ 2×10⁻³, g-dependent bias ≤ 0.005 °/h, 15 "
        "readings every 5 min for 7.3 (70 min), axes south and west, rates 2, 5, 20, 60, 120, 180, "
        "240, 300 °/s"),
    "rlg-tilted-harmonic": (
        Spec(parallelism=(0.08, 0.1), orders=(2, 3, 4, 5, 6, 8), harm_amp=(0.0, 0.5), kappa=1e-6,
             s_lin=1e-6,
             s_low=1e-6, tt_U=(0.1, 0.3), tt_dist="normal", zero=(16, 240.0)),
        "declared parallelism 0.08–0.1° (appendix A 1 asks for better than 0.1°; the tilt within "
        "it, at any azimuth), harmonics of orders 2–8 up to 0.5″, |κ₆₀| ≤ 1 ppm, rate dependence ≤ "
        "1 ppm, turntable certificate U 0.1–0.3″ (k = 2, normal), 16 readings every 4 min for 7.3"),
}


def _variant(name: str, spec: Spec, describe: str) -> Variant:
    return Variant(name, "ogam", "7.1,7.2,7.3,7.4,7.5,7.6,7.7", describe,
                   lambda f, rng, quick: build_ogam(f, rng, spec, quick))


VARIANTS = {name: _variant(name, spec, d) for name, (spec, d) in SPECS.items()}


def markdown(rows: list[dict], label: str = "") -> str:
    """The table of docs/independent-campaigns.md (ogam section) from the rows of one or more
    sweeps."""
    out = ["| variant | item | result | devices | not reportable | within U (or not reportable) | "
           "mean E_n | rms E_n | max abs E_n | B_s truth = this hour's own: within U, mean E_n |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    out += [IC.table_row(s, label=label) for s in summarise(rows)]
    return "\n".join(out)


def main(argv=None) -> int:
    return IC.cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-ogam-",
                  alt_label="this hour's own",
                  quick_help="fewer Monte Carlo draws for the noise truths",
                  table=lambda rows, a: markdown(rows, a.label),
                  add_arguments=lambda ap: ap.add_argument(
                      "--label", default="",
                      help="with --markdown: a prefix for the variant column"))

if __name__ == "__main__":
    sys.exit(main())

"""JJF 2014—2022 7.2.23: start-up time, decided where the output's noise lets it be.

The item's evaluation is a chain of steps, each a function below: the trials (7.2.23.1), each
record smoothed by the moving-average window with its noise and rounding bounds, the settled
value of a position trial, the interval in which each trial's settling is decided
(interpretations.md, "7.2.23 — a settling decided by noise"), where in it the crossing lies
("7.2.23 — where in the interval"), a ringing output decided by its samples ("7.2.23 — a ringing
output decided by its samples"), and the result with its budget (7.2.23.2: the largest trial's).
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Metric, Option,
                       Outcome, Result, Segment, SegmentRequirement, Step, TableSpec, join, msg)
from metro.api import settling as S

from . import budgets as B
from . import formulas as F
from .common import (RATE_OPTS, JJFItem, calibration_of, condition_in, need_segments, output_step,
                     quantity_text, read_output, scale_factor_for)
from .scale_factor import ScaleFactor

TRIALS = ("position", "rate")


@attrs.frozen
class Smoothed:
    """One power-on record (°/s) after the 7.2.23 moving-average window, with its noise and the
    rounding bounds of its digitised output."""

    t: np.ndarray  #: centre of each window, s from power-on
    r: np.ndarray  #: the window means, °/s
    dt: float  #: sampling interval, s
    sd: float  #: noise of one window mean, °/s
    k: int  #: samples per window
    raw: np.ndarray  #: the samples, °/s
    sd1: float  #: one sample's noise, °/s
    qw: float  #: rounding bound of a window mean, °/s
    q1: float  #: rounding bound of one sample, °/s


@attrs.frozen
class Trial:
    """One 7.2.23 trial: its record, the value it must reach, the tolerance and the target's u."""

    seg: Segment
    rec: Smoothed
    r: np.ndarray  #: window means about the target's reference (rate trials: less the zero)
    target: float
    tol: float
    ut: float  #: standard uncertainty of the target, °/s
    raw: np.ndarray  #: samples about the same reference


@attrs.frozen
class Decided:
    """Where one trial's settling was decided: between ``lo`` and ``hi`` (s), at ``est``; ``st``
    holds the sample exits when the samples decided it (a ringing output), else None."""

    lo: float
    hi: float
    est: float
    st: dict | None = None


def trial_segments(campaign: Campaign, proc) -> tuple[list[Segment], list[Segment], list[Segment]]:
    """The ``startup`` segments, and of them the position and the rate trials (7.2.23.1): every
    segment's ``trial`` is one of the two, and there is at least one position trial."""
    segs = need_segments(campaign, proc, "startup")
    for s in segs:
        if str(s.condition("trial")).strip().lower() not in TRIALS:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions.trial",
                            f"must be \"position\" or \"rate\" (7.2.23.1), "
                            f"got {s.condition('trial')!r}")
    pos = [s for s in segs if str(s.condition("trial")).strip().lower() == "position"]
    rat = [s for s in segs if str(s.condition("trial")).strip().lower() == "rate"]
    if not pos:
        raise DataError(campaign.source, "segments",
                        "7.2.23 needs at least one position trial (trial = position)")
    return segs, pos, rat


def smoothed(campaign: Campaign, s: Segment, win: float, K: float) -> Smoothed:
    """The record of ``s`` in °/s (÷ K) after the moving-average ``win`` the test is made on
    (7.2.23.2), the noise of a window mean and of one sample, and the bounds the output's step
    puts on each (interpretations.md, "7.2.23 — a settling decided by noise")."""
    x, dt = read_output(s)
    k = max(1, int(round(win / dt)))
    if x.size < 4 * k:
        raise DataError(s.file or s.id, "output", f"record too short for a {win:g} s window")
    c = np.convolve(x, np.ones(k) / k, mode="valid")
    t = (np.arange(c.size) + (k + 1) / 2.0) * dt  # centre of each window, from power-on
    d = np.diff(x)
    # the noise of one window mean, °/s, from the sample-to-sample differences (robust: the median
    # absolute deviation, which the transient's few large steps do not move)
    s1 = float(1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(2))
    # a rounded output's differences are mostly 0 or ±q, and their MAD can collapse to 0: the
    # differences' standard deviation over the settled last quarter (rounding included) is then
    # the larger
    s_q = float(np.std(d[-max(d.size // 4, 2):], ddof=1)) / math.sqrt(2)
    s1 = max(s1, s_q)
    sd = s1 / math.sqrt(k) / abs(K)
    # one sample's noise where the samples decide (a ringing output): the MAD of the record's
    # second half — over the whole record an output ringing at 0.2–2 Hz for a third of it puts its
    # own steps into the median (up to 4× the noise, and a last swing beyond the band within that
    # was not seen)
    dh = d[d.size // 2:]
    mad_h = float(1.4826 * np.median(np.abs(dh - np.median(dh))) / math.sqrt(2))
    sd1 = max(mad_h, s_q) / abs(K)
    # an output digitised to a step q: a window mean is off by up to the rounding's half-width
    # (±q/2 where the noise does not dither it — the differences' MAD then sees little or none of
    # it), one sample by up to q/2: both are added to the margins
    q, _src = output_step(campaign, [x])
    hw, _dith = F.rounding_half_width(q, s1)
    return Smoothed(t, c / K, dt, sd, k, x / K, sd1, hw / abs(K), q / 2.0 / abs(K))


def settled_value(rec: Smoothed) -> tuple[float, float]:
    """A position trial's settled value (°/s, its own target: the last quarter's mean) and its
    standard uncertainty; a slow tail still moving in the last quarter adds the drift seen there
    (half of it over the quarter) where the samples' slope is resolved from their noise."""
    r, raw, sd, k, dt = rec.r, rec.raw, rec.sd, rec.k, rec.dt
    last = r[int(0.75 * r.size):]
    settled = float(np.mean(last))
    u_set = sd * math.sqrt(k / max(last.size, 1))  # the last quarter's mean: ≈ last.size/k means
    rl = raw[int(0.75 * raw.size):]
    tl = dt * np.arange(rl.size)
    if rl.size >= 3:
        sxx = float(np.sum((tl - tl.mean()) ** 2))
        slope = float(np.sum((tl - tl.mean()) * (rl - rl.mean())) / sxx)
        if abs(slope) > 2.0 * sd * math.sqrt(k) / math.sqrt(sxx):
            u_set = math.hypot(u_set, abs(slope) * (tl[-1] - tl[0]) / 2.0)
    return settled, u_set


def build_trials(campaign: Campaign, pos: list[Segment], rat: list[Segment], win: float, K: float,
                 btol: float, rtol: float) -> list[Trial]:
    """The 7.2.23 trials: a position trial must stay within ±``btol`` of its settled value; a rate
    trial's output, less the position trials' mean zero, within ``rtol``·|Ω| of Ω."""
    trials = []
    zero, uzero = [], []
    for s in pos:
        rec = smoothed(campaign, s, win, K)
        settled, u_set = settled_value(rec)
        zero.append(settled)
        uzero.append(u_set)
        trials.append(Trial(s, rec, rec.r, settled, btol, u_set, rec.raw))
    z = float(np.mean(zero))
    uz = math.sqrt(sum(u * u for u in uzero)) / len(uzero)
    for s in rat:
        om = condition_in(s, "rate", "deg/s")
        rec = smoothed(campaign, s, win, K)
        trials.append(Trial(s, rec, rec.r - z, om, rtol * abs(om), uz, rec.raw - z))
    return trials


def window_interval(tr: Trial, win: float) -> tuple[str, float, float, np.ndarray, float, float]:
    """7.2.23.2's time of one trial from its window means, decided where the noise lets it be
    (interpretations.md, "7.2.23 — a settling decided by noise"): a window mean counts as outside
    the band only when outside by more than 2u (u: its noise and the target's), as inside only when
    inside by more than z_N·u, z_N the two-sided 95 % family-wise quantile over the N = (tail
    length)/window independent window means after the last clearly-outside one (at 2u each, one of
    ≈ 50 windows would be a false alarm almost surely).  Returns (why it cannot be decided, or "";
    the first time after the last clearly-outside mean; the first after the last not-clearly-inside
    one; the indices of the clearly-outside means; the settled output less the target; 2u)."""
    from scipy.stats import norm

    rec = tr.rec
    t, r, target, tol = rec.t, tr.r, tr.target, tr.tol
    m = 2.0 * math.hypot(rec.sd, tr.ut) + rec.qw
    dev = np.abs(r - target)
    out = np.flatnonzero(dev > tol + m)
    lo = float(t[min(out[-1] + 1, t.size - 1)]) if out.size else float(t[0])
    n_tail = max(1.0, (float(t[-1]) - lo) / win)
    z_in = max(2.0, float(norm.isf(0.025 / n_tail)))
    m_in = z_in * math.hypot(rec.sd, tr.ut) + rec.qw
    if not tol - m > 0:
        return msg("{id}: the output's noise and its target's uncertainty (2u = {m:.3g} °/s over "
                   "the {w:g} s window) are as large as the tolerance ±{tol:.3g} °/s, so whether "
                   "it is inside cannot be decided",
                   id=tr.seg.id, m=m, w=win, tol=tol), lo, lo, out, math.nan, m
    # the settled output (the last quarter's mean; for a position trial its own target) must be
    # inside the band by more than the window means' z_N·u, or the tail's windows cannot tell it
    # from the band's edge
    settled = float(np.mean(r[int(0.75 * r.size):])) - target
    if not tol - abs(settled) - m_in > 0:
        return msg("{id}: the output's noise and its target's uncertainty ({z:.2g}u = {m:.3g} °/s "
                   "over the {w:g} s window, {z:.2g} for the {n:.0f} window means after it left "
                   "the band) are as large as the settled output's margin to the band's edge "
                   "({g:.3g} °/s of ±{tol:.3g} °/s), so when it stays inside cannot be decided",
                   id=tr.seg.id, z=z_in, m=m_in, w=win, n=n_tail, g=tol - abs(settled),
                   tol=tol), lo, lo, out, settled, m
    # the end of the record is one test (2u, 95 %); the scan of the tail a family of n_tail (z_N·u)
    if dev[-1] >= tol - m:
        return msg("{id}: the output is not inside ±{tol:.3g} °/s of {target:.4g} °/s (less 2u = "
                   "{m:.3g} °/s of noise) at the end of the record ({end:.3g} s): it has not "
                   "settled, or not resolvably",
                   id=tr.seg.id, tol=tol, target=target, m=m,
                   end=float(t[-1])), lo, lo, out, settled, m
    notin = np.flatnonzero(dev >= tol - m_in)
    hi = float(t[min(notin[-1] + 1, t.size - 1)]) if notin.size else float(t[0])
    return "", lo, hi, out, settled, m


def exponential_crossing(tr: Trial, lo: float, hi: float, out: np.ndarray, settled: float,
                         m: float) -> float:
    """Where in [lo, hi] the trial's output crosses the band's edge (interpretations.md, "7.2.23 —
    where in the interval"): the settled value's distance g to the edge the output approached; an
    exponential approach e^(−t/τ) to the settled value is g + m from it at lo and crosses the edge
    τ·ln((g + m)/g) later; τ from the last e-fold before lo, where the output is clearly resolved
    (e·(g + m) to g + m).  The interval's middle where that cannot be seen."""
    est = (lo + hi) / 2.0
    t, r, target, tol = tr.rec.t, tr.r, tr.target, tr.tol
    if hi > lo and out.size:
        side = 1.0 if r[out[-1]] > target else -1.0
        g = tol - side * settled
        above = (np.flatnonzero(side * (r - target - settled) > math.e * (g + m)) if g > 0
                 else out[:0])
        if above.size and lo > float(t[above[-1] + 1]):
            tau = lo - float(t[above[-1] + 1])
            est = min(max(lo + tau * math.log((g + m) / g), lo), hi)
    return est


def ringing_exits(tr: Trial, lo: float, settled: float, win: float) -> tuple[str, dict | None]:
    """An output ringing faster than the window (interpretations.md, "7.2.23 — a ringing output
    decided by its samples"): the window means average its swings away, the samples show them.
    Their lobes about the settled value (:mod:`metro.api.settling`, as GB/T 6.2.7.7's) each have
    the probability that the noise-free output left the band in it, and the start-up is the
    expected last real exit.  Returns ("", None) when the output does not ring, (why, None) when
    the samples cannot decide, else ("", the sample exits of ``F.startup_sample_exits``)."""
    from scipy.stats import norm

    rec = tr.rec
    target, tol, ut, sd1, q1, dt, raw = tr.target, tr.tol, tr.ut, rec.sd1, rec.q1, rec.dt, tr.raw
    m1 = 4.5 * math.hypot(sd1, ut) + q1
    ts = dt * np.arange(1, raw.size + 1)  # sample j at (j + 1)·dt from power-on
    rdev = np.abs(raw - target)
    # the band about the settled value (its edges differ where a rate trial settles off Ω); a
    # rounding that the noise does not dither is common to a lobe's samples (uniform ±q/2)
    s_common = math.hypot(ut, q1 / math.sqrt(3.0) if sd1 < q1 else 0.0)
    s_p = math.hypot(sd1, s_common)
    lobes = S.excursion_lobes(raw - target - settled, ts, dt, 1, tol - settled, tol + settled, sd1,
                              s_common, half_lobe_fit=True)
    i_lo = int(np.searchsorted(ts, lo))
    z_ring = float(norm.isf(0.025 / max(raw.size - i_lo, 1)))
    # ringing: a sample clearly outside after the window means settle, or — where one sample's
    # noise lets the samples decide at all — a swing past the settled value to the other side than
    # the one the output approached from, beyond the tail's family-wise noise
    side = next((lb.sign for lb in lobes if lb.start <= i_lo < lb.end), 0)
    ringing = (np.any((rdev > tol + m1) & (ts >= lo))
               or (tol - m1 > 0
                   and any(lb.start >= i_lo and lb.sign != side and lb.top > z_ring * s_p
                                        for lb in lobes)))
    if not ringing:
        return "", None
    st = F.startup_sample_exits(raw - target - settled, ts, dt, tol - settled, tol + settled, s_p,
                                lobes, S.last_exit(lobes, float(ts[0])))
    late = [e for e, pr in zip(st["lobe_exits"], st["lobe_probabilities"])
            if pr > 0.01 and e > ts[int(0.75 * ts.size)]]
    if not tol - m1 > 0 or late:
        return msg("{id}: the output rings faster than the {w:g} s window (samples outside "
                   "±{tol:.3g} °/s after the window means settle) and one sample's noise (4.5u = "
                   "{m:.3g} °/s) does not let the samples decide",
                   id=tr.seg.id, w=win, tol=tol, m=m1), None
    return "", st


def decide_trial(tr: Trial, win: float) -> tuple[str, float, Decided | None]:
    """One trial's start-up time (7.2.23.2): (why it cannot be decided or "", the plain crossing
    of ``F.settle_time`` for the table, where it was decided or None)."""
    try:
        plain = F.settle_time(tr.rec.t, tr.r, tr.target, tr.tol)
    except ValueError:
        plain = math.nan
    why, lo, hi, out, settled, m = window_interval(tr, win)
    if why:
        return why, plain, None
    est = exponential_crossing(tr, lo, hi, out, settled, m)
    why, st = ringing_exits(tr, lo, settled, win)
    if why:
        return why, plain, None
    if st is not None:
        return "", plain, Decided(st["t"] - st["d95"], st["t"] + st["d95"], st["t"], st)
    return "", plain, Decided(lo, hi, est)


def sampling_row(half: float) -> BudgetRow:
    """The crossing lies within one sampling interval (or the trials' largest): ±Δt/2 uniform."""
    return BudgetRow.type_b("sampling: the crossing lies within one interval", "Δt/2",
                            Q_(half, "s"), distribution="uniform")


def noise_rows(lo: float, hi: float, ts: float) -> list[BudgetRow]:
    """The settling decided between ``lo`` and ``hi`` (uniform), and the crossing ``ts``'s offset
    from the interval's middle (the second moment about the result is the uniform's variance plus
    the offset squared)."""
    rows = []
    if hi > lo:
        rows.append(BudgetRow.type_b(msg("the settling decided from the output's noise (outside at "
                                         "2u, inside at the window means' family-wise 95 %): "
                                         "between {lo:.3g} s and {hi:.3g} s", lo=lo, hi=hi),
                                     "Δt_{noise}/2", Q_((hi - lo) / 2, "s"),
                                     distribution="uniform"))
        off = abs(ts - (lo + hi) / 2.0)
        if off > 1e-3 * (hi - lo):
            rows.append(BudgetRow.type_b(msg("the crossing of an exponential approach, {off:.3g} s "
                                             "from the interval's middle", off=off), "δt_mid",
                                         Q_(off, "s"), distribution="normal", k=1.0))
    return rows


# =============================================================================== 7.2.23


class StartupTime(JJFItem):
    """JJF 2014—2022 7.2.23 启动时间: position trials (time until the output reaches the required
    bias: stays within ± bias_tolerance of its settled value) and rate trials (calibrated output
    within rate_tolerance of KΩ); the start-up time is the largest of all (7.2.23.2)."""

    item = "7.2.23"
    title = "Start-up time (启动时间)"
    clause = "7.2.23"
    metrics = (Metric("t_startup", "start-up time", "t_s", "s", "7.2.23.2",
                      "prose, no eq. number"),)
    requires = (SegmentRequirement("startup", "power-on records: trial = position (at rest) or "
                                              "rate (table at Ω)",
                                   {"trial": "", "rate": "deg/s", "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (
        Option("bias_tolerance", "0.05 deg/s", "deg/s", "required bias band (position trials)"),
        Option("rate_tolerance", "1 %", "", "rate error requirement, relative (rate trials)"),
        Option("window", "1 s", "s", "moving-average window applied before the test"),
        Option("full_scale", "100 deg/s", "deg/s", "full-scale rate for the rate trials"))
    equipment = JJFItem.equipment + (EquipmentRequirement("timer", "timer / time base",
                                                          calibration=("",)),)

    def sequence(self, options):
        fs = float(options["full_scale"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for q in (1, 2, 3):
            steps.append(Step(f"startup-position#{q}", "startup",
                              f"power on at rest, run {q}, 60 s at 0.1 s",
                              Q_(60, "s"), Q_(0.1, "s"),
                              {"trial": "position", "rate": "0 deg/s", "run": str(q)}))
        for frac in (1.0, 0.1, 0.01):
            steps.append(Step(f"startup-rate{frac:g}FS", "startup",
                              f"power on with the table at {frac * fs:g} °/s",
                              Q_(60, "s"), Q_(0.1, "s"),
                              {"trial": "rate", "rate": quantity_text(frac * fs, "deg/s"),
                               "run": "1"}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        segs, pos, rat = trial_segments(campaign, type(self))
        btol = float(opts["bias_tolerance"].to("deg/s").magnitude)
        rtol = float(opts["rate_tolerance"].to("").magnitude)
        win = float(opts["window"].to("s").magnitude)
        trials = build_trials(campaign, pos, rat, win, kv.K, btol, rtol)
        why: list[str] = []
        table = []  # (segment, target, tol, plain, lo, hi)
        lo_hi = []  # (lo, hi, segment, dt, estimate, sample exits or None)
        for tr in trials:
            reason, plain, d = decide_trial(tr, win)
            if reason:
                why.append(reason)
                table.append((tr.seg, tr.target, tr.tol, plain, math.nan, math.nan))
                continue
            lo_hi.append((d.lo, d.hi, tr.seg, tr.rec.dt, d.est, d.st))
            table.append((tr.seg, tr.target, tr.tol, plain, d.lo, d.hi))
        tab = self._table(table)
        if why:
            return self._undecided_outcome(trials, table, why, tab, segs, opts)
        # the start-up time is the largest trial's: between the largest lo and the largest hi, at
        # the largest trial's crossing
        best = max(lo_hi, key=lambda x: x[4])
        if best[5] is not None:
            return self._ringing_outcome(campaign, best, [x for x in lo_hi if x is not best], tab,
                                         segs, opts)
        return self._decided_outcome(campaign, best, lo_hi, tab, segs, opts)

    @staticmethod
    def _table(table: list) -> TableSpec:
        """The start-up time per trial: its target, tolerance, plain crossing and decided
        interval."""
        return TableSpec("startup", msg("Start-up time per trial"),
                         [msg("trial"), msg("segment"), msg("target"), msg("tolerance"), "t (s)",
                          msg("decided within (s)")],
                         [[str(x[0].condition("trial")), x[0].id, f"{x[1]:.4g} °/s",
                           f"{x[2]:.3g} °/s",
                           f"{x[3]:.2f}", f"{x[4]:.2f} … {x[5]:.2f}"] for x in table])

    def _undecided_outcome(self, trials, table, why, tab, segs, opts) -> Outcome:
        """A trial the noise cannot decide: the largest plain crossing, not reportable, with why."""
        plains = [x[3] for x in table if math.isfinite(x[3])]
        ts = max(plains) if plains else float(max(tr.rec.t[-1] for tr in trials))
        rows = [sampling_row(max(tr.rec.dt for tr in trials) / 2)]
        b = B.type_a_budget("t_startup", "s", rows)
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, reportable=False,
                                     reason=join("; ", why))],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)

    def _decided_outcome(self, campaign, best, lo_hi, tab, segs, opts) -> Outcome:
        """The start-up time decided by the window means (7.2.23.2: the largest trial's), with the
        sampling, noise-interval, crossing-offset and timer rows."""
        lo = max(x[0] for x in lo_hi)
        hi = max(x[1] for x in lo_hi)
        s, dt, est = best[2:5]
        ts = min(max(est, lo), hi)
        rows = [sampling_row(dt / 2)] + noise_rows(lo, hi, ts)
        rows += B.relative_calibration_row("timer", "u_rel(t)", calibration_of(campaign, "timer"),
                                           Q_(ts, "s"))
        b = B.type_a_budget("t_startup", "s", rows)
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b,
                                     note=msg("largest in {id}", id=s.id))],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)

    def _ringing_outcome(self, campaign, best, others, tab, segs, opts) -> Outcome:
        """The start-up time where the largest trial's samples decided it (an output ringing faster
        than the window): the expected last real exit with the spread of the candidates' exits
        (normal), their noise re-crossings (uniform) and, where another trial's interval reaches
        later, the rest of that interval."""
        _lo, _hi, s, dt, ts, st = best
        rows = [sampling_row(dt / 2)]
        # U reaches the candidates holding 95 % of the probability
        u_sel = max(st["u_selection"], st["d95"] / 2.0)
        if u_sel > 0:
            rows.append(BudgetRow.type_b(
                msg("which excursion beyond the band is the last real one (spread of the "
                    "candidates' exits)"),
                "u_sel", Q_(u_sel, "s"), distribution="normal", k=1.0,
                note=msg("exits {exits} s with probabilities {probs}",
                         exits=", ".join(f"{e:.4g}" for e in st["lobe_exits"]),
                         probs=", ".join(f"{p:.2f}" for p in st["lobe_probabilities"]))))
        hi_other = max((x[1] for x in others), default=-math.inf)
        if hi_other > ts:
            rows.append(BudgetRow.type_b(msg("another trial's settling is decided up to {hi:.3g} s",
                                             hi=hi_other),
                                         "Δt_other/2", Q_((hi_other - ts) / 2, "s"),
                                         distribution="uniform"))
        rows += B.relative_calibration_row("timer", "u_rel(t)", calibration_of(campaign, "timer"),
                                           Q_(ts, "s"))
        b = B.type_a_budget("t_startup", "s", rows)
        note = msg("largest in {id}, decided by its samples: the output rings faster than the "
                   "window",
                   id=s.id)
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, note=note)],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)

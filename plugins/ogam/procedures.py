"""Draft JJF 光学陀螺测角仪校准规范 items 7.1–7.7 as metro procedures.

Each class is one item; formulas live in :mod:`.formulas`.  Data (docs/standards/ogam.md):

* ``scale-factor`` segments (7.1, 7.2): one row per round, columns ``angle`` (θ_i, the
  standard angular displacement) and ``counts`` (C_i, in P);
* ``zero`` segments (7.3): one row per reading, column ``reading`` (an angle), read every
  ``sample_interval`` (5 min) for 1 h;
* ``positioning`` segments (7.4–7.7): one round of the 7.4 table, one row per stop, columns
  ``standard`` (S_i) and ``reading`` (M_i); conditions ``rate`` (°/s), ``axis``
  (up/north/south/east/west) and ``round`` (1, 2, …).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, Metric, Option, Outcome, PlotSpec,
                       ProcedureError, Result, RunContext, Step, TableSpec, UncertaintyBudget, join,
                       msg, std_sampling_u)

from . import formulas as F
from .common import (AXES, COVERAGE_NU, RATES, REF_RATE, ROUNDS, SCALE, STANDARD, ZERO, OgamItem,
                     PositionErrorItem, ScaleFactorItem, column_of, disclosed, e_budget,
                     error_matrix, pos_step, positioning_group, positioning_groups, positioning_row,
                     reading_step_of, round_errors, rounds_at_reference)

# ------------------------------------------------------------------------------ 7.1 and 7.2


def _scale_factors(campaign: Campaign, item: str):
    segs = campaign.find_segments("scale-factor")
    if not segs:
        raise DataError(campaign.source, "segments",
                        f"{item} needs a segment of kind \"scale-factor\" ({SCALE.description}); "
                        "none found",
                        hint=f"`metro plan -s ogam -i {item}` shows what to measure")
    seg = segs[0]
    theta = column_of(seg, "angle", "deg")
    counts = column_of(seg, "counts", "P")
    if theta.size < 2:
        raise DataError(seg.file or f"segment {seg.id}", "angle", "7.1 needs several rounds (six)")
    if np.any(theta <= 0):
        raise DataError(seg.file or f"segment {seg.id}", "angle",
                        "every angular displacement θ_i must be positive")
    return seg, theta, counts, F.scale_factors_71(counts, theta)


class ScaleFactor71(ScaleFactorItem):
    """Draft JJF 光学陀螺测角仪 7.1 标度因数 (scale factor): K_i = C_i/θ_i, K = (1/6)ΣK_i.

    Budget: scatter of the K_i (type A, s/√n, ν = n − 1), the turntable positioning error,
    which changes each θ_i (type B; sensitivity of the mean, sqrt(Σ(K_i/θ_i)²)/n per ″), and
    the counting of the C_i: ±1 count, triangular — the counter is zeroed and read at arbitrary
    phases of the pulse train, two independent ±0.5 count roundings (interpretations.md, "7.1 / 7.2
    — a count is ±1 count"); sensitivity sqrt(Σθ_i⁻²)/n.
    """

    item = "7.1"
    title = "Scale factor (标度因数)"
    clause = "7.1"
    metrics = (Metric("K", "scale factor", "K", "P/deg", "7.1", "K = ΣK_i/6, K_i = C_i/θ_i"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg, theta, counts, k_i = _scale_factors(campaign, self.item)
        K = F.scale_factor_71(k_i)
        warnings: list[str] = []
        n = k_i.size
        if n != 6:
            warnings.append(msg("{n} rounds; clause 7.1 asks for six (60°…360°)", n=n))
        sens = math.sqrt(float(np.sum((k_i / (theta * F.ARCSEC_PER_DEG)) ** 2))) / n
        rows = [
            BudgetRow.type_a(msg("scatter of the rounds' K_i"), "s(K_i)/√n",
                             Q_(float(np.std(k_i, ddof=1)) / math.sqrt(n), "P/deg"), n - 1,
                             note=msg("{n} rounds", n=n)),
            attrs_evolve_sensitivity(positioning_row(campaign, warnings), Q_(sens, "P/deg/arcsec")),
            BudgetRow.type_b(msg("counting of the C_i (±1 count, triangular: a counter zeroed and "
                                 "read at any phase of the pulses)"),
                             "u(C)", Q_(1.0, "P"), distribution="triangular",
                             sensitivity=Q_(math.sqrt(float(np.sum(theta ** -2.0))) / n, "1/deg"),
                             note=msg("each K_i = C_i/θ_i, independent roundings")),
        ]
        budget = UncertaintyBudget("K", "P/deg", rows, coverage=COVERAGE_NU)
        res = Result(self.metrics[0], Q_(K, "P/deg"), budget.combined, budget)
        table = TableSpec("k_rounds", msg("Scale factor per round (7.1)"),
                          [msg("round"), "θ_i (°)", "C_i (P)", "K_i (P/°)"],
                          [[i + 1, f"{theta[i]:g}", f"{counts[i]:.0f}", f"{k_i[i]:.6f}"]
                           for i in range(n)])
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)],
                       tables=[table], warnings=warnings,
                       segments=[seg.id], options={k: str(v) for k, v in opts.items()})


def attrs_evolve_sensitivity(row: BudgetRow, sensitivity) -> BudgetRow:
    """The same budget row with another sensitivity coefficient."""
    return attrs.evolve(row, sensitivity=sensitivity)


#: 7.2: Monte Carlo draws of the K_i's noise (GUM Supplement 1; a fixed seed keeps a run
#: reproducible)
KL_DRAWS = 4000
KL_SEED = 72


def _draw(row: BudgetRow, unit: str, size: tuple[int, int], rng: np.random.Generator) -> np.ndarray:
    """Draws of the error a budget row describes, in ``unit``, by its distribution (a half-width
    for uniform/triangular/arcsine, else normal with the row's standard uncertainty)."""
    a = float(row.value.to(unit).magnitude)
    if row.distribution in ("uniform", "rectangular"):
        return rng.uniform(-a, a, size)
    if row.distribution == "triangular":
        return rng.triangular(-a, 0.0, a, size)
    if row.distribution == "arcsine":
        return a * np.sin(2.0 * math.pi * rng.uniform(0.0, 1.0, size))
    return rng.normal(0.0, float(row.standard_uncertainty.to(unit).magnitude), size)


def linearity_noise(campaign: Campaign, theta_deg: np.ndarray, K: float, warnings: list[str]
                    ) -> tuple[np.ndarray, str]:
    """Draws (KL_DRAWS × rounds) of the relative errors of the K_i = C_i/θ_i, and what they hold.

    Each K_i errs by δφ_i/θ_i: the turntable positioning at the stop (its calibration), the count
    counting (±1 count = 1/K of a degree, triangular: zeroed and read at any phase) and, when the
    campaign has the 7.5 rounds at 60 °/s with the axis up, the angle repeatability R of 7.5 in
    place of the positioning when larger (R holds the positioning, the reading noise and the random
    walk of a stop)."""
    rng = np.random.default_rng(KL_SEED)
    size = (KL_DRAWS, theta_deg.size)
    pos = positioning_row(campaign, warnings)
    what = msg("turntable positioning ({distribution}, u = {u:.3g}″)",
               distribution=pos.distribution,
               u=pos.standard_uncertainty.to('arcsec').magnitude)
    ang = _draw(pos, "arcsec", size, rng)
    rounds = positioning_groups(campaign).get((REF_RATE, "up"), [])
    if len(rounds) >= 2:
        R, _ = F.repeatability_75(error_matrix(rounds)[1])
        if R > float(pos.standard_uncertainty.to("arcsec").magnitude):
            ang = rng.normal(0.0, R, size)
            what = msg("angle repeatability R = {R:.3g}″ of 7.5 ({n} rounds; holds the "
                       "positioning)", R=R, n=len(rounds))
    else:
        what = join("; ", [what, msg("no 7.5 rounds: the reading noise and random walk of a stop "
                                     "are not in it")])
    count = 1.0 / K * F.ARCSEC_PER_DEG
    ang = ang + rng.triangular(-count, 0.0, count, size)
    counting = msg("counting ±1 count (triangular) = ±{c:.3g}″", c=count)
    return ang / (theta_deg * F.ARCSEC_PER_DEG), join("; ", [what, counting])


class Linearity72(ScaleFactorItem):
    """Draft JJF 光学陀螺测角仪 7.2 标度因数线性度 (scale-factor linearity):
    K_l = (max K_i − min K_i)/K, in %, corrected for the widening of a range by the K_i's noise.

    The printed range reads high: the noise of the six K_i (positioning, count rounding, the angle
    repeatability of 7.5) can only widen it.  metro reports the instrument's own range, the printed
    one less the expected widening found by moment matching over Monte Carlo draws of that noise
    (:func:`.formulas.linearity_72_moment_matched`; interpretations.md, "7.2 — K_l is a range of
    noisy K_i"); the printed value is in the note.  Budget: the spread of the range over the draws
    and the correction, uncertain by its own size (both type B, normal).
    """

    item = "7.2"
    title = "Scale-factor linearity (标度因数线性度)"
    clause = "7.2"
    metrics = (Metric("Kl", "scale-factor linearity", "K_l", "percent", "7.2",
                      "K_l = (max K_i − min K_i)/K, less the widening by the K_i's noise"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg, theta, _counts, k_i = _scale_factors(campaign, self.item)
        warnings: list[str] = []
        K = F.scale_factor_71(k_i)
        noise, what = linearity_noise(campaign, theta, K, warnings)
        est = F.linearity_72_moment_matched(k_i, noise)
        pct = 100.0
        rows = [BudgetRow.type_b(msg("noise of the K_i: spread of their range"), "s(K_l)",
                                 Q_(est.spread * pct, "percent"),
                                 distribution="normal", k=1.0,
                                 note=msg("Monte Carlo, {n} draws of {what}", n=KL_DRAWS,
                                          what=what)),
                BudgetRow.type_b(msg("correction for the widening of the range by that noise, "
                                     "uncertain by its own size"),
                                 "u(δ)", Q_(est.inflation * pct, "percent"), distribution="normal",
                                 k=1.0,
                                 note=msg("δ = {d:.3g} % (moment matched; the noise alone gives "
                                          "{n:.3g} % on average)",
                                          d=est.inflation * pct, n=est.noise_only * pct))]
        budget = UncertaintyBudget("K_l", "percent", rows, coverage=COVERAGE_NU)
        i_max, i_min = int(np.argmax(k_i)), int(np.argmin(k_i))
        note = msg("as printed (max K_i − min K_i)/K = {printed:.3g} % (max K_i at θ = {max:g}°, "
                   "min at θ = {min:g}°), less its widening by the K_i's noise, {d:.3g} %",
                   printed=est.printed * pct, max=theta[i_max],
                   min=theta[i_min], d=est.inflation * pct)
        if est.estimate == 0.0:
            note = join("; ", [note, msg("not resolved from 0: the noise alone gives a range of "
                                         "{n:.3g} % on average, no less than the one observed",
                                         n=est.noise_only * pct)])
        res = Result(self.metrics[0], Q_(est.estimate * pct, "percent"), budget.combined, budget,
                     note=note)
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)],
                       warnings=warnings, segments=[seg.id],
                       options={k: str(v) for k, v in opts.items()})


# ------------------------------------------------------------------------------------ 7.3


class ZeroStability73(OgamItem):
    """Draft JJF 光学陀螺测角仪 7.3 零位稳定性 (zero stability) B_s, °/h.

    B_s = s(M_n)/T (clause 7.3: Bessel standard deviation over the duration T); with
    ``statistic=range`` the definition 3.3 reading (max − min)/T.  T = (n − 1)·Δt, the time
    the readings span.  Type A: sampling of a standard deviation of n values, B_s/√(2(n−1)).
    """

    item = "7.3"
    title = "Zero stability (零位稳定性)"
    clause = "7.3"
    metrics = (Metric("Bs", "zero stability", "B_s", "deg/h", "7.3", "B_s = s(M)/T"),)
    requires = (ZERO,)
    options = (Option("statistic", "std", None,
                      "std (clause 7.3, default) or range (definition 3.3)"),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("zero-1h", "zero",
                     "instrument at rest on a stable platform, sensitive axis vertical; warm up "
                     "1 h, then read the angle every 5 min for 1 h (7.3)", Q_(1, "h"), Q_(5, "min"),
                     {"axis": "up"}, warmup=Q_(1, "h"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        stat = str(opts["statistic"]).strip().lower()
        if stat not in ("std", "range"):
            raise ProcedureError(f"7.3: option statistic must be std or range, got {stat!r}")
        segs = campaign.find_segments("zero")
        if not segs:
            raise DataError(campaign.source, "segments",
                            f"7.3 needs a segment of kind \"zero\" ({ZERO.description})",
                            hint="`metro plan -s ogam -i 7.3` shows what to measure")
        seg = segs[0]
        m = column_of(seg, "reading", "deg")
        if m.size < 3:
            raise DataError(seg.file or f"segment {seg.id}", "reading",
                            f"{m.size} readings; 7.3 needs at least 3")
        T_h = (m.size - 1) * float(seg.interval.to("h").magnitude)
        Bs = F.zero_stability_73(m, T_h, stat)
        warnings = []
        if abs(T_h - 1.0) > 1e-6:
            warnings.append(msg("the readings span {minutes:g} min; clause 7.3 asks for 1 h",
                                minutes=T_h * 60))
        n = m.size
        if not Bs > 0:
            # every reading the same: the hour's drift is below the reading's resolution (or the
            # instrument is not running); only this result is lost, not the run
            # (interpretations.md, "7.3 — readings that do not move")
            res = Result(self.metrics[0], Q_(0.0, "deg/h"), reportable=False, reason=msg(
                "the {n} readings do not vary at all: the drift over the hour is below the "
                "reading's resolution (or the instrument is not running), so B_s is not measured",
                n=n))
            return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)],
                           warnings=warnings,
                           segments=[seg.id], options={k: str(v) for k, v in opts.items()})
        rows = [BudgetRow.type_a(msg("sampling of the standard deviation of {n} readings", n=n)
                                 if stat == "std" else
                                 msg("sampling of the range of {n} readings", n=n), "B_s/√(2(n−1))",
                                 Q_(Bs / math.sqrt(2 * (n - 1)), "deg/h"), n - 1)]
        budget = UncertaintyBudget("B_s", "deg/h", rows, coverage=COVERAGE_NU)
        other = F.zero_stability_73(m, T_h, "range" if stat == "std" else "std")
        res = Result(self.metrics[0], Q_(Bs, "deg/h"), budget.combined, budget,
                     note=msg("{n} readings over {minutes:g} min; range reading {other:.3g} °/h",
                              n=n,
                              minutes=T_h * 60, other=other) if stat == "std" else
                     msg("{n} readings over {minutes:g} min; std reading {other:.3g} °/h", n=n,
                         minutes=T_h * 60,
                         other=other))
        # interpretations.md, "7.3 — B_s is this hour's": what U covers, said where the number is
        res = attrs.evolve(res, note=join("; ", [res.note, msg(
            "this hour's zero stability: U holds the readout and the sampling of the readings, not "
            "the spread from one hour to another of an instrument whose rate wanders")]))
        plot = PlotSpec("zero", msg("Readings at rest (7.3)"), "t (min)", "M (″)",
                        [{"label": "M_n", "x": (np.arange(n) * T_h * 60 / (n - 1)).tolist(),
                          "y": (m * F.ARCSEC_PER_DEG).tolist(), "style": "o-"}])
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)], plots=[plot],
                       warnings=warnings,
                       segments=[seg.id], options={k: str(v) for k, v in opts.items()})


# ------------------------------------------------------------------------------ 7.4 and 7.5


class PositionError74(PositionErrorItem):
    """Draft JJF 光学陀螺测角仪 7.4 角位置测量偏差 (angle-position error): E_i = M_i − S_i,
    E = ± max|E_i|, with the appendix A budget: turntable positioning (4.1), the simulated
    sensing-plane tilt (4.2, eqs. (2)–(5)), zero drift (4.3) and repeatability (4.4);
    u_c as appendix A 7, U = 2·u_c (A 8).  E is taken from the first round unless ``round``
    is given (7.4 is one round; 7.5 repeats it).
    """

    item = "7.4"
    title = "Angle-position error (角位置测量偏差)"
    clause = "7.4"
    metrics = (Metric("E", "angle-position error", "E", "arcsec", "7.4",
                      "E = ±max|E_i|; appendix A"),)
    options = PositionErrorItem.options + (
        Option("round", None, None, "the round whose E_i give E (default: the first)"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        warnings: list[str] = []
        S, E, rounds, _R, R_i, rows, sim = self._reference(campaign, opts, warnings)
        rnums = [r for r, _ in rounds]
        try:
            want = rnums[0] if opts["round"] is None else int(str(opts["round"]))
        except ValueError:
            raise DataError(None, "option round", f"{opts['round']!r} is not a round number",
                            hint=f"the rounds recorded: {', '.join(map(str, rnums))}") from None
        if want not in rnums:
            raise ProcedureError(f"7.4: no round {want} at 60 °/s axis up; rounds: {rnums}")
        e_i = E[rnums.index(want)]
        Emax = F.position_error_74(e_i)
        j = int(np.argmax(np.abs(e_i)))
        budget = e_budget(rows)
        res = Result(self.metrics[0], Q_(Emax, "arcsec"), budget.combined, budget,
                     note=msg("reported as ±{E:.3g}″; largest |E_i| at S = {S:g}° (E_i = "
                              "{Ei:+.3f}″), round {round}",
                              E=Emax, S=S[j], Ei=e_i[j], round=want))
        if reading_step_of(campaign, E)[0] == 0.0:
            res = attrs.evolve(res, reportable=False, reason=msg(
                "every reading of every round is the same E_ij: the reading's resolution, which "
                "bounds the error, cannot be seen in the data"))  # nor in a 7.3 record
        plot = PlotSpec("E_i", msg("Angle-position error per position (7.4)"), "S (°)", "E_i (″)",
                        [{"label": msg("round {r}", r=r), "x": S.tolist(), "y": E[k].tolist(),
                          "style": "o-" if r == want else ":"} for k, r in enumerate(rnums)])
        tilt = PlotSpec("tilt",
                        msg("Simulated tilt error, ψ = {psi:g}° (appendix A 4.2)", psi=sim.psi_deg),
                        "θ (°)", "Δ(θ) (″)",
                        [{"label": "Δ(θ) = θ_ψ − θ", "x": sim.theta_deg[::40].tolist(),
                          "y": sim.error_arcsec[::40].tolist(), "style": "-"}])
        table = TableSpec("E_i", msg("E_i and R_i per calibration point"),
                          ["i", "S_i (°)", "E_i (″)", "R_i (″)"],
                          [[i + 1, f"{S[i]:g}", f"{e_i[i]:+.3f}", f"{R_i[i]:.3f}"]
                           for i in range(S.size)])
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)],
                       plots=[plot, tilt], tables=[table],
                       warnings=warnings, segments=[s.id for _, s in rounds],
                       options={k: str(v) for k, v in opts.items()})


class Repeatability75(PositionErrorItem):
    """Draft JJF 光学陀螺测角仪 7.5 角位置测量重复性 (repeatability): R_i = Bessel standard
    deviation of E_ij over the 10 rounds, R = max R_i.  Type A: R/√(2(n−1)), ν = n − 1.
    """

    item = "7.5"
    title = "Angle-position repeatability (角位置测量重复性)"
    clause = "7.5"
    metrics = (Metric("R", "angle-position repeatability", "R", "arcsec", "7.5", "R = max R_i"),)
    options = ()

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        rounds = positioning_group(campaign, REF_RATE, "up", self.item)
        S, E = error_matrix(rounds)
        warnings = []
        if E.shape[0] < 2:
            raise DataError(campaign.source, "segments",
                            f"7.5 needs the 7.4 test repeated; found {E.shape[0]} round")
        if E.shape[0] < ROUNDS:
            warnings.append(msg("{n} rounds; clause 7.5 asks for {rounds}", n=E.shape[0],
                                rounds=ROUNDS))
        R, R_i = F.repeatability_75(E)
        n = E.shape[0]
        budget = UncertaintyBudget("R", "arcsec", [BudgetRow.type_a(
            msg("sampling of a standard deviation of {n} rounds (χ² bound)", n=n),
                                                                    "(s_{upper} − R)/2",
            Q_(std_sampling_u(R, n), "arcsec"), math.inf)], coverage=COVERAGE_NU)
        j = int(np.argmax(R_i))
        res = Result(self.metrics[0], Q_(R, "arcsec"), budget.combined, budget,
                     note=msg("largest at S = {S:g}°", S=S[j]))
        if R == 0.0:
            # every round read the same at every stop: the spread is below the reading's
            # resolution, and a standard deviation of 0 with U = 0 would be a confident wrong
            # number (issue 13)
            res = attrs.evolve(res, reportable=False, reason=msg(
                "every round read the same at every stop: the repeatability is below the reading "
                "resolution and is not resolved by {n} rounds", n=n))
        plot = PlotSpec("R_i", msg("Repeatability per position (7.5)"), "S (°)", "R_i (″)",
                        [{"label": "R_i", "x": S.tolist(), "y": R_i.tolist(), "style": "o-"}])
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)], plots=[plot],
                       warnings=warnings,
                       segments=[s.id for _, s in rounds],
                       options={k: str(v) for k, v in opts.items()})


# ------------------------------------------------------------------------------ 7.6 and 7.7


def _consistency(proc: PositionErrorItem, campaign: Campaign, opts,
                 groups_wanted: list[tuple[float, str]],
                 ref: tuple[float, str], label):
    """(C in %, budget rows, warnings, segment ids used, {key: E}, table rows, C as printed) for
    7.6/7.7.

    C is the printed (max E − min E)/E_ref less the widening of the range by the E's own noise
    (:func:`.formulas.range_moment_matched`, the non-common part of the E budget drawn normal;
    interpretations.md, "7.6 / 7.7 — the range of noisy E")."""
    warnings: list[str] = []
    _S, _E, _rounds, _R, R_i, rows, _sim = proc._reference(campaign, opts, warnings)
    groups = positioning_groups(campaign)
    values, used, table_rows = {}, [], []
    for key in groups_wanted:
        if key not in groups:
            continue
        lst = groups[key]
        _, e = round_errors(lst[0][1])
        values[key] = F.position_error_74(e)
        used.append(lst[0][1].id)
        table_rows.append([label(key), f"{values[key]:.3f}"])
    missing = [label(k) for k in groups_wanted if k not in values]
    if len(values) < 2:
        raise DataError(campaign.source, "segments",
                        f"{proc.item} needs the angle-position error under at least two "
                        f"{('rates' if proc.item == '7.6' else 'axis directions')}; missing: "
                        f"{', '.join(missing)}",
                        hint=f"`metro plan -s ogam -i {proc.item}` lists what to measure")
    if missing:
        warnings.append(msg("not measured: {what}", what=", ".join(missing)))
    e_ref = values[ref]
    if e_ref == 0:
        # every stop of the reference round read the standard exactly (a reading rounded coarser
        # than the instrument's errors): the ratio is undefined, and only this result is lost (not
        # the run)
        return None, [], warnings, used, values, table_rows, ""
    C = F.consistency_ratio(list(values.values()), e_ref) * 100.0
    # the extreme and the reference E each carry the non-common part of the E budget
    # (positioning, drift, repeatability); the tilt error is common to all and cancels
    c = 100.0 * math.sqrt(2.0 + (C / 100.0) ** 2) / e_ref
    noncommon = (rows[0], rows[2], rows[3], rows[4])
    brows = [attrs_evolve_sensitivity(r, Q_(c, "percent/arcsec")) for r in noncommon]
    uE = math.sqrt(sum(float(r.standard_uncertainty.to("arcsec").magnitude) ** 2
                       for r in noncommon))
    if e_ref < 2 * uE:
        warnings.append(msg("the reference E = {E:.3g}″ is below twice its uncertainty "
                            "({twice_u:.2g}″): the ratio is ill-conditioned; see the range (max − "
                            "min) in the note", E=e_ref, twice_u=2 * uE))
    printed = C
    # eight (three) noisy E can only widen their range on average: the printed ratio reads high by
    # mean E_n +0.25 … +0.32 on the independent harness's drifting instruments; corrected as K_l's
    # range, with the random part of one round's E — the repeatability R of 7.5 and the reading
    # resolution.  The turntable's positioning at a stop and the drift bound are bounds of
    # systematic errors, not a scatter between rounds (taking them as noise took off too much: C_v
    # 93–94 % within U, mean E_n −0.26 … −0.35) a stop's scatter between rounds, pooled over the
    # stops (R of 7.5 is the largest R_i: as the noise of every E it took off too much, C_v mean
    # E_n −0.32 on the harness's coarse-reading instruments)
    u_rand = float(np.sqrt(np.mean(np.square(R_i))))
    if u_rand > 0:
        draws = np.random.default_rng(7607).normal(0.0, u_rand, size=(KL_DRAWS, len(values)))
        est = F.range_moment_matched(list(values.values()), draws)
        lam = est.estimate / est.printed if est.printed > 0 else 1.0
        C = printed * lam
        brows.append(BudgetRow.type_b(
            msg("correction for the widening of the range of the E by their noise, uncertain by "
                "its own size"), "u(δ_R)",
            Q_(abs(printed - C), "percent"), distribution="normal", k=1.0,
            note=msg("δ = {d:.3g} % (moment matched, {n} draws of one round's random error u = "
                     "{u:.3g}″, the R_i of 7.5 pooled; the noise alone gives a range of {m:.3g}″ "
                     "on average)", d=printed - C, n=KL_DRAWS, u=u_rand, m=est.noise_only)))
    note = _printed_note(printed, C)
    if printed != 0 and C == 0.0:
        note = join("; ", [x for x in (note,) if x] + [msg("not resolved from 0: the noise alone "
                                                           "gives a range of {n:.3g}″ on average, "
                                                           "no less than the one "
                                                           "observed", n=est.noise_only)])
    return C, brows, warnings, used, values, table_rows, note


def _printed_note(printed: float | None, C: float | None) -> str:
    if printed is None or C is None or printed == C:
        return ""
    return msg("as printed by the formula {p:.4g} %, less the widening of the range by the E's "
               "noise ({d:.3g} %)",
               p=printed, d=printed - C)


def _ratio_result(metric: Metric, C: float | None, rows: list[BudgetRow], name: str,
                  note) -> Result:
    """The C_v / C_g result; not reportable when the reference E is 0 (interpretations.md, "7.6 /
    7.7 — E_ref = 0")."""
    if C is None:
        return Result(metric, Q_(0.0, "percent"), reportable=False, note=note, reason=msg(
            "the reference E is 0 (every stop read the standard angle at the reading's "
            "resolution): the ratio (max E − min E)/E_ref is undefined"))
    budget = UncertaintyBudget(name, "percent", rows, coverage=COVERAGE_NU)
    return Result(metric, Q_(C, "percent"), budget.combined, budget, note=note)


def rate_points_76(campaign: Campaign) -> list[tuple[float, str]]:
    """The rate points 7.6 compares: every rate recorded with the axis up, 60 °/s among them.

    Clause 7.6 asks for 8 rate points in (1–300) °/s and prints 1, 10, 60, 100, 150, 200, 250 and
    300 °/s as reference values (参考值), so a campaign may use others; those are the ones measured
    (interpretations.md, "7.6 — the rate points are the campaign's").  Without rounds at other rates
    the clause's reference values are listed as missing."""
    rates = sorted({r for r, a in positioning_groups(campaign) if a == "up"} | {REF_RATE})
    return [(v, "up") for v in (rates if len(rates) > 1 else RATES)]


class RateConsistency76(PositionErrorItem):
    """Draft JJF 光学陀螺测角仪 7.6 速率一致性 (rate consistency), definition 3.4:
    C_v = (max E_v − min E_v)/E_60°/s in %, E_v the 7.4 result (max|E_i|, first round) at each of
    the 8 rates.  Budget: the non-common E components (positioning, drift, repeatability),
    sensitivity sqrt(2 + C_v²)/E_60 (linearised).
    """

    item = "7.6"
    title = "Rate consistency (速率一致性)"
    clause = "7.6"
    metrics = (Metric("Cv", "rate consistency", "C_v", "percent", "7.6",
                      "C_v = (max E_v − min E_v)/E_60"),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [pos_step(v, "up", 1) for v in RATES if v != REF_RATE] + rounds_at_reference()

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        C, rows, warnings, used, values, trows, cnote = _consistency(
            self, campaign, opts, rate_points_76(campaign), (REF_RATE, "up"),
                                                                     lambda k: f"{k[0]:g} °/s")
        if len(values) != len(RATES):
            warnings.append(msg("{n} rate points; clause 7.6 asks for {asked}", n=len(values),
                                asked=len(RATES)))
        rng = max(values.values()) - min(values.values())
        res = _ratio_result(self.metrics[0], C, rows, "C_v", join("; ", [x for x in (
            msg("max E_v − min E_v = {range:.3f}″, E_60 = {ref:.3f}″", range=rng,
                ref=values[(REF_RATE, 'up')]), cnote) if x]))
        table = TableSpec("E_v", msg("Angle-position error per rate (7.6)"),
                          [msg("rate"), "E_v (″)"], trows)
        plot = PlotSpec("E_v", msg("Angle-position error against rate (7.6)"), "v (°/s)", "E_v (″)",
                        [{"label": "E_v", "x": [k[0] for k in values], "y": list(values.values()),
                          "style": "o-"}],
                        logx=True)
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)], plots=[plot],
                       tables=[table],
                       warnings=warnings, segments=used,
                       options={k: str(v) for k, v in opts.items()})


class PointingConsistency77(PositionErrorItem):
    """Draft JJF 光学陀螺测角仪 7.7 指向一致性 (pointing consistency), definition 3.5:
    C_g = (max E_g − min E_g)/E_up in %, E_g the 7.4 result (first round) with the turntable
    axis up, north (or south), east (or west).  Budget as 7.6.
    """

    item = "7.7"
    title = "Pointing consistency (指向一致性)"
    clause = "7.7"
    metrics = (Metric("Cg", "pointing consistency", "C_g", "percent", "7.7",
                      "C_g = (max E_g − min E_g)/E_up"),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [pos_step(REF_RATE, a, 1) for a in AXES if a != "up"] + rounds_at_reference()

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        groups = positioning_groups(campaign)
        north = "north" if (REF_RATE, "north") in groups or (REF_RATE,
                                                             "south") not in groups else "south"
        east = "east" if (REF_RATE, "east") in groups or (REF_RATE,
                                                          "west") not in groups else "west"
        C, rows, warnings, used, values, trows, cnote = _consistency(
            self, campaign, opts, [(REF_RATE, a) for a in ("up", north, east)], (REF_RATE, "up"),
                                                                     lambda k: k[1])
        rng = max(values.values()) - min(values.values())
        res = _ratio_result(self.metrics[0], C, rows, "C_g", join("; ", [x for x in (
            msg("max E_g − min E_g = {range:.3f}″, E_up = {ref:.3f}″", range=rng,
                ref=values[(REF_RATE, 'up')]), cnote) if x]))
        table = TableSpec("E_g", msg("Angle-position error per axis direction (7.7)"),
                          [msg("axis"), "E_g (″)"], trows)
        return Outcome(STANDARD, self.item, self.title, self.clause, [disclosed(res)],
                       tables=[table], warnings=warnings,
                       segments=used, options={k: str(v) for k, v in opts.items()})


PROCEDURES = (ScaleFactor71, Linearity72, ZeroStability73, PositionError74, Repeatability75,
              RateConsistency76,
              PointingConsistency77)

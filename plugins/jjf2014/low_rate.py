"""JJF 2014—2022 7.2.9–7.2.12: threshold, resolution, input-axis misalignment and its
repeatability."""

from __future__ import annotations

import math

import attrs
import numpy as np
from metro.api import (INF, Q_, BudgetRow, DataError, EquipmentRequirement, Metric, Option,
                       ProcedureError, Result, Segment, SegmentRequirement, Step, TableSpec, join,
                       msg)

from . import budgets as B
from . import formulas as F
from .common import (RATE_OPTS, JJFItem, Spread, budget_row_a, calibration_of, check_distinct,
                     condition_in, group_by, mean_and_u, need_segments, num_option, output_step,
                     parse_magnitudes, quantity_text, read_output, scale_factor_for, stated_spread)
from .scale_factor import ScaleFactor

# =============================================================================== 7.2.9, 7.2.10


def _grid_result(metric, cands: dict[str, tuple[float, float | None]], campaign, what: str):
    """Result for a grid-searched quantity, from the larger |candidate| of the two directions, as
    7.2.9.1 f) / 7.2.10.1 g) pick it.  The candidate meets eq. (17)/(18) and the next smaller
    level does not, so the true value lies in (next level, candidate] (or (0, candidate] when every
    level passed): nothing more is known of where.  Reported as the middle of that interval with a
    uniform half-width of half the step, u = step/√12 (JJF 1059.1's rectangular distribution); the
    candidate, an upper bound, is in the note (interpretations.md, "7.2.9 / 7.2.10")."""
    d = max(cands, key=lambda k: abs(cands[k][0]))
    val, nxt = cands[d]
    hi, lo = abs(val), (abs(nxt) if nxt is not None else 0.0)
    mid, half = (hi + lo) / 2.0, (hi - lo) / 2.0
    rows = [BudgetRow.type_b(msg("step of the {what} levels ({direction}): true value in ({lo:g}, "
                                 "{hi:g}] °/s",
                                 what=what, direction=d, lo=lo, hi=hi), "Δ/2",
                             Q_(half, "deg/s"), distribution="uniform",
                             note=msg("the middle of the interval between the failing and the "
                                      "candidate level, u = Δ/√12"))]
    rows += B.relative_calibration_row("rate table at low rate", "u_rel(Ω)",
                                       calibration_of(campaign, "rate_table"),
                                       Q_(mid, "deg/s"))
    b = B.type_a_budget(metric.key, "deg/s", rows)
    return Result(metric, Q_(mid, "deg/s"), b.combined, b,
                  note=msg("larger in the {direction} direction: the level that meets the "
                           "criterion (the standard's value) is {hi:g} °/s, the next smaller one "
                           "({lo:g} °/s) does not; reported as the middle of ({lo:g}, {hi:g}]",
                           direction=d, hi=hi, lo=lo))


def pair_scatter(levels: dict[str, tuple[np.ndarray, np.ndarray]]) -> tuple[float, int]:
    """The scatter of one response between records, from the two directions: at each |Ω| both
    directions were applied, F₊ + F₋ ≈ 0 for an odd response (the dead zone, K and its small-rate
    nonlinearity cancel), so √(mean (F₊ + F₋)²/2) estimates the standard deviation of one F_i — its
    own record's noise, the reference record's and the bias's drift between records, which the
    records' own s/√N cannot see (flicker, wander).  Returns (scatter, number of pairs)."""
    if set(levels) != {"forward", "reverse"}:
        return 0.0, 0
    (om1, f1), (om2, f2) = levels["forward"], levels["reverse"]
    by = {round(abs(o), 12): x for o, x in zip(om2, f2)}
    sums = [x + by[round(abs(o), 12)] for o, x in zip(om1, f1) if round(abs(o), 12) in by]
    if len(sums) < 3:
        return 0.0, len(sums)
    return float(np.sqrt(np.mean(np.square(sums)) / 2.0)), len(sums)


def _resolved(brackets: dict, cands: dict, scatter: tuple[float, int],
              what: str) -> tuple[dict, str, str]:
    """Each direction's (candidate, next level) widened to the levels whose pass / fail is resolved
    from the noise at k = 2 (:func:`.formulas.resolved_bracket`); returns (cands, note, reason for
    not reportable or "")."""
    out, notes, why = dict(cands), [], ""
    s, n = scatter
    for name, (om, br) in brackets.items():
        if br is None:
            why = msg("the {direction} {what} levels' passes are not resolved from the noise of "
                      "the responses (k = 2, between-record scatter {s:.3g} mV from {n} ±pairs): "
                      "record longer or at larger levels",
                      direction=name, what=what, s=s, n=n)
            continue
        h, lo, i = br
        if h != i or lo != i + 1:
            out[name] = (float(om[h]), float(om[lo]) if lo is not None else None)
            notes.append(msg("{direction}: the pass of {cand:g} °/s or the fail of the next level "
                             "is within the noise of the responses (k = 2, between-record scatter "
                             "{s:.3g} mV from {n} ±pairs): interval widened to ({lo:g}, {hi:g}] "
                             "°/s", direction=name, cand=abs(float(om[i])), s=s, n=n,
                             lo=abs(float(om[lo])) if lo is not None else 0.0,
                             hi=abs(float(om[h]))))
    return out, join("; ", notes), why


def _rounding_check(campaign, res: Result, pairs: list[tuple[str, Segment, Segment, float]],
                    K: float,
                    eq: str) -> Result:
    """Issue 13: a level counts only if its response is resolved from the output's rounding.  Each
    response is a difference of two means, F̄(level) − F̄(reference), each off by up to its rounding
    half-width (Widrow bound when the noise dithers the rounding, else ±q/2); when that sum reaches
    eq. (17)/(18)'s margin at a direction's candidate, 50 %·|K·level|, the pass may be rounding and
    the result is not reportable (interpretations.md, "JJF 2014 — output quantization").
    ``pairs``: (direction, candidate's segment, reference segment, candidate level) per
    direction."""
    worst = None
    for name, seg_c, seg_r, level in pairs:
        xc, xr = read_output(seg_c)[0], read_output(seg_r)[0]
        q, src = output_step(campaign, [xc, xr])
        if q <= 0:
            return res
        (hc, dc), (hr, dr) = (F.rounding_half_width(q, float(np.std(x, ddof=1))) for x in (xc, xr))
        e, margin = hc + hr, 0.5 * abs(K * level)
        if worst is None or e / margin > worst[0]:
            worst = (e / margin, name, e, margin, q, src, dc and dr)
    _, name, e, margin, q, src, dith = worst
    text = (msg("output step q = {q:.3g} mV ({src}, dithered by the noise): the {name} candidate's "
                "response may be off by up to ±{e:.3g} mV from rounding", q=q, src=src, name=name,
                e=e) if dith else
            msg("output step q = {q:.3g} mV ({src}, not dithered by the noise): the {name} "
                "candidate's response may be off by up to ±{e:.3g} mV from rounding", q=q, src=src,
                name=name, e=e))
    if e >= margin:
        return attrs.evolve(res, reportable=False, reason=(
            msg("{text}, as large as {eq}'s 50 % margin ({margin:.3g} mV): the level may pass or "
                "fail on rounding alone (digitise more finely)", text=text, eq=eq, margin=margin)
                                                           if dith else
            msg("{text}, as large as {eq}'s 50 % margin ({margin:.3g} mV): the level may pass or "
                "fail on rounding alone (digitise more finely; a longer record does not average "
                "undithered rounding out)", text=text,
                eq=eq, margin=margin)))
    return attrs.evolve(res, note=join("; ", [res.note, msg("{text}, below {eq}'s 50 % margin "
                                                            "{margin:.3g} mV",
                                                             text=text, eq=eq, margin=margin)]))


def _decided(metric, campaign, cands: dict, levels: dict, uw: dict, K: float, what: str,
             pairs: list, eq: str) -> Result:
    """The grid result of 7.2.9 / 7.2.10 with each level decided only where its response is
    resolved from the noise (issue 13): u of each F_i is the larger of its two records' s/√N and
    the between-record scatter of the ±pairs (:func:`_pair_scatter`); the candidate's interval is
    widened to the resolved levels, or the result is not reportable (interpretations.md, "7.2.9 /
    7.2.10 — a level decided by noise"); then the output-rounding check."""
    sc = pair_scatter(levels)
    brackets = {}
    for name, (om, f) in levels.items():
        u = np.maximum(uw[name], sc[0])
        brackets[name] = (om, F.resolved_bracket(om, f, K, u))
    widened, note, why = _resolved(brackets, cands, sc, what)
    res = _grid_result(metric, widened, campaign, what)
    if note:
        res = attrs.evolve(res, note=join("; ", [res.note, note]))
    if why:
        return attrs.evolve(res, reportable=False, reason=why)
    return _rounding_check(campaign, res, pairs, K, eq)


class Threshold(JJFItem):
    """JJF 2014—2022 7.2.9 阈值: decreasing rates in each direction; F̂_i = KΩ_i (16);
    candidate = the last rate meeting |(F̂_i − F_i)/F̂_i| ≤ 50 % (17) with F_i the output minus
    the zero-input mean; threshold = the larger |candidate| of the two directions (7.2.9.1 f))."""

    item = "7.2.9"
    title = "Threshold (阈值)"
    clause = "7.2.9"
    metrics = (Metric("threshold", "threshold", "Ω_th", "deg/s", "7.2.9.2", "16, 17"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "threshold", "table at decreasing small rates Ω_i in each direction, and at rest (rate 0)",
        {"rate": "deg/s"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("levels", "0.1, 0.05, 0.03, 0.02, 0.015, 0.01, 0.007, 0.005, "
                                            "0.003", None,
                                  "small rates (°/s), largest first"),
                           Option("seconds", 200, None, "record length per level (s at 1 s)"))

    def sequence(self, options):
        n = num_option(options, "seconds", 2)
        steps = ScaleFactor().sequence(options)
        steps.append(Step("threshold-0", "threshold", "table at rest (zero input)", Q_(n, "s"),
                          Q_(1, "s"),
                          {"rate": "0 deg/s"}))
        for r in parse_magnitudes(options["levels"], "levels"):
            for sgn in (1, -1):
                steps.append(Step(f"threshold{'+' if sgn > 0 else '-'}{r:g}", "threshold",
                                  f"table at {sgn * r:+g} °/s",
                                  Q_(n, "s"), Q_(1, "s"),
                                  {"rate": quantity_text(sgn * r, "deg/s")}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, _, _ = scale_factor_for(campaign, type(self))
        segs = need_segments(campaign, type(self), "threshold")
        zero = [s for s in segs if condition_in(s, "rate", "deg/s") == 0.0]
        if not zero:
            raise DataError(campaign.source, "segments",
                            "7.2.9 needs a zero-input segment (kind threshold, rate 0)")
        f0 = np.mean([mean_and_u(s)[0] for s in zero])
        u0 = math.sqrt(sum(mean_and_u(s)[1] ** 2 for s in zero)) / len(zero)
        cands = {}
        rows = []
        pairs = []
        levels, uw = {}, {}
        for name, sgn in (("forward", 1), ("reverse", -1)):
            d = sorted([s for s in segs if sgn * condition_in(s, "rate", "deg/s") > 0],
                       key=lambda s: -abs(condition_in(s, "rate", "deg/s")))
            if len(d) < 2:
                raise DataError(campaign.source, "segments",
                                f"7.2.9 needs at least 2 {name} levels")
            om = np.array([condition_in(s, "rate", "deg/s") for s in d])
            check_distinct(campaign, om, f"7.2.9 {name} levels (condition rate)")
            fc = np.array([mean_and_u(s)[0] - f0 for s in d])
            levels[name], uw[name] = (om,
                                      fc), np.array([math.hypot(mean_and_u(s)[1], u0) for s in d])
            c, i = F.threshold_eq16_17(om, fc, K)
            if c is None:
                raise ProcedureError(f"7.2.9: already the largest {name} level {om[0]:g} °/s fails "
                                     "eq. (17)",
                                     hint="start the decreasing sequence at a larger rate (option "
                                          "levels)")
            cands[name] = (c, float(om[i + 1]) if i + 1 < om.size else None)
            pairs.append((name, d[i], zero[0], c))
            rows += [[name, f"{o:g}", f"{K * o:.4g}", f"{x:.4g}",
                      f"{abs((K * o - x) / (K * o)) * 100:.1f}"]
                     for o, x in zip(om, fc)]
        res = _decided(self.metrics[0], campaign, cands, levels, uw, K, "threshold", pairs,
                       "eq. (17)")
        tab = TableSpec("threshold", msg("Eq. (17) per level"),
                        [msg("direction"), "Ω_i (°/s)", "F̂_i (mV)", "F_i (mV)",
                                                             "|F̂−F|/F̂ (%)"], rows)
        return self._outcome([res], tables=[tab], segments=[s.id for s in segs], opts=opts)


class Resolution(JJFItem):
    """JJF 2014—2022 7.2.10 分辨率: increments ΔΩ_i on a base rate 20–50× the threshold;
    ΔF̂_i = KΔΩ_i by eq. (6); candidate = last increment meeting eq. (18); resolution = the
    larger |candidate| of the two directions (7.2.10.1 g))."""

    item = "7.2.10"
    title = "Resolution (分辨率)"
    clause = "7.2.10"
    metrics = (Metric("resolution", "resolution", "Ω_res", "deg/s", "7.2.10.2", "18"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "resolution", "base rate Ω_b and Ω_b + ΔΩ_i for decreasing increments, each direction",
        {"base_rate": "deg/s", "increment": "deg/s"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("base_rate", "0.3 deg/s", "deg/s",
                                  "base rate (20–50× the estimated threshold)"),
                           Option("increments",
                                  "0.05, 0.02, 0.01, 0.007, 0.005, 0.003, 0.002, 0.001", None,
                                  "increments (°/s), largest first"),
                           Option("seconds", 200, None, "record length per level (s at 1 s)"))

    def sequence(self, options):
        n = num_option(options, "seconds", 2)
        base = float(options["base_rate"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for sgn, d in ((1, "+"), (-1, "-")):
            steps.append(Step(f"resolution{d}base", "resolution", f"base rate {sgn * base:+g} °/s",
                              Q_(n, "s"),
                              Q_(1, "s"),
                              {"base_rate": quantity_text(sgn * base, "deg/s"),
                               "increment": "0 deg/s"}))
            for r in parse_magnitudes(options["increments"], "increments"):
                steps.append(Step(f"resolution{d}{r:g}", "resolution",
                                  f"base {sgn * base:+g} °/s + {sgn * r:+g} °/s",
                                  Q_(n, "s"), Q_(1, "s"),
                                  {"base_rate": quantity_text(sgn * base, "deg/s"),
                                   "increment": quantity_text(sgn * r, "deg/s")}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, _, _ = scale_factor_for(campaign, type(self))
        segs = need_segments(campaign, type(self), "resolution")
        cands, rows, pairs = {}, [], []
        levels, uw = {}, {}
        for name, sgn in (("forward", 1), ("reverse", -1)):
            mine = [s for s in segs if sgn * condition_in(s, "base_rate", "deg/s") > 0]
            base = [s for s in mine if condition_in(s, "increment", "deg/s") == 0.0]
            inc = sorted([s for s in mine if condition_in(s, "increment", "deg/s") != 0.0],
                         key=lambda s: -abs(condition_in(s, "increment", "deg/s")))
            if not base or len(inc) < 2:
                raise DataError(campaign.source, "segments",
                                f"7.2.10 needs, in the {name} direction, a base segment (increment "
                                "0) and ≥ 2 increments")
            fb = mean_and_u(base[0])[0]
            dom = np.array([condition_in(s, "increment", "deg/s") for s in inc])
            check_distinct(campaign, dom, f"7.2.10 {name} increments (condition increment)")
            if len(base) > 1:
                raise DataError(campaign.source, "segments",
                                f"7.2.10: {len(base)} {name} base segments (increment 0); give one")
            dF = np.array([mean_and_u(s)[0] - fb for s in inc])
            levels[name] = (dom, dF)
            uw[name] = np.array([math.hypot(mean_and_u(s)[1], mean_and_u(base[0])[1]) for s in inc])
            c, i = F.resolution_eq18(dom, dF, K)
            if c is None:
                raise ProcedureError(f"7.2.10: already the largest {name} increment {dom[0]:g} °/s "
                                     "fails eq. (18)")
            cands[name] = (c, float(dom[i + 1]) if i + 1 < dom.size else None)
            pairs.append((name, inc[i], base[0], c))
            rows += [[name, f"{o:g}", f"{K * o:.4g}", f"{x:.4g}"] for o, x in zip(dom, dF)]
        res = _decided(self.metrics[0], campaign, cands, levels, uw, K, "increment", pairs,
                       "eq. (18)")
        tab = TableSpec("resolution", msg("Eq. (18) per increment"),
                        [msg("direction"), "ΔΩ_i (°/s)", "ΔF̂_i (mV)", "ΔF_i (mV)"],
                        rows)
        return self._outcome([res], tables=[tab], segments=[s.id for s in segs], opts=opts)


# =============================================================================== 7.2.11, 7.2.12


def _misalignment_run(campaign, proc, segs: list[Segment], K: float, uK_rel: float):
    Fm: dict[tuple[int, str], float] = {}
    uF: dict[tuple[int, str], float] = {}
    omegas = set()
    for s in segs:
        ptxt = str(s.condition("position")).strip()
        p = int(ptxt) if ptxt in ("1", "2", "3", "4") else 0
        if not p:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions.position",
                            f"must be 1, 2, 3 or 4 (the four mountings of 7.2.11.1), got {ptxt!r}")
        om = condition_in(s, "rate", "deg/s")
        if om == 0:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions.rate",
                            "must be ±Ω_(+), not 0")
        key = (p, "+" if om > 0 else "-")
        if key in Fm:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions",
                            f"two records of position {p} turning "
                            f"{'forward' if key[1] == '+' else 'reverse'} in one run")
        Fm[key], uF[key], _ = mean_and_u(s)
        omegas.add(abs(om))
    missing = [f"{p}{d}" for p in (1, 2, 3, 4) for d in "+-" if (p, d) not in Fm]
    if missing:
        raise DataError(campaign.source, "segments",
                        "7.2.11 needs all four positions in both directions; missing "
                        f"{', '.join(missing)}")
    if len(omegas) != 1:
        raise DataError(campaign.source, "segments",
                        "7.2.11: all records must use the same table rate Ω_(+)")
    om = omegas.pop()
    r = F.misalignment_eq19_25(Fm, om, K)
    # u(α) from the four means of positions 1, 2: each δ has u = √(u²(F+) + u²(F−))/(2ΩK)
    ud = {p: math.hypot(uF[(p, "+")], uF[(p, "-")]) / (2 * om * K) for p in (1, 2, 3, 4)}
    ua, ub = math.hypot(ud[1], ud[2]) / 2, math.hypot(ud[3], ud[4]) / 2
    g_rad = math.hypot(r["alpha"], r["beta"])
    to_arcmin = 10800.0 / math.pi
    u_noise = (math.hypot(r["alpha"] * ua, r["beta"] * ub) / g_rad if g_rad > 0
               else math.hypot(ua, ub)) * to_arcmin
    return r, u_noise, om


def misalignment_reproducibility(campaign, runs, K: float, uK: float) -> Spread | None:
    """γ_mr (′, eq. (26)): the spread of γ_m over the campaign's repeated mountings (7.2.12,
    ≥ 2 runs), else ``device.misalignment_repeatability``, else None."""
    if len(runs) >= 2:
        gam = [_misalignment_run(campaign, Misalignment, g, K, uK)[0]["gamma"] for _,
               g in sorted(runs.items())]
        gr = F.std_bessel(gam, "eq. (26)")
        return Spread(gr, len(gam) - 1, msg("γ_mr = {g:.3g}′ from this campaign's {n} mountings "
                                            "(7.2.12)", g=gr, n=len(gam)))
    return stated_spread(campaign, "misalignment_repeatability", "arcmin",
                         "misalignment repeatability in ′")


def _reseating(campaign, rows: list, u_noise: float) -> tuple[list, str]:
    """γ_m of one set of mountings with no 7.2.12 runs and no stated γ_mr: each of the four
    mountings seats the device anew, δ_p = ±α + ε + η_p, and eqs. (21)/(24) cancel the fixture's ε,
    not the η_p (interpretations.md, "7.2.11 — one set of mountings").  The fixture's
    ``reseat_tilt`` (a half-width per mounting, as GB/T D.1's fixture) gives a uniform row of
    half-width reseat_tilt/√2 (α = (δ₁ − δ₂)/2 holds two seatings: √2/2 of one); without it the
    result is not reportable: the eight means' scatter alone leaves the re-seating out."""
    fx = campaign.equipment_for("fixture")
    if fx is not None and "reseat_tilt" in fx.properties:
        seat = float(Q_(fx.prop("reseat_tilt", "arcmin",
                                source=campaign.source)).to("arcmin").magnitude)
        return rows + [BudgetRow.type_b(msg("re-seating of the device in the fixture {fx} at each "
                                            "of the four mountings (α = (δ₁ − δ₂)/2: 1/√2 of one "
                                            "seating)", fx=fx.id),
                                        "η/√2", Q_(seat / math.sqrt(2), "arcmin"),
                                        distribution="uniform")], ""
    return rows, msg("one set of the four mountings and no 7.2.12 runs: how far another seating "
                     "puts the input axis is not known, and the scatter of the eight means "
                     "({u:.2g}′) leaves it out (give 7.2.12 runs, "
                     "device.misalignment_repeatability or the fixture's reseat_tilt)", u=u_noise)


class Misalignment(JJFItem):
    """JJF 2014—2022 7.2.11 输入轴失准角: four mountings, δ_p eqs. (19), (20), (22), (23),
    α_m (21), β_m (24), γ_m = 10800√(α_m² + β_m²)/π in ′ (25)."""

    item = "7.2.11"
    title = "Input-axis misalignment (输入轴失准角)"
    clause = "7.2.11"
    metrics = (Metric("gamma", "input-axis misalignment", "γ_m", "arcmin", "7.2.11.2", "25"),)
    equipment = JJFItem.equipment + (EquipmentRequirement("fixture", "fixture seating the device "
                                                                     "at positions 1–4; its "
                                                       "re-seating tilt enters the budget"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "misalignment", "positions 1–4 (OY up, +180° about IRA, OX up, +180°), table ±Ω for 1 min",
        {"position": "", "rate": "deg/s", "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("table_rate", "360 deg/s", "deg/s", "Ω_(+) (7.2.11.1 b))"),)
    runs_default = 1

    def _steps(self, options, runs):
        om = float(options["table_rate"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for q in range(1, runs + 1):
            for p in (1, 2, 3, 4):
                for sgn in (1, -1):
                    steps.append(Step(f"misalignment#{q}p{p}{'+' if sgn > 0 else '-'}",
                                      "misalignment",
                                      f"run {q}, position {p}, table {sgn * om:+g} °/s, 1 min",
                                      Q_(60, "s"),
                                      Q_(1, "s"),
                                      {"position": str(p), "rate": quantity_text(sgn * om, "deg/s"),
                                       "run": str(q)}))
        return steps

    def sequence(self, options):
        return self._steps(options, 1)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K, uK = kv.K, kv.u_rel
        segs = need_segments(campaign, type(self), "misalignment")
        runs = group_by(segs, "run") if all("run" in s.conditions for s in segs) else {"1": segs}
        first = sorted(runs)[0]
        r, u_noise, om = _misalignment_run(campaign, type(self), runs[first], K, uK)
        gamma = r["gamma"]
        rep = misalignment_reproducibility(campaign, runs, K, uK)
        why = ""
        if rep is not None and rep.value > u_noise:
            # another mounting gives another γ (7.2.12): that spread holds the scatter of the means
            rows = [rep.row("mounting reproducibility (another mounting gives another γ_m)", "γ_mr",
                            rep.value,
                            "arcmin")]
        else:
            rows = [budget_row_a("scatter of the eight mean outputs", "u_A", u_noise, "arcmin",
                                 INF)]
            if rep is None:
                rows, why = _reseating(campaign, rows, u_noise)
        rows.append(kv.row(gamma, "arcmin", "scale factor K (γ ∝ 1/K)"))
        rows += B.relative_calibration_row(msg("rate table Ω_(+) (γ ∝ 1/Ω)"), "u_rel(Ω)",
                                           calibration_of(campaign, "rate_table"),
                                           Q_(gamma, "arcmin"))
        b = B.type_a_budget("gamma", "arcmin", rows)
        note = msg("α_m = {a:.4g}′, β_m = {b:.4g}′ (run {run}, Ω = {om:g} °/s)",
                   a=r['alpha'] * 10800 / math.pi,
                   b=r['beta'] * 10800 / math.pi, run=first, om=om)
        return self._outcome([Result(self.metrics[0], Q_(gamma, "arcmin"), b.combined, b, note=note,
                                     reportable=not why, reason=why)],
                             segments=[s.id for s in runs[first]], opts=opts)


class MisalignmentRepeatability(Misalignment):
    """JJF 2014—2022 7.2.12 输入轴失准角重复性: 7.2.11 repeated Q ≥ 7 times, γ_mr eq. (26)."""

    item = "7.2.12"
    title = "Input-axis misalignment repeatability (输入轴失准角重复性)"
    clause = "7.2.12"
    metrics = (Metric("gamma_r", "input-axis misalignment repeatability", "γ_mr", "arcmin",
                      "7.2.12.2", "26"),)
    options = Misalignment.options + (Option("runs", 7, None, "Q (≥ 7)"),)

    def sequence(self, options):
        return self._steps(options, num_option(options, "runs", 7, integer=True))

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        runs = group_by(need_segments(campaign, type(self), "misalignment"), "run")
        if len(runs) < 7:
            raise DataError(campaign.source, "segments",
                            "7.2.12 needs Q ≥ 7 repetitions of 7.2.11 (condition run); got "
                            f"{len(runs)}")
        gam = [_misalignment_run(campaign, type(self), g, K, uK)[0]["gamma"] for _,
               g in sorted(runs.items())]
        gr = F.std_bessel(gam, "eq. (26)", 7)
        u, dof = B.std_of_std(gr, len(gam))
        b = B.type_a_budget("gamma_r", "arcmin", [budget_row_a(msg("sampling of a standard "
                                                                   "deviation of Q values (χ² "
                                                                   "bound)"),
                                                                "(s_{upper} − γ_mr)/2", u, "arcmin",
                                                               dof)])
        tab = TableSpec("gamma_runs", msg("γ_mi per run"), [msg("run"), "γ_mi (′)"],
                        [[k, f"{g:.4f}"] for k, g in zip(sorted(runs), gam)])
        return self._outcome([Result(self.metrics[0], Q_(gr, "arcmin"), b.combined, b)],
                             tables=[tab],
                             segments=[s.id for g in runs.values() for s in g], opts=opts)

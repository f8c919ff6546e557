"""GB/T 45570—2025 appendix D procedures: D.5.1 bias, D.5.2 bias stability, D.5.6 ARW.

Each class is one item; its docstring names the clause and equations, and the formulas
live in :mod:`.formulas`.  Procedures orchestrate: pick segments, convert units at the
boundary, call the formulas and the core's shared maths, and build the budgets.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement,
                       Metric, Option, Outcome, PlotSpec, ProcedureError, Result,
                       RunContext, Segment, SegmentRequirement, Step, TableSpec, UncertaintyBudget,
                       allan, hint, join, msg, parse_quantity)

from . import formulas as F
from .arw import AngleRandomWalkD56
from .common import (BIAS_EQUIPMENT, COVERAGE, STANDARD, GbtItem, delta_temperature_u, opts_text,
                     scale_factor_row, timebase_row)
from .repeatability import bias_repeat_row, bias_turn_on
from .static_bias import (STATIC, duration_warnings, quantization_of, quantization_rows_std,
                          segment_bias, segments_of, static_input, static_segment)

# --------------------------------------------------------------------------------------------
# D.5.1 Bias
# --------------------------------------------------------------------------------------------


class BiasD51(GbtItem):
    """GB/T 45570—2025 D.5.1 零偏 (bias), eq. (D.40).

    B0 = (1/(τK))·(1/n)ΣN_i − 15.041·sin θ.  For LSB or rate output the first term is the
    mean indicated rate (reading notes).  Type A uncertainty: batch means (``batches``
    equal consecutive batches; u = s_batch/√b, ν = b − 1), which stays honest when the
    noise is correlated.  Type B: scale factor, latitude, levelling of the IRA, time base.
    """

    item = "D.5.1"
    title = "Bias (零偏)"
    clause = "D.5.1"
    metrics = (Metric("B0", "bias", "B₀", "deg/h", "D.5.1.3", "D.40"),)
    requires = (STATIC,)
    equipment = BIAS_EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("batches", 20, None, "number of batch means for the type A uncertainty", minimum=2),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static-1h", "static",
                     "IRA up on the levelled platform; power on, wait the set-up time, "
                     "record 1 h at τ = 1 s; power off (D.5.1.2)", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up"})]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg = static_segment(type(self), campaign, opts)
        est = segment_bias(seg, campaign, int(opts["batches"]))
        rep_rows, rep_note = bias_repeat_row(campaign, int(opts["batches"]), est.u_A)
        budget = UncertaintyBudget("B0", "deg/h", list(est.budget.rows) + rep_rows,
                                   coverage=COVERAGE)
        note = msg("earth rate {earth:+.4f} °/h removed ({orientation}, θ = {theta:g}°)",
                   earth=est.earth,
                   orientation=est.orientation, theta=est.theta)
        res = Result(self.metrics[0], Q_(est.B0, "deg/h"), budget.combined, budget,
                     note=join("; ", [note, rep_note]) if rep_note else note, earth_rate="removed")
        warnings = duration_warnings(est.series, Q_(1, "h"), "D.5.1.2 c)")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], warnings=warnings,
                       segments=[seg.id], options=opts_text(opts))


# --------------------------------------------------------------------------------------------
# D.5.2 Bias stability
# --------------------------------------------------------------------------------------------


def smoothing_times(text: Any) -> list[Any]:
    """The smoothing times t of option ``t`` (D.5.2.2: the τ samples are accumulated over t), each a
    time > 0; a t that is zero or negative is refused before anything else is said about it."""
    out = []
    for part in str(text).split(","):
        t = parse_quantity(part.strip(), dimension="s", field="option t")
        if not float(t.to("s").magnitude) > 0:
            raise DataError(None, "option t",
                            f"t = {t:~P}: the smoothing time t must be > 0 (D.5.2.2 accumulates "
                            f"the "
                            "samples over t)", hint='e.g. -o t="10 s, 100 s"')
        out.append(t)
    return out


class BiasStabilityD52(GbtItem):
    """GB/T 45570—2025 D.5.2 零偏稳定性 (bias stability), eq. (D.41).

    Samples are accumulated over t (10 s and 100 s unless another ``t`` is given) and
    B_s = (1/(tK))·std(N'_i) (Bessel).  Type A: the sampling uncertainty of a standard
    deviation of m values, u = B_s/√(2(m − 1)), ν = m − 1.  Type B: scale factor, time base.
    """

    item = "D.5.2"
    title = "Bias stability (零偏稳定性)"
    clause = "D.5.2"
    metrics = (Metric("Bs", "bias stability", "B_s", "deg/h", "D.5.2.3", "D.41"),)
    requires = (STATIC,)
    equipment = BIAS_EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("t", "10 s, 100 s", None, "smoothing times t, comma-separated (D.5.2.2)"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        # refuse a bad t before acquiring
        smoothing_times(options.get("t", self.options[1].default))
        return BiasD51().sequence(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        times = smoothing_times(opts["t"])
        seg, series, conv, raw = static_input(type(self), campaign, opts)
        tau0 = float(series.interval.to("s").magnitude)
        results = []
        for t in times:
            ts = float(t.to("s").magnitude)
            factor = ts / tau0
            if abs(factor - round(factor)) > 1e-9 or round(factor) < 1:
                raise ProcedureError(f"D.5.2: t = {t:~P} is not a whole number of sampling "
                                     f"intervals τ = {tau0:g} s")
            factor = int(round(factor))
            m = raw.size // factor
            if m < 3:
                raise DataError(seg.file, "output",
                                f"a {series.duration.to('s'):~.0fP} record gives only {m} "
                                f"values of t = {ts:g} s; D.41 needs at least 3",
                                hint="record longer (1 h)")
            sd, m = allan.block_std(raw, factor)
            Bs = sd * conv.magnitude
            label = f"{ts:g} s"
            metric = Metric(f"Bs_{ts:g}s", msg("bias stability (t = {t})", t=label),
                            f"B_s({label})", "deg/h",
                            "D.5.2.3", "D.41")
            if not Bs > 0 and conv.output_kind == "pulse" and np.ptp(raw) > 0:
                # the counts vary sample to sample but every t-block holds the same whole number of
                # pulses: an undithered counter at a steady rate hides the noise (as D.5.6)
                reason = msg("every {t} block holds the same whole number of pulses (an undithered "
                             "counter at a steady rate): the bias noise over {t} is below one "
                             "pulse, {p:.3g} °/h, and cannot be measured",
                             t=label, p=conv.magnitude / factor)
                results.append(Result(metric, Q_(0.0, "deg/h"), reportable=False, reason=reason,
                                      earth_rate="not applicable"))
                continue
            if not Bs > 0 and quantization_of(campaign, conv, raw).q <= 0:
                raise DataError(seg.file, "output",
                                "the output does not vary at all (zero variance); "
                                "is the gyro powered and the counter connected?")
            # a rounded output coarser than its noise may not vary at all: B_s = 0, and the rounding
            # row (up to q/2) covers what it hides
            rows = [BudgetRow.type_a(msg("sampling of the standard deviation of {m} values", m=m),
                                     "B_s/√(2(m−1))",
                                     Q_(Bs / math.sqrt(2 * (m - 1)), "deg/h"), m - 1)]
            rows += scale_factor_row(conv, Bs, "deg/h")
            rows += timebase_row(campaign, Bs, "deg/h", "B_s")
            rows += quantization_rows_std(campaign, conv, raw, factor)
            budget = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
            results.append(Result(metric, Q_(Bs, "deg/h"), budget.combined, budget, note=f"m = {m}",
                                  earth_rate="not applicable"))
        warnings = duration_warnings(series, Q_(1, "h"), "D.5.1.2 c)")
        return Outcome(STANDARD, self.item, self.title, self.clause, results, warnings=warnings,
                       segments=[seg.id], options=opts_text(opts))


# --------------------------------------------------------------------------------------------
# D.5.3 Bias repeatability, D.5.4 temperature sensitivity, D.5.5 magnetic sensitivity
# --------------------------------------------------------------------------------------------


class BiasRepeatabilityD53(GbtItem):
    """GB/T 45570—2025 D.5.3 零偏重复性 (bias repeatability), eq. (D.42).

    Q ≥ 7 biases B_oi, each by D.5.1 (eq. D.40) on its own power-on (segments of kind
    ``static-repeat`` with condition ``run`` = 1 … Q), and B_r = Bessel standard deviation
    of them.  Type A: from the χ² distribution of a variance with Q − 1 degrees of freedom,
    u(B_r) = (s_upper − B_r)/2 with s_upper the 97.7 % upper confidence limit (the linear
    B_r/√(2(Q − 1)) under-covers at small Q); the within-run scatter is part of what D.42
    measures.  Type B: quantization, scale factor.
    """

    item = "D.5.3"
    title = "Bias repeatability (零偏重复性)"
    clause = "D.5.3"
    metrics = (Metric("Br", "bias repeatability", "B_r", "deg/h", "D.5.3.3", "D.42"),)
    requires = (SegmentRequirement("static-repeat",
                                   "Q ≥ 7 power-ons, each as D.5.1.2 (condition run = i)",
                                   conditions={"orientation": "", "run": ""},
                                   columns={"output": OUTPUT_UNITS},
                                   min_count=7),)
    equipment = BIAS_EQUIPMENT
    options = (Option("Q", 7, None, "number of repeats (≥ 7) for the sequence", minimum=2),
               Option("batches", 20, None, "batch means per run for each bias's type A uncertainty",
                      minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        q = int(options.get("Q", 7))
        return [Step(f"repeat-{i}", "static-repeat",
                     f"power-on {i} of {q}: as D.5.1.2, 1 h at τ = 1 s; then power "
                     "off for at least one working time (D.5.3.2)", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up", "run": i}) for i in range(1, q + 1)]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = segments_of(type(self), campaign, "static-repeat", 7, "Q ≥ 7 power-ons (D.5.3.2)")
        ests = [segment_bias(s, campaign, int(opts["batches"])) for s in segs]
        b = [e.B0 for e in ests]
        Q = len(b)
        Br = F.bias_repeatability_d42(b)
        if not Br > 0 and not max(e.hw_q for e in ests) > 0:
            raise DataError(campaign.source, "segments",
                            "all Q biases are identical; B_r = 0 cannot be right")
        # identical biases from a quantized output: the rounding hides the spread (not reportable
        # below)
        # a standard deviation of few values: its sampling distribution (χ²) is skewed, and
        # s ± k·s/√(2(Q−1)) covers σ in only ≈ 92 % of cases at Q = 7 (measured: 93.5 % of 200
        # devices). The row is set from the χ² bound instead: s + 2u is the 97.7 % upper confidence
        # limit s·√((Q−1)/χ²₀.₀₂₃(Q−1)), entered with ν = ∞ (its size already carries the coverage)
        upper = F.std_upper_limit(Br, Q)
        rows = [BudgetRow.type_a(msg("sampling of the standard deviation of Q = {Q} biases (χ² "
                                     "bound)", Q=Q),
                                 "(s_{upper} − B_r)/2", Q_((upper - Br) / 2.0, "deg/h"), math.inf,
                                 note=msg("97.7 % upper limit of σ from Q − 1 = {dof} degrees of "
                                          "freedom: {upper:.3g} °/h; "
                                          "the linear s/√(2(Q−1)) = {lin:.3g} °/h", dof=Q - 1,
                                          upper=upper,
                                          lin=Br / math.sqrt(2 * (Q - 1))))]
        hw_q = max(e.hw_q for e in ests)
        reason = ""
        if hw_q > 0:
            # |std(B + e) − std(B)| ≤ std(e) ≤ max|e|: each bias's rounding error moves B_r by at
            # most it
            rows.append(BudgetRow.type_b(msg("quantization of each bias (the D.5.1 row), through "
                                             "the standard deviation"),
                                         "max|δB₀|", Q_(hw_q, "deg/h"), distribution="uniform",
                                         note=msg("|Δs| ≤ std of the biases' rounding errors ≤ "
                                                  "their largest bound")))
            if hw_q >= Br:
                reason = msg("the output's quantization can move each bias by up to {q:.3g} °/h, "
                             "as much as the measured spread B_r = {Br:.3g} °/h: the repeatability "
                             "cannot be told from the rounding", q=hw_q, Br=Br)
        rows += scale_factor_row(ests[0].conv, Br, "deg/h")
        budget = UncertaintyBudget("B_r", "deg/h", rows, coverage=COVERAGE)
        # D.42 measures the scatter of the D.40 biases as they are, each a mean over its own record:
        # the within-run noise of each mean is part of it (interpretations.md, D.5.3).  Stated
        # beside
        # it: that share, and the turn-on scatter left when it is removed (one-way analysis of
        # variance)
        w = float(np.mean([e.u_A**2 for e in ests]))
        turn_on = (msg("turn-on scatter without it √(B_r² − mean u_A²) = {s:.3g} °/h",
                       s=math.sqrt(Br**2 - w))
                   if Br**2 > w
                   else msg("the turn-on scatter is not resolved from it (B_r² ≤ mean u_A²)"))
        res = Result(self.metrics[0], Q_(Br, "deg/h"), budget.combined, budget,
                     note=msg("Q = {Q}; within-run noise of each bias √(mean u_A²) = {w:.3g} °/h, "
                              "part of D.42; {turn_on}",
                              Q=Q, w=math.sqrt(w), turn_on=turn_on), earth_rate="not applicable",
                     reportable=not reason, reason=reason)
        warnings = [msg("B_r is NOT REPORTABLE: {reason}", reason=reason)] if reason else []
        table = TableSpec("biases", msg("Bias of each power-on (D.40)"), [msg("run"),
                                                                          msg("segment"),
                                                                          "B₀ (°/h)", "u_A (°/h)"],
                          [[s.conditions.get("run", i + 1), s.id, f"{e.B0:.5f}", f"{e.u_A:.2g}"]
                           for i, (s, e) in enumerate(zip(segs, ests))])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table],
                       warnings=warnings,
                       segments=[s.id for s in segs], options=opts_text(opts))


REPEATS_OPTION = Option("repeats", 7, None,
                        "D.5.3 power-ons planned with this item to measure the turn-on "
                        "scatter of the bias (0: none; then give device.bias_repeatability)",
                        minimum=0)


class BiasTemperatureSensitivityD54(GbtItem):
    """GB/T 45570—2025 D.5.4 零偏温度灵敏度 (bias temperature sensitivity), eq. (D.43).

    B_t = max_i |(B_i − B_00)/(T_i − T_0)|: B_i by D.5.1 at each temperature point (segments of
    kind ``static-temperature`` with condition ``temperature``), B_00/T_0 at room temperature —
    the point nearest the ``room`` option, which must lie within 6.1.1's 15 °C … 35 °C.
    Budget of the maximising point: the two biases' type A (batch means), the chamber's
    temperature uncertainty on T_i − T_0, the scale factor.
    """

    item = "D.5.4"
    title = "Bias temperature sensitivity (零偏温度灵敏度)"
    clause = "D.5.4"
    metrics = (Metric("Bt", "bias temperature sensitivity", "B_t", "deg/h/delta_degC", "D.5.4.3",
                      "D.43"),)
    requires = (SegmentRequirement("static-temperature",
                                   "1 h at each temperature point after ≥ 2 h soak",
                                   conditions={"orientation": "", "temperature": "degC"},
                                   columns={"output": OUTPUT_UNITS}, min_count=3),)
    equipment = BIAS_EQUIPMENT + (EquipmentRequirement("chamber",
                                                       "temperature chamber, control better than "
                                                       "±2 °C"),)
    options = (Option("temperatures", "-40 °C, 20 °C, 60 °C", None,
                      "temperature points for the sequence: both limits and room temperature "
                      "(D.5.4.2 b))"),
               Option("room", "20 °C", "degC",
                      "room temperature T0: the nearest point is the reference"),
               Option("batches", 20, None,
                      "batch means per point for each bias's type A uncertainty", minimum=2),
               REPEATS_OPTION)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures",
                                                    "-40 °C, 20 °C, 60 °C")).split(",")]
        return [Step(f"temperature-{i + 1}", "static-temperature",
                     f"power off, soak ≥ 2 h at {t}, then as D.5.1.2 "
                     "record 1 h (D.5.4.2 c))", Q_(1, "h"), Q_(1, "s"), {"orientation": "IRA up",
                                                                         "temperature": t},
                     warmup=Q_(2, "h")) for i, t in enumerate(temps)] + repeat_steps(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = segments_of(type(self), campaign, "static-temperature", 3,
                            "two limit temperatures and room temperature (D.5.4.2 b))")
        temps = [float(s.condition("temperature", "degC").to("degC").magnitude) for s in segs]
        room = float(opts["room"].to("degC").magnitude)
        i0 = int(np.argmin([abs(t - room) for t in temps]))
        if not 15.0 <= temps[i0] <= 35.0:
            raise DataError(campaign.source, f"segments.{segs[i0].id}.conditions.temperature",
                            f"no point at room temperature: the nearest is {temps[i0]:g} °C "
                            f"(6.1.1: 15 °C … 35 °C)")
        ests = [segment_bias(s, campaign, int(opts["batches"])) for s in segs]
        for i, t in enumerate(temps):
            if i != i0 and abs(t - temps[i0]) < 1.0:
                raise DataError(campaign.source, f"segments.{segs[i].id}.conditions.temperature",
                                f"{t:g} °C is within 1 °C of room temperature {temps[i0]:g} °C; "
                                f"D.43 divides by T_i − T0")
        Bt, imax = F.bias_temperature_sensitivity_d43([e.B0 for e in ests], temps, i0)
        dT = temps[imax] - temps[i0]
        eA, e0 = ests[imax], ests[i0]
        uA = math.hypot(eA.u_A, e0.u_A) / abs(dT)
        nu = uA**4 / ((eA.u_A / dT) ** 4 / eA.nu_A
                      + (e0.u_A / dT) ** 4 / e0.nu_A) if uA > 0 else math.inf
        rows = [BudgetRow.type_a(msg("scatter of B_i and B_00 (batch means)"),
                                 "√(u²(B_i)+u²(B_00))/|ΔT|",
                                 Q_(uA, "deg/h/delta_degC"), nu)]
        # D.5.4.2 c): off between points, so every B_i is a power-on of its own and differs from
        # B(T_i) by the turn-on scatter σ_on that D.5.3 measures (interpretations.md, D.5.4)
        on = bias_turn_on(campaign, int(opts["batches"]), msg(
            "each temperature point is a power-on of its own (D.5.4.2 c)), so B_i and B_00 also "
            "differ by the turn-on scatter of the bias, which this campaign does not measure: "
            "record D.5.3's power-ons with it or state the bias repeatability of an earlier "
            "D.5.3{hint}",
            hint=hint(" (static-repeat runs, as metro plan -s gbt45570 -i D.5.4 lists them, or "
                      "[device] bias_repeatability)")))
        s_on, nu_on, rep_note = on.sigma, on.nu, on.note
        u_on = math.sqrt(2.0) * s_on / abs(dT)
        u_tot = math.hypot(uA, u_on)
        den = (uA**4 / nu if uA > 0 else 0.0) + (u_on**4 / nu_on if u_on > 0 else 0.0)
        nu_tot = u_tot**4 / den if den > 0 else math.inf  # σ_on of D.5.3 has ν = ∞
        # D.43 takes the largest of several noisy |slopes|: corrected for the selection bias about a
        # smoothed B(T) (interpretations.md, D.5.4); the spread of the maximum replaces one slope's
        # u
        from metro.api import max_slope_selection, selection_note, selection_rows

        sel = max_slope_selection([e.B0 for e in ests], [math.hypot(e.u_A, s_on) for e in ests],
                                  temps, i0,
                                  relative=False)
        if len(temps) > 2:
            rows = [BudgetRow.type_a(msg("B_i at every T_i and B_00 through the maximum of the "
                                         "slopes (Monte Carlo "
                                         "about the smoothed B(T))"), "s(max_i |ΔB_i/ΔT_i|)",
                                     Q_(max(sel.s, u_tot), "deg/h/delta_degC"), nu_tot,
                                     note=join("; ",
                                               [msg("the maximising point alone gives {u:.3g} "
                                                    "(°/h)/°C", u=u_tot)]
                                               + ([on.describe(u_on,
                                                               "(°/h)/°C")] if on.known
                                                  and s_on > 0 else [])))]
            rows += selection_rows(sel, len(temps) - 1, "deg/h/delta_degC")
            Bt = max(sel.value, 0.0)
        if eA.u_q > 0 or e0.u_q > 0:
            rows.append(BudgetRow.type_b(msg("quantization of B_i and B_00 (the D.5.1 rows)"),
                                         "√(u_q²(B_i)+u_q²(B_00))/|ΔT|",
                                         Q_(math.hypot(eA.u_q, e0.u_q) / abs(dT),
                                            "deg/h/delta_degC"),
                                         distribution="normal", k=1.0))
        uT = delta_temperature_u(campaign)
        if uT is not None:
            rows.append(BudgetRow.type_b(msg("chamber temperature T_i and T_0 ({equipment})",
                                             equipment=uT[1]), "√2·u(T)",
                                         Q_(math.sqrt(2) * uT[0], "K"), distribution="normal",
                                         k=1.0,
                                         sensitivity=Q_(Bt / abs(dT), "deg/h/delta_degC/K"),
                                         note=msg("∂B_t/∂ΔT = −B_t/ΔT")))
        rows += scale_factor_row(eA.conv, Bt, "deg/h/delta_degC")
        budget = UncertaintyBudget("B_t", "deg/h/delta_degC", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Bt, "deg/h/delta_degC"), budget.combined, budget,
                     note=join("; ", [msg("largest at T = {T:g} °C against T0 = {T0:g} °C",
                                          T=temps[imax], T0=temps[i0])]
                               + ([selection_note(sel, 1.0,
                                                  '(°/h)/°C')] if len(temps) > 2 else [])),
                     earth_rate="not applicable", reportable=on.known, reason=rep_note)
        plot, table = _bias_temperature_figures(segs, temps, ests, i0, imax, Bt)
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot],
                       tables=[table],
                       segments=[s.id for s in segs], options=opts_text(opts))


def _bias_temperature_figures(segs: list[Segment], temps: list[float], ests: list[Any], i0: int,
                              imax: int, Bt: float) -> tuple[PlotSpec, TableSpec]:
    """D.5.4's plot of the bias against temperature and its table of the points."""
    eA, e0 = ests[imax], ests[i0]
    order = np.argsort(temps)
    plot = PlotSpec("bias_temperature", msg("Bias against temperature (D.5.4)"), "T (°C)",
                    "B₀ (°/h)",
                    [{"label": "B₀(T) (D.40)", "x": [temps[i] for i in order],
                      "y": [ests[i].B0 for i in order],
                      "yerr": [2 * ests[i].u_A for i in order], "style": "o"},
                     {"label": msg("slope of the largest |ΔB/ΔT| = {Bt:.3g} °/h/°C", Bt=Bt),
                      "x": [temps[i0], temps[imax]], "y": [e0.B0, eA.B0], "style": "--"}])
    table = TableSpec("bias_points", msg("Bias at each temperature point"),
                      [msg("segment"), "T (°C)", "B₀ (°/h)", "|ΔB/ΔT| ((°/h)/°C)"],
                      [[s.id, f"{t:g}", f"{e.B0:.5f}", msg("room (T0)") if i == i0 else
                        f"{abs((e.B0 - e0.B0) / (t - temps[i0])):.3g}"]
                       for i, (s, t, e) in enumerate(zip(segs, temps, ests))])
    return plot, table


def repeat_steps(options: Mapping[str, Any]) -> list[Step]:
    """D.5.3's power-ons, planned with D.5.4 / D.5.5 so that their turn-on scatter is measured on
    the
    same campaign (``repeats`` = Q; 0: none — then give ``device.bias_repeatability``).  Shared with
    D.5.3's own steps when both items run (the same kind and conditions are measured once)."""
    q = int(options.get("repeats", 7))
    return BiasRepeatabilityD53().sequence({"Q": q}) if q > 0 else []


class BiasMagneticSensitivityD55(GbtItem):
    """GB/T 45570—2025 D.5.5 零偏磁场灵敏度 (bias magnetic sensitivity), eq. (D.44).

    For each axis (IRA, XRA, YRA): B_h = |B_0+ − B_0−| / (2 H_b), the biases by D.5.1 with the
    field H_b applied forward and reversed (segments of kind ``static-field`` with conditions
    ``field_axis`` and a signed ``field``, 10 min each).  Budget: the two biases' type A, the
    field generator's uniformity (5 %, uniform) and calibration, the scale factor.
    """

    item = "D.5.5"
    title = "Bias magnetic sensitivity (零偏磁场灵敏度)"
    clause = "D.5.5"
    metrics = tuple(Metric(f"Bh_{ax}", f"bias magnetic sensitivity, field along {ax}", f"B_h({ax})",
                           "deg/h/mT", "D.5.5.3", "D.44") for ax in ("IRA", "XRA", "YRA"))
    requires = (SegmentRequirement("static-field",
                                   "10 min with +H_b and with −H_b along each of IRA, XRA, YRA",
                                   conditions={"orientation": "", "field_axis": "", "field": "mT"},
                                   columns={"output": OUTPUT_UNITS}, min_count=6),)
    equipment = BIAS_EQUIPMENT + (EquipmentRequirement("field_generator",
                                                       "DC magnetic field generator, uniformity "
                                                   "better than 5 % over the gyro (D.5.5.1 b))"),)
    options = (Option("H_b", "1 mT", "mT", "field strength for the sequence"),
               Option("batches", 20, None,
                      "batch means per segment for each bias's type A uncertainty", minimum=2),
               REPEATS_OPTION)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        H = parse_quantity(options.get("H_b", "1 mT"), dimension="mT").to("mT").magnitude
        steps = []
        for ax in ("IRA", "XRA", "YRA"):
            for sign, word in ((1, "forward"), (-1, "reversed")):
                steps.append(Step(f"field-{ax}-{'plus' if sign > 0 else 'minus'}", "static-field",
                                  f"{word} field of {H:g} mT along {ax}; bias as D.5.1.2 for 10 "
                                  f"min (D.5.5.2)",
                                  Q_(10, "min"), Q_(1, "s"),
                                  {"orientation": "IRA up", "field_axis": ax,
                                   "field": f"{sign * H:g} mT"}))
        return steps + repeat_steps(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = segments_of(type(self), campaign, "static-field", 6, "±H_b along IRA, XRA and YRA")
        gen = campaign.equipment_for("field_generator")
        uniformity = 0.05
        if gen is not None and "uniformity" in gen.properties:
            uniformity = float(gen.prop("uniformity", "percent",
                                        source=campaign.source).to("").magnitude)
        results, rows_table, used = [], [], []
        # each field record is taken "by D.5.1.2" — a power-on of its own: the two biases differ by
        # √2·σ_on besides their noise (interpretations.md, "D.5.5 — each field record a power-on")
        on = bias_turn_on(campaign, int(opts["batches"]), msg(
            "each field record is a power-on of its own (\"by D.5.1.2\"), so B_0+ and B_0− also "
            "differ by the turn-on scatter of the bias, which this campaign does not measure: "
            "record D.5.3's power-ons with it or state the bias repeatability of an earlier "
            "D.5.3{hint}",
            hint=hint(" (static-repeat runs, as metro plan -s gbt45570 -i D.5.5 lists them, or "
                      "[device] bias_repeatability)")))
        s_on, nu_on = on.sigma, on.nu
        from metro.api import abs_change, abs_change_note, abs_change_rows

        for metric, ax in zip(self.metrics, ("IRA", "XRA", "YRA")):
            mine = [s for s in segs if str(s.condition("field_axis")).upper() == ax]
            fields = [float(s.condition("field", "mT").to("mT").magnitude) for s in mine]
            plus = [s for s, h in zip(mine, fields) if h > 0]
            minus = [s for s, h in zip(mine, fields) if h < 0]
            if not plus or not minus:
                raise DataError(campaign.source, "segments",
                                f"D.5.5 needs a forward (+) and a reversed (−) field segment along "
                                f"{ax}; found {len(plus)} forward and {len(minus)} reversed")
            sp, sm = plus[0], minus[0]
            Hp = float(sp.condition("field", "mT").to("mT").magnitude)
            Hm = -float(sm.condition("field", "mT").to("mT").magnitude)
            Hb = 0.5 * (Hp + Hm)
            ep = segment_bias(sp, campaign, int(opts["batches"]))
            em = segment_bias(sm, campaign, int(opts["batches"]))
            Bh = F.bias_magnetic_sensitivity_d44(ep.B0, em.B0, Hb)
            uA = math.hypot(ep.u_A, em.u_A) / (2.0 * Hb)
            nu = (uA**4 / ((ep.u_A / (2 * Hb)) ** 4 / ep.nu_A + (em.u_A / (2 * Hb)) ** 4 / em.nu_A)
                  if uA > 0 else math.inf)
            rows = [BudgetRow.type_a(msg("scatter of B_0+ and B_0− (batch means)"),
                                     "√(u²₊+u²₋)/(2H_b)",
                                     Q_(uA, "deg/h/mT"), nu)]
            u_noise2 = uA**2
            if s_on > 0:
                u_on = Q_(math.sqrt(2.0) * s_on / (2.0 * Hb), "deg/h/mT")
                u_noise2 += u_on.magnitude**2
                rows.append(BudgetRow.type_b(on.source(), "√2·σ_on/(2H_b)", u_on,
                                             distribution="normal", k=1.0)
                            if on.stated else BudgetRow.type_a(on.source(), "√2·σ_on/(2H_b)", u_on,
                                                               nu_on))
            if ep.u_q > 0 or em.u_q > 0:
                u_noise2 += (math.hypot(ep.u_q, em.u_q) / (2.0 * Hb)) ** 2
                rows.append(BudgetRow.type_b(msg("quantization of B_0+ and B_0− (the D.5.1 rows)"),
                                             "√(u_q²₊+u_q²₋)/(2H_b)",
                                             Q_(math.hypot(ep.u_q, em.u_q) / (2.0 * Hb),
                                                "deg/h/mT"),
                                             distribution="normal", k=1.0))
            # D.44 takes |B_0+ − B_0−|: the absolute value of a noisy difference reads high where
            # the field
            # changes the bias by less than the noise (a folded normal); corrected in closed form,
            # the printed
            # value kept in the note (interpretations.md, "D.5.5 / D.6.3 / D.6.4 — the absolute
            # value of one
            # noisy difference")
            sel = abs_change((ep.B0 - em.B0) / (2.0 * Hb), math.sqrt(u_noise2))
            rows += abs_change_rows(sel, "deg/h/mT", math.sqrt(u_noise2))
            Bh = max(sel.value, 0.0)
            rows += _field_rows(gen, uniformity, Bh)
            rows += scale_factor_row(ep.conv, Bh, "deg/h/mT")
            budget = UncertaintyBudget(metric.symbol, "deg/h/mT", rows, coverage=COVERAGE)
            warn = ""
            if abs(Hp - Hm) > 0.01 * Hb:
                warn = msg("forward {p:g} mT and reversed {m:g} mT differ; H_b = their mean", p=Hp,
                           m=Hm)
            warn = join("; ", ([warn] if warn else []) + ([abs_change_note(sel, 1.0,
                                                                           "(°/h)/mT")] if sel.bias
                                                          else []))
            results.append(Result(metric, Q_(Bh, "deg/h/mT"), budget.combined, budget, note=warn,
                                  earth_rate="not applicable", reportable=on.known, reason=on.note))
            rows_table.append([ax, f"{Hb:g}", f"{ep.B0:.5f}", f"{em.B0:.5f}", f"{sel.printed:.4g}"])
            used += [sp.id, sm.id]
        table = TableSpec("field_biases", msg("Biases with the field forward and reversed (D.5.5)"),
                          [msg("axis"), "H_b (mT)", "B₀₊ (°/h)", "B₀₋ (°/h)", "B_h ((°/h)/mT)"],
                          rows_table)
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[table],
                       segments=used,
                       options=opts_text(opts))


def _field_rows(gen: Any, uniformity: float, Bh: float) -> list[BudgetRow]:
    """D.5.5's type B rows of the field: its uniformity over the gyro and the generator's
    calibration, each relative, on B_h."""
    rows: list[BudgetRow] = []
    rows.append(BudgetRow.type_b(msg("field uniformity over the gyro"), "ΔH/H",
                                 Q_(uniformity, ""),
                                 distribution="uniform", sensitivity=Q_(Bh, "deg/h/mT"),
                                 note=msg("D.5.5.1 b): better than 5 %")))
    cal = gen.calibration if gen is not None else None
    if cal is not None and cal.uncertainty.dimensionless:
        rows.append(BudgetRow.from_calibration(
            msg("field strength ({equipment})", equipment=gen.describe()), "u_rel(H_b)",
            gen.calibration, sensitivity=Q_(Bh, "deg/h/mT")))
    return rows


PROCEDURES = (BiasD51, BiasStabilityD52, BiasRepeatabilityD53, BiasTemperatureSensitivityD54,
              BiasMagneticSensitivityD55, AngleRandomWalkD56)

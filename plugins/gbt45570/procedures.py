"""GB/T 45570—2025 appendix D procedures: D.5.1 bias, D.5.2 bias stability, D.5.6 ARW.

Each class is one item; its docstring names the clause and equations, and the formulas
live in :mod:`.formulas`.  Procedures orchestrate: pick segments, convert units at the
boundary, call the formulas and the core's shared maths, and build the budgets.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (
    OUTPUT_UNITS,
    Q_,
    BudgetRow,
    Campaign,
    Coverage,
    DataError,
    EquipmentRequirement,
    Metric,
    Option,
    Outcome,
    PlotSpec,
    Procedure,
    ProcedureError,
    RateConversion,
    Result,
    RunContext,
    Segment,
    SegmentRequirement,
    Step,
    TableSpec,
    UncertaintyBudget,
    allan,
    gyro_output,
    hint,
    join,
    msg,
    parse_quantity,
)

from . import formulas as F

STANDARD = "gbt45570"
#: χ²/ν of the D.45 fit beyond which its model is taken not to hold (interpretations.md,
#: "D.5.6 — when the D.45 model does not hold"): on records the model describes χ²/ν of the
#: nested-level GLS fit is mostly 0.4 … 5 (median 1.5); every undithered-counter RWC outside its
#: U had χ²/ν ≥ 11.4 (200 seeds, 4 h records)
D45_MISFIT_LIMIT = 10.0
COVERAGE = Coverage.probability(0.9545)

STATIC = SegmentRequirement(
    kind="static",
    description="gyro at rest on a levelled stable platform, IRA along the local vertical (D.5.1.2)",
    conditions={"orientation": ""},
    columns={"output": OUTPUT_UNITS},
)

_EQUIPMENT = (
    EquipmentRequirement("platform", "levelled stable platform (D.5.1.1 a)); its levelness enters the bias budget"),
    EquipmentRequirement("counter", "gyro test system / counter; its time-base uncertainty enters the budgets"),
)


def _static_segment(proc: type[Procedure], campaign: Campaign, options: Mapping[str, Any]) -> Segment:
    wanted = options.get("segment")
    segs = campaign.find_segments("static")
    if wanted:
        segs = [s for s in segs if s.id == wanted]
        if not segs:
            raise DataError(campaign.source, "segments", f"no static segment with id {wanted!r}")
    if not segs:
        raise DataError(
            campaign.source, "segments",
            f"{proc.qualified_id()} needs a segment of kind \"static\" ({STATIC.description}); none found",
            hint="`metro plan --standard gbt45570 --item " + proc.item + "` shows what to measure",
        )
    seg = segs[0]
    _orientation(seg, campaign)
    return seg


def _static_input(proc: type[Procedure], campaign: Campaign, options: Mapping[str, Any]):
    """The static segment, its output series, the conversion to °/h and the raw samples
    (checked finite) — the common start of every D.5 item."""
    seg = _static_segment(proc, campaign, options)
    series, conv = gyro_output(seg, campaign.device, source=campaign.source)
    raw = np.asarray(series.data.magnitude)
    _check_finite(raw, seg)
    return seg, series, conv, raw


def _orientation(seg: Segment, campaign: Campaign) -> str:
    """'up' or 'down' from the segment's required ``orientation`` condition (D.5.1.2 a))."""
    orient = str(seg.condition("orientation")).strip().lower().replace("ira", "").strip()
    if orient not in ("up", "down"):
        raise DataError(seg.file or campaign.source, f"segments.{seg.id}.conditions.orientation",
                        f"must be \"IRA up\" or \"IRA down\" (D.5.1.2 a)), got {seg.conditions['orientation']!r}")
    return orient


def _timebase_row(campaign: Campaign, measured: float, unit: str, what: str) -> list[BudgetRow]:
    eq = campaign.equipment_for("counter")
    if eq is None or eq.calibration is None:
        return []
    cal = eq.calibration
    if not cal.uncertainty.dimensionless:
        return []
    return [BudgetRow.from_calibration(
        msg("time base of the counter ({equipment})", equipment=eq.describe()), "u_rel(τ)", cal,
        sensitivity=Q_(abs(measured), unit),
        note=msg("{what} ∝ 1/τ; {certificate}", what=what, certificate=cal.certificate),
    )]


def _scale_factor_row(conv: RateConversion, measured: float, unit: str) -> list[BudgetRow]:
    if conv.output_kind == "rate" or conv.relative_u_scale_factor == 0.0:
        return []
    return [BudgetRow.type_b(
        msg("scale factor K used to convert the output"), "u_rel(K)",
        Q_(conv.relative_u_scale_factor, ""), distribution="normal", k=1.0,
        sensitivity=Q_(abs(measured), unit),
        note=msg("K = {K}; result ∝ 1/K", K=f"{conv.scale_factor:~P}"),
    )]


def _check_finite(raw: np.ndarray, seg: Segment) -> None:
    ok = np.isfinite(raw)
    if not ok.all():
        i = int(np.argmin(ok))
        raise DataError(seg.file or f"segment {seg.id}", "output", f"sample {i + 1} is {raw[i]!r}")


# --------------------------------------------------------------------------------------------
# D.5.1 Bias
# --------------------------------------------------------------------------------------------


class BiasD51(Procedure):
    """GB/T 45570—2025 D.5.1 零偏 (bias), eq. (D.40).

    B0 = (1/(τK))·(1/n)ΣN_i − 15.041·sin θ.  For LSB or rate output the first term is the
    mean indicated rate (reading notes).  Type A uncertainty: batch means (``batches``
    equal consecutive batches; u = s_batch/√b, ν = b − 1), which stays honest when the
    noise is correlated.  Type B: scale factor, latitude, levelling of the IRA, time base.
    """

    standard = STANDARD
    item = "D.5.1"
    title = "Bias (零偏)"
    clause = "D.5.1"
    metrics = (Metric("B0", "bias", "B₀", "deg/h", "D.5.1.3", "D.40"),)
    requires = (STATIC,)
    equipment = _EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("batches", 20, None, "number of batch means for the type A uncertainty", minimum=2),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static-1h", "static", "IRA up on the levelled platform; power on, wait the set-up time, "
                     "record 1 h at τ = 1 s; power off (D.5.1.2)", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up"})]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg = _static_segment(type(self), campaign, opts)
        est = segment_bias(seg, campaign, int(opts["batches"]))
        from .repeatability import bias_repeat_row

        rep_rows, rep_note = bias_repeat_row(campaign, int(opts["batches"]), est.u_A)
        budget = UncertaintyBudget("B0", "deg/h", list(est.budget.rows) + rep_rows, coverage=COVERAGE)
        note = msg("earth rate {earth:+.4f} °/h removed ({orientation}, θ = {theta:g}°)", earth=est.earth,
                   orientation=est.orientation, theta=est.theta)
        res = Result(self.metrics[0], Q_(est.B0, "deg/h"), budget.combined, budget,
                     note=join("; ", [note, rep_note]) if rep_note else note, earth_rate="removed")
        warnings = _duration_warnings(est.series, Q_(1, "h"), "D.5.1.2 c)")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], warnings=warnings,
                       segments=[seg.id], options={k: str(v) for k, v in opts.items()})


@attrs.frozen
class BiasEstimate:
    """D.40 applied to one static segment, with its full budget and its type A part."""

    B0: float  # °/h
    u_A: float  # °/h, batch-means standard uncertainty
    nu_A: int
    budget: UncertaintyBudget
    earth: float
    orientation: str
    theta: float
    conv: RateConversion
    series: Any
    u_q: float = 0.0  # °/h, standard uncertainty of B0 from the output's quantization
    hw_q: float = 0.0  # °/h, its half-width (uniform)


def segment_bias(seg: Segment, campaign: Campaign, batches: int = 20) -> BiasEstimate:
    """Bias of one static segment by D.40 (D.5.1.3), with its budget.

    Shared by D.5.1 and the items built on it (D.5.3 repeatability, D.5.4 temperature and
    D.5.5 magnetic sensitivity), which apply "the method of D.5.1.2" to each segment.
    """
    series, conv = gyro_output(seg, campaign.device, source=campaign.source)
    raw = np.asarray(series.data.magnitude)
    _check_finite(raw, seg)
    b = int(batches)
    if raw.size < 2 * b:
        raise DataError(seg.file or f"segment {seg.id}", "output",
                        f"{raw.size} samples are too few for {b} batch means")
    orient = _orientation(seg, campaign)
    theta = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    mean_raw = float(np.mean(raw, dtype=np.float64))
    indicated = mean_raw * conv.magnitude
    earth = F.earth_rate_vertical(theta, orient)
    if conv.output_kind == "pulse":
        B0 = F.bias_d40(mean_raw, float(series.interval.to("s").magnitude),
                        float(conv.scale_factor.to("P/arcsec").magnitude), theta)
        if orient == "down":
            B0 += 2 * F.earth_rate_vertical(theta)
    else:
        B0 = indicated - earth
    # correlated noise (bias instability, rate random walk) makes neighbouring batch means alike, and
    # their scatter understates the mean's u: five long batches are checked against it and taken
    # when they disagree beyond chance (F test, 95 %) (interpretations.md, D.5.1)
    bm = allan.mean_u_batches(raw, b)
    uA, nb = bm.u * conv.magnitude, bm.batches
    note = msg("{nb} batches of {n} samples", nb=nb, n=raw.size // b)
    if bm.correlated:
        note = msg("{n5} batches of {n} samples: the {nb} batch means ({uA:.3g} °/h) are correlated (bias "
                   "instability or random walk), their scatter understates the mean's u", n5=nb, n=raw.size // nb,
                   nb=bm.batches_short, uA=bm.u_short * conv.magnitude)
    rows = [BudgetRow.type_a(msg("scatter of the output (batch means)"), "s_b/√b", Q_(uA, "deg/h"), nb - 1, note=note)]
    rows += _scale_factor_row(conv, indicated, "deg/h")
    lat_u = campaign.site.get("latitude_uncertainty")
    c_theta = F.EARTH_RATE_DEG_PER_H * math.cos(math.radians(theta))
    if lat_u is not None:
        lu = parse_quantity(lat_u, dimension="deg", file=campaign.source, field="site.latitude_uncertainty")
        rows.append(BudgetRow.type_b(msg("site latitude θ"), "u(θ)", lu.to("rad"), distribution="uniform",
                                     sensitivity=Q_(c_theta, "deg/h/rad"), note=msg("∂B0/∂θ = −15.041·cos θ")))
    plat = campaign.equipment_for("platform")
    if plat is not None and "levelness" in plat.properties:
        lev = plat.prop("levelness", "arcsec", source=campaign.source)
        rows.append(BudgetRow.type_b(msg("levelling of the IRA ({equipment})", equipment=plat.describe()), "δ",
                                     lev.to("rad"), distribution="uniform", sensitivity=Q_(c_theta, "deg/h/rad"),
                                     note=msg("horizontal earth rate Ω·cos θ·sin δ leaks into the IRA")))
    rows += _timebase_row(campaign, indicated, "deg/h", msg("indicated rate"))
    q_rows = quantization_rows_mean(campaign, conv, raw, msg("the mean of D.40"))
    rows += q_rows
    budget = UncertaintyBudget("B0", "deg/h", rows, coverage=COVERAGE)
    u_q = float(q_rows[0].contribution.to("deg/h").magnitude) if q_rows else 0.0
    return BiasEstimate(B0, uA, nb - 1, budget, earth, orient, theta, conv, series, u_q, u_q * math.sqrt(3.0))


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
            raise DataError(None, "option t", f"t = {t:~P}: the smoothing time t must be > 0 (D.5.2.2 accumulates the "
                            "samples over t)", hint='e.g. -o t="10 s, 100 s"')
        out.append(t)
    return out


class BiasStabilityD52(Procedure):
    """GB/T 45570—2025 D.5.2 零偏稳定性 (bias stability), eq. (D.41).

    Samples are accumulated over t (10 s and 100 s unless another ``t`` is given) and
    B_s = (1/(tK))·std(N'_i) (Bessel).  Type A: the sampling uncertainty of a standard
    deviation of m values, u = B_s/√(2(m − 1)), ν = m − 1.  Type B: scale factor, time base.
    """

    standard = STANDARD
    item = "D.5.2"
    title = "Bias stability (零偏稳定性)"
    clause = "D.5.2"
    metrics = (Metric("Bs", "bias stability", "B_s", "deg/h", "D.5.2.3", "D.41"),)
    requires = (STATIC,)
    equipment = _EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("t", "10 s, 100 s", None, "smoothing times t, comma-separated (D.5.2.2)"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        smoothing_times(options.get("t", self.options[1].default))  # refuse a bad t before acquiring
        return BiasD51().sequence(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        times = smoothing_times(opts["t"])
        seg, series, conv, raw = _static_input(type(self), campaign, opts)
        tau0 = float(series.interval.to("s").magnitude)
        results = []
        for t in times:
            ts = float(t.to("s").magnitude)
            factor = ts / tau0
            if abs(factor - round(factor)) > 1e-9 or round(factor) < 1:
                raise ProcedureError(f"D.5.2: t = {t:~P} is not a whole number of sampling intervals τ = {tau0:g} s")
            factor = int(round(factor))
            m = raw.size // factor
            if m < 3:
                raise DataError(seg.file, "output", f"a {series.duration.to('s'):~.0fP} record gives only {m} "
                                f"values of t = {ts:g} s; D.41 needs at least 3", hint="record longer (1 h)")
            sd, m = allan.block_std(raw, factor)
            Bs = sd * conv.magnitude
            label = f"{ts:g} s"
            metric = Metric(f"Bs_{ts:g}s", msg("bias stability (t = {t})", t=label), f"B_s({label})", "deg/h",
                            "D.5.2.3", "D.41")
            if not Bs > 0 and conv.output_kind == "pulse" and np.ptp(raw) > 0:
                # the counts vary sample to sample but every t-block holds the same whole number of
                # pulses: an undithered counter at a steady rate hides the noise (as D.5.6)
                reason = msg("every {t} block holds the same whole number of pulses (an undithered counter at a steady "
                             "rate): the bias noise over {t} is below one pulse, {p:.3g} °/h, and cannot be measured",
                             t=label, p=conv.magnitude / factor)
                results.append(Result(metric, Q_(0.0, "deg/h"), reportable=False, reason=reason,
                                      earth_rate="not applicable"))
                continue
            if not Bs > 0 and quantization_of(campaign, conv, raw).q <= 0:
                raise DataError(seg.file, "output", "the output does not vary at all (zero variance); "
                                "is the gyro powered and the counter connected?")
            # a rounded output coarser than its noise may not vary at all: B_s = 0, and the rounding
            # row (up to q/2) covers what it hides
            rows = [BudgetRow.type_a(msg("sampling of the standard deviation of {m} values", m=m), "B_s/√(2(m−1))",
                                     Q_(Bs / math.sqrt(2 * (m - 1)), "deg/h"), m - 1)]
            rows += _scale_factor_row(conv, Bs, "deg/h")
            rows += _timebase_row(campaign, Bs, "deg/h", "B_s")
            rows += quantization_rows_std(campaign, conv, raw, factor)
            budget = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
            results.append(Result(metric, Q_(Bs, "deg/h"), budget.combined, budget, note=f"m = {m}",
                                  earth_rate="not applicable"))
        warnings = _duration_warnings(series, Q_(1, "h"), "D.5.1.2 c)")
        return Outcome(STANDARD, self.item, self.title, self.clause, results, warnings=warnings,
                       segments=[seg.id], options={k: str(v) for k, v in opts.items()})


# --------------------------------------------------------------------------------------------
# D.5.3 Bias repeatability, D.5.4 temperature sensitivity, D.5.5 magnetic sensitivity
# --------------------------------------------------------------------------------------------


def _segments_of(proc: type[Procedure], campaign: Campaign, kind: str, need: int, what: str) -> list[Segment]:
    segs = campaign.find_segments(kind)
    if len(segs) < need:
        raise DataError(
            campaign.source, "segments",
            f"{proc.qualified_id()} needs at least {need} segments of kind \"{kind}\" ({what}); found {len(segs)}",
            hint=f"`metro plan --standard gbt45570 --item {proc.item}` lists them",
        )
    return segs


class BiasRepeatabilityD53(Procedure):
    """GB/T 45570—2025 D.5.3 零偏重复性 (bias repeatability), eq. (D.42).

    Q ≥ 7 biases B_oi, each by D.5.1 (eq. D.40) on its own power-on (segments of kind
    ``static-repeat`` with condition ``run`` = 1 … Q), and B_r = Bessel standard deviation
    of them.  Type A: from the χ² distribution of a variance with Q − 1 degrees of freedom,
    u(B_r) = (s_upper − B_r)/2 with s_upper the 97.7 % upper confidence limit (the linear
    B_r/√(2(Q − 1)) under-covers at small Q); the within-run scatter is part of what D.42
    measures.  Type B: quantization, scale factor.
    """

    standard = STANDARD
    item = "D.5.3"
    title = "Bias repeatability (零偏重复性)"
    clause = "D.5.3"
    metrics = (Metric("Br", "bias repeatability", "B_r", "deg/h", "D.5.3.3", "D.42"),)
    requires = (SegmentRequirement("static-repeat", "Q ≥ 7 power-ons, each as D.5.1.2 (condition run = i)",
                                   conditions={"orientation": "", "run": ""}, columns={"output": OUTPUT_UNITS},
                                   min_count=7),)
    equipment = _EQUIPMENT
    options = (Option("Q", 7, None, "number of repeats (≥ 7) for the sequence", minimum=2),
               Option("batches", 20, None, "batch means per run for each bias's type A uncertainty", minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        q = int(options.get("Q", 7))
        return [Step(f"repeat-{i}", "static-repeat", f"power-on {i} of {q}: as D.5.1.2, 1 h at τ = 1 s; then power "
                     "off for at least one working time (D.5.3.2)", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up", "run": i}) for i in range(1, q + 1)]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = _segments_of(type(self), campaign, "static-repeat", 7, "Q ≥ 7 power-ons (D.5.3.2)")
        ests = [segment_bias(s, campaign, int(opts["batches"])) for s in segs]
        b = [e.B0 for e in ests]
        Q = len(b)
        Br = F.bias_repeatability_d42(b)
        if not Br > 0 and not max(e.hw_q for e in ests) > 0:
            raise DataError(campaign.source, "segments", "all Q biases are identical; B_r = 0 cannot be right")
        # identical biases from a quantized output: the rounding hides the spread (not reportable below)
        # a standard deviation of few values: its sampling distribution (χ²) is skewed, and
        # s ± k·s/√(2(Q−1)) covers σ in only ≈ 92 % of cases at Q = 7 (measured: 93.5 % of 200
        # devices). The row is set from the χ² bound instead: s + 2u is the 97.7 % upper confidence
        # limit s·√((Q−1)/χ²₀.₀₂₃(Q−1)), entered with ν = ∞ (its size already carries the coverage)
        upper = F.std_upper_limit(Br, Q)
        rows = [BudgetRow.type_a(msg("sampling of the standard deviation of Q = {Q} biases (χ² bound)", Q=Q),
                                 "(s_{upper} − B_r)/2", Q_((upper - Br) / 2.0, "deg/h"), math.inf,
                                 note=msg("97.7 % upper limit of σ from Q − 1 = {dof} degrees of freedom: {upper:.3g} °/h; "
                                          "the linear s/√(2(Q−1)) = {lin:.3g} °/h", dof=Q - 1, upper=upper,
                                          lin=Br / math.sqrt(2 * (Q - 1))))]
        hw_q = max(e.hw_q for e in ests)
        reason = ""
        if hw_q > 0:
            # |std(B + e) − std(B)| ≤ std(e) ≤ max|e|: each bias's rounding error moves B_r by at most it
            rows.append(BudgetRow.type_b(msg("quantization of each bias (the D.5.1 row), through the standard deviation"),
                                         "max|δB₀|", Q_(hw_q, "deg/h"), distribution="uniform",
                                         note=msg("|Δs| ≤ std of the biases' rounding errors ≤ their largest bound")))
            if hw_q >= Br:
                reason = msg("the output's quantization can move each bias by up to {q:.3g} °/h, as much as the measured "
                             "spread B_r = {Br:.3g} °/h: the repeatability cannot be told from the rounding", q=hw_q, Br=Br)
        rows += _scale_factor_row(ests[0].conv, Br, "deg/h")
        budget = UncertaintyBudget("B_r", "deg/h", rows, coverage=COVERAGE)
        # D.42 measures the scatter of the D.40 biases as they are, each a mean over its own record:
        # the within-run noise of each mean is part of it (interpretations.md, D.5.3).  Stated beside
        # it: that share, and the turn-on scatter left when it is removed (one-way analysis of variance)
        w = float(np.mean([e.u_A**2 for e in ests]))
        turn_on = (msg("turn-on scatter without it √(B_r² − mean u_A²) = {s:.3g} °/h", s=math.sqrt(Br**2 - w))
                   if Br**2 > w else msg("the turn-on scatter is not resolved from it (B_r² ≤ mean u_A²)"))
        res = Result(self.metrics[0], Q_(Br, "deg/h"), budget.combined, budget,
                     note=msg("Q = {Q}; within-run noise of each bias √(mean u_A²) = {w:.3g} °/h, part of D.42; {turn_on}",
                              Q=Q, w=math.sqrt(w), turn_on=turn_on), earth_rate="not applicable",
                     reportable=not reason, reason=reason)
        warnings = [msg("B_r is NOT REPORTABLE: {reason}", reason=reason)] if reason else []
        table = TableSpec("biases", msg("Bias of each power-on (D.40)"), [msg("run"), msg("segment"), "B₀ (°/h)", "u_A (°/h)"],
                          [[s.conditions.get("run", i + 1), s.id, f"{e.B0:.5f}", f"{e.u_A:.2g}"]
                           for i, (s, e) in enumerate(zip(segs, ests))])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table], warnings=warnings,
                       segments=[s.id for s in segs], options={k: str(v) for k, v in opts.items()})


def _delta_temperature_u(campaign: Campaign) -> tuple[float, str] | None:
    """Standard uncertainty (K) of one chamber temperature reading, from the chamber's calibration."""
    ch = campaign.equipment_for("chamber")
    if ch is None or ch.calibration is None:
        return None
    U = ch.calibration.uncertainty
    # an uncertainty is a temperature *difference*: "0.3 K" or "0.3 delta_degC"; "0.3 °C" means the same here
    mag = float(U.magnitude) if str(U.units) in ("degree_Celsius", "degC") else float(U.to("K").magnitude)
    div = ch.calibration.k if ch.calibration.distribution == "normal" else math.sqrt(3.0)
    return mag / div, ch.describe()


REPEATS_OPTION = Option("repeats", 7, None, "D.5.3 power-ons planned with this item to measure the turn-on "
                        "scatter of the bias (0: none; then give device.bias_repeatability)", minimum=0)


class BiasTemperatureSensitivityD54(Procedure):
    """GB/T 45570—2025 D.5.4 零偏温度灵敏度 (bias temperature sensitivity), eq. (D.43).

    B_t = max_i |(B_i − B_00)/(T_i − T_0)|: B_i by D.5.1 at each temperature point (segments of
    kind ``static-temperature`` with condition ``temperature``), B_00/T_0 at room temperature —
    the point nearest the ``room`` option, which must lie within 6.1.1's 15 °C … 35 °C.
    Budget of the maximising point: the two biases' type A (batch means), the chamber's
    temperature uncertainty on T_i − T_0, the scale factor.
    """

    standard = STANDARD
    item = "D.5.4"
    title = "Bias temperature sensitivity (零偏温度灵敏度)"
    clause = "D.5.4"
    metrics = (Metric("Bt", "bias temperature sensitivity", "B_t", "deg/h/delta_degC", "D.5.4.3", "D.43"),)
    requires = (SegmentRequirement("static-temperature", "1 h at each temperature point after ≥ 2 h soak",
                                   conditions={"orientation": "", "temperature": "degC"},
                                   columns={"output": OUTPUT_UNITS}, min_count=3),)
    equipment = _EQUIPMENT + (EquipmentRequirement("chamber", "temperature chamber, control better than ±2 °C"),)
    options = (Option("temperatures", "-40 °C, 20 °C, 60 °C", None,
                      "temperature points for the sequence: both limits and room temperature (D.5.4.2 b))"),
               Option("room", "20 °C", "degC", "room temperature T0: the nearest point is the reference"),
               Option("batches", 20, None, "batch means per point for each bias's type A uncertainty", minimum=2),
               REPEATS_OPTION)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures", "-40 °C, 20 °C, 60 °C")).split(",")]
        return [Step(f"temperature-{i + 1}", "static-temperature", f"power off, soak ≥ 2 h at {t}, then as D.5.1.2 "
                     "record 1 h (D.5.4.2 c))", Q_(1, "h"), Q_(1, "s"), {"orientation": "IRA up", "temperature": t},
                     warmup=Q_(2, "h")) for i, t in enumerate(temps)] + _repeat_steps(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = _segments_of(type(self), campaign, "static-temperature", 3,
                            "two limit temperatures and room temperature (D.5.4.2 b))")
        temps = [float(s.condition("temperature", "degC").to("degC").magnitude) for s in segs]
        room = float(opts["room"].to("degC").magnitude)
        i0 = int(np.argmin([abs(t - room) for t in temps]))
        if not 15.0 <= temps[i0] <= 35.0:
            raise DataError(campaign.source, f"segments.{segs[i0].id}.conditions.temperature",
                            f"no point at room temperature: the nearest is {temps[i0]:g} °C (6.1.1: 15 °C … 35 °C)")
        ests = [segment_bias(s, campaign, int(opts["batches"])) for s in segs]
        for i, t in enumerate(temps):
            if i != i0 and abs(t - temps[i0]) < 1.0:
                raise DataError(campaign.source, f"segments.{segs[i].id}.conditions.temperature",
                                f"{t:g} °C is within 1 °C of room temperature {temps[i0]:g} °C; D.43 divides by T_i − T0")
        Bt, imax = F.bias_temperature_sensitivity_d43([e.B0 for e in ests], temps, i0)
        dT = temps[imax] - temps[i0]
        eA, e0 = ests[imax], ests[i0]
        uA = math.hypot(eA.u_A, e0.u_A) / abs(dT)
        nu = uA**4 / ((eA.u_A / dT) ** 4 / eA.nu_A + (e0.u_A / dT) ** 4 / e0.nu_A) if uA > 0 else math.inf
        rows = [BudgetRow.type_a(msg("scatter of B_i and B_00 (batch means)"), "√(u²(B_i)+u²(B_00))/|ΔT|",
                                 Q_(uA, "deg/h/delta_degC"), nu)]
        # D.5.4.2 c): off between points, so every B_i is a power-on of its own and differs from
        # B(T_i) by the turn-on scatter σ_on that D.5.3 measures (interpretations.md, D.5.4)
        on = _turn_on(campaign, int(opts["batches"]), msg(
            "each temperature point is a power-on of its own (D.5.4.2 c)), so B_i and B_00 also differ by the "
            "turn-on scatter of the bias, which this campaign does not measure: record D.5.3's power-ons with it "
            "or state the bias repeatability of an earlier D.5.3{hint}",
            hint=hint(" (static-repeat runs, as metro plan -s gbt45570 -i D.5.4 lists them, or [device] "
                      "bias_repeatability)")))
        s_on, nu_on, rep_note = on.sigma, on.nu, on.note
        u_on = math.sqrt(2.0) * s_on / abs(dT)
        u_tot = math.hypot(uA, u_on)
        den = (uA**4 / nu if uA > 0 else 0.0) + (u_on**4 / nu_on if u_on > 0 else 0.0)
        nu_tot = u_tot**4 / den if den > 0 else math.inf  # σ_on of D.5.3 has ν = ∞
        # D.43 takes the largest of several noisy |slopes|: corrected for the selection bias about a
        # smoothed B(T) (interpretations.md, D.5.4); the spread of the maximum replaces one slope's u
        from metro.api import max_slope_selection, selection_note, selection_rows

        sel = max_slope_selection([e.B0 for e in ests], [math.hypot(e.u_A, s_on) for e in ests], temps, i0,
                                  relative=False)
        if len(temps) > 2:
            rows = [BudgetRow.type_a(msg("B_i at every T_i and B_00 through the maximum of the slopes (Monte Carlo "
                                         "about the smoothed B(T))"), "s(max_i |ΔB_i/ΔT_i|)",
                                     Q_(max(sel.s, u_tot), "deg/h/delta_degC"), nu_tot,
                                     note=join("; ", [msg("the maximising point alone gives {u:.3g} (°/h)/°C", u=u_tot)]
                                               + ([on.describe(u_on, "(°/h)/°C")] if on.known and s_on > 0 else [])))]
            rows += selection_rows(sel, len(temps) - 1, "deg/h/delta_degC")
            Bt = max(sel.value, 0.0)
        if eA.u_q > 0 or e0.u_q > 0:
            rows.append(BudgetRow.type_b(msg("quantization of B_i and B_00 (the D.5.1 rows)"), "√(u_q²(B_i)+u_q²(B_00))/|ΔT|",
                                         Q_(math.hypot(eA.u_q, e0.u_q) / abs(dT), "deg/h/delta_degC"),
                                         distribution="normal", k=1.0))
        uT = _delta_temperature_u(campaign)
        if uT is not None:
            rows.append(BudgetRow.type_b(msg("chamber temperature T_i and T_0 ({equipment})", equipment=uT[1]), "√2·u(T)",
                                         Q_(math.sqrt(2) * uT[0], "K"), distribution="normal", k=1.0,
                                         sensitivity=Q_(Bt / abs(dT), "deg/h/delta_degC/K"),
                                         note=msg("∂B_t/∂ΔT = −B_t/ΔT")))
        rows += _scale_factor_row(eA.conv, Bt, "deg/h/delta_degC")
        budget = UncertaintyBudget("B_t", "deg/h/delta_degC", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Bt, "deg/h/delta_degC"), budget.combined, budget,
                     note=join("; ", [msg("largest at T = {T:g} °C against T0 = {T0:g} °C", T=temps[imax], T0=temps[i0])]
                               + ([selection_note(sel, 1.0, '(°/h)/°C')] if len(temps) > 2 else [])),
                     earth_rate="not applicable", reportable=on.known, reason=rep_note)
        order = np.argsort(temps)
        plot = PlotSpec("bias_temperature", msg("Bias against temperature (D.5.4)"), "T (°C)", "B₀ (°/h)",
                        [{"label": "B₀(T) (D.40)", "x": [temps[i] for i in order], "y": [ests[i].B0 for i in order],
                          "yerr": [2 * ests[i].u_A for i in order], "style": "o"},
                         {"label": msg("slope of the largest |ΔB/ΔT| = {Bt:.3g} °/h/°C", Bt=Bt),
                          "x": [temps[i0], temps[imax]], "y": [e0.B0, eA.B0], "style": "--"}])
        table = TableSpec("bias_points", msg("Bias at each temperature point"),
                          [msg("segment"), "T (°C)", "B₀ (°/h)", "|ΔB/ΔT| ((°/h)/°C)"],
                          [[s.id, f"{t:g}", f"{e.B0:.5f}", msg("room (T0)") if i == i0 else
                            f"{abs((e.B0 - e0.B0) / (t - temps[i0])):.3g}"]
                           for i, (s, t, e) in enumerate(zip(segs, temps, ests))])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot], tables=[table],
                       segments=[s.id for s in segs], options={k: str(v) for k, v in opts.items()})


@attrs.frozen
class TurnOn:
    """The turn-on scatter of one power-on's bias as an item uses it (:func:`_turn_on`)."""

    sigma: float  #: σ_on, °/h (0 when not known)
    nu: float  #: its degrees of freedom
    known: bool  #: measured on this campaign (D.5.3) or stated (device.bias_repeatability)
    stated: bool  #: from device.bias_repeatability
    note: str  #: why it is not known ("" when known)

    def describe(self, u: float, unit: str) -> str:
        """The budget note on the row √2·σ_on/… of a difference of two power-ons."""
        if self.stated:
            return msg("each record a power-on of its own: with the turn-on scatter σ_on = {s:.4g} °/h stated for the "
                       "device{hint}, {u:.3g} {unit} at the maximising point", s=self.sigma, u=u, unit=unit,
                       hint=hint(" (device.bias_repeatability)"))
        return msg("each B_i a power-on of its own (D.5.4.2 c)): with the turn-on scatter σ_on = {s:.4g} °/h of D.5.3 "
                   "on this campaign (ν = {nu:.3g}), √2·σ_on/|ΔT| = {u:.3g} (°/h)/°C at the maximising point",
                   s=self.sigma, nu=self.nu, u=u)

    def source(self) -> str:
        """The row's source text for D.5.5's √2·σ_on/(2H_b)."""
        if self.stated:
            return msg("turn-on scatter of B_0+ and B_0−, each a power-on of its own (\"by D.5.1.2\"): σ_on = {s:.4g} °/h "
                       "stated for the device{hint}", s=self.sigma, hint=hint(" (device.bias_repeatability)"))
        return msg("turn-on scatter of B_0+ and B_0−, each a power-on of its own (\"by D.5.1.2\"): σ_on = {s:.4g} °/h of "
                   "D.5.3 on this campaign", s=self.sigma)


def _turn_on(campaign: Campaign, batches: int, missing: str) -> TurnOn:
    """The turn-on scatter σ_on of one power-on's bias, for items whose records are power-ons of their
    own (D.5.4, D.5.5, D.6.3 / D.6.4, the 6.2.8 changes).

    From D.5.3's repeats on this campaign (:func:`.repeatability.bias_repeat_row`, the one place it is
    computed): σ_on² = B_r² − mean u_A² is a variance component estimated as a difference, entered as its
    posterior mean given the runs, with ν = ∞ — never 0 where the runs only bound it (interpretations.md,
    "σ_on — a variance component the data only bound").  Else from ``device.bias_repeatability``
    (°/h, a B_r measured before, e.g. an earlier D.5.3; type B, ν = ∞; as a whole B_r it also holds its
    runs' within-run noise, so it errs on the safe side).  Else not known, with ``missing`` as the note
    (the items then declare their result not reportable: interpretations.md, "D.5.4 / D.5.5 — without
    the turn-on scatter")."""
    from .repeatability import bias_repeat_row

    rep_rows, rep_note = bias_repeat_row(campaign, batches, None)
    if rep_rows:
        r = rep_rows[0]
        stated = r.type == "B"  # device.bias_repeatability: no repeats on this campaign
        return TurnOn(float(r.standard_uncertainty.to("deg/h").magnitude), math.inf if stated else r.dof, True,
                      stated, "")
    if len(campaign.find_segments("static-repeat")) >= 2 and rep_note:
        missing = join("; ", [missing, rep_note])
    return TurnOn(0.0, math.inf, False, False, missing)


def _repeat_steps(options: Mapping[str, Any]) -> list[Step]:
    """D.5.3's power-ons, planned with D.5.4 / D.5.5 so that their turn-on scatter is measured on the
    same campaign (``repeats`` = Q; 0: none — then give ``device.bias_repeatability``).  Shared with
    D.5.3's own steps when both items run (the same kind and conditions are measured once)."""
    q = int(options.get("repeats", 7))
    return BiasRepeatabilityD53().sequence({"Q": q}) if q > 0 else []


class BiasMagneticSensitivityD55(Procedure):
    """GB/T 45570—2025 D.5.5 零偏磁场灵敏度 (bias magnetic sensitivity), eq. (D.44).

    For each axis (IRA, XRA, YRA): B_h = |B_0+ − B_0−| / (2 H_b), the biases by D.5.1 with the
    field H_b applied forward and reversed (segments of kind ``static-field`` with conditions
    ``field_axis`` and a signed ``field``, 10 min each).  Budget: the two biases' type A, the
    field generator's uniformity (5 %, uniform) and calibration, the scale factor.
    """

    standard = STANDARD
    item = "D.5.5"
    title = "Bias magnetic sensitivity (零偏磁场灵敏度)"
    clause = "D.5.5"
    metrics = tuple(Metric(f"Bh_{ax}", f"bias magnetic sensitivity, field along {ax}", f"B_h({ax})",
                           "deg/h/mT", "D.5.5.3", "D.44") for ax in ("IRA", "XRA", "YRA"))
    requires = (SegmentRequirement("static-field", "10 min with +H_b and with −H_b along each of IRA, XRA, YRA",
                                   conditions={"orientation": "", "field_axis": "", "field": "mT"},
                                   columns={"output": OUTPUT_UNITS}, min_count=6),)
    equipment = _EQUIPMENT + (EquipmentRequirement("field_generator", "DC magnetic field generator, uniformity "
                                                   "better than 5 % over the gyro (D.5.5.1 b))"),)
    options = (Option("H_b", "1 mT", "mT", "field strength for the sequence"),
               Option("batches", 20, None, "batch means per segment for each bias's type A uncertainty", minimum=2),
               REPEATS_OPTION)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        H = parse_quantity(options.get("H_b", "1 mT"), dimension="mT").to("mT").magnitude
        steps = []
        for ax in ("IRA", "XRA", "YRA"):
            for sign, word in ((1, "forward"), (-1, "reversed")):
                steps.append(Step(f"field-{ax}-{'plus' if sign > 0 else 'minus'}", "static-field",
                                  f"{word} field of {H:g} mT along {ax}; bias as D.5.1.2 for 10 min (D.5.5.2)",
                                  Q_(10, "min"), Q_(1, "s"),
                                  {"orientation": "IRA up", "field_axis": ax, "field": f"{sign * H:g} mT"}))
        return steps + _repeat_steps(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = _segments_of(type(self), campaign, "static-field", 6, "±H_b along IRA, XRA and YRA")
        gen = campaign.equipment_for("field_generator")
        uniformity = 0.05
        if gen is not None and "uniformity" in gen.properties:
            uniformity = float(gen.prop("uniformity", "percent", source=campaign.source).to("").magnitude)
        results, rows_table, used = [], [], []
        # each field record is taken "by D.5.1.2" — a power-on of its own: the two biases differ by
        # √2·σ_on besides their noise (interpretations.md, "D.5.5 — each field record a power-on")
        on = _turn_on(campaign, int(opts["batches"]), msg(
            "each field record is a power-on of its own (\"by D.5.1.2\"), so B_0+ and B_0− also differ by the turn-on "
            "scatter of the bias, which this campaign does not measure: record D.5.3's power-ons with it or state the "
            "bias repeatability of an earlier D.5.3{hint}",
            hint=hint(" (static-repeat runs, as metro plan -s gbt45570 -i D.5.5 lists them, or [device] "
                      "bias_repeatability)")))
        s_on, nu_on = on.sigma, on.nu
        from metro.api import abs_change, abs_change_note, abs_change_rows

        for metric, ax in zip(self.metrics, ("IRA", "XRA", "YRA")):
            mine = [s for s in segs if str(s.condition("field_axis")).upper() == ax]
            fields = [float(s.condition("field", "mT").to("mT").magnitude) for s in mine]
            plus = [s for s, h in zip(mine, fields) if h > 0]
            minus = [s for s, h in zip(mine, fields) if h < 0]
            if not plus or not minus:
                raise DataError(campaign.source, "segments",
                                f"D.5.5 needs a forward (+) and a reversed (−) field segment along {ax}; "
                                f"found {len(plus)} forward and {len(minus)} reversed")
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
            rows = [BudgetRow.type_a(msg("scatter of B_0+ and B_0− (batch means)"), "√(u²₊+u²₋)/(2H_b)",
                                     Q_(uA, "deg/h/mT"), nu)]
            u_noise2 = uA**2
            if s_on > 0:
                u_on = Q_(math.sqrt(2.0) * s_on / (2.0 * Hb), "deg/h/mT")
                u_noise2 += u_on.magnitude**2
                rows.append(BudgetRow.type_b(on.source(), "√2·σ_on/(2H_b)", u_on, distribution="normal", k=1.0)
                            if on.stated else BudgetRow.type_a(on.source(), "√2·σ_on/(2H_b)", u_on, nu_on))
            if ep.u_q > 0 or em.u_q > 0:
                u_noise2 += (math.hypot(ep.u_q, em.u_q) / (2.0 * Hb)) ** 2
                rows.append(BudgetRow.type_b(msg("quantization of B_0+ and B_0− (the D.5.1 rows)"), "√(u_q²₊+u_q²₋)/(2H_b)",
                                             Q_(math.hypot(ep.u_q, em.u_q) / (2.0 * Hb), "deg/h/mT"),
                                             distribution="normal", k=1.0))
            # D.44 takes |B_0+ − B_0−|: the absolute value of a noisy difference reads high where the field
            # changes the bias by less than the noise (a folded normal); corrected in closed form, the printed
            # value kept in the note (interpretations.md, "D.5.5 / D.6.3 / D.6.4 — the absolute value of one
            # noisy difference")
            sel = abs_change((ep.B0 - em.B0) / (2.0 * Hb), math.sqrt(u_noise2))
            rows += abs_change_rows(sel, "deg/h/mT", math.sqrt(u_noise2))
            Bh = max(sel.value, 0.0)
            rows.append(BudgetRow.type_b(msg("field uniformity over the gyro"), "ΔH/H", Q_(uniformity, ""),
                                         distribution="uniform", sensitivity=Q_(Bh, "deg/h/mT"),
                                         note=msg("D.5.5.1 b): better than 5 %")))
            if gen is not None and gen.calibration is not None and gen.calibration.uncertainty.dimensionless:
                rows.append(BudgetRow.from_calibration(msg("field strength ({equipment})", equipment=gen.describe()),
                                                       "u_rel(H_b)",
                                                       gen.calibration, sensitivity=Q_(Bh, "deg/h/mT")))
            rows += _scale_factor_row(ep.conv, Bh, "deg/h/mT")
            budget = UncertaintyBudget(metric.symbol, "deg/h/mT", rows, coverage=COVERAGE)
            warn = ""
            if abs(Hp - Hm) > 0.01 * Hb:
                warn = msg("forward {p:g} mT and reversed {m:g} mT differ; H_b = their mean", p=Hp, m=Hm)
            warn = join("; ", ([warn] if warn else []) + ([abs_change_note(sel, 1.0, "(°/h)/mT")] if sel.bias else []))
            results.append(Result(metric, Q_(Bh, "deg/h/mT"), budget.combined, budget, note=warn,
                                  earth_rate="not applicable", reportable=on.known, reason=on.note))
            rows_table.append([ax, f"{Hb:g}", f"{ep.B0:.5f}", f"{em.B0:.5f}", f"{sel.printed:.4g}"])
            used += [sp.id, sm.id]
        table = TableSpec("field_biases", msg("Biases with the field forward and reversed (D.5.5)"),
                          [msg("axis"), "H_b (mT)", "B₀₊ (°/h)", "B₀₋ (°/h)", "B_h ((°/h)/mT)"], rows_table)
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[table], segments=used,
                       options={k: str(v) for k, v in opts.items()})


# --------------------------------------------------------------------------------------------
# D.5.6 Angle random walk
# --------------------------------------------------------------------------------------------


class AngleRandomWalkD56(Procedure):
    """GB/T 45570—2025 D.5.6 角度随机游走 (angle random walk), eqs. (D.45), (D.46).

    From the initial series (interval τ), the interval is doubled, τ_k = 2^(k−1)·τ, by
    averaging adjacent pairs; at each level B_s(τ_k) is the D.41 bias stability (Bessel
    standard deviation of the block means).  Levels are kept while they hold at least
    ``min_blocks`` blocks (the standard does not say how far to go; interpretations.md).
    B_s²(τ_k) = α0 + α1/τ_k + α2/τ_k² (τ_k in h) is fitted by generalised least squares and
    RWC = √α1.
    """

    standard = STANDARD
    item = "D.5.6"
    title = "Angle random walk (角度随机游走)"
    clause = "D.5.6"
    metrics = (
        Metric("RWC", "angle random walk", "RWC", "deg/hour**0.5", "D.5.6.3", "D.46"),
        Metric("alpha0", "D.45 coefficient α0", "α₀", "deg**2/hour**2", "D.5.6.3", "D.45"),
        Metric("alpha1", "D.45 coefficient α1", "α₁", "deg**2/hour", "D.5.6.3", "D.45"),
        Metric("alpha2", "D.45 coefficient α2", "α₂", "deg**2", "D.5.6.3", "D.45"),
    )
    requires = (STATIC,)
    equipment = _EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("min_blocks", 10, None, "keep a τ level only while it has at least this many blocks", minimum=2),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static-8h", "static", "IRA up on the levelled platform; warm up ≥ 30 min, then record 8 h "
                     "at τ = 1 s (D.5.6.2)", Q_(8, "h"), Q_(1, "s"), {"orientation": "IRA up"},
                     warmup=Q_(30, "min"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg, series, conv, raw = _static_input(type(self), campaign, opts)
        tau0_s = float(series.interval.to("s").magnitude)
        min_blocks = int(opts["min_blocks"])
        ctx.report_progress("D.5.6 block means", 0, 1)
        # numpy engine: 0.3 s on 28.8 M samples, less than loading the numba kernel in a fresh
        # process (docs/performance.md)
        pyr = allan.block_variance_doubling(raw, tau0_s, min_blocks=min_blocks, engine="numpy")
        ctx.report_progress("D.5.6 block means", 1, 1)
        tau_s = np.asarray(pyr.tau, dtype=float)
        bs = np.asarray(pyr.std, dtype=float) * conv.magnitude
        m = np.asarray(pyr.n_blocks)
        if tau_s.size < 4:
            raise DataError(seg.file, "output",
                            f"a record of {raw.size} samples gives only {tau_s.size} τ levels with ≥ {min_blocks} "
                            "blocks; the D.45 fit needs at least 4 (too short a record for the τ range)",
                            hint="D.5.6.2 asks for 8 h")
        zero = np.flatnonzero(~(bs > 0))
        if zero.size:
            qz = quantization_of(campaign, conv, raw)
            if qz.q <= 0 and not (conv.output_kind == "pulse" and zero[0] > 0):
                raise DataError(seg.file, "output",
                                f"B_s(τ = {tau_s[zero[0]]:g} s) is zero: the output does not vary (zero variance)")
            what = (msg("the output, rounded to q = {q:.3g} °/h (step from {source}), does not vary", q=qz.q,
                        source=qz.source) if qz.q > 0 else
                    msg("every block holds the same whole number of pulses (an undithered counter at a steady rate)"))
            reason = msg("B_s(τ = {tau:g} s) is zero: {what} — its noise is hidden by the quantization, so there is no "
                         "RWC to fit", tau=tau_s[zero[0]], what=what)
            return Outcome(STANDARD, self.item, self.title, self.clause,
                           [Result(self.metrics[0], Q_(0.0, "deg/hour**0.5"), reportable=False, reason=reason,
                                   earth_rate="not applicable")],
                           warnings=[reason], segments=[seg.id], options={k: str(v) for k, v in opts.items()})
        tau_h = tau_s / 3600.0
        try:
            fit = F.fit_d45(tau_h, bs, m)
        except ValueError as exc:
            if conv.output_kind != "pulse" and quantization_of(campaign, conv, raw).q <= 0:
                raise ProcedureError(f"D.5.6: {exc}") from exc
            # quantized counts whose B_s(τ) D.45 cannot even be fitted to: not a data error
            reason = msg("the D.45 fit is not determined ({exc}); the output's quantization dominates B_s(τ)", exc=str(exc))
            return Outcome(STANDARD, self.item, self.title, self.clause,
                           [Result(self.metrics[0], Q_(0.0, "deg/hour**0.5"), reportable=False, reason=reason,
                                   earth_rate="not applicable")],
                           warnings=[msg("RWC is NOT REPORTABLE: {reason}", reason=reason)], segments=[seg.id],
                           options={k: str(v) for k, v in opts.items()})
        a0, a1, a2 = (float(x) for x in fit.alpha)
        ua = fit.u_alpha
        warnings = list(_duration_warnings(series, Q_(8, "h"), "D.5.6.2"))
        not_reportable: list[str] = []
        # rounded rate samples (LSB word, rate of finite resolution): white rate noise that D.45
        # cannot tell from the sensor's ARW (interpretations.md, "D.5 — output quantization")
        qz = quantization_of(campaign, conv, raw)
        q_rows: list[BudgetRow] = []
        a1_q = F.alpha1_rounding_d45(qz.q, tau0_s / 3600.0) if qz.q > 0 else 0.0
        a1_sensor = a1
        if a1_q > 0 and qz.dithered:
            a1_sensor = a1 - a1_q  # Sheppard's correction: the rounding's q²/12 per sample removed
        elif a1_q > 0 and 3.0 * a1_q > 0.01 * max(a1, 0.0):
            not_reportable.append(
                msg("the output is rounded to q = {q:.3g} °/h (step from {source}), coarser than its noise (s = {s:.3g} "
                    "°/h per sample): the rounding error is not white noise of a known size and adds up to q²τ/4 = "
                    "{add:.3g} (°)²/h to α1 = {a1:.3g}, so the sensor's RWC cannot be separated from it (D.45 has no "
                    "term for it)", q=qz.q, source=qz.source, s=qz.s, add=3 * a1_q, a1=a1))
        if fit.dof > 0 and fit.chi2 / fit.dof > D45_MISFIT_LIMIT:
            not_reportable.append(
                msg("the D.45 model does not hold: χ²/ν = {chi2:.3g} > {limit:g} (B_s(τ) has a shape D.45 cannot follow, "
                    "e.g. the sawtooth quantization of an undithered counter or correlated noise); the uncertainty "
                    "scaled by √(χ²/ν) would not cover a systematic misfit", chi2=fit.chi2 / fit.dof,
                    limit=D45_MISFIT_LIMIT))
        if a1_sensor > 0 and a1_sensor - 2.0 * float(ua[1]) <= 0:
            # α1 not resolved from zero (≈95 %): reporting √α1 only when noise happens to push it up
            # would bias the reported RWC high (interpretations.md)
            not_reportable.append(
                msg("α1 = {a1:.3g} ± {U:.2g} (°)²/h (k = 2) is not resolved from zero: the record's other terms "
                    "(quantization α2, bias instability α0) dominate B_s(τ), so RWC = √α1 is not determined; record "
                    "longer or with a finer output", a1=a1_sensor, U=2.0 * float(ua[1])))
        if not a1_sensor > 0:
            not_reportable.append(
                msg("the fitted α1 = {a1:.3g} (°)²/h is not positive, so RWC = √α1 (D.46) is undefined; the record is "
                    "dominated by other noise, quantization or too short (look at the B_s(τ) plot)", a1=a1_sensor))
            a1_sensor = 0.0
        rwc = math.sqrt(a1_sensor)
        for name, val in (("α0", a0), ("α2", a2)):
            if val < 0:
                warnings.append(msg("fitted {name} = {val:.3g} is negative (not physical); kept as the standard's "
                                    "unconstrained fit gives it — RWC uses α1 only", name=name, val=val))
        if fit.birge > 1.5:
            warnings.append(msg("the D.45 model fits poorly (χ²/ν = {chi2:.2g}); the uncertainty of α was scaled up "
                                "accordingly", chi2=fit.birge ** 2))
        scale = max(rwc, math.sqrt(max(a1, 0.0)), math.sqrt(abs(float(ua[1]))), 1e-30)
        u_rwc_fit = ua[1] / (2.0 * scale)
        rows = [BudgetRow.type_a(msg("D.45 fit of B_s²(τ_k) (GLS, nested-level covariance)"), "u(α₁)/(2√α₁)",
                                 Q_(u_rwc_fit, "deg/hour**0.5"), max(fit.dof, 1),
                                 note=(msg("{n} levels, χ²/ν = {chi2:.3g}, u scaled by √(χ²/ν) = {b:.3g}", n=tau_s.size,
                                           chi2=fit.chi2 / max(fit.dof, 1), b=fit.birge) if fit.birge > 1 else
                                       msg("{n} levels, χ²/ν = {chi2:.3g}", n=tau_s.size, chi2=fit.chi2 / max(fit.dof, 1))))]
        if a1_q > 0 and qz.dithered:
            # the correction's own uncertainty: half of it, uniform (Sheppard's q²/12 holds to
            # < 10⁻³ when s ≥ q; the rest covers noise that is not Gaussian)
            q_rows.append(BudgetRow.type_b(
                msg("rounding of each sample to q = {q:.3g} °/h: Sheppard's correction α1 − q²τ₀/12 ({c:.3g} (°)²/h) "
                    "applied", q=qz.q, c=a1_q), "δα₁", Q_(a1_q / 2.0, "deg**2/hour"), distribution="uniform",
                sensitivity=Q_(1.0 / (2.0 * scale), "hour**0.5/deg"),
                note=msg("noise s = {s:.3g} °/h ≥ q dithers the rounding (step from {source})", s=qz.s, source=qz.source)))
        rows += q_rows
        rows += _scale_factor_row(conv, rwc, "deg/hour**0.5")
        rows += _timebase_row(campaign, rwc, "deg/hour**0.5", "RWC")
        budget = UncertaintyBudget("RWC", "deg/hour**0.5", rows, coverage=COVERAGE)
        reason = join("; ", not_reportable) if not_reportable else ""
        if reason:
            warnings.append(msg("RWC is NOT REPORTABLE: {reason}", reason=reason))
        results = [
            Result(self.metrics[0], Q_(rwc, "deg/hour**0.5"), budget.combined, budget,
                   reportable=not not_reportable, reason=reason, earth_rate="not applicable",
                   note=(msg("RWC of the sensor: √(α₁ − q²τ₀/12), the output's rounding removed") if a1_q > 0 and
                         qz.dithered else "")),
            Result(self.metrics[1], Q_(a0, "deg**2/hour**2"), Q_(ua[0], "deg**2/hour**2"), earth_rate="not applicable"),
            Result(self.metrics[2], Q_(a1, "deg**2/hour"), Q_(ua[1], "deg**2/hour"), earth_rate="not applicable"),
            Result(self.metrics[3], Q_(a2, "deg**2"), Q_(ua[2], "deg**2"), earth_rate="not applicable"),
        ]
        model = fit.model(tau_h)
        plot = PlotSpec(
            "bs_tau", msg("B_s(τ_k) and the D.45 fit"), "τ_k (s)", "B_s (°/h)",
            [
                {"label": "B_s(τ_k) (D.41)", "x": tau_s.tolist(), "y": bs.tolist(),
                 "yerr": (bs / np.sqrt(2 * (m - 1))).tolist(), "style": "o"},
                {"label": "D.45 fit", "x": tau_s.tolist(), "y": np.sqrt(np.clip(model, 0, None)).tolist(), "style": "-"},
                {"label": f"ARW term √(α₁/τ), RWC = {rwc:.3g} °/√h", "x": tau_s.tolist(),
                 "y": np.sqrt(np.clip(a1_sensor / tau_h, 0, None)).tolist(), "style": "--"},
            ],
            logx=True, logy=True,
        )
        table = TableSpec(
            "bs_levels", msg("B_s(τ_k) per level (D.5.6.2)"),
            ["k", "τ_k (s)", "m (blocks)", "B_s (°/h)", "fit (°/h)"],
            [[i + 1, f"{tau_s[i]:g}", int(m[i]), f"{bs[i]:.5g}", f"{math.sqrt(max(model[i], 0)):.5g}"]
             for i in range(tau_s.size)],
        )
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=[plot], tables=[table],
                       warnings=warnings, segments=[seg.id], options={k: str(v) for k, v in opts.items()})


def _duration_warnings(series, wanted, clause: str) -> list[str]:
    dur = series.duration.to("h")
    if dur < wanted * 0.999:
        return [msg("the record lasts {dur}; {clause} asks for {wanted} (or the user's application time)",
                    dur=f"{dur:~.3gP}", clause=clause, wanted=f"{wanted:~P}")]
    return []


PROCEDURES = (BiasD51, BiasStabilityD52, BiasRepeatabilityD53, BiasTemperatureSensitivityD54,
              BiasMagneticSensitivityD55, AngleRandomWalkD56)


# --------------------------------------------------------------------------------------------
# Output quantization (docs/interpretations.md, "D.5 — output quantization")
# --------------------------------------------------------------------------------------------


@attrs.frozen
class Quantization:
    """How the static record's samples are quantized.

    ``q`` is the rounding step of a rate sample in °/h (0 for pulse output, whose counts carry
    their remainder: its quantization is white angle noise, the α2 term of D.45, or a sawtooth
    the D.45 fit's χ² detects); ``s`` the measured standard deviation of one sample in °/h;
    ``dithered`` whether the noise dithers the rounding (s ≥ q)."""

    q: float
    s: float
    source: str

    @property
    def dithered(self) -> bool:
        return self.q <= 0 or self.s >= self.q


def output_quantum(campaign: Campaign, conv: RateConversion, raw: np.ndarray) -> tuple[float, str]:
    """The rounding step of the output in raw units and where it comes from: the device's
    ``resolution`` if it states one (LSB or the rate unit), else read from the data — the
    greatest step all distinct values are whole multiples of (integers: 1) — else 0."""
    dev = campaign.device
    if "resolution" in dev.properties:
        res = dev.properties["resolution"]
        q = parse_quantity(res, file=campaign.source, field="device.resolution")
        if q.check("[digital_count]"):
            return float(q.to("LSB").magnitude), msg("device resolution {res}", res=res)
        if q.is_compatible_with("deg/h") and conv.magnitude:
            return float(q.to("deg/h").magnitude) / conv.magnitude, msg("device resolution {res}", res=res)
        raise DataError(campaign.source, "device.resolution",
                        f"{res!r} is not a resolution of a {conv.output_kind} output (LSB or a rate such as °/h)")
    sample = np.asarray(raw[: 200_000], dtype=np.float64)
    vals = np.unique(sample)
    if conv.output_kind == "digital" and np.all(vals == np.round(vals)):
        return 1.0, msg("the data (whole LSB)")
    if vals.size < 2:
        return 0.0, msg("the data (constant output)")
    if np.all(vals == np.round(vals)):
        step = float(np.min(np.diff(vals)))
        return (1.0 if step >= 1 else 0.0), msg("the data (whole numbers)")
    step = float(np.min(np.diff(vals)))
    if step > 1e-9 * float(vals[-1] - vals[0]):
        ratio = (vals - vals[0]) / step
        if np.all(np.abs(ratio - np.round(ratio)) < 1e-6 * np.maximum(1.0, np.abs(ratio))):
            return step, msg("the data (every value a whole number of this step)")
    return 0.0, msg("the data (no common step)")


def quantization_of(campaign: Campaign, conv: RateConversion, raw: np.ndarray) -> Quantization:
    """:class:`Quantization` of a static record (rate samples rounded; pulse counts: q = 0)."""
    s = float(np.std(raw, ddof=1)) * abs(conv.magnitude) if raw.size > 1 else 0.0
    if conv.output_kind == "pulse":
        return Quantization(0.0, s, msg("pulse counts (remainder carried)"))
    q_raw, source = output_quantum(campaign, conv, raw)
    return Quantization(q_raw * abs(conv.magnitude), s, source)


def _raw_unit(conv: RateConversion) -> str:
    return {"digital": "LSB", "pulse": "P"}.get(conv.output_kind, "deg/h")


def quantization_rows_mean(campaign: Campaign, conv: RateConversion, raw: np.ndarray, what: str) -> list[BudgetRow]:
    """The quantization row of a mean of the output (D.5.1, and through it D.5.3–D.5.5).

    * pulse counts carry their remainder: the mean count is off by at most the readout error at
      the two ends of the record, ±1 P over n samples;
    * a rounded rate sample (LSB word, rate of finite resolution q): ±q/2 (the row of D.2.1,
      :func:`.rate_method._resolution_row`) unless the noise dithers the rounding (s ≥ q), when
      the offset of the mean is bounded by :func:`.formulas.rounding_mean_bound`."""
    from .rate_method import _resolution_row

    c = abs(conv.magnitude)
    if conv.output_kind == "pulse":
        return [_resolution_row(campaign, c, "deg/h", what, q=1.0, raw_unit="P", half_width=1.0 / raw.size,
                                note=msg("readout at the record's two ends: ±1 P over {n} samples", n=raw.size))]
    qz = quantization_of(campaign, conv, raw)
    if qz.q <= 0:
        return []
    if conv.output_kind == "rate":
        c = 1.0  # the row in °/h, whatever rate unit the samples came in
    q_raw = qz.q / c if c else 0.0
    if qz.dithered:
        hw = F.rounding_mean_bound(qz.q, F.rounding_sigma(qz.s, qz.q)) / c
        note = msg("noise s = {s:.3g} °/h ≥ q = {q:.3g} °/h dithers the rounding: offset of the mean ≤ "
                   "Σ(q/πk)e^(−2π²k²σ²/q²) (step from {source})", s=qz.s, q=qz.q, source=qz.source)
    else:
        hw = q_raw / 2.0
        note = msg("noise s = {s:.3g} °/h < q = {q:.3g} °/h: the rounding does not average out, "
                   "±q/2 on the mean (step from {source})", s=qz.s, q=qz.q, source=qz.source)
    return [_resolution_row(campaign, c, "deg/h", what, q=q_raw, raw_unit=_raw_unit(conv), half_width=hw, note=note)]


def quantization_rows_std(campaign: Campaign, conv: RateConversion, raw: np.ndarray, factor: int) -> list[BudgetRow]:
    """The quantization row of a standard deviation of means of ``factor`` rounded rate samples
    (D.5.2): |Δstd| ≤ std of the means' rounding errors — q/√(12·factor) when the noise dithers
    the rounding (independent errors of variance q²/12), else up to q/2.  Pulse counts: none
    (the carried remainder enters as white angle noise, part of what D.41 measures)."""
    from .rate_method import _resolution_row

    if conv.output_kind == "pulse":
        return []
    qz = quantization_of(campaign, conv, raw)
    c = abs(conv.magnitude)
    if qz.q <= 0 or not c:
        return []
    if conv.output_kind == "rate":
        c = 1.0
    q_raw = qz.q / c
    hw = q_raw / math.sqrt(12.0 * factor) if qz.dithered else q_raw / 2.0
    note = (msg("dithered by the noise: rounding errors independent, q/√(12·n) on each mean") if qz.dithered else
            msg("noise s = {s:.3g} °/h < q = {q:.3g} °/h: each mean's rounding error up to ±q/2", s=qz.s, q=qz.q))
    return [_resolution_row(campaign, c, "deg/h", msg("the D.41 means of {n} samples", n=factor), q=q_raw,
                            raw_unit=_raw_unit(conv), half_width=hw, note=note)]

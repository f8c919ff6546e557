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

from metro.core import allan
from metro.core.budget import INF, BudgetRow, Coverage, UncertaintyBudget
from metro.core.errors import DataError, ProcedureError
from metro.core.model import (
    Campaign,
    EquipmentRequirement,
    Metric,
    Option,
    Outcome,
    PlotSpec,
    Procedure,
    Result,
    RunContext,
    Segment,
    SegmentRequirement,
    Step,
    TableSpec,
)
from metro.core.signals import OUTPUT_UNITS, RateConversion, gyro_output
from metro.core.units import Q_, fmt_unit, parse_quantity

from . import formulas as F

STANDARD = "gbt45570"
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
        f"time base of the counter ({eq.describe()})", "u_rel(τ)", cal,
        sensitivity=Q_(abs(measured), unit),
        note=f"{what} ∝ 1/τ; {cal.certificate}",
    )]


def _scale_factor_row(conv: RateConversion, measured: float, unit: str) -> list[BudgetRow]:
    if conv.output_kind == "rate" or conv.relative_u_scale_factor == 0.0:
        return []
    return [BudgetRow.type_b(
        "scale factor K used to convert the output", "u_rel(K)",
        Q_(conv.relative_u_scale_factor, ""), distribution="normal", k=1.0,
        sensitivity=Q_(abs(measured), unit),
        note=f"K = {conv.scale_factor:~P}; result ∝ 1/K",
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
        Option("batches", 20, None, "number of batch means for the type A uncertainty"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static-1h", "static", "IRA up on the levelled platform; power on, wait the set-up time, "
                     "record 1 h at τ = 1 s; power off (D.5.1.2)", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up"})]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg = _static_segment(type(self), campaign, opts)
        est = segment_bias(seg, campaign, int(opts["batches"]))
        res = Result(self.metrics[0], Q_(est.B0, "deg/h"), est.budget.combined, est.budget,
                     note=f"earth rate {est.earth:+.4f} °/h removed ({est.orientation}, θ = {est.theta:g}°)")
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
    sd_batch, nb = allan.block_std(raw, raw.size // b)
    uA = sd_batch * conv.magnitude / math.sqrt(nb)
    rows = [BudgetRow.type_a("scatter of the output (batch means)", "s_b/√b", Q_(uA, "deg/h"), nb - 1,
                             note=f"{nb} batches of {raw.size // b} samples")]
    rows += _scale_factor_row(conv, indicated, "deg/h")
    lat_u = campaign.site.get("latitude_uncertainty")
    c_theta = F.EARTH_RATE_DEG_PER_H * math.cos(math.radians(theta))
    if lat_u is not None:
        lu = parse_quantity(lat_u, dimension="deg", file=campaign.source, field="site.latitude_uncertainty")
        rows.append(BudgetRow.type_b("site latitude θ", "u(θ)", lu.to("rad"), distribution="uniform",
                                     sensitivity=Q_(c_theta, "deg/h/rad"), note="∂B0/∂θ = −15.041·cos θ"))
    plat = campaign.equipment_for("platform")
    if plat is not None and "levelness" in plat.properties:
        lev = plat.prop("levelness", "arcsec", source=campaign.source)
        rows.append(BudgetRow.type_b(f"levelling of the IRA ({plat.describe()})", "δ", lev.to("rad"),
                                     distribution="uniform", sensitivity=Q_(c_theta, "deg/h/rad"),
                                     note="horizontal earth rate Ω·cos θ·sin δ leaks into the IRA"))
    rows += _timebase_row(campaign, indicated, "deg/h", "indicated rate")
    budget = UncertaintyBudget("B0", "deg/h", rows, coverage=COVERAGE)
    return BiasEstimate(B0, uA, nb - 1, budget, earth, orient, theta, conv, series)


# --------------------------------------------------------------------------------------------
# D.5.2 Bias stability
# --------------------------------------------------------------------------------------------


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
        return BiasD51().sequence(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg, series, conv, raw = _static_input(type(self), campaign, opts)
        tau0 = float(series.interval.to("s").magnitude)
        from metro.core.units import parse_quantity
        results = []
        for text in str(opts["t"]).split(","):
            t = parse_quantity(text.strip(), dimension="s", field="option t")
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
            if not Bs > 0:
                raise DataError(seg.file, "output", "the output does not vary at all (zero variance); "
                                "is the gyro powered and the counter connected?")
            rows = [BudgetRow.type_a(f"sampling of the standard deviation of {m} values", "B_s/√(2(m−1))",
                                     Q_(Bs / math.sqrt(2 * (m - 1)), "deg/h"), m - 1)]
            rows += _scale_factor_row(conv, Bs, "deg/h")
            rows += _timebase_row(campaign, Bs, "deg/h", "B_s")
            label = f"{ts:g} s"
            metric = Metric(f"Bs_{ts:g}s", f"bias stability (t = {label})", f"B_s({label})", "deg/h",
                            "D.5.2.3", "D.41")
            budget = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
            results.append(Result(metric, Q_(Bs, "deg/h"), budget.combined, budget, note=f"m = {m}"))
        warnings = _duration_warnings(series, Q_(1, "h"), "D.5.1.2 c)")
        return Outcome(STANDARD, self.item, self.title, self.clause, results, warnings=warnings,
                       segments=[seg.id], options={k: str(v) for k, v in opts.items()})


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
        Option("min_blocks", 10, None, "keep a τ level only while it has at least this many blocks"),
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
            raise DataError(seg.file, "output",
                            f"B_s(τ = {tau_s[zero[0]]:g} s) is zero: the output does not vary (zero variance)")
        tau_h = tau_s / 3600.0
        try:
            fit = F.fit_d45(tau_h, bs, m)
        except ValueError as exc:
            raise ProcedureError(f"D.5.6: {exc}") from exc
        a0, a1, a2 = (float(x) for x in fit.alpha)
        ua = fit.u_alpha
        if not a1 > 0:
            raise ProcedureError(
                f"D.5.6: the fitted α1 = {a1:.3g} (°)²/h is not positive, so RWC = √α1 (D.46) is undefined; "
                "the record is dominated by other noise or too short",
                hint="look at the B_s(τ) plot (run with --report) and check the warm-up and the record length",
            )
        rwc = F.rwc_d46(a1)
        warnings = list(_duration_warnings(series, Q_(8, "h"), "D.5.6.2"))
        for name, val in (("α0", a0), ("α2", a2)):
            if val < 0:
                warnings.append(f"fitted {name} = {val:.3g} is negative (not physical); kept as the standard's "
                                "unconstrained fit gives it — RWC uses α1 only")
        if fit.birge > 1.5:
            warnings.append(f"the D.45 model fits poorly (χ²/ν = {fit.birge ** 2:.2g}); the uncertainty of α "
                            "was scaled up accordingly")
        u_rwc_fit = ua[1] / (2.0 * rwc)
        rows = [BudgetRow.type_a("D.45 fit of B_s²(τ_k) (GLS, nested-level covariance)", "u(α₁)/(2√α₁)",
                                 Q_(u_rwc_fit, "deg/hour**0.5"), max(fit.dof, 1),
                                 note=f"{tau_s.size} levels, χ²/ν = {fit.chi2 / max(fit.dof, 1):.3g}")]
        rows += _scale_factor_row(conv, rwc, "deg/hour**0.5")
        rows += _timebase_row(campaign, rwc, "deg/hour**0.5", "RWC")
        budget = UncertaintyBudget("RWC", "deg/hour**0.5", rows, coverage=COVERAGE)
        results = [
            Result(self.metrics[0], Q_(rwc, "deg/hour**0.5"), budget.combined, budget),
            Result(self.metrics[1], Q_(a0, "deg**2/hour**2"), Q_(ua[0], "deg**2/hour**2")),
            Result(self.metrics[2], Q_(a1, "deg**2/hour"), Q_(ua[1], "deg**2/hour")),
            Result(self.metrics[3], Q_(a2, "deg**2"), Q_(ua[2], "deg**2")),
        ]
        model = fit.model(tau_h)
        plot = PlotSpec(
            "bs_tau", "B_s(τ_k) and the D.45 fit", "τ_k (s)", "B_s (°/h)",
            [
                {"label": "B_s(τ_k) (D.41)", "x": tau_s.tolist(), "y": bs.tolist(),
                 "yerr": (bs / np.sqrt(2 * (m - 1))).tolist(), "style": "o"},
                {"label": "D.45 fit", "x": tau_s.tolist(), "y": np.sqrt(np.clip(model, 0, None)).tolist(), "style": "-"},
                {"label": f"ARW term √(α₁/τ), RWC = {rwc:.3g} °/√h", "x": tau_s.tolist(),
                 "y": np.sqrt(a1 / tau_h).tolist(), "style": "--"},
            ],
            logx=True, logy=True,
        )
        table = TableSpec(
            "bs_levels", "B_s(τ_k) per level (D.5.6.2)",
            ["k", "τ_k (s)", "m (blocks)", "B_s (°/h)", "fit (°/h)"],
            [[i + 1, f"{tau_s[i]:g}", int(m[i]), f"{bs[i]:.5g}", f"{math.sqrt(max(model[i], 0)):.5g}"]
             for i in range(tau_s.size)],
        )
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=[plot], tables=[table],
                       warnings=warnings, segments=[seg.id], options={k: str(v) for k, v in opts.items()})


def _duration_warnings(series, wanted, clause: str) -> list[str]:
    dur = series.duration.to("h")
    if dur < wanted * 0.999:
        return [f"the record lasts {dur:~.3gP}; {clause} asks for {wanted:~P} (or the user's application time)"]
    return []


PROCEDURES = (BiasD51, BiasStabilityD52, AngleRandomWalkD56)

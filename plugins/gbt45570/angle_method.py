"""GB/T 45570—2025 D.1 scale factor series by the angle method (pulse output):
D.1.1 scale factor, D.1.2 nonlinearity, D.1.3 asymmetry, D.1.4 repeatability, D.1.5
temperature sensitivity, D.1.6 input-axis misalignment.

Data: one segment of kind ``rate-revolutions`` per rate point and direction, with conditions
``rate`` (signed: + counter-clockwise, − clockwise, D.1.1.2 note) and ``turns`` (m), and columns
``count`` (P, pulses over each whole revolution, counted between revolution pulses) and
``duration`` (s, the time of each revolution, D.1.3.2 a)); for D.1.3 also segments of kind
``static-zero`` (table at rest, τ = 1 s, n = 300, at several symmetric positions, at the start
and end of the test) with an ``output`` column in P.  D.1.4 uses segments of kind
``revolutions-repeat`` (the same columns at 30 °/s, condition ``run`` = 1 … 7), D.1.5
``revolutions-temperature`` (the whole sweep at each ``temperature``) and D.1.6
``revolutions-mounting`` (conditions ``axis_up`` XRA/YRA and ``turn`` 0°/180° about IRA).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (
    Q_,
    BudgetRow,
    Campaign,
    DataError,
    EquipmentRequirement,
    Metric,
    Option,
    Outcome,
    PlotSpec,
    Procedure,
    Result,
    RunContext,
    SegmentRequirement,
    Step,
    TableSpec,
    UncertaintyBudget,
    fit_line,
    hint,
    join,
    max_slope_selection,
    msg,
    selection_note,
    selection_rows,
    std_sampling_u,
)

from . import formulas as F
from . import formulas_rate as F2
from .procedures import COVERAGE, STANDARD

#: GB/T 321 R5 preferred numbers, rounded, up to 400 °/s (D.1.1.2 e))
R5_RATES = (1.0, 1.6, 2.5, 4.0, 6.3, 10.0, 16.0, 25.0, 40.0, 63.0, 100.0, 160.0, 250.0, 400.0)

REVOLUTIONS = SegmentRequirement(
    "rate-revolutions", "m whole revolutions at each rate point, each direction (D.1.1.2 g))",
    conditions={"rate": "deg/s", "turns": ""}, columns={"count": ("P",), "duration": ("s",)}, min_count=22,
)
ZERO = SegmentRequirement("static-zero", "table at rest, τ = 1 s, n = 300, several symmetric positions (D.1.3.2 a))",
                          conditions={}, columns={"output": ("P",)})
_EQUIPMENT = (
    EquipmentRequirement("rate_table", "rate table with angle output and a revolution pulse generator (D.1.1.1)",
                         required=True),
    EquipmentRequirement("counter", "gyro test system / counter"),
)
_OPTIONS = (
    Option("max_rate", "400 °/s", "deg/s", "largest rate point (the device's maximum input rate)"),
    Option("turns", 5, None, "whole revolutions m per rate point and direction"),
    Option("min_points", 11, None, "fewest rate points accepted (D.1.1.2 e): not fewer than 11)"),
)


def rate_points(max_rate_deg_s: float) -> list[float]:
    """R5 rate points up to and including the maximum input rate (D.1.1.2 e))."""
    pts = [r for r in R5_RATES if r < max_rate_deg_s * (1 - 1e-9)]
    return pts + [float(max_rate_deg_s)]


def _sequence(options: Mapping[str, Any], zero: bool) -> list[Step]:
    from metro.api import parse_quantity

    rmax = float(parse_quantity(options.get("max_rate", "400 °/s"), dimension="deg/s").to("deg/s").magnitude)
    m = int(options.get("turns", 5))
    steps = []
    if zero:
        steps.append(Step("zero-start", "static-zero", "table at rest, 300 s at τ = 1 s (D.1.3.2 a))",
                          Q_(300, "s"), Q_(1, "s"), {"orientation": "IRA up"}))
    for r in rate_points(rmax):
        for sign, word in ((1, "counter-clockwise (+)"), (-1, "clockwise (−)")):
            steps.append(Step(f"rate{sign * r:+g}", "rate-revolutions",
                              f"{m} whole revolutions at {r:g} °/s {word}, counting pulses between revolution "
                              "pulses (D.1.1.2 g))", Q_(m * 360.0 / r, "s"), Q_(360.0 / r, "s"),
                              {"rate": f"{sign * r:g} deg/s", "turns": m}, warmup=Q_(30, "min")))
    if zero:
        steps.append(Step("zero-end", "static-zero", "table at rest, 300 s at τ = 1 s (D.1.3.2 a))",
                          Q_(300, "s"), Q_(1, "s"), {"orientation": "IRA up"}))
    return steps


def revolution_trend(c_plus: np.ndarray, c_minus: np.ndarray) -> tuple[float, float, int]:
    """The common slope β (P per revolution) of the per-revolution counts of a rate point's + and
    − runs against each revolution's place in its run, each run with its own mean (the counts
    differ by ≈ 2·K·360·3 600 between the runs), its standard uncertainty from the residuals and
    ν = m₊ + m₋ − 3.  A bias changing at ḃ (″/s²) through the point adds K·ḃ·T² per revolution
    of T seconds to both runs' counts, so β = K·ḃ·T².  Not a formula of the standard: metro's
    bound on the bias drift between the + and − runs of D.1.1.2 g) (interpretations.md, "D.1.2 /
    D.1.3 — the bias drifting through the sweep").  Returns (0, inf, 0) below two revolutions a run."""
    cp, cm = np.asarray(c_plus, dtype=float), np.asarray(c_minus, dtype=float)
    if cp.size < 2 or cm.size < 2 or cp.size + cm.size < 5:
        return 0.0, math.inf, 0
    jp, jm = np.arange(cp.size) - (cp.size - 1) / 2.0, np.arange(cm.size) - (cm.size - 1) / 2.0
    sxx = float(jp @ jp + jm @ jm)
    beta = float((jp @ (cp - cp.mean()) + jm @ (cm - cm.mean())) / sxx)
    res = np.concatenate([cp - cp.mean() - beta * jp, cm - cm.mean() - beta * jm])
    dof = cp.size + cm.size - 3
    return beta, math.sqrt(float(res @ res) / dof / sxx), dof


@attrs.frozen
class RatePoint:
    rate: float  # |Ω|, °/s
    n_plus: float
    n_minus: float
    s_plus: float  # standard deviation of one revolution's count
    s_minus: float
    m_plus: int
    m_minus: int
    t_plus: float  # mean revolution time, s
    t_minus: float
    segments: tuple[str, str]
    #: common slope of the two runs' per-revolution counts against the revolution's place in its run
    #: (P per revolution; the bias drifting through the point), its standard uncertainty and ν
    trend: float = 0.0
    u_trend: float = math.inf
    dof_trend: int = 0

    @property
    def K(self) -> float:
        return F.scale_factor_d2(self.n_plus, self.n_minus)

    @property
    def u_K(self) -> float:
        """Standard uncertainty of K_i from the scatter of the revolutions' counts."""
        up = self.s_plus / math.sqrt(self.m_plus) if self.m_plus > 1 else 0.5
        um = self.s_minus / math.sqrt(self.m_minus) if self.m_minus > 1 else 0.5
        return math.hypot(up, um) / (2 * F.REVOLUTION_ARCSEC)


@attrs.frozen
class SweepDrift:
    """The bias's rate of change through a sweep, from the revolutions' own counts: the rms ḃ
    (″/s², i.e. (°/h)/s) of the rate points' trends (:func:`revolution_trend`), weighted by their
    inverse variance, their own noise removed (√(max(Σw(ḃ_i² − u_i²)/Σw, 0))), and its degrees of
    freedom, the effective number of points (Σw)²/Σw²."""

    rms: float
    dof: float
    points: int


def sweep_drift(pts: list["RatePoint"]) -> SweepDrift:
    """:class:`SweepDrift` of the rate points ``pts`` (interpretations.md, "D.1.2 / D.1.3 — the bias
    drifting through the sweep")."""
    num = den = den2 = 0.0
    n = 0
    for p in pts:
        T = 0.5 * (p.t_plus + p.t_minus)
        if not (p.dof_trend > 0 and math.isfinite(p.u_trend) and p.u_trend > 0):
            continue
        scale = abs(p.K) * T * T  # β = K·ḃ·T²
        b, v = p.trend / scale, (p.u_trend / scale) ** 2
        w = 1.0 / v
        num += w * (b * b - v)
        den += w
        den2 += w * w
        n += 1
    if n == 0 or den <= 0:
        return SweepDrift(0.0, math.inf, 0)
    return SweepDrift(math.sqrt(max(num / den, 0.0)), max(den * den / den2, 1.0), n)


def point_drift(p: "RatePoint") -> float:
    """Relative standard uncertainty of K_i (D.2) from the bias drifting between the + and − runs of
    D.1.1.2 g) at this point, from its own revolutions' trend β (:func:`revolution_trend`): the
    difference N₊ − N₋ keeps −β·Δ, Δ the runs' centres apart in revolutions ((m₊ + m₋)/2), which is
    not corrected, so u = Δ·√(β² + u²(β))/(2·360·3 600″·K_i) — the drift the counts show and the
    drift they cannot exclude."""
    if not (p.dof_trend > 0 and math.isfinite(p.u_trend)):
        return 0.0
    dt = 0.5 * (p.m_plus * p.t_plus + p.m_minus * p.t_minus) / (0.5 * (p.t_plus + p.t_minus))
    return dt * math.hypot(p.trend, p.u_trend) / (2.0 * F.REVOLUTION_ARCSEC * abs(p.K))


def collect_rate_points(proc: type[Procedure], campaign: Campaign, min_points: int,
                        segments: list | None = None, what: str = "") -> list[RatePoint]:
    """Pair the + and − revolution segments of every rate point (D.1.1.2 g), eq. (D.1)).

    ``segments`` (default: every ``rate-revolutions`` segment) and ``what`` (e.g. "at 60 °C",
    named in the errors) let D.1.4–D.1.6 apply it to one run, temperature or mounting.
    """
    segs = campaign.find_segments("rate-revolutions") if segments is None else segments
    by_rate: dict[float, dict[int, Any]] = {}
    for s in segs:
        rate = float(s.condition("rate", "deg/s").to("deg/s").magnitude)
        if rate == 0:
            raise DataError(campaign.source, f"segments.{s.id}.conditions.rate", "a rate point cannot be 0 °/s")
        key = round(abs(rate), 9)
        d = 1 if rate > 0 else -1
        if d in by_rate.setdefault(key, {}):
            raise DataError(campaign.source, f"segments.{s.id}", f"two segments at {rate:+g} °/s")
        by_rate[key][d] = s
    points = []
    for rate, pair in sorted(by_rate.items()):
        if set(pair) != {1, -1}:
            missing = "clockwise (−)" if 1 in pair else "counter-clockwise (+)"
            only = pair.get(1) or pair.get(-1)
            raise DataError(campaign.source, f"segments.{only.id}",
                            f"rate point {rate:g} °/s{' ' + what if what else ''} has no {missing} run; "
                            "D.2 needs both directions")
        stats = {}
        for d, s in pair.items():
            c = np.asarray(s.series("count", "P").data.magnitude, dtype=float)
            t = np.asarray(s.series("duration", "s").data.to("s").magnitude, dtype=float)
            if c.size < 1 or not np.all(np.isfinite(c)) or not np.all(np.isfinite(t)) or np.any(t <= 0):
                raise DataError(s.file or f"segment {s.id}", "count/duration",
                                "needs at least one revolution with finite counts and positive durations")
            expect_t = 360.0 / rate
            if abs(float(np.mean(t)) - expect_t) > 0.05 * expect_t:
                raise DataError(s.file or f"segment {s.id}", "duration",
                                f"revolutions last {np.mean(t):.4g} s on average, but 360° at {rate:g} °/s takes "
                                f"{expect_t:.4g} s; is the rate or the duration unit wrong?")
            stats[d] = (F.mean_counts_d1(c), float(np.std(c, ddof=1)) if c.size > 1 else 0.0, c.size,
                        float(np.mean(t)), s.id, c)
        (np_, sp, mp, tp, idp, cp), (nm, sm, mm, tm, idm, cm) = stats[1], stats[-1]
        points.append(RatePoint(rate, np_, nm, sp, sm, mp, mm, tp, tm, (idp, idm), *revolution_trend(cp, cm)))
    if len(points) < min_points:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs at least {min_points} rate points (D.1.1.2 e))"
                        f"{' ' + what if what else ''}; found {len(points)}",
                        hint="or lower the option min_points if agreed with the user")
    return points


def _angle_row(campaign: Campaign, value: float, unit: str) -> list[BudgetRow]:
    table = campaign.equipment_for("rate_table")
    if table is None or "revolution_pulse_accuracy" not in table.properties:
        return []
    acc = table.prop("revolution_pulse_accuracy", "arcsec", source=campaign.source)
    rel = float(acc.to("arcsec").magnitude) / F.REVOLUTION_ARCSEC
    return [BudgetRow.type_b(msg("revolution pulse position ({equipment})", equipment=table.describe()), "δθ/360°",
                             Q_(rel, ""), distribution="uniform", sensitivity=Q_(abs(value), unit),
                             note=msg("±{acc} on 360° (D.1.1.1 d))", acc=f"{acc:~P}"))]


class ScaleFactorD11(Procedure):
    """GB/T 45570—2025 D.1.1 标度因数 (scale factor), angle method, eqs. (D.1), (D.2), (D.4)–(D.6).

    K_i per rate point from whole revolutions both ways (D.2); K and W by least squares of
    K_i = K + W·Ω_i (D.5, D.6; computed with metro's QR least squares, which equals the closed
    forms).  Type A: the fit's standard error of K (ν = n − 2); type B: the revolution-pulse
    position accuracy of the table.
    """

    standard = STANDARD
    item = "D.1.1"
    title = "Scale factor, angle method (标度因数 角度法)"
    clause = "D.1.1"
    metrics = (Metric("K", "scale factor", "K", "P/arcsec", "D.1.1.3", "D.5"),
               Metric("W", "scale factor change with rate", "W", "P/arcsec/(deg/s)", "D.1.1.3", "D.6"))
    requires = (REVOLUTIONS,)
    equipment = _EQUIPMENT
    options = _OPTIONS

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return _sequence(options, zero=False)

    def fit(self, campaign: Campaign, opts: Mapping[str, Any]):
        pts = collect_rate_points(type(self), campaign, int(opts["min_points"]))
        rates = np.array([p.rate for p in pts])
        Ki = np.array([p.K for p in pts])
        fit = fit_line(rates, Ki)
        return pts, rates, Ki, fit

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        pts, rates, Ki, fit = self.fit(campaign, opts)
        K, W = (float(x) for x in fit.coef)
        uK, uW = (float(x) for x in fit.stderr)
        rows = [BudgetRow.type_a(msg("least-squares fit of K_i = K + W·Ω_i (D.4)"), "s(K)", Q_(uK, "P/arcsec"), fit.dof,
                                 note=msg("{n} rate points", n=len(pts)))]
        rows += _angle_row(campaign, K, "P/arcsec")
        from .repeatability import scale_factor_angle_repeat_row

        rep_rows, rep_note = scale_factor_angle_repeat_row(campaign, K, "P/arcsec")
        rows += rep_rows
        budget = UncertaintyBudget("K", "P/arcsec", rows, coverage=COVERAGE)
        res = [Result(self.metrics[0], Q_(K, "P/arcsec"), budget.combined, budget, earth_rate="removed", note=rep_note),
               Result(self.metrics[1], Q_(W, "P/arcsec/(deg/s)"), Q_(uW, "P/arcsec/(deg/s)"), earth_rate="removed")]
        model = K + W * rates
        plot = PlotSpec("K_rate", msg("K_i against rate with the eq. (D.4) fit"),
                        "Ω (°/s)", "K_i (P/″)",
                        [{"label": "K_i (D.2)", "x": rates.tolist(), "y": Ki.tolist(),
                          "yerr": [2 * p.u_K for p in pts], "style": "o"},
                         {"label": f"K + WΩ: K = {K:.7g} P/″", "x": rates.tolist(), "y": model.tolist(), "style": "-"}],
                        logx=True)
        table = TableSpec("K_points", msg("K_i per rate point (D.1, D.2)"),
                          ["Ω (°/s)", "N₊ (P)", "N₋ (P)", "K_i (P/″)", msg("K_i − (K + WΩ_i) (ppm of K)")],
                          [[f"{p.rate:g}", f"{p.n_plus:.1f}", f"{p.n_minus:.1f}", f"{p.K:.8f}",
                            f"{(p.K - K - W * p.rate) / K * 1e6:.2f}"] for p in pts])
        return Outcome(STANDARD, self.item, self.title, self.clause, res, plots=[plot], tables=[table],
                       segments=[s for p in pts for s in p.segments], options={k: str(v) for k, v in opts.items()})


class NonlinearityD12(ScaleFactorD11):
    """GB/T 45570—2025 D.1.2 标度因数非线性度 (nonlinearity), eq. (D.7): K_n = |K_i − K|_max / K.

    K is the D.5 intercept, as D.7 is printed (so a slope W counts as nonlinearity; see
    interpretations.md).  Type A: the scatter of the maximising K_i (its revolutions) and the
    fit's standard error of K; type B: the revolution-pulse position accuracy.
    """

    item = "D.1.2"
    title = "Scale factor nonlinearity, angle method (标度因数非线性度)"
    clause = "D.1.2"
    metrics = (Metric("Kn", "scale factor nonlinearity", "K_n", "ppm", "D.1.2.3", "D.7"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        pts, rates, Ki, fit = self.fit(campaign, opts)
        K = float(fit.coef[0])
        Kn, i = F.nonlinearity_d7(Ki, K)
        u = math.hypot(pts[i].u_K, float(fit.stderr[0])) / K
        rows = [BudgetRow.type_a(msg("K_i at {rate:g} °/s (revolution scatter) and the fitted K", rate=pts[i].rate),
                                 "u(K_i − K)/K",
                                 Q_(u, ""), max(min(pts[i].m_plus, pts[i].m_minus) - 1, 1))]
        u_dr = point_drift(pts[i])
        if u_dr > 0:
            rows.append(BudgetRow.type_a(
                msg("bias drift between the + and − runs at {rate:g} °/s (D.1.1.2 g)), from the trend of the point's "
                    "revolutions", rate=pts[i].rate), "Δ·√(β² + u²(β))/(2·360·3600″·K_i)", Q_(u_dr, ""), pts[i].dof_trend,
                note=msg("β = {b:.3g} ± {u:.2g} P per revolution", b=pts[i].trend, u=pts[i].u_trend)))
        rows += _angle_row(campaign, Kn, "")
        budget = UncertaintyBudget("K_n", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Kn, ""), budget.combined, budget,
                     note=msg("largest |K_i − K| at {rate:g} °/s", rate=pts[i].rate), earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[s for p in pts for s in p.segments], options={k: str(v) for k, v in opts.items()})


class AsymmetryD13(ScaleFactorD11):
    """GB/T 45570—2025 D.1.3 标度因数不对称度 (asymmetry), eqs. (D.8)–(D.10).

    The zero-rate count N̄_0 (pulses per second, from the ``static-zero`` segments) times each
    revolution's time is removed from each direction's count; K_+ and K_− are the D.5
    intercepts of each direction; K_a = |K_+ − K_−| / ((K_+ + K_−)/2).  Type A: the two fits'
    standard errors and u(N̄_0) through the analytic ∂K_a/∂N̄_0
    (:func:`.formulas.asymmetry_sensitivity_n0`).
    """

    item = "D.1.3"
    title = "Scale factor asymmetry, angle method (标度因数不对称度)"
    clause = "D.1.3"
    metrics = (Metric("Ka", "scale factor asymmetry", "K_a", "ppm", "D.1.3.3", "D.10"),)
    requires = (REVOLUTIONS, ZERO)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return _sequence(options, zero=True)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        pts = collect_rate_points(type(self), campaign, int(opts["min_points"]))
        zeros = campaign.find_segments("static-zero")
        if not zeros:
            raise DataError(campaign.source, "segments", "D.1.3 needs the zero-rate count: segments of kind "
                            "\"static-zero\" (table at rest, τ = 1 s, n = 300) at the start and end (D.1.3.2 a))")
        per_s = []
        for z in zeros:
            ser = z.series("output", "P")
            x = np.asarray(ser.data.magnitude, dtype=float)
            if x.size < 2 or not np.all(np.isfinite(x)):
                raise DataError(z.file or f"segment {z.id}", "output", "needs at least 2 finite samples")
            per_s.append(x / float(ser.interval.to("s").magnitude))
        allz = np.concatenate(per_s)
        N0 = float(np.mean(allz))
        uN0 = float(np.std(allz, ddof=1) / math.sqrt(allz.size))
        rates = np.array([p.rate for p in pts])

        def ka(n0: float):
            kp = np.array([F.scale_factor_plus_d8(p.n_plus, n0, p.t_plus) for p in pts])
            km = np.array([F.scale_factor_minus_d9(p.n_minus, n0, p.t_minus) for p in pts])
            fp, fm = fit_line(rates, kp), fit_line(rates, km)
            return F.asymmetry_d10(float(fp.coef[0]), float(fm.coef[0])), fp, fm

        Ka, fp, fm = ka(N0)
        Kbar = 0.5 * (float(fp.coef[0]) + float(fm.coef[0]))
        u_fit = math.hypot(float(fp.stderr[0]), float(fm.stderr[0])) / Kbar
        # analytic sensitivity: a central difference through |K₊ − K₋| fails at the kink (issue 13)
        c_n0 = F.asymmetry_sensitivity_n0(rates, [p.t_plus for p in pts], [p.t_minus for p in pts],
                                          float(fp.coef[0]), float(fm.coef[0]))
        rows = [BudgetRow.type_a(msg("fits of K_+i and K_−i (D.4, D.5)"), "√(u²(K₊)+u²(K₋))/K̄", Q_(u_fit, ""), fp.dof),
                BudgetRow.type_a(msg("zero-rate count N̄_0"), "u(N̄₀)", Q_(uN0, "P/s"), allz.size - 1,
                                 sensitivity=Q_(abs(c_n0), "s/P"),
                                 note=msg("∂K_a/∂N̄₀ analytic through the D.5 intercepts (one-sided at K₊ = K₋)"))]
        drift = sweep_drift(pts)
        if drift.rms > 0:
            # N̄₀ is the bias at the start and the end (D.1.3.2 a)); at a rate point between them the bias
            # is off their mean by at most ḃ·S/2, S the time the test spans (zero records and runs)
            span = sum(float(np.asarray(z.series("output", "P").data.magnitude).size)
                       * float(z.series("output", "P").interval.to("s").magnitude) for z in zeros)
            span += sum(p.m_plus * p.t_plus + p.m_minus * p.t_minus for p in pts)
            Kbar_p_s = abs(Kbar)  # P/″ = (P/s)/(″/s)
            rows.append(BudgetRow.type_a(
                msg("bias drift during the sweep: the bias at each rate point against N̄₀ of the start and the end"),
                "ḃ·S/(2√3)", Q_(Kbar_p_s * drift.rms * span / (2.0 * math.sqrt(3.0)), "P/s"), drift.dof,
                sensitivity=Q_(abs(c_n0), "s/P"),
                note=msg("ḃ_rms = {b:.3g} (°/h)/h from the trends of {n} rate points' revolutions, over S = {S:.3g} h "
                         "(uniform within ±ḃ·S/2)", b=drift.rms * 3600.0, n=drift.points, S=span / 3600.0)))
        budget = UncertaintyBudget("K_a", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Ka, ""), budget.combined, budget,
                     note=msg("K₊ = {Kp:.8f} P/″, K₋ = {Km:.8f} P/″, N̄₀ = {N0:.4f} P/s", Kp=fp.coef[0], Km=fm.coef[0], N0=N0),
                     earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[z.id for z in zeros] + [s for p in pts for s in p.segments],
                       options={k: str(v) for k, v in opts.items()})


# --------------------------------------------------------------------------------------------
# D.1.4 repeatability, D.1.5 temperature sensitivity, D.1.6 input-axis misalignment
# --------------------------------------------------------------------------------------------

REPEAT_RATE = "30 °/s"  # D.1.4.2


def _grouped(campaign: Campaign, kind: str, key: str) -> dict[str, list]:
    groups: dict[str, list] = {}
    for s in campaign.find_segments(kind):
        groups.setdefault(str(s.condition(key)), []).append(s)
    return groups


def _counter_row(pts: list[RatePoint], value: float, unit: str) -> BudgetRow:
    """±1 P of the counter on the pulses of m revolutions, as a relative half-width on K."""
    p = pts[0]
    rel = 1.0 / (min(p.m_plus, p.m_minus) * abs(p.n_plus - p.n_minus))
    return BudgetRow.type_b(msg("counter resolution (±1 P over m revolutions each way)"), "δN/N", Q_(rel, ""),
                            distribution="uniform", sensitivity=Q_(abs(value), unit))


class ScaleFactorRepeatabilityD14(Procedure):
    """GB/T 45570—2025 D.1.4 标度因数重复性 (scale-factor repeatability), angle method, eq. (D.11).

    Q = 7 power-ons (segments of kind ``revolutions-repeat``, condition ``run`` = 1 … 7, at 30 °/s
    both ways), K_j by eq. (D.2) for each, K_r = s(K_j)/K̄.  Type A: the sampling uncertainty of a
    standard deviation of Q values, K_r/√(2(Q − 1)), ν = Q − 1; type B: the counter's ±1 P and
    the revolution-pulse position, per run (both bounded, uniform).
    """

    standard = STANDARD
    item = "D.1.4"
    title = "Scale factor repeatability, angle method (标度因数重复性)"
    clause = "D.1.4"
    metrics = (Metric("Kr", "scale factor repeatability", "K_r", "ppm", "D.1.4.3", "D.11"),)
    requires = (SegmentRequirement("revolutions-repeat", "m whole revolutions each way at 30 °/s on each of 7 "
                                   "power-ons, off ≥ 10 min between (D.1.4.2)",
                                   conditions={"rate": "deg/s", "turns": "", "run": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=14),)
    equipment = _EQUIPMENT
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate of the repeats (D.1.4.2: 30 °/s)"),
               Option("turns", 5, None, "whole revolutions m each way"),
               Option("Q", 7, None, "number of power-ons; D.11 is written for 7", minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        from metro.api import parse_quantity

        r = float(parse_quantity(options.get("rate", REPEAT_RATE), dimension="deg/s").to("deg/s").magnitude)
        m, q = int(options.get("turns", 5)), int(options.get("Q", 7))
        steps = []
        for j in range(1, q + 1):
            for sign, word in ((1, "counter-clockwise (+)"), (-1, "clockwise (−)")):
                steps.append(Step(f"run{j}-rate{sign * r:+g}", "revolutions-repeat",
                                  f"power-on {j} of {q}: {m} whole revolutions at {r:g} °/s {word} as D.1.1.2; "
                                  "then power off ≥ 10 min (D.1.4.2)", Q_(m * 360.0 / r, "s"), Q_(360.0 / r, "s"),
                                  {"rate": f"{sign * r:g} deg/s", "turns": m, "run": j}, warmup=Q_(30, "min")))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        q = int(opts["Q"])
        runs = _grouped(campaign, "revolutions-repeat", "run")
        if len(runs) != q:
            raise DataError(campaign.source, "segments",
                            f"D.1.4 needs {q} power-ons (segments of kind \"revolutions-repeat\" with run = 1 … {q}, "
                            f"D.1.4.2); found {len(runs)} run(s): {', '.join(sorted(runs)) or 'none'}",
                            hint="D.11 is written for 7 repeats")
        pts = []
        for run, segs in sorted(runs.items()):
            p = collect_rate_points(type(self), campaign, 1, segs, f"in run {run}")
            if len(p) != 1:
                raise DataError(campaign.source, f"segments.{segs[0].id}.conditions.rate",
                                f"run {run} has {len(p)} rate points; D.1.4 tests at one rate ({opts['rate']:~P})")
            pts.append((run, p[0]))
        Kj = [p.K for _, p in pts]
        want = float(opts["rate"].to("deg/s").magnitude)
        off = sorted({f"{p.rate:g}" for _, p in pts if abs(p.rate - want) > 0.01 * want})
        warnings = [msg("runs at {off} °/s; D.1.4.2 repeats the test at {want:g} °/s{hint}", off=", ".join(off),
                        want=want, hint=hint(" (option rate)"))] if off else []
        Kr = F2.scale_factor_repeatability_d11(Kj)
        if not Kr > 0:
            # identical whole counts: one pulse in m revolutions is coarser than the power-on scatter
            # (a coarse undithered counter), not a data error — K_r cannot be measured
            p0 = pts[0][1]
            res_ppm = 1e6 / (min(p0.m_plus, p0.m_minus) * abs(p0.n_plus - p0.n_minus))
            reason = msg("the {q} scale factors K_j are identical: one count over the m revolutions ({res:.3g} ppm of "
                         "K) is coarser than the power-on scatter, which cannot be measured — use more revolutions",
                         q=q, res=res_ppm)
            res = Result(self.metrics[0], Q_(0.0, ""), reportable=False, reason=reason, earth_rate="removed")
            return Outcome(STANDARD, self.item, self.title, self.clause, [res], warnings=warnings + [reason],
                           segments=[s for _, p in pts for s in p.segments],
                           options={k: str(v) for k, v in opts.items()})
        rows = [BudgetRow.type_a(msg("sampling of the standard deviation of Q = {q} scale factors (χ² bound)", q=q),
                                 "(s_{upper} − K_r)/2", Q_(std_sampling_u(Kr, q), ""), math.inf),
                _counter_row([p for _, p in pts], 1.0, "")]
        m = min(min(p.m_plus, p.m_minus) for _, p in pts)
        rows += [attrs.evolve(r, source=msg("{source}, run to run", source=r.source), sensitivity=Q_(1.0 / m, ""),
                              note=join("; ", [r.note, msg("over m = {m} revolutions", m=m)]))
                 for r in _angle_row(campaign, 1.0, "")]
        budget = UncertaintyBudget("K_r", "ppm", rows, coverage=COVERAGE)
        mean = float(np.mean(Kj))
        res = Result(self.metrics[0], Q_(Kr, ""), budget.combined, budget, note=msg("K̄ = {mean:.8f} P/″, Q = {q}", mean=mean, q=q), earth_rate="removed")
        table = TableSpec("K_runs", msg("K_j of each power-on (D.2)"), [msg("run"), "Ω (°/s)", "K_j (P/″)", "K_j − K̄ (ppm)"],
                          [[run, f"{p.rate:g}", f"{p.K:.8f}", f"{(p.K - mean) / mean * 1e6:.2f}"] for run, p in pts])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table], warnings=warnings,
                       segments=[s for _, p in pts for s in p.segments], options={k: str(v) for k, v in opts.items()})


def room_index(campaign: Campaign, segs_by_T: Mapping[str, list], room: float, need: int, clause: str) -> tuple[
        list[str], list[float], int]:
    """The temperature points (sorted), their values in °C and the index of room temperature
    (the point nearest ``room``, which must lie in 6.1.1's 15 °C … 35 °C)."""
    keys = sorted(segs_by_T, key=lambda k: float(parse_T(campaign, segs_by_T[k][0])))
    if len(keys) < need:
        raise DataError(campaign.source, "segments",
                        f"{clause} needs at least {need} temperature points (both limits and room temperature); "
                        f"found {len(keys)}: {', '.join(keys) or 'none'}")
    temps = [parse_T(campaign, segs_by_T[k][0]) for k in keys]
    i0 = int(np.argmin([abs(t - room) for t in temps]))
    if not 15.0 <= temps[i0] <= 35.0:
        raise DataError(campaign.source, f"segments.{segs_by_T[keys[i0]][0].id}.conditions.temperature",
                        f"no point at room temperature: the nearest is {temps[i0]:g} °C (6.1.1: 15 °C … 35 °C); "
                        f"{clause} refers K_t to room temperature")
    for i, t in enumerate(temps):
        if i != i0 and abs(t - temps[i0]) < 1.0:
            raise DataError(campaign.source, f"segments.{segs_by_T[keys[i]][0].id}.conditions.temperature",
                            f"{t:g} °C is within 1 °C of room temperature {temps[i0]:g} °C; K_t divides by T_i − T0")
    return keys, temps, i0


def parse_T(campaign: Campaign, seg) -> float:
    return float(seg.condition("temperature", "degC").to("degC").magnitude)


class ScaleFactorTemperatureSensitivityD15(Procedure):
    """GB/T 45570—2025 D.1.5 标度因数温度灵敏度 (scale-factor temperature sensitivity), angle
    method, eq. (D.12).

    At each temperature point (segments of kind ``revolutions-temperature``, condition
    ``temperature``, the full D.1.1.2 rate sweep) K is the D.5 intercept; K_t = max |(K_i − K_00)/
    (K_00 (T_i − T_0))| with K_00, T_0 at room temperature (the point nearest the option ``room``,
    within 15 °C … 35 °C).  Budget of the maximising point: the two fits' standard errors (A) and
    the chamber's temperature uncertainty on T_i − T_0 (B).
    """

    standard = STANDARD
    item = "D.1.5"
    title = "Scale factor temperature sensitivity, angle method (标度因数温度灵敏度)"
    clause = "D.1.5"
    metrics = (Metric("Kt", "scale factor temperature sensitivity", "K_t", "ppm/delta_degC", "D.1.5.3", "D.12"),)
    requires = (SegmentRequirement("revolutions-temperature", "the D.1.1.2 rate sweep at each temperature point after "
                                   "≥ 2 h soak, powered off while the temperature changes (D.1.5.2)",
                                   conditions={"rate": "deg/s", "turns": "", "temperature": "degC"},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=66),)
    equipment = _EQUIPMENT + (EquipmentRequirement("chamber", "temperature chamber, vibration-isolated, control "
                                                   "better than ±2 °C (D.1.5.1 b))"),)
    options = _OPTIONS + (
        Option("temperatures", "-40 °C, 20 °C, 60 °C", None,
               "temperature points for the sequence: both limits and room temperature (D.1.5.2 b))"),
        Option("room", "20 °C", "degC", "room temperature T0: the nearest point is the reference"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures", "-40 °C, 20 °C, 60 °C")).split(",")]
        steps = []
        for i, T in enumerate(temps):
            for st in _sequence(options, zero=False):
                steps.append(attrs.evolve(st, segment=f"T{i + 1}-{st.segment}", kind="revolutions-temperature",
                                          description=f"at {T} (power off, soak ≥ 2 h, D.1.5.2 c)): " + st.description,
                                          conditions=dict(st.conditions) | {"temperature": T},
                                          warmup=Q_(2, "h")))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        byT = _grouped(campaign, "revolutions-temperature", "temperature")
        keys, temps, i0 = room_index(campaign, byT, float(opts["room"].to("degC").magnitude), 3, "D.1.5")
        Ks, uKs, dofs, used = [], [], [], []
        for k, T in zip(keys, temps):
            pts = collect_rate_points(type(self), campaign, int(opts["min_points"]), byT[k], f"at {T:g} °C")
            rates = np.array([p.rate for p in pts])
            Ks.append(F.scale_factor_fit_d5_d6([p.K for p in pts], rates)[0])
            # type A of the D.5 intercept from each K_i's revolution scatter (not the residuals,
            # which hold the nonlinearity)
            ca, _ = F2.line_fit_sensitivities(rates)
            u, nu = F2.propagate(ca, [p.u_K for p in pts], [max(min(p.m_plus, p.m_minus) - 1, 1) for p in pts])
            uKs.append(u)
            dofs.append(nu)
            used += [s for p in pts for s in p.segments]
        Kt, imax = F2.scale_factor_temperature_sensitivity_d12(Ks, temps, i0)
        return _temperature_outcome(self, campaign, opts, Kt, imax, i0, temps, Ks, uKs, dofs, used, "P/″")


def _temperature_outcome(proc: Procedure, campaign: Campaign, opts, Kt: float, imax: int, i0: int, temps, Ks, uKs,
                         dofs, segments, k_unit: str) -> Outcome:
    """Result, budget, plot and table of D.1.5 / D.2.5 (the maximising point of D.12 / D.29)."""
    from .procedures import _delta_temperature_u
    from .repeatability import points_dof, pool_turn_on, scale_factor_turn_on

    dT = temps[imax] - temps[i0]
    K0 = Ks[i0]
    ci, c0 = 1.0 / (K0 * abs(dT)), abs(Ks[imax]) / (K0 * K0 * abs(dT))
    # D.1.5.2 c) / D.2.5.2 c): off while the chamber changes temperature, so each K_i is a power-on of
    # its own and carries K's turn-on scatter (D.1.4 / D.2.4 on this campaign; interpretations.md
    # "D.2.5 — every temperature point is a power-on" and "D.1.5 — …")
    # (σ_K² the posterior mean of the turn-on variance given the runs, ν = ∞: interpretations.md "σ_K — …")
    on = scale_factor_turn_on(campaign, int(opts.get("min_points", 11)), "angle" if proc.item == "D.1.5" else "rate")
    on, pooled_note = pool_turn_on(Ks, uKs, temps, on)
    s_on, nu_on, on_note = on.sigma, on.nu, on.note
    u_on = [s_on * abs(k) for k in Ks]
    sel_observed = s_on > 0 and len(Ks) >= 4  # the points may share a power-on after all: at most what they show
    uKs = [math.hypot(u, v) for u, v in zip(uKs, u_on)]
    # the two turn-on parts are one estimate (σ_K of the same runs): one ν between them, not two
    # (interpretations.md "D.2.5 — the line test with an estimated scatter")
    u_on_both = math.hypot(ci * u_on[imax], c0 * u_on[i0])
    parts = [(ci * math.sqrt(max(uKs[imax] ** 2 - u_on[imax] ** 2, 0.0)), dofs[imax]),
             (c0 * math.sqrt(max(uKs[i0] ** 2 - u_on[i0] ** 2, 0.0)), dofs[i0]),
             (u_on_both, nu_on)]
    uA = math.sqrt(sum(u * u for u, _ in parts))
    den = sum(u**4 / max(d, 1) for u, d in parts)
    nu = uA**4 / den if den > 0 else math.inf
    # the line test of the selection Monte Carlo against u's whose turn-on part rests on an estimate of
    # on.dof degrees of freedom (the runs', pooled): F(n − 2, ν_eff of the points' u) rather than χ²
    sel = max_slope_selection(Ks, uKs, temps, i0, relative=True, observed=sel_observed,
                                 u_dof=points_dof(uKs, u_on, dofs, on.dof if on.dof > 0 else math.inf))
    notes = [msg("the maximising point alone gives {u:.3g}/°C", u=uA)]
    if s_on > 0 and on.dof > 0:
        notes.append(msg("each K_i a power-on of its own: with the turn-on scatter of K, {s:.3g} ppm (the posterior "
                         "mean of its variance given {d:.3g} degrees of freedom of the repeatability runs on this "
                         "campaign{resolved}; ν = ∞)", s=s_on * 1e6, d=on.dof,
                         resolved=msg(", K_r² − mean u²(K_j)/K_j² ≤ 0: not resolved from the runs' own noise, only "
                                      "bounded") if on.s2 <= on.within else ""))
    elif s_on > 0:
        notes.append(msg("each K_i a power-on of its own: with the turn-on scatter of K, {s:.3g} ppm stated for the "
                         "device{hint}", s=s_on * 1e6, hint=hint(" (device.scale_factor_repeatability)")))
    if pooled_note:
        notes.append(pooled_note)
    rows = [BudgetRow.type_a(msg("K at every T_i and T_0 through the maximum of the ratios (Monte Carlo about the "
                                 "smoothed K(T))"), "s(max_i |ΔK_i/(K₀₀ΔT_i)|)", Q_(max(sel.s, uA), "1/delta_degC"), nu,
                             note=join("; ", notes))]
    rows += selection_rows(sel, len(Ks) - 1, "1/delta_degC")
    Kt = max(sel.value, 0.0)
    uT = _delta_temperature_u(campaign)
    if uT is not None:
        rows.append(BudgetRow.type_b(msg("chamber temperature T_i and T_0 ({equipment})", equipment=uT[1]), "√2·u(T)",
                                     Q_(math.sqrt(2) * uT[0], "K"), distribution="normal", k=1.0,
                                     sensitivity=Q_(Kt / abs(dT), "1/delta_degC/K"), note="∂K_t/∂ΔT = −K_t/ΔT"))
    budget = UncertaintyBudget("K_t", "ppm/delta_degC", rows, coverage=COVERAGE)
    res = Result(proc.metrics[0], Q_(Kt, "1/delta_degC"), budget.combined, budget,
                 note=join("; ", [msg("largest at T = {T:g} °C against T0 = {T0:g} °C", T=temps[imax], T0=temps[i0]),
                                  selection_note(sel, 1e6, 'ppm/°C')] + ([on_note] if on_note else [])),
                 earth_rate="removed")
    # each point a power-on of its own (D.1.5.2 c) / D.2.5.2 c)): without K's turn-on scatter bounded by
    # ≥ MIN_TURN_ON_RUNS D.1.4 / D.2.4 runs or stated (device.scale_factor_repeatability), not reportable
    if not on.known:
        from .repeatability import missing_turn_on

        why = msg("each temperature point is a power-on of its own ({clause}.2 c))", clause=proc.item)
        res = attrs.evolve(res, reportable=False, reason=join("; ", [missing_turn_on(
            "K", "D.1.4" if proc.item == "D.1.5" else "D.2.4", why), on_note]))
    plot = PlotSpec("K_temperature", msg("Scale factor against temperature ({item})", item=proc.item), "T (°C)",
                    "(K − K₀₀)/K₀₀ (ppm)",
                    [{"label": "K(T)", "x": list(temps), "y": [(k - K0) / K0 * 1e6 for k in Ks],
                      "yerr": [2e6 * u / K0 for u in uKs], "style": "o"}])
    table = TableSpec("K_temperatures", msg("K at each temperature point"), ["T (°C)", f"K ({k_unit})",
                                                                        "|(K − K₀₀)/(K₀₀ΔT)| (ppm/°C)"],
                      [[f"{t:g}", f"{k:.8g}", msg("room (T0)") if i == i0 else f"{abs((k - K0) / (K0 * (t - temps[i0]))) * 1e6:.4g}"]
                       for i, (t, k) in enumerate(zip(temps, Ks))])
    return Outcome(STANDARD, proc.item, proc.title, proc.clause, [res], plots=[plot], tables=[table],
                   segments=list(segments), options={k: str(v) for k, v in opts.items()})


#: the four mountings of D.1.6.3 / D.2.6.3: (axis along the table axis, turn about IRA)
MOUNTINGS = (("XRA", 0), ("XRA", 180), ("YRA", 0), ("YRA", 180))


def mounting_groups(campaign: Campaign, kind: str, clause: str) -> dict[tuple[str, int], list]:
    """Segments of each of the four mountings (conditions ``axis_up`` XRA/YRA and ``turn`` 0°/180°);
    a missing mounting is an error that names it."""
    groups: dict[tuple[str, int], list] = {}
    from metro.api import parse_quantity

    for s in campaign.find_segments(kind):
        ax = str(s.condition("axis_up")).upper().replace("+", "").strip()
        turn = float(parse_quantity(s.condition("turn"), dimension="deg", file=campaign.source,
                                    field=f"segments.{s.id}.conditions.turn").to("deg").magnitude) % 360.0
        if ax not in ("XRA", "YRA") or min(abs(turn), abs(turn - 180.0)) > 1e-6:
            raise DataError(campaign.source, f"segments.{s.id}.conditions",
                            f"axis_up = {s.conditions.get('axis_up')!r}, turn = {s.conditions.get('turn')!r}: a "
                            f"{clause} mounting has XRA or YRA along the table axis, turned 0° or 180° about IRA")
        groups.setdefault((ax, int(round(turn))), []).append(s)
    missing = [f"{ax} up, turned {t}°" for ax, t in MOUNTINGS if (ax, t) not in groups]
    if missing:
        raise DataError(campaign.source, "segments",
                        f"{clause} needs four mountings (segments of kind \"{kind}\"); missing: {'; '.join(missing)}",
                        hint="the 180° turn about IRA cancels the fixture's error (D.1.6.3 e))")
    return groups


def misalignment_outcome(proc: Procedure, campaign: Campaign, opts, ang: Mapping[tuple[str, int], tuple[float, float, int]],
                         rel_rows: list[BudgetRow], segments: list[str], what: str) -> Outcome:
    """α, β (D.15/D.32, D.35) and γ (D.16/D.36) with their budgets from the four mountings'
    angles ``ang[(axis, turn)] = (angle in °, its type A standard uncertainty in °, ν)``.

    ``rel_rows`` are relative type B rows (scale factor, revolution pulse …) with sensitivity 1;
    each is scaled by the result.  The fixture's re-seating tilt (``fixture`` equipment,
    ``reseat_tilt``, a half-width per mounting) enters each angle with sensitivity 1/√2."""
    fx = campaign.equipment_for("fixture")
    reseat = None
    if fx is not None and "reseat_tilt" in fx.properties:
        reseat = (fx.prop("reseat_tilt", "arcsec", source=campaign.source), fx.describe())
    vals, us, nus = {}, {}, {}
    for sym, ax in (("α", "XRA"), ("β", "YRA")):
        (a1, u1, n1), (a2, u2, n2) = ang[(ax, 0)], ang[(ax, 180)]
        vals[sym] = F2.misalignment_half_difference_d15(a1, a2)
        us[sym] = 0.5 * math.hypot(u1, u2)
        nus[sym] = max(min(n1, n2), 1)
    gamma = F2.misalignment_gamma_d16(vals["α"], vals["β"])
    results = []
    for metric in proc.metrics:
        sym = metric.symbol
        if sym in vals:
            v = vals[sym]
            rows = [BudgetRow.type_a(msg("{what}, the two {sym} mountings", what=what, sym=sym), f"u({sym})", Q_(us[sym], "deg"), nus[sym])]
            sens_reseat = 1.0 / math.sqrt(2.0)
        else:
            v = gamma
            ca = vals["α"] / gamma if gamma > 0 else 1.0
            cb = vals["β"] / gamma if gamma > 0 else 1.0
            rows = [BudgetRow.type_a(msg("{what}, α mountings", what=what), "u(α)", Q_(us["α"], "deg"), nus["α"],
                                     sensitivity=Q_(abs(ca), "")),
                    BudgetRow.type_a(msg("{what}, β mountings", what=what), "u(β)", Q_(us["β"], "deg"), nus["β"],
                                     sensitivity=Q_(abs(cb), ""))]
            sens_reseat = math.hypot(ca, cb) / math.sqrt(2.0)
        if reseat is not None:
            rows.append(BudgetRow.type_b(msg("re-seating tilt of the gyro in the fixture ({equipment})", equipment=reseat[1]),
                                         "δ_{fixture}",
                                         reseat[0].to("deg"), distribution="uniform",
                                         sensitivity=Q_(sens_reseat, ""),
                                         note=msg("independent in the 0° and 180° mountings; (δ₁ − δ₂)/2")))
        rows += [attrs.evolve(r, sensitivity=Q_(abs(v), "deg")) for r in rel_rows]
        budget = UncertaintyBudget(sym, "deg", rows, coverage=COVERAGE)
        results.append(Result(metric, Q_(v, "deg"), budget.combined, budget,
                              note=f"= {v * 3600:.2f}″", earth_rate="removed"))
    table = TableSpec("mountings", msg("Angle of each mounting ({item})", item=proc.item),
                      [msg("mounting"), msg("angle (°)"), msg("angle (″)")],
                      [[msg("{axis} up, turned {turn}°", axis=ax, turn=t), f"{ang[(ax, t)][0]:.6f}", f"{ang[(ax, t)][0] * 3600:.2f}"]
                       for ax, t in MOUNTINGS])
    return Outcome(STANDARD, proc.item, proc.title, proc.clause, results, tables=[table], segments=segments,
                   options={k: str(v) for k, v in opts.items()})


def misalignment_metrics(clause: str, eqs: tuple[str, str, str]) -> tuple[Metric, ...]:
    return (Metric("alpha", "input axis misalignment towards XRA", "α", "deg", clause, eqs[0]),
            Metric("beta", "input axis misalignment towards YRA", "β", "deg", clause, eqs[1]),
            Metric("gamma", "input axis misalignment", "γ", "deg", clause, eqs[2]))


def mounting_steps(kind: str, rate: float, options: Mapping[str, Any], revolutions: bool) -> list[Step]:
    m = int(options.get("turns", 5))
    steps = []
    for ax, turn in MOUNTINGS:
        for sign, word in ((1, "counter-clockwise (+)"), (-1, "clockwise (−)")):
            cond = {"axis_up": ax, "turn": f"{turn} deg", "rate": f"{sign * rate:g} deg/s"}
            what = (f"{m} whole revolutions" if revolutions else f"{m} whole revolutions' output")
            if revolutions:
                cond["turns"] = m
            steps.append(Step(f"{ax}-{turn}-rate{sign * rate:+g}", kind,
                              f"{ax} along the table axis, gyro turned {turn}° about IRA in the fixture: {what} at "
                              f"{rate:g} °/s {word}", Q_(m * 360.0 / rate, "s"),
                              Q_(360.0 / rate, "s") if revolutions else Q_(1, "s"), cond, warmup=Q_(30, "min")))
    return steps


class InputAxisMisalignmentD16(Procedure):
    """GB/T 45570—2025 D.1.6 输入轴失准角 (input-axis misalignment), angle method, eqs. (D.13)–(D.16).

    Four mountings (segments of kind ``revolutions-mounting``, conditions ``axis_up`` XRA/YRA and
    ``turn`` 0°/180° about IRA, signed ``rate``): N_± per mounting (D.13), α_{1,2} = (N₊ − N₋)/
    (2·360·3600·K)·180/π (D.14) with the device's K, α = (α₁ − α₂)/2 (D.15), β likewise,
    γ = √(α² + β²) (D.16).  Type A: the revolutions' count scatter; type B: the fixture's
    re-seating tilt, the scale factor K, the revolution-pulse position.
    """

    standard = STANDARD
    item = "D.1.6"
    title = "Input axis misalignment, angle method (输入轴失准角)"
    clause = "D.1.6"
    metrics = misalignment_metrics("D.1.6.4", ("D.15", "D.15", "D.16"))
    requires = (SegmentRequirement("revolutions-mounting", "m whole revolutions each way with XRA, then YRA, along the "
                                   "table axis, each before and after a 180° turn about IRA (D.1.6.3)",
                                   conditions={"axis_up": "", "turn": "deg", "rate": "deg/s", "turns": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=8),)
    equipment = _EQUIPMENT + (EquipmentRequirement("fixture", "fixture holding XRA/YRA along the table axis, "
                                                   "turnable 180° about IRA; its re-seating tilt enters the budget"),)
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate (D.1.6.3 d): \"a given rate\")"),
               Option("turns", 5, None, "whole revolutions m each way"))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        from metro.api import parse_quantity

        r = float(parse_quantity(options.get("rate", REPEAT_RATE), dimension="deg/s").to("deg/s").magnitude)
        return mounting_steps("revolutions-mounting", r, options, revolutions=True)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        from metro.api import required_scale_factor

        opts = self.option_values(ctx.options)
        groups = mounting_groups(campaign, "revolutions-mounting", "D.1.6")
        k, u_rel_K = required_scale_factor(campaign.device, "P/arcsec", source=campaign.source,
                                           needed_by="eq. (D.14) of D.1.6 (K from D.1.1)")
        ang, used = {}, []
        for (ax, turn), segs in groups.items():
            pts = collect_rate_points(type(self), campaign, 1, segs, f"({ax} up, turned {turn}°)")
            if len(pts) != 1:
                raise DataError(campaign.source, f"segments.{segs[0].id}.conditions.rate",
                                f"mounting {ax} up, turned {turn}° has {len(pts)} rate points; D.1.6 uses one rate")
            p = pts[0]
            a = F2.misalignment_d14(p.n_plus, p.n_minus, k)
            up = p.s_plus / math.sqrt(p.m_plus) if p.m_plus > 1 else 0.5
            um = p.s_minus / math.sqrt(p.m_minus) if p.m_minus > 1 else 0.5
            u = math.hypot(up, um) / (2.0 * F.REVOLUTION_ARCSEC * k) * 180.0 / math.pi
            ang[(ax, turn)] = (a, u, max(min(p.m_plus, p.m_minus) - 1, 1))
            used += list(p.segments)
        rel = []
        if u_rel_K > 0:
            rel.append(BudgetRow.type_b("scale factor K (device)", "u_rel(K)", Q_(u_rel_K, ""), distribution="normal",
                                        k=1.0, note=msg("K = {k:g} P/″; α ∝ 1/K", k=k)))
        rel += [attrs.evolve(r, sensitivity=Q_(1.0, "")) for r in _angle_row(campaign, 1.0, "")]
        return misalignment_outcome(self, campaign, opts, ang, rel, used, msg("revolution count scatter"))


PROCEDURES = (ScaleFactorD11, NonlinearityD12, AsymmetryD13, ScaleFactorRepeatabilityD14,
              ScaleFactorTemperatureSensitivityD15, InputAxisMisalignmentD16)

"""GB/T 45570—2025 D.1 scale factor series by the angle method (pulse output):
D.1.1 scale factor, D.1.2 nonlinearity, D.1.3 asymmetry.

Data: one segment of kind ``rate-revolutions`` per rate point and direction, with conditions
``rate`` (signed: + counter-clockwise, − clockwise, D.1.1.2 note) and ``turns`` (m), and columns
``count`` (P, pulses over each whole revolution, counted between revolution pulses) and
``duration`` (s, the time of each revolution, D.1.3.2 a)); for D.1.3 also segments of kind
``static-zero`` (table at rest, τ = 1 s, n = 300, at several symmetric positions, at the start
and end of the test) with an ``output`` column in P.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np

from metro.core.budget import BudgetRow, UncertaintyBudget
from metro.core.errors import DataError
from metro.core.lsq import fit_line
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
    SegmentRequirement,
    Step,
    TableSpec,
)
from metro.core.units import Q_

from . import formulas as F
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
    from metro.core.units import parse_quantity

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

    @property
    def K(self) -> float:
        return F.scale_factor_d2(self.n_plus, self.n_minus)

    @property
    def u_K(self) -> float:
        """Standard uncertainty of K_i from the scatter of the revolutions' counts."""
        up = self.s_plus / math.sqrt(self.m_plus) if self.m_plus > 1 else 0.5
        um = self.s_minus / math.sqrt(self.m_minus) if self.m_minus > 1 else 0.5
        return math.hypot(up, um) / (2 * F.REVOLUTION_ARCSEC)


def collect_rate_points(proc: type[Procedure], campaign: Campaign, min_points: int) -> list[RatePoint]:
    """Pair the + and − revolution segments of every rate point (D.1.1.2 g), eq. (D.1))."""
    segs = campaign.find_segments("rate-revolutions")
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
                            f"rate point {rate:g} °/s has no {missing} run; D.2 needs both directions")
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
                        float(np.mean(t)), s.id)
        (np_, sp, mp, tp, idp), (nm, sm, mm, tm, idm) = stats[1], stats[-1]
        points.append(RatePoint(rate, np_, nm, sp, sm, mp, mm, tp, tm, (idp, idm)))
    if len(points) < min_points:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs at least {min_points} rate points (D.1.1.2 e)); "
                        f"found {len(points)}", hint="or lower the option min_points if agreed with the user")
    return points


def _angle_row(campaign: Campaign, value: float, unit: str) -> list[BudgetRow]:
    table = campaign.equipment_for("rate_table")
    if table is None or "revolution_pulse_accuracy" not in table.properties:
        return []
    acc = table.prop("revolution_pulse_accuracy", "arcsec", source=campaign.source)
    rel = float(acc.to("arcsec").magnitude) / F.REVOLUTION_ARCSEC
    return [BudgetRow.type_b(f"revolution pulse position ({table.describe()})", "δθ/360°", Q_(rel, ""),
                             distribution="uniform", sensitivity=Q_(abs(value), unit),
                             note=f"±{acc:~P} on 360° (D.1.1.1 d))")]


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
        rows = [BudgetRow.type_a("least-squares fit of K_i = K + W·Ω_i (D.4)", "s(K)", Q_(uK, "P/arcsec"), fit.dof,
                                 note=f"{len(pts)} rate points")]
        rows += _angle_row(campaign, K, "P/arcsec")
        budget = UncertaintyBudget("K", "P/arcsec", rows, coverage=COVERAGE)
        res = [Result(self.metrics[0], Q_(K, "P/arcsec"), budget.combined, budget),
               Result(self.metrics[1], Q_(W, "P/arcsec/(deg/s)"), Q_(uW, "P/arcsec/(deg/s)"))]
        model = K + W * rates
        plot = PlotSpec("K_rate", "K_i against rate with the D.4 fit, and the residuals",
                        "Ω (°/s)", "K_i (P/″)",
                        [{"label": "K_i (D.2)", "x": rates.tolist(), "y": Ki.tolist(),
                          "yerr": [2 * p.u_K for p in pts], "style": "o"},
                         {"label": f"K + WΩ: K = {K:.7g} P/″", "x": rates.tolist(), "y": model.tolist(), "style": "-"}],
                        logx=True)
        table = TableSpec("K_points", "K_i per rate point (D.1, D.2)",
                          ["Ω (°/s)", "N₊ (P)", "N₋ (P)", "K_i (P/″)", "K_i − (K + WΩ_i) (ppm of K)"],
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
        rows = [BudgetRow.type_a(f"K_i at {pts[i].rate:g} °/s (revolution scatter) and the fitted K", "u(K_i − K)/K",
                                 Q_(u, ""), max(min(pts[i].m_plus, pts[i].m_minus) - 1, 1))]
        rows += _angle_row(campaign, Kn, "")
        budget = UncertaintyBudget("K_n", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Kn, ""), budget.combined, budget,
                     note=f"largest |K_i − K| at {pts[i].rate:g} °/s")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[s for p in pts for s in p.segments], options={k: str(v) for k, v in opts.items()})


class AsymmetryD13(ScaleFactorD11):
    """GB/T 45570—2025 D.1.3 标度因数不对称度 (asymmetry), eqs. (D.8)–(D.10).

    The zero-rate count N̄_0 (pulses per second, from the ``static-zero`` segments) times each
    revolution's time is removed from each direction's count; K_+ and K_− are the D.5
    intercepts of each direction; K_a = |K_+ − K_−| / ((K_+ + K_−)/2).  Type A: the two fits'
    standard errors and u(N̄_0) (its effect found by re-evaluating with N̄_0 ± u).
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
        c_n0 = (ka(N0 + uN0)[0] - ka(N0 - uN0)[0]) / (2 * uN0) if uN0 > 0 else 0.0
        rows = [BudgetRow.type_a("fits of K_+i and K_−i (D.4, D.5)", "√(u²(K₊)+u²(K₋))/K̄", Q_(u_fit, ""), fp.dof),
                BudgetRow.type_a("zero-rate count N̄_0", "u(N̄₀)", Q_(uN0, "P/s"), allz.size - 1,
                                 sensitivity=Q_(abs(c_n0), "s/P"), note="sensitivity by re-evaluation at N̄₀ ± u")]
        budget = UncertaintyBudget("K_a", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Ka, ""), budget.combined, budget,
                     note=f"K₊ = {fp.coef[0]:.8f} P/″, K₋ = {fm.coef[0]:.8f} P/″, N̄₀ = {N0:.4f} P/s")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[z.id for z in zeros] + [s for p in pts for s in p.segments],
                       options={k: str(v) for k, v in opts.items()})


PROCEDURES = (ScaleFactorD11, NonlinearityD12, AsymmetryD13)

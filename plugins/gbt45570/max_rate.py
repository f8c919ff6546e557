"""GB/T 45570—2025 D.3 maximum input rate: the largest tested rate whose range meets the
scale-factor nonlinearity limit, on the sweep of either method (D.1 angle method, D.7; D.2 rate
method, D.23–D.25)."""

from __future__ import annotations

from typing import Any, Callable, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, DeviceUnderTest, Metric, Option, Outcome,
                       PlotSpec, Procedure, ProcedureError, Result, RunContext, SegmentRequirement,
                       Step, TableSpec, UncertaintyBudget, fit_line, hint, join, msg,
                       parse_quantity)

from . import formulas as F
from . import formulas_rate as F2
from .common import COVERAGE, STANDARD, GbtItem, group_of, opts_text
from .rate_data import (RATE_EQUIPMENT, RATE_OUTPUT, collect_rate_data, default_nonlinearity_limit,
                        fit_scale_factor, nonlinearity_budget, nonlinearity_of, rate_row,
                        rate_sequence)
from .revolutions import angle_sequence, collect_rate_points


class MaxInputRateD3(GbtItem):
    """GB/T 45570—2025 D.3 最大输入角速率 (maximum input rate).

    The largest tested table rate Ω whose range [−Ω, +Ω] has a scale-factor nonlinearity within
    the limit (definition 3.13 note 1).  K_n of each range is that of the data's method: D.7 on
    the K_i of the rate points up to Ω (angle method, ``rate-revolutions`` segments), or
    D.23–D.25 on the F_kj up to Ω with F_m the output at Ω (rate method, ``rate-output``
    segments).  The limit (option ``Kn_limit``) defaults to the device's
    ``nonlinearity_limit``, else tables A.1/B.1 for its technology and application.  Type A:
    the rate realised at Ω_max as the gyro indicates it (its output's scatter); type B: the rate
    table's rate accuracy.
    """

    item = "D.3"
    title = "Maximum input rate (最大输入角速率)"
    clause = "D.3"
    metrics = (Metric("Omega_max", "maximum input rate", "Ω_max", "deg/s", "D.3", "D.7, D.25"),)
    requires = (attrs.evolve(RATE_OUTPUT, description="rate method: " + RATE_OUTPUT.description,
                             alternative="sweep"),
                SegmentRequirement("rate-revolutions",
                                   "or, angle method: m whole revolutions at each rate point, each "
                                   "direction (D.1.1.2 g))", conditions={"rate": "deg/s",
                                                                         "turns": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=22,
                                   alternative="sweep"))
    equipment = RATE_EQUIPMENT
    options = (
        Option("Kn_limit", None, None,
               "nonlinearity limit, e.g. \"10 ppm\" (default: device.nonlinearity_limit, "
               "else table A.1/B.1 for the device's technology and application)"),
        Option("method", "auto", None,
               "\"angle\" (pulse output, D.1), \"rate\" (LSB output, D.2) or \"auto\" (the sweep "
               "the data hold; both: the one matching the device's output; for the sequence, "
               "\"auto\" means angle)"),
        Option("max_rate", "400 °/s", "deg/s",
               "largest rate point tested (test beyond the expected maximum)"),
        Option("turns", 5, None, "angle method: whole revolutions m per rate point and direction"),
        Option("duration", "100 s", "s", "rate method: record at each rate point and at rest"),
        Option("interval", "1 s", "s", "rate method: sampling interval"),
        Option("min_points", 11, None, "fewest rate points accepted (D.1.1.2 e), D.2.1.2 e))"),
        Option("min_range_points", 3, None,
               "fewest rate points in a range before its K_n is judged"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        if str(options.get("method", "auto")).lower() == "rate":
            return rate_sequence(options)
        return angle_sequence(options, zero=False)

    def sequence_for_device(self, options: Mapping[str, Any],
                            device: DeviceUnderTest | None) -> list[Step]:
        """The sequence for a known device: ``method = auto`` becomes the sweep the device can give
        —
        whole-revolution pulse counts (angle method) need a pulse output, so a digital or analog
        output takes the rate method; a pulse output follows the 6.2.7.1 method rule."""
        if device is None or str(options.get("method", "auto")).lower() != "auto":
            return self.sequence(options)
        from .method_rule import method_for

        method = method_for(device)[0] if str(device.output).lower() == "pulse" else "rate"
        return self.sequence(dict(options) | {"method": method})

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        method = _d3_method(campaign, opts)
        limit, lim_src = _d3_limit(campaign, opts)
        nmin, rmin = int(opts["min_points"]), int(opts["min_range_points"])
        sweep = (_angle_sweep(type(self), campaign, nmin) if method == "angle" else
                 _rate_sweep(type(self), campaign, nmin))
        try:
            om, curve = F2.max_input_rate_d3(sweep.rates, sweep.kn_of, limit, rmin)
        except ValueError as exc:
            raise DataError(campaign.source, "segments", f"D.3: {exc}") from exc
        if om is None:
            raise ProcedureError(f"D.3: no tested range meets the nonlinearity limit "
                                 f"{limit * 1e6:g} ppm ({lim_src}); the smallest range, up to "
                                 f"{curve[0][0]:g} °/s, has K_n = {curve[0][1] * 1e6:.3g} ppm",
                                 hint="test lower rates, or check the limit (option Kn_limit)")
        warnings = []
        if om == max(sweep.rates):
            warnings.append(msg("K_n meets the limit up to the largest rate tested ({om:g} °/s); "
                                "the maximum input rate "
                                "may be higher — test beyond it{hint}", om=om,
                                hint=hint(" (plan with -o max_rate=…)")))
        failing_below = [r for r, kn in curve if r < om and kn > limit]
        if failing_below:
            warnings.append(msg("ranges up to {rates} °/s exceed the limit while the range up to "
                                "{om:g} °/s meets it "
                                "(definition 3.13 judges the range up to Ω_max)",
                                rates=", ".join(f'{r:g}' for r in failing_below), om=om))
        # type A: the table rate at Ω_max as the gyro indicates it
        u_rate, nu = sweep.rate_u(om)
        how = msg("angle method") if method == "angle" else msg("rate method")
        rows = [BudgetRow.type_a(msg("rate realised at {om:g} °/s, as the gyro indicates it",
                                     om=om), "u(Ω)",
                                 Q_(u_rate, "deg/s"), nu, note=how)]
        rows += rate_row(campaign, msg("at {om:g} °/s", om=om), om, "deg/s",
                         msg("the table's setting of Ω_max"),
                         rate=om)
        rows += _decision_rows(curve, sweep.kn_u, limit, om)
        budget = UncertaintyBudget("Ω_max", "deg/s", rows, coverage=COVERAGE)
        kn_at = dict(curve)[om]
        res = Result(
            self.metrics[0],
            Q_(om, "deg/s"),
            budget.combined,
            budget,
            note=join(
                "; ",
                [
                    msg(
                        "K_n up to {om:g} °/s = {kn:.3g} ppm ≤ {limit:g} ppm ({source})",
                        om=om,
                        kn=kn_at * 1e6,
                        limit=limit * 1e6,
                        source=lim_src,
                    ),
                    how,
                ],
            ),
            earth_rate="not applicable",
        )
        plot, table = _d3_figures(curve, limit)
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot],
                       tables=[table],
                       warnings=warnings, segments=sweep.segments, options=opts_text(opts))


def _d3_method(campaign: Campaign, opts: Mapping[str, Any]) -> str:
    """D.3's sweep, "angle" or "rate": the option ``method``, or with "auto" the sweep the data hold
    (both: the one matching the device's output)."""
    method = str(opts["method"]).strip().lower()
    if method not in ("auto", "angle", "rate"):
        raise ProcedureError(f"D.3: option method = {opts['method']!r}; use angle, rate or auto")
    if method != "auto":
        return method
    has_angle = bool(campaign.find_segments("rate-revolutions"))
    has_rate = any(group_of(s) == ("", "") for s in campaign.find_segments("rate-output"))
    if has_angle and has_rate:
        # both sweeps measured: the one that matches the device's output
        return "rate" if str(campaign.device.output).lower() in ("digital", "analog") else "angle"
    if has_angle:
        return "angle"
    if has_rate:
        return "rate"
    raise DataError(campaign.source, "segments",
                    "D.3 needs the scale-factor sweep of D.1 (segments of kind "
                    "\"rate-revolutions\") or of "
                    "D.2 (\"rate-output\" and \"rate-static\"); none found",
                    hint="`metro plan --standard gbt45570 --item D.3` lists them")


def _d3_limit(campaign: Campaign, opts: Mapping[str, Any]) -> tuple[float, str]:
    """The K_n limit D.3 judges against and where it comes from (option ``Kn_limit``, else
    :func:`.rate_data.default_nonlinearity_limit`)."""
    if opts["Kn_limit"] is not None:
        lim_q = parse_quantity(opts["Kn_limit"], dimension="", field="option Kn_limit")
        limit, lim_src = float(lim_q.to("").magnitude), "option Kn_limit"
    else:
        lim_q, lim_src = default_nonlinearity_limit(campaign.device, campaign.source)
        limit = float(lim_q.to("").magnitude)
    if not limit > 0:
        raise ProcedureError(f"D.3: the nonlinearity limit must be positive, got {limit:g}")
    return limit, lim_src


@attrs.frozen
class _Sweep:
    """What D.3 reads of one method's sweep: the tested rates, K_n of the range up to a rate and
    its standard uncertainty, the type A of the rate realised at Ω_max, the segments used."""

    rates: list[float]
    kn_of: Callable[[float], float]
    kn_u: Callable[[float], float]
    rate_u: Callable[[float], tuple[float, float]]
    segments: list[str]


def _angle_sweep(proc: type[Procedure], campaign: Campaign, nmin: int) -> _Sweep:
    """D.3 on the angle method's sweep: K_n of D.7 on the K_i up to each rate."""
    pts = collect_rate_points(proc, campaign, nmin)

    def kn_of(upto: float) -> float:
        sub = [p for p in pts if p.rate <= upto * (1 + 1e-12)]
        fit = fit_line(np.array([p.rate for p in sub]), np.array([p.K for p in sub]))
        return F.nonlinearity_d7([p.K for p in sub], float(fit.coef[0]))[0]

    def kn_u(upto: float) -> float:
        # D.7's |K_j − K|/K with K the D.5 intercept: K_j − K = Σ g_i·K_i, g = δ_ij − c_a,i
        sub = [p for p in pts if p.rate <= upto * (1 + 1e-12)]
        w = np.array([p.rate for p in sub])
        Ki = np.array([p.K for p in sub])
        K0 = float(fit_line(w, Ki).coef[0])
        j = F.nonlinearity_d7(Ki, K0)[1]
        ca, _cb = F2.line_fit_sensitivities(w)
        g = -ca
        g[j] += 1.0
        return F2.propagate(g / K0, [p.u_K for p in sub], [max(min(p.m_plus, p.m_minus) - 1,
                                                               1) for p in sub])[0]

    def rate_u(om: float) -> tuple[float, float]:
        p = next(p for p in pts if p.rate == om)
        return om * p.u_K / p.K, max(min(p.m_plus, p.m_minus) - 1, 1)

    return _Sweep([p.rate for p in pts], kn_of, kn_u, rate_u, [s for p in pts for s in p.segments])


def _rate_sweep(proc: type[Procedure], campaign: Campaign, nmin: int) -> _Sweep:
    """D.3 on the rate method's sweep: K_n of D.23–D.25 on the F_kj up to each rate."""
    data = collect_rate_data(proc, campaign, nmin)

    def kn_of(upto: float) -> float:
        return nonlinearity_of(data, upto)[0]

    def kn_u(upto: float) -> float:
        # D.2.2's budget of the range's K_n: its outputs' scatter, resolution, the table's rate
        # error
        _kn, j, Fm, sel, K, _F0 = nonlinearity_of(data, upto)
        b = nonlinearity_budget(campaign, data, j, Fm, K, sel=sel)
        return float(b.combined.to("").magnitude)

    def rate_u(om: float) -> tuple[float, float]:
        K = fit_scale_factor(data).K
        sel = np.abs(data.rates) == om
        u = float(np.sqrt(np.mean(data.uF[sel] ** 2) / sel.sum())) / abs(K)
        return u, int(data.n[sel].min()) - 1

    return _Sweep(data.magnitudes, kn_of, kn_u, rate_u, list(data.segments))


def _d3_figures(curve: list[tuple[float, float]], limit: float) -> tuple[PlotSpec, TableSpec]:
    """D.3's plot and table of K_n of each range against the limit."""
    plot = PlotSpec("Kn_range", msg("K_n of the range [−Ω, +Ω] against Ω (D.3)"), "Ω (°/s)",
                    "K_n (ppm)",
                    [{"label": "K_n up to Ω", "x": [r for r, _ in curve], "y": [k * 1e6 for _,
                                                                                k in curve],
                      "style": "o-"},
                     {"label": msg("limit {v:g} ppm", v=limit * 1e6), "x": [curve[0][0],
                                                                            curve[-1][0]],
                      "y": [limit * 1e6] * 2, "style": "--"}], logx=True)
    table = TableSpec("Kn_ranges", msg("K_n of each range (D.3)"),
                      [msg("up to Ω (°/s)"), "K_n (ppm)", msg("meets the limit")],
                      [[f"{r:g}", f"{k * 1e6:.3g}", msg("yes") if k <= limit else msg("no")] for r,
                       k in curve])
    return plot, table


def _decision_rows(curve: list[tuple[float, float]], kn_u, limit: float,
                   om: float) -> list[BudgetRow]:
    """D.3's decision near the limit (interpretations.md, "D.3 — a range near the limit"): Ω_max is
    a tested
    rate picked by comparing each range's K_n with the limit, so a K_n within 2u of the limit may
    have
    been judged either way by the noise and the table's error.  The candidates are Ω_max, every
    larger
    range whose K_n is within 2u of the limit (it may truly meet it), and, when Ω_max's own K_n is
    within
    2u, the next smaller range; the row is uniform over the whole distance to the farthest candidate
    (as
    D.4's 50 % decision)."""
    rates = [r for r, _ in curve]
    kn = dict(curve)
    doubtful = {r for r in rates if abs(kn[r] - limit) < 2.0 * kn_u(r)}
    cands = [r for r in rates if r > om and r in doubtful]
    if om in doubtful:
        smaller = [r for r in rates if r < om]
        if smaller:
            cands.append(max(smaller))
    if not cands:
        return []
    half = max(abs(c - om) for c in cands)
    why = join("; ", [msg("K_n up to {r:g} °/s = {kn:.3g} ± {u:.2g} ppm (2u) against {limit:g} ppm",
                          r=r, kn=kn[r] * 1e6,
                          u=2e6 * kn_u(r), limit=limit * 1e6) for r in sorted(doubtful)])
    return [BudgetRow.type_b(msg("decision near the limit: a range whose K_n is within 2u of the "
                                 "limit may be judged "
                                 "either way, so Ω_max may be the neighbouring rate"),
                             "ΔΩ (decision)",
                             Q_(half, "deg/s"), distribution="uniform", note=why)]

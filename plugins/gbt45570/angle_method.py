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
from metro.api import (Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Metric, Option,
                       Outcome, PlotSpec, Result, RunContext, SegmentRequirement, Step,
                       TableSpec, UncertaintyBudget, fit_line, hint, join, msg, parse_quantity,
                       required_scale_factor)

from . import formulas as F
from . import formulas_rate as F2
from .common import COVERAGE, DIRECTIONS, STANDARD, GbtItem, grouped, kr_sampling_row, opts_text
from .misalignment import FIXTURE, DeviceScale, MountingMisalignment, misalignment_metrics
from .repeatability import scale_factor_angle_repeat_row
from .revolutions import (REPEAT_RATE, RatePoint, angle_row, angle_sequence, collect_rate_points,
                          point_drift, sweep_drift)
from .temperature import room_index, temperature_outcome

REVOLUTIONS = SegmentRequirement(
    "rate-revolutions", "m whole revolutions at each rate point, each direction (D.1.1.2 g))",
    conditions={"rate": "deg/s", "turns": ""}, columns={"count": ("P",), "duration": ("s",)},
                                 min_count=22,
)
ZERO = SegmentRequirement("static-zero",
                          "table at rest, τ = 1 s, n = 300, several symmetric positions (D.1.3.2 "
                          "a))",
                          conditions={}, columns={"output": ("P",)})
_EQUIPMENT = (
    EquipmentRequirement("rate_table",
                         "rate table with angle output and a revolution pulse generator (D.1.1.1)",
                         required=True),
    EquipmentRequirement("counter", "gyro test system / counter"),
)
_OPTIONS = (
    Option("max_rate", "400 °/s", "deg/s", "largest rate point (the device's maximum input rate)"),
    Option("turns", 5, None, "whole revolutions m per rate point and direction"),
    Option("min_points", 11, None, "fewest rate points accepted (D.1.1.2 e): not fewer than 11)"),
)


class ScaleFactorD11(GbtItem):
    """GB/T 45570—2025 D.1.1 标度因数 (scale factor), angle method, eqs. (D.1), (D.2), (D.4)–(D.6).

    K_i per rate point from whole revolutions both ways (D.2); K and W by least squares of
    K_i = K + W·Ω_i (D.5, D.6; computed with metro's QR least squares, which equals the closed
    forms).  Type A: the fit's standard error of K (ν = n − 2); type B: the revolution-pulse
    position accuracy of the table.
    """

    item = "D.1.1"
    title = "Scale factor, angle method (标度因数 角度法)"
    clause = "D.1.1"
    metrics = (Metric("K", "scale factor", "K", "P/arcsec", "D.1.1.3", "D.5"),
               Metric("W", "scale factor change with rate", "W", "P/arcsec/(deg/s)", "D.1.1.3",
                      "D.6"))
    requires = (REVOLUTIONS,)
    equipment = _EQUIPMENT
    options = _OPTIONS

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return angle_sequence(options, zero=False)

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
        rows = [
            BudgetRow.type_a(
                msg("least-squares fit of K_i = K + W·Ω_i (D.4)"),
                "s(K)",
                Q_(uK, "P/arcsec"),
                fit.dof,
                note=msg("{n} rate points", n=len(pts)),
            )
        ]
        rows += angle_row(campaign, K, "P/arcsec")
        rep_rows, rep_note = scale_factor_angle_repeat_row(campaign, K, "P/arcsec")
        rows += rep_rows
        budget = UncertaintyBudget("K", "P/arcsec", rows, coverage=COVERAGE)
        res = [Result(self.metrics[0], Q_(K, "P/arcsec"), budget.combined, budget,
                      earth_rate="removed", note=rep_note),
               Result(self.metrics[1], Q_(W, "P/arcsec/(deg/s)"), Q_(uW, "P/arcsec/(deg/s)"),
                      earth_rate="removed")]
        model = K + W * rates
        plot = PlotSpec("K_rate", msg("K_i against rate with the eq. (D.4) fit"),
                        "Ω (°/s)", "K_i (P/″)",
                        [{"label": "K_i (D.2)", "x": rates.tolist(), "y": Ki.tolist(),
                          "yerr": [2 * p.u_K for p in pts], "style": "o"},
                         {"label": f"K + WΩ: K = {K:.7g} P/″", "x": rates.tolist(),
                          "y": model.tolist(), "style": "-"}],
                        logx=True)
        table = TableSpec("K_points", msg("K_i per rate point (D.1, D.2)"),
                          ["Ω (°/s)", "N₊ (P)", "N₋ (P)", "K_i (P/″)",
                           msg("K_i − (K + WΩ_i) (ppm of K)")],
                          [[f"{p.rate:g}", f"{p.n_plus:.1f}", f"{p.n_minus:.1f}", f"{p.K:.8f}",
                            f"{(p.K - K - W * p.rate) / K * 1e6:.2f}"] for p in pts])
        return Outcome(STANDARD, self.item, self.title, self.clause, res, plots=[plot],
                       tables=[table],
                       segments=[s for p in pts for s in p.segments], options=opts_text(opts))


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
        rows = [BudgetRow.type_a(msg("K_i at {rate:g} °/s (revolution scatter) and the fitted K",
                                     rate=pts[i].rate),
                                 "u(K_i − K)/K",
                                 Q_(u, ""), max(min(pts[i].m_plus, pts[i].m_minus) - 1, 1))]
        u_dr = point_drift(pts[i])
        if u_dr > 0:
            rows.append(BudgetRow.type_a(
                msg("bias drift between the + and − runs at {rate:g} °/s (D.1.1.2 g)), from the "
                    "trend of the point's "
                    "revolutions", rate=pts[i].rate), "Δ·√(β² + u²(β))/(2·360·3600″·K_i)", Q_(u_dr,
                                                                                              ""),
                                         pts[i].dof_trend,
                note=msg("β = {b:.3g} ± {u:.2g} P per revolution", b=pts[i].trend,
                         u=pts[i].u_trend)))
        rows += angle_row(campaign, Kn, "")
        budget = UncertaintyBudget("K_n", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Kn, ""), budget.combined, budget,
                     note=msg("largest |K_i − K| at {rate:g} °/s", rate=pts[i].rate),
                     earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[s for p in pts for s in p.segments], options=opts_text(opts))


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
        return angle_sequence(options, zero=True)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        pts = collect_rate_points(type(self), campaign, int(opts["min_points"]))
        zeros = campaign.find_segments("static-zero")
        if not zeros:
            raise DataError(campaign.source, "segments",
                            "D.1.3 needs the zero-rate count: segments of kind \"static-zero\" "
                            "(table at rest, τ = 1 s, n = 300) at the start and end (D.1.3.2 a))")
        per_s = []
        for z in zeros:
            ser = z.series("output", "P")
            x = np.asarray(ser.data.magnitude, dtype=float)
            if x.size < 2 or not np.all(np.isfinite(x)):
                raise DataError(z.file or f"segment {z.id}", "output",
                                "needs at least 2 finite samples")
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
        rows = [BudgetRow.type_a(msg("fits of K_+i and K_−i (D.4, D.5)"), "√(u²(K₊)+u²(K₋))/K̄",
                                 Q_(u_fit, ""), fp.dof),
                BudgetRow.type_a(msg("zero-rate count N̄_0"), "u(N̄₀)", Q_(uN0, "P/s"),
                                 allz.size - 1,
                                 sensitivity=Q_(abs(c_n0), "s/P"),
                                 note=msg("∂K_a/∂N̄₀ analytic through the D.5 intercepts "
                                          "(one-sided at K₊ = K₋)"))]
        drift = sweep_drift(pts)
        if drift.rms > 0:
            # N̄₀ is the bias at the start and the end (D.1.3.2 a)); at a rate point between them
            # the bias
            # is off their mean by at most ḃ·S/2, S the time the test spans (zero records and runs)
            span = sum(float(np.asarray(z.series("output", "P").data.magnitude).size)
                       * float(z.series("output", "P").interval.to("s").magnitude) for z in zeros)
            span += sum(p.m_plus * p.t_plus + p.m_minus * p.t_minus for p in pts)
            Kbar_p_s = abs(Kbar)  # P/″ = (P/s)/(″/s)
            rows.append(BudgetRow.type_a(
                msg("bias drift during the sweep: the bias at each rate point against N̄₀ of the "
                    "start and the end"),
                "ḃ·S/(2√3)", Q_(Kbar_p_s * drift.rms * span / (2.0 * math.sqrt(3.0)), "P/s"),
                                         drift.dof,
                sensitivity=Q_(abs(c_n0), "s/P"),
                note=msg("ḃ_rms = {b:.3g} (°/h)/h from the trends of {n} rate points' revolutions, "
                         "over S = {S:.3g} h "
                         "(uniform within ±ḃ·S/2)", b=drift.rms * 3600.0, n=drift.points,
                         S=span / 3600.0)))
        budget = UncertaintyBudget("K_a", "ppm", rows, coverage=COVERAGE,
                                   model=F.asymmetry_model_d10(Ka, abs(c_n0), len(rows)))
        res = Result(self.metrics[0], Q_(Ka, ""), budget.combined, budget,
                     note=msg("K₊ = {Kp:.8f} P/″, K₋ = {Km:.8f} P/″, N̄₀ = {N0:.4f} P/s",
                              Kp=fp.coef[0], Km=fm.coef[0], N0=N0),
                     earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                       segments=[z.id for z in zeros] + [s for p in pts for s in p.segments],
                       options=opts_text(opts))


# --------------------------------------------------------------------------------------------
# D.1.4 repeatability, D.1.5 temperature sensitivity, D.1.6 input-axis misalignment
# --------------------------------------------------------------------------------------------


def _counter_row(pts: list[RatePoint], value: float, unit: str) -> BudgetRow:
    """±1 P of the counter on the pulses of m revolutions, as a relative half-width on K."""
    p = pts[0]
    rel = 1.0 / (min(p.m_plus, p.m_minus) * abs(p.n_plus - p.n_minus))
    return BudgetRow.type_b(msg("counter resolution (±1 P over m revolutions each way)"), "δN/N",
                            Q_(rel, ""),
                            distribution="uniform", sensitivity=Q_(abs(value), unit))


class ScaleFactorRepeatabilityD14(GbtItem):
    """GB/T 45570—2025 D.1.4 标度因数重复性 (scale-factor repeatability), angle method, eq. (D.11).

    Q = 7 power-ons (segments of kind ``revolutions-repeat``, condition ``run`` = 1 … 7, at 30 °/s
    both ways), K_j by eq. (D.2) for each, K_r = s(K_j)/K̄.  Type A: the sampling uncertainty of a
    standard deviation of Q values, K_r/√(2(Q − 1)), ν = Q − 1; type B: the counter's ±1 P and
    the revolution-pulse position, per run (both bounded, uniform).
    """

    item = "D.1.4"
    title = "Scale factor repeatability, angle method (标度因数重复性)"
    clause = "D.1.4"
    metrics = (Metric("Kr", "scale factor repeatability", "K_r", "ppm", "D.1.4.3", "D.11"),)
    requires = (SegmentRequirement("revolutions-repeat",
                                   "m whole revolutions each way at 30 °/s on each of 7 "
                                   "power-ons, off ≥ 10 min between (D.1.4.2)",
                                   conditions={"rate": "deg/s", "turns": "", "run": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=14),)
    equipment = _EQUIPMENT
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate of the repeats (D.1.4.2: 30 °/s)"),
               Option("turns", 5, None, "whole revolutions m each way"),
               Option("Q", 7, None, "number of power-ons; D.11 is written for 7", minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        r = float(parse_quantity(options.get("rate", REPEAT_RATE),
                                 dimension="deg/s").to("deg/s").magnitude)
        m, q = int(options.get("turns", 5)), int(options.get("Q", 7))
        steps = []
        for j in range(1, q + 1):
            for sign, word in DIRECTIONS:
                steps.append(Step(f"run{j}-rate{sign * r:+g}", "revolutions-repeat",
                                  f"power-on {j} of {q}: {m} whole revolutions at {r:g} °/s {word} "
                                  f"as D.1.1.2; "
                                  "then power off ≥ 10 min (D.1.4.2)", Q_(m * 360.0 / r, "s"),
                                  Q_(360.0 / r, "s"),
                                  {"rate": f"{sign * r:g} deg/s", "turns": m, "run": j},
                                  warmup=Q_(30, "min")))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        q = int(opts["Q"])
        runs = grouped(campaign, "revolutions-repeat", "run")
        if len(runs) != q:
            raise DataError(campaign.source, "segments",
                            f"D.1.4 needs {q} power-ons (segments of kind \"revolutions-repeat\" "
                            f"with run = 1 … {q}, D.1.4.2); found {len(runs)} run(s): "
                            f"{', '.join(sorted(runs)) or 'none'}",
                            hint="D.11 is written for 7 repeats")
        pts = []
        for run, segs in sorted(runs.items()):
            p = collect_rate_points(type(self), campaign, 1, segs, f"in run {run}")
            if len(p) != 1:
                raise DataError(campaign.source, f"segments.{segs[0].id}.conditions.rate",
                                f"run {run} has {len(p)} rate points; D.1.4 tests at one rate "
                                f"({opts['rate']:~P})")
            pts.append((run, p[0]))
        Kj = [p.K for _, p in pts]
        want = float(opts["rate"].to("deg/s").magnitude)
        off = sorted({f"{p.rate:g}" for _, p in pts if abs(p.rate - want) > 0.01 * want})
        warnings = [msg("runs at {off} °/s; D.1.4.2 repeats the test at {want:g} °/s{hint}",
                        off=", ".join(off),
                        want=want, hint=hint(" (option rate)"))] if off else []
        Kr = F2.scale_factor_repeatability_d11(Kj)
        if not Kr > 0:
            # identical whole counts: one pulse in m revolutions is coarser than the power-on
            # scatter
            # (a coarse undithered counter), not a data error — K_r cannot be measured
            p0 = pts[0][1]
            res_ppm = 1e6 / (min(p0.m_plus, p0.m_minus) * abs(p0.n_plus - p0.n_minus))
            reason = msg("the {q} scale factors K_j are identical: one count over the m "
                         "revolutions ({res:.3g} ppm of K) is coarser than the power-on scatter, "
                         "which cannot be measured — use more revolutions",
                         q=q, res=res_ppm)
            res = Result(self.metrics[0], Q_(0.0, ""), reportable=False, reason=reason,
                         earth_rate="removed")
            return Outcome(STANDARD, self.item, self.title, self.clause, [res],
                           warnings=warnings + [reason],
                           segments=[s for _, p in pts for s in p.segments],
                           options=opts_text(opts))
        rows = [kr_sampling_row(Kr, q), _counter_row([p for _, p in pts], 1.0, "")]
        m = min(min(p.m_plus, p.m_minus) for _, p in pts)
        rows += [attrs.evolve(r, source=msg("{source}, run to run", source=r.source),
                              sensitivity=Q_(1.0 / m, ""),
                              note=join("; ", [r.note, msg("over m = {m} revolutions", m=m)]))
                 for r in angle_row(campaign, 1.0, "")]
        budget = UncertaintyBudget("K_r", "ppm", rows, coverage=COVERAGE)
        mean = float(np.mean(Kj))
        res = Result(self.metrics[0], Q_(Kr, ""), budget.combined, budget,
                     note=msg("K̄ = {mean:.8f} P/″, Q = {q}", mean=mean, q=q), earth_rate="removed")
        table = TableSpec("K_runs", msg("K_j of each power-on (D.2)"), [msg("run"), "Ω (°/s)",
                                                                        "K_j (P/″)",
                                                                        "K_j − K̄ (ppm)"],
                          [[run, f"{p.rate:g}", f"{p.K:.8f}",
                            f"{(p.K - mean) / mean * 1e6:.2f}"] for run, p in pts])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table],
                       warnings=warnings,
                       segments=[s for _, p in pts for s in p.segments], options=opts_text(opts))


class ScaleFactorTemperatureSensitivityD15(GbtItem):
    """GB/T 45570—2025 D.1.5 标度因数温度灵敏度 (scale-factor temperature sensitivity), angle
    method, eq. (D.12).

    At each temperature point (segments of kind ``revolutions-temperature``, condition
    ``temperature``, the full D.1.1.2 rate sweep) K is the D.5 intercept; K_t = max |(K_i − K_00)/
    (K_00 (T_i − T_0))| with K_00, T_0 at room temperature (the point nearest the option ``room``,
    within 15 °C … 35 °C).  Budget of the maximising point: the two fits' standard errors (A) and
    the chamber's temperature uncertainty on T_i − T_0 (B).
    """

    item = "D.1.5"
    title = "Scale factor temperature sensitivity, angle method (标度因数温度灵敏度)"
    clause = "D.1.5"
    metrics = (Metric("Kt", "scale factor temperature sensitivity", "K_t", "ppm/delta_degC",
                      "D.1.5.3", "D.12"),)
    requires = (
        SegmentRequirement(
            "revolutions-temperature",
            "the D.1.1.2 rate sweep at each temperature point after "
            "≥ 2 h soak, powered off while the temperature changes (D.1.5.2)",
            conditions={"rate": "deg/s", "turns": "", "temperature": "degC"},
            columns={"count": ("P",), "duration": ("s",)},
            min_count=66,
        ),
    )
    equipment = _EQUIPMENT + (EquipmentRequirement("chamber",
                                                   "temperature chamber, vibration-isolated, "
                                                   "control better than ±2 °C (D.1.5.1 b))"),)
    options = _OPTIONS + (
        Option(
            "temperatures",
            "-40 °C, 20 °C, 60 °C",
            None,
            "temperature points for the sequence: both limits and room temperature (D.1.5.2 b))",
        ),
        Option("room", "20 °C", "degC", "room temperature T0: the nearest point is the reference"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures",
                                                    "-40 °C, 20 °C, 60 °C")).split(",")]
        steps = []
        for i, T in enumerate(temps):
            for st in angle_sequence(options, zero=False):
                steps.append(attrs.evolve(st, segment=f"T{i + 1}-{st.segment}",
                                          kind="revolutions-temperature",
                                          description=f"at {T} (power off, soak ≥ 2 h, D.1.5.2 "
                                                      f"c)): " + st.description,
                                          conditions=dict(st.conditions) | {"temperature": T},
                                          warmup=Q_(2, "h")))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        byT = grouped(campaign, "revolutions-temperature", "temperature")
        keys, temps, i0 = room_index(campaign, byT, float(opts["room"].to("degC").magnitude), 3,
                                     "D.1.5")
        Ks, uKs, dofs, used = [], [], [], []
        for k, T in zip(keys, temps):
            pts = collect_rate_points(type(self), campaign, int(opts["min_points"]), byT[k],
                                      f"at {T:g} °C")
            rates = np.array([p.rate for p in pts])
            Ks.append(F.scale_factor_fit_d5_d6([p.K for p in pts], rates)[0])
            # type A of the D.5 intercept from each K_i's revolution scatter (not the residuals,
            # which hold the nonlinearity)
            ca, _ = F2.line_fit_sensitivities(rates)
            u, nu = F2.propagate(ca, [p.u_K for p in pts], [max(min(p.m_plus, p.m_minus) - 1,
                                                                1) for p in pts])
            uKs.append(u)
            dofs.append(nu)
            used += [s for p in pts for s in p.segments]
        Kt, imax = F2.scale_factor_temperature_sensitivity_d12(Ks, temps, i0)
        return temperature_outcome(self, campaign, opts, Kt, imax, i0, temps, Ks, uKs, dofs, used,
                                   "P/″")


class InputAxisMisalignmentD16(MountingMisalignment):
    """GB/T 45570—2025 D.1.6 输入轴失准角 (input-axis misalignment), angle method, eqs.
    (D.13)–(D.16).

    Four mountings (segments of kind ``revolutions-mounting``, conditions ``axis_up`` XRA/YRA and
    ``turn`` 0°/180° about IRA, signed ``rate``): N_± per mounting (D.13), α_{1,2} = (N₊ − N₋)/
    (2·360·3600·K)·180/π (D.14) with the device's K, α = (α₁ − α₂)/2 (D.15), β likewise,
    γ = √(α² + β²) (D.16).  Type A: the revolutions' count scatter; type B: the fixture's
    re-seating tilt, the scale factor K, the revolution-pulse position.
    """

    item = "D.1.6"
    title = "Input axis misalignment, angle method (输入轴失准角)"
    clause = "D.1.6"
    metrics = misalignment_metrics("D.1.6.4", ("D.15", "D.15", "D.16"))
    requires = (SegmentRequirement("revolutions-mounting",
                                   "m whole revolutions each way with XRA, then YRA, "
                                   "along the table axis, each before and after a 180° turn about "
                                   "IRA (D.1.6.3)",
                                   conditions={"axis_up": "", "turn": "deg", "rate": "deg/s",
                                               "turns": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=8),)
    equipment = _EQUIPMENT + (FIXTURE,)
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate (D.1.6.3 d): \"a given rate\")"),
               Option("turns", 5, None, "whole revolutions m each way"))
    mounting_kind = "revolutions-mounting"
    revolutions = True
    scatter = msg("revolution count scatter")

    def scale_factor(self, campaign: Campaign, groups: Mapping[tuple[str, int],
                                                               list]) -> DeviceScale:
        k, u_rel_K = required_scale_factor(campaign.device, "P/arcsec", source=campaign.source,
                                           needed_by="eq. (D.14) of D.1.6 (K from D.1.1)")
        return DeviceScale(k, u_rel_K, "P")

    def mounting_angle(self, campaign: Campaign, mounting: tuple[str, int], segs: list,
                       scale: DeviceScale) -> tuple[tuple[float, float, int], list[str]]:
        ax, turn = mounting
        k = scale.k
        pts = collect_rate_points(type(self), campaign, 1, segs, f"({ax} up, turned {turn}°)")
        if len(pts) != 1:
            raise DataError(campaign.source, f"segments.{segs[0].id}.conditions.rate",
                            f"mounting {ax} up, turned {turn}° has {len(pts)} rate points; D.1.6 "
                            f"uses one rate")
        p = pts[0]
        a = F2.misalignment_d14(p.n_plus, p.n_minus, k)
        up = p.s_plus / math.sqrt(p.m_plus) if p.m_plus > 1 else 0.5
        um = p.s_minus / math.sqrt(p.m_minus) if p.m_minus > 1 else 0.5
        u = math.hypot(up, um) / (2.0 * F.REVOLUTION_ARCSEC * k) * 180.0 / math.pi
        return (a, u, max(min(p.m_plus, p.m_minus) - 1, 1)), list(p.segments)

    def relative_rows(self, campaign: Campaign, scale: DeviceScale) -> list[BudgetRow]:
        k, u_rel_K = scale.k, scale.u_rel
        rel = []
        if u_rel_K > 0:
            rel.append(BudgetRow.type_b("scale factor K (device)", "u_rel(K)", Q_(u_rel_K, ""),
                                        distribution="normal",
                                        k=1.0, note=msg("K = {k:g} P/″; α ∝ 1/K", k=k)))
        rel += [attrs.evolve(r, sensitivity=Q_(1.0, "")) for r in angle_row(campaign, 1.0, "")]
        return rel


PROCEDURES = (ScaleFactorD11, NonlinearityD12, AsymmetryD13, ScaleFactorRepeatabilityD14,
              ScaleFactorTemperatureSensitivityD15, InputAxisMisalignmentD16)

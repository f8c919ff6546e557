"""GB/T 45570—2025 D.2 scale factor series by the rate method (digital output in LSB, °/s or Hz):
D.2.1 scale factor, D.2.2 nonlinearity, D.2.3 asymmetry, D.2.4 repeatability, D.2.5
temperature sensitivity, D.2.6 input-axis misalignment — and D.3 maximum input rate, which
works on the data of either method.

Data: one segment of kind ``rate-output`` per rate point and direction (condition ``rate``,
signed: + counter-clockwise), with an ``output`` column — in LSB, as a frequency in Hz (D.23
names it) or as a digital rate in °/s (any angular-rate unit) — sampled once the table is
steady (D.2.1.2 f), g)); two segments of kind ``rate-static`` (condition ``when`` = ``start`` /
``end``), the table at rest at the start and end of the test (D.2.1.2 h)).  D.2.4 adds the
condition ``run`` = 1 … 7 to both kinds, D.2.5 ``temperature``; D.2.1–D.2.3 and D.3 use the
segments that have neither.  D.2.6 uses segments of kind ``rate-mounting`` (conditions
``axis_up`` XRA/YRA, ``turn`` 0°/180° about IRA, signed ``rate``).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Metric, Option,
                       Outcome, PlotSpec, Result, RunContext, Segment,
                       SegmentRequirement, Step, TableSpec, UncertaintyBudget, join, msg,
                       required_scale_factor)

from . import formulas_rate as F2
from .common import (COVERAGE, STANDARD, GbtItem, group_of, kr_sampling_row, opts_text, repeat_runs,
                     signed_rate)
from .max_rate import MaxInputRateD3
from .misalignment import (FIXTURE, MOUNTINGS, DeviceScale, MountingMisalignment,
                           misalignment_metrics)
from .rate_data import (LSB_PER_RATE, OUTPUT_UNITS, RATE_EQUIPMENT, RATE_OUTPUT, REST, RateData,
                        collect_rate_data, default_nonlinearity_limit, fit_scale_factor,
                        intercept_table_row, k_text, mean_output, metric_in, nonlinearity_budget,
                        nonlinearity_of, out_resolution_row, output_series, per_rate, rate_row,
                        rate_sequence, rate_table_rel, stability_row, through_fit, unit_text)
from .repeatability import scale_factor_rate_repeat_row
from .revolutions import REPEAT_RATE
from .temperature import room_index, temperature_outcome

_OPTIONS = (
    Option("max_rate", "400 °/s", "deg/s", "largest rate point (the device's maximum input rate)"),
    Option("duration", "100 s", "s",
           "record at each rate point and at rest (n samples × interval)"),
    Option("interval", "1 s", "s", "sampling interval (D.2.1.2 d))"),
    Option("min_points", 11, None, "fewest rate points accepted (D.2.1.2 e): not fewer than 11)"),
)


# --------------------------------------------------------------------------------------------
# D.2.1 scale factor, D.2.2 nonlinearity, D.2.3 asymmetry
# --------------------------------------------------------------------------------------------


class ScaleFactorD21(GbtItem):
    """GB/T 45570—2025 D.2.1 标度因数 (scale factor), rate method, eqs. (D.17)–(D.22).

    F̄_j per rate point (D.17), the rest output F̄_r = (F̄_s + F̄_e)/2 (D.18) removed (D.19), and
    F_kj = K·Ω_ij + F_0 fitted by least squares over all M signed rates (D.20)–(D.22).
    Type A: the fit's standard error (ν = M − 2); type B: the rate table's rate accuracy (K ∝ 1/Ω).
    """

    item = "D.2.1"
    title = "Scale factor, rate method (标度因数 速率法)"
    clause = "D.2.1"
    metrics = (Metric("K", "scale factor", "K", LSB_PER_RATE, "D.2.1.3", "D.21"),
               Metric("F0", "fitted zero", "F₀", "LSB", "D.2.1.3", "D.22"))
    requires = (RATE_OUTPUT, REST)
    equipment = RATE_EQUIPMENT
    options = _OPTIONS
    station = "simulated-digital"

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return rate_sequence(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        fit = fit_scale_factor(data)
        K, F0 = fit.K, fit.F0
        out, ku, ot = data.unit, per_rate(data.unit), unit_text(data.unit)
        rows = [BudgetRow.type_a(msg("mean outputs F̄_j through the D.21 fit"), "√Σ(c_j·u(F̄_j))²",
                                 Q_(fit.uK, ku),
                                 fit.nuK,
                                 note=msg("M = {m} rates; residual s = {s:.3g} {unit} (systematic "
                                                   "nonlinearity, D.2.2)", m=data.rates.size,
                                                   s=fit.residual_sd,
                                                   unit=ot))]
        ca, cb = F2.line_fit_sensitivities(data.rates)
        rows.append(out_resolution_row(campaign, float(np.linalg.norm(cb)), ku, "D.21", out))
        rows += rate_row(campaign, msg("on every Ω_ij"), K, ku, "K ∝ 1/Ω")
        rep_rows, rep_note = scale_factor_rate_repeat_row(campaign, K, ku, int(opts["min_points"]))
        rows += rep_rows
        bK = UncertaintyBudget("K", ku, rows, coverage=COVERAGE)
        b0 = UncertaintyBudget("F₀", out, [
            BudgetRow.type_a(msg("mean outputs F̄_j through the D.22 fit"), "√Σ(c_j·u(F̄_j))²",
                             Q_(fit.uF0, out),
                             fit.nuF0),
            BudgetRow.type_a(msg("rest output F̄_r removed from every point (D.18)"), "u(F̄_r)",
                             Q_(data.uFr, out),
                             int(data.n.min()) - 1),
            # F̄_r = (F̄_s + F̄_e)/2 enters F₀ with sensitivity −1: √(2·(1/2)²) on its two means
            out_resolution_row(campaign, math.hypot(float(np.linalg.norm(ca)), math.sqrt(0.5)), out,
                                "D.22 and F̄_r", out),
            *intercept_table_row(campaign, data.rates, K, out)], coverage=COVERAGE)
        res = [Result(metric_in(self.metrics[0], ku), Q_(K, ku), bK.combined, bK,
                      earth_rate="removed", note=rep_note),
               Result(metric_in(self.metrics[1], out), Q_(F0, out), b0.combined, b0,
                      note=f"F̄_r = {data.Fr:.4f} {ot}",
                      earth_rate="removed")]
        resid = data.Fk - (K * data.rates + F0)
        plot = PlotSpec("F_rate", msg("F_kj against Ω with the D.20 fit: residuals"), "Ω (°/s)",
                        f"F_kj − (KΩ + F₀) ({ot})",
                        [{"label": "residual", "x": data.rates.tolist(), "y": resid.tolist(),
                          "yerr": (2 * data.uF).tolist(), "style": "o"}])
        table = TableSpec("F_points", msg("F_kj per rate point (D.17–D.19)"),
                          ["Ω (°/s)", f"F_kj ({ot})", msg("residual ({unit})", unit=ot)],
                          [[f"{r:+g}", f"{f:.3f}", f"{e:.3f}"] for r, f, e in zip(data.rates,
                                                                                  data.Fk, resid)])
        return Outcome(STANDARD, self.item, self.title, self.clause, res, plots=[plot],
                       tables=[table],
                       segments=data.segments, options=opts_text(opts))


class NonlinearityD22(ScaleFactorD21):
    """GB/T 45570—2025 D.2.2 标度因数非线性度 (nonlinearity), rate method, eqs. (D.23)–(D.25).

    F̂_j = K·Ω_ij + F_0 from D.2.1; a_j = (F̂_j − F_kj)/|F_m| with F_m the output at the maximum
    input rate (the larger of its two directions); K_n = |a_j|_max.  Type A: the maximising
    point's mean (its samples' scatter) and the fitted line there; type B: the table's rate
    accuracy at that point (a rate error not proportional to Ω looks like nonlinearity).
    """

    item = "D.2.2"
    title = "Scale factor nonlinearity, rate method (标度因数非线性度)"
    clause = "D.2.2"
    metrics = (Metric("Kn", "scale factor nonlinearity", "K_n", "ppm", "D.2.2.3", "D.25"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        Kn, j, Fm, _, K, F0 = nonlinearity_of(data)
        # K_n is the largest of 2M noisy |a_j|: corrected for the selection (interpretations.md,
        # D.2.2)
        from metro.api import selection_note, selection_rows

        sel = F2.nonlinearity_selection(data.rates, data.Fk, data.uF)
        budget = nonlinearity_budget(campaign, data, j, Fm, K, spread=sel.s)
        budget = UncertaintyBudget("K_n", "ppm", list(budget.rows) + selection_rows(sel,
                                                                                    data.rates.size,
                                                                                    ""),
                                   coverage=COVERAGE)
        a = (F2.fitted_output_d23(K, F0, data.rates) - data.Fk) / Fm
        res = Result(self.metrics[0], Q_(max(sel.value, 0.0), ""), budget.combined, budget,
                     note=join("; ", [msg("largest |a_j| at {rate:+g} °/s", rate=data.rates[j]),
                                      f"|F_m| = {Fm:.1f} {unit_text(data.unit)}",
                                      selection_note(sel, 1e6, 'ppm')]),
                     earth_rate="removed")
        plot = PlotSpec("a_rate", msg("Point nonlinearity a_j (D.24)"), "Ω (°/s)", "a_j (ppm)",
                        [{"label": "a_j", "x": data.rates.tolist(), "y": (a * 1e6).tolist(),
                          "style": "o"}])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot],
                       segments=data.segments,
                       options=opts_text(opts))


class AsymmetryD23(ScaleFactorD21):
    """GB/T 45570—2025 D.2.3 标度因数不对称度 (asymmetry), rate method, eqs. (D.26), (D.27).

    The D.2.1 outputs regrouped by direction; K_(+) and K_(−) by the D.21 fit of each group;
    K_a = |K_(+) − K_(−)| / ((K_(+) + K_(−))/2).  Type A: the two fits' standard errors; type B:
    the table's rate accuracy between the two directions.
    """

    item = "D.2.3"
    title = "Scale factor asymmetry, rate method (标度因数不对称度)"
    clause = "D.2.3"
    metrics = (Metric("Ka", "scale factor asymmetry", "K_a", "ppm", "D.2.3.3", "D.26"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        pos, neg = data.rates > 0, data.rates < 0
        fp, fm = fit_scale_factor(data, pos), fit_scale_factor(data, neg)
        Kp, Km = fp.K, fm.K
        Ka = F2.asymmetry_d26_d27(Kp, Km)
        Kbar = 0.5 * (Kp + Km)
        rows = [BudgetRow.type_a(msg("K_(+): D.21 on the + rates"), "u(K₊)/K̄", Q_(fp.uK / Kbar,
                                                                                   ""), fp.nuK),
                BudgetRow.type_a(msg("K_(−): D.21 on the − rates"), "u(K₋)/K̄", Q_(fm.uK / Kbar,
                                                                                   ""), fm.nuK)]
        per_point = [rate_table_rel(campaign, float(r)) for r in data.rates]
        if all(p is not None for p in per_point):
            u_rel = np.array([p[0] for p in per_point])
            u_dir = math.hypot(through_fit(data.rates[pos], list(u_rel[pos])),
                               through_fit(data.rates[neg], list(u_rel[neg])))
            rows.append(BudgetRow.type_b(msg("rate-table rate error at each set point, through "
                                             "K(+) and K(−) ({table})", table=per_point[-1][1]),
                                         "u(δK₊/K ⊖ δK₋/K)", Q_(u_dir, ""),
                                         distribution="normal", k=1.0,
                                         note=msg("independent at each signed set point; a common "
                                                  "error cancels")))
        budget = UncertaintyBudget("K_a", "ppm", rows, coverage=COVERAGE,
                                   model=F2.asymmetry_model_d26(Kp, Km, len(rows) > 2))
        res = Result(self.metrics[0], Q_(Ka, ""), budget.combined, budget,
                     note=f"K(+) = {Kp:.4f}, K(−) = {Km:.4f} {k_text(data.unit)}",
                     earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], segments=data.segments,
                       options=opts_text(opts))


# --------------------------------------------------------------------------------------------
# D.2.4 repeatability, D.2.5 temperature sensitivity
# --------------------------------------------------------------------------------------------


class ScaleFactorRepeatabilityD24(ScaleFactorD21):
    """GB/T 45570—2025 D.2.4 标度因数重复性 (scale-factor repeatability), rate method, eq. (D.28).

    Seven D.2.1 tests (condition ``run`` = 1 … 7 on their ``rate-output`` and ``rate-static``
    segments), power off ≥ 10 min between; K_j by D.21 for each; K_r = s(K_j)/K̄.  Type A: the
    sampling uncertainty of a standard deviation of Q values, K_r/√(2(Q − 1)), ν = Q − 1; type B:
    the table's rate accuracy, bounding a rate that differs between runs.
    """

    item = "D.2.4"
    title = "Scale factor repeatability, rate method (标度因数重复性)"
    clause = "D.2.4"
    metrics = (Metric("Kr", "scale factor repeatability", "K_r", "ppm", "D.2.4.3", "D.28"),)
    requires = (attrs.evolve(RATE_OUTPUT, conditions={"rate": "deg/s", "run": ""}, min_count=154),
                attrs.evolve(REST, conditions={"when": "", "run": ""}, min_count=14))
    options = _OPTIONS + (Option("Q", 7, None, "number of power-ons; D.28 is written for 7",
                                 minimum=2),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        q = int(options.get("Q", 7))
        return [s for j in range(1, q + 1)
                for s in rate_sequence(options, {"run": j}, f"run{j}-",
                                       f"power-on {j} of {q} (off ≥ 10 min before, D.2.4.2)")]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        q = int(opts["Q"])
        runs = repeat_runs(campaign)
        if len(runs) != q:
            raise DataError(campaign.source, "segments",
                            f"D.2.4 needs {q} power-ons (segments of kind \"rate-output\" with run "
                            f"= 1 … {q}, "
                            f"D.2.4.2); found {len(runs)} run(s): {', '.join(runs) or 'none'}",
                            hint="D.28 is written for 7 repeats")
        Kj, used = [], []
        for r in runs:
            last = collect_rate_data(type(self), campaign, int(opts["min_points"]), (r, ""),
                                     f"in run {r}")
            Kj.append(fit_scale_factor(last).K)
            used += list(last.segments)
        Kr = F2.scale_factor_repeatability_d28(Kj)
        if not Kr > 0:
            raise DataError(campaign.source, "segments",
                            f"the {q} scale factors are identical; K_r = 0 cannot be right")
        rows = [kr_sampling_row(Kr, q)]
        rows += stability_row(campaign, last)
        budget = UncertaintyBudget("K_r", "ppm", rows, coverage=COVERAGE)
        mean = float(np.mean(Kj))
        kt = k_text(last.unit)
        res = Result(self.metrics[0], Q_(Kr, ""), budget.combined, budget,
                     note=f"K̄ = {mean:.4f} {kt}, Q = {q}",
                     earth_rate="removed")
        table = TableSpec("K_runs", msg("K_j of each power-on (D.21)"), [msg("run"), f"K_j ({kt})",
                                                                         "K_j − K̄ (ppm)"],
                          [[r, f"{k:.5f}", f"{(k - mean) / mean * 1e6:.2f}"] for r, k in zip(runs,
                                                                                             Kj)])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table],
                       segments=used,
                       options=opts_text(opts))


class ScaleFactorTemperatureSensitivityD25(ScaleFactorD21):
    """GB/T 45570—2025 D.2.5 标度因数温度灵敏度 (scale-factor temperature sensitivity), rate
    method, eq. (D.29).

    A D.2.1 test at each of ≥ 5 temperature points including room temperature (condition
    ``temperature`` on the ``rate-output`` and ``rate-static`` segments), K_i by D.21;
    K_t = max |(K_i − K_00)/(K_00 (T_i − T_0))|.  Budget of the maximising point: the two fits'
    standard errors (A), the chamber's temperature uncertainty on T_i − T_0 (B).
    """

    item = "D.2.5"
    title = "Scale factor temperature sensitivity, rate method (标度因数温度灵敏度)"
    clause = "D.2.5"
    metrics = (Metric("Kt", "scale factor temperature sensitivity", "K_t", "ppm/delta_degC",
                      "D.2.5.3", "D.29"),)
    requires = (attrs.evolve(RATE_OUTPUT, conditions={"rate": "deg/s", "temperature": "degC"},
                             min_count=110),
                attrs.evolve(REST, conditions={"when": "", "temperature": "degC"}, min_count=10))
    equipment = RATE_EQUIPMENT + (EquipmentRequirement("chamber",
                                                       "temperature chamber, vibration-isolated, "
                                                       "control "
                                                   "better than ±2 °C (D.2.5.1 b))"),)
    options = _OPTIONS + (
        Option("temperatures", "-40 °C, -20 °C, 0 °C, 20 °C, 40 °C, 60 °C", None,
               "≥ 5 temperature points, evenly spread, including room temperature (D.2.5.2 b))"),
        Option("room", "20 °C", "degC", "room temperature T0: the nearest point is the reference"),
        Option("min_temperatures", 5, None,
               "fewest temperature points accepted (D.2.5.2 b): not fewer than 5)"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures",
                                                    "-40 °C, -20 °C, 0 °C, 20 °C, 40 °C, 60 °C"))
                 .split(",")]
        return [
            s
            for i, T in enumerate(temps)
            for s in rate_sequence(
                options,
                {"temperature": T},
                f"T{i + 1}-",
                f"at {T} (power off while changing, soak ≥ 2 h, D.2.5.2 c))",
            )
        ]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        byT: dict[str, list[Segment]] = {}
        for s in campaign.find_segments("rate-output"):
            run, T = group_of(s)
            if T and not run:
                byT.setdefault(T, []).append(s)
        keys, temps, i0 = room_index(campaign, byT, float(opts["room"].to("degC").magnitude),
                                     int(opts["min_temperatures"]), "D.2.5")
        Ks, uKs, dofs, used = [], [], [], []
        for k, T in zip(keys, temps):
            data = collect_rate_data(type(self), campaign, int(opts["min_points"]), ("", k),
                                     f"at {T:g} °C")
            fit = fit_scale_factor(data)
            Ks.append(fit.K)
            uKs.append(fit.uK)
            dofs.append(fit.nuK)
            used += list(data.segments)
        Kt, imax = F2.scale_factor_temperature_sensitivity_d29(Ks, temps, i0)
        kt = k_text(data.unit)
        return temperature_outcome(self, campaign, opts, Kt, imax, i0, temps, Ks, uKs, dofs, used,
                                   kt)


# --------------------------------------------------------------------------------------------
# D.2.6 input-axis misalignment
# --------------------------------------------------------------------------------------------


class InputAxisMisalignmentD26(MountingMisalignment):
    """GB/T 45570—2025 D.2.6 输入轴失准角 (input-axis misalignment), rate method, eqs.
    (D.30)–(D.36).

    Four mountings (segments of kind ``rate-mounting``: ``axis_up`` XRA/YRA, ``turn`` 0°/180°
    about IRA, signed ``rate``): δ = sin⁻¹((F₊ − F₋)/(2KΩ)) per mounting (D.30, D.31, D.33,
    D.34) with the device's K, α = (δ₁ − δ₂)/2 (D.32), β = (δ₃ − δ₄)/2 (D.35), γ = √(α² + β²)
    (D.36).  Type A: the mean outputs' scatter; type B: the fixture's re-seating tilt, the scale
    factor and the table's rate accuracy (δ ∝ 1/(KΩ)).
    """

    item = "D.2.6"
    title = "Input axis misalignment, rate method (输入轴失准角)"
    clause = "D.2.6"
    metrics = misalignment_metrics("D.2.6.4", ("D.32", "D.35", "D.36"))
    requires = (SegmentRequirement("rate-mounting",
                                   "output at ±Ω with XRA, then YRA, along the table axis, each "
                                   "before and after a 180° turn about IRA (D.2.6.3)",
                                   conditions={"axis_up": "", "turn": "deg", "rate": "deg/s"},
                                   columns={"output": OUTPUT_UNITS}, min_count=8),)
    equipment = RATE_EQUIPMENT + (FIXTURE,)
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate Ω (D.2.6.3 d): \"a given rate\")"),
               Option("turns", 5, None,
                      "whole revolutions recorded at each rate (the horizontal earth rate "
                      "averages out over whole revolutions)"))
    station = "simulated-digital"
    mounting_kind = "rate-mounting"
    revolutions = False
    scatter = msg("scatter of the mean outputs")

    def scale_factor(self, campaign: Campaign, groups: Mapping[tuple[str, int],
                                                               list]) -> DeviceScale:
        first = next(iter(groups.values()))[0]
        out_unit = output_series(first)[1]
        if out_unit == "deg/s":
            # a rate output is its own K: (°/s)/(°/s) = 1; its scale error (ppm, D.2.1) moves δ by
            # as many ppm of itself, negligible against the mean outputs' scatter
            return DeviceScale(1.0, 0.0, out_unit, first.id)
        k_unit = LSB_PER_RATE if out_unit == "LSB" else "Hz/(deg/s)"
        k, u_rel_K = required_scale_factor(campaign.device, k_unit, source=campaign.source,
                                           needed_by="eq. (D.30) of D.2.6 (K from D.2.1)")
        return DeviceScale(k, u_rel_K, out_unit, first.id)

    def mounting_angle(self, campaign: Campaign, mounting: tuple[str, int], segs: list,
                       scale: DeviceScale) -> tuple[tuple[float, float, int], list[str]]:
        ax, turn = mounting
        k, out_unit = scale.k, scale.unit
        where = f"mounting {ax} up, turned {turn}°"
        by_dir: dict[int, tuple] = {}
        for s in segs:
            rate, d = signed_rate(campaign, s, "the rate cannot be 0 °/s")
            if d in by_dir:
                raise DataError(campaign.source, f"segments.{s.id}",
                                f"{where}: two segments at {rate:+g} °/s")
            mean = mean_output(s, campaign)
            if mean[3] != out_unit:  # D.30 divides by the device's K in the output's unit per °/s
                raise DataError(s.file or campaign.source, "output",
                                f"D.2.6 reads one kind of output in every mounting (D.30 divides "
                                f"by K in {unit_text(out_unit)}/(°/s)); segment {s.id!r} is in "
                                f"{unit_text(mean[3])}, segment {scale.reference!r} in "
                                f"{unit_text(out_unit)}")
            by_dir[d] = (s, abs(rate)) + mean[:3]
        if set(by_dir) != {1, -1}:
            only = next(iter(by_dir.values()))[0]
            raise DataError(campaign.source, f"segments.{only.id}",
                            f"{where} has no "
                            f"{'clockwise (−)' if 1 in by_dir else 'counter-clockwise (+)'} "
                            "record; D.30 needs F₊ and F₋")
        (sp, rp, Fp, up, n_p), (sm, rm, Fm, um, n_m) = by_dir[1], by_dir[-1]
        if abs(rp - rm) > 1e-9 * rp:
            raise DataError(campaign.source, f"segments.{sm.id}.conditions.rate",
                            f"{where}: the two directions differ in rate ({rp:g} and {rm:g} °/s); "
                            f"D.30 uses one Ω")
        try:
            delta = F2.misalignment_d30(Fp, Fm, k, rp)
        except ValueError as exc:
            raise DataError(campaign.source, f"segments.{sp.id}", f"{where}: {exc}") from exc
        c = 1.0 / (2.0 * k * rp * math.cos(math.radians(delta))) * 180.0 / math.pi
        return (delta, c * math.hypot(up, um), max(min(n_p, n_m) - 1, 1)), [sp.id, sm.id]

    def relative_rows(self, campaign: Campaign, scale: DeviceScale) -> list[BudgetRow]:
        k, u_rel_K, out_unit = scale.k, scale.u_rel, scale.unit
        rel = []
        if u_rel_K > 0:
            rel.append(BudgetRow.type_b(msg("scale factor K (device)"), "u_rel(K)", Q_(u_rel_K, ""),
                                        distribution="normal",
                                        k=1.0,
                                        note=f"K = {k:g} {unit_text(out_unit)}/[(°)/s]; δ ≈ (F₊ − "
                                             f"F₋)/(2KΩ)"))
        r = rate_table_rel(campaign)
        if r is not None:
            rel.append(BudgetRow.type_b(msg("rate-table rate accuracy ({table})", table=r[1]),
                                        "u_rel(Ω)", Q_(r[0], ""),
                                        distribution="normal", k=1.0, note="δ ∝ 1/Ω"))
        return rel


PROCEDURES = (ScaleFactorD21, NonlinearityD22, AsymmetryD23, ScaleFactorRepeatabilityD24,
              ScaleFactorTemperatureSensitivityD25, InputAxisMisalignmentD26, MaxInputRateD3)

__all__ = ["PROCEDURES", "default_nonlinearity_limit", "collect_rate_data", "nonlinearity_of",
           "rate_sequence",
           "RateData", "MOUNTINGS"] + [c.__name__ for c in PROCEDURES]

"""GB/T 45570—2025 D.5.6 angle random walk (eqs. D.45, D.46): B_s(τ_k) over doubling τ, the
generalised least-squares D.45 fit and RWC = √α1, with the output's quantization taken out where
the noise dithers it and the result declared not reportable where it cannot be."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, Metric, Option, Outcome, PlotSpec,
                       ProcedureError, RateConversion, Result, RunContext, Segment, Step,
                       TableSpec, UncertaintyBudget, allan, join, msg)

from . import formulas as F
from .common import (BIAS_EQUIPMENT, COVERAGE, STANDARD, GbtItem, opts_text, scale_factor_row,
                     timebase_row)
from .static_bias import STATIC, Quantization, duration_warnings, quantization_of, static_input

#: χ²/ν of the D.45 fit beyond which its model is taken not to hold (interpretations.md,
#: "D.5.6 — when the D.45 model does not hold"): on records the model describes χ²/ν of the
#: nested-level GLS fit is mostly 0.4 … 5 (median 1.5); every undithered-counter RWC outside its
#: U had χ²/ν ≥ 11.4 (200 seeds, 4 h records)
D45_MISFIT_LIMIT = 10.0


class AngleRandomWalkD56(GbtItem):
    """GB/T 45570—2025 D.5.6 角度随机游走 (angle random walk), eqs. (D.45), (D.46).

    From the initial series (interval τ), the interval is doubled, τ_k = 2^(k−1)·τ, by
    averaging adjacent pairs; at each level B_s(τ_k) is the D.41 bias stability (Bessel
    standard deviation of the block means).  Levels are kept while they hold at least
    ``min_blocks`` blocks (the standard does not say how far to go; interpretations.md).
    B_s²(τ_k) = α0 + α1/τ_k + α2/τ_k² (τ_k in h) is fitted by generalised least squares and
    RWC = √α1.
    """

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
    equipment = BIAS_EQUIPMENT
    options = (
        Option("segment", None, None, "id of the static segment to use (default: the first)"),
        Option("min_blocks", 10, None, "keep a τ level only while it has at least this many blocks",
               minimum=2),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("static-8h", "static",
                     "IRA up on the levelled platform; warm up ≥ 30 min, then record 8 h "
                     "at τ = 1 s (D.5.6.2)", Q_(8, "h"), Q_(1, "s"), {"orientation": "IRA up"},
                     warmup=Q_(30, "min"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg, series, conv, raw = static_input(type(self), campaign, opts)
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
                            f"a record of {raw.size} samples gives only {tau_s.size} τ levels with "
                            f"≥ {min_blocks} "
                            "blocks; the D.45 fit needs at least 4 (too short a record for the τ "
                            "range)",
                            hint="D.5.6.2 asks for 8 h")
        zero = np.flatnonzero(~(bs > 0))
        if zero.size:
            reason = _zero_level_reason(campaign, conv, raw, seg, float(tau_s[zero[0]]),
                                        int(zero[0]))
            return self._not_fitted(opts, seg, reason, reason)
        tau_h = tau_s / 3600.0
        try:
            fit = F.fit_d45(tau_h, bs, m)
        except ValueError as exc:
            if conv.output_kind != "pulse" and quantization_of(campaign, conv, raw).q <= 0:
                raise ProcedureError(f"D.5.6: {exc}") from exc
            # quantized counts whose B_s(τ) D.45 cannot even be fitted to: not a data error
            reason = msg("the D.45 fit is not determined ({exc}); the output's quantization "
                         "dominates B_s(τ)",
                         exc=str(exc))
            return self._not_fitted(opts, seg, reason, msg("RWC is NOT REPORTABLE: {reason}",
                                                           reason=reason))
        a0, a1, a2 = (float(x) for x in fit.alpha)
        ua = fit.u_alpha
        warnings = list(duration_warnings(series, Q_(8, "h"), "D.5.6.2"))
        # rounded rate samples (LSB word, rate of finite resolution): white rate noise that D.45
        # cannot tell from the sensor's ARW (interpretations.md, "D.5 — output quantization")
        qz = quantization_of(campaign, conv, raw)
        a1_q = F.alpha1_rounding_d45(qz.q, tau0_s / 3600.0) if qz.q > 0 else 0.0
        a1_sensor, not_reportable = _alpha1_of_sensor(fit, qz, a1_q)
        rwc = math.sqrt(a1_sensor)
        for name, val in (("α0", a0), ("α2", a2)):
            if val < 0:
                warnings.append(msg("fitted {name} = {val:.3g} is negative (not physical); kept as "
                                    "the standard's "
                                    "unconstrained fit gives it — RWC uses α1 only", name=name,
                                    val=val))
        if fit.birge > 1.5:
            warnings.append(msg("the D.45 model fits poorly (χ²/ν = {chi2:.2g}); the uncertainty "
                                "of α was scaled up accordingly", chi2=fit.birge ** 2))
        budget = _rwc_budget(campaign, conv, fit, tau_s.size, rwc, qz, a1_q)
        reason = join("; ", not_reportable) if not_reportable else ""
        if reason:
            warnings.append(msg("RWC is NOT REPORTABLE: {reason}", reason=reason))
        results = [
            Result(self.metrics[0], Q_(rwc, "deg/hour**0.5"), budget.combined, budget,
                   reportable=not not_reportable, reason=reason, earth_rate="not applicable",
                   note=(msg("RWC of the sensor: √(α₁ − q²τ₀/12), the output's rounding removed")
                         if a1_q > 0 and
                         qz.dithered else "")),
            Result(self.metrics[1], Q_(a0, "deg**2/hour**2"), Q_(ua[0], "deg**2/hour**2"),
                   earth_rate="not applicable"),
            Result(self.metrics[2], Q_(a1, "deg**2/hour"), Q_(ua[1], "deg**2/hour"),
                   earth_rate="not applicable"),
            Result(self.metrics[3], Q_(a2, "deg**2"), Q_(ua[2], "deg**2"),
                   earth_rate="not applicable"),
        ]
        plot, table = _d45_figures(tau_s, bs, m, fit.model(tau_h), rwc, a1_sensor)
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=[plot],
                       tables=[table],
                       warnings=warnings, segments=[seg.id], options=opts_text(opts))

    def _not_fitted(self, opts: Mapping[str, Any], seg: Segment, reason: str,
                    warning: str) -> Outcome:
        """The outcome when the quantization leaves no RWC to fit: RWC not reportable."""
        return Outcome(STANDARD, self.item, self.title, self.clause,
                       [Result(self.metrics[0], Q_(0.0, "deg/hour**0.5"), reportable=False,
                               reason=reason,
                               earth_rate="not applicable")],
                       warnings=[warning], segments=[seg.id], options=opts_text(opts))


def _zero_level_reason(campaign: Campaign, conv: RateConversion, raw: np.ndarray, seg: Segment,
                       tau: float,
                       first: int) -> str:
    """Why B_s(τ) is zero at level ``first`` (τ in s): the output's quantization hides its noise; a
    DataError when nothing explains it (the output does not vary)."""
    qz = quantization_of(campaign, conv, raw)
    if qz.q <= 0 and not (conv.output_kind == "pulse" and first > 0):
        raise DataError(seg.file, "output",
                        f"B_s(τ = {tau:g} s) is zero: the output does not vary (zero variance)")
    what = (msg("the output, rounded to q = {q:.3g} °/h (step from {source}), does not vary",
                q=qz.q,
                source=qz.source) if qz.q > 0 else
            msg("every block holds the same whole number of pulses (an undithered counter at a "
                "steady rate)"))
    return msg("B_s(τ = {tau:g} s) is zero: {what} — its noise is hidden by the quantization, so "
               "there is no RWC to fit", tau=tau, what=what)


def _alpha1_of_sensor(fit: Any, qz: Quantization, a1_q: float) -> tuple[float, list[str]]:
    """The sensor's α1 (D.45; the output's rounding removed where the noise dithers it, else
    α1 as fitted; 0 when not positive) and the reasons RWC = √α1 is not reportable."""
    a1 = float(fit.alpha[1])
    ua = fit.u_alpha
    not_reportable: list[str] = []
    a1_sensor = a1
    if a1_q > 0 and qz.dithered:
        a1_sensor = a1 - a1_q  # Sheppard's correction: the rounding's q²/12 per sample removed
    elif a1_q > 0 and 3.0 * a1_q > 0.01 * max(a1, 0.0):
        not_reportable.append(
            msg("the output is rounded to q = {q:.3g} °/h (step from {source}), coarser than its "
                "noise (s = {s:.3g} °/h per sample): the rounding error is not white noise of a "
                "known size and adds up to q²τ/4 = {add:.3g} (°)²/h to α1 = {a1:.3g}, so the "
                "sensor's RWC cannot be separated from it (D.45 has no term for "
                "it)", q=qz.q, source=qz.source, s=qz.s, add=3 * a1_q, a1=a1))
    if fit.dof > 0 and fit.chi2 / fit.dof > D45_MISFIT_LIMIT:
        not_reportable.append(
            msg("the D.45 model does not hold: χ²/ν = {chi2:.3g} > {limit:g} (B_s(τ) has a shape "
                "D.45 cannot follow, e.g. the sawtooth quantization of an undithered counter or "
                "correlated noise); the uncertainty scaled by √(χ²/ν) would not cover a systematic "
                "misfit", chi2=fit.chi2 / fit.dof,
                limit=D45_MISFIT_LIMIT))
    if a1_sensor > 0 and a1_sensor - 2.0 * float(ua[1]) <= 0:
        # α1 not resolved from zero (≈95 %): reporting √α1 only when noise happens to push it up
        # would bias the reported RWC high (interpretations.md)
        not_reportable.append(
            msg("α1 = {a1:.3g} ± {U:.2g} (°)²/h (k = 2) is not resolved from zero: the record's "
                "other terms (quantization α2, bias instability α0) dominate B_s(τ), so RWC = √α1 "
                "is not determined; record longer or with a finer "
                "output", a1=a1_sensor, U=2.0 * float(ua[1])))
    if not a1_sensor > 0:
        not_reportable.append(
            msg("the fitted α1 = {a1:.3g} (°)²/h is not positive, so RWC = √α1 (D.46) is "
                "undefined; the record is "
                "dominated by other noise, quantization or too short (look at the B_s(τ) plot)",
                a1=a1_sensor))
        a1_sensor = 0.0
    return a1_sensor, not_reportable


def _rwc_budget(campaign: Campaign, conv: RateConversion, fit: Any, levels: int, rwc: float,
                qz: Quantization,
                a1_q: float) -> UncertaintyBudget:
    """RWC's budget: the D.45 fit's u(α1) through √α1, Sheppard's correction where applied, the
    scale factor and the time base."""
    a1, ua = float(fit.alpha[1]), fit.u_alpha
    scale = max(rwc, math.sqrt(max(a1, 0.0)), math.sqrt(abs(float(ua[1]))), 1e-30)
    u_rwc_fit = ua[1] / (2.0 * scale)
    chi2 = fit.chi2 / max(fit.dof, 1)
    rows = [BudgetRow.type_a(msg("D.45 fit of B_s²(τ_k) (GLS, nested-level covariance)"),
                             "u(α₁)/(2√α₁)",
                             Q_(u_rwc_fit, "deg/hour**0.5"), max(fit.dof, 1),
                             note=(msg("{n} levels, χ²/ν = {chi2:.3g}, u scaled by √(χ²/ν) = "
                                       "{b:.3g}", n=levels,
                                       chi2=chi2, b=fit.birge) if fit.birge > 1 else
                                   msg("{n} levels, χ²/ν = {chi2:.3g}", n=levels, chi2=chi2)))]
    if a1_q > 0 and qz.dithered:
        # the correction's own uncertainty: half of it, uniform (Sheppard's q²/12 holds to
        # < 10⁻³ when s ≥ q; the rest covers noise that is not Gaussian)
        rows.append(BudgetRow.type_b(
            msg("rounding of each sample to q = {q:.3g} °/h: Sheppard's correction α1 − q²τ₀/12 "
                "({c:.3g} (°)²/h) applied", q=qz.q, c=a1_q), "δα₁", Q_(a1_q / 2.0, "deg**2/hour"),
                                     distribution="uniform",
            sensitivity=Q_(1.0 / (2.0 * scale), "hour**0.5/deg"),
            note=msg("noise s = {s:.3g} °/h ≥ q dithers the rounding (step from {source})", s=qz.s,
                     source=qz.source)))
    rows += scale_factor_row(conv, rwc, "deg/hour**0.5")
    rows += timebase_row(campaign, rwc, "deg/hour**0.5", "RWC")
    return UncertaintyBudget("RWC", "deg/hour**0.5", rows, coverage=COVERAGE)


def _d45_figures(tau_s: np.ndarray, bs: np.ndarray, m: np.ndarray, model: np.ndarray, rwc: float,
                 a1_sensor: float) -> tuple[PlotSpec, TableSpec]:
    """D.5.6's plot of B_s(τ_k) with the D.45 fit and its table per level."""
    tau_h = tau_s / 3600.0
    plot = PlotSpec(
        "bs_tau", msg("B_s(τ_k) and the D.45 fit"), "τ_k (s)", "B_s (°/h)",
        [
            {"label": "B_s(τ_k) (D.41)", "x": tau_s.tolist(), "y": bs.tolist(),
             "yerr": (bs / np.sqrt(2 * (m - 1))).tolist(), "style": "o"},
            {"label": "D.45 fit", "x": tau_s.tolist(), "y": np.sqrt(np.clip(model, 0,
                                                                            None)).tolist(),
             "style": "-"},
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
    return plot, table

"""GB/T 45570—2025 5.5 reliability from declared evidence: 5.5.1 MTBF ≥ 5 000 h (method 6.2.9.1)
and 5.5.2 life — working life ≥ 1 000 h, calendar life ≥ 5 a (method 6.2.9.2).

6.2.9 leaves both methods to the product specification.  metro reads the evidence a lab declares
in the manifest's ``[reliability]`` table (accumulated operating hours T of all units on test,
number of relevant failures r, the test plan, the one-sided confidence C) and estimates the MTBF
under the constant-failure-rate (exponential) model by the χ² method of IEC 60605-6 (GB/T 5080.4)
— the usual reliability-demonstration arithmetic:

* point estimate θ̂ = T / r (r ≥ 1; none for r = 0);
* one-sided lower confidence bound at C = 1 − α:
  time-terminated test  θ_L = 2T / χ²(1 − α; 2r + 2),
  failure-terminated    θ_L = 2T / χ²(1 − α; 2r),
  χ²(p; ν) the p-quantile of the χ² distribution with ν degrees of freedom (scipy.stats.chi2).

5.5.1 is judged on θ_L: the MTBF is demonstrated to be at least θ_L with confidence C, so
θ_L ≥ 5 000 h conforms (docs/interpretations.md).  Life (5.5.2) is read from the records as
declared — both lives are cumulative, "whichever comes first" (以先到为准) — and judged as given.
"""

from __future__ import annotations

import math
from typing import Any, Mapping

from metro.api import (Q_, BudgetRow, Campaign, DataError, Metric, Option, Outcome, RunContext,
                       Step, TableSpec, UncertaintyBudget, msg)

from . import records as R
from .common import COVERAGE, STANDARD, GbtItem, opts_text

PLANS = ("time-terminated", "failure-terminated")


def mtbf_point(T_h: float, r: int) -> float | None:
    """θ̂ = T/r (h) — the maximum-likelihood MTBF of exponential lifetimes; None for r = 0."""
    return T_h / r if r > 0 else None


def mtbf_lower_bound(T_h: float, r: int, confidence: float, plan: str) -> float:
    """One-sided lower confidence bound of the MTBF (IEC 60605-6, χ² method):
    time-terminated θ_L = 2T/χ²(C; 2r+2), failure-terminated θ_L = 2T/χ²(C; 2r), C = 1 − α."""
    from scipy.stats import chi2

    if not 0.0 < confidence < 1.0:
        raise ValueError(f"confidence {confidence} is not between 0 and 1")
    if T_h <= 0 or r < 0:
        raise ValueError("T must be positive and r non-negative")
    if plan == "time-terminated":
        nu = 2 * r + 2
    elif plan == "failure-terminated":
        if r < 1:
            raise ValueError("a failure-terminated test ends at a failure: r ≥ 1")
        nu = 2 * r
    else:
        raise ValueError(f"unknown test plan {plan!r}")
    return 2.0 * T_h / float(chi2.ppf(confidence, nu))


def _exact_budget(symbol: str, unit: str, what: str) -> UncertaintyBudget:
    return UncertaintyBudget(symbol, unit, [BudgetRow.type_b(what, f"u({symbol})", Q_(0.0, unit),
                                                             distribution="uniform")],
                             coverage=COVERAGE)


def _evidence(campaign: Campaign) -> tuple[Mapping[str, Any], str]:
    return R.section(campaign, "reliability", "5.5"), R.where_of(campaign)


class Mtbf6291(GbtItem):
    """GB/T 45570—2025 5.5.1 平均故障间隔时间 MTBF ≥ 5 000 h, by 6.2.9.1 (the product
    specification's
    method): θ̂ = T/r and the one-sided lower bound θ_L = 2T/χ²(C; 2r+2) (time-terminated) or
    2T/χ²(C; 2r) (failure-terminated) from the declared ``[reliability]`` evidence (IEC 60605-6).
    θ_L is a confidence bound: its sampling uncertainty is the stated confidence, so its budget is
    the declared hours taken as exact; θ̂ carries u = θ̂/√r (exponential model, for information)."""

    item = "6.2.9.1"
    clause = "5.5.1"
    title = "MTBF (平均故障间隔时间)"
    metrics = (Metric("mtbf_lower", "MTBF, one-sided lower confidence bound", "θ_L", "h", "5.5.1",
                      "IEC 60605-6 χ²"),
               Metric("mtbf_point", "MTBF, point estimate T/r", "θ̂", "h", "5.5.1", "T/r"))
    record_sections = ("reliability",)
    options = (Option("confidence", 0.9, None,
                      "one-sided confidence of θ_L when [reliability] does not state it"),)

    @classmethod
    def missing_records(cls, campaign: Campaign) -> str:
        rec = campaign.records.get("reliability")
        return (
            ""
            if isinstance(rec, Mapping) and "operating_hours" in rec
            else "[reliability] operating_hours"
        )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("reliability-mtbf", "record:reliability.mtbf",
                     "from the reliability test records: accumulated operating hours of all units, "
                     "relevant failures, the test plan (time- or failure-terminated) and its "
                     "confidence (6.2.9.1)",
                     Q_(0, "s"), Q_(0, "s"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        rec, src = _evidence(campaign)
        T = R.quantity(rec.get("operating_hours"), "h", src, "reliability.operating_hours")
        T_h = float(T.to("h").magnitude)
        if T_h <= 0:
            raise DataError(src, "reliability.operating_hours", f"must be positive, got {T:~P}")
        r = rec.get("failures")
        if isinstance(r, bool) or not isinstance(r, int) or r < 0:
            raise DataError(src, "reliability.failures",
                            f"must be a whole number ≥ 0 (relevant failures), got {r!r}")
        plan = R.text(rec, "plan", src, "reliability").strip().lower()
        if plan not in PLANS:
            raise DataError(src, "reliability.plan",
                            f"must be one of {', '.join(PLANS)}, got {plan!r}")
        if plan == "failure-terminated" and r < 1:
            raise DataError(src, "reliability.failures",
                            "a failure-terminated test ends at a failure: r ≥ 1",
                            hint="a test that ended without failure is time-terminated")
        C = rec.get("confidence", opts["confidence"])
        if isinstance(C, str):
            C = float(R.quantity(C, "", src, "reliability.confidence").to("").magnitude)
        if isinstance(C, bool) or not isinstance(C, (int, float)) or not 0.5 <= float(C) < 1.0:
            raise DataError(src, "reliability.confidence",
                            f"must be a one-sided confidence in [0.5, 1), got {C!r}",
                            hint="e.g. confidence = 0.9 (or \"90 %\")")
        C = float(C)
        lower = mtbf_lower_bound(T_h, r, C, plan)
        nu = 2 * r + 2 if plan == "time-terminated" else 2 * r
        m = self.metrics
        bl = _exact_budget("θ_L", "h",
                           "declared operating hours and failures, taken as exact; the sampling of "
                           "failures is in the confidence level")
        results = [R.na_result(m[0], Q_(lower, "h"), bl.combined, bl,
                          note=f"{plan}, T = {T_h:g} h, r = {r}, C = {C:.0%} one-sided, χ²({C:g}; "
                               f"{nu})")]
        point = mtbf_point(T_h, r)
        warnings = []
        if point is not None:
            b = UncertaintyBudget("θ̂", "h", [BudgetRow.type_b(
                "sampling of r failures (exponential lifetimes)", "θ̂/√r", Q_(point / math.sqrt(r),
                                                                              "h"),
                distribution="normal", k=1.0, note="for information; 5.5.1 is judged on θ_L")],
                                  coverage=COVERAGE)
            results.append(R.na_result(m[1], Q_(point, "h"), b.combined, b,
                                       note=f"T/r = {T_h:g} h / {r}"))
        else:
            warnings.append(msg("no failure: the point estimate T/r does not exist; only θ_L is "
                                "given"))
        tab = TableSpec("reliability", "Declared reliability evidence (6.2.9.1)", ["quantity",
                                                                                   "value"],
                        [["accumulated operating hours T", f"{T_h:g} h"], ["relevant failures r",
                                                                           str(r)],
                         ["test plan", plan], ["one-sided confidence C", f"{C:g}"],
                         ["evidence", R.text(rec, "source", src, "reliability", required=False,
                                             default="—")]])
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[tab],
                       warnings=warnings,
                       options=opts_text(opts))


class Life6292(GbtItem):
    """GB/T 45570—2025 5.5.2 寿命 (life), by 6.2.9.2 (the product specification's method): working
    life ≥ 1 000 h and calendar life ≥ 5 a, both cumulative, whichever comes first — read from the
    declared ``[reliability]`` records (``working_life``, ``calendar_life``) and judged as
    declared."""

    item = "6.2.9.2"
    clause = "5.5.2"
    title = "Life (寿命)"
    metrics = (Metric("working_life", "working life (cumulative)", "L_w", "h", "5.5.2 a)"),
               Metric("calendar_life", "calendar life (cumulative)", "L_c", "year", "5.5.2 b)"))
    record_sections = ("reliability",)

    @classmethod
    def missing_records(cls, campaign: Campaign) -> str:
        rec = campaign.records.get("reliability")
        ok = isinstance(rec, Mapping) and ("working_life" in rec or "calendar_life" in rec)
        return "" if ok else "[reliability] working_life / calendar_life"

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step("reliability-life", "record:reliability.life",
                     "from the life test and storage records: the working life (h) and calendar "
                     "life (a) demonstrated (6.2.9.2)", Q_(0, "s"), Q_(0, "s"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        rec, src = _evidence(campaign)
        results, warnings = [], []
        for metric, key, dim in ((self.metrics[0], "working_life", "h"), (self.metrics[1],
                                                                          "calendar_life", "year")):
            if key not in rec:
                warnings.append(msg("{key} not declared in [reliability]: not judged", key=key))
                continue
            q = R.quantity(rec[key], dim, src, f"reliability.{key}")
            if float(q.magnitude) < 0:
                raise DataError(src, f"reliability.{key}",
                                f"must not be negative, got {rec[key]!r}")
            b = _exact_budget(metric.symbol, dim, "declared from the records, taken as exact")
            results.append(R.na_result(metric, q.to(dim), b.combined, b,
                                       note="as declared in [reliability]"))
        return Outcome(STANDARD, self.item, self.title, self.clause, results, warnings=warnings)


PROCEDURES = (Mtbf6291, Life6292)

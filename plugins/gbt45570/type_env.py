"""GB/T 45570—2025 5.4 environmental tests that clause 6.2.8 leaves to other standards and the
product specification: 5.4 b) low-temperature storage (6.2.8.2, GB/T 2423.1), d) high-temperature
storage (6.2.8.4, GB/T 2423.2), e) temperature shock (6.2.8.5, GB/T 2423.22), f) low pressure
(6.2.8.6, GB/T 2423.21), g) acceleration (6.2.8.7, GB/T 2423.15), k) damp heat (6.2.8.10,
GB/T 2423.3), l) mould (6.2.8.11, GB/T 2423.16), m) salt fog (6.2.8.12, GB/T 2423.17), n) thermal
vacuum (6.2.8.13, GB/T 34522), o) radiation (6.2.8.14, GB/T 4937.18) and p) EMC (6.2.8.15).

The test itself is done by a test lab to its standard; the campaign records, per test, one
``[[environmental_tests]]`` table (docs/standards/gbt45570.md): the severity applied, the severity
required by the product specification (optional: limits as text, ``">= 40 degC"``), the functional
check after the test, and the ids of two static segments of the gyro's output recorded before and
after it.  Each item reports

* every severity parameter applied, judged against the product specification's requirement where
  the record gives one, else against table C.1 for the device's application (5.1: the product
  specification prevails; C.1 is the typical severity).  A severity weaker than the reference does
  not conform: the test applied was too mild to show the requirement (interpretations.md);
* the bias before and after by D.5.1 (eq. (D.40), :func:`.static_bias.segment_bias`) and its change
  ΔB₀ = B₀(after) − B₀(before), judged against the product specification's ``bias_change`` limit;
* the scale factor before and after, where the campaign has the records: whole revolutions
  (``type-env-revolutions``, pulse output) by D.1.1 (eqs. (D.1), (D.2), (D.4)) or the output at rate
  points and at rest (``type-env-rate-output`` / ``type-env-rate-static``, LSB output) by D.2.1
  (eqs. (D.17)–(D.22)), and its relative change ΔK/K, judged against ``scale_factor_change``;
* the functional check (0 = passed, 1 = failed), which must be 0.
"""

from __future__ import annotations

import math
import re
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, Comparison, DataError, EquipmentRequirement, Metric,
                       Option, Outcome, Procedure, Result, RunContext, Specification, Step,
                       TableSpec, UncertaintyBudget, hint, join, msg, parse_limit)

from . import formulas as F
from . import records as R
from .common import (COVERAGE, STANDARD, GbtItem, opts_text, scale_factor_row,
                     sequence_options)
from .conformity import TABLE_C1, application_of, clause_source, product_source
from .repeatability import (bias_repeat_row, missing_turn_on, scale_factor_angle_repeat_row,
                            scale_factor_rate_repeat_row, turn_on_known)
from .static_bias import segment_bias

SECTION = "environmental_tests"
SEGMENT_KIND = "type-env"
#: revolutions at a rate point before/after a test (pulse output, D.1.1 maths); conditions test,
#: phase, rate, turns
REVOLUTIONS_KIND = "type-env-revolutions"
#: LSB output at a rate point / at rest before/after a test (D.2.1 maths); conditions test, phase,
#: rate or when
RATE_KINDS = {"type-env-rate-output": "rate-output", "type-env-rate-static": "rate-static"}
LE, GE = Comparison.AT_MOST, Comparison.AT_LEAST


@attrs.frozen
class Param:
    """One severity parameter: its name in the record, unit, the direction that is more severe
    (``LE``: a lower temperature/pressure is more severe) and table C.1's value per application
    (``None``: C.1 states none)."""

    name: str
    unit: str
    comparison: Comparison
    c1: Mapping[str, float | None] = attrs.field(factory=dict)
    label: str = ""


def _apps(a: float | None, b: float | None, c: float | None) -> dict[str, float | None]:
    return {"aerospace": a, "aviation": b, "marine": c}


@attrs.frozen
class EnvTest:
    key: str  # the record's ``test`` value
    item: str  # the method clause, used as the item id
    letter: str  # 5.4 letter
    tag: str  # metric key prefix
    name_cn: str
    name_en: str
    method: str  # the standard that gives the test method
    c1_row: int
    params: tuple[Param, ...]
    unpowered: bool = False


_T = "degC"
TESTS = (
    EnvTest("low-temperature storage", "6.2.8.2", "b", "lts", "低温贮存", "low-temperature storage",
            "GB/T 2423.1",
            2, (Param("temperature", _T, LE, _apps(-55, -55, -20), "storage temperature"),
                Param("duration", "h", GE, label="exposure time")), unpowered=True),
    EnvTest("high-temperature storage", "6.2.8.4", "d", "hts", "高温贮存",
            "high-temperature storage",
            "GB/T 2423.2",
            4, (Param("temperature", _T, GE, _apps(85, 85, 60), "storage temperature"),
                Param("duration", "h", GE, label="exposure time")), unpowered=True),
    EnvTest("temperature shock", "6.2.8.5", "e", "tsh", "温度冲击", "temperature shock",
            "GB/T 2423.22",
            5,
            (Param("low_temperature", _T, LE, _apps(-55, -55, -20), "low temperature"),
             Param("high_temperature", _T, GE, _apps(85, 85, 60), "high temperature"),
             Param("transfer_time", "min", LE, _apps(2, 2, 2), "transfer time"),
             Param("cycles", "", GE, _apps(3, 3, 3), "cycles")), unpowered=True),
    EnvTest("low pressure", "6.2.8.6", "f", "lp", "低气压(高度)", "low pressure (altitude)",
            "GB/T 2423.21", 6,
            (Param("pressure", "Pa", LE, _apps(1.33e-3, 3500, None), "pressure"),
             Param("duration", "h", GE, label="exposure time"))),
    EnvTest("acceleration", "6.2.8.7", "g", "acc", "加速度", "acceleration", "GB/T 2423.15", 7,
            (Param("acceleration", "gn", GE, _apps(18, 15, None), "steady-state acceleration"),
             Param("duration", "min", GE, label="time per direction"))),
    EnvTest("damp heat", "6.2.8.10", "k", "dh", "湿热", "damp heat", "GB/T 2423.3", 11,
            (Param("temperature", _T, GE, label="temperature"), Param("humidity", "percent", GE,
                                                                      label="humidity"),
             Param("duration", "h", GE, label="duration"))),
    EnvTest("mould", "6.2.8.11", "l", "mould", "霉菌", "mould growth", "GB/T 2423.16", 12,
            (Param("duration", "day", GE, label="incubation"),)),
    EnvTest("salt fog", "6.2.8.12", "m", "salt", "盐雾", "salt fog", "GB/T 2423.17", 13,
            (Param("duration", "h", GE, label="exposure time"),)),
    EnvTest("thermal vacuum", "6.2.8.13", "n", "tvac", "热真空", "thermal vacuum", "GB/T 34522", 14,
            (Param("pressure", "Pa", LE, _apps(6.65e-3, None, None), "test pressure"),
             Param("low_temperature", _T, LE, _apps(-45, None, None), "low temperature"),
             Param("high_temperature", _T, GE, _apps(85, None, None), "high temperature"),
             Param("cycles", "", GE, _apps(3, None, None), "cycles"))),
    EnvTest("radiation", "6.2.8.14", "o", "rad", "抗辐照", "radiation (total dose)", "GB/T 4937.18",
            15,
            (Param("total_dose", "Gy", GE, _apps(200.0, None, None),
                   "total ionising dose (Si); 20 krad = 200 Gy"),)),
    EnvTest("emc", "6.2.8.15", "p", "emc", "电磁兼容性", "electromagnetic compatibility",
            "product specification", 16,
            ()),
)
BY_KEY = {t.key: t for t in TESTS}
_ALIASES = (
    {t.tag: t.key for t in TESTS}
    | {t.item: t.key for t in TESTS}
    | {
        "electromagnetic compatibility": "emc",
        "thermal shock": "temperature shock",
        "salt mist": "salt fog",
        "mold": "mould",
        "altitude": "low pressure",
    }
)


def test_key(value: Any, file: str, field: str) -> str:
    k = str(value or "").strip().lower()
    k = _ALIASES.get(k, k)
    if k not in BY_KEY:
        raise DataError(file, field, f"unknown test {value!r}; use one of {', '.join(BY_KEY)}")
    return k


def records_of(campaign: Campaign, test: EnvTest) -> list[tuple[int, Mapping[str, Any]]]:
    """The ``[[environmental_tests]]`` entries for ``test`` (index, table)."""
    raw = campaign.records.get(SECTION)
    if raw is None:
        return []
    seq = raw if isinstance(raw, list) else [raw]
    out = []
    for i, t in enumerate(seq):
        if not isinstance(t, Mapping):
            raise DataError(R.where_of(campaign), f"{SECTION}[{i}]",
                            "must be a table ([[environmental_tests]])")
        if test_key(t.get("test"), R.where_of(campaign), f"{SECTION}[{i}].test") == test.key:
            out.append((i, t))
    return out


def c1_specification(test: EnvTest, p: Param, application: str | None) -> Specification | None:
    """Table C.1's severity for ``p`` in the device's application, as a limit on the applied
    value."""
    if application is None or p.c1.get(application) is None:
        return None
    row = next(r for r in TABLE_C1 if r.no == test.c1_row)
    return Specification(f"{test.tag}_{p.name}", p.comparison, Q_(p.c1[application], p.unit),
                         source=row.source(application),
                         name=f"{test.name_en}: {p.label or p.name} (severity)",
                         items=(test.item,))


def required_specifications(campaign: Campaign, test: EnvTest) -> list[Specification]:
    """The severity the record says the product specification requires (``[…required]``), else
    table C.1's; and the product specification's ``bias_change`` limit."""
    out: list[Specification] = []
    src = R.where_of(campaign)
    app = application_of(campaign.device.application)
    for i, rec in records_of(campaign, test):
        req = rec.get("required", {})
        if not isinstance(req, Mapping):
            raise DataError(src, f"{SECTION}[{i}].required",
                            "must be a table of limits such as temperature = \"<= -55 degC\"")
        source = str(req.get("source") or "") or product_source(f"manifest {SECTION}[{i}].required")
        known = {p.name for p in test.params} | {"bias_change", "scale_factor_change", "source"}
        for key in req:
            if key not in known:
                raise DataError(src, f"{SECTION}[{i}].required.{key}",
                                f"not a severity of {test.key} "
                                f"({', '.join(sorted(known - {'source'}))})")
        for p in test.params:
            if p.name in req:
                out.append(attrs.evolve(parse_limit(f"{test.tag}_{p.name}", req[p.name],
                                                    source=source, file=src,
                                                    field=f"{SECTION}[{i}].required.{p.name}"),
                                        items=(test.item,)))
            else:
                spec = c1_specification(test, p, app)
                if spec is not None:
                    out.append(spec)
        if "scale_factor_change" in req:
            out.append(attrs.evolve(parse_limit(f"{test.tag}_dK", req["scale_factor_change"],
                                                source=source, file=src,
                                                field=f"{SECTION}[{i}].required.scale_factor_change"),
                                    items=(test.item,)))
        if "bias_change" in req:
            out.append(attrs.evolve(parse_limit(f"{test.tag}_dB0", req["bias_change"],
                                                source=source, file=src,
                                                field=f"{SECTION}[{i}].required.bias_change"),
                                    items=(test.item,)))
        break  # the first record of the test is the one evaluated
    return out


def specifications(campaign: Campaign) -> list[Specification]:
    """Every environmental test's severity and bias-change limits, and the functional checks (=
    0)."""
    out = []
    for t in TESTS:
        if records_of(campaign, t):
            out += required_specifications(campaign, t)
            out.append(Specification(f"{t.tag}_function", LE, Q_(0, ""),
                                     source=clause_source(f"5.4 {t.letter})",
                                                          msg("functional check after the test")),
                                     name=msg("{test}: functional check", test=t.name_en),
                                     items=(t.item,)))
    return out


def turn_on_rows(rows: list[BudgetRow], absent: str, what: str, unit: str,
                 scale: float) -> tuple[list[BudgetRow], str]:
    """The before and after records of a 5.4 test are two power-ons (a storage test is unpowered):
    each
    carries the turn-on scatter that the campaign's repeatability item measures (D.5.3's σ_on, D.1.4
    /
    D.2.4's K_r), √2 of it on their difference.  ``rows`` / ``absent`` are what
    :mod:`.repeatability` found (the row of one power-on, or why there is none); ``scale`` turns the
    row's u into ``unit``; the row keeps its degrees of freedom (σ_on of D.5.3 is the posterior mean
    of a
    variance component, ν = ∞; K_r of D.1.4 / D.2.4, Q − 1) (interpretations.md, "6.2.8 — before and
    after
    are two power-ons", "σ_on — a variance component the data only bound")."""
    if not rows:
        return [], absent
    r = rows[0]
    u = math.sqrt(2.0) * float(r.contribution.magnitude) * scale
    src = msg("power-on repeatability of {what} in each of the two records: √2 × one power-on's",
              what=what)
    if r.type == "B":  # stated as a device property, not measured here
        return [BudgetRow.type_b(src, "√2·σ_on", Q_(u, unit), distribution="normal", k=1.0,
                                 note=r.source)], ""
    return [BudgetRow.type_a(src, "√2·σ_on", Q_(u, unit), r.dof, note=join("; ", [r.source,
                                                                                  r.note]) if r.note
                             else r.source)], ""


def not_without_turn_on(result: Result, campaign: Campaign, what: str, item: str, why: str,
                        method: str = "") -> Result:
    """A difference of two power-ons whose turn-on scatter the campaign neither measures nor states
    is not
    reportable (interpretations.md, "GB/T 45570 — a difference of power-ons needs their turn-on
    scatter")."""
    if turn_on_known(campaign, what, method):
        return result
    return attrs.evolve(result, reportable=False, reason=missing_turn_on(what, item, why))


def _bias_change(
    metric: Metric, before, after, turn_on: tuple[list[BudgetRow], str] = ([], "")
) -> Result:
    """ΔB₀ = B₀(after) − B₀(before) (both by D.40) with the two biases' batch scatter (A) and the
    scale factor (B); the earth-rate, latitude and levelling terms are common and cancel; the two
    power-ons' turn-on scatter (``turn_on``: :func:`turn_on_rows`)."""
    d = after.B0 - before.B0
    uA = math.hypot(before.u_A, after.u_A)
    nu = uA**4 / (before.u_A**4 / before.nu_A + after.u_A**4 / after.nu_A) if uA > 0 else math.inf
    rows = [BudgetRow.type_a(msg("scatter of the two biases (batch means)"), "√(u²(B_a)+u²(B_b))",
                             Q_(uA, "deg/h"), nu,
                             note=msg("earth rate, latitude and levelling are common to both "
                                      "records and cancel"))]
    for phase, est in (("before", before), ("after", after)):
        # the D.5.1 row of each bias: two roundings, independent (different true values)
        if est.hw_q > 0:
            rows.append(
                BudgetRow.type_b(
                    msg("quantization of the output: B₀ before (the D.5.1 row)")
                    if phase == "before"
                    else msg("quantization of the output: B₀ after (the D.5.1 row)"),
                    "δB₀",
                    Q_(est.hw_q, "deg/h"),
                    distribution="uniform",
                    note=msg("the two biases' rounding errors do not cancel in the difference"),
                )
            )
    rows += turn_on[0]
    rows += scale_factor_row(before.conv, d, "deg/h")
    b = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
    return Result(metric, Q_(d, "deg/h"), b.combined, b, earth_rate="removed",
                  note=join("; ",
                            [msg("B₀ before {b:.5f} °/h, after {a:.5f} °/h (D.5.1, eq. (D.40))",
                                 b=before.B0,
                                       a=after.B0), *([turn_on[1]] if turn_on[1] else [])]))


def _severity_result(metric: Metric, q, rec: Mapping, p: Param, src: str,
                     where: str) -> tuple[Result, str]:
    """The applied severity with the uncertainty the test lab declares (``[…uncertainty]``, U at
    k = 2), else none evaluated (a zero row, named in a warning, as for the D.6 conditions); a
    count (cycles) is exact."""
    unc = rec.get("uncertainty", {})
    delta = "delta_degC" if p.unit == "degC" else p.unit
    missing = ""
    if isinstance(unc, Mapping) and p.name in unc:
        U = R.quantity(unc[p.name], delta, src, f"{where}.uncertainty.{p.name}")
        rows = [BudgetRow.type_b(msg("{what}: test lab's declared U", what=p.label or p.name),
                                 f"u({metric.symbol})",
                                 U.to(delta),
                                 distribution="normal", k=2.0)]
    elif p.unit == "":
        rows = [BudgetRow.type_b(msg("{what}: a count (exact)", what=p.label or p.name),
                                 f"u({metric.symbol})", Q_(0.0, ""),
                                 distribution="uniform")]
    else:
        rows = [BudgetRow.type_b(msg("{what}: no uncertainty declared by the test lab",
                                     what=p.label or p.name),
                                 f"u({metric.symbol})", Q_(0.0, delta), distribution="uniform",
                                 note=msg("uncertainty of the severity not evaluated"))]
        missing = p.label or p.name
    b = UncertaintyBudget(metric.symbol, delta, rows, coverage=COVERAGE)
    return R.na_result(metric, q.to(p.unit), b.combined, b,
                       note=msg("as applied, as the test lab records it")), missing


def _phase_segments(campaign: Campaign, kinds, tag: str, phase: str) -> list:
    return [sg for sg in campaign.segments if sg.kind in kinds and str(sg.conditions.get("test",
                                                                                         "")) == tag
            and str(sg.conditions.get("phase", "")).lower() == phase]


def _counts_type_a(pts, c) -> tuple[float, float]:
    """u and ν of Σ c_j·K_j, each K_j of eq. (D.2) from the mean counts of the + and − revolutions:
    each direction's mean is a type A, s/√m of its m revolution counts with ν = m − 1 (one
    revolution: ±½ P, ν = ∞); their Welch–Satterthwaite ν (JJF 1059.1 eq. (34)).  Three revolutions
    per direction give ν = 2 each, so ν of K is a few, not ∞ (interpretations.md, 6.2.8 ΔK/K)."""
    from .formulas_rate import propagate

    cs, us, nus = [], [], []
    for pt, cj in zip(pts, c):
        for s, m in ((pt.s_plus, pt.m_plus), (pt.s_minus, pt.m_minus)):
            cs.append(cj / (2 * F.REVOLUTION_ARCSEC))
            us.append(s / math.sqrt(m) if m > 1 else 0.5)
            nus.append(m - 1 if m > 1 else math.inf)
    return propagate(cs, us, nus)


def scale_factor_at_phase(proc: type[Procedure], campaign: Campaign, tag: str, phase: str):
    """(K, u(K), ν, unit, method) of the records before or after a test, or None without records:
    D.1.1 on whole revolutions (one rate point: K_i of eq. (D.2); more: K of the eq. (D.4) fit), or
    D.2.1 on the LSB output (K of eqs. (D.21)/(D.22) with its propagated type A)."""
    from metro.api import fit_line

    from .rate_data import collect_rate_data, fit_scale_factor
    from .revolutions import collect_rate_points

    what = f"{phase} the test {tag}"
    revs = _phase_segments(campaign, (REVOLUTIONS_KIND,), tag, phase)
    if revs and campaign.device.output not in ("pulse", ""):
        # whole-revolution pulse counts are the angle method's (D.1.1): not for this output
        revs = []
    if revs:
        pts = collect_rate_points(proc, campaign, 1, segments=revs, what=what)
        if len(pts) == 1:
            uK, nuK = _counts_type_a(pts, [1.0])
            return pts[0].K, uK, nuK, "P/arcsec", "D.1.1, eq. (D.2), one rate point"
        rates = np.array([pt.rate for pt in pts])
        Ki = np.array([pt.K for pt in pts])
        if len(pts) == 2:  # a line through two points: no residual dof; u from the counts' scatter
            w = (Ki[1] - Ki[0]) / (rates[1] - rates[0])
            K = float(Ki[0] - w * rates[0])
            # K = K_1·Ω_2/(Ω_2 − Ω_1) − K_2·Ω_1/(Ω_2 − Ω_1)
            uK, nuK = _counts_type_a(pts,
                                     [abs(r_other) / abs(rates[1] - rates[0])
                                      for r_other in rates[::-1]])
            return K, uK, nuK, "P/arcsec", "D.1.1, eq. (D.4) through two rate points"
        fit = fit_line(rates, Ki)
        return float(fit.coef[0]), float(fit.stderr[0]), fit.dof, "P/arcsec", "D.1.1, eq. (D.4) fit"
    lsb = _phase_segments(campaign, tuple(RATE_KINDS), tag, phase)
    if lsb:
        view = attrs.evolve(campaign, segments=[attrs.evolve(sg,
                                                             kind=RATE_KINDS[sg.kind])
                                                for sg in lsb])
        data = collect_rate_data(proc, view, 1, what=what)
        fit = fit_scale_factor(data)
        return fit.K, fit.uK, fit.nuK, "LSB/(deg/s)", "D.2.1, eqs. (D.21), (D.22)"
    return None


def scale_factor_change(
    metric: Metric, before, after, turn_on: tuple[list[BudgetRow], str] = ([], "")
) -> Result:
    """ΔK/K = (K_after − K_before)/K_before (ppm) with the two K's type A (relative, combined) and
    the
    two power-ons' turn-on scatter (``turn_on``: :func:`turn_on_rows`, in ppm)."""
    Kb, ub, nub, unit, how = before
    Ka, ua, nua, unit_a, _ = after
    if unit != unit_a:
        raise DataError(None, metric.key,
                        f"the scale factor before is in {unit}, after in {unit_a}: records of two "
                        f"methods")
    d = (Ka - Kb) / Kb
    u = math.hypot(ua / Kb, ub * Ka / Kb**2)
    parts = [(ua / Kb, nua), (ub * Ka / Kb**2, nub)]
    nu = u**4 / sum(x**4 / n for x, n in parts if x > 0 and math.isfinite(n)) if u > 0 and any(
        x > 0 and math.isfinite(n) for x, n in parts) else math.inf
    rows = [BudgetRow.type_a(msg("scatter of the two scale factors"), "u(ΔK/K)", Q_(u * 1e6, "ppm"),
                             nu,
                             note=join("; ", [how,
                                              msg("the table's angle and time base are common to "
                                                  "both and cancel")]))]
    rows += turn_on[0]
    b = UncertaintyBudget(metric.symbol, "ppm", rows, coverage=COVERAGE)
    return Result(metric, Q_(d * 1e6, "ppm"), b.combined, b, earth_rate="removed",
                  note=join("; ", [msg("K before {b:.8g}, after {a:.8g} {unit} ({how})", b=Kb, a=Ka,
                                       unit=unit, how=how),
                                   *([turn_on[1]] if turn_on[1] else [])]))



def _severity_results(t: EnvTest, sev: Mapping[str, Any], rec: Mapping[str, Any], src: str,
                      where: str) -> tuple[list[Result], list[list[Any]], list[str]]:
    """The results of the severities a test record states (each judged by table C.1 where it has a
    row), their table rows and the severities whose uncertainty the test lab does not declare."""
    names = {p.name for p in t.params}
    for key in sev:
        if names and key not in names:
            raise DataError(src, f"{where}.severity.{key}", f"not a severity of {t.key}; known: "
                            f"{', '.join(sorted(names))}")
    results: list[Result] = []
    table, undeclared = [], []
    for p in t.params:
        if p.name not in sev:
            if p.c1:
                raise DataError(src, f"{where}.severity.{p.name}",
                                f"missing: table C.1 row {t.c1_row} states the "
                                f"{p.label or p.name} of {t.key}")
            continue
        q = R.quantity(sev[p.name], p.unit, src, f"{where}.severity.{p.name}")
        m = Metric(f"{t.tag}_{p.name}", msg("{test}: {what} applied", test=t.name_en,
                                            what=p.label or p.name), p.name, p.unit,
                   f"5.4 {t.letter})", t.method)
        r, missing = _severity_result(m, q, rec, p, src, where)
        results.append(r)
        if missing:
            undeclared.append(missing)
        table.append([p.label or p.name, f"{q:~P}"])
    return results, table, undeclared


def _bias_change_result(t: EnvTest, rec: Mapping[str, Any], campaign: Campaign, src: str,
                        where: str,
                        batches: int) -> tuple[dict[str, Any], Result]:
    """The segments before and after a test and the change of the bias between them (D.40), with
    the turn-on scatter of D.5.3 (two power-ons)."""
    ids = {}
    for ph in ("before", "after"):
        sid = R.text(rec, ph, src, where)
        seg = next((s for s in campaign.segments if s.id == sid), None)
        if seg is None:
            raise DataError(src, f"{where}.{ph}", f"no segment with id {sid!r} in the campaign")
        ids[ph] = seg
    est = {ph: segment_bias(seg, campaign, batches) for ph, seg in ids.items()}
    dm = Metric(f"{t.tag}_dB0", msg("{test}: bias change after − before", test=t.name_en), "ΔB₀",
                "deg/h", "D.5.1.3", "D.40")
    # σ_on of D.5.3 as D.5.4 / D.5.5 / D.6.3 / D.6.4 take it (its posterior mean, ν = ∞: the row's
    # own)
    on = turn_on_rows(*bias_repeat_row(campaign, batches, None), "B₀", "deg/h", 1.0)
    result = not_without_turn_on(_bias_change(dm, est["before"], est["after"], on), campaign, "B₀",
                                 "D.5.3",
                                 msg("before and after {test} are two power-ons", test=t.key))
    return ids, result


class _EnvironmentalTest(GbtItem):
    """Shared by the 5.4 tests done elsewhere: severity applied, bias before/after (D.5.1), the
    functional check.  Subclasses set ``test``."""

    test: EnvTest
    record_sections = (SECTION,)
    # the biases before/after are D.5.1's (segment_bias): the counter's time base and the platform's
    # levelness
    equipment = (EquipmentRequirement("counter",
                                      "gyro test system / counter; its time-base uncertainty "
                                      "enters the budgets"),
                 EquipmentRequirement("platform",
                                      "levelled stable platform (D.5.1.1 a)); its levelness enters "
                                      "the bias budget"))
    options = (Option("batches", 20, None, "batch means for the biases' type A uncertainty",
                      minimum=2),
               Option("scale_factor", "angle", None,
                      "scale factor before/after: angle (D.1.1 revolutions, pulse "
                      "output), rate (D.2.1, LSB output) or none"),
               Option("sf_rates", "10 deg/s, 100 deg/s", None,
                      "rate points of the scale-factor check"),
               Option("turns", 3, None,
                      "whole revolutions per rate point and direction (angle method)"))

    @classmethod
    def missing_records(cls, campaign: Campaign) -> str:
        try:
            found = records_of(campaign, cls.test)
        except DataError:
            return ""  # evaluate reports the bad record by name
        return "" if found else f"[[{SECTION}]] with test = \"{cls.test.key}\""

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        t = self.test
        base = {"orientation": "IRA up", "test": t.tag}
        sf = {ph: self._sf_steps(opts, ph) for ph in ("before", "after")}
        return sf["before"] + [
            Step(f"env-{t.tag}-before", SEGMENT_KIND,
                 f"before the {t.name_en} test: IRA up on the levelled platform, "
                 "record 10 min at τ = 1 s (bias by D.5.1)", Q_(10, "min"), Q_(1, "s"),
                 base | {"phase": "before"},
                 warmup=Q_(10, "min")),
            Step(f"env-{t.tag}-record", f"record:{SECTION}.{t.tag}",
                 f"{t.name_en} ({t.name_cn}) by "
                 f"{t.method}{', gyro not operating' if t.unpowered else ''}, at the "
                 f"product specification's severity (table C.1 row {t.c1_row}): record the "
                 f"severity applied, the "
                 "functional check and the test report", Q_(0, "s"), Q_(0, "s"), {"test": t.tag}),
            Step(f"env-{t.tag}-after", SEGMENT_KIND,
                 f"after the {t.name_en} test and recovery: IRA up, record 10 min "
                 "at τ = 1 s (bias by D.5.1); functional check", Q_(10, "min"), Q_(1, "s"),
                 base | {"phase": "after"},
                 warmup=Q_(10, "min")),
        ] + sf["after"]

    def _sf_steps(self, opts: Mapping[str, Any], phase: str) -> list[Step]:
        t, how = self.test, str(opts["scale_factor"]).strip().lower()
        if how not in ("angle", "rate", "none"):
            raise DataError(None, "option scale_factor",
                            f"must be angle, rate or none, got {how!r}")
        if how == "none":
            return []
        from metro.api import parse_quantity

        rates = [float(parse_quantity(x.strip(), dimension="deg/s",
                                      field="option sf_rates").to("deg/s").magnitude)
                 for x in str(opts["sf_rates"]).split(",") if x.strip()]
        base = {"test": t.tag, "phase": phase}
        steps = []
        if how == "rate":
            for when in ("start", "end"):
                steps.append(Step(f"env-{t.tag}-{phase}-rest-{when}", "type-env-rate-static",
                                  f"{phase} the {t.name_en} test: table at rest ({when}), 100 s "
                                  f"(D.2.1.2 h))",
                                  Q_(100, "s"), Q_(1, "s"), base | {"when": when}))
        for r in rates:
            for sign in (1, -1):
                if how == "angle":
                    m = int(opts["turns"])
                    steps.append(Step(f"env-{t.tag}-{phase}-rev{sign * r:+g}", REVOLUTIONS_KIND,
                                      f"{phase} the {t.name_en} test: {m} whole revolutions at "
                                      f"{sign * r:+g} °/s "
                                      "(D.1.1.2 g))", Q_(m * 360.0 / r, "s"), Q_(360.0 / r, "s"),
                                      base | {"rate": f"{sign * r:g} deg/s", "turns": m}))
                else:
                    steps.append(Step(f"env-{t.tag}-{phase}-rate{sign * r:+g}",
                                      "type-env-rate-output",
                                      f"{phase} the {t.name_en} test: table at {sign * r:+g} °/s, "
                                      f"100 s (D.2.1.2 g))",
                                      Q_(100, "s"), Q_(1, "s"),
                                      base | {"rate": f"{sign * r:g} deg/s"}))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        t = self.test
        src = R.where_of(campaign)
        found = records_of(campaign, t)
        if not found:
            raise DataError(src, SECTION,
                            f"GB/T 45570 {t.item} needs a [[{SECTION}]] table with test = "
                            f"\"{t.key}\"; "
                            "none found", hint="docs/standards/gbt45570.md shows the record")
        i, rec = found[0]
        where = f"{SECTION}[{i}]"
        warnings = [msg("{test}: a second record of the test is not evaluated (the first is)",
                        test=t.name_en)
                    for _ in found[1:]]
        sev = rec.get("severity")
        if not isinstance(sev, Mapping):
            raise DataError(src, f"{where}.severity",
                            "missing: the severity applied (a table such as temperature = "
                            "\"-55 degC\")")
        results, table, undeclared = _severity_results(t, sev, rec, src, where)
        if undeclared:
            warnings.append(msg("{test}: the test lab declares no uncertainty of the applied "
                                "{what}: judged as stated",
                                test=t.name_en, what=join(", ", undeclared)))
        if not t.params:
            table.append([msg("severity"), "; ".join(f"{k} = {v}" for k, v in sev.items()) or "—"])
        func = R.answer(rec, "functional_check", src, where)
        fm = Metric(f"{t.tag}_function",
                    msg("{test}: functional check after the test failed (1) or passed (0)",
                        test=t.name_en),
                    "F", "", f"5.4 {t.letter})")
        fb = UncertaintyBudget("F", "", [BudgetRow.type_b(msg("an observed pass/fail: exact"),
                                                          "u(F)", Q_(0.0, ""),
                                                          distribution="uniform")],
                               coverage=COVERAGE)
        results.append(R.na_result(fm, Q_(0.0 if func else 1.0, ""), fb.combined, fb,
                              note=msg("passed") if func else msg("FAILED")))
        used: list[str] = []
        if "before" in rec or "after" in rec:
            ids, result = _bias_change_result(t, rec, campaign, src, where, int(opts["batches"]))
            results.append(result)
            used = [ids["before"].id, ids["after"].id]
        else:
            warnings.append(msg("no before/after records of the gyro's output for {test}: the "
                                "change of its bias is not evaluated", test=t.key))
        sf = {ph: scale_factor_at_phase(type(self), campaign, t.tag, ph) for ph in ("before",
                                                                                    "after")}
        if campaign.device.output not in ("pulse", "") and any(
                sg.kind == REVOLUTIONS_KIND and str(sg.conditions.get("test",
                                                                      "")) == t.tag
                                                               for sg in campaign.segments):
            warnings.append(msg("revolution counts of {test} ignored: the angle method (D.1.1) "
                                "reads pulse output and this gyro's output is {output}; record it "
                                "with the rate method (D.2.1) to check its scale "
                                "factor{hint}", test=t.key, output=campaign.device.output,
                                hint=hint(" (option scale_factor = rate)")))
        if sf["before"] is not None and sf["after"] is not None:
            km = Metric(f"{t.tag}_dK", msg("{test}: relative scale-factor change after − before",
                                           test=t.name_en), "ΔK/K", "ppm",
                        "D.1.1.3 / D.2.1.3")
            Kb = sf["before"][0]
            found = (scale_factor_angle_repeat_row(campaign, Kb,
                                                   "") if sf["before"][3] == "P/arcsec" else
                     scale_factor_rate_repeat_row(campaign, Kb, "", 1))
            on = turn_on_rows(*found, "K", "ppm", 1e6 / abs(Kb))
            angle = sf["before"][3] == "P/arcsec"
            results.append(not_without_turn_on(scale_factor_change(km, sf["before"], sf["after"],
                                                                   on), campaign, "K",
                                               "D.1.4" if angle else "D.2.4",
                                               msg("before and after {test} are two power-ons",
                                                   test=t.key),
                                               "angle" if angle else "rate"))
            used += [sg.id for sg in campaign.segments if sg.kind in (REVOLUTIONS_KIND, *RATE_KINDS)
                     and str(sg.conditions.get("test", "")) == t.tag]
        elif sf["before"] is not None or sf["after"] is not None:
            missing = "after" if sf["after"] is None else "before"
            raise DataError(src, "segments",
                            f"scale-factor records of {t.key} "
                            f"{'before' if missing == 'after' else 'after'} the test but none "
                            f"{missing} it (test = \"{t.tag}\", phase = \"{missing}\")")
        meta = [[msg("test method"), str(rec.get("standard") or t.method)],
                [msg("test lab / report"), join(" / ", [rec[k] for k in ("lab",
                                                                         "report") if k in rec])
                 if any(
                    k in rec for k in ("lab", "report")) else "—"]]
        tab = TableSpec(f"{t.tag}_severity", msg("{test}: severity applied", test=t.name_en),
                        [msg("parameter"), msg("value")],
                        meta + table)
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[tab],
                       warnings=warnings,
                       segments=used, options=opts_text(opts))


def _make(test: EnvTest) -> type[Procedure]:
    doc = (f"GB/T 45570—2025 5.4 {test.letter}) {test.name_cn} ({test.name_en}), by {test.item}: "
           f"{test.method} and the product specification's conditions; severity judged against the "
           f"product specification or table C.1 row {test.c1_row}, bias before/after by D.5.1 (eq. "
           f"(D.40)), functional check.")
    words = "".join(w.capitalize() for w in re.sub(r"[^A-Za-z ]+", " ", test.name_en).split())
    return type(f"{words}{test.item.replace('.', '')}", (_EnvironmentalTest,), {
        "__doc__": doc, "__module__": __name__, "item": test.item, "clause": f"5.4 {test.letter})",
        "title": f"{test.name_en.capitalize()} ({test.name_cn})", "test": test,
        "metrics": tuple(Metric(f"{test.tag}_{p.name}",
                                f"{test.name_en}: {p.label or p.name} applied", p.name,
                                p.unit, f"5.4 {test.letter})") for p in test.params)
        + (Metric(f"{test.tag}_function", f"{test.name_en}: functional check", "F", "",
                  f"5.4 {test.letter})"),
           Metric(f"{test.tag}_dB0", f"{test.name_en}: bias change", "ΔB₀", "deg/h", "D.5.1.3",
                  "D.40"),
           Metric(f"{test.tag}_dK", f"{test.name_en}: scale-factor change", "ΔK/K", "ppm",
                  "D.1.1.3 / D.2.1.3")),
    })


PROCEDURES = tuple(_make(t) for t in TESTS)

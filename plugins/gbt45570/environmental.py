"""GB/T 45570—2025 D.6 environmental tests and the general tests 6.2.7.7 and 6.2.7.8:
D.6.1 low-temperature and D.6.2 high-temperature operation (bias and bias stability at the
temperature), D.6.3 vibration (ΔB_V12, ΔB_V13), D.6.4 mechanical shock (ΔB_V13), 6.2.7.7 set-up
time and 6.2.7.8 power consumption.

Besides the bias quantities each environmental item reports the condition it applied (the
temperature, the vibration or shock level), with the uncertainty of the equipment that set it,
since table C.1 states its limits as those conditions.

Data (segment kinds and conditions):

* D.6.1 / D.6.2: ``low-temperature`` / ``high-temperature``, conditions ``orientation`` and
  ``temperature``, 1 h of ``output`` after a soak of at least 2 h;
* D.6.3: ``vibration``, conditions ``axis`` (IRA/XRA/YRA, the axis along the vibration),
  ``test`` (``performance``/``endurance``), ``phase`` (``before``/``during``/``after``) and
  ``level`` (g_rms); ``during`` only for performance vibration (unpowered otherwise);
* D.6.4: ``shock``, conditions ``axis``, ``phase`` (``before``/``after``), ``level`` (peak, g) and
  ``pulse`` (duration, ms);
* 6.2.7.7: ``power-on``, ``output`` from the switch-on (its first sample starts at t = 0);
* 6.2.7.8: ``power``, one per supply (condition ``supply``), columns ``voltage`` (V) and
  ``current`` (A).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement,
                       Metric, Option, Outcome, Procedure, ProcedureError, Result, RunContext,
                       Segment, SegmentRequirement, Step, TableSpec, UncertaintyBudget, allan, hint,
                       join, msg, parse_quantity)

from . import env_formulas as E
from .common import (COUNTER, COVERAGE, PLATFORM, STANDARD, GbtItem, opts_text, scale_factor_row,
                     need_segments, sequence_options, timebase_row)
from .power_on import PowerConsumption6278, SetupTime6277
from .procedures import REPEATS_OPTION, repeat_steps
from .repeatability import bias_turn_on
from .static_bias import mean_rate, segment_bias

AXES = ("IRA", "XRA", "YRA")


def _names(text: Any, allowed: tuple[str, ...], option: str) -> list[str]:
    out = [p.strip() for p in str(text).split(",") if p.strip()]
    for p in out:
        if p not in allowed:
            raise ProcedureError(f"option {option}: {p!r} is not one of {', '.join(allowed)}")
    return out


def _condition_result(metric: Metric, value, equipment, campaign: Campaign, *,
                      prop: str | None = None,
                      what: str) -> tuple[Result, list[str]]:
    """A Result for an applied condition (temperature, vibration or shock level) with a budget
    from the equipment that set it: its calibration (relative or absolute) and, if given, the
    property ``prop`` (a half-width, uniform)."""
    unit = metric.unit
    mag = float(value.to(unit).magnitude)
    delta = "delta_degC" if unit == "degC" else unit
    rows, warnings = [], []
    if equipment is not None and equipment.calibration is not None:
        cal = equipment.calibration
        sens = Q_(abs(mag), delta) if cal.uncertainty.dimensionless else Q_(1.0, "")
        rows.append(BudgetRow.from_calibration(msg("{what} ({equipment})", what=what,
                                                   equipment=equipment.describe()),
                                               f"u({metric.symbol})", cal,
                                               sensitivity=sens))
    if equipment is not None and prop and prop in equipment.properties:
        v = equipment.properties[prop]
        q = (
            parse_quantity(v, file=campaign.source, field=f"equipment.{prop}")
            if isinstance(v, str)
            else v
        )
        sens = Q_(abs(mag), delta) if q.dimensionless else Q_(1.0, "")
        rows.append(BudgetRow.type_b(msg("{prop} of the {role}", prop=prop.replace('_', ' '),
                                         role=equipment.role.replace('_', ' ')),
                                     f"δ({metric.symbol})", q, distribution="uniform",
                                     sensitivity=sens))
    if not rows:
        rows.append(BudgetRow.type_b(msg("{what}: no calibration data given", what=what),
                                     f"u({metric.symbol})",
                                     Q_(0.0, delta), distribution="uniform",
                                     note=msg("uncertainty of the condition not evaluated")))
        warnings.append(msg("{name}: no calibration data for the {what}; its uncertainty is not "
                            "evaluated",
                            name=metric.name, what=what))
    budget = UncertaintyBudget(metric.symbol, delta, rows, coverage=COVERAGE)
    return Result(metric, Q_(mag, unit), budget.combined, budget,
                  earth_rate="not applicable"), warnings


# --------------------------------------------------------------------------------------------
# D.6.1 / D.6.2 low- and high-temperature operation
# --------------------------------------------------------------------------------------------


class _TemperatureOperation(GbtItem):
    """Shared by D.6.1 and D.6.2: bias (D.5.1, D.40) and bias stability (D.5.2, D.41) of 1 h at
    the temperature point after the soak, and the temperature itself."""

    kind: str
    word: str
    equipment = (EquipmentRequirement("chamber",
                                      "high/low temperature chamber (D.6.1.1 b)); its calibration "
                                      "and property uniformity enter the temperature's budget"),
                 COUNTER, PLATFORM)

    def __init_subclass__(cls, word: str = "", row: str = "", default: str = "", points: str = "",
                          **kw: Any) -> None:
        """An item at the ``word`` temperature (table C.1 ``row``: ``points``; the default option
        ``default`` covers them all): its metrics, its one segment and its options."""
        super().__init_subclass__(**kw)
        if not word:  # a subclass of a complete item keeps its own
            return
        cls.kind, cls.word = f"{word}-temperature", word
        cls.metrics = _temperature_metrics(word, word, cls.clause, row)
        cls.requires = (SegmentRequirement(cls.kind, f"1 h at the {word} temperature after a soak "
                                                     "of at least 2 h",
                                           conditions={"orientation": "", "temperature": "degC"},
                                           columns={"output": OUTPUT_UNITS}),)
        cls.options = (Option("temperature", default, "degC",
                              f"the {word} temperature point (product spec; table C.1 {row}: "
                              f"{points}, the default covers all three)"),
                       Option("batches", 20, None, "batch means for the bias's type A uncertainty",
                              minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        T = parse_quantity(options.get("temperature", self.options[0].default), dimension="degC")
        Tc = float(T.to("degC").magnitude)
        return [Step(f"{self.kind}", self.kind,
                     f"chamber to {Tc:+g} °C at ≤ 1 °C/min, soak ≥ 2 h; record 1 h at τ = 1 s (IRA "
                     f"up) ({self.clause}.2 a), b))", Q_(1, "h"), Q_(1, "s"),
                     {"orientation": "IRA up", "temperature": f"{Tc:g} degC"}, warmup=Q_(2, "h"))]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg = need_segments(campaign, self.kind,
                            f"{self.qualified_id()} needs a segment of kind \"{self.kind}\" (1 h "
                            f"at the {self.word} temperature after the soak, conditions "
                            "orientation and temperature); none found", self.item)[0]
        T = seg.condition("temperature", "degC")
        est = segment_bias(seg, campaign, int(opts["batches"]))
        m = self.metrics
        results, warnings = [], []
        r, w = _condition_result(m[0], T, campaign.equipment_for("chamber"), campaign,
                                 prop="uniformity",
                                 what="chamber temperature")
        results.append(r)
        warnings += w
        results.append(Result(m[1], Q_(est.B0, "deg/h"), est.budget.combined,
                              UncertaintyBudget(m[1].symbol, "deg/h", est.budget.rows,
                                                coverage=COVERAGE),
                              note=msg("earth rate {earth:+.4f} °/h removed ({orientation})",
                                       earth=est.earth,
                                       orientation=est.orientation), earth_rate="removed"))
        raw = np.asarray(est.series.data.magnitude, dtype=float)
        tau0 = float(est.series.interval.to("s").magnitude)
        conv = est.conv
        for metric, t_s in ((m[2], 10.0), (m[3], 100.0)):
            factor = t_s / tau0
            if abs(factor - round(factor)) > 1e-9 or round(factor) < 1:
                raise DataError(seg.file or f"segment {seg.id}", "sample_interval",
                                f"t = {t_s:g} s is not a whole number of sampling intervals τ = "
                                f"{tau0:g} s (D.5.2)")
            if raw.size // int(round(factor)) < 3:
                raise DataError(seg.file or f"segment {seg.id}", "output",
                                f"the record gives fewer than 3 values of t = {t_s:g} s; D.41 "
                                f"needs at least 3",
                                hint=f"{self.clause}.2 b) asks for 1 h")
            sd, mm = allan.block_std(raw, int(round(factor)))
            Bs = sd * conv.magnitude
            rows = [BudgetRow.type_a(msg("sampling of the standard deviation of {m} values", m=mm),
                                     "B_s/√(2(m−1))",
                                     Q_(Bs / math.sqrt(2 * (mm - 1)), "deg/h"), mm - 1)]
            rows += scale_factor_row(conv, Bs, "deg/h")
            rows += timebase_row(campaign, Bs, "deg/h", "B_s")
            budget = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
            results.append(Result(metric, Q_(Bs, "deg/h"), budget.combined, budget,
                                  note=f"m = {mm}", earth_rate="not applicable"))
        dur = est.series.duration.to("h")
        if dur < Q_(1, "h") * 0.999:
            warnings.append(msg("the record lasts {dur}; {clause}.2 b) asks for 1 h",
                                dur=f"{dur:~.3gP}", clause=self.clause))
        return Outcome(STANDARD, self.item, self.title, self.clause, results, warnings=warnings,
                       segments=[seg.id],
                       options=opts_text(opts))


def _temperature_metrics(tag: str, word: str, clause: str, row: str) -> tuple[Metric, ...]:
    return (
        Metric(f"T_{tag}", f"{word} operating temperature (table C.1 {row})", f"T_{tag}", "degC",
               f"{clause}.2", ""),
        Metric(f"B0_{tag}", f"bias at the {word} temperature", "B₀", "deg/h", f"{clause}.3",
               "D.40"),
        Metric(f"Bs_{tag}_10s", f"bias stability at the {word} temperature (t = 10 s)", "B_s(10 s)",
               "deg/h",
               f"{clause}.3", "D.41"),
        Metric(f"Bs_{tag}_100s", f"bias stability at the {word} temperature (t = 100 s)",
               "B_s(100 s)", "deg/h",
               f"{clause}.3", "D.41"),
    )


class LowTemperatureOperationD61(_TemperatureOperation, word="low", row="row 1",
                                 default="-55 °C", points="−45/−55/−20 °C"):
    """GB/T 45570—2025 D.6.1 低温工作试验 (low-temperature operation): after ≥ 2 h soak at the low
    temperature, 1 h of output processed by D.5.1 (B₀, eq. (D.40)) and D.5.2 (B_s, eq. (D.41),
    t = 10 s and 100 s) (D.6.1.3); the temperature T_low (table C.1 row 1) with the chamber's
    budget."""

    item = "D.6.1"
    clause = "D.6.1"
    title = "Low-temperature operation (低温工作)"


class HighTemperatureOperationD62(_TemperatureOperation, word="high", row="row 3",
                                  default="85 °C", points="+70/+85/+60 °C"):
    """GB/T 45570—2025 D.6.2 高温工作试验 (high-temperature operation): as D.6.1 at the high
    temperature (D.6.2.3: B₀ by eq. (D.40), B_s by eq. (D.41)); T_high is table C.1 row 3."""

    item = "D.6.2"
    clause = "D.6.2"
    title = "High-temperature operation (高温工作)"


# --------------------------------------------------------------------------------------------
# D.6.3 vibration, D.6.4 mechanical shock
# --------------------------------------------------------------------------------------------


def _phase_segments(proc: type[Procedure], campaign: Campaign, kind: str, axis: str,
                    phases: tuple[str, ...],
                    **conds: str) -> dict[str, Segment]:
    segs = [s for s in campaign.find_segments(kind)
            if str(s.conditions.get("axis", "")).upper() == axis
            and all(str(s.conditions.get(k, "")).lower() == v for k, v in conds.items())]
    found: dict[str, Segment] = {}
    for s in segs:
        ph = str(s.condition("phase")).lower()
        if ph in found:
            raise DataError(campaign.source, f"segments.{s.id}",
                            f"a second \"{ph}\" segment for axis {axis} "
                            f"({', '.join(f'{k} {v}' for k, v in conds.items()) or kind}); also "
                            f"{found[ph].id}")
        found[ph] = s
    missing = [p for p in phases if p not in found]
    if missing:
        what = ", ".join(f"{k} = {v}" for k, v in conds.items())
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs the {' and '.join(missing)} segment(s) of "
                        f"kind \"{kind}\" for axis {axis}{' (' + what + ')' if what else ''}; "
                        f"found phases: {', '.join(sorted(found)) or 'none'}",
                        hint=f"`metro plan --standard gbt45570 --item {proc.item}` lists the "
                             f"segments")
    return found


def _two_power_ons(campaign: Campaign, why: str) -> tuple[list[BudgetRow], str, bool]:
    """The turn-on scatter of a bias difference whose two records are power-ons of their own
    (D.6.3.2 c)
    endurance vibration and D.6.4.2 c) shock: the gyro is unpowered in between, and D.6.3.2 b) /
    D.6.4.2 b)
    power it on before): √2 × σ_on from the campaign's D.5.3 repeats (type A, the Satterthwaite ν of
    a
    variance difference) or from ``device.bias_repeatability`` (type B), as D.5.4 / D.5.5 take it
    (:func:`.repeatability.bias_turn_on`); with neither the result is not reportable
    (interpretations.md,
    "D.6.3 / D.6.4 — unpowered tests: before and after are two power-ons").  Returns (rows, reason,
    known)."""
    on = bias_turn_on(campaign, 20,
                      msg("the turn-on scatter is not known: before and after are two power-ons "
                          "({why}); "
                                    "record D.5.3's power-ons (static-repeat) in the campaign or "
                                    "state "
                                    "device.bias_repeatability", why=why))
    if not on.known:
        return [], on.note, False
    u = math.sqrt(2.0) * on.sigma
    if on.stated:
        return [BudgetRow.type_b(msg("turn-on scatter of the two power-ons: √2 × σ_on stated for "
                                     "the device{hint}",
                                     hint=hint(" (device.bias_repeatability)")),
                                 "√2·σ_on", Q_(u, "deg/h"), distribution="normal", k=1.0)], "", True
    return [BudgetRow.type_a(msg("power-on repeatability of {what} in each of the two records: √2 "
                                 "× one power-on's", what="B₀"),
                             "√2·σ_on", Q_(u, "deg/h"), on.nu,
                             note=msg("σ_on = {s:.4g} °/h of D.5.3 on this campaign (ν = {nu:.3g})",
                                      s=on.sigma,
                                      nu=on.nu))], "", True


def _delta_result(metric: Metric, eq: str, a: dict, b: dict, campaign: Campaign, value: float,
                  turn_on: tuple[list[BudgetRow], str, bool] = ([], "", True)) -> Result:
    """|B_a − B_b| (D.47/D.48) with its budget: the two means' batch scatter (A), scale factor, time
    base,
    and for records that are two power-ons, the turn-on scatter (``turn_on``:
    :func:`_two_power_ons`).
    ``value`` (the formula's |B_a − B_b|) is corrected for the bias of an absolute value of a noisy
    difference (:func:`metro.api.abs_change`, with the noise of those rows),
    ≥ 0."""
    uA = math.hypot(a["u"], b["u"])
    nu = uA**4 / (a["u"] ** 4 / a["nu"] + b["u"] ** 4 / b["nu"]) if uA > 0 else math.inf
    rows = [BudgetRow.type_a(msg("scatter of the two biases (batch means)"), "√(u²(B_a)+u²(B_b))",
                             Q_(uA, "deg/h"), nu,
                             note=msg("the earth-rate term of D.40 is common to both and cancels"))]
    uq = math.hypot(a.get("u_q", 0.0), b.get("u_q", 0.0))
    if uq > 0:
        rows.append(BudgetRow.type_b(msg("quantization of the two means (the D.5.1 rows)"),
                                     "√(u_q²(B_a)+u_q²(B_b))",
                                     Q_(uq, "deg/h"), distribution="normal", k=1.0,
                                     note=msg("±1 P over a record, or a rounded rate not dithered "
                                              "by the noise")))
    rows += turn_on[0]
    # D.47/D.48 take |B_a − B_b|: the absolute value of a noisy difference reads high where the
    # change is
    # near zero (a folded normal); corrected in closed form, the printed value kept in the note
    # (interpretations.md, "D.5.5 / D.6.3 / D.6.4 — the absolute value of one noisy difference")
    from metro.api import abs_change, abs_change_note, abs_change_rows

    u_noise = math.sqrt(uA**2 + uq**2 + sum(r.standard_uncertainty.to("deg/h").magnitude ** 2
                                            for r in turn_on[0]))
    sel = abs_change(a["rate"] - b["rate"], u_noise)
    rows += abs_change_rows(sel, "deg/h", u_noise)
    value = max(sel.value, 0.0)
    rows += scale_factor_row(a["conv"], value, "deg/h")
    rows += timebase_row(campaign, value, "deg/h", metric.symbol)
    budget = UncertaintyBudget(metric.symbol, "deg/h", rows, coverage=COVERAGE)
    note = join("; ", [msg("eq. ({eq})", eq=eq)] + ([abs_change_note(sel, 1.0,
                                                                     "°/h")] if sel.bias else []))
    return Result(metric, Q_(value, "deg/h"), budget.combined, budget, note=note,
                  earth_rate="not applicable", reportable=turn_on[2], reason=turn_on[1])


#: the options D.6.3 and D.6.4 share: batch means of each bias, and D.5.3's power-ons (the
#: turn-on scatter of a difference of two power-ons)
_CHANGE_OPTIONS = (Option("batches", 10, None, "batch means per segment for the type A uncertainty",
                          minimum=2), REPEATS_OPTION)


def _vibration_metrics() -> tuple[Metric, ...]:
    out = [Metric("vib_perf_level", "performance vibration level (table C.1 row 8)", "a_rms", "gn",
                  "D.6.3.2", ""),
           Metric("vib_end_level", "endurance vibration level (table C.1 row 9)", "a_rms", "gn",
                  "D.6.3.2", "")]
    for ax in AXES:
        out += [Metric(f"dBV12_{ax}", f"bias change during performance vibration along {ax}",
                       "ΔB_V12", "deg/h",
                       "D.6.3.3", "D.47"),
                Metric(f"dBV13_{ax}", f"bias change after performance vibration along {ax}",
                       "ΔB_V13", "deg/h",
                       "D.6.3.3", "D.48"),
                Metric(f"dBV13end_{ax}", f"bias change after endurance vibration along {ax}",
                       "ΔB_V13", "deg/h",
                       "D.6.3.3", "D.48")]
    return tuple(out)


class VibrationD63(GbtItem):
    """GB/T 45570—2025 D.6.3 振动试验 (vibration), eqs. (D.47), (D.48).

    Along each of IRA, XRA, YRA: for performance vibration the biases before (B_01), during
    (B_02, sampled at 1 s) and after (B_03) by D.5.1, ΔB_V12 = |B_02 − B_01| (D.47) and
    ΔB_V13 = |B_03 − B_01| (D.48); for endurance vibration (unpowered while vibrating) ΔB_V13
    (D.48).  The biases are the mean indicated rates of D.40; its earth-rate term is common to
    the two segments of a difference and cancels.  Budget: the two biases' batch-means scatter
    (A), scale factor and time base (B).  The applied levels (g_rms, table C.1 rows 8 and 9; the
    smallest over the axes) carry the vibration table's calibration.
    """

    item = "D.6.3"
    title = "Vibration (振动试验)"
    clause = "D.6.3"
    metrics = _vibration_metrics()
    requires = (SegmentRequirement("vibration",
                                   "10 min before, during (performance only) and 10 min after the "
                                   "vibration along each axis", conditions={"axis": "", "test": "",
                                                                            "phase": "",
                                                                            "level": "gn"},
                                   columns={"output": OUTPUT_UNITS}, min_count=15),)
    equipment = (EquipmentRequirement("vibration_table",
                                      "vibration table (D.6.3.1 b)); its calibration (level) "
                                      "enters the level's budget"), COUNTER, PLATFORM)
    options = (
        Option("tests", "performance, endurance", None,
               "which vibration tests: performance, endurance"),
        Option("axes", "IRA, XRA, YRA", None, "axes along the vibration (D.6.3.2 e))"),
        Option("performance_level", "6.6 g", "gn",
               "performance vibration level, g_rms (product spec; table C.1 row 8)"),
        Option("endurance_level", "9 g", "gn",
               "endurance vibration level, g_rms (product spec; table C.1 row 9)"),
        Option("vibration_time", "10 min", "s", "vibration time per axis (product spec)"),
        *_CHANGE_OPTIONS,
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        vt = opts["vibration_time"]
        steps = []
        for ax in _names(opts["axes"], AXES, "axes"):
            orient = "IRA up" if ax == "IRA" else "IRA east"
            for test in _names(opts["tests"], ("performance", "endurance"), "tests"):
                lvl = opts[f"{test}_level"].to("gn").magnitude
                base = {"orientation": orient, "axis": ax, "test": test, "level": f"{lvl:g} gn"}
                steps.append(Step(f"vib-{test[:4]}-{ax}-before", "vibration",
                                  f"{ax} along the vibration; warm up 10 min, record 10 min before "
                                  f"{test} vibration "
                                  "(D.6.3.2 b))", Q_(10, "min"), Q_(1, "s"),
                                  base | {"phase": "before"},
                                  warmup=Q_(10, "min")))
                if test == "performance":
                    steps.append(Step(f"vib-perf-{ax}-during", "vibration",
                                      f"{lvl:g} g_rms along {ax}, powered, sampled at 1 s (D.6.3.2 "
                                      f"c))", vt,
                                      Q_(1, "s"), base | {"phase": "during"}))
                steps.append(Step(f"vib-{test[:4]}-{ax}-after", "vibration",
                                  f"after {test} vibration ({lvl:g} "
                                  f"g_rms{', unpowered' if test == 'endurance' else ''}):"
                                  " record 10 min (D.6.3.2 d))", Q_(10, "min"), Q_(1, "s"),
                                  base | {"phase": "after"}))
        # endurance vibration is unpowered: its before/after are two power-ons, whose turn-on
        # scatter D.5.3 measures
        if "endurance" in _names(opts["tests"], ("performance", "endurance"), "tests"):
            steps += repeat_steps(options)
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        tests = _names(opts["tests"], ("performance", "endurance"), "tests")
        axes = _names(opts["axes"], AXES, "axes")
        b = int(opts["batches"])
        byk = {m.key: m for m in self.metrics}
        results, warnings, used, table = [], [], [], []
        levels: dict[str, list[float]] = {t: [] for t in tests}
        on_end = None
        for ax in axes:
            for test in tests:
                phases = ("before", "during", "after") if test == "performance" else ("before",
                                                                                      "after")
                segs = _phase_segments(type(self), campaign, "vibration", ax, phases, test=test)
                if test == "endurance" and "during" in segs:
                    warnings.append(msg("a \"during\" segment of endurance vibration along {axis} "
                                        "is ignored (D.6.3.2 c): "
                                        "the gyro is not powered)", axis=ax))
                means = {p: mean_rate(segs[p], campaign, b) for p in phases}
                levels[test].append(float(segs["before"].condition("level",
                                                                   "gn").to("gn").magnitude))
                used += [segs[p].id for p in phases]
                if test == "performance":
                    v12 = E.bias_change_d47(means["during"]["rate"], means["before"]["rate"])
                    v13 = E.bias_change_d48(means["after"]["rate"], means["before"]["rate"])
                    results.append(_delta_result(byk[f"dBV12_{ax}"], "D.47", means["during"],
                                                 means["before"],
                                                 campaign, v12))
                    results.append(_delta_result(byk[f"dBV13_{ax}"], "D.48", means["after"],
                                                 means["before"],
                                                 campaign, v13))
                else:
                    v13 = E.bias_change_d48(means["after"]["rate"], means["before"]["rate"])
                    if on_end is None:
                        on_end = _two_power_ons(campaign,
                                                msg("unpowered during endurance vibration, D.6.3.2 "
                                                    "c)"))
                    results.append(_delta_result(byk[f"dBV13end_{ax}"], "D.48", means["after"],
                                                 means["before"],
                                                 campaign, v13, on_end))
                table.append([ax, test] + [f"{means[p]['rate']:.5f}" if p in means else "—"
                                           for p in ("before", "during", "after")])
        table_eq = campaign.equipment_for("vibration_table")
        for test in tests:
            key = "vib_perf_level" if test == "performance" else "vib_end_level"
            r, w = _condition_result(byk[key], Q_(min(levels[test]), "gn"), table_eq, campaign,
                                     prop="level_accuracy",
                                     what="vibration level")
            results.insert(0 if test == "performance" else 1, r)
            warnings += w
        tab = TableSpec("vibration_biases",
                        msg("Mean indicated rate before, during and after vibration (°/h)"),
                        [msg("axis"), msg("test"), msg("before B₀₁"), msg("during B₀₂"),
                         msg("after B₀₃")], table)
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[tab],
                       warnings=warnings,
                       segments=used, options=opts_text(opts))


def _shock_metrics() -> tuple[Metric, ...]:
    out = [Metric("shock_level", "mechanical shock peak level (table C.1 row 10)", "a_p", "gn",
                  "D.6.4.2", ""),
           Metric("shock_duration", "mechanical shock pulse duration (table C.1 row 10)", "t_p",
                  "ms", "D.6.4.2", "")]
    for ax in AXES:
        out.append(Metric(f"dBshock_{ax}", f"bias change after mechanical shock along {ax}",
                          "ΔB_V13", "deg/h",
                          "D.6.4.3", "D.48"))
    return tuple(out)


class MechanicalShockD64(GbtItem):
    """GB/T 45570—2025 D.6.4 机械冲击试验 (mechanical shock), eq. (D.48).

    Along each of IRA, XRA, YRA the biases before and after the (unpowered) shocks by D.5.1 and
    ΔB_V13 = |B_03 − B_01| (D.48, as D.6.4.3 directs).  Budget as D.6.3.  The applied peak level
    (g) and pulse duration (ms) of table C.1 row 10 (the smallest over the axes) carry the shock
    table's calibration and its duration accuracy.
    """

    item = "D.6.4"
    title = "Mechanical shock (机械冲击试验)"
    clause = "D.6.4"
    metrics = _shock_metrics()
    requires = (SegmentRequirement("shock",
                                   "10 min before and 10 min after the shocks along each axis",
                                   conditions={"axis": "", "phase": "", "level": "gn",
                                               "pulse": "ms"},
                                   columns={"output": OUTPUT_UNITS}, min_count=6),)
    equipment = (EquipmentRequirement("shock_table",
                                      "shock table (D.6.4.1 b)); its calibration (peak level) and "
                                      "property duration_accuracy enter the budgets"), COUNTER,
                 PLATFORM)
    options = (
        Option("axes", "IRA, XRA, YRA", None, "axes along the shock (D.6.4.2 e))"),
        Option("level", "40 g", "gn", "peak acceleration (product spec; table C.1 row 10)"),
        Option("pulse", "20 ms", "ms", "pulse duration (product spec; table C.1 row 10)"),
        *_CHANGE_OPTIONS,
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        lvl = opts["level"].to("gn").magnitude
        dur = opts["pulse"].to("ms").magnitude
        steps = []
        for ax in _names(opts["axes"], AXES, "axes"):
            base = {"orientation": "IRA up" if ax == "IRA" else "IRA east", "axis": ax,
                    "level": f"{lvl:g} gn",
                    "pulse": f"{dur:g} ms"}
            steps.append(Step(f"shock-{ax}-before", "shock",
                              f"{ax} along the shock; warm up 10 min, record 10 min "
                              "(D.6.4.2 b))", Q_(10, "min"), Q_(1, "s"), base | {"phase": "before"},
                              warmup=Q_(10, "min")))
            steps.append(Step(f"shock-{ax}-after", "shock",
                              f"unpowered shocks of {lvl:g} g, {dur:g} ms along {ax}; "
                              "then record 10 min (D.6.4.2 c), d))", Q_(10, "min"), Q_(1, "s"),
                              base | {"phase": "after"}))
        # unpowered shocks: before/after are two power-ons, whose turn-on scatter D.5.3 measures
        return steps + repeat_steps(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        b = int(opts["batches"])
        byk = {m.key: m for m in self.metrics}
        results, warnings, used, table, lv, pl = [], [], [], [], [], []
        on = _two_power_ons(campaign, msg("unpowered during the shocks, D.6.4.2 c)"))
        for ax in _names(opts["axes"], AXES, "axes"):
            segs = _phase_segments(type(self), campaign, "shock", ax, ("before", "after"))
            means = {p: mean_rate(segs[p], campaign, b) for p in ("before", "after")}
            lv.append(float(segs["after"].condition("level", "gn").to("gn").magnitude))
            pl.append(float(segs["after"].condition("pulse", "ms").to("ms").magnitude))
            v = E.bias_change_d48(means["after"]["rate"], means["before"]["rate"])
            results.append(_delta_result(byk[f"dBshock_{ax}"], "D.48", means["after"],
                                         means["before"], campaign, v, on))
            used += [segs["before"].id, segs["after"].id]
            table.append([ax, f"{means['before']['rate']:.5f}", f"{means['after']['rate']:.5f}",
                          f"{v:.5f}"])
        eq = campaign.equipment_for("shock_table")
        r1, w1 = _condition_result(byk["shock_level"], Q_(min(lv), "gn"), eq, campaign,
                                   what="shock peak level")
        r2, w2 = _condition_result(byk["shock_duration"], Q_(min(pl), "ms"),
                                   None if eq is None else _no_cal(eq),
                                   campaign, prop="duration_accuracy", what="shock pulse duration")
        tab = TableSpec("shock_biases",
                        msg("Mean indicated rate before and after the shocks (°/h)"),
                        [msg("axis"), msg("before B₀₁"), msg("after B₀₃"), "ΔB_V13"], table)
        return Outcome(STANDARD, self.item, self.title, self.clause, [r1, r2] + results,
                       tables=[tab],
                       warnings=warnings + w1 + w2, segments=used, options=opts_text(opts))


def _no_cal(eq):
    """The equipment without its calibration (whose uncertainty is that of the level, not the
    duration)."""
    import attrs

    return attrs.evolve(eq, calibration=None)


PROCEDURES = (LowTemperatureOperationD61, HighTemperatureOperationD62, VibrationD63,
              MechanicalShockD64,
              SetupTime6277, PowerConsumption6278)

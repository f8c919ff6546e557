"""GB/T 45570—2025 5.2.3–5.2.8 inspection items, from the campaign's ``[inspection]`` record:

* 6.2.1 appearance (5.2.3 a)–d)) — the visual checklist under normal lighting;
* 6.2.2 dimensions (5.2.4) — each dimension's readings against its nominal and tolerance from the
  product specification, and the tolerance's grade against IT12 (GB/T 1800.1);
* 6.2.3 mass (5.2.5) — readings on an electronic balance, cables, connectors and screws included
  when they are delivered with the gyro;
* 5.2.6 supply requirements — the product specification states voltage type and accuracy, current
  and power (and, where measured, the supply voltages lie within it);
* 6.2.4 interfaces (5.2.7.1 mechanical, 5.2.7.2 electrical: RS-422/RS-485, output content);
* 6.2.5 insulation resistance (5.2.8 ≥ 50 MΩ) per terminal pair, non-operating, with a megohmmeter.

A measured value carries its budget: the instrument's calibration U (absolute or relative), the
resolution of its indication (uniform, d/2) and, for repeated readings, their scatter (type A,
s/√n, ν = n − 1).  A checklist gives the count of requirements not met (exact), which must be 0.
"""

from __future__ import annotations

import math
import re
from typing import Mapping

import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, Comparison, DataError, EquipmentRequirement, Metric,
                       Outcome, Result, RunContext, Specification, TableSpec,
                       UncertaintyBudget, join, msg, parse_limit)

from . import records as R
from .common import COVERAGE, STANDARD
from .conformity import clause_source, product_source

SECTION = "inspection"
INSULATION_MIN = Q_(50, "Mohm")
GE, LE, RANGE = Comparison.AT_LEAST, Comparison.AT_MOST, Comparison.RANGE

#: GB/T 1800.1—2020 table 1, standard tolerance IT12 (mm) for nominal sizes (upper bound of the
#: range, mm)
IT12_MM = ((3, 0.10), (6, 0.12), (10, 0.15), (18, 0.18), (30, 0.21), (50, 0.25), (80, 0.30), (120,
                                                                                              0.35),
           (180, 0.40), (250, 0.46), (315, 0.52), (400, 0.57), (500, 0.63), (630, 0.70), (800,
                                                                                          0.80),
           (1000, 0.90))


def it12(nominal_mm: float) -> float:
    """IT12 (mm) for a nominal size (mm), GB/T 1800.1—2020 table 1 (ranges 'above … up to and
    including')."""
    if not 0 < nominal_mm <= IT12_MM[-1][0]:
        raise ValueError(f"nominal size {nominal_mm:g} mm is outside 0 … {IT12_MM[-1][0]} mm of "
                         f"the table")
    for upper, value in IT12_MM:
        if nominal_mm <= upper:
            return value
    raise AssertionError  # pragma: no cover


def mean_and_type_a(values: np.ndarray) -> tuple[float, float, int]:
    """Mean, the standard uncertainty of the mean s/√n (JJF 1059.1, type A) and ν = n − 1; (x, 0, 0)
    for n = 1."""
    n = values.size
    if n == 1:
        return float(values[0]), 0.0, 0
    return float(np.mean(values)), float(np.std(values, ddof=1)) / math.sqrt(n), n - 1


def _exact(symbol: str, unit: str, what: str) -> UncertaintyBudget:
    return UncertaintyBudget(symbol, unit, [BudgetRow.type_b(what, f"u({symbol})", Q_(0.0, unit),
                                                             distribution="uniform")],
                             coverage=COVERAGE)


def _count_result(metric: Metric, failed: list[str], what: str) -> Result:
    b = _exact(metric.symbol, "", msg("{what}: observed answers, a count (exact)", what=what))
    return R.na_result(metric, Q_(float(len(failed)), ""), b.combined, b,
                  note=msg("not met: {failed}", failed=join("; ",
                                                            failed)) if failed else msg("all met"))


def _beyond(shown: str, below: bool, bound: float):
    """A megohmmeter reading beyond its range: only the inequality is known."""
    if below:
        return msg("the megohmmeter shows {shown} (below its range): R < {bound:g} MΩ, not a "
                   "measured value",
                   shown=shown, bound=bound)
    return msg("the megohmmeter shows {shown} (over its range): R > {bound:g} MΩ, not a measured "
               "value",
               shown=shown, bound=bound)


def measured_result(metric: Metric, readings: list, eq, campaign: Campaign, *,
                    note: str = "") -> Result:
    """Mean of repeated readings with its budget: repeatability (A), calibration (B), resolution
    (B)."""
    unit = metric.unit
    vals = np.array([float(q.to(unit).magnitude) for q in readings])
    x, uA, nu = mean_and_type_a(vals)
    rows = []
    if nu > 0:
        rows.append(BudgetRow.type_a(msg("repeatability of {n} readings", n=vals.size), "s/√n",
                                     Q_(uA, unit), nu))
    rows.append(R.calibration_row(eq, f"u_cal({metric.symbol})", Q_(x, unit), unit))
    rows += R.resolution_row(eq, f"δ({metric.symbol})", unit, R.where_of(campaign))
    b = UncertaintyBudget(metric.symbol, unit, rows, coverage=COVERAGE)
    parts = [p for p in (note,
                         "" if nu > 0 else msg("one reading: repeatability not evaluated")) if p]
    return R.na_result(metric, Q_(x, unit), b.combined, b, note=join("; ", parts) if parts else "")


def _key(name: str) -> str:
    k = re.sub(r"[^0-9A-Za-z]+", "_", name).strip("_")
    if not k:
        raise ValueError(name)
    return k


class _Inspection(R.InspectionRecord):
    def _outcome(self, results, *, tables=(), warnings=()) -> Outcome:
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=tables,
                       warnings=warnings)


# ---------------------------------------------------------------------------------------- 5.2.3


class Appearance621(_Inspection):
    """GB/T 45570—2025 5.2.3 外观质量 by 6.2.1: visual inspection under normal lighting (against a
    reference sample where needed), checklist a) clean surface, no cracks, dents, burrs, marked
    scratches, rust, coating intact; b) fasteners and connectors tight; c) marks legible, in a
    visible
    place, no missing characters; d) connectors undamaged, with protective caps, insulation
    intact."""

    item = "6.2.1"
    clause = "5.2.3"
    title = "Appearance (外观质量)"
    path = "appearance"
    metrics = (Metric("appearance_nc", "appearance requirements a)–d) not met", "n_nc", "",
                      "5.2.3"),)
    CHECKS = {"a": "surface clean, no cracks/dents/burrs/marked scratches, no rust, coating intact",
              "b": "fasteners and connectors tight",
              "c": "marks legible, visible, no missing characters",
              "d": "electrical connectors undamaged, capped, insulation intact"}

    step = ("visual inspection under normal lighting (6.2.1): answer the "
            "checklist a)–d) of 5.2.3")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.3")
        answers = {k: R.answer(rec, k, src, where) for k in self.CHECKS}
        failed = [f"{k}) {self.CHECKS[k]}" for k, ok in answers.items() if not ok]
        tab = TableSpec("appearance", "Appearance checklist (5.2.3)", ["", "requirement",
                                                                       "observed"],
                        [[f"{k})", t, "met" if answers[k] else "NOT MET"] for k,
                         t in self.CHECKS.items()])
        warnings = [] if "lighting" in rec else ["the lighting of the inspection is not recorded "
                                                 "(6.2.1: normal lighting)"]
        return self._outcome([_count_result(self.metrics[0], failed, "checklist a)–d)")],
                             tables=[tab],
                             warnings=warnings)


# ---------------------------------------------------------------------------------------- 5.2.4


def dimension_records(campaign: Campaign) -> list[tuple[str, Mapping, str]]:
    rows = R.section(campaign, f"{SECTION}.dimensions", "5.2.4", kind=list)
    src = R.where_of(campaign)
    out, seen = [], set()
    for i, d in enumerate(rows):
        where = f"{SECTION}.dimensions[{i}]"
        if not isinstance(d, Mapping):
            raise DataError(src, where, "must be a table ([[inspection.dimensions]])")
        name = R.text(d, "name", src, where)
        try:
            key = _key(name)
        except ValueError:
            raise DataError(src, f"{where}.name", f"{name!r} has no letters or digits") from None
        if key in seen:
            raise DataError(src, f"{where}.name", f"a second dimension named {name!r}")
        seen.add(key)
        out.append((key, d, where))
    return out


def tolerance_of(d: Mapping, src: str, where: str):
    """(nominal, lower deviation, upper deviation) of a dimension record: ``tolerance = "± 0.1 mm"``
    or ``upper``/``lower`` deviations (``"+0.1 mm"``, ``"-0.05 mm"``)."""
    nominal = R.quantity(d.get("nominal"), "mm", src, f"{where}.nominal")
    if "tolerance" in d:
        t = str(d["tolerance"]).strip()
        if not t.startswith(("±", "+-", "+/-")):
            raise DataError(src, f"{where}.tolerance",
                            f"write \"± 0.1 mm\" or give upper and lower deviations, got {t!r}")
        half = R.quantity(t.lstrip("±+-/ "), "mm", src, f"{where}.tolerance")
        lo, hi = -abs(half), abs(half)
    else:
        if "upper" not in d or "lower" not in d:
            raise DataError(src, f"{where}.tolerance",
                            "missing: give tolerance = \"± … mm\" or upper and lower "
                            "deviations from the product specification")
        hi = R.quantity(d["upper"], "mm", src, f"{where}.upper")
        lo = R.quantity(d["lower"], "mm", src, f"{where}.lower")
        if not hi > lo:
            raise DataError(src, f"{where}.upper",
                            f"the upper deviation {hi:~P} is not above the lower {lo:~P}")
    return nominal, lo, hi


def dimension_specifications(campaign: Campaign) -> list[Specification]:
    """Each dimension within nominal + lower … nominal + upper (product specification) and its
    tolerance zone at most IT12 wide (5.2.4, GB/T 1800.1)."""
    if not R.has(campaign, f"{SECTION}.dimensions"):
        return []
    src = R.where_of(campaign)
    out = []
    for key, d, where in dimension_records(campaign):
        nominal, lo, hi = tolerance_of(d, src, where)
        out.append(Specification(f"dim_{key}", RANGE, (nominal + lo).to("mm"),
                                 (nominal + hi).to("mm"),
                                 source=product_source(msg("{where}: nominal {nominal}, {lo}/{hi}",
                                                           where=where, nominal=f"{nominal:~P}",
                                                                    lo=f"{lo:+~P}",
                                                           hi=f"{hi:+~P}")),
                                 name=msg("dimension {name}", name=d['name']), items=("6.2.2",)))
        out.append(
            Specification(
                f"itgrade_{key}",
                LE,
                Q_(1.0, ""),
                source=clause_source(
                    "5.2.4", msg("tolerance grade not above IT12, GB/T 1800.1—2020 table 1")
                ),
                name=f"tolerance of {d['name']} / IT12",
                items=("6.2.2",),
            )
        )
    return out


class Dimensions622(_Inspection):
    """GB/T 45570—2025 5.2.4 外形尺寸 by 6.2.2: each dimension measured with a gauge (callipers) and
    judged against the product specification's nominal and tolerance; the tolerance zone (upper −
    lower deviation) must not exceed IT12 for the nominal size (GB/T 1800.1—2020 table 1), reported
    as the ratio tolerance/IT12 ≤ 1 (exact: both are specification values)."""

    item = "6.2.2"
    clause = "5.2.4"
    title = "Dimensions (外形尺寸)"
    path = "dimensions"
    equipment = (EquipmentRequirement("calliper",
                                      "callipers or other gauge (6.2.2); its calibration and "
                                      "resolution enter each dimension's budget", required=True),)
    metrics = (Metric("dim", "dimension", "l", "mm", "5.2.4"),
               Metric("itgrade", "tolerance zone over IT12", "T/IT12", "", "5.2.4"))

    step = ("measure each outline dimension of the product specification with "
            "callipers (6.2.2), repeated readings; record nominal and tolerance")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src = R.where_of(campaign)
        recs = dimension_records(campaign)
        eq = R.equipment(campaign, "calliper", "5.2.4", "the dimensions")
        results, table = [], []
        for key, d, where in recs:
            nominal, lo, hi = tolerance_of(d, src, where)
            vals = R.readings(d, "readings", "mm", src, where)
            m = Metric(f"dim_{key}", msg("dimension {name}", name=d['name']), "l", "mm", "5.2.4")
            results.append(measured_result(m, vals, eq, campaign,
                                           note=msg("nominal {nominal} {tol}",
                                                    nominal=f"{nominal:~P}",
                                                    tol=f"{lo:+~P}/{hi:+~P}")))
            nom = float(nominal.to("mm").magnitude)
            try:
                it = it12(nom)
            except ValueError as exc:
                raise DataError(src, f"{where}.nominal", str(exc)) from exc
            width = float((hi - lo).to("mm").magnitude)
            g = Metric(f"itgrade_{key}", msg("tolerance zone of {name} over IT12", name=d['name']),
                       "T/IT12", "", "5.2.4")
            b = _exact("T/IT12", "", "tolerance and IT12 are specification values (exact)")
            results.append(R.na_result(g, Q_(width / it, ""), b.combined, b,
                                  note=msg("T = {T:g} mm, IT12 = {it:g} mm at {nom:g} mm (GB/T "
                                           "1800.1 table 1)", T=width,
                                           it=it, nom=nom)))
            table.append([str(d["name"]), f"{nominal:~P}", f"{lo:+~P} / {hi:+~P}", f"{it:g} mm",
                          ", ".join(f"{v.to('mm').magnitude:g}" for v in vals)])
        tab = TableSpec("dimensions", "Dimensions (5.2.4): specification and readings (mm)",
                        ["dimension", "nominal", "deviations", "IT12", "readings (mm)"], table)
        return self._outcome(results, tables=[tab])


# ---------------------------------------------------------------------------------------- 5.2.5


def mass_specifications(campaign: Campaign) -> list[Specification]:
    """The product specification's mass limit written in the record (``limit = "<= 1.3 kg"``)."""
    if not R.has(campaign, f"{SECTION}.mass"):
        return []
    rec = R.section(campaign, f"{SECTION}.mass", "5.2.5")
    if "limit" not in rec:
        return []
    spec = parse_limit("mass", str(rec["limit"]), source=product_source(f"{SECTION}.mass.limit"),
                       file=R.where_of(campaign), field=f"{SECTION}.mass.limit")
    from metro.api import check_dimension

    check_dimension(spec.limit, "kg", file=R.where_of(campaign), field=f"{SECTION}.mass.limit")
    return [spec]


class Mass623(_Inspection):
    """GB/T 45570—2025 5.2.5 重量 by 6.2.3: the gyro weighed on an electronic balance, with the
    cables,
    connectors and mounting screws delivered as part of it (5.2.5, second paragraph).  Budget:
    repeatability of the readings (A), the balance's calibration and resolution (B)."""

    item = "6.2.3"
    clause = "5.2.5"
    title = "Mass (重量)"
    path = "mass"
    equipment = (EquipmentRequirement("balance",
                                      "electronic balance (6.2.3); its calibration and resolution "
                                      "enter the budget", required=True),)
    metrics = (Metric("mass", "mass as delivered", "m", "g", "5.2.5"),)

    step = ("weigh the gyro on the electronic balance (6.2.3) with the "
            "cables, connectors and screws delivered with it; repeated readings")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.5")
        vals = R.readings(rec, "readings", "kg", src, where)
        delivered = _names(rec, "delivered_with", src, where)
        included = _names(rec, "includes", src, where)
        left_out = [p for p in delivered if p not in included]
        if left_out:
            raise DataError(src, f"{where}.includes",
                            "5.2.5: parts delivered as part of the gyro are weighed with it; "
                            f"the record leaves out {', '.join(left_out)}",
                            hint="weigh again with them, or correct delivered_with")
        eq = R.equipment(campaign, "balance", "5.2.5", "the mass")
        note = (
            msg("weighed with {what}", what=join(", ", included))
            if included
            else msg("weighed with the gyro alone")
        )
        res = measured_result(self.metrics[0], vals, eq, campaign, note=note)
        warnings = [] if mass_specifications(campaign) or "mass" in campaign.specification else [
            "no mass limit given (record limit or [specification] mass): by product specification, "
            "not judged"]
        return self._outcome([res], warnings=warnings)


def _names(rec: Mapping, key: str, src: str, where: str) -> list[str]:
    v = rec.get(key, [])
    if isinstance(v, str):
        v = [v]
    if not isinstance(v, list) or not all(isinstance(x, str) for x in v):
        raise DataError(src, f"{where}.{key}", f"must be a list of part names, got {v!r}")
    return [x.strip().lower() for x in v]


# ---------------------------------------------------------------------------------------- 5.2.6


class Supply526(_Inspection):
    """GB/T 45570—2025 5.2.6 供电要求: the product specification states the supply voltage's kind
    and
    accuracy, the current and the power.  Each ``[[inspection.supply.rails]]`` gives the nominal
    voltage, its tolerance and the current; the record the kind (``voltage_type``) and the power.
    Where the voltage at the gyro was measured (``readings``, with a voltmeter) it is judged against
    nominal ± tolerance."""

    item = "5.2.6"
    clause = "5.2.6"
    title = "Supply requirements (供电要求)"
    path = "supply"
    equipment = (EquipmentRequirement("voltmeter",
                                      "voltage measuring equipment for the voltages measured at "
                                      "the gyro (5.2.6); its calibration enters their budget"),)
    metrics = (Metric("supply_missing", "supply requirements the specification does not state", "n",
                      "", "5.2.6"),
               Metric("supply_V", "supply voltage at the gyro", "U", "V", "5.2.6"))

    step = ("check that the product specification states voltage kind and "
            "accuracy, current and power for each supply (5.2.6); measure the "
            "voltages at the gyro")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.6")
        missing = []
        if not str(rec.get("voltage_type", "")).strip():
            missing.append("voltage kind (voltage_type)")
        if "power" in rec:
            R.quantity(rec["power"], "W", src, f"{where}.power")
        else:
            missing.append("power")
        rails = rec.get("rails", [])
        if isinstance(rails, Mapping):
            rails = [rails]
        if not rails:
            missing.append("supply rails (nominal voltage, accuracy, current)")
        results, table, eq = [], [], None
        for i, rail in enumerate(rails):
            w = f"{where}.rails[{i}]"
            if not isinstance(rail, Mapping):
                raise DataError(src, w, "must be a table")
            nominal = R.quantity(rail.get("nominal"), "V", src, f"{w}.nominal")
            tol = None
            if "tolerance" in rail:
                t = str(rail["tolerance"]).strip().lstrip("±+-/ ")
                tol = R.quantity(t, "", src, f"{w}.tolerance") if "%" in t else R.quantity(t, "V",
                                                                                           src,
                                                                                           f"{w}.tolerance")
                tol = abs(nominal) * tol.to("") if tol.dimensionless else tol.to("V")
            else:
                missing.append(f"accuracy of the {nominal:~P} supply")
            if "current" in rail:
                R.quantity(rail["current"], "A", src, f"{w}.current")
            else:
                missing.append(f"current of the {nominal:~P} supply")
            cell = "—"
            if "readings" in rail:
                if tol is None:
                    raise DataError(src, f"{w}.tolerance",
                                    "a measured supply voltage needs the tolerance to be judged")
                eq = eq or R.equipment(campaign, "voltmeter", "5.2.6", "the supply voltages")
                vals = R.readings(rail, "readings", "V", src, w)
                key = _rail_key(nominal)
                m = Metric(f"supply_V_{key}", msg("voltage of the {nominal} supply at the gyro",
                                                  nominal=f"{nominal:~P}"), "U",
                           "V", "5.2.6")
                results.append(measured_result(m, vals, eq, campaign,
                                               note=msg("nominal {nominal} ± {tol}",
                                                        nominal=f"{nominal:~P}", tol=f"{tol:~P}")))
                cell = f"{results[-1].value:.4g~P}"
            table.append([f"{nominal:~P}", f"± {tol:~P}" if tol is not None else "not stated",
                          str(rail.get("current", "not stated")), cell])
        m0 = self.metrics[0]
        results.insert(0, _count_result(m0, missing, "statements of the product specification"))
        tab = TableSpec("supply", msg("Supply requirements (5.2.6): {kind}, power {power}",
                                      kind=rec.get("voltage_type") or msg("kind not stated"),
                                      power=rec.get("power") or msg("not stated")),
                        ["nominal", "accuracy", "current", "measured"], table)
        return self._outcome(results, tables=[tab])


def supply_specifications(campaign: Campaign) -> list[Specification]:
    if not R.has(campaign, f"{SECTION}.supply"):
        return []
    rec, src = R.section(campaign, f"{SECTION}.supply", "5.2.6"), R.where_of(campaign)
    rails = rec.get("rails", [])
    out = []
    for i, rail in enumerate([rails] if isinstance(rails, Mapping) else rails):
        if not isinstance(rail, Mapping) or "readings" not in rail or "tolerance" not in rail:
            continue
        w = f"{SECTION}.supply.rails[{i}]"
        nominal = R.quantity(rail.get("nominal"), "V", src, f"{w}.nominal")
        t = str(rail["tolerance"]).strip().lstrip("±+-/ ")
        tol = R.quantity(t, "", src, f"{w}.tolerance") if "%" in t else R.quantity(t, "V", src,
                                                                                   f"{w}.tolerance")
        tol = abs(nominal) * tol.to("") if tol.dimensionless else tol.to("V")
        key = _rail_key(nominal)
        lo, hi = sorted([(nominal - tol).to("V"), (nominal + tol).to("V")],
                        key=lambda q: q.magnitude)
        out.append(Specification(f"supply_V_{key}", RANGE, lo, hi, source=product_source(w),
                                 name=f"{nominal:~P} supply", items=("5.2.6",)))
    return out


def _rail_key(nominal) -> str:
    v = float(nominal.to("V").magnitude)
    return ("m" if v < 0 else "") + _key(f"{abs(v):g}V")


# ---------------------------------------------------------------------------------------- 5.2.7


class Interfaces624(_Inspection):
    """GB/T 45570—2025 5.2.7 接口 by 6.2.4: 5.2.7.1 mechanical interface per the product
    specification
    (measured with suitable gauges, 6.2.4.1); the mounting face *should* (宜) be perpendicular to
    the
    input axis — a "no" is noted, not a nonconformity; 5.2.7.2 electrical interface and protocol per
    the product specification (6.2.4.2); the communication interface is *generally* (一般)
    RS-422/RS-485
    — another is noted; the output *shall* contain angle or rate information and detection
    information
    (generally electrical parameters, temperature and status word)."""

    item = "6.2.4"
    clause = "5.2.7"
    title = "Mechanical and electrical interfaces (接口)"
    path = "interfaces"
    metrics = (Metric("mech_interface_nc", "mechanical interface requirements not met", "n_m", "",
                      "5.2.7.1"),
               Metric("elec_interface_nc", "electrical interface requirements not met", "n_e", "",
                      "5.2.7.2"))
    RATE_WORDS = {"angle", "rate", "angular rate", "angular increment", "角度", "角速度"}
    DETECTION = {"voltage": "electrical", "current": "electrical", "electrical": "electrical",
                 "temperature": "temperature",
                 "status": "status", "status word": "status", "电参量": "electrical",
                 "温度": "temperature", "状态字": "status"}

    step = ("check the mechanical interface with gauges (6.2.4.1) and the "
            "electrical interface, protocol and output frame content (6.2.4.2) "
            "against the product specification")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.7")
        warnings, mech, elec = [], [], []
        if not R.answer(rec, "mechanical_per_specification", src, where):
            mech.append("mechanical interface not as the product specification")
        if "mounting_face_perpendicular" in rec and not R.answer(rec, "mounting_face_perpendicular",
                                                                 src, where):
            warnings.append(msg("5.2.7.1: the mounting face is not perpendicular to the input axis "
                                "(recommended, 宜)"))
        if not R.answer(rec, "electrical_per_specification", src, where):
            elec.append("electrical interface not as the product specification")
        if not R.answer(rec, "protocol_per_specification", src, where):
            elec.append("communication protocol not as the product specification")
        comm = R.text(rec, "communication", src, where).strip()
        if comm.upper().replace(" ", "") not in ("RS-422", "RS422", "RS-485", "RS485"):
            warnings.append(msg("5.2.7.2: communication interface {comm}; the standard names "
                                "RS-422/RS-485 as usual (一般)",
                                comm=repr(comm)))
        content = _names(rec, "output_content", src, where)
        if not content:
            raise DataError(src, f"{where}.output_content",
                            "missing: list what the output frame carries "
                            "(e.g. [\"rate\", \"temperature\", \"voltage\", \"status\"])")
        if not any(c in self.RATE_WORDS for c in content):
            elec.append("output carries no angle or rate information")
        kinds = {self.DETECTION[c] for c in content if c in self.DETECTION}
        if not kinds:
            elec.append("output carries no detection information (electrical parameters, "
                        "temperature, status word)")
        elif kinds != {"electrical", "temperature", "status"}:
            warnings.append("5.2.7.2: detection information lacks " + ", ".join(
                sorted({"electrical", "temperature",
                        "status"} - kinds)) + " (generally included, 一般)")
        m = self.metrics
        tab = TableSpec("interfaces", "Interfaces (5.2.7)", ["check", "observed"],
                        [["communication interface", comm], ["output content", ", ".join(content)],
                         ["mechanical", "; ".join(mech) or "as specified"], ["electrical",
                                                                             "; ".join(elec)
                                                                             or "as specified"]])
        return self._outcome(
            [
                _count_result(m[0], mech, "mechanical checks"),
                _count_result(m[1], elec, "electrical checks"),
            ],
            tables=[tab],
            warnings=warnings,
        )


# ---------------------------------------------------------------------------------------- 5.2.8


class Insulation625(_Inspection):
    """GB/T 45570—2025 5.2.8 绝缘电阻 ≥ 50 MΩ between mutually insulated terminals and between
    terminals and case, by 6.2.5: gyro not operating, the megohmmeter and measuring points of the
    relevant specification.  Per terminal pair: the readings' mean with the megohmmeter's
    calibration
    (relative or absolute), resolution and repeatability.  A reading beyond the megohmmeter's range
    is written as the instrument shows it: ``"> 10 GΩ"`` (over range) conforms when its bound is at
    least 50 MΩ; ``"< 1 MΩ"`` (below range) does not conform when its bound is below 50 MΩ; either
    bound on the wrong side of 50 MΩ says nothing and is an error (interpretations.md).  Such a
    pair's result is its bound, marked not reportable, judged exactly."""

    item = "6.2.5"
    clause = "5.2.8"
    title = "Insulation resistance (绝缘电阻)"
    path = "insulation"
    equipment = (EquipmentRequirement("megohmmeter",
                                      "megohmmeter of the relevant specification (6.2.5); its "
                                      "calibration and resolution enter each pair's budget",
                                      required=True),)
    metrics = (Metric("R_ins", "insulation resistance", "R", "Mohm", "5.2.8"),)

    step = ("gyro not operating: measure the insulation resistance between "
            "mutually insulated terminals and between terminals and case with the "
            "megohmmeter at the specified test voltage (6.2.5)")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src = R.where_of(campaign)
        pairs = R.section(campaign, f"{SECTION}.{self.path}", "5.2.8", kind=list)
        eq = R.equipment(campaign, "megohmmeter", "5.2.8", "the insulation resistance")
        results, table, warnings, seen = [], [], [], set()
        limit = float(INSULATION_MIN.to("Mohm").magnitude)
        for i, p in enumerate(pairs):
            where = f"{SECTION}.{self.path}[{i}]"
            if not isinstance(p, Mapping):
                raise DataError(src, where, "must be a table ([[inspection.insulation]])")
            pair = R.text(p, "pair", src, where)
            state = R.text(p, "state", src, where).strip().lower()
            if state not in ("non-operating", "not operating", "unpowered", "非工作状态"):
                raise DataError(src, f"{where}.state",
                                f"6.2.5 measures with the gyro not operating; got {state!r}",
                                hint="state = \"non-operating\"")
            V = R.quantity(p.get("voltage"), "V", src, f"{where}.voltage")
            raw = p.get("readings", p.get("reading"))
            if raw is None:
                raise DataError(src, f"{where}.readings", "missing")
            seq = raw if isinstance(raw, list) else [raw]
            vals = [R.reading_or_censored(v, "Mohm", src, f"{where}.readings[{j}]") for j,
                    v in enumerate(seq)]
            key = _key(pair)
            if key in seen:
                raise DataError(src, f"{where}.pair", f"a second record of the pair {pair!r}")
            seen.add(key)
            m = Metric(f"R_ins_{key}", msg("insulation resistance {pair}", pair=pair), "R", "Mohm",
                       "5.2.8")
            cens = [v for v in vals if isinstance(v, R.Censored)]
            if cens:
                below = cens[0].below
                if len(cens) != len(vals) or any(v.below != below for v in cens):
                    raise DataError(src, f"{where}.readings",
                                    "readings beyond the range mixed with others "
                                    f"({', '.join(str(v) for v in seq)}): metro does not combine "
                                    f"them",
                                    hint="record the readings of one range")
                # R < every bound below the range (the least is the tightest), R > every bound over
                # it
                pick = min if below else max
                c = pick(cens, key=lambda v: float(v.bound.to("Mohm").magnitude))
                bound = float(c.bound.to("Mohm").magnitude)
                if below and bound > limit:
                    raise DataError(src, f"{where}.readings",
                                    f"{c.text!r} is below the megohmmeter's range, whose "
                                    "lower end is above the 50 MΩ of 5.2.8: R may be on either "
                                    "side of the limit",
                                    hint="measure again on a lower range")
                if not below and bound < limit:
                    raise DataError(src, f"{where}.readings",
                                    f"{c.text!r} is over the megohmmeter's range, whose "
                                    "upper end is below the 50 MΩ of 5.2.8: R may be on either "
                                    "side of the limit",
                                    hint="measure again on a higher range")
                b = _exact("R", "Mohm", "a reading beyond the range: only the inequality is known")
                results.append(R.na_result(m, Q_(bound, "Mohm"), b.combined, b, reportable=False,
                                      bound="upper" if below else "lower", reason=_beyond(c.text,
                                                                                          below,
                                                                                          bound),
                                      note=join("; ", [_beyond(c.text, below, bound),
                                                       msg("test voltage {V}", V=f"{V:~P}")])))
                cell = c.text
            else:
                results.append(measured_result(m, vals, eq, campaign, note=msg("test voltage {V}",
                                                                               V=f"{V:~P}")))
                cell = f"{results[-1].value.to('Mohm').magnitude:.4g} MΩ"
            table.append([pair, f"{V:~P}", ", ".join(str(v) for v in seq), cell])
        tab = TableSpec("insulation",
                        "Insulation resistance per terminal pair (5.2.8), gyro not operating",
                        ["terminal pair", "test voltage", "readings", "result"], table)
        return self._outcome(results, tables=[tab], warnings=warnings)


INSULATION_SPEC = Specification("R_ins", GE, INSULATION_MIN, source=clause_source("5.2.8",
                                                                                  msg("insulation "
                                                                                      "resistance "
                                                                                      "≥ 50 MΩ")),
                                name="insulation resistance", items=("6.2.5",))
COUNT_SPECS = tuple(Specification(key, LE, Q_(0, ""), source=clause_source(clause), name=name,
                                  items=(item,))
                    for key, clause, name, item in (
                        ("appearance_nc", "5.2.3 a)–d)", "appearance checklist", "6.2.1"),
                        ("supply_missing", "5.2.6", "supply requirements stated", "5.2.6"),
                        ("mech_interface_nc", "5.2.7.1", "mechanical interface", "6.2.4"),
                        ("elec_interface_nc", "5.2.7.2", "electrical interface", "6.2.4")))


def specifications(campaign: Campaign) -> list[Specification]:
    """The inspection items' limits: clause 5's own (checklists = 0, insulation ≥ 50 MΩ, IT12) and
    the
    product specification's written in the records (dimensions, mass, supply voltages)."""
    return (list(COUNT_SPECS) + [INSULATION_SPEC] + dimension_specifications(campaign)
            + mass_specifications(campaign)
            + supply_specifications(campaign))


PROCEDURES = (Appearance621, Dimensions622, Mass623, Supply526, Interfaces624, Insulation625)

"""Reading the GB/T 45570 type-test record sections of a campaign (:attr:`Campaign.records`).

The sections — ``[inspection]`` (5.2.3–5.2.8), ``[[environmental_tests]]`` (5.4 tests done
elsewhere by GB/T 2423.x and the others) and ``[reliability]`` (5.5) — are written by a lab as
text with units (docs/data-format.md, docs/standards/gbt45570.md); these helpers read one value
and, on bad input, raise a :class:`DataError` naming the manifest, the field (``inspection.mass.
readings[1]``) and the reason.  Equipment comes from the campaign's ``[[equipment]]`` by role.
"""

from __future__ import annotations

import math
import re
from typing import Any, Mapping

import attrs
import pint
from metro.api import (Q_, BudgetRow, Campaign, DataError, Equipment, Result, Step,
                       UnitError, msg, parse_quantity, unit)

from .common import GbtItem

INSPECTION = "inspection"


def where_of(campaign: Campaign) -> str:
    return campaign.source or "campaign"


def section(campaign: Campaign, path: str, item: str, *, kind: type = dict) -> Any:
    """The record at ``path`` (``inspection.mass``), or a DataError saying it is missing."""
    node: Any = campaign.records
    parts = path.split(".")
    for p in parts:
        if not isinstance(node, Mapping) or p not in node:
            raise DataError(where_of(campaign), path,
                            f"missing: GB/T 45570 {item} reads the record [{path}]",
                            hint="docs/standards/gbt45570.md (clause 5 records) shows how to write "
                                 "it")
        node = node[p]
    if kind is list and isinstance(node, Mapping):
        node = [node]
    if not isinstance(node, kind):
        want = "an array of tables ([[…]])" if kind is list else "a table"
        raise DataError(where_of(campaign), path, f"must be {want}, got {type(node).__name__}")
    return node


def has(campaign: Campaign, path: str) -> bool:
    node: Any = campaign.records
    for p in path.split("."):
        if not isinstance(node, Mapping) or p not in node:
            return False
        node = node[p]
    return True


def quantity(value: Any, dimension: str, file: str, field: str) -> pint.Quantity:
    """``value`` as a quantity of ``dimension``; a number or text without a unit is refused by
    name."""
    if isinstance(value, bool) or value is None:
        raise DataError(file, field,
                        f"expected a quantity such as \"1 {dimension}\", got {value!r}")
    if isinstance(value, (int, float)) or (isinstance(value, str) and _is_number(value)):
        if not Q_(1, dimension).dimensionless:
            raise UnitError(file, field,
                            f"{value!r} has no unit; write it with its unit, e.g. \"{value} "
                            f"{dimension}\" (metro never guesses a unit)")
    q = parse_quantity(value if not isinstance(value, (int, float)) else str(value),
                       dimension=dimension,
                       file=file, field=field)
    if not math.isfinite(float(q.magnitude)):
        raise DataError(file, field, f"{value!r} is not a finite value")
    return q


def _is_number(text: str) -> bool:
    try:
        float(text.strip())
    except ValueError:
        return False
    return True


def text(table: Mapping, key: str, file: str, where: str, *, required: bool = True,
         default: str = "") -> str:
    v = table.get(key)
    if v is None:
        if required:
            raise DataError(file, f"{where}.{key}", "missing")
        return default
    if not isinstance(v, (str, int, float)) or isinstance(v, bool):
        raise DataError(file, f"{where}.{key}", f"must be text, got {v!r}")
    return str(v)


_YES = {"yes", "y", "true", "pass", "ok", "conforms", "合格", "是", "符合"}
_NO = {"no", "n", "false", "fail", "does not conform", "不合格", "否", "不符合"}


def answer(table: Mapping, key: str, file: str, where: str) -> bool:
    """A checklist answer: true/false or yes/no (pass/fail, 是/否); anything else is an error."""
    if key not in table:
        raise DataError(file, f"{where}.{key}", "missing checklist answer",
                        hint="write true/false or \"yes\"/\"no\"")
    v = table[key]
    if isinstance(v, bool):
        return v
    if isinstance(v, str) and v.strip().lower() in _YES:
        return True
    if isinstance(v, str) and v.strip().lower() in _NO:
        return False
    raise DataError(file, f"{where}.{key}",
                    f"a checklist answer must be true/false or yes/no, got {v!r}")


def readings(table: Mapping, key: str, dimension: str, file: str,
             where: str) -> list[pint.Quantity]:
    """One reading or a list of repeated readings, each with its unit."""
    if key not in table:
        raise DataError(file, f"{where}.{key}", "missing",
                        hint=f"write {key} = [\"… {dimension}\", …]")
    raw = table[key]
    seq = raw if isinstance(raw, list) else [raw]
    if not seq:
        raise DataError(file, f"{where}.{key}", "no reading given")
    return [
        quantity(
            v, dimension, file, f"{where}.{key}[{i}]" if isinstance(raw, list) else f"{where}.{key}"
        )
        for i, v in enumerate(seq)
    ]


@attrs.frozen
class Censored:
    """A reading outside an instrument's range, as the instrument shows it: ``< 1 MΩ`` (below the
    range: the value is less than ``bound``) or ``> 10 GΩ`` (over the range)."""

    below: bool
    bound: pint.Quantity
    text: str


_CENSORED = re.compile(r"^\s*(?P<op><|>|≤|≥|<=|>=)\s*(?P<q>.+)$")


def reading_or_censored(value: Any, dimension: str, file: str,
                        field: str) -> pint.Quantity | Censored:
    """A reading, or a :class:`Censored` one written ``"< 1 MΩ"`` / ``"> 10 GΩ"`` (not a number)."""
    if isinstance(value, str):
        m = _CENSORED.match(value)
        if m:
            return Censored(m["op"] in ("<", "≤", "<="), quantity(m["q"].strip(), dimension, file,
                                                                  field), value)
    return quantity(value, dimension, file, field)


def equipment(campaign: Campaign, role: str, item: str, what: str) -> Equipment:
    """The equipment of ``role``; a measured item without it is an error (its budget needs it)."""
    eq = campaign.equipment_for(role)
    if eq is None:
        raise DataError(where_of(campaign), "equipment",
                        f"GB/T 45570 {item} measures {what} but the campaign lists no equipment "
                        f"with role \"{role}\"; the result's uncertainty needs its calibration",
                        hint=f"add [[equipment]] with role = \"{role}\" and its "
                             f"[equipment.calibration]")
    if eq.calibration is None:
        raise DataError(where_of(campaign), f"equipment.{eq.id}.calibration",
                        f"the {role} ({eq.describe()}) used for {what} ({item}) has no calibration "
                        f"data; "
                        "6.1.2 asks for calibrated equipment and the budget needs its U",
                        hint="add [equipment.calibration] with certificate, U and k")
    return eq


def calibration_row(eq: Equipment, symbol: str, value: pint.Quantity, out_unit: str) -> BudgetRow:
    """The equipment's certificate U (absolute, or relative to ``value``) as a type B row."""
    cal = eq.calibration
    sens = Q_(abs(float(value.to(out_unit).magnitude)),
              out_unit) if cal.uncertainty.dimensionless else Q_(1.0, "")
    return BudgetRow.from_calibration(msg("calibration of the {role} ({equipment})",
                                          role=eq.role.replace("_", " "),
                                          equipment=eq.describe()), symbol, cal,
                                      sensitivity=sens)


def resolution_row(eq: Equipment, symbol: str, out_unit: str, file: str) -> list[BudgetRow]:
    """The indication's resolution d (property ``resolution``): uniform, half-width d/2."""
    if "resolution" not in eq.properties:
        return []
    d = quantity(eq.properties["resolution"], out_unit, file, f"equipment.{eq.id}.resolution")
    return [BudgetRow.type_b(msg("resolution of the {role} (d = {d})", role=eq.role.replace("_",
                                                                                            " "),
                                 d=f"{d:~P}"),
                             symbol, (d / 2).to(out_unit), distribution="uniform",
                             note=msg("half-width d/2 (JJF 1059.1)"))]


def as_unit(text_unit: str) -> pint.Unit:
    return unit(text_unit)


def na_result(*args: Any, **kw: Any) -> Result:
    """A Result about the device's build or records, in which the earth's rate has no part."""
    return Result(*args, earth_rate="not applicable", **kw)


class InspectionRecord(GbtItem):
    """An item answered from one table ``[inspection.<path>]`` of the campaign's records (5.2.1–
    5.2.8): its one step asks the lab for that table, as ``step`` says."""

    record_sections = (INSPECTION,)
    path: str
    step: str

    @classmethod
    def missing_records(cls, campaign: Campaign) -> str:
        where = f"{INSPECTION}.{cls.path}"
        return "" if has(campaign, where) else f"[{where}]"

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [Step(f"inspection-{self.path}", f"record:{INSPECTION}.{self.path}", self.step,
                     Q_(0, "s"), Q_(0, "s"))]

    def record(self, campaign: Campaign, item: str) -> tuple[str, str, Any]:
        """(file, field, table) of this item's record; a DataError citing ``item`` without it."""
        where = f"{INSPECTION}.{self.path}"
        return where_of(campaign), where, section(campaign, where, item)

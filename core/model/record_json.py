"""The JSON form of a run record: what ``metro run --json`` prints, what ``metro batch`` keeps
beside each device's report, and what the register stores of a run.

Below the command line on purpose: the register (:mod:`metro.core.record.registering`) and the
command line (:mod:`metro.core.cli.present`) both use it.  The conventions (docs/json.md):

- a missing value is ``null``, never the text ``"None"``; a number that is not finite is ``null``;
- a number whose unit is named beside it keeps that unit in a sibling field (a result's
  ``value``, ``u`` and ``U`` are in its ``unit``);
- a value that may be of any kind (an option, a condition, a declared truth, the environment) is
  written as what it is: a number, a text, a flag, a list, or a quantity as
  ``{"value": number, "unit": text}``, the unit as metro prints it (``°/h``, ``°/√h``).
"""

from __future__ import annotations

import datetime as dt
import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import TYPE_CHECKING, Any

# annotations only: reading a register prints JSON without pint
if TYPE_CHECKING:  # pragma: no cover
    from .provenance import RunRecord


def _fmt_unit(u: Any) -> str:
    """:func:`metro.core.base.units.fmt_unit`, imported when a unit is printed (it loads pint)."""
    from ..base.units import fmt_unit as fmt

    return fmt(u)


def json_value(v: Any) -> Any:
    """``v`` as a JSON value of its own kind: None → null, a flag, an integer, a finite float (a
    non-finite one → null), a text, a pint quantity → ``{"value", "unit"}``, a mapping → an object,
    a sequence (a numpy array too) → a list, a date → its ISO text; anything else → its text."""
    if v is None or isinstance(v, (bool, str)):
        return v
    if isinstance(v, int):
        return int(v)
    if isinstance(v, float):
        return float(v) if math.isfinite(v) else None
    if hasattr(v, "magnitude") and hasattr(v, "units"):  # a pint quantity
        return {"value": json_value(_plain_number(v.magnitude)), "unit": _fmt_unit(v.units)}
    if isinstance(v, Mapping):
        return {str(k): json_value(x) for k, x in v.items()}
    if isinstance(v, (list, tuple, set, frozenset)):
        return [json_value(x) for x in v]
    if isinstance(v, (dt.date, dt.datetime)):
        return v.isoformat()
    if hasattr(v, "tolist"):  # a numpy number or array
        return json_value(v.tolist())
    return str(v)


def _plain_number(m: Any) -> Any:
    """A quantity's magnitude as a Python number or list (numpy's as ``tolist()``)."""
    return m.tolist() if hasattr(m, "tolist") else m


#: a number, then what follows it (``10``, ``-2.5e-3``, ``10 s``, ``0.5 °/h``)
_NUMBER_FIRST = re.compile(r"^([-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)\s*(.*)$")


def option_value(v: Any) -> Any:
    """An item's option value as what it is.  Items hand their option values over as text
    (``str(value)``), so a text is read back: ``None`` → null, ``True``/``False`` → a flag, a
    number → a number, one number and a unit metro reads (``10 s``) → ``{"value", "unit"}``;
    any other text (``IRA up``, ``10 s, 100 s``) stays text.  A value that is not a text is
    written by :func:`json_value`."""
    if not isinstance(v, str):
        return json_value(v)
    text = v.strip()
    if text in ("None", "True", "False"):
        return {"None": None, "True": True, "False": False}[text]
    m = _NUMBER_FIRST.match(text)
    if m is None:
        return v
    number, rest = m.groups()
    value = json_value(int(number) if re.fullmatch(r"[-+]?\d+", number) else float(number))
    if not rest:
        return value
    if re.search(r"[,;]|\s[-+.]?\d", rest):  # a list of values, not one quantity
        return v
    try:
        from ..base.units import unit

        return {"value": value, "unit": _fmt_unit(unit(rest))}
    except Exception:  # noqa: BLE001 — pint's parse errors are of many kinds: not a unit
        return v


def options_json(options: Mapping[str, Any]) -> dict[str, Any]:
    """An item's option values (:attr:`Outcome.options`) as JSON values (:func:`option_value`)."""
    return {str(k): option_value(v) for k, v in options.items()}


def truth_checks(record: RunRecord) -> list[dict[str, Any]]:
    """On a simulated run, compare each result with the station's expected value (by metric key)."""
    if not record.simulated:
        return []
    exp = record.campaign.expected
    out = []
    for o in record.outcomes:
        for r in o.results:
            if r.metric.key not in exp or r.U is None:
                continue
            unit = r.metric.unit
            v = float(r.value.to(unit).magnitude)
            t = float(exp[r.metric.key].to(unit).magnitude)
            U = float(r.U.magnitude)
            out.append({"item": o.item, "key": r.metric.key, "truth": t, "value": v, "U": U,
                        "within_U": abs(v - t) <= U,
                        "reportable": bool(getattr(r, "reportable", True)),
                        "unit": _fmt_unit(unit)})
    return out


def _items(record: RunRecord) -> list[dict[str, Any]]:
    return [{"item": o.item, "title": o.title, "clause": o.clause,
             "warnings": list(map(str, o.warnings)),
             "options": options_json(o.options),
             "tables": [{"name": t.name, "title": str(t.title), "header": list(map(str, t.header)),
                         "rows": [list(map(str, r)) for r in t.rows]} for t in o.tables]}
            for o in record.outcomes]


def _conformity(record: RunRecord) -> dict[str, Any] | None:
    a = record.conformity
    if a is None:
        return None
    return {
        "rule": a.rule.name,
        "statement": a.rule.statement,
        "overall": a.overall.value if a.overall else None,
        "verdicts": [v.as_dict() for v in a.verdicts],
        "not_assessed": [{"symbol": sp.symbol, "limit": sp.text(), "source": sp.source}
                         for sp in a.not_assessed],
    }


def _provenance(record: RunRecord) -> dict[str, Any]:
    c = record.campaign
    return {"software": dict(record.software), "plugins": dict(record.plugins),
            "data_files": [{"file": f, "sha256": h} for f, h in record.data_files],
            "manifest": {"file": c.source, "sha256": c.manifest_sha256} if c.manifest_sha256
            else None,
            "source": c.source, "created": record.created.isoformat()}


def record_document(record: RunRecord, report_path: Path | None) -> dict[str, Any]:
    """The run as one JSON object (docs/json.md, core/cli/schemas/run.schema.json), without the
    ``schema_version`` and ``register`` fields the command line adds."""
    results = []
    budgets = []
    for o in record.outcomes:
        for r in o.results:
            d = r.as_dict()
            d["item"] = o.item
            d["budget"] = r.budget.as_dict() if r.budget is not None else None
            if r.budget is not None:
                budgets.append(d["budget"] | {"item": o.item})
            results.append(d)
    c = record.campaign
    return {
        "standard": record.standard,
        "item": ",".join(o.item for o in record.outcomes),
        "items": _items(record),
        "results": results,
        "budget": budgets[0] if budgets else None,
        "budgets": budgets,
        "report": str(report_path) if report_path else None,
        "report_number": record.report_number,
        "simulated": record.simulated,
        "truth": {str(k): json_value(v) for k, v in record.truth.items()},
        "truth_checks": truth_checks(record),
        "device": {"id": c.device.id, "model": c.device.model, "serial": c.device.serial},
        "environment": json_value(dict(c.environment)),
        "site": json_value(dict(c.site)),
        "equipment": [{"id": e.id, "role": e.role, "status": e.status(record.test_date),
                       "calibration_valid": None if e.calibration is None
                       else e.calibration.is_valid(record.test_date)} for e in c.equipment],
        "manifest_warnings": list(map(str, c.warnings)),
        "timings_s": dict(record.timings),
        "selection": [{"item": ch.item, "run": ch.run, "reason": ch.reason, "via": ch.via}
                      for ch in record.selection],
        "conformity": _conformity(record),
        "provenance": _provenance(record),
    }


__all__ = ["json_value", "option_value", "options_json", "record_document", "truth_checks"]

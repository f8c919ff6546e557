"""The machine values of a report, as the report context keeps them (``context["data"]``).

:func:`metro.core.documents.context.report_context` formats every number for print; a DCC needs
the numbers, units, coverage factors and verdict codes themselves.  :func:`dcc_data` adds them
once, under one key, as plain JSON (floats, text, lists, dicts; messages stay :class:`Text` so
that the register keeps them translatable), so that a DCC can be written again from the register
(``metro report NUMBER --format dcc``) exactly as at the run.  ``DATA_VERSION`` is stored with
them; a context without ``data`` (stored before this) is refused by the DCC writer.
"""

from __future__ import annotations

import datetime as dt
import math
import re
from typing import TYPE_CHECKING, Any

from ...base.formatting import fmt_quantity
from ...base.units import difference_unit, fmt_unit
from ...stats.earth import EARTH_RATE_DEG_PER_H, vertical_earth_rate_deg_h

if TYPE_CHECKING:  # pragma: no cover
    from ...model.campaign import Equipment
    from ...model.provenance import RunRecord
    from ...model.results import Result

__all__ = ["DATA_VERSION", "dcc_data", "decimal_text", "coverage_probability"]

#: the version of the ``context["data"]`` layout (the DCC writer refuses another)
DATA_VERSION = 1

_SUP = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺", "0123456789-+")
_POWER = re.compile(r"^([-+]?\d+(?:\.\d*)?)\s*[×x·]\s*10([⁻⁺]?[⁰¹²³⁴⁵⁶⁷⁸⁹]+)$")
_DECIMAL = re.compile(r"^[-+]?((\d*\.\d+)|(\d+\.\d*)|(\d+\.?))([Ee][-+]?\d+)?$")


def decimal_text(text: str) -> str | None:
    """A number as metro prints it (``"0.00150"``, ``"6.5×10⁻⁶"``, ``"−3.2"``) as decimal text
    that keeps its digits (``"0.00150"``, ``"6.5e-6"``, ``"-3.2"``); None for text that is not a
    number (``"—"``, ``"u = 0.1"``).

    >>> decimal_text("6.5×10⁻⁶"), decimal_text("-0.00150"), decimal_text("—")
    ('6.5e-6', '-0.00150', None)
    """
    t = str(text).strip().replace("−", "-").replace("\u2009", "").replace(" ", "")
    m = _POWER.match(t)
    if m:
        t = f"{m.group(1)}e{m.group(2).translate(_SUP)}"
    return t if _DECIMAL.match(t) else None


def coverage_probability(coverage: Any, k: float) -> float:
    """The coverage probability of an expanded uncertainty: the budget's ``p`` when k was chosen
    as t_p(ν_eff) (JJF 1059.1 clause 5.3.4), else that of a normal distribution for the fixed k,
    p = erf(k/√2) (JJF 1059.1 clause 5.3.3: k = 2 gives p ≈ 95.45 %), rounded to 4 decimals."""
    p = getattr(coverage, "p", None)
    if p is not None:
        return round(float(p), 4)
    return round(math.erf(float(k) / math.sqrt(2.0)), 4)


def _num(x: Any) -> float | None:
    if x is None:
        return None
    f = float(x)
    return f if math.isfinite(f) else None


def _budget(r: "Result") -> dict[str, Any] | None:
    b = r.budget
    if b is None:
        return None
    d = b.as_dict()
    rows = [{"source": row["source"], "symbol": row["symbol"], "type": row["type"],
             "distribution": row["distribution"], "value": _num(row["value"]),
             "value_unit": row["value_unit"], "divisor": _num(row["divisor"]),
             "standard_uncertainty": _num(row["standard_uncertainty"]),
             "sensitivity": _num(row["sensitivity"]),
             "sensitivity_unit": row["sensitivity_unit"],
             "contribution": _num(row["contribution"]), "dof": _num(row["dof"]),
             "note": row["note"]} for row in d["rows"]]
    return {"measurand": d["measurand"], "unit": d["unit"], "rows": rows,
            "u_c": _num(d["u_c"]), "nu_eff": _num(d["nu_eff"]), "k": _num(d["k"]),
            "coverage": d["coverage"], "U": _num(d["U"]), "U_text": d["U_reported"]}


def _result(item: str, r: "Result") -> dict[str, Any]:
    m = r.metric
    vtext, utext = r.reported()
    U = r.U
    k = r.k
    return {
        "item": item, "key": m.key, "quantity": m.name, "symbol": m.symbol,
        "clause": m.clause, "equation": m.equation,
        "unit": fmt_unit(m.unit),
        "value": float(r.value.to(m.unit).magnitude),
        "value_text": vtext,
        "U": None if U is None else float(U.magnitude),
        "U_text": utext,
        "u": None if r.u is None else float(r.u.to(difference_unit(m.unit)).magnitude),
        "k": _num(k),
        "p": None if k is None or r.budget is None
        else coverage_probability(r.budget.coverage, k),
        "reportable": bool(r.reportable), "reason": r.reason or "",
        "bound": r.bound or "", "earth_rate": r.earth_rate or "", "note": r.note or "",
        "budget": _budget(r),
    }


def _equipment(e: "Equipment") -> dict[str, Any]:
    cal = e.calibration
    out: dict[str, Any] = {"id": e.id, "role": e.role, "description": e.describe(),
                           "manufacturer": e.manufacturer, "model": e.model, "serial": e.serial,
                           "certificate": None, "lab": "", "due": None}
    if cal is not None:
        out.update(certificate=cal.certificate, lab=cal.lab,
                   due=cal.due.isoformat() if cal.due else None,
                   U=_num(getattr(cal.uncertainty, "magnitude", cal.uncertainty)),
                   U_unit=fmt_unit(cal.uncertainty.units)
                   if hasattr(cal.uncertainty, "units") else "",
                   k=_num(cal.k), distribution=cal.distribution)
    return out


def _quantity(v: Any) -> dict[str, Any] | None:
    """A manifest value (``"20 °C"``, a quantity, a number) as {value, unit, text}; None for
    text that is not a quantity (a place name)."""
    from ...base.errors import MetroError
    from ...base.units import parse_quantity

    try:
        q = parse_quantity(v)
    except (MetroError, ValueError, TypeError):
        return None
    return {"value": float(q.magnitude), "unit": fmt_unit(q.units), "text": fmt_quantity(v)}


def _conditions(record: "RunRecord") -> dict[str, Any]:
    camp = record.campaign
    env = {str(k): _quantity(v) for k, v in camp.environment.items()}
    site = {str(k): _quantity(v) for k, v in camp.site.items()}
    out: dict[str, Any] = {"environment": {k: v for k, v in env.items() if v is not None},
                           "site": {k: v for k, v in site.items() if v is not None},
                           "earth_rate": {"value": EARTH_RATE_DEG_PER_H, "unit": "°/h",
                                          "text": f"{EARTH_RATE_DEG_PER_H:.5g} °/h"}}
    lat = out["site"].get("latitude")
    if lat is not None and lat["unit"] == "°":
        v = vertical_earth_rate_deg_h(lat["value"])
        out["earth_rate_vertical"] = {"value": v, "unit": "°/h", "text": f"{v:.5g} °/h"}
    return out


def _dates(record: "RunRecord") -> dict[str, str]:
    """The first and last day of measurement: the segments' start times, else the campaign's
    measurement date (the report's test date)."""
    days = sorted({s.started.date() for s in record.campaign.segments
                   if isinstance(getattr(s, "started", None), dt.datetime)})
    on = record.test_date
    return {"begin": (days[0] if days else on).isoformat(),
            "end": (days[-1] if days else on).isoformat()}


def _verdicts(record: "RunRecord") -> list[dict[str, Any]]:
    a = getattr(record, "conformity", None)
    if a is None:
        return []
    return [{"item": v.item, "key": v.key, "status": v.status.value, "detail": v.detail,
             "limit": v.spec.text(), "source": v.spec.source, "rule": a.rule.name,
             "reason": v.reason} for v in a.verdicts]


def dcc_data(record: "RunRecord") -> dict[str, Any]:
    """The machine values of ``record``'s report: ``version``, ``country`` (``[site]`` or
    ``[campaign]`` ``country``, else ``""``), ``dates`` {begin, end}, ``device`` {id,
    manufacturer, model, serial, customer_id}, ``results`` (one per result of every outcome:
    item, key, quantity, symbol, clause, equation, unit, value, value_text, U, U_text, u, k, p,
    reportable, reason, bound, earth_rate, note, budget {measurand, unit, rows, u_c, nu_eff, k,
    coverage, U, U_text}), ``verdicts`` ({item, key, status, detail, limit, source, rule,
    reason}), ``equipment`` ({id, role, description, manufacturer, model, serial, certificate,
    lab, due, U, U_unit, k, distribution}), ``conditions`` {environment, site, earth_rate,
    earth_rate_vertical} as {value, unit, text} and ``decision_rule`` {name, statement}."""
    camp = record.campaign
    dev = camp.device
    country = str(camp.site.get("country") or camp.meta.get("country") or "").strip().upper()
    a = getattr(record, "conformity", None)
    return {
        "version": DATA_VERSION,
        "country": country,
        "dates": _dates(record),
        "device": {"id": dev.id, "manufacturer": dev.manufacturer, "model": dev.model,
                   "serial": dev.serial,
                   "customer_id": str(dev.properties.get("customer_id") or "")},
        "results": [_result(o.item, r) for o in record.outcomes for r in o.results],
        "verdicts": _verdicts(record),
        "equipment": [_equipment(e) for e in camp.equipment],
        "conditions": _conditions(record),
        "decision_rule": None if a is None else {"name": a.rule.name, "title": a.rule.title,
                                                 "statement": a.rule.statement},
    }

"""Certificate data for JJF 2003—2022 (appendix B inner page, clause 8 a)–l)).

:func:`certificate_context` turns a run record into ``context["jjf2003"]`` for the template
``templates/certificate.docx`` (built by ``templates/make_certificate.py``).  Values are
rounded as :meth:`metro.core.model.Result.reported` rounds them (U to two significant digits,
rounded up as appendix A does, k = 2).
"""

from __future__ import annotations

from typing import Any

from metro.core.units import fmt_unit

AXES = ("x", "y", "z")
DASH = "—"


def _results(record) -> dict[str, Any]:
    """Latest result per metric key over the jjf2003 outcomes."""
    out: dict[str, Any] = {}
    for o in record.outcomes:
        if o.standard != "jjf2003":
            continue
        for r in o.results:
            out[r.metric.key] = r
    return out


def _unit(r) -> str:
    u = fmt_unit(r.metric.unit)
    return "" if u in ("", "1", "dimensionless") else u


def _row(r) -> dict[str, str]:
    v, U = r.reported()
    return {"name": r.metric.name, "symbol": r.metric.symbol, "value": v, "U": U or DASH, "unit": _unit(r) or "1",
            "k": "2" if r.k is None else f"{r.k:g}", "clause": r.metric.clause}


def _rows(res, keys) -> list[dict[str, str]]:
    return [_row(res[k]) for k in keys if k in res]


def _matrix(res, prefix: str, zero_diagonal: bool = False) -> dict[str, Any] | None:
    keys = [f"{prefix}{r}{c}" for r in AXES for c in AXES]
    if not all(k in res for k in keys if not (zero_diagonal and k[-1] == k[-2])):
        return None
    values, uncs = [], []
    unit = ""
    for r in AXES:
        vrow, urow = {"axis": r}, {"axis": r}
        for n, c in enumerate(AXES, start=1):
            if zero_diagonal and r == c:
                vrow[f"c{n}"], urow[f"c{n}"] = "0", DASH
                continue
            v, U = res[f"{prefix}{r}{c}"].reported()
            unit = _unit(res[f"{prefix}{r}{c}"])
            vrow[f"c{n}"], urow[f"c{n}"] = v, U or DASH
        values.append(vrow)
        uncs.append(urow)
    return {"value_rows": values, "u_rows": uncs, "unit": unit or "1"}


def _text(v) -> str:
    return DASH if v in (None, "") else str(v)


def certificate_context(record) -> dict[str, Any]:
    """``context["jjf2003"]``: ``clause8`` (a)–l) fields), ``scale_factors``, ``biases``,
    ``gyro_cross`` / ``accel_cross`` (rows), ``K_g``, ``K_a``, ``g``, ``p`` (matrices
    {value_rows, u_rows, unit} with rows {axis, c1, c2, c3}, or None), ``notes``."""
    camp = record.campaign
    res = _results(record)
    dev = camp.device
    created = record.created.date().isoformat() if hasattr(record.created, "date") else str(record.created)
    env = "; ".join(f"{k}: {v:~P}" if hasattr(v, "units") else f"{k}: {v}" for k, v in camp.environment.items())
    standards = []
    for e in camp.equipment:
        cal = e.calibration
        standards.append({
            "name": e.describe(), "role": e.role or DASH, "serial": e.serial or e.id,
            "accuracy": DASH if cal is None else (f"U = {cal.uncertainty:~P}, k = {cal.k:g}"
                                                  if cal.distribution == "normal" else f"±{cal.uncertainty:~P}"),
            "certificate": DASH if cal is None else cal.certificate,
        })
    clause8 = {
        "title": "校准证书 Calibration certificate",
        "lab_name": _text(camp.lab.name), "lab_address": _text(camp.lab.address),
        "number": record.report_number,
        "customer": _text(camp.customer.name), "customer_address": _text(camp.customer.address),
        "device_name": "微惯性测量组合 (MIMU) " + (dev.model or ""), "manufacturer": dev.manufacturer or DASH,
        "model": dev.model or DASH, "serial": dev.serial or dev.id,
        "received": _text(camp.date_received and camp.date_received.isoformat()),
        "calibrated": camp.measurement_date.isoformat() if camp.measurement_date else created,
        "standards": standards, "environment": env or DASH,
        "issuer": _text(camp.people.approved_by), "issuer_title": _text(camp.people.approved_by_title),
        "issued": created,
        "operator": _text(camp.people.operator), "checker": _text(camp.people.checked_by),
    }
    notes = [f"{o.item}: {w}" for o in record.outcomes if o.standard == "jjf2003" for w in o.warnings
             if "DEVIATION" in w or "as printed" in w]
    return {
        "clause8": clause8,
        "scale_factors": _rows(res, [f"K_g{a}{a}" for a in AXES] + [f"K_a{a}{a}" for a in AXES]),
        "biases": _rows(res, [f"B_g{a}" for a in AXES] + [f"B_a{a}" for a in AXES]),
        "gyro_cross": _rows(res, [f"K_g{r}{c}" for r in AXES for c in AXES if r != c]),
        "accel_cross": _rows(res, [f"K_a{r}{c}" for r in AXES for c in AXES if r != c]),
        "K_g": _matrix(res, "K_g"), "K_a": _matrix(res, "K_a"),
        "g": _matrix(res, "g_"), "p": _matrix(res, "p_", zero_diagonal=True),
        "notes": notes,
    }

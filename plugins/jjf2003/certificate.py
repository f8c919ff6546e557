"""Certificate data for JJF 2003—2022 (appendix B inner page, clause 8 a)–l)).

:func:`certificate_context` turns a run record into ``context["jjf2003"]`` for the template
the document :func:`layout`.  Values are
rounded as :meth:`metro.core.model.results.Result.reported` rounds them (U to two significant
digits, rounded up as appendix A does, k = 2).
"""

from __future__ import annotations

from typing import Any

from metro.api import fmt_num, fmt_quantity, fmt_unit, group_notes, join

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


def _row(r) -> dict[str, Any]:
    v, U = r.reported()
    return {"name": r.metric.name, "symbol": r.metric.symbol, "value": v, "U": U or DASH,
            "unit": _unit(r) or "1",
            "k": "2" if r.k is None else fmt_num(r.k, 3), "clause": r.metric.clause,
            # the reason stays a message, so the document writes it in its language
            "reportable": bool(getattr(r, "reportable", True)),
            "reason": getattr(r, "reason", "") or ""}


def _rows(res, keys) -> list[dict[str, str]]:
    return [_row(res[k]) for k in keys if k in res]


#: a matrix cell whose result is not reportable (translated by the layout; the reasons follow the
#: matrix)
NOT_REPORTABLE = "not reportable"


def _matrix(res, prefix: str, zero_diagonal: bool = False) -> dict[str, Any] | None:
    keys = [f"{prefix}{r}{c}" for r in AXES for c in AXES]
    if not all(k in res for k in keys if not (zero_diagonal and k[-1] == k[-2])):
        return None
    values, uncs = [], []
    unit = ""
    withheld: list[tuple[str, Any]] = []  # (symbol, reason) of the cells not reportable
    for r in AXES:
        vrow, urow = {"axis": r}, {"axis": r}
        for n, c in enumerate(AXES, start=1):
            if zero_diagonal and r == c:
                vrow[f"c{n}"], urow[f"c{n}"] = "0", DASH
                continue
            result = res[f"{prefix}{r}{c}"]
            v, U = result.reported()
            unit = _unit(result)
            if not getattr(result, "reportable", True):  # the value is not issued: the cell says so
                vrow[f"c{n}"], urow[f"c{n}"] = NOT_REPORTABLE, DASH
                withheld.append((result.metric.symbol, getattr(result, "reason", "") or ""))
                continue
            vrow[f"c{n}"], urow[f"c{n}"] = v, U or DASH
        values.append(vrow)
        uncs.append(urow)
    return {"value_rows": values, "u_rows": uncs, "unit": unit or "1", "not_reportable": withheld}


def _text(v) -> str:
    return DASH if v in (None, "") else str(v)


def certificate_context(record) -> dict[str, Any]:
    """``context["jjf2003"]``: ``clause8`` (a)–l) fields), ``scale_factors``, ``biases``,
    ``gyro_cross`` / ``accel_cross`` (rows), ``K_g``, ``K_a``, ``g``, ``p`` (matrices
    {value_rows, u_rows, unit} with rows {axis, c1, c2, c3}, or None), ``notes``."""
    camp = record.campaign
    res = _results(record)
    dev = camp.device
    created = record.created.date().isoformat() if hasattr(record.created,
                                                           "date") else str(record.created)
    env = "; ".join(f"{k}: {fmt_quantity(v)}" for k, v in camp.environment.items())
    standards = []
    for e in camp.equipment:
        cal = e.calibration
        standards.append({
            "name": e.describe(), "role": e.role or DASH, "serial": e.serial or e.id,
            "accuracy": DASH if cal is None else (f"U = {fmt_quantity(cal.uncertainty)} (k = "
                                                  f"{cal.k:g})"
                                                  if cal.distribution == "normal"
                                                  else f"±{fmt_quantity(cal.uncertainty)}"),
            "certificate": DASH if cal is None else cal.certificate,
        })
    clause8 = {
        "title": "校准证书 Calibration certificate",
        "lab_name": _text(camp.lab.name), "lab_address": _text(camp.lab.address),
        "number": record.report_number,
        "customer": _text(camp.customer.name), "customer_address": _text(camp.customer.address),
        "device_name": "微惯性测量组合 (MIMU) " + (dev.model or ""),
               "manufacturer": dev.manufacturer or DASH,
        "model": dev.model or DASH, "serial": dev.serial or dev.id,
        "received": _text(camp.date_received and camp.date_received.isoformat()),
        "calibrated": camp.measurement_date.isoformat() if camp.measurement_date else created,
        "standards": standards, "environment": env or DASH,
        "issuer": _text(camp.people.approved_by),
               "issuer_title": _text(camp.people.approved_by_title),
        "issued": created,
        "operator": _text(camp.people.operator), "checker": _text(camp.people.checked_by),
    }
    # each deviation once, naming the items it applies to (7.2.2 and 7.2.3 share some)
    notes = [join(": ", [where, w]) for where, w in group_notes(
        (o.item, "", w) for o in record.outcomes if o.standard == "jjf2003" for w in o.warnings
        if "DEVIATION" in w or "as printed" in w)]
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


#: appendix B groups: (no., Chinese title, English title, context key)
GROUPS = (
    ("1", "标度因数", "Scale factors", "scale_factors"),
    ("2", "零偏", "Biases", "biases"),
    ("3", "陀螺交叉耦合系数", "Gyroscope cross-coupling coefficients", "gyro_cross"),
    ("4", "加速度计交叉耦合系数", "Accelerometer cross-coupling coefficients", "accel_cross"),
)
MATRICES = (
    ("5", "陀螺加速度敏感系数", "Gyroscope acceleration sensitivity", "g", "g"),
    ("6", "加速度计角速度灵敏系数", "Accelerometer angular-rate sensitivity", "p", "p"),
)


def layout(doc, ctx: dict) -> None:
    """JJF 2003—2022 MIMU calibration certificate: clause 8 (title to signatures) and the
    appendix B inner page (groups 1–6, each with its measurement uncertainty)."""
    from metro.api import document as D

    c = ctx.get("jjf2003")
    if c is None:
        D.generic_layout(doc, ctx)
        return
    tr, f, c8 = doc.tr, ctx["facts"], c["clause8"]
    doc.title_block(tr("Calibration certificate"))
    doc.kv([
        (tr("Certificate No."), c8["number"]),
        (tr("Laboratory name"), D.or_dash(f["lab"])),
        (tr("Laboratory address"), D.or_dash(f["lab_address"])),
        (tr("Seal of the calibrating laboratory"), tr("(affixed on the issued certificate)")),
        (tr("Customer"), D.or_dash(f["customer"])),
        (tr("Customer address"), D.or_dash(f["customer_address"])),
        (tr("Instrument calibrated"),
         tr.pick("微惯性测量组合 (MIMU)", "micro inertial measurement unit (MIMU)")),
        (tr("Manufacturer"), c8["manufacturer"]),
        (tr("Model"), c8["model"]),
        (tr("Serial number"), c8["serial"]),
        (tr("Date received"), D.or_dash(f["received"])),
        (tr("Date of calibration"), D.or_dash(f["measured"])),
        (tr("Calibration specification"), tr.pick("JJF 2003—2022 微惯性测量组合(MIMU)校准规范",
                                                  "JJF 2003—2022 Calibration Specification for "
                                                  "MIMU")),
        (tr("Environment"),
         "; ".join(f"{tr(n['name'].capitalize())} {n['value']}" for n in ctx["environment"])
         or DASH),
    ])
    doc.heading(tr("Measurement standards used"), 2)
    doc.table([tr("Name"), tr("Serial number"), tr("Accuracy"), tr("Certificate No."),
               tr("Status on the date of measurement")],
              [[s["name"], s["serial"], s["accuracy"], s["certificate"],
                D.status_text(tr, e["status"])]
               for s, e in zip(c8["standards"], ctx["equipment"])])
    doc.heading(tr("MIMU calibration results"), 1)
    for no, cn, en, key in GROUPS:
        rows = c[key]
        doc.heading(f"{no}. {tr.pick(cn, en)}", 2)
        if not rows:
            doc.para(tr("not performed"))
            continue
        # a result not reportable: the cell says so, its U is not issued, the reason follows the
        # table
        doc.table([tr("Quantity"), tr("Symbol"), tr("Calibration result"),
                   tr("Expanded uncertainty")],
                  [[r["name"], r["symbol"], D.with_unit(r["value"], r["unit"]),
                    f"U = {D.with_unit(r['U'], r['unit'])} "
                    f"(k = {r['k']})" if r["U"] != DASH else tr("not evaluated")]
                   if r["reportable"] else
                   [r["name"], r["symbol"], tr(NOT_REPORTABLE), DASH] for r in rows], prefer=0)
        D.withheld_reasons(doc, [(r["symbol"], r["reason"]) for r in rows if not r["reportable"]])
    for no, cn, en, key, sym in MATRICES:
        m = c[key]
        doc.heading(f"{no}. {tr.pick(cn, en)} ({sym})", 2)
        if m is None:
            doc.para(tr("not performed"))
            continue
        unit = "" if m["unit"] == "1" else f" ({m['unit']})"
        def cell(x: str) -> str:
            return tr(x) if x == NOT_REPORTABLE else x

        doc.para(f"{sym}{unit}:", keep_next=True)
        doc.table(["", "x", "y", "z"],
                  [[r["axis"], *(cell(r[f"c{n}"]) for n in (1, 2, 3))] for r in m["value_rows"]],
                  width_mm=110)
        doc.para(f"{tr('Measurement uncertainty')} U (k = 2){unit}:", keep_next=True)
        doc.table(["", "x", "y", "z"],
                  [[r["axis"], r["c1"], r["c2"], r["c3"]] for r in m["u_rows"]], width_mm=110)
        D.withheld_reasons(doc, m.get("not_reportable", ()))
    doc.heading(tr("Notes on the results"), 2)
    D.notes_section(doc, ctx)
    doc.heading(tr("Signatures"), 2)
    D.signatures(doc, D.signatory_rows(f, [tr("Calibrated by"), tr("Checked by"), tr("Issued by")]),
                 titled=True)
    doc.para(f"{tr('Date of issue')}: {D.or_dash(f['issued'])}")
    doc.para(tr("Recommended recalibration interval: {interval}", interval=tr.msg("1 year")),
             size=8.5)
    D.annexes(doc, ctx)

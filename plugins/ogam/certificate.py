"""The draft's certificate (appendix B inner page, clauses 8–9): ``context["ogam"]`` and the
document layout.

Every item carries its own expanded uncertainty (clause 8: "给出校准项目和校准结果以及相应的测量
不确定度"), as :meth:`metro.core.model.results.Result.reported` rounds it; appendix B's line for E
("角位置测量偏差的测量不确定度: U = …, k = 2") is printed under the table as the draft asks.
Clause 9: the recalibration interval is stated (at most 12 months, as the draft recommends).
"""

from __future__ import annotations

from typing import Any

#: appendix B rows: (no., Chinese name, English name, item id, metric key)
ROWS = (
    ("1", "标度因数", "scale factor", "7.1", "K"),
    ("2", "标度因数线性度", "scale-factor linearity", "7.2", "Kl"),
    ("3", "零位漂移", "zero drift", "7.3", "Bs"),
    ("4", "角位置测量偏差", "angle-position error", "7.4", "E"),
    ("5", "角位置测量重复性", "angle-position repeatability", "7.5", "R"),
    ("6", "速率一致性", "rate consistency", "7.6", "Cv"),
    ("7", "指向一致性", "pointing consistency", "7.7", "Cg"),
)
DESIGNATION_CN = "JJF xxxx—xxxx 光学陀螺测角仪校准规范 (征求意见稿)"
DESIGNATION_EN = ("JJF xxxx—xxxx Calibration Specification for Optical Gyroscope Angle Measuring "
                  "Instruments (draft)")
DASH = "—"


def certificate_context(record) -> dict[str, Any]:
    """{rows [{no, item_cn, item_en, symbol, performed, reportable, reason, value, U, k}], U_E,
    k_E}."""
    from metro.api import result_fields

    results = {(o.item, r.metric.key): r for o in record.outcomes if o.standard == "ogam"
               for r in o.results}
    rows = []
    U_E, k_E = DASH, "2"
    for no, cn, en, item, key in ROWS:
        r = results.get((item, key))
        base = {"no": no, "item_cn": cn, "item_en": en, "clause": item}
        if r is None:
            rows.append(base | {"performed": False, "reportable": True, "reason": "", "value": "",
                                "U": "",
                                "k": "", "symbol": ""})
            continue
        row = result_fields(r)
        value = row["value_unit"]
        if key == "E" and not value.startswith(("-", "−")):
            value = "±" + value  # 7.4: E = ±max|E_i|
        rows.append(base | {"performed": True, "reportable": row["reportable"],
                            "reason": row["reason"],
                            "value": value, "U": row["U_unit"], "k": row["k"],
                            "symbol": r.metric.symbol})
        if key == "E" and row["U_unit"] != DASH:
            U_E, k_E = row["U_unit"], row["k"]
    return {"designation": DESIGNATION_CN, "rows": rows, "U_E": U_E, "k_E": k_E}


def layout(doc, ctx: dict) -> None:
    """The certificate: laboratory, customer, instrument, dates, specification, standards and
    environment; appendix B's seven rows each with U; notes; signatures; clause 9 interval;
    figures and budgets as annexes."""
    from metro.api import document as D

    c = ctx.get("ogam")
    if c is None:
        D.generic_layout(doc, ctx)
        return
    tr, f, dev = doc.tr, ctx["facts"], ctx["device"]
    doc.title_block(tr("Calibration certificate"))
    doc.kv([
        (tr("Certificate No."), ctx["report_number"]),
        (tr("Laboratory"), D.or_dash(f["lab"])),
        (tr("Laboratory address"), D.or_dash(f["lab_address"])),
        (tr("Customer"), D.or_dash(f["customer"])),
        (tr("Customer address"), D.or_dash(f["customer_address"])),
        (tr("Instrument calibrated"),
         f"{tr.pick('光学陀螺测角仪', 'optical gyroscope angle measuring instrument')}: "
                                      f"{tr.text(dev['description'])} ({tr('id')} {dev['id']})"),
        (tr("Date of calibration"), D.or_dash(f["measured"])),
        (tr("Date received"), D.or_dash(f["received"])),
        (tr("Date of issue"), D.or_dash(f["issued"])),
        (tr("Calibration specification"), tr.pick(DESIGNATION_CN, DESIGNATION_EN)),
        (tr("Environment"),
         "; ".join(f"{tr(n['name'].capitalize())} {n['value']}" for n in ctx["environment"])
         or DASH),
    ])
    doc.heading(tr("Calibration results"), 1)
    rows = []
    for r in c["rows"]:
        if not r["performed"]:
            value, U = tr("not performed"), DASH
        elif not r["reportable"]:
            value, U = D.not_reportable(tr, r["reason"]), DASH
        else:
            value = r["value"]
            U = f"U = {r['U']} (k = {r['k']})" if r["U"] != DASH else tr("not evaluated")
        rows.append([r["no"],
                     tr.pick(r["item_cn"],
                             r["item_en"]) + (f" {r['symbol']}" if r["symbol"] else ""),
                     value, U])
    doc.table([tr("No."), tr("Calibration item"), tr("Calibration result"),
               tr("Expanded uncertainty")], rows)
    doc.para(f"{tr('Measurement uncertainty of the angle-position error')}: U = {c['U_E']}, k = "
             f"{c['k_E']}")
    doc.heading(tr("Notes on the results"), 2)
    D.notes_section(doc, ctx)
    doc.heading(tr("Measurement standards used and their traceability"), 2)
    D.equipment_table(doc, ctx)
    doc.heading(tr("Signatures"), 2)
    D.signatures(doc, D.signatory_rows(f, [tr("Calibrated by"), tr("Checked by"), tr("Issued by")]),
                 titled=True)
    doc.para(tr("The calibration results relate only to the item calibrated."), size=8.5)
    doc.para(tr("Recommended recalibration interval: {interval}",
                interval=tr.msg("at most 12 months")), size=8.5)
    D.annexes(doc, ctx)

"""Certificate data for JJF 2014—2022 (clause 8 a)–p), appendix A inner page):
``context["jjf2014"]``.

The 24 rows of appendix A map to the metrics of the items (table 3).  A row whose item was
not run in this record says so ("未检测 not performed") — never blank, never zero.
Laboratory, customer, signatories and dates come from the report context's ``facts``
(:func:`metro.core.documents.context.record_facts`: the campaign, and the lab profile when one is
given); a missing one is shown as "—" so a reviewer sees it is missing.  :func:`layout` lays out
clause 8 a)–p) (each field marked with its letter in the code) and the appendix A inner page.
"""

from __future__ import annotations

from typing import Any

from metro.api import group_notes, join

#: appendix A rows: (no., 校准项目, English, item, metric key)
ROWS = (
    (1, "标度因数", "scale factor", "7.2.1", "K"),
    (2, "标度因数非线性度", "scale-factor nonlinearity", "7.2.2", "Kn"),
    (3, "量程", "range", "7.2.2", "range"),
    (4, "标度因数不对称度", "scale-factor asymmetry", "7.2.3", "Ka"),
    (5, "标度因数重复性", "scale-factor repeatability", "7.2.4", "Kr"),
    (6, "标度因数温度灵敏度", "scale-factor temperature sensitivity", "7.2.5", "Kt"),
    (7, "标度因数轴向加速度敏感度", "scale-factor axial-acceleration sensitivity", "7.2.6", "Kg"),
    (8, "标度因数冲击前后变化量", "scale-factor change after shock", "7.2.7", "dK_shock"),
    (9, "标度因数振动前后变化量", "scale-factor change after vibration", "7.2.8", "dK_vib"),
    (10, "阈值", "threshold", "7.2.9", "threshold"),
    (11, "分辨率", "resolution", "7.2.10", "resolution"),
    (12, "输入轴失准角", "input-axis misalignment", "7.2.11", "gamma"),
    (13, "输入轴失准角重复性", "input-axis misalignment repeatability", "7.2.12", "gamma_r"),
    (14, "零偏", "bias", "7.2.13", "B0"),
    (15, "零偏稳定性", "bias stability", "7.2.14", "Bs"),
    (16, "零偏重复性", "bias repeatability", "7.2.15", "Br"),
    (17, "零偏温度灵敏度", "bias temperature sensitivity", "7.2.16", "Bt"),
    (18, "零偏加速度灵敏度", "bias acceleration sensitivity", "7.2.17", "Bg"),
    (19, "零偏冲击前后变化量", "bias change after shock", "7.2.18", "dB_shock"),
    (20, "零偏振动前后变化量", "bias change after vibration", "7.2.19", "dB_vib"),
    (21, "角度随机游走系数", "angle random walk", "7.2.20", "ARW"),
    (22, "带宽", "bandwidth", "7.2.21", "Bw"),
    (23, "输出延迟时间", "output delay", "7.2.22", "Td"),
    (24, "启动时间", "start-up time", "7.2.23", "t_startup"),
)

NOT_PERFORMED = "not performed"
DASH = "—"
SPECIFICATION_CN = "JJF 2014—2022 金属振子式速率陀螺校准规范"
SPECIFICATION_EN = ("JJF 2014—2022 Calibration Specification for Metal-Shell Vibratory Rate "
                    "Gyroscopes")


def certificate_rows(outcomes) -> list[dict[str, Any]]:
    """The 24 appendix-A rows, each {no, item_cn, item_en, clause, performed, reportable, reason,
    value, U, k, note, earth_rate, symbol}; value and U as :meth:`Result.reported` rounds them."""
    from metro.api import result_fields

    found = {}
    for o in outcomes:
        if o.standard != "jjf2014":
            continue
        for r in o.results:
            found[(o.item, r.metric.key)] = r
    rows = []
    for no, cn, en, item, key in ROWS:
        r = found.get((item, key))
        base = {"no": str(no), "item_cn": cn, "item_en": en, "clause": item}
        if r is None:
            rows.append(base | {"performed": False, "reportable": True, "reason": "", "value": "",
                                "U": "",
                                "k": "", "note": "", "earth_rate": "", "symbol": ""})
            continue
        row = result_fields(r)
        rows.append(base | {"performed": True, "reportable": row["reportable"],
                            "reason": row["reason"],
                            "value": row["value_unit"], "U": row["U_unit"], "k": row["k"],
                            "note": r.note,
                            "earth_rate": row["earth_rate"], "symbol": r.metric.symbol})
    return rows


def extend_context(record, context: dict) -> None:
    """metro_extend_report_context for JJF 2014: adds ``context["jjf2014"]``."""
    outs = [o for o in record.outcomes if o.standard == "jjf2014"]
    if not outs:
        return
    rows = certificate_rows(outs)
    context["jjf2014"] = {
        "number": record.report_number,
        "rows": rows,
        "performed_count": sum(r["performed"] for r in rows),
        # a warning several items share (the same missing repeat data) once, naming them
        "deviations": [join(": ", [where, w]) for where, w
                       in group_notes((o.item, "", w) for o in outs for w in o.warnings)],
    }


def _env(ctx: dict, name: str) -> str:
    for n in ctx["environment"]:
        if n["name"].lower() == name:
            return n["value"]
    return DASH


def layout(doc, ctx: dict) -> None:
    """JJF 2014—2022 calibration certificate: clause 8 a)–p) and the appendix A inner page."""
    from metro.api import document as D

    c = ctx.get("jjf2014")
    if c is None:
        D.generic_layout(doc, ctx)
        return
    tr, f, dev = doc.tr, ctx["facts"], ctx["device"]
    doc.title_block(tr("Calibration certificate"))                                  # 8 a)
    doc.kv([
        (tr("Certificate No."), c["number"]),                                      # 8 d)
        (tr("Laboratory"), D.or_dash(f["lab"])),                                  # 8 b)
        (tr("Laboratory address"), D.or_dash(f["lab_address"])),
        (tr("Place of calibration"), D.or_dash(f["location"] or f["lab_address"])),  # 8 c)
        (tr("Customer"), D.or_dash(f["customer"])),                               # 8 e)
        (tr("Customer address"), D.or_dash(f["customer_address"])),
        (tr("Instrument calibrated"),                                             # 8 f)
         f"{tr.pick('金属振子式速率陀螺', 'metal-shell vibratory rate gyroscope')}: "
         f"{tr.text(dev['description'])} ({tr('id')} {dev['id']})"),
        (tr("Date of calibration"), D.or_dash(f["measured"])),                    # 8 g)
        (tr("Date received"), D.or_dash(f["received"])),
        (tr("Date of issue"), D.or_dash(f["issued"])),
        (tr("Sampling"), tr("none: the item named above was calibrated")),          # 8 h)
        (tr("Calibration specification"), tr.pick(SPECIFICATION_CN, SPECIFICATION_EN)),  # 8 i)
    ])
    # appendix A inner page: environment, then the 24 rows                           8 k), 8 l)
    doc.heading(tr("Calibration results"), 1)
    doc.kv([(tr("Temperature"), _env(ctx, "temperature")), (tr("Place"), D.or_dash(f["location"])),
            (tr("Relative humidity"), _env(ctx, "humidity")), (tr("Other"), _env(ctx, "other"))])
    rows = []
    for r in c["rows"]:
        if not r["performed"]:
            value, U = tr(NOT_PERFORMED), DASH
        elif not r["reportable"]:
            value, U = D.not_reportable(tr, r["reason"]), DASH
        else:
            value = r["value"]
            U = f"U = {r['U']} (k = {r['k']})" if r["U"] not in ("", DASH) else tr("not evaluated")
        item = tr.pick(r["item_cn"], r["item_en"]) + (f" {r['symbol']}" if r["symbol"] else "")
        rows.append([r["no"], item, value, U])
    doc.table([tr("No."), tr("Calibration item"), tr("Calibration result"),
               tr("Expanded uncertainty")], rows)
    doc.heading(tr("Notes on the results"), 2)                                     # 8 l)
    D.notes_section(doc, ctx, include_warnings=False)
    doc.heading(tr("Measurement standards used and their traceability"), 2)         # 8 j)
    D.equipment_table(doc, ctx)
    doc.heading(tr("Deviations from the specification"), 2)                         # 8 m)
    if c["deviations"]:
        doc.bullets(c["deviations"], size=8.5)
    else:
        doc.para(tr("none"))
    # 8 n), appendix A
    doc.heading(tr("Signatures"), 2)
    D.signatures(doc, D.signatory_rows(f, [tr("Calibrated by"), tr("Checked by"), tr("Issued by")]),
                 titled=True)
    # 8 o)
    doc.para(tr("The calibration results relate only to the item calibrated."), size=8.5)
    # 8 p)
    doc.para(tr("This certificate shall not be reproduced except in full without the written "
                "approval of the laboratory."), size=8.5)
    # clause 9
    doc.para(tr("Recommended recalibration interval: {interval}", interval=tr.msg("1 year")),
             size=8.5)
    D.annexes(doc, ctx)

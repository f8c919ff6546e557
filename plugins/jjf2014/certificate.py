"""Certificate data for JJF 2014—2022 (clause 8 a)–p), appendix A inner page): ``context["jjf2014"]``.

The 24 rows of appendix A map to the metrics of the items (table 3).  A row whose item was
not run in this record says so ("未校准 / not performed") — never blank, never zero.
Laboratory, customer and signatories come from the manifest's ``[campaign]`` table
(read through the vocabulary, metro.core.vocabulary: ``lab``, ``lab_address``, ``location``,
``customer``, ``customer_address``, ``date_received``, ``measurement_date``, ``operator`` (the
"calibrated by"), ``checked_by``, ``approved_by``); a missing one is shown as
"—" so a reviewer sees it is missing.
"""

from __future__ import annotations

from typing import Any

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

NOT_PERFORMED = "未校准 (not performed)"
DASH = "—"

STATEMENT_VALIDITY = "本证书的校准结果仅对被校对象有效。The calibration results relate only to the item calibrated."
STATEMENT_COPY = ("未经实验室书面批准，不得部分复制本证书。This certificate shall not be reproduced except in full "
                  "without the written approval of the laboratory.")


def _unit_text(u: str) -> str:
    from metro.core.units import fmt_unit, unit

    return fmt_unit(unit(u)) if u else ""


def result_text(r) -> tuple[str, str]:
    """(value with unit, 'U = … (k = …)') as reported (JJF 1059.1 rounding)."""
    v, U = r.reported()
    ut = _unit_text(r.metric.unit)
    val = f"{v} {ut}".strip()
    if U is None:
        return val, "U not evaluated"
    return val, f"U = {U} {ut} (k = {r.k:g})".replace("  ", " ")


def certificate_rows(outcomes) -> list[dict[str, Any]]:
    """The 24 appendix-A rows, each {no, item_cn, item_en, clause, performed, value, U, note}."""
    found = {}
    for o in outcomes:
        if o.standard != "jjf2014":
            continue
        for r in o.results:
            found[(o.item, r.metric.key)] = r
    rows = []
    for no, cn, en, item, key in ROWS:
        r = found.get((item, key))
        if r is None:
            rows.append({"no": str(no), "item_cn": cn, "item_en": en, "clause": item, "performed": False,
                         "value": NOT_PERFORMED, "U": "", "note": ""})
        else:
            v, U = result_text(r)
            rows.append({"no": str(no), "item_cn": cn, "item_en": en, "clause": item, "performed": True,
                         "value": v, "U": U, "note": r.note})
    return rows


def extend_context(record, context: dict) -> None:
    """metro_extend_report_context for JJF 2014: adds ``context["jjf2014"]``."""
    outs = [o for o in record.outcomes if o.standard == "jjf2014"]
    if not outs:
        return
    camp = record.campaign
    env = dict(camp.environment)
    people, lab, customer = camp.people, camp.lab, camp.customer

    def m(v):
        return str(v) if v not in (None, "") else DASH

    def e(key):
        from metro.core.report import fmt_quantity

        import pint

        v = env.get(key)
        if v is None:
            return DASH
        return fmt_quantity(v) if isinstance(v, pint.Quantity) else str(v)

    deviations = []
    for o in outs:
        deviations += [f"{o.item}: {w}" for w in o.warnings]
    if record.simulated or camp.simulated:
        deviations.insert(0, "SIMULATED data (simulated-jjf2014 station): not a calibration of a real device.")
    rows = certificate_rows(outs)
    context["jjf2014"] = {
        "title": "校准证书 Calibration Certificate",
        "number": record.report_number,
        "lab": m(lab.name), "lab_address": m(lab.address), "location": m(lab.location),
        "customer": m(customer.name), "customer_address": m(customer.address),
        "received": m(camp.date_received and camp.date_received.isoformat()),
        "calibrated_on": camp.measurement_date.isoformat() if camp.measurement_date else context.get("created", DASH),
        "specification": "JJF 2014—2022 金属振子式速率陀螺校准规范",
        "environment": {"temperature": e("temperature"), "humidity": e("humidity"),
                        "location": m(lab.location) if "location" not in env else str(env["location"]),
                        "other": e("other")},
        "rows": rows,
        "performed_count": str(sum(r["performed"] for r in rows)),
        "not_performed": [r["no"] for r in rows if not r["performed"]],
        "deviations": deviations or ["无 (none)"],
        "calibrated_by": m(people.operator), "checked_by": m(people.checked_by), "approved_by": m(people.approved_by),
        "statement_validity": STATEMENT_VALIDITY,
        "statement_copy": STATEMENT_COPY,
    }

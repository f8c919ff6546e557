"""Report-context entries for the draft's appendix B certificate inner page (key ``ogam``)."""

from __future__ import annotations

from typing import Any

from metro.core.units import fmt_unit

#: appendix B rows: (no., certificate wording, item id, metric key)
ROWS = (
    ("1", "标度因数 K (scale factor)", "7.1", "K"),
    ("2", "标度因数线性度 K_l (scale-factor linearity)", "7.2", "Kl"),
    ("3", "零位漂移 B_s (zero stability)", "7.3", "Bs"),
    ("4", "角位置测量偏差 E (angle-position error)", "7.4", "E"),
    ("5", "角位置测量重复性 R (repeatability)", "7.5", "R"),
    ("6", "速率一致性 C_v (rate consistency)", "7.6", "Cv"),
    ("7", "指向一致性 C_g (pointing consistency)", "7.7", "Cg"),
)
NOT_CALIBRATED = "— (not calibrated)"


def _unit(result) -> str:
    u = fmt_unit(result.metric.unit)
    return {"percent": "%", "arcsec": "″"}.get(u, u)


def certificate_context(record) -> dict[str, Any]:
    """{designation, rows [{no, item, result}], U_E, k_E, environment_text, equipment_text, warnings}."""
    results = {(o.item, r.metric.key): r for o in record.outcomes if o.standard == "ogam" for r in o.results}
    rows = []
    U_E, k_E = "—", "2"
    for no, label, item, key in ROWS:
        r = results.get((item, key))
        if r is None:
            text = NOT_CALIBRATED
        else:
            v, _ = r.reported()
            unit = _unit(r)
            text = f"±{v}{unit}" if key == "E" else f"{v} {unit}".replace(" ″", "″")
            if key == "E" and r.U is not None:
                _, U_E = r.reported()
                U_E += "″"
                k_E = f"{r.k:g}"
        rows.append({"no": no, "item": label, "result": text})
    camp = record.campaign
    env = "; ".join(f"{k} {v:~P}" if hasattr(v, "units") else f"{k} {v}" for k, v in camp.environment.items())
    eq = "; ".join(f"{e.describe()} ({e.status()})" for e in camp.equipment)
    # one note per distinct warning, naming the items it came from (7.6 and 7.7 share the E budget)
    by_text: dict[str, list[str]] = {}
    for o in record.outcomes:
        if o.standard == "ogam":
            for w in o.warnings:
                by_text.setdefault(w, []).append(o.item)
    warnings = [f"{', '.join(items)}: {w}" for w, items in by_text.items()]
    return {"designation": "JJF xxxx—xxxx 光学陀螺测角仪校准规范 (征求意见稿)", "rows": rows, "U_E": U_E, "k_E": k_E,
            "environment_text": env or "—", "equipment_text": eq or "—", "warnings": warnings}

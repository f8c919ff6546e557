"""GB/T 45570—2025 test report data: ``context["gbt45570"]`` for ``templates/report.docx``.

Adds to the generic report context (:func:`metro.core.report.report_context`): laboratory
and customer (manifest ``[campaign]`` keys read through metro.core.vocabulary: ``lab``,
``lab_address``, ``customer``, ``customer_address``, ``operator`` (the "tested by"),
``checked_by``, ``approved_by``, ``measurement_date``; a missing one prints "—"), the 6.1.1 test environment checked against its limits, the method choice of 6.2.7.1
and the items ``--all``/series chose, the conformity verdicts with the decision rule and
their reasons, the typical-limit table of the device (A.1 or B.1) row by row — "not
performed" where no result exists, never a zero — the C.1 severities, a residual figure of
K_i about the eq. (D.4) fit, and one SHA-256 over all data digests.
"""

from __future__ import annotations

import hashlib
from typing import Any

import numpy as np

from metro.core.budget import report_pair
from metro.core.conformity import SIMPLE, Comparison, Specification, decide
from metro.core.model import PlotSpec
from metro.core.units import Q_

from .conformity import APPLICATION_CN, TABLE_C1, application_of, table_for
from .method_rule import ANGLE_ITEMS, RATE_ITEMS, method_for

STANDARD = "gbt45570"
DASH = "—"
NOT_PERFORMED = "未检测 (not performed)"
TITLE = "试验报告 Test report — GB/T 45570—2025 光学陀螺仪通用技术要求"

#: 6.1.1 试验环境: (environment key, label, specification)
ENVIRONMENT = (
    ("temperature", "温度 Temperature (6.1.1 a)",
     Specification("temperature", Comparison.RANGE, Q_(15, "degC"), Q_(35, "degC"), source="GB/T 45570—2025 6.1.1 a)")),
    ("humidity", "相对湿度 Relative humidity (6.1.1 b)",
     Specification("humidity", Comparison.RANGE, Q_(20, "percent"), Q_(80, "percent"),
                   source="GB/T 45570—2025 6.1.1 b)")),
    ("magnetic_field", "磁场强度 Magnetic field (6.1.1 d)",
     Specification("magnetic_field", Comparison.AT_MOST, Q_(1e-4, "T"), source="GB/T 45570—2025 6.1.1 d)",
                   magnitude=True)),
)
STATUS_TEXT = {"pass": "合格 conforms", "fail": "不合格 does not conform", "indeterminate": "不确定 indeterminate"}


def _fmt_q(q: Any) -> str:
    from metro.core.report import fmt_quantity

    return fmt_quantity(q)


def environment_rows(env: dict) -> list[dict[str, str]]:
    """6.1.1 a), b), d) checked (simple acceptance: the conditions are recorded values); c) is the
    site's pressure, reported as given."""
    rows = []
    for key, label, spec in ENVIRONMENT:
        v = env.get(key)
        if v is None or not hasattr(v, "magnitude"):
            rows.append({"name": label, "required": spec.text(), "measured": "not recorded", "verdict": DASH})
            continue
        verdict = decide(spec, v, None, SIMPLE)
        rows.append({"name": label, "required": spec.text(), "measured": _fmt_q(v),
                     "verdict": STATUS_TEXT[verdict.status.value]})
    p = env.get("pressure")
    rows.insert(2, {"name": "大气压力 Pressure (6.1.1 c)", "required": "the site's pressure",
                    "measured": _fmt_q(p) if p is not None else "not recorded", "verdict": DASH})
    return rows


def _result_cells(r) -> tuple[str, str, str]:
    from metro.core.report import _unit_text

    v, U = r.reported()
    ut = _unit_text(r.metric.unit)
    k = DASH if r.k is None else f"{r.k:.2f}"
    return f"{v} {ut}".strip(), (f"{U} {ut}".strip() if U is not None else DASH), k


def verdict_rows(assessment) -> list[dict[str, str]]:
    from metro.core.report import fmt_num

    from metro.core.units import fmt_unit

    rows = []
    for v in assessment.verdicts:
        ut = fmt_unit(v.spec.limit.units)
        ut = "" if ut == "1" else f" {ut}"
        value, U = v.in_limit_unit()
        if U is not None and U > 0:  # rounded as the results are (JJF 1059.1: U to 2 digits)
            rv, rU = report_pair(value, U)
            vtext, Utext = rv.text + ut, rU.text + ut
        else:
            vtext, Utext = fmt_num(value, 6) + ut, (DASH if U is None else "0" + ut)
        rows.append({
            "item": v.item, "key": v.key, "limit": v.spec.text(), "source": v.spec.source,
            "value": vtext,
            "U": Utext,
            "k": DASH if v.k is None else f"{v.k:.2f}",
            "status": v.status.value, "status_text": STATUS_TEXT[v.status.value],
            "detail": v.detail, "reason": v.reason,
        })
    return rows


def limit_table(device, outcomes, assessment) -> dict[str, Any] | None:
    """The device's A.1/B.1 table for its application, each row with its results or "not performed"."""
    rows = table_for(device.technology)
    app = application_of(device.application)
    if rows is None or app is None:
        return None
    verdicts = {} if assessment is None else {(v.item, v.key, v.spec.symbol): v for v in assessment.verdicts}
    found = [(o, r) for o in outcomes if o.standard == STANDARD for r in o.results]
    out = []
    for row in rows:
        spec = row.specification(app)
        mine = [(o, r) for o, r in found if spec.applies_to(r.metric.key, o.item)]
        if not mine:
            out.append({"no": str(row.no), "name": f"{row.name_cn} {row.name_en}", "limit": spec.text(),
                        "method": " / ".join(row.items), "result": NOT_PERFORMED, "verdict": DASH})
            continue
        for o, r in mine:
            val, U, k = _result_cells(r)
            v = verdicts.get((o.item, r.metric.key, row.key))
            out.append({"no": str(row.no), "name": f"{row.name_cn} {row.name_en} ({r.metric.symbol})",
                        "limit": spec.text(), "method": o.item,
                        "result": f"{val}, U = {U} (k = {k})" if U != DASH else val,
                        "verdict": STATUS_TEXT[v.status.value] if v is not None else DASH})
    table = rows[0].table
    kind = "laser" if table == "A.1" else "fibre"
    return {"table": table, "application": f"{APPLICATION_CN[app]} {app}",
            "title": f"Table {table} — typical {kind}-gyro indices, {APPLICATION_CN[app]} {app} "
                     "(GB/T 45570—2025, informative appendix)", "rows": out}


def severity_rows(device, outcomes) -> list[dict[str, str]]:
    app = application_of(device.application)
    if app is None:
        return []
    done = {o.item for o in outcomes if o.standard == STANDARD}
    rows = []
    for r in TABLE_C1:
        if not r.items:
            status = "no test method in appendix D (product specification)"
        elif done & set(r.items):
            status = "performed: " + ", ".join(sorted(done & set(r.items)))
        else:
            status = NOT_PERFORMED
        rows.append({"no": str(r.no), "name": f"{r.name_cn} {r.name_en}", "severity": r.text(app),
                     "method": ", ".join(r.items) or DASH, "status": status})
    return rows


def method_text(record) -> str:
    """Which method 6.2.7.1 chose and why (only when a scale-factor item is in the report)."""
    items = {o.item for o in record.outcomes if o.standard == STANDARD}
    if not items & set(ANGLE_ITEMS + RATE_ITEMS):
        return ""
    method, why = method_for(record.campaign.device)
    return f"Scale-factor series by the {method} method ({'D.1' if method == 'angle' else 'D.2'}): {why}."


def residual_plot(spec: PlotSpec) -> PlotSpec | None:
    """K_i − (K + WΩ_i) in ppm of the fit, from the K_rate figure's points and fit line."""
    pts = next((s for s in spec.series if s.get("style") == "o"), None)
    fit = next((s for s in spec.series if s.get("style") == "-"), None)
    if pts is None or fit is None:
        return None
    x = np.asarray(pts["x"], dtype=float)
    k_i, model = np.asarray(pts["y"], dtype=float), np.asarray(fit["y"], dtype=float)
    if k_i.shape != model.shape or not np.all(model != 0):
        return None
    series = [{"label": "K_i − (K + WΩ_i)", "x": x.tolist(), "y": ((k_i - model) / model * 1e6).tolist(),
               "style": "o"}]
    if pts.get("yerr") is not None:
        series[0]["yerr"] = (np.asarray(pts["yerr"], dtype=float) / model * 1e6).tolist()
    series.append({"x": [float(x.min()), float(x.max())], "y": [0.0, 0.0], "style": "--"})
    return PlotSpec("K_residuals", "Residuals of K_i about the eq. (D.4) fit", spec.xlabel, "residual (ppm of K)",
                    series, logx=spec.logx)


def _add_residual_figures(context: dict) -> None:
    from metro.core.report import plot_caption

    n = 1
    for o in context.get("outcomes", []):
        plots = []
        for p in o["plots"]:
            plots.append(p)
            if p["name"] == "K_rate" and o["standard"] == STANDARD:
                extra = residual_plot(p["spec"])
                if extra is not None:
                    plots.append({"number": 0, "name": extra.name, "title": extra.title,
                                  "caption": plot_caption(extra.title, o["item"]), "spec": extra, "image": None})
        for p in plots:
            p["number"] = n
            n += 1
        o["plots"] = plots


def data_digest(files: list[dict[str, str]]) -> str:
    """One SHA-256 over the sorted 'sha256  file' lines of every data file (or segment)."""
    lines = sorted(f"{f['sha256']}  {f['file']}\n" for f in files if f.get("sha256"))
    return hashlib.sha256("".join(lines).encode("utf-8")).hexdigest() if lines else DASH


#: Keys of one row of the clause-5 table (GB/T 45570—2025 clause 5 requirements), in column order.
CLAUSE5_FIELDS = ("clause", "requirement", "result", "verdict", "note")


def clause5_rows(record) -> list[dict[str, str]]:
    """The clause-5 table: one row per clause-5 requirement, each a dict with the keys of
    :data:`CLAUSE5_FIELDS` (all text; ``verdict`` e.g. "合格 conforms" or "未检测 (not performed)").

    The rows come from ``metro.plugins.gbt45570.clause5.clause5_rows(record)`` when that module
    exists (it is written by the clause-5 work); until then the table is empty and not printed."""
    import importlib.util

    if importlib.util.find_spec(f"{__package__}.clause5") is None:
        return []
    from . import clause5  # type: ignore[attr-defined]

    rows = [dict(r) for r in clause5.clause5_rows(record)]
    for r in rows:
        missing = [k for k in CLAUSE5_FIELDS[:4] if k not in r]
        if missing:
            raise ValueError(f"clause-5 row {r!r} lacks {', '.join(missing)}")
        r.setdefault("note", "")
    return rows


def extend_context(record, context: dict) -> None:
    """metro_extend_report_context for GB/T 45570: adds ``context["gbt45570"]``."""
    outs = [o for o in record.outcomes if o.standard == STANDARD]
    if not outs:
        return
    camp = record.campaign
    people, lab, customer = camp.people, camp.lab, camp.customer

    def m(v: str) -> str:
        return v or DASH

    a = record.conformity
    deviations = [f"{o.item}: {w}" for o in outs for w in o.warnings]
    if record.simulated or camp.simulated:
        deviations.insert(0, "SIMULATED data (built-in simulated station): not a test of a real device.")
    _add_residual_figures(context)
    selection = [{"item": c.item, "run": "run" if c.run else "not run", "reason": c.reason, "via": c.via}
                 for c in record.selection]
    context["gbt45570"] = {
        "title": TITLE,
        "number": record.report_number,
        "lab": m(lab.name), "lab_address": m(lab.address), "customer": m(customer.name),
        "customer_address": m(customer.address),
        "tested_on": camp.measurement_date.isoformat() if camp.measurement_date else context.get("created", DASH),
        "tested_by": m(people.operator), "checked_by": m(people.checked_by), "approved_by": m(people.approved_by),
        "device_application": (f"{camp.device.technology or DASH} gyro, application "
                               f"{camp.device.application or DASH}"),
        "environment": environment_rows(dict(camp.environment)),
        "method": method_text(record),
        "selection": selection,
        "has_conformity": a is not None,
        "rule": {"name": a.rule.name, "title": a.rule.title, "statement": a.rule.statement} if a else
                {"name": DASH, "title": "no specification given", "statement":
                 "No specification applies (device technology or application not given, and no [specification] "
                 "in the manifest): no conformity statement is made."},
        "overall": STATUS_TEXT[a.overall.value] if a is not None and a.overall is not None else DASH,
        "counts": ", ".join(f"{n} {s}" for s, n in a.counts().items()) if a is not None else DASH,
        "verdicts": verdict_rows(a) if a is not None else [],
        "not_assessed": [f"{s.symbol} {s.text()} ({s.source})" for s in a.not_assessed] if a is not None else [],
        "limits": limit_table(camp.device, outs, a),
        "severities": severity_rows(camp.device, outs),
        "data_digest": data_digest(context.get("provenance", {}).get("data_files", [])),
        "deviations": deviations or ["无 (none)"],
        "clause5": clause5_rows(record),
    }

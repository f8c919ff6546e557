"""GB/T 45570—2025 test report: ``context["gbt45570"]`` and the document :func:`layout`.

Adds to the generic report context (:func:`metro.core.documents.context.report_context`, whose
``facts``
carry laboratory, customer, people and dates): the 6.1.1 test environment checked against its
limits, the method choice of 6.2.7.1
and the items ``--all``/series chose, the conformity verdicts with the decision rule and
their reasons, the typical-limit table of the device (A.1 or B.1) row by row — "not
performed" where no result exists, never a zero — the C.1 severities, a residual figure of
K_i about the eq. (D.4) fit, and one SHA-256 over all data digests.
"""

from __future__ import annotations

import hashlib
import re
from typing import Any, Iterable

import numpy as np
from metro.api import (Q_, SIMPLE, Comparison, PlotSpec, Specification, Text, decide, group_notes,
                       join, msg, report_pair)

from .conformity import (APPLICATION_CN, CLAUSE_SOURCE, CLAUSE_WHY_SOURCE, PRODUCT_SOURCE,
                         REMARK_SOURCE, ROW_SOURCE, TABLE_C1, application_of, table_for)
from .method_rule import ANGLE_ITEMS, RATE_ITEMS, method_for

STANDARD = "gbt45570"
DASH = "—"
NOT_PERFORMED = "not performed"
TITLE = "试验报告 Test report — GB/T 45570—2025 光学陀螺仪通用技术要求"

#: 6.1.1 试验环境: (environment key, label (a message id), clause, specification)
ENVIRONMENT = (
    ("temperature", "Temperature", "6.1.1 a)",
     Specification("temperature", Comparison.RANGE, Q_(15, "degC"), Q_(35, "degC"),
                   source="GB/T 45570—2025 6.1.1 a)")),
    ("humidity", "Relative humidity", "6.1.1 b)",
     Specification("humidity", Comparison.RANGE, Q_(20, "percent"), Q_(80, "percent"),
                   source="GB/T 45570—2025 6.1.1 b)")),
    ("magnetic_field", "Magnetic field", "6.1.1 d)",
     Specification("magnetic_field", Comparison.AT_MOST, Q_(1e-4, "T"),
                   source="GB/T 45570—2025 6.1.1 d)",
                   magnitude=True)),
)
#: verdicts as the catalog's message ids (translated by the layout)
STATUS_TEXT = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate"}
#: the verdict on a result that is not reportable: no statement is made
#: (core.conformity.not_reportable)
NO_STATEMENT = "no statement (not reportable)"


def verdict_text(v) -> str:
    """A verdict's words: ``STATUS_TEXT``, or ``NO_STATEMENT`` for a result that is not
    reportable."""
    return NO_STATEMENT if v.detail == "not reportable" else STATUS_TEXT[v.status.value]


def _fmt_q(q: Any) -> str:
    from metro.api import fmt_quantity

    return fmt_quantity(q)


def environment_rows(env: dict) -> list[dict[str, str]]:
    """6.1.1 a), b), d) checked (simple acceptance: the conditions are recorded values); c) is the
    site's pressure, reported as given."""
    rows = []
    for key, label, clause, spec in ENVIRONMENT:
        v = env.get(key)
        if v is None or not hasattr(v, "magnitude"):
            rows.append({"name": label, "clause": clause, "required": spec.text(),
                         "measured": "not recorded",
                         "verdict": ""})
            continue
        verdict = decide(spec, v, None, SIMPLE)
        rows.append({"name": label, "clause": clause, "required": spec.text(),
                     "measured": _fmt_q(v),
                     "verdict": STATUS_TEXT[verdict.status.value]})
    p = env.get("pressure")
    rows.insert(2, {"name": "Atmospheric pressure", "clause": "6.1.1 c)",
                    "required": "the site's pressure",
                    "measured": _fmt_q(p) if p is not None else "not recorded", "verdict": ""})
    return rows


def _result_cells(r) -> tuple[str, str, str]:
    from metro.api import unit_text

    v, U = r.reported()
    ut = unit_text(r.metric.unit)
    k = DASH if r.k is None else f"{r.k:.2f}"
    return f"{v} {ut}".strip(), (f"{U} {ut}".strip() if U is not None else DASH), k


def verdict_rows(assessment) -> list[dict[str, str]]:
    from metro.api import fmt_num, fmt_unit

    rows = []
    for v in assessment.verdicts:
        ut = fmt_unit(v.spec.limit.units)
        ut = "" if ut == "1" else f" {ut}"
        value, U = v.in_limit_unit()
        if v.detail == "not reportable":  # the value is not issued: the results table says why
            vtext, Utext = "not reportable", DASH
        elif U is not None and U > 0:  # rounded as the results are (JJF 1059.1: U to 2 digits)
            rv, rU = report_pair(value, U)
            vtext, Utext = rv.text + ut, rU.text + ut
        else:
            vtext, Utext = fmt_num(value, 6) + ut, (DASH if U is None else "0" + ut)
        rows.append({
            "item": v.item, "key": v.key, "limit": v.spec.text(), "source": v.spec.source,
            "value": vtext,
            "U": Utext,
            "k": DASH if v.k is None else f"{v.k:.2f}",
            "status": v.status.value, "status_text": verdict_text(v),
            "detail": v.detail, "reason": v.reason,
        })
    return rows


def limit_table(device, outcomes, assessment) -> dict[str, Any] | None:
    """The device's A.1/B.1 table for its application, each row with its results or "not
    performed"."""
    rows = table_for(device.technology)
    app = application_of(device.application)
    if rows is None or app is None:
        return None
    verdicts = {} if assessment is None else {(v.item, v.key,
                                               v.spec.symbol): v for v in assessment.verdicts}
    found = [(o, r) for o in outcomes if o.standard == STANDARD for r in o.results]
    out = []
    for row in rows:
        spec = row.specification(app)
        mine = [(o, r) for o, r in found if spec.applies_to(r.metric.key, o.item)]
        if not mine:
            out.append({"no": str(row.no), "name": f"{row.name_cn} {row.name_en}",
                        "name_cn": row.name_cn,
                        "name_en": row.name_en, "symbol": "", "limit": spec.text(),
                        "method": " / ".join(row.items), "result": NOT_PERFORMED, "verdict": "",
                        "performed": False})
            continue
        for o, r in mine:
            val, U, k = _result_cells(r)
            # judged by the row (``Bs``) or by a limit on this result's own key (row 10 at t = 100
            # s: ``Bs_100s``)
            v = verdicts.get((o.item, r.metric.key, row.key)) or verdicts.get((o.item, r.metric.key,
                                                                               r.metric.key))
            # the bound is what is issued (D.4: threshold ≤ H); the results table says why
            if getattr(r, "bound", ""):
                result = (f"{r.bound_sign} {val}, U = {U} (k = {k})" if U != DASH else
                          f"{r.bound_sign} {val}")
            elif not getattr(r, "reportable", True):
                # the results table gives the value and why it is not issued
                result = "not reportable"
            else:
                result = f"{val}, U = {U} (k = {k})" if U != DASH else val
            out.append({"no": str(row.no),
                        "name": f"{row.name_cn} {row.name_en} ({r.metric.symbol})",
                        "name_cn": row.name_cn, "name_en": row.name_en, "symbol": r.metric.symbol,
                        "limit": spec.text(), "method": o.item, "result": result,
                        "verdict": verdict_text(v) if v is not None else "", "performed": True})
    table = rows[0].table
    kind = "laser" if table == "A.1" else "fibre"
    return {"table": table, "application": f"{APPLICATION_CN[app]} {app}", "kind": kind, "app": app,
            "app_cn": APPLICATION_CN[app],
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
            status, which = "no test method in appendix D (product specification)", ""
        elif done & set(r.items):
            status, which = "performed", ", ".join(sorted(done & set(r.items)))
        else:
            status, which = NOT_PERFORMED, ""
        rows.append({"no": str(r.no), "name": f"{r.name_cn} {r.name_en}", "name_cn": r.name_cn,
                     "name_en": r.name_en,
                     "severity": r.text(app), "method": ", ".join(r.items) or DASH,
                     "status": status,
                     "performed_items": which})
    return rows


def method_text(record) -> str:
    """Which method 6.2.7.1 chose and why (only when a scale-factor item is in the report)."""
    items = {o.item for o in record.outcomes if o.standard == STANDARD}
    if not items & set(ANGLE_ITEMS + RATE_ITEMS):
        return ""
    method, why = method_for(record.campaign.device)
    return msg("{method}: {why}.", method="D.1" if method == "angle" else "D.2", why=why)


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
    series = [{"label": "K_i − (K + WΩ_i)", "x": x.tolist(),
               "y": ((k_i - model) / model * 1e6).tolist(),
               "style": "o"}]
    if pts.get("yerr") is not None:
        series[0]["yerr"] = (np.asarray(pts["yerr"], dtype=float) / model * 1e6).tolist()
    series.append({"x": [float(x.min()), float(x.max())], "y": [0.0, 0.0], "style": "--"})
    return PlotSpec("K_residuals", msg("Residuals of K_i about the eq. (D.4) fit"), spec.xlabel,
                    msg("residual (ppm of K)"),
                    series, logx=spec.logx)


def _add_residual_figures(context: dict) -> None:
    from metro.api import plot_caption

    n = 1
    for o in context.get("outcomes", []):
        plots = []
        for p in o["plots"]:
            if p["name"] == "K_temperature" and o["standard"] == STANDARD:
                p["spec"] = with_fit_line(p["spec"])
            plots.append(p)
            if p["name"] == "K_rate" and o["standard"] == STANDARD:
                extra = residual_plot(p["spec"])
                if extra is not None:
                    plots.append({"number": 0, "name": extra.name, "title": extra.title,
                                  "caption": plot_caption(extra.title, o["item"]), "spec": extra,
                                  "image": None})
        for p in plots:
            p["number"] = n
            n += 1
        o["plots"] = plots


def with_fit_line(spec: PlotSpec) -> PlotSpec:
    """A K-against-temperature figure with the least-squares straight line through its points
    (its slope, in ppm/°C, in the legend): the points alone do not show the trend K_t sums up."""
    pts = next((s for s in spec.series if s.get("style") == "o"), None)
    if pts is None or any(s.get("style") == "-" for s in spec.series):
        return spec
    x, y = np.asarray(pts["x"], dtype=float), np.asarray(pts["y"], dtype=float)
    if x.size < 2 or np.ptp(x) == 0:
        return spec
    slope, icpt = np.polyfit(x, y, 1)
    xs = [float(x.min()), float(x.max())]
    line = {"label": msg("least-squares line, slope {slope:.3g} ppm/°C", slope=slope), "x": xs,
            "y": [float(icpt + slope * v) for v in xs], "style": "-"}
    return PlotSpec(spec.name, spec.title, spec.xlabel, spec.ylabel, list(spec.series) + [line],
                    logx=spec.logx, logy=spec.logy)


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
    # a warning several items share once, naming them (metro.core.documents.notes)
    deviations = [join(": ", [where, w]) for where, w in group_notes((o.item, "",
                                                                      w) for o in outs
                                                                     for w in o.warnings)]

    _add_residual_figures(context)
    selection = [{"item": c.item, "run": bool(c.run), "reason": c.reason} for c in record.selection]
    context["gbt45570"] = {
        "title": TITLE,
        "number": record.report_number,
        "lab": m(lab.name), "lab_address": m(lab.address), "customer": m(customer.name),
        "customer_address": m(customer.address),
        "tested_on": camp.measurement_date.isoformat() if camp.measurement_date
                           else context.get("created", DASH),
        "tested_by": m(people.operator), "checked_by": m(people.checked_by),
                           "approved_by": m(people.approved_by),
        "device_application": (f"{camp.device.technology or DASH} gyro, application "
                               f"{camp.device.application or DASH}"),
        "environment": environment_rows(dict(camp.environment)),
        "method": method_text(record),
        "selection": selection,
        "has_conformity": a is not None,
        "rule": {"name": a.rule.name, "title": a.rule.title,
                 "statement": a.rule.statement} if a else
                {"name": DASH, "title": "no specification given", "statement":
                 "No specification applies (device technology or application not given, and no "
                 "[specification] in the manifest): no conformity statement is made."},
        "overall": STATUS_TEXT[a.overall.value] if a is not None and a.overall is not None else "",
        "counts": dict(a.counts()) if a is not None else {},
        "verdicts": verdict_rows(a) if a is not None else [],
        "not_assessed": [msg("{symbol} {limit} ({source})", symbol=s.symbol, limit=s.text(),
                             source=s.source)
                         for s in a.not_assessed] if a is not None else [],
        "limits": limit_table(camp.device, outs, a),
        "severities": severity_rows(camp.device, outs),
        "data_digest": data_digest(context.get("provenance", {}).get("data_files", [])),
        "deviations": deviations,
        "clause5": clause5_rows(record),
        # a type test (--all): the clause-5 table and the whole of tables A.1/B.1 and C.1 belong
        # in it; a report of chosen items lists only what was performed
        # (--all, or a run with items of clause 5 / 6.2 beyond appendix D's performance tests)
        "type_test": any(getattr(c, "via", "") == "--all" for c in record.selection)
        or any(not o.item.startswith("D.") for o in outs),
    }


def _is(src: Any, msgid: str) -> bool:
    return isinstance(src, Text) and src.msgid == msgid


def _semi(parts: list[Any]) -> Any:
    """``a; b; c`` as one message (``a；b；c`` in Chinese): each part keeps its own message."""
    out = parts[0]
    for p in parts[1:]:
        out = msg("{a}; {b}", a=out, b=p)
    return out


def limit_sources(sources: Iterable[Any]) -> Any:
    """The sources of the limits (``Specification.source``, messages made by
    :func:`~metro.plugins.gbt45570.conformity.row_source`, ``clause_source``, ``product_source``,
    ``with_remark``), each once, merged by their fields, as one message a document prints in its
    language: the rows of one table and application as ``table A.1 rows 1–16, aviation`` (a row's
    remark kept, naming the row), the lettered items of one clause with one reason as
    ``5.4 b), d) (functional check after the test)``, GB/T 45570 named once before its parts, the
    product specification's fields in one parenthesis.  A source made otherwise (a manifest's own
    text) is printed as it is.

    ``[row_source("A.1", 1, "scale factor", "aviation"), row_source("A.1", 2, "scale factor
    nonlinearity", "aviation"), clause_source("5.2.6"), product_source("inspection.mass.limit")]`` →
    ``GB/T 45570—2025: table A.1 rows 1, 2, aviation; 5.2.6; product specification
    (inspection.mass.limit)``.
    """
    gb: dict[tuple, Any] = {}
    products: list[Any] = []
    order: list[Any] = []
    for src in dict.fromkeys(sources):
        s, remark = src, None
        if _is(s, REMARK_SOURCE):
            s, remark = s.fields["source"], s.fields["remark"]
        if _is(s, ROW_SOURCE):
            key = ("row", str(s.fields["table"]), str(s.fields["application"]))
            gb.setdefault(key, []).append((int(s.fields["row"]), remark))
            order.append("GB")
            continue
        if remark is None and (_is(s, CLAUSE_SOURCE) or _is(s, CLAUSE_WHY_SOURCE)):
            clause, why = str(s.fields["clause"]), s.fields.get("why")
            m = re.fullmatch(r"(\d+(?:\.\d+)*) ([a-z]\))", clause)
            # "5.4 b) (why)", "5.4 d) (why)" -> "5.4 b), d) (why)"
            if m is not None and why is not None:
                key = ("sub", m[1], str(why))
                gb.setdefault(key, [why]).append(m[2])
            else:
                gb.setdefault(("clause", clause, str(why)), [why])
            order.append("GB")
            continue
        if remark is None and _is(s, PRODUCT_SOURCE):
            products.append(s.fields["where"])
            order.append("PS")
            continue
        order.append(src)
    parts: list[Any] = []
    for key, val in gb.items():
        if key[0] == "row":
            rows = sorted(val, key=lambda rv: rv[0])
            nums = [r for r, _ in rows]
            text = (msg("table {table} row {row}, {application}", table=key[1], row=nums[0],
                        application=key[2])
                    if len(nums) == 1 else
                    msg("table {table} rows {rows}, {application}", table=key[1],
                        rows=_ranges(nums),
                        application=key[2]))
            remarks = [msg("row {row}: {remark}", row=r, remark=rem) for r,
                       rem in rows if rem is not None]
            parts.append(msg("{text} ({remarks})", text=text,
                             remarks=_semi(remarks)) if remarks else text)
        elif key[0] == "sub":
            parts.append(msg("{clause} {items} ({why})", clause=key[1], items=", ".join(val[1:]),
                             why=val[0]))
        else:
            parts.append(key[1] if val[0] is None else msg("{clause} ({why})", clause=key[1],
                                                           why=val[0]))
    out: list[Any] = []
    for o in dict.fromkeys(order):
        if o == "GB":
            out.append(msg("GB/T 45570—2025 {clause}", clause=parts[0]) if len(parts) == 1 else
                       msg("GB/T 45570—2025: {parts}", parts=_semi(parts)))
        elif o == "PS":
            out.append(msg("product specification ({where})", where=_semi(products)))
        else:
            out.append(o)
    return _semi(out) if out else ""


def _ranges(nums: list[int]) -> str:
    """``[1, 2, 3, 5, 8, 9, 10]`` → ``1–3, 5, 8–10``."""
    out, start = [], None
    for i, v in enumerate(nums):
        if start is None:
            start = v
        if i + 1 == len(nums) or nums[i + 1] != v + 1:
            out.append(f"{start}" if start == v else f"{start}{'–' if v > start + 1 else ', '}{v}")
            start = None
    return ", ".join(out)


def _first_results(tr, text: str, keep: int = 1) -> str:
    """The first ``keep`` result(s) of a clause-5 row (``a = 1; b = 2; c = 3``), then how many more
    the results table holds: a 5.4 test's seven results are on page 1 already."""
    parts = [p for p in re.split(r";\s+(?![^\[]*\])", text) if p]
    more = 0
    if parts and parts[-1].startswith("… and "):  # the clause-5 module's own cut
        m = re.match(r"… and (\d+) more", parts.pop())
        more = int(m.group(1)) if m else 0
    if len(parts) <= keep and not more:
        return text
    more += max(0, len(parts) - keep)
    return "; ".join(parts[:keep]) + f"; … {tr('and {n} more', n=more)}"


_GREEK = ("alpha", "beta", "gamma", "delta", "theta", "omega")


def _symbolizer(ctx: dict, tr=None):
    """A function putting result symbols in place of the code keys in free text (``Bs_10s ± U``
    → ``B_s(10 s) ± U``, ``Kn`` → ``K_n``, ``alpha`` → ``α``): keys with an underscore, a digit or
    a capital, and Greek letter names; never plain words (``mass``, ``threshold``)."""
    from metro.api import display_symbol

    found: dict[str, tuple[str, str]] = {}
    for o in ctx["outcomes"]:
        for r in o["results"]:
            key, sym = r["key"], display_symbol(r.get("symbol") or "")
            if key != sym and len(key) > 1 and (re.search(r"[_\dA-Z]", key) or key in _GREEK):
                found.setdefault(key, (sym, r.get("quantity") or ""))
    shared = {s for s, _ in found.values() if sum(1 for t, _ in found.values() if t == s) > 1}
    # a symbol several keys share (l for length, width and height) would not say which: the name
    # (a name in the document's language when a translator is given)
    names = {k: (s if s and s not in shared else (tr.text(n) if tr is not None else n))
             for k, (s, n) in found.items() if s or n}
    if not names:
        return lambda text: text
    rx = re.compile(r"(?<![\w.])(" + "|".join(sorted(map(re.escape, names), key=len,
                                                     reverse=True)) + r")(?!\w)")
    return lambda text: rx.sub(lambda m: names[m.group(1)], text)


# ----------------------------------------------------------------------------------------
# The document: GB/T 45570—2025 test report (clauses 5 and 6.1; appendices A/B, C, D)
# ----------------------------------------------------------------------------------------


def layout(doc, ctx: dict) -> None:
    """The GB/T 45570 test report: page 1 identifies the device and gives the overall verdict
    and every result; then clause 5, the 6.1 test conditions, method, conformity, the typical
    limits (A.1/B.1), the C.1 severities, notes, deviations and signatures; budgets, data,
    figures and provenance follow as annexes."""
    from metro.api import document as D

    g = ctx.get("gbt45570")
    if g is None:
        D.generic_layout(doc, ctx)
        return
    tr = doc.tr
    verdicts = _front_page(doc, ctx, g)
    D.results_table(doc, ctx, verdicts=verdicts)
    n = 1
    type_test = g.get("type_test", False)
    symbols = _symbolizer(ctx, tr)
    if g["clause5"] and type_test:
        n = _clause5_section(doc, g, symbols, n)
    n = _conditions_section(doc, ctx, g, n)
    n = _conformity_section(doc, ctx, g, symbols, n)
    n = _limits_section(doc, g, type_test, n)
    n = _severities_section(doc, g, type_test, n)
    _closing_sections(doc, ctx, g, n)


def _front_page(doc, ctx: dict, g: dict) -> dict:
    """Page 1: the title, the device's identification, the overall verdict and the heading of the
    results table; returns each result's verdict text, keyed by (item, key)."""
    from metro.api import document as D

    tr = doc.tr
    doc.title_block(tr("Test report"), "GB/T 45570—2025 " + tr.pick("光学陀螺仪通用技术要求",
                                                                    "Optical gyroscopes — general "
                                                                    "technical requirements"))
    dev = ctx["device"]
    D.identification(
        doc,
        ctx,
        [
            (
                tr("Technology and application"),
                f"{tr(dev['technology']) if dev['technology'] != DASH else DASH}, "
                f"{tr(dev['application']) if dev['application'] != DASH else DASH}",
            ),
            (tr("Standard"), "GB/T 45570—2025, " + tr("appendix D")),
            (tr("Items"), ", ".join(dict.fromkeys(o["item"] for o in ctx["outcomes"]))),
        ],
    )
    verdicts = {(v["item"], v["key"]): tr(v["status_text"]) for v in g["verdicts"]}
    if g["has_conformity"]:
        counts = ", ".join(f"{n} {tr(STATUS_TEXT[k])}" for k, n in g["counts"].items() if n)
        doc.para(f"{tr('Overall verdict')}: {tr(g['overall']) if g['overall'] else DASH} "
                 f"({counts or tr('no result judged against a limit')})", bold=True, size=10.5)
    else:
        doc.para(tr("No specification applies: no conformity statement is made."), bold=True)
    doc.heading(tr("Results"), 1)
    return verdicts


def _clause5_section(doc, g: dict, symbols, n: int) -> int:
    """Clause 5: each requirement with its results and verdict."""
    tr = doc.tr
    doc.heading(f"{n} {tr('Technical requirements')} (5)", 1)
    # each requirement with its results (symbols, not code keys) and verdict; the why only
    # where the verdict is not "conforms" (the interval inside the limit is the results table's)
    doc.table(
        [tr("Clause"), tr("Requirement"), tr("Result"), tr("Verdict"), tr("Note")],
        [
            [
                r["clause"],
                tr.pick(r["requirement_cn"], r["requirement_en"])
                if r.get("requirement_cn")
                else r["requirement"],
                _first_results(tr, symbols(r["result"])).replace(
                    "[not reportable]", f"[{tr('not reportable')}]"
                ),
                tr(r["verdict"]) if r["verdict"] else DASH,
                "" if r["verdict"] == "conforms" else symbols(tr.text(r.get("note", ""))),
            ]
            for r in g["clause5"]
        ],
        # the why of a verdict not "conforms" is long
        font_pt=7.5,
        prefer=4,
        prefer_share=0.5,
    )
    n += 1
    return n


def _conditions_section(doc, ctx: dict, g: dict, n: int) -> int:
    """The 6.1 test conditions and equipment, then the method and the items run."""
    from metro.api import document as D

    tr = doc.tr
    doc.heading(f"{n} {tr('Test conditions')} (6.1)", 1)
    doc.heading(f"{tr('Test environment')} (6.1.1)", 2)
    doc.table([tr("Condition"), tr("Required"), tr("Recorded"), tr("Verdict")],
              [[f"{tr(r['name'])} ({r['clause']}",
                tr(r["required"]) if r["required"] == "the site's pressure" else r["required"],
                tr(r["measured"]) if r["measured"] == "not recorded" else r["measured"],
                tr(r["verdict"]) if r["verdict"] else DASH] for r in g["environment"]])
    doc.heading(f"{tr('Test equipment and measuring instruments')} (6.1.2)", 2)
    D.equipment_table(doc, ctx)
    if g["method"] or g["selection"]:
        n += 1
        doc.heading(f"{n} {tr('Method and items')}", 1)
        if g["method"]:
            doc.para(f"{tr('Scale-factor method')} (6.2.7.1): {tr.text(g['method'])}")
        if g["selection"]:
            groups: dict[tuple[bool, str], list[str]] = {}
            for c in g["selection"]:
                groups.setdefault((c["run"], c["reason"]), []).append(c["item"])
            doc.table([tr("Run"), tr("Items"), tr("Reason")],
                      [[tr("yes") if run else tr("no"), ", ".join(items), tr.text(reason)]
                       for (run, reason), items in sorted(groups.items(),
                                                          key=lambda kv: not kv[0][0])],
                      prefer=1)
    return n


def _conformity_section(doc, ctx: dict, g: dict, symbols, n: int) -> int:
    """The decision rule and the verdicts other than "conforms", with the limits' sources."""
    from metro.api import document as D

    tr = doc.tr
    n += 1
    doc.heading(f"{n} {tr('Conformity')}", 1)
    # not alone at a page foot
    doc.para(f"{tr('Decision rule')}: {tr.text(g['rule']['title'])}", keep_next=True)
    doc.para(g["rule"]["statement"], size=8.5, keep_next=True)
    # the results table gives every verdict
    shown = [v for v in g["verdicts"] if v["status"] != "pass"]
    if shown:
        doc.table([tr("Item"), tr("Quantity"), tr("Limit"), tr("Value"), tr("U (k)"), tr("Verdict"),
                   tr("Reason")],
                  [[v["item"], D.quantity_for(ctx, v["item"], v["key"]), v["limit"],
                    tr(v["value"]) if v["detail"] == "not reportable" else v["value"],
                    DASH if v["detail"] == "not reportable" else f"{v['U']} (k = {v['k']})",
                    tr(v["status_text"]), symbols(tr.text(v["reason"]))] for v in shown],
                  font_pt=7.5,
                  prefer=6)
    if len(shown) < len(g["verdicts"]):
        doc.para(tr("The other {n} results conform: each interval value ± U lies within its limit "
                    "(results table above).", n=len(g["verdicts"]) - len(shown)), size=8.5)
    if g["verdicts"]:
        doc.para(
            f"{tr('Sources of the limits')}: "
            + tr.text(limit_sources(v["source"] for v in g["verdicts"])),
            size=8,
        )
    if g["not_assessed"] and not g["limits"]:  # else table A.1/B.1 shows them as not performed
        doc.para(
            f"{tr('Not assessed (item not performed)')}: "
            + "; ".join(tr.text(x) for x in g["not_assessed"]),
            size=8,
        )
    return n


def _limits_section(doc, g: dict, type_test: bool, n: int) -> int:
    """Table A.1 / B.1: the typical indices of the device's kind and application."""
    tr = doc.tr
    lim = g["limits"]
    if lim:
        n += 1
        kind = tr("laser gyro") if lim["kind"] == "laser" else tr("fibre-optic gyro")
        doc.heading(f"{n} {tr('Typical indices, table {table}', table=lim['table'])} — {kind}, "
                    f"{tr.pick(lim['app_cn'], lim['app'])}", 1)
        rows = [r for r in lim["rows"] if type_test or r["performed"]]
        if rows:
            doc.table([tr("No."), tr("Index"), tr("Limit"), tr("Method"), tr("Result"),
                       tr("Verdict")],
                      [[r["no"], tr.pick(r["name_cn"],
                                         r["name_en"]) + (f" {r['symbol']}" if r["symbol"] else ""),
                        r["limit"], r["method"],
                        (tr(r["result"]) if r["result"] == "not reportable" else r["result"])
                        if r["performed"]
                        else tr(NOT_PERFORMED),
                        tr(r["verdict"]) if r["verdict"] else DASH] for r in rows], font_pt=7.5)
        idle = [r["no"] for r in lim["rows"] if not r["performed"]]
        if idle and not type_test:
            doc.para(tr("Rows of table {table} not performed in this run: {rows}",
                        table=lim["table"],
                        rows=", ".join(idle)), size=8.5)
    return n


def _severities_section(doc, g: dict, type_test: bool, n: int) -> int:
    """Table C.1: the environmental severities."""
    tr = doc.tr
    if g["severities"]:
        n += 1
        doc.heading(f"{n} {tr('Environmental severities')} (C.1)", 1)
        rows = [r for r in g["severities"] if type_test or r["status"] == "performed"]
        if rows:
            doc.table([tr("No."), tr("Test"), tr("Severity"), tr("Method"), tr("Status")],
                      [[r["no"], tr.pick(r["name_cn"], r["name_en"]), r["severity"], r["method"],
                        tr(r["status"]) + (f": {r['performed_items']}" if r["performed_items"]
                                           else "")]
                       for r in rows], font_pt=7.5)
        if not type_test:
            idle = [r["no"] for r in g["severities"] if r["status"] != "performed"]
            if idle:
                doc.para(tr("Rows of table {table} not performed in this run: {rows}", table="C.1",
                            rows=", ".join(idle)), size=8.5)
    return n


def _closing_sections(doc, ctx: dict, g: dict, n: int) -> None:
    """Notes, deviations, signatures and the annexes."""
    from metro.api import document as D

    tr, f = doc.tr, ctx["facts"]
    n += 1
    doc.heading(f"{n} {tr('Notes')}", 1)
    D.notes_section(doc, ctx, include_warnings=False)
    n += 1
    doc.heading(f"{n} {tr('Deviations')}", 1)
    if g["deviations"]:
        doc.bullets(g["deviations"], size=8.5)
    else:
        doc.para(tr("none"))
    n += 1
    doc.heading(f"{n} {tr('Signatures')}", 1)
    D.signatures(doc, D.signatory_rows(f, [tr("Tested by"), tr("Checked by"), tr("Approved by")]))
    doc.para(tr("The results relate only to the device tested. This report shall not be reproduced "
                "except in full without the written approval of the laboratory."), size=8.5)
    D.annexes(doc, ctx)

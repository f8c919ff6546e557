"""Render a :class:`~metro.core.model.provenance.RunRecord` as a Word (and PDF) report or certificate.

Two steps, so the content can be checked without Word:

1. :func:`report_context` turns the record into a plain dict of strings, lists and dicts
   (every number already formatted: results as :meth:`Result.reported` rounds them,
   budget figures with four significant digits, units as :func:`fmt_unit` prints them;
   who, where and when in ``facts``: :func:`record_facts`);
2. :func:`write_report` builds the document from that dict with
   :class:`metro.core.documents.document.DocumentBuilder` and the standard's layout (each plugin lays out
   its own appendix), or renders a docxtpl template of a lab's own, draws the figures with
   :mod:`metro.core.documents.plots`, and writes the ``.docx`` (or ``.pdf``, through LibreOffice)
   atomically: a failure at any point leaves no file at the target (and an earlier report
   there untouched).

docx, docxtpl, matplotlib and pint are imported inside the functions, so
``import metro.core.documents.report`` stays cheap.

Dict keys are chosen not to clash with ``dict`` methods (Jinja looks attributes up first,
so a key called ``items`` or ``values`` would be shadowed in ``{{ x.items }}``).
"""

from __future__ import annotations

import datetime as dt
import os
import re
import tempfile
from pathlib import Path
from typing import Callable, TYPE_CHECKING, Any, Iterable, Mapping

from ..base.atomic import atomic_path
from ..base.formatting import (
    DASH, fmt_divisor, fmt_dof, fmt_num, fmt_quantity, or_dash, pretty_powers, unit_text, with_unit,
)
from ..base.locale import Text, join, msg, translator

if TYPE_CHECKING:  # pragma: no cover
    from ..uncertainty.budget import UncertaintyBudget
    from ..model.campaign import Equipment
    from ..model.results import Outcome, Result, TableSpec
    from ..model.provenance import RunRecord

__all__ = [
    "write_report",
    "build_context",
    "render_context",
    "report_context",
    "default_template",
    "SIMULATED_BANNER",
    "IMAGE_WIDTH_MM",
]

SIMULATED_BANNER = (
    "SIMULATED — Results from the built-in simulated test station — "
    "not a measurement of a real device."
)

#: Width of a figure in the report.
IMAGE_WIDTH_MM = 150

def _pretty_context(obj: Any) -> Any:
    """:func:`pretty_powers` on every string of a report context (dicts, lists, tuples); other
    objects (plot specs, images) are kept as they are."""
    if isinstance(obj, Text):
        return obj.map(pretty_powers)
    if isinstance(obj, str):
        return pretty_powers(obj)
    if isinstance(obj, dict):
        return {k: _pretty_context(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_pretty_context(v) for v in obj]
    if isinstance(obj, tuple):
        return tuple(_pretty_context(v) for v in obj)
    return obj


def _label(key: str) -> str:
    """``latitude_uncertainty`` -> ``Latitude uncertainty``."""
    s = str(key).replace("_", " ").strip()
    return s[:1].upper() + s[1:] if s else s


def _name_values(m: Mapping[str, Any], *, relabel: bool = True) -> list[dict[str, str]]:
    return [{"name": _label(k) if relabel else str(k), "value": fmt_quantity(v)} for k, v in m.items()]


def _date_text(d: dt.datetime | dt.date) -> str:
    if isinstance(d, dt.datetime):
        text = d.strftime("%Y-%m-%d %H:%M")
        if d.tzinfo is not None:
            off = d.utcoffset()
            text += " UTC" if off == dt.timedelta(0) else d.strftime(" %z")
        return text
    return d.isoformat()


# --------------------------------------------------------------------------------------
# Sections
# --------------------------------------------------------------------------------------


def _equipment_row(e: "Equipment", on: dt.date) -> dict[str, Any]:
    cal = e.calibration
    status = e.status(on)
    if cal is not None:
        prefix = f"certificate {cal.certificate}, "
        if status.startswith(prefix):
            status = status[len(prefix):]
        if cal.due is not None:  # the same words as Calibration.status, as a message
            status = (msg("EXPIRED on {date}", date=cal.due.isoformat()) if cal.due < on else
                      msg("valid until {date}", date=cal.due.isoformat()))
        elif status == "no due date stated":
            status = msg("no due date stated")
        if cal.distribution == "normal":
            U = f"{fmt_quantity(cal.uncertainty)} (k = {fmt_num(cal.k, 3)})"
        else:
            U = msg("{U} ({distribution}, half-width)", U=fmt_quantity(cal.uncertainty),
                    distribution=cal.distribution)
        expired = not cal.is_valid(on)
        relative = not unit_text(getattr(cal.uncertainty, "units", "")) if hasattr(cal.uncertainty, "units") else True
    else:
        U = DASH
        expired = False
        relative = False
    certificate = DASH if cal is None else cal.certificate + (f" ({cal.lab})" if cal.lab else "")
    return {
        "id": e.id,
        "description": e.describe(),
        "role": or_dash(e.role),
        "certificate": certificate,
        "U": U,
        "U_relative": relative,
        "due": DASH if cal is None or cal.due is None else cal.due.isoformat(),
        "status": status,
        "expired": expired,
        "valid": cal is not None and not expired,
    }


def _result_row(r: "Result") -> dict[str, Any]:
    m = r.metric
    vtext, Utext = r.reported()
    if Utext is None and r.u is not None:
        u = float(r.u.to(m.unit).magnitude)
        Utext = f"u = {fmt_num(u, 2)}"  # a standard uncertainty without a budget: say so
    reference = m.clause + (f", {m.equation}" if m.equation else "")
    unit = unit_text(m.unit)
    return {
        "reportable": bool(getattr(r, "reportable", True)),
        "reason": getattr(r, "reason", "") or "",
        "bound": getattr(r, "bound", "") or "",
        "earth_rate": str(getattr(r, "earth_rate", "") or ""),
        "value_unit": with_unit(vtext, unit),
        "U_unit": DASH if Utext is None else (Utext if Utext.startswith("u = ") else with_unit(Utext, unit)),
        "key": m.key,
        "quantity": m.name,
        "symbol": m.symbol,
        "value": vtext,
        "U": Utext if Utext is not None else DASH,
        "unit": unit_text(m.unit) or "1",
        "k": DASH if r.k is None else fmt_num(r.k, 3),
        "clause": m.clause,
        "equation": m.equation,
        "reference": reference or DASH,
        "note": r.note,
    }


def _budget_title(m: Any, measurand: str) -> str:
    """A budget's title: the result's name and symbol, then its measurand in parentheses only
    when the measurand says something the name does not (``scale factor K``, not ``scale factor K
    (scale factor K)``; ``fitted zero F₀``, not ``… (fitted zero F0)``).

    >>> from types import SimpleNamespace as N
    >>> _budget_title(N(name="scale-factor nonlinearity", symbol="K_n", key="K_n"), "nonlinearity Kn")
    'scale-factor nonlinearity K_n'
    >>> _budget_title(N(name="bias", symbol="B₀", key="B0"), "mean of the static record")
    'bias B₀ (mean of the static record)'
    >>> _budget_title(N(name="start-up time", symbol="t_s", key="t_startup"), "t_startup")
    'start-up time t_s'
    """
    from .document import _plain, quantity_name

    title = quantity_name({"quantity": m.name, "symbol": m.symbol, "key": m.key})
    words = set(re.split(r"[\s()\-]+", _plain(title).lower()))
    said = all(w in words for w in re.split(r"[\s()\-]+", _plain(measurand or "").lower()) if w)
    # a measurand that is the result's code key (dB_shock, gamma_r, t_startup) says nothing a reader reads
    key = measurand in (m.key, m.symbol) or re.fullmatch(r"[A-Za-z]+(?:_[A-Za-z0-9]+)+", measurand or "")
    return title if not measurand or said or key else msg("{name} ({measurand})", name=title, measurand=measurand)


def _budget_block(r: "Result", budget: "UncertaintyBudget") -> dict[str, Any]:
    d = budget.as_dict()
    unit = d["unit"] if d["unit"] != "1" else ""
    rows = []
    for row in d["rows"]:
        rows.append({
            "source": msg("{source} ({note})", source=row["source"], note=row["note"]) if row["note"]
            else row["source"],
            "source_only": row["source"], "note": row["note"],  # apart, for a document to number repeated notes
            "symbol": row["symbol"],
            "type": row["type"],
            "distribution": row["distribution"],
            "value": with_unit(fmt_num(row["value"]), row["value_unit"]),
            "divisor": fmt_divisor(row["divisor"]),
            "sensitivity": with_unit(fmt_num(row["sensitivity"]), row["sensitivity_unit"]),
            "contribution": fmt_num(row["contribution"]),
            "dof": fmt_dof(row["dof"]),
        })
    m = r.metric
    k_text = fmt_num(d["k"], 3)
    if d["coverage"] != f"k = {d['k']:g}":  # k from t_p(ν_eff): say how it was chosen
        k_text += f" ({d['coverage'].removeprefix('k = ')})"
    return {
        "title": _budget_title(m, d["measurand"]),
        "measurand": d["measurand"],
        "result": m.key,
        "unit": unit or "1",
        "relative": d["relative"],
        "rows": rows,
        "u_c": fmt_num(d["u_c"]),
        "nu_eff": fmt_dof(d["nu_eff"]),
        "k": k_text,
        "coverage": d["coverage"],
        "U": d["U_reported"],
        "U_unrounded": fmt_num(d["U"]),
        "rounding": d["rounding"],
        "note": d["note"],
    }


def _cell(v: Any) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, float):
        return f"{v:.6g}"
    return fmt_quantity(v, 6)


def _table_block(t: "TableSpec") -> dict[str, Any]:
    return {
        "name": t.name,
        "title": t.title,
        "header": [h if isinstance(h, str) else str(h) for h in t.header],
        "rows": [[_cell(c) for c in row] for row in t.rows],
    }


def plot_caption(title: str, item: str) -> str:
    """A figure's caption: its title and the item it belongs to, ``(item)`` added once."""
    return title if title.endswith(f"({item})") else join(" ", [title, f"({item})"])


def _outcome_block(o: "Outcome", number: str, designation: str, first_figure: int) -> dict[str, Any]:
    results = list(o.results)
    plots = [
        {"number": first_figure + i, "name": p.name, "title": p.title, "caption": plot_caption(p.title, o.item),
         "spec": p, "image": None}
        for i, p in enumerate(o.plots)
    ]
    return {
        "number": number,
        "id": o.id,
        "standard": o.standard,
        "designation": designation,
        "item": o.item,
        "title": o.title,
        "clause": o.clause,
        "segments_text": ", ".join(o.segments) or DASH,
        "options": _name_values(o.options, relabel=False),
        "options_text": "; ".join(f"{k} = {fmt_quantity(v)}" for k, v in o.options.items()),
        "results": [_result_row(r) for r in results],
        "notes": [join(": ", [r.metric.symbol or r.metric.name, r.note]) for r in results if r.note],
        "budgets": [_budget_block(r, r.budget) for r in results if r.budget is not None],
        "tables": [_table_block(t) for t in o.tables],
        "plots": plots,
        "warnings": [w if isinstance(w, str) else str(w) for w in o.warnings],
    }


def _sanitize(obj: Any) -> Any:
    """Drop the characters XML 1.0 cannot hold (:data:`metro.core.base.vocabulary.NOT_XML`: C0 controls,
    lone surrogates, U+FFFE/U+FFFF) from every string of the context.  Manifests, bench files and
    lab profiles are refused with such a character at load; this keeps any other text (a sample
    file's header, a plugin's note) from stopping the document."""
    from ..base.vocabulary import NOT_XML

    if isinstance(obj, Text):
        return obj.map(lambda s: NOT_XML.sub("", s))
    if isinstance(obj, str):
        return NOT_XML.sub("", obj)
    if isinstance(obj, dict):
        return {k: _sanitize(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_sanitize(v) for v in obj]
    return obj


def _conformity_block(a: Any) -> dict[str, Any] | None:
    """The verdicts as text (None when no specification applied)."""
    if a is None:
        return None
    return {
        "rule": a.rule.name,
        "rule_title": a.rule.title,
        "statement": a.rule.statement,
        "overall": a.overall.value if a.overall is not None else DASH,
        "verdicts": [{"item": v.item, "key": v.key, "limit": v.spec.text(), "source": v.spec.source,
                      "status": v.status.value, "detail": v.detail, "reason": v.reason} for v in a.verdicts],
        "not_assessed": [msg("{symbol} {limit} ({source})", symbol=s.symbol, limit=s.text(), source=s.source)
                         for s in a.not_assessed],
    }


def _unique(seq: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(seq))


def _data_files(record: "RunRecord") -> list[dict[str, str]]:
    """The manifest (first, when read from one) and every samples file, with their SHA-256: the
    manifest's hash proves which K, latitude and equipment produced the report."""
    files = list(record.data_files) or list(record.campaign.data_files())
    out = [{"file": f if isinstance(f, str) else str(f), "sha256": str(h)} for f, h in files]
    manifest = getattr(record.campaign, "manifest_sha256", "")
    if manifest:
        out.insert(0, {"file": f"{record.campaign.source} (manifest)", "sha256": manifest})
    if not out:  # a simulated campaign: its samples live in memory, still hashed
        out = [
            {"file": f"segment {s.id} ({'simulated, ' if record.campaign.simulated else ''}in memory)",
             "sha256": s.sha256}
            for s in record.campaign.segments if s.sha256
        ]
    return out


def _fact_text(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (dt.date, dt.datetime)):
        return _date_text(v)
    return str(v).strip()


def record_facts(record: "RunRecord") -> dict[str, str]:
    """Who, where and when, from the campaign through the manifest vocabulary
    (:mod:`metro.core.base.vocabulary`; a lab profile in force has filled in what the manifest leaves
    out, :func:`metro.core.record.registering.with_lab`): ``lab``, ``lab_address``, ``location``,
    ``customer``, ``customer_address``, ``operator``, ``checker``, ``approver`` and their titles
    ``operator_title``, ``checker_title``, ``approver_title``, ``received``, ``measured`` (the measurement date,
    :attr:`RunRecord.test_date`; where it came from in ``measured_from``), ``issued`` (the
    manifest's ``issued``, else the day the document is written) and ``processed`` (the time of
    this run).  A missing fact is the empty string; documents print it as "—"."""
    from ..model.provenance import measurement_date

    camp = record.campaign
    meta = dict(camp.meta)
    people, lab, customer = camp.people, camp.lab, camp.customer
    received = camp.date_received
    out = {
        "lab": lab.name, "lab_address": lab.address, "location": lab.location,
        "customer": customer.name, "customer_address": customer.address,
        "operator": people.operator, "checker": people.checked_by, "approver": people.approved_by,
        "approver_title": people.approved_by_title, "operator_title": people.operator_title,
        "checker_title": people.checked_by_title,
        "received": received.isoformat() if received else "",
        "issued": _fact_text(meta.get("issued")),
        "logo": _fact_text(meta.get("lab_logo")),
    }
    measured = measurement_date(camp)
    if measured is not None:
        out["measured"] = measured.isoformat()
        out["measured_from"] = "campaign" if camp.measurement_date else "acquisition time"
    else:
        out["measured"] = record.test_date.isoformat()
        out["measured_from"] = "processing time"
    if not out["issued"]:
        out["issued"] = dt.date.today().isoformat()
    out["processed"] = _date_text(record.created)
    return {k: str(v or "") for k, v in out.items()}


def report_context(record: "RunRecord", *, designations: Mapping[str, str] | None = None) -> dict[str, Any]:
    """Everything the report shows, as plain Python (strings, lists, dicts).

    ``designations`` maps a standard id to its designation (``{"gbt45570": "GB/T 45570—2025"}``,
    from the plugin registry's ``StandardInfo``); without it the standard id is shown.

    Keys: ``report_number``, ``created``, ``created_iso``, ``title``, ``footer``,
    ``generator``, ``standards`` (list of {id, designation, items}), ``standards_text``,
    ``items_text``, ``simulated``, ``simulated_banner``, ``truth`` ([{name, value}]),
    ``campaign`` {id, source}, ``device`` {id, manufacturer, model, serial, technology,
    application, output, description, properties}, ``environment`` and ``site``
    ([{name, value}]), ``latitude``, ``equipment`` ([{id, description, role, certificate, U,
    due, status, expired, valid}]), ``equipment_warnings``, ``outcomes`` (see below),
    ``provenance`` {source, software, plugins ([{name, version}]), data_files ([{file,
    sha256}])}, ``selection`` ([{item, run, reason, via}]: what ``--all``/a series chose and why)
    and ``conformity`` (None, or {rule, rule_title, statement, overall, verdicts ([{item, key,
    limit, source, status, detail, reason}]), not_assessed ([text])}).

    Each outcome: ``number`` ("5.1"), ``id``, ``standard``, ``designation``, ``item``,
    ``title``, ``clause``, ``segments_text``, ``options``, ``options_text``, ``results``
    ([{key, quantity, symbol, value, U, unit, k, clause, equation, reference, note}] — value
    and U as :meth:`Result.reported` gives them), ``notes``, ``budgets`` ([{title,
    measurand, result, unit, rows, u_c, nu_eff, k, coverage, U, U_unrounded, rounding,
    note}], each row {source, symbol, type, distribution, value, divisor, sensitivity,
    contribution, dof}), ``tables`` ([{name, title, header, rows}]), ``plots`` ([{number,
    name, title, caption, spec, image}]; ``caption`` is the title with the item, ``image`` is filled in by
    :func:`write_report`) and
    ``warnings``.
    """
    designations = dict(designations or {})
    camp = record.campaign
    dev = camp.device
    simulated = bool(record.simulated or camp.simulated)
    on = record.test_date

    # standards and items, in the order the outcomes came
    standards: dict[str, list[str]] = {}
    for o in record.outcomes:
        standards.setdefault(o.standard, []).append(o.item)
    std_list = [
        {"id": s, "designation": designations.get(s) or s, "items_text": ", ".join(_unique(items))}
        for s, items in standards.items()
    ]
    items_text = "; ".join(f"{s['designation']} {s['items_text']}" for s in std_list)
    title = "Test report — " + (items_text or camp.id)

    outcomes = []
    figure = 1
    for i, o in enumerate(record.outcomes, start=1):
        block = _outcome_block(o, f"5.{i}", designations.get(o.standard) or o.standard, figure)
        figure += len(block["plots"])
        outcomes.append(block)

    equipment = [_equipment_row(e, on) for e in camp.equipment]
    equipment_warnings = [
        msg("The calibration of {id} ({certificate}) is {status}: results that depend on it are not "
            "traceable until it is recalibrated.", id=e["id"], certificate=e["certificate"], status=e["status"])
        for e in equipment if e["expired"]
    ]

    truth = dict(camp.truth)
    truth.update(record.truth)
    site = dict(camp.site)
    latitude = fmt_quantity(site["latitude"]) if "latitude" in site else None

    software = dict(record.software)
    generator = f"metro {software['metro']}" if "metro" in software else "metro"
    source = camp.source or ("simulated station" if simulated else DASH)

    return _sanitize({
        "facts": record_facts(record),
        "report_number": record.report_number,
        "created": _date_text(record.created),
        "created_iso": record.created.isoformat(),
        "title": title,
        "footer": f"{title} · {record.report_number}",
        "generator": generator,
        "standards": std_list,
        "standards_text": ", ".join(s["designation"] for s in std_list) or DASH,
        "items_text": items_text or DASH,
        "simulated": simulated,
        "simulated_banner": SIMULATED_BANNER if simulated else "",
        "truth": _name_values(truth, relabel=False) if simulated else [],
        "campaign": {"id": camp.id, "source": source},
        "device": {
            "id": dev.id,
            "manufacturer": or_dash(dev.manufacturer),
            "model": or_dash(dev.model),
            "serial": or_dash(dev.serial),
            "technology": or_dash(dev.technology),
            "application": or_dash(dev.application),
            "output": or_dash(dev.output),
            "description": dev.describe(),
            "properties": _name_values(dev.properties),
        },
        "environment": _name_values(camp.environment),
        "site": _name_values(site),
        "latitude": latitude,
        "equipment": equipment,
        "equipment_warnings": equipment_warnings,
        "outcomes": outcomes,
        "selection": [{"item": c.item, "run": c.run, "reason": c.reason, "via": c.via}
                      for c in getattr(record, "selection", ())],
        "conformity": _conformity_block(getattr(record, "conformity", None)),
        "provenance": {
            "source": source,
            "software": [{"name": k, "version": str(v)} for k, v in software.items()],
            "plugins": [{"name": k, "version": str(v)} for k, v in dict(record.plugins).items()],
            "data_files": _data_files(record),
            "manifest": {"file": record.campaign.source,
                         "sha256": getattr(record.campaign, "manifest_sha256", "") or "—"},
        },
    })


# --------------------------------------------------------------------------------------
# Word
# --------------------------------------------------------------------------------------


def default_template() -> Any:
    """The packaged docxtpl template, ``metro/core/documents/templates/report.docx`` (an importlib
    Traversable): a starting point for a lab's own template; metro's documents are built by
    :mod:`metro.core.documents.document`."""
    from importlib import resources

    return resources.files("metro.core.documents") / "templates" / "report.docx"


def build_context(
    record: "RunRecord",
    *,
    designations: Mapping[str, str] | None = None,
    extend: Callable[["RunRecord", dict], None] | None = None,
    register: Mapping[str, Any] | None = None,
    lang: str | None = None,
) -> dict[str, Any]:
    """The context :func:`render_context` renders: :func:`report_context`, then the plugins'
    ``metro_extend_report_context`` (``extend``), numbers in free text as powers of ten.

    ``register`` is the register statement: ``{"registered": bool, "notices": [text, …]}``
    (:mod:`metro.core.record.registering`); each notice is printed at the top of the report.  ``lang``
    (``zh``, ``en``, ``zh+en``) is kept in the context (``ctx["lang"]``) so the same document can
    be written again.  The result is plain JSON apart from each figure's ``spec`` (a PlotSpec),
    so the register can keep it and write the same report again (``metro report NUMBER``)."""
    ctx = report_context(record, designations=designations)
    ctx["register"] = dict(register) if register is not None else {"registered": False, "notices": []}
    if lang is not None:
        ctx["lang"] = lang
    if extend is not None:  # plugins' metro_extend_report_context
        extend(record, ctx)
    ctx = _pretty_context(ctx)
    ctx["logo"] = _logo(ctx["facts"].get("logo", ""))  # after the text clean-up: image bytes as base64
    return ctx


def _logo(path: str) -> dict[str, str] | None:
    """The lab's logo (``facts["logo"]``, from the lab profile) as ``{"file", "base64"}``: kept in
    the context itself so the register can write the same document again without the file."""
    import base64

    from ..base.errors import DataError

    if not path:
        return None
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise DataError(str(p), "lab.logo", f"cannot read the logo image: {exc.strerror or exc}") from exc
    return {"file": p.name, "base64": base64.b64encode(data).decode("ascii")}


def write_report(
    path: str | os.PathLike[str],
    record: "RunRecord",
    *,
    template: str | os.PathLike[str] | None = None,
    designations: Mapping[str, str] | None = None,
    extend: Callable[["RunRecord", dict], None] | None = None,
    register: Mapping[str, Any] | None = None,
    layout: Any = None,
    lang: str | None = None,
    pdf: bool = False,
) -> Path:
    """Write ``record`` as a Word document at ``path`` (atomically); return ``path``.

    Without ``template`` the document is built by :class:`metro.core.documents.document.DocumentBuilder`
    with ``layout`` (a callable ``layout(doc, ctx)``, ``"module:function"`` text, or None for
    the generic report) in ``lang`` (``zh``, ``en`` or ``zh+en``; default ``zh+en``).  With
    ``template`` (a docxtpl ``.docx`` of a lab's own) the template is rendered instead.
    A ``path`` ending in ``.pdf`` writes the PDF only; ``pdf=True`` writes the ``.docx`` and a
    ``.pdf`` beside it (LibreOffice, :func:`metro.core.documents.document.to_pdf`).  Any failure leaves no
    file (and no temporary file) behind.
    """
    if Path(path).suffix.lower() == ".pdf" or pdf:
        from .document import soffice_path

        soffice_path()  # a clear error before any work when LibreOffice is missing
    ctx = build_context(record, designations=designations, extend=extend, register=register, lang=lang)
    return render_context(path, ctx, template=template, layout=layout, pdf=pdf)


def _core_property(text: str, limit: int = 255) -> str:
    """A .docx core property holds at most 255 characters (python-docx refuses more): a longer
    title or item list (a whole standard's items) is cut with an ellipsis; the report's pages keep
    the full text."""
    text = str(text)
    return text if len(text) <= limit else text[: limit - 1] + "…"


def _add_notices(document: Any, notices: Iterable[str]) -> None:
    """The register statement (registered, replaces …, not registered, --allow-expired) as bold
    paragraphs at the top of the document body, whatever the template — under the lab's logo
    when the document opens with it."""
    from docx.oxml.ns import qn

    body = document.element.body
    first = body[0] if len(body) else None
    start = 1 if first is not None and first.tag == qn("w:p") and first.findall(".//" + qn("w:drawing")) else 0
    for i, text in enumerate(notices):
        para = document.add_paragraph()
        para.add_run(text).bold = True
        body.remove(para._p)
        body.insert(start + i, para._p)


def render_figures(ctx: Mapping[str, Any], folder: str | os.PathLike[str]) -> dict[int, Path]:
    """Draw every figure of a context to ``folder/figure-N.png``; {figure number: PNG path}."""
    out = {}
    tr = translator(ctx.get("lang"))
    for o in ctx["outcomes"]:
        for p in o["plots"]:
            out[p["number"]] = draw_figure(p["spec"], tr, Path(folder) / f"figure-{p['number']}.png")
    return out


def draw_figure(spec: Any, tr: Any, png: Path) -> Path:
    """Draw a figure of a context in the document's language (``tr``) as the PNG ``png``, in a
    folder of the document's own (a plain write: the folder is temporary).  A figure drawn before
    with the same inputs comes from :mod:`metro.core.documents.figure_cache` (a document written again from
    the register draws nothing twice)."""
    from . import plots
    from .figure_cache import cached_png

    png.write_bytes(cached_png(plots.localized(spec, tr)))
    return png


def render_context(
    path: str | os.PathLike[str],
    ctx: Mapping[str, Any],
    *,
    template: str | os.PathLike[str] | None = None,
    layout: Any = None,
    lang: str | None = None,
    pdf: bool = False,
    figures: Mapping[int, str | os.PathLike[str]] | None = None,
) -> Path:
    """Write a context made by :func:`build_context` (or kept by the register) as a document at
    ``path`` atomically; return ``path``.  ``template`` (a docxtpl ``.docx``) renders it into that
    template; else ``layout`` builds it (:func:`write_report`), in ``lang`` (default: the
    context's ``lang``, else zh+en).  A ``.pdf`` path or ``pdf=True`` goes through LibreOffice.
    ``figures`` ({figure number: PNG}, from :func:`render_figures`) are used instead of drawing
    the figures again (the register draws them before it takes its lock)."""
    path = Path(path)
    pdf_only = path.suffix.lower() == ".pdf"
    if pdf_only or pdf:
        from .document import soffice_path

        soffice_path()
    ctx = dict(ctx)
    ctx["outcomes"] = [dict(o, plots=[dict(p) for p in o["plots"]]) for o in ctx["outcomes"]]
    with tempfile.TemporaryDirectory(prefix="metro-report-") as tmpdir:
        docx_tmp = Path(tmpdir) / "document.docx"
        if template is not None:
            _render_template(docx_tmp, ctx, template, figures)
        else:
            figdir = Path(tmpdir) / "figures"
            figdir.mkdir()
            doc = build_document(ctx, figdir, layout=layout, lang=lang, figures=figures)
            doc.save(docx_tmp)
        if pdf_only or pdf:
            from .document import to_pdf

            target = path if pdf_only else path.with_suffix(".pdf")
            with atomic_path(target) as tmp:
                to_pdf(docx_tmp, Path(tmp))
        if not pdf_only:
            with atomic_path(path) as tmp:
                Path(tmp).write_bytes(docx_tmp.read_bytes())
    return path


def _resolve_layout(layout: Any) -> Callable[..., None]:
    """A layout callable from a callable, ``"module:function"`` text or None (the generic one)."""
    from .document import generic_layout

    if layout is None:
        return generic_layout
    if callable(layout):
        return layout
    import importlib

    module, _, name = str(layout).partition(":")
    return getattr(importlib.import_module(module), name)


def _document_title(ctx: Mapping[str, Any], tr: Any) -> str:
    return tr("Test report")


def _set_properties(docx_doc: Any, ctx: Mapping[str, Any]) -> None:
    props = docx_doc.core_properties
    props.title = _core_property(ctx["title"])
    props.subject = _core_property(ctx["items_text"])
    props.identifier = ctx["report_number"]
    props.author = ctx["generator"]
    props.last_modified_by = ctx["generator"]
    props.keywords = "SIMULATED" if ctx["simulated"] else ""
    created = dt.datetime.fromisoformat(ctx["created_iso"]) if ctx.get("created_iso") else None
    if isinstance(created, dt.datetime):
        if created.tzinfo is not None:  # python-docx writes naive datetimes as UTC
            created = created.astimezone(dt.timezone.utc).replace(tzinfo=None)
        props.created = props.modified = created
    props.revision = 1


def build_document(ctx: Mapping[str, Any], figdir: Path, *, layout: Any = None, lang: str | None = None,
                   figures: Mapping[int, str | os.PathLike[str]] | None = None) -> Any:
    """The document of a context built in memory (a :class:`~metro.core.documents.document.DocumentBuilder`);
    figures are drawn into ``figdir``; ``doc.tr.missing`` lists message ids the catalog lacked."""
    from .document import DocumentBuilder

    ctx = dict(ctx)
    ctx["outcomes"] = [dict(o, plots=[dict(p) for p in o["plots"]]) for o in ctx["outcomes"]]
    tr = translator(lang or ctx.get("lang"))
    ctx["lang"] = tr.lang
    ctx["doc_title"] = _document_title(ctx, tr)
    doc = DocumentBuilder(number=ctx["report_number"], title=ctx["doc_title"], tr=tr,
                          simulated=ctx["simulated"], footer=ctx["generator"])
    if ctx.get("logo"):
        import base64

        doc.logo = base64.b64decode(ctx["logo"]["base64"])
    for o in ctx["outcomes"]:
        for p in o["plots"]:
            if figures is not None and p["number"] in figures:
                p["image"] = str(figures[p["number"]])
            else:
                p["image"] = str(draw_figure(p["spec"], tr, Path(figdir) / f"figure-{p['number']}.png"))
    _resolve_layout(layout)(doc, ctx)
    _add_notices(doc.doc, (ctx.get("register") or {}).get("notices") or ())
    _set_properties(doc.doc, ctx)
    return doc


def _render_template(target: Path, ctx: dict, template: str | os.PathLike[str],
                     figures: Mapping[int, str | os.PathLike[str]] | None = None) -> None:
    import io

    from docx.shared import Mm
    from docxtpl import DocxTemplate, InlineImage
    from jinja2 import TemplateError

    from ..base.errors import MetroError

    template_name = os.fspath(template)
    if not Path(template_name).is_file():
        raise MetroError(f"report template {template_name} does not exist")
    tpl = DocxTemplate(io.BytesIO(Path(template_name).read_bytes()))
    tr = translator(ctx.get("lang"))
    with tempfile.TemporaryDirectory(prefix="metro-report-") as tmpdir:
        for o in ctx["outcomes"]:
            for p in o["plots"]:
                if figures is not None and p["number"] in figures:
                    png = Path(figures[p["number"]])
                else:
                    png = draw_figure(p["spec"], tr, Path(tmpdir) / f"figure-{p['number']}.png")
                p["image"] = InlineImage(tpl, str(png), width=Mm(IMAGE_WIDTH_MM))
        try:
            tpl.render(ctx, autoescape=True)
        except TemplateError as exc:
            where = f" (line {exc.lineno})" if getattr(exc, "lineno", None) else ""
            raise MetroError(
                f"report template {template_name}: {exc}{where}",
                hint="check the template's {{ }} and {% %} tags against metro.core.documents.report.report_context",
            ) from exc
    _add_notices(tpl.docx, (ctx.get("register") or {}).get("notices") or ())
    _set_properties(tpl.docx, ctx)
    tpl.save(str(target))

"""Between a run and the register: issue a run's report under a register number, re-render
it, amend it; and the statements a report makes about its registration.

* :func:`register_run` — a run with a lab profile: the register allocates the number, the
  report is written with it, the row keeps what :func:`draft_for` collects (results, budgets,
  verdicts, provenance, equipment status, the render context);
* :func:`unregistered` — the statement of a report that is not in a register (no lab profile,
  or a simulated run without ``--register-simulated``): its number is not a register number;
* :func:`rerender` — ``metro report NUMBER``: the stored context rendered again into the
  standard's template (same numbers, same content);
* :func:`check_equipment` — equipment past its due date on the measurement date refuses a
  registered run unless ``--allow-expired`` (which the report then states).
"""

from __future__ import annotations

import datetime as dt
import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping, Sequence

import attrs

from ..base.errors import MetroError

if TYPE_CHECKING:  # pragma: no cover
    from .lab import LabProfile
    from ..run.plugin_manager import MetroPluginManager
    from ..model.provenance import RunRecord
    from .register import Issued, Register

__all__ = ["register_run", "unregistered", "rerender", "amend", "check_equipment",
           "measurement_date", "stored_context",
           "expired_equipment", "encode_context", "decode_context"]


#: the report number in a context made before the register gives the number (replaced in it then)
PENDING = "METRO-REGISTER-NUMBER-PENDING"


def with_lab(record: "RunRecord", lab: "LabProfile") -> "RunRecord":
    """``record`` whose campaign names the lab and its people from the profile: ``[campaign]``
    keys ``lab``, ``lab_address``, ``operator`` (calibrated by), ``checked_by``, ``approved_by`` and
    each one's title (``operator_title``, ``checked_by_title``, ``approved_by_title``) are filled in
    where the manifest gives none (under any spelling metro reads): campaign values override the
    profile per run, and a person the manifest names gets no title from the profile. ``lab_logo``
    carries the profile's logo image (its path), which the documents draw above the title, and
    ``lab_verify_url`` the base of the verify link a registered report prints as a QR code."""
    try:
        from ..base.vocabulary import CAMPAIGN_ALIASES
    except ImportError:  # pragma: no cover - before the manifest vocabulary
        CAMPAIGN_ALIASES = {}
    camp = record.campaign
    meta = dict(camp.meta)

    def given(key: str) -> bool:
        return any(meta.get(k) not in (None, "") for k
                   in (key, *[a for a, c in CAMPAIGN_ALIASES.items()
                                                                   if c == key]))

    cal, chk, app = (lab.signatory(r) for r in ("calibrated_by", "checked_by", "approved_by"))
    values = {"lab": lab.name_zh + (f" {lab.name_en}" if lab.name_zh and lab.name_en
                                    else lab.name_en),
              "lab_address": lab.address, "operator": cal.name if cal else "",
              "checked_by": chk.name if chk else "", "approved_by": app.name if app else "",
              "operator_title": cal.title if cal else "", "checked_by_title": chk.title if chk
              else "",
              "approved_by_title": app.title if app else "",
              "lab_logo": str(lab.logo) if lab.logo else "", "lab_verify_url": lab.verify_url,
              "country": lab.country}
    added = {k: v for k, v in values.items() if v and not given(k)}
    for person in ("operator", "checked_by", "approved_by"):  # the title goes with the person
        if given(person):
            added.pop(f"{person}_title", None)
    if not added:
        return record
    return attrs.evolve(record, campaign=attrs.evolve(camp, meta={**meta, **added}))


def measurement_date(record: "RunRecord") -> dt.date:
    """The manifest's ``[campaign] measurement_date`` when given, else the day of the run."""
    return getattr(record.campaign, "measurement_date", None) or record.test_date


def expired_equipment(campaign: Any, on: dt.date) -> list[str]:
    """One sentence per piece of equipment whose calibration was past its due date ``on``."""
    out = []
    for e in campaign.equipment:
        cal = e.calibration
        if cal is not None and not cal.is_valid(on):
            out.append(f"{e.id} ({e.role}, certificate {cal.certificate}) was due "
                       f"{cal.due.isoformat()}")
    return out


def check_equipment(campaign: Any, on: dt.date, *, allow_expired: bool) -> list[str]:
    """Refuse (a :class:`MetroError`) equipment past its due date ``on``, unless ``allow_expired``;
    return the expired ones' sentences (the report states them)."""
    expired = expired_equipment(campaign, on)
    if expired and not allow_expired:
        raise MetroError(
            f"equipment past its calibration due date on the measurement date {on.isoformat()}: "
            + "; ".join(expired),
            hint="recalibrate it (and update the lab profile or manifest), or run with "
            "--allow-expired (the report then says so)",
        )
    return expired


def _say(language: str, zh: str, en: str) -> str:
    """One statement in the lab's certificate language: ``zh``, ``en`` or both (``zh+en``)."""
    if language == "zh":
        return zh
    if language == "en":
        return en
    return f"{zh} {en}"


#: why a report is not registered: (中文, English)
NOT_REGISTERED = {
    "no lab profile": ("未配置实验室档案", "no lab profile"),
    "simulated": ("仿真运行", "simulated run; --register-simulated registers it"),
}


def unregistered(record: "RunRecord", why: str, language: str = "zh+en") -> dict[str, Any]:
    """The register statement of a report that is not registered (``why``: a key of
    :data:`NOT_REGISTERED`)."""
    zh, en = NOT_REGISTERED[why]
    n = record.report_number
    return {
        "registered": False, "number": n, "supersedes": None, "reason": "", "expired": [],
        "on": None,
        "notices": [_say(language,
                         f"未登记（{zh}）：本报告未列入实验室报告登记册，编号 {n} 不是登记编号。",
                         f"Not registered ({en}): this report is in no lab register, and its "
                         f"number {n} is not a register number.")],
    }


def notices_for(lab: "LabProfile", number: str, *, supersedes: str | None = None, reason: str = "",
                expired: Sequence[str] = (), on: str | None = None) -> list[str]:
    """The statements at the top of a registered report: its register number and lab, the report
    it replaces and why, and equipment used past its due date (``--allow-expired``)."""
    lang = lab.language
    out = [_say(lang, f"登记报告 {number}，{lab.name_zh or lab.name_en}。",
                f"Registered report {number} of {lab.name_en or lab.name_zh}.")]
    if supersedes:
        out.append(_say(lang, f"本报告替代报告 {supersedes}（该报告已被替代）。原因：{reason}",
                        f"This report replaces report {supersedes}, which is superseded by it. "
                        f"Reason: {reason}"))
    if expired:
        out.append(_say(lang,
                        f"按 --allow-expired 出具：下列设备在测量日期 {on} 已超过校准有效期："
                        + "；".join(expired) + "。",
                        "Issued with --allow-expired: equipment past its calibration due date on "
                        f"the measurement date {on}: " + "; ".join(expired) + "."))
    return out


# --------------------------------------------------------------------------------------
# The render context as JSON (figures' PlotSpec included)
# --------------------------------------------------------------------------------------


def _plain(v: Any) -> Any:
    """A figure's numbers as JSON values: a pint quantity's magnitude, an array as a list (a
    non-finite value as None), a numpy number as a float; anything else as it is."""
    import numpy as np

    v = getattr(v, "magnitude", v)
    if isinstance(v, np.ndarray):
        return [None if not np.isfinite(x) else float(x) for x in v.ravel()]
    if isinstance(v, (np.floating, np.integer)):
        return float(v)
    return v


def encode_context(ctx: Mapping[str, Any]) -> dict[str, Any]:
    """The context as plain JSON: each figure's PlotSpec as ``{"plotspec": {field: value}}`` (every
    field of the class, series as lists of numbers) and every translatable text, wherever it is —
    in the context, a figure's title and labels, a series' legend entry or any value nested in
    them — as ``{"text": {...}}``, so that a document written again from the register draws its
    figures in every language of the certificate, as the first one did (issue 29)."""
    from ..base.locale import Text
    from ..model.results import PlotSpec
    from .register import json_safe

    def enc(obj: Any, figure: bool) -> Any:
        # a message keeps its id and fields: the document is written again in any language
        if isinstance(obj, Text):
            return {"text": obj.encode()}
        if isinstance(obj, PlotSpec):
            return {"plotspec": {f.name: enc(getattr(obj, f.name), True) for f
                                 in attrs.fields(PlotSpec)}}
        if figure:
            obj = _plain(obj)
        if isinstance(obj, Mapping):
            return {str(k): enc(v, figure) for k, v in obj.items() if figure or k != "image"}
        if isinstance(obj, (list, tuple)):
            return [enc(v, figure) for v in obj]
        return obj

    return json_safe(enc(ctx, False))


def decode_context(doc: Mapping[str, Any]) -> dict[str, Any]:
    """:func:`encode_context` undone: figures become PlotSpec again (images drawn when rendering),
    translatable texts :class:`Text` again wherever they are; a figure's missing numbers (None in
    a list) are NaN again.  A context stored before figures kept their texts reads as it was."""
    from ..base.locale import Text
    from ..model.results import PlotSpec

    fields = {f.name for f in attrs.fields(PlotSpec)}

    def dec(obj: Any, figure: bool) -> Any:
        if isinstance(obj, Mapping):
            if set(obj) == {"text"} and isinstance(obj["text"], Mapping):
                return Text.decode(obj["text"])
            if set(obj) == {"plotspec"}:
                return PlotSpec(**{k: dec(v, True) for k, v in obj["plotspec"].items() if k
                                   in fields})
            return {k: dec(v, figure) for k, v in obj.items()}
        if isinstance(obj, list):
            return [float("nan") if figure and v is None else dec(v, figure) for v in obj]
        return obj

    ctx = dec(doc, False)
    for o in ctx.get("outcomes", []):
        for p in o.get("plots", []):
            p.setdefault("image", None)
    return ctx


# --------------------------------------------------------------------------------------
# Issuing
# --------------------------------------------------------------------------------------


def _template(pm: "MetroPluginManager", standard: str):
    return pm.template_for(standard)


def _lab_identity(lab: "LabProfile") -> dict[str, Any]:
    return {"name_zh": lab.name_zh, "name_en": lab.name_en, "address": lab.address,
            "accreditation_body": lab.accreditation_body,
            "accreditation_number": lab.accreditation_number,
            "signatories": [s.as_dict() for s in lab.signatories], "source": lab.source}


def draft_for(record: "RunRecord", ctx: Mapping[str, Any], *, lab: "LabProfile", template: Any,
              allow_expired: bool, options: Mapping[str, Any] | None = None):
    """The register row of a run (:class:`~metro.core.record.register.Draft` without its writer)."""
    from ..model.record_json import options_json, record_document

    doc = record_document(record, None)
    camp = record.campaign
    dev = camp.device
    on = measurement_date(record)
    customer = getattr(camp, "customer", None)
    customer = getattr(customer, "name",
                       None) if customer is not None else camp.meta.get("customer", "")
    results = []
    for o in record.outcomes:
        for r in o.results:
            d = r.as_dict()
            results.append({"item": o.item, "key": d["key"], "quantity": d["quantity"],
                            "symbol": d["symbol"],
                            "value": d["value"], "u": d["u"], "U": d["U"], "k": d["k"],
                            "nu_eff": d["nu_eff"],
                            "unit": d["unit"], "value_text": d["reported"]["value"] or "",
                            "U_text": d["reported"]["U"], "reportable": bool(d["reportable"]),
                            "reason": d["reason"] or ""})
    equipment = [{"id": e.id, "role": e.role, "description": e.describe(),
                  "certificate": e.calibration.certificate if e.calibration else None,
                  "due": e.calibration.due.isoformat() if e.calibration and e.calibration.due
                  else None,
                  "status": e.status(on),
                  "valid": None if e.calibration is None else e.calibration.is_valid(on)}
                 for e in camp.equipment]
    provenance = dict(doc["provenance"])
    provenance["template"] = {"name": template.name, "layout": template.layout
                              if isinstance(template.layout, str)
                              else None, "sha256": _template_sha256(template)}
    fields = {
        "standard": record.standard,
        "items": [o.item for o in record.outcomes],
        "options": {o.item: options_json(o.options) for o in record.outcomes}
        | ({"_given": options_json(options)} if options else {}),
        "device_id": dev.id, "device_manufacturer": dev.manufacturer, "device_model": dev.model,
        "device_serial": dev.serial or dev.id,
        "customer": str(customer or ""),
        "measurement_date": on,
        "simulated": bool(record.simulated),
        "allow_expired": bool(allow_expired and expired_equipment(camp, on)),
        "lab": _lab_identity(lab),
        "verdicts": doc["conformity"],
        "budgets": doc["budgets"],
        "provenance": provenance,
        "manifest_sha256": getattr(camp, "manifest_sha256", "") or None,
        "equipment": equipment,
        "template": template.name,
    }
    return fields, results


def register_run(
    record: "RunRecord",
    *,
    pm: "MetroPluginManager",
    lab: "LabProfile",
    folder: str | os.PathLike[str],
    register: "Register | None" = None,
    allow_expired: bool = False,
    supersedes: str | None = None,
    reason: str = "",
    options: Mapping[str, Any] | None = None,
    who: str | None = None,
    lang: str | None = None,
    dcc: Any = None,
) -> tuple["Issued", "RunRecord"]:
    """Issue ``record``'s report under the next register number in ``folder``; return the issued
    report and the record carrying its number.  Equipment past its due date on the measurement
    date refuses it unless ``allow_expired``.  With ``supersedes`` it is an amendment.  With
    ``dcc`` (a :class:`metro.core.record.dcc_out.DccWriter`) the report's DCC is issued with it
    (``folder/<number>.xml``, its SHA-256 in the register), checked before a number is
    allocated."""
    from .register import Draft, open_register
    from ..documents.report import build_context, render_context

    record = with_lab(record, lab)
    on = measurement_date(record)
    expired = check_equipment(record.campaign, on, allow_expired=allow_expired)
    template = _template(pm, record.standard)
    designations = {s.id: s.designation for s in pm.registry.standards.values()}
    own = register is None
    reg = register or open_register(lab.register_url())
    numbered: list[Any] = []
    # everything that does not depend on the number is made before the register's lock is taken:
    # the context with a provisional number (replaced once allocated), and the figures
    import tempfile

    from ..documents.report import render_figures

    pending = attrs.evolve(record, report_number=PENDING)
    statement = {"registered": True, "number": PENDING, "supersedes": supersedes, "reason": reason,
                 "lab": lab.name, "expired": list(expired), "on": on.isoformat(),
                 "notices": notices_for(lab, PENDING, supersedes=supersedes, reason=reason,
                                        expired=expired,
                                        on=on.isoformat())}
    ctx0 = build_context(pending, designations=designations, extend=pm.extend_report_context,
                         register=statement,
                         lang=lang or lab.language)
    if dcc is not None:  # refused (an unmapped unit) before anything is allocated or written
        dcc.check(ctx0)
    tmpdir = tempfile.TemporaryDirectory(prefix="metro-figures-")
    figures = render_figures(ctx0, tmpdir.name)

    def make(number: str, issued_at: dt.datetime) -> Draft:
        rec = attrs.evolve(record, report_number=number)
        numbered.append(rec)
        ctx = _replace_text(ctx0, PENDING, number)
        ctx["register"] = dict(ctx["register"], issued_at=issued_at.isoformat())
        fields, results = draft_for(rec, ctx, lab=lab, template=template,
                                    allow_expired=allow_expired,
                                    options=options)
        fields["context"] = encode_context(ctx)

        def write(tmp: Path) -> None:
            render_context(tmp, ctx, template=template.path, layout=template.layout,
                           figures=figures)

        return Draft(fields, results, write, dcc=dcc.maker(decode_context(fields["context"]))
                     if dcc is not None else None)

    try:
        issued = reg.issue(make, folder=folder, scheme=lambda seq,
                           year: lab.format_number(seq, year),
                           per_year=lab.per_year(), timezone=lab.timezone, supersedes=supersedes,
                           reason=reason,
                           who=who)
    finally:
        tmpdir.cleanup()
        if own:
            reg.close()
    pm.report_written(issued.path, record.outcomes)
    return issued, numbered[-1]


def stored_context(reg: "Register", number: str, pm: "MetroPluginManager") -> tuple[Any, Any]:
    """Report ``number``'s stored document context and the loaded template it was rendered with;
    a :class:`MetroError` when no loaded plugin registers that template now."""
    doc, template_name = reg.context(number)
    if template_name == "validation":  # metro validate's record (metro.core.validation)
        raise MetroError(f"{number} is a software validation record (metro validate): it is kept "
                         "as issued and not rendered again",
                         hint="its file is listed by `metro register show`; run `metro validate` "
                         "for a new validation")
    tpl = pm.register_all().templates.get(template_name)
    if tpl is None:
        raise MetroError(f"report {number} was rendered with the template {template_name!r}, which "
                         "no loaded plugin registers now",
                         hint="load the plugin of its standard (metro plugins)")
    return doc, tpl


def rerender(reg: "Register", number: str, out: str | os.PathLike[str], *,
             pm: "MetroPluginManager") -> Path:
    """Write report ``number`` again from the register into ``out/<number>.docx`` (never replacing
    a file): the stored context rendered into the standard's template."""
    from ..base.atomic import atomic_path
    from ..documents.report import render_context

    doc, tpl = stored_context(reg, number, pm)
    folder = Path(out)
    folder.mkdir(parents=True, exist_ok=True)
    target = folder / f"{number}.docx"
    if target.exists():
        raise MetroError(f"{target} exists; metro report does not replace a file",
                         hint="give another --out folder")
    ctx = decode_context(doc)
    with atomic_path(target) as tmp:
        render_context(tmp, ctx, template=tpl.path, layout=tpl.layout)
        if target.exists():
            raise MetroError(f"{target} exists; metro report does not replace a file")
    return target


def template_changed(reg: "Register", number: str, pm: "MetroPluginManager") -> bool | None:
    """Whether the template report ``number`` was rendered with differs now (its SHA-256); None
    when it was not recorded.  A re-rendered report then has the same content in a new layout."""
    stored = (reg.get(number)["provenance"].get("template") or {})
    tpl = pm.register_all().templates.get(stored.get("name") or "")
    now = _template_sha256(tpl) if tpl is not None else None
    if not stored.get("sha256") or now is None:
        return None
    return now != stored["sha256"]


def _template_sha256(template: Any) -> str | None:
    """The identity of a registered document: its docxtpl file's SHA-256, or for a layout
    (metro.core.documents.document) the SHA-256 of its code and message catalog."""
    from .register import sha256_file

    if template.path is not None:
        path = Path(os.fspath(template.path))
        return sha256_file(path) if path.is_file() else None
    from ..documents.document import layout_digest

    return layout_digest(template.layout)


def amend(
    reg: "Register", number: str, reason: str, *, pm: "MetroPluginManager", lab: "LabProfile",
    folder: str | os.PathLike[str] | None = None, record: "RunRecord | None" = None,
    allow_expired: bool = False, who: str | None = None, dcc: Any = None,
) -> "Issued":
    """Issue a report replacing ``number``: from ``record`` (a new run, ``--data``) or, without
    one, from the stored content of ``number`` under a new number with the amendment stated.
    With ``dcc`` (a :class:`metro.core.record.dcc_out.DccWriter`) the new report's DCC is issued
    with it, stating the replacement (``reportAmendedSubstituted``)."""
    from .register import Draft
    from ..documents.report import render_context

    if not reason.strip():
        raise MetroError("an amendment needs a reason (--reason TEXT)")
    old = reg.get(number)
    folder = Path(folder) if folder is not None else Path(old["report_path"]).parent
    writer = dcc
    if record is not None:
        issued, _ = register_run(record, pm=pm, lab=lab, folder=folder, register=reg,
                                 allow_expired=allow_expired,
                                 supersedes=number, reason=reason, who=who, dcc=writer)
        return issued
    doc, tpl = stored_context(reg, number, pm)
    if writer is not None:  # refused (an unmapped unit) before anything is allocated or written
        writer.check(decode_context(doc))

    from sqlalchemy import select

    from .register.models import Report

    with reg._session(read=True) as s:
        row = s.execute(select(Report).where(Report.number == number)).scalar_one()
        keep = {c: getattr(row, c) for c in (
            "standard", "items", "options", "device_id", "device_manufacturer", "device_model",
            "device_serial",
            "customer", "measurement_date", "simulated", "allow_expired", "lab", "verdicts",
            "budgets",
            "provenance", "manifest_sha256", "equipment", "template")}
        results = [{c: getattr(x, c) for c in ("item", "key", "quantity", "symbol", "value", "u",
                                               "U", "k",
                                               "nu_eff", "unit", "value_text", "U_text",
                                               "reportable", "reason")}
                   for x in row.results]

    def make(new: str, issued_at: dt.datetime) -> Draft:
        old_number = doc["report_number"]
        ctx = decode_context(_replace_text(doc, old_number, new))
        before = ctx.get("register") or {}
        expired, on = before.get("expired") or [], before.get("on")
        ctx["register"] = {"registered": True, "number": new, "supersedes": number,
                           "reason": reason,
                           "lab": lab.name, "expired": expired, "on": on,
                           "notices": notices_for(lab, new, supersedes=number, reason=reason,
                                                  expired=expired, on=on),
                           "issued_at": issued_at.isoformat()}
        fields = dict(keep, context=encode_context(ctx))

        def write(tmp: Path) -> None:
            render_context(tmp, ctx, template=tpl.path, layout=tpl.layout)

        return Draft(fields, results, write, dcc=writer.maker(decode_context(fields["context"]))
                     if writer is not None else None)

    return reg.issue(make, folder=folder, scheme=lambda seq, year: lab.format_number(seq, year),
                     per_year=lab.per_year(), timezone=lab.timezone, supersedes=number,
                     reason=reason, who=who)


def _replace_text(obj: Any, old: str, new: str) -> Any:
    """``old`` replaced by ``new`` in every string of a context (the report number wherever a
    template or plugin context printed it). A translatable text stays one: a :class:`Text` is mapped
    field by field (:meth:`Text.map`), and its JSON form (``{"text": {...}}``, as the register keeps
    it) has its fields, parts and English replaced, never its message id, so the document still
    writes it in every language of the certificate. A figure's PlotSpec (in a context made by
    :func:`~metro.core.documents.report.build_context`) has every field mapped the same way."""
    from ..base.locale import Text
    from ..model.results import PlotSpec

    if isinstance(obj, Text):
        return obj.map(lambda s: s.replace(old, new)) if old in obj else obj
    if isinstance(obj, str):
        return obj.replace(old, new)
    if isinstance(obj, PlotSpec):
        return attrs.evolve(obj, **{f.name: _replace_text(getattr(obj, f.name), old, new)
                                    for f in attrs.fields(PlotSpec)})
    if isinstance(obj, Mapping):
        if set(obj) == {"text"} and isinstance(obj["text"], Mapping):
            return {"text": {k: (v if k in ("msgid", "sep") else _replace_text(v, old, new))
                             for k, v in obj["text"].items()}}
        return {k: _replace_text(v, old, new) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_replace_text(v, old, new) for v in obj]
    if isinstance(obj, tuple):
        return tuple(_replace_text(v, old, new) for v in obj)
    return obj


def history(reg: "Register", serial: str, *, keys: Sequence[str] | None = None) -> dict[str, Any]:
    """A device's calibrations (issued reports, oldest first) and each result over time, with
    |E_n| = |x₂ − x₁| / √(U₁² + U₂²) between consecutive calibrations; |E_n| > 1 is drift
    (ISO 13528 §9.7 / the usual comparison criterion)."""
    import math

    reports = [r for r in reg.list(device=serial, results=True) if r["status"] == "issued"]
    reports.sort(key=lambda r: (r["measurement_date"], r["issued_at"]))
    series: dict[tuple[str, str, str], list[dict[str, Any]]] = {}
    for r in reports:
        for x in r["results"]:
            if x["value"] is None or not x["reportable"]:
                continue
            if keys and x["key"] not in keys:
                continue
            series.setdefault((r["standard"], x["item"], x["key"]), []).append({
                "number": r["number"], "date": r["measurement_date"], "value": x["value"],
                "U": x["U"],
                "unit": x["unit"], "symbol": x["symbol"], "quantity": x["quantity"],
                "reported": x["reported"]})
    out = []
    for (std, item, key), pts in series.items():
        for a, b in zip(pts, pts[1:]):
            if a["U"] and b["U"] and a["unit"] == b["unit"]:
                en = abs(b["value"] - a["value"]) / math.sqrt(a["U"] ** 2 + b["U"] ** 2)
                b["E_n"] = en
                b["drift"] = en > 1.0
            else:
                b["E_n"] = None
                b["drift"] = None
        out.append({"standard": std, "item": item, "key": key, "symbol": pts[0]["symbol"],
                    "quantity": pts[0]["quantity"], "unit": pts[0]["unit"], "points": pts,
                    "drift": any(p.get("drift") for p in pts)})
    return {"serial": serial, "calibrations": [{k: r[k] for k in ("number", "standard", "items",
                                                                   "measurement_date", "issued_at",
                                                                  "status")}
                                               for r in reports], "results": out}


def history_plot(hist: Mapping[str, Any], path: str | os.PathLike[str]) -> Path:
    """One panel per result: value against measurement date with U error bars, drift points in
    red."""
    import matplotlib

    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib import dates as mdates
    from matplotlib.figure import Figure

    from ..base.atomic import atomic_path
    from ..documents.plots import MissingGlyphs, font_families

    results = hist["results"]
    n = max(1, len(results))
    with matplotlib.rc_context({"font.family": font_families()}), MissingGlyphs():
        fig = Figure(figsize=(7.0, 2.4 * n), layout="constrained")
        FigureCanvasAgg(fig)
        axes = fig.subplots(n, 1, squeeze=False)[:, 0]
        for ax, res in zip(axes, results):
            dates = [dt.date.fromisoformat(p["date"]) for p in res["points"]]
            vals = [p["value"] for p in res["points"]]
            errs = [p["U"] or 0.0 for p in res["points"]]
            ax.errorbar(dates, vals, yerr=errs, fmt="o-", capsize=4, label="value ± U")
            drift = [(d, v) for d, v, p in zip(dates, vals, res["points"]) if p.get("drift")]
            if drift:
                ax.plot([d for d, _ in drift], [v for _, v in drift], "s", color="red", mfc="none",
                        ms=12,
                        label="drift: |E_n| > 1")
            unit = f" / {res['unit']}" if res["unit"] not in ("", "1") else ""
            title = f"{res['standard']} {res['item']}: {res['quantity']} {res['symbol']}"
            ax.set_title(title.strip(), fontsize=9)
            ax.set_ylabel(f"{res['symbol'] or res['key']}{unit}")
            ax.legend(fontsize=7)
            ax.grid(True, alpha=0.3)
            # dates that do not overlap however many reports there are (year once, then months);
            # one day only: that date
            if len(set(dates)) > 1:
                locator = mdates.AutoDateLocator(maxticks=8)
                ax.xaxis.set_major_locator(locator)
                ax.xaxis.set_major_formatter(mdates.ConciseDateFormatter(locator))
            else:
                ax.set_xticks(dates[:1])
                ax.xaxis.set_major_formatter(mdates.DateFormatter("%Y-%m-%d"))
        if not results:
            axes[0].text(0.5, 0.5, f"no results for {hist['serial']}", ha="center", va="center")
        fig.suptitle(f"History of device {hist['serial']}")
        with atomic_path(path) as tmp:
            fig.savefig(tmp, format="png", dpi=100)
    return Path(path)

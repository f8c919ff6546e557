"""Render a :class:`~metro.core.model.provenance.RunRecord` as a Word (and PDF) report or
certificate.

Two steps, so the content can be checked without Word:

1. :func:`~metro.core.documents.context.build_context` turns the record into a plain dict of
   strings, lists and dicts (:mod:`metro.core.documents.context`);
2. :func:`write_report` builds the document from that dict with
   :class:`metro.core.documents.document.DocumentBuilder` and the standard's layout (each plugin
   lays out
   its own appendix), or renders a docxtpl template of a lab's own, draws the figures with
   :mod:`metro.core.documents.plots`, and writes the ``.docx`` (or ``.pdf``, through LibreOffice)
   atomically: a failure at any point leaves no file at the target (and an earlier report
   there untouched).

docx, docxtpl, matplotlib and pint are imported inside the functions, so
``import metro.core.documents.report`` stays cheap.
"""

from __future__ import annotations

import datetime as dt
import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping

from ..base.atomic import atomic_path
from ..base.locale import translator
from .context import build_context
from .document import DocumentBuilder, generic_layout
from .pdf import soffice_path, to_pdf

if TYPE_CHECKING:  # pragma: no cover
    from ..model.provenance import RunRecord

__all__ = [
    "write_report",
    "build_context",
    "render_context",
    "render_figures",
    "draw_figure",
    "build_document",
    "default_template",
    "IMAGE_WIDTH_MM",
]

#: Width of a figure in the report.
IMAGE_WIDTH_MM = 150

# --------------------------------------------------------------------------------------
# Word
# --------------------------------------------------------------------------------------


def default_template() -> Any:
    """The packaged docxtpl template, ``metro/core/documents/templates/report.docx`` (an importlib
    Traversable): a starting point for a lab's own template; metro's documents are built by
    :mod:`metro.core.documents.document`."""
    from importlib import resources

    return resources.files("metro.core.documents") / "templates" / "report.docx"


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

    Without ``template`` the document is built by
    :class:`metro.core.documents.document.DocumentBuilder`
    with ``layout`` (a callable ``layout(doc, ctx)``, ``"module:function"`` text, or None for the
    generic report) in ``lang`` (``zh``, ``en`` or ``zh+en``; default ``zh+en``).  With ``template``
    (a docxtpl ``.docx`` of a lab's own) the template is rendered instead. A ``path`` ending in
    ``.pdf`` writes the PDF only; ``pdf=True`` writes the ``.docx`` and a ``.pdf`` beside it
    (LibreOffice, :func:`metro.core.documents.pdf.to_pdf`).  Any failure leaves no file (and no
    temporary file) behind.
    """
    if Path(path).suffix.lower() == ".pdf" or pdf:
        soffice_path()  # a clear error before any work when LibreOffice is missing
    ctx = build_context(
        record, designations=designations, extend=extend, register=register, lang=lang
    )
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
    when the document opens with it (an inline picture; the floating verify QR code is no logo)."""
    from docx.oxml.ns import qn

    body = document.element.body
    first = body[0] if len(body) else None
    start = (
        1
        if first is not None and first.tag == qn("w:p") and first.findall(".//" + qn("wp:inline"))
        else 0
    )
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
            out[p["number"]] = draw_figure(
                p["spec"], tr, Path(folder) / f"figure-{p['number']}.png"
            )
    return out


def draw_figure(spec: Any, tr: Any, png: Path) -> Path:
    """Draw a figure of a context in the document's language (``tr``) as the PNG ``png``, in a
    folder of the document's own (a plain write: the folder is temporary).  A figure drawn before
    with the same inputs comes from :mod:`metro.core.documents.figure_cache` (a document written
    again from
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
            target = path if pdf_only else path.with_suffix(".pdf")
            with atomic_path(target) as tmp:
                to_pdf(docx_tmp, Path(tmp))
        if not pdf_only:
            with atomic_path(path) as tmp:
                Path(tmp).write_bytes(docx_tmp.read_bytes())
    return path


def _resolve_layout(layout: Any) -> Callable[..., None]:
    """A layout callable from a callable, ``"module:function"`` text or None (the generic one)."""
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


def build_document(
    ctx: Mapping[str, Any],
    figdir: Path,
    *,
    layout: Any = None,
    lang: str | None = None,
    figures: Mapping[int, str | os.PathLike[str]] | None = None,
) -> Any:
    """The document of a context built in memory (a
    :class:`~metro.core.documents.document.DocumentBuilder`);
    figures are drawn into ``figdir``; ``doc.tr.missing`` lists message ids the catalog lacked."""
    ctx = dict(ctx)
    ctx["outcomes"] = [dict(o, plots=[dict(p) for p in o["plots"]]) for o in ctx["outcomes"]]
    tr = translator(lang or ctx.get("lang"))
    ctx["lang"] = tr.lang
    ctx["doc_title"] = _document_title(ctx, tr)
    doc = DocumentBuilder(
        number=ctx["report_number"],
        title=ctx["doc_title"],
        tr=tr,
        simulated=ctx["simulated"],
        footer=ctx["generator"],
    )
    if ctx.get("logo"):
        import base64

        doc.logo = base64.b64decode(ctx["logo"]["base64"])
    link = _verify_link(ctx)
    if link:
        from .qr import qr_png

        doc.qr = (qr_png(link), link)
    for o in ctx["outcomes"]:
        for p in o["plots"]:
            if figures is not None and p["number"] in figures:
                p["image"] = str(figures[p["number"]])
            else:
                p["image"] = str(
                    draw_figure(p["spec"], tr, Path(figdir) / f"figure-{p['number']}.png")
                )
    _resolve_layout(layout)(doc, ctx)
    _add_notices(doc.doc, (ctx.get("register") or {}).get("notices") or ())
    _set_properties(doc.doc, ctx)
    return doc


def _verify_link(ctx: Mapping[str, Any]) -> str:
    """The verify link a registered report prints as a QR code (the lab profile's verify URL and
    the report number), or ``""``: none without a verify URL or when the report is not
    registered."""
    if not (ctx.get("verify_url") and (ctx.get("register") or {}).get("registered")):
        return ""
    from .qr import verify_link

    return verify_link(ctx["verify_url"], ctx["report_number"])


def _render_template(
    target: Path,
    ctx: dict,
    template: str | os.PathLike[str],
    figures: Mapping[int, str | os.PathLike[str]] | None = None,
) -> None:
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
        link = _verify_link(ctx)
        if link:  # the template's {{ verify_qr }} and {{ verify_link }}
            from .qr import qr_png

            ctx["verify_qr"] = InlineImage(tpl, io.BytesIO(qr_png(link)),
                                           width=Mm(DocumentBuilder.QR_MM))
            ctx["verify_link"] = link
        try:
            tpl.render(ctx, autoescape=True)
        except TemplateError as exc:
            where = f" (line {exc.lineno})" if getattr(exc, "lineno", None) else ""
            raise MetroError(
                f"report template {template_name}: {exc}{where}",
                hint="check the template's {{ }} and {% %} tags against "
                "metro.core.documents.context.report_context",
            ) from exc
    _add_notices(tpl.docx, (ctx.get("register") or {}).get("notices") or ())
    _set_properties(tpl.docx, ctx)
    tpl.save(str(target))

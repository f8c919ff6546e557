"""The one document builder for every report and certificate metro writes.

A plugin supplies only its appendix's content and order (a *layout*: a function
``layout(doc, ctx)``); this module supplies the pieces every document shares:

* A4 portrait, 20 mm margins; a header on every page with the title, the report number and
  "page x of y" (Word fields), and the SIMULATED mark on every page when the data are simulated;
* headings kept with what follows (``w:keepNext``);
* tables whose header row repeats on every page (``w:tblHeader``), whose rows never split
  across pages (``w:cantSplit``), and whose column widths are computed from their content: the
  grid (``w:tblGrid``, which LibreOffice draws by) and every cell (``w:tcW``, which Word draws
  by) carry the same widths, and no column is narrower than its longest unbreakable word, so a
  number never breaks across lines (a number and its unit are joined by a no-break space);
* symbols with real subscripts: ``K_l`` prints as K with a subscript l;
* figures placed with their caption kept on the same page;
* labels through the message catalog (:mod:`metro.core.base.locale`): ``--lang zh|en|zh+en``.

Numbers are formatted before they get here, by :mod:`metro.core.documents.report` (one notation,
``×10ⁿ``).  python-docx is imported inside the functions.
"""

from __future__ import annotations

import functools
import math
import re
from typing import TYPE_CHECKING, Any, Callable, Iterable, Sequence

from .text import (BODY_PT, CELL_MARGIN_MM, CJK_FONT, HEAD_FILL, LABEL_FILL, LATIN_FONT, MARGIN_MM,
                   MIN_TABLE_PT, NBSP, PAGE_H_MM, PAGE_W_MM, TABLE_PT, TEXT_WIDTH_MM, column_widths,
                   glue, subscript_runs, two_lines, unit_may_wrap)

if TYPE_CHECKING:  # pragma: no cover
    from ..base.locale import Translator

__all__ = [
    "DocumentBuilder",
    "Layout",
    "append_runs",
    "fit_check",
    "oxml_element",
    "insert_ordered",
    "mm_to_twips",
    "TRPR_ORDER",
    "TBLPR_ORDER",
    "TCPR_ORDER",
]

#: a layout: fills the document from the report context
Layout = Callable[["DocumentBuilder", dict], None]

# ----------------------------------------------------------------------------------------
# The builder
# ----------------------------------------------------------------------------------------

TRPR_ORDER = (
    "w:cnfStyle",
    "w:divId",
    "w:gridBefore",
    "w:gridAfter",
    "w:wBefore",
    "w:wAfter",
    "w:cantSplit",
    "w:trHeight",
    "w:tblHeader",
    "w:tblCellSpacing",
    "w:jc",
    "w:hidden",
)
TBLPR_ORDER = (
    "w:tblStyle",
    "w:tblpPr",
    "w:tblOverlap",
    "w:bidiVisual",
    "w:tblStyleRowBandSize",
    "w:tblStyleColBandSize",
    "w:tblW",
    "w:jc",
    "w:tblCellSpacing",
    "w:tblInd",
    "w:tblBorders",
    "w:shd",
    "w:tblLayout",
    "w:tblCellMar",
    "w:tblLook",
)
TCPR_ORDER = (
    "w:cnfStyle",
    "w:tcW",
    "w:gridSpan",
    "w:hMerge",
    "w:vMerge",
    "w:tcBorders",
    "w:shd",
    "w:noWrap",
    "w:tcMar",
    "w:textDirection",
    "w:tcFitText",
    "w:vAlign",
)


def oxml_element(tag: str, **attrs: str):
    """A WordprocessingML element ``tag`` (``w:…``) with ``w:`` attributes."""
    from docx.oxml import OxmlElement
    from docx.oxml.ns import qn

    el = OxmlElement(tag)
    for k, v in attrs.items():
        el.set(qn(f"w:{k}"), v)
    return el


def insert_ordered(parent, child, order: tuple[str, ...]) -> None:
    """Put ``child`` into ``parent`` at the place the schema's element ``order``
    asks (ECMA-376), replacing an element of the same tag."""
    from docx.oxml.ns import qn

    tags = [qn(t) for t in order]
    later = set(tags[tags.index(child.tag) + 1 :])
    for existing in parent:
        if existing.tag == child.tag:
            parent.replace(existing, child)
            return
    for existing in parent:
        if existing.tag in later:
            existing.addprevious(child)
            return
    parent.append(child)


def mm_to_twips(mm: float) -> int:
    """Millimetres in twips (1/1440 inch), as Word's widths are written."""
    return int(round(mm / 25.4 * 1440))


# Runs and table rows are written as lxml elements directly (one SubElement call per element), not
# through python-docx's per-run and per-cell proxies, which parse a snippet of XML for every element
# they add and search the children for its place: a GB/T --all report has ~5 000 cells, and building
# them the python-docx way took most of the time of writing the report. The XML is the same element
# for element (tests/core/documents/test_document_speed.py builds both ways and compares).
_W = "{http://schemas.openxmlformats.org/wordprocessingml/2006/main}"
_XML_SPACE = "{http://www.w3.org/XML/1998/namespace}space"
_RUN_BREAKS = re.compile(r"([\t\r\n])")


@functools.lru_cache(maxsize=64)
def _half_points(size: float) -> str:
    """``w:sz`` of a size in points, as python-docx writes it (half-points, truncated)."""
    from docx.shared import Emu, Pt

    return str(int(Emu(Pt(size)).pt * 2))


@functools.lru_cache(maxsize=16)
def _rgb(color: str) -> str:
    from docx.shared import RGBColor

    return str(RGBColor.from_string(color))


def _run_text(r, text: str) -> None:
    """The content of run ``r`` for ``text``: ``w:t`` (``xml:space="preserve"`` when it starts or
    ends with white space), a tab as ``w:tab``, a carriage return or line feed as ``w:br``."""
    from lxml.etree import SubElement

    for chunk in (
        _RUN_BREAKS.split(text) if ("\t" in text or "\r" in text or "\n" in text) else (text,)
    ):
        if chunk == "\t":
            SubElement(r, _W + "tab")
        elif chunk in ("\r", "\n"):
            SubElement(r, _W + "br")
        elif chunk:
            t = SubElement(r, _W + "t")
            t.text = chunk
            if len(chunk.strip()) < len(chunk):
                t.set(_XML_SPACE, "preserve")


def append_runs(p, text: str, *, bold: bool = False, size: float | None = None,
                italic: bool = False, color: str | None = None) -> None:
    """Append ``text`` to the paragraph element ``p`` (``w:p``) as runs: a subscript (``K_l``) as
    its own run, a line break (``\\n``) as a run holding ``w:br``; every run formatted alike
    (bold, italic, colour ``RRGGBB``, size in points).  The text is used as given (see
    :meth:`DocumentBuilder.runs` for the translated, glued form)."""
    from lxml.etree import SubElement

    sz = _half_points(size) if size else None
    rgb = _rgb(color) if color else None
    lines = text.split("\n")
    for n, line in enumerate(lines):
        for piece, sub in subscript_runs(line):
            r = SubElement(p, _W + "r")
            if bold or italic or rgb or sz or sub:
                rpr = SubElement(r, _W + "rPr")
                if bold:
                    SubElement(rpr, _W + "b")
                if italic:
                    SubElement(rpr, _W + "i")
                if rgb:
                    SubElement(rpr, _W + "color", {_W + "val": rgb})
                if sz:
                    SubElement(rpr, _W + "sz", {_W + "val": sz})
                if sub:
                    SubElement(rpr, _W + "vertAlign", {_W + "val": "subscript"})
            _run_text(r, piece)
        if n < len(lines) - 1:
            SubElement(SubElement(p, _W + "r"), _W + "br")


class DocumentBuilder:
    """A Word document laid out the one way metro's documents are.

    :param number: the report or certificate number (from the run record), printed in every header.
    :param title: the document title (header and first line).
    :param tr: the translator (:func:`metro.core.base.locale.translator`).
    :param simulated: put the SIMULATED mark in every page header.
    :param footer: footer text (the software that wrote the document).
    """

    def __init__(
        self,
        *,
        number: str,
        title: str,
        tr: "Translator",
        simulated: bool = False,
        footer: str = "",
    ):
        import docx
        from docx.oxml.ns import qn
        from docx.shared import Mm, Pt

        self.tr = tr
        self.number = number
        self.title = title
        self.simulated = simulated
        self.doc = docx.Document()
        sec = self.doc.sections[0]
        sec.page_width, sec.page_height = Mm(PAGE_W_MM), Mm(PAGE_H_MM)
        for side in ("left_margin", "right_margin", "top_margin", "bottom_margin"):
            setattr(sec, side, Mm(MARGIN_MM))
        sec.header_distance = sec.footer_distance = Mm(10)
        for name in ("Normal", "Heading 1", "Heading 2", "Heading 3", "Title"):
            st = self.doc.styles[name]
            st.font.name = LATIN_FONT
            rpr = st.element.get_or_add_rPr()
            fonts = rpr.find(qn("w:rFonts"))
            if fonts is None:
                fonts = oxml_element("w:rFonts")
                rpr.insert(0, fonts)
            for attr in ("w:ascii", "w:hAnsi", "w:cs"):
                fonts.set(qn(attr), LATIN_FONT)
            fonts.set(qn("w:eastAsia"), CJK_FONT)
            for attr in ("w:asciiTheme", "w:hAnsiTheme", "w:eastAsiaTheme", "w:cstheme"):
                if fonts.get(qn(attr)) is not None:
                    del fonts.attrib[qn(attr)]
            st.font.color.rgb = None
        self.doc.styles["Normal"].font.size = Pt(BODY_PT)
        pf = self.doc.styles["Normal"].paragraph_format
        pf.space_after = Pt(2)
        pf.space_before = Pt(0)
        pf.widow_control = True
        for name, size in (("Heading 1", 12), ("Heading 2", 10.5), ("Heading 3", 9.5)):
            st = self.doc.styles[name]
            st.font.size = Pt(size)
            st.font.bold = True
            st.font.italic = False
            st.paragraph_format.space_before = Pt(8 if name != "Heading 3" else 5)
            st.paragraph_format.space_after = Pt(3)
            st.paragraph_format.keep_with_next = True
        self._header(footer)

    # -- page furniture ------------------------------------------------------------------

    def _field(self, paragraph, instr: str, shown: str, half_points: int = 16) -> None:
        """A Word field (PAGE, NUMPAGES) in the header's 8-point type (its number was drawn in the
        body size, larger than the words around it)."""
        fld = oxml_element("w:fldSimple", instr=f" {instr} \\* MERGEFORMAT ")
        r = oxml_element("w:r")
        rpr = oxml_element("w:rPr")
        rpr.append(oxml_element("w:sz", val=str(half_points)))
        rpr.append(oxml_element("w:szCs", val=str(half_points)))
        r.append(rpr)
        t = oxml_element("w:t")
        t.text = shown
        r.append(t)
        fld.append(r)
        paragraph._p.append(fld)

    def _header(self, footer: str) -> None:
        from docx.enum.text import WD_TAB_ALIGNMENT
        from docx.shared import Mm, Pt, RGBColor

        sec = self.doc.sections[0]
        for name in ("Header", "Footer"):
            self.doc.styles[name].paragraph_format.tab_stops.clear_all()
        head = sec.header.paragraphs[0]
        head.paragraph_format.tab_stops.add_tab_stop(Mm(TEXT_WIDTH_MM), WD_TAB_ALIGNMENT.RIGHT)
        r = head.add_run(glue(f"{self.tr('Report No.')} {self.number}"))
        r.font.size = Pt(8)
        r = head.add_run("\t")
        # "page x of y": the catalog's sentence, with the two numbers as PAGE and NUMPAGES fields
        pattern = self.tr("Page {page} of {pages}")
        for piece in re.split(r"(\{page\}|\{pages\})", pattern):
            if piece == "{page}":
                self._field(head, "PAGE", "1")
            elif piece == "{pages}":
                self._field(head, "NUMPAGES", "1")
            elif piece:
                head.add_run(piece.replace(" ", NBSP)).font.size = Pt(8)
        if self.simulated:
            p = sec.header.add_paragraph()
            run = p.add_run(self.tr("SIMULATED — not a measurement of a real device"))
            run.bold = True
            run.font.size = Pt(8.5)
            run.font.color.rgb = RGBColor(0xB0, 0x1C, 0x1C)
        foot = sec.footer.paragraphs[0]
        foot.paragraph_format.tab_stops.add_tab_stop(Mm(TEXT_WIDTH_MM), WD_TAB_ALIGNMENT.RIGHT)
        run = foot.add_run(f"{self.number}\t{footer}")
        run.font.size = Pt(7.5)

    # -- text ------------------------------------------------------------------------------

    def runs(self, paragraph, text: str, *, bold: bool = False, size: float | None = None,
             italic: bool = False, color: str | None = None) -> None:
        """Add ``text`` to ``paragraph`` with real subscripts and no-break spaces."""
        append_runs(
            paragraph._p, glue(self.tr.text(text)), bold=bold, size=size, italic=italic, color=color
        )

    def heading(self, text: str, level: int = 1):
        """A heading of ``level`` (translated, with subscripts), kept with what follows."""
        p = self.doc.add_heading(level=level)
        self.runs(p, text)
        p.paragraph_format.keep_with_next = True
        return p

    #: the lab's logo (image bytes, from the lab profile), drawn above the title of page 1
    logo: bytes | None = None
    LOGO_HEIGHT_MM = 14.0
    #: the verify QR code of a registered report (PNG bytes, :mod:`metro.core.documents.qr`) and
    #: the link it encodes, drawn at the top right of page 1 when the lab profile has a verify URL
    qr: tuple[bytes, str] | None = None
    QR_MM = 22.0

    def title_block(self, title: str, subtitle: str = "") -> None:
        """The title (and subtitle) of page 1, under the lab's logo when the profile gives one;
        the verify QR code (:attr:`qr`) floats at the top right."""
        import io

        from docx.enum.text import WD_ALIGN_PARAGRAPH
        from docx.shared import Mm

        if self.logo:
            p = self.doc.add_paragraph()
            p.alignment = WD_ALIGN_PARAGRAPH.CENTER
            p.paragraph_format.keep_with_next = True
            p.add_run().add_picture(io.BytesIO(self.logo), height=Mm(self.LOGO_HEIGHT_MM))

        p = self.doc.add_paragraph()
        p.alignment = WD_ALIGN_PARAGRAPH.CENTER
        if self.qr:
            from .qr import float_top_right

            float_top_right(p, self.qr[0], self.QR_MM, self.qr[1])
        self.runs(p, title, bold=True, size=16)
        p.paragraph_format.space_after = self._pt(4)
        if subtitle:
            p = self.doc.add_paragraph()
            p.alignment = WD_ALIGN_PARAGRAPH.CENTER
            self.runs(p, subtitle, size=10)

    @staticmethod
    def _pt(v: float):
        from docx.shared import Pt

        return Pt(v)

    def para(
        self,
        text: str,
        *,
        bold: bool = False,
        size: float | None = None,
        keep_next: bool = False,
        italic: bool = False,
        color: str | None = None,
        box: bool = False,
    ):
        """A paragraph of ``text`` (translated and glued), formatted alike."""
        p = self.doc.add_paragraph()
        self.runs(p, text, bold=bold, size=size, italic=italic, color=color)
        if keep_next:
            p.paragraph_format.keep_with_next = True
        if box:
            ppr = p._p.get_or_add_pPr()
            bdr = oxml_element("w:pBdr")
            for side in ("top", "left", "bottom", "right"):
                bdr.append(
                    oxml_element(f"w:{side}", val="single", sz="8", space="4", color="B01C1C")
                )
            ppr.insert(0, bdr)
        return p

    def bullets(self, lines: Iterable[str], *, size: float | None = None) -> None:
        """One bulleted paragraph per line."""
        for line in lines:
            p = self.para("• " + self.tr.text(line), size=size)
            p.paragraph_format.left_indent = self._pt(10)
            p.paragraph_format.first_line_indent = self._pt(-7)

    def page_break(self) -> None:
        """A page break."""
        from docx.enum.text import WD_BREAK

        self.doc.add_paragraph().add_run().add_break(WD_BREAK.PAGE)

    # -- tables ----------------------------------------------------------------------------

    def table(
        self,
        header: Sequence[str] | None,
        rows: Sequence[Sequence[str]],
        *,
        font_pt: float = TABLE_PT,
        label_column: bool = False,
        width_mm: float = TEXT_WIDTH_MM,
        shade: Sequence[int] = (),
        prefer: int | None = None,
        prefer_share: float = 0.6,
        spans: Sequence[int] = (),
        bold_rows: Sequence[int] = (),
        unit_break: Sequence[int] = (),
    ):
        """A bordered table: ``header`` (repeated on every page; None for a label/value table),
        then ``rows`` (each row kept on one page).  ``label_column`` shades and bolds the first
        column (label/value tables).  ``shade`` lists row indexes to shade (summary rows). ``spans``
        lists rows (indexes into ``rows``, each a one-cell row) whose text spans every column (a
        title or a summary inside a long table; printed bold when it is in ``bold_rows`` too; never
        kept with the row below, see the comment in the loop).  In the columns ``unit_break`` a unit
        may go to the next line under its number (``4.946×10⁻⁸`` / ``°/°C/h``; the number stays
        whole). Column widths fit the content (:func:`column_widths`, spanning rows left out); the
        font
        shrinks (to 6.5 pt) only when the longest words would not fit otherwise."""
        rows = [[glue(self.tr.text(c)) for c in r] for r in rows]
        if unit_break:
            rows = [
                [unit_may_wrap(c) if j in unit_break else c for j, c in enumerate(r)] for r in rows
            ]
        head = [two_lines(glue(self.tr.text(h))) for h in header] if header else None
        spans = set(spans)
        n = len(head) if head else max(len(r) for i, r in enumerate(rows) if i not in spans)
        rows = [list(r) + [""] * (n - len(r)) for r in rows]
        everything = ([head] if head else []) + rows
        first = 1 if head else 0
        cols = [
            [r[j] for i, r in enumerate(everything) if i - first not in spans] for j in range(n)
        ]
        widths, pt = _fitted_widths(cols, width_mm, font_pt, bold_first=bool(head),
                                    bold_column=label_column, prefer=prefer,
                                    prefer_share=prefer_share)
        t = self._empty_table(n, width_mm, widths)
        tbl = t._tbl
        twips = [str(mm_to_twips(w)) for w in widths]
        for i, values in enumerate(everything):
            is_head = head is not None and i == 0
            if i - first in spans:
                # not kept with the row below: LibreOffice (7.x) lost every later row of a budget
                # whose kept title row fell at a page foot (a 6.2.7.7 report printed 1 of 6 rows
                # and no U); a title alone at a page foot is the lesser harm
                self._table_row(
                    tbl,
                    [values[0]],
                    [str(sum(mm_to_twips(w) for w in widths))],
                    span=n,
                    fills=[LABEL_FILL if i - first in shade else None],
                    keep=False,
                    bold=[i - first in bold_rows],
                    pt=pt,
                )
                continue
            row_fill = LABEL_FILL if (i - first) in shade else None
            fills = [
                HEAD_FILL if is_head else (LABEL_FILL if label_column and j == 0 else row_fill)
                for j in range(n)
            ]
            # the header row is kept with the next; a body row says it is not, the last says nothing
            keep = is_head if (is_head or i < len(everything) - 1) else None
            self._table_row(
                tbl,
                values,
                twips,
                header=is_head,
                fills=fills,
                keep=keep,
                bold=[is_head or (label_column and j == 0) for j in range(n)],
                pt=pt,
            )
        return t

    def _empty_table(self, n: int, width_mm: float, widths: Sequence[float]) -> Any:
        """A table of ``n`` columns of ``widths`` (mm) and no rows (they come as XML), in the body
        as Document.add_table puts it, without its search of the whole body for the section's
        width: the grid and ``w:tblW`` get the widths, fixed layout, the cell margins."""
        from docx.enum.table import WD_TABLE_ALIGNMENT
        from docx.oxml.ns import qn
        from docx.shared import Mm

        t = self.doc._body.add_table(0, n, Mm(width_mm))
        tbl = t._tbl
        tblPr = tbl.tblPr
        tblPr.style = self._table_style_id()
        t.alignment = WD_TABLE_ALIGNMENT.CENTER
        t.autofit = False
        insert_ordered(
            tblPr,
            oxml_element("w:tblW", w=str(sum(mm_to_twips(w) for w in widths)), type="dxa"),
            TBLPR_ORDER,
        )
        insert_ordered(tblPr, oxml_element("w:tblLayout", type="fixed"), TBLPR_ORDER)
        mar = oxml_element("w:tblCellMar")
        for side in ("left", "right"):
            mar.append(oxml_element(f"w:{side}", w=str(mm_to_twips(CELL_MARGIN_MM)), type="dxa"))
        insert_ordered(tblPr, mar, TBLPR_ORDER)
        grid = tbl.tblGrid
        for gc, w in zip(grid.findall(qn("w:gridCol")), widths):
            gc.set(qn("w:w"), str(mm_to_twips(w)))
        return t

    def _table_style_id(self) -> str:
        """The style id of "Table Grid" (looked up in the styles part once per document)."""
        if self._grid_style is None:
            from docx.enum.style import WD_STYLE_TYPE

            self._grid_style = self.doc.part.get_style_id("Table Grid", WD_STYLE_TYPE.TABLE)
        return self._grid_style

    _grid_style: str | None = None

    def _table_row(
        self,
        tbl,
        values: Sequence[str],
        twips: Sequence[str],
        *,
        span: int = 1,
        header: bool = False,
        fills: Sequence[str | None],
        keep: bool | None,
        bold: Sequence[bool],
        pt: float,
    ) -> None:
        """Append one ``w:tr`` to ``tbl``: never split across pages, repeated on each page when it
        is the ``header``; per cell its width (twips), fill, and one paragraph with no space after,
        kept with the next row or not (``keep``; None says nothing), its text through :meth:`runs`.
        With
        ``span`` > 1 its one cell spans that many grid columns."""
        from lxml.etree import SubElement

        tr = SubElement(tbl, _W + "tr")
        trPr = SubElement(tr, _W + "trPr")
        SubElement(trPr, _W + "cantSplit")
        if header:
            SubElement(trPr, _W + "tblHeader")
        for value, w, fill, b in zip(values, twips, fills, bold):
            tc = SubElement(tr, _W + "tc")
            tcPr = SubElement(tc, _W + "tcPr")
            SubElement(tcPr, _W + "tcW", {_W + "w": w, _W + "type": "dxa"})
            if span > 1:
                SubElement(tcPr, _W + "gridSpan", {_W + "val": str(span)})
            if fill:
                SubElement(
                    tcPr, _W + "shd", {_W + "val": "clear", _W + "color": "auto", _W + "fill": fill}
                )
            p = SubElement(tc, _W + "p")
            pPr = SubElement(p, _W + "pPr")
            if keep is not None:
                SubElement(pPr, _W + "keepNext", {} if keep else {_W + "val": "0"})
            SubElement(pPr, _W + "spacing", {_W + "after": "0"})
            append_runs(p, glue(self.tr.text(value)), bold=b, size=pt)

    def kv(self, pairs: Sequence[tuple[str, str]], *, font_pt: float = 9.0):
        """A label/value table (identification, signatures)."""
        return self.table(None, [(a, b) for a, b in pairs], font_pt=font_pt, label_column=True)

    def caption(self, text: str):
        """A centred caption (of a figure or table)."""
        from docx.enum.text import WD_ALIGN_PARAGRAPH

        p = self.para(text, size=8.5, italic=True)
        p.alignment = WD_ALIGN_PARAGRAPH.CENTER
        return p

    def figure(self, image_path: str, caption: str, *, width_mm: float = 150.0) -> None:
        """A figure with its caption below, the two kept on one page."""
        from docx.enum.text import WD_ALIGN_PARAGRAPH
        from docx.shared import Mm

        p = self.doc.add_paragraph()
        p.alignment = WD_ALIGN_PARAGRAPH.CENTER
        p.paragraph_format.keep_with_next = True
        p.add_run().add_picture(str(image_path), width=Mm(width_mm))
        self.caption(caption)

    def save(self, path) -> None:
        """Write the document to ``path``."""
        self.doc.save(str(path))


def _fitted_widths(cols: Sequence[Sequence[str]], width_mm: float, font_pt: float, *,
                   bold_first: bool, bold_column: bool, prefer: int | None,
                   prefer_share: float) -> tuple[list[float], float]:
    """Column widths (mm) and the font size (pt) of a table: :func:`column_widths` at
    ``font_pt``, the font shrunk by half points (to :data:`MIN_TABLE_PT`) while the longest
    words do not fit, and still too wide, widths in proportion to the longest words (a word may
    then break)."""
    pt = font_pt
    kw = dict(bold_first=bold_first, bold_column=bold_column, prefer=prefer,
              prefer_share=prefer_share)
    widths = column_widths(cols, width_mm, pt, **kw)
    while widths is None and pt > MIN_TABLE_PT:
        pt = max(MIN_TABLE_PT, pt - 0.5)
        widths = column_widths(cols, width_mm, pt, **kw)
    if widths is None:
        widths = column_widths(cols, width_mm, pt, bold_first=bold_first,
                               bold_column=bold_column, squeeze=True)
    return widths, pt


def fit_check(widths: Sequence[float], total: float = TEXT_WIDTH_MM) -> bool:
    """Whether column ``widths`` (mm) fill ``total`` to half a millimetre."""
    return math.isclose(sum(widths), total, abs_tol=0.5)

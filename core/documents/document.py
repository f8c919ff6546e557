"""One document builder for every report and certificate metro writes.

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
import unicodedata
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping, Sequence

from ..base.formatting import DASH, or_dash, pretty_powers, with_unit

if TYPE_CHECKING:  # pragma: no cover
    from ..base.locale import Translator

__all__ = ["DocumentBuilder", "Layout", "subscript_runs", "glue", "column_widths", "TEXT_WIDTH_MM",
           "DASH", "or_dash", "with_unit"]

PAGE_W_MM, PAGE_H_MM, MARGIN_MM = 210.0, 297.0, 20.0
TEXT_WIDTH_MM = PAGE_W_MM - 2 * MARGIN_MM
BODY_PT = 9.5
TABLE_PT = 8.5
MIN_TABLE_PT = 6.5
CELL_MARGIN_MM = 1.2
HEAD_FILL = "D9E2EC"
LABEL_FILL = "EEF2F6"
LATIN_FONT = "Times New Roman"
CJK_FONT = "SimSun"
NBSP = "\u00a0"
FIGURE_WIDTH_MM = 150.0

#: a layout: fills the document from the report context
Layout = Callable[["DocumentBuilder", dict], None]

# ----------------------------------------------------------------------------------------
# Text: subscripts, no-break spaces, width estimates
# ----------------------------------------------------------------------------------------

# a symbol with a subscript: one or two letters (Greek allowed, Δ prefix allowed), or max/min with a
# one-character subscript, "_",
# then 1–4 letters/digits or a braced group (s_{upper}); not inside a longer word or a file name (a Chinese
# character or a subscript digit before it is no word: 计数N_0, K₀₀ΔT_i).
_SUB = re.compile(r"(?<![A-Za-z0-9_./\\-])((?:max|min)(?=_[A-Za-z0-9](?!\w))|Δ?[A-Za-zΑ-Ωα-ω][A-Za-zΑ-Ωα-ω]?)_(?:\{([^{}]{1,8})\}|([A-Za-z0-9]{1,4}))(?![\w.\\/-]*\.\w{2,4}\b)(?!\w)")


def subscript_runs(text: str) -> list[tuple[str, bool]]:
    """``text`` cut into (piece, is_subscript): ``"K_l = 3"`` → [("K", False), ("l", True), (" = 3", False)].

    >>> subscript_runs("B_s and ΔB_V13; rate_table, t_startup, run_1.csv")
    [('B', False), ('s', True), (' and ΔB', False), ('V13', True), ('; rate_table, t_startup, run_1.csv', False)]
    """
    out: list[tuple[str, bool]] = []
    pos = 0
    for m in _SUB.finditer(text):
        out.append((text[pos:m.start()] + m.group(1), False))
        out.append((m.group(2) or m.group(3), True))
        pos = m.end()
    out.append((text[pos:], False))
    merged: list[tuple[str, bool]] = []
    for piece, sub in out:
        if not piece:
            continue
        if merged and merged[-1][1] == sub:
            merged[-1] = (merged[-1][0] + piece, sub)
        else:
            merged.append((piece, sub))
    return merged


_NUM_UNIT = re.compile(r"(?<=[\d⁰¹²³⁴⁵⁶⁷⁸⁹%″′°∞]) (?=[^\s\d(=,;]{1,12}(?:[\s,;)]|$))")
_EQ = re.compile(r"(?<=\b[A-Za-zνΔ]) = (?=[-−±\d(])|(?<=\b[A-Za-zνΔ]{2}) = (?=[-−±\d(])|(?<=[uUkK]) = ")


_SMALL = re.compile(r"(?<![\w.\-/])(-?)0\.(000+)(\d+)(?![\w.])")
_SUP = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def one_notation(text: str) -> str:
    """Plain decimals below 0.001 as ×10ⁿ, so a value and its U print in one notation
    (``0.0006021`` next to ``6.6×10⁻⁶`` → ``6.021×10⁻⁴``); every digit is kept.

    >>> one_notation("0.0006021 and 6.6×10⁻⁶; 0.0012; run_0.0001.csv")
    '6.021×10⁻⁴ and 6.6×10⁻⁶; 0.0012; run_0.0001.csv'
    """
    def sub(m: re.Match) -> str:
        digits = m.group(3)
        exp = -(len(m.group(2)) + 1)
        mant = digits[0] + (f".{digits[1:]}" if len(digits) > 1 else "")
        return f"{m.group(1)}{mant}×10{str(exp).translate(_SUP)}"

    return _SMALL.sub(sub, text)


#: a number and its unit as :func:`glue` joins them (a no-break space between)
_NUM_NBSP_UNIT = re.compile(r"^([^\s\u00a0]*[\d⁰¹²³⁴⁵⁶⁷⁸⁹])\u00a0([^\s\d=]\S*)$")


def _unit_may_wrap(cell: str) -> str:
    """``4.946×10⁻⁸ °/°C/h`` with an ordinary space before the unit (it may go under the number)
    and word joiners inside the unit (LibreOffice would break it at a slash)."""
    m = _NUM_NBSP_UNIT.match(cell)
    if m is None:
        return cell
    return f"{m.group(1)} " + "\u2060".join(m.group(2))


_NEG = re.compile(r"(?<![\w.\-/\u2060])-(?=\d)")


@functools.lru_cache(maxsize=8192)  # a report glues ~9 000 cell texts, most of them more than once
def glue(text: str) -> str:
    """No-break spaces where a line must not break: between a number and its unit
    (``1.2 ppm``) and around ``=`` in ``k = 2`` / ``U = 0.4``.

    >>> glue("U = 1.2 ppm (k = 2)") == "U\u00a0=\u00a01.2\u00a0ppm (k\u00a0=\u00a02)"
    True
    """
    text = _NUM_UNIT.sub(NBSP, _EQ.sub(f"{NBSP}={NBSP}", one_notation(pretty_powers(text))))
    # a minus sign written as a hyphen: LibreOffice breaks after it ("alpha0 = -" / "2.3…"),
    # a word joiner (U+2060, invisible) keeps it with its number
    return _NEG.sub("-\u2060", text)


@functools.lru_cache(maxsize=2)
def _metrics(bold: bool) -> Any:
    """DejaVu Serif (matplotlib ships it; LibreOffice draws Times New Roman with it where Times is
    not installed, and it is wider than Times, so widths measured with it fit either)."""
    from pathlib import Path

    import matplotlib
    from matplotlib.ft2font import FT2Font

    name = "DejaVuSerif-Bold.ttf" if bold else "DejaVuSerif.ttf"
    font = FT2Font(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name))
    font.set_size(100, 72)
    return font


@functools.lru_cache(maxsize=4096)
def _char_em(c: str, bold: bool = False) -> float:
    """Advance of one character in em: DejaVu Serif's, 1 em for CJK, 0.6 em for a glyph it lacks."""
    if unicodedata.east_asian_width(c) in ("W", "F"):
        return 1.0
    font = _metrics(bold)
    if not font.get_char_index(ord(c)):
        return 0.6
    glyph = font.load_char(ord(c))
    return glyph.linearHoriAdvance / 65536 / 100


def text_mm(text: str, pt: float, bold: bool = False) -> float:
    """Width of ``text`` set at ``pt`` points, in millimetres (DejaVu Serif metrics)."""
    return _text_em(text, bold) * pt * 25.4 / 72


@functools.lru_cache(maxsize=16384)
def _text_em(text: str, bold: bool) -> float:
    """Width of ``text`` in em (a table's column widths are measured again at each smaller size)."""
    return sum(_char_em(c, bold) for c in text)


#: a run of Chinese up to this many characters (a term: 正态, 类型，分布, 标度因数) is kept on one
#: line; a longer run may break, but a column holding one is at least CJK_CHUNK characters wide
CJK_WORD, CJK_CHUNK = 6, 4


def _words(text: str) -> list[str]:
    """The pieces a line may not break inside (for column widths): split at ordinary spaces, line
    breaks, before a full-width ``（`` and after ``）`` (a no-break space joins).  Chinese may
    break between any two characters, but a column one character wide prints a term one
    character per line (类/型/，/分/布): a run of Chinese up to :data:`CJK_WORD` characters
    counts as one piece, a longer run splits after full-width punctuation, and a longer
    stretch still in pieces of :data:`CJK_CHUNK`.

    >>> _words("chamber)（∂B/∂T）and 温箱 x B, 正态 类型，分布 标度因数非线性度 低温贮存：施加的贮存温度")
    ['chamber)', '（∂B/∂T）', 'and', '温箱', 'x', 'B,', '正态', '类型，分布', '标度因数', '非线性度', '低温贮存：', '施加的贮', '存温度']
    """
    out: list[str] = []

    def run(r: str) -> None:
        if len(r) <= CJK_WORD:
            out.append(r)
            return
        for seg in re.findall(r"[^，。；：、！？]*[，。；：、！？]*", r):
            if len(seg) <= CJK_WORD:
                out.append(seg) if seg else None
            else:
                out.extend(seg[i:i + CJK_CHUNK] for i in range(0, len(seg), CJK_CHUNK))

    for part in re.split(r"[ \n\t]+", text):
        buf, cjk = "", ""
        for c in part:
            if c == "（":  # a line may break before a full-width opening parenthesis ...
                if buf:
                    out.append(buf)
                if cjk:
                    run(cjk)
                buf, cjk = c, ""
            elif c == "）":  # ... and after a closing one
                if cjk:
                    run(cjk + c)
                    cjk = ""
                else:
                    out.append(buf + c)
                    buf = ""
            elif unicodedata.east_asian_width(c) in ("W", "F"):
                if buf and buf != "（":
                    out.append(buf)
                    buf = ""
                cjk += buf + c
                buf = ""
            else:
                if cjk:
                    run(cjk)
                    cjk = ""
                buf += c
        if cjk:
            run(cjk)
        if buf:
            out.append(buf)
    return out


@functools.lru_cache(maxsize=8192)
def _words_of(text: str) -> tuple[str, ...]:
    """:func:`_words` of a cell, kept (a column's cells are split again at each smaller size)."""
    return tuple(_words(text))


_ZH_EN = re.compile(r"(?<=[\u3400-\u9fff）])[ \u00a0](?=[A-Za-zΑ-Ωα-ωνΔ(])")


def _two_lines(header: str) -> str:
    """A bilingual header cell (``扩展不确定度 Expanded uncertainty``) as two lines, Chinese above
    English, so a narrow column does not wrap it mid-phrase.

    >>> _two_lines("扩展不确定度 Expanded uncertainty").split("\\n"), _two_lines("Source")
    (['扩展不确定度', 'Expanded uncertainty'], 'Source')
    """
    return _ZH_EN.sub("\n", header, count=1)


def column_widths(columns: Sequence[Sequence[str]], total_mm: float, pt: float,
                  bold_first: bool = True, bold_column: bool = False,
                  prefer: int | None = None, prefer_share: float = 0.6, squeeze: bool = False) -> list[float] | None:
    """Column widths (mm) summing to ``total_mm`` for cells ``columns[j][i]`` at ``pt`` points,
    or None when the longest unbreakable words alone do not fit.

    Each column gets at least its longest word plus the cell margins; what is left is shared in
    proportion to how much each column's longest cell still lacks, so short columns stay narrow
    and text columns take the room."""
    pad = 2 * CELL_MARGIN_MM + 0.8
    mins, wants = [], []
    for j, col in enumerate(columns):
        bold = [bold_first and i == 0 or bold_column and j == 0 for i in range(len(col))]
        mins.append(max((text_mm(w, pt, b) for cell, b in zip(col, bold) for w in _words_of(cell)), default=0.0)
                    * 1.03 + pad)
        wants.append(max((text_mm(cell, pt, b) for cell, b in zip(col, bold)), default=0.0) * 1.03 + pad)
    if sum(mins) > total_mm:
        # the longest words alone do not fit: None, or (squeeze) widths in proportion to them,
        # so the columns whose words are longest stay widest (a word may then break)
        return [m * total_mm / sum(mins) for m in mins] if squeeze else None
    wants = [max(w, m) for w, m in zip(wants, mins)]
    if sum(wants) <= total_mm:
        spare = total_mm - sum(wants)
        return [w + spare * w / sum(wants) for w in wants]
    room = total_mm - sum(mins)
    lack = [w - m for w, m in zip(wants, mins)]
    # water-filling: columns that lack little get all they lack, the others share the rest;
    # a preferred column (the text of a table, e.g. a budget's sources) first takes up to
    # ``prefer_share`` (60 %) of the room
    widths = list(mins)
    if prefer is not None and lack[prefer] > 0:
        take = min(lack[prefer], room * prefer_share)
        widths[prefer] += take
        room -= take
        lack[prefer] -= take
    open_ = [j for j in range(len(lack)) if lack[j] > 0]
    while open_ and room > 1e-6:
        share = room / len(open_)
        done = [j for j in open_ if lack[j] <= share]
        if not done:
            for j in open_:
                widths[j] += share
            room = 0
            break
        for j in done:
            widths[j] += lack[j]
            room -= lack[j]
            open_.remove(j)
    return widths


# ----------------------------------------------------------------------------------------
# The builder
# ----------------------------------------------------------------------------------------

_TRPR_ORDER = ("w:cnfStyle", "w:divId", "w:gridBefore", "w:gridAfter", "w:wBefore", "w:wAfter",
               "w:cantSplit", "w:trHeight", "w:tblHeader", "w:tblCellSpacing", "w:jc", "w:hidden")
_TBLPR_ORDER = ("w:tblStyle", "w:tblpPr", "w:tblOverlap", "w:bidiVisual", "w:tblStyleRowBandSize",
                "w:tblStyleColBandSize", "w:tblW", "w:jc", "w:tblCellSpacing", "w:tblInd", "w:tblBorders",
                "w:shd", "w:tblLayout", "w:tblCellMar", "w:tblLook")
_TCPR_ORDER = ("w:cnfStyle", "w:tcW", "w:gridSpan", "w:hMerge", "w:vMerge", "w:tcBorders",
               "w:shd", "w:noWrap", "w:tcMar", "w:textDirection", "w:tcFitText", "w:vAlign")


def _el(tag: str, **attrs: str):
    from docx.oxml import OxmlElement
    from docx.oxml.ns import qn

    el = OxmlElement(tag)
    for k, v in attrs.items():
        el.set(qn(f"w:{k}"), v)
    return el


def _insert_ordered(parent, child, order: tuple[str, ...]) -> None:
    from docx.oxml.ns import qn

    tags = [qn(t) for t in order]
    later = set(tags[tags.index(child.tag) + 1:])
    for existing in parent:
        if existing.tag == child.tag:
            parent.replace(existing, child)
            return
    for existing in parent:
        if existing.tag in later:
            existing.addprevious(child)
            return
    parent.append(child)


def _twips(mm: float) -> int:
    return int(round(mm / 25.4 * 1440))


# Runs and table rows are written as lxml elements directly (one SubElement call per element),
# not through python-docx's per-run and per-cell proxies, which parse a snippet of XML for every
# element they add and search the children for its place: a GB/T --all report has ~5 000 cells,
# and building them the python-docx way took most of the time of writing the report.  The XML is
# the same element for element (tests/test_document_speed.py builds both ways and compares).
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

    for chunk in _RUN_BREAKS.split(text) if ("\t" in text or "\r" in text or "\n" in text) else (text,):
        if chunk == "\t":
            SubElement(r, _W + "tab")
        elif chunk in ("\r", "\n"):
            SubElement(r, _W + "br")
        elif chunk:
            t = SubElement(r, _W + "t")
            t.text = chunk
            if len(chunk.strip()) < len(chunk):
                t.set(_XML_SPACE, "preserve")


def append_runs(p, text: str, *, bold: bool = False, size: float | None = None, italic: bool = False,
                color: str | None = None) -> None:
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

    def __init__(self, *, number: str, title: str, tr: "Translator", simulated: bool = False,
                 footer: str = ""):
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
                fonts = _el("w:rFonts")
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
        fld = _el("w:fldSimple", instr=f" {instr} \\* MERGEFORMAT ")
        r = _el("w:r")
        rpr = _el("w:rPr")
        rpr.append(_el("w:sz", val=str(half_points)))
        rpr.append(_el("w:szCs", val=str(half_points)))
        r.append(rpr)
        t = _el("w:t")
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
        append_runs(paragraph._p, glue(self.tr.text(text)), bold=bold, size=size, italic=italic, color=color)

    def heading(self, text: str, level: int = 1):
        p = self.doc.add_heading(level=level)
        self.runs(p, text)
        p.paragraph_format.keep_with_next = True
        return p

    #: the lab's logo (image bytes, from the lab profile), drawn above the title of page 1
    logo: bytes | None = None
    LOGO_HEIGHT_MM = 14.0

    def title_block(self, title: str, subtitle: str = "") -> None:
        """The title (and subtitle) of page 1, under the lab's logo when the profile gives one."""
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

    def para(self, text: str, *, bold: bool = False, size: float | None = None, keep_next: bool = False,
             italic: bool = False, color: str | None = None, box: bool = False):
        p = self.doc.add_paragraph()
        self.runs(p, text, bold=bold, size=size, italic=italic, color=color)
        if keep_next:
            p.paragraph_format.keep_with_next = True
        if box:
            ppr = p._p.get_or_add_pPr()
            bdr = _el("w:pBdr")
            for side in ("top", "left", "bottom", "right"):
                bdr.append(_el(f"w:{side}", val="single", sz="8", space="4", color="B01C1C"))
            ppr.insert(0, bdr)
        return p

    def bullets(self, lines: Iterable[str], *, size: float | None = None) -> None:
        for line in lines:
            p = self.para("• " + self.tr.text(line), size=size)
            p.paragraph_format.left_indent = self._pt(10)
            p.paragraph_format.first_line_indent = self._pt(-7)

    def page_break(self) -> None:
        from docx.enum.text import WD_BREAK

        self.doc.add_paragraph().add_run().add_break(WD_BREAK.PAGE)

    # -- tables ----------------------------------------------------------------------------

    def table(self, header: Sequence[str] | None, rows: Sequence[Sequence[str]], *,
              font_pt: float = TABLE_PT, label_column: bool = False, width_mm: float = TEXT_WIDTH_MM,
              shade: Sequence[int] = (), prefer: int | None = None, prefer_share: float = 0.6,
              spans: Sequence[int] = (), bold_rows: Sequence[int] = (), unit_break: Sequence[int] = ()):
        """A bordered table: ``header`` (repeated on every page; None for a label/value table),
        then ``rows`` (each row kept on one page).  ``label_column`` shades and bolds the first
        column (label/value tables).  ``shade`` lists row indexes to shade (summary rows).
        ``spans`` lists rows (indexes into ``rows``, each a one-cell row) whose text spans every
        column (a title or a summary inside a long table; printed bold when it is in ``bold_rows``
        too; never kept with the row below, see the comment in the loop).  In the columns ``unit_break`` a unit may go to
        the next line under its number (``4.946×10⁻⁸`` / ``°/°C/h``; the number stays whole).
        Column widths fit the content (:func:`column_widths`, spanning rows left out); the font
        shrinks (to 6.5 pt) only when the longest words would not fit otherwise."""
        from docx.enum.table import WD_TABLE_ALIGNMENT
        from docx.oxml.ns import qn
        from docx.shared import Mm

        rows = [[glue(self.tr.text(c)) for c in r] for r in rows]
        if unit_break:
            rows = [[_unit_may_wrap(c) if j in unit_break else c for j, c in enumerate(r)] for r in rows]
        head = [_two_lines(glue(self.tr.text(h))) for h in header] if header else None
        spans = set(spans)
        n = len(head) if head else max(len(r) for i, r in enumerate(rows) if i not in spans)
        rows = [list(r) + [""] * (n - len(r)) for r in rows]
        everything = ([head] if head else []) + rows
        first = 1 if head else 0
        cols = [[r[j] for i, r in enumerate(everything) if i - first not in spans] for j in range(n)]
        pt = font_pt
        widths = column_widths(cols, width_mm, pt, bold_first=bool(head), bold_column=label_column,
                               prefer=prefer, prefer_share=prefer_share)
        while widths is None and pt > MIN_TABLE_PT:
            pt = max(MIN_TABLE_PT, pt - 0.5)
            widths = column_widths(cols, width_mm, pt, bold_first=bool(head), bold_column=label_column,
                                   prefer=prefer, prefer_share=prefer_share)
        if widths is None:  # still too wide: in proportion to the longest words (a word may then break)
            widths = column_widths(cols, width_mm, pt, bold_first=bool(head), bold_column=label_column,
                                   squeeze=True)
        # the table without rows (they come below, as XML), in the body as Document.add_table puts it,
        # without its search of the whole body for the section's width: the grid gets its own widths
        t = self.doc._body.add_table(0, n, Mm(width_mm))
        tbl = t._tbl
        tblPr = tbl.tblPr
        tblPr.style = self._table_style_id()
        t.alignment = WD_TABLE_ALIGNMENT.CENTER
        t.autofit = False
        _insert_ordered(tblPr, _el("w:tblW", w=str(sum(_twips(w) for w in widths)), type="dxa"), _TBLPR_ORDER)
        _insert_ordered(tblPr, _el("w:tblLayout", type="fixed"), _TBLPR_ORDER)
        mar = _el("w:tblCellMar")
        for side in ("left", "right"):
            mar.append(_el(f"w:{side}", w=str(_twips(CELL_MARGIN_MM)), type="dxa"))
        _insert_ordered(tblPr, mar, _TBLPR_ORDER)
        grid = tbl.tblGrid
        for gc, w in zip(grid.findall(qn("w:gridCol")), widths):
            gc.set(qn("w:w"), str(_twips(w)))
        twips = [str(_twips(w)) for w in widths]
        for i, values in enumerate(everything):
            is_head = head is not None and i == 0
            if i - first in spans:
                # not kept with the row below: LibreOffice (7.x) lost every later row of a budget whose
                # kept title row fell at a page foot (a 6.2.7.7 report printed 1 of 6 rows and no U);
                # a title alone at a page foot is the lesser harm
                self._table_row(tbl, [values[0]], [str(sum(_twips(w) for w in widths))], span=n,
                                fills=[LABEL_FILL if i - first in shade else None], keep=False,
                                bold=[i - first in bold_rows], pt=pt)
                continue
            row_fill = LABEL_FILL if (i - first) in shade else None
            fills = [HEAD_FILL if is_head else (LABEL_FILL if label_column and j == 0 else row_fill)
                     for j in range(n)]
            # the header row is kept with the next; a body row says it is not, the last says nothing
            keep = is_head if (is_head or i < len(everything) - 1) else None
            self._table_row(tbl, values, twips, header=is_head, fills=fills, keep=keep,
                            bold=[is_head or (label_column and j == 0) for j in range(n)], pt=pt)
        return t

    def _table_style_id(self) -> str:
        """The style id of "Table Grid" (looked up in the styles part once per document)."""
        if self._grid_style is None:
            from docx.enum.style import WD_STYLE_TYPE

            self._grid_style = self.doc.part.get_style_id("Table Grid", WD_STYLE_TYPE.TABLE)
        return self._grid_style

    _grid_style: str | None = None

    def _table_row(self, tbl, values: Sequence[str], twips: Sequence[str], *, span: int = 1,
                   header: bool = False, fills: Sequence[str | None], keep: bool | None,
                   bold: Sequence[bool], pt: float) -> None:
        """Append one ``w:tr`` to ``tbl``: never split across pages, repeated on each page when it is
        the ``header``; per cell its width (twips), fill, and one paragraph with no space after, kept
        with the next row or not (``keep``; None says nothing), its text through :meth:`runs`.  With
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
                SubElement(tcPr, _W + "shd", {_W + "val": "clear", _W + "color": "auto", _W + "fill": fill})
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
        self.doc.save(str(path))


def fit_check(widths: Sequence[float], total: float = TEXT_WIDTH_MM) -> bool:
    return math.isclose(sum(widths), total, abs_tol=0.5)


# ----------------------------------------------------------------------------------------
# Sections every document may use (a layout picks them and adds its appendix's own)
# ----------------------------------------------------------------------------------------

def not_reportable(tr, reason: Any) -> str:
    """"not reportable: reason" in the document's language(s).  A reason made as a message
    (:class:`metro.core.base.locale.Text`) is written in each language; a plain one (data, in one
    language) is printed once, not once per language."""
    from ..base.locale import Text

    if tr.lang != "zh+en" or (isinstance(reason, Text) and tr.render(reason, "zh") != tr.render(reason, "en")):
        return tr("not reportable: {reason}", reason=reason or DASH)
    head = tr("not reportable: {reason}", reason="").rstrip()
    return f"{head}{'' if head.endswith('：') else ' '}{reason or DASH}"


def withheld_reasons(doc: DocumentBuilder, withheld: Sequence[tuple[str, Any]], size: float = 8.5) -> None:
    """Why the results of a table or matrix whose cells say "not reportable" are withheld, after it:
    ``withheld`` = (symbol, reason).  A reason, or a part of one (a "; " join: what a drifting gyro
    does, what to do), that several share is stated once naming them; the parts only one result
    has, on one line (:func:`metro.core.documents.notes.group_notes`)."""
    from .notes import group_notes

    tr = doc.tr
    for where, reason in group_notes([("", sym, r) for sym, r in withheld], key=tr.text):
        doc.para(f"{where}: {not_reportable(tr, reason)}" if where else not_reportable(tr, reason), size=size)


def status_text(tr, status: Any) -> str:
    """An equipment status on the date of measurement, translated where it is a message."""
    from ..base.locale import Text

    return tr(status) if isinstance(status, Text) or status in _STATUS_MSGS else status


def result_cells(doc: DocumentBuilder, r: dict) -> tuple[str, str]:
    """(value with unit, "U = … (k = …)") of a result row of the report context; a result not
    reportable says so, with its reason, in place of its value; one that bounds the quantity (D.4's
    threshold ≤ H, a megohmmeter over its range) states the bound, with its U and why it is one."""
    from ..model.results import BOUND_SIGNS

    tr = doc.tr
    bound = "" if r.get("reportable", True) else r.get("bound") or ""
    if not r.get("reportable", True) and not bound:
        return not_reportable(tr, r.get("reason") or ""), DASH
    value = r["value_unit"]
    if bound:
        value = tr("{sign} {value} (a bound: {reason})", sign=BOUND_SIGNS[bound], value=value,
                   reason=r.get("reason") or DASH)
    U = r.get("U_unit") or DASH
    if U == DASH:
        return value, tr("not evaluated")
    if U.startswith("u = "):
        return value, U
    if r.get("U") in ("0", "0.0"):  # a count or a value taken as declared: no k to state
        return value, tr("no uncertainty (exact)")
    return value, f"U = {U} (k = {r['k']})"


def result_fields(result: Any) -> dict:
    """A :class:`~metro.core.model.results.Result` as the report context shows it: ``value_unit``,
    ``U_unit`` (``—`` without a budget), ``k``, ``reportable``, ``reason``, ``earth_rate``,
    ``note``, ``quantity``, ``symbol`` … (numbers rounded as :meth:`Result.reported` rounds them)."""
    from .report import _result_row

    return _result_row(result)


_SUBDIGITS = str.maketrans("₀₁₂₃₄₅₆₇₈₉", "0123456789")
_CODE_KEY = re.compile(r"^[a-z][a-z0-9]*(?:_[a-z0-9]+)*$")


def _plain(sym: str) -> str:
    """A symbol as typed in plain text: ``α₀`` and ``α_0`` and ``α_{0}`` → ``α0``."""
    return re.sub(r"[_{}]", "", sym.translate(_SUBDIGITS))


def display_symbol(sym: str) -> str:
    """The symbol a document prints: a code key given as a symbol (``low_temperature``,
    ``duration``: lower-case words of three or more letters) is not a symbol and prints as
    nothing (the quantity's name says it).

    >>> display_symbol("ΔB_V13"), display_symbol("low_temperature"), display_symbol("n_nc"), display_symbol("ARW")
    ('ΔB_V13', '', 'n_nc', 'ARW')
    """
    sym = (sym or "").strip()
    if _CODE_KEY.match(sym) and max(len(p) for p in sym.split("_")) >= 4:
        return ""
    return sym


def quantity_name(r: dict) -> str:
    """A result's name for a document: its quantity name and its symbol once, never its code key.

    A name that already holds the symbol in plain text (``D.45 coefficient α0`` with symbol
    ``α₀``) gets the symbol in its place, with its real subscript, not a second time:

    >>> quantity_name({"quantity": "D.45 coefficient α0", "symbol": "α₀"})
    'D.45 coefficient α₀'
    >>> quantity_name({"quantity": "bias stability", "symbol": "B_s"})
    'bias stability B_s'
    >>> quantity_name({"quantity": "damp heat: duration applied", "symbol": "duration", "key": "dh_duration"})
    'damp heat: duration applied'
    """
    name = (r.get("quantity") or "").strip()
    sym = display_symbol(r.get("symbol") or "")
    if not name:
        return sym or r.get("key", "")
    if not sym:
        return r.get("quantity")  # a Text stays one: the document writes the name in its language
    plain = _plain(sym)
    tokens = name.split(" ")
    for i, tok in enumerate(tokens):
        core = tok.strip(",;:()")
        if core and (core == sym or _plain(core) == plain):
            tokens[i] = tok.replace(core, sym)
            return " ".join(tokens)
    from ..base.locale import join

    return join(" ", [r.get("quantity"), sym])  # each part in the document's language


def quantity_for(ctx: dict, item: str, key: str) -> str:
    """The name and symbol of result ``key`` of ``item`` in the context (the key if not found)."""
    for o in ctx["outcomes"]:
        if o["item"] == item:
            for r in o["results"]:
                if r["key"] == key:
                    return quantity_name(r)
    return key


def identification(doc: DocumentBuilder, ctx: dict, rows: Sequence[tuple[str, str]] = ()) -> None:
    """Laboratory, customer, device, dates, then ``rows`` (the appendix's own)."""
    tr, f, dev = doc.tr, ctx["facts"], ctx["device"]
    pairs = [
        (tr("Report No."), ctx["report_number"]),
        (tr("Laboratory"), or_dash(f["lab"])),
        (tr("Laboratory address"), or_dash(f["lab_address"])),
        (tr("Customer"), or_dash(f["customer"])),
        (tr("Customer address"), or_dash(f["customer_address"])),
        (tr("Device"), f"{tr.text(dev['description'])} ({tr('id')} {dev['id']})"),
        (tr("Date of measurement"), or_dash(f["measured"])),
        (tr("Date received"), or_dash(f["received"])),
        (tr("Date of issue"), or_dash(f["issued"])),
    ]
    doc.kv(pairs + list(rows))


def results_table(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None,
                  verdicts: dict | None = None) -> None:
    """One table of every result: item, quantity, value, U (k) [, verdict]."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    header = [tr("Item"), tr("Quantity"), tr("Result"), tr("Expanded uncertainty")]
    if verdicts is not None:
        header.append(tr("Verdict"))
    rows = []
    for o in outcomes:
        for r in o["results"]:
            v, U = result_cells(doc, r)
            row = [o["item"], quantity_name(r), v, U]
            if verdicts is not None:
                row.append(verdicts.get((o["item"], r["key"]), DASH))
            rows.append(row)
    doc.table(header, rows, prefer=1, prefer_share=0.8)


def environment_table(doc: DocumentBuilder, ctx: dict) -> None:
    tr = doc.tr
    rows = [(tr(n["name"].capitalize()) if n["name"].islower() else n["name"], n["value"])
            for n in ctx["environment"]]
    if rows:
        doc.kv(rows)
    else:
        doc.para(tr("not recorded"))


_STATUS_MSGS = ("no calibration data given", "no due date stated")

#: canonical equipment roles (metro.core.base.vocabulary) as a document names them (catalog ids)
ROLE_LABELS = {
    "rate_table": "rate table", "position_table": "position table", "tilt_table": "tilt table",
    "turntable": "turntable", "platform": "stable platform", "counter": "counter", "dmm": "digital multimeter",
    "acquisition": "data acquisition", "timer": "timer", "chamber": "temperature chamber",
    "field_generator": "magnetic field generator", "fixture": "fixture", "vibration_table": "vibration table",
    "angular_vibration_table": "angular vibration table", "shock_table": "shock table", "voltmeter": "voltmeter",
    "ammeter": "ammeter", "calliper": "callipers", "balance": "balance", "megohmmeter": "megohmmeter",
}


def role_label(tr, role: str) -> str:
    """An equipment role as words in the document's language(s) (``rate_table`` → ``速率转台 rate
    table``), never the code key; a role metro does not know prints with spaces for underscores."""
    role = (role or "").strip()
    if not role or role == DASH:
        return DASH
    label = ROLE_LABELS.get(role)
    return tr(label) if label else role.replace("_", " ")


def equipment_table(doc: DocumentBuilder, ctx: dict) -> None:
    """The measurement standards used, their certificates, U with unit and status on the day
    of measurement."""
    tr = doc.tr
    rows = [[f"{tr.text(e['description'])} ({e['id']})", role_label(tr, e["role"]), e["certificate"],
             e["U"] + (f" ({tr('relative')})" if e.get("U_relative") else ""), e["due"],
             status_text(tr, e["status"])] for e in ctx["equipment"]]
    if not rows:
        doc.para(tr("No equipment recorded."))
        return
    doc.table([tr("Equipment"), tr("Role"), tr("Certificate"), tr("Uncertainty"), tr("Due"),
               tr("Status on the date of measurement")], rows)
    for w in ctx["equipment_warnings"]:
        doc.para(w, color="B01C1C")


def notes_section(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None,
                  include_warnings: bool = True) -> None:
    """Result notes, earth-rate statements and warnings, each text once.

    Each note or warning text is one line naming the results and items it applies to
    (:func:`metro.core.documents.notes.group_notes`: ``K_gxx, K_gyy (7.2.1): …``, ``7.2.1, 7.2.2, 7.2.3: …``),
    in the order the texts first appear; a part several results share (of a note joined with
    ``"; "``) is its own line, and a sentence that differs between results only in its indices is
    stated once in index form (``g_ij``).  The earth-rate statement is one line per kind naming
    the items it applies to."""
    from .notes import group_notes

    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    earth: dict[str, list[str]] = {}
    entries: list[tuple[str, str, Any]] = []
    for o in outcomes:
        for r in o["results"]:
            sym = display_symbol(r.get("symbol") or "") or r.get("quantity") or ""
            if r.get("note"):
                entries.append((o["item"], tr.text(sym) if sym else "", r["note"]))
            er = r.get("earth_rate")
            if er:
                earth.setdefault(er, []).append(o["item"])
        for w in (o["warnings"] if include_warnings else ()):
            entries.append((o["item"], "", w))
    lines = [f"{where}: {tr.text(text)}" for where, text in group_notes(entries, key=tr.text)]
    for how, items in earth.items():
        lines.append(f"{tr('Earth rate: {how}', how=tr.msg(how))}: {', '.join(dict.fromkeys(items))}")
    if lines:
        doc.bullets(lines, size=8)
    else:
        doc.para(tr("none"))


def signatory_rows(facts: Mapping[str, Any], labels: Sequence[str]) -> list[tuple[str, str, str]]:
    """(role, name, title) of the three signatories in a context's ``facts``: who performed the
    measurement (``operator``), who checked it and who approved (issued) the document, each with
    the title the campaign or the lab profile gives (``operator_title``, ``checker_title``,
    ``approver_title``; a context kept by the register before titles were kept has none)."""
    keys = (("operator", "operator_title"), ("checker", "checker_title"), ("approver", "approver_title"))
    return [(label, str(facts.get(name) or ""), str(facts.get(title) or ""))
            for label, (name, title) in zip(labels, keys)]


def signatures(doc: DocumentBuilder, roles: Sequence[tuple[str, ...]], *, titled: bool | None = None) -> None:
    """Signature rows: (role, name) or (role, name, title — 职务); each row is tall enough to sign.
    The title column is there when a row has a title, or always with ``titled=True`` (a
    certificate's clause 8 n) asks for the issuer's title); a missing title prints "—"."""
    from docx.shared import Mm

    tr = doc.tr
    if titled is None:
        titled = any(len(r) > 2 and r[2] for r in roles)
    header = [tr("Role"), tr("Name")] + ([tr("Title")] if titled else []) + [tr("Signature"), tr("Date")]
    rows = [[r[0], or_dash(r[1])] + ([or_dash(r[2] if len(r) > 2 else "")] if titled else [])
            + ["\u2003" * 12, "\u2003" * 6] for r in roles]
    t = doc.table(header, rows, font_pt=9)
    for row in t.rows[1:]:
        row.height = Mm(11)
    for row in t.rows[:-1]:  # the table on one page (Word and LibreOffice keep a row with the next)
        for cell in row.cells:
            for p in cell.paragraphs:
                p.paragraph_format.keep_with_next = True


def budgets_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    """Every uncertainty budget, in one table whose header (source, symbol, type and
    distribution, value, divisor, cᵢ, uᵢ(y), νᵢ) repeats on each page: per budget a title row
    (item, quantity, the unit of its uᵢ(y)), its rows, and a row with u_c, ν_eff, k and U.  A
    budget whose every contribution is zero (an exact count, a value taken as declared) is not a
    table: such budgets are listed first, those sharing one reason under it once.  In zh+en a
    row's distribution is printed in Chinese (the names in both languages once, above the table)."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    exact: dict[tuple, tuple[list, list[str]]] = {}
    tables: list[tuple[list, list[int], list[int]]] = []
    dists: dict[str, None] = {}
    # a row's note that several rows share is printed once, numbered, above the tables
    seen: dict[str, int] = {}
    for o in outcomes:
        for b in o["budgets"]:
            for x in b["rows"]:
                if x.get("note") and len(str(x["note"])) > 40:
                    seen[str(x["note"])] = seen.get(str(x["note"]), 0) + 1
    numbered = {n: None for n, c in seen.items() if c > 1}
    notes: dict[str, tuple[int, Any]] = {}

    def source_of(x: dict) -> Any:
        if x.get("note") and str(x["note"]) in numbered:
            k = notes.setdefault(str(x["note"]), (len(notes) + 1, x["note"]))[0]
            return f"{tr.text(x['source_only'])} [{k}]"
        return x["source"]

    for o in outcomes:
        rows: list[list[str]] = []
        spans: list[int] = []
        titles: list[int] = []
        for b in o["budgets"]:
            name = f"{o['item']} {tr.text(b['title'])}"
            if all(x["contribution"] in ("0", "0.0") for x in b["rows"]):
                key = tuple(str(_generic(x["source"])) for x in b["rows"])
                exact.setdefault(key, ([x["source"] for x in b["rows"]], []))[1].append(name)
                continue
            unit = "" if b["unit"] == "1" else b["unit"]
            spans.append(len(rows))
            titles.append(len(rows))
            rows.append([f"{o['item']} — {tr.text(b['title'])}" + (f"   [u_i(y): {unit}]" if unit else "")])
            for x in b["rows"]:
                dists[x["distribution"]] = None
                dist = tr.zh(x["distribution"]) if tr.lang == "zh+en" else tr(x["distribution"])
                rows.append([source_of(x), x["symbol"], f"{x['type']}, {dist}", x["value"], x["divisor"],
                             x["sensitivity"], x["contribution"], x["dof"]])
            unit = f" {unit}" if unit else ""
            spans.append(len(rows))
            rows.append([f"u_c = {b['u_c']}{unit}, ν_eff = {b['nu_eff']}, k = {b['k']}, U = {b['U']}{unit}"
                         + (f". {tr.text(b['note'])}" if b.get("note") else "")])
        if rows:
            tables.append((rows, spans, titles))
    if exact:
        doc.para(f"{tr('no uncertainty (exact)')}:", size=7.5, keep_next=True)
        lines = []
        for sources, names in exact.values():
            why = "; ".join(tr.text(_generic(x) if len(names) > 1 else x) for x in sources)
            lines.append(f"{why}: {'; '.join(names)}")
        doc.bullets(lines, size=7.5)
    if notes:
        doc.para(f"{tr('Notes to several rows')}:", size=7.5, keep_next=True)
        for k, note in notes.values():
            p = doc.para(f"[{k}] {tr.text(note)}", size=7.5)
            p.paragraph_format.space_after = doc._pt(0)
    if tables and tr.lang == "zh+en":
        doc.para(f"{tr('Distribution')}: " + ", ".join(tr(d) for d in dists), size=7.5, keep_next=True)
    for i, (rows, spans, titles) in enumerate(tables):  # one table per item: its widths fit its own budgets
        if i:  # two tables with nothing between them are one table to LibreOffice and Word
            doc.para("", size=2)
        doc.table([tr("Source"), tr("Symbol"), _type_distribution_header(tr), tr("Value"), tr("Divisor"),
                   "c_i", "u_i(y)", "ν_i"], rows, font_pt=7, prefer=0, prefer_share=1.0, spans=spans,
                  bold_rows=titles, shade=titles, unit_break=(3, 5, 6))


def _generic(text: Any) -> Any:
    """A message with its data fields (a quantity's name, a count) left out as "…", to say once
    what several exact budgets share ("…: no uncertainty declared by the test lab"); a field with
    a number format keeps the message whole."""
    import string

    from ..base.locale import Text

    if not isinstance(text, Text):
        return text
    if text.msgid is None:
        return Text(None, sep=text.sep, parts=tuple(_generic(p) for p in text.parts))
    formatted = {f for _, f, spec, conv in string.Formatter().parse(text.msgid) if f and (spec or conv)}
    fields = {}
    for k, v in text.fields.items():
        if isinstance(v, Text):
            fields[k] = _generic(v)
        elif k in formatted:
            return text
        else:
            fields[k] = "…"
    return Text(text.msgid, fields)


def _type_distribution_header(tr) -> str:
    """One header for the type and distribution columns merged: ``类型，分布`` above ``Type, distribution``."""
    if tr.lang == "zh+en":
        return f"{tr.zh('Type')}，{tr.zh('Distribution')}\nType, distribution"
    if tr.lang == "zh":
        return f"{tr.zh('Type')}，{tr.zh('Distribution')}"
    return "Type, distribution"


def tables_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    for o in outcomes:
        for t in o["tables"]:
            doc.para(f"{o['item']} — {doc.tr.text(t['title'])}", bold=True, keep_next=True)
            doc.table(t["header"], t["rows"], font_pt=7.5)


def figures_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    for o in outcomes:
        for p in o["plots"]:
            if p.get("image"):
                doc.figure(p["image"], f"{tr('Figure')} {p['number']}: {tr.text(p['caption'])}",
                           width_mm=FIGURE_WIDTH_MM)


#: beyond this many data files (segments), the document prints the digest of their sorted list only
MAX_LISTED_DIGESTS = 240


def provenance_annex(doc: DocumentBuilder, ctx: dict) -> None:
    """Software and plugin versions, then the data's SHA-256 in one compact table (full digests
    for up to 24 files; beyond that the first 16 hex digits, three to a row; one SHA-256 over the
    sorted list, which alone is printed beyond :data:`MAX_LISTED_DIGESTS` files — the run record's
    --json output lists every digest in full)."""
    import hashlib

    tr = doc.tr
    prov = ctx["provenance"]
    sw = ", ".join(f"{s['name']} {s['version']}" for s in prov["software"])
    pl = ", ".join(f"{p['name']} {p['version']}" for p in prov["plugins"])
    doc.kv([(tr("Software"), sw or DASH), (tr("Plugins"), pl or DASH),
            (tr("Data source"), or_dash(prov["source"])), (tr("Campaign"), ctx["campaign"]["id"]),
            (tr("Processed"), ctx["facts"]["processed"])], font_pt=8)
    if ctx["truth"]:
        doc.para(tr("Declared truth of the simulated device"), bold=True, keep_next=True)
        doc.kv([(t["name"], t["value"]) for t in ctx["truth"]], font_pt=8)
    files = [f for f in prov["data_files"] if f.get("sha256")]
    if not files:
        return
    lines = sorted(f"{f['sha256']}  {f['file']}\n" for f in files)
    digest = hashlib.sha256("".join(lines).encode("utf-8")).hexdigest()
    doc.para(f"{tr('SHA-256 of the sorted list of data digests')}: {digest}", size=8, keep_next=True)
    # a file or segment name is an identifier: in one language (English in zh+en), not twice
    one = "zh" if tr.lang == "zh" else "en"
    if len(files) <= 24:
        names = [_short_name(tr.render(f["file"], one)) for f in files]
        prefix, suffix = _common_affixes(names)
        if prefix or suffix:
            doc.para(f"{tr('Data')}: {(prefix + '…' + suffix).strip()}", size=7.5, keep_next=True)
        doc.table([tr("Data"), "SHA-256"], [[n[len(prefix):len(n) - len(suffix)].strip(), f["sha256"]]
                                            for n, f in zip(names, files)], font_pt=7)
        return
    # many files (simulated segments): the name without what they all share, the first 16 hex
    # digits, three to a row (one line each at 6 pt); the shared words said once above the table
    if len(files) > MAX_LISTED_DIGESTS:
        # hundreds of segments (a JJF 2014 --all run has ~700): five pages of hex help no reader;
        # the digest over the sorted list above fixes them all, and the record lists each
        doc.para(tr("{n} data files or segments: the SHA-256 above is over the sorted list of their "
                    "digests, which the record of the run lists in full (the register keeps it with the "
                    "report).", n=len(files)), size=7.5)
        return
    names = [_short_name(tr.render(f["file"], one)) for f in files]
    prefix, suffix = _common_affixes(names)
    title = tr("Data (SHA-256, first 16 hex digits)")
    if prefix or suffix:
        title += f"; {tr('Data')}: {(prefix + '…' + suffix).strip()}"
    doc.para(title, size=7.5, keep_next=True, bold=True)
    cells = [f"{n[len(prefix):len(n) - len(suffix)].strip()} {f['sha256'][:16]}" for n, f in zip(names, files)]
    rows = [cells[i:i + 3] for i in range(0, len(cells), 3)]
    doc.table(None, rows, font_pt=6)


def _common_affixes(names: Sequence[str]) -> tuple[str, str]:
    """The word-aligned prefix and suffix every name shares (``segment `` … `` (simulated, in memory)``).

    >>> _common_affixes(["segment a-1 (sim)", "segment b-22 (sim)"])
    ('segment ', ' (sim)')
    """
    import os

    if len(names) < 2:
        return "", ""
    pre = os.path.commonprefix(list(names))
    pre = pre[:pre.rfind(" ") + 1] if " " in pre else ""
    suf = os.path.commonprefix([n[::-1] for n in names])[::-1]
    suf = suf[suf.find(" "):] if " " in suf else ""
    if any(len(n) <= len(pre) + len(suf) for n in names):
        return "", ""
    return pre, suf


def _short_name(name: str) -> str:
    import os

    return os.path.basename(name) if ("/" in name or "\\" in name) else name


def generic_layout(doc: DocumentBuilder, ctx: dict) -> None:
    """The report of a standard without a layout of its own."""
    tr = doc.tr
    doc.title_block(tr("Test report"), ctx["items_text"])
    identification(doc, ctx, [(tr("Standard"), ctx["standards_text"])])
    doc.heading(tr("Results"), 1)
    results_table(doc, ctx)
    doc.heading(tr("Notes"), 2)
    notes_section(doc, ctx)
    doc.heading(tr("Environment"), 2)
    environment_table(doc, ctx)
    doc.heading(tr("Equipment"), 2)
    equipment_table(doc, ctx)
    doc.heading(tr("Conformity"), 2)
    conformity_section(doc, ctx)
    doc.heading(tr("Signatures"), 2)
    f = ctx["facts"]
    signatures(doc, signatory_rows(f, [tr("Tested by"), tr("Checked by"), tr("Approved by")]))
    doc.para(tr("The results relate only to the item tested. This report shall not be reproduced "
                "except in full without the written approval of the laboratory."), size=8.5)
    annexes(doc, ctx)


def conformity_section(doc: DocumentBuilder, ctx: dict) -> None:
    """The decision rule and every verdict with its reason (or: no statement is made)."""
    tr = doc.tr
    a = ctx["conformity"]
    if a is None:
        doc.para(tr("No specification was given: this report makes no statement of conformity."))
        return
    doc.para(f"{tr('Decision rule')}: {tr.text(a['rule_title'])}")
    doc.para(a["statement"], size=8.5)
    doc.para(f"{tr('Overall verdict')}: {tr(_VERDICT.get(a['overall'], a['overall']))}", bold=True)
    doc.table([tr("Item"), tr("Quantity"), tr("Limit"), tr("Source"), tr("Verdict"), tr("Reason")],
              [[v["item"], quantity_for(ctx, v["item"], v["key"]), v["limit"], v["source"],
                tr(_VERDICT.get(v["status"], v["status"])),
                v["reason"]] for v in a["verdicts"]], font_pt=8)
    if a["not_assessed"]:
        doc.para(f"{tr('Not assessed (item not performed)')}: " + "; ".join(tr.text(x) for x in a["not_assessed"]),
                 size=8.5)


_VERDICT = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate"}


def annexes(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None,
            first: str = "A") -> None:
    """Budgets, data tables, figures and provenance as annexes A, B, C, D."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    letter = ord(first)
    parts = [("Uncertainty budgets", budgets_annex, any(o["budgets"] for o in outcomes)),
             ("Data tables", tables_annex, any(o["tables"] for o in outcomes)),
             ("Figures", figures_annex, any(o["plots"] for o in outcomes)),
             ("Provenance", lambda d, c, _o: provenance_annex(d, c), True)]
    for title, fn, present in parts:
        if not present:
            continue
        doc.heading(f"{tr('Annex')} {chr(letter)} {tr(title)}", 1)
        fn(doc, ctx, outcomes)
        letter += 1


# ----------------------------------------------------------------------------------------
# PDF through LibreOffice
# ----------------------------------------------------------------------------------------


def soffice_path() -> str:
    """The LibreOffice program (``soffice`` or ``libreoffice`` on PATH, or ``$METRO_SOFFICE``);
    a clear error when there is none."""
    import os
    import shutil

    from ..base.errors import MetroError

    given = os.environ.get("METRO_SOFFICE")
    for cand in ([given] if given else []) + ["soffice", "libreoffice"]:
        found = shutil.which(cand)
        if found:
            return found
    raise MetroError("a PDF needs LibreOffice, and neither soffice nor libreoffice is on PATH",
                     hint="install LibreOffice (e.g. apt-get install libreoffice-writer-nogui), set "
                          "METRO_SOFFICE to its soffice, or write the .docx and convert it yourself")


def to_pdf(docx_path, pdf_path, *, timeout: float = 300.0) -> None:
    """Convert ``docx_path`` to PDF/A-2b at ``pdf_path`` with LibreOffice headless.

    The conversion runs in a temporary directory with its own LibreOffice user profile
    (``-env:UserInstallation``), so several conversions at once do not collide."""
    import shutil
    import subprocess
    import tempfile
    from pathlib import Path

    from ..base.errors import MetroError

    exe = soffice_path()
    with tempfile.TemporaryDirectory(prefix="metro-pdf-") as tmp:
        tmp = Path(tmp)
        src = tmp / "document.docx"
        shutil.copyfile(docx_path, src)
        profile = (tmp / "profile").as_uri()
        # SelectPdfVersion 2 = PDF/A-2b (LibreOffice ≥ 7.4 reads the filter options as JSON)
        target = 'pdf:writer_pdf_Export:{"SelectPdfVersion":{"type":"long","value":"2"}}'
        cmd = [exe, f"-env:UserInstallation={profile}", "--headless", "--norestore", "--convert-to", target,
               "--outdir", str(tmp / "out"), str(src)]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired as exc:
            raise MetroError(f"LibreOffice did not convert {docx_path} to PDF within {timeout:g} s") from exc
        out = tmp / "out" / "document.pdf"
        if proc.returncode != 0 or not out.is_file():
            raise MetroError(f"LibreOffice could not convert {docx_path} to PDF (exit {proc.returncode})",
                             hint=(proc.stderr or proc.stdout).strip()[-300:] or None)
        shutil.copyfile(out, pdf_path)


def layout_digest(layout: Any) -> str:
    """A SHA-256 that changes when a layout's document would: over the source of the layout's
    module, this module and the message catalog (the register keeps it as the report's template
    identity, as it keeps a docxtpl template's file hash)."""
    import hashlib
    import importlib
    import inspect
    from importlib import resources
    from pathlib import Path

    if layout is None:
        module = __name__
    elif callable(layout):
        module = layout.__module__
    else:
        module = str(layout).partition(":")[0]
    h = hashlib.sha256()
    for mod in dict.fromkeys((module, __name__)):
        h.update(Path(inspect.getfile(importlib.import_module(mod))).read_bytes())
    h.update((resources.files("metro.core.base.locale") / "zh" / "LC_MESSAGES" / "metro.po").read_bytes())
    return h.hexdigest()

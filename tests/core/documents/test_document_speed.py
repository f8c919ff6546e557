"""The fast document writing (metro.core.documents.document builds table rows and runs as lxml
elements) writes the same XML as python-docx's own per-run and per-cell calls did: the reference
path below is the former implementation, kept here to hold the fast one to it. Not timed (the times
are in benchmarks/bench_report_write.py and docs/performance.md)."""

from __future__ import annotations

import io
import zipfile

import pytest
from lxml import etree

from metro.core.documents import builder as B, document as D, text as T
from metro.core.base.locale import translator


# ------------------------------------------------------------------------------------------------
# the reference: python-docx proxies, one call per run, per cell property (the code before the
# change)
# ------------------------------------------------------------------------------------------------


def _reference_runs(doc, paragraph, text, *, bold=False, size=None, italic=False, color=None):
    from docx.shared import Pt, RGBColor

    text = T.glue(doc.tr.text(text))
    lines = text.split("\n")
    for n, line in enumerate(lines):
        for piece, sub in T.subscript_runs(line):
            r = paragraph.add_run(piece)
            if bold:
                r.bold = True
            if italic:
                r.italic = True
            if size:
                r.font.size = Pt(size)
            if sub:
                r.font.subscript = True
            if color:
                r.font.color.rgb = RGBColor.from_string(color)
        if n < len(lines) - 1:
            paragraph.add_run().add_break()


def _reference_table(doc, header, rows, *, font_pt=T.TABLE_PT, label_column=False, shade=(),
                     spans=(),
                     bold_rows=(), unit_break=()):
    from docx.enum.table import WD_TABLE_ALIGNMENT
    from docx.oxml.ns import qn
    from docx.shared import Pt

    E, ins = B.oxml_element, B.insert_ordered
    rows = [[T.glue(doc.tr.text(c)) for c in r] for r in rows]
    if unit_break:
        rows = [[T.unit_may_wrap(c) if j in unit_break else c for j, c in enumerate(r)] for r
                in rows]
    head = [T.two_lines(T.glue(doc.tr.text(h))) for h in header] if header else None
    spans = set(spans)
    n = len(head) if head else max(len(r) for i, r in enumerate(rows) if i not in spans)
    rows = [list(r) + [""] * (n - len(r)) for r in rows]
    everything = ([head] if head else []) + rows
    first = 1 if head else 0
    cols = [[r[j] for i, r in enumerate(everything) if i - first not in spans] for j in range(n)]
    widths = T.column_widths(cols, T.TEXT_WIDTH_MM, font_pt, bold_first=bool(head),
                             bold_column=label_column)
    pt = font_pt
    t = doc.doc.add_table(rows=len(everything), cols=n)
    t.style = "Table Grid"
    t.alignment = WD_TABLE_ALIGNMENT.CENTER
    t.autofit = False
    tblPr = t._tbl.tblPr
    ins(tblPr, E("w:tblW", w=str(sum(B.mm_to_twips(w) for w in widths)), type="dxa"), B.TBLPR_ORDER)
    ins(tblPr, E("w:tblLayout", type="fixed"), B.TBLPR_ORDER)
    mar = E("w:tblCellMar")
    for side in ("left", "right"):
        mar.append(E(f"w:{side}", w=str(B.mm_to_twips(T.CELL_MARGIN_MM)), type="dxa"))
    ins(tblPr, mar, B.TBLPR_ORDER)
    for gc, w in zip(t._tbl.tblGrid.findall(qn("w:gridCol")), widths):
        gc.set(qn("w:w"), str(B.mm_to_twips(w)))
    for i, (row, values) in enumerate(zip(t.rows, everything)):
        trPr = row._tr.get_or_add_trPr()
        ins(trPr, E("w:cantSplit"), B.TRPR_ORDER)
        is_head = head is not None and i == 0
        if is_head:
            ins(trPr, E("w:tblHeader"), B.TRPR_ORDER)
        if i - first in spans:
            cell = row.cells[0].merge(row.cells[n - 1]) if n > 1 else row.cells[0]
            tcPr = cell._tc.get_or_add_tcPr()
            ins(
                tcPr,
                E("w:tcW", w=str(sum(B.mm_to_twips(w) for w in widths)), type="dxa"),
                B.TCPR_ORDER,
            )
            if i - first in shade:
                ins(tcPr, E("w:shd", val="clear", color="auto", fill=T.LABEL_FILL), B.TCPR_ORDER)
            p = cell.paragraphs[0]
            p.paragraph_format.space_after = Pt(0)
            p.paragraph_format.keep_with_next = False
            _reference_runs(doc, p, values[0], bold=i - first in bold_rows, size=pt)
            continue
        for j, (cell, value, w) in enumerate(zip(row.cells, values, widths)):
            tcPr = cell._tc.get_or_add_tcPr()
            ins(tcPr, E("w:tcW", w=str(B.mm_to_twips(w)), type="dxa"), B.TCPR_ORDER)
            bold = is_head or (label_column and j == 0)
            fill = T.HEAD_FILL if is_head else (T.LABEL_FILL if (label_column and j == 0) or
                                                (i - (1 if head else 0)) in shade else None)
            if fill:
                ins(tcPr, E("w:shd", val="clear", color="auto", fill=fill), B.TCPR_ORDER)
            p = cell.paragraphs[0]
            p.paragraph_format.space_after = Pt(0)
            if is_head or i < len(everything) - 1:
                p.paragraph_format.keep_with_next = is_head
            _reference_runs(doc, p, value, bold=bold, size=pt)
    return t


# ------------------------------------------------------------------------------------------------


def _builder(lang="zh+en"):
    return D.DocumentBuilder(number="MTR-1", title="Test report", tr=translator(lang),
                             simulated=True, footer="metro")


def _xml(element) -> bytes:
    return etree.tostring(element, encoding="utf-8")


#: a small budget table: a header in both languages, subscripts, a spanning title row (bold,
#: shaded), units that may wrap, a negative number, a summary row, leading/trailing spaces, a tab
#: and a line break
HEADER = ["Source", "Symbol", "Type, distribution", "Value", "Divisor", "c_i", "u_i(y)", "ν_i"]
ROWS = [
    ["D.5.2 — bias stability B_s   [u_i(y): °/h]"],
    ["repeatability of B_s (t = 10 s)", "B_s", "A, normal", "4.946×10⁻⁸ °/°C/h", "1", "1",
     "0.0012 °/h", "9"],
    ["rate table: stated U (k = 2)", "Ω_r", "B, uniform", "-0.5 °/s", "1.732", "2.3 ppm", " 0.29 ",
     "∞"],
    ["a tab\there and a line\nbreak", "K_{upper}", "B, normal", "1 ppm", "2", "1", "0.5", "∞"],
    ["u_c = 0.0012 °/h, ν_eff = 9, k = 2.26, U = 0.0027 °/h"],
]


@pytest.mark.parametrize("lang", ["zh+en", "en", "zh"])
def test_table_rows_are_the_xml_python_docx_wrote(lang):
    fast, ref = _builder(lang), _builder(lang)
    kw = dict(font_pt=7, spans=[0, 4], shade=[0], bold_rows=[0], unit_break=(3, 5, 6))
    t1 = fast.table(HEADER, ROWS, **kw)
    t2 = _reference_table(ref, HEADER, ROWS, **kw)
    assert b"<w:gridSpan" in _xml(t1._tbl) and b"<w:tblHeader/>" in _xml(t1._tbl)
    assert b'xml:space="preserve"' in _xml(t1._tbl) and b"<w:tab/>" in _xml(t1._tbl)
    assert _xml(t1._tbl) == _xml(t2._tbl)


def test_label_value_table_is_the_xml_python_docx_wrote():
    fast, ref = _builder(), _builder()
    pairs = [("Report No.", "MTR-1"), ("Device", "FOG (id G-7)"), ("Date of measurement", "—")]
    t1 = fast.kv(pairs)
    t2 = _reference_table(ref, None, [list(p) for p in pairs], font_pt=9.0, label_column=True)
    assert _xml(t1._tbl) == _xml(t2._tbl)


@pytest.mark.parametrize("kw", [{}, {"bold": True, "size": 8}, {"italic": True, "color": "b01c1c",
                                                                "size": 7.5}])
def test_paragraph_runs_are_the_xml_python_docx_wrote(kw):
    fast, ref = _builder(), _builder()
    text = "K_l = 3 ppm and α_0 = -1.2×10⁻⁷\nsecond line with\ta tab "
    p1 = fast.doc.add_paragraph()
    fast.runs(p1, text, **kw)
    p2 = ref.doc.add_paragraph()
    _reference_runs(ref, p2, text, **kw)
    assert _xml(p1._p) == _xml(p2._p)
    assert b"vertAlign" in _xml(p1._p)


def test_fast_table_still_works_through_python_docx():
    """The rows written as XML are python-docx rows: signatures() sets their height and keeps
    their paragraphs with the next, and the saved document reads back with its text."""
    import docx

    fast = _builder("en")
    D.signatures(fast, [("Tested by", "A. Operator"), ("Approved by", "B. Head", "Head of lab")])
    out = io.BytesIO()
    fast.doc.save(out)
    back = docx.Document(io.BytesIO(out.getvalue()))
    table = back.tables[-1]
    assert [c.text for c in table.rows[1].cells][:3] == ["Tested by", "A. Operator", "—"]
    assert table.rows[2].height is not None
    xml = zipfile.ZipFile(io.BytesIO(out.getvalue())).read("word/document.xml")
    assert xml.count(b"<w:trHeight") == 2


def test_text_that_xml_cannot_hold_is_refused_as_before():
    """A character XML 1.0 forbids (U+FFFE) is refused by lxml, as python-docx refused it."""
    fast = _builder("en")
    with pytest.raises(ValueError, match="XML compatible"):
        fast.table(["Source"], [["bad \ufffe text"]])

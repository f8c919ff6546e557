"""Build the docxtpl report template, ``report.docx``, next to this script: a starting point
for a laboratory's own template (``write_report(…, template=PATH)``, or a plugin's
``add_template(name, PATH)``).  metro's own reports and certificates do not use it: they are
built by :mod:`metro.core.documents.document` with each standard's layout.

Run it after changing the layout (the output is committed)::

    python core/documents/templates/make_templates.py            # writes
    core/documents/templates/report.docx
    python core/documents/templates/make_templates.py OUT.docx   # writes elsewhere

The document is built with python-docx and carries docxtpl (Jinja2) tags that
:func:`metro.core.documents.report.write_report` fills from
:func:`metro.core.documents.context.report_context`:

* ``{{ name }}`` — a text value (always a string prepared by ``report_context``);
* ``{%p if … %}`` / ``{%p for … %}`` … ``{%p endif %}`` / ``{%p endfor %}`` — a paragraph
  holding only the tag, which docxtpl removes: conditional and repeated blocks;
* ``{%tr for r in … %}`` in the row *before* a table's template row and ``{%tr endfor %}``
  in the row after it — one table row per item;
* ``{%tc for … %}`` … ``{%tc endfor %}`` in the cells around a template cell — one column per
  item (the supplementary tables, whose number of columns varies);
* ``{{ p.image }}`` — an ``InlineImage`` (a figure).

The output is byte-for-byte reproducible: fixed document properties, and the zip entries
are rewritten with a fixed time stamp.  Engineers may restyle the template in Word as long
as the tags stay intact; re-running this script overwrites such edits.
"""

from __future__ import annotations

import io
from contextlib import contextmanager
import sys
import zipfile
from pathlib import Path
from typing import Any, Iterator

import docx
from docx.enum.section import WD_ORIENT
from docx.enum.style import WD_STYLE_TYPE
from docx.enum.table import WD_TABLE_ALIGNMENT
from docx.enum.text import WD_ALIGN_PARAGRAPH, WD_TAB_ALIGNMENT
from docx.oxml import OxmlElement
from docx.oxml.ns import qn
from docx.shared import Mm, Pt, RGBColor

from metro.core.documents.builder import (
    TBLPR_ORDER, TCPR_ORDER, TRPR_ORDER, insert_ordered, oxml_element,
)

OUT = Path(__file__).with_name("report.docx")

PAGE_W, PAGE_H = 210, 297  # A4 portrait, mm
MARGIN = 20  # mm
TEXT_W = PAGE_W - 2 * MARGIN  # 170 mm

HEAD_FILL = "D9E2EC"  # table header shading
SUM_FILL = "F2F2F2"  # budget summary rows
BANNER_FILL = "FDE9E7"
BANNER_TEXT = RGBColor(0x9C, 0x1C, 0x1C)
DARK = RGBColor(0x1F, 0x2A, 0x37)

CLOSING = (
    "The results in this report relate only to the item tested, as identified in section 2, "
    "and only to the conditions stated in section 3. This report shall be reproduced only in "
    "full; an extract needs the written approval of the laboratory that issued it."
)

# Element order inside w:pPr, w:tcPr and w:trPr (ECMA-376), for inserting children in place.
_PPR_ORDER = ("w:pStyle", "w:keepNext", "w:keepLines", "w:pageBreakBefore", "w:framePr",
              "w:widowControl", "w:numPr", "w:suppressLineNumbers", "w:pBdr", "w:shd", "w:tabs",
              "w:suppressAutoHyphens", "w:spacing", "w:ind", "w:jc", "w:outlineLvl", "w:rPr")


# --------------------------------------------------------------------------------------
# Low-level helpers
# --------------------------------------------------------------------------------------


def _shade_cell(cell, fill: str) -> None:
    shd = oxml_element("w:shd", val="clear", color="auto", fill=fill)
    insert_ordered(cell._tc.get_or_add_tcPr(), shd, TCPR_ORDER)


def _shade_paragraph(paragraph, fill: str, border: str) -> None:
    ppr = paragraph._p.get_or_add_pPr()
    bdr = oxml_element("w:pBdr")
    for side in ("top", "left", "bottom", "right"):
        bdr.append(oxml_element(f"w:{side}", val="single", sz="8", space="4", color=border))
    insert_ordered(ppr, bdr, _PPR_ORDER)
    insert_ordered(ppr, oxml_element("w:shd", val="clear", color="auto", fill=fill), _PPR_ORDER)


def _bottom_rule(paragraph) -> None:
    ppr = paragraph._p.get_or_add_pPr()
    bdr = oxml_element("w:pBdr")
    bdr.append(oxml_element("w:bottom", val="single", sz="6", space="1", color="808080"))
    insert_ordered(ppr, bdr, _PPR_ORDER)


def _row_flag(row, tag: str) -> None:
    insert_ordered(row._tr.get_or_add_trPr(), oxml_element(tag), TRPR_ORDER)


def _field(paragraph, instr: str, shown: str) -> None:
    """Append a Word field (``PAGE``, ``NUMPAGES``) with ``shown`` as its cached result."""
    fld = oxml_element("w:fldSimple", instr=f" {instr} \\* MERGEFORMAT ")
    run = OxmlElement("w:r")
    text = OxmlElement("w:t")
    text.text = shown
    run.append(text)
    fld.append(run)
    paragraph._p.append(fld)


def _set_text(cell, text: str, *, bold: bool = False, style: str = "Table Text") -> None:
    p = cell.paragraphs[0]
    p.style = style
    run = p.add_run(text)
    run.bold = bold or None


def _fix_widths(table, widths_mm: list[float]) -> None:
    table.autofit = False
    for col, w in zip(table.columns, widths_mm):
        col.width = Mm(w)
    for row in table.rows:
        for cell, w in zip(row.cells, widths_mm):
            cell.width = Mm(w)


def _header_row(table, headers: list[str]) -> None:
    row = table.rows[0]
    _row_flag(row, "w:cantSplit")
    _row_flag(row, "w:tblHeader")  # repeated at the top of every page the table spans
    for cell, text in zip(row.cells, headers):
        _set_text(cell, text, bold=True, style="Table Head")
        _shade_cell(cell, HEAD_FILL)


def _new_table(doc, n_rows: int, widths_mm: list[float]):
    table = doc.add_table(rows=n_rows, cols=len(widths_mm))
    table.style = "Table Grid"
    table.alignment = WD_TABLE_ALIGNMENT.CENTER
    _fix_widths(table, widths_mm)
    return table


def loop_table(doc, headers: list[str], cells: list[str], widths_mm: list[float], loop: str,
               styles: dict[int, str] | None = None):
    """A table: a header row, then one row per item of ``loop`` (``"r in o.results"``);
    ``styles`` gives a paragraph style to some columns of the template row."""
    table = _new_table(doc, 4, widths_mm)
    _header_row(table, headers)
    _set_text(table.rows[1].cells[0], f"{{%tr for {loop} %}}")
    for i, (cell, text) in enumerate(zip(table.rows[2].cells, cells)):
        _set_text(cell, text, style=(styles or {}).get(i, "Table Text"))
    _row_flag(table.rows[2], "w:cantSplit")
    _set_text(table.rows[3].cells[0], "{%tr endfor %}")
    return table


def kv_table(doc, rows: list[tuple[str, str]], widths_mm=(50, TEXT_W - 50),
             loop: tuple[str, str, str] | None = None):
    """A two-column label/value table; ``loop`` = (``"p in device.properties"``, label, value)
    appends one row per item."""
    n = len(rows) + (3 if loop else 0)
    table = _new_table(doc, n, list(widths_mm))
    for row, (label, value) in zip(table.rows, rows):
        _set_text(row.cells[0], label, bold=True)
        _shade_cell(row.cells[0], HEAD_FILL)
        _set_text(row.cells[1], value)
    if loop:
        spec, loop_label, loop_value = loop
        r0, r1, r2 = table.rows[len(rows):]
        _set_text(r0.cells[0], f"{{%tr for {spec} %}}")
        _set_text(r1.cells[0], loop_label, bold=True)
        _shade_cell(r1.cells[0], HEAD_FILL)
        _set_text(r1.cells[1], loop_value)
        _set_text(r2.cells[0], "{%tr endfor %}")
    return table


def column_loop_table(doc, header: str, rows: str):
    """A table whose columns come from data: ``{%tc for %}`` around one template cell.

    docxtpl adds or removes grid columns to match after rendering; the template cells carry
    no fixed width, so Word spreads the table over the text width.
    """
    table = doc.add_table(rows=4, cols=3)
    table.style = "Table Grid"
    table.alignment = WD_TABLE_ALIGNMENT.CENTER
    tbl_pr = table._tbl.tblPr
    for old in tbl_pr.findall(qn("w:tblW")):
        tbl_pr.remove(old)
    insert_ordered(tbl_pr, oxml_element("w:tblW", w="5000", type="pct"), TBLPR_ORDER)
    for col in table.columns:
        col.width = Mm(TEXT_W / 3)
    for row in table.rows:
        for cell in row.cells:
            tcpr = cell._tc.get_or_add_tcPr()
            for w in tcpr.findall(qn("w:tcW")):
                tcpr.remove(w)
            insert_ordered(tcpr, oxml_element("w:tcW", w="0", type="auto"), TCPR_ORDER)
    h = table.rows[0]
    _row_flag(h, "w:cantSplit")
    _row_flag(h, "w:tblHeader")
    _set_text(h.cells[0], f"{{%tc for h in {header} %}}")
    _set_text(h.cells[1], "{{ h }}", bold=True, style="Table Head")
    _shade_cell(h.cells[1], HEAD_FILL)
    _set_text(h.cells[2], "{%tc endfor %}")
    _set_text(table.rows[1].cells[0], f"{{%tr for row in {rows} %}}")
    body = table.rows[2]
    _row_flag(body, "w:cantSplit")
    _set_text(body.cells[0], "{%tc for c in row %}")
    _set_text(body.cells[1], "{{ c }}")
    _set_text(body.cells[2], "{%tc endfor %}")
    _set_text(table.rows[3].cells[0], "{%tr endfor %}")
    return table


def tag(doc, text: str) -> None:
    """A paragraph holding only a docxtpl paragraph tag (removed when rendered)."""
    doc.add_paragraph(text)


@contextmanager
def block(doc, head: str) -> Iterator[None]:
    """``{%p if … %}`` or ``{%p for … %}`` paragraphs around what the body adds, closed by
    ``{%p endif %}`` or ``{%p endfor %}``."""
    tag(doc, "{%p " + head + " %}")
    yield
    tag(doc, "{%p end" + head.split()[0] + " %}")


def para(doc, text: str = "", *, style: str | None = None, bold: bool = False, italic: bool = False,
         align=None):
    p = doc.add_paragraph(style=style)
    if text:
        run = p.add_run(text)
        run.bold = bold or None
        run.italic = italic or None
    if align is not None:
        p.alignment = align
    return p


def heading(doc, text: str, level: int):
    return doc.add_heading(text, level=level)


def label(doc, text: str):
    """A small bold lead-in above a table; kept with the table."""
    p = para(doc, text, style="Table Caption")
    return p


# --------------------------------------------------------------------------------------
# Styles and page
# --------------------------------------------------------------------------------------


def _styles(doc) -> None:
    styles = doc.styles
    normal = styles["Normal"]
    normal.font.name = "Calibri"
    normal.font.size = Pt(10)
    normal.paragraph_format.space_after = Pt(4)
    normal.paragraph_format.space_before = Pt(0)

    sizes = (("Title", 18, 0), ("Heading 1", 14, 14), ("Heading 2", 12, 12), ("Heading 3", 10.5, 8))
    for name, size, before in sizes:
        st = styles[name]
        st.font.name = "Calibri"
        st.font.size = Pt(size)
        st.font.bold = True
        st.font.color.rgb = DARK
        st.paragraph_format.space_before = Pt(before)
        st.paragraph_format.space_after = Pt(4)
        st.paragraph_format.keep_with_next = True
        rpr = st.element.get_or_add_rPr()
        for fonts in rpr.findall(qn("w:rFonts")):  # drop theme fonts so "Calibri" applies
            for a in ("asciiTheme", "hAnsiTheme", "eastAsiaTheme", "cstheme"):
                fonts.attrib.pop(qn(f"w:{a}"), None)
    title = styles["Title"]
    title_ppr = title.element.get_or_add_pPr()
    for bdr in title_ppr.findall(qn("w:pBdr")):  # the default Title has a blue rule
        title_ppr.remove(bdr)

    th = styles.add_style("Table Text", WD_STYLE_TYPE.PARAGRAPH)
    th.base_style = normal
    th.font.size = Pt(8.5)
    th.paragraph_format.space_after = Pt(0)
    th.paragraph_format.space_before = Pt(0)

    mono = styles.add_style("Table Mono", WD_STYLE_TYPE.PARAGRAPH)
    mono.base_style = th
    mono.font.name = "Consolas"
    mono.font.size = Pt(7.5)

    hd = styles.add_style("Table Head", WD_STYLE_TYPE.PARAGRAPH)
    hd.base_style = th
    hd.font.bold = True

    cap = styles.add_style("Table Caption", WD_STYLE_TYPE.PARAGRAPH)
    cap.base_style = normal
    cap.font.bold = True
    cap.font.size = Pt(9)
    cap.paragraph_format.space_before = Pt(6)
    cap.paragraph_format.space_after = Pt(2)
    cap.paragraph_format.keep_with_next = True

    fig = styles.add_style("Figure", WD_STYLE_TYPE.PARAGRAPH)
    fig.base_style = normal
    fig.paragraph_format.alignment = WD_ALIGN_PARAGRAPH.CENTER
    fig.paragraph_format.keep_with_next = True
    fig.paragraph_format.space_before = Pt(6)

    caption = styles["Caption"]
    caption.font.color.rgb = DARK
    caption.font.size = Pt(9)
    caption.paragraph_format.alignment = WD_ALIGN_PARAGRAPH.CENTER

    banner = styles.add_style("Banner", WD_STYLE_TYPE.PARAGRAPH)
    banner.base_style = normal
    banner.font.bold = True
    banner.font.color.rgb = BANNER_TEXT
    banner.paragraph_format.space_before = Pt(6)
    banner.paragraph_format.space_after = Pt(6)

    hdr = styles["Header"]
    hdr.font.size = Pt(8.5)
    hdr.paragraph_format.tab_stops.clear_all()
    hdr.paragraph_format.tab_stops.add_tab_stop(Mm(TEXT_W), WD_TAB_ALIGNMENT.RIGHT)
    ftr = styles["Footer"]
    ftr.font.size = Pt(8)
    ftr.paragraph_format.tab_stops.clear_all()
    ftr.paragraph_format.tab_stops.add_tab_stop(Mm(TEXT_W), WD_TAB_ALIGNMENT.RIGHT)


def _page(doc) -> None:
    sec = doc.sections[0]
    sec.orientation = WD_ORIENT.PORTRAIT
    sec.page_width, sec.page_height = Mm(PAGE_W), Mm(PAGE_H)
    sec.left_margin = sec.right_margin = Mm(MARGIN)
    sec.top_margin, sec.bottom_margin = Mm(25), Mm(20)
    sec.header_distance, sec.footer_distance = Mm(10), Mm(10)

    hp = sec.header.paragraphs[0]
    hp.style = "Header"
    hp.add_run("Test report {{ report_number }}").bold = True
    hp.add_run("\tPage ")
    _field(hp, "PAGE", "1")
    hp.add_run(" of ")
    _field(hp, "NUMPAGES", "1")
    # the SIMULATED mark on every page, as metro's own documents carry it (docxtpl fills headers
    # too)
    sp = sec.header.add_paragraph(style="Header")
    run = sp.add_run("{% if simulated %}SIMULATED — not a measurement of a real device{% endif %}")
    run.bold = True
    run.font.color.rgb = RGBColor(0xB0, 0x1C, 0x1C)
    _bottom_rule(sp)

    fp = sec.footer.paragraphs[0]
    fp.style = "Footer"
    fp.add_run("{{ footer }}")
    fp.add_run("\t{{ created }}")


def _properties(doc) -> None:
    import datetime as dt

    cp = doc.core_properties
    fixed = dt.datetime(2025, 1, 1, 0, 0, 0)
    cp.author = "metro"
    cp.last_modified_by = "metro"
    cp.title = "metro test report template"
    cp.subject = "docxtpl template for metro.core.documents.report"
    cp.keywords = "metro; calibration; test report"
    cp.comments = "Generated by core/documents/templates/make_templates.py; docxtpl tags inside."
    cp.created = cp.modified = fixed
    cp.last_printed = fixed
    cp.revision = 1


# --------------------------------------------------------------------------------------
# The report
# --------------------------------------------------------------------------------------


def _title_block(doc: Any) -> None:
    """The title, the report number, the verify QR code of a registered report (when the lab
    profile has a verify URL) and the SIMULATED banner."""
    para(doc, "{{ title }}", style="Title")
    para(doc, "Report number {{ report_number }} · issued {{ created }}", bold=True)
    with block(doc, "if verify_qr"):
        para(doc, "{{ verify_qr }}", style="Figure")
        para(doc, "Verify this report: {{ verify_link }}", style="Caption")
    with block(doc, "if simulated"):
        _shade_paragraph(para(doc, "{{ simulated_banner }}", style="Banner"), BANNER_FILL, "9C1C1C")


def _identification(doc: Any) -> None:
    """1 Identification: who, what and when."""
    heading(doc, "1 Identification", 1)
    kv_table(doc, [
        ("Report number", "{{ report_number }}"),
        ("Laboratory", "{{ facts.lab or '—' }}"),
        ("Laboratory address", "{{ facts.lab_address or '—' }}"),
        ("Customer", "{{ facts.customer or '—' }}"),
        ("Customer address", "{{ facts.customer_address or '—' }}"),
        ("Date of measurement", "{{ facts.measured or '—' }}"),
        ("Date received", "{{ facts.received or '—' }}"),
        ("Date of issue", "{{ facts.issued or '—' }}"),
        ("Standard", "{{ standards_text }}"),
        ("Items tested", "{{ items_text }}"),
        ("Campaign", "{{ campaign.id }}"),
        ("Data source", "{{ campaign.source }}"),
        ("Issued with", "{{ generator }}"),
    ])


def _device(doc: Any) -> None:
    """2 Device under test."""
    heading(doc, "2 Device under test", 1)
    kv_table(doc, [
        ("Identifier", "{{ device.id }}"),
        ("Manufacturer", "{{ device.manufacturer }}"),
        ("Model", "{{ device.model }}"),
        ("Serial number", "{{ device.serial }}"),
        ("Technology", "{{ device.technology }}"),
        ("Application", "{{ device.application }}"),
        ("Output", "{{ device.output }}"),
    ], loop=("p in device.properties", "{{ p.name }}", "{{ p.value }}"))


def _environment(doc: Any) -> None:
    """3 Environment and site."""
    heading(doc, "3 Environment and site", 1)
    label(doc, "Environmental conditions")
    tag(doc, "{%p if environment %}")
    loop_table(doc, ["Quantity", "Value"], ["{{ e.name }}", "{{ e.value }}"], [50, TEXT_W - 50],
               "e in environment")
    tag(doc, "{%p else %}")
    para(doc, "No environmental conditions were stated for this campaign.", italic=True)
    tag(doc, "{%p endif %}")
    label(doc, "Test site")
    tag(doc, "{%p if site %}")
    loop_table(doc, ["Quantity", "Value"], ["{{ s.name }}", "{{ s.value }}"], [50, TEXT_W - 50],
               "s in site")
    tag(doc, "{%p else %}")
    para(doc, "No site data were stated for this campaign.", italic=True)
    tag(doc, "{%p endif %}")


def _equipment(doc: Any) -> None:
    """4 Equipment and traceability."""
    heading(doc, "4 Equipment and traceability", 1)
    para(doc, "Calibration status on the date of measurement ({{ facts.measured }}). "
              "U is the expanded "
              "uncertainty stated on the certificate, with its coverage factor k.")
    tag(doc, "{%p if equipment %}")
    loop_table(
        doc,
        ["ID", "Description", "Role", "Certificate", "U (k)", "Due", "Status"],
        ["{{ e.id }}", "{{ e.description }}", "{{ e.role }}", "{{ e.certificate }}", "{{ e.U }}",
         "{{ e.due }}", "{{ e.status }}"],
        [20, 33, 18, 25, 24, 20, 30],
        "e in equipment",
    )
    tag(doc, "{%p else %}")
    para(doc, "No equipment was listed for this campaign.", italic=True)
    tag(doc, "{%p endif %}")
    with block(doc, "for w in equipment_warnings"):
        para(doc, "{{ w }}", style="Banner")


def _budget(doc: Any) -> None:
    """An outcome's uncertainty budgets (inside the outcome loop)."""
    with block(doc, "for b in o.budgets"):
        heading(doc, "Uncertainty budget: {{ b.title }}", 3)
        # type and distribution in one column (as metro's own documents print them), so no header
        # word is cut ("Typ|e", "Distribut|ion" in columns of 12 and 19 mm)
        widths = [32, 18, 26, 22, 16, 22, 24, 10]
        budget = loop_table(
            doc,
            ["Source of uncertainty", "Symbol", "Type, distribution", "Value", "Divisor",
             "Sensitivity c_i", "u_i(y) / {{ b.unit }}", "ν_i"],
            ["{{ r.source }}", "{{ r.symbol }}", "{{ r.type }}, {{ r.distribution }}",
             "{{ r.value }}", "{{ r.divisor }}", "{{ r.sensitivity }}", "{{ r.contribution }}",
             "{{ r.dof }}"],
            widths,
            "r in b.rows",
        )
        for label_text, value_text in (
            ("Combined standard uncertainty u_c", "{{ b.u_c }} {{ b.unit }}"),
            ("Effective degrees of freedom ν_eff", "{{ b.nu_eff }}"),
            ("Coverage factor k", "{{ b.k }}"),
            ("Expanded uncertainty U = k·u_c", "{{ b.U }} {{ b.unit }}"),
        ):
            row = budget.add_row()
            _row_flag(row, "w:cantSplit")
            left = row.cells[0].merge(row.cells[4])
            right = row.cells[5].merge(row.cells[7])
            _set_text(left, label_text, bold=True)
            _set_text(right, value_text, bold=True)
            _shade_cell(left, SUM_FILL)
            _shade_cell(right, SUM_FILL)
        with block(doc, "if b.note"):
            para(doc, "{{ b.note }}", italic=True)


def _outcome(doc: Any) -> None:
    """One outcome (inside the outcome loop): results, notes, budgets, tables, figures, warnings."""
    heading(doc, "{{ o.number }} {{ o.item }} — {{ o.title }}", 2)
    para(doc, "{{ o.designation }}, clause {{ o.clause }}. "
              "Segments evaluated: {{ o.segments_text }}.")
    with block(doc, "if o.options_text"):
        para(doc, "Options: {{ o.options_text }}")
    label(doc, "Results")
    loop_table(
        doc,
        ["Quantity", "Symbol", "Value", "U", "Unit", "k", "Clause / equation"],
        ["{{ r.quantity }}", "{{ r.symbol }}", "{{ r.value }}", "{{ r.U }}", "{{ r.unit }}",
         "{{ r.k }}", "{{ r.reference }}"],
        [38, 18, 24, 20, 16, 12, 42],
        "r in o.results",
    )
    with block(doc, "for n in o.notes"):
        para(doc, "Note: {{ n }}", italic=True)

    _budget(doc)

    with block(doc, "for t in o.tables"):
        label(doc, "{{ t.title }}")
        column_loop_table(doc, "t.header", "t.rows")

    with block(doc, "for p in o.plots"):
        para(doc, "{{ p.image }}", style="Figure")
        para(doc, "Figure {{ p.number }} — {{ p.title }}", style="Caption")

    with block(doc, "if o.warnings"):
        label(doc, "Warnings")
        with block(doc, "for w in o.warnings"):
            para(doc, "{{ w }}", style="List Bullet")


def _results(doc: Any) -> None:
    """5 Results: the declared truth of a simulated run, then each outcome."""
    heading(doc, "5 Results", 1)
    para(doc, "Values are reported with their expanded uncertainty U = k·u_c; U has at most two "
              "significant digits and the value is rounded to the same decimal place (JJF 1059.1).")
    with block(doc, "if simulated"):
        _shade_paragraph(para(doc, "{{ simulated_banner }}", style="Banner"), BANNER_FILL, "9C1C1C")
        label(doc, "Declared truth of the simulated station (compare with the results below)")
        loop_table(doc, ["Parameter", "Declared value"], ["{{ t.name }}", "{{ t.value }}"],
                   [70, TEXT_W - 70],
                   "t in truth")
    with block(doc, "for o in outcomes"):
        _outcome(doc)
    with block(doc, "if not outcomes"):
        para(doc, "This report holds no results.", italic=True)


def _conformity(doc: Any) -> None:
    """6 Conformity with the specification."""
    heading(doc, "6 Conformity with the specification", 1)
    tag(doc, "{%p if conformity %}")
    para(doc, "Decision rule: {{ conformity.rule_title }}. {{ conformity.statement }}")
    para(doc, "Overall: {{ conformity.overall }}", bold=True)
    loop_table(
        doc,
        ["Item", "Result", "Limit", "Source of the limit", "Verdict", "Why"],
        ["{{ v.item }}", "{{ v.key }}", "{{ v.limit }}", "{{ v.source }}", "{{ v.status }}",
         "{{ v.reason }}"],
        [18, 18, 26, 40, 20, 48],
        "v in conformity.verdicts",
    )
    with block(doc, "if conformity.not_assessed"):
        label(doc, "Limits given but not assessed (no result of this run)")
        with block(doc, "for n in conformity.not_assessed"):
            para(doc, "{{ n }}", style="List Bullet")
    tag(doc, "{%p else %}")
    para(doc, "No specification was given for this campaign; this report makes no statement of "
              "conformity.", italic=True)
    tag(doc, "{%p endif %}")


def _provenance(doc: Any) -> None:
    """7 Provenance: campaign source, software, plugins, raw data."""
    heading(doc, "7 Provenance", 1)
    para(doc, "Campaign source: {{ provenance.source }}")
    label(doc, "Software")
    loop_table(doc, ["Component", "Version"], ["{{ s.name }}", "{{ s.version }}"],
               [50, TEXT_W - 50],
               "s in provenance.software")
    label(doc, "Plugins")
    tag(doc, "{%p if provenance.plugins %}")
    loop_table(doc, ["Plugin", "Distribution and version"], ["{{ s.name }}", "{{ s.version }}"],
               [50, TEXT_W - 50], "s in provenance.plugins")
    tag(doc, "{%p else %}")
    para(doc, "No plugins were recorded.", italic=True)
    tag(doc, "{%p endif %}")
    label(doc, "Raw data")
    tag(doc, "{%p if provenance.data_files %}")
    loop_table(doc, ["File", "SHA-256"], ["{{ f.file }}", "{{ f.sha256 }}"], [58, TEXT_W - 58],
               "f in provenance.data_files", styles={1: "Table Mono"})
    tag(doc, "{%p else %}")
    para(doc, "No raw data files were recorded.", italic=True)
    tag(doc, "{%p endif %}")


def _signatures(doc: Any) -> None:
    """The signature table, with room to sign."""
    heading(doc, "Signatures", 1)
    sig = kv_table(doc, [
        ("Tested by", "{{ facts.operator or '—' }}"),
        ("Checked by", "{{ facts.checker or '—' }}"),
        ("Approved by", "{{ facts.approver or '—' }}"
                        "{% if facts.approver_title %}, {{ facts.approver_title }}{% endif %}"),
    ])
    for row in sig.rows:
        row.height = Mm(11)  # room to sign


def _closing(doc: Any) -> None:
    """The closing statement."""
    heading(doc, "Statement", 1)
    para(doc, CLOSING)
    para(doc, "End of report {{ report_number }}", italic=True, align=WD_ALIGN_PARAGRAPH.CENTER)


def build() -> "docx.document.Document":
    """The docxtpl report template, section by section."""
    doc = docx.Document()
    _styles(doc)
    _page(doc)
    _properties(doc)
    _title_block(doc)
    _identification(doc)
    _device(doc)
    _environment(doc)
    _equipment(doc)
    _results(doc)
    _conformity(doc)
    _provenance(doc)
    _signatures(doc)
    _closing(doc)
    return doc


def _reproducible_zip(data: bytes) -> bytes:
    """The same package with fixed zip time stamps and attributes (deterministic bytes)."""
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(data)) as src, \
            zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            fixed = zipfile.ZipInfo(info.filename, date_time=(1980, 1, 1, 0, 0, 0))
            fixed.compress_type = zipfile.ZIP_DEFLATED
            fixed.external_attr = 0o644 << 16
            fixed.create_system = 3
            dst.writestr(fixed, src.read(info.filename))
    return out.getvalue()


def main(argv: list[str] | None = None) -> Path:
    argv = sys.argv[1:] if argv is None else argv
    out = Path(argv[0]) if argv else OUT
    buf = io.BytesIO()
    build().save(buf)
    data = _reproducible_zip(buf.getvalue())
    try:
        from metro.core.base.atomic import atomic_write_bytes
    except ImportError:  # pragma: no cover - run outside an installed metro
        out.write_bytes(data)
    else:
        atomic_write_bytes(out, data)
    print(f"wrote {out} ({len(data)} bytes)")
    return out


if __name__ == "__main__":
    main()

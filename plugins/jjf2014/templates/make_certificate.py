"""Build the JJF 2014—2022 certificate template, ``certificate.docx``, next to this script.

Run after changing the layout (the output is committed)::

    python plugins/jjf2014/templates/make_certificate.py [OUT.docx]

Layout follows clause 8 a)–p) and appendix A: title; laboratory; place; certificate number
with "page x of y" on every page (header); customer; device; dates; the specification; the
standards used and their traceability; the environment (appendix A); the 24-row results table
(appendix A) with expanded uncertainties; uncertainty budgets; figures; deviations; signatures;
the two statements.  Tags are docxtpl (Jinja2) tags filled from
:func:`metro.core.report.report_context` and ``context["jjf2014"]``
(:mod:`metro.plugins.jjf2014.certificate`).  The output is byte-for-byte reproducible
(fixed core properties, fixed zip time stamps).
"""

from __future__ import annotations

import datetime as dt
import io
import sys
import zipfile
from pathlib import Path

import docx
from docx.enum.text import WD_ALIGN_PARAGRAPH
from docx.oxml import OxmlElement
from docx.oxml.ns import qn
from docx.shared import Mm, Pt
from metro.core.budget import TEMPLATE_BUDGET_COLUMNS, TEMPLATE_BUDGET_HEADING

OUT = Path(__file__).with_name("certificate.docx")


def _fld(par, instr: str, shown: str) -> None:
    f = OxmlElement("w:fldSimple")
    f.set(qn("w:instr"), instr)
    r = OxmlElement("w:r")
    t = OxmlElement("w:t")
    t.text = shown
    r.append(t)
    f.append(r)
    par._p.append(f)


def _table(doc, header, template_cells, loop=None, widths=None):
    """A table with a header row, optionally a {%tr for %} row, one template row, {%tr endfor %}."""
    rows = 2 + (2 if loop else 0)
    tb = doc.add_table(rows=rows, cols=len(header))
    tb.style = "Table Grid"
    for i, h in enumerate(header):
        tb.cell(0, i).text = h
        for run in tb.cell(0, i).paragraphs[0].runs:
            run.bold = True
    r = 1
    if loop:
        tb.cell(r, 0).text = "{%tr for " + loop + " %}"
        r += 1
    for i, c in enumerate(template_cells):
        tb.cell(r, i).text = c
    if loop:
        tb.cell(r + 1, 0).text = "{%tr endfor %}"
    if widths:
        for row in tb.rows:
            for cell, w in zip(row.cells, widths):
                cell.width = Mm(w)
    return tb


def _kv_table(doc, pairs):
    tb = doc.add_table(rows=len(pairs), cols=2)
    tb.style = "Table Grid"
    for i, (k, v) in enumerate(pairs):
        tb.cell(i, 0).text = k
        tb.cell(i, 1).text = v
        tb.cell(i, 0).width, tb.cell(i, 1).width = Mm(55), Mm(115)
    return tb


def build() -> bytes:
    doc = docx.Document()
    sec = doc.sections[0]
    sec.page_width, sec.page_height = Mm(210), Mm(297)
    for side in ("left_margin", "right_margin", "top_margin", "bottom_margin"):
        setattr(sec, side, Mm(20))
    st = doc.styles["Normal"]
    st.font.name = "SimSun"
    st.font.size = Pt(10.5)
    st.element.rPr.rFonts.set(qn("w:eastAsia"), "SimSun")

    # d) certificate number and page x of y on every page
    hp = sec.header.paragraphs[0]
    hp.text = "证书编号 Certificate No. {{ jjf2014.number }}    第 "
    _fld(hp, "PAGE", "1")
    hp.add_run(" 页 共 ")
    _fld(hp, "NUMPAGES", "1")
    hp.add_run(" 页 (page x of y)")
    fp = sec.footer.paragraphs[0]
    fp.text = "{{ jjf2014.statement_copy }}"

    # a) title
    t = doc.add_paragraph()
    t.alignment = WD_ALIGN_PARAGRAPH.CENTER
    run = t.add_run("{{ jjf2014.title }}")
    run.bold = True
    run.font.size = Pt(20)
    doc.add_paragraph("{%p if simulated %}")
    doc.add_paragraph("{{ simulated_banner }}")
    doc.add_paragraph("{%p endif %}")

    # b) c) e) f) g) i)
    _kv_table(doc, [
        ("实验室 Laboratory", "{{ jjf2014.lab }}, {{ jjf2014.lab_address }}"),
        ("校准地点 Place of calibration", "{{ jjf2014.location }}"),
        ("客户 Customer", "{{ jjf2014.customer }}, {{ jjf2014.customer_address }}"),
        ("被校对象 Device", "{{ device.description }} (id {{ device.id }}; output {{ device.output }})"),
        ("接收日期 Received", "{{ jjf2014.received }}"),
        ("校准日期 Date of calibration", "{{ jjf2014.calibrated_on }}"),
        ("校准依据 Specification", "{{ jjf2014.specification }}"),
    ])

    # j) standards used and their traceability
    doc.add_heading("校准所用测量标准 Standards used and traceability", level=2)
    _table(doc, ["设备 Equipment", "用途 Role", "证书 Certificate", "U", "有效性 Validity"],
           ["{{ e.id }} {{ e.description }}", "{{ e.role }}", "{{ e.certificate }}", "{{ e.U }}", "{{ e.status }}"],
           loop="e in equipment")

    # k) environment (appendix A)
    doc.add_heading("校准环境条件 Environment", level=2)
    tb = doc.add_table(rows=2, cols=4)
    tb.style = "Table Grid"
    for (r, c), txt in {(0, 0): "温度 Temperature", (0, 1): "{{ jjf2014.environment.temperature }}",
                        (0, 2): "地点 Location", (0, 3): "{{ jjf2014.environment.location }}",
                        (1, 0): "相对湿度 Humidity", (1, 1): "{{ jjf2014.environment.humidity }}",
                        (1, 2): "其他 Other", (1, 3): "{{ jjf2014.environment.other }}"}.items():
        tb.cell(r, c).text = txt

    # l) results (appendix A, 24 rows)
    doc.add_heading("校准结果 Results (appendix A)", level=2)
    _table(doc, ["序号 No.", "校准项目 Item", "条款 Clause", "校准结果 Result", "扩展不确定度 U"],
           ["{{ r.no }}", "{{ r.item_cn }} {{ r.item_en }}", "{{ r.clause }}", "{{ r.value }}", "{{ r.U }}"],
           loop="r in jjf2014.rows", widths=(14, 62, 18, 40, 36))
    doc.add_paragraph("{{ jjf2014.performed_count }} of 24 items calibrated; items marked 未校准 were not performed.")

    doc.add_heading("不确定度评定 Uncertainty budgets", level=2)
    doc.add_paragraph("{%p for o in outcomes %}")
    doc.add_paragraph("{%p for b in o.budgets %}")
    doc.add_paragraph(TEMPLATE_BUDGET_HEADING)
    _table(doc, [h for h, _, _ in TEMPLATE_BUDGET_COLUMNS], [c for _, c, _ in TEMPLATE_BUDGET_COLUMNS],
           loop="row in b.rows", widths=tuple(w for _, _, w in TEMPLATE_BUDGET_COLUMNS))
    doc.add_paragraph("{%p endfor %}")
    doc.add_paragraph("{%p endfor %}")

    doc.add_heading("图 Figures", level=2)
    doc.add_paragraph("{%p for o in outcomes %}")
    doc.add_paragraph("{%p for p in o.plots %}")
    doc.add_paragraph("{{ p.image }}")
    doc.add_paragraph("Figure {{ p.number }}: {{ p.caption }}")
    doc.add_paragraph("{%p endfor %}")
    doc.add_paragraph("{%p endfor %}")

    # m) deviations from the specification
    doc.add_heading("对校准规范的偏离 Deviations from the specification", level=2)
    doc.add_paragraph("{%p for d in jjf2014.deviations %}")
    doc.add_paragraph("{{ d }}")
    doc.add_paragraph("{%p endfor %}")

    # n) signatures
    doc.add_heading("签名 Signatures", level=2)
    _kv_table(doc, [("校准员 Calibrated by", "{{ jjf2014.calibrated_by }}"),
                    ("核验员 Checked by", "{{ jjf2014.checked_by }}"),
                    ("批准人 Approved by", "{{ jjf2014.approved_by }}")])
    # o) p)
    doc.add_paragraph("{{ jjf2014.statement_validity }}")
    doc.add_paragraph("{{ jjf2014.statement_copy }}")

    cp = doc.core_properties
    cp.author = cp.last_modified_by = "metro jjf2014"
    cp.title = "JJF 2014—2022 calibration certificate template"
    cp.created = cp.modified = dt.datetime(2022, 1, 1)
    cp.revision = 1
    buf = io.BytesIO()
    doc.save(buf)
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(buf.getvalue())) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            zi = zipfile.ZipInfo(info.filename, date_time=(1980, 1, 1, 0, 0, 0))
            zi.compress_type = zipfile.ZIP_DEFLATED
            dst.writestr(zi, src.read(info.filename))
    return out.getvalue()


def main(argv: list[str]) -> None:
    target = Path(argv[1]) if len(argv) > 1 else OUT
    target.write_bytes(build())
    print(f"wrote {target}")


if __name__ == "__main__":
    main(sys.argv)

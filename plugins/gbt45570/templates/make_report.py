"""Build the GB/T 45570—2025 test-report template, ``report.docx``, next to this script.

Run after changing the layout (the output is committed)::

    python plugins/gbt45570/templates/make_report.py [OUT.docx]

Sections: identification (laboratory, customer, device, dates, standard); 6.1.1 test
environment checked against its limits; equipment with calibration status; the 6.2.7.1
method choice and the items run; every item's results with U and k; conformity verdicts with
the decision rule and the reason for each; the device's typical-limit table (A.1 or B.1) with
"not performed" rows; the C.1 severities; budgets; figures; provenance (software, plugin
versions, data SHA-256); deviations; signatures.  The report number and "page x of y" are in
the header of every page.  Tags are docxtpl (Jinja2) tags filled from
:func:`metro.core.report.report_context` and ``context["gbt45570"]``
(:mod:`metro.plugins.gbt45570.report`).  The output is byte-for-byte reproducible.
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

OUT = Path(__file__).with_name("report.docx")


def _field(paragraph, instruction: str, shown: str) -> None:
    """A simple Word field (PAGE, NUMPAGES) showing ``shown`` until Word updates it."""
    fld = OxmlElement("w:fldSimple")
    fld.set(qn("w:instr"), instruction)
    run = OxmlElement("w:r")
    text = OxmlElement("w:t")
    text.text = shown
    run.append(text)
    fld.append(run)
    paragraph._p.append(fld)


def _grid(doc, header: list[str], cells: list[str], loop: str | None = None, widths: tuple = ()) -> None:
    """A bordered table: bold header, then one row of tags repeated by ``{%tr for loop %}``."""
    n_rows = 2 + (2 if loop else 0)
    table = doc.add_table(rows=n_rows, cols=len(header))
    table.style = "Table Grid"
    for i, h in enumerate(header):
        table.cell(0, i).text = h
        for run in table.cell(0, i).paragraphs[0].runs:
            run.bold = True
    row = 1
    if loop:
        table.cell(row, 0).text = "{%tr for " + loop + " %}"
        row += 1
    for i, c in enumerate(cells):
        table.cell(row, i).text = c
    if loop:
        table.cell(row + 1, 0).text = "{%tr endfor %}"
    if widths:  # the grid (LibreOffice) and every cell (Word) carry the widths
        table.autofit = False
        for col, w in zip(table.columns, widths):
            col.width = Mm(w)
        for r in table.rows:
            for cell, w in zip(r.cells, widths):
                cell.width = Mm(w)


def _pairs(doc, pairs: list[tuple[str, str]]) -> None:
    table = doc.add_table(rows=len(pairs), cols=2)
    table.style = "Table Grid"
    for i, (label, value) in enumerate(pairs):
        table.cell(i, 0).text = label
        table.cell(i, 1).text = value
        table.cell(i, 0).width, table.cell(i, 1).width = Mm(50), Mm(120)
    table.autofit = False
    table.columns[0].width, table.columns[1].width = Mm(50), Mm(120)


def _lines(doc, loop: str, body: str) -> None:
    doc.add_paragraph("{%p for " + loop + " %}")
    doc.add_paragraph(body)
    doc.add_paragraph("{%p endfor %}")


def build() -> bytes:
    doc = docx.Document()
    sec = doc.sections[0]
    sec.page_width, sec.page_height = Mm(210), Mm(297)
    for side in ("left_margin", "right_margin", "top_margin", "bottom_margin"):
        setattr(sec, side, Mm(20))
    normal = doc.styles["Normal"]
    normal.font.name = "SimSun"
    normal.font.size = Pt(10)
    normal.element.rPr.rFonts.set(qn("w:eastAsia"), "SimSun")

    # the report number and page x of y on every page
    head = sec.header.paragraphs[0]
    head.text = "报告编号 Report No. {{ gbt45570.number }}    第 "
    _field(head, "PAGE", "1")
    head.add_run(" 页 共 ")
    _field(head, "NUMPAGES", "1")
    head.add_run(" 页 (page x of y)")
    foot = sec.footer.paragraphs[0]
    foot.text = "{{ gbt45570.number }} · GB/T 45570—2025 · {{ generator }}"

    title = doc.add_paragraph()
    title.alignment = WD_ALIGN_PARAGRAPH.CENTER
    run = title.add_run("{{ gbt45570.title }}")
    run.bold = True
    run.font.size = Pt(16)
    doc.add_paragraph("{%p if simulated %}")
    doc.add_paragraph("{{ simulated_banner }}")
    doc.add_paragraph("{%p endif %}")

    doc.add_heading("1 标识 Identification", level=2)
    _pairs(doc, [
        ("报告编号 Report No.", "{{ gbt45570.number }}"),
        ("实验室 Laboratory", "{{ gbt45570.lab }}, {{ gbt45570.lab_address }}"),
        ("委托方 Customer", "{{ gbt45570.customer }}, {{ gbt45570.customer_address }}"),
        ("被试产品 Device under test", "{{ device.description }} (id {{ device.id }}; output {{ device.output }})"),
        ("类型与应用 Technology, application", "{{ gbt45570.device_application }}"),
        ("试验日期 Date of test", "{{ gbt45570.tested_on }}"),
        ("依据 Standard", "GB/T 45570—2025 光学陀螺仪通用技术要求, appendix D; items {{ items_text }}"),
        ("数据来源 Campaign", "{{ campaign.id }} ({{ campaign.source }})"),
    ])

    doc.add_heading("2 试验环境 Test environment (6.1.1)", level=2)
    _grid(doc, ["条件 Condition", "要求 Required", "实测 Recorded", "符合性 Conformity"],
          ["{{ r.name }}", "{{ r.required }}", "{{ r.measured }}", "{{ r.verdict }}"],
          loop="r in gbt45570.environment", widths=(55, 40, 40, 35))

    doc.add_heading("3 试验设备 Equipment and calibration status", level=2)
    _grid(doc, ["设备 Equipment", "用途 Role", "证书 Certificate", "U", "状态 Status"],
          ["{{ e.id }} {{ e.description }}", "{{ e.role }}", "{{ e.certificate }}", "{{ e.U }}", "{{ e.status }}"],
          loop="e in equipment", widths=(50, 25, 35, 25, 35))
    _lines(doc, "w in equipment_warnings", "{{ w }}")

    doc.add_heading("4 试验方法与项目 Method and items", level=2)
    doc.add_paragraph("{%p if gbt45570.method %}")
    doc.add_paragraph("{{ gbt45570.method }}")
    doc.add_paragraph("{%p endif %}")
    doc.add_paragraph("{%p if gbt45570.selection %}")
    _grid(doc, ["项目 Item", "来源 Via", "执行 Run", "理由 Reason"],
          ["{{ c.item }}", "{{ c.via }}", "{{ c.run }}", "{{ c.reason }}"],
          loop="c in gbt45570.selection", widths=(20, 30, 20, 100))
    doc.add_paragraph("{%p endif %}")

    doc.add_heading("5 试验结果 Results", level=2)
    doc.add_paragraph("{%p for o in outcomes %}")
    doc.add_paragraph("{{ o.number }} {{ o.item }} {{ o.title }} (clause {{ o.clause }}; segments {{ o.segments_text }})")
    _grid(doc, ["量 Quantity", "结果 Value", "U", "单位 Unit", "k", "公式 Ref."],
          ["{{ r.quantity }} {{ r.symbol }}", "{{ r.value }}", "{{ r.U }}", "{{ r.unit }}", "{{ r.k }}",
           "{{ r.reference }}"], loop="r in o.results", widths=(50, 30, 25, 25, 12, 28))
    _lines(doc, "n in o.notes", "{{ n }}")
    _lines(doc, "w in o.warnings", "warning: {{ w }}")
    doc.add_paragraph("{%p endfor %}")

    doc.add_heading("6 符合性判定 Conformity", level=2)
    doc.add_paragraph("判定规则 Decision rule: {{ gbt45570.rule.title }}")
    doc.add_paragraph("{{ gbt45570.rule.statement }}")
    doc.add_paragraph("{%p if gbt45570.has_conformity %}")
    doc.add_paragraph("总体 Overall: {{ gbt45570.overall }} ({{ gbt45570.counts }})")
    _grid(doc, ["项目 Item", "结果 Result", "限值 Limit", "值 Value", "U (k)", "判定 Verdict", "理由 Reason"],
          ["{{ v.item }}", "{{ v.key }}", "{{ v.limit }}", "{{ v.value }}", "{{ v.U }} ({{ v.k }})",
           "{{ v.status_text }}", "{{ v.reason }}"],
          loop="v in gbt45570.verdicts", widths=(14, 16, 22, 20, 22, 20, 56))
    doc.add_paragraph("限值来源 Sources of the limits:")
    _lines(doc, "v in gbt45570.verdicts", "{{ v.key }}: {{ v.source }}")
    doc.add_paragraph("{%p if gbt45570.not_assessed %}")
    doc.add_paragraph("未判定 Not assessed (item not performed):")
    _lines(doc, "s in gbt45570.not_assessed", "{{ s }}")
    doc.add_paragraph("{%p endif %}")
    doc.add_paragraph("{%p endif %}")

    doc.add_paragraph("{%p if gbt45570.limits %}")
    doc.add_heading("7 典型指标 Typical indices", level=2)
    doc.add_paragraph("{{ gbt45570.limits.title }}")
    _grid(doc, ["序号 No.", "项目 Item", "指标 Limit", "方法 Method", "结果 Result", "判定 Verdict"],
          ["{{ r.no }}", "{{ r.name }}", "{{ r.limit }}", "{{ r.method }}", "{{ r.result }}", "{{ r.verdict }}"],
          loop="r in gbt45570.limits.rows", widths=(12, 45, 25, 20, 45, 23))
    doc.add_paragraph("{%p endif %}")
    doc.add_paragraph("{%p if gbt45570.severities %}")
    doc.add_heading("8 环境适应性 Environmental severities (table C.1)", level=2)
    _grid(doc, ["序号 No.", "项目 Test", "严酷度 Severity", "方法 Method", "状态 Status"],
          ["{{ r.no }}", "{{ r.name }}", "{{ r.severity }}", "{{ r.method }}", "{{ r.status }}"],
          loop="r in gbt45570.severities", widths=(12, 40, 58, 20, 40))
    doc.add_paragraph("{%p endif %}")

    doc.add_heading("9 不确定度 Uncertainty budgets", level=2)
    doc.add_paragraph("{%p for o in outcomes %}")
    doc.add_paragraph("{%p for b in o.budgets %}")
    doc.add_paragraph(TEMPLATE_BUDGET_HEADING)
    _grid(doc, [h for h, _, _ in TEMPLATE_BUDGET_COLUMNS], [c for _, c, _ in TEMPLATE_BUDGET_COLUMNS],
          loop="row in b.rows", widths=tuple(w for _, _, w in TEMPLATE_BUDGET_COLUMNS))
    doc.add_paragraph("{%p endfor %}")
    doc.add_paragraph("{%p endfor %}")

    doc.add_heading("10 图 Figures", level=2)
    doc.add_paragraph("{%p for o in outcomes %}")
    doc.add_paragraph("{%p for p in o.plots %}")
    doc.add_paragraph("{{ p.image }}")
    doc.add_paragraph("Figure {{ p.number }}: {{ p.caption }}")
    doc.add_paragraph("{%p endfor %}")
    doc.add_paragraph("{%p endfor %}")

    doc.add_heading("11 溯源与数据 Provenance", level=2)
    _lines(doc, "s in provenance.software", "{{ s.name }} {{ s.version }}")
    _lines(doc, "p in provenance.plugins", "plugin {{ p.name }}: {{ p.version }}")
    _grid(doc, ["数据 Data", "SHA-256"], ["{{ f.file }}", "{{ f.sha256 }}"], loop="f in provenance.data_files",
          widths=(60, 110))
    doc.add_paragraph("数据摘要 Data digest (SHA-256 of all digests): {{ gbt45570.data_digest }}")

    doc.add_heading("12 偏离 Deviations", level=2)
    _lines(doc, "d in gbt45570.deviations", "{{ d }}")
    doc.add_heading("签名 Signatures", level=2)
    _pairs(doc, [("试验 Tested by", "{{ gbt45570.tested_by }}"), ("校核 Checked by", "{{ gbt45570.checked_by }}"),
                 ("批准 Approved by", "{{ gbt45570.approved_by }}")])
    doc.add_paragraph("本报告结果仅对被试样品有效。The results relate only to the device tested. "
                      "This report shall not be reproduced except in full.")

    props = doc.core_properties
    props.author = props.last_modified_by = "metro gbt45570"
    props.title = "GB/T 45570—2025 test report template"
    props.created = props.modified = dt.datetime(2025, 1, 1)
    props.revision = 1
    raw = io.BytesIO()
    doc.save(raw)
    out = io.BytesIO()
    with zipfile.ZipFile(io.BytesIO(raw.getvalue())) as src, zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as dst:
        for info in src.infolist():
            entry = zipfile.ZipInfo(info.filename, date_time=(1980, 1, 1, 0, 0, 0))
            entry.compress_type = zipfile.ZIP_DEFLATED
            dst.writestr(entry, src.read(info.filename))
    return out.getvalue()


def main(argv: list[str]) -> None:
    target = Path(argv[1]) if len(argv) > 1 else OUT
    target.write_bytes(build())
    print(f"wrote {target}")


if __name__ == "__main__":
    main(sys.argv)

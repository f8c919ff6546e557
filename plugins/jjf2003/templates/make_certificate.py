"""Build the JJF 2003—2022 certificate template, ``certificate.docx``, next to this script.

    python plugins/jjf2003/templates/make_certificate.py [OUT.docx]

The layout follows clause 8 a)–l) (front page) and appendix B (the inner page: 1 scale
factors, 2 biases, 3 gyro cross-coupling, 4 accelerometer cross-coupling, 5 gyro g matrix,
6 accelerometer p matrix, each with its uncertainty).  Matrices are 3×3 tables.  Tags are
docxtpl's: ``{{ }}``, ``{%p if %}``/``{%p endif %}`` paragraphs and ``{%tr for %}``/
``{%tr endfor %}`` rows; data come from ``context["jjf2003"]``
(:func:`metro.plugins.jjf2003.certificate.certificate_context`) and the generic report
context (banner, environment).  The output is byte-for-byte reproducible (fixed properties
and zip time stamps).
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

OUT = Path(__file__).with_name("certificate.docx")
C = "jjf2003"


def _p(doc, text="", *, bold=False, size=None, center=False):
    p = doc.add_paragraph()
    if text:
        r = p.add_run(text)
        r.bold = bold or None
        if size:
            r.font.size = Pt(size)
    if center:
        p.alignment = WD_ALIGN_PARAGRAPH.CENTER
    return p


def _fld(paragraph, instr: str, shown: str) -> None:
    f = OxmlElement("w:fldSimple")
    f.set(qn("w:instr"), f" {instr} ")
    r = OxmlElement("w:r")
    t = OxmlElement("w:t")
    t.text = shown
    r.append(t)
    f.append(r)
    paragraph._p.append(f)


def _grid(doc, n_rows: int, n_cols: int):
    t = doc.add_table(rows=n_rows, cols=n_cols)
    t.style = "Table Grid"
    return t


def _kv(doc, rows):
    t = _grid(doc, len(rows), 2)
    for row, (k, v) in zip(t.rows, rows):
        row.cells[0].text = k
        row.cells[1].text = v
    return t


def _loop_table(doc, headers, cells, loop):
    """Header row, a {%tr for %} row, the template row, a {%tr endfor %} row."""
    t = _grid(doc, 4, len(headers))
    for c, h in zip(t.rows[0].cells, headers):
        c.text = h
        for r in c.paragraphs[0].runs:
            r.bold = True
    t.rows[1].cells[0].text = "{%tr for " + loop + " %}"
    for c, text in zip(t.rows[2].cells, cells):
        c.text = text
    t.rows[3].cells[0].text = "{%tr endfor %}"
    return t


def _result_rows(doc, key: str, title: str):
    _p(doc, "{%p if " + f"{C}.{key}" + " %}")
    _p(doc, title, bold=True)
    _loop_table(doc, ["quantity", "symbol", "value", "U (k = 2)", "unit"],
                ["{{ r.name }}", "{{ r.symbol }}", "{{ r.value }}", "{{ r.U }}", "{{ r.unit }}"],
                f"r in {C}.{key}")
    _p(doc, "{%p endif %}")


def _matrix(doc, key: str, title: str, symbol: str):
    m = f"{C}.{key}"
    _p(doc, "{%p if " + m + " %}")
    _p(doc, title, bold=True)
    _p(doc, f"{symbol} (rows: output axis x, y, z; columns: input axis x, y, z), unit {{{{ {m}.unit }}}}:")
    _loop_table(doc, ["", "x", "y", "z"], ["{{ r.axis }}", "{{ r.c1 }}", "{{ r.c2 }}", "{{ r.c3 }}"],
                f"r in {m}.value_rows")
    _p(doc, "测量不确定度 (expanded uncertainty U, k = 2), same layout:")
    _loop_table(doc, ["", "x", "y", "z"], ["{{ r.axis }}", "{{ r.c1 }}", "{{ r.c2 }}", "{{ r.c3 }}"],
                f"r in {m}.u_rows")
    _p(doc, "{%p endif %}")


def build():
    doc = docx.Document()
    sec = doc.sections[0]
    sec.page_width, sec.page_height = Mm(210), Mm(297)
    for side in ("left_margin", "right_margin", "top_margin", "bottom_margin"):
        setattr(sec, side, Mm(20))
    foot = sec.footer.paragraphs[0]
    foot.add_run(f"{{{{ {C}.clause8.number }}}}    第 ")
    _fld(foot, "PAGE", "1")
    foot.add_run(" 页 共 ")
    _fld(foot, "NUMPAGES", "1")
    foot.add_run(" 页 (page of pages)")

    # clause 8 a)–l)
    _p(doc, "{%p if simulated %}")
    _p(doc, "{{ simulated_banner }}", bold=True, center=True)
    _p(doc, "{%p endif %}")
    _p(doc, f"{{{{ {C}.clause8.title }}}}", bold=True, size=18, center=True)
    _p(doc, f"{{{{ {C}.clause8.lab_name }}}}", center=True)
    _p(doc, f"{{{{ {C}.clause8.lab_address }}}}", center=True)
    _kv(doc, [
        ("证书编号 Certificate number", f"{{{{ {C}.clause8.number }}}}"),
        ("送校单位 Customer", f"{{{{ {C}.clause8.customer }}}}"),
        ("送校单位地址 Customer address", f"{{{{ {C}.clause8.customer_address }}}}"),
        ("被校对象 Item", f"{{{{ {C}.clause8.device_name }}}}"),
        ("制造厂 Manufacturer", f"{{{{ {C}.clause8.manufacturer }}}}"),
        ("型号规格 Model", f"{{{{ {C}.clause8.model }}}}"),
        ("编号 Serial number", f"{{{{ {C}.clause8.serial }}}}"),
        ("接收日期 Date received", f"{{{{ {C}.clause8.received }}}}"),
        ("校准日期 Date of calibration", f"{{{{ {C}.clause8.calibrated }}}}"),
        ("校准依据 Specification", "JJF 2003—2022 微惯性测量组合 (MIMU) 校准规范"),
        ("环境条件 Environment", "{% for e in environment %}{{ e.name }}: {{ e.value }}; {% endfor %}"),
    ])
    _p(doc, "本次校准所用测量标准 Measurement standards used", bold=True)
    _loop_table(doc, ["name", "role", "serial", "accuracy / uncertainty", "certificate"],
                ["{{ s.name }}", "{{ s.role }}", "{{ s.serial }}", "{{ s.accuracy }}", "{{ s.certificate }}"],
                f"s in {C}.clause8.standards")
    _kv(doc, [
        ("签发人 Issued by (signature, title)", f"{{{{ {C}.clause8.issuer }}}}, {{{{ {C}.clause8.issuer_title }}}}"),
        ("签发日期 Date of issue", f"{{{{ {C}.clause8.issued }}}}"),
        ("校准员 Calibrated by", f"{{{{ {C}.clause8.operator }}}}"),
        ("核验员 Checked by", f"{{{{ {C}.clause8.checker }}}}"),
        ("校准专用章 Calibration seal", ""),
    ])
    doc.add_page_break()

    # appendix B inner page
    _p(doc, "MIMU 校准结果 Calibration results", bold=True, size=14, center=True)
    _result_rows(doc, "scale_factors", "1. 标度因数 Scale factors")
    _result_rows(doc, "biases", "2. 零偏 Biases")
    _result_rows(doc, "gyro_cross", "3. 陀螺交叉耦合系数 Gyro cross-coupling")
    _matrix(doc, "K_g", "3a. 陀螺标度因数矩阵 K̄_g", "K̄_g")
    _result_rows(doc, "accel_cross", "4. 加速度计交叉耦合系数 Accelerometer cross-coupling")
    _matrix(doc, "K_a", "4a. 加速度计标度因数矩阵 K_a", "K_a")
    _matrix(doc, "g", "5. 陀螺加速度敏感系数 (g)", "g")
    _matrix(doc, "p", "6. 加速度计角速度灵敏系数 (p)", "p")
    _p(doc, "{%p if " + f"{C}.notes" + " %}")
    _p(doc, "Deviations and notes", bold=True)
    _p(doc, "{%p for n in " + f"{C}.notes" + " %}")
    _p(doc, "{{ n }}")
    _p(doc, "{%p endfor %}")
    _p(doc, "{%p endif %}")
    _p(doc, "测量不确定度: U = k·u_c, k = 2 (JJF 2003 appendix A), rounded up to two significant digits.")
    _p(doc, "建议复校时间间隔 1 年 (clause 9).")

    cp = doc.core_properties
    cp.author = cp.last_modified_by = "metro"
    cp.title = "JJF 2003—2022 calibration certificate template"
    cp.created = cp.modified = dt.datetime(2026, 1, 1)
    cp.revision = 1
    return doc


def _deterministic(data: bytes) -> bytes:
    src = zipfile.ZipFile(io.BytesIO(data))
    out = io.BytesIO()
    with zipfile.ZipFile(out, "w", zipfile.ZIP_DEFLATED) as z:
        for info in sorted(src.infolist(), key=lambda i: i.filename):
            zi = zipfile.ZipInfo(info.filename, date_time=(2026, 1, 1, 0, 0, 0))
            zi.compress_type = zipfile.ZIP_DEFLATED
            z.writestr(zi, src.read(info.filename))
    return out.getvalue()


def main(argv: list[str]) -> None:
    target = Path(argv[0]) if argv else OUT
    buf = io.BytesIO()
    build().save(buf)
    target.write_bytes(_deterministic(buf.getvalue()))


if __name__ == "__main__":
    main(sys.argv[1:])

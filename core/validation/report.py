"""The software validation report (ISO/IEC 17025 §7.11.2): a Word document built with metro's
document builder (:class:`metro.core.documents.builder.DocumentBuilder`), and its PDF through
LibreOffice (:mod:`metro.core.documents.pdf`).

It gives the lab's identity (from its profile), the summary and overall verdict, the software
and platform the cases ran on, every case (its source, and per value the reference, tolerance,
result and verdict), and in an annex the SHA-256 of every installed file of metro and its
plugins.  Labels come in the lab's language(s): ``zh``, ``en`` or ``zh+en``.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Any, Iterable, Sequence

if TYPE_CHECKING:  # pragma: no cover
    from ..base.locale import Translator
    from ..documents.builder import DocumentBuilder
    from .case import ValidationCase
    from .suite import ValidationRun

__all__ = ["LABELS", "value_text", "write_validation_report"]

#: the report's labels, one a line: key | Chinese | English
_LABEL_LINES = """
title | 软件确认报告 | Software validation report
subtitle | 依据 ISO/IEC 17025:2017 7.11.2 | ISO/IEC 17025:2017 clause 7.11.2
lab | 实验室 | Laboratory
address | 地址 | Address
accreditation | 认可 | Accreditation
number | 报告编号 | Report number
date | 确认日期 | Date of validation
mode | 范围 | Scope
full | 全部案例 | every case
quick | 快速（--quick） | quick cases (--quick)
cases | 案例 | Cases
counts | 通过 / 不通过 / 出错 | passed / failed / errors
overall | 总结论 | Overall verdict
duration | 用时 | Duration
summary | 1 概述 | 1 Summary
method | 2 方法 | 2 Method
software | 3 软件与平台 | 3 Software and platform
results | 4 案例结果 | 4 Results of the cases
annex | 附录 A 已安装文件的 SHA-256 | Annex A SHA-256 of the installed files
python | Python | Python
platform | 平台 | Platform
plugin | 插件 | Plugin
plugins_of | 来源插件 | Contributed by
quantity | 量 | Quantity
reference | 参考值 | Reference
computed | 计算值 | Result
tolerance | 容差 | Tolerance
verdict | 结论 | Verdict
source | 来源 | Source
file | 文件 | File
pass | 通过 | pass
fail | 不通过 | FAIL
error | 出错 | ERROR
validated | 已确认：全部案例通过 | validated: every case passed
not_validated | 未确认：有案例未通过 | NOT validated: a case did not pass
metro_cases | metro 自身 | metro itself
footer | metro validate | metro validate
not_registered | 未登记（无实验室配置） | not registered (no lab profile)
"""

#: the report's labels: key → (Chinese, English)
LABELS: dict[str, tuple[str, str]] = {
    k: (zh, en) for k, zh, en in (ln.split(" | ") for ln in _LABEL_LINES.strip().splitlines())
}
LABELS["method_text"] = (
    "每个案例用所安装的 metro 及其插件计算已发表的算例或参考数据，并在所述容差内与发表值比较："
    "文本（标准中印出的数）须逐位相同，"
    "数值须满足 |计算值 − 参考值| ≤ 绝对容差 + 相对容差·|参考值|。全部案例通过时软件视为已确认。",
    "Each case computes a published worked example or reference data set with the installed "
    "metro and its plugins and compares the result with the published values at the tolerance "
    "stated: text (a value as the standard prints it) must agree digit for digit, numbers within "
    "|computed − reference| ≤ absolute tolerance + relative tolerance · |reference|. The "
    "software is validated when every case passes.")
LABELS["annex_text"] = ("metro 及其插件的每个已安装文件（编译缓存除外）。",
                        "Every installed file of metro and its plugins (compiled caches left out).")


def _say(tr: "Translator", key: str) -> str:
    zh, en = LABELS[key]
    return tr.pick(zh, en)


#: the tolerance's words in Chinese (a zh report)
TOLERANCE_ZH = (("exact (as printed)", "逐位相同（按印出值）"), (" relative", " 相对"),
                (" absolute, per value", " 绝对，逐值"), (" absolute", " 绝对"))


def _tolerance(tr: "Translator", text: str) -> str:
    if tr.lang != "zh":
        return text
    for en, zh in TOLERANCE_ZH:
        text = text.replace(en, zh)
    return text


def value_text(v: Any) -> str:
    """A value as the report prints it: text as it is, numbers to 10 significant digits."""
    if isinstance(v, str):
        return v
    if v is None or (isinstance(v, float) and math.isnan(v)):
        return "—"
    return f"{v:.10g}"


def _identity(b: "DocumentBuilder", tr: "Translator", lab: Any, number: str,
              run: "ValidationRun") -> None:
    counts = run.counts()
    pairs = []
    if lab is not None:
        pairs.append((_say(tr, "lab"), tr.pick(lab.name_zh or lab.name_en,
                                               lab.name_en or lab.name_zh)))
        if lab.address:
            pairs.append((_say(tr, "address"), lab.address))
        if lab.accreditation_body or lab.accreditation_number:
            pairs.append((_say(tr, "accreditation"),
                          f"{lab.accreditation_body} {lab.accreditation_number}".strip()))
    pairs += [
        (_say(tr, "number"), number),
        (_say(tr, "date"), run.started.strftime("%Y-%m-%d %H:%M UTC")),
        (_say(tr, "mode"), _say(tr, "quick" if run.quick else "full")),
        (_say(tr, "cases"), str(len(run.cases))),
        (_say(tr, "counts"), f"{counts['pass']} / {counts['fail']} / {counts['error']}"),
        (_say(tr, "duration"), f"{run.seconds:.0f} s"),
        (_say(tr, "overall"), _say(tr, "validated" if run.passed else "not_validated")),
    ]
    b.kv(pairs)


def _software(b: "DocumentBuilder", tr: "Translator", env: dict[str, Any]) -> None:
    pairs = [("metro", env["metro"])]
    pairs += [(f"{_say(tr, 'plugin')} {name}", v) for name, v in env["plugins"].items()]
    pairs.append((_say(tr, "python"), env["python"]))
    pairs += [(name, v) for name, v in env["libraries"].items()]
    pairs.append((_say(tr, "platform"), f"{env['platform']} ({env['machine']})"))
    b.kv(pairs)


def _case_rows(tr: "Translator", cases: Sequence["ValidationCase"]) -> tuple[list, list, list]:
    """Rows of the results table: per case a spanning title row (id, title, source), then one row
    per value (quantity, reference, result, tolerance, verdict)."""
    rows: list[list[str]] = []
    spans, shade = [], []
    for c in cases:
        spans.append(len(rows))
        rows.append([f"{c.id} — {c.title}. {_say(tr, 'source')}: {c.source}"])
        unit = f" ({c.unit})" if c.unit else ""
        computed = c.computed or ()
        for i, ref in enumerate(c.reference):
            got = computed[i] if i < len(computed) else None
            ok = got is not None and c.verdict != "error" and (not c.detail or f"{c.label(i)}:"
                                                               not in c.detail)
            verdict = _say(tr, "pass" if ok else ("error" if c.verdict == "error" else "fail"))
            tol = c.tolerance if not isinstance(c.atol, tuple) else f"±{c.atol_of(i):.3g}"
            rows.append([c.label(i) + unit, value_text(ref), value_text(got), _tolerance(tr, tol),
                         verdict])
        if c.verdict == "error" or not c.reference:
            shade.append(len(rows))
            rows.append([f"{_say(tr, 'error')}: {c.detail}", "", "", "", _say(tr, "error")])
    return rows, spans, shade


def _results(b: "DocumentBuilder", tr: "Translator", run: "ValidationRun") -> None:
    header = [_say(tr, k) for k in ("quantity", "reference", "computed", "tolerance", "verdict")]
    groups: dict[str, list] = {}
    for c in run.cases:
        groups.setdefault(c.plugin, []).append(c)
    for n, (plugin, cases) in enumerate(groups.items(), 1):
        name = _say(tr, "metro_cases") if plugin == "metro" else f"{_say(tr, 'plugin')} {plugin}"
        b.heading(f"4.{n} {name}", level=2)
        rows, spans, shade = _case_rows(tr, cases)
        b.table(header, rows, spans=spans, bold_rows=spans, shade=shade, font_pt=7.5, prefer=0)


def _annex(b: "DocumentBuilder", tr: "Translator", files: Iterable[dict[str, str]]) -> None:
    b.page_break()
    b.heading(_say(tr, "annex"), level=1)
    b.para(_say(tr, "annex_text"), size=8.5)
    rows = [[f["path"], f["sha256"]] for f in files]
    b.table([_say(tr, "file"), "SHA-256"], rows, font_pt=6.5)


def build_document(run: "ValidationRun", *, number: str, lang: str, lab: Any = None
                   ) -> "DocumentBuilder":
    """The report as a :class:`DocumentBuilder` (not yet saved)."""
    from ..base.locale import translator
    from ..documents.builder import DocumentBuilder

    tr = translator(lang)
    b = DocumentBuilder(number=number, title=_say(tr, "title"), tr=tr,
                        footer=f"metro {run.environment['metro']} · {_say(tr, 'footer')}")
    if lab is not None and getattr(lab, "logo", None):
        b.logo = Path(lab.logo).read_bytes()
    b.title_block(_say(tr, "title"), _say(tr, "subtitle"))
    b.heading(_say(tr, "summary"), level=1)
    _identity(b, tr, lab, number, run)
    b.heading(_say(tr, "method"), level=1)
    b.para(_say(tr, "method_text"))
    b.heading(_say(tr, "software"), level=1)
    _software(b, tr, run.environment)
    b.heading(_say(tr, "results"), level=1)
    _results(b, tr, run)
    _annex(b, tr, run.files)
    return b


def write_validation_report(path: str | Path, run: "ValidationRun", *, number: str,
                            lang: str = "zh+en", lab: Any = None) -> Path:
    """Write the report (.docx) to ``path``; returns the path."""
    path = Path(path)
    build_document(run, number=number, lang=lang, lab=lab).save(path)
    return path

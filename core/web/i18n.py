"""The words of the web pages in Chinese and English (``zh``/``en``); the language a request
gets: ``?lang=``, else the ``metro_lang`` cookie, else the lab's default language."""

from __future__ import annotations

from typing import Mapping

__all__ = ["LANGS", "COOKIE", "WORDS", "words", "default_lang", "pick_lang"]

LANGS = ("zh", "en")
#: the cookie that remembers a reader's choice of language
COOKIE = "metro_lang"

#: label → (zh, en)
WORDS: dict[str, tuple[str, str]] = {
    "title": ("报告登记簿", "Report register"),
    "reports": ("报告", "Reports"),
    "equipment": ("设备", "Equipment"),
    "verify": ("证书核验", "Certificate verification"),
    "number": ("编号", "Number"),
    "status": ("状态", "Status"),
    "standard": ("标准", "Standard"),
    "items_label": ("项目", "Items"),
    "device": ("被测设备", "Device"),
    "serial": ("序列号", "Serial"),
    "customer": ("委托方", "Customer"),
    "measured": ("测量日期", "Measured"),
    "issued": ("签发", "Issued"),
    "issued_by": ("签发人", "Issued by"),
    "from": ("自", "From"),
    "to": ("至", "To"),
    "any": ("全部", "any"),
    "filter": ("筛选", "Filter"),
    "clear_filters": ("清除", "Clear"),
    "count": ("共 {n} 份报告", "{n} reports"),
    "page": ("第 {page} / {pages} 页", "page {page} of {pages}"),
    "prev": ("上一页", "Previous"),
    "next": ("下一页", "Next"),
    "none": ("没有符合条件的报告。", "No report matches."),
    "st_issued": ("有效", "issued"),
    "st_superseded": ("已被替代", "superseded"),
    "st_withdrawn": ("已撤回", "withdrawn"),
    "chain": ("修订链", "Amendment chain"),
    "supersedes": ("替代", "replaces"),
    "superseded_by": ("被替代为", "replaced by"),
    "reason": ("原因", "reason"),
    "results": ("结果", "Results"),
    "quantity": ("量", "Quantity"),
    "value": ("值", "Value"),
    "unit": ("单位", "Unit"),
    "verdict": ("判定", "Verdict"),
    "v_pass": ("符合", "conforms"),
    "v_fail": ("不符合", "does not conform"),
    "v_indeterminate": ("不确定", "indeterminate"),
    "not_reportable": ("不报告", "not reported"),
    "conformity": ("符合性声明", "Statement of conformity"),
    "rule": ("判定规则", "Decision rule"),
    "overall": ("总体判定", "Overall verdict"),
    "no_conformity": ("未给出技术指标：本报告不作符合性声明。",
                      "No specification was given: this report makes no statement of conformity."),
    "eq_used": ("所用设备（测量日期时的状态）", "Equipment used (status on the measurement date)"),
    "certificate": ("证书", "Certificate"),
    "due": ("有效期至", "Due"),
    "role": ("用途", "Role"),
    "downloads": ("下载", "Downloads"),
    "docx": ("Word 报告", "Word report"),
    "pdf": ("PDF 报告", "PDF report"),
    "dcc": ("数字校准证书 (DCC)", "Digital calibration certificate (DCC)"),
    "no_file": ("无", "none"),
    "history": ("设备历史", "Device history"),
    "calibrations": ("校准记录", "Calibrations"),
    "drift": ("漂移", "drift"),
    "drift_note": ("|E_n| > 1 标为漂移（与上一次校准比较）。",
                   "|E_n| > 1 is flagged as drift (against the previous calibration)."),
    "no_history": ("该序列号没有有效报告。", "No issued report for this serial."),
    "plot": ("历史曲线", "History plot"),
    "lab_equipment": ("实验室设备", "The lab's equipment"),
    "due_soon": ("30 天内到期", "Due within 30 days"),
    "expired": ("已过期", "expired"),
    "ok": ("有效", "valid"),
    "no_lab": ("没有实验室配置文件：没有设备清单。", "No lab profile: no equipment list."),
    "nothing_due": ("30 天内没有到期的设备。", "Nothing falls due in the next 30 days."),
    "as_of": ("状态日期：", "Status as of"),
    "verify_issued": ("报告 {number} 已签发，有效。", "Report {number} is issued and valid."),
    "verify_superseded": ("报告 {number} 已被替代。", "Report {number} has been superseded."),
    "verify_withdrawn": ("报告 {number} 已撤回。", "Report {number} has been withdrawn."),
    "verify_unknown": ("登记簿中没有报告 {number}。", "Report {number} is not in the register."),
    "replaced_by_report": ("替代它的报告：", "Replaced by report "),
    "upload_title": ("核对文件", "Check a file"),
    "upload_help": ("选择您收到的文件（Word、DCC），核对其 SHA-256 与登记簿是否一致。",
                    "Choose the file you received (Word, DCC) to compare its SHA-256 with the "
                    "register."),
    "upload": ("核对", "Check"),
    "matches": ("一致：该文件与登记簿中的 {file} 相符。",
                "matches: this file is the registered {file}."),
    "no_match": ("不一致：该文件与登记簿中的文件不符。",
                 "does not match: this file is not the one in the register."),
    "no_upload": ("没有收到文件。", "No file was received."),
    "error": ("错误", "Error"),
    "not_found": ("未找到", "Not found"),
    "file_changed": ("文件与登记簿中的 SHA-256 不符，不予提供。",
                     "The file does not match its SHA-256 in the register; it is not served."),
    "file_missing": ("登记簿中的文件不存在。", "The registered file is missing."),
    "simulated": ("仿真", "simulated"),
    "language": ("语言", "Language"),
}


def words(lang: str) -> dict[str, str]:
    """Every label in ``lang`` (``zh`` or ``en``)."""
    i = 0 if lang == "zh" else 1
    return {k: v[i] for k, v in WORDS.items()}


def default_lang(lab_language: str | None) -> str:
    """The lab's default language for pages: ``zh`` for ``zh`` and ``zh+en``, ``en`` for ``en``;
    Chinese without a lab profile (a profile's own default)."""
    return "en" if (lab_language or "zh").split("+")[0] == "en" else "zh"


def pick_lang(query: Mapping[str, str], cookies: Mapping[str, str], default: str) -> str:
    """``?lang=`` when it names a language, else the cookie's, else ``default``."""
    for cand in (query.get("lang"), cookies.get(COOKIE)):
        if cand in LANGS:
            return cand
    return default

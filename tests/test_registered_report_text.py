"""A registered report says what the unregistered one says, in the same languages.

Issue 29: in zh+en the registered report printed English-only quantity names, notes and budget
rows, because the report number was substituted through the context as plain strings, which
dropped every translatable text's Chinese (core/registering.py).  Here the same simulated campaign
(same seed) is written unregistered (a lab profile, simulated run) and registered
(``--register-simulated``), and then amended from the register; each PDF that LibreOffice renders is
read with pdftotext.  Apart from the report number and the registration statements at the top, the
three say the same: the lines only one of two documents has (those around the number and the
statements, which break where the number's length puts them) hold the same characters once the
statements are taken out — in particular the same Chinese.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from collections import Counter
from pathlib import Path
from types import SimpleNamespace

import pytest

from metro.core.cli import main

pytestmark = pytest.mark.skipif(
    not (shutil.which("soffice") or shutil.which("libreoffice")) or not shutil.which("pdftotext"),
    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and read the PDF",
)

RUN = ["run", "-s", "gbt45570", "-i", "D.5.1,D.5.2,D.5.6", "--station-option", "duration_scale=0.05",
       "--seed", "1", "--no-progress", "--pdf", "-q"]
_HAN = re.compile(r"[\u3400-\u9fff]")


def _pdf_text(pdf: Path) -> str:
    return subprocess.run(["pdftotext", "-layout", "-enc", "UTF-8", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout


def _squash(text: str) -> str:
    return re.sub(r"[\s\-\u00ad]", "", text)


#: the page numbers (a longer statement at the top may add a page)
_PAGE = re.compile(r"第\s*\d+\s*页\s*共\s*\d+\s*页|Page\s+\d+\s+of\s+\d+")


def _lines(text: str, number: str) -> set[str]:
    """The document's distinct lines (pdftotext -layout, spaces collapsed), the report number as one
    token, page numbers left out: a table header repeated on each page counts once."""
    return {re.sub(r"\s+", " ", _PAGE.sub("", ln.replace(number, "\x00"))).strip() for ln in text.splitlines()} - {""}


def _difference(a: tuple[str, str, list[str]], b: tuple[str, str, list[str]]) -> tuple[Counter, Counter]:
    """The characters of the lines only ``a`` has and of those only ``b`` has, each without its
    registration statements (``(text, number, statements)``): the same when the two documents say the
    same apart from the number and the statements, however the lines around those break."""
    la, lb = _lines(a[0], a[1]), _lines(b[0], b[1])
    out = []
    for only, (_, number, notices) in ((la - lb, a), (lb - la, b)):
        chars = Counter(_squash("".join(only)))
        for n in notices:
            note = Counter(_squash(n.replace(number, "\x00")))
            assert not note - chars, f"statement not printed whole: {n}"
            chars -= note
        out.append(chars)
    return out[0], out[1]


def _report(folder: Path) -> tuple[Path, str]:
    pdf = next(folder.glob("*.pdf"))
    return pdf, pdf.stem


@pytest.fixture
def lab(tmp_path, monkeypatch, capsys):
    path = tmp_path / "lab.toml"
    assert main(["lab", "init", str(path)]) == 0
    capsys.readouterr()
    monkeypatch.setenv("METRO_LAB", str(path))
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    return path


def test_registered_and_amended_reports_keep_both_languages(lab, tmp_path, capsys):
    from metro.core.document import to_pdf
    from metro.core.lab import load_lab
    from metro.core.registering import notices_for, unregistered

    profile = load_lab(lab)
    assert profile.language == "zh+en"
    assert main([*RUN, "--out", str(tmp_path / "plain")]) in (0, 3, 4)
    assert main([*RUN, "--out", str(tmp_path / "reg"), "--register-simulated"]) in (0, 3, 4)
    capsys.readouterr()
    plain_pdf, plain_no = _report(tmp_path / "plain")
    reg_pdf, reg_no = _report(tmp_path / "reg")
    assert plain_no.startswith("MTR-") and reg_no.startswith("EML")

    plain_notes = unregistered(SimpleNamespace(report_number=plain_no), "simulated", "zh+en")["notices"]
    plain = (_pdf_text(plain_pdf), plain_no, plain_notes)
    assert len(_HAN.findall(plain[0])) > 1000  # the document is bilingual
    only_plain, only_reg = _difference(plain, (_pdf_text(reg_pdf), reg_no, notices_for(profile, reg_no)))
    han = lambda c: {k: v for k, v in c.items() if _HAN.match(k)}  # noqa: E731
    assert han(only_reg) == han(only_plain), "registered report lost or gained Chinese"
    assert only_reg == only_plain

    # an amendment from the register's stored content: the same text again
    reason = "the customer's name corrected"
    assert main(["amend", reg_no, "--reason", reason, "--out", str(tmp_path / "amend")]) == 0
    capsys.readouterr()
    docx = next((tmp_path / "amend").glob("*.docx"))
    to_pdf(docx, docx.with_suffix(".pdf"))
    amend_no = docx.stem
    assert amend_no != reg_no
    amended = (_pdf_text(docx.with_suffix(".pdf")).replace(reg_no, amend_no), amend_no,
               notices_for(profile, amend_no, supersedes=amend_no, reason=reason))
    only_plain, only_amended = _difference(plain, amended)
    assert han(only_amended) == han(only_plain), "amended report lost or gained Chinese"
    assert only_amended == only_plain

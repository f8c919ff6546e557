"""A registered report says what the unregistered one says, in the same languages.

Issue 29: in zh+en the registered report printed English-only quantity names, notes and budget
rows, because the report number was substituted through the context as plain strings, which
dropped every translatable text's Chinese (core/registering.py).  Here the same simulated campaign
(same seed) is written unregistered (a lab profile, simulated run) and registered
(``--register-simulated``), and then amended from the register; each PDF that LibreOffice renders is
read with pdftotext.  Apart from the report number and the registration statements at the top, the
three carry the same characters (compared as a multiset, so that line breaks, which move with the
number's length, do not matter) — in particular the same Chinese.
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
    return subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout


def _squash(text: str) -> str:
    return re.sub(r"[\s\-\u00ad]", "", text)


def _header_cells(docx_path: Path) -> list[str]:
    """The texts of the cells of table header rows, which repeat on each page a table runs onto
    (how often depends on where the pages break, which moves with the statements' length)."""
    import docx

    out = set()
    for table in docx.Document(str(docx_path)).tables:
        for row in table.rows:
            if row._tr.trPr is not None and row._tr.trPr.find(
                    "{http://schemas.openxmlformats.org/wordprocessingml/2006/main}tblHeader") is not None:
                out.update(_squash(c.text) for c in row.cells if _squash(c.text))
    return sorted(out, key=len, reverse=True)


def _characters(text: str, number: str, notices: list[str], headers: list[str]) -> Counter:
    """The characters of ``text`` (no white space, no hyphens a line break may add) with the report
    number as one token, the registration statements and the repeated table headers taken out."""
    def squash(t: str) -> str:
        return _squash(t.replace(number, "\x00"))

    body = squash(text)
    for h in headers:
        body = body.replace(h, "")
    out = Counter(body)
    for n in notices:
        note = Counter(squash(n))
        assert not note - out, f"statement not printed whole: {n}"
        out -= note
    del out["\x00"]
    return out


def _report(folder: Path) -> tuple[Path, str]:
    pdf = next(folder.glob("*.pdf"))
    return pdf, pdf.stem


def _headers(*folders: Path) -> list[str]:
    cells = {h for f in folders for h in _header_cells(next(f.glob("*.docx")))}
    return sorted(cells, key=len, reverse=True)


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
    headers = _headers(tmp_path / "plain", tmp_path / "reg")
    plain = _characters(_pdf_text(plain_pdf), plain_no, plain_notes, headers)
    reg = _characters(_pdf_text(reg_pdf), reg_no, notices_for(profile, reg_no), headers)
    assert sum(v for c, v in plain.items() if _HAN.match(c)) > 1000  # the document is bilingual
    han = lambda c: {k: v for k, v in c.items() if _HAN.match(k)}  # noqa: E731
    assert han(reg) == han(plain), "registered report lost or gained Chinese"
    assert reg == plain

    # an amendment from the register's stored content: the same text again
    reason = "the customer's name corrected"
    assert main(["amend", reg_no, "--reason", reason, "--out", str(tmp_path / "amend")]) == 0
    capsys.readouterr()
    docx = next((tmp_path / "amend").glob("*.docx"))
    to_pdf(docx, docx.with_suffix(".pdf"))
    amend_no = docx.stem
    assert amend_no != reg_no
    text = _pdf_text(docx.with_suffix(".pdf"))
    amended = _characters(text.replace(reg_no, amend_no), amend_no,
                          notices_for(profile, amend_no, supersedes=amend_no, reason=reason), headers)
    assert han(amended) == han(plain), "amended report lost or gained Chinese"
    assert amended == plain

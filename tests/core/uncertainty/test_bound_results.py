"""A result that bounds its quantity (``Result.bound``: D.4's threshold ≤ H when nothing below H is
resolved, a megohmmeter over its range) is issued as the bound: the terminal, the document's
results table and the GB/T limit table print "≤ value" / "≥ value" with its U and why it is a bound,
never "not reportable" beside a verdict that conforms, and the reason carries no software hint."""

from __future__ import annotations

import shutil
import subprocess

import pytest

from metro.core.model.results import BOUND_SIGNS


def test_signs():
    assert BOUND_SIGNS == {"lower": "≥", "upper": "≤"}


def test_terminal_states_the_bound(run_cli):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.4", "--no-report", "--no-progress")
    assert code == 0, err
    flat = " ".join(out.split())
    assert "≤ 0.0" in flat and "a bound:" in flat and "stated as at most" in flat
    assert "NOT REPORTABLE" not in out + err and "not reportable:" not in flat
    assert "conforms" in flat


@pytest.mark.skipif(not (shutil.which("soffice") or shutil.which("libreoffice")) or
                    not shutil.which("pdftotext"),
                    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and "
                    "read the PDF")
def test_document_states_the_bound(run_cli, tmp_path):
    out = tmp_path / "out"
    code, _, err = run_cli("run", "-s", "gbt45570", "-i", "D.4", "--out", str(out), "--pdf",
                           "--no-progress")
    assert code == 0, err
    (pdf,) = out.glob("*.pdf")
    text = subprocess.run(["pdftotext", "-layout", str(pdf), "-"], capture_output=True, text=True,
                          check=True).stdout
    flat = " ".join(text.split())
    squashed = "".join(text.split())  # Chinese wraps anywhere in a cell
    assert "不予报告" not in squashed and "not reportable" not in flat
    assert "（界限值：" in squashed and "(a bound: " in flat and "故阈值表述为不大于" in squashed
    # the results table and the A.1 table both print the bound with its U
    assert flat.count("≤ 0.0") >= 3  # results (zh, en) and the limit table's result cell
    assert "U = " in flat.split("(a bound: ")[1]
    # no software syntax on the certificate
    assert "option seconds" not in flat and "选项seconds" not in squashed

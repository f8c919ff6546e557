"""A registered report says what the unregistered one says, in the same languages.

Issue 29: in zh+en the registered report printed English-only quantity names, notes and budget rows,
because the report number was substituted through the context as plain strings, which dropped every
translatable text's Chinese (core/record/registering.py). Here the same simulated campaign (same
seed) is written unregistered (a lab profile, simulated run) and registered
(``--register-simulated``), and then amended from the register; each PDF that LibreOffice renders is
read with pdftotext. Apart from the report number and the registration statements at the top, the
three say the same: the lines only one of two documents has (those around the number and the
statements, which break where the number's length puts them) hold the same characters once the
statements are taken out — in particular the same Chinese.

pdftotext does not read a figure's pixels: the figures are compared by the texts they draw (title,
axis labels, legend entries, in zh+en, zh and en) from the specs the documents are drawn from.
"""

from __future__ import annotations

import re
import shutil
import subprocess
from collections import Counter
from pathlib import Path
from types import SimpleNamespace

import pytest

from metro.core.cli.app import main

needs_pdf = pytest.mark.skipif(
    not (shutil.which("soffice") or shutil.which("libreoffice")) or not shutil.which("pdftotext"),
    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and read the PDF",
)

RUN = ["run", "-s", "gbt45570", "-i", "D.5.1,D.5.2,D.5.6", "--station-option",
       "duration_scale=0.05",
       "--seed", "1", "--no-progress", "--pdf", "-q"]
_HAN = re.compile(r"[\u3400-\u9fff]")


def _pdf_text(pdf: Path) -> str:
    return subprocess.run(["pdftotext", "-layout", "-enc", "UTF-8", str(pdf), "-"],
                          capture_output=True, text=True,
                          check=True).stdout


def _squash(text: str) -> str:
    return re.sub(r"[\s\-\u00ad]", "", text)


#: the page numbers (a longer statement at the top may add a page), and the clock times of the
#: two runs (the report's issue time: a slow machine may run them in different minutes)
_PAGE = (
    re.compile(r"第\s*\d+\s*页\s*共\s*\d+\s*页|Page\s+\d+\s+of\s+\d+|\b\d{1,2}:\d{2}(?::\d{2})?\b")
)


def _lines(text: str, number: str) -> set[str]:
    """The document's distinct lines (pdftotext -layout, spaces collapsed), the report number as one
    token, page numbers left out: a table header repeated on each page counts once."""
    return {re.sub(r"\s+", " ", _PAGE.sub("", ln.replace(number, "\x00"))).strip() for ln
            in text.splitlines()} - {""}


def _difference(a: tuple[str, str, list[str]],
                b: tuple[str, str, list[str]]) -> tuple[Counter, Counter]:
    """The characters of the lines only ``a`` has and of those only ``b`` has, each without its
    registration statements (``(text, number, statements)``): the same when the two documents say
    the same apart from the number and the statements, however the lines around those break."""
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


@needs_pdf
def test_registered_and_amended_reports_keep_both_languages(lab, tmp_path, capsys):
    from metro.core.documents.pdf import to_pdf
    from metro.core.record.lab import load_lab
    from metro.core.record.registering import notices_for, unregistered

    profile = load_lab(lab)
    assert profile.language == "zh+en"
    assert main([*RUN, "--out", str(tmp_path / "plain")]) in (0, 3, 4)
    assert main([*RUN, "--out", str(tmp_path / "reg"), "--register-simulated"]) in (0, 3, 4)
    capsys.readouterr()
    plain_pdf, plain_no = _report(tmp_path / "plain")
    reg_pdf, reg_no = _report(tmp_path / "reg")
    assert plain_no.startswith("MTR-") and reg_no.startswith("EML")

    plain_notes = unregistered(SimpleNamespace(report_number=plain_no), "simulated",
                               "zh+en")["notices"]
    plain = (_pdf_text(plain_pdf), plain_no, plain_notes)
    assert len(_HAN.findall(plain[0])) > 1000  # the document is bilingual
    only_plain, only_reg = _difference(plain, (_pdf_text(reg_pdf), reg_no,
                                               notices_for(profile, reg_no)))
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


# --------------------------------------------------------------------------------------
# Figures: the texts drawn inside them (pdftotext does not read a figure's pixels)
# --------------------------------------------------------------------------------------

#: GB/T D.1.5 (title: a message with the item as a field) and D.3 (legend "limit {x} ppm"), and
#: ogam 7.4 (legend "round {r}", title "Simulated tilt error, ψ = {psi:g}° …")
FIGURE_RUNS = {
    "gbt45570": ["-s", "gbt45570", "-i", "D.1.5,D.3", "--station-option", "duration_scale=0.05"],
    "ogam": ["-s", "ogam", "-i", "7.4"],
}


def _drawn(spec, lang: str) -> tuple:
    """What a figure draws in ``lang``: its title, axis labels, and each series' legend entry and
    points (:func:`metro.core.documents.plots.localized`, the spec the figure is drawn from)."""
    import numpy as np

    from metro.core.documents import plots
    from metro.core.base.locale import translator

    s = plots.localized(spec, translator(lang))
    series = tuple((str(x.get("label") or ""), str(x.get("style") or ""),
                    tuple(np.round(np.asarray(getattr(x["x"], "magnitude", x["x"]), dtype=float),
                                   9)),
                    tuple(np.round(np.asarray(getattr(x["y"], "magnitude", x["y"]), dtype=float),
                                   9)))
                   for x in s.series)
    return s.name, str(s.title), str(s.xlabel), str(s.ylabel), series, s.logx, s.logy


@pytest.fixture
def figures_drawn(monkeypatch):
    """Every figure a document draws, as (language, spec) — the spec before translation."""
    from metro.core.documents import report

    drawn: list[tuple[str, object]] = []
    draw = report.draw_figure

    def spy(spec, tr, png):
        drawn.append((tr.lang, spec))
        return draw(spec, tr, png)

    monkeypatch.setattr(report, "draw_figure", spy)
    return drawn


@pytest.mark.parametrize("standard", sorted(FIGURE_RUNS))
def test_figures_from_the_register_draw_the_texts_of_the_unregistered_report(
    standard, lab, tmp_path, capsys,
                                                                           figures_drawn):
    """Issue 29: the register's stored context (:func:`encode_context` / :func:`decode_context`)
    kept a figure's title and legend entries as English strings, so a report written again from
    the register (``metro report N``) or amended drew "Scale factor against temperature (D.1.5)"
    and "limit 10 ppm" where the unregistered report drew "标度因数随温度的变化（D.1.5） Scale
    factor against temperature (D.1.5)" and "限值 10 ppm limit 10 ppm"."""
    from metro.core.record.lab import load_lab
    from metro.core.record.register import open_register
    from metro.core.record.registering import decode_context

    run = ["run", *FIGURE_RUNS[standard], "--seed", "1", "--no-progress", "-q"]
    assert main([*run, "--out", str(tmp_path / "plain")]) in (0, 3, 4)
    plain = [spec for _, spec in figures_drawn]
    assert plain and {lang for lang, _ in figures_drawn} == {"zh+en"}
    zh_en = [_drawn(s, "zh+en") for s in plain]
    # the figures do say something in Chinese that only a message with fields carries
    wanted = {"gbt45570": ["标度因数随温度的变化（D.1.5）", "限值 10 ppm limit 10 ppm"],
              "ogam": ["倾斜误差仿真，ψ =", "第 1 轮 round 1"]}[standard]
    for w in wanted:
        assert w in repr(zh_en), (w, zh_en)

    assert main([*run, "--out", str(tmp_path / "reg"), "--register-simulated"]) in (0, 3, 4)
    _, reg_no = _report_docx(tmp_path / "reg")
    # the context the register keeps, decoded: the same figures in every language
    with open_register(load_lab(lab).register_url()) as reg:
        doc, _ = reg.context(reg_no)
    stored = [p["spec"] for o in decode_context(doc)["outcomes"] for p in o["plots"]]
    for lang in ("zh+en", "zh", "en"):
        assert [_drawn(s, lang) for s in stored] == [_drawn(s, lang) for s in plain], lang

    # the documents written from the register draw them so: `metro report N` and an amendment
    for command in (["report", reg_no, "--out", str(tmp_path / "again")],
                    ["amend", reg_no, "--reason", "the customer's name corrected", "--out",
                     str(tmp_path / "amend")]):
        figures_drawn.clear()
        assert main(command) == 0
        assert [_drawn(s, lang) for lang, s in figures_drawn] == zh_en, command[0]
    capsys.readouterr()


def _report_docx(folder: Path) -> tuple[Path, str]:
    docx = next(folder.glob("*.docx"))
    return docx, docx.stem

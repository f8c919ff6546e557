"""A certificate speaks to its reader: no program syntax on it (issue 29).

Budget sources printed literal underscores (``(s_upper − R)/2``, ``Δt_noise/2``); notes named
command options and JSON paths (``(plan with -o max_rate=…)``, ``-o earth_rate=on``, ``metro run
--json: provenance.data_files``, ``metro plan -s gbt45570 -i D.5.4``,
``device.bias_repeatability``). Symbols are now typeset as the others (``s_{upper}`` prints s with a
subscript), and advice about the software is a terminal-only field of its message
(:func:`metro.core.base.locale.hint`): the terminal and ``--json`` keep it, a document leaves it
out. Each document is rendered by LibreOffice and read with pdftotext.
"""

from __future__ import annotations

import re
import shutil
import subprocess

import pytest

from metro.core.base.locale import Text, hint, msg, translator
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.documents.report import write_report
from metro.core.run.runner import run_items

needs_office = pytest.mark.skipif(
    not (shutil.which("soffice") or shutil.which("libreoffice")) or not shutil.which("pdftotext"),
    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and read the PDF",
)

#: what program text looks like; none of it may reach a document
SOFTWARE = re.compile(r"_upper|_noise|_fixture|metro "
                      r"(run|plan|acquire)|(^|[\s(])-o\s|\s--[a-z]|provenance\.|option "
                      r"(earth_rate|scale_factor)|\[device\]|device\.[a-z]+_[a-z_]+")

# (standard, items, station options, item options, what the terminal says that the document must
# not): the items whose budgets or notes had such text
CASES = [
    ("ogam", ["7.5"], {}, {}, ["(s_{upper} − R)/2"]),
    ("jjf2014", ["7.2.4", "7.2.12", "7.2.13", "7.2.14", "7.2.15", "7.2.23"], {"seed": 3}, {},
     ["(s_{upper} − K_r)/2", "(s_{upper} − B_s)/2", "(s_{upper} − B_r)/2", "Δt_{noise}/2",
      "(-o earth_rate=on"]),
    ("gbt45570", ["D.1.4", "D.5.4"], {"seed": 3, "duration_scale": 0.2,
                                      "states_repeatability": False},
     {"repeats": "0"}, ["(s_{upper} − K_r)/2", "as metro plan -s gbt45570 -i D.5.4 lists them"]),
    ("gbt45570", ["D.2.4"], {"seed": 3}, {}, ["(s_{upper} − K_r)/2"]),
    ("gbt45570", ["D.3"], {"seed": 3}, {}, ["(plan with -o max_rate=…)"]),
    ("jjf2003", ["7.2.2"], {}, {}, ["; option earth_rate = yes removes it"]),
]


def _all_text(record) -> str:
    """Every note, warning, reason and budget source of a run as the terminal prints them
    (English)."""
    out = []
    for o in record.outcomes:
        out += [str(w) for w in o.warnings]
        for r in o.results:
            out += [str(r.note), str(r.reason)]
            if r.budget is not None:
                out += [f"{row.source} {row.symbol} {row.note or ''}" for row in r.budget.rows]
    return "\n".join(out)


@needs_office
@pytest.mark.parametrize("standard, items, station, options, said", CASES,
                         ids=[f"{c[0]}-{'-'.join(c[1])}" for c in CASES])
def test_documents_print_no_program_syntax(tmp_path, standard, items, station, options, said):
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, standard, items, station_options=station, options=options)
    terminal = _all_text(rec)
    missing = [s for s in said if s not in terminal]
    assert not missing, missing  # the run says it (so the document had it to leave out)
    for lang in ("zh+en", "en"):
        pdf = write_report(tmp_path / f"{lang}.pdf", rec, layout=pm.template_for(standard).layout,
                           extend=pm.extend_report_context, lang=lang)
        text = subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True,
                              text=True,
                              check=True).stdout
        found = sorted({m.group(0).strip() for m in SOFTWARE.finditer(text)})
        assert not found, (standard, lang, found, [ln for ln in text.splitlines()
                                                   if SOFTWARE.search(ln)][:5])
    # the symbols are there, typeset (the χ² bound of a sampled standard deviation prints s with
    # subscript upper)
    if any("s_{upper}" in s for s in said):
        assert "(supper−" in re.sub(r"\s", "", text)


def test_the_terminal_keeps_the_hint_a_document_leaves_out():
    note = msg("earth rate removed ({amount}; not in the standard){hint}", amount="Ω_e·sin φ",
               hint=hint(" (-o earth_rate=on)"))
    # terminal, --json
    assert str(note) == "earth rate removed (Ω_e·sin φ; not in the standard) (-o earth_rate=on)"
    for lang in ("en", "zh", "zh+en"):
        printed = translator(lang).text(note)
        assert "-o" not in printed and "earth_rate" not in printed, (lang, printed)
    assert translator("zh+en").text(note) == "已扣除地球自转角速度（Ω_e·sin φ；规范中无此修正） " \
                                             "earth rate removed (Ω_e·sin φ; not in the standard)"
    # kept by the register as JSON and written again: still a hint
    again = Text.decode(note.encode())
    assert str(again) == str(note) and "-o" not in translator("en").text(again)
    # the register's number substitution keeps it a hint too
    assert "-o" not in translator("en").text(note.map(lambda s: s.replace("x", "x")))

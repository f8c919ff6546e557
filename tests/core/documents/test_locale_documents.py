"""Issue 16 point 5: every string a document prints comes through the message catalog.

One full simulated run per standard (``--all``, as ``metro run -s S --all`` runs it; GB/T also a
coarse pulse device whose threshold and repeatability are not reportable, so reasons appear) is
rendered in zh, en and zh+en from the same context.  The zh document must hold no English prose:
no run of three or more purely alphabetic ASCII words outside a short allowlist; the en document
no Chinese; the zh+en document both.  The terminal's --json output stays English.
"""

from __future__ import annotations

import json
import re

import pytest

from metro.core.documents import report
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.runner import run_items

CJK = re.compile(r"[\u3000-\u303f\u4e00-\u9fff\uff00-\uffef]")
#: three or more alphabetic ASCII words in a row (spaces or no-break spaces between them), not
#: part of a file name, a path, a code key or a hyphenated word
PROSE = re.compile(r"(?<![\w./\\\-])[A-Za-z]+(?:[ \u00a0]+[A-Za-z]+){2,}(?![\w/\\\-])")
#: what may stay in English in a Chinese document: names of software and the report's identity
ALLOW = ("metro simulator",)

CASES = {
    "ogam": ("ogam", [], True, {}),
    "jjf2003": ("jjf2003", [], True, {}),
    "jjf2014": ("jjf2014", [], True, {}),
}


def _texts(doc) -> list[str]:
    """Every paragraph of the body, the tables (nested too) and the headers and footers."""
    out = []

    def tables(ts):
        for t in ts:
            for row in t.rows:
                seen = set()
                for c in row.cells:
                    if id(c._tc) in seen:
                        continue
                    seen.add(id(c._tc))
                    out.extend(p.text for p in c.paragraphs)
                    tables(c.tables)

    out.extend(p.text for p in doc.paragraphs)
    tables(doc.tables)
    for s in doc.sections:
        for part in (s.header, s.footer):
            out.extend(p.text for p in part.paragraphs)
            tables(part.tables)
    return out


def english_prose(texts: list[str]) -> list[str]:
    found = []
    for t in texts:
        for m in PROSE.finditer(t):
            if m.group().replace("\u00a0", " ") not in ALLOW:
                found.append(f"{m.group()!r} in {t[:160]!r}")
    return found


@pytest.fixture(scope="module")
def pm():
    return get_plugin_manager()


@pytest.fixture(scope="module", params=sorted(CASES))
def rendered(request, pm, tmp_path_factory):
    """One run per case; its context rendered in the three languages (figures drawn once)."""
    standard, items, run_all, so = CASES[request.param]
    rec = run_items(pm, standard, items, run_all=run_all, station_options=so)
    ctx = report.build_context(rec, extend=pm.extend_report_context)
    tmp = tmp_path_factory.mktemp(request.param)
    figures = report.render_figures(ctx, tmp)
    layout = pm.template_for(standard).layout
    docs = {}
    for lang in ("zh", "en", "zh+en"):
        doc = report.build_document(ctx, tmp, layout=layout, lang=lang, figures=figures)
        docs[lang] = (doc, _texts(doc.doc))
    return request.param, rec, docs


def test_a_chinese_document_has_no_english_prose(rendered):
    case, _rec, docs = rendered
    doc, texts = docs["zh"]
    assert not doc.tr.missing, sorted(doc.tr.missing)
    bad = english_prose(texts)
    assert not bad, f"{case}: {len(bad)} English runs, e.g.\n" + "\n".join(bad[:15])


def test_the_figures_of_a_chinese_document_draw_no_english_prose(rendered):
    """The words drawn inside the figures (title, axis labels, legend entries) are the document's
    language too: a legend made as plain English text ("pure delay −ωT_d", "least-squares line,
    slope …", "1 s mean", "band") was drawn in English in every language."""
    from metro.core.documents import plots
    from metro.core.base.locale import translator

    case, rec, _docs = rendered
    tr = translator("zh")
    specs = [plots.localized(p, tr) for o in rec.outcomes for p in o.plots]
    assert specs, case
    drawn = [str(t) for s in specs for t in (s.title, s.xlabel, s.ylabel,
                                             *(x.get("label") or "" for x in s.series))]
    bad = english_prose(drawn)
    assert not bad, f"{case}: {len(bad)} English runs in figures, e.g.\n" + "\n".join(bad[:15])


def test_an_english_document_has_no_chinese(rendered):
    case, _rec, docs = rendered
    _doc, texts = docs["en"]
    bad = [t for t in texts if CJK.search(t)]
    assert not bad, f"{case}: {bad[:10]}"


def test_a_bilingual_document_has_both_and_every_note_in_both(rendered):
    case, rec, docs = rendered
    _doc, texts = docs["zh+en"]
    text = "\n".join(texts).replace("\u00a0", " ")
    assert CJK.search(text) and english_prose(texts)
    zh_text = "\n".join(docs["zh"][1]).replace("\u00a0", " ")
    # a note of the run (a message): its Chinese in the zh document, its English in the zh+en one
    from metro.core.documents.text import glue, subscript_runs
    from metro.core.base.locale import translator

    def printed(s: str) -> str:  # as a document's text reads it: no-break spaces, real subscripts
        s = glue(s).replace("\u00a0", " ").replace("\u2060", "")
        return "\n".join("".join(p for p, _ in subscript_runs(line)) for line in s.split("\n"))

    note = next(r.note for o in rec.outcomes for r in o.results if r.note
                and getattr(r.note, "msgid", None))
    assert printed(translator("zh").text(note)) in zh_text.replace("\u2060", "")
    assert printed(str(note)) in text.replace("\u2060", "")


def test_terminal_json_stays_english(capsys):
    """--lang changes the document only: the --json output (notes, reasons, budget sources) is
    English."""
    from metro.core.cli.app import main

    code = main(["run", "-s", "ogam", "-i", "7.1,7.2,7.4", "--lang", "zh", "--json", "-q",
                 "--no-report"])
    out = capsys.readouterr().out
    assert code == 0, out[-2000:]
    doc = json.loads(out)
    notes = [r["note"] for r in doc["results"]]
    sources = [row["source"] for b in doc["budgets"] for row in b["rows"]]
    assert any("earth rate removed" in n for n in notes) and "scatter of the rounds' K_i" in sources
    assert not any(CJK.search(t) for t in notes + sources)


def test_gbt45570_type_test_report_in_chinese(pm, tmp_path):
    """GB/T 45570 `--all` (the type test: clause-5 table, 5.4 severities, not-reportable threshold)
    in zh holds no English prose, the merged line of the limits' sources included (its table rows,
    clauses and remarks are messages merged by their fields, no longer English text parsed: it was
    the one English line left, 'table A.1 rows 1–16, 航空 aviation (row 1: applies to D.1.1 only
    …)'); the en document has no Chinese in that line ('航空', '绝缘电阻', '极性应为正' were there);
    the catalog lacks nothing. Before the clause-5 table rendered its requirements, results and
    notes through the catalog the report had 58 English runs all over the clause-5 table."""
    rec = run_items(pm, "gbt45570", [], run_all=True)
    ctx = report.build_context(rec, extend=pm.extend_report_context)
    figures = report.render_figures(ctx, tmp_path)
    layout = pm.template_for("gbt45570").layout
    doc = report.build_document(ctx, tmp_path, layout=layout, lang="zh", figures=figures)
    assert not doc.tr.missing, sorted(doc.tr.missing)
    texts = _texts(doc.doc)
    bad = english_prose(texts)
    assert not bad, bad[:10]
    line = next(t for t in texts if t.startswith("限值来源")).replace("\u00a0", " ")
    assert ("表 A.1 第 1–16 行，航空（第 1 行：仅适用于 D.1.1" in line
            and "5.2.8（绝缘电阻 ≥ 50 MΩ）" in line), line
    # the figures' own words too (D.1.5's fit line, 6.2.7.7's window mean and band are added to the
    # specs)
    from metro.core.documents import plots
    from metro.core.base.locale import translator

    specs = [plots.localized(p["spec"], translator("zh")) for o in ctx["outcomes"] for p
             in o["plots"]]
    drawn = [str(t) for sp in specs for t in (sp.title, sp.xlabel, sp.ylabel,
                                              *(x.get("label") or "" for x in sp.series))]
    assert len(specs) >= 8 and not english_prose(drawn), english_prose(drawn)[:10]
    en = report.build_document(ctx, tmp_path, layout=layout, lang="en", figures=figures)
    line = next(t for t in _texts(en.doc)
                if t.startswith("Sources of the limits")).replace("\u00a0", " ")
    assert not CJK.search(
        line) and "table A.1 rows 1–16, aviation (row 1: applies to D.1.1 only" in line, line


#: two English words in a row (a sentence or phrase, not a symbol or a unit)
WORDY = re.compile(r"[A-Za-z]{2,}[ ,;:()]+[A-Za-z]{2,}")


def _bypassing(rec) -> list[str]:
    """The texts of a run a document prints that would stay English in a zh document: a plain
    string with English words the catalog does not hold, or a message whose id it lacks (the
    fields of a message are data: equipment names, file names)."""
    from metro.core.base.locale import Text, translator

    tr = translator("zh")
    texts = []
    for o in rec.outcomes:
        texts += [(o.id, "warning", w) for w in o.warnings]
        texts += [(o.id, "table", t.title) for t in o.tables] + [(o.id, "plot", p.title) for p
                                                                 in o.plots]
        for r in o.results:
            texts += [(o.id, "note", r.note), (o.id, "reason", r.reason)]
            if r.budget is not None:
                texts += [(o.id, "budget note", r.budget.note)]
                texts += [(o.id, "source", row.source) for row in r.budget.rows]
                texts += [(o.id, "row note", row.note) for row in r.budget.rows]
    bad = []
    for item, what, t in texts:
        if not t:
            continue
        before = set(tr.missing)
        tr.text(t)
        if tr.missing - before or (not isinstance(t, Text) and WORDY.search(str(t)) and str(t)
                                   not in tr._zh):
            bad.append(f"{item} {what}: {str(t)[:120]}")
    return bad


def test_rate_method_and_quantization_texts_go_through_the_catalog(pm):
    """GB/T D.2 (rate method) on the rate-output station and the D.5 items on its rounded LSB
    output: every budget source and note, result note, warning and table title is a message the
    catalog translates.  Before, D.2's budget sources and notes were plain English literals and
    f-strings ('mean outputs F̄_j through the D.21 fit', 'rate-table ripple averaged over each rate
    point …', 'the D.41 means of 10 samples', 'noise s = … the rounding does not average out …'),
    printed in English in a Chinese report."""
    rec = run_items(pm, "gbt45570", ["D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.6", "D.3", "D.5.1",
                                     "D.5.2"],
                    station="simulated-digital")
    bad = _bypassing(rec)
    assert not bad, "\n".join(bad[:20])


def test_every_standards_texts_go_through_the_catalog(pm):
    """ogam, JJF 2003, JJF 2014 and the GB/T type test (--all): warnings ('not measured: …', 'n
    rounds at 60 °/s …'), the 5.2.x declarations' warnings and budget sources ('observed answers, a
    count (exact)', JJF 2014 7.2.11's 'rate table Ω_(+) (γ ∝ 1/Ω)') are messages."""
    bad = [b for s in ("ogam", "jjf2003", "jjf2014", "gbt45570") for b
           in _bypassing(run_items(pm, s, [], run_all=True))]
    assert not bad, "\n".join(bad[:20])


def test_figure_text_in_the_document_language(pm, tmp_path, monkeypatch):
    """The words drawn inside a figure — title, axis labels, legend — are the document's language
    (issue 16: 'every string on the document'); the zh document drew English titles before."""
    from metro.core.documents import plots
    from metro.core.base.locale import catalog

    rec = run_items(pm, "gbt45570", ["D.5.4"], station_options={"duration_scale": 0.1})
    ctx = report.build_context(rec, extend=pm.extend_report_context, lang="zh")
    titles = [p["spec"].title for o in ctx["outcomes"] for p in o["plots"]]
    assert titles and all(getattr(t, "msgid", None) in catalog("zh") for t in titles)
    drawn: list[str] = []
    real = plots.png_bytes
    monkeypatch.setattr(plots, "png_bytes", lambda spec,
                        **kw: (drawn.append(spec.title), real(spec, **kw))[1])
    import warnings

    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        report.build_document(ctx, tmp_path, layout=pm.template_for("gbt45570").layout, lang="zh")
    # a CJK font is installed (CI installs fonts-noto-cjk): no empty boxes
    if len(plots.font_families()) > 1:
        assert not [w for w in caught if "missing from font" in str(w.message)], caught[:3]
    assert drawn and all(re.search(r"[\u4e00-\u9fff]", t) and not re.search(r"[A-Za-z]{4,}", t)
                         for t in drawn), drawn
    assert plots.localized(ctx["outcomes"][0]["plots"][0]["spec"],
                           report.translator("en")).title == str(titles[0])

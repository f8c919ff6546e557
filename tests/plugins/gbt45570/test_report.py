"""The GB/T 45570—2025 test report: template, context, the produced .docx read back with
python-docx."""

from __future__ import annotations

import json
import re

import docx
import pytest

from metro.core.uncertainty.conformity import GUARDED, SIMPLE
from metro.core.documents.text import one_notation
from metro.core.base.locale import translator
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.documents.report import write_report
from metro.core.run.runner import run_items
from metro.plugins.gbt45570 import report as gbt_report

ITEMS = ["D.1.1", "D.1.2", "D.5.1", "D.5.4", "D.5.6"]


@pytest.fixture(scope="module")
def produced(tmp_path_factory):
    """A short simulated run of five items, written with the GB/T layout; (record, Document,
    path)."""
    pm = get_plugin_manager(autoload=False)
    # the marginal unit (issue 29): its indeterminate RWC gives the conformity section a verdict to
    # list
    rec = run_items(pm, "gbt45570", ITEMS, station_options={"duration_scale": 0.25, "seed": 11,
                                                            "grade": "marginal"})
    tpl = pm.template_for("gbt45570")
    assert tpl.name == "gbt45570-report" and tpl.layout == "metro.plugins.gbt45570.report:layout"
    path = write_report(tmp_path_factory.mktemp("gbt") / "r.docx", rec, layout=tpl.layout,
                        designations={"gbt45570": "GB/T 45570—2025"},
                        extend=pm.extend_report_context)
    return rec, docx.Document(str(path)), path


def _norm(text: str) -> str:
    # a bilingual header: two lines
    return text.replace("\u00a0", " ").replace("\u2060", "").replace("\n", " ")


def _texts(doc) -> list[str]:
    return [_norm(p.text) for p in doc.paragraphs]


def _cells(row) -> list[str]:
    return [_norm(c.text) for c in row.cells]


def _table_with(doc, header_word: str):
    for t in doc.tables:
        if any(header_word in c for c in _cells(t.rows[0])):
            yield t


def test_verdict_table_lists_every_verdict_not_conforming_with_its_reason(produced):
    """The conformity section lists each verdict that is not "conforms" with its reason; the
    results table on page 1 gives every verdict; the count of the others is stated."""
    rec, doc, _ = produced
    verdicts = rec.conformity.verdicts
    assert rec.conformity.rule is GUARDED and verdicts
    shown = [v for v in verdicts if v.status.value != "pass"]
    assert shown  # the seed gives an indeterminate RWC
    (table,) = list(_table_with(doc, "理由 Reason"))
    rows = [_cells(r) for r in table.rows[1:]]
    assert len(rows) == len(shown)
    status = {"pass": "合格 conforms", "fail": "不合格 does not conform",
              "indeterminate": "不确定 indeterminate"}
    for row, v in zip(rows, shown):
        assert row[0] == v.item and row[2] == v.spec.text()
        assert row[5] == status[v.status.value]
        # the reason in both languages (a message of the catalog); values below 0.001 as ×10ⁿ
        assert row[6] == one_notation(translator("zh+en").text(v.reason))
        assert one_notation(v.reason) in row[6] and re.search(r"[\u4e00-\u9fff]", row[6])
        # a quantity name with its symbol, not a key
        assert row[1] != v.key and len(row[1]) > len(v.key)
    text = "\n".join(_texts(doc))
    assert f"其余 {len(verdicts) - len(shown)} 个结果合格" in text
    (results,) = [t for t in _table_with(doc, "扩展不确定度 Expanded uncertainty")][:1]
    verdict_col = [_cells(r)[4] for r in results.rows[1:]]
    assert verdict_col.count("合格 conforms") == len(verdicts) - len(shown)
    # quantity name (zh+en) and symbol
    assert "零偏 bias B₀" in [_cells(r)[1] for r in results.rows[1:]]


def test_decision_rule_text_and_sources(produced):
    _, doc, _ = produced
    text = "\n".join(_texts(doc))
    assert ("判定规则 Decision rule: 保护带接受（保护带 w = U） "
            "guarded acceptance (guard band w = U)") in text
    # both languages
    assert GUARDED.statement in text and translator("zh").text(GUARDED.statement) in text
    # the limits' sources, each table once
    assert "GB/T 45570—2025 table A.1 rows 1, 2, 9, 12, 14" in text


def test_report_number_on_every_page_and_in_the_properties(produced):
    rec, doc, path = produced
    num = rec.report_number
    for sec in doc.sections:
        assert num in sec.header.paragraphs[0].text
        assert num in sec.footer.paragraphs[0].text
        assert "SIMULATED" in "".join(p.text for p in sec.header.paragraphs)  # on every page
    xml = doc.sections[0].header._element.xml
    assert "PAGE" in xml and "NUMPAGES" in xml  # page x of y
    assert "(page x of y)" not in xml
    assert doc.core_properties.identifier == num
    assert not list(path.parent.glob("*.tmp*"))  # written atomically, nothing left over


def test_data_digest_is_the_sha256_of_every_segment_digest(produced):
    rec, doc, _ = produced
    files = rec.data_files or [(s.id, s.sha256) for s in rec.campaign.segments if s.sha256]
    assert files
    (para,) = [t for t in _texts(doc) if "SHA-256 of the sorted list of data digests" in t]
    ctx_files = [f"{h}  {f}\n" for f, h in files]
    assert len(para.split(": ")[-1]) == 64
    # one compact table: after its title (above it), three names with 16 hex digits to a row
    body = doc.element.body
    (title,) = [p for p in doc.paragraphs if "first 16 hex digits" in _norm(p.text)]
    table = next(t for t in doc.tables if body.index(t._tbl) == body.index(title._p) + 1)
    assert sum(1 for t in doc.tables if any(len(c) >= 16 and all(ch in "0123456789abcdef" for ch
                                                                 in c.split()[-1])
                                            for r in t.rows for c in _cells(r) if c.split())) == 1
    text = "\n".join(c for r in table.rows for c in _cells(r))
    for _, h in files:
        assert h[:16] in text
    assert len(ctx_files) == len(files)


def test_items_not_performed_are_marked_never_zero(produced):
    """A report of chosen items lists the rows of table A.1 it performed, with their results, and
    names the others as not performed (never a zero); the C.1 rows likewise."""
    rec, doc, _ = produced
    (table,) = [t for t in _table_with(doc, "指标 Index")]
    rows = {_cells(r)[1]: _cells(r)[4] for r in table.rows[1:]}
    assert [_cells(r)[0] for r in table.rows[1:]] == ["1", "2", "9", "12", "14"]
    assert any(k.startswith("零偏 bias B₀") and "U =" in v for k, v in rows.items())
    for value in rows.values():
        assert "U =" in value and not value.startswith("0 ")
    text = "\n".join(_texts(doc))
    # row 4: K_r, 11: B_r
    assert "表 A.1 中本次未检测的行：3, 4, 5, 6, 7, 8, 10, 11, 13, 15, 16" in text
    assert "表 C.1 中本次未检测的行：1, 2, 3" in text


def test_type_test_prints_clause_5_and_whole_tables(produced):
    """A type test (--all) prints the clause-5 table and every row of A.1/B.1 and C.1; a report
    of chosen items prints no clause-5 table (the ITEMS run here)."""
    import attrs

    from metro.core.documents.report import build_context
    from metro.core.run.runner import ItemChoice

    rec, doc, _ = produced
    assert not any("技术要求 Technical requirements" in t for t in _texts(doc))
    pm = get_plugin_manager(autoload=False)
    typ = attrs.evolve(rec, selection=[ItemChoice(i, True, "applies", "--all") for i in ITEMS])
    ctx = build_context(typ, extend=pm.extend_report_context)
    assert ctx["gbt45570"]["type_test"] and not build_context(rec,
                                                              extend=pm.extend_report_context)["gbt45570"]["type_test"]
    from metro.core.documents.report import render_context

    path = render_context(produced[2].with_name("type-test.docx"), ctx,
                          layout=pm.template_for("gbt45570").layout)
    d = docx.Document(str(path))
    texts = _texts(d)
    assert any(t.startswith("1 技术要求 Technical requirements (5)") for t in texts)
    (table,) = [t for t in _table_with(d, "指标 Index")]
    # each of A.1's 16 rows once
    assert [_cells(r)[0] for r in table.rows[1:]] == [str(i) for i in range(1, 17)]
    (c1,) = [t for t in _table_with(d, "严酷等级 Severity")]
    assert len(c1.rows) == 1 + 16
    assert not any("本次未检测的行" in t for t in texts)


def test_environment_equipment_method_and_figures(produced):
    rec, doc, _ = produced
    (env,) = list(_table_with(doc, "条件 Condition"))
    cells = {_cells(r)[0]: (_cells(r)[2], _cells(r)[3]) for r in env.rows[1:]}
    assert cells["温度 Temperature (6.1.1 a)"] == ("20 °C", "合格 conforms")
    (eq,) = list(_table_with(doc, "职责 Role"))[:1]
    ids = {e.id for e in rec.campaign.equipment}
    assert {_cells(r)[0].rsplit("(", 1)[1].rstrip(")") for r in eq.rows[1:]} == ids
    text = "\n".join(_texts(doc))
    assert "D.1: laser gyro: clause 6.2.7.1" in text
    assert "Via" not in text and "--all" not in text  # no command-line jargon
    titles = [t for t in _texts(doc) if t.startswith("图 Figure ")]
    assert [t.split(":")[0] for t in titles] == [f"图 Figure {i}" for i
                                                 in range(1, len(titles) + 1)]
    assert any("Residuals of Ki" in t for t in titles) and any("D.45 fit" in t for t in titles)
    assert any("Bias against temperature" in t for t in titles)
    assert len(doc.inline_shapes) == len(titles)


def test_page_one_has_the_device_the_overall_verdict_and_the_results(produced):
    """Before the first numbered section: identification, the overall verdict and every result."""
    rec, doc, _ = produced
    body = doc.element.body
    first_heading = next(i for i, p in enumerate(doc.paragraphs) if _norm(p.text).startswith("1 "))
    before = "\n".join(_texts(doc)[:first_heading])
    assert "总体判定 Overall verdict:" in before
    (results,) = [t for t in _table_with(doc, "扩展不确定度 Expanded uncertainty")][:1]
    n_results = sum(len(o.results) for o in rec.outcomes)
    assert len(results.rows) == n_results + 1
    assert body.index(results._tbl) < body.index(doc.paragraphs[first_heading]._p)
    names = [_cells(r)[1] for r in results.rows[1:]]
    assert not any("_" in n for n in names)  # quantity names, no code keys like Bs_10s


def test_simple_rule_and_no_specification_are_stated():
    from metro.core.model.campaign import DeviceUnderTest
    from metro.core.documents.context import report_context

    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "gbt45570", ["D.5.1"], station_options={"duration_scale": 0.1},
                    decision_rule="simple")
    ctx = report_context(rec)
    assert ctx["conformity"]["rule"] == "simple" and ctx["conformity"]["verdicts"][0]["key"] == "B0"
    pm.extend_report_context(rec, ctx)
    assert ctx["gbt45570"]["rule"]["statement"] == SIMPLE.statement
    assert all(v["status"] in ("pass", "fail") for v in ctx["gbt45570"]["verdicts"])
    import attrs

    other = attrs.evolve(rec, campaign=attrs.evolve(rec.campaign,
                                                    device=DeviceUnderTest("M", technology="mems")),
                         conformity=None)
    ctx = report_context(other)
    pm.extend_report_context(other, ctx)
    assert not ctx["gbt45570"]["has_conformity"] and "no conformity statement" in ctx["gbt45570"][
        "rule"]["statement"]
    assert ctx["gbt45570"]["limits"] is None


def test_series_alias_reports_the_method_choice(run_cli):
    code, out, _ = run_cli("run", "-s", "gbt45570", "-i", "scale-factor", "--json", "--no-report",
                           "--no-progress", "--seed", "5")
    assert code in (0, 3, 4)  # evaluated (0 conforms, 3 does not conform, 4 indeterminate)
    doc = json.loads(out)
    sel = {c["item"]: c for c in doc["selection"]}
    assert sel["D.1.1"]["run"] and sel["D.1.1"]["via"] == "series scale-factor"
    assert "6.2.7.1" in sel["D.1.1"]["reason"] and "angle method" in sel["D.1.1"]["reason"]
    assert not sel["D.2.1"]["run"]
    assert {r["item"] for r in doc["results"]} <= {"D.1.1", "D.1.2", "D.1.3", "D.1.4", "D.1.5"}
    assert doc["conformity"]["rule"] == "guarded" and doc["conformity"]["verdicts"]
    code, _, err = run_cli("run", "-s", "gbt45570", "--no-report")
    assert code == 2 and "--all" in err
    code, out, _ = run_cli("items", "-s", "gbt45570", "--json")
    series = {x["name"]: x for x in json.loads(out)["series"]}
    assert code == 0 and series["scale-factor"]["members"][:2] == ["D.1.1", "D.1.2"]
    code, out, _ = run_cli("plan", "-s", "gbt45570", "-i", "scale-factor", "--json")
    kinds = {s["kind"] for s in json.loads(out)["steps"]}
    # the angle method's steps
    assert code == 0 and "rate-revolutions" in kinds and "rate-output" not in kinds


def test_fibre_gyro_takes_the_rate_method_and_table_b1():
    """The digital-output (fibre) simulated gyro: 6.2.7.1 picks D.2 (no declared nonlinearity; B.1
    aviation limit 50×10⁻⁶ > 5×10⁻⁶) and the verdicts cite table B.1."""
    from metro.core.documents.context import report_context

    from metro.core.run.runner import select_items, station_device

    pm = get_plugin_manager(autoload=False)
    device = station_device(pm, "simulated-digital", {})
    assert device.technology == "fibre"
    items, choices = select_items(pm, "gbt45570", ["scale-factor"], device=device)
    assert items == ["D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.5"]
    why = {c.item: c for c in choices}
    assert not why["D.1.1"].run and "rate method (D.2)" in why[
        "D.1.1"].reason and "table B.1" in why["D.1.1"].reason
    rec = run_items(pm, "gbt45570", ["D.2.1", "D.2.2"], station="simulated-digital",
                    station_options={"duration_scale": 0.3, "seed": 4})
    assert all("table B.1" in v.spec.source for v in rec.conformity.verdicts)
    ctx = report_context(rec)
    pm.extend_report_context(rec, ctx)
    g = ctx["gbt45570"]
    assert g["limits"]["table"] == "B.1" and g["method"].startswith("D.2:")
    rows = {r["name"].split(" (")[0]: r for r in g["limits"]["rows"]}
    assert rows["零偏 bias"]["result"] == gbt_report.NOT_PERFORMED and not rows["零偏 bias"][
        "performed"]


def test_clause5_rows_come_from_the_clause5_module(produced, monkeypatch):
    """The clause-5 table's contract: ``metro.plugins.gbt45570.clause5.clause5_rows(record)`` gives
    rows with clause, requirement, result, verdict (note optional); a row lacking one is an
    error."""
    import sys
    import types

    rec = produced[0]
    fake = types.ModuleType("metro.plugins.gbt45570.clause5")
    fake.__spec__ = types.SimpleNamespace(name=fake.__name__)
    fake.clause5_rows = lambda record: [{"clause": "5.2.1", "requirement": "scale factor",
                                         "result": "1.0 ″/P", "verdict": "合格 conforms"}]
    monkeypatch.setitem(sys.modules, fake.__name__, fake)
    monkeypatch.setattr(sys.modules["metro.plugins.gbt45570"], "clause5", fake, raising=False)
    assert gbt_report.clause5_rows(rec) == [{"clause": "5.2.1", "requirement": "scale factor",
                                              "result": "1.0 ″/P", "verdict": "合格 conforms",
                                             "note": ""}]
    fake.clause5_rows = lambda record: [{"clause": "5.2.1"}]
    with pytest.raises(ValueError, match="requirement"):
        gbt_report.clause5_rows(rec)


def test_environmental_notes_name_the_test_not_the_manifest_field(tmp_path):
    """6.2.8 results: a severity's note said where it sat in the manifest ('as applied
    (environmental_tests[0].severity.temperature)'), and the warning on undeclared uncertainties
    '([environmental_tests[0].uncertainty])': a certificate names the test, not a place in the lab's
    files (the manifest and its digest are in the provenance annex).  Rendered in zh and en, the
    document holds no 'environmental_tests'; the warning names the test."""
    pm = get_plugin_manager()
    rec = run_items(pm, "gbt45570", ["6.2.8.2", "6.2.8.5"])
    texts = [str(r.note) for o in rec.outcomes for r
             in o.results] + [str(w) for o in rec.outcomes for w in o.warnings]
    assert not [t for t in texts if "environmental_tests" in t], texts
    assert any(str(w).startswith("low-temperature storage: the test lab declares no uncertainty")
               for o in rec.outcomes
               for w in o.warnings), texts
    tpl = pm.template_for("gbt45570")
    for lang in ("zh", "en"):
        out = write_report(tmp_path / f"r_{lang}.docx", rec, layout=tpl.layout,
                           extend=pm.extend_report_context,
                           lang=lang)
        d = docx.Document(str(out))
        body = "\n".join(_texts(d) + [c for t in d.tables for row in t.rows for c in _cells(row)])
        assert "environmental_tests" not in body, lang

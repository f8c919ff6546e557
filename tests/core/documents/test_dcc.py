"""A report as a PTB DCC 3.3.0 (issue 31): each standard's ``--all`` run on the simulated station
is valid against ../shared/reference/dcc (read with xmlschema here, not through metro's own
validator), and reads back with every result's value, U, k, unit and verdict as the run gave
them; an amendment, not-reportable results, the embedded PDF, a stored (register) context, and
the refusals (no machine values, a withdrawn report, a unit with no D-SI mapping)."""

from __future__ import annotations

import base64
import datetime as dt
import math
import re
import xml.etree.ElementTree as ET
from pathlib import Path

import attrs
import pytest
from metro.core.base.errors import MetroError, UnitError
from metro.core.base.locale import translator
from metro.core.base.units import Q_, angle_power, difference_unit, unit
from metro.core.documents.dcc import (SCHEMA_DIR, DccError, build_dcc, read_dcc_results,
                                      validate_dcc, write_dcc)
from metro.core.documents.report import build_context
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.runner import run_items

REFERENCE = Path(__file__).resolve().parents[3].parent / "shared" / "reference" / "dcc"
needs_reference = pytest.mark.skipif(
    not (REFERENCE / "dcc.xsd").is_file(),
    reason=f"the DCC reference schemas are not at {REFERENCE} (CI has them)")
D = "{https://ptb.de/dcc}"
S = "{https://ptb.de/si}"
SUP = str.maketrans("⁰¹²³⁴⁵⁶⁷⁸⁹⁻", "0123456789-")

#: (standard, station options): the short runs each standard's simulated station allows (measured
#: here: jjf2014 17 s, jjf2003 10 s, gbt45570 4 s, ogam 1.5 s, DCC and validation included)
RUNS = {
    "jjf2003": {},
    "ogam": {},
    "jjf2014": {"duration_scale": 0.1},
    "gbt45570": {},
}
_RECORDS: dict[str, tuple] = {}


def _reference_schema():
    xmlschema = pytest.importorskip("xmlschema")
    imports = {"https://ptb.de/si/v2.2.1/SI_Format.xsd": "SI_Format.xsd",
               "https://www.ptb.de/dcc/d-sig/xmldsig-core-schema.xsd": "xmldsig-core-schema.xsd",
               "https://www.ptb.de/si/v2.2.1/qudt/quantitykind.xsd": "quantitykind.xsd"}
    return xmlschema.XMLSchema(str(REFERENCE / "dcc.xsd"), allow="local",
                               uri_mapper={u: str(REFERENCE / f) for u, f in imports.items()})


def _run(standard: str):
    """The record and document context of ``standard``'s --all run (once per session)."""
    if standard not in _RECORDS:
        pm = get_plugin_manager(autoload=False)
        rec = run_items(pm, standard, [], run_all=True, station_options=RUNS[standard])
        designations = {s.id: s.designation for s in pm.registry.standards.values()}
        ctx = build_context(rec, designations=designations, extend=pm.extend_report_context,
                            lang="zh+en")
        _RECORDS[standard] = (rec, ctx)
    return _RECORDS[standard]


def _number(text: str) -> float:
    """A number as the report prints it (``6.5×10⁻⁶``), read here without metro's code."""
    t = text.replace("−", "-")
    m = re.fullmatch(r"([-+]?[\d.]+)×10([⁻⁰¹²³⁴⁵⁶⁷⁸⁹]+)", t)
    return float(f"{m[1]}e{m[2].translate(SUP)}") if m else float(t)


def _same_unit(got: str, want: str) -> bool:
    a, b = unit(got), unit(want)
    if a.dimensionality != b.dimensionality or angle_power(a) != angle_power(b):
        return False
    one = Q_(1.0, difference_unit(a)).to(difference_unit(b)).magnitude
    return math.isclose(one, 1.0, rel_tol=1e-12)


def _results(rec) -> list[tuple[str, object]]:
    return [(o.item, r) for o in rec.outcomes for r in o.results]


def _verdicts(rec) -> dict[tuple[str, str], str]:
    a = rec.conformity
    return {} if a is None else {(v.item, v.key): v.detail for v in a.verdicts}


def _check_round_trip(rec, xml: bytes) -> None:
    back = read_dcc_results(xml)
    mine = _results(rec)
    assert len(back) == len(mine)
    verdicts = _verdicts(rec)
    for got, (item, r) in zip(back, mine):
        where = (item, r.metric.key)
        assert (got["item"], got["key"]) == where
        assert got["reportable"] is bool(r.reportable), where
        v = verdicts.get(where)
        assert got["verdict"] == (v if v in ("pass", "fail", "conditional pass",
                                             "conditional fail") else None), where
        if not r.reportable:
            # the reason as a document prints it (advice about the software left out)
            said = " ".join(translator("en").render(r.reason, "en").split())
            assert got["value"] is None and got["reason"] == said, where
            continue
        vtext, utext = r.reported()
        assert got["value"] == _number(vtext), where
        assert _same_unit(got["unit"], r.metric.unit), where
        if r.budget is None:
            assert got["U"] is None and got["k"] is None, where
        else:
            assert got["U"] == _number(utext), where
            assert got["k"] == r.k, where
            assert 0.9 < got["p"] < 1.0, where


@needs_reference
@pytest.mark.parametrize("standard", list(RUNS))
def test_all_items_dcc_is_valid_and_reads_back(standard: str) -> None:
    rec, ctx = _run(standard)
    xml = build_dcc(ctx)
    _reference_schema().validate(xml.decode("utf-8"))
    _check_round_trip(rec, xml)


def test_shipped_schemas_equal_the_reference() -> None:
    if not (REFERENCE / "dcc.xsd").is_file():
        pytest.skip(f"the DCC reference schemas are not at {REFERENCE} (CI has them)")
    for name in ("dcc.xsd", "SI_Format.xsd", "quantitykind.xsd", "xmldsig-core-schema.xsd",
                 "COPYING.LESSER"):
        assert (SCHEMA_DIR / name).read_bytes() == (REFERENCE / name).read_bytes(), name


def _root(xml: bytes) -> ET.Element:
    return ET.fromstring(xml)


@needs_reference
def test_jjf2003_matrices_are_dsi_lists_of_the_results() -> None:
    rec, ctx = _run("jjf2003")
    root = _root(build_dcc(ctx))
    found = {}
    for res in root.iter(f"{D}result"):
        if res.get("refType") == "metro_matrix":
            lst = res.find(f"{D}data/{D}quantity/{S}realListXMLList")
            labels = lst.findtext(f"{S}labelXMLList").split()
            values = [float(x) for x in lst.findtext(f"{S}valueXMLList").split()]
            found[res.get("id")] = dict(zip(labels, values))
    assert set(found) == {"matrix-7.2.2-g-0", "matrix-7.2.3-K_g-0", "matrix-7.2.4-K_a-0"}
    kg = found["matrix-7.2.3-K_g-0"]
    assert list(kg) == [f"K_g{a}{b}" for a in "xyz" for b in "xyz"]
    by_key = {(i, r.metric.key): r for i, r in _results(rec)}
    for key, value in kg.items():
        assert value == _number(by_key[("7.2.3", key)].reported()[0])


@needs_reference
def test_not_reportable_results_carry_their_reason_and_no_value() -> None:
    rec, _ = _run("jjf2003")
    o = rec.outcomes[0]
    bad = attrs.evolve(o.results[1], reportable=False, reason="the fit does not hold here")
    rec2 = attrs.evolve(rec, outcomes=(attrs.evolve(o, results=(o.results[0], bad,
                                                                *o.results[2:])),
                                       *rec.outcomes[1:]))
    ctx = build_context(rec2, lang="en")
    xml = build_dcc(ctx)
    _reference_schema().validate(xml.decode("utf-8"))
    res = next(e for e in _root(xml).iter(f"{D}result")
               if e.get("id") == f"result-{o.item}-{bad.metric.key}")
    assert res.find(f".//{S}real") is None or res.find(f"{D}data/{D}quantity/{S}real") is None
    assert res.findtext(f"{D}data/{D}quantity/{D}noQuantity/{D}content") == \
        "the fit does not hold here"
    _check_round_trip(rec2, xml)


@needs_reference
def test_an_amendment_names_the_report_it_replaces() -> None:
    rec, _ = _run("ogam")
    register = {"registered": True, "number": rec.report_number, "supersedes": "LAB-2026-0007",
                "reason": "serial number corrected", "notices": ["This report replaces report "
                                                                 "LAB-2026-0007. Reason: serial "
                                                                 "number corrected"]}
    ctx = build_context(rec, register=register, lang="en")
    xml = build_dcc(ctx)
    _reference_schema().validate(xml.decode("utf-8"))
    core = _root(xml).find(f"{D}administrativeData/{D}coreData")
    ras = core.find(f"{D}reportAmendedSubstituted")
    assert ras.findtext(f"{D}typeOfChange") == "substituted"
    assert ras.findtext(f"{D}replacedUniqueIdentifier") == "LAB-2026-0007"
    assert core.findtext(f"{D}uniqueIdentifier") == rec.report_number
    assert [e.text for e in core.findall(f"{D}usedLangCodeISO639_1")] == ["en"]
    with pytest.raises(DccError, match="withdrawn"):
        build_dcc({**ctx, "register": {**register, "status": "withdrawn"}})


def test_a_stored_context_gives_the_same_dcc() -> None:
    from metro.core.record.registering import encode_context
    import json

    _, ctx = _run("ogam")
    stored = json.loads(json.dumps(encode_context(ctx)))
    assert build_dcc(stored) == build_dcc(ctx)


def test_a_context_without_machine_values_is_refused() -> None:
    _, ctx = _run("ogam")
    old = {k: v for k, v in ctx.items() if k != "data"}
    with pytest.raises(DccError, match="without the machine values"):
        build_dcc(old)


def test_a_unit_with_no_mapping_is_refused_naming_unit_and_result() -> None:
    _, ctx = _run("ogam")
    results = [dict(r) for r in ctx["data"]["results"]]
    first = next(r for r in results if r["reportable"])
    first["unit"] = "furlong/h"
    with pytest.raises(UnitError, match="furlong") as err:
        build_dcc({**ctx, "data": {**ctx["data"], "results": results}})
    assert f"{first['item']} {first['key']}" in str(err.value)


def test_pdf_embedded_and_file_never_replaced(tmp_path) -> None:
    _, ctx = _run("ogam")
    pdf = b"%PDF-1.7\n" + bytes(range(256))
    target = write_dcc(ctx, tmp_path / "cert.xml", pdf=pdf)
    doc = _root(target.read_bytes()).find(f"{D}document")
    assert base64.b64decode(doc.findtext(f"{D}dataBase64")) == pdf
    assert doc.findtext(f"{D}mimeType") == "application/pdf"
    # read back by the DCC's reader (what metro serve hands out as the report's PDF)
    from metro.core.documents.dcc import embedded_pdf

    assert embedded_pdf(target.read_bytes()) == pdf
    assert embedded_pdf(build_dcc(ctx)) is None and embedded_pdf(b"not xml") is None
    before = target.read_bytes()
    with pytest.raises(DccError, match="never replaces"):
        write_dcc(ctx, target)
    assert target.read_bytes() == before
    assert sorted(p.name for p in tmp_path.iterdir()) == ["cert.xml"]


def test_budget_is_a_table_of_its_components() -> None:
    rec, ctx = _run("jjf2003")
    root = _root(build_dcc(ctx))
    item, r = _results(rec)[0]
    res = next(e for e in root.iter(f"{D}result") if e.get("id") == f"result-{item}-K_gxx")
    budget = res.find(f"{D}data/{D}list[@refType='metro_budget']")
    comps = budget.findall(f"{D}list")
    assert len(comps) == len(r.budget.rows)
    got = []
    for c in comps:
        q = next(q for q in c.findall(f"{D}quantity")
                 if q.findtext(f"{D}name/{D}content[@lang='en']") == "contribution"
                 or q.findtext(f"{D}name/{D}content") == "contribution")
        got.append(float(q.findtext(f"{S}real/{S}value")))
    assert got == pytest.approx(r.budget.contributions(), rel=1e-15)
    assert math.sqrt(sum(x * x for x in got)) == pytest.approx(r.budget.combined.magnitude,
                                                               rel=1e-12)


def test_core_data_from_the_campaign() -> None:
    rec, _ = _run("ogam")
    camp = attrs.evolve(rec.campaign, site={**rec.campaign.site, "country": "de"},
                        meta={**rec.campaign.meta, "customer": "ACME Navigation",
                              "approved_by": "Li Wei", "operator": "Zhang San",
                              "measurement_date": "2026-02-03"})
    ctx = build_context(attrs.evolve(rec, campaign=camp), lang="zh")
    adm = _root(build_dcc(ctx)).find(f"{D}administrativeData")
    core = adm.find(f"{D}coreData")
    assert core.findtext(f"{D}countryCodeISO3166_1") == "DE"
    assert [e.text for e in core.findall(f"{D}usedLangCodeISO639_1")] == ["zh"]
    software = [s.findtext(f"{D}name/{D}content") for s in adm.iter(f"{D}software")]
    assert software[0] == "metro" and "metro plugin ogam" in software
    people = {p.findtext(f"{D}person/{D}name/{D}content"): p.findtext(f"{D}mainSigner")
              for p in adm.iter(f"{D}respPerson")}
    assert people == {"Zhang San": "false", "Li Wei": "true"}
    assert adm.findtext(f"{D}customer/{D}name/{D}content") == "ACME Navigation"
    # a Chinese certificate: translated texts in Chinese only, data (names) without a language
    langs = {c.get("lang") for c in adm.iter(f"{D}content")}
    assert langs == {None, "zh"}
    name = adm.find(f"{D}customer/{D}name/{D}content")
    assert name.get("lang") is None


def test_validate_dcc_names_the_element_of_a_broken_document() -> None:
    pytest.importorskip("xmlschema")
    _, ctx = _run("ogam")
    xml = build_dcc(ctx)
    validate_dcc(xml)
    broken = xml.replace(b"<dcc:uniqueIdentifier>", b"<dcc:uniqueIdentifier> ", 1)
    broken = re.sub(rb"<dcc:countryCodeISO3166_1>[A-Z]{2}<", b"<dcc:countryCodeISO3166_1>zz<",
                    broken)
    with pytest.raises(MetroError, match="countryCodeISO3166_1"):
        validate_dcc(broken)


@needs_reference
def test_recorded_campaign_with_a_lab_profile(tmp_path, capsys) -> None:
    """A campaign read from its files (``metro acquire``), the lab profile ``metro lab init``
    writes, and the register statement of a registered report."""
    import tomllib

    import tomli_w
    from metro.core.cli.app import main
    from metro.core.record.lab import load_lab
    from metro.core.record.registering import notices_for, with_lab

    assert main(["lab", "init", str(tmp_path / "lab.toml")]) == 0
    assert main(["acquire", "-s", "ogam", "--all", "--out", str(tmp_path / "camp"), "-q"]) == 0
    capsys.readouterr()
    manifest = tmp_path / "camp" / "manifest.toml"
    doc = tomllib.loads(manifest.read_text(encoding="utf-8"))
    doc["site"]["country"] = "CN"
    doc["campaign"]["customer"] = "某导航公司"
    segments = doc["segments"]  # measured over two days
    segments[0]["started"] = dt.datetime(2026, 3, 1, 9, 30, tzinfo=dt.timezone.utc)
    segments[-1]["started"] = dt.datetime(2026, 3, 2, 16, 5, tzinfo=dt.timezone.utc)
    manifest.write_text(tomli_w.dumps(doc), encoding="utf-8")
    lab = load_lab(tmp_path / "lab.toml")
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "ogam", [], run_all=True, data=manifest,
                    lab_equipment=lab.equipment_by_id())
    rec = attrs.evolve(with_lab(rec, lab), report_number="EML2026-00001")
    statement = {"registered": True, "number": "EML2026-00001", "supersedes": None, "reason": "",
                 "notices": notices_for(lab, "EML2026-00001")}
    ctx = build_context(rec, register=statement, lang=lab.language,
                        designations={s.id: s.designation for s in pm.registry.standards.values()})
    xml = build_dcc(ctx)
    _reference_schema().validate(xml.decode("utf-8"))
    _check_round_trip(rec, xml)
    adm = _root(xml).find(f"{D}administrativeData")
    core = adm.find(f"{D}coreData")
    assert core.findtext(f"{D}uniqueIdentifier") == "EML2026-00001"
    assert core.findtext(f"{D}countryCodeISO3166_1") == "CN"
    assert (core.findtext(f"{D}beginPerformanceDate"),
            core.findtext(f"{D}endPerformanceDate")) == ("2026-03-01", "2026-03-02")
    lab_name = adm.findtext(f"{D}calibrationLaboratory/{D}contact/{D}name/{D}content")
    assert lab_name == "示例计量实验室 Example Metrology Laboratory"
    people = {p.findtext(f"{D}person/{D}name/{D}content"): p.findtext(f"{D}mainSigner")
              for p in adm.iter(f"{D}respPerson")}
    assert people == {"张三": "false", "李四": "false", "王五": "true"}
    assert adm.findtext(f"{D}customer/{D}name/{D}content") == "某导航公司"


@pytest.mark.parametrize(("printed", "decimal"), [
    ("6.5×10⁻⁶", "6.5e-6"), ("1.2×10³", "1.2e3"), ("−0.00150", "-0.00150"), ("8", "8"),
    ("1.01245", "1.01245"), ("—", None), ("u = 0.1", None)])
def test_printed_numbers_as_dsi_decimals(printed: str, decimal: str | None) -> None:
    from metro.core.documents.dcc.data import decimal_text

    assert decimal_text(printed) == decimal


def test_coverage_probability_of_a_fixed_k_is_the_normal_one() -> None:
    from types import SimpleNamespace

    from metro.core.documents.dcc.data import coverage_probability

    # GUM G.1.3 table G.1: k = 2 → 95.45 %, k = 3 → 99.73 %, k = 1 → 68.27 %
    fixed = SimpleNamespace(k=2.0, p=None)
    assert [coverage_probability(fixed, k) for k in (2.0, 3.0, 1.0)] == [0.9545, 0.9973, 0.6827]
    assert coverage_probability(SimpleNamespace(k=None, p=0.95), 2.03) == 0.95

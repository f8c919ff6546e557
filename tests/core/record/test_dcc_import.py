"""An equipment's DCC 3.3.0 from its calibration provider into the lab's equipment store
(metro.core.record.dcc_import): what is read, what is stored with which provenance, and every
refusal naming the file, the element path and the reason, with nothing written.

The certificates are validated against the reference schemas in ../shared/reference/dcc (not the
copy shipped in the package); the tests skip, saying so, where that folder is absent."""

from __future__ import annotations

import datetime as dt
import hashlib
import json
import re
import tomllib
from pathlib import Path

import pytest

from metro.core.base.errors import DataError, MetroError

ROOT = Path(__file__).resolve().parents[3]
REFERENCE = ROOT.parent / "shared" / "reference" / "dcc"
DATA = ROOT / "tests" / "data" / "dcc"
VALID = DATA / "counter_dcc.xml"
MALFORMED = tomllib.loads((DATA / "malformed.toml").read_text(encoding="utf-8"))
TODAY = dt.date(2026, 11, 1)


@pytest.fixture
def lab(tmp_path, monkeypatch):
    """A lab profile (the template: RT-01 is its equipment), the reference schemas in force."""
    pytest.importorskip("xmlschema")
    if not (REFERENCE / "dcc.xsd").is_file():
        pytest.skip(f"the reference DCC schemas are not in {REFERENCE} (CI has them)")
    from metro.core.record.dcc_import import ENV_SCHEMA
    from metro.core.record.lab import write_template

    monkeypatch.setenv(ENV_SCHEMA, str(REFERENCE))
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    return write_template(tmp_path / "lab.toml")


def malformed_cases() -> list[dict]:
    return MALFORMED["case"]


def malformed_text(case: dict) -> str:
    """The certificate of one case of tests/data/dcc/malformed.toml."""
    if "text" in case:
        return case["text"]
    text = VALID.read_text(encoding="utf-8")
    for pattern, new in case["edit"]:
        edited = re.sub(pattern, lambda m, new=new: new, text, flags=re.S)
        assert edited != text, (case["name"], pattern)  # every edit changes the certificate
        text = edited
    return text


def expected_field(case: dict) -> str:
    return case["field"].format(R=MALFORMED["R"], REAL1=MALFORMED["REAL1"])


def test_reads_the_hand_written_certificate(lab):
    from metro.core.record.dcc_import import read_dcc

    d = read_dcc(VALID)
    assert d.sha256 == hashlib.sha256(VALID.read_bytes()).hexdigest()
    assert (d.unique_identifier, d.issuer) == ("TFL-2026-04417",
                                               "Example Time and Frequency Laboratory")
    assert (d.manufacturer, d.model, d.serial, d.lab_id) == ("Keysight", "53230A", "MY5501234",
                                                             "CNT-7")
    assert (d.begin_date, d.calibration_date, d.issue_date, d.due) == (
        dt.date(2026, 3, 9), dt.date(2026, 3, 10), dt.date(2026, 3, 12), dt.date(2027, 3, 10))
    assert [(r.ident, r.value, r.unit_dsi, r.U, r.k, r.p) for r in d.results] == [
        ("timebase", 1.2e-8, "\\one", 2e-7, 2.0, 0.95),
        ("frequency", 10000000.12, "\\hertz", 2.0, 2.0, 0.95)]


def test_import_writes_equipment_with_provenance_beside_the_profile(lab):
    from metro.core.record.dcc_import import import_dcc
    from metro.core.record.lab import load_lab

    before = lab.read_bytes()
    plan, target = import_dcc(VALID, lab, role="counter", today=TODAY)
    assert target == lab.parent / "lab.equipment" / "CNT-7.toml" and target.is_file()
    assert lab.read_bytes() == before  # the user's profile is never edited
    assert (target.parent / "CNT-7.dcc.xml").read_bytes() == VALID.read_bytes()
    doc = tomllib.loads(target.read_text(encoding="utf-8"))
    assert doc["dcc"]["sha256"] == hashlib.sha256(VALID.read_bytes()).hexdigest()
    assert doc["dcc"]["issuer"] == "Example Time and Frequency Laboratory"
    assert doc["dcc"]["result"].endswith("dcc:result[1]/dcc:data/dcc:quantity/si:real")
    (cnt,) = [e for e in load_lab(lab).equipment if e.id == "CNT-7"]
    cal = cnt.calibration
    assert (cnt.role, cnt.manufacturer, cnt.model, cnt.serial) == ("counter", "Keysight",
                                                                   "53230A", "MY5501234")
    assert (cal.certificate, cal.lab, cal.k, cal.due) == (
        "TFL-2026-04417", "Example Time and Frequency Laboratory", 2.0, dt.date(2027, 3, 10))
    assert cal.uncertainty.dimensionless and float(cal.uncertainty.magnitude) == 2e-7
    assert float(cal.standard_uncertainty.magnitude) == pytest.approx(1e-7, rel=1e-12)
    assert plan.read == cnt


def test_the_role_chooses_the_result_and_result_names_one(lab):
    from metro.core.record.dcc_import import import_dcc

    # a timer takes a relative U or one in seconds: the time base's, not the frequency's
    plan, _ = import_dcc(VALID, lab, role="timer", eid="T-1", today=TODAY, dry_run=True)
    assert plan.equipment["calibration"]["U"] == "2e-07"
    # a role whose U no item reads takes any unit, but only the result it is told to
    with pytest.raises(DataError, match="2 results have a unit a platform can use"):
        import_dcc(VALID, lab, role="platform", eid="P-1", today=TODAY, dry_run=True)
    plan, _ = import_dcc(VALID, lab, role="platform", eid="P-1", select="frequency",
                         today=TODAY, dry_run=True)
    assert plan.equipment["calibration"]["U"] == "2.0 hertz"
    with pytest.raises(DataError, match="no result.* named 'drift'"):
        import_dcc(VALID, lab, role="counter", select="drift", today=TODAY)
    # an angle is not a ratio, though pint counts both dimensionless
    with pytest.raises(DataError, match="must be in arcsec"):
        import_dcc(VALID, lab, role="position_table", eid="PT-1", today=TODAY)
    with pytest.raises(MetroError, match="unknown equipment role 'countr'"):
        import_dcc(VALID, lab, role="countr", today=TODAY)
    assert not (lab.parent / "lab.equipment").exists()


def test_duplicate_ids_are_refused_and_replace_only_replaces_an_import(lab):
    from metro.core.record.dcc_import import import_dcc
    from metro.core.record.lab import load_lab

    _, target = import_dcc(VALID, lab, role="counter", today=TODAY)
    first = target.read_bytes()
    with pytest.raises(MetroError, match="duplicate equipment id 'CNT-7': imported already"):
        import_dcc(VALID, lab, role="counter", today=TODAY)
    with pytest.raises(MetroError, match="duplicate equipment id 'RT-01': the lab profile"):
        import_dcc(VALID, lab, role="counter", eid="RT-01", today=TODAY, replace=True)
    assert target.read_bytes() == first
    _, again = import_dcc(VALID, lab, role="timer", today=TODAY, replace=True)
    assert again == target and 'role = "timer"' in target.read_text(encoding="utf-8")
    # an id given twice (a store file edited by hand) is refused where the profile is read
    target.write_text(target.read_text(encoding="utf-8").replace('id = "CNT-7"', 'id = "RT-01"'),
                      encoding="utf-8")
    with pytest.raises(DataError, match="duplicate equipment id 'RT-01'") as err:
        load_lab(lab)
    assert err.value.file == str(target)


def test_an_expired_certificate_imports_only_when_allowed(lab):
    from metro.core.record.dcc_import import import_dcc

    later = dt.date(2027, 3, 11)
    with pytest.raises(DataError, match="due on 2027-03-10: expired"):
        import_dcc(VALID, lab, role="counter", today=later)
    plan, target = import_dcc(VALID, lab, role="counter", today=later, allow_expired=True)
    assert target.is_file() and "expired" in plan.warnings[0]


def test_a_missing_certificate_is_refused(lab):
    from metro.core.record.dcc_import import import_dcc

    with pytest.raises(DataError, match="certificate not found") as err:
        import_dcc(lab.parent / "absent.xml", lab, role="counter")
    assert err.value.file == str(lab.parent / "absent.xml")
    with pytest.raises(DataError, match="not a file"):
        import_dcc(lab.parent, lab, role="counter")


def test_a_text_no_report_can_hold_names_its_element(lab, tmp_path):
    """A model of 600 characters (a report takes 500) is refused at dcc:model, not at a field of
    metro's own table."""
    from metro.core.record.dcc_import import import_dcc

    cert = tmp_path / "long.xml"
    cert.write_text(VALID.read_text(encoding="utf-8").replace(
        "<dcc:model>53230A</dcc:model>", f"<dcc:model>{'X' * 600}</dcc:model>"), encoding="utf-8")
    with pytest.raises(DataError, match="600 characters") as err:
        import_dcc(cert, lab, role="counter", today=TODAY)
    assert err.value.field.endswith("/dcc:administrativeData/dcc:items/dcc:item/dcc:model")
    with pytest.raises(DataError, match="600 characters") as err:
        import_dcc(VALID, lab, role="counter", eid="Y" * 600, today=TODAY)
    assert err.value.field == "--id"


@pytest.mark.parametrize("case", malformed_cases(), ids=lambda c: c["name"])
def test_malformed_certificates_are_refused_naming_the_element(lab, tmp_path, case):
    from metro.core.record.dcc_import import import_dcc

    cert = tmp_path / f"{case['name']}.xml"
    cert.write_text(malformed_text(case), encoding="utf-8")
    with pytest.raises(DataError) as err:
        import_dcc(cert, lab, role="counter", today=TODAY)
    assert err.value.file == str(cert)
    assert (err.value.field or "") == expected_field(case)
    assert case["reason"] in err.value.detail
    assert not (lab.parent / "lab.equipment").exists()


def test_there_are_at_least_ten_malformed_certificates():
    assert len({c["name"] for c in malformed_cases()}) >= 10


def test_a_dcc_metro_wrote_imports_as_equipment(lab, tmp_path, capsys):
    """The round trip: a registered run's DCC (metro.core.documents.dcc.build_dcc of the stored
    context) imports, its U and k those of the register's result."""
    from metro.core.cli.app import main
    from metro.core.documents.dcc import build_dcc, read_dcc_results
    from metro.core.record.dcc_import import import_dcc
    from metro.core.record.lab import load_lab
    from metro.core.record.register import open_register

    assert main(["--lab", str(lab), "run", "-s", "jjf2014", "-i", "7.2.3", "--no-progress",
                 "--seed", "2", "--register-simulated", "--out", str(tmp_path / "out"),
                 "--json"]) in (0, 3, 4)
    run = json.loads(capsys.readouterr().out)
    number = run["report_number"]
    profile = load_lab(lab)
    context, _ = open_register(profile.register_url(), create=False).context(number)
    cert = tmp_path / f"{number}.xml"
    cert.write_bytes(build_dcc(context))
    (written,) = read_dcc_results(cert.read_bytes())
    assert main(["--lab", str(lab), "register", "show", number, "--json"]) == 0
    shown = json.loads(capsys.readouterr().out)
    (result,) = [r for r in shown["results"] if r["key"] == written["key"]]
    # a relative U, as a rate table's; the device's ids are the lab's, none the customer's
    plan, target = import_dcc(cert, lab, role="rate_table", eid="REF-1", select="Ka")
    cal = plan.read.calibration
    assert (cal.certificate, cal.lab) == (number, profile.name_zh + " " + profile.name_en)
    assert cal.uncertainty.dimensionless and cal.due is None
    assert (float(cal.uncertainty.magnitude), cal.k) == (written["U"], written["k"])
    assert (written["U"], written["k"]) == (float(result["reported"]["U"]), result["k"])
    assert tomllib.loads(target.read_text(encoding="utf-8"))["dcc"]["sha256"] == hashlib.sha256(
        cert.read_bytes()).hexdigest()

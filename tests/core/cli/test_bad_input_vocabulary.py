"""One manifest vocabulary (metro.core.base.vocabulary): canonical keys, old spellings read with a
deprecation warning, unknown keys reported with a "did you mean", the typed [campaign] view
documents and the register read, and the manifest's SHA-256 in --json and the report."""

from __future__ import annotations

import datetime as dt
import hashlib
import json

import pytest

from metro.core.base import vocabulary as voc
from metro.core.run.manifest import load_manifest
from metro.core.base.errors import DataError
from metro.core.run.plugin_manager import get_plugin_manager


def _load(path):
    return load_manifest(path, get_plugin_manager(autoload=False).reader_for)


def _with_campaign(lines: str):
    return lambda t: t.replace('[campaign]\nid = "TEST-001"\noperator = "test"\n',
                               "[campaign]\nid = \"TEST-001\"\n" + lines)


def test_canonical_keys_fill_the_typed_view(tmp_path, campaign_factory):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05, manifest_edit=_with_campaign(
        'lab = "NIM inertial lab"\nlab_address = "18 Bei San Huan Dong Lu"\nlocation = "hall 3"\n'
        'customer = "Acme"\ncustomer_address = "1 Road"\noperator = "A. Tester"\nchecked_by = "B. '
        'Checker"\napproved_by = "C. Head"\napproved_by_title = "head of '
        'laboratory"\nmeasurement_date = 2026-11-20\ndate_received = "2026-11-01"\n'))
    c = _load(m)
    assert c.warnings == ()
    assert c.people == voc.People("A. Tester", "B. Checker", "C. Head", "head of laboratory")
    assert c.lab == voc.Lab("NIM inertial lab", "18 Bei San Huan Dong Lu", "hall 3")
    assert c.customer == voc.Customer("Acme", "1 Road")
    assert c.measurement_date == dt.date(2026, 11, 20)
    assert c.date_received == dt.date(2026, 11, 1)  # a date written as text is read as a date


@pytest.mark.parametrize("old, new, attr", [
    ('laboratory = "L"', "lab", lambda c: c.lab.name),
    ('laboratory_address = "L"', "lab_address", lambda c: c.lab.address),
    ('tested_by = "L"', "operator", lambda c: c.people.operator),
    ('calibrated_by = "L"', "operator", lambda c: c.people.operator),
    ('checker = "L"', "checked_by", lambda c: c.people.checked_by),
    ('issuer = "L"', "approved_by", lambda c: c.people.approved_by),
    ('issuer_title = "L"', "approved_by_title", lambda c: c.people.approved_by_title),
    ("date = 2026-11-20", "measurement_date", lambda c: c.measurement_date),
    ("received = 2026-11-20", "date_received", lambda c: c.date_received),
])
def test_old_spellings_are_read_with_a_deprecation_warning(tmp_path, campaign_factory, old, new,
                                                           attr):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=_with_campaign(old + "\n"))
    c = _load(m)
    assert attr(c) in ("L", dt.date(2026, 11, 20))
    (w,) = c.warnings
    key = old.split(" ")[0]
    assert "deprecated" in w and f"campaign.{key}" in w and repr(new) in w and str(m) in w


def test_both_spellings_of_one_key_are_an_error(tmp_path, campaign_factory):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=_with_campaign(
                                            'lab = "A"\nlaboratory = "B"\n'))
    with pytest.raises(DataError) as exc:
        _load(m)
    assert exc.value.file == str(m) and exc.value.field == "campaign.laboratory"


# (text of the manifest, what replaces it, the key the warning names, the key it suggests)
@pytest.mark.parametrize("old, new, field, guess", [
    ('operator = "test"', 'opertor = "test"', "campaign.opertor", "operator"),
    ("[site]", '[enviroment]\nx = 1\n\n[site]', "enviroment", "environment"),
    ('humidity = "45 %"', 'humidity = "45 %"\nhumdity = "45 %"', "environment.humdity",
     "humidity"),
    ("latitude_uncertainty", "latitude_uncertainity", "site.latitude_uncertainity",
     "latitude_uncertainty"),
    ("scale_factor_U =", "scale_factor_u =", "device.scale_factor_u", "scale_factor_U"),
    ('lab = "NIM"', 'lab = "NIM"\ncertficate_date = 2026-01-01',
     "equipment[1].calibration.certficate_date", None),
    ('file = "static.csv"', 'file = "static.csv"\nfiles = "x.csv"', "segments[0].files", "file"),
    ('role = "counter"', 'role = "countr"', "equipment[1].role", "counter"),
])
def test_unknown_keys_warn_with_did_you_mean(tmp_path, campaign_factory, old, new, field, guess):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=lambda t: t.replace(old, new))
    c = _load(m)
    (w,) = [w for w in c.warnings if f"'{field}'" in w]
    assert str(m) in w
    if guess:
        assert f"did you mean {guess!r}" in w


def test_a_property_that_is_not_a_misspelling_is_kept_without_a_warning(tmp_path, campaign_factory):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=lambda t: t.replace(
        'humidity = "45 %"', 'humidity = "45 %"\nvibration_level = "0.1 g"'))
    c = _load(m)
    assert c.warnings == () and "vibration_level" in c.environment


def test_a_plugin_registers_its_own_section(tmp_path, campaign_factory, monkeypatch):
    monkeypatch.setattr(voc, "SECTIONS", dict(voc.SECTIONS))
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=lambda t: t
                                        + '\n[insulation]\nvoltage = "500 V"\n')
    assert any("'insulation'" in w for w in _load(m).warnings)
    voc.register_section("insulation", "GB/T 45570 5.x insulation resistance")
    assert _load(m).warnings == ()


@pytest.mark.parametrize("given", ["rate-table", "table", "Rate Table", "RATE_TABLE", "ratetable"])
def test_roles_are_canonical_and_old_spellings_warn(tmp_path, campaign_factory, given):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=lambda t: t.replace(
        'role = "platform"', f'role = "{given}"'))
    c = _load(m)
    (eq,) = [e for e in c.equipment if e.id == "PLAT-1"]
    assert eq.role == "rate_table"
    assert c.equipment_for("rate-table") is eq and c.equipment_for("rate_table") is eq
    (w,) = c.warnings
    assert "equipment[0].role" in w and "'rate_table'" in w and "deprecated" in w


def test_every_role_an_item_requires_is_in_the_vocabulary():
    pm = get_plugin_manager(autoload=False)
    for info in pm.registry.procedures.values():
        for req in info.cls.equipment:
            assert req.role in voc.ROLES, (
                f"{info.cls.qualified_id()}: role {req.role!r} not in the vocabulary")


@pytest.mark.parametrize("edit, field", [
    (_with_campaign("measurement_date = \"20 Nov 2026\"\n"), "campaign.measurement_date"),
    (_with_campaign("operator = 42\n"), "campaign.operator"),
    (_with_campaign("lab = [\"a\"]\n"), "campaign.lab"),
    (_with_campaign("customer = \"" + "x" * 600 + "\"\n"), "campaign.customer"),
    (lambda t: t.replace('id = "LG-0042"', 'id = "' + "D" * 1_000_000 + '"'), "device.id"),
    (lambda t: t.replace('model = "RLG-90"', 'model = "' + "M" * 501 + '"'), "device.model"),
    (lambda t: t.replace('id = "LG-0042"', 'id = ""'), "device.id"),
    (lambda t: t.replace('id = "LG-0042"', 'id = "   "'), "device.id"),
    (lambda t: t.replace('id = "LG-0042"', 'id = "a\\u0000b"'), "device.id"),
    (lambda t: t.replace('id = "PLAT-1"', 'id = ""'), "equipment[0].id"),
])
def test_campaign_text_and_dates_are_checked(tmp_path, campaign_factory, edit, field):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05, manifest_edit=edit)
    with pytest.raises(DataError) as exc:
        _load(m)
    assert exc.value.file == str(m) and exc.value.field == field
    assert len(str(exc.value)) < 2000  # the message quotes no megabyte


def test_manifest_sha256_in_json_and_report(tmp_path, campaign_factory, run_cli):
    import docx

    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.2,
                                        manifest_edit=_with_campaign('tested_by = "X"\n'))
    digest = hashlib.sha256(m.read_bytes()).hexdigest()
    report = tmp_path / "out" / "r.docx"
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m), "--json",
                             "--report", str(report), "--no-progress")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["provenance"]["manifest"] == {"file": str(m), "sha256": digest}
    assert len(doc["manifest_warnings"]) == 1 and "tested_by" in doc["manifest_warnings"][0]
    assert "metro: warning:" in err and "tested_by" in err
    text = "\n".join(c.text for t in docx.Document(report).tables for r in t.rows for c in r.cells)
    assert digest in text


def test_the_simulated_stations_speak_the_vocabulary():
    """A campaign a built-in station writes reads back without a vocabulary warning: its
    equipment roles are canonical roles and its device keys are not near-misses of known keys."""
    from metro.core.run.manifest import _typos

    pm = get_plugin_manager(autoload=False)
    for name in sorted(pm.registry.stations):
        if name == "bench":  # a live bench: its equipment comes from the bench file
            continue
        st = pm.station(name).factory()
        for e in st.equipment():
            assert e.role in voc.ROLES, f"{name}: role {e.role!r}"
        dev = getattr(st, "device", None)
        dev = dev() if callable(dev) else dev
        if dev is not None:
            warnings: list[str] = []
            _typos(dict(dev.properties), "m.toml", "device", voc.DEVICE_KEYS, "device", warnings)
            assert warnings == [], f"{name}: {warnings}"

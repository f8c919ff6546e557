"""The lab profile: metro lab init/show, where the profile is found, and bad profiles."""

from __future__ import annotations

import json

import pytest

from metro.core.record import lab as labmod
from metro.core.cli.app import main
from metro.core.base.errors import DataError


def _init(tmp_path, capsys):
    path = tmp_path / "lab.toml"
    assert main(["lab", "init", str(path)]) == 0
    capsys.readouterr()
    return path


def test_init_then_show_json(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    path = _init(tmp_path, capsys)
    assert main(["--lab", str(path), "lab", "show", "--json"]) == 0
    doc = json.loads(capsys.readouterr().out)
    assert doc["name_en"] == "Example Metrology Laboratory" and doc["name_zh"] == "示例计量实验室"
    assert [s["role"] for s in doc["signatories"]] == ["calibrated_by", "checked_by", "approved_by"]
    assert doc["numbering"]["example"] == "EML2026-00001" and doc["numbering"]["per_year"] is True
    # the register file is relative to the profile
    assert doc["register"] == "sqlite:///" + str((tmp_path / "register.sqlite").resolve())
    assert doc["equipment"][0]["id"] == "RT-01" and doc["equipment"][0]["due"] == "2027-06-30"
    assert doc["timezone"] == "Asia/Shanghai"


def test_init_never_replaces(tmp_path, capsys):
    path = tmp_path / "lab.toml"
    path.write_text("mine", encoding="utf-8")
    assert main(["lab", "init", str(path)]) == 2
    assert "exists" in capsys.readouterr().err
    assert path.read_text(encoding="utf-8") == "mine"


def test_found_by_env_then_user_config(tmp_path, capsys, monkeypatch):
    path = _init(tmp_path, capsys)
    monkeypatch.setenv("METRO_LAB", str(path))
    assert labmod.find_lab_path(None) == path
    assert labmod.find_lab_path(tmp_path / "other.toml") == tmp_path / "other.toml"  # --lab wins
    monkeypatch.delenv("METRO_LAB")
    monkeypatch.setattr(labmod, "user_lab_path", lambda: tmp_path / "cfg" / "lab.toml")
    assert labmod.find_lab_path(None) is None
    assert main(["lab", "show"]) == 2
    assert "no lab profile in force" in capsys.readouterr().err
    (tmp_path / "cfg").mkdir()
    (tmp_path / "cfg" / "lab.toml").write_text(path.read_text(encoding="utf-8"), encoding="utf-8")
    assert labmod.find_lab_path(None) == tmp_path / "cfg" / "lab.toml"
    assert labmod.lab_in_force().prefix == "EML"


def test_register_env_overrides(tmp_path, capsys, monkeypatch):
    path = _init(tmp_path, capsys)
    monkeypatch.setenv("METRO_REGISTER", "postgresql+psycopg://metro:secret@db:5432/metro")
    p = labmod.load_lab(path)
    assert p.register_url() == "postgresql+psycopg://metro:secret@db:5432/metro"
    assert p.as_dict()["register"] == "postgresql+psycopg://metro:***@db:5432/metro"


@pytest.mark.parametrize("old,new,field,reason", [
    ('scheme = "{prefix}{year}-{seq:05d}"', 'scheme = "{prefix}{year}"',
     "numbering.scheme", "no {seq}"),
    ('scheme = "{prefix}{year}-{seq:05d}"', 'scheme = "{prefix}{month}-{seq}"',
     "numbering.scheme", "{month}"),
    ('scheme = "{prefix}{year}-{seq:05d}"', 'scheme = "{prefix}/{seq}"',
     "numbering.scheme", "file name"),
    ('role = "checked_by"', 'role = "checker"',
     "signatories[1].role", "checker"),
    ('timezone = "Asia/Shanghai"', 'timezone = "Mars/Olympus"',
     "lab.timezone", "Mars/Olympus"),
    ('language = "zh+en"', 'language = "fr"',
     "lab.language", "fr"),
    ('# logo = "logo.png"', 'logo = "logo.png"',
     "lab.logo", "not found"),
    ('name_zh = "示例计量实验室"', 'name_zh = "示例计量实验室"\ncolour = "red"',
     "lab.colour", "unknown key"),
    ('U = "5e-6"', 'U = "five"',
     "equipment[0].calibration.U", ""),
    ('due = 2027-06-30', 'due = "June"',
     "equipment[0].calibration.due", "not a date"),
    ('format = "metro-lab/1"', 'format = "metro-lab/9"',
     "format", "unsupported"),
    ('[lab]', '[lab]\n[lab.extra]',
     "lab.extra", "unknown key"),
    ('country = "CN"', 'country = "China"', "lab.country", "ISO 3166-1 alpha-2"),
    ('# verify_url = "https://lab.example/verify/"', 'verify_url = "lab.example/verify/"',
     "lab.verify_url", "not an http"),
    ('# verify_url = "https://lab.example/verify/"', 'verify_url = "ftp://lab.example/verify/"',
     "lab.verify_url", "not an http"),
    ('# verify_url = "https://lab.example/verify/"', 'verify_url = "https://lab.example/v?n="',
     "lab.verify_url", "query"),
    ('# verify_url = "https://lab.example/verify/"', 'verify_url = "https://lab.example/a b/"',
     "lab.verify_url", "space"),
])
def test_bad_profile_names_file_field_reason(tmp_path, capsys, old, new, field, reason):
    path = _init(tmp_path, capsys)
    text = path.read_text(encoding="utf-8")
    assert old in text
    path.write_text(text.replace(old, new, 1), encoding="utf-8")
    with pytest.raises(DataError) as exc:
        labmod.load_lab(path)
    assert exc.value.file == str(path) and exc.value.field == field and reason in exc.value.reason
    assert main(["--lab", str(path), "lab", "show", "--json"]) == 2
    out = capsys.readouterr()
    doc = json.loads(out.out)
    assert doc["file"] == str(path) and doc["field"] == field
    assert "Traceback" not in out.err


def test_missing_name_and_not_toml(tmp_path, capsys):
    path = tmp_path / "lab.toml"
    path.write_text('format = "metro-lab/1"\n[lab]\naddress = "x"\n', encoding="utf-8")
    with pytest.raises(DataError, match="no name"):
        labmod.load_lab(path)
    path.write_text("[lab\n", encoding="utf-8")
    with pytest.raises(DataError, match="not valid TOML"):
        labmod.load_lab(path)
    with pytest.raises(DataError, match="not found"):
        labmod.load_lab(tmp_path / "nope.toml")


def test_profile_api(tmp_path, capsys):
    p = labmod.load_lab(_init(tmp_path, capsys))
    assert p.signatory("approved_by").name == "王五" and p.signatory(
        "approved_by").title == "技术负责人"
    assert p.format_number(42, 2027) == "EML2027-00042"
    assert set(p.equipment_by_id()) == {"RT-01"}
    with pytest.raises(ValueError):
        labmod.Signatory(name="x", role="boss")
    with pytest.raises(ValueError):
        labmod.LabProfile(name_en="x", scheme="{prefix}")
    assert p.verify_url == ""  # the template leaves it commented out: no QR code


def test_verify_url_is_read(tmp_path, capsys):
    """``[lab] verify_url``, the base of the verify link a registered report prints as QR code."""
    path = _init(tmp_path, capsys)
    text = path.read_text(encoding="utf-8")
    path.write_text(text.replace('# verify_url = "https://lab.example/verify/"',
                                 'verify_url = "http://10.0.0.5:8000/verify"'), encoding="utf-8")
    assert labmod.load_lab(path).verify_url == "http://10.0.0.5:8000/verify"


def test_the_labs_country_reaches_the_campaign_unless_the_campaign_names_one(tmp_path, capsys):
    """``country`` of the profile goes where a DCC's coreData reads it (the campaign's meta), as
    the lab's address does; a campaign's own ``country`` is kept."""
    import attrs

    from metro.core.record.registering import with_lab
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    lab = labmod.load_lab(_init(tmp_path, capsys))
    assert lab.country == "CN"
    rec = run_items(get_plugin_manager(autoload=False), "ogam", ["7.1"])
    assert rec.campaign.meta.get("country") is None
    assert with_lab(rec, lab).campaign.meta["country"] == "CN"
    named = attrs.evolve(rec, campaign=attrs.evolve(rec.campaign,
                                                    meta={**rec.campaign.meta, "country": "DE"}))
    assert with_lab(named, lab).campaign.meta["country"] == "DE"

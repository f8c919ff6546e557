"""The register on the command line: registered and unregistered runs, list/show/verify,
re-rendering, amendments, withdrawal, expired equipment and device history."""

from __future__ import annotations

import datetime as dt
import json
import math
import zipfile
from pathlib import Path

import pytest

from metro.core.cli.app import main

SIM_GBT = ["run", "-s", "gbt45570", "-i", "D.5.6", "--station-option", "duration_scale=0.05",
           "--no-progress"]
SIM_JJF = ["run", "-s", "jjf2014", "-i", "7.2.3", "--no-progress"]


def _docx_text(path) -> list[str]:
    import docx

    d = docx.Document(str(path))
    out = [p.text for p in d.paragraphs]
    for t in d.tables:
        out += ["|".join(c.text for c in r.cells) for r in t.rows]
    return out


def _json(capsys, *argv) -> tuple[int, dict]:
    code = main(list(argv) + ["--json"])
    out = capsys.readouterr().out
    return code, (json.loads(out) if out.strip() else {})


def test_runs_register_amend_withdraw_verify_report(lab, tmp_path, capsys, campaign_factory):
    year = dt.datetime.now(dt.timezone.utc).year
    out = tmp_path / "out"
    # a simulated run is not registered unless asked; its report says so
    code, doc = _json(capsys, *SIM_GBT, "--seed", "1", "--out", str(out))
    # a run exits 0, 3 or 4 by its verdict (README "Exit codes")
    assert code in (0, 3,
                    4) and doc["register"]["registered"] is False and doc[
                        "report_number"].startswith("MTR-")
    text = _docx_text(doc["report"])
    assert text[0].startswith("未登记（仿真运行）") and "Not registered (simulated run" in text[0]
    assert doc["report_number"] in text[0]
    # two standards on the simulator with --register-simulated, then a recorded campaign
    code, a = _json(capsys, *SIM_GBT, "--seed", "1", "--out", str(out), "--register-simulated")
    code2, b = _json(capsys, *SIM_JJF, "--seed", "2", "--out", str(out), "--register-simulated")
    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.5)
    code3, c = _json(capsys, "run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                     "--out", str(out))
    assert {code, code2, code3} <= {0, 3, 4}
    numbers = [x["report_number"] for x in (a, b, c)]
    assert numbers == [f"EML{year}-{i:05d}" for i in (1, 2, 3)]
    assert all(x["register"]["registered"] for x in (a, b, c))
    assert Path(a["report"]).name == f"EML{year}-00001.docx"
    # the context is made before the number is known: no placeholder is left anywhere
    from metro.core.record.registering import PENDING

    for part in zipfile.ZipFile(a["report"]).namelist():
        assert PENDING.encode() not in zipfile.ZipFile(a["report"]).read(part), part
    first = _docx_text(a["report"])
    # the template's language is zh+en: the statement in both
    assert first[0] == (f"登记报告 EML{year}-00001，示例计量实验室。 "
                        f"Registered report EML{year}-00001 of Example Metrology Laboratory.")
    # lab identity from the profile
    assert any("示例计量实验室 Example Metrology Laboratory" in t for t in first)

    code, lst = _json(capsys, "register", "list")
    assert [r["number"] for r in lst["reports"]] == numbers
    assert [r["number"] for r in _json(capsys, "register", "list", "--standard",
                                       "jjf2014")[1]["reports"]] == [numbers[1]]
    assert [r["number"] for r in _json(capsys, "register", "list", "--device",
                                       "0042")[1]["reports"]] == [numbers[2]]
    tomorrow = (dt.date.today() + dt.timedelta(days=2)).isoformat()
    assert _json(capsys, "register", "list", "--since", tomorrow)[1]["reports"] == []

    code, show = _json(capsys, "register", "show", numbers[2])
    assert show["device"] == {"id": "LG-0042", "manufacturer": "Acme Inertial", "model": "RLG-90",
                              "serial": "0042"}
    import hashlib

    assert show["manifest_sha256"] == hashlib.sha256(manifest.read_bytes()).hexdigest()
    assert show["simulated"] is False
    res = {r["key"]: r for r in show["results"]}
    run_res = {r["key"]: r for r in c["results"]}
    for key, r in run_res.items():  # the register keeps what the run reported
        assert res[key]["value"] == pytest.approx(r["value"], rel=1e-12)
        assert res[key]["reported"] == r["reported"] and res[key]["k"] == r["k"]
    assert show["audit"][0]["action"] == "issue"
    from metro.core.record.lab import load_lab
    from metro.core.record.register import open_register

    with open_register(load_lab(lab).register_url()) as reg:
        for n in numbers:
            ctx, _ = reg.context(n)
            assert PENDING not in json.dumps(ctx, ensure_ascii=False) and ctx["report_number"] == n
    assert any(e["id"] == "CNT-1" and e["valid"] is True for e in show["equipment"])
    assert show["provenance"]["data_files"][0]["sha256"] == c["provenance"]["data_files"][0][
        "sha256"]

    # metro report NUMBER: the same document again (every part of the .docx identical)
    code, rep = _json(capsys, "report", numbers[0], "--out", str(tmp_path / "again"))
    assert code == 0
    za, zb = zipfile.ZipFile(a["report"]), zipfile.ZipFile(rep["report"])
    assert za.namelist() == zb.namelist()
    assert [n for n in za.namelist() if za.read(n) != zb.read(n)] == []
    assert rep["template_changed"] is False
    assert main(["report", numbers[0], "--out", str(tmp_path / "again")]) == 2  # never replaces
    capsys.readouterr()

    # amendments: a new run on the manifest, then a re-issue of the stored content
    code, am1 = _json(capsys, "amend", numbers[2], "--reason", "customer name corrected", "--data",
                      str(manifest))
    code2, am2 = _json(capsys, "amend", am1["number"], "--reason", "typo in the serial number")
    assert (code, code2) == (0, 0)
    assert (am1["number"], am2["number"]) == (f"EML{year}-00004", f"EML{year}-00005")
    statuses = {r["number"]: (r["status"], r["supersedes"], r["superseded_by"])
                for r in _json(capsys, "register", "list")[1]["reports"]}
    assert statuses[numbers[2]] == ("superseded", None, am1["number"])
    assert statuses[am1["number"]] == ("superseded", numbers[2], am2["number"])
    assert statuses[am2["number"]] == ("issued", am1["number"], None)
    t5 = _docx_text(am2["report"])
    assert t5[1].endswith(f"This report replaces report {am1['number']}, which is superseded by "
                          "it. Reason: typo in the serial number")
    assert t5[1].startswith(f"本报告替代报告 {am1['number']}（该报告已被替代）。原因：typo in the "
                            "serial number")
    assert not any(am1["number"] in t for t in t5[2:])  # the old number printed nowhere else
    # a superseded report is not amended
    assert main(["amend", numbers[2], "--reason", "again"]) == 2
    assert "superseded" in capsys.readouterr().err

    code, wd = _json(capsys, "withdraw", numbers[1], "--reason", "wrong device")
    assert code == 0 and _json(capsys, "register", "show", numbers[1])[1]["status"] == "withdrawn"

    code, ver = _json(capsys, "register", "verify")
    assert code == 0 and ver["ok"] is True and len(ver["reports"]) == 5
    with open(a["report"], "ab") as fh:
        fh.write(b"\0")
    code, ver = _json(capsys, "register", "verify")
    assert code == 6 and ver["ok"] is False  # README "Exit codes": 6, a check found a problem
    assert {r["number"]: r["check"] for r in ver["reports"]}[numbers[0]] == "modified"


def test_expired_equipment_refuses_unless_allowed(lab, tmp_path, capsys, campaign_factory):
    manifest = campaign_factory.write_campaign(
        tmp_path / "camp", hours=0.5,
        manifest_edit=lambda t: t.replace("due = 2027-08-15", "due = 2025-01-01"))
    out = tmp_path / "out"
    args = ["run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), "--out", str(out)]
    assert main(args) == 2
    err = capsys.readouterr().err
    assert "CNT-1" in err and "2025-01-01" in err and "--allow-expired" in err
    assert not out.exists() or list(out.iterdir()) == []
    # nothing registered: not even the register was made
    code, listed = _json(capsys, "register", "list")
    assert code == 2 and listed["message"].startswith("no register at") and not (
        tmp_path / "register.sqlite").exists()
    code, doc = _json(capsys, *args, "--allow-expired")
    assert code in (0, 3, 4) and doc["register"]["registered"]
    text = _docx_text(doc["report"])
    assert text[1].startswith("按 --allow-expired 出具") and "Issued with --allow-expired" in text[
        1]
    assert "CNT-1" in text[1] and "2025-01-01" in text[1]
    show = _json(capsys, "register", "show", doc["report_number"])[1]
    assert show["allow_expired"] is True
    assert [e["valid"] for e in show["equipment"] if e["id"] == "CNT-1"] == [False]


def test_register_simulated_needs_a_lab(tmp_path, capsys, monkeypatch):
    monkeypatch.delenv("METRO_LAB", raising=False)
    import metro.core.record.lab as labmod

    monkeypatch.setattr(labmod, "user_lab_path", lambda: tmp_path / "none" / "lab.toml")
    assert main([*SIM_JJF, "--out", str(tmp_path / "o"), "--register-simulated"]) == 2
    assert "needs a lab profile" in capsys.readouterr().err
    assert not (tmp_path / "o").exists()


def test_cli_on_postgresql(lab, tmp_path, capsys, monkeypatch, pg_server):
    url = pg_server.new_database()
    monkeypatch.setenv("METRO_REGISTER", url)
    year = dt.datetime.now(dt.timezone.utc).year
    out = tmp_path / "out"
    numbers = []
    for seed in ("1", "2"):
        code, d = _json(capsys, *SIM_JJF, "--seed", seed, "--out", str(out), "--register-simulated")
        assert code == 0 and d["register"]["register"].startswith("postgresql+psycopg://metro@127.0.0.1")
        numbers.append(d["report_number"])
    assert numbers == [f"EML{year}-00001", f"EML{year}-00002"]
    assert [r["number"] for r in _json(capsys, "register", "list")[1]["reports"]] == numbers
    code, rep = _json(capsys, "report", numbers[1], "--out", str(tmp_path / "again"))
    assert _docx_text(rep["report"]) == _docx_text(out / f"{numbers[1]}.docx")
    # METRO_REGISTER took the place of the profile's file
    assert not (tmp_path / "register.sqlite").exists()


def test_history_flags_drift(lab, tmp_path, capsys):
    """Three calibrations of S1: 1.0 ± 0.2, 1.1 ± 0.2, 2.0 ± 0.3 (U, k = 2).  E_n (hand-worked):
    |1.1 − 1.0| / √(0.2² + 0.2²) = 0.354 (no drift),
    |2.0 − 1.1| / √(0.2² + 0.3²) = 2.496 (drift)."""
    from metro.core.record.lab import load_lab
    from metro.core.record.register import Draft, open_register

    profile = load_lab(lab)
    reg = open_register(profile.register_url())
    for day, value, U in ((1, 1.0, 0.2), (2, 1.1, 0.2), (3, 2.0, 0.3)):
        fields = {"standard": "std", "items": ["A.1"], "options": {}, "device_id": "d",
                  "device_manufacturer": "m",
                  "device_model": "M", "device_serial": "S1", "customer": "",
                  "measurement_date": dt.date(2026, 1, day),
                  "simulated": False, "allow_expired": False, "lab": {}, "verdicts": None,
                  "budgets": [],
                  "provenance": {}, "manifest_sha256": None, "equipment": [], "template": "",
                  "context": {}}
        result = {"item": "A.1", "key": "bias", "quantity": "bias", "symbol": "B", "value": value,
                  "u": U / 2,
                  "U": U, "k": 2.0, "nu_eff": None, "unit": "°/h", "value_text": str(value),
                  "U_text": str(U),
                  "reportable": True, "reason": ""}
        reg.issue(lambda n, t, f=fields, r=result: Draft(f, [r], lambda tmp: tmp.write_text("x")),
                  folder=tmp_path / "out", scheme=profile.format_number, per_year=True)
    reg.close()
    code, hist = _json(capsys, "history", "S1", "--out", str(tmp_path / "h"))
    assert code == 0 and len(hist["calibrations"]) == 3
    (res,) = hist["results"]
    ens = [p.get("E_n") for p in res["points"]]
    assert ens[0] is None
    assert ens[1] == pytest.approx(0.1 / math.sqrt(0.08),
                                   rel=1e-9) and res["points"][1]["drift"] is False
    assert ens[2] == pytest.approx(0.9 / math.sqrt(0.13),
                                   rel=1e-9) and res["points"][2]["drift"] is True
    assert res["drift"] is True
    png = Path(hist["plot"])
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert main(["history", "S1", "--out", str(tmp_path / "h2")]) == 0
    assert "DRIFT" in capsys.readouterr().out
    assert main(["history", "NOPE", "--out", str(tmp_path / "h3")]) == 2


def test_manifest_names_lab_equipment_by_id(lab, tmp_path, capsys, campaign_factory):
    """CNT-1 given by id alone: its calibration comes from the lab profile; an id the profile does
    not know, without a role, is an error naming the field."""
    text = lab.read_text(encoding="utf-8").replace('id = "RT-01"', 'id = "CNT-9"').replace(
        'role = "rate_table"', 'role = "counter"').replace('certificate = "CAL-2026-0001"',
                                                           'certificate = "LAB-CNT-9"')
    lab.write_text(text, encoding="utf-8")

    def by_id(t: str, ident: str) -> str:
        start = t.index('[[equipment]]\nid = "CNT-1"')
        end = t.index("[[segments]]")
        return t[:start] + f'[[equipment]]\nid = "{ident}"\n\n' + t[end:]

    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.5,
                                               manifest_edit=lambda t: by_id(t, "CNT-9"))
    code, doc = _json(capsys, "run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                      "--out",
                      str(tmp_path / "out"))
    assert code == 0
    show = _json(capsys, "register", "show", doc["report_number"])[1]
    (cnt,) = [e for e in show["equipment"] if e["id"] == "CNT-9"]
    assert (cnt["role"], cnt["certificate"], cnt["due"],
            cnt["valid"]) == ("counter", "LAB-CNT-9", "2027-06-30", True)
    assert any("LAB-CNT-9" in t for t in _docx_text(doc["report"]))
    bad = campaign_factory.write_campaign(tmp_path / "camp2", hours=0.5,
                                          manifest_edit=lambda t: by_id(t, "CNT-404"))
    code, err = _json(capsys, "run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(bad), "--out",
                      str(tmp_path / "o2"))
    assert code == 2 and err["field"] == "equipment[1].role" and "CNT-404" in err["message"]
    # the profile's equipment past its due date refuses the run before anything is evaluated
    lab.write_text(text.replace("due = 2027-06-30", "due = 2020-01-01"), encoding="utf-8")
    assert main(["run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), "--out",
                 str(tmp_path / "o3")]) == 2
    assert "LAB-CNT-9" in capsys.readouterr().err and not (tmp_path / "o3").exists()


def test_statement_follows_the_lab_language(lab, tmp_path, capsys):
    lab.write_text(lab.read_text(encoding="utf-8").replace('language = "zh+en"', 'language = "en"'),
                   encoding="utf-8")
    year = dt.datetime.now(dt.timezone.utc).year
    code, d = _json(capsys, *SIM_JJF, "--seed", "4", "--out", str(tmp_path / "o"),
                    "--register-simulated")
    assert _docx_text(d["report"])[
        0] == f"Registered report EML{year}-00001 of Example Metrology Laboratory."
    code, a = _json(capsys, "amend", d["report_number"], "--reason", "re-issued")
    assert _docx_text(a["report"])[:2] == [
        f"Registered report EML{year}-00002 of Example Metrology Laboratory.",
        f"This report replaces report EML{year}-00001, which is superseded by it. "
        "Reason: re-issued"]


def test_registration_problems_are_said_before_evaluating(lab, tmp_path, capsys, monkeypatch):
    """--report PATH with a registered run, and --register-simulated without a profile, are refused
    before any item is evaluated."""
    import metro.core.run.runner as runner

    calls = []
    real = runner.judge
    monkeypatch.setattr(runner, "judge", lambda *a, **k: calls.append(1) or real(*a, **k))
    assert main([*SIM_JJF, "--register-simulated", "--report", str(tmp_path / "r.docx")]) == 2
    assert "--report PATH cannot be used" in capsys.readouterr().err
    monkeypatch.delenv("METRO_LAB")
    import metro.core.record.lab as labmod

    monkeypatch.setattr(labmod, "user_lab_path", lambda: tmp_path / "none" / "lab.toml")
    assert main([*SIM_JJF, "--register-simulated", "--out", str(tmp_path / "o")]) == 2
    assert "needs a lab profile" in capsys.readouterr().err
    assert calls == [] and not (tmp_path / "r.docx").exists() and not (tmp_path / "o").exists()

"""A registered report issued as a DCC: a recorded campaign run with a lab profile and
``--format dcc`` writes the Word report and its DCC (valid against ../shared/reference/dcc, the
report's PDF embedded) in one transaction, the register keeps the DCC's SHA-256 and ``register
verify`` checks it; ``metro report NUMBER --format dcc`` writes the same DCC again; an amendment's
DCC states the replacement; a withdrawn report is never issued as a DCC; a unit with no D-SI
mapping takes no number, and a DCC failing inside the transaction leaves no file and no row; a
register written before DCCs is brought up to date and still read."""

from __future__ import annotations

import datetime as dt
import hashlib
import json
import runpy
from pathlib import Path
from types import SimpleNamespace

from metro.core.cli.app import main

ROOT = Path(__file__).resolve().parents[3]
SIM = ["run", "-s", "gbt45570", "-i", "D.5.6", "--station-option", "duration_scale=0.05",
       "--no-progress", "--seed", "1", "--register-simulated"]


#: tests/dcc_reference.py: the reference schemas, readers of a DCC, the skip marks
REF = SimpleNamespace(**runpy.run_path(str(ROOT / "tests" / "dcc_reference.py")))
needs_reference, needs_soffice = REF.needs_reference, REF.needs_soffice
unmapped_hour = REF.unmapped_hour  # a fixture: °/h has no D-SI mapping


def _json(capsys, *argv: str) -> tuple[int, dict]:
    code = main([*argv, "--json"])
    out = capsys.readouterr()
    assert "Traceback" not in out.err, out.err
    return code, json.loads(out.out) if out.out.strip() else {}


def _valid(name: str, doc: dict) -> None:
    from metro.core.cli.schemas import validator

    errors = [f"{list(e.absolute_path)}: {e.message}" for e in validator(name).iter_errors(doc)]
    assert not errors, errors[:5]


def _sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@needs_reference
@needs_soffice
def test_recorded_campaign_dcc_registered_verified_and_written_again(lab, tmp_path, capsys,
                                                                      campaign_factory):
    year = dt.datetime.now(dt.timezone.utc).year
    out = tmp_path / "out"
    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.3)
    code, run = _json(capsys, "run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                      "--no-progress", "--format", "dcc", "--out", str(out), "--pdf")
    assert code in (0, 3, 4)
    _valid("run", run)
    number = run["report_number"]
    assert number == f"EML{year}-00001" and run["register"]["registered"] is True
    xml = out / f"{number}.xml"
    assert sorted(p.name for p in out.iterdir()) == [f"{number}.{s}" for s in ("docx", "pdf",
                                                                                "xml")]
    REF.validate(xml)
    assert REF.core_text(xml, f"{REF.DCC}uniqueIdentifier") == number
    # the PDF it embeds is the one --pdf wrote beside the Word report (one conversion)
    assert REF.embedded_pdf(xml) == (out / f"{number}.pdf").read_bytes()
    assert REF.embedded_pdf(xml).startswith(b"%PDF-")
    # the register keeps the DCC's path and SHA-256
    digest = _sha256(xml)
    assert run["register"]["dcc"] == {"path": str(xml.resolve()), "sha256": digest}
    code, show = _json(capsys, "register", "show", number)
    _valid("register-show", show)
    assert (show["dcc_path"], show["dcc_sha256"]) == (str(xml.resolve()), digest)
    assert show["report_sha256"] == _sha256(out / f"{number}.docx")
    assert [a["action"] for a in show["audit"]] == ["issue", "dcc"]
    # verify: both files ok, then the DCC altered is found
    code, ver = _json(capsys, "register", "verify")
    _valid("register-verify", ver)
    assert code == 0 and ver["ok"] is True
    assert [(r["file"], r["check"]) for r in ver["reports"]] == [("report", "ok"), ("dcc", "ok")]
    xml.write_bytes(xml.read_bytes().replace(b"</dcc:digitalCalibrationCertificate>",
                                             b"<!-- x --></dcc:digitalCalibrationCertificate>"))
    code, ver = _json(capsys, "register", "verify")
    assert code == 6 and ver["ok"] is False
    bad = [r for r in ver["reports"] if r["check"] != "ok"]
    assert [(r["file"], r["check"], r["sha256_stored"]) for r in bad] == [("dcc", "modified",
                                                                           digest)]
    # metro report NUMBER --format dcc: the same DCC from the register (its PDF made again)
    code, rep = _json(capsys, "report", number, "--format", "dcc", "--out", str(tmp_path / "again"))
    _valid("report", rep)
    again = tmp_path / "again" / f"{number}.xml"
    assert code == 0 and rep["report"] == str(again)
    assert rep["dcc"] == {"path": str(again), "sha256": _sha256(again)}
    REF.validate(again)
    xml.write_bytes(xml.read_bytes().replace(b"<!-- x -->", b""))
    assert _sha256(xml) == digest
    assert REF.without_pdf(again) == REF.without_pdf(xml)
    assert REF.embedded_pdf(again).startswith(b"%PDF-")
    # never over an existing file
    assert main(["report", number, "--format", "dcc", "--out", str(tmp_path / "again")]) == 2
    assert "never replaces" in capsys.readouterr().err
    assert _sha256(again) == rep["dcc"]["sha256"]


@needs_reference
@needs_soffice
def test_amendment_dcc_and_withdrawn_report(lab, tmp_path, capsys):
    out = tmp_path / "out"
    code, first = _json(capsys, *SIM, "--format", "dcc", "--out", str(out))
    old = first["report_number"]
    # an amendment of a report issued with a DCC gets one, stating what it replaces
    code, am = _json(capsys, "amend", old, "--reason", "customer name corrected")
    _valid("amend", am)
    assert code == 0 and am["supersedes"] == old
    new_xml = Path(am["dcc"]["path"])
    assert new_xml == (out / f"{am['number']}.xml").resolve() and am["dcc"]["sha256"] == _sha256(
        new_xml)
    REF.validate(new_xml)
    ras = f"{REF.DCC}reportAmendedSubstituted/"
    assert REF.core_text(new_xml, f"{ras}{REF.DCC}replacedUniqueIdentifier") == old
    assert REF.core_text(new_xml, f"{ras}{REF.DCC}typeOfChange")
    assert REF.core_text(new_xml, f"{REF.DCC}uniqueIdentifier") == am["number"]
    assert REF.core_text(out / f"{old}.xml", f"{REF.DCC}reportAmendedSubstituted") is None
    # --format docx: the next amendment without a DCC
    code, am2 = _json(capsys, "amend", am["number"], "--reason", "typo", "--format", "docx")
    assert code == 0 and "dcc" not in am2 and not (out / f"{am2['number']}.xml").exists()
    code, show = _json(capsys, "register", "show", am2["number"])
    assert show["dcc_path"] is None and show["dcc_sha256"] is None
    # a withdrawn report is never issued as a DCC
    assert main(["withdraw", am2["number"], "--reason", "wrong device"]) == 0
    capsys.readouterr()
    again = tmp_path / "again"
    code = main(["report", am2["number"], "--format", "dcc", "--out", str(again)])
    err = capsys.readouterr().err
    assert code == 2 and "withdrawn" in err and "never issued as a DCC" in err
    assert not again.exists()
    code, ver = _json(capsys, "register", "verify")
    assert code == 0 and [r["file"] for r in ver["reports"]] == ["report", "dcc", "report", "dcc",
                                                                 "report"]


@needs_soffice
def test_a_unit_with_no_dsi_mapping_takes_no_number(lab, unmapped_hour, tmp_path, capsys):
    out = tmp_path / "out"
    code = main([*SIM, "--format", "dcc", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "has no D-SI mapping" in err and "Traceback" not in err
    assert not out.exists() or list(out.iterdir()) == []
    code, lst = _json(capsys, "register", "list")
    assert lst.get("reports", []) == []
    # the counter was not moved: the next report (a Word one) takes the first number
    code, run = _json(capsys, *SIM, "--out", str(out))
    assert run["report_number"].endswith("-00001")


@needs_soffice
def test_a_dcc_failing_in_the_transaction_leaves_no_file_and_no_row(lab, tmp_path, capsys,
                                                                     monkeypatch):
    from metro.core.base.errors import MetroError
    from metro.core.record import dcc_out

    def broken(docx):  # the PDF conversion fails once the Word file is written
        raise MetroError("LibreOffice could not convert the report (test)")

    monkeypatch.setattr(dcc_out, "docx_pdf", broken)
    out = tmp_path / "out"
    code = main([*SIM, "--format", "dcc", "--out", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and "could not convert the report (test)" in err and "Traceback" not in err
    # neither the Word file nor the DCC, nor a temporary one, and no row
    assert list(out.iterdir()) == []
    assert _json(capsys, "register", "list")[1]["reports"] == []


def test_a_register_written_before_dccs_is_migrated_and_read(tmp_path, draft_rows):
    from alembic import command
    from alembic.config import Config
    from sqlalchemy import create_engine

    from metro.core.record import register as regmod
    from metro.core.record.register import Draft, open_register

    url = "sqlite:///" + str(tmp_path / "register.sqlite")
    fields, result = draft_rows()
    with open_register(url) as reg:
        issued = reg.issue(lambda n, t: Draft(fields, [result], lambda p: p.write_text("x")),
                           folder=tmp_path / "reports", scheme=lambda s, y: f"T{y}-{s:04d}",
                           per_year=True)
        assert issued.dcc_path is None
    # back to the schema before DCCs (revision 0001: no dcc columns)
    cfg = Config()
    cfg.set_main_option("script_location", str(Path(regmod.__file__).parent / "migrations"))
    engine = create_engine(url)
    with engine.begin() as conn:
        cfg.attributes["connection"] = conn
        command.downgrade(cfg, "0001")
    with engine.connect() as conn:
        cols = {r[1] for r in conn.exec_driver_sql("PRAGMA table_info(reports)")}
    engine.dispose()
    assert "dcc_sha256" not in cols and "report_sha256" in cols
    assert regmod.register_state(url)["revision"] == "0001"
    # this metro opens it: migrated to the newest revision, the old report read and verified
    with open_register(url, create=False) as reg:
        entry = reg.get(issued.number)
        checks = reg.verify()
    assert regmod.register_state(url)["revision"] == regmod.SCHEMA_HEAD == "0002"
    assert (entry["dcc_path"], entry["dcc_sha256"]) == (None, None)
    assert [(c["file"], c["check"]) for c in checks] == [("report", "ok")]

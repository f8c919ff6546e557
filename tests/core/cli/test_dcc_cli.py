"""DCC output on the command line, without a lab profile: ``metro run … --report cert.xml`` and
``--format dcc --out DIR`` write a DCC valid against the reference schema (../shared/reference/dcc)
with the report's PDF embedded, named with its SHA-256 in ``--json``; bad input (an unknown
``--format``, ``--format dcc`` without ``--out``, an existing ``.xml``, a unit with no D-SI
mapping) exits 2 with a clean message and writes nothing."""

from __future__ import annotations

import hashlib
import json
import runpy
from pathlib import Path
from types import SimpleNamespace

import pytest

from metro.core.cli.app import main

ROOT = Path(__file__).resolve().parents[3]
SIM = ["run", "-s", "gbt45570", "-i", "D.5.6", "--station-option", "duration_scale=0.05",
       "--no-progress", "--seed", "1"]


#: tests/dcc_reference.py: the reference schemas, readers of a DCC, the skip marks
REF = SimpleNamespace(**runpy.run_path(str(ROOT / "tests" / "dcc_reference.py")))
needs_reference, needs_soffice = REF.needs_reference, REF.needs_soffice
unmapped_hour = REF.unmapped_hour  # a fixture: °/h has no D-SI mapping


@pytest.fixture
def no_lab(monkeypatch):
    """No lab profile in force: reports are not registered."""
    monkeypatch.delenv("METRO_LAB", raising=False)
    monkeypatch.delenv("METRO_REGISTER", raising=False)


def _json(capsys, *argv: str) -> tuple[int, dict, str]:
    code = main([*argv, "--json"])
    out = capsys.readouterr()
    return code, json.loads(out.out) if out.out.strip() else {}, out.err


def _sha256(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


@needs_reference
@needs_soffice
def test_report_xml_writes_a_valid_dcc_with_its_pdf(no_lab, tmp_path, capsys):
    from metro.core.cli.schemas import validator

    cert = tmp_path / "certs" / "cert.xml"
    code, doc, err = _json(capsys, *SIM, "--report", str(cert), "--pdf")
    assert code == 0, err
    assert doc["register"]["registered"] is False and Path(doc["report"]) == cert
    # the JSON names the DCC and its SHA-256, and validates against the run schema
    assert doc["register"]["dcc"] == {"path": str(cert), "sha256": _sha256(cert)}
    assert not list(validator("run").iter_errors(doc))
    REF.validate(cert)
    assert REF.core_text(cert, f"{REF.DCC}uniqueIdentifier") == doc["report_number"]
    pdf = REF.embedded_pdf(cert)
    assert pdf.startswith(b"%PDF-")
    # --pdf: the same PDF beside the DCC (one conversion), and no Word file
    assert cert.with_suffix(".pdf").read_bytes() == pdf
    assert sorted(p.name for p in cert.parent.iterdir()) == ["cert.pdf", "cert.xml"]


@needs_reference
@needs_soffice
def test_format_dcc_out_writes_number_xml(no_lab, tmp_path, capsys):
    out = tmp_path / "out"
    code = main([*SIM, "--format", "dcc", "--out", str(out)])
    printed = capsys.readouterr()
    assert code == 0, printed.err
    [target] = list(out.iterdir())  # <report number>.xml, and no Word file
    assert target.suffix == ".xml"
    REF.validate(target)
    # the terminal names the DCC and its SHA-256
    assert f": DCC {target}" in " ".join(printed.out.split())
    assert f"DCC {target} (sha256 {_sha256(target)})\n" in printed.err  # one line


def _refused(capsys, tmp_path, *argv: str, says: str) -> str:
    """``metro …`` exits 2 with ``says`` in its message, no traceback, and writes nothing under
    ``tmp_path`` beyond what was there."""
    before = sorted(tmp_path.rglob("*"))
    code = main(list(argv))
    err = capsys.readouterr().err
    assert code == 2, err
    assert says in err and "Traceback" not in err, err
    assert sorted(tmp_path.rglob("*")) == before
    return err


def test_bad_format_options_are_refused_before_evaluation(no_lab, tmp_path, capsys):
    out = str(tmp_path / "out")
    _refused(capsys, tmp_path, *SIM, "--format", "pdf", "--out", out,
             says="argument --format: invalid choice: 'pdf'")
    _refused(capsys, tmp_path, *SIM, "--format", "dcc",
             says="--format dcc needs --out DIR")
    _refused(capsys, tmp_path, *SIM, "--format", "dcc", "--report", str(tmp_path / "a.xml"),
             says="--format goes with --out")
    _refused(capsys, tmp_path, *SIM, "--format", "dcc", "--out", out, "--no-report",
             says="--no-report writes no report")
    # an existing .xml is never replaced, not even with --force
    cert = tmp_path / "cert.xml"
    cert.write_text("someone else's certificate", encoding="utf-8")
    _refused(capsys, tmp_path, *SIM, "--report", str(cert), "--force",
             says="never replaces a DCC file")
    assert cert.read_text(encoding="utf-8") == "someone else's certificate"
    # the JSON error document names the problem
    code, doc, _ = _json(capsys, *SIM, "--format", "dcc")
    assert code == 2 and "--format dcc needs --out" in doc["message"]


@needs_soffice
def test_a_unit_with_no_dsi_mapping_writes_nothing(no_lab, unmapped_hour, tmp_path, capsys):
    out = tmp_path / "out"
    out.mkdir()
    err = _refused(capsys, tmp_path, *SIM, "--format", "dcc", "--out", str(out),
                   says="has no D-SI mapping")
    assert "°/h" in err
    _refused(capsys, tmp_path, *SIM, "--report", str(tmp_path / "cert.xml"),
             says="has no D-SI mapping")

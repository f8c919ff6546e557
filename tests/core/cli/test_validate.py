"""``metro validate``: every case passes on this install (exit 0), the --json document validates
against its schema, the report is written (and registered with a lab profile, in a counter of its
own), and a broken formula makes validate fail (exit 6) naming the case."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest

jsonschema = pytest.importorskip("jsonschema")


def _main(*argv: str) -> tuple[int, str, str]:
    from metro.core.cli.app import main

    out, err = io.StringIO(), io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
        code = main(list(argv))
    return code, out.getvalue(), err.getvalue()


def _lab(tmp_path: Path) -> Path:
    from metro.core.record.lab import write_template

    lab = write_template(tmp_path / "lab.toml")
    text = lab.read_text(encoding="utf-8").replace('language = "zh+en"', 'language = "en"')
    lab.write_text(text, encoding="utf-8")
    return lab


def test_validate_quick_passes_registers_and_its_json_validates(tmp_path, monkeypatch):
    from metro.core.cli.schemas import SCHEMA_VERSION, validator

    monkeypatch.delenv("METRO_REGISTER", raising=False)
    monkeypatch.setenv("METRO_LAB", str(_lab(tmp_path)))
    code, out, _ = _main("validate", "--quick", "--no-pdf", "--out", str(tmp_path / "out"),
                         "--json")
    doc = json.loads(out)
    v = validator("validate")
    errors = [f"{list(e.absolute_path)}: {e.message}" for e in v.iter_errors(doc)]
    assert not errors, errors[:5]
    assert code == 0 and doc["ok"] and doc["schema_version"] == SCHEMA_VERSION
    assert doc["counts"]["fail"] == doc["counts"]["error"] == 0
    ids = {c["id"] for c in doc["cases"]}
    # every kind of case the issue names is there
    for prefix in ("nist:", "allan:", "units:", "jcgm101:", "within-u:", "gbt45570:", "jjf2014:",
                   "jjf2003:", "ogam:"):
        assert any(i.startswith(prefix) for i in ids), prefix
    # each standard's worked examples come from its own plugin, through the hook
    assert {c["plugin"] for c in doc["cases"] if c["id"].startswith("jjf2003:")} == {"jjf2003"}
    rep = doc["report"]
    # the first validation record: its own counter (the lab's scheme behind VAL-)
    assert rep["registered"] and rep["number"].startswith("VAL-EML")
    assert rep["number"].endswith("-00001")
    assert Path(rep["docx"]).is_file() and rep["pdf"] is None
    # registered as a record of its own kind: a validation counter, the standard metro-validate
    from metro.core.record.lab import load_lab
    from metro.core.record.register import open_register

    lab = load_lab(Path(tmp_path / "lab.toml"))
    with open_register(lab.register_url()) as reg:
        row = reg.get(rep["number"])
    assert row["standard"] == "metro-validate" and row["scope"].startswith("validation:")
    assert len(row["results"]) == len(doc["cases"])
    # the report in the lab's language (en), with the lab's name and every case id
    import docx

    d = docx.Document(rep["docx"])
    text = "\n".join(c.text for t in d.tables for r in t.rows for c in r.cells)
    assert "Example Metrology Laboratory" in text and "示例" not in text
    assert "nist:norris" in text and "jcgm101:9.3-mass" in text
    assert "metro.core/validation/case.py" in text


def test_a_broken_formula_makes_validate_fail_and_name_the_case(tmp_path, monkeypatch):
    """The ogam plugin's zero-drift term (appendix A 4.3) made twice too large: exit 6, and the
    worked-example case that uses it is named on stdout; metro's own cases still pass."""
    from metro.core.validation import coverage, jcgm101
    from metro.plugins.ogam import formulas

    monkeypatch.delenv("METRO_LAB", raising=False)
    monkeypatch.setattr(coverage, "coverage_cases", lambda pm, quick=False: [])  # time
    monkeypatch.setattr(jcgm101, "jcgm101_cases", lambda: [])
    real = formulas.zero_drift_error
    monkeypatch.setattr(formulas, "zero_drift_error", lambda *a: 2 * real(*a))
    code, out, _ = _main("validate", "--quick", "--no-pdf", "--out", str(tmp_path))
    assert code == 6
    failed = [ln.split()[1] for ln in out.splitlines() if ln.startswith("FAIL")]
    assert "ogam:A-tilt" in failed and all(f.startswith("ogam:") for f in failed)
    assert "drift term" in out and "NOT validated" in out


def test_the_progress_line_fits_the_terminal(monkeypatch, capsys):
    """One line redrawn in place, never wider than the terminal (a long case id is cut)."""
    import os

    from metro.core.cli.validate_command import ProgressLine
    from metro.core.validation.case import ValidationCase

    monkeypatch.setattr("shutil.get_terminal_size", lambda fallback=None: os.terminal_size((30, 5)))
    prog = ProgressLine(True)
    case = ValidationCase("x:" + "long-id-" * 10, "t", "s", [1.0], lambda: 1.0)
    prog(1, 2, case)
    prog(1, 2, case.run())
    err = capsys.readouterr().err
    lines = err.split("\r")[1:]
    assert lines and all(len(ln) <= 29 for ln in lines)
    assert lines[0].startswith("[1/2] …") and lines[1].startswith("[1/2] ok")

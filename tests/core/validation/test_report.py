"""The validation report (metro.core.validation.report) and its register record
(metro.core.validation.registering): the lab's identity in its language, every case with its
reference, tolerance, result and verdict, the software, the files' SHA-256; registered in a
counter of its own, beside the calibration reports' numbers."""

from __future__ import annotations

import datetime as dt
import hashlib
from pathlib import Path

import docx
import pytest

from metro.core.validation.case import ValidationCase
from metro.core.validation.suite import ValidationRun

ENV = {"metro": "9.9.9", "plugins": {"vendorx": "vendorx 1.2"}, "python": "CPython 3.11.7",
       "libraries": {"numpy": "2.0.0", "scipy": "1.14.0"}, "platform": "Linux-test",
       "machine": "x86_64", "executable": "/usr/bin/python"}


def _run() -> ValidationRun:
    good = ValidationCase("vendorx:A.1", "appendix A.1", "VX-001 appendix A.1", ["2.12e-04", 0.5],
                          lambda: ["2.12e-04", 0.5], rtol=1e-12, labels=("u_c", "k"),
                          plugin="vendorx").run()
    bad = ValidationCase("nist:norris", "straight line", "NIST StRD Norris", [1.0],
                         lambda: [1.5], rtol=1e-12, labels=("B1",), plugin="metro").run()
    files = [{"path": "metro.core/x.py", "sha256": hashlib.sha256(b"x").hexdigest()}]
    return ValidationRun([bad, good], dt.datetime(2026, 11, 29, 7, 0, tzinfo=dt.timezone.utc),
                         12.0, False, ENV, files)


def _text(path: Path) -> str:
    d = docx.Document(str(path))
    parts = [p.text for p in d.paragraphs]
    parts += [c.text for t in d.tables for r in t.rows for c in r.cells]
    return "\n".join(parts).replace("\xa0", " ")  # the builder glues numbers to units


@pytest.mark.parametrize("lang", ["zh", "en"])
def test_the_report_gives_every_case_the_software_and_the_files(tmp_path, lang):
    from metro.core.record.lab import LabProfile
    from metro.core.validation.report import write_validation_report

    lab = LabProfile(name_zh="示例实验室", name_en="Example Lab", address="1 Road",
                     accreditation_body="CNAS", accreditation_number="L0001")
    path = write_validation_report(tmp_path / "v.docx", _run(), number="VAL-1", lang=lang,
                                   lab=lab)
    text = _text(path)
    assert ("示例实验室" in text) == (lang == "zh") and ("Example Lab" in text) == (lang == "en")
    assert "CNAS L0001" in text and "VAL-1" in text
    # each case: its source, then per value the reference, result, tolerance and verdict
    assert "VX-001 appendix A.1" in text and "NIST StRD Norris" in text
    assert "2.12×10⁻⁴" in text and "1.5" in text  # printed in the one notation of reports
    verdicts = ("通过", "不通过") if lang == "zh" else ("pass", "FAIL")
    assert all(v in text for v in verdicts)
    assert ("未确认" if lang == "zh" else "NOT validated") in text
    # the software and the annex
    for v in ("9.9.9", "vendorx 1.2", "CPython 3.11.7", "2.0.0", "1.14.0", "Linux-test"):
        assert v in text, v
    assert hashlib.sha256(b"x").hexdigest() in text and "metro.core/x.py" in text
    assert ("相对" in text) == (lang == "zh")


def test_a_validation_record_is_numbered_apart_from_the_reports(tmp_path, monkeypatch):
    """The validation report takes VAL- and a counter of its own: a calibration report issued
    after it is still number 1 of its year, and the register verifies both files."""
    from metro.core.record.lab import load_lab, write_template
    from metro.core.record.register import Draft, open_register
    from metro.core.validation.registering import register_validation

    monkeypatch.delenv("METRO_REGISTER", raising=False)
    lab = load_lab(write_template(tmp_path / "lab.toml"))
    issued = register_validation(_run(), lab, tmp_path / "out")
    year = issued.issued_at.year
    assert issued.number == f"VAL-EML{year}-00001" and issued.scope == f"validation:{year}"
    assert "nist:norris" in _text(issued.path)

    with open_register(lab.register_url()) as reg:
        row = reg.get(issued.number)
        assert row["standard"] == "metro-validate" and row["verdicts"]["overall"] == "fail"
        assert [r["item"] for r in row["results"]] == ["nist:norris", "vendorx:A.1"]
        other = reg.issue(lambda n, at: Draft(fields=row_fields(), results=[],
                                              write=lambda p: p.write_bytes(b"report")),
                          folder=tmp_path / "out", scheme=lab.format_number,
                          per_year=lab.per_year(), timezone=lab.timezone)
        assert other.number == f"EML{year}-00001" and other.scope == str(year)
        assert [v["check"] for v in reg.verify()] == ["ok", "ok"]
        # kept as issued: metro report / amend say what it is instead of looking for a template
        from metro.core.base.errors import MetroError
        from metro.core.record.registering import rerender
        from metro.core.run.plugin_manager import builtin_plugin_manager

        with pytest.raises(MetroError, match="software validation record"):
            rerender(reg, issued.number, tmp_path / "again", pm=builtin_plugin_manager())


def row_fields() -> dict:
    return {"standard": "gbt45570", "items": ["D.5.1"], "measurement_date": dt.date(2026, 11, 29)}

"""``metro lab equipment import CERT.xml`` on the command line: a provider's DCC imports, a run
whose manifest names the equipment by id uses it and its budget row names the certificate, and
each malformed certificate is refused with exit code 2, the file, the element path and the
reason, no traceback, and nothing written."""

from __future__ import annotations

import datetime as dt
import json
import re
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
REFERENCE = ROOT.parent / "shared" / "reference" / "dcc"
DATA = ROOT / "tests" / "data" / "dcc"
MALFORMED = tomllib.loads((DATA / "malformed.toml").read_text(encoding="utf-8"))


@pytest.fixture
def cert(tmp_path, lab, monkeypatch) -> Path:
    """tests/data/dcc/counter_dcc.xml due a year from today (the reference schemas in force)."""
    pytest.importorskip("xmlschema")
    if not (REFERENCE / "dcc.xsd").is_file():
        pytest.skip(f"the reference DCC schemas are not in {REFERENCE} (CI has them)")
    monkeypatch.setenv("METRO_DCC_SCHEMA", str(REFERENCE))
    path = tmp_path / "counter_dcc.xml"
    path.write_text(_due_in_a_year((DATA / "counter_dcc.xml").read_text(encoding="utf-8")),
                    encoding="utf-8")
    return path


def _due_in_a_year(text: str) -> str:
    due = dt.date.today() + dt.timedelta(days=365)
    return text.replace("<dcc:date>2027-03-10</dcc:date>",
                        f"<dcc:date>{due.isoformat()}</dcc:date>")


def test_import_then_a_run_names_the_certificate(lab, cert, run_cli, tmp_path, campaign_factory):
    code, out, err = run_cli("lab", "equipment", "import", str(cert), "--role", "counter")
    assert code == 0, err
    store = lab.parent / "lab.equipment" / "CNT-7.toml"
    assert f"written: {store}" in out and "TFL-2026-04417" in out
    code, out, _ = run_cli("lab", "show", "--json")
    (cnt,) = [e for e in json.loads(out)["equipment"] if e["id"] == "CNT-7"]
    assert (cnt["certificate"], cnt["role"], cnt["k"]) == ("TFL-2026-04417", "counter", 2.0)

    def by_id(t: str) -> str:  # the manifest names the imported counter by its id alone
        start = t.index('[[equipment]]\nid = "CNT-1"')
        return t[:start] + '[[equipment]]\nid = "CNT-7"\n\n' + t[t.index("[[segments]]"):]

    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.5, manifest_edit=by_id)
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                             "--out", str(tmp_path / "out"), "--json")
    assert code == 0, err
    doc = json.loads(out)
    due = re.search(r"<dcc:date>(.*)</dcc:date>", cert.read_text(encoding="utf-8")).group(1)
    (eq,) = [e for e in doc["equipment"] if e["id"] == "CNT-7"]
    assert eq["status"] == f"certificate TFL-2026-04417, valid until {due}"
    rows = [r for b in doc["budgets"] for r in b["rows"] if "counter" in r["source"]]
    assert rows and all("TFL-2026-04417" in r["note"] for r in rows)
    assert {(r["value"], r["divisor"]) for r in rows} == {(2e-7, 2.0)}


def test_dry_run_writes_nothing(lab, cert, run_cli):
    code, out, _ = run_cli("lab", "equipment", "import", str(cert), "--role", "timer", "--id",
                           "TB-1", "--dry-run")
    assert code == 0 and "would import TB-1 (timer" in out
    # a role a plugin registers (GB/T 45570's insulation tester: relative or in ohm)
    code, out, err = run_cli("lab", "equipment", "import", str(cert), "--role", "megohmmeter",
                             "--id", "MEG-1", "--dry-run")
    assert code == 0 and "would import MEG-1 (megohmmeter" in out and "U = 2e-07" in out, err
    assert not (lab.parent / "lab.equipment").exists()


def _malformed(case: dict) -> str:
    """The case's certificate; still due a year from now unless the case edits the due date."""
    if "text" in case:
        return case["text"]
    text = (DATA / "counter_dcc.xml").read_text(encoding="utf-8")
    for pattern, new in case["edit"]:
        text = re.sub(pattern, lambda m, new=new: new, text, flags=re.S)
    return _due_in_a_year(text)


@pytest.mark.parametrize("case", MALFORMED["case"], ids=lambda c: c["name"])
def test_malformed_certificate_exits_2_and_imports_nothing(lab, cert, run_cli, case):
    bad = cert.with_name(f"{case['name']}.xml")
    bad.write_text(_malformed(case), encoding="utf-8")
    before = lab.read_bytes()
    code, out, err = run_cli("lab", "equipment", "import", str(bad), "--role", "counter")
    assert code == 2 and out == "" and "Traceback" not in err
    field = case["field"].format(R=MALFORMED["R"], REAL1=MALFORMED["REAL1"])
    assert err.startswith(f"metro: error: {bad}") and field in err and case["reason"] in err
    assert lab.read_bytes() == before and not (lab.parent / "lab.equipment").exists()


def test_a_missing_file_and_a_duplicate_id_exit_2(lab, cert, run_cli):
    code, _, err = run_cli("lab", "equipment", "import", str(cert.with_name("none.xml")),
                           "--role", "counter")
    assert code == 2 and "none.xml" in err and "certificate not found" in err
    code, _, err = run_cli("lab", "equipment", "import", str(cert), "--role", "counter", "--id",
                           "RT-01")
    assert code == 2 and "duplicate equipment id 'RT-01'" in err and "Traceback" not in err
    assert not (lab.parent / "lab.equipment").exists()

"""End to end through the command line: simulated default, recorded data, JSON, report, provenance."""

from __future__ import annotations

import hashlib
import json

import pytest


def test_default_run_on_the_simulated_station_json(tmp_path, run_cli):
    code, out, err = run_cli("run", "--standard", "gbt45570", "--item", "D.5.6", "--json", "--out", str(tmp_path),
                             "--no-progress")
    assert code == 0, err
    doc = json.loads(out)
    for key in ("standard", "item", "results", "budget", "report"):
        assert key in doc
    assert doc["standard"] == "gbt45570" and doc["item"] == "D.5.6"
    assert doc["simulated"] is True
    rwc = [r for r in doc["results"] if r["key"] == "RWC"][0]
    for key in ("quantity", "value", "unit", "u", "U", "k"):
        assert key in rwc
    assert rwc["unit"] == "°/√h"
    assert doc["budget"]["measurand"] == "RWC" and doc["budget"]["rows"]
    # the simulator's truth is recovered within U
    (check,) = [c for c in doc["truth_checks"] if c["key"] == "RWC"]
    assert check["within_U"]
    assert doc["report"].endswith(".docx")
    assert (tmp_path / doc["report"].split("/")[-1]).is_file()


def test_terminal_output_says_simulated(run_cli, tmp_path):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--no-report", "--no-progress")
    assert code == 0
    assert "SIMULATED" in err or "SIMULATED" in out
    assert "B₀" in out or "B0" in out


def test_recorded_campaign_with_provenance(tmp_path, campaign_factory, run_cli):
    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=1.0)
    digest = hashlib.sha256((tmp_path / "c" / "static.csv").read_bytes()).hexdigest()
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.2", "--data", str(manifest), "--json",
                             "--out", str(tmp_path / "out"), "--no-progress")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["simulated"] is False
    assert doc["provenance"]["data_files"] == [{"file": str((tmp_path / "c" / "static.csv").resolve()), "sha256": digest}]
    assert {"metro", "numpy", "pint"} <= set(doc["provenance"]["software"])
    assert "gbt45570" in doc["provenance"]["plugins"]
    assert {e["id"] for e in doc["equipment"]} == {"PLAT-1", "CNT-1"}
    keys = {r["key"] for r in doc["results"]}
    assert {"B0", "Bs_10s", "Bs_100s"} <= keys
    from docx import Document

    text = "\n".join(p.text for p in Document(doc["report"]).paragraphs)
    tables = "\n".join(c.text for t in Document(doc["report"]).tables for row in t.rows for c in row.cells)
    assert digest in text + tables
    assert "CNAS-2026-0815" in text + tables


def test_time_column_in_milliseconds(tmp_path, campaign_factory, run_cli):
    def ms(csv: str) -> str:
        lines = csv.splitlines()
        out = ["time [ms],output [P]"] + [f"{int(l.split(',')[0]) * 1000},{l.split(',')[1]}" for l in lines[1:]]
        return "\n".join(out) + "\n"

    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=0.5, data_edit=ms)
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), "--no-report",
                             "--no-progress")
    assert code == 0, err


def test_same_result_from_files_and_from_memory(tmp_path, campaign_factory, pm):
    """The reader path and the in-memory simulated path agree exactly on the same samples."""
    from metro.core.campaign import load_manifest
    from metro.core.runner import run_items
    from metro.instruments.simulated import GyroTruth, SimulatedStation

    truth = GyroTruth(seed=77)
    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=1.0, truth=truth)
    rec_file = run_items(pm, "gbt45570", ["D.5.1"], campaign=load_manifest(manifest, pm.reader_for))
    st = SimulatedStation(truth=truth, duration_scale=1 / 8)
    camp = st.acquire(pm.procedure("gbt45570", "D.5.6")().sequence({}))
    # the station seeds segment i with seed + i, the factory with seed: same samples
    rec_mem = run_items(pm, "gbt45570", ["D.5.1"], campaign=camp)
    a = rec_file.outcomes[0].result("B0").value.magnitude
    b = rec_mem.outcomes[0].result("B0").value.magnitude
    assert a == pytest.approx(b, rel=1e-12)


def test_plugins_and_items_and_plan(run_cli):
    code, out, _ = run_cli("plugins", "--json")
    doc = json.loads(out)
    names = {p["name"]: p for p in doc["plugins"]}
    assert names["gbt45570"]["version"] and names["gbt45570"]["distribution"] == "metro"
    code, out, _ = run_cli("items", "--json", "-s", "gbt45570")
    assert {i["item"] for i in json.loads(out)["items"]} >= {"D.5.1", "D.5.2", "D.5.6"}
    code, out, _ = run_cli("plan", "-s", "gbt45570", "-i", "D.5.1,D.5.6")
    assert "8 h" in out and out.count("[static") == 1  # one shared static record


def test_unknown_item_lists_the_items(run_cli):
    code, _, err = run_cli("run", "-s", "gbt45570", "-i", "D.9.9", "--no-report")
    assert code == 2 and "D.5.6" in err


@pytest.mark.parametrize("station, item", [("simulated", ("gbt45570", "D.5.1")),
                                           ("simulated-jjf2014", ("jjf2014", "7.2.13")),
                                           ("simulated-mimu", ("jjf2003", "7.2.2")),
                                           ("simulated-ogam", ("ogam", "7.3"))])
def test_a_misspelt_station_option_is_refused_and_nothing_is_written(tmp_path, run_cli, station, item):
    """A station option the station does not take is an error naming it and listing the ones it
    takes — never dropped silently with the run going ahead on defaults."""
    std, it = item
    code, _, err = run_cli("acquire", "-s", std, "-i", it, "--station", station, "--station-option",
                           "duration_scal=0.1", "--out", str(tmp_path / "c"), "--no-progress")
    assert code == 2, err
    assert "duration_scal" in err and "seed" in err  # the bad name, and what the station takes
    assert not (tmp_path / "c").exists()
    code, _, err = run_cli("run", "-s", std, "-i", it, "--station-option", "duration_scal=0.1", "--out",
                           str(tmp_path / "r"), "--no-progress")
    assert code == 2 and "duration_scal" in err
    assert not (tmp_path / "r").exists()


def test_run_takes_station_options_and_refuses_them_with_data(tmp_path, run_cli, campaign_factory):
    """`metro run` without --data passes --station-option to the station (here: the JJF 2014
    rate table made faultless changes K); with --data the station arguments are an error."""
    ks = []
    for opt in ("table_errors=true", "table_errors=false"):
        code, out, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--station-option", opt,
                                 "--station-option", "duration_scale=0.1", "--json", "--no-report", "--no-progress")
        assert code == 0, err
        ks.append(next(r["value"] for r in json.loads(out)["results"] if r["key"] == "K"))
    assert ks[0] != ks[1]
    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=0.2)
    for extra in (["--seed", "3"], ["--station-option", "duration_scale=0.1"]):
        code, _, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), *extra,
                               "--out", str(tmp_path / "o"), "--no-progress")
        assert code == 2 and extra[0] in err and "--data" in err
        assert not (tmp_path / "o").exists()


def test_expired_equipment_is_named_on_the_terminal_and_in_json(tmp_path, run_cli):
    """A piece of equipment whose calibration is past due on the day of the run: the terminal says
    so (results that depend on it are not traceable) and --json marks it calibration_valid = false."""
    import shutil
    from pathlib import Path

    src = Path(__file__).resolve().parent.parent / "docs" / "examples" / "campaign"
    shutil.copytree(src, tmp_path / "c")
    m = tmp_path / "c" / "manifest.toml"
    text = m.read_text(encoding="utf-8")
    assert "due = 2027-08-15" in text
    m.write_text(text.replace("due = 2027-08-15", "due = 2025-08-15"), encoding="utf-8")
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m), "--no-report", "--no-progress")
    assert code == 0, err
    assert "CNT-1" in out and "EXPIRED on 2025-08-15" in out and "not traceable" in out
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m), "--no-report", "--json",
                             "--no-progress")
    eq = {e["id"]: e for e in json.loads(out)["equipment"]}
    assert eq["CNT-1"]["calibration_valid"] is False and eq["PLAT-1"]["calibration_valid"] is None


def test_a_station_flag_that_is_neither_true_nor_false_is_refused(run_cli, tmp_path):
    code, _, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--station-option", "table_errors=maybe",
                           "--out", str(tmp_path / "o"), "--no-progress")
    assert code == 2 and "table_errors" in err and "not true or false" in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("std, item, option, says", [
    ("gbt45570", "D.5.1", "arw_deg_rt_h=abc", "is not a number"),
    ("ogam", "7.1", "tilt_deg=inf", "is not a finite number"),
    ("jjf2003", "7.2.1", "bits=12.5", "is not a whole number"),
    ("jjf2014", "7.2.13", "bias_accel_dps_per_g=0.001,0.002", "is not 3 comma-separated numbers"),
    ("jjf2003", "7.2.1", "K_g=1", "a matrix is set from Python"),
])
def test_a_station_option_of_the_wrong_form_is_a_clear_error(run_cli, tmp_path, std, item, option, says):
    """Values from the command line are text: each is converted to the type of the field it sets,
    and one that does not convert names the option and its form — never a TypeError from inside
    a simulation."""
    code, _, err = run_cli("run", "-s", std, "-i", item, "--station-option", option, "--out", str(tmp_path / "o"),
                           "--no-progress")
    assert code == 2 and option.split("=")[0] in err and says in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("std, item, option, says", [
    ("gbt45570", "D.1.1", "turns=2.5", "is not a whole number"),
    ("gbt45570", "D.1.4", "Q=seven", "is not a whole number"),
    ("jjf2014", "7.2.13", "batches=many", "is not a whole number"),
])
def test_an_item_count_option_of_the_wrong_form_is_a_clear_error(run_cli, tmp_path, std, item, option, says):
    """A unitless option whose default is a count takes a whole number (it once ended in a
    ValueError traceback from int())."""
    code, _, err = run_cli("run", "-s", std, "-i", item, "-o", option, "--out", str(tmp_path / "o"), "--no-progress")
    assert code == 2 and option.split("=")[0] in err and says in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_json_is_strict_json_even_with_infinite_degrees_of_freedom(run_cli):
    """--json is read by other programs: no NaN or Infinity literals (invalid JSON), also where a
    budget has ν_eff = ∞ (D.6.1's T_low row is type B only)."""
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.6.1,D.5.1", "--station-option", "duration_scale=0.5",
                             "--json", "--no-report", "--no-progress")
    assert code == 0, err

    def refuse(name):
        raise AssertionError(f"{name} in the JSON output")

    doc = json.loads(out, parse_constant=refuse)
    t_low = next(b for b in doc["budgets"] if b["measurand"] == "T_low")
    assert t_low["nu_eff"] is None and t_low["rows"][0]["dof"] is None  # ∞ is written as null

"""End to end through the command line: simulated default, recorded data, JSON, report,
provenance."""

from __future__ import annotations

import hashlib
import json

import pytest


def test_default_run_on_the_simulated_station_json(tmp_path, run_cli):
    code, out, err = run_cli("run", "--standard", "gbt45570", "--item", "D.5.6", "--json", "--out",
                             str(tmp_path),
                             "--no-progress")
    assert code in (0, 3, 4), err
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
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.2", "--data", str(manifest),
                             "--json",
                             "--out", str(tmp_path / "out"), "--no-progress")
    assert code in (0, 3, 4), err
    doc = json.loads(out)
    assert doc["simulated"] is False
    assert doc["provenance"]["data_files"] == [
        {"file": str((tmp_path / "c" / "static.csv").resolve()), "sha256": digest}
    ]
    assert {"metro", "numpy", "pint"} <= set(doc["provenance"]["software"])
    assert "gbt45570" in doc["provenance"]["plugins"]
    assert {e["id"] for e in doc["equipment"]} == {"PLAT-1", "CNT-1"}
    keys = {r["key"] for r in doc["results"]}
    assert {"B0", "Bs_10s", "Bs_100s"} <= keys
    from docx import Document

    text = "\n".join(p.text for p in Document(doc["report"]).paragraphs)
    tables = "\n".join(c.text for t in Document(doc["report"]).tables for row in t.rows for c
                       in row.cells)
    assert digest in text + tables
    assert "CNAS-2026-0815" in text + tables


def test_time_column_in_milliseconds(tmp_path, campaign_factory, run_cli):
    def ms(csv: str) -> str:
        lines = csv.splitlines()
        out = ["time [ms],output [P]"] + [f"{int(ln.split(',')[0]) * 1000},{ln.split(',')[1]}"
                                          for ln in lines[1:]]
        return "\n".join(out) + "\n"

    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=0.5, data_edit=ms)
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                             "--no-report",
                             "--no-progress")
    assert code == 0, err


def test_same_result_from_files_and_from_memory(tmp_path, campaign_factory, pm):
    """The reader path and the in-memory simulated path agree exactly on the same samples."""
    from metro.core.run.manifest import load_manifest
    from metro.core.run.runner import run_items
    from metro.instruments.simulated import GyroTruth, SimulatedStation

    from metro.instruments.stations import step_seed

    truth = GyroTruth(seed=77)
    steps = pm.procedure("gbt45570", "D.5.6")().sequence({})
    # the station seeds a segment with seed + step_seed(its step) (the step's identity), the
    # factory with its truth's seed: same samples
    file_truth = GyroTruth(seed=77 + step_seed(steps[0]))
    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=1.0, truth=file_truth)
    rec_file = run_items(pm, "gbt45570", ["D.5.1"], campaign=load_manifest(manifest, pm.reader_for))
    st = SimulatedStation(truth=truth, duration_scale=1 / 8)
    camp = st.acquire(steps)
    rec_mem = run_items(pm, "gbt45570", ["D.5.1"], campaign=camp)
    a = rec_file.outcomes[0].result("B0").value.magnitude
    b = rec_mem.outcomes[0].result("B0").value.magnitude
    assert a == pytest.approx(b, rel=1e-12)


def test_plugins_and_items_and_plan(run_cli):
    code, out, _ = run_cli("plugins", "--json")
    doc = json.loads(out)
    names = {p["name"]: p for p in doc["plugins"]}
    assert names["gbt45570"]["version"] and names["gbt45570"]["distribution"] == "metro-inertial"
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
def test_a_misspelt_station_option_is_refused_and_nothing_is_written(tmp_path, run_cli, station,
                                                                     item):
    """A station option the station does not take is an error naming it and listing the ones it
    takes — never dropped silently with the run going ahead on defaults."""
    std, it = item
    code, _, err = run_cli("acquire", "-s", std, "-i", it, "--station", station, "--station-option",
                           "duration_scal=0.1", "--out", str(tmp_path / "c"), "--no-progress")
    assert code == 2, err
    assert "duration_scal" in err and "seed" in err  # the bad name, and what the station takes
    assert not (tmp_path / "c").exists()
    code, _, err = run_cli("run", "-s", std, "-i", it, "--station-option", "duration_scal=0.1",
                           "--out",
                           str(tmp_path / "r"), "--no-progress")
    assert code == 2 and "duration_scal" in err
    assert not (tmp_path / "r").exists()


def test_run_takes_station_options_and_refuses_them_with_data(tmp_path, run_cli, campaign_factory):
    """`metro run` without --data passes --station-option to the station (here: the JJF 2014
    rate table made faultless changes K); with --data the station arguments are an error."""
    ks = []
    for opt in ("table_errors=true", "table_errors=false"):
        code, out, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--station-option", opt,
                                 "--station-option", "duration_scale=0.1", "--json", "--no-report",
                                 "--no-progress")
        assert code == 0, err
        ks.append(next(r["value"] for r in json.loads(out)["results"] if r["key"] == "K"))
    assert ks[0] != ks[1]
    manifest = campaign_factory.write_campaign(tmp_path / "c", hours=0.2)
    for extra in (["--seed", "3"], ["--station-option", "duration_scale=0.1"]):
        code, _, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                               *extra,
                               "--out", str(tmp_path / "o"), "--no-progress")
        assert code == 2 and extra[0] in err and "--data" in err
        assert not (tmp_path / "o").exists()


def test_expired_equipment_is_named_on_the_terminal_and_in_json(tmp_path, run_cli):
    """A piece of equipment whose calibration is past due on the day of the run: the terminal says
    so (results that depend on it are not traceable) and --json marks it calibration_valid =
    false."""
    import shutil
    from pathlib import Path

    src = Path(__file__).resolve().parents[3] / "docs" / "examples" / "campaign"
    shutil.copytree(src, tmp_path / "c")
    m = tmp_path / "c" / "manifest.toml"
    text = m.read_text(encoding="utf-8")
    assert "due = 2027-08-15" in text
    m.write_text(text.replace("due = 2027-08-15", "due = 2025-08-15"), encoding="utf-8")
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m),
                             "--no-report", "--no-progress")
    assert code == 0, err
    assert "CNT-1" in out and "EXPIRED on 2025-08-15" in out and "not traceable" in out
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m),
                             "--no-report", "--json",
                             "--no-progress")
    eq = {e["id"]: e for e in json.loads(out)["equipment"]}
    assert eq["CNT-1"]["calibration_valid"] is False and eq["PLAT-1"]["calibration_valid"] is None


def test_a_station_flag_that_is_neither_true_nor_false_is_refused(run_cli, tmp_path):
    code, _, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--station-option",
                           "table_errors=maybe",
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
def test_a_station_option_of_the_wrong_form_is_a_clear_error(run_cli, tmp_path, std, item, option,
                                                             says):
    """Values from the command line are text: each is converted to the type of the field it sets,
    and one that does not convert names the option and its form — never a TypeError from inside
    a simulation."""
    code, _, err = run_cli("run", "-s", std, "-i", item, "--station-option", option, "--out",
                           str(tmp_path / "o"),
                           "--no-progress")
    assert code == 2 and option.split("=")[0] in err and says in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


@pytest.mark.parametrize("std, item, option, says", [
    ("gbt45570", "D.1.1", "turns=2.5", "is not a whole number"),
    ("gbt45570", "D.1.4", "Q=seven", "is not a whole number"),
    ("jjf2014", "7.2.13", "batches=many", "is not a whole number"),
])
def test_an_item_count_option_of_the_wrong_form_is_a_clear_error(run_cli, tmp_path, std, item,
                                                                 option, says):
    """A unitless option whose default is a count takes a whole number (it once ended in a
    ValueError traceback from int())."""
    code, _, err = run_cli("run", "-s", std, "-i", item, "-o", option, "--out", str(tmp_path / "o"),
                           "--no-progress")
    assert code == 2 and option.split("=")[0] in err and says in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()


def test_json_is_strict_json_even_with_infinite_degrees_of_freedom(run_cli):
    """--json is read by other programs: no NaN or Infinity literals (invalid JSON), also where a
    budget has ν_eff = ∞ (D.6.1's T_low row is type B only)."""
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.6.1,D.5.1", "--station-option",
                             "duration_scale=0.5",
                             "--json", "--no-report", "--no-progress")
    assert code in (0, 3, 4), err

    def refuse(name):
        raise AssertionError(f"{name} in the JSON output")

    doc = json.loads(out, parse_constant=refuse)
    t_low = next(b for b in doc["budgets"] if b["measurand"] == "T_low")
    assert t_low["nu_eff"] is None and t_low["rows"][0]["dof"] is None  # ∞ is written as null


# ---- a command line scripts can rely on (issue 17) ----------------------------------------------

def _spec_run(run_cli, tmp_path, campaign_factory, name, spec):
    manifest = campaign_factory.write_campaign(
        tmp_path / name, hours=0.3, manifest_edit=(lambda t: t
                                                   + f'\n[specification]\nB0 = "{spec}"\n') if spec
        else None)
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest),
                             "--json", "--no-report")
    return code, json.loads(out), err


def test_exit_codes_follow_the_overall_verdict(tmp_path, campaign_factory, run_cli):
    """0 conforms, 3 does not conform, 4 indeterminate (README "Exit codes"); the limits are set
    around the measured B₀ ± U of the same campaign so each verdict is certain."""
    code, doc, err = _spec_run(run_cli, tmp_path, campaign_factory, "a", "-100 .. 100 °/h")
    assert code == 0, err
    assert doc["conformity"]["overall"] == "pass"
    b0 = next(r for r in doc["results"] if r["key"] == "B0")
    v, U = b0["value"], b0["U"]
    code, doc, _ = _spec_run(run_cli, tmp_path, campaign_factory, "b",
                             f"{v + 3 * U:.5f} .. {v + 10 * U:.5f} °/h")
    assert (code, doc.get("conformity", {}).get("overall")) == (3, "fail"), doc
    # straddles
    code, doc, _ = _spec_run(run_cli, tmp_path, campaign_factory, "c", f"<= {v + U / 3:.5f} °/h")
    assert (code, doc["conformity"]["overall"]) == (4, "indeterminate"), doc


def test_exit_code_0_when_nothing_is_judged_and_130_when_interrupted(run_cli, monkeypatch):
    code, out, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--station-option",
                             "duration_scale=0.1",
                             "--json", "--no-report")
    assert code == 0, err
    assert json.loads(out)["conformity"] is None  # JJF 2014 declares no limits: nothing to judge

    def interrupted(*a, **k):
        raise KeyboardInterrupt

    monkeypatch.setattr("metro.core.run.runner.run_items", interrupted)
    code, _, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--no-report")
    assert code == 130 and "interrupted" in err


def test_version_names_metro_and_each_loaded_plugin(run_cli):
    from importlib.metadata import version

    code, out, _ = run_cli("--version")
    assert code == 0
    lines = out.splitlines()
    assert lines[0] == f"metro {version('metro-inertial')}"
    for name in ("gbt45570", "jjf2014", "jjf2003", "ogam", "instruments"):
        assert any(line.strip().startswith(f"plugin {name}: metro-inertial "
                                           f"{version('metro-inertial')}") for line in lines), name
    code, out, _ = run_cli("--block-plugin", "ogam", "--version")
    assert "plugin ogam" not in out and "plugin gbt45570" in out


def test_python_dash_m_metro(tmp_path):
    """`python -m metro` is the command (metro stays a namespace package: no metro/__init__.py)."""
    import subprocess
    import sys

    p = subprocess.run([sys.executable, "-m", "metro", "--version"], capture_output=True, text=True,
                       cwd=tmp_path)
    assert p.returncode == 0, p.stderr
    assert p.stdout.startswith("metro ") and "plugin gbt45570" in p.stdout
    p = subprocess.run([sys.executable, "-m", "metro", "items", "-s", "nosuch"],
                       capture_output=True, text=True,
                       cwd=tmp_path)
    assert p.returncode == 2 and "unknown standard" in p.stderr
    p = subprocess.run([sys.executable, "-c", "import metro; print(metro.__file__)"],
                       capture_output=True, text=True)
    assert p.stdout.strip() == "None"  # a namespace package


@pytest.mark.parametrize("args, says", [
    (("items", "-s", "gbt4557"), "did you mean 'gbt45570'"),
    (("run", "-s", "GBT4557", "-i", "D.5.1"), "did you mean 'gbt45570'"),
    (("run", "-s", "gbt45570", "-i", "D.5.66"), "did you mean 'D.5.6'"),
    (("run", "-s", "gbt45570", "-i", "scale-factr"), "did you mean 'scale-factor'"),
    (("run", "-s", "gbt45570", "-i", "D.5.6", "-o", "min_block=3"), "did you mean 'min_blocks'"),
    (("run", "-s", "gbt45570", "--itme", "D.5.6"), "did you mean '--item'"),
    (("rnu", "-s", "gbt45570"), "did you mean 'run'"),
    (("plan", "-s", "gbt45570", "-i", "d.51"), "did you mean 'D.5.1'"),
])
def test_mistyped_names_get_a_suggestion_and_exit_2(run_cli, args, says, tmp_path):
    code, out, err = run_cli(*args, "--out", str(tmp_path
                                                 / "o")) if args[0] == "run" else run_cli(*args)
    assert code == 2, err
    assert says in err and "Traceback" not in err
    assert "SIMULATED" not in err  # usage errors come before any banner
    assert not (tmp_path / "o").exists()


def test_items_of_an_unknown_standard_exit_2_naming_the_loaded_ones(run_cli):
    code, out, err = run_cli("items", "-s", "foo")
    assert code == 2 and out == ""
    assert "unknown standard 'foo'" in err and "gbt45570" in err and "jjf2014" in err


def test_ids_are_case_insensitive_and_taken_as_items_prints_them(run_cli):
    """`metro items` prints gbt45570:D.5.1; `run -i` takes that (with or without -s) in any case."""
    code, out, _ = run_cli("items", "--json", "-s", "GBT45570")
    ids = [i["id"] for i in json.loads(out)["items"]]
    assert "gbt45570:D.5.1" in ids
    keys = []
    for args in (("-i", "gbt45570:D.5.1"), ("-s", "GbT45570", "-i", "d.5.1"),
                 ("-i", "GBT45570:d.5.1")):
        code, out, err = run_cli("run", *args, "--station-option", "duration_scale=0.1", "--json",
                                 "--no-report")
        assert code in (0, 3, 4), err
        doc = json.loads(out)
        assert doc["standard"] == "gbt45570" and doc["item"] == "D.5.1"
        keys.append(next(r["value"] for r in doc["results"] if r["key"] == "B0"))
    assert keys[0] == keys[1] == keys[2]  # same seeded station, same item
    code, _, err = run_cli("run", "-s", "jjf2014", "-i", "gbt45570:D.5.1", "--no-report")
    assert code == 2 and "belongs to gbt45570" in err
    code, _, err = run_cli("run", "-i", "D.5.1", "--no-report")
    assert code == 2 and "no --standard" in err


def test_run_help_example_runs_on_the_readme_item(run_cli):
    """The example in `metro run --help` is the README's item and its option exists."""
    import re
    import shlex

    code, out, _ = run_cli("run", "--help")
    assert code == 0
    text = " ".join(out.split())
    example = re.search(r"Example: metro (run .*?) {0,3}exit codes", text).group(1)
    readme = (__import__("pathlib").Path(__file__).resolve().parents[3]
              / "README.md").read_text(encoding="utf-8")
    assert "--item D.5.6" in readme and "-i D.5.6" in example
    code, out, err = run_cli(*shlex.split(example), "--json", "--no-report")
    assert code in (0, 3, 4), err
    assert json.loads(out)["item"] == "D.5.6"


def _pipe_closed_early(*args):
    import subprocess
    import sys

    p = subprocess.Popen([sys.executable, "-m", "metro", *args], stdout=subprocess.PIPE,
                         stderr=subprocess.PIPE)
    p.stdout.close()  # the reader is gone before the first line is written (as `| head -0`)
    err = p.stderr.read().decode()
    return p.wait(), err


@pytest.mark.parametrize("args", [("plan", "-s", "gbt45570", "--all"), ("items",)])
def test_a_closed_pipe_ends_quietly(args):
    code, err = _pipe_closed_early(*args)
    assert "Traceback" not in err and "Exception ignored" not in err and "BrokenPipe" not in err
    assert code == 141


def test_items_readable_at_80_columns(run_cli, monkeypatch):
    from rich.cells import cell_len

    monkeypatch.setenv("COLUMNS", "80")
    code, out, _ = run_cli("items")
    assert code == 0
    assert "(default None)" not in out and "…" not in out
    assert max(cell_len(line.rstrip()) for line in out.splitlines()) <= 80
    code, doc, _ = run_cli("items", "--json")
    words = set(out.split())
    for it in json.loads(doc)["items"]:
        for w in it["title"].split():  # every title in full (wrapped, never cut)
            assert w in words or any(w in x for x in words), (it["id"], w)
    assert len(out.splitlines()) < 250  # was 407 lines


def test_plan_all_gives_the_total_duration(run_cli):
    import pint

    code, out, _ = run_cli("plan", "-s", "gbt45570", "--all", "--json")
    assert code == 0
    doc = json.loads(out)
    ureg = pint.UnitRegistry()

    def seconds(q):  # a quantity is {"value", "unit"} (docs/json.md)
        return ureg.Quantity(q["value"], q["unit"]).to("s").magnitude

    rec = sum(seconds(s["duration"]) for s in doc["steps"])
    warm = sum(seconds(s["warmup"]) for s in doc["steps"] if s["warmup"])
    assert doc["total"]["recording_s"] == pytest.approx(rec) and doc["total"][
        "warmup_s"] == pytest.approx(warm)
    assert len(doc["total"]["items"]) > 15 and doc["total"]["steps"] == len(doc["steps"])
    code, out, _ = run_cli("plan", "-s", "gbt45570", "-i", "D.5.1,D.5.6")
    assert out.splitlines()[-1].startswith("total: 1 steps for 2 item(s): 8 h of recording + 30 "
                                           "min of warm-up")


def test_progress_is_one_overall_bar_and_the_current_step(pm):
    """A run reports items and segments done of the total to one overall bar; every other event
    goes to one 'current step' line: never more than two lines, whatever the run."""
    import io

    from rich.console import Console

    from metro.core.cli import present
    from metro.core.run.runner import run_items

    con = Console(file=io.StringIO(), force_terminal=True, width=100, height=10)
    seen = []
    with present.progress(True, console=con) as prog:
        def spy(task, done, total):
            seen.append((task, done, total))
            prog(task, done, total)

        record = run_items(pm, "gbt45570", ["D.5.1", "D.5.6", "D.1.1"], progress=spy,
                           station_options={"duration_scale": 0.05})
        tasks = prog.display.tasks
    assert len(tasks) == 2
    overall = tasks[0]
    n_items = len(record.outcomes)
    n_segments = max(t for task, _, t in seen if task == "segments")
    assert overall.total == n_items + n_segments and overall.completed == overall.total
    assert n_segments > 1 and len({task for task, _, _ in seen}) > 5  # many events, two lines


def test_no_progress_on_a_non_terminal_and_quiet_silences_it(run_cli, monkeypatch):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--station-option",
                             "duration_scale=0.1",
                             "--no-report")
    assert "%" not in err and "━" not in err  # stderr is not a terminal here
    flags = []
    import metro.core.cli.present as present

    real = present.progress

    def record(enabled=True, **kw):
        flags.append(enabled)
        return real(False, **kw)

    monkeypatch.setattr(present, "progress", record)
    monkeypatch.setattr("sys.stderr.isatty", lambda: True, raising=False)
    run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--station-option", "duration_scale=0.1",
            "--no-report")
    run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--station-option", "duration_scale=0.1",
            "--no-report", "-q")
    assert flags == [True, False]


def test_terminal_summary_is_concise_and_verbose_adds_the_detail(tmp_path, campaign_factory,
                                                                 run_cli):
    manifest = campaign_factory.write_campaign(
        tmp_path / "c",
        hours=0.3,
        manifest_edit=lambda t: t + '\n[specification]\nB0 = "-100 .. 100 °/h"\n',
    )
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.2", "--data", str(manifest),
                             "--out", str(tmp_path / "o"))
    assert code in (0, 3, 4), err
    lines = out.splitlines()
    assert "sha256" not in out and "Budget" not in out
    assert out.count("Results") == 1
    verdict = next(line for line in lines if line.startswith(("conforms", "does not conform",
                                                              "indeterminate")))
    assert "pass" in verdict and "rule" in verdict
    assert "Word report" in out and str(tmp_path / "o") in out
    code2, outv, _ = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.2", "--data", str(manifest),
                             "--no-report",
                             "--verbose")
    assert "sha256" in outv and "Budget" in outv and "Conformity" in outv
    assert len(outv.splitlines()) > 2 * len(lines)


def test_the_overall_verdict_line_counts_each_status(pm, tmp_path, campaign_factory, capsys):
    """The line the issue asks for: 'does not conform: 17 pass, 2 fail, 6 indeterminate'."""
    import attrs

    from metro.core.uncertainty import conformity as cf
    from metro.core.cli.present import verdict_line
    from metro.core.run.runner import run_items

    record = run_items(pm, "gbt45570", ["D.5.1"], station_options={"duration_scale": 0.1})
    (v,) = [v for v in record.conformity.verdicts if v.key == "B0"]
    vs = ([attrs.evolve(v, status=cf.Status.PASS)] * 17
          + [attrs.evolve(v, status=cf.Status.FAIL)] * 2
          + [attrs.evolve(v, status=cf.Status.INDETERMINATE)] * 6)
    a = attrs.evolve(record.conformity, verdicts=vs, not_assessed=())
    assert verdict_line(a) == "does not conform: 17 pass, 2 fail, 6 indeterminate (guarded rule)"
    assert verdict_line(None).startswith("not judged")


def test_a_result_not_reportable_and_its_earth_rate_show_in_its_row(pm, capsys, monkeypatch):
    import attrs

    from metro.core.cli import present
    from metro.core.run.runner import run_items

    monkeypatch.setenv("COLUMNS", "200")
    record = run_items(pm, "gbt45570", ["D.5.1"], station_options={"duration_scale": 0.1})
    o = record.outcomes[0]
    r = attrs.evolve(o.results[0], reportable=False, reason="misfit of the test model",
                     earth_rate="removed")
    record = attrs.evolve(record, outcomes=[attrs.evolve(o, results=[r])])
    present.print_record(record, None)
    row = next(line for line in capsys.readouterr().out.splitlines() if "B₀" in line)
    assert "not reportable: misfit of the test model" in row and "earth rate removed" in row


def test_readme_exit_code_table_is_what_metro_returns():
    """The README's table and the codes in metro.core.cli.app are the same list."""
    import re
    from pathlib import Path

    from metro.core.cli import app as cli

    text = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    table = text.split("### Exit codes", 1)[1]
    documented = {int(c) for c in re.findall(r"^\| (\d+) \|", table, flags=re.M)}
    assert documented == {cli.EXIT_OK, cli.EXIT_USER_ERROR, cli.EXIT_NONCONFORMING,
                          cli.EXIT_INDETERMINATE,
                          cli.EXIT_CAMPAIGN_FAILED, cli.EXIT_CHECK_FAILED, cli.EXIT_INTERRUPTED,
                          cli.EXIT_BROKEN_PIPE}
    assert (cli.exit_code_for("pass"), cli.exit_code_for(None), cli.exit_code_for("fail"),
            cli.exit_code_for("indeterminate")) == (0, 0, 3, 4)


def test_simulated_run_exits_0_unless_strict(run_cli, tmp_path):
    """The README's main job runs on the simulated station and must exit 0 once evaluated: a verdict
    about the virtual device is printed, not returned; --strict returns it as for recorded data."""
    # the marginal virtual gyro's ARW equals table A.1's aviation limit: not shown to conform (the
    # default unit conforms since issue 29: tests/plugins/gbt45570/test_bias_stability_limit.py)
    marginal = ("--station-option", "grade=marginal")
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.6", "--json", "--no-report",
                             *marginal)
    assert code == 0, err
    overall = json.loads(out)["conformity"]["overall"]
    assert overall in ("fail", "indeterminate")
    code_strict, _, _ = run_cli("run", "-s", "gbt45570", "-i", "D.5.6", "--json", "--no-report",
                                "--strict",
                                *marginal)
    assert code_strict == {"fail": 3, "indeterminate": 4}[overall]

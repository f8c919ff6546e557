"""`metro batch` on real dask.distributed clusters: a local cluster of processes, and a scheduler
with a worker started as separate processes on 127.0.0.1; a lot with one broken campaign.

The statistics are checked against values computed here from each device's own `metro run
--data … --json` (run separately, in this process), not from the batch's files."""

from __future__ import annotations

import csv
import json
import os
import socket
import statistics as st
import subprocess
import sys
import time
from pathlib import Path

import pytest

ITEMS = "D.5.1,D.5.2"
SEEDS = (11, 12, 13)


@pytest.fixture(scope="module")
def lot(tmp_path_factory, campaign_factory_module):
    """Three good campaigns of three devices (different seeded truths) and one whose samples file
    has a value that is not a number (a data error naming the file)."""
    from metro.instruments.simulated import GyroTruth

    root = tmp_path_factory.mktemp("lot")
    for seed in SEEDS:
        campaign_factory_module.write_campaign(root / f"unit-{seed}", hours=0.3,
                                               truth=GyroTruth(seed=seed))

    def corrupt(text: str) -> str:
        lines = text.splitlines()
        lines[40] = lines[40].split(",")[0] + ",twelve"
        return "\n".join(lines) + "\n"

    campaign_factory_module.write_campaign(root / "unit-broken", hours=0.3, data_edit=corrupt)
    return root


@pytest.fixture(scope="module")
def campaign_factory_module():
    import importlib.util

    spec = importlib.util.spec_from_file_location("metro_tests_campaign_factory_b",
                                                  (Path(__file__).parents[2]
                                                   / "campaign_factory.py"))
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@pytest.fixture(scope="module")
def single_runs(lot):
    """Each good device through `metro run --data … --json` on its own: the independent values."""
    import contextlib
    import io

    from metro.core.cli.app import main

    docs = {}
    for seed in SEEDS:
        buf = io.StringIO()
        with contextlib.redirect_stdout(buf):
            code = main(["run", "-s", "gbt45570", "-i", ITEMS, "--data",
                         str(lot / f"unit-{seed}" / "manifest.toml"),
                         "--json", "--no-report"])
        assert code in (0, 3, 4)
        docs[f"unit-{seed}"] = json.loads(buf.getvalue())
    return docs


def _check_lot(out: Path, summary: dict, single_runs: dict, lot: Path) -> None:
    # every device its own report, as a single run writes it; the broken one listed with its error
    devices = {d["name"]: d for d in summary["devices"]}
    assert set(devices) == {"unit-11", "unit-12", "unit-13", "unit-broken"}
    bad = devices["unit-broken"]
    assert bad["status"] == "error" and bad["error"] == "DataError"
    assert "unit-broken" in bad["message"] and "twelve" in bad["message"]
    assert not (out / "devices" / "unit-broken").exists()  # nothing partial written for it
    from docx import Document

    for name, single in single_runs.items():
        d = devices[name]
        assert d["status"] == "evaluated" and Path(d["report"]).is_file()
        assert Path(d["report"]).parent == out / "devices" / name
        text = "\n".join(c.text for t in Document(d["report"]).tables for r in t.rows for c
                         in r.cells)
        assert single["provenance"]["data_files"][0]["sha256"] in text
        doc = json.loads(Path(d["json"]).read_text(encoding="utf-8"))
        # same evaluation
        assert [(r["item"], r["key"], r["value"], r["U"]) for r in doc["results"]] == \
            [(r["item"], r["key"], r["value"], r["U"]) for r in single["results"]]
        assert d["overall"] == single["conformity"]["overall"]

    # every result of every device, CSV and Parquet
    import pyarrow.parquet as pq

    table = pq.read_table(out / "lot-results.parquet").to_pylist()
    with (out / "lot-results.csv").open(encoding="utf-8") as fh:
        rows = list(csv.DictReader(fh))
    n_results = sum(len(doc["results"]) for doc in single_runs.values())
    assert len(table) == len(rows) == n_results
    for r in table:
        (ref,) = [x for x in single_runs[r["device"]]["results"] if (x["item"], x["key"])
                  == (r["item"], r["key"])]
        assert r["value"] == ref["value"] and r["unit"] == ref["unit"]

    # per-quantity statistics against values computed here from the single runs
    with (out / "lot-statistics.csv").open(encoding="utf-8") as fh:
        stats = {(s["item"], s["key"]): s for s in csv.DictReader(fh)}
    keys = {(r["item"], r["key"]) for doc in single_runs.values() for r in doc["results"]}
    assert set(stats) == keys
    for item, key in keys:
        vals = [next(r["value"] for r in doc["results"] if (r["item"], r["key"]) == (item, key))
                for doc in single_runs.values()]
        s = stats[(item, key)]
        assert int(s["n"]) == 3
        assert float(s["mean"]) == pytest.approx(st.mean(vals), rel=1e-12)
        assert float(s["std"]) == pytest.approx(st.stdev(vals), rel=1e-9)  # sample σ (n − 1)
        assert (float(s["min"]), float(s["max"])) == (min(vals), max(vals))
        verdicts = [next((v["status"] for v in doc["conformity"]["verdicts"]
                          if (v["item"], v["key"]) == (item, key)),
                         None) for doc in single_runs.values()]
        judged = [v for v in verdicts if v]
        if judged:
            assert float(s["yield"]) == pytest.approx(judged.count("pass") / len(judged))
            assert (out / "histograms" / f"{item}_{key}.png").is_file()
        else:
            assert s["yield"] == ""
    report = Document(out / "lot-report.docx")
    # no-break spaces of the builder
    text = "\n".join(p.text for p in report.paragraphs).replace("\u00a0", " ")
    assert ("Lot summary — gbt45570" in text and "unit-broken" in text
            and "4 (3 evaluated, 1 failed)" in text)


def test_batch_on_a_local_cluster_of_processes(lot, single_runs, run_cli, tmp_path, monkeypatch):
    out = tmp_path / "out"
    lab = tmp_path / "lab.toml"  # a lab profile: each device registered as `metro run` registers it
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    assert run_cli("lab", "init", str(lab))[0] == 0
    code, stdout, err = run_cli("--lab", str(lab), "batch", "-s", "gbt45570", "-i", ITEMS, "--data",
                                str(lot / "*"),
                                "--workers", "2", "--out", str(out), "--json")
    assert code == 5, err  # a campaign failed: non-zero whatever the others' verdicts
    summary = json.loads(stdout)
    assert summary["counts"]["error"] == 1 and summary["counts"]["evaluated"] == 3
    evaluated = [d for d in summary["devices"] if d["status"] == "evaluated"]
    assert all(d["registered"] for d in evaluated)
    code, listed, _ = run_cli("--lab", str(lab), "register", "list", "--json")
    assert sorted(r["number"] for r
                  in json.loads(listed)["reports"]) == sorted(d["report_number"] for d in evaluated)
    assert all(Path(d["report"]).name == f"{d['report_number']}.docx" for d in evaluated)
    pids = {d["name"]: d for d in json.loads((out
                                              / "batch-state.json").read_text())[
                                                  "campaigns"].values()}
    # evaluated in worker processes
    assert all(p["worker_pid"] != os.getpid() for p in pids.values())
    _check_lot(out, summary, single_runs, lot)

    # resumed: the evaluated campaigns (same manifest SHA-256) are skipped, the failed one retried
    reports = sorted(p.name for p in (out / "devices").rglob("*.docx"))
    code, stdout, err = run_cli("--lab", str(lab), "batch", "-s", "gbt45570", "-i", ITEMS, "--data",
                                str(lot / "*"),
                                "--workers", "1", "--out", str(out), "--json")
    assert code == 5
    again = {d["name"]: d for d in json.loads(stdout)["devices"]}
    assert all(again[f"unit-{s}"]["skipped"] for s in SEEDS) and not again["unit-broken"]["skipped"]
    # no report written again
    assert sorted(p.name for p in (out / "devices").rglob("*.docx")) == reports
    assert json.loads(stdout)["timing"]["evaluated_now"] == 1
    _check_lot(out, json.loads(stdout), single_runs, lot)

    # another job on the same --out is refused before anything runs
    code, _, err = run_cli("batch", "-s", "gbt45570", "-i", "D.5.1", "--data", str(lot / "*"),
                           "--out", str(out))
    assert code == 2 and "another job" in err


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


@pytest.fixture
def scheduler_address(tmp_path):
    """A real Dask cluster of separate processes: `dask scheduler` and one `dask worker` on
    loopback."""
    port = _free_port()
    addr = f"tcp://127.0.0.1:{port}"
    logs = [open(tmp_path / n, "w") for n in ("scheduler.log", "worker.log")]
    procs = [subprocess.Popen([sys.executable, "-m", "dask", "scheduler", "--host", "127.0.0.1",
                               "--port", str(port),
                               "--no-dashboard"], stdout=logs[0], stderr=logs[0])]
    try:
        from distributed import Client

        deadline = time.monotonic() + 90
        while True:
            try:
                client = Client(addr, timeout="5s")
                break
            except OSError:
                if time.monotonic() > deadline:
                    raise
                time.sleep(0.5)
        procs.append(subprocess.Popen([sys.executable, "-m", "dask", "worker", addr, "--nworkers",
                                       "1", "--nthreads",
                                       "1", "--no-dashboard"], stdout=logs[1], stderr=logs[1]))
        client.wait_for_workers(1, timeout=90)
        client.close()
        yield addr
    finally:
        for p in reversed(procs):
            p.terminate()
        for p in reversed(procs):
            try:
                p.wait(timeout=30)
            except subprocess.TimeoutExpired:
                p.kill()
        for f in logs:
            f.close()


def test_batch_through_a_scheduler_address(lot, single_runs, run_cli, tmp_path, scheduler_address):
    out = tmp_path / "out"
    data = ",".join(str(lot / n / "manifest.toml") for n
                    in ("unit-11", "unit-broken", "unit-12", "unit-13"))
    code, stdout, err = run_cli("batch", "-i", "gbt45570:D.5.1", "-i", "gbt45570:d.5.2", "--data",
                                data,
                                "--scheduler", scheduler_address, "--out", str(out))
    assert code == 5, err
    assert "unit-broken" in stdout and "FAILED" in stdout and "1 failed" in stdout
    summary = json.loads((out / "lot-summary.json").read_text(encoding="utf-8"))
    assert summary["timing"]["scheduler"] == scheduler_address
    _check_lot(out, summary, single_runs, lot)


def test_batch_exit_code_is_the_worst_verdict_when_every_campaign_ran(lot, single_runs):
    from metro.core.cli.batch import exit_code

    def summary(**c):
        return {"counts": {"error": 0, "fail": 0, "indeterminate": 0, **c}}

    assert exit_code(summary()) == 0
    assert exit_code(summary(indeterminate=2)) == 4
    assert exit_code(summary(indeterminate=2, fail=1)) == 3
    assert exit_code(summary(fail=1, error=1)) == 5


@pytest.mark.parametrize("args, says", [
    (("--data", "/nonexistent/*/manifest.toml"), "no campaign matches"),
    (("--data", "/nonexistent/manifest.toml"), "no such campaign manifest"),
    (("--data", "x", "--workers", "0"), "at least 1"),
    (("--data", "x", "--workers", "2", "--scheduler", "tcp://127.0.0.1:1"),
     "--workers sizes the local cluster"),
])
def test_batch_usage_errors_exit_2_before_any_cluster_starts(run_cli, args, says, tmp_path):
    t0 = time.perf_counter()
    code, _, err = run_cli("batch", "-s", "gbt45570", "-i", "D.5.1", *args, "--out",
                           str(tmp_path / "o"))
    assert code == 2 and says in err and "Traceback" not in err
    assert not (tmp_path / "o").exists()
    assert time.perf_counter() - t0 < 20

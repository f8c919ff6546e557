"""Throughput of `metro batch` on a production lot, with 1 and 2 local workers (not a test).

Run:  .venv/bin/python benchmarks/bench_batch.py [--devices N] [--repeat R]

* Acquires N device campaigns once (GB/T 45570 D.5.1 + D.5.2 on the simulated station, a
  different seeded device each, ``duration_scale=0.2``: 12 min records at 1 s) into
  benchmarks/data/lot-N/ (git-ignored); later runs reuse them.
* Times a single cold ``metro run --data … --out …`` (fresh process, the report written: what one
  device costs without batch) on three of the campaigns.
* Times ``metro batch --workers 1`` and ``--workers 2`` on the whole lot (fresh --out each, so
  nothing is skipped), R times each, interleaved; from the lot summary's own timing it separates
  the cluster's start-up from the evaluation of the campaigns.
* Prints throughput (campaigns per minute), the 1 → 2 worker scaling and the per-campaign cost
  against the single run, with the machine's load average (other jobs make the figures noisy).
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
METRO = [sys.executable, "-m", "metro"]
ITEMS = "D.5.1,D.5.2"


def acquire_lot(n: int) -> Path:
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.manifest_writer import acquire_campaign

    lot = ROOT / "benchmarks" / "data" / f"lot-{n}"
    pm = get_plugin_manager()
    lot.mkdir(parents=True, exist_ok=True)
    for i in range(1, n + 1):
        folder = lot / f"dev-{i:03d}"
        if (folder / "manifest.toml").is_file():
            continue
        acquire_campaign(pm, "gbt45570", ITEMS.split(","), folder,
                         station_options={"seed": 1000 + i, "duration_scale": 0.2})
    return lot


def single_run(manifest: Path) -> float:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        p = subprocess.run([*METRO, "run", "-s", "gbt45570", "-i", ITEMS, "--data", str(manifest),
                            "--out", out,
                            "--quiet"], capture_output=True, text=True)
        wall = time.perf_counter() - t0
    if p.returncode not in (0, 3, 4):
        raise SystemExit(f"metro run failed ({p.returncode}): {p.stderr}")
    return wall


def batch(lot: Path, workers: int) -> dict:
    with tempfile.TemporaryDirectory() as out:
        t0 = time.perf_counter()
        p = subprocess.run([*METRO, "batch", "-s", "gbt45570", "-i", ITEMS, "--data",
                            str(lot / "*"),
                            "--workers", str(workers), "--out", out, "--json", "--quiet"],
                           capture_output=True,
                           text=True)
        wall = time.perf_counter() - t0
        if p.returncode not in (0, 3, 4, 5):
            raise SystemExit(f"metro batch failed ({p.returncode}): {p.stderr[-2000:]}")
        summary = json.loads(p.stdout)
        for d in summary["devices"]:
            if d["status"] == "error":  # listed, and counted below; the lot went on
                print(f"  campaign {d['name']} failed: {d['error']}: {d['message']}")
    t = summary["timing"]
    n = summary["campaigns"]
    evaluate = t["seconds"] - t["cluster_start_s"]
    done = [d for d in summary["devices"] if d["status"] == "evaluated"]
    cpu = sum(d["cpu_seconds"] for d in done) / max(1, len(done))
    busy = sum(d["seconds"] for d in done) / max(1, len(done))
    return {"workers": workers, "campaigns": n, "wall_s": wall,
            "cluster_start_s": t["cluster_start_s"],
            "cpu_per_campaign_s": cpu, "wall_per_campaign_in_worker_s": busy,
            "evaluate_s": evaluate, "per_min_wall": 60 * n / wall, "per_min_evaluate": 60 * n
            / evaluate,
            "failed": summary["counts"]["error"], "load_before": os.getloadavg()[0]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--devices", type=int, default=60)
    ap.add_argument("--repeat", type=int, default=2)
    ap.add_argument("--json", metavar="PATH", help="also write the figures as JSON")
    a = ap.parse_args()
    t0 = time.perf_counter()
    lot = acquire_lot(a.devices)
    print(f"lot: {a.devices} campaigns in {lot} (acquired/checked in "
          f"{time.perf_counter() - t0:.1f} s)")
    manifests = sorted(lot.glob("*/manifest.toml"))
    singles = [single_run(m) for m in manifests[:3]]
    print(f"single cold `metro run` with report: {statistics.median(singles):.2f} s (median of 3: "
          + ", ".join(f"{s:.2f}" for s in singles) + ")")
    runs = []
    for r in range(a.repeat):
        for w in (1, 2):
            res = batch(lot, w)
            runs.append(res)
            print(f"round {r + 1}, {w} worker(s): wall {res['wall_s']:.1f} s (cluster start "
                  f"{res['cluster_start_s']:.1f} s, evaluation {res['evaluate_s']:.1f} s) → "
                  f"{res['per_min_wall']:.1f} campaigns/min overall, "
                  f"{res['per_min_evaluate']:.1f}/min evaluating; per campaign in its worker "
                  f"{res['wall_per_campaign_in_worker_s']:.2f} s wall, "
                  f"{res['cpu_per_campaign_s']:.2f} s CPU; load {res['load_before']:.1f}")
    best = {w: max((x for x in runs if x["workers"] == w), key=lambda x: x["per_min_evaluate"])
            for w in (1, 2)}
    scaling = best[2]["per_min_evaluate"] / best[1]["per_min_evaluate"]
    per_campaign_1 = best[1]["evaluate_s"] / best[1]["campaigns"]
    cpu_ratio = best[2]["cpu_per_campaign_s"] / best[1]["cpu_per_campaign_s"]
    print(f"CPU per campaign, 2 workers / 1 worker: {cpu_ratio:.2f} (1.00: the workers share "
          "nothing but the cores; scaling on idle cores is then bounded by the cores, not by the "
          "design)")
    print(f"scaling 1 → 2 workers (evaluation, best rounds): {scaling:.2f}×; "
          f"per campaign with 1 worker {per_campaign_1:.2f} s vs a single cold run "
          f"{statistics.median(singles):.2f} s")
    if a.json:
        Path(a.json).write_text(json.dumps({"single_run_s": singles, "runs": runs,
                                            "scaling": scaling,
                                            "cpus": os.cpu_count()}, indent=2))


if __name__ == "__main__":
    main()

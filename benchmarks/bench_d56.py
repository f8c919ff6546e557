"""End-to-end benchmark of GB/T 45570 D.5.6 on an 8 h, 1 kHz record (28.8 M samples).

Run:  .venv/bin/python benchmarks/bench_d56.py [--n N] [--no-allantools] [--repeat R]

In ONE run, on the same simulated pulse record (virtual laser gyro, τ0 = 1 ms):
  * one ``np.cumsum`` pass over the data (the memory-bandwidth yardstick);
  * metro ``oadev`` at octave τ and ``allantools.oadev(..., taus='octave')``;
  * the whole D.5.6 evaluation (unit conversion, finiteness check, block-mean pyramid,
    GLS fit of D.45, budget) on an in-memory campaign;
  * a cold ``metro run --standard gbt45570 --item D.5.6 --data …`` in a fresh process, on
    the record written as CSV and as .npy, with the run's own stage timings;
  * ``metro --help`` start-up.
Prints a table; docs/performance.md records the figures.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _measure import MiB, format_table, measure  # noqa: E402

from metro.core.stats import allan  # noqa: E402
from metro.core.model.campaign import Campaign, DeviceUnderTest, Segment  # noqa: E402
from metro.core.run.plugin_manager import get_plugin_manager  # noqa: E402
from metro.core.run.runner import run_items  # noqa: E402
from metro.core.base.units import Q_  # noqa: E402
from metro.instruments.readers import write_samples_csv, write_samples_npy  # noqa: E402
from metro.instruments.simulated import GyroTruth, simulate_static  # noqa: E402

ROOT = Path(__file__).resolve().parents[1]
METRO = str(Path(sys.executable).with_name("metro"))

MANIFEST = """format = "metro-campaign/1"
[device]
id = "BENCH"
output = "pulse"
scale_factor = "0.8 P/″"
scale_factor_U = "4 ppm"
[environment]
temperature = "20 °C"
humidity = "40 %"
[site]
latitude = "39.98°"
[[segments]]
id = "static-8h"
kind = "static"
file = "{file}"
sample_interval = "1 ms"
[segments.conditions]
orientation = "IRA up"
"""


def cold_run(manifest: Path) -> dict:
    t0 = time.perf_counter()
    out = subprocess.run([METRO, "run", "-s", "gbt45570", "-i", "D.5.6", "--data", str(manifest),
                          "--json",
                          "--no-report", "--no-progress"], capture_output=True, text=True,
                         check=True)
    wall = time.perf_counter() - t0
    doc = json.loads(out.stdout)
    rwc = [r for r in doc["results"] if r["key"] == "RWC"][0]
    return {"wall": wall, "timings": doc["timings_s"], "rwc": rwc["value"], "U": rwc["U"]}


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--n", type=int, default=28_800_000)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--no-allantools", action="store_true")
    args = ap.parse_args()
    n = args.n
    truth = GyroTruth(seed=8)
    print(f"simulating {n} samples at 1 kHz …", flush=True)
    y = simulate_static(truth, n=n, interval_s=1e-3, latitude_deg=39.98)
    nbytes = y.nbytes
    rows = []
    ref = measure(np.cumsum, y, label="np.cumsum (one pass)", repeat=args.repeat)
    rows.append(ref)
    ms = allan.octave_m(n)
    allan.oadev(y[:100_000], 1e-3, ms[ms < 25_000])  # warm-up (numba compile or cache load)
    rows.append(measure(allan.oadev, y, 1e-3, ms, label="metro oadev octave (numba)",
                        repeat=args.repeat))
    if not args.no_allantools:
        import allantools

        rows.append(measure(allantools.oadev, y, rate=1000.0, data_type="freq", taus="octave",
                            label="allantools.oadev octave", repeat=1))

    pm = get_plugin_manager(autoload=False)
    seg = Segment("static-8h", "static", {"orientation": "IRA up"}, Q_(1, "ms"), sha256="bench",
                  loader=lambda: {"output": (y, "P")})
    dev = DeviceUnderTest("BENCH", properties={"scale_factor": Q_(0.8, "P/arcsec"),
                                               "scale_factor_U": Q_(4e-6, "")})
    camp = Campaign("B", dev, [], {}, {"latitude": Q_(39.98, "deg")}, [seg])
    run_items(pm, "gbt45570", ["D.5.6"], campaign=camp)  # warm-up
    rows.append(measure(run_items, pm, "gbt45570", ["D.5.6"], campaign=camp,
                        label="D.5.6 whole evaluation (in memory)", repeat=args.repeat))
    rec = run_items(pm, "gbt45570", ["D.5.6"], campaign=camp)
    r = rec.outcomes[0].result("RWC")
    print(f"D.5.6 RWC = {r.value.magnitude:.5g} ± {r.U.magnitude:.2g} °/√h (truth "
          f"{truth.arw_deg_rt_h})")

    header = ["what", "best wall s", "cpu s", "extra MiB (traced)", "extra MiB (RSS)",
              "extra / input", "cumsum speed ratio"]
    table = [m.row(nbytes, ref.wall) for m in rows]
    print(format_table(table, header))

    with tempfile.TemporaryDirectory(dir=ROOT / "benchmarks") as tmp:
        tmp = Path(tmp)
        t0 = time.perf_counter()
        write_samples_csv(tmp / "static.csv", {"output": y}, {"output": "P"})
        t_csv = time.perf_counter() - t0
        write_samples_npy(tmp / "static.npy", {"output": y}, {"output": "P"})
        (tmp / "csv.toml").write_text(MANIFEST.format(file="static.csv"), encoding="utf-8")
        (tmp / "npy.toml").write_text(MANIFEST.format(file="static.npy"), encoding="utf-8")
        size = (tmp / "static.csv").stat().st_size
        print(f"CSV written in {t_csv:.1f} s ({size / MiB:.0f} MiB)")
        for name in ("csv", "npy"):
            best = None
            for _ in range(2):
                res = cold_run(tmp / f"{name}.toml")
                if best is None or res["wall"] < best["wall"]:
                    best = res
            print(f"cold metro run D.5.6 on .{name}: {best['wall']:.2f} s wall; stages: "
                  + ", ".join(f"{k} {v:.2f} s" for k, v in best["timings"].items())
                  + f"; RWC {best['rwc']:.4g} ± {best['U']:.2g}")
    helps = []
    for _ in range(5):
        t0 = time.perf_counter()
        subprocess.run([METRO, "--help"], capture_output=True, check=True)
        helps.append(time.perf_counter() - t0)
    print(f"metro --help: best {min(helps):.3f} s, median {sorted(helps)[2]:.3f} s")
    print(f"machine: {os.cpu_count()} cores, numpy {np.__version__}")


if __name__ == "__main__":
    main()

"""Benchmark: metro's CSV reader with pyarrow (the ``fast`` extra) against its numpy parser (the
core install), on a long one-column record and a multi-column one.

Usage::

    .venv/bin/python benchmarks/bench_read_fallback.py [--rounds 3] [--rows 30000000] \
        [--multi-rows 3000000]

Data (written to ``benchmarks/data/`` on first use, gitignored): ``fallback_one_<N>.csv``, header
``output [P]``, seeded normal values rounded to three decimals (an 8 h record at 1 kHz is 28.8 M
rows); ``fallback_multi_<N>.csv``, eight columns (time, three gyro rates to 6 decimals, three
accelerations to 7, a temperature to 3), as an IMU record.  Each read runs in a fresh child process
(``METRO_NO_PYARROW`` unset or 1) with the file in the page cache; the two readers alternate in
``--rounds`` rounds and the best and median wall times of ``read_samples`` are reported, with the
ratio numpy / pyarrow, and a check that both give the same float64 values bit for bit.
"""

from __future__ import annotations

import argparse
import hashlib
import json
import os
import statistics
import subprocess
import sys
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"
SEED = 20261129


def make_data(rows: int, multi_rows: int) -> tuple[Path, Path]:
    import numpy as np

    from metro.instruments.readers import write_samples_csv

    DATA.mkdir(parents=True, exist_ok=True)
    one = DATA / f"fallback_one_{rows / 1e6:g}M.csv"
    multi = DATA / f"fallback_multi_{multi_rows / 1e6:g}M.csv"
    rng = np.random.default_rng(SEED)
    if not one.exists():
        write_samples_csv(one, {"output": np.round(rng.normal(0.0, 1.5e4, rows), 3)},
                          {"output": "P"})
    if not multi.exists():
        cols = {"time": np.arange(multi_rows) * 0.005}
        units = {"time": "s"}
        for k in ("gx", "gy", "gz"):
            cols[k], units[k] = np.round(rng.normal(0.002, 0.01, multi_rows), 6), "°/s"
        for k in ("ax", "ay", "az"):
            cols[k], units[k] = np.round(rng.normal(0.0, 1e-4, multi_rows), 7), "gn"
        cols["temperature"], units["temperature"] = np.round(rng.normal(25.0, 0.05, multi_rows),
                                                             3), "degC"
        write_samples_csv(multi, cols, units)
    return one, multi


def child(path: str) -> dict:
    import numpy as np

    from metro.instruments.readers import read_samples

    if os.environ.get("METRO_NO_PYARROW") in (None, "", "0"):
        import pyarrow.csv  # noqa: F401  (imported lazily by metro; keep the import out of the timing)
    t0 = time.perf_counter()
    table = read_samples(path, rel_interval_tol=None)
    wall = time.perf_counter() - t0
    digest = hashlib.sha256()
    for name in sorted(table.columns):
        digest.update(np.ascontiguousarray(table.columns[name]).tobytes())
    return {"wall": wall, "rows": table.n_rows, "values": digest.hexdigest()}


def run(path: Path, numpy: bool) -> dict:
    env = dict(os.environ)
    env.pop("METRO_NO_PYARROW", None)
    if numpy:
        env["METRO_NO_PYARROW"] = "1"
    out = subprocess.run([sys.executable, __file__, "--child", str(path)], capture_output=True,
                         text=True,
                         env=env, check=True)
    return json.loads(out.stdout)


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--rows", type=int, default=30_000_000)
    ap.add_argument("--multi-rows", type=int, default=3_000_000)
    ap.add_argument("--child")
    args = ap.parse_args()
    if args.child:
        print(json.dumps(child(args.child)))
        return
    files = make_data(args.rows, args.multi_rows)
    for path in files:
        path.read_bytes()  # into the page cache
        times: dict[str, list[float]] = {"pyarrow": [], "numpy": []}
        values = set()
        for _ in range(args.rounds):
            for name in ("pyarrow", "numpy"):
                r = run(path, name == "numpy")
                times[name].append(r["wall"])
                values.add(r["values"])
        best = {k: min(v) for k, v in times.items()}
        med = {k: statistics.median(v) for k, v in times.items()}
        print(f"{path.name} ({path.stat().st_size / 1e6:.0f} MB, {r['rows']} rows): "
              f"pyarrow best {best['pyarrow']:.2f} s median {med['pyarrow']:.2f} s; "
              f"numpy best {best['numpy']:.2f} s median {med['numpy']:.2f} s; "
              f"ratio best {best['numpy'] / best['pyarrow']:.2f}, median "
              f"{med['numpy'] / med['pyarrow']:.2f}; same values: {len(values) == 1}", flush=True)


if __name__ == "__main__":
    main()

"""Benchmark: reading one long samples file with metro versus pandas, pyarrow and polars.

Usage::

    .venv/bin/python benchmarks/bench_read.py [--rounds 5] [--rows 28800000]

The data (a one-column CSV, header ``output [P]``, seeded normal values rounded to three
decimals, about 284 MB for 28.8 M rows, plus the same values as a plain ``.npy``) is
written to ``benchmarks/data/`` on first use (gitignored).  Every measurement runs in a
fresh child process, so each reader starts from the same state and its peak memory is
its own; the file is in the page cache (the parent reads it once first).  The readers are
run in interleaved rounds and the best and median wall times are reported, together with
CPU time, peak memory above the child's baseline, and whether the values read equal the
reference bit for bit.  The ratio is to the fastest third-party CSV reader.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import statistics
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _measure import reset_peak_rss  # noqa: E402  (a sibling script, not a package)

HERE = Path(__file__).resolve().parent
DATA = HERE / "data"
SEED = 20261122

THIRD_PARTY = ("pandas (c)", "pyarrow.csv", "polars")
READERS = (
    "metro",
    "metro + sha256",
    "metro, eager sha256",
    "pandas (c)",
    "pyarrow.csv",
    "pyarrow.csv typed",
    "polars",
    "np.load .npy",
    "metro .npy",
)


def data_paths(rows: int) -> tuple[Path, Path]:
    tag = f"{rows / 1e6:g}M"
    return DATA / f"output_{tag}.csv", DATA / f"output_{tag}.npy"


def make_data(rows: int) -> tuple[Path, Path]:
    import numpy as np

    from metro.instruments.readers import write_samples_csv

    csv_path, npy_path = data_paths(rows)
    if csv_path.exists() and npy_path.exists():
        return csv_path, npy_path
    DATA.mkdir(parents=True, exist_ok=True)
    rng = np.random.default_rng(SEED)
    values = np.round(rng.normal(0.0, 1.5e4, rows), 3)
    t = time.perf_counter()
    write_samples_csv(csv_path, {"output": values}, {"output": "P"})
    print(f"wrote {csv_path.name}: {csv_path.stat().st_size / 1e6:.1f} MB in "
          f"{time.perf_counter() - t:.1f} s (write_samples_csv)", flush=True)
    np.save(npy_path, values)
    return csv_path, npy_path


def _rss() -> int:
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * os.sysconf("SC_PAGE_SIZE")


def _peak() -> int:
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith("VmHWM:"):
                return int(line.split()[1]) * 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024


def child(reader: str, csv_path: Path, npy_path: Path) -> dict:
    """Run one reader once in this (fresh) process and return its measurements."""
    import numpy as np

    if reader.startswith("metro"):
        from metro.instruments.readers import read_samples

        import pyarrow  # noqa: F401  (imported lazily by metro; keep it out of the timing)
        import pyarrow.csv  # noqa: F401
    elif reader == "pandas (c)":
        import pandas as pd
    elif reader.startswith("pyarrow.csv"):
        import pyarrow as pa
        import pyarrow.csv as pacsv

        typed = {
            "read_options": pacsv.ReadOptions(skip_rows=1, column_names=["output"],
                                              block_size=4 << 20),
            "convert_options": pacsv.ConvertOptions(column_types={"output": pa.float64()},
                                                    null_values=[], strings_can_be_null=False),
        }
    elif reader == "polars":
        import polars as pl

    # Third-party readers are timed for their read call alone (as they are usually
    # quoted); getting a numpy array out of them happens after the clock stops.
    def run():
        if reader == "metro":
            return read_samples(csv_path)["output"]
        if reader == "metro + sha256":
            table = read_samples(csv_path)
            assert len(table.sha256) == 64
            return table["output"]
        if reader == "metro, eager sha256":
            return read_samples(csv_path, background_hash=False)["output"]
        if reader == "pandas (c)":
            return pd.read_csv(csv_path, engine="c")
        if reader == "pyarrow.csv":
            return pacsv.read_csv(csv_path)
        if reader == "pyarrow.csv typed":  # the call metro makes, without metro's checks
            return pacsv.read_csv(csv_path, **typed)
        if reader == "polars":
            return pl.read_csv(csv_path)
        if reader == "np.load .npy":
            return np.load(npy_path)
        if reader == "metro .npy":
            return read_samples(npy_path, columns=[("output", "P")])["output"]
        raise ValueError(reader)

    base = _rss()
    if not reset_peak_rss():
        print("warning: cannot reset the peak RSS; peak memory is an upper bound", file=sys.stderr)
    c0 = os.times()
    t0 = time.perf_counter()
    values = run()
    seconds = time.perf_counter() - t0
    c1 = os.times()
    peak = _peak() - base
    if reader == "pandas (c)":
        values = values["output [P]"].to_numpy()
    elif reader.startswith("pyarrow.csv"):
        values = values.column(0).to_numpy()
    elif reader == "polars":
        values = values.to_series(0).to_numpy()
    ref = np.load(npy_path, mmap_mode="r")
    exact = bool(
        values.shape == ref.shape and np.array_equal(values.view(np.uint64), ref.view(np.uint64))
    )
    return {
        "seconds": seconds,
        "cpu": (c1.user - c0.user) + (c1.system - c0.system),
        "peak_mb": peak / 1e6,
        "rows": int(values.shape[0]),
        "exact": exact,
    }


def machine() -> str:
    cpu = "?"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    return f"{os.cpu_count()} cores, {cpu}, Python {platform.python_version()}"


def versions() -> str:
    import numpy
    import pandas
    import polars
    import pyarrow

    return (f"numpy {numpy.__version__}, pyarrow {pyarrow.__version__}, "
            f"pandas {pandas.__version__}, polars {polars.__version__}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rows", type=int, default=28_800_000)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--only", nargs="*", default=None, help="reader names to run")
    ap.add_argument("--child", help=argparse.SUPPRESS)
    ap.add_argument("--json", type=Path, help="also write the results here")
    args = ap.parse_args()
    csv_path, npy_path = data_paths(args.rows)
    if args.child:
        print(json.dumps(child(args.child, csv_path, npy_path)))
        return

    csv_path, npy_path = make_data(args.rows)
    for path in (csv_path, npy_path):  # into the page cache, in pieces (keeps our RSS low)
        with open(path, "rb") as f:
            while f.read(16 << 20):
                pass
    readers = [r for r in READERS if args.only is None or r in args.only]
    results: dict[str, list[dict]] = {r: [] for r in readers}
    print(f"{machine()}\n{versions()}\n{csv_path.name}: {csv_path.stat().st_size / 1e6:.1f} MB, "
          f"{args.rows:,} rows; {args.rounds} interleaved rounds, one child process per run",
          flush=True)
    for k in range(args.rounds):
        for reader in readers:
            out = subprocess.run(
                [sys.executable, __file__, "--rows", str(args.rows), "--child", reader],
                capture_output=True, text=True,
            )
            if out.returncode != 0:
                sys.exit(f"{reader} failed:\n{out.stderr}")
            results[reader].append(json.loads(out.stdout.strip().splitlines()[-1]))
        print(f"  round {k + 1}/{args.rounds} done", flush=True)

    best = {r: min(x["seconds"] for x in v) for r, v in results.items()}
    fastest = min(best[r] for r in THIRD_PARTY if r in best) if any(r in best for r
                                                                    in THIRD_PARTY) else None
    head = (f"{'reader':<22}{'best s':>8}{'median s':>10}{'CPU s':>8}{'peak MB':>9}"
            f"{'exact':>7}{'ratio':>7}")
    print("\n" + head + "\n" + "-" * len(head))
    for r, v in results.items():
        med = statistics.median(x["seconds"] for x in v)
        cpu = statistics.median(x["cpu"] for x in v)
        peak = max(x["peak_mb"] for x in v)
        ratio = f"{best[r] / fastest:.2f}" if fastest else "-"
        exact = "yes" if all(x["exact"] for x in v) else "NO"
        print(f"{r:<22}{best[r]:>8.3f}{med:>10.3f}{cpu:>8.2f}{peak:>9.0f}{exact:>7}{ratio:>7}")
    if fastest:
        print(f"\nratio = best time / best of {', '.join(THIRD_PARTY)} ({fastest:.3f} s)")
    if args.json:
        args.json.write_text(json.dumps({"machine": machine(), "versions": versions(),
                                         "results": results}, indent=1))


if __name__ == "__main__":
    main()

"""Benchmark of metro's Allan statistics on an 8 h, 1 kHz gyro-sized record (28.8 M samples).

Run:  .venv/bin/python benchmarks/bench_allan.py [--n N] [--repeat R] [--no-allantools]

Measures in one run, on the same data (seeded white noise + a small random walk on a
1e7 offset): one ``np.cumsum`` pass (memory-bandwidth reference), metro ``oadev`` at the
octave factors allantools uses (numba kernel after warm-up; pure-numpy fallback),
``allantools.oadev(..., data_type='freq', taus='octave')``, and metro
``block_variance_doubling``; plus the first-call latency of the numba path (JIT compile
with an empty cache, and loading from the on-disk cache) in fresh subprocesses.  Memory is
the peak extra memory of one traced call (see benchmarks/_measure.py).  Prints a table
and the largest relative difference between metro's and allantools' OADEV.
"""

from __future__ import annotations

import argparse
import datetime as _dt
import os
import platform
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from _measure import MiB, format_table, measure
from metro.core.stats import allan

HEADER = [
    "what",
    "best wall s",
    "cpu s",
    "extra MiB (traced)",
    "extra MiB (RSS)",
    "extra / input",
    "vs allantools",
]


def make_data(n: int, seed: int = 20240801) -> np.ndarray:
    rng = np.random.default_rng(seed)
    y = rng.standard_normal(n)
    rw = rng.standard_normal(n)
    rw *= 1e-3
    np.cumsum(rw, out=rw)
    y += rw
    del rw
    y += 1e7
    return y


def first_call_latency(n: int = 1 << 17) -> tuple[float, float]:
    """Wall time of import + first numba oadev call in a fresh process: (cold cache, warm cache)."""
    code = (
        "import time; t = time.perf_counter()\n"
        "import numpy as np\n"
        "from metro.core.stats.allan import oadev\n"
        f"y = np.random.default_rng(0).normal(size={n})\n"
        "oadev(y, 1e-3, engine='numba')\n"
        "print(time.perf_counter() - t)\n"
    )
    out = []
    with tempfile.TemporaryDirectory() as cache:
        env = dict(os.environ, NUMBA_CACHE_DIR=cache)
        env.pop("METRO_NO_NUMBA", None)
        for _ in range(2):
            res = subprocess.run(
                [sys.executable, "-c", code], env=env, capture_output=True, text=True, check=True
            )
            out.append(float(res.stdout.strip().splitlines()[-1]))
    return out[0], out[1]


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=28_800_000, help="number of samples (default 28.8 M)")
    ap.add_argument("--rate", type=float, default=1000.0, help="sample rate in Hz (default 1000)")
    ap.add_argument("--repeat", type=int, default=3, help="timed repetitions (best is reported)")
    ap.add_argument("--no-allantools", action="store_true", help="skip the allantools comparison")
    args = ap.parse_args()

    n, rate = args.n, args.rate
    tau0 = 1.0 / rate
    y = make_data(n)
    nbytes = y.nbytes
    print(f"metro bench_allan  {_dt.datetime.now().isoformat(timespec='seconds')}")
    print(
        f"machine: {platform.machine()} {os.cpu_count()} CPU(s), "
        f"python {platform.python_version()}, numpy {np.__version__}"
    )
    print(f"data: N = {n:,} float64 ({nbytes / MiB:,.0f} MiB), tau0 = {tau0:g} s, offset 1e7\n")

    # allantools' octave list: m = 2^k, k = 0 .. floor(log2 N); OADEV needs N >= 2m
    ms = 1 << np.arange(int(np.floor(np.log2(n))) + 1, dtype=np.int64)
    ms = ms[2 * ms <= n]

    rows = []
    results = {}

    m_cumsum = measure(np.cumsum, y, label="np.cumsum(y) (one pass, reference)", repeat=args.repeat)
    m_cumsum.result = None

    # numba path: warm-up on the data slice compiles (or loads the cached kernel)
    allan.oadev(y[: 1 << 17], tau0, engine="numba")
    m_nb = measure(
        allan.oadev, y, tau0, ms, engine="numba", label="metro oadev, numba", repeat=args.repeat
    )
    results["numba"] = m_nb.result
    m_np = measure(allan.oadev, y, tau0, ms, engine="numpy", label="metro oadev, numpy fallback",
                   repeat=max(1, args.repeat - 1))
    results["numpy"] = m_np.result

    allan.block_variance_doubling(y[: 1 << 17], tau0, engine="numba")
    m_bvd, m_bvd_np = (measure(allan.block_variance_doubling, y, tau0, engine=engine,
                               label=f"metro block_variance_doubling, {engine}",
                               repeat=args.repeat) for engine in ("numba", "numpy"))

    m_at = None
    if not args.no_allantools:
        try:
            import allantools
        except ImportError:
            print("allantools not installed: comparison skipped")
        else:
            m_at = measure(allantools.oadev, y, rate=rate, data_type="freq", taus="octave",
                           label="allantools.oadev(taus='octave')", repeat=max(1, args.repeat - 1))
            results["allantools"] = m_at.result

    cold, warm = first_call_latency()

    ref = m_at.wall if m_at else None
    for m in (m_cumsum, m_nb, m_np, m_at, m_bvd, m_bvd_np):
        if m is not None:
            rows.append(m.row(nbytes, ref))
    print(format_table(rows, HEADER))
    print(
        f"\n{len(ms)} octave factors m = 1 .. {ms[-1]}; numba first call in a fresh process "
        f"(import + compile + run on 2^17 samples): {cold:.2f} s with an empty cache, "
        f"{warm:.2f} s with the on-disk cache"
    )

    nb_dev = results["numba"].deviation
    diff = np.max(np.abs(nb_dev / results["numpy"].deviation - 1))
    print(f"numba vs numpy fallback: max rel diff {diff:.2e}")
    if "allantools" in results:
        taus, dev = results["allantools"][0], results["allantools"][1]
        common = np.isin(np.round(taus * rate).astype(np.int64), ms)
        at_m = np.round(taus[common] * rate).astype(np.int64)
        mine = nb_dev[np.searchsorted(ms, at_m)]
        print(
            f"metro vs allantools OADEV on {common.sum()} common taus: max rel diff "
            f"{np.max(np.abs(mine / dev[common] - 1)):.2e}"
        )
        print(
            f"speed-up of metro numba OADEV over allantools: {m_at.wall / m_nb.wall:.1f}x; "
            f"numpy fallback: {m_at.wall / m_np.wall:.1f}x"
        )
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

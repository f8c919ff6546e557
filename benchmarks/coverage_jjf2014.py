"""Coverage of the JJF 2014—2022 results over many seeds of the simulated station.

Run:  .venv/bin/python benchmarks/coverage_jjf2014.py items  [--seeds 1:31] [--faultless-table]
      .venv/bin/python benchmarks/coverage_jjf2014.py allan  [--seeds 2000:2300]

``items``: every item of the plugin (the options of ``tests/test_jjf2014.py``) on
``simulated-jjf2014`` for each seed; per result, how often |result − expected| ≤ U and the rms
of (result − expected)/(U/2).  ``--faultless-table`` runs the station with ``table_errors=False``.

``allan``: 7.2.20 alone on 1 h records at 0.1 s for three noise mixes (rate random walk
dominating, flicker + ARW, ARW alone); the same two figures for ARW, Q, B, K_rrw and R.

Not a test: a statistical statement needs hundreds of seeds, and the figures go to
docs/standards/jjf2014.md and docs/interpretations.md (7.2.20).
"""

from __future__ import annotations

import argparse
import math
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT / "tests"))

ITEM_KEYS = ("K", "F0", "Kn", "range", "Ka", "Kr", "Kt", "Kg", "dK_shock", "dK_vib", "threshold", "resolution",
             "gamma", "gamma_r", "B0", "Br", "Bt", "Bg", "dB_shock", "dB_vib", "ARW", "Q", "BI", "RRW", "RR", "Bw",
             "Td")
ALLAN_KEYS = ("ARW", "Q", "BI", "RRW", "RR")
MIXES = {"RRW dominating": {"rrw_deg_h_rt_h": 5.0},
         "flicker + ARW": {"bias_instability_deg_h": 1.0, "arw_deg_rt_h": 0.05},
         "ARW alone": {}}


def _seeds(text: str) -> range:
    a, b = (int(x) for x in text.split(":"))
    return range(a, b)


def _campaign(pm, items, truth, options, table_errors=True):
    from metro.core.runner import merge_steps, split_options
    from metro.instruments.vibratory import VibratoryStation

    from test_jjf2014 import LAT

    procs = [pm.procedure("jjf2014", i) for i in items]
    per = split_options(procs, dict(options))
    st = VibratoryStation(truth=truth, latitude_deg=LAT, table_errors=table_errors)
    return st.acquire(merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)]))


def _tally(rows, keys, outcomes, expected):
    for o in outcomes:
        for r in o.results:
            if r.metric.key in keys and r.metric.key in expected:
                d = r.value.to(r.metric.unit).magnitude - expected[r.metric.key].to(r.metric.unit).magnitude
                U = r.U.magnitude
                rows.setdefault(r.metric.key, []).append((abs(d) <= U, d / (U / 2) if U else math.nan))


def _print(title, rows, keys, n, seconds):
    print(f"\n{title}: {n} seeds, {seconds:.0f} s")
    print(f"{'result':12s} {'within U':>10s} {'rms z':>7s}")
    for k in keys:
        if k in rows:
            hit = sum(h for h, _ in rows[k])
            z = np.array([z for _, z in rows[k]])
            print(f"{k:12s} {hit:4d}/{len(rows[k]):<4d} {100 * hit / len(rows[k]):5.1f} % "
                  f"{math.sqrt(np.nanmean(z**2)):5.2f}")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("what", choices=("items", "allan"))
    ap.add_argument("--seeds", help="first:stop (default items 1:31, allan 2000:2300)")
    ap.add_argument("--faultless-table", action="store_true")
    a = ap.parse_args()

    from metro.core.plugins import get_plugin_manager
    from metro.core.runner import run_items
    from metro.instruments.vibratory import VibratoryTruth

    pm = get_plugin_manager(autoload=False)
    if a.what == "items":
        from test_jjf2014 import ALL, OPTS

        seeds = _seeds(a.seeds or "1:31")
        rows: dict = {}
        t0 = time.perf_counter()
        for seed in seeds:
            camp = _campaign(pm, ALL, VibratoryTruth(seed=seed), OPTS, table_errors=not a.faultless_table)
            _tally(rows, ITEM_KEYS, run_items(pm, "jjf2014", ALL, campaign=camp, options=OPTS).outcomes,
                   camp.expected)
        table = "faultless table" if a.faultless_table else "table erring as its certificate says"
        _print(f"every item, {table}", rows, ITEM_KEYS, len(seeds), time.perf_counter() - t0)
        return
    seeds = _seeds(a.seeds or "2000:2300")
    for name, kw in MIXES.items():
        rows = {}
        t0 = time.perf_counter()
        for seed in seeds:
            camp = _campaign(pm, ["7.2.20"], VibratoryTruth(seed=seed, **kw), {})
            _tally(rows, ALLAN_KEYS, run_items(pm, "jjf2014", ["7.2.20"], campaign=camp).outcomes, camp.expected)
        _print(f"7.2.20, {name}", rows, ALLAN_KEYS, len(seeds), time.perf_counter() - t0)


if __name__ == "__main__":
    main()

"""Coverage of a standard's results over many seeds of its simulated station.

Run:  .venv/bin/python benchmarks/within_u.py -s STANDARD (-i ITEMS | --all) [--seeds A:B]
                                              [-o NAME=VALUE ...] [--station-option NAME=VALUE ...]

For each seed the items run on their simulated station (as ``metro run`` without ``--data``, the
seed passed as the station's ``seed``); each result that the station's ``expected`` values cover
is compared with it.  Per result: how often |result − expected| ≤ U, and the rms of
z = (result − expected)/(U/2), which is about 1 when U/2 is the right standard uncertainty.

Not a test: a statistical statement needs hundreds of seeds.  The figures go to the standards'
pages in docs/standards/ and to docs/interpretations.md.  Examples (the recorded runs):

  benchmarks/within_u.py -s gbt45570 -i D.2.1,D.2.2,D.2.3,D.2.4,D.2.5,D.2.6 --seeds 1:301
  benchmarks/within_u.py -s gbt45570 -i D.1.1,…,D.6.4,6.2.6,6.2.7.7,6.2.7.8 --seeds 1:201
  benchmarks/within_u.py -s jjf2014 --all -o records=3 -o "sample_rate=2000 Hz" --seeds 1:31
  benchmarks/within_u.py -s jjf2014 ... --station-option table_errors=false
  benchmarks/within_u.py -s jjf2014 -i 7.2.20 --station-option rrw_deg_h_rt_h=5 --seeds 2000:2300
"""

from __future__ import annotations

import argparse
import math
import time

import numpy as np


def _pairs(values: list[str]) -> dict[str, object]:
    out: dict[str, object] = {}
    for v in values:
        k, _, x = v.partition("=")
        try:
            out[k] = float(x) if any(c in x for c in ".eE") else int(x)
        except ValueError:
            out[k] = x
    return out


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-s", "--standard", required=True)
    ap.add_argument("-i", "--item", default="", help="comma-separated item ids")
    ap.add_argument("--all", action="store_true", help="every item of the standard")
    ap.add_argument("--seeds", default="1:101", help="first:stop")
    ap.add_argument("-o", "--option", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE")
    a = ap.parse_args()

    from metro.core.plugins import get_plugin_manager
    from metro.core.present import truth_checks
    from metro.core.runner import run_items

    pm = get_plugin_manager(autoload=False)
    items = [x for x in a.item.split(",") if x]
    if a.all:
        items = [p.item for p in pm.procedures_of(a.standard)]
    first, stop = (int(x) for x in a.seeds.split(":"))
    options = {k: str(v) for k, v in _pairs(a.option).items()}
    rows: dict[tuple[str, str], list[tuple[bool, float]]] = {}
    t0 = time.perf_counter()
    for seed in range(first, stop):
        rec = run_items(pm, a.standard, items, options=options,
                        station_options=_pairs(a.station_option) | {"seed": seed})
        for c in truth_checks(rec):
            z = (c["value"] - c["truth"]) / (c["U"] / 2) if c["U"] else math.nan
            rows.setdefault((c["item"], c["key"]), []).append((bool(c["within_U"]), z))
    n = stop - first
    print(f"{a.standard}: {len(items)} items, seeds {first}–{stop - 1} ({n}), "
          f"station options {_pairs(a.station_option) or 'none'}, {time.perf_counter() - t0:.0f} s")
    print(f"{'item':10s} {'result':14s} {'within U':>16s} {'rms z':>6s}")
    for (item, key), v in rows.items():
        hit = sum(h for h, _ in v)
        z = np.array([z for _, z in v])
        print(f"{item:10s} {key:14s} {hit:5d}/{len(v):<4d} {100 * hit / len(v):5.1f} % "
              f"{math.sqrt(np.nanmean(z**2)):6.2f}")


if __name__ == "__main__":
    main()

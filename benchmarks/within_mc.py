"""Coverage of the certificate's interval when ``metro run --monte-carlo`` moves it to Monte Carlo.

Run:  .venv/bin/python benchmarks/within_mc.py -s STANDARD (-i ITEMS | --all) [--seeds A:B]
                                               [--station-option NAME=VALUE ...]

For each seed the items run on their simulated station (as benchmarks/within_u.py does), every
budget is checked by Monte Carlo (JCGM 101, core/run/montecarlo_run.py, seeded with the seed),
and each result the station's declared truth covers is compared with it twice: within the GUM
interval value ± U, and within the interval the certificate states — the Monte Carlo shortest
interval where the GUM one is not validated (JCGM 101 clause 8), its ends ± their numerical
tolerance δ, else value ± U.  Per result:
the seeds, how many moved to Monte Carlo, the GUM coverage, and the certificate's coverage over
all seeds and over the moved ones.  Figures in docs/monte-carlo.md.

Example: benchmarks/within_mc.py -s jjf2003 -i 7.2.2,7.2.4,7.2.5 --seeds 1:101
"""

from __future__ import annotations

import argparse
import json
import time


def station_options(values: list[str]) -> dict[str, object]:
    """``NAME=VALUE`` pairs; a value JSON reads (a number, true/false) as what it is, else text."""
    out: dict[str, object] = {}
    for name, _, text in (v.partition("=") for v in values):
        try:
            out[name] = json.loads(text)
        except ValueError:
            out[name] = text
    return out


def sweep(standard: str, items: list[str], seeds: range, station_options: dict) -> dict:
    """(item, key) → list of (moved, within GUM U, within the certificate's interval)."""
    from metro.core.run.montecarlo_run import with_monte_carlo
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    rows: dict[tuple[str, str], list[tuple[bool, bool, bool]]] = {}
    for seed in seeds:
        rec = run_items(pm, standard, items, station_options=station_options | {"seed": seed})
        rec = with_monte_carlo(rec, seed)
        expected = rec.campaign.expected
        for o in rec.outcomes:
            for r in o.results:
                if r.metric.key not in expected or r.monte_carlo is None or not r.reportable:
                    continue
                unit = r.metric.unit
                v = float(r.value.to(unit).magnitude)
                t = float(expected[r.metric.key].to(unit).magnitude)
                gum = abs(v - t) <= float(r.U.magnitude)
                moved = not r.monte_carlo.validated
                mc = r.monte_carlo_dict()
                low, high = mc["interval"]
                # the ends are known to ± δ (JCGM 101 7.9.2): a truth on a bound (K_a = 0) lies
                # below the smallest draw, the interval's lower end, by less than δ
                cert = low - mc["delta"] <= t <= high + mc["delta"] if moved else gum
                rows.setdefault((o.item, r.metric.key), []).append((moved, gum, cert))
    return rows


#: the command line, as benchmarks/within_u.py reads it
OPTIONS = (
    (("-s", "--standard"), {"required": True}),
    (("-i", "--item"), {"default": "", "help": "comma-separated item ids"}),
    (("--all",), {"action": "store_true", "help": "every item of the standard"}),
    (("--seeds",), {"default": "1:101", "help": "first:stop"}),
    (("--station-option",), {"action": "append", "default": [], "metavar": "NAME=VALUE"}),
)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    for flags, kwargs in OPTIONS:
        ap.add_argument(*flags, **kwargs)
    a = ap.parse_args()
    items = [x for x in a.item.split(",") if x]
    if a.all:
        from metro.core.run.plugin_manager import get_plugin_manager

        items = [p.item for p in get_plugin_manager(autoload=False).procedures_of(a.standard)]
    first, stop = (int(x) for x in a.seeds.split(":"))
    t0 = time.perf_counter()
    rows = sweep(a.standard, items, range(first, stop), station_options(a.station_option))
    print(f"{a.standard}: items {','.join(items)}, seeds {first}–{stop - 1}, "
          f"{time.perf_counter() - t0:.0f} s")
    print("| item | result | seeds | moved to MC | within GUM U | within the certificate's "
          "interval | within it, moved seeds |")
    print("|---|---|---|---|---|---|---|")
    for (item, key), v in rows.items():
        n = len(v)
        moved = [c for m, _, c in v if m]
        within_moved = (f"{100 * sum(moved) / len(moved):.1f} % ({len(moved)})" if moved
                        else "—")
        print(f"| {item} | {key} | {n} | {len(moved)} | {100 * sum(g for _, g, _ in v) / n:.1f} % "
              f"| {100 * sum(c for _, _, c in v) / n:.1f} % | {within_moved} |")


if __name__ == "__main__":
    main()

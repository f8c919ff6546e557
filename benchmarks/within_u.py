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

GB/T 45570 device classes (instruments/simulated.py DEVICE_CLASSES; each seed draws one device of
the class): ``--device-class NAME`` (or ``all``) runs every item that applies to the class's
device, seed by seed, and prints per result the fraction within U — a result declared not
reportable (with its reason) counts as covered — and the mean E_n = (result − truth)/U over the
reportable ones:

  nice -n 10 benchmarks/within_u.py -s gbt45570 --device-class all --seeds 1:201
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
    ap = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("-s", "--standard", required=True)
    ap.add_argument("-i", "--item", default="", help="comma-separated item ids")
    ap.add_argument("--all", action="store_true", help="every item of the standard")
    ap.add_argument("--seeds", default="1:101", help="first:stop")
    ap.add_argument("-o", "--option", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE")
    ap.add_argument("--device-class", default="",
                    help="GB/T 45570: a device class of the simulated station, or all")
    ap.add_argument("--classes", default="",
                    help="JJF 2014 / JJF 2003 / ogam: comma-separated device classes, "
                    "each run over the seeds; prints a Markdown table (result, class, seeds, "
                    "within U, mean E_n)")
    a = ap.parse_args()
    if a.device_class:
        gbt_device_classes_main(a)
        return
    if a.classes:
        return jjf_classes_main(a)

    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.cli.present import truth_checks
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    items = [x for x in a.item.split(",") if x]
    if a.all:
        items = [p.item for p in pm.procedures_of(a.standard)]
    first, stop = (int(x) for x in a.seeds.split(":"))
    options = {k: str(v) for k, v in _pairs(a.option).items()}
    rows: dict[tuple[str, str], list[tuple[bool, float, bool]]] = {}
    t0 = time.perf_counter()
    for seed in range(first, stop):
        rec = run_items(pm, a.standard, items, options=options,
                        station_options=_pairs(a.station_option) | {"seed": seed})
        flagged = {(o.item, r.metric.key) for o in rec.outcomes for r in o.results if
                   not r.reportable}
        for c in truth_checks(rec):
            z = (c["value"] - c["truth"]) / (c["U"] / 2) if c["U"] else math.nan
            rows.setdefault((c["item"], c["key"]), []).append(
                (bool(c["within_U"]), z, (c["item"], c["key"]) in flagged))
    n = stop - first
    print(f"{a.standard}: {len(items)} items, seeds {first}–{stop - 1} ({n}), "
          f"station options {_pairs(a.station_option) or 'none'}, {time.perf_counter() - t0:.0f} s")
    # within U: every seed's value against its U; not rep.: seeds declared not reportable; covered:
    # within U or not reportable (issue 13); mean E_n = mean z/2 over the reportable seeds
    print(f"{'item':10s} {'result':14s} {'within U':>16s} {'rms z':>6s} {'not rep.':>8s} "
          f"{'covered':>8s} {'mean E_n':>8s}")
    for (item, key), v in rows.items():
        hit = sum(h for h, _, _ in v)
        z = np.array([z for _, z, _ in v])
        nr = sum(f for _, _, f in v)
        cov = sum(h or f for h, _, f in v)
        zr = np.array([z for _, z, f in v if not f])
        en = f"{np.nanmean(zr) / 2:+8.2f}" if zr.size and np.isfinite(zr).any() else f"{'—':>8s}"
        print(f"{item:10s} {key:14s} {hit:5d}/{len(v):<4d} {100 * hit / len(v):5.1f} % "
              f"{math.sqrt(np.nanmean(z**2)):6.2f} {nr:8d} {100 * cov / len(v):6.1f} % {en}")


# --------------------------------------------------------------------------------------------
# GB/T 45570 device classes
# --------------------------------------------------------------------------------------------


def gbt_class_items(pm, device_class: str, station_options: dict,
                    options: dict) -> tuple[list[str], dict[str, str]]:
    """The items that apply to the class's device, and those that fail on it (item → error):
    each applicable item is tried once on seed 1."""
    from metro.core.run.runner import run_items, select_items, station_device

    so = station_options | {"seed": 1, "device_class": device_class}
    items, _ = select_items(pm, "gbt45570", [], run_all=True,
                            device=station_device(pm, "simulated", so))
    ok, failed = [], {}
    for item in items:
        try:
            run_items(pm, "gbt45570", [item], station="simulated", station_options=so,
                      options=options)
            ok.append(item)
        except Exception as exc:  # noqa: BLE001 - reported in the table, not hidden
            failed[item] = f"{type(exc).__name__}: {str(exc).splitlines()[0][:120]}"
    return ok, failed


def sweep_gbt_class(pm, device_class: str, items: list[str], seeds: range, station_options: dict,
                    options: dict) -> tuple[dict, list[str]]:
    """Per (item, result): a list of (reportable, within U, E_n) over ``seeds``; and the errors."""
    from metro.core.run.runner import run_items

    rows: dict[tuple[str, str], list[tuple[bool, bool, float]]] = {}
    errors = []
    for seed in seeds:
        try:
            rec = run_items(pm, "gbt45570", items, station="simulated", options=options,
                            station_options=station_options | {"seed": seed,
                                                               "device_class": device_class})
        except Exception as exc:  # noqa: BLE001
            errors.append(f"seed {seed}: {type(exc).__name__}: {str(exc).splitlines()[0][:120]}")
            continue
        exp = rec.campaign.expected
        for o in rec.outcomes:
            for r in o.results:
                if r.metric.key not in exp:
                    continue
                if r.U is None:
                    if not r.reportable:  # declared not reportable without a budget: covered
                        rows.setdefault((o.item, r.metric.key), []).append((False, False, math.nan))
                    continue
                unit = r.metric.unit
                v = float(r.value.to(unit).magnitude)
                t = float(exp[r.metric.key].to(unit).magnitude)
                U = float(r.U.magnitude)
                en = (v - t) / U if U > 0 else (0.0 if v == t else math.inf)
                rows.setdefault((o.item, r.metric.key),
                                []).append((bool(r.reportable), abs(en) <= 1.0, en))
    return rows, errors


def gbt_table(device_class: str, rows: dict) -> list[str]:
    """Markdown rows: result, class, seeds, not reportable, within U (or not reportable), mean E_n,
    verdict."""
    out = []
    for (item, key), v in sorted(rows.items()):
        n = len(v)
        nr = sum(1 for rep, _, _ in v if not rep)
        covered = sum(1 for rep, ok, _ in v if ok or not rep)
        ens = [en for rep, _, en in v if rep and math.isfinite(en)]
        # the mean E_n over the reportable seeds (when fewer than 10 are, it says little: n/a)
        mean_en = float(np.mean(ens)) if len(ens) >= 10 else math.nan
        good = covered / n >= 0.95 and (math.isnan(mean_en) or abs(mean_en) <= 0.3)
        en_text = f"{mean_en:+.2f}" if not math.isnan(mean_en) else f"n/a ({len(ens)} reportable)"
        out.append(f"| {item} {key} | {device_class} | {n} | {nr} | {100 * covered / n:.1f} % | "
                   f"{en_text} | {'yes' if good else '**no**'} |")
    return out


def gbt_device_classes_main(a) -> None:
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.instruments.simulated import DEVICE_CLASSES

    pm = get_plugin_manager(autoload=False)
    classes = list(DEVICE_CLASSES) if a.device_class == "all" else a.device_class.split(",")
    first, stop = (int(x) for x in a.seeds.split(":"))
    options = {k: str(v) for k, v in _pairs(a.option).items()}
    so = _pairs(a.station_option)
    print(f"gbt45570 device classes, seeds {first}–{stop - 1}, station options {so or 'none'}, "
          f"item options {options or 'none'}")
    print("| result | class | seeds | not reportable | within U or not reportable | mean E_n | ≥ "
          "95 %, |E_n| ≤ 0.3 |")
    print("|---|---|---|---|---|---|---|")
    notes = []
    for cls in classes:
        t0 = time.perf_counter()
        items = [x for x in a.item.split(",") if x]
        failed = {}
        if not items:
            items, failed = gbt_class_items(pm, cls, so, options)
        rows, errors = sweep_gbt_class(pm, cls, items, range(first, stop), so, options)
        for line in gbt_table(cls, rows):
            print(line, flush=True)
        notes += [f"{cls}: {item} not run — {why}" for item, why in failed.items()]
        notes += [f"{cls}: {e}" for e in errors]
        notes.append(f"{cls}: {len(items)} items, {time.perf_counter() - t0:.0f} s")
    for line in notes:
        print("  " + line)

# ------------------------------------------------------------------ device classes (JJF 2014, JJF
# 2003, ogam)


def class_rows(standard: str, items: list[str], device_class: str, seeds: range,
               options: dict[str, str],
               station_options: dict[str, object]) -> dict[tuple[str, str],
                                                           list[tuple[bool, float]]]:
    """Per (item, result): (within U, E_n = (result − truth)/U) for each seed, the station drawing
    one device of ``device_class`` per seed. A result marked not reportable counts as covered when
    it says why (issue 13: "within U … or declared not reportable with a reason") and has E_n =
    nan."""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.cli.present import truth_checks
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    rows: dict[tuple[str, str], list[tuple[bool, float]]] = {}
    for seed in seeds:
        rec = run_items(pm, standard, items, options=options,
                        station_options=station_options | {"seed": seed,
                                                           "device_class": device_class})
        flagged = {(o.item, r.metric.key): r for o in rec.outcomes for r in o.results if
                   not r.reportable}
        for c in truth_checks(rec):
            if (c["item"], c["key"]) in flagged:
                rows.setdefault((c["item"], c["key"] + " (not reportable)"),
                                []).append((True, math.nan))
                continue
            en = (c["value"] - c["truth"]) / c["U"] if c["U"] else math.nan
            rows.setdefault((c["item"], c["key"]), []).append((bool(c["within_U"]), en))
    return rows


def class_table(device_class: str, rows: dict[tuple[str, str],
                                              list[tuple[bool, float]]]) -> list[str]:
    """Markdown rows: | item | result | class | seeds | within U | mean E_n | rms E_n |."""
    out = []
    for (item, key), v in rows.items():
        hit = sum(h for h, _ in v)
        en = np.array([e for _, e in v], dtype=float)
        fin = en[np.isfinite(en)]
        mean = f"{fin.mean():+.2f}" if fin.size else "—"
        rms = f"{math.sqrt(np.mean(fin**2)):.2f}" if fin.size else "—"
        out.append(f"| {item} | {key} | {device_class} | {len(v)} | {100 * hit / len(v):.1f} % | "
                   f"{mean} | {rms} |")
    return out


def jjf_classes_main(a) -> None:
    items = [x for x in a.item.split(",") if x]
    if a.all:
        from metro.core.run.plugin_manager import get_plugin_manager

        items = [p.item for p in get_plugin_manager(autoload=False).procedures_of(a.standard)]
    first, stop = (int(x) for x in a.seeds.split(":"))
    options = {k: str(v) for k, v in _pairs(a.option).items()}
    st = _pairs(a.station_option)
    print(f"<!-- {a.standard}, items {','.join(items)}, seeds {first}–{stop - 1}, options "
          f"{options or 'none'}, station options {st or 'none'} -->")
    print("| item | result | class | seeds | within U | mean E_n | rms E_n |")
    print("|---|---|---|---|---|---|---|")
    for cls in a.classes.split(","):
        t0 = time.perf_counter()
        rows: dict[tuple[str, str], list[tuple[bool, float]]] = {}
        # a cumulative table every 50 seeds (a long run can be cut short)
        for lo in range(first, stop, 50):
            for k, v in class_rows(a.standard, items, cls, range(lo, min(lo + 50, stop)), options,
                                   st).items():
                rows.setdefault(k, []).extend(v)
            print(f"<!-- {cls}: seeds {first}–{min(lo + 50, stop) - 1}, "
                  f"{time.perf_counter() - t0:.0f} s -->",
                  flush=True)
            for line in class_table(cls, rows):
                print(line, flush=True)


if __name__ == "__main__":
    main()

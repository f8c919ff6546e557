"""JJF 2003 gyro bias drift (plugins/jjf2003/drift.py) on the simulated MIMU's device classes.

Run: nice -n 10 .venv/bin/python benchmarks/jjf2003_drift.py [--classes mems-16bit,mems-12bit,…]
[--seeds 1:101]

For each seed the station acquires the 7.2.1 and 7.2.2 plan (and 7.2.3 from the same sweeps) for a
device of the class; the items run twice: on the records as written (with each segment's
``started``: the drift corrected where resolved) and on the same records without their times (the
row u_b of the drift the trends cannot exclude; not reportable where the pooled drift is
significant). Printed per class: the fraction of gyros whose pooled drift is significant, the
fraction of K_g / g results not reportable without times, and per result group the fraction within U
of the station's ``expected`` (the device without the drift) with times, and the mean and rms E_n;
then without times the fraction within U or not reportable, the mean E_n of the reportable ones and
the median ratio of their U to the same result's U with times. Not a test: the figures go to
docs/standards/jjf2003.md.
"""

from __future__ import annotations

import argparse
import math
import time

import attrs
import numpy as np


#: the options a class assumes (mems-power-on: three further calibrations for u₃ of K_g, as on
#: docs/standards/jjf2003.md "Device classes")
CLASS_OPTIONS = {"mems-power-on": {"repeats": "3"}}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--classes", default="mems-16bit,mems-12bit,mems-power-on,mems-warmup")
    ap.add_argument("--seeds", default="1:101")
    a = ap.parse_args()
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import merge_steps, run_items, split_options
    from metro.instruments.mimu import station_factory
    from metro.plugins.jjf2003 import drift as D

    pm = get_plugin_manager(autoload=False)
    lo, hi = (int(x) for x in a.seeds.split(":"))
    items = ["7.2.1", "7.2.2", "7.2.3"]
    procs = [pm.procedure("jjf2003", i) for i in items]
    print("| class | seeds | gyros with a significant drift | K_g, g not reportable without times "
          "| group | within U with times | mean E_n | rms E_n | without times: within U or n.r. | "
          "mean E_n | U ratio |")
    print("|---|---|---|---|---|---|---|---|---|---|---|")
    for cls in a.classes.split(","):
        t0 = time.time()
        opts = CLASS_OPTIONS.get(cls, {})
        per = split_options(procs, opts)
        steps = merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)])
        sig, nr, nres = 0, 0, 0
        groups: dict[str, list[float]] = {}
        bare_groups: dict[str, list[tuple[float, float]]] = {}
        for seed in range(lo, hi):
            camp = station_factory(seed=seed, device_class=cls).acquire(steps)
            rec = run_items(pm, "jjf2003", items, campaign=camp, options=opts)
            exp = rec.campaign.expected
            U_with = {}
            for o in rec.outcomes:
                for r in o.results:
                    k = r.metric.key
                    if not k.startswith(("K_g", "g_")) or k not in exp:
                        continue
                    g = ("K_g diagonal" if k[3] == k[4]
                         else "K_g off-diagonal") if k.startswith("K_g") else \
                        ("g diagonal" if k[2] == k[3] else "g off-diagonal")
                    g = f"{o.item} {g}"
                    U = float(r.U.magnitude)
                    U_with[(o.item, k)] = U
                    e = (float(r.value.magnitude)
                         - float(exp[k].to(r.value.units).magnitude)) / U if U > 0 else math.inf
                    groups.setdefault(g, []).append(e)
            bare = attrs.evolve(camp, segments=[attrs.evolve(s, started=None) for s
                                                in camp.segments])
            d = D.campaign_drift(bare)
            sig += sum(d.significant(i) for i in range(3))
            rec2 = run_items(pm, "jjf2003", items, campaign=bare, options=opts)
            for o in rec2.outcomes:
                for r in o.results:
                    k = r.metric.key
                    if k.startswith(("K_g", "g_")):
                        nres += 1
                        nr += not r.reportable
                    if (o.item, k) not in U_with:
                        continue
                    g = ("K_g diagonal" if k[3] == k[4]
                         else "K_g off-diagonal") if k.startswith("K_g") else \
                        ("g diagonal" if k[2] == k[3] else "g off-diagonal")
                    U = float(r.U.magnitude)
                    if not r.reportable:
                        bare_groups.setdefault(f"{o.item} {g}", []).append((math.nan, math.nan))
                        continue
                    e = (float(r.value.magnitude)
                         - float(exp[k].to(r.value.units).magnitude)) / U if U > 0 else math.inf
                    bare_groups.setdefault(f"{o.item} {g}", []).append((e, U / U_with[(o.item, k)]))
        n = hi - lo
        first = True
        for g, es in sorted(groups.items()):
            es_ = np.array(es)
            head = (f"| {cls} | {n} | {sig} of {3 * n} ({100 * sig / (3 * n):.1f} %) | {nr} of "
                    f"{nres} ({100 * nr / max(nres, 1):.1f} %) |") if first else "| | | | |"
            b = np.array(bare_groups.get(g, [(math.nan, math.nan)]))
            ok = ~np.isnan(b[:, 0])
            cov = np.mean(np.where(ok, np.abs(np.nan_to_num(b[:, 0])) <= 1, True))
            mean_b = f"{b[ok, 0].mean():+.2f}" if ok.any() else "—"
            ratio = f"{np.median(b[ok, 1]):.2f}" if ok.any() else "—"
            print(f"{head} {g} | {100 * np.mean(np.abs(es_) <= 1):.1f} % | {es_.mean():+.2f} | "
                  f"{math.sqrt(np.mean(es_**2)):.2f} | {100 * cov:.1f} % | {mean_b} | {ratio} |")
            first = False
        print(f"<!-- {cls}: {time.time() - t0:.0f} s -->")


if __name__ == "__main__":
    main()

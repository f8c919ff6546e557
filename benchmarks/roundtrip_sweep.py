"""Sweep of plan → acquire → run round trips: every item of every loaded standard on every
simulated station (plus a few multi-item and series cases), through the real CLI entry
(``metro.core.cli.app.main``, in-process).

Each case ends in one of:

* ``ok`` — plan and acquire exit 0, run evaluates (exit 0, or 3/4: does not conform /
  indeterminate);
* ``refused``  — acquire exits 2 with a message and writes nothing (a clean refusal);
* ``broken``   — acquire wrote a campaign that run does not evaluate (exit ≠ 0);
* ``leak``     — acquire refused but left something in --out;
* ``crash``    — a traceback (an exception escaped the CLI) or an exit code other than 0/2.

Usage: ``nice -n 10 python benchmarks/roundtrip_sweep.py [--json out.json] [--only STD]``.
"""

from __future__ import annotations

import argparse
import contextlib
import io
import json
import shutil
import sys
import tempfile
import time
import traceback
from pathlib import Path

STATIONS = ("simulated", "simulated-digital", "simulated-jjf2014", "simulated-mimu",
            "simulated-ogam")
#: stations that take the option duration_scale (--scale)
SCALED = ("simulated", "simulated-digital", "simulated-jjf2014", "simulated-mimu")
SCALE: float | None = None


def _cli(argv: list[str]) -> tuple[int | str, str]:
    from metro.core.cli.app import main

    err = io.StringIO()
    out = io.StringIO()
    try:
        with contextlib.redirect_stderr(err), contextlib.redirect_stdout(out):
            rc = main(argv)
    except SystemExit as exc:  # argparse
        rc = exc.code if isinstance(exc.code, int) else 2
    except BaseException:  # noqa: BLE001 - a traceback is what we count
        return "traceback", traceback.format_exc().strip().splitlines()[-1]
    return rc, err.getvalue().strip().splitlines()[0] if err.getvalue().strip() else ""


def case(standard: str, items: str, station: str, root: Path, seed: int = 7) -> dict:
    out = root / f"{standard}-{items.replace(',', '+')}-{station}".replace(":", "_")[:120]
    rec = {"standard": standard, "items": items, "station": station}
    rc, msg = _cli(["plan", "-s", standard, "-i", items, "--json"])
    rec["plan"] = rc
    if rc == "traceback":
        rec.update(result="crash", where="plan", message=msg)
        return rec
    argv = ["acquire", "-s", standard, "-i", items, "--station", station, "--out", str(out),
            "--seed", str(seed),
            "--no-progress"]
    if SCALE is not None and station in SCALED:
        argv += ["--station-option", f"duration_scale={SCALE}"]
    t0 = time.perf_counter()
    rc, msg = _cli(argv)
    rec["acquire"], rec["acquire_s"] = rc, round(time.perf_counter() - t0, 2)
    if rc == "traceback" or rc not in (0, 2):
        rec.update(result="crash", where="acquire", message=msg)
        return rec
    if rc == 2:
        rec.update(result="leak" if out.exists() else "refused", message=msg)
        return rec
    rc, msg = _cli(["run", "-s", standard, "-i", items, "--data", str(out / "manifest.toml"),
                    "--no-report",
                    "--json", "--no-progress"])
    rec["run"] = rc
    # run's exit codes for an evaluation: 0 (conforms / nothing judged), 3 (does not conform), 4
    # (indeterminate)
    if rc == "traceback" or rc not in (0, 2, 3, 4):
        rec.update(result="crash", where="run", message=msg)
    elif rc == 2:
        rec.update(result="broken", message=msg)
    else:
        rec["result"] = "ok"
    shutil.rmtree(out, ignore_errors=True)
    return rec


def cases(only: str | None) -> list[tuple[str, str, str]]:
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    out = []
    stds: dict[str, list[str]] = {}
    for cls in pm.registry.procedures.values():
        stds.setdefault(cls.cls.standard, []).append(cls.cls.item)
    for std in sorted(stds):
        if only and std != only:
            continue
        for item in sorted(stds[std]):
            for st in STATIONS:
                out.append((std, item, st))
    extra = [("gbt45570", "D.2.1,D.3", "simulated-digital"),
             ("gbt45570", "D.1.1,D.2.1", "simulated"),
             ("gbt45570", "scale-factor", "simulated"),
             ("gbt45570", "scale-factor", "simulated-digital"),
             ("gbt45570", "bias", "simulated"), ("gbt45570", "misalignment", "simulated-digital")]
    out += [e for e in extra if not only or e[0] == only]
    return out


def main() -> int:
    ap = argparse.ArgumentParser()
    ap.add_argument("--json", help="write every case's record here")
    ap.add_argument("--only", help="one standard")
    ap.add_argument("--scale", type=float,
                    help="duration_scale of the stations that take it (default: none given)")
    args = ap.parse_args()
    global SCALE
    SCALE = args.scale
    t0 = time.perf_counter()
    recs = []
    with tempfile.TemporaryDirectory() as d:
        for std, items, st in cases(args.only):
            r = case(std, items, st, Path(d))
            recs.append(r)
            print(f"{r['result']:8s} {std}:{items} @ {st}  {r.get('message', '')[:150]}",
                  flush=True)
    from collections import Counter

    c = Counter(r["result"] for r in recs)
    print(f"\n{len(recs)} cases in {time.perf_counter() - t0:.0f} s: "
          + ", ".join(f"{k} {v}" for k, v in sorted(c.items())))
    consistent = c["ok"] + c["refused"]
    print(f"consistent (ok or clean refusal): {consistent}/{len(recs)}")
    per_item: dict[str, list[str]] = {}
    for r in recs:
        per_item.setdefault(f"{r['standard']}:{r['items']}",
                            []).extend([r["station"]] if r["result"] == "ok" else [])
    none = [k for k, v in per_item.items() if not v]
    print(f"items/sets evaluated on no station: {len(none)} {none}")
    if args.json:
        Path(args.json).write_text(json.dumps(recs, indent=1, ensure_ascii=False))
    return 0


if __name__ == "__main__":
    sys.exit(main())

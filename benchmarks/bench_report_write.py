"""Writing the report of a GB/T 45570 --all run: this tree against another commit, in one run.

Run:  .venv/bin/python benchmarks/bench_report_write.py [--base DIR] [--runs N] [--data MANIFEST]

``--base`` is a checkout of the commit to compare with (default ``/tmp/metro-base``; make one
with ``git worktree add /tmp/metro-base 3dea654``).  Both trees run in this venv: a small
bootstrap puts the tree's ``core``, ``plugins`` and ``instruments`` folders in front of the
installed ``metro`` package, then calls its ``metro run``.

In ONE run, on the same recorded campaign (``metro acquire --standard gbt45570 --all``, written
by the base tree unless ``--data`` is given), the two trees taking turns, ``--runs`` times each
(default 5), each in a fresh process:

* ``metro run --standard gbt45570 --all --data … --json``: the run's own stage timing ``write
  report`` (context, figures, document, saving it) and the process's wall and CPU time.  The
  figure cache is off (``METRO_FIGURE_CACHE=off``): a run on new data draws every figure;
* writing the same report again from its stored context, as ``metro report NUMBER`` and
  ``metro amend`` do: the context as the register keeps it (``encode_context`` → JSON →
  ``decode_context``), written by ``render_context`` (timed: decoding and writing); the figure
  cache on, in a folder of the benchmark's own that the first writing filled.

The tables give medians (and min–max).  docs/performance.md ("Writing documents") records them.
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: runs ``metro`` from the source tree given as the first argument (its packages first on the path)
BOOT = r"""
import importlib.abc, importlib.machinery, importlib.util, sys
from pathlib import Path

root = Path(sys.argv.pop(1)).resolve()
folders = {"metro": root / "core" / "_metro", "metro.core": root / "core",
           "metro.instruments": root / "instruments", "metro.plugins": root / "plugins"}


class Tree(importlib.abc.MetaPathFinder):
    def find_spec(self, name, path=None, target=None):
        folder = folders.get(name)
        if folder is None:
            return None
        init = folder / "__init__.py"
        if init.is_file():
            return importlib.util.spec_from_file_location(
                name, init, submodule_search_locations=[str(folder)])
        spec = importlib.machinery.ModuleSpec(name, None, is_package=True)
        spec.submodule_search_locations = [str(folder)]
        return spec


sys.meta_path.insert(0, Tree())
"""

#: the module paths of the tree's layout (core by layer since the architecture change; flat before)
LAYOUT = """
try:
    from metro.core.cli.app import main
    from metro.core.documents import report
    from metro.core.record.registering import decode_context, encode_context, unregistered
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items
except ImportError:
    from metro.core.cli import main
    from metro.core import report
    from metro.core.registering import decode_context, encode_context, unregistered
    from metro.core.plugins import get_plugin_manager
    from metro.core.runner import run_items
"""

CLI = BOOT + LAYOUT + """

sys.exit(main(sys.argv[1:]))
"""

#: ``prepare MANIFEST JSON DOCX``: run --all, keep the context as the register does, write it once;
#: ``write JSON DOCX``: write it again from the kept context, print the seconds it took
REWRITE = BOOT + LAYOUT + """
import json, time

if sys.argv[1] == "prepare":
    pm = get_plugin_manager()
    record = run_items(pm, "gbt45570", [], data=sys.argv[2], run_all=True)
    designations = {s.id: s.designation for s in pm.registry.standards.values()}
    ctx = report.build_context(record, designations=designations,
                               extend=pm.extend_report_context,
                               register=unregistered(record, "no lab profile"))
    layout = pm.template_for("gbt45570").layout
    with open(sys.argv[3], "w", encoding="utf-8") as fh:
        json.dump({"layout": layout, "context": encode_context(ctx)}, fh, ensure_ascii=False)
    report.render_context(sys.argv[4], ctx, layout=layout)
else:
    t0 = time.perf_counter()
    with open(sys.argv[2], encoding="utf-8") as fh:
        kept = json.load(fh)
    report.render_context(sys.argv[3], decode_context(kept["context"]), layout=kept["layout"])
    print(time.perf_counter() - t0)
"""


def metro(tree: Path, args: list[str], *, code: str = CLI, env: dict[str, str] | None = None
          ) -> subprocess.CompletedProcess:
    return subprocess.run([sys.executable, "-c", code, str(tree), *args], capture_output=True,
                          text=True,
                          env={**os.environ, **(env or {})})


def acquire(tree: Path, out: Path) -> Path:
    p = metro(tree, ["acquire", "--standard", "gbt45570", "--all", "--out", str(out)])
    if p.returncode != 0:
        raise SystemExit(f"acquire failed ({tree}):\n{p.stderr[-2000:]}")
    return out / "manifest.toml"


def one_run(tree: Path, data: Path, out: Path) -> dict[str, float]:
    """One cold ``metro run --all --json``: its ``write report`` stage, the process's wall and
    CPU."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    p = metro(tree, ["run", "--standard", "gbt45570", "--all", "--data", str(data), "--out",
                     str(out), "--json"],
              env={"METRO_FIGURE_CACHE": "off"})
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    # 3/4: the device does not conform / indeterminate (still a report)
    if p.returncode not in (0, 3, 4):
        raise SystemExit(f"metro run failed ({tree}, exit {p.returncode}):\n{p.stderr[-2000:]}")
    timings = json.loads(p.stdout)["timings_s"]
    evaluate = sum(v for k, v in timings.items() if k.startswith(("evaluate", "read samples")))
    return {"write report": timings["write report"], "evaluate": evaluate, "wall": wall,
            "cpu": (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)}


def rewrite(tree: Path, kept: Path, out: Path, cache: Path) -> float:
    """Seconds to write the report again from its kept context (``REWRITE write``)."""
    p = metro(tree, ["write", str(kept), str(out)], code=REWRITE,
              env={"METRO_CACHE_DIR": str(cache)})
    if p.returncode != 0:
        raise SystemExit(f"writing from the kept context failed ({tree}):\n{p.stderr[-2000:]}")
    return float(p.stdout.strip().splitlines()[-1])


def prepare(tree: Path, data: Path, kept: Path, out: Path, cache: Path) -> None:
    p = metro(tree, ["prepare", str(data), str(kept), str(out)], code=REWRITE,
              env={"METRO_CACHE_DIR": str(cache)})
    if p.returncode != 0:
        raise SystemExit(f"keeping the context failed ({tree}):\n{p.stderr[-2000:]}")


def table(title: str, trees: dict[str, Path], results: dict[str, list[dict[str, float]]],
          cols: tuple[str, ...]) -> dict[tuple[str, str], float]:
    print(f"\n{title}")
    print("| tree | " + " | ".join(f"{c} s" for c in cols) + " |")
    print("|---|" + "---|" * len(cols))
    med = {}
    for name in trees:
        cells = []
        for c in cols:
            xs = [r[c] for r in results[name]]
            med[name, c] = statistics.median(xs)
            cells.append(f"{med[name, c]:.2f} ({min(xs):.2f}–{max(xs):.2f})")
        print(f"| {name} | " + " | ".join(cells) + " |")
    return med


def git_describe(tree: Path) -> str:
    p = subprocess.run(["git", "-C", str(tree), "log", "-1", "--format=%h %s"], capture_output=True,
                       text=True)
    dirty = subprocess.run(["git", "-C", str(tree), "status", "--porcelain",
                            "--untracked-files=no"],
                           capture_output=True, text=True).stdout.strip()
    return (p.stdout.strip()[:60] or str(tree)) + (" (+ uncommitted changes)" if dirty else "")


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--base", type=Path, default=Path("/tmp/metro-base"),
                    help="checkout of the commit to compare with")
    ap.add_argument("--runs", type=int, default=5, help="runs of each tree (default 5)")
    ap.add_argument("--data", type=Path,
                    help="a recorded campaign's manifest (default: acquired now by --base)")
    args = ap.parse_args(argv)
    if not (args.base / "core" / "cli.py").is_file() and not (args.base / "core" / "cli"
                                                              / "app.py").is_file():
        raise SystemExit(f"{args.base} is not a metro checkout: git worktree add {args.base} "
                         "3dea654")
    trees = {"base": args.base, "this tree": ROOT}
    tag = {"base": "base", "this tree": "this"}
    with tempfile.TemporaryDirectory(prefix="bench-report-") as tmp:
        tmp = Path(tmp)
        data = args.data or acquire(args.base, tmp / "campaign")
        runs: dict[str, list[dict[str, float]]] = {name: [] for name in trees}
        again: dict[str, list[dict[str, float]]] = {name: [] for name in trees}
        # one warm-up each (bytecode, pint caches), the context kept
        for name, tree in trees.items():
            one_run(tree, data, tmp / f"warm-{tag[name]}")
            prepare(tree, data, tmp / f"kept-{tag[name]}.json", tmp / f"kept-{tag[name]}.docx", tmp
                    / f"cache-{tag[name]}")
        for i in range(args.runs):
            for name, tree in (trees.items() if i % 2 == 0 else reversed(trees.items())):
                runs[name].append(one_run(tree, data, tmp / f"run-{i}-{tag[name]}"))
                again[name].append({"write again": rewrite(tree, tmp / f"kept-{tag[name]}.json",
                                                           tmp / f"again-{i}-{tag[name]}.docx", tmp
                                                           / f"cache-{tag[name]}")})
                print(f"{i + 1}/{args.runs} {name}: write report "
                      f"{runs[name][-1]['write report']:.2f} s, again "
                      f"{again[name][-1]['write again']:.2f} s", file=sys.stderr)
    print(f"GB/T 45570 --all on recorded data, {args.runs} runs each, medians (min–max); "
          f"load average at the end {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
    for name, tree in trees.items():
        print(f"  {name}: {git_describe(tree)}")
    med = table("metro run --all --json (figure cache off)", trees, runs,
                ("write report", "evaluate", "wall", "cpu"))
    med2 = table("the report written again from its kept context (figure cache on)", trees, again,
                 ("write again",))
    print(f"\nwrite report: {med['base', 'write report'] / med['this tree', 'write report']:.1f}x "
          f"faster; whole run: {med['base', 'wall'] / med['this tree', 'wall']:.1f}x; written "
          f"again: {med2['base', 'write again'] / med2['this tree', 'write again']:.1f}x")
    return 0


if __name__ == "__main__":
    sys.exit(main())

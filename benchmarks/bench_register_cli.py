"""Time the register commands of two metro trees side by side: this checkout and a base (e.g. the
commit before the start-up work, checked out with ``git worktree add /tmp/metro-base 3dea654``).

    python benchmarks/bench_register_cli.py --base-src /tmp/metro-base [--runs 5] [--json]

Both trees run with this interpreter and its installed packages; each tree is put first on
``PYTHONPATH`` through a folder of links (``metro/core``, ``metro/plugins``,
``metro/instruments`` → the tree), so ``python -m metro`` is that tree's command.  A register of
20 reports (simulated runs registered with ``--register-simulated``: JJF 2014 7.2.3 and GB/T 45570
D.5.6, four devices with five calibrations each) is written once, by the base tree when one is
given (so that both read a register the older code wrote), then every command runs as a fresh
process, base and head one after the other, ``--runs`` times; the table gives the median wall time
and the median CPU time (user + system of the process), which a busy machine inflates less; one
untimed run of each command per tree comes first (byte code compiled, files cached).
``amend`` works on a fresh copy of the 20-report register at each run (``METRO_REGISTER``).
"""

from __future__ import annotations

import argparse
import json
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parents[1]
N_REPORTS = 20
#: command → target (s) from issue 29's "Done when"
TARGETS = {"register list": 0.5, "register show": 0.5, "history": 1.5, "report N": 3.0,
           "amend": 3.0}


def shim(tree: Path, where: Path) -> Path:
    """A folder whose ``metro`` namespace is ``tree`` (put first on PYTHONPATH)."""
    pkg = where / "metro"
    pkg.mkdir(parents=True)
    for part in ("core", "plugins", "instruments"):
        (pkg / part).symlink_to(tree / part)
    shutil.copy(tree / "core" / "_metro" / "__main__.py", pkg / "__main__.py")
    return where


def environment(path: Path, lab: Path, extra: dict[str, str] | None = None) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(path), METRO_LAB=str(lab), COLUMNS="120")
    env.pop("METRO_REGISTER", None)
    env.update(extra or {})
    return env


BUILD = """
import sys
try:
    from metro.core.cli.app import main
except ImportError:  # the flat layout before the architecture change
    from metro.core.cli import main
out = sys.argv[1]
for i in range({n}):
    seed = str(1 + i % 4)  # four devices ("seed 1" … "seed 4"), five calibrations each
    std = ["-s", "jjf2014", "-i", "7.2.3"] if i % 2 == 0 else [
        "-s", "gbt45570", "-i", "D.5.6", "--station-option", "duration_scale=0.05"]
    code = main(["run", *std, "--seed", seed, "--quiet", "--register-simulated", "--out", out,
                 "--json"])
    assert code in (0, 3, 4), code
"""


def build_register(path: Path, work: Path) -> tuple[Path, list[dict]]:
    """``metro lab init`` and 20 registered runs with the tree at ``path``; the lab profile and the
    list."""
    lab = work / "lab.toml"
    env = environment(path, lab)
    subprocess.run([sys.executable, "-m", "metro", "lab", "init", str(lab)], env=env, check=True,
                   capture_output=True)
    subprocess.run([sys.executable, "-c", BUILD.format(n=N_REPORTS), str(work / "reports")],
                   env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    listed = subprocess.run([sys.executable, "-m", "metro", "register", "list", "--json"], env=env,
                            check=True,
                            capture_output=True, text=True)
    reports = json.loads(listed.stdout)["reports"]
    assert len(reports) == N_REPORTS, len(reports)
    return lab, reports


def timed(argv: list[str], env: dict[str, str]) -> tuple[float, float, int, str]:
    """(wall s, CPU s of the child, exit code, stderr's last line) of one fresh process."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    t0 = time.perf_counter()
    done = subprocess.run([sys.executable, "-m", "metro", *argv], env=env,
                          stdout=subprocess.DEVNULL,
                          stderr=subprocess.PIPE, text=True)
    wall = time.perf_counter() - t0
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    return wall, cpu, done.returncode, (done.stderr.strip().splitlines() or [""])[-1]


def commands(reports: list[dict], work: Path, run: int,
             version: str) -> dict[str, tuple[list[str], dict]]:
    """Each benchmarked command's arguments (and extra environment) for one run of one version."""
    number = reports[3]["number"]
    serial = reports[0]["device"]["serial"]
    fresh = work / f"{version}-{run}"
    issued = [r["number"] for r in reports if r["status"] == "issued"]
    run = run % len(issued)  # the warm-up (-1) amends the last one
    register = work / "register.sqlite"
    copy = fresh / "register.sqlite"
    return {
        "--version": (["--version"], {}),
        "register list": (["register", "list"], {}),
        "register show": (["register", "show", number], {}),
        "history": (["history", serial, "--out", str(fresh / "history")], {}),
        "report N": (["report", number, "--out", str(fresh / "report")], {}),
        "amend": (["amend", issued[run], "--reason", "benchmark", "--out", str(fresh / "amend")],
                  {"METRO_REGISTER": "sqlite:///" + str(copy), "_copy": (register, copy)}),
    }


def bench(trees: dict[str, Path], reports: list[dict], lab: Path, work: Path,
          runs: int) -> dict[str, dict]:
    """Each command once untimed per tree (byte-code compiled and cached, files in the page cache),
    then ``runs`` timed runs, the trees taking turns."""
    figures: dict[str, dict] = {}
    for run in range(-1, runs):
        for version, path in trees.items():
            for name, (argv, extra) in commands(reports, work, run, version).items():
                extra = dict(extra)
                if "_copy" in extra:
                    src, dst = extra.pop("_copy")
                    dst.parent.mkdir(parents=True, exist_ok=True)
                    shutil.copy(src, dst)
                wall, cpu, code, last = timed(argv, environment(path, lab, extra))
                if code != 0:
                    raise SystemExit(f"{version}: metro {' '.join(argv)} exited {code}: {last}")
                if run < 0:  # the warm-up
                    continue
                slot = figures.setdefault(name, {}).setdefault(version, {"wall": [], "cpu": []})
                slot["wall"].append(wall)
                slot["cpu"].append(cpu)
    return figures


def table(figures: dict[str, dict], versions: list[str]) -> str:
    head = "| command | " + " | ".join(f"{v}: wall (CPU) s" for v in versions) + " | target |"
    lines = [head, "|---" * (len(versions) + 2) + "|"]
    for name, per in figures.items():
        cells = [f"{statistics.median(per[v]['wall']):.2f} ({statistics.median(per[v]['cpu']):.2f})"
                 for v in versions]
        target = TARGETS.get(name)
        lines.append(f"| `{name}` | " + " | ".join(cells)
                     + f" | {f'≤ {target:g} s' if target else '—'} |")
    return "\n".join(lines)


def main() -> int:
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("--base-src", type=Path,
                   help="a checkout of the base commit (e.g. a git worktree of 3dea654)")
    p.add_argument("--runs", type=int, default=5,
                   help="runs of each command per tree (median; default 5)")
    p.add_argument("--json", action="store_true", help="print the raw figures as JSON")
    args = p.parse_args()
    with tempfile.TemporaryDirectory(prefix="metro-bench-register-") as tmp:
        work = Path(tmp)
        trees = {}
        if args.base_src:
            trees["base"] = shim(args.base_src.resolve(), work / "shim-base")
        trees["head"] = shim(HERE, work / "shim-head")
        load0 = os.getloadavg()
        t0 = time.perf_counter()
        lab, reports = build_register(trees["base" if "base" in trees else "head"], work)
        built = time.perf_counter() - t0
        figures = bench(trees, reports, lab, work, args.runs)
        load1 = os.getloadavg()
    if args.json:
        print(json.dumps({"figures": figures, "runs": args.runs, "load": [load0, load1],
                          "build_s": built},
                         indent=2))
        return 0
    print(f"register of {N_REPORTS} reports written in {built:.0f} s; {args.runs} runs per command "
          f"and tree; load average {load0[0]:.1f} → {load1[0]:.1f} on {os.cpu_count()} CPUs")
    print(table(figures, list(trees)))
    return 0


if __name__ == "__main__":
    sys.exit(main())

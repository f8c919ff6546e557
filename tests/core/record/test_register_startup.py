"""What the register commands load (issue 29, speed): their time went to imports, so the modules a
fresh process holds after the command are checked here, not the time (benchmarks/
bench_register_cli.py measures that)."""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from metro.core.cli.app import main

#: what reading the register needs none of
HEAVY = {"sqlalchemy", "alembic", "pint", "numpy", "scipy", "matplotlib", "docx", "dask",
         "distributed", "numba",
         "pyarrow"}

PROBE = """
import json, sys
from metro.core.cli.app import main
code = main(sys.argv[2:])
with open(sys.argv[1], "w") as fh:
    json.dump({"code": code, "modules": sorted({m.split(".")[0] for m in sys.modules})}, fh)
"""


def _loaded(tmp_path: Path, *argv: str, env: dict[str, str]) -> tuple[int, set[str]]:
    out = tmp_path / "modules.json"
    subprocess.run([sys.executable, "-c", PROBE, str(out), *argv], env=env, check=True,
                   stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    doc = json.loads(out.read_text())
    return doc["code"], set(doc["modules"])


@pytest.fixture
def register(tmp_path, capsys, draft_rows):
    """A lab profile (with equipment: reading it needs pint) and a register of two reports."""
    from metro.core.record.lab import load_lab
    from metro.core.record.register import Draft, open_register

    lab = tmp_path / "lab.toml"
    assert main(["lab", "init", str(lab)]) == 0
    capsys.readouterr()
    profile = load_lab(lab)
    assert profile.equipment  # the template lists the lab's equipment
    numbers = []
    with open_register(profile.register_url()) as reg:
        for day in (1, 2):
            fields, result = draft_rows(day=day)
            numbers.append(reg.issue(lambda n, t, f=fields,
                                     r=result: Draft(f, [r], lambda p: p.write_text("x")),
                                     folder=tmp_path / "reports", scheme=profile.format_number,
                                     per_year=True).number)
    env = dict(os.environ, METRO_LAB=str(lab))
    env.pop("METRO_REGISTER", None)
    return env, numbers


@pytest.mark.parametrize("argv", [["register", "list"], ["register", "show", "{n}"],
                                  ["register", "verify"],
                                  ["register", "list", "--json"]], ids=lambda a: " ".join(a))
def test_reading_the_register_loads_nothing_heavy(register, tmp_path, argv):
    env, numbers = register
    code, modules = _loaded(tmp_path, *[a.format(n=numbers[0]) for a in argv], env=env)
    assert code == 0
    assert modules & HEAVY == set()


def test_loading_the_plugins_imports_no_scipy(tmp_path):
    """core.lsq imports scipy.linalg where it fits, not when GB/T 45570's angle method is
    imported."""
    out = tmp_path / "m.json"
    code = ("import json, sys\nfrom metro.core.run.plugin_manager import get_plugin_manager\n"
            "get_plugin_manager(autoload=False).register_all()\n"
            f"json.dump(sorted(sys.modules), open({str(out)!r}, 'w'))")
    subprocess.run([sys.executable, "-c", code], check=True)
    loaded = json.loads(out.read_text())
    assert "metro.plugins.gbt45570.angle_method" in loaded and "scipy.linalg" not in loaded


def test_version_registers_no_items(tmp_path):
    out = tmp_path / "m.json"
    subprocess.run([sys.executable, "-c",
                    "import json, sys\nfrom metro.core.cli.app import main\nmain(['--version'])\n"
                    f"json.dump(sorted(sys.modules), open({str(out)!r}, 'w'))"], check=True,
                   stdout=subprocess.DEVNULL)
    assert not any(m.startswith("metro.plugins.gbt45570.angle_method") for m
                   in json.loads(out.read_text()))

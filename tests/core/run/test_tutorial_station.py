"""docs/tutorial-station.md runs: its plugin (the python blocks marked ``# file:
quiet_metro/plugin.py``) is a working plugin with its own simulated station, its tests (the
block marked ``# file: tests/test_quiet.py``) pass with metro's pytest plugin, its ``metro``
commands run on that station, and its pyproject declares the entry point."""

from __future__ import annotations

import ast
import json
import os
import re
import shlex
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[3]
DOC = ROOT / "docs" / "tutorial-station.md"
PLUGIN = "quiet_metro/plugin.py"
TESTS = "tests/test_quiet.py"


def _blocks(lang: str) -> list[str]:
    return re.findall(rf"```{lang}\n(.*?)```", DOC.read_text(encoding="utf-8"), re.DOTALL)


def _files() -> dict[str, str]:
    """The python blocks by the file their first line names, concatenated in order."""
    files: dict[str, list[str]] = {}
    for block in _blocks("python"):
        first, _, body = block.partition("\n")
        m = re.fullmatch(r"# file: (\S+)", first.strip())
        assert m, f"a python block of the tutorial names no file: {first!r}"
        files.setdefault(m.group(1), []).append(body)
    return {name: "\n\n".join(parts) for name, parts in files.items()}


@pytest.fixture(scope="module")
def tutorial(tmp_path_factory) -> Path:
    """The tutorial's package and tests written out as a plugin author would have them."""
    root = tmp_path_factory.mktemp("quiet")
    files = _files()
    assert set(files) == {PLUGIN, TESTS}
    for name, text in files.items():
        path = root / name
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(text, encoding="utf-8")
    (root / "quiet_metro" / "__init__.py").write_text("", encoding="utf-8")
    return root


def _env(root: Path) -> dict[str, str]:
    env = dict(os.environ, PYTHONPATH=str(root), PATH=f"{Path(sys.executable).parent}{os.pathsep}"
               + os.environ.get("PATH", ""))
    env.pop("METRO_PLUGINS", None)
    env.pop("METRO_DISABLE_PLUGIN_AUTOLOAD", None)
    return env


def test_every_block_names_a_file_and_the_plugin_imports_only_metro_api(tutorial):
    tree = ast.parse((tutorial / PLUGIN).read_text(encoding="utf-8"))
    metro = {n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)
             and (n.module or "").startswith("metro")}
    metro |= {a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names
              if a.name.startswith("metro")}
    assert metro == {"metro.api"}


def test_the_pyproject_declares_the_plugin_entry_point():
    (toml,) = _blocks("toml")
    project = tomllib.loads(toml)["project"]
    assert project["entry-points"]["metro"] == {"quiet": "quiet_metro.plugin"}


def test_the_tutorial_tests_pass_with_metros_pytest_plugin(tutorial):
    out = subprocess.run(
        [sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider", "--rootdir", str(tutorial),
         str(tutorial / TESTS)], capture_output=True, text=True, env=_env(tutorial), cwd=tutorial,
        check=False,
        timeout=300)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]
    assert "3 passed" in out.stdout


def _commands() -> list[str]:
    (sh,) = _blocks("sh")
    return [line for line in sh.splitlines() if line.strip()]


def _run(tutorial: Path, line: str) -> subprocess.CompletedProcess:
    env = _env(tutorial)
    words = shlex.split(line)
    while "=" in words[0]:  # VAR=value before the command
        k, _, v = words.pop(0).partition("=")
        env[k] = v
    assert words[0] == "metro"
    return subprocess.run([sys.executable, "-m", "metro", *words[1:], "--no-progress"]
                          if words[1] == "run" else [sys.executable, "-m", "metro", *words[1:]],
                          capture_output=True, text=True, env=env, cwd=tutorial, timeout=300,
                          check=False)


def test_metro_run_uses_the_plugins_station_and_names_it(tutorial):
    """The tutorial's commands: ``metro plugins`` lists the station; ``metro run`` acquires on
    it, the banner names it (not the built-in simulated station), and the declared truth is
    recovered within U."""
    plugins, verbose, as_json, _acquire, _run_data = _commands()
    out = _run(tutorial, plugins)
    assert out.returncode == 0, out.stderr
    assert "quiet-gyro" in out.stdout
    out = _run(tutorial, verbose)
    assert out.returncode == 0, out.stderr
    banner = " ".join(out.stderr.split())
    assert "running on station 'quiet-gyro' of plugin" in banner, out.stderr
    assert "built-in simulated test station" not in banner
    text = " ".join(out.stdout.split())
    assert "declared truth recovered within U by 1 of 1 reportable results" in text, out.stdout
    out = _run(tutorial, as_json)
    assert out.returncode == 0, out.stderr
    doc = json.loads(out.stdout)
    (check,) = doc["truth_checks"]
    assert check["key"] == "B" and check["truth"] == pytest.approx(2.5) and check["within_U"]
    assert abs(doc["results"][0]["value"] - 2.5) < 0.02  # 600 samples of σ = 0.05 °/h


def test_metro_acquire_writes_a_campaign_that_metro_run_evaluates(tutorial):
    """The station's campaign written as a manifest (``metro acquire``) and read back."""
    acquire, run_data = _commands()[3:]
    out = _run(tutorial, acquire)
    assert out.returncode == 0, out.stderr
    manifest = tomllib.loads((tutorial / "campaign" / "manifest.toml").read_text(encoding="utf-8"))
    assert manifest["campaign"]["station"] == "quiet-gyro" and manifest["campaign"]["simulated"]
    assert [s["id"] for s in manifest["segments"]] == ["rest"]
    out = _run(tutorial, run_data)
    assert out.returncode == 0, out.stderr
    assert "bias" in out.stdout and "SIMULATED data" in " ".join(out.stdout.split())


def test_metro_run_writes_the_report_of_the_plugins_station(tutorial, tmp_path):
    """End to end, with the report: a Word document of the simulated campaign."""
    line = _commands()[1].replace("--no-report --verbose", f"--out {tmp_path}")
    out = _run(tutorial, line)
    assert out.returncode == 0, out.stderr
    assert list(tmp_path.glob("*.docx")), out.stdout

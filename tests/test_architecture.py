"""The architecture as contracts: layers and imports (.importlinter, run with lint-imports), no
private name crossing a module, the size limits, ruff clean at the configured line length, and
docs/architecture.md drawing the same layers as the contracts file."""

from __future__ import annotations

import ast
import configparser
import re
import subprocess
import sys
import tomllib
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
PACKAGES = {"core": "metro.core", "instruments": "metro.instruments", "plugins": "metro.plugins"}
MAX_FUNCTION_LINES = 100
MAX_MODULE_LINES = 800


def _modules() -> dict[str, Path]:
    """Every module of the three packages (and metro.api), by dotted name."""
    out = {}
    for folder, package in PACKAGES.items():
        for path in sorted((ROOT / folder).rglob("*.py")):
            rel = path.relative_to(ROOT / folder).with_suffix("")
            if "_metro" in rel.parts or "migrations" in rel.parts:
                continue
            parts = [package, *rel.parts]
            if parts[-1] == "__init__":
                parts.pop()
            out[".".join(parts)] = path
    out["metro.api"] = ROOT / "core" / "_metro" / "api.py"
    return out


MODULES = _modules()


def _absolute(importer: str, path: Path, node: ast.ImportFrom) -> str:
    """The module an ``ImportFrom`` names, made absolute."""
    if not node.level:
        return node.module or ""
    package = importer if path.name == "__init__.py" else importer.rsplit(".", 1)[0]
    base = package.split(".")[: len(package.split(".")) - (node.level - 1)]
    return ".".join(base + ([node.module] if node.module else []))


def test_the_import_contracts_hold():
    """lint-imports on .importlinter: layers, core alone, plugins through metro.api, no cycles."""
    lint = pytest.importorskip("importlinter.cli", reason="import-linter is in the [test] extra")
    assert lint.lint_imports(config_filename=str(ROOT / ".importlinter")) == 0


def test_ruff_is_clean_over_the_whole_tree():
    """``ruff check`` with the project's rules (pyproject.toml) finds nothing anywhere: packages,
    tests, benchmarks, tools and examples."""
    pytest.importorskip("ruff", reason="ruff is in the [test] extra")
    run = subprocess.run([sys.executable, "-m", "ruff", "check", "--no-cache",
                          "--output-format", "concise", str(ROOT)],
                         capture_output=True, text=True, cwd=ROOT)
    assert run.returncode == 0, run.stdout[-3000:] + run.stderr[-1000:]


def test_ruff_checks_line_length_100_and_the_error_rules():
    """The rules cannot be weakened silently: 100 columns, pycodestyle errors (E501 among them),
    pyflakes and bugbear are selected, and no rule of E or F is ignored."""
    ruff = tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["tool"]["ruff"]
    assert ruff["line-length"] == 100
    assert {"E", "W", "F", "B"} <= set(ruff["lint"]["select"])
    assert not [r for r in ruff["lint"].get("ignore", []) if r[0] in "EF"]


def test_the_contracts_ignore_nothing():
    text = (ROOT / ".importlinter").read_text(encoding="utf-8")
    assert "ignore_imports" not in text


def test_architecture_md_draws_the_contract_layers():
    cfg = configparser.ConfigParser()
    cfg.read(ROOT / ".importlinter", encoding="utf-8")
    layers = [x.strip() for x in cfg["importlinter:contract:core-layers"]["layers"].split("\n")
              if x.strip()]
    doc = (ROOT / "docs" / "architecture.md").read_text(encoding="utf-8")
    block = re.search(r"<!-- layers -->\s*```text\n(.*?)```", doc, re.S)
    assert block, "docs/architecture.md lost its layers block"
    assert [x.strip() for x in block.group(1).splitlines() if x.strip()] == layers
    for layer in layers:
        for name in layer.split("|"):
            assert (ROOT / "core" / name.strip() / "__init__.py").is_file(), name


def _is_private(name: str) -> bool:
    """``_x`` is private; a dunder (``__version__``) is not."""
    return name.startswith("_") and not (name.startswith("__") and name.endswith("__"))


def _private_imports() -> list[str]:
    found = []
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if not isinstance(node, ast.ImportFrom):
                continue
            target = _absolute(name, path, node)
            if not target.startswith("metro"):
                continue
            for alias in node.names:
                sub = f"{target}.{alias.name}"
                if _is_private(alias.name) and sub not in MODULES and target != name:
                    found.append(f"{name}: from {target} import {alias.name}")
    return found


def test_no_module_imports_another_modules_private_name():
    assert _private_imports() == []


def _long_functions() -> list[str]:
    found = []
    for name, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        for node in ast.walk(tree):
            if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
                n = node.end_lineno - node.lineno + 1
                if n > MAX_FUNCTION_LINES:
                    found.append(f"{name}.{node.name}: {n} lines")
    return found


def test_no_function_is_over_100_lines():
    assert _long_functions() == []


def test_no_module_is_over_800_lines():
    long = {n: len(p.read_text(encoding="utf-8").splitlines()) for n, p in MODULES.items()}
    assert {n: k for n, k in long.items() if k > MAX_MODULE_LINES} == {}


#: the project-wide checks that stand at tests/ itself (the rest mirror the tree)
PROJECT_TESTS = {"test_architecture.py", "test_contributing.py", "test_docs.py", "test_examples.py",
                 "test_independent_campaigns.py", "test_install.py", "test_packaging.py"}


def test_tests_mirror_the_tree():
    """A test of ``core/<layer>/`` is under ``tests/core/<layer>/``, one of ``plugins/<std>/`` under
    ``tests/plugins/<std>/``, one of ``instruments/`` under ``tests/instruments/``; a test file is
    named for the behaviour it checks, never for how it came about (``*_findings``, ``*_fixes``)."""
    tests = ROOT / "tests"
    allowed = {("core", p.name) for p in (ROOT / "core").iterdir() if (p / "__init__.py").is_file()}
    allowed |= {("plugins", p.name) for p in (ROOT / "plugins").iterdir()
                if (p / "__init__.py").is_file()}
    misplaced, named = [], []
    for f in sorted(tests.rglob("test_*.py")):
        rel = f.relative_to(tests).parts
        if rel[0] == "data":
            continue
        if len(rel) == 1:
            ok = f.name in PROJECT_TESTS
        elif rel[0] == "instruments":
            ok = len(rel) == 2
        else:
            ok = len(rel) == 3 and (rel[0], rel[1]) in allowed
        if not ok:
            misplaced.append("/".join(rel))
        if re.search(r"findings|fixes", f.stem):
            named.append("/".join(rel))
    assert misplaced == [] and named == []

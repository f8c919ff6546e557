"""Shared fixtures: a plugin manager without autoload, and a small simulated campaign."""

from __future__ import annotations

import contextlib
import os

import pytest
from hypothesis import settings

# Property tests check invariants, not speed: on a loaded 2-core CI machine hypothesis's default
# 200 ms deadline per example fails tests that are right (seen: test_budget_invariants).
settings.register_profile("metro", deadline=None)
settings.load_profile("metro")

# Tests draw every figure (metro.core.documents.figure_cache off): a figure kept in the user's cache
# by an earlier run would hide a drawing under test; tests/core/documents/test_figure_cache.py turns
# it on in a tmp folder.
os.environ["METRO_FIGURE_CACHE"] = "off"


@pytest.fixture
def pm():
    """metro's plugin manager with only the built-in plugins (no third-party autoload)."""
    from metro.core.run.plugin_manager import get_plugin_manager

    return get_plugin_manager(autoload=False)


def _load_local(name: str):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parent / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"metro_tests_{name}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


@contextlib.contextmanager
def _benchmark(name: str):
    """A harness module of benchmarks/ (scripts, not a package), with benchmarks/ on sys.path while
    it is in use (the harness modules import their shared pieces as siblings) and registered in
    sys.modules (their dataclasses look their module up)."""
    import importlib.util
    import sys
    from pathlib import Path

    d = Path(__file__).resolve().parents[1] / "benchmarks"
    sys.path.insert(0, str(d))
    try:
        spec = importlib.util.spec_from_file_location(name, d / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = mod
        spec.loader.exec_module(mod)
        yield mod
    finally:
        sys.path.remove(str(d))


@pytest.fixture(scope="session")
def benchmark_imports():
    """``text, imports = benchmark_imports("independent_gbt_env")``: a harness module's source and
    its ``import`` / ``from`` lines (stripped), for the tests that keep its generators independent
    of metro."""
    from pathlib import Path

    def read(name: str) -> tuple[str, list[str]]:
        text = (Path(__file__).resolve().parents[1] / "benchmarks"
                / f"{name}.py").read_text(encoding="utf-8")
        return text, [ln.strip() for ln in text.splitlines()
                      if ln.lstrip().startswith(("import ", "from "))]

    return read


@pytest.fixture(scope="session")
def load_benchmark():
    """``with load_benchmark("independent_gbt_env") as mod: …`` (:func:`_benchmark`)."""
    return _benchmark


@pytest.fixture(scope="module")
def gbt_more_harness():
    """benchmarks/independent_gbt_more.py, the GB/T harness whose device builders several tests
    use."""
    with _benchmark("independent_gbt_more") as mod:
        yield mod


@pytest.fixture(scope="session")
def campaign_factory():
    """The module tests/campaign_factory.py (writes small valid campaigns)."""
    return _load_local("campaign_factory")


@pytest.fixture
def run_cli(capsys):
    """Run ``metro`` in-process; return (exit code, stdout, stderr)."""
    from metro.core.cli.app import main

    def run(*args: str):
        code = main(list(args))
        out = capsys.readouterr()
        return code, out.out, out.err

    return run


@pytest.fixture
def lab(tmp_path, monkeypatch, capsys):
    """A lab profile (``metro lab init``) in force through ``METRO_LAB``, its register not yet
    made (a test module may define its own ``lab``)."""
    from metro.core.cli.app import main

    path = tmp_path / "lab.toml"
    assert main(["lab", "init", str(path)]) == 0
    capsys.readouterr()
    monkeypatch.setenv("METRO_LAB", str(path))
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    return path


@pytest.fixture(scope="session")
def pg_server():
    """A PostgreSQL server started for this test session (tests/pg.py), stopped at its end."""
    pg = _load_local("pg")
    if pg.SKIP_REASON:
        pytest.skip(pg.SKIP_REASON)
    server = pg.Server().start()
    yield server
    server.stop()


@pytest.fixture(params=["sqlite", "postgresql"])
def register_url(request, tmp_path):
    """An empty register database: an SQLite file, then a fresh PostgreSQL database."""
    if request.param == "sqlite":
        return "sqlite:///" + str(tmp_path / "register.sqlite")
    return request.getfixturevalue("pg_server").new_database()

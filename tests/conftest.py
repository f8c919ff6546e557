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


def _within_u(rows: list[dict]) -> None:
    for r in rows:
        if r["status"] == "not reportable":
            assert r["reason"], r
            continue
        assert r["status"] == "ok", r  # a missing result or a wrong unit fails here
        assert abs(r["En"]) <= 1, r


@pytest.fixture(scope="session")
def within_u():
    """``within_u(rows)``: every row an independent harness scored is within U of its truth
    (|E_n| ≤ 1), or not reportable with a reason."""
    return _within_u


@pytest.fixture(scope="session")
def harness_device():
    """``folder, truth = harness_device(harness, build, seed, items, tmp_path)``: the device
    ``build(harness, folder, rng)`` writes into ``tmp_path/dev-<seed>``, drawn from the seed
    ``[seed, crc32(items)]`` (the sweeps' draw)."""
    import zlib

    import numpy as np

    def make(harness, build, seed: int, items: str, tmp_path):
        folder = tmp_path / f"dev-{seed}"
        folder.mkdir()
        rng = np.random.default_rng([seed, zlib.crc32(items.encode())])
        return folder, build(harness, folder, rng)

    return make


@pytest.fixture(scope="session")
def evaluated_within_u():
    """``evaluated_within_u(run_metro, score, folder, standard, items, truth)``: the campaign in
    ``folder`` through the harness's ``run_metro`` evaluates with no manifest warning, ``score``
    gives a row for every key of ``truth``, and each row is within U (:func:`within_u`)."""
    def check(run_metro, score, folder, standard: str, items: str, truth: dict) -> None:
        code, doc, err = run_metro(folder / "manifest.toml", standard, items)
        assert code in (0, 3, 4), err
        assert not doc.get("manifest_warnings"), doc.get("manifest_warnings")
        rows = score(truth, doc)
        assert {(r["item"], r["key"]) for r in rows} == set(truth)
        _within_u(rows)

    return check


@pytest.fixture(scope="session")
def draft_rows():
    """``fields, result = draft_rows(standard=…, items=…, serial=…, day=…, value=…)``: the
    fields of a register draft (measured 2026-01-``day``) and its one result row (A.1 bias
    ``value`` °/h, U = 0.2 with k = 2), for tests that fill a register through its API."""
    import datetime as dt

    def rows(*, standard: str = "std", items: tuple[str, ...] = ("A.1",), serial: str = "S1",
             day: int = 1, value: float = 1.0) -> tuple[dict, dict]:
        fields = {"standard": standard, "items": list(items), "options": {}, "device_id": "d",
                  "device_manufacturer": "m", "device_model": "M", "device_serial": serial,
                  "customer": "", "measurement_date": dt.date(2026, 1, day), "simulated": False,
                  "allow_expired": False, "lab": {}, "verdicts": None, "budgets": [],
                  "provenance": {}, "manifest_sha256": None, "equipment": [], "template": "",
                  "context": {}}
        result = {"item": "A.1", "key": "bias", "quantity": "bias", "symbol": "B", "value": value,
                  "u": 0.1, "U": 0.2, "k": 2.0, "nu_eff": None, "unit": "°/h",
                  "value_text": "1.0", "U_text": "0.2", "reportable": True, "reason": ""}
        return fields, result

    return rows


@pytest.fixture(scope="session")
def load_tool():
    """``load_tool("gen_api_docs")``: the script tools/<name>.py, loaded as a module."""
    import importlib.util
    from pathlib import Path

    def load(name: str):
        path = Path(__file__).resolve().parents[1] / "tools" / f"{name}.py"
        spec = importlib.util.spec_from_file_location(name, path)
        mod = importlib.util.module_from_spec(spec)
        spec.loader.exec_module(mod)
        return mod

    return load

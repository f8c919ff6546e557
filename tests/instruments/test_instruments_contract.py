"""The contracts of metro.instruments: it never imports a plugin, core never imports it, its modules
form no cycle and share no private name; a station gets a standard's expected values through the
``metro_expected_values`` hook, and the campaign writer gets its file formats from the registry.

Imports are read with ``ast`` from every module, those inside functions included.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

from metro.api import Q_, hookimpl
from metro.core.base.errors import DataError, PluginError
from metro.core.model.campaign import Campaign, DeviceUnderTest
from metro.core.run.plugin_manager import MetroPluginManager

ROOT = Path(__file__).resolve().parents[2]
PACKAGES = {"core": "metro.core", "instruments": "metro.instruments", "plugins": "metro.plugins"}


def _module_name(path: Path) -> tuple[str, bool]:
    """(dotted name, is a package) of a source file of one of the three folders."""
    rel = path.relative_to(ROOT)
    if rel.parts[:2] == ("core", "_metro"):  # core/_metro is mapped onto the metro namespace itself
        parts = ["metro", *rel.parts[2:]]
    else:
        parts = [*PACKAGES[rel.parts[0]].split("."), *rel.parts[1:]]
    parts[-1] = parts[-1][:-3]
    package = parts[-1] == "__init__"
    if package:
        parts.pop()
    return ".".join(parts), package


def _imports(
    path: Path, name: str | None = None, package: bool = False
) -> list[tuple[str, list[str], int]]:
    """Every import of ``path`` (module ``name``, default: from its place in the tree) as (absolute
    module, names imported from it, line), function-level imports included; relative imports
    resolved."""
    if name is None:
        name, package = _module_name(path)
    here = name.split(".") if package else name.split(".")[:-1]
    out = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out += [(a.name, [], node.lineno) for a in node.names]
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = here[: len(here) - node.level + 1]
                mod = ".".join(base + ([node.module] if node.module else []))
            else:
                mod = node.module or ""
            out.append((mod, [a.name for a in node.names], node.lineno))
    return out


def _sources(folder: str) -> list[Path]:
    return sorted(p for p in (ROOT / folder).rglob("*.py") if "__pycache__" not in p.parts)


def _within(mod: str, package: str) -> bool:
    return mod == package or mod.startswith(package + ".")


def _offending(folder: str, forbidden: tuple[str, ...]) -> list[str]:
    bad = []
    for path in _sources(folder):
        for mod, names, line in _imports(path):
            targets = [mod] + [f"{mod}.{n}" for n in names]
            if any(_within(t, f) for t in targets for f in forbidden):
                bad.append(f"{path.relative_to(ROOT)}:{line} imports {mod} {names or ''}".strip())
    return bad


def test_instruments_never_import_plugins():
    assert _offending("instruments", ("metro.plugins",)) == []


def test_core_never_imports_instruments():
    # the pytest plugin (core/run/testing.py) reaches stations through the registry, like the CLI
    assert _offending("core", ("metro.instruments",)) == []


def test_instruments_import_no_private_name_of_another_module():
    bad = []
    for path in _sources("instruments"):
        for mod, names, line in _imports(path):
            if _within(mod, "metro.instruments"):
                private = [n for n in names if n.startswith("_") and not n.startswith("__")]
                if private:
                    bad.append(
                        f"{path.relative_to(ROOT)}:{line} imports {', '.join(private)} from {mod}"
                    )
    assert bad == []


def test_instruments_modules_form_no_cycle():
    modules = {_module_name(p)[0]: p for p in _sources("instruments")}
    graph: dict[str, set[str]] = {m: set() for m in modules}
    for m, path in modules.items():
        for mod, names, _line in _imports(path):
            for target in [f"{mod}.{n}" for n in names] + [mod]:
                if target in modules and target != m:
                    graph[m].add(target)
                    break
    state: dict[str, int] = {}
    cycles: list[list[str]] = []

    def visit(m: str, stack: list[str]) -> None:
        state[m] = 1
        for n in sorted(graph[m]):
            if state.get(n) == 1:
                cycles.append(stack[stack.index(n) :] + [n] if n in stack else [m, n])
            elif n not in state:
                visit(n, stack + [n])
        state[m] = 2

    for m in sorted(graph):
        if m not in state:
            visit(m, [m])
    assert cycles == []


def test_the_scan_sees_function_level_and_relative_imports(tmp_path):
    """What the scans above read: an import hidden in a function, written relatively, resolved."""
    probe = tmp_path / "probe.py"
    probe.write_text(
        "def f():\n    from ..plugins.gbt45570 import env_formulas\n    from ._x import _y\n"
    )
    assert _imports(probe, "metro.instruments.probe") == [
        ("metro.plugins.gbt45570", ["env_formulas"], 2),
        ("metro.instruments._x", ["_y"], 3),
    ]


# ------------------------------------------------------------------ the expected-values hook


class _Probe:
    """A plugin answering the key ``probe:value`` with ``x = 2·value`` seconds."""

    @hookimpl
    def metro_expected_values(self, campaign, ideal):
        if "probe:value" not in ideal:
            return None
        return {"x": Q_(2.0 * ideal["probe:value"], "s"), "device": Q_(len(campaign.device.id), "")}


class _Broken:
    @hookimpl
    def metro_expected_values(self, campaign, ideal):
        return [("x", 1.0)]


def _campaign() -> Campaign:
    return Campaign(
        id="c",
        device=DeviceUnderTest(id="DUT-12"),
        equipment=[],
        environment={},
        site={},
        segments=[],
    )


def test_expected_values_come_from_the_plugin_that_knows_the_key():
    from metro.instruments.stations import standard_expected

    pm = MetroPluginManager()
    pm.add_plugin(_Probe(), "probe")
    pm.register_all()
    got = standard_expected(_campaign(), {"probe:value": 1.5}, pm)
    assert got == {"x": Q_(3.0, "s"), "device": Q_(6, "")}
    assert standard_expected(_campaign(), {"other:value": 1.5}, pm) == {}


def test_expected_values_that_are_not_a_mapping_name_the_plugin():
    pm = MetroPluginManager()
    pm.add_plugin(_Broken(), "broken")
    pm.register_all()
    with pytest.raises(PluginError, match="plugin 'broken'"):
        pm.expected_values(_campaign(), {"probe:value": 1.0})


def test_a_simulated_threshold_needs_the_standards_plugin():
    """The virtual gyro's threshold (GB/T 45570 D.39) is the plugin's: with gbt45570 blocked the
    station still acquires, with no expected threshold; with it, about 2 × the dead band."""
    from metro.instruments.simulated import GyroTruth
    from metro.instruments.stations import standard_expected
    from metro.instruments.sim_gbt_env import tilt_responses

    truth = GyroTruth(dead_band_deg_h=0.002)
    pairs = tilt_responses(truth, [89.99, 89.98, 89.97, 89.95, 89.9, 89.8, 89.5, 90.0])
    blocked = MetroPluginManager().load(autoload=False, block=["gbt45570"])
    blocked.register_all()
    assert standard_expected(_campaign(), {"gbt45570:tilt_response": pairs}, blocked) == {}
    th = standard_expected(_campaign(), {"gbt45570:tilt_response": pairs})["threshold"]
    # inputs 15.041·cos Ψ: 0.0026, 0.0053, 0.0079 … °/h; the response reaches 50 % from
    # 2d = 0.004 on
    assert th.to("deg/h").magnitude == pytest.approx(15.041 * 0.000349065, rel=1e-3)


# ------------------------------------------------------------------ writers from the registry


class _ReadOnly:
    @hookimpl
    def metro_register_readers(self, registrar):
        registrar.add_reader((".csv",), lambda path, **kw: None, "read-only text")


def test_a_campaign_is_not_written_without_a_registered_writer(tmp_path):
    from metro.core.run.manifest_writer import write_campaign

    pm = MetroPluginManager()
    pm.add_plugin(_ReadOnly(), "read-only")
    pm.register_all()
    with pytest.raises(DataError, match=r"no writer is registered for files ending in '\.csv'"):
        write_campaign(_campaign(), tmp_path / "c", pm=pm)
    assert list(tmp_path.iterdir()) == []


def test_the_builtin_formats_write_csv_and_npy(metro_pm):
    from metro.instruments import readers

    assert metro_pm.writer_for(".csv") is readers.write_samples_csv
    assert metro_pm.writer_for(".NPY") is readers.write_samples_npy
    with pytest.raises(DataError, match="writers exist for .csv, .npy"):
        metro_pm.writer_for(".parquet")

"""The plugin system: entry-point loading, registrars, duplicates, blocking, every hook."""

from __future__ import annotations

import pytest

from metro.core.model import hookspec
from metro.core.base.errors import PluginError
from metro.core.run.plugin_manager import MetroPluginManager, get_plugin_manager


def _pm_with(*modules):
    pm = MetroPluginManager().load(autoload=False)
    for name in modules:
        pm.add_plugin(_load_sample(name), name)
    return pm


def _load_sample(name):
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[2] / "data" / "plugins" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"metro_test_plugins.{name}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def test_builtins_load_through_the_entry_point_group(pm):
    names = set(pm.plugins)
    assert {"core", "instruments", "gbt45570"} <= names
    for n in ("core", "instruments", "gbt45570"):
        assert pm.plugins[n].distribution == "metro-inertial" and pm.plugins[n].builtin
        assert pm.plugins[n].version
    assert {"gbt45570:D.5.1", "gbt45570:D.5.2", "gbt45570:D.5.6"} <= set(pm.registry.procedures)
    assert pm.registry.procedures["gbt45570:D.5.6"].plugin == "gbt45570"


def test_block_one_plugin_by_option_and_env(monkeypatch):
    pm = get_plugin_manager(autoload=False, block=["gbt45570"])
    assert "gbt45570" not in pm.plugins and "gbt45570" not in pm.registry.standards
    monkeypatch.setenv("METRO_BLOCK_PLUGINS", "gbt45570")
    pm = get_plugin_manager()
    assert "gbt45570" not in pm.plugins
    with pytest.raises(PluginError, match="unknown standard"):
        pm.procedure("gbt45570", "D.5.6")


def test_autoload_env_var_keeps_builtins(monkeypatch):
    monkeypatch.setenv("METRO_DISABLE_PLUGIN_AUTOLOAD", "1")
    pm = get_plugin_manager()
    assert all(p.builtin for p in pm.plugins.values())
    assert "gbt45570" in pm.plugins


def test_duplicate_item_names_both_plugins():
    pm = _pm_with("duplicate_item")
    with pytest.raises(PluginError) as exc:
        pm.register_all()
    msg = str(exc.value)
    assert "gbt45570:D.5.6" in msg and "'gbt45570'" in msg and "'duplicate_item'" in msg


def test_registrar_validates_input():
    from metro.core.run.plugin_manager import Registry, StandardRegistrar

    reg = StandardRegistrar(Registry(), "p")
    with pytest.raises(PluginError, match="not a metro Procedure"):
        reg.add_procedure(object)
    with pytest.raises(PluginError, match="lower-case"):
        reg.add_standard("GB T", "x")


def test_driver_registrar_validates_input():
    """metro_register_drivers: kind, interface, completeness and duplicates are checked."""
    from metro.core.run.plugin_manager import DriverRegistrar, Registry
    from metro.instruments.drivers.base import RateTableDriver

    reg = Registry()
    r = DriverRegistrar(reg, "p")
    with pytest.raises(PluginError, match="unknown kind 'oven'"):
        r.add_driver("x", "oven", RateTableDriver)
    with pytest.raises(PluginError, match="does not subclass"):
        r.add_driver("x", "rate-table", object)
    with pytest.raises(PluginError, match="does not subclass"):
        r.add_driver("x", "rate-table", lambda **kw: None)

    class Half(RateTableDriver):
        def identify(self):
            return None

    with pytest.raises(PluginError, match="does not implement .*set_rate"):
        r.add_driver("x", "rate-table", Half)
    with pytest.raises(PluginError, match="non-empty word"):
        r.add_driver("two words", "rate-table", Half)
    mod = _load_sample("sample_vendor")
    r.add_driver("acme", "rate-table", mod.AcmeRateTableDriver)
    with pytest.raises(PluginError, match="registered twice: by plugin 'p' and by plugin 'q'"):
        DriverRegistrar(reg, "q").add_driver("acme", "rate-table", mod.AcmeRateTableDriver)


def test_every_hook_of_a_third_party_plugin(tmp_path):
    """One sample plugin implements every hook; each one is exercised here."""
    from metro.core.base.errors import ProcedureError
    from metro.core.model.campaign import Campaign, DeviceUnderTest, Segment
    from metro.core.run.runner import run_items
    from metro.core.base.units import Q_
    import numpy as np

    mod = _load_sample("sample_vendor")
    pm = _pm_with()
    pm.add_plugin(mod, "sample_vendor")
    reg = pm.register_all()
    # metro_unit_definitions
    assert Q_(2, "vtick").to("arcsec").magnitude == pytest.approx(1.0)
    # metro_register_standards
    assert pm.procedure("vendorx", "V.1").__name__ == "MeanOutput"
    # metro_register_readers, metro_register_stations, metro_register_templates
    assert reg.readers[".vxb"].plugin == "sample_vendor"
    assert pm.station("vendorx-bench").plugin == "sample_vendor"
    assert pm.template_for("vendorx").name == "vendorx-report"
    assert pm.template_for("gbt45570").name == "gbt45570-report"
    assert pm.template_for("jjf2003-unknown").name == "generic-report"
    # metro_register_drivers: the vendor's rate table, next to the built-in drivers
    info = pm.driver("acme-rt300")
    assert (info.kind, info.plugin) == ("rate-table", "sample_vendor")
    assert [d.name for d in pm.drivers_of("rate-table")] == ["acme-rt300"]
    assert {"scpi-dmm", "serial-gyro"} <= set(reg.drivers)
    with info.cls(seed=3) as table:
        table.set_rate(Q_(10, "deg/s"))
        # within the 10 °/s band's error
        assert abs(table.rate().to("deg/s").magnitude / 10 - 1) <= 1e-5
        table.move_to(Q_(90, "deg"))
        assert table.angle().to("deg").magnitude == pytest.approx(90.0)
        eq = table.equipment()
        assert eq.role == "rate_table" and eq.calibration.certificate == "ACME-CAL-2031"
    with pytest.raises(PluginError, match="unknown driver 'nope'"):
        pm.driver("nope")
    # lifecycle hooks
    data = np.linspace(1.0, 2.0, 101)
    camp = Campaign("C1", DeviceUnderTest("D1"), [], {}, {}, [
        Segment("s", "static", {}, Q_(1, "s"), loader=lambda: {"output": (data, "deg/h")},
                sha256="0" * 64)])
    pm.campaign_loaded(camp)
    rec = run_items(pm, "vendorx", ["V.1"], campaign=camp)
    assert rec.outcomes[0].results[0].value.magnitude == pytest.approx(1.5)
    # metro_conformity_specifications: the vendor's limit judges the result (default rule: guarded)
    (verdict,) = rec.conformity.verdicts
    assert verdict.spec.source == "VX-001 limit table" and verdict.status.value == "pass"
    # metro_item_applicability and a series: the series runs the members that exist and apply
    rec = run_items(pm, "vendorx", ["all-means"], campaign=camp)
    assert [o.item for o in rec.outcomes] == ["V.1"]
    assert {c.item: c.run for c in rec.selection} == {"V.1": True, "V.2": False}
    assert "not available" in rec.selection[1].reason
    from metro.core.run.runner import select_items

    with pytest.raises(ProcedureError, match="V.1: V.1 needs a rate-output device"):
        select_items(pm, "vendorx", [], run_all=True, device=DeviceUnderTest("P", output="pulse"))
    from metro.core.documents.report import write_report

    path = write_report(tmp_path / "r.docx", rec, template=pm.template_for("vendorx").path,
                        extend=pm.extend_report_context)
    pm.report_written(path, rec.outcomes)
    kinds = [e[0] for e in mod.EVENTS]
    for hook in ("metro_campaign_loaded", "metro_procedure_started", "metro_procedure_finished",
                 "metro_extend_report_context", "metro_report_written", "metro_item_applicability",
                 "metro_conformity_specifications"):
        assert hook in kinds, hook
    assert kinds.index("metro_procedure_started") < kinds.index("metro_procedure_finished")
    # metro_expected_values: the plugin answers the keys it knows, merged with the built-ins'
    got = pm.expected_values(camp, {"vendorx:offset": 0.25, "nobody:else": 1})
    assert got["X"].to("deg/h").magnitude == pytest.approx(0.25) and "nobody:else" not in got
    assert pm.expected_values(camp, {"nobody:else": 1}) == {}
    # metro_validation_cases: the vendor's worked example, run as metro's own cases are
    (case,) = [c for cases in pm.pm.hook.metro_validation_cases() for c in cases
               if c.id.startswith("vendorx:")]
    assert case.run().verdict == "pass" and case.run().computed == (0.5, 3.5)


def test_hookspecs_are_documented_typed_stubs():
    import inspect

    names = [n for n in dir(hookspec) if n.startswith("metro_")]
    assert len(names) == 15
    for n in names:
        fn = getattr(hookspec, n)
        doc = inspect.getdoc(fn) or ""
        assert len(doc) > 80, n
        assert ":return:" in doc, n
        assert "return" in inspect.get_annotations(fn), n


def test_items_choose_their_default_station():
    """Procedure.station names the station used without data; mixing stations is an error."""
    from metro.core.run.runner import run_items

    mod = _load_sample("sample_vendor")
    pm = _pm_with()
    pm.add_plugin(mod, "sample_vendor")
    pm.register_all()
    assert pm.procedure("gbt45570", "D.5.6").station == "simulated"

    class Other(pm.procedure("gbt45570", "D.5.1")):
        station = "elsewhere"
        item = "X.1"

    pm.registry.procedures["gbt45570:X.1"] = (
        type(pm.registry.procedures["gbt45570:D.5.1"])(Other, "test")
    )
    # items on different stations: each station acquires its own campaign
    with pytest.raises(PluginError, match="unknown station 'elsewhere'"):
        run_items(pm, "gbt45570", ["D.5.1", "X.1"])
    with pytest.raises(PluginError, match="unknown station 'elsewhere'"):
        run_items(pm, "gbt45570", ["X.1"])


def test_items_are_listed_in_the_standards_order():
    from metro.core.run.plugin_manager import item_sort_key

    ids = ["7.2.10", "7.2.2", "D.2.1", "D.1.6", "7.2.1", "D.10", "6.2.7.8", "6.2.6"]
    assert sorted(ids, key=item_sort_key) == ["6.2.6", "6.2.7.8", "7.2.1", "7.2.2", "7.2.10",
                                              "D.1.6", "D.2.1",
                                              "D.10"]


class _OwnStation:
    """A plugin's station, made by the factory registered below (not a built-in one)."""

    def __init__(self, seed: int = 0) -> None:
        self.seed = seed


class _StationPlugin:
    __name__ = "own_station_plugin"

    @staticmethod
    @hookspec.hookimpl
    def metro_register_stations(registrar):
        registrar.add_station("own-sim", _OwnStation, "a plugin's own simulated station")


def test_metro_station_fixture_makes_a_plugins_own_station(metro_station):
    """metro_station reaches a station a plugin registers, given the plugin object, and still
    the built-in ones; an unknown name lists what is registered."""
    st = metro_station("own-sim", _StationPlugin(), seed=7)
    assert type(st) is _OwnStation and st.seed == 7
    assert metro_station("simulated-ogam", seed=4).truth.seed == 4
    with pytest.raises(PluginError, match="unknown station 'own-sim'.*simulated-ogam"):
        metro_station("own-sim")  # not registered without the plugin


_OWN_STATION_MODULE = '''
from metro.api import hookimpl


class OwnStation:
    def __init__(self, seed=0):
        self.seed = seed


@hookimpl
def metro_register_stations(registrar):
    registrar.add_station("own-sim", OwnStation, "a plugin's own simulated station")
'''


def test_metro_station_fixture_finds_an_installed_plugins_station(metro_station, monkeypatch,
                                                                   tmp_path):
    """A plugin metro loads by itself (an installed entry point; METRO_PLUGINS here) needs no
    argument: the fixture falls back to the plugins metro loads."""
    (tmp_path / "metro_test_own_station.py").write_text(_OWN_STATION_MODULE, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setenv("METRO_PLUGINS", "metro_test_own_station")
    monkeypatch.delenv("METRO_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    st = metro_station("own-sim", seed=2)
    assert type(st).__name__ == "OwnStation" and st.seed == 2


def test_the_pytest_plugin_reaches_stations_through_the_registry():
    """core/run/testing.py never imports metro.instruments (core does not import instruments):
    the simulated station comes from the plugin manager's registry."""
    import ast
    from pathlib import Path

    import metro.core.run.testing as testing

    tree = ast.parse(Path(testing.__file__).read_text(encoding="utf-8"))
    imported = [n.module for n in ast.walk(tree) if isinstance(n, ast.ImportFrom)]
    imported += [a.name for n in ast.walk(tree) if isinstance(n, ast.Import) for a in n.names]
    assert not [m for m in imported if m and m.startswith("metro.instruments")]

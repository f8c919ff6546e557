"""metro's pytest plugin (metro.core.run.testing) provides its fixtures to any test session."""

from __future__ import annotations

import pytest


def test_fixtures(metro_pm, metro_pm_factory, simulated_station, approx_quantity):
    from metro.core.base.units import Q_

    assert "gbt45570" in metro_pm.registry.standards
    pm = metro_pm_factory()
    assert set(pm.plugins) == set(metro_pm.plugins)
    st = simulated_station(seed=3)
    assert st.truth.seed == 3
    assert approx_quantity(Q_(1, "deg/h"), rel=1e-12) == Q_(3600, "arcsec/h")
    assert approx_quantity(Q_(1, "deg/h"), rel=1e-3) != Q_(1.01, "deg/h")
    with pytest.raises(Exception, match="not compatible"):
        assert approx_quantity(Q_(1, "deg/h")) == Q_(1, "Hz")


def test_metro_station_fixture(metro_station):
    st = metro_station("simulated-ogam", seed=4)
    assert st.truth.seed == 4
    assert metro_station("simulated", seed=5).truth.seed == 5
    with pytest.raises(Exception, match="unknown station"):
        metro_station("no-such-bench")


_THIRD_PARTY = '''
from metro.core import hookimpl


@hookimpl
def metro_register_standards(registrar):
    registrar.add_standard("tp", "an installed third-party plugin", designation="TP-1")
'''


def test_metro_pm_leaves_installed_third_party_plugins_out(request, monkeypatch, tmp_path):
    """metro_pm / metro_pm_factory do not autoload: an installed third-party entry point in the
    "metro" group (simulated here) is not loaded, while normal loading picks it up."""
    from importlib import metadata

    import metro.core.run.plugin_manager as mp

    (tmp_path / "tp_plugin.py").write_text(_THIRD_PARTY, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    real = metadata.entry_points
    fake = metadata.EntryPoint("tp", "tp_plugin", "metro")

    def entry_points(**kw):
        eps = list(real(**kw))
        return eps + [fake] if kw.get("group") == "metro" else eps

    monkeypatch.setattr(mp.metadata, "entry_points", entry_points)
    monkeypatch.delenv("METRO_PLUGINS", raising=False)
    monkeypatch.delenv("METRO_DISABLE_PLUGIN_AUTOLOAD", raising=False)
    assert "tp" in mp.get_plugin_manager().plugins  # autoload finds it
    pm = request.getfixturevalue("metro_pm")
    assert "tp" not in pm.plugins and "tp" not in pm.registry.standards
    assert pm.plugins and all(p.builtin for p in pm.plugins.values())
    made = request.getfixturevalue("metro_pm_factory")()
    assert set(made.plugins) == set(pm.plugins)


def test_approx_quantity_tolerances(approx_quantity):
    from metro.core.base.units import Q_

    # abs as a quantity in another unit: 1″ = 1/3600°
    assert approx_quantity(Q_(10.0, "deg"), abs=Q_(2, "arcsec")) == Q_(10.0 + 1 / 3600, "deg")
    assert approx_quantity(Q_(10.0, "deg"), abs=Q_(0.5, "arcsec")) != Q_(10.0 + 1 / 3600, "deg")
    # a plain number is not a quantity
    assert approx_quantity(Q_(1.0, "deg")) != 1.0

"""metro's pytest plugin (metro.core.testing) provides its fixtures to any test session."""

from __future__ import annotations

import pytest


def test_fixtures(metro_pm, metro_pm_factory, simulated_station, approx_quantity):
    from metro.core.units import Q_

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

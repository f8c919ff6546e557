"""core.earth constants against independently stated values."""

import math

import pytest

from metro.core.stats import earth
from metro.core.base.units import Q_


def test_earth_rate_in_degrees_per_hour():
    # IERS Ω = 7.2921150e-5 rad/s; 15.041 °/h is the rounded figure GB/T 45570 D.40 prints
    assert earth.EARTH_RATE_DEG_PER_H == pytest.approx(15.041067, abs=1e-6)
    assert Q_(earth.EARTH_RATE_RAD_S, "rad/s").to("deg/h").magnitude == pytest.approx(
        earth.EARTH_RATE_DEG_PER_H, rel=1e-15
    )


def test_components_add_up_and_match_the_poles():
    for lat in (-90.0, -30.0, 0.0, 39.98, 90.0):
        v, h = earth.vertical_earth_rate_deg_h(lat), earth.horizontal_earth_rate_deg_h(lat)
        assert math.hypot(v, h) == pytest.approx(earth.EARTH_RATE_DEG_PER_H, rel=1e-14)
    assert earth.vertical_earth_rate_deg_h(90.0) == pytest.approx(earth.EARTH_RATE_DEG_PER_H)
    assert earth.horizontal_earth_rate_deg_h(0.0) == pytest.approx(earth.EARTH_RATE_DEG_PER_H)


def test_standard_gravity_is_the_registry_g():
    # "g" means standard gravity only where an acceleration is expected; "gn" always does
    assert Q_(1, "gn").to("m/s**2").magnitude == earth.STANDARD_GRAVITY_M_S2

"""Units: one registry, the field's units, clear errors on mismatches."""

from __future__ import annotations

import pytest
from hypothesis import given
from hypothesis import strategies as st

from metro.core.errors import UnitError
from metro.core.units import Q_, angle_power, check_dimension, fmt_unit, parse_quantity, unit, ureg


@pytest.mark.parametrize(
    "text, pretty",
    [
        ("°/h", "°/h"), ("(°)/h", "°/h"), ("deg/s", "°/s"), ("°/√h", "°/√h"), ("″", "″"), ("′", "′"),
        ("P", "P"), ("LSB", "LSB"), ("mV", "mV"), ("mT", "mT"), ("ppm", "ppm"), ("1/degC", "1/°C"),
        ("P/″", "P/″"), ("(°/h)/mT", "°/h/mT"),
    ],
)
def test_field_units_parse_and_print(text, pretty):
    assert fmt_unit(unit(text)) == pretty


def test_one_arcsecond_per_second_is_one_degree_per_hour():
    # GB/T 45570 D.40 relies on this identity (reading notes).
    assert Q_(1, "″/s").to("°/h").magnitude == pytest.approx(1.0, rel=1e-15)


def test_g_is_standard_gravity_where_acceleration_is_expected():
    q = parse_quantity("0.5 (°/h)/g", dimension="deg/h/gn")
    assert q.to("deg/h/(m/s**2)").magnitude == pytest.approx(0.5 / 9.80665, rel=1e-12)
    assert fmt_unit(q.units) == "°/h/g"


def test_angle_kinds_are_not_confused():
    # pint makes angles dimensionless; metro still refuses Hz for °/h and ppm for ″
    assert angle_power(unit("deg/h")) == 1
    assert angle_power(unit("Hz")) == 0
    with pytest.raises(UnitError, match="Hz"):
        check_dimension(Q_(1, "Hz"), "deg/h", file="m.toml", field="rate")
    with pytest.raises(UnitError, match="ppm"):
        check_dimension(Q_(1, "ppm"), "arcsec")


def test_number_without_unit_is_refused_with_an_example():
    with pytest.raises(UnitError) as exc:
        parse_quantity(3.0, dimension="deg/h", file="manifest.toml", field="site.rate")
    assert "manifest.toml" in str(exc.value) and "site.rate" in str(exc.value) and "3.0 deg/h" in str(exc.value)


def test_unparseable_quantity():
    with pytest.raises(UnitError, match="cannot read"):
        parse_quantity("12 furlongs per fortnightish", file="f", field="x")


def test_single_registry():
    assert Q_(1, "s")._REGISTRY is ureg


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_rate_round_trip(x):
    q = Q_(x, "deg/s").to("deg/h").to("deg/s")
    assert q.magnitude == pytest.approx(x, rel=1e-12, abs=1e-300)

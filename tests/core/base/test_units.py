"""Units: one registry, the field's units, clear errors on mismatches."""

from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

import pytest
from hypothesis import given
from hypothesis import strategies as st

from metro.core.base.errors import UnitError
from metro.core.base.units import (Q_, angle_power, check_dimension, fmt_unit, parse_quantity, unit,
                                   ureg)


@pytest.mark.parametrize(
    "text, pretty",
    [
        ("°/h", "°/h"), ("(°)/h", "°/h"), ("deg/s", "°/s"), ("°/√h", "°/√h"), ("″", "″"),
        ("′", "′"),
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
    assert "manifest.toml" in str(exc.value) and "site.rate" in str(
        exc.value) and "3.0 deg/h" in str(exc.value)


def test_unparseable_quantity():
    with pytest.raises(UnitError, match="cannot read"):
        parse_quantity("12 furlongs per fortnightish", file="f", field="x")


def test_single_registry():
    assert Q_(1, "s")._REGISTRY is ureg


@given(st.floats(min_value=-1e6, max_value=1e6, allow_nan=False))
def test_rate_round_trip(x):
    q = Q_(x, "deg/s").to("deg/h").to("deg/s")
    assert q.magnitude == pytest.approx(x, rel=1e-12, abs=1e-300)


def _units_in_subprocess(env_extra: dict[str, str]) -> subprocess.CompletedProcess:
    code = ("import warnings; warnings.simplefilter('always')\n"
            "from metro.core.base.units import Q_, ureg\n"
            "print(Q_(1, 'deg/h').to('arcsec/s').magnitude, ureg.cache_folder)\n")
    env = dict(os.environ) | env_extra
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env,
                          timeout=120)


def test_the_definitions_cache_is_per_installation_and_never_fatal(tmp_path):
    """pint's shared ':auto:' cache remembers where another environment's definitions file was,
    and breaks every environment once that one is deleted (pint #1572). metro's cache folder is
    keyed by this pint's location and version; a folder that cannot be used costs time, not the
    run."""
    import hashlib

    import pint

    key = (
        hashlib.sha256(f"{Path(pint.__file__).resolve().parent}|{pint.__version__}".encode()).hexdigest()[:16]
    )
    good = _units_in_subprocess({"METRO_CACHE_DIR": str(tmp_path / "c")})
    assert good.returncode == 0, good.stderr
    value, folder = good.stdout.split()
    assert float(value) == 1.0
    assert Path(folder) == tmp_path / "c" / "pint" / key and any(Path(folder).iterdir())
    # the cache folder's place is taken by a file: the registry is built without a cache
    (tmp_path / "bad" / "pint").mkdir(parents=True)
    (tmp_path / "bad" / "pint" / key).write_text("not a folder")
    bad = _units_in_subprocess({"METRO_CACHE_DIR": str(tmp_path / "bad")})
    assert bad.returncode == 0, bad.stderr
    assert bad.stdout.split()[0] == "1.0" and "parsing without it" in bad.stderr


def test_convert_options_gives_each_field_its_type():
    import attrs

    from metro.core.base.errors import DataError
    from metro.core.base.options import convert_options

    @attrs.frozen
    class T:
        x: float = 0.5
        n: int = 3
        on: bool = False
        name: str = "a"
        v: tuple = (1.0, 2.0, 3.0)
        m: tuple = ((1.0, 0.0), (0.0, 1.0))

    got = convert_options("T", T, {"x": "0.25", "n": "7", "on": "yes", "name": 5, "v": "4, 5,6",
                                   "m": [[2, 0], [0, 2]],
                                   "other": "left out"})
    assert got == {"x": 0.25, "n": 7, "on": True, "name": "5", "v": (4.0, 5.0, 6.0),
                   "m": ([2, 0], [0, 2])}
    assert isinstance(got["x"], float) and isinstance(got["n"], int)
    for bad in ({"x": "nan"}, {"n": "2.5"}, {"on": "maybe"}, {"v": "1,2"}, {"m": "1,0,0,1"},
                {"x": True}):
        with pytest.raises(DataError):
            convert_options("T", T, bad)

"""D-SI unit strings both ways (issue 31): the table the issue names, every Metric unit of every
registered item round-trips, an unmapped unit or token is refused."""

from __future__ import annotations

import math

import pint
import pytest
from metro.core.base.dsi import dsi_unit, metro_unit
from metro.core.base.errors import UnitError
from metro.core.base.units import Q_, angle_power, difference_unit, unit
from metro.core.run.plugin_manager import get_plugin_manager

# Written by hand from D-SI 2.2.1's token list (SI brochure names, \tothe{n} powers), not from
# the module's table.
EXPECTED = {
    "°/h": r"\degree\hour\tothe{-1}",
    "°/√h": r"\degree\hour\tothe{-0.5}",
    "°/h/√h": r"\degree\hour\tothe{-1.5}",
    "″": r"\arcsecond",
    "ppm": r"\ppm",
    "P/″": r"|\pulse\arcsecond\tothe{-1}",
    "LSB/(°/s)": r"|\lsb\second\degree\tothe{-1}",
    "mV/(°/s)": r"\milli\volt\second\degree\tothe{-1}",
    "gn": r"|\standardgravity",
    "s": r"\second",
    "Hz": r"\hertz",
    "°C": r"\degreecelsius",
    "°/h/°C": r"\degree\hour\tothe{-1}\degreecelsius\tothe{-1}",
    "MΩ": r"\mega\ohm",
    "kg": r"\kilogram",
    "%": r"\percent",
    "": r"\one",
}


def _same_unit(got: pint.Unit, want: pint.Unit) -> bool:
    """Same dimension, same power of plane angle, and 1 ``got`` = 1 ``want`` within 1e-12."""
    if got.dimensionality != want.dimensionality or angle_power(got) != angle_power(want):
        return False
    one = Q_(1.0, difference_unit(got)).to(difference_unit(want)).magnitude
    return math.isclose(one, 1.0, rel_tol=1e-12)


def _metric_units() -> dict[str, str]:
    pm = get_plugin_manager()
    out: dict[str, str] = {}
    for pid, info in pm.registry.procedures.items():
        for m in info.cls.metrics:
            out.setdefault(m.unit, f"{pid} {m.key}")
    return out


@pytest.mark.parametrize(("text", "dsi"), sorted(EXPECTED.items()))
def test_named_units_map_to_dsi_and_back(text: str, dsi: str) -> None:
    assert dsi_unit(text) == dsi
    assert _same_unit(unit(metro_unit(dsi)), unit(text))


def test_g_n_spellings() -> None:
    assert dsi_unit("g_n") == dsi_unit("gₙ") == r"|\standardgravity"
    assert dsi_unit("°/h/g") == r"|\degree\hour\tothe{-1}\standardgravity\tothe{-1}"


def test_every_metric_unit_round_trips() -> None:
    units = _metric_units()
    assert len(units) > 30  # the four standards' plugins are loaded
    for text, who in units.items():
        dsi = dsi_unit(text, result=who)
        assert dsi.startswith(("\\", "|\\")), (who, dsi)
        assert _same_unit(unit(metro_unit(dsi)), unit(text)), (who, text, dsi)


def test_dsi_from_a_registry_unit() -> None:
    assert dsi_unit(unit("deg/h")) == r"\degree\hour\tothe{-1}"


def test_temperature_difference_alone_is_kelvin() -> None:
    assert dsi_unit("delta_degC") == r"\kelvin"
    assert metro_unit(r"\kelvin") == "K"


def test_unmapped_unit_is_refused_naming_unit_and_result() -> None:
    with pytest.raises(UnitError, match=r"fortnight.*no D-SI mapping|no D-SI mapping.*fortnight") \
            as err:
        dsi_unit("deg/fortnight", result="gbt45570:5.3.6 bias_stability")
    assert "gbt45570:5.3.6 bias_stability" in str(err.value)
    with pytest.raises(UnitError, match="no D-SI mapping"):
        dsi_unit("furlong")
    with pytest.raises(UnitError, match="no D-SI mapping"):
        dsi_unit("not a unit ((")


def test_external_spellings_read() -> None:
    assert metro_unit(r"\metre\per\second\tothe{2}") == "m/s²"
    assert metro_unit(r"\kilo\gram") == "kg"
    assert metro_unit(r"\micro\metre\metre\tothe{-1}") == unit_text_of("um/m")


def unit_text_of(text: str) -> str:
    from metro.core.base.units import fmt_unit

    return fmt_unit(unit(text))


@pytest.mark.parametrize("bad", [r"\foo", "metre", r"\milli", r"\tothe{2}", r"\metre\tothe{x}",
                                 "", "|", r"\metre\per\second\per\second", r"\milli\one"])
def test_bad_dsi_text_is_refused(bad: str) -> None:
    with pytest.raises(UnitError):
        metro_unit(bad)

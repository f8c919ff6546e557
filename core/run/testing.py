"""metro's pytest plugin: fixtures a plugin author needs.

Loaded automatically by pytest through the ``pytest11`` entry point of the ``metro``
distribution.  Fixtures:

* ``metro_pm`` — a registered plugin manager with metro's built-ins only (no third-party
  autoload), so a test sees exactly what it adds;
* ``metro_pm_factory`` — ``metro_pm_factory(*plugins)`` → such a manager with the given
  plugin objects (modules or instances) added under their ``__name__``;
* ``simulated_station`` — ``simulated_station(**options)`` → the built-in simulated station;
* ``metro_station`` — ``metro_station(name, *plugins, **options)`` → the station registered as
  ``name``, made by its factory with ``options``: a built-in one (e.g. ``"simulated-ogam"``, the
  angle instrument on a turntable), one of the plugin objects given (modules or instances, as
  to ``metro_pm_factory``), or one of an installed plugin (the ``metro`` entry points);
* ``approx_quantity`` — ``approx_quantity(expected, rel=…, abs=…)``: a unit-aware
  ``pytest.approx`` that converts the actual value to the expected one's unit and refuses a
  dimension mismatch.  Write it on the left: ``assert approx_quantity(Q_(1, "deg/h")) == q``
  (pint's ``Quantity.__eq__`` answers False rather than deferring).
"""

from __future__ import annotations

from collections.abc import Callable, Sequence
from typing import Any

import pytest


@pytest.fixture
def metro_pm():
    from metro.core.run.plugin_manager import get_plugin_manager

    return get_plugin_manager(autoload=False)


@pytest.fixture
def metro_pm_factory():
    from metro.core.run.plugin_manager import MetroPluginManager

    def make(*plugins: Any):
        pm = MetroPluginManager().load(autoload=False)
        for p in plugins:
            pm.add_plugin(p, getattr(p, "__name__", type(p).__name__))
        pm.register_all()
        return pm

    return make


@pytest.fixture
def simulated_station(metro_pm):
    """The factory of the built-in ``simulated`` station (reached through the registry: core
    never imports the instruments)."""
    return metro_pm.station("simulated").factory


def station_factory_of(name: str, plugins: Sequence[Any] = ()) -> Callable[..., Any]:
    """The factory of the station registered as ``name``: by metro's built-ins or one of
    ``plugins`` (objects added as ``metro_pm_factory`` adds them), else by an installed plugin
    (the ``metro`` entry-point group).  An unknown name is a :class:`PluginError` listing the
    stations every one of these registers."""
    from metro.core.base.errors import PluginError
    from metro.core.run.plugin_manager import MetroPluginManager, get_plugin_manager

    pm = MetroPluginManager().load(autoload=False)
    for p in plugins:
        pm.add_plugin(p, getattr(p, "__name__", type(p).__name__))
    known = pm.register_all().stations
    if name in known:
        return known[name].factory
    installed = get_plugin_manager().register_all().stations
    if name in installed:
        return installed[name].factory
    available = ", ".join(sorted(set(known) | set(installed)))
    raise PluginError(f"unknown station {name!r}; available: {available}",
                      hint="pass your plugin: metro_station(name, your_plugin, **options)")


@pytest.fixture
def metro_station():
    """``metro_station(name, *plugins, **options)`` → the station ``name`` (a built-in one, one
    of ``plugins``, or an installed plugin's), made by its factory with ``options``."""

    def make(name: str, *plugins: Any, **options: Any):
        return station_factory_of(name, plugins)(**options)

    return make


class _ApproxQuantity:
    def __init__(self, expected, rel=None, abs=None):
        self.expected = expected
        self.rel = rel
        self.abs = abs

    def __ne__(self, actual) -> bool:
        return not self.__eq__(actual)

    def __eq__(self, actual) -> bool:
        import pint
        from metro.core.base.units import check_dimension

        if not isinstance(actual, pint.Quantity):
            return False
        check_dimension(actual, str(self.expected.units))
        a = actual.to(self.expected.units).magnitude
        abs_ = None if self.abs is None else (
            self.abs.to(self.expected.units).magnitude if isinstance(self.abs, pint.Quantity)
            else self.abs)
        return a == pytest.approx(self.expected.magnitude, rel=self.rel, abs=abs_)

    def __repr__(self) -> str:
        return f"approx_quantity({self.expected!r}, rel={self.rel}, abs={self.abs})"


@pytest.fixture
def approx_quantity():
    return _ApproxQuantity

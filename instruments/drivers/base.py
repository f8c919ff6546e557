"""The driver interfaces, re-exported from :mod:`metro.core.model.drivers` (where the plugin
contract keeps them) for code that imported them from here."""

from __future__ import annotations

import importlib
from types import ModuleType

from metro.core.base.errors import DriverError
from metro.core.model.drivers import (DRIVER_KINDS, DmmDriver, Driver, GyroOutputDriver, Identity,
                                      RateTableDriver)

__all__ = ["Identity", "Driver", "DmmDriver", "GyroOutputDriver", "RateTableDriver", "DRIVER_KINDS",
           "DRIVERS_HINT", "import_for_driver"]

#: how to install what the live-instrument drivers import
DRIVERS_HINT = "pip install 'metro-inertial[drivers]'"


def import_for_driver(
    module: str, resource: str | None, *, package: str = "", hint: str = DRIVERS_HINT
) -> ModuleType:
    """The module ``module`` a driver of ``resource`` talks through, or a :class:`DriverError`
    saying that ``package`` (default: ``module``) is not installed and how to install it
    (``hint``).

    >>> import_for_driver("math", None).sqrt(4.0)
    2.0
    """
    try:
        return importlib.import_module(module)
    except ImportError as exc:
        what = package or module
        raise DriverError(resource, None, f"{what} is not installed", hint=hint) from exc

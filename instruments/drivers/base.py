"""The driver interfaces, re-exported from :mod:`metro.core.model.drivers` (where the plugin
contract keeps them) for code that imported them from here."""

from __future__ import annotations

from metro.core.model.drivers import (DRIVER_KINDS, DmmDriver, Driver, GyroOutputDriver, Identity,
                                      RateTableDriver)

__all__ = ["Identity", "Driver", "DmmDriver", "GyroOutputDriver", "RateTableDriver", "DRIVER_KINDS"]

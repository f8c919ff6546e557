"""Drivers for live instruments (optional extra ``drivers``: ``pip install
'metro-inertial[drivers]'``).

* :mod:`metro.core.model.drivers` — the interfaces a driver implements
  (:class:`~metro.core.model.drivers.DmmDriver`,
  :class:`~metro.core.model.drivers.GyroOutputDriver`,
  :class:`~metro.core.model.drivers.RateTableDriver`), part of the plugin contract
  (re-exported here and by :mod:`.base`);
* :mod:`.scpi_dmm` — a SCPI 6½-digit DMM over PyVISA;
* :mod:`.serial_gyro` — a gyro's binary frame stream over RS-422/RS-485 (pyserial), with a
  declared frame layout.

PyVISA and pyserial are imported only when a driver is opened, so ``import metro`` and the
CLI stay fast and work without them.
"""

from __future__ import annotations

from metro.core.model.drivers import (DRIVER_KINDS, DmmDriver, Driver, GyroOutputDriver, Identity,
                                      RateTableDriver)

__all__ = ["DRIVER_KINDS", "DmmDriver", "Driver", "GyroOutputDriver", "Identity", "RateTableDriver"]

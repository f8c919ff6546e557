"""Drivers for live instruments (optional extra ``drivers``: ``pip install 'metro-inertial[drivers]'``).

* :mod:`.base` — the interfaces (:class:`~.base.DmmDriver`, :class:`~.base.GyroOutputDriver`,
  :class:`~.base.RateTableDriver`) a driver implements;
* :mod:`.scpi_dmm` — a SCPI 6½-digit DMM over PyVISA;
* :mod:`.serial_gyro` — a gyro's binary frame stream over RS-422/RS-485 (pyserial), with a
  declared frame layout.

PyVISA and pyserial are imported only when a driver is opened, so ``import metro`` and the
CLI stay fast and work without them.
"""

from __future__ import annotations

from .base import DRIVER_KINDS, DmmDriver, Driver, GyroOutputDriver, Identity, RateTableDriver

__all__ = ["DRIVER_KINDS", "DmmDriver", "Driver", "GyroOutputDriver", "Identity", "RateTableDriver"]

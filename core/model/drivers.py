"""The driver contract: the interfaces live-instrument drivers implement, one abstract base class
per kind, and :data:`DRIVER_KINDS`, which the plugin manager's driver registrar checks against.

Part of the plugin contract (core), so the registrar needs nothing from ``metro.instruments``;
metro's own drivers (``metro.instruments.drivers``) implement these interfaces like any
plugin's.

A driver talks to one instrument and speaks pint quantities to metro: set points go in as
quantities, readings come back as quantities, and every failure is a
:class:`~metro.core.base.errors.DriverError` naming the resource, what was being done and why.
Drivers are registered by plugins with the ``metro_register_drivers`` hook
(``registrar.add_driver(name, kind, cls, description)``); the registrar checks that ``cls``
subclasses the interface of ``kind`` and implements all of it.

Kinds and their interfaces:

* ``"dmm"`` — :class:`DmmDriver` (a digital multimeter for a gyro's analog output);
* ``"gyro-output"`` — :class:`GyroOutputDriver` (a gyro's digital output stream);
* ``"rate-table"`` — :class:`RateTableDriver` (a rate/position table a vendor supplies).

Every driver is a context manager (``with Driver(...) as d:``) and closes its connection on exit.
"""

from __future__ import annotations

import abc
from typing import Any, Mapping

import attrs
import pint

from .campaign import Equipment

__all__ = ["Identity", "Driver", "DmmDriver", "GyroOutputDriver", "RateTableDriver", "DRIVER_KINDS"]


@attrs.frozen
class Identity:
    """Who an instrument says it is (e.g. from ``*IDN?``)."""

    manufacturer: str
    model: str
    serial: str = ""
    firmware: str = ""

    @classmethod
    def from_idn(cls, text: str) -> "Identity":
        """Parse a SCPI ``*IDN?`` reply: ``manufacturer,model,serial,firmware``."""
        parts = [p.strip() for p in text.strip().split(",")]
        if len(parts) < 2 or not parts[0] or not parts[1]:
            raise ValueError(f"not a *IDN? reply (manufacturer,model,serial,firmware): {text!r}")
        parts += [""] * (4 - len(parts))
        return cls(parts[0], parts[1], parts[2], ",".join(parts[3:]).strip(","))


class Driver(abc.ABC):
    """What every driver does: identify the instrument and close the connection."""

    #: the instrument's address (VISA resource name, serial port …), for error messages
    resource: str = ""

    @abc.abstractmethod
    def identify(self) -> Identity:
        """Ask the instrument who it is."""

    @abc.abstractmethod
    def close(self) -> None:
        """Release the connection (idempotent)."""

    def __enter__(self) -> "Driver":
        return self

    def __exit__(self, *exc: Any) -> None:
        self.close()


class DmmDriver(Driver):
    """A digital multimeter measuring DC voltage (a gyro's analog output)."""

    @abc.abstractmethod
    def configure_dc_voltage(
        self, range: pint.Quantity | None = None, *, nplc: float = 10.0
    ) -> None:
        """Select DC voltage on ``range`` (``None``: autorange) integrating over ``nplc``
        power-line cycles."""

    @abc.abstractmethod
    def read(self) -> pint.Quantity:
        """Trigger and return one reading (volts)."""


class GyroOutputDriver(Driver):
    """A gyro's digital output (frames over RS-422/RS-485 …)."""

    @abc.abstractmethod
    def read(self, n_frames: int) -> Any:
        """Read ``n_frames`` frames; return a record with the data columns (quantities) and every
        problem found (bad checksums, counter gaps with their byte positions)."""

    def restart(self) -> None:
        """Start a new record: discard what the device sent before now, so the next :meth:`read`
        begins with fresh frames.  A streaming driver overrides it; the default does nothing
        (for outputs that send only when asked)."""


class RateTableDriver(Driver):
    """A single- or multi-axis rate/position table.

    A vendor's implementation translates these calls into its controller's protocol.  Rates and
    angles are pint quantities (``deg/s``, ``deg``); ``axis`` numbers the table's axes from 1.
    """

    @abc.abstractmethod
    def set_rate(self, rate: pint.Quantity, *, axis: int = 1) -> None:
        """Start turning ``axis`` at ``rate`` (signed); returns once the command is accepted."""

    @abc.abstractmethod
    def move_to(self, angle: pint.Quantity, *, axis: int = 1) -> None:
        """Position ``axis`` at the absolute ``angle`` and hold it; returns when in position."""

    @abc.abstractmethod
    def stop(self, *, axis: int | None = None) -> None:
        """Bring ``axis`` (or all axes) to rest."""

    @abc.abstractmethod
    def rate(self, *, axis: int = 1) -> pint.Quantity:
        """The rate the table measures on ``axis`` now."""

    @abc.abstractmethod
    def angle(self, *, axis: int = 1) -> pint.Quantity:
        """The angle the table's encoder reads on ``axis`` now."""

    @abc.abstractmethod
    def wait_stable(self, timeout: pint.Quantity, *, axis: int = 1) -> bool:
        """Wait until ``axis`` holds its set rate or angle; ``False`` if ``timeout`` passed
        first."""

    @abc.abstractmethod
    def equipment(self) -> Equipment:
        """The table as campaign equipment (role ``rate_table``/``table``, accuracy,
        calibration)."""


#: driver kind -> the interface its classes implement
DRIVER_KINDS: Mapping[str, type[Driver]] = {
    "dmm": DmmDriver,
    "gyro-output": GyroOutputDriver,
    "rate-table": RateTableDriver,
}

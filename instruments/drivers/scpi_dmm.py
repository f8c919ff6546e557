"""A SCPI 6½-digit digital multimeter over PyVISA (GPIB, USB-TMC, LAN, serial).

The commands are the common SCPI subset 6½-digit DMMs understand::

    *IDN?                     identification
    *RST; *CLS                reset, clear the error queue
    CONF:VOLT:DC <range>      DC voltage on a fixed range (CONF:VOLT:DC AUTO for autorange)
    VOLT:DC:NPLC <n>          integration time in power-line cycles
    VOLT:DC:RANG?             the range in use
    READ?                     trigger and return one reading
    SYST:ERR?                 next error: '+0,"No error"' when the queue is empty

After every configuration command the error queue is read; an instrument error is a
:class:`~metro.core.base.errors.DriverError` naming the resource, the command and the instrument's
message.  An overload reading (SCPI's 9.9E37) is an error too, never a number.

PyVISA is imported when the driver opens (optional extra ``drivers``).  For tests and
demonstrations, ``visa_library="path/to/file.yaml@sim"`` uses pyvisa-sim.
"""

from __future__ import annotations

import math
from typing import Any

import pint

from metro.core.base.errors import DriverError
from metro.core.base.units import Q_, parse_quantity

from metro.core.model.drivers import DmmDriver, Identity

from .base import DRIVERS_HINT, import_for_driver

__all__ = ["ScpiDmm", "OVERLOAD"]

#: SCPI's "not a number / overload" reading
OVERLOAD = 9.9e37


def _visa():
    return import_for_driver("pyvisa", None, package="PyVISA",
                             hint=DRIVERS_HINT + " (pyvisa, pyvisa-sim, pyserial)")


class ScpiDmm(DmmDriver):
    """A SCPI DMM at a VISA ``resource`` (e.g. ``"TCPIP::192.168.0.7::INSTR"``).

    :param resource: the VISA resource name.
    :param visa_library: PyVISA's library argument (``""`` the default backend, ``"@py"``
        pyvisa-py, ``"file.yaml@sim"`` pyvisa-sim).
    :param timeout: how long one reply may take (a quantity of time).
    """

    def __init__(
        self,
        resource: str,
        *,
        visa_library: str = "",
        timeout: Any = "5 s",
        read_termination: str = "\n",
        write_termination: str = "\n",
    ) -> None:
        self.resource = resource
        tmo = parse_quantity(timeout, dimension="s", field="timeout")
        pyvisa = _visa()
        try:
            self._rm = pyvisa.ResourceManager(visa_library)
            self._inst = self._rm.open_resource(resource)
        except Exception as exc:  # noqa: BLE001 - pyvisa raises several types
            raise DriverError(
                resource,
                None,
                f"cannot open the instrument: {exc}",
                hint="check the address (`python -m pyvisa info`, the instrument's I/O menu)",
            ) from exc
        self._inst.timeout = int(round(float(tmo.to("ms").magnitude)))
        self._inst.read_termination = read_termination
        self._inst.write_termination = write_termination
        self._closed = False
        #: whether the VISA device clear on opening took effect: it drops a reply that an
        #: interrupted earlier session left in the instrument's output buffer, which the first
        #: query would otherwise read as its own answer.  Best effort: some backends (pyvisa-sim,
        #: raw sockets) do not offer it, and ``*IDN?`` below still checks what answers.
        self.device_cleared = False
        try:
            self._inst.clear()
            self.device_cleared = True
        except Exception:  # noqa: BLE001 - a backend without viClear (pyvisa-sim),
            # VI_ERROR_NSUP_OPER, …
            pass
        try:
            #: what the instrument said it is when the driver opened (an absent one fails here)
            self.identity = self.identify()
        except DriverError:
            self.close()
            raise

    # -- low level ----------------------------------------------------------------------
    def _query(self, command: str) -> str:
        if self._closed:
            raise DriverError(self.resource, command, "the driver is closed")
        try:
            reply = self._inst.query(command)
        except Exception as exc:  # noqa: BLE001 - timeouts, I/O errors
            raise DriverError(
                self.resource,
                command,
                f"no valid reply ({type(exc).__name__}: {exc})",
                hint="is the instrument connected, switched on and in SCPI mode?",
            ) from exc
        if reply is None or not str(reply).strip():
            raise DriverError(
                self.resource,
                command,
                "empty reply",
                hint="is the instrument at this address connected and switched on?",
            )
        return str(reply).strip()

    def _write(self, command: str) -> None:
        if self._closed:
            raise DriverError(self.resource, command, "the driver is closed")
        try:
            self._inst.write(command)
        except Exception as exc:  # noqa: BLE001
            raise DriverError(self.resource, command, f"cannot send the command ({exc})") from exc
        self._check_errors(command)

    def _check_errors(self, after: str) -> None:
        """Read the error queue; any entry other than 0 is an error naming the command."""
        messages = []
        for _ in range(20):
            reply = self._query("SYST:ERR?")
            code_text, _, msg = reply.partition(",")
            try:
                code = int(code_text)
            except ValueError as exc:
                raise DriverError(
                    self.resource, "SYST:ERR?", f"malformed error-queue reply {reply!r}"
                ) from exc
            if code == 0:
                break
            messages.append(f"{code}: {msg.strip().strip(chr(34))}")
        if messages:
            raise DriverError(self.resource, after, "the instrument reports " + "; ".join(messages))

    # -- the interface --------------------------------------------------------------------
    def identify(self) -> Identity:
        reply = self._query("*IDN?")
        try:
            return Identity.from_idn(reply)
        except ValueError as exc:
            raise DriverError(self.resource, "*IDN?", str(exc)) from exc

    def reset(self) -> None:
        """``*RST`` then ``*CLS``: the instrument's default state, an empty error queue."""
        self._write("*RST")
        self._write("*CLS")

    def configure_dc_voltage(
        self, range: pint.Quantity | str | None = None, *, nplc: float = 10.0
    ) -> None:
        if range is None:
            self._write("CONF:VOLT:DC AUTO")
        else:
            r = parse_quantity(range, dimension="V", field="range")
            v = float(r.to("V").magnitude)
            if not v > 0:
                raise DriverError(self.resource, "range", f"a range must be positive, got {r}")
            self._write(f"CONF:VOLT:DC {v:.6E}")
        if not (isinstance(nplc, (int, float)) and nplc > 0 and math.isfinite(nplc)):
            raise DriverError(
                self.resource,
                "nplc",
                f"must be a positive number of power-line cycles, got {nplc!r}",
            )
        self._write(f"VOLT:DC:NPLC {float(nplc):.6E}")

    def range(self) -> pint.Quantity:
        """The DC voltage range in use."""
        return Q_(self._number("VOLT:DC:RANG?"), "V")

    def _number(self, command: str) -> float:
        reply = self._query(command)
        try:
            v = float(reply)
        except ValueError as exc:
            raise DriverError(
                self.resource, command, f"the reply {reply!r} is not a number"
            ) from exc
        if not math.isfinite(v) or abs(v) >= OVERLOAD * 0.99:
            raise DriverError(
                self.resource,
                command,
                f"overload or invalid reading ({reply})",
                hint="select a larger range or check the input",
            )
        return v

    def read(self) -> pint.Quantity:
        return Q_(self._number("READ?"), "V")

    def read_many(self, n: int) -> pint.Quantity:
        """``n`` readings, one ``READ?`` each (volts)."""
        if n < 1:
            raise DriverError(self.resource, "n", f"need at least one reading, got {n}")
        import numpy as np

        return Q_(np.array([self._number("READ?") for _ in range(n)]), "V")

    def close(self) -> None:
        if getattr(self, "_closed", True):
            return
        self._closed = True
        try:
            self._inst.close()
        finally:
            self._rm.close()

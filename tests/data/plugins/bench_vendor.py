"""A test-only vendor plugin for the bench station: a rate-table driver over a simulated table,
in a simulated world with its own clock and an analog gyro wired to a pyvisa-sim DMM.

The world (:data:`WORLD`, set by a test with :func:`install`) holds:

* a :class:`SimClock` — the bench's injectable clock; ``sleep`` advances simulated time and
  lets the world move on (no test waits in real time);
* the table: a :class:`metro.instruments.equipment.RateTable` error model (a rate error fixed
  per set point inside its band, a ripple per sample) that accelerates at a finite rate and is
  stable a settling time after reaching its set point — or never, when ``table_stuck``;
* an analog vibratory gyro on the table: V = F₀ + K·Ω_actual + noise, written to the input of the
  pyvisa-sim DMM (tests/data/drivers/scpi_dmm.yaml, its ``SIM:INPUT`` property) every time the
  clock moves, so the DMM's ``READ?`` returns what the gyro puts out at that moment.
"""

from __future__ import annotations

import math
from typing import Any

import attrs
import numpy as np

from metro.core import hookimpl
from metro.core.base.errors import DriverError
from metro.core.base.units import Q_, parse_quantity
from metro.instruments.drivers.base import Identity, RateTableDriver
from metro.instruments.equipment import RateTable


@attrs.define
class SimClock:
    """Simulated monotonic time; ``sleep`` advances it and lets the world move."""

    t: float = 1000.0
    world: Any = None
    sleeps: int = 0

    def monotonic(self) -> float:
        return self.t

    def sleep(self, seconds: float) -> None:
        if seconds > 0:
            self.t += seconds
            self.sleeps += 1
            if self.world is not None:
                self.world.advance()


@attrs.define
class World:
    """The simulated bench: table motion, the gyro's voltage, the DMM's input."""

    clock: SimClock
    table: RateTable
    dmm_library: str = ""
    dmm_resource: str = ""
    K_mV_per_deg_s: float = 25.0
    F0_mV: float = 3.5
    noise_mV: float = 0.02
    acceleration: float = 50.0  # °/s²
    settle_s: float = 2.0
    table_stuck: bool = False
    seed: int = 11
    set_rate: float = 0.0  # °/s, commanded
    ramp_from: float = 0.0
    ramp_t0: float = 0.0
    angle: float = 0.0
    commands: list = attrs.field(factory=list)
    open_tables: int = 0
    #: (mean rate °/s, relative ripple) the table holds at its set point
    held: tuple[float, float] = (0.0, 0.0)
    rng: np.random.Generator = attrs.field(init=False)

    def __attrs_post_init__(self) -> None:
        self.rng = np.random.default_rng(self.seed)
        self.clock.world = self

    # -- the table --------------------------------------------------------------------
    def ramp_end(self) -> float:
        return self.ramp_t0 + abs(self.set_rate - self.ramp_from) / self.acceleration

    def mean_rate(self, t: float) -> float:
        """The table's rate at time t, without ripple (°/s)."""
        if t >= self.ramp_end():
            return self.held[0]
        frac = (t - self.ramp_t0) / max(self.ramp_end() - self.ramp_t0, 1e-12)
        return self.ramp_from + (self.set_rate - self.ramp_from) * frac

    def command(self, rate: float) -> None:
        now = self.clock.t
        self.ramp_from = self.mean_rate(now)
        self.ramp_t0 = now
        self.set_rate = rate
        if rate == 0.0:
            self.held = (0.0, 0.0)
        else:  # the table's error model: a rate error fixed per set point, the band's ripple
            q = Q_(rate, "deg/s")
            self.held = (rate * (1.0 + self.table.systematic_error(q)),
                         float(self.table.band(q).ripple.to("").magnitude))
        self.commands.append(("rate", rate))

    def stable_at(self) -> float:
        return math.inf if self.table_stuck else self.ramp_end() + self.settle_s

    # -- the gyro and the DMM ------------------------------------------------------------
    def actual_rate(self) -> float:
        om = self.mean_rate(self.clock.t)
        if om == 0.0:
            return 0.0
        return om + abs(om) * self.held[1] * float(self.rng.normal())

    def voltage_mV(self) -> float:
        return (
            self.F0_mV + self.K_mV_per_deg_s * self.actual_rate() + self.noise_mV
            * float(self.rng.normal())
        )

    def advance(self) -> None:
        if not self.dmm_library:
            return
        from pyvisa.highlevel import open_visa_library
        from pyvisa.rname import to_canonical_name

        # the same library object (and devices) the bench's ScpiDmm talks to
        dev = open_visa_library(self.dmm_library).devices[to_canonical_name(self.dmm_resource)]
        dev._properties["input"].set_value(f"{self.voltage_mV() / 1000.0:.9E}")


#: the world the drivers of this plugin act in (a test installs one)
WORLD: World | None = None


def install(world: World) -> World:
    global WORLD
    WORLD = world
    return world


def _world() -> World:
    if WORLD is None:
        raise DriverError("sim://", None,
                          "no simulated world installed (tests call bench_vendor.install)")
    return WORLD


class SimRateTable(RateTableDriver):
    """The vendor's RT-500 rate table driver, here talking to the simulated world's table."""

    def __init__(self, address: str = "sim://rt-500", *, serial: str = "RT500-0042") -> None:
        self.resource = address
        self.world = _world()
        self._serial = serial
        self._open = True
        self.world.open_tables += 1

    def _check(self, axis: int) -> None:
        if not self._open:
            raise DriverError(self.resource, None, "the connection is closed")
        if axis != 1:
            raise DriverError(self.resource, "axis", f"the RT-500 has one axis, not axis {axis}")

    def identify(self) -> Identity:
        return Identity("ACME", "RT-500", self._serial, "3.1.4")

    def set_rate(self, rate, *, axis=1):
        self._check(axis)
        r = parse_quantity(rate, dimension="deg/s", field="rate")
        self.world.table.band(r)  # refuses a rate beyond the table's range
        self.world.command(float(r.to("deg/s").magnitude))

    def move_to(self, angle, *, axis=1):
        self._check(axis)
        self.world.command(0.0)
        self.world.angle = float(
            parse_quantity(angle, dimension="deg", field="angle").to("deg").magnitude
        )

    def stop(self, *, axis=None):
        if not self._open:
            raise DriverError(self.resource, "stop", "the connection is closed")
        if self.world.set_rate != 0.0:
            self.world.command(0.0)
        self.world.commands.append(("stop", None))

    def rate(self, *, axis=1):
        self._check(axis)
        return Q_(self.world.mean_rate(self.world.clock.t), "deg/s")

    def angle(self, *, axis=1):
        self._check(axis)
        return Q_(self.world.angle % 360.0, "deg")

    def wait_stable(self, timeout, *, axis=1):
        self._check(axis)
        tmo = float(parse_quantity(timeout, dimension="s", field="timeout").to("s").magnitude)
        clock = self.world.clock
        wait = self.world.stable_at() - clock.t
        if wait > tmo:
            clock.sleep(tmo)
            return False
        clock.sleep(max(wait, 0.0))
        return True

    def equipment(self):
        return self.world.table.equipment()

    def close(self):
        if self._open:
            self._open = False
            self.world.open_tables -= 1


@hookimpl
def metro_register_drivers(registrar):
    registrar.add_driver("acme-rt500", "rate-table", SimRateTable,
                         "ACME RT-500 rate table (simulated, tests)")

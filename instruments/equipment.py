"""Models of the lab's test equipment: what each one states about its accuracy, and how it acts.

Every model is an ``attrs.frozen`` value holding its accuracy parameters as pint quantities
(checked against their dimension when the model is made) and its calibration data.  A model
does two things:

* :meth:`~EquipmentModel.equipment` gives the :class:`~metro.core.model.campaign.Equipment` a
campaign
  carries — its ``role``, its accuracy parameters as properties and a
  :class:`~metro.core.model.campaign.Calibration` (certificate id, U, k, due date) — which the
  procedures
  read as type B components of their budgets (``campaign.equipment_for(role)``);
* its *act* methods reproduce, in simulation, the errors it states: a rate table turns at the set
  rate with its band's systematic error and ripple, a DMM adds its reading error and rounds to
  its resolution, an ADC quantizes, a counter counts whole pulses and carries the remainder, a
  chamber holds its set point within its setpoint error and fluctuation once soaked …

Errors that are *fixed for an instrument* (a DMM's gain and offset, a rate table's error at one
set point) are drawn from the model's ``seed`` and the set point, so the same instrument gives
the same error every time it is asked; errors that vary from sample to sample (ripple,
fluctuation, noise) are drawn from the generator the caller passes.  Half-widths (maximum
permissible errors) are drawn uniformly inside ±the half-width, so an act never exceeds what the
model states; tests in ``tests/instruments/test_equipment.py`` check each claim.

Role names are the ones the built-in procedures look for: ``platform``, ``rate_table``,
``chamber``, ``field_generator``, ``counter`` (GB/T 45570); ``rate-table``, ``dmm``, ``chamber``,
``position-table``, ``angular-vibration``, ``shock``, ``vibration``, ``timer`` (JJF 2014);
``table``, ``acquisition`` (JJF 2003); ``turntable``, ``timer`` (angle instruments).  Each model
has a default role and takes another one as ``role=``.
"""

from __future__ import annotations

import math
from typing import Any, Sequence

import attrs
import numpy as np
import pint

from metro.core.base.errors import DataError
from metro.core.model.campaign import Equipment
from metro.core.base.units import Q_, parse_quantity
from .equipment_base import (EquipmentModel, accuracy_field, as_float_array, fixed_rng,
                             magnitude_in, non_negative, opt_q_of, q_of, uncertainty_converter)

__all__ = [
    "EquipmentModel",
    "RateBand",
    "RateTable",
    "LevelPlatform",
    "Fixture",
    "PositionTable",
    "TiltTable",
    "ThreeAxisTable",
    "TemperatureChamber",
    "AngularVibrationTable",
    "LinearShaker",
    "ShockTable",
    "FieldGenerator",
    "DigitalMultimeter",
    "Counter",
    "ADC",
    "Timer",
    "AngleTurntable",
]


# ------------------------------------------------------------------------------ helpers


# ------------------------------------------------------------------------------ base


# ------------------------------------------------------------------------------ tables


@attrs.frozen
class RateBand:
    """Accuracy of a rate table for rates |Ω| up to ``upper``: the mean rate is within
    ±``error`` (relative, a half-width) of the set point, and the rate over one sample scatters
    with relative standard deviation ``ripple`` (the rate stability)."""

    upper: pint.Quantity = attrs.field(converter=q_of("deg/s"))
    error: pint.Quantity = attrs.field(converter=q_of(""), validator=non_negative)
    ripple: pint.Quantity = attrs.field(converter=q_of(""), validator=non_negative)


def _default_bands() -> tuple[RateBand, ...]:
    return (
        RateBand("1 deg/s", 1e-4, 1e-3),
        RateBand("10 deg/s", 1e-5, 1e-4),
        RateBand("1000 deg/s", 5e-6, 2e-5),
    )


@attrs.frozen(kw_only=True)
class RateTable(EquipmentModel):
    """Single-axis rate table with an angle output and a once-per-revolution pulse.

    * ``bands`` — rate error and ripple by rate band (:class:`RateBand`, by increasing ``upper``);
    * ``angle_resolution`` — the step of its angle output;
    * ``revolution_pulse_accuracy`` — where, within ±this angle, the revolution pulse comes
      (GB/T 45570 D.1.1 reads it as ``revolution_pulse_accuracy``).
    """

    ROLE = "rate_table"
    bands: tuple[RateBand, ...] = attrs.field(factory=_default_bands, converter=tuple)
    angle_resolution: pint.Quantity = accuracy_field(Q_(0.36, "arcsec"), "arcsec")
    revolution_pulse_accuracy: pint.Quantity = accuracy_field(Q_(2.0, "arcsec"), "arcsec")

    def __attrs_post_init__(self) -> None:
        super().__attrs_post_init__()
        ups = [magnitude_in(b.upper, "deg/s") for b in self.bands]
        if not ups or ups != sorted(ups):
            raise DataError(
                None, f"{self.id}.bands", "give at least one band, by increasing upper rate"
            )

    def properties(self) -> dict[str, Any]:
        p: dict[str, Any] = {
            "revolution_pulse_accuracy": self.revolution_pulse_accuracy,
            "angle_resolution": self.angle_resolution,
        }
        for i, b in enumerate(self.bands, 1):
            p[f"rate_band_{i}_upper"] = b.upper
            p[f"rate_band_{i}_error"] = b.error
            p[f"rate_band_{i}_ripple"] = b.ripple
        return p

    def band(self, rate: pint.Quantity) -> RateBand:
        """The band that covers |``rate``|; a rate above the last band is an error."""
        r = abs(magnitude_in(parse_quantity(rate, dimension="deg/s", field="rate"), "deg/s"))
        for b in self.bands:
            if r <= magnitude_in(b.upper, "deg/s"):
                return b
        raise DataError(
            None, "rate", f"{r:g} °/s is beyond the table's range ({self.bands[-1].upper})"
        )

    def systematic_error(self, setpoint: pint.Quantity) -> float:
        """The table's fixed relative rate error at this set point (inside ±band error)."""
        b = self.band(setpoint)
        e = float(b.error.to("").magnitude)
        return float(
            fixed_rng(self.seed, "rate", round(magnitude_in(setpoint, "deg/s"), 9)).uniform(-e, e)
        )

    def actual_rate(
        self, setpoint: pint.Quantity, n: int, rng: np.random.Generator
    ) -> pint.Quantity:
        """``n`` samples of the rate the table actually turns at: Ω·(1 + δ) + Ω·ripple·N(0, 1)."""
        om = magnitude_in(parse_quantity(setpoint, dimension="deg/s", field="setpoint"), "deg/s")
        rip = float(self.band(setpoint).ripple.to("").magnitude)
        mean = om * (1.0 + self.systematic_error(setpoint))
        noise = rng.normal(0.0, abs(om) * rip, size=n) if rip > 0 else np.zeros(n)
        return Q_(mean + noise, "deg/s")

    def angle_output(
        self, rate: pint.Quantity, interval: pint.Quantity, start: pint.Quantity | None = None
    ) -> tuple[pint.Quantity, pint.Quantity]:
        """The table's angle readings at the end of each sample for this rate record, and the
        true angle at the end (pass it as ``start`` of the next chunk).

        Readings are the true accumulated angle truncated to ``angle_resolution``; as they read an
        absolute angle, splitting a record into chunks loses nothing.
        """
        w = as_float_array(rate, "deg/s", "rate")
        dt_s = magnitude_in(parse_quantity(interval, dimension="s", field="interval"), "s")
        start = (
            Q_(0.0, "deg")
            if start is None
            else parse_quantity(start, dimension="deg", field="start")
        )
        theta = magnitude_in(start, "arcsec") + np.cumsum(w) * dt_s * 3600.0
        res = magnitude_in(self.angle_resolution, "arcsec")
        read = np.floor(theta / res) * res if res > 0 else theta
        return Q_(read, "arcsec").to("deg"), Q_(
            float(theta[-1]) if theta.size else magnitude_in(start, "arcsec"), "arcsec"
        ).to("deg")

    def revolution_times(
        self, rate: pint.Quantity, turns: int, rng: np.random.Generator
    ) -> pint.Quantity:
        """Times of the ``turns`` revolution pulses at a constant ``rate``: k·360°/Ω, each shifted
        by
        the pulse's angle error (uniform in ±``revolution_pulse_accuracy``) divided by Ω."""
        om = abs(magnitude_in(parse_quantity(rate, dimension="deg/s", field="rate"), "deg/s"))
        if om <= 0:
            raise DataError(None, "rate", "revolution pulses need a non-zero rate")
        acc = magnitude_in(self.revolution_pulse_accuracy, "deg")
        k = np.arange(1, turns + 1)
        err = rng.uniform(-acc, acc, size=turns) if acc > 0 else np.zeros(turns)
        return Q_((360.0 * k + err) / om, "s")


@attrs.frozen(kw_only=True)
class LevelPlatform(EquipmentModel):
    """A levelled platform: its top is level within ±``levelness`` (GB/T 45570 D.5 reads
    ``levelness``)."""

    ROLE = "platform"
    levelness: pint.Quantity = accuracy_field(Q_(2.0, "arcsec"), "arcsec")

    def properties(self) -> dict[str, Any]:
        return {"levelness": self.levelness}

    def tilt(self) -> pint.Quantity:
        """The platform's fixed tilt (inside ±levelness)."""
        lv = magnitude_in(self.levelness, "arcsec")
        return Q_(float(fixed_rng(self.seed, "tilt").uniform(-lv, lv)), "arcsec")


@attrs.frozen(kw_only=True)
class Fixture(EquipmentModel):
    """The gyro's mounting fixture: each time the gyro is re-seated (e.g. turned 180° about its
    IRA) its axes tilt by up to ±``reseat_tilt`` (GB/T 45570's misalignment items read
    ``reseat_tilt``)."""

    ROLE = "fixture"
    reseat_tilt: pint.Quantity = accuracy_field(Q_(3.0, "arcsec"), "arcsec")

    def properties(self) -> dict[str, Any]:
        return {"reseat_tilt": self.reseat_tilt}

    def reseat(self, rng: np.random.Generator) -> tuple[pint.Quantity, pint.Quantity]:
        """The tilts (about two axes) after one re-seating, each uniform in ±reseat_tilt."""
        e = magnitude_in(self.reseat_tilt, "arcsec")
        a, b = rng.uniform(-e, e, size=2) if e > 0 else (0.0, 0.0)
        return Q_(float(a), "arcsec"), Q_(float(b), "arcsec")


def reached_angles(
    setpoints: pint.Quantity, accuracy: pint.Quantity, rng: np.random.Generator
) -> pint.Quantity:
    """The angles (deg) a table reaches for ``setpoints``: each within ±``accuracy``, uniform
    (drawn from ``rng`` when ``accuracy`` is not 0)."""
    s = as_float_array(setpoints, "deg", "setpoints")
    e = magnitude_in(accuracy, "deg")
    return Q_(s + (rng.uniform(-e, e, size=s.shape) if e > 0 else 0.0), "deg")


@attrs.frozen(kw_only=True)
class _Positioner(EquipmentModel):
    """A table that sets angles within ±``position_accuracy`` (uniform)."""

    position_accuracy: pint.Quantity = accuracy_field(Q_(3.0, "arcsec"), "arcsec")

    def properties(self) -> dict[str, Any]:
        return {"position_accuracy": self.position_accuracy}

    def position(self, setpoints: pint.Quantity, rng: np.random.Generator) -> pint.Quantity:
        """The angles the table actually reaches for these set points."""
        return reached_angles(setpoints, self.position_accuracy, rng)


@attrs.frozen(kw_only=True)
class PositionTable(_Positioner):
    """Two-axis position table (orientations for the g-sensitivity and misalignment tests)."""

    ROLE = "position-table"


@attrs.frozen(kw_only=True)
class TiltTable(_Positioner):
    """Tilt (latitude) table: sets the input axis to an angle from the horizontal within
    ±``position_accuracy`` (GB/T 45570's threshold items read ``position_accuracy``);
    ``tilt_range`` is the largest tilt it can set."""

    ROLE = "tilt_table"
    tilt_range: pint.Quantity = attrs.field(default=Q_(90.0, "deg"), converter=q_of("deg"))

    def properties(self) -> dict[str, Any]:
        return super().properties() | {"tilt_range": self.tilt_range}

    def position(self, setpoints: pint.Quantity, rng: np.random.Generator) -> pint.Quantity:
        s = as_float_array(setpoints, "deg", "setpoints")
        lim = magnitude_in(self.tilt_range, "deg")
        if np.any(np.abs(s) > lim):
            raise DataError(
                None, "setpoints", f"a tilt beyond ±{lim:g}° cannot be set on {self.id}"
            )
        return super().position(setpoints, rng)


@attrs.frozen(kw_only=True)
class ThreeAxisTable(RateTable):
    """Three-axis position/rate table: positions each axis within ±``position_accuracy``
    (JJF 2003 reads ``position_accuracy``) and turns with the rate bands of :class:`RateTable`."""

    ROLE = "table"
    position_accuracy: pint.Quantity = accuracy_field(Q_(10.0, "arcsec"), "arcsec")

    def properties(self) -> dict[str, Any]:
        p = super().properties()
        del p["revolution_pulse_accuracy"]
        return {"position_accuracy": self.position_accuracy} | p

    def position(self, setpoints: pint.Quantity, rng: np.random.Generator) -> pint.Quantity:
        """Angles reached on one axis for these set points (uniform in ±position_accuracy)."""
        return reached_angles(setpoints, self.position_accuracy, rng)


# ------------------------------------------------------------------------------ environment


@attrs.frozen(kw_only=True)
class TemperatureChamber(EquipmentModel):
    """Temperature chamber: once soaked, the air is within ±``setpoint_error`` of the set point
    (a fixed offset per set point) and fluctuates within ±``fluctuation`` about it (a slow
    cycle of period ``cycle``); ``soak`` is the time it needs to settle after a change (the
    approach is exponential with time constant soak/5, i.e. within 1 % of the step at ``soak``).
    ``uniformity`` (optional) is the half-width of the temperature differences over the working
    volume; GB/T 45570's temperature items add it to the budget of the applied temperature.
    """

    ROLE = "chamber"
    U: pint.Quantity | None = attrs.field(
        default=None, converter=uncertainty_converter("K"), validator=non_negative
    )
    setpoint_error: pint.Quantity = accuracy_field(Q_(0.5, "K"), "K")
    fluctuation: pint.Quantity = accuracy_field(Q_(0.2, "K"), "K")
    soak: pint.Quantity = accuracy_field(Q_(60.0, "min"), "s")
    cycle: pint.Quantity = attrs.field(default=Q_(10.0, "min"), converter=q_of("s"))
    uniformity: pint.Quantity | None = attrs.field(
        default=None, converter=opt_q_of("K"), validator=non_negative
    )

    def properties(self) -> dict[str, Any]:
        return self.given("setpoint_error", "fluctuation", "soak", "uniformity")

    def offset(self, setpoint: pint.Quantity) -> float:
        """The fixed offset (K) of the chamber at this set point (inside ±setpoint_error)."""
        e = magnitude_in(self.setpoint_error, "K")
        T = magnitude_in(parse_quantity(setpoint, dimension="degC", field="setpoint"), "degC")
        return float(fixed_rng(self.seed, "T", round(T, 6)).uniform(-e, e))

    def temperature(
        self,
        setpoint: pint.Quantity,
        times: pint.Quantity,
        rng: np.random.Generator,
        *,
        previous: pint.Quantity | None = None,
    ) -> pint.Quantity:
        """Air temperature at ``times`` after the set point was changed from ``previous`` (default:
        already soaked at ``setpoint``)."""
        t = as_float_array(times, "s", "times")
        T = magnitude_in(parse_quantity(setpoint, dimension="degC", field="setpoint"), "degC")
        target = T + self.offset(setpoint)
        fl = magnitude_in(self.fluctuation, "K")
        phase = rng.uniform(0.0, 2.0 * math.pi)
        wave = fl * np.sin(2.0 * math.pi * t / magnitude_in(self.cycle, "s") + phase)
        if previous is None:
            base = np.full(t.shape, target)
        else:
            T0 = magnitude_in(parse_quantity(previous, dimension="degC", field="previous"), "degC")
            tau = max(magnitude_in(self.soak, "s") / 5.0, 1e-9)
            base = target + (T0 - target) * np.exp(-np.clip(t, 0, None) / tau)
        return Q_(base + wave, "degC")

    def soaked(self, elapsed: pint.Quantity) -> bool:
        """Whether ``elapsed`` since the last change is at least the soak time."""
        return magnitude_in(
            parse_quantity(elapsed, dimension="s", field="elapsed"), "s"
        ) >= magnitude_in(self.soak, "s")


@attrs.frozen(kw_only=True)
class FieldGenerator(EquipmentModel):
    """DC magnetic field generator (Helmholtz coil): the field at the centre is the set point
    times (1 + δ), δ fixed per set point within ±``setting_error``; over the test volume it varies
    by ±``uniformity`` (GB/T 45570 D.5.5 reads ``uniformity``)."""

    ROLE = "field_generator"
    setting_error: pint.Quantity = accuracy_field(Q_(5e-3, ""), "")
    uniformity: pint.Quantity = accuracy_field(Q_(5.0, "percent"), "")
    max_field: pint.Quantity = attrs.field(default=Q_(2.0, "mT"), converter=q_of("mT"))

    def properties(self) -> dict[str, Any]:
        return {
            "uniformity": self.uniformity,
            "setting_error": self.setting_error,
            "max_field": self.max_field,
        }

    def field(self, setpoint: pint.Quantity, position: float = 0.0) -> pint.Quantity:
        """Field at a point of the test volume; ``position`` ∈ [−1, 1] from the centre to the
        edge."""
        H = magnitude_in(parse_quantity(setpoint, dimension="mT", field="setpoint"), "mT")
        if abs(H) > magnitude_in(self.max_field, "mT"):
            raise DataError(None, "setpoint", f"{H:g} mT is beyond {self.id}'s {self.max_field}")
        if not -1.0 <= position <= 1.0:
            raise DataError(
                None, "position", "must be in [-1, 1] (centre 0, edge of the test volume ±1)"
            )
        e = float(self.setting_error.to("").magnitude)
        d = float(fixed_rng(self.seed, "H", round(H, 9)).uniform(-e, e))
        return Q_(H * (1.0 + d) * (1.0 + float(self.uniformity.to("").magnitude) * position), "mT")


# ------------------------------------------------------------------------------ vibration, shock


@attrs.frozen(kw_only=True)
class AngularVibrationTable(EquipmentModel):
    """Angular vibration table with a reference rate sensor.

    The table turns as Ω_a·sin(2πft); the reference sensor reads it with a relative amplitude
    error fixed per frequency within ±``amplitude_error`` and a phase error fixed per frequency,
    normal with expanded uncertainty ``phase_U`` (k = 2).  JJF 2014 7.2.22 reads ``phase_U``.
    """

    ROLE = "angular-vibration"
    amplitude_error: pint.Quantity = accuracy_field(Q_(5e-3, ""), "")
    phase_U: pint.Quantity = accuracy_field(Q_(0.2, "deg"), "deg")
    frequency_range: tuple[pint.Quantity, pint.Quantity] = attrs.field(
        default=(Q_(0.1, "Hz"), Q_(500.0, "Hz")),
        converter=lambda v: tuple(q_of("Hz")(x) for x in v),
    )

    def properties(self) -> dict[str, Any]:
        return {
            "phase_U": self.phase_U,
            "amplitude_error": self.amplitude_error,
            "frequency_min": self.frequency_range[0],
            "frequency_max": self.frequency_range[1],
        }

    def motion(
        self, amplitude: pint.Quantity, frequency: pint.Quantity, times: pint.Quantity
    ) -> tuple[pint.Quantity, pint.Quantity]:
        """(true rate, reference sensor reading) at ``times``."""
        a = magnitude_in(parse_quantity(amplitude, dimension="deg/s", field="amplitude"), "deg/s")
        f = magnitude_in(parse_quantity(frequency, dimension="Hz", field="frequency"), "Hz")
        lo, hi = (magnitude_in(x, "Hz") for x in self.frequency_range)
        if not lo <= f <= hi:
            raise DataError(
                None, "frequency", f"{f:g} Hz is outside {self.id}'s range {lo:g}–{hi:g} Hz"
            )
        t = as_float_array(times, "s", "times")
        r = fixed_rng(self.seed, "avt", round(f, 9))
        e = float(self.amplitude_error.to("").magnitude)
        da = r.uniform(-e, e)
        dphi = r.normal(0.0, magnitude_in(self.phase_U, "rad") / 2.0)
        w = 2.0 * math.pi * f
        return Q_(a * np.sin(w * t), "deg/s"), Q_(a * (1.0 + da) * np.sin(w * t + dphi), "deg/s")


@attrs.frozen(kw_only=True)
class LinearShaker(EquipmentModel):
    """Linear vibration table: sinusoidal acceleration of amplitude within ±``amplitude_error``
    (relative) of the set value and frequency within ±``frequency_error`` (relative).
    ``level_accuracy`` (optional; relative or in g) is stated as a property for procedures that
    budget the applied level from it (GB/T 45570's vibration items read ``level_accuracy``)."""

    ROLE = "vibration"
    amplitude_error: pint.Quantity = accuracy_field(Q_(0.05, ""), "")
    frequency_error: pint.Quantity = accuracy_field(Q_(1e-3, ""), "")
    max_acceleration: pint.Quantity = attrs.field(default=Q_(20.0, "gn"), converter=q_of("gn"))
    level_accuracy: pint.Quantity | None = attrs.field(
        default=None, converter=uncertainty_converter("gn"), validator=non_negative
    )

    def properties(self) -> dict[str, Any]:
        return self.given(
            "amplitude_error", "frequency_error", "max_acceleration", "level_accuracy"
        )

    def acceleration(
        self, amplitude: pint.Quantity, frequency: pint.Quantity, times: pint.Quantity
    ) -> pint.Quantity:
        a = magnitude_in(parse_quantity(amplitude, dimension="gn", field="amplitude"), "gn")
        if abs(a) > magnitude_in(self.max_acceleration, "gn"):
            raise DataError(
                None, "amplitude", f"{a:g} g is beyond {self.id}'s {self.max_acceleration}"
            )
        f = magnitude_in(parse_quantity(frequency, dimension="Hz", field="frequency"), "Hz")
        r = fixed_rng(self.seed, "shaker", round(a, 9), round(f, 9))
        ea, ef = (float(x.to("").magnitude) for x in (self.amplitude_error, self.frequency_error))
        t = as_float_array(times, "s", "times")
        return Q_(
            a * (1 + r.uniform(-ea, ea)) * np.sin(2 * math.pi * f * (1 + r.uniform(-ef, ef)) * t),
            "gn",
        )


@attrs.frozen(kw_only=True)
class ShockTable(EquipmentModel):
    """Shock machine: half-sine pulses whose peak is within ±``peak_error`` (relative) and whose
    duration is within ±``duration_accuracy`` of the set values (GB/T 45570's shock item reads
    ``duration_accuracy``)."""

    ROLE = "shock"
    peak_error: pint.Quantity = accuracy_field(Q_(0.1, ""), "")
    duration_accuracy: pint.Quantity = accuracy_field(Q_(1.0, "ms"), "s")

    def properties(self) -> dict[str, Any]:
        return {"peak_error": self.peak_error, "duration_accuracy": self.duration_accuracy}

    def pulse(
        self,
        peak: pint.Quantity,
        duration: pint.Quantity,
        interval: pint.Quantity,
        rng: np.random.Generator,
    ) -> pint.Quantity:
        """One half-sine pulse sampled every ``interval`` (and one zero sample either side)."""
        p = magnitude_in(parse_quantity(peak, dimension="gn", field="peak"), "gn")
        d = magnitude_in(parse_quantity(duration, dimension="s", field="duration"), "s")
        dt_s = magnitude_in(parse_quantity(interval, dimension="s", field="interval"), "s")
        ep, ed = float(self.peak_error.to("").magnitude), magnitude_in(self.duration_accuracy, "s")
        if ed >= d:
            raise DataError(
                None, "duration", f"{d:g} s is not longer than {self.id}'s duration accuracy"
            )
        p *= 1 + rng.uniform(-ep, ep)
        d += rng.uniform(-ed, ed)
        t = np.arange(-dt_s, d + 2 * dt_s, dt_s)
        a = np.where((t >= 0) & (t <= d), p * np.sin(math.pi * np.clip(t, 0, d) / d), 0.0)
        return Q_(a, "gn")


# ------------------------------------------------------------------------------ data acquisition


def _meter_range(v: Any) -> pint.Quantity:
    q = parse_quantity(v, field="range")
    for unit_ in ("V", "A"):
        if q.dimensionality == Q_(1, unit_).dimensionality:
            return q
    raise DataError(None, "range", f"a DC voltage (V) or current (A) range, not {q}")


@attrs.frozen(kw_only=True)
class DigitalMultimeter(EquipmentModel):
    """6½-digit DMM on a DC voltage (or current) range: error within ±(``reading_error``·|x| +
    ``range_error``·range) — a gain and an offset fixed for the instrument — and readings rounded
    to the resolution range/10^⌊digits⌋ (10 µV on the 10 V range for 6½ digits).  The same model
    serves as the ``voltmeter`` or ``ammeter`` (GB/T 45570 power item) with ``role=``."""

    ROLE = "dmm"
    range: pint.Quantity = attrs.field(default=Q_(10.0, "V"), converter=_meter_range)
    reading_error: pint.Quantity = accuracy_field(Q_(35.0, "ppm"), "")
    range_error: pint.Quantity = accuracy_field(Q_(5.0, "ppm"), "")
    digits: float = 6.5

    @property
    def _unit(self) -> str:
        return "V" if self.range.dimensionality == Q_(1, "V").dimensionality else "A"

    @property
    def resolution(self) -> pint.Quantity:
        return self.range / 10 ** math.floor(self.digits)

    def properties(self) -> dict[str, Any]:
        return {
            "range": self.range,
            "reading_error": self.reading_error,
            "range_error": self.range_error,
            "resolution": self.resolution,
        }

    def error_bound(self, values: pint.Quantity) -> pint.Quantity:
        """The stated maximum error at these readings (without the rounding's half step)."""
        u = self._unit
        v = np.abs(as_float_array(values, u, "values"))
        return Q_(
            float(self.reading_error.to("").magnitude) * v
            + float(self.range_error.to("").magnitude) * magnitude_in(self.range, u),
            u,
        )

    def read(self, values: pint.Quantity) -> pint.Quantity:
        """What the meter reads for these true values (returned in the unit they were given)."""
        u = self._unit
        q = (
            values
            if isinstance(values, pint.Quantity)
            else parse_quantity(values, dimension=u, field="values")
        )
        v = as_float_array(q, u, "values")
        rng_v = magnitude_in(self.range, u)
        if np.any(np.abs(v) > 1.2 * rng_v):
            raise DataError(
                None,
                "values",
                f"overload: a reading beyond 1.2 × the {self.range} range of {self.id}",
            )
        r = fixed_rng(self.seed, "dmm", rng_v)
        gain = r.uniform(-1, 1) * float(self.reading_error.to("").magnitude)
        offset = r.uniform(-1, 1) * float(self.range_error.to("").magnitude) * rng_v
        res = magnitude_in(self.resolution, u)
        out = np.round((v * (1 + gain) + offset) / res) * res
        return Q_(out, u).to(q.units)


@attrs.frozen(kw_only=True)
class Counter(EquipmentModel):
    """Pulse counter with a time base of relative error within ±``timebase_error``: gates last
    the nominal time × (1 + δ); counts are whole pulses and the part of a pulse not yet complete is
    carried into the next gate, so no pulse is lost or counted twice."""

    ROLE = "counter"
    timebase_error: pint.Quantity = accuracy_field(Q_(5e-8, ""), "")

    def properties(self) -> dict[str, Any]:
        return {"timebase_error": self.timebase_error}

    def gate(self, nominal: pint.Quantity) -> pint.Quantity:
        e = float(self.timebase_error.to("").magnitude)
        d = float(fixed_rng(self.seed, "timebase").uniform(-e, e))
        return parse_quantity(nominal, dimension="s", field="gate") * (1.0 + d)

    @staticmethod
    def count(increments: pint.Quantity, carry: float = 0.0) -> tuple[pint.Quantity, float]:
        """Whole pulses counted in each gate for these (fractional) pulse increments, and the carry
        (0 ≤ carry < 1 for non-negative totals) to pass to the next call."""
        inc = as_float_array(increments, "P", "increments")
        cum = np.cumsum(inc) + carry
        whole = np.floor(cum)
        counts = np.diff(whole, prepend=math.floor(carry))
        new_carry = float(cum[-1] - whole[-1]) if cum.size else carry
        return Q_(counts, "P"), new_carry


@attrs.frozen(kw_only=True)
class ADC(EquipmentModel):
    """N-bit analogue-to-digital converter over ±``full_scale``: a code per LSB =
    2·full_scale/2^N, rounded to the nearest code (error within ±½ LSB), clipped at the ends.
    JJF 2003 reads ``bits`` (A.1.2.2: δ = 1/2^N)."""

    ROLE = "acquisition"
    bits: int = 12
    full_scale: pint.Quantity = attrs.field(default=Q_(10.0, "V"), converter=q_of("V"))

    def __attrs_post_init__(self) -> None:
        super().__attrs_post_init__()
        if not 2 <= int(self.bits) <= 32:
            raise DataError(
                None, f"{self.id}.bits", f"{self.bits} bits is not a converter (2 … 32)"
            )

    @property
    def lsb(self) -> pint.Quantity:
        return 2 * self.full_scale / 2 ** int(self.bits)

    def properties(self) -> dict[str, Any]:
        return {"bits": int(self.bits), "full_scale": self.full_scale}

    def codes(self, volts: pint.Quantity) -> tuple[np.ndarray, int]:
        """Integer codes (−2^(N−1) … 2^(N−1) − 1) and how many samples were clipped."""
        v = as_float_array(volts, "V", "volts")
        lo, hi = -(2 ** (int(self.bits) - 1)), 2 ** (int(self.bits) - 1) - 1
        c = np.round(v / magnitude_in(self.lsb, "V"))
        clipped = int(np.count_nonzero((c < lo) | (c > hi)))
        return np.clip(c, lo, hi).astype(np.int64), clipped

    def quantize(self, volts: pint.Quantity) -> pint.Quantity:
        """The voltages the converter reports (code × LSB); clipping is an error."""
        c, clipped = self.codes(volts)
        if clipped:
            raise DataError(
                None,
                "volts",
                f"{clipped} sample(s) beyond ±{self.full_scale} were clipped by {self.id}",
            )
        return Q_(c * magnitude_in(self.lsb, "V"), "V")


@attrs.frozen(kw_only=True)
class Timer(EquipmentModel):
    """Timer: measures intervals with relative error within ±``accuracy`` and rounds to
    ``resolution``."""

    ROLE = "timer"
    accuracy: pint.Quantity = accuracy_field(Q_(5e-7, ""), "")
    resolution: pint.Quantity = accuracy_field(Q_(1e-6, "s"), "s")

    def properties(self) -> dict[str, Any]:
        return {"accuracy": self.accuracy, "resolution": self.resolution}

    def measure(self, elapsed: pint.Quantity) -> pint.Quantity:
        t = as_float_array(elapsed, "s", "elapsed")
        e = float(self.accuracy.to("").magnitude)
        d = float(fixed_rng(self.seed, "timer").uniform(-e, e))
        res = magnitude_in(self.resolution, "s")
        m = t * (1 + d)
        return Q_(np.round(m / res) * res if res > 0 else m, "s")


@attrs.frozen(kw_only=True)
class AngleTurntable(_Positioner):
    """Low-speed angle turntable (angle instruments): stops within ±``position_accuracy``;
    ``axis_wobble`` and ``parallelism`` (of the instrument's axis to the table's; the ``ogam``
    items read it) are stated too."""

    ROLE = "turntable"
    position_accuracy: pint.Quantity = accuracy_field(Q_(0.1, "arcsec"), "arcsec")
    axis_wobble: pint.Quantity = accuracy_field(Q_(0.3, "arcsec"), "arcsec")
    parallelism: pint.Quantity = accuracy_field(Q_(0.1, "deg"), "deg")

    def properties(self) -> dict[str, Any]:
        return {
            "axis_wobble": self.axis_wobble,
            "parallelism": self.parallelism,
            "position_accuracy": self.position_accuracy,
        }


def equipment_list(models: Sequence[EquipmentModel]) -> list[Equipment]:
    """The campaign's equipment for these models; two models may not share an id."""
    ids = [m.id for m in models]
    dup = sorted({i for i in ids if ids.count(i) > 1})
    if dup:
        raise DataError(None, "equipment", f"duplicate equipment id(s) {', '.join(dup)}")
    return [m.equipment() for m in models]


__all__ += ["equipment_list", "reached_angles"]

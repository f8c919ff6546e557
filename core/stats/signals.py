"""Turning a gyro's raw output into an indicated angular rate, with units checked.

A gyro's samples come as pulses per sampling interval (P, angle-increment output), as a
digital word (LSB), as an analog voltage (mV) or already as a rate (°/h, °/s).  Procedures
work on the raw magnitudes (no full-size copies of long records) and convert with one
scalar factor::

    rate = raw × factor

* pulses:   rate = N / (τ·K)      with K in P/″ (GB/T 45570 D.40, D.41)
* LSB, mV:  rate = F / K          with K in LSB/[(°)/s] or mV/[(°)/s]
* a rate:   rate = value          (unit conversion only)

``factor`` is a pint quantity in (°/h) per raw unit, so the result unit is always checked.
"""

from __future__ import annotations

import math

import attrs
import pint

from ..base.errors import DataError
from ..base.units import Q_, check_dimension, fmt_unit

RATE = "deg/h"

#: accepted raw output units of a gyro (header units)
OUTPUT_UNITS = ("P", "LSB", "mV", "deg/h")


@attrs.frozen
class RateConversion:
    """rate = raw × factor; ``relative_u`` is the relative standard uncertainty of the factor
    (from the scale factor and the time base)."""

    factor: pint.Quantity  # °/h for one raw unit
    output_kind: str  # "pulse" | "digital" | "analog" | "rate"
    #: the device's scale factor K the factor was made from (P/″ for a pulse output, LSB/(°/s)
    #: or mV/(°/s) for a digital or analog one), as given; None when none was given (a rate
    #: output needs none)
    scale_factor: pint.Quantity | None
    #: the relative standard uncertainty u(K)/K of the scale factor (a fraction, k = 1); 0.0
    #: for a rate output or a K stated without uncertainty
    relative_u_scale_factor: float
    #: the conversion as text for a reader (``"rate = F/K"``, ``"rate = N/(τ·K)  (GB/T 45570
    #: eq. D.40)"``, ``"output already a rate"``)
    explanation: str

    @property
    def magnitude(self) -> float:
        """°/h per raw unit, as a float to multiply raw magnitudes by."""
        return float(self.factor.to(RATE).magnitude)

    def __call__(self, raw: float) -> pint.Quantity:
        """The indicated rate (°/h) of a raw magnitude."""
        return Q_(raw * self.magnitude, RATE)


def rate_conversion(
    raw_unit: pint.Unit,
    interval: pint.Quantity,
    scale_factor: pint.Quantity | None,
    *,
    scale_factor_u_rel: float = 0.0,
    source: str | None = None,
) -> RateConversion:
    """The factor that turns raw samples (in ``raw_unit``, one per ``interval``) into °/h.

    :raises DataError: when the output needs a scale factor and none (or one of the wrong
        kind, e.g. LSB/(°/s) for a pulse output) is given.
    """
    check_dimension(interval, "s", file=source, field="sample_interval")
    raw = Q_(1.0, raw_unit)
    if raw.check("[pulse_count]"):
        if scale_factor is None:
            raise DataError(
                source,
                "device.scale_factor",
                "pulse output needs the scale factor K in P/″",
                hint='add scale_factor = "… P/″" under [device] (from D.1.1)',
            )
        check_dimension(scale_factor, "P/arcsec", file=source, field="device.scale_factor")
        f = raw / (interval * scale_factor)
        kind, expl = "pulse", "rate = N/(τ·K)  (GB/T 45570 eq. D.40)"
    elif raw.check("[digital_count]") or raw.check("[electric_potential]"):
        if scale_factor is None:
            raise DataError(
                source,
                "device.scale_factor",
                f"{fmt_unit(raw_unit)} output needs the scale factor K in "
                f"{fmt_unit(raw_unit)}/[(°)/s]",
                hint='add scale_factor = "… LSB/(°/s)" under [device] (from D.2.1)',
            )
        check_dimension(
            scale_factor, f"{raw_unit}/(deg/s)", file=source, field="device.scale_factor"
        )
        f = raw / scale_factor
        kind = "digital" if raw.check("[digital_count]") else "analog"
        expl = "rate = F/K"
    else:
        check_dimension(raw, RATE, file=source, field="output")
        f = raw
        kind, expl = "rate", "output already a rate"
        scale_factor_u_rel = 0.0
    f = f.to(RATE)
    if not math.isfinite(f.magnitude) or f.magnitude == 0:
        raise DataError(source, "device.scale_factor", f"gives an unusable conversion factor {f}")
    return RateConversion(
        factor=Q_(f.magnitude, RATE),
        output_kind=kind,
        scale_factor=scale_factor,
        relative_u_scale_factor=scale_factor_u_rel,
        explanation=expl,
    )


def device_scale_factor(device, source: str | None = None) -> tuple[pint.Quantity | None, float]:
    """The device's scale factor K and its *relative standard* uncertainty, from the
    manifest's ``[device]`` keys ``scale_factor``, ``scale_factor_U`` (expanded, absolute
    or relative) and ``scale_factor_k`` (default 2)."""
    props = device.properties
    K = props.get("scale_factor")
    if K is None:
        return None, 0.0
    U = props.get("scale_factor_U")
    k = float(props.get("scale_factor_k", 2.0))
    if U is None:
        return K, 0.0
    if U.dimensionless and not K.dimensionless:
        rel = float(U.to("").magnitude)
    else:
        check_dimension(U, str(K.units), file=source, field="device.scale_factor_U")
        rel = float((U / K).to("").magnitude)
    return K, abs(rel) / k


def required_scale_factor(
    device, unit: str, *, source: str | None, needed_by: str
) -> tuple[float, float]:
    """The device's scale factor K as a number in ``unit`` and its relative standard
    uncertainty, for a formula that divides by K; a missing or wrongly dimensioned
    ``[device] scale_factor`` is a :class:`DataError` saying which formula needs it
    (``needed_by``, e.g. ``"D.14 (D.1.6)"``)."""
    K, urel = device_scale_factor(device, source)
    if K is None:
        raise DataError(
            source,
            "device.scale_factor",
            f"{needed_by} divides by the scale factor K ({fmt_unit(unit)}); give the device's K",
            hint=f'add scale_factor = "… {unit}" under [device]',
        )
    check_dimension(K, unit, file=source, field="device.scale_factor")
    return float(K.to(unit).magnitude), urel


def gyro_output(segment, device, *, column: str = "output", source: str | None = None):
    """The segment's gyro output column and the conversion of its samples to °/h."""
    series = segment.series(column, OUTPUT_UNITS)
    K, urel = device_scale_factor(device, source)
    conv = rate_conversion(
        series.unit, series.interval, K, scale_factor_u_rel=urel, source=segment.file or source
    )
    return series, conv

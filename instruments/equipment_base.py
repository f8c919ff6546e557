"""What every simulated instrument shares: :class:`EquipmentModel` (an instrument with its
certificate and a seed for its fixed errors) and the converters and draws its fields use."""

from __future__ import annotations

import datetime as dt
import zlib
from typing import Any, Callable

import attrs
import numpy as np
import pint

from metro.core.base.errors import DataError
from metro.core.model.campaign import Calibration, Equipment
from metro.core.base.units import parse_quantity


def q_of(dimension: str) -> Callable[[Any], pint.Quantity]:
    """attrs converter: a quantity (or its text) of ``dimension``; a bare number only if
    dimensionless."""

    def conv(v: Any) -> pint.Quantity:
        return parse_quantity(
            v, dimension=dimension, field=f"equipment parameter ({dimension or 'ratio'})"
        )

    return conv


def opt_q_of(dimension: str) -> Callable[[Any], pint.Quantity | None]:
    """attrs converter: as :func:`q_of`, ``None`` kept as ``None`` (an optional parameter)."""
    c = q_of(dimension)
    return lambda v: None if v is None else c(v)


def non_negative(inst: Any, attribute: attrs.Attribute, value: pint.Quantity) -> None:
    if value is not None and float(np.min(value.magnitude)) < 0:
        raise DataError(
            None, f"{type(inst).__name__}.{attribute.name}", f"must not be negative (got {value})"
        )


def accuracy_field(default: pint.Quantity, dimension: str) -> Any:
    """An attrs field of a model: a non-negative quantity of ``dimension`` (or its text),
    ``default`` unless given, as the accuracy parameters of the models are."""
    return attrs.field(default=default, converter=q_of(dimension), validator=non_negative)


def magnitude_in(q: pint.Quantity, unit: str) -> float:
    """The magnitude of ``q`` in ``unit``, as a float."""
    return float(q.to(unit).magnitude)


def as_float_array(q: Any, unit: str, name: str) -> np.ndarray:
    """``q`` (a quantity or its text) in ``unit`` as a float array; a DataError naming ``name``."""
    q = parse_quantity(q, dimension=unit, field=name) if not isinstance(q, pint.Quantity) else q
    try:
        return np.asarray(q.to(unit).magnitude, dtype=float)
    except pint.DimensionalityError as exc:
        raise DataError(None, name, f"expected a quantity like {unit}, got {q.units}") from exc


def fixed_rng(seed: int, *tags: Any) -> np.random.Generator:
    """A generator for an instrument's fixed errors: the same instrument (seed) and tags, the
    same draw."""
    words = [int(seed) & 0xFFFFFFFF] + [zlib.crc32(repr(t).encode()) for t in tags]
    return np.random.default_rng(words)


@attrs.frozen(kw_only=True)
class EquipmentModel:
    """Identification and calibration data common to every model.

    ``U`` is the expanded uncertainty of the certificate (relative, e.g. ``1e-5``, or absolute,
    e.g. ``"0.3 K"``) with coverage factor ``k``; ``distribution = "uniform"`` makes ``U`` a
    half-width.  ``certificate = ""`` means no calibration data are given.
    """

    id: str
    model: str = ""
    manufacturer: str = ""
    serial: str = ""
    role: str = ""
    certificate: str = ""
    U: pint.Quantity | None = attrs.field(
        default=None, converter=lambda v: uncertainty_converter(None)(v), validator=non_negative
    )
    k: float = 2.0
    due: dt.date | None = None
    lab: str = ""
    distribution: str = attrs.field(
        default="normal", validator=attrs.validators.in_(("normal", "uniform"))
    )
    seed: int = 1

    #: the role a model of this class takes unless ``role`` is given (set by each subclass)
    ROLE = ""

    def __attrs_post_init__(self) -> None:
        if self.certificate and self.U is None:
            raise DataError(
                None, f"{self.id}.U", "a certificate is given without its expanded uncertainty U"
            )

    @property
    def calibration(self) -> Calibration | None:
        if not self.certificate:
            return None
        return Calibration(
            self.certificate,
            self.U,
            k=float(self.k),
            due=self.due,
            lab=self.lab,
            distribution=self.distribution,
        )

    def properties(self) -> dict[str, Any]:
        """The accuracy parameters as equipment properties (names the procedures read)."""
        return {}

    def given(self, *names: str) -> dict[str, Any]:
        """The fields ``names`` by name, in that order, leaving out those not given (``None``):
        what :meth:`properties` states of a model with optional parameters.

        >>> EquipmentModel(id="X", model="m").given("model", "U")
        {'model': 'm'}
        """
        return {n: v for n in names if (v := getattr(self, n)) is not None}

    def equipment(self) -> Equipment:
        """The :class:`Equipment` a campaign carries for this instrument."""
        role = self.role or type(self).ROLE
        return Equipment(
            id=self.id,
            model=self.model,
            serial=self.serial,
            manufacturer=self.manufacturer,
            role=role,
            properties=self.properties(),
            calibration=self.calibration,
        )


def uncertainty_converter(dimension: str | None):
    """Converter for a calibration U: relative, or (if ``dimension`` is given) of ``dimension``."""

    def conv(v: Any) -> pint.Quantity | None:
        if v is None:
            return None
        q = parse_quantity(v, field="U")
        if dimension is not None and not q.dimensionless:
            q = parse_quantity(v, dimension=dimension, field="U")
        return q

    return conv


def simulated_lab(seed: int, certificate: str = "", U: Any = None) -> dict[str, Any]:
    """The fields of an instrument of a simulated station: calibrated in the ``"simulated"`` lab
    under ``certificate`` with expanded uncertainty ``U`` (none given: no calibration data), its
    fixed errors drawn by ``seed``.

    >>> simulated_lab(3, "SIM-CAL-0001", "1e-7")
    {'lab': 'simulated', 'seed': 3, 'certificate': 'SIM-CAL-0001', 'U': '1e-7'}
    """
    fields: dict[str, Any] = {"lab": "simulated", "seed": int(seed)}
    if certificate:
        fields |= {"certificate": certificate, "U": U}
    return fields

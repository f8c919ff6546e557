"""What a campaign is made of: the device under test, the equipment and its calibrations,
the recorded segments (a :class:`Segment` holds a *loader* supplied by a reader, never a file
handle) and the :class:`Campaign` that gathers them.  Values are ``attrs.frozen``."""

from __future__ import annotations


import datetime as dt
import math
from types import MappingProxyType
from typing import Any, Callable, Mapping, Sequence

import attrs
import numpy as np
import pint

from ..base.errors import DataError
from ..base.units import Q_, check_dimension, fmt_unit, parse_quantity, unit
from ..base.vocabulary import (Customer, Lab, People, canonical_role, customer_of, date_of, lab_of,
                               people_of)

__all__ = ['Calibration', 'Instrument', 'DeviceUnderTest', 'Equipment', 'Series', 'Segment',
           'Campaign']


def frozen_map(m: Mapping | None) -> Mapping:
    return MappingProxyType(dict(m or {}))


# --------------------------------------------------------------------------------------
# Instruments
# --------------------------------------------------------------------------------------


@attrs.frozen
class Calibration:
    """A piece of equipment's calibration data, as its certificate states it.

    ``uncertainty`` is the expanded uncertainty U (absolute, e.g. ``0.5 ″``, or relative,
    e.g. ``1e-4`` / ``100 ppm``) with coverage factor ``k``; ``distribution`` is ``normal``
    for a certificate's U, or ``uniform`` when only a maximum permissible error (a
    half-width) is known, in which case ``k`` is ignored.
    """

    #: the calibration certificate's number
    certificate: str
    #: the expanded uncertainty U the certificate states: absolute (a quantity in the
    #: equipment's unit) or relative (dimensionless, ``1e-4`` or ``100 ppm``)
    uncertainty: pint.Quantity
    #: the coverage factor of ``uncertainty`` (ignored for a ``uniform`` distribution)
    k: float = 2.0
    #: the date the calibration is due again, or None (not stated); past it, a run says the
    #: results that depend on it are not traceable
    due: dt.date | None = None
    #: the laboratory that issued the certificate
    lab: str = ""
    #: ``"normal"`` (a certificate's U with its k) or ``"uniform"`` (a maximum permissible error)
    distribution: str = "normal"

    @property
    def standard_uncertainty(self) -> pint.Quantity:
        """The standard uncertainty: U/k (normal) or the half-width/√3 (uniform)."""
        if self.distribution == "normal":
            return self.uncertainty / self.k
        return self.uncertainty / math.sqrt(3.0)

    def status(self, on: dt.date | None = None) -> str:
        """'valid until …', 'EXPIRED on …' or 'no due date' as of ``on`` (today by default)."""
        on = on or dt.date.today()
        if self.due is None:
            return f"certificate {self.certificate}, no due date stated"
        if self.due < on:
            return f"certificate {self.certificate}, EXPIRED on {self.due.isoformat()}"
        return f"certificate {self.certificate}, valid until {self.due.isoformat()}"

    def is_valid(self, on: dt.date | None = None) -> bool:
        """Whether the calibration is not past its due date on ``on`` (today by default)."""
        return self.due is None or self.due >= (on or dt.date.today())


@attrs.frozen
class Instrument:
    """A device under test or a piece of the lab's equipment (identification + properties)."""

    #: the identifier the manifest gives it (``[device] id``, ``[[equipment]] id``)
    id: str
    #: the model designation
    model: str = ""
    #: the serial number
    serial: str = ""
    #: the manufacturer
    manufacturer: str = ""
    #: further properties by name, as the manifest gives them (quantities for values with a
    #: unit: a device's ``scale_factor``, ``resolution`` …); read them with :meth:`prop`
    properties: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)

    def prop(self, name: str, dimension: str | None = None, *, source: str | None = None) -> Any:
        """A property by name, checked against ``dimension`` when given; a clear error if
        missing."""
        if name not in self.properties:
            raise DataError(source, f"{self.kind}.{name}", f"missing (needed for {self.id})")
        v = self.properties[name]
        if dimension is not None:
            check_dimension(v, dimension, file=source, field=f"{self.kind}.{name}")
        return v

    @property
    def kind(self) -> str:
        """``"device"`` or ``"equipment"``: the manifest section, in messages."""
        return "instrument"

    def describe(self) -> str:
        """Manufacturer and model (else the id), with the serial number: a text for documents."""
        from ..base.locale import join, msg

        parts = [p for p in (self.manufacturer, self.model) if p]
        text = join(" ", parts) if parts else self.id
        if self.serial:  # a message, so a document writes a simulated model name in its language
            text = msg("{text} (s/n {serial})", text=text, serial=self.serial)
        return text


@attrs.frozen
class DeviceUnderTest(Instrument):
    """The gyro (or IMU, or angle instrument) being tested.

    ``technology`` (e.g. ``laser``/``fibre``), ``application`` (e.g. ``aerospace``) and
    ``output`` (``pulse``, ``digital``, ``analog``, ``rate``) drive method selection and
    conformity in the plugins.
    """

    #: the sensing technology (``"laser"``, ``"fibre"``, ``"mems"``, ``"vibratory"`` …)
    technology: str = ""
    #: the application class the standard's limits depend on (``"aviation"``, ``"aerospace"``)
    application: str = ""
    #: the kind of output (``"pulse"``, ``"digital"``, ``"analog"``, ``"rate"``): how
    #: ``gyro_output`` turns the recorded column into a rate
    output: str = ""

    @property
    def kind(self) -> str:
        return "device"


@attrs.frozen
class Equipment(Instrument):
    """A piece of the lab's equipment with its role in the test and its calibration data."""

    #: canonical spelling (metro.core.base.vocabulary.canonical_role: ``rate-table`` →
    #: ``rate_table``)
    role: str = attrs.field(default="", converter=lambda r: canonical_role(r))
    #: its calibration data, or None (an item that needs its U then says so)
    calibration: Calibration | None = None

    @property
    def kind(self) -> str:
        """``"equipment"``."""
        return "equipment"

    def status(self, on: dt.date | None = None) -> str:
        """The calibration's :meth:`Calibration.status`, or that no calibration data were given."""
        if self.calibration is None:
            return "no calibration data given"
        return self.calibration.status(on)


# --------------------------------------------------------------------------------------
# Data: series, segments, campaigns
# --------------------------------------------------------------------------------------


@attrs.frozen
class Series:
    """A uniformly sampled column: ``data`` (a pint quantity wrapping a 1-D array, not copied)
    sampled every ``interval``, from ``source`` (file and column)."""

    #: the samples: a pint quantity wrapping a 1-D numpy array, in the column's recorded unit
    data: pint.Quantity
    #: the sample interval (a time quantity)
    interval: pint.Quantity
    #: where the samples come from: the file, or ``"segment <id>"`` for a station's segment
    source: str = ""
    #: the column's name
    column: str = ""

    @property
    def n(self) -> int:
        """The number of samples."""
        return int(np.shape(self.data.magnitude)[0])

    @property
    def duration(self) -> pint.Quantity:
        """The record's duration, ``n`` × ``interval``."""
        return self.interval * self.n

    @property
    def unit(self) -> pint.Unit:
        """The samples' unit."""
        return self.data.units


@attrs.frozen(eq=False)
class Segment:
    """One measurement segment of a campaign: its conditions and its samples.

    ``loader`` returns ``{column: (array, unit_text)}`` when called; it is supplied by a
    reader (files) or by a station (simulation) and is called at most once per run.  A
    procedure reads a column with :meth:`series`, which checks its unit.
    """

    #: the segment's id, unique in the campaign: the ``segment`` of the step that recorded it
    id: str
    #: what was recorded (``"static"``, ``"rate-revolutions"`` …): the step's ``kind``, which
    #: procedures find segments by (``Campaign.find_segments(kind, …)``)
    kind: str
    #: the conditions it was recorded under, by name (``orientation``, ``rate``,
    #: ``temperature`` …; text such as ``"10 deg/s"`` or quantities); read with :meth:`condition`
    conditions: Mapping[str, Any] = attrs.field(converter=frozen_map)
    #: the sample interval (a time quantity), or None when the segment has no fixed interval
    interval: pint.Quantity | None
    #: the samples file (as the manifest names it), or None for a station's segment in memory
    file: str | None = None
    #: the SHA-256 of the raw data (hex), or None: the reader computes it while loading
    sha256: str | None = None
    #: units the manifest declares per column (checked against the file's header), by column
    declared_units: Mapping[str, str] = attrs.field(factory=dict, converter=frozen_map)
    #: a function of no argument returning ``{column: (1-D numpy array, unit text)}`` — e.g.
    #: ``lambda: {"output": (samples, "deg/h")}``; None for a segment without data
    loader: Callable[[], Mapping[str, tuple[np.ndarray, str]]] | None = None
    #: when the record's first sample was taken (time-zone aware), or None: the manifest's optional
    #: ``started`` (docs/data-format.md); a procedure that differences records uses it for drift
    started: dt.datetime | None = attrs.field(default=None, validator=attrs.validators.optional(
        attrs.validators.instance_of(dt.datetime)))
    _cache: dict = attrs.field(factory=dict, init=False, repr=False)

    @started.validator
    def _started_aware(self, attribute, value) -> None:
        if value is not None and value.utcoffset() is None:
            raise DataError(self.file, f"segments.{self.id}.started",
                            f"{value.isoformat()} has no UTC offset; the recording time must say "
                            "its time zone")

    def condition(self, name: str, dimension: str | None = None) -> Any:
        """The condition ``name`` as recorded, or parsed as a quantity checked against
        ``dimension`` when given; a :class:`DataError` naming the segment when it is missing."""
        if name not in self.conditions:
            raise DataError(self.file, f"segments.{self.id}.conditions.{name}", "missing condition",
                            hint=f"add '{name} = \"…\"' under [segments.conditions] of segment "
                            f"{self.id!r}")
        v = self.conditions[name]
        if dimension is not None:
            v = parse_quantity(v, dimension=dimension, file=self.file,
                               field=f"segments.{self.id}.conditions.{name}")
        return v

    def columns(self) -> Mapping[str, tuple[np.ndarray, str]]:
        """The columns as the loader gives them, except a ratiometric one (``mV/V``), which is
        turned into mV with the segment's ``supply`` voltage at this boundary, so every procedure
        reads a voltage (docs/data-format.md, "Ratiometric outputs")."""
        if "cols" not in self._cache:
            self._cache["cols"] = self._ratiometric(self.recorded_columns())
        return self._cache["cols"]

    def recorded_columns(self) -> Mapping[str, tuple[np.ndarray, str]]:
        """The columns exactly as recorded (a ratiometric column still in mV/V): what a writer of
        the campaign's files keeps."""
        if "raw" not in self._cache:
            if self.loader is None:
                raise DataError(self.file, f"segments.{self.id}", "segment has no data")
            import time

            t0 = time.perf_counter()
            self._cache["raw"] = self.loader()
            self._cache["load_seconds"] = time.perf_counter() - t0
        return self._cache["raw"]

    def _ratiometric(self, cols: Mapping[str, tuple[np.ndarray,
                                                    str]]) -> Mapping[str, tuple[np.ndarray, str]]:
        from ..base.units import is_voltage_ratio

        out = dict(cols)
        for name, (arr, utext) in cols.items():
            if not is_voltage_ratio(utext):
                continue
            if "supply" not in self.conditions:
                raise DataError(self.file, name,
                                f"column {name!r} is ratiometric ({utext}); turning it into a "
                                "voltage needs the supply voltage it is referred to",
                                hint="add supply_voltage = \"5 V\" under [device], or supply = \"5 "
                                "V\" to the "
                                     f"conditions of segment {self.id!r}")
            v = self.condition("supply", "V")
            if not float(v.magnitude) > 0:
                raise DataError(self.file, f"segments.{self.id}.conditions.supply",
                                f"{v} is not a positive voltage")
            out[name] = (np.asarray(arr, dtype=float) * float((Q_(1.0,
                                                                  utext) * v).to("mV").magnitude),
                         "mV")
        return out

    @property
    def load_seconds(self) -> float:
        """Wall time spent reading this segment's samples (0 if not read)."""
        return float(self._cache.get("load_seconds", 0.0))

    def digest(self) -> str | None:
        """SHA-256 of the raw data: as given, or as computed by the reader while loading."""
        if self.sha256:
            return self.sha256
        # the reader's columns carry it (a ratiometric conversion copies them)
        for key in ("raw", "cols"):
            if key in self._cache and getattr(self._cache[key], "sha256", None):
                return self._cache[key].sha256
        return None

    def series(self, column: str, dimension: str | Sequence[str]) -> Series:
        """The named column as a :class:`Series`, its header unit checked against ``dimension``
        (one unit or a list of acceptable ones)."""
        cols = self.columns()
        if column not in cols:
            raise DataError(
                self.file, column,
                f"segment {self.id!r} has no column {column!r} (columns: "
                f"{', '.join(cols) or 'none'})",
            )
        arr, utext = cols[column]
        try:
            u = unit(utext)
        except Exception as exc:
            raise DataError(self.file, column,
                            f"cannot read unit {utext!r} in the header ({exc})") from exc
        dims = [dimension] if isinstance(dimension, str) else list(dimension)
        errors = []
        for d in dims:
            try:
                check_dimension(Q_(1.0, u), d, file=self.file, field=column)
                break
            except DataError as exc:
                errors.append(exc)
        else:
            raise DataError(
                self.file, column,
                f"header unit {fmt_unit(u)} is not one of the accepted kinds "
                f"({', '.join(fmt_unit(d) for d in dims)})",
            )
        declared = self.declared_units.get(column)
        # the header as recorded (mV/V before its conversion)
        rec_text = self.recorded_columns()[column][1]
        if declared is not None and unit(declared) != unit(rec_text):
            raise DataError(
                self.file, column,
                f"the header says [{rec_text}] but the manifest declares [{declared}]; "
                "metro does not guess which is right",
                hint="correct the header or the manifest's units table",
            )
        if self.interval is None:
            raise DataError(self.file, f"segments.{self.id}.sample_interval",
                            "missing sample interval")
        return Series(Q_(arr, u), self.interval, source=self.file or f"segment {self.id}",
                      column=column)


@attrs.frozen(eq=False)
class Campaign:
    """Everything measured in one test campaign on one device.

    A manifest (``metro run --data``) or a station's ``acquire`` (docs/tutorial-station.md)
    makes one; procedures read it.  A simulated station fills ``truth`` and ``expected``: after
    a run metro compares each result whose metric key is in ``expected`` with that value
    (``truth_checks`` in ``--json``, "declared truth recovered within U" in the terminal).
    """

    #: the campaign's id (``[campaign] id``; ``"SIMULATED"`` for the built-in stations)
    id: str
    #: the device under test
    device: DeviceUnderTest
    #: the lab's equipment used, each with its role and calibration (see ``equipment_for``)
    equipment: tuple[Equipment, ...] = attrs.field(converter=tuple)
    #: the ambient conditions by name (``temperature``, ``humidity`` …; quantities or text)
    environment: Mapping[str, Any] = attrs.field(converter=frozen_map)
    #: the test site by name (``latitude``, ``latitude_uncertainty``, ``gravity`` …); read with
    #: :meth:`site_value`, which checks the dimension
    site: Mapping[str, Any] = attrs.field(converter=frozen_map)
    #: the recorded segments (each step of a sequence gives one)
    segments: tuple[Segment, ...] = attrs.field(converter=tuple)
    #: where the campaign comes from: the manifest's path, or a station's name in words
    #: (``"simulated station"``); :class:`DataError` messages name it
    source: str = ""
    #: whether the data are simulated: documents then carry the SIMULATED banner on every page
    simulated: bool = False
    #: a simulated station's declared truth — the parameters it simulated the device with
    #: (``"bias B0"``: ``Q_(0.12, "deg/h")`` …), by name in words; printed by
    #: ``metro run --verbose`` and in the report; empty for measured data
    truth: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
    #: the manifest's ``[campaign]`` table as written (people, lab, customer, dates: read them
    #: through :attr:`people`, :attr:`lab`, :attr:`customer`, :attr:`measurement_date`)
    meta: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
    #: on a simulated campaign: by metric key (``Metric.key``), the value a faultless evaluation
    #: of the item gives on the simulated device without its noise (from the station's truth and
    #: the conditions it simulated, not from the noisy recorded samples) — a quantity of the
    #: metric's dimension; metro checks each result against it within the result's U (met on
    #: about 95 % of seeds at k = 2).  Empty for measured data
    expected: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
    #: the manifest's ``[specification]`` table as written (limits as text; see core.conformity)
    specification: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
    #: SHA-256 of the manifest's bytes (empty for a campaign a station has just acquired)
    manifest_sha256: str = ""
    #: what reading the manifest noticed without refusing it (deprecated spellings, unknown keys)
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)

    #: records that are not sampled signals — the manifest's further sections (``[inspection]``,
    #: ``[[environmental_tests]]``, ``[reliability]`` …) as written (text with units, numbers,
    #: tables), by section name; the plugin whose items read a section validates it
    records: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)

    # the typed view of [campaign] (metro.core.base.vocabulary) that documents and the register read
    @property
    def people(self) -> People:
        """Who measured (``operator``), checked and approved, from ``[campaign]``."""
        return people_of(self.meta)

    @property
    def lab(self) -> Lab:
        """The laboratory (``lab``, ``lab_address``, ``location``) from ``[campaign]``."""
        return lab_of(self.meta)

    @property
    def customer(self) -> Customer:
        """The customer (``customer``, ``customer_address``) from ``[campaign]``."""
        return customer_of(self.meta)

    @property
    def measurement_date(self) -> dt.date | None:
        """``[campaign] measurement_date`` (None when the manifest does not give it)."""
        return date_of(self.meta, "measurement_date")

    @property
    def date_received(self) -> dt.date | None:
        """``[campaign] date_received`` (None when the manifest does not give it)."""
        return date_of(self.meta, "date_received")

    def find_segments(self, kind: str | None = None, **conditions: Any) -> list[Segment]:
        """The segments of ``kind`` (any kind when None) whose conditions equal ``conditions``
        (compared as text: ``orientation="IRA up"``), in campaign order."""
        out = []
        for s in self.segments:
            if kind is not None and s.kind != kind:
                continue
            if all(str(s.conditions.get(k)) == str(v) for k, v in conditions.items()):
                out.append(s)
        return out

    def equipment_for(self, role: str) -> Equipment | None:
        """The equipment with ``role`` (any spelling :func:`canonical_role` accepts), or None;
        declare the role in the procedure's ``equipment``."""
        role = canonical_role(role)
        for e in self.equipment:
            if e.role == role:
                return e
        return None

    def site_value(self, name: str, dimension: str) -> pint.Quantity:
        """The site's ``name`` as a quantity checked against ``dimension``; a :class:`DataError`
        naming ``[site]`` when it is missing."""
        if name not in self.site:
            raise DataError(self.source, f"site.{name}", "missing",
                            hint=f"add '{name} = \"…\"' under [site]")
        return parse_quantity(self.site[name], dimension=dimension, file=self.source,
                              field=f"site.{name}")

    def data_files(self) -> list[tuple[str, str]]:
        """(file, sha256) of every raw data file used by the campaign."""
        return [(s.file, s.digest()) for s in self.segments if s.file and s.digest()]


# --------------------------------------------------------------------------------------
# Procedures and their results
# --------------------------------------------------------------------------------------



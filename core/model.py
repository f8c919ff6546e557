"""metro's core abstractions: instruments, campaigns, procedures, metrics and results.

Values are ``attrs.frozen`` (readings, results, calibration data); the pieces that carry
state while a run is under way (:class:`RunContext`) are ``attrs.define``.  I/O lives
elsewhere: a :class:`Segment` holds a *loader* supplied by a reader, never a file handle.
"""

from __future__ import annotations

import abc
import datetime as dt
import math
from types import MappingProxyType
from typing import Any, Callable, ClassVar, Mapping, Sequence

import attrs
import numpy as np
import pint

from .budget import UncertaintyBudget, report_pair
from .errors import DataError, ProcedureError
from .units import Q_, check_dimension, difference_unit, fmt_unit, parse_quantity, unit
from .vocabulary import Customer, Lab, People, canonical_role, customer_of, date_of, lab_of, people_of

__all__ = [
    "Calibration",
    "Instrument",
    "DeviceUnderTest",
    "Equipment",
    "Series",
    "Segment",
    "Campaign",
    "Metric",
    "Result",
    "PlotSpec",
    "TableSpec",
    "Outcome",
    "SegmentRequirement",
    "EquipmentRequirement",
    "Applicability",
    "Option",
    "Step",
    "Procedure",
    "RunContext",
]


def _frozen_map(m: Mapping | None) -> Mapping:
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

    certificate: str
    uncertainty: pint.Quantity
    k: float = 2.0
    due: dt.date | None = None
    lab: str = ""
    distribution: str = "normal"

    @property
    def standard_uncertainty(self) -> pint.Quantity:
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
        return self.due is None or self.due >= (on or dt.date.today())


@attrs.frozen
class Instrument:
    """A device under test or a piece of the lab's equipment (identification + properties)."""

    id: str
    model: str = ""
    serial: str = ""
    manufacturer: str = ""
    properties: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)

    def prop(self, name: str, dimension: str | None = None, *, source: str | None = None) -> Any:
        """A property by name, checked against ``dimension`` when given; a clear error if missing."""
        if name not in self.properties:
            raise DataError(source, f"{self.kind}.{name}", f"missing (needed for {self.id})")
        v = self.properties[name]
        if dimension is not None:
            check_dimension(v, dimension, file=source, field=f"{self.kind}.{name}")
        return v

    @property
    def kind(self) -> str:
        return "instrument"

    def describe(self) -> str:
        from .locale import join, msg

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

    technology: str = ""
    application: str = ""
    output: str = ""

    @property
    def kind(self) -> str:
        return "device"


@attrs.frozen
class Equipment(Instrument):
    """A piece of the lab's equipment with its role in the test and its calibration data."""

    #: canonical spelling (metro.core.vocabulary.canonical_role: ``rate-table`` → ``rate_table``)
    role: str = attrs.field(default="", converter=lambda r: canonical_role(r))
    calibration: Calibration | None = None

    @property
    def kind(self) -> str:
        return "equipment"

    def status(self, on: dt.date | None = None) -> str:
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

    data: pint.Quantity
    interval: pint.Quantity
    source: str = ""
    column: str = ""

    @property
    def n(self) -> int:
        return int(np.shape(self.data.magnitude)[0])

    @property
    def duration(self) -> pint.Quantity:
        return self.interval * self.n

    @property
    def unit(self) -> pint.Unit:
        return self.data.units


@attrs.frozen(eq=False)
class Segment:
    """One measurement segment of a campaign: its conditions and its samples.

    ``loader`` returns ``{column: (array, unit_text)}`` when called; it is supplied by a
    reader (files) or by a station (simulation) and is called at most once per run.
    """

    id: str
    kind: str
    conditions: Mapping[str, Any] = attrs.field(converter=_frozen_map)
    interval: pint.Quantity | None
    file: str | None = None
    sha256: str | None = None
    declared_units: Mapping[str, str] = attrs.field(factory=dict, converter=_frozen_map)
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
                            f"{value.isoformat()} has no UTC offset; the recording time must say its time zone")

    def condition(self, name: str, dimension: str | None = None) -> Any:
        if name not in self.conditions:
            raise DataError(self.file, f"segments.{self.id}.conditions.{name}", "missing condition",
                            hint=f"add '{name} = \"…\"' under [segments.conditions] of segment {self.id!r}")
        v = self.conditions[name]
        if dimension is not None:
            v = parse_quantity(v, dimension=dimension, file=self.file, field=f"segments.{self.id}.conditions.{name}")
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

    def _ratiometric(self, cols: Mapping[str, tuple[np.ndarray, str]]) -> Mapping[str, tuple[np.ndarray, str]]:
        from .units import is_voltage_ratio

        out = dict(cols)
        for name, (arr, utext) in cols.items():
            if not is_voltage_ratio(utext):
                continue
            if "supply" not in self.conditions:
                raise DataError(self.file, name, f"column {name!r} is ratiometric ({utext}); turning it into a "
                                "voltage needs the supply voltage it is referred to",
                                hint="add supply_voltage = \"5 V\" under [device], or supply = \"5 V\" to the "
                                     f"conditions of segment {self.id!r}")
            v = self.condition("supply", "V")
            if not float(v.magnitude) > 0:
                raise DataError(self.file, f"segments.{self.id}.conditions.supply", f"{v} is not a positive voltage")
            out[name] = (np.asarray(arr, dtype=float) * float((Q_(1.0, utext) * v).to("mV").magnitude), "mV")
        return out

    @property
    def load_seconds(self) -> float:
        """Wall time spent reading this segment's samples (0 if not read)."""
        return float(self._cache.get("load_seconds", 0.0))

    def digest(self) -> str | None:
        """SHA-256 of the raw data: as given, or as computed by the reader while loading."""
        if self.sha256:
            return self.sha256
        for key in ("raw", "cols"):  # the reader's columns carry it (a ratiometric conversion copies them)
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
                f"segment {self.id!r} has no column {column!r} (columns: {', '.join(cols) or 'none'})",
            )
        arr, utext = cols[column]
        try:
            u = unit(utext)
        except Exception as exc:
            raise DataError(self.file, column, f"cannot read unit {utext!r} in the header ({exc})") from exc
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
        rec_text = self.recorded_columns()[column][1]  # the header as recorded (mV/V before its conversion)
        if declared is not None and unit(declared) != unit(rec_text):
            raise DataError(
                self.file, column,
                f"the header says [{rec_text}] but the manifest declares [{declared}]; "
                "metro does not guess which is right",
                hint="correct the header or the manifest's units table",
            )
        if self.interval is None:
            raise DataError(self.file, f"segments.{self.id}.sample_interval", "missing sample interval")
        return Series(Q_(arr, u), self.interval, source=self.file or f"segment {self.id}", column=column)


@attrs.frozen(eq=False)
class Campaign:
    """Everything measured in one test campaign on one device."""

    id: str
    device: DeviceUnderTest
    equipment: tuple[Equipment, ...] = attrs.field(converter=tuple)
    environment: Mapping[str, Any] = attrs.field(converter=_frozen_map)
    site: Mapping[str, Any] = attrs.field(converter=_frozen_map)
    segments: tuple[Segment, ...] = attrs.field(converter=tuple)
    source: str = ""  # manifest path, or "simulated station"
    simulated: bool = False
    truth: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)
    meta: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)
    #: on a simulated campaign: what an ideal evaluation gives, by metric key (a quantity)
    expected: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)
    #: the manifest's ``[specification]`` table as written (limits as text; see core.conformity)
    specification: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)
    #: SHA-256 of the manifest's bytes (empty for a campaign a station has just acquired)
    manifest_sha256: str = ""
    #: what reading the manifest noticed without refusing it (deprecated spellings, unknown keys)
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)

    #: records that are not sampled signals — the manifest's further sections (``[inspection]``,
    #: ``[[environmental_tests]]``, ``[reliability]`` …) as written (text with units, numbers,
    #: tables), by section name; the plugin whose items read a section validates it
    records: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)

    # the typed view of [campaign] (metro.core.vocabulary) that documents and the register read
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
        return customer_of(self.meta)

    @property
    def measurement_date(self) -> dt.date | None:
        """``[campaign] measurement_date`` (None when the manifest does not give it)."""
        return date_of(self.meta, "measurement_date")

    @property
    def date_received(self) -> dt.date | None:
        return date_of(self.meta, "date_received")

    def find_segments(self, kind: str | None = None, **conditions: Any) -> list[Segment]:
        out = []
        for s in self.segments:
            if kind is not None and s.kind != kind:
                continue
            if all(str(s.conditions.get(k)) == str(v) for k, v in conditions.items()):
                out.append(s)
        return out

    def equipment_for(self, role: str) -> Equipment | None:
        role = canonical_role(role)
        for e in self.equipment:
            if e.role == role:
                return e
        return None

    def site_value(self, name: str, dimension: str) -> pint.Quantity:
        if name not in self.site:
            raise DataError(self.source, f"site.{name}", "missing", hint=f"add '{name} = \"…\"' under [site]")
        return parse_quantity(self.site[name], dimension=dimension, file=self.source, field=f"site.{name}")

    def data_files(self) -> list[tuple[str, str]]:
        """(file, sha256) of every raw data file used by the campaign."""
        return [(s.file, s.digest()) for s in self.segments if s.file and s.digest()]


# --------------------------------------------------------------------------------------
# Procedures and their results
# --------------------------------------------------------------------------------------


@attrs.frozen
class Metric:
    """A declared output of a procedure: what it is, its unit, and where its formula is."""

    key: str
    name: str
    symbol: str
    unit: str
    clause: str
    equation: str = ""
    description: str = ""

    @property
    def reference(self) -> str:
        """Where the formula is: the clause, and the equation when there is one (``D.5.1.3 (D.40)``)."""
        return f"{self.clause} ({self.equation})" if self.equation else self.clause


#: a bound as the terminal, the documents and the verdicts state it (:attr:`Result.bound`): the true
#: value is at least (``lower``) or at most (``upper``) the value shown
BOUND_SIGNS = {"lower": "≥", "upper": "≤"}


@attrs.frozen
class Result:
    """A metric's value with its standard uncertainty and budget."""

    metric: Metric
    value: pint.Quantity
    u: pint.Quantity | None = None
    budget: UncertaintyBudget | None = None
    note: str = ""
    #: False when the data show the method's model does not hold (misfit, unresolved response,
    #: quantization the budget cannot cover): the value is shown but not reported as a result.
    reportable: bool = True
    #: why the result is not reportable (required when ``reportable`` is False)
    reason: str = ""
    #: whether the earth's rate is contained in the value: "included", "removed", "not applicable"
    #: or "" (not stated by the procedure)
    earth_rate: str = ""
    #: for a result that is not reportable as a value but bounds the quantity (a reading beyond the
    #: instrument's range): "lower" — the true value is at least ``value``; "upper" — at most; "" — no
    #: bound (stated with :data:`BOUND_SIGNS`)
    bound: str = attrs.field(default="", validator=attrs.validators.in_(("", "lower", "upper")))

    @property
    def bound_sign(self) -> str:
        """How a bound is stated beside its value: ``≥`` (lower), ``≤`` (upper), ``""`` (a value).

        >>> BOUND_SIGNS["upper"], BOUND_SIGNS.get("", "")
        ('≤', '')
        """
        return BOUND_SIGNS.get(self.bound, "")

    def __attrs_post_init__(self) -> None:
        check_dimension(self.value, self.metric.unit, field=self.metric.key)
        if not self.reportable and not self.reason.strip():
            raise ProcedureError(f"{self.metric.key}: a result marked not reportable needs a reason")
        if not np.all(np.isfinite(np.asarray(self.value.magnitude, dtype=float))):
            raise ProcedureError(f"{self.metric.key}: result is not finite ({self.value})")

    @property
    def k(self) -> float | None:
        return self.budget.k if self.budget is not None else None

    @property
    def U(self) -> pint.Quantity | None:
        if self.budget is not None:
            return self.budget.expanded.to(difference_unit(self.metric.unit))  # °C: U in Δ°C
        return None

    def reported(self) -> tuple[str, str | None]:
        """(value text, U text) rounded as JJF 1059.1 asks, in the metric's unit."""
        v = float(self.value.to(self.metric.unit).magnitude)
        if self.U is None:
            if self.u is not None and float(self.u.magnitude) > 0:
                # no expanded U (no budget): the value still keeps the digits its u supports
                try:
                    u = float(self.u.to(difference_unit(self.metric.unit)).magnitude)
                except pint.errors.PintError:
                    u = float(self.u.to(self.metric.unit).magnitude)
                return report_pair(v, u)[0].text, None
            return f"{v:.6g}", None
        mode = self.budget.round_mode if self.budget else "half-even"
        rv, rU = report_pair(v, float(self.U.magnitude), mode=mode)
        return rv.text, rU.text

    def as_dict(self) -> dict:
        unit_ = self.metric.unit
        val = self.value.to(unit_).magnitude
        vtext, Utext = self.reported()
        return {
            "key": self.metric.key,
            "quantity": self.metric.name,
            "symbol": self.metric.symbol,
            "clause": self.metric.clause,
            "equation": self.metric.equation,
            "value": float(val),
            "unit": fmt_unit(unit_),
            "u": None if self.u is None else float(self.u.to(difference_unit(unit_)).magnitude),
            "U": None if self.U is None else float(self.U.magnitude),
            "k": self.k,
            "nu_eff": None if self.budget is None or math.isinf(self.budget.nu_eff) else self.budget.nu_eff,
            "reported": {"value": vtext, "U": Utext},
            "note": self.note,
            "reportable": self.reportable,
            "reason": self.reason or None,
            "earth_rate": self.earth_rate or None,
            "bound": self.bound or None,
        }


@attrs.frozen
class PlotSpec:
    """Data for one figure; reports render it (matplotlib), procedures only describe it."""

    name: str
    title: str
    xlabel: str
    ylabel: str
    series: tuple[Mapping[str, Any], ...] = attrs.field(converter=tuple)  # {label, x, y, style, yerr}
    logx: bool = False
    logy: bool = False


@attrs.frozen
class TableSpec:
    """A supplementary table (e.g. B_s(τ_k) per level)."""

    name: str
    title: str
    header: tuple[str, ...] = attrs.field(converter=tuple)
    rows: tuple[tuple[Any, ...], ...] = attrs.field(converter=lambda rs: tuple(tuple(r) for r in rs))


@attrs.frozen
class Outcome:
    """What one procedure produced from one campaign."""

    standard: str
    item: str
    title: str
    clause: str
    results: tuple[Result, ...] = attrs.field(converter=tuple)
    plots: tuple[PlotSpec, ...] = attrs.field(default=(), converter=tuple)
    tables: tuple[TableSpec, ...] = attrs.field(default=(), converter=tuple)
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    segments: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    options: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)

    @property
    def id(self) -> str:
        return f"{self.standard}:{self.item}"

    def result(self, key: str) -> Result:
        for r in self.results:
            if r.metric.key == key:
                return r
        raise KeyError(key)


@attrs.frozen
class SegmentRequirement:
    """What data a procedure needs: segments of ``kind`` with these conditions and columns."""

    kind: str
    description: str
    conditions: Mapping[str, str] = attrs.field(factory=dict, converter=_frozen_map)  # name -> unit
    columns: Mapping[str, tuple[str, ...]] = attrs.field(factory=dict, converter=_frozen_map)  # name -> accepted units
    min_duration: pint.Quantity | None = None
    min_count: int = 1
    #: requirements of one item that share a non-empty tag are alternatives: data for any one of
    #: them suffice (GB/T 45570 D.3 takes the sweep of the angle method or of the rate method)
    alternative: str = ""


@attrs.frozen
class EquipmentRequirement:
    """Equipment an item uses, found by ``role`` (canonical spelling, metro.core.vocabulary).

    ``required``: the item refuses a campaign that does not list it (an error naming the role);
    an optional one that is absent is a note row in the item's budgets.  ``calibration``: the
    kinds of unit its calibration U may be given in (``""`` relative, else a unit such as
    ``"s"``, ``"arcsec"``); a U of another kind is an error naming the equipment and the role,
    never a budget row dropped without a word.  Empty: any kind (the item does not use U).
    ``noted``: False where the item itself covers an absent optional role (a bound the standard
    states enters the budget instead), so no note row says its uncertainty is missing.  Every
    role an item looks up is declared: the declared roles are the equipment a report lists."""

    role: str = attrs.field(converter=lambda r: canonical_role(r))
    description: str = ""
    required: bool = False
    calibration: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    noted: bool = True


@attrs.frozen
class Applicability:
    """Whether an item applies to a device (``metro run --all``, series), and why in words."""

    applies: bool
    reason: str = ""


@attrs.frozen
class Option:
    """An item option (the standard's '除另有规定外' values), with its unit and default."""

    name: str
    default: Any
    unit: str | None
    description: str
    #: the least value a count (an option whose default is a whole number) may take; 1 if not given
    minimum: int | None = attrs.field(default=None, kw_only=True)
    #: the largest; 10 000 if not given (a typo such as frequencies=1e9 must not try to allocate
    #: a billion segments)
    maximum: int | None = attrs.field(default=None, kw_only=True)

    def parse(self, value: Any) -> Any:
        if self.unit is None:
            if isinstance(self.default, (bool, int, float)) and value is not self.default:
                # a count or a flag given as text on the command line: its default's type, or a clear error
                from .options import convert_value

                value = convert_value("this item", f"option {self.name}", value, self.default)
            if isinstance(self.default, int) and not isinstance(self.default, bool):
                least = 1 if self.minimum is None else self.minimum
                most = 10_000 if self.maximum is None else self.maximum
                if not least <= value <= most:
                    raise DataError(None, f"option {self.name}", f"{value} is outside {least} … {most}",
                                    hint=f"{self.description} (default {self.default})")
            return value
        return parse_quantity(value, dimension=self.unit, field=f"option {self.name}")


#: a step whose kind starts with this produces records (:attr:`Campaign.records`), not a segment
RECORD_KIND_PREFIX = "record:"


@attrs.frozen
class Step:
    """One step of a test sequence: acquire a segment under these conditions (or, for a kind
    ``record:<section>``, take down a record — an inspection, a test done elsewhere — in that
    section of :attr:`Campaign.records`)."""

    segment: str
    kind: str
    description: str
    duration: pint.Quantity
    interval: pint.Quantity
    conditions: Mapping[str, Any] = attrs.field(factory=dict, converter=_frozen_map)
    warmup: pint.Quantity | None = None

    @property
    def is_record(self) -> bool:
        """Whether the step takes down a record rather than acquiring a segment."""
        return self.kind.startswith(RECORD_KIND_PREFIX)


@attrs.define
class RunContext:
    """State of one run: options, the progress reporter, lifecycle hooks, the clock."""

    options: dict[str, Any] = attrs.field(factory=dict)
    progress: Callable[[str, float, float], None] | None = None
    today: dt.date = attrs.field(factory=dt.date.today)

    def report_progress(self, task: str, done: float, total: float) -> None:
        if self.progress is not None:
            self.progress(task, done, total)


class Procedure(abc.ABC):
    """One calibration/test item of one standard (e.g. ``gbt45570:D.5.6``).

    Subclasses declare, as class attributes, the item's id, clause, title, the metrics it
    produces, the data and equipment it needs, its options, and implement
    :meth:`sequence` (what to measure) and :meth:`evaluate` (formulas → results + budgets).
    """

    standard: ClassVar[str]
    item: ClassVar[str]
    title: ClassVar[str]
    clause: ClassVar[str]
    metrics: ClassVar[tuple[Metric, ...]] = ()
    requires: ClassVar[tuple[SegmentRequirement, ...]] = ()
    equipment: ClassVar[tuple[EquipmentRequirement, ...]] = ()
    options: ClassVar[tuple[Option, ...]] = ()
    #: the registered station that runs this item when no data is given
    station: ClassVar[str] = "simulated"
    #: the record sections (:attr:`Campaign.records`) the item reads
    record_sections: ClassVar[tuple[str, ...]] = ()

    @classmethod
    def missing_records(cls, campaign: Campaign) -> str:
        """What records the item needs and ``campaign`` lacks, in words ('' if none); items
        reading part of a section override this to look deeper."""
        return ", ".join(f"[{s}]" for s in cls.record_sections if s not in campaign.records)

    @classmethod
    def qualified_id(cls) -> str:
        return f"{cls.standard}:{cls.item}"

    @classmethod
    def applies_to(cls, device: DeviceUnderTest | None) -> Applicability:
        """Whether this item applies to ``device`` (``None``: not known yet) when a whole
        standard or a series is run.  Every item applies unless a subclass says otherwise; a
        plugin can also decide for items it does not own with ``metro_item_applicability``."""
        return Applicability(True, "")

    @classmethod
    def option_values(cls, given: Mapping[str, Any] | None) -> dict[str, Any]:
        """Defaults overlaid with ``given`` (parsed and unit-checked); unknown names are errors."""
        given = dict(given or {})
        known = {o.name: o for o in cls.options}
        unknown = sorted(set(given) - set(known))
        if unknown:
            raise ProcedureError(
                f"{cls.qualified_id()}: unknown option(s) {', '.join(unknown)}; "
                f"this item takes: {', '.join(known) or 'no options'}"
            )
        out = {}
        for name, opt in known.items():
            out[name] = opt.parse(given[name]) if name in given else opt.parse(opt.default)
        return out

    @abc.abstractmethod
    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        """The test sequence: the segments to acquire, in order."""

    @abc.abstractmethod
    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        """Compute the item's results (with budgets) from ``campaign``."""

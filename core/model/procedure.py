"""A test item as code: :class:`Procedure` (what to measure and how to evaluate it), its
requirements on segments and equipment, its options, the :class:`Step` list a station
records and the :class:`RunContext` of one run (``attrs.define``: it carries state)."""

from __future__ import annotations


import abc
import datetime as dt
from typing import Any, Callable, ClassVar, Mapping

import attrs
import pint

from ..base.errors import DataError, ProcedureError
from ..base.units import parse_quantity
from ..base.vocabulary import canonical_role
from .campaign import frozen_map, DeviceUnderTest, Campaign
from .results import Metric, Outcome

__all__ = ['SegmentRequirement', 'EquipmentRequirement', 'Applicability', 'Option', 'RECORD_KIND_PREFIX', 'Step', 'RunContext', 'Procedure']


@attrs.frozen
class SegmentRequirement:
    """What data a procedure needs: segments of ``kind`` with these conditions and columns."""

    kind: str
    description: str
    conditions: Mapping[str, str] = attrs.field(factory=dict, converter=frozen_map)  # name -> unit
    columns: Mapping[str, tuple[str, ...]] = attrs.field(factory=dict, converter=frozen_map)  # name -> accepted units
    min_duration: pint.Quantity | None = None
    min_count: int = 1
    #: requirements of one item that share a non-empty tag are alternatives: data for any one of
    #: them suffice (GB/T 45570 D.3 takes the sweep of the angle method or of the rate method)
    alternative: str = ""


@attrs.frozen
class EquipmentRequirement:
    """Equipment an item uses, found by ``role`` (canonical spelling, metro.core.base.vocabulary).

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
                from ..base.options import convert_value

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
    conditions: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
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

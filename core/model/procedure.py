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

__all__ = ['SegmentRequirement', 'EquipmentRequirement', 'Applicability', 'Option',
           'RECORD_KIND_PREFIX', 'Step', 'RunContext', 'Procedure']


@attrs.frozen
class SegmentRequirement:
    """What data a procedure needs: segments of ``kind`` with these conditions and columns."""

    #: the segment kind needed (``Segment.kind``, the ``kind`` of the item's steps)
    kind: str
    #: what the segment is, in words (printed when the campaign has none)
    description: str
    #: the conditions such a segment states, name → the unit they are in (``""``: text)
    conditions: Mapping[str, str] = attrs.field(factory=dict, converter=frozen_map)
    #: the columns it must have, name → the accepted units (any unit of one of these kinds,
    #: e.g. ``OUTPUT_UNITS``): a campaign without them is refused before evaluation
    columns: Mapping[str, tuple[str, ...]] = attrs.field(factory=dict, converter=frozen_map)
    #: the least record length the method needs, or None (documentation: the item checks it)
    min_duration: pint.Quantity | None = None
    #: how many such segments the method needs (documentation: the item checks it)
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

    #: the equipment's role (``"rate_table"``, ``"dmm"``; any spelling canonical_role accepts)
    role: str = attrs.field(converter=lambda r: canonical_role(r))
    #: what the item uses it for, in words (in messages and note rows)
    description: str = ""
    #: the item refuses a campaign without it (else: a note row in the item's budgets)
    required: bool = False
    #: the kinds of unit its calibration U may be given in (``""`` relative, ``"arcsec"`` …);
    #: empty: any kind
    calibration: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: False when the item covers an absent optional role itself (no "missing" note row)
    noted: bool = True


@attrs.frozen
class Applicability:
    """Whether an item applies to a device (``metro run --all``, series), and why in words."""

    #: whether the item runs for the device
    applies: bool
    #: why, in words (printed and reported; a :func:`msg` is translated)
    reason: str = ""


@attrs.frozen
class Option:
    """An item option (the standard's '除另有规定外' values), with its unit and default.

    Given on the command line as ``-o name=value``; ``Procedure.option_values`` parses it.
    """

    #: the option's name (``-o name=value``)
    name: str
    #: the value when none is given: text with a unit (``"5 min"``) for an option with a unit,
    #: else a number, a whole number (a count), a bool or a text
    default: Any
    #: the unit (kind) a value must have (``"s"``): values are parsed to quantities and
    #: checked; None for a unitless option (its value takes the default's type)
    unit: str | None
    #: what the option sets, in words (``metro items`` prints it)
    description: str
    #: the least value a count (an option whose default is a whole number) may take; 1 if not given
    minimum: int | None = attrs.field(default=None, kw_only=True)
    #: the largest; 10 000 if not given (a typo such as frequencies=1e9 must not try to allocate
    #: a billion segments)
    maximum: int | None = attrs.field(default=None, kw_only=True)

    def parse(self, value: Any) -> Any:
        """``value`` (text or a value) as the option's value: a quantity of :attr:`unit`, else
        of the default's type; a :class:`DataError` naming the option when it is not."""
        if self.unit is None:
            if isinstance(self.default, (bool, int, float)) and value is not self.default:
                # a count or a flag given as text on the command line: its default's type, or a
                # clear error
                from ..base.options import convert_value

                value = convert_value("this item", f"option {self.name}", value, self.default)
            if isinstance(self.default, int) and not isinstance(self.default, bool):
                least = 1 if self.minimum is None else self.minimum
                most = 10_000 if self.maximum is None else self.maximum
                if not least <= value <= most:
                    raise DataError(None, f"option {self.name}",
                                    f"{value} is outside {least} … {most}",
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

    #: the id of the segment to record (the station's segment carries it); unique per item —
    #: steps of several items with the same kind, conditions and interval are acquired once,
    #: for the longest duration
    segment: str
    #: what to record (``"static"``, ``"rate-revolutions"``, ``"record:<section>"`` …): a kind
    #: the station knows how to acquire, and the ``kind`` of the item's requirement
    kind: str
    #: the instruction for the operator, in words (``metro plan`` prints it)
    description: str
    #: how long to record (a time quantity)
    duration: pint.Quantity
    #: the sample interval (a time quantity)
    interval: pint.Quantity
    #: the conditions to record under, by name (``orientation = "IRA up"``, ``rate =
    #: "10 deg/s"``): the station sets them and copies them into the segment
    conditions: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)
    #: a time to wait, powered, before recording (a live station waits; ``metro plan`` adds it)
    warmup: pint.Quantity | None = None

    @property
    def is_record(self) -> bool:
        """Whether the step takes down a record rather than acquiring a segment."""
        return self.kind.startswith(RECORD_KIND_PREFIX)


@attrs.define
class RunContext:
    """State of one run: options, the progress reporter, lifecycle hooks, the clock."""

    #: the options given for this item (``-o``), as given: read them with
    #: ``self.option_values(ctx.options)`` (defaults filled in, parsed and checked)
    options: dict[str, Any] = attrs.field(factory=dict)
    #: ``progress(task, done, total)`` for long evaluations, or None: call
    #: :meth:`report_progress`
    progress: Callable[[str, float, float], None] | None = None
    #: the date of the run (calibration due dates are judged against it)
    today: dt.date = attrs.field(factory=dt.date.today)

    def report_progress(self, task: str, done: float, total: float) -> None:
        """Report progress of a long evaluation (nothing happens without a reporter)."""
        if self.progress is not None:
            self.progress(task, done, total)


class Procedure(abc.ABC):
    """One calibration/test item of one standard (e.g. ``gbt45570:D.5.6``).

    Subclasses declare, as class attributes, the item's id, clause, title, the metrics it
    produces, the data and equipment it needs, its options, and implement
    :meth:`sequence` (what to measure) and :meth:`evaluate` (formulas → results + budgets).

    An item whose sequence depends on the device may also define
    ``sequence_for_device(options, device) -> list[Step]``: a station that names its device
    before acquiring (``Station.device``) gets that sequence instead of :meth:`sequence` (GB/T
    45570 D.3 resolves its ``method = auto`` option so).
    """

    #: the standard's id (``"gbt45570"``), registered with ``registrar.add_standard``
    standard: ClassVar[str]
    #: the item's id within the standard (``"D.5.1"``; ``-i`` on the command line)
    item: ClassVar[str]
    #: the item's title, in words
    title: ClassVar[str]
    #: the clause of the standard the item implements
    clause: ClassVar[str]
    #: the metrics the item produces (one :class:`Result` each)
    metrics: ClassVar[tuple[Metric, ...]] = ()
    #: the segments it needs (checked before evaluation)
    requires: ClassVar[tuple[SegmentRequirement, ...]] = ()
    #: the equipment it uses, by role (the report lists these)
    equipment: ClassVar[tuple[EquipmentRequirement, ...]] = ()
    #: its options (``-o name=value``)
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
        """``standard:item`` (``"gbt45570:D.5.1"``)."""
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

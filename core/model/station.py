"""What a test station is to metro: the :class:`Station` protocol, exactly what the runner
calls on the object a registered station factory returns.

A plugin registers a station with ``registrar.add_station(name, factory, description)`` in its
``metro_register_stations`` hook (docs/hooks.md); ``factory(**options)`` — the options are the
``--station-option name=value`` and ``--seed`` of the command line — returns a station.
``metro run`` without ``--data`` and ``metro acquire`` then, in this order:

1. call :meth:`Station.device` (when the station has it) to learn the device it would measure,
   so ``--all`` and series choose the items that apply and each item's sequence is planned for
   that device;
2. call ``check(steps, items=…)`` (optional, see below) so a station refuses what it cannot do
   before anything moves;
3. call :meth:`Station.acquire` once with the merged :class:`~metro.core.model.procedure.Step`
   list of every item that runs on the station, and evaluate the items on the
   :class:`~metro.core.model.campaign.Campaign` it returns.

docs/tutorial-station.md builds a simulated station step by step.
"""

from __future__ import annotations

from collections.abc import Callable, Mapping, Sequence
from typing import TYPE_CHECKING, Protocol, runtime_checkable

if TYPE_CHECKING:  # pragma: no cover
    from .campaign import Campaign, DeviceUnderTest
    from .procedure import Step

__all__ = ["CheckingStation", "Progress", "Station"]

#: ``progress(task, done, total)``: what a station reports while it acquires — a task name
#: (e.g. ``"simulating static-1"``), the work done and the total, in any unit; the runner
#: counts a segment finished when its task reaches its total (or when ``total`` is the number
#: of steps and ``done`` counts them)
Progress = Callable[[str, float, float], None]


@runtime_checkable
class Station(Protocol):
    """A test station, simulated or live: the object ``factory(**options)`` returns.

    Required: :meth:`acquire`.  :meth:`device` is called when the station has it (a station
    that cannot say before acquiring leaves it out, or returns ``None``).  A station may also
    define ``check(steps, *, items=None) -> None`` (:class:`CheckingStation`), called before
    :meth:`acquire` by ``metro acquire``; it raises a :class:`~metro.core.base.errors.MetroError`
    naming the step it cannot do.
    """

    def acquire(self, steps: Sequence[Step], *, progress: Progress | None = None) -> Campaign:
        """Acquire every step, in order, and return the campaign.

        :param steps: the merged test sequence of the items that run on this station (each
            item's :meth:`~metro.core.model.procedure.Procedure.sequence`, steps asked by several
            items once).  Each step's ``segment`` is the id the returned campaign's segment must
            carry; a step whose ``kind`` starts with ``record:`` asks for a record (put in
            ``Campaign.records``) instead of a segment.
        :param progress: called as ``progress(task, done, total)`` while acquiring, or ``None``.
        :return: a :class:`~metro.core.model.campaign.Campaign` with one
            :class:`~metro.core.model.campaign.Segment` per step (same ``id``, ``kind`` and
            ``conditions``); a simulated station sets ``simulated=True`` and fills ``truth``
            (what it simulated) and ``expected`` (what a faultless evaluation gives, by metric
            key), which ``metro run`` compares with the results.
        """
        ...  # pragma: no cover

    def device(self) -> DeviceUnderTest | None:
        """The device under test this station measures, known before acquiring, or ``None``.

        :return: the :class:`~metro.core.model.campaign.DeviceUnderTest` that :meth:`acquire`
            will put in its campaign (same id, technology, application and output).
        """
        ...  # pragma: no cover


@runtime_checkable
class CheckingStation(Station, Protocol):
    """A :class:`Station` that can refuse a test sequence before anything is acquired."""

    def check(self, steps: Sequence[Step], *,
              items: Mapping[str, Sequence[str]] | None = None) -> None:
        """Raise a :class:`~metro.core.base.errors.MetroError` if a step cannot be acquired.

        :param steps: the steps :meth:`Station.acquire` would be given.
        :param items: segment id → the qualified ids of the items that asked for it (for the
            message), or ``None``.
        :return: nothing (the station can acquire every step).
        """
        ...  # pragma: no cover

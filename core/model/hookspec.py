"""Every hook metro calls, in one module, grouped by phase.

Plugins implement hooks with ``@metro.core.hookimpl``.  Built-in standards are plugins
loaded from the same ``metro`` entry-point group as third-party ones.  metro never relies on
the order in which implementations are called (pluggy calls the newest registered first);
where one answer is wanted the hook is ``firstresult``.

Phases:

1. **Set-up** — :func:`metro_unit_definitions`, run once when the plugin manager is built.
2. **Registration** — :func:`metro_register_standards`, :func:`metro_register_readers`,
   :func:`metro_register_stations`, :func:`metro_register_templates`,
   :func:`metro_register_drivers`.  Each receives a
   *registrar* that validates what it is given and remembers which plugin gave it.
   :func:`metro_extend_report_context` lets a plugin add to what report templates see.
   :func:`metro_item_applicability` decides which items of a standard apply to a device
   (``metro run --all`` and series); :func:`metro_conformity_specifications` supplies the
   limits results are judged against; :func:`metro_expected_values` computes, by a standard's
   formulas, the expected values of a simulated campaign from what its station declares.
3. **Run** — :func:`metro_campaign_loaded`, :func:`metro_procedure_started`,
   :func:`metro_procedure_finished`, :func:`metro_report_written`: lifecycle events.
4. **Validation** — :func:`metro_validation_cases`: the cases ``metro validate`` runs.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any, Mapping, Sequence

import pluggy

if TYPE_CHECKING:  # pragma: no cover
    from pathlib import Path

    from ..uncertainty.conformity import Specification
    from .procedure import Applicability, Procedure, RunContext
    from .campaign import Campaign, DeviceUnderTest
    from .results import Outcome
    from .provenance import RunRecord
    from .registry import (DriverRegistrar, ReaderRegistrar, StandardRegistrar, StationRegistrar,
                           TemplateRegistrar)

PROJECT = "metro"
hookspec = pluggy.HookspecMarker(PROJECT)
hookimpl = pluggy.HookimplMarker(PROJECT)


# ---------------------------------------------------------------------------------------
# 1. Set-up
# ---------------------------------------------------------------------------------------


@hookspec
def metro_unit_definitions() -> Sequence[str]:
    """Return unit definition lines to add to metro's single unit registry.

    Lines use pint's definitions-file syntax (as in pint's ``default_en.txt``), e.g.
    ``"milli_earth_rate = 0.015041 * degree / hour = mΩe"``.  Called once, before any
    registration hook, so registered procedures can use the new units.

    :return: a sequence of definition lines (may be empty).  Results of all plugins are
        added; a line that redefines an existing unit is an error naming the plugin.
    """


# ---------------------------------------------------------------------------------------
# 2. Registration
# ---------------------------------------------------------------------------------------


@hookspec
def metro_register_standards(registrar: "StandardRegistrar") -> None:
    """Register standards and their procedures (calibration items).

    Call ``registrar.add_standard(id, title, ...)`` then
    ``registrar.add_procedure(ProcedureClass)`` for each item.  A plugin may also add
    procedures to a standard another plugin registered (a vendor-specific item), as long as
    the item id is new: a duplicate ``standard:item`` is an error naming both plugins.

    :param registrar: validates and records what this plugin registers.
    :return: nothing.
    """


@hookspec
def metro_register_readers(registrar: "ReaderRegistrar") -> None:
    """Register data readers for samples files, by file suffix.

    Call ``registrar.add_reader(suffixes=(".csv",), read=callable, description=...)``.
    ``read(path, **kw)`` returns a :class:`metro.instruments.readers.SampleTable`-like
    object with ``columns``, ``units`` and ``sha256``, or raises
    :class:`metro.core.base.errors.DataError`.  A suffix claimed twice is an error naming both.
    A format metro may also write (the samples files of a campaign ``metro acquire`` writes)
    gives ``write=callable`` too: ``write(path, columns, units)`` writes ``{name: array}`` with
    ``{name: unit text}`` so that ``read`` gives them back.

    :param registrar: validates and records the readers.
    :return: nothing.
    """


@hookspec
def metro_register_stations(registrar: "StationRegistrar") -> None:
    """Register test stations (simulated or live) that can acquire a campaign.

    Call ``registrar.add_station(name, factory, description=...)``; ``factory(**options)``
    (the ``--station-option`` and ``--seed`` values) returns a :class:`metro.api.Station`:
    ``acquire(steps, *, progress=None) -> Campaign`` acquires the merged test sequence of the
    items that run on it, and ``device() -> DeviceUnderTest | None`` (optional) names the device
    it measures before acquiring, so ``--all`` and series choose the items that apply.  An
    optional ``check(steps, *, items=None)`` refuses, before anything moves, a step it cannot
    do.  A procedure runs on the station its ``station`` attribute names (default
    ``simulated``, registered this way by ``metro.instruments``) unless ``--station`` is
    given.  docs/tutorial-station.md builds one.

    :param registrar: validates and records the stations.
    :return: nothing.
    """


@hookspec
def metro_register_templates(registrar: "TemplateRegistrar") -> None:
    """Register report or certificate documents: a layout or a Word (docxtpl) template.

    Call ``registrar.add_template(name, standard=None, kind="report", layout="pkg.mod:layout")``
    for a layout built by :mod:`metro.core.documents.document` (a function ``layout(doc, ctx)``), or
    ``registrar.add_template(name, path, standard=None, kind="report")`` for a docxtpl ``.docx``.
    A template registered for a standard is used for that standard's reports; ``standard=None``
    makes it the generic fallback.  Names must be unique.

    :param registrar: validates and records the templates.
    :return: nothing.
    """


@hookspec
def metro_register_drivers(registrar: "DriverRegistrar") -> None:
    """Register drivers for live instruments (a vendor's rate table, a DMM, a gyro's output).

    Call ``registrar.add_driver(name, kind, cls, description=...)``.  ``kind`` is one of
    ``metro.core.model.drivers.DRIVER_KINDS`` (``"rate-table"``, ``"dmm"``,
    ``"gyro-output"``) and ``cls`` a class implementing that kind's interface
    (:class:`metro.core.model.drivers.RateTableDriver` …); ``cls(**options)`` opens a
    connection.  The registrar refuses an unknown kind, a class that does not subclass the
    interface or leaves abstract methods unimplemented, and a name registered twice (naming
    both plugins).  Driver modules should import their I/O libraries (PyVISA, pyserial, a
    vendor SDK) when a driver is opened, not at registration, so ``metro --help`` stays fast.

    :param registrar: validates and records the drivers.
    :return: nothing.
    """


@hookspec
def metro_extend_report_context(record: "RunRecord", context: dict) -> None:
    """Add entries to the context a Word report/certificate template is rendered with.

    Called after :func:`metro.core.documents.context.report_context` has built the generic context
    and before the template renders. Add keys under a name of your own (e.g. ``context["jjf2003"] =
    {...}`` with matrices laid out as rows) so certificate templates registered with
    :func:`metro_register_templates` can show standard-specific layouts. Do not remove or change
    existing keys.

    :param record: the run record being reported.
    :param context: the template context (a plain dict), modified in place.
    :return: nothing.
    """


@hookspec(firstresult=True)
def metro_item_applicability(
    procedure: "type[Procedure]", device: "DeviceUnderTest | None"
) -> "Applicability | None":
    """Decide whether an item applies to a device when a whole standard or a series is run.

    ``metro run --standard S --all`` and series aliases (``registrar.add_series``) run only the
    items that apply. The first non-``None`` answer decides; when every plugin returns ``None`` the
    procedure's own :meth:`~metro.core.model.procedure.Procedure.applies_to` does (every item
    applies by default). Answer only for standards you know — GB/T 45570 uses it to choose the angle
    method (D.1) or the rate method (D.2) by clause 6.2.7.1 — and say why in the
    :class:`~metro.core.model.procedure.Applicability`'s ``reason``: it is printed and reported.

    :param procedure: the candidate item's procedure class.
    :param device: the device under test (from the manifest, or the station's virtual device);
        ``None`` when it is not known before acquisition.
    :return: an :class:`~metro.core.model.procedure.Applicability` (applies, reason), or ``None`` to
        leave the decision to others.
    """


@hookspec
def metro_conformity_specifications(standard: str,
                                    campaign: "Campaign") -> "Sequence[Specification] | None":
    """Supply the specification limits results of ``standard`` are judged against.

    Return :class:`metro.core.uncertainty.conformity.Specification` values (metric key,
    ``≤``/``≥``/range, the limit as a pint quantity, the source cited, e.g. "GB/T 45570—2025 table
    A.1, aviation") chosen for the campaign's device (``campaign.device.technology``,
    ``.application``). Results of all plugins are combined; limits the campaign manifest gives in
    its ``[specification]`` table replace them metric by metric. Results are then judged with the
    run's decision rule (:mod:`metro.core.uncertainty.conformity`).

    :param standard: the standard whose items were run.
    :param campaign: the campaign they were run on.
    :return: a sequence of specifications (may be empty), or ``None`` when this plugin has
        none for ``standard``.
    """


@hookspec
def metro_expected_values(
    campaign: "Campaign", ideal: "Mapping[str, Any]"
) -> "Mapping[str, Any] | None":
    """Compute, by a standard's formulas, what an ideal evaluation of a simulated campaign gives.

    A simulated station declares its device's truth, and ``campaign.expected`` holds what an
    ideal evaluation of that truth gives: the values results are scored against (``metro run``'s
    comparison on a simulated campaign, the within-U benchmarks).  Most follow from the truth
    directly and the station computes them itself.  Where one follows only through the
    standard's formulas (GB/T 45570's threshold by D.39, JJF 2003's matrix fits), the station
    does not import the standard's plugin: it puts the noise-free quantities those formulas
    take into ``ideal`` and calls this hook, and the plugin that knows the keys applies them.

    Keys of ``ideal`` are ``"<standard>:<what>"`` (e.g. ``"gbt45570:tilt_response"``); the
    plugin that reads them documents what each holds.  Answer only for keys you know.

    :param campaign: the simulated campaign as acquired (device, site, segments, records); its
        expected values are not filled in yet.
    :param ideal: the noise-free quantities the station declares, by key.
    :return: expected values (pint quantities by metric key), or ``None`` when this plugin knows
        none of the keys.  Results of all plugins are merged, in plugin-name order.
    """


# ---------------------------------------------------------------------------------------
# 3. Run (lifecycle events)
# ---------------------------------------------------------------------------------------


@hookspec
def metro_campaign_loaded(campaign: "Campaign") -> None:
    """Called after a campaign was read (or acquired) and validated, before any procedure runs.

    Raise :class:`metro.core.base.errors.DataError` to refuse it (e.g. a lab rule that equipment
    must be within its calibration period).

    :param campaign: the loaded campaign.
    :return: nothing.
    """


@hookspec
def metro_procedure_started(procedure: "Procedure", campaign: "Campaign",
                            ctx: "RunContext") -> None:
    """Called just before ``procedure.evaluate(campaign, ctx)``.

    :param procedure: the procedure about to run.
    :param campaign: its data.
    :param ctx: the run context (options, progress).
    :return: nothing.
    """


@hookspec
def metro_procedure_finished(procedure: "Procedure", outcome: "Outcome") -> None:
    """Called when a procedure has produced its outcome (results and budgets).

    :param procedure: the procedure that ran.
    :param outcome: what it produced.
    :return: nothing.
    """


@hookspec
def metro_report_written(path: "Path", outcomes: Sequence["Outcome"]) -> None:
    """Called after a report or certificate was written (atomically) to ``path``.

    :param path: the final path of the document.
    :param outcomes: the outcomes it contains.
    :return: nothing.
    """


# ---------------------------------------------------------------------------------------
# 4. Validation
# ---------------------------------------------------------------------------------------


@hookspec
def metro_validation_cases() -> Sequence[Any]:
    """Contribute validation cases to ``metro validate`` (ISO/IEC 17025 §7.11.2).

    Return :class:`metro.api.ValidationCase` values: each names its published source (the
    standard's worked example, its clause or table), gives the reference values as published
    and the tolerance they are compared at, and computes its own values with the plugin's
    formulas when it is run (a function of no argument).  A standard's plugin returns its worked
    examples reproduced digit for digit; a third-party plugin its own.  ``metro validate`` runs
    every case of every plugin (docs/validation.md), reports each (reference, tolerance, result,
    verdict, the plugin that gave it) and exits 0 only when all pass.  Ids must be unique:
    prefix them with the standard (``"jjf2003:A.1"``).  Building the list must be cheap; the
    work is done when a case is run.

    :return: a sequence of :class:`metro.api.ValidationCase` (may be empty).  Results of all
        plugins are combined; each case is marked with the plugin that gave it.
    """

"""Running items: get a campaign (from a manifest or a station), evaluate, collect provenance.

No printing and no files here: the CLI presents, :mod:`metro.core.documents.report` writes.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import time
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import re

import attrs

from .equipment_check import check_equipment, note_absent_equipment, used_equipment
from .manifest import load_manifest
from ..base.errors import DataError, MetroError, ProcedureError
from ..base.locale import msg
from ..model.campaign import Campaign, DeviceUnderTest, Segment
from ..model.results import Outcome
from ..model.procedure import Procedure, RunContext, SegmentRequirement, Step
from .plugin_manager import MetroPluginManager
from ..model.provenance import RunRecord, new_report_number, software_versions

Progress = Callable[[str, float, float], None]


def merge_steps(sequences: Sequence[Sequence[Step]]) -> list[Step]:
    """Union of several items' sequences: steps of the same kind and conditions are measured
    once, for the longest duration any item asks (e.g. D.5.1, D.5.2 and D.5.6 share one
    static record)."""
    merged: dict[tuple, Step] = {}
    for seq in sequences:
        for st in seq:
            key = (st.kind, tuple(sorted((k, str(v)) for k, v in st.conditions.items())),
                   str(st.interval))
            if key not in merged or st.duration > merged[key].duration:
                merged[key] = st
    return _unique_ids(list(merged.values()))


def _unique_ids(steps: list[Step]) -> list[Step]:
    """Segment ids unique by construction: two different measurements (kind, conditions or
    interval differ) that their items named alike — ``rate+1`` of the angle method's whole
    revolutions and of the rate method's sampled output — are both renamed ``<id>@<kind>``
    (and, should that still clash, a short digest of their conditions is added), whatever the
    order the items were listed in; a file per segment then never overwrites another."""
    import hashlib

    def rename(group: list[Step], fmt) -> list[Step]:
        return [attrs.evolve(s, segment=fmt(s)) for s in group]

    by_id: dict[str, list[int]] = {}
    for i, s in enumerate(steps):
        by_id.setdefault(s.segment, []).append(i)
    out = list(steps)
    for _sid, idx in by_id.items():
        if len(idx) < 2:
            continue
        for i, new in zip(idx, rename([steps[i] for i in idx], lambda s: f"{s.segment}@{s.kind}")):
            out[i] = new
    again: dict[str, list[int]] = {}
    for i, s in enumerate(out):
        again.setdefault(s.segment, []).append(i)
    for _sid, idx in again.items():
        if len(idx) < 2:
            continue
        for i in idx:
            s = out[i]
            tag = hashlib.sha256(repr((sorted((k, str(v)) for k, v in s.conditions.items()),
                                       str(s.interval))).encode()).hexdigest()[:6]
            out[i] = attrs.evolve(s, segment=f"{s.segment}-{tag}")
    return out


def split_options(procs: Sequence[type[Procedure]],
                  options: Mapping[str, Any]) -> list[dict[str, Any]]:
    """Give each item the options it declares; an option no item declares is an error."""
    per = []
    used: set[str] = set()
    for cls in procs:
        names = {o.name for o in cls.options}
        mine = {k: v for k, v in options.items() if k in names}
        used |= set(mine)
        per.append(mine)
    unknown = sorted(set(options) - used)
    if unknown:
        import difflib

        taken = sorted({o.name for cls in procs for o in cls.options})
        close = [f"{u}: did you mean {m[0]!r}?" for u in unknown
                 if (m := difflib.get_close_matches(u, taken, n=1, cutoff=0.6))]
        raise ProcedureError(
            f"option(s) {', '.join(unknown)} are not taken by any of the items "
            f"{', '.join(c.qualified_id() for c in procs)}"
            + (f" ({'; '.join(close)})" if close else "")
            + f"; they take: {', '.join(taken) or 'no options'}",
            hint="`metro items --standard S` lists each item's options",
        )
    return per


def item_sequence(cls: type[Procedure], options: Mapping[str, Any], device: DeviceUnderTest
                  | None = None) -> list[Step]:
    """``cls``'s test sequence; for a known ``device``, the procedure's ``sequence_for_device``
    when it has one (an option such as D.3's ``method = auto`` resolved for the device)."""
    proc = cls()
    fn = getattr(proc, "sequence_for_device", None)
    if device is not None and callable(fn):
        return fn(options, device)
    return proc.sequence(options)


def requirement_groups(cls: type[Procedure]) -> list[list[SegmentRequirement]]:
    """``cls.requires`` as a list of groups, each met when any one of its requirements is met:
    requirements sharing a non-empty ``alternative`` tag form one group, every other one its own."""
    groups: list[list[SegmentRequirement]] = []
    tagged: dict[str, list[SegmentRequirement]] = {}
    for req in cls.requires:
        if req.alternative:
            if req.alternative not in tagged:
                tagged[req.alternative] = []
                groups.append(tagged[req.alternative])
            tagged[req.alternative].append(req)
        else:
            groups.append([req])
    return groups


def _column_problem(req: SegmentRequirement, seg: Segment) -> str | None:
    """Why ``seg`` does not give the columns ``req`` asks for (missing, or a unit of another
    kind)."""
    from ..base.units import Q_, check_dimension, fmt_unit, unit

    if not req.columns:
        return None
    cols = seg.columns()
    for name, accepted in req.columns.items():
        if name not in cols:
            return (
                f"segment {seg.id!r} has no column {name!r} (columns: {', '.join(cols) or 'none'})"
            )
        utext = cols[name][1]
        try:
            u = unit(utext)
        except Exception:  # noqa: BLE001 - an unreadable unit is a mismatch, said as such
            return f"column {name!r} of segment {seg.id!r} is in {utext!r}, which is not a unit"
        ok = False
        for dim in accepted:
            try:
                check_dimension(Q_(1.0, u), dim, field=name)
                ok = True
                break
            except MetroError:
                continue
        if not ok:
            return (f"column {name!r} is recorded in {fmt_unit(u)}, and the item accepts "
                    f"{' or '.join(fmt_unit(d) for d in accepted)}")
    return None


def unmet_requirements(cls: type[Procedure], segments: Sequence[Segment], *,
                       columns: bool = True) -> list[str]:
    """What ``cls`` needs and ``segments`` do not give, in words (empty: every requirement group
    is met).  A group is met when one of its alternatives has a segment of its kind (and, with
    ``columns``, whose columns are there in a unit of an accepted kind — this reads the samples)."""
    problems = []
    for group in requirement_groups(cls):
        why = []
        for req in group:
            segs = [s for s in segments if s.kind == req.kind]
            if not segs:
                why.append(f"no segment of kind {req.kind!r} ({req.description})")
                continue
            if not columns:
                break
            bad = [p for p in (_column_problem(req, s) for s in segs) if p]
            if not bad:
                break
            why.append(f"segments of kind {req.kind!r}: {bad[0]}")
        else:
            problems.append(" — or ".join(why) if len(why) > 1 else why[0])
    return problems


@attrs.frozen
class ItemChoice:
    """One candidate item of ``--all`` or a series: whether it runs, and why (printed and
    reported)."""

    item: str
    run: bool
    reason: str
    via: str  # "--all", "series scale-factor" or "requested"


def _item_order(item: str) -> tuple:
    """D.1.10 after D.1.9: compare the numeric parts as numbers."""
    return tuple((0, int(p), "") if p.isdigit() else (1, 0, p) for p in re.split(r"[.\-]", item))


def select_items(
    pm: MetroPluginManager, standard: str, requested: Sequence[str], *, run_all: bool = False,
    device: DeviceUnderTest | None = None, campaign: Campaign | None = None,
) -> tuple[list[str], list[ItemChoice]]:
    """Expand ``--all`` and series aliases into the items to run.

    Items named explicitly always run.  With ``run_all`` every registered item of the
    standard is a candidate; a series name stands for its members.  A candidate runs if it is
    registered and applies to ``device`` (``metro_item_applicability``, else
    ``Procedure.applies_to``) and, given a recorded ``campaign`` (whose device is then used),
    if the campaign has segments of every kind the item requires.  Returns (items to run, in
    order; every choice with its reason).
    """
    if standard not in pm.register_all().standards:
        pm.procedure(standard, "")  # raises the unknown-standard error listing the loaded ones
    choices: list[ItemChoice] = []
    registered = {cls.item: cls for cls in pm.procedures_of(standard)}
    if campaign is not None:
        device = campaign.device

    def consider(item: str, via: str) -> None:
        if any(c.item == item for c in choices):
            return
        cls = registered.get(item)
        if cls is None:
            choices.append(ItemChoice(item, False,
                                      msg("not available in this metro (no loaded plugin registers "
                                          "it)"), via))
            return
        a = pm.item_applicability(cls, device)
        if a.applies and campaign is not None:  # recorded data: only items whose segments are there
            missing = unmet_requirements(cls, campaign.segments, columns=False)
            if missing:
                choices.append(ItemChoice(item, False,
                                          msg("no data: {missing}", missing="; ".join(missing)),
                                          via))
                return
            lacking = cls.missing_records(campaign)
            if lacking:
                choices.append(ItemChoice(item, False,
                                          msg("no record: the campaign has no {lacking}",
                                              lacking=lacking), via))
                return
        choices.append(ItemChoice(item, a.applies, a.reason
                                  or (msg("applies") if a.applies else msg("does not apply")), via))

    for name in requested:
        ser = pm.series(standard, name)
        if ser is not None:
            for m in ser.members:
                consider(m, f"series {name}")
        else:
            pm.procedure(standard, name)  # an unknown item is an error naming the items
            choices[:] = [c for c in choices if c.item != name]  # named explicitly: it runs
            choices.append(ItemChoice(name, True, msg("requested"), "requested"))
    if run_all:
        for item in sorted(registered, key=_item_order):
            consider(item, "--all")
    run = [c.item for c in choices if c.run]
    if not run:
        raise ProcedureError(
            f"none of the candidate items of {standard} applies to this device: "
            + "; ".join(f"{c.item}: {c.reason}" for c in choices),
        )
    return run, choices


def station_device(pm: MetroPluginManager, name: str, station_options: Mapping[str, Any] | None):
    """The virtual device a station would measure, when the station can say before acquiring."""
    st = pm.station(name).factory(**dict(station_options or {}))
    dev = getattr(st, "device", None)
    dev = dev() if callable(dev) else dev
    return dev if isinstance(dev, DeviceUnderTest) else None


def _merge_campaigns(parts: Sequence[tuple[str, Campaign]]) -> Campaign:
    """One campaign from several stations' campaigns of the *same* device (segments, equipment,
    truth joined); a report covers one device, so different devices are an error."""
    if len(parts) == 1:
        return parts[0][1]
    first = parts[0][1]
    if any(c.device != first.device for _, c in parts[1:]):
        raise ProcedureError(
            "the items need different simulated stations ("
            + ", ".join(f"{n}: device {c.device.id}" for n, c in parts)
            + ") that simulate different devices; a report covers one device, so run them "
            "separately or give --data",
        )
    segments, seen, equipment, eq_ids = [], set(), [], set()
    truth: dict[str, Any] = {}
    expected: dict[str, Any] = {}
    records: dict[str, Any] = {}
    for name, c in parts:
        records.update(c.records)
        for seg in c.segments:
            segments.append(seg if seg.id not in seen else attrs.evolve(seg, id=f"{name}:{seg.id}"))
            seen.add(segments[-1].id)
        for e in c.equipment:
            if e.id not in eq_ids:
                equipment.append(e)
                eq_ids.add(e.id)
        truth.update(c.truth)
        expected.update(c.expected)
    return attrs.evolve(
        first, id="+".join(c.id for _, c in parts), equipment=equipment, segments=segments,
        source="; ".join(f"{c.source} ({n})" for n, c in parts),
        simulated=any(c.simulated for _, c in parts),
        truth=truth, expected=expected, records=records,
    )


class _SegmentTracker:
    """Passes a station's progress through and counts its finished segments for the overall
    ``("segments", done, total)`` event: a station reporting ``(task, i, n_steps)`` counts
    directly; one reporting each segment as its own task counts tasks that reached their total."""

    def __init__(self, progress: Progress, before: int, total: int, n_steps: int) -> None:
        self.progress, self.before, self.total, self.n = progress, before, total, n_steps
        self.finished: set[str] = set()

    def __call__(self, task: str, done: float, total: float) -> None:
        self.progress(task, done, total)
        if total == self.n and self.n > 1:
            count = int(done)
        else:
            if total and done >= total:
                self.finished.add(task)
            count = len(self.finished)
        self.progress("segments", self.before + min(count, self.n), self.total)


def load_campaign(
    pm: MetroPluginManager,
    procs: Sequence[type[Procedure]],
    options: Sequence[Mapping[str, Any]],
    *,
    data: str | Path | None,
    station: str | None = None,
    station_options: Mapping[str, Any] | None = None,
    progress: Progress | None = None,
    lab_equipment: Mapping[str, Any] | None = None,
) -> Campaign:
    """The campaign of a run: the manifest ``data`` (equipment named by id alone taken from
    ``lab_equipment``, the lab profile's), or an acquisition on the items' stations."""
    if data is not None:
        campaign = load_manifest(data, pm.reader_for, lab_equipment=lab_equipment)
    else:
        # one acquisition per station the items need (all on --station when given)
        groups: dict[str, list[int]] = {}
        for i, cls in enumerate(procs):
            groups.setdefault(station or cls.station, []).append(i)
        stations = {name: pm.station(name).factory(**dict(station_options or {})) for name
                    in groups}

        def device_of(st):
            dev = getattr(st, "device", None)
            dev = dev() if callable(dev) else dev
            return dev if isinstance(dev, DeviceUnderTest) else None

        plans = [(name, merge_steps([item_sequence(procs[i], procs[i].option_values(options[i]),
                                                   device_of(stations[name])) for i in idx]))
                 for name, idx in groups.items()]
        total = sum(len(steps) for _, steps in plans)
        done = 0
        if progress is not None:
            progress("segments", 0, total)
        parts = []
        for name, steps in plans:
            st = stations[name]
            tracker = _SegmentTracker(progress, done, total,
                                      len(steps)) if progress is not None else None
            parts.append((name, st.acquire(steps, progress=tracker)))
            done += len(steps)
            if progress is not None:
                progress("segments", done, total)
        campaign = _merge_campaigns(parts)
    pm.campaign_loaded(campaign)
    return campaign


def run_items(
    pm: MetroPluginManager,
    standard: str,
    items: Sequence[str],
    *,
    data: str | Path | None = None,
    options: Mapping[str, Any] | None = None,
    station: str | None = None,
    station_options: Mapping[str, Any] | None = None,
    progress: Progress | None = None,
    campaign: Campaign | None = None,
    run_all: bool = False,
    decision_rule: str | None = None,
    lab_equipment: Mapping[str, Any] | None = None,
    check_campaign: Callable[[Campaign], None] | None = None,
) -> RunRecord:
    """Evaluate ``items`` of ``standard`` on one campaign and return the run record.

    ``items`` may name series (``registrar.add_series``); ``run_all`` adds every item of the
    standard that applies to the device.  Results are judged against the specifications
    plugins and the manifest give, with ``decision_rule`` (``simple``/``guarded``; default:
    the manifest's ``decision_rule``, else :data:`metro.core.uncertainty.conformity.DEFAULT_RULE`).
    ``lab_equipment`` (the lab profile's, by id) completes manifest equipment named by id
    alone; ``check_campaign(campaign)`` runs before any item is evaluated (e.g. the lab's
    refusal of equipment past its due date).
    """
    if not items and not run_all:
        raise MetroError("no item given", hint="use --item, e.g. --item D.5.6, or --all")
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    selection: list[ItemChoice] = []
    if run_all or any(pm.series(standard, i) is not None for i in items):
        if campaign is None and data is not None:
            campaign = load_campaign(pm, [], [], data=data, lab_equipment=lab_equipment)
        if campaign is not None:
            items, selection = select_items(pm, standard, items, run_all=run_all, campaign=campaign)
        else:
            cands = pm.procedures_of(standard)
            device = station_device(pm, station or (cands[0].station if cands else "simulated"),
                                    station_options)
            items, selection = select_items(pm, standard, items, run_all=run_all, device=device)
    procs = [pm.procedure(standard, item) for item in items]
    per_opts = split_options(procs, dict(options or {}))
    if progress is not None:  # the overall display: items (and, below, segments) done of total
        progress("items", 0, len(procs))
    if campaign is None:
        campaign = load_campaign(pm, procs, per_opts, data=data, station=station,
                                 station_options=station_options, progress=progress,
                                 lab_equipment=lab_equipment)
    if check_campaign is not None:
        check_campaign(campaign)
    timings["campaign (manifest or simulation)"] = time.perf_counter() - t0
    outcomes: list[Outcome] = []
    check_specification_units(pm, standard, campaign)
    as_given = campaign  # judged below from its whole [specification]
    campaign = specification_for(pm, standard, campaign)  # the items see the lines for them
    # every item's equipment requirements before anything is evaluated (a required role missing
    # or a calibration U of the wrong kind is an error; absent optional roles become note rows)
    absent_by_item = [check_equipment(campaign, cls) for cls in procs]
    for n_done, (cls, opts, absent) in enumerate(zip(procs, per_opts, absent_by_item)):
        if progress is not None:
            progress("items", n_done, len(procs))
            progress(f"{cls.item} {cls.title}", 0, 1)
        proc = cls()
        ctx = RunContext(options=dict(opts), progress=progress)
        pm.procedure_started(proc, campaign, ctx)
        read_before = sum(s.load_seconds for s in campaign.segments)
        t1 = time.perf_counter()
        with manifest_fields_named(campaign):
            outcome = note_absent_equipment(proc.evaluate(campaign, ctx), absent)
        dt_eval = time.perf_counter() - t1
        read = sum(s.load_seconds for s in campaign.segments) - read_before
        if read > 0:
            timings[f"read samples ({cls.item})"] = read
        timings[f"evaluate {cls.item}"] = dt_eval - read
        pm.procedure_finished(proc, outcome)
        outcomes.append(outcome)
    if progress is not None:
        progress("items", len(procs), len(procs))
    t1 = time.perf_counter()
    conformity = judge(pm, standard, as_given, outcomes, decision_rule)
    timings["conformity"] = time.perf_counter() - t1
    used = {sid for o in outcomes for sid in o.segments}
    files = [(s.file or msg("simulated segment {id}", id=s.id), s.digest()) for s
             in campaign.segments
             if s.id in used and s.digest()]
    return RunRecord(
        report_number=new_report_number(),
        created=dt.datetime.now(dt.timezone.utc),
        campaign=used_equipment(campaign, procs),  # the report lists the equipment its items used
        outcomes=outcomes,
        software=software_versions(),
        plugins=pm.versions(),
        data_files=files,
        simulated=campaign.simulated,
        truth=dict(campaign.truth),
        timings=timings,
        selection=selection,
        conformity=conformity,
    )


#: the fields that are the manifest's (not a samples file's): an error about one names the manifest
_MANIFEST_FIELDS = ("segments.", "segments[", "device.", "site.", "environment.", "equipment",
                    "specification",
                    "campaign.")


@contextlib.contextmanager
def manifest_fields_named(campaign: Campaign):
    """An error a procedure raises about a manifest field (a segment's condition, the device's
    scale factor) against a samples file is re-raised naming the manifest, where the field is."""
    try:
        yield
    except DataError as exc:
        manifest = campaign.source if campaign.manifest_sha256 else None
        if (manifest and exc.file and exc.file != manifest and exc.field
                and str(exc.field).startswith(_MANIFEST_FIELDS)):
            raise DataError(manifest, exc.field, exc.detail, hint=exc.hint) from exc
        raise


def metric_keys(pm: MetroPluginManager) -> dict[str, set[str]]:
    """{standard: the keys of the metrics its items declare} for every loaded standard."""
    return {std: {m.key for cls in pm.procedures_of(std) for m in cls.metrics}
            for std in sorted(pm.register_all().standards)}


def specification_for(pm: MetroPluginManager, standard: str, campaign: Campaign) -> Campaign:
    """The campaign as ``standard``'s items and plugins see it: its ``[specification]`` reduced
    to the flat table of the lines that judge ``standard`` (:func:`~metro.core.uncertainty.
    conformity.limits_for`), with a warning in ``campaign.warnings`` for a flat line more than
    one loaded standard has.  The same campaign when it gives no specification."""
    from ..uncertainty import conformity as cf

    if not campaign.specification:
        return campaign
    limits = cf.limits_for(campaign.specification, standard, metric_keys(pm), file=campaign.source)
    if dict(limits.table) == dict(campaign.specification) and not limits.warnings:
        return campaign
    new = [w for w in limits.warnings if w not in campaign.warnings]
    return attrs.evolve(campaign, specification=limits.table, warnings=(*campaign.warnings, *new))


def check_specification_units(pm: MetroPluginManager, standard: str, campaign: Campaign) -> None:
    """Before any evaluation: each ``[specification]`` limit that judges ``standard`` must be of
    the kind of unit of the metrics it judges (``Kn = "<= 5 °/h"`` is refused naming
    ``specification.Kn``; a line of ``[specification.gbt45570]`` as
    ``specification.gbt45570.Kn``)."""
    from ..uncertainty import conformity as cf
    from ..base.units import Q_, fmt_unit

    if not campaign.specification:
        return
    limits = cf.limits_for(campaign.specification, standard, metric_keys(pm), file=campaign.source)
    if not [k for k in limits.table if k not in cf.SETTINGS]:
        return
    metrics = [m for cls in pm.procedures_of(standard) for m in cls.metrics]
    for spec in limits.specifications(campaign.source):
        judged = [m for m in metrics if spec.applies_to(m.key)]
        if not judged:
            continue
        if not any(cf.compatible(Q_(1.0, m.unit), spec.limit) for m in judged):
            m = judged[0]
            field = limits.fields.get(spec.symbol, f"specification.{spec.symbol}")
            unit = fmt_unit(Q_(1.0, m.unit).units)
            raise DataError(campaign.source, field,
                            f"the limit is in {fmt_unit(spec.limit.units)} but {m.key} ({m.name}) "
                            f"is in {unit}: different kinds of quantity",
                            hint=f"state the limit in a unit of the kind of {unit}")


def _for_the_outputs(specs, outcomes):
    """A plugin's limit written for another kind of output does not apply to a result in this one
    (GB/T 45570 table B.1's K in LSB/[(°)/s] against a K in Hz/[(°)/s] or P/″): such a limit is
    kept from the results it cannot judge — it is listed as not assessed, its source saying why —
    instead of stopping the run on the unit.  A limit the manifest gives is never filtered: a
    ``[specification]`` in the wrong kind of unit stays an error."""
    from ..uncertainty.conformity import compatible

    out = []
    for sp in specs:
        clash = sorted({o.item for o in outcomes for r in o.results
                        if sp.applies_to(r.metric.key, o.item) and
                        not compatible(r.value, sp.limit)})
        if not clash:
            out.append(sp)
            continue
        keep = tuple(i for i in (sp.items or {o.item for o in outcomes}) if i not in clash)
        note = (f"{sp.source}; not applied to {', '.join(clash)}: that result is in another unit "
                "(another kind of output) than this limit")
        out.append(attrs.evolve(sp, items=keep or ("(none)",), source=note))
    return out


def judge(pm: MetroPluginManager, standard: str, campaign: Campaign, outcomes: Sequence[Outcome],
          decision_rule: str | None = None):
    """The conformity assessment of ``outcomes``: plugins' specifications for ``standard``, the
    manifest's ``[specification]`` lines for ``standard`` (:func:`specification_for`) replacing
    them metric by metric; ``None`` when there is none."""
    from ..uncertainty import conformity as cf

    campaign = specification_for(pm, standard, campaign)  # the lines that judge this standard
    given = dict(campaign.specification)
    typical = _for_the_outputs(pm.conformity_specifications(standard, campaign), outcomes)
    specs = cf.merge_specifications(typical,
                                    cf.specifications_from_table(given, file=campaign.source))
    if not specs:
        return None
    rule = cf.rule_named(decision_rule or given.get("decision_rule"))
    return cf.assess(outcomes, specs, rule)

"""Running items: get a campaign (from a manifest or a station), evaluate, collect provenance.

No printing and no files here: the CLI presents, :mod:`metro.core.report` writes.
"""

from __future__ import annotations

import datetime as dt
import time
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

from .campaign import load_manifest
from .errors import MetroError, ProcedureError
from .model import Campaign, Outcome, Procedure, RunContext, Step
from .plugins import MetroPluginManager
from .provenance import RunRecord, new_report_number, software_versions

Progress = Callable[[str, float, float], None]


def merge_steps(sequences: Sequence[Sequence[Step]]) -> list[Step]:
    """Union of several items' sequences: steps of the same kind and conditions are measured
    once, for the longest duration any item asks (e.g. D.5.1, D.5.2 and D.5.6 share one
    static record)."""
    merged: dict[tuple, Step] = {}
    for seq in sequences:
        for st in seq:
            key = (st.kind, tuple(sorted((k, str(v)) for k, v in st.conditions.items())), str(st.interval))
            if key not in merged or st.duration > merged[key].duration:
                merged[key] = st
    return list(merged.values())


def split_options(procs: Sequence[type[Procedure]], options: Mapping[str, Any]) -> list[dict[str, Any]]:
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
        raise ProcedureError(
            f"option(s) {', '.join(unknown)} are not taken by any of the items "
            f"{', '.join(c.qualified_id() for c in procs)}",
            hint="`metro items --standard S` lists each item's options",
        )
    return per


def load_campaign(
    pm: MetroPluginManager,
    procs: Sequence[type[Procedure]],
    options: Sequence[Mapping[str, Any]],
    *,
    data: str | Path | None,
    station: str | None = None,
    station_options: Mapping[str, Any] | None = None,
    progress: Progress | None = None,
) -> Campaign:
    if data is not None:
        campaign = load_manifest(data, pm.reader_for)
    else:
        if station is None:
            wanted = sorted({cls.station for cls in procs})
            if len(wanted) > 1:
                raise ProcedureError(
                    f"the items need different simulated stations ({', '.join(wanted)}); run them separately "
                    "or give --data"
                )
            station = wanted[0]
        st = pm.station(station).factory(**dict(station_options or {}))
        steps = merge_steps([cls().sequence(cls.option_values(o)) for cls, o in zip(procs, options)])
        campaign = st.acquire(steps, progress=progress)
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
) -> RunRecord:
    """Evaluate ``items`` of ``standard`` on one campaign and return the run record."""
    if not items:
        raise MetroError("no item given", hint="use --item, e.g. --item D.5.6")
    procs = [pm.procedure(standard, item) for item in items]
    per_opts = split_options(procs, dict(options or {}))
    timings: dict[str, float] = {}
    t0 = time.perf_counter()
    if campaign is None:
        campaign = load_campaign(pm, procs, per_opts, data=data, station=station,
                                 station_options=station_options, progress=progress)
    timings["campaign (manifest or simulation)"] = time.perf_counter() - t0
    outcomes: list[Outcome] = []
    for cls, opts in zip(procs, per_opts):
        proc = cls()
        ctx = RunContext(options=dict(opts), progress=progress)
        pm.procedure_started(proc, campaign, ctx)
        read_before = sum(s.load_seconds for s in campaign.segments)
        t1 = time.perf_counter()
        outcome = proc.evaluate(campaign, ctx)
        dt_eval = time.perf_counter() - t1
        read = sum(s.load_seconds for s in campaign.segments) - read_before
        if read > 0:
            timings[f"read samples ({cls.item})"] = read
        timings[f"evaluate {cls.item}"] = dt_eval - read
        pm.procedure_finished(proc, outcome)
        outcomes.append(outcome)
    used = {sid for o in outcomes for sid in o.segments}
    files = [(s.file or f"simulated segment {s.id}", s.digest()) for s in campaign.segments
             if s.id in used and s.digest()]
    return RunRecord(
        report_number=new_report_number(),
        created=dt.datetime.now(dt.timezone.utc),
        campaign=campaign,
        outcomes=outcomes,
        software=software_versions(),
        plugins=pm.versions(),
        data_files=files,
        simulated=campaign.simulated,
        truth=dict(campaign.truth),
        timings=timings,
    )

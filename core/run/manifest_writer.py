"""Writing a :class:`~metro.core.model.campaign.Campaign` to disk in the ``metro-campaign/1``
format.

:func:`write_campaign` turns any campaign — one a station has just acquired (simulated or live) or
one read from another manifest — into a folder that :func:`metro.core.run.manifest.load_manifest`
reads back to the same numbers:

* ``manifest.toml`` with the device, every piece of equipment and its calibration, the
  environment, the site and each segment's kind, conditions, sample interval and column units;
* one samples file per segment: a CSV with ``name [unit]`` headers for short records (floats
  written as the shortest text that reads back to the same float64), a structured ``.npy`` for
  long ones (``npy_rows`` and more).

The folder appears complete or not at all: everything is written into a hidden temporary
folder next to the target, which is renamed into place only when the last file is on disk; on
any error (``KeyboardInterrupt`` included) the temporary folder is removed and nothing is left.

:func:`acquire_campaign` runs the merged test sequence of some items on a registered station and
writes the result; it is what ``metro acquire`` calls.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import math
import os
import re
import secrets
import shutil
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pint

from metro.core.base.atomic import TMP_MARKER, atomic_write_text, write_failure
from metro.core.run.manifest import FORMAT
from metro.core.base.errors import DataError, MetroError
from metro.core.model.campaign import Calibration, Campaign, Equipment, Segment

__all__ = ["write_campaign", "acquire_campaign", "quantity_text", "NPY_ROWS", "MANIFEST"]

#: records with at least this many rows are written as ``.npy`` rather than CSV
NPY_ROWS = 100_000
MANIFEST = "manifest.toml"

Progress = Callable[[str, float, float], None]

_SAFE_FILE = re.compile(r"[^A-Za-z0-9._+-]+")


# ------------------------------------------------------------------------------ TOML text


def quantity_text(q: pint.Quantity, *, field: str = "") -> str:
    """A scalar quantity as manifest text that :func:`metro.core.base.units.parse_quantity` reads
    back to the same magnitude and unit (``"0.8 pulse / arcsecond"``, ``"-40 degree_Celsius"``,
    ``"4e-06"`` for a dimensionless ratio)."""
    mag = q.magnitude
    if np.ndim(mag) != 0:
        raise DataError(None, field,
                        f"cannot write an array quantity ({q!r}) as one manifest value")
    mag = mag.item() if isinstance(mag, np.generic) else mag
    if isinstance(mag, float) and not math.isfinite(mag):
        raise DataError(None, field, f"cannot write the non-finite value {mag!r}")
    units = f"{q.units:D}"
    if units in ("", "dimensionless"):
        return repr(mag)
    return f"{mag!r} {units}"


def _value(v: Any, field: str) -> Any:
    """One manifest value as tomli-w writes it: text, quantity (as text), number, boolean, date or
    a list of these."""
    if isinstance(v, pint.Quantity):
        return quantity_text(v, field=field)
    if isinstance(v, (bool, np.bool_)):
        return bool(v)
    if isinstance(v, (int, np.integer)):
        return int(v)
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if not math.isfinite(f):
            raise DataError(None, field, f"cannot write the non-finite value {f!r}")
        return f
    if isinstance(v, (str, dt.date, dt.datetime)):
        return v
    if isinstance(v, (tuple, list)):
        return [_value(x, f"{field}[{i}]") for i, x in enumerate(v)]
    raise DataError(None, field, f"cannot write a {type(v).__name__} ({v!r}) into the manifest",
                    hint="give properties and conditions as text, numbers or quantities")


def _table(items: Mapping[str, Any], where: str) -> dict[str, Any]:
    """A table of plain values (None left out)."""
    return {str(k): _value(v, f"{where}.{k}") for k, v in items.items() if v is not None}


def _calibration_items(cal: Calibration) -> dict[str, Any]:
    out: dict[str, Any] = {"certificate": cal.certificate, "U": cal.uncertainty, "k": float(cal.k)}
    if cal.due is not None:
        out["due"] = cal.due
    if cal.lab:
        out["lab"] = cal.lab
    out["distribution"] = cal.distribution
    return out


def _equipment_table(e: Equipment, i: int) -> dict[str, Any]:
    head = {"id": e.id, "role": e.role, "manufacturer": e.manufacturer or None, "model": e.model
            or None,
            "serial": e.serial or None}
    reserved = set(head) | {"calibration"}
    clash = sorted(set(e.properties) & reserved)
    if clash:
        raise DataError(None, f"equipment[{i}]",
                        f"property name(s) {', '.join(clash)} clash with the "
                        "manifest's own keys")
    out = _table(head | dict(e.properties), f"equipment[{i}]")
    if e.calibration is not None:
        out["calibration"] = _table(_calibration_items(e.calibration),
                                    f"equipment[{i}].calibration")
    return out


def _segment_table(campaign: Campaign, seg: Segment, fname: str,
                   units: Mapping[str, str]) -> dict[str, Any]:
    if seg.interval is None:
        raise DataError(campaign.source, f"segments.{seg.id}.sample_interval",
                        "the segment has no sample interval; the data format requires one")
    out = _table({"id": seg.id, "kind": seg.kind, "file": fname, "sample_interval": seg.interval,
                  "started": seg.started}, f"segments.{seg.id}")
    if seg.conditions:
        out["conditions"] = _table(seg.conditions, f"segments.{seg.id}.conditions")
    out["units"] = _table(units, f"segments.{seg.id}.units")
    return out


def manifest_text(campaign: Campaign, files: Mapping[str, tuple[str, Mapping[str, str]]],
                  extra: Mapping[str, Any] | None = None) -> str:
    """The manifest of ``campaign`` (TOML written by tomli-w); ``files`` maps each segment id to
    (file name, {column: unit})."""
    import tomli_w

    camp = {"id": campaign.id} | dict(campaign.meta) | dict(extra or {})
    if campaign.simulated:
        camp.setdefault("simulated", True)
    d = campaign.device
    dev = {"id": d.id, "manufacturer": d.manufacturer or None, "model": d.model or None,
           "serial": d.serial or None,
           "technology": d.technology or None, "application": d.application or None,
           "output": d.output or None}
    doc: dict[str, Any] = {"format": FORMAT, "campaign": _table(camp, "campaign"),
                           "device": _table(dev | dict(d.properties), "device"),
                           "environment": _table(campaign.environment, "environment"),
                           "site": _table(campaign.site, "site")}
    if campaign.equipment:
        doc["equipment"] = [_equipment_table(e, i) for i, e in enumerate(campaign.equipment)]
    if campaign.segments:
        doc["segments"] = [_segment_table(campaign, seg, *files[seg.id]) for seg
                           in campaign.segments]
    for name, value in campaign.records.items():
        if str(name) in doc:
            raise DataError(None, str(name),
                            f"the record section '{name}' clashes with the manifest's own keys")
        doc[str(name)] = _record(str(name), value)
    source = " ".join(str(campaign.source or "campaign").split())
    return (
        f"# metro campaign written by metro.core.run.manifest_writer ({source})\n"
        + tomli_w.dumps(doc)
    )


def _is_table_array(v: Any) -> bool:
    return isinstance(v, (list, tuple)) and bool(v) and all(isinstance(x, Mapping) for x in v)


def _record(path: str, value: Any) -> Any:
    """A record section (Campaign.records): a table or an array of tables, with sub-tables."""
    if _is_table_array(value):
        return [_record_table(path, item) for item in value]
    if isinstance(value, Mapping):
        return _record_table(path, value)
    raise DataError(None, path,
                    f"a record section must be a table or an array of tables, got {value!r}")


def _record_table(path: str, table: Mapping[str, Any]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    for k, v in table.items():
        if isinstance(v, Mapping) or _is_table_array(v):
            out[str(k)] = _record(f"{path}.{k}", v)
        elif v is not None:
            out[str(k)] = _value(v, f"{path}.{k}")
    return out


# ------------------------------------------------------------------------------ samples


def _file_names(segments: Sequence[Segment]) -> dict[str, str]:
    """A distinct, portable file stem per segment id."""
    out: dict[str, str] = {}
    used: set[str] = set()
    for s in segments:
        stem = _SAFE_FILE.sub("_", s.id).strip("._") or "segment"
        cand, n = stem, 1
        while cand.lower() in used:
            n += 1
            cand = f"{stem}-{n}"
        used.add(cand.lower())
        out[s.id] = cand
    return out


def _distinct_segments(campaign: Campaign) -> None:
    """Refuse, before anything is written, two segments that would land in one file: the same id
    (the manifest could not tell them apart and one record would replace the other)."""
    seen: dict[str, Segment] = {}
    for seg in campaign.segments:
        other = seen.get(seg.id)
        if other is not None:
            raise DataError(campaign.source or None, f"segments.{seg.id}",
                            f"two segments have the id {seg.id!r} (kinds {other.kind!r} and "
                            f"{seg.kind!r}); one record would replace the other, so nothing was "
                            "written",
                            hint="give every segment its own id (metro.core.run.runner.merge_steps "
                            "does for merged sequences)")
        seen[seg.id] = seg


def _write_samples(folder: Path, stem: str, seg: Segment, npy_rows: int,
                   writer_for: Callable[[str], Callable[..., Any]]) -> tuple[str, dict[str, str]]:
    """One segment's samples file, written by the format registered for its suffix."""
    cols = seg.recorded_columns()  # as recorded: a ratiometric column stays in mV/V
    if not cols:
        raise DataError(None, f"segments.{seg.id}", "the segment has no columns to write")
    arrays = {name: np.asarray(a) for name, (a, _u) in cols.items()}
    units = {name: str(u) for name, (_a, u) in cols.items()}
    rows = {len(a) for a in arrays.values()}
    if len(rows) != 1:
        raise DataError(None, f"segments.{seg.id}",
                        f"the columns have different lengths {sorted(rows)}")
    n = rows.pop()
    name = f"{stem}.npy" if n >= npy_rows else f"{stem}.csv"
    if name.endswith(".npy"):
        writer_for(".npy")(folder / name, arrays, units)
    else:
        writer_for(".csv")(folder / name, arrays, units,
                           comments=[f"segment {seg.id} ({seg.kind}), {n} rows"])
    return name, units


# ------------------------------------------------------------------------------ the folder


def _fresh_target(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise DataError(str(out), None, "exists and is not a folder", hint="choose another --out")
    if out.is_dir() and any(out.iterdir()):
        raise DataError(str(out), None,
                        "the folder exists and is not empty; metro never overwrites a campaign",
                        hint="choose a new --out folder or remove the old one")
    # missing parents are made (as mkdir -p does); a file in the way is not
    for parent in out.parents:
        if parent.exists() and not parent.is_dir():
            raise DataError(str(out), None, f"{parent} is not a folder",
                            hint="choose another --out")


def _make_parents(out: Path) -> list[Path]:
    """The missing parent folders of ``out`` made, as ``mkdir -p`` makes them (never replacing
    anything); return them, outermost first, so that a failure can remove them again."""
    made: list[Path] = []
    try:
        for parent in reversed(out.parents):
            if not parent.exists():
                parent.mkdir()
                made.append(parent)
    except OSError as exc:
        for parent in reversed(made):
            with contextlib.suppress(OSError):
                parent.rmdir()
        raise DataError(str(out), None,
                        f"cannot make its parent folders ({exc.strerror or exc})") from exc
    return made


def write_campaign(
    campaign: Campaign,
    out: str | os.PathLike[str],
    *,
    npy_rows: int = NPY_ROWS,
    extra: Mapping[str, Any] | None = None,
    progress: Progress | None = None,
    pm: Any = None,
) -> Path:
    """Write ``campaign`` as a folder ``out`` (manifest + samples) and return the manifest's path.

    ``out`` must not exist or be an empty folder.  Segments of ``npy_rows`` rows or more go to
    ``.npy``, shorter ones to CSV, each by the writer the plugin manager ``pm`` has registered for
    the suffix (default: metro's built-in plugins).  ``extra`` adds keys to the manifest's
    ``[campaign]`` table
    (e.g. the station and the items acquired).  Atomic: a hidden temporary folder is renamed
    onto ``out`` at the end; on error nothing is left behind.
    """
    out = Path(out).absolute()
    _fresh_target(out)
    _distinct_segments(campaign)
    if pm is None:
        from metro.core.run.plugin_manager import builtin_plugin_manager

        pm = builtin_plugin_manager()
    for sfx in (".csv", ".npy"):  # refused before anything is made
        pm.writer_for(sfx)
    tmp = out.with_name(f".{out.name}{TMP_MARKER}{secrets.token_hex(4)}")
    made = _make_parents(out)
    try:
        tmp.mkdir()
        stems = _file_names(campaign.segments)
        files: dict[str, tuple[str, dict[str, str]]] = {}
        total = len(campaign.segments)
        for i, seg in enumerate(campaign.segments):
            files[seg.id] = _write_samples(tmp, stems[seg.id], seg, npy_rows, pm.writer_for)
            if progress is not None:
                progress("writing samples", i + 1, total)
        atomic_write_text(tmp / MANIFEST, manifest_text(campaign, files, extra))
        _fresh_target(out)  # still free?
        if out.is_dir():
            out.rmdir()  # empty: checked above
        os.rename(tmp, out)
    except BaseException as exc:
        shutil.rmtree(tmp, ignore_errors=True)
        for parent in reversed(made):  # the folders made for it, innermost first (empty again)
            with contextlib.suppress(OSError):
                parent.rmdir()
        if isinstance(exc, OSError):  # a full disk, a read-only file system: said, not a traceback
            reason, hint = write_failure(exc)
            raise DataError(str(out), None,
                            f"cannot write the campaign: {reason}; nothing was written",
                            hint=hint) from exc
        raise
    try:
        fd = os.open(out.parent, os.O_RDONLY)
    except OSError:  # pragma: no cover - Windows
        pass
    else:
        try:
            os.fsync(fd)
        except OSError:  # pragma: no cover
            pass
        finally:
            os.close(fd)
    return out / MANIFEST


def acquire_campaign(
    pm: Any,
    standard: str,
    items: Sequence[str],
    out: str | os.PathLike[str],
    *,
    station: str | None = None,
    options: Mapping[str, Any] | None = None,
    station_options: Mapping[str, Any] | None = None,
    npy_rows: int = NPY_ROWS,
    progress: Progress | None = None,
    run_all: bool = False,
    evaluate: bool | None = None,
) -> Path:
    """Run the merged sequence of ``items`` on ``station`` (default: the items' own station) and
    write the campaign to ``out``; return the manifest path.  ``pm`` is a loaded plugin manager.

    ``items`` may name series; ``run_all`` adds every item of the standard that applies to the
    station's device (as ``metro run`` selects them). Every item is checked against the station and
    its device before anything is recorded: the item applies to the device (GB/T 45570 6.2.7.1's
    method rule …) and the station simulates or runs every step kind. After the record, and before
    anything is written, every item's segment requirements (kinds, alternatives, columns in an
    accepted unit) are checked against what was recorded, and a simulated campaign is evaluated in
    memory (``evaluate``, default: when simulated) — so a campaign that acquire writes is one that
    ``metro run --data`` evaluates. A mismatch is a :class:`~metro.core.base.errors.MetroError`
    naming the stations that would fit; nothing is written.
    """
    from metro.core.run.runner import item_sequence, merge_steps, select_items, split_options

    if not items and not run_all:
        raise MetroError("no item given",
                         hint="use --item, e.g. --item D.5.1, a series name, or --all")
    _fresh_target(Path(out).absolute())
    if station is None:
        named = [pm.procedure(standard, i) for i in items if pm.series(standard, i) is None]
        if run_all or len(named) < len(items):  # --all or a series: the station run would simulate
            cands = pm.procedures_of(standard)
            named += cands[:1]
        wanted = sorted({cls.station for cls in named})
        if len(wanted) > 1:
            raise MetroError(f"the items need different stations ({', '.join(wanted)}); acquire "
                             "them separately",
                             hint="or name one with --station")
        station = wanted[0] if wanted else "simulated"
    st = pm.station(station).factory(**dict(station_options or {}))
    device = _device_of(st)
    if run_all or any(pm.series(standard, i) is not None for i in items):
        items, _choices = select_items(pm, standard, items, run_all=run_all, device=device)
    items = list(items)
    procs = [pm.procedure(standard, i) for i in items]
    per_opts = split_options(procs, dict(options or {}))
    sequences = [item_sequence(cls, cls.option_values(o), device) for cls, o
                 in zip(procs, per_opts)]
    steps = merge_steps(sequences)
    origin = _origin(procs, sequences, steps)
    check = getattr(st, "check", None)
    if callable(check):  # a station refuses what it cannot do before anything moves
        try:
            check(steps, items=origin)
        except MetroError as exc:  # the station's own error, with the stations that would fit
            fits = _fits(pm, standard, procs[0], station) if len(procs) == 1 else ""
            exc.hint = "; ".join(x for x in (exc.hint, fits) if x) or None
            raise
    if device is not None:
        for cls in procs:
            a = pm.item_applicability(cls, device)
            if not a.applies:
                raise MetroError(
                    f"{cls.qualified_id()} does not apply to the device of station {station!r} "
                    f"({device.id}, {device.technology or 'technology not stated'}, "
                    f"{device.output or 'output not stated'} output): {a.reason}; nothing was "
                    "recorded",
                    hint=_fits(pm, standard, cls, station))
    if progress is not None:
        progress("acquiring", 0, len(steps))
    campaign = st.acquire(steps, progress=progress)
    if progress is not None:
        progress("acquiring", len(steps), len(steps))
    from metro.core.run.equipment_check import used_equipment

    # the equipment these items use, not the whole station's
    campaign = used_equipment(campaign, procs)
    ids = {seg.id for seg in campaign.segments}
    missing = [s.segment for s in steps if s.segment not in ids and not s.is_record]
    if missing:
        raise MetroError(
            f"station {station!r} returned no segment for step(s) {', '.join(missing)}")
    _check_recorded(pm, standard, station, procs, campaign, origin)
    if evaluate if evaluate is not None else campaign.simulated:
        _check_evaluates(pm, standard, station, items, options, campaign)
    extra = {"station": station, "standard": standard, "items": ",".join(items),
             "acquired": dt.datetime.now(dt.timezone.utc).replace(microsecond=0).isoformat()}
    return write_campaign(campaign, out, npy_rows=npy_rows, extra=extra, progress=progress, pm=pm)


def _device_of(st: Any):
    from metro.core.model.campaign import DeviceUnderTest

    dev = getattr(st, "device", None)
    try:
        dev = dev() if callable(dev) else dev
    except MetroError:
        return None
    return dev if isinstance(dev, DeviceUnderTest) else None


def _origin(procs, sequences, steps) -> dict[str, list[str]]:
    """Merged segment id -> the items that asked for it (steps matched by kind, conditions,
    interval)."""
    def key(s):
        return (s.kind, tuple(sorted((k, str(v)) for k, v in s.conditions.items())),
                str(s.interval))

    ids = {key(s): s.segment for s in steps}
    origin: dict[str, list[str]] = {}
    for cls, seq in zip(procs, sequences):
        for s in seq:
            sid = ids.get(key(s))
            if sid is not None and cls.qualified_id() not in origin.setdefault(sid, []):
                origin[sid].append(cls.qualified_id())
    return origin


def _check_recorded(pm, standard: str, station: str, procs, campaign: Campaign, origin) -> None:
    """Every item's requirements met by the segments recorded for it (kinds, alternatives,
    columns in a unit of an accepted kind), before anything is written."""
    from metro.core.run.runner import unmet_requirements

    for cls in procs:
        mine = [s for s in campaign.segments if cls.qualified_id() in origin.get(s.id, ())]
        problems = unmet_requirements(cls, mine)
        if problems:
            raise MetroError(
                f"station {station!r} records what {cls.qualified_id()} cannot evaluate: "
                f"{'; '.join(problems)}; nothing was written",
                hint=_fits(pm, standard, cls, station))


def _check_evaluates(pm, standard: str, station: str, items, options, campaign: Campaign) -> None:
    """A simulated campaign is evaluated in memory before it is written: what run would refuse,
    acquire refuses (nothing written), naming the item and the reason."""
    from metro.core.run.runner import run_items

    try:
        run_items(pm, standard, list(items), options=options, campaign=campaign)
    except MetroError as exc:
        raise MetroError(f"the campaign recorded on station {station!r} would not evaluate: "
                         f"{exc.reason}; nothing was written",
                         hint=exc.hint or "a longer record (duration_scale) or other item "
                         "options may help") from exc


def _fits(pm, standard: str, cls, refused: str) -> str:
    """'stations that fit: …' — the registered simulated stations on whose device ``cls`` applies
    and which simulate every step kind of its sequence (checked without recording anything)."""
    from metro.core.run.runner import item_sequence, merge_steps

    ok = []
    for name in sorted(pm.registry.stations):
        if name in (refused, "bench"):
            continue
        try:
            try:
                st = pm.station(name).factory(duration_scale=0.05)
            except MetroError:
                st = pm.station(name).factory()
            dev = _device_of(st)
            if dev is not None and not pm.item_applicability(cls, dev).applies:
                continue
            steps = merge_steps([item_sequence(cls, cls.option_values({}), dev)])
            check = getattr(st, "check", None)
            if not callable(check):
                continue
            check(steps)
            ok.append(name)
        except Exception:  # noqa: BLE001 - a station that cannot serve the item does not fit
            continue
    if ok:
        return f"stations that fit {cls.qualified_id()}: {', '.join(ok)} (--station NAME)"
    return (
        f"no registered simulated station serves {cls.qualified_id()}; record it and use `metro "
        "run --data`"
    )

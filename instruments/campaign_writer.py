"""Writing a :class:`~metro.core.model.Campaign` to disk in the ``metro-campaign/1`` format.

:func:`write_campaign` turns any campaign — one a station has just acquired (simulated or
live) or one read from another manifest — into a folder that :func:`metro.core.campaign.load_manifest`
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

import datetime as dt
import json
import math
import os
import re
import secrets
import shutil
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import numpy as np
import pint

from metro.core.atomic import TMP_MARKER, atomic_write_text
from metro.core.campaign import FORMAT
from metro.core.errors import DataError, MetroError
from metro.core.model import Calibration, Campaign, Equipment, Segment

__all__ = ["write_campaign", "acquire_campaign", "quantity_text", "NPY_ROWS", "MANIFEST"]

#: records with at least this many rows are written as ``.npy`` rather than CSV
NPY_ROWS = 100_000
MANIFEST = "manifest.toml"

Progress = Callable[[str, float, float], None]

_BARE_KEY = re.compile(r"^[A-Za-z0-9_-]+$")
_SAFE_FILE = re.compile(r"[^A-Za-z0-9._+-]+")


# ------------------------------------------------------------------------------ TOML text


def quantity_text(q: pint.Quantity, *, field: str = "") -> str:
    """A scalar quantity as manifest text that :func:`metro.core.units.parse_quantity` reads back
    to the same magnitude and unit (``"0.8 pulse / arcsecond"``, ``"-40 degree_Celsius"``,
    ``"4e-06"`` for a dimensionless ratio)."""
    mag = q.magnitude
    if np.ndim(mag) != 0:
        raise DataError(None, field, f"cannot write an array quantity ({q!r}) as one manifest value")
    mag = mag.item() if isinstance(mag, np.generic) else mag
    if isinstance(mag, float) and not math.isfinite(mag):
        raise DataError(None, field, f"cannot write the non-finite value {mag!r}")
    units = f"{q.units:D}"
    if units in ("", "dimensionless"):
        return repr(mag)
    return f"{mag!r} {units}"


def _key(k: str) -> str:
    return k if _BARE_KEY.match(k) else json.dumps(k, ensure_ascii=False)


def _value(v: Any, field: str) -> str:
    """One TOML value: text, quantity (as text), number, boolean or date."""
    if isinstance(v, pint.Quantity):
        return json.dumps(quantity_text(v, field=field), ensure_ascii=False)
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, np.integer)):
        return str(int(v))
    if isinstance(v, (float, np.floating)):
        f = float(v)
        if not math.isfinite(f):
            raise DataError(None, field, f"cannot write the non-finite value {f!r}")
        return repr(f)
    if isinstance(v, (dt.date, dt.datetime)):
        return v.isoformat()
    if isinstance(v, str):
        return json.dumps(v, ensure_ascii=False)
    if isinstance(v, (tuple, list)):
        return "[" + ", ".join(_value(x, f"{field}[{i}]") for i, x in enumerate(v)) + "]"
    raise DataError(None, field, f"cannot write a {type(v).__name__} ({v!r}) into the manifest",
                    hint="give properties and conditions as text, numbers or quantities")


def _table(lines: list[str], header: str | None, items: Mapping[str, Any], where: str) -> None:
    if header is not None:
        lines.append(header)
    for k, v in items.items():
        if v is None:
            continue
        lines.append(f"{_key(str(k))} = {_value(v, f'{where}.{k}')}")


def _calibration_items(cal: Calibration) -> dict[str, Any]:
    out: dict[str, Any] = {"certificate": cal.certificate, "U": cal.uncertainty, "k": float(cal.k)}
    if cal.due is not None:
        out["due"] = cal.due
    if cal.lab:
        out["lab"] = cal.lab
    out["distribution"] = cal.distribution
    return out


def _equipment_lines(lines: list[str], e: Equipment, i: int) -> None:
    lines += ["", "[[equipment]]"]
    head = {"id": e.id, "role": e.role, "manufacturer": e.manufacturer or None, "model": e.model or None,
            "serial": e.serial or None}
    reserved = set(head) | {"calibration"}
    clash = sorted(set(e.properties) & reserved)
    if clash:
        raise DataError(None, f"equipment[{i}]", f"property name(s) {', '.join(clash)} clash with the "
                        "manifest's own keys")
    _table(lines, None, head | dict(e.properties), f"equipment[{i}]")
    if e.calibration is not None:
        _table(lines, "[equipment.calibration]", _calibration_items(e.calibration), f"equipment[{i}].calibration")


def manifest_text(campaign: Campaign, files: Mapping[str, tuple[str, Mapping[str, str]]],
                  extra: Mapping[str, Any] | None = None) -> str:
    """The manifest of ``campaign``; ``files`` maps each segment id to (file name, {column: unit})."""
    lines = [f"# metro campaign written by metro.instruments.campaign_writer ({campaign.source or 'campaign'})",
             f"format = {json.dumps(FORMAT)}", ""]
    camp = {"id": campaign.id} | dict(campaign.meta) | dict(extra or {})
    if campaign.simulated:
        camp.setdefault("simulated", True)
    _table(lines, "[campaign]", camp, "campaign")
    d = campaign.device
    dev = {"id": d.id, "manufacturer": d.manufacturer or None, "model": d.model or None, "serial": d.serial or None,
           "technology": d.technology or None, "application": d.application or None, "output": d.output or None}
    _table(lines, "\n[device]", dev | dict(d.properties), "device")
    _table(lines, "\n[environment]", campaign.environment, "environment")
    _table(lines, "\n[site]", campaign.site, "site")
    for i, e in enumerate(campaign.equipment):
        _equipment_lines(lines, e, i)
    for seg in campaign.segments:
        fname, units = files[seg.id]
        if seg.interval is None:
            raise DataError(campaign.source, f"segments.{seg.id}.sample_interval",
                            "the segment has no sample interval; the data format requires one")
        lines += ["", "[[segments]]"]
        _table(lines, None, {"id": seg.id, "kind": seg.kind, "file": fname, "sample_interval": seg.interval},
               f"segments.{seg.id}")
        if seg.conditions:
            _table(lines, "[segments.conditions]", seg.conditions, f"segments.{seg.id}.conditions")
        _table(lines, "[segments.units]", units, f"segments.{seg.id}.units")
    for name, value in campaign.records.items():
        _record_lines(lines, str(name), value)
    return "\n".join(lines) + "\n"


def _is_table_array(v: Any) -> bool:
    return isinstance(v, (list, tuple)) and bool(v) and all(isinstance(x, Mapping) for x in v)


def _record_lines(lines: list[str], path: str, value: Any) -> None:
    """A record section (Campaign.records) as TOML: ``[path]`` for a table, ``[[path]]`` for an
    array of tables, their sub-tables below them."""
    if _is_table_array(value):
        for item in value:
            _record_table(lines, f"[[{path}]]", path, item)
    elif isinstance(value, Mapping):
        _record_table(lines, f"[{path}]", path, value)
    else:
        raise DataError(None, path, f"a record section must be a table or an array of tables, got {value!r}")


def _record_table(lines: list[str], header: str, path: str, table: Mapping[str, Any]) -> None:
    lines += ["", header]
    nested = {}
    for k, v in table.items():
        if isinstance(v, Mapping) or _is_table_array(v):
            nested[k] = v
        elif v is not None:
            lines.append(f"{_key(str(k))} = {_value(v, f'{path}.{k}')}")
    for k, v in nested.items():
        _record_lines(lines, f"{path}.{_key(str(k))}", v)


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
                            f"two segments have the id {seg.id!r} (kinds {other.kind!r} and {seg.kind!r}); "
                            "one record would replace the other, so nothing was written",
                            hint="give every segment its own id (metro.core.runner.merge_steps does for "
                            "merged sequences)")
        seen[seg.id] = seg


def _write_samples(folder: Path, stem: str, seg: Segment, npy_rows: int) -> tuple[str, dict[str, str]]:
    from .readers import write_samples_csv, write_samples_npy

    cols = seg.columns()
    if not cols:
        raise DataError(None, f"segments.{seg.id}", "the segment has no columns to write")
    arrays = {name: np.asarray(a) for name, (a, _u) in cols.items()}
    units = {name: str(u) for name, (_a, u) in cols.items()}
    rows = {len(a) for a in arrays.values()}
    if len(rows) != 1:
        raise DataError(None, f"segments.{seg.id}", f"the columns have different lengths {sorted(rows)}")
    n = rows.pop()
    name = f"{stem}.npy" if n >= npy_rows else f"{stem}.csv"
    if name.endswith(".npy"):
        write_samples_npy(folder / name, arrays, units)
    else:
        write_samples_csv(folder / name, arrays, units,
                          comments=[f"segment {seg.id} ({seg.kind}), {n} rows"])
    return name, units


# ------------------------------------------------------------------------------ the folder


def _fresh_target(out: Path) -> None:
    if out.exists() and not out.is_dir():
        raise DataError(str(out), None, "exists and is not a folder", hint="choose another --out")
    if out.is_dir() and any(out.iterdir()):
        raise DataError(str(out), None, "the folder exists and is not empty; metro never overwrites a campaign",
                        hint="choose a new --out folder or remove the old one")
    if not out.parent.is_dir():
        raise DataError(str(out), None, f"the parent folder {out.parent} does not exist")


def write_campaign(
    campaign: Campaign,
    out: str | os.PathLike[str],
    *,
    npy_rows: int = NPY_ROWS,
    extra: Mapping[str, Any] | None = None,
    progress: Progress | None = None,
) -> Path:
    """Write ``campaign`` as a folder ``out`` (manifest + samples) and return the manifest's path.

    ``out`` must not exist or be an empty folder.  Segments of ``npy_rows`` rows or more go to
    ``.npy``, shorter ones to CSV.  ``extra`` adds keys to the manifest's ``[campaign]`` table
    (e.g. the station and the items acquired).  Atomic: a hidden temporary folder is renamed
    onto ``out`` at the end; on error nothing is left behind.
    """
    out = Path(out).absolute()
    _fresh_target(out)
    _distinct_segments(campaign)
    tmp = out.with_name(f".{out.name}{TMP_MARKER}{secrets.token_hex(4)}")
    tmp.mkdir()
    try:
        stems = _file_names(campaign.segments)
        files: dict[str, tuple[str, dict[str, str]]] = {}
        total = len(campaign.segments)
        for i, seg in enumerate(campaign.segments):
            files[seg.id] = _write_samples(tmp, stems[seg.id], seg, npy_rows)
            if progress is not None:
                progress("writing samples", i + 1, total)
        atomic_write_text(tmp / MANIFEST, manifest_text(campaign, files, extra))
        _fresh_target(out)  # still free?
        if out.is_dir():
            out.rmdir()  # empty: checked above
        os.rename(tmp, out)
    except BaseException:
        shutil.rmtree(tmp, ignore_errors=True)
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
) -> Path:
    """Run the merged sequence of ``items`` on ``station`` (default: the items' own station) and
    write the campaign to ``out``; return the manifest path.  ``pm`` is a loaded plugin manager."""
    from metro.core.runner import merge_steps, split_options

    if not items:
        raise MetroError("no item given", hint="use --item, e.g. --item D.5.1")
    procs = [pm.procedure(standard, i) for i in items]
    per_opts = split_options(procs, dict(options or {}))
    if station is None:
        wanted = sorted({cls.station for cls in procs})
        if len(wanted) > 1:
            raise MetroError(f"the items need different stations ({', '.join(wanted)}); acquire them separately",
                             hint="or name one with --station")
        station = wanted[0]
    _fresh_target(Path(out).absolute())
    st = pm.station(station).factory(**dict(station_options or {}))
    sequences = [cls().sequence(cls.option_values(o)) for cls, o in zip(procs, per_opts)]
    steps = merge_steps(sequences)
    check = getattr(st, "check", None)
    if callable(check):  # a live station refuses what it cannot do before anything moves
        origin: dict[str, list[str]] = {}
        for cls, seq in zip(procs, sequences):
            for s in seq:
                origin.setdefault(s.segment, []).append(cls.qualified_id())
        check(steps, items=origin)
    if progress is not None:
        progress("acquiring", 0, len(steps))
    campaign = st.acquire(steps, progress=progress)
    if progress is not None:
        progress("acquiring", len(steps), len(steps))
    ids = {seg.id for seg in campaign.segments}
    missing = [s.segment for s in steps if s.segment not in ids and not s.is_record]
    if missing:
        raise MetroError(f"station {station!r} returned no segment for step(s) {', '.join(missing)}")
    extra = {"station": station, "standard": standard, "items": ",".join(items),
             "acquired": dt.datetime.now(dt.timezone.utc).replace(microsecond=0).isoformat()}
    return write_campaign(campaign, out, npy_rows=npy_rows, extra=extra, progress=progress)

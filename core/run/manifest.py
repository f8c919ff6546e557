"""Reading a campaign manifest (TOML) into a :class:`~metro.core.model.campaign.Campaign`.

The format is documented in docs/data-format.md.  Every problem is a
:class:`~metro.core.base.errors.DataError` naming the manifest (or samples file), the field and
the reason; nothing is evaluated until the whole manifest has been checked.
"""

from __future__ import annotations

import datetime as dt
import hashlib
import math
import tomllib

import attrs
from pathlib import Path
from typing import Any, Mapping

from ..base.errors import DataError, UnitError
from ..model.campaign import Calibration, Campaign, DeviceUnderTest, Equipment, Segment
from ..base.units import parse_quantity
from ..base import vocabulary as voc

FORMAT = "metro-campaign/1"

_DEVICE_KEYS = {"id", "manufacturer", "model", "serial", "technology", "application", "output"}
_DEVICE_QUANTITIES = {"scale_factor": None, "scale_factor_U": None}
#: the manifest's own top-level keys; every other table is a record section (Campaign.records)
CORE_KEYS = frozenset({"format", "campaign", "device", "environment", "site", "equipment",
                       "segments",
                       "specification"})
_TECH = {"laser", "fibre", "fiber", "mems", "vibratory", "other", ""}
_OUTPUT = {"pulse", "digital", "analog", "rate", ""}


def _table(doc: Mapping, key: str, src: str, *, required: bool = True) -> Mapping:
    v = doc.get(key)
    if v is None:
        if required:
            raise DataError(src, f"[{key}]", "missing table",
                            hint=f"add a [{key}] table (docs/data-format.md)")
        return {}
    if not isinstance(v, dict):
        raise DataError(src, key, f"must be a table, got {type(v).__name__}")
    return v


def _str(t: Mapping, key: str, src: str, where: str, *, required: bool = True,
         default: str = "") -> str:
    v = t.get(key)
    if v is None:
        if required:
            raise DataError(src, f"{where}.{key}", "missing",
                            hint=f"add {key} = \"…\" to [{where}]")
        return default
    if isinstance(v, bool) or not isinstance(v, (str, int)):
        raise DataError(src, f"{where}.{key}", f"must be text, got {_short(v)}")
    return _bounded(str(v), src, f"{where}.{key}")


def _short(v: Any) -> str:
    text = repr(v)
    return text if len(text) <= 60 else text[:57] + "…"


def _bounded(text: str, src: str, field: str) -> str:
    """Text no longer than :data:`metro.core.base.vocabulary.MAX_TEXT` characters (a report must
    stay renderable) and without control characters other than a line break."""
    if len(text) > voc.MAX_TEXT:
        raise DataError(src, field, f"{len(text)} characters; at most {voc.MAX_TEXT} are taken",
                        hint="shorten it; long descriptions belong in a separate document")
    bad = next((c for c in text if ord(c) < 32 and c not in "\n\t" or ord(c) == 127), None)
    if bad is not None:
        raise DataError(src, field, f"contains the control character U+{ord(bad):04X}")
    return text


def _condition_value(v: Any, src: str, field: str) -> Any:
    """A segment condition: as :func:`maybe_quantity`, except that a text without a digit stays
    text.

    A condition is a quantity only when written with its number (``"10 deg/s"``, ``"-55 °C"``); a
    word such as a test's tag (``test = "acc"``, ``"dh"``, ``"rad"`` of GB/T 45570 6.2.8) is a name
    even when pint knows it as a unit (attocubic centimetre, decihour, radian) — read as ``1 acc``
    it matched no tag and the records were silently unused. A condition read with a dimension
    (``Segment.condition(name, unit)``) is parsed there as before; ``"inf °C"`` and ``"nan"`` are
    still refused."""
    if isinstance(v, str) and not any(ch.isdigit() for ch in v):
        try:
            q = parse_quantity(v, file=src, field=field)
        except UnitError:
            return _bounded(v, src, field)
        try:
            finite = math.isfinite(float(q.magnitude))
        except (TypeError, ValueError):
            finite = False
        if finite:
            return _bounded(v, src, field)
    return maybe_quantity(v, src, field)


def maybe_quantity(v: Any, src: str, field: str) -> Any:
    """Values written as text with a unit become quantities; plain text stays text."""
    if isinstance(v, str):
        try:
            q = parse_quantity(v, file=src, field=field)
        except UnitError:
            return _bounded(v, src, field)
        _finite(q, src, field)
        return q
    if isinstance(v, bool):
        return v
    if isinstance(v, float) and not math.isfinite(v):
        raise DataError(src, field, f"{v!r} is not a finite number")
    if isinstance(v, (int, float)):
        return v
    return v


def _finite(q, src: str, field: str):
    """A quantity whose magnitude is a finite number (``inf °C``, ``nan`` are refused)."""
    import numpy as np

    mag = np.asarray(q.magnitude, dtype=float)
    if not np.all(np.isfinite(mag)):
        raise DataError(src, field, f"{q.magnitude!r} is not a finite number")
    return q


def _in_range(q, unit: str, lo: float | None, hi: float | None, src: str, field: str, why: str):
    """``q`` in ``unit`` within [lo, hi] (a :class:`DataError` saying ``why`` otherwise)."""
    _finite(q, src, field)
    v = float(q.to(unit).magnitude)
    if (lo is not None and v < lo) or (hi is not None and v > hi):
        raise DataError(src, field, f"{q:~P} is {why}")
    return q


def _calibration(t: Mapping, src: str, where: str) -> Calibration:
    cert = _str(t, "certificate", src, where)
    if "U" not in t:
        raise DataError(src, f"{where}.U", "missing expanded uncertainty",
                        hint="write U = \"0.5 arcsec\" (absolute) or U = \"1e-4\" (relative) with "
                        "its k")
    if isinstance(t["U"], bool) or not isinstance(t["U"], (str, int, float)):
        raise DataError(src, f"{where}.U",
                        "must be a quantity such as \"2e-7\" or \"0.5 arcsec\", got "
                        f"{_short(t['U'])}")
    U = parse_quantity(t["U"] if not isinstance(t["U"], (int, float)) else str(t["U"]), file=src,
                       field=f"{where}.U")
    _finite(U, src, f"{where}.U")
    # an uncertainty is a difference: "0.5 °C" (a chamber's U, as docs/data-format.md lists it) is
    # 0.5 K, not the temperature 0.5 °C, on which no budget row can be multiplied (pint refuses an
    # offset unit: a traceback on the independent harness's JJF 2014 7.2.5/7.2.16 campaigns)
    from ..base.units import Q_, difference_unit

    U = Q_(float(U.magnitude), difference_unit(U.units))
    if float(U.magnitude) < 0:
        raise DataError(src, f"{where}.U", f"{U:~P} is negative; an expanded uncertainty is ≥ 0")
    k = t.get("k", 2.0)
    if isinstance(k, bool) or not isinstance(k, (int, float)) or not 0 < k < 100:
        raise DataError(src, f"{where}.k",
                        f"must be a positive number (a coverage factor, e.g. 2), got {_short(k)}")
    due = t.get("due")
    if due is not None and not isinstance(due, dt.date):
        try:
            due = dt.date.fromisoformat(str(due))
        except ValueError as exc:
            raise DataError(src, f"{where}.due", f"not a date (YYYY-MM-DD): {due!r}") from exc
    dist = _str(t, "distribution", src, where, required=False, default="normal")
    if dist not in ("normal", "uniform"):
        raise DataError(src, f"{where}.distribution", f"must be normal or uniform, got {dist!r}")
    return Calibration(cert, U, float(k), due, _str(t, "lab", src, where, required=False), dist)


def calibration_from_table(t: Mapping, src: str, where: str) -> Calibration:
    """A ``[….calibration]`` table (certificate, U, k, due, lab, distribution), checked."""
    return _calibration(t, src, where)


def _typos(t: Mapping, src: str, where: str, known, what: str, warnings: list[str] | None) -> None:
    """Warn about keys of an open table (whose other keys are kept as properties) that look like
    a misspelling of a key metro reads (``temprature``)."""
    if warnings is None:
        return
    known = list(known)
    for key in t:
        if key in known:
            continue
        guess = voc.did_you_mean(key, known, cutoff=0.8)
        if guess is not None:
            warnings.append(f"{src}: field '{where}.{key}': not a key metro reads (kept as a "
                            f"property) — did you mean {guess!r}?")


def _closed(t: Mapping, src: str, where: str, known, what: str, warnings: list[str] | None) -> None:
    """Warn about every key of a closed table that is in no list (with a "did you mean")."""
    if warnings is None:
        return
    known = list(known)
    for key in t:
        if key not in known:
            warnings.append(voc.unknown_key_warning(src, f"{where}.{key}" if where else key, key,
                                                    known, what))


def device_from_table(dev_t: Mapping, src: str, warnings: list[str]
                      | None = None) -> DeviceUnderTest:
    """The manifest's ``[device]`` table as a :class:`DeviceUnderTest` (also used by bench
    files)."""
    dev_id = _str(dev_t, "id", src, "device")
    if not dev_id.strip():
        raise DataError(src, "device.id",
                        "empty; the device needs an id (its serial number will do)")
    _typos(dev_t, src, "device", voc.DEVICE_KEYS, "device", warnings)
    tech = _str(dev_t, "technology", src, "device", required=False).lower()
    if tech not in _TECH:
        raise DataError(src, "device.technology",
                        f"unknown technology {tech!r}; use one of laser, fibre, mems, vibratory, "
                        "other")
    application = _str(dev_t, "application", src, "device", required=False).strip().lower()
    if application not in voc.APPLICATIONS:
        guess = voc.did_you_mean(application, [a for a in voc.APPLICATIONS if a])
        raise DataError(src, "device.application", f"unknown application {application!r}"
                        + (f" — did you mean {guess!r}?" if guess else ""),
                        hint="use one of " + ", ".join(sorted(a for a in voc.APPLICATIONS if a))
                        + " (or leave it out)")
    output = _str(dev_t, "output", src, "device", required=False).lower()
    if output not in _OUTPUT:
        raise DataError(src, "device.output",
                        f"unknown output {output!r}; use pulse, digital, analog or rate")
    props: dict[str, Any] = {}
    for key, val in dev_t.items():
        if key in _DEVICE_KEYS:
            continue
        if key == "scale_factor_k":
            if isinstance(val, bool) or not isinstance(val, (int, float)) or not 0 < val < 100:
                raise DataError(src, "device.scale_factor_k",
                                f"must be a positive number, got {val!r}")
            props[key] = float(val)
        elif key in _DEVICE_QUANTITIES:
            if isinstance(val, bool) or not isinstance(val, (str, int, float)):
                raise DataError(src, f"device.{key}",
                                f"must be a quantity with its unit, got {_short(val)}")
            q = _finite(parse_quantity(val if not isinstance(val, (int, float)) else str(val),
                                       file=src,
                                       field=f"device.{key}"), src, f"device.{key}")
            if key == "scale_factor" and not float(q.magnitude) > 0:
                raise DataError(src, "device.scale_factor",
                                f"{q:~P}: a scale factor must be positive (zero "
                                "would turn every output into an infinite rate)",
                                hint="K is a magnitude; the sign of the "
                                "output is the polarity item's (GB/T 45570 6.2.6)")
            if key == "scale_factor_U" and float(q.magnitude) < 0:
                raise DataError(src, "device.scale_factor_U",
                                f"{q:~P} is negative; an expanded uncertainty is ≥ 0")
            props[key] = q
        else:
            props[key] = maybe_quantity(val, src, f"device.{key}")
    return DeviceUnderTest(
        id=dev_id, model=_str(dev_t, "model", src, "device", required=False),
        serial=_str(dev_t, "serial", src, "device", required=False),
        manufacturer=_str(dev_t, "manufacturer", src, "device", required=False),
        properties=props, technology="fibre" if tech == "fiber" else tech,
        application=application, output=output,
    )


def environment_from_table(env_t: Mapping, src: str, warnings: list[str]
                           | None = None) -> dict[str, Any]:
    """The ``[environment]`` table: temperature and humidity required, other keys kept."""
    _typos(env_t, src, "environment", voc.ENVIRONMENT_KEYS, "environment", warnings)
    environment: dict[str, Any] = {}
    for key, dim in (("temperature", "degC"), ("humidity", "percent")):
        if key not in env_t:
            raise DataError(src, f"environment.{key}", "missing",
                            hint=f"add {key} = \"…\" under [environment]")
        environment[key] = parse_quantity(env_t[key], dimension=dim, file=src,
                                          field=f"environment.{key}")
    _in_range(environment["temperature"], "degC", *voc.TEMPERATURE_RANGE_C, src,
              "environment.temperature",
              f"not a test environment's temperature ({voc.TEMPERATURE_RANGE_C[0]:g} °C … "
              f"{voc.TEMPERATURE_RANGE_C[1]:g} °C; −273.15 °C is absolute zero)")
    _in_range(environment["humidity"], "percent", 0.0, 100.0, src, "environment.humidity",
              "not a relative humidity (0 % … 100 %)")
    for key, val in env_t.items():
        if key not in environment:
            environment[key] = maybe_quantity(val, src, f"environment.{key}")
    p = environment.get("pressure")
    if p is not None and hasattr(p, "units"):
        if p.dimensionality != parse_quantity("1 kPa").dimensionality:
            raise DataError(src, "environment.pressure", f"{p:~P} is not a pressure",
                            hint="write e.g. \"101.3 kPa\"")
        _in_range(p, "kPa", 0.0, 1000.0, src, "environment.pressure",
                  "not an air pressure (0 … 1000 kPa)")
    return environment


def site_from_table(site_t: Mapping, src: str, warnings: list[str] | None = None) -> dict[str, Any]:
    """The ``[site]`` table: the latitude required (−90° … 90°), other keys kept."""
    _typos(site_t, src, "site", voc.SITE_KEYS, "site", warnings)
    if "latitude" not in site_t:
        raise DataError(src, "site.latitude", "missing",
                        hint="add latitude = \"39.98°\" under [site]")
    site: dict[str, Any] = {"latitude": parse_quantity(site_t["latitude"], dimension="deg",
                                                       file=src, field="site.latitude")}
    lat = site["latitude"].to("deg").magnitude
    if not -90 <= lat <= 90:
        raise DataError(src, "site.latitude", f"{lat:g}° is not a latitude (−90° … 90°)")
    for key, val in site_t.items():
        if key not in site:
            site[key] = maybe_quantity(val, src, f"site.{key}")
    if "latitude_uncertainty" in site:
        q = site["latitude_uncertainty"]
        if not hasattr(q, "units"):
            raise DataError(src, "site.latitude_uncertainty",
                            f"must be an angle such as \"0.001°\", got {_short(q)}")
        q = parse_quantity(f"{q.magnitude} {q.units}", dimension="deg", file=src,
                           field="site.latitude_uncertainty")
        _in_range(q, "deg", 0.0, 90.0, src, "site.latitude_uncertainty",
                  "not a latitude uncertainty (a half-width, 0° … 90°)")
    return site


def equipment_from_table(e: Mapping, src: str, where: str, warnings: list[str]
                         | None = None) -> Equipment:
    """One ``[[equipment]]`` table (id, role, model, serial, manufacturer, properties, calibration).

    The role is stored in its canonical spelling (:mod:`metro.core.base.vocabulary`); an old
    spelling (``rate-table``) or a role no item looks for is reported in ``warnings``."""
    if not isinstance(e, dict):
        raise DataError(src, where, f"must be a table, got {type(e).__name__}")
    eid = _str(e, "id", src, where)
    if not eid.strip():
        raise DataError(src, f"{where}.id", "empty; every piece of equipment needs an id")
    role = _str(e, "role", src, where)
    if warnings is not None:
        new = voc.role_alias(role)
        if new is not None:
            warnings.append(voc.deprecated_warning(src, f"{where}.role", role, new, "role"))
        elif voc.canonical_role(role) not in voc.ROLES:
            guess = voc.did_you_mean(voc.canonical_role(role), voc.ROLES)
            warnings.append(f"{src}: field '{where}.role': no item looks for the role {role!r}"
                            + (f" — did you mean {guess!r}?" if guess else
                               f" (roles: {', '.join(sorted(voc.ROLES))})"))
    _typos(e, src, where, voc.EQUIPMENT_KEYS, "equipment", warnings)
    if "calibration" in e and not isinstance(e["calibration"], dict):
        raise DataError(src, f"{where}.calibration", "must be a table ([equipment.calibration])")
    if "calibration" in e:
        _closed(e["calibration"], src, f"{where}.calibration", voc.CALIBRATION_KEYS, "calibration",
                warnings)
    cal = _calibration(e["calibration"], src,
                       f"{where}.calibration") if "calibration" in e else None
    eprops = {k: maybe_quantity(v, src, f"{where}.{k}") for k, v in e.items()
              if k not in {"id", "role", "model", "serial", "manufacturer", "calibration"}}
    return Equipment(
        id=eid,
        role=_str(e, "role", src, where),
        model=_str(e, "model", src, where, required=False),
        serial=_str(e, "serial", src, where, required=False),
        manufacturer=_str(e, "manufacturer", src, where, required=False),
        properties=eprops,
        calibration=cal,
    )


def read_toml(path: str | Path, fmt: str, *, what: str, hint: str) -> tuple[str, dict[str, Any]]:
    """``(source text, document)`` of a metro TOML file (a manifest, a bench file) whose
    ``format`` key, if given, must be ``fmt``; a missing, undecodable or invalid file is a
    :class:`DataError` naming it (``what`` and ``hint`` say what was expected)."""
    src, doc, _ = read_toml_digest(path, fmt, what=what, hint=hint)
    return src, doc


#: a manifest larger than this is not a manifest (samples belong in their own files)
MAX_MANIFEST_BYTES = 16 * 1024 * 1024


def read_toml_digest(path: str | Path, fmt: str, *, what: str,
                     hint: str) -> tuple[str, dict[str, Any], str]:
    """As :func:`read_toml`, with the SHA-256 of the bytes that were parsed."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise DataError(src, None, f"{what} not found", hint=hint)
    try:
        raw = p.read_bytes()
    except OSError as exc:
        raise DataError(src, None, f"cannot read the {what}: {exc.strerror or exc}") from exc
    if len(raw) > MAX_MANIFEST_BYTES:
        raise DataError(src, None, f"{len(raw)} bytes is too large for a {what} "
                        f"(at most {MAX_MANIFEST_BYTES} bytes)")
    digest = hashlib.sha256(raw).hexdigest()
    try:
        # utf-8-sig: a byte-order mark (Windows Notepad, Excel exports) is not part of the TOML
        doc = tomllib.loads(raw.decode("utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise DataError(src, None, f"not UTF-8 text ({exc})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise DataError(src, None, f"not valid TOML: {exc}") from exc
    voc.check_characters(doc, src)
    found = doc.get("format", fmt)
    if found != fmt:
        raise DataError(src, "format",
                        f"unsupported format {_short(found)}; this metro reads {fmt!r}")
    return src, doc, digest


def equipment_list(doc: Mapping[str, Any], src: str, lab_equipment: Mapping[str, Equipment] | None,
                   warnings: list[str]) -> list[Equipment]:
    """The manifest's ``[[equipment]]`` (docs/data-format.md): each entry read, or the lab
    profile's entry of that id when it gives no calibration of its own (only its role may
    change)."""
    equipment = []
    seen: set[str] = set()
    eq_list = doc.get("equipment", [])
    if not isinstance(eq_list, list):
        raise DataError(src, "equipment", "must be an array of tables ([[equipment]])")
    for i, e in enumerate(eq_list):
        where = f"equipment[{i}]"
        if not isinstance(e, dict):
            raise DataError(src, where, f"must be a table, got {type(e).__name__}")
        eid = _str(e, "id", src, where)
        if eid in seen:
            raise DataError(src, f"{where}.id", f"duplicate equipment id {eid!r}")
        seen.add(eid)
        if lab_equipment and eid in lab_equipment and "calibration" not in e:
            # the lab profile's equipment named by id: its calibration, model, serial from the
            # profile; a role given here replaces the profile's
            known = lab_equipment[eid]
            extra = sorted(set(e) - {"id", "role"})
            if extra:
                raise DataError(src, f"{where}.{extra[0]}",
                                f"equipment {eid!r} is the lab profile's "
                                f"({getattr(known, 'source', '') or 'lab profile'}); only its role "
                                "may be given here",
                                hint="change it in the lab profile, or give this entry another id")
            role = _str(e, "role", src, where, required=False) or known.role
            equipment.append(attrs.evolve(known, role=role))
            continue
        if "role" not in e and lab_equipment is not None:
            raise DataError(src, f"{where}.role",
                            f"missing, and the lab profile names no equipment {eid!r}",
                            hint="the lab profile's equipment: "
                            + (", ".join(sorted(lab_equipment)) or "none"))
        equipment.append(equipment_from_table(e, src, where, warnings))

    return equipment


def segment_list(seg_list: list, path: Path, src: str, device: Any, reader_for,
                 warnings: list[str]) -> list[Segment]:
    """The manifest's ``[[segments]]``: ids unique, each samples file present and read by one
    segment of a kind, with its sample interval, start, conditions and declared units."""
    segments = []
    seen = set()
    read_by: dict[tuple[Path, str], str] = {}  # (samples file, kind) -> the segment reading it
    for i, s in enumerate(seg_list):
        segments.append(segment_from_table(s, i, path, src, device, reader_for, warnings, seen,
                                           read_by))
    return segments


def segment_from_table(s: Any, i: int, path: Path, src: str, device: Any, reader_for,
                       warnings: list[str],
                       seen: set[str], read_by: dict[tuple[Path, str], str]) -> Segment:
    """One ``[[segments]]`` entry (index ``i``) as a :class:`Segment` whose loader reads its
    file."""
    where = f"segments[{i}]"
    if not isinstance(s, dict):
        raise DataError(src, where, f"must be a table, got {type(s).__name__}")
    _closed(s, src, where, voc.SEGMENT_KEYS, "segment", warnings)
    sid = _str(s, "id", src, where)
    if not sid.strip():
        raise DataError(src, f"{where}.id", "empty; every segment needs an id")
    if sid in seen:
        raise DataError(src, f"{where}.id", f"duplicate segment id {sid!r}")
    seen.add(sid)
    kind = _str(s, "kind", src, where)
    fname = _str(s, "file", src, where)
    fpath = (path.parent / fname).resolve()
    if not fpath.is_file():
        raise DataError(src, f"{where}.file",
                        f"samples file {fname!r} not found (looked in {fpath.parent})")
    other = read_by.get((fpath, kind))
    if other is not None:  # one record cannot be two measurements of one kind (two rates, two runs)
        raise DataError(
            src,
            f"{where}.file",
            f"segment {sid!r} reads {fname!r}, the samples file of segment {other!r} "
            f"of the same kind {kind!r}: each measurement has its own record",
            hint="give each segment the file it was recorded in (a file-name typo, or "
            "a name cut "
            "at a dot such as 'rate+0.25' -> 'rate+0.csv'?)",
        )
    read_by[(fpath, kind)] = sid
    if "sample_interval" not in s:
        raise DataError(src, f"{where}.sample_interval", "missing",
                        hint="add sample_interval = \"1 s\"")
    interval = parse_quantity(s["sample_interval"], dimension="s", file=src,
                              field=f"{where}.sample_interval")
    if not interval.magnitude > 0 or not math.isfinite(interval.magnitude):
        raise DataError(src, f"{where}.sample_interval", "must be a positive, finite time")
    started = _started(s.get("started"), src, f"{where}.started")
    conds = s.get("conditions", {})
    if not isinstance(conds, dict):
        raise DataError(src, f"{where}.conditions", "must be a table")
    conditions = {k: _condition_value(v, src, f"{where}.conditions.{k}") for k, v in conds.items()}
    if "supply" not in conditions and "supply_voltage" in device.properties:
        # a ratiometric output's reference
        conditions["supply"] = device.properties["supply_voltage"]
    declared = s.get("units", {})
    if not isinstance(declared, dict):
        raise DataError(src, f"{where}.units", "must be a table of column = \"unit\"")
    for col, utext in declared.items():
        if not isinstance(utext, str):
            raise DataError(src, f"{where}.units.{col}",
                            f"must be a unit as text, got {_short(utext)}")
        try:
            parse_quantity(f"1 {utext}", file=src, field=f"{where}.units.{col}")
        except DataError as exc:
            raise DataError(src, f"{where}.units.{col}", f"{utext!r} is not a unit metro knows",
                            hint="write the unit as in the samples file's header, e.g. \"P\", "
                            "\"LSB\", \"°/h\"") from exc
    reader = reader_for(fpath)
    interval_s = float(interval.to("s").magnitude)
    return Segment(
        id=sid, kind=kind, conditions=conditions, interval=interval, file=str(fpath),
        sha256=None, declared_units={k: str(v) for k, v in declared.items()},
        loader=_make_loader(reader.read, fpath, interval_s, declared), started=started,
    )


def load_manifest(path: str | Path, reader_for, *, lab_equipment: Mapping[str, Equipment]
                  | None = None) -> Campaign:
    """Read and validate a manifest; ``reader_for(path)`` returns the registered reader
    (an object with ``read``) for a samples file (the plugin manager's ``reader_for``).

    What is read but not refused — a deprecated spelling, a key in no list — is in the
    campaign's ``warnings``; the manifest's SHA-256 is its ``manifest_sha256``."""
    path = Path(path)
    src, doc, digest = read_toml_digest(path, FORMAT, what="manifest",
                                        hint="give the path of a manifest.toml "
                                        "(docs/data-format.md)")
    warnings: list[str] = []
    _closed(doc, src, "", voc.SECTIONS, "top-level", warnings)

    camp = campaign_meta(_table(doc, "campaign", src, required=False), src, warnings)
    device = device_from_table(_table(doc, "device", src), src, warnings)
    environment = environment_from_table(_table(doc, "environment", src), src, warnings)
    site = site_from_table(_table(doc, "site", src), src, warnings)

    equipment = equipment_list(doc, src, lab_equipment, warnings)

    records = {k: v for k, v in doc.items() if k not in CORE_KEYS and isinstance(v, (dict, list))}
    seg_list = doc.get("segments")
    if not seg_list and not records:
        raise DataError(src, "segments",
                        "no [[segments]] given; a campaign needs at least one measured segment "
                        "(or record sections such as [inspection], docs/data-format.md)")
    if seg_list is not None and not isinstance(seg_list, list):
        raise DataError(src, "segments", "must be an array of tables ([[segments]])")
    segments = segment_list(seg_list or [], path, src, device, reader_for, warnings)

    spec_t = _table(doc, "specification", src, required=False)
    specification = _specification(spec_t, src)

    simulated = camp.get("simulated", False)
    if not isinstance(simulated, bool):
        raise DataError(src, "campaign.simulated", f"must be true or false, got {simulated!r}",
                        hint="metro acquire writes simulated = true for data from a simulated "
                        "station")
    return Campaign(
        id=_str(camp, "id", src, "campaign", required=False, default=path.parent.name),
        device=device, equipment=equipment, environment=environment, site=site, segments=segments,
        source=src, simulated=simulated,
        meta={k: v for k, v in camp.items() if k != "id"},
        specification=specification, manifest_sha256=digest, warnings=warnings, records=records,
    )


def _started(v: Any, src: str, field: str) -> dt.datetime | None:
    """A segment's optional ``started``: when its first sample was taken, an RFC 3339 date-time with
    its UTC offset (a TOML offset date-time or the same as text), e.g. 2026-11-24T10:15:00+08:00."""
    if v is None:
        return None
    hint = (
        'write the time the record began with its UTC offset, e.g. started = '
        '"2026-11-24T10:15:00+08:00"'
    )
    if isinstance(v, dt.datetime):
        t = v
    elif isinstance(v, str):
        text = v.strip()
        if text.endswith(("Z", "z")):
            text = text[:-1] + "+00:00"
        try:
            t = dt.datetime.fromisoformat(text)
        except ValueError:
            raise DataError(src, field, f"not a date and time: {_short(v)}", hint=hint) from None
        if "T" not in text.upper() and " " not in text:
            raise DataError(src, field, f"{_short(v)} is a date without the time of day", hint=hint)
    else:
        what = ("a date without the time of day" if isinstance(v, dt.date)
                else f"not a date and time: {_short(v)}")
        raise DataError(src, field, what, hint=hint)
    if t.utcoffset() is None:
        raise DataError(src, field,
                        f"{t.isoformat()} has no UTC offset; a recording time must say its time "
                        "zone",
                        hint=hint)
    return t


def campaign_meta(t: Mapping, src: str, warnings: list[str] | None = None) -> dict[str, Any]:
    """The ``[campaign]`` table with canonical keys (:mod:`metro.core.base.vocabulary`): an old
    spelling (``laboratory``, ``tested_by``, ``issuer``, ``date`` …) is read under its canonical
    key with a deprecation warning; people, lab and customer must be text, dates dates."""
    out: dict[str, Any] = {}
    for key, val in t.items():
        canon = voc.campaign_key(key)
        field = f"campaign.{key}"
        if canon != key:
            if warnings is not None:
                warnings.append(voc.deprecated_warning(src, field, key, canon))
            if canon in t or canon in out:
                raise DataError(src, field, f"given twice: as {key!r} and as {canon!r}",
                                hint=f"keep {canon!r} only")
        elif canon not in voc.CAMPAIGN_KEYS and warnings is not None:
            warnings.append(voc.unknown_key_warning(src, field, key, voc.CAMPAIGN_KEYS,
                                                    "[campaign]"))
        if canon in voc.DATE_KEYS:
            if isinstance(val, dt.datetime):
                val = val.date()
            elif not isinstance(val, dt.date):
                try:
                    val = dt.date.fromisoformat(str(val).strip())
                except ValueError:
                    raise DataError(src, field, f"not a date (YYYY-MM-DD): {_short(val)}") from None
        elif canon in ("simulated",):
            pass
        elif isinstance(val, str):
            val = _bounded(val, src, field)
        elif canon in ("id", "customer", "customer_address", "lab", "lab_address", "location",
                       *voc.PEOPLE_KEYS):
            raise DataError(src, field, f"must be text, got {_short(val)}")
        out[canon] = val
    return out


def _specification(t: Mapping, src: str) -> dict[str, Any]:
    """The ``[specification]`` table as written: flat ``symbol = "limit"`` lines (the old form),
    ``[specification.<standard>]`` tables and ``"<standard>:<key>"`` lines, ``decision_rule`` and
    ``source``; every limit and rule is checked now, so a bad one is reported before anything is
    evaluated (which lines judge which standard is the runner's: ``conformity.limits_for``)."""
    from ..uncertainty.conformity import rule_named, specifications_from_table, split_table

    flat, by_std = split_table(t, file=src)
    for lines in [flat, *by_std.values()]:
        if "decision_rule" in lines:
            field, text = lines["decision_rule"]
            try:
                rule_named(text)
            except DataError as exc:
                raise DataError(src, field, exc.detail) from exc
        specifications_from_table({k: v for k, (_, v) in lines.items()}, file=src,
                                  fields={k: f for k, (f, _) in lines.items()})
    return {k: dict(v) if isinstance(v, Mapping) else v for k, v in t.items()}


class _Columns(dict):
    """Columns of a samples file, with the SHA-256 of its bytes (computed while reading)."""

    sha256: str | None = None


def _make_loader(read, fpath: Path, interval_s: float, declared: Mapping[str, str]):
    def load():
        table = read(fpath)
        out = _Columns()
        for name, arr in table.columns.items():
            _check_magnitudes(fpath, name, arr)
            out[name] = (arr, table.units[name])
        if "time" in out:
            _check_time_interval(fpath, out["time"], interval_s)
        out.sha256 = table.sha256
        return out

    return load


#: the largest sample magnitude taken: beyond 2⁵³ a float64 no longer holds whole counts
#: exactly, and no gyro output (counts, LSB, mV, °/h) comes near it — such a value is a
#: corrupt or mis-scaled record (1e20, ±1e308 would overflow the statistics)
MAX_SAMPLE = float(2**53)


def _check_magnitudes(fpath: Path, column: str, arr) -> None:
    """Every sample finite and within ±:data:`MAX_SAMPLE` (one vectorised pass), else a
    :class:`DataError` naming the file, the column and the first row."""
    import numpy as np

    a = np.asarray(arr)
    if a.dtype.kind not in "fiu" or a.size == 0:
        return
    if a.dtype.kind in "iu" and a.dtype.itemsize < 8:
        return
    bad = ~(np.abs(a) <= MAX_SAMPLE) if a.dtype.kind == "f" else (np.abs(a.astype(np.float64))
                                                                  > MAX_SAMPLE)
    if bad.any():
        i = int(np.argmax(bad))
        raise DataError(str(fpath), column,
                        f"row {i + 1}: {float(a[i]):g} is not a plausible sample "
                        f"(|x| ≤ 2⁵³ ≈ {MAX_SAMPLE:.3g}, finite)",
                        hint="check the record for corruption or a wrong scale")


def _check_time_interval(fpath: Path, time_col, interval_s: float) -> None:
    """The time column's step (in its header unit) must equal the manifest's sample_interval."""
    arr, utext = time_col
    try:
        u = parse_quantity(f"1 {utext}", dimension="s", file=str(fpath), field="time")
    except DataError:
        raise
    if arr.size < 2:
        return
    step = float(arr[1] - arr[0]) * float(u.to("s").magnitude)
    if abs(step - interval_s) > 1e-6 * interval_s:
        raise DataError(
            str(fpath), "time",
            f"the time column steps by {step:g} s but the manifest's sample_interval is "
            f"{interval_s:g} s",
            hint="correct sample_interval in the manifest or the time column",
        )

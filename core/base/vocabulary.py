"""The manifest's vocabulary: one spelling for every key a standard's plugin reads.

One lab manifest serves every standard: the people who test, check and approve, the lab, the
customer, the dates and the equipment roles have one canonical key each, whichever plugin reads
them.  Spellings that earlier plugins used (``laboratory``, ``tested_by``, ``calibrated_by``,
``issuer``, ``date``, the role ``rate-table`` …) are still read, each with a deprecation warning
that names the canonical key; a key that is in no list is reported with a "did you mean"
(:mod:`difflib`), never ignored without a word.

The lists are extensible: a plugin that reads a manifest section or a device property of its
own registers it (:func:`register_section`, :func:`register_device_property`,
:func:`register_role`) when its module is imported, so that the unknown-key check knows it.

Kept light (no numpy/pint): :mod:`metro.core.model` uses it in converters.
"""

from __future__ import annotations

import datetime as dt
import difflib
import re
from typing import Any, Iterable, Mapping

import attrs

from .errors import DataError

__all__ = [
    "CAMPAIGN_KEYS", "CAMPAIGN_ALIASES", "ROLES", "ROLE_ALIASES", "SECTIONS", "DEVICE_KEYS",
    "MAX_TEXT", "NOT_XML", "check_characters", "People", "Lab", "Customer",
    "canonical_role", "role_alias", "campaign_key", "did_you_mean", "unknown_key_warning",
    "register_section", "register_device_property", "register_role", "register_campaign_key",
    "people_of", "lab_of", "customer_of", "date_of",
]

#: the longest text metro takes in a manifest value (an id, a name, an address …): a report
#: must stay renderable, and a 1 MB "device name" is an input mistake, not a name
MAX_TEXT = 500

# -----------------------------------------------------------------------------------------
# [campaign]: identification, people, lab, customer, dates
# -----------------------------------------------------------------------------------------

#: canonical key -> meaning (docs/data-format.md prints the same table)
CAMPAIGN_KEYS: dict[str, str] = {
    "id": "campaign identification (default: the manifest's folder name)",
    "customer": "the customer (who ordered the test or calibration)",
    "customer_address": "the customer's address",
    "lab": "the laboratory that performs the test or calibration",
    "lab_address": "the laboratory's address",
    "location": "where the measurement was made, when not at the laboratory's address",
    "operator": "who performed the measurement (tested by / calibrated by)",
    "checked_by": "who checked the results",
    "approved_by": "who approved (issued) the report or certificate",
    "approved_by_title": "the approver's title, e.g. head of laboratory",
    "operator_title": "the operator's title, e.g. calibration engineer",
    "checked_by_title": "the checker's title",
    "measurement_date": ("the day of the measurement (YYYY-MM-DD); reports print it as the test "
                         "date"),
    "date_received": "the day the device was received (YYYY-MM-DD)",
    "notes": "free text kept with the campaign",
    # written by metro acquire
    "simulated": "true for data from a simulated station (metro acquire writes it)",
    "station": "the station the campaign was acquired on (metro acquire)",
    "standard": "the standard whose items were acquired (metro acquire)",
    "items": "the items acquired (metro acquire)",
    "acquired": "when the campaign was acquired, UTC (metro acquire)",
    "bench": "the bench file of a live acquisition (metro acquire --station bench)",
    "bench_id": "the bench's id (metro acquire --station bench)",
    "rate_table": "the rate table's identity on a live bench (metro acquire --station bench)",
    "output": "the device output's identity on a live bench (metro acquire --station bench)",
    "operator_steps": "how many steps the bench asked the operator to do (metro acquire --station "
    "bench)",
}

#: old spelling -> canonical key (read, with a deprecation warning)
CAMPAIGN_ALIASES: dict[str, str] = {
    "laboratory": "lab",
    "laboratory_address": "lab_address",
    "tested_by": "operator",
    "calibrated_by": "operator",
    "checker": "checked_by",
    "issuer": "approved_by",
    "issuer_title": "approved_by_title",
    "date": "measurement_date",
    "received": "date_received",
}

#: the [campaign] keys that name a person
PEOPLE_KEYS = ("operator", "checked_by", "approved_by", "approved_by_title", "operator_title",
               "checked_by_title")
#: the [campaign] keys that are dates
DATE_KEYS = ("measurement_date", "date_received")

# -----------------------------------------------------------------------------------------
# equipment roles
# -----------------------------------------------------------------------------------------

#: canonical role -> what it is; procedures find their equipment by role
ROLES: dict[str, str] = {
    "rate_table": "rate / position table (single or multi-axis) turning the device",
    "position_table": "position table setting the device's attitude (JJF 2014 table 2)",
    "tilt_table": "two-axis tilt table (GB/T 45570 D.4)",
    "turntable": ("low-speed turntable of an angle measuring instrument's calibration (ogam "
                  "table 1)"),
    "platform": "levelled stable platform",
    "counter": "gyro test system / counter (its time base)",
    "dmm": "digital multimeter / data acquisition of an analog output",
    "acquisition": "data acquisition of a digital output (its bits give the quantization)",
    "timer": "timer / time base",
    "chamber": "temperature chamber",
    "field_generator": "DC magnetic field generator",
    "fixture": "fixture holding the device's XRA/YRA along the table axis",
    "vibration_table": "(linear) vibration table",
    "angular_vibration_table": "angular vibration table (JJF 2014 7.2.22)",
    "shock_table": "shock table",
    "voltmeter": "voltage measuring equipment",
    "ammeter": "current measuring equipment",
}

#: the kinds of unit a role's calibration U is used in by the built-in items ("" relative, else
#: a unit of the accepted kind); an item's EquipmentRequirement.calibration overrides it
ROLE_CALIBRATION: dict[str, tuple[str, ...]] = {
    "rate_table": ("",),
    "position_table": ("arcsec",),
    "turntable": ("arcsec",),
    "counter": ("",),
    "dmm": ("",),
    "timer": ("", "s"),
    "chamber": ("K",),
    "field_generator": ("",),
    "vibration_table": ("", "m/s^2"),
    "angular_vibration_table": ("",),
    "shock_table": ("", "m/s^2"),
    "voltmeter": ("", "V"),
    "ammeter": ("", "A"),
}

#: old or other spelling -> canonical role (read, with a deprecation warning)
ROLE_ALIASES: dict[str, str] = {
    "table": "rate_table",
    "ratetable": "rate_table",
    "angular_vibration": "angular_vibration_table",
    "multimeter": "dmm",
    "daq": "acquisition",
    "time_base": "timer",
    "temperature_chamber": "chamber",
    "shaker": "vibration_table",
    "vibration": "vibration_table",
    "shock": "shock_table",
}

# -----------------------------------------------------------------------------------------
# top-level sections and device keys
# -----------------------------------------------------------------------------------------

#: top-level manifest keys/sections -> meaning; plugins add theirs with register_section
SECTIONS: dict[str, str] = {
    "format": "the manifest format, \"metro-campaign/1\"",
    "campaign": "identification, people, lab, customer, dates",
    "device": "the device under test",
    "environment": "conditions of the test",
    "site": "latitude and other site values",
    "equipment": "the lab's equipment ([[equipment]])",
    "segments": "the measured segments ([[segments]])",
    "specification": "the product's own limits",
}

#: [device] keys metro or a plugin reads (other keys are kept as properties; a key close to
#: one of these is reported as a probable misspelling)
DEVICE_KEYS: dict[str, str] = {
    "id": "device id", "manufacturer": "manufacturer", "model": "model", "serial": "serial number",
    "technology": "laser, fibre, mems, vibratory, other",
    "application": "aerospace, aviation, marine",
    "output": "pulse, digital, analog, rate",
    "scale_factor": "K", "scale_factor_U": "expanded uncertainty of K",
    "scale_factor_k": "its coverage factor",
    "nonlinearity": "the scale-factor nonlinearity the device is specified for",
    # read by the built-in plugins
    "nonlinearity_limit": "GB/T 45570 rate method: the nonlinearity limit the device is tested "
    "against",
    "nonlinearity_spec": "JJF 2014 7.2.2: the specified nonlinearity",
    "resolution": "output resolution (GB/T 45570 LSB outputs)",
    "gyro_range": "full-scale gyro range (JJF 2003, JJF 2014)",
    "accel_range": "full-scale accelerometer range (JJF 2003)",
    "ira_axis": "the device's input axis (JJF 2014)",
    "scale_factor_repeatability": "stated scale-factor repeatability (JJF 2003, JJF 2014)",
    "bias_repeatability": "stated bias repeatability (JJF 2014)",
    "misalignment_repeatability": "stated misalignment repeatability (JJF 2014)",
    "zero_stability": "stated zero stability (ogam)",
    "supply_voltage": "the supply a ratiometric (mV/V) output is referred to; default supply of "
    "every segment",
}

#: [device] application values (GB/T 45570 tables A.1/B.1); plugins may add theirs
APPLICATIONS: set[str] = {"aerospace", "aviation", "marine", ""}

#: the [environment] temperature metro takes as a test environment's (°C): well beyond any
#: laboratory or chamber, but no longer a typing slip such as −300 °C (below absolute zero)
TEMPERATURE_RANGE_C = (-100.0, 200.0)

SEGMENT_KEYS = ("id", "kind", "file", "sample_interval", "started", "conditions", "units")
CALIBRATION_KEYS = ("certificate", "U", "k", "due", "lab", "distribution")
#: [environment] and [site] keys metro reads (other keys are kept)
ENVIRONMENT_KEYS = ("temperature", "humidity", "pressure", "magnetic_field", "location", "other")
SITE_KEYS = ("latitude", "latitude_uncertainty", "altitude", "gravity", "gravity_uncertainty",
             "name")
EQUIPMENT_KEYS = ("id", "role", "model", "serial", "manufacturer", "calibration")


def register_section(name: str, description: str) -> None:
    """A plugin that reads a top-level manifest section ``[name]`` of its own registers it here,
    so that the unknown-section check does not warn about it."""
    SECTIONS.setdefault(name, description)


def register_device_property(name: str, description: str) -> None:
    """A ``[device]`` key a plugin reads (its misspellings are then reported)."""
    DEVICE_KEYS.setdefault(name, description)


def register_campaign_key(name: str, description: str) -> None:
    """A ``[campaign]`` key a plugin reads."""
    CAMPAIGN_KEYS.setdefault(name, description)


def register_role(name: str, description: str, aliases: Iterable[str] = (),
                  calibration: Iterable[str] | None = None) -> None:
    """An equipment role a plugin's items look for, with other spellings it accepts and the
    kinds of unit its calibration U may be in (``""`` relative)."""
    ROLES.setdefault(name, description)
    if calibration is not None:
        ROLE_CALIBRATION.setdefault(name, tuple(calibration))
    for a in aliases:
        ROLE_ALIASES.setdefault(_norm(a), name)


# -----------------------------------------------------------------------------------------
# lookups
# -----------------------------------------------------------------------------------------


def _norm(text: str) -> str:
    return "_".join(str(text).strip().lower().replace("-", " ").replace("_", " ").split())


def canonical_role(role: str) -> str:
    """The canonical spelling of an equipment role (``rate-table``, ``Rate Table``, ``table`` →
    ``rate_table``); a role in no list is returned as written (normalised: lower case, ``_``)."""
    if not role:
        return ""
    n = _norm(role)
    if n in ROLES:
        return n
    return ROLE_ALIASES.get(n, n)


def role_alias(role: str) -> str | None:
    """The canonical role when ``role`` is an old or other spelling of it (a deprecation
    warning is due), else ``None``."""
    if not role:
        return None
    c = canonical_role(role)
    return c if c != role and c in ROLES else None


def campaign_key(key: str) -> str:
    """The canonical ``[campaign]`` key of ``key`` (an old spelling is mapped)."""
    return CAMPAIGN_ALIASES.get(key, key)


def did_you_mean(key: str, known: Iterable[str], *, cutoff: float = 0.6) -> str | None:
    """The known key closest to ``key`` (difflib), or ``None``."""
    known = list(known)
    lowered = {k.lower(): k for k in known}
    if key.lower() in lowered:
        return lowered[key.lower()]
    m = difflib.get_close_matches(key, known, n=1, cutoff=cutoff)
    if not m:
        m = difflib.get_close_matches(key.lower(), list(lowered), n=1, cutoff=cutoff)
        m = [lowered[x] for x in m]
    return m[0] if m else None


def unknown_key_warning(src: str, field: str, key: str, known: Iterable[str], what: str) -> str:
    """The warning text for an unknown ``key`` at ``field`` of ``src``."""
    guess = did_you_mean(key, known)
    text = f"{src}: field '{field}': unknown {what} key {key!r}, ignored"
    if guess:
        text += f" — did you mean {guess!r}?"
    return text


def deprecated_warning(src: str, field: str, old: str, new: str, what: str = "key") -> str:
    return (f"{src}: field '{field}': the {what} {old!r} is deprecated; it is read as {new!r} "
            f"— write {new!r} (docs/data-format.md)")


# -----------------------------------------------------------------------------------------
# typed view of [campaign] for documents and the register
# -----------------------------------------------------------------------------------------


@attrs.frozen
class People:
    """Who measured, checked and approved (empty text where the manifest does not say)."""

    #: who performed the measurement, the report's "tested by" and the certificate's
    #: "calibrated by" (``[campaign] operator``)
    operator: str = ""
    #: who checked the results (``[campaign] checked_by``)
    checked_by: str = ""
    #: who approved (issued) the report or certificate (``[campaign] approved_by``)
    approved_by: str = ""
    #: the approver's title, printed beside the name in the signatures (``approved_by_title``)
    approved_by_title: str = ""
    #: the operator's title, printed beside the name in the signatures (``operator_title``)
    operator_title: str = ""
    #: the checker's title, printed beside the name in the signatures (``checked_by_title``)
    checked_by_title: str = ""


@attrs.frozen
class Lab:
    """The laboratory that performed the test or calibration."""

    #: the laboratory's name (``[campaign] lab``, else the lab profile's), or ``""``
    name: str = ""
    #: the laboratory's address (``[campaign] lab_address``, else the lab profile's), or ``""``
    address: str = ""
    #: where the measurement was made when not at the laboratory (``[campaign] location``), or
    #: ``""``
    location: str = ""


@attrs.frozen
class Customer:
    #: who ordered the test or calibration (``[campaign] customer``), or ``""``
    name: str = ""
    #: the customer's address (``[campaign] customer_address``), or ``""``
    address: str = ""


def _get(meta: Mapping[str, Any], key: str) -> Any:
    """``meta[key]``, or the value under an old spelling of ``key``."""
    if meta.get(key) not in (None, ""):
        return meta[key]
    for old, new in CAMPAIGN_ALIASES.items():
        if new == key and meta.get(old) not in (None, ""):
            return meta[old]
    return None


def _text(meta: Mapping[str, Any], key: str) -> str:
    v = _get(meta, key)
    return "" if v is None else str(v)


def people_of(meta: Mapping[str, Any]) -> People:
    return People(*(_text(meta, k) for k in PEOPLE_KEYS))


def lab_of(meta: Mapping[str, Any]) -> Lab:
    return Lab(_text(meta, "lab"), _text(meta, "lab_address"), _text(meta, "location"))


def customer_of(meta: Mapping[str, Any]) -> Customer:
    return Customer(_text(meta, "customer"), _text(meta, "customer_address"))


def date_of(meta: Mapping[str, Any], key: str) -> dt.date | None:
    """A date key of ``[campaign]`` as a :class:`datetime.date` (``None`` when not given)."""
    v = _get(meta, key)
    if v is None:
        return None
    if isinstance(v, dt.datetime):
        return v.date()
    if isinstance(v, dt.date):
        return v
    try:
        return dt.date.fromisoformat(str(v).strip()[:10])
    except ValueError:
        return None


# ------------------------------------------------------------------------------ characters

#: characters XML 1.0 does not allow (a Word report is XML): C0 controls other than tab, line feed
#: and carriage return, lone surrogates, U+FFFE and U+FFFF
NOT_XML = re.compile("[\x00-\x08\x0b\x0c\x0e-\x1f\ud800-\udfff\ufffe\uffff]")


def _character_error(src: str | None, field: str, text: str, what: str) -> DataError | None:
    m = NOT_XML.search(text)
    if m is None:
        return None
    cp = ord(m.group())
    kind = ("the control character" if cp < 32 else "a lone surrogate" if 0xD800 <= cp <= 0xDFFF
            else "the non-character")
    return DataError(src, field,
                     f"{what} contains {kind} U+{cp:04X} at position {m.start() + 1}, which a "
                     "report cannot hold (XML allows no such character)",
                     hint="delete it or retype the text; it is often left by a copy from another "
                     "program")


def check_characters(doc: Any, src: str | None, field: str = "") -> None:
    """Every text of a TOML document (keys and values, at any depth) must be one a report can hold:
    a :class:`DataError` names the file, the field and the character (``U+FFFE at position 5``)."""
    err = None
    if isinstance(doc, str):
        err = _character_error(src, field, doc, "the text")
    elif isinstance(doc, dict):
        for k, v in doc.items():
            err = _character_error(src, field or "(top level)", str(k), f"the key {str(k)!r}")
            if err is not None:
                break
            check_characters(v, src, f"{field}.{k}" if field else str(k))
    elif isinstance(doc, list):
        for i, v in enumerate(doc):
            check_characters(v, src, f"{field}[{i}]")
    if err is not None:
        raise err

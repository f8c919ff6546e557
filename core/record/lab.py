"""The lab profile: who the lab is, who signs, how reports are numbered, where the register is.

A lab names itself once, in a TOML file (``metro lab init PATH`` writes a commented
template; docs/register.md explains every key).  metro finds the profile in force by

1. the global option ``--lab PATH``,
2. else the environment variable ``METRO_LAB``,
3. else ``lab.toml`` in the user configuration folder (``platformdirs.user_config_dir("metro")``),

and runs without one when none of these exists (reports then say "not registered").

Everything is checked when the profile is read: a bad profile is a
:class:`~metro.core.base.errors.DataError` naming the file, the field and the reason.  The values
are attrs frozen classes; reports, certificates and the register take lab identity and
people from :class:`LabProfile` (campaign values override people per run).

Importing this module is cheap (attrs and tomllib); the lab's equipment is parsed with
:mod:`metro.core.run.manifest` (pint) only when a profile is loaded.
"""

from __future__ import annotations

import os
import re
import string
import tomllib
from pathlib import Path
from typing import Any, Mapping

import attrs

from ..base.errors import DataError, MetroError

__all__ = [
    "FORMAT",
    "ROLES",
    "LANGUAGES",
    "DEFAULT_SCHEME",
    "Signatory",
    "LabProfile",
    "load_lab",
    "find_lab_path",
    "lab_in_force",
    "write_template",
    "default_register_url",
    "TEMPLATE",
]

FORMAT = "metro-lab/1"
#: Roles a signatory can take on a report (ISO/IEC 17025 §7.8.2.1 k: who authorizes it).
ROLES = ("calibrated_by", "checked_by", "approved_by")
#: Certificate languages: Chinese, English, or both side by side.
LANGUAGES = ("zh", "en", "zh+en")
DEFAULT_SCHEME = "{prefix}{year}-{seq:05d}"
_SCHEME_FIELDS = {"prefix", "year", "seq"}
ENV_LAB = "METRO_LAB"
ENV_REGISTER = "METRO_REGISTER"


def _check_scheme(instance: Any, attribute: Any, value: str) -> None:
    problem = scheme_problem(value)
    if problem:
        raise ValueError(problem)


def scheme_problem(scheme: str) -> str | None:
    """Why ``scheme`` is not a usable numbering scheme, or ``None``.

    A scheme is a Python format string with the fields ``{prefix}``, ``{year}`` and
    ``{seq}`` (``{seq}`` required, with an integer format such as ``{seq:05d}``)."""
    try:
        fields = [f for _, f, _, _ in string.Formatter().parse(scheme) if f is not None]
    except ValueError as exc:
        return f"not a format string: {exc}"
    unknown = sorted(set(fields) - _SCHEME_FIELDS)
    if unknown:
        return (
            f"unknown field(s) {', '.join('{' + f + '}' for f in unknown)}; use {{prefix}}, "
            f"{{year}}, {{seq}}"
        )
    if "seq" not in fields:
        return "has no {seq} field: numbers would not differ"
    try:
        a = scheme.format(prefix="P", year=2026, seq=1)
        b = scheme.format(prefix="P", year=2026, seq=2)
    except (ValueError, TypeError, KeyError, IndexError) as exc:
        return f"cannot be formatted ({exc})"
    if a == b:
        return "gives the same text for different sequence numbers"
    if any(c in a for c in '/\\:*?"<>|') or a.strip() != a or not a:
        return f"gives {a!r}, which cannot be a file name"
    return None


@attrs.frozen
class Signatory:
    """A person who signs reports: name, 职务 (title) and role (calibrated/checked/approved by)."""

    name: str = attrs.field(validator=attrs.validators.min_len(1))
    title: str = ""
    role: str = attrs.field(default="calibrated_by", validator=attrs.validators.in_(ROLES))

    def as_dict(self) -> dict[str, str]:
        return {"name": self.name, "title": self.title, "role": self.role}


@attrs.frozen
class LabProfile:
    """One lab's identity, signatories, numbering, language, time zone, register and equipment."""

    name_zh: str = ""
    name_en: str = ""
    address: str = ""
    #: ISO 3166-1 alpha-2 code of the lab's country (``CN``), written into a DCC's coreData
    country: str = ""
    accreditation_body: str = ""
    accreditation_number: str = ""
    logo: Path | None = None
    signatories: tuple[Signatory, ...] = attrs.field(default=(), converter=tuple)
    prefix: str = "MTR"
    scheme: str = attrs.field(default=DEFAULT_SCHEME, validator=_check_scheme)
    language: str = attrs.field(default="zh+en", validator=attrs.validators.in_(LANGUAGES))
    timezone: str = "UTC"
    #: SQLAlchemy URL of the register (an SQLite file path already made absolute, or PostgreSQL)
    register: str = ""
    #: the lab's equipment (metro.core.model.campaign.Equipment), found by id from a manifest
    equipment: tuple[Any, ...] = attrs.field(default=(), converter=tuple)
    source: str = ""
    #: the base of the public verify page (``https://lab.example/verify/``): each registered report
    #: prints a QR code linking to ``<verify_url>/<number>``; empty: no QR code
    verify_url: str = ""

    @property
    def name(self) -> str:
        """The lab's name for one line: English, else Chinese."""
        return self.name_en or self.name_zh

    def signatory(self, role: str) -> Signatory | None:
        """The first signatory with ``role`` (``calibrated_by``, ``checked_by``,
        ``approved_by``)."""
        if role not in ROLES:
            raise ValueError(f"unknown role {role!r}; one of {', '.join(ROLES)}")
        return next((s for s in self.signatories if s.role == role), None)

    def equipment_by_id(self) -> dict[str, Any]:
        return {e.id: e for e in self.equipment}

    def per_year(self) -> bool:
        """Whether numbers restart each year (the scheme contains ``{year}``)."""
        return any(f == "year" for _, f, _, _ in string.Formatter().parse(self.scheme))

    def format_number(self, seq: int, year: int) -> str:
        return self.scheme.format(prefix=self.prefix, year=year, seq=seq)

    def register_url(self) -> str:
        """The register in force: ``METRO_REGISTER``, else the profile's, else the user data
        folder's."""
        return os.environ.get(ENV_REGISTER) or self.register or default_register_url()

    def as_dict(self) -> dict[str, Any]:
        """Plain values (``metro lab show --json``); equipment with its calibration as text."""
        eq = []
        for e in self.equipment:
            cal = e.calibration
            eq.append({
                "id": e.id, "role": e.role, "manufacturer": e.manufacturer, "model": e.model,
                "serial": e.serial,
                "certificate": cal.certificate if cal else None,
                "U": f"{cal.uncertainty:~P}" if cal else None, "k": cal.k if cal else None,
                "due": cal.due.isoformat() if cal and cal.due else None,
                "distribution": cal.distribution if cal else None,
            })
        return {
            "source": self.source, "name_zh": self.name_zh, "name_en": self.name_en,
            "address": self.address, "country": self.country, "verify_url": self.verify_url,
            "accreditation_body": self.accreditation_body,
            "accreditation_number": self.accreditation_number,
            "logo": str(self.logo) if self.logo else None,
            "signatories": [s.as_dict() for s in self.signatories],
            "numbering": {"scheme": self.scheme, "prefix": self.prefix, "per_year": self.per_year(),
                          "example": self.format_number(1, 2026)},
            "language": self.language, "timezone": self.timezone,
            "register": redact_url(self.register_url()),
            "equipment": eq,
        }


def redact_url(url: str) -> str:
    """A database URL without its password (for printing)."""
    if "://" in url and "@" in url.split("://", 1)[1]:
        scheme, rest = url.split("://", 1)
        cred, host = rest.rsplit("@", 1)
        if ":" in cred:
            cred = cred.split(":", 1)[0] + ":***"
        return f"{scheme}://{cred}@{host}"
    return url


def default_register_url() -> str:
    """An SQLite file in the user data folder (``platformdirs.user_data_dir("metro")``)."""
    import platformdirs

    return "sqlite:///" + str(Path(platformdirs.user_data_dir("metro")) / "register.sqlite")


def user_lab_path() -> Path:
    import platformdirs

    return Path(platformdirs.user_config_dir("metro")) / "lab.toml"


def find_lab_path(cli_path: str | os.PathLike[str] | None = None) -> Path | None:
    """The profile in force: ``--lab``, else ``METRO_LAB``, else the user config folder's
    ``lab.toml`` when it exists; ``None`` when there is none. A path given explicitly must exist."""
    if cli_path:
        return Path(cli_path)
    env = os.environ.get(ENV_LAB)
    if env:
        return Path(env)
    p = user_lab_path()
    return p if p.is_file() else None


def lab_in_force(cli_path: str | os.PathLike[str] | None = None, *,
                 equipment: bool = True) -> LabProfile | None:
    """:func:`load_lab` of :func:`find_lab_path`, or ``None`` without a profile."""
    p = find_lab_path(cli_path)
    return None if p is None else load_lab(p, equipment=equipment)


# --------------------------------------------------------------------------------------
# Reading
# --------------------------------------------------------------------------------------

_LAB_KEYS = {"name_zh", "name_en", "address", "country", "accreditation_body",
             "accreditation_number", "logo",
             "language", "timezone", "register", "verify_url"}


def _text(t: Mapping, key: str, src: str, where: str, default: str = "") -> str:
    v = t.get(key, default)
    if not isinstance(v, str):
        raise DataError(src, f"{where}.{key}", f"must be text, got {v!r}")
    return v.strip()


def _register(value: str, base: Path, src: str) -> str:
    if not value:
        return ""
    if "://" in value:
        if not value.startswith(("sqlite:", "postgresql")):
            raise DataError(src, "lab.register", f"unsupported database {value.split(':', 1)[0]!r}",
                            hint="an SQLite file path, or postgresql+psycopg://user@host:port/db")
        return value
    p = Path(value).expanduser()
    if not p.is_absolute():
        p = base / p
    return "sqlite:///" + str(p.resolve())


def verify_url_problem(url: str) -> str | None:
    """Why ``url`` cannot be the base of the verify links printed as QR codes, or ``None``: an
    ``http(s)://host/…`` URL without spaces, query or fragment (the report number is appended)."""
    from urllib.parse import urlsplit

    if any(c.isspace() for c in url):
        return "contains a space"
    try:
        parts = urlsplit(url)
    except ValueError as exc:
        return f"is not a URL ({exc})"
    if parts.scheme not in ("http", "https") or not parts.hostname:
        return "is not an http:// or https:// URL with a host"
    if parts.query or parts.fragment or url.endswith(("?", "#")):
        return "has a query or fragment (?, #): the report number is appended to it"
    return None


def numbering(doc: dict, src: str) -> tuple[str, str]:
    """The profile's ``[numbering]``: (scheme, prefix), the scheme checked and the prefix one a
    file name can hold."""
    num = doc.get("numbering", {})
    if not isinstance(num, dict):
        raise DataError(src, "numbering", "must be a table ([numbering])")
    bad = sorted(set(num) - {"scheme", "prefix"})
    if bad:
        raise DataError(src, f"numbering.{bad[0]}", "unknown key",
                        hint="known keys: scheme, prefix")
    scheme = _text(num, "scheme", src, "numbering", DEFAULT_SCHEME)
    prefix = _text(num, "prefix", src, "numbering", "MTR")
    problem = scheme_problem(scheme)
    if problem:
        raise DataError(src, "numbering.scheme", f"{scheme!r} {problem}",
                        hint='e.g. scheme = "{prefix}{year}-{seq:05d}"')
    if any(c in prefix for c in '/\\:*?"<>|'):
        raise DataError(src, "numbering.prefix",
                        f"{prefix!r} contains a character a file name cannot hold")
    return scheme, prefix


def signatories_of(doc: dict, src: str) -> list[Signatory]:
    """The profile's ``[[signatories]]``: name, title and role (one of :data:`ROLES`)."""
    sigs = doc.get("signatories", [])
    if not isinstance(sigs, list):
        raise DataError(src, "signatories", "must be an array of tables ([[signatories]])")
    signatories = []
    for i, s in enumerate(sigs):
        where = f"signatories[{i}]"
        if not isinstance(s, dict):
            raise DataError(src, where, "must be a table")
        bad = sorted(set(s) - {"name", "title", "role"})
        if bad:
            raise DataError(src, f"{where}.{bad[0]}", "unknown key",
                            hint="known keys: name, title, role")
        name = _text(s, "name", src, where)
        if not name:
            raise DataError(src, f"{where}.name", "missing")
        role = _text(s, "role", src, where)
        if role not in ROLES:
            raise DataError(src, f"{where}.role",
                            f"must be one of {', '.join(ROLES)}, got {role!r}")
        signatories.append(Signatory(name=name, title=_text(s, "title", src, where), role=role))
    return signatories


def lab_equipment(doc: dict, src: str, *, read: bool = True) -> list:
    """The profile's ``[[equipment]]``, each with its calibration (certificate, U, k, due), ids
    unique; ``read=False`` checks only that it is an array of tables (no pint imported)."""
    eq_list = doc.get("equipment", [])
    if not isinstance(eq_list, list):
        raise DataError(src, "equipment", "must be an array of tables ([[equipment]])")
    equipment = []
    if eq_list and read:
        from ..run.manifest import equipment_from_table

        seen: set[str] = set()
        for i, e in enumerate(eq_list):
            where = f"equipment[{i}]"
            eq = equipment_from_table(e, src, where)
            if eq.id in seen:
                raise DataError(src, f"{where}.id", f"duplicate equipment id {eq.id!r}")
            if eq.calibration is None:
                raise DataError(src, f"{where}.calibration", "missing",
                                hint="the lab's equipment states its calibration: certificate, U, "
                                "k, due")
            seen.add(eq.id)
            equipment.append(eq)
    return equipment


def load_lab(path: str | os.PathLike[str], *, equipment: bool = True) -> LabProfile:
    """Read and check a lab profile; a problem is a DataError naming the file, the field and why.
    ``equipment=False`` leaves the ``[[equipment]]`` tables unread (no pint): what the commands
    that only read the register need (its URL and the lab's identity)."""
    p = Path(path)
    src = str(p)
    if not p.is_file():
        raise DataError(src, None, "lab profile not found",
                        hint="write one with `metro lab init PATH`, or give --lab / METRO_LAB")
    try:
        doc = tomllib.loads(p.read_text(encoding="utf-8-sig"))
    except UnicodeDecodeError as exc:
        raise DataError(src, None, f"not UTF-8 text ({exc})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise DataError(src, None, f"not valid TOML: {exc}") from exc
    from ..base.vocabulary import check_characters

    check_characters(doc, src)  # every text must be one a report can hold
    fmt = doc.get("format", FORMAT)
    if fmt != FORMAT:
        raise DataError(src, "format", f"unsupported format {fmt!r}; this metro reads {FORMAT!r}")
    unknown = sorted(set(doc) - {"format", "lab", "numbering", "signatories", "equipment"})
    if unknown:
        raise DataError(src, unknown[0], "unknown key",
                        hint="a lab profile has [lab], [numbering], [[signatories]] and "
                        "[[equipment]]")
    lab = doc.get("lab", {})
    if not isinstance(lab, dict):
        raise DataError(src, "lab", "must be a table ([lab])")
    bad = sorted(set(lab) - _LAB_KEYS)
    if bad:
        raise DataError(src, f"lab.{bad[0]}", "unknown key", hint="known keys: "
                        + ", ".join(sorted(_LAB_KEYS)))
    vals = {k: _text(lab, k, src, "lab") for k in _LAB_KEYS}
    if not (vals["name_zh"] or vals["name_en"]):
        raise DataError(src, "lab.name_en", "the lab has no name (name_zh or name_en)")
    base = p.parent.resolve()
    logo = None
    if vals["logo"]:
        logo = Path(vals["logo"]).expanduser()
        logo = logo if logo.is_absolute() else base / logo
        if not logo.is_file():
            raise DataError(src, "lab.logo",
                            f"logo image {vals['logo']!r} not found (looked for {logo})")
        if logo.suffix.lower() not in (".png", ".jpg", ".jpeg", ".gif", ".bmp"):
            raise DataError(src, "lab.logo", f"{logo.name}: not a PNG, JPEG, GIF or BMP image")
    language = vals["language"] or "zh+en"
    if language not in LANGUAGES:
        raise DataError(src, "lab.language",
                        f"must be one of {', '.join(LANGUAGES)}, got {language!r}")
    tz = vals["timezone"] or "UTC"
    import zoneinfo

    try:
        zoneinfo.ZoneInfo(tz)
    except (zoneinfo.ZoneInfoNotFoundError, ValueError) as exc:
        raise DataError(src, "lab.timezone", f"unknown time zone {tz!r}",
                        hint="an IANA name such as Asia/Shanghai or UTC") from exc
    register = _register(vals["register"], base, src)
    if vals["country"] and not re.fullmatch(r"[A-Z]{2}", vals["country"]):
        raise DataError(src, "lab.country",
                        f"{vals['country']!r} is not an ISO 3166-1 alpha-2 code",
                        hint='two capital letters, e.g. country = "CN"')
    problem = verify_url_problem(vals["verify_url"]) if vals["verify_url"] else None
    if problem:
        raise DataError(src, "lab.verify_url", f"{vals['verify_url']!r} {problem}",
                        hint='e.g. verify_url = "https://lab.example/verify/"')

    scheme, prefix = numbering(doc, src)
    signatories = signatories_of(doc, src)
    read = equipment
    equipment = lab_equipment(doc, src, read=read)
    if read:  # and what `metro lab equipment import` wrote beside the profile
        from .equipment_store import read_store

        equipment += read_store(p, {e.id for e in equipment})
    return LabProfile(
        name_zh=vals["name_zh"], name_en=vals["name_en"], address=vals["address"],
        country=vals["country"],
        accreditation_body=vals["accreditation_body"],
        accreditation_number=vals["accreditation_number"],
        logo=logo, signatories=signatories, prefix=prefix, scheme=scheme, language=language,
        timezone=tz,
        register=register, equipment=equipment, source=src, verify_url=vals["verify_url"],
    )


# --------------------------------------------------------------------------------------
# Template
# --------------------------------------------------------------------------------------

TEMPLATE = '''\
# metro lab profile (docs/register.md). Lines starting with # are comments.
format = "metro-lab/1"

[lab]
name_zh = "示例计量实验室"                 # the lab's name in Chinese
name_en = "Example Metrology Laboratory"  # … and in English (one of the two is required)
address = "1 Example Road, Example City"
country = "CN"                          # ISO 3166-1 alpha-2 (a DCC's coreData names it)
accreditation_body = "CNAS"              # who accredits the lab (leave empty if not accredited)
accreditation_number = "CNAS L00000"
# logo = "logo.png"                      # an image beside this file, printed on certificates
language = "zh+en"                       # default certificate language: zh, en or zh+en
timezone = "Asia/Shanghai"               # IANA time zone: issue times are printed in it
# register: an SQLite file (relative to this file) or one PostgreSQL database for several
# stations, e.g. "postgresql+psycopg://metro@db.lab.example:5432/metro"; METRO_REGISTER overrides.
register = "register.sqlite"
# the public verify page: each registered certificate prints a QR code linking to
# <verify_url>/<number> (`metro serve` serves /verify/<number>); without it no QR code is printed
# verify_url = "https://lab.example/verify/"

[numbering]
# {prefix}, {year} (numbers restart each year when it is used) and {seq} (required)
scheme = "{prefix}{year}-{seq:05d}"
prefix = "EML"

# People who sign reports; role: calibrated_by, checked_by or approved_by.
# A campaign's [people] (or equivalent) values override them for one run.
[[signatories]]
name = "张三"
title = "校准员"
role = "calibrated_by"

[[signatories]]
name = "李四"
title = "核验员"
role = "checked_by"

[[signatories]]
name = "王五"
title = "技术负责人"
role = "approved_by"

# The lab's equipment: a manifest may name it by id alone ([[equipment]] id = "RT-01").
# Equipment past its due date on the measurement date refuses a run unless --allow-expired.
[[equipment]]
id = "RT-01"
role = "rate_table"
manufacturer = "Example Motion"
model = "RT-300"
serial = "0001"
  [equipment.calibration]
  certificate = "CAL-2026-0001"
  U = "5e-6"            # expanded uncertainty (relative or with a unit, e.g. "0.5 arcsec")
  k = 2
  due = 2027-06-30
  distribution = "normal"   # or uniform (U is then a half-width)
'''


def write_template(path: str | os.PathLike[str]) -> Path:
    """Write the commented template to ``path``; an existing file is never replaced."""
    from ..base.atomic import atomic_path

    p = Path(path)
    if p.exists():
        raise MetroError(f"{p} exists; metro lab init does not replace a file",
                         hint="choose another path, or edit the existing profile")
    if not p.parent.is_dir():
        raise MetroError(f"cannot write {p}: folder {p.parent} does not exist")
    with atomic_path(p) as tmp:
        tmp.write_text(TEMPLATE, encoding="utf-8")
        if p.exists():  # created meanwhile: still never replaced
            raise MetroError(f"{p} exists; metro lab init does not replace a file")
    return p

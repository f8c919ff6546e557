"""Provenance of a run: who/what/which data, and a unique report number."""

from __future__ import annotations

import datetime as dt
import platform
import secrets
import sys
from typing import Any, Mapping

import attrs

from .campaign import Campaign
from .results import Outcome


def new_report_number(now: dt.datetime | None = None) -> str:
    """A unique report number: ``MTR-<UTC date>-<UTC time>-<6 hex digits>`` (UTC time + 24 random
    bits)."""
    now = now or dt.datetime.now(dt.timezone.utc)
    return f"MTR-{now:%Y%m%d-%H%M%S}-{secrets.token_hex(3).upper()}"


@attrs.frozen
class RunRecord:
    """Everything a report needs: the outcomes, the campaign and the provenance."""

    report_number: str
    created: dt.datetime
    campaign: Campaign
    outcomes: tuple[Outcome, ...] = attrs.field(converter=tuple)
    # {"metro": "0.1.0", "python": ..., "numpy": ...}
    software: Mapping[str, str] = attrs.field(factory=dict)
    plugins: Mapping[str, str] = attrs.field(factory=dict)  # {plugin name: "dist version"}
    # (file, sha256)
    data_files: tuple[tuple[str, str], ...] = attrs.field(default=(), converter=tuple)
    simulated: bool = False
    truth: Mapping[str, Any] = attrs.field(factory=dict)
    timings: Mapping[str, float] = attrs.field(factory=dict)  # stage -> seconds
    #: which items ran and why (``--all``, series): runner.ItemChoice values
    selection: tuple[Any, ...] = attrs.field(default=(), converter=tuple)
    #: the results judged against specifications (a conformity.Assessment), if any were given
    conformity: Any = None

    @property
    def standard(self) -> str:
        return self.outcomes[0].standard if self.outcomes else ""

    @property
    def test_date(self) -> dt.date:
        """The day of the measurement: the campaign's ``measurement_date``, else the day its data
        were acquired (``acquired``, written by ``metro acquire``), else the day of this run.
        Equipment calibration status is judged on it (reports, terminal, ``--json``)."""
        d = measurement_date(self.campaign)
        if d is not None:
            return d
        return self.created.date() if isinstance(self.created, dt.datetime) else self.created


def _as_date(v: Any) -> dt.date | None:
    """A TOML date/datetime or an ISO text as a date; None when absent or unreadable."""
    if isinstance(v, dt.datetime):
        return v.date()
    if isinstance(v, dt.date):
        return v
    if isinstance(v, str) and v.strip():
        text = v.strip()
        try:
            return dt.datetime.fromisoformat(text.replace("Z", "+00:00")).date()
        except ValueError:
            try:
                return dt.date.fromisoformat(text[:10])
            except ValueError:
                return None
    return None


def measurement_date(campaign: Campaign) -> dt.date | None:
    """The campaign's measurement date: ``[campaign] measurement_date`` (any spelling the
    vocabulary reads), else the day it was ``acquired`` (None if neither)."""
    given = getattr(campaign, "measurement_date", None)
    if given is not None:
        return given
    return _as_date(campaign.meta.get("acquired"))


def software_versions() -> dict[str, str]:
    from importlib import metadata

    out = {"python": sys.version.split()[0], "platform": platform.platform(terse=True)}
    from ..base.extras import DISTRIBUTION

    for key, dist in (("metro", DISTRIBUTION), *((d, d) for d in ("numpy", "scipy", "pint",
                                                                  "pluggy", "attrs",
                                                                    "docxtpl", "numba",
                                                                  "pyarrow"))):
        try:
            out[key] = metadata.version(dist)
        except metadata.PackageNotFoundError:
            pass
    return out

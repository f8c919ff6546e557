"""What every simulated station shares: seeds that follow a step's identity, and the refusal of
step kinds a station cannot simulate.

* :func:`step_seed` — a segment's random stream is drawn from a stable hash of the step's
  identity (its kind, conditions and sample interval: what :func:`metro.core.run.runner.merge_steps`
  treats as "the same measurement") together with the station's seed, never from the step's
  position in the merged sequence; so the same seed gives the same data for a segment whatever
  order the items are listed in and whichever other items are acquired with it.
* :func:`refuse_unknown_kinds` — a station that is asked for a kind of step it does not know
  refuses before simulating anything, naming the step kind, the segment and the station, and the
  kinds it does simulate; it never records "a gyro at rest" in place of a motion it cannot make.
* :func:`standard_expected` — the expected values that follow from a station's truth only through
  a standard's formulas, computed by that standard's plugin (the ``metro_expected_values`` hook)
  from the noise-free quantities the station declares; instruments never import a plugin.
"""

from __future__ import annotations

import hashlib
from typing import Any, Iterable, Mapping, Sequence

from metro.core.base.errors import MetroError
from metro.core.model.campaign import Campaign
from metro.core.model.procedure import Step

__all__ = [
    "step_identity",
    "step_seed",
    "refuse_unknown_kinds",
    "standard_expected",
    "StationError",
]


class StationError(MetroError):
    """A station cannot do what a step asks (a clean refusal: exit 2, nothing recorded)."""


def step_identity(step: Step) -> str:
    """The text that identifies a step's measurement: kind, sorted conditions, sample interval."""
    conds = ";".join(
        f"{k}={v}" for k, v in sorted((str(k), str(v)) for k, v in step.conditions.items())
    )
    return f"{step.kind}|{conds}|{step.interval}"


def step_seed(step: Step) -> int:
    """A stable 31-bit number from :func:`step_identity` (SHA-256, so it is the same on every
    platform and Python run); stations combine it with their own seed for the step's stream."""
    return (
        int.from_bytes(hashlib.sha256(step_identity(step).encode("utf-8")).digest()[:4], "big")
        & 0x7FFFFFFF
    )


def refuse_unknown_kinds(
    station: str,
    steps: Sequence[Step],
    kinds: Iterable[str],
    *,
    items: Mapping[str, Sequence[str]] | None = None,
    hint: str = "",
) -> None:
    """Raise :class:`StationError` for the first step whose kind ``station`` does not simulate."""
    known = set(kinds)
    items = items or {}
    for step in steps:
        if step.kind in known:
            continue
        same = [s for s in steps if s.kind == step.kind]
        segs = ", ".join(s.segment for s in same[:4]) + (" …" if len(same) > 4 else "")
        its = sorted({i for s in same for i in items.get(s.segment, ())})
        raise StationError(
            f"station {station!r} cannot simulate steps of kind {step.kind!r}"
            f"{' (item ' + ', '.join(its) + ')' if its else ''} (segment {segs}); "
            "nothing was recorded",
            hint=(hint + "; " if hint else "")
            + f"{station} simulates the kinds {', '.join(sorted(known))}",
        )


def standard_expected(
    campaign: Campaign, ideal: Mapping[str, Any], pm: Any = None
) -> dict[str, Any]:
    """The expected values the standards' plugins compute (``metro_expected_values``) from the
    noise-free quantities ``ideal`` a station declares for ``campaign``, through the plugin manager
    ``pm`` (default: metro's built-in plugins); empty when no loaded plugin knows the keys."""
    if not ideal:
        return {}
    if pm is None:
        from metro.core.run.plugin_manager import builtin_plugin_manager

        pm = builtin_plugin_manager()
    return pm.expected_values(campaign, ideal)

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
* :func:`memory_segment` — a simulated step's segment, its columns held in memory;
  :func:`simulated_campaign` — the campaign a simulated station returns.
* :func:`device_class_fields`, :func:`with_device_class` and :func:`drawn_station` — the
  ``device_class`` station option of the simulated stations: a preset class of devices, one of
  which the seed draws.
* :func:`standard_expected` — the expected values that follow from a station's truth only through
  a standard's formulas, computed by that standard's plugin (the ``metro_expected_values`` hook)
  from the noise-free quantities the station declares; instruments never import a plugin.
"""

from __future__ import annotations

import hashlib
from typing import Any, Callable, Iterable, Mapping, Sequence

from metro.core.base.errors import DataError, MetroError
from metro.core.base.units import Q_
from metro.core.model.campaign import Campaign, DeviceUnderTest, Segment
from metro.core.model.procedure import Step

__all__ = [
    "step_identity",
    "step_seed",
    "refuse_unknown_kinds",
    "ELSEWHERE_HINT",
    "memory_segment",
    "simulated_campaign",
    "simulated_device",
    "device_class_fields",
    "with_device_class",
    "drawn_station",
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


#: the hint of :func:`refuse_unknown_kinds` unless a station gives its own
ELSEWHERE_HINT = (
    "acquire these items on a station that simulates them (`metro plugins` lists them)"
)


def refuse_unknown_kinds(
    station: str,
    steps: Sequence[Step],
    kinds: Iterable[str],
    *,
    items: Mapping[str, Sequence[str]] | None = None,
    hint: str = ELSEWHERE_HINT,
) -> None:
    """Raise :class:`StationError` for the first step whose kind ``station`` does not simulate;
    the refusal's hint starts with ``hint`` and ends with the kinds the station does simulate."""
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


def memory_segment(
    step: Step, interval_s: float, columns: Mapping[str, tuple[Any, str]]
) -> Segment:
    """The segment a station simulated for ``step`` (its id, kind and conditions): ``columns``
    (``{name: (array, unit)}``) held in memory, the sample interval ``interval_s`` (s), and the
    SHA-256 of the arrays' bytes one after another in the order of ``columns``.

    >>> import numpy as np
    >>> step = Step("S1", "static", "at rest", duration=Q_(1, "s"), interval=Q_(1, "s"))
    >>> seg = memory_segment(step, 0.5, {"output": (np.zeros(2), "P")})
    >>> seg.interval, seg.sha256[:8], seg.loader()["output"][1]
    (<Quantity(0.5, 'second')>, '374708ff', 'P')
    """
    cols = dict(columns)
    digest = hashlib.sha256(b"".join(a.tobytes() for a, _ in cols.values())).hexdigest()
    return Segment(
        id=step.segment,
        kind=step.kind,
        conditions=dict(step.conditions),
        interval=Q_(interval_s, "s"),
        sha256=digest,
        loader=(lambda: dict(cols)),
    )


def simulated_campaign(
    station: Any,
    campaign_id: str,
    segments: Sequence[Segment],
    *,
    source: str = "simulated station",
    environment: Mapping[str, Any] | None = None,
    site: Mapping[str, Any] | None = None,
    **fields: Any,
) -> Campaign:
    """The campaign of a simulated ``station`` (its ``device()``, ``equipment()``, ``truth`` and
    ``latitude_deg``): the ``segments`` it simulated, in the simulated laboratory (20 °C, 45 %
    humidity, then ``environment``) at a site at the station's latitude (then ``site``), with the
    truth and the site latitude it declares; ``fields`` (``expected``, ``records`` …) as given."""
    latitude = Q_(station.latitude_deg, "deg")
    return Campaign(
        id=campaign_id,
        device=station.device(),
        equipment=station.equipment(),
        environment={"temperature": Q_(20.0, "degC"), "humidity": Q_(45.0, "percent")}
        | dict(environment or {}),
        site={"latitude": latitude} | dict(site or {}),
        segments=segments,
        source=source,
        simulated=True,
        truth=station.truth.as_quantities() | {"site latitude": Q_(station.latitude_deg, "deg")},
        **fields,
    )


def simulated_device(seed: int, device_id: str, model: str, **fields: Any) -> DeviceUnderTest:
    """The device under test of a simulated station: ``device_id``, ``model``, made by the
    "metro simulator", its serial the truth's ``seed``; ``fields`` (``technology``, ``output``,
    ``properties`` …) as given.

    >>> simulated_device(7, "SIM-1", "virtual gyro", output="rate").serial
    'seed 7'
    """
    return DeviceUnderTest(
        id=device_id, model=model, serial=f"seed {seed}", manufacturer="metro simulator", **fields
    )


def device_class_fields(
    device_class: str, classes: Mapping[str, Mapping[str, Any]]
) -> dict[str, Any]:
    """A copy of the preset truth fields of ``device_class`` in ``classes``; a :class:`DataError`
    naming the known classes when there is no such class.

    >>> device_class_fields("quiet", {"quiet": {"arw": 0.1}})
    {'arw': 0.1}
    """
    if device_class not in classes:
        raise DataError(
            None,
            "station option device_class",
            f"{device_class!r} is not a device class",
            hint="device classes: " + ", ".join(classes),
        )
    return dict(classes[device_class])


def with_device_class(
    truth_kw: dict[str, Any],
    draw: Callable[[str, int], Mapping[str, Any]],
    default_seed: int,
) -> dict[str, Any]:
    """The truth fields of a station factory with the ``device_class`` option resolved: without
    it, ``truth_kw`` as given; with it, the device ``draw(device_class, seed)`` draws (``seed``
    from ``truth_kw``, else ``default_seed``), then the fields given in ``truth_kw`` over it.
    The option is taken out of ``truth_kw``.

    >>> def draw(cls, seed):
    ...     return {"bias": 0.1 * seed, "noise": 1.0}
    >>> with_device_class({"device_class": "a", "noise": 2.0}, draw, 3)
    {'bias': 0.30000000000000004, 'noise': 2.0, 'device_class': 'a'}
    >>> with_device_class({"noise": 2.0}, draw, 3)
    {'noise': 2.0}
    """
    cls = truth_kw.pop("device_class", "")
    if not cls:
        return truth_kw
    return dict(draw(cls, truth_kw.get("seed", default_seed))) | truth_kw | {"device_class": cls}


def drawn_station(
    name: str,
    truth_cls: type,
    station_cls: type,
    draw: Callable[[str, int], Mapping[str, Any]],
    options: Mapping[str, Any],
    station_fields: Iterable[str],
) -> Any:
    """The station ``station_cls`` a factory registered as ``name`` builds from ``options``: any
    field of ``truth_cls`` and the ``station_fields`` of the station, and ``device_class`` (the
    device ``draw`` draws with the seed, :func:`with_device_class`)."""
    from metro.core.base.options import station_options

    truth_kw, st_kw = station_options(name, truth_cls, station_cls, options, station_fields)
    truth_kw = with_device_class(truth_kw, draw, truth_cls().seed)
    return station_cls(truth=truth_cls(**truth_kw), **st_kw)


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

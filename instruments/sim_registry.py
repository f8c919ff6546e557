"""What the step modules of the simulated optical-gyro station register: the simulators of step
kinds and record kinds beyond the station's own, and the functions that add expected values.

:mod:`.simulated` keeps one station (one virtual gyro, one truth); the motions of other test
methods live in their own modules (:data:`STEP_MODULES`), imported on first use, which register
here with :func:`register_step_kind`, :func:`register_record_kind`, :func:`register_expected`
and :func:`register_record_expected`.
"""

from __future__ import annotations

from typing import Any, Callable, Mapping

from metro.core.model.campaign import Segment

__all__ = [
    "STEP_MODULES",
    "register_step_kind",
    "step_simulators",
    "register_record_kind",
    "record_simulators",
    "merge_records",
    "register_expected",
    "expected_contributors",
    "register_record_expected",
    "record_expected_contributors",
]


#: step kind -> simulator; see :func:`register_step_kind`
_STEP_SIMULATORS: dict[str, Callable[..., Segment]] = {}
#: modules that register further step kinds of the virtual gyro (imported on first use)
STEP_MODULES: tuple[str, ...] = (
    "metro.instruments.sim_gbt_rate",
    "metro.instruments.sim_gbt_env",
    "metro.instruments.sim_gbt_type",
)
#: record kind (``record:<section>…``) -> fn(station, step, index) -> {section: table};
#: see :func:`register_record_kind`
_RECORD_SIMULATORS: dict[str, Callable[..., Mapping[str, Any]]] = {}
#: functions ``fn(station, campaign) -> {metric key: quantity}`` adding expected values of
#: record items
_RECORD_EXPECTED: list[Callable[..., Mapping[str, Any]]] = []


def register_record_kind(kind: str):
    """Decorator: ``fn(station, step, index) -> {section: table}`` takes down the records of
    steps of ``kind`` (which starts with ``record:``) on :class:`SimulatedStation` — an
    inspection, a test done
    elsewhere — as a lab would write them in the manifest (text with units)."""
    from metro.core.model.procedure import RECORD_KIND_PREFIX

    if not kind.startswith(RECORD_KIND_PREFIX):
        raise ValueError(f"a record kind starts with {RECORD_KIND_PREFIX!r}, got {kind!r}")

    def deco(fn):
        if kind in _RECORD_SIMULATORS and _RECORD_SIMULATORS[kind] is not fn:
            raise ValueError(
                f"record kind {kind!r} is already simulated by "
                f"{_RECORD_SIMULATORS[kind].__qualname__}"
            )
        _RECORD_SIMULATORS[kind] = fn
        return fn

    return deco


def register_record_expected(
    fn: Callable[..., Mapping[str, Any]],
) -> Callable[..., Mapping[str, Any]]:
    """Decorator: ``fn(station, campaign)`` returns the values (quantities by metric key) an ideal
    evaluation of the campaign's simulated records (``campaign.records``) gives; merged into the
    campaign's ``expected``."""
    if fn not in _RECORD_EXPECTED:
        _RECORD_EXPECTED.append(fn)
    return fn


def record_simulators() -> Mapping[str, Callable[..., Mapping[str, Any]]]:
    step_simulators()  # imports the step modules, which register their record kinds
    return _RECORD_SIMULATORS


def merge_records(into: dict[str, Any], more: Mapping[str, Any]) -> dict[str, Any]:
    """Add ``more`` to ``into`` section by section: tables merge key by key, arrays of tables
    extend."""
    for key, val in more.items():
        old = into.get(key)
        if isinstance(old, dict) and isinstance(val, Mapping):
            merge_records(old, val)
        elif isinstance(old, list) and isinstance(val, list):
            old.extend(val)
        else:
            into[key] = (
                dict(val)
                if isinstance(val, Mapping)
                else (list(val) if isinstance(val, list) else val)
            )
    return into


def register_step_kind(kind: str) -> Callable[[Callable[..., Segment]], Callable[..., Segment]]:
    """Decorator: ``fn(station, step, index, *, interval_s, n, orientation, bias_offset_deg_h,
    progress) -> Segment`` simulates steps of ``kind`` on :class:`SimulatedStation`.

    Keeps one station (one virtual gyro, one truth) while the test methods that need other
    motions (rate runs, tilts, vibration …) live in their own modules.
    """

    def deco(fn: Callable[..., Segment]) -> Callable[..., Segment]:
        if kind in _STEP_SIMULATORS and _STEP_SIMULATORS[kind] is not fn:
            raise ValueError(
                f"step kind {kind!r} is already simulated by {_STEP_SIMULATORS[kind].__qualname__}"
            )
        _STEP_SIMULATORS[kind] = fn
        return fn

    return deco


#: functions ``fn(station, campaign) -> {metric key: quantity}`` adding expected values
_EXPECTED_CONTRIBUTORS: list[Callable[..., Mapping[str, Any]]] = []


def register_expected(fn: Callable[..., Mapping[str, Any]]) -> Callable[..., Mapping[str, Any]]:
    """Decorator: ``fn(station, campaign)`` returns expected values (quantities by metric key) for
    the items whose motions a step module simulates (on ``campaign.segments``); merged into the
    campaign's ``expected``.  A value that needs the standard's formulas comes from its plugin
    (:func:`metro.instruments.stations.standard_expected`)."""
    if fn not in _EXPECTED_CONTRIBUTORS:
        _EXPECTED_CONTRIBUTORS.append(fn)
    return fn


def expected_contributors() -> list[Callable[..., Mapping[str, Any]]]:
    step_simulators()  # imports the step modules, which register their contributors
    return list(_EXPECTED_CONTRIBUTORS)


def step_simulators() -> Mapping[str, Callable[..., Segment]]:
    import importlib

    for mod in STEP_MODULES:
        importlib.import_module(mod)
    return _STEP_SIMULATORS


def record_expected_contributors() -> list[Callable[..., Mapping[str, Any]]]:
    """The functions :func:`register_record_expected` registered (the step modules imported
    first)."""
    step_simulators()  # imports the step modules, which register their contributors
    return list(_RECORD_EXPECTED)

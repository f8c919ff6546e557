"""Short within-U coverage runs: for each device class of the built-in simulated stations, a few
seeds of a few items through the public runner (as ``metro run`` without ``--data``), each
result compared with the truth the station declares (``campaign.expected``).

A result is *covered* when |result − truth| ≤ U, or when it is declared not reportable (with its
reason), as in ``benchmarks/within_u.py``.  A short run cannot measure a 95 % coverage; it finds
a budget that is grossly too small: the case passes when the covered fraction over its seeds and
results is within 0.95 ± 0.15 (at least 80 %).  The long sweeps (hundreds of seeds) are in the
standards' pages of docs/standards/.
"""

from __future__ import annotations

import functools
from typing import TYPE_CHECKING, Any, Sequence

from .case import ValidationCase

if TYPE_CHECKING:  # pragma: no cover
    from ..run.plugin_manager import MetroPluginManager

__all__ = ["CLASS_OPTIONS", "CLASS_RUNS", "coverage_cases", "covered", "covered_fraction"]

#: (standard, items, station, station options, the station's device classes)
CLASS_RUNS: tuple[tuple[str, tuple[str, ...], str, dict[str, Any], tuple[str, ...]], ...] = (
    ("gbt45570", ("D.5.1", "D.5.6"), "simulated", {"duration_scale": 0.1},
     ("pulse-fine", "pulse-fine-undithered", "pulse-coarse", "pulse-coarse-undithered",
      "lsb-fine", "lsb-coarse", "lsb-coarse-dithered", "rate-dh", "rate-ds")),
    ("jjf2014", ("7.2.3",), "simulated-jjf2014", {"duration_scale": 0.1},
     ("analog-fine", "analog-power-on", "analog-coarse", "analog-coarser", "analog-ratiometric")),
    ("jjf2003", ("7.2.1",), "simulated-mimu", {},
     ("mems-16bit", "mems-12bit", "mems-power-on", "mems-warmup")),
    ("ogam", ("7.1",), "simulated-ogam", {}, ("rlg-fine", "fog-coarse", "rlg-drifting")),
)

#: item options a device class is run with (what the class assumes: docs/standards/jjf2003.md);
#: a class run with repeats is left out of ``--quick`` (three calibrations a seed)
CLASS_OPTIONS: dict[str, dict[str, str]] = {"mems-power-on": {"repeats": "3"}}

#: the nominal coverage and the margin a short run is allowed
NOMINAL, MARGIN = 0.95, 0.15


def covered(rec: Any) -> list[bool]:
    """Per result the station declares a truth for: within U, or declared not reportable."""
    exp = rec.campaign.expected
    out = []
    for o in rec.outcomes:
        for r in o.results:
            if r.metric.key not in exp:
                continue
            if not r.reportable:
                out.append(True)
                continue
            if r.U is None:
                continue
            unit = r.U.units
            diff = abs(float((r.value - exp[r.metric.key]).to(unit).magnitude))
            out.append(diff <= float(r.U.magnitude))
    return out


def covered_fraction(pm: "MetroPluginManager", standard: str, items: Sequence[str], station: str,
                     options: dict[str, Any], seeds: Sequence[int],
                     item_options: dict[str, str] | None = None) -> float:
    """The fraction of (seed, result) pairs covered over ``seeds``, the items run with
    ``item_options`` on ``station`` with ``options`` and each seed (a run with no result the
    station declares a truth for is an error)."""
    from ..run.runner import run_items

    flags: list[bool] = []
    for seed in seeds:
        rec = run_items(pm, standard, list(items), station=station,
                        station_options=dict(options) | {"seed": seed},
                        options=dict(item_options or {}))
        flags += covered(rec)
    if not flags:
        raise ValueError(f"{standard} {', '.join(items)}: no result has a declared truth")
    return sum(flags) / len(flags)


def coverage_cases(pm: "MetroPluginManager", *, quick: bool = False) -> list[ValidationCase]:
    """One case per device class of the runs in :data:`CLASS_RUNS` whose standard and station
    are loaded: 5 seeds (1 with ``quick``, and the classes of :data:`CLASS_OPTIONS` left out)."""
    seeds = (1,) if quick else (1, 2, 3, 4, 5)
    stations = set(pm.register_all().stations)
    out = []
    for standard, items, station, options, classes in CLASS_RUNS:
        if station not in stations or not pm.procedures_of(standard):
            continue
        for cls in classes:
            out.append(ValidationCase(
                f"within-u:{standard}:{cls}",
                f"{standard} {', '.join(items)} on the {station} station, device class {cls}, "
                f"seeds {seeds[0]}–{seeds[-1]}: fraction of results within U",
                "simulated truth declared by the station (campaign.expected); nominal coverage "
                "95 % (JCGM 100 6.2), a short run allowed ±15 %",
                [NOMINAL], functools.partial(covered_fraction, pm, standard, items, station,
                                             options | {"device_class": cls}, seeds,
                                             CLASS_OPTIONS.get(cls)),
                atol=MARGIN, labels=("covered fraction",), quick=cls not in CLASS_OPTIONS))
    return out

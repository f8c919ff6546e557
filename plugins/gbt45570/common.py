"""What every GB/T 45570 item module shares: the standard's id, the coverage of its budgets, the
budget rows of the counter's time base, the scale factor and the output's resolution, and small
helpers on segments and options.  It imports no other item module, so they all can import it."""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, Coverage, DataError, EquipmentRequirement,
                       Procedure, RateConversion, Segment, msg, std_sampling_u)

STANDARD = "gbt45570"
COVERAGE = Coverage.probability(0.9545)
COUNTER = EquipmentRequirement("counter",
                               "gyro test system / counter; its time-base uncertainty enters the "
                               "budgets")
PLATFORM = EquipmentRequirement("platform",
                                "levelled stable platform (D.5.1.1 a)); its levelness enters the "
                                "bias budget")
#: the equipment of the static bias items (D.5): the platform's levelness and the counter's time
#: base
#: enter their budgets
BIAS_EQUIPMENT = (PLATFORM, COUNTER)


@attrs.frozen
class ItemRef:
    """An item of this standard as the data collectors name it in their messages (what they read of
    a :class:`~metro.api.Procedure` class: ``item`` and :meth:`qualified_id`), for helpers that
    collect another item's runs without importing its class."""

    item: str
    standard: str = STANDARD

    def qualified_id(self) -> str:
        """``standard:item``, as :meth:`metro.api.Procedure.qualified_id` gives it."""
        return f"{self.standard}:{self.item}"


#: the two directions of a rate point, as the steps name them (D.1.1.2 g), D.2.1.2 f))
DIRECTIONS = ((1, "counter-clockwise (+)"), (-1, "clockwise (−)"))


def kr_sampling_row(Kr: float, q: int) -> BudgetRow:
    """The type A row of K_r, a standard deviation of ``q`` scale factors (D.11 / D.28): from the
    χ² bound, (s_upper − K_r)/2 with ν = ∞."""
    return BudgetRow.type_a(msg("sampling of the standard deviation of Q = {q} scale factors "
                                "(χ² bound)", q=q),
                            "(s_{upper} − K_r)/2", Q_(std_sampling_u(Kr, q), ""), math.inf)


def opts_text(opts: Mapping[str, Any]) -> dict[str, str]:
    """An item's option values as the outcome records them (each as text)."""
    return {k: str(v) for k, v in opts.items()}


class GbtItem(Procedure):
    """The base of the GB/T 45570 items: the standard they belong to."""

    standard = STANDARD


def need_segments(campaign: Campaign, kind: str, what: str,
                  item: str | None = None) -> list[Segment]:
    """The campaign's segments of ``kind``; without one a DataError saying ``what`` is needed
    (with ``item``, naming the `metro plan` line that shows it)."""
    segs = campaign.find_segments(kind)
    if not segs:
        raise DataError(campaign.source, "segments", what,
                        hint=None if item is None else f"`metro plan --standard gbt45570 --item "
                                                       f"{item}` shows what to measure")
    return segs


def sequence_options(proc: Procedure, options: Mapping[str, Any]) -> dict[str, Any]:
    """The item's own options among ``options`` (a series plans every item with one set of
    options, some of them another item's), parsed by :meth:`Procedure.option_values`."""
    names = {o.name for o in proc.options}
    return proc.option_values({k: v for k, v in options.items() if k in names})


def timebase_row(campaign: Campaign, measured: float, unit: str, what: str) -> list[BudgetRow]:
    """The counter's time base as a relative row on a result ∝ 1/τ (none without a relative
    calibration of the ``counter``)."""
    eq = campaign.equipment_for("counter")
    if eq is None or eq.calibration is None:
        return []
    cal = eq.calibration
    if not cal.uncertainty.dimensionless:
        return []
    return [BudgetRow.from_calibration(
        msg("time base of the counter ({equipment})", equipment=eq.describe()), "u_rel(τ)", cal,
        sensitivity=Q_(abs(measured), unit),
        note=msg("{what} ∝ 1/τ; {certificate}", what=what, certificate=cal.certificate),
    )]


def scale_factor_row(conv: RateConversion, measured: float, unit: str) -> list[BudgetRow]:
    """The relative uncertainty of the scale factor K that converted the output, as a row on a
    result ∝ 1/K (none for a rate output or an exact K)."""
    if conv.output_kind == "rate" or conv.relative_u_scale_factor == 0.0:
        return []
    return [BudgetRow.type_b(
        msg("scale factor K used to convert the output"), "u_rel(K)",
        Q_(conv.relative_u_scale_factor, ""), distribution="normal", k=1.0,
        sensitivity=Q_(abs(measured), unit),
        note=msg("K = {K}; result ∝ 1/K", K=f"{conv.scale_factor:~P}"),
    )]


def signed_rate(campaign: Campaign, seg: Segment,
                zero: str = "a rate point cannot be 0 °/s") -> tuple[float, int]:
    """The ``rate`` condition of ``seg`` in °/s and its direction (+1 or −1); a rate of 0 is a
    DataError that ``zero`` words."""
    rate = float(seg.condition("rate", "deg/s").to("deg/s").magnitude)
    if rate == 0:
        raise DataError(campaign.source, f"segments.{seg.id}.conditions.rate", zero)
    return rate, 1 if rate > 0 else -1


def check_finite(raw: np.ndarray, seg: Segment) -> None:
    """A DataError naming the first sample of ``raw`` that is not finite."""
    ok = np.isfinite(raw)
    if not ok.all():
        i = int(np.argmin(ok))
        raise DataError(seg.file or f"segment {seg.id}", "output", f"sample {i + 1} is {raw[i]!r}")


def delta_temperature_u(campaign: Campaign) -> tuple[float, str] | None:
    """Standard uncertainty (K) of one chamber temperature reading, from the chamber's
    calibration."""
    ch = campaign.equipment_for("chamber")
    if ch is None or ch.calibration is None:
        return None
    U = ch.calibration.uncertainty
    # an uncertainty is a temperature *difference*: "0.3 K" or "0.3 delta_degC"; "0.3 °C" means the
    # same here
    mag = float(U.magnitude) if str(U.units) in ("degree_Celsius",
                                                 "degC") else float(U.to("K").magnitude)
    div = ch.calibration.k if ch.calibration.distribution == "normal" else math.sqrt(3.0)
    return mag / div, ch.describe()


def resolution(campaign: Campaign, unit: str = "LSB") -> float:
    """The output's resolution in ``unit``: the device's ``resolution`` if stated, else 1 LSB for
    an LSB output and 0 (none known) for a frequency or rate output."""
    if "resolution" in campaign.device.properties:
        return float(campaign.device.prop("resolution", unit,
                                          source=campaign.source).to(unit).magnitude)
    return 1.0 if unit == "LSB" else 0.0


def resolution_row(campaign: Campaign, c_norm: float, unit: str, what: str, *,
                   q: float | None = None,
                    raw_unit: str = "LSB", half_width: float | None = None,
                    note: str = msg("±half an LSB on each mean, independent")) -> BudgetRow:
    """Rounding of the output word: each mean F̄ is off by up to ±resolution/2 when the noise is
    smaller than one LSB (it then does not average out); ``c_norm`` = √Σc² of the result's
    sensitivities to the means, independent errors assumed.  ``q`` (default: :func:`resolution`),
    its ``raw_unit`` and a smaller ``half_width`` (noise that dithers the rounding) serve the D.5
    items' rows on LSB and rate outputs."""
    q = resolution(campaign) if q is None else q
    hw = q / 2.0 if half_width is None else half_width
    return BudgetRow.type_b(msg("output resolution {q:.4g} {unit}, through {what}", q=q,
                                unit=raw_unit, what=what), "δF",
                            Q_(hw, raw_unit),
                            distribution="uniform",
                            sensitivity=Q_(c_norm,
                                           f"({unit})/({raw_unit})" if unit else f"1/({raw_unit})"),
                            note=note)


def group_of(seg: Segment) -> tuple[str, str]:
    """The (``run``, ``temperature``) conditions of a D.2 segment: which test of D.2.1, D.2.4 or
    D.2.5 it belongs to ("" where absent)."""
    return str(seg.conditions.get("run", "")), str(seg.conditions.get("temperature", ""))


def repeat_runs(campaign: Campaign) -> list[str]:
    """The ``run`` values of D.2.4's tests (``rate-output`` segments with a run and no
    temperature), in the order of their numbers."""
    return sorted({group_of(s)[0] for s in campaign.find_segments("rate-output") if group_of(s)[0]
                   and not group_of(s)[1]}, key=lambda r: (len(r), r))


def grouped(campaign: Campaign, kind: str, key: str) -> dict[str, list]:
    """The segments of ``kind`` grouped by the value of their condition ``key``."""
    groups: dict[str, list] = {}
    for s in campaign.find_segments(kind):
        groups.setdefault(str(s.condition(key)), []).append(s)
    return groups

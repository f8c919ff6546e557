"""JJF 2003—2022: what the items of :mod:`.procedures` share — the segment requirements and
equipment of table 1, the coverage (JJF 1059.1 5.3.4), the appendix A budget rows u₁ (table)
and u₂ (acquisition quantization, A.3), and the sequences of 7.2.1.1 and appendix C."""

from __future__ import annotations

from typing import Any, Mapping

from metro.api import (Q_, BudgetRow, Campaign, Coverage, EquipmentRequirement, Option,
                       ProcedureError, SegmentRequirement, Step, msg)

from . import formulas as F
from .data import (ACCEL, AXES, GYRO, HEADINGS)

STANDARD = "jjf2003"
STATION = "simulated-mimu"
#: k = t_p(ν_eff), p = 95.45 % (JJF 1059.1 5.3.4): appendix A's "取 k = 2" with components stated
#: without degrees of freedom is the large-ν_eff case (interpretations.md, "Coverage factor (JJF
#: 2003)")
COVERAGE = Coverage.probability(0.9545)
ROUND = "up"


def mimu_segment(kind: str, description: str, conditions: dict[str, str],
                 min_count: int) -> SegmentRequirement:
    """A record of ``kind``: every gyro (°/s) and accelerometer (m/s²) column, ≥ 30 s."""
    return SegmentRequirement(kind=kind, description=description, conditions=conditions,
                              columns={c: ("deg/s",) for c in GYRO}
                              | {c: ("m/s**2",) for c in ACCEL},
                              min_duration=Q_(30, "s"), min_count=min_count)


RATE_SEG = mimu_segment("rate", "MIMU axis `axis` up along the rate table axis, table at `rate` "
                                "(signed about +axis), ≥ 30 s",
                        {"axis": "", "rate": "deg/s"}, 21)
POSITION_SEG = mimu_segment("position", "MIMU axis `up` (±x, ±y, ±z) to the zenith, table heading "
                                        "0° or 180°, ≥ 30 s (appendix C)",
                            {"up": "", "heading": "deg"}, 12)

EQUIPMENT = (
    EquipmentRequirement("rate_table",
                         "three-axis position/rate table (table 1); its rate uncertainty "
                         "(calibration, relative) and `position_accuracy` enter the "
                         "budgets", required=False),
    EquipmentRequirement("acquisition",
                         "data acquisition; its `bits` give the quantization term u₂ (A.3)"),
)
#: the items whose budgets hold the fixture's perpendicularity (6.2; the standard's bound when not
#: stated)
EQUIPMENT_FIXTURE = EQUIPMENT + (
    EquipmentRequirement("fixture", "fixture holding the MIMU on the table; its perpendicularity "
                                    "enters the cross-coupling budgets (6.2: the standard's bound "
                                    "when not stated)",
                         noted=False),
)

# ------------------------------------------------------------------------------ budget rows


def table_rate_row(campaign: Campaign, sensitivity, note: str,
                   warnings: list[str]) -> list[BudgetRow]:
    eq = campaign.equipment_for("rate_table")
    if eq is None or eq.calibration is None or not eq.calibration.uncertainty.dimensionless:
        warnings.append(msg("no three-axis table with a relative rate uncertainty (equipment role "
                            "\"table\", calibration U relative): u₁ (A.1.2.1) is missing from the "
                            "budget"))
        return []
    return [BudgetRow.from_calibration(msg("three-axis table rate ({equipment})",
                                           equipment=eq.describe()), "u₁", eq.calibration,
                                       sensitivity=sensitivity, note=note)]


def table_position_row(campaign: Campaign, sensitivity, note: str,
                       warnings: list[str]) -> list[BudgetRow]:
    eq = campaign.equipment_for("rate_table")
    if eq is None or "position_accuracy" not in eq.properties:
        warnings.append(msg("no `position_accuracy` of the three-axis table (equipment role "
                            "\"table\"): u₁ (A.2.2.1) is missing from the budget"))
        return []
    acc = eq.prop("position_accuracy", "deg", source=campaign.source)
    return [BudgetRow.type_b(msg("three-axis table positioning ({equipment})",
                                 equipment=eq.describe()), "u₁", acc.to("rad"),
                             distribution="uniform", sensitivity=sensitivity, note=note)]


def acquisition_bits(campaign: Campaign, warnings: list[str]) -> int | None:
    eq = campaign.equipment_for("acquisition")
    if eq is None or "bits" not in eq.properties:
        warnings.append(msg("no acquisition `bits` (equipment role \"acquisition\"): u₂ (A.1.2.2) "
                            "is missing from the budget"))
        return None
    return int(eq.properties["bits"])


def relative_quant_row(campaign: Campaign, scale: float, warnings: list[str]) -> list[BudgetRow]:
    """A.1.2.2: δ = 1/2^N relative, uniform, times the scale factor of the swept axis."""
    n = acquisition_bits(campaign, warnings)
    if n is None:
        return []
    return [BudgetRow.type_b(msg("acquisition quantization, {n} bits (A.3)", n=n), "u₂",
                             Q_(1.0 / 2**n, ""),
                             distribution="uniform", sensitivity=Q_(abs(scale), ""),
                             note=msg("δ = 1/2^N relative to full scale"))]


def abs_quant_row(campaign: Campaign, range_prop: str, unit: str, csum,
                  warnings: list[str]) -> list[BudgetRow]:
    """A.2.2.2 with (A.3): the quantization error δ = 1/2^N relative to the full scale FS, i.e. the
    half-width δ·FS = FS/2^N (half an LSB of an N-bit converter over ±FS), uniform, in every mean;
    sensitivity Σ|cᵢ| (the means' errors added linearly, as appendix A adds u₃)."""
    n = acquisition_bits(campaign, warnings)
    if n is None:
        return []
    dev = campaign.device
    if range_prop not in dev.properties:
        warnings.append(msg("no device `{prop}` (full scale): u₂ is missing from the budget",
                            prop=range_prop))
        return []
    fs = dev.prop(range_prop, unit, source=campaign.source).to(unit).magnitude
    half_width = float(fs) / 2**n  # δ·FS, δ = 1/2^N (A.3)
    return [BudgetRow.type_b(msg("acquisition quantization, {n} bits over ±{fs:g} (A.3)", n=n,
                                 fs=float(fs)), "u₂",
                             Q_(half_width, unit), distribution="uniform", sensitivity=csum,
                             note=msg("δ·FS = FS/2^N (half an LSB) in each mean, Σ|cᵢ|"))]


# ------------------------------------------------------------------------------ procedures


def rates_option(opts: Mapping[str, Any]) -> list[float]:
    from metro.api import parse_quantity

    out = []
    for t in str(opts["rates"]).split(","):
        t = t.strip()
        if not t:
            continue
        q = parse_quantity(t if any(ch.isalpha() or ch in "°/" for ch in t) else t + " deg/s",
                           dimension="deg/s", field="option rates")
        out.append(float(q.to("deg/s").magnitude))
    return out


def sweep_steps(opts: Mapping[str, Any]) -> list[Step]:
    steps = []
    for a in AXES:
        for r in rates_option(opts):
            steps.append(Step(f"rate-{a}-{r:g}", "rate",
                              f"MIMU {a} axis up along the table axis (7.2.1.1 a), e), f)); table "
                              f"at {r:g} °/s; record ≥ 30 s after the rate is "
                              "steady", Q_(30, "s"), Q_(0.01, "s"),
                              {"axis": a, "rate": Q_(r, "deg/s")}))
    raw = str(opts.get("repeats", "0")).strip() or "0"
    try:
        q = int(raw)
    except ValueError:
        q = -1
    if q < 0 or q == 1:
        raise ProcedureError(f"option repeats: {raw!r} must be 0 or a whole number ≥ 2 (repeated "
                             "calibrations)")
    for run in range(1, q + 1):
        for a in AXES:
            for r in rates_option(opts):
                steps.append(Step(f"rate-repeat#{run}-{a}-{r:g}", "rate-repeat",
                                  f"repeat {run}: power off, remount, then as 7.2.1.1 (MIMU {a} "
                                  f"axis up), table at {r:g} °/s, ≥ 30 s", Q_(30, "s"),
                                  Q_(0.01, "s"),
                                  {"axis": a, "rate": Q_(r, "deg/s"), "run": str(run)}))
    return steps


def position_steps() -> list[Step]:
    steps = []
    for up in F.SIX_POSITIONS:
        for h in HEADINGS:
            steps.append(Step(f"pos{up}-h{h:g}", "position",
                              f"MIMU {up} axis to the zenith, heading {h:g}° (7.2.2.1 a), appendix "
                              "C); hold ≥ 30 s",
                              Q_(30, "s"), Q_(0.01, "s"), {"up": up, "heading": Q_(h, "deg")}))
    return steps


SWEEP_OPTIONS = (Option("rates", "-400, -200, -100, -50, 0, 50, 100, 200, 400", None,
                         "rate points in °/s for each axis (7–11 including the maximum, 7.2.1.1 "
                         "c))"),
                  Option("repeats", "0", None,
                         "repeated calibrations (power off, remount) whose spread is u₃ of K "
                         "(appendix A.1.2.3); 0: none (u₃ then from "
                         "device.scale_factor_repeatability or the fit)"))


def options_text(opts):
    return {k: str(v) for k, v in opts.items()}



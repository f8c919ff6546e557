"""Draft JJF 光学陀螺测角仪校准规范: what the items of :mod:`.procedures` share — the
segment layout and the sequences, data access, and the appendix A budget rows of the 7.4 angle-
position error E (A 4.1–4.4, A 7–8) with the base of the items 7.4–7.7 that rest on it."""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, Coverage, DataError, EquipmentRequirement, Option,
                       Procedure, Result, Segment, SegmentRequirement, Step, UncertaintyBudget,
                       join, msg, parse_quantity)

from . import formulas as F

STANDARD = "ogam"
STATION = "simulated-ogam"
#: E: appendix A 8 and the certificate format of appendix B fix "k = 2" (interpretations.md,
#: "Coverage factor (ogam)")
COVERAGE = Coverage.fixed(2.0)
#: every other result (the draft fixes no k for them): k = t_p(ν_eff), p = 95.45 % (JJF 1059.1
#: 5.3.4)
COVERAGE_NU = Coverage.probability(0.9545)
#: "校准开始前, 光学陀螺测角仪完成预热和地球自转(地速)补偿操作" (clause 7): the instrument
#: removes the earth rate before every item; what its compensation leaves (η·Ω) is part of the
#: zero drift
EARTH_RATE = "removed"
EARTH_NOTE = msg("earth rate removed by the instrument's own compensation before the item (clause "
                 "7)")


def disclosed(res: Result) -> Result:
    """The result with its earth-rate statement (issue 13)."""
    note = join("; ", [res.note, EARTH_NOTE]) if res.note else EARTH_NOTE
    return attrs.evolve(res, earth_rate=EARTH_RATE, note=note)
REF_RATE = 60.0  # °/s, clauses 7.1, 7.4 and the reference of 7.6
RATES = (1.0, 10.0, 60.0, 100.0, 150.0, 200.0, 250.0, 300.0)  # clause 7.6
AXES = ("up", "north", "east")  # clause 7.7 (north may be south, east may be west)
ROUNDS = 10  # clause 7.5
#: table 1: turntable angle-positioning error ±0.1″, used when no turntable calibration is given
TABLE1_POSITIONING = Q_(0.1, "arcsec")
#: appendix A 1: sensing plane parallel to the turntable plane to better than 0.1°
DEFAULT_TILT = Q_(0.1, "deg")

SCALE = SegmentRequirement(
    "scale-factor", "axis vertical, 60 °/s, six rounds to 60°…360°, 60 s stop at each (7.1)",
    conditions={"rate": "deg/s", "axis": ""}, columns={"angle": ("deg",), "counts": ("P",)},
)
ZERO = SegmentRequirement(
    "zero", "instrument at rest on a stable platform, after 1 h warm-up a reading every 5 min for "
            "1 h (7.3)",
    columns={"reading": ("deg",)},
)
POSITIONING = SegmentRequirement(
    "positioning", "one round of the 7.4 table: twelve stops 30°…360°, 60 s each",
    conditions={"rate": "deg/s", "axis": "", "round": ""},
                                 columns={"standard": ("deg",), "reading": ("deg",)},
    min_count=1,
)
EQUIPMENT = (
    EquipmentRequirement("turntable",
                         "low-speed turntable of table 1 (positioning error ±0.1″, axis "
                         "up/north/east); its calibration (a uniform half-width) enters the E "
                         "budget",
                         required=False),
    EquipmentRequirement("timer", "timer (table 1)"),
)


# ------------------------------------------------------------------------------ sequences


def scale_step() -> Step:
    return Step("sf-60-up", "scale-factor",
                "axis vertical; zero both readouts; 60 °/s to 60°, 120°, …, 360°, stop 60 s at "
                "each; record the counts C_i of each round (7.1)",
                Q_(7, "min"), Q_(60, "s"),
                {"axis": "up", "rate": "60 deg/s", "step": "60 deg", "stops": "6"})


def pos_step(rate: float, axis: str, rnd: int) -> Step:
    turn_s = 360.0 / rate
    return Step(f"pos-{rate:g}-{axis}-r{rnd:02d}", "positioning",
                f"axis {axis}; zero both readouts; {rate:g} °/s through 30°, 60°, …, 360°, stop 60 "
                f"s at each; read M_i and S_i (7.4, round {rnd})",
                Q_(12 * 60 + turn_s, "s"), Q_(60, "s"),
                {"axis": axis, "rate": f"{rate:g} deg/s", "step": "30 deg", "stops": "12",
                 "round": str(rnd)})


def rounds_at_reference() -> list[Step]:
    return [pos_step(REF_RATE, "up", r) for r in range(1, ROUNDS + 1)]


# ------------------------------------------------------------------------------ data access


def rate_of(seg: Segment) -> float:
    return round(float(seg.condition("rate", "deg/s").to("deg/s").magnitude), 6)


def axis_of(seg: Segment, manifest: Any = None) -> str:
    a = str(seg.condition("axis")).strip().lower()
    if a not in ("up", "north", "south", "east", "west"):
        # the conditions are written in the manifest, not in the segment's data file
        raise DataError(manifest or seg.file, f"segments.{seg.id}.conditions.axis",
                        f"must be up, north, south, east or west (7.7), got {a!r}")
    return a


def round_of(seg: Segment, manifest: Any = None) -> int:
    v = seg.conditions.get("round", 1)
    try:
        return int(str(v))
    except ValueError:
        raise DataError(manifest or seg.file, f"segments.{seg.id}.conditions.round",
                        f"must be a whole number, got {v!r}") from None


def column_of(seg: Segment, name: str, unit: str) -> np.ndarray:
    s = seg.series(name, unit)
    a = np.asarray(s.data.to(unit).magnitude, dtype=float)
    bad = np.flatnonzero(~np.isfinite(a))
    if bad.size:
        raise DataError(seg.file or f"segment {seg.id}", name,
                        f"row {bad[0] + 1} is not a finite number")
    return a


def positioning_groups(campaign: Campaign) -> dict[tuple[float, str], list[tuple[int, Segment]]]:
    """Positioning segments by (rate °/s, axis), each list sorted by round."""
    out: dict[tuple[float, str], list[tuple[int, Segment]]] = {}
    for seg in campaign.find_segments("positioning"):
        out.setdefault((rate_of(seg), axis_of(seg, campaign.source)),
                       []).append((round_of(seg, campaign.source), seg))
    for key, lst in out.items():
        lst.sort(key=lambda x: x[0])
        rounds = [r for r, _ in lst]
        if len(set(rounds)) != len(rounds):
            raise DataError(campaign.source, "segments",
                            f"two positioning segments at {key[0]:g} °/s, axis {key[1]} have the "
                            "same round")
    return out


def round_errors(seg: Segment) -> tuple[np.ndarray, np.ndarray]:
    """(S_i in °, E_i = M_i − S_i in ″) of one positioning round (7.4)."""
    S = column_of(seg, "standard", "deg")
    M = column_of(seg, "reading", "deg")
    if S.size < 2:
        raise DataError(seg.file or f"segment {seg.id}", "standard",
                        "a round needs at least 2 stops")
    return S, F.position_errors_74(M, S) * F.ARCSEC_PER_DEG


def positioning_group(campaign: Campaign, rate: float, axis: str,
                      item: str) -> list[tuple[int, Segment]]:
    groups = positioning_groups(campaign)
    if (rate, axis) not in groups:
        have = ", ".join(f"{r:g} °/s {a}" for r, a in sorted(groups)) or "none"
        raise DataError(campaign.source, "segments",
                        f"{item} needs positioning segments at {rate:g} °/s with the axis {axis}; "
                        f"found: {have}",
                        hint=f"`metro plan -s ogam -i {item}` lists what to measure")
    return groups[(rate, axis)]


def error_matrix(rounds: list[tuple[int, Segment]]) -> tuple[np.ndarray, np.ndarray]:
    """(S_i, E_ij as rounds × positions, ″); every round must stop at the same S_i."""
    S0, rows = None, []
    for _, seg in rounds:
        S, E = round_errors(seg)
        if S0 is None:
            S0 = S
        elif S.size != S0.size or np.max(np.abs(S - S0)) > 1e-6:
            raise DataError(seg.file or f"segment {seg.id}", "standard",
                            "this round does not stop at the same standard angles as the first "
                            "round (7.5)")
        rows.append(E)
    return S0, np.vstack(rows)


def option_quantity(opts: Mapping[str, Any], name: str, dim: str) -> Any:
    v = opts.get(name)
    return None if v is None else parse_quantity(v, dimension=dim, field=f"option {name}")


# ------------------------------------------------------------------------------ budgets


def positioning_row(campaign: Campaign, warnings: list[str]) -> BudgetRow:
    """Appendix A 4.1: the turntable's angle-positioning error (from its calibration, else
    table 1)."""
    tt = campaign.equipment_for("turntable")
    if tt is not None and tt.calibration is not None:
        return BudgetRow.from_calibration(msg("turntable angle positioning ({equipment})",
                                              equipment=tt.describe()), "u(P)", tt.calibration)
    warnings.append(msg("no turntable calibration given: the E budget uses table 1's ±0.1″ "
                        "positioning error"))
    return BudgetRow.type_b(msg("turntable angle positioning (table 1 requirement, ±0.1″)"), "u(P)",
                            TABLE1_POSITIONING, distribution="uniform")


def tilt_row(psi: Any) -> tuple[BudgetRow, F.TiltSimulation]:
    """Appendix A 4.2: simulate the tilt ψ over 0…360° (eqs. (2)–(5)); its extreme is a uniform
    half-width."""
    sim = F.tilt_error_simulation(float(psi.to("deg").magnitude))
    row = BudgetRow.type_b(
        msg("sensing plane not parallel to the turntable plane"), "u(θ_ψ)",
                           Q_(sim.extreme_arcsec, "arcsec"),
        distribution="uniform",
        note=msg("ψ = {psi:g}°, simulated extreme {extreme:.4f}″ (appendix A 4.2)", psi=sim.psi_deg,
                 extreme=sim.extreme_arcsec))
    return row, sim


def drift_row(zero_stability: Any, time: Any) -> BudgetRow:
    """Appendix A 4.3: zero drift over the measurement time, a uniform half-width."""
    a = F.zero_drift_error(float(zero_stability.to("deg/h").magnitude),
                           float(time.to("min").magnitude))
    return BudgetRow.type_b(msg("zero drift of the instrument"), "u(δ)", Q_(a, "arcsec"),
                            distribution="uniform",
                            note=msg("{rate:g} °/h over {time:g} min",
                                     rate=zero_stability.to('deg/h').magnitude,
                                     time=time.to('min').magnitude))


def repeatability_row(R_arcsec: float, rounds: int) -> BudgetRow:
    """Appendix A 4.4: the 7.5 repeatability (largest R_i), type A with ν = rounds − 1."""
    return BudgetRow.type_a(msg("measurement repeatability (max R_i, 7.5)"), "u(r)",
                            Q_(R_arcsec, "arcsec"), rounds - 1,
                            note=msg("{n} rounds", n=rounds))


def reading_step_of(campaign: Campaign, E: np.ndarray) -> tuple[float, str]:
    """(q in ″, where it was seen): the step of the positioning readings, else of the 7.3 readings
    at rest (the same display; over an hour at rest the reading moves by whole steps), else 0."""
    q = F.reading_step(E)
    if q > 0.0:
        return q, "positioning"
    for seg in campaign.find_segments("zero"):
        qz = F.reading_step(column_of(seg, "reading", "arcsec")[:, None].T)
        if qz > 0.0:
            return qz, "zero"
    return 0.0, ""


def resolution_row(E: np.ndarray, campaign: Campaign | None = None) -> BudgetRow:
    """The reading's resolution, ±q/2 uniform, q the step the readings show
    (:func:`.formulas.reading_step`; interpretations.md, "7.4 — the reading's resolution"): a
    reading rounded coarser than the instrument's noise errs by a fixed amount at each stop that
    the repeatability of 7.5 does not see."""
    q, where = (reading_step_of(campaign, E) if campaign is not None
                else (F.reading_step(E), "positioning"))
    if q == 0.0:  # 7.4 then reports E as not reportable
        return BudgetRow.type_b(msg("resolution of the reading (every E_ij equal: the step is "
                                    "unknown)"), "u(q)",
                                Q_(0.0, "arcsec"), distribution="uniform")
    return BudgetRow.type_b(msg("resolution of the reading (±q/2)"), "u(q)", Q_(q / 2.0, "arcsec"),
                            distribution="uniform",
                            note=msg("q = {q:.3g}″, the smallest step between the readings", q=q)
                            if where == "positioning"
                            else msg("q = {q:.3g}″, the smallest step between the 7.3 readings at "
                                     "rest (the positioning readings all read the same)", q=q))


def e_budget(rows: list[BudgetRow]) -> UncertaintyBudget:
    """Appendix A 7–8: u_c = sqrt(u(P)² + u(θ_ψ)² + u(δ)² + u(r)²), U = 2·u_c, with the reading's
    resolution u(q) added (not in appendix A, whose instrument reads far finer than its noise)."""
    return UncertaintyBudget("E", "arcsec", rows, coverage=COVERAGE)


def zero_stability_of(campaign: Campaign, opts: Mapping[str, Any]) -> Any:
    v = option_quantity(opts, "zero_stability", "deg/h")
    if v is not None:
        return v
    if "zero_stability" in campaign.device.properties:
        return campaign.device.prop("zero_stability", "deg/h", source=campaign.source)
    raise DataError(campaign.source, "device.zero_stability",
                    "missing: the E budget (appendix A 4.3) needs the instrument's zero stability",
                    hint="add zero_stability = \"0.005 °/h\" under [device] or give -o "
                         "zero_stability=…")


class OgamItem(Procedure):
    """An item of the draft: its standard, the simulated station and the equipment of table 1."""

    standard = STANDARD
    station = STATION
    equipment = EQUIPMENT


class ScaleFactorItem(OgamItem):
    """The items read from the 7.1 rounds to 60°…360° at 60 °/s (7.1 and 7.2)."""

    requires = (SCALE,)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return [scale_step()]


class PositionErrorItem(OgamItem):
    """Shared by the items whose results rest on the 7.4 angle-position error."""

    requires = (POSITIONING,)
    options = (
        Option("tilt", None, None,
               "largest sensing-plane/turntable tilt ψ (default: the turntable's `parallelism` "
               "property, else 0.1° as appendix A 1)"),
        Option("zero_stability", None, None,
               "instrument zero stability for appendix A 4.3 (default: device property "
               "zero_stability)"),
        Option("drift_time", "0.5 min", None,
               "measurement time for the drift term (appendix A 1 and 4.3: 0.5 min)"),
    )

    def _reference(self, campaign: Campaign, opts: Mapping[str, Any], warnings: list[str]):
        """(S, E_ij at 60 °/s axis up, R, R_i, the E budget rows, the tilt simulation)."""
        rounds = positioning_group(campaign, REF_RATE, "up", self.item)
        S, E = error_matrix(rounds)
        if E.shape[0] < 2:
            raise DataError(campaign.source, "segments",
                            f"only {E.shape[0]} round at 60 °/s with the axis up: the "
                            "repeatability (7.5) and the E budget (appendix A 4.4) need the 7.4 "
                            "test repeated (10 rounds)",
                            hint="record rounds 1…10 as segments with conditions round = 1 … 10")
        if E.shape[0] < ROUNDS:
            warnings.append(msg("{n} rounds at 60 °/s; clause 7.5 asks for {asked}", n=E.shape[0],
                                asked=ROUNDS))
        R, R_i = F.repeatability_75(E)
        psi = option_quantity(opts, "tilt", "deg")
        if psi is None:
            tt = campaign.equipment_for("turntable")
            psi = (tt.prop("parallelism", "deg")
                   if tt is not None and "parallelism" in tt.properties else DEFAULT_TILT)
        trow, sim = tilt_row(psi)
        time = parse_quantity(opts["drift_time"], dimension="min", field="option drift_time")
        rows = [positioning_row(campaign, warnings), trow,
                drift_row(zero_stability_of(campaign, opts), time),
                repeatability_row(R, E.shape[0]), resolution_row(E, campaign)]
        return S, E, rounds, R, R_i, rows, sim

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return rounds_at_reference()



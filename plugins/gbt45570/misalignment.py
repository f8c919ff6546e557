"""Input-axis misalignment from four mountings (GB/T 45570 D.1.6, angle method, and D.2.6, rate
method): the mountings' steps and segments, α, β and γ with their budgets (D.15/D.32, D.35,
D.16/D.36), and the procedure both items share, which differs only in how one mounting's angle
is read from its segments."""

from __future__ import annotations

import abc
import math
from typing import Any, Mapping

import attrs
from metro.api import (Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Metric, Outcome,
                       Procedure, Result, RunContext, Step, TableSpec, UncertaintyBudget, msg,
                       parse_quantity)

from . import formulas_rate as F2
from .common import COVERAGE, DIRECTIONS, STANDARD, GbtItem, opts_text
from .revolutions import REPEAT_RATE

#: the four mountings of D.1.6.3 / D.2.6.3: (axis along the table axis, turn about IRA)
MOUNTINGS = (("XRA", 0), ("XRA", 180), ("YRA", 0), ("YRA", 180))
FIXTURE = EquipmentRequirement("fixture",
                               "fixture holding XRA/YRA along the table axis, turnable 180° about "
                               "IRA; its re-seating tilt enters the budget")


def mounting_groups(campaign: Campaign, kind: str, clause: str) -> dict[tuple[str, int], list]:
    """Segments of each of the four mountings (conditions ``axis_up`` XRA/YRA and ``turn`` 0°/180°);
    a missing mounting is an error that names it."""
    groups: dict[tuple[str, int], list] = {}
    for s in campaign.find_segments(kind):
        ax = str(s.condition("axis_up")).upper().replace("+", "").strip()
        turn = (
            float(
                parse_quantity(
                    s.condition("turn"),
                    dimension="deg",
                    file=campaign.source,
                    field=f"segments.{s.id}.conditions.turn",
                )
                .to("deg")
                .magnitude
            )
            % 360.0
        )
        if ax not in ("XRA", "YRA") or min(abs(turn), abs(turn - 180.0)) > 1e-6:
            raise DataError(campaign.source, f"segments.{s.id}.conditions",
                            f"axis_up = {s.conditions.get('axis_up')!r}, turn = "
                            f"{s.conditions.get('turn')!r}: a {clause} mounting has XRA or YRA "
                            f"along the table axis, turned 0° or 180° about IRA")
        groups.setdefault((ax, int(round(turn))), []).append(s)
    missing = [f"{ax} up, turned {t}°" for ax, t in MOUNTINGS if (ax, t) not in groups]
    if missing:
        raise DataError(campaign.source, "segments",
                        f"{clause} needs four mountings (segments of kind \"{kind}\"); missing: "
                        f"{'; '.join(missing)}",
                        hint="the 180° turn about IRA cancels the fixture's error (D.1.6.3 e))")
    return groups


def misalignment_outcome(proc: Procedure, campaign: Campaign, opts, ang: Mapping[tuple[str, int],
                                                                                 tuple[float, float,
                                                                                       int]],
                         rel_rows: list[BudgetRow], segments: list[str], what: str) -> Outcome:
    """α, β (D.15/D.32, D.35) and γ (D.16/D.36) with their budgets from the four mountings'
    angles ``ang[(axis, turn)] = (angle in °, its type A standard uncertainty in °, ν)``.

    ``rel_rows`` are relative type B rows (scale factor, revolution pulse …) with sensitivity 1;
    each is scaled by the result.  The fixture's re-seating tilt (``fixture`` equipment,
    ``reseat_tilt``, a half-width per mounting) enters each angle with sensitivity 1/√2."""
    fx = campaign.equipment_for("fixture")
    reseat = None
    if fx is not None and "reseat_tilt" in fx.properties:
        reseat = (fx.prop("reseat_tilt", "arcsec", source=campaign.source), fx.describe())
    vals, us, nus = {}, {}, {}
    for sym, ax in (("α", "XRA"), ("β", "YRA")):
        (a1, u1, n1), (a2, u2, n2) = ang[(ax, 0)], ang[(ax, 180)]
        vals[sym] = F2.misalignment_half_difference_d15(a1, a2)
        us[sym] = 0.5 * math.hypot(u1, u2)
        nus[sym] = max(min(n1, n2), 1)
    gamma = F2.misalignment_gamma_d16(vals["α"], vals["β"])
    results = []
    for metric in proc.metrics:
        sym = metric.symbol
        if sym in vals:
            v = vals[sym]
            rows = [BudgetRow.type_a(msg("{what}, the two {sym} mountings", what=what, sym=sym),
                                     f"u({sym})", Q_(us[sym], "deg"), nus[sym])]
            sens_reseat = 1.0 / math.sqrt(2.0)
        else:
            v = gamma
            ca = vals["α"] / gamma if gamma > 0 else 1.0
            cb = vals["β"] / gamma if gamma > 0 else 1.0
            rows = [BudgetRow.type_a(msg("{what}, α mountings", what=what), "u(α)", Q_(us["α"],
                                                                                       "deg"),
                                     nus["α"],
                                     sensitivity=Q_(abs(ca), "")),
                    BudgetRow.type_a(msg("{what}, β mountings", what=what), "u(β)", Q_(us["β"],
                                                                                       "deg"),
                                     nus["β"],
                                     sensitivity=Q_(abs(cb), ""))]
            sens_reseat = math.hypot(ca, cb) / math.sqrt(2.0)
        if reseat is not None:
            rows.append(BudgetRow.type_b(msg("re-seating tilt of the gyro in the fixture "
                                             "({equipment})", equipment=reseat[1]),
                                         "δ_{fixture}",
                                         reseat[0].to("deg"), distribution="uniform",
                                         sensitivity=Q_(sens_reseat, ""),
                                         note=msg("independent in the 0° and 180° mountings; (δ₁ − "
                                                  "δ₂)/2")))
        rows += [attrs.evolve(r, sensitivity=Q_(abs(v), "deg")) for r in rel_rows]
        budget = UncertaintyBudget(sym, "deg", rows, coverage=COVERAGE)
        results.append(Result(metric, Q_(v, "deg"), budget.combined, budget,
                              note=f"= {v * 3600:.2f}″", earth_rate="removed"))
    table = TableSpec("mountings", msg("Angle of each mounting ({item})", item=proc.item),
                      [msg("mounting"), msg("angle (°)"), msg("angle (″)")],
                      [[msg("{axis} up, turned {turn}°", axis=ax, turn=t), f"{ang[(ax, t)][0]:.6f}",
                        f"{ang[(ax, t)][0] * 3600:.2f}"]
                       for ax, t in MOUNTINGS])
    return Outcome(STANDARD, proc.item, proc.title, proc.clause, results, tables=[table],
                   segments=segments,
                   options=opts_text(opts))


def misalignment_metrics(clause: str, eqs: tuple[str, str, str]) -> tuple[Metric, ...]:
    """The metrics α, β, γ of D.1.6 / D.2.6 with their clause and equations."""
    return (Metric("alpha", "input axis misalignment towards XRA", "α", "deg", clause, eqs[0]),
            Metric("beta", "input axis misalignment towards YRA", "β", "deg", clause, eqs[1]),
            Metric("gamma", "input axis misalignment", "γ", "deg", clause, eqs[2]))


def mounting_steps(kind: str, rate: float, options: Mapping[str, Any],
                   revolutions: bool) -> list[Step]:
    """The steps of the four mountings (D.1.6.3 / D.2.6.3), each direction at ``rate`` (°/s):
    whole revolutions counted (``revolutions``) or the output sampled."""
    m = int(options.get("turns", 5))
    steps = []
    for ax, turn in MOUNTINGS:
        for sign, word in DIRECTIONS:
            cond = {"axis_up": ax, "turn": f"{turn} deg", "rate": f"{sign * rate:g} deg/s"}
            what = (f"{m} whole revolutions" if revolutions else f"{m} whole revolutions' output")
            if revolutions:
                cond["turns"] = m
            steps.append(Step(f"{ax}-{turn}-rate{sign * rate:+g}", kind,
                              f"{ax} along the table axis, gyro turned {turn}° about IRA in the "
                              f"fixture: {what} at {rate:g} °/s {word}", Q_(m * 360.0 / rate, "s"),
                              Q_(360.0 / rate, "s") if revolutions else Q_(1, "s"), cond,
                              warmup=Q_(30, "min")))
    return steps


@attrs.frozen
class DeviceScale:
    """The device's scale factor the mountings' angles divide by (D.14 / D.30)."""

    k: float  #: K, in the output's unit per °/s (P/″ for pulses)
    u_rel: float  #: its relative standard uncertainty (0: none stated or none needed)
    unit: str = ""  #: the output's unit (LSB, Hz, deg/s; P for pulses)
    reference: str = ""  #: the segment whose unit every mounting's must match


class MountingMisalignment(GbtItem):
    """The procedure D.1.6 (angle method) and D.2.6 (rate method) share: the four mountings'
    steps at the ``rate`` option, their segments (:func:`mounting_groups`), one angle per mounting
    and α, β, γ with their budgets (:func:`misalignment_outcome`).  A subclass says how one
    mounting's angle is read (:meth:`mounting_angle`), which scale factor of the device it divides
    by (:meth:`scale_factor`) and which relative type B rows scale the result
    (:meth:`relative_rows`)."""

    #: the kind of the mountings' segments
    mounting_kind = ""
    #: whether each step counts the pulses of whole revolutions (angle method) or samples the output
    revolutions = True
    #: the source of the angles' type A rows
    scatter = ""

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        r = float(parse_quantity(options.get("rate", REPEAT_RATE),
                                 dimension="deg/s").to("deg/s").magnitude)
        return mounting_steps(self.mounting_kind, r, options, revolutions=self.revolutions)

    @abc.abstractmethod
    def scale_factor(self, campaign: Campaign,
                     groups: Mapping[tuple[str, int], list]) -> DeviceScale:
        """The device's K the angles divide by (what :meth:`mounting_angle` and
        :meth:`relative_rows` are given)."""

    @abc.abstractmethod
    def mounting_angle(self, campaign: Campaign, mounting: tuple[str, int], segs: list,
                       scale: DeviceScale) -> tuple[tuple[float, float, int], list[str]]:
        """One mounting's (angle in °, its type A standard uncertainty in °, ν) and the ids of the
        segments it used."""

    @abc.abstractmethod
    def relative_rows(self, campaign: Campaign, scale: DeviceScale) -> list[BudgetRow]:
        """Relative type B rows (sensitivity 1), each scaled by the result."""

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        groups = mounting_groups(campaign, self.mounting_kind, self.item)
        scale = self.scale_factor(campaign, groups)
        ang, used = {}, []
        for mounting, segs in groups.items():
            ang[mounting], ids = self.mounting_angle(campaign, mounting, segs, scale)
            used += ids
        rel = self.relative_rows(campaign, scale)
        return misalignment_outcome(self, campaign, opts, ang, rel, used, self.scatter)

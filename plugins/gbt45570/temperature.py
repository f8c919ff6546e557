"""The temperature points of D.1.5 and D.2.5 (scale-factor temperature sensitivity, eqs. D.12 and
D.29): room temperature picked among them, and the result, budget, plot and table both items give
from the scale factors at each point."""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, Outcome, PlotSpec, Procedure, Result,
                       TableSpec, UncertaintyBudget, hint, join, max_slope_selection, msg,
                       selection_note, selection_rows)

from .common import COVERAGE, STANDARD, delta_temperature_u, opts_text
from .repeatability import missing_turn_on, points_dof, pool_turn_on, scale_factor_turn_on


def room_index(campaign: Campaign, segs_by_T: Mapping[str, list], room: float, need: int,
               clause: str) -> tuple[
        list[str], list[float], int]:
    """The temperature points (sorted), their values in °C and the index of room temperature
    (the point nearest ``room``, which must lie in 6.1.1's 15 °C … 35 °C)."""
    keys = sorted(segs_by_T, key=lambda k: float(parse_T(campaign, segs_by_T[k][0])))
    if len(keys) < need:
        raise DataError(campaign.source, "segments",
                        f"{clause} needs at least {need} temperature points (both limits and room "
                        f"temperature); found {len(keys)}: {', '.join(keys) or 'none'}")
    temps = [parse_T(campaign, segs_by_T[k][0]) for k in keys]
    i0 = int(np.argmin([abs(t - room) for t in temps]))
    if not 15.0 <= temps[i0] <= 35.0:
        raise DataError(campaign.source,
                        f"segments.{segs_by_T[keys[i0]][0].id}.conditions.temperature",
                        f"no point at room temperature: the nearest is {temps[i0]:g} °C (6.1.1: 15 "
                        f"°C … 35 °C); {clause} refers K_t to room temperature")
    for i, t in enumerate(temps):
        if i != i0 and abs(t - temps[i0]) < 1.0:
            raise DataError(campaign.source,
                            f"segments.{segs_by_T[keys[i]][0].id}.conditions.temperature",
                            f"{t:g} °C is within 1 °C of room temperature {temps[i0]:g} °C; K_t "
                            f"divides by T_i − T0")
    return keys, temps, i0


def parse_T(campaign: Campaign, seg) -> float:
    """The segment's ``temperature`` condition in °C."""
    return float(seg.condition("temperature", "degC").to("degC").magnitude)


def temperature_outcome(proc: Procedure, campaign: Campaign, opts, Kt: float, imax: int, i0: int,
                        temps, Ks, uKs,
                         dofs, segments, k_unit: str) -> Outcome:
    """Result, budget, plot and table of D.1.5 / D.2.5 (the maximising point of D.12 / D.29)."""
    dT = temps[imax] - temps[i0]
    K0 = Ks[i0]
    ci, c0 = 1.0 / (K0 * abs(dT)), abs(Ks[imax]) / (K0 * K0 * abs(dT))
    # D.1.5.2 c) / D.2.5.2 c): off while the chamber changes temperature, so each K_i is a power-on
    # of
    # its own and carries K's turn-on scatter (D.1.4 / D.2.4 on this campaign; interpretations.md
    # "D.2.5 — every temperature point is a power-on" and "D.1.5 — …")
    # (σ_K² the posterior mean of the turn-on variance given the runs, ν = ∞: interpretations.md
    # "σ_K — …")
    on = scale_factor_turn_on(campaign, int(opts.get("min_points", 11)),
                              "angle" if proc.item == "D.1.5" else "rate")
    on, pooled_note = pool_turn_on(Ks, uKs, temps, on)
    s_on, nu_on, on_note = on.sigma, on.nu, on.note
    u_on = [s_on * abs(k) for k in Ks]
    # the points may share a power-on after all: at most what they show
    sel_observed = s_on > 0 and len(Ks) >= 4
    uKs = [math.hypot(u, v) for u, v in zip(uKs, u_on)]
    # the two turn-on parts are one estimate (σ_K of the same runs): one ν between them, not two
    # (interpretations.md "D.2.5 — the line test with an estimated scatter")
    u_on_both = math.hypot(ci * u_on[imax], c0 * u_on[i0])
    parts = [(ci * math.sqrt(max(uKs[imax] ** 2 - u_on[imax] ** 2, 0.0)), dofs[imax]),
             (c0 * math.sqrt(max(uKs[i0] ** 2 - u_on[i0] ** 2, 0.0)), dofs[i0]),
             (u_on_both, nu_on)]
    uA = math.sqrt(sum(u * u for u, _ in parts))
    den = sum(u**4 / max(d, 1) for u, d in parts)
    nu = uA**4 / den if den > 0 else math.inf
    # the line test of the selection Monte Carlo against u's whose turn-on part rests on an estimate
    # of
    # on.dof degrees of freedom (the runs', pooled): F(n − 2, ν_eff of the points' u) rather than χ²
    sel = max_slope_selection(Ks, uKs, temps, i0, relative=True, observed=sel_observed,
                                 u_dof=points_dof(uKs, u_on, dofs,
                                                  on.dof if on.dof > 0 else math.inf))
    notes = _turn_on_notes(uA, on, pooled_note)
    rows = [BudgetRow.type_a(msg("K at every T_i and T_0 through the maximum of the ratios (Monte "
                                 "Carlo about the "
                                 "smoothed K(T))"), "s(max_i |ΔK_i/(K₀₀ΔT_i)|)", Q_(max(sel.s, uA),
                                                                                    "1/delta_degC"),
                             nu,
                             note=join("; ", notes))]
    rows += selection_rows(sel, len(Ks) - 1, "1/delta_degC")
    Kt = max(sel.value, 0.0)
    uT = delta_temperature_u(campaign)
    if uT is not None:
        rows.append(BudgetRow.type_b(msg("chamber temperature T_i and T_0 ({equipment})",
                                         equipment=uT[1]), "√2·u(T)",
                                     Q_(math.sqrt(2) * uT[0], "K"), distribution="normal", k=1.0,
                                     sensitivity=Q_(Kt / abs(dT), "1/delta_degC/K"),
                                     note="∂K_t/∂ΔT = −K_t/ΔT"))
    budget = UncertaintyBudget("K_t", "ppm/delta_degC", rows, coverage=COVERAGE)
    res = Result(proc.metrics[0], Q_(Kt, "1/delta_degC"), budget.combined, budget,
                 note=join("; ", [msg("largest at T = {T:g} °C against T0 = {T0:g} °C",
                                      T=temps[imax], T0=temps[i0]),
                                  selection_note(sel, 1e6,
                                                 'ppm/°C')] + ([on_note] if on_note else [])),
                 earth_rate="removed")
    # each point a power-on of its own (D.1.5.2 c) / D.2.5.2 c)): without K's turn-on scatter
    # bounded by
    # ≥ MIN_TURN_ON_RUNS D.1.4 / D.2.4 runs or stated (device.scale_factor_repeatability), not
    # reportable
    if not on.known:
        why = msg("each temperature point is a power-on of its own ({clause}.2 c))",
                  clause=proc.item)
        res = attrs.evolve(res, reportable=False, reason=join("; ", [missing_turn_on(
            "K", "D.1.4" if proc.item == "D.1.5" else "D.2.4", why), on_note]))
    plot = PlotSpec("K_temperature", msg("Scale factor against temperature ({item})",
                                         item=proc.item), "T (°C)",
                    "(K − K₀₀)/K₀₀ (ppm)",
                    [{"label": "K(T)", "x": list(temps), "y": [(k - K0) / K0 * 1e6 for k in Ks],
                      "yerr": [2e6 * u / K0 for u in uKs], "style": "o"}])
    table = TableSpec("K_temperatures", msg("K at each temperature point"), ["T (°C)",
                                                                             f"K ({k_unit})",
                                                                        "|(K − K₀₀)/(K₀₀ΔT)| "
                                                                        "(ppm/°C)"],
                      [[f"{t:g}", f"{k:.8g}",
                        msg("room (T0)") if i == i0
                        else f"{abs((k - K0) / (K0 * (t - temps[i0]))) * 1e6:.4g}"]
                       for i, (t, k) in enumerate(zip(temps, Ks))])
    return Outcome(STANDARD, proc.item, proc.title, proc.clause, [res], plots=[plot],
                   tables=[table],
                   segments=list(segments), options=opts_text(opts))


def _turn_on_notes(uA: float, on: Any, pooled_note: str) -> list[str]:
    """The notes on D.1.5 / D.2.5's type A row: the maximising point's own u and the turn-on
    scatter of K each point carries (measured, bounded or stated)."""
    s_on = on.sigma
    notes = [msg("the maximising point alone gives {u:.3g}/°C", u=uA)]
    if s_on > 0 and on.dof > 0:
        notes.append(msg("each K_i a power-on of its own: with the turn-on scatter of K, {s:.3g} "
                         "ppm (the posterior mean of its variance given {d:.3g} degrees of freedom "
                         "of the repeatability runs on this campaign{resolved}; ν = "
                         "∞)", s=s_on * 1e6, d=on.dof,
                         resolved=msg(", K_r² − mean u²(K_j)/K_j² ≤ 0: not resolved from the runs' "
                                      "own noise, only bounded") if on.s2 <= on.within else ""))
    elif s_on > 0:
        notes.append(msg("each K_i a power-on of its own: with the turn-on scatter of K, {s:.3g} "
                         "ppm stated for the device{hint}", s=s_on * 1e6,
                         hint=hint(" (device.scale_factor_repeatability)")))
    if pooled_note:
        notes.append(pooled_note)
    return notes

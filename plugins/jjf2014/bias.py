"""JJF 2014—2022 7.2.13–7.2.19: bias, bias stability, repeatability, temperature and acceleration
sensitivity, change after shock and vibration."""

from __future__ import annotations

import math
import statistics
from typing import Any

import attrs
import numpy as np
from metro.api import (INF, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Metric,
                       Option, ProcedureError, Result, Segment, SegmentRequirement, Step, TableSpec,
                       allan, curve_scatter, hint, join, max_abs_selection, max_slope_selection,
                       msg, selection_note, selection_rows, spread_rows)

from . import budgets as B
from . import formulas as F
from .common import (AXES, RATE_OPTS, JJFItem, KValue, SFSet, Spread, axis_of, before_after_change,
                     bias_repeatability, budget_row_a, calibration_of, chamber_rows,
                     chamber_temperatures, flag_option, group_by, need_segments, num_option,
                     one_estimate, parse_floats, phase_of, quantity_text, read_output, room_index,
                     rounding_row_mean, scale_factor_for, up_or_down, where_of, with_scatter)
from .scale_factor import ScaleFactor

# =============================================================================== 7.2.13 – 7.2.19


STATIC_STEP_DESC = "IRA vertical on the base, warm-up ≤ 30 min, record (7.2.13.1)"
EARTH_OPT = Option("earth_rate", "off", None,
                   "on: subtract 15.041·sin(latitude) °/h for IRA up (add for down); the standard "
                   "has no such term")


def static_segment(campaign: Campaign, proc, warnings: list[str]) -> Segment:
    """The 7.2.13.1 record: the one segment of kind "static" (several: the first, with a
    warning)."""
    segs = need_segments(campaign, proc, "static")
    if len(segs) > 1:
        warnings.append(msg("{n} segments of kind static; {item} uses the first, {id!r}",
                            n=len(segs), item=proc.item, id=segs[0].id))
    return segs[0]


def _earth_text(campaign, on: bool, per_g: bool = False) -> str:
    """What the result says about the earth rate (issue 13: every result discloses it)."""
    try:
        lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
        v = F.EARTH_RATE_DEG_PER_H * math.sin(math.radians(lat))
        amount = (msg("Ω_e·sin φ = {v:.4g} °/h at φ = {lat:g}°", v=v, lat=lat) if not per_g else
                  msg("Ω_e·sin φ = {v:.4g} °/h (→ {v:.4g} °/h/g in (B_up − B_down)/2g) at φ = "
                      "{lat:g}°", v=v, lat=lat))
    except Exception:  # no latitude: say it without the number
        amount = "Ω_e·sin φ"
    if on:
        return msg("earth rate removed ({amount}; not in the standard){hint}", amount=amount,
                   hint=hint(" (-o earth_rate=on)"))
    return msg("earth rate included: the vertical input axis senses {amount}; the standard has no "
               "correction{hint}",
               amount=amount, hint=hint(" (-o earth_rate=on removes it)"))


def _earth_term(campaign, seg: Segment | None, on: str, orient: str | None = None) -> float:
    """Earth-rate correction (°/h) to subtract; 0 unless the option is on (README reading note)."""
    if not flag_option({"earth_rate": on}, "earth_rate"):
        return 0.0
    lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    o = orient or (str(seg.conditions.get("orientation", "IRA up")).lower() if seg is not None
                   else "ira up")
    sign = -1.0 if "down" in o else 1.0
    return sign * F.EARTH_RATE_DEG_PER_H * math.sin(math.radians(lat))


class BiasValue:
    """B_0 of one static segment (eqs. (27), (28)) in °/h with its batch-means type A u."""

    def __init__(self, seg: Segment, K: float, earth: float = 0.0, batches: int = 20):
        x, dt = read_output(seg)
        if x.size < 2 * batches:
            raise DataError(seg.file or seg.id, "output",
                            f"{x.size} samples are too few for {batches} batch means")
        self.seg, self.x, self.dt, self.K = seg, x, dt, K
        self.Fbar = F.mean_output_eq2(x)
        self.B0 = F.bias_eq27_28(x, K) * 3600.0 - earth  # °/h
        # 20 batch means, or 5 long ones when an F test shows the short ones correlated (flicker,
        # wander): their scatter then understates the mean's u
        # (metro.core.stats.allan.mean_u_batches; interpretations.md, "D.5.1 — correlated noise":
        # B₀ was within U on 43–67 % of the independent harness's flicker devices)
        bm = allan.mean_u_batches(x, batches)
        self.correlated = bm.correlated
        self.uA = bm.u / abs(K) * 3600.0
        self.dof = bm.batches - 1


def _rounded(campaign: Campaign, bv: BiasValue, what, scale: float, unit: str) -> list[BudgetRow]:
    """The rounding row of one bias record on a digitised output, times ``scale`` (as
    :func:`_single`): ±q/2 on F̄ when the noise does not dither the rounding, else the Widrow
    bound, over K (interpretations.md, "JJF 2014 — output quantization")."""
    return rounding_row_mean(campaign, bv.x, what, scale * 3600.0 / abs(bv.K), unit)


def _u_single(bv: BiasValue, rep: Spread | None, kv: "KValue | None" = None) -> float:
    """u (°/h) of one bias record as the device's bias at its condition: as :func:`_single` and,
    without a bias repeatability, with :func:`_power_on` (its power-on's K)."""
    if rep is not None and rep.value > bv.uA:
        return rep.value
    return math.hypot(bv.uA, kv.power_on_u(bv.B0) if (kv is not None and rep is None) else 0.0)


def _power_on(bv: BiasValue, rep: Spread | None, kv: "KValue", what: str, scale: float,
              unit: str) -> list[BudgetRow]:
    """Without a bias repeatability B_r (which holds it: each of its runs is a power-on divided by
    the same K), the record's own power-on K differs from the 7.2.1 calibration's by K_r:
    |B₀|·K_r·scale (:meth:`KValue.power_on_rows`; interpretations.md, "7.2.13 — the static record
    is another power-on")."""
    return kv.power_on_rows(bv.B0, scale, unit, what) if rep is None else []


def _power_on_note(rep: Spread | None, kv: "KValue") -> str:
    """The budget's note when B_r is not known: a record that is a power-on of its own differs from
    another by the turn-on scatter of the bias, which only 7.2.15's runs (or a stated B_r) measure
    — and, without K_r either, by the variation of K between power-ons."""
    if rep is not None:
        return ""
    if kv.kr is None:
        return msg("no bias repeatability (7.2.15) and no K_r (7.2.4): the variation of K between "
                   "power-ons is not in this budget{hint}",
                   hint=hint(" (give rate-repeat runs or device.scale_factor_repeatability)"))
    return msg("no bias repeatability (7.2.15): where the records are power-ons of their own, the "
               "turn-on scatter of the bias between them is not in this budget{hint}",
               hint=hint(" (give static-repeat runs or device.bias_repeatability)"))


def _single(bv: BiasValue, rep: Spread | None, what: str, scale: float, unit: str) -> BudgetRow:
    """The row of one bias record taken as the device's bias at its condition, times ``scale``
    (the sensitivity, e.g. 1/2g or 1/|ΔT|): the larger of the record's batch-means u_A and the
    bias repeatability B_r, since two records are two power-ons or mountings and differ by B_r
    even when each is precise (interpretations.md, "Repeatability in every budget")."""
    if _u_single(bv, rep) > bv.uA:
        return rep.row(msg("{what}: bias repeatability", what=what), "B_r·c", rep.value * scale,
                       unit)
    if bv.correlated:
        return budget_row_a(msg("{what} ({n} long batch means: the short ones are correlated)",
                                what=what, n=bv.dof + 1),
                             "u_A·c", bv.uA * scale, unit, bv.dof)
    return budget_row_a(msg("{what} (batch means)", what=what), "u_A·c", bv.uA * scale, unit,
                        bv.dof)


class Bias(JJFItem):
    """JJF 2014—2022 7.2.13 零偏: B_0 = F̄/K, eqs. (27), (28); budget B.2 (plus the type A
    scatter of F̄).  No earth-rate term unless option earth_rate = on."""

    item = "7.2.13"
    title = "Bias (零偏)"
    clause = "7.2.13"
    metrics = (Metric("B0", "bias", "B₀", "deg/h", "7.2.13.2", "28"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static", STATIC_STEP_DESC,
                                                          {"orientation": ""},
                                                          {"output": ("mV",)},
                                                          min_duration=Q_(1, "h")),)
    options = RATE_OPTS + (EARTH_OPT, Option("batches", 20, None,
                                             "batch means for the type A uncertainty", minimum=2))

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step("static", "static", STATIC_STEP_DESC + ", 1 h at 0.1 s", Q_(1, "h"), Q_(0.1, "s"),
                 {"orientation": "IRA up"})]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        kv = scale_factor_for(campaign, type(self))
        K, uK, src = kv
        seg = static_segment(campaign, type(self), w)
        bv = BiasValue(seg, K, _earth_term(campaign, seg, opts["earth_rate"]),
                       num_option(opts, "batches", 2, integer=True))
        rep = bias_repeatability(campaign, K)
        dur = bv.x.size * bv.dt
        if dur < 3600 * 0.999:
            w.append(msg("the record lasts {minutes:.3g} min; 7.2.13.1 c) asks for more than 1 h",
                         minutes=dur / 60))
        rep_row = rep.row("bias repeatability (another power-on gives another B₀)", "B_r",
                          rep.value,
                          "deg/h") if rep is not None and rep.value > bv.uA else None
        b = B.bias_budget(Q_(bv.B0, "deg/h"), uK, dmm=calibration_of(campaign, "dmm"),
                          u_A=Q_(bv.uA, "deg/h"), dof_A=bv.dof,
                          warnings=w, dof_K=kv.dof, rep_row=rep_row,
                          note_A=msg("{n} long batch means: the short ones are correlated (F test, "
                                     "95 %), their scatter understates the mean's u", n=bv.dof + 1)
                          if bv.correlated else "",
                          extra=[*rounding_row_mean(campaign, bv.x, "the mean output F̄ (eq. (27))",
                                                    3600.0 / abs(K), "deg/h"),
                                 *(kv.power_on_rows(bv.B0, 1.0, "deg/h",
                                                    msg("the static record (7.2.13.1)"))
                                   if rep is None else [])])
        if rep is None:
            b = attrs.evolve(b,
                             note=join("; ", [x for x in (b.note, _power_on_note(None, kv)) if x]))
        on = flag_option(opts, "earth_rate")
        return self._outcome([Result(self.metrics[0], Q_(bv.B0, "deg/h"), b.combined, b,
                                     note=join("; ",
                                               [msg("K from {source}", source=src),
                                                _earth_text(campaign, on)]),
                                     earth_rate="removed" if on else "included")],
                             warnings=w, segments=[seg.id], opts=opts)


class StaticRecordItem(JJFItem):
    """The items read from the 7.2.13.1 static record as 7.2.13 measures it (7.2.14, 7.2.20)."""

    requires = Bias.requires

    def sequence(self, options):
        return Bias().sequence(options)

    def static_start(self, campaign, ctx) -> tuple[dict, list[str], KValue, Segment]:
        """The item's options, its warnings so far, K (:func:`scale_factor_for`: 7.2.1 or the
        device's) and the static record (:func:`static_segment`)."""
        opts = self.option_values(ctx.options)
        w: list[str] = []
        kv = scale_factor_for(campaign, type(self))
        seg = static_segment(campaign, type(self), w)
        return opts, w, kv, seg


class BiasStability(StaticRecordItem):
    """JJF 2014—2022 7.2.14 零偏稳定性: B_s = (1/K)·s(F̄_i over P), eq. (29)."""

    item = "7.2.14"
    title = "Bias stability (零偏稳定性)"
    clause = "7.2.14"
    metrics = (Metric("Bs", "bias stability", "B_s", "deg/h", "7.2.14.2", "29"),)
    options = RATE_OPTS + (Option("P", "10 s", "s", "averaging period P"),)

    def evaluate(self, campaign, ctx):
        opts, w, kv, seg = self.static_start(campaign, ctx)
        K = kv.K
        x, dt = read_output(seg)
        p = float(opts["P"].to("s").magnitude) / dt
        if abs(p - round(p)) > 1e-6 or round(p) < 1:
            raise ProcedureError(f"7.2.14: P = {opts['P']} is not a whole number of sampling "
                                 f"intervals ({dt:g} s)")
        try:
            bs, m = F.bias_stability_eq29(x, K, int(round(p)))
        except ValueError as exc:
            raise DataError(seg.file or seg.id, "output", str(exc)) from exc
        bs *= 3600.0
        P_ = int(round(p))
        u, dof, cnote = B.std_of_std_correlated(bs, x[: m * P_].reshape(m, P_).mean(axis=1),
                                                x[: m * P_], P_, dt)
        rows = [budget_row_a(msg("sampling of a standard deviation of N/P averages (χ² bound)"),
                             "(s_{upper} − B_s)/2", u,
                              "deg/h", dof, note=cnote),
                kv.row(bs, "deg/h")]
        rows += B.relative_calibration_row("data acquisition, DMM", "u_rel",
                                           calibration_of(campaign, "dmm"), Q_(bs, "deg/h"))
        b = B.type_a_budget("Bs", "deg/h", rows)
        return self._outcome([Result(self.metrics[0], Q_(bs, "deg/h"), b.combined, b,
                                     note=msg("{m} averages of P", m=m))],
                             warnings=w, segments=[seg.id], opts=opts)


class BiasRepeatability(JJFItem):
    """JJF 2014—2022 7.2.15 零偏重复性: Q biases by 7.2.13 (power off between), B_r eq. (30)."""

    item = "7.2.15"
    title = "Bias repeatability (零偏重复性)"
    clause = "7.2.15"
    metrics = (Metric("Br", "bias repeatability", "B_r", "deg/h", "7.2.15.2", "30"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-repeat",
                                                          "7.2.13 repeated Q times", {"run": ""},
                                                          {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("runs", 6, None, "Q"),)

    def sequence(self, options):
        steps = ScaleFactor().sequence(options)
        runs = num_option(options, "runs", 2, integer=True)
        return steps + [
            Step(f"static-repeat#{q}", "static-repeat", STATIC_STEP_DESC + f", run {q}, 1 h at 1 s",
                 Q_(1, "h"), Q_(1, "s"), {"run": str(q), "orientation": "IRA up"})
            for q in range(1, runs + 1)]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
        runs = group_by(need_segments(campaign, type(self), "static-repeat"), "run")
        if len(runs) < 2:
            raise DataError(campaign.source, "segments",
                            f"7.2.15 needs Q ≥ 2 runs, got {len(runs)}")
        for r, g in runs.items():
            if len(g) > 1:
                raise DataError(where_of(g[1]), f"segments.{g[1].id}.conditions.run",
                                f"7.2.15: run {r!r} has {len(g)} records; give one per run")
        bvs = [BiasValue(g[0], K) for _, g in sorted(runs.items())]
        br = F.std_bessel([b.B0 for b in bvs], "eq. (30)")
        u, dof = B.std_of_std(br, len(bvs))
        # the rounding of each B_0i moves their standard deviation by at most the largest
        # half-width; when that reaches B_r itself, the spread may be rounding alone
        # (interpretations.md, output quantization)
        qrows = max((_rounded(campaign, x, msg("each B_0i (the standard deviation moves by at most "
                                               "its half-width)"), 1.0, "deg/h") for x in bvs),
                    key=lambda r: r[0].value.magnitude if r else -1.0)
        b = B.type_a_budget("Br", "deg/h", [
            budget_row_a(msg("sampling of a standard deviation of Q values (χ² bound)"),
                         "(s_{upper} − B_r)/2", u, "deg/h", dof),
            kv.row(br, "deg/h"), *qrows])
        why = ""
        if qrows and qrows[0].value.to("deg/h").magnitude >= br:
            why = msg("the rounding of the output moves each B_0i by up to ±{hw:.3g} °/h, no less "
                      "than their spread B_r = {br:.3g} °/h: the spread may be rounding alone "
                      "(digitise more finely)",
                      hw=qrows[0].value.to("deg/h").magnitude, br=br)
        elif not qrows and all(float(np.ptp(x.x)) == 0.0 for x in bvs):
            # every record one value: a step coarser than the noise, which no record shows (no
            # rounding row), and B_r with U = 0 from identical means (analog-coarser: B_r = 0 ± 0
            # against 2.8 °/h)
            why = msg("every run's record is one constant value: the output's step is coarser than "
                      "its noise and the data do not show it, so B_r = {br:.3g} °/h may be "
                      "rounding alone (state the output's resolution, or digitise more "
                      "finely){hint}", br=br, hint=hint(" (device.output_resolution)"))
        tab = TableSpec("bias_runs", msg("B_0i per run"), [msg("run"), "B_0i (°/h)", "u_A (°/h)"],
                        [[k, f"{x.B0:.5g}", f"{x.uA:.2g}"] for k, x in zip(sorted(runs), bvs)])
        return self._outcome([Result(self.metrics[0], Q_(br, "deg/h"), b.combined, b,
                                     reportable=not why,
                                     reason=why)], tables=[tab], segments=[x.seg.id for x in bvs],
                             opts=opts)


def _k_ratio_at(campaign: Campaign, temps: list[float],
                m: int) -> tuple[list[tuple[float, float, float]] | None, str]:
    """K_i/K_m at each chamber point of 7.2.16 from the 7.2.5 calibrations (kind
    "rate-temperature") of this campaign: [(ratio, its relative u from the two fits, ν)], or None
    and the budget's note when they are not there for every point (the B_0i are then over the
    room-temperature K, and the error |B_0i|·|K_i/K_m − 1| is not in the budget)."""
    segs = campaign.find_segments("rate-temperature")
    missing = msg("K at each chamber point is the room-temperature K of 7.2.1: B₀ at T_i errs by "
                  "|B₀ᵢ|·|K_i/K_m − 1|, not in this budget (give the 7.2.5 calibrations at the "
                  "same points)")
    if not segs:
        return None, missing
    groups = group_by(segs, "temperature")
    T5 = chamber_temperatures(groups, "7.2.5")
    fits = {}
    for key, t in T5.items():
        fits[round(t, 3)] = SFSet(groups[key])
    if any(round(t, 3) not in fits for t in temps):
        return None, missing
    fm = fits[round(temps[m], 3)]
    out = []
    for t in temps:
        fi = fits[round(t, 3)]
        if fi is fm:
            out.append((1.0, 0.0, INF))
            continue
        u = math.hypot(fi.fit.u_K / fi.K, fm.fit.u_K / fm.K)
        out.append((fi.K / fm.K, u, float(min(fi.fit.dof, fm.fit.dof))))
    return out, ""


class BiasTemperature(JJFItem):
    """JJF 2014—2022 7.2.16 零偏温度灵敏度: B_0i per temperature by 7.2.13, B_t eq. (31)."""

    item = "7.2.16"
    title = "Bias temperature sensitivity (零偏温度灵敏度)"
    clause = "7.2.16"
    metrics = (Metric("Bt", "bias temperature sensitivity", "B_t", "deg/h/delta_degC", "7.2.16.2",
                      "31"),)
    equipment = JJFItem.equipment + (EquipmentRequirement("chamber", "temperature chamber (table 2 "
                                                                     "no. 2); its calibration U "
                                                                     "(in K) enters the budget"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-temperature",
                                                          "7.2.13 at each chamber temperature",
                                                          {"temperature": "degC"},
                                                          {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("temperatures", "-40, -10, 20, 40, 60", None,
                                  "chamber points (°C)"),
                           Option("room_temperature", "20 °C", "degC", "T_m"))

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"static-temperature@{T:g}C", "static-temperature",
                 STATIC_STEP_DESC + f" at {T:g} °C, 1 h at 1 s",
                 Q_(1, "h"), Q_(1, "s"),
                 {"temperature": quantity_text(T, "degC"), "orientation": "IRA up"})
            for T in parse_floats(options["temperatures"], "temperatures")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
        groups = group_by(need_segments(campaign, type(self), "static-temperature"), "temperature")
        T = chamber_temperatures(groups, "7.2.16")
        keys = sorted(groups, key=T.get)
        if len(keys) < 2:
            raise DataError(campaign.source, "segments", "7.2.16 needs at least 2 temperatures")
        temps = [T[k] for k in keys]
        for k in keys:
            if len(groups[k]) > 1:
                raise DataError(where_of(groups[k][1]),
                                f"segments.{groups[k][1].id}.conditions.temperature",
                                f"7.2.16: {len(groups[k])} records at {k}; give one per "
                                "temperature")
        m = room_index(temps, float(opts["room_temperature"].to("degC").magnitude), "7.2.16")
        # each B_0i is an equivalent input rate at T_i: F̄_i over the K the device has at T_i,
        # K·K_i/K_m with the 7.2.5 calibrations of this campaign at the same chamber points
        # (interpretations.md, "7.2.16 — the bias at T_i is over the K at T_i")
        kt_ratio, kt_note = _k_ratio_at(campaign, temps, m)
        bvs = [BiasValue(groups[k][0], K * (kt_ratio[j][0] if kt_ratio else 1.0)) for j,
               k in enumerate(keys)]
        bt, i = F.bias_temperature_eq31([b.B0 for b in bvs], temps, m)
        dT = abs(temps[i] - temps[m])
        # one power-on through the chamber (7.2.16.1 c)): without a B_r the points carry their own
        # u, not their scatter about a line in T, which holds B(T)'s curvature (interpretations.md,
        # "7.2.5 / 7.2.16 — a curved K(T) is not noise")
        base = bias_repeatability(campaign, K)
        deg = 2 if len(bvs) >= 5 else 1
        rep = base if base is None else with_scatter(base,
                                                     *curve_scatter([b.B0 for b in bvs], temps,
                                                                    deg),
                                                     msg("the B_0i about a straight line in T")
                                                     if deg == 1 else
                                                     msg("the B_0i about a quadratic in T"))
        # the largest of N − 1 noisy slopes: its selection bias removed (interpretations.md, "JJF
        # 2014 — the largest of noisy slopes and changes"); drawn with B_r, or the points' scatter
        # about a line in T where it is smaller
        sel = max_slope_selection([b.B0 for b in bvs], [_u_single(b, rep, kv) for b in bvs], temps,
                                  m, relative=False,
                                  observed=True, cap_degree=2)
        bt = max(sel.value, 0.0)
        rows = [_single(bvs[i], rep, f"B₀ at {temps[i]:g} °C", 1 / dT, "deg/h/delta_degC"),
                _single(bvs[m], rep, f"B₀ at {temps[m]:g} °C", 1 / dT, "deg/h/delta_degC"),
                *_power_on(bvs[i], rep, kv, f"B₀ at {temps[i]:g} °C", 1 / dT, "deg/h/delta_degC"),
                *_power_on(bvs[m], rep, kv, f"B₀ at {temps[m]:g} °C", 1 / dT, "deg/h/delta_degC")]
        u_point = math.hypot(*(float(r.contribution.magnitude) for r in rows))
        rows += spread_rows(sel, u_point, "deg/h/delta_degC")
        rows += selection_rows(sel, len(bvs) - 1, "deg/h/delta_degC", point_unit="°/h")
        rows += [*_rounded(campaign, bvs[i], f"B₀ at {temps[i]:g} °C", 1 / abs(dT),
                           "deg/h/delta_degC"),
                *_rounded(campaign, bvs[m], f"B₀ at {temps[m]:g} °C", 1 / abs(dT),
                          "deg/h/delta_degC"),
                kv.row(bt, "deg/h/delta_degC")]
        if kt_ratio and kt_ratio[i][1] > 0:
            rows.append(budget_row_a(msg("K_i/K_m at {T:g} °C (7.2.5 fits) that B₀ at T_i is "
                                         "divided by",
                                          T=temps[i]), "|B₀ᵢ|·u(K_i/K_m)/|ΔT|",
                                      abs(bvs[i].B0) * kt_ratio[i][1] / dT, "deg/h/delta_degC",
                                     kt_ratio[i][2]))
        rows += chamber_rows(campaign, bt / dT * math.sqrt(2), "deg/h/delta_degC")
        b = B.type_a_budget("Bt", "deg/h/delta_degC", one_estimate(rows, rep),
                            note=join("; ", [x for x in (_power_on_note(rep, kv), kt_note) if x]))
        tab = TableSpec("bias_temperature", msg("B_0i per temperature"), ["T_i (°C)", "B_0i (°/h)"],
                        [[f"{t:g}", f"{x.B0:.5g}"] for t, x in zip(temps, bvs)])
        note = msg("maximum at {T:g} °C", T=temps[i])
        if sel.bias:
            note = join("; ", [note, selection_note(sel, 1.0, "(°/h)/°C")])
        return self._outcome([Result(self.metrics[0], Q_(bt, "deg/h/delta_degC"), b.combined, b,
                                     note=note)], tables=[tab],
                             segments=[x.seg.id for x in bvs], opts=opts)


class BiasAcceleration(JJFItem):
    """JJF 2014—2022 7.2.17 零偏加速度灵敏度: per axis (B_up − B_down)/2 g, maximum |·| over
    X, Y, Z (7.2.17.2).  Earth rate: option earth_rate = on corrects the pair whose axis is the
    IRA (device.ira_axis, default Z) for ±15.041·sin φ."""

    item = "7.2.17"
    title = "Bias acceleration sensitivity (零偏加速度灵敏度)"
    clause = "7.2.17"
    metrics = (Metric("Bg", "bias acceleration sensitivity", "B_g", "deg/h/gn", "7.2.17.2",
                      "prose, no eq. number"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-accel",
                                                          "X, Y, Z each up and down on the "
                                                          "position table",
                                                          {"axis": "", "orientation": ""},
                                                          {"output": ("mV",)}),)
    options = RATE_OPTS + (EARTH_OPT,)
    equipment = JJFItem.equipment + (EquipmentRequirement("position_table",
                                                          "two-axis position table"),)

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"static-accel[{a}-{o}]", "static-accel",
                 f"{a} axis {o} on the position table, 30 min at 1 s",
                 Q_(30, "min"), Q_(1, "s"), {"axis": a, "orientation": o}) for a in AXES
                                                  for o in ("up", "down")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
        ira = str(campaign.device.properties.get("ira_axis", "Z")).upper()
        vals: dict[str, dict[str, BiasValue]] = {}
        for s in need_segments(campaign, type(self), "static-accel"):
            a, o = axis_of(s), up_or_down(s)
            earth = _earth_term(campaign, s, opts["earth_rate"], o) if a == ira else 0.0
            if o in vals.get(a, {}):
                raise DataError(where_of(s), f"segments.{s.id}.conditions",
                                f"7.2.17: two records for axis {a} {o}; give one")
            vals.setdefault(a, {})[o] = BiasValue(s, K, earth)
        per = {a: F.per_g_726(v["up"].B0, v["down"].B0) for a,
               v in vals.items() if {"up", "down"} <= set(v)}
        if not per:
            raise DataError(campaign.source, "segments",
                            "7.2.17 needs at least one axis both up and down")
        worst = max(per, key=lambda a: abs(per[a]))
        bg = abs(per[worst])
        v = vals[worst]
        rep = bias_repeatability(campaign, K)
        rows = [_single(v["up"], rep, msg("B₀ {axis} up", axis=worst), 0.5, "deg/h/gn"),
                _single(v["down"], rep, msg("B₀ {axis} down", axis=worst), 0.5, "deg/h/gn"),
                *_power_on(v["up"], rep, kv, msg("B₀ {axis} up", axis=worst), 0.5, "deg/h/gn"),
                *_power_on(v["down"], rep, kv, msg("B₀ {axis} down", axis=worst), 0.5, "deg/h/gn"),
                *_rounded(campaign, v["up"], msg("B₀ {axis} up", axis=worst), 0.5, "deg/h/gn"),
                *_rounded(campaign, v["down"], msg("B₀ {axis} down", axis=worst), 0.5, "deg/h/gn"),
                kv.row(bg, "deg/h/gn")]
        b = B.type_a_budget("Bg", "deg/h/gn", one_estimate(rows, rep), note=_power_on_note(rep, kv))
        w = [] if len(per) == 3 else [msg("only axes {axes} tested", axes=", ".join(per))]
        tab = TableSpec("bias_accel", msg("Per axis"),
                        [msg("axis"), "B up (°/h)", "B down (°/h)", "(up−down)/2g (°/h/g)"],
                        [[a, f"{vals[a]['up'].B0:.5g}", f"{vals[a]['down'].B0:.5g}",
                          f"{per[a]:.4g}"] for a in per])
        on = flag_option(opts, "earth_rate")
        if worst == ira:
            er, etxt = ("removed" if on else "included"), _earth_text(campaign, on, per_g=True)
        else:
            er, etxt = "not applicable", msg("input axis horizontal, east–west: no earth-rate "
                                             "component")
        return self._outcome([Result(self.metrics[0], Q_(bg, "deg/h/gn"), b.combined, b,
                                     note=join("; ",
                                               [msg("largest on axis {axis}", axis=worst), etxt]),
                                     earth_rate=er)], tables=[tab], warnings=w,
                             segments=[x.seg.id for d in vals.values() for x in d.values()],
                             opts=opts)


class _BiasChange(JJFItem):
    """7.2.18 and 7.2.19: the bias before and after a ``what`` on each axis (segments ``kind``,
    ``static-<what>``), after the scale factor's segments; a subclass names ``what`` as a class
    keyword."""

    kind = ""
    what = ""
    options = RATE_OPTS

    def __init_subclass__(cls, what: str = "", **kw: Any) -> None:
        super().__init_subclass__(**kw)
        if not what:  # a subclass of a complete item keeps its segments
            return
        cls.what, cls.kind = what, f"static-{what}"
        cls.requires = ScaleFactor.requires + (SegmentRequirement(
            cls.kind, f"bias before/after {what} per axis", {"axis": "", "phase": ""},
            {"output": ("mV",)}),)

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"{self.kind}[{a}-{p}]", self.kind,
                 f"7.2.13 bias {p} {self.what} on {a}, 30 min at 1 s",
                 Q_(30, "min"), Q_(1, "s"), {"axis": a, "phase": p, "orientation": "IRA up"})
            for a in AXES for p in ("before", "after")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
        vals: dict[tuple[str, str], BiasValue] = {}
        for s in need_segments(campaign, type(self), self.kind):
            key = (axis_of(s), phase_of(s))
            if key in vals:
                raise DataError(where_of(s), f"segments.{s.id}.conditions",
                                f"{self.item}: two records for axis {key[0]} {key[1]}; give one")
            vals[key] = BiasValue(s, K)
        before, after, printed, worst, per = before_after_change(
            {k: v.B0 for k, v in vals.items()}, self.item, campaign.source)
        v1, v2 = vals[(worst, "before")], vals[(worst, "after")]
        ax = list(per)
        rep = with_scatter(bias_repeatability(campaign, K),
                           statistics.stdev([before[a] for a in ax]) if len(ax) > 1
                           else 0.0, len(ax) - 1, msg("B₀ before the test over the axes"))
        # the largest of the axes' |ΔB|: its selection bias removed (interpretations.md, "JJF 2014
        # — the largest of noisy slopes and changes"), drawn with the scatter of the biases before
        # the test over the axes where it is smaller than B_r
        sel = max_abs_selection([after[a] - before[a] for a in ax],
                                [math.hypot(_u_single(vals[(a, "before")], rep, kv),
                                            _u_single(vals[(a, "after")], rep, kv))
                                 for a in ax],
                                same=[before[a] for a in ax])
        db = max(sel.value, 0.0)
        rows = [_single(v1, rep, msg("B₀ before ({axis})", axis=worst), 1.0, "deg/h"),
                _single(v2, rep, msg("B₀ after ({axis})", axis=worst), 1.0, "deg/h"),
                *_power_on(v1, rep, kv, msg("B₀ before ({axis})", axis=worst), 1.0, "deg/h"),
                *_power_on(v2, rep, kv, msg("B₀ after ({axis})", axis=worst), 1.0, "deg/h")]
        u_point = math.hypot(*(float(r.contribution.magnitude) for r in rows))
        rows += spread_rows(sel, u_point, "deg/h") + selection_rows(sel, len(ax), "deg/h",
                                                                    slopes=False, point_unit="°/h")
        b = B.type_a_budget(self.metrics[0].key, "deg/h", one_estimate([
            *rows,
            *_rounded(campaign, v1, msg("B₀ before ({axis})", axis=worst), 1.0, "deg/h"),
            *_rounded(campaign, v2, msg("B₀ after ({axis})", axis=worst), 1.0, "deg/h"),
            kv.row(db, "deg/h")], rep), note=_power_on_note(rep, kv))
        w = [] if len(per) == 3 else [msg("only the axes {axes} were tested (the clause asks for "
                                          "3)", axes=", ".join(per))]
        tab = TableSpec("per_axis",
                        msg("B₀ before/after shock") if self.what == "shock"
                        else msg("B₀ before/after vibration"),
                        [msg("axis"), "B₁ (°/h)", "B₂ (°/h)", "|ΔB| (°/h)"],
                        [[a, f"{before[a]:.5g}", f"{after[a]:.5g}", f"{per[a]:.4g}"] for a in per])
        note = msg("largest on axis {axis}", axis=worst)
        if sel.bias:
            note = join("; ", [note, selection_note(sel, 1.0, "°/h")])
        return self._outcome([Result(self.metrics[0], Q_(db, "deg/h"), b.combined, b, note=note)],
                             tables=[tab], warnings=w, segments=[x.seg.id for x in vals.values()],
                             opts=opts)


class BiasShock(_BiasChange, what="shock"):
    """JJF 2014—2022 7.2.18 零偏冲击前后变化量: ΔB_i = |B_i2 − B_i1| eq. (32), max over 3 axes."""

    item = "7.2.18"
    title = "Bias change after shock (零偏冲击前后变化量)"
    clause = "7.2.18"
    metrics = (Metric("dB_shock", "bias change after shock", "ΔB_i", "deg/h", "7.2.18.2", "32"),)


class BiasVibration(_BiasChange, what="vibration"):
    """JJF 2014—2022 7.2.19 零偏振动前后变化量: ΔB_v = |B_v2 − B_v1| eq. (33), max over 3 axes."""

    item = "7.2.19"
    title = "Bias change after vibration (零偏振动前后变化量)"
    clause = "7.2.19"
    metrics = (Metric("dB_vib", "bias change after vibration", "ΔB_v", "deg/h", "7.2.19.2", "33"),)

"""Power-on repeatability carried into the single-power-on results (issue 13).

D.1.1 / D.2.1 give K and D.5.1 gives B₀ of *one* power-on.  Stated as the device's K or B₀, the
scatter between power-ons that D.1.4 / D.2.4 (K_r, eqs. D.11 / D.28) and D.5.3 (B_r, eq. D.42)
measure belongs in their budgets: no budget may be smaller than the spread the standard's own
repeatability item measures on the same campaign.  When the campaign holds those repeats, each
function here returns the row; when it does not, a note that says the row is absent and why (no
row is dropped silently).  interpretations.md, "D.1.1 / D.2.1 / D.5.1 — power-on repeatability".
"""

from __future__ import annotations

import math
from typing import Any, Callable

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, between_variance, curve_scatter, hint,
                       join, msg, parse_quantity)

from . import formulas as F
from . import formulas_rate as F2
from .common import ItemRef, grouped, repeat_runs
from .rate_data import collect_rate_data, fit_scale_factor
from .revolutions import collect_rate_points
from .static_bias import segment_bias

#: the repeatability items whose runs the rows here read (named in their messages)
D14, D24 = ItemRef("D.1.4"), ItemRef("D.2.4")

#: D.5.3 power-ons needed to bound σ_on: the posterior mean of a variance from Q values is finite
#: for Q ≥ 4
MIN_BIAS_RUNS = 4
#: D.1.4 / D.2.4 runs needed to bound K's turn-on scatter σ_K, for the same reason
MIN_TURN_ON_RUNS = 4


def stated_repeatability(campaign: Campaign, key: str) -> float | None:
    """``[device] bias_repeatability`` (°/h) or ``[device] scale_factor_repeatability`` (relative):
    1σ of one
    power-on's bias or K measured before (an earlier D.5.3 / D.1.4 / D.2.4 of the same gyro), for
    campaigns
    without repeats of their own; None when not given.  A bad value is a DataError naming the
    field."""
    v = campaign.device.properties.get(key)
    if v in (None, ""):
        return None
    unit, what = {"bias_repeatability": ("deg/h", "bias repeatability in °/h"),
                  "scale_factor_repeatability": ("", "relative repeatability of K")}[key]
    x = float(parse_quantity(v, dimension=unit, file=campaign.source,
                             field=f"device.{key}").to(unit).magnitude)
    if not (x >= 0 and math.isfinite(x)):
        raise DataError(campaign.source, f"device.{key}",
                        f"must be a non-negative {what}, got {v!r}")
    return x


def _stated_row(campaign: Campaign, key: str, symbol: str, u: float, unit: str) -> BudgetRow:
    return BudgetRow.type_b(msg("power-on repeatability of {symbol} stated for the device{hint} "
                                "(not measured on this "
                                "campaign)", symbol=symbol, hint=hint(f" (device.{key})")),
                            "σ_on" if symbol == "B₀" else "K_r·K",
                            Q_(u, unit), distribution="normal", k=1.0)


def turn_on_known(campaign: Campaign, what: str, method: str = "") -> bool:
    """Whether this campaign can state the turn-on scatter of ``what`` ("B₀" or "K"): the
    repeatability
    item's runs are in it (D.5.3's ``static-repeat``; D.1.4's ``revolutions-repeat`` or D.2.4's
    ``rate-output`` runs) or the device states it.  A difference of two power-ons without it is not
    reportable (interpretations.md, "GB/T 45570 — a difference of power-ons needs their turn-on
    scatter")."""
    key = "bias_repeatability" if what == "B₀" else "scale_factor_repeatability"
    return _runs_present(campaign, what, method) or stated_repeatability(campaign, key) is not None


def _runs_present(campaign: Campaign, what: str, method: str = "") -> bool:
    if what == "B₀":
        return len(campaign.find_segments("static-repeat")) >= MIN_BIAS_RUNS
    angle = len({str(s.conditions.get("run"))
                 for s in campaign.find_segments("revolutions-repeat")}) >= 2
    rate = (
        len(
            {
                str(s.conditions.get("run"))
                for s in campaign.find_segments("rate-output")
                if s.conditions.get("run") not in (None, "") and not s.conditions.get("temperature")
            }
        )
        >= 2
    )
    return {"angle": angle, "rate": rate}.get(method, angle or rate)


def missing_turn_on(what: str, item: str, why: str) -> str:
    """The reason a difference of two power-ons is not reportable without their turn-on scatter."""
    key = "bias_repeatability" if what == "B₀" else "scale_factor_repeatability"
    return msg("{why}: the turn-on scatter of {what} between them is not measured on this campaign "
               "and not stated — "
               "record {item}'s power-ons with it or give [device] {key} from an earlier {item}",
               why=why, what=what, item=item, key=key)


def _no_repeats(item: str, what: str):
    return msg("power-on repeatability not in U: the campaign has no {item} repeats, so U is that "
               "of this power-on (run {item} to state the device's {what})", item=item, what=what)


def _scale_factor_repeat_row(campaign: Campaign, K: float, unit: str, item: str, eq: str,
                             runs: list, k_of: Callable[[Any], float],
                             formula: Callable[[list[float]], float],
                             errors: tuple[type[Exception], ...]) -> tuple[list[BudgetRow], str]:
    """K_r of ``item`` (eq. ``eq``: ``formula`` over the K_j that ``k_of`` gives of each of the
    ``runs``) as a row u = K_r·K; with fewer than 2 runs the device's stated repeatability, or a
    note that there is none."""
    # a bad value is an error even when unused
    st = stated_repeatability(campaign, "scale_factor_repeatability")
    if len(runs) < 2:
        if st is not None:
            return [_stated_row(campaign, "scale_factor_repeatability", "K", abs(st * K), unit)], ""
        return [], _no_repeats(item, "K")
    try:
        Kj = [k_of(r) for r in runs]
    except errors as exc:  # the item itself reports what is wrong with its runs
        return [], msg("power-on repeatability not in U: the {item} runs could not be evaluated "
                       "({exc})", item=item, exc=str(exc))
    return [_row("K", f"{item}, eq. ({eq})", formula(Kj), K, len(Kj), unit)], ""


def scale_factor_angle_repeat_row(campaign: Campaign, K: float, unit: str) -> tuple[list[BudgetRow],
                                                                                    str]:
    """K_r of D.1.4 (``revolutions-repeat`` runs, eq. D.11) as a row u = K_r·K on K of D.1.1."""
    runs = sorted(grouped(campaign, "revolutions-repeat", "run").items())
    return _scale_factor_repeat_row(
        campaign, K, unit, "D.1.4", "D.11", runs,
        lambda run: collect_rate_points(D14, campaign, 1, run[1], f"in run {run[0]}")[0].K,
        F2.scale_factor_repeatability_d11, (DataError, IndexError))


def scale_factor_rate_repeat_row(campaign: Campaign, K: float, unit: str,
                                 min_points: int) -> tuple[list[BudgetRow], str]:
    """K_r of D.2.4 (``rate-output`` runs, eq. D.28) as a row u = K_r·K on K of D.2.1."""
    return _scale_factor_repeat_row(
        campaign, K, unit, "D.2.4", "D.28", repeat_runs(campaign),
        lambda r: fit_scale_factor(collect_rate_data(D24, campaign, min_points, (r, ""),
                                                     f"in run {r}")).K,
        F2.scale_factor_repeatability_d28, (DataError,))


def _row(symbol: str, where: str, Kr: float, K: float, q: int, unit: str) -> BudgetRow:
    return BudgetRow.type_a(msg("power-on repeatability of {symbol} ({where} on this campaign, K_r "
                                "= {Kr:.3g} ppm): "
                                "{symbol} of one power-on stated as the device's", symbol=symbol,
                                where=where,
                                Kr=Kr * 1e6), "K_r·K", Q_(abs(Kr * K), unit), q - 1,
                            note=msg("s of Q = {q} power-ons' K_j over their mean", q=q))


def bias_repeat_row(campaign: Campaign, batches: int,
                    own_uA: float | None) -> tuple[list[BudgetRow], str]:
    """The turn-on part of B_r of D.5.3 (``static-repeat`` runs, eq. D.42) as a row on B₀ of D.5.1:
    σ_on² = B_r² less the runs' within-run part (mean u_A², already B₀'s own type A), taken as the
    posterior mean of that variance component given the runs
    (:func:`metro.api.between_variance`,
    ν = ∞): never 0 where the runs do not resolve σ_on from their noise, only bound it
    (interpretations.md, "σ_on — a variance component the data only bound"); but never less than
    what keeps U ≥ B_r: u ≥ √(max(B_r²/4 − u_A(B₀)², 0)) (``own_uA`` = u_A(B₀); None: the turn-on
    part
    alone, as 6.2.8, D.5.4, D.5.5 and D.6.3 / D.6.4 take it through
    :func:`.repeatability.bias_turn_on`).
    Fewer than 4 runs cannot bound σ_on: no row, with a note."""
    segs = campaign.find_segments("static-repeat")
    # a bad value is an error even when unused
    st = stated_repeatability(campaign, "bias_repeatability")
    if len(segs) < MIN_BIAS_RUNS:
        if st is not None:
            return [_stated_row(campaign, "bias_repeatability", "B₀", st, "deg/h")], ""
        if len(segs) < 2:
            return [], _no_repeats("D.5.3", "B₀")
        return [], msg("power-on repeatability not in U: {q} D.5.3 power-ons cannot bound the "
                       "turn-on scatter "
                       "(at least {m}; D.5.3 records 7)", q=len(segs), m=MIN_BIAS_RUNS)
    try:
        ests = [segment_bias(s, campaign, batches) for s in segs]
    except DataError as exc:
        return [], msg("power-on repeatability not in U: the {item} runs could not be evaluated "
                       "({exc})", item="D.5.3", exc=str(exc))
    Br = F.bias_repeatability_d42([e.B0 for e in ests])
    w = float(np.mean([e.u_A**2 for e in ests]))
    q = len(ests)
    u = math.sqrt(between_variance(Br**2, w, q - 1))
    if own_uA is not None:
        u = max(u, math.sqrt(max(Br**2 / 4.0 - own_uA**2, 0.0)))
    moment = Br**2 - w
    return [BudgetRow.type_a(msg("power-on repeatability of B₀ (D.5.3, eq. (D.42) on this "
                                 "campaign, B_r = {Br:.3g} °/h, its within-run part removed): B₀ "
                                 "of one power-on stated as the device's", Br=Br), "σ_on",
                             Q_(u, "deg/h"), math.inf,
                             note=msg("Q = {q} power-ons; mean within-run u_A = {w:.3g} °/h; σ_on² "
                                      "is the posterior mean "
                                      "of the turn-on variance given them ({moment}), ν = ∞", q=q,
                                      w=math.sqrt(w),
                                      moment=msg("√(B_r² − u_A²) = {s:.3g} °/h",
                                                 s=math.sqrt(moment)) if moment > 0
                                      else msg("B_r² − u_A² ≤ 0: not resolved from the within-run "
                                               "noise, only bounded"))
                             )], ""


@attrs.frozen
class ScaleTurnOn:
    """K's turn-on scatter as D.1.5 / D.2.5 take it (:func:`scale_factor_turn_on`,
    :func:`pool_turn_on`)."""

    #: σ_K, relative: √ of the posterior mean of the turn-on variance (or the stated value)
    sigma: float
    nu: float  #: the row's degrees of freedom: ∞ (a posterior mean, or stated)
    #: measured on this campaign from ≥ 4 runs, or stated (device.scale_factor_repeatability)
    known: bool
    note: str  #: why it is not in U, or how the runs show it ("" when nothing to say)
    s2: float = 0.0  #: K_r² of the runs (relative)
    #: the part of K_r² each K_j's own noise explains, mean (u(K_j)/K_j)² (0: taken whole)
    within: float = 0.0
    #: the degrees of freedom the estimate rests on (Q − 1, + n − 3 when pooled; 0 stated or none)
    dof: float = 0.0


def turn_on_sigma(Kj, rel_u=None) -> tuple[float, float, float, int]:
    """σ_K of the Q scale factors K_j of D.1.4 / D.2.4's runs: (σ_K, K_r², own part, Q − 1).

    K_r of eqs. (D.11) / (D.28) (the same form); the own part w = mean (u(K_j)/K_j)² (``rel_u`` the
    K_j's
    relative u; None: K_r taken whole, w = 0); σ_K² = the posterior mean of the turn-on variance
    given
    the runs, :func:`metro.api.between_variance`(K_r², w, Q − 1) — Box & Tiao
    §5.2's one-way
    random-effect model with the reference prior, ν = ∞ (interpretations.md "σ_K — …").  Needs Q ≥
    4."""
    Kr = F2.scale_factor_repeatability_d11(Kj)
    w = 0.0 if rel_u is None else float(np.mean(np.square(np.asarray(rel_u, dtype=float))))
    q = len(Kj)
    return math.sqrt(between_variance(Kr * Kr, w, q - 1)), Kr * Kr, w, q - 1


def scale_factor_turn_on(campaign: Campaign, min_points: int, method: str = "rate") -> ScaleTurnOn:
    """The turn-on part of K's scatter between power-ons, relative, for results whose points are
    power-ons of their own (D.1.5.2 c) / D.2.5.2 c): off while the chamber changes temperature),
    from
    the campaign's repeatability runs — D.2.4 (``rate-output`` with ``run``, ``method="rate"``) or
    D.1.4
    (``revolutions-repeat``, K_j of eq. (D.2), ``method="angle"``).

    σ_K² = K_r² less the runs' own part, mean (u(K_j)/K_j)², is a variance component estimated as a
    difference; it enters as its posterior mean given the runs
    (:func:`metro.api.between_variance`, ν = ∞), never 0 where the runs only
    bound it, as σ_on of
    D.5.3 does (interpretations.md, "σ_on — a variance component the data only bound", "σ_K — …").
    D.1.4's K_j take K_r whole (own part 0: the revolutions' scatter overstates a K_j's noise where
    the
    counter's rounding dominates; interpretations.md "D.1.5 — every temperature point is a
    power-on"),
    so there it is (Q − 1)/(Q − 3)·K_r².  Fewer than 4 runs cannot bound σ_K (the posterior mean is
    infinite): not known, with a note.  Without runs, ``device.scale_factor_repeatability`` stands
    for
    σ_K (ν = ∞), as it does with too few runs."""
    st = stated_repeatability(campaign, "scale_factor_repeatability")
    item = "D.1.4" if method == "angle" else "D.2.4"
    if method == "angle":
        runs = sorted(grouped(campaign, "revolutions-repeat", "run").items())
    else:
        runs = repeat_runs(campaign)
    if len(runs) < MIN_TURN_ON_RUNS:
        if st is not None:
            return ScaleTurnOn(st, math.inf, True, "")
        if len(runs) < 2:
            return ScaleTurnOn(0.0, math.inf, False, msg(
                "turn-on scatter of K not in U: each temperature point is a power-on of its own, "
                "but the campaign has no {item} runs to measure it", item=item))
        return ScaleTurnOn(0.0, math.inf, False, msg(
            "turn-on scatter of K not in U: {q} {item} power-ons cannot bound it (at least {m}; "
            "{item} records 7)",
            q=len(runs), item=item, m=MIN_TURN_ON_RUNS))
    try:
        if method == "angle":
            pts = [collect_rate_points(D14, campaign, 1, segs, f"in run {r}")[0]
                   for r, segs in runs]
            # D.1.4: consecutive revolutions are read off one accumulating count, so their rounding
            # cancels in the sum and s/√m overstates a K_j's own noise; taken away, it would remove
            # turn-on scatter that is there: K_r whole (own part 0)
            sigma, s2, within, dof = turn_on_sigma([p.K for p in pts])
        else:
            fits = [fit_scale_factor(collect_rate_data(D24, campaign, min_points, (r, ""),
                                                       f"in run {r}")) for r in runs]
            sigma, s2, within, dof = turn_on_sigma([f.K for f in fits], [f.uK / f.K for f in fits])
    # D.1.4 / D.2.4 themselves report what is wrong with their runs
    except (DataError, IndexError) as exc:
        return ScaleTurnOn(0.0, math.inf, False,
                           msg("turn-on scatter of K not in U: the {item} runs could not be "
                                                     "evaluated ({exc})", item=item, exc=str(exc)))
    note = ""
    # K_r = 0 with the own part taken as 0: identical K_j of a counter coarser than the scatter
    if sigma == 0.0:
        note = msg("turn-on scatter of K not in U: the {q} scale factors of the {item} runs are "
                   "identical "
                   "(their resolution is coarser than the scatter, which they cannot measure)",
                   q=dof + 1, item=item)
    return ScaleTurnOn(sigma, math.inf, True, note, s2, within, dof)


def pool_turn_on(Ks, uKs, temps, on: ScaleTurnOn) -> tuple[ScaleTurnOn, str]:
    """K's turn-on scatter σ_K pooled with what the temperature points themselves show.

    Each temperature point is a power-on (D.1.5.2 c)) / D.2.5.2 c)), so the K_i's mean square about
    a
    smooth K(T) (a quadratic in T, :func:`metro.api.curve_scatter`, n − 3
    degrees of freedom,
    its own part mean (u(K_i)/K_i)²) is a second estimate of the same variance beside the runs'
    (K_r², Q − 1).
    Pooled — mean squares and own parts each weighted by their degrees of freedom — the posterior
    mean of the
    variance component (:func:`metro.api.between_variance`, Q − 1 + n − 3
    degrees of freedom) is
    taken where it is larger than the runs' alone; it never lowers σ_K below what the repeatability
    item
    measured (interpretations.md "D.2.5 — the line test with an estimated scatter").  Needs ≥ 5
    points and
    a σ_K from runs; otherwise ``on`` unchanged, with ""."""
    n = len(Ks)
    if not (on.known and on.dof > 0 and n >= 5):
        return on, ""
    K = np.asarray(Ks, dtype=float)
    s_T, d = curve_scatter(K / float(np.mean(K)), temps, 2)
    own = float(np.mean(np.square(np.asarray(uKs, dtype=float) / np.abs(K))))
    dof = on.dof + d
    s2 = (on.dof * on.s2 + d * s_T * s_T) / dof
    within = (on.dof * on.within + d * own) / dof
    pooled = math.sqrt(between_variance(s2, within, int(round(dof))))
    if pooled <= on.sigma:
        return on, ""
    return (attrs.evolve(on, sigma=pooled, s2=s2, within=within, dof=dof),
            msg("pooled with the temperature points' scatter about a quadratic in T ({s:.3g} ppm; "
                "their own noise "
                "{o:.3g} ppm; {d} degrees of freedom): σ_K {r:.3g} → {p:.3g} ppm", s=s_T * 1e6,
                o=math.sqrt(own) * 1e6,
                d=d, r=on.sigma * 1e6, p=pooled * 1e6))


def points_dof(u_points, u_on, dofs, nu_on: float) -> float:
    """The Welch–Satterthwaite degrees of freedom of the temperature points' u (each √(own² +
    turn-on²),
    the own part with its ν, the turn-on part with ν_on), over the points together: (mean u²)² /
    mean(own⁴/ν + on⁴/ν_on); ∞ without a turn-on part of finite ν.  The line test of D.12/D.29's
    selection Monte Carlo uses it (interpretations.md "D.2.5 — the line test with an estimated
    scatter")."""
    if not (math.isfinite(nu_on) and any(b > 0 for b in u_on)):
        return math.inf
    own = [math.sqrt(max(a * a - b * b, 0.0)) for a, b in zip(u_points, u_on)]
    num = float(np.mean(np.square(u_points))) ** 2
    den = float(np.mean([o**4 / max(d, 1) + b**4 / nu_on for o, b, d in zip(own, u_on, dofs)]))
    return num / den if den > 0 else math.inf


@attrs.frozen
class TurnOn:
    """The turn-on scatter of one power-on's bias as an item uses it (:func:`bias_turn_on`)."""

    sigma: float  #: σ_on, °/h (0 when not known)
    nu: float  #: its degrees of freedom
    known: bool  #: measured on this campaign (D.5.3) or stated (device.bias_repeatability)
    stated: bool  #: from device.bias_repeatability
    note: str  #: why it is not known ("" when known)

    def describe(self, u: float, unit: str) -> str:
        """The budget note on the row √2·σ_on/… of a difference of two power-ons."""
        if self.stated:
            return msg("each record a power-on of its own: with the turn-on scatter σ_on = {s:.4g} "
                       "°/h stated for the "
                       "device{hint}, {u:.3g} {unit} at the maximising point", s=self.sigma, u=u,
                       unit=unit,
                       hint=hint(" (device.bias_repeatability)"))
        return msg("each B_i a power-on of its own (D.5.4.2 c)): with the turn-on scatter σ_on = "
                   "{s:.4g} °/h of D.5.3 on this campaign (ν = {nu:.3g}), √2·σ_on/|ΔT| = {u:.3g} "
                   "(°/h)/°C at the maximising point",
                   s=self.sigma, nu=self.nu, u=u)

    def source(self) -> str:
        """The row's source text for D.5.5's √2·σ_on/(2H_b)."""
        if self.stated:
            return msg("turn-on scatter of B_0+ and B_0−, each a power-on of its own (\"by "
                       "D.5.1.2\"): σ_on = {s:.4g} °/h stated for the device{hint}", s=self.sigma,
                       hint=hint(" (device.bias_repeatability)"))
        return msg("turn-on scatter of B_0+ and B_0−, each a power-on of its own (\"by D.5.1.2\"): "
                   "σ_on = {s:.4g} °/h of D.5.3 on this campaign", s=self.sigma)


def bias_turn_on(campaign: Campaign, batches: int, missing: str) -> TurnOn:
    """The turn-on scatter σ_on of one power-on's bias, for items whose records are power-ons of
    their
    own (D.5.4, D.5.5, D.6.3 / D.6.4, the 6.2.8 changes).

    From D.5.3's repeats on this campaign (:func:`.repeatability.bias_repeat_row`, the one place it
    is
    computed): σ_on² = B_r² − mean u_A² is a variance component estimated as a difference, entered
    as its
    posterior mean given the runs, with ν = ∞ — never 0 where the runs only bound it
    (interpretations.md,
    "σ_on — a variance component the data only bound").  Else from ``device.bias_repeatability``
    (°/h, a B_r measured before, e.g. an earlier D.5.3; type B, ν = ∞; as a whole B_r it also holds
    its
    runs' within-run noise, so it errs on the safe side).  Else not known, with ``missing`` as the
    note
    (the items then declare their result not reportable: interpretations.md, "D.5.4 / D.5.5 —
    without
    the turn-on scatter")."""
    rep_rows, rep_note = bias_repeat_row(campaign, batches, None)
    if rep_rows:
        r = rep_rows[0]
        stated = r.type == "B"  # device.bias_repeatability: no repeats on this campaign
        return TurnOn(float(r.standard_uncertainty.to("deg/h").magnitude),
                      math.inf if stated else r.dof, True,
                      stated, "")
    if len(campaign.find_segments("static-repeat")) >= 2 and rep_note:
        missing = join("; ", [missing, rep_note])
    return TurnOn(0.0, math.inf, False, False, missing)

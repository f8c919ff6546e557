"""JJF 2003—2022: a gyro bias that drifts during the campaign (docs/interpretations.md, JJF 2003
"Gyro bias drift during the campaign").

Eq. (1) takes B_g constant over the sweeps of 7.2.1.1 and the twelve mountings of 7.2.2.1 a); the
standard asks only that the supply current be steady (7.2.1.1 b) "待电源电流稳定后").  A MEMS gyro
still warming up drifts by 0.1–0.3 °/s per hour; a sweep recorded in rate order turns that drift
into a slope (eq. (5) fits U = K·X + b to outputs that also grow with time), and the ±j differences
of the six-position solution (eq. (7)) into g terms.  The biases themselves (B_g, the mean of all
twelve records) and the accelerometer results are not differences of records and are not
touched.

* **Detection** (:func:`campaign_drift`): each record's own trend of each gyro output, fitted by
  least squares within the record (at rest: offset and slope; turning: offset, slope and the
  table-rate sinusoid of the horizontal earth rate; the gyro along a turning table axis is left
  out: the table's rate ripple is in it), pooled over the campaign's records by inverse variance,
  its standard error scaled up by the Birge ratio where the records disagree more than their
  noise says.
* **Correct** (``started`` on the segments, docs/data-format.md): the drift moves a result that
  combines records by Σ w_k·β̄_k, w_k the result's weights of the record means (eq. (5): the
  least-squares slope weights; eq. (7): ∂G/∂U of the pair means) and β̄_k the bias change over
  record k.  Each gyro's drift rate is fitted to the record trends at their mid-times as a line in
  time (:class:`RateModel`: a warm-up that settles slows down, which the line follows to first
  order), the result is corrected by −Σ w_k·β̄_k (GUM 3.2.3, 3.2.4: a recognised systematic
  effect is corrected) and carries the correction's uncertainty u_d = √(gᵀ·Cov·g); where the line
  does not fit the trends (χ² beyond its 99 % quantile) also the model's error u_dm, the trends'
  residuals from the line integrated over time and carried through the same weights.  A gyro with
  fewer than three timed records keeps the uncorrected row u = √(d̂² + u(d̂)²)·|τ| (GUM F.2.4.5).
* **Without times** the records' lever arm is not known; the least it can be is the plan's order
  with the records back to back (:func:`plan_sweep_factor`, :func:`plan_six_factors`: gaps between
  records only lengthen it).  Each result carries the drift its records' trends cannot exclude,
  u_b = (|d̂| + 2u(d̂))·|τ_plan| (:func:`bound_row`); where the drift is significant (|d̂|/u(d̂) ≥
  :data:`Z_CRIT`), seen but not placed in time, and moves the result by :data:`MATERIAL` of its U
  or more over that least lever arm, the result is not reportable, with the reason
  (:func:`not_reportable_reason`).
"""

from __future__ import annotations

import math
import weakref
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import Q_, BudgetRow, Campaign, DataError, Segment, fit_linear, join, msg

from . import formulas as F
from .data import axis_of, columns_of, rate_of

AXES = ("x", "y", "z")
#: without recording times, a significant drift withholds a result it moves by this share of U or
#: more with the records back to back in the plan's order — the least lever arm they can have had;
#: below it, gaps would have to lengthen that lever arm tenfold to move the result by U (the drift
#: is in u_b too)
MATERIAL = 0.1
GYRO = ("gx", "gy", "gz")
#: the pooled drift of one gyro is significant at |d̂|/u(d̂) ≥ Z_CRIT (two-sided 1.2 % per gyro for
#: a steady device; measured false rates in docs/standards/jjf2003.md)
Z_CRIT = 2.5
#: with recording times a result is corrected for the drift where its effect Δ on it is resolved:
#: |Δ|/u(Δ) beyond the two-sided quantile of Student's t with the drift model's ν at the false rate
#: Z_CORRECT standard errors have for a normal variable (1.24 %; :func:`correct_threshold`: 3.1 at ν
#: = 10, the twelve six-position records of 7.2.2 alone — 2.5 flat corrected 3 % of steady gyros
#: there by chance).  GUM 3.2.4's "significant"; an effect the data do not resolve is budgeted
#: uncorrected, √(Δ² + u²). Correcting always (Z_CORRECT = 0, measured with
#: benchmarks/jjf2003_drift_modes.py) is unbiased but puts the estimate's noise into every steady
#: device's K_g and g (rms E_n × 3–10)
Z_CORRECT = Z_CRIT


def correct_threshold(nu: float) -> float:
    """|Δ|/u(Δ) from which a drift's effect is corrected: the two-sided t quantile with ν degrees of
    freedom at the rate a normal variable exceeds :data:`Z_CORRECT` (Z_CORRECT itself at ν = ∞; 0
    when Z_CORRECT is 0)."""
    if Z_CORRECT <= 0:
        return 0.0
    from scipy.stats import norm, t

    return float(t.isf(norm.sf(Z_CORRECT), max(nu, 1)))
#: the line in time fits the record trends unless χ² exceeds its 99 % quantile (the drift model's
#: error then enters the budget, :func:`correction`)
P_FIT = 0.01
#: a turning record's trend is fitted with the table-rate sinusoid only over at least one revolution
MIN_TURNS = 1.0
#: kinds whose records the gyro items read
KINDS = ("position", "rate", "rate-repeat")


@attrs.frozen
class RateModel:
    """The drift rate of one gyro as a straight line in time, d(t) = a + c·(t − t_ref) (°/s per s),
    fitted by weighted least squares to the records' own trends at their mid-times (absolute
    weights, covariance scaled by the Birge ratio² where it exceeds 1): the bias then changes by
    β(t) = a·(t − t_ref) + c·(t − t_ref)²/2 — a warm-up that settles (exponentially, as a MEMS gyro
    does) slows down during the campaign, which c follows to first order."""

    a: float
    c: float
    cov: tuple[tuple[float, float], tuple[float, float]]
    dof: int
    t_ref: float
    birge: float
    #: the records' mid-times (sorted) and the integral of the trends' residuals from the line up to
    #: each (°/s): the bias change the line does not follow
    knots: tuple[float, ...] = ()
    left: tuple[float, ...] = ()
    #: χ² of the trends about the line (absolute weights) and its upper-tail probability
    chi2: float = 0.0
    p_fit: float = 1.0
    #: the rate changes in time (c fitted) or is constant (c = 0: the fitted c was below Z_CRIT
    #: standard errors); c_seen: the fitted c and its standard error either way
    line: bool = True
    c_seen: tuple[float, float] = (0.0, 0.0)
    records: int = 0

    @property
    def misfit(self) -> bool:
        """The line does not fit the trends: χ² beyond its (1 − :data:`P_FIT`) quantile."""
        return self.p_fit < P_FIT

    def leftover(self, t: float) -> float:
        """The bias change at time t that the line leaves out: the trapezoid integral of the
        record trends' residuals over the records' mid-times, linearly interpolated."""
        if len(self.knots) < 2:
            return 0.0
        return float(np.interp(t, self.knots, self.left))

    def basis(self, mid: float, duration: float, interval: float) -> np.ndarray:
        """[mean of (t − t_ref), mean of (t − t_ref)²/2] over a record's samples (mid-time ``mid``,
        ``duration`` = samples × ``interval``)."""
        x = mid - self.t_ref
        # variance of the sample times about mid
        spread = max(duration**2 - interval**2, 0.0) / 12.0
        return np.array([x, 0.5 * (x * x + spread)])

    def effect(self, grad: np.ndarray) -> tuple[float, float]:
        """The change Σ w_k·β̄_k of a result whose record weights w give ``grad`` = Σ w_k·basis_k,
        and its standard uncertainty √(gᵀ·Cov·g)."""
        g = np.asarray(grad, float)
        cov = np.asarray(self.cov, float)
        return float(g @ np.array([self.a, self.c])), math.sqrt(max(float(g @ cov @ g), 0.0))


@attrs.frozen
class GyroDrift:
    """The pooled within-record trend of each gyro (°/s per s): estimate, standard error, ν, the
    number of records, and each record's mid-time in s from the first record's start (None where
    the manifest gives no ``started``); with the times, each gyro's :class:`RateModel`."""

    d: tuple[float, float, float]
    u: tuple[float, float, float]
    dof: tuple[int, int, int]
    records: tuple[int, int, int]
    mid_times: Mapping[str, float] | None
    durations: Mapping[str, float]
    #: records with ``started`` when not all have it (their times are then not used)
    timed: int = 0
    #: each gyro's drift rate as a line in time (None without times or with fewer than three
    #: records)
    models: tuple[RateModel | None, RateModel | None, RateModel | None] = (None, None, None)
    intervals: Mapping[str, float] = attrs.field(factory=dict)

    def z(self, i: int) -> float:
        return abs(self.d[i]) / self.u[i] if self.u[i] > 0 else 0.0

    def significant(self, i: int) -> bool:
        return self.z(i) >= Z_CRIT

    def corrects(self, i: int) -> bool:
        """The results of gyro i are evaluated with its :class:`RateModel` (:func:`correction`:
        corrected where the drift's effect on them is resolved): recording times and ≥ 3 records."""
        return self.models[i] is not None

    def basis(self, i: int, sid: str) -> np.ndarray:
        """:meth:`RateModel.basis` of record ``sid`` for gyro i's model, and the bias change the
        model leaves out at its mid-time (:meth:`RateModel.leftover`)."""
        m, t = self.models[i], self.mid_times[sid]
        return np.append(m.basis(t, self.durations[sid], self.intervals[sid]), m.leftover(t))


def record_trend(y: np.ndarray, dt_s: float, rate_deg_s: float,
                 lsb: float | None) -> tuple[np.ndarray, np.ndarray]:
    """Least-squares trend (per s) of each column of ``y`` (n × k) within one record and its
    standard error: y = a + b·t (+ c·cos ωt + s·sin ωt for a turning table, ω = ``rate_deg_s``),
    t about the record's middle; the residual variance is floored at LSB²/12 (a record frozen
    on one code says nothing finer than its LSB)."""
    n = y.shape[0]
    t = (np.arange(n) - 0.5 * (n - 1)) * dt_s
    cols = [np.ones(n), t]
    if rate_deg_s != 0.0:
        th = math.radians(rate_deg_s) * t
        cols += [np.cos(th), np.sin(th)]
    H = np.column_stack(cols)
    coef, *_ = np.linalg.lstsq(H, y, rcond=None)
    res = y - H @ coef
    dof = max(n - H.shape[1], 1)
    s2 = np.sum(res**2, axis=0) / dof
    if lsb:
        s2 = np.maximum(s2, lsb**2 / 12.0)
    cov11 = float(np.linalg.inv(H.T @ H)[1, 1])
    return coef[1], np.sqrt(s2 * cov11)


def pooled(b: np.ndarray, se: np.ndarray) -> tuple[float, float, int]:
    """Inverse-variance mean of the record trends b with standard errors se (core.lsq's weighted
    fit of a constant, absolute weights); its standard error scaled by the Birge ratio √(χ²/(n −
    1)) where that exceeds 1; ν = n − 1."""
    ok = se > 0
    b, se = b[ok], se[ok]
    n = int(b.size)
    if n < 2:
        return 0.0, math.inf, 0
    fit = fit_linear(np.ones(n), b, weights=1.0 / se**2, scale_cov=False)
    return float(fit.coef[0]), math.sqrt(float(fit.cov[0, 0])) * max(1.0, fit.residual_sd), n - 1


def rate_model(b: np.ndarray, se: np.ndarray, mid: np.ndarray) -> RateModel | None:
    """The record trends b (standard errors se, at mid-times ``mid``) fitted by a drift rate that
    is a straight line in time (:class:`RateModel`; core.lsq's weighted fit, absolute weights, its
    covariance scaled by the Birge ratio² where that exceeds 1; t_ref the weighted mean time, so
    that a is the pooled trend of :func:`pooled`); where its change in time c is below
    :data:`Z_CRIT` standard errors the rate is taken constant (c = 0, the pooled trend: a slope
    that the data do not show would only add its noise to the correction).  None with fewer than
    three records."""
    from scipy.stats import chi2 as _chi2

    ok = se > 0
    b, se, mid = b[ok], se[ok], mid[ok]
    if b.size < 3 or np.ptp(mid) <= 0:
        return None
    w = 1.0 / se**2
    t_ref = float(np.sum(w * mid) / np.sum(w))
    fit = fit_linear(np.column_stack([np.ones(b.size), mid - t_ref]), b, weights=w, scale_cov=False)
    birge = max(1.0, float(fit.residual_sd))
    cov = np.asarray(fit.cov, float) * birge**2
    c_seen = (float(fit.coef[1]), math.sqrt(float(cov[1, 1])))
    line = abs(c_seen[0]) >= Z_CRIT * c_seen[1]
    if not line:
        fit = fit_linear(np.ones(b.size), b, weights=w, scale_cov=False)
        birge = max(1.0, float(fit.residual_sd))
        cov = np.array([[float(fit.cov[0, 0]) * birge**2, 0.0], [0.0, 0.0]])
    nu = int(b.size - (2 if line else 1))
    order = np.argsort(mid)
    tk, rk = mid[order], np.asarray(fit.residuals, float)[order]
    left = np.concatenate([[0.0], np.cumsum(0.5 * (rk[1:] + rk[:-1]) * np.diff(tk))])
    x2 = float(fit.residual_sd) ** 2 * nu
    return RateModel(a=float(fit.coef[0]), c=float(fit.coef[1]) if line else 0.0, chi2=x2,
                     p_fit=float(_chi2.sf(x2, nu)),
                     cov=((float(cov[0, 0]), float(cov[0, 1])),
                          (float(cov[1, 0]), float(cov[1, 1]))),
                     dof=nu, t_ref=t_ref, birge=birge, knots=tuple(float(x) for x in tk),
                     left=tuple(float(x) for x in left), line=line, c_seen=c_seen,
                     records=int(b.size))


_CACHE: "weakref.WeakKeyDictionary[Campaign, GyroDrift]" = weakref.WeakKeyDictionary()


def _lsb(campaign: Campaign) -> float | None:
    eq = campaign.equipment_for("acquisition")
    rng = campaign.device.properties.get("gyro_range")
    if eq is None or "bits" not in eq.properties or rng is None:
        return None
    try:
        fs = float(campaign.device.prop("gyro_range", "deg/s",
                                        source=campaign.source).to("deg/s").magnitude)
        return 2.0 * fs / 2 ** int(eq.properties["bits"])
    except (DataError, ValueError, TypeError):
        return None


def _segments(campaign: Campaign) -> list[Segment]:
    return [s for k in KINDS for s in campaign.find_segments(k)]


def _times(campaign: Campaign, segs: list[Segment], durations: Mapping[str, float],
           intervals: Mapping[str, float]) -> dict[str, float] | None:
    """Mid-times (s from the earliest start) of the records, or None unless every record has
    ``started``; two records of one MIMU that overlap in time are a data error."""
    if not segs or any(s.started is None for s in segs):
        return None
    t0 = min(s.started for s in segs)
    start = {s.id: (s.started - t0).total_seconds() for s in segs}
    order = sorted(segs, key=lambda s: start[s.id])
    for a, b in zip(order, order[1:]):
        end = start[a.id] + durations[a.id]
        if start[b.id] < end - intervals[a.id]:
            raise DataError(b.file or campaign.source, f"segments.{b.id}.started",
                            f"{b.started.isoformat()} is before the end of segment {a.id!r} "
                            f"(started {a.started.isoformat()}, {durations[a.id]:g} s long): the "
                            "records of one MIMU on one table cannot overlap",
                            hint="give each segment the time its first sample was taken")
    return {s.id: start[s.id] + 0.5 * (durations[s.id] - intervals[s.id]) for s in segs}


def campaign_drift(campaign: Campaign) -> GyroDrift:
    """The pooled drift of each gyro over the campaign's position, rate and rate-repeat records."""
    try:
        return _CACHE[campaign]
    except (KeyError, TypeError):
        pass
    segs = _segments(campaign)
    lsb = _lsb(campaign)
    per: list[tuple[list[float], list[float]]] = [([], []) for _ in AXES]
    ids: list[list[str]] = [[] for _ in AXES]
    durations, intervals = {}, {}
    for seg in segs:
        y = columns_of(seg, GYRO, "deg/s").T  # n × 3, °/s
        dt_s = float(seg.interval.to("s").magnitude)
        durations[seg.id], intervals[seg.id] = y.shape[0] * dt_s, dt_s
        rate, axis = 0.0, None
        if seg.kind != "position":
            rate, axis = rate_of(seg, campaign), AXES.index(axis_of(seg, campaign))
        if rate != 0.0 and abs(rate) * y.shape[0] * dt_s < 360.0 * MIN_TURNS:
            continue  # the table-rate sinusoid and a trend are not separable within one turn
        b, se = record_trend(y, dt_s, rate, lsb)
        for i in range(3):
            if rate != 0.0 and i == axis:
                continue  # the rate ripple of the table is in the gyro along its axis
            per[i][0].append(float(b[i]))
            per[i][1].append(float(se[i]))
            ids[i].append(seg.id)
    est = [pooled(np.array(b), np.array(s)) for b, s in per]
    times = _times(campaign, segs, durations, intervals)
    models = tuple(rate_model(np.array(b), np.array(s), np.array([times[k] for k in sid]))
                   if times is not None else None for (b, s), sid in zip(per, ids))
    out = GyroDrift(d=tuple(e[0] for e in est), u=tuple(e[1] for e in est),
                    dof=tuple(e[2] for e in est),
                    records=tuple(len(b) for b, _ in per), mid_times=times, durations=durations,
                    timed=0 if times is not None else sum(s.started is not None for s in segs),
                    models=models, intervals=intervals)
    try:
        _CACHE[campaign] = out
    except TypeError:
        pass
    return out


# ------------------------------------------------------------------------------ time structure


def sweep_factor(rates, times) -> float:
    """τ of eq. (5): a drift d·t of the outputs moves the fitted K by d·τ, τ the least-squares slope
    of the records' mid-times t on their rates X (s per °/s), 7.2.1.2 eq. (5) applied to t."""
    return float(F.scale_factor_eq5(np.asarray(rates, float), np.asarray(times, float)).coef[0])


def six_position_factors(pair_times, ratio: float) -> np.ndarray:
    """τ of eq. (7) for columns x, y, z of G (s per g_n): Σ_k t_k·∂G/∂U_k over the six pair-averaged
    positions (t_k the mean mid-time of the pair), per g_n of the local gravity (÷ g/g_n)."""
    S = F.six_position_sensitivities()
    return np.asarray(pair_times, float) @ S[:, :3] / ratio


def sweep_gradient(drift: GyroDrift, i: int, rates, sids) -> np.ndarray:
    """Σ w_k·basis_k of eq. (5)'s slope (w_k its least-squares weights of the record means) for gyro
    i's :class:`RateModel`: [τ, τ₂], τ as :func:`sweep_factor`, τ₂ the same slope of the records'
    mean (t − t_ref)²/2."""
    B = np.array([drift.basis(i, sid) for sid in sids])
    return np.array([sweep_factor(rates, B[:, k]) for k in range(B.shape[1])])


def six_gradient(drift: GyroDrift, i: int, pairs, j: int, ratio: float) -> np.ndarray:
    """Σ w_k·basis_k of column j of eq. (7) (per g_n of the local gravity, ÷ ``ratio``) for gyro i's
    :class:`RateModel`: each position's basis is the mean of its two mountings' (``pairs``: per
    position of F.SIX_POSITIONS the two segment ids)."""
    S = F.six_position_sensitivities()
    B = np.array([0.5 * (drift.basis(i, a) + drift.basis(i, b)) for a, b in pairs])
    return S[:, j] @ B / ratio


def plan_sweep_factor(rates, durations) -> float:
    """τ of a sweep whose records were taken back to back in rate order (``metro plan``'s order,
    the sweep from the lowest rate up): the least time structure a rate-ordered sweep has."""
    order = np.argsort(rates)
    d = np.asarray(durations, float)[order]
    mids = np.cumsum(d) - 0.5 * d
    return sweep_factor(np.asarray(rates, float)[order], mids)


def plan_six_factors(durations_by_position: Mapping[tuple[str, float], float],
                     ratio: float) -> np.ndarray:
    """τ of eq. (7) for the twelve mountings taken back to back in ``metro plan``'s order (each
    position at heading 0° then 180°, +x, −x, +y, −y, +z, −z)."""
    clock, pair_t = 0.0, []
    for up in F.SIX_POSITIONS:
        mids = []
        for h in (0.0, 180.0):
            d = durations_by_position[(up, h)]
            mids.append(clock + 0.5 * d)
            clock += d
        pair_t.append(0.5 * sum(mids))
    return six_position_factors(pair_t, ratio)


# ------------------------------------------------------------------------------ budget and verdict


def correction(drift: GyroDrift, i: int, grad: np.ndarray, unit: str, what, tau_unit: str,
               shown: str = "") -> tuple[float, list[BudgetRow]]:
    """The drift of gyro i over the records a result combines, Δ = a·τ + c·τ₂ (its
    :class:`RateModel`; ``grad`` = [τ, τ₂, e]: τ in ``tau_unit``, τ₂ in ``tau_unit``·s, e the bias
    change the line leaves out carried through the result, in ``unit``), to be subtracted from the
    result where it is resolved (|Δ| ≥ :func:`correct_threshold`(ν)·u(Δ); else 0),
    and its rows: u_d, the correction's uncertainty u(Δ) = √(gᵀ·Cov(a, c)·g) (type A, ν = records
    − 2; GUM 3.2.3, 3.2.4: a recognised significant systematic effect is corrected, the correction's
    uncertainty budgeted), or for an unresolved effect left in √(Δ² + u(Δ)²) (GUM F.2.4.5); u_dc
    for the unresolved change of a rate taken constant, √(ĉ² + u(ĉ)²)·|τ₂|; and where the model
    does not fit the trends (:attr:`RateModel.misfit`) u_dm = |e|."""
    m = drift.models[i]
    delta, u = m.effect(grad[:2])
    shape = (msg("as a line in time: {a:.3g} ± {ua:.2g} °/s per hour, changing by {c:.2g} ± "
                 "{uc:.2g} °/s per hour per hour", a=m.a * 3600.0,
                 ua=math.sqrt(m.cov[0][0]) * 3600.0, c=m.c * 3600.0**2,
                 uc=math.sqrt(m.cov[1][1]) * 3600.0**2) if m.line else
             msg("as a constant: {a:.3g} ± {ua:.2g} °/s per hour (a change in time of {c:.2g} ± "
                 "{uc:.2g} °/s per hour per hour, below {z:g} standard errors, is not fitted)",
                 a=m.a * 3600.0,
                 ua=math.sqrt(m.cov[0][0]) * 3600.0, c=m.c_seen[0] * 3600.0**2,
                 uc=m.c_seen[1] * 3600.0**2, z=Z_CRIT))
    z_cut = correct_threshold(m.dof)
    applied = abs(delta) >= z_cut * u
    if applied:
        rows = [BudgetRow.type_a(
            msg("correction for the gyro bias drift between the records ({what})", what=what),
                                 "u_d",
            Q_(u, unit), max(m.dof, 1),
            note=msg("gyro {gyro}'s drift rate fitted to the within-record trends of {n} records "
                     "{shape} (Birge ratio {birge:.2f}, χ² = {chi2:.1f}, ν = {nu}); τ = {tau:.4g} "
                     "{tau_unit}; the result is corrected by {delta:.3g}{unit}", gyro=AXES[i],
                     n=m.records, shape=shape, birge=m.birge, chi2=m.chi2,
                     nu=m.dof, tau=float(grad[0]), tau_unit=tau_unit, delta=-delta, unit=shown))]
    else:  # an effect the data do not resolve: left in, budgeted (GUM F.2.4.5)
        rows = [BudgetRow.type_a(
            msg("gyro bias drift between the records ({what})", what=what), "u_d",
            Q_(math.hypot(delta, u), unit), max(m.dof, 1),
            note=msg("gyro {gyro}'s drift rate fitted to the within-record trends of {n} records "
                     "{shape} (Birge ratio {birge:.2f}, χ² = {chi2:.1f}, ν = {nu}); τ = {tau:.4g} "
                     "{tau_unit}; its effect on this result, {delta:.3g} ± {ud:.2g}{unit}, is "
                     "below {z:g} standard errors: not corrected, √(Δ² + u²)", gyro=AXES[i],
                     n=m.records, shape=shape, birge=m.birge, chi2=m.chi2, nu=m.dof,
                     tau=float(grad[0]), tau_unit=tau_unit, delta=delta, ud=u, unit=shown,
                     z=round(z_cut, 2)))]
    # the change of the rate in time that the data do not resolve: budgeted, not corrected
    if not m.line:
        rows.append(BudgetRow.type_a(
            msg("change of the drift rate in time, not corrected ({what})", what=what), "u_dc",
            Q_(math.hypot(*m.c_seen) * abs(float(grad[1])), unit), max(m.records - 2, 1),
            note=msg("√(ĉ² + u(ĉ)²)·|τ₂|, ĉ the fitted change of gyro {gyro}'s drift rate in time, "
                     "τ₂ = {tau2:.4g} {tau_unit}·s (GUM F.2.4.5)", gyro=AXES[i],
                     tau2=float(grad[1]),
                     tau_unit=tau_unit)))
    if m.misfit:
        rows.append(BudgetRow.type_a(
            msg("drift model error: the bias change a line in time leaves out ({what})", what=what),
                                     "u_dm",
            Q_(abs(float(grad[2])), unit), max(m.dof, 1),
            note=msg("the trends do not lie on a line in time (χ² = {chi2:.1f}, ν = {nu}, p = "
                     "{p:.2g}): their residuals, integrated over the records' times and carried "
                     "through the result's formula",
                     chi2=m.chi2, nu=m.dof, p=m.p_fit)))
    return (delta if applied else 0.0), rows


def corrected_note(delta: float, unit: str):
    """The result note of a value corrected for the drift."""
    return msg("corrected for the gyro bias drift during the campaign by {delta:.3g}{unit} (from "
               "the recording times)", delta=-delta, unit=unit)


def drift_row(drift: GyroDrift, i: int, tau: float, unit: str, what, tau_unit: str) -> BudgetRow:
    """u = √(d̂² + u(d̂)²)·|τ| for gyro i's drift over the records a result combines (τ in
    ``tau_unit``: s per °/s for eq. (5), s per g_n for eq. (7)); the drift left uncorrected (a gyro
    with fewer than three timed records, where no :class:`RateModel` is fitted)."""
    d, u = drift.d[i], drift.u[i]
    return BudgetRow.type_a(
        msg("gyro bias drift between the records ({what})", what=what), "u_d",
        Q_(math.hypot(d, u) * abs(tau), unit), max(drift.dof[i], 1),
        note=msg("pooled within-record trend of gyro {gyro}: {d:.3g} ± {u:.2g} °/s per hour over "
                 "{n} records × τ = {tau:.4g} {tau_unit}; √(d̂² + u²)·|τ| (drift not corrected)",
                 gyro=AXES[i], d=d * 3600.0,
                 u=u * 3600.0, n=drift.records[i], tau=tau, tau_unit=tau_unit))


def drift_bound(drift: GyroDrift, i: int) -> float:
    """The largest drift rate of gyro i that its records' pooled trend cannot exclude, |d̂| + 2u(d̂)
    (°/s per s; two Birge-scaled standard errors)."""
    return abs(drift.d[i]) + 2.0 * drift.u[i]


def bound_row(drift: GyroDrift, i: int, tau_plan: float, unit: str, what,
              tau_unit: str) -> BudgetRow | None:
    """Without recording times: the drift of gyro i that its records' trends cannot exclude, carried
    through a result with the least lever arm its records can have had (τ_plan: back to back in the
    plan's order), u_b = (|d̂| + 2u(d̂))·|τ_plan| as a standard uncertainty (type B, ν of the
    trends) — not the bound ÷ √3: gaps between the records, which no manifest without times states,
    lengthen the lever arm (measured, docs/interpretations.md: ÷ √3 covered the harness's warm-up
    device's results 86.7–95.8 %, the bound itself 98.3–100 %).  None where fewer than two records
    give the gyro a trend (:func:`not_reportable_reason` then withholds the result)."""
    if not math.isfinite(drift.u[i]):
        return None
    return BudgetRow.type_b(
        msg("gyro bias drift the records cannot exclude, no recording times ({what})", what=what),
                            "u_b",
        Q_(drift_bound(drift, i) * abs(tau_plan), unit), distribution="normal", k=1.0,
                            dof=max(drift.dof[i], 1),
        note=msg("(|d̂| + 2u(d̂))·|τ|: gyro {gyro}'s pooled within-record trend {d:.3g} ± {u:.2g} "
                 "°/s per hour over {n} records, τ = {tau:.4g} {tau_unit} with the records back to "
                 "back in the plan's order (the least lever arm they can have had); give `started` "
                 "on the segments to evaluate the drift instead",
                 gyro=AXES[i], d=drift.d[i] * 3600.0, u=drift.u[i] * 3600.0, n=drift.records[i],
                 tau=tau_plan,
                 tau_unit=tau_unit))


def not_reportable_reason(drift: GyroDrift, i: int, tau_plan: float, U: float, unit: str):
    """The reason a result of gyro i cannot be reported without recording times, or None: the drift
    is significant (|d̂|/u(d̂) ≥ :data:`Z_CRIT`) — seen, but not placed in time — and moves the
    result by |d̂|·|τ_plan| ≥ :data:`MATERIAL`·U with the records back to back in the plan's order
    (``U`` without :func:`bound_row`'s row), the least it can do: gaps between the records, which no
    manifest without times states, make it more; or no record gives the gyro a within-record
    trend."""
    if not math.isfinite(drift.u[i]):
        return msg("fewer than two of the records give gyro {gyro} a within-record trend, so a "
                   "bias drift during the campaign can be neither seen nor bounded, and the "
                   "manifest gives no recording times (`started` on the segments). Give `started` "
                   "on every segment, or record each position and rate over at least one table "
                   "revolution", gyro=AXES[i])
    if not U > 0 or not drift.significant(i):
        return None
    effect = abs(drift.d[i] * tau_plan)
    if effect < MATERIAL * U:  # stays below U even with a lever arm 1/MATERIAL times the plan's
        return None
    # three parts ("; "): what the gyro does (shared by its results), what it does to this result,
    # and what to do (shared by all) — a certificate states a shared part once
    # (core.notes.group_notes)
    return join("; ", [
        msg("gyro {gyro}'s bias drifts by {d:.3g} °/s per hour during the campaign (pooled trend "
            "of its {n} records, {z:.1f} standard errors)", gyro=AXES[i], d=drift.d[i] * 3600.0,
            n=drift.records[i], z=drift.z(i)),
        msg("it moves this result by {effect:.2g}{unit} ({ratio:.2g} × its U without the drift) "
            "were the records taken back to back in the plan's order, by more with gaps between "
            "them", effect=effect, unit=unit,
            ratio=effect / U),
        msg("the manifest gives no recording times (`started` on the segments) to budget the "
            "drift: give `started` on every segment, or let the MIMU warm up until its bias is "
            "steady (7.2.1.1 b)) and recalibrate")])


def drift_warning(drift: GyroDrift) -> list[Any]:
    """A warning per gyro whose drift is significant (whatever the results do with it)."""
    out = []
    if drift.timed:
        out.append(msg("`started` is given on {n} of the {m} records only: the recording times are "
                       "not used, and a drift between the records is not budgeted", n=drift.timed,
                       m=len(drift.durations)))
    for i in range(3):
        if drift.significant(i):
            out.append(msg("gyro {gyro}'s bias drifts by {d:.3g} ± {u:.2g} °/s per hour during the "
                           "campaign (pooled within-record trend of {n} records): JJF 2003 takes "
                           "B_g as constant; the results that difference records {how}",
                           gyro=AXES[i], d=drift.d[i] * 3600.0, u=drift.u[i] * 3600.0,
                           n=drift.records[i],
                           how=(msg("are corrected for it where its effect on them is resolved, "
                                    "with the correction's uncertainty in the budget, and carry it "
                                    "as a budget row where not (recording times given)")
                                if drift.corrects(i)
                                else msg("carry it as a budget row (recording times given)")
                                if drift.mid_times is not None
                                else msg("are not reportable: its effect on them cannot be placed "
                                         "without recording times"))))
    return out

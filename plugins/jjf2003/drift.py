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
* **Cover** (``started`` on the segments, docs/data-format.md): the drift d moves a result
  that combines records recorded at times t by d·τ, τ = ∂(result)/∂(output) · t summed over the
  records — for eq. (5) τ is the least-squares slope of the records' mid-times on their rates
  (:func:`sweep_factor`), for eq. (7) Σ t_k·∂G/∂U_k (:func:`six_position_factors`).  The budget row
  is u = √(d̂² + u(d̂)²)·|τ| (GUM F.2.4.5: a known effect left uncorrected), the printed value
  stays the standard's.
* **Without times** the drift cannot be budgeted: where it is significant (|d̂|/u(d̂) ≥
  :data:`Z_CRIT`) and would move a result by :data:`MATERIAL` of its U or more were the records
  taken back to back in the plan's order (:func:`plan_sweep_factor`, :func:`plan_six_factors`),
  the result is not reportable, with the reason.
"""

from __future__ import annotations

import math
import weakref
from typing import Any, Mapping

import attrs
import numpy as np

from metro.core.budget import BudgetRow
from metro.core.errors import DataError
from metro.core.locale import msg
from metro.core.lsq import fit_linear
from metro.core.model import Campaign, Segment
from metro.core.units import Q_

from . import formulas as F
from .data import _axis_of, _columns, _rate_of

AXES = ("x", "y", "z")
GYRO = ("gx", "gy", "gz")
#: the pooled drift of one gyro is significant at |d̂|/u(d̂) ≥ Z_CRIT (two-sided 1.2 % per gyro for a
#: steady device; measured false rates in docs/standards/jjf2003.md)
Z_CRIT = 2.5
#: … and, without recording times, material where the plan's order would move a result by this
#: fraction of its U
MATERIAL = 0.5
#: a turning record's trend is fitted with the table-rate sinusoid only over at least one revolution
MIN_TURNS = 1.0
#: kinds whose records the gyro items read
KINDS = ("position", "rate", "rate-repeat")


@attrs.frozen
class GyroDrift:
    """The pooled within-record trend of each gyro (°/s per s): estimate, standard error, ν, the
    number of records, and each record's mid-time in s from the first record's start (None where
    the manifest gives no ``started``)."""

    d: tuple[float, float, float]
    u: tuple[float, float, float]
    dof: tuple[int, int, int]
    records: tuple[int, int, int]
    mid_times: Mapping[str, float] | None
    durations: Mapping[str, float]
    #: records with ``started`` when not all have it (their times are then not used)
    timed: int = 0

    def z(self, i: int) -> float:
        return abs(self.d[i]) / self.u[i] if self.u[i] > 0 else 0.0

    def significant(self, i: int) -> bool:
        return self.z(i) >= Z_CRIT


def record_trend(y: np.ndarray, dt_s: float, rate_deg_s: float, lsb: float | None) -> tuple[np.ndarray, np.ndarray]:
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
    """Inverse-variance mean of the record trends b with standard errors se (core.lsq's weighted fit of a
    constant, absolute weights); its standard error scaled by the Birge ratio √(χ²/(n − 1)) where that
    exceeds 1; ν = n − 1."""
    ok = se > 0
    b, se = b[ok], se[ok]
    n = int(b.size)
    if n < 2:
        return 0.0, math.inf, 0
    fit = fit_linear(np.ones(n), b, weights=1.0 / se**2, scale_cov=False)
    return float(fit.coef[0]), math.sqrt(float(fit.cov[0, 0])) * max(1.0, fit.residual_sd), n - 1


_CACHE: "weakref.WeakKeyDictionary[Campaign, GyroDrift]" = weakref.WeakKeyDictionary()


def _lsb(campaign: Campaign) -> float | None:
    eq = campaign.equipment_for("acquisition")
    rng = campaign.device.properties.get("gyro_range")
    if eq is None or "bits" not in eq.properties or rng is None:
        return None
    try:
        fs = float(campaign.device.prop("gyro_range", "deg/s", source=campaign.source).to("deg/s").magnitude)
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
                            f"{b.started.isoformat()} is before the end of segment {a.id!r} (started "
                            f"{a.started.isoformat()}, {durations[a.id]:g} s long): the records of one MIMU "
                            "on one table cannot overlap",
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
    durations, intervals = {}, {}
    for seg in segs:
        y = _columns(seg, GYRO, "deg/s").T  # n × 3, °/s
        dt_s = float(seg.interval.to("s").magnitude)
        durations[seg.id], intervals[seg.id] = y.shape[0] * dt_s, dt_s
        rate, axis = 0.0, None
        if seg.kind != "position":
            rate, axis = _rate_of(seg, campaign), AXES.index(_axis_of(seg, campaign))
        if rate != 0.0 and abs(rate) * y.shape[0] * dt_s < 360.0 * MIN_TURNS:
            continue  # the table-rate sinusoid and a trend are not separable within one turn
        b, se = record_trend(y, dt_s, rate, lsb)
        for i in range(3):
            if rate != 0.0 and i == axis:
                continue  # the rate ripple of the table is in the gyro along its axis
            per[i][0].append(float(b[i]))
            per[i][1].append(float(se[i]))
    est = [pooled(np.array(b), np.array(s)) for b, s in per]
    times = _times(campaign, segs, durations, intervals)
    out = GyroDrift(d=tuple(e[0] for e in est), u=tuple(e[1] for e in est), dof=tuple(e[2] for e in est),
                    records=tuple(len(b) for b, _ in per), mid_times=times, durations=durations,
                    timed=0 if times is not None else sum(s.started is not None for s in segs))
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


def plan_sweep_factor(rates, durations) -> float:
    """τ of a sweep whose records were taken back to back in rate order (``metro plan``'s order,
    the sweep from the lowest rate up): the least time structure a rate-ordered sweep has."""
    order = np.argsort(rates)
    d = np.asarray(durations, float)[order]
    mids = np.cumsum(d) - 0.5 * d
    return sweep_factor(np.asarray(rates, float)[order], mids)


def plan_six_factors(durations_by_position: Mapping[tuple[str, float], float], ratio: float) -> np.ndarray:
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


def drift_row(drift: GyroDrift, i: int, tau: float, unit: str, what, tau_unit: str) -> BudgetRow:
    """u = √(d̂² + u(d̂)²)·|τ| for gyro i's drift over the records a result combines (τ in
    ``tau_unit``: s per °/s for eq. (5), s per g_n for eq. (7))."""
    d, u = drift.d[i], drift.u[i]
    return BudgetRow.type_a(
        msg("gyro bias drift between the records ({what})", what=what), "u_d",
        Q_(math.hypot(d, u) * abs(tau), unit), max(drift.dof[i], 1),
        note=msg("pooled within-record trend of gyro {gyro}: {d:.3g} ± {u:.2g} °/s per hour over {n} records "
                 "× τ = {tau:.4g} {tau_unit}; √(d̂² + u²)·|τ| (drift not corrected)", gyro=AXES[i], d=d * 3600.0,
                 u=u * 3600.0, n=drift.records[i], tau=tau, tau_unit=tau_unit))


def not_reportable_reason(drift: GyroDrift, i: int, tau_plan: float, U: float, unit: str):
    """The reason a result of gyro i cannot be reported without recording times, or None: the
    drift is significant and, in the plan's order, would move the result by ≥ MATERIAL·U."""
    if not drift.significant(i) or not U > 0:
        return None
    effect = abs(drift.d[i] * tau_plan)
    if effect < MATERIAL * U:
        return None
    return msg("gyro {gyro}'s bias drifts by {d:.3g} °/s per hour during the campaign (pooled trend of its {n} "
               "records, {z:.1f} standard errors); recorded back to back in the plan's order the drift would move "
               "this result by {effect:.2g} {unit} ({ratio:.1f} × its U), and the manifest gives no recording times "
               "(`started` on the segments) to budget it. Give `started` on every segment, or let the MIMU warm up "
               "until its bias is steady (7.2.1.1 b)) and recalibrate", gyro=AXES[i], d=drift.d[i] * 3600.0,
               n=drift.records[i], z=drift.z(i), effect=effect, unit=unit, ratio=effect / U)


def drift_warning(drift: GyroDrift) -> list[Any]:
    """A warning per gyro whose drift is significant (whatever the results do with it)."""
    out = []
    if drift.timed:
        out.append(msg("`started` is given on {n} of the {m} records only: the recording times are not used, and a "
                       "drift between the records is not budgeted", n=drift.timed, m=len(drift.durations)))
    for i in range(3):
        if drift.significant(i):
            out.append(msg("gyro {gyro}'s bias drifts by {d:.3g} ± {u:.2g} °/s per hour during the campaign (pooled "
                           "within-record trend of {n} records): JJF 2003 takes B_g as constant; the results that "
                           "difference records {how}", gyro=AXES[i], d=drift.d[i] * 3600.0, u=drift.u[i] * 3600.0,
                           n=drift.records[i],
                           how=(msg("carry it as a budget row (recording times given)") if drift.mid_times is not None
                                else msg("are checked against it (no recording times)"))))
    return out

"""Draft JJF 光学陀螺测角仪校准规范 (征求意见稿) — formulas as pure functions on plain numbers.

Clause and equation numbers refer to the draft (file 004 in the standards folder; its
extraction lost the layout, so the structured reading in the standards README is used
alongside it).  The draft numbers the equations of clause 7 only by clause, so each
docstring cites the clause and the formula as printed; appendix A numbers its own
equations (A) (2)–(5).  Units are those the draft states; procedures convert at the boundary.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import attrs
import numpy as np

ARCSEC_PER_DEG = 3600.0


def _arr(x: Sequence[float], what: str, n_min: int = 1) -> np.ndarray:
    a = np.asarray(x, dtype=float)
    if a.ndim != 1 or a.size < n_min:
        raise ValueError(f"{what} needs at least {n_min} values, got {a.size}")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{what}: values must be finite")
    return a


# ------------------------------------------------------------------------------ 7.1 / 7.2


def scale_factors_71(counts: Sequence[float], angles_deg: Sequence[float]) -> np.ndarray:
    """Per-round scale factor, clause 7.1: K_i = C_i / θ_i (counts/°).

    :param counts: C_i, output counts of round i.
    :param angles_deg: θ_i, angular displacement of round i, °.
    """
    c = _arr(counts, "7.1 counts")
    t = _arr(angles_deg, "7.1 angles")
    if c.size != t.size:
        raise ValueError("7.1: as many counts as angular displacements are needed")
    if np.any(t == 0):
        raise ValueError("7.1: an angular displacement θ_i is zero")
    return c / t


def scale_factor_71(k_i: Sequence[float]) -> float:
    """Scale factor, clause 7.1: K = (1/6) Σ K_i (the mean of the rounds' K_i), counts/°."""
    return float(np.mean(_arr(k_i, "7.1 K_i")))


def linearity_72(k_i: Sequence[float]) -> float:
    """Scale-factor linearity, clause 7.2: K_l = (max K_i − min K_i) / K (a ratio; ×100 for %)."""
    k = _arr(k_i, "7.2 K_i", 2)
    K = float(np.mean(k))
    if K == 0:
        raise ValueError("7.2: the mean scale factor is zero")
    return float((k.max() - k.min()) / K)


@attrs.frozen
class RangeEstimate:
    """K_l of clause 7.2 from noisy K_i (:func:`linearity_72_moment_matched`), all relative to K."""

    printed: float  #: (max K_i − min K_i)/K as clause 7.2 prints it
    estimate: float  #: the instrument's own range, the printed one less the inflation by the noise
    spread: float  #: standard deviation of the range of the K_i as measured, over the noise draws
    noise_only: float  #: mean range the noise alone gives (every K_i equal): the d₂(n)·σ of equal σ

    @property
    def inflation(self) -> float:
        """printed − estimate: how much the noise of the K_i widened the printed range (≥ 0)."""
        return self.printed - self.estimate


def linearity_72_moment_matched(k_i: Sequence[float], noise: np.ndarray, *,
                                iterations: int = 50) -> RangeEstimate:
    """Clause 7.2's K_l = (max K_i − min K_i)/K corrected for the widening of a range by noise.

    Not in the draft (interpretations.md, "7.2 — K_l is a range of noisy K_i").  The noise of the
    K_i can only widen their range on average (a range is convex: E[range(d + e)] ≥ range(d)); for
    n equal standard deviations σ and no true variation the expected range is d₂(n)·σ (d₂(6) =
    2.534). With d_i = K_i/K̄ − 1 and ``noise`` an (M × n) array of draws of the relative errors of
    the K_i (GUM Supplement 1), f(λ) = mean over the draws of range(λ·d + e) grows with λ; the
    estimate is λ̂·range(d) with f(λ̂) = range(d) (moment matching, bisection; common draws keep f
    monotone), 0 when the noise alone already gives the observed range on average (f(0) ≥ range(d)).

    :param k_i: the rounds' scale factors K_i (any unit).
    :param noise: relative errors of the K_i, one row per draw, one column per round.
    """
    k = _arr(k_i, "7.2 K_i", 2)
    e = np.asarray(noise, dtype=float)
    if e.ndim != 2 or e.shape[1] != k.size or e.shape[0] < 2:
        raise ValueError("7.2: the noise draws must be an array of draws × rounds")
    K = float(np.mean(k))
    if K == 0:
        raise ValueError("7.2: the mean scale factor is zero")
    return _range_matched(k / K - 1.0, e, iterations)


def range_moment_matched(values: Sequence[float], noise: np.ndarray, *,
                         iterations: int = 50) -> RangeEstimate:
    """The range max x_i − min x_i of noisy values less its expected widening by their noise, as
    :func:`linearity_72_moment_matched` does for K_l, in the values' own unit: for clause 7.6's C_v
    and 7.7's C_g, whose numerator is the range of eight (three) noisy E (interpretations.md, "7.6
    / 7.7 — the range of noisy E").  With d_i = x_i − mean(x) and ``noise`` an (M × n) array of
    draws of the errors of the x_i, f(λ) = mean range(λ·d + e); the estimate is λ̂·range(d) with
    f(λ̂) = range(d), 0 when the noise alone already gives the observed range on average."""
    x = _arr(values, "range values", 2)
    e = np.asarray(noise, dtype=float)
    if e.ndim != 2 or e.shape[1] != x.size or e.shape[0] < 2:
        raise ValueError("the noise draws must be an array of draws × values")
    return _range_matched(x - float(np.mean(x)), e, iterations)


def _range_matched(d: np.ndarray, e: np.ndarray, iterations: int) -> RangeEstimate:
    R = float(d.max() - d.min())

    def ranges(lam: float) -> np.ndarray:
        x = lam * d + e
        return x.max(axis=1) - x.min(axis=1)

    m0 = float(np.mean(ranges(0.0)))
    if m0 >= R:
        lam = 0.0
    else:
        lo, hi = 0.0, 1.0
        for _ in range(iterations):
            mid = 0.5 * (lo + hi)
            lo, hi = (mid, hi) if float(np.mean(ranges(mid))) < R else (lo, mid)
        lam = 0.5 * (lo + hi)
    return RangeEstimate(R, lam * R, float(np.std(ranges(1.0), ddof=1)), m0)


# ------------------------------------------------------------------------------------ 7.3


def zero_stability_73(readings_deg: Sequence[float], duration_h: float,
                      statistic: str = "std") -> float:
    """Zero stability B_s, clause 7.3 (method) or definition 3.3, °/h.

    * ``statistic="std"`` (clause 7.3, the method): B_s = s(M) / T with s the Bessel
      standard deviation of the readings M_n and T the duration;
    * ``statistic="range"`` (definition 3.3): B_s = (max M − min M) / T.

    :param readings_deg: angle readings M_n of the instrument at rest, °.
    :param duration_h: T, the time the readings span, h.
    """
    m = _arr(readings_deg, "7.3 readings", 3)
    if not duration_h > 0:
        raise ValueError("7.3: the duration must be positive")
    if statistic == "std":
        return float(np.std(m, ddof=1)) / duration_h
    if statistic == "range":
        return float(m.max() - m.min()) / duration_h
    raise ValueError(f"7.3: statistic must be 'std' or 'range', got {statistic!r}")


# ------------------------------------------------------------------------------ 7.4 / 7.5


def position_errors_74(readings: Sequence[float], standard: Sequence[float]) -> np.ndarray:
    """Angle-position error of each calibration point, clause 7.4: E_i = M_i − S_i."""
    m = _arr(readings, "7.4 readings")
    s = _arr(standard, "7.4 standard angles")
    if m.size != s.size:
        raise ValueError("7.4: as many readings as standard angles are needed")
    return m - s


def position_error_74(errors: Sequence[float]) -> float:
    """Result of clause 7.4: E = ± max |E_i| (the magnitude is returned; it is reported with ±)."""
    return float(np.max(np.abs(_arr(errors, "7.4 E_i"))))


def repeatability_75(errors_by_round: np.ndarray) -> tuple[float, np.ndarray]:
    """Repeatability, clause 7.5: R_i = Bessel standard deviation of E_ij over the rounds j
    at position i; R = max R_i.

    :param errors_by_round: array (rounds × positions) of E_ij.
    :return: (R, the R_i per position).
    """
    e = np.asarray(errors_by_round, dtype=float)
    if e.ndim != 2 or e.shape[0] < 2:
        raise ValueError("7.5 needs at least 2 rounds of the 7.4 positions")
    r_i = np.std(e, axis=0, ddof=1)
    return float(r_i.max()), r_i


def reading_step(errors_arcsec: np.ndarray, *, tol: float = 1e-6) -> float:
    """The step of the readings, inferred from the data (not in the draft; interpretations.md,
    "7.4 — the reading's resolution"), ″.

    Readings rounded to a resolution q differ by whole multiples of q: the smallest non-zero
    difference between the rounds' E_ij at one stop (columns: stops), over the stops; when every
    round reads the same at every stop, the smallest non-zero difference between any two E_ij (the
    standard angles, whole multiples of 30°, keep a decimal q's grid).  Unrounded readings give a
    step far below their noise.  0 when all values are equal.

    :param errors_arcsec: E_ij, ″, rounds × stops.
    :param tol: differences below this (″) are float noise of the unit conversion, not a step.
    """
    e = np.atleast_2d(np.asarray(errors_arcsec, dtype=float))

    def smallest(v: np.ndarray) -> float:
        d = np.diff(np.unique(v))
        d = d[d > tol]
        return float(d.min()) if d.size else math.inf

    q = min((smallest(e[:, j]) for j in range(e.shape[1])), default=math.inf)
    if not math.isfinite(q):
        q = smallest(e.ravel())
    return q if math.isfinite(q) else 0.0


# ------------------------------------------------------------------------------ 7.6 / 7.7


def consistency_ratio(values: Sequence[float], reference: float) -> float:
    """Rate consistency C_v (clause 7.6, definition 3.4) and pointing consistency C_g
    (clause 7.7, definition 3.5): (max E − min E) / E_ref, a ratio (×100 for %).

    ``values`` are the angle-position errors E (the 7.4 results) under each rate or axis
    direction; ``reference`` the one at 60 °/s (C_v) or with the axis up (C_g).
    """
    v = _arr(values, "consistency values", 2)
    if reference == 0:
        raise ValueError("the reference angle-position error is zero, so the ratio is undefined")
    return float((v.max() - v.min()) / reference)


# ----------------------------------------------------------------------- appendix A, 4.2


def ellipse_radius_a3(theta_rad: np.ndarray, psi_rad: float, r: float = 1.0) -> np.ndarray:
    """Appendix A eq. (3): radius of the projected (elliptical) optical path at turntable angle θ::

        r(θ) = r·cos ψ / sqrt(cos²ψ·cos²θ + sin²θ)
    """
    th = np.asarray(theta_rad, dtype=float)
    return r * math.cos(psi_rad) / np.sqrt(math.cos(psi_rad) ** 2 * np.cos(th) ** 2
                                           + np.sin(th) ** 2)


@attrs.frozen
class TiltSimulation:
    """Result of the appendix A 4.2 numerical simulation (angles in °, errors in ″)."""

    psi_deg: float
    theta_deg: np.ndarray
    error_arcsec: np.ndarray

    @property
    def extreme_arcsec(self) -> float:
        """max |Δ(θ)| over 0…360°, ″ (the draft's 误差极限值)."""
        return float(np.max(np.abs(self.error_arcsec)))


def tilt_error_simulation(psi_deg: float, *, n: int = 7201) -> TiltSimulation:
    """Appendix A 4.2, eqs. (2)–(5): angle error from a sensing plane tilted by ψ to the
    turntable plane, by numerical integration over 0…360°.

    The gyro senses the arc length dl_ψ = r(θ)·dθ of the elliptical projection (eq. (2),
    r(θ) from eq. (3)); the arc-to-angle coefficient k = 360°/C, C the ellipse perimeter,
    is fixed by the scale-factor calibration over a full turn (eq. (4)), so the reading at
    turntable angle θ is::

        θ_ψ(θ) = 360° · ∫₀^θ r(φ) dφ / ∫₀^{2π} r(φ) dφ

    and the error (eq. (5)) is Δ(θ) = θ_ψ(θ) − θ.  The integrals are cumulative composite
    Simpson sums on ``n`` points (n odd); the result is exact to far below 0.001″ for
    ψ ≤ 1° with the default grid.
    """
    if n < 5 or n % 2 == 0:
        raise ValueError("n must be odd and ≥ 5")
    psi = math.radians(psi_deg)
    th = np.linspace(0.0, 2.0 * math.pi, n)
    r = ellipse_radius_a3(th, psi)
    h = th[1] - th[0]
    # cumulative composite Simpson: even nodes by whole Simpson pairs, odd nodes add the
    # first interval of the next pair, ∫_{x0}^{x1} f ≈ h/12·(5f0 + 8f1 − f2)
    cum = np.zeros(n)
    pair = h / 3.0 * (r[0:-2:2] + 4.0 * r[1:-1:2] + r[2::2])
    cum[2::2] = np.cumsum(pair)
    cum[1::2] = cum[0:-1:2] + h / 12.0 * (5.0 * r[0:-1:2] + 8.0 * r[1::2] - r[2::2])
    reading = 2.0 * math.pi * cum / cum[-1]
    err = np.degrees(reading - th) * ARCSEC_PER_DEG
    return TiltSimulation(psi_deg, np.degrees(th), err)


def tilt_error_small_angle(psi_deg: float) -> float:
    """Closed-form check of :func:`tilt_error_simulation` for small ψ (not in the draft):
    with ε = sin²ψ, r(θ)/r̄ ≈ 1 + (ε/4)·cos 2θ, so Δ(θ) ≈ (ε/8)·sin 2θ and the extreme is
    ε/8 rad; returned in ″."""
    eps = math.sin(math.radians(psi_deg)) ** 2
    return math.degrees(eps / 8.0) * ARCSEC_PER_DEG


def zero_drift_error(drift_deg_per_h: float, time_min: float) -> float:
    """Appendix A 4.3: largest drift over the measurement time, ″ = B_s[″/min] × t[min]
    (0.005 °/h = 0.3 ″/min; × 0.5 min = 0.15 ″)."""
    return abs(drift_deg_per_h) * ARCSEC_PER_DEG / 60.0 * time_min

"""GB/T 45570—2025 appendix D formulas, as pure functions on plain numbers.

Units are those the standard states for each formula (given in each docstring); the
procedures in :mod:`metro.plugins.gbt45570.procedures` convert at the boundary.  Shared
maths (block statistics, least squares) comes from :mod:`metro.api`.
"""

from __future__ import annotations

import math
from typing import Sequence

import attrs
import numpy as np
from metro.api import fit_linear, rounding_mean_bound  # noqa: F401  (core.stats.quantization)

#: Earth rotation rate as printed in D.40, °/h.
EARTH_RATE_DEG_PER_H = 15.041


def bias_d40(mean_count: float, tau_s: float, K_P_per_arcsec: float, latitude_deg: float) -> float:
    """Bias (zero offset) of a pulse-output gyro, GB/T 45570 D.5.1.3 eq. (D.40)::

        B0 = (1/(τ·K)) · (1/n) Σ N_i − 15.041 · sin θ

    :param mean_count: (1/n) Σ N_i, mean pulses per sampling interval, P.
    :param tau_s: sampling interval τ, s.
    :param K_P_per_arcsec: scale factor K, P/″.
    :param latitude_deg: site latitude θ, °.
    :return: B0 in °/h (1 ″/s = 1 °/h exactly).
    """
    return mean_count / (tau_s * K_P_per_arcsec) - earth_rate_vertical(latitude_deg)


def earth_rate_vertical(latitude_deg: float, orientation: str = "up") -> float:
    """Component of the earth rate along an input axis pointing ``up`` (or ``down``), °/h:
    ±15.041·sin θ (the term subtracted in D.40)."""
    sign = {"up": 1.0, "down": -1.0}[orientation]
    return sign * EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))


def bias_stability_d41(accumulated_counts: Sequence[float], t_s: float,
                       K_P_per_arcsec: float) -> float:
    """Bias stability, GB/T 45570 D.5.2.3 eq. (D.41)::

        B_s = (1/(t·K)) · [ Σ (N'_i − N̄')² / (m − 1) ]^(1/2)

    :param accumulated_counts: N'_i, pulses accumulated over each smoothing time t (m values).
    :param t_s: smoothing time t, s.
    :param K_P_per_arcsec: scale factor K, P/″.
    :return: B_s in °/h.
    """
    n = np.asarray(accumulated_counts, dtype=float)
    if n.size < 2:
        raise ValueError(f"D.41 needs at least 2 accumulated values, got {n.size}")
    return float(np.std(n, ddof=1)) / (t_s * K_P_per_arcsec)


def bias_repeatability_d42(biases: Sequence[float]) -> float:
    """Bias repeatability, D.5.3.3 eq. (D.42): Bessel standard deviation of the Q biases (°/h)."""
    b = np.asarray(biases, dtype=float)
    if b.size < 2:
        raise ValueError("D.42 needs at least 2 biases")
    return float(np.std(b, ddof=1))


@attrs.frozen
class D45Fit:
    """Result of fitting B_s²(τ_k) = α0 + α1/τ_k + α2/τ_k² (D.45), τ_k in hours."""

    alpha: np.ndarray  # α0 [(°/h)²], α1 [(°)²/h], α2 [(°)²]
    cov: np.ndarray
    chi2: float
    dof: int
    birge: float  # sqrt(chi2/dof) when > 1 (covariance scaled by its square), else 1
    tau_h: np.ndarray
    bs2: np.ndarray
    m: np.ndarray

    @property
    def u_alpha(self) -> np.ndarray:
        return np.sqrt(np.diag(self.cov))

    def model(self, tau_h: np.ndarray) -> np.ndarray:
        t = np.asarray(tau_h, dtype=float)
        return self.alpha[0] + self.alpha[1] / t + self.alpha[2] / t**2


def d45_design(tau_h: np.ndarray) -> np.ndarray:
    """Design matrix [1, 1/τ, 1/τ²] of eq. (D.45)."""
    t = np.asarray(tau_h, dtype=float)
    return np.column_stack([np.ones_like(t), 1.0 / t, 1.0 / t**2])


def d45_covariance(model_bs2: np.ndarray, m: np.ndarray) -> np.ndarray:
    """Covariance of the sample variances B_s²(τ_k) of nested block means.

    Treating the block means at each level as independent normal values (exact for white
    noise), level k+d is built from level k by averaging groups of 2^d, and the sum of
    squares at level k splits into the level-(k+d) part and an independent within-group
    part.  Hence, with σ_k² the expected variance at level k and m_k its number of blocks::

        var(s_k²)        = 2 σ_k⁴ / (m_k − 1)
        cov(s_j², s_k²)  = 2 σ_j² σ_k² / (m_j − 1)     (j the finer level, m_j > m_k)

    so adjacent levels correlate by about 1/√2.  (interpretations.md, "D.5.6 fit weights")
    """
    s2 = np.asarray(model_bs2, dtype=float)
    mm = np.asarray(m, dtype=float)
    n = s2.size
    C = np.empty((n, n))
    for j in range(n):
        for k in range(n):
            fine = j if mm[j] >= mm[k] else k
            C[j, k] = 2.0 * s2[j] * s2[k] / (mm[fine] - 1.0)
    return C


def fit_d45(tau_h: Sequence[float], bs: Sequence[float], m: Sequence[int], *,
            iterations: int = 4) -> D45Fit:
    """Least-squares fit of the bias-stability model, GB/T 45570 D.5.6.3 eq. (D.45)::

        B_s²(τ_k) = α0 + α1 (1/τ_k) + α2 (1/τ_k)²,   τ_k in h, B_s in °/h

    The standard says "least squares" without weights.  B_s² spans decades, so metro uses
    generalised least squares with the covariance of :func:`d45_covariance` evaluated at
    the model (iterated from the observed values); if the fit's χ²/ν exceeds 1 the
    covariance of α is scaled by it (Birge ratio), so a model that does not fit the data
    reports a larger uncertainty.  See docs/interpretations.md.

    :param tau_h: τ_k in hours (at least 4 levels).
    :param bs: B_s(τ_k) in °/h.
    :param m: number of blocks behind each B_s(τ_k).
    """
    t = np.asarray(tau_h, dtype=float)
    b = np.asarray(bs, dtype=float)
    mm = np.asarray(m, dtype=float)
    if not (t.size == b.size == mm.size):
        raise ValueError("tau, B_s and m must have the same length")
    if t.size < 4:
        raise ValueError(
            f"the D.45 fit has 3 coefficients and needs at least 4 τ levels; got {t.size} "
            "(record too short for the τ range)"
        )
    if np.any(b <= 0) or not np.all(np.isfinite(b)):
        bad = int(np.argmin(b > 0)) if np.any(b <= 0) else int(np.argmin(np.isfinite(b)))
        raise ValueError(
            f"B_s(τ) must be positive and finite; level {bad + 1} (τ = {t[bad] * 3600:g} s) gives "
            f"{b[bad]!r} "
            "(zero-variance or constant data?)"
        )
    if np.any(mm < 2):
        raise ValueError("every level needs at least 2 blocks")
    y = b**2
    A = d45_design(t)
    s2 = y.copy()
    fit = None
    for _ in range(max(1, iterations)):
        C = d45_covariance(s2, mm)
        fit = fit_linear(A, y, cov_y=C, scale_cov=False)
        pred = A @ fit.coef
        # keep the covariance positive: where the model is not positive use the observation
        s2 = np.where(pred > 0, pred, y)
    assert fit is not None
    C = d45_covariance(s2, mm)
    r = y - A @ fit.coef
    chi2 = float(r @ np.linalg.solve(C, r))
    dof = t.size - 3
    birge = math.sqrt(chi2 / dof) if dof > 0 and chi2 > dof else 1.0
    cov = np.asarray(fit.cov) * birge**2
    return D45Fit(np.asarray(fit.coef), cov, chi2, dof, birge, t, y, mm)


def rwc_d46(alpha1: float) -> float:
    """Angle random walk coefficient, D.5.6.3 eq. (D.46): RWC = α1^(1/2), °/√h."""
    if not alpha1 > 0:
        raise ValueError(f"α1 = {alpha1:g} is not positive, so RWC = √α1 is undefined")
    return math.sqrt(alpha1)


def bias_temperature_sensitivity_d43(biases: Sequence[float], temps_C: Sequence[float],
                                     i0: int) -> tuple[float, int]:
    """Bias temperature sensitivity, D.5.4.3 eq. (D.43)::

        B_t = | (B_i − B_00) / (T_i − T_0) |_max

    :param biases: B_i in °/h at each temperature point (the room-temperature one included).
    :param temps_C: T_i in °C.
    :param i0: index of the room-temperature point (B_00, T_0).
    :return: (B_t in (°/h)/°C, index i of the maximising point).
    """
    best, imax = -1.0, -1
    for i, (b, t) in enumerate(zip(biases, temps_C)):
        if i == i0:
            continue
        if t == temps_C[i0]:
            raise ValueError(f"point {i} has the room temperature {t} °C; "
                             "D.43 divides by T_i − T_0")
        r = abs((b - biases[i0]) / (t - temps_C[i0]))
        if r > best:
            best, imax = r, i
    if imax < 0:
        raise ValueError("D.43 needs at least one point besides room temperature")
    return best, imax


def bias_magnetic_sensitivity_d44(b_plus: float, b_minus: float, H_b_mT: float) -> float:
    """Bias magnetic sensitivity, D.5.5.3 eq. (D.44): B_h = |B_0+ − B_0−| / (2 H_b), (°/h)/mT."""
    if not H_b_mT > 0:
        raise ValueError(f"H_b must be positive, got {H_b_mT}")
    return abs(b_plus - b_minus) / (2.0 * H_b_mT)


# --------------------------------------------------------------------------------------------
# D.1 scale factor series, angle method (pulse output)
# --------------------------------------------------------------------------------------------

#: arcseconds in one revolution, 360 × 3 600 (the denominators of D.2, D.8, D.9)
REVOLUTION_ARCSEC = 360.0 * 3600.0


def mean_of(values: Sequence[float], eq: str, what: str) -> float:
    """The arithmetic mean (1/n) Σ x of eq. ``eq`` (D.1, D.17); a ValueError naming the equation
    when there is no ``what`` to average."""
    a = np.asarray(values, dtype=float)
    if a.size < 1:
        raise ValueError(f"{eq} needs at least one {what}")
    return float(a.mean())


def mean_counts_d1(counts_per_turn: Sequence[float]) -> float:
    """N_±i = (1/m) Σ_j N_±ij, eq. (D.1): mean pulses per whole revolution (P)."""
    return mean_of(counts_per_turn, "D.1", "revolution")


def scale_factor_d2(n_plus: float, n_minus: float) -> float:
    """K_i = (N_+i − N_−i) / (2 × 360 × 3 600), eq. (D.2), in P/″.

    (The standard's unit line prints P/(°); the 3 600 in the denominator makes it P/″, as
    table A.1 states — see interpretations.md.)
    """
    return (n_plus - n_minus) / (2.0 * REVOLUTION_ARCSEC)


def scale_factor_d3(n_plus: float, n_minus: float, theta_plus_deg: float,
                    theta_minus_deg: float) -> float:
    """Fixed-angle method, eq. (D.3): K_i = (N'_+i − N'_−i) / ((|θ_+| + |θ_−|) × 3 600), P/″."""
    return (n_plus - n_minus) / ((abs(theta_plus_deg) + abs(theta_minus_deg)) * 3600.0)


def scale_factor_fit_d5_d6(K_i: Sequence[float], rates_deg_s: Sequence[float]) -> tuple[float,
                                                                                        float]:
    """Least squares of K_i = K + W·Ω_i (eq. D.4), closed forms (D.5) and (D.6).

    :return: (K in P/″, W in (P/″)/((°)/s)).
    """
    k = np.asarray(K_i, dtype=float)
    w = np.asarray(rates_deg_s, dtype=float)
    n = k.size
    if n < 2 or w.size != n:
        raise ValueError("D.5/D.6 need at least 2 rate points and one K_i per rate")
    den = n * np.sum(w**2) - np.sum(w) ** 2
    if den == 0:
        raise ValueError("all rate points are equal; the eq. (D.4) fit is singular")
    K = (np.sum(k) * np.sum(w**2) - np.sum(k * w) * np.sum(w)) / den
    W = (n * np.sum(k * w) - np.sum(w) * np.sum(k)) / den
    return float(K), float(W)


def nonlinearity_d7(K_i: Sequence[float], K: float) -> tuple[float, int]:
    """K_n = |K_i − K|_max / K, eq. (D.7); returns (K_n, index of the maximum)."""
    d = np.abs(np.asarray(K_i, dtype=float) - K)
    i = int(np.argmax(d))
    return float(d[i] / K), i


def scale_factor_plus_d8(n_plus: float, n0_per_s: float, t_plus_s: float) -> float:
    """K_+i = (N_+i − N̄_0 × t_+i) / (360 × 3 600), eq. (D.8), P/″."""
    return (n_plus - n0_per_s * t_plus_s) / REVOLUTION_ARCSEC


def scale_factor_minus_d9(n_minus: float, n0_per_s: float, t_minus_s: float) -> float:
    """K_−i = (N_−i − N̄_0 × t_−i) / (−360 × 3 600), eq. (D.9), P/″."""
    return (n_minus - n0_per_s * t_minus_s) / (-REVOLUTION_ARCSEC)


def asymmetry_d10(K_plus: float, K_minus: float) -> float:
    """K_a = |K_+ − K_−| / ((K_+ + K_−)/2), eq. (D.10)."""
    return abs(K_plus - K_minus) / ((K_plus + K_minus) / 2.0)


def asymmetry_model_d10(Ka: float, c_n0: float, n_rows: int):
    """The measurement model of K_a (eq. (D.10)) for the Monte Carlo check of its budget (JCGM 101):
    K_a = |K_+ − K_−|/K̄ is folded at 0, which the budget's linear Σ c_i·x_i is not.  Given the
    draws of the rows' deviations (rows × M: the fits' relative √(u²(K₊)+u²(K₋))/K̄, then u(N̄₀) and
    the bias drift in P/s, both through |∂K_a/∂N̄₀| = ``c_n0``), the deviation of K_a in ppm:
    |K_a + δ_fit + c·(δN̄₀ + δḃ)| − K_a (the sign of K_+ − K_− is a symmetric draw's).

    >>> import numpy as np
    >>> round(float(asymmetry_model_d10(1e-6, 0.0, 2)(np.array([[-3e-6], [0.0]]))[0]), 9)
    1.0
    """

    def model(d):
        lin = Ka + d[0] + c_n0 * sum(d[i] for i in range(1, n_rows))
        return (abs(lin) - Ka) * 1e6

    return model


# --------------------------------------------------------------------------------------------
# Output quantization (not in the standard: the budget rows D.5.1, D.5.2 and D.5.6 need;
# docs/interpretations.md, "D.5 — output quantization")
# --------------------------------------------------------------------------------------------


def rounding_sigma(s_measured: float, q: float) -> float:
    """σ of the noise before rounding from the measured standard deviation ``s`` of the rounded
    samples, by Sheppard's correction σ² = s² − q²/12 (valid when the noise dithers the
    rounding, σ ≳ q/2; 0 when s² < q²/12)."""
    return math.sqrt(max(s_measured**2 - q * q / 12.0, 0.0))


def alpha1_rounding_d45(q_deg_h: float, tau0_h: float) -> float:
    """The part of D.45's α1 that rounding each rate sample to q adds when the noise dithers the
    rounding: white rate noise of variance q²/12 per sample of τ0, i.e. α1 = q²·τ0/12
    ((°/h)²·h; B_s²(τ) = α1/τ for white rate noise)."""
    return q_deg_h * q_deg_h * tau0_h / 12.0


def asymmetry_sensitivity_n0(rates_deg_s: Sequence[float], t_plus_s: Sequence[float],
                             t_minus_s: Sequence[float],
                             K_plus: float, K_minus: float) -> float:
    """|∂K_a/∂N̄_0| of eqs. (D.8)–(D.10) (GB/T 45570 D.1.3.3), s/P, analytically.

    K_± are the D.5 intercepts of the K_±i of (D.8)/(D.9), linear in N̄_0: the intercept of a line
    fit is linear in the data, so ∂K_+/∂N̄_0 = −a(t_+)/R and ∂K_−/∂N̄_0 = +a(t_−)/R, with a(t) the
    intercept of the same fit of the revolution times and R = 360 × 3 600″.  With D = K_+ − K_− and
    M = (K_+ + K_−)/2, K_a = |D|/M and

        ∂K_a/∂N̄_0 = sign(D)·D′/M − |D|·M′/M²

    At the kink (D = 0) the two one-sided slopes are ±D′/M; their common magnitude is returned
    (a central difference through |D| would give about 0 there, or K_a itself near it)."""
    r = np.asarray(rates_deg_s, dtype=float)

    def icpt(y) -> float:
        return float(np.polyfit(r, np.asarray(y, dtype=float), 1)[1])

    dKp = -icpt(t_plus_s) / REVOLUTION_ARCSEC
    dKm = icpt(t_minus_s) / REVOLUTION_ARCSEC
    D, M = K_plus - K_minus, 0.5 * (K_plus + K_minus)
    dD, dM = dKp - dKm, 0.5 * (dKp + dKm)
    if D == 0.0:
        return abs(dD) / M
    return abs(math.copysign(1.0, D) * dD / M - abs(D) * dM / M**2)


def std_upper_limit(s: float, n_values: int, p: float = 0.02275) -> float:
    """Upper confidence limit of σ from a Bessel standard deviation ``s`` of ``n_values`` normal
    values, s·√(ν/χ²_p(ν)), ν = n − 1 (:func:`metro.api.std_upper_limit`).  Used
    for the
    sampling row of D.42 (interpretations.md, D.5.3): at Q = 7, σ_upper = 2.243·s."""
    from metro.api import std_upper_limit as upper

    return upper(s, n_values, p)

"""GB/T 45570—2025 appendix D formulas of D.1.4–D.1.6 (angle method), D.2 (rate method) and
D.3 (maximum input rate), as pure functions on plain numbers.

Units are those the standard states for each formula (each docstring names them); the
procedures in :mod:`.angle_method` and :mod:`.rate_method` convert at the boundary.
"""

from __future__ import annotations

import math
from typing import Callable, Sequence

import numpy as np
from metro.api import (  # D.12, D.29, D.43: the maximum's selection bias
    MaxSelection,
)

from .formulas import REVOLUTION_ARCSEC, mean_of

# --------------------------------------------------------------------------------------------
# D.1.4 / D.2.4 repeatability, D.1.5 / D.2.5 temperature sensitivity
# --------------------------------------------------------------------------------------------


def scale_factor_repeatability_d11(K_j: Sequence[float]) -> float:
    """Scale-factor repeatability, D.1.4.3 eq. (D.11) (and D.2.4.3 eq. (D.28), the same form)::

        K_r = [ Σ (K_j − K̄)² / (Q − 1) ]^(1/2) / K̄,   K̄ = (1/Q) Σ K_j

    The standard writes Q = 7 (the sums to 7, the divisor 6); the function takes any Q ≥ 2 and
    the procedures insist on 7.  Dimensionless (K_j in P/″ or LSB/[(°)/s], both cancel).
    """
    k = np.asarray(K_j, dtype=float)
    if k.size < 2:
        raise ValueError(f"D.11 needs at least 2 scale factors, got {k.size}")
    mean = float(k.mean())
    if mean == 0:
        raise ValueError("the mean scale factor is 0; D.11 divides by it")
    return float(np.std(k, ddof=1)) / abs(mean)


#: eq. (D.28) of D.2.4.3 is printed identically to (D.11)
scale_factor_repeatability_d28 = scale_factor_repeatability_d11


def scale_factor_temperature_sensitivity_d12(K_i: Sequence[float], temps_C: Sequence[float],
                                             i0: int) -> tuple[float, int]:
    """Scale-factor temperature sensitivity, D.1.5.3 eq. (D.12) (and D.2.5.3 eq. (D.29))::

        K_t = | (K_i − K_00) / (K_00 × (T_i − T_0)) |_max

    :param K_i: scale factors at each temperature point (the room-temperature one included).
    :param temps_C: T_i in °C.
    :param i0: index of the room-temperature point (K_00, T_0).
    :return: (K_t in 1/°C, index of the maximising point).
    """
    K = np.asarray(K_i, dtype=float)
    T = np.asarray(temps_C, dtype=float)
    if K.size != T.size:
        raise ValueError("one scale factor per temperature point")
    if K[i0] == 0:
        raise ValueError("K_00 is 0; D.12 divides by it")
    best, imax = -1.0, -1
    for i in range(K.size):
        if i == i0:
            continue
        if T[i] == T[i0]:
            raise ValueError(f"point {i} has the room temperature {T[i]:g} °C; D.12 divides by T_i "
                             f"− T_0")
        r = abs((K[i] - K[i0]) / (K[i0] * (T[i] - T[i0])))
        if r > best:
            best, imax = r, i
    if imax < 0:
        raise ValueError("D.12 needs at least one point besides room temperature")
    return float(best), imax


#: eq. (D.29) of D.2.5.3 is printed identically to (D.12)
scale_factor_temperature_sensitivity_d29 = scale_factor_temperature_sensitivity_d12


# --------------------------------------------------------------------------------------------
# D.1.6 / D.2.6 input-axis misalignment
# --------------------------------------------------------------------------------------------


def misalignment_d14(n_plus: float, n_minus: float, K_P_per_arcsec: float) -> float:
    """Angle of one mounting, D.1.6.4 eq. (D.14)::

        α_{1,2} = (N_+ − N_−) / (2 × 360 × 3 600 · K) × 180/π

    :param n_plus: N_+, mean pulses per counter-clockwise revolution (D.13), P.
    :param n_minus: N_−, mean pulses per clockwise revolution, P.
    :param K_P_per_arcsec: scale factor K, P/″.
    :return: α_{1,2} in degrees (the ratio is the sine of the angle, read as radians).
    """
    if not K_P_per_arcsec > 0:
        raise ValueError(f"K must be positive, got {K_P_per_arcsec}")
    return (n_plus - n_minus) / (2.0 * REVOLUTION_ARCSEC * K_P_per_arcsec) * 180.0 / math.pi


def misalignment_half_difference_d15(a1: float, a2: float) -> float:
    """α = (α_1 − α_2)/2, eq. (D.15) (also (D.32) and (D.35)): the fixture's error, common to
    both mountings, cancels; the gyro's own angle, reversed by the 180° turn, remains."""
    return (a1 - a2) / 2.0


def misalignment_gamma_d16(alpha: float, beta: float) -> float:
    """γ = (α² + β²)^(1/2), eq. (D.16) (also (D.36)); same unit as α and β."""
    return math.hypot(alpha, beta)


def misalignment_d30(F_plus: float, F_minus: float, K: float, rate: float) -> float:
    """Deviation angle of one mounting, D.2.6.4 eq. (D.30) (and (D.31), (D.33), (D.34))::

        δ = sin⁻¹( (F_+ − F_−) / (2 K Ω) )

    :param F_plus: mean output with the table turning at +Ω, LSB.
    :param F_minus: mean output at −Ω, LSB.
    :param K: scale factor, LSB/[(°)/s].
    :param rate: Ω, the table rate, (°)/s (positive).
    :return: δ in degrees.
    """
    if not (K > 0 and rate > 0):
        raise ValueError(f"K and Ω must be positive, got K = {K}, Ω = {rate}")
    s = (F_plus - F_minus) / (2.0 * K * rate)
    if abs(s) > 1:
        raise ValueError(f"(F₊ − F₋)/(2KΩ) = {s:.4g} is outside [−1, 1]; wrong K, Ω or mounting?")
    return math.degrees(math.asin(s))


# --------------------------------------------------------------------------------------------
# D.2.1–D.2.3 rate method: scale factor, nonlinearity, asymmetry
# --------------------------------------------------------------------------------------------


def mean_output_d17(samples: Sequence[float]) -> float:
    """F̄_j = (1/n) Σ_p F_jp, eq. (D.17): mean output at one input rate, LSB."""
    return mean_of(samples, "D.17", "sample")


def rest_output_d18(F_start: float, F_end: float) -> float:
    """F̄_r = (F̄_s + F̄_e)/2, eq. (D.18): output with the table at rest, start and end, LSB."""
    return 0.5 * (F_start + F_end)


def rate_output_d19(F_j: float, F_r: float) -> float:
    """F_kj = F̄_j − F̄_r, eq. (D.19): output at rate j with bias and earth rate removed, LSB."""
    return F_j - F_r


def scale_factor_fit_d21_d22(rates_deg_s: Sequence[float], F_k: Sequence[float]) -> tuple[float,
                                                                                          float]:
    """Least squares of F_kj = K·Ω_ij + F_0 (eq. D.20), closed forms (D.21) and (D.22).

    :param rates_deg_s: Ω_ij, signed (+ counter-clockwise), (°)/s; M of them.
    :param F_k: F_kj, LSB.
    :return: (K in LSB/[(°)/s], F_0 in LSB).
    """
    w = np.asarray(rates_deg_s, dtype=float)
    f = np.asarray(F_k, dtype=float)
    M = w.size
    if M < 2 or f.size != M:
        raise ValueError("D.21/D.22 need at least 2 input rates and one output per rate")
    den = np.sum(w**2) - np.sum(w) ** 2 / M
    if den == 0:
        raise ValueError("all input rates are equal; the D.20 fit is singular")
    K = (np.sum(w * f) - np.sum(w) * np.sum(f) / M) / den
    F0 = np.sum(f) / M - K / M * np.sum(w)
    return float(K), float(F0)


def fitted_output_d23(K: float, F0: float, rates_deg_s: Sequence[float]) -> np.ndarray:
    """F̂_j = K·Ω_ij + F_0, eq. (D.23), LSB."""
    return K * np.asarray(rates_deg_s, dtype=float) + F0


def nonlinearity_d24_d25(F_hat: Sequence[float], F_k: Sequence[float], F_m: float) -> tuple[float,
                                                                                            int]:
    """a_j = (F̂_j − F_kj)/|F_m| (eq. D.24) and K_n = |a_j|_max (eq. D.25).

    :param F_m: output at the stated rate (by default the maximum input rate), LSB.
    :return: (K_n, index j of the maximum).
    """
    if F_m == 0:
        raise ValueError("F_m is 0; D.24 divides by it")
    a = (np.asarray(F_hat, dtype=float) - np.asarray(F_k, dtype=float)) / abs(F_m)
    j = int(np.argmax(np.abs(a)))
    return float(abs(a[j])), j


def asymmetry_d26_d27(K_plus: float, K_minus: float) -> float:
    """K_a = |K_(+) − K_(−)| / K̄_(+,−) (eq. D.26), K̄_(+,−) = (K_(+) + K_(−))/2 (eq. D.27)."""
    mean = (K_plus + K_minus) / 2.0
    if mean == 0:
        raise ValueError("the mean of K(+) and K(−) is 0; D.26 divides by it")
    return abs(K_plus - K_minus) / abs(mean)


def asymmetry_model_d26(K_plus: float, K_minus: float, table_row: bool):
    """The measurement model of K_a (eqs. (D.26), (D.27)) for the Monte Carlo check of its budget
    (JCGM 101): |K_(+) − K_(−)|/K̄ is folded at 0 and a ratio, which the budget's linear sum is not.
    Given the draws of the rows' relative deviations (rows × M: δK₊/K̄, δK₋/K̄, and with
    ``table_row`` the table's rate error between the directions), the deviation of K_a in ppm.

    >>> import numpy as np
    >>> round(float(asymmetry_model_d26(1.0, 1.0, False)(np.array([[2e-6], [0.0]]))[0]), 6)
    1.999998
    """
    mean = (K_plus + K_minus) / 2.0
    d0 = (K_plus - K_minus) / mean
    Ka = abs(d0)

    def model(d):
        diff = d0 + d[0] - d[1] + (d[2] if table_row else 0.0)
        return (abs(diff) / (1.0 + (d[0] + d[1]) / 2.0) - Ka) * 1e6

    return model


# --------------------------------------------------------------------------------------------
# D.3 maximum input rate
# --------------------------------------------------------------------------------------------


def max_input_rate_d3(rates_deg_s: Sequence[float], nonlinearity_of: Callable[[float], float],
                      limit: float, min_points: int = 3) -> tuple[float | None, list[tuple[float,
                                                                                           float]]]:
    """Maximum input rate, D.3: the largest table rate whose range [−Ω, +Ω] has a scale-factor
    nonlinearity that meets its limit (definition 3.13, note 1: "within this range").

    :param rates_deg_s: the tested rate magnitudes |Ω_i|, (°)/s.
    :param nonlinearity_of: K_n of the range up to a given rate (D.7 or D.24/D.25 evaluated on
        the rate points ≤ that rate).
    :param limit: the limit on K_n (dimensionless).
    :param min_points: fewest rate points a range needs before its K_n is judged (the fit
        has two parameters).
    :return: (Ω_max or None if no range meets the limit, [(Ω, K_n of the range up to Ω), …]).
    """
    r = sorted({abs(float(x)) for x in rates_deg_s})
    if len(r) < min_points:
        raise ValueError(f"D.3 needs at least {min_points} rate points, got {len(r)}")
    curve = [(om, float(nonlinearity_of(om))) for om in r[min_points - 1:]]
    passing = [om for om, kn in curve if kn <= limit]
    return (max(passing) if passing else None), curve


def line_fit_sensitivities(x: Sequence[float]) -> tuple[np.ndarray, np.ndarray]:
    """The ordinary least-squares line y = a + b·x as linear combinations of the observations:
    a = Σ c_a,j·y_j and b = Σ c_b,j·y_j (the weights of (D.5)/(D.6) and (D.21)/(D.22)).

    With these, the standard uncertainty of a or b from independent u(y_j) is the GUM law of
    propagation, √Σ (c_j·u(y_j))², which — unlike the residual standard error — does not count a
    systematic nonlinearity of the data as noise.
    """
    w = np.asarray(x, dtype=float)
    if w.size < 2:
        raise ValueError("a line needs at least 2 points")
    sxx = float(np.sum((w - w.mean()) ** 2))
    if sxx == 0:
        raise ValueError("all abscissae are equal; the line fit is singular")
    cb = (w - w.mean()) / sxx
    ca = 1.0 / w.size - w.mean() * cb
    return ca, cb


def propagate(c: Sequence[float], u: Sequence[float], dof: Sequence[float]) -> tuple[float, float]:
    """u = √Σ (c_j u_j)² and its Welch–Satterthwaite degrees of freedom from each u_j's ν_j."""
    parts = np.abs(np.asarray(c, dtype=float) * np.asarray(u, dtype=float))
    uc = float(np.sqrt(np.sum(parts**2)))
    d = np.asarray(dof, dtype=float)
    den = float(np.sum(parts**4 / d))
    return uc, (uc**4 / den if den > 0 else math.inf)


def nonlinearity_selection(rates: Sequence[float], Fk: Sequence[float], uF: Sequence[float], *,
                           draws: int = 2000, seed: int = 45570) -> MaxSelection:
    """Selection bias of K_n = max_j |F̂_j − F_kj|/|F_m| (D.23–D.25), as :func:`max_slope_selection`
    does for the temperature slopes: the largest of 2M noisy point deviations overstates a small
    nonlinearity.  The F_kj are smoothed by a weighted least-squares fit of the smooth forms a
    scale factor takes against rate — 1, Ω, |Ω| (asymmetry), Ω|Ω| (a linear K(|Ω|)), Ω³ (a quadratic
    one) — kept as measured when its χ² exceeds the 95 % point; drawn about it with their u (normal,
    independent; GUM Supplement 1); bias = mean(K_n*) − K_n(smoothed)."""
    w = np.asarray(rates, dtype=float)
    y = np.asarray(Fk, dtype=float)
    uu = np.asarray(uF, dtype=float)
    X = np.column_stack([np.ones_like(w), w])
    H = X @ np.linalg.solve(X.T @ X, X.T)  # the D.21/D.22 line as a projection
    top = np.abs(w) == np.abs(w).max()

    def stat(Y: np.ndarray) -> np.ndarray:
        resid = Y - Y @ H.T
        return np.max(np.abs(resid), axis=-1) / np.max(np.abs(Y[..., top]), axis=-1)

    printed = float(stat(y))
    if not np.all(uu > 0):
        return MaxSelection(printed, printed, 0.0, 0.0, -1)
    B = np.column_stack([np.ones_like(w), w, np.abs(w), w * np.abs(w), w**3])
    scale = np.max(np.abs(B), axis=0)
    Bw = B / scale / uu[:, None]
    coef, *_ = np.linalg.lstsq(Bw, y / uu, rcond=None)
    smooth = (B / scale) @ coef
    dof = w.size - B.shape[1]
    deg = 3
    from scipy.stats import chi2

    if dof < 1 or float(np.sum(((y - smooth) / uu) ** 2)) > float(chi2.ppf(0.95, dof)):
        smooth, deg = y, -1
    sample = np.random.default_rng(seed).normal(smooth, uu, size=(int(draws), w.size))
    kn = stat(sample)
    bias = float(kn.mean() - stat(smooth))
    return MaxSelection(printed, printed - bias, float(kn.std(ddof=1)), bias, deg)

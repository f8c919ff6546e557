"""JJF 2014—2022 clause 7.2 formulas and appendix B budgets, as pure functions on numbers.

Units are those named in each docstring: input rates Ω in °/s, outputs F in mV, scale
factors K in mV/[(°)/s], biases in °/s unless stated.  The procedures convert at the
boundary.  Shared maths comes from :mod:`metro.core` (lsq, allan, sinefit).
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence

import attrs
import numpy as np
from metro.api import allan, fit_linear, rounding_mean_bound  # core.stats.quantization

#: Earth rotation rate in °/h, as GB/T 45570 D.40 prints it (JJF 2014 has no earth term).
EARTH_RATE_DEG_PER_H = 15.041


# ------------------------------------------------------------------ 7.2.1 scale factor


@attrs.frozen
class LineFit:
    """Result of the eq. (3)–(5) fit F_i = K·Ω_i + F_0 + v_i."""

    K: float
    F0: float
    u_K: float  # standard error of K from the residuals (s/√Σ(Ω−Ω̄)²)
    u_F0: float
    residuals: np.ndarray  # v_i = F_i − (KΩ_i + F_0)
    dof: int

    def predict(self, omega) -> np.ndarray:
        """F̂_i = K·Ω_i + F_0, eq. (6)."""
        return self.K * np.asarray(omega, dtype=float) + self.F0


def mean_output_eq2(samples: Sequence[float]) -> float:
    """F̄_i = (1/N) Σ F_iP, eq. (2) (mV)."""
    a = np.asarray(samples, dtype=float)
    if a.size < 1:
        raise ValueError("eq. (2) needs at least one sample")
    return float(np.mean(a))


def scale_factor_eq4_5(omega: Sequence[float], F: Sequence[float]) -> LineFit:
    """Least-squares K and F_0 of the linear model eq. (3), JJF 2014 7.2.1.2 eqs. (4), (5)::

        K   = [n ΣΩ_iF_i − ΣΩ_i ΣF_i] / [n ΣΩ_i² − (ΣΩ_i)²]
        F_0 = (1/n) ΣF_i − (K/n) ΣΩ_i

    evaluated in the algebraically identical centred form K = Σ(Ω−Ω̄)(F−F̄)/Σ(Ω−Ω̄)²
    (no cancellation of large sums).  Standard errors from the residual variance
    s² = Σv_i²/(n − 2): u(K) = s/√Σ(Ω−Ω̄)², u(F_0) = s·√(1/n + Ω̄²/Σ(Ω−Ω̄)²).

    :param omega: input rates Ω_i (°/s), at least 3, not all equal.
    :param F: mean outputs F̄_i (mV).
    """
    om = np.asarray(omega, dtype=float)
    f = np.asarray(F, dtype=float)
    if om.shape != f.shape or om.ndim != 1:
        raise ValueError("Ω and F must be 1-D of the same length")
    if om.size < 3:
        raise ValueError("eq. (4) needs at least 3 input rates for a fit with an uncertainty, got "
                         f"{om.size}")
    if not (np.all(np.isfinite(om)) and np.all(np.isfinite(f))):
        raise ValueError("Ω or F is not finite")
    ob, fb = om.mean(), f.mean()
    sxx = float(np.sum((om - ob) ** 2))
    if sxx == 0.0:
        raise ValueError("all input rates are equal: K is undefined (eq. (4) denominator is zero)")
    K = float(np.sum((om - ob) * (f - fb)) / sxx)
    F0 = float(fb - K * ob)
    v = f - (K * om + F0)
    dof = om.size - 2
    s = math.sqrt(float(v @ v) / dof)
    return LineFit(K, F0, s / math.sqrt(sxx), s * math.sqrt(1.0 / om.size + ob * ob / sxx), v, dof)


# ------------------------------------------------------------------ 7.2.2 – 7.2.4


def nonlinearity_eq7_8(omega: Sequence[float], F: Sequence[float],
                       fit: LineFit) -> tuple[np.ndarray, float]:
    """Point deviations a_i = (F̂_i − F_i)/(K·|Ω_max+ − Ω_max−|), eq. (7), and
    K_n = |a_i|_max, eq. (8).  Ω_max+ / Ω_max− are the largest forward / reverse rates."""
    om = np.asarray(omega, dtype=float)
    f = np.asarray(F, dtype=float)
    if not (np.any(om > 0) and np.any(om < 0)):
        raise ValueError("eq. (7) needs forward (Ω > 0) and reverse (Ω < 0) rates")
    span = abs(om.max() - om.min())
    a = (fit.predict(om) - f) / (fit.K * span)
    return a, float(np.max(np.abs(a)))


def range_from_nonlinearity(omega: Sequence[float], F: Sequence[float],
                            limit: float) -> tuple[float | None, float]:
    """The range (7.2.2.2, last paragraph): the largest input rate Ω_m such that the
    eq. (4)–(8) nonlinearity of the points with |Ω| ≤ Ω_m meets ``limit``.

    Returns (Ω_m or None if no range meets it, K_n over that range)."""
    om = np.asarray(omega, dtype=float)
    f = np.asarray(F, dtype=float)
    for top in np.unique(np.abs(om))[::-1]:
        sel = np.abs(om) <= top
        if sel.sum() < 3 or not (np.any(om[sel] > 0) and np.any(om[sel] < 0)):
            break
        fit = scale_factor_eq4_5(om[sel], f[sel])
        _, kn = nonlinearity_eq7_8(om[sel], f[sel], fit)
        if kn <= limit:
            return float(top), kn
    return None, float("nan")


def asymmetry_eq9(K_plus: float, K_minus: float, K: float) -> float:
    """K_a = |K_+ − K_−| / K, eq. (9)."""
    if K == 0:
        raise ValueError("K = 0")
    return abs(K_plus - K_minus) / abs(K)


def relative_repeatability_eq10(K: Sequence[float]) -> float:
    """K_r = s(K_i)/|K̄| (Bessel), eq. (10): a repeatability is a magnitude, whatever the sign of K
    (a device whose output falls with the rate has K < 0; docs/independent-campaigns.md)."""
    k = np.asarray(K, dtype=float)
    if k.size < 2:
        raise ValueError(f"eq. (10) needs Q ≥ 2 calibrations, got {k.size}")
    return float(np.std(k, ddof=1) / abs(np.mean(k)))


# ------------------------------------------------------------------ 7.2.5 – 7.2.8, 7.2.16 – 7.2.19


def sf_temperature_eq11(K: Sequence[float], T: Sequence[float], m: int) -> tuple[float, int]:
    """K_t = max_i |(K_i − K_m)/(K_m (T_i − T_m))|, eq. (11) (1/°C); returns (K_t, argmax i).
    ``m`` is the index of the room-temperature point."""
    k = np.asarray(K, dtype=float)
    t = np.asarray(T, dtype=float)
    vals = [(abs((k[i] - k[m]) / (k[m] * (t[i] - t[m]))), i) for i in range(k.size) if i != m]
    if not vals:
        raise ValueError("eq. (11) needs at least one temperature point besides room temperature")
    if any(t[i] == t[m] for i in range(k.size) if i != m):
        raise ValueError("two temperature points equal room temperature: T_i − T_m = 0 in eq. (11)")
    return max(vals)


def bias_temperature_eq31(B: Sequence[float], T: Sequence[float], m: int) -> tuple[float, int]:
    """B_t = max_i |(B_0i − B_0m)/(T_i − T_m)|, eq. (31); returns (B_t, argmax i)."""
    b = np.asarray(B, dtype=float)
    t = np.asarray(T, dtype=float)
    if any(t[i] == t[m] for i in range(b.size) if i != m):
        raise ValueError("two temperature points equal room temperature: T_i − T_m = 0 in eq. (31)")
    vals = [(abs((b[i] - b[m]) / (t[i] - t[m])), i) for i in range(b.size) if i != m]
    if not vals:
        raise ValueError("eq. (31) needs at least one temperature point besides room temperature")
    return max(vals)


def per_g_726(up: float, down: float) -> float:
    """7.2.6.2 / 7.2.17.2: (value with the axis up − value with it down) / 2 g (per g)."""
    return (up - down) / 2.0


def max_change_eq12_13(before: Mapping[str, float],
                       after: Mapping[str, float]) -> tuple[float, str, dict]:
    """ΔK_j = |K_j2 − K_j1| per axis j (eq. (12)/(14)/(32)/(33)) and the maximum over the
    axes (eq. (13)/(15), 7.2.18.2/7.2.19.2 last sentence); returns (max, its axis, per axis)."""
    axes = [a for a in before if a in after]
    if not axes:
        raise ValueError("no axis has both a before and an after value")
    d = {a: abs(after[a] - before[a]) for a in axes}
    worst = max(d, key=d.get)
    return d[worst], worst, d


# ------------------------------------------------------------------ 7.2.9, 7.2.10


def threshold_eq16_17(omega_desc: Sequence[float], F_cal: Sequence[float],
                      K: float) -> tuple[float | None, int]:
    """Candidate threshold of one direction, eqs. (16), (17).

    Rates are taken in the order applied (decreasing |Ω|); F̂_i = K·Ω_i (eq. (16)); a rate
    meets eq. (17) when |(F̂_i − F_i)/F̂_i| ≤ 50 %.  The candidate is the last rate of the
    unbroken run of rates, from the largest down, that meet it (interpretations.md).
    Returns (candidate or None if the largest rate already fails, index of the candidate)."""
    om = np.asarray(omega_desc, dtype=float)
    f = np.asarray(F_cal, dtype=float)
    if np.any(np.diff(np.abs(om)) >= 0):
        raise ValueError("threshold rates must be strictly decreasing in magnitude")
    ok = np.abs((K * om - f) / (K * om)) <= 0.5
    if not ok[0]:
        return None, -1
    i = int(np.argmin(ok)) - 1 if not ok.all() else om.size - 1
    return float(om[i]), i


def resolution_eq18(increments_desc: Sequence[float], dF: Sequence[float],
                    K: float) -> tuple[float | None, int]:
    """Candidate resolution of one direction, eq. (18): ΔF̂_i = K·ΔΩ_i (slope of eq. (6));
    an increment meets it when |(ΔF̂_i − ΔF_i)/ΔF̂_i| ≤ 50 %; same run rule as eq. (17)."""
    return threshold_eq16_17(increments_desc, dF, K)


def resolved_bracket(omega_desc: Sequence[float], F_cal: Sequence[float], K: float,
                     u: Sequence[float],
                     k: float = 2.0) -> tuple[int, int | None, int] | None:
    """Where the threshold (eq. (17)) or resolution (eq. (18)) lies when each response F_i has a
    standard uncertainty u_i (issue 13: a level counts only if its pass is resolved from the noise).

    d_i = |F̂_i − F_i| − 50 %·|F̂_i| (F̂_i = K·Ω_i) passes at d_i ≤ 0; the pass is *resolved* at
    d_i ≤ −k·u_i, a fail at d_i ≥ k·u_i.  The standard's candidate is the last level i of the
    unbroken run of passes (:func:`threshold_eq16_17`).  The true value is at most the smallest
    level h ≤ i whose pass is resolved, and above the largest level below h whose fail is resolved
    (0 when none is): (Ω_lo, Ω_h]. Returns (h, lo index or None, i), or None when no level of the
    run passes resolved."""
    om = np.asarray(omega_desc, dtype=float)
    f = np.asarray(F_cal, dtype=float)
    uu = np.asarray(u, dtype=float)
    c, i = threshold_eq16_17(om, f, K)
    if c is None:
        return None
    d = np.abs(K * om - f) - 0.5 * np.abs(K * om)
    passed = [j for j in range(i + 1) if d[j] <= -k * uu[j]]
    if not passed:
        return None
    h = max(passed)
    lo = next((j for j in range(h + 1, om.size) if d[j] >= k * uu[j]), None)
    return h, lo, i


# ------------------------------------------------------------------ 7.2.11, 7.2.12


def misalignment_eq19_25(F: Mapping[tuple[int, str], float], omega: float,
                         K: float) -> dict[str, float]:
    """Input-axis misalignment, eqs. (19)–(25).

    ``F[(p, '+')]``/``F[(p, '-')]`` are the mean outputs (mV) at mounting position p = 1…4 with
    the table turning forward/reverse at Ω_(+) = ``omega`` (°/s); K in mV/[(°)/s].
    δ_p = (F_p+ − F_p−)/(2Ω_(+)K) (19), (20), (22), (23); α_m = (δ1 − δ2)/2 (21);
    β_m = (δ3 − δ4)/2 (24); γ_m = 10800·√(α_m² + β_m²)/π in ′ (25)."""
    if omega == 0 or K == 0:
        raise ValueError("Ω_(+) and K must be non-zero")
    d = {p: (F[(p, "+")] - F[(p, "-")]) / (2.0 * omega * K) for p in (1, 2, 3, 4)}
    alpha = (d[1] - d[2]) / 2.0
    beta = (d[3] - d[4]) / 2.0
    gamma = 10800.0 * math.hypot(alpha, beta) / math.pi
    return {"delta1": d[1], "delta2": d[2], "delta3": d[3], "delta4": d[4],
            "alpha": alpha, "beta": beta, "gamma": gamma}


def std_bessel(values: Sequence[float], clause: str = "eq. (26)/(30)", min_q: int = 2) -> float:
    """Bessel standard deviation [Σ(x_i − x̄)²/(Q − 1)]^½, eqs. (26), (30)."""
    x = np.asarray(values, dtype=float)
    if x.size < min_q:
        raise ValueError(f"{clause} needs Q ≥ {min_q} values, got {x.size}")
    return float(np.std(x, ddof=1))


# ------------------------------------------------------------------ 7.2.13 – 7.2.15


def bias_eq27_28(F: Sequence[float], K: float) -> float:
    """B_0 = F̄/K with F̄ = (1/N)ΣF_i, eqs. (27), (28) (°/s for K in mV/[(°)/s])."""
    return mean_output_eq2(F) / K


def bias_stability_eq29(F: Sequence[float], K: float, P: int) -> tuple[float, int]:
    """B_s = (1/K)·[Σ(F̄_i − F̄)²/(N/P − 1)]^½ over the N/P averages of P samples, eq. (29).
    An incomplete last block is dropped.  Returns (B_s, number of averages)."""
    f = np.asarray(F, dtype=float)
    if P < 1:
        raise ValueError("the averaging period P must be ≥ 1 sample")
    m = f.size // P
    if m < 2:
        raise ValueError(f"eq. (29) needs at least 2 averages of {P} samples; the record has "
                         f"{f.size} samples")
    means = f[: m * P].reshape(m, P).mean(axis=1)
    return float(np.std(means, ddof=1) / abs(K)), m


# ------------------------------------------------------------------ 7.2.20 Allan variance


#: exponents m of eq. (38) and the name of each term
ALLAN_TERMS = ((-2, "quantization"), (-1, "angle random walk"), (0, "bias instability"),
               (1, "rate random walk"), (2, "rate ramp"))


@attrs.frozen
class AllanFit:
    """Result of the eq. (38) fit σ²(τ) = Σ A_m τ^m (τ in h, σ in °/h)."""

    A: np.ndarray  # A_-2 … A_2 as fitted (0 for a term removed by the non-negative variant)
    u_A: np.ndarray  # standard uncertainties (unconstrained value's u for a dropped term)
    raw: np.ndarray  # unconstrained estimates
    active: np.ndarray  # bool per term: kept and ≥ 0 (a False term is reported "not resolved")
    chi2: float
    dof: int
    birge: float

    def model(self, tau_h) -> np.ndarray:
        """The fitted σ²(τ) (with every coefficient as fitted, negative ones included)."""
        t = np.asarray(tau_h, dtype=float)
        return sum(self.A[i] * t ** m for i, (m, _) in enumerate(ALLAN_TERMS))


def allan_covariance(A: Sequence[float], tau_h: np.ndarray, n_samples: int,
                     tau0_h: float) -> np.ndarray:
    """Covariance of the σ̂²(τ_k) (overlapping Allan variance, 7.2.20) used as the eq. (38) fit's
    weights, for the noise the fitted model says is there.

    Eq. (38)'s terms are independent noises — A₋₂τ⁻² quantization (white angle), A₋₁τ⁻¹ angle random
    walk, A₀ bias instability (flicker rate), A₁τ rate random walk — and a rate ramp A₂τ²;
    :func:`metro.core.stats.allan.oadev_covariance` gives the exact Gaussian covariance of the
    estimates for that mix (generalized autocovariances, C. A. Greenhall, TMO Progress Report
    42-137, 1999), with A_m ≥ 0 (a negative term counts as 0).  So the correlation between octave
    levels follows the noise that dominates there: ≈ 0.5 (adjacent) where white rate noise does, ≈
    0.69 for flicker, ≈ 0.89 for rate random walk, ≈ 0.40 (and 0.51 two apart) for quantization —
    what repeated records show (tests/core/stats/test_allan_covariance.py, interpretations.md
    "7.2.20 — weighting").

    :param A: A₋₂ … A₂ (τ in h, σ in °/h).
    :param tau_h: the cluster times τ_k = m_k·τ₀ in h.
    :param n_samples: number of samples of the record.
    :param tau0_h: sample interval τ₀ in h."""
    t = np.asarray(tau_h, dtype=float)
    m = np.rint(t / tau0_h).astype(np.int64)
    if np.any(np.abs(m * tau0_h - t) > 1e-6 * t):
        raise ValueError("τ values must be whole multiples of the sample interval τ₀")
    a = np.asarray(A, dtype=float) * tau0_h ** np.array([mm for mm, _ in ALLAN_TERMS], dtype=float)
    return allan.oadev_covariance(int(n_samples), m, a)


def allan_covariance_approx(model_s2: np.ndarray, edf: np.ndarray, tau: np.ndarray) -> np.ndarray:
    """Approximate covariance of the σ̂²(τ_k): the first weights of the eq. (38) fit, before its
    coefficients are known, and the weights when the record length is not given.

    var(σ̂²_k) = 2σ_k⁴/edf_k (χ² law, white-rate-noise edf); between levels the correlation
    √(τ_fine/τ_coarse) — 0.71 between adjacent octaves, 0.5 two apart — between what white rate
    noise (≈ 0.5 adjacent) and rate random walk (≈ 0.89) give.  Capped at 0.95."""
    s2 = np.asarray(model_s2, dtype=float)
    e = np.asarray(edf, dtype=float)
    d = np.sqrt(2.0 / e) * s2
    t = np.asarray(tau, dtype=float)
    R = np.minimum(np.sqrt(np.minimum.outer(t, t) / np.maximum.outer(t, t)), 0.95)
    np.fill_diagonal(R, 1.0)
    return R * np.outer(d, d)


def _allan_wls(tau_h, s2, cov, active):
    cols = [tau_h ** m for (m, _), a in zip(ALLAN_TERMS, active) if a]
    A = np.column_stack(cols)
    return fit_linear(A, s2, cov_y=cov, scale_cov=False), A


def fit_allan_eq38(tau_h: Sequence[float], sigma: Sequence[float], edf: Sequence[float], *,
                   n_samples: int | None = None, tau0_h: float | None = None,
                   iterations: int = 4, nonnegative: bool = False) -> AllanFit:
    """Generalised least-squares fit of eq. (38), σ²(τ) = Σ_{m=−2}^{2} A_m τ^m.

    Weights: with the record's ``n_samples`` and ``tau0_h``, the covariance of the σ̂²(τ) for the
    noise mix of the fitted model (:func:`allan_covariance`), iterated with the fit (start: the
    approximate :func:`allan_covariance_approx` on the observations); without them, the
    approximate covariance (2σ⁴/edf, correlation √(τ ratio)) with σ² from the model, iterated.
    Covariance of A = (AᵀC⁻¹A)⁻¹, scaled by χ²/ν when that exceeds 1 (Birge ratio).
    A coefficient that comes out negative is not physical.  Default (``nonnegative=False``):
    all five estimates are kept as fitted (unbiased; ``active`` flags the non-negative ones)
    and the caller reports a negative one as "not resolved".  With ``nonnegative=True`` the
    negative term is removed and the fit repeated (active-set non-negative least squares)
    until all kept terms are ≥ 0; a removed term is 0 with the standard uncertainty of its
    all-terms estimate.  The constraint biases the kept terms (ARW low by ≈ 0.7 u on white
    noise), which is why it is not the default (interpretations.md, "7.2.20 weighting and
    negative coefficients").

    :param tau_h: cluster times τ in hours (≥ 6 values).
    :param sigma: Allan deviations σ(τ) in °/h.
    :param edf: equivalent degrees of freedom of each σ²(τ) (the start of the iteration).
    :param n_samples: samples in the record (with ``tau0_h``: exact covariance for the model's
    noise).
    :param tau0_h: sample interval in h.
    """
    t = np.asarray(tau_h, dtype=float)
    s = np.asarray(sigma, dtype=float)
    e = np.asarray(edf, dtype=float)
    if not (t.size == s.size == e.size):
        raise ValueError("τ, σ and edf must have the same length")
    if t.size < 6:
        raise ValueError(f"eq. (38) has 5 coefficients and needs at least 6 τ values, got {t.size}")
    if np.any(~(s > 0)) or not np.all(np.isfinite(s)):
        raise ValueError("σ(τ) must be positive and finite (constant or zero-variance data?)")
    s2 = s**2
    active = np.ones(5, dtype=bool)
    raw = None
    raw_u = None
    exact = n_samples is not None and tau0_h is not None

    def weights(model, coef):
        if exact:
            full = np.zeros(5)
            full[active] = coef
            if np.all(sum(max(full[i], 0.0) * t**mm for i, (mm, _) in enumerate(ALLAN_TERMS)) > 0):
                return allan_covariance(full, t, n_samples, tau0_h)
        return allan_covariance_approx(model, e, t)

    for _ in range(5):
        model = s2.copy()
        cov = allan_covariance_approx(model, e, t)
        for it in range(max(1, iterations)):
            fit, A = _allan_wls(t, s2, cov, active)
            if it == max(1, iterations) - 1:
                break
            pred = A @ fit.coef
            model = np.where(pred > 0, pred, s2)
            cov = weights(model, np.asarray(fit.coef, dtype=float))
        if raw is None:
            raw, raw_u = np.asarray(fit.coef, dtype=float), np.sqrt(np.diag(fit.cov))
        coef = np.zeros(5)
        coef[active] = fit.coef
        if not nonnegative or np.all(coef[active] >= 0):
            break
        neg = np.flatnonzero(active)[np.argmin(np.where(coef[active] < 0, coef[active] / np.maximum(
            np.sqrt(np.diag(fit.cov)), 1e-300), np.inf))]
        active[neg] = False
        if not active.any():
            raise ValueError("every coefficient of eq. (38) came out negative")
    r = s2 - A @ fit.coef
    chi2 = float(r @ np.linalg.solve(cov, r))
    dof = t.size - int(active.sum())
    birge = math.sqrt(chi2 / dof) if dof > 0 and chi2 > dof else 1.0
    u = np.zeros(5)
    u[active] = np.sqrt(np.diag(fit.cov)) * birge
    u[~active] = np.asarray(raw_u)[~active] * birge
    raw_full = np.asarray(raw)
    if not nonnegative:
        active = coef >= 0
    return AllanFit(coef, u, raw_full, active.copy(), chi2, dof, birge)


def noise_coefficients(A: Sequence[float]) -> dict[str, float]:
    """IEEE Std 952 coefficients from the eq. (38) A_m (τ in h, σ in °/h):

    * quantization Q = √(A_−2/3)     (°; σ² = 3Q²/τ²)
    * ARW N = √A_−1                   (°/√h; eq. (39))
    * bias instability B = √(A_0·π/(2 ln 2))   (°/h; σ² = (2 ln 2/π)B²)
    * rate random walk K = √(3A_1)    (°/h/√h; σ² = K²τ/3)
    * rate ramp R = √(2A_2)           (°/h²; σ² = R²τ²/2)
    """
    a = np.clip(np.asarray(A, dtype=float), 0.0, None)
    return {"Q": math.sqrt(a[0] / 3.0), "N": math.sqrt(a[1]),
            "B": math.sqrt(a[2] * math.pi / (2 * math.log(2))), "K": math.sqrt(3 * a[3]),
            "R": math.sqrt(2 * a[4])}


#: d(coefficient)/d(A_m) factor c in coefficient = √(c·A): u(coef) = c·u(A)/(2·coef)
NOISE_FACTORS = (1.0 / 3.0, 1.0, math.pi / (2 * math.log(2)), 3.0, 2.0)


def coefficient_u(A: float, u_A: float, c: float, k: float = 2.0) -> tuple[float, str]:
    """Standard uncertainty of a noise coefficient √(c·A) (:func:`noise_coefficients`) from the
    fitted A and u(A), and how it was obtained (7.2.20, interpretations.md).

    The A ± k·u(A) interval is mapped through the monotone √(c·max(A, 0)) and the larger
    distance from the reported value to an end of the mapped interval is taken as k·u.  When A
    is many u(A) above 0 this is the linear c·u(A)/(2√(cA)) to first order; near 0 the linearisation
    collapses (u → small as the value → 0) while the mapped interval still reaches 0, which is
    what keeps a barely resolved coefficient's interval honest.  A negative A (reported as 0):
    the upper end √(c·(A + k·u)), or √(c·u(A)) when even that is negative."""
    val = math.sqrt(c * A) if A > 0 else 0.0
    lo = math.sqrt(c * max(A - k * u_A, 0.0))
    hi = math.sqrt(c * max(A + k * u_A, 0.0))
    if A > 0:
        return max(val - lo, hi - val) / k, "k·u(A) interval of A mapped through √(c·A)"
    return max(hi,
               math.sqrt(c * u_A)) / k, "A ≤ 0, reported 0: k·u = max(√(c·(A + k·u(A))), √(c·u(A)))"


def not_resolved_bound(A: float, u_A: float, c: float, k: float = 3.0) -> float:
    """Upper bound √(c·max(A + k·u(A), 0)) on a noise coefficient √(c·A) whose eq. (38) term is not
    resolved from 0 (7.2.20, A − 3u ≤ 0; interpretations.md, "7.2.20 — the other four
    coefficients").

    One-sided, k = 3: the estimate of a long-τ term is skewed — when it comes out low, the u(A) of
    the fitted model comes out low with it — so A + 2u lay below the true A₁ in 8–10 % of 1 h
    records dominated by rate random walk (Monte Carlo, 300 records;
    tests/core/stats/test_allan_covariance.py), A + 3u in 3.3 %."""
    return math.sqrt(c * max(A + k * u_A, 0.0))


def arw_eq39(A_minus1: float) -> float:
    """ARW = √A_−1, eq. (39)."""
    if not A_minus1 > 0:
        raise ValueError(f"A_−1 = {A_minus1:g} is not positive, so ARW = √A_−1 (eq. (39)) is "
                         "undefined")
    return math.sqrt(A_minus1)


# ------------------------------------------------------------------ 7.2.21, 7.2.22


def bandwidth_fit_743(f: Sequence[float], Kr: Sequence[float], level: float = 0.707,
                      quartic: bool = False) -> tuple[float, np.ndarray, np.ndarray]:
    """Curve fit of the N + 1 sensitivity ratios (7.2.21.2, after eq. (43)) and its 0.707 point.

    The curve is the amplitude response of the first-order model of eq. (46),
    K(f) = 1/√(a + b f²), fitted as the straight line 1/K_i² = a + b·f_i² through the N
    measured ratios and the zero-frequency point (0, 1).  f_c solves K(f_c) = ``level``:
    f_c = √((1/level² − a)/b).  With ``quartic`` the curve is 1/K² = a + b f² + c f⁴, which a
    second-order response |H|⁻² = 1 + (4ζ² − 2)(f/f_n)² + (f/f_n)⁴ (times any pure delay) follows
    exactly (interpretations.md, "7.2.21 — a response that is not first order"); f_c is then the
    lowest f² > 0 where the curve reaches 1/level².  Returns (f_c, coefficients (a, b[, c]), their
    covariance)."""
    ff = np.asarray(f, dtype=float)
    k = np.asarray(Kr, dtype=float)
    if np.any(~(k > 0)):
        raise ValueError("sensitivity ratios must be positive")
    x = np.concatenate([[0.0], ff**2])
    y = np.concatenate([[1.0], 1.0 / k**2])
    cols = [np.ones_like(x), x] + ([x * x] if quartic else [])
    fit = fit_linear(np.column_stack(cols), y)
    coef = np.asarray(fit.coef, dtype=float)
    target = 1.0 / level**2
    if not quartic:
        a, b = (float(c) for c in coef)
        if not b > 0:
            raise ValueError("the fitted amplitude curve does not fall with frequency (b ≤ 0): no "
                             "0.707 point")
        q = (target - a) / b
        if not q > 0:
            raise ValueError("the fitted curve is below 0.707 already at 0 Hz")
        return math.sqrt(q), coef, np.asarray(fit.cov)
    a, b, c = (float(v) for v in coef)
    if not a < target:
        raise ValueError("the fitted curve is below 0.707 already at 0 Hz")
    roots = (np.roots([c, b, a - target]) if c != 0
             else np.array([(target - a) / b]) if b != 0 else np.array([]))
    pos = sorted(float(r.real) for r in np.atleast_1d(roots)
                 if abs(r.imag) < 1e-12 * max(1.0, abs(r.real)) and r.real > 0)
    if not pos:
        raise ValueError("the fitted amplitude curve never falls to 0.707")
    return math.sqrt(pos[0]), coef, np.asarray(fit.cov)


def delay_eq48_50(omega: Sequence[float], P: Sequence[float],
                  T: float) -> tuple[float, float, np.ndarray]:
    """Output delay T_d by least squares, eqs. (48)–(50)::

        y_i = −P_i − atan(ω_i T) = ω_i T_d,   T_d = (ΩΩᵀ)⁻¹ Ω y

    :param omega: angular frequencies ω_i (rad/s).
    :param P: phase delays P_i = φ̄_i − φ_0 (rad; negative for a lag), unwrapped.
    :param T: time constant T = 1/(2π B_w), eq. (47) (s).
    :return: (T_d in s, its standard error from the residuals, residuals y − ωT_d)."""
    w = np.asarray(omega, dtype=float)
    p = np.asarray(P, dtype=float)
    if w.size < 2:
        raise ValueError("eq. (50) needs at least 2 frequencies")
    y = -p - np.arctan(w * T)
    Td = float(w @ y / (w @ w))
    r = y - w * Td
    s = math.sqrt(float(r @ r) / (w.size - 1))
    return Td, s / math.sqrt(float(w @ w)), r


# ------------------------------------------------------------------ 7.2.23


def settle_time(t: Sequence[float], x: Sequence[float], target: float, tol: float) -> float:
    """7.2.23.2: time from power-on until x stays within target ± tol (the first sample
    after the last sample outside).  Returns the time of that sample; raises if x never
    settles (the last sample is outside)."""
    tt = np.asarray(t, dtype=float)
    xx = np.asarray(x, dtype=float)
    out = np.abs(xx - target) > tol
    if out[-1]:
        raise ValueError("the output is still outside the tolerance at the end of the record")
    if not out.any():
        return float(tt[0])
    return float(tt[int(np.flatnonzero(out)[-1]) + 1])


def startup_sample_exits(d: Sequence[float], t: Sequence[float], dt: float, upper: float,
                         lower: float, sigma: float,
                         lobes: Sequence, chain: Mapping) -> dict:
    """7.2.23.2 on the samples of an output that rings: the distribution of the start-up time (the
    first sample after the last one outside the band) over the candidate lobes of
    :func:`metro.core.stats.settling.last_exit` (``chain``; its ``lobes`` index ``lobes``, its
    ``probabilities`` P_i are those of lobe i being the last real one).  Within lobe i the
    noise-free output falls from its top (sample k) back into the band once: the last sample
    outside is sample j ≥ k with probability ∝ Π_{k≤i≤j} q_i·Π_{i>j}(1 − q_i) (a change point), q_i
    = Φ((s·d_i − edge)/σ) (the noise-free sample i outside its edge, s the lobe's sign, edge
    ``upper`` or ``lower``); its exit is the next sample, t_j + dt (interpretations.md, "7.2.23 — a
    ringing output decided by its samples").  Over all candidates:

        t = Σ W_m·x_m,   u_sel = √(Σ W_m·(x_m − t)²),   d_95: the distance from t within which Σ
        W_m ≥ 95 %.

    :return: ``t``, ``u_selection``, ``d95`` (s), and per candidate lobe its total probability and
    mean exit
        (``lobe_probabilities``, ``lobe_exits``).
    """
    from scipy.special import ndtr

    d = np.asarray(d, dtype=float)
    t = np.asarray(t, dtype=float)
    xs, ws, lobe_p, lobe_x = [], [], [], []
    n_lobes = len(chain["lobes"])
    for m, P in enumerate(chain["probabilities"]):
        if m >= n_lobes:  # no lobe certain: inside from the first sample with the probability left
            xs.append(chain["exits"][m]), ws.append(P)
            lobe_p.append(P), lobe_x.append(chain["exits"][m])
            continue
        lb = lobes[chain["lobes"][m]]
        edge = upper if lb.sign > 0 else lower
        k = lb.start + int(np.argmax(lb.sign * d[lb.start:lb.end]))
        q = np.clip(ndtr((lb.sign * d[k:lb.end] - edge) / max(sigma, 1e-12)), 1e-300, 1.0 - 1e-16)
        # log of Π_{i≤j} q_i · Π_{i>j} (1 − q_i) for j = k … end − 1
        logw = np.cumsum(np.log(q)) + np.concatenate((np.cumsum(np.log1p(-q)[::-1])[::-1][1:],
                                                      [0.0]))
        w = np.exp(logw - float(np.max(logw)))
        w = w / float(w.sum())
        j = np.arange(k, lb.end)
        x = np.where(j + 1 < t.size, t[np.minimum(j + 1, t.size - 1)], t[-1] + dt)
        xs.extend(x.tolist()), ws.extend((P * w).tolist())
        lobe_p.append(P), lobe_x.append(float(w @ x))
    x, w = np.asarray(xs), np.asarray(ws)
    w = w / float(w.sum())
    ts = float(w @ x)
    order = np.argsort(np.abs(x - ts), kind="stable")
    cum = np.cumsum(w[order])
    d95 = float(np.abs(x - ts)[order][min(int(np.searchsorted(cum, 0.95 - 1e-12)), x.size - 1)])
    return {"t": ts, "u_selection": float(math.sqrt(max(float(w @ (x - ts) ** 2), 0.0))),
            "d95": d95,
            "lobe_probabilities": lobe_p, "lobe_exits": lobe_x}


# ------------------------------------------------------------------ appendix B


# ------------------------------------------------------------------------------- output
# quantization (not in the standard: the budget rows of the results read from a digitised output
# need them; interpretations.md, "JJF 2014 — output quantization")


def rounding_half_width(q: float, s: float) -> tuple[float, bool]:
    """Half-width of the rounding offset of a mean of samples rounded to q whose measured standard
    deviation is s: (half-width, dithered).  The noise dithers the rounding when s ≥ q/2 (where
    Sheppard's correction σ² = s² − q²/12 recovers the noise before rounding): the Widrow bound of
    :func:`rounding_mean_bound` at that σ; otherwise ±q/2, the rounding of one sample."""
    if q <= 0:
        return 0.0, True
    if s >= q / 2.0:
        return rounding_mean_bound(q, math.sqrt(max(s * s - q * q / 12.0, 0.0))), True
    return q / 2.0, False


def appendix_b_presentation(u_c: float, k: float = 2.0) -> tuple[str, str]:
    """Appendix B's way of writing the result: u_c rounded to three significant digits and
    U = k × that rounded u_c, printed without trailing zeros (B.1.3/B.1.4: 1.65×10⁻⁴ → 3.3×10⁻⁴;
    B.2.3/B.2.4: 1.68×10⁻⁴ → 3.36×10⁻⁴).  Returns (u_c text, U text) in 'd.dd×10⁻ⁿ' form."""
    def sci(x: float, digits: int) -> str:
        e = math.floor(math.log10(abs(x)))
        m = round(x / 10**e, digits - 1)
        if m >= 10:
            m, e = m / 10, e + 1
        txt = f"{m:.{digits - 1}f}".rstrip("0").rstrip(".")
        return f"{txt}×10^{e}"
    e = math.floor(math.log10(u_c))
    uc3 = round(u_c / 10**e, 2) * 10**e
    return sci(uc3, 3), sci(k * uc3, 3)

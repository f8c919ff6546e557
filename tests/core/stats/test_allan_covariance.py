"""Covariance of overlapping Allan variance estimates at several τ
(metro.core.stats.allan.oadev_covariance) and its use as the weights of the JJF 2014 7.2.20 eq. (38)
fit (plugins/jjf2014/formulas.allan_covariance).

References: white FM and white PM — an independent exact computation, the covariance of two Gaussian
quadratic forms Cov(yᵀAy, yᵀBy) = 2 tr(AΣBΣ) with explicit matrices (tolerance 1e-9 relative,
rounding only). Flicker and rate-random-walk noise — Monte Carlo with the simulator's own generators
(metro.instruments.vibratory), the tolerance being 4 standard errors of the sampled correlation ((1
− ρ²)/√R) or of the sampled standard deviation (1/√(2R)).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from metro.core.stats import allan
from metro.instruments.vibratory import VibratoryTruth, static_noise
from metro.plugins.jjf2014 import formulas as F


def _oavar_matrix(n: int, m: int) -> np.ndarray:
    """σ̂²(m) of :func:`allan.oadev` as the quadratic form yᵀMy (mean removed, x = cumulative
    sum)."""
    P = np.eye(n) - 1.0 / n
    L = np.tril(np.ones((n + 1, n)), -1)  # x_0 = 0, x_{i+1} = x_i + y_i
    T = n - 2 * m + 1
    D = np.zeros((T, n + 1))
    for j in range(T):
        D[j, j], D[j, j + m], D[j, j + 2 * m] = 1.0, -2.0, 1.0
    G = D @ L @ P
    return G.T @ G / (2.0 * m * m * T)


def test_white_fm_and_white_pm_covariance_is_the_exact_quadratic_form_covariance():
    n, ms = 40, [1, 2, 4, 8]
    s2, q2 = 0.7, 0.2  # white FM: var(y_i) = s2; white PM: θ_i i.i.d. var q2, y_i = θ_{i+1} − θ_i
    Sigma = s2 * np.eye(n) + q2 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    Ms = [_oavar_matrix(n, m) for m in ms]
    brute = np.array([[2.0 * np.trace(A @ Sigma @ B @ Sigma) for B in Ms] for A in Ms])
    means = np.array([np.trace(A @ Sigma) for A in Ms])
    a = [3.0 * q2, s2, 0.0, 0.0, 0.0]  # σ²(m) = 3q²/m² + s²/m
    np.testing.assert_allclose(means, [a[0] / m**2 + a[1] / m for m in ms], rtol=1e-12)
    np.testing.assert_allclose(allan.oadev_covariance(n, ms, a), brute, rtol=1e-9)


def test_white_fm_variance_is_the_white_fm_edf():
    """Against core.allan.edf_white_fm's own sum (tolerance 1e-4: both use a midpoint rule on long
    lags)."""
    n, ms = 36000, allan.octave_m(36000)
    C = allan.oadev_covariance(n, ms, [0.0, 1.0, 0.0, 0.0, 0.0])
    np.testing.assert_allclose(2.0 * (1.0 / ms) ** 2 / np.diag(C),
                               allan.edf_white_fm("oadev", n, ms), rtol=1e-4)


def test_ramp_adds_the_cross_term_of_its_constant_second_difference():
    """A ramp alone has no variance; with white FM the estimate's variance gains 4 d² Var(ē) — here
    checked against the explicit quadratic form Σ(d + e_j)²: Var = Var(Σe²) + 4d² Var(Σe)."""
    n, m = 40, 4
    a = [0.0, 1.0, 0.0, 0.0, 0.01]
    d = m * m * math.sqrt(2 * a[4])
    T = n - 2 * m + 1
    M = _oavar_matrix(n, m) * (2.0 * m * m * T)  # Σ e_j² as yᵀMy
    P = np.eye(n) - 1.0 / n
    L = np.tril(np.ones((n + 1, n)), -1)
    s = np.zeros(n + 1)
    for j in range(T):
        s[j] += 1.0
        s[j + m] -= 2.0
        s[j + 2 * m] += 1.0
    g = s @ L @ P  # Σ e_j = gᵀy
    var = 2.0 * np.trace(M @ M) + 4.0 * d * d * (g @ g)
    got = allan.oadev_covariance(n, [m], a)[0, 0]
    assert got == pytest.approx(var / (2.0 * m * m * T) ** 2, rel=1e-9)


def _mc(truth: VibratoryTruth, n: int, ms, reps: int, seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    return np.array([allan.oadev(static_noise(truth, rng, n, 1.0) * 3600.0, 1.0, ms).deviation ** 2
                     for _ in range(reps)])


@pytest.mark.parametrize("kw, A_index, A_of", [
    ({"arw_deg_rt_h": 0.0, "rrw_deg_h_rt_h": 5.0}, 3, lambda t: t.rrw_deg_h_rt_h**2 / 3.0),
    ({"arw_deg_rt_h": 0.0, "bias_instability_deg_h": 1.0}, 2,
     lambda t: 2.0 * math.log(2.0) / math.pi * t.bias_instability_deg_h**2),
])
def test_octave_correlation_for_rrw_and_flicker_matches_monte_carlo(kw, A_index, A_of):
    """Rate random walk: adjacent octaves correlate at ≈ 0.89, flicker ≈ 0.69 (the eq. (38) fit used
    √(τ ratio) = 0.71 for every noise before). 400 records of 4096 samples; levels m = 8 … 256 (away
    from m = 1, 2 where the discrete simulation differs from the continuous-time model)."""
    n, ms, reps = 4096, allan.octave_m(4096), 400
    truth = VibratoryTruth(**kw)
    S = _mc(truth, n, ms, reps, seed=11)
    a = np.zeros(5)
    a[A_index] = A_of(truth) * (1.0 / 3600.0) ** (A_index - 2)  # A_m τ^m with τ in h → per sample
    C = allan.oadev_covariance(n, ms, a)
    sd = np.sqrt(np.diag(C))
    R = C / np.outer(sd, sd)
    E = np.corrcoef(S.T)
    lv = [i for i, m in enumerate(ms) if 8 <= m <= 256]
    for i in lv[:-1]:
        rho = R[i, i + 1]
        assert abs(E[i, i + 1] - rho) <= 4 * (1
                                              - rho**2) / math.sqrt(reps), (ms[i], E[i, i + 1], rho)
    ratio = S[:, lv].std(axis=0) / sd[lv]
    assert np.all(np.abs(ratio - 1.0) <= 4 / math.sqrt(2 * reps)), ratio
    if A_index == 3:
        assert np.mean(np.diag(R, 1)[lv[:-1]]) > 0.85  # far from the old model's 0.71


def test_eq38_weights_follow_the_noise_that_dominates_each_level():
    """F.allan_covariance on the RRW-dominated mix of docs/standards/jjf2014.md (K = 5 °/h/√h, N =
    0.1 °/√h, 1 h at 0.1 s): adjacent correlation ≈ 0.5 where ARW dominates (short τ), ≈ 0.89 where
    RRW does."""
    n, tau0 = 36000, 0.1 / 3600
    ms = allan.octave_m(n)
    C = F.allan_covariance([0.0, 0.01, 0.0, 25.0 / 3, 0.0], ms * tau0, n, tau0)
    sd = np.sqrt(np.diag(C))
    adj = np.diag(C / np.outer(sd, sd), 1)
    assert 0.45 < adj[2] < 0.56  # τ = 0.4 s / 0.8 s: white
    assert adj[-2] > 0.75  # τ = 205 s / 410 s: RRW
    with pytest.raises(ValueError, match="multiples"):
        F.allan_covariance([0, 1, 0, 0, 0], np.array([1.5, 3.0]) * tau0, n, tau0)


def test_eq38_fit_chi2_and_u_match_the_scatter_on_an_rrw_record():
    """With the exact weights the fit's χ² has its expected size (mean χ²/ν ≈ 1; the approximate
    weights gave ≈ 2–3 on this mix, so the Birge ratio scaled u up in most records), and u(A₁)
    matches the scatter of A₁ over 60 records of 8192 samples (tolerance: 4 standard errors of a
    sampled sd)."""
    n, dt = 8192, 0.1
    ms = allan.octave_m(n)
    truth = VibratoryTruth(rrw_deg_h_rt_h=5.0)
    rng = np.random.default_rng(5)
    A1, u1, chi, chi_approx = [], [], [], []
    for _ in range(60):
        ad = allan.oadev(static_noise(truth, rng, n, dt) * 3600.0, dt, ms)
        args = (np.asarray(ad.tau) / 3600, np.asarray(ad.deviation), np.asarray(ad.edf))
        f = F.fit_allan_eq38(*args, n_samples=n, tau0_h=dt / 3600)
        A1.append(f.raw[3])
        u1.append(f.u_A[3] / f.birge)
        chi.append(f.chi2 / f.dof)
        g = F.fit_allan_eq38(*args)
        chi_approx.append(g.chi2 / g.dof)
    assert 0.7 < np.mean(chi) < 1.35
    assert np.mean(chi_approx) > 1.5
    assert abs(np.std(A1) / np.mean(u1) - 1.0) < 4 / math.sqrt(2 * 60)


def test_not_resolved_bound_hand_worked():
    assert F.not_resolved_bound(1.0, 2.0, 3.0) == pytest.approx(math.sqrt(3 * 7))
    assert F.not_resolved_bound(-1.0, 0.2, 3.0) == 0.0


@pytest.mark.slow
def test_not_resolved_bound_covers_an_unresolved_rrw():
    """1 h at 0.1 s, K = 5 °/h/√h over N = 0.1 °/√h (the RRW mix of docs/standards/jjf2014.md): A₁
    is not resolved (A₁/u ≈ 1) and its estimate is skewed. The bound A + 3u lies above the true A₁ =
    K²/3 in ≥ 95 % of 300 records (seen: 96.7 %); A + 2u did not (seen: 90–92 %). About 30 s."""
    n, dt = 36000, 0.1
    ms = allan.octave_m(n)
    truth = VibratoryTruth(rrw_deg_h_rt_h=5.0)
    rng = np.random.default_rng(9)
    above2 = above3 = 0
    reps = 300
    for _ in range(reps):
        ad = allan.oadev(static_noise(truth, rng, n, dt) * 3600.0, dt, ms)
        f = F.fit_allan_eq38(np.asarray(ad.tau) / 3600, np.asarray(ad.deviation),
                             np.asarray(ad.edf),
                             n_samples=n, tau0_h=dt / 3600)
        K = 5.0
        above2 += F.not_resolved_bound(f.raw[3], f.u_A[3], 3.0, k=2.0) >= K
        above3 += F.not_resolved_bound(f.raw[3], f.u_A[3], 3.0) >= K
    assert above3 >= 0.95 * reps
    assert above2 < 0.95 * reps


def _block_matrix(n: int, f: int) -> np.ndarray:
    """The M × n matrix of the block means of f samples (an incomplete tail dropped)."""
    M = n // f
    Bm = np.zeros((M, n))
    for i in range(M):
        Bm[i, i * f:(i + 1) * f] = 1.0 / f
    return Bm


def test_block_variance_dof_is_the_exact_quadratic_form_for_white_noise_and_a_ramp():
    """White FM + white PM + a ramp: against the explicit Gaussian quadratic form of the Bessel
    variance of the block means, E = (tr(CΣ) + μᵀCμ)/(M − 1), Var = (2 tr((CΣ)²) + 4 μᵀCΣCμ)/(M −
    1)², with Σ, μ built from the samples (tolerance 1e-9 relative, rounding only); white FM alone
    gives ν = M − 1 exactly."""
    n, f = 96, 8
    M = n // f
    # white FM var(y_i); white PM θ_i var q2, y_i = θ_{i+1} − θ_i; ramp per sample
    s2, q2, R = 0.7, 0.2, 0.03
    Sigma = s2 * np.eye(n) + q2 * (2 * np.eye(n) - np.eye(n, k=1) - np.eye(n, k=-1))
    Bm = _block_matrix(n, f)
    C = np.eye(M) - 1.0 / M
    S = C @ Bm @ Sigma @ Bm.T @ C
    mu = C @ Bm @ (R * np.arange(n))
    E = np.trace(S) + mu @ mu
    V = 2 * np.trace(S @ S) + 4 * mu @ S @ mu
    nu, e = allan.block_variance_dof(M, f, [3 * q2, s2, 0.0, 0.0, R * R / 2])
    assert e == pytest.approx(E / (M - 1), rel=1e-9)
    assert nu == pytest.approx(2 * E * E / V, rel=1e-9)
    nu_w, e_w = allan.block_variance_dof(M, f, [0.0, s2, 0.0, 0.0, 0.0])
    assert (nu_w, e_w) == (pytest.approx(M - 1, rel=1e-12), pytest.approx(s2 / f, rel=1e-12))


def test_block_variance_dof_matches_monte_carlo_for_flicker_and_random_walk():
    """White + flicker + rate random walk + a ramp (the mix of a 7.2.14 record): E[s²] and ν =
    2E²/Var(s²) of the Bessel variance of 60 block means of 8 samples against 3000 records from this
    test's own generators (white: normal; random walk: a cumulative sum; flicker: 1/f spectrum
    synthesised over 16 × the record and cut to a random window). Tolerances: 4 standard errors of
    the sampled mean (E) and 12 % for ν (the sampled Var(s²) of 3000 draws). The white-noise count M
    − 1 = 59 would be off by a factor ≈ 5."""
    rng = np.random.default_rng(29)
    M, f = 60, 8
    n = M * f
    q, R, fl = 0.02, 0.002, 0.3  # RW step per sample; ramp per sample; flicker Allan plateau
    h = fl * fl / (2 * math.log(2))
    big = 1 << int(math.ceil(math.log2(16 * n)))
    fr = np.fft.rfftfreq(big, 1.0)
    amp = np.zeros_like(fr)
    amp[1:] = np.sqrt(h / fr[1:] / big) / 2 * big

    def flicker():
        x = np.fft.irfft(amp * (rng.standard_normal(fr.size) + 1j * rng.standard_normal(fr.size)),
                         big)
        st = int(rng.integers(0, big - n + 1))
        return x[st:st + n]

    s2 = np.array([np.var((rng.standard_normal(n) + np.cumsum(q * rng.standard_normal(n)) + R
                           * np.arange(n)
                           + flicker()).reshape(M, f).mean(axis=1), ddof=1) for _ in range(3000)])
    nu, e = allan.block_variance_dof(M, f, [0.0, 1.0, fl * fl, q * q / 3, R * R / 2])
    assert abs(s2.mean() - e) <= 4 * s2.std() / math.sqrt(s2.size), (s2.mean(), e)
    nu_mc = 2 * s2.mean() ** 2 / s2.var()
    assert nu == pytest.approx(nu_mc, rel=0.12), (nu, nu_mc)
    assert nu < (M - 1) / 3

"""Block statistics of sampled rate data: block means and their standard deviation
(:func:`block_means`, :func:`block_std`), the degrees of freedom of a block variance under
power-law noise (:func:`block_variance_dof`), the uncertainty of a mean from batch means
(:func:`mean_u_batches`) and the block means at doubling averaging times of GB/T 45570 D.5.6
(:func:`block_means_pyramid`, :func:`block_variance_doubling`).

The conventions (``y``, ``tau0``, ``m``) are those of :mod:`metro.core.stats.allan`.
"""

from __future__ import annotations

import math
from typing import NamedTuple

import numpy as np
from numpy.typing import ArrayLike

from .allan_base import (CHUNK, BlockDoublingResult, Engine, FloatArray, as_int, checked_series,
                         checked_tau0, kernels)
from .allan_edf import gacv

__all__ = [
    "BatchMeanU",
    "mean_u_batches",
    "block_means",
    "block_means_pyramid",
    "block_std",
    "block_variance_doubling",
    "block_variance_dof",
]

# --------------------------------------------------------------------------- block statistics


def _factor(factor: object) -> int:
    f = as_int(factor, "factor")
    if f < 1:
        raise ValueError(f"factor must be >= 1, got {f}")
    return f


def block_means(y: ArrayLike, factor: int) -> FloatArray:
    """Means of consecutive non-overlapping blocks of ``factor`` samples.

    ybar_k = (1/f) sum_{i=0}^{f-1} y_{kf+i},  k = 0 .. floor(N/f) - 1;  the incomplete
    tail (N mod f samples) is dropped.  Used for the fixed accumulation times of
    GB/T 45570 D.5.2 (e.g. f = round(10 s / tau0)).  Each block is summed pairwise.

    Raises ValueError if N < factor (no complete block), for NaN/Inf or factor < 1.
    """
    arr, _ = checked_series(y)
    f = _factor(factor)
    M = arr.size // f
    if M < 1:
        raise ValueError(f"too few points: N = {arr.size} is shorter than one block of {f}")
    return arr[: M * f].reshape(M, f).mean(axis=1)


def block_std(y: ArrayLike, factor: int) -> tuple[float, int]:
    """Bessel-corrected sample standard deviation of the block means and their number.

        s = sqrt( 1/(M-1) sum_k (ybar_k - mean(ybar))^2 ),   M = floor(N / factor),

    computed in chunks by shifted sums (shift = mean of y, so a large offset is harmless)
    without a full-size temporary.  Returns ``(s, M)``; needs M >= 2.
    """
    arr, mu = checked_series(y)
    f = _factor(factor)
    M = arr.size // f
    if M < 2:
        raise ValueError(
            f"too few points: N = {arr.size} gives {M} block(s) of {f}; at least 2 are needed"
        )
    nb = max(1, CHUNK // f)
    s1 = 0.0
    s2 = 0.0
    for k0 in range(0, M, nb):
        k1 = min(k0 + nb, M)
        v = arr[k0 * f : k1 * f].reshape(k1 - k0, f).mean(axis=1)
        v -= mu
        s1 += float(np.sum(v))
        s2 += float(np.sum(np.square(v, out=v)))
    var = max(0.0, (s2 - s1 * s1 / M) / (M - 1))
    return math.sqrt(var), M


def _toeplitz_times(gamma: FloatArray, v: FloatArray) -> FloatArray:
    """S v for the symmetric Toeplitz S_ij = gamma[|i - j|] (gamma of length M)."""
    from scipy.signal import fftconvolve

    full = np.concatenate([gamma[:0:-1], gamma])
    return (
        fftconvolve(full, v, mode="valid") if v.size > 256 else np.convolve(full, v, mode="valid")
    )


def block_variance_dof(n_blocks: int, factor: int, coefficients: ArrayLike) -> tuple[float, float]:
    """Effective degrees of freedom and expectation of the Bessel sample variance s^2 of M block
    means of ``factor`` samples each (the statistic of :func:`block_std`, JJF 2014 eq. (29)), for
    Gaussian noise with the Allan-variance power law of :func:`oadev_covariance`,

        sigma^2(m tau0) = sum_{k=-2}^{2} a_k m^k        (a_k in the unit of y^2, tau in samples):

    white PM (k = -2), white FM (-1), flicker FM (0) and random-walk FM (1) as independent noises,
    and a deterministic rate ramp (2) of slope sqrt(2 a_2) per sample.

    The block mean is a phase difference, ybar_i = (x_{(i+1)f} - x_{if}) / f, so the block means'
    covariance at lag j follows from the generalized autocovariance R of the phase (the same
    R as in :func:`oadev_covariance`; C. A. Greenhall, TMO Progress Report 42-137, 1999):

        gamma_j = [2 R(j f) - R((j - 1) f) - R((j + 1) f)] / f^2.

    For flicker and random-walk FM this S is defined only up to terms u 1' + 1 u', which the
    centring C = I - 11'/M removes; s^2 = y' C y / (M - 1) is such a contrast, so

        E[(M - 1) s^2]   = tr(C S) + mu' C mu,
        Var[(M - 1) s^2] = 2 tr((C S)^2) + 4 mu' C S C mu      (Gaussian quadratic form),

    with mu the ramp's block means.  nu = 2 E^2 / Var is Satterthwaite's effective number of degrees
    of freedom of s^2 (F. E. Satterthwaite, Biometrics Bulletin 2, 1946): M - 1 for white noise,
    fewer where the block means are correlated — M. S. Bartlett's (J. R. Stat. Soc. Suppl. 8, 1946)
    nu = (M - 1)/(1 + 2 sum rho_k^2) is its large-M form with a known autocorrelation; here the
    autocorrelation is the noise model's, including the centring of a nonstationary flicker or
    random walk (the bias of s^2 under them is the "B1" bias function of J. A. Barnes, NBS Technical
    Note 375, 1969: E[s^2] below the Allan variance at the record length).  The sums use the
    Toeplitz structure: O(M log M).

    Returns (nu, E[s^2]); nu = inf when s^2 is certain (no noise).  Coefficients below 0 count as 0.
    """
    M = as_int(n_blocks, "n_blocks")
    f = _factor(factor)
    a = np.clip(np.asarray(coefficients, dtype=np.float64), 0.0, None)
    if a.shape != (5,):
        raise ValueError(f"coefficients must be the 5 values a_-2 .. a_2, got shape {a.shape}")
    if M < 2:
        raise ValueError(f"s^2 needs at least 2 block means, got {M}")
    j = np.arange(M, dtype=np.float64)
    gamma = np.zeros(M)
    gamma[0] += (2.0 / 3.0) * a[0] / f**2 + a[1] / f  # white PM: phase white, variance a_-2/3
    if M > 1:
        gamma[1] -= (1.0 / 3.0) * a[0] / f**2
    for k, c in ((0, a[2]), (1, a[3] * f)):  # flicker FM, random-walk FM in block units
        if c > 0.0:
            gamma += c * (2.0 * gacv(k, j) - gacv(k, j - 1.0) - gacv(k, j + 1.0))
    row = _toeplitz_times(gamma, np.ones(M))  # S 1
    tot = float(row.sum())  # 1' S 1
    weights = M - j
    weights[1:] *= 2.0
    tr_cs = M * float(gamma[0]) - tot / M
    tr_cs2 = float(np.sum(weights * gamma * gamma)) - 2.0 * float(row @ row) / M + tot * tot / M**2
    mu = math.sqrt(2.0 * a[4]) * f * (j - j.mean())  # the ramp's centred block means
    smu = _toeplitz_times(gamma, mu)
    smu -= smu.mean()  # C S C mu (C mu = mu)
    e = tr_cs + float(mu @ mu)
    v = 2.0 * tr_cs2 + 4.0 * float(mu @ smu)
    if not v > 0.0:
        return math.inf, max(e, 0.0) / (M - 1)
    return 2.0 * e * e / v, e / (M - 1)


class BatchMeanU(NamedTuple):
    """What :func:`mean_u_batches` found: the u of the mean taken, its number of batches, whether
    the
    short batches were found correlated, and the short batches' own u and number."""

    u: float
    batches: int
    correlated: bool
    u_short: float
    batches_short: int


def mean_u_batches(y: ArrayLike, batches: int = 20, few: int = 5, p: float = 0.95) -> BatchMeanU:
    """Standard uncertainty of the mean of ``y`` from the scatter of its batch means, s_b/√b, with a
    check for correlated noise.

    With correlated noise (flicker / bias instability, random walk, slow wander) neighbouring batch
    means are alike and the scatter of ``batches`` short ones understates the mean's u.  ``few``
    long batches are compared with them; when (u_few/u)² exceeds the ``p`` point of F(few − 1, b −
    1), the long batches' u is taken (``correlated``).  Used by GB/T 45570 D.5.1 (eq. D.40) and JJF
    2014 7.2.13 (eqs. (27), (28)); interpretations.md, "D.5.1 — correlated noise".  Needs ≥
    2·batches samples.
    """
    from scipy.stats import f as f_dist

    arr = np.asarray(y)
    sd, nb = block_std(arr, arr.size // batches)
    u = float(sd / np.sqrt(nb))
    if batches > few >= 2 and arr.size >= 2 * few:
        sd5, n5 = block_std(arr, arr.size // few)
        u5 = float(sd5 / np.sqrt(n5))
        if u > 0 and (u5 / u) ** 2 > float(f_dist.ppf(p, n5 - 1, nb - 1)):
            return BatchMeanU(u5, int(n5), True, u, int(nb))
    return BatchMeanU(u, int(nb), False, u, int(nb))


def block_means_pyramid(y: ArrayLike, levels: int) -> list[FloatArray]:
    """Block-mean series of doubling length: level 1 is y, level k+1 averages adjacent pairs
    of level k (an odd last element is dropped), so level k has floor(N / 2^(k-1)) means of
    2^(k-1) samples (averaging time 2^(k-1) tau0).

    Returns a list of ``levels`` arrays; element 0 is y itself (as float64, not copied when
    already float64).  Total extra memory ~ N values; use
    :func:`block_variance_doubling` when only the statistics are needed.
    """
    arr, _ = checked_series(y)
    L = as_int(levels, "levels")
    if L < 1:
        raise ValueError(f"levels must be >= 1, got {L}")
    if arr.size >> (L - 1) < 1:
        raise ValueError(
            f"too few points: N = {arr.size} has no complete block at level {L} "
            f"(needs N >= {1 << (L - 1)})"
        )
    out = [arr]
    for _ in range(1, L):
        prev = out[-1]
        h = prev.size // 2
        out.append(0.5 * (prev[0 : 2 * h : 2] + prev[1 : 2 * h : 2]))
    return out


def _pyramid_numpy(y: FloatArray, shift: float, nlev: int):
    cnt = np.zeros(nlev, dtype=np.int64)
    s1 = np.zeros(nlev)
    s2 = np.zeros(nlev)
    tmp = np.empty(CHUNK)

    def stats(v: FloatArray) -> tuple[float, float]:
        a = 0.0
        b = 0.0
        for i0 in range(0, v.size, CHUNK):
            t = tmp[: min(CHUNK, v.size - i0)]
            np.subtract(v[i0 : i0 + t.size], shift, out=t)
            a += float(np.sum(t))
            b += float(np.sum(np.square(t, out=t)))
        return a, b

    cnt[0] = y.size
    s1[0], s2[0] = stats(y)
    if nlev == 1:
        return cnt, s1, s2
    buf = np.empty(y.size // 2)
    h = y.size
    src = y
    for lev in range(1, nlev):
        h //= 2
        a = 0.0
        b = 0.0
        # block i0..i1 reads src[2 i0 : 2 i1], never written by later blocks (in place ok)
        for i0 in range(0, h, CHUNK):
            i1 = min(i0 + CHUNK, h)
            t = tmp[: i1 - i0]
            np.add(src[2 * i0 : 2 * i1 : 2], src[2 * i0 + 1 : 2 * i1 : 2], out=t)
            t *= 0.5
            buf[i0:i1] = t
            t -= shift
            a += float(np.sum(t))
            b += float(np.sum(np.square(t, out=t)))
        cnt[lev] = h
        s1[lev] = a
        s2[lev] = b
        src = buf
    return cnt, s1, s2


def block_variance_doubling(
    y: ArrayLike,
    tau0: float,
    *,
    min_blocks: int = 10,
    kmax: int | None = None,
    engine: Engine = "auto",
) -> BlockDoublingResult:
    """Standard deviation of block means at doubling averaging times (GB/T 45570 D.5.6).

    Starting from the series y (level 1, interval tau0), level k + 1 is formed by
    averaging adjacent pairs of level k (non-overlapping block means; an odd last value is
    dropped), so level k has m_k = floor(N / 2^(k-1)) means at tau_k = 2^(k-1) tau0.  For
    each level the Bessel-corrected sample standard deviation

        s_k = sqrt( 1/(m_k - 1) sum_i (v_i - vbar)^2 )

    is returned, computed from sums shifted by mean(y) (numerically stable with a large
    offset; the shift is close to every level's mean).

    Stopping rule: a level is kept only while it has at least ``min_blocks`` blocks
    (default 10) and, if given, k <= ``kmax``.

    Implementation: one pass over y gives level 1's sums and writes level 2 into a buffer of
    N/2 values; every later level overwrites that buffer in place (extra memory 0.5x the
    input).

    Parameters
    ----------
    y : array_like, shape (N,)
    tau0 : float
        Sampling interval (> 0).
    min_blocks : int, default 10
        Smallest number of blocks a level must have to be reported (>= 2).
    kmax : int, optional
        Largest level to report (>= 1).
    engine : {"auto", "numba", "numpy"}

    Raises
    ------
    ValueError
        NaN/Inf, tau0 <= 0, min_blocks < 2, kmax < 1, or N < min_blocks.
    """
    arr, mu = checked_series(y)
    t0 = checked_tau0(tau0)
    mb = as_int(min_blocks, "min_blocks")
    if mb < 2:
        raise ValueError(f"min_blocks must be >= 2 (a sample standard deviation needs 2), got {mb}")
    n = arr.size
    if n < mb:
        raise ValueError(f"too few points: N = {n} < min_blocks = {mb}")
    nlev = 1
    while (n >> nlev) >= mb:
        nlev += 1
    if kmax is not None:
        km = as_int(kmax, "kmax")
        if km < 1:
            raise ValueError(f"kmax must be >= 1, got {km}")
        nlev = min(nlev, km)
    k = kernels(engine, n)
    if k is None:
        cnt, s1, s2 = _pyramid_numpy(arr, mu, nlev)
    else:
        buf = np.empty(max(n // 2, 1) if nlev > 1 else 1)
        cnt, s1, s2 = k.pyramid_stats(arr, mu, buf, nlev)
        del buf
    cntf = cnt.astype(np.float64)
    var = np.maximum(0.0, (s2 - s1 * s1 / cntf) / (cntf - 1.0))
    return BlockDoublingResult(
        tau0=t0,
        tau=t0 * 2.0 ** np.arange(nlev),
        std=np.sqrt(var),
        n_blocks=cnt,
    )

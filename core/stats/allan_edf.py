"""How far an Allan deviation can be trusted: the equivalent degrees of freedom of ADEV, OADEV and
MDEV for white frequency noise (:func:`edf_white_fm`) and the covariance of overlapping Allan
variances at several averaging factors for a power-law noise (:func:`oadev_covariance`), from
which :mod:`metro.core.stats.allan_blocks` takes the degrees of freedom of block variances.

The conventions (``y``, ``tau0``, ``m``) are those of :mod:`metro.core.stats.allan`.
"""

from __future__ import annotations

import functools
import math

import numpy as np
from numpy.typing import ArrayLike

from .allan_base import FloatArray, as_int

__all__ = ["edf_white_fm", "oadev_covariance", "gacv"]

#: h-range up to which the edf autocovariance sums are evaluated term by term (beyond it:
#: a midpoint rule on this many panels)
_EDF_EXACT_MAX = 1 << 13

# --------------------------------------------------------------------------- edf


def _autocov_sum(T: int, r, hmax: int) -> float:
    """sum_{h=1}^{min(T-1,hmax)} (T - h) r(h)^2, term by term for short ranges, else by a
    midpoint rule on 2^13 panels (r is piecewise polynomial with at most 3 kinks: relative
    error below 1e-3, far below the meaning of an edf)."""
    H = min(T - 1, hmax)
    if H <= 0:
        return 0.0
    if H <= _EDF_EXACT_MAX:
        h = np.arange(1, H + 1, dtype=np.float64)
        v = r(h)
        return float(np.sum((T - h) * v * v))
    K = _EDF_EXACT_MAX
    w = H / K
    h = 0.5 + w * (np.arange(K) + 0.5)
    v = r(h)
    return float(w * np.sum((T - h) * v * v))


def _c3(t: FloatArray) -> FloatArray:
    return np.where(t > 0.0, t * (t - 1.0) * (t - 2.0) / 6.0, 0.0)


def _q4(h: FloatArray, m: int) -> FloatArray:
    """Autocorrelation of the m-box convolved with itself (discrete Irwin-Hall count)."""
    s = h + 2.0 * m - 2.0
    return (
        _c3(s + 3.0)
        - 4.0 * _c3(s - m + 3.0)
        + 6.0 * _c3(s - 2.0 * m + 3.0)
        - 4.0 * _c3(s - 3.0 * m + 3.0)
        + _c3(s - 4.0 * m + 3.0)
    )


def edf_white_fm(kind: str, n: int, m: ArrayLike) -> FloatArray:
    """Equivalent degrees of freedom of an Allan-type variance estimate for white FM noise.

    For Gaussian white FM (white rate noise) each estimator is a quadratic form
    Q = sum_j d_j^2 of the i.i.d. samples, d_j = sum_i g_i y_{j+i}.  With the coefficient
    autocorrelation r(h) = sum_i g_i g_{i+h} and T terms, the chi-square fit of Q
    (matching mean and variance) has

        edf = 2 E[Q]^2 / Var[Q] = (T r(0))^2 / (T r(0)^2 + 2 sum_{h=1}^{T-1} (T-h) r(h)^2),

    the approach of C. A. Greenhall and W. J. Riley, "Uncertainty of stability variances
    based on finite differences", Proc. 35th PTTI Meeting, 2003, here specialised to white
    FM, where r is known in closed form:

    * adev (non-overlapping, M = N // m block means, T = M - 1):
      edf = 2 (M-1)^2 / (3M - 4)  (exact; first differences of i.i.d. means);
    * oadev (T = N - 2m + 1): r(0) = 2m, r(h) = 2m - 3h for h <= m, h - 2m for m < h < 2m;
    * mdev (T = N - 3m + 2): r(h) = 2q(h) - q(h-m) - q(h+m), q the autocorrelation of the
      m-box convolved with itself (a discrete cubic B-spline).

    For oadev the result agrees with the simple white-FM approximation of D. A. Howe,
    D. W. Allan and J. A. Barnes, "Properties of signal sources and measurement methods",
    Proc. 35th Frequency Control Symposium (1981) (also NIST SP 1065, table 5),
    edf ~ [3(N'-1)/(2m) - 2(N'-2)/N'] 4m^2/(4m^2+5) with N' = N + 1 phase points, to within
    about 2 %.  For other noise types these values are only indicative.

    Parameters
    ----------
    kind : {"adev", "oadev", "mdev"}
    n : int
        Number of frequency samples N.
    m : int or array of int
        Averaging factors.
    """
    n = as_int(n, "n")
    ms = np.atleast_1d(np.asarray(m, dtype=np.int64))
    out = np.empty(ms.size)
    for i, mm in enumerate(ms.tolist()):
        if mm < 1:
            raise ValueError(f"m must be >= 1, got {mm}")
        if kind == "adev":
            M = n // mm
            if M < 2:
                raise ValueError(f"adev needs N >= 2m (N = {n}, m = {mm})")
            out[i] = 2.0 * (M - 1) ** 2 / (3.0 * M - 4.0) if M > 2 else 1.0
        elif kind == "oadev":
            T = n - 2 * mm + 1
            if T < 1:
                raise ValueError(f"oadev needs N >= 2m (N = {n}, m = {mm})")
            r0 = 2.0 * mm

            def r_oadev(h: FloatArray, m_: int = mm) -> FloatArray:
                return np.where(h <= m_, 2.0 * m_ - 3.0 * h, h - 2.0 * m_)

            out[i] = (T * r0) ** 2 / (T * r0 * r0 + 2.0 * _autocov_sum(T, r_oadev, 2 * mm - 1))
        elif kind == "mdev":
            T = n - 3 * mm + 2
            if T < 1:
                raise ValueError(f"mdev needs N >= 3m - 1 (N = {n}, m = {mm})")

            def r_mdev(h: FloatArray, m_: int = mm) -> FloatArray:
                return 2.0 * _q4(h, m_) - _q4(h - m_, m_) - _q4(h + m_, m_)

            r0 = float(r_mdev(np.zeros(1))[0])
            out[i] = (T * r0) ** 2 / (T * r0 * r0 + 2.0 * _autocov_sum(T, r_mdev, 3 * mm - 2))
        else:
            raise ValueError(f"kind must be 'adev', 'oadev' or 'mdev', got {kind!r}")
    return out


# --------------------------------------------------------------------------- covariance of OAVAR


#: the second-difference coefficients of an Allan variance term (x_j, x_{j+m}, x_{j+2m})
_D2 = np.array([1.0, -2.0, 1.0])
# : lag sums over the region |h| <= 4(m + m') + 2 are exact up to this many lags, beyond: midpoint
# rule
_COV_NEAR_MAX = 1 << 12
#: log-spaced midpoint panels for the flicker-FM tail beyond that region
_COV_FAR_PANELS = 256
#: terms of the flicker-FM tail series (converges for |h| > 2 max(m, m'); used for |h| > 4(m + m'))
_COV_SERIES = 20


def gacv(k: int, u: FloatArray) -> FloatArray:
    """Generalized autocovariance of the phase x for the term a_k m^k of sigma^2 (a_k = 1, tau0 =
    1).

    White FM (k = -1): -|u|/2; flicker FM (k = 0): u^2 ln|u| / (4 ln 2); random-walk FM (k = 1):
    |u|^3 / 4.  (White PM, k = -2, is the Kronecker delta / 3, handled by the caller.)  Each gives
    sum_{a,b} c_a c_b K(t_a - t_b) = 2 m^2 * m^k for the second difference c = (1, -2, 1) at
    spacing m, i.e. the Allan variance m^k."""
    au = np.abs(u)
    if k == -1:
        return -0.5 * au
    if k == 0:
        safe = np.where(au > 0.0, au, 1.0)
        return np.where(au > 0.0, u * u * np.log(safe), 0.0) / (4.0 * math.log(2.0))
    return au**3 / 4.0


def _d2_cross(k: int, h: FloatArray, m: int, mp: int) -> FloatArray:
    """Cov(e_m(j), e_m'(j + h)) for the noise term k, e_m(j) = x_{j+2m} - 2 x_{j+m} + x_j."""
    out = np.zeros_like(h)
    for a in range(3):
        for b in range(3):
            out += _D2[a] * _D2[b] * gacv(k, h + b * mp - a * m)
    return out


def _flicker_series_coefficients() -> FloatArray:
    """g_k of (1 + e)^2 ln(1 + e) = sum_k g_k e^k."""
    lg = np.array([0.0] + [(-1.0) ** (j + 1) / j for j in range(1, _COV_SERIES + 1)])
    g = np.zeros(_COV_SERIES + 1)
    for k in range(1, _COV_SERIES + 1):
        g[k] = lg[k] + 2.0 * lg[k - 1] + (lg[k - 2] if k >= 2 else 0.0)
    return g


def _d2_cross_flicker_far(h: FloatArray, m: int, mp: int) -> FloatArray:
    """:func:`_d2_cross` for flicker FM at |h| > 4(m + m'), as the series in (b m' - a m)/h (the
    nine-term sum cancels catastrophically there: terms ~ h^2 ln h, result ~ m^2 m'^2 / h^2)."""
    g = _flicker_series_coefficients()
    out = np.zeros_like(h)
    for k in range(4, _COV_SERIES + 1):  # the moments of order < 4 vanish (second differences)
        mk = sum(_D2[a] * _D2[b] * float(b * mp - a * m) ** k for a in range(3) for b in range(3))
        out += g[k] * mk * h ** (2.0 - k)
    return out / (4.0 * math.log(2.0))


def _pair_count(h: FloatArray, t1: int, t2: int) -> FloatArray:
    """Number of (j, k), 0 <= j < t1, 0 <= k < t2, with k - j = h."""
    return np.clip(np.minimum(t1, t2 - h) - np.maximum(0.0, -h), 0.0, None)


def _oadev_cov_pair(n: int, m: int, mp: int) -> tuple[FloatArray, FloatArray]:
    """(Q, L) for one pair of factors: Q[s, t] = sum_h n(h) C_s(h) C_t(h) and L[s] = sum_h n(h)
    C_s(h)
    over the noise terms s, t in (-2, -1, 0, 1) (indices 0..3)."""
    t1, t2 = n - 2 * m + 1, n - 2 * mp + 1
    Q = np.zeros((4, 4))
    L = np.zeros(4)
    # white PM: C(h) = (1/3) sum of c_a c_b over the (at most 9) lags h = a m - b m'
    lag: dict[int, float] = {}
    for a in range(3):
        for b in range(3):
            lag[a * m - b * mp] = lag.get(a * m - b * mp, 0.0) + _D2[a] * _D2[b] / 3.0
    hq = np.array(sorted(lag), dtype=np.float64)
    cq = np.array([lag[int(v)] for v in hq])
    wq = _pair_count(hq, t1, t2)
    Q[0, 0] = float(np.sum(wq * cq * cq))
    for i, k in enumerate((-1, 0, 1), 1):
        Q[0, i] = Q[i, 0] = float(np.sum(wq * cq * _d2_cross(k, hq, m, mp)))
    L[0] = float(np.sum(wq * cq))
    # white, flicker and random-walk FM near the pair's support
    w_ = 4 * (m + mp) + 2
    lo, hi = max(-w_, -(t1 - 1)), min(w_, t2 - 1)
    if hi - lo + 1 <= _COV_NEAR_MAX:
        h = np.arange(lo, hi + 1, dtype=np.float64)
        w = _pair_count(h, t1, t2)
    else:
        step = (hi - lo + 1) / _COV_NEAR_MAX
        h = lo - 0.5 + step * (np.arange(_COV_NEAR_MAX) + 0.5)
        w = step * _pair_count(h, t1, t2)
    c = [_d2_cross(k, h, m, mp) for k in (-1, 0, 1)]
    for i in range(3):
        L[i + 1] = float(np.sum(w * c[i]))
        for j in range(3):
            Q[i + 1, j + 1] = float(np.sum(w * c[i] * c[j]))
    # flicker FM's tail (the other terms have no covariance beyond |h| = 2 max(m, m'))
    for sign, top in ((1.0, t2 - 1), (-1.0, t1 - 1)):
        if top <= w_:
            continue
        edges = np.unique(np.round(np.geomspace(w_ + 0.5, top + 0.5, _COV_FAR_PANELS + 1)))
        hh = sign * 0.5 * (edges[1:] + edges[:-1])
        cf = _d2_cross_flicker_far(hh, m, mp)
        wf = np.diff(edges) * _pair_count(hh, t1, t2)
        Q[2, 2] += float(np.sum(wf * cf * cf))
        L[2] += float(np.sum(wf * cf))
    return Q, L


@functools.lru_cache(maxsize=16)
def _oadev_cov_basis(n: int, ms: tuple[int, ...]) -> tuple[FloatArray, FloatArray]:
    k = len(ms)
    Q = np.zeros((k, k, 4, 4))
    L = np.zeros((k, k, 4))
    for i in range(k):
        for j in range(i, k):
            q, l1 = _oadev_cov_pair(n, ms[i], ms[j])
            Q[i, j], Q[j, i], L[i, j], L[j, i] = q, q, l1, l1  # both symmetric in (m, m')
    Q.setflags(write=False)
    L.setflags(write=False)
    return Q, L


def oadev_covariance(n: int, m: ArrayLike, coefficients: ArrayLike) -> FloatArray:
    """Covariance matrix of the overlapping Allan variance estimates sigma^2(m_i tau0) of
    :func:`oadev`, for Gaussian noise whose Allan variance is the five-term power law

        sigma^2(m tau0) = sum_{k=-2}^{2} a_k m^k          (a_k in the unit of y^2, tau in samples)

    of IEEE Std 952-1997 annex C: white PM / quantization (k = -2), white FM / angle random walk
    (-1), flicker FM / bias instability (0), random-walk FM / rate random walk (1), each an
    independent noise, plus a deterministic ramp (2).  Coefficients below 0 count as 0.

    Each estimate is a quadratic form in the phase, sigma^2_m = sum_j e_m(j)^2 / (2 m^2 T_m),
    e_m(j) = x_{j+2m} - 2 x_{j+m} + x_j, T_m = N - 2m + 1.  For zero-mean Gaussian e,
    Cov(e^2, e'^2) = 2 Cov(e, e')^2 (Isserlis), so

        Cov(sigma^2_m, sigma^2_m') = [2 sum_h n(h) C(h)^2 + 4 d_m d_m' sum_h n(h) C(h)] / (4 m^2
        m'^2 T_m T_m')

    with C(h) = Cov(e_m(j), e_m'(j + h)), n(h) the number of index pairs at lag h, and
    d_m = m^2 sqrt(2 a_2) the ramp's (constant) second difference.  C is a linear combination
    of the noises' generalized autocovariances of the phase (C. A. Greenhall, "The generalized
    autocovariance: a tool for clock noise statistics", TMO Progress Report 42-137, JPL, 1999):
    white PM a_{-2}/3 at lag 0, white FM -a_{-1}|u|/2, flicker FM a_0 u^2 ln|u| / (4 ln 2),
    random-walk FM a_1 |u|^3 / 4 — each reproduces its term a_k m^k exactly.  With white FM
    alone the diagonal gives 2 sigma^4 / edf with the edf of :func:`edf_white_fm` (C. A. Greenhall
    and W. J. Riley, PTTI 2003: the variance of a quadratic form as a sum of squared
    autocovariances).  Flicker and random-walk FM are taken in continuous time (their discrete
    simulation differs at m = 1, 2, where white noise usually dominates).

    The lag sums depend only on N and m and are cached; the result is then a quadratic form in
    the a_k.  Lags beyond 4096 near a pair's support are summed by the midpoint rule and the
    flicker tail on log-spaced panels (relative error below 1e-3).

    Parameters
    ----------
    n : int
        Number of samples N of y.
    m : array of int
        Averaging factors (each with N >= 2m).
    coefficients : array of 5 floats
        a_{-2} .. a_2 in the unit of y^2, for tau counted in samples (a_k = A_k tau0^k for A_k
        given with tau in time units).
    """
    n = as_int(n, "n")
    ms = np.atleast_1d(np.asarray(m, dtype=np.int64))
    a = np.clip(np.asarray(coefficients, dtype=np.float64), 0.0, None)
    if a.shape != (5,):
        raise ValueError(f"coefficients must be the 5 values a_-2 .. a_2, got shape {a.shape}")
    if ms.size == 0 or np.any(ms < 1) or np.any(2 * ms > n):
        raise ValueError(f"each averaging factor needs 1 <= m <= N/2 (N = {n}, m = {ms.tolist()})")
    Q, L = _oadev_cov_basis(n, tuple(int(v) for v in ms))
    msf = ms.astype(np.float64)
    quad = 2.0 * np.einsum("ijst,s,t->ij", Q, a[:4], a[:4])
    d = msf**2 * math.sqrt(2.0 * a[4])
    lin = 4.0 * np.outer(d, d) * np.einsum("ijs,s->ij", L, a[:4])
    norm = 2.0 * msf**2 * (n - 2.0 * msf + 1.0)
    return (quad + lin) / np.outer(norm, norm)

"""Allan-type stability statistics and block statistics of sampled rate / frequency data.

Conventions
-----------
``y`` is a 1-D series of N samples of a rate or fractional frequency (a gyro output in
deg/h, a normalised frequency...), taken back to back at the interval ``tau0``.  An
averaging factor ``m`` (a positive integer) gives the averaging time tau = m * tau0, in the
unit of ``tau0``.  Deviations are in the unit of ``y``.  Inputs are plain numpy arrays;
units are the caller's business.

Everything is computed from the phase (running sum) of the mean-removed series

    x_0 = 0,   x_{i+1} = x_i + (y_i - mean(y)),    i = 0 .. N-1,

so a large constant offset (a gyro sitting on a big bias, cf. NIST StRD NumAcc4:
10000000.2 +- 0.1) costs no accuracy: the statistics below are invariant to a constant
added to y, and removing the mean first keeps |x| small.  The phase here is in units of
"y times samples"; the factor tau0 cancels in every frequency-data deviation.

Engines
-------
Each statistic has a compiled numba kernel (``metro.core.stats.allan_kernels``, imported and
compiled on first use, cached on disk) and a pure-numpy fallback implementing the same
algorithm in cache-sized chunks.  ``engine="auto"`` (default) uses numba for N >= 65536
samples when numba is importable and the environment variable ``METRO_NO_NUMBA`` is not
set to a non-empty value other than "0"; ``engine="numba"`` / ``"numpy"`` force one.
Both need one temporary of N + 1 float64 (the phase) and a few cache-sized buffers, so
the extra memory is about 1.0x the input (plus one converted copy if ``y`` is not a
C-contiguous float64 array).  Both build bit-identical phase arrays, so the two engines
agree to ~1e-15 relative.  The rounding error of a squared second difference is about
eps * max|x| / |x_{j+2m} - 2x_{j+m} + x_j|, i.e. it grows only with the excursion of the
mean-removed phase (a strong frequency drift), never with the offset.

Speed (28.8 M samples, 24 octave factors, 2-core Xeon, see docs/performance-allan.md):
numba OADEV ~0.4 s, numpy fallback ~2 s, allantools.oadev ~9 s on the same machine.

Averaging-factor lists and stopping rule
----------------------------------------
:func:`octave_m` and :func:`log_m` stop at m <= ``max_fraction`` * N with the default
``max_fraction = 0.25`` (Stable32's stop ratio of 4 for the overlapping estimators): at the
largest tau the overlapping ADEV still averages >= N/2 squared differences, the
non-overlapping ADEV >= 3, and MDEV >= N/4.

References
----------
* IEEE Std 1139-2008, Standard definitions of physical quantities for fundamental
  frequency and time metrology -- random instabilities.
* D. W. Allan, "Statistics of atomic frequency standards", Proc. IEEE 54(2), 1966.
* D. B. Sullivan, D. W. Allan, D. A. Howe, F. L. Walls (eds.), NIST Technical Note 1337,
  1990, and NBS Monograph 140 (1974), Annex 8.E (the "NBS14" test data used by the tests).
* W. J. Riley, Handbook of Frequency Stability Analysis, NIST SP 1065, 2008 (definitions
  of ADEV, OADEV, MDEV in terms of phase; stop ratios).
* IEEE Std 952-1997, Annex C (Allan variance of gyro rate data).
* GB/T 45570, clause D.5.6 (block means of doubling averaging time) and D.5.2 (fixed
  accumulation time), for :func:`block_variance_doubling` and :func:`block_means`.
"""

from __future__ import annotations

import functools
import math
import os
from types import ModuleType
from typing import Literal, NamedTuple

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "BatchMeanU",
    "mean_u_batches",
    "AllanResult",
    "BlockDoublingResult",
    "adev",
    "block_means",
    "block_means_pyramid",
    "block_std",
    "block_variance_doubling",
    "block_variance_dof",
    "edf_white_fm",
    "log_m",
    "oadev_covariance",
    "mdev",
    "oadev",
    "octave_m",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Engine = Literal["auto", "numba", "numpy"]

#: below this many samples ``engine="auto"`` uses numpy (no compile latency for small data)
NUMBA_MIN_N = 1 << 16
#: chunk length (samples) of the numpy fallback's work buffers
_CHUNK = 1 << 15
#: block length of the compiled OADEV kernel
_BLOCK = 2048
#: h-range up to which the edf autocovariance sums are evaluated term by term (beyond it:
#: a midpoint rule on this many panels)
_EDF_EXACT_MAX = 1 << 13


# --------------------------------------------------------------------------- helpers


def _readonly(a: ArrayLike) -> np.ndarray:
    arr = np.array(a, copy=True)
    arr.setflags(write=False)
    return arr


def _kernels(engine: Engine, n: int) -> ModuleType | None:
    """The compiled-kernel module, or None for the numpy path."""
    if engine not in ("auto", "numba", "numpy"):
        raise ValueError(f"engine must be 'auto', 'numba' or 'numpy', got {engine!r}")
    if engine == "numpy":
        return None
    if engine == "auto" and (
        os.environ.get("METRO_NO_NUMBA", "") not in ("", "0") or n < NUMBA_MIN_N
    ):
        return None
    try:
        from . import allan_kernels as _allan_kernels
    except ImportError:
        if engine == "numba":
            raise
        return None
    return _allan_kernels


def _first_nonfinite(a: np.ndarray) -> int | None:
    for i0 in range(0, a.size, 1 << 20):
        chunk = a[i0 : i0 + (1 << 20)]
        ok = np.isfinite(chunk)
        if not ok.all():
            return i0 + int(np.argmin(ok))
    return None


def _series(y: ArrayLike, name: str = "y") -> tuple[FloatArray, float]:
    """Validated C-contiguous float64 view (copy only if needed) and the mean."""
    arr = np.asarray(y)
    if np.iscomplexobj(arr):
        raise ValueError(f"{name} must be real-valued")
    if arr.dtype != np.float64:
        try:
            arr = arr.astype(np.float64)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{name} must be numeric: {exc}") from None
    if arr.ndim != 1:
        raise ValueError(f"{name} must be 1-dimensional, got shape {arr.shape}")
    if arr.size == 0:
        raise ValueError(f"{name} is empty")
    arr = np.ascontiguousarray(arr)
    mu = float(np.mean(arr))  # pairwise summation; NaN/Inf anywhere makes it non-finite
    if not math.isfinite(mu):
        bad = _first_nonfinite(arr)
        if bad is None:
            raise ValueError(f"{name} values are too large: their sum overflows float64")
        raise ValueError(f"{name} contains NaN or Inf (first at index {bad})")
    return arr, mu


def _tau0(tau0: float) -> float:
    try:
        t = float(tau0)
    except (TypeError, ValueError):
        raise ValueError(f"tau0 must be a number, got {tau0!r}") from None
    if not math.isfinite(t) or t <= 0.0:
        raise ValueError(f"tau0 must be a finite positive number, got {tau0!r}")
    return t


def _as_int(v: object, name: str) -> int:
    if isinstance(v, (bool, np.bool_)):
        raise ValueError(f"{name} must be an integer, got {v!r}")  # noqa: TRY004
    try:
        f = float(v)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an integer, got {v!r}") from None
    if not math.isfinite(f) or f != int(f):
        raise ValueError(f"{name} must be an integer, got {v!r}")
    return int(f)


def _m_list(m: ArrayLike | int | None, n: int, kind: str) -> IntArray:
    if m is None:
        ms = octave_m(n)
    else:
        arr = np.atleast_1d(np.asarray(m))
        if arr.ndim != 1 or arr.size == 0:
            raise ValueError("m must be a positive integer or a non-empty 1-D list of them")
        if arr.dtype.kind == "b" or arr.dtype.kind not in "iuf":
            raise ValueError(f"m must contain integers, got dtype {arr.dtype}")
        if arr.dtype.kind == "f" and not (
            np.all(np.isfinite(arr)) and np.all(arr == np.round(arr))
        ):
            raise ValueError("m must contain integers (averaging factors), got non-integral values")
        ms = np.unique(arr.astype(np.int64))
    if ms[0] < 1:
        raise ValueError(
            f"averaging factors must be >= 1 (tau must be positive), got m = {int(ms[0])}"
        )
    mmax = int(ms[-1])
    if kind == "mdev":
        if 3 * mmax - 1 > n:
            raise ValueError(
                f"m = {mmax} is too large for N = {n} samples: mdev needs N >= 3m - 1 "
                f"(largest usable m is {(n + 1) // 3})"
            )
    elif 2 * mmax > n:
        raise ValueError(
            f"m = {mmax} is too large for N = {n} samples: {kind} needs N >= 2m "
            f"(largest usable m is {n // 2})"
        )
    return ms


# --------------------------------------------------------------------------- m lists


def _mmax(n: int, max_fraction: float) -> int:
    n = _as_int(n, "n")
    if n < 1:
        raise ValueError(f"n must be >= 1, got {n}")
    if not (0.0 < max_fraction <= 0.5):
        raise ValueError(f"max_fraction must be in (0, 0.5], got {max_fraction}")
    mmax = math.floor(max_fraction * n)
    if mmax < 1:
        need = math.ceil(1.0 / max_fraction)
        raise ValueError(
            f"too few points: N = {n} gives no averaging factor m <= {max_fraction} N "
            f"(at least {need} samples are needed)"
        )
    return mmax


def octave_m(n: int, max_fraction: float = 0.25) -> IntArray:
    """Octave-spaced averaging factors m = 1, 2, 4, ..., 2^k with 2^k <= max_fraction * n.

    Stopping rule: the largest factor is the largest power of two not above
    ``max_fraction * n`` (default 1/4, Stable32's stop ratio for overlapping estimators,
    W. J. Riley, NIST SP 1065 (2008), table of stop ratios).  With 1/4 the overlapping ADEV
    at the last tau still averages at least N/2 squared second differences and the
    non-overlapping ADEV at least 3.  ``max_fraction`` may be raised to 0.5 (the absolute
    limit of ADEV/OADEV: N >= 2m).

    Raises ValueError when n * max_fraction < 1 (too few points).
    """
    mmax = _mmax(n, max_fraction)
    return (1 << np.arange(mmax.bit_length(), dtype=np.int64)).astype(np.int64)


def log_m(n: int, per_decade: int = 10, max_fraction: float = 0.25) -> IntArray:
    """Log-spaced averaging factors round(10^(k/per_decade)), k = 0, 1, ..., de-duplicated.

    Same stopping rule as :func:`octave_m` (m <= max_fraction * n).  ``per_decade=1``
    gives 1, 10, 100, ...; ``per_decade=3`` gives 1, 2, 5, 10, 22, 46, 100, ...
    """
    per_decade = _as_int(per_decade, "per_decade")
    if per_decade < 1:
        raise ValueError(f"per_decade must be >= 1, got {per_decade}")
    mmax = _mmax(n, max_fraction)
    kmax = math.floor(per_decade * math.log10(mmax) + 1e-9)
    m = np.unique(np.round(10.0 ** (np.arange(kmax + 1) / per_decade)).astype(np.int64))
    return m[(m >= 1) & (m <= mmax)]


# --------------------------------------------------------------------------- results


@attrs.frozen(eq=False)
class AllanResult:
    """Deviations at a list of averaging times.

    Attributes
    ----------
    kind : str
        "adev", "oadev" or "mdev".
    tau0 : float
        Sampling interval of the input.
    m : ndarray of int
        Averaging factors (ascending).
    tau : ndarray
        Averaging times m * tau0.
    deviation : ndarray
        The deviation sigma(tau) (square root of the variance), in the unit of y.
    n_terms : ndarray of int
        Number of squared differences averaged at each tau.
    edf : ndarray
        Equivalent degrees of freedom of the variance estimate, for white FM noise
        (white rate noise / angle random walk for a gyro), see :func:`edf_white_fm`.
    n_samples : int
        Length N of the input series.
    """

    kind: str
    tau0: float
    m: IntArray = attrs.field(converter=_readonly)
    tau: FloatArray = attrs.field(converter=_readonly)
    deviation: FloatArray = attrs.field(converter=_readonly)
    n_terms: IntArray = attrs.field(converter=_readonly)
    edf: FloatArray = attrs.field(converter=_readonly)
    n_samples: int

    @property
    def variance(self) -> FloatArray:
        """sigma^2(tau)."""
        return self.deviation**2

    @property
    def uncertainty(self) -> FloatArray:
        """Standard uncertainty of each deviation from its edf: u(sigma) = sigma / sqrt(2 edf).

        From Var[s^2] = 2 sigma^4 / edf for a chi-square distributed variance estimate and
        first-order propagation to the square root.
        """
        return self.deviation / np.sqrt(2.0 * self.edf)

    def ci(self, p: float = 0.683) -> tuple[FloatArray, FloatArray]:
        """Two-sided confidence interval (lower, upper) of each deviation at level ``p``.

        Treats edf * s^2 / sigma^2 as chi-square with edf degrees of freedom:

            lower = s sqrt(edf / chi2_{(1+p)/2}(edf)),  upper = s sqrt(edf / chi2_{(1-p)/2}(edf)).

        Reference: D. A. Howe, D. W. Allan, J. A. Barnes, "Properties of signal sources and
        measurement methods", Proc. 35th Frequency Control Symposium, 1981; NIST SP 1065,
        sec. 5.3.
        """
        p = float(p)
        if not (0.0 < p < 1.0):
            raise ValueError(f"p must be in (0, 1), got {p}")
        from scipy.stats import chi2

        lo_q = chi2.ppf(0.5 * (1.0 + p), self.edf)
        hi_q = chi2.ppf(0.5 * (1.0 - p), self.edf)
        return self.deviation * np.sqrt(self.edf / lo_q), self.deviation * np.sqrt(self.edf / hi_q)


@attrs.frozen(eq=False)
class BlockDoublingResult:
    """Sample standard deviation of block means at doubling averaging times.

    Level k = 1, 2, ... has averaging time tau_k = 2^(k-1) tau0, n_blocks[k-1] = m_k block
    means and std[k-1] their Bessel-corrected (n - 1) sample standard deviation.
    """

    tau0: float
    tau: FloatArray = attrs.field(converter=_readonly)
    std: FloatArray = attrs.field(converter=_readonly)
    n_blocks: IntArray = attrs.field(converter=_readonly)

    @property
    def level(self) -> IntArray:
        """Level numbers k = 1 .. K."""
        return np.arange(1, self.std.size + 1, dtype=np.int64)

    @property
    def variance(self) -> FloatArray:
        return self.std**2


# --------------------------------------------------------------------------- phase


def _phase_numpy(y: FloatArray, mu: float) -> FloatArray:
    x = np.empty(y.size + 1)
    x[0] = 0.0
    buf = np.empty(min(_CHUNK, y.size))
    carry = 0.0
    for i0 in range(0, y.size, _CHUNK):
        i1 = min(i0 + _CHUNK, y.size)
        b = buf[: i1 - i0]
        np.subtract(y[i0:i1], mu, out=b)
        b[0] += carry  # same operation order as a sequential running sum (bit-identical)
        out = x[i0 + 1 : i1 + 1]
        np.cumsum(b, out=out)
        carry = float(out[-1])
    return x


def _phase(y: FloatArray, mu: float, k: ModuleType | None) -> FloatArray:
    if k is None:
        return _phase_numpy(y, mu)
    x = np.empty(y.size + 1)
    k.phase(y, mu, x)
    return x


def _ssq_numpy_oadev(x: FloatArray, ms: IntArray) -> FloatArray:
    """sum_j (x[j+2m] - 2x[j+m] + x[j])^2 for each m: chunk-outer, m-inner (cache reuse)."""
    nx = x.size
    out = np.zeros(ms.size)
    buf = np.empty(_CHUNK)
    mlist = ms.tolist()
    for j0 in range(0, nx, _CHUNK):
        for k, m in enumerate(mlist):
            j1 = min(j0 + _CHUNK, nx - 2 * m)
            if j1 <= j0:
                break
            b = buf[: j1 - j0]
            np.multiply(x[j0 + m : j1 + m], -2.0, out=b)
            b += x[j0:j1]
            b += x[j0 + 2 * m : j1 + 2 * m]
            np.square(b, out=b)
            out[k] += float(np.sum(b))
    return out


def _octave_groups(ms: IntArray) -> tuple[IntArray, IntArray]:
    """Split sorted factors into octave quadruples (g, 2g, 4g, 8g) and the rest."""
    left = set(ms.tolist())
    groups: list[int] = []
    for m in ms.tolist():
        quad = (m, 2 * m, 4 * m, 8 * m)
        if all(q in left for q in quad):
            groups.append(m)
            left.difference_update(quad)
    return np.array(groups, dtype=np.int64), np.array(sorted(left), dtype=np.int64)


def _oadev_numba(k: ModuleType, x: FloatArray, ms: IntArray) -> FloatArray:
    groups, singles = _octave_groups(ms)
    sg, ss = k.oadev_ssq(x, groups, singles, _BLOCK)
    found = dict(zip(singles.tolist(), ss.tolist()))
    for i, g in enumerate(groups.tolist()):
        for j in range(4):
            found[g << j] = float(sg[4 * i + j])
    return np.array([found[m] for m in ms.tolist()])


def _ssq_numpy_adev(x: FloatArray, ms: IntArray) -> FloatArray:
    n = x.size - 1
    out = np.zeros(ms.size)
    buf = np.empty(_CHUNK)
    for k, m in enumerate(ms.tolist()):
        M = n // m
        xs = x[0 : M * m + 1 : m]  # M + 1 phase points at the block boundaries (a view)
        nterm = M - 1
        for i0 in range(0, nterm, _CHUNK):
            i1 = min(i0 + _CHUNK, nterm)
            b = buf[: i1 - i0]
            np.multiply(xs[i0 + 1 : i1 + 1], -2.0, out=b)
            b += xs[i0:i1]
            b += xs[i0 + 2 : i1 + 2]
            np.square(b, out=b)
            out[k] += float(np.sum(b))
    return out


def _ssq_numpy_mdev(x: FloatArray, ms: IntArray) -> FloatArray:
    n = x.size - 1
    out = np.zeros(ms.size)
    da = np.empty(_CHUNK)
    db = np.empty(_CHUNK)

    def second_diff(i0: int, i1: int, m: int, b: FloatArray) -> FloatArray:
        b = b[: i1 - i0]
        np.multiply(x[i0 + m : i1 + m], -2.0, out=b)
        b += x[i0:i1]
        b += x[i0 + 2 * m : i1 + 2 * m]
        return b

    for k, m in enumerate(ms.tolist()):
        T = n - 3 * m + 2
        w = 0.0  # w_0 = sum_{i<m} d_i
        for i0 in range(0, m, _CHUNK):
            w += float(np.sum(second_diff(i0, min(i0 + _CHUNK, m), m, da)))
        tot = 0.0
        for j0 in range(0, T, _CHUNK):
            j1 = min(j0 + _CHUNK, T)
            # u_j = d_{j+m} - d_j drives w_{j+1} = w_j + u_j, for j < T - 1
            u1 = min(j1, T - 1)
            tot += w * w
            if u1 > j0:
                u = np.subtract(second_diff(j0 + m, u1 + m, m, db), second_diff(j0, u1, m, da))
                ws = np.cumsum(u)
                ws += w
                # w_{j0+1} .. w_{u1}; those below j1 are terms of this chunk
                inner = ws[: j1 - j0 - 1]
                tot += float(np.sum(np.square(inner, out=inner)))
                w = float(ws[-1])
        out[k] = tot
    return out


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
    n = _as_int(n, "n")
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
#: lag sums over the region |h| <= 4(m + m') + 2 are exact up to this many lags, beyond: midpoint rule
_COV_NEAR_MAX = 1 << 12
#: log-spaced midpoint panels for the flicker-FM tail beyond that region
_COV_FAR_PANELS = 256
#: terms of the flicker-FM tail series (converges for |h| > 2 max(m, m'); used for |h| > 4(m + m'))
_COV_SERIES = 20


def _gacv(k: int, u: FloatArray) -> FloatArray:
    """Generalized autocovariance of the phase x for the term a_k m^k of sigma^2 (a_k = 1, tau0 = 1).

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
            out += _D2[a] * _D2[b] * _gacv(k, h + b * mp - a * m)
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
    """(Q, L) for one pair of factors: Q[s, t] = sum_h n(h) C_s(h) C_t(h) and L[s] = sum_h n(h) C_s(h)
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

        Cov(sigma^2_m, sigma^2_m') = [2 sum_h n(h) C(h)^2 + 4 d_m d_m' sum_h n(h) C(h)] / (4 m^2 m'^2 T_m T_m')

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
    n = _as_int(n, "n")
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


# --------------------------------------------------------------------------- deviations


def _result(kind: str, tau0: float, ms: IntArray, ssq: FloatArray, n: int) -> AllanResult:
    msf = ms.astype(np.float64)
    if kind == "adev":
        nterm = n // ms - 1
        var = ssq / (2.0 * msf * msf * nterm)
    elif kind == "oadev":
        nterm = n - 2 * ms + 1
        var = ssq / (2.0 * msf * msf * nterm)
    else:
        nterm = n - 3 * ms + 2
        var = ssq / (2.0 * msf**4 * nterm)
    return AllanResult(
        kind=kind,
        tau0=tau0,
        m=ms,
        tau=msf * tau0,
        deviation=np.sqrt(var),
        n_terms=nterm.astype(np.int64),
        edf=edf_white_fm(kind, n, ms),
        n_samples=n,
    )


def adev(
    y: ArrayLike, tau0: float, m: ArrayLike | int | None = None, *, engine: Engine = "auto"
) -> AllanResult:
    """Non-overlapping Allan deviation of frequency (rate) data.

    With M = floor(N/m) consecutive block means ybar_k of m samples each (the incomplete
    tail is dropped),

        sigma_y^2(m tau0) = 1 / (2 (M-1)) sum_{k=0}^{M-2} (ybar_{k+1} - ybar_k)^2
                          = 1 / (2 m^2 (M-1)) sum_k (x_{(k+2)m} - 2 x_{(k+1)m} + x_{km})^2,

    x being the phase (running sum) of y.  This is the two-sample (Allan) variance of
    IEEE Std 1139 and NBS Monograph 140; for gyros, IEEE Std 952 Annex C.

    Parameters
    ----------
    y : array_like, shape (N,)
        Frequency / rate samples at interval ``tau0``; finite values only.
    tau0 : float
        Sampling interval (> 0); the output ``tau`` is in its unit.
    m : int or sequence of int, optional
        Averaging factors (sorted, de-duplicated); each needs N >= 2m.  Default
        ``octave_m(N)``.
    engine : {"auto", "numba", "numpy"}
        Computation engine (see the module docstring).

    Returns
    -------
    AllanResult
        ``n_terms`` = M - 1; ``edf`` for white FM: 2 (M-1)^2 / (3M-4).

    Raises
    ------
    ValueError
        Empty or non-1-D input, NaN/Inf, tau0 <= 0, m < 1 or m > N/2.

    References
    ----------
    D. W. Allan, Proc. IEEE 54(2) (1966); IEEE Std 1139-2008; NIST SP 1065 (2008), eq. 6-8.
    """
    arr, mu = _series(y)
    t0 = _tau0(tau0)
    ms = _m_list(m, arr.size, "adev")
    k = _kernels(engine, arr.size)
    x = _phase(arr, mu, k)
    ssq = _ssq_numpy_adev(x, ms) if k is None else k.adev_ssq(x, ms)
    del x
    return _result("adev", t0, ms, ssq, arr.size)


def oadev(
    y: ArrayLike, tau0: float, m: ArrayLike | int | None = None, *, engine: Engine = "auto"
) -> AllanResult:
    """Overlapping Allan deviation of frequency (rate) data.

    All N - 2m + 1 overlapping pairs of adjacent m-sample averages are used:

        sigma_y^2(m tau0) = 1 / (2 m^2 (N - 2m + 1)) sum_{j=0}^{N-2m} (x_{j+2m} - 2 x_{j+m} + x_j)^2

    with x the phase of the mean-removed y (x_0 = 0, x_{i+1} = x_i + y_i - mean(y)).  Same
    expectation as the non-overlapping ADEV, smaller variance (NIST SP 1065, sec. 5.2.4).

    Implementation: one phase array (N + 1 float64) and a single blocked sweep that, for
    every block of 2048 phase points, accumulates the squared second differences of all
    requested m; block partial sums are combined with compensated (Neumaier) summation.

    Parameters
    ----------
    y : array_like, shape (N,)
        Frequency / rate samples at interval ``tau0``; finite values only.
    tau0 : float
        Sampling interval (> 0).
    m : int or sequence of int, optional
        Averaging factors (sorted, de-duplicated); each needs N >= 2m.  Default
        ``octave_m(N)``.
    engine : {"auto", "numba", "numpy"}

    Returns
    -------
    AllanResult
        ``n_terms`` = N - 2m + 1; ``edf`` for white FM from :func:`edf_white_fm`.

    References
    ----------
    IEEE Std 1139-2008; D. A. Howe, D. W. Allan, J. A. Barnes, Proc. 35th Frequency Control
    Symposium (1981); NIST SP 1065 (2008), eq. 11.
    """
    arr, mu = _series(y)
    t0 = _tau0(tau0)
    ms = _m_list(m, arr.size, "oadev")
    k = _kernels(engine, arr.size)
    x = _phase(arr, mu, k)
    ssq = _ssq_numpy_oadev(x, ms) if k is None else _oadev_numba(k, x, ms)
    del x
    return _result("oadev", t0, ms, ssq, arr.size)


def mdev(
    y: ArrayLike, tau0: float, m: ArrayLike | int | None = None, *, engine: Engine = "auto"
) -> AllanResult:
    """Modified Allan deviation of frequency (rate) data.

        Mod sigma_y^2(m tau0) = 1 / (2 m^4 T) sum_{j=0}^{T-1}
                                [ sum_{i=j}^{j+m-1} (x_{i+2m} - 2 x_{i+m} + x_i) ]^2,
        T = N - 3m + 2,

    x being the phase of the mean-removed y.  The inner window sum is carried along j
    as a running sum (w_{j+1} = w_j + d_{j+m} - d_j, d_i the second difference), so each m
    costs one pass over the phase.  For m = 1 it equals the ADEV.

    Parameters
    ----------
    y, tau0, engine
        As for :func:`oadev`.
    m : int or sequence of int, optional
        Averaging factors; each needs N >= 3m - 1.  Default ``octave_m(N)``.

    References
    ----------
    D. W. Allan, J. A. Barnes, "A modified Allan variance with increased oscillator
    characterization ability", Proc. 35th Frequency Control Symposium (1981);
    NIST SP 1065 (2008), eq. 14.
    """
    arr, mu = _series(y)
    t0 = _tau0(tau0)
    ms = _m_list(m, arr.size, "mdev")
    k = _kernels(engine, arr.size)
    x = _phase(arr, mu, k)
    ssq = _ssq_numpy_mdev(x, ms) if k is None else k.mdev_ssq(x, ms)
    del x
    return _result("mdev", t0, ms, ssq, arr.size)


# --------------------------------------------------------------------------- block statistics


def _factor(factor: object) -> int:
    f = _as_int(factor, "factor")
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
    arr, _ = _series(y)
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
    arr, mu = _series(y)
    f = _factor(factor)
    M = arr.size // f
    if M < 2:
        raise ValueError(
            f"too few points: N = {arr.size} gives {M} block(s) of {f}; at least 2 are needed"
        )
    nb = max(1, _CHUNK // f)
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
    return fftconvolve(full, v, mode="valid") if v.size > 256 else np.convolve(full, v, mode="valid")


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
    M = _as_int(n_blocks, "n_blocks")
    f = _factor(factor)
    a = np.clip(np.asarray(coefficients, dtype=np.float64), 0.0, None)
    if a.shape != (5,):
        raise ValueError(f"coefficients must be the 5 values a_-2 .. a_2, got shape {a.shape}")
    if M < 2:
        raise ValueError(f"s^2 needs at least 2 block means, got {M}")
    j = np.arange(M, dtype=np.float64)
    gamma = np.zeros(M)
    gamma[0] += (2.0 / 3.0) * a[0] / f**2 + a[1] / f           # white PM: phase white, variance a_-2/3
    if M > 1:
        gamma[1] -= (1.0 / 3.0) * a[0] / f**2
    for k, c in ((0, a[2]), (1, a[3] * f)):                    # flicker FM, random-walk FM in block units
        if c > 0.0:
            gamma += c * (2.0 * _gacv(k, j) - _gacv(k, j - 1.0) - _gacv(k, j + 1.0))
    row = _toeplitz_times(gamma, np.ones(M))                   # S 1
    tot = float(row.sum())                                     # 1' S 1
    weights = M - j
    weights[1:] *= 2.0
    tr_cs = M * float(gamma[0]) - tot / M
    tr_cs2 = float(np.sum(weights * gamma * gamma)) - 2.0 * float(row @ row) / M + tot * tot / M**2
    mu = math.sqrt(2.0 * a[4]) * f * (j - j.mean())           # the ramp's centred block means
    smu = _toeplitz_times(gamma, mu)
    smu -= smu.mean()                                          # C S C mu (C mu = mu)
    e = tr_cs + float(mu @ mu)
    v = 2.0 * tr_cs2 + 4.0 * float(mu @ smu)
    if not v > 0.0:
        return math.inf, max(e, 0.0) / (M - 1)
    return 2.0 * e * e / v, e / (M - 1)


class BatchMeanU(NamedTuple):
    """What :func:`mean_u_batches` found: the u of the mean taken, its number of batches, whether the
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
    means are alike and the scatter of ``batches`` short ones understates the mean's u.  ``few`` long
    batches are compared with them; when (u_few/u)² exceeds the ``p`` point of F(few − 1, b − 1), the
    long batches' u is taken (``correlated``).  Used by GB/T 45570 D.5.1 (eq. D.40) and JJF 2014
    7.2.13 (eqs. (27), (28)); interpretations.md, "D.5.1 — correlated noise".  Needs ≥ 2·batches
    samples.
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
    arr, _ = _series(y)
    L = _as_int(levels, "levels")
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
    tmp = np.empty(_CHUNK)

    def stats(v: FloatArray) -> tuple[float, float]:
        a = 0.0
        b = 0.0
        for i0 in range(0, v.size, _CHUNK):
            t = tmp[: min(_CHUNK, v.size - i0)]
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
        for i0 in range(0, h, _CHUNK):
            i1 = min(i0 + _CHUNK, h)
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
    arr, mu = _series(y)
    t0 = _tau0(tau0)
    mb = _as_int(min_blocks, "min_blocks")
    if mb < 2:
        raise ValueError(f"min_blocks must be >= 2 (a sample standard deviation needs 2), got {mb}")
    n = arr.size
    if n < mb:
        raise ValueError(f"too few points: N = {n} < min_blocks = {mb}")
    nlev = 1
    while (n >> nlev) >= mb:
        nlev += 1
    if kmax is not None:
        km = _as_int(kmax, "kmax")
        if km < 1:
            raise ValueError(f"kmax must be >= 1, got {km}")
        nlev = min(nlev, km)
    k = _kernels(engine, n)
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

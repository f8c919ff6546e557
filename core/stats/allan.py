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

Speed (28.8 M samples, 24 octave factors, 2-core Xeon, see docs/performance.md):
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

Modules
-------
This module holds the deviations (:func:`adev`, :func:`oadev`, :func:`mdev`) and names the
rest: the shared checks, factor lists and result types are in
:mod:`metro.core.stats.allan_base`, degrees of freedom and covariances in
:mod:`metro.core.stats.allan_edf`, block statistics in :mod:`metro.core.stats.allan_blocks`.
"""

from __future__ import annotations

from types import ModuleType

import numpy as np
from numpy.typing import ArrayLike

from .allan_base import (
    CHUNK, AllanResult, BlockDoublingResult, Engine, FloatArray, IntArray, checked_series,
    checked_tau0, kernels, log_m, m_list, octave_m,
)
from .allan_blocks import (
    BatchMeanU, block_means, block_means_pyramid, block_std, block_variance_doubling,
    block_variance_dof, mean_u_batches,
)
from .allan_edf import edf_white_fm, oadev_covariance

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

#: block length of the compiled OADEV kernel
_BLOCK = 2048


# --------------------------------------------------------------------------- phase


def _phase_numpy(y: FloatArray, mu: float) -> FloatArray:
    x = np.empty(y.size + 1)
    x[0] = 0.0
    buf = np.empty(min(CHUNK, y.size))
    carry = 0.0
    for i0 in range(0, y.size, CHUNK):
        i1 = min(i0 + CHUNK, y.size)
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
    buf = np.empty(CHUNK)
    mlist = ms.tolist()
    for j0 in range(0, nx, CHUNK):
        for k, m in enumerate(mlist):
            j1 = min(j0 + CHUNK, nx - 2 * m)
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
    buf = np.empty(CHUNK)
    for k, m in enumerate(ms.tolist()):
        M = n // m
        xs = x[0 : M * m + 1 : m]  # M + 1 phase points at the block boundaries (a view)
        nterm = M - 1
        for i0 in range(0, nterm, CHUNK):
            i1 = min(i0 + CHUNK, nterm)
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
    da = np.empty(CHUNK)
    db = np.empty(CHUNK)

    def second_diff(i0: int, i1: int, m: int, b: FloatArray) -> FloatArray:
        b = b[: i1 - i0]
        np.multiply(x[i0 + m : i1 + m], -2.0, out=b)
        b += x[i0:i1]
        b += x[i0 + 2 * m : i1 + 2 * m]
        return b

    for k, m in enumerate(ms.tolist()):
        T = n - 3 * m + 2
        w = 0.0  # w_0 = sum_{i<m} d_i
        for i0 in range(0, m, CHUNK):
            w += float(np.sum(second_diff(i0, min(i0 + CHUNK, m), m, da)))
        tot = 0.0
        for j0 in range(0, T, CHUNK):
            j1 = min(j0 + CHUNK, T)
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


def _deviation(kind: str, y: ArrayLike, tau0: float, m: ArrayLike | int | None,
               engine: Engine) -> AllanResult:
    """The path adev, oadev and mdev share: check the series, the averaging factors, integrate
    to phase, then the kind's sums of squares (numba kernels when the engine has them)."""
    arr, mu = checked_series(y)
    t0 = checked_tau0(tau0)
    ms = m_list(m, arr.size, kind)
    k = kernels(engine, arr.size)
    x = _phase(arr, mu, k)
    if kind == "adev":
        ssq = _ssq_numpy_adev(x, ms) if k is None else k.adev_ssq(x, ms)
    elif kind == "oadev":
        ssq = _ssq_numpy_oadev(x, ms) if k is None else _oadev_numba(k, x, ms)
    else:
        ssq = _ssq_numpy_mdev(x, ms) if k is None else k.mdev_ssq(x, ms)
    del x
    return _result(kind, t0, ms, ssq, arr.size)


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
    return _deviation("adev", y, tau0, m, engine)


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
    return _deviation("oadev", y, tau0, m, engine)


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
    return _deviation("mdev", y, tau0, m, engine)

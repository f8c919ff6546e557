"""What the Allan statistics share (:mod:`metro.core.stats.allan`): the array types, the engine
choice (compiled kernels or numpy), the checks of a series, an interval and an integer argument,
the averaging-factor lists (:func:`octave_m`, :func:`log_m`, and their stopping rule) and the result
types (:class:`AllanResult`, :class:`BlockDoublingResult`).

The conventions (``y``, ``tau0``, ``m``) are those of :mod:`metro.core.stats.allan`.
"""

from __future__ import annotations

import math
import os
from types import ModuleType
from typing import Literal

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "FloatArray", "IntArray", "Engine", "NUMBA_MIN_N", "CHUNK", "kernels", "checked_series",
    "checked_tau0", "as_int", "m_list", "octave_m", "log_m", "AllanResult", "BlockDoublingResult",
]

FloatArray = NDArray[np.float64]
IntArray = NDArray[np.int64]
Engine = Literal["auto", "numba", "numpy"]

#: below this many samples ``engine="auto"`` uses numpy (no compile latency for small data)
NUMBA_MIN_N = 1 << 16
#: chunk length (samples) of the numpy fallback's work buffers
CHUNK = 1 << 15


# --------------------------------------------------------------------------- helpers


def readonly_copy(a: ArrayLike) -> np.ndarray:
    """A read-only copy of ``a`` (a result's arrays cannot be changed in place)."""
    arr = np.array(a, copy=True)
    arr.setflags(write=False)
    return arr


def kernels(engine: Engine, n: int) -> ModuleType | None:
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


def checked_series(y: ArrayLike, name: str = "y") -> tuple[FloatArray, float]:
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


def checked_tau0(tau0: float) -> float:
    """The sampling interval as a float; a non-finite or non-positive one is refused."""
    try:
        t = float(tau0)
    except (TypeError, ValueError):
        raise ValueError(f"tau0 must be a number, got {tau0!r}") from None
    if not math.isfinite(t) or t <= 0.0:
        raise ValueError(f"tau0 must be a finite positive number, got {tau0!r}")
    return t


def as_int(v: object, name: str) -> int:
    """``v`` as an int; a bool or a non-integral value of ``name`` is refused."""
    if isinstance(v, (bool, np.bool_)):
        raise ValueError(f"{name} must be an integer, got {v!r}")  # noqa: TRY004
    try:
        f = float(v)  # type: ignore[arg-type]
    except (TypeError, ValueError):
        raise ValueError(f"{name} must be an integer, got {v!r}") from None
    if not math.isfinite(f) or f != int(f):
        raise ValueError(f"{name} must be an integer, got {v!r}")
    return int(f)


def m_list(m: ArrayLike | int | None, n: int, kind: str) -> IntArray:
    """The averaging factors to evaluate: ``m`` checked (integers, 1 ≤ m and
    small enough for ``kind`` at N = ``n``), or the octave list."""
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
    n = as_int(n, "n")
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
    per_decade = as_int(per_decade, "per_decade")
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
    m: IntArray = attrs.field(converter=readonly_copy)
    tau: FloatArray = attrs.field(converter=readonly_copy)
    deviation: FloatArray = attrs.field(converter=readonly_copy)
    n_terms: IntArray = attrs.field(converter=readonly_copy)
    edf: FloatArray = attrs.field(converter=readonly_copy)
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
    tau: FloatArray = attrs.field(converter=readonly_copy)
    std: FloatArray = attrs.field(converter=readonly_copy)
    n_blocks: IntArray = attrs.field(converter=readonly_copy)

    @property
    def level(self) -> IntArray:
        """Level numbers k = 1 .. K."""
        return np.arange(1, self.std.size + 1, dtype=np.int64)

    @property
    def variance(self) -> FloatArray:
        """The variances of the block means at each level (squared standard deviations)."""
        return self.std**2

"""Least-squares sine fit at a known frequency (IEEE Std 1057 / 1241 "three-parameter" fit).

The model, for samples y_j at times t_j and a known angular frequency ω = 2πf, is::

    y_j = a·cos(ω t_j) + b·sin(ω t_j) [+ c] + e_j
        = E·cos(ω t_j + φ) [+ c] + e_j,      E = √(a² + b²),  φ = atan2(−b, a)

which is linear in (a, b[, c]) and solved by :func:`metro.core.stats.lsq.fit_linear` (QR, no
normal equations).  With ``offset=False`` it is the two-parameter fit (amplitude and phase
only) of JJF 2014—2022 eq. (40); with ``offset=True`` (default) a constant c is fitted as
well, which a signal with a DC level (a gyro's null voltage) needs.

The covariance of (E, φ) follows from that of (a, b) by first-order propagation with the
Jacobian ∂E/∂a = a/E, ∂E/∂b = b/E, ∂φ/∂a = b/E², ∂φ/∂b = −a/E²; it is scaled by the residual
variance (the noise is estimated from the data).

Pure functions on plain arrays; callers handle units.  Invalid input raises ``ValueError``.

References: IEEE Std 1057-2017 clause 8.5.1 (three-parameter sine fit, known frequency);
IEEE Std 1241-2010 clause 4.1.4.1.
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from numpy.typing import ArrayLike

from .lsq import fit_linear

__all__ = ["SineFit", "fit_sine", "wrap_phase"]


@attrs.frozen(eq=False)
class SineFit:
    """Result of :func:`fit_sine`: y ≈ E·cos(ωt + φ) + c."""

    #: the known frequency f the sine was fitted at, in Hz (with t in s); ω = 2πf
    frequency: float
    #: the amplitude E = √(a² + b²) > 0, in the unit of y
    amplitude: float
    #: the phase φ = atan2(−b, a) of E·cos(ωt + φ), in rad, in (−π, π]
    phase: float
    #: the fitted constant c, in the unit of y; 0.0 for a two-parameter fit (``offset=False``)
    offset: float
    #: the coefficient of cos(ωt), in the unit of y
    a: float
    #: the coefficient of sin(ωt), in the unit of y
    b: float
    #: the 3×3 covariance matrix of (a, b, c), scaled by the residual variance s²; the row and
    #: column of c are zero for a two-parameter fit
    cov_abc: np.ndarray
    #: the residual standard deviation s = √(SSR/ν), in the unit of y
    residual_sd: float
    #: the degrees of freedom ν = n − p of the residuals (p = 3 with the offset, 2 without)
    dof: int
    #: the number of samples fitted
    n: int

    @property
    def cov_amplitude_phase(self) -> np.ndarray:
        """2×2 covariance of (E, φ) (first-order propagation from (a, b))."""
        E2 = self.amplitude**2
        J = np.array([[self.a / self.amplitude, self.b / self.amplitude],
                      [self.b / E2, -self.a / E2]])
        return J @ self.cov_abc[:2, :2] @ J.T

    @property
    def u_amplitude(self) -> float:
        return float(math.sqrt(self.cov_amplitude_phase[0, 0]))

    @property
    def u_phase(self) -> float:
        return float(math.sqrt(self.cov_amplitude_phase[1, 1]))

    def predict(self, t: ArrayLike) -> np.ndarray:
        w = 2 * math.pi * self.frequency
        return self.amplitude * np.cos(w * np.asarray(t, dtype=float) + self.phase) + self.offset


def fit_sine(t: ArrayLike, y: ArrayLike, frequency: float, *, offset: bool = True) -> SineFit:
    """Fit E·cos(2πf·t + φ) [+ c] to (t, y) by linear least squares (IEEE 1057 8.5.1).

    :param t: sample times (s), 1-D, finite.
    :param y: samples, same length, finite.
    :param frequency: the known frequency f (Hz), > 0.
    :param offset: fit a constant c as well (three-parameter fit); False = two parameters.
    :raises ValueError: bad shapes, non-finite values, f ≤ 0, too few samples (< p + 1), or
        samples that do not resolve the sine (e.g. all at the same phase; singular design), or
        a fitted amplitude of zero (phase undefined).
    """
    tt = np.asarray(t, dtype=float)
    yy = np.asarray(y, dtype=float)
    if tt.ndim != 1 or yy.ndim != 1 or tt.size != yy.size:
        raise ValueError(f"t and y must be 1-D of the same length (got {tt.shape} and {yy.shape})")
    if not (math.isfinite(frequency) and frequency > 0):
        raise ValueError(f"the frequency must be finite and > 0, got {frequency!r}")
    if not (np.all(np.isfinite(tt)) and np.all(np.isfinite(yy))):
        raise ValueError("t or y contains NaN or Inf")
    w = 2 * math.pi * frequency
    cols = [np.cos(w * tt), np.sin(w * tt)]
    if offset:
        cols.append(np.ones_like(tt))
    A = np.column_stack(cols)
    fit = fit_linear(A, yy)  # raises ValueError on too few points / singular design
    a, b = float(fit.coef[0]), float(fit.coef[1])
    E = math.hypot(a, b)
    if E == 0.0:
        raise ValueError("the fitted amplitude is zero: the phase is undefined")
    cov = np.zeros((3, 3))
    p = 3 if offset else 2
    cov[:p, :p] = fit.cov
    return SineFit(frequency=float(frequency), amplitude=E, phase=math.atan2(-b, a),
                   offset=float(fit.coef[2]) if offset else 0.0, a=a, b=b, cov_abc=cov,
                   residual_sd=float(fit.residual_sd), dof=int(fit.dof), n=int(tt.size))


def wrap_phase(phi: ArrayLike) -> np.ndarray:
    """Phase(s) wrapped into (−π, π]."""
    p = np.asarray(phi, dtype=float)
    out = np.mod(p + math.pi, 2 * math.pi) - math.pi
    return np.where(out == -math.pi, math.pi, out)

"""Linear least squares: the fitting core used by every calibration model in metro.

The functions here solve the linear model

    y = A b + e,        E[e] = 0,   Cov[e] = s^2 V

for the coefficient vector ``b`` (length p) given a design matrix ``A`` (n x p) and the
observations ``y`` (length n).  Three flavours share one solver:

* ordinary least squares (OLS): V = I;
* weighted least squares (WLS): V = diag(1 / w), ``weights`` w_i = 1 / sigma_i^2;
* generalised least squares (GLS): V = ``cov_y`` (full, symmetric positive definite).

WLS and GLS are reduced to OLS by *whitening*: with V = L L^T (Cholesky) the system
L^-1 y = L^-1 A b + L^-1 e has uncorrelated errors of equal variance.  The whitened
problem is then solved by a Householder QR factorisation of the column-scaled design
matrix (each column divided by its Euclidean norm), which keeps full accuracy when the
columns differ by many orders of magnitude (e.g. 1, x, x^2 with x ~ 1e6).  Normal
equations are never formed, so the conditioning is that of A, not of A^T A.

All functions are pure: inputs are plain numpy arrays (callers handle units), nothing is
printed or written, and invalid input raises ``ValueError`` with a message saying what is
wrong.

References
----------
* G. H. Golub, C. F. Van Loan, *Matrix Computations*, 4th ed., Johns Hopkins, 2013,
  sections 5.3 (the full-rank least-squares problem) and 6.1 (weighting, column scaling).
* A. Bjorck, *Numerical Methods for Least Squares Problems*, SIAM, 1996, ch. 2 and 4
  (covariance of the estimate, generalised least squares by whitening).
* NIST Statistical Reference Datasets (StRD), linear regression, used by the tests as the
  certified reference (datasets Norris and Pontius).
"""

from __future__ import annotations

import math

import attrs
import numpy as np
from numpy.typing import ArrayLike, NDArray

__all__ = [
    "LinearFit",
    "fit_line",
    "fit_linear",
    "fit_polynomial",
    "polynomial_design",
]

FloatArray = NDArray[np.float64]


def _readonly(a: np.ndarray) -> np.ndarray:
    a = np.ascontiguousarray(a)
    a.setflags(write=False)
    return a


@attrs.frozen(eq=False)
class LinearFit:
    """Result of a linear least-squares fit ``y = A @ coef + e``.

    Attributes
    ----------
    coef : ndarray, shape (p,)
        Estimated coefficients b.
    cov : ndarray, shape (p, p)
        Covariance matrix of ``coef``.  With ``scale_cov=True`` (the default of the fitting
        functions) this is s^2 (A^T W A)^-1 with s^2 = SSR / dof, the classical estimate
        when the weights are only relative.  With ``scale_cov=False`` it is (A^T W A)^-1,
        the covariance implied by weights (or ``cov_y``) that are absolute variances.
    residuals : ndarray, shape (n,)
        Raw residuals y - A @ coef, in the units of y (not whitened, not weighted).
    dof : int
        Residual degrees of freedom n - p.
    residual_sd : float
        Residual standard deviation s = sqrt(SSR / dof), where SSR is the weighted sum of
        squared residuals r^T V^-1 r (the plain sum of squares for OLS).
    r2 : float
        Coefficient of determination 1 - SSR / SST.  SST is taken about the (weighted)
        mean of y when the design has a constant column (an intercept) and about zero
        otherwise (the NIST StRD convention for models without intercept).  Reported as
        1.0 when SST is zero.
    weighted : bool
        True when ``weights`` or ``cov_y`` were given.
    ssr : float
        Weighted sum of squared residuals r^T V^-1 r.
    """

    coef: FloatArray = attrs.field(converter=_readonly)
    cov: FloatArray = attrs.field(converter=_readonly)
    residuals: FloatArray = attrs.field(converter=_readonly)
    dof: int
    residual_sd: float
    r2: float
    weighted: bool
    ssr: float

    @property
    def stderr(self) -> FloatArray:
        """Standard uncertainties of the coefficients, sqrt(diag(cov))."""
        return np.sqrt(np.diag(self.cov))

    def predict(self, A: ArrayLike) -> FloatArray:
        """Fitted values ``A @ coef`` for a design matrix ``A`` of shape (k, p) or (p,).

        ``A`` must be built in the same basis as the fit (for :func:`fit_polynomial`, use
        :func:`polynomial_design` on the original x values).
        """
        A = np.asarray(A, dtype=np.float64)
        p = self.coef.shape[0]
        if A.shape[-1] != p:
            raise ValueError(
                f"design matrix has {A.shape[-1]} columns, the fit has {p} coefficients"
            )
        if not np.all(np.isfinite(A)):
            raise ValueError("design matrix contains NaN or Inf")
        return A @ self.coef


# --------------------------------------------------------------------------- validation


def _as_finite(name: str, a: ArrayLike, ndim: int) -> FloatArray:
    try:
        arr = np.asarray(a, dtype=np.float64)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be numeric: {exc}") from None
    if arr.ndim != ndim:
        raise ValueError(f"{name} must be {ndim}-dimensional, got shape {arr.shape}")
    if not np.all(np.isfinite(arr)):
        bad = np.argwhere(~np.isfinite(arr))[0]
        where = tuple(int(i) for i in bad)
        raise ValueError(
            f"{name} contains NaN or Inf (first at index {where if ndim > 1 else where[0]})"
        )
    return arr


def _has_constant_column(A: FloatArray) -> bool:
    first = A[0]
    return bool(np.any(np.all(A == first, axis=0) & (first != 0.0)))


def _checked_system(A: ArrayLike, y: ArrayLike) -> tuple[FloatArray, FloatArray]:
    """The design (a 1-D array as one column) and the observations of :func:`fit_linear` as
    finite float arrays, with at least one residual degree of freedom."""
    A_arr = _as_finite("A", np.reshape(A, (-1, 1)) if np.ndim(A) == 1 else A, 2)
    y_arr = _as_finite("y", y, 1)
    n, p = A_arr.shape
    if y_arr.shape[0] != n:
        raise ValueError(f"A has {n} rows but y has {y_arr.shape[0]} values")
    if p < 1:
        raise ValueError("A must have at least one column")
    if n < p + 1:
        raise ValueError(
            f"too few points: {n} observation(s) for {p} parameter(s); at least {p + 1} are "
            "needed (one residual degree of freedom)"
        )
    return A_arr, y_arr


def _whiten(
    A_arr: FloatArray, y_arr: FloatArray, weights: ArrayLike | None, cov_y: ArrayLike | None,
) -> tuple[FloatArray, FloatArray, FloatArray | None, FloatArray | None]:
    """The whitened system L^-1 A, L^-1 y of :func:`fit_linear` (V = L L^T; L = diag(1/sqrt(w))
    for WLS, the Cholesky factor of ``cov_y`` for GLS, I for OLS), with the weights and the
    Cholesky factor used (None when not given)."""
    from scipy import linalg as sla

    n = A_arr.shape[0]
    chol: FloatArray | None = None
    w: FloatArray | None = None
    if weights is not None:
        w = _as_finite("weights", weights, 1)
        if w.shape[0] != n:
            raise ValueError(f"weights has {w.shape[0]} values, expected {n}")
        if np.any(w <= 0.0):
            raise ValueError("weights must be strictly positive (w = 1/sigma^2)")
        sw = np.sqrt(w)
        Aw = A_arr * sw[:, None]
        yw = y_arr * sw
    elif cov_y is not None:
        V = _as_finite("cov_y", cov_y, 2)
        if V.shape != (n, n):
            raise ValueError(f"cov_y must have shape ({n}, {n}), got {V.shape}")
        scale = np.max(np.abs(V))
        if not np.allclose(V, V.T, rtol=1e-12, atol=1e-14 * scale):
            raise ValueError("cov_y must be symmetric")
        try:
            chol = sla.cholesky(V, lower=True, check_finite=False)
        except np.linalg.LinAlgError:
            raise ValueError("cov_y is not positive definite") from None
        Aw = sla.solve_triangular(chol, A_arr, lower=True, check_finite=False)
        yw = sla.solve_triangular(chol, y_arr, lower=True, check_finite=False)
    else:
        Aw = A_arr
        yw = y_arr
    return Aw, yw, w, chol


def _scaled_qr(Aw: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray, FloatArray]:
    """Column norms d, the column-scaled design Aw / d and its reduced Q R; a design of rank
    below its column count is refused (Golub & Van Loan sec. 5.3)."""
    n, p = Aw.shape
    norms = np.linalg.norm(Aw, axis=0)
    if np.any(norms == 0.0):
        k = int(np.flatnonzero(norms == 0.0)[0])
        raise ValueError(f"singular design matrix: column {k} is all zeros")
    As = Aw / norms
    Q, R = np.linalg.qr(As, mode="reduced")
    sv = np.linalg.svd(R, compute_uv=False)
    tol = max(n, p) * np.finfo(np.float64).eps * sv[0]
    if sv[-1] <= tol:
        rank = int(np.sum(sv > tol))
        cond = sv[0] / max(sv[-1], 1e-300)
        raise ValueError(
            f"singular design matrix: rank {rank} < {p} columns (columns are linearly "
            f"dependent; condition number of the column-scaled design ~ {cond:.3g})"
        )
    return norms, As, Q, R


def _total_ss(A_arr: FloatArray, y_arr: FloatArray, yw: FloatArray, w: FloatArray | None,
              chol: FloatArray | None) -> float:
    """The total sum of squares in the same (whitened) metric as SSR: about the weighted mean
    when the design has a constant column, about zero otherwise (for R^2)."""
    from scipy import linalg as sla

    n = y_arr.shape[0]
    if _has_constant_column(A_arr):
        if w is not None:
            ybar = float(np.sum(w * y_arr) / np.sum(w))
            return float(np.sum(w * (y_arr - ybar) ** 2))
        if chol is not None:
            ow = sla.solve_triangular(chol, np.ones(n), lower=True, check_finite=False)
            ybar = float(ow @ yw / (ow @ ow))
            dev = yw - ybar * ow
            return float(dev @ dev)
        dev = y_arr - np.mean(y_arr)
        return float(dev @ dev)
    return float(yw @ yw)


# --------------------------------------------------------------------------- solver


def fit_linear(A: ArrayLike, y: ArrayLike, *, weights: ArrayLike | None = None,
               cov_y: ArrayLike | None = None, scale_cov: bool = True) -> LinearFit:
    """Least-squares solution of ``y = A b + e`` (OLS, WLS or GLS).

    The estimate minimises (y - A b)^T V^-1 (y - A b), with V = I (OLS),
    V = diag(1/weights) (WLS) or V = ``cov_y`` (GLS):

        b_hat = (A^T V^-1 A)^-1 A^T V^-1 y,
        Cov[b_hat] = s^2 (A^T V^-1 A)^-1,     s^2 = SSR / (n - p)   (``scale_cov=True``)
        Cov[b_hat] = (A^T V^-1 A)^-1                                (``scale_cov=False``)

    It is computed without normal equations: V = L L^T is factorised (L = diag(1/sqrt(w))
    for WLS), the whitened system L^-1 A, L^-1 y is column-scaled by the column norms
    d_k = ||(L^-1 A)_k||, factorised as Q R, and R z = Q^T L^-1 y is solved; then
    b = z / d and Cov = (R^T R)^-1 / (d d^T) (times s^2).  The accuracy is governed by the
    condition number of the column-scaled whitened design, not by its square.

    Parameters
    ----------
    A : array_like, shape (n, p) or (n,)
        Design matrix (a 1-D array is a single column).
    y : array_like, shape (n,)
        Observations.
    weights : array_like, shape (n,), optional
        Positive weights w_i = 1 / sigma_i^2 (WLS).  Exclusive with ``cov_y``.
    cov_y : array_like, shape (n, n), optional
        Covariance matrix of y, symmetric positive definite (GLS).  Exclusive with
        ``weights``.
    scale_cov : bool, default True
        Scale the covariance by s^2 = SSR/dof (relative weights, unknown variance).  Use
        False when ``weights`` / ``cov_y`` are absolute variances.

    Returns
    -------
    LinearFit

    Raises
    ------
    ValueError
        Non-finite input, shape mismatch, fewer than p + 1 points (at least one residual
        degree of freedom is required), a rank-deficient (singular) design matrix,
        non-positive weights, a ``cov_y`` that is not symmetric positive definite, or both
        ``weights`` and ``cov_y`` given.

    References
    ----------
    Golub & Van Loan, *Matrix Computations* (2013), sec. 5.3; Bjorck, *Numerical Methods
    for Least Squares Problems* (1996), sec. 4.1 (GLS by whitening).
    """
    from scipy import linalg as sla  # here, not at import: loading the plugins needs no scipy

    A_arr, y_arr = _checked_system(A, y)
    n, p = A_arr.shape
    if weights is not None and cov_y is not None:
        raise ValueError("give either weights or cov_y, not both")

    Aw, yw, w, chol = _whiten(A_arr, y_arr, weights, cov_y)
    norms, As, Q, R = _scaled_qr(Aw)
    z = sla.solve_triangular(R, Q.T @ yw, lower=False, check_finite=False)
    coef = z / norms

    resid_w = yw - As @ z
    ssr = float(resid_w @ resid_w)
    dof = n - p
    s2 = ssr / dof

    Rinv = sla.solve_triangular(R, np.eye(p), lower=False, check_finite=False)
    cov = (Rinv @ Rinv.T) / np.outer(norms, norms)
    if scale_cov:
        cov = cov * s2
    cov = 0.5 * (cov + cov.T)

    residuals = y_arr - A_arr @ coef

    sst = _total_ss(A_arr, y_arr, yw, w, chol)
    r2 = 1.0 if sst == 0.0 else 1.0 - ssr / sst

    return LinearFit(
        coef=coef,
        cov=cov,
        residuals=residuals,
        dof=dof,
        residual_sd=math.sqrt(s2),
        r2=r2,
        weighted=(weights is not None or cov_y is not None),
        ssr=ssr,
    )


# --------------------------------------------------------------------------- polynomials


def polynomial_design(x: ArrayLike, degree: int) -> FloatArray:
    """Design matrix [1, x, x^2, ..., x^degree] (shape (n, degree + 1)) for ``predict``."""
    x_arr = _as_finite("x", x, 1)
    if isinstance(degree, bool) or int(degree) != degree or degree < 0:
        raise ValueError(f"degree must be a non-negative integer, got {degree!r}")
    return np.vander(x_arr, int(degree) + 1, increasing=True)


def _basis_change(center: float, scale: float, p: int) -> FloatArray:
    """Matrix T with a = T b, where sum_k b_k ((x - c)/s)^k == sum_j a_j x^j."""
    T = np.zeros((p, p))
    for k in range(p):
        inv = 1.0 / scale**k
        for j in range(k + 1):
            T[j, k] = math.comb(k, j) * (-center) ** (k - j) * inv
    return T


def fit_polynomial(
    x: ArrayLike,
    y: ArrayLike,
    degree: int,
    *,
    weights: ArrayLike | None = None,
    cov_y: ArrayLike | None = None,
    scale_cov: bool = True,
    center: bool = True,
) -> LinearFit:
    """Least-squares polynomial y = c0 + c1 x + ... + c_d x^d (via :func:`fit_linear`).

    With ``center=True`` (default) the fit is done in the variable t = (x - x_c) / h,
    x_c = (max x + min x)/2, h = (max x - min x)/2, which keeps the design well conditioned
    for data far from the origin.  The coefficients b of the t-polynomial are then mapped
    to the original basis by a = T b with

        T[j, k] = C(k, j) (-x_c)^(k-j) / h^k      (j <= k),

    and the covariance by Cov[a] = T Cov[b] T^T (exact linear propagation).  Residuals,
    SSR, residual SD and R^2 come from the well-conditioned t-fit and do not depend on the
    basis.  Note that the monomial coefficients themselves can be intrinsically
    ill-conditioned when |x_c| >> h; the fitted values are not.

    Parameters
    ----------
    x, y : array_like, shape (n,)
    degree : int
        Polynomial degree d >= 0 (d + 2 points at least are required).
    weights, cov_y, scale_cov
        As for :func:`fit_linear`.
    center : bool, default True
        Centre and scale x internally (recommended).  With False the raw monomials are
        used (``fit_linear`` still scales each column by its norm).

    Returns
    -------
    LinearFit
        ``coef`` = (c0, c1, ..., c_d) in the original x basis; use
        ``fit.predict(polynomial_design(x_new, degree))`` for fitted values.
    """
    x_arr = _as_finite("x", x, 1)
    if isinstance(degree, bool) or int(degree) != degree or degree < 0:
        raise ValueError(f"degree must be a non-negative integer, got {degree!r}")
    degree = int(degree)
    p = degree + 1
    y_arr = _as_finite("y", y, 1)
    if y_arr.shape[0] != x_arr.shape[0]:
        raise ValueError(f"x has {x_arr.shape[0]} values but y has {y_arr.shape[0]}")
    if x_arr.shape[0] < p + 1:
        raise ValueError(
            f"too few points: {x_arr.shape[0]} for a degree-{degree} polynomial; at least "
            f"{p + 1} are needed"
        )
    if center:
        lo, hi = float(np.min(x_arr)), float(np.max(x_arr))
        xc = 0.5 * (lo + hi)
        h = 0.5 * (hi - lo)
        if h == 0.0:
            if degree > 0:
                raise ValueError(
                    f"singular design matrix: all x values are equal, cannot fit degree {degree}"
                )
            h = 1.0
    else:
        xc, h = 0.0, 1.0
    t = (x_arr - xc) / h if center else x_arr
    fit = fit_linear(
        np.vander(t, p, increasing=True), y_arr, weights=weights, cov_y=cov_y, scale_cov=scale_cov
    )
    if not center:
        return fit
    T = _basis_change(xc, h, p)
    coef = T @ fit.coef
    cov = T @ fit.cov @ T.T
    cov = 0.5 * (cov + cov.T)
    return attrs.evolve(fit, coef=coef, cov=cov)


def fit_line(x: ArrayLike, y: ArrayLike, **kw) -> LinearFit:
    """Straight line y = b0 + b1 x; ``coef`` = (intercept, slope).

    Shorthand for ``fit_polynomial(x, y, 1, **kw)``; keyword arguments as there
    (``weights``, ``cov_y``, ``scale_cov``, ``center``).
    """
    return fit_polynomial(x, y, 1, **kw)

"""Tests for metro.core.stats.lsq against NIST StRD certified values and independent computations.

Reference data: NIST Statistical Reference Datasets (public domain), copied verbatim into
tests/data/nist/ so a clean clone has them.
"""

from __future__ import annotations

import re
from pathlib import Path

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from metro.core.stats.lsq import LinearFit, fit_line, fit_linear, fit_polynomial, polynomial_design

NIST = Path(__file__).resolve().parents[2] / "data" / "nist"


def _num(s: str) -> float:
    return float(s.replace("D", "E"))


# --------------------------------------------------------------------------- NIST StRD


def _read_norris():
    """Norris.dat: certified values in the header (lines 31-37), data from line 61 (y x)."""
    lines = (NIST / "Norris.dat").read_text().splitlines()
    text = "\n".join(lines[:60])
    num = r"([-+]?\d*\.\d+(?:[EeDd][-+]?\d+)?)"
    b0 = re.search(rf"^\s*B0\s+{num}\s+{num}", text, re.MULTILINE)
    b1 = re.search(rf"^\s*B1\s+{num}\s+{num}", text, re.MULTILINE)
    rsd = re.search(rf"Residual\s*\n\s*Standard Deviation\s+{num}", text)
    r2 = re.search(rf"R-Squared\s+{num}", text)
    cert = {
        "B0": _num(b0.group(1)),
        "sdB0": _num(b0.group(2)),
        "B1": _num(b1.group(1)),
        "sdB1": _num(b1.group(2)),
        "rsd": _num(rsd.group(1)),
        "r2": _num(r2.group(1)),
    }
    data = np.array([[float(v) for v in ln.split()] for ln in lines[60:] if ln.strip()])
    return cert, data[:, 1], data[:, 0]


def _read_pontius():
    """Pontius.dat (metro's copy): '#' header with 'Bk estimate sd' lines and the RSS."""
    text = (NIST / "Pontius.dat").read_text()
    cert = {}
    for k, est, sd in re.findall(r"^#\s*B(\d)\s+(\S+)\s+(\S+)", text, re.MULTILINE):
        cert[f"B{k}"] = _num(est)
        cert[f"sdB{k}"] = _num(sd)
    cert["rss"] = _num(re.search(r"residual sum of squares\s+(\S+)", text).group(1))
    data = np.loadtxt(NIST / "Pontius.dat", comments="#")
    return cert, data[:, 1], data[:, 0]


def test_nist_norris_certified_values():
    # NIST StRD Norris (linear, lower difficulty); certified to 15 digits.  Tolerance 1e-12 rel.
    cert, x, y = _read_norris()
    assert x.size == 36
    fit = fit_line(x, y)
    rtol = 1e-12
    assert fit.coef[0] == pytest.approx(cert["B0"], rel=rtol)
    assert fit.coef[1] == pytest.approx(cert["B1"], rel=rtol)
    assert fit.stderr[0] == pytest.approx(cert["sdB0"], rel=rtol)
    assert fit.stderr[1] == pytest.approx(cert["sdB1"], rel=rtol)
    assert fit.residual_sd == pytest.approx(cert["rsd"], rel=rtol)
    assert fit.r2 == pytest.approx(cert["r2"], rel=rtol)
    assert fit.dof == 34
    assert not fit.weighted


def test_nist_norris_uncentred_design():
    # Same certified values with the raw [1, x] design through fit_linear.
    cert, x, y = _read_norris()
    fit = fit_linear(np.column_stack([np.ones_like(x), x]), y)
    np.testing.assert_allclose(fit.coef, [cert["B0"], cert["B1"]], rtol=1e-12)
    np.testing.assert_allclose(fit.stderr, [cert["sdB0"], cert["sdB1"]], rtol=1e-12)
    assert fit.residual_sd == pytest.approx(cert["rsd"], rel=1e-12)
    assert fit.r2 == pytest.approx(cert["r2"], rel=1e-12)


@pytest.mark.parametrize("center", [True, False])
def test_nist_pontius_quadratic(center):
    # NIST StRD Pontius (quadratic, x up to 3e6 so x^2 ~ 1e13: badly scaled).  1e-10 rel.
    cert, x, y = _read_pontius()
    assert x.size == 40
    fit = fit_polynomial(x, y, 2, center=center)
    rtol = 1e-10
    for k in range(3):
        assert fit.coef[k] == pytest.approx(cert[f"B{k}"], rel=rtol)
        assert fit.stderr[k] == pytest.approx(cert[f"sdB{k}"], rel=rtol)
    assert fit.ssr == pytest.approx(cert["rss"], rel=rtol)
    assert fit.residual_sd == pytest.approx(np.sqrt(cert["rss"] / 37), rel=rtol)


# --------------------------------------------------------------------------- small cases


def test_hand_worked_three_points():
    # x = 0, 1, 2; y = 1, 3, 2.  Sxx = 2, Sxy = 1 -> slope 0.5, intercept 1.5;
    # residuals -0.5, 1, -0.5; SSR = 1.5, dof = 1, s^2 = 1.5;
    # var(b1) = s^2/Sxx = 0.75, var(b0) = s^2 (1/3 + 1/2) = 1.25, cov = -xbar s^2/Sxx = -0.75;
    # SST = 2 -> R^2 = 0.25.
    fit = fit_line([0.0, 1.0, 2.0], [1.0, 3.0, 2.0])
    np.testing.assert_allclose(fit.coef, [1.5, 0.5], rtol=1e-14)
    np.testing.assert_allclose(fit.residuals, [-0.5, 1.0, -0.5], atol=1e-14)
    assert fit.ssr == pytest.approx(1.5, rel=1e-14)
    assert fit.dof == 1
    assert fit.residual_sd == pytest.approx(np.sqrt(1.5), rel=1e-14)
    np.testing.assert_allclose(fit.cov, [[1.25, -0.75], [-0.75, 0.75]], rtol=1e-13)
    assert fit.r2 == pytest.approx(0.25, rel=1e-13)
    np.testing.assert_allclose(fit.predict(polynomial_design([3.0], 1)), [3.0], rtol=1e-14)


def _random_problem(seed, n=30, p=3):
    rng = np.random.default_rng(seed)
    A = np.column_stack([np.ones(n), rng.normal(size=(n, p - 1))])
    y = A @ rng.normal(size=p) + rng.normal(scale=0.3, size=n)
    return A, y, rng


def test_wls_against_normal_equations():
    A, y, rng = _random_problem(1)
    w = rng.uniform(0.5, 4.0, size=y.size)
    fit = fit_linear(A, y, weights=w, scale_cov=False)
    N = A.T @ (w[:, None] * A)
    b = np.linalg.solve(N, A.T @ (w * y))
    np.testing.assert_allclose(fit.coef, b, rtol=1e-12)
    np.testing.assert_allclose(fit.cov, np.linalg.inv(N), rtol=1e-12)
    r = y - A @ b
    ssr = float(np.sum(w * r * r))
    assert fit.ssr == pytest.approx(ssr, rel=1e-12)
    np.testing.assert_allclose(fit.residuals, r, atol=1e-12)
    assert fit.weighted
    scaled = fit_linear(A, y, weights=w)
    np.testing.assert_allclose(scaled.cov, np.linalg.inv(N) * ssr / (y.size - 3), rtol=1e-12)
    ybar = np.sum(w * y) / np.sum(w)
    assert fit.r2 == pytest.approx(1 - ssr / np.sum(w * (y - ybar) ** 2), rel=1e-12)


def test_gls_with_diagonal_cov_equals_wls():
    A, y, rng = _random_problem(2)
    w = rng.uniform(0.2, 5.0, size=y.size)
    for scale_cov in (True, False):
        wls = fit_linear(A, y, weights=w, scale_cov=scale_cov)
        gls = fit_linear(A, y, cov_y=np.diag(1.0 / w), scale_cov=scale_cov)
        np.testing.assert_allclose(gls.coef, wls.coef, rtol=1e-12)
        np.testing.assert_allclose(gls.cov, wls.cov, rtol=1e-11)
        assert gls.ssr == pytest.approx(wls.ssr, rel=1e-12)
        assert gls.r2 == pytest.approx(wls.r2, rel=1e-12)
        np.testing.assert_allclose(gls.residuals, wls.residuals, atol=1e-12)


def test_gls_full_covariance_against_normal_equations():
    A, y, _ = _random_problem(3, n=20)
    # AR(1)-like correlated errors
    idx = np.arange(y.size)
    V = 0.09 * 0.6 ** np.abs(idx[:, None] - idx[None, :])
    fit = fit_linear(A, y, cov_y=V, scale_cov=False)
    Vi = np.linalg.inv(V)
    N = A.T @ Vi @ A
    b = np.linalg.solve(N, A.T @ Vi @ y)
    np.testing.assert_allclose(fit.coef, b, rtol=1e-11)
    np.testing.assert_allclose(fit.cov, np.linalg.inv(N), rtol=1e-11)
    r = y - A @ b
    assert fit.ssr == pytest.approx(float(r @ Vi @ r), rel=1e-11)


def test_no_intercept_r2_is_uncentred():
    # NIST convention for models without a constant term: R^2 = 1 - SSR / sum(y^2).
    x = np.array([1.0, 2.0, 3.0, 4.0, 5.0])
    y = np.array([2.1, 3.9, 6.2, 7.8, 10.1])
    fit = fit_linear(x, y)
    b = (x @ y) / (x @ x)
    assert fit.coef[0] == pytest.approx(b, rel=1e-14)
    ssr = np.sum((y - b * x) ** 2)
    assert fit.r2 == pytest.approx(1 - ssr / np.sum(y * y), rel=1e-13)


def test_polynomial_covariance_transform_matches_raw_basis():
    rng = np.random.default_rng(4)
    x = np.linspace(1000.0, 1010.0, 25)
    y = 3.0 - 0.2 * (x - 1000) + 0.05 * (x - 1000) ** 2 + rng.normal(scale=0.01, size=x.size)
    centred = fit_polynomial(x, y, 2)
    t = x - 1000.0
    ref = fit_polynomial(t, y, 2, center=False)
    # map the t-basis reference to the x basis: c(x) = sum b_k (x - 1000)^k
    T = np.array([[1, -1000.0, 1000.0**2], [0, 1, -2000.0], [0, 0, 1]])
    np.testing.assert_allclose(centred.coef, T @ ref.coef, rtol=1e-9)
    np.testing.assert_allclose(centred.cov, T @ ref.cov @ T.T, rtol=1e-7)
    # fitted values: exact from the residuals; through monomials at x ~ 1000 a few digits go
    np.testing.assert_allclose(centred.residuals, ref.residuals, rtol=0, atol=1e-12)
    np.testing.assert_allclose(
        centred.predict(polynomial_design(x, 2)), ref.predict(polynomial_design(t, 2)), rtol=1e-9
    )
    assert centred.residual_sd == pytest.approx(ref.residual_sd, rel=1e-12)


def test_result_is_frozen_and_readonly():
    fit = fit_line([0.0, 1.0, 2.0, 3.0], [0.1, 0.9, 2.1, 2.9])
    assert isinstance(fit, LinearFit)
    with pytest.raises(AttributeError):
        fit.dof = 3  # type: ignore[misc]
    with pytest.raises(ValueError):
        fit.coef[0] = 1.0


# --------------------------------------------------------------------------- properties


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    degree=st.integers(0, 3),
    coef=st.lists(st.floats(-10, 10, allow_nan=False), min_size=4, max_size=4),
    lo=st.floats(-1e3, 1e3, allow_nan=False),
    width=st.floats(1.0, 1e3, allow_nan=False),
    extra=st.integers(1, 20),
)
def test_exact_polynomial_is_recovered(degree, coef, lo, width, extra):
    n = degree + 1 + extra
    x = np.linspace(lo, lo + width, n)
    c = np.array(coef[: degree + 1])
    y = polynomial_design(x, degree) @ c
    fit = fit_polynomial(x, y, degree)
    scale = np.max(np.abs(y)) + 1.0
    np.testing.assert_allclose(
        fit.predict(polynomial_design(x, degree)), y, rtol=0, atol=1e-9 * scale
    )
    assert fit.residual_sd <= 1e-9 * scale
    # coefficients: compare in the centred basis where the problem is well conditioned
    xc = lo + width / 2
    ref = fit_polynomial(x - xc, y, degree, center=False)
    shifted = fit_polynomial(x - xc, polynomial_design(x, degree) @ c, degree)
    np.testing.assert_allclose(shifted.coef, ref.coef, rtol=1e-7, atol=1e-9 * scale)


@settings(max_examples=60, deadline=None, derandomize=True)
@given(
    seed=st.integers(0, 2**32 - 1),
    exponents=st.lists(st.integers(-8, 8), min_size=3, max_size=3),
)
def test_fitted_values_invariant_under_column_rescaling(seed, exponents):
    A, y, _ = _random_problem(seed, n=15, p=3)
    d = 10.0 ** np.array(exponents, dtype=float)
    base = fit_linear(A, y)
    scaled = fit_linear(A * d, y)
    np.testing.assert_allclose(scaled.predict(A * d), base.predict(A), rtol=1e-10, atol=1e-12)
    np.testing.assert_allclose(scaled.coef * d, base.coef, rtol=1e-9, atol=1e-12)
    np.testing.assert_allclose(scaled.stderr * d, base.stderr, rtol=1e-9)
    assert scaled.residual_sd == pytest.approx(base.residual_sd, rel=1e-9)


# --------------------------------------------------------------------------- errors


def test_error_non_finite():
    with pytest.raises(ValueError, match="NaN or Inf"):
        fit_line([0.0, 1.0, 2.0], [1.0, np.nan, 2.0])
    with pytest.raises(ValueError, match="NaN or Inf"):
        fit_linear(np.array([[1.0, np.inf], [1.0, 2.0], [1.0, 3.0]]), [1.0, 2.0, 3.0])
    with pytest.raises(ValueError, match="NaN or Inf"):
        fit_line([0.0, 1.0, 2.0], [1.0, 2.0, 2.0], weights=[1.0, np.nan, 1.0])


def test_error_too_few_points():
    with pytest.raises(ValueError, match="at least 3 are needed"):
        fit_linear(np.ones((2, 2)) + np.eye(2), [1.0, 2.0])
    with pytest.raises(ValueError, match="at least 4"):
        fit_polynomial([0.0, 1.0, 2.0], [1.0, 2.0, 0.0], 2)


def test_error_rank_deficient():
    x = np.arange(6.0)
    A = np.column_stack([np.ones(6), x, 2 * x])
    with pytest.raises(ValueError, match="singular design"):
        fit_linear(A, x**2)
    with pytest.raises(ValueError, match="singular design"):
        fit_linear(np.column_stack([np.ones(6), np.zeros(6)]), x)
    with pytest.raises(ValueError, match="all x values are equal"):
        fit_line(np.full(5, 3.0), x[:5])


def test_error_bad_weights_and_covariance():
    x = np.arange(5.0)
    y = 2 * x + 1
    with pytest.raises(ValueError, match="strictly positive"):
        fit_line(x, y, weights=[1, 1, 0, 1, 1])
    with pytest.raises(ValueError, match="not both"):
        fit_line(x, y, weights=np.ones(5), cov_y=np.eye(5))
    with pytest.raises(ValueError, match="positive definite"):
        fit_line(x, y, cov_y=-np.eye(5))
    with pytest.raises(ValueError, match="symmetric"):
        fit_line(x, y, cov_y=np.eye(5) + np.triu(np.ones((5, 5)), 1))
    with pytest.raises(ValueError, match="shape"):
        fit_line(x, y, cov_y=np.eye(4))
    with pytest.raises(ValueError, match="rows but y has"):
        fit_linear(np.ones((5, 1)), np.ones(4))
    with pytest.raises(ValueError, match="degree"):
        fit_polynomial(x, y, -1)

"""metro.core.uncertainty.selection: the largest of noisy slopes and changes (interpretations.md,
"D.1.5 / D.2.5 / D.5.4 — the largest of several noisy slopes" and "JJF 2014 — the largest of noisy
slopes and changes")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from metro.core.uncertainty.selection import (max_abs_selection, max_slope_selection,
                                              selection_rows, spread_rows, upper_sigma)


def test_upper_sigma_against_chi_square_table():
    """One-sided 95 % upper limit of σ, s·√(ν/χ²₀.₀₅(ν)); χ²₀.₀₅ from the printed table
    (NIST/SEMATECH e-Handbook 1.3.6.7.4, lower tail 0.05): ν = 2: 0.103, ν = 5: 1.145 (3 digits)."""
    assert upper_sigma(1.0, 2) == pytest.approx(math.sqrt(2 / 0.103), rel=3e-3)  # 0.103 is rounded
    assert upper_sigma(2.0, 5) == pytest.approx(2 * math.sqrt(5 / 1.145), rel=2e-3)


def test_largest_change_over_axes_reads_high_and_is_corrected():
    """Three axes' changes d_j ~ N(δ_j, 1), δ = (−0.53, 0.88, 0.35): max_j |d_j| reads high by ≈ 0.7
    (hand simulation, 1000 draws: +0.68); the corrected value by less than half as much."""
    delta, truth = np.array([-0.53, 0.88, 0.35]), 0.88
    rng = np.random.default_rng(11)
    printed, corrected = [], []
    for i in range(400):
        sel = max_abs_selection(rng.normal(delta, 1.0), [1.0] * 3, draws=1000, seed=i)
        printed.append(sel.printed)
        corrected.append(max(sel.value, 0.0))
        assert sel.degree == -2 and sel.scatter is None and sel.s > 0
    high = np.mean(printed) - truth
    assert high > 0.5
    assert abs(np.mean(corrected) - truth) < 0.45 * high


def test_largest_change_drawn_with_at_most_what_the_calibrations_show():
    """A stated u (K_r·K) far above the scatter of the calibrations that estimate one K (the K
    before the test on every axis): the draws use the 95 % upper limit of that scatter, the
    correction shrinks accordingly; with a scatter as large as u the stated u stays."""
    d, u = [0.005, 0.003, 0.002], [0.0057] * 3
    big = max_abs_selection(d, u)
    small = max_abs_selection(d, u, same=[23.0, 23.0 + 1e-6, 23.0 - 1e-6])
    assert big.bias > 1e-3 and big.scatter is None
    assert small.scatter == pytest.approx(math.sqrt(2) * upper_sigma(1e-6, 2), rel=1e-6)
    assert abs(small.bias) < 1e-4
    same_as_u = max_abs_selection(d, u, same=[23.0, 23.01, 22.99])  # s = 0.01 > 0.0057/√2
    assert same_as_u.scatter is None and same_as_u.bias == pytest.approx(big.bias, rel=1e-9)


def test_largest_slope_with_observed_scatter():
    """Points on a line within 10⁻⁷ but stated u 10⁻⁴ (a repeatability the chamber's points do not
    carry): with ``observed`` the draws use the points' own scatter and the correction is
    negligible; without, it is the selection bias of u = 10⁻⁴ noise."""
    T = [-40.0, -10.0, 20.0, 40.0, 60.0]
    rng = np.random.default_rng(3)
    K = [1.0 + 1.5e-4 * (t - 20.0) + e for t, e in zip(T, rng.normal(0.0, 1e-7, 5))]
    stated = max_slope_selection(K, [1e-4] * 5, T, 2, relative=True)
    seen = max_slope_selection(K, [1e-4] * 5, T, 2, relative=True, observed=True)
    assert stated.bias > 1e-6 and stated.scatter is None
    assert seen.scatter is not None and seen.scatter < 1e-6 and abs(seen.bias) < 0.05 * stated.bias
    assert seen.value == pytest.approx(1.5e-4, rel=1e-3)


def test_rows_of_a_correction():
    sel = max_abs_selection([3.0, 0.5, 0.2], [1.0] * 3)
    rows = selection_rows(sel, 3, "deg/h", slopes=False)
    assert len(rows) == 1 and rows[0].distribution == "uniform" and "noisy changes" in rows[
        0].source
    assert rows[0].contribution.m_as("deg/h") == pytest.approx(abs(sel.bias) / math.sqrt(3),
                                                               rel=1e-9)
    assert spread_rows(sel, 10.0, "deg/h") == []
    extra = spread_rows(sel, 0.1, "deg/h")
    assert extra[0].contribution.m_as("deg/h") == pytest.approx(math.sqrt(sel.s ** 2 - 0.01),
                                                                rel=1e-9)


def test_absolute_value_of_one_difference_in_closed_form():
    """GB/T 45570 D.44 / D.47 / D.48 take |one noisy difference|; :func:`abs_change` gives its bias
    in closed form about δ̂ = √max(0, d² − u²). Checked against scipy's folded normal (an
    independent implementation of E|N(δ̂, u²)|), against the Monte Carlo of
    :func:`max_abs_selection` with one value (400 000 draws, 3 σ of the draws' mean ≈ 0.003 u), and
    by hand at d = 0: bias = u·√(2/π)."""
    from scipy.stats import foldnorm

    from metro.core.uncertainty.selection import abs_change

    assert abs_change(0.0, 2.0).bias == pytest.approx(2.0 * math.sqrt(2.0 / math.pi), rel=1e-12)
    for d, u in ((0.0, 1.0), (0.5, 1.0), (-1.2, 1.0), (3.0, 1.0), (-0.04, 0.01), (7.0, 1.0)):
        sel = abs_change(d, u)
        m = math.sqrt(max(0.0, d * d - u * u))
        expected = foldnorm.mean(m / u, scale=u) - m
        assert sel.bias == (pytest.approx(expected, rel=1e-9) if expected >= 1e-3 * u else 0.0)
        assert sel.s == pytest.approx(foldnorm.std(m / u, scale=u), rel=1e-6, abs=1e-12)
        assert (
            sel.printed == abs(d)
            and sel.value == pytest.approx(abs(d) - sel.bias)
            and sel.degree == -3
        )
        mc = max_abs_selection([d], [u], draws=400_000, seed=3)
        assert sel.bias == pytest.approx(mc.bias, abs=0.003 * u)
    assert abs_change(0.3, 0.0).bias == 0.0 and abs_change(0.3, 0.0).value == 0.3
    # a change of 5 u: the bias (1.8e-7 u) is no correction — value, row and note as the formula's
    assert abs_change(5.0, 1.0).bias == 0.0 and abs_change(5.0, 1.0).value == 5.0


def test_absolute_value_of_one_difference_reads_high_and_is_corrected():
    """Over noise draws d ~ N(δ, 1), U = 2·u_c: |d| reads high by E|d| − |δ| (0.80 at δ = 0, 0.40 at
    0.5; folded normal), mean E_n = (|d| − δ)/U +0.40 at δ = 0. The corrected value (≥ 0) with the
    correction's row (normal, √(u·bias + bias²/4)): mean E_n at most +0.25 at every δ, and on every
    draw where |d| ± 2u held δ, the corrected value's U holds it too (its interval contains the
    formula's)."""
    from scipy.stats import foldnorm

    from metro.core.uncertainty.selection import abs_change, abs_change_rows

    rng = np.random.default_rng(45570)
    for delta in (0.0, 0.5, 1.0, 2.0, 2.5, 3.0, 4.0):
        d = rng.normal(delta, 1.0, 8000)
        sels = [abs_change(x, 1.0) for x in d]
        printed = np.abs(d)
        corrected = np.array([max(s.value, 0.0) for s in sels])
        assert np.all(corrected >= 0.0)
        assert printed.mean() - delta == pytest.approx(foldnorm.mean(delta, scale=1.0) - delta,
                                                       abs=0.04)
        U = np.array([2.0 * math.hypot(1.0, sum(r.standard_uncertainty.magnitude for r
                                                in abs_change_rows(s, "deg/h", 1.0)))
                      for s in sels])
        en_printed, en = np.mean((printed - delta) / 2.0), np.mean((corrected - delta) / U)
        assert abs(en) <= 0.25, (delta, en)
        if delta == 0.0:
            assert en_printed > 0.35 and en < 0.6 * en_printed, (en_printed, en)
        held = np.abs(printed - delta) <= 2.0
        assert np.all(np.abs(corrected[held] - delta) <= U[held] * (1 + 1e-12)), delta
        assert np.mean(held) >= 0.94
    rows = abs_change_rows(abs_change(0.0, 1.0), "deg/h", 1.0)
    b = math.sqrt(2 / math.pi)
    assert len(rows) == 1 and rows[0].distribution == "normal"
    assert rows[0].standard_uncertainty.to("deg/h").magnitude == pytest.approx(math.sqrt(
        b + b * b / 4))
    assert abs_change_rows(abs_change(0.3, 0.0), "deg/h", 0.0) == []


def test_line_test_against_u_of_few_degrees_of_freedom():
    """Six points whose residuals about the line give Σ(r/u)² = 12: beyond χ²₀.₉₅(4) = 9.49, so with
    u taken as exact the line is rejected and the points are drawn as they are (degree −1); with u
    an estimate of ν = 6 (σ_K from seven repeatability runs) the limit is 4·F₀.₉₅(4, 6) = 18.1 and
    the line stands (degree 1)."""
    from scipy.stats import chi2, f

    assert chi2.ppf(0.95, 4) == pytest.approx(9.488, abs=1e-3)
    assert 4 * f.ppf(0.95, 4, 6) == pytest.approx(18.13, abs=0.01)
    T = np.array([-40.0, -20.0, 0.0, 20.0, 40.0, 60.0])
    tc = T - T.mean()
    r = tc**2 - np.mean(tc**2)
    r -= tc * (r @ tc) / (tc @ tc)
    r *= math.sqrt(12.0) / math.sqrt(r @ r)
    K = 1.0 + 2e-6 * (T - 20.0) + 1e-6 * r
    exact = max_slope_selection(K, [1e-6] * 6, T, 3, relative=True)
    estimated = max_slope_selection(K, [1e-6] * 6, T, 3, relative=True, u_dof=6)
    assert exact.degree == -1 and estimated.degree == 1

"""metro.core.selection: the largest of noisy slopes and changes (interpretations.md, "D.1.5 / D.2.5 /
D.5.4 — the largest of several noisy slopes" and "JJF 2014 — the largest of noisy slopes and changes")."""

from __future__ import annotations

import math

import numpy as np
import pytest

from metro.core.selection import max_abs_selection, max_slope_selection, selection_rows, spread_rows, upper_sigma


def test_upper_sigma_against_chi_square_table():
    """One-sided 95 % upper limit of σ, s·√(ν/χ²₀.₀₅(ν)); χ²₀.₀₅ from the printed table (NIST/SEMATECH
    e-Handbook 1.3.6.7.4, lower tail 0.05): ν = 2: 0.103, ν = 5: 1.145 (3 digits)."""
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
    """A stated u (K_r·K) far above the scatter of the calibrations that estimate one K (the K before the
    test on every axis): the draws use the 95 % upper limit of that scatter, the correction shrinks
    accordingly; with a scatter as large as u the stated u stays."""
    d, u = [0.005, 0.003, 0.002], [0.0057] * 3
    big = max_abs_selection(d, u)
    small = max_abs_selection(d, u, same=[23.0, 23.0 + 1e-6, 23.0 - 1e-6])
    assert big.bias > 1e-3 and big.scatter is None
    assert small.scatter == pytest.approx(math.sqrt(2) * upper_sigma(1e-6, 2), rel=1e-6)
    assert abs(small.bias) < 1e-4
    same_as_u = max_abs_selection(d, u, same=[23.0, 23.01, 22.99])  # s = 0.01 > 0.0057/√2
    assert same_as_u.scatter is None and same_as_u.bias == pytest.approx(big.bias, rel=1e-9)


def test_largest_slope_with_observed_scatter():
    """Points on a line within 10⁻⁷ but stated u 10⁻⁴ (a repeatability the chamber's points do not carry):
    with ``observed`` the draws use the points' own scatter and the correction is negligible; without,
    it is the selection bias of u = 10⁻⁴ noise."""
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
    assert len(rows) == 1 and rows[0].distribution == "uniform" and "noisy changes" in rows[0].source
    assert rows[0].contribution.m_as("deg/h") == pytest.approx(abs(sel.bias) / math.sqrt(3), rel=1e-9)
    assert spread_rows(sel, 10.0, "deg/h") == []
    extra = spread_rows(sel, 0.1, "deg/h")
    assert extra[0].contribution.m_as("deg/h") == pytest.approx(math.sqrt(sel.s ** 2 - 0.01), rel=1e-9)

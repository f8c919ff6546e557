"""metro.core.stats.sinefit: hand-worked values, exact ("certified") data, Monte Carlo covariance,
bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from metro.core.stats.sinefit import fit_sine, wrap_phase


def test_hand_worked_eight_points_per_period():
    # y = 3 + 2·cos(ωt + π/6), f = 1 Hz, t = 0, 1/8, …, 7/8 s. Over whole periods the normal
    # equations are diagonal: a = (2/N)Σy cos ωt = 2 cos(π/6) = √3, b = (2/N)Σy sin ωt = −2 sin(π/6)
    # = −1
    t = np.arange(8) / 8.0
    y = 3 + 2 * np.cos(2 * math.pi * t + math.pi / 6)
    f = fit_sine(t, y, 1.0)
    assert f.a == pytest.approx(math.sqrt(3), abs=1e-12)
    assert f.b == pytest.approx(-1.0, abs=1e-12)
    assert f.amplitude == pytest.approx(2.0, abs=1e-12)
    assert f.phase == pytest.approx(math.pi / 6, abs=1e-12)
    assert f.offset == pytest.approx(3.0, abs=1e-12)
    assert f.dof == 5


def test_certified_exact_data_non_integer_periods():
    """StRD-style: data generated exactly from certified parameters (non-integer number of
    periods, large offset) must be recovered to ~1e-10 relative."""
    E, phi, c, fr = 1.234567890123, -2.0123456789, 1.0e3, 37.3
    t = np.arange(4001) * 1.0 / 4999.0
    y = E * np.cos(2 * math.pi * fr * t + phi) + c
    f = fit_sine(t, y, fr)
    assert f.amplitude == pytest.approx(E, rel=1e-10)
    assert f.phase == pytest.approx(phi, abs=1e-10)
    assert f.offset == pytest.approx(c, rel=1e-12)
    assert f.residual_sd < 1e-9


def test_two_parameter_fit_is_eq40_without_offset():
    t = np.arange(100) * 0.01
    y = 0.5 * np.cos(2 * math.pi * 3 * t - 1.0)
    f = fit_sine(t, y, 3.0, offset=False)
    assert f.amplitude == pytest.approx(0.5, rel=1e-12)
    assert f.phase == pytest.approx(-1.0, abs=1e-12)
    assert f.offset == 0.0 and f.dof == 98


def test_covariance_matches_monte_carlo():
    rng = np.random.default_rng(3)
    t = np.arange(200) * 0.003
    E0, p0, sd = 1.0, 0.4, 0.2
    amps, phs, us = [], [], []
    for _ in range(1500):
        y = E0 * np.cos(2 * math.pi * 7 * t + p0) + 0.1 + rng.normal(0, sd, t.size)
        f = fit_sine(t, y, 7.0)
        amps.append(f.amplitude)
        phs.append(f.phase)
        us.append((f.u_amplitude, f.u_phase))
    u = np.mean(us, axis=0)
    assert np.std(amps) == pytest.approx(u[0], rel=0.08)
    assert np.std(phs) == pytest.approx(u[1], rel=0.08)
    # large-sample value: u(E) ≈ σ·√(2/N), u(φ) ≈ σ/E·√(2/N)
    assert u[0] == pytest.approx(sd * math.sqrt(2 / t.size), rel=0.05)


def test_wrap_phase():
    np.testing.assert_allclose(wrap_phase([0.0, 3 * math.pi, -math.pi, 4.0]),
                               [0.0, math.pi, math.pi, 4.0 - 2 * math.pi])


@pytest.mark.parametrize("t,y,f,msg", [
    (np.arange(3.0), np.ones(3), 1.0, "too few"),
    (np.arange(10.0), np.ones(9), 1.0, "same length"),
    (np.arange(10.0), np.r_[np.ones(9), np.nan], 1.0, "NaN"),
    (np.arange(10.0), np.ones(10), 0.0, "frequency"),
    (np.arange(10.0), np.ones(10), 1.0, "singular"),  # integer t at f = 1 Hz: sin ωt ≡ 0
])
def test_bad_input(t, y, f, msg):
    with pytest.raises(ValueError, match=msg):
        fit_sine(t, y, f)

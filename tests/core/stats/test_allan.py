"""Tests for metro.core.stats.allan.

Reference values: the "NBS14" test data of NBS Monograph 140, Annex 8.E, as tabulated by
W. J. Riley ("The calculation of time domain frequency stability", and NIST SP 1065);
Stable32 reproduces them.  Printed to 7 significant digits, so they are compared at
1e-6 relative.  The data and values ship in the package (``metro/core/validation/data/
allan_nbs14.json``, which ``metro validate`` uses too); read here as plain JSON, the series
generated here, the statistics computed by the functions under test.
"""

from __future__ import annotations

import json
import subprocess
import sys
from importlib import resources

import numpy as np
import pytest
from metro.core.stats import allan_base, allan_edf
from metro.core.stats.allan import (AllanResult, adev, block_means, block_means_pyramid, block_std,
                                    block_variance_doubling, edf_white_fm, log_m, mdev, oadev,
                                    octave_m)

ENGINES = ["numpy", "numba"]

#: the NBS14 reference (package data): {"short": {data, m, adev, oadev, mdev}, "long": {…}}
NBS14 = json.loads(resources.files("metro.core.validation").joinpath(
    "data", "allan_nbs14.json").read_text(encoding="utf-8"))
NBS14_9 = np.array(NBS14["short"]["data"], dtype=float)
SHORT, LONG = NBS14["short"], NBS14["long"]


def nbs14_1000() -> np.ndarray:
    """n0 = 1234567890, n_{i+1} = 16807 n_i mod 2147483647, y_i = n_i / 2147483647."""
    n = 1234567890
    out = np.empty(1000)
    for i in range(1000):
        out[i] = n / 2147483647
        n = (16807 * n) % 2147483647
    return out


# --------------------------------------------------------------------------- NBS14


@pytest.mark.parametrize("engine", ENGINES)
def test_nbs14_short_series(engine):
    # NBS Monograph 140 Annex 8.E, 9 frequency values, tau0 = 1:
    # ADEV 91.22945, 115.8082; OADEV 91.22945, 85.95287; MDEV 91.22945, 74.78849.  1e-6 rel.
    a = adev(NBS14_9, 1.0, [1, 2], engine=engine)
    o = oadev(NBS14_9, 1.0, [1, 2], engine=engine)
    md = mdev(NBS14_9, 1.0, [1, 2], engine=engine)
    assert SHORT["adev"] == [91.22945, 115.8082] and SHORT["m"] == [1, 2]
    np.testing.assert_allclose(a.deviation, SHORT["adev"], rtol=1e-6)
    np.testing.assert_allclose(o.deviation, SHORT["oadev"], rtol=1e-6)
    np.testing.assert_allclose(md.deviation, SHORT["mdev"], rtol=1e-6)
    np.testing.assert_array_equal(a.tau, [1.0, 2.0])
    np.testing.assert_array_equal(a.n_terms, [8, 3])
    np.testing.assert_array_equal(o.n_terms, [8, 6])
    np.testing.assert_array_equal(md.n_terms, [8, 5])


@pytest.mark.parametrize("engine", ENGINES)
def test_nbs14_1000_points(engine):
    # NBS14 1000-point set (seed is the first value), tau = 1, 10, 100.  1e-6 rel.
    y = nbs14_1000()
    m = [1, 10, 100]
    assert LONG["m"] == m and LONG["seed"] == 1234567890
    for fn in (adev, oadev, mdev):
        np.testing.assert_allclose(fn(y, 1.0, m, engine=engine).deviation, LONG[fn.__name__],
                                   rtol=1e-6, err_msg=fn.__name__)


def test_tau_scales_with_tau0():
    y = nbs14_1000()
    r = oadev(y, 0.001, [1, 10, 100])
    np.testing.assert_allclose(r.tau, [0.001, 0.01, 0.1])
    np.testing.assert_allclose(r.deviation, LONG["oadev"], rtol=1e-6)


# --------------------------------------------------------------------------- engines


@pytest.fixture(scope="module")
def noisy():
    rng = np.random.default_rng(20240601)
    n = 70_001  # above NUMBA_MIN_N and odd
    return 3.0 + rng.normal(size=n) + 1e-3 * np.cumsum(rng.normal(size=n))


def test_numba_and_numpy_agree(noisy):
    # octave list (grouped kernel path) plus non-octave factors (single path), 1e-12 rel
    ms = np.unique(np.concatenate([octave_m(noisy.size), [3, 5, 7, 100, 999, 12345]]))
    for fn in (adev, oadev, mdev):
        a = fn(noisy, 0.01, ms, engine="numba")
        b = fn(noisy, 0.01, ms, engine="numpy")
        np.testing.assert_allclose(a.deviation, b.deviation, rtol=1e-12, err_msg=fn.__name__)
        np.testing.assert_array_equal(a.n_terms, b.n_terms)
        np.testing.assert_array_equal(a.m, ms)
    a = block_variance_doubling(noisy, 0.01, engine="numba")
    b = block_variance_doubling(noisy, 0.01, engine="numpy")
    np.testing.assert_allclose(a.std, b.std, rtol=1e-12)
    np.testing.assert_array_equal(a.n_blocks, b.n_blocks)


def test_env_var_forces_numpy(monkeypatch):
    monkeypatch.setenv("METRO_NO_NUMBA", "1")
    assert allan_base.kernels("auto", 10**8) is None
    monkeypatch.setenv("METRO_NO_NUMBA", "0")
    assert allan_base.kernels("auto", 10**8) is not None
    monkeypatch.delenv("METRO_NO_NUMBA")
    assert allan_base.kernels("auto", 10**8) is not None
    assert allan_base.kernels("auto", 100) is None  # small data: no compile latency
    assert allan_base.kernels("numpy", 10**8) is None
    with pytest.raises(ValueError, match="engine"):
        allan_base.kernels("fortran", 10)  # type: ignore[arg-type]


def test_import_does_not_load_numba():
    code = "import sys, metro.core.stats.allan; assert 'numba' not in sys.modules, 'numba imported'"
    subprocess.run([sys.executable, "-c", code], check=True)


def test_agrees_with_allantools(noisy):
    at = pytest.importorskip("allantools")
    y = noisy[:8192]
    for fn, afn in ((adev, at.adev), (oadev, at.oadev), (mdev, at.mdev)):
        r = fn(y, 0.01)
        taus, dev, _err, n = afn(y, rate=100.0, data_type="freq", taus=r.tau)
        np.testing.assert_allclose(taus, r.tau, rtol=1e-12)
        np.testing.assert_allclose(r.deviation, dev, rtol=1e-9, err_msg=fn.__name__)
        np.testing.assert_array_equal(r.n_terms, n)


# --------------------------------------------------------------------------- accuracy


@pytest.mark.parametrize("engine", ENGINES)
def test_large_offset_costs_no_accuracy(engine, noisy):
    # Gyro output on a big bias: adding 1e7 (NumAcc4-like) must not change the result.
    # y + 1e7 - 1e7 is exactly representable, so compare against the offset-free data.
    y = (noisy[:65_536] + 1e7) - 1e7
    ms = [1, 2, 4, 8, 16, 100, 1000, 8192]
    for fn in (oadev, adev, mdev):
        ref = fn(y, 1.0, ms, engine=engine)
        off = fn(y + 1e7, 1.0, ms, engine=engine)
        np.testing.assert_allclose(off.deviation, ref.deviation, rtol=1e-9, err_msg=fn.__name__)
    ref = block_variance_doubling(y, 1.0, engine=engine)
    off = block_variance_doubling(y + 1e7, 1.0, engine=engine)
    # level means of y + 1e7 are rounded to ~1e-9 absolute: compare at 1e-7
    np.testing.assert_allclose(off.std, ref.std, rtol=1e-7)


@pytest.mark.parametrize("engine", ENGINES)
def test_numacc4_block_std(engine):
    # NIST StRD NumAcc4: 10000000.2, then 500 pairs 10000000.1 / 10000000.3; certified
    # standard deviation 0.1.  A one-pass sum-of-squares formula returns 0 here.
    y = np.concatenate([[10000000.2], np.tile([10000000.1, 10000000.3], 500)])
    r = block_variance_doubling(y, 1.0, kmax=1, engine=engine)
    assert r.std[0] == pytest.approx(0.1, rel=1e-7)
    s, nb = block_std(y, 1)
    assert nb == 1001
    assert s == pytest.approx(0.1, rel=1e-7)


def test_white_noise_matches_theory():
    # White FM of standard deviation s: E[ADEV^2] = E[OADEV^2] = s^2/m; MDEV^2 = s^2 r(0)/(2 m^4)
    # with r(0) = sum of the squared MDEV coefficients.  Each estimate must lie within
    # 4 standard uncertainties (from its white-FM edf) of the expectation (seeded).
    s = 2.5
    y = np.random.default_rng(7).normal(scale=s, size=1 << 15)
    for fn in (adev, oadev, mdev):
        r = fn(y, 1.0)
        if fn is mdev:
            r0 = np.array(
                [np.sum(np.convolve(np.ones(m), np.r_[-np.ones(m), np.ones(m)]) ** 2) for m in r.m]
            )
            expect = s * np.sqrt(r0 / (2.0 * r.m.astype(float) ** 4))
        else:
            expect = s / np.sqrt(r.m)
        u = expect / np.sqrt(2.0 * r.edf)
        assert np.all(np.abs(r.deviation - expect) <= 4.0 * u), fn.__name__
        lo, hi = r.ci(0.95)
        assert np.all((lo < r.deviation) & (r.deviation < hi))
        np.testing.assert_allclose(r.uncertainty, r.deviation / np.sqrt(2.0 * r.edf))


# --------------------------------------------------------------------------- edf


def _brute_edf(kind: str, n: int, m: int) -> float:
    """(tr C)^2 / tr(C^2) with C = G G^T, G the coefficient rows of the estimator."""
    if kind == "adev":
        M = n // m
        G = np.zeros((M - 1, n))
        for k in range(M - 1):
            G[k, k * m : (k + 1) * m] = -1.0
            G[k, (k + 1) * m : (k + 2) * m] = 1.0
    else:
        c = np.r_[-np.ones(m), np.ones(m)]
        g = c if kind == "oadev" else np.convolve(np.ones(m), c)
        T = n - g.size + 1
        G = np.zeros((T, n))
        for j in range(T):
            G[j, j : j + g.size] = g
    C = G @ G.T
    return float(np.trace(C) ** 2 / np.sum(C * C))


@pytest.mark.parametrize("kind", ["adev", "oadev", "mdev"])
def test_edf_matches_quadratic_form(kind):
    n = 60
    for m in (1, 2, 3, 5, 8, 13, 19):
        if kind == "mdev" and 3 * m - 1 > n:
            continue
        assert edf_white_fm(kind, n, m)[0] == pytest.approx(_brute_edf(kind, n, m), rel=1e-12)


def test_edf_oadev_close_to_howe_allan_barnes():
    # Howe, Allan & Barnes (1981) white-FM approximation, N' = N + 1 phase points.
    for n, m in ((1000, 1), (1000, 10), (1000, 100), (100_000, 3000), (28_800_000, 1 << 20)):
        nx = n + 1
        hab = (3 * (nx - 1) / (2 * m) - 2 * (nx - 2) / nx) * 4 * m * m / (4 * m * m + 5)
        assert edf_white_fm("oadev", n, m)[0] == pytest.approx(hab, rel=0.02)


def test_edf_sampled_sum_is_accurate(monkeypatch):
    n, ms = 200_000, [3000, 20_000, 60_000]
    exact = {k: edf_white_fm(k, n, ms) for k in ("oadev", "mdev")}
    monkeypatch.setattr(allan_edf, "_EDF_EXACT_MAX", 512)
    for k, v in exact.items():
        np.testing.assert_allclose(edf_white_fm(k, n, ms), v, rtol=1e-3)


# --------------------------------------------------------------------------- block statistics


@pytest.mark.parametrize("engine", ENGINES)
def test_block_variance_doubling_hand_worked(engine):
    # 1 3 2 6 4 4 9 3: mean 4, squared deviations sum 44 -> s1 = sqrt(44/7)
    # pair means 2 4 4 6: sum of squares about 4 is 8 -> s2 = sqrt(8/3)
    # 3 5 -> s3 = sqrt(2); the trailing 100 (9th value) is dropped from level 2 on.
    y = np.array([1, 3, 2, 6, 4, 4, 9, 3], dtype=float)
    r = block_variance_doubling(y, 0.5, min_blocks=2, engine=engine)
    np.testing.assert_allclose(r.std, np.sqrt([44 / 7, 8 / 3, 2.0]), rtol=1e-14)
    np.testing.assert_array_equal(r.n_blocks, [8, 4, 2])
    np.testing.assert_array_equal(r.tau, [0.5, 1.0, 2.0])
    np.testing.assert_array_equal(r.level, [1, 2, 3])
    odd = block_variance_doubling(np.append(y, 100.0), 0.5, min_blocks=2, engine=engine)
    np.testing.assert_allclose(odd.std[1:], r.std[1:], rtol=1e-14)
    np.testing.assert_array_equal(odd.n_blocks, [9, 4, 2])
    assert odd.std[0] == pytest.approx(np.std(np.append(y, 100.0), ddof=1), rel=1e-14)


def test_block_variance_doubling_stopping_rule(noisy):
    r = block_variance_doubling(noisy, 1.0)  # min_blocks = 10
    assert r.n_blocks[-1] >= 10 and r.n_blocks[-1] // 2 < 10
    np.testing.assert_array_equal(r.n_blocks, noisy.size >> np.arange(r.n_blocks.size))
    assert block_variance_doubling(noisy, 1.0, kmax=3).std.size == 3
    pyr = block_means_pyramid(noisy, r.std.size)
    np.testing.assert_allclose([np.std(v, ddof=1) for v in pyr], r.std, rtol=1e-11)
    assert pyr[0] is noisy or np.shares_memory(pyr[0], noisy)


def test_block_means_and_std():
    y = np.arange(10.0)  # blocks of 3: (0,1,2) (3,4,5) (6,7,8); 9 dropped
    np.testing.assert_allclose(block_means(y, 3), [1.0, 4.0, 7.0])
    s, m = block_std(y, 3)
    assert m == 3
    assert s == pytest.approx(3.0, rel=1e-14)
    np.testing.assert_allclose(block_means(y, 1), y)
    s, m = block_std(y, 1)
    assert (s, m) == (pytest.approx(np.std(y, ddof=1), rel=1e-14), 10)


# --------------------------------------------------------------------------- m lists


def test_octave_and_log_m():
    np.testing.assert_array_equal(octave_m(9), [1, 2])
    np.testing.assert_array_equal(octave_m(1000), [1, 2, 4, 8, 16, 32, 64, 128])
    np.testing.assert_array_equal(octave_m(1000, max_fraction=0.5), 2 ** np.arange(9))
    np.testing.assert_array_equal(log_m(1000, 1), [1, 10, 100])
    np.testing.assert_array_equal(log_m(4000, 1), [1, 10, 100, 1000])
    np.testing.assert_array_equal(log_m(1000, 3), [1, 2, 5, 10, 22, 46, 100, 215])
    with pytest.raises(ValueError, match="too few points"):
        octave_m(3)
    with pytest.raises(ValueError, match="max_fraction"):
        octave_m(100, max_fraction=0.7)


def test_default_m_is_octave(noisy):
    r = oadev(noisy, 1.0)
    np.testing.assert_array_equal(r.m, octave_m(noisy.size))
    assert isinstance(r, AllanResult)
    assert r.kind == "oadev" and r.n_samples == noisy.size


# --------------------------------------------------------------------------- errors


@pytest.mark.parametrize("fn", [adev, oadev, mdev])
def test_input_errors(fn):
    y = np.ones(100)
    with pytest.raises(ValueError, match="NaN or Inf .*index 5"):
        fn(np.r_[np.ones(5), np.nan, np.ones(5)], 1.0)
    with pytest.raises(ValueError, match="NaN or Inf"):
        fn(np.r_[np.ones(5), np.inf, np.ones(5)], 1.0)
    with pytest.raises(ValueError, match="empty"):
        fn(np.array([]), 1.0)
    with pytest.raises(ValueError, match="1-dimensional"):
        fn(np.ones((10, 2)), 1.0)
    with pytest.raises(ValueError, match="too few points"):
        fn(np.ones(3), 1.0)
    with pytest.raises(ValueError, match="too large"):
        fn(y, 1.0, [1, 60])
    with pytest.raises(ValueError, match=">= 1"):
        fn(y, 1.0, [0, 1])
    with pytest.raises(ValueError, match="integers"):
        fn(y, 1.0, [1.5])
    for bad in (0.0, -1.0, np.nan, np.inf):
        with pytest.raises(ValueError, match="tau0"):
            fn(y, bad)


def test_mdev_limit_and_block_errors():
    with pytest.raises(ValueError, match="3m - 1"):
        mdev(np.ones(20), 1.0, [8])
    with pytest.raises(ValueError, match="min_blocks"):
        block_variance_doubling(np.ones(20), 1.0, min_blocks=1)
    with pytest.raises(ValueError, match="too few points"):
        block_variance_doubling(np.ones(5), 1.0)
    with pytest.raises(ValueError, match="kmax"):
        block_variance_doubling(np.ones(50), 1.0, kmax=0)
    with pytest.raises(ValueError, match="NaN or Inf"):
        block_variance_doubling(np.r_[np.ones(20), np.nan], 1.0)
    with pytest.raises(ValueError, match="too few points"):
        block_means(np.ones(3), 4)
    with pytest.raises(ValueError, match="at least 2"):
        block_std(np.ones(7), 4)
    with pytest.raises(ValueError, match="factor"):
        block_means(np.ones(7), 0)
    with pytest.raises(ValueError, match="level"):
        block_means_pyramid(np.ones(7), 4)
    with pytest.raises(ValueError, match="p must be"):
        oadev(np.arange(20.0), 1.0).ci(1.5)


from hypothesis import given, settings  # noqa: E402
from hypothesis import strategies as st  # noqa: E402


@settings(max_examples=40, deadline=None)
@given(st.integers(min_value=0, max_value=2**32 - 1), st.integers(min_value=9, max_value=400),
       st.floats(min_value=-1e3, max_value=1e3).filter(lambda a: abs(a) > 1e-3),
       st.floats(min_value=-1e6, max_value=1e6))
def test_deviations_follow_scale_and_ignore_offset(seed, n, a, b):
    """For any record y: σ(a·y + b) = |a|·σ(y) (an Allan deviation sees differences of means, so
    an offset drops out and a scale factor comes out), and at m = 1 the overlapping and the
    non-overlapping estimators are the same sum (NIST SP 1065 eqs. (10), (14))."""
    y = np.random.default_rng(seed).normal(size=n)
    ms = [m for m in (1, 2, 3, n // 4) if 1 <= m <= (n - 1) // 2]
    for fn in (adev, oadev, mdev):
        ref = fn(y, 0.1, ms, engine="numpy").deviation
        got = fn(a * y + b, 0.1, ms, engine="numpy").deviation
        # a·y + b is itself rounded: about eps·|b| per sample against a spread of |a|
        tol = 1e-9 + 1e-14 * abs(b) / abs(a)
        np.testing.assert_allclose(got, abs(a) * ref, rtol=tol, err_msg=fn.__name__)
    np.testing.assert_allclose(oadev(y, 0.1, [1]).deviation, adev(y, 0.1, [1]).deviation,
                               rtol=1e-12)


def test_mean_u_batches_checks_for_correlated_batch_means():
    """metro.core.stats.allan.mean_u_batches: white noise keeps the 20 batch means (u = s_b/√20); a
    random walk makes them alike and the F test (95 %) takes 5 long batches, whose u is larger."""
    from metro.core.stats.allan import block_std, mean_u_batches

    rng = np.random.default_rng(7)
    w = rng.normal(0.0, 1.0, 20000)
    r = mean_u_batches(w)
    sd, nb = block_std(w, 1000)
    assert (not r.correlated and r.batches == 20
            and r.u == pytest.approx(sd / np.sqrt(nb), rel=1e-12))
    walk = w + 0.05 * np.cumsum(rng.normal(0.0, 1.0, 20000))
    c = mean_u_batches(walk)
    assert c.correlated and c.batches == 5 and c.batches_short == 20 and c.u > 2 * c.u_short

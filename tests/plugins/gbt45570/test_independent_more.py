"""GB/T 45570 scale-factor and Allan items on devices from the independent harness.

benchmarks/independent_gbt_more.py writes campaigns from the documented format with its own numpy
generators (nonlinearity of several shapes, asymmetry of either sign, K varying between power-ons,
undithered and dithered pulse counters, LSB words, °/h and °/s rate outputs, a turn-on scatter at
every temperature point) and scores D.1.1–D.1.4, D.2.1–D.2.4, D.5.4–D.5.6 against the truth it knows
by construction. Here a few devices at short record lengths: metro must read them, give each result
in the standard's unit, and land within U of the truth or say why it cannot report it. The sweeps
and their table are at the end of docs/independent-campaigns.md.
"""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="module")
def more(load_benchmark):
    with load_benchmark("independent_gbt_more") as mod:
        yield mod


def test_module_does_not_use_metro_generators(benchmark_imports):
    """Independence: the generators import no part of metro (the campaigns are evaluated through
    the sibling module's `metro run`), and take nothing but writers and scoring from it."""
    text, imports = benchmark_imports("independent_gbt_more")
    assert imports, "no imports found"
    assert not [ln for ln in imports if "metro" in ln or "simulated" in ln or "instruments"
                in ln], imports


def test_nonlinearity_truth_is_the_clause_formula_on_a_hand_worked_device(more):
    """The truth of D.7 on a device whose K_i are known: g = c·(Ω/Ω_m)² at Ω = 1, 2, 4 with
    Ω_m = 4 and c = 16e-6 gives K_i/K = 1 + 1e-6, 1 + 4e-6, 1 + 16e-6; by hand, the D.5 line through
    (1, 1), (2, 4), (4, 16) (×1e-6): x̄ = 7/3, ȳ = 7, Sxx = 14/3, Sxy = 24, so W = 36/7 and the
    intercept 7 − (36/7)(7/3) = −5; D.7's K_n = |16 − (−5)|/(1 − 5e-6) ≈ 21 ppm at 4 °/s."""
    g = more.nonlinearity("quadratic", 16e-6, 4.0)
    w = np.array([1.0, 2.0, 4.0])
    ki = 1 + g(w)
    assert np.allclose(ki - 1, [1e-6, 4e-6, 16e-6])
    a, b = more.line(w, ki)
    assert b == pytest.approx(36 / 7 * 1e-6, rel=1e-6)
    assert a - 1 == pytest.approx(-5e-6, rel=1e-6)
    assert float(np.max(np.abs(ki - a)) / a) == pytest.approx(21e-6 / (1 - 5e-6), rel=1e-6)
    # odd shape: the two directions' K_i average it away (D.2), so D.7 sees none of it
    odd = more.nonlinearity("odd", 50e-6, 4.0)
    assert np.allclose((1 + odd(w)) + (1 + odd(-w)), 2.0)


DEVICES = [
    ("D.1.1,D.1.2,D.1.3,D.1.4", 31, lambda m, f, rng: m.build_angle(f, rng, quick=True)),
    ("D.2.1,D.2.2,D.2.3,D.2.4", 32,
     lambda m, f, rng: m.build_rate(f, rng, kind="LSB", dt=0.1, seconds=100.0, q=0.05, quick=True)),
    ("D.2.1,D.2.2,D.2.3,D.2.4", 33,
     lambda m, f, rng: m.build_rate(f, rng, kind="deg/s", dt=1.0, seconds=60.0, q=1e-5, fmt="csv",
                                    quick=True)),
    ("D.5.6", 34, lambda m, f, rng: m.build_arw(f, rng, kind="pulse", dt=1.0, hours=8.0,
                                                quick=True)),
    ("D.5.4,D.5.5", 35, lambda m, f, rng: m.build_bias_env(f, rng, kind="pulse", dt=1.0, fmt="csv",
                                                           quick=True)),
]


@pytest.mark.parametrize("items,seed,build", DEVICES,
                         ids=["angle-pulse", "rate-lsb", "rate-degs", "arw-pulse", "bt-bh-pulse"])
def test_independent_device_evaluates_within_U(more, tmp_path, items, seed, build, harness_device,
                                                evaluated_within_u):
    import independent_campaigns as ic

    folder, truth = harness_device(more, build, seed, items, tmp_path)
    evaluated_within_u(ic.run_metro, more.score_more, folder, "gbt45570", items, truth)

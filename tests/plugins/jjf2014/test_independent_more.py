"""JJF 2014 campaigns from the independent harness's second module
(benchmarks/independent_jjf2014_more.py) read and evaluate within U.

The module writes devices metro's simulators do not make — nonlinear and asymmetric scale factors of
either sign, K and bias sensitive to temperature and to g on any axis, power-on scatter of K and
bias, flicker, rate random walk and ramps, mV and ratiometric mV/V outputs, 1 Hz … 400 Hz — from the
documented format only, and scores 7.2.2 K_n and range, 7.2.3 K_a, 7.2.5 K_t, 7.2.6 K_g, 7.2.15 B_r,
7.2.16 B_t, 7.2.17 B_g and 7.2.20 against the truth it knows by construction. Here one short device
of each kind: every result in the standard's unit, within U of the truth or not reportable with a
reason. The sweeps and their tables: docs/independent-campaigns.md, "JJF 2014: the other items".
"""

from __future__ import annotations

import numpy as np
import pytest


@pytest.fixture(scope="module")
def more(load_benchmark):
    with load_benchmark("independent_jjf2014_more") as mod:
        yield mod


@pytest.mark.parametrize("module", ["independent_jjf2014_more", "independent_jjf2014_dyn"])
def test_the_module_does_not_use_metro_generators(benchmark_imports, module):
    """Independence: the module's generators (this one's and the dynamic items' of
    test_independent_dynamic.py) import no part of metro (they reach metro only through the shared
    harness's command line)."""
    text, imports = benchmark_imports(module)
    assert imports
    assert not [ln for ln in imports if "metro" in ln or "simulat" in ln or "instruments"
                in ln], imports
    assert ("from independent_campaigns import (  # noqa: E402  "
            "(the shared pieces of the harness)") in imports


DEVICES = {
    "nonlin-mV": ("jjf-nonlin-mV-1Hz", 2),
    "temp-g-mV": ("jjf-temp-g-mV-1Hz", 3),
    "repeat-allan-mVV": ("jjf-repeat-allan-mVV-100Hz-flicker-q", 4),
    "allan-terms-mV": ("jjf-allan-terms-mV-10Hz", 5),
    "misalignment-Q7": ("jjf-misalignment-mV-Q7", 6),
    "threshold-mV": ("jjf-threshold-mV-1Hz", 7),
}


@pytest.mark.parametrize("name", list(DEVICES))
def test_independent_jjf2014_device_within_U(more, tmp_path, name, within_u):
    variant, seed = DEVICES[name]
    v = more.VARIANTS[variant]
    rows = more.run_more(v, 1, seed, tmp_path, quick=True)
    assert rows and all("item" in r for r in rows), rows
    items = {r["item"] for r in rows}
    assert items >= set(v.items.split(",")) - {"7.2.1", "7.2.4"}, items
    within_u(rows)


def test_truth_of_the_range_is_the_noise_free_span(more):
    """The harness's own eqs. (4), (7), (8) on a hand case: a cubic output K(Ω + cΩ³/Ω_m²) has K_n
    growing with the span, and the range is the largest span whose K_n meets the requirement."""
    om = np.array([s * r for r in (1, 2, 4, 10, 25, 63, 100) for s in (1, -1)], dtype=float)
    F = 10.0 * (om + 1e-3 * om ** 3 / 100.0 ** 2)
    kn = {t: more.kn_eq7_8(om[np.abs(om) <= t], F[np.abs(om) <= t]) for t in (25, 63, 100)}
    assert kn[25] < kn[63] < kn[100]
    assert more.range_722(om, F, (kn[63] + kn[100]) / 2) == 63.0
    assert more.range_722(om, F, kn[100] * 2) == 100.0

"""JJF 2014 campaigns from the independent harness's dynamic module
(benchmarks/independent_jjf2014_dyn.py) read and evaluate within U.

The module writes devices metro's simulators do not make — K of either sign shifted by shocks and
vibrations on no, one or every axis, biases that shift, power-ons between records or not, flicker
and a wander, mV and ratiometric mV/V outputs, first- and second-order frequency responses with a
delay, start-up transients of several shapes — from the documented format only, and scores 7.2.7,
7.2.8, 7.2.14, 7.2.18, 7.2.19, 7.2.21, 7.2.22 and 7.2.23 against the truth it knows by construction.
Here one short device of each kind: every result in the standard's unit, within U of the truth or
not reportable with a reason. The sweeps and their tables: docs/independent-campaigns.md, "JJF 2014:
shock, vibration, stability and dynamic items".
"""

from __future__ import annotations

import math

import numpy as np
import pytest


@pytest.fixture(scope="module")
def dyn(load_benchmark):
    with load_benchmark("independent_jjf2014_dyn") as mod:
        yield mod


DEVICES = {
    "dK-mV": ("jjf-dK-shock-vib-mV-1Hz", 2),
    "dB-mVV-flicker": ("jjf-dB-shock-vib-mVV-10Hz-flicker-q-repeats", 3),
    "Bs-flicker": ("jjf-Bs-mVV-10Hz-flicker-wander-q", 4),
    "Bw-Td-first": ("jjf-Bw-Td-first-order-mV", 5),
    "Bw-Td-second": ("jjf-Bw-Td-second-order-mVV-q", 7),
    "startup-quiet": ("jjf-startup-mVV-10Hz-quiet-q", 8),
}


@pytest.mark.parametrize("name", list(DEVICES))
def test_independent_jjf2014_dynamic_device_within_U(dyn, tmp_path, name, within_u):
    variant, seed = DEVICES[name]
    v = dyn.VARIANTS[variant]
    rows = dyn.run_dyn(v, 1, seed, tmp_path, quick=True)
    assert rows and all("item" in r for r in rows), rows
    assert {r["item"] for r in rows} == set(v.items.split(",")) - {"7.2.1", "7.2.4", "7.2.15"}
    within_u(rows)


def test_truth_of_the_dynamic_items(dyn):
    """The harness's own truths on hand cases: a first-order response's 0.707 point is
    f_c·√(1/0.707² − 1) and its −3 dB point f_c; eq. (50) on its exact phases with T = 1/(2πf_c)
    returns its delay."""
    r = dyn.Response(1, 80.0, 1.5e-3)
    assert r.level_point(0.707) == pytest.approx(80.0 * math.sqrt(1 / 0.707 ** 2 - 1), rel=1e-9)
    assert r.level_point(1 / math.sqrt(2)) == pytest.approx(80.0, rel=1e-9)
    f = np.geomspace(10, 160, 12)
    assert dyn.td_eq50(f, np.unwrap(np.angle(r(f))), 80.0) == pytest.approx(1.5e-3, rel=1e-9)
    # a second-order response with ζ = 1/√2 has its −3 dB point at f_n
    assert dyn.Response(2, 100.0, 0.0, zeta=1 / math.sqrt(2)).level_point(
        1 / math.sqrt(2)
    ) == pytest.approx(100.0, rel=1e-9)

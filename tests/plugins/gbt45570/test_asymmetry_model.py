"""GB/T 45570 D.1.3 and D.2.3: K_a's budget carries its measurement model, |K₊ − K₋|/K̄, for the
Monte Carlo check (JCGM 101): the model is folded at 0, the budget's linear sum is not."""

from __future__ import annotations

import attrs
import numpy as np
import pytest

from metro.core.run.runner import run_items
from metro.core.uncertainty.montecarlo_budget import check_budget
from metro.plugins.gbt45570 import formulas as F
from metro.plugins.gbt45570 import formulas_rate as F2


def test_d10_model_is_folded_at_zero():
    model = F.asymmetry_model_d10(2e-6, 0.5, 2)
    d = np.array([[-5e-6, 1e-6, 0.0], [0.0, 0.0, 2e-6]])
    # K_a = |2 − 5| ppm = 3 ppm, not −3; |2 + 1| = 3; |2 + 0.5·2| = 3: deviations of +1 ppm
    assert model(d) == pytest.approx([1.0, 1.0, 1.0])


def test_d26_model_is_the_ratio_of_the_perturbed_fits():
    Kp, Km = 1.00003, 0.99997
    model = F2.asymmetry_model_d26(Kp, Km, True)
    mean = (Kp + Km) / 2
    d = np.array([[1e-5], [-2e-5], [3e-6]])
    kp, km = Kp + mean * 1e-5, Km - mean * 2e-5
    expected = (abs(kp - km + mean * 3e-6) / ((kp + km) / 2) - F2.asymmetry_d26_d27(Kp, Km)) * 1e6
    assert model(d)[0] == pytest.approx(expected, rel=1e-9)


def test_d13_budget_checks_through_the_model(pm):
    rec = run_items(pm, "gbt45570", ["D.1.3"], station_options={"seed": 1})
    r = rec.outcomes[0].results[0]
    assert r.budget.model is not None
    c = check_budget(r.budget, 1)
    linear = check_budget(attrs.evolve(r.budget, model=None), 1)
    assert c.model == "model" and linear.model == "linear"
    # K_a ≥ 0 for every draw: the interval never reaches below −K_a; here (K_a ≈ U) the shortest
    # interval starts at K_a = 0, and its upper end is well below the symmetric linear one's
    value = float(r.value.to("ppm").magnitude)
    assert value == pytest.approx(c.U_gum, rel=0.05)
    assert value + c.interval[0] >= -1e-9 and value + c.interval[0] < 0.01
    assert c.interval[1] < linear.interval[1] - 20 * c.delta
    assert linear.interval[0] == pytest.approx(-linear.interval[1], abs=3 * c.delta)


def test_d23_budget_checks_through_the_model(pm):
    rec = run_items(pm, "gbt45570", ["D.2.3"], station_options={"seed": 1, "duration_scale": 0.1})
    r = rec.outcomes[0].results[0]
    assert r.budget.model is not None and len(r.budget.rows) == 3  # K₊, K₋, the table
    c = check_budget(r.budget, 1)
    assert c.model == "model" and c.converged is not None
    assert c.u_mc == pytest.approx(c.u_gum, rel=0.2)  # first order: the budget


def test_model_doctests():
    import doctest

    for f in (F.asymmetry_model_d10, F2.asymmetry_model_d26):
        runner = doctest.DocTestRunner()
        for test in doctest.DocTestFinder().find(f):
            runner.run(test)
        assert runner.summarize(verbose=False).failed == 0 and runner.tries > 0

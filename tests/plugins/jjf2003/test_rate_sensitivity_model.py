"""JJF 2003 7.2.5: p = (U₈ − U₇)/ω² carries its measurement model (ω squared in the denominator)
for the Monte Carlo check of its budget (JCGM 101)."""

from __future__ import annotations

import numpy as np
import pytest

from metro.core.run.runner import run_items
from metro.core.uncertainty.montecarlo_budget import check_budget
from metro.plugins.jjf2003 import formulas as F


def test_the_rate_error_divides_squared():
    model = F.rate_sensitivity_model(2.0, [1.0, 0.5, 4.0], 2)
    d = np.array([[0.1], [0.2], [0.05]])
    assert model(d)[0] == pytest.approx((2.0 + 0.1 + 0.1) / 1.05**2 - 2.0)
    # without a rate row the model is the budget's sum
    assert F.rate_sensitivity_model(2.0, [1.0, 0.5], None)(d[:2])[0] == pytest.approx(0.2)


def test_p_budgets_check_through_the_model(pm):
    rec = run_items(pm, "jjf2003", ["7.2.5"], station_options={"seed": 1})
    for r in rec.outcomes[0].results:
        assert r.budget.model is not None
        c = check_budget(r.budget, 1)
        assert c.model == "model"
        # the model's first order is the budget: the Monte Carlo u stays near u_c
        assert c.u_mc == pytest.approx(c.u_gum, rel=0.1)


def test_model_doctest():
    import doctest

    runner = doctest.DocTestRunner()
    for test in doctest.DocTestFinder().find(F.rate_sensitivity_model):
        runner.run(test)
    assert runner.summarize(verbose=False).failed == 0 and runner.tries > 0

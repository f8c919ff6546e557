"""A budget checked by Monte Carlo (JCGM 101 clause 8): its rows as input distributions, the
linear or the budget's own model, and the verdict on the GUM interval."""

from __future__ import annotations

import doctest
import math

import numpy as np
import pytest

from metro.core.uncertainty import montecarlo_budget
from metro.core.uncertainty.budget import BudgetRow, Coverage, UncertaintyBudget
from metro.core.uncertainty.montecarlo_budget import check_budget, row_inputs


def test_doctests():
    result = doctest.testmod(montecarlo_budget)
    assert result.attempted > 0 and result.failed == 0


K2 = Coverage.fixed(2.0)


def _budget(*rows, coverage=K2, model=None):
    return UncertaintyBudget("y", "", rows, coverage=coverage, model=model)


def test_rows_become_inputs_by_distribution_and_dof():
    b = _budget(
        BudgetRow.type_a("repeatability", "s", 0.3, dof=4, sensitivity=2.0),
        BudgetRow.type_b("calibration", "U", 0.4, distribution="normal", k=2),
        BudgetRow.type_b("resolution", "q", 0.5),
        BudgetRow.type_b("limit", "a", 0.6, distribution="arcsine"),
        BudgetRow.type_b("tri", "b", 0.6, distribution="triangular"),
    )
    got = [(i.distribution, round(i.u, 6), i.dof) for i in row_inputs(b, in_output_unit=True)]
    assert got == [("t", 0.6, 4.0), ("normal", 0.2, math.inf),
                   ("rectangular", round(0.5 / math.sqrt(3), 6), math.inf),
                   ("arcsine", round(0.6 / math.sqrt(2), 6), math.inf),
                   ("triangular", round(0.6 / math.sqrt(6), 6), math.inf)]
    own = row_inputs(b, in_output_unit=False)
    assert own[0].u == pytest.approx(0.3)  # u(x) in the row's own unit, c applied by the model


def test_a_normal_budget_with_known_u_is_validated():
    b = _budget(BudgetRow.type_b("a", "a", 2.0, distribution="normal", k=2),
                BudgetRow.type_b("b", "b", 1.0, distribution="normal", k=1),
                coverage=Coverage.probability(0.95))
    c = check_budget(b, 3)
    assert c.validated and c.model == "linear" and c.p == 0.95
    assert c.u_mc == pytest.approx(math.sqrt(2.0), abs=2 * c.delta)
    assert c.delta == pytest.approx(0.05)  # u_c = 1.4 → 14×10⁻¹, δ = ½·10⁻¹


def test_one_rectangular_row_is_not_validated_at_k_2():
    # R(±a): U = 2a/√3 = 1.155a, while the 95.45 % interval of the output is ±0.9545a
    b = _budget(BudgetRow.type_b("quantization", "q", 1.0))
    c = check_budget(b, 5)
    assert c.U_gum == pytest.approx(2 / math.sqrt(3))
    assert c.p == pytest.approx(0.9545, abs=1e-4)
    assert c.interval[0] == pytest.approx(-0.9545, abs=3 * c.delta)
    assert c.interval[1] == pytest.approx(0.9545, abs=3 * c.delta)
    assert not c.validated and c.dominant_distribution == "uniform"
    assert c.d_low > 0.15 and c.d_high > 0.15


def test_a_t_row_with_one_degree_of_freedom_has_no_monte_carlo_u():
    b = _budget(BudgetRow.type_a("2 readings", "s", 1.0, dof=1),
                BudgetRow.type_b("cal", "U", 1.0, distribution="normal", k=1))
    c = check_budget(b, 2)
    assert math.isnan(c.u_mc) and c.as_dict()["u"] is None
    assert not c.validated  # the Cauchy tails widen the interval far beyond U


def test_a_non_linear_model_replaces_the_sum():
    # y = x₁² about x₁ = 0 (JCGM 101 9.4's case): GUM's c = 2x₁ = 0 gives a budget with u_c = 0
    # from that row; with a second row it is still linear in GUM, not in the model
    u = 0.005
    model = lambda d: (0.010 + d[0]) ** 2 - 0.010 ** 2 + d[1] ** 2  # noqa: E731
    b = _budget(BudgetRow.type_b("x1", "u(x1)", u, distribution="normal", k=1,
                                 sensitivity=2 * 0.010),
                BudgetRow.type_b("x2", "u(x2)", u, distribution="normal", k=1, sensitivity=0.0),
                coverage=Coverage.probability(0.95), model=model)
    c = check_budget(b, np.random.default_rng(9))
    assert c.model == "model" and c.u_gum == pytest.approx(100e-6)
    assert c.u_mc == pytest.approx(111.8e-6, rel=0.01)  # JCGM 101 9.4.2: 112×10⁻⁶
    assert c.shift == pytest.approx(50e-6, rel=0.05)  # E[X₁²] + E[X₂²] − x₁² = 2u²
    assert not c.validated


def test_the_model_changes_neither_equality_nor_the_gum_figures():
    rows = (BudgetRow.type_b("a", "a", 1.0),)
    with_model = _budget(*rows, model=lambda d: d[0] ** 2)
    assert with_model == _budget(*rows)
    assert with_model.as_dict() == _budget(*rows).as_dict()


def test_an_exact_budget_is_validated_without_trials():
    c = check_budget(_budget(BudgetRow.type_b("a pass/fail: exact", "—", 0.0)), 1)
    assert c.validated and c.trials == 0 and c.interval == (0.0, 0.0) and c.U_gum == 0.0

"""A budget checked by Monte Carlo (JCGM 101 clause 8): its rows drawn, propagated through the
budget's model, and the GUM interval y ± U compared with the Monte Carlo one.

Each row of an :class:`~metro.core.uncertainty.budget.UncertaintyBudget` is an input X_i drawn
about its estimate (the draws are deviations δx_i, mean 0) with the row's standard uncertainty
u(x_i) and distribution (JCGM 101 clause 6.4, Table 1):

* ``"normal"`` with ν_i = ∞: N(0, u²); with a finite ν_i (a type A mean of ν + 1 readings): the
  scaled and shifted t_ν of clause 6.4.9.7, u·t_ν;
* ``"uniform"``/``"rectangular"``, ``"triangular"``, ``"arcsine"``: the symmetric distribution of
  half-width a = u·divisor (√3, √6, √2) — a finite ν_i of such a row (the reliability of a bound)
  is not drawn, as JCGM 101 6.4.3 draws it only with a stated inexactness of the limits;
* ``"t"``: u·t_ν.

The output's deviation δy is Σ c_i·δx_i (the budget's linear model, JJF 1059.1 eq. (24)), or the
budget's ``model`` (a non-linear measurement model: a ratio, a square) given the δx_i in each
row's input unit.  The GUM interval y ± U has the coverage probability p of the budget
(``Coverage.p``, or erf(k/√2) for a fixed k: 95.45 % at k = 2), and the Monte Carlo shortest
100p % interval (clause 7.7.2) is compared with it (clause 8.2, eqs. (27), (28)); the adaptive
procedure (clause 7.9) and the comparison use the numerical tolerance δ of the GUM u_c at two
significant digits (JJF 1059.1 states U with at most two): ½ unit of u_c's second digit.  The
Monte Carlo u is ``None`` (NaN) where a row is a t with ν ≤ 2, which has no variance.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from .budget import UncertaintyBudget
from .montecarlo import (
    Input,
    Validation,
    gum_coverage_probability,
    linear_model,
    numerical_tolerance,
    propagate,
    validate_gum,
)

#: the most trials one budget's adaptive run may take (a t row with ν ≤ 4 converges slowly)
BUDGET_MAX_TRIALS = 2_000_000

_BOUNDED = {"uniform": "rectangular", "rectangular": "rectangular", "triangular": "triangular",
            "arcsine": "arcsine"}


@attrs.frozen
class BudgetCheck:
    """A budget's GUM figures beside its Monte Carlo ones, in the budget's unit, and the
    clause-8 verdict.  Intervals are deviations from the result's estimate y."""

    #: the GUM u_c and U = k·u_c, and the coverage probability p of y ± U
    u_gum: float
    U_gum: float
    p: float
    #: the Monte Carlo u(y), the shift of its estimate from y and its shortest 100p % interval
    u_mc: float
    shift: float
    interval: tuple[float, float]
    #: the numerical tolerance δ (JCGM 101 7.9.2) and d_low, d_high (clause 8.2)
    delta: float
    d_low: float
    d_high: float
    #: the trials the adaptive procedure ran (0 for an exact budget, u_c = 0), and whether it met
    #: its tolerance
    trials: int
    converged: bool
    #: ``"linear"`` (Σ c_i·x_i) or ``"model"`` (the budget's own measurement model)
    model: str
    #: the row with the largest contribution |c_i|·u(x_i) and its distribution
    dominant: str
    dominant_distribution: str

    @property
    def validated(self) -> bool:
        """True when d_low and d_high are both at most δ (JCGM 101 clause 8.2 c)."""
        return Validation(self.d_low, self.d_high, self.delta).validated

    def as_dict(self, scale: float = 1.0, value: float = 0.0) -> dict:
        """The check as ``--json`` writes it, in a unit ``scale`` times the budget's (the result's
        unit), the interval absolute about the result's ``value``."""
        return {
            "u": None if math.isnan(self.u_mc) else self.u_mc * scale,
            "U_gum": self.U_gum * scale,
            "p": self.p,
            "estimate": value + self.shift * scale,
            "interval": [value + self.interval[0] * scale, value + self.interval[1] * scale],
            "delta": self.delta * scale,
            "d_low": self.d_low * scale,
            "d_high": self.d_high * scale,
            "validated": self.validated,
            "trials": self.trials,
            "converged": self.converged,
            "model": self.model,
            "dominant": self.dominant,
            "dominant_distribution": self.dominant_distribution,
        }


def row_inputs(budget: UncertaintyBudget, *, in_output_unit: bool) -> list[Input]:
    """One :class:`Input` per row, about 0: with u = |c_i|·u(x_i) in the budget's unit
    (``in_output_unit``, for the linear model) or u(x_i) in the row's own unit (for a model).

    >>> from metro.core.uncertainty.budget import BudgetRow
    >>> b = UncertaintyBudget("y", "", [BudgetRow.type_a("r", "s", 0.2, dof=4, sensitivity=3.0),
    ...                                  BudgetRow.type_b("q", "q", 0.5)])
    >>> [(i.distribution, round(i.u, 4), i.dof) for i in row_inputs(b, in_output_unit=True)]
    [('t', 0.6, 4.0), ('rectangular', 0.2887, inf)]
    """
    out = []
    contributions = budget.contributions()
    for row, c in zip(budget.rows, contributions):
        u = c if in_output_unit else float(row.standard_uncertainty.magnitude)
        dist = _BOUNDED.get(row.distribution)
        if dist is None:
            dist = "t" if row.distribution == "t" or not math.isinf(row.dof) else "normal"
        out.append(Input(dist, 0.0, u, dof=row.dof if dist == "t" else math.inf))
    return out


def check_budget(
    budget: UncertaintyBudget, rng: np.random.Generator | int | None = None, *, digits: int = 2
) -> BudgetCheck:
    """Monte Carlo of ``budget`` (JCGM 101 clauses 6.4, 7.9) and the clause-8 validation of its GUM
    interval y ± U at the budget's coverage probability.

    A rectangular row four times the normal one (JCGM 101 9.2.4's case): GUM's 2·u_c overstates
    the 95.45 % interval of a nearly rectangular output, and is not validated:

    >>> from metro.core.uncertainty.budget import BudgetRow
    >>> b = UncertaintyBudget("y", "", [BudgetRow.type_b("a", "a", 1.0 * 3 ** 0.5),
    ...                                  BudgetRow.type_a("r", "s", 0.25, dof=math.inf)])
    >>> c = check_budget(b, 1)
    >>> round(c.U_gum, 2), round(c.interval[1], 2), c.validated
    (2.06, 1.78, False)
    """
    model_given = getattr(budget, "model", None) is not None
    inputs = row_inputs(budget, in_output_unit=not model_given)
    if model_given:
        model = budget.model
    else:
        signs = [1.0 if float(r.sensitivity.magnitude) >= 0 else -1.0 for r in budget.rows]
        model = linear_model(signs)
    p = budget.coverage.p if budget.coverage.p is not None else gum_coverage_probability(
        budget.k)
    u_gum = float(budget.combined.magnitude)
    top = budget.dominant()
    if u_gum == 0 and not model_given:  # exact (a count, a pass/fail): 0 ± 0 either way
        return BudgetCheck(0.0, 0.0, p, 0.0, 0.0, (0.0, 0.0), 0.0, 0.0, 0.0, 0, True, "linear",
                           str(top.source), top.distribution)
    r = propagate(inputs, model, p=p, digits=digits, rng=rng, max_trials=BUDGET_MAX_TRIALS,
                  delta=numerical_tolerance(u_gum, digits))
    U = float(budget.expanded.magnitude)
    v = validate_gum(0.0, U, r.shortest, r.delta)
    return BudgetCheck(u_gum, U, p, r.u, r.y, r.shortest, r.delta, v.d_low, v.d_high, r.trials,
                       r.converged, "model" if model_given else "linear", str(top.source),
                       top.distribution)

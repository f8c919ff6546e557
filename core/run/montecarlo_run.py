"""``metro run --monte-carlo``: every result's budget checked by Monte Carlo (JCGM 101 clause 8).

The checks go on the results (``Result.monte_carlo``), so ``--json``, the terminal summary and
the report all show the same figures; without the option nothing here runs.
"""

from __future__ import annotations

import attrs
import numpy as np

from ..model.provenance import RunRecord
from ..uncertainty.montecarlo_budget import check_budget

#: the seed of the Monte Carlo checks when the run gives none (a report is then reproducible)
DEFAULT_SEED = 101


def with_monte_carlo(record: RunRecord, seed: int | None = None) -> RunRecord:
    """``record`` with a :class:`~metro.core.uncertainty.montecarlo_budget.BudgetCheck` on every
    result that has a budget (an exact one, u_c = 0, is validated as it is), drawn in the results'
    order from one generator seeded with ``seed`` (default :data:`DEFAULT_SEED`)."""
    rng = np.random.default_rng(DEFAULT_SEED if seed is None else seed)
    outcomes = []
    for o in record.outcomes:
        results = []
        for r in o.results:
            if r.budget is not None:
                r = attrs.evolve(r, monte_carlo=check_budget(r.budget, rng))
            results.append(r)
        outcomes.append(attrs.evolve(o, results=results))
    return attrs.evolve(record, outcomes=outcomes)


def gum_not_validated(record: RunRecord) -> list[tuple[str, str]]:
    """(item, result key) of every result whose GUM interval the Monte Carlo check did not
    validate (JCGM 101 clause 8.2)."""
    return [(o.item, r.metric.key) for o in record.outcomes for r in o.results
            if r.monte_carlo is not None and not r.monte_carlo.validated]

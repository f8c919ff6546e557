"""The JCGM 101:2008 clause 9 examples as validation cases: metro's Monte Carlo propagation
(:mod:`metro.core.uncertainty.montecarlo`) against the published figures.

The figures are computed, and the published values and tolerances held, by
:mod:`metro.core.uncertainty.montecarlo_examples` (a fixed seed): each figure passes within 2δ
(a figure that is exact or first order) or 3δ (a published Monte Carlo figure, whose own numerical
error adds a δ), δ the numerical tolerance of JCGM 101 clause 7.9.2 at the digits the figure is
published with.
"""

from __future__ import annotations

import functools
from typing import Any, Callable

from .case import Figures, ValidationCase

__all__ = ["EXAMPLES", "jcgm101_cases"]

#: (id, title, the clause and table of the published figures, unit)
EXAMPLES: tuple[tuple[str, str, str, str], ...] = (
    ("9.2-normal", "additive model Y = X₁ + X₂ + X₃ + X₄, four N(0, 1) inputs", "9.2.2, table 2",
     ""),
    ("9.2-rectangular", "additive model, four rectangular inputs with σ = 1", "9.2.3, table 3", ""),
    ("9.3-mass", "mass calibration δm (a non-linear model, eq. (22))", "9.3, table 6", "mg"),
    ("9.4-x1=0", "comparison loss δY = X₁² + X₂², x₁ = x₂ = 0 (GUM gives 0 ± 0)", "9.4.1", ""),
    ("9.4-x1=0.010", "comparison loss δY = X₁² + X₂², x₁ = 0.010", "9.4.2", ""),
    ("9.5-gauge-block", "gauge block calibration (scaled t, arcsine and curvilinear trapezoid "
     "inputs)", "9.5, table 15", "nm"),
)


def _example(name: str) -> Callable[[], list[Any]]:
    from ..uncertainty import montecarlo_examples as ex

    return {
        "9.2-normal": functools.partial(ex.additive, "normal"),
        "9.2-rectangular": functools.partial(ex.additive, "rectangular"),
        "9.3-mass": ex.mass,
        "9.4-x1=0": functools.partial(ex.comparison_loss, 0.0),
        "9.4-x1=0.010": functools.partial(ex.comparison_loss, 0.010),
        "9.5-gauge-block": ex.gauge_block,
    }[name]


def _figures(name: str) -> Figures:
    figs = _example(name)()
    # "JCGM 101 9.3 mass calibration: u(δm) GUM" → "u(δm) GUM"
    return Figures([f.computed for f in figs], [f.reference for f in figs],
                   [f.tolerance for f in figs], [f.case.rpartition(": ")[2] for f in figs])


def jcgm101_cases() -> list[ValidationCase]:
    """One case per clause-9 example (:data:`EXAMPLES`), each figure within its 2δ or 3δ."""
    return [
        ValidationCase(f"jcgm101:{name}", f"Monte Carlo propagation: {title}",
                       f"JCGM 101:2008 (GUM Supplement 1) {clause}", (),
                       functools.partial(_figures, name), unit=unit)
        for name, title, clause, unit in EXAMPLES
    ]

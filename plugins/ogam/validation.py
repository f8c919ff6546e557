"""The ogam draft's worked examples as validation cases (``metro validate``): appendix A's
budget of the indication error E and its tilt simulation, recomputed by this plugin's formulas
and printed as the appendix prints them."""

from __future__ import annotations

from metro.api import Q_, BudgetRow, ValidationCase

from . import common as C
from . import formulas as F

SOURCE = "draft JJF 光学陀螺测角仪 appendix A"


def appendix_a_rows() -> list[BudgetRow]:
    """The rows of appendix A's budget of E from its printed inputs: the turntable's 0.1″
    (rectangular), a tilt of 0.1°, a drift of 0.005 °/h over 0.5 min, the repeatability 0.096″
    of 10 readings."""
    return [
        BudgetRow.type_b("turntable", "u(P)", Q_(0.1, "arcsec"), distribution="uniform"),
        C.tilt_row(Q_(0.1, "deg"))[0],
        C.drift_row(Q_(0.005, "deg/h"), Q_(0.5, "min")),
        C.repeatability_row(0.096, 10),
    ]


def _budget() -> list[object]:
    b = C.e_budget(appendix_a_rows())
    c = b.contributions()
    return [*(f"{x:.2f}" for x in c[:3]), float(c[3]),
            f"{b.combined.to('arcsec').magnitude:.2f}", float(b.k), b.expanded_reported().text]


def _tilt() -> list[object]:
    return [f"{F.tilt_error_simulation(0.1).extreme_arcsec:.2f}", F.zero_drift_error(0.005, 0.5)]


def validation_cases() -> list[ValidationCase]:
    """Appendix A 4.1–4.4, 7 and 8 (the budget of E) and A 4.2–4.3 (tilt extreme, drift)."""
    return [
        ValidationCase("ogam:A-budget", "budget of the indication error E: contributions, u_c, "
                       "k and U", f"{SOURCE} 4.1–4.4, 7, 8",
                       ["0.06", "0.05", "0.09", 0.096, "0.15", 2.0, "0.30"], _budget,
                       atol=1e-12, unit="″",
                       labels=("u₁ turntable", "u₂ tilt", "u₃ drift", "u₄ repeatability", "u_c",
                               "k", "U")),
        ValidationCase("ogam:A-tilt", "tilt of 0.1°: extreme error by simulation; zero drift "
                       "0.005 °/h over 0.5 min", f"{SOURCE} 4.2, 4.3", ["0.08", 0.15], _tilt,
                       rtol=1e-12, unit="″", labels=("tilt error extreme", "drift term")),
    ]

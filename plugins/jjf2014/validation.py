"""JJF 2014—2022's worked examples as validation cases (``metro validate``): appendix B's scale
factor and bias budgets, recomputed by this plugin's budgets and printed as the appendix prints
them."""

from __future__ import annotations

import math

from metro.api import Q_, Calibration, ValidationCase

from . import budgets as B
from . import formulas as F


def _cal(U: float) -> Calibration:
    return Calibration("appendix B", Q_(U, ""), k=2.0)


def _b1() -> list[str]:
    b = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4),
                              dmm=_cal(6e-5))
    uc, U = F.appendix_b_presentation(b.combined.magnitude, b.k)
    return [uc, U, b.expanded_reported().text]


def _b2() -> list[str]:
    b1 = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4),
                               dmm=_cal(6e-5))
    uc1 = float(F.appendix_b_presentation(b1.combined.magnitude)[0].split("×")[0]) * 1e-4
    b = B.bias_budget(Q_(1.0, ""), uc1, dmm=_cal(6e-5))
    uc, U = F.appendix_b_presentation(b.combined.magnitude, b.k)
    return [uc, U, b.expanded_reported().text]


def validation_cases() -> list[ValidationCase]:
    """Appendix B.1 and B.2 digit for digit (and U as metro's certificate rounds it)."""
    labels = ("u_c as printed", "U as printed", "U by JJF 1059.1 (certificate)")
    return [
        ValidationCase("jjf2014:B.1", "scale factor budget: rate table 1×10⁻⁴ (k = 2), DMM "
                       "6×10⁻⁵ (k = 2), repeatability 1.54×10⁻⁴", "JJF 2014—2022 appendix B.1",
                       ["1.65×10^-4", "3.3×10^-4", "0.00033"], _b1, labels=labels),
        ValidationCase("jjf2014:B.2", "bias budget: DMM 6×10⁻⁵ (k = 2) and the scale factor's "
                       "u_c of B.1", "JJF 2014—2022 appendix B.2",
                       ["1.68×10^-4", "3.36×10^-4", "0.00034"], _b2, labels=labels),
    ]

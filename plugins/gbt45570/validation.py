"""GB/T 45570—2025's formulas as validation cases (``metro validate``): appendix D's equations
D.40–D.44 on inputs worked by hand (as this plugin's tests check them) and the MTBF lower bound
of 5.5 on the published χ² table."""

from __future__ import annotations

import math

from metro.api import ValidationCase

from . import formulas as F
from . import reliability

#: NIST/SEMATECH e-Handbook 1.3.6.7.4, χ²(0.90; ν) for ν = 8, 6, 2 (3 decimals)
CHI2_090 = {8: 13.362, 6: 10.645, 2: 4.605}


def _hand_worked() -> list[float]:
    bt, _ = F.bias_temperature_sensitivity_d43([0.10, 0.13, 0.07], [20.0, 60.0, -40.0], 0)
    return [F.bias_d40(10.0, 1.0, 1.0, 30.0), F.bias_d40(10.0, 2.0, 0.5, 0.0),
            F.bias_stability_d41([100, 102, 98, 100], 10.0, 1.0),
            F.bias_repeatability_d42([0.1, 0.3, 0.2]), bt,
            F.bias_magnetic_sensitivity_d44(0.15, 0.11, 1.0)]


def _mtbf() -> list[float]:
    T = 62000.0
    return [reliability.mtbf_lower_bound(T, 3, 0.9, "time-terminated"),
            reliability.mtbf_lower_bound(T, 3, 0.9, "failure-terminated"),
            reliability.mtbf_lower_bound(10000.0, 0, 0.9, "time-terminated")]


def validation_cases() -> list[ValidationCase]:
    """D.40–D.44 on inputs worked by hand, and the MTBF lower bounds of 5.5."""
    return [
        ValidationCase(
            "gbt45570:D.40-D.44", "bias (D.40, with and without the earth term), stability (D.41), "
            "repeatability (D.42), temperature (D.43) and magnetic (D.44) sensitivity",
            "GB/T 45570—2025 appendix D eqs. (D.40)–(D.44), inputs worked by hand",
            [10.0 - 15.041 * 0.5, 10.0, math.sqrt(8 / 3) / 10, 0.1, 7.5e-4, 0.02], _hand_worked,
            rtol=1e-12, atol=1e-12,
            labels=("B (D.40), θ = 30°, °/h", "B (D.40), θ = 0, °/h", "B_s (D.41), °/h",
                    "B_r (D.42), °/h", "B_t (D.43), °/h/°C", "B_m (D.44), °/h/mT")),
        ValidationCase(
            "gbt45570:5.5-MTBF", "MTBF lower bound at 90 %: time- and failure-terminated, "
            "r = 3 over 62 000 h; no failure in 10 000 h",
            "GB/T 45570—2025 5.5; χ² from the NIST/SEMATECH e-Handbook 1.3.6.7.4 (3 decimals)",
            [2 * 62000 / CHI2_090[8], 2 * 62000 / CHI2_090[6], 20000 / CHI2_090[2]], _mtbf,
            atol=0.6, unit="h",
            labels=("time-terminated, r = 3", "failure-terminated, r = 3", "r = 0")),
    ]

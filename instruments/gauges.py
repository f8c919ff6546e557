"""The gauges of the simulated GB/T 45570 clause-5 type test: callipers, balance and megohmmeter
(:func:`type_test_equipment`).

Each reads a true value with a fixed error drawn within its certificate's U (seeded by the
instrument and what it reads), adds a relative noise per reading and rounds to its resolution.
"""

from __future__ import annotations

import math
from typing import Any

import attrs
import numpy as np
import pint

from metro.core.base.units import Q_

from .equipment_base import EquipmentModel, fixed_rng, non_negative, q_of, simulated_lab

__all__ = ["Gauge", "Calliper", "Balance", "Megohmmeter", "type_test_equipment"]


@attrs.frozen(kw_only=True)
class Gauge(EquipmentModel):
    """A gauge that reads a true value with a fixed error uniform within ±√3·U/2 (its certificate's
    standard uncertainty), a relative ``noise`` per reading, rounded to ``resolution``."""

    resolution: pint.Quantity = attrs.field(
        default=Q_(0.01, "mm"),
        converter=lambda v: v if isinstance(v, pint.Quantity) else Q_(v),
        validator=non_negative,
    )
    noise: float = 0.0

    def properties(self) -> dict[str, Any]:
        return {"resolution": self.resolution}

    def read(
        self, true: pint.Quantity, n: int, rng: np.random.Generator, *tag: Any
    ) -> list[pint.Quantity]:
        u = self.resolution.units
        x = float(true.to(u).magnitude)
        U = self.U
        if U is None:
            half = 0.0
        else:  # the fixed error: uniform with the certificate's standard uncertainty U/k
            u_abs = (
                float(U.to("").magnitude) * abs(x) if U.dimensionless else float(U.to(u).magnitude)
            )
            half = math.sqrt(3.0) * u_abs / self.k
        err = float(fixed_rng(self.seed, type(self).__name__, *tag).uniform(-half, half))
        res = float(self.resolution.magnitude)
        vals = x + err + rng.normal(0.0, self.noise * abs(x), size=n)
        return [Q_(float(np.round(v / res) * res), u) for v in vals]


@attrs.frozen(kw_only=True)
class Calliper(Gauge):
    ROLE = "calliper"


@attrs.frozen(kw_only=True)
class Balance(Gauge):
    ROLE = "balance"


@attrs.frozen(kw_only=True)
class Megohmmeter(Gauge):
    """Insulation tester: range ``low`` … ``high``; beyond it the display shows ``< low`` /
    ``> high``."""

    ROLE = "megohmmeter"
    low: pint.Quantity = attrs.field(default=Q_(0.1, "Mohm"), converter=q_of("ohm"))
    high: pint.Quantity = attrs.field(default=Q_(10_000, "Mohm"), converter=q_of("ohm"))

    def properties(self) -> dict[str, Any]:
        return {"resolution": self.resolution, "range_low": self.low, "range_high": self.high}


def type_test_equipment(seed: int = 1) -> list[EquipmentModel]:
    """Callipers, balance and megohmmeter of the simulated type test (certificates, U,
    resolution)."""
    return [
        Calliper(id="SIM-CALLIPER", model="simulated digital callipers 0–150 mm",
                 resolution=Q_(0.01, "mm"), noise=1e-4,
                 **simulated_lab(seed, "SIM-CAL-0101", Q_(0.02, "mm"))),
        Balance(id="SIM-BALANCE", model="simulated electronic balance 0–3 kg",
                resolution=Q_(0.1, "g"), noise=2e-5,
                **simulated_lab(seed, "SIM-CAL-0102", Q_(0.2, "g"))),
        Megohmmeter(id="SIM-MEGOHM", model="simulated insulation tester 500 V",
                    resolution=Q_(1, "Mohm"), noise=5e-3,
                    **simulated_lab(seed, "SIM-CAL-0103", Q_(0.05, ""))),
    ]

"""ACME's 10 s-smoothed bias stability, as a metro procedure.

ACME test specification AT-7 clause 3.2: the rate output is smoothed with a 10 s moving
average (every window, overlapping) and the bias stability is the Bessel standard deviation
of the smoothed series, °/h.  For comparison the note gives the GB/T 45570 D.41 value with
non-overlapping 10 s means (``metro.core.stats.allan.block_std``).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from metro.api import (
    OUTPUT_UNITS, Q_, BudgetRow, Coverage, DataError, Metric, Option, Outcome, Procedure, Result,
    SegmentRequirement, Step, UncertaintyBudget, allan, gyro_output,
)
from metro.plugins.gbt45570 import procedures as gbt


def smoothed_std(raw: np.ndarray, window: int) -> tuple[float, int]:
    """ACME AT-7 3.2 eq. (1): s of the moving averages ȳ_j = (1/w) Σ_{i=j}^{j+w−1} y_i, and the
    number of independent windows ⌊n/w⌋ (for the degrees of freedom)."""
    y = np.asarray(raw, dtype=np.float64)
    if window < 1 or y.size < 2 * window:
        raise ValueError(f"{y.size} samples are too few for a {window}-sample moving average")
    mu = float(np.mean(y))
    c = np.concatenate([[0.0], np.cumsum(y - mu)])
    ma = (c[window:] - c[:-window]) / window
    return float(np.std(ma, ddof=1)), y.size // window


class AcmeBiasStability10s(Procedure):
    """ACME AT-7 3.2: 10 s-smoothed bias stability (vendor item in the GB/T 45570 family)."""

    standard = "gbt45570"
    item = "ACME.BS10"
    title = "ACME 10 s-smoothed bias stability"
    clause = "ACME AT-7 3.2"
    metrics = (Metric("Bs_ma10", "10 s-smoothed bias stability", "B_s,10", "deg/h", "AT-7 3.2",
                      "(1)"),)
    requires = (SegmentRequirement("static", "gyro at rest, IRA up (as GB/T 45570 D.5.1.2)",
                                   conditions={"orientation": ""},
                                   columns={"output": OUTPUT_UNITS}),)
    options = (Option("window", "10 s", "s", "moving-average length"),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return gbt.BiasD51().sequence(options)

    def evaluate(self, campaign, ctx) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = campaign.find_segments("static")
        if not segs:
            raise DataError(campaign.source, "segments", f"{self.item} needs a static segment")
        seg = segs[0]
        series, conv = gyro_output(seg, campaign.device, source=campaign.source)
        raw = np.asarray(series.data.magnitude, dtype=np.float64)
        tau = float(series.interval.to("s").magnitude)
        w = int(round(float(opts["window"].to("s").magnitude) / tau))
        try:
            s, m = smoothed_std(raw, w)
        except ValueError as exc:
            raise DataError(seg.file or f"segment {seg.id}", "output", str(exc)) from exc
        bs = s * conv.magnitude
        d41, _ = allan.block_std(raw, w)
        rows = [BudgetRow.type_a(f"sampling of s over {m} independent windows", "B_s/√(2(m−1))",
                                 Q_(bs / math.sqrt(2 * (m - 1)), "deg/h"), m - 1)]
        budget = UncertaintyBudget("B_s,10", "deg/h", rows, coverage=Coverage.fixed(2.0))
        res = Result(self.metrics[0], Q_(bs, "deg/h"), budget.combined, budget,
                     note=f"GB/T 45570 D.41 with non-overlapping means: {d41 * conv.magnitude:.4g} "
                     "°/h")
        return Outcome(self.standard, self.item, self.title, self.clause, [res], segments=[seg.id],
                       options={k: str(v) for k, v in opts.items()})


class AcmeAcceptance(AcmeBiasStability10s):
    """ACME factory acceptance FAT.1: the AT-7 3.2 bias stability on ACME's certificate."""

    standard = "acme"
    item = "FAT.1"
    title = "Factory acceptance: 10 s-smoothed bias stability"

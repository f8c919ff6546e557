"""Uncertainty budgets of JJF 2014—2022, built the way appendix B builds them.

* B.1 scale factor, model K = (F − F_0 − ν)/Ω (B.1), propagation (B.2): rate table
  (relative U, k = 2), data acquisition (6½-digit DMM, relative U, k = 2) and the measurement
  repeatability (type A, from the data).
* B.2 bias, model B_0 = F/K (B.3), propagation (B.4): data acquisition (relative) and the
  scale factor (its relative combined uncertainty from B.1).  In a real run metro adds the
  type A scatter of the mean output F̄, which appendix B leaves out (interpretations.md).

Rows are relative standard uncertainties multiplied by the measured value (sensitivity), so
the budget is in the measurand's unit; with the value 1 (dimensionless) the budget is the
relative one that appendix B prints.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
import pint

from metro.core.locale import join, msg
from metro.core.budget import INF, BudgetRow, Coverage, UncertaintyBudget
from metro.core.model import Calibration
from metro.core.units import Q_

#: k = t_p(ν_eff) for p = 95.45 % (JJF 1059.1 5.3.4): 2.00 for the large ν_eff of appendix B's
#: examples, larger where a repeatability of Q = 6 runs dominates (interpretations.md, "Coverage factor")
COVERAGE = Coverage.probability(0.9545)


def relative_calibration_row(source: str, symbol: str, cal: Calibration | None, value: pint.Quantity,
                             warnings: list[str] | None = None, note: str = "") -> list[BudgetRow]:
    """A type B row from a relative (dimensionless) calibration uncertainty, sensitivity |value|.
    Nothing (and a warning) when the equipment has no relative calibration data."""
    if cal is None or not cal.uncertainty.dimensionless:
        if warnings is not None:
            warnings.append(msg("{source}: no relative calibration uncertainty given, left out of the budget", source=source))
        return []
    return [BudgetRow.from_calibration(source, symbol, cal, sensitivity=abs(value),
                                       note=note or msg("certificate {certificate}", certificate=cal.certificate))]


def scale_factor_budget(K: pint.Quantity, u_rep: pint.Quantity | None, dof: float, *,
                        rate_table: Calibration | None, dmm: Calibration | None,
                        warnings: list[str] | None = None, rep_source: str = "measurement repeatability",
                        extra: Sequence[BudgetRow] = (), rep_row: BudgetRow | None = None) -> UncertaintyBudget:
    """Appendix B.1 budget of K: u_c² = u_1² + u_2² + u_3² (B.2 with relative components).

    :param K: the scale factor (use ``Q_(1, "")`` for the relative budget of appendix B).
    :param u_rep: standard uncertainty from repeatability, in K's unit (B.1.2.2 3)).
    :param dof: its degrees of freedom (``math.inf`` when stated without).
    :param rep_row: the u₃ row itself (instead of ``u_rep``/``dof``), e.g. a stated repeatability (type B).
    """
    rows = relative_calibration_row("rate table (B.1.2.2 1))", "u₁", rate_table, K, warnings)
    rows += relative_calibration_row("data acquisition, 6½-digit DMM (B.1.2.2 2))", "u₂", dmm, K, warnings)
    rows.append(rep_row if rep_row is not None else BudgetRow.type_a(join(" ", [rep_source, "(B.1.2.2 3))"]), "u₃", u_rep, dof))
    rows += list(extra)
    return UncertaintyBudget("scale factor K", K.units, rows, coverage=COVERAGE)


def bias_budget(B0: pint.Quantity, u_rel_K: float, *, dmm: Calibration | None, u_A: pint.Quantity | None = None,
                dof_A: float = INF, warnings: list[str] | None = None,
                extra: Sequence[BudgetRow] = (), dof_K: float = INF,
                rep_row: BudgetRow | None = None, note_A: str = "") -> UncertaintyBudget:
    """Appendix B.2 budget of B_0 = F/K: data acquisition (relative, B.2.2.2 1)) and the scale
    factor (relative u_c of K with its ν_eff, B.2.2.2 2)); plus, when given, the type A scatter
    of F̄/K, or ``rep_row`` in its place (the bias repeatability, which holds that scatter)."""
    rows = relative_calibration_row("data acquisition, 6½-digit DMM (B.2.2.2 1))", "u₁", dmm, B0, warnings)
    rows.append(BudgetRow.type_b("scale factor K (B.2.2.2 2))", "u₂", Q_(u_rel_K, ""), distribution="normal",
                                 k=1.0, sensitivity=abs(B0), dof=dof_K, note=msg("relative combined uncertainty of K (B.1.3)")))
    if rep_row is not None:
        rows.append(rep_row)
    elif u_A is not None:
        rows.append(BudgetRow.type_a("scatter of the mean output (batch means)", "u_A", u_A, dof_A, note=note_A))
    rows += list(extra)
    return UncertaintyBudget("bias B0", B0.units, rows, coverage=COVERAGE)


def type_a_budget(measurand: str, unit: str, rows: Sequence[BudgetRow], note: str = "") -> UncertaintyBudget:
    return UncertaintyBudget(measurand, unit, list(rows), coverage=COVERAGE, note=note)


def std_of_std(s: float, q: int) -> tuple[float, float]:
    """Standard uncertainty of a Bessel standard deviation of q values as an estimate of σ, and its ν:
    the χ² bound (σ_upper − s)/2 with ν = ∞ (:func:`metro.core.budget.std_sampling_u`; s + 2u is the
    97.7 % upper confidence limit).  The linear s/√(2(q − 1)) with ν = q − 1 covered K_r in 91 % of the
    independent harness's devices at q = 6 (docs/independent-campaigns.md)."""
    from metro.core.budget import std_sampling_u

    return std_sampling_u(s, q), math.inf


def std_of_std_correlated(s: float, means) -> tuple[float, float, str]:
    """Standard uncertainty of eq. (29)'s B_s, a Bessel standard deviation ``s`` of the m averages
    ``means``, when the averages may be correlated (flicker, wander, a ramp: neighbouring averages
    alike): the χ² bound of :func:`std_of_std` on the effective number of degrees of freedom
    ν_eff = (m − 1)/(1 + 2Σρ_k²) (Bartlett's variance of a sample variance of a correlated
    series; ρ_k the averages' sample autocorrelation over lags 1 … m/4, each ρ̂_k² less the 1/m that
    sampling noise alone puts into it).  Independent averages give ν_eff ≈ m − 1 and the χ² bound of m values.  Returns
    (u, ν = ∞ as the χ² bound is entered, a note naming ν_eff when it is below m − 1)
    (interpretations.md, "7.2.14 — B_s of correlated averages")."""
    from scipy.stats import chi2

    x = np.asarray(means, dtype=float)
    m = x.size
    x = x - x.mean()
    c0 = float(x @ x) / m
    acc = 0.0
    if c0 > 0 and m >= 8:
        L = m // 4
        c = np.array([c0] + [float(x[:-k] @ x[k:]) / m for k in range(1, L + 1)])
        # the autocovariances about the record's own mean are low by Var(x̄), the variance of that mean
        # (E[ĉ_k] ≈ γ_k − Var(x̄)); where the averages are correlated over a good part of the record this
        # is much of γ_k, and ν_eff came out too large.  Var(x̄) = γ₀/m·(1 + 2Σ(1 − k/m)ρ_k) from the
        # corrected ρ, by fixed point (interpretations.md, "7.2.14 — B_s of correlated averages")
        lag = np.arange(1, L + 1)
        v = 0.0
        for _ in range(50):
            g = c + v
            v_new = max(0.0, float(g[0] / m * (1.0 + 2.0 * np.sum((1.0 - lag / m) * g[1:] / g[0]))))
            if abs(v_new - v) <= 1e-9 * g[0]:
                break
            v = v_new
        r = (c[1:] + v) / (c[0] + v)
        acc = max(0.0, float(np.sum(r * r)) - L / m)  # each ρ̂_k² carries ≈ 1/m of sampling noise
    nu = (m - 1) / (1.0 + 2.0 * acc)
    upper = float(s) * math.sqrt(nu / float(chi2.ppf(0.02275, nu)))
    note = ("" if acc * 2 < 0.05 else
            msg("the {m} averages are correlated (Σρ_k² = {acc:.3g}): χ² bound on ν_eff = {nu:.3g}", m=m, acc=acc, nu=nu))
    return (upper - float(s)) / 2.0, math.inf, note


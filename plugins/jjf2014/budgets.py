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
from metro.api import INF, Q_, BudgetRow, Calibration, Coverage, UncertaintyBudget, join, msg

#: k = t_p(ν_eff) for p = 95.45 % (JJF 1059.1 5.3.4): 2.00 for the large ν_eff of appendix B's
#: examples, larger where a repeatability of Q = 6 runs dominates (interpretations.md, "Coverage
#: factor")
COVERAGE = Coverage.probability(0.9545)


def relative_calibration_row(source: str, symbol: str, cal: Calibration | None,
                             value: pint.Quantity,
                             warnings: list[str] | None = None, note: str = "") -> list[BudgetRow]:
    """A type B row from a relative (dimensionless) calibration uncertainty, sensitivity |value|.
    Nothing (and a warning) when the equipment has no relative calibration data."""
    if cal is None or not cal.uncertainty.dimensionless:
        if warnings is not None:
            warnings.append(msg("{source}: no relative calibration uncertainty given, left out of "
                                "the budget", source=source))
        return []
    return [BudgetRow.from_calibration(source, symbol, cal, sensitivity=abs(value),
                                       note=note
                                       or msg("certificate {certificate}",
                                              certificate=cal.certificate))]


def scale_factor_budget(K: pint.Quantity, u_rep: pint.Quantity | None, dof: float, *,
                        rate_table: Calibration | None, dmm: Calibration | None,
                        warnings: list[str] | None = None,
                        rep_source: str = "measurement repeatability",
                        extra: Sequence[BudgetRow] = (),
                        rep_row: BudgetRow | None = None) -> UncertaintyBudget:
    """Appendix B.1 budget of K: u_c² = u_1² + u_2² + u_3² (B.2 with relative components).

    :param K: the scale factor (use ``Q_(1, "")`` for the relative budget of appendix B).
    :param u_rep: standard uncertainty from repeatability, in K's unit (B.1.2.2 3)).
    :param dof: its degrees of freedom (``math.inf`` when stated without).
    :param rep_row: the u₃ row itself (instead of ``u_rep``/``dof``), e.g. a stated repeatability
    (type B).
    """
    rows = relative_calibration_row("rate table (B.1.2.2 1))", "u₁", rate_table, K, warnings)
    rows += relative_calibration_row("data acquisition, 6½-digit DMM (B.1.2.2 2))", "u₂", dmm, K,
                                     warnings)
    rows.append(rep_row if rep_row is not None
                else BudgetRow.type_a(join(" ", [rep_source, "(B.1.2.2 3))"]), "u₃", u_rep, dof))
    rows += list(extra)
    return UncertaintyBudget("scale factor K", K.units, rows, coverage=COVERAGE)


def bias_budget(B0: pint.Quantity, u_rel_K: float, *, dmm: Calibration | None,
                u_A: pint.Quantity | None = None,
                dof_A: float = INF, warnings: list[str] | None = None,
                extra: Sequence[BudgetRow] = (), dof_K: float = INF,
                rep_row: BudgetRow | None = None, note_A: str = "") -> UncertaintyBudget:
    """Appendix B.2 budget of B_0 = F/K: data acquisition (relative, B.2.2.2 1)) and the scale
    factor (relative u_c of K with its ν_eff, B.2.2.2 2)); plus, when given, the type A scatter
    of F̄/K, or ``rep_row`` in its place (the bias repeatability, which holds that scatter)."""
    rows = relative_calibration_row("data acquisition, 6½-digit DMM (B.2.2.2 1))", "u₁", dmm, B0,
                                    warnings)
    rows.append(BudgetRow.type_b("scale factor K (B.2.2.2 2))", "u₂", Q_(u_rel_K, ""),
                                 distribution="normal",
                                 k=1.0, sensitivity=abs(B0), dof=dof_K,
                                 note=msg("relative combined uncertainty of K (B.1.3)")))
    if rep_row is not None:
        rows.append(rep_row)
    elif u_A is not None:
        rows.append(BudgetRow.type_a("scatter of the mean output (batch means)", "u_A", u_A, dof_A,
                                     note=note_A))
    rows += list(extra)
    return UncertaintyBudget("bias B0", B0.units, rows, coverage=COVERAGE)


def type_a_budget(measurand: str, unit: str, rows: Sequence[BudgetRow],
                  note: str = "") -> UncertaintyBudget:
    return UncertaintyBudget(measurand, unit, list(rows), coverage=COVERAGE, note=note)


def std_of_std(s: float, q: int) -> tuple[float, float]:
    """Standard uncertainty of a Bessel standard deviation of q values as an estimate of σ, and its
    ν: the χ² bound (σ_upper − s)/2 with ν = ∞
    (:func:`metro.core.uncertainty.budget.std_sampling_u`; s + 2u is the 97.7 % upper confidence
    limit).  The linear s/√(2(q − 1)) with ν = q − 1 covered K_r in 91 % of the independent
    harness's devices at q = 6 (docs/independent-campaigns.md)."""
    from metro.api import std_sampling_u

    return std_sampling_u(s, q), math.inf


def averages_dof_model(x, P: int, dt: float) -> tuple[float, float] | None:
    """Effective degrees of freedom of eq. (29)'s s² of the N/P averages, from the record's own
    noise model: 7.2.20's eq. (38) fit σ²(τ) = Σ A_m τ^m to the overlapping Allan variance of the
    samples ``x`` (octave τ up to N/4, GLS with the exact covariance, negative terms removed:
    :func:`formulas.fit_allan_eq38`), then
    :func:`metro.core.stats.allan.block_variance_dof` — the averages' covariance under that white /
    flicker / random- walk model with its rate ramp as a fixed trend, and ν = 2E[s²]²/Var(s²) of
    the Bessel variance of the centred averages.  The model's flicker and random walk are read off
    the whole range of τ (many clusters each), not off the few slow excursions one record happens
    to hold, which is what fooled ν from the record's own autocorrelation (docs/interpretations.md,
    "7.2.14 — B_s of correlated averages").  None when the record is too short for the fit (fewer
    than 6 octave τ values) or has no noise; (ν, E[s²]) otherwise."""
    from metro.api import allan

    from .formulas import ALLAN_TERMS, fit_allan_eq38

    y = np.asarray(x, dtype=float)
    m = y.size // P
    try:
        ms = allan.octave_m(y.size, 0.25)
        if ms.size < 6 or m < 2:
            return None
        ad = allan.oadev(y, dt, ms)
        tau0_h = dt / 3600.0
        fit = fit_allan_eq38(np.asarray(ad.tau) / 3600.0, np.asarray(ad.deviation),
                             np.asarray(ad.edf),
                             n_samples=int(ad.n_samples), tau0_h=tau0_h, nonnegative=True)
    except (ValueError, np.linalg.LinAlgError):
        return None
    a = np.asarray(fit.A, dtype=float) * tau0_h ** np.array([k for k, _ in ALLAN_TERMS],
                                                            dtype=float)
    nu, e = allan.block_variance_dof(m, P, a)
    return (nu, e) if math.isfinite(e) and e > 0 else None


def std_of_std_correlated(s: float, means, samples=None, P: int | None = None,
                          dt: float | None = None) -> tuple[float, float, str]:
    """Standard uncertainty of eq. (29)'s B_s, a Bessel standard deviation ``s`` of the m averages
    ``means``, when the averages may be correlated (flicker, wander, a ramp: neighbouring averages
    alike): the χ² bound of :func:`std_of_std` on an effective number of degrees of freedom ν_eff.

    With the record's ``samples`` (and ``P`` samples per average, interval ``dt``) ν_eff is the
    noise model's (:func:`averages_dof_model`: Satterthwaite's ν of s² for the eq. (38) fit's
    white, flicker, random walk and ramp).  Without them, or when the record is too short for that
    fit, Bartlett's ν_eff = (m − 1)/(1 + 2Σρ_k²) (M. S. Bartlett, J. R. Stat. Soc. Suppl. 8, 1946:
    the variance of a sample variance of a correlated series; ρ_k the averages' sample
    autocorrelation over lags 1 … m/4, corrected for the record's own mean, each ρ̂_k² less the 1/m
    that sampling noise alone puts into it). Bartlett's ν from one record is too large exactly when
    the record happened to show little of its slow noise — and then s is low too — so it left B_s
    outside U on 6 % of the independent harness's flicker and wander devices; the model's ν is read
    off the whole Allan curve (interpretations.md, "7.2.14 — B_s of correlated averages").
    Independent averages give ν_eff ≈ m − 1 and the χ² bound of m values.  Returns (u, ν = ∞ as the
    χ² bound is entered, a note naming ν_eff when it is below m − 1)."""
    from metro.api import std_sampling_u

    x = np.asarray(means, dtype=float)
    m = x.size
    model = averages_dof_model(samples, int(P),
                               float(dt)) if samples is not None and P and dt else None
    if model is not None:
        nu = min(float(m - 1), max(1.0, model[0]))
        note = ("" if nu >= 0.95 * (m - 1) else
                msg("ν_eff = {nu:.3g} of the {m} averages from the record's noise model (eq. (38) "
                    "fit: white, flicker, random walk, ramp): χ² bound on it", nu=nu, m=m))
        return std_sampling_u(s, dof=nu), math.inf, note
    x = x - x.mean()
    c0 = float(x @ x) / m
    acc = 0.0
    if c0 > 0 and m >= 8:
        L = m // 4
        c = np.array([c0] + [float(x[:-k] @ x[k:]) / m for k in range(1, L + 1)])
        # the autocovariances about the record's own mean are low by Var(x̄), the variance of that
        # mean (E[ĉ_k] ≈ γ_k − Var(x̄)); where the averages are correlated over a good part of the
        # record this is much of γ_k, and ν_eff came out too large.  Var(x̄) = γ₀/m·(1 + 2Σ(1 −
        # k/m)ρ_k) from the corrected ρ, by fixed point (interpretations.md, "7.2.14 — B_s of
        # correlated averages")
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
    note = ("" if acc * 2 < 0.05 else
            msg("the {m} averages are correlated (Σρ_k² = {acc:.3g}): χ² bound on ν_eff = {nu:.3g}",
                m=m, acc=acc, nu=nu))
    return std_sampling_u(s, dof=nu), math.inf, note


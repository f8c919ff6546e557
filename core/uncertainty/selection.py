"""The largest of several noisy slopes: its selection bias by Monte Carlo (GUM Supplement 1).

Standards define temperature sensitivities as the largest |slope| against room temperature over
the points (GB/T 45570 eqs. (D.12), (D.29), (D.43); JJF 2014 eqs. (11) and (31)), and changes or
sensitivities as the largest |difference| over the axes (JJF 2014 eqs. (13), (15), 7.2.17.2,
7.2.18.2, 7.2.19.2).  The largest of several noisy values overstates the device's largest; this
module estimates by how much, and gives the budget rows and note of the correction
(interpretations.md, "D.1.5 / D.2.5 / D.5.4 — the largest of several noisy slopes" and
"JJF 2014 — the largest of noisy slopes and changes").
"""

from __future__ import annotations

import math
from typing import Sequence

import attrs
import numpy as np

from .budget import BudgetRow, std_upper_limit
from ..stats.lsq import fit_line
from ..base.locale import msg
from ..base.units import Q_

__all__ = [
    "MaxSelection",
    "max_slope_selection",
    "max_abs_selection",
    "selection_rows",
    "abs_change",
    "abs_change_rows",
    "abs_change_note",
    "selection_note",
    "spread_rows",
    "upper_sigma",
    "line_scatter",
]


@attrs.frozen
class MaxSelection:
    """The largest of several noisy slopes (D.12, D.29, D.43) and what selecting it costs."""

    printed: float  # the standard's value, max_i |…| of the measured points
    value: float  # corrected for the selection bias: printed − bias
    s: float  # standard deviation of the maximum over the Monte Carlo draws
    bias: float  # mean of the simulated maxima minus the maximum of the smoothed points
    # degree of the polynomial the points were smoothed with (−1: not smoothed, χ² rejected it;
    # −2: each value's size shrunk by its own noise, :func:`max_abs_selection`)
    degree: int
    #: the points' observed scatter, where it was smaller than their stated u and the draws used it
    #: instead (``observed=True``); None when the stated u were used
    scatter: float | None = None


def upper_sigma(s: float, dof: int, p: float = 0.95) -> float:
    """The one-sided ``p`` upper confidence limit of σ from a standard deviation ``s`` of ``dof``
    degrees of freedom, s·√(ν/χ²_{1−p}(ν)) (:func:`metro.core.uncertainty.budget.std_upper_limit`; ν
    = 2: 4.41·s,
    ν = 5: 2.09·s)."""
    return std_upper_limit(s, int(dof) + 1, 1.0 - p)


def line_scatter(y: Sequence[float], x: Sequence[float]) -> tuple[float, int]:
    """The residual standard deviation of ``y`` about a least-squares straight line in ``x``
    (:func:`metro.core.stats.lsq.fit_line`) and its n − 2 degrees of freedom; (0, 0) with fewer than
    four
    points (a line through three leaves one degree of freedom: no estimate of a scatter)."""
    if len(y) < 4:
        return 0.0, 0
    fit = fit_line(np.asarray(x, dtype=float), np.asarray(y, dtype=float))
    return float(fit.residual_sd), int(fit.dof)


def curve_scatter(y: Sequence[float], x: Sequence[float], degree: int = 1) -> tuple[float, int]:
    """The residual standard deviation of ``y`` about a least-squares polynomial of ``degree`` in
    ``x`` and its n − degree − 1 degrees of freedom; :func:`line_scatter` for degree 1, and (0, 0)
    with fewer than degree + 3 points (no estimate of a scatter from one degree of freedom)."""
    if degree <= 1:
        return line_scatter(y, x)
    yy, xx = np.asarray(y, dtype=float), np.asarray(x, dtype=float)
    if yy.size < degree + 3:
        return 0.0, 0
    xc = xx - xx.mean()
    r = yy - np.polyval(np.polyfit(xc, yy, degree), xc)
    dof = yy.size - degree - 1
    return float(math.sqrt(float(np.sum(r * r)) / dof)), int(dof)


def max_slope_selection(
    values: Sequence[float],
    u: Sequence[float],
    temps_C: Sequence[float],
    i0: int,
    *,
    relative: bool,
    draws: int = 4000,
    seed: int = 45570,
    observed: bool = False,
    cap_degree: int = 1,
    u_dof: float = math.inf,
) -> MaxSelection:
    """Selection bias of max_i |(y_i − y_0)/(d·(T_i − T_0))| (d = y_0 when ``relative``, D.12/D.29;
    d = 1, D.43), by Monte Carlo (GUM Supplement 1) about a smoothed K(T) or B(T).

    Taking the largest of several noisy slopes overstates the device's largest slope: when the
    sensitivity is the same at every point (a linear K(T)), the maximum of N noisy slopes exceeds
    it by about the expected maximum of N normal deviates (≈ 1.16 σ for N = 5).  A bootstrap about
    the measured points sees almost none of it (their noise has already spread them apart), so the
    points are first smoothed by a weighted straight line in T — unless its χ²
    exceeds the 95 % point for n − degree − 1 degrees of freedom, when the points are kept as they
    are (the slopes differ beyond the noise) — the y_i drawn about it with their u_i (normal,
    independent), and

        bias = mean(max*) − max(smoothed),   s = std(max*),   value = printed − bias.

    ``observed``: ``u`` may hold a scatter between calibrations that these points do not have (JJF
    2014's budgets put the repeatability K_r·K or B_r in every point, while the chamber's points
    may be one power-on).  With ``observed`` (n ≥ 4), each point is drawn with at most the 95 %
    upper confidence limit of σ from the points' rms scatter s_r about a straight line in T
    (n − 2 degrees of freedom, s_r·√((n − 2)/χ²₀.₀₅(n − 2))): a stated u far above what the points
    show would correct for a noise they do not have, while a scatter small by chance does not
    take away the correction of a noise they do have.  ``cap_degree`` 2: where there are ≥ 5 points,
    the smaller of that limit and the one from the scatter about a quadratic in T (n − 3 degrees of
    freedom) — a curved K(T) is a real difference between the slopes, not scatter (JJF 2014,
    interpretations.md "7.2.5 / 7.2.16 — a curved K(T) is not noise").

    ``u_dof``: the degrees of freedom of the u_i themselves where they are one estimate of few
    degrees of freedom (GB/T D.1.5 / D.2.5: K's turn-on scatter from seven repeatability runs).  The
    straight line is then rejected when Σ((y − line)/u)²/(n − 2) exceeds the 95 % point of F(n − 2,
    u_dof) rather than of χ²(n − 2)/(n − 2): a u small by chance must not reject the line
    (interpretations.md "D.2.5 — the line test with an estimated scatter").

    Hand-checked: five equal slopes of u = 1 give bias ≈ +1.1 (the mean maximum of five |N(0,1)|
    deviates about a common slope of 10 is 10 + 1.16; the shared y_0 correlates them, which lowers
    it a little); one slope far above the rest gives bias ≈ 0.
    """
    y = np.asarray(values, dtype=float)
    uu = np.asarray(u, dtype=float)
    T = np.asarray(temps_C, dtype=float)
    if not (y.size == uu.size == T.size) or y.size < 2:
        raise ValueError("one value and one u per temperature point, at least two points")
    others = np.array([i for i in range(y.size) if i != i0])

    def stat(Y: np.ndarray) -> np.ndarray:
        d = Y[..., [i0]] if relative else 1.0
        return np.max(np.abs((Y[..., others] - Y[..., [i0]]) / (d * (T[others] - T[i0]))), axis=-1)

    printed = float(stat(y))
    scatter = None
    sr, nu = line_scatter(y, T) if observed else (0.0, 0)
    if nu:
        cap = upper_sigma(sr, nu)
        sq, nq = curve_scatter(y, T, cap_degree) if cap_degree > 1 else (0.0, 0)
        if nq:
            cap = min(cap, upper_sigma(sq, nq))
        if np.any(cap < uu):
            uu, scatter = np.minimum(uu, cap), cap
    deg = 1
    w = 1.0 / np.where(uu > 0, uu, np.min(uu[uu > 0]) if np.any(uu > 0) else 1.0)
    tc = T - T.mean()
    smooth = np.polyval(np.polyfit(tc, y, deg, w=w), tc)
    if not np.any(uu > 0):
        return MaxSelection(printed, printed, 0.0, 0.0, deg, scatter)
    from scipy.stats import chi2

    dof = y.size - deg - 1
    if math.isfinite(u_dof) and u_dof > 0:
        from scipy.stats import f as f_dist

        limit = dof * float(f_dist.ppf(0.95, dof, u_dof)) if dof >= 1 else math.inf
    else:
        limit = float(chi2.ppf(0.95, dof)) if dof >= 1 else math.inf
    if dof >= 1 and float(np.sum(((y - smooth) * w) ** 2)) > limit:
        smooth, deg = (
            y,
            -1,
        )  # the points depart from a smooth curve beyond their u: take them as they are
    sample = np.random.default_rng(seed).normal(smooth, uu, size=(int(draws), y.size))
    mx = stat(sample)
    bias = float(mx.mean() - stat(smooth))
    return MaxSelection(printed, printed - bias, float(mx.std(ddof=1)), bias, deg, scatter)


def max_abs_selection(
    values: Sequence[float],
    u: Sequence[float],
    *,
    draws: int = 4000,
    seed: int = 2014,
    same: Sequence[float] | None = None,
) -> MaxSelection:
    """Selection bias of max_j |d_j| over independent noisy values d_j ~ N(δ_j, u_j²) (the largest
    change over the axes, JJF 2014 eqs. (13), (15), 7.2.18.2, 7.2.19.2; the largest sensitivity,
    7.2.17.2), by Monte Carlo (GUM Supplement 1).

    |d_j| overstates |δ_j| (E d_j² = δ_j² + u_j²) and the maximum over the axes picks the one whose
    noise pushed it up.  Each size is first shrunk by its own noise, moment-matched,
    δ̂_j = sign(d_j)·√max(0, d_j² − u_j²); the d_j are drawn about δ̂_j with their u_j, and

        bias = mean(max_j |d_j*|) − max_j |δ̂_j|,   s = std(max_j |d_j*|),   value = printed − bias.

    ``same``: when ``u`` may hold a scatter between calibrations that these do not have (JJF 2014's
    budgets put K_r·K or B_r in every calibration), values that estimate one quantity with the same
    kind of calibration (the K or bias before the test, on every axis): each d_j, a difference of
    two calibrations, is drawn with at most √2 times the 95 % upper confidence limit of σ from
    their standard deviation (as ``observed`` of :func:`max_slope_selection`).

    Hand-checked over 1000 draws each (u = 1, three axes): true changes (−0.53, 0.88, 0.35)·u read
    +0.34·U high as printed and +0.10·U corrected; one change of 5u alone: no bias either way; all
    three zero: +0.67 → +0.36 (the value is kept ≥ 0), the case where a maximum of pure noise is
    reported — see interpretations.md.
    """
    d = np.asarray(values, dtype=float)
    uu = np.asarray(u, dtype=float)
    if d.size != uu.size or d.size < 1:
        raise ValueError("one u per value, at least one value")
    printed = float(np.max(np.abs(d)))
    scatter = None
    if same is not None and len(same) >= 2:
        cap = float(np.sqrt(2.0)) * upper_sigma(
            float(np.std(np.asarray(same, dtype=float), ddof=1)), len(same) - 1
        )
        if np.any(cap < uu):
            uu, scatter = np.minimum(uu, cap), cap
    if not np.any(uu > 0):
        return MaxSelection(printed, printed, 0.0, 0.0, -2, scatter)
    shrunk = np.sign(d) * np.sqrt(np.maximum(0.0, d * d - uu * uu))
    sample = np.random.default_rng(seed).normal(shrunk, uu, size=(int(draws), d.size))
    mx = np.max(np.abs(sample), axis=-1)
    bias = float(mx.mean() - np.max(np.abs(shrunk)))
    return MaxSelection(printed, printed - bias, float(mx.std(ddof=1)), bias, -2, scatter)


def selection_rows(
    sel: MaxSelection, n: int, unit: str, *, slopes: bool = True, point_unit: str = ""
) -> list[BudgetRow]:
    """The row of the selection-bias correction of a maximum (D.12, D.29, D.43; JJF 2014 eqs. (11),
    (13), (15), (31)): the correction is uncertain by up to its own size (uniform, half-width
    |bias|)."""
    if not sel.bias:
        return []
    what = (
        msg("correction for taking the largest of {n} noisy slopes (Monte Carlo)", n=n)
        if slopes
        else msg("correction for taking the largest of {n} noisy changes (Monte Carlo)", n=n)
    )
    if sel.degree >= 0:
        how = msg("{c:+.3g} applied; about a degree-{d} polynomial in T", c=-sel.bias, d=sel.degree)
    elif sel.degree == -2:
        how = msg("{c:+.3g} applied; about each value shrunk by its own noise", c=-sel.bias)
    else:
        how = msg("{c:+.3g} applied; about the points as measured", c=-sel.bias)
    if sel.scatter is not None:
        how = msg(
            "{how}; drawn with at most {s:.3g} {unit}, "
            "the 95 % upper limit of the points' own scatter",
            how=how,
            s=sel.scatter,
            unit=point_unit,
        )
    return [
        BudgetRow.type_b(what, "δ_sel", Q_(abs(sel.bias), unit), distribution="uniform", note=how)
    ]


def spread_rows(sel: MaxSelection, u_point: float, unit: str) -> list[BudgetRow]:
    """What the maximum's spread over the Monte Carlo draws adds to the maximising point's own
    u (``u_point``, the budget's rows for that point): √(s² − u_point²) when s is larger (another
    point could have given the maximum), normal, else nothing."""
    if not sel.s > u_point:
        return []
    return [
        BudgetRow.type_b(
            msg(
                "spread of the maximum over the Monte Carlo draws "
                "beyond the maximising point's own u"
            ),
            "√(s² − u_i²)",
            Q_(float(np.sqrt(sel.s**2 - u_point**2)), unit),
            distribution="normal",
            k=1.0,
            note=msg("s = {s:.3g}, the maximising point alone {u:.3g}", s=sel.s, u=u_point),
        )
    ]


def selection_note(sel: MaxSelection, scale: float, unit: str) -> str:
    """The note of a corrected maximum: the value as the standard's formula prints it, and the bias
    removed."""
    return msg(
        "as printed by the formula {printed:.4g} {unit}, selection bias {bias:+.2g} {unit} removed "
        "(interpretations.md)",
        printed=sel.printed * scale,
        bias=sel.bias * scale,
        unit=unit,
    )


def abs_change(d: float, u: float) -> MaxSelection:
    """The absolute value of one noisy difference d ~ N(δ, u²), read as |δ| (GB/T 45570 eqs. (D.44),
    (D.47), (D.48)): its bias, in closed form (the folded normal distribution).

    E|d| = u·√(2/π)·exp(−δ²/2u²) + δ·erf(δ/(u√2)) exceeds |δ| (by 0.80 u at δ = 0, 0.20 u at δ = u,
    under 0.01 u beyond 2.6 u).  The bias is estimated about the size shrunk by its own noise,
    moment-matched as :func:`max_abs_selection` does for several values, δ̂ = √max(0, d² − u²)
    (E d² = δ² + u²), and

        bias = E|N(δ̂, u²)| − δ̂,   s = √(δ̂² + u² − (E|N(δ̂, u²)|)²),   value = |d| − bias

    (``degree`` −3: one value, in closed form — the one-value case of :func:`max_abs_selection`
    without its Monte Carlo).  A bias under 0.001 u (δ̂ beyond ≈ 3 u) is taken as none: no row, no
    note.  The caller keeps the value ≥ 0.  Hand-checked: d = 0, u = 1 gives
    bias √(2/π) = 0.798 (value −0.798, reported as 0); d = 3, u = 1: δ̂ = √8 = 2.828, E|N(δ̂, 1)| =
    2.8298, bias 0.0014; d = 1.2, u = 1: δ̂ = 0.663, bias 0.304 (Monte Carlo of
    :func:`max_abs_selection` over 400 000 draws: 0.798, 0.0011, 0.303).  Over noise draws the
    printed |d|
    reads +0.80 u high at δ = 0 and the corrected value +0.3 u (interpretations.md "D.5.5 / D.6.3 /
    D.6.4 — the absolute value of one noisy difference").
    """
    d, u = float(d), abs(float(u))
    printed = abs(d)
    if not u > 0 or not math.isfinite(u):
        return MaxSelection(printed, printed, 0.0, 0.0, -3)
    m = math.sqrt(max(0.0, d * d - u * u))
    mean = u * math.sqrt(2.0 / math.pi) * math.exp(-0.5 * (m / u) ** 2) + m * math.erf(
        m / (u * math.sqrt(2.0))
    )
    bias = max(0.0, mean - m)  # ≥ 0: E|X| ≥ |E X|; rounding can take it a hair below
    if (
        bias < 1e-3 * u
    ):  # δ̂ beyond ≈ 3 u: nothing worth a row or a note (it was 1e-16 … 1e-7 of the value)
        bias = 0.0
    s = math.sqrt(max(0.0, m * m + u * u - mean * mean))
    return MaxSelection(printed, printed - bias, s, bias, -3)


def abs_change_rows(sel: MaxSelection, unit: str, u: float) -> list[BudgetRow]:
    """The row of the correction of :func:`abs_change` (``u``: the difference's noise, as given to
    it): normal, of standard uncertainty √(u·bias + bias²/4), so that the corrected value's interval
    at k = 2, (|d| − bias) ± 2√(u² + u·bias + bias²/4) = (|d| − bias) ± (2u + bias), holds the
    formula's |d| ± 2u.

    The correction depends on δ, known only to about u: at d ≈ u it may be anything from 0 (δ ≈ 2–3
    u) to 0.8 u (δ = 0).  The uniform ±|bias| of a maximum's correction (:func:`selection_rows`)
    left the value outside U on 9 % of draws at δ = 2.5 u (|d| ± 2u: 4.4 %); u = |bias|, 5.8 % at δ
    = 3 u
    (4.4 %); this row never more than |d| ± 2u (interpretations.md)."""
    if not sel.bias > 0:
        return []
    uc = math.sqrt(abs(float(u)) * sel.bias + 0.25 * sel.bias**2)
    return [
        BudgetRow.type_b(
            msg("folded-normal correction of |d| (the amount: the result's note)"),
            "δ_abs",
            Q_(uc, unit),
            distribution="normal",
            k=1.0,
        )
    ]


def abs_change_note(sel: MaxSelection, scale: float, unit: str) -> str:
    """The note of a corrected absolute difference: the value as the standard's formula prints it,
    and the bias
    removed."""
    return msg(
        "as printed by the formula {printed:.4g} {unit}, less {bias:.2g} {unit} (folded normal)",
        printed=sel.printed * scale,
        bias=sel.bias * scale,
        unit=unit,
    )

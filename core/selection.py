"""The largest of several noisy slopes: its selection bias by Monte Carlo (GUM Supplement 1).

Standards define temperature sensitivities as the largest |slope| against room temperature over
the points (GB/T 45570 eqs. (D.12), (D.29), (D.43); JJF 2014's eqs. (11) and (31) have the same
form but do not use this yet).  With a sensitivity that is the same at every point, the largest of
N noisy slopes overstates it; this module estimates by how much
(interpretations.md, "D.1.5 / D.2.5 / D.5.4 — the largest of several noisy slopes").
"""

from __future__ import annotations

from typing import Sequence

import attrs
import numpy as np

__all__ = ["MaxSelection", "max_slope_selection"]


@attrs.frozen
class MaxSelection:
    """The largest of several noisy slopes (D.12, D.29, D.43) and what selecting it costs."""

    printed: float  # the standard's value, max_i |…| of the measured points
    value: float  # corrected for the selection bias: printed − bias
    s: float  # standard deviation of the maximum over the Monte Carlo draws
    bias: float  # mean of the simulated maxima minus the maximum of the smoothed points
    degree: int  # degree of the polynomial the points were smoothed with (−1: not smoothed, χ² rejected it)


def max_slope_selection(values: Sequence[float], u: Sequence[float], temps_C: Sequence[float], i0: int, *,
                        relative: bool, draws: int = 4000, seed: int = 45570) -> MaxSelection:
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
    deg = 1
    w = 1.0 / np.where(uu > 0, uu, np.min(uu[uu > 0]) if np.any(uu > 0) else 1.0)
    tc = T - T.mean()
    smooth = np.polyval(np.polyfit(tc, y, deg, w=w), tc)
    if not np.any(uu > 0):
        return MaxSelection(printed, printed, 0.0, 0.0, deg)
    from scipy.stats import chi2

    dof = y.size - deg - 1
    if dof >= 1 and float(np.sum(((y - smooth) * w) ** 2)) > float(chi2.ppf(0.95, dof)):
        smooth, deg = y, -1  # the points depart from a smooth curve beyond their u: take them as they are
    sample = np.random.default_rng(seed).normal(smooth, uu, size=(int(draws), y.size))
    mx = stat(sample)
    bias = float(mx.mean() - stat(smooth))
    return MaxSelection(printed, printed - bias, float(mx.std(ddof=1)), bias, deg)



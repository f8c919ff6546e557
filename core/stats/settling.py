"""Settling of a noisy record into a band: which excursion beyond the band is the last real one.

A start-up or set-up time is the instant the output enters a band about its target for good.  An
output that rings passes through the band several times before it stays, and near the band's edge
noise decides whether a swing left it.  This module cuts the deviation from the settled value into
lobes (its swings to either side), gives each lobe the probability that the noise-free output left
the band in it, and takes the expected instant of the last real exit with the spread of that
distribution (interpretations.md, "6.2.7.7 — the last real excursion" and "7.2.23 — a ringing output
decided by its samples").  Used by GB/T 45570 6.2.7.7 on the window means of the output and by JJF
2014 7.2.23 on the samples of an output ringing faster than its window.
"""

from __future__ import annotations

import math
from typing import Sequence

import attrs
import numpy as np

__all__ = ["SETTLE_CERTAIN", "Lobe", "quadratic_peak", "excursion_lobes", "last_exit"]

#: an excursion whose probability of being real is below this ends the search (the output has
#: come clearly inside the band), one above 1 − this is taken as certain
SETTLE_CERTAIN = 0.00135  # Φ(−3)


@attrs.frozen
class Lobe:
    """One swing of the deviation to one side of the settled value: indices ``start`` … ``end`` − 1,
    ``sign`` ±1, ``top`` its largest |deviation| (observed), ``p`` the probability that the
    noise-free output left the band on its side in it, ``p_near`` the same against the nearer of the
    two edges (= ``p`` for a band symmetric about the settled value), its ``exit`` (s) with the
    ``half_span`` of
    the noise re-crossings about it, and the exit as an index (``exit_index``)."""

    start: int
    end: int
    sign: int
    top: float
    p: float
    p_near: float
    exit: float
    half_span: float
    exit_index: int


def quadratic_peak(
    t: np.ndarray, z: np.ndarray, k: int, h: int, window: int, sigma_w: float
) -> tuple[float, float, float]:
    """The top of one lobe of the window mean, fitted by a parabola over z[k − h … k + h]: (the
    value at the vertex, its standard deviation, the vertex time).  The fitted value is a linear
    combination g·z of window means; a window mean averages ``window`` raw samples, which are taken
    as white with the variance window·σ_w² that makes one window mean's σ equal to ``sigma_w``, so
    σ² = window·σ_w²·Σ(g ∗ box_window/window)².  Falls back to the largest window mean (σ = σ_w)
    where the segment is too short or not concave."""
    a, b = max(k - h, 0), min(k + h + 1, z.size)
    if b - a < 5:
        return float(z[k]), sigma_w, float(t[k])
    tt = t[a:b] - t[k]
    X = np.column_stack([np.ones_like(tt), tt, tt * tt])
    beta, *_ = np.linalg.lstsq(X, z[a:b], rcond=None)
    if beta[2] >= 0:
        return float(z[k]), sigma_w, float(t[k])
    tv = float(np.clip(-beta[1] / (2.0 * beta[2]), tt[0], tt[-1]))
    x = np.array([1.0, tv, tv * tv])
    g = X @ np.linalg.solve(X.T @ X, x)
    spread = np.convolve(g, np.full(window, 1.0 / window))
    sd = sigma_w * math.sqrt(window * float(np.sum(spread * spread)))
    return float(x @ beta), sd, tv + float(t[k])


def _lobe_cuts(d: np.ndarray, hyst: float) -> list[int]:
    """Where a deviation's lobes part: at each sign change of ``d`` past the hysteresis ``hyst``
    on the other side, the index where ``d`` last left zero."""
    cuts, state, zero = [], 0, 0
    for i, v in enumerate(d):
        s_i = 1 if v >= 0 else -1
        if i and s_i != (1 if d[i - 1] >= 0 else -1):
            zero = i
        if state == 0 and abs(v) > hyst:
            state = s_i
        elif state and s_i != state and abs(v) > hyst:
            cuts.append(zero)
            state = s_i
    return cuts


def excursion_lobes(
    d: Sequence[float],
    t: Sequence[float],
    interval_s: float,
    window: int,
    upper: float,
    lower: float,
    sigma: float,
    sigma_common: float = 0.0,
    *,
    half_lobe_fit: bool = False,
) -> list[Lobe]:
    """The lobes of a deviation ``d`` from the settled value (window means or samples ending at the
    times ``t``, s, one ``interval_s`` apart), against a band from −``lower`` to +``upper`` about
    the settled value (both > 0; equal for a band centred on it).

    Lobes are cut at the sign changes of d with a hysteresis of 2σ (at most half the nearer edge),
    so that noise about zero does not cut one swing into slivers; a lobe starts where d last left
    zero before it passed the other side's threshold.  Each lobe's top is fitted by a parabola (σ of
    the fitted value from ``sigma``, the σ of one element of d, :func:`quadratic_peak`;
    ``sigma_common`` is added in quadrature: an uncertainty shared by every element, such as that of
    the band's centre) and p = Φ((top − edge)/σ_top) is the probability that the noise-free d left
    the band in that lobe; a lobe more than 6σ beyond or inside its edge is certain.  Its exit is
    the midpoint of the first element inside the band after the top and the one after the last
    element outside it in the lobe (noise re-crossings; half their span is the lobe's own spread),
    or the vertex where no element was outside. With ``half_lobe_fit`` the parabola is fitted only
    where it spans at most half the lobe, else the top is the largest element (a ringing sampled a
    few times per swing: a parabola over most of a cosine's lobe misses its top by a few per cent of
    the swing).
    """
    from scipy.special import ndtr

    d = np.asarray(d, dtype=float)
    t = np.asarray(t, dtype=float)
    sigma = max(sigma, 1e-12)
    s_tot = math.hypot(sigma, sigma_common)
    near = min(upper, lower)
    out = (d > upper) | (d < -lower)
    hyst = min(2.0 * sigma, 0.5 * near)
    bounds = np.concatenate(([0], _lobe_cuts(d, hyst), [d.size])).astype(int)
    lobes = []
    for a, b in zip(bounds[:-1], bounds[1:]):
        z = np.abs(d[a:b])
        k = int(np.argmax(z))
        sign = 1 if d[a + k] >= 0 else -1
        edge = upper if sign > 0 else lower
        fit = None

        def prob(e: float, z=z, k=k, a=a, b=b) -> float:
            nonlocal fit
            margin = float(z[k]) - e
            if margin > 6.0 * s_tot:
                return 1.0
            if margin < -6.0 * s_tot:
                return 0.0
            if fit is None:
                h = max(window // 2, (b - a) // 4, 2)
                fit = (
                    (float(z[k]), sigma, float(t[a + k]))
                    if half_lobe_fit and 4 * h + 1 > b - a
                    else quadratic_peak(t[a:b], z, k, h, window, sigma)
                )
            return float(ndtr((fit[0] - e) / max(math.hypot(fit[1], sigma_common), 1e-12)))

        p = prob(edge)
        p_near = p if edge == near else prob(near)
        outs = np.flatnonzero(out[a:b])
        if outs.size and outs[-1] >= k:
            last_out = a + int(outs[-1])
            after = np.flatnonzero(~out[a + k : b])
            first_in = a + k + int(after[0]) if after.size else b
            e_out = t[last_out + 1] if last_out + 1 < d.size else t[last_out] + interval_s
            e_in = t[first_in] if first_in < d.size else t[-1] + interval_s
            lo, hi = min(e_in, e_out), max(e_in, e_out)
            lobes.append(Lobe(int(a), int(b), sign, float(z[k]), p, p_near, 0.5 * (lo + hi),
                              0.5 * (hi - lo), int(min(last_out + 1, d.size - 1))))
        else:
            lobes.append(
                Lobe(int(a), int(b), sign, float(z[k]), p, p_near, float(t[a + k]), 0.0, int(a + k))
            )
    return lobes


def last_exit(lobes: Sequence[Lobe], t_first: float) -> dict:
    """The expected instant of the last real exit from the band over ``lobes``
    (:func:`excursion_lobes`).

    The last certain lobe (p ≥ 1 − SETTLE_CERTAIN) and the lobes after it up to the first that is
    clearly inside the nearer edge (p_near < SETTLE_CERTAIN: the output has then come clearly
    inside; a later lobe is noise) are the candidates; the last real one is lobe i with probability
    P_i = p_i·Π_{j>i}(1 − p_j), and

        t_s = Σ_i P_i·e_i,   u_sel² = Σ_i P_i·(e_i − t_s)²,   u_span² = Σ_i P_i·(half span_i)²/3.

    Where no lobe is certain the output may have been inside from the first element, whose time
    ``t_first`` then takes the remaining probability.

    :return: a dict with ``t_s``, ``u_selection``, ``u_span`` (s), ``exits`` (the candidates' e_i,
    s),
        ``probabilities`` (P_i), ``p_real`` (p_i), ``exit_index`` and ``lobes`` (the candidates'
        indices into ``lobes``).
    """
    certain = [i for i, lb in enumerate(lobes) if lb.p >= 1.0 - SETTLE_CERTAIN]
    first = certain[-1] if certain else 0
    cand = []
    for i in range(first, len(lobes)):
        if i > first and lobes[i].p_near < SETTLE_CERTAIN:
            break
        cand.append(i)
    p_real = [1.0 if certain and i == first else lobes[i].p for i in cand]
    probs, rest = [], 1.0
    for p in reversed(p_real):
        probs.append(p * rest)
        rest *= 1.0 - p
    probs.reverse()
    exits = [lobes[i].exit for i in cand]
    spans = [lobes[i].half_span for i in cand]
    index = [lobes[i].exit_index for i in cand]
    if rest > 0.0:  # no lobe certain: inside from the first element with the probability left
        probs.append(rest)
        exits.append(float(t_first))
        spans.append(0.0)
        index.append(0)
    P = np.asarray(probs) / float(np.sum(probs))
    e = np.asarray(exits)
    ts = float(P @ e)
    return {
        "t_s": ts,
        "u_selection": float(math.sqrt(max(P @ (e - ts) ** 2, 0.0))),
        "u_span": float(math.sqrt(P @ (np.asarray(spans) ** 2) / 3.0)),
        "exits": e.tolist(),
        "probabilities": P.tolist(),
        "p_real": p_real,
        "exit_index": index,
        "lobes": cand,
    }

"""Compiled (numba) kernels for :mod:`metro.core.stats.allan`.

Imported lazily by ``metro.core.stats.allan`` on first use (never at package import time), so
``import metro.core.stats.allan`` does not pay numba's import or compile cost.  Every kernel is
compiled with ``cache=True`` (the machine code is kept next to this file in
``__pycache__``, or in numba's user cache when that folder is read-only).

The kernels take only C-contiguous float64 / int64 arrays and Python scalars, so each is
compiled for a single signature.  The pure-numpy fallback in ``allan.py`` implements the
same algorithms; the tests check that both agree to ~1e-12 relative.

Summation accuracy: inner sums run over short blocks (vectorised, reassociated by the
compiler) and the block partial sums are combined with Neumaier's compensated summation,
so the rounding error of a sum of N terms does not grow like N.
"""

from __future__ import annotations

import numba as nb
import numpy as np

# Reassociation lets LLVM vectorise the block reductions; NaN/Inf handling is left intact
# (inputs are validated before the kernels run).
_FM = {"reassoc", "contract"}

BLOCK = 2048


@nb.njit(cache=True, fastmath=_FM)
def _ssq2(a, b, c):  # pragma: no cover - compiled
    """sum_j (c[j] - 2 b[j] + a[j])^2 over equal-length slices."""
    s = 0.0
    for j in range(a.size):
        d = c[j] - 2.0 * b[j] + a[j]
        s += d * d
    return s


@nb.njit(cache=True, fastmath=_FM)
def _sum_shifted(v, shift):  # pragma: no cover - compiled
    s1 = 0.0
    s2 = 0.0
    for i in range(v.size):
        d = v[i] - shift
        s1 += d
        s2 += d * d
    return s1, s2


@nb.njit(cache=True)
def phase(y, mu, x):  # pragma: no cover - compiled
    """x[0] = 0, x[i+1] = x[i] + (y[i] - mu): phase (in sample units) of mean-removed y."""
    acc = 0.0
    x[0] = 0.0
    for i in range(y.size):
        acc += y[i] - mu
        x[i + 1] = acc


@nb.njit(cache=True, fastmath=_FM)
def _ssq2x4(a0, a1, a2, a4, a8, a16):  # pragma: no cover - compiled
    """Squared second differences of four octave lags sharing the loads:
    lags m, 2m, 4m, 8m from the slices x[j], x[j+m], x[j+2m], x[j+4m], x[j+8m], x[j+16m]."""
    s1 = 0.0
    s2 = 0.0
    s4 = 0.0
    s8 = 0.0
    for j in range(a0.size):
        x0 = a0[j]
        x2 = a2[j]
        x4 = a4[j]
        x8 = a8[j]
        d = x2 - 2.0 * a1[j] + x0
        s1 += d * d
        d = x4 - 2.0 * x2 + x0
        s2 += d * d
        d = x8 - 2.0 * x4 + x0
        s4 += d * d
        d = a16[j] - 2.0 * x8 + x0
        s8 += d * d
    return s1, s2, s4, s8


@nb.njit(cache=True)
def _add(out, comp, i, v):  # pragma: no cover - compiled
    """Neumaier-compensated out[i] += v."""
    t = out[i] + v
    if abs(out[i]) >= abs(v):
        comp[i] += (out[i] - t) + v
    else:
        comp[i] += (v - t) + out[i]
    out[i] = t


@nb.njit(cache=True)
def oadev_ssq(x, groups, singles, block):  # pragma: no cover - compiled
    """Sums of squared overlapping second differences of the phase x.

    For an averaging factor m the sum is S(m) = sum_{j=0}^{nx-1-2m} (x[j+2m] - 2x[j+m] + x[j])^2.
    ``groups`` holds base factors g of octave quadruples (g, 2g, 4g, 8g), whose four
    second differences share six loads per j; ``singles`` holds the other factors.
    Returns (S for the groups, 4 per group in order g, 2g, 4g, 8g; S for the singles).

    x is swept once in blocks of ``block`` points; every factor is processed inside the
    block, so the block and its nearby shifted copies are reused from cache.
    """
    nx = x.size
    ng = groups.size
    ns = singles.size
    og = np.zeros(4 * ng)
    cg = np.zeros(4 * ng)
    os_ = np.zeros(ns)
    cs = np.zeros(ns)
    for j0 in range(0, nx, block):
        j1 = min(j0 + block, nx)
        for g in range(ng):
            m = groups[g]
            jm = min(j1, nx - 16 * m)
            if jm > j0:
                s1, s2, s4, s8 = _ssq2x4(
                    x[j0:jm],
                    x[j0 + m : jm + m],
                    x[j0 + 2 * m : jm + 2 * m],
                    x[j0 + 4 * m : jm + 4 * m],
                    x[j0 + 8 * m : jm + 8 * m],
                    x[j0 + 16 * m : jm + 16 * m],
                )
                _add(og, cg, 4 * g, s1)
                _add(og, cg, 4 * g + 1, s2)
                _add(og, cg, 4 * g + 2, s4)
                _add(og, cg, 4 * g + 3, s8)
            a = max(j0, jm)
            for i in range(4):
                mi = m << i
                b = min(j1, nx - 2 * mi)
                if b > a:
                    v = _ssq2(x[a:b], x[a + mi : b + mi], x[a + 2 * mi : b + 2 * mi])
                    _add(og, cg, 4 * g + i, v)
        for k in range(ns):
            m = singles[k]
            b = min(j1, nx - 2 * m)
            if b > j0:
                v = _ssq2(x[j0:b], x[j0 + m : b + m], x[j0 + 2 * m : b + 2 * m])
                _add(os_, cs, k, v)
    return og + cg, os_ + cs


@nb.njit(cache=True)
def adev_ssq(x, ms):  # pragma: no cover - compiled
    """For each m: sum_{k=0}^{M-2} (x[(k+2)m] - 2 x[(k+1)m] + x[km])^2, M = N // m."""
    n = x.size - 1
    nm = ms.size
    out = np.zeros(nm)
    for k in range(nm):
        m = ms[k]
        nterm = n // m - 1
        tot = 0.0
        comp = 0.0
        for i0 in range(0, nterm, BLOCK):
            i1 = min(i0 + BLOCK, nterm)
            s = 0.0
            for i in range(i0, i1):
                d = x[(i + 2) * m] - 2.0 * x[(i + 1) * m] + x[i * m]
                s += d * d
            t = tot + s
            if abs(tot) >= abs(s):
                comp += (tot - t) + s
            else:
                comp += (s - t) + tot
            tot = t
        out[k] = tot + comp
    return out


@nb.njit(cache=True)
def mdev_ssq(x, ms):  # pragma: no cover - compiled
    """For each m: sum_{j=0}^{T-1} w_j^2 with w_j = sum_{i=j}^{j+m-1} d_i,
    d_i = x[i+2m] - 2 x[i+m] + x[i], T = N - 3m + 2.

    w is carried as a running window sum, w_{j+1} = w_j + d_{j+m} - d_j; the squares are
    summed per block of BLOCK terms and the block sums combined with Neumaier's method."""
    n = x.size - 1
    nm = ms.size
    out = np.zeros(nm)
    for k in range(nm):
        m = ms[k]
        T = n - 3 * m + 2
        w = 0.0
        for i in range(m):
            w += x[i + 2 * m] - 2.0 * x[i + m] + x[i]
        tot = 0.0
        comp = 0.0
        for j0 in range(0, T, BLOCK):
            j1 = min(j0 + BLOCK, T)
            s = 0.0
            # terms j0 .. j1-1; w advances after each term except the very last (j = T-1)
            ju = min(j1, T - 1)
            for j in range(j0, ju):
                s += w * w
                i = j + m
                w += (x[i + 2 * m] - 2.0 * x[i + m] + x[i]) - (x[j + 2 * m] - 2.0 * x[j + m] + x[j])
            if ju < j1:
                s += w * w
            tot, comp = _acc(tot, comp, s)
        out[k] = tot + comp
    return out


@nb.njit(cache=True)
def _acc(tot, comp, v):  # pragma: no cover - compiled
    t = tot + v
    if abs(tot) >= abs(v):
        comp += (tot - t) + v
    else:
        comp += (v - t) + tot
    return t, comp


@nb.njit(cache=True)
def _halve_stats(src, dst, h, shift):  # pragma: no cover - compiled
    """dst[i] = (src[2i] + src[2i+1]) / 2 for i < h, returning the shifted sums of dst[:h].

    Block i0..i1 reads src[2 i0 : 2 i1], which later blocks never write, so src may be
    dst itself (in-place halving)."""
    a1 = c1 = a2 = c2 = 0.0  # Kahan-compensated sums of (v - shift) and (v - shift)^2
    for i0 in range(0, h, BLOCK):
        i1 = min(i0 + BLOCK, h)
        for i in range(i0, i1):
            dst[i] = 0.5 * (src[2 * i] + src[2 * i + 1])
        p, q = _sum_shifted(dst[i0:i1], shift)
        a1, c1 = _acc(a1, c1, p)
        a2, c2 = _acc(a2, c2, q)
    return a1 + c1, a2 + c2


@nb.njit(cache=True)
def pyramid_stats(y, shift, buf, nlev):  # pragma: no cover - compiled
    """Block means of doubling size and their shifted sums, levels 1..nlev.

    Level 1 is y itself; level 2 (written to ``buf``, size >= N // 2) holds the means of
    adjacent pairs of y; every later level overwrites ``buf`` in place with the means of
    adjacent pairs of the previous level (an odd last element is dropped).  Returns
    (count, s1, s2) per level with s1 = sum(v - shift), s2 = sum((v - shift)^2).
    """
    cnt = np.zeros(nlev, dtype=np.int64)
    s1 = np.zeros(nlev)
    s2 = np.zeros(nlev)
    n = y.size
    a1 = c1 = a2 = c2 = 0.0  # Kahan-compensated sums of (v - shift) and (v - shift)^2
    for i0 in range(0, n, BLOCK):
        i1 = min(i0 + BLOCK, n)
        p, q = _sum_shifted(y[i0:i1], shift)
        a1, c1 = _acc(a1, c1, p)
        a2, c2 = _acc(a2, c2, q)
    cnt[0] = n
    s1[0] = a1 + c1
    s2[0] = a2 + c2
    h = n
    for lev in range(1, nlev):
        h = h // 2
        if lev == 1:
            p, q = _halve_stats(y, buf, h, shift)
        else:
            p, q = _halve_stats(buf, buf, h, shift)
        cnt[lev] = h
        s1[lev] = p
        s2[lev] = q
    return cnt, s1, s2

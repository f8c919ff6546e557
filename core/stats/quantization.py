"""Quantization: what rounding samples to a step q does to their mean.

A digital output (LSB counts, a pulse count over a gate, a reading to a displayed digit) rounds
each sample to a step q.  GB/T 45570 (D.40's static bias from rounded rate samples) and JJF 2014
(the bias and scale-factor items of a quantized output) both need the bound on the offset this
leaves in a mean; it lives here, once.
"""

from __future__ import annotations

import math

__all__ = ["rounding_mean_bound"]


def rounding_mean_bound(q: float, sigma: float) -> float:
    """Largest offset of the mean of round(x + n) from x, n ~ N(0, σ²), rounding step q.

    The mean rounding error is periodic in x; its Fourier series for a Gaussian input (Widrow's
    quantization theorem) is Σ_k (−1)^k (q/(πk))·e^(−2π²k²σ²/q²)·sin(2πkx/q), so
    |offset| ≤ Σ_k (q/(πk))·e^(−2π²k²σ²/q²), and never more than q/2 (plain rounding). With
    σ ≥ q the bound is below 10⁻⁸·q: noise that large dithers the rounding.

    >>> rounding_mean_bound(1.0, 0.0)
    0.5
    >>> rounding_mean_bound(1.0, 1.0) < 1e-8
    True
    >>> round(rounding_mean_bound(1.0, 0.25), 6)
    0.093842
    """
    if q <= 0:
        return 0.0
    if sigma <= 0:
        return q / 2.0
    r = 2.0 * math.pi**2 * (sigma / q) ** 2
    return min(q / 2.0, sum(q / (math.pi * k) * math.exp(-r * k * k) for k in range(1, 50)))

"""GB/T 45570—2025 formulas of D.4 (threshold), D.6.3/D.6.4 (bias change under vibration and
shock), 6.2.7.7 (set-up time) and 6.2.7.8 (power consumption), as pure functions on plain numbers.

Units are those stated in each docstring; the procedures in :mod:`.threshold` and
:mod:`.environmental` convert at the boundary.
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from metro.api import excursion_lobes, last_exit

from .formulas import EARTH_RATE_DEG_PER_H

#: D.39: the response must reach at least this fraction of the expected output
THRESHOLD_FRACTION = 0.5


# --------------------------------------------------------------------------------------------
# D.4 threshold
# --------------------------------------------------------------------------------------------


def tilt_input_d37(psi_deg: float, omega_e_deg_h: float = EARTH_RATE_DEG_PER_H) -> float:
    """The input along the IRA when it makes the angle Ψ_i with the earth's axis, Ω_e·cos Ψ_i
    (the rate factor of D.37 and the quantity D.39 minimises), °/h."""
    return omega_e_deg_h * math.cos(math.radians(psi_deg))


def expected_counts_d37(K_P_per_arcsec: float, psi_deg: float, tau_s: float,
                        omega_e_deg_h: float = EARTH_RATE_DEG_PER_H) -> float:
    """Expected pulses per sampling interval at Ψ_i, D.4.3 eq. (D.37)::

        N_i = K · Ω_e cos Ψ_i · τ

    :param K_P_per_arcsec: scale factor K, P/″.
    :param psi_deg: Ψ_i, angle between the IRA and the earth's axis, °.
    :param tau_s: sampling interval τ, s (1 °/h = 1 ″/s, so K·Ω·τ is in P).
    :return: N_i in P.
    """
    return K_P_per_arcsec * tilt_input_d37(psi_deg, omega_e_deg_h) * tau_s


def mean_counts_d38(counts: Sequence[float]) -> float:
    """N̄*_i = (1/n) Σ_j N_ij, D.4.3 eq. (D.38): the mean measured pulses per interval at Ψ_i."""
    c = np.asarray(counts, dtype=float)
    if c.size < 1:
        raise ValueError("D.38 needs at least one sample")
    return float(c.mean())


def response_ratio_d39(n_star: float, n0: float, n_expected: float) -> float:
    """The signed ratio (N̄*_i − N̄_0) / N_i of D.4.3 eq. (D.39); D.39 compares its absolute value
    with 50 %.  Works in any consistent unit (P per interval, or °/h for every term)."""
    if n_expected == 0:
        raise ValueError("the expected output N_i is zero (Ψ_i = 90°): D.39 divides by it")
    return (n_star - n0) / n_expected


def threshold_d39(inputs_deg_h: Sequence[float], ratios: Sequence[float],
                  fraction: float = THRESHOLD_FRACTION) -> tuple[float | None, int | None]:
    """The threshold by D.4.3 c): the smallest |Ω_e cos Ψ_i| whose |(N̄*_i − N̄_0)/N_i| ≥ 50 %
    (D.39).

    :param inputs_deg_h: Ω_e cos Ψ_i of each tilt position, °/h.
    :param ratios: the D.39 ratios of the same positions.
    :return: (threshold in °/h, index of that position), or (None, None) if no position meets D.39.
    """
    x = np.abs(np.asarray(inputs_deg_h, dtype=float))
    r = np.abs(np.asarray(ratios, dtype=float))
    if x.size != r.size:
        raise ValueError("one ratio per tilt position is needed")
    ok = np.flatnonzero(r >= fraction)
    if ok.size == 0:
        return None, None
    i = int(ok[np.argmin(x[ok])])
    return float(x[i]), i


# --------------------------------------------------------------------------------------------
# D.6.3 / D.6.4 bias change under vibration and shock
# --------------------------------------------------------------------------------------------


def bias_change_d47(b02: float, b01: float) -> float:
    """ΔB_V12 = |B_02 − B_01|, D.6.3.3 eq. (D.47): bias during against before vibration, °/h."""
    return abs(b02 - b01)


def bias_change_d48(b03: float, b01: float) -> float:
    """ΔB_V13 = |B_03 − B_01|, D.6.3.3 eq. (D.48): bias after against before vibration (also the
    endurance vibration and the mechanical shock of D.6.4.3), °/h."""
    return abs(b03 - b01)


# --------------------------------------------------------------------------------------------
# 6.2.7.7 set-up time, 6.2.7.8 power consumption
# --------------------------------------------------------------------------------------------


def moving_mean(y: Sequence[float], window: int) -> np.ndarray:
    """Means of ``window`` consecutive samples ending at each sample (valid part only:
    element j is the mean of y[j … j + window − 1])."""
    a = np.asarray(y, dtype=float)
    if window < 1 or a.size < window:
        raise ValueError(f"{a.size} samples are too few for a window of {window}")
    c = np.concatenate(([0.0], np.cumsum(a - a[0])))
    return (c[window:] - c[:-window]) / window + a[0]


def settled_and_window_means(rate_deg_h: Sequence[float], window: int,
                              settled_from: int) -> tuple[float, np.ndarray]:
    """6.2.7.7 on a record from switch-on: the settled bias (the mean from sample ``settled_from``
    to the end, °/h) and the means of ``window`` samples before it (:func:`moving_mean`)."""
    y = np.asarray(rate_deg_h, dtype=float)
    if not 0 < settled_from < y.size - 1:
        raise ValueError(f"the settled part must start inside the record (sample {settled_from} of "
                         f"{y.size})")
    return float(np.mean(y[settled_from:])), moving_mean(y[:settled_from], window)


def setup_time_6277(rate_deg_h: Sequence[float], interval_s: float, window: int, settled_from: int,
                    tolerance_deg_h: float) -> tuple[float, float, float, float]:
    """Set-up time by 6.2.7.7: the interval from switch-on (the first sample starts at t = 0)
    until the gyro reaches the required performance, read here as the instant the mean output
    over a window of ``window`` samples comes within ±``tolerance_deg_h`` of the settled bias
    (the mean from sample ``settled_from`` to the end) (docs/interpretations.md).

    Noise may take the window mean in and out of the band for a while: t_in is the end of the
    first window inside it, t_out the end of the first window from which every window stays
    inside, and t_s = (t_in + t_out)/2 (the first is early, the last late by about as much).

    :return: (t_s, the settled bias in °/h, t_in, t_out), times in s.
    """
    settled, mm = settled_and_window_means(rate_deg_h, window, settled_from)
    out = np.abs(mm - settled) > tolerance_deg_h
    if out.size and out[-1]:
        raise ValueError(f"the output is still outside ±{tolerance_deg_h:g} °/h of the settled "
                         f"bias when the "
                         "settled part begins: the gyro has not reached the required performance "
                         "in the record")
    bad = np.flatnonzero(out)
    j_out = int(bad[-1]) + 1 if bad.size else 0  # first window of the final in-band run
    j_in = int(np.argmin(out))  # first window inside the band
    t_in, t_out = (j_in + window) * interval_s, (j_out + window) * interval_s
    return 0.5 * (t_in + t_out), settled, t_in, t_out


def power_6278(voltages_V: Sequence[Sequence[float]],
               currents_A: Sequence[Sequence[float]]) -> tuple[float, list[float]]:
    """Power consumption by 6.2.7.8: the sum over the supplies of the input voltage times current,
    each supply's U·I averaged over its record::

        P = Σ_j (1/n_j) Σ_i U_ji · I_ji

    :param voltages_V: per supply, the voltage samples, V.
    :param currents_A: per supply, the current samples (same length), A.
    :return: (P in W, each supply's mean power in W).
    """
    if len(voltages_V) != len(currents_A) or not voltages_V:
        raise ValueError("one current record per voltage record, and at least one supply")
    parts = []
    for j, (u, i) in enumerate(zip(voltages_V, currents_A)):
        u, i = np.asarray(u, dtype=float), np.asarray(i, dtype=float)
        if u.size != i.size or u.size < 1:
            raise ValueError(f"supply {j + 1}: {u.size} voltage and {i.size} current samples")
        parts.append(abs(float(np.mean(u * i))))  # a negative rail: U < 0 and I < 0
    return float(sum(parts)), parts


# --------------------------------------------------------------------------------------------
# 6.2.7.7 set-up time on a noisy record: which excursion beyond the band is the last real one
# --------------------------------------------------------------------------------------------

def setup_time_excursions_6277(rate_deg_h: Sequence[float], interval_s: float, window: int,
                               settled_from: int,
                               tolerance_deg_h: float, sigma_w: float) -> dict:
    """Set-up time by 6.2.7.7 on a noisy record: the expected instant the window mean of the output
    leaves ±``tolerance_deg_h`` of the settled bias for the last time (docs/interpretations.md
    "6.2.7.7 — the last real excursion").

    The window mean's deviation from the settled bias (the mean from sample ``settled_from`` on) is
    cut into lobes at its sign changes.  Each lobe's top is fitted by a parabola (σ of the fitted
    value
    from ``sigma_w``, the σ of one window mean) and p_i = Φ((top_i − tolerance)/σ_top,i) is the
    probability that the noise-free window mean left the band in that lobe.  Its exit e_i is the
    midpoint of the first window inside the band after the top and the end of the last window
    outside it in the lobe (noise re-crossings; half their span is the lobe's own spread), or the
    vertex where no window mean was outside.  The last certain lobe (p ≥ 1 − SETTLE_CERTAIN) and the
    lobes after it up to the first with p < SETTLE_CERTAIN (the output is then clearly inside: a
    later lobe is noise) are the candidates; the last real one is lobe i with probability
    P_i = p_i·Π_{j>i}(1 − p_j), and

        t_s = Σ_i P_i·e_i,   u_sel² = Σ_i P_i·(e_i − t_s)²,   u_span² = Σ_i P_i·(half span_i)²/3.

    Where no lobe is certain the output may have been inside from the first window, whose end then
    takes the remaining probability.  Times are window ends from the switch-on (the first sample
    starts at t = 0).  The lobes and their candidates: :mod:`metro.api.settling` (shared with
    JJF 2014
    7.2.23).

    :return: a dict with ``t_s``, ``settled`` (°/h), ``u_selection``, ``u_span`` (s), ``exits`` (the
        candidates' e_i, s), ``probabilities`` (P_i), ``p_real`` (p_i) and ``exit_index`` (each
        candidate's exit as an index into the window means).
    """
    settled, mm = settled_and_window_means(rate_deg_h, window, settled_from)
    d = mm - settled
    if d.size and abs(d[-1]) > tolerance_deg_h:
        raise ValueError(f"the output is still outside ±{tolerance_deg_h:g} °/h of the settled "
                         f"bias when the "
                         "settled part begins: the gyro has not reached the required performance "
                         "in the record")
    t = (np.arange(mm.size) + window) * interval_s
    st = last_exit(excursion_lobes(d, t, interval_s, window, tolerance_deg_h, tolerance_deg_h,
                                   sigma_w), float(t[0]))
    return {"settled": settled, **{k: st[k] for k in ("t_s", "u_selection", "u_span", "exits",
                                                      "probabilities",
                                                      "p_real", "exit_index")}}

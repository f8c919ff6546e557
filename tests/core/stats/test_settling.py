"""metro.core.stats.settling: the lobes of a settling record and the expected last real exit from a
band (shared by GB/T 45570 6.2.7.7 and JJF 2014 7.2.23; the symmetric case is also tested through
tests/plugins/gbt45570/test_env.py::test_setup_time_last_real_excursion_hand_worked)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from metro.core.stats import settling as S


def test_an_off_centre_band_is_searched_past_a_lobe_inside_its_far_edge():
    """Band from −1.4 to +0.6 about the settled value (a rate trial settling 0.4 above the centre of
    ±1), σ = 0.05, one element a second: 5, 0, −3, 0, 2, 0, −1.0, 0, 0.62, 0 … The −1.0 lobe is
    clearly inside its own edge (1.4) but not inside the nearer one (0.6), so the search goes on to
    the 0.62 lobe, p = Φ(0.02/0.05) = 0.655 (its largest element: a parabola would span more than
    half the lobe). Candidates: the certain 2 lobe (exit 6 s), the −1.0 lobe (p 0) and the 0.62 lobe
    (exit 10 s): P = 0.345, 0, 0.655, t = 8.62 s. Stopping at the first lobe inside its own edge
    (the symmetric rule) would give 6 s."""
    d = np.array([5, 0, -3, 0, 2, 0, -1.0, 0, 0.62, 0, 0, 0, 0, 0])
    t = np.arange(1, d.size + 1) * 1.0
    lobes = S.excursion_lobes(d, t, 1.0, 1, 0.6, 1.4, 0.05, half_lobe_fit=True)
    assert [lb.sign for lb in lobes] == [1, -1, 1, -1, 1]
    assert lobes[3].p == 0.0 and lobes[3].p_near == 1.0
    p = 0.5 * (1 + math.erf(0.4 / math.sqrt(2)))
    st = S.last_exit(lobes, 1.0)
    assert st["exits"] == pytest.approx([6.0, 7.0, 10.0])
    assert st["probabilities"] == pytest.approx([1 - p, 0.0, p])
    assert st["t_s"] == pytest.approx(6.0 * (1 - p) + 10.0 * p)


def test_a_common_uncertainty_widens_every_lobe_probability():
    """A lobe topping 0.1 beyond its edge with σ = 0.05 per element: p = Φ(2) alone, Φ(0.1/√(0.05² +
    0.05²)) = Φ(1.41) with a common σ of 0.05 (the band's centre uncertain by that much)."""
    d = np.array([5, 0, -1.1, 0, 0, 0])
    t = np.arange(1, d.size + 1) * 1.0
    alone = S.excursion_lobes(d, t, 1.0, 1, 1.0, 1.0, 0.05, half_lobe_fit=True)[1].p
    common = S.excursion_lobes(d, t, 1.0, 1, 1.0, 1.0, 0.05, 0.05, half_lobe_fit=True)[1].p
    assert alone == pytest.approx(0.5 * (1 + math.erf(2 / math.sqrt(2))))
    assert common == pytest.approx(
        0.5 * (1 + math.erf(0.1 / math.hypot(0.05, 0.05) / math.sqrt(2)))
    )

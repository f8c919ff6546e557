"""What an ideal evaluation of a simulated JJF 2003 campaign gives, by this standard's formulas
(the ``metro_expected_values`` hook).

A simulated MIMU station declares its device's truth and the exact means of what its table did
(each mounting's tilt, each rate point's mean rate) without noise.  It gives them in ``ideal``
under the key ``"jjf2003:segment_means"``: a function ``means(segment)`` returning the noise-free
means of a segment's columns, in the form the items' fits read (:data:`.data.Means`).  This
module applies the default evaluation of every item to them (:func:`.data.ideal_evaluation`):
the K_g sweeps, the six-position g and K_a matrices with their biases, and the cross-coupling
matrix p.
"""

from __future__ import annotations

from typing import Any, Mapping

__all__ = ["expected_values"]


def expected_values(campaign: Any, ideal: Mapping[str, Any]) -> dict[str, Any]:
    """Every metric's expected value from the station's noise-free segment means (nothing when
    ``ideal`` has no ``"jjf2003:segment_means"``)."""
    means = ideal.get("jjf2003:segment_means")
    if means is None:
        return {}
    from .data import ideal_evaluation

    return ideal_evaluation(campaign, means)

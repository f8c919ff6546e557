"""What an ideal evaluation of a simulated GB/T 45570 campaign gives, by this standard's formulas
(the ``metro_expected_values`` hook).

A simulated station declares its gyro's truth and, where an item's expected value follows from
that truth only through the standard's own formulas, the noise-free quantities those formulas
take.  It puts them in ``ideal`` under these keys; this module applies the formulas:

* ``"gbt45570:tilt_response"`` — ``[(Ψ in °, response in °/h), …]``: each D.4 tilt position's
  angle to the earth's axis and the rate the gyro indicates beyond its bias there → the
  threshold (D.37, D.39), metric ``threshold``;
* ``"gbt45570:power_on_rate"`` — ``(rates in °/h, interval in s)``: the noise-free indicated rate
  of the power-on record → the set-up time of 6.2.7.7 with the item's default options, metric
  ``setup_time`` (none when the record is too short for them);
* ``"gbt45570:nonlinearity"`` — ``[(Ω in °/s, K_n), …]``: the scale-factor nonlinearity of the
  rate points up to each candidate Ω → the maximum input rate of D.3 against the default K_n
  limit for the campaign's device, metric ``Omega_max``;
* ``"gbt45570:reliability"`` — ``{"operating_hours", "failures", "confidence", "plan"}``: the
  declared reliability evidence → the MTBF lower bound of 5.5, metric ``mtbf_lower``.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from metro.api import Q_

__all__ = ["expected_values", "threshold", "setup_time", "omega_max", "mtbf_lower"]


def threshold(pairs: Sequence[tuple[float, float]]) -> dict[str, Any]:
    """D.4: the threshold (D.39) of noise-free tilt positions, each input taken as D.37 prints it
    (Ω_e·cos Ψ with Ω_e = 15.041 °/h); the position at Ψ = 90° (no input) is left out."""
    from .env_formulas import threshold_d39, tilt_input_d37

    inputs, ratios = [], []
    for psi, response in pairs:
        if abs(psi - 90.0) < 1e-9:
            continue
        x_std = tilt_input_d37(psi)
        inputs.append(x_std)
        ratios.append(response / x_std)
    th, _ = threshold_d39(inputs, ratios)
    return {} if th is None else {"threshold": Q_(th, "deg/h")}


def setup_time(rates_deg_h: Sequence[float], interval_s: float) -> dict[str, Any]:
    """6.2.7.7 with the item's default options (window, settled part, tolerance) on the
    noise-free power-on record; nothing when the record is too short for them."""
    from .env_formulas import setup_time_6277
    from .environmental import SetupTime6277

    opts = SetupTime6277.option_values({})
    n = len(rates_deg_h)
    w = max(1, int(round(float(opts["window"].to("s").magnitude) / interval_s)))
    n_set = int(round(float(opts["settled"].to("s").magnitude) / interval_s))
    tol = float(opts["tolerance"].to("deg/h").magnitude)
    try:
        return {
            "setup_time": Q_(setup_time_6277(rates_deg_h, interval_s, w, n - n_set, tol)[0], "s")
        }
    except ValueError:
        return {}


def omega_max(device: Any, curve: Sequence[tuple[float, float]]) -> dict[str, Any]:
    """D.3: the largest candidate Ω whose noise-free K_n stays within the default limit for
    ``device`` (the device specification's, else table A.1/B.1's typical value)."""
    from .rate_method import default_nonlinearity_limit

    limit = float(default_nonlinearity_limit(device)[0].to("").magnitude)
    ok = [om for om, kn in curve if kn <= limit]
    return {"Omega_max": Q_(max(ok), "deg/s")} if ok else {}


def mtbf_lower(evidence: Mapping[str, Any]) -> dict[str, Any]:
    """5.5: the one-sided MTBF lower bound of the declared reliability evidence."""
    from .reliability import mtbf_lower_bound

    bound = mtbf_lower_bound(
        evidence["operating_hours"], evidence["failures"], evidence["confidence"], evidence["plan"]
    )
    return {"mtbf_lower": Q_(bound, "h")}


def expected_values(campaign: Any, ideal: Mapping[str, Any]) -> dict[str, Any]:
    """Every expected value the keys of ``ideal`` this module knows give (see the module)."""
    out: dict[str, Any] = {}
    if "gbt45570:tilt_response" in ideal:
        out |= threshold(ideal["gbt45570:tilt_response"])
    if "gbt45570:power_on_rate" in ideal:
        out |= setup_time(*ideal["gbt45570:power_on_rate"])
    if "gbt45570:nonlinearity" in ideal:
        out |= omega_max(campaign.device, ideal["gbt45570:nonlinearity"])
    if "gbt45570:reliability" in ideal:
        out |= mtbf_lower(ideal["gbt45570:reliability"])
    return out

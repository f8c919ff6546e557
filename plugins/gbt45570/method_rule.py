"""GB/T 45570—2025 clause 6.2.7.1 (and 6.2.7.2): angle method D.1 or rate method D.2.

6.2.7.1.1–6.2.7.1.5: laser gyros are tested by the angle method (D.1.1–D.1.5); fibre gyros
whose scale-factor nonlinearity is not greater than 5×10⁻⁶ by the angle method too, those
above 5×10⁻⁶ by the rate method (D.2.1–D.2.5).  6.2.7.2: the input-axis misalignment of a
laser gyro by D.1.6, of a fibre gyro by D.2.6.

The 5×10⁻⁶ is compared with the nonlinearity the device is *specified* for — a method has
to be chosen before anything is measured: the device's declared ``nonlinearity`` (manifest
``[device] nonlinearity = "3 ppm"``), else the typical table-B.1 limit of its application
(10×10⁻⁶ … 50×10⁻⁶, so the rate method).  With neither, the rate method, which does not
presume a small nonlinearity.  Other technologies (the standard covers laser and fibre gyros)
follow the nonlinearity criterion as fibre gyros do.  docs/interpretations.md records why.
"""

from __future__ import annotations

from typing import Any

from metro.api import Q_, Applicability, DeviceUnderTest, check_dimension, msg

from .conformity import TABLE_B1, application_of

#: 6.2.7.1: the threshold on the scale-factor nonlinearity
THRESHOLD = Q_(5e-6, "")
ANGLE_ITEMS = ("D.1.1", "D.1.2", "D.1.3", "D.1.4", "D.1.5")
RATE_ITEMS = ("D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.5")
MISALIGNMENT = {"angle": "D.1.6", "rate": "D.2.6"}

#: series aliases: name -> (member items, description)
SERIES = {
    "scale-factor": (ANGLE_ITEMS + RATE_ITEMS,
                     "6.2.7.1 标度因数系列: D.1.1–D.1.5 or D.2.1–D.2.5 by the 6.2.7.1 method rule"),
    "misalignment": (("D.1.6", "D.2.6"),
                     "6.2.7.2 input-axis misalignment: D.1.6 (laser) or D.2.6 (fibre)"),
    "bias": (("D.5.1", "D.5.2", "D.5.3", "D.5.4", "D.5.5"), "6.2.7.5 零偏系列: D.5.1–D.5.5"),
    "environmental": (("D.6.1", "D.6.2", "D.6.3", "D.6.4"),
                      "6.2.8 environmental tests: D.6.1–D.6.4"),
}


def _declared_nonlinearity(device: DeviceUnderTest) -> Any:
    v = device.properties.get("nonlinearity")
    if v is None:
        return None
    check_dimension(v, "", field="device.nonlinearity")
    return v


def method_for(device: DeviceUnderTest | None) -> tuple[str, str]:
    """("angle" or "rate", the reason in words) for ``device`` by clause 6.2.7.1."""
    if device is None:
        return "angle", msg("device not known before acquisition; "
                            "the angle method (D.1) is assumed")
    tech = (device.technology or "").lower()
    if tech == "laser":
        return "angle", msg("laser gyro: clause 6.2.7.1 prescribes the angle method (D.1)")
    who = (msg("fibre gyro") if tech in ("fibre", "fiber") else
           msg("{tech}-technology gyro", tech=tech) if tech else msg("unstated-technology gyro"))
    declared = _declared_nonlinearity(device)
    if declared is not None:
        what = msg("declared nonlinearity {kn:g}×10⁻⁶", kn=declared.to('ppm').magnitude)
        basis = declared
    else:
        app = application_of(device.application)
        if app is None:
            return "rate", msg("{who} without a declared nonlinearity or a known application: "
                               "clause 6.2.7.1 rate "
                               "method (D.2), which does not presume K_n ≤ 5×10⁻⁶", who=who)
        row = next(r for r in TABLE_B1 if r.key == "Kn")
        basis = Q_(row.limits[app], row.unit)
        what = msg("typical nonlinearity limit {kn:g}×10⁻⁶ (table B.1, {app}; none declared)",
                   kn=basis.to('ppm').magnitude, app=app)
    if basis.to("").magnitude <= THRESHOLD.magnitude:
        return "angle", msg("{who}, {what} ≤ 5×10⁻⁶: clause 6.2.7.1 angle method (D.1)", who=who,
                            what=what)
    return "rate", msg("{who}, {what} > 5×10⁻⁶: clause 6.2.7.1 rate method (D.2)", who=who,
                       what=what)


def applicability(procedure, device: DeviceUnderTest | None) -> Applicability | None:
    """metro_item_applicability for GB/T 45570 items; ``None`` for other standards."""
    if getattr(procedure, "standard", None) != "gbt45570":
        return None
    item = procedure.item
    if item in ANGLE_ITEMS or item in RATE_ITEMS:
        method, why = method_for(device)
        mine = "angle" if item in ANGLE_ITEMS else "rate"
        return Applicability(method == mine, why)
    if item in MISALIGNMENT.values():
        tech = (device.technology if device is not None else "").lower()
        if tech == "laser":
            method, why = "angle", msg("laser gyro: clause 6.2.7.2 prescribes D.1.6")
        elif tech in ("fibre", "fiber"):
            method, why = "rate", msg("fibre gyro: clause 6.2.7.2 prescribes D.2.6")
        else:
            method, why = method_for(device)
        return Applicability(MISALIGNMENT[method] == item, why)
    return None

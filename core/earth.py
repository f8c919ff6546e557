"""The Earth as inertial test benches see it: its rotation rate and standard gravity.

One home for the physical constants every simulator and procedure uses.  The standards' own
rounded constants (GB/T 45570 D.40 and JJF 2014 subtract 15.041 °/h) stay in their plugins'
formula modules, next to the equation that prints them.

* Ω_e = 7.2921150×10⁻⁵ rad/s (IERS conventions, the sidereal rotation rate) ≈ 15.04107 °/h;
* g_n = 9.80665 m/s² (standard gravity, CGPM 1901), the ``g`` of metro's unit registry.
"""

from __future__ import annotations

import math

EARTH_RATE_RAD_S = 7.2921150e-5
EARTH_RATE_DEG_S = math.degrees(EARTH_RATE_RAD_S)
EARTH_RATE_DEG_PER_H = EARTH_RATE_DEG_S * 3600.0
STANDARD_GRAVITY_M_S2 = 9.80665


def vertical_earth_rate_deg_h(latitude_deg: float) -> float:
    """Ω_e·sin φ (°/h): the earth rate along the local vertical (up) at latitude φ."""
    return EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))


def horizontal_earth_rate_deg_h(latitude_deg: float) -> float:
    """Ω_e·cos φ (°/h): the earth rate along local north."""
    return EARTH_RATE_DEG_PER_H * math.cos(math.radians(latitude_deg))


__all__ = ["EARTH_RATE_RAD_S", "EARTH_RATE_DEG_S", "EARTH_RATE_DEG_PER_H", "STANDARD_GRAVITY_M_S2",
           "vertical_earth_rate_deg_h", "horizontal_earth_rate_deg_h"]

"""The Earth as inertial test benches see it: its rotation rate and standard gravity.

One home for the physical constants every simulator and procedure uses.  The standards' own
rounded constants (GB/T 45570 D.40 and JJF 2014 subtract 15.041 °/h) stay in their plugins'
formula modules, next to the equation that prints them.

* Ω_e = 7.2921150×10⁻⁵ rad/s (IERS conventions, the sidereal rotation rate) ≈ 15.04107 °/h;
* g_n = 9.80665 m/s² (standard gravity, CGPM 1901), the ``g`` of metro's unit registry;
* the local gravity a MIMU at rest on a table feels is not g_n: :func:`normal_gravity` is the
  GRS 80 normal gravity at a latitude and height (9.780 m/s² at the equator, 9.832 m/s² at the
  poles).
"""

from __future__ import annotations

import math

EARTH_RATE_RAD_S = 7.2921150e-5
EARTH_RATE_DEG_S = math.degrees(EARTH_RATE_RAD_S)
EARTH_RATE_DEG_PER_H = EARTH_RATE_DEG_S * 3600.0
STANDARD_GRAVITY_M_S2 = 9.80665


# : GRS 80 (H. Moritz, "Geodetic Reference System 1980", J. Geodesy 74 (2000) 128–133): normal
# gravity
#: at the equator (m/s²), Somigliana's constant k and the first eccentricity squared e²
GRS80_GAMMA_E = 9.7803267715
GRS80_K = 0.001931851353
GRS80_E2 = 0.00669438002290
#: free-air gradient of normal gravity near the surface, (m/s²) per m (the first-order term)
FREE_AIR_GRADIENT = 3.086e-6


def normal_gravity(latitude_deg: float, height_m: float = 0.0) -> float:
    """Normal gravity (m/s²) at geodetic latitude φ and height h above the ellipsoid: Somigliana's
    closed formula with the GRS 80 constants, γ₀ = γ_e·(1 + k·sin²φ)/√(1 − e²·sin²φ), less the
    free-air gradient 3.086×10⁻⁶ s⁻²·h.  A site's actual gravity differs from it by the gravity
    anomaly (rarely beyond ±300 mGal, 3×10⁻⁴ relative)."""
    s2 = math.sin(math.radians(latitude_deg)) ** 2
    gamma0 = GRS80_GAMMA_E * (1.0 + GRS80_K * s2) / math.sqrt(1.0 - GRS80_E2 * s2)
    return gamma0 - FREE_AIR_GRADIENT * height_m


def vertical_earth_rate_deg_h(latitude_deg: float) -> float:
    """Ω_e·sin φ (°/h): the earth rate along the local vertical (up) at latitude φ."""
    return EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))


def horizontal_earth_rate_deg_h(latitude_deg: float) -> float:
    """Ω_e·cos φ (°/h): the earth rate along local north."""
    return EARTH_RATE_DEG_PER_H * math.cos(math.radians(latitude_deg))


__all__ = [
    "EARTH_RATE_RAD_S",
    "EARTH_RATE_DEG_S",
    "EARTH_RATE_DEG_PER_H",
    "STANDARD_GRAVITY_M_S2",
    "normal_gravity",
    "vertical_earth_rate_deg_h",
    "horizontal_earth_rate_deg_h",
]

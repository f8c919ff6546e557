"""JJF 2003—2022: what the table, the fixture and the site put into the matrices.

Budget rows and the local gravity the six-position and rate-sensitivity results need beyond
appendix A's three components (docs/interpretations.md, JJF 2003 "Local gravity in Ā" and
"Alignment of the MIMU axes"):

* **Local gravity** (7.2.2.2, 7.2.4.2): the accelerometers at rest feel the local gravity g, not
  g_n; Ā's ±1 are ±g/g_n when the outputs are in g_n.  g is ``[site] gravity`` (with
  ``gravity_uncertainty``, a half-width) or the GRS 80 normal gravity at the site's latitude and
  ``altitude`` (:func:`metro.core.stats.earth.normal_gravity`), the anomaly a uniform ±3×10⁻⁴.
* **Alignment of a swept axis** (7.2.1.1 a), 7.2.3): a table axis that is off the MIMU's axis by
  δ puts K_ii·δ into K_g[i, j] — the table's positioning (``position_accuracy``, table 1 ±10″), its
  axis perpendicularity (``axis_perpendicularity``, table 1 ±10″) and the fixture
  (``perpendicularity``, 6.2: 10″).
* **Fixture** (7.2.2, 7.2.4): the MIMU seated in its fixture is misaligned by the same angle in all
  twelve mountings; the pair differences keep it: K_ii·δ in each off-diagonal term.
* **Table axis tilt at rest** (7.2.5): U₇ is read at rest, where a table axis leaning by δ from the
  vertical puts K_ii·g·δ on accelerometer i; turning at ω averages it out of U₈.
"""

from __future__ import annotations

import math

from metro.api import (Q_, STANDARD_GRAVITY_M_S2, BudgetRow, Campaign, DataError, msg,
                       normal_gravity, parse_quantity)

#: half-width of the gravity anomaly about normal gravity (±300 mGal), relative
GRAVITY_ANOMALY_REL = 3e-4
#: a site without its altitude is taken at 0 m; each 1000 m lowers g by 3.1×10⁻⁴ (free air)
NO_ALTITUDE_REL = 3.1e-4
#: table 1: 角位置定位精度 ±10″, 轴线垂直度 ±10″; 6.2: 夹具各垂直面相互垂直度 10″
TABLE1_POSITION_ARCSEC = 10.0
TABLE1_AXIS_PERPENDICULARITY_ARCSEC = 10.0
FIXTURE_62_ARCSEC = 10.0


def local_gravity(campaign: Campaign) -> tuple[float, float | None, str]:
    """(g/g_n, relative half-width of g (uniform) or None when stated without one, where g came
    from)."""
    site = campaign.site
    if "gravity" in site:
        g = float(campaign.site_value("gravity", "m/s**2").to("m/s**2").magnitude)
        if not 9.7 <= g <= 9.9:
            raise DataError(campaign.source, "site.gravity",
                            f"{g:g} m/s² is not a gravity on the earth's surface (9.78–9.83 m/s²)",
                            hint='write the local gravity, e.g. gravity = "9.80122 m/s²"')
        rel = None
        if "gravity_uncertainty" in site:
            hw = float(campaign.site_value("gravity_uncertainty", "m/s**2").to("m/s**2").magnitude)
            if not 0 <= hw < 0.1:
                raise DataError(campaign.source, "site.gravity_uncertainty",
                                f"{hw:g} m/s² is not a half-width of a local gravity (0 … 0.1 "
                                "m/s²)")
            rel = hw / g
        return g / STANDARD_GRAVITY_M_S2, rel, msg("[site] gravity = {g:.6g} m/s²", g=g)
    lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    rel = GRAVITY_ANOMALY_REL
    if "altitude" in site:
        h = float(parse_quantity(site["altitude"], dimension="m", file=campaign.source,
                                 field="site.altitude").to("m").magnitude)
        where = msg("GRS 80 normal gravity at φ = {lat:g}°, {h:g} m", lat=lat, h=h)
    else:
        h = 0.0
        rel += NO_ALTITUDE_REL
        where = msg("GRS 80 normal gravity at φ = {lat:g}°, 0 m (no [site] altitude)", lat=lat)
    g = normal_gravity(lat, h)
    return g / STANDARD_GRAVITY_M_S2, rel, msg("{where}: {g:.6g} m/s²", where=where, g=g)


def gravity_row(campaign: Campaign, value: float, unit: str) -> BudgetRow:
    """The local gravity's uncertainty in a six-position matrix term ``value`` (∝ 1/g)."""
    ratio, rel, where = local_gravity(campaign)
    if rel is None:
        return BudgetRow.type_b(msg("local gravity ({where})", where=where), "u_g", Q_(0.0, ""),
                                distribution="uniform", sensitivity=Q_(abs(value), unit),
                                note=msg("stated without gravity_uncertainty: taken as exact"))
    return BudgetRow.type_b(msg("local gravity ({where})", where=where), "u_g", Q_(rel, ""),
                            distribution="uniform",
                            sensitivity=Q_(abs(value), unit),
                            note=msg("Ā's ±1 are ±g/g_n; relative half-width of g"))


def _angle(eq, prop: str, default: float, source: str) -> tuple[float, str]:
    """(half-width in rad, where from): the equipment's stated angle, else the standard's bound."""
    if eq is not None and prop in eq.properties:
        q = eq.prop(prop, "deg", source=source)
        return float(q.to("rad").magnitude), msg("stated by {equipment}", equipment=eq.describe())
    return math.radians(default / 3600.0), msg("{a:g}″, the standard's bound (not stated by the "
                                               "lab)", a=default)


def fixture_row(campaign: Campaign, sensitivity: float, unit: str) -> BudgetRow:
    """6.2: the fixture's perpendicularity (the MIMU's axes against the table's), uniform."""
    eq = campaign.equipment_for("fixture")
    hw, where = _angle(eq, "perpendicularity", FIXTURE_62_ARCSEC, campaign.source)
    return BudgetRow.type_b(msg("fixture perpendicularity (6.2)"), "u_f", Q_(hw, "rad"),
                            distribution="uniform",
                            sensitivity=Q_(abs(sensitivity), f"{unit}/rad" if unit else "1/rad"),
                            note=msg("the same in every mounting; {where}", where=where))


def swept_axis_rows(campaign: Campaign, K_ii: float) -> list[BudgetRow]:
    """7.2.3: a table axis off the MIMU's axis j by δ puts K_ii·δ into K_g[i, j] (i ≠ j): the
    table's positioning and axis perpendicularity (table 1) and the fixture (6.2), uniform each."""
    eq = campaign.equipment_for("rate_table")
    rows = []
    for prop, default, name in (("position_accuracy", TABLE1_POSITION_ARCSEC,
                                 msg("table positioning of the swept axis")),
                                ("axis_perpendicularity", TABLE1_AXIS_PERPENDICULARITY_ARCSEC,
                                 msg("table axis perpendicularity (table 1)"))):
        hw, where = _angle(eq, prop, default, campaign.source)
        rows.append(BudgetRow.type_b(name, "u_δ", Q_(hw, "rad"), distribution="uniform",
                                     sensitivity=Q_(abs(K_ii), "1/rad"),
                                     note=msg("δ·K_ii enters K_g[i, j]; {where}", where=where)))
    rows.append(fixture_row(campaign, K_ii, ""))
    return rows


def rest_tilt_row(campaign: Campaign, K_ii_gn: float, omega_rad_s: float, p_unit: str) -> BudgetRow:
    """7.2.5: U₇ at rest carries K_ii·g·δ of a table axis leaning by δ (table positioning,
    ``position_accuracy``), which turning averages out of U₈: c = K_ii·g/ω² per rad."""
    eq = campaign.equipment_for("rate_table")
    hw, where = _angle(eq, "position_accuracy", TABLE1_POSITION_ARCSEC, campaign.source)
    return BudgetRow.type_b(msg("table axis tilt at rest (U₇)"), "u_t", Q_(hw, "rad"),
                            distribution="uniform",
                            sensitivity=Q_(abs(K_ii_gn) / omega_rad_s**2, f"{p_unit}/rad"),
                            note=msg("K_ii·g·δ in U₇, averaged out of U₈; {where}", where=where))

"""JJF 2003—2022: reading the campaign's records and the eq. (3)–(12) computations the items share.

The segment layout (``rate``: ``axis``, ``rate``; ``position``: ``up``, ``heading``), the means of
eq. (3) with their batch-mean standard uncertainties, the eq. (5) sweep fits, the six-position
solution of eq. (7)/(10), the 7.2.5 rest/turning pairs, and the ideal evaluation a simulated
station's ``expected`` comes from.  Split from :mod:`.procedures` (which re-exports these names).
"""

from __future__ import annotations

import math
from typing import Any, Callable

import numpy as np
from metro.api import Q_, Campaign, DataError, ProcedureError, Segment

from . import formulas as F
from . import mounting

AXES = ("x", "y", "z")
GYRO = ("gx", "gy", "gz")
ACCEL = ("ax", "ay", "az")
RATE_UNIT = "deg/s"
ACC_UNIT = "gn"
P_UNIT = "gn/(rad/s)**2"
G_UNIT = "deg/s/gn"
MIN_SECONDS = 30.0
HEADINGS = (0.0, 180.0)
BATCHES = 10


Means = Callable[[Segment], tuple[np.ndarray, np.ndarray]]


# ------------------------------------------------------------------------------ data access


def duration_ok(seg: Segment, campaign: Campaign) -> None:
    s = seg.series("gx", "deg/s")
    dur = float(s.duration.to("s").magnitude)
    if dur < MIN_SECONDS * 0.999:
        raise DataError(seg.file or campaign.source, f"segments.{seg.id}",
                        f"held for {dur:.3g} s; JJF 2003 7.2.1.1 d) / 7.2.2.1 a) ask for at least "
                        "30 s",
                        hint="record each rate point and position for 30 s or more")


def columns_of(seg: Segment, names, dim: str) -> np.ndarray:
    arrs = []
    for c in names:
        s = seg.series(c, dim)
        a = np.asarray(s.data.to(RATE_UNIT if dim == "deg/s" else ACC_UNIT).magnitude, dtype=float)
        if a.size < 2 * BATCHES:
            raise DataError(seg.file, c,
                            f"segment {seg.id!r} has {a.size} samples; at least {2 * BATCHES} "
                            f"needed")
        bad = ~np.isfinite(a)
        if bad.any():
            i = int(np.argmax(bad))
            raise DataError(seg.file or f"segment {seg.id}", c, f"sample {i + 1} is {a[i]!r}")
        arrs.append(a)
    return np.vstack(arrs)


def batch_u(a: np.ndarray) -> np.ndarray:
    """Standard uncertainty of each row's mean from BATCHES batch means (dof BATCHES − 1)."""
    m = a.shape[1] // BATCHES
    b = a[:, : m * BATCHES].reshape(a.shape[0], BATCHES, m).mean(axis=2)
    return b.std(axis=1, ddof=1) / math.sqrt(BATCHES)


def data_means(
    campaign: Campaign,
) -> tuple[Means, Callable[[Segment], tuple[np.ndarray, np.ndarray]]]:
    """(means(seg) → (gyro[3] °/s, accel[3] gn) by eq. (3); u(seg) → their standard
    uncertainties)."""
    cache: dict[str, tuple] = {}

    def load(seg: Segment):
        if seg.id not in cache:
            duration_ok(seg, campaign)
            g = columns_of(seg, GYRO, "deg/s")
            a = columns_of(seg, ACCEL, "m/s**2")
            cache[seg.id] = (g.mean(axis=1), a.mean(axis=1), batch_u(g), batch_u(a))
        return cache[seg.id]

    return (lambda s: load(s)[:2]), (lambda s: load(s)[2:])


def rate_of(seg: Segment, campaign: Campaign) -> float:
    r = seg.condition("rate", "deg/s")
    return float(r.to("deg/s").magnitude)


def axis_of(seg: Segment, campaign: Campaign) -> str:
    a = str(seg.condition("axis")).strip().lower().lstrip("+")
    if a not in AXES:
        raise DataError(seg.file or campaign.source, f"segments.{seg.id}.conditions.axis",
                        "must be x, y or z (the MIMU axis along the table axis, pointing up), got "
                        f"{a!r}")
    return a


def sweeps(campaign: Campaign, axes=AXES, segments=None) -> dict[str, list[tuple[float, Segment]]]:
    """Rate segments per axis, sorted by rate; checks 7–11 distinct rates (7.2.1.1 c)).
    ``segments``: another set than the campaign's kind ``rate`` (one repeated sweep)."""
    out: dict[str, list[tuple[float, Segment]]] = {a: [] for a in axes}
    for seg in (campaign.find_segments("rate") if segments is None else segments):
        a = axis_of(seg, campaign)
        if a in out:
            out[a].append((rate_of(seg, campaign), seg))
    for a, pts in out.items():
        rates = [r for r, _ in pts]
        if len(set(rates)) != len(rates):
            dup = sorted({r for r in rates if rates.count(r) > 1})
            raise DataError(campaign.source, "segments",
                            f"axis {a}: more than one segment at rate(s) "
                            f"{', '.join(f'{r:g}' for r in dup)} °/s; metro does not guess which "
                            "to use")
        if len(rates) < 7:
            raise DataError(campaign.source, "segments",
                            f"axis {a} is swept with {len(rates)} rate(s); JJF 2003 7.2.1.1 c) "
                            "asks for 7–11 rate points including the maximum input rate",
                            hint="`metro plan -s jjf2003 -i 7.2.1` lists the rate points")
        pts.sort(key=lambda p: p[0])
    return out


def heading_of(seg: Segment, campaign: Campaign) -> float:
    h = seg.condition("heading")
    if isinstance(h, (int, float)):
        v = float(h)
    else:
        v = float(seg.condition("heading", "deg").to("deg").magnitude)
    v = v % 360.0
    for ref in HEADINGS:
        if abs(v - ref) < 1e-6:
            return ref
    raise DataError(seg.file or campaign.source, f"segments.{seg.id}.conditions.heading",
                    f"must be 0° or 180° (7.2.2.1 a): two mountings a 180° turn apart), got {v:g}°")


def positions(campaign: Campaign) -> dict[tuple[str, float], Segment]:
    """The twelve mountings (up axis, heading) of 7.2.2.1 a); all must be present."""
    found: dict[tuple[str, float], Segment] = {}
    for seg in campaign.find_segments("position"):
        up = str(seg.condition("up")).strip().lower()
        if up in AXES:
            up = "+" + up
        if up not in F.SIX_POSITIONS:
            raise DataError(seg.file or campaign.source, f"segments.{seg.id}.conditions.up",
                            f"must be one of {', '.join(F.SIX_POSITIONS)}, got {up!r}")
        key = (up, heading_of(seg, campaign))
        if key in found:
            raise DataError(campaign.source, "segments",
                            f"two segments ({found[key].id}, {seg.id}) for position {up} up, "
                            f"heading {key[1]:g}°")
        found[key] = seg
    missing = [f"{u} up, heading {h:g}°" for u in F.SIX_POSITIONS for h in HEADINGS
               if (u, h) not in found]
    if missing:
        raise DataError(campaign.source, "segments",
                        "the six-position method (7.2.2.1 a), appendix C) needs 12 mountings; "
                        f"missing: {'; '.join(missing)}", hint="`metro plan -s jjf2003 -i 7.2.2` "
                                                               "lists the 12 mountings")
    return found


# ------------------------------------------------------------------------------ computations


def sweep_fits(campaign: Campaign, means: Means, segments=None) -> dict[str, dict[str, Any]]:
    """Per swept axis j: eq. (5) fits of each gyro output i against the rate → K_g[i, j]."""
    out = {}
    for j, pts in sweeps(campaign, segments=segments).items():
        X = np.array([r for r, _ in pts])
        U = np.array([means(s)[0] for _, s in pts])  # n × 3
        fits = []
        for i in range(3):
            try:
                fits.append(F.scale_factor_eq5(X, U[:, i]))
            except ValueError as exc:
                raise ProcedureError(f"7.2.1 axis {j}: the eq. (5) design is singular or too small "
                                     f"({exc})") from exc
        out[j] = {"X": X, "U": U, "fits": fits, "segments": [s.id for _, s in pts]}
    return out


def six_position(campaign: Campaign, means: Means,
                 which: int) -> tuple[np.ndarray, np.ndarray, list[str]]:
    """Pair-averaged outputs U (3×6) of the gyros (which=0) or accelerometers (1) and the eq.
    (7)/(10) solution [M | B] (3×4)."""
    segs = positions(campaign)
    cols = []
    for up in F.SIX_POSITIONS:
        cols.append(F.pair_average(means(segs[(up, 0.0)])[which], means(segs[(up, 180.0)])[which]))
    U = np.column_stack(cols)
    try:
        GB = F.six_position_eq7(U)
    except ValueError as exc:
        raise ProcedureError(f"six-position method: {exc}") from exc
    # Ā's ±1 are the local gravity in g_n (interpretations, "Local gravity in Ā"): a term per g_n
    # of input is the eq. (7) column over g/g_n; the biases (the row of ones) are unchanged
    ratio, _, _ = mounting.local_gravity(campaign)
    GB[:, :3] = GB[:, :3] / ratio
    return U, GB, [s.id for s in segs.values()]


def rate_pairs(campaign: Campaign, omega_deg_s: float) -> dict[str, tuple[Segment, Segment]]:
    """Per axis: the segment at rest (U₇) and at ω (U₈) of 7.2.5.1 a)–d)."""
    out = {}
    for a in AXES:
        rest = turning = None
        for seg in campaign.find_segments("rate"):
            if axis_of(seg, campaign) != a:
                continue
            r = rate_of(seg, campaign)
            if r == 0.0:
                rest = seg
            elif abs(r - omega_deg_s) < 1e-9 * max(1.0, abs(omega_deg_s)):
                turning = seg
        if rest is None or turning is None:
            what = "at rest (U₇)" if rest is None else f"turning at ω = {omega_deg_s:g} °/s (U₈)"
            raise DataError(campaign.source, "segments",
                            f"7.2.5 needs, for axis {a} up, a rate segment {what}; none found",
                            hint="`metro plan -s jjf2003 -i 7.2.5`, or set the option omega to a "
                                 "recorded rate")
        out[a] = (rest, turning)
    return out


def p_matrix(campaign: Campaign, means: Means, omega_deg_s: float, sign: str) -> np.ndarray:
    """p (3×3, zero diagonal) by eq. (12)/(13) with ω in rad/s."""
    w = math.radians(omega_deg_s)
    p = np.zeros((3, 3))
    for j, a in enumerate(AXES):
        rest, turning = rate_pairs(campaign, omega_deg_s)[a]
        u7, u8 = means(rest)[1], means(turning)[1]
        for i in range(3):
            if i != j:
                p[i, j] = F.rate_sensitivity_eq12(u7[i], u8[i], w, sign=sign)
    return p


def ideal_evaluation(campaign: Campaign, means: Means) -> dict[str, Any]:
    """Every metric by the default evaluation, from given (exact) segment means (for
    ``expected``)."""
    out: dict[str, Any] = {}
    try:
        fits = sweep_fits(campaign, means)
        for j, d in fits.items():
            for i, r in enumerate(AXES):
                out[f"K_g{r}{j}"] = Q_(float(d["fits"][i].coef[0]), "")
    except Exception:  # noqa: BLE001 - items not in this campaign
        pass
    for which, prefix_m, prefix_b, mu, bu in ((0, "g_", "B_g", G_UNIT, RATE_UNIT),
                                              (1, "K_a", "B_a", "", ACC_UNIT)):
        try:
            _, GB, _ = six_position(campaign, means, which)
        except Exception:  # noqa: BLE001
            continue
        for i, r in enumerate(AXES):
            out[f"{prefix_b}{r}"] = Q_(float(GB[i, 3]), bu)
            for j, c in enumerate(AXES):
                out[f"{prefix_m}{r}{c}"] = Q_(float(GB[i, j]), mu)
    try:
        p = p_matrix(campaign, means, 400.0, "model")
        for i, r in enumerate(AXES):
            for j, c in enumerate(AXES):
                if i != j:
                    out[f"p_{r}{c}"] = Q_(float(p[i, j]), P_UNIT)
    except Exception:  # noqa: BLE001
        pass
    return out

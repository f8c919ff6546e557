"""The angle method's data (GB/T 45570 D.1): the R5 rate points and the sweep of whole
revolutions (D.1.1.2), each rate point's pulse counts paired by direction (D.1, D.2), and the
bias drifting through the sweep, read off the revolutions' own counts.  Shared by the D.1 items,
D.3 on an angle-method sweep, the repeatability rows and the clause-5 environmental tests."""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import Q_, BudgetRow, Campaign, DataError, Procedure, Step, msg

from . import formulas as F
from .common import DIRECTIONS, ItemRef, signed_rate

#: GB/T 321 R5 preferred numbers, rounded, up to 400 °/s (D.1.1.2 e))
R5_RATES = (1.0, 1.6, 2.5, 4.0, 6.3, 10.0, 16.0, 25.0, 40.0, 63.0, 100.0, 160.0, 250.0, 400.0)


REPEAT_RATE = "30 °/s"  # D.1.4.2


def rate_points(max_rate_deg_s: float) -> list[float]:
    """R5 rate points up to and including the maximum input rate (D.1.1.2 e))."""
    pts = [r for r in R5_RATES if r < max_rate_deg_s * (1 - 1e-9)]
    return pts + [float(max_rate_deg_s)]


def angle_sequence(options: Mapping[str, Any], zero: bool) -> list[Step]:
    """D.1.1.2: whole revolutions both ways at each R5 rate point, with (``zero``) the zero-rate
    records of D.1.3.2 a) at the start and end."""
    from metro.api import parse_quantity

    rmax = float(parse_quantity(options.get("max_rate", "400 °/s"),
                                dimension="deg/s").to("deg/s").magnitude)
    m = int(options.get("turns", 5))
    steps = []
    if zero:
        steps.append(Step("zero-start", "static-zero",
                          "table at rest, 300 s at τ = 1 s (D.1.3.2 a))",
                          Q_(300, "s"), Q_(1, "s"), {"orientation": "IRA up"}))
    for r in rate_points(rmax):
        for sign, word in DIRECTIONS:
            steps.append(Step(f"rate{sign * r:+g}", "rate-revolutions",
                              f"{m} whole revolutions at {r:g} °/s {word}, counting pulses between "
                              f"revolution "
                              "pulses (D.1.1.2 g))", Q_(m * 360.0 / r, "s"), Q_(360.0 / r, "s"),
                              {"rate": f"{sign * r:g} deg/s", "turns": m}, warmup=Q_(30, "min")))
    if zero:
        steps.append(Step("zero-end", "static-zero", "table at rest, 300 s at τ = 1 s (D.1.3.2 a))",
                          Q_(300, "s"), Q_(1, "s"), {"orientation": "IRA up"}))
    return steps


def revolution_trend(c_plus: np.ndarray, c_minus: np.ndarray) -> tuple[float, float, int]:
    """The common slope β (P per revolution) of the per-revolution counts of a rate point's + and
    − runs against each revolution's place in its run, each run with its own mean (the counts
    differ by ≈ 2·K·360·3 600 between the runs), its standard uncertainty from the residuals and
    ν = m₊ + m₋ − 3.  A bias changing at ḃ (″/s²) through the point adds K·ḃ·T² per revolution
    of T seconds to both runs' counts, so β = K·ḃ·T².  Not a formula of the standard: metro's
    bound on the bias drift between the + and − runs of D.1.1.2 g) (interpretations.md, "D.1.2 /
    D.1.3 — the bias drifting through the sweep").  Returns (0, inf, 0) below two revolutions a
    run."""
    cp, cm = np.asarray(c_plus, dtype=float), np.asarray(c_minus, dtype=float)
    if cp.size < 2 or cm.size < 2 or cp.size + cm.size < 5:
        return 0.0, math.inf, 0
    jp, jm = np.arange(cp.size) - (cp.size - 1) / 2.0, np.arange(cm.size) - (cm.size - 1) / 2.0
    sxx = float(jp @ jp + jm @ jm)
    beta = float((jp @ (cp - cp.mean()) + jm @ (cm - cm.mean())) / sxx)
    res = np.concatenate([cp - cp.mean() - beta * jp, cm - cm.mean() - beta * jm])
    dof = cp.size + cm.size - 3
    return beta, math.sqrt(float(res @ res) / dof / sxx), dof


@attrs.frozen
class RatePoint:
    """One rate point of the angle method: the mean pulse counts of its + and − runs (D.1), their
    scatter, revolutions and times, and the trend of the counts within the runs."""

    rate: float  # |Ω|, °/s
    n_plus: float
    n_minus: float
    s_plus: float  # standard deviation of one revolution's count
    s_minus: float
    m_plus: int
    m_minus: int
    t_plus: float  # mean revolution time, s
    t_minus: float
    segments: tuple[str, str]
    #: common slope of the two runs' per-revolution counts against the revolution's place in its run
    #: (P per revolution; the bias drifting through the point), its standard uncertainty and ν
    trend: float = 0.0
    u_trend: float = math.inf
    dof_trend: int = 0

    @property
    def K(self) -> float:
        return F.scale_factor_d2(self.n_plus, self.n_minus)

    @property
    def u_K(self) -> float:
        """Standard uncertainty of K_i from the scatter of the revolutions' counts."""
        up = self.s_plus / math.sqrt(self.m_plus) if self.m_plus > 1 else 0.5
        um = self.s_minus / math.sqrt(self.m_minus) if self.m_minus > 1 else 0.5
        return math.hypot(up, um) / (2 * F.REVOLUTION_ARCSEC)


@attrs.frozen
class SweepDrift:
    """The bias's rate of change through a sweep, from the revolutions' own counts: the rms ḃ
    (″/s², i.e. (°/h)/s) of the rate points' trends (:func:`revolution_trend`), weighted by their
    inverse variance, their own noise removed (√(max(Σw(ḃ_i² − u_i²)/Σw, 0))), and its degrees of
    freedom, the effective number of points (Σw)²/Σw²."""

    rms: float
    dof: float
    points: int


def sweep_drift(pts: list["RatePoint"]) -> SweepDrift:
    """:class:`SweepDrift` of the rate points ``pts`` (interpretations.md, "D.1.2 / D.1.3 — the bias
    drifting through the sweep")."""
    num = den = den2 = 0.0
    n = 0
    for p in pts:
        T = 0.5 * (p.t_plus + p.t_minus)
        if not (p.dof_trend > 0 and math.isfinite(p.u_trend) and p.u_trend > 0):
            continue
        scale = abs(p.K) * T * T  # β = K·ḃ·T²
        b, v = p.trend / scale, (p.u_trend / scale) ** 2
        w = 1.0 / v
        num += w * (b * b - v)
        den += w
        den2 += w * w
        n += 1
    if n == 0 or den <= 0:
        return SweepDrift(0.0, math.inf, 0)
    return SweepDrift(math.sqrt(max(num / den, 0.0)), max(den * den / den2, 1.0), n)


def point_drift(p: "RatePoint") -> float:
    """Relative standard uncertainty of K_i (D.2) from the bias drifting between the + and − runs of
    D.1.1.2 g) at this point, from its own revolutions' trend β (:func:`revolution_trend`): the
    difference N₊ − N₋ keeps −β·Δ, Δ the runs' centres apart in revolutions ((m₊ + m₋)/2), which is
    not corrected, so u = Δ·√(β² + u²(β))/(2·360·3 600″·K_i) — the drift the counts show and the
    drift they cannot exclude."""
    if not (p.dof_trend > 0 and math.isfinite(p.u_trend)):
        return 0.0
    dt = 0.5 * (p.m_plus * p.t_plus + p.m_minus * p.t_minus) / (0.5 * (p.t_plus + p.t_minus))
    return dt * math.hypot(p.trend, p.u_trend) / (2.0 * F.REVOLUTION_ARCSEC * abs(p.K))


def collect_rate_points(proc: type[Procedure] | ItemRef, campaign: Campaign, min_points: int,
                        segments: list | None = None, what: str = "") -> list[RatePoint]:
    """Pair the + and − revolution segments of every rate point (D.1.1.2 g), eq. (D.1)).

    ``segments`` (default: every ``rate-revolutions`` segment) and ``what`` (e.g. "at 60 °C",
    named in the errors) let D.1.4–D.1.6 apply it to one run, temperature or mounting.
    """
    segs = campaign.find_segments("rate-revolutions") if segments is None else segments
    by_rate: dict[float, dict[int, Any]] = {}
    for s in segs:
        rate, d = signed_rate(campaign, s)
        key = round(abs(rate), 9)
        if d in by_rate.setdefault(key, {}):
            raise DataError(campaign.source, f"segments.{s.id}", f"two segments at {rate:+g} °/s")
        by_rate[key][d] = s
    points = []
    for rate, pair in sorted(by_rate.items()):
        if set(pair) != {1, -1}:
            missing = "clockwise (−)" if 1 in pair else "counter-clockwise (+)"
            only = pair.get(1) or pair.get(-1)
            raise DataError(campaign.source, f"segments.{only.id}",
                            f"rate point {rate:g} °/s{' ' + what if what else ''} has no {missing} "
                            f"run; "
                            "D.2 needs both directions")
        stats = {}
        for d, s in pair.items():
            c = np.asarray(s.series("count", "P").data.magnitude, dtype=float)
            t = np.asarray(s.series("duration", "s").data.to("s").magnitude, dtype=float)
            if (c.size < 1 or not np.all(np.isfinite(c)) or not np.all(np.isfinite(t))
                    or np.any(t <= 0)):
                raise DataError(s.file or f"segment {s.id}", "count/duration",
                                "needs at least one revolution with finite counts and positive "
                                "durations")
            expect_t = 360.0 / rate
            if abs(float(np.mean(t)) - expect_t) > 0.05 * expect_t:
                raise DataError(s.file or f"segment {s.id}", "duration",
                                f"revolutions last {np.mean(t):.4g} s on average, but 360° at "
                                f"{rate:g} °/s takes "
                                f"{expect_t:.4g} s; is the rate or the duration unit wrong?")
            stats[d] = (F.mean_counts_d1(c), float(np.std(c, ddof=1)) if c.size > 1 else 0.0,
                        c.size,
                        float(np.mean(t)), s.id, c)
        (np_, sp, mp, tp, idp, cp), (nm, sm, mm, tm, idm, cm) = stats[1], stats[-1]
        points.append(RatePoint(rate, np_, nm, sp, sm, mp, mm, tp, tm, (idp, idm),
                                *revolution_trend(cp, cm)))
    if len(points) < min_points:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs at least {min_points} rate points (D.1.1.2 "
                        f"e)){' ' + what if what else ''}; found {len(points)}",
                        hint="or lower the option min_points if agreed with the user")
    return points


def angle_row(campaign: Campaign, value: float, unit: str) -> list[BudgetRow]:
    """The revolution pulse's position accuracy (D.1.1.1 d)) as a relative row on ``value``."""
    table = campaign.equipment_for("rate_table")
    if table is None or "revolution_pulse_accuracy" not in table.properties:
        return []
    acc = table.prop("revolution_pulse_accuracy", "arcsec", source=campaign.source)
    rel = float(acc.to("arcsec").magnitude) / F.REVOLUTION_ARCSEC
    return [BudgetRow.type_b(msg("revolution pulse position ({equipment})",
                                 equipment=table.describe()), "δθ/360°",
                             Q_(rel, ""), distribution="uniform", sensitivity=Q_(abs(value), unit),
                             note=msg("±{acc} on 360° (D.1.1.1 d))", acc=f"{acc:~P}"))]

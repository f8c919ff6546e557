"""A static record's bias (GB/T 45570 D.5.1, eq. D.40) and what the output's quantization does to
means and standard deviations of it (interpretations.md, "D.5 — output quantization").  Shared by
the D.5 items, the environmental items (D.6, 6.2.7), polarity, the threshold and the clause-5
environmental tests, which all apply "the method of D.5.1.2" to their segments."""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, Procedure, RateConversion,
                       Segment, SegmentRequirement, UncertaintyBudget, allan, gyro_output, msg,
                       parse_quantity)

from . import formulas as F
from .common import COVERAGE, check_finite, resolution_row, scale_factor_row, timebase_row

STATIC = SegmentRequirement(
    kind="static",
    description="gyro at rest on a levelled stable platform, IRA along the local vertical "
                "(D.5.1.2)",
    conditions={"orientation": ""},
    columns={"output": OUTPUT_UNITS},
)


def static_segment(proc: type[Procedure], campaign: Campaign, options: Mapping[str,
                                                                               Any]) -> Segment:
    """The static segment a D.5 item evaluates (option ``segment``, else the first), its
    orientation checked."""
    wanted = options.get("segment")
    segs = campaign.find_segments("static")
    if wanted:
        segs = [s for s in segs if s.id == wanted]
        if not segs:
            raise DataError(campaign.source, "segments", f"no static segment with id {wanted!r}")
    if not segs:
        raise DataError(
            campaign.source, "segments",
            f"{proc.qualified_id()} needs a segment of kind \"static\" ({STATIC.description}); "
            f"none found",
            hint="`metro plan --standard gbt45570 --item " + proc.item + "` shows what to measure",
        )
    seg = segs[0]
    orientation(seg, campaign)
    return seg


def static_input(proc: type[Procedure], campaign: Campaign, options: Mapping[str, Any]):
    """The static segment, its output series, the conversion to °/h and the raw samples
    (checked finite) — the common start of every D.5 item."""
    seg = static_segment(proc, campaign, options)
    series, conv = gyro_output(seg, campaign.device, source=campaign.source)
    raw = np.asarray(series.data.magnitude)
    check_finite(raw, seg)
    return seg, series, conv, raw


def orientation(seg: Segment, campaign: Campaign) -> str:
    """'up' or 'down' from the segment's required ``orientation`` condition (D.5.1.2 a))."""
    orient = str(seg.condition("orientation")).strip().lower().replace("ira", "").strip()
    if orient not in ("up", "down"):
        raise DataError(seg.file or campaign.source, f"segments.{seg.id}.conditions.orientation",
                        f"must be \"IRA up\" or \"IRA down\" (D.5.1.2 a)), got "
                        f"{seg.conditions['orientation']!r}")
    return orient


@attrs.frozen
class BiasEstimate:
    """D.40 applied to one static segment, with its full budget and its type A part."""

    B0: float  # °/h
    u_A: float  # °/h, batch-means standard uncertainty
    nu_A: int
    budget: UncertaintyBudget
    earth: float
    orientation: str
    theta: float
    conv: RateConversion
    series: Any
    u_q: float = 0.0  # °/h, standard uncertainty of B0 from the output's quantization
    hw_q: float = 0.0  # °/h, its half-width (uniform)


def batch_record(seg: Segment, campaign: Campaign, batches: int,
                 dtype: Any = float) -> tuple[Any, RateConversion, np.ndarray]:
    """A segment's output series, its conversion to °/h and its samples (as ``dtype``), checked
    finite and long enough for ``batches`` batch means."""
    series, conv = gyro_output(seg, campaign.device, source=campaign.source)
    raw = np.asarray(series.data.magnitude, dtype=dtype)
    check_finite(raw, seg)
    if raw.size < 2 * batches:
        raise DataError(seg.file or f"segment {seg.id}", "output",
                        f"{raw.size} samples are too few for {batches} batch means")
    return series, conv, raw


def segment_bias(seg: Segment, campaign: Campaign, batches: int = 20) -> BiasEstimate:
    """Bias of one static segment by D.40 (D.5.1.3), with its budget.

    Shared by D.5.1 and the items built on it (D.5.3 repeatability, D.5.4 temperature and
    D.5.5 magnetic sensitivity), which apply "the method of D.5.1.2" to each segment.
    """
    b = int(batches)
    series, conv, raw = batch_record(seg, campaign, b, dtype=None)
    orient = orientation(seg, campaign)
    theta = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    mean_raw = float(np.mean(raw, dtype=np.float64))
    indicated = mean_raw * conv.magnitude
    earth = F.earth_rate_vertical(theta, orient)
    if conv.output_kind == "pulse":
        B0 = F.bias_d40(mean_raw, float(series.interval.to("s").magnitude),
                        float(conv.scale_factor.to("P/arcsec").magnitude), theta)
        if orient == "down":
            B0 += 2 * F.earth_rate_vertical(theta)
    else:
        B0 = indicated - earth
    # correlated noise (bias instability, rate random walk) makes neighbouring batch means alike,
    # and
    # their scatter understates the mean's u: five long batches are checked against it and taken
    # when they disagree beyond chance (F test, 95 %) (interpretations.md, D.5.1)
    bm = allan.mean_u_batches(raw, b)
    uA, nb = bm.u * conv.magnitude, bm.batches
    note = msg("{nb} batches of {n} samples", nb=nb, n=raw.size // b)
    if bm.correlated:
        note = msg("{n5} batches of {n} samples: the {nb} batch means ({uA:.3g} °/h) are "
                   "correlated (bias "
                   "instability or random walk), their scatter understates the mean's u", n5=nb,
                   n=raw.size // nb,
                   nb=bm.batches_short, uA=bm.u_short * conv.magnitude)
    rows = [BudgetRow.type_a(msg("scatter of the output (batch means)"), "s_b/√b", Q_(uA, "deg/h"),
                             nb - 1, note=note)]
    rows += scale_factor_row(conv, indicated, "deg/h")
    lat_u = campaign.site.get("latitude_uncertainty")
    c_theta = F.EARTH_RATE_DEG_PER_H * math.cos(math.radians(theta))
    if lat_u is not None:
        lu = parse_quantity(lat_u, dimension="deg", file=campaign.source,
                            field="site.latitude_uncertainty")
        rows.append(BudgetRow.type_b(msg("site latitude θ"), "u(θ)", lu.to("rad"),
                                     distribution="uniform",
                                     sensitivity=Q_(c_theta, "deg/h/rad"),
                                     note=msg("∂B0/∂θ = −15.041·cos θ")))
    plat = campaign.equipment_for("platform")
    if plat is not None and "levelness" in plat.properties:
        lev = plat.prop("levelness", "arcsec", source=campaign.source)
        rows.append(BudgetRow.type_b(msg("levelling of the IRA ({equipment})",
                                         equipment=plat.describe()), "δ",
                                     lev.to("rad"), distribution="uniform", sensitivity=Q_(c_theta,
                                                                                           "deg/h/rad"),
                                     note=msg("horizontal earth rate Ω·cos θ·sin δ leaks into the "
                                              "IRA")))
    rows += timebase_row(campaign, indicated, "deg/h", msg("indicated rate"))
    q_rows = quantization_rows_mean(campaign, conv, raw, msg("the mean of D.40"))
    rows += q_rows
    budget = UncertaintyBudget("B0", "deg/h", rows, coverage=COVERAGE)
    u_q = float(q_rows[0].contribution.to("deg/h").magnitude) if q_rows else 0.0
    return BiasEstimate(B0, uA, nb - 1, budget, earth, orient, theta, conv, series, u_q,
                        u_q * math.sqrt(3.0))


def duration_warnings(series, wanted, clause: str) -> list[str]:
    """A warning when the record is shorter than the clause asks."""
    dur = series.duration.to("h")
    if dur < wanted * 0.999:
        return [msg("the record lasts {dur}; {clause} asks for {wanted} (or the user's application "
                    "time)",
                    dur=f"{dur:~.3gP}", clause=clause, wanted=f"{wanted:~P}")]
    return []


def segments_of(proc: type[Procedure], campaign: Campaign, kind: str, need: int,
                what: str) -> list[Segment]:
    """The segments of ``kind``; a DataError when fewer than ``need``."""
    segs = campaign.find_segments(kind)
    if len(segs) < need:
        raise DataError(
            campaign.source, "segments",
            f"{proc.qualified_id()} needs at least {need} segments of kind \"{kind}\" ({what}); "
            f"found {len(segs)}",
            hint=f"`metro plan --standard gbt45570 --item {proc.item}` lists them",
        )
    return segs


@attrs.frozen
class Quantization:
    """How the static record's samples are quantized.

    ``q`` is the rounding step of a rate sample in °/h (0 for pulse output, whose counts carry
    their remainder: its quantization is white angle noise, the α2 term of D.45, or a sawtooth
    the D.45 fit's χ² detects); ``s`` the measured standard deviation of one sample in °/h;
    ``dithered`` whether the noise dithers the rounding (s ≥ q)."""

    q: float
    s: float
    source: str

    @property
    def dithered(self) -> bool:
        return self.q <= 0 or self.s >= self.q


def output_quantum(campaign: Campaign, conv: RateConversion, raw: np.ndarray) -> tuple[float, str]:
    """The rounding step of the output in raw units and where it comes from: the device's
    ``resolution`` if it states one (LSB or the rate unit), else read from the data — the
    greatest step all distinct values are whole multiples of (integers: 1) — else 0."""
    dev = campaign.device
    if "resolution" in dev.properties:
        res = dev.properties["resolution"]
        q = parse_quantity(res, file=campaign.source, field="device.resolution")
        if q.check("[digital_count]"):
            return float(q.to("LSB").magnitude), msg("device resolution {res}", res=res)
        if q.is_compatible_with("deg/h") and conv.magnitude:
            return float(q.to("deg/h").magnitude) / conv.magnitude, msg("device resolution {res}",
                                                                        res=res)
        raise DataError(campaign.source, "device.resolution",
                        f"{res!r} is not a resolution of a {conv.output_kind} output (LSB or a "
                        f"rate such as °/h)")
    sample = np.asarray(raw[: 200_000], dtype=np.float64)
    vals = np.unique(sample)
    if conv.output_kind == "digital" and np.all(vals == np.round(vals)):
        return 1.0, msg("the data (whole LSB)")
    if vals.size < 2:
        return 0.0, msg("the data (constant output)")
    if np.all(vals == np.round(vals)):
        step = float(np.min(np.diff(vals)))
        return (1.0 if step >= 1 else 0.0), msg("the data (whole numbers)")
    step = float(np.min(np.diff(vals)))
    if step > 1e-9 * float(vals[-1] - vals[0]):
        ratio = (vals - vals[0]) / step
        if np.all(np.abs(ratio - np.round(ratio)) < 1e-6 * np.maximum(1.0, np.abs(ratio))):
            return step, msg("the data (every value a whole number of this step)")
    return 0.0, msg("the data (no common step)")


def quantization_of(campaign: Campaign, conv: RateConversion, raw: np.ndarray) -> Quantization:
    """:class:`Quantization` of a static record (rate samples rounded; pulse counts: q = 0)."""
    s = float(np.std(raw, ddof=1)) * abs(conv.magnitude) if raw.size > 1 else 0.0
    if conv.output_kind == "pulse":
        return Quantization(0.0, s, msg("pulse counts (remainder carried)"))
    q_raw, source = output_quantum(campaign, conv, raw)
    return Quantization(q_raw * abs(conv.magnitude), s, source)


def raw_unit(conv: RateConversion) -> str:
    """The unit of the raw samples of an output of this kind."""
    return {"digital": "LSB", "pulse": "P"}.get(conv.output_kind, "deg/h")


def quantization_rows_mean(campaign: Campaign, conv: RateConversion, raw: np.ndarray,
                           what: str) -> list[BudgetRow]:
    """The quantization row of a mean of the output (D.5.1, and through it D.5.3–D.5.5).

    * pulse counts carry their remainder: the mean count is off by at most the readout error at
      the two ends of the record, ±1 P over n samples;
    * a rounded rate sample (LSB word, rate of finite resolution q): ±q/2 (the row of D.2.1,
      :func:`.common.resolution_row`) unless the noise dithers the rounding (s ≥ q), when
      the offset of the mean is bounded by :func:`metro.api.rounding_mean_bound`."""
    c = abs(conv.magnitude)
    if conv.output_kind == "pulse":
        return [resolution_row(campaign, c, "deg/h", what, q=1.0, raw_unit="P",
                               half_width=1.0 / raw.size,
                                note=msg("readout at the record's two ends: ±1 P over {n} samples",
                                         n=raw.size))]
    qz = quantization_of(campaign, conv, raw)
    if qz.q <= 0:
        return []
    if conv.output_kind == "rate":
        c = 1.0  # the row in °/h, whatever rate unit the samples came in
    q_raw = qz.q / c if c else 0.0
    if qz.dithered:
        hw = F.rounding_mean_bound(qz.q, F.rounding_sigma(qz.s, qz.q)) / c
        note = msg("noise s = {s:.3g} °/h ≥ q = {q:.3g} °/h dithers the rounding: offset of the "
                   "mean ≤ "
                   "Σ(q/πk)e^(−2π²k²σ²/q²) (step from {source})", s=qz.s, q=qz.q, source=qz.source)
    else:
        hw = q_raw / 2.0
        note = msg("noise s = {s:.3g} °/h < q = {q:.3g} °/h: the rounding does not average out, "
                   "±q/2 on the mean (step from {source})", s=qz.s, q=qz.q, source=qz.source)
    return [resolution_row(campaign, c, "deg/h", what, q=q_raw, raw_unit=raw_unit(conv),
                           half_width=hw, note=note)]


def quantization_rows_std(campaign: Campaign, conv: RateConversion, raw: np.ndarray,
                          factor: int) -> list[BudgetRow]:
    """The quantization row of a standard deviation of means of ``factor`` rounded rate samples
    (D.5.2): |Δstd| ≤ std of the means' rounding errors — q/√(12·factor) when the noise dithers
    the rounding (independent errors of variance q²/12), else up to q/2.  Pulse counts: none
    (the carried remainder enters as white angle noise, part of what D.41 measures)."""
    if conv.output_kind == "pulse":
        return []
    qz = quantization_of(campaign, conv, raw)
    c = abs(conv.magnitude)
    if qz.q <= 0 or not c:
        return []
    if conv.output_kind == "rate":
        c = 1.0
    q_raw = qz.q / c
    hw = q_raw / math.sqrt(12.0 * factor) if qz.dithered else q_raw / 2.0
    note = (msg("dithered by the noise: rounding errors independent, q/√(12·n) on each mean")
            if qz.dithered else
            msg("noise s = {s:.3g} °/h < q = {q:.3g} °/h: each mean's rounding error up to ±q/2",
                s=qz.s, q=qz.q))
    return [resolution_row(campaign, c, "deg/h", msg("the D.41 means of {n} samples", n=factor),
                           q=q_raw,
                            raw_unit=raw_unit(conv), half_width=hw, note=note)]


def mean_rate(seg: Segment, campaign: Campaign, batches: int) -> dict[str, Any]:
    """Mean indicated rate of a segment (°/h, the first term of D.40) and its batch-means u."""
    series, conv, raw = batch_record(seg, campaign, batches)
    sd, nb = allan.block_std(raw, raw.size // batches)
    q_rows = quantization_rows_mean(campaign, conv, raw, "the mean")
    return {"rate": float(np.mean(raw)) * conv.magnitude, "u": sd * conv.magnitude / math.sqrt(nb),
            "nu": nb - 1, "conv": conv,
            "u_q": float(q_rows[0].contribution.to("deg/h").magnitude) if q_rows else 0.0}

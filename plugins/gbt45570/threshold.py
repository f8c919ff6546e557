"""GB/T 45570—2025 D.4 threshold (阈值) by tilting the input axis against the earth rate.

The tilt table's face is first tilted south by the latitude, which puts the IRA in the
equatorial plane (Ψ = 90°, no earth-rate input); the reference output N̄_0 is recorded there.
Tilting further changes Ψ_i, the angle between the IRA and the earth's axis, and the gyro sees
Ω_e·cos Ψ_i.  Data: segments of kind ``tilt`` with condition ``psi`` (Ψ_i, an angle; the
reference has ``psi = "90 deg"``) and an ``output`` column, τ = 1 s, n = 600 (D.4.2 d), e)).
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from typing import Any

import numpy as np
from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement,
                       Metric, Option, Outcome, PlotSpec, Result, RunContext, Segment,
                       SegmentRequirement, Step, TableSpec, UncertaintyBudget, allan, hint, join,
                       msg, parse_quantity)

from . import env_formulas as E
from .common import COVERAGE, STANDARD, GbtItem, opts_text, scale_factor_row
from .formulas import EARTH_RATE_DEG_PER_H
from .static_bias import batch_record, quantization_of

TILT = SegmentRequirement(
    "tilt",
                          "IRA at the angle Ψ_i to the earth's axis on the tilt table; Ψ = 90° "
                          "(tilted south by the "
    "latitude) is the reference N̄_0 (D.4.2 b)–e))",
    conditions={"psi": "deg"}, columns={"output": OUTPUT_UNITS}, min_count=2,
)


def psi_for_input(input_deg_h: float) -> float:
    """Ψ_i (°) at which the IRA sees ``input_deg_h`` of the earth rate (D.37's Ω_e·cos Ψ_i)."""
    if not 0 <= input_deg_h <= EARTH_RATE_DEG_PER_H:
        raise ValueError(f"an input of {input_deg_h:g} °/h is outside 0 … 15.041 °/h")
    return math.degrees(math.acos(input_deg_h / EARTH_RATE_DEG_PER_H))


def _psi(seg: Segment) -> float:
    return float(seg.condition("psi", "deg").to("deg").magnitude)


class ThresholdD4(GbtItem):
    """GB/T 45570—2025 D.4 阈值 (threshold), eqs. (D.37)–(D.39).

    At each tilt position N_i = K·Ω_e cos Ψ_i·τ (D.37) is the expected output and N̄*_i the
    mean measured one (D.38); the threshold is the smallest Ω_e cos Ψ_i for which
    |(N̄*_i − N̄_0)/N_i| ≥ 50 % (D.39).  For LSB or rate output every term is taken in °/h.
    Budget: the response's noise (type A, batch means of N̄*_i and N̄_0, as an input-equivalent
    rate), the step of the tilt series (type B, uniform between the next smaller input and the
    threshold), the 50 % decision (type B, the whole distance to a neighbouring position when
    its ratio or the threshold's is within 2u of 50 %), the tilt table's position accuracy and the
    site latitude (type B, through
    Ω_e·sin Ψ), the scale factor (type B).
    """

    item = "D.4"
    title = "Threshold (阈值)"
    clause = "D.4"
    metrics = (Metric("threshold", "threshold", "Ω_i", "deg/h", "D.4.3", "D.37–D.39"),)
    requires = (TILT,)
    equipment = (
        EquipmentRequirement("tilt_table",
                             "two-axis tilt table, position accuracy of a few arcseconds (D.4.1 "
                             "a)); its property position_accuracy enters the budget"),
        EquipmentRequirement("counter", "gyro test system / counter"),
    )
    options = (
        Option("levels", "0.002, 0.004, 0.006, 0.008, 0.01, 0.012, 0.015, 0.02, 0.03, 0.05", None,
               "inputs Ω_e·cos Ψ_i of the tilt series in °/h, smallest first (the sequence's Ψ_i)"),
        Option("seconds", "600 s", "s", "record per position, τ = 1 s (D.4.2 d): n = 600)"),
        Option("batches", 10, None, "batch means per position for the type A uncertainty",
               minimum=2),
        Option("confidence", 0.95, None,
               "one-sided confidence with which a position's response must be resolved from noise "
               "and quantization to count (interpretations.md, \"D.4 — a response that counts\")",
               minimum=0.5, maximum=0.9999),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        n = parse_quantity(options.get("seconds", "600 s"), dimension="s")
        steps = [Step("tilt-ref", "tilt",
                      "tilt the table face south by the latitude (IRA in the equatorial plane, "
                      "Ψ = 90°); warm up 30 min; record N̄_0 (D.4.2 b)–d))", n, Q_(1, "s"),
                      {"psi": "90 deg"},
                      warmup=Q_(30, "min"))]
        for x in parse_levels(options.get("levels", self.options[0].default)):
            psi = psi_for_input(x)
            steps.append(Step(f"tilt-{x:g}", "tilt",
                              f"Ψ = {psi:.7f}° (input Ω_e·cos Ψ = {x:g} °/h); record "
                              "600 s; stop once D.39 holds (D.4.2 e), f))", n, Q_(1, "s"),
                              {"psi": f"{psi:.7f} deg"}))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        refs, tilted = _tilt_segments(campaign)
        batches = int(opts["batches"])
        ref = _mean_response(refs[0], campaign, batches)
        conv = ref["conv"]
        pulse = conv.output_kind == "pulse"
        rows_t, inputs, ratios, points = _responses(campaign, ref, tilted, batches)
        conf = float(opts["confidence"])
        # the family of positions at ``conf`` (Bonferroni): each position at 1 − (1 − conf)/L, so
        # noise passes no position below the threshold with more than 1 − conf probability
        conf_each = 1.0 - (1.0 - conf) / len(points)
        verdicts = [resolved(abs(x), r, p[2], ref, conf_each) for x, r, p in zip(inputs, ratios,
                                                                                 points)]
        for row, v in zip(rows_t, verdicts):
            row.append(v[0])
        raw_th, raw_i = E.threshold_d39(inputs, ratios)
        passing = [j for j, v in enumerate(verdicts) if v[0] == "resolved ≥ 50 %"]
        hidden = None
        if raw_th is None and not passing:
            j = int(np.argmax(np.abs(inputs)))
            if math.hypot(points[j][2]["uq"],
                          ref["uq"]) * math.sqrt(3.0) >= E.THRESHOLD_FRACTION * abs(inputs[j]):
                # the output's rounding is coarser than the response sought: not a data error, a
                # device whose threshold this series cannot measure
                hidden = j
        if raw_th is None and not passing and hidden is None:
            raise DataError(campaign.source, "segments",
                            f"the tilt series never reaches 50 % of the expected response (D.39): "
                            f"the largest input {abs(inputs[j]):.4g} °/h (segment "
                            f"{points[j][0].id}) gives {abs(ratios[j]) * 100:.1f} %, the best "
                            f"{max(abs(r) for r in ratios) * 100:.1f} %",
                            hint="continue the series to larger inputs (option levels)")
        warnings = []
        opposite = [abs(inputs[j]) for j, r in enumerate(ratios) if r <= -E.THRESHOLD_FRACTION]
        if opposite:
            warnings.append(msg("response opposite in sign to the input at {inputs} °/h: such a "
                                "position does not count (check the polarity)",
                                inputs=", ".join(f"{x:.4g}" for x in opposite)))
        i, th, bound, cand_row, not_reportable = _threshold_pick(inputs, ratios, verdicts, points,
                                                                 ref, conf,
                                                                 (raw_i, raw_th), hidden)
        seg, psi, m, Ni = points[i]
        budget = _threshold_budget(campaign, conv, inputs, ratios, points, ref, i, th, cand_row,
                                   bound)
        res = Result(self.metrics[0], Q_(th, "deg/h"), budget.combined, budget,
                     note=msg("Ψ_i = {psi:.6f}° (segment {seg}); N̄_0 from {ref}; each position "
                              "counts only when its response is resolved ({conf:.0%} confidence "
                              "over the {n} positions, {each:.4g} each)",
                              psi=psi, seg=seg.id, ref=refs[0].id, conf=conf, n=len(points),
                              each=conf_each),
                     earth_rate="not applicable",
                     reportable=not not_reportable, reason=join("; ",
                                                                not_reportable) if not_reportable
                     else "",
                     bound=bound)
        if not_reportable and not bound:  # a bound is issued as such, its reason beside it
            warnings.append(msg("the threshold is NOT REPORTABLE: {reason}", reason=join("; ",
                                                                                         not_reportable)))
        plot, tab = _threshold_figures(inputs, ratios, rows_t, pulse)
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot],
                       tables=[tab],
                       warnings=warnings, segments=[refs[0].id] + [p[0].id for p in points],
                       options=opts_text(opts))


def _tilt_segments(campaign: Campaign) -> tuple[list[Segment], list[Segment]]:
    """D.4's reference segments (Ψ = 90°) and its tilted positions; an error when either is
    missing."""
    segs = campaign.find_segments("tilt")
    refs = [s for s in segs if abs(_psi(s) - 90.0) < 1e-9]
    tilted = [s for s in segs if abs(_psi(s) - 90.0) >= 1e-9]
    if not refs:
        raise DataError(campaign.source, "segments",
                        "D.4 needs the reference position: a segment of kind "
                        "\"tilt\" with psi = \"90 deg\" (table tilted south by the latitude, D.4.2 "
                        "b), d)); "
                        f"found {len(segs)} tilt segment(s) and none at Ψ = 90°",
                        hint="`metro plan --standard gbt45570 --item D.4` lists the positions")
    if not tilted:
        raise DataError(campaign.source, "segments",
                        "D.4 needs tilt positions with Ψ_i ≠ 90° (D.4.2 e)); none found")
    return refs, tilted


def _responses(campaign: Campaign, ref: Mapping[str, Any], tilted: list[Segment],
               batches: int) -> tuple[list[list[str]], list[float], list[float], list[tuple]]:
    """Each tilt position's table row, input Ω_e·cos Ψ_i (D.37), D.39 ratio and (segment, Ψ_i, its
    mean response, N_i), smallest input first."""
    conv = ref["conv"]
    pulse = conv.output_kind == "pulse"
    tau = ref["tau"]
    K = float(conv.scale_factor.to("P/arcsec").magnitude) if pulse else None
    rows_t, inputs, ratios, points = [], [], [], []
    for s in sorted(tilted, key=lambda s: abs(math.cos(math.radians(_psi(s))))):
        m = _mean_response(s, campaign, batches)
        psi = _psi(s)
        if pulse:
            if abs(m["tau"] - tau) > 1e-9 * tau:
                raise DataError(s.file or f"segment {s.id}", "output",
                                f"sampling interval {m['tau']:g} s differs from the reference's "
                                f"{tau:g} s; D.39 compares pulses per interval")
            Ni = E.expected_counts_d37(K, psi, tau)
            ratio = E.response_ratio_d39(m["raw_mean"], ref["raw_mean"], Ni)
        else:
            Ni = E.tilt_input_d37(psi)
            ratio = E.response_ratio_d39(m["rate"], ref["rate"], Ni)
        x = E.tilt_input_d37(psi)
        inputs.append(x)
        ratios.append(ratio)
        points.append((s, psi, m, Ni))
        rows_t.append([s.id, f"{psi:.7f}", f"{x:.5f}", f"{Ni:.5g}",
                       f"{m['raw_mean'] if pulse else m['rate']:.5g}", f"{ratio * 100:.1f}"])
    return rows_t, inputs, ratios, points


def _threshold_pick(inputs: list[float], ratios: list[float], verdicts: list[tuple[str, str]],
                    points: list[tuple],
                    ref: Mapping[str, Any], conf: float, raw: tuple[Any, Any],
                    hidden: int | None) -> tuple[int, float, str, list[BudgetRow], list[str]]:
    """The position D.4 states as the threshold, its input, whether it is an upper bound, the row
    of the positions it may be, and why the result is not reportable (empty: it is)."""
    raw_i, raw_th = raw
    passing = [j for j, v in enumerate(verdicts) if v[0] == "resolved ≥ 50 %"]
    not_reportable: list[str] = []
    cand_row: list[BudgetRow] = []
    bound = ""
    if passing:
        hi = min(passing, key=lambda j: abs(inputs[j]))
        H = abs(inputs[hi])
        fails = [abs(inputs[j]) for j,
                 v in enumerate(verdicts) if v[0] == "resolved < 50 %" and abs(inputs[j]) < H]
        L = max(fails) if fails else 0.0
        # the positions the threshold may be: every one above the last resolved failure up to
        # the first resolved pass; D.39 (right sign) picks among them
        cands = sorted((j for j in range(len(inputs)) if L < abs(inputs[j]) <= H),
                       key=lambda j: abs(inputs[j]))
        i = next((j for j in cands if ratios[j] >= E.THRESHOLD_FRACTION), hi)
        th = abs(inputs[i])
        lo_c, hi_c = abs(inputs[cands[0]]), abs(inputs[cands[-1]])
        if len(cands) > 1 and not fails:
            not_reportable.append(
                msg("no position below {H:.4g} °/h is resolved from the noise and quantization at "
                    "{conf:.0%} confidence (at {x:.4g} °/h: {why}), so the threshold is stated as "
                    "at most {H:.4g} °/h{hint}",
                    H=H, conf=conf, x=abs(inputs[cands[0]]), why=verdicts[cands[0]][1],
                    hint=hint("; record longer at each position (option seconds) to resolve it")))
            # the first resolved pass bounds the threshold from above: ≤ H, judged as (−∞, H + U]
            # (interpretations.md, "D.4 — an upper bound when nothing below is resolved")
            i, th, bound = hi, H, "upper"
        elif len(cands) > 1:
            cand_row.append(BudgetRow.type_b(
                msg("positions not resolved from the noise: the threshold may be any of them"),
                                             "ΔΩ (unresolved)",
                Q_(max(th - lo_c, hi_c - th), "deg/h"), distribution="uniform",
                note=msg("{n} positions {lo:.4g} … {hi:.4g} °/h between the last resolved failure "
                         "({L:.4g} °/h) "
                         "and the first resolved pass", n=len(cands), lo=lo_c, hi=hi_c, L=L)))
    elif hidden is not None:
        i, th = hidden, abs(inputs[hidden])
        not_reportable.append(
            msg("no position reaches 50 % (D.39), and the output's quantization (up to ±{q:.3g} "
                "°/h on a response) is as large as the inputs (at most {th:.4g} °/h): the "
                "threshold cannot be measured with this output; shown is the largest input",
                q=math.hypot(points[i][2]['uq'], ref['uq']) * math.sqrt(3.0), th=th))
    else:
        i, th = raw_i, raw_th
        not_reportable.append(
            msg("no position's response is resolved at ≥ 50 % with the right sign at {conf:.0%} "
                "confidence "
                "(D.39's |ratio| alone first reaches 50 % at {th:.4g} °/h: {why})", conf=conf,
                th=th,
                why=verdicts[i][1]))
    return i, th, bound, cand_row, not_reportable


def _threshold_budget(campaign: Campaign, conv: Any, inputs: list[float], ratios: list[float],
                      points: list[tuple], ref: Mapping[str, Any], i: int, th: float,
                      cand_row: list[BudgetRow],
                      bound: str) -> UncertaintyBudget:
    """The threshold's budget at position ``i`` (input ``th``)."""
    seg, psi, m, Ni = points[i]
    smaller = [abs(x) for x in inputs if abs(x) < th]
    below = max(smaller) if smaller else 0.0
    uA = math.hypot(m["u"], ref["u"])
    nu = uA**4 / (m["u"] ** 4 / m["nu"] + ref["u"] ** 4 / ref["nu"]) if uA > 0 else math.inf
    rows = [BudgetRow.type_a(msg("noise of the response N̄*_i − N̄_0 (batch means), as an input "
                                 "rate"),
                             "√(u²(N̄*)+u²(N̄₀))", Q_(uA, "deg/h"), nu,
                             note=msg("ratio {r:.1f} % against 50 %", r=ratios[i] * 100)),
            BudgetRow.type_b(msg("quantization of N̄*_i and N̄_0 (one count, or the rounding step, "
                                 "per mean)"), "u_q",
                             Q_(math.hypot(m["uq"], ref["uq"]), "deg/h"), distribution="normal",
                             k=1.0,
                             note=msg("the resolution a response must clear as well as the noise")),
            BudgetRow.type_b(msg("step of the tilt series: the threshold lies between the next "
                                 "smaller input and Ω_i"),
                             "(Ω_i − Ω_i−1)/2", Q_((th - below) / 2.0, "deg/h"),
                             distribution="uniform",
                             note=msg("next smaller input {x:.4g} °/h", x=below))]
    rows += cand_row
    rows += decision_row(inputs, ratios, [p[2]["u"] for p in points], ref["u"], i)
    if bound:
        # "threshold ≤ H" rests on H's resolved response (its noise is in that decision, at the
        # family's confidence); its U is that of the input realised at H: tilt, latitude, K
        rows = []
    c_psi = EARTH_RATE_DEG_PER_H * abs(math.sin(math.radians(psi)))
    table = campaign.equipment_for("tilt_table")
    if table is not None and "position_accuracy" in table.properties:
        acc = table.prop("position_accuracy", "arcsec", source=campaign.source)
        rows.append(
            BudgetRow.type_b(
                msg(
                    "tilt table position, Ψ_i and the reference ({equipment})",
                    equipment=table.describe(),
                ),
                "δΨ",
                acc.to("rad"),
                distribution="uniform",
                sensitivity=Q_(math.hypot(c_psi, EARTH_RATE_DEG_PER_H), "deg/h/rad"),
                note=msg("∂(Ω_e cos Ψ)/∂Ψ = −Ω_e sin Ψ at Ψ_i and at Ψ = 90°"),
            )
        )
    lat_u = campaign.site.get("latitude_uncertainty")
    if lat_u is not None:
        lu = parse_quantity(lat_u, dimension="deg", file=campaign.source,
                            field="site.latitude_uncertainty")
        rows.append(BudgetRow.type_b(msg("site latitude (sets the reference tilt)"), "u(θ)",
                                     lu.to("rad"),
                                     distribution="uniform", sensitivity=Q_(c_psi, "deg/h/rad"),
                                     note=msg("a latitude error tilts every position by the same "
                                              "angle")))
    rows += scale_factor_row(conv, th, "deg/h")
    return UncertaintyBudget("Ω_i", "deg/h", rows, coverage=COVERAGE)


def _threshold_figures(inputs: list[float], ratios: list[float], rows_t: list[list[str]],
                       pulse: bool) -> tuple[PlotSpec, TableSpec]:
    """D.4's plot of the D.39 ratios and its table of the tilt positions."""
    order = np.argsort(np.abs(inputs))
    plot = PlotSpec("threshold_ratio", msg("Response against the expected one (D.39)"),
                    "Ω_e cos Ψ_i (°/h)",
                    "|(N̄* − N̄₀)/N_i| (%)",
                    [{"label": "D.39 ratio", "x": [abs(inputs[k]) for k in order],
                      "y": [abs(ratios[k]) * 100 for k in order], "style": "o-"},
                     {"label": "50 %", "x": [abs(inputs[k]) for k in order[[0, -1]]], "y": [50, 50],
                      "style": "--"}],
                    logx=True)
    tab = TableSpec("tilt_positions", msg("Tilt positions (D.37–D.39)"),
                    [msg("segment"), "Ψ_i (°)", "Ω_e cos Ψ_i (°/h)",
                     "N_i (D.37)" + (" (P)" if pulse else " (°/h)"),
                     "N̄*_i (D.38)" + (" (P)" if pulse else " (°/h)"), msg("ratio (%)"),
                     msg("decision")], rows_t)
    return plot, tab


def decision_row(inputs: list[float], ratios: list[float], u_pos: list[float], u_ref: float,
                  i: int) -> list[BudgetRow]:
    """A type B row when the 50 % decision at the threshold position, or at the next smaller one,
    is within 2 standard uncertainties of the ratio: noise may have moved the threshold to that
    neighbour, so the row spans the whole distance to it (uniform)."""
    x = [abs(v) for v in inputs]
    th = x[i]

    def doubtful(j: int) -> bool:
        u_ratio = math.hypot(u_pos[j], u_ref) / x[j]
        return abs(abs(ratios[j]) - E.THRESHOLD_FRACTION) < 2.0 * u_ratio

    larger = [v for v in x if v > th]
    smaller = [(v, j) for j, v in enumerate(x) if v < th]
    half, why = 0.0, []
    if larger and doubtful(i):
        half = max(half, min(larger) - th)
        why.append(msg("Ω_i's ratio {r:.1f} % is within 2u of 50 %", r=abs(ratios[i]) * 100))
    if smaller:
        v, j = max(smaller)
        if doubtful(j):
            half = max(half, th - v)
            why.append(msg("the next smaller input's ratio {r:.1f} % is within 2u of 50 %",
                           r=abs(ratios[j]) * 100))
    if half == 0.0:
        return []
    return [BudgetRow.type_b(msg("50 % decision near the noise: the threshold may be the "
                                 "neighbouring position"),
                             "ΔΩ (neighbour)", Q_(half, "deg/h"), distribution="uniform",
                             note=join("; ", why))]


def parse_levels(text: Any) -> list[float]:
    """The tilt inputs Ω_e·cos Ψ_i (°/h) of option ``levels``."""
    out = []
    for part in str(text).split(","):
        part = part.strip()
        if not part:
            continue
        try:
            x = float(part)
        except ValueError as exc:
            raise DataError(None, "option levels", f"{part!r} is not a number of °/h") from exc
        if not 0.0 < x < EARTH_RATE_DEG_PER_H:
            # a tilt input Ω_e·cos Ψ (D.37) lies between 0 and the earth rate
            raise DataError(None, "option levels",
                            f"{part} °/h is not an input a tilt can give (0 … "
                            f"{EARTH_RATE_DEG_PER_H:.3f} °/h)")
        out.append(x)
    return out


def _mean_response(seg: Segment, campaign: Campaign, batches: int) -> dict[str, Any]:
    """Mean output of one tilt position (D.38) in raw units and °/h, with its batch-means u
    (°/h)."""
    series, conv, raw = batch_record(seg, campaign, batches)
    mean_raw = E.mean_counts_d38(raw)
    sd, nb = allan.block_std(raw, raw.size // batches)
    return {"raw_mean": mean_raw, "rate": mean_raw * conv.magnitude,
            "u": sd * conv.magnitude / math.sqrt(nb),
            "nu": nb - 1, "conv": conv, "tau": float(series.interval.to("s").magnitude),
            "uq": _quantization_u(campaign, conv, raw)}


def _quantization_u(campaign: Campaign, conv, raw: np.ndarray) -> float:
    """Standard uncertainty (°/h) of one position's mean from the output's quantization: pulse
    counts ±1 P over the record (the readout at its two ends), a rounded rate ±q/2 unless the
    noise dithers the rounding (:func:`.static_bias.quantization_rows_mean`'s rule); uniform."""
    from .formulas import rounding_mean_bound, rounding_sigma

    if conv.output_kind == "pulse":
        h = abs(conv.magnitude) / raw.size
    else:
        qz = quantization_of(campaign, conv, raw)
        if qz.q <= 0:
            return 0.0
        h = rounding_mean_bound(qz.q, rounding_sigma(qz.s, qz.q)) if qz.dithered else qz.q / 2.0
    return h / math.sqrt(3.0)


def resolved(x: float, ratio: float, m: Mapping[str, Any], ref: Mapping[str, Any],
             conf: float) -> tuple[str, str]:
    """Whether a position's response is resolved at ≥ 50 % of its input, resolved below it, or
    neither (interpretations.md, "D.4 — a response that counts").

    The response along the input, d = ratio·x (°/h, negative when opposite in sign), has the
    standard uncertainty u = √(u²(N̄*) + u²(N̄₀) + u_q²) (batch-means noise of both means and their
    quantization); with t the one-sided ``conf`` quantile of Student's t at the Welch–Satterthwaite
    ν, the position counts when d − t·u ≥ 50 %·x, and surely fails when d + t·u < 50 %·x."""
    from scipy.stats import t as student

    ua = math.hypot(m["u"], ref["u"])
    uq = math.hypot(m["uq"], ref["uq"])
    u = math.hypot(ua, uq)
    nu = u**4 / (m["u"] ** 4 / m["nu"] + ref["u"] ** 4 / ref["nu"]) if ua > 0 else math.inf
    tq = float(student.ppf(conf, nu)) if math.isfinite(nu) else float(student.ppf(conf, 1e9))
    d = ratio * x
    need = E.THRESHOLD_FRACTION * x
    text = msg("response {d:.3g} ± {u:.2g} °/h against 50 % = {need:.3g} °/h", d=d, u=tq * u,
               need=need)
    if d - tq * u >= need:
        return "resolved ≥ 50 %", text
    if d + tq * u < need:
        return "resolved < 50 %", text
    return "not resolved", text


PROCEDURES = (ThresholdD4,)

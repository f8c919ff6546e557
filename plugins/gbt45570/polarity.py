"""GB/T 45570—2025 6.2.6 极性 (polarity) and its requirement 5.2.9 (the polarity shall be positive).

6.2.6: with the fingers of the right hand along the turning and the thumb along the positive
input axis, turn the gyro counter-clockwise (a positive rate about +IA); if the output grows
against the gyro at rest, the polarity is positive.  metro measures it as the response ratio

    r = (ω̄_turn − ω̄_rest) / Ω

the change of the indicated rate (the output converted with the device's K, as D.40 does) over
the applied rate: r ≈ +1 for a positive gyro and ≈ −1 for a reversed one, so the polarity is the
sign of r and its uncertainty is that of r.  Segments: kind ``polarity``, one at rest (condition
``rate = "0 deg/s"``) and one turning (a non-zero signed ``rate``), both IRA up; column
``output``.  A turn that does not move the output beyond 5 u(r) is an error, not a guess.
"""

from __future__ import annotations

from collections.abc import Mapping
from typing import Any

from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement,
                       Metric, Option, Outcome, Result, RunContext, SegmentRequirement,
                       Step, UncertaintyBudget, msg)

from .common import (COUNTER, COVERAGE, STANDARD, GbtItem, opts_text, scale_factor_row,
                     sequence_options)
from .rate_data import rate_row
from .static_bias import mean_rate

#: |r| must exceed this many standard uncertainties for the sign to be read
DECISIVE = 5.0


def response_ratio(rest_deg_h: float, turn_deg_h: float, rate_deg_s: float) -> float:
    """r = (ω̄_turn − ω̄_rest)/Ω (GB/T 45570 6.2.6 as a number): rates in °/h, Ω in °/s."""
    if rate_deg_s == 0:
        raise ValueError("the turning rate Ω must not be zero")
    return (turn_deg_h - rest_deg_h) / (rate_deg_s * 3600.0)


class Polarity626(GbtItem):
    """GB/T 45570—2025 6.2.6 极性 (polarity), judged against 5.2.9 (positive): the response ratio
    r = (ω̄_turn − ω̄_rest)/Ω and the polarity sign(r).  Budget of r: the two means (A, batch means
    so that correlated noise is not understated), the device's K used to convert the output (B)
    and the table's rate (B)."""

    item = "6.2.6"
    title = "Polarity (极性)"
    clause = "6.2.6"
    metrics = (
        Metric("polarity_ratio", "response ratio (output change over applied rate)", "r", "",
               "6.2.6", ""),
        Metric("polarity", "polarity (+1 positive, −1 negative; 5.2.9 asks +1)", "P_ol", "",
               "6.2.6", ""),
    )
    requires = (SegmentRequirement("polarity",
                                   "the output at rest and turning at a positive rate about +IA, "
                                   "IRA up",
                                   conditions={"rate": "deg/s", "orientation": ""},
                                   columns={"output": OUTPUT_UNITS}, min_count=2),)
    equipment = (EquipmentRequirement("rate_table",
                                      "rate table turning the gyro about its IRA; its rate "
                                      "accuracy enters the budget"), COUNTER)
    options = (Option("rate", "10 deg/s", "deg/s",
                      "the positive (counter-clockwise about +IA) turning rate"),
               Option("duration", "20 s", "s", "record length at rest and turning"),
               Option("interval", "0.1 s", "s", "sampling interval"),
               Option("batches", 10, None, "batch means for the type A uncertainty of each mean",
                      minimum=2))

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        rate = opts["rate"].to("deg/s")
        return [
            Step("polarity-rest", "polarity",
                 "gyro at rest on the table, IRA up along the table axis (6.2.6)",
                 opts["duration"].to("s"), opts["interval"].to("s"), {"rate": "0 deg/s",
                                                                      "orientation": "IRA up"}),
            Step("polarity-turn", "polarity",
                 f"table turning counter-clockwise about +IA at {rate:~P} (6.2.6)",
                 opts["duration"].to("s"), opts["interval"].to("s"),
                 {"rate": f"{rate.magnitude:g} deg/s", "orientation": "IRA up"}),
        ]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = campaign.find_segments("polarity")
        rest = [s for s in segs if float(s.condition("rate", "deg/s").to("deg/s").magnitude) == 0.0]
        turn = [s for s in segs if float(s.condition("rate", "deg/s").to("deg/s").magnitude) != 0.0]
        if not rest or not turn:
            missing = "at rest (rate = \"0 deg/s\")" if not rest else "turning (a non-zero rate)"
            raise DataError(campaign.source, "segments",
                            f"6.2.6 compares the output at rest with the output "
                            f"turning; no segment of kind \"polarity\" {missing}",
                            hint="`metro plan --standard gbt45570 --item 6.2.6` shows what to "
                                 "measure")
        r0, r1 = rest[0], turn[0]
        omega = float(r1.condition("rate", "deg/s").to("deg/s").magnitude)
        batches = int(opts["batches"])
        m0, m1 = mean_rate(r0, campaign, batches), mean_rate(r1, campaign, batches)
        r = response_ratio(m0["rate"], m1["rate"], omega)
        scale = 1.0 / (abs(omega) * 3600.0)
        rows = [
            BudgetRow.type_a(msg("mean indicated rate at rest (batch means)"), "u(ω̄_rest)",
                             Q_(m0["u"], "deg/h"),
                             m0["nu"], sensitivity=Q_(scale, "h/deg")),
            BudgetRow.type_a(msg("mean indicated rate turning (batch means)"), "u(ω̄_turn)",
                             Q_(m1["u"], "deg/h"),
                             m1["nu"], sensitivity=Q_(scale, "h/deg")),
        ]
        rows += scale_factor_row(m1["conv"], r, "")
        rows += rate_row(campaign, "at the polarity rate", r, "", "r ∝ 1/Ω", rate=abs(omega))
        budget = UncertaintyBudget("r", "", rows, coverage=COVERAGE)
        u = float(budget.combined.to("").magnitude)
        where = f"segments {r0.id}, {r1.id}"
        if abs(r) <= DECISIVE * u:
            raise DataError(r1.file or f"segment {r1.id}", "output",
                            f"turning at {omega:g} °/s changed the indicated rate by "
                            f"{m1['rate'] - m0['rate']:.4g} °/h, "
                            f"within {DECISIVE:g} standard uncertainties of no change ({where}): "
                            f"the polarity "
                            "cannot be read",
                            hint="turn faster (option rate) or record longer (option duration)")
        sign = 1 if r > 0 else -1
        res_r = Result(self.metrics[0], Q_(r, ""), budget.combined, budget,
                       note=msg("Ω = {omega:g} °/s; ω̄_rest = {rest:.5g} °/h, ω̄_turn = {turn:.5g} "
                                "°/h", omega=omega,
                                rest=m0['rate'], turn=m1['rate']), earth_rate="removed")
        res_p = Result(self.metrics[1], Q_(float(sign), ""),
                       note=msg("{words}: the output {how} while the gyro turns {dir} about +IA; "
                                "|r|/u(r) = {ratio:.0f}",
                                words=msg("positive") if sign > 0 else msg("NEGATIVE"),
                                how=msg("grows") if r * omega > 0 else msg("falls"),
                                dir=msg("counter-clockwise") if omega > 0 else msg("clockwise"),
                                ratio=abs(r) / u),
                       earth_rate="not applicable")
        warnings = [] if sign > 0 else [msg("the polarity is negative; GB/T 45570 5.2.9 requires a "
                                            "positive polarity")]
        return Outcome(STANDARD, self.item, self.title, self.clause, [res_r, res_p],
                       segments=[r0.id, r1.id],
                       warnings=warnings, options=opts_text(opts))


PROCEDURES = (Polarity626,)

__all__ = ["PROCEDURES", "Polarity626", "response_ratio", "DECISIVE"]

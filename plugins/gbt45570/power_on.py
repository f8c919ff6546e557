"""GB/T 45570—2025 6.2.7.7 set-up time and 6.2.7.8 power consumption."""

from __future__ import annotations

import math
from typing import Any, Mapping

import numpy as np
from metro.api import (OUTPUT_UNITS, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement,
                       Metric, Option, Outcome, PlotSpec, Result, RunContext,
                       SegmentRequirement, Step, TableSpec, UncertaintyBudget, allan, gyro_output,
                       hint, msg, parse_quantity)

from . import env_formulas as E
from .common import (COUNTER, COVERAGE, STANDARD, GbtItem, check_finite, need_segments,
                     opts_text, sequence_options, timebase_row)
from .static_bias import output_quantum


class SetupTime6277(GbtItem):
    """GB/T 45570—2025 6.2.7.7 准备时间 (set-up time): the time from switch-on until the gyro
    reaches the required performance, read as the instant the window mean of the output comes
    within ±``tolerance`` of the settled bias (the mean of the last ``settled`` of the record);
    where noise takes it in and out of the band, the midpoint of the first entry and the final
    one (eq. in :func:`.env_formulas.setup_time_6277`; interpretations.md).  Budget: the crossing's
    noise
    (A: σ of a window mean over the output's slope there), the re-crossings of the band between
    the first entry and the final one (B: uniform over that span), the sampling of the record (B:
    uniform
    ±τ), the timer or the counter's time base (B).
    """

    item = "6.2.7.7"
    title = "Set-up time (准备时间)"
    clause = "6.2.7.7"
    metrics = (Metric("setup_time", "set-up time", "t_s", "s", "6.2.7.7", ""),)
    requires = (SegmentRequirement("power-on", "output recorded from the switch-on, IRA up",
                                   conditions={"orientation": ""},
                                   columns={"output": OUTPUT_UNITS}),)
    equipment = (EquipmentRequirement("timer",
                                      "timer (6.2.7.7); its calibration enters the budget, "
                                      "otherwise the counter's time base"), COUNTER)
    options = (
        Option("tolerance", "5 deg/h", "deg/h",
               "the required performance: band around the settled bias"),
        Option("window", "1 s", "s", "averaging window of the output"),
        Option("settled", "60 s", "s", "the last part of the record that gives the settled bias"),
        Option("record", "120 s", "s", "record length from the switch-on"),
        Option("interval", "0.1 s", "s", "sampling interval"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        return [Step("power-on", "power-on",
                     "gyro at rest, IRA up, unpowered; switch on and record from that instant "
                     f"for {opts['record']:~P} at {opts['interval']:~P} (6.2.7.7)",
                     opts["record"].to("s"),
                     opts["interval"].to("s"), {"orientation": "IRA up"})]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        seg = need_segments(campaign, "power-on", "6.2.7.7 needs a segment of kind \"power-on\": "
                            "the output recorded from the switch-on; none found", self.item)[0]
        series, conv = gyro_output(seg, campaign.device, source=campaign.source)
        raw = np.asarray(series.data.magnitude, dtype=float)
        check_finite(raw, seg)
        tau = float(series.interval.to("s").magnitude)
        y = raw * conv.magnitude
        w = max(1, int(round(float(opts["window"].to("s").magnitude) / tau)))
        n_set = int(round(float(opts["settled"].to("s").magnitude) / tau))
        tol = float(opts["tolerance"].to("deg/h").magnitude)
        start = y.size - n_set
        if start < 2 * w or n_set < 2 * w:
            raise DataError(seg.file or f"segment {seg.id}", "output",
                            f"a record of {y.size} samples at {tau:g} s is too short for the "
                            f"settled part "
                            f"({opts['settled']:~P}) and windows of {opts['window']:~P} before it")
        # what a window mean can resolve: one pulse over the window (a pulse count carries its
        # remainder), or one step of a rounded output (it does not average out undithered)
        if conv.output_kind == "pulse":
            res = abs(conv.magnitude) / w
        else:
            res = output_quantum(campaign, conv, raw)[0] * abs(conv.magnitude)
        reason, w_used = "", w
        if res > tol / 2.0:
            # the band cannot be told from the output's steps at this window: widen it until one
            # step is within half the band, evaluate for information, and say so (not reportable)
            w_used = w * int(math.ceil(res / (tol / 2.0)))
            reason = msg("over the {w:g} s window the output resolves only {res:.3g} °/h (one "
                         "{what}), coarser than half the band ±{tol:g} °/h: the instant the gyro "
                         "enters the band cannot be read; the value shown is from a {used:g} s "
                         "window — use a finer output or agree a longer "
                         "window{hint}", hint=hint(" (option window)"),
                         w=w * tau, res=res,
                         what=msg("pulse") if conv.output_kind == "pulse" else msg("output step"),
                         tol=tol, used=w_used * tau)
            if start < 2 * w_used:
                raise DataError(seg.file or f"segment {seg.id}", "output",
                                f"{reason}; the record is too short for it before the settled part",
                                hint="record longer (option record)")
            w = w_used
        tail = y[start: start + (n_set // w) * w].reshape(-1, w).mean(axis=1)
        s_w = float(np.std(tail, ddof=1)) if tail.size > 1 else 0.0
        try:
            st = E.setup_time_excursions_6277(y, tau, w, start, tol, s_w)
        except ValueError as exc:
            raise DataError(seg.file or f"segment {seg.id}", "output", str(exc),
                            hint="record longer, or check the option tolerance against the product "
                                 "spec") from exc
        ts, settled = st["t_s"], st["settled"]
        mm = E.moving_mean(y[:start], w)
        rows = _setup_rows(campaign, mm, tau, w, st, s_w, res, tail.size)
        budget = UncertaintyBudget("t_s", "s", rows, coverage=COVERAGE)
        result = Result(self.metrics[0], Q_(ts, "s"), budget.combined, budget,
                        note=msg("settled bias {b:.4g} °/h, band ±{tol:g} °/h, window {w:g} s",
                                 b=settled, tol=tol, w=w * tau),
                        earth_rate="not applicable", reportable=not reason, reason=reason)
        plot = _setup_plot(mm, tau, w, settled, tol, ts)
        return Outcome(STANDARD, self.item, self.title, self.clause, [result], plots=[plot],
                       segments=[seg.id],
                       options=opts_text(opts),
                       warnings=[f"t_s is NOT REPORTABLE: {reason}"] if reason else [])


def _setup_rows(campaign: Campaign, mm: np.ndarray, tau: float, w: int, st: Mapping[str, Any],
                s_w: float,
                res: float, n_tail: int) -> list[BudgetRow]:
    """The budget rows of the set-up time t_s (6.2.7.7): the window mean's noise and resolution at
    the crossing over the output's slope, the sampling, re-crossings, the choice of the last
    excursion, the timer."""
    P = st["probabilities"]
    ts = st["t_s"]
    u_noise2 = u_res2 = 0.0
    slopes = []
    for prob, jx in zip(P, st["exit_index"]):
        if jx <= 0:  # inside from the first window: no crossing
            continue
        lo, hi = max(jx - w, 0), min(jx + w, mm.size - 1)
        slope = abs(mm[hi] - mm[lo]) / ((hi - lo) * tau) if hi > lo else 0.0
        slope_noise = s_w * math.sqrt(2.0) / ((hi - lo) * tau) if hi > lo else math.inf
        eff = max(slope, 2.0 * slope_noise)
        slopes.append((prob, slope))
        if eff > 0:
            u_noise2 += prob * (s_w / eff) ** 2
            u_res2 += prob * (res / 2.0 / eff) ** 2
    rows = []
    if slopes:  # the output was outside the band at first: the crossing time carries noise
        slope = max(slopes)[1]
        rows.append(BudgetRow.type_a(msg("noise of the window mean at the crossing, over the "
                                         "output's slope"),
                                     "σ_w/|dȳ/dt|", Q_(math.sqrt(u_noise2), "s"), max(n_tail - 1,
                                                                                      1),
                                     note=msg("σ_w = {s:.3g} °/h, slope {slope:.3g} (°/h)/s", s=s_w,
                                              slope=slope)))
        if u_res2 > 0:
            # a quantized window mean (an undithered counter's sawtooth, a rounded word) is not in
            # σ_w
            rows.append(BudgetRow.type_b(msg("resolution of the window mean at the crossing (half "
                                             "a step), over the output's slope"), "δ_q/|dȳ/dt|",
                                         Q_(math.sqrt(3.0 * u_res2), "s"),
                                         distribution="uniform",
                                         note=msg("one step of the window mean: {res:.3g} °/h",
                                                  res=res)))
    rows.append(BudgetRow.type_b(msg("sampling: the window means step by τ, the crossing lies "
                                     "within ±τ of the reported instant"), "τ", Q_(tau, "s"),
                                 distribution="uniform"))
    if st["u_span"] > 0:  # noise took the output in and out of the band: the crossing is ambiguous
        rows.append(BudgetRow.type_b(msg("re-crossings of the band between the first entry and the "
                                         "final one"),
                                     "(t_out − t_in)/2", Q_(math.sqrt(3.0) * st["u_span"], "s"),
                                     distribution="uniform"))
    if st["u_selection"] > 0:  # which excursion beyond the band was the last real one
        rows.append(BudgetRow.type_b(
            msg("which excursion beyond the band is the last real one (spread of the candidates' "
                "exits)"),
            "u_sel", Q_(st["u_selection"], "s"), distribution="normal", k=1.0,
            note=msg("exits {exits} s with probabilities {probs}",
                     exits=", ".join(f"{e:.4g}" for e in st["exits"]),
                     probs=", ".join(f"{p:.2f}" for p in P))))
    timer = campaign.equipment_for("timer")
    if timer is not None and timer.calibration is not None:
        cal = timer.calibration
        sens = Q_(ts, "s") if cal.uncertainty.dimensionless else Q_(1.0, "")
        rows.append(BudgetRow.from_calibration(msg("timer ({equipment})",
                                                   equipment=timer.describe()), "u(t)", cal,
                                               sensitivity=sens))
    else:
        rows += timebase_row(campaign, ts, "s", "t_s")
    return rows


def _setup_plot(mm: np.ndarray, tau: float, w: int, settled: float, tol: float,
                ts: float) -> PlotSpec:
    """6.2.7.7's plot: the window mean after switch-on, the band and t_s."""
    t_mm = (np.arange(mm.size) + w) * tau
    step = max(1, mm.size // 400)
    plot = PlotSpec("setup", msg("Window mean of the output after switch-on (6.2.7.7)"), "t (s)",
                    "ω̄ (°/h)",
                    [{"label": msg("{w:g} s mean", w=w * tau), "x": t_mm[::step].tolist(),
                      "y": mm[::step].tolist(),
                      "style": "-"},
                     {"label": msg("band"), "x": [0.0, float(t_mm[-1])], "y": [settled + tol,
                                                                               settled + tol],
                      "style": "--"},
                     {"label": "", "x": [0.0, float(t_mm[-1])], "y": [settled - tol, settled - tol],
                      "style": "--"},
                     {"label": f"t_s = {ts:g} s", "x": [ts, ts], "y": [settled - tol,
                                                                       settled + tol],
                      "style": "-"}])
    return plot


class PowerConsumption6278(GbtItem):
    """GB/T 45570—2025 6.2.7.8 功耗 (power consumption): P = Σ_j mean(U_j·I_j) over the supplies.

    One ``power`` segment per supply with ``voltage`` and ``current`` columns.  Budget: each
    supply's batch-means scatter of U·I (A), the voltmeter's and the ammeter's calibration (B,
    relative or absolute; the same instrument on every supply, so its rows add linearly over the
    supplies and are entered once).
    """

    item = "6.2.7.8"
    title = "Power consumption (功耗)"
    clause = "6.2.7.8"
    metrics = (Metric("P", "power consumption", "P", "W", "6.2.7.8", ""),)
    requires = (SegmentRequirement("power", "input voltage and current of one supply, in operation",
                                   conditions={"supply": ""}, columns={"voltage": ("V",),
                                                                       "current": ("A",)}),)
    equipment = (EquipmentRequirement("voltmeter", "voltage measuring equipment (6.2.7.8)"),
                 EquipmentRequirement("ammeter", "current measuring equipment (6.2.7.8)"))
    options = (
        Option("supplies", "5 V, 15 V, -15 V", None, "nominal voltages of the gyro's supplies"),
        Option("record", "60 s", "s", "record per supply"),
        Option("batches", 10, None, "batch means per supply for the type A uncertainty", minimum=2),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        opts = sequence_options(self, options)
        steps = []
        for text in str(opts["supplies"]).split(","):
            V = parse_quantity(text.strip(), dimension="V", field="option supplies")
            v = float(V.to("V").magnitude)
            steps.append(Step(f"power-{v:+g}V", "power",
                              f"gyro in operation: record the {v:+g} V supply's voltage and "
                              f"current for {opts['record']:~P} at 1 s (6.2.7.8)",
                              opts["record"].to("s"), Q_(1, "s"),
                              {"supply": f"{v:g} V"}))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        segs = need_segments(campaign, "power", "6.2.7.8 needs one segment of kind \"power\" per "
                             "supply (columns voltage [V] and current [A]); none found")
        b = int(opts["batches"])
        Us, Is, rowsA, table = [], [], [], []
        for s in segs:
            s.condition("supply")
            u = np.asarray(s.series("voltage", "V").data.to("V").magnitude, dtype=float)
            i = np.asarray(s.series("current", "A").data.to("A").magnitude, dtype=float)
            for name, a in (("voltage", u), ("current", i)):
                if not np.all(np.isfinite(a)):
                    k = int(np.argmin(np.isfinite(a)))
                    raise DataError(s.file or f"segment {s.id}", name,
                                    f"sample {k + 1} is {a[k]!r}")
            if u.size != i.size:
                raise DataError(s.file or f"segment {s.id}", "current",
                                f"{i.size} current samples against {u.size} voltage samples")
            if u.size < 2 * b:
                raise DataError(s.file or f"segment {s.id}", "voltage",
                                f"{u.size} samples are too few for {b} batches")
            Us.append(u)
            Is.append(i)
            sd, nb = allan.block_std(u * i, u.size // b)
            rowsA.append(BudgetRow.type_a(msg("scatter of U·I, supply {supply} (batch means)",
                                              supply=s.conditions['supply']),
                                          "s_b/√b", Q_(sd / math.sqrt(nb), "W"), nb - 1))
        P, parts = E.power_6278(Us, Is)
        rows = list(rowsA)
        for role, sym in (("voltmeter", "u(U)"), ("ammeter", "u(I)")):
            eq = campaign.equipment_for(role)
            if eq is None or eq.calibration is None:
                continue
            cal = eq.calibration
            other = [abs(float(np.mean(x))) for x in (Is if role == "voltmeter" else Us)]
            if cal.uncertainty.dimensionless:
                sens = Q_(P, "W")
            else:
                sens = Q_(sum(other), "W") / Q_(1.0, "V" if role == "voltmeter" else "A")
            rows.append(BudgetRow.from_calibration(msg("{what} ({equipment})", what=role,
                                                       equipment=eq.describe()), sym, cal,
                                                   sensitivity=sens,
                                                   note=msg("same instrument on every supply: "
                                                            "contributions add linearly")))
        budget = UncertaintyBudget("P", "W", rows, coverage=COVERAGE)
        for s, u, i, p in zip(segs, Us, Is, parts):
            table.append([s.id, str(s.conditions["supply"]), f"{np.mean(u):.4f}",
                          f"{np.mean(i):.5f}", f"{p:.4f}"])
        tab = TableSpec("supplies", msg("Mean voltage, current and power per supply (6.2.7.8)"),
                        [msg("segment"), msg("supply"), "U (V)", "I (A)", "U·I (W)"], table)
        res = Result(self.metrics[0], Q_(P, "W"), budget.combined, budget, note=msg("{n} supplies",
                                                                                    n=len(segs)),
                     earth_rate="not applicable")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[tab],
                       segments=[s.id for s in segs], options=opts_text(opts))

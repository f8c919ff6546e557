"""GB/T 45570—2025 D.2 scale factor series by the rate method (digital output in LSB, °/s or Hz):
D.2.1 scale factor, D.2.2 nonlinearity, D.2.3 asymmetry, D.2.4 repeatability, D.2.5
temperature sensitivity, D.2.6 input-axis misalignment — and D.3 maximum input rate, which
works on the data of either method.

Data: one segment of kind ``rate-output`` per rate point and direction (condition ``rate``,
signed: + counter-clockwise), with an ``output`` column — in LSB, as a frequency in Hz (D.23
names it) or as a digital rate in °/s (any angular-rate unit) — sampled once the table is
steady (D.2.1.2 f), g)); two segments of kind ``rate-static`` (condition ``when`` = ``start`` /
``end``), the table at rest at the start and end of the test (D.2.1.2 h)).  D.2.4 adds the
condition ``run`` = 1 … 7 to both kinds, D.2.5 ``temperature``; D.2.1–D.2.3 and D.3 use the
segments that have neither.  D.2.6 uses segments of kind ``rate-mounting`` (conditions
``axis_up`` XRA/YRA, ``turn`` 0°/180° about IRA, signed ``rate``).
"""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (
    Q_,
    BudgetRow,
    Campaign,
    DataError,
    DeviceUnderTest,
    EquipmentRequirement,
    Metric,
    Option,
    Outcome,
    PlotSpec,
    Procedure,
    ProcedureError,
    Result,
    RunContext,
    Segment,
    SegmentRequirement,
    Step,
    TableSpec,
    UncertaintyBudget,
    fit_line,
    hint,
    join,
    msg,
    parse_quantity,
    std_sampling_u,
)

from . import formulas as F
from . import formulas_rate as F2
from .angle_method import (
    MOUNTINGS,
    REPEAT_RATE,
    _temperature_outcome,
    collect_rate_points,
    misalignment_metrics,
    misalignment_outcome,
    mounting_groups,
    mounting_steps,
    rate_points,
    room_index,
)
from .angle_method import (
    _sequence as _angle_sequence,
)
from .procedures import COVERAGE, STANDARD

LSB_PER_RATE = "LSB/(deg/s)"
#: the output kinds D.2 takes: a digital word in LSB (D.17–D.22), a frequency in Hz (D.23 names it)
#: or a digital rate in °/s (any angular-rate unit, converted to °/s); K is then in LSB/[(°)/s],
#: Hz/[(°)/s] or (°/s)/(°/s) (a ratio)
OUTPUT_UNITS = ("LSB", "Hz", "deg/s")

RATE_OUTPUT = SegmentRequirement(
    "rate-output", "output sampled at each rate point once the table is steady, both directions (D.2.1.2 f), g))",
    conditions={"rate": "deg/s"}, columns={"output": OUTPUT_UNITS}, min_count=22,
)
REST = SegmentRequirement("rate-static", "table at rest at the start and at the end of the test (D.2.1.2 h))",
                          conditions={"when": ""}, columns={"output": OUTPUT_UNITS}, min_count=2)


def per_rate(unit: str) -> str:
    """The unit of K for an output in ``unit`` (LSB, Hz or deg/s): output per °/s."""
    return "" if unit == "deg/s" else f"{unit}/(deg/s)"


def unit_text(unit: str) -> str:
    """``unit`` as the notes and tables print it."""
    return {"LSB": "LSB", "Hz": "Hz", "deg/s": "°/s", "": "(°/s)/(°/s)"}.get(unit, unit)


def k_text(unit: str) -> str:
    """K's unit for an output in ``unit``, as printed: LSB/(°/s), Hz/(°/s), (°/s)/(°/s)."""
    return "(°/s)/(°/s)" if unit == "deg/s" else f"{unit_text(unit)}/(°/s)"


def metric_in(metric: Metric, unit: str) -> Metric:
    """``metric`` declared in ``unit`` (K and F₀ follow the output's kind)."""
    return metric if metric.unit == unit else attrs.evolve(metric, unit=unit)
_EQUIPMENT = (
    EquipmentRequirement("rate_table", "rate table with rate output (D.2.1.1 a)); its rate accuracy enters the "
                         "budgets", required=True),
    EquipmentRequirement("counter", "gyro test system"),
)
_OPTIONS = (
    Option("max_rate", "400 °/s", "deg/s", "largest rate point (the device's maximum input rate)"),
    Option("duration", "100 s", "s", "record at each rate point and at rest (n samples × interval)"),
    Option("interval", "1 s", "s", "sampling interval (D.2.1.2 d))"),
    Option("min_points", 11, None, "fewest rate points accepted (D.2.1.2 e): not fewer than 11)"),
)

#: typical nonlinearity limits of tables A.1 (laser) and B.1 (fibre), by application, ×10⁻⁶
NONLINEARITY_LIMITS_PPM = {
    "laser": {"aerospace": 10.0, "aviation": 10.0, "marine": 5.0},
    "fibre": {"aerospace": 50.0, "aviation": 50.0, "marine": 10.0},
}
_TECHNOLOGY = {"laser": "laser", "ring laser": "laser", "rlg": "laser", "激光": "laser",
               "fibre": "fibre", "fiber": "fibre", "fog": "fibre", "光纤": "fibre"}
_APPLICATION = {"aerospace": "aerospace", "space": "aerospace", "航天": "aerospace",
                "aviation": "aviation", "aircraft": "aviation", "航空": "aviation",
                "marine": "marine", "ship": "marine", "naval": "marine", "船舶": "marine"}


def default_nonlinearity_limit(device: DeviceUnderTest, source: str | None = None) -> tuple[Any, str]:
    """The K_n limit D.3 judges against: the device specification's ``nonlinearity_limit`` if
    given, else the typical value of table A.1 (laser) or B.1 (fibre) for its application."""
    if "nonlinearity_limit" in device.properties:
        q = device.prop("nonlinearity_limit", "", source=source)
        return Q_(float(q.to("").magnitude), ""), msg("device specification (device.nonlinearity_limit)")
    tech = _TECHNOLOGY.get(str(device.technology).strip().lower())
    app = _APPLICATION.get(str(device.application).strip().lower())
    if tech is None or app is None:
        raise DataError(source, "device.technology/application",
                        f"no default nonlinearity limit for technology {device.technology!r}, application "
                        f"{device.application!r} (tables A.1/B.1 know laser/fibre × aerospace/aviation/marine)",
                        hint="give the option Kn_limit (e.g. \"10 ppm\") or device.nonlinearity_limit")
    table = "A.1" if tech == "laser" else "B.1"
    return Q_(NONLINEARITY_LIMITS_PPM[tech][app] * 1e-6, ""), msg("table {table} ({technology}, {application})",
                                                                   table=table, technology=tech, application=app)


def rate_sequence(options: Mapping[str, Any], extra: Mapping[str, Any] | None = None, prefix: str = "",
                  note: str = "") -> list[Step]:
    """D.2.1.2: at rest (start), each R5 rate point both ways, at rest (end)."""
    rmax = float(parse_quantity(options.get("max_rate", "400 °/s"), dimension="deg/s").to("deg/s").magnitude)
    dur = parse_quantity(options.get("duration", "100 s"), dimension="s")
    tau = parse_quantity(options.get("interval", "1 s"), dimension="s")
    extra = dict(extra or {})
    head = f"{note}: " if note else ""
    steps = [Step(f"{prefix}rest-start", "rate-static", head + "table at rest at the start; record n samples "
                  "(D.2.1.2 h))", dur, tau, {"when": "start"} | extra, warmup=Q_(30, "min"))]
    for r in rate_points(rmax):
        for sign, word in ((1, "counter-clockwise (+)"), (-1, "clockwise (−)")):
            steps.append(Step(f"{prefix}rate{sign * r:+g}", "rate-output",
                              head + f"table at {r:g} °/s {word}; once steady record n samples, stop "
                              "(D.2.1.2 f), g))", dur, tau, {"rate": f"{sign * r:g} deg/s"} | extra))
    steps.append(Step(f"{prefix}rest-end", "rate-static", head + "table at rest at the end; record n samples "
                      "(D.2.1.2 h))", dur, tau, {"when": "end"} | extra))
    return steps


@attrs.frozen
class RateData:
    """The D.17–D.19 reduction of one D.2.1 test (one group of segments)."""

    rates: np.ndarray  # Ω_ij, signed, °/s
    Fk: np.ndarray  # F_kj, in ``unit``
    uF: np.ndarray  # standard uncertainty of each F̄_j (its samples' scatter), in ``unit``
    n: np.ndarray  # samples behind each F̄_j
    Fr: float
    uFr: float
    segments: tuple[str, ...]
    unit: str = "LSB"  # the output's kind: LSB, Hz or deg/s

    @property
    def magnitudes(self) -> list[float]:
        return sorted({float(abs(r)) for r in self.rates})


def output_series(seg: Segment) -> tuple[np.ndarray, str]:
    """The ``output`` column in the kind D.2 takes (:data:`OUTPUT_UNITS`): LSB as recorded, a
    frequency in Hz, an angular rate in °/s; and that unit."""
    from metro.api import check_dimension

    data = seg.series("output", OUTPUT_UNITS).data
    for unit in OUTPUT_UNITS:  # metro's check: an angle is not a plain number (Hz is not °/s)
        try:
            check_dimension(Q_(1.0, data.units), unit)
        except DataError:
            continue
        return np.asarray(data.to(unit).magnitude, dtype=float), unit
    raise DataError(seg.file, "output", f"unit {data.units} is none of {', '.join(OUTPUT_UNITS)}")  # pragma: no cover


def _mean_output(seg: Segment, campaign: Campaign) -> tuple[float, float, int, str]:
    x, unit = output_series(seg)
    if x.size < 2 or not np.all(np.isfinite(x)):
        bad = "fewer than 2 samples" if x.size < 2 else f"sample {int(np.argmin(np.isfinite(x))) + 1} is not finite"
        raise DataError(seg.file or f"segment {seg.id}", "output", f"{bad}; D.17 needs a finite record")
    return F2.mean_output_d17(x), float(np.std(x, ddof=1) / math.sqrt(x.size)), int(x.size), unit


def _group_of(seg: Segment) -> tuple[str, str]:
    return str(seg.conditions.get("run", "")), str(seg.conditions.get("temperature", ""))


def collect_rate_data(proc: type[Procedure], campaign: Campaign, min_points: int, group: tuple[str, str] = ("", ""),
                      what: str = "") -> RateData:
    """Mean outputs (D.17), the rest output (D.18) and F_kj (D.19) of the segments of one group
    (``run``, ``temperature``; ("", "") = neither)."""
    where = f" {what}" if what else ""
    segs = [s for s in campaign.find_segments("rate-output") if _group_of(s) == group]
    rest = [s for s in campaign.find_segments("rate-static") if _group_of(s) == group]
    if not segs:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs segments of kind \"rate-output\"{where} (output at each rate "
                        "point, D.2.1.2 g)); none found",
                        hint=f"`metro plan --standard gbt45570 --item {proc.item}` lists them")
    when = {str(s.condition("when")).strip().lower(): s for s in rest}
    missing = [w for w in ("start", "end") if w not in when]
    if missing:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs the output with the table at rest at the start and the end "
                        f"(segments of kind \"rate-static\", when = start / end{where}, D.2.1.2 h)); missing: "
                        f"{', '.join(missing)}")
    (Fs, us, _, unit), (Fe, ue, _, unit_e) = _mean_output(when["start"], campaign), _mean_output(when["end"], campaign)
    units = {unit, unit_e}
    Fr = F2.rest_output_d18(Fs, Fe)
    uFr = 0.5 * math.hypot(us, ue)
    by_rate: dict[float, dict[int, tuple]] = {}
    for s in segs:
        rate = float(s.condition("rate", "deg/s").to("deg/s").magnitude)
        if rate == 0:
            raise DataError(campaign.source, f"segments.{s.id}.conditions.rate", "a rate point cannot be 0 °/s")
        d = 1 if rate > 0 else -1
        slot = by_rate.setdefault(round(abs(rate), 9), {})
        if d in slot:
            raise DataError(campaign.source, f"segments.{s.id}", f"two segments at {rate:+g} °/s{where}")
        mean = _mean_output(s, campaign)
        slot[d] = (s, rate) + mean[:3]
        units.add(mean[3])
    if len(units) > 1:
        raise DataError(campaign.source, "segments", f"{proc.qualified_id()}{where}: the outputs are of different "
                        f"kinds ({', '.join(sorted(units))}); one test records one output")
    rates, Fk, uF, n, ids = [], [], [], [], [s.id for s in rest]
    for mag, pair in sorted(by_rate.items()):
        if set(pair) != {1, -1}:
            only = next(iter(pair.values()))[0]
            missing_dir = "clockwise (−)" if 1 in pair else "counter-clockwise (+)"
            raise DataError(campaign.source, f"segments.{only.id}",
                            f"rate point {mag:g} °/s{where} has no {missing_dir} record; D.2.1.2 f) turns the table "
                            "both ways")
        for d in (1, -1):
            s, rate, Fj, u, m = pair[d]
            rates.append(rate)
            Fk.append(F2.rate_output_d19(Fj, Fr))
            uF.append(u)
            n.append(m)
            ids.append(s.id)
    if len(by_rate) < min_points:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs at least {min_points} rate points (D.2.1.2 e)){where}; "
                        f"found {len(by_rate)}", hint="or lower the option min_points if agreed with the user")
    return RateData(np.array(rates), np.array(Fk), np.array(uF), np.array(n), Fr, uFr, tuple(ids), unit)


def rate_band(campaign: Campaign, rate: float) -> tuple[float, float, str] | None:
    """The rate table's stated accuracy at |``rate``| (°/s) from its ``rate_band_i_upper``,
    ``rate_band_i_error`` (relative half-width of the mean rate) and ``rate_band_i_ripple``
    (relative standard deviation of the rate over one sample) properties, if it states them."""
    tab = campaign.equipment_for("rate_table")
    if tab is None:
        return None
    i = 1
    while f"rate_band_{i}_upper" in tab.properties:
        upper = float(tab.prop(f"rate_band_{i}_upper", "deg/s", source=campaign.source).to("deg/s").magnitude)
        if abs(rate) <= upper * (1 + 1e-12):
            err = tab.prop(f"rate_band_{i}_error", "", source=campaign.source)
            rip = tab.prop(f"rate_band_{i}_ripple", "", source=campaign.source)
            return float(err.to("").magnitude), float(rip.to("").magnitude), msg("{equipment}, band ≤ {upper:g} °/s", equipment=tab.describe(),
                                                                                  upper=upper)
        i += 1
    return None


def rate_table_rel(campaign: Campaign, rate: float | None = None) -> tuple[float, str] | None:
    """Relative standard uncertainty of the table's rate and its description: at a given rate the
    band's error (a half-width, uniform) when the table states bands, else (or with no rate) its
    calibration certificate's U/k."""
    tab = campaign.equipment_for("rate_table")
    if tab is None:
        return None
    if rate is not None:
        b = rate_band(campaign, rate)
        if b is not None:
            return b[0] / math.sqrt(3.0), msg("{band}: ±{e:.2g} (uniform)", band=b[2], e=b[0])
    cal = tab.calibration
    if cal is None or not cal.uncertainty.dimensionless:
        return None
    return float(cal.standard_uncertainty.to("").magnitude), join(", ", [tab.describe(), cal.certificate])


def _rate_row(campaign: Campaign, what: str, value: float, unit: str, note: str,
              rate: float | None = None) -> list[BudgetRow]:
    r = rate_table_rel(campaign, rate)
    if r is None:
        return []
    return [BudgetRow.type_b(msg("rate-table rate accuracy, {what} ({table})", what=what, table=r[1]), "u_rel(Ω)",
                             Q_(r[0], ""), distribution="normal", k=1.0, sensitivity=Q_(abs(value), unit), note=note)]


def _through_fit(rates: np.ndarray, u_rel: list[float], *, intercept: bool = False) -> float:
    """What independent relative rate errors u_rel[i] at the set points do to the D.21/D.22 fit:
    the relative standard uncertainty of the slope, δK/K = Σ c_K,i·Ω_i·δ_i, or (``intercept``)
    the intercept's per unit K, δF₀/K = Σ c_F0,i·Ω_i·δ_i."""
    ca, cb = F2.line_fit_sensitivities(rates)
    c = ca if intercept else cb
    return float(np.sqrt(np.sum((c * rates * np.asarray(u_rel)) ** 2)))


def _intercept_table_row(campaign: Campaign, rates: np.ndarray, K: float, unit: str = "LSB") -> list[BudgetRow]:
    """The table's error at each set point moves F₀ (D.22) by K·Σ c_F0,j·Ω_j·δ_j. A relative error
    common to all set points cancels (Σ c_F0,j·Ω_j = 0 for a least-squares intercept); a fixed error
    of its own at each set point (uniform within its band, else the calibration's U/k) does not.
    Independent set points: u(F₀) = |K|·√Σ(c_F0,j·Ω_j·u_rel,j)²."""
    per_point = [rate_table_rel(campaign, float(r)) for r in rates]
    if any(x is None for x in per_point):
        return []
    u = abs(K) * _through_fit(rates, [x[0] for x in per_point], intercept=True)
    table = campaign.equipment_for("rate_table")
    return [BudgetRow.type_b(msg("rate-table error at each set point, within its band, through D.22 ({table})",
                                 table=table.describe()),
                             "u(F₀)", Q_(u, unit), distribution="normal", k=1.0,
                             note=msg("a fixed error of its own at each Ω_ij, independent between set points; "
                                      "an error common to all cancels in the intercept"))]


def _stability_row(campaign: Campaign, data: RateData) -> list[BudgetRow]:
    """Run-to-run change of K from the table: its ripple (rate stability, 速率平稳度 D.2.1.1 a))
    averaged over the n samples of each rate point, through the D.21 fit (a fixed error at a set
    point repeats in every run and cancels in K_r); with no bands stated, the calibration's U/k
    bounds it."""
    bands = [rate_band(campaign, float(r)) for r in data.rates]
    if any(b is None for b in bands):
        return _rate_row(campaign, msg("run to run (no rate bands stated: its calibration bounds it)"), 1.0, "",
                         msg("bounds a table rate that differs between runs"))
    u = _through_fit(data.rates, [b[1] / math.sqrt(m) for b, m in zip(bands, data.n)])
    return [BudgetRow.type_b(msg("rate-table ripple averaged over each rate point, through D.21, run to run "
                                 "({equipment})", equipment=bands[0][2].fields["equipment"]), "u(δK/K)", Q_(u, ""),
                             distribution="normal", k=1.0,
                             note=msg("independent in each run; adds to the spread of the K_j"))]


def resolution(campaign: Campaign, unit: str = "LSB") -> float:
    """The output's resolution in ``unit``: the device's ``resolution`` if stated, else 1 LSB for
    an LSB output and 0 (none known) for a frequency or rate output."""
    if "resolution" in campaign.device.properties:
        return float(campaign.device.prop("resolution", unit, source=campaign.source).to(unit).magnitude)
    return 1.0 if unit == "LSB" else 0.0


def _out_resolution_row(campaign: Campaign, c_norm: float, unit: str, what: str, out: str) -> BudgetRow:
    """:func:`_resolution_row` for an output in ``out`` (LSB, Hz, deg/s)."""
    if out == "LSB":
        return _resolution_row(campaign, c_norm, unit, what)
    q = resolution(campaign, out)
    note = (msg("±half the stated resolution on each mean, independent") if q > 0 else
            msg("the device states no resolution of its {unit} output (device.resolution): none assumed",
                unit=unit_text(out)))
    return _resolution_row(campaign, c_norm, unit, what, q=q, raw_unit=out, note=note)


def _resolution_row(campaign: Campaign, c_norm: float, unit: str, what: str, *, q: float | None = None,
                    raw_unit: str = "LSB", half_width: float | None = None,
                    note: str = msg("±half an LSB on each mean, independent")) -> BudgetRow:
    """Rounding of the output word: each mean F̄ is off by up to ±resolution/2 when the noise is
    smaller than one LSB (it then does not average out); ``c_norm`` = √Σc² of the result's
    sensitivities to the means, independent errors assumed.  ``q`` (default: :func:`resolution`),
    its ``raw_unit`` and a smaller ``half_width`` (noise that dithers the rounding) serve the D.5
    items' rows on LSB and rate outputs."""
    q = resolution(campaign) if q is None else q
    hw = q / 2.0 if half_width is None else half_width
    return BudgetRow.type_b(msg("output resolution {q:.4g} {unit}, through {what}", q=q, unit=raw_unit, what=what), "δF",
                            Q_(hw, raw_unit),
                            distribution="uniform",
                            sensitivity=Q_(c_norm, f"({unit})/({raw_unit})" if unit else f"1/({raw_unit})"),
                            note=note)


@attrs.frozen
class ScaleFit:
    """K, F_0 of (D.21), (D.22) with their type A standard uncertainties propagated from the
    scatter of each F̄_j (interpretations.md, "D.2.1 — type A of the fit")."""

    K: float
    F0: float
    uK: float
    nuK: float
    uF0: float
    nuF0: float
    residual_sd: float
    dof: int


def fit_scale_factor(data: RateData, mask: np.ndarray | None = None) -> ScaleFit:
    """D.21/D.22 on the rate points (all, or those selected by ``mask``), cross-checked against
    metro's QR least squares."""
    w = data.rates if mask is None else data.rates[mask]
    f = data.Fk if mask is None else data.Fk[mask]
    u = data.uF if mask is None else data.uF[mask]
    n = data.n if mask is None else data.n[mask]
    K, F0 = F2.scale_factor_fit_d21_d22(w, f)
    qr = fit_line(w, f)
    if not math.isclose(K, float(qr.coef[1]), rel_tol=1e-9, abs_tol=1e-12 * max(1.0, abs(K))):
        raise ProcedureError(f"D.21 gives K = {K!r} but the QR least squares {float(qr.coef[1])!r}; ill-conditioned rates?")
    ca, cb = F2.line_fit_sensitivities(w)
    uK, nuK = F2.propagate(cb, u, n - 1)
    uF0, nuF0 = F2.propagate(ca, u, n - 1)
    return ScaleFit(K, F0, uK, nuK, uF0, nuF0, float(qr.residual_sd), qr.dof)


def _opts_text(opts) -> dict[str, str]:
    return {k: str(v) for k, v in opts.items()}


# --------------------------------------------------------------------------------------------
# D.2.1 scale factor, D.2.2 nonlinearity, D.2.3 asymmetry
# --------------------------------------------------------------------------------------------


class ScaleFactorD21(Procedure):
    """GB/T 45570—2025 D.2.1 标度因数 (scale factor), rate method, eqs. (D.17)–(D.22).

    F̄_j per rate point (D.17), the rest output F̄_r = (F̄_s + F̄_e)/2 (D.18) removed (D.19), and
    F_kj = K·Ω_ij + F_0 fitted by least squares over all M signed rates (D.20)–(D.22).
    Type A: the fit's standard error (ν = M − 2); type B: the rate table's rate accuracy (K ∝ 1/Ω).
    """

    standard = STANDARD
    item = "D.2.1"
    title = "Scale factor, rate method (标度因数 速率法)"
    clause = "D.2.1"
    metrics = (Metric("K", "scale factor", "K", LSB_PER_RATE, "D.2.1.3", "D.21"),
               Metric("F0", "fitted zero", "F₀", "LSB", "D.2.1.3", "D.22"))
    requires = (RATE_OUTPUT, REST)
    equipment = _EQUIPMENT
    options = _OPTIONS
    station = "simulated-digital"

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return rate_sequence(options)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        fit = fit_scale_factor(data)
        K, F0 = fit.K, fit.F0
        out, ku, ot = data.unit, per_rate(data.unit), unit_text(data.unit)
        rows = [BudgetRow.type_a(msg("mean outputs F̄_j through the D.21 fit"), "√Σ(c_j·u(F̄_j))²", Q_(fit.uK, ku),
                                 fit.nuK, note=msg("M = {m} rates; residual s = {s:.3g} {unit} (systematic "
                                                   "nonlinearity, D.2.2)", m=data.rates.size, s=fit.residual_sd,
                                                   unit=ot))]
        ca, cb = F2.line_fit_sensitivities(data.rates)
        rows.append(_out_resolution_row(campaign, float(np.linalg.norm(cb)), ku, "D.21", out))
        rows += _rate_row(campaign, msg("on every Ω_ij"), K, ku, "K ∝ 1/Ω")
        from .repeatability import scale_factor_rate_repeat_row

        rep_rows, rep_note = scale_factor_rate_repeat_row(campaign, K, ku, int(opts["min_points"]))
        rows += rep_rows
        bK = UncertaintyBudget("K", ku, rows, coverage=COVERAGE)
        b0 = UncertaintyBudget("F₀", out, [
            BudgetRow.type_a(msg("mean outputs F̄_j through the D.22 fit"), "√Σ(c_j·u(F̄_j))²", Q_(fit.uF0, out),
                             fit.nuF0),
            BudgetRow.type_a(msg("rest output F̄_r removed from every point (D.18)"), "u(F̄_r)", Q_(data.uFr, out),
                             int(data.n.min()) - 1),
            # F̄_r = (F̄_s + F̄_e)/2 enters F₀ with sensitivity −1: √(2·(1/2)²) on its two means
            _out_resolution_row(campaign, math.hypot(float(np.linalg.norm(ca)), math.sqrt(0.5)), out,
                                "D.22 and F̄_r", out),
            *_intercept_table_row(campaign, data.rates, K, out)], coverage=COVERAGE)
        res = [Result(metric_in(self.metrics[0], ku), Q_(K, ku), bK.combined, bK, earth_rate="removed", note=rep_note),
               Result(metric_in(self.metrics[1], out), Q_(F0, out), b0.combined, b0, note=f"F̄_r = {data.Fr:.4f} {ot}",
                      earth_rate="removed")]
        resid = data.Fk - (K * data.rates + F0)
        plot = PlotSpec("F_rate", msg("F_kj against Ω with the D.20 fit: residuals"), "Ω (°/s)", f"F_kj − (KΩ + F₀) ({ot})",
                        [{"label": "residual", "x": data.rates.tolist(), "y": resid.tolist(),
                          "yerr": (2 * data.uF).tolist(), "style": "o"}])
        table = TableSpec("F_points", msg("F_kj per rate point (D.17–D.19)"),
                          ["Ω (°/s)", f"F_kj ({ot})", msg("residual ({unit})", unit=ot)],
                          [[f"{r:+g}", f"{f:.3f}", f"{e:.3f}"] for r, f, e in zip(data.rates, data.Fk, resid)])
        return Outcome(STANDARD, self.item, self.title, self.clause, res, plots=[plot], tables=[table],
                       segments=data.segments, options=_opts_text(opts))


def nonlinearity_of(data: RateData, upto: float | None = None) -> tuple[float, int, float, np.ndarray, float, float]:
    """D.23–D.25 on the rate points with |Ω| ≤ ``upto`` (all by default): (K_n, index j of the
    maximum within the selection, |F_m|, the selection mask, K, F_0).  F_m is the output at the
    largest rate of the selection, the larger of its two directions."""
    sel = np.ones(data.rates.size, bool) if upto is None else np.abs(data.rates) <= upto * (1 + 1e-12)
    w, f = data.rates[sel], data.Fk[sel]
    K, F0 = F2.scale_factor_fit_d21_d22(w, f)
    top = np.abs(w) == np.abs(w).max()
    Fm = float(np.max(np.abs(f[top])))
    Kn, j = F2.nonlinearity_d24_d25(F2.fitted_output_d23(K, F0, w), f, Fm)
    return Kn, j, Fm, sel, K, F0


class NonlinearityD22(ScaleFactorD21):
    """GB/T 45570—2025 D.2.2 标度因数非线性度 (nonlinearity), rate method, eqs. (D.23)–(D.25).

    F̂_j = K·Ω_ij + F_0 from D.2.1; a_j = (F̂_j − F_kj)/|F_m| with F_m the output at the maximum
    input rate (the larger of its two directions); K_n = |a_j|_max.  Type A: the maximising
    point's mean (its samples' scatter) and the fitted line there; type B: the table's rate
    accuracy at that point (a rate error not proportional to Ω looks like nonlinearity).
    """

    item = "D.2.2"
    title = "Scale factor nonlinearity, rate method (标度因数非线性度)"
    clause = "D.2.2"
    metrics = (Metric("Kn", "scale factor nonlinearity", "K_n", "ppm", "D.2.2.3", "D.25"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        Kn, j, Fm, _, K, F0 = nonlinearity_of(data)
        # K_n is the largest of 2M noisy |a_j|: corrected for the selection (interpretations.md, D.2.2)
        from metro.api import selection_note, selection_rows

        sel = F2.nonlinearity_selection(data.rates, data.Fk, data.uF)
        budget = nonlinearity_budget(campaign, data, j, Fm, K, spread=sel.s)
        budget = UncertaintyBudget("K_n", "ppm", list(budget.rows) + selection_rows(sel, data.rates.size, ""),
                                   coverage=COVERAGE)
        a = (F2.fitted_output_d23(K, F0, data.rates) - data.Fk) / Fm
        res = Result(self.metrics[0], Q_(max(sel.value, 0.0), ""), budget.combined, budget,
                     note=join("; ", [msg("largest |a_j| at {rate:+g} °/s", rate=data.rates[j]),
                                      f"|F_m| = {Fm:.1f} {unit_text(data.unit)}", selection_note(sel, 1e6, 'ppm')]),
                     earth_rate="removed")
        plot = PlotSpec("a_rate", msg("Point nonlinearity a_j (D.24)"), "Ω (°/s)", "a_j (ppm)",
                        [{"label": "a_j", "x": data.rates.tolist(), "y": (a * 1e6).tolist(), "style": "o"}])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot], segments=data.segments,
                       options=_opts_text(opts))


def nonlinearity_budget(campaign: Campaign, data: RateData, j: int, Fm: float, K: float, sel=None,
                        spread: float = 0.0) -> UncertaintyBudget:
    """Budget of K_n = |F̂_j − F_kj|/|F_m| at the maximising point j: F̂_j − F_kj is a linear
    combination of all the F̄_i of the fit (g_i = c_F0,i + c_K,i·Ω_j − δ_ij), so its type A
    uncertainty is propagated from each point's scatter, the correlation with F̂_j included."""
    w = data.rates if sel is None else data.rates[sel]
    uF = data.uF if sel is None else data.uF[sel]
    n = data.n if sel is None else data.n[sel]
    ca, cb = F2.line_fit_sensitivities(w)
    g = ca + cb * w[j]
    g[j] -= 1.0
    u, nu = F2.propagate(g / Fm, uF, n - 1)
    # with ``spread`` (the Monte Carlo spread of the maximum over all points) the larger of the two
    rows = [BudgetRow.type_a(msg("mean outputs through F̂_j − F_kj at {rate:+g} °/s", rate=w[j]) if spread <= u else
                             msg("mean outputs through the largest |F̂_j − F_kj| (Monte Carlo over every point)"),
                             "√Σ(g_i·u(F̄_i))²/|F_m|" if spread <= u else "s(max_j |a_j|)", Q_(max(u, spread), ""), nu),
            _out_resolution_row(campaign, float(np.linalg.norm(g)) / Fm, "", "F̂_j − F_kj", data.unit)]
    rows += _rate_row(campaign, msg("at {rate:+g} °/s", rate=w[j]), K * abs(w[j]) / Fm, "",
                      msg("an error not proportional to Ω shows as nonlinearity; bounded by the table's accuracy"),
                      rate=float(w[j]))
    return UncertaintyBudget("K_n", "ppm", rows, coverage=COVERAGE)


class AsymmetryD23(ScaleFactorD21):
    """GB/T 45570—2025 D.2.3 标度因数不对称度 (asymmetry), rate method, eqs. (D.26), (D.27).

    The D.2.1 outputs regrouped by direction; K_(+) and K_(−) by the D.21 fit of each group;
    K_a = |K_(+) − K_(−)| / ((K_(+) + K_(−))/2).  Type A: the two fits' standard errors; type B:
    the table's rate accuracy between the two directions.
    """

    item = "D.2.3"
    title = "Scale factor asymmetry, rate method (标度因数不对称度)"
    clause = "D.2.3"
    metrics = (Metric("Ka", "scale factor asymmetry", "K_a", "ppm", "D.2.3.3", "D.26"),)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        data = collect_rate_data(type(self), campaign, int(opts["min_points"]))
        pos, neg = data.rates > 0, data.rates < 0
        fp, fm = fit_scale_factor(data, pos), fit_scale_factor(data, neg)
        Kp, Km = fp.K, fm.K
        Ka = F2.asymmetry_d26_d27(Kp, Km)
        Kbar = 0.5 * (Kp + Km)
        rows = [BudgetRow.type_a(msg("K_(+): D.21 on the + rates"), "u(K₊)/K̄", Q_(fp.uK / Kbar, ""), fp.nuK),
                BudgetRow.type_a(msg("K_(−): D.21 on the − rates"), "u(K₋)/K̄", Q_(fm.uK / Kbar, ""), fm.nuK)]
        per_point = [rate_table_rel(campaign, float(r)) for r in data.rates]
        if all(p is not None for p in per_point):
            u_rel = np.array([p[0] for p in per_point])
            u_dir = math.hypot(_through_fit(data.rates[pos], list(u_rel[pos])),
                               _through_fit(data.rates[neg], list(u_rel[neg])))
            rows.append(BudgetRow.type_b(msg("rate-table rate error at each set point, through K(+) and K(−) "
                                             "({table})", table=per_point[-1][1]), "u(δK₊/K ⊖ δK₋/K)", Q_(u_dir, ""),
                                         distribution="normal", k=1.0,
                                         note=msg("independent at each signed set point; a common error cancels")))
        budget = UncertaintyBudget("K_a", "ppm", rows, coverage=COVERAGE)
        res = Result(self.metrics[0], Q_(Ka, ""), budget.combined, budget,
                     note=f"K(+) = {Kp:.4f}, K(−) = {Km:.4f} {k_text(data.unit)}", earth_rate="removed")
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], segments=data.segments,
                       options=_opts_text(opts))


# --------------------------------------------------------------------------------------------
# D.2.4 repeatability, D.2.5 temperature sensitivity
# --------------------------------------------------------------------------------------------


class ScaleFactorRepeatabilityD24(ScaleFactorD21):
    """GB/T 45570—2025 D.2.4 标度因数重复性 (scale-factor repeatability), rate method, eq. (D.28).

    Seven D.2.1 tests (condition ``run`` = 1 … 7 on their ``rate-output`` and ``rate-static``
    segments), power off ≥ 10 min between; K_j by D.21 for each; K_r = s(K_j)/K̄.  Type A: the
    sampling uncertainty of a standard deviation of Q values, K_r/√(2(Q − 1)), ν = Q − 1; type B:
    the table's rate accuracy, bounding a rate that differs between runs.
    """

    item = "D.2.4"
    title = "Scale factor repeatability, rate method (标度因数重复性)"
    clause = "D.2.4"
    metrics = (Metric("Kr", "scale factor repeatability", "K_r", "ppm", "D.2.4.3", "D.28"),)
    requires = (attrs.evolve(RATE_OUTPUT, conditions={"rate": "deg/s", "run": ""}, min_count=154),
                attrs.evolve(REST, conditions={"when": "", "run": ""}, min_count=14))
    options = _OPTIONS + (Option("Q", 7, None, "number of power-ons; D.28 is written for 7", minimum=2),)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        q = int(options.get("Q", 7))
        return [s for j in range(1, q + 1)
                for s in rate_sequence(options, {"run": j}, f"run{j}-",
                                       f"power-on {j} of {q} (off ≥ 10 min before, D.2.4.2)")]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        q = int(opts["Q"])
        runs = sorted({_group_of(s)[0] for s in campaign.find_segments("rate-output") if _group_of(s)[0]
                       and not _group_of(s)[1]}, key=lambda r: (len(r), r))
        if len(runs) != q:
            raise DataError(campaign.source, "segments",
                            f"D.2.4 needs {q} power-ons (segments of kind \"rate-output\" with run = 1 … {q}, "
                            f"D.2.4.2); found {len(runs)} run(s): {', '.join(runs) or 'none'}",
                            hint="D.28 is written for 7 repeats")
        Kj, used = [], []
        for r in runs:
            last = collect_rate_data(type(self), campaign, int(opts["min_points"]), (r, ""), f"in run {r}")
            Kj.append(fit_scale_factor(last).K)
            used += list(last.segments)
        Kr = F2.scale_factor_repeatability_d28(Kj)
        if not Kr > 0:
            raise DataError(campaign.source, "segments", f"the {q} scale factors are identical; K_r = 0 cannot be right")
        rows = [BudgetRow.type_a(msg("sampling of the standard deviation of Q = {q} scale factors (χ² bound)", q=q),
                                 "(s_{upper} − K_r)/2", Q_(std_sampling_u(Kr, q), ""), math.inf)]
        rows += _stability_row(campaign, last)
        budget = UncertaintyBudget("K_r", "ppm", rows, coverage=COVERAGE)
        mean = float(np.mean(Kj))
        kt = k_text(last.unit)
        res = Result(self.metrics[0], Q_(Kr, ""), budget.combined, budget, note=f"K̄ = {mean:.4f} {kt}, Q = {q}",
                     earth_rate="removed")
        table = TableSpec("K_runs", msg("K_j of each power-on (D.21)"), [msg("run"), f"K_j ({kt})", "K_j − K̄ (ppm)"],
                          [[r, f"{k:.5f}", f"{(k - mean) / mean * 1e6:.2f}"] for r, k in zip(runs, Kj)])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[table], segments=used,
                       options=_opts_text(opts))


class ScaleFactorTemperatureSensitivityD25(ScaleFactorD21):
    """GB/T 45570—2025 D.2.5 标度因数温度灵敏度 (scale-factor temperature sensitivity), rate
    method, eq. (D.29).

    A D.2.1 test at each of ≥ 5 temperature points including room temperature (condition
    ``temperature`` on the ``rate-output`` and ``rate-static`` segments), K_i by D.21;
    K_t = max |(K_i − K_00)/(K_00 (T_i − T_0))|.  Budget of the maximising point: the two fits'
    standard errors (A), the chamber's temperature uncertainty on T_i − T_0 (B).
    """

    item = "D.2.5"
    title = "Scale factor temperature sensitivity, rate method (标度因数温度灵敏度)"
    clause = "D.2.5"
    metrics = (Metric("Kt", "scale factor temperature sensitivity", "K_t", "ppm/delta_degC", "D.2.5.3", "D.29"),)
    requires = (attrs.evolve(RATE_OUTPUT, conditions={"rate": "deg/s", "temperature": "degC"}, min_count=110),
                attrs.evolve(REST, conditions={"when": "", "temperature": "degC"}, min_count=10))
    equipment = _EQUIPMENT + (EquipmentRequirement("chamber", "temperature chamber, vibration-isolated, control "
                                                   "better than ±2 °C (D.2.5.1 b))"),)
    options = _OPTIONS + (
        Option("temperatures", "-40 °C, -20 °C, 0 °C, 20 °C, 40 °C, 60 °C", None,
               "≥ 5 temperature points, evenly spread, including room temperature (D.2.5.2 b))"),
        Option("room", "20 °C", "degC", "room temperature T0: the nearest point is the reference"),
        Option("min_temperatures", 5, None, "fewest temperature points accepted (D.2.5.2 b): not fewer than 5)"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        temps = [t.strip() for t in str(options.get("temperatures", "-40 °C, -20 °C, 0 °C, 20 °C, 40 °C, 60 °C"))
                 .split(",")]
        return [s for i, T in enumerate(temps)
                for s in rate_sequence(options, {"temperature": T}, f"T{i + 1}-",
                                       f"at {T} (power off while changing, soak ≥ 2 h, D.2.5.2 c))")]

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        byT: dict[str, list[Segment]] = {}
        for s in campaign.find_segments("rate-output"):
            run, T = _group_of(s)
            if T and not run:
                byT.setdefault(T, []).append(s)
        keys, temps, i0 = room_index(campaign, byT, float(opts["room"].to("degC").magnitude),
                                     int(opts["min_temperatures"]), "D.2.5")
        Ks, uKs, dofs, used = [], [], [], []
        for k, T in zip(keys, temps):
            data = collect_rate_data(type(self), campaign, int(opts["min_points"]), ("", k), f"at {T:g} °C")
            fit = fit_scale_factor(data)
            Ks.append(fit.K)
            uKs.append(fit.uK)
            dofs.append(fit.nuK)
            used += list(data.segments)
        Kt, imax = F2.scale_factor_temperature_sensitivity_d29(Ks, temps, i0)
        kt = k_text(data.unit)
        return _temperature_outcome(self, campaign, opts, Kt, imax, i0, temps, Ks, uKs, dofs, used, kt)


# --------------------------------------------------------------------------------------------
# D.2.6 input-axis misalignment
# --------------------------------------------------------------------------------------------


class InputAxisMisalignmentD26(Procedure):
    """GB/T 45570—2025 D.2.6 输入轴失准角 (input-axis misalignment), rate method, eqs. (D.30)–(D.36).

    Four mountings (segments of kind ``rate-mounting``: ``axis_up`` XRA/YRA, ``turn`` 0°/180°
    about IRA, signed ``rate``): δ = sin⁻¹((F₊ − F₋)/(2KΩ)) per mounting (D.30, D.31, D.33,
    D.34) with the device's K, α = (δ₁ − δ₂)/2 (D.32), β = (δ₃ − δ₄)/2 (D.35), γ = √(α² + β²)
    (D.36).  Type A: the mean outputs' scatter; type B: the fixture's re-seating tilt, the scale
    factor and the table's rate accuracy (δ ∝ 1/(KΩ)).
    """

    standard = STANDARD
    item = "D.2.6"
    title = "Input axis misalignment, rate method (输入轴失准角)"
    clause = "D.2.6"
    metrics = misalignment_metrics("D.2.6.4", ("D.32", "D.35", "D.36"))
    requires = (SegmentRequirement("rate-mounting", "output at ±Ω with XRA, then YRA, along the table axis, each "
                                   "before and after a 180° turn about IRA (D.2.6.3)",
                                   conditions={"axis_up": "", "turn": "deg", "rate": "deg/s"},
                                   columns={"output": OUTPUT_UNITS}, min_count=8),)
    equipment = _EQUIPMENT + (EquipmentRequirement("fixture", "fixture holding XRA/YRA along the table axis, "
                                                   "turnable 180° about IRA; its re-seating tilt enters the budget"),)
    options = (Option("rate", REPEAT_RATE, "deg/s", "table rate Ω (D.2.6.3 d): \"a given rate\")"),
               Option("turns", 5, None, "whole revolutions recorded at each rate (the horizontal earth rate "
                      "averages out over whole revolutions)"))
    station = "simulated-digital"

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        r = float(parse_quantity(options.get("rate", REPEAT_RATE), dimension="deg/s").to("deg/s").magnitude)
        return mounting_steps("rate-mounting", r, options, revolutions=False)

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        from metro.api import required_scale_factor

        opts = self.option_values(ctx.options)
        groups = mounting_groups(campaign, "rate-mounting", "D.2.6")
        first = next(iter(groups.values()))[0]
        out_unit = output_series(first)[1]
        if out_unit == "deg/s":
            # a rate output is its own K: (°/s)/(°/s) = 1; its scale error (ppm, D.2.1) moves δ by
            # as many ppm of itself, negligible against the mean outputs' scatter
            k, u_rel_K = 1.0, 0.0
        else:
            k_unit = LSB_PER_RATE if out_unit == "LSB" else "Hz/(deg/s)"
            k, u_rel_K = required_scale_factor(campaign.device, k_unit, source=campaign.source,
                                               needed_by="eq. (D.30) of D.2.6 (K from D.2.1)")
        ang, used = {}, []
        for (ax, turn), segs in groups.items():
            where = f"mounting {ax} up, turned {turn}°"
            by_dir: dict[int, tuple] = {}
            for s in segs:
                rate = float(s.condition("rate", "deg/s").to("deg/s").magnitude)
                if rate == 0:
                    raise DataError(campaign.source, f"segments.{s.id}.conditions.rate", "the rate cannot be 0 °/s")
                d = 1 if rate > 0 else -1
                if d in by_dir:
                    raise DataError(campaign.source, f"segments.{s.id}", f"{where}: two segments at {rate:+g} °/s")
                mean = _mean_output(s, campaign)
                if mean[3] != out_unit:  # D.30 divides by the device's K in the output's unit per °/s
                    raise DataError(s.file or campaign.source, "output",
                                    f"D.2.6 reads one kind of output in every mounting (D.30 divides by K in "
                                    f"{unit_text(out_unit)}/(°/s)); segment {s.id!r} is in {unit_text(mean[3])}, "
                                    f"segment {first.id!r} in {unit_text(out_unit)}")
                by_dir[d] = (s, abs(rate)) + mean[:3]
            if set(by_dir) != {1, -1}:
                only = next(iter(by_dir.values()))[0]
                raise DataError(campaign.source, f"segments.{only.id}",
                                f"{where} has no {'clockwise (−)' if 1 in by_dir else 'counter-clockwise (+)'} record; "
                                "D.30 needs F₊ and F₋")
            (sp, rp, Fp, up, n_p), (sm, rm, Fm, um, n_m) = by_dir[1], by_dir[-1]
            if abs(rp - rm) > 1e-9 * rp:
                raise DataError(campaign.source, f"segments.{sm.id}.conditions.rate",
                                f"{where}: the two directions differ in rate ({rp:g} and {rm:g} °/s); D.30 uses one Ω")
            try:
                delta = F2.misalignment_d30(Fp, Fm, k, rp)
            except ValueError as exc:
                raise DataError(campaign.source, f"segments.{sp.id}", f"{where}: {exc}") from exc
            c = 1.0 / (2.0 * k * rp * math.cos(math.radians(delta))) * 180.0 / math.pi
            ang[(ax, turn)] = (delta, c * math.hypot(up, um), max(min(n_p, n_m) - 1, 1))
            used += [sp.id, sm.id]
        rel = []
        if u_rel_K > 0:
            rel.append(BudgetRow.type_b(msg("scale factor K (device)"), "u_rel(K)", Q_(u_rel_K, ""), distribution="normal",
                                        k=1.0, note=f"K = {k:g} {unit_text(out_unit)}/[(°)/s]; δ ≈ (F₊ − F₋)/(2KΩ)"))
        r = rate_table_rel(campaign)
        if r is not None:
            rel.append(BudgetRow.type_b(msg("rate-table rate accuracy ({table})", table=r[1]), "u_rel(Ω)", Q_(r[0], ""),
                                        distribution="normal", k=1.0, note="δ ∝ 1/Ω"))
        return misalignment_outcome(self, campaign, opts, ang, rel, used, msg("scatter of the mean outputs"))


# --------------------------------------------------------------------------------------------
# D.3 maximum input rate
# --------------------------------------------------------------------------------------------


class MaxInputRateD3(Procedure):
    """GB/T 45570—2025 D.3 最大输入角速率 (maximum input rate).

    The largest tested table rate Ω whose range [−Ω, +Ω] has a scale-factor nonlinearity within
    the limit (definition 3.13 note 1).  K_n of each range is that of the data's method: D.7 on
    the K_i of the rate points up to Ω (angle method, ``rate-revolutions`` segments), or
    D.23–D.25 on the F_kj up to Ω with F_m the output at Ω (rate method, ``rate-output``
    segments).  The limit (option ``Kn_limit``) defaults to the device's
    ``nonlinearity_limit``, else tables A.1/B.1 for its technology and application.  Type A:
    the rate realised at Ω_max as the gyro indicates it (its output's scatter); type B: the rate
    table's rate accuracy.
    """

    standard = STANDARD
    item = "D.3"
    title = "Maximum input rate (最大输入角速率)"
    clause = "D.3"
    metrics = (Metric("Omega_max", "maximum input rate", "Ω_max", "deg/s", "D.3", "D.7, D.25"),)
    requires = (attrs.evolve(RATE_OUTPUT, description="rate method: " + RATE_OUTPUT.description, alternative="sweep"),
                SegmentRequirement("rate-revolutions", "or, angle method: m whole revolutions at each rate point, each "
                                   "direction (D.1.1.2 g))", conditions={"rate": "deg/s", "turns": ""},
                                   columns={"count": ("P",), "duration": ("s",)}, min_count=22, alternative="sweep"))
    equipment = _EQUIPMENT
    options = (
        Option("Kn_limit", None, None, "nonlinearity limit, e.g. \"10 ppm\" (default: device.nonlinearity_limit, "
               "else table A.1/B.1 for the device's technology and application)"),
        Option("method", "auto", None, "\"angle\" (pulse output, D.1), \"rate\" (LSB output, D.2) or \"auto\" "
               "(the sweep the data hold; both: the one matching the device's output; for the sequence, "
               "\"auto\" means angle)"),
        Option("max_rate", "400 °/s", "deg/s", "largest rate point tested (test beyond the expected maximum)"),
        Option("turns", 5, None, "angle method: whole revolutions m per rate point and direction"),
        Option("duration", "100 s", "s", "rate method: record at each rate point and at rest"),
        Option("interval", "1 s", "s", "rate method: sampling interval"),
        Option("min_points", 11, None, "fewest rate points accepted (D.1.1.2 e), D.2.1.2 e))"),
        Option("min_range_points", 3, None, "fewest rate points in a range before its K_n is judged"),
    )

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        if str(options.get("method", "auto")).lower() == "rate":
            return rate_sequence(options)
        return _angle_sequence(options, zero=False)

    def sequence_for_device(self, options: Mapping[str, Any], device: DeviceUnderTest | None) -> list[Step]:
        """The sequence for a known device: ``method = auto`` becomes the sweep the device can give —
        whole-revolution pulse counts (angle method) need a pulse output, so a digital or analog
        output takes the rate method; a pulse output follows the 6.2.7.1 method rule."""
        if device is None or str(options.get("method", "auto")).lower() != "auto":
            return self.sequence(options)
        from .method_rule import method_for

        method = method_for(device)[0] if str(device.output).lower() == "pulse" else "rate"
        return self.sequence(dict(options) | {"method": method})

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        method = str(opts["method"]).strip().lower()
        if method not in ("auto", "angle", "rate"):
            raise ProcedureError(f"D.3: option method = {opts['method']!r}; use angle, rate or auto")
        if method == "auto":
            has_angle = bool(campaign.find_segments("rate-revolutions"))
            has_rate = any(_group_of(s) == ("", "") for s in campaign.find_segments("rate-output"))
            if has_angle and has_rate:
                # both sweeps measured: the one that matches the device's output
                method = "rate" if str(campaign.device.output).lower() in ("digital", "analog") else "angle"
            elif has_angle:
                method = "angle"
            elif has_rate:
                method = "rate"
            else:
                raise DataError(campaign.source, "segments",
                                "D.3 needs the scale-factor sweep of D.1 (segments of kind \"rate-revolutions\") or of "
                                "D.2 (\"rate-output\" and \"rate-static\"); none found",
                                hint="`metro plan --standard gbt45570 --item D.3` lists them")
        if opts["Kn_limit"] is not None:
            lim_q = parse_quantity(opts["Kn_limit"], dimension="", field="option Kn_limit")
            limit, lim_src = float(lim_q.to("").magnitude), "option Kn_limit"
        else:
            lim_q, lim_src = default_nonlinearity_limit(campaign.device, campaign.source)
            limit = float(lim_q.to("").magnitude)
        if not limit > 0:
            raise ProcedureError(f"D.3: the nonlinearity limit must be positive, got {limit:g}")
        nmin, rmin = int(opts["min_points"]), int(opts["min_range_points"])
        if method == "angle":
            pts = collect_rate_points(type(self), campaign, nmin)

            def kn_of(upto: float) -> float:
                sub = [p for p in pts if p.rate <= upto * (1 + 1e-12)]
                fit = fit_line(np.array([p.rate for p in sub]), np.array([p.K for p in sub]))
                return F.nonlinearity_d7([p.K for p in sub], float(fit.coef[0]))[0]

            def kn_u(upto: float) -> float:
                # D.7's |K_j − K|/K with K the D.5 intercept: K_j − K = Σ g_i·K_i, g = δ_ij − c_a,i
                sub = [p for p in pts if p.rate <= upto * (1 + 1e-12)]
                w = np.array([p.rate for p in sub])
                Ki = np.array([p.K for p in sub])
                K0 = float(fit_line(w, Ki).coef[0])
                j = F.nonlinearity_d7(Ki, K0)[1]
                ca, _cb = F2.line_fit_sensitivities(w)
                g = -ca
                g[j] += 1.0
                return F2.propagate(g / K0, [p.u_K for p in sub], [max(min(p.m_plus, p.m_minus) - 1, 1) for p in sub])[0]

            rates = [p.rate for p in pts]
            segments = [s for p in pts for s in p.segments]
        else:
            data = collect_rate_data(type(self), campaign, nmin)

            def kn_of(upto: float) -> float:
                return nonlinearity_of(data, upto)[0]

            def kn_u(upto: float) -> float:
                # D.2.2's budget of the range's K_n: its outputs' scatter, resolution, the table's rate error
                _kn, j, Fm, sel, K, _F0 = nonlinearity_of(data, upto)
                b = nonlinearity_budget(campaign, data, j, Fm, K, sel=sel)
                return float(b.combined.to("").magnitude)

            rates = data.magnitudes
            segments = list(data.segments)
        try:
            om, curve = F2.max_input_rate_d3(rates, kn_of, limit, rmin)
        except ValueError as exc:
            raise DataError(campaign.source, "segments", f"D.3: {exc}") from exc
        if om is None:
            raise ProcedureError(f"D.3: no tested range meets the nonlinearity limit {limit * 1e6:g} ppm ({lim_src}); "
                                 f"the smallest range, up to {curve[0][0]:g} °/s, has K_n = {curve[0][1] * 1e6:.3g} ppm",
                                 hint="test lower rates, or check the limit (option Kn_limit)")
        warnings = []
        if om == max(rates):
            warnings.append(msg("K_n meets the limit up to the largest rate tested ({om:g} °/s); the maximum input rate "
                                "may be higher — test beyond it{hint}", om=om, hint=hint(" (plan with -o max_rate=…)")))
        failing_below = [r for r, kn in curve if r < om and kn > limit]
        if failing_below:
            warnings.append(msg("ranges up to {rates} °/s exceed the limit while the range up to {om:g} °/s meets it "
                                "(definition 3.13 judges the range up to Ω_max)",
                                rates=", ".join(f'{r:g}' for r in failing_below), om=om))
        # type A: the table rate at Ω_max as the gyro indicates it
        if method == "angle":
            p = next(p for p in pts if p.rate == om)
            u_rate = om * p.u_K / p.K
            nu = max(min(p.m_plus, p.m_minus) - 1, 1)
        else:
            K = fit_scale_factor(data).K
            sel = np.abs(data.rates) == om
            u_rate = float(np.sqrt(np.mean(data.uF[sel] ** 2) / sel.sum())) / abs(K)
            nu = int(data.n[sel].min()) - 1
        how = msg("angle method") if method == "angle" else msg("rate method")
        rows = [BudgetRow.type_a(msg("rate realised at {om:g} °/s, as the gyro indicates it", om=om), "u(Ω)",
                                 Q_(u_rate, "deg/s"), nu, note=how)]
        rows += _rate_row(campaign, msg("at {om:g} °/s", om=om), om, "deg/s", msg("the table's setting of Ω_max"), rate=om)
        rows += _decision_rows(curve, kn_u, limit, om)
        budget = UncertaintyBudget("Ω_max", "deg/s", rows, coverage=COVERAGE)
        kn_at = dict(curve)[om]
        res = Result(self.metrics[0], Q_(om, "deg/s"), budget.combined, budget,
                     note=join("; ", [msg("K_n up to {om:g} °/s = {kn:.3g} ppm ≤ {limit:g} ppm ({source})", om=om, kn=kn_at * 1e6,
                                          limit=limit * 1e6, source=lim_src), how]), earth_rate="not applicable")
        plot = PlotSpec("Kn_range", msg("K_n of the range [−Ω, +Ω] against Ω (D.3)"), "Ω (°/s)", "K_n (ppm)",
                        [{"label": "K_n up to Ω", "x": [r for r, _ in curve], "y": [k * 1e6 for _, k in curve],
                          "style": "o-"},
                         {"label": msg("limit {v:g} ppm", v=limit * 1e6), "x": [curve[0][0], curve[-1][0]],
                          "y": [limit * 1e6] * 2, "style": "--"}], logx=True)
        table = TableSpec("Kn_ranges", msg("K_n of each range (D.3)"), [msg("up to Ω (°/s)"), "K_n (ppm)", msg("meets the limit")],
                          [[f"{r:g}", f"{k * 1e6:.3g}", msg("yes") if k <= limit else msg("no")] for r, k in curve])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], plots=[plot], tables=[table],
                       warnings=warnings, segments=segments, options=_opts_text(opts))


def _decision_rows(curve: list[tuple[float, float]], kn_u, limit: float, om: float) -> list[BudgetRow]:
    """D.3's decision near the limit (interpretations.md, "D.3 — a range near the limit"): Ω_max is a tested
    rate picked by comparing each range's K_n with the limit, so a K_n within 2u of the limit may have
    been judged either way by the noise and the table's error.  The candidates are Ω_max, every larger
    range whose K_n is within 2u of the limit (it may truly meet it), and, when Ω_max's own K_n is within
    2u, the next smaller range; the row is uniform over the whole distance to the farthest candidate (as
    D.4's 50 % decision)."""
    rates = [r for r, _ in curve]
    kn = dict(curve)
    doubtful = {r for r in rates if abs(kn[r] - limit) < 2.0 * kn_u(r)}
    cands = [r for r in rates if r > om and r in doubtful]
    if om in doubtful:
        smaller = [r for r in rates if r < om]
        if smaller:
            cands.append(max(smaller))
    if not cands:
        return []
    half = max(abs(c - om) for c in cands)
    why = join("; ", [msg("K_n up to {r:g} °/s = {kn:.3g} ± {u:.2g} ppm (2u) against {limit:g} ppm", r=r, kn=kn[r] * 1e6,
                          u=2e6 * kn_u(r), limit=limit * 1e6) for r in sorted(doubtful)])
    return [BudgetRow.type_b(msg("decision near the limit: a range whose K_n is within 2u of the limit may be judged "
                                 "either way, so Ω_max may be the neighbouring rate"), "ΔΩ (decision)",
                             Q_(half, "deg/s"), distribution="uniform", note=why)]


PROCEDURES = (ScaleFactorD21, NonlinearityD22, AsymmetryD23, ScaleFactorRepeatabilityD24,
              ScaleFactorTemperatureSensitivityD25, InputAxisMisalignmentD26, MaxInputRateD3)

__all__ = ["PROCEDURES", "default_nonlinearity_limit", "collect_rate_data", "nonlinearity_of", "rate_sequence",
           "RateData", "MOUNTINGS"] + [c.__name__ for c in PROCEDURES]

"""The rate method's data (GB/T 45570 D.2): the output kinds it takes, the sweep of rate points
(D.2.1.2), the mean outputs and the rest output of one test (D.17–D.19), the D.21/D.22 fit with
its type A, the nonlinearity of a range (D.23–D.25), and the rate table's and the output's rows.
Shared by the D.2 items, D.3, the repeatability rows and the clause-5 environmental tests."""

from __future__ import annotations

import math
from typing import Any, Mapping

import attrs
import numpy as np
from metro.api import (Q_, BudgetRow, Campaign, DataError, DeviceUnderTest, EquipmentRequirement,
                       Metric, Procedure, ProcedureError, Segment, SegmentRequirement, Step,
                       UncertaintyBudget, fit_line, join, msg, parse_quantity)

from . import formulas_rate as F2
from .common import (COVERAGE, DIRECTIONS, ItemRef, group_of, resolution, resolution_row,
                     signed_rate)
from .revolutions import rate_points

LSB_PER_RATE = "LSB/(deg/s)"


#: the output kinds D.2 takes: a digital word in LSB (D.17–D.22), a frequency in Hz (D.23 names it)
#: or a digital rate in °/s (any angular-rate unit, converted to °/s); K is then in LSB/[(°)/s],
#: Hz/[(°)/s] or (°/s)/(°/s) (a ratio)
OUTPUT_UNITS = ("LSB", "Hz", "deg/s")


RATE_OUTPUT = SegmentRequirement(
    "rate-output",
                                 "output sampled at each rate point once the table is steady, both "
                                 "directions (D.2.1.2 f), g))",
    conditions={"rate": "deg/s"}, columns={"output": OUTPUT_UNITS}, min_count=22,
)


REST = SegmentRequirement("rate-static",
                          "table at rest at the start and at the end of the test (D.2.1.2 h))",
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


def default_nonlinearity_limit(device: DeviceUnderTest, source: str | None = None) -> tuple[Any,
                                                                                            str]:
    """The K_n limit D.3 judges against: the device specification's ``nonlinearity_limit`` if
    given, else the typical value of table A.1 (laser) or B.1 (fibre) for its application."""
    if "nonlinearity_limit" in device.properties:
        q = device.prop("nonlinearity_limit", "", source=source)
        return Q_(float(q.to("").magnitude),
                  ""), msg("device specification (device.nonlinearity_limit)")
    tech = _TECHNOLOGY.get(str(device.technology).strip().lower())
    app = _APPLICATION.get(str(device.application).strip().lower())
    if tech is None or app is None:
        raise DataError(source, "device.technology/application",
                        f"no default nonlinearity limit for technology {device.technology!r}, "
                        f"application {device.application!r} (tables A.1/B.1 know laser/fibre × "
                        f"aerospace/aviation/marine)",
                        hint="give the option Kn_limit (e.g. \"10 ppm\") or "
                             "device.nonlinearity_limit")
    table = "A.1" if tech == "laser" else "B.1"
    return Q_(NONLINEARITY_LIMITS_PPM[tech][app] * 1e-6,
              ""), msg("table {table} ({technology}, {application})",
                                                                   table=table, technology=tech,
                                                                  application=app)


def rate_sequence(options: Mapping[str, Any], extra: Mapping[str, Any] | None = None,
                  prefix: str = "",
                  note: str = "") -> list[Step]:
    """D.2.1.2: at rest (start), each R5 rate point both ways, at rest (end)."""
    rmax = float(parse_quantity(options.get("max_rate", "400 °/s"),
                                dimension="deg/s").to("deg/s").magnitude)
    dur = parse_quantity(options.get("duration", "100 s"), dimension="s")
    tau = parse_quantity(options.get("interval", "1 s"), dimension="s")
    extra = dict(extra or {})
    head = f"{note}: " if note else ""
    steps = [Step(f"{prefix}rest-start", "rate-static",
                  head + "table at rest at the start; record n samples "
                  "(D.2.1.2 h))", dur, tau, {"when": "start"} | extra, warmup=Q_(30, "min"))]
    for r in rate_points(rmax):
        for sign, word in DIRECTIONS:
            steps.append(Step(f"{prefix}rate{sign * r:+g}", "rate-output",
                              head + f"table at {r:g} °/s {word}; once steady record n samples, "
                                     f"stop "
                              "(D.2.1.2 f), g))", dur, tau,
                              {"rate": f"{sign * r:g} deg/s"} | extra))
    steps.append(Step(f"{prefix}rest-end", "rate-static",
                      head + "table at rest at the end; record n samples "
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
    # pragma: no cover
    raise DataError(seg.file, "output", f"unit {data.units} is none of {', '.join(OUTPUT_UNITS)}")


def mean_output(seg: Segment, campaign: Campaign) -> tuple[float, float, int, str]:
    """The mean output of one segment (D.17), its standard uncertainty, its number of samples and
    its unit."""
    x, unit = output_series(seg)
    if x.size < 2 or not np.all(np.isfinite(x)):
        bad = ("fewer than 2 samples" if x.size < 2 else
               f"sample {int(np.argmin(np.isfinite(x))) + 1} is not finite")
        raise DataError(seg.file or f"segment {seg.id}", "output",
                        f"{bad}; D.17 needs a finite record")
    return F2.mean_output_d17(x), float(np.std(x, ddof=1) / math.sqrt(x.size)), int(x.size), unit


def collect_rate_data(proc: type[Procedure] | ItemRef, campaign: Campaign, min_points: int,
                      group: tuple[str, str] = ("", ""),
                      what: str = "") -> RateData:
    """Mean outputs (D.17), the rest output (D.18) and F_kj (D.19) of the segments of one group
    (``run``, ``temperature``; ("", "") = neither)."""
    where = f" {what}" if what else ""
    segs = [s for s in campaign.find_segments("rate-output") if group_of(s) == group]
    rest = [s for s in campaign.find_segments("rate-static") if group_of(s) == group]
    if not segs:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs segments of kind \"rate-output\"{where} "
                        f"(output at each rate "
                        "point, D.2.1.2 g)); none found",
                        hint=f"`metro plan --standard gbt45570 --item {proc.item}` lists them")
    when = {str(s.condition("when")).strip().lower(): s for s in rest}
    missing = [w for w in ("start", "end") if w not in when]
    if missing:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs the output with the table at rest at the "
                        f"start and the end (segments of kind \"rate-static\", when = start / "
                        f"end{where}, D.2.1.2 h)); missing: {', '.join(missing)}")
    (Fs, us, _, unit), (Fe, ue, _, unit_e) = mean_output(when["start"],
                                                         campaign), mean_output(when["end"],
                                                                                campaign)
    units = {unit, unit_e}
    Fr = F2.rest_output_d18(Fs, Fe)
    uFr = 0.5 * math.hypot(us, ue)
    by_rate: dict[float, dict[int, tuple]] = {}
    for s in segs:
        rate, d = signed_rate(campaign, s)
        slot = by_rate.setdefault(round(abs(rate), 9), {})
        if d in slot:
            raise DataError(campaign.source, f"segments.{s.id}",
                            f"two segments at {rate:+g} °/s{where}")
        mean = mean_output(s, campaign)
        slot[d] = (s, rate) + mean[:3]
        units.add(mean[3])
    if len(units) > 1:
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()}{where}: the outputs are of different "
                        f"kinds ({', '.join(sorted(units))}); one test records one output")
    rates, Fk, uF, n, ids = [], [], [], [], [s.id for s in rest]
    for mag, pair in sorted(by_rate.items()):
        if set(pair) != {1, -1}:
            only = next(iter(pair.values()))[0]
            missing_dir = "clockwise (−)" if 1 in pair else "counter-clockwise (+)"
            raise DataError(campaign.source, f"segments.{only.id}",
                            f"rate point {mag:g} °/s{where} has no {missing_dir} record; D.2.1.2 "
                            f"f) turns the table "
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
                        f"{proc.qualified_id()} needs at least {min_points} rate points (D.2.1.2 "
                        f"e)){where}; found {len(by_rate)}",
                        hint="or lower the option min_points if agreed with the user")
    return RateData(np.array(rates), np.array(Fk), np.array(uF), np.array(n), Fr, uFr, tuple(ids),
                    unit)


def rate_band(campaign: Campaign, rate: float) -> tuple[float, float, str] | None:
    """The rate table's stated accuracy at |``rate``| (°/s) from its ``rate_band_i_upper``,
    ``rate_band_i_error`` (relative half-width of the mean rate) and ``rate_band_i_ripple``
    (relative standard deviation of the rate over one sample) properties, if it states them."""
    tab = campaign.equipment_for("rate_table")
    if tab is None:
        return None
    i = 1
    while f"rate_band_{i}_upper" in tab.properties:
        upper = float(tab.prop(f"rate_band_{i}_upper", "deg/s",
                               source=campaign.source).to("deg/s").magnitude)
        if abs(rate) <= upper * (1 + 1e-12):
            err = tab.prop(f"rate_band_{i}_error", "", source=campaign.source)
            rip = tab.prop(f"rate_band_{i}_ripple", "", source=campaign.source)
            return float(err.to("").magnitude), float(rip.to("").magnitude), msg("{equipment}, "
                                                                                 "band ≤ {upper:g} "
                                                                                 "°/s",
                                                                                 equipment=tab.describe(),
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
    return float(cal.standard_uncertainty.to("").magnitude), join(", ", [tab.describe(),
                                                                         cal.certificate])


def rate_row(campaign: Campaign, what: str, value: float, unit: str, note: str,
              rate: float | None = None) -> list[BudgetRow]:
    """The rate table's rate accuracy (at ``rate``, or its calibration) as a relative row on
    ``value``."""
    r = rate_table_rel(campaign, rate)
    if r is None:
        return []
    return [BudgetRow.type_b(msg("rate-table rate accuracy, {what} ({table})", what=what,
                                 table=r[1]), "u_rel(Ω)",
                             Q_(r[0], ""), distribution="normal", k=1.0, sensitivity=Q_(abs(value),
                                                                                        unit),
                             note=note)]


def through_fit(rates: np.ndarray, u_rel: list[float], *, intercept: bool = False) -> float:
    """What independent relative rate errors u_rel[i] at the set points do to the D.21/D.22 fit:
    the relative standard uncertainty of the slope, δK/K = Σ c_K,i·Ω_i·δ_i, or (``intercept``)
    the intercept's per unit K, δF₀/K = Σ c_F0,i·Ω_i·δ_i."""
    ca, cb = F2.line_fit_sensitivities(rates)
    c = ca if intercept else cb
    return float(np.sqrt(np.sum((c * rates * np.asarray(u_rel)) ** 2)))


def intercept_table_row(campaign: Campaign, rates: np.ndarray, K: float,
                        unit: str = "LSB") -> list[BudgetRow]:
    """The table's error at each set point moves F₀ (D.22) by K·Σ c_F0,j·Ω_j·δ_j. A relative error
    common to all set points cancels (Σ c_F0,j·Ω_j = 0 for a least-squares intercept); a fixed error
    of its own at each set point (uniform within its band, else the calibration's U/k) does not.
    Independent set points: u(F₀) = |K|·√Σ(c_F0,j·Ω_j·u_rel,j)²."""
    per_point = [rate_table_rel(campaign, float(r)) for r in rates]
    if any(x is None for x in per_point):
        return []
    u = abs(K) * through_fit(rates, [x[0] for x in per_point], intercept=True)
    table = campaign.equipment_for("rate_table")
    return [BudgetRow.type_b(msg("rate-table error at each set point, within its band, through "
                                 "D.22 ({table})",
                                 table=table.describe()),
                             "u(F₀)", Q_(u, unit), distribution="normal", k=1.0,
                             note=msg("a fixed error of its own at each Ω_ij, independent between "
                                      "set points; "
                                      "an error common to all cancels in the intercept"))]


def stability_row(campaign: Campaign, data: RateData) -> list[BudgetRow]:
    """Run-to-run change of K from the table: its ripple (rate stability, 速率平稳度 D.2.1.1 a))
    averaged over the n samples of each rate point, through the D.21 fit (a fixed error at a set
    point repeats in every run and cancels in K_r); with no bands stated, the calibration's U/k
    bounds it."""
    bands = [rate_band(campaign, float(r)) for r in data.rates]
    if any(b is None for b in bands):
        return rate_row(campaign,
                        msg("run to run (no rate bands stated: its calibration bounds it)"), 1.0,
                        "",
                         msg("bounds a table rate that differs between runs"))
    u = through_fit(data.rates, [b[1] / math.sqrt(m) for b, m in zip(bands, data.n)])
    return [BudgetRow.type_b(msg("rate-table ripple averaged over each rate point, through D.21, "
                                 "run to run "
                                 "({equipment})", equipment=bands[0][2].fields["equipment"]),
                             "u(δK/K)", Q_(u, ""),
                             distribution="normal", k=1.0,
                             note=msg("independent in each run; adds to the spread of the K_j"))]


def out_resolution_row(campaign: Campaign, c_norm: float, unit: str, what: str,
                       out: str) -> BudgetRow:
    """:func:`resolution_row` for an output in ``out`` (LSB, Hz, deg/s)."""
    if out == "LSB":
        return resolution_row(campaign, c_norm, unit, what)
    q = resolution(campaign, out)
    note = (msg("±half the stated resolution on each mean, independent") if q > 0 else
            msg("the device states no resolution of its {unit} output (device.resolution): none "
                "assumed",
                unit=unit_text(out)))
    return resolution_row(campaign, c_norm, unit, what, q=q, raw_unit=out, note=note)


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
        raise ProcedureError(f"D.21 gives K = {K!r} but the QR least squares "
                             f"{float(qr.coef[1])!r}; ill-conditioned rates?")
    ca, cb = F2.line_fit_sensitivities(w)
    uK, nuK = F2.propagate(cb, u, n - 1)
    uF0, nuF0 = F2.propagate(ca, u, n - 1)
    return ScaleFit(K, F0, uK, nuK, uF0, nuF0, float(qr.residual_sd), qr.dof)


def nonlinearity_of(data: RateData, upto: float | None = None) -> tuple[float, int, float,
                                                                        np.ndarray, float, float]:
    """D.23–D.25 on the rate points with |Ω| ≤ ``upto`` (all by default): (K_n, index j of the
    maximum within the selection, |F_m|, the selection mask, K, F_0).  F_m is the output at the
    largest rate of the selection, the larger of its two directions."""
    sel = np.ones(data.rates.size,
                  bool) if upto is None else np.abs(data.rates) <= upto * (1 + 1e-12)
    w, f = data.rates[sel], data.Fk[sel]
    K, F0 = F2.scale_factor_fit_d21_d22(w, f)
    top = np.abs(w) == np.abs(w).max()
    Fm = float(np.max(np.abs(f[top])))
    Kn, j = F2.nonlinearity_d24_d25(F2.fitted_output_d23(K, F0, w), f, Fm)
    return Kn, j, Fm, sel, K, F0


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
    rows = [BudgetRow.type_a(msg("mean outputs through F̂_j − F_kj at {rate:+g} °/s",
                                 rate=w[j]) if spread <= u else
                             msg("mean outputs through the largest |F̂_j − F_kj| (Monte Carlo over "
                                 "every point)"),
                             "√Σ(g_i·u(F̄_i))²/|F_m|" if spread <= u else "s(max_j |a_j|)",
                             Q_(max(u, spread), ""), nu),
            out_resolution_row(campaign, float(np.linalg.norm(g)) / Fm, "", "F̂_j − F_kj",
                               data.unit)]
    rows += rate_row(campaign, msg("at {rate:+g} °/s", rate=w[j]), K * abs(w[j]) / Fm, "",
                      msg("an error not proportional to Ω shows as nonlinearity; bounded by the "
                          "table's accuracy"),
                      rate=float(w[j]))
    return UncertaintyBudget("K_n", "ppm", rows, coverage=COVERAGE)


RATE_EQUIPMENT = (
    EquipmentRequirement("rate_table",
                         "rate table with rate output (D.2.1.1 a)); its rate accuracy enters the "
                         "budgets", required=True),
    EquipmentRequirement("counter", "gyro test system"),
)

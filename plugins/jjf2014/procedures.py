"""JJF 2014—2022 clause 7.2 procedures (one class per calibration item of table 3).

Each class names its clause and equations; the formulas live in :mod:`.formulas`, the
appendix-B-style budgets in :mod:`.budgets`.  Data model (segment ``kind`` and the
conditions each item reads) is in docs/standards/jjf2014.md.  The device's output is an
analog voltage: every segment has an ``output`` column in mV (the angular vibration
segments also a ``reference`` column in °/s from the table's reference sensor).
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import numpy as np
from metro.core import allan
from metro.core.budget import INF, BudgetRow
from metro.core.errors import DataError, ProcedureError
from metro.core.model import (
    Campaign,
    EquipmentRequirement,
    Metric,
    Option,
    Outcome,
    PlotSpec,
    Procedure,
    Result,
    Segment,
    SegmentRequirement,
    Step,
    TableSpec,
)
from metro.core.signals import device_scale_factor
from metro.core.sinefit import fit_sine, wrap_phase
from metro.core.units import Q_, parse_quantity

from . import budgets as B
from . import formulas as F

STANDARD = "jjf2014"
STATION = "simulated-jjf2014"
KU = "mV/(deg/s)"
AXES = ("X", "Y", "Z")

DEFAULT_RATES = "0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100"


def _floats(text: Any, what: str) -> list[float]:
    try:
        vals = [float(x) for x in str(text).replace(";", ",").split(",") if x.strip()]
    except ValueError as exc:
        raise ProcedureError(f"option {what}: {text!r} is not a comma-separated list of numbers") from exc
    if not vals:
        raise ProcedureError(f"option {what} is empty")
    return vals


def _magnitudes(text: Any, what: str) -> list[float]:
    """A list option of rate magnitudes (°/s), each applied in both directions (7.2.1.1 b),
    7.2.9, 7.2.10): every value positive and finite."""
    vals = _floats(text, what)
    if not all(v > 0 and math.isfinite(v) for v in vals):
        raise ProcedureError(f"option {what}: every value must be a positive magnitude in °/s, got {text!r}")
    return vals


def _q(v: float, unit: str) -> str:
    return f"{v:g} {unit}"


def _num(options: Mapping[str, Any], name: str, lo: float, *, integer: bool = False) -> float:
    """A numeric option, checked: ≥ ``lo`` and (when ``integer``) whole."""
    raw = options[name]
    try:
        v = float(raw)
    except (TypeError, ValueError) as exc:
        raise ProcedureError(f"option {name}: {raw!r} is not a number") from exc
    if not math.isfinite(v) or v < lo or (integer and v != int(v)):
        raise ProcedureError(f"option {name}: {raw!r} must be {'a whole number ' if integer else ''}≥ {lo:g}")
    return int(v) if integer else v


def _flag(options: Mapping[str, Any], name: str) -> bool:
    """An on/off option."""
    t = str(options[name]).strip().lower()
    if t in ("on", "true", "yes", "1"):
        return True
    if t in ("off", "false", "no", "0", ""):
        return False
    raise ProcedureError(f"option {name} must be on or off, got {options[name]!r}")


# ------------------------------------------------------------------------------- data access


def _output(seg: Segment, column: str = "output", unit: str = "mV") -> tuple[np.ndarray, float]:
    """The segment's column as floats in ``unit`` (checked finite) and its interval in s."""
    s = seg.series(column, unit)
    x = np.asarray(s.data.to(unit).magnitude, dtype=float)
    ok = np.isfinite(x)
    if not ok.all():
        i = int(np.argmin(ok))
        raise DataError(seg.file or f"segment {seg.id}", column, f"sample {i + 1} is {x[i]!r}")
    if x.size < 2:
        raise DataError(seg.file or f"segment {seg.id}", column, f"only {x.size} sample(s)")
    return x, float(s.interval.to("s").magnitude)


def _mean_u(seg: Segment) -> tuple[float, float, int]:
    """F̄ (eq. (2)), its standard uncertainty s/√N, and N."""
    x, _ = _output(seg)
    return F.mean_output_eq2(x), float(np.std(x, ddof=1) / math.sqrt(x.size)), x.size


def _cond_q(seg: Segment, name: str, unit: str) -> float:
    return float(seg.condition(name, unit).to(unit).magnitude)


def _need(campaign: Campaign, proc: type[Procedure], kind: str, **conditions) -> list[Segment]:
    segs = campaign.find_segments(kind, **conditions)
    if not segs:
        extra = ", ".join(f"{k} = {v!r}" for k, v in conditions.items())
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs segments of kind {kind!r}{' with ' + extra if extra else ''}; "
                        "none found",
                        hint=f"`metro plan --standard jjf2014 --item {proc.item}` lists what to measure")
    return segs


def _cal(campaign: Campaign, role: str):
    e = campaign.equipment_for(role)
    return None if e is None else e.calibration


def _by(segs: Iterable[Segment], name: str) -> dict[str, list[Segment]]:
    out: dict[str, list[Segment]] = {}
    for s in segs:
        out.setdefault(str(s.condition(name)), []).append(s)
    return out


def _axis(seg: Segment) -> str:
    a = str(seg.condition("axis")).strip().upper()
    if a not in AXES:
        raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.axis", f"must be X, Y or Z, got {a!r}")
    return a


def _phase(seg: Segment) -> str:
    p = str(seg.condition("phase")).strip().lower()
    if p not in ("before", "after"):
        raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.phase",
                        f"must be \"before\" or \"after\", got {p!r}")
    return p


def _updown(seg: Segment) -> str:
    o = str(seg.condition("orientation")).lower()
    if "up" in o:
        return "up"
    if "down" in o:
        return "down"
    raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.orientation",
                    f"must say up or down, got {o!r}")


# ------------------------------------------------------------------------------- scale factor sets


class SFSet:
    """One 7.2.1 calibration: the mean output at each input rate and the eq. (4)/(5) fit."""

    def __init__(self, segs: list[Segment]):
        if len(segs) < 3:
            raise DataError(segs[0].file if segs else None, "segments",
                            f"a scale-factor calibration needs at least 3 input rates, got {len(segs)}")
        rows = []
        for s in segs:
            om = _cond_q(s, "rate", "deg/s")
            fbar, u, n = _mean_u(s)
            rows.append((om, fbar, u, n, s.id))
        rows.sort(key=lambda r: r[0])
        self.omega = np.array([r[0] for r in rows])
        if np.unique(self.omega).size != self.omega.size:
            raise DataError(segs[0].file, "segments", "two segments of one calibration have the same input rate")
        self.F = np.array([r[1] for r in rows])
        self.uF = np.array([r[2] for r in rows])
        self.n = [r[3] for r in rows]
        self.ids = [r[4] for r in rows]
        try:
            self.fit = F.scale_factor_eq4_5(self.omega, self.F)
        except ValueError as exc:
            raise ProcedureError(f"7.2.1 fit: {exc}") from exc

    @property
    def K(self) -> float:
        return self.fit.K

    def budget(self, campaign: Campaign, warnings: list[str] | None = None):
        return B.scale_factor_budget(Q_(self.K, KU), Q_(self.fit.u_K, KU), self.fit.dof,
                                     rate_table=_cal(campaign, "rate-table"), dmm=_cal(campaign, "dmm"),
                                     warnings=warnings, rep_source="repeatability: residual scatter of the eq. (3) fit")


def _main_set(campaign: Campaign, proc) -> SFSet:
    return SFSet(_need(campaign, proc, "rate"))


def scale_factor_for(campaign: Campaign, proc) -> tuple[float, float, str]:
    """K (mV/[(°)/s]) and its relative standard uncertainty for items that divide by K: from
    the campaign's 7.2.1 segments (kind "rate") if any, else from ``device.scale_factor``."""
    if campaign.find_segments("rate"):
        s = SFSet(campaign.find_segments("rate"))
        b = s.budget(campaign)
        return s.K, float(b.combined.to(KU).magnitude) / abs(s.K), "7.2.1 segments of this campaign"
    K, urel = device_scale_factor(campaign.device, campaign.source)
    if K is None:
        raise DataError(campaign.source, "device.scale_factor",
                        f"{proc.qualified_id()} needs the scale factor K: give 7.2.1 segments (kind \"rate\") "
                        "or device.scale_factor in mV/((°)/s)")
    return float(parse_quantity(K, dimension=KU).to(KU).magnitude), urel, "device.scale_factor"


def _rate_steps(kind: str, rates: list[float], extra: Mapping[str, Any] | None = None, tag: str = "",
                seconds: float = 10.0) -> list[Step]:
    steps = []
    for r in rates:
        for sgn in (1, -1):
            c = {"rate": _q(sgn * r, "deg/s")} | dict(extra or {})
            sid = f"{kind}{tag}{'+' if sgn > 0 else '-'}{r:g}"
            steps.append(Step(sid, kind, f"table at {sgn * r:+g} °/s, record {seconds:g} samples at 1 s (7.2.1.1)",
                              Q_(seconds, "s"), Q_(1, "s"), c))
    return steps


RATE_OPTS = (Option("rates", DEFAULT_RATES, None, "input rate magnitudes (°/s), both directions (7.2.1.1 b))"),)


def _budget_row_a(source, symbol, u, unit, dof, note=""):
    return BudgetRow.type_a(source, symbol, Q_(u, unit), dof, note=note)


class _JJF(Procedure):
    standard = STANDARD
    station = STATION
    equipment = (
        EquipmentRequirement("rate-table", "rate table (table 2 no. 1); relative calibration U enters the budgets"),
        EquipmentRequirement("dmm", "data acquisition, 6½-digit DMM; relative calibration U enters the budgets"),
    )

    def _outcome(self, results, *, plots=(), tables=(), warnings=(), segments=(), opts=None) -> Outcome:
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=list(plots),
                       tables=list(tables), warnings=list(warnings), segments=list(segments),
                       options={k: str(v) for k, v in (opts or {}).items()})


def _sf_plots(s: SFSet) -> list[PlotSpec]:
    """7.2.1 figures: the mean outputs with the eq. (6) line, and the eq. (3) residuals v_i on
    their own axis (at the outputs' scale a residual of µV would be invisible)."""
    fit = s.fit
    return [PlotSpec("sf_fit", "Scale factor: mean outputs F̄_i (eq. (2)) and the fitted line F̂ = KΩ + F₀ (eq. (6))",
                     "input rate Ω (°/s)", "output (mV)",
                     [{"label": "F̄_i (eq. (2))", "x": s.omega.tolist(), "y": s.F.tolist(), "style": "o"},
                      {"label": f"F̂ = KΩ + F₀, K = {fit.K:.6g} mV/((°)/s), F₀ = {fit.F0:.4g} mV",
                       "x": s.omega.tolist(), "y": fit.predict(s.omega).tolist(), "style": "-"}]),
            PlotSpec("sf_residuals", "Scale factor: residuals v_i = F̄_i − (KΩ_i + F₀) of the eq. (3) fit",
                     "input rate Ω (°/s)", "residual v_i (mV)",
                     [{"label": "v_i", "x": s.omega.tolist(), "y": fit.residuals.tolist(), "style": "o",
                       "yerr": s.uF.tolist()},
                      {"label": "0", "x": [float(s.omega.min()), float(s.omega.max())], "y": [0.0, 0.0],
                       "style": ":"}])]


# =============================================================================== 7.2.1 – 7.2.4


class ScaleFactor(_JJF):
    """JJF 2014—2022 7.2.1 标度因数: K and F_0 by least squares, eqs. (2)–(5); budget B.1."""

    item = "7.2.1"
    title = "Scale factor (标度因数)"
    clause = "7.2.1"
    metrics = (Metric("K", "scale factor", "K", KU, "7.2.1.2", "4"),
               Metric("F0", "fitted zero (拟合零位)", "F₀", "mV", "7.2.1.2", "5"))
    requires = (SegmentRequirement("rate", "rate table at Ω_i, IRA ∥ table axis; ≥ 11 rates per direction incl. "
                                   "the maximum, ≥ 10 samples at 1 s each (7.2.1.1)", {"rate": "deg/s"},
                                   {"output": ("mV",)}, min_count=22),)
    options = RATE_OPTS

    def sequence(self, options):
        return _rate_steps("rate", _magnitudes(options["rates"], "rates"))

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        s = _main_set(campaign, type(self))
        npos, nneg = int(np.sum(s.omega > 0)), int(np.sum(s.omega < 0))
        if min(npos, nneg) < 11:
            w.append(f"7.2.1.1 b) asks for at least 11 rates per direction; got {npos} forward, {nneg} reverse")
        if min(s.n) < 10:
            w.append(f"7.2.1.1 c) asks for at least 10 samples per rate; the shortest segment has {min(s.n)}")
        bK = s.budget(campaign, w)
        bF0 = B.type_a_budget("fitted zero F0", "mV", [
            _budget_row_a("residual scatter of the eq. (3) fit", "u(F₀)", s.fit.u_F0, "mV", s.fit.dof),
            *B.relative_calibration_row("data acquisition, 6½-digit DMM", "u_DMM", _cal(campaign, "dmm"),
                                        Q_(s.fit.F0, "mV"))])
        res = [Result(self.metrics[0], Q_(s.K, KU), bK.combined, bK),
               Result(self.metrics[1], Q_(s.fit.F0, "mV"), bF0.combined, bF0)]
        tab = TableSpec("sf_points", "Mean output per input rate (eq. (2)) and residuals",
                        ["Ω_i (°/s)", "F̄_i (mV)", "u(F̄_i) (mV)", "v_i (mV)"],
                        [[f"{o:g}", f"{f:.6f}", f"{u:.2g}", f"{v:.3g}"]
                         for o, f, u, v in zip(s.omega, s.F, s.uF, s.fit.residuals)])
        return self._outcome(res, plots=_sf_plots(s), tables=[tab], warnings=w, segments=s.ids, opts=opts)


class NonlinearityRange(_JJF):
    """JJF 2014—2022 7.2.2 标度因数非线性度和量程: a_i eq. (7), K_n eq. (8); the range is the
    largest input rate whose span meets the nonlinearity requirement (7.2.2.2)."""

    item = "7.2.2"
    title = "Scale-factor nonlinearity and range (标度因数非线性度和量程)"
    clause = "7.2.2"
    metrics = (Metric("Kn", "scale-factor nonlinearity", "K_n", "", "7.2.2.2", "8"),
               Metric("range", "range (量程)", "Ω_max", "deg/s", "7.2.2.2", "prose after eq. 8"))
    requires = ScaleFactor.requires
    options = RATE_OPTS + (Option("nonlinearity_limit", "", None,
                                  "required K_n for the range (default: device.nonlinearity_spec)"),)

    def sequence(self, options):
        return ScaleFactor().sequence(options)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        s = _main_set(campaign, type(self))
        try:
            a, kn = F.nonlinearity_eq7_8(s.omega, s.F, s.fit)
        except ValueError as exc:
            raise ProcedureError(f"7.2.2: {exc}") from exc
        span = abs(s.omega.max() - s.omega.min())
        i = int(np.argmax(np.abs(a)))
        # u(a_i): the scatter of F̄_i (and of the fit) over K·span; the rate table's error at Ω_i
        u_pt = math.hypot(s.uF[i], s.fit.residuals.std(ddof=2) / math.sqrt(len(s.F))) / (s.K * span)
        cal = _cal(campaign, "rate-table")
        rows = [_budget_row_a("scatter of F̄_i at the worst point and of the fit", "u(a_i)", u_pt, "", s.fit.dof)]
        if cal is not None and cal.uncertainty.dimensionless:
            rows.append(BudgetRow.from_calibration("rate table error at Ω_i", "u_rel(Ω)", cal,
                                                   sensitivity=Q_(abs(s.omega[i]) / span, "")))
        bkn = B.type_a_budget("nonlinearity Kn", "", rows)
        limit_txt = opts["nonlinearity_limit"] or campaign.device.properties.get("nonlinearity_spec")
        results = [Result(self.metrics[0], Q_(kn, ""), bkn.combined, bkn)]
        if limit_txt in (None, ""):
            w.append("no nonlinearity requirement given (option nonlinearity_limit or device.nonlinearity_spec): "
                     "the range is not determined")
        else:
            limit = float(parse_quantity(limit_txt, dimension="").to("").magnitude)
            rng, kn_r = F.range_from_nonlinearity(s.omega, s.F, limit)
            if rng is None:
                w.append(f"no symmetric span meets K_n ≤ {limit:g}: the range is not determined")
            else:
                rr = B.relative_calibration_row("rate table (the range is a set table rate)", "u_rel(Ω)", cal,
                                                Q_(rng, "deg/s"), w)
                br = B.type_a_budget("range", "deg/s", rr) if rr else None
                results.append(Result(self.metrics[1], Q_(rng, "deg/s"), br.combined if br else None, br,
                                       note=f"K_n = {kn_r:.3g} ≤ {limit:g} over ±{rng:g} °/s"))
        tab = TableSpec("nonlinearity", "Point nonlinearity a_i (eq. (7))", ["Ω_i (°/s)", "a_i"],
                        [[f"{o:g}", f"{x:.3e}"] for o, x in zip(s.omega, a)])
        return self._outcome(results, tables=[tab], warnings=w, segments=s.ids, opts=opts)


class Asymmetry(_JJF):
    """JJF 2014—2022 7.2.3 标度因数不对称度: K_+, K_− by eq. (4) on each direction, K_a eq. (9)."""

    item = "7.2.3"
    title = "Scale-factor asymmetry (标度因数不对称度)"
    clause = "7.2.3"
    metrics = (Metric("Ka", "scale-factor asymmetry", "K_a", "", "7.2.3.2", "9"),)
    requires = ScaleFactor.requires
    options = RATE_OPTS

    def sequence(self, options):
        return ScaleFactor().sequence(options)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        s = _main_set(campaign, type(self))
        pos, neg = s.omega > 0, s.omega < 0
        if pos.sum() < 3 or neg.sum() < 3:
            raise DataError(campaign.source, "segments", "7.2.3 needs at least 3 forward and 3 reverse rates")
        fp = F.scale_factor_eq4_5(s.omega[pos], s.F[pos])
        fm = F.scale_factor_eq4_5(s.omega[neg], s.F[neg])
        ka = F.asymmetry_eq9(fp.K, fm.K, s.K)
        u = math.hypot(fp.u_K, fm.u_K) / abs(s.K)
        dof = u**4 / ((fp.u_K / s.K) ** 4 / fp.dof + (fm.u_K / s.K) ** 4 / fm.dof) if u > 0 else INF
        b = B.type_a_budget("asymmetry Ka", "", [
            _budget_row_a("fits of K₊ and K₋ (eq. (4) per direction)", "√(u²(K₊)+u²(K₋))/K", u, "", dof,
                          note="the rate table and DMM errors are common to K₊, K₋ and K and cancel in eq. (9)")])
        return self._outcome([Result(self.metrics[0], Q_(ka, ""), b.combined, b,
                                     note=f"K₊ = {fp.K:.7g}, K₋ = {fm.K:.7g} mV/((°)/s)")],
                             segments=s.ids, opts=opts)


class Repeatability(_JJF):
    """JJF 2014—2022 7.2.4 标度因数重复性: Q calibrations by 7.2.1, K_r eq. (10)."""

    item = "7.2.4"
    title = "Scale-factor repeatability (标度因数重复性)"
    clause = "7.2.4"
    metrics = (Metric("Kr", "scale-factor repeatability", "K_r", "", "7.2.4.2", "10"),)
    requires = (SegmentRequirement("rate-repeat", "7.2.1 repeated Q times, power off between runs", {"rate": "deg/s",
                                   "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("runs", 6, None, "number of calibrations Q"),)

    def sequence(self, options):
        steps = []
        for q in range(1, _num(options, "runs", 2, integer=True) + 1):
            steps += _rate_steps("rate-repeat", _magnitudes(options["rates"], "rates"), {"run": str(q)}, tag=f"#{q}")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        runs = _by(_need(campaign, type(self), "rate-repeat"), "run")
        if len(runs) < 2:
            raise DataError(campaign.source, "segments", f"7.2.4 needs Q ≥ 2 runs (condition run), got {len(runs)}")
        sets = {r: SFSet(g) for r, g in sorted(runs.items())}
        Ks = [s.K for s in sets.values()]
        kr = F.relative_repeatability_eq10(Ks)
        u, dof = B.std_of_std(kr, len(Ks))
        b = B.type_a_budget("repeatability Kr", "", [
            _budget_row_a("sampling of a standard deviation of Q values", "K_r/√(2(Q−1))", u, "", dof)])
        tab = TableSpec("sf_runs", "K_i per calibration", ["run", "K_i (mV/((°)/s))", "u(K_i) fit"],
                        [[r, f"{s.K:.7g}", f"{s.fit.u_K:.2g}"] for r, s in sets.items()])
        return self._outcome([Result(self.metrics[0], Q_(kr, ""), b.combined, b)], tables=[tab],
                             segments=[i for s in sets.values() for i in s.ids], opts=opts)


# =============================================================================== 7.2.5 – 7.2.8


def _distinct(campaign: Campaign, values: np.ndarray, what: str) -> None:
    """Levels applied in decreasing order must differ (two records of one level: which one?)."""
    mags = np.abs(values)
    if np.unique(mags).size != mags.size:
        dup = sorted({float(v) for v in mags if np.sum(mags == v) > 1})
        raise DataError(campaign.source, "segments", f"{what}: the level(s) {', '.join(f'{v:g}' for v in dup)} "
                        "°/s appear more than once; give one record per level")


def _temperatures(groups: Mapping[str, list[Segment]], what: str) -> dict[str, float]:
    """The chamber temperature (°C) of each group, parsed from its first segment's condition;
    two groups at the same temperature (e.g. "20 °C" and "20 degC") are an error."""
    T = {k: _cond_q(g[0], "temperature", "degC") for k, g in groups.items()}
    seen: dict[float, str] = {}
    for k, t in T.items():
        if t in seen:
            raise DataError(_where(groups[k][0]), f"segments.{groups[k][0].id}.conditions.temperature",
                            f"{what}: {k!r} and {seen[t]!r} are the same temperature; one calibration per point")
        seen[t] = k
    return T


def _where(seg: Segment) -> str:
    return seg.file or seg.id


def _room_index(temps: list[float], Tm: float, what: str) -> int:
    i = int(np.argmin([abs(t - Tm) for t in temps]))
    if abs(temps[i] - Tm) > 2.0:
        raise DataError(None, "segments.conditions.temperature",
                        f"{what} needs a point at room temperature T_m = {Tm:g} °C (within 2 °C); "
                        f"temperatures given: {', '.join(f'{t:g}' for t in temps)}")
    return i


def _chamber_rows(campaign, sens: float, unit: str) -> list[BudgetRow]:
    cal = _cal(campaign, "chamber")
    if cal is None or cal.uncertainty.dimensionless:
        return []
    return [BudgetRow.from_calibration("chamber temperature T_i (table 2 no. 2)", "u(T_i)", cal,
                                       sensitivity=Q_(abs(sens), f"{unit}/delta_degC"))]


class SFTemperature(_JJF):
    """JJF 2014—2022 7.2.5 标度因数温度灵敏度: K_i at each temperature by 7.2.1, K_t eq. (11)."""

    item = "7.2.5"
    title = "Scale-factor temperature sensitivity (标度因数温度灵敏度)"
    clause = "7.2.5"
    metrics = (Metric("Kt", "scale-factor temperature sensitivity", "K_t", "1/delta_degC", "7.2.5.2", "11"),)
    requires = (SegmentRequirement("rate-temperature", "7.2.1 at each chamber temperature incl. room temperature",
                                   {"rate": "deg/s", "temperature": "degC"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("temperatures", "-40, -10, 20, 40, 60", None, "chamber points (°C), R5-like"),
                           Option("room_temperature", "20 °C", "degC", "T_m"))

    def sequence(self, options):
        steps = []
        for T in _floats(options["temperatures"], "temperatures"):
            steps += _rate_steps("rate-temperature", _magnitudes(options["rates"], "rates"),
                                 {"temperature": _q(T, "degC")}, tag=f"@{T:g}C")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        groups = _by(_need(campaign, type(self), "rate-temperature"), "temperature")
        T = _temperatures(groups, "7.2.5")
        keys = sorted(groups, key=T.get)
        temps = [T[k] for k in keys]
        if len(keys) < 2:
            raise DataError(campaign.source, "segments", "7.2.5 needs at least 2 temperatures")
        sets = [SFSet(groups[k]) for k in keys]
        m = _room_index(temps, float(opts["room_temperature"].to("degC").magnitude), "7.2.5")
        Ks = [s.K for s in sets]
        kt, i = F.sf_temperature_eq11(Ks, temps, m)
        dT = temps[i] - temps[m]
        # Kt = |K_i/K_m − 1|/|ΔT|: ∂/∂K_i = 1/(K_m|ΔT|), ∂/∂K_m ≈ K_i/(K_m²|ΔT|)
        rows = [_budget_row_a(f"fit of K_i at {temps[i]:g} °C", "u(K_i)/(K_m|ΔT|)",
                              sets[i].fit.u_K / (Ks[m] * abs(dT)), "1/delta_degC", sets[i].fit.dof),
                _budget_row_a(f"fit of K_m at {temps[m]:g} °C", "K_i·u(K_m)/(K_m²|ΔT|)",
                              Ks[i] * sets[m].fit.u_K / (Ks[m] ** 2 * abs(dT)), "1/delta_degC", sets[m].fit.dof)]
        rows += _chamber_rows(campaign, kt / abs(dT) * math.sqrt(2), "1/delta_degC")
        b = B.type_a_budget("Kt", "1/delta_degC", rows)
        tab = TableSpec("sf_temperature", "K_i per temperature", ["T_i (°C)", "K_i (mV/((°)/s))"],
                        [[f"{t:g}", f"{k:.7g}"] for t, k in zip(temps, Ks)])
        return self._outcome([Result(self.metrics[0], Q_(kt, "1/delta_degC"), b.combined, b,
                                     note=f"maximum at T_i = {temps[i]:g} °C, T_m = {temps[m]:g} °C")],
                             tables=[tab], segments=[x for s in sets for x in s.ids], opts=opts)


class SFAxialAcceleration(_JJF):
    """JJF 2014—2022 7.2.6 标度因数轴向加速度敏感度: K with the IRA up and down (±1 g along the
    input axis), (K_up − K_down)/2 g (7.2.6.2)."""

    item = "7.2.6"
    title = "Scale-factor axial-acceleration sensitivity (标度因数轴向加速度敏感度)"
    clause = "7.2.6"
    metrics = (Metric("Kg", "scale-factor axial-acceleration sensitivity", "K_g", "mV/(deg/s)/gn", "7.2.6.2", "prose, no eq. number"),)
    requires = (SegmentRequirement("rate-accel", "7.2.1 with the IRA pointing up and down", {"rate": "deg/s",
                                   "orientation": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS

    def sequence(self, options):
        steps = []
        for o in ("IRA up", "IRA down"):
            steps += _rate_steps("rate-accel", _magnitudes(options["rates"], "rates"), {"orientation": o},
                                 tag=f"[{o.split()[1]}]")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        segs = _need(campaign, type(self), "rate-accel")
        g: dict[str, list[Segment]] = {}
        for s in segs:
            g.setdefault(_updown(s), []).append(s)
        if set(g) != {"up", "down"}:
            raise DataError(campaign.source, "segments", "7.2.6 needs calibrations with the IRA up and with it down")
        up, dn = SFSet(g["up"]), SFSet(g["down"])
        kg = F.per_g_726(up.K, dn.K)
        b = B.type_a_budget("Kg", "mV/(deg/s)/gn", [
            _budget_row_a("fit of K (IRA up)", "u(K_up)/2g", up.fit.u_K / 2, "mV/(deg/s)/gn", up.fit.dof),
            _budget_row_a("fit of K (IRA down)", "u(K_down)/2g", dn.fit.u_K / 2, "mV/(deg/s)/gn", dn.fit.dof),
            *B.relative_calibration_row("rate table (common to both, acts on the difference)", "u_rel(Ω)",
                                        _cal(campaign, "rate-table"), Q_(kg, "mV/(deg/s)/gn"))])
        return self._outcome([Result(self.metrics[0], Q_(kg, "mV/(deg/s)/gn"), b.combined, b,
                                     note=f"K_up = {up.K:.7g}, K_down = {dn.K:.7g} mV/((°)/s)")],
                             segments=up.ids + dn.ids, opts=opts)


class _SFChange(_JJF):
    kind = ""
    what = ""

    def sequence(self, options):
        steps = []
        for a in AXES:
            for p in ("before", "after"):
                steps += _rate_steps(self.kind, _magnitudes(options["rates"], "rates"), {"axis": a, "phase": p},
                                     tag=f"[{a}-{p}]")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        sets: dict[tuple[str, str], list[Segment]] = {}
        for s in _need(campaign, type(self), self.kind):
            sets.setdefault((_axis(s), _phase(s)), []).append(s)
        fits = {k: SFSet(v) for k, v in sets.items()}
        before = {a: fits[(a, "before")].K for a in AXES if (a, "before") in fits}
        after = {a: fits[(a, "after")].K for a in AXES if (a, "after") in fits}
        try:
            dk, worst, per = F.max_change_eq12_13(before, after)
        except ValueError as exc:
            raise DataError(campaign.source, "segments", f"{self.item}: {exc}") from exc
        w = [] if len(per) == 3 else [f"only the axes {', '.join(per)} were tested (the clause asks for X, Y, Z)"]
        f1, f2 = fits[(worst, "before")].fit, fits[(worst, "after")].fit
        b = B.type_a_budget(self.metrics[0].key, KU, [
            _budget_row_a(f"fit of K before ({worst})", "u(K₁)", f1.u_K, KU, f1.dof),
            _budget_row_a(f"fit of K after ({worst})", "u(K₂)", f2.u_K, KU, f2.dof),
            *B.relative_calibration_row("rate table (common, acts on the difference)", "u_rel(Ω)",
                                        _cal(campaign, "rate-table"), Q_(dk, KU))])
        tab = TableSpec("per_axis", f"K before/after {self.what} per axis",
                        ["axis", "K₁ (mV/((°)/s))", "K₂ (mV/((°)/s))", "|ΔK|"],
                        [[a, f"{before[a]:.7g}", f"{after[a]:.7g}", f"{per[a]:.3g}"] for a in per])
        return self._outcome([Result(self.metrics[0], Q_(dk, KU), b.combined, b, note=f"largest on axis {worst}")],
                             tables=[tab], warnings=w, segments=[i for s in fits.values() for i in s.ids], opts=opts)


class SFShock(_SFChange):
    """JJF 2014—2022 7.2.7 标度因数冲击前后变化量: ΔK_ij = |K_ij2 − K_ij1| eq. (12), max over X, Y, Z eq. (13)."""

    item = "7.2.7"
    title = "Scale-factor change after shock (标度因数冲击前后变化量)"
    clause = "7.2.7"
    kind = "rate-shock"
    what = "shock"
    metrics = (Metric("dK_shock", "scale-factor change after shock", "ΔK_i", KU, "7.2.7.2", "12, 13"),)
    requires = (SegmentRequirement("rate-shock", "7.2.1 before and after a shock on each axis",
                                   {"rate": "deg/s", "axis": "", "phase": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS


class SFVibration(_SFChange):
    """JJF 2014—2022 7.2.8 标度因数振动前后变化量: ΔK_vj eq. (14), max over X, Y, Z eq. (15)."""

    item = "7.2.8"
    title = "Scale-factor change after vibration (标度因数振动前后变化量)"
    clause = "7.2.8"
    kind = "rate-vibration"
    what = "vibration"
    metrics = (Metric("dK_vib", "scale-factor change after vibration", "ΔK_v", KU, "7.2.8.2", "14, 15"),)
    requires = (SegmentRequirement("rate-vibration", "7.2.1 before and after vibration on each axis",
                                   {"rate": "deg/s", "axis": "", "phase": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS


# =============================================================================== 7.2.9, 7.2.10


def _grid_result(metric, cands: dict[str, tuple[float, float | None]], campaign, what: str):
    """Result for a grid-searched quantity: the larger |candidate| of the two directions, as
    7.2.9.1 f) / 7.2.10.1 g) report it.  The candidate meets eq. (17)/(18) and the next smaller
    level does not, so the true value lies in (next level, candidate] (or (0, candidate] when
    every level passed): the candidate errs by 0 … one step, always upward.  Its standard
    uncertainty about the candidate is the RMS of that one-sided error, step/√3, written as a
    uniform of half-width one step (interpretations.md, "7.2.9 / 7.2.10")."""
    d = max(cands, key=lambda k: abs(cands[k][0]))
    val, nxt = cands[d]
    step = abs(val) - abs(nxt) if nxt is not None else abs(val)
    rows = [BudgetRow.type_b(f"step of the {what} levels ({d}): true value in (next level, candidate]", "Δ",
                             Q_(step, "deg/s"), distribution="uniform",
                             note="one-sided: the candidate errs by 0 … Δ, u = Δ/√3")]
    rows += B.relative_calibration_row("rate table at low rate", "u_rel(Ω)", _cal(campaign, "rate-table"),
                                       Q_(abs(val), "deg/s"))
    b = B.type_a_budget(metric.key, "deg/s", rows)
    return Result(metric, Q_(abs(val), "deg/s"), b.combined, b, note=f"larger in the {d} direction")


class Threshold(_JJF):
    """JJF 2014—2022 7.2.9 阈值: decreasing rates in each direction; F̂_i = KΩ_i (16);
    candidate = the last rate meeting |(F̂_i − F_i)/F̂_i| ≤ 50 % (17) with F_i the output minus
    the zero-input mean; threshold = the larger |candidate| of the two directions (7.2.9.1 f))."""

    item = "7.2.9"
    title = "Threshold (阈值)"
    clause = "7.2.9"
    metrics = (Metric("threshold", "threshold", "Ω_th", "deg/s", "7.2.9.2", "16, 17"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "threshold", "table at decreasing small rates Ω_i in each direction, and at rest (rate 0)",
        {"rate": "deg/s"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("levels", "0.1, 0.05, 0.03, 0.02, 0.015, 0.01, 0.007, 0.005, 0.003", None,
                                  "small rates (°/s), largest first"),
                           Option("seconds", 200, None, "record length per level (s at 1 s)"))

    def sequence(self, options):
        n = _num(options, "seconds", 2)
        steps = ScaleFactor().sequence(options)
        steps.append(Step("threshold-0", "threshold", "table at rest (zero input)", Q_(n, "s"), Q_(1, "s"),
                          {"rate": "0 deg/s"}))
        for r in _magnitudes(options["levels"], "levels"):
            for sgn in (1, -1):
                steps.append(Step(f"threshold{'+' if sgn > 0 else '-'}{r:g}", "threshold", f"table at {sgn * r:+g} °/s",
                                  Q_(n, "s"), Q_(1, "s"), {"rate": _q(sgn * r, "deg/s")}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, _, _ = scale_factor_for(campaign, type(self))
        segs = _need(campaign, type(self), "threshold")
        zero = [s for s in segs if _cond_q(s, "rate", "deg/s") == 0.0]
        if not zero:
            raise DataError(campaign.source, "segments", "7.2.9 needs a zero-input segment (kind threshold, rate 0)")
        f0 = np.mean([_mean_u(s)[0] for s in zero])
        cands = {}
        rows = []
        for name, sgn in (("forward", 1), ("reverse", -1)):
            d = sorted([s for s in segs if sgn * _cond_q(s, "rate", "deg/s") > 0],
                       key=lambda s: -abs(_cond_q(s, "rate", "deg/s")))
            if len(d) < 2:
                raise DataError(campaign.source, "segments", f"7.2.9 needs at least 2 {name} levels")
            om = np.array([_cond_q(s, "rate", "deg/s") for s in d])
            _distinct(campaign, om, f"7.2.9 {name} levels (condition rate)")
            fc = np.array([_mean_u(s)[0] - f0 for s in d])
            c, i = F.threshold_eq16_17(om, fc, K)
            if c is None:
                raise ProcedureError(f"7.2.9: already the largest {name} level {om[0]:g} °/s fails eq. (17)",
                                     hint="start the decreasing sequence at a larger rate (option levels)")
            cands[name] = (c, float(om[i + 1]) if i + 1 < om.size else None)
            rows += [[name, f"{o:g}", f"{K * o:.4g}", f"{x:.4g}", f"{abs((K * o - x) / (K * o)) * 100:.1f}"]
                     for o, x in zip(om, fc)]
        res = _grid_result(self.metrics[0], cands, campaign, "threshold")
        tab = TableSpec("threshold", "Eq. (17) per level", ["direction", "Ω_i (°/s)", "F̂_i (mV)", "F_i (mV)",
                                                             "|F̂−F|/F̂ (%)"], rows)
        return self._outcome([res], tables=[tab], segments=[s.id for s in segs], opts=opts)


class Resolution(_JJF):
    """JJF 2014—2022 7.2.10 分辨率: increments ΔΩ_i on a base rate 20–50× the threshold;
    ΔF̂_i = KΔΩ_i by eq. (6); candidate = last increment meeting eq. (18); resolution = the
    larger |candidate| of the two directions (7.2.10.1 g))."""

    item = "7.2.10"
    title = "Resolution (分辨率)"
    clause = "7.2.10"
    metrics = (Metric("resolution", "resolution", "Ω_res", "deg/s", "7.2.10.2", "18"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "resolution", "base rate Ω_b and Ω_b + ΔΩ_i for decreasing increments, each direction",
        {"base_rate": "deg/s", "increment": "deg/s"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("base_rate", "0.3 deg/s", "deg/s", "base rate (20–50× the estimated threshold)"),
                           Option("increments", "0.05, 0.02, 0.01, 0.007, 0.005, 0.003, 0.002, 0.001", None,
                                  "increments (°/s), largest first"),
                           Option("seconds", 200, None, "record length per level (s at 1 s)"))

    def sequence(self, options):
        n = _num(options, "seconds", 2)
        base = float(options["base_rate"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for sgn, d in ((1, "+"), (-1, "-")):
            steps.append(Step(f"resolution{d}base", "resolution", f"base rate {sgn * base:+g} °/s", Q_(n, "s"),
                              Q_(1, "s"), {"base_rate": _q(sgn * base, "deg/s"), "increment": "0 deg/s"}))
            for r in _magnitudes(options["increments"], "increments"):
                steps.append(Step(f"resolution{d}{r:g}", "resolution", f"base {sgn * base:+g} °/s + {sgn * r:+g} °/s",
                                  Q_(n, "s"), Q_(1, "s"),
                                  {"base_rate": _q(sgn * base, "deg/s"), "increment": _q(sgn * r, "deg/s")}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, _, _ = scale_factor_for(campaign, type(self))
        segs = _need(campaign, type(self), "resolution")
        cands, rows = {}, []
        for name, sgn in (("forward", 1), ("reverse", -1)):
            mine = [s for s in segs if sgn * _cond_q(s, "base_rate", "deg/s") > 0]
            base = [s for s in mine if _cond_q(s, "increment", "deg/s") == 0.0]
            inc = sorted([s for s in mine if _cond_q(s, "increment", "deg/s") != 0.0],
                         key=lambda s: -abs(_cond_q(s, "increment", "deg/s")))
            if not base or len(inc) < 2:
                raise DataError(campaign.source, "segments",
                                f"7.2.10 needs, in the {name} direction, a base segment (increment 0) and ≥ 2 increments")
            fb = _mean_u(base[0])[0]
            dom = np.array([_cond_q(s, "increment", "deg/s") for s in inc])
            _distinct(campaign, dom, f"7.2.10 {name} increments (condition increment)")
            if len(base) > 1:
                raise DataError(campaign.source, "segments", f"7.2.10: {len(base)} {name} base segments (increment 0); "
                                "give one")
            dF = np.array([_mean_u(s)[0] - fb for s in inc])
            c, i = F.resolution_eq18(dom, dF, K)
            if c is None:
                raise ProcedureError(f"7.2.10: already the largest {name} increment {dom[0]:g} °/s fails eq. (18)")
            cands[name] = (c, float(dom[i + 1]) if i + 1 < dom.size else None)
            rows += [[name, f"{o:g}", f"{K * o:.4g}", f"{x:.4g}"] for o, x in zip(dom, dF)]
        res = _grid_result(self.metrics[0], cands, campaign, "increment")
        tab = TableSpec("resolution", "Eq. (18) per increment", ["direction", "ΔΩ_i (°/s)", "ΔF̂_i (mV)", "ΔF_i (mV)"],
                        rows)
        return self._outcome([res], tables=[tab], segments=[s.id for s in segs], opts=opts)


# =============================================================================== 7.2.11, 7.2.12


def _misalignment_run(campaign, proc, segs: list[Segment], K: float, uK_rel: float):
    Fm: dict[tuple[int, str], float] = {}
    uF: dict[tuple[int, str], float] = {}
    omegas = set()
    for s in segs:
        ptxt = str(s.condition("position")).strip()
        p = int(ptxt) if ptxt in ("1", "2", "3", "4") else 0
        if not p:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions.position",
                            f"must be 1, 2, 3 or 4 (the four mountings of 7.2.11.1), got {ptxt!r}")
        om = _cond_q(s, "rate", "deg/s")
        if om == 0:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions.rate", "must be ±Ω_(+), not 0")
        key = (p, "+" if om > 0 else "-")
        if key in Fm:
            raise DataError(s.file or s.id, f"segments.{s.id}.conditions",
                            f"two records of position {p} turning {'forward' if key[1] == '+' else 'reverse'} in one run")
        Fm[key], uF[key], _ = _mean_u(s)
        omegas.add(abs(om))
    missing = [f"{p}{d}" for p in (1, 2, 3, 4) for d in "+-" if (p, d) not in Fm]
    if missing:
        raise DataError(campaign.source, "segments", f"7.2.11 needs all four positions in both directions; "
                        f"missing {', '.join(missing)}")
    if len(omegas) != 1:
        raise DataError(campaign.source, "segments", "7.2.11: all records must use the same table rate Ω_(+)")
    om = omegas.pop()
    r = F.misalignment_eq19_25(Fm, om, K)
    # u(α) from the four means of positions 1, 2: each δ has u = √(u²(F+) + u²(F−))/(2ΩK)
    ud = {p: math.hypot(uF[(p, "+")], uF[(p, "-")]) / (2 * om * K) for p in (1, 2, 3, 4)}
    ua, ub = math.hypot(ud[1], ud[2]) / 2, math.hypot(ud[3], ud[4]) / 2
    g_rad = math.hypot(r["alpha"], r["beta"])
    to_arcmin = 10800.0 / math.pi
    u_noise = (math.hypot(r["alpha"] * ua, r["beta"] * ub) / g_rad if g_rad > 0 else math.hypot(ua, ub)) * to_arcmin
    return r, u_noise, om


class Misalignment(_JJF):
    """JJF 2014—2022 7.2.11 输入轴失准角: four mountings, δ_p eqs. (19), (20), (22), (23),
    α_m (21), β_m (24), γ_m = 10800√(α_m² + β_m²)/π in ′ (25)."""

    item = "7.2.11"
    title = "Input-axis misalignment (输入轴失准角)"
    clause = "7.2.11"
    metrics = (Metric("gamma", "input-axis misalignment", "γ_m", "arcmin", "7.2.11.2", "25"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "misalignment", "positions 1–4 (OY up, +180° about IRA, OX up, +180°), table ±Ω for 1 min",
        {"position": "", "rate": "deg/s", "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("table_rate", "360 deg/s", "deg/s", "Ω_(+) (7.2.11.1 b))"),)
    runs_default = 1

    def _steps(self, options, runs):
        om = float(options["table_rate"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for q in range(1, runs + 1):
            for p in (1, 2, 3, 4):
                for sgn in (1, -1):
                    steps.append(Step(f"misalignment#{q}p{p}{'+' if sgn > 0 else '-'}", "misalignment",
                                      f"run {q}, position {p}, table {sgn * om:+g} °/s, 1 min", Q_(60, "s"),
                                      Q_(1, "s"), {"position": str(p), "rate": _q(sgn * om, "deg/s"), "run": str(q)}))
        return steps

    def sequence(self, options):
        return self._steps(options, 1)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        segs = _need(campaign, type(self), "misalignment")
        runs = _by(segs, "run") if all("run" in s.conditions for s in segs) else {"1": segs}
        first = sorted(runs)[0]
        r, u_noise, om = _misalignment_run(campaign, type(self), runs[first], K, uK)
        gamma = r["gamma"]
        rows = [_budget_row_a("scatter of the eight mean outputs", "u_A", u_noise, "arcmin", INF),
                BudgetRow.type_b("scale factor K (γ ∝ 1/K)", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                                 sensitivity=Q_(gamma, "arcmin"))]
        rows += B.relative_calibration_row("rate table Ω_(+) (γ ∝ 1/Ω)", "u_rel(Ω)", _cal(campaign, "rate-table"),
                                           Q_(gamma, "arcmin"))
        b = B.type_a_budget("gamma", "arcmin", rows)
        note = (f"α_m = {r['alpha'] * 10800 / math.pi:.4g}′, β_m = {r['beta'] * 10800 / math.pi:.4g}′ "
                f"(run {first}, Ω = {om:g} °/s)")
        return self._outcome([Result(self.metrics[0], Q_(gamma, "arcmin"), b.combined, b, note=note)],
                             segments=[s.id for s in runs[first]], opts=opts)


class MisalignmentRepeatability(Misalignment):
    """JJF 2014—2022 7.2.12 输入轴失准角重复性: 7.2.11 repeated Q ≥ 7 times, γ_mr eq. (26)."""

    item = "7.2.12"
    title = "Input-axis misalignment repeatability (输入轴失准角重复性)"
    clause = "7.2.12"
    metrics = (Metric("gamma_r", "input-axis misalignment repeatability", "γ_mr", "arcmin", "7.2.12.2", "26"),)
    options = Misalignment.options + (Option("runs", 7, None, "Q (≥ 7)"),)

    def sequence(self, options):
        return self._steps(options, _num(options, "runs", 7, integer=True))

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        runs = _by(_need(campaign, type(self), "misalignment"), "run")
        if len(runs) < 7:
            raise DataError(campaign.source, "segments",
                            f"7.2.12 needs Q ≥ 7 repetitions of 7.2.11 (condition run); got {len(runs)}")
        gam = [_misalignment_run(campaign, type(self), g, K, uK)[0]["gamma"] for _, g in sorted(runs.items())]
        gr = F.std_bessel(gam, "eq. (26)", 7)
        u, dof = B.std_of_std(gr, len(gam))
        b = B.type_a_budget("gamma_r", "arcmin", [_budget_row_a("sampling of a standard deviation of Q values",
                                                                "γ_mr/√(2(Q−1))", u, "arcmin", dof)])
        tab = TableSpec("gamma_runs", "γ_mi per run", ["run", "γ_mi (′)"],
                        [[k, f"{g:.4f}"] for k, g in zip(sorted(runs), gam)])
        return self._outcome([Result(self.metrics[0], Q_(gr, "arcmin"), b.combined, b)], tables=[tab],
                             segments=[s.id for g in runs.values() for s in g], opts=opts)


# =============================================================================== 7.2.13 – 7.2.19


STATIC_STEP_DESC = "IRA vertical on the base, warm-up ≤ 30 min, record (7.2.13.1)"
EARTH_OPT = Option("earth_rate", "off", None,
                   "on: subtract 15.041·sin(latitude) °/h for IRA up (add for down); the standard has no such term")


def _static(campaign: Campaign, proc, warnings: list[str]) -> Segment:
    """The 7.2.13.1 record: the one segment of kind "static" (several: the first, with a warning)."""
    segs = _need(campaign, proc, "static")
    if len(segs) > 1:
        warnings.append(f"{len(segs)} segments of kind static; {proc.item} uses the first, {segs[0].id!r}")
    return segs[0]


def _earth_term(campaign, seg: Segment | None, on: str, orient: str | None = None) -> float:
    """Earth-rate correction (°/h) to subtract; 0 unless the option is on (README reading note)."""
    if not _flag({"earth_rate": on}, "earth_rate"):
        return 0.0
    lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    o = orient or (str(seg.conditions.get("orientation", "IRA up")).lower() if seg is not None else "ira up")
    sign = -1.0 if "down" in o else 1.0
    return sign * F.EARTH_RATE_DEG_PER_H * math.sin(math.radians(lat))


class BiasValue:
    """B_0 of one static segment (eqs. (27), (28)) in °/h with its batch-means type A u."""

    def __init__(self, seg: Segment, K: float, earth: float = 0.0, batches: int = 20):
        x, dt = _output(seg)
        if x.size < 2 * batches:
            raise DataError(seg.file or seg.id, "output", f"{x.size} samples are too few for {batches} batch means")
        self.seg, self.x, self.dt = seg, x, dt
        self.Fbar = F.mean_output_eq2(x)
        self.B0 = F.bias_eq27_28(x, K) * 3600.0 - earth  # °/h
        sd, nb = allan.block_std(x, x.size // batches)
        self.uA = sd / math.sqrt(nb) / abs(K) * 3600.0
        self.dof = nb - 1


class Bias(_JJF):
    """JJF 2014—2022 7.2.13 零偏: B_0 = F̄/K, eqs. (27), (28); budget B.2 (plus the type A
    scatter of F̄).  No earth-rate term unless option earth_rate = on."""

    item = "7.2.13"
    title = "Bias (零偏)"
    clause = "7.2.13"
    metrics = (Metric("B0", "bias", "B₀", "deg/h", "7.2.13.2", "28"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static", STATIC_STEP_DESC, {"orientation": ""},
                                                          {"output": ("mV",)}, min_duration=Q_(1, "h")),)
    options = RATE_OPTS + (EARTH_OPT, Option("batches", 20, None, "batch means for the type A uncertainty", minimum=2))

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step("static", "static", STATIC_STEP_DESC + ", 1 h at 0.1 s", Q_(1, "h"), Q_(0.1, "s"),
                 {"orientation": "IRA up"})]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        K, uK, src = scale_factor_for(campaign, type(self))
        seg = _static(campaign, type(self), w)
        bv = BiasValue(seg, K, _earth_term(campaign, seg, opts["earth_rate"]), _num(opts, "batches", 2, integer=True))
        dur = bv.x.size * bv.dt
        if dur < 3600 * 0.999:
            w.append(f"the record lasts {dur / 60:.3g} min; 7.2.13.1 c) asks for more than 1 h")
        b = B.bias_budget(Q_(bv.B0, "deg/h"), uK, dmm=_cal(campaign, "dmm"), u_A=Q_(bv.uA, "deg/h"), dof_A=bv.dof,
                          warnings=w)
        return self._outcome([Result(self.metrics[0], Q_(bv.B0, "deg/h"), b.combined, b,
                                     note=f"K from {src}; earth rate {'subtracted' if _flag(opts, 'earth_rate') else 'not subtracted'}")],
                             warnings=w, segments=[seg.id], opts=opts)


class BiasStability(_JJF):
    """JJF 2014—2022 7.2.14 零偏稳定性: B_s = (1/K)·s(F̄_i over P), eq. (29)."""

    item = "7.2.14"
    title = "Bias stability (零偏稳定性)"
    clause = "7.2.14"
    metrics = (Metric("Bs", "bias stability", "B_s", "deg/h", "7.2.14.2", "29"),)
    requires = Bias.requires
    options = RATE_OPTS + (Option("P", "10 s", "s", "averaging period P"),)

    def sequence(self, options):
        return Bias().sequence(options)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        K, uK, _ = scale_factor_for(campaign, type(self))
        seg = _static(campaign, type(self), w)
        x, dt = _output(seg)
        p = float(opts["P"].to("s").magnitude) / dt
        if abs(p - round(p)) > 1e-6 or round(p) < 1:
            raise ProcedureError(f"7.2.14: P = {opts['P']} is not a whole number of sampling intervals ({dt:g} s)")
        try:
            bs, m = F.bias_stability_eq29(x, K, int(round(p)))
        except ValueError as exc:
            raise DataError(seg.file or seg.id, "output", str(exc)) from exc
        bs *= 3600.0
        u, dof = B.std_of_std(bs, m)
        rows = [_budget_row_a("sampling of a standard deviation of N/P averages", "B_s/√(2(m−1))", u, "deg/h", dof),
                BudgetRow.type_b("scale factor K", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                                 sensitivity=Q_(bs, "deg/h"))]
        rows += B.relative_calibration_row("data acquisition, DMM", "u_rel", _cal(campaign, "dmm"), Q_(bs, "deg/h"))
        b = B.type_a_budget("Bs", "deg/h", rows)
        return self._outcome([Result(self.metrics[0], Q_(bs, "deg/h"), b.combined, b, note=f"{m} averages of P")],
                             warnings=w, segments=[seg.id], opts=opts)


class BiasRepeatability(_JJF):
    """JJF 2014—2022 7.2.15 零偏重复性: Q biases by 7.2.13 (power off between), B_r eq. (30)."""

    item = "7.2.15"
    title = "Bias repeatability (零偏重复性)"
    clause = "7.2.15"
    metrics = (Metric("Br", "bias repeatability", "B_r", "deg/h", "7.2.15.2", "30"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-repeat", "7.2.13 repeated Q times", {"run": ""},
                                                          {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("runs", 6, None, "Q"),)

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"static-repeat#{q}", "static-repeat", STATIC_STEP_DESC + f", run {q}, 1 h at 1 s", Q_(1, "h"),
                 Q_(1, "s"), {"run": str(q), "orientation": "IRA up"}) for q in range(1, _num(options, "runs", 2, integer=True) + 1)]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        runs = _by(_need(campaign, type(self), "static-repeat"), "run")
        if len(runs) < 2:
            raise DataError(campaign.source, "segments", f"7.2.15 needs Q ≥ 2 runs, got {len(runs)}")
        for r, g in runs.items():
            if len(g) > 1:
                raise DataError(_where(g[1]), f"segments.{g[1].id}.conditions.run",
                                f"7.2.15: run {r!r} has {len(g)} records; give one per run")
        bvs = [BiasValue(g[0], K) for _, g in sorted(runs.items())]
        br = F.std_bessel([b.B0 for b in bvs], "eq. (30)")
        u, dof = B.std_of_std(br, len(bvs))
        b = B.type_a_budget("Br", "deg/h", [
            _budget_row_a("sampling of a standard deviation of Q values", "B_r/√(2(Q−1))", u, "deg/h", dof),
            BudgetRow.type_b("scale factor K", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                             sensitivity=Q_(br, "deg/h"))])
        tab = TableSpec("bias_runs", "B_0i per run", ["run", "B_0i (°/h)", "u_A (°/h)"],
                        [[k, f"{x.B0:.5g}", f"{x.uA:.2g}"] for k, x in zip(sorted(runs), bvs)])
        return self._outcome([Result(self.metrics[0], Q_(br, "deg/h"), b.combined, b)], tables=[tab],
                             segments=[x.seg.id for x in bvs], opts=opts)


class BiasTemperature(_JJF):
    """JJF 2014—2022 7.2.16 零偏温度灵敏度: B_0i per temperature by 7.2.13, B_t eq. (31)."""

    item = "7.2.16"
    title = "Bias temperature sensitivity (零偏温度灵敏度)"
    clause = "7.2.16"
    metrics = (Metric("Bt", "bias temperature sensitivity", "B_t", "deg/h/delta_degC", "7.2.16.2", "31"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-temperature", "7.2.13 at each chamber temperature",
                                                          {"temperature": "degC"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("temperatures", "-40, -10, 20, 40, 60", None, "chamber points (°C)"),
                           Option("room_temperature", "20 °C", "degC", "T_m"))

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"static-temperature@{T:g}C", "static-temperature", STATIC_STEP_DESC + f" at {T:g} °C, 1 h at 1 s",
                 Q_(1, "h"), Q_(1, "s"), {"temperature": _q(T, "degC"), "orientation": "IRA up"})
            for T in _floats(options["temperatures"], "temperatures")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        groups = _by(_need(campaign, type(self), "static-temperature"), "temperature")
        T = _temperatures(groups, "7.2.16")
        keys = sorted(groups, key=T.get)
        if len(keys) < 2:
            raise DataError(campaign.source, "segments", "7.2.16 needs at least 2 temperatures")
        temps = [T[k] for k in keys]
        for k in keys:
            if len(groups[k]) > 1:
                raise DataError(_where(groups[k][1]), f"segments.{groups[k][1].id}.conditions.temperature",
                                f"7.2.16: {len(groups[k])} records at {k}; give one per temperature")
        bvs = [BiasValue(groups[k][0], K) for k in keys]
        m = _room_index(temps, float(opts["room_temperature"].to("degC").magnitude), "7.2.16")
        bt, i = F.bias_temperature_eq31([b.B0 for b in bvs], temps, m)
        dT = abs(temps[i] - temps[m])
        rows = [_budget_row_a(f"B₀ at {temps[i]:g} °C (batch means)", "u(B_0i)/|ΔT|", bvs[i].uA / dT,
                              "deg/h/delta_degC", bvs[i].dof),
                _budget_row_a(f"B₀ at {temps[m]:g} °C (batch means)", "u(B_0m)/|ΔT|", bvs[m].uA / dT,
                              "deg/h/delta_degC", bvs[m].dof),
                BudgetRow.type_b("scale factor K", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                                 sensitivity=Q_(bt, "deg/h/delta_degC"))]
        rows += _chamber_rows(campaign, bt / dT * math.sqrt(2), "deg/h/delta_degC")
        b = B.type_a_budget("Bt", "deg/h/delta_degC", rows)
        tab = TableSpec("bias_temperature", "B_0i per temperature", ["T_i (°C)", "B_0i (°/h)"],
                        [[f"{t:g}", f"{x.B0:.5g}"] for t, x in zip(temps, bvs)])
        return self._outcome([Result(self.metrics[0], Q_(bt, "deg/h/delta_degC"), b.combined, b,
                                     note=f"maximum at {temps[i]:g} °C")], tables=[tab],
                             segments=[x.seg.id for x in bvs], opts=opts)


class BiasAcceleration(_JJF):
    """JJF 2014—2022 7.2.17 零偏加速度灵敏度: per axis (B_up − B_down)/2 g, maximum |·| over
    X, Y, Z (7.2.17.2).  Earth rate: option earth_rate = on corrects the pair whose axis is the
    IRA (device.ira_axis, default Z) for ±15.041·sin φ."""

    item = "7.2.17"
    title = "Bias acceleration sensitivity (零偏加速度灵敏度)"
    clause = "7.2.17"
    metrics = (Metric("Bg", "bias acceleration sensitivity", "B_g", "deg/h/gn", "7.2.17.2", "prose, no eq. number"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-accel", "X, Y, Z each up and down on the position "
                                                          "table", {"axis": "", "orientation": ""},
                                                          {"output": ("mV",)}),)
    options = RATE_OPTS + (EARTH_OPT,)
    equipment = _JJF.equipment + (EquipmentRequirement("position-table", "two-axis position table"),)

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"static-accel[{a}-{o}]", "static-accel", f"{a} axis {o} on the position table, 30 min at 1 s",
                 Q_(30, "min"), Q_(1, "s"), {"axis": a, "orientation": o}) for a in AXES for o in ("up", "down")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        ira = str(campaign.device.properties.get("ira_axis", "Z")).upper()
        vals: dict[str, dict[str, BiasValue]] = {}
        for s in _need(campaign, type(self), "static-accel"):
            a, o = _axis(s), _updown(s)
            earth = _earth_term(campaign, s, opts["earth_rate"], o) if a == ira else 0.0
            if o in vals.get(a, {}):
                raise DataError(_where(s), f"segments.{s.id}.conditions", f"7.2.17: two records for axis {a} {o}; give one")
            vals.setdefault(a, {})[o] = BiasValue(s, K, earth)
        per = {a: F.per_g_726(v["up"].B0, v["down"].B0) for a, v in vals.items() if {"up", "down"} <= set(v)}
        if not per:
            raise DataError(campaign.source, "segments", "7.2.17 needs at least one axis both up and down")
        worst = max(per, key=lambda a: abs(per[a]))
        bg = abs(per[worst])
        v = vals[worst]
        rows = [_budget_row_a(f"B₀ {worst} up (batch means)", "u/2g", v["up"].uA / 2, "deg/h/gn", v["up"].dof),
                _budget_row_a(f"B₀ {worst} down (batch means)", "u/2g", v["down"].uA / 2, "deg/h/gn", v["down"].dof),
                BudgetRow.type_b("scale factor K", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                                 sensitivity=Q_(bg, "deg/h/gn"))]
        b = B.type_a_budget("Bg", "deg/h/gn", rows)
        w = [] if len(per) == 3 else [f"only axes {', '.join(per)} tested"]
        tab = TableSpec("bias_accel", "Per axis", ["axis", "B up (°/h)", "B down (°/h)", "(up−down)/2g (°/h/g)"],
                        [[a, f"{vals[a]['up'].B0:.5g}", f"{vals[a]['down'].B0:.5g}", f"{per[a]:.4g}"] for a in per])
        return self._outcome([Result(self.metrics[0], Q_(bg, "deg/h/gn"), b.combined, b,
                                     note=f"largest on axis {worst}")], tables=[tab], warnings=w,
                             segments=[x.seg.id for d in vals.values() for x in d.values()], opts=opts)


class _BiasChange(_JJF):
    kind = ""
    what = ""

    def sequence(self, options):
        return ScaleFactor().sequence(options) + [
            Step(f"{self.kind}[{a}-{p}]", self.kind, f"7.2.13 bias {p} {self.what} on {a}, 30 min at 1 s",
                 Q_(30, "min"), Q_(1, "s"), {"axis": a, "phase": p, "orientation": "IRA up"})
            for a in AXES for p in ("before", "after")]

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        vals: dict[tuple[str, str], BiasValue] = {}
        for s in _need(campaign, type(self), self.kind):
            key = (_axis(s), _phase(s))
            if key in vals:
                raise DataError(_where(s), f"segments.{s.id}.conditions",
                                f"{self.item}: two records for axis {key[0]} {key[1]}; give one")
            vals[key] = BiasValue(s, K)
        before = {a: vals[(a, "before")].B0 for a in AXES if (a, "before") in vals}
        after = {a: vals[(a, "after")].B0 for a in AXES if (a, "after") in vals}
        try:
            db, worst, per = F.max_change_eq12_13(before, after)
        except ValueError as exc:
            raise DataError(campaign.source, "segments", f"{self.item}: {exc}") from exc
        v1, v2 = vals[(worst, "before")], vals[(worst, "after")]
        b = B.type_a_budget(self.metrics[0].key, "deg/h", [
            _budget_row_a(f"B₀ before ({worst})", "u(B₁)", v1.uA, "deg/h", v1.dof),
            _budget_row_a(f"B₀ after ({worst})", "u(B₂)", v2.uA, "deg/h", v2.dof),
            BudgetRow.type_b("scale factor K", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                             sensitivity=Q_(db, "deg/h"))])
        w = [] if len(per) == 3 else [f"only the axes {', '.join(per)} were tested (the clause asks for 3)"]
        tab = TableSpec("per_axis", f"B₀ before/after {self.what}", ["axis", "B₁ (°/h)", "B₂ (°/h)", "|ΔB| (°/h)"],
                        [[a, f"{before[a]:.5g}", f"{after[a]:.5g}", f"{per[a]:.4g}"] for a in per])
        return self._outcome([Result(self.metrics[0], Q_(db, "deg/h"), b.combined, b, note=f"largest on axis {worst}")],
                             tables=[tab], warnings=w, segments=[x.seg.id for x in vals.values()], opts=opts)


class BiasShock(_BiasChange):
    """JJF 2014—2022 7.2.18 零偏冲击前后变化量: ΔB_i = |B_i2 − B_i1| eq. (32), max over 3 axes."""

    item = "7.2.18"
    title = "Bias change after shock (零偏冲击前后变化量)"
    clause = "7.2.18"
    kind = "static-shock"
    what = "shock"
    metrics = (Metric("dB_shock", "bias change after shock", "ΔB_i", "deg/h", "7.2.18.2", "32"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-shock", "bias before/after shock per axis",
                                                          {"axis": "", "phase": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS


class BiasVibration(_BiasChange):
    """JJF 2014—2022 7.2.19 零偏振动前后变化量: ΔB_v = |B_v2 − B_v1| eq. (33), max over 3 axes."""

    item = "7.2.19"
    title = "Bias change after vibration (零偏振动前后变化量)"
    clause = "7.2.19"
    kind = "static-vibration"
    what = "vibration"
    metrics = (Metric("dB_vib", "bias change after vibration", "ΔB_v", "deg/h", "7.2.19.2", "33"),)
    requires = ScaleFactor.requires + (SegmentRequirement("static-vibration", "bias before/after vibration per axis",
                                                          {"axis": "", "phase": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS


# =============================================================================== 7.2.20


class AngleRandomWalk(_JJF):
    """JJF 2014—2022 7.2.20 角度随机游走系数: Ω_j = F_j/K (34); overlapping Allan variance of
    cluster averages τ = k·t₀ (the intent of eqs. (35)–(37), see interpretations.md); WLS fit
    of eq. (38) σ²(τ) = Σ_{m=−2}^{2} A_m τ^m; ARW = √A_−1 (39).  Also reports the other four
    IEEE 952 coefficients from A_−2, A_0, A_1, A_2."""

    item = "7.2.20"
    title = "Angle random walk (角度随机游走系数)"
    clause = "7.2.20"
    metrics = (Metric("ARW", "angle random walk", "ARW", "deg/hour**0.5", "7.2.20.2", "39"),
               Metric("Q", "quantization noise", "Q", "arcsec", "7.2.20.2", "38: A₋₂ = 3Q²"),
               Metric("BI", "bias instability", "B", "deg/h", "7.2.20.2", "38: A₀ = (2ln2/π)B²"),
               Metric("RRW", "rate random walk", "K_rrw", "deg/h/hour**0.5", "7.2.20.2", "38: A₁ = K²/3"),
               Metric("RR", "rate ramp", "R", "deg/h**2", "7.2.20.2", "38: A₂ = R²/2"))
    requires = Bias.requires
    options = RATE_OPTS + (Option("max_fraction", 0.25, None, "largest cluster length k as a fraction of n"),
                           Option("nonnegative", "off", None, "on: remove negative eq. (38) terms and refit "
                                  "(biases the others; see interpretations.md)"))

    def sequence(self, options):
        return Bias().sequence(options)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        K, uK, _ = scale_factor_for(campaign, type(self))
        seg = _static(campaign, type(self), w)
        x, dt = _output(seg)
        rate = x / K * 3600.0  # eq. (34), °/h
        try:
            ad = allan.oadev(rate, dt, allan.octave_m(rate.size, _num(opts, "max_fraction", 1e-6)))
        except ValueError as exc:
            raise DataError(seg.file or seg.id, "output", f"Allan variance: {exc}") from exc
        tau_h = np.asarray(ad.tau) / 3600.0
        sig = np.asarray(ad.deviation)
        try:
            fit = F.fit_allan_eq38(tau_h, sig, np.asarray(ad.edf),
                                   nonnegative=_flag(opts, "nonnegative"))
        except ValueError as exc:
            raise ProcedureError(f"7.2.20: {exc}", hint="record longer (7.2.13.1: ≥ 1 h) or check the data") from exc
        if not fit.A[1] > 0:
            raise ProcedureError("7.2.20: the fitted A₋₁ is negative, so ARW = √A₋₁ (eq. (39)) is undefined",
                                 hint="look at the Allan plot; the record may be dominated by other noise")
        for i, (m, name) in enumerate(F.ALLAN_TERMS):
            if not fit.active[i]:
                how = ("the term was removed and the fit repeated" if fit.A[i] == 0 and fit.raw[i] != 0
                       else "kept in the fitted curve")
                sig_txt = "consistent with 0" if abs(fit.raw[i]) <= 2 * fit.u_A[i] else "significantly negative: the model does not describe the data"
                w.append(f"A_{m} ({name}) came out negative in the eq. (38) fit ({fit.raw[i]:.3g} ± {fit.u_A[i]:.2g}, "
                         f"{sig_txt}); {how}; reported as 0 (not resolved)")
        if fit.birge > 1.5:
            w.append(f"eq. (38) fits poorly (χ²/ν = {fit.birge ** 2:.2g}); the uncertainties were scaled up")
        coefs = F.noise_coefficients(fit.A)
        keys = ("Q", "ARW", "BI", "RRW", "RR")
        units = ("deg", "deg/hour**0.5", "deg/h", "deg/h/hour**0.5", "deg/h**2")
        cnames = ("Q", "N", "B", "K", "R")
        results = []
        for i, (key, unit_, cn, fac) in enumerate(zip(keys, units, cnames, F.NOISE_FACTORS)):
            metric = self.metrics[[m.key for m in self.metrics].index(key)]
            to_metric = float(Q_(1.0, unit_).to(metric.unit).magnitude)
            val = coefs[cn] * to_metric
            u_fit, how = F.coefficient_u(fit.A[i], fit.u_A[i], fac)
            u_fit *= to_metric
            rows = [_budget_row_a(f"eq. (38) GLS fit (edf per τ), A_{F.ALLAN_TERMS[i][0]}", "u(A)", u_fit, metric.unit,
                                  max(fit.dof, 1), note=f"{tau_h.size} τ values, χ²/ν = {fit.chi2 / max(fit.dof, 1):.3g}; "
                                  + how),
                    BudgetRow.type_b("scale factor K (eq. (34))", "u_rel(K)", Q_(uK, ""), distribution="normal",
                                     k=1.0, sensitivity=Q_(val, metric.unit))]
            b = B.type_a_budget(key, metric.unit, rows)
            results.append(Result(metric, Q_(val, metric.unit), b.combined, b,
                                  note="" if fit.active[i] else "term not resolved (fitted negative)"))
        results.insert(0, results.pop(1))  # ARW first
        model = fit.model(tau_h)
        series = [{"label": "σ(τ) overlapping Allan deviation", "x": (tau_h * 3600).tolist(), "y": sig.tolist(),
                   "yerr": (sig / np.sqrt(2 * np.asarray(ad.edf))).tolist(), "style": "o"},
                  {"label": "eq. (38) fit", "x": (tau_h * 3600).tolist(), "y": np.sqrt(np.clip(model, 0, None)).tolist(),
                   "style": "-"}]
        for i, (m, name) in enumerate(F.ALLAN_TERMS):
            if fit.A[i] > 0:
                series.append({"label": f"{name} term", "x": (tau_h * 3600).tolist(),
                               "y": np.sqrt(fit.A[i] * tau_h**m).tolist(), "style": "--"})
        plot = PlotSpec("allan", "Allan deviation, eq. (38) fit and its terms", "τ (s)", "σ(τ) (°/h)", series,
                        logx=True, logy=True)
        tab = TableSpec("allan_coef", "Eq. (38) coefficients (τ in h, σ in °/h)", ["m", "term", "A_m", "u(A_m)", "kept"],
                        [[m, name, f"{fit.A[i]:.4g}", f"{fit.u_A[i]:.2g}", "yes" if fit.active[i] else "no (negative: not resolved)"]
                         for i, (m, name) in enumerate(F.ALLAN_TERMS)])
        return self._outcome(results, plots=[plot], tables=[tab], warnings=w, segments=[seg.id], opts=opts)


# =============================================================================== 7.2.21, 7.2.22


class _Dynamic:
    """Sine fits (eq. (40)) of every angular-vibration record, per frequency."""

    def __init__(self, campaign, proc):
        segs = _need(campaign, proc, "angular-vibration")
        by_f: dict[float, list[Segment]] = {}
        for s in segs:
            by_f.setdefault(_cond_q(s, "frequency", "Hz"), []).append(s)
        if len(by_f) < 3:
            raise DataError(campaign.source, "segments", f"{proc.item} needs at least 3 frequencies (7.2.21.1 b): N ≥ 10)")
        self.f = np.array(sorted(by_f))
        self.E, self.A, self.phi, self.uS = [], [], [], []
        self.n = []
        self.fs = min(1.0 / float(s.interval.to("s").magnitude) for s in segs if s.interval is not None)
        self.ids = [s.id for s in segs]
        for f in self.f:
            Es, As, ph = [], [], []
            for s in by_f[f]:
                y, dt = _output(s)
                ref, _ = _output(s, "reference", "deg/s")
                if f >= 0.5 / dt:
                    raise DataError(s.file or s.id, "sample_interval", f"{1 / dt:g} Hz sampling cannot resolve {f:g} Hz")
                t = np.arange(y.size) * dt
                try:
                    gy = fit_sine(t, y, f)
                    gr = fit_sine(t, ref, f)
                except ValueError as exc:
                    raise DataError(s.file or s.id, "output", f"sine fit at {f:g} Hz: {exc}") from exc
                Es.append(gy.amplitude)
                As.append(gr.amplitude)
                ph.append(float(wrap_phase(gy.phase - gr.phase)))
            ratio = np.array(Es) / np.array(As)
            self.E.append(float(np.mean(Es)))  # eq. (41)
            self.A.append(float(np.mean(As)))
            # eq. (44) on phases relative to the table's signal (P_i of eq. (45) per record)
            self.phi.append(float(np.angle(np.mean(np.exp(1j * np.array(ph))))))
            self.uS.append(float(np.std(ratio, ddof=1) / math.sqrt(ratio.size)) if ratio.size > 1 else 0.0)
            self.n.append(len(Es))
        self.S = np.array(self.E) / np.array(self.A)  # eq. (42)
        self.P = np.unwrap(np.array(self.phi))  # eq. (45), continuous in f
        self.uS = np.array(self.uS)


class Bandwidth(_JJF):
    """JJF 2014—2022 7.2.21 带宽: sine fits eq. (40), Ē_i (41), S_i = Ē_i/A (42), K_i = S_i/S_0
    (43) with S_0 = K from 7.2.1; curve 1/K² = a + b f² through the N + 1 ratios, B_w at K = 0.707."""

    item = "7.2.21"
    title = "Bandwidth (带宽)"
    clause = "7.2.21"
    metrics = (Metric("Bw", "bandwidth", "B_w", "Hz", "7.2.21.2", "40–43"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "angular-vibration", "angular vibration table, N ≥ 10 log-spaced frequencies 10 Hz … 2·B_w, n ≥ 10 records",
        {"frequency": "Hz", "amplitude": "deg/s", "repeat": ""}, {"output": ("mV",), "reference": ("deg/s",)}),)
    options = RATE_OPTS + (Option("bandwidth_estimate", "80 Hz", "Hz", "expected B_w (sets the top frequency 2·B_w)"),
                           Option("frequencies", 12, None, "N"), Option("records", 10, None, "n per frequency"),
                           Option("amplitude", "20 deg/s", "deg/s", "table amplitude (10–30 % of range)"),
                           Option("sample_rate", "5000 Hz", "Hz", "> 20·B_w"))
    equipment = _JJF.equipment + (EquipmentRequirement("angular-vibration", "angular vibration table and its "
                                                       "reference sensor (relative U of amplitude; phase_U)"),)

    def sequence(self, options):
        bw = float(options["bandwidth_estimate"].to("Hz").magnitude)
        fs = float(options["sample_rate"].to("Hz").magnitude)
        A = float(options["amplitude"].to("deg/s").magnitude)
        freqs = np.round(np.geomspace(10.0, 2 * bw, _num(options, "frequencies", 3, integer=True)), 1)
        steps = ScaleFactor().sequence(options)
        for f in freqs:
            for j in range(1, _num(options, "records", 1, integer=True) + 1):
                steps.append(Step(f"angvib-{f:g}Hz#{j}", "angular-vibration", f"{f:g} Hz, {A:g} °/s, record {j}",
                                  Q_(1, "s"), Q_(1 / fs, "s"),
                                  {"frequency": _q(f, "Hz"), "amplitude": _q(A, "deg/s"), "repeat": str(j)}))
        return steps

    @staticmethod
    def _fc(dyn, S0, scale=1.0):
        return F.bandwidth_fit_743(dyn.f, dyn.S * scale / S0)

    @classmethod
    def _analyse(cls, campaign, dyn, K, uK):
        """(B_w, its budget, (a, b) of the curve, warnings)."""
        try:
            fc, ab, cov = cls._fc(dyn, K)
        except ValueError as exc:
            raise ProcedureError(f"7.2.21: {exc}",
                                 hint="raise the top frequency (option bandwidth_estimate) past the 0.707 point") from exc
        w = [] if dyn.f.size >= 10 else [f"7.2.21.1 b) asks for N ≥ 10 frequencies; got {dyn.f.size}"]
        if min(dyn.n) < 10:
            w.append(f"7.2.21.1 c) asks for n ≥ 10 records per frequency; the fewest is {min(dyn.n)}")
        if dyn.fs < 20 * fc:
            w.append(f"7.2.21.1 c) asks for a sampling rate above 20·B_w = {20 * fc:.4g} Hz; got {dyn.fs:g} Hz")
        if fc > dyn.f.max():
            w.append(f"B_w = {fc:.4g} Hz lies above the highest frequency {dyn.f.max():g} Hz (extrapolated)")
        # sensitivities by numerical differentiation of the whole evaluation
        eps = 1e-4
        dfc_ds = (cls._fc(dyn, K, 1 + eps)[0] - fc) / eps  # ∂f_c/∂(relative scale of all S_i)
        rows = []
        # type A: scatter of the ratios E/A at each frequency, propagated by perturbing S_i
        uA2 = 0.0
        for i in range(dyn.f.size):
            S = dyn.S.copy()
            h = max(dyn.uS[i], 1e-12 * S[i])
            S[i] += h
            d = (F.bandwidth_fit_743(dyn.f, S / K)[0] - fc) / h
            uA2 += (d * dyn.uS[i]) ** 2
        nmin = min(dyn.n)
        rows.append(_budget_row_a("sine-fit amplitudes (scatter of Ē_i/A_i over the n records)", "u_A",
                                  math.sqrt(uA2), "Hz", max(nmin - 1, 1)))
        cal = _cal(campaign, "angular-vibration")
        rows += B.relative_calibration_row("reference sensor amplitude (scales every S_i)", "u_rel(A)", cal,
                                           Q_(abs(dfc_ds), "Hz"), w)
        rows.append(BudgetRow.type_b("S₀ = K from 7.2.1", "u_rel(K)", Q_(uK, ""), distribution="normal", k=1.0,
                                     sensitivity=Q_(abs(dfc_ds), "Hz")))
        return fc, B.type_a_budget("Bw", "Hz", rows), ab, w

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        dyn = _Dynamic(campaign, type(self))
        fc, b, ab, w = self._analyse(campaign, dyn, K, uK)
        kr = dyn.S / K
        fine = np.linspace(0, max(dyn.f.max(), fc) * 1.05, 200)
        plot = PlotSpec("amplitude_ratio", "Amplitude ratio K_i = S_i/S₀ (eq. (43)), fit and the 0.707 point",
                        "f (Hz)", "K_i",
                        [{"label": "K_i", "x": [0.0] + dyn.f.tolist(), "y": [1.0] + kr.tolist(), "style": "o"},
                         {"label": "fit 1/K² = a + b f²", "x": fine.tolist(),
                          "y": (1 / np.sqrt(ab[0] + ab[1] * fine**2)).tolist(), "style": "-"},
                         {"label": f"0.707 → B_w = {fc:.4g} Hz", "x": [0.0, fc, fc], "y": [0.707, 0.707, 0.0],
                          "style": "--"}])
        tab = TableSpec("dynamic", "Per frequency", ["f_i (Hz)", "Ē_i (mV)", "A (°/s)", "S_i (mV/((°)/s))", "K_i",
                                                     "P_i (rad)"],
                        [[f"{f:g}", f"{e:.5g}", f"{a:.5g}", f"{s:.6g}", f"{k:.5f}", f"{p:.5f}"]
                         for f, e, a, s, k, p in zip(dyn.f, dyn.E, dyn.A, dyn.S, kr, dyn.P)])
        return self._outcome([Result(self.metrics[0], Q_(fc, "Hz"), b.combined, b)], plots=[plot], tables=[tab],
                             warnings=w, segments=dyn.ids, opts=opts)


class OutputDelay(Bandwidth):
    """JJF 2014—2022 7.2.22 输出延迟时间: φ̄_i (44), P_i = φ̄_i − φ₀ (45) (φ₀ from the reference
    sensor's fit of the same record), model (46) with T = 1/(2πB_w) (47), T_d by (48)–(50)."""

    item = "7.2.22"
    title = "Output delay (输出延迟时间)"
    clause = "7.2.22"
    metrics = (Metric("Td", "output delay", "T_d", "s", "7.2.22.2", "48–50"),)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        dyn = _Dynamic(campaign, type(self))
        fc, bbw, _, _ = self._analyse(campaign, dyn, K, uK)
        w_ = 2 * math.pi * dyn.f
        T = 1.0 / (2 * math.pi * fc)  # eq. (47)
        Td, u_fit, resid = F.delay_eq48_50(w_, dyn.P, T)
        # u(B_w) from the 7.2.21 evaluation
        u_bw = float(bbw.combined.to("Hz").magnitude)
        d = 1e-3 * fc
        Td2 = F.delay_eq48_50(w_, dyn.P, 1.0 / (2 * math.pi * (fc + d)))[0]
        rows = [_budget_row_a("least squares of eq. (50) (phase residuals)", "u(T_d)", u_fit, "s", dyn.f.size - 1),
                BudgetRow.type_b("bandwidth B_w via T = 1/(2πB_w) (eq. (47))", "u(B_w)", Q_(u_bw, "Hz"),
                                 distribution="normal", k=1.0, sensitivity=Q_(abs((Td2 - Td) / d), "s/Hz"))]
        eq = campaign.equipment_for("angular-vibration")
        if eq is not None and "phase_U" in eq.properties:
            pu = parse_quantity(eq.properties["phase_U"], dimension="deg").to("rad").magnitude
            rows.append(BudgetRow.type_b("reference sensor phase", "u(φ₀)", Q_(pu, ""), distribution="normal", k=2.0,
                                         sensitivity=Q_(1.0 / math.sqrt(float(w_ @ w_) / w_.size), "s"),
                                         note="a common phase error φ acts as φ/ω on T_d (RMS ω)"))
        b = B.type_a_budget("Td", "s", rows)
        fine = np.linspace(dyn.f.min(), dyn.f.max(), 100)
        wf = 2 * np.pi * fine
        plot = PlotSpec("phase", "Phase delay P_i (eq. (45)) and the model −atan(ωT) − ωT_d (eq. (46))", "f (Hz)",
                        "P (rad)",
                        [{"label": "P_i", "x": dyn.f.tolist(), "y": dyn.P.tolist(), "style": "o"},
                         {"label": f"model, T_d = {Td * 1e3:.4g} ms, B_w = {fc:.4g} Hz", "x": fine.tolist(),
                          "y": (-np.arctan(wf * T) - wf * Td).tolist(), "style": "-"},
                         {"label": "pure delay −ωT_d", "x": fine.tolist(), "y": (-wf * Td).tolist(), "style": ":"},
                         {"label": f"B_w = {fc:.4g} Hz", "x": [fc, fc],
                          "y": [float(np.min(dyn.P)), 0.0], "style": "--"}])
        return self._outcome([Result(self.metrics[0], Q_(Td, "s"), b.combined, b, note=f"T = {T * 1e3:.4g} ms")],
                             plots=[plot], segments=dyn.ids, opts=opts)


# =============================================================================== 7.2.23


class StartupTime(_JJF):
    """JJF 2014—2022 7.2.23 启动时间: position trials (time until the output reaches the required
    bias: stays within ± bias_tolerance of its settled value) and rate trials (calibrated output
    within rate_tolerance of KΩ); the start-up time is the largest of all (7.2.23.2)."""

    item = "7.2.23"
    title = "Start-up time (启动时间)"
    clause = "7.2.23"
    metrics = (Metric("t_startup", "start-up time", "t_s", "s", "7.2.23.2", "prose, no eq. number"),)
    requires = (SegmentRequirement("startup", "power-on records: trial = position (at rest) or rate (table at Ω)",
                                   {"trial": "", "rate": "deg/s", "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("bias_tolerance", "0.05 deg/s", "deg/s", "required bias band (position trials)"),
                           Option("rate_tolerance", "1 %", "", "rate error requirement, relative (rate trials)"),
                           Option("window", "1 s", "s", "moving-average window applied before the test"),
                           Option("full_scale", "100 deg/s", "deg/s", "full-scale rate for the rate trials"))
    equipment = _JJF.equipment + (EquipmentRequirement("timer", "timer / time base"),)

    def sequence(self, options):
        fs = float(options["full_scale"].to("deg/s").magnitude)
        steps = ScaleFactor().sequence(options)
        for q in (1, 2, 3):
            steps.append(Step(f"startup-position#{q}", "startup", f"power on at rest, run {q}, 60 s at 0.1 s",
                              Q_(60, "s"), Q_(0.1, "s"), {"trial": "position", "rate": "0 deg/s", "run": str(q)}))
        for frac in (1.0, 0.1, 0.01):
            steps.append(Step(f"startup-rate{frac:g}FS", "startup", f"power on with the table at {frac * fs:g} °/s",
                              Q_(60, "s"), Q_(0.1, "s"), {"trial": "rate", "rate": _q(frac * fs, "deg/s"), "run": "1"}))
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        K, uK, _ = scale_factor_for(campaign, type(self))
        segs = _need(campaign, type(self), "startup")
        btol = float(opts["bias_tolerance"].to("deg/s").magnitude)
        rtol = float(opts["rate_tolerance"].to("").magnitude)
        win = float(opts["window"].to("s").magnitude)
        for s in segs:
            if str(s.condition("trial")).strip().lower() not in ("position", "rate"):
                raise DataError(s.file or s.id, f"segments.{s.id}.conditions.trial",
                                f"must be \"position\" or \"rate\" (7.2.23.1), got {s.condition('trial')!r}")
        pos = [s for s in segs if str(s.condition("trial")).strip().lower() == "position"]
        rat = [s for s in segs if str(s.condition("trial")).strip().lower() == "rate"]
        if not pos:
            raise DataError(campaign.source, "segments", "7.2.23 needs at least one position trial (trial = position)")
        rows, times = [], []

        def smooth(s):
            x, dt = _output(s)
            k = max(1, int(round(win / dt)))
            if x.size < 4 * k:
                raise DataError(s.file or s.id, "output", f"record too short for a {win:g} s window")
            c = np.convolve(x, np.ones(k) / k, mode="valid")
            t = (np.arange(c.size) + (k + 1) / 2.0) * dt  # centre of each window, from power-on
            return t, c / K, dt, float(np.std(np.diff(x)) / math.sqrt(2 * k) / abs(K))

        zero = []
        for s in pos:
            t, r, dt, sd = smooth(s)
            settled = float(np.mean(r[int(0.75 * r.size):]))
            zero.append(settled)
            try:
                ts = F.settle_time(t, r, settled, btol)
            except ValueError as exc:
                raise ProcedureError(f"7.2.23 position trial {s.id}: {exc}") from exc
            times.append((ts, s, t, r, settled, btol, dt, sd))
        z = float(np.mean(zero))
        for s in rat:
            om = _cond_q(s, "rate", "deg/s")
            t, r, dt, sd = smooth(s)
            tol = rtol * abs(om)
            try:
                ts = F.settle_time(t, r - z, om, tol)
            except ValueError as exc:
                raise ProcedureError(f"7.2.23 rate trial {s.id}: {exc}") from exc
            times.append((ts, s, t, r - z, om, tol, dt, sd))
        ts, s, t, r, target, tol, dt, sd = max(times, key=lambda x: x[0])
        i = int(np.searchsorted(t, ts))
        j0, j1 = max(i - 5, 0), min(i + 5, t.size - 1)
        slope = abs((r[j1] - r[j0]) / (t[j1] - t[j0])) if j1 > j0 else 0.0
        rows = [BudgetRow.type_b("sampling: the crossing lies within one interval", "Δt/2", Q_(dt / 2, "s"),
                                 distribution="uniform")]
        if slope > 0:
            rows.append(_budget_row_a("output noise at the crossing / slope of the settling output", "σ/|dx/dt|",
                                      sd / slope, "s", INF))
        rows += B.relative_calibration_row("timer", "u_rel(t)", _cal(campaign, "timer"), Q_(ts, "s"))
        b = B.type_a_budget("t_startup", "s", rows)
        tab = TableSpec("startup", "Start-up time per trial", ["trial", "segment", "target", "tolerance", "t (s)"],
                        [[str(x[1].condition("trial")), x[1].id, f"{x[4]:.4g} °/s", f"{x[5]:.3g} °/s", f"{x[0]:.2f}"]
                         for x in times])
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, note=f"largest in {s.id}")],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)


PROCEDURES = (ScaleFactor, NonlinearityRange, Asymmetry, Repeatability, SFTemperature, SFAxialAcceleration, SFShock,
              SFVibration, Threshold, Resolution, Misalignment, MisalignmentRepeatability, Bias, BiasStability,
              BiasRepeatability, BiasTemperature, BiasAcceleration, BiasShock, BiasVibration, AngleRandomWalk,
              Bandwidth, OutputDelay, StartupTime)

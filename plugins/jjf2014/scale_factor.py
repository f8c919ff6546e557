"""JJF 2014—2022 7.2.1–7.2.8: scale factor, nonlinearity and range, asymmetry, repeatability,
temperature and acceleration sensitivity, change after shock and vibration."""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from metro.api import (INF, Q_, BudgetRow, DataError, EquipmentRequirement, Metric, Option,
                       ProcedureError, Result, Segment, SegmentRequirement, TableSpec,
                       curve_scatter, hint, join, max_abs_selection, max_slope_selection, msg,
                       parse_quantity, selection_note, selection_rows, spread_rows)

from . import budgets as B
from . import formulas as F
from .common import (AXES, KU, RATE_OPTS, JJFItem, SFSet, axis_of, before_after_change,
                     bias_repeatability, budget_row_a, calibration_of, chamber_rows,
                     chamber_temperatures, group_by, main_set, need_segments, num_option,
                     one_estimate, parse_floats, parse_magnitudes, phase_of, quantity_text,
                     rate_steps, room_index, sf_plots, sf_repeatability, up_or_down, with_scatter)

# =============================================================================== 7.2.1 – 7.2.4


class ScaleFactor(JJFItem):
    """JJF 2014—2022 7.2.1 标度因数: K and F_0 by least squares, eqs. (2)–(5); budget B.1."""

    item = "7.2.1"
    title = "Scale factor (标度因数)"
    clause = "7.2.1"
    metrics = (Metric("K", "scale factor", "K", KU, "7.2.1.2", "4"),
               Metric("F0", "fitted zero", "F₀", "mV", "7.2.1.2", "5"))
    requires = (SegmentRequirement("rate", "rate table at Ω_i, IRA ∥ table axis; ≥ 11 rates per "
                                           "direction incl. the maximum, ≥ 10 samples at 1 s each "
                                           "(7.2.1.1)",
                                   {"rate": "deg/s"},
                                   {"output": ("mV",)}, min_count=22),)
    options = RATE_OPTS

    def sequence(self, options):
        return rate_steps("rate", parse_magnitudes(options["rates"], "rates"))

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        s = main_set(campaign, type(self))
        npos, nneg = int(np.sum(s.omega > 0)), int(np.sum(s.omega < 0))
        if min(npos, nneg) < 11:
            w.append(msg("7.2.1.1 b) asks for at least 11 rates per direction; got {pos} forward, "
                         "{neg} reverse", pos=npos, neg=nneg))
        if min(s.n) < 10:
            w.append(msg("7.2.1.1 c) asks for at least 10 samples per rate; the shortest segment "
                         "has {n}", n=min(s.n)))
        bK = s.budget(campaign, w)
        # F₀ = K·(bias + earth rate) + …: another power-on gives another F₀, by K·B_r (7.2.15)
        brep = bias_repeatability(campaign, s.K)
        u_b = brep.value / 3600.0 * abs(s.K) if brep is not None else 0.0
        f0_row = (brep.row("bias repeatability × K (another power-on gives another F₀)", "K·B_r",
                           u_b, "mV")
                  if brep is not None and u_b > s.fit.u_F0 else
                  budget_row_a("residual scatter of the eq. (3) fit", "u(F₀)", s.fit.u_F0, "mV",
                               s.fit.dof))
        bF0 = B.type_a_budget("fitted zero F0", "mV", [
            f0_row,
            *B.relative_calibration_row("data acquisition, 6½-digit DMM", "u_DMM",
                                        calibration_of(campaign, "dmm"),
                                        Q_(s.fit.F0, "mV")),
            *s.rounding_rows(campaign)[1]])
        res = [Result(self.metrics[0], Q_(s.K, KU), bK.combined, bK),
               Result(self.metrics[1], Q_(s.fit.F0, "mV"), bF0.combined, bF0, earth_rate="included",
                      note=msg("F₀ holds K·Ω_e·sin φ, the earth rate along the vertical input axis "
                               "(7.2.1 has no correction; it does not affect K)"))]
        tab = TableSpec("sf_points", msg("Mean output per input rate (eq. (2)) and residuals"),
                        ["Ω_i (°/s)", "F̄_i (mV)", "u(F̄_i) (mV)", "v_i (mV)"],
                        [[f"{o:g}", f"{f:.6f}", f"{u:.2g}", f"{v:.3g}"]
                         for o, f, u, v in zip(s.omega, s.F, s.uF, s.fit.residuals)])
        return self._outcome(res, plots=sf_plots(s), tables=[tab], warnings=w, segments=s.ids,
                             opts=opts)


class NonlinearityRange(JJFItem):
    """JJF 2014—2022 7.2.2 标度因数非线性度和量程: a_i eq. (7), K_n eq. (8); the range is the
    largest input rate whose span meets the nonlinearity requirement (7.2.2.2)."""

    item = "7.2.2"
    title = "Scale-factor nonlinearity and range (标度因数非线性度和量程)"
    clause = "7.2.2"
    metrics = (Metric("Kn", "scale-factor nonlinearity", "K_n", "", "7.2.2.2", "8"),
               Metric("range", "range", "Ω_max", "deg/s", "7.2.2.2", "prose after eq. 8"))
    requires = ScaleFactor.requires
    options = RATE_OPTS + (
        Option("nonlinearity_limit", "", None,
               "required K_n for the range (default: device.nonlinearity_spec)"),)

    def sequence(self, options):
        return ScaleFactor().sequence(options)

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        w: list[str] = []
        s = main_set(campaign, type(self))
        try:
            a, kn = F.nonlinearity_eq7_8(s.omega, s.F, s.fit)
        except ValueError as exc:
            raise ProcedureError(f"7.2.2: {exc}") from exc
        cal = calibration_of(campaign, "rate_table")
        kn, bkn = _kn_budget(s, np.ones(s.omega.size, dtype=bool), cal)
        limit_txt = (opts["nonlinearity_limit"]
                     or campaign.device.properties.get("nonlinearity_spec"))
        results = [Result(self.metrics[0], Q_(kn, ""), bkn.combined, bkn)]
        if limit_txt in (None, ""):
            w.append(msg("no nonlinearity requirement given{hint}: the range is not determined",
                         hint=hint(" (option nonlinearity_limit or device.nonlinearity_spec)")))
        else:
            limit = float(parse_quantity(limit_txt, dimension="").to("").magnitude)
            res = _range_decision(s, limit, cal)
            if res is None:
                w.append(msg("no symmetric span meets K_n ≤ {limit:g}: the range is not determined",
                             limit=limit))
            else:
                rng, kn_r, why = res
                rr = B.relative_calibration_row("rate table (the range is a set table rate)",
                                                "u_rel(Ω)", cal,
                                                Q_(rng, "deg/s"), w)
                br = B.type_a_budget("range", "deg/s", rr) if rr else None
                results.append(Result(self.metrics[1], Q_(rng, "deg/s"),
                                      br.combined if br else None, br,
                                      reportable=not why, reason=why,
                                      note=msg("K_n = {Kn:.3g} ≤ {limit:g} over ±{range:g} °/s",
                                               Kn=kn_r, limit=limit, range=rng)))
        tab = TableSpec("nonlinearity", msg("Point nonlinearity a_i (eq. (7))"),
                        ["Ω_i (°/s)", "a_i"],
                        [[f"{o:g}", f"{x:.3e}"] for o, x in zip(s.omega, a)])
        return self._outcome(results, tables=[tab], warnings=w, segments=s.ids, opts=opts)


def _kn_budget(s: SFSet, sel: np.ndarray, cal) -> tuple[float, "B.UncertaintyBudget"]:
    """K_n (eqs. (6)–(8)) of the points ``sel`` of ``s`` (a symmetric span) and its budget: the
    scatter of F̄_i at the worst point and of the fit, over K·span; the rate table's error at
    Ω_i."""
    om, f, uf = s.omega[sel], s.F[sel], s.uF[sel]
    fit = F.scale_factor_eq4_5(om, f)
    try:
        a, kn = F.nonlinearity_eq7_8(om, f, fit)
    except ValueError as exc:
        raise ProcedureError(f"7.2.2: {exc}") from exc
    span = abs(om.max() - om.min())
    i = int(np.argmax(np.abs(a)))
    u_pt = math.hypot(uf[i], fit.residuals.std(ddof=2) / math.sqrt(len(f))) / (abs(fit.K) * span)
    rows = [budget_row_a("scatter of F̄_i at the worst point and of the fit", "u(a_i)", u_pt, "",
                         fit.dof)]
    if cal is not None and cal.uncertainty.dimensionless:
        rows.append(BudgetRow.from_calibration("rate table error at Ω_i", "u_rel(Ω)", cal,
                                               sensitivity=Q_(abs(om[i]) / span, "")))
    return kn, B.type_a_budget("nonlinearity Kn", "", rows)


def _range_decision(s: SFSet, limit: float, cal) -> tuple[float, float, str] | None:
    """The range of 7.2.2.2's last sentence — the largest set rate Ω_m whose span ±Ω_m meets the
    nonlinearity requirement — and whether the data decide it (interpretations.md, "7.2.2 — the
    range is a decision").  Each span's K_n carries its U; the range is reportable when its own K_n
    + U meets the limit and every larger span's K_n − U exceeds it.  Returns (Ω_m, its K_n, reason
    not reportable or ""), or None when every span's K_n − U exceeds the limit (no range)."""
    tops = np.unique(np.abs(s.omega))[::-1]
    spans = []
    for top in tops:
        sel = np.abs(s.omega) <= top
        if sel.sum() < 3 or not (np.any(s.omega[sel] > 0) and np.any(s.omega[sel] < 0)):
            break
        kn, b = _kn_budget(s, sel, cal)
        spans.append((float(top), kn, float(b.expanded.magnitude)))
    meets = [x for x in spans if x[1] <= limit]
    if meets:
        top, kn, U = meets[0]
        larger = [x for x in spans if x[0] > top]
        undecided = [x for x in larger if x[1] - x[2] <= limit]
        if kn + U > limit:
            why = msg("K_n = {kn:.3g} over ±{top:g} °/s meets {limit:g} by less than its U = "
                      "{U:.2g}: noise may decide the range", kn=kn, top=top, limit=limit, U=U)
        elif undecided:
            x = undecided[0]
            why = msg("K_n = {kn:.3g} over the larger span ±{top:g} °/s exceeds {limit:g} by less "
                      "than its U = {U:.2g}: noise may decide the range", kn=x[1], top=x[0],
                      limit=limit, U=x[2])
        else:
            why = ""
        return top, kn, why
    near = [x for x in spans if x[1] - x[2] <= limit]
    if near:
        top, kn, U = near[0]
        return top, kn, msg("no span meets K_n ≤ {limit:g}, but K_n = {kn:.3g} over ±{top:g} °/s "
                            "is within its U = {U:.2g} of it: noise may decide the range",
                            limit=limit, kn=kn, top=top, U=U)
    return None


class Asymmetry(JJFItem):
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
        s = main_set(campaign, type(self))
        pos, neg = s.omega > 0, s.omega < 0
        if pos.sum() < 3 or neg.sum() < 3:
            raise DataError(campaign.source, "segments",
                            "7.2.3 needs at least 3 forward and 3 reverse rates")
        fp = F.scale_factor_eq4_5(s.omega[pos], s.F[pos])
        fm = F.scale_factor_eq4_5(s.omega[neg], s.F[neg])
        ka = F.asymmetry_eq9(fp.K, fm.K, s.K)
        u = math.hypot(fp.u_K, fm.u_K) / abs(s.K)
        dof = u**4 / ((fp.u_K / s.K) ** 4 / fp.dof + (fm.u_K / s.K) ** 4 / fm.dof) if u > 0 else INF
        b = B.type_a_budget("asymmetry Ka", "", [
            budget_row_a("fits of K₊ and K₋ (eq. (4) per direction)", "√(u²(K₊)+u²(K₋))/K", u, "",
                         dof,
                          note=msg("the rate table and DMM errors are common to K₊, K₋ and K and "
                                   "cancel in eq. (9)"))])
        return self._outcome([Result(self.metrics[0], Q_(ka, ""), b.combined, b,
                                     note=msg("K₊ = {Kp:.7g}, K₋ = {Km:.7g} mV/((°)/s)", Kp=fp.K,
                                              Km=fm.K))],
                             segments=s.ids, opts=opts)


class Repeatability(JJFItem):
    """JJF 2014—2022 7.2.4 标度因数重复性: Q calibrations by 7.2.1, K_r eq. (10)."""

    item = "7.2.4"
    title = "Scale-factor repeatability (标度因数重复性)"
    clause = "7.2.4"
    metrics = (Metric("Kr", "scale-factor repeatability", "K_r", "", "7.2.4.2", "10"),)
    requires = (SegmentRequirement("rate-repeat", "7.2.1 repeated Q times, power off between runs",
                                   {"rate": "deg/s",
                                   "run": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("runs", 6, None, "number of calibrations Q"),)

    def sequence(self, options):
        steps = []
        for q in range(1, num_option(options, "runs", 2, integer=True) + 1):
            steps += rate_steps("rate-repeat", parse_magnitudes(options["rates"], "rates"),
                                {"run": str(q)}, tag=f"#{q}")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        runs = group_by(need_segments(campaign, type(self), "rate-repeat"), "run")
        if len(runs) < 2:
            raise DataError(campaign.source, "segments",
                            f"7.2.4 needs Q ≥ 2 runs (condition run), got {len(runs)}")
        sets = {r: SFSet(g) for r, g in sorted(runs.items())}
        Ks = [s.K for s in sets.values()]
        kr = F.relative_repeatability_eq10(Ks)
        u, dof = B.std_of_std(kr, len(Ks))
        b = B.type_a_budget("repeatability Kr", "", [
            budget_row_a(msg("sampling of a standard deviation of Q values (χ² bound)"),
                         "(s_{upper} − K_r)/2", u, "", dof)])
        tab = TableSpec("sf_runs", msg("K_i per calibration"),
                        [msg("run"), "K_i (mV/((°)/s))", "u(K_i) fit"],
                        [[r, f"{s.K:.7g}", f"{s.fit.u_K:.2g}"] for r, s in sets.items()])
        return self._outcome([Result(self.metrics[0], Q_(kr, ""), b.combined, b)], tables=[tab],
                             segments=[i for s in sets.values() for i in s.ids], opts=opts)


# =============================================================================== 7.2.5 – 7.2.8


class SFTemperature(JJFItem):
    """JJF 2014—2022 7.2.5 标度因数温度灵敏度: K_i at each temperature by 7.2.1, K_t eq. (11)."""

    item = "7.2.5"
    title = "Scale-factor temperature sensitivity (标度因数温度灵敏度)"
    clause = "7.2.5"
    metrics = (Metric("Kt", "scale-factor temperature sensitivity", "K_t", "1/delta_degC",
                      "7.2.5.2", "11"),)
    equipment = JJFItem.equipment + (EquipmentRequirement("chamber", "temperature chamber (table 2 "
                                                                     "no. 2); its calibration U "
                                                                     "(in K) enters the budget"),)
    requires = (SegmentRequirement("rate-temperature",
                                   "7.2.1 at each chamber temperature incl. room temperature",
                                   {"rate": "deg/s", "temperature": "degC"}, {"output": ("mV",)}),)
    options = RATE_OPTS + (Option("temperatures", "-40, -10, 20, 40, 60", None,
                                  "chamber points (°C), R5-like"),
                           Option("room_temperature", "20 °C", "degC", "T_m"))

    def sequence(self, options):
        steps = []
        for T in parse_floats(options["temperatures"], "temperatures"):
            steps += rate_steps("rate-temperature", parse_magnitudes(options["rates"], "rates"),
                                 {"temperature": quantity_text(T, "degC")}, tag=f"@{T:g}C")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        groups = group_by(need_segments(campaign, type(self), "rate-temperature"), "temperature")
        T = chamber_temperatures(groups, "7.2.5")
        keys = sorted(groups, key=T.get)
        temps = [T[k] for k in keys]
        if len(keys) < 2:
            raise DataError(campaign.source, "segments", "7.2.5 needs at least 2 temperatures")
        sets = [SFSet(groups[k]) for k in keys]
        m = room_index(temps, float(opts["room_temperature"].to("degC").magnitude), "7.2.5")
        Ks = [s.K for s in sets]
        kt, i = F.sf_temperature_eq11(Ks, temps, m)
        dT = temps[i] - temps[m]
        # one power-on through the chamber (7.2.5.1 d)): without a K_r the points carry their own
        # fits' u, not their scatter about a line in T — that holds K(T)'s curvature, a real slope
        # difference (interpretations.md, "7.2.5 / 7.2.16 — a curved K(T) is not noise")
        base = sf_repeatability(campaign)
        deg = 2 if len(Ks) >= 5 else 1
        rep = base if base is None else with_scatter(base,
                                                     *curve_scatter(np.asarray(Ks) / np.mean(Ks),
                                                                    temps, deg),
                                                     msg("the K_i about a straight line in T")
                                                     if deg == 1 else
                                                     msg("the K_i about a quadratic in T"))
        # the largest of N − 1 noisy slopes: its selection bias removed (interpretations.md, "JJF
        # 2014 — the largest of noisy slopes and changes"); the points drawn with K_r·K, or their
        # scatter about a line in T where it is smaller (one power-on through the chamber)
        sel = max_slope_selection(Ks, [s.u_single(rep)[0] for s in sets], temps, m, relative=True,
                                  observed=True,
                                  cap_degree=2)
        kt = max(sel.value, 0.0)
        # Kt = |K_i/K_m − 1|/|ΔT|: ∂/∂K_i = 1/(K_m|ΔT|), ∂/∂K_m ≈ K_i/(K_m²|ΔT|)
        ci, cm = 1 / (Ks[m] * abs(dT)), Ks[i] / (Ks[m] ** 2 * abs(dT))
        rows = [_k_row(sets[i], rep, msg("K_i at {T:g} °C", T=temps[i]), "u(K_i)/(K_m|ΔT|)", ci,
                       "1/delta_degC"),
                _k_row(sets[m], rep, msg("K_m at {T:g} °C", T=temps[m]), "K_i·u(K_m)/(K_m²|ΔT|)",
                       cm, "1/delta_degC")]
        u_point = math.hypot(*(float(r.contribution.magnitude) for r in rows))
        rows += spread_rows(sel, u_point, "1/delta_degC")
        rows += selection_rows(sel, len(Ks) - 1, "1/delta_degC", point_unit="mV/((°)/s)")
        rows += chamber_rows(campaign, kt / abs(dT) * math.sqrt(2), "1/delta_degC")
        b = B.type_a_budget("Kt", "1/delta_degC", one_estimate(rows, rep))
        tab = TableSpec("sf_temperature", msg("K_i per temperature"),
                        ["T_i (°C)", "K_i (mV/((°)/s))"],
                        [[f"{t:g}", f"{k:.7g}"] for t, k in zip(temps, Ks)])
        note = msg("maximum at T_i = {Ti:g} °C, T_m = {Tm:g} °C", Ti=temps[i], Tm=temps[m])
        if sel.bias:
            note = join("; ", [note, selection_note(sel, 1e6, "ppm/°C")])
        return self._outcome([Result(self.metrics[0], Q_(kt, "1/delta_degC"), b.combined, b,
                                     note=note)],
                             tables=[tab], segments=[x for s in sets for x in s.ids], opts=opts)


def _k_row(s: SFSet, rep, what: str, symbol: str, scale: float, unit: str) -> BudgetRow:
    """One calibration's K taken as the device's K at its condition, times ``scale``: the larger
    of the fit's standard error and the repeatability K_r·K (another calibration — power-on,
    temperature, mounting — gives another K; interpretations.md, "Repeatability in every
    budget")."""
    u, dof, src, typ = s.u_single(rep)
    if typ == "A":
        return budget_row_a(join(": ", [what, src]), symbol, u * scale, unit, dof)
    return BudgetRow.type_b(join(": ", [what, src]), symbol, Q_(u * scale, unit),
                            distribution="normal", k=1.0)


class SFAxialAcceleration(JJFItem):
    """JJF 2014—2022 7.2.6 标度因数轴向加速度敏感度: K with the IRA up and down (±1 g along the
    input axis), (K_up − K_down)/2 g (7.2.6.2)."""

    item = "7.2.6"
    title = "Scale-factor axial-acceleration sensitivity (标度因数轴向加速度敏感度)"
    clause = "7.2.6"
    metrics = (Metric("Kg", "scale-factor axial-acceleration sensitivity", "K_g", "mV/(deg/s)/gn",
                      "7.2.6.2", "prose, no eq. number"),)
    requires = (SegmentRequirement("rate-accel", "7.2.1 with the IRA pointing up and down",
                                   {"rate": "deg/s",
                                   "orientation": ""}, {"output": ("mV",)}),)
    options = RATE_OPTS

    def sequence(self, options):
        steps = []
        for o in ("IRA up", "IRA down"):
            steps += rate_steps("rate-accel", parse_magnitudes(options["rates"], "rates"),
                                {"orientation": o},
                                 tag=f"[{o.split()[1]}]")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        segs = need_segments(campaign, type(self), "rate-accel")
        g: dict[str, list[Segment]] = {}
        for s in segs:
            g.setdefault(up_or_down(s), []).append(s)
        if set(g) != {"up", "down"}:
            raise DataError(campaign.source, "segments",
                            "7.2.6 needs calibrations with the IRA up and with it down")
        up, dn = SFSet(g["up"]), SFSet(g["down"])
        kg = F.per_g_726(up.K, dn.K)
        rep = sf_repeatability(campaign)
        b = B.type_a_budget("Kg", "mV/(deg/s)/gn", one_estimate([
            _k_row(up, rep, "K (IRA up)", "u(K_up)/2g", 0.5, "mV/(deg/s)/gn"),
            _k_row(dn, rep, "K (IRA down)", "u(K_down)/2g", 0.5, "mV/(deg/s)/gn"),
            *B.relative_calibration_row("rate table (common to both, acts on the difference)",
                                        "u_rel(Ω)",
                                        calibration_of(campaign, "rate_table"),
                                        Q_(kg, "mV/(deg/s)/gn"))], rep))
        return self._outcome([Result(self.metrics[0], Q_(kg, "mV/(deg/s)/gn"), b.combined, b,
                                     note=msg("K_up = {up:.7g}, K_down = {down:.7g} mV/((°)/s)",
                                              up=up.K, down=dn.K))],
                             segments=up.ids + dn.ids, opts=opts)


class _SFChange(JJFItem):
    """7.2.7 and 7.2.8: K before and after a ``what`` on each axis (segments ``kind``,
    ``rate-<what>``); a subclass names ``what`` and the ``event`` (its wording in the segment's
    description) as class keywords."""

    kind = ""
    what = ""
    options = RATE_OPTS

    def __init_subclass__(cls, what: str = "", event: str = "", **kw: Any) -> None:
        super().__init_subclass__(**kw)
        if not what:  # a subclass of a complete item keeps its segments
            return
        cls.what, cls.kind = what, f"rate-{what}"
        cls.requires = (SegmentRequirement(cls.kind, f"7.2.1 before and after {event} on each axis",
                                           {"rate": "deg/s", "axis": "", "phase": ""},
                                           {"output": ("mV",)}),)

    def sequence(self, options):
        steps = []
        for a in AXES:
            for p in ("before", "after"):
                steps += rate_steps(self.kind, parse_magnitudes(options["rates"], "rates"),
                                    {"axis": a, "phase": p},
                                     tag=f"[{a}-{p}]")
        return steps

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        sets: dict[tuple[str, str], list[Segment]] = {}
        for s in need_segments(campaign, type(self), self.kind):
            sets.setdefault((axis_of(s), phase_of(s)), []).append(s)
        fits = {k: SFSet(v) for k, v in sets.items()}
        before, after, printed, worst, per = before_after_change(
            {k: f.K for k, f in fits.items()}, self.item, campaign.source)
        w = [] if len(per) == 3 else [msg("only the axes {axes} were tested (the clause asks for "
                                          "X, Y, Z)", axes=", ".join(per))]
        ax = list(per)
        rep = with_scatter(sf_repeatability(campaign),
                           float(np.std([before[a] for a in ax], ddof=1) / abs(np.mean(
            [before[a] for a in ax]))) if len(ax) > 1 else 0.0, len(ax) - 1,
                           msg("K before the test over the axes"))
        # the largest of the axes' |ΔK|: its selection bias removed (interpretations.md, "JJF 2014
        # — the largest of noisy slopes and changes"), drawn with the scatter of the K before the
        # test over the axes where it is smaller than K_r·K
        u_of = {k: f.u_single(rep)[0] for k, f in fits.items()}
        sel = max_abs_selection([after[a] - before[a] for a in ax],
                                [math.hypot(u_of[(a, "before")], u_of[(a, "after")]) for a in ax],
                                same=[before[a] for a in ax])
        dk = max(sel.value, 0.0)
        rows = [_k_row(fits[(worst, "before")], rep, msg("K before ({axis})", axis=worst), "u(K₁)",
                       1.0, KU),
                _k_row(fits[(worst, "after")], rep, msg("K after ({axis})", axis=worst), "u(K₂)",
                       1.0, KU)]
        u_point = math.hypot(*(float(r.contribution.magnitude) for r in rows))
        rows += spread_rows(sel, u_point, KU) + selection_rows(sel, len(ax), KU, slopes=False,
                                                               point_unit="mV/((°)/s)")
        b = B.type_a_budget(self.metrics[0].key, KU, one_estimate([
            *rows,
            *B.relative_calibration_row("rate table (common, acts on the difference)", "u_rel(Ω)",
                                        calibration_of(campaign, "rate_table"), Q_(dk, KU))], rep))
        tab = TableSpec("per_axis",
                        msg("K before/after shock per axis") if self.what == "shock" else
                        msg("K before/after vibration per axis"),
                        [msg("axis"), "K₁ (mV/((°)/s))", "K₂ (mV/((°)/s))", "|ΔK|"],
                        [[a, f"{before[a]:.7g}", f"{after[a]:.7g}", f"{per[a]:.3g}"] for a in per])
        note = msg("largest on axis {axis}", axis=worst)
        if sel.bias:
            note = join("; ", [note, selection_note(sel, 1.0, "mV/((°)/s)")])
        return self._outcome([Result(self.metrics[0], Q_(dk, KU), b.combined, b, note=note)],
                             tables=[tab], warnings=w,
                             segments=[i for s in fits.values() for i in s.ids], opts=opts)


class SFShock(_SFChange, what="shock", event="a shock"):
    """JJF 2014—2022 7.2.7 标度因数冲击前后变化量: ΔK_ij = |K_ij2 − K_ij1| eq. (12), max over X, Y,
    Z eq. (13)."""

    item = "7.2.7"
    title = "Scale-factor change after shock (标度因数冲击前后变化量)"
    clause = "7.2.7"
    metrics = (Metric("dK_shock", "scale-factor change after shock", "ΔK_i", KU, "7.2.7.2",
                      "12, 13"),)


class SFVibration(_SFChange, what="vibration", event="vibration"):
    """JJF 2014—2022 7.2.8 标度因数振动前后变化量: ΔK_vj eq. (14), max over X, Y, Z eq. (15)."""

    item = "7.2.8"
    title = "Scale-factor change after vibration (标度因数振动前后变化量)"
    clause = "7.2.8"
    metrics = (Metric("dK_vib", "scale-factor change after vibration", "ΔK_v", KU, "7.2.8.2",
                      "14, 15"),)

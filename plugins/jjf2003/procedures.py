"""JJF 2003—2022 items 7.2.1–7.2.5 (the eight items of table 2).

Table 2 → metro item ids:

* 1 陀螺标度因数 → ``7.2.1`` :class:`GyroScaleFactor`
* 2 陀螺零偏, 3 陀螺零偏加速度敏感系数 → ``7.2.2`` :class:`GyroBiasGSensitivity`
* 4 陀螺交叉耦合系数 → ``7.2.3`` :class:`GyroCrossCoupling`
* 5 加速度计偏值, 6 标度因数, 7 交叉耦合系数 → ``7.2.4`` :class:`AccelSixPosition`
* 8 加速度计角速度灵敏系数 → ``7.2.5`` :class:`AccelRateSensitivity`

Data: ``rate`` segments (conditions ``axis`` = x|y|z pointing up along the table axis,
``rate`` signed about +axis) and ``position`` segments (conditions ``up`` = ±x|±y|±z,
``heading`` = 0°|180°), with columns gx, gy, gz (angular rate) and ax, ay, az (acceleration).
Budgets follow appendix A: u₁ three-axis table, u₂ acquisition quantization, u₃ repeatability
of K from the campaign's repeated sweeps (kind ``rate-repeat``); k = t_p(ν_eff) at 95.45 % (2 for
appendix A's large ν_eff); U rounded up to two significant digits.
"""

from __future__ import annotations

import abc
import math
from typing import Any, Mapping

import numpy as np
from metro.api import (EARTH_RATE_DEG_S, Q_, BudgetRow, Campaign, DataError, Metric, Option,
                       Outcome, PlotSpec, Procedure, ProcedureError, Result, RunContext, Segment,
                       Step, TableSpec, UncertaintyBudget, hint, index, join, msg)

from . import drift as D
from . import formulas as F
from . import mounting
from .common import (COVERAGE, EQUIPMENT, EQUIPMENT_FIXTURE, POSITION_SEG, RATE_SEG, ROUND,
                     STANDARD, STATION, SWEEP_OPTIONS, abs_quant_row, options_text, position_steps,
                     relative_quant_row, sweep_steps, table_position_row, table_rate_row)
from .data import (  # noqa: F401 - re-exported: the segment layout and the shared computations
    ACC_UNIT,
    ACCEL,
    AXES,
    BATCHES,
    G_UNIT,
    GYRO,
    HEADINGS,
    MIN_SECONDS,
    P_UNIT,
    RATE_UNIT,
    Means,
    axis_of,
    batch_u,
    columns_of,
    data_means,
    duration_ok,
    heading_of,
    ideal_evaluation,
    p_matrix,
    positions,
    rate_of,
    rate_pairs,
    six_position,
    sweep_fits,
    sweeps,
)


def repeat_fits(campaign: Campaign, means: Means) -> list[dict[str, dict[str, Any]]]:
    """The campaign's repeated 7.2.1 calibrations (kind ``rate-repeat``, condition ``run``; the
    MIMU powered off and remounted between runs), each as :func:`sweep_fits`."""
    runs: dict[str, list[Segment]] = {}
    for seg in campaign.find_segments("rate-repeat"):
        runs.setdefault(str(seg.condition("run")), []).append(seg)
    return [sweep_fits(campaign, means, g) for _, g in sorted(runs.items())]


def _repeatability_row(campaign, fits, repeats, i, j, warnings) -> BudgetRow:
    """Appendix A.1.2.3 u₃ of K_g[i, j]: a repeatability "from a large amount of experimental data"
    (interpretations.md, "Appendix A — u₃ of K is a repeatability"): the standard deviation of
    K_g[i, j] over the campaign's calibrations (the 7.2.1 sweep and its ``rate-repeat`` runs,
    ν = runs − 1); else ``device.scale_factor_repeatability`` (relative, × |K_jj|, type B);
    never less than the eq. (5) fit's standard error, which alone is the fallback (warned)."""
    d = fits[AXES[j]]
    fit = d["fits"][i]
    se, dof = float(fit.stderr[0]), max(fit.dof, 1)
    if repeats:
        Ks = [float(d["fits"][i].coef[0])] + [float(r[AXES[j]]["fits"][i].coef[0]) for r in repeats]
        sd = float(np.std(Ks, ddof=1))
        if sd >= se:
            return BudgetRow.type_a(msg("repeatability: standard deviation of K over this "
                                        "campaign's {n} calibrations (A.1.2.3)", n=len(Ks)), "u₃",
                                    Q_(sd, ""), len(Ks) - 1)
        return BudgetRow.type_a(msg("repeatability: least-squares scatter of eq. (5) (larger than "
                                    "the spread of {n} calibrations, A.1.2.3)", n=len(Ks)), "u₃",
                                Q_(se, ""), dof)
    stated = campaign.device.properties.get("scale_factor_repeatability")
    if stated not in (None, ""):
        from metro.api import parse_quantity

        rel = float(parse_quantity(stated, dimension="", file=campaign.source,
                                   field="device.scale_factor_repeatability").to("").magnitude)
        Kjj = abs(float(d["fits"][j].coef[0]))
        if rel * Kjj >= se:
            return BudgetRow.type_b(msg("repeatability stated for the device (A.1.2.3){hint}",
                                        hint=hint(" (device.scale_factor_repeatability)")), "u₃",
                                    Q_(rel, ""), distribution="normal", k=1.0,
                                    sensitivity=Q_(Kjj, ""))
    else:
        warnings.append(msg("no repeated calibrations (7.2.1) and no stated repeatability of K: u₃ "
                            "of K is the eq. (5) fit's standard error, which leaves out the "
                            "variation of K between power-ons and mountings{hint}",
                            hint=hint(" (rate-repeat runs, option repeats of 7.2.1, or "
                                                         "device.scale_factor_repeatability)")))
    return BudgetRow.type_a(msg("repeatability: least-squares scatter of eq. (5)"), "u₃",
                            Q_(se, ""), dof,
                            note=msg("{n} rate points", n=len(d['X'])))


def _fit_results(proc, campaign, fits, pairs, warnings, repeats=()) -> list[Result]:
    results = []
    drift = D.campaign_drift(campaign)
    warnings.extend(D.drift_warning(drift))
    for (i, j) in pairs:
        d = fits[AXES[j]]
        fit = d["fits"][i]
        K = float(fit.coef[0])
        Kjj = float(d["fits"][j].coef[0])
        rows = table_rate_row(campaign, Q_(abs(Kjj), ""), msg("input rate error scales the slope "
                                                              "(A.1.2.1)"), warnings)
        rows += relative_quant_row(campaign, Kjj, warnings)
        rows.append(_repeatability_row(campaign, fits, repeats, i, j, warnings))
        # the swept axis off the MIMU's axis j puts K_ii·δ into K_g[i, j] (interpretations)
        if i != j:
            rows += mounting.swept_axis_rows(campaign, float(fits[AXES[i]]["fits"][i].coef[0]))
        # a gyro bias drifting while the sweep is recorded adds its change to the slope (drift.py):
        # corrected with the recording times, its correction's uncertainty budgeted
        note = msg("fitted bias b = {b:.5g} °/s", b=float(fit.coef[1]))
        if drift.corrects(i):
            delta, drows = D.correction(drift, i, D.sweep_gradient(drift, i, d["X"], d["segments"]),
                                        "",
                                        msg("the sweep about {axis}", axis=AXES[j]), "s/(°/s)")
            K -= delta
            rows += drows
            if delta:
                note = join("; ", [note, D.corrected_note(delta, "")])
        elif drift.mid_times is not None:
            tau = D.sweep_factor(d["X"], [drift.mid_times[sid] for sid in d["segments"]])
            rows.append(D.drift_row(drift, i, tau, "", msg("the sweep about {axis}", axis=AXES[j]),
                                    "s/(°/s)"))
        metric = proc.metric_for(i, j)
        budget = UncertaintyBudget(metric.symbol, "", rows, coverage=COVERAGE, round_mode=ROUND)
        reason = None
        # no recording times: the drift the trends cannot exclude (drift.py)
        if drift.mid_times is None:
            tau = D.plan_sweep_factor(d["X"], [drift.durations[sid] for sid in d["segments"]])
            reason = D.not_reportable_reason(drift, i, tau, float(budget.expanded.to("").magnitude),
                                             "")
            row = D.bound_row(drift, i, tau, "", msg("the sweep about {axis}", axis=AXES[j]),
                              "s/(°/s)")
            if row is not None:
                budget = UncertaintyBudget(metric.symbol, "", rows + [row], coverage=COVERAGE,
                                           round_mode=ROUND)
        results.append(Result(metric, Q_(K, ""), budget.combined, budget, note=note,
                              earth_rate="not applicable",
                              reportable=reason is None, reason=reason or ""))
    return results


def _kg_metric(i: int, j: int) -> Metric:
    r, c = AXES[i], AXES[j]
    if i == j:
        return Metric(f"K_g{r}{c}", msg("{axis} gyro scale factor", axis=r.upper()), f"K_g{r}{c}",
                      "", "7.2.1.2", "eq. (5)")
    return Metric(f"K_g{r}{c}",
                  msg("gyro cross-coupling ({input} input → {gyro} gyro)", input=c.upper(),
                      gyro=r.upper()), f"K_g{r}{c}", "",
                  "7.2.3.2", "K̄_g, eq. (5)")


def _fit_plot_table(fits) -> tuple[PlotSpec, TableSpec]:
    series, rows = [], []
    for j, d in fits.items():
        i = AXES.index(j)
        fit = d["fits"][i]
        series.append({"label": msg("{axis} axis: residual of eq. (5)", axis=j),
                       "x": d["X"].tolist(),
                       "y": np.asarray(fit.residuals).tolist(), "style": "o-"})
        for X, U, sid in zip(d["X"], d["U"], d["segments"]):
            rows.append([j, f"{X:g}", f"{U[0]:.6g}", f"{U[1]:.6g}", f"{U[2]:.6g}", sid])
    plot = PlotSpec("sf_residuals", msg("Residuals of the eq. (5) fits"), msg("input rate (°/s)"),
                    msg("residual (°/s)"), series)
    table = TableSpec("rate_points", msg("Mean outputs at each rate point, eq. (3)"),
                      [msg("axis"), msg("rate (°/s)"), "gx (°/s)", "gy (°/s)", "gz (°/s)",
                       msg("segment")], rows)
    return plot, table


def _sweep_warnings(campaign: Campaign, fits) -> list[str]:
    w = []
    rng = campaign.device.properties.get("gyro_range")
    for j, d in fits.items():
        if len(d["X"]) > 11:
            w.append(f"axis {j}: {len(d['X'])} rate points; 7.2.1.1 c) asks for 7–11")
        if rng is not None:
            top = float(rng.to("deg/s").magnitude)
            if np.max(np.abs(d["X"])) < 0.999 * top:
                w.append(f"axis {j}: the largest rate {np.max(np.abs(d['X'])):g} °/s is below the "
                         f"measuring range {top:g} °/s; 7.2.1.1 c) includes the maximum input rate")
    return w


class _GyroSweepItem(Procedure):
    """The items read from the three 7.2.1 sweeps: the fits of eq. (5) per swept axis, the results
    of the ``pairs`` (i, j) of K̄_g (appendix A.1/A.4 budgets) and the item's figures."""

    standard = STANDARD
    requires = (RATE_SEG,)
    options = SWEEP_OPTIONS
    station = STATION
    #: the (output i, swept axis j) entries of K̄_g the item reports
    pairs: tuple[tuple[int, int], ...] = ()

    @staticmethod
    def metric_for(i: int, j: int) -> Metric:
        return _kg_metric(i, j)

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return sweep_steps(options)

    @abc.abstractmethod
    def figures(self, fits) -> tuple[list[PlotSpec], list[TableSpec]]:
        """The item's plots and tables from the sweeps' fits."""

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        means, _ = data_means(campaign)
        fits = sweep_fits(campaign, means)
        warnings = _sweep_warnings(campaign, fits)
        results = _fit_results(self, campaign, fits, list(self.pairs), warnings,
                               repeat_fits(campaign, means))
        plots, tables = self.figures(fits)
        segs = [s for d in fits.values() for s in d["segments"]]
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=plots,
                       tables=tables, warnings=_unique(warnings), segments=segs,
                       options=options_text(opts))


class GyroScaleFactor(_GyroSweepItem):
    """JJF 2003—2022 7.2.1 陀螺标度因数: K_gxx, K_gyy, K_gzz by least squares, eq. (3)–(5).

    Each axis is swept over 7–11 rates (≥ 30 s each); U_k = mean output (3), [K b] = (HᵀH)⁻¹HᵀU (5).
    Budget (appendix A.1): u₁ table rate (relative, × K), u₂ quantization δ/√3 (× K), u₃ the
    standard error of K from the fit; k = 2, U rounded up.
    """

    item = "7.2.1"
    title = "Gyro scale factors (陀螺标度因数)"
    clause = "7.2.1"
    metrics = tuple(_kg_metric(i, i) for i in range(3))
    equipment = EQUIPMENT
    pairs = tuple((i, i) for i in range(3))

    def figures(self, fits) -> tuple[list[PlotSpec], list[TableSpec]]:
        """The fitted lines of the three sweeps and the table of their coefficients."""
        plot, table = _fit_plot_table(fits)
        return [plot], [table]


class GyroCrossCoupling(_GyroSweepItem):
    """JJF 2003—2022 7.2.3 陀螺交叉耦合: the full K̄_g matrix (7.2.3.2) from the three sweeps of
    7.2.1.

    Column j of K̄_g holds the eq. (5) slopes of the three gyro outputs while the table turns
    about axis j; the off-diagonal terms are the cross-coupling coefficients.  Budget as A.4
    (the same model as the scale factor; u₁ and u₂ relative to K_jj of the swept axis).
    """

    item = "7.2.3"
    title = "Gyro cross-coupling (陀螺交叉耦合系数)"
    clause = "7.2.3"
    metrics = tuple(_kg_metric(i, j) for i in range(3) for j in range(3))
    equipment = EQUIPMENT_FIXTURE
    pairs = tuple((i, j) for i in range(3) for j in range(3))

    def figures(self, fits) -> tuple[list[PlotSpec], list[TableSpec]]:
        """K̄_g (7.2.3.2): rows the gyro outputs, columns the swept axes."""
        K = np.array([[float(fits[AXES[j]]["fits"][i].coef[0]) for j in range(3)]
                      for i in range(3)])
        table = TableSpec("K_g", msg("K̄_g (rows: gyro x, y, z; columns: input about x, y, z)"),
                          ["", "x", "y", "z"],
                          [[AXES[i]] + [f"{K[i, j]:.6g}" for j in range(3)] for i in range(3)])
        return [], [table]


def _six_budget_rows(campaign, u_means, segs, which, col, i, M, warnings, unit, range_prop,
                     per_gn: bool):
    """Appendix A.2/A.3 rows for entry (i, col) of [M | B] from the six-position data."""
    S = F.six_position_sensitivities()  # 6 × 4
    c = S[:, col]
    u6 = []
    for up in F.SIX_POSITIONS:
        u0 = u_means(segs[(up, 0.0)])[which][i]
        u1 = u_means(segs[(up, 180.0)])[which][i]
        u6.append(0.5 * math.hypot(u0, u1))
    out_unit = unit + ("/gn" if per_gn else "")
    csum = Q_(float(np.sum(np.abs(c))), "1/gn" if per_gn else "")
    uA = float(np.sum(np.abs(c) * np.array(u6)))
    rows = [BudgetRow.type_a(msg("repeatability of the position means, Σ|cᵢ|·u(Uᵢ) (A.2.2.3)"),
                             "u₃",
                             Q_(uA, out_unit), BATCHES - 1,
                             note=msg("{n} batch means per mounting; linear sum as appendix A",
                                      n=BATCHES))]
    rows += abs_quant_row(campaign, range_prop, unit, csum, warnings)
    if col < 3:  # a matrix term: per g_n of the local gravity (Ā), and the fixture's misalignment
        rows.append(mounting.gravity_row(campaign, float(M[i, col]), out_unit))
        if col != i:
            rows.append(mounting.fixture_row(campaign, float(M[i, i]), out_unit))
    off = ([abs(M[i, k]) for k in range(3) if k != col] if col < 3
           else [abs(M[i, k]) for k in range(3)])
    tilt = max(off) if off else 0.0
    if tilt > 0:
        sens = Q_(tilt, f"{out_unit}/rad") if per_gn else Q_(tilt, f"{unit}/rad")
        rows += table_position_row(campaign, sens, msg("a tilt δθ puts δθ·gn on the other axes"),
                                   warnings)
    return rows


def _unique(seq):
    return list(dict.fromkeys(seq))


def _earth_rate_leak(campaign: Campaign, means: Means, warnings: list[str]) -> np.ndarray:
    """7.2.2 with option earth_rate = yes (a deviation, stated in ``warnings``): the vertical
    earth rate K_g[:, j]·Ω_e·sin φ / g that eq. (7) puts into column j of the g matrix, K̄_g from
    the campaign's 7.2.3 sweeps (else the identity)."""
    lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    try:
        fits = sweep_fits(campaign, means)
        Kg = np.array([[float(fits[AXES[j]]["fits"][i].coef[0]) for j in range(3)]
                       for i in range(3)])
        src = msg("K̄_g from the campaign's rate sweeps (7.2.3)")
    except (DataError, ProcedureError):
        Kg = np.eye(3)
        src = msg("K̄_g taken as the identity (no complete rate sweeps in the campaign)")
    leak = F.earth_rate_leak(Kg, lat, EARTH_RATE_DEG_S) / mounting.local_gravity(campaign)[0]
    warnings.append(msg("DEVIATION from JJF 2003 7.2.2: the vertical earth rate (Ω·sin φ = "
                        "{rate:.4f} °/h at φ = {lat:g}°) that eq. (7) puts into the g "
                        "matrix was removed, using {src}",
                        rate=EARTH_RATE_DEG_S * math.sin(math.radians(lat)) * 3600, lat=lat,
                        src=src))
    return leak


def _six_drift_factors(drift, segs: dict, ratio: float) -> np.ndarray:
    """How a drift enters each column j of eq. (7) through the ±j differences (drift.py): from
    the recording times of the twelve mountings, else from the planned durations."""
    if drift.mid_times is not None:
        mid = drift.mid_times
        return D.six_position_factors(
            [0.5 * (mid[segs[(up, 0.0)].id] + mid[segs[(up, 180.0)].id])
             for up in F.SIX_POSITIONS], ratio)
    return D.plan_six_factors({k: drift.durations[sg.id] for k, sg in segs.items()}, ratio)


def _earth_rate_note(campaign: Campaign, leak: np.ndarray | None, i: int,
                     j: int) -> tuple[str, str]:
    """The earth-rate statement of g_ij (note, "removed" or "included"): the vertical earth rate
    is along +j with axis j up and flips with it, so eq. (7) puts K_g[:, j]·Ω_e·sin φ into the
    whole column j — the diagonal mostly, the cross terms by the cross-coupling
    (interpretations.md, "Earth rate disclosed (JJF 2003)")."""
    r, c = AXES[i], AXES[j]
    try:
        lat = float(campaign.site_value("latitude", "deg").to("deg").magnitude)
    except (DataError, KeyError, ValueError):
        lat = math.nan
    v = EARTH_RATE_DEG_S * math.sin(math.radians(lat)) / mounting.local_gravity(campaign)[0]
    if leak is not None:
        return msg("earth-rate leak {leak:.3g} (°/s)/gn removed (deviation)",
                   leak=leak[i, j]), "removed"
    if i == j:
        return msg("earth rate included: eq. (7) puts K_g{r}{r}·Ω_e·sin φ ≈ {v:.3g} (°/s)/gn "
                   "(φ = {lat:g}°) into g_{r}{r}, as the standard prints{hint}", r=index(r), v=v,
                   lat=lat, hint=hint("; option earth_rate = yes removes it")), "included"
    return msg("earth rate included: eq. (7) puts the cross-coupling K_g{r}{c} × Ω_e·sin φ "
               "({v:.3g} (°/s)/gn at φ = {lat:g}°) into g_{r}{c}{hint}", r=index(r), c=index(c),
               v=v, lat=lat, hint=hint("; option earth_rate = yes removes it")), "included"


class GyroBiasGSensitivity(Procedure):
    """JJF 2003—2022 7.2.2 陀螺零偏、零偏加速度敏感系数: B_g and the 3×3 g matrix, eq. (6)–(8).

    Twelve mountings (six axis-up/axis-down positions, each at heading 0° and 180°); U_i is the
    pair mean; Ḡ = U·Āᵀ(ĀĀᵀ)⁻¹ = [G | B].  Option ``earth_rate``: ``no`` (the standard) or
    ``yes`` (subtract the vertical earth rate K_g[:, j]·Ω·sin φ that eq. (7) puts into column j;
    a deviation, stated in the warnings).  Budget (A.2, A.3): u₃ repeatability Σ|cᵢ|u(Uᵢ),
    u₂ quantization (δ·FS = FS/2^N per mean), u₁ table positioning (tilt).
    """

    standard = STANDARD
    item = "7.2.2"
    title = "Gyro bias and g-sensitivity (陀螺零偏、零偏加速度敏感系数)"
    clause = "7.2.2"
    metrics = tuple(Metric(f"B_g{r}", msg("{axis} gyro bias", axis=r.upper()), f"B_g{r}", RATE_UNIT,
                           "7.2.2.2", "eq. (8)")
                    for r in AXES) + tuple(
        Metric(f"g_{r}{c}",
               msg("gyro g-sensitivity ({input} acceleration → {gyro} gyro)", input=c.upper(),
                   gyro=r.upper()), f"g_{r}{c}",
               G_UNIT, "7.2.2.2", "eq. (8)") for r in AXES for c in AXES)
    requires = (POSITION_SEG,)
    equipment = EQUIPMENT_FIXTURE
    options = (Option("earth_rate", "no", None,
                      "yes: remove the earth-rate leak from the g diagonal (a deviation from "
                      "7.2.2; needs site.latitude)"),)
    station = STATION

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return position_steps()

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        flag = str(opts["earth_rate"]).strip().lower()
        if flag not in ("yes", "no", "true", "false", "on", "off"):
            raise ProcedureError("7.2.2: option earth_rate must be yes or no, got "
                                 f"{opts['earth_rate']!r}")
        correct = flag in ("yes", "true", "on")
        means, u_means = data_means(campaign)
        U, GB, seg_ids = six_position(campaign, means, 0)
        segs = positions(campaign)
        warnings: list[str] = []
        G = GB[:, :3].copy()
        leak = _earth_rate_leak(campaign, means, warnings) if correct else None
        if leak is not None:
            G = G - leak
        results = []
        drift = D.campaign_drift(campaign)
        warnings.extend(D.drift_warning(drift))
        ratio = mounting.local_gravity(campaign)[0]
        pairs = [(segs[(up, 0.0)].id, segs[(up, 180.0)].id) for up in F.SIX_POSITIONS]
        tau = _six_drift_factors(drift, segs, ratio)
        for i in range(len(AXES)):
            rows = _six_budget_rows(campaign, u_means, segs, 0, 3, i, G, warnings, RATE_UNIT,
                                    "gyro_range", False)
            m = self.metrics[i]
            b = UncertaintyBudget(m.symbol, RATE_UNIT, rows, coverage=COVERAGE, round_mode=ROUND)
            results.append(Result(m, Q_(float(GB[i, 3]), RATE_UNIT), b.combined, b,
                                  earth_rate="not applicable",
                                  note=msg("the vertical earth rate flips with the up axis and "
                                           "cancels in the mean of six")))
        for i in range(len(AXES)):
            for j, c in enumerate(AXES):
                rows = _six_budget_rows(campaign, u_means, segs, 0, j, i, G, warnings, RATE_UNIT,
                                        "gyro_range", True)
                delta = 0.0
                if drift.corrects(i):
                    delta, drows = D.correction(drift, i, D.six_gradient(drift, i, pairs, j, ratio),
                                                G_UNIT,
                                                msg("the ±{axis} mountings", axis=c), "s/gn",
                                                " (°/s)/gn")
                    rows += drows
                elif drift.mid_times is not None:
                    rows.append(D.drift_row(drift, i, float(tau[j]), G_UNIT,
                                            msg("the ±{axis} mountings", axis=c),
                                            "s/gn"))
                m = self.metrics[3 + 3 * i + j]
                b = UncertaintyBudget(m.symbol, G_UNIT, rows, coverage=COVERAGE, round_mode=ROUND)
                reason = None
                # no recording times: the drift the trends cannot exclude
                if drift.mid_times is None:
                    reason = D.not_reportable_reason(drift, i, float(tau[j]),
                                                     float(b.expanded.to(G_UNIT).magnitude),
                                                     " (°/s)/gn")
                    row = D.bound_row(drift, i, float(tau[j]), G_UNIT,
                                      msg("the ±{axis} mountings", axis=c), "s/gn")
                    if row is not None:
                        b = UncertaintyBudget(m.symbol, G_UNIT, rows + [row], coverage=COVERAGE,
                                              round_mode=ROUND)
                note, er = _earth_rate_note(campaign, leak, i, j)
                if delta:
                    note = join("; ", [note, D.corrected_note(delta, " (°/s)/gn")])
                results.append(Result(m, Q_(float(G[i, j]) - delta, G_UNIT), b.combined, b,
                                      note=note, earth_rate=er,
                                      reportable=reason is None, reason=reason or ""))
        table = TableSpec("six_positions", msg("Pair-averaged gyro outputs U_g (°/s), eq. (6)"),
                          ["", *F.SIX_POSITIONS],
                          [[f"g{AXES[i]}"] + [f"{U[i, k]:.6g}" for k in range(6)]
                                                   for i in range(3)])
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[table],
                       warnings=_unique(warnings), segments=seg_ids, options=options_text(opts))


class AccelSixPosition(Procedure):
    """JJF 2003—2022 7.2.4 加速度计偏值、标度因数、交叉耦合: K̄_a = U_a·Āᵀ(ĀĀᵀ)⁻¹ = [K_a | B_a],
    eq. (9)–(11), from the same twelve mountings as 7.2.2.

    Diagonal of K_a: scale factors; off-diagonal: cross-coupling; B_a: biases (gn).  Budget as
    7.2.2 (u₃ repeatability, u₂ quantization over the accelerometer range, u₁ table tilt).
    """

    standard = STANDARD
    item = "7.2.4"
    title = ("Accelerometer biases, scale factors and cross-coupling "
             "(加速度计偏值、标度因数、交叉耦合)")
    clause = "7.2.4"
    metrics = tuple(Metric(f"B_a{r}", msg("{axis} accelerometer bias", axis=r.upper()), f"B_a{r}",
                           ACC_UNIT, "7.2.4.2", "eq. (11)")
                    for r in AXES) + tuple(
        Metric(f"K_a{r}{c}",
               (msg("{axis} accelerometer scale factor", axis=r.upper()) if r == c else
                              msg("accelerometer cross-coupling ({input} input → {acc} "
                                  "accelerometer)", input=c.upper(),
                                  acc=r.upper())),
               f"K_a{r}{c}", "", "7.2.4.2", "eq. (11)") for r in AXES for c in AXES)
    requires = (POSITION_SEG,)
    equipment = EQUIPMENT_FIXTURE
    options = ()
    station = STATION

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        return position_steps()

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        means, u_means = data_means(campaign)
        U, KB, seg_ids = six_position(campaign, means, 1)
        segs = positions(campaign)
        warnings: list[str] = []
        results = []
        for i in range(3):
            rows = _six_budget_rows(campaign, u_means, segs, 1, 3, i, KB[:, :3], warnings, ACC_UNIT,
                                    "accel_range",
                                    False)
            m = self.metrics[i]
            b = UncertaintyBudget(m.symbol, ACC_UNIT, rows, coverage=COVERAGE, round_mode=ROUND)
            results.append(Result(m, Q_(float(KB[i, 3]), ACC_UNIT), b.combined, b,
                                  earth_rate="not applicable"))
        for i in range(3):
            for j in range(3):
                rows = _six_budget_rows(campaign, u_means, segs, 1, j, i, KB[:, :3], warnings,
                                        ACC_UNIT,
                                        "accel_range", True)
                m = self.metrics[3 + 3 * i + j]
                b = UncertaintyBudget(m.symbol, "", rows, coverage=COVERAGE, round_mode=ROUND)
                results.append(Result(m, Q_(float(KB[i, j]), ""), b.combined, b,
                                      earth_rate="not applicable"))
        table = TableSpec("six_positions", msg("Pair-averaged accelerometer outputs U_a (gn), eq. "
                                               "(9)"),
                          ["", *F.SIX_POSITIONS],
                          [[f"a{AXES[i]}"] + [f"{U[i, k]:.6g}" for k in range(6)]
                                                   for i in range(3)])
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[table],
                       warnings=_unique(warnings), segments=seg_ids, options=options_text(opts))


def _p_model(p: float, rows: list, rate_row: int | None):
    """7.2.5's measurement model for the Monte Carlo check (:func:`.formulas.
    rate_sensitivity_model`): each row's c_i in gn/(rad/s)², the table's ε at ``rate_row``."""
    cs = [float((r.sensitivity * Q_(1.0, r.value.units)).to(P_UNIT).magnitude) for r in rows]
    return F.rate_sensitivity_model(p, cs, rate_row)


def _accel_scale(campaign: Campaign, means: Means, pairs, i: int) -> float:
    """|K_ii|·g of accelerometer i in g_n, the sensitivity of its reading to a tilt: its reading at
    rest with axis i up (U₇ of axis i's sweep), bias included (a few per cent of the row at
    most)."""
    rest = pairs[AXES[i]][0]
    return abs(float(means(rest)[1][i]))


class AccelRateSensitivity(Procedure):
    """JJF 2003—2022 7.2.5 加速度计角速度灵敏系数: the six off-diagonal p terms, eq. (12), (13).

    Axis j up on the rate table: U₇ at rest, U₈ turning at ω; p_ij = (U₈ − U₇)/ω² with ω in rad/s.
    Eq. (12) prints (U₇ − U₈)/ω², the opposite sign to the model eq. (2): metro follows the
    model by default (option ``sign`` = ``model`` | ``as-printed``; docs/interpretations.md).
    Budget (A.5): u₃ = |c|(u(U₇) + u(U₈)), u₂ quantization (δ·FS in each mean), u₁ table rate
    (c(ω) = −2p/ω, so 2|p|·u_rel).
    """

    standard = STANDARD
    item = "7.2.5"
    title = "Accelerometer angular-rate sensitivity (加速度计角速度灵敏系数)"
    clause = "7.2.5"
    metrics = tuple(Metric(f"p_{r}{c}", msg("accelerometer rate sensitivity ({rate} rate → {acc} "
                                            "accelerometer)",
                               rate=c.upper(), acc=r.upper()), f"p_{r}{c}", P_UNIT, "7.2.5.2",
                           "eq. (12)")
                    for r in AXES for c in AXES if r != c)
    requires = (RATE_SEG,)
    equipment = EQUIPMENT
    options = (Option("omega", "400 deg/s", "deg/s", "table rate ω of 7.2.5.1 b)"),
               Option("sign", "model", None,
                      "model: p = (U₈ − U₇)/ω² (eq. (2)); as-printed: (U₇ − U₈)/ω² (eq. (12))"))
    station = STATION

    def sequence(self, options: Mapping[str, Any]) -> list[Step]:
        w = float(self.option_values(options)["omega"].to("deg/s").magnitude)
        steps = []
        for a in AXES:
            for r in (0.0, w):
                steps.append(Step(f"rate-{a}-{r:g}", "rate",
                                  f"MIMU {a} accelerometer axis up on the table (7.2.5.1); table "
                                  f"at {r:g} °/s; record ≥ 30 s", Q_(30, "s"),
                                  Q_(0.01, "s"),
                                  {"axis": a, "rate": Q_(r, "deg/s")}))
        return steps

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        opts = self.option_values(ctx.options)
        sign = str(opts["sign"]).strip().lower()
        if sign not in ("model", "as-printed"):
            raise ProcedureError("7.2.5: option sign must be model or as-printed, got "
                                 f"{opts['sign']!r}")
        w_deg = float(opts["omega"].to("deg/s").magnitude)
        if w_deg == 0:
            raise ProcedureError("7.2.5: ω must not be zero (eq. (12) divides by ω²)")
        w = math.radians(w_deg)
        means, u_means = data_means(campaign)
        pairs = rate_pairs(campaign, w_deg)
        p = p_matrix(campaign, means, w_deg, sign)
        warnings: list[str] = []
        if sign == "as-printed":
            warnings.append(msg("p computed with eq. (12) as printed, (U₇ − U₈)/ω²: opposite sign "
                                "to the model of eq. (2)"))
        results = []
        c = 1.0 / w**2
        for m in self.metrics:
            i, j = AXES.index(m.key[2]), AXES.index(m.key[3])
            rest, turning = pairs[AXES[j]]
            u7, u8 = u_means(rest)[1][i], u_means(turning)[1][i]
            rows = [BudgetRow.type_a(
                msg("repeatability of U₇ and U₈, |c|(u(U₇) + u(U₈)) (A.5.2.3)"), "u₃",
                Q_(c * (u7 + u8), P_UNIT), BATCHES - 1)]
            rows += abs_quant_row(campaign, "accel_range", ACC_UNIT, Q_(2 * c, "1/(rad/s)**2"),
                                  warnings)
            n_rate = len(rows)  # the table-rate row's place, if there is one
            rows += table_rate_row(campaign, Q_(2 * abs(p[i, j]), P_UNIT),
                                   msg("c(ω) = −2p/ω (A.12)"), warnings)
            n_rate = n_rate if len(rows) > n_rate else None
            rows.append(mounting.rest_tilt_row(campaign, _accel_scale(campaign, means, pairs, i), w,
                                               P_UNIT))
            b = UncertaintyBudget(m.symbol, P_UNIT, rows, coverage=COVERAGE, round_mode=ROUND,
                                  model=_p_model(float(p[i, j]), rows, n_rate))
            results.append(Result(m, Q_(float(p[i, j]), P_UNIT), b.combined, b,
                                  earth_rate="not applicable",
                                  note=msg("the vertical earth rate adds a relative 2Ω_e·sin φ/ω "
                                           "to ω² (10⁻⁵ at 400 °/s): neglected")))
        table = TableSpec("p", msg("p (rows: accelerometer x, y, z; columns: rate about x, y, z), "
                                   "gn/(rad/s)²"),
                          ["", "x", "y", "z"],
                          [[AXES[i]] + [f"{p[i, j]:.5g}" for j in range(3)] for i in range(3)])
        segs = [s.id for pr in pairs.values() for s in pr]
        return Outcome(STANDARD, self.item, self.title, self.clause, results, tables=[table],
                       warnings=_unique(warnings), segments=segs, options=options_text(opts))


PROCEDURES = (GyroScaleFactor, GyroBiasGSensitivity, GyroCrossCoupling, AccelSixPosition,
              AccelRateSensitivity)

"""JJF 2014—2022 7.2.20–7.2.22: angle random walk (Allan variance), bandwidth, output delay
(7.2.23, start-up time, is in :mod:`.startup`)."""

from __future__ import annotations

import math

import numpy as np
from metro.api import (Q_, BudgetRow, DataError, EquipmentRequirement, Metric, Option, PlotSpec,
                       ProcedureError, Result, Segment, SegmentRequirement, Step, TableSpec, allan,
                       fit_sine, join, msg, parse_quantity, wrap_phase)

from . import budgets as B
from . import formulas as F
from .bias import StaticRecordItem
from .common import (RATE_OPTS, JJFItem, budget_row_a, calibration_of, condition_in, flag_option,
                     need_segments, num_option, output_step, quantity_text, read_output,
                     scale_factor_for)
from .scale_factor import ScaleFactor

# =============================================================================== 7.2.20


def _arw_rounding(campaign, x: np.ndarray, dt: float, K: float, A1: float, arw: float,
                  to_metric: float):
    """ARW when the output is digitised to a step q (interpretations.md, "JJF 2014 — output
    quantization"): rounding each sample adds white rate noise of variance q²/12 when the noise
    dithers it, i.e. q²τ₀/12 to A₋₁ (σ²(τ) = A₋₁/τ), which Sheppard's correction takes off (half the
    correction is kept as a uniform row); when the noise does not dither it, the rounding adds up to
    q²τ₀/4 with an unknown share and ARW is not reportable unless that is below 1 % of A₋₁.
    Returns (ARW, rows, note, reason for not reportable or "")."""
    q, src = output_step(campaign, [x])
    if q <= 0:
        return arw, [], "", ""
    sd = float(np.std(x, ddof=1))
    _hw, dithered = F.rounding_half_width(q, sd)
    qh, tau0 = q / abs(K) * 3600.0, dt / 3600.0  # °/h, h
    if dithered:
        c = qh * qh * tau0 / 12.0
        if not A1 - c > 0:
            return arw, [], "", msg("the rounding of the output (q = {q:.3g} mV) accounts for all "
                                    "of A₋₁: q²τ₀/12 = {c:.3g} ≥ A₋₁ = {A1:.3g} (°/h)²·h; the "
                                    "sensor's ARW is not resolved", q=q, c=c, A1=A1)
        arw_c = math.sqrt(A1 - c) * to_metric
        row = BudgetRow.type_b(msg("output step {q:.3g} mV: Sheppard's correction of A₋₁ (q²τ₀/12)",
                                   q=q), "δARW_q",
                               Q_((arw - arw_c) / 2.0, "deg/hour**0.5"),
                               distribution="uniform",
                               note=msg("noise s = {s:.3g} mV ≥ q/2 ({src}) dithers the rounding: "
                                        "white rate noise of q²/12 per sample; half the correction "
                                        "kept", s=sd, src=src))
        return arw_c, [row], msg("A₋₁ less the rounding's q²τ₀/12 = {c:.3g} (°/h)²·h (Sheppard); "
                                 "as fitted {arw:.4g}",
                                 c=c, arw=arw), ""
    bound = qh * qh * tau0 / 4.0
    if bound >= 0.01 * A1:
        return arw, [], "", msg("the output step q = {q:.3g} mV ({qh:.3g} °/h) is not dithered by "
                                "the noise (s = {s:.3g} mV < q/2): the rounding adds up to q²τ₀/4 "
                                "= {bound:.3g} (°/h)²·h to A₋₁ = {A1:.3g}, an unknown share; ARW "
                                "is not resolved from it (digitise more finely)",
                                q=q, qh=qh, s=sd, bound=bound, A1=A1)
    row = BudgetRow.type_b(msg("output step {q:.3g} mV, not dithered: up to q²τ₀/4 in A₋₁", q=q),
                           "δARW_q",
                           Q_(arw - math.sqrt(A1 - bound) * to_metric, "deg/hour**0.5"),
                           distribution="uniform",
                           note=msg("noise s = {s:.3g} mV < q/2 ({src})", s=sd, src=src))
    return arw, [row], "", ""


def _fit_warnings(fit) -> list[str]:
    """What the eq. (38) fit of 7.2.20 leaves to say: each term that came out negative (removed
    and refitted, or kept in the curve; reported as 0) and a poor fit (χ²/ν > 1.5², the
    uncertainties scaled up)."""
    w = []
    for i, (m, name) in enumerate(F.ALLAN_TERMS):
        if not fit.active[i]:
            how = (msg("the term was removed and the fit repeated")
                   if fit.A[i] == 0 and fit.raw[i] != 0 else msg("kept in the fitted curve"))
            sig_txt = (msg("consistent with 0") if abs(fit.raw[i]) <= 2 * fit.u_A[i] else
                       msg("significantly negative: the model does not describe the data"))
            w.append(msg("A_{m} ({name}) came out negative in the eq. (38) fit ({raw:.3g} ± "
                         "{u:.2g}, {sig}); {how}; reported as 0 (not resolved)", m=m, name=name,
                         raw=fit.raw[i], u=fit.u_A[i], sig=sig_txt, how=how))
    if fit.birge > 1.5:
        w.append(msg("eq. (38) fits poorly (χ²/ν = {chi2:.2g}); the uncertainties were scaled "
                     "up", chi2=fit.birge ** 2))
    return w


def _allan_plot(tau_h: np.ndarray, sig: np.ndarray, edf: np.ndarray, fit) -> PlotSpec:
    """7.2.20's figure: the overlapping Allan deviation σ(τ) of the eq. (34) rate with its
    uncertainty, the eq. (38) fit and each of its positive terms."""
    model = fit.model(tau_h)
    series = [{"label": msg("σ(τ) overlapping Allan deviation"), "x": (tau_h * 3600).tolist(),
               "y": sig.tolist(), "yerr": (sig / np.sqrt(2 * edf)).tolist(), "style": "o"},
              {"label": "eq. (38) fit", "x": (tau_h * 3600).tolist(),
               "y": np.sqrt(np.clip(model, 0, None)).tolist(), "style": "-"}]
    for i, (m, name) in enumerate(F.ALLAN_TERMS):
        if fit.A[i] > 0:
            series.append({"label": msg("{name} term", name=name), "x": (tau_h * 3600).tolist(),
                           "y": np.sqrt(fit.A[i] * tau_h**m).tolist(), "style": "--"})
    return PlotSpec("allan", msg("Allan deviation, eq. (38) fit and its terms"), "τ (s)",
                    "σ(τ) (°/h)", series, logx=True, logy=True)


class AngleRandomWalk(StaticRecordItem):
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
               Metric("RRW", "rate random walk", "K_rrw", "deg/h/hour**0.5", "7.2.20.2",
                      "38: A₁ = K²/3"),
               Metric("RR", "rate ramp", "R", "deg/h**2", "7.2.20.2", "38: A₂ = R²/2"))
    options = RATE_OPTS + (Option("max_fraction", 0.25, None,
                                  "largest cluster length k as a fraction of n"),
                           Option("nonnegative", "off", None,
                                  "on: remove negative eq. (38) terms and refit (biases the "
                                  "others; see interpretations.md)"))

    def evaluate(self, campaign, ctx):
        opts, w, kv, seg = self.static_start(campaign, ctx)
        K = kv.K
        x, dt = read_output(seg)
        rate = x / K * 3600.0  # eq. (34), °/h
        try:
            ad = allan.oadev(rate, dt,
                             allan.octave_m(rate.size, num_option(opts, "max_fraction", 1e-6)))
        except ValueError as exc:
            raise DataError(seg.file or seg.id, "output", f"Allan variance: {exc}") from exc
        tau_h = np.asarray(ad.tau) / 3600.0
        sig = np.asarray(ad.deviation)
        try:
            fit = F.fit_allan_eq38(tau_h, sig, np.asarray(ad.edf), n_samples=int(ad.n_samples),
                                   tau0_h=dt / 3600.0, nonnegative=flag_option(opts, "nonnegative"))
        except ValueError as exc:
            raise ProcedureError(f"7.2.20: {exc}", hint="record longer (7.2.13.1: ≥ 1 h) or check "
                                                        "the data") from exc
        if not fit.A[1] > 0:
            raise ProcedureError("7.2.20: the fitted A₋₁ is negative, so ARW = √A₋₁ (eq. (39)) is "
                                 "undefined",
                                 hint="look at the Allan plot; the record may be dominated by "
                                      "other noise")
        w.extend(_fit_warnings(fit))
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
            rows = [budget_row_a(msg("eq. (38) GLS fit (edf per τ), A_{m}", m=F.ALLAN_TERMS[i][0]),
                                 "u(A)", u_fit,
                                  metric.unit, max(fit.dof, 1),
                                  note=join("; ",
                                            [msg("{n} τ values, χ²/ν = {chi2:.3g}", n=tau_h.size,
                                                       chi2=fit.chi2 / max(fit.dof, 1)), how])),
                    kv.row(val, metric.unit, "scale factor K (eq. (34))")]
            note = "" if fit.active[i] else msg("term not resolved (fitted negative)")
            why = ""
            if key == "ARW":
                val, qrows, qnote, why = _arw_rounding(campaign, x, dt, K, float(fit.A[1]), val,
                                                       to_metric)
                rows += qrows
                note = join("; ", [t for t in (note, qnote) if t]) if qnote else note
            elif fit.raw[i] - 3.0 * fit.u_A[i] <= 0.0:
                # an extra of metro's (7.2.20 reports ARW only): a term not resolved from zero
                # would be a non-negative estimate of what may be 0, biased up (interpretations.md,
                # 7.2.20)
                top = F.not_resolved_bound(fit.raw[i], fit.u_A[i], fac) * to_metric
                why = msg("A_{m} = {A:.3g} ± {u:.2g} is not resolved from 0 (A − 3u ≤ 0): the "
                          "{name} coefficient is below {top:.3g} {unit} (the record does not show "
                          "this term)", m=F.ALLAN_TERMS[i][0],
                          A=fit.raw[i], u=fit.u_A[i], name=F.ALLAN_TERMS[i][1], top=top,
                          unit=metric.unit)
            b = B.type_a_budget(key, metric.unit, rows)
            results.append(Result(metric, Q_(val, metric.unit), b.combined, b, note=note,
                                  reportable=not why, reason=why))
        results.insert(0, results.pop(1))  # ARW first
        plot = _allan_plot(tau_h, sig, np.asarray(ad.edf), fit)
        tab = TableSpec("allan_coef", msg("Eq. (38) coefficients (τ in h, σ in °/h)"),
                        ["m", msg("term"), "A_m", "u(A_m)", msg("kept")],
                        [[m, name, f"{fit.A[i]:.4g}", f"{fit.u_A[i]:.2g}",
                          msg("yes") if fit.active[i] else msg("no (negative: not resolved)")]
                         for i, (m, name) in enumerate(F.ALLAN_TERMS)])
        return self._outcome(results, plots=[plot], tables=[tab], warnings=w, segments=[seg.id],
                             opts=opts)


# =============================================================================== 7.2.21, 7.2.22


class _Dynamic:
    """Sine fits (eq. (40)) of every angular-vibration record, per frequency.  ``K`` is the 7.2.1
    scale factor: a negative K turns the output over, which is a polarity, not half a period of lag
    (the output is read times sign(K); interpretations.md, "7.2.21 / 7.2.22 — a negative K")."""

    def __init__(self, campaign, proc, K: float = 1.0):
        sign = -1.0 if K < 0 else 1.0
        segs = need_segments(campaign, proc, "angular-vibration")
        by_f: dict[float, list[Segment]] = {}
        for s in segs:
            by_f.setdefault(condition_in(s, "frequency", "Hz"), []).append(s)
        if len(by_f) < 3:
            raise DataError(campaign.source, "segments",
                            f"{proc.item} needs at least 3 frequencies (7.2.21.1 b): N ≥ 10)")
        self.f = np.array(sorted(by_f))
        self.E, self.A, self.phi, self.uS = [], [], [], []
        self.n = []
        self.fs = min(1.0 / float(s.interval.to("s").magnitude) for s in segs
                      if s.interval is not None)
        self.ids = [s.id for s in segs]
        for f in self.f:
            Es, As, ph = [], [], []
            for s in by_f[f]:
                y, dt = read_output(s)
                y = sign * y
                ref, _ = read_output(s, "reference", "deg/s")
                if f >= 0.5 / dt:
                    raise DataError(s.file or s.id, "sample_interval",
                                    f"{1 / dt:g} Hz sampling cannot resolve {f:g} Hz")
                t = np.arange(y.size) * dt
                try:
                    gy = fit_sine(t, y, f)
                    gr = fit_sine(t, ref, f)
                except ValueError as exc:
                    raise DataError(s.file or s.id, "output",
                                    f"sine fit at {f:g} Hz: {exc}") from exc
                Es.append(gy.amplitude)
                As.append(gr.amplitude)
                ph.append(float(wrap_phase(gy.phase - gr.phase)))
            ratio = np.array(Es) / np.array(As)
            self.E.append(float(np.mean(Es)))  # eq. (41)
            self.A.append(float(np.mean(As)))
            # eq. (44) on phases relative to the table's signal (P_i of eq. (45) per record)
            self.phi.append(float(np.angle(np.mean(np.exp(1j * np.array(ph))))))
            self.uS.append(float(np.std(ratio, ddof=1) / math.sqrt(ratio.size)) if ratio.size > 1
                           else 0.0)
            self.n.append(len(Es))
        self.S = np.array(self.E) / np.array(self.A)  # eq. (42)
        self.P = np.unwrap(np.array(self.phi))  # eq. (45), continuous in f
        self.uS = np.array(self.uS)


def _nested_better(x: np.ndarray, y: np.ndarray, p: int) -> float:
    """p-value of the F test that a polynomial in ``x`` of ``p`` + 1 terms fits ``y`` better than
    one of ``p`` terms (ordinary least squares, as the curve of 7.2.21 is fitted); 1.0 when there
    are too few points."""
    from scipy.stats import f as f_dist

    nu = x.size - (p + 1)
    if nu < 2:
        return 1.0
    rss = []
    for m in (p, p + 1):
        A = np.column_stack([x ** j for j in range(m)])
        coef, *_ = np.linalg.lstsq(A, y, rcond=None)
        r = y - A @ coef
        rss.append(float(r @ r))
    if not rss[1] > 0:
        return 0.0 if rss[0] > 0 else 1.0
    return float(f_dist.sf((rss[0] - rss[1]) / (rss[1] / nu), 1, nu))


def curve_model(f: np.ndarray, kr: np.ndarray) -> tuple[bool, str, bool]:
    """Which curve 7.2.21.2's fit through the N + 1 ratios uses (interpretations.md, "7.2.21 — a
    response that is not first order"): 1/K² = a + b f² (eq. (46)'s first order) unless the F test
    (1 %) says a + b f² + c f⁴ (a second order) fits better.  Returns (quartic, note, misfit):
    ``misfit`` when even the chosen curve leaves a significant next term (the caller widens the
    type A by the Birge ratio)."""
    x = np.concatenate([[0.0], np.asarray(f, dtype=float) ** 2])
    y = np.concatenate([[1.0], 1.0 / np.asarray(kr, dtype=float) ** 2])
    s = max(float(np.max(x)), 1e-300)
    p2 = _nested_better(x / s, y, 2)
    if p2 >= 0.01:
        return False, "", False
    note = msg("the ratios do not follow the first-order curve 1/K² = a + b f² (F test p = "
               "{p:.2g}): fitted as 1/K² = a + b f² + c f⁴ (a second-order response)", p=p2)
    return True, note, _nested_better(x / s, y, 3) < 0.01


class Bandwidth(JJFItem):
    """JJF 2014—2022 7.2.21 带宽: sine fits eq. (40), Ē_i (41), S_i = Ē_i/A (42), K_i = S_i/S_0
    (43) with S_0 = K from 7.2.1; curve 1/K² = a + b f² through the N + 1 ratios, B_w at K =
    0.707."""

    item = "7.2.21"
    title = "Bandwidth (带宽)"
    clause = "7.2.21"
    metrics = (Metric("Bw", "bandwidth", "B_w", "Hz", "7.2.21.2", "40–43"),)
    requires = ScaleFactor.requires + (SegmentRequirement(
        "angular-vibration", "angular vibration table, N ≥ 10 log-spaced frequencies 10 Hz … "
                             "2·B_w, n ≥ 10 records",
        {"frequency": "Hz", "amplitude": "deg/s", "repeat": ""},
                                                          {"output": ("mV",),
                                                           "reference": ("deg/s",)}),)
    options = RATE_OPTS + (Option("bandwidth_estimate", "80 Hz", "Hz",
                                  "expected B_w (sets the top frequency 2·B_w)"),
                           Option("frequencies", 12, None, "N"),
                           Option("records", 10, None, "n per frequency"),
                           Option("amplitude", "20 deg/s", "deg/s",
                                  "table amplitude (10–30 % of range)"),
                           Option("sample_rate", "5000 Hz", "Hz", "> 20·B_w"))
    equipment = JJFItem.equipment + (EquipmentRequirement("angular_vibration_table",
                                                          "angular vibration table and its "
                                                       "reference sensor (relative U of amplitude; "
                                                       "phase_U)"),)

    def sequence(self, options):
        bw = float(options["bandwidth_estimate"].to("Hz").magnitude)
        fs = float(options["sample_rate"].to("Hz").magnitude)
        A = float(options["amplitude"].to("deg/s").magnitude)
        freqs = np.round(np.geomspace(10.0, 2 * bw,
                                      num_option(options, "frequencies", 3, integer=True)), 1)
        steps = ScaleFactor().sequence(options)
        for f in freqs:
            for j in range(1, num_option(options, "records", 1, integer=True) + 1):
                steps.append(Step(f"angvib-{f:g}Hz#{j}", "angular-vibration",
                                  f"{f:g} Hz, {A:g} °/s, record {j}",
                                  Q_(1, "s"), Q_(1 / fs, "s"),
                                  {"frequency": quantity_text(f, "Hz"),
                                   "amplitude": quantity_text(A, "deg/s"), "repeat": str(j)}))
        return steps

    #: 7.2.21.2 reads the curve at K_i = 0.707 as printed
    LEVEL = 0.707

    @staticmethod
    def _fc(dyn, S0, scale=1.0, level=LEVEL, quartic=False):
        return F.bandwidth_fit_743(dyn.f, dyn.S * scale / S0, level, quartic)

    @classmethod
    def _analyse(cls, campaign, dyn, kv, level=LEVEL):
        """(f at the ``level`` point, its budget, the curve's coefficients, warnings, note)."""
        K = abs(kv.K)  # S₀: the amplitude ratio of eq. (43) is a magnitude
        quartic, note, misfit = curve_model(dyn.f, dyn.S / K)
        try:
            fc, ab, cov = cls._fc(dyn, K, level=level, quartic=quartic)
        except ValueError as exc:
            raise ProcedureError(f"7.2.21: {exc}",
                                 hint="raise the top frequency (option bandwidth_estimate) past "
                                      "the 0.707 point") from exc
        w = [] if dyn.f.size >= 10 else [msg("7.2.21.1 b) asks for N ≥ 10 frequencies; got {n}",
                                             n=dyn.f.size)]
        if min(dyn.n) < 10:
            w.append(msg("7.2.21.1 c) asks for n ≥ 10 records per frequency; the fewest is {n}",
                         n=min(dyn.n)))
        if dyn.fs < 20 * fc:
            w.append(msg("7.2.21.1 c) asks for a sampling rate above 20·B_w = {f:.4g} Hz; got "
                         "{fs:g} Hz", f=20 * fc, fs=dyn.fs))
        if fc > dyn.f.max():
            w.append(msg("B_w = {fc:.4g} Hz lies above the highest frequency {fmax:g} Hz "
                         "(extrapolated)", fc=fc, fmax=dyn.f.max()))
        # sensitivities by numerical differentiation of the whole evaluation
        eps = 1e-4
        # ∂f_c/∂(relative scale of all S_i)
        dfc_ds = (cls._fc(dyn, K, 1 + eps, level, quartic)[0] - fc) / eps
        rows = []
        # type A: scatter of the ratios E/A at each frequency, propagated by perturbing S_i
        uA2 = 0.0
        for i in range(dyn.f.size):
            S = dyn.S.copy()
            h = max(dyn.uS[i], 1e-12 * S[i])
            S[i] += h
            d = (F.bandwidth_fit_743(dyn.f, S / K, level, quartic)[0] - fc) / h
            uA2 += (d * dyn.uS[i]) ** 2
        nmin = min(dyn.n)
        uA, noteA = math.sqrt(uA2), ""
        if misfit and nmin >= 2:
            # the chosen curve leaves a significant next term: its misfit, measured against the
            # ratios' own scatter, widens the type A (Birge ratio; interpretations.md, "7.2.21 — a
            # response that is not first order")
            kk = dyn.S / K
            x = dyn.f ** 2
            yv = 1.0 / kk ** 2
            uy = 2.0 * (dyn.uS / K) / kk ** 3
            model = np.polyval(np.asarray(ab)[::-1], x)
            nu = dyn.f.size + 1 - np.asarray(ab).size
            if nu >= 1 and np.all(uy > 0):
                birge = math.sqrt(float(np.sum(((yv - model) / uy) ** 2)) / nu)
                if birge > 1.0:
                    uA *= birge
                    noteA = msg("the fitted curve leaves a significant misfit (χ²/ν = {c:.3g} "
                                "against the ratios' scatter): scaled by the Birge ratio {b:.3g}",
                                c=birge ** 2, b=birge)
                    note = join("; ", [x for x in (note, noteA) if x])
        rows.append(budget_row_a("sine-fit amplitudes (scatter of Ē_i/A_i over the n records)",
                                 "u_A",
                                  uA, "Hz", max(nmin - 1, 1), note=noteA))
        cal = calibration_of(campaign, "angular_vibration_table")
        rows += B.relative_calibration_row("reference sensor amplitude (scales every S_i)",
                                           "u_rel(A)", cal,
                                           Q_(abs(dfc_ds), "Hz"), w)
        rows.append(kv.row(dfc_ds, "Hz", "S₀ = K from 7.2.1"))
        return fc, B.type_a_budget("Bw", "Hz", rows, note=note), ab, w, note

    def evaluate(self, campaign, ctx):
        opts = self.option_values(ctx.options)
        kv = scale_factor_for(campaign, type(self))
        K = abs(kv.K)
        dyn = _Dynamic(campaign, type(self), kv.K)
        fc, b, ab, w, note = self._analyse(campaign, dyn, kv)
        kr = dyn.S / K
        fine = np.linspace(0, max(dyn.f.max(), fc) * 1.05, 200)
        plot = PlotSpec("amplitude_ratio", msg("Amplitude ratio K_i = S_i/S₀ (eq. (43)), fit and "
                                               "the 0.707 point"),
                        "f (Hz)", "K_i",
                        [{"label": "K_i", "x": [0.0] + dyn.f.tolist(), "y": [1.0] + kr.tolist(),
                          "style": "o"},
                         {"label": msg("fit 1/K² = a + b f² + c f⁴") if ab.size > 2
                          else msg("fit 1/K² = a + b f²"),
                          "x": fine.tolist(),
                          "y": (1 / np.sqrt(np.clip(np.polyval(ab[::-1], fine**2), 1e-12,
                                                    None))).tolist(),
                          "style": "-"},
                         {"label": msg("0.707 → B_w = {fc:.4g} Hz", fc=fc), "x": [0.0, fc, fc],
                          "y": [0.707, 0.707, 0.0],
                          "style": "--"}])
        tab = TableSpec("dynamic", msg("Per frequency"),
                        ["f_i (Hz)", "Ē_i (mV)", "A (°/s)", "S_i (mV/((°)/s))", "K_i",
                                                     "P_i (rad)"],
                        [[f"{f:g}", f"{e:.5g}", f"{a:.5g}", f"{s:.6g}", f"{k:.5f}", f"{p:.5f}"]
                         for f, e, a, s, k, p in zip(dyn.f, dyn.E, dyn.A, dyn.S, kr, dyn.P)])
        return self._outcome([Result(self.metrics[0], Q_(fc, "Hz"), b.combined, b, note=note)],
                             plots=[plot], tables=[tab],
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
        kv = scale_factor_for(campaign, type(self))
        dyn = _Dynamic(campaign, type(self), kv.K)
        # eq. (47) T = 1/(2πB_w) is the first-order model's corner, where |G| = K_D/√2: read there,
        # not at the literal 0.707 of 7.2.21 (which puts B_w 0.04 % high and biases T_d by +1.65 U
        # on average; interpretations.md, "7.2.22 — B_w of eq. (47)")
        fc, bbw, _, _, bw_note = self._analyse(campaign, dyn, kv, level=1 / math.sqrt(2))
        w_ = 2 * math.pi * dyn.f
        T = 1.0 / (2 * math.pi * fc)  # eq. (47)
        Td, u_fit, resid = F.delay_eq48_50(w_, dyn.P, T)
        # u(B_w) from the 7.2.21 evaluation
        u_bw = float(bbw.combined.to("Hz").magnitude)
        d = 1e-3 * fc
        Td2 = F.delay_eq48_50(w_, dyn.P, 1.0 / (2 * math.pi * (fc + d)))[0]
        rows = [budget_row_a("least squares of eq. (50) (phase residuals)", "u(T_d)", u_fit, "s",
                             dyn.f.size - 1),
                BudgetRow.type_b("bandwidth B_w via T = 1/(2πB_w) (eq. (47))", "u(B_w)",
                                 Q_(u_bw, "Hz"),
                                 distribution="normal", k=1.0,
                                 sensitivity=Q_(abs((Td2 - Td) / d), "s/Hz"))]
        eq = campaign.equipment_for("angular_vibration_table")
        if eq is not None and "phase_U" in eq.properties:
            pu = parse_quantity(eq.properties["phase_U"], dimension="deg").to("rad").magnitude
            rows.append(BudgetRow.type_b("reference sensor phase", "u(φ₀)", Q_(pu, ""),
                                         distribution="normal", k=2.0,
                                         sensitivity=Q_(1.0 / math.sqrt(float(w_ @ w_) / w_.size),
                                                        "s"),
                                         note=msg("a common phase error φ acts as φ/ω on T_d (RMS "
                                                  "ω)")))
        b = B.type_a_budget("Td", "s", rows)
        fine = np.linspace(dyn.f.min(), dyn.f.max(), 100)
        wf = 2 * np.pi * fine
        plot = PlotSpec("phase", msg("Phase delay P_i (eq. (45)) and the model −atan(ωT) − ωT_d "
                                     "(eq. (46))"), "f (Hz)",
                        "P (rad)",
                        [{"label": "P_i", "x": dyn.f.tolist(), "y": dyn.P.tolist(), "style": "o"},
                         {"label": msg("model, T_d = {td:.4g} ms, B_w = {bw:.4g} Hz", td=Td * 1e3,
                                       bw=fc), "x": fine.tolist(),
                          "y": (-np.arctan(wf * T) - wf * Td).tolist(), "style": "-"},
                         {"label": msg("pure delay −ωT_d"), "x": fine.tolist(),
                          "y": (-wf * Td).tolist(), "style": ":"},
                         {"label": f"B_w = {fc:.4g} Hz", "x": [fc, fc],
                          "y": [float(np.min(dyn.P)), 0.0], "style": "--"}])
        return self._outcome([Result(self.metrics[0], Q_(Td, "s"), b.combined, b,
                                     note=join("; ",
                                               [x for x in (f"T = {T * 1e3:.4g} ms", bw_note)
                                                if x]))],
                             plots=[plot], segments=dyn.ids, opts=opts)

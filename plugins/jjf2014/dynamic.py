"""JJF 2014—2022 7.2.20–7.2.23: angle random walk (Allan variance), bandwidth, output delay, start-up time."""

from __future__ import annotations

import math

import numpy as np
from metro.api import (
    Q_,
    BudgetRow,
    DataError,
    EquipmentRequirement,
    Metric,
    Option,
    PlotSpec,
    ProcedureError,
    Result,
    Segment,
    SegmentRequirement,
    Step,
    TableSpec,
    allan,
    fit_sine,
    join,
    msg,
    parse_quantity,
    wrap_phase,
)
from metro.api import settling as S

from . import budgets as B
from . import formulas as F
from .bias import Bias, _static
from .common import (
    _JJF,
    RATE_OPTS,
    _budget_row_a,
    _cal,
    _cond_q,
    _flag,
    _need,
    _num,
    _output,
    _q,
    output_step,
    scale_factor_for,
)
from .scale_factor import ScaleFactor

# =============================================================================== 7.2.20


def _arw_rounding(campaign, x: np.ndarray, dt: float, K: float, A1: float, arw: float, to_metric: float):
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
            return arw, [], "", msg("the rounding of the output (q = {q:.3g} mV) accounts for all of A₋₁: q²τ₀/12 = "
                                    "{c:.3g} ≥ A₋₁ = {A1:.3g} (°/h)²·h; the sensor's ARW is not resolved", q=q, c=c, A1=A1)
        arw_c = math.sqrt(A1 - c) * to_metric
        row = BudgetRow.type_b(msg("output step {q:.3g} mV: Sheppard's correction of A₋₁ (q²τ₀/12)", q=q), "δARW_q",
                               Q_((arw - arw_c) / 2.0, "deg/hour**0.5"),
                               distribution="uniform",
                               note=msg("noise s = {s:.3g} mV ≥ q/2 ({src}) dithers the rounding: white rate noise of "
                                        "q²/12 per sample; half the correction kept", s=sd, src=src))
        return arw_c, [row], msg("A₋₁ less the rounding's q²τ₀/12 = {c:.3g} (°/h)²·h (Sheppard); as fitted {arw:.4g}",
                                 c=c, arw=arw), ""
    bound = qh * qh * tau0 / 4.0
    if bound >= 0.01 * A1:
        return arw, [], "", msg("the output step q = {q:.3g} mV ({qh:.3g} °/h) is not dithered by the noise "
                                "(s = {s:.3g} mV < q/2): the rounding adds up to q²τ₀/4 = {bound:.3g} (°/h)²·h to "
                                "A₋₁ = {A1:.3g}, an unknown share; ARW is not resolved from it (digitise more finely)",
                                q=q, qh=qh, s=sd, bound=bound, A1=A1)
    row = BudgetRow.type_b(msg("output step {q:.3g} mV, not dithered: up to q²τ₀/4 in A₋₁", q=q), "δARW_q",
                           Q_(arw - math.sqrt(A1 - bound) * to_metric, "deg/hour**0.5"), distribution="uniform",
                           note=msg("noise s = {s:.3g} mV < q/2 ({src})", s=sd, src=src))
    return arw, [row], "", ""


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
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
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
            fit = F.fit_allan_eq38(tau_h, sig, np.asarray(ad.edf), n_samples=int(ad.n_samples),
                                   tau0_h=dt / 3600.0, nonnegative=_flag(opts, "nonnegative"))
        except ValueError as exc:
            raise ProcedureError(f"7.2.20: {exc}", hint="record longer (7.2.13.1: ≥ 1 h) or check the data") from exc
        if not fit.A[1] > 0:
            raise ProcedureError("7.2.20: the fitted A₋₁ is negative, so ARW = √A₋₁ (eq. (39)) is undefined",
                                 hint="look at the Allan plot; the record may be dominated by other noise")
        for i, (m, name) in enumerate(F.ALLAN_TERMS):
            if not fit.active[i]:
                how = (msg("the term was removed and the fit repeated") if fit.A[i] == 0 and fit.raw[i] != 0
                       else msg("kept in the fitted curve"))
                sig_txt = (msg("consistent with 0") if abs(fit.raw[i]) <= 2 * fit.u_A[i] else
                           msg("significantly negative: the model does not describe the data"))
                w.append(msg("A_{m} ({name}) came out negative in the eq. (38) fit ({raw:.3g} ± {u:.2g}, {sig}); {how}; "
                             "reported as 0 (not resolved)", m=m, name=name, raw=fit.raw[i], u=fit.u_A[i], sig=sig_txt,
                             how=how))
        if fit.birge > 1.5:
            w.append(msg("eq. (38) fits poorly (χ²/ν = {chi2:.2g}); the uncertainties were scaled up", chi2=fit.birge ** 2))
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
            rows = [_budget_row_a(msg("eq. (38) GLS fit (edf per τ), A_{m}", m=F.ALLAN_TERMS[i][0]), "u(A)", u_fit,
                                  metric.unit, max(fit.dof, 1),
                                  note=join("; ", [msg("{n} τ values, χ²/ν = {chi2:.3g}", n=tau_h.size,
                                                       chi2=fit.chi2 / max(fit.dof, 1)), how])),
                    kv.row(val, metric.unit, "scale factor K (eq. (34))")]
            note = "" if fit.active[i] else msg("term not resolved (fitted negative)")
            why = ""
            if key == "ARW":
                val, qrows, qnote, why = _arw_rounding(campaign, x, dt, K, float(fit.A[1]), val, to_metric)
                rows += qrows
                note = join("; ", [t for t in (note, qnote) if t]) if qnote else note
            elif fit.raw[i] - 3.0 * fit.u_A[i] <= 0.0:
                # an extra of metro's (7.2.20 reports ARW only): a term not resolved from zero would be a
                # non-negative estimate of what may be 0, biased up (interpretations.md, 7.2.20)
                top = F.not_resolved_bound(fit.raw[i], fit.u_A[i], fac) * to_metric
                why = msg("A_{m} = {A:.3g} ± {u:.2g} is not resolved from 0 (A − 3u ≤ 0): the {name} coefficient is "
                          "below {top:.3g} {unit} (the record does not show this term)", m=F.ALLAN_TERMS[i][0],
                          A=fit.raw[i], u=fit.u_A[i], name=F.ALLAN_TERMS[i][1], top=top, unit=metric.unit)
            b = B.type_a_budget(key, metric.unit, rows)
            results.append(Result(metric, Q_(val, metric.unit), b.combined, b, note=note,
                                  reportable=not why, reason=why))
        results.insert(0, results.pop(1))  # ARW first
        model = fit.model(tau_h)
        series = [{"label": msg("σ(τ) overlapping Allan deviation"), "x": (tau_h * 3600).tolist(), "y": sig.tolist(),
                   "yerr": (sig / np.sqrt(2 * np.asarray(ad.edf))).tolist(), "style": "o"},
                  {"label": "eq. (38) fit", "x": (tau_h * 3600).tolist(), "y": np.sqrt(np.clip(model, 0, None)).tolist(),
                   "style": "-"}]
        for i, (m, name) in enumerate(F.ALLAN_TERMS):
            if fit.A[i] > 0:
                series.append({"label": msg("{name} term", name=name), "x": (tau_h * 3600).tolist(),
                               "y": np.sqrt(fit.A[i] * tau_h**m).tolist(), "style": "--"})
        plot = PlotSpec("allan", msg("Allan deviation, eq. (38) fit and its terms"), "τ (s)", "σ(τ) (°/h)", series,
                        logx=True, logy=True)
        tab = TableSpec("allan_coef", msg("Eq. (38) coefficients (τ in h, σ in °/h)"), ["m", msg("term"), "A_m", "u(A_m)", msg("kept")],
                        [[m, name, f"{fit.A[i]:.4g}", f"{fit.u_A[i]:.2g}", msg("yes") if fit.active[i] else msg("no (negative: not resolved)")]
                         for i, (m, name) in enumerate(F.ALLAN_TERMS)])
        return self._outcome(results, plots=[plot], tables=[tab], warnings=w, segments=[seg.id], opts=opts)


# =============================================================================== 7.2.21, 7.2.22


class _Dynamic:
    """Sine fits (eq. (40)) of every angular-vibration record, per frequency.  ``K`` is the 7.2.1
    scale factor: a negative K turns the output over, which is a polarity, not half a period of lag
    (the output is read times sign(K); interpretations.md, "7.2.21 / 7.2.22 — a negative K")."""

    def __init__(self, campaign, proc, K: float = 1.0):
        sign = -1.0 if K < 0 else 1.0
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
                y = sign * y
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


def _nested_better(x: np.ndarray, y: np.ndarray, p: int) -> float:
    """p-value of the F test that a polynomial in ``x`` of ``p`` + 1 terms fits ``y`` better than one of ``p``
    terms (ordinary least squares, as the curve of 7.2.21 is fitted); 1.0 when there are too few points."""
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
    """Which curve 7.2.21.2's fit through the N + 1 ratios uses (interpretations.md, "7.2.21 — a response
    that is not first order"): 1/K² = a + b f² (eq. (46)'s first order) unless the F test (1 %) says a
    + b f² + c f⁴ (a second order) fits better.  Returns (quartic, note, misfit): ``misfit`` when even
    the chosen curve leaves a significant next term (the caller widens the type A by the Birge ratio)."""
    x = np.concatenate([[0.0], np.asarray(f, dtype=float) ** 2])
    y = np.concatenate([[1.0], 1.0 / np.asarray(kr, dtype=float) ** 2])
    s = max(float(np.max(x)), 1e-300)
    p2 = _nested_better(x / s, y, 2)
    if p2 >= 0.01:
        return False, "", False
    note = msg("the ratios do not follow the first-order curve 1/K² = a + b f² (F test p = {p:.2g}): fitted as "
               "1/K² = a + b f² + c f⁴ (a second-order response)", p=p2)
    return True, note, _nested_better(x / s, y, 3) < 0.01


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
    equipment = _JJF.equipment + (EquipmentRequirement("angular_vibration_table", "angular vibration table and its "
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
                                 hint="raise the top frequency (option bandwidth_estimate) past the 0.707 point") from exc
        w = [] if dyn.f.size >= 10 else [msg("7.2.21.1 b) asks for N ≥ 10 frequencies; got {n}", n=dyn.f.size)]
        if min(dyn.n) < 10:
            w.append(msg("7.2.21.1 c) asks for n ≥ 10 records per frequency; the fewest is {n}", n=min(dyn.n)))
        if dyn.fs < 20 * fc:
            w.append(msg("7.2.21.1 c) asks for a sampling rate above 20·B_w = {f:.4g} Hz; got {fs:g} Hz", f=20 * fc, fs=dyn.fs))
        if fc > dyn.f.max():
            w.append(msg("B_w = {fc:.4g} Hz lies above the highest frequency {fmax:g} Hz (extrapolated)", fc=fc, fmax=dyn.f.max()))
        # sensitivities by numerical differentiation of the whole evaluation
        eps = 1e-4
        dfc_ds = (cls._fc(dyn, K, 1 + eps, level, quartic)[0] - fc) / eps  # ∂f_c/∂(relative scale of all S_i)
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
            # the chosen curve leaves a significant next term: its misfit, measured against the ratios' own
            # scatter, widens the type A (Birge ratio; interpretations.md, "7.2.21 — a response that is not
            # first order")
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
                    noteA = msg("the fitted curve leaves a significant misfit (χ²/ν = {c:.3g} against the ratios' "
                                "scatter): scaled by the Birge ratio {b:.3g}", c=birge ** 2, b=birge)
                    note = join("; ", [x for x in (note, noteA) if x])
        rows.append(_budget_row_a("sine-fit amplitudes (scatter of Ē_i/A_i over the n records)", "u_A",
                                  uA, "Hz", max(nmin - 1, 1), note=noteA))
        cal = _cal(campaign, "angular_vibration_table")
        rows += B.relative_calibration_row("reference sensor amplitude (scales every S_i)", "u_rel(A)", cal,
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
        plot = PlotSpec("amplitude_ratio", msg("Amplitude ratio K_i = S_i/S₀ (eq. (43)), fit and the 0.707 point"),
                        "f (Hz)", "K_i",
                        [{"label": "K_i", "x": [0.0] + dyn.f.tolist(), "y": [1.0] + kr.tolist(), "style": "o"},
                         {"label": msg("fit 1/K² = a + b f² + c f⁴") if ab.size > 2 else msg("fit 1/K² = a + b f²"),
                          "x": fine.tolist(),
                          "y": (1 / np.sqrt(np.clip(np.polyval(ab[::-1], fine**2), 1e-12, None))).tolist(),
                          "style": "-"},
                         {"label": msg("0.707 → B_w = {fc:.4g} Hz", fc=fc), "x": [0.0, fc, fc], "y": [0.707, 0.707, 0.0],
                          "style": "--"}])
        tab = TableSpec("dynamic", msg("Per frequency"), ["f_i (Hz)", "Ē_i (mV)", "A (°/s)", "S_i (mV/((°)/s))", "K_i",
                                                     "P_i (rad)"],
                        [[f"{f:g}", f"{e:.5g}", f"{a:.5g}", f"{s:.6g}", f"{k:.5f}", f"{p:.5f}"]
                         for f, e, a, s, k, p in zip(dyn.f, dyn.E, dyn.A, dyn.S, kr, dyn.P)])
        return self._outcome([Result(self.metrics[0], Q_(fc, "Hz"), b.combined, b, note=note)], plots=[plot], tables=[tab],
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
        rows = [_budget_row_a("least squares of eq. (50) (phase residuals)", "u(T_d)", u_fit, "s", dyn.f.size - 1),
                BudgetRow.type_b("bandwidth B_w via T = 1/(2πB_w) (eq. (47))", "u(B_w)", Q_(u_bw, "Hz"),
                                 distribution="normal", k=1.0, sensitivity=Q_(abs((Td2 - Td) / d), "s/Hz"))]
        eq = campaign.equipment_for("angular_vibration_table")
        if eq is not None and "phase_U" in eq.properties:
            pu = parse_quantity(eq.properties["phase_U"], dimension="deg").to("rad").magnitude
            rows.append(BudgetRow.type_b("reference sensor phase", "u(φ₀)", Q_(pu, ""), distribution="normal", k=2.0,
                                         sensitivity=Q_(1.0 / math.sqrt(float(w_ @ w_) / w_.size), "s"),
                                         note=msg("a common phase error φ acts as φ/ω on T_d (RMS ω)")))
        b = B.type_a_budget("Td", "s", rows)
        fine = np.linspace(dyn.f.min(), dyn.f.max(), 100)
        wf = 2 * np.pi * fine
        plot = PlotSpec("phase", msg("Phase delay P_i (eq. (45)) and the model −atan(ωT) − ωT_d (eq. (46))"), "f (Hz)",
                        "P (rad)",
                        [{"label": "P_i", "x": dyn.f.tolist(), "y": dyn.P.tolist(), "style": "o"},
                         {"label": msg("model, T_d = {td:.4g} ms, B_w = {bw:.4g} Hz", td=Td * 1e3, bw=fc), "x": fine.tolist(),
                          "y": (-np.arctan(wf * T) - wf * Td).tolist(), "style": "-"},
                         {"label": msg("pure delay −ωT_d"), "x": fine.tolist(), "y": (-wf * Td).tolist(), "style": ":"},
                         {"label": f"B_w = {fc:.4g} Hz", "x": [fc, fc],
                          "y": [float(np.min(dyn.P)), 0.0], "style": "--"}])
        return self._outcome([Result(self.metrics[0], Q_(Td, "s"), b.combined, b,
                                     note=join("; ", [x for x in (f"T = {T * 1e3:.4g} ms", bw_note) if x]))],
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
    equipment = _JJF.equipment + (EquipmentRequirement("timer", "timer / time base", calibration=("",)),)

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
        kv = scale_factor_for(campaign, type(self))
        K = kv.K
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

        def smooth(s):
            x, dt = _output(s)
            k = max(1, int(round(win / dt)))
            if x.size < 4 * k:
                raise DataError(s.file or s.id, "output", f"record too short for a {win:g} s window")
            c = np.convolve(x, np.ones(k) / k, mode="valid")
            t = (np.arange(c.size) + (k + 1) / 2.0) * dt  # centre of each window, from power-on
            d = np.diff(x)
            # the noise of one window mean, °/s, from the sample-to-sample differences (robust: the median
            # absolute deviation, which the transient's few large steps do not move)
            s1 = float(1.4826 * np.median(np.abs(d - np.median(d))) / math.sqrt(2))
            # a rounded output's differences are mostly 0 or ±q, and their MAD can collapse to 0: the differences'
            # standard deviation over the settled last quarter (rounding included) is then the larger
            s_q = float(np.std(d[-max(d.size // 4, 2):], ddof=1)) / math.sqrt(2)
            s1 = max(s1, s_q)
            sd = s1 / math.sqrt(k) / abs(K)
            # one sample's noise where the samples decide (a ringing output): the MAD of the record's second half —
            # over the whole record an output ringing at 0.2–2 Hz for a third of it puts its own steps into the
            # median (up to 4× the noise, and a last swing beyond the band within that was not seen)
            dh = d[d.size // 2:]
            one_sample[s.id] = max(float(1.4826 * np.median(np.abs(dh - np.median(dh))) / math.sqrt(2)), s_q) / abs(K)
            # an output digitised to a step q: a window mean is off by up to the rounding's half-width (±q/2
            # where the noise does not dither it — the differences' MAD then sees little or none of it), one
            # sample by up to q/2: both are added to the margins below
            q, _src = output_step(campaign, [x])
            hw, _dith = F.rounding_half_width(q, s1)
            rounding[s.id] = (hw / abs(K), q / 2.0 / abs(K))
            return t, c / K, dt, sd, k, x / K

        rounding: dict[str, tuple[float, float]] = {}  # per segment: rounding bound of a window mean, of a sample (°/s)
        one_sample: dict[str, float] = {}  # per segment: one sample's noise (°/s)
        trials = []  # (segment, t, r, target, tol, dt, sd, u(target), samples, sd of one sample)
        zero, uzero = [], []
        for s in pos:
            t, r, dt, sd, k, raw = smooth(s)
            last = r[int(0.75 * r.size):]
            settled = float(np.mean(last))
            u_set = sd * math.sqrt(k / max(last.size, 1))  # the last quarter's mean: ≈ last.size/k window means
            # a slow tail still moving in the last quarter: the settled value is uncertain by the drift seen
            # there (half of it over the quarter) where the samples' slope is resolved from their noise
            rl = raw[int(0.75 * raw.size):]
            tl = dt * np.arange(rl.size)
            if rl.size >= 3:
                sxx = float(np.sum((tl - tl.mean()) ** 2))
                slope = float(np.sum((tl - tl.mean()) * (rl - rl.mean())) / sxx)
                if abs(slope) > 2.0 * sd * math.sqrt(k) / math.sqrt(sxx):
                    u_set = math.hypot(u_set, abs(slope) * (tl[-1] - tl[0]) / 2.0)
            zero.append(settled)
            uzero.append(u_set)
            trials.append((s, t, r, settled, btol, dt, sd, u_set, raw, one_sample[s.id]))
        z = float(np.mean(zero))
        uz = math.sqrt(sum(u * u for u in uzero)) / len(uzero)
        for s in rat:
            om = _cond_q(s, "rate", "deg/s")
            t, r, dt, sd, k, raw = smooth(s)
            trials.append((s, t, r - z, om, rtol * abs(om), dt, sd, uz, raw - z, one_sample[s.id]))
        # 7.2.23.2's time per trial, decided where the noise lets it be (interpretations.md, "7.2.23 — a
        # settling decided by noise"): a window mean counts as outside the band only when it is outside by
        # more than 2u (u: its noise and the target's), as inside only when inside by more than 2u; the
        # start-up time lies between the first sample after the last clearly-outside one and the first
        # after the last not-clearly-inside one.  An output that rings faster than the window is averaged
        # flat by it: where single samples after that are outside the band by more than 4.5u of one
        # sample's noise (a false alarm in ≈ 2 % of 60 s records at 10 Hz), the window cannot decide, and
        # the samples do — outside and not-clearly-inside at that 4.5u
        # The tail's test is made over every window mean after the last clearly-outside one: "not clearly
        # inside" at 2u each would be a false alarm somewhere in ≈ 50 independent windows almost surely, and
        # the interval's end was then the last noise excursion (mean E_n +0.70 on the harness's noisy
        # devices).  So inside is decided at z_N·u, z_N the two-sided 95 % family-wise quantile over the
        # N = (tail length)/window independent window means (z ≈ 3.3 for 50 s); and the point in the interval
        # is the crossing of a first-order (exponential) approach to the settled value through the band's edge
        # — the interval is not symmetric about it (interpretations.md, "7.2.23 — where in the interval")
        from scipy.stats import norm

        why: list[str] = []
        table = []
        lo_hi = []
        for s, t, r, target, tol, dt, sd, ut, raw, sd1 in trials:
            qw, q1 = rounding[s.id]
            m = 2.0 * math.hypot(sd, ut) + qw
            dev = np.abs(r - target)
            try:
                plain = F.settle_time(t, r, target, tol)
            except ValueError:
                plain = math.nan
            out = np.flatnonzero(dev > tol + m)
            lo = float(t[min(out[-1] + 1, t.size - 1)]) if out.size else float(t[0])
            n_tail = max(1.0, (float(t[-1]) - lo) / win)
            z_in = max(2.0, float(norm.isf(0.025 / n_tail)))
            m_in = z_in * math.hypot(sd, ut) + qw
            if not tol - m > 0:
                why.append(msg("{id}: the output's noise and its target's uncertainty (2u = {m:.3g} °/s over the {w:g} s "
                               "window) are as large as the tolerance ±{tol:.3g} °/s, so whether it is inside cannot "
                               "be decided",
                               id=s.id, m=m, w=win, tol=tol))
                table.append((s, target, tol, plain, math.nan, math.nan))
                continue
            # the settled output (the last quarter's mean; for a position trial its own target) must be inside the
            # band by more than the window means' z_N·u, or the tail's windows cannot tell it from the band's edge
            settled = float(np.mean(r[int(0.75 * r.size):])) - target
            if not tol - abs(settled) - m_in > 0:
                why.append(msg("{id}: the output's noise and its target's uncertainty ({z:.2g}u = {m:.3g} °/s over the "
                               "{w:g} s window, {z:.2g} for the {n:.0f} window means after it left the band) are as "
                               "large as the settled output's margin to the band's edge ({g:.3g} °/s of ±{tol:.3g} °/s), "
                               "so when it stays inside cannot be decided",
                               id=s.id, z=z_in, m=m_in, w=win, n=n_tail, g=tol - abs(settled), tol=tol))
                table.append((s, target, tol, plain, math.nan, math.nan))
                continue
            # the end of the record is one test (2u, 95 %); the scan of the tail a family of n_tail (z_N·u)
            if dev[-1] >= tol - m:
                why.append(msg("{id}: the output is not inside ±{tol:.3g} °/s of {target:.4g} °/s (less 2u = {m:.3g} "
                               "°/s of noise) at the end of the record ({end:.3g} s): it has not settled, or not "
                               "resolvably", id=s.id, tol=tol, target=target, m=m, end=float(t[-1])))
                table.append((s, target, tol, plain, math.nan, math.nan))
                continue
            notin = np.flatnonzero(dev >= tol - m_in)
            hi = float(t[min(notin[-1] + 1, t.size - 1)]) if notin.size else float(t[0])
            est = (lo + hi) / 2.0
            # the settled value's distance g to the edge the output approached: an exponential approach
            # e^(−t/τ) to the settled value is g + m from it at lo and crosses the edge τ·ln((g + m)/g) later;
            # τ from the last e-fold before lo, where the output is clearly resolved (e·(g + m) to g + m)
            if hi > lo and out.size:
                side = 1.0 if r[out[-1]] > target else -1.0
                g = tol - side * settled
                above = np.flatnonzero(side * (r - target - settled) > math.e * (g + m)) if g > 0 else out[:0]
                if above.size and lo > float(t[above[-1] + 1]):
                    tau = lo - float(t[above[-1] + 1])
                    est = min(max(lo + tau * math.log((g + m) / g), lo), hi)
            # an output ringing faster than the window: the window means average its swings away, the samples
            # show them (interpretations.md, "7.2.23 — a ringing output decided by its samples").  Their lobes
            # about the settled value (metro.core.stats.settling, as GB/T 6.2.7.7's): each has the probability that
            # the noise-free output left the band in it, and the start-up is the expected last real exit
            m1 = 4.5 * math.hypot(sd1, ut) + q1
            ts = dt * np.arange(1, raw.size + 1)  # sample j at (j + 1)·dt from power-on
            rdev = np.abs(raw - target)
            # the band about the settled value (its edges differ where a rate trial settles off Ω); a rounding
            # that the noise does not dither is common to a lobe's samples (uniform ±q/2)
            s_common = math.hypot(ut, q1 / math.sqrt(3.0) if sd1 < q1 else 0.0)
            s_p = math.hypot(sd1, s_common)
            lobes = S.excursion_lobes(raw - target - settled, ts, dt, 1, tol - settled, tol + settled, sd1, s_common,
                                      half_lobe_fit=True)
            i_lo = int(np.searchsorted(ts, lo))
            z_ring = float(norm.isf(0.025 / max(raw.size - i_lo, 1)))
            # ringing: a sample clearly outside after the window means settle, or — where one sample's noise lets the
            # samples decide at all — a swing past the settled value to the other side than the one the output
            # approached from, beyond the tail's family-wise noise
            side = next((lb.sign for lb in lobes if lb.start <= i_lo < lb.end), 0)
            ringing = (np.any((rdev > tol + m1) & (ts >= lo))
                       or (tol - m1 > 0 and any(lb.start >= i_lo and lb.sign != side and lb.top > z_ring * s_p
                                                for lb in lobes)))
            decided = None
            if ringing:
                st = F.startup_sample_exits(raw - target - settled, ts, dt, tol - settled, tol + settled, s_p, lobes,
                                            S.last_exit(lobes, float(ts[0])))
                late = [e for e, pr in zip(st["lobe_exits"], st["lobe_probabilities"])
                        if pr > 0.01 and e > ts[int(0.75 * ts.size)]]
                if not tol - m1 > 0 or late:
                    why.append(msg("{id}: the output rings faster than the {w:g} s window (samples outside ±{tol:.3g} °/s "
                                   "after the window means settle) and one sample's noise (4.5u = {m:.3g} °/s) does not "
                                   "let the samples decide", id=s.id, w=win, tol=tol, m=m1))
                    table.append((s, target, tol, plain, math.nan, math.nan))
                    continue
                est = st["t"]
                lo, hi = est - st["d95"], est + st["d95"]
                decided = st
            lo_hi.append((lo, hi, s, dt, est, decided))
            table.append((s, target, tol, plain, lo, hi))
        tab = TableSpec("startup", msg("Start-up time per trial"),
                        [msg("trial"), msg("segment"), msg("target"), msg("tolerance"), "t (s)", msg("decided within (s)")],
                        [[str(x[0].condition("trial")), x[0].id, f"{x[1]:.4g} °/s", f"{x[2]:.3g} °/s", f"{x[3]:.2f}",
                          f"{x[4]:.2f} … {x[5]:.2f}"] for x in table])
        if why:
            plains = [x[3] for x in table if math.isfinite(x[3])]
            ts = max(plains) if plains else float(max(x[1][-1] for x in trials))
            rows = [BudgetRow.type_b("sampling: the crossing lies within one interval", "Δt/2",
                                     Q_(max(x[5] for x in trials) / 2, "s"), distribution="uniform")]
            b = B.type_a_budget("t_startup", "s", rows)
            return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, reportable=False,
                                         reason=join("; ", why))],
                                 tables=[tab], segments=[x.id for x in segs], opts=opts)
        # the start-up time is the largest trial's: between the largest lo and the largest hi, at the largest
        # trial's crossing
        best = max(lo_hi, key=lambda x: x[4])
        if best[5] is not None:
            return self._ringing_outcome(campaign, best, [x for x in lo_hi if x is not best], tab, segs, opts)
        lo = max(x[0] for x in lo_hi)
        hi = max(x[1] for x in lo_hi)
        s, dt, est = best[2:5]
        ts = min(max(est, lo), hi)
        rows = [BudgetRow.type_b("sampling: the crossing lies within one interval", "Δt/2", Q_(dt / 2, "s"),
                                 distribution="uniform")]
        if hi > lo:
            rows.append(BudgetRow.type_b(msg("the settling decided from the output's noise (outside at 2u, inside at "
                                             "the window means' family-wise 95 %): between {lo:.3g} s and {hi:.3g} s",
                                             lo=lo, hi=hi), "Δt_{noise}/2", Q_((hi - lo) / 2, "s"),
                                         distribution="uniform"))
            off = abs(ts - (lo + hi) / 2.0)
            if off > 1e-3 * (hi - lo):
                # the uniform row is about the interval's middle; the result is the crossing, off the middle: the
                # second moment about the result is the uniform's variance plus the offset squared
                rows.append(BudgetRow.type_b(msg("the crossing of an exponential approach, {off:.3g} s from the "
                                                 "interval's middle", off=off), "δt_mid", Q_(off, "s"),
                                             distribution="normal", k=1.0))
        rows += B.relative_calibration_row("timer", "u_rel(t)", _cal(campaign, "timer"), Q_(ts, "s"))
        b = B.type_a_budget("t_startup", "s", rows)
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, note=msg("largest in {id}", id=s.id))],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)

    def _ringing_outcome(self, campaign, best, others, tab, segs, opts):
        """The start-up time where the largest trial's samples decided it (an output ringing faster than the
        window): the expected last real exit with the spread of the candidates' exits (normal), their noise
        re-crossings (uniform) and, where another trial's interval reaches later, the rest of that interval."""
        _lo, _hi, s, dt, ts, st = best
        rows = [BudgetRow.type_b("sampling: the crossing lies within one interval", "Δt/2", Q_(dt / 2, "s"),
                                 distribution="uniform")]
        u_sel = max(st["u_selection"], st["d95"] / 2.0)  # U reaches the candidates holding 95 % of the probability
        if u_sel > 0:
            rows.append(BudgetRow.type_b(
                msg("which excursion beyond the band is the last real one (spread of the candidates' exits)"),
                "u_sel", Q_(u_sel, "s"), distribution="normal", k=1.0,
                note=msg("exits {exits} s with probabilities {probs}",
                         exits=", ".join(f"{e:.4g}" for e in st["lobe_exits"]),
                         probs=", ".join(f"{p:.2f}" for p in st["lobe_probabilities"]))))
        hi_other = max((x[1] for x in others), default=-math.inf)
        if hi_other > ts:
            rows.append(BudgetRow.type_b(msg("another trial's settling is decided up to {hi:.3g} s", hi=hi_other),
                                         "Δt_other/2", Q_((hi_other - ts) / 2, "s"), distribution="uniform"))
        rows += B.relative_calibration_row("timer", "u_rel(t)", _cal(campaign, "timer"), Q_(ts, "s"))
        b = B.type_a_budget("t_startup", "s", rows)
        note = msg("largest in {id}, decided by its samples: the output rings faster than the window", id=s.id)
        return self._outcome([Result(self.metrics[0], Q_(ts, "s"), b.combined, b, note=note)],
                             tables=[tab], segments=[x.id for x in segs], opts=opts)

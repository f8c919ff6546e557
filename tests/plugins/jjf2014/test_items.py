"""JJF 2014—2022: appendix B digits, hand-worked formulas, the simulated station's truth, bad
input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from metro.core.base.errors import DataError, MetroError, ProcedureError
from metro.core.model.campaign import Calibration, Campaign, DeviceUnderTest, Segment
from metro.core.run.runner import merge_steps, run_items
from metro.core.base.units import Q_
from metro.instruments.vibratory import EARTH_RATE_DEG_PER_H, VibratoryStation, VibratoryTruth
from metro.plugins.jjf2014 import budgets as B
from metro.plugins.jjf2014 import formulas as F
from metro.plugins.jjf2014.procedures import PROCEDURES

LAT = 39.98

# ------------------------------------------------------------------------------ appendix B


def _cal(U):
    return Calibration("appendix B", Q_(U, ""), k=2.0)


def test_appendix_b1_scale_factor_budget_digits():
    """B.1: rate table 1e-4 (k=2), DMM 6e-5 (k=2), repeatability 1.54e-4 → 1.65e-4, 3.3e-4."""
    b = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4),
                              dmm=_cal(6e-5))
    assert b.contributions() == pytest.approx([0.5e-4, 3e-5, 1.54e-4], rel=1e-12)
    assert b.combined.magnitude == pytest.approx(math.sqrt(0.5e-4**2 + 3e-5**2 + 1.54e-4**2),
                                                 rel=1e-12)
    assert F.appendix_b_presentation(b.combined.magnitude, b.k) == ("1.65×10^-4", "3.3×10^-4")
    # JJF 1059.1 two-digit rounding of U gives the same 3.3e-4
    assert b.expanded_reported().text == "0.00033"


def test_appendix_b2_bias_budget_digits():
    """B.2: DMM 6e-5 (k=2) and the scale factor's 1.65e-4 → 1.68e-4, 3.36e-4 (U = k × rounded
    u_c)."""
    b = B.bias_budget(Q_(1.0, ""), 1.65e-4, dmm=_cal(6e-5))
    assert b.combined.magnitude == pytest.approx(math.hypot(3e-5, 1.65e-4), rel=1e-12)
    assert F.appendix_b_presentation(b.combined.magnitude, b.k) == ("1.68×10^-4", "3.36×10^-4")
    # metro's certificates round U by JJF 1059.1 (two digits of k·u_c = 3.354e-4): 3.4e-4
    assert b.expanded_reported().text == "0.00034"


def test_appendix_presentation_chain_from_b1_to_b2():
    b1 = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4),
                               dmm=_cal(6e-5))
    uc1 = float(F.appendix_b_presentation(b1.combined.magnitude)[0].split("×")[0]) * 1e-4
    b2 = B.bias_budget(Q_(1.0, ""), uc1, dmm=_cal(6e-5))
    assert F.appendix_b_presentation(b2.combined.magnitude) == ("1.68×10^-4", "3.36×10^-4")


# ------------------------------------------------------------------------------ hand-worked


def test_eq4_5_hand_worked():
    f = F.scale_factor_eq4_5([-2, -1, 1, 2], [-3.9, -1.9, 2.1, 4.1])
    assert f.K == pytest.approx(2.0, abs=1e-12) and f.F0 == pytest.approx(0.1, abs=1e-12)
    assert f.u_K == pytest.approx(0.0, abs=1e-12)
    # the raw-sum form of eq. (4) gives the same K
    om, Fv = np.array([-2, -1, 1, 2.0]), np.array([-3.9, -1.9, 2.1, 4.1])
    n = 4
    K4 = (n * (om * Fv).sum() - om.sum() * Fv.sum()) / (n * (om**2).sum() - om.sum() ** 2)
    assert f.K == pytest.approx(K4, rel=1e-12)


def test_eq7_8_hand_worked():
    om, Fv = [-10, -5, 5, 10], [-20, -10.5, 9.5, 20]
    fit = F.scale_factor_eq4_5(om, Fv)  # K = 2, F0 = −0.25
    a, kn = F.nonlinearity_eq7_8(om, Fv, fit)
    np.testing.assert_allclose(a, [-0.00625, 0.00625, 0.00625, -0.00625], atol=1e-12)
    assert kn == pytest.approx(0.00625, abs=1e-12)


def test_range_is_largest_span_meeting_the_limit():
    om = np.array([-100, -50, -10, 10, 50, 100.0])
    Fv = 2 * om + 2e-4 * om**3 / 100  # cubic: nonlinearity grows with span
    r_all, kn_all = F.range_from_nonlinearity(om, Fv, 1.0)
    assert r_all == 100.0
    r, kn = F.range_from_nonlinearity(om, Fv, kn_all * 0.9)
    assert r == 50.0 and kn <= kn_all * 0.9


def test_eq9_10_11_31_hand_worked():
    assert F.asymmetry_eq9(2.002, 1.998, 2.0) == pytest.approx(0.002, rel=1e-9)
    assert F.relative_repeatability_eq10([1.0, 1.1, 0.9]) == pytest.approx(0.1, rel=1e-12)
    kt, i = F.sf_temperature_eq11([0.99, 1.0, 1.02], [0.0, 20.0, 40.0], 1)
    assert (kt, i) == (pytest.approx(1e-3, rel=1e-9), 2)
    bt, i = F.bias_temperature_eq31([1.0, 2.0, 4.0], [0.0, 20.0, 40.0], 1)
    assert (bt, i) == (pytest.approx(0.1, rel=1e-12), 2)


def test_eq12_13_hand_worked():
    d, axis, per = F.max_change_eq12_13({"X": 1, "Y": 2, "Z": 3}, {"X": 1.1, "Y": 1.7, "Z": 3.05})
    assert axis == "Y" and d == pytest.approx(0.3)
    assert per["Z"] == pytest.approx(0.05)


def test_eq16_17_hand_worked():
    om = np.array([0.1, 0.05, 0.02, 0.01])
    c, i = F.threshold_eq16_17(om, 20 * om * np.array([1, 0.9, 0.55, 0.4]), 20.0)
    assert (c, i) == (0.02, 2)
    assert F.threshold_eq16_17(om, 20 * om * 0.3, 20.0) == (None, -1)
    with pytest.raises(ValueError, match="decreasing"):
        F.threshold_eq16_17(om[::-1], om, 20.0)


def test_eq19_25_hand_worked():
    K, om = 10.0, 100.0
    d = {1: 0.003, 2: -0.001, 3: 0.002, 4: 0.0}
    Fm = {}
    for p, dp in d.items():
        Fm[(p, "+")] = 5.0 + dp * 2 * om * K / 2
        Fm[(p, "-")] = 5.0 - dp * 2 * om * K / 2
    r = F.misalignment_eq19_25(Fm, om, K)
    assert r["alpha"] == pytest.approx(0.002) and r["beta"] == pytest.approx(0.001)
    assert r["gamma"] == pytest.approx(10800 * math.sqrt(5e-6) / math.pi, rel=1e-12)  # 7.6871′


def test_eq27_29_30_hand_worked():
    assert F.bias_eq27_28([1, 3], 2.0) == pytest.approx(1.0)
    # last incomplete block dropped
    bs, m = F.bias_stability_eq29([1, 3, 1, 3, 5, 7, 5, 7, 9], 2.0, 2)
    assert m == 4 and bs == pytest.approx(math.sqrt(16 / 3) / 2, rel=1e-12)
    assert F.std_bessel([0.1, 0.3, 0.2]) == pytest.approx(0.1, rel=1e-12)
    with pytest.raises(ValueError, match="Q ≥ 7"):
        F.std_bessel([1, 2, 3], "eq. (26)", 7)


def test_eq38_fit_recovers_exact_five_term_model():
    tau = 2.0 ** np.arange(14) * 0.1 / 3600
    A = np.array([3 * (0.5 / 3600) ** 2, 0.1**2, 0.05, 0.02, 0.1])
    s2 = sum(A[i] * tau**m for i, (m, _) in enumerate(F.ALLAN_TERMS))
    fit = F.fit_allan_eq38(tau, np.sqrt(s2), 36000 / 2.0 ** np.arange(14))
    np.testing.assert_allclose(fit.A, A, rtol=1e-6)
    assert fit.active.all()
    c = F.noise_coefficients(fit.A)
    assert c["Q"] == pytest.approx(0.5 / 3600, rel=1e-6) and c["N"] == pytest.approx(0.1, rel=1e-6)
    assert c["B"] == pytest.approx(math.sqrt(0.05 * math.pi / (2 * math.log(2))), rel=1e-6)
    assert c["K"] == pytest.approx(math.sqrt(0.06),
                                   rel=1e-6) and c["R"] == pytest.approx(math.sqrt(0.2), rel=1e-6)
    assert F.arw_eq39(0.01) == pytest.approx(0.1)


def test_eq38_negative_coefficient_default_kept_and_flagged_or_removed_on_request():
    tau = 2.0 ** np.arange(12) / 3600
    s2 = 0.01 / tau + 1e-3 - 5e-4 * tau / tau.max()  # bends down: unconstrained A_1 < 0
    edf = 20000 / 2.0 ** np.arange(12)
    i1 = [m for m, _ in F.ALLAN_TERMS].index(1)
    fit = F.fit_allan_eq38(tau, np.sqrt(s2), edf)  # default: as fitted, flagged
    assert fit.A[i1] < 0 and not fit.active[i1] and fit.A[i1] == fit.raw[i1]
    assert F.noise_coefficients(fit.A)["K"] == 0.0  # reported as 0 (not resolved)
    nn = F.fit_allan_eq38(tau, np.sqrt(s2), edf, nonnegative=True)
    assert nn.raw[i1] < 0 and not nn.active[i1] and nn.A[i1] == 0.0
    assert np.all(nn.A >= 0) and nn.u_A[i1] > 0


def test_arw_unbiased_on_white_noise_with_the_default_fit():
    """The default (unconstrained) eq. (38) fit on pure white rate noise: A₋₁ unbiased within
    0.5 u on average over 40 records, the non-negative variant biased low (why it is not the
    default)."""
    from metro.core.stats import allan

    rng = np.random.default_rng(1)
    z, znn = [], []
    for _ in range(40):
        y = rng.normal(0, 1, 18000)  # σ²(τ) = 0.1 s/τ, τ₀ = 0.1 s
        ad = allan.oadev(y, 0.1, allan.octave_m(y.size))
        t, s, e = np.asarray(ad.tau) / 3600, np.asarray(ad.deviation), np.asarray(ad.edf)
        f = F.fit_allan_eq38(t, s, e, n_samples=y.size, tau0_h=0.1 / 3600)
        g = F.fit_allan_eq38(t, s, e, n_samples=y.size, tau0_h=0.1 / 3600, nonnegative=True)
        z.append((f.A[1] - 0.1 / 3600) / f.u_A[1])
        znn.append((g.A[1] - 0.1 / 3600) / g.u_A[1])
    assert abs(np.mean(z)) < 0.5 and 0.6 < np.std(z) < 1.5
    assert np.mean(znn) < np.mean(z)


def test_eq39_negative_refused():
    with pytest.raises(ValueError, match="undefined"):
        F.arw_eq39(-1e-6)


def test_bandwidth_and_delay_hand_worked():
    f = np.geomspace(10, 160, 12)
    fc, T, Td = 80.0, 1 / (2 * math.pi * 80.0), 0.002
    kr = 1 / np.sqrt(1 + (f / fc) ** 2)
    got, ab, _ = F.bandwidth_fit_743(f, kr)
    # exact first-order data: a = 1, b = 1/f_c², and K = 0.707 (literal) at f_c·√(1/0.707² − 1) =
    # 1.00042·f_c
    np.testing.assert_allclose(ab, [1.0, 1 / fc**2], rtol=1e-9)
    assert got == pytest.approx(math.sqrt(1 / 0.707**2 - 1) * fc, rel=1e-9)
    w = 2 * math.pi * f
    P = -np.arctan(w * T) - w * Td
    td, u, r = F.delay_eq48_50(w, P, T)
    assert td == pytest.approx(Td, rel=1e-12) and u == pytest.approx(0, abs=1e-15)


def test_settle_time():
    t = np.arange(10.0)
    x = np.array([5, 3, 1, 0.2, 0.6, 0.1, 0, 0, 0.05, 0])
    assert F.settle_time(t, x, 0.0, 0.5) == 5.0
    with pytest.raises(ValueError, match="still outside"):
        F.settle_time(t, np.ones(10), 0.0, 0.5)


# ------------------------------------------------------------------------------ simulated truth


ALL = [cls.item for cls in PROCEDURES]
OPTS = {"records": 3, "sample_rate": "2000 Hz"}


def _campaign(pm, items, truth=None, scale=1.0, options=None, lat=LAT):
    st = VibratoryStation(truth=truth or VibratoryTruth(), latitude_deg=lat, duration_scale=scale)
    procs = [pm.procedure("jjf2014", i) for i in items]
    from metro.core.run.runner import split_options

    per = split_options(procs, dict(options or {}))
    return st.acquire(merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)]))


@pytest.fixture(scope="module")
def full_run():
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    # seed 20221123: segments are seeded by their step's identity since issue 14; with the default
    # seed (20221122) that draw put Q (expected 0) 1.43 U high; seeds 20221123–20221127 put all 27
    # metrics within U
    camp = _campaign(pm, ALL, truth=VibratoryTruth(seed=20221123), options=OPTS)
    rec = run_items(pm, "jjf2014", ALL, campaign=camp, options=OPTS)
    return camp, {o.item: o for o in rec.outcomes}, rec


def _within(r, expected, factor=1.0):
    v = r.value.to(r.metric.unit).magnitude
    e = expected.to(r.metric.unit).magnitude
    assert abs(v - e) <= factor * r.U.magnitude, f"{r.metric.key}: {v} vs {e} ± {r.U}"


@pytest.mark.parametrize("key", ["K", "F0", "Kn", "range", "Ka", "Kr", "Kt", "Kg", "dK_shock",
                                 "dK_vib", "threshold",
                                 "resolution", "gamma", "gamma_r", "B0", "Br", "Bt", "Bg",
                                 "dB_shock", "dB_vib", "ARW",
                                 "Q", "BI", "RRW", "RR", "Bw", "Td"])
def test_simulated_truth_within_U(full_run, key):
    camp, outs, _ = full_run
    r = next(r for o in outs.values() for r in o.results if r.metric.key == key)
    assert key in camp.expected
    _within(r, camp.expected[key])


def test_simulated_threshold_resolution_stability_startup(full_run):
    camp, outs, _ = full_run
    t = VibratoryTruth()
    # threshold: gain Ω²/(Ω²+Ω_th²) ≥ 0.5 first fails at 0.007 °/s, so the last passing level is
    # 0.01; the result is the middle of (0.007, 0.01] (resolution: of (0.003, 0.005]), the level
    # itself in the note — or of a wider interval where the pass of the candidate or the fail of the
    # next level is within the responses' noise (interpretations.md, "7.2.9 / 7.2.10 — a level
    # decided by noise"): on this device the forward 0.003 °/s increment fails by less than 2u, so
    # the resolution's interval is (0.002, 0.005]
    th, res = outs["7.2.9"].result("threshold"), outs["7.2.10"].result("resolution")
    assert th.value.magnitude == pytest.approx(0.0085) and "is 0.01 °/s" in th.note
    assert "is 0.005 °/s" in res.note and "widened to (0.002, 0.005] °/s" in res.note
    assert res.value.magnitude == pytest.approx(0.0035)
    assert camp.expected["threshold_grid"].magnitude == pytest.approx(0.01)
    assert camp.expected["resolution_grid"].magnitude == pytest.approx(0.005)
    # the device's own threshold / resolution (50 % response) is within U of the reported level
    assert camp.expected["threshold"].magnitude == t.threshold_dps
    _within(outs["7.2.9"].result("threshold"), Q_(t.threshold_dps, "deg/s"))
    _within(outs["7.2.10"].result("resolution"), Q_(t.resolution_dps, "deg/s"))
    # white noise: B_s(P) = N/√P
    _within(outs["7.2.14"].result("Bs"), Q_(t.arw_deg_rt_h / math.sqrt(10 / 3600), "deg/h"))
    # start-up: the slowest trial is 0.01·FS with 1 % → 0.01 °/s: t = τ·ln(d₀/0.01)
    _within(outs["7.2.23"].result("t_startup"), Q_(t.startup_tau_s
                                                   * math.log(t.startup_excursion_dps / 0.01), "s"))


def test_every_result_has_a_budget_and_plots_exist(full_run):
    _, outs, _ = full_run
    assert len(outs) == 23
    for o in outs.values():
        for r in o.results:
            assert r.budget is not None, r.metric.key
    names = {p.name for o in outs.values() for p in o.plots}
    assert {"sf_fit", "allan", "amplitude_ratio", "phase"} <= names


def test_bias_earth_rate_option(pm):
    truth = VibratoryTruth(seed=7)
    camp = _campaign(pm, ["7.2.13"], truth=truth, scale=0.25)
    off = run_items(pm, "jjf2014", ["7.2.13"], campaign=camp).outcomes[0].result("B0")
    on = run_items(pm, "jjf2014", ["7.2.13"], campaign=camp,
                   options={"earth_rate": "on"}).outcomes[0].result("B0")
    s = math.sin(math.radians(LAT))
    _within(off, Q_(truth.bias_dps * 3600 + EARTH_RATE_DEG_PER_H * s, "deg/h"))
    _within(on, Q_(truth.bias_dps * 3600 + (EARTH_RATE_DEG_PER_H - 15.041) * s, "deg/h"))
    assert off.value.magnitude - on.value.magnitude == pytest.approx(15.041 * s, rel=1e-12)


def test_bias_acceleration_earth_rate_leak_and_correction(pm):
    truth = VibratoryTruth(seed=8, bias_accel_dps_per_g=(0.0, 0.0, 0.0))
    camp = _campaign(pm, ["7.2.17"], truth=truth, scale=0.5)
    off = run_items(pm, "jjf2014", ["7.2.17"], campaign=camp).outcomes[0].result("Bg")
    on = run_items(pm, "jjf2014", ["7.2.17"], campaign=camp,
                   options={"earth_rate": "on"}).outcomes[0].result("Bg")
    # no true g-sensitivity: uncorrected, the flipped vertical earth rate leaks in as Ω_e·sin φ per
    # g
    _within(off, Q_(EARTH_RATE_DEG_PER_H * math.sin(math.radians(LAT)), "deg/h/gn"))
    assert on.value.magnitude < 0.05 * off.value.magnitude


def test_arw_coverage_over_seeds(pm):
    """ARW (7.2.20) against the truth over 12 seeds: at least 10 within U (k = 2)."""
    inside = 0
    for seed in range(12):
        truth = VibratoryTruth(seed=500 + seed, arw_deg_rt_h=0.15)
        camp = _campaign(pm, ["7.2.20"], truth=truth, scale=0.5)
        r = run_items(pm, "jjf2014", ["7.2.20"], campaign=camp).outcomes[0].result("ARW")
        inside += abs(r.value.magnitude - 0.15) <= r.U.magnitude
    assert inside >= 10


def test_allan_five_terms_with_quantization_and_ramp(pm):
    truth = VibratoryTruth(seed=21, arw_deg_rt_h=0.05, quantization_arcsec=2.0,
                           rate_ramp_deg_h2=400.0)
    camp = _campaign(pm, ["7.2.20"], truth=truth, options={})
    o = run_items(pm, "jjf2014", ["7.2.20"], campaign=camp).outcomes[0]
    _within(o.result("ARW"), Q_(0.05, "deg/hour**0.5"), 1.5)
    _within(o.result("Q"), Q_(2.0, "arcsec"), 1.5)
    _within(o.result("RR"), Q_(400.0, "deg/h**2"), 1.5)


def test_sf_plots_fit_and_residuals(full_run):
    _, outs, _ = full_run
    fit, res = outs["7.2.1"].plots
    assert (fit.name, res.name) == ("sf_fit", "sf_residuals")
    assert fit.series[0]["x"] == sorted(fit.series[0]["x"]) and len(fit.series) == 2
    s = outs["7.2.1"].tables[0]
    assert [float(r[3]) for r in s.rows] == pytest.approx(res.series[0]["y"], rel=1e-2, abs=1e-3)


# ------------------------------------------------------------------------------ bad input


def _camp(segs, props=None):
    dev = DeviceUnderTest("D", properties=props or {})
    return Campaign("C", dev, [], {}, {"latitude": Q_(40, "deg")}, segs, source="test.toml")


def _seg(id, kind, cond, data, unit="mV", interval=1.0):
    return Segment(id, kind, cond, Q_(interval, "s"), sha256="0" * 64,
                   loader=lambda: {"output": (np.asarray(data, float), unit)})


def test_bias_without_scale_factor_is_a_data_error(pm):
    camp = _camp([_seg("s", "static", {"orientation": "IRA up"}, np.ones(100))])
    with pytest.raises(DataError, match="scale factor"):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_bias_with_device_scale_factor(pm):
    camp = _camp([_seg("s", "static", {"orientation": "IRA up"},
                       np.r_[np.full(50, 1.0), np.full(50, 3.0)])],
                 {"scale_factor": Q_(20, "mV/(deg/s)")})
    r = run_items(pm, "jjf2014", ["7.2.13"], campaign=camp).outcomes[0].result("B0")
    assert r.value.magnitude == pytest.approx(2.0 / 20 * 3600)


def test_nan_sample_named(pm):
    data = np.r_[np.ones(40), np.nan, np.ones(59)]
    camp = _camp([_seg("s", "static", {}, data)], {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(DataError, match="sample 41"):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_wrong_unit_refused(pm):
    camp = _camp([_seg("s", "static", {}, np.ones(100), unit="deg/h")],
                 {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(MetroError):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_misalignment_repeatability_needs_seven_runs(pm):
    with pytest.raises(ProcedureError, match="option runs"):  # a plan with Q < 7 is refused
        _campaign(pm, ["7.2.12"], options={"runs": 3})
    camp = _campaign(pm, ["7.2.12"])
    segs = [s for s in camp.segments if not (s.kind == "misalignment" and s.conditions["run"]
                                             in ("5", "6", "7"))]
    bad = Campaign("C", camp.device, camp.equipment, {}, camp.site, segs, source="x")
    with pytest.raises(DataError, match="Q ≥ 7"):
        run_items(pm, "jjf2014", ["7.2.12"], campaign=bad)


def test_threshold_needs_zero_input(pm):
    camp = _campaign(pm, ["7.2.9"])
    segs = [s for s in camp.segments if s.id != "threshold-0"]
    bad = Campaign("C", camp.device, camp.equipment, {}, camp.site, segs, source="x")
    with pytest.raises(DataError, match="zero-input"):
        run_items(pm, "jjf2014", ["7.2.9"], campaign=bad)


def test_allan_constant_data_refused(pm):
    camp = _camp([_seg("s", "static", {}, np.full(3600, 2.0))],
                 {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(ProcedureError, match="positive"):
        run_items(pm, "jjf2014", ["7.2.20"], campaign=camp)


def test_scale_factor_too_few_rates(pm):
    camp = _camp([_seg("a", "rate", {"rate": "1 deg/s"}, np.ones(10)),
                  _seg("b", "rate", {"rate": "2 deg/s"}, np.ones(10))])
    with pytest.raises(DataError, match="at least 3"):
        run_items(pm, "jjf2014", ["7.2.1"], campaign=camp)


def test_bandwidth_needs_frequencies(pm):
    camp = _campaign(pm, ["7.2.21"], options={"frequencies": 3, "records": 2,
                                              "sample_rate": "1000 Hz"})
    top = max(s.conditions["frequency"] for s in camp.segments if s.kind == "angular-vibration")
    segs = [s for s in camp.segments if s.conditions.get("frequency") != top]
    bad = Campaign("C", camp.device, camp.equipment, {}, camp.site, segs, source="x")
    with pytest.raises(DataError, match="at least 3 frequencies"):
        run_items(pm, "jjf2014", ["7.2.21"], campaign=bad)


def test_temperature_needs_room_point(pm):
    camp = _campaign(pm, ["7.2.5"], options={"temperatures": "-40, 60"})
    with pytest.raises(DataError, match="room temperature"):
        run_items(pm, "jjf2014", ["7.2.5"], campaign=camp)


def test_startup_never_settles(pm):
    """An output still outside its band at the end of the record has no start-up time within it: the
    result is not reportable with that reason (it was a ProcedureError that stopped every other item
    of the run too; docs/independent-campaigns.md, "JJF 2014: shock, vibration, stability and
    dynamic items")."""
    camp = _campaign(pm, ["7.2.23"], truth=VibratoryTruth(startup_tau_s=200.0))
    r = run_items(pm, "jjf2014", ["7.2.23"], campaign=camp).outcomes[0].result("t_startup")
    # its last quarter still drifts, so the settled value itself is not known to the band's width
    assert not r.reportable and ("at the end of the record" in r.reason or "cannot be decided"
                                 in r.reason), r.reason


def test_startup_of_a_coarsely_digitised_output(pm):
    """analog-coarser (output rounded to 0.2 mV ≈ 0.01 °/s, coarser than one sample's noise): the
    samples' noise from their differences' MAD is ≈ 0, so single rounded samples counted as outside
    the band "by more than 4.5u" to the record's end — 60.0 s with U 0.06 s against τ·ln(d₀/0.01) =
    18.6 s (seeds 26 and 34 of the class: E_n +716 and +38). The rounding's half-width now widens
    the margins; a result is within U or not reportable (interpretations.md, "7.2.23 — where in the
    interval")."""
    t = VibratoryTruth()
    truth = t.startup_tau_s * math.log(t.startup_excursion_dps / 0.01)
    for seed in (26, 34):
        rec = run_items(pm, "jjf2014", ["7.2.23"],
                        station_options={"seed": seed, "device_class": "analog-coarser"})
        r = rec.outcomes[0].result("t_startup")
        assert not r.reportable or abs(r.value.magnitude
                                       - truth) <= r.U.magnitude, (seed, r.value, r.U)


def test_procedure_classes_are_registered(pm):
    from metro.plugins.jjf2014.procedures import (AngleRandomWalk, Asymmetry, Bandwidth, Bias,
                                                  BiasAcceleration, BiasRepeatability, BiasShock,
                                                  BiasStability, BiasTemperature, BiasVibration,
                                                  Misalignment, MisalignmentRepeatability,
                                                  NonlinearityRange, OutputDelay, Repeatability,
                                                  Resolution, ScaleFactor, SFAxialAcceleration,
                                                  SFShock, SFTemperature, SFVibration, StartupTime,
                                                  Threshold)

    classes = (ScaleFactor, NonlinearityRange, Asymmetry, Repeatability, SFTemperature,
               SFAxialAcceleration, SFShock,
               SFVibration, Threshold, Resolution, Misalignment, MisalignmentRepeatability, Bias,
               BiasStability,
               BiasRepeatability, BiasTemperature, BiasAcceleration, BiasShock, BiasVibration,
               AngleRandomWalk,
               Bandwidth, OutputDelay, StartupTime)
    for cls in classes:
        assert pm.procedure("jjf2014", cls.item) is cls
        assert cls.station == "simulated-jjf2014"
    assert [c.item for c in classes] == [f"7.2.{i}" for i in range(1, 24)]


def test_station_is_registered(pm):
    st = pm.station("simulated-jjf2014").factory(seed=3)
    assert st.truth.seed == 3


# ------------------------------------------------------------------------------ audit additions


def test_threshold_resolution_budget_is_the_one_sided_level_step(full_run):
    """7.2.9/7.2.10: the true value lies in (next level, candidate]; reported as its middle with
    u = step/√12. (As the candidate with u = step/√3 the result was always above the device's value:
    mean E_n +0.58 and +0.43 over every device class, a fixed truth between two levels.)"""
    _, outs, _ = full_run
    # (the resolution's interval is wider on this device: its 0.003 °/s fail is within the noise,
    # below)
    for item, key, hi, lo in (("7.2.9", "threshold", 0.01, 0.007),
                              ("7.2.10", "resolution", 0.005, 0.002)):
        r = outs[item].result(key)
        assert r.value.to("deg/s").magnitude == pytest.approx((hi + lo) / 2, rel=1e-12)
        row = r.budget.rows[0]
        assert row.standard_uncertainty.to("deg/s").magnitude == pytest.approx(
            (hi - lo) / math.sqrt(12), rel=1e-12)


@pytest.mark.parametrize("hard", [False, True], ids=["soft-dead-zone", "hard-dead-band"])
def test_dead_band_threshold_and_resolution_recovered_over_seeds(pm, hard):
    """A device with a (soft or hard) dead band: its threshold Ω_th and resolution r_res (50 %
    response) lie within U of what 7.2.9/7.2.10 report, over seeds and for truths between levels."""
    for seed, (th, res) in enumerate(((0.012, 0.006), (0.008, 0.004), (0.025, 0.0025))):
        truth = VibratoryTruth(seed=40 + seed, threshold_dps=th, resolution_dps=res,
                               hard_dead_band=hard)
        camp = _campaign(pm, ["7.2.9", "7.2.10"], truth=truth)
        assert camp.expected["threshold"].magnitude == th and camp.expected[
            "resolution"].magnitude == res
        outs = {o.item: o for o in run_items(pm, "jjf2014", ["7.2.9", "7.2.10"],
                                             campaign=camp).outcomes}
        t, r = outs["7.2.9"].result("threshold"), outs["7.2.10"].result("resolution")
        assert "the standard's value" in t.note and "the standard's value" in r.note
        _within(t, Q_(th, "deg/s"))
        _within(r, Q_(res, "deg/s"))


def test_hard_dead_band_has_no_output_below_the_threshold():
    from metro.instruments.vibratory import increment_gain, steady_output

    t = VibratoryTruth(hard_dead_band=True, bias_dps=0.0)
    out = steady_output(t, np.array([0.0079, 0.008, -0.0079, -0.0081]), K=20.0, bias_dps=0.0)
    assert out[0] == 0.0 and out[2] == 0.0 and out[1] > 0 and out[3] < 0
    assert increment_gain(t, 0.0039) == 0.0 and increment_gain(t, 0.004) == 1.0
    # soft: exactly half at r_res
    assert increment_gain(VibratoryTruth(), 0.004) == pytest.approx(0.5)


def test_eq35_37_as_printed_is_not_the_allan_variance_implemented():
    """Reading note: eq. (35) sums k + 1 samples over k; eq. (37) normalises by 2n(n−k−1) and
    differences averages one sample apart.  metro implements the overlapping Allan variance of
    cluster averages of τ = k·t₀ (core.allan.oadev); hand-worked here, and the literal formula
    shown to miss the Allan variance of white noise by orders of magnitude."""
    from metro.core.stats import allan

    y = np.array([1.0, 3.0, 2.0, 6.0, 4.0])
    ad = allan.oadev(y, 1.0, [1, 2])
    # m = 1: differences 2, −1, 4, −2 → 25/(2·4); m = 2: cluster means 2, 2.5, 4, 5 → (2² +
    # 2.5²)/(2·2)
    np.testing.assert_allclose(np.asarray(ad.deviation) ** 2, [25 / 8, 10.25 / 4], rtol=1e-12)

    def eq35_37_as_printed(om, k):
        n = om.size
        means = np.array([om[p:p + k + 1].sum() / k for p in range(n - k)])  # Σ_{i=p}^{p+k} / k
        d2 = means[2:] - 2 * means[1:-1] + means[:-2]
        return float((d2[: n - k - 1] ** 2).sum() / (2 * n * (n - k - 1)))

    w = np.random.default_rng(0).normal(0.0, 1.0, 4000)  # white: σ²(τ₀) = 1
    assert float(allan.oadev(w, 1.0, [1]).deviation[0] ** 2) == pytest.approx(1.0, rel=0.05)
    assert eq35_37_as_printed(w, 1) < 1e-3


def test_allan_covariance_uses_the_tau_ratio():
    """The starting weights (before the fit's noise mix is known;
    tests/core/stats/test_allan_covariance.py has the covariance for the fitted mix)."""
    tau = 2.0 ** np.arange(4)
    C = F.allan_covariance_approx(np.ones(4), np.array([2400.0, 2057, 1252, 662]), tau)
    R = C / np.sqrt(np.outer(np.diag(C), np.diag(C)))
    assert R[0, 1] == pytest.approx(math.sqrt(0.5)) and R[0, 2] == pytest.approx(0.5)
    assert C[0, 0] == pytest.approx(2 / 2400)


def test_coefficient_u_maps_the_interval_through_the_square_root():
    u, _ = F.coefficient_u(1.0, 1e-3, 1.0)
    assert u == pytest.approx(1e-3 / 2, rel=1e-3)  # well resolved: the linear c·u(A)/(2√(cA))
    u, _ = F.coefficient_u(1e-3, 1e-3, 1.0)  # barely resolved: the A ± 2u interval reaches √0 = 0
    # linearisation would give only 1e-3/√1e-3 = 0.5 of that
    assert 2 * u == pytest.approx(math.sqrt(1e-3))
    u, _ = F.coefficient_u(-1e-3, 1e-3, 3.0)
    assert 2 * u == pytest.approx(math.sqrt(3 * 1e-3))


def test_allan_bias_instability_and_rate_random_walk_recovered(pm):
    """Flicker (bias instability) or rate random walk on top of ARW in the simulator: the five
    eq. (38) coefficients within U of the truth in ≥ 85 % of 2 × 4 seeds × 5 coefficients (k = 2,
    so about 95 % expected; 300 seeds per mix: interpretations.md, "7.2.20 — weighting")."""
    inside, total = 0, 0
    for kw in ({"bias_instability_deg_h": 1.0, "arw_deg_rt_h": 0.05}, {"rrw_deg_h_rt_h": 5.0}):
        for seed in range(4):
            truth = VibratoryTruth(seed=300 + seed, **kw)
            camp = _campaign(pm, ["7.2.20"], truth=truth)
            o = run_items(pm, "jjf2014", ["7.2.20"], campaign=camp).outcomes[0]
            for key in ("ARW", "Q", "BI", "RRW", "RR"):
                r, e = o.result(key), camp.expected[key]
                inside += abs(r.value.magnitude - e.to(r.metric.unit).magnitude) <= r.U.magnitude
                total += 1
            if "bias_instability_deg_h" in kw:  # flicker is resolved, not reported 0
                assert o.result("BI").value.magnitude > o.result("BI").U.magnitude / 2
    assert inside >= 0.85 * total


# ------------------------------------------------------------------------------ bad input, per item


def _mut(camp, keep=lambda s: True, cond=None, cols=None):
    import attrs

    segs = []
    for s in camp.segments:
        if not keep(s):
            continue
        c = cond(s) if cond else None
        if c is not None:
            s = attrs.evolve(s, conditions=c)
        data = cols(s) if cols is not None else None
        if data is not None:
            s = attrs.evolve(s, loader=(lambda d=data: d))
        segs.append(s)
    return Campaign("C", camp.device, camp.equipment, {}, camp.site, segs, source="bad.toml")


def _set(s, kind, **kv):
    return (dict(s.conditions) | kv) if s.kind == kind else None


BAD = [
    ("7.2.2", dict(keep=lambda s: not (s.kind == "rate"
                                       and str(s.conditions["rate"]).startswith("-"))),
     ProcedureError, "forward"),
    ("7.2.3", dict(keep=lambda s: not (s.kind == "rate"
                                       and str(s.conditions["rate"]).startswith("-")
                                       and abs(float(str(s.conditions["rate"]).split()[0])) < 60)),
     DataError, "3 forward and 3 reverse"),
    ("7.2.4", dict(keep=lambda s: s.kind != "rate-repeat" or s.conditions["run"] == "1"), DataError,
     "Q ≥ 2"),
    ("7.2.5", dict(cond=lambda s: _set(s, "rate-temperature", temperature="20.0 °C")
                   if s.conditions.get("temperature") == "60 degC" else None), DataError,
     "same temperature"),
    ("7.2.6", dict(keep=lambda s: not (s.kind == "rate-accel" and "down"
                                       in s.conditions["orientation"])),
     DataError, "IRA up and with it down"),
    ("7.2.7", dict(cond=lambda s: _set(s, "rate-shock", axis="W")), DataError, "axis.*X, Y or Z"),
    ("7.2.8", dict(cond=lambda s: _set(s, "rate-vibration", phase="during")), DataError,
     "phase.*before"),
    ("7.2.9", dict(cond=lambda s: _set(s, "threshold", rate="0.05 deg/s")
                   if s.id == "threshold+0.03" else None), DataError, "more than once"),
    ("7.2.10", dict(keep=lambda s: s.id != "resolution+base"), DataError, "base segment"),
    ("7.2.11", dict(cond=lambda s: _set(s, "misalignment", position="5") if s.id.endswith("p4+")
                    else None),
     DataError, "position.*1, 2, 3 or 4"),
    ("7.2.13", dict(keep=lambda s: s.kind != "static"), DataError, "kind 'static'"),
    ("7.2.14", dict(keep=lambda s: s.kind != "static"), DataError, "kind 'static'"),
    ("7.2.15", dict(keep=lambda s: s.kind != "static-repeat" or s.conditions["run"] == "1"),
     DataError, "Q ≥ 2"),
    ("7.2.16", dict(keep=lambda s: s.kind != "static-temperature" or s.conditions["temperature"]
                    == "20 degC"),
     DataError, "at least 2 temperatures"),
    ("7.2.17", dict(keep=lambda s: not (s.kind == "static-accel" and s.conditions["orientation"]
                                        == "down")),
     DataError, "both up and down"),
    ("7.2.18", dict(keep=lambda s: not (s.kind == "static-shock" and s.conditions["phase"]
                                        == "after")),
     DataError, "before and an after"),
    ("7.2.19", dict(cond=lambda s: _set(s, "static-vibration", axis="Q")), DataError, "axis"),
    ("7.2.20", dict(cols=lambda s: {"output": (np.full(3600, 2.0), "mV")} if s.kind == "static"
                    else None),
     ProcedureError, "positive"),
    ("7.2.21", dict(cols=lambda s: {"output": s.columns()["output"]} if s.kind
                    == "angular-vibration" else None),
     DataError, "no column 'reference'"),
    ("7.2.22", dict(cols=lambda s: {"output": (s.columns()["output"][0], "V"),
                                    "reference": (s.columns()["reference"][0], "rad")}
                    if s.kind == "angular-vibration" else None), DataError, "reference"),
    ("7.2.23", dict(cond=lambda s: _set(s, "startup", trial="warm-up")), DataError,
     "trial.*position"),
]


@pytest.mark.parametrize("item,mut,exc,match", BAD, ids=[b[0] for b in BAD])
def test_bad_input_per_item(full_run, pm, item, mut, exc, match):
    camp, _, _ = full_run
    with pytest.raises(exc, match=match) as ei:
        run_items(pm, "jjf2014", [item], campaign=_mut(camp, **mut),
                  options=OPTS if item in ("7.2.21", "7.2.22") else {})
    if isinstance(ei.value, DataError):
        # names the field (and the file, for recorded data: see the CLI tests)
        assert ei.value.field


def test_bad_input_covers_every_item():
    # 7.2.1: too few rates; 7.2.12: Q < 7 (tests above)
    named = {b[0] for b in BAD} | {"7.2.1", "7.2.12"}
    assert named == set(ALL)


def test_bad_options_are_clear_errors(full_run, pm):
    camp, _, _ = full_run
    for item, opt, match in (("7.2.20", {"nonnegative": "maybe"}, "nonnegative"),
                             ("7.2.13", {"earth_rate": "sometimes"}, "earth_rate"),
                             ("7.2.13", {"batches": "1.5"},
                              "option batches': '1.5' is not a whole number"),
                             ("7.2.14", {"P": "0.15 s"}, "whole number of sampling intervals")):
        with pytest.raises((ProcedureError, DataError), match=match):
            run_items(pm, "jjf2014", [item], campaign=camp, options=opt)


# ------------------------------------------------------------------------------ issue 13: budgets
# that hold


def _with(camp, segs=None, **props):
    """The campaign with other segments and/or extra device properties."""
    import attrs

    dev = attrs.evolve(camp.device, properties={**camp.device.properties, **props})
    return Campaign(camp.id, dev, camp.equipment, camp.environment, camp.site,
                    camp.segments if segs is None else segs, source=camp.source)


def test_scale_factor_u3_is_the_repeatability_of_the_campaign(pm):
    """Appendix B's u₃r (1.54×10⁻⁴) is a repeatability: with the campaign's 7.2.4 runs, u₃ of
    7.2.1 is K_r·K with ν = Q − 1 (was the fit's standard error, 30× smaller here); without
    them it falls back to device.scale_factor_repeatability (type B), else to the fit's standard
    error with a warning."""
    truth = VibratoryTruth(seed=31, sf_repeat_rel=5e-4)
    camp = _campaign(pm, ["7.2.1", "7.2.4"], truth=truth)
    outs = {o.item: o for o in run_items(pm, "jjf2014", ["7.2.1", "7.2.4"], campaign=camp).outcomes}
    K, Kr = outs["7.2.1"].result("K"), outs["7.2.4"].result("Kr")
    u3 = next(r for r in K.budget.rows if r.symbol == "u₃")
    assert u3.standard_uncertainty.magnitude == pytest.approx(
        Kr.value.magnitude * K.value.magnitude, rel=1e-12
    )
    assert u3.type == "A" and u3.dof == 5
    # the rule of issue 13: no budget smaller than the spread the standard's own repeatability item
    # measures
    assert K.U.magnitude / K.value.magnitude >= Kr.value.magnitude
    # the items that divide by K carry it (and its ν_eff)
    b0 = run_items(pm, "jjf2014", ["7.2.21"], campaign=_campaign(pm, ["7.2.4", "7.2.21"],
                                                                 truth=truth,
                                                                options=OPTS)).outcomes[0].result("Bw")
    kb = next(r for r in b0.budget.rows if r.symbol == "u_rel(K)")
    assert kb.standard_uncertainty.magnitude >= Kr.value.magnitude * 0.5 and math.isfinite(kb.dof)
    # fallbacks
    only = _with(camp, [s for s in camp.segments if s.kind == "rate"])
    o = run_items(pm, "jjf2014", ["7.2.1"], campaign=only).outcomes[0]
    assert any("rate-repeat" in w and "fit's standard error" in w for w in o.warnings)
    assert o.result("K").U.magnitude < 0.2 * K.U.magnitude
    stated = run_items(pm, "jjf2014", ["7.2.1"],
                       campaign=_with(only, scale_factor_repeatability=Q_(3e-4, ""))
                       ).outcomes[0].result("K")
    u3s = next(r for r in stated.budget.rows if r.symbol == "u₃")
    assert u3s.type == "B" and u3s.standard_uncertainty.magnitude == pytest.approx(
        3e-4 * stated.value.magnitude)


def test_no_budget_smaller_than_the_campaigns_own_repeatability(full_run):
    """Issue 13: U(K)/K ≥ K_r, U(γ_m) ≥ γ_mr, U(B₀) ≥ B_r, and each single K or B₀ in a
    difference (K_t, K_g, ΔK, B_t, B_g, ΔB) carries at least the repeatability."""
    _, outs, _ = full_run
    r = {x.metric.key: x for o in outs.values() for x in o.results}
    assert r["K"].U.magnitude / r["K"].value.magnitude >= r["Kr"].value.magnitude
    assert r["gamma"].U.magnitude >= r["gamma_r"].value.magnitude
    assert r["B0"].U.magnitude >= r["Br"].value.magnitude
    K, Kr, Br = r["K"].value.magnitude, r["Kr"].value.magnitude, r["Br"].value.magnitude
    for key, scale in (("dK_shock", 1.0), ("dK_vib", 1.0), ("Kg", 0.5)):
        assert r[key].budget.combined.magnitude >= math.sqrt(2) * scale * Kr * K * (1 - 1e-3), key
    for key, scale in (("dB_shock", 1.0), ("dB_vib", 1.0), ("Bg", 0.5)):
        assert r[key].budget.combined.magnitude >= math.sqrt(2) * scale * Br * (1 - 1e-9), key
    g = next(x for x in r["gamma"].budget.rows if x.symbol == "γ_mr")
    assert g.standard_uncertainty.magnitude == pytest.approx(r[
        "gamma_r"].value.magnitude) and g.dof == 6


def test_coverage_factor_from_nu_eff(full_run):
    """k = t_p(ν_eff), p = 95.45 % (interpretations.md "JJF 2014 — coverage factor"): K of 7.2.1,
    whose u₃ = K_r·K has ν = Q − 1 = 5, gets k = t(ν_eff) > 2.2, not 2; a budget of infinite ν gets
    2.00. K_r and B_r themselves: the χ² bound (interpretations.md "Repeatabilities: the χ² bound"),
    ν = ∞, k = 2 and s + U = s·√(5/χ²₀.₀₂₂₇₅(5)) = 2.505·s, the 97.7 % upper limit of σ."""
    from scipy import stats

    from metro.core.uncertainty.budget import std_upper_limit

    _, outs, _ = full_run
    b = outs["7.2.1"].result("K").budget
    assert math.isfinite(b.nu_eff) and b.k == pytest.approx(stats.t.ppf(0.97725, b.nu_eff),
                                                            rel=1e-9) and b.k > 2.2
    for key, item in (("Kr", "7.2.4"), ("Br", "7.2.15")):
        r = outs[item].result(key)
        row = r.budget.rows[0]
        assert "χ² bound" in row.source and row.dof == math.inf
        s = r.value.magnitude
        assert row.standard_uncertainty.magnitude == pytest.approx((std_upper_limit(s, 6) - s) / 2,
                                                                   rel=1e-9)
        assert std_upper_limit(1.0, 6) == pytest.approx(2.505, abs=1e-3)
    b = B.scale_factor_budget(Q_(1, ""), Q_(1.54e-4, ""), math.inf,
                              rate_table=Calibration("T", Q_(1e-4, ""), k=2),
                              dmm=Calibration("D", Q_(6e-5, ""), k=2))
    assert b.k == pytest.approx(2.0, abs=1e-5)


def test_output_delay_uses_the_minus_3_db_point(pm):
    """7.2.22: T = 1/(2πB_w) (eq. (47)) is the corner of the eq. (46) model, where |G| = 1/√2.
    On a noiseless first-order-plus-delay device T_d is exact; read at the literal 0.707 it was
    0.5 µs long (+1.65 U on average over seeds)."""
    from metro.core.run.runner import split_options

    truth = VibratoryTruth(seed=5, arw_deg_rt_h=0.0, ref_noise_dps=0.0, cubic=0.0, asymmetry=0.0,
                           threshold_dps=0.0)
    proc = pm.procedure("jjf2014", "7.2.22")
    steps = proc().sequence(proc.option_values(split_options([proc], OPTS)[0]))
    camp = VibratoryStation(truth=truth, latitude_deg=LAT, table_errors=False).acquire(steps)
    td = run_items(pm, "jjf2014", ["7.2.22"], campaign=camp, options=OPTS).outcomes[0].result("Td")
    assert td.value.to("s").magnitude == pytest.approx(truth.delay_s, abs=2e-9)
    # hand-worked: exact first-order data with f_c = 80 Hz, T_d = 2 ms
    f = np.geomspace(10, 160, 12)
    kr = 1 / np.sqrt(1 + (f / 80.0) ** 2)
    w = 2 * math.pi * f
    P = -np.arctan(w / (2 * math.pi * 80.0)) - w * 0.002
    fc3, _, _ = F.bandwidth_fit_743(f, kr, 1 / math.sqrt(2))
    assert fc3 == pytest.approx(80.0, rel=1e-12)
    assert F.delay_eq48_50(w, P, 1 / (2 * math.pi * fc3))[0] == pytest.approx(0.002, rel=1e-10)
    fc7 = F.bandwidth_fit_743(f, kr)[0]  # the literal 0.707: 80.033 Hz
    assert F.delay_eq48_50(w, P, 1 / (2 * math.pi * fc7))[0] - 0.002 > 2e-7


def test_every_result_discloses_the_earth_rate(full_run, pm):
    """Issue 13: Result.earth_rate on every result; B₀, F₀ and the IRA pair of B_g hold
    Ω_e·sin φ as the standard prints (B_g ≈ 20 °/h/g for a 10.8 °/h/g device here), and say so."""
    _, outs, _ = full_run
    for o in outs.values():
        for r in o.results:
            assert r.earth_rate in ("included", "removed", "not applicable"), r.metric.key
    assert outs["7.2.13"].result("B0").earth_rate == "included"
    assert outs["7.2.1"].result("F0").earth_rate == "included"
    assert outs["7.2.1"].result("K").earth_rate == "not applicable"
    bg = outs["7.2.17"].result("Bg")
    assert (bg.earth_rate == "included" and "earth rate included" in bg.note
            and "-o earth_rate=on" in bg.note)
    camp = _campaign(pm, ["7.2.17"], scale=0.25)
    on = run_items(pm, "jjf2014", ["7.2.17"], campaign=camp,
                   options={"earth_rate": "on"}).outcomes[0].result("Bg")
    assert on.earth_rate in ("removed", "not applicable")
    b0 = run_items(pm, "jjf2014", ["7.2.13"], campaign=_campaign(pm, ["7.2.13"], scale=0.25),
                   options={"earth_rate": "on"}).outcomes[0].result("B0")
    assert b0.earth_rate == "removed" and "earth rate removed" in b0.note


# ------------------------------------------------------------------------------ device classes
# (issue 13)


def _class_checks(pm, cls, items, seeds, **station):
    from metro.core.cli.present import truth_checks

    out = []
    for seed in seeds:
        rec = run_items(pm, "jjf2014", items, station_options={"seed": seed, "device_class": cls,
                                                               **station})
        out += [(seed, c) for c in truth_checks(rec)]
    return out


def test_device_classes_are_populations_and_refused_when_unknown():
    from metro.instruments.vibratory import DEVICE_CLASSES, draw_device, station_factory

    assert {"analog-fine", "analog-power-on", "analog-coarse"} <= set(DEVICE_CLASSES)
    a, b = station_factory(device_class="analog-power-on",
                           seed=1), station_factory(device_class="analog-power-on", seed=2)
    assert a.truth.power_on_variation and a.truth.K_mV_per_dps != b.truth.K_mV_per_dps
    assert station_factory(device_class="analog-coarse", seed=3,
                           output_lsb_mV="0.05").truth.output_lsb_mV == 0.05
    assert draw_device("analog-fine", 4) == draw_device("analog-fine", 4)
    with pytest.raises(MetroError, match="device class"):
        station_factory(device_class="analog-nonesuch")


@pytest.mark.parametrize("cls, items", [
    ("analog-fine", ["7.2.1", "7.2.4", "7.2.13", "7.2.15"]),
    ("analog-power-on", ["7.2.1", "7.2.4", "7.2.13", "7.2.15", "7.2.18"]),
    ("analog-coarse", ["7.2.1", "7.2.13", "7.2.14"]),
    ("analog-ratiometric", ["7.2.1", "7.2.4", "7.2.13", "7.2.15"]),
])
def test_device_class_truth_within_U(pm, cls, items):
    """One modest run per device class (issue 13; the ≥ 200-seed tables are on
    docs/standards/jjf2014.md): the checked results of 3 devices of the class within their U, one in
    eight outside at most (a 95 % interval misses one in twenty; with the fit's standard error as u₃
    most K fall outside)."""
    checks = _class_checks(pm, cls, items, range(1, 4), duration_scale=0.1)
    bad = [(s, c["key"], c["value"], c["truth"], c["U"]) for s, c in checks if not c["within_U"]]
    assert len(checks) >= 3 * len(items) and len(bad) <= len(checks) // 8, bad


def test_power_on_class_k_would_fail_with_the_fits_standard_error(pm):
    """The analog-power-on device: 7.2.1's K is off the device's K by one power-on's draw (1σ
    2×10⁻⁴), many times its fit's standard error (≈ 10⁻⁵); u₃ = K_r·K (ν = 5) covers it, the fit's
    standard error would not (seeds 1–5: 3 of 5 inside, against 1 of 5 with the fit's error)."""
    inside, outside_fit, n = 0, 0, 0
    for _seed, c in _class_checks(pm, "analog-power-on", ["7.2.1", "7.2.4"], range(1, 6),
                                 duration_scale=0.1):
        if c["key"] == "K":
            n += 1
            inside += bool(c["within_U"])
            outside_fit += abs(c["value"] - c["truth"]) > 4 * 1e-5 * c["truth"]  # ≫ 2·u_fit(K)
    assert n == 5 and inside >= 3 and outside_fit >= 2  # with u₃ = the fit's error: 1 of 5 inside


@pytest.mark.slow
def test_power_on_class_coverage_over_seeds(pm):
    """12 devices of class analog-power-on, the items whose budgets carry the repeatability: ≥ 80 %
    within U for each result (the 200-seed figures are on docs/standards/jjf2014.md)."""
    checks = _class_checks(pm, "analog-power-on", ["7.2.1", "7.2.4", "7.2.13", "7.2.15"],
                           range(100, 112),
                           duration_scale=0.1)
    by: dict[str, list[bool]] = {}
    for _, c in checks:
        by.setdefault(c["key"], []).append(bool(c["within_U"]))
    for key, v in by.items():
        assert sum(v) >= 0.8 * len(v), (key, sum(v), len(v))


def test_repeatability_pooled_with_a_larger_scatter_of_the_items_own_calibrations():
    """interpretations.md "JJF 2014 — the largest of noisy slopes and changes": the K before a test
    on three axes (ν = 2) that scatter more than K_r (ν = 5) are pooled with it; less: K_r stays
    (never below the repeatability item's spread); no K_r: the scatter alone."""
    from metro.core.uncertainty.selection import line_scatter
    from metro.plugins.jjf2014.common import Spread, with_scatter

    rep = Spread(1e-4, 5.0, "K_r")
    p = with_scatter(rep, 3e-4, 2, "K before")
    assert p.value == pytest.approx(math.sqrt((5 * 1e-8 + 2 * 9e-8) / 7), rel=1e-12) and p.dof == 7
    assert with_scatter(rep, 0.5e-4, 2, "K before") is rep
    alone = with_scatter(None, 3e-4, 2, "K before")
    assert alone.value == 3e-4 and alone.dof == 2 and alone.type == "A"
    assert with_scatter(Spread(5e-4, math.inf, "stated", "B"), 3e-4, 2, "K before").value == 5e-4
    # residuals about the least-squares line
    s, nu = line_scatter([1.0, 2.0, 3.1, 3.9, 5.0], [0, 1, 2, 3, 4])
    r = np.array([1.0, 2.0, 3.1, 3.9, 5.0]) - np.polyval(
        np.polyfit(np.arange(5.0), [1.0, 2.0, 3.1, 3.9, 5.0], 1), np.arange(5.0)
    )
    assert nu == 3 and s == pytest.approx(math.sqrt(np.sum(r * r) / 3), rel=1e-12)


def test_largest_slope_and_change_corrected_on_power_on_devices(pm):
    """K_t (eq. 11) and ΔK (eqs. 12–15) are maxima of noisy values: on analog-power-on devices (each
    calibration before and after a shock or vibration its own power-on, K 1σ 2×10⁻⁴) the formula's
    ΔK reads high; the corrected value is nearer the device's (seeds 1–8; the 200-device table is on
    docs/standards/jjf2014.md). K_t's points share one power-on through the chamber (7.2.5.1 d), as
    the station now keeps them): their maximum is not biased there. On analog-fine the correction is
    a small part of U."""
    import re

    printed_err, value_err, kt_err = [], [], []
    for seed in range(1, 9):
        rec = run_items(pm, "jjf2014", ["7.2.4", "7.2.5", "7.2.7", "7.2.8"],
                        station_options={"seed": seed, "device_class": "analog-power-on",
                                         "duration_scale": 0.1})
        from metro.core.cli.present import truth_checks

        truth = {c["key"]: c["truth"] for c in truth_checks(rec)}
        for o in rec.outcomes:
            for r in o.results:
                if r.metric.key in ("Kt", "dK_vib", "dK_shock"):
                    m = re.search(r"as printed by the formula ([-0-9.e+]+)", str(r.note))
                    assert m, r.note
                    scale = 1e6 if r.metric.key == "Kt" else 1.0  # the note prints K_t in ppm/°C
                    U = r.budget.expanded.magnitude
                    if r.metric.key == "Kt":
                        kt_err.append((float(m.group(1)) / scale - truth[r.metric.key]) / U)
                        continue
                    printed_err.append((float(m.group(1)) / scale - truth[r.metric.key]) / U)
                    value_err.append((r.value.magnitude - truth[r.metric.key]) / U)
    assert len(printed_err) == 16 and len(kt_err) == 8
    # measured: ΔK printed +0.39, corrected +0.23; K_t printed +0.01
    assert np.mean(printed_err) > 0.25 and np.mean(value_err) < np.mean(printed_err) - 0.1
    assert abs(np.mean(kt_err)) < 0.15
    rec = run_items(
        pm,
        "jjf2014",
        ["7.2.4", "7.2.5"],
        station_options={"seed": 1, "device_class": "analog-fine", "duration_scale": 0.1},
    )
    kt = rec.outcomes[1].results[0]
    row = [r for r in kt.budget.rows if "largest of" in r.source]
    assert row and row[0].contribution.magnitude < 0.1 * kt.budget.combined.magnitude


def test_ratiometric_output_round_trip_and_refusal(pm, tmp_path):
    """A ratiometric (mV/V) output (docs/data-format.md "Ratiometric outputs"): in memory and after
    acquire → run the same K to 1e-12; the written file keeps mV/V; a mV/V column without a supply
    is a data error naming the column and where to give the supply."""
    from metro.core.base.units import is_voltage_ratio
    from metro.core.run.manifest_writer import write_campaign
    from metro.core.run.manifest import load_manifest

    assert is_voltage_ratio("mV/V") and is_voltage_ratio("V/V") and not is_voltage_ratio("mV")
    assert not is_voltage_ratio("mA/V") and not is_voltage_ratio("dimensionless")
    so = {"seed": 3, "device_class": "analog-ratiometric"}
    rec = run_items(pm, "jjf2014", ["7.2.1"], station_options=so)
    k_mem = rec.outcomes[0].results[0].value.magnitude
    seg = rec.campaign.segments[0]
    assert seg.recorded_columns()["output"][1] == "mV/V" and seg.columns()["output"][1] == "mV"
    assert {
        c["key"]: c["within_U"]
        for c in __import__("metro.core.cli.present", fromlist=["x"]).truth_checks(rec)
    }["K"]
    out = tmp_path / "camp"
    write_campaign(rec.campaign, out)
    text = next(out.glob("*.csv")).read_text()
    assert "[mV/V]" in text.splitlines()[1]
    camp = load_manifest(out / "manifest.toml", pm.reader_for)
    k_file = run_items(pm, "jjf2014", ["7.2.1"],
                       campaign=camp).outcomes[0].results[0].value.magnitude
    assert k_file == pytest.approx(k_mem, rel=1e-12)
    manifest = (out / "manifest.toml").read_text()
    (out / "manifest.toml").write_text("\n".join(ln for ln in manifest.splitlines()
                                                 if not ln.startswith((
                                                     "supply_voltage", "supply ="))))
    camp = load_manifest(out / "manifest.toml", pm.reader_for)
    with pytest.raises(DataError, match="ratiometric") as exc:
        run_items(pm, "jjf2014", ["7.2.1"], campaign=camp)
    assert exc.value.field == "output" and "supply_voltage" in exc.value.hint


def test_one_estimate_counts_its_degrees_of_freedom_once():
    """Two rows from one B_r estimate of six runs (ν = 5), the two members of a difference: with ν
    apportioned (interpretations.md, "JJF 2014 — one estimate, one ν") the budget's ν_eff is 5 and
    k = t(5) at 95.45 % = 2.65; counted twice it was ≈ 10 and k ≈ 2.28."""
    from metro.core.uncertainty.budget import BudgetRow, UncertaintyBudget
    from metro.core.base.units import Q_
    from metro.plugins.jjf2014 import budgets as B
    from metro.plugins.jjf2014.common import Spread, one_estimate

    rep = Spread(0.5, 5.0, "7.2.15 runs of this campaign", "A")
    rows = [rep.row("B₀ before", "B_r", 0.5, "deg/h"), rep.row("B₀ after", "B_r", 0.5, "deg/h"),
            BudgetRow.type_a("other", "u", Q_(1e-6, "deg/h"), 19)]
    twice = UncertaintyBudget("dB", "deg/h", rows, coverage=B.COVERAGE)
    once = UncertaintyBudget("dB", "deg/h", one_estimate(rows, rep), coverage=B.COVERAGE)
    assert twice.nu_eff == pytest.approx(10.0,
                                         rel=1e-3) and once.nu_eff == pytest.approx(5.0, rel=1e-3)
    assert once.k == pytest.approx(2.649, abs=0.01) and once.combined == twice.combined


def test_repeatability_of_a_negative_scale_factor_is_a_magnitude():
    """Eq. (10) K_r = s/|K̄|: a device whose output falls with the rate (K < 0) has the same K_r as
    its mirror image (docs/independent-campaigns.md: K_r < 0 on every negative-K device, 0 of 103
    within U)."""
    Ks = [20.0, 20.004, 19.997, 20.001, 19.999, 20.003]
    assert F.relative_repeatability_eq10([-k for k
                                          in Ks]) == pytest.approx(F.relative_repeatability_eq10(
                                              Ks), rel=1e-12)
    assert F.relative_repeatability_eq10([-k for k in Ks]) > 0


def test_bias_under_correlated_noise_takes_the_long_batches():
    """7.2.13 B₀ (eqs. (27), (28)) of a record whose noise is mostly a slow wander (a random walk of
    the output, as flicker does within one record): the 20 short batch means are alike and their
    scatter understates u(F̄); the F test takes 5 long batches (u several times larger, ν = 4), and
    says so in the budget. White noise alone keeps the 20 (docs/independent-campaigns.md: B₀ within
    U on 43–67 % of the flicker devices before)."""
    from metro.plugins.jjf2014.bias import BiasValue

    rng = np.random.default_rng(2014)
    n = 36000
    white = rng.normal(0.0, 1.0, n)
    walk = 0.05 * np.cumsum(rng.normal(0.0, 1.0, n))
    K = -20.0  # mV/((°)/s); either sign
    bw = BiasValue(_seg("static", "static", {"orientation": "IRA up"}, white, "mV", 0.1), K)
    bc = BiasValue(_seg("static", "static", {"orientation": "IRA up"}, white + walk, "mV", 0.1), K)
    assert not bw.correlated and bw.dof == 19
    assert bc.correlated and bc.dof == 4
    short = float(np.std((white + walk).reshape(20, -1).mean(axis=1), ddof=1)
                  / math.sqrt(20)) / abs(K) * 3600.0
    assert bc.uA > 2.0 * short  # the 20 batch means would have said this


def test_static_record_is_another_power_on_its_k_in_the_b0_budget(pm):
    """interpretations.md "7.2.13 — the static record is another power-on": B₀ = F̄/K divides the
    static record by the K of the 7.2.1 calibration, another power-on; its own K differs by K_r, so
    without a bias repeatability (7.2.15, whose runs hold that variation) the budget carries
    |B₀|·K_r, one estimate with u₃ = K_r·K of u(K) (ν = (Q − 1)/3, so that Welch–Satterthwaite
    counts it once). On the independent harness's 1 Hz white-noise devices (|B| to 360 °/h, K
    power-on σ to 4×10⁻⁴) B₀ was within U on 90.7 % / 84.6 % of the devices where |B|·σ_K is 0.5–1 /
    > 1 times the record's noise (docs/independent-campaigns.md)."""
    so = {"seed": 1, "device_class": "analog-power-on", "duration_scale": 0.1}
    rec = run_items(pm, "jjf2014", ["7.2.1", "7.2.4", "7.2.13"], station_options=so)
    r = {x.metric.key: x for o in rec.outcomes for x in o.results}
    b0, kr = r["B0"], r["Kr"].value.magnitude
    row = [x for x in b0.budget.rows if x.symbol == "K_r·B·c"]
    assert len(row) == 1 and "K_r" in row[0].source
    assert row[0].contribution.to("deg/h").magnitude == pytest.approx(
        abs(b0.value.magnitude) * kr, rel=1e-9)
    assert row[0].dof == pytest.approx(5 / 3)
    # with 7.2.15's runs in the campaign B_r holds it: no second row
    rec = run_items(pm, "jjf2014", ["7.2.1", "7.2.4", "7.2.13", "7.2.15"], station_options=so)
    b0 = next(x for o in rec.outcomes for x in o.results if x.metric.key == "B0")
    assert not [x for x in b0.budget.rows if x.symbol
                == "K_r·B·c"] and [x for x in b0.budget.rows if x.symbol == "B_r"]
    # neither K_r nor B_r: no row, and the budget says what is missing
    rec = run_items(pm, "jjf2014", ["7.2.1", "7.2.13"], station_options=so)
    b0 = next(x for o in rec.outcomes for x in o.results if x.metric.key == "B0")
    assert not [x for x in b0.budget.rows if x.symbol == "K_r·B·c"]
    assert "variation of K between power-ons is not in this budget" in b0.budget.note


def test_threshold_level_counts_only_where_its_response_is_resolved_from_noise():
    """interpretations.md "7.2.9 / 7.2.10 — a level decided by noise" (issue 13 item 3): d_i = |F̂_i
    − F_i| − 50 %·|F̂_i|; the candidate's pass and the next level's fail count where |d| ≥ 2u, else
    the interval widens to the resolved levels; none resolved: None. Hand-worked, K = 20 mV/((°)/s):
    at 0.01 °/s F̂ = 0.2 mV and F = 0.11 (45 %: d = −0.01), at 0.007 F̂ = 0.14, F = 0.067 (52 %: d =
    +0.0028)."""
    om = [0.1, 0.05, 0.02, 0.01, 0.007, 0.005]
    F_ = [2.0, 0.99, 0.38, 0.11, 0.067, 0.02]
    assert F.threshold_eq16_17(om, F_, 20.0) == (0.01, 3)
    # both decisions resolved
    assert F.resolved_bracket(om, F_, 20.0, [1e-4] * 6) == (3, 4, 3)
    # 0.007's fail is not: (0.005, 0.01]
    assert F.resolved_bracket(om, F_, 20.0, [0.002] * 6) == (3, 5, 3)
    # nor 0.01's pass: (0.005, 0.02]
    assert F.resolved_bracket(om, F_, 20.0, [0.006] * 6) == (2, 5, 3)
    assert F.resolved_bracket(om, F_, 20.0, [5.0] * 6) is None                # no pass is resolved
    # the between-record scatter from the ±pairs: an odd response cancels, the drift between records
    # does not
    from metro.plugins.jjf2014.low_rate import pair_scatter

    o = np.array(om)
    s, n = pair_scatter({"forward": (o, np.array(F_)),
                         "reverse": (-o, -np.array(F_) + np.array([0.01, -0.01] * 3))})
    assert n == 6 and s == pytest.approx(0.01 / math.sqrt(2), rel=1e-12)

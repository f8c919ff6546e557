"""JJF 2014—2022: appendix B digits, hand-worked formulas, the simulated station's truth, bad input."""

from __future__ import annotations

import math

import numpy as np
import pytest
from metro.core.errors import DataError, MetroError, ProcedureError
from metro.core.model import Calibration, Campaign, DeviceUnderTest, Segment
from metro.core.runner import merge_steps, run_items
from metro.core.units import Q_
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
    b = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4), dmm=_cal(6e-5))
    assert b.contributions() == pytest.approx([0.5e-4, 3e-5, 1.54e-4], rel=1e-12)
    assert b.combined.magnitude == pytest.approx(math.sqrt(0.5e-4**2 + 3e-5**2 + 1.54e-4**2), rel=1e-12)
    assert F.appendix_b_presentation(b.combined.magnitude, b.k) == ("1.65×10^-4", "3.3×10^-4")
    # JJF 1059.1 two-digit rounding of U gives the same 3.3e-4
    assert b.expanded_reported().text == "0.00033"


def test_appendix_b2_bias_budget_digits():
    """B.2: DMM 6e-5 (k=2) and the scale factor's 1.65e-4 → 1.68e-4, 3.36e-4 (U = k × rounded u_c)."""
    b = B.bias_budget(Q_(1.0, ""), 1.65e-4, dmm=_cal(6e-5))
    assert b.combined.magnitude == pytest.approx(math.hypot(3e-5, 1.65e-4), rel=1e-12)
    assert F.appendix_b_presentation(b.combined.magnitude, b.k) == ("1.68×10^-4", "3.36×10^-4")
    # metro's certificates round U by JJF 1059.1 (two digits of k·u_c = 3.354e-4): 3.4e-4
    assert b.expanded_reported().text == "0.00034"


def test_appendix_presentation_chain_from_b1_to_b2():
    b1 = B.scale_factor_budget(Q_(1.0, ""), Q_(1.54e-4, ""), math.inf, rate_table=_cal(1e-4), dmm=_cal(6e-5))
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
    bs, m = F.bias_stability_eq29([1, 3, 1, 3, 5, 7, 5, 7, 9], 2.0, 2)  # last incomplete block dropped
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
    assert c["K"] == pytest.approx(math.sqrt(0.06), rel=1e-6) and c["R"] == pytest.approx(math.sqrt(0.2), rel=1e-6)
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
    0.5 u on average over 40 records, the non-negative variant biased low (why it is not the default)."""
    from metro.core import allan

    rng = np.random.default_rng(1)
    z, znn = [], []
    for _ in range(40):
        y = rng.normal(0, 1, 18000)  # σ²(τ) = 0.1 s/τ, τ₀ = 0.1 s
        ad = allan.oadev(y, 0.1, allan.octave_m(y.size))
        t, s, e = np.asarray(ad.tau) / 3600, np.asarray(ad.deviation), np.asarray(ad.edf)
        f = F.fit_allan_eq38(t, s, e)
        g = F.fit_allan_eq38(t, s, e, nonnegative=True)
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
    # exact first-order data: a = 1, b = 1/f_c², and K = 0.707 (literal) at f_c·√(1/0.707² − 1) = 1.00042·f_c
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
    from metro.core.runner import split_options

    per = split_options(procs, dict(options or {}))
    return st.acquire(merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)]))


@pytest.fixture(scope="module")
def full_run():
    from metro.core.plugins import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    camp = _campaign(pm, ALL, options=OPTS)
    rec = run_items(pm, "jjf2014", ALL, campaign=camp, options=OPTS)
    return camp, {o.item: o for o in rec.outcomes}, rec


def _within(r, expected, factor=1.0):
    v = r.value.to(r.metric.unit).magnitude
    e = expected.to(r.metric.unit).magnitude
    assert abs(v - e) <= factor * r.U.magnitude, f"{r.metric.key}: {v} vs {e} ± {r.U}"


@pytest.mark.parametrize("key", ["K", "F0", "Kn", "range", "Ka", "Kr", "Kt", "Kg", "dK_shock", "dK_vib", "gamma",
                                 "gamma_r", "B0", "Br", "Bt", "Bg", "dB_shock", "dB_vib", "ARW", "Bw", "Td"])
def test_simulated_truth_within_U(full_run, key):
    camp, outs, _ = full_run
    r = next(r for o in outs.values() for r in o.results if r.metric.key == key)
    assert key in camp.expected
    _within(r, camp.expected[key])


def test_simulated_threshold_resolution_stability_startup(full_run):
    camp, outs, _ = full_run
    t = VibratoryTruth()
    # threshold: gain Ω²/(Ω²+Ω_th²) ≥ 0.5 first fails at 0.007 °/s, so the last passing level is 0.01
    assert outs["7.2.9"].result("threshold").value.magnitude == pytest.approx(0.01)
    assert outs["7.2.10"].result("resolution").value.magnitude == pytest.approx(0.005)
    assert camp.expected["threshold"].magnitude == pytest.approx(0.01)
    assert camp.expected["resolution"].magnitude == pytest.approx(0.005)
    # white noise: B_s(P) = N/√P
    _within(outs["7.2.14"].result("Bs"), Q_(t.arw_deg_rt_h / math.sqrt(10 / 3600), "deg/h"))
    # start-up: the slowest trial is 0.01·FS with 1 % → 0.01 °/s: t = τ·ln(d₀/0.01)
    _within(outs["7.2.23"].result("t_startup"), Q_(t.startup_tau_s * math.log(t.startup_excursion_dps / 0.01), "s"))


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
    on = run_items(pm, "jjf2014", ["7.2.13"], campaign=camp, options={"earth_rate": "on"}).outcomes[0].result("B0")
    s = math.sin(math.radians(LAT))
    _within(off, Q_(truth.bias_dps * 3600 + EARTH_RATE_DEG_PER_H * s, "deg/h"))
    _within(on, Q_(truth.bias_dps * 3600 + (EARTH_RATE_DEG_PER_H - 15.041) * s, "deg/h"))
    assert off.value.magnitude - on.value.magnitude == pytest.approx(15.041 * s, rel=1e-12)


def test_bias_acceleration_earth_rate_leak_and_correction(pm):
    truth = VibratoryTruth(seed=8, bias_accel_dps_per_g=(0.0, 0.0, 0.0))
    camp = _campaign(pm, ["7.2.17"], truth=truth, scale=0.5)
    off = run_items(pm, "jjf2014", ["7.2.17"], campaign=camp).outcomes[0].result("Bg")
    on = run_items(pm, "jjf2014", ["7.2.17"], campaign=camp, options={"earth_rate": "on"}).outcomes[0].result("Bg")
    # no true g-sensitivity: uncorrected, the flipped vertical earth rate leaks in as Ω_e·sin φ per g
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
    truth = VibratoryTruth(seed=21, arw_deg_rt_h=0.05, quantization_arcsec=2.0, rate_ramp_deg_h2=400.0)
    camp = _campaign(pm, ["7.2.20"], truth=truth, options={})
    o = run_items(pm, "jjf2014", ["7.2.20"], campaign=camp).outcomes[0]
    _within(o.result("ARW"), Q_(0.05, "deg/hour**0.5"), 1.5)
    _within(o.result("Q"), Q_(2.0, "arcsec"), 1.5)
    _within(o.result("RR"), Q_(400.0, "deg/h**2"), 1.5)


def test_sf_plot_and_24_rows_order(full_run):
    _, outs, _ = full_run
    p = outs["7.2.1"].plots[0]
    assert p.series[0]["x"] == sorted(p.series[0]["x"]) and len(p.series) == 3


# ------------------------------------------------------------------------------ bad input


def _camp(segs, props=None):
    dev = DeviceUnderTest("D", properties=props or {})
    return Campaign("C", dev, [], {}, {"latitude": Q_(40, "deg")}, segs, source="test.toml")


def _seg(id, kind, cond, data, unit="mV", interval=1.0):
    return Segment(id, kind, cond, Q_(interval, "s"), sha256="0" * 64, loader=lambda: {"output": (np.asarray(data, float), unit)})


def test_bias_without_scale_factor_is_a_data_error(pm):
    camp = _camp([_seg("s", "static", {"orientation": "IRA up"}, np.ones(100))])
    with pytest.raises(DataError, match="scale factor"):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_bias_with_device_scale_factor(pm):
    camp = _camp([_seg("s", "static", {"orientation": "IRA up"}, np.r_[np.full(50, 1.0), np.full(50, 3.0)])],
                 {"scale_factor": Q_(20, "mV/(deg/s)")})
    r = run_items(pm, "jjf2014", ["7.2.13"], campaign=camp).outcomes[0].result("B0")
    assert r.value.magnitude == pytest.approx(2.0 / 20 * 3600)


def test_nan_sample_named(pm):
    data = np.r_[np.ones(40), np.nan, np.ones(59)]
    camp = _camp([_seg("s", "static", {}, data)], {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(DataError, match="sample 41"):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_wrong_unit_refused(pm):
    camp = _camp([_seg("s", "static", {}, np.ones(100), unit="deg/h")], {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(MetroError):
        run_items(pm, "jjf2014", ["7.2.13"], campaign=camp)


def test_misalignment_repeatability_needs_seven_runs(pm):
    camp = _campaign(pm, ["7.2.12"], options={"runs": 3})
    with pytest.raises(DataError, match="Q ≥ 7"):
        run_items(pm, "jjf2014", ["7.2.12"], campaign=camp)


def test_threshold_needs_zero_input(pm):
    camp = _campaign(pm, ["7.2.9"])
    segs = [s for s in camp.segments if s.id != "threshold-0"]
    bad = Campaign("C", camp.device, camp.equipment, {}, camp.site, segs, source="x")
    with pytest.raises(DataError, match="zero-input"):
        run_items(pm, "jjf2014", ["7.2.9"], campaign=bad)


def test_allan_constant_data_refused(pm):
    camp = _camp([_seg("s", "static", {}, np.full(3600, 2.0))], {"scale_factor": Q_(20, "mV/(deg/s)")})
    with pytest.raises(ProcedureError, match="positive"):
        run_items(pm, "jjf2014", ["7.2.20"], campaign=camp)


def test_scale_factor_too_few_rates(pm):
    camp = _camp([_seg("a", "rate", {"rate": "1 deg/s"}, np.ones(10)), _seg("b", "rate", {"rate": "2 deg/s"}, np.ones(10))])
    with pytest.raises(DataError, match="at least 3"):
        run_items(pm, "jjf2014", ["7.2.1"], campaign=camp)


def test_bandwidth_needs_frequencies(pm):
    camp = _campaign(pm, ["7.2.21"], options={"frequencies": 2, "records": 2, "sample_rate": "1000 Hz"})
    with pytest.raises(DataError, match="at least 3 frequencies"):
        run_items(pm, "jjf2014", ["7.2.21"], campaign=camp, options={"frequencies": 2})


def test_temperature_needs_room_point(pm):
    camp = _campaign(pm, ["7.2.5"], options={"temperatures": "-40, 60"})
    with pytest.raises(DataError, match="room temperature"):
        run_items(pm, "jjf2014", ["7.2.5"], campaign=camp)


def test_startup_never_settles(pm):
    camp = _campaign(pm, ["7.2.23"], truth=VibratoryTruth(startup_tau_s=200.0))
    with pytest.raises(ProcedureError, match="still outside"):
        run_items(pm, "jjf2014", ["7.2.23"], campaign=camp)


def test_procedure_classes_are_registered(pm):
    from metro.plugins.jjf2014.procedures import (
        AngleRandomWalk,
        Asymmetry,
        Bandwidth,
        Bias,
        BiasAcceleration,
        BiasRepeatability,
        BiasShock,
        BiasStability,
        BiasTemperature,
        BiasVibration,
        Misalignment,
        MisalignmentRepeatability,
        NonlinearityRange,
        OutputDelay,
        Repeatability,
        Resolution,
        ScaleFactor,
        SFAxialAcceleration,
        SFShock,
        SFTemperature,
        SFVibration,
        StartupTime,
        Threshold,
    )

    classes = (ScaleFactor, NonlinearityRange, Asymmetry, Repeatability, SFTemperature, SFAxialAcceleration, SFShock,
               SFVibration, Threshold, Resolution, Misalignment, MisalignmentRepeatability, Bias, BiasStability,
               BiasRepeatability, BiasTemperature, BiasAcceleration, BiasShock, BiasVibration, AngleRandomWalk,
               Bandwidth, OutputDelay, StartupTime)
    for cls in classes:
        assert pm.procedure("jjf2014", cls.item) is cls
        assert cls.station == "simulated-jjf2014"
    assert [c.item for c in classes] == [f"7.2.{i}" for i in range(1, 24)]


def test_station_is_registered(pm):
    st = pm.station("simulated-jjf2014").factory(seed=3)
    assert st.truth.seed == 3

"""GB/T 45570—2025 D.1.1–D.1.6, angle method: hand-worked formulas and simulated truth."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from metro.core.base.errors import DataError, UnitError
from metro.core.stats.lsq import fit_line
from metro.core.run.runner import run_items
from metro.core.base.units import Q_
from metro.instruments.simulated import GyroTruth, SimulatedStation
from metro.plugins.gbt45570 import formulas as F
from metro.plugins.gbt45570.angle_method import AsymmetryD13, NonlinearityD12, ScaleFactorD11
from metro.plugins.gbt45570.revolutions import rate_points


def test_d1_d2_hand_worked():
    assert F.mean_counts_d1([1036896, 1036898]) == 1036897
    # K = 0.8 P/″: +360° gives 1 036 800 P, −360° gives −1 036 800 P
    assert F.scale_factor_d2(1_036_800.0, -1_036_800.0) == pytest.approx(0.8, rel=1e-15)


def test_d3_fixed_angle_hand_worked():
    # 90° each way at K = 0.8 P/″: N' = ±259 200 P
    assert F.scale_factor_d3(259_200.0, -259_200.0, 90.0, -90.0) == pytest.approx(0.8, rel=1e-15)


@settings(max_examples=30, deadline=None)
@given(st.lists(st.floats(0.5, 500.0), min_size=3, max_size=14, unique=True),
       st.floats(0.2, 2.0), st.floats(-1e-8, 1e-8))
def test_d5_d6_closed_forms_equal_the_qr_least_squares(rates, K, W):
    rates = np.array(rates)
    Ki = K + W * rates + 1e-9 * np.sin(rates)
    k, w = F.scale_factor_fit_d5_d6(Ki, rates)
    fit = fit_line(rates, Ki)
    assert k == pytest.approx(fit.coef[0], rel=1e-9)
    assert w == pytest.approx(fit.coef[1], rel=1e-6, abs=1e-15)


def test_d7_hand_worked():
    kn, i = F.nonlinearity_d7([0.800001, 0.799998, 0.8000004], 0.8)
    assert kn == pytest.approx(2.5e-6, rel=1e-9) and i == 1


def test_d8_d9_d10_hand_worked():
    # N0 = 10 P/s over t = 12 s removes 120 P from each direction's count
    kp = F.scale_factor_plus_d8(1_036_800.0 + 120.0 + 4.0, 10.0, 12.0)
    km = F.scale_factor_minus_d9(-1_036_800.0 + 120.0, 10.0, 12.0)
    assert km == pytest.approx(0.8, rel=1e-15)
    assert F.asymmetry_d10(kp, km) == pytest.approx((4 / 1_296_000) / ((kp + km) / 2), rel=1e-12)


def test_r5_rate_points_include_the_maximum():
    pts = rate_points(400.0)
    assert len(pts) >= 11 and pts[-1] == 400.0 and pts[0] == 1.0
    assert rate_points(300.0)[-1] == 300.0


def _camp(pm, items, seed=9, drop=None, edit=None):
    st_ = SimulatedStation(truth=GyroTruth(seed=seed))
    from metro.core.run.runner import merge_steps

    steps = merge_steps([pm.procedure("gbt45570", i)().sequence({}) for i in items])
    if drop:
        steps = [s for s in steps if s.segment not in drop]
    return st_.acquire(steps)


def test_angle_method_recovers_simulated_truth(pm):
    assert pm.procedure("gbt45570", "D.1.1") is ScaleFactorD11
    assert pm.procedure("gbt45570", "D.1.2") is NonlinearityD12
    assert pm.procedure("gbt45570", "D.1.3") is AsymmetryD13
    camp = _camp(pm, ["D.1.1", "D.1.2", "D.1.3"])
    rec = run_items(pm, "gbt45570", ["D.1.1", "D.1.2", "D.1.3"], campaign=camp)
    checked = 0
    for o in rec.outcomes:
        for r in o.results:
            if r.metric.key in camp.expected and r.U is not None:
                exp = camp.expected[r.metric.key].to(r.metric.unit).magnitude
                assert abs(r.value.to(r.metric.unit).magnitude - exp) <= r.U.magnitude, r.metric.key
                checked += 1
    assert checked == 3
    # a non-trivial device: the nonlinearity and asymmetry are resolved (not zero)
    assert rec.outcomes[1].result("Kn").value.to("ppm").magnitude > 1.0


def test_fewer_than_eleven_rate_points(pm):
    camp = _camp(pm, ["D.1.1"], drop={"rate+1", "rate-1", "rate+1.6", "rate-1.6", "rate+2.5",
                                      "rate-2.5",
                                      "rate+4", "rate-4"})
    with pytest.raises(DataError, match="at least 11 rate points"):
        run_items(pm, "gbt45570", ["D.1.1"], campaign=camp)


def test_missing_direction(pm):
    camp = _camp(pm, ["D.1.1"], drop={"rate-25"})
    with pytest.raises(DataError, match="clockwise"):
        run_items(pm, "gbt45570", ["D.1.1"], campaign=camp)


def test_asymmetry_needs_zero_rate_count(pm):
    camp = _camp(pm, ["D.1.3"], drop={"zero-start", "zero-end"})
    with pytest.raises(DataError, match="static-zero"):
        run_items(pm, "gbt45570", ["D.1.3"], campaign=camp)


# ---------------------------------------------------------------------------- D.1.4–D.1.6


def test_d11_on_seven_d2_scale_factors_hand_worked():
    from metro.plugins.gbt45570 import formulas_rate as F2

    # seven runs at 30 °/s: K_j from D.2, then D.11
    n = [(1_036_800.0 + d, -1_036_800.0 - d) for d in (0.0, 1.0, -1.0, 2.0, 0.0, -2.0, 0.0)]
    k = [F.scale_factor_d2(p, m) for p, m in n]
    expect = np.std(k, ddof=1) / np.mean(k)
    assert F2.scale_factor_repeatability_d11(k) == pytest.approx(expect, rel=1e-12)
    assert F2.scale_factor_repeatability_d11(k) == pytest.approx(math.sqrt(10 / 6) / 1_036_800.0,
                                                                 rel=1e-9)


def test_d14_reversed_mounting_cancels_a_fixture_error_exactly():
    from metro.plugins.gbt45570 import formulas_rate as F2

    K, rev = 0.8, 1_296_000.0
    alpha, eps = math.radians(40 / 3600), math.radians(90 / 3600)
    # N₊ − N₋ = 2·K·360·3600·sin(±α + ε)
    a1 = F2.misalignment_d14(K * rev * math.sin(alpha + eps), -K * rev * math.sin(alpha + eps), K)
    a2 = F2.misalignment_d14(K * rev * math.sin(-alpha + eps), -K * rev * math.sin(-alpha + eps), K)
    got = F2.misalignment_half_difference_d15(a1, a2)
    assert got * 3600 == pytest.approx(40.0 * math.cos(eps), rel=1e-6)


def test_d14_d15_d16_recover_simulated_truth(pm):
    from metro.plugins.gbt45570.angle_method import (InputAxisMisalignmentD16,
                                                     ScaleFactorRepeatabilityD14,
                                                     ScaleFactorTemperatureSensitivityD15)

    assert pm.procedure("gbt45570", "D.1.4") is ScaleFactorRepeatabilityD14
    assert pm.procedure("gbt45570", "D.1.5") is ScaleFactorTemperatureSensitivityD15
    assert pm.procedure("gbt45570", "D.1.6") is InputAxisMisalignmentD16
    items = ["D.1.4", "D.1.5", "D.1.6"]
    st_ = SimulatedStation(truth=GyroTruth(seed=11, sf_turn_on_sigma=1e-5, sf_tc_per_C=4e-7,
                                           misalign_alpha_arcsec=-55.0, misalign_beta_arcsec=35.0,
                                           fixture_tilt_arcsec=(300.0, 200.0)))
    from metro.core.run.runner import merge_steps

    camp = st_.acquire(merge_steps([pm.procedure("gbt45570", i)().sequence({}) for i in items]))
    rec = run_items(pm, "gbt45570", items, campaign=camp)
    checked = set()
    for o in rec.outcomes:
        for r in o.results:
            assert any(row.type == "A" for row
                       in r.budget.rows) and any(row.type == "B" for row in r.budget.rows)
            exp = camp.expected[r.metric.key].to(r.metric.unit).magnitude
            assert abs(r.value.to(r.metric.unit).magnitude - exp) <= r.U.magnitude, r.metric.key
            checked.add(r.metric.key)
    assert checked == {"Kr", "Kt", "alpha", "beta", "gamma"}
    o = rec.outcomes[2]
    # the truth itself: the 300″/200″ fixture errors cancel in D.15
    alpha, beta = o.result("alpha"), o.result("beta")
    assert alpha.value.to("arcsec").magnitude == pytest.approx(
        -55.0, abs=alpha.U.to("arcsec").magnitude)
    assert beta.value.to("arcsec").magnitude == pytest.approx(
        35.0, abs=beta.U.to("arcsec").magnitude)
    # K_t: the simulator's truth is D.12 on the noise-free K(T) = K·(1 + 4×10⁻⁷·(T − 20)), exactly
    # 0.4 ppm/°C; each temperature point is a power-on of its own (D.1.5.2 c)), so the measured K_t
    # is off by the turn-on draws (σ 10 ppm over ΔT = 40 … 60 °C) and U holds D.1.4's K_r for them
    kt = rec.outcomes[1].result("Kt")
    assert camp.expected["Kt"].to("ppm/delta_degC").magnitude == pytest.approx(0.4, rel=1e-9)
    assert abs(kt.value.to("ppm/delta_degC").magnitude - 0.4) <= kt.U.to("ppm/delta_degC").magnitude
    kr = rec.outcomes[0].result("Kr").value.to("ppm").magnitude
    (row,) = [r for r in kt.budget.rows if r.symbol == "s(max_i |ΔK_i/(K₀₀ΔT_i)|)"]
    s_on = float(str(row.note).split("turn-on scatter of K, ")[1].split(" ppm")[0])
    # D.1.4's K_r of this campaign taken whole (own part 0), as the posterior mean of the turn-on
    # variance given its Q − 1 = 6 degrees of freedom: (Q − 1)/(Q − 3)·K_r² (interpretations.md "σ_K
    # — …"), to 3 digits
    assert s_on == pytest.approx(kr * math.sqrt(6 / 4), rel=2e-3)


def test_simulated_d15_temperature_points_are_power_ons():
    """D.1.5.2 c): the gyro is off while the chamber changes temperature, so the simulated station
    gives every D.1.5 point a turn-on draw of K of its own (``temperature_power_on``): with no
    noise, K_i of each point's sweep is K(T)·(1 + δ_T), not K(T). (Before, the sweep ran in one
    power-on.)"""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import merge_steps
    from metro.instruments.sim_gbt_rate import scale_factor_multiplier, temperature_power_on

    truth = GyroTruth(seed=5, sf_turn_on_sigma=2e-5, arw_deg_rt_h=1e-9,
                      scale_factor_P_per_arcsec=50.0)
    steps = get_plugin_manager(autoload=False).procedure("gbt45570",
                                                         "D.1.5")().sequence({
                                                             "max_rate": "100 °/s"})
    camp = SimulatedStation(truth=truth).acquire(merge_steps([steps]))
    segs = {s.id: s for s in camp.segments}
    deltas = []
    for i, T in enumerate(("-40 °C", "20 °C", "60 °C"), start=1):
        n_p, n_m = (float(np.mean(segs[f"T{i}-rate{d}100"].series("count", "P").data.magnitude))
                    for d in "+-")
        k_meas = F.scale_factor_d2(n_p, n_m)
        k_plus = (
            truth.scale_factor_P_per_arcsec
            * scale_factor_multiplier(truth, 100.0, 1, {"temperature": T})
        )
        k_minus = (
            truth.scale_factor_P_per_arcsec
            * scale_factor_multiplier(truth, 100.0, -1, {"temperature": T})
        )
        dk, _ = temperature_power_on(truth, {"temperature": T})
        # the noise-free D.2 with the power-on's K; rounding of 50 P/″ counts: ≤ 1 P in 6.5×10⁷
        assert k_meas == pytest.approx((k_plus + k_minus) / 2 * (1 + dk), rel=3e-8)
        deltas.append(dk)
    assert len(set(deltas)) == 3 and max(abs(d) for d in deltas) > 5e-6


def test_d14_six_repeats_instead_of_seven(pm):
    camp = _camp(pm, ["D.1.4"], drop={"run7-rate+30", "run7-rate-30"})
    with pytest.raises(DataError, match=r"D.1.4 needs 7 power-ons.*found 6 run"):
        run_items(pm, "gbt45570", ["D.1.4"], campaign=camp)


def test_d14_missing_direction_names_the_run(pm):
    camp = _camp(pm, ["D.1.4"], drop={"run3-rate-30"})
    with pytest.raises(DataError, match=r"in run 3 has no clockwise") as e:
        run_items(pm, "gbt45570", ["D.1.4"], campaign=camp)
    assert e.value.field == "segments.run3-rate+30"


def test_d15_temperatures_without_room_temperature(pm):
    from metro.core.run.runner import merge_steps

    st_ = SimulatedStation(truth=GyroTruth(seed=3))
    steps = pm.procedure("gbt45570", "D.1.5")().sequence({"temperatures": "-40 °C, 0 °C, 60 °C"})
    camp = st_.acquire(merge_steps([steps]))
    with pytest.raises(DataError, match="no point at room temperature: the nearest is 0 °C"):
        run_items(pm, "gbt45570", ["D.1.5"], campaign=camp)


def test_d15_needs_three_temperature_points(pm):
    camp = _camp(pm, ["D.1.5"], drop={s.segment for s
                                      in pm.procedure("gbt45570", "D.1.5")().sequence({})
                                      if s.segment.startswith("T3-")})
    with pytest.raises(DataError, match="at least 3 temperature points"):
        run_items(pm, "gbt45570", ["D.1.5"], campaign=camp)


def test_d16_missing_mounting(pm):
    camp = _camp(pm, ["D.1.6"], drop={"XRA-180-rate+30", "XRA-180-rate-30"})
    with pytest.raises(DataError, match=r"four mountings.*missing: XRA up, turned 180°"):
        run_items(pm, "gbt45570", ["D.1.6"], campaign=camp)


def test_d16_needs_the_device_scale_factor(pm):
    import attrs

    camp = _camp(pm, ["D.1.6"])
    camp = attrs.evolve(camp, device=attrs.evolve(camp.device, properties={}))
    with pytest.raises(DataError, match="divides by the scale factor") as e:
        run_items(pm, "gbt45570", ["D.1.6"], campaign=camp)
    assert e.value.field == "device.scale_factor"
    # a K in the rate method's unit is not silently used by the angle method
    camp = attrs.evolve(camp, device=attrs.evolve(camp.device,
                                                  properties={"scale_factor": Q_(
                                                      100.0, "LSB/(deg/s)")}))
    with pytest.raises(UnitError, match="scale_factor") as e:
        run_items(pm, "gbt45570", ["D.1.6"], campaign=camp)
    assert "LSB" in str(e.value)


def test_d14_warns_when_the_runs_are_not_at_the_stated_rate(pm):
    from metro.core.run.runner import merge_steps

    st_ = SimulatedStation(truth=GyroTruth(seed=5))
    camp = st_.acquire(merge_steps([pm.procedure("gbt45570",
                                                 "D.1.4")().sequence({"rate": "60 °/s"})]))
    o = run_items(pm, "gbt45570", ["D.1.4"], campaign=camp).outcomes[0]
    assert any("repeats the test at 30 °/s" in w for w in o.warnings)
    o = run_items(pm, "gbt45570", ["D.1.4"], campaign=camp, options={"rate": "60 °/s"}).outcomes[0]
    assert not o.warnings


def test_d13_sensitivity_to_n0_hand_worked():
    """∂K_a/∂N̄₀ (issue 13): rates 10, 20, 30 °/s, t = 36, 18, 12 s: the line through (r, t) has
    slope −240/200 = −1.2 s/(°/s) and intercept 22 + 1.2·20 = 46 s, so ∂K₊/∂N̄₀ = −46/R and
    ∂K₋/∂N̄₀ = +46/R (R = 1 296 000″); at K₊ = K₋ = 0.8 P/″: |∂K_a/∂N̄₀| = 92/(R·0.8) s/P."""
    R = 1_296_000.0
    rates, t = [10.0, 20.0, 30.0], [36.0, 18.0, 12.0]
    assert F.asymmetry_sensitivity_n0(rates, t, t, 0.8,
                                      0.8) == pytest.approx(92 / (R * 0.8), rel=1e-9)
    # away from the kink, with t₋ = t₊ + 1 s (intercept 47 s): D′ = −93/R, M′ = +0.5/R,
    # D = 4.8×10⁻⁶ → ∂K_a/∂N̄₀ = −93/(R·M) − D·0.5/(R·M²)
    kp, km = 0.8 + 4.8e-6, 0.8
    M = (kp + km) / 2
    want = abs(-93 / (R * M) - 4.8e-6 * 0.5 / (R * M * M))
    assert F.asymmetry_sensitivity_n0(rates, t, [37.0, 19.0, 13.0], kp,
                                      km) == pytest.approx(want, rel=1e-9)


def test_d13_u_ka_at_the_kink(pm):
    """A gyro with K₊ = K₋ exactly: a central difference through |K₊ − K₋| gave ∂K_a/∂N̄₀ = 0 there
    (U(K_a) without its N̄₀ row); the analytic slope gives U = k·|D′|/M·u(N̄₀) (hand-worked)."""
    from metro.core.model.campaign import Campaign, DeviceUnderTest, Segment

    R, K, N0 = 1_296_000.0, 0.8, 7.7
    rates = [1.0, 2.0, 5.0, 10.0, 20.0, 50.0, 100.0, 150.0, 200.0, 300.0, 400.0]
    segs = []
    for r in rates:
        t = 360.0 / r
        for d in (1, -1):
            c = np.full(5, d * K * R + N0 * t)
            segs.append(Segment(f"rev{d:+d}-{r:g}", "rate-revolutions",
                                {"rate": f"{d * r:g} deg/s", "turns": "5"},
                                Q_(t, "s"), sha256="0" * 64,
                                loader=lambda c=c, t=t: {"count": (c, "P"),
                                                         "duration": (np.full(5, t), "s")}))
    zero = N0 + np.tile([0.5, -0.5], 150)  # u(N̄₀) = s/√n, s = 0.5·√(300/299)
    segs.append(Segment("zero", "static-zero", {}, Q_(1, "s"), sha256="0" * 64,
                        loader=lambda: {"output": (zero, "P")}))
    st = SimulatedStation()
    dev = DeviceUnderTest("D", properties={"scale_factor": Q_(K, "P/arcsec")}, output="pulse")
    camp = Campaign("C", dev, st.equipment(), {}, {"latitude": Q_(40, "deg")}, segs)
    res = run_items(pm, "gbt45570", ["D.1.3"], campaign=camp).outcomes[0].results[0]
    # independent least-squares intercept of t = 360/r against r
    r, t = np.array(rates), 360.0 / np.array(rates)
    slope = np.sum((r - r.mean()) * (t - t.mean())) / np.sum((r - r.mean()) ** 2)
    icpt = t.mean() - slope * r.mean()
    c = 2 * icpt / (R * K)
    u_n0 = 0.5 * math.sqrt(300 / 299) / math.sqrt(300)
    row = next(row for row in res.budget.rows if "N̄_0" in row.source)
    assert row.sensitivity.to("s/P").magnitude == pytest.approx(c, rel=1e-6)
    assert res.budget.combined.to("").magnitude == pytest.approx(c * u_n0, rel=1e-3)

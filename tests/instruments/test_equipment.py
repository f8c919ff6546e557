"""Evidence that the simulators and the equipment models produce what they state."""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from metro.core.stats import allan
from metro.core.base.errors import DataError, UnitError
from metro.core.base.units import Q_
from metro.instruments import equipment as E
from metro.instruments import kits
from metro.instruments.simulated import EARTH_RATE_DEG_PER_H, GyroTruth, simulate_static

FAST = settings(max_examples=40, deadline=None)


# ------------------------------------------------------------------------------ the virtual gyro


def test_arw_only_noise_has_allan_deviation_n_over_root_tau():
    """White rate noise of ARW N (°/√h) must give σ(τ) = N/√τ (τ in h) at every τ."""
    N = 0.02
    truth = GyroTruth(output="rate", bias_deg_h=0.0, arw_deg_rt_h=N, gm_sigma_deg_h=0.0,
                      rrw_deg_h_rt_h=0.0,
                      seed=11)
    tau0 = 0.1
    y = simulate_static(truth, n=400_000, interval_s=tau0, latitude_deg=0.0)
    res = allan.oadev(y, tau0, allan.octave_m(y.size, 0.1))
    expect = N / np.sqrt(res.tau / 3600.0)  # °/h
    ratio = res.deviation / expect
    # each point within 4 σ of its chi-square scatter (edf from the white-FM model)
    tol = 4.0 / np.sqrt(2.0 * res.edf)
    assert np.all(np.abs(ratio - 1.0) < tol), list(zip(res.tau, ratio, tol))
    # and the log-log slope is −½
    slope = np.polyfit(np.log(res.tau), np.log(res.deviation), 1)[0]
    assert slope == pytest.approx(-0.5, abs=0.03)


@FAST
@given(chunk=st.integers(min_value=1, max_value=5000), n=st.integers(min_value=1, max_value=5000))
def test_pulses_integrate_to_the_exact_angle_for_any_chunk_size(chunk, n):
    """No pulse is lost or doubled between chunks: Σ pulses is the integrated angle × K to within
    one pulse."""
    truth = GyroTruth(output="pulse", arw_deg_rt_h=0.0, bias_deg_h=0.37, seed=3)
    tau, lat = 0.01, 39.98
    out = simulate_static(truth, n=n, interval_s=tau, latitude_deg=lat, chunk=chunk)
    rate = EARTH_RATE_DEG_PER_H * math.sin(math.radians(lat)) + truth.bias_deg_h  # °/h = ″/s
    exact = rate * tau * n * truth.scale_factor_P_per_arcsec
    assert np.all(out == np.round(out))  # whole pulses only
    assert abs(out.sum() - exact) < 1.0


def test_pulse_output_of_a_long_noisy_record_keeps_its_angle_across_chunks():
    truth = GyroTruth(output="pulse", seed=5)
    a = simulate_static(truth, n=20_000, interval_s=0.01, latitude_deg=39.98, chunk=20_000)
    b = simulate_static(truth, n=20_000, interval_s=0.01, latitude_deg=39.98, chunk=333)
    # the same noise stream, split differently: totals agree to a pulse
    assert abs(a.sum() - b.sum()) <= 1.0


# ------------------------------------------------------------------------------ counter carry


@FAST
@given(incs=st.lists(st.integers(min_value=0, max_value=4000), min_size=1, max_size=300),
       cuts=st.lists(st.integers(min_value=0, max_value=300), max_size=20),
       start=st.integers(min_value=0, max_value=7))
def test_counter_carry_conserves_pulses_for_any_chunking(incs, cuts, start):
    # increments in eighths of a pulse: exact in binary floating point
    inc = np.asarray(incs, dtype=float) / 8.0
    whole, carry_whole = E.Counter.count(Q_(inc, "P"), start / 8.0)
    bounds = sorted({0, len(inc), *[c for c in cuts if c < len(inc)]})
    carry, parts = start / 8.0, []
    for a, b in zip(bounds[:-1], bounds[1:]):
        c, carry = E.Counter.count(Q_(inc[a:b], "P"), carry)
        parts.append(c.magnitude)
    chunked = np.concatenate(parts)
    np.testing.assert_array_equal(chunked, whole.magnitude)
    assert carry == carry_whole and 0.0 <= carry < 1.0
    assert chunked.sum() + carry == pytest.approx(inc.sum() + start / 8.0, abs=1e-9)


def test_counter_gate_within_timebase_error():
    c = E.Counter(id="C", timebase_error=Q_(1e-7, ""), seed=9)
    g = c.gate(Q_(10, "s")).to("s").magnitude
    assert abs(g - 10.0) <= 1e-6 and g != 10.0
    assert c.gate(Q_(10, "s")) == c.gate(Q_(10, "s"))  # a fixed error of the instrument


# ------------------------------------------------------------------------------ rate table


def test_rate_table_error_and_ripple_follow_their_band():
    t = E.RateTable(id="RT", seed=4)
    rng = np.random.default_rng(1)
    for sp, band in ((0.5, 0), (5.0, 1), (-200.0, 2)):
        b = t.bands[band]
        assert t.band(Q_(sp, "deg/s")) is b
        w = t.actual_rate(Q_(sp, "deg/s"), 40_000, rng).to("deg/s").magnitude
        rel = w / sp - 1.0
        e, rip = float(b.error.magnitude), float(b.ripple.magnitude)
        assert abs(rel.mean()) <= e + 5 * rip / math.sqrt(w.size)
        assert rel.mean() == pytest.approx(t.systematic_error(Q_(sp, "deg/s")), abs=5 * rip
                                           / math.sqrt(w.size))
        assert rel.std(ddof=1) == pytest.approx(rip, rel=0.03)
    with pytest.raises(DataError, match="beyond the table's range"):
        t.band(Q_(5000, "deg/s"))


def test_rate_table_angle_output_is_quantized_and_chunk_free():
    t = E.RateTable(id="RT", angle_resolution=Q_(0.5, "arcsec"))
    rng = np.random.default_rng(2)
    w = t.actual_rate(Q_(3.0, "deg/s"), 10_000, rng)
    dt = Q_(0.01, "s")
    read, end = t.angle_output(w, dt)
    true = np.cumsum(w.to("deg/s").magnitude) * 0.01 * 3600.0
    err = read.to("arcsec").magnitude - true
    assert np.all(err <= 1e-6) and np.all(err > -0.5 - 1e-6)
    steps = np.diff(read.to("arcsec").magnitude) / 0.5
    np.testing.assert_allclose(steps, np.round(steps), atol=1e-6)
    # the same record in chunks reads the same angles
    parts, start = [], Q_(0.0, "deg")
    for a in range(0, 10_000, 777):
        r, start = t.angle_output(w[a:a + 777], dt, start)
        parts.append(r.to("arcsec").magnitude)
    np.testing.assert_allclose(np.concatenate(parts), read.to("arcsec").magnitude, atol=1e-6)
    assert end.to("arcsec").magnitude == pytest.approx(true[-1])


def test_revolution_pulses_within_their_accuracy():
    t = E.RateTable(id="RT", revolution_pulse_accuracy=Q_(2.0, "arcsec"))
    times = t.revolution_times(Q_(10.0, "deg/s"), 200, np.random.default_rng(3)).to("s").magnitude
    angle_err = (times * 10.0 - 360.0 * np.arange(1, 201)) * 3600.0  # ″
    assert np.all(np.abs(angle_err) <= 2.0) and angle_err.std() > 0.5


# ------------------------------------------------------------------------------ acquisition


@FAST
@given(v=st.floats(min_value=-11.9, max_value=11.9, allow_nan=False), seed=st.integers(0, 1000))
def test_dmm_reading_within_its_stated_error(v, seed):
    dmm = E.DigitalMultimeter(id="DMM", seed=seed)
    r = dmm.read(Q_(v, "V")).to("V").magnitude
    bound = dmm.error_bound(Q_(v, "V")).to("V").magnitude + dmm.resolution.to("V").magnitude / 2
    assert abs(r - v) <= bound * (1 + 1e-9)
    res = dmm.resolution.to("V").magnitude
    assert r / res == pytest.approx(round(r / res), abs=1e-6)


def test_dmm_reads_mV_in_mV_and_refuses_an_overload():
    dmm = E.DigitalMultimeter(id="DMM")
    assert dmm.resolution == Q_(10.0, "V") / 1e6
    r = dmm.read(Q_(250.0, "mV"))
    assert str(r.units) in ("mV", "millivolt") and abs(r.magnitude - 250.0) < 0.05
    with pytest.raises(DataError, match="overload"):
        dmm.read(Q_(13.0, "V"))
    amm = E.DigitalMultimeter(id="AMM", range=Q_(3, "A"))
    assert amm.read(Q_(1.0, "A")).to("A").magnitude == pytest.approx(1.0, abs=1e-3)
    with pytest.raises(DataError):
        E.DigitalMultimeter(id="X", range=Q_(1, "s"))


@FAST
@given(v=st.floats(min_value=-10.0, max_value=9.99, allow_nan=False))
def test_adc_quantization_error_within_half_an_lsb(v):
    adc = E.ADC(id="ADC", bits=12, full_scale=Q_(10, "V"))
    q = adc.quantize(Q_(v, "V")).to("V").magnitude
    assert abs(q - v) <= adc.lsb.to("V").magnitude / 2 * (1 + 1e-12)


def test_adc_quantization_noise_is_lsb_squared_over_12_and_clipping_is_loud():
    adc = E.ADC(id="ADC", bits=12, full_scale=Q_(10, "V"))
    lsb = adc.lsb.to("V").magnitude
    assert lsb == pytest.approx(20.0 / 4096)
    v = np.random.default_rng(4).uniform(-9.9, 9.9, 200_000)
    e = adc.quantize(Q_(v, "V")).to("V").magnitude - v
    assert e.var() == pytest.approx(lsb**2 / 12, rel=0.02)
    assert abs(e.mean()) < 0.01 * lsb
    codes, clipped = adc.codes(Q_([0.0, 12.0, -12.0], "V"))
    assert clipped == 2 and codes.tolist() == [0, 2047, -2048]
    with pytest.raises(DataError, match="clipped"):
        adc.quantize(Q_([12.0], "V"))
    with pytest.raises(DataError):
        E.ADC(id="bad", bits=1)


def test_timer_within_accuracy_and_resolution():
    t = E.Timer(id="T", accuracy=Q_(1e-6, ""), resolution=Q_(1e-3, "s"))
    m = t.measure(Q_([1.0, 100.0, 1000.0], "s")).to("s").magnitude
    assert np.all(np.abs(m - [1.0, 100.0, 1000.0]) <= np.array([1.0, 100.0, 1000.0]) * 1e-6 + 5e-4)


# ------------------------------------------------------------------------------ environment, tables


def test_chamber_holds_setpoint_within_error_and_fluctuation_once_soaked():
    ch = E.TemperatureChamber(id="CH", setpoint_error=Q_(0.5, "K"), fluctuation=Q_(0.2, "K"),
                              soak=Q_(60, "min"))
    times = Q_(np.arange(0, 7200, 10.0), "s")
    T = ch.temperature(Q_(60, "degC"), times, np.random.default_rng(1)).to("degC").magnitude
    assert np.all(np.abs(T - 60) <= 0.7 + 1e-9)
    assert abs(T.mean() - 60 - ch.offset(Q_(60, "degC"))) < 0.02
    assert T.max() - T.min() == pytest.approx(0.4, abs=0.01)
    # after a change from 20 °C: not settled at first, within 1 % of the step after the soak time
    T2 = ch.temperature(Q_(60, "degC"), times, np.random.default_rng(1),
                        previous=Q_(20, "degC")).to("degC").magnitude
    assert T2[0] < 25 and abs(T2[times.magnitude >= 3600][0] - 60) < 0.7 + 0.4
    assert ch.soaked(Q_(61, "min")) and not ch.soaked(Q_(59, "min"))


def test_positioners_stay_within_their_accuracy():
    rng = np.random.default_rng(5)
    sp = Q_(np.arange(0, 360, 5.0), "deg")
    for m in (E.PositionTable(id="P", position_accuracy=Q_(3, "arcsec")),
              E.TiltTable(id="T", position_accuracy=Q_(2, "arcsec"), tilt_range=Q_(360, "deg")),
              E.ThreeAxisTable(id="3", position_accuracy=Q_(10, "arcsec")),
              E.AngleTurntable(id="A", position_accuracy=Q_(0.1, "arcsec"))):
        acc = m.equipment().properties["position_accuracy"].to("arcsec").magnitude
        err = (m.position(sp, rng) - sp).to("arcsec").magnitude
        assert np.all(np.abs(err) <= acc) and np.abs(err).max() > 0.5 * acc
    with pytest.raises(DataError, match="tilt beyond"):
        E.TiltTable(id="T").position(Q_([95.0], "deg"), rng)


def test_field_vibration_shock_and_reference_sensor():
    fg = E.FieldGenerator(id="F", setting_error=Q_(1e-3, ""), uniformity=Q_(5, "percent"))
    H = fg.field(Q_(1.0, "mT")).to("mT").magnitude
    assert abs(H - 1.0) <= 1e-3 and fg.field(Q_(1.0, "mT"),
                                             1.0).to("mT").magnitude == pytest.approx(H * 1.05)
    with pytest.raises(DataError):
        fg.field(Q_(5.0, "mT"))
    t = Q_(np.linspace(0, 1, 20001), "s")
    sh = E.LinearShaker(id="V", amplitude_error=Q_(0.05, ""))
    a = sh.acceleration(Q_(6, "gn"), Q_(100, "Hz"), t).to("gn").magnitude
    assert 6 * 0.95 - 1e-2 <= np.abs(a).max() <= 6 * 1.05
    sk = E.ShockTable(id="S", peak_error=Q_(0.1, ""), duration_accuracy=Q_(1, "ms"))
    p = sk.pulse(Q_(100, "gn"), Q_(6, "ms"), Q_(1e-5, "s"),
                 np.random.default_rng(1)).to("gn").magnitude
    assert 90 - 0.1 <= p.max() <= 110 and p[0] == 0 and p[-1] == 0
    assert (p > 0).sum() * 1e-5 == pytest.approx(6e-3, abs=1.05e-3)
    avt = E.AngularVibrationTable(id="AVT", amplitude_error=Q_(5e-3, ""), phase_U=Q_(0.2, "deg"))
    true, ref = avt.motion(Q_(10, "deg/s"), Q_(20, "Hz"), t)
    tr, rf = true.magnitude, ref.magnitude
    w = 2 * np.pi * 20 * t.magnitude
    X = np.column_stack([np.sin(w), np.cos(w)])
    (c, s), *_ = np.linalg.lstsq(X, rf, rcond=None)
    assert abs(math.hypot(c, s) / 10 - 1) <= 5e-3 + 1e-9
    assert abs(math.degrees(math.atan2(s, c))) < 0.5  # phase error ~ N(0, 0.1°)
    assert np.abs(tr).max() == pytest.approx(10, rel=1e-4)
    with pytest.raises(DataError, match="outside"):
        avt.motion(Q_(10, "deg/s"), Q_(1000, "Hz"), t)


def test_models_check_units_and_calibration():
    with pytest.raises(UnitError):
        E.RateTable(id="RT", revolution_pulse_accuracy=Q_(2, "s"))
    with pytest.raises(UnitError):
        E.LevelPlatform(id="P", levelness=2.0)  # a bare number for an angle
    with pytest.raises(DataError, match="without its expanded uncertainty"):
        E.Counter(id="C", certificate="X-1")
    with pytest.raises(DataError, match="negative"):
        E.Timer(id="T", accuracy=Q_(-1e-6, ""))
    with pytest.raises(DataError, match="increasing"):
        E.RateTable(id="RT", bands=(E.RateBand("10 deg/s", 1e-5, 1e-4),
                                    E.RateBand("1 deg/s", 1e-4, 1e-3)))
    import datetime as dt

    eq = E.Counter(id="C", certificate="CAL-7", U=Q_(1e-7, ""), k=2.0, due=dt.date(2030, 1, 1),
                   lab="NIM").equipment()
    assert (eq.role == "counter" and eq.calibration.certificate == "CAL-7"
            and eq.calibration.due.year == 2030)
    assert eq.calibration.standard_uncertainty == Q_(5e-8, "")
    assert E.Counter(id="C", role="timebase").equipment().role == "timebase"
    with pytest.raises(DataError, match="duplicate"):
        E.equipment_list([E.Timer(id="T"), E.Counter(id="T")])


# ------------------------------------------------------------------------------ stations


# every (role, property) the built-in procedures read — keep in step with
# `grep -rn 'equipment_for\|\.prop("' plugins/`
READ_BY_PROCEDURES = {
    "simulated": {"platform": ["levelness"],
                  "rate_table": ["revolution_pulse_accuracy", "rate_band_1_upper",
                                 "rate_band_1_error",
                                 "rate_band_1_ripple"],
                  "chamber": [],
                  "field_generator": ["uniformity"], "counter": [], "fixture": ["reseat_tilt"],
                  "tilt_table": ["position_accuracy"], "vibration_table": [],
                  "shock_table": ["duration_accuracy"],
                  "voltmeter": [], "ammeter": []},
    "simulated-jjf2014": {"rate_table": [], "dmm": [], "chamber": [],
                          "angular_vibration_table": ["phase_U"],
                          "timer": []},
    "simulated-mimu": {"rate_table": ["position_accuracy"], "acquisition": ["bits"]},
    "simulated-ogam": {"turntable": ["parallelism"]},
}


@pytest.mark.parametrize("station", sorted(READ_BY_PROCEDURES))
def test_station_equipment_keeps_the_roles_and_properties_procedures_read(station):
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    st_ = pm.station(station).factory()
    eq = {e.role: e for e in st_.equipment()}
    for role, props in READ_BY_PROCEDURES[station].items():
        assert role in eq, f"{station}: no equipment with role {role!r}"
        for p in props:
            assert p in eq[role].properties, f"{station}: {role} lacks {p!r}"


def test_a_simulated_station_reads_its_output_through_its_dmm_model():
    """simulated-jjf2014 with instrument_errors: the mV record is what the station's DMM reads —
    within the DMM's stated error of the gyro's output, on its 6½-digit grid — and the item still
    recovers the truth within U."""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import load_campaign, run_items

    pm = get_plugin_manager(autoload=False)
    proc = pm.procedure("jjf2014", "7.2.1")
    ideal = load_campaign(pm, [proc], [{}], data=None, station_options={"duration_scale": 0.05})
    real = load_campaign(pm, [proc], [{}], data=None,
                         station_options={"duration_scale": 0.05, "instrument_errors": True})
    dmm = next(m for m in kits.jjf2014_equipment() if isinstance(m, E.DigitalMultimeter))
    res_mV = dmm.resolution.to("mV").magnitude
    for a, b in zip(ideal.segments, real.segments):
        x, u = a.columns()["output"]
        y, _ = b.columns()["output"]
        bound = dmm.error_bound(Q_(x, u)).to(u).magnitude + res_mV / 2
        assert np.all(np.abs(y - x) <= bound * (1 + 1e-9))
        np.testing.assert_allclose(y / res_mV, np.round(y / res_mV), atol=1e-6)
    assert any(np.any(a.columns()["output"][0] != b.columns()["output"][0])
               for a, b in zip(ideal.segments, real.segments))
    r = run_items(pm, "jjf2014", ["7.2.1"], campaign=real).outcomes[0].result("K")
    truth = real.expected["K"]
    assert abs(r.value - truth) <= r.U


def test_the_simulated_jjf2014_rate_table_errs_as_its_certificate_says():
    """simulated-jjf2014: every rate segment is recorded at the rate the table really turns at —
    a fixed error per set point uniform within ±√3 × U/k (U_rel = 1×10⁻⁴, k = 2, appendix B.1) —
    drawn afresh for each seed; the device's noise is the same draw with or without it, so the
    difference of the two records is the table's doing alone."""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.instruments.vibratory import VibratoryStation, VibratoryTruth, mean_output

    pm = get_plugin_manager(autoload=False)
    steps = pm.procedure("jjf2014", "7.2.1")().sequence(
        pm.procedure("jjf2014", "7.2.1").option_values({})
    )
    half = math.sqrt(3.0) * 0.5e-4
    deltas = {}
    for seed in (1, 2):
        truth = VibratoryTruth(seed=seed)
        exact = VibratoryStation(truth=truth, table_errors=False).acquire(steps)
        real = VibratoryStation(truth=truth).acquire(steps)
        table = next(m for m in kits.jjf2014_equipment(seed=seed) if isinstance(m, E.RateTable))
        assert table.U.magnitude == pytest.approx(1e-4)
        for a, b, s in zip(exact.segments, real.segments, steps):
            om = float(Q_(s.conditions["rate"]).to("deg/s").magnitude)
            x = a.columns()["output"][0]
            y = b.columns()["output"][0]
            # the local slope of the device at this rate turns an output shift into a rate error
            h = 1e-6
            slope = (mean_output(truth, "rate", {"rate": Q_(om * (1 + h), "deg/s")}, 39.98)
                     - mean_output(truth, "rate", {"rate": Q_(om * (1 - h), "deg/s")},
                                   39.98)) / (2 * h * om)
            seen = float(np.mean(y - x)) / (slope * om)
            ripple = float(table.band(Q_(om, "deg/s")).ripple.magnitude)
            want = table.systematic_error(Q_(om, "deg/s"))
            assert abs(want) <= half
            assert seen == pytest.approx(want, abs=5 * ripple / math.sqrt(x.size) + 1e-9)
            deltas[(seed, om)] = want
    per_seed = [np.array([v for (s, _), v in sorted(deltas.items()) if s == seed]) for seed
                in (1, 2)]
    # the errors fill the certificate's interval
    assert max(np.max(np.abs(d)) for d in per_seed) > 0.5e-4
    assert not np.allclose(per_seed[0], per_seed[1])  # another seed, another table

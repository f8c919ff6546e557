"""Motions of GB/T 45570 D.1.4–D.1.6, D.2 and D.3 on the simulated station's virtual gyro.

Registered step kinds (see :func:`metro.instruments.simulated.register_step_kind`):

* ``revolutions-repeat`` / ``revolutions-temperature`` — whole table revolutions, IRA up, as
  ``rate-revolutions`` but on a power-on ``run`` (D.1.4) or at a chamber ``temperature`` (D.1.5,
  each point a power-on of its own: D.1.5.2 c) switches the gyro off between points);
  columns ``count`` (P per revolution) and ``duration`` (s);
* ``revolutions-mounting`` — the same with XRA or YRA along the table axis (condition
  ``axis_up``), the gyro turned 0° or 180° about its IRA in the fixture (condition ``turn``)
  (D.1.6);
* ``rate-output`` — the table turning at a constant signed ``rate``, IRA up, the output sampled
  (LSB for the digital gyro) (D.2.1–D.2.5, D.3); with ``run`` or ``temperature`` as above;
* ``rate-mounting`` — ``rate-output`` in the mountings of D.2.6;
* ``polarity`` — the output at rest (``rate`` 0) or turning at a signed ``rate`` about IRA (6.2.6).

The table at rest (``rate-static``) is the station's ordinary static record.  While turning,
the table's model (:class:`metro.instruments.equipment.RateTable`) sets the rate: its fixed
error at each set point and its ripple, the errors the procedures' type B rows must cover.

The truth (fields of :class:`~metro.instruments.simulated.GyroTruth`): the scale factor at
rate |Ω| and direction s is K·(1 + sf_slope·|Ω| + sf_quadratic·(Ω/400)² + s·sf_asymmetry/2)
(as in the angle method), times (1 + sf_tc·(T − T_ref)) in the chamber and times (1 + δ_run)
after power-on ``run`` (δ_run ~ N(0, sf_turn_on_sigma), seeded by (seed, run)); a D.1.5 or D.2.5
temperature point's power-on draws its own δ (and turn-on bias), seeded by (seed, temperature),
which the expected K_t leaves out (it is measurement error).  The input
axis IA leans from IRA by α towards XRA and β towards YRA; a mounting's fixture leans the
reference axis by ε (``fixture_tilt_arcsec``) towards IRA, the same before and after the 180°
turn, so D.15/D.32 cancel it.  The horizontal earth rate turns with the table and averages out
over the whole revolutions a step lasts; its vertical part and the bias enter as a constant.
"""

from __future__ import annotations

import functools
import math
from typing import Any, Mapping

import numpy as np
from metro.core.model.campaign import Campaign, Segment
from metro.core.base.units import Q_, parse_quantity

from .simulated import (DIGITAL_DEFAULTS, EARTH_RATE_DEG_PER_H, GyroTruth, SimulatedStation,
                        register_expected, mounting_key, output_unit, pulse_readout, quantize_rate,
                        register_step_kind, scale_factor_at, station_factory)
from .stations import memory_segment, standard_expected

REV_ARCSEC = 360.0 * 3600.0


# --------------------------------------------------------------------------------------------
# the truth at a step's conditions
# --------------------------------------------------------------------------------------------


def turn_on_scale_factor(truth: GyroTruth, run: Any) -> float:
    """Relative scale-factor change δ_run of power-on ``run`` (seeded by (seed, run))."""
    rng = np.random.default_rng([truth.seed, int(run), 1931])
    return float(rng.normal(0.0, truth.sf_turn_on_sigma))


def scale_factor_multiplier(
    truth: GyroTruth, rate_deg_s: float, direction: int, conditions: Mapping[str, Any]
) -> float:
    """K(|Ω|, s, T, run)/K: rate, direction, temperature and power-on effects on the scale
    factor."""
    f = scale_factor_at(truth, rate_deg_s, direction) / truth.scale_factor_P_per_arcsec
    if "temperature" in conditions:
        T = float(parse_quantity(conditions["temperature"], dimension="degC").to("degC").magnitude)
        f *= 1.0 + truth.sf_tc_per_C * (T - truth.temp_ref_C)
    if "run" in conditions:
        f *= 1.0 + turn_on_scale_factor(truth, conditions["run"])
    if truth.sf_mount_sigma > 0 and mounting_key(conditions):
        f *= 1.0 + float(
            np.random.default_rng([truth.seed, *mounting_key(conditions), 2281]).normal(
                0.0, truth.sf_mount_sigma
            )
        )
    return f


def input_axis(truth: GyroTruth) -> np.ndarray:
    """IA as a unit vector in (XRA, YRA, IRA), from α (towards XRA) and β (towards YRA), fig.
    D.1."""
    v = np.array(
        [
            math.tan(math.radians(truth.misalign_alpha_arcsec / 3600.0)),
            math.tan(math.radians(truth.misalign_beta_arcsec / 3600.0)),
            1.0,
        ]
    )
    return v / np.linalg.norm(v)


def mounting_projection(truth: GyroTruth, conditions: Mapping[str, Any]) -> float:
    """IA · (table axis) in a D.1.6/D.2.6 mounting: ``axis_up`` XRA or YRA along the table axis,
    ``turn`` 0° or 180° about IRA; the fixture leans the axis by ε towards IRA in both turns."""
    axis = str(conditions.get("axis_up", "IRA")).upper().replace("+", "").strip()
    turn = float(
        parse_quantity(conditions.get("turn", "0 deg"), dimension="deg").to("deg").magnitude
    )
    flip = -1.0 if abs((turn % 360.0) - 180.0) < 1e-6 else 1.0
    if axis == "IRA":
        return float(input_axis(truth)[2])
    k = {"XRA": 0, "YRA": 1}[axis]
    eps = math.radians(truth.fixture_tilt_arcsec[k] / 3600.0)
    a = np.zeros(3)
    a[k] = flip * math.cos(eps)
    a[2] = math.sin(eps)
    return float(input_axis(truth) @ a)


def _signed_rate(step) -> tuple[float, int]:
    rate = float(parse_quantity(step.conditions["rate"], dimension="deg/s").to("deg/s").magnitude)
    if rate == 0:
        raise ValueError(f"step {step.segment}: a turning step needs a non-zero rate")
    return abs(rate), (1 if rate > 0 else -1)


# --------------------------------------------------------------------------------------------
# whole revolutions (angle method)
# --------------------------------------------------------------------------------------------


def temperature_power_on(
    truth: GyroTruth, conditions: Mapping[str, Any], salt: int = 1951
) -> tuple[float, float]:
    """(δK/K, δB in °/h) of the power-on at a D.1.5 (or, ``salt`` 2953, D.2.5) temperature point:
    D.1.5.2 c) / D.2.5.2 c) switch the gyro off while the chamber changes temperature and on again
    for
    the point's sweep, so every point has a turn-on draw of its own, K from N(0, sf_turn_on_sigma)
    and
    the bias from N(0, turn_on_sigma_deg_h), seeded by (seed, salt, temperature).  Measurement
    error,
    not truth: the expected K_t is D.12 / D.29 on the noise-free K(T)."""
    T = float(parse_quantity(conditions["temperature"], dimension="degC").to("degC").magnitude)
    rng = np.random.default_rng([truth.seed, salt, int(round((T + 300.0) * 1000.0))])
    return float(rng.normal(0.0, truth.sf_turn_on_sigma)), float(
        rng.normal(0.0, truth.turn_on_sigma_deg_h)
    )


def _revolutions(
    station: SimulatedStation,
    step,
    index: int,
    projection: float,
    bias_offset_deg_h: float,
    k_factor: float = 1.0,
) -> Segment:
    t = station.truth
    rate, direction = _signed_rate(step)
    turns = int(step.conditions.get("turns", 5))
    K = (
        t.scale_factor_P_per_arcsec
        * scale_factor_multiplier(t, rate, direction, step.conditions)
        * k_factor
    )
    T = 360.0 / rate
    drift = (
        EARTH_RATE_DEG_PER_H * math.sin(math.radians(station.latitude_deg)) * projection
        + t.bias_deg_h
        + bias_offset_deg_h
    )  # ″/s along IA
    rng = np.random.default_rng([t.seed, index, 7411])
    noise_sd = t.arw_deg_rt_h * math.sqrt(T / 3600.0) * 3600.0
    angle = direction * REV_ARCSEC * projection + drift * T
    cum = np.cumsum(K * (angle + rng.normal(0.0, noise_sd, size=turns)))
    counts = np.diff(pulse_readout(t, cum, rng), prepend=0.0)
    dur = np.full(turns, T)
    return memory_segment(step, T, {"count": (counts, "P"), "duration": (dur, "s")})


@register_step_kind("revolutions-repeat")
def sim_revolutions_repeat(station, step, index, *, bias_offset_deg_h, **_):
    return _revolutions(station, step, index, 1.0, bias_offset_deg_h)


@register_step_kind("revolutions-temperature")
def sim_revolutions_temperature(station, step, index, *, bias_offset_deg_h, **_):
    dk, db = temperature_power_on(
        station.truth, step.conditions
    )  # a power-on at each point (D.1.5.2 c))
    return _revolutions(station, step, index, 1.0, bias_offset_deg_h + db, k_factor=1.0 + dk)


@register_step_kind("revolutions-mounting")
def sim_revolutions_mounting(station, step, index, *, bias_offset_deg_h, **_):
    return _revolutions(
        station, step, index, mounting_projection(station.truth, step.conditions), bias_offset_deg_h
    )


# --------------------------------------------------------------------------------------------
# sampled output at a constant table rate (rate method)
# --------------------------------------------------------------------------------------------


@functools.lru_cache(maxsize=16)
def _rate_table(seed: int):
    """The station's rate-table model for this device seed (its band error and ripple act on
    every rate step; the models are frozen values, so they are kept)."""
    from .equipment import RateTable
    from .kits import gbt45570_equipment

    return next((m for m in gbt45570_equipment(seed=seed) if isinstance(m, RateTable)), None)


def rate_samples(
    station: SimulatedStation,
    step,
    index: int,
    n: int,
    interval_s: float,
    projection: float,
    bias_offset_deg_h: float,
) -> Segment:
    """The sampled output of ``n`` samples with the table turning at the step's ``rate``, the
    input axis projected on the table axis by ``projection``."""
    t = station.truth
    rate, direction = _signed_rate(step)
    f = scale_factor_multiplier(t, rate, direction, step.conditions)
    if "temperature" in step.conditions and "run" not in step.conditions:
        # a D.2.5 temperature point is a power-on of its own (D.2.5.2 c)): its own K and bias draw
        dk, db = temperature_power_on(t, step.conditions, salt=2953)
        f *= 1.0 + dk
        bias_offset_deg_h += db
    rng = np.random.default_rng([t.seed, index, 5309])
    static = (
        EARTH_RATE_DEG_PER_H * math.sin(math.radians(station.latitude_deg)) * projection
        + t.bias_deg_h
        + bias_offset_deg_h
    )  # °/h
    white_sd = t.arw_deg_rt_h / math.sqrt(interval_s / 3600.0)
    table = _rate_table(t.seed)
    # the rate the table actually turns at: its fixed error at this set point and its ripple
    actual = (
        np.asarray(table.actual_rate(Q_(direction * rate, "deg/s"), n, rng).to("deg/s").magnitude)
        if table is not None
        else np.full(n, direction * rate)
    )
    # indicated rate, °/h: the table's component along IA through the scale factor, plus the rest
    w = actual * 3600.0 * projection * f + static + rng.normal(0.0, white_sd, size=n)
    unit = output_unit(t)
    if t.output == "pulse":
        cum = np.cumsum(w * interval_s * t.scale_factor_P_per_arcsec)
        out = np.diff(pulse_readout(t, cum, rng), prepend=0.0)
    else:
        out = quantize_rate(t, w, rng)
    return memory_segment(step, interval_s, {"output": (out, unit)})


@register_step_kind("rate-output")
def sim_rate_output(station, step, index, *, interval_s, n, bias_offset_deg_h, **_):
    return rate_samples(station, step, index, n, interval_s, 1.0, bias_offset_deg_h)


@register_step_kind("polarity")
def sim_polarity(
    station, step, index, *, interval_s, n, orientation, bias_offset_deg_h, progress=None, **_
):
    """GB/T 45570 6.2.6: the output at rest (``rate`` 0) or turning at a signed ``rate`` about
    IRA."""
    rate = float(parse_quantity(step.conditions["rate"], dimension="deg/s").to("deg/s").magnitude)
    if rate != 0:
        return rate_samples(station, step, index, n, interval_s, 1.0, bias_offset_deg_h)
    from .simulated import simulate_static

    out = simulate_static(
        station.truth,
        n=n,
        interval_s=interval_s,
        latitude_deg=station.latitude_deg,
        orientation=orientation,
        seed=station.truth.seed + 104729 * (index + 1),
        progress=progress,
        bias_offset_deg_h=bias_offset_deg_h,
    )
    unit = output_unit(station.truth)
    return memory_segment(step, interval_s, {"output": (out, unit)})


@register_step_kind("rate-mounting")
def sim_rate_mounting(station, step, index, *, interval_s, n, bias_offset_deg_h, **_):
    return rate_samples(
        station,
        step,
        index,
        n,
        interval_s,
        mounting_projection(station.truth, step.conditions),
        bias_offset_deg_h,
    )


# --------------------------------------------------------------------------------------------
# what an ideal evaluation gives (noise-free data through the standard's formulas)
# --------------------------------------------------------------------------------------------


def _rate_of(seg: Segment) -> float:
    return float(parse_quantity(seg.conditions["rate"], dimension="deg/s").to("deg/s").magnitude)


def _ideal_Ki(
    truth: GyroTruth, rates, conditions, latitude_deg: float, projection: float = 1.0
) -> np.ndarray:
    """K_i (D.2) of noise-free revolutions at the rate magnitudes ``rates``."""
    d = EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg)) * projection + truth.bias_deg_h
    out = []
    for r in rates:
        T = 360.0 / r
        kp = truth.scale_factor_P_per_arcsec * scale_factor_multiplier(truth, r, 1, conditions)
        km = truth.scale_factor_P_per_arcsec * scale_factor_multiplier(truth, r, -1, conditions)
        n_plus = kp * (REV_ARCSEC * projection + d * T)
        n_minus = km * (-REV_ARCSEC * projection + d * T)
        out.append((n_plus - n_minus) / (2 * REV_ARCSEC))
    return np.array(out)


def _ideal_Fk(truth: GyroTruth, signed_rates, conditions, projection: float = 1.0) -> np.ndarray:
    """F_kj (D.19) of the noise-free digital output: the static part removed exactly."""
    return np.array(
        [
            truth.lsb_per_deg_s
            * r
            * projection
            * scale_factor_multiplier(truth, abs(r), 1 if r > 0 else -1, conditions)
            for r in signed_rates
        ]
    )


def _line(x, y) -> tuple[float, float]:
    slope, icept = np.polyfit(np.asarray(x, float), np.asarray(y, float), 1)
    return float(slope), float(icept)


def _kn_angle(rates, Ki) -> float:
    _, K = _line(rates, Ki)
    return float(np.max(np.abs(Ki - K)) / K)


def _kn_rate(signed, Fk) -> float:
    K, F0 = _line(signed, Fk)
    return float(np.max(np.abs(K * np.asarray(signed) + F0 - Fk)) / np.max(np.abs(Fk)))


def _nonlinearity_curve(rates_abs, kn_of) -> list[tuple[float, float]]:
    """(Ω, K_n of the rate points up to Ω) for each candidate Ω of D.3 (from the third rate on):
    what GB/T 45570's plugin turns into the expected Ω_max against its K_n limit."""
    return [(om, kn_of(om)) for om in sorted(set(rates_abs))[2:]]


def _by(segs, key):
    groups: dict[str, list[Segment]] = {}
    for s in segs:
        groups.setdefault(str(s.conditions[key]), []).append(s)
    return groups


def _temperature(text) -> float:
    return float(parse_quantity(text, dimension="degC").to("degC").magnitude)


def _kt(values: dict[str, float]) -> float:
    temps = {k: _temperature(k) for k in values}
    room = min(temps, key=lambda k: abs(temps[k] - 20.0))
    return max(
        abs((values[k] - values[room]) / (values[room] * (temps[k] - temps[room])))
        for k in values
        if k != room
    )


def _kr(values) -> float:
    v = np.asarray(list(values), float)
    return float(np.std(v, ddof=1) / np.mean(v))


def _abg(a1, a2, b1, b2) -> dict[str, Any]:
    a, b = (a1 - a2) / 2.0, (b1 - b2) / 2.0
    return {"alpha": Q_(a, "deg"), "beta": Q_(b, "deg"), "gamma": Q_(math.hypot(a, b), "deg")}


@register_expected
def expected_polarity(station: SimulatedStation, camp: Campaign) -> dict[str, Any]:
    """Expected response ratio r and polarity of 6.2.6: the polarity times the scale factor's
    relative value at the turning rate (the table's rate error is left to the budget)."""
    turning = [s for s in camp.segments if s.kind == "polarity" and _rate_of(s) != 0]
    if not turning:
        return {}
    rate = _rate_of(turning[0])
    t = station.truth
    f = scale_factor_multiplier(t, abs(rate), 1 if rate > 0 else -1, turning[0].conditions)
    return {"polarity_ratio": Q_(t.polarity * f, ""), "polarity": Q_(float(t.polarity), "")}


def _kinds(segments) -> dict[str, list[Segment]]:
    kinds: dict[str, list[Segment]] = {}
    for s in segments:
        kinds.setdefault(s.kind, []).append(s)
    return kinds


@register_expected
def expected_rate_items(station: SimulatedStation, camp: Campaign) -> dict[str, Any]:
    """Expected K_r, K_t, α, β, γ (D.1.4–D.1.6, D.2.4–D.2.6), K, F_0, K_n, K_a (D.2.1–D.2.3) and
    Ω_max (D.3, by the standard's plugin with its default nonlinearity limit for the device)."""
    kinds = _kinds(camp.segments)
    return _expected_angle(station, camp, kinds) | _expected_rate(station, camp, kinds)


def _expected_angle(
    station: SimulatedStation, camp: Campaign, kinds: Mapping[str, list[Segment]]
) -> dict[str, Any]:
    """The angle method's expected values (whole revolutions, D.1.4–D.1.6 and D.3)."""
    t, lat = station.truth, station.latitude_deg
    out: dict[str, Any] = {}
    if "rate-revolutions" in kinds:
        rates = sorted({abs(_rate_of(s)) for s in kinds["rate-revolutions"]})
        if len(rates) >= 3 and not (t.output == "digital" and "rate-output" in kinds):

            def kn_of(c):
                sel = [r for r in rates if r <= c]
                return _kn_angle(sel, _ideal_Ki(t, sel, {}, lat))

            out |= standard_expected(
                camp, {"gbt45570:nonlinearity": _nonlinearity_curve(rates, kn_of)}
            )
    if "revolutions-repeat" in kinds:
        runs = _by(kinds["revolutions-repeat"], "run")
        Kj = [
            float(_ideal_Ki(t, [abs(_rate_of(g[0]))], g[0].conditions, lat)[0])
            for g in runs.values()
        ]
        if len(Kj) >= 2:
            out["Kr"] = Q_(_kr(Kj), "")
    if "revolutions-temperature" in kinds:
        Ks = {}
        for T, g in _by(kinds["revolutions-temperature"], "temperature").items():
            rates = sorted({abs(_rate_of(s)) for s in g})
            Ks[T] = (
                _line(rates, _ideal_Ki(t, rates, g[0].conditions, lat))[1]
                if len(rates) > 1
                else float(_ideal_Ki(t, rates, g[0].conditions, lat)[0])
            )
        if len(Ks) >= 2:
            out["Kt"] = Q_(_kt(Ks), "1/delta_degC")
    if "revolutions-mounting" in kinds:
        ang = {}
        for s in kinds["revolutions-mounting"]:
            key = (str(s.conditions["axis_up"]).upper(), str(s.conditions["turn"]))
            proj = mounting_projection(t, s.conditions)
            r = abs(_rate_of(s))
            ang[key] = math.degrees(
                float(_ideal_Ki(t, [r], s.conditions, lat, proj)[0]) / t.scale_factor_P_per_arcsec
            )
        out |= _mounting_expected(ang)
    return out


def _expected_rate(
    station: SimulatedStation, camp: Campaign, kinds: Mapping[str, list[Segment]]
) -> dict[str, Any]:
    """The rate method's expected values (sampled output, D.2.1–D.2.6 and D.3)."""
    t = station.truth
    out: dict[str, Any] = {}
    if "rate-output" in kinds:
        plain = [
            s
            for s in kinds["rate-output"]
            if "run" not in s.conditions and "temperature" not in s.conditions
        ]
        if plain:
            out |= _expected_rate_plain(
                camp, t, [_rate_of(s) for s in plain], "rate-revolutions" in kinds
            )
        runs = _by([s for s in kinds["rate-output"] if "run" in s.conditions], "run")
        if len(runs) >= 2:
            Kj = []
            for g in runs.values():
                signed = [_rate_of(s) for s in g]
                Kj.append(_line(signed, _ideal_Fk(t, signed, g[0].conditions))[0])
            out["Kr"] = Q_(_kr(Kj), "")
        temps = _by(
            [s for s in kinds["rate-output"] if "temperature" in s.conditions], "temperature"
        )
        if len(temps) >= 2:
            Ks = {}
            for T, g in temps.items():
                signed = [_rate_of(s) for s in g]
                Ks[T] = _line(signed, _ideal_Fk(t, signed, g[0].conditions))[0]
            out["Kt"] = Q_(_kt(Ks), "1/delta_degC")
    if "rate-mounting" in kinds:
        ang = {}
        for (ax, turn), g in _pairs(kinds["rate-mounting"]).items():
            r = abs(_rate_of(g[0]))
            proj = mounting_projection(t, g[0].conditions)
            fp, fm = _ideal_Fk(t, [r, -r], g[0].conditions, proj)
            ang[(ax, turn)] = math.degrees(math.asin((fp - fm) / (2 * t.lsb_per_deg_s * r)))
        out |= _mounting_expected(ang)
    return out


def _expected_rate_plain(
    camp: Campaign, t: GyroTruth, signed: list[float], revolutions: bool
) -> dict[str, Any]:
    """K, F₀, K_n, K_a (D.2.1–D.2.3) and Ω_max (D.3) of the plain rate points ``signed`` (°/s)."""
    out: dict[str, Any] = {}
    Fk = _ideal_Fk(t, signed, {})
    K, F0 = _line(signed, Fk)
    if (
        t.output == "rate"
    ):  # a digital rate: K a ratio, F₀ in °/s (D.2 reads any angular rate as °/s)
        out["K"], out["F0"] = Q_(K / t.lsb_per_deg_s, ""), Q_(F0 / t.lsb_per_deg_s, "deg/s")
    else:
        out["K"], out["F0"] = Q_(K, "LSB/(deg/s)"), Q_(F0, "LSB")
    out["Kn"] = Q_(_kn_rate(signed, Fk), "")
    pos = [(r, f) for r, f in zip(signed, Fk) if r > 0]
    neg = [(r, f) for r, f in zip(signed, Fk) if r < 0]
    if len(pos) > 1 and len(neg) > 1:
        kp, km = _line(*zip(*pos))[0], _line(*zip(*neg))[0]
        out["Ka"] = Q_(abs(kp - km) / ((kp + km) / 2), "")
    mags = sorted({abs(r) for r in signed})
    if len(mags) >= 3 and (t.output == "digital" or not revolutions):

        def kn_of(c):
            sel = [r for r in signed if abs(r) <= c]
            return _kn_rate(sel, _ideal_Fk(t, sel, {}))

        out |= standard_expected(camp, {"gbt45570:nonlinearity": _nonlinearity_curve(mags, kn_of)})
    return out


def _pairs(segs) -> dict[tuple[str, str], list[Segment]]:
    groups: dict[tuple[str, str], list[Segment]] = {}
    for s in segs:
        groups.setdefault(
            (str(s.conditions["axis_up"]).upper(), str(s.conditions["turn"])), []
        ).append(s)
    return groups


def _mounting_expected(ang: Mapping[tuple[str, str], float]) -> dict[str, Any]:
    def get(ax, flip):
        for (a, turn), v in ang.items():
            deg = float(parse_quantity(turn, dimension="deg").to("deg").magnitude) % 360.0
            if a == ax and (abs(deg - 180.0) < 1e-6) == flip:
                return v
        return None

    vals = [get("XRA", False), get("XRA", True), get("YRA", False), get("YRA", True)]
    if any(v is None for v in vals):
        return {}
    return _abg(*vals)


# --------------------------------------------------------------------------------------------
# the digital-output station
# --------------------------------------------------------------------------------------------


def digital_station_factory(**options: Any) -> SimulatedStation:
    """Factory registered as ``simulated-digital``: the virtual gyro with LSB output (a fibre gyro
    for the rate method); options as for ``simulated``, over :data:`DIGITAL_DEFAULTS` (a
    ``device_class`` replaces them with the class's own values)."""
    import attrs

    if options.get("device_class"):
        return attrs.evolve(station_factory(**options), name="simulated-digital")
    base = dict(DIGITAL_DEFAULTS) | (
        dict(DIGITAL_TYPICAL) if str(options.get("grade", "typical")) == "typical" else {}
    )
    return attrs.evolve(station_factory(**(base | dict(options))), name="simulated-digital")


#: the ``typical`` grade of the ``simulated-digital`` station over :data:`DIGITAL_DEFAULTS`: a
#: typical aviation-grade
#: fibre gyro that conforms to GB/T 45570 table B.1 — its LSB (0.0072 °/h) finer than its noise,
#: K_t 0.5 ppm/°C
#: (B.1: ≤ 3), K turn-on scatter 1 ppm (≤ 10).  ``grade=marginal`` (or ``failing``) keeps
#: DIGITAL_DEFAULTS as they
#: were: 1 LSB = 0.72 °/h, coarser than the noise, K_t 2 ppm/°C
DIGITAL_TYPICAL = {"lsb_per_deg_s": 500000.0, "sf_tc_per_C": 5e-7, "sf_turn_on_sigma": 1e-6}


__all__ = [
    "digital_station_factory",
    "expected_rate_items",
    "mounting_projection",
    "scale_factor_multiplier",
    "turn_on_scale_factor",
    "temperature_power_on",
    "input_axis",
    "DIGITAL_DEFAULTS",
    "DIGITAL_TYPICAL",
]

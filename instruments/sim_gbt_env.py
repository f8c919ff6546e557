"""Motions of the virtual optical gyro for GB/T 45570 D.4 (threshold), D.6.3/D.6.4 (vibration,
shock), 6.2.7.7 (set-up time) and 6.2.7.8 (power consumption).

Registered step kinds (see :func:`metro.instruments.simulated.register_step_kind`):

* ``tilt`` — IRA at the angle ``psi`` (Ψ) to the earth's axis; the gyro sees Ω_e·cos Ψ (the
  physical earth rate) through a dead band d: r = sign(Ω)·max(|Ω| − d, 0), so its output reaches
  50 % of the expected one from |Ω| = 2d on (``dead_band_deg_h``);
* ``vibration`` — at rest with ``axis`` (IRA/XRA/YRA) along the vibration; ``IRA up`` or
  ``IRA east`` (no earth rate along a horizontal east IRA); the bias shifts by
  ``vib_shift_during_deg_h`` while vibrating (``phase = during``), by ``vib_shift_after_deg_h``
  after performance and ``vib_endurance_shift_deg_h`` after endurance vibration;
* ``shock`` — as ``vibration``, the bias shifting by ``shock_shift_deg_h`` after the shocks;
* ``power-on`` — the output from the switch-on with an excess bias A·e^(−t/τ)
  (``setup_transient_deg_h``, ``setup_tau_s``);
* ``power`` — columns ``voltage`` [V] and ``current`` [A] of the supply whose nominal voltage is
  the condition ``supply``, from ``power_supplies``, with relative noise ``power_noise_rel``.

The low/high-temperature records of D.6.1/D.6.2 are ordinary static records at a chamber
``temperature`` (the station's default simulation with the bias temperature coefficient).
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
from metro.core.model.campaign import Campaign, Segment
from metro.core.base.units import Q_, parse_quantity

from .simulated import (AXES, EARTH_RATE_DEG_PER_H, GyroTruth, SimulatedStation, register_expected,
                        register_step_kind)
from .stations import memory_segment, standard_expected


def dead_band_response(truth: GyroTruth, input_deg_h: float) -> float:
    """The rate the virtual gyro indicates (beyond its bias) for a small input: a dead band d."""
    d = truth.dead_band_deg_h
    return math.copysign(max(abs(input_deg_h) - d, 0.0), input_deg_h)


def _psi(conditions) -> float:
    return float(parse_quantity(conditions["psi"], dimension="deg").to("deg").magnitude)


def _axis(conditions) -> int:
    return AXES.index(str(conditions.get("axis", "IRA")).upper())


@register_step_kind("tilt")
def sim_tilt(station, step, index, *, interval_s, n, bias_offset_deg_h, progress=None, **_):
    t = station.truth
    x = EARTH_RATE_DEG_PER_H * math.cos(math.radians(_psi(step.conditions)))
    # latitude 0 removes the vertical earth rate of simulate_static: the input is Ω_e·cos Ψ alone
    return station.at_rest(
        step, index, n=n, interval_s=interval_s, latitude_deg=0.0,
        offset=bias_offset_deg_h + dead_band_response(t, x), progress=progress,
    )


def _environment_shift(truth: GyroTruth, kind: str, conditions) -> float:
    ax = _axis(conditions)
    phase = str(conditions.get("phase", "before")).lower()
    if phase == "before":
        return 0.0
    if kind == "shock":
        return truth.shock_shift_deg_h[ax]
    if phase == "during":
        return truth.vib_shift_during_deg_h[ax]
    if str(conditions.get("test", "performance")).lower() == "endurance":
        return truth.vib_endurance_shift_deg_h[ax]
    return truth.vib_shift_after_deg_h[ax]


def _mounted_latitude(station: SimulatedStation, conditions) -> float:
    orient = str(conditions.get("orientation", "IRA up")).lower()
    if "east" in orient or "west" in orient:
        return 0.0  # a horizontal IRA pointing east sees no earth rate
    return station.latitude_deg


@register_step_kind("shock")
@register_step_kind("vibration")
def sim_vibration_shock(
    station, step, index, *, interval_s, n, bias_offset_deg_h, progress=None, **_
):
    """The gyro at rest on the vibration or the shock table (the step's kind), its bias shifted
    as the test and its phase say."""
    off = bias_offset_deg_h + _environment_shift(station.truth, step.kind, step.conditions)
    return station.at_rest(
        step, index, n=n, interval_s=interval_s,
        latitude_deg=_mounted_latitude(station, step.conditions), offset=off, progress=progress,
    )


def transient_per_sample(truth: GyroTruth, n: int, interval_s: float) -> np.ndarray:
    """Mean excess rate (°/h) over each sample interval of A·e^(−t/τ), t from the switch-on."""
    edges = np.arange(n + 1) * interval_s
    tau = truth.setup_tau_s
    return (
        truth.setup_transient_deg_h
        * tau
        * (np.exp(-edges[:-1] / tau) - np.exp(-edges[1:] / tau))
        / interval_s
    )


@register_step_kind("power-on")
def sim_power_on(
    station, step, index, *, interval_s, n, orientation, bias_offset_deg_h, progress=None, **_
):
    # the transient is part of the indicated rate, quantized with it
    return station.at_rest(
        step, index, n=n, interval_s=interval_s, orientation=orientation,
        offset=bias_offset_deg_h, progress=progress,
        extra_deg_h=transient_per_sample(station.truth, n, interval_s),
    )


def supply_current(truth: GyroTruth, nominal_V: float) -> float:
    """The current (A) the virtual gyro draws from the supply of this nominal voltage (0 if
    none)."""
    for v, i in truth.power_supplies:
        if abs(v - nominal_V) < 1e-9:
            return i
    return 0.0


def _supply_voltage(conditions) -> float:
    return float(parse_quantity(conditions["supply"], dimension="V").to("V").magnitude)


@register_step_kind("power")
def sim_power(station, step, index, *, interval_s, n, **_):
    t = station.truth
    V = _supply_voltage(step.conditions)
    current = supply_current(t, V)
    rng = np.random.default_rng([t.seed, index, 3301])
    u = V * (1.0 + rng.normal(0.0, t.power_noise_rel, size=n))
    i = current * (1.0 + rng.normal(0.0, t.power_noise_rel, size=n))
    return memory_segment(step, interval_s, {"voltage": (u, "V"), "current": (i, "A")})


# --------------------------------------------------------------------------------------------
# what an ideal evaluation gives
# --------------------------------------------------------------------------------------------


def tilt_responses(truth: GyroTruth, psis_deg) -> list[tuple[float, float]]:
    """(Ψ, the rate beyond its bias the virtual gyro indicates at Ψ) of noise-free tilt positions:
    what GB/T 45570's plugin turns into the expected threshold (D.37, D.39)."""
    return [
        (psi, dead_band_response(truth, EARTH_RATE_DEG_PER_H * math.cos(math.radians(psi))))
        for psi in psis_deg
    ]


def power_on_rates(truth: GyroTruth, n: int, interval_s: float, latitude_deg: float) -> np.ndarray:
    """The noise-free indicated rate (°/h) of ``n`` samples from the switch-on, IRA up: what GB/T
    45570's plugin turns into the expected set-up time (6.2.7.7)."""
    return (
        truth.bias_deg_h
        + EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))
        + transient_per_sample(truth, n, interval_s)
    )


@register_expected
def expected_env_items(station: SimulatedStation, camp: Campaign) -> dict[str, Any]:
    """Expected threshold (D.4), B₀ at the operating temperatures (D.6.1/D.6.2), ΔB_V12/ΔB_V13
    (D.6.3), the shock's ΔB_V13 (D.6.4), the set-up time (6.2.7.7) and the power (6.2.7.8); the
    threshold and the set-up time by the standard's formulas (its plugin) on noise-free records."""
    t, lat = station.truth, station.latitude_deg
    out: dict[str, Any] = {}
    kinds: dict[str, list[Segment]] = {}
    for s in camp.segments:
        kinds.setdefault(s.kind, []).append(s)
    if "tilt" in kinds:
        out |= standard_expected(
            camp,
            {
                "gbt45570:tilt_response": tilt_responses(
                    t, [_psi(s.conditions) for s in kinds["tilt"]]
                )
            },
        )
    earth_diff = (EARTH_RATE_DEG_PER_H - 15.041) * math.sin(math.radians(lat))
    for kind, tag in (("low-temperature", "low"), ("high-temperature", "high")):
        for s in kinds.get(kind, [])[:1]:
            T = float(
                parse_quantity(s.conditions["temperature"], dimension="degC").to("degC").magnitude
            )
            out[f"B0_{tag}"] = Q_(
                t.bias_deg_h + t.bias_tc_deg_h_per_C * (T - t.temp_ref_C) + earth_diff, "deg/h"
            )
    for ax, name in enumerate(AXES):
        out[f"dBV12_{name}"] = Q_(abs(t.vib_shift_during_deg_h[ax]), "deg/h")
        out[f"dBV13_{name}"] = Q_(abs(t.vib_shift_after_deg_h[ax]), "deg/h")
        out[f"dBV13end_{name}"] = Q_(abs(t.vib_endurance_shift_deg_h[ax]), "deg/h")
        out[f"dBshock_{name}"] = Q_(abs(t.shock_shift_deg_h[ax]), "deg/h")
    for s in kinds.get("power-on", [])[:1]:
        dt = float(s.interval.to("s").magnitude)
        n = int(s.columns()["output"][0].size)
        out |= standard_expected(
            camp, {"gbt45570:power_on_rate": (power_on_rates(t, n, dt, lat), dt)}
        )
    if "power" in kinds:
        out["P"] = Q_(
            sum(
                abs(
                    _supply_voltage(s.conditions) * supply_current(t, _supply_voltage(s.conditions))
                )
                for s in kinds["power"]
            ),
            "W",
        )
    return out

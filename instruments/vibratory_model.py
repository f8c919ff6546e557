"""The virtual analog vibratory rate gyro of the simulated JJF 2014 station: its declared truth
(:class:`VibratoryTruth`), its operating point and mean output under a step's conditions, and the
noise of its records (:func:`simulate_segment`)."""

from __future__ import annotations

import math
import zlib
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np
from metro.core.base.units import Q_, parse_quantity

from metro.core.stats.earth import EARTH_RATE_DEG_PER_H  # noqa: E402  physical, 15.04107 °/h


AXES = ("X", "Y", "Z")


@attrs.frozen
class VibratoryTruth:
    """Declared truth of the virtual gyro (magnitudes in the units named)."""

    K_mV_per_dps: float = 20.0
    bias_dps: float = 0.05
    asymmetry: float = 2e-4
    cubic: float = 3e-4
    full_scale_dps: float = 100.0
    arw_deg_rt_h: float = 0.1
    quantization_arcsec: float = 0.0
    rrw_deg_h_rt_h: float = 0.0
    rate_ramp_deg_h2: float = 0.0
    bias_instability_deg_h: float = 0.0
    sf_temp_per_degC: float = 1.5e-4
    bias_temp_dps_per_degC: float = 2e-4
    sf_accel_mV_dps_per_g: float = 0.004
    bias_accel_dps_per_g: tuple = (0.002, -0.001, 0.003)
    sf_shock_mV_dps: tuple = (0.004, -0.002, 0.006)
    bias_shock_dps: tuple = (0.001, -0.003, 0.002)
    sf_vib_mV_dps: tuple = (-0.003, 0.005, 0.002)
    bias_vib_dps: tuple = (0.002, 0.001, -0.004)
    sf_repeat_rel: float = 1e-4
    bias_repeat_dps: float = 5e-4
    threshold_dps: float = 0.008
    resolution_dps: float = 0.004
    hard_dead_band: bool = False
    misalign_alpha_rad: float = 1.0e-3
    misalign_beta_rad: float = -6.0e-4
    fixture_error_rad: tuple = (2e-3, -1e-3)  # (about x: enters positions 1/2, about y: 3/4)
    misalign_repeat_rad: float = 2e-5
    bandwidth_hz: float = 80.0
    delay_s: float = 0.002
    startup_tau_s: float = 3.0
    startup_excursion_dps: float = 5.0
    ref_noise_dps: float = 0.01
    #: every calibration and record is its own power-on (or mounting): K and the bias take their own
    #: draws of ``sf_repeat_rel`` / ``bias_repeat_dps`` in every kind, not only in the repeat kinds
    #: of 7.2.4 and 7.2.15 (what those items assume of a real device); off: only the repeats vary
    power_on_variation: bool = False
    #: the output as digitised by the acquisition, rounded to this quantum (mV); 0: not rounded
    output_lsb_mV: float = 0.0
    #: a ratiometric output: recorded in mV/V against this supply voltage (V); 0: recorded in mV.
    #: The device's voltage output scales with its supply, so the ratio is what stays put; metro
    #: turns it back into mV with the declared supply (docs/data-format.md, "Ratiometric outputs")
    ratiometric_supply_V: float = 0.0
    #: the class this device was drawn from (station option ``device_class``; "" = fields as given)
    device_class: str = ""
    seed: int = 20221122

    def as_quantities(self) -> dict[str, Any]:
        return {
            "scale factor K": Q_(self.K_mV_per_dps, "mV/(deg/s)"),
            "bias b": Q_(self.bias_dps * 3600, "deg/h"),
            "asymmetry a": self.asymmetry,
            "cubic nonlinearity c (rel. to full scale)": self.cubic,
            "full scale": Q_(self.full_scale_dps, "deg/s"),
            "angle random walk": Q_(self.arw_deg_rt_h, "deg/hour**0.5"),
            "quantization": Q_(self.quantization_arcsec, "arcsec"),
            "rate random walk": Q_(self.rrw_deg_h_rt_h, "deg/h/hour**0.5"),
            "rate ramp": Q_(self.rate_ramp_deg_h2, "deg/h**2"),
            "bias instability": Q_(self.bias_instability_deg_h, "deg/h"),
            "K temperature coefficient": Q_(self.sf_temp_per_degC, "1/delta_degC"),
            "bias temperature coefficient": Q_(
                self.bias_temp_dps_per_degC * 3600, "deg/h/delta_degC"
            ),
            "threshold model Ω_th": Q_(self.threshold_dps, "deg/s"),
            "resolution model r_res": Q_(self.resolution_dps, "deg/s"),
            "dead band": "hard (no output below Ω_th / r_res)"
            if self.hard_dead_band
            else "soft (Ω³/(Ω² + Ω_th²))",
            "misalignment α, β": f"{self.misalign_alpha_rad:g} rad, {self.misalign_beta_rad:g} rad",
            "bandwidth": Q_(self.bandwidth_hz, "Hz"),
            "delay": Q_(self.delay_s, "s"),
            "start-up time constant": Q_(self.startup_tau_s, "s"),
            "variation between power-ons": (
                "every calibration and record"
                if self.power_on_variation
                else "the 7.2.4 / 7.2.15 repeats only"
            ),
            "output quantum": Q_(self.output_lsb_mV, "mV"),
            "device class": self.device_class or "(fields as given)",
            "seed": self.seed,
        }


def dead_zone(omega: np.ndarray | float, th: float, hard: bool = False) -> np.ndarray:
    w = np.asarray(omega, dtype=float)
    if th <= 0:
        return w
    if hard:
        return np.where(np.abs(w) >= th, w, 0.0)
    return w * w * w / (w * w + th * th)


def increment_gain(t: VibratoryTruth, d: float) -> float:
    """Fraction of a rate increment ΔΩ (°/s) on a steady rate that reaches the output."""
    if d == 0:
        return 0.0
    if t.hard_dead_band:
        return 1.0 if abs(d) >= t.resolution_dps else 0.0
    return d * d / (d * d + t.resolution_dps**2)


def steady_output(t: VibratoryTruth, omega_dps, *, K: float, bias_dps: float) -> np.ndarray:
    """Noiseless steady output (mV) for input rate(s) Ω (°/s) with scale factor K and bias b."""
    r = dead_zone(omega_dps, t.threshold_dps, t.hard_dead_band)
    kdir = np.where(r > 0, K * (1 + t.asymmetry / 2), K * (1 - t.asymmetry / 2))
    return kdir * r + K * t.cubic * r**3 / t.full_scale_dps**2 + K * bias_dps


def condition_value(
    conditions: Mapping[str, Any], name: str, unit: str | None = None, default=None
):
    if name not in conditions:
        return default
    v = conditions[name]
    if unit is None:
        return v
    return float(parse_quantity(v, dimension=unit).to(unit).magnitude)


def run_rng(t: VibratoryTruth, tag: str, run: Any) -> np.random.Generator:
    return np.random.default_rng([t.seed, zlib.crc32(tag.encode()), zlib.crc32(str(run).encode())])


def operating_point(
    t: VibratoryTruth, kind: str, c: Mapping[str, Any], latitude_deg: float
) -> tuple[float, float]:
    """(K in mV/(°/s), bias in °/s, earth rate included) for a segment's conditions."""
    K, b = t.K_mV_per_dps, t.bias_dps
    T = condition_value(c, "temperature", "degC", 20.0)
    K *= 1 + t.sf_temp_per_degC * (T - 20.0)
    b += t.bias_temp_dps_per_degC * (T - 20.0)
    run = c.get("run")
    if run is not None and kind in ("rate-repeat", "static-repeat"):
        rng = run_rng(t, kind, run)
        K *= 1 + t.sf_repeat_rel * rng.standard_normal()
        b += t.bias_repeat_dps * rng.standard_normal()
    elif t.power_on_variation and kind not in ("misalignment", "angular-vibration", "startup"):
        rng = run_rng(t, kind, power_on_key(kind, c))
        K *= 1 + t.sf_repeat_rel * rng.standard_normal()
        b += t.bias_repeat_dps * rng.standard_normal()
    axis = str(c.get("axis", "Z")).upper()
    orient = str(c.get("orientation", "up")).lower()
    sign = -1.0 if "down" in orient else 1.0
    if kind == "rate-accel":  # IRA (Z) up or down: ±1 g along the input axis
        K += t.sf_accel_mV_dps_per_g * sign
        b += t.bias_accel_dps_per_g[2] * sign
    if kind == "static-accel":
        b += t.bias_accel_dps_per_g[AXES.index(axis)] * sign
    phase = str(c.get("phase", "before")).lower()
    if phase == "after" and kind in (
        "rate-shock",
        "rate-vibration",
        "static-shock",
        "static-vibration",
    ):
        i = AXES.index(axis)
        if kind == "rate-shock":
            K += t.sf_shock_mV_dps[i]
        elif kind == "rate-vibration":
            K += t.sf_vib_mV_dps[i]
        elif kind == "static-shock":
            b += t.bias_shock_dps[i]
        else:
            b += t.bias_vib_dps[i]
    # earth rate along the input axis: vertical input axis (IRA up/down); in the X/Y pairs of
    # the acceleration test the input axis is horizontal and set east–west (no component)
    ira_vertical = not (kind == "static-accel" and axis != "Z")
    if ira_vertical and kind not in ("misalignment", "angular-vibration"):
        b += sign * EARTH_RATE_DEG_PER_H / 3600.0 * math.sin(math.radians(latitude_deg))
    return K, b


#: conditions that do not start a new power-on, by kind: the chamber's points of 7.2.5 / 7.2.16
#: (their c): "在校准过程中，陀螺始终处于工作状态", the gyro works throughout) and the
#: flips of 7.2.6 / 7.2.17 (b) powers on once, c) turns the table) share one power-on
SAME_POWER_ON = {
    "rate-temperature": ("temperature",),
    "static-temperature": ("temperature",),
    "rate-accel": ("orientation", "axis"),
    "static-accel": ("orientation", "axis"),
}


def power_on_key(kind: str, c: Mapping[str, Any]) -> str:
    """Which power-on a segment belongs to: one calibration or record is one power-on, so every
    condition but the rate (and the resolution's increment) names it (7.2.7/7.2.8 one per axis and
    phase, …) — except where the clause keeps the gyro on across them (:data:`SAME_POWER_ON`: 7.2.5
    and
    7.2.16 one power-on through the chamber, 7.2.6 and 7.2.17 one for all the flips)."""
    same = ("rate", "increment", "base_rate") + SAME_POWER_ON.get(kind, ())
    return ";".join(f"{k}={c[k]}" for k in sorted(c) if k not in same)


def misalignment_angles(t: VibratoryTruth, run: Any) -> tuple[float, float]:
    """(α, β) in rad of one mounting run (the mounting repeatability draw)."""
    if t.misalign_repeat_rad <= 0:
        return t.misalign_alpha_rad, t.misalign_beta_rad
    rng = run_rng(t, "misalignment", run)
    return (
        t.misalign_alpha_rad + t.misalign_repeat_rad * rng.standard_normal(),
        t.misalign_beta_rad + t.misalign_repeat_rad * rng.standard_normal(),
    )


def mean_output(t: VibratoryTruth, kind: str, c: Mapping[str, Any], latitude_deg: float) -> float:
    """Noiseless mean output (mV) of a rate-type or static segment."""
    K, b = operating_point(t, kind, c, latitude_deg)
    if kind == "resolution":
        base = condition_value(c, "base_rate", "deg/s")
        d = condition_value(c, "increment", "deg/s")
        return float(steady_output(t, base, K=K, bias_dps=b) + K * increment_gain(t, d) * d)
    omega = condition_value(c, "rate", "deg/s", 0.0)
    if kind == "misalignment":
        a, be = misalignment_angles(t, c.get("run", 1))
        pos = int(c["position"])
        proj = {
            1: a + t.fixture_error_rad[0],
            2: -a + t.fixture_error_rad[0],
            3: be + t.fixture_error_rad[1],
            4: -be + t.fixture_error_rad[1],
        }[pos]
        omega = omega * math.sin(proj)
    return float(steady_output(t, omega, K=K, bias_dps=b))


def white_rate(rng, n: int, interval_s: float, arw: float) -> np.ndarray:
    """White rate noise (°/s) of angle random walk ``arw`` (°/√h) sampled every ``interval_s``."""
    if arw <= 0:
        return np.zeros(n)
    return rng.normal(0.0, arw / (60.0 * math.sqrt(interval_s)), size=n)


def flicker_rate(rng, n: int, interval_s: float, B_deg_h: float) -> np.ndarray:
    """Flicker (1/f) rate noise (°/s) of bias instability B (°/h).

    IEEE Std 952 C.3 writes the two-sided PSD S_Ω(f) = (B²/2π)/|f|, i.e. the one-sided
    B²/(π f), whose Allan variance is (2 ln 2/π)·B² for Δt ≪ τ (2 ln 2·h₋₁ with h₋₁ = B²/π).
    Drawn in the frequency domain over 8n samples (so the spectrum reaches 1/(8n·Δt) and the
    plateau holds up to τ ≈ n·Δt/4) and cut to the first n."""
    if B_deg_h <= 0 or n < 4:
        return np.zeros(n)
    m = 8 * n
    f = np.fft.rfftfreq(m, interval_s)
    S = np.zeros_like(f)
    S[1:] = B_deg_h**2 / (math.pi * f[1:])
    amp = np.sqrt(S * m / (2.0 * interval_s))
    X = amp * (rng.standard_normal(f.size) + 1j * rng.standard_normal(f.size)) / math.sqrt(2.0)
    if m % 2 == 0:  # the Nyquist bin is real
        X[-1] = amp[-1] * rng.standard_normal()
    return np.fft.irfft(X, m)[:n] / 3600.0


def static_noise(t: VibratoryTruth, rng, n: int, interval_s: float) -> np.ndarray:
    """Rate noise (°/s) of a static record: ARW + quantization + bias instability + RRW + ramp."""
    w = white_rate(rng, n, interval_s, t.arw_deg_rt_h)
    if t.bias_instability_deg_h > 0:
        w += flicker_rate(rng, n, interval_s, t.bias_instability_deg_h)
    if t.quantization_arcsec > 0:
        theta = rng.normal(0.0, t.quantization_arcsec / 3600.0, size=n + 1)  # °
        w += np.diff(theta) / interval_s
    if t.rrw_deg_h_rt_h > 0:
        step = t.rrw_deg_h_rt_h * math.sqrt(interval_s / 3600.0) / 3600.0  # °/s per sample
        w += np.cumsum(rng.normal(0.0, step, size=n))
    if t.rate_ramp_deg_h2 > 0:
        tt = (np.arange(n) + 0.5) * interval_s
        w += t.rate_ramp_deg_h2 * (tt / 3600.0) / 3600.0  # R·t in °/h, as °/s
    return w


def simulate_segment(
    t: VibratoryTruth,
    kind: str,
    c: Mapping[str, Any],
    n: int,
    interval_s: float,
    latitude_deg: float,
    rng: np.random.Generator,
) -> dict[str, tuple[np.ndarray, str]]:
    """The columns of one segment (``output`` in mV; ``reference`` in °/s on the angular
    vibration table)."""
    if kind == "angular-vibration":
        f = condition_value(c, "frequency", "Hz")
        A = condition_value(c, "amplitude", "deg/s")
        K, b = operating_point(t, kind, c, latitude_deg)
        tt = np.arange(n) * interval_s
        ph = rng.uniform(-math.pi, math.pi)
        w = 2 * math.pi * f
        T = 1.0 / (2 * math.pi * t.bandwidth_hz)
        gain = 1.0 / math.sqrt(1 + (w * T) ** 2)
        lag = math.atan(w * T) + w * t.delay_s
        ref = A * np.cos(w * tt + ph) + rng.normal(0.0, t.ref_noise_dps, n)
        out = (
            K * b
            + K * A * gain * np.cos(w * tt + ph - lag)
            + K * white_rate(rng, n, interval_s, t.arw_deg_rt_h)
        )
        return {"output": (out, "mV"), "reference": (ref, "deg/s")}
    if kind == "startup":
        K, b = operating_point(t, kind, c, latitude_deg)
        omega = condition_value(c, "rate", "deg/s", 0.0)
        tt = (np.arange(n) + 1) * interval_s
        out = (
            steady_output(t, omega, K=K, bias_dps=b)
            + K * t.startup_excursion_dps * np.exp(-tt / t.startup_tau_s)
            + K * white_rate(rng, n, interval_s, t.arw_deg_rt_h)
        )
        return {"output": (np.asarray(out, dtype=float), "mV")}
    m = mean_output(t, kind, c, latitude_deg)
    K, _ = operating_point(t, kind, c, latitude_deg)
    if kind.startswith("static"):
        noise = static_noise(t, rng, n, interval_s)
    else:
        noise = white_rate(rng, n, interval_s, t.arw_deg_rt_h)
    return {"output": (m + K * noise, "mV")}

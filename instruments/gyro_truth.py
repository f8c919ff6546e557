"""The virtual optical gyro's declared truth (:class:`GyroTruth`), the grades of unit the simulated
station offers (:data:`GRADES`) and the device classes it draws from (:data:`DEVICE_CLASSES`,
:func:`draw_device`)."""

from __future__ import annotations

from typing import Any, Mapping

import attrs
import numpy as np

from metro.core.base.units import Q_

from .stations import device_class_fields


#: the grades of device the station simulates (station option ``grade``; values in :data:`GRADES`)
GRADE_NAMES = ("typical", "marginal", "failing")


@attrs.frozen
class GyroTruth:
    """The simulated gyro's declared truth (magnitudes in the units in their names).

    The defaults are the ``typical`` grade: a typical aviation-grade ring-laser gyro that conforms
    to GB/T 45570 table A.1 (aviation column) with margin — every A.1 quantity its items measure
    lies
    within the row's limit by more than the result's U on ordinary seeds
    (docs/standards/gbt45570.md,
    "The simulated device").  :data:`GRADES` holds the ``marginal`` and ``failing`` units.
    """

    scale_factor_P_per_arcsec: float = 5.0
    bias_deg_h: float = 0.12
    arw_deg_rt_h: float = 0.0003
    gm_sigma_deg_h: float = 0.0
    gm_tau_s: float = 600.0
    rrw_deg_h_rt_h: float = 0.0
    bias_tc_deg_h_per_C: float = 0.0004
    temp_ref_C: float = 20.0
    mag_sens_deg_h_per_mT: tuple[float, float, float] = (
        0.04,
        0.015,
        0.025,
    )  # field along IRA, XRA, YRA
    turn_on_sigma_deg_h: float = 0.0015
    # scale factor of the pulse output against rate Ω (°/s) and direction s = ±1:
    # K_s(Ω) = K · (1 + sf_slope·Ω + sf_quadratic·(Ω/400)² + s·sf_asymmetry/2)
    sf_slope_per_deg_s: float = 2e-9
    sf_quadratic: float = 3e-6
    sf_asymmetry: float = 2e-6
    # --- scale-factor repeatability, temperature sensitivity and input-axis misalignment
    # (GB/T 45570 D.1.4–D.1.6, D.2.4–D.2.6; motions in instruments/sim_gbt_rate.py) ---
    sf_turn_on_sigma: float = (
        1e-6  # relative scatter of K between power-ons (per `run`, per D.1.5 point)
    )
    sf_tc_per_C: float = 1e-7  # relative change of K per °C about temp_ref_C (linear)
    misalign_alpha_arcsec: float = 40.0  # IA tilted from IRA towards XRA (α of fig. D.1)
    misalign_beta_arcsec: float = -25.0  # IA tilted from IRA towards YRA (β)
    fixture_tilt_arcsec: tuple[float, float] = (
        90.0,
        -60.0,
    )  # XRA-up, YRA-up fixture errors (cancelled by 180°)
    # --- end of the D.1.4–D.1.6 / D.2 block ---
    # --- threshold, environmental response, set-up and power (GB/T 45570 D.4, D.6.1–D.6.4,
    # 6.2.7.7, 6.2.7.8; motions in instruments/sim_gbt_env.py) ---
    dead_band_deg_h: float = 0.0005  # response r = sign(Ω)·max(|Ω| − d, 0): threshold (50 %) at 2d
    vib_shift_during_deg_h: tuple[float, float, float] = (
        0.02,
        0.012,
        0.015,
    )  # while vibrating along IRA, XRA, YRA
    vib_shift_after_deg_h: tuple[float, float, float] = (
        0.006,
        0.004,
        0.005,
    )  # after performance vibration
    vib_endurance_shift_deg_h: tuple[float, float, float] = (
        0.01,
        0.007,
        0.008,
    )  # after endurance vibration
    shock_shift_deg_h: tuple[float, float, float] = (
        0.008,
        0.005,
        0.006,
    )  # after the shocks along each axis
    setup_transient_deg_h: float = 300.0  # bias excess at switch-on, decaying exponentially …
    setup_tau_s: float = 1.5  # … with this time constant (set-up time ≈ τ·ln(A/tolerance))
    power_supplies: tuple[tuple[float, float], ...] = (
        (5.0, 0.24),
        (15.0, 0.06),
        (-15.0, -0.02),
    )  # (V, A)
    power_noise_rel: float = 0.002  # relative noise of each voltage and current sample
    # --- end of the D.4 / D.6 / set-up / power block ---
    output: str = attrs.field(
        default="pulse", validator=attrs.validators.in_(("pulse", "digital", "rate"))
    )
    lsb_per_deg_s: float = 5000.0
    # --- how the output is quantized (device classes, see DEVICE_CLASSES) ---
    # pulse output: True reads the accumulated angle at a random phase each sample (a dithered ring
    # laser gyro, white quantization error); False at a fixed phase, so the leftover fraction of a
    # pulse drifts with the earth rate and the quantization error is a slow sawtooth
    dither: bool = True
    # LSB output: True adds a uniform ±½ LSB dither before the word is rounded (its mean is then
    # unbiased whatever the noise); False rounds the rate as it is
    lsb_dither: bool = False
    # rate output: the unit of the output column and its resolution in that unit (0: unquantized)
    rate_unit: str = attrs.field(
        default="deg/h", validator=attrs.validators.in_(("deg/h", "deg/s"))
    )
    rate_resolution: float = attrs.field(default=0.0, validator=attrs.validators.ge(0.0))
    # relative scale-factor and bias changes between mountings (D.1.6/D.2.6 axis_up/turn and D.5
    # orientations): drawn per mounting, seeded by (seed, mounting)
    sf_mount_sigma: float = 0.0
    bias_mount_sigma_deg_h: float = 0.0
    # the device class this truth was made from ("" when set field by field)
    device_class: str = ""
    # GB/T 45570 5.2.9 / 6.2.6: +1 when the output grows while the gyro turns counter-clockwise
    # about
    # +IA (right-hand rule); −1 a reversed gyro (every output column is negated)
    polarity: int = attrs.field(default=1, validator=attrs.validators.in_((1, -1)))
    #: which unit this is (:data:`GRADE_NAMES`; the station option ``grade`` takes its values from
    #: :data:`GRADES`)
    grade: str = attrs.field(default="typical", validator=attrs.validators.in_(GRADE_NAMES))
    #: the device's data sheet states its turn-on scatter (bias and K repeatability, 1σ, as from an
    #: earlier
    #: D.5.3 / D.1.4): ``[device] bias_repeatability`` / ``scale_factor_repeatability``
    states_repeatability: bool = True
    seed: int = 20251122

    def as_quantities(self) -> dict[str, Any]:
        out = {
            "bias B0": Q_(self.bias_deg_h, "deg/h"),
            "angle random walk": Q_(self.arw_deg_rt_h, "deg/hour**0.5"),
            "Gauss–Markov bias wander σ": Q_(self.gm_sigma_deg_h, "deg/h"),
            "Gauss–Markov correlation time": Q_(self.gm_tau_s, "s"),
            "rate random walk": Q_(self.rrw_deg_h_rt_h, "deg/h/hour**0.5"),
            "bias temperature coefficient": Q_(self.bias_tc_deg_h_per_C, "deg/h/delta_degC"),
            "bias magnetic sensitivity (IRA, XRA, YRA)": ", ".join(
                f"{v:g}" for v in self.mag_sens_deg_h_per_mT
            )
            + " °/h/mT",
            "turn-on bias σ (per power-on)": Q_(self.turn_on_sigma_deg_h, "deg/h"),
            "scale-factor slope (relative per °/s)": self.sf_slope_per_deg_s,
            "scale-factor quadratic term at 400 °/s (relative)": self.sf_quadratic,
            "scale-factor asymmetry (relative)": self.sf_asymmetry,
            "scale-factor turn-on σ (relative, per power-on)": self.sf_turn_on_sigma,
            "scale-factor temperature coefficient": Q_(self.sf_tc_per_C, "1/delta_degC"),
            "input-axis misalignment α, β": f"{self.misalign_alpha_arcsec:g}″, "
            f"{self.misalign_beta_arcsec:g}″",
            "fixture tilt (XRA-up, YRA-up mountings)": ", ".join(
                f"{v:g}″" for v in self.fixture_tilt_arcsec
            ),
            "seed": self.seed,
            "output": self.output,
            "device class": self.device_class or "(fields as given)",
            "quantization": quantization_text(self),
            "polarity (6.2.6)": "positive" if self.polarity > 0 else "negative",
            "grade": device_description(self),
        }
        if self.output == "pulse":
            out["scale factor K"] = Q_(self.scale_factor_P_per_arcsec, "P/arcsec")
        elif self.output == "digital":
            out["scale factor K"] = Q_(self.lsb_per_deg_s, "LSB/(deg/s)")
        return out


def quantization_text(truth: GyroTruth) -> str:
    """One line on how the output is quantized (for the truth table)."""
    if truth.output == "pulse":
        w = 1.0 / truth.scale_factor_P_per_arcsec
        return f"1 P = {w:.4g}″, " + (
            "dithered readout" if truth.dither else "undithered (fixed readout phase)"
        )
    if truth.output == "digital":
        q = 3600.0 / truth.lsb_per_deg_s
        return f"1 LSB = {q:.4g} °/h, " + (
            "±½ LSB dither" if truth.lsb_dither else "rounded, no dither"
        )
    res = (
        f"{truth.rate_resolution:g} {truth.rate_unit}"
        if truth.rate_resolution > 0
        else "unquantized"
    )
    return f"rate in {truth.rate_unit}, resolution {res}"


#: the units the station simulates by ``grade`` (fields that differ from :class:`GyroTruth`'s
#: defaults, which
#: are the ``typical`` unit).  ``marginal`` is the station's default unit before issue 29 (an angle
#: random walk
#: on table A.1's aviation limit, 1 P = 1.25″: B_s(100 s) ≈ 0.011 (°)/h fails row 10, RWC = 0.0015
#: (°)/h^½ is
#: indeterminate by design); the device classes (:data:`DEVICE_CLASSES`) vary it.  ``failing``
#: fails rows 5,
#: 10, 12 and 14 of the aviation column outright.
GRADES: Mapping[str, Mapping[str, Any]] = {
    "typical": {"grade": "typical"},
    "marginal": {
        "grade": "marginal",
        "scale_factor_P_per_arcsec": 0.8,
        "arw_deg_rt_h": 0.0015,
        "dead_band_deg_h": 0.0035,
        "turn_on_sigma_deg_h": 0.002,
        "bias_tc_deg_h_per_C": 0.0006,
        "sf_asymmetry": 4e-6,
        "sf_turn_on_sigma": 3e-6,
        "sf_tc_per_C": 3e-7,
        "states_repeatability": False,
    },
    "failing": {
        "grade": "failing",
        "scale_factor_P_per_arcsec": 0.8,
        "arw_deg_rt_h": 0.004,
        "dead_band_deg_h": 0.0035,
        "turn_on_sigma_deg_h": 0.002,
        "bias_tc_deg_h_per_C": 0.002,
        "sf_asymmetry": 4e-6,
        "sf_turn_on_sigma": 3e-6,
        "sf_tc_per_C": 1.5e-6,
    },
}


#: what each grade is, in the device's model name and the truth table
GRADE_TEXT: Mapping[str, str] = {
    "typical": "typical aviation-grade unit, conforms to table {table}",
    "marginal": "marginal unit: near or beyond the limits of table {table}",
    "failing": "failing unit: does not conform to table {table}",
}


def device_description(truth: GyroTruth) -> str:
    """The simulated device's model name: what it is and how it stands against GB/T 45570's table
    of its
    technology (A.1 for the pulse-output ring-laser gyro, B.1 for a fibre gyro's LSB or rate
    output)."""
    laser = truth.output == "pulse"
    what = "virtual ring-laser gyro" if laser else "virtual fibre-optic gyro"
    return f"{what} ({GRADE_TEXT[truth.grade].format(table='A.1' if laser else 'B.1')})"


#: a fibre-optic gyro with a digital output and a scale-factor nonlinearity above 5 × 10⁻⁶, which
#: 6.2.7.1 sends to the rate method (D.2) — the ``simulated-digital`` station's defaults
DIGITAL_DEFAULTS: Mapping[str, Any] = {
    "output": "digital",
    "sf_quadratic": 3e-5,
    "sf_slope_per_deg_s": 2e-8,
    "sf_asymmetry": 2e-5,
    "sf_tc_per_C": 2e-6,
    "sf_turn_on_sigma": 5e-6,
}


_MOUNTING = {"sf_mount_sigma": 2e-6, "bias_mount_sigma_deg_h": 0.003}


#: device classes: what real optical gyros vary — output kind, quantization coarse and fine,
#: dither on and off — as station-option presets (``device_class=NAME``).  A class is a population:
#: each seed draws one device of it (see :func:`draw_device`).  Options given with the class
#: override its values.
DEVICE_CLASSES: Mapping[str, Mapping[str, Any]] = {
    # ring-laser gyro, 0.8 P/″ (1 P = 1.25″), dithered readout — the ``marginal`` grade
    "pulse-fine": {"output": "pulse"} | _MOUNTING,
    # the same counted at a fixed phase: the leftover fraction drifts with the earth rate
    "pulse-fine-undithered": {"output": "pulse", "dither": False} | _MOUNTING,
    # 0.05 P/″ (1 P = 20″, about 2 s of earth rate), dithered / undithered
    "pulse-coarse": {"output": "pulse", "scale_factor_P_per_arcsec": 0.05} | _MOUNTING,
    "pulse-coarse-undithered": {
        "output": "pulse",
        "scale_factor_P_per_arcsec": 0.05,
        "dither": False,
    }
    | _MOUNTING,
    # fibre gyro, LSB word: 1 LSB = 0.0072 °/h (finer than the noise) and 0.72 °/h (coarser),
    # rounded
    "lsb-fine": dict(DIGITAL_DEFAULTS) | {"lsb_per_deg_s": 500000.0} | _MOUNTING,
    "lsb-coarse": dict(DIGITAL_DEFAULTS) | _MOUNTING,
    "lsb-coarse-dithered": dict(DIGITAL_DEFAULTS) | {"lsb_dither": True} | _MOUNTING,
    # rate output in °/h (resolution 0.001 °/h) and in °/s (resolution 10⁻⁶ °/s = 0.0036 °/h)
    "rate-dh": {"output": "rate", "rate_unit": "deg/h", "rate_resolution": 0.001} | _MOUNTING,
    "rate-ds": {"output": "rate", "rate_unit": "deg/s", "rate_resolution": 1e-6} | _MOUNTING,
}


def draw_device(device_class: str, seed: int) -> dict[str, Any]:
    """The truth fields of one device of ``device_class``, drawn with ``seed``: the class's values,
    then a bias uniform in ±0.5 °/h, a scale factor within ±0.2 % of the class's and an angle random
    walk 0.7 … 1.5 times the marginal unit's (so a sweep over seeds sees where the quantization
    falls);
    the other fields are the ``marginal`` grade's (:data:`GRADES`), the unit the classes were built
    on."""
    kw = dict(GRADES["marginal"]) | device_class_fields(device_class, DEVICE_CLASSES)
    base = GyroTruth(**GRADES["marginal"])
    rng = np.random.default_rng([int(seed), 4099])
    kw["bias_deg_h"] = float(rng.uniform(-0.5, 0.5))
    sf = 1.0 + float(rng.uniform(-0.002, 0.002))
    if kw.get("output") == "digital":
        kw["lsb_per_deg_s"] = float(kw.get("lsb_per_deg_s", base.lsb_per_deg_s)) * sf
    elif kw.get("output") == "pulse":
        kw["scale_factor_P_per_arcsec"] = (
            float(kw.get("scale_factor_P_per_arcsec", base.scale_factor_P_per_arcsec)) * sf
        )
    kw["arw_deg_rt_h"] = base.arw_deg_rt_h * float(rng.uniform(0.7, 1.5))
    kw["device_class"] = device_class
    return kw

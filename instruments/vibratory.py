"""A simulated test station for an analog (mV) metal-shell vibratory rate gyro (JJF 2014—2022).

The station holds a rate table with a temperature chamber, a two-axis position table, a
shock machine, a linear vibration table, an angular vibration table with its reference
sensor, a 6½-digit DMM (the data acquisition) and a timer.  The virtual gyro's declared,
seeded truth is :class:`VibratoryTruth`; every segment is generated from it by
:func:`simulate_segment` from the segment's *kind* and *conditions*, which are exactly what
the ``jjf2014`` procedures put in their :class:`~metro.core.model.procedure.Step` lists.

The gyro's steady output for an input rate Ω (°/s) along its input axis is::

    r   = Ω·Ω²/(Ω² + Ω_th²)                          dead zone (threshold)  [r(0) = 0]
    r   = Ω if |Ω| ≥ Ω_th else 0                     with ``hard_dead_band`` (a dead band)
    F   = K_±·r + K·c·r³/Ω_fs² + K·b + noise         mV

with K_± = K(1 ± a/2) for r > 0 / r < 0 (asymmetry a), a cubic nonlinearity c relative to
full scale Ω_fs, and the bias b (°/s).  K and b depend on temperature (linear coefficients),
on gravity along the input axis, on the run (seeded repeatability draws), and change after
shock and vibration (per axis).  A rate increment ΔΩ on top of a steady rate is passed with
gain ΔΩ²/(ΔΩ² + r_res²) (a stick–slip resolution model), or with ``hard_dead_band`` passed
whole when |ΔΩ| ≥ r_res and not at all below.  Either way the response is exactly half (soft)
or jumps from none to all (hard) at Ω_th / r_res, so by the 50 % criterion of eqs. (17)/(18)
the device's threshold is Ω_th and its resolution r_res: those are the declared truth.  Dynamics:
first order with time
constant T = 1/(2π·B_w) in series with a pure delay T_d (JJF 2014 eq. (46), (47)).  Start-up:
the output settles as K·d₀·exp(−t/τ_s) after power-on.

Noise (static records): white rate noise of angle random walk N, white angle noise of
quantization Q (σ_θ = Q, so σ²(τ) = 3Q²/τ²), flicker rate noise of bias instability B
(σ²(τ) ≈ (2 ln 2/π)B²), rate random walk K_rrw and a rate ramp R; on the
other records white rate noise only.  The earth rate (physical 15.04107 °/h) adds
Ω_e·sin φ to the input when the input axis points up (rate table, bias records), as it
physically does; the jjf2014 bias items leave it in unless asked to remove it.

``expected`` values are computed here, independently of the plugin's code, by applying the
standard's definitions to the noiseless model at the planned points.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np
from metro.core.model.campaign import Campaign, DeviceUnderTest, Equipment, Segment
from metro.core.model.procedure import Step
from metro.core.base.units import Q_

from metro.core.stats.earth import EARTH_RATE_DEG_PER_H  # noqa: E402  physical, 15.04107 °/h
from .stations import device_class_fields, drawn_station, simulated_campaign, simulated_device
from .vibratory_model import (AXES, SAME_POWER_ON, VibratoryTruth, condition_value, increment_gain,
                              mean_output, misalignment_angles, operating_point, power_on_key,
                              simulate_segment, static_noise, steady_output)


# ------------------------------------------------------------------------------ the model


# ------------------------------------------------------------------------------ expected


def _fit(om, F):
    A = np.column_stack([om, np.ones_like(om)])
    (K, F0), *_ = np.linalg.lstsq(A, F, rcond=None)
    return float(K), float(F0)


def largest_shift(by_axis_phase: Mapping[tuple[str, str], float]) -> float:
    """The largest change |after − before| over the axes recorded after a shock or vibration
    test, of values keyed by (axis, phase).

    >>> largest_shift({("X", "before"): 1.0, ("X", "after"): 1.5, ("Y", "before"): 2.0,
    ...                ("Y", "after"): 1.25, ("Z", "before"): 0.0})
    0.75
    """
    s = by_axis_phase
    return max(abs(s[(a, "after")] - s[(a, "before")]) for a in AXES if (a, "after") in s)


def _sets(steps, kind, key):
    out: dict[Any, list] = {}
    for s in steps:
        if s.kind == kind:
            out.setdefault(tuple(str(s.conditions.get(k)) for k in key), []).append(s)
    return out


def _sf_points(t: VibratoryTruth, group, kind: str, lat: float) -> tuple[np.ndarray, np.ndarray]:
    """The set rates (°/s) of ``group`` and the noiseless mean outputs (mV) there."""
    om = np.array([condition_value(s.conditions, "rate", "deg/s") for s in group])
    F = np.array([mean_output(t, kind, s.conditions, lat) for s in group])
    return om, F


def _expected_rate(
    t: VibratoryTruth, rate: list[Step], lat: float, nonlinearity_spec: float
) -> dict[str, Any]:
    """K, F₀, K_n, the input range (the largest span within the nonlinearity spec) and K_a."""
    ex: dict[str, Any] = {}
    om, F = _sf_points(t, rate, "rate", lat)
    K, F0 = _fit(om, F)
    ex["K"], ex["F0"] = Q_(K, "mV/(deg/s)"), Q_(F0, "mV")
    span = om.max() - om.min()
    ex["Kn"] = Q_(float(np.max(np.abs(K * om + F0 - F)) / (K * span)), "")
    mags = np.unique(np.abs(om))[::-1]
    rng_ = None
    for top in mags:
        sel = np.abs(om) <= top
        if np.any(om[sel] > 0) and np.any(om[sel] < 0) and sel.sum() >= 3:
            k, f0 = _fit(om[sel], F[sel])
            kn = np.max(np.abs(k * om[sel] + f0 - F[sel])) / (k * (om[sel].max() - om[sel].min()))
            if kn <= nonlinearity_spec:
                rng_ = top
                break
    if rng_ is not None:
        ex["range"] = Q_(float(rng_), "deg/s")
    kp, _ = _fit(om[om > 0], F[om > 0])
    km, _ = _fit(om[om < 0], F[om < 0])
    ex["Ka"] = Q_(abs(kp - km) / K, "")
    return ex


def _expected_k_sets(t: VibratoryTruth, steps: list[Step], lat: float) -> dict[str, Any]:
    """K_r, K_t, K_g and the scale-factor changes after shock and vibration."""
    ex: dict[str, Any] = {}

    def kset(kind, key):
        return {
            k: _fit(*_sf_points(t, g, kind, lat))[0] for k, g in _sets(steps, kind, key).items()
        }

    rep = kset("rate-repeat", ("run",))
    if len(rep) >= 2:
        v = np.array(list(rep.values()))
        ex["Kr"] = Q_(float(np.std(v, ddof=1) / np.mean(v)), "")
    temp = kset("rate-temperature", ("temperature",))
    if len(temp) >= 2:
        T = {k: condition_value({"t": k[0]}, "t", "degC") for k in temp}
        km = min(temp, key=lambda k: abs(T[k] - 20.0))
        ex["Kt"] = Q_(
            max(abs((temp[k] - temp[km]) / (temp[km] * (T[k] - T[km]))) for k in temp if k != km),
            "1/delta_degC",
        )
    acc = kset("rate-accel", ("orientation",))
    if len(acc) == 2:
        up = [v for k, v in acc.items() if "up" in k[0].lower()][0]
        dn = [v for k, v in acc.items() if "down" in k[0].lower()][0]
        ex["Kg"] = Q_((up - dn) / 2.0, "mV/(deg/s)/gn")
    for kind, key in (("rate-shock", "dK_shock"), ("rate-vibration", "dK_vib")):
        s = kset(kind, ("axis", "phase"))
        if s:
            ex[key] = Q_(largest_shift(s), "mV/(deg/s)")
    return ex


def _expected_static(
    t0: VibratoryTruth, t: VibratoryTruth, static: list[Step], lat: float, Kn: float
) -> dict[str, Any]:
    """B₀ of 7.2.13 and the noise terms of the static record."""
    # B₀ of 7.2.13 is the bias of this record's power-on (interpretations.md, "7.2.13"): its turn-on
    # draw is part of the truth (the record's K differs from 7.2.1's: that is error, K_r's row)
    own = (
        operating_point(t0, "static", static[0].conditions, lat)[1]
        - operating_point(t, "static", static[0].conditions, lat)[1]
    )
    return {
        "B0": Q_(
            (mean_output(t, "static", static[0].conditions, lat) / Kn + own) * 3600.0, "deg/h"
        ),
        "ARW": Q_(t.arw_deg_rt_h, "deg/hour**0.5"),
        "Q": Q_(t.quantization_arcsec, "arcsec"),
        "RRW": Q_(t.rrw_deg_h_rt_h, "deg/h/hour**0.5"),
        "RR": Q_(t.rate_ramp_deg_h2, "deg/h**2"),
        "BI": Q_(t.bias_instability_deg_h, "deg/h"),
    }


def _expected_bias_sets(
    t: VibratoryTruth, steps: list[Step], lat: float, Kn: float
) -> dict[str, Any]:
    """B_r, B_t, B_g and the bias changes after shock and vibration."""
    ex: dict[str, Any] = {}

    def bset(kind, key):
        return {
            k: mean_output(t, kind, g[0].conditions, lat) / Kn * 3600.0
            for k, g in _sets(steps, kind, key).items()
        }

    br = bset("static-repeat", ("run",))
    if len(br) >= 2:
        ex["Br"] = Q_(float(np.std(list(br.values()), ddof=1)), "deg/h")
    bt = bset("static-temperature", ("temperature",))
    if len(bt) >= 2:
        T = {k: condition_value({"t": k[0]}, "t", "degC") for k in bt}
        km = min(bt, key=lambda k: abs(T[k] - 20.0))
        ex["Bt"] = Q_(
            max(abs((bt[k] - bt[km]) / (T[k] - T[km])) for k in bt if k != km), "deg/h/delta_degC"
        )
    bg = bset("static-accel", ("axis", "orientation"))
    if bg:
        vals = []
        for a in AXES:
            up = [v for k, v in bg.items() if k[0] == a and "up" in k[1].lower()]
            dn = [v for k, v in bg.items() if k[0] == a and "down" in k[1].lower()]
            if up and dn:
                vals.append(abs(up[0] - dn[0]) / 2.0)
        ex["Bg"] = Q_(max(vals), "deg/h/gn")
    for kind, key in (("static-shock", "dB_shock"), ("static-vibration", "dB_vib")):
        s = bset(kind, ("axis", "phase"))
        if s:
            ex[key] = Q_(largest_shift(s), "deg/h")
    return ex


def _expected_misalignment(t: VibratoryTruth, steps: list[Step]) -> dict[str, Any]:
    """γ of the first run and, with two runs or more, its scatter γ_r."""
    ex: dict[str, Any] = {}
    mis = _sets(steps, "misalignment", ("run",))
    if mis:
        gam = []
        for run in mis:
            a, b = misalignment_angles(t, run[0] if run[0] != "None" else 1)
            gam.append(math.degrees(math.hypot(a, b)) * 60.0)
        ex["gamma"] = Q_(gam[0], "arcmin")
        if len(gam) >= 2:
            ex["gamma_r"] = Q_(float(np.std(gam, ddof=1)), "arcmin")
    return ex


def _last_passing(pairs, K):
    """Largest-first run of levels with |(KΩ − F)/(KΩ)| ≤ 50 % (eqs. (17), (18)): its last level."""
    last = None
    for om, f in sorted(pairs, key=lambda p: -abs(p[0])):
        if abs((K * om - f) / (K * om)) > 0.5:
            break
        last = abs(om)
    return last


def _expected_threshold(
    t: VibratoryTruth, steps: list[Step], lat: float, K: float
) -> dict[str, Any]:
    """The threshold of 7.2.9: the device's Ω_th and the last passing level of the planned steps."""
    f0 = mean_output(t, "threshold", {"rate": "0 deg/s"}, lat)
    lv = [
        s
        for s in steps
        if s.kind == "threshold" and condition_value(s.conditions, "rate", "deg/s") != 0
    ]
    c = [
        _last_passing(
            [
                (
                    condition_value(s.conditions, "rate", "deg/s"),
                    mean_output(t, "threshold", s.conditions, lat) - f0,
                )
                for s in lv
                if np.sign(condition_value(s.conditions, "rate", "deg/s")) == sg
            ],
            K,
        )
        for sg in (1, -1)
    ]
    if not all(x is not None for x in c):
        return {}
    # the device's threshold by the 50 % criterion is Ω_th; the last passing level of the
    # planned (noiseless) sequence is what 7.2.9 reports, one level step above it at most
    return {"threshold": Q_(t.threshold_dps, "deg/s"), "threshold_grid": Q_(max(c), "deg/s")}


def _expected_resolution(
    t: VibratoryTruth, steps: list[Step], lat: float, K: float
) -> dict[str, Any]:
    """The resolution of 7.2.10: the device's and the last passing increment of the planned
    steps."""
    c = []
    for sg in (1, -1):
        mine = [
            s
            for s in steps
            if s.kind == "resolution"
            and np.sign(condition_value(s.conditions, "base_rate", "deg/s")) == sg
        ]
        base = [s for s in mine if condition_value(s.conditions, "increment", "deg/s") == 0]
        if not base:
            continue
        fb = mean_output(t, "resolution", base[0].conditions, lat)
        c.append(
            _last_passing(
                [
                    (
                        condition_value(s.conditions, "increment", "deg/s"),
                        mean_output(t, "resolution", s.conditions, lat) - fb,
                    )
                    for s in mine
                    if condition_value(s.conditions, "increment", "deg/s") != 0
                ],
                K,
            )
        )
    if not (c and all(x is not None for x in c)):
        return {}
    return {"resolution": Q_(t.resolution_dps, "deg/s"), "resolution_grid": Q_(max(c), "deg/s")}


def expected_values(
    t: VibratoryTruth, steps: list[Step], lat: float, nonlinearity_spec: float
) -> dict[str, Any]:
    """An ideal (noiseless) evaluation of the planned steps, by the standard's definitions.  The
    truth is the device's own K and bias: a power-on's draw (``power_on_variation``) is an error of
    that calibration, not the device's value (the repeats of 7.2.4 / 7.2.15 keep their draws, whose
    spread is what those items measure) — except the bias B₀ of 7.2.13, which is the static record's
    own power-on's."""
    t0, t = t, attrs.evolve(t, power_on_variation=False)
    ex: dict[str, Any] = {}
    rate = [s for s in steps if s.kind == "rate"]
    if rate:
        ex |= _expected_rate(t, rate, lat, nonlinearity_spec)
    ex |= _expected_k_sets(t, steps, lat)
    # the items divide by K as calibrated by 7.2.1 (the noiseless fit), not by the nominal K
    Kn = float(ex["K"].magnitude) if "K" in ex else t.K_mV_per_dps
    static = [s for s in steps if s.kind == "static"]
    if static:
        ex |= _expected_static(t0, t, static, lat, Kn)
    ex |= _expected_bias_sets(t, steps, lat, Kn)
    ex |= _expected_misalignment(t, steps)
    if rate and any(s.kind == "threshold" for s in steps):
        ex |= _expected_threshold(t, steps, lat, ex["K"].magnitude)
    if rate and any(s.kind == "resolution" for s in steps):
        ex |= _expected_resolution(t, steps, lat, ex["K"].magnitude)
    if any(s.kind == "angular-vibration" for s in steps):
        # eq. (47) model; 7.2.21 reads the curve at K = 0.707 (not 1/√2): f = B_w·√(1/0.707² − 1)
        ex["Bw"] = Q_(t.bandwidth_hz * math.sqrt(1 / 0.707**2 - 1), "Hz")
        ex["Td"] = Q_(t.delay_s, "s")
    return ex


# ------------------------------------------------------------------------------ station


@attrs.define
class VibratoryStation:
    """The simulated JJF 2014 station; ``acquire(steps)`` returns an in-memory campaign."""

    truth: VibratoryTruth = attrs.field(factory=VibratoryTruth)
    latitude_deg: float = 39.98
    duration_scale: float = 1.0
    nonlinearity_spec: float = 2e-4
    #: read the mV output through the station's DMM model (its gain and offset errors and 6½-digit
    #: rounding, :class:`metro.instruments.equipment.DigitalMultimeter`); off by default: appendix
    #: B's DMM term is relative to the reading and does not cover the meter's range (offset) error
    instrument_errors: bool = False
    #: the rate table turns at the rate it actually turns at (:meth:`RateTable.actual_rate`: a fixed
    #: error per set point inside its band and a per-sample ripple), drawn from the device's seed so
    #: that each seed is another table of the same certificate; off only to study the device alone
    table_errors: bool = True

    name = "simulated-jjf2014"

    def _models(self):
        from .kits import jjf2014_equipment

        return jjf2014_equipment(seed=self.truth.seed)

    def device(self) -> DeviceUnderTest:
        return simulated_device(
            self.truth.seed, "SIM-MVG-1", "virtual metal-shell vibratory rate gyro",
            properties={
                "full_scale": Q_(self.truth.full_scale_dps, "deg/s"),
                "nonlinearity_spec": Q_(self.nonlinearity_spec, ""),
            }
            | (
                {"supply_voltage": Q_(self.truth.ratiometric_supply_V, "V")}
                if self.truth.ratiometric_supply_V > 0
                else {}
            ),
            technology="vibratory",
            application="",
            output="analog",
        )

    def equipment(self) -> list[Equipment]:
        from .equipment import equipment_list

        return equipment_list(self._models())

    def _through_dmm(
        self, cols: dict[str, tuple[np.ndarray, str]]
    ) -> dict[str, tuple[np.ndarray, str]]:
        from .equipment import DigitalMultimeter

        dmm = next(m for m in self._models() if isinstance(m, DigitalMultimeter))
        arr, u = cols["output"]
        return cols | {"output": (np.asarray(dmm.read(Q_(arr, u)).to(u).magnitude, dtype=float), u)}

    def _on_table(
        self, st: Step, cols: dict[str, tuple[np.ndarray, str]], n: int, rng: np.random.Generator
    ) -> dict[str, tuple[np.ndarray, str]]:
        """The output of a segment run on the rate table, at the rate the table really turned at.

        The set point is the condition ``rate`` (``base_rate`` + ``increment`` for 7.2.10). The
        table's mean error shifts the steady output exactly (the device's model is evaluated at
        the scaled rate); its ripple, a relative 10⁻³ at most, enters through the local slope.
        """
        from .equipment import RateTable

        # static records turn nothing; the angular vibration table has its own reference sensor
        if st.kind == "angular-vibration" or st.kind.startswith("static"):
            return cols
        c = st.conditions
        names = ("base_rate", "increment") if st.kind == "resolution" else ("rate",)
        om = sum(condition_value(c, k, "deg/s", 0.0) for k in names)
        if om == 0.0:
            return cols
        table = next(m for m in self._models() if isinstance(m, RateTable))
        w = table.actual_rate(Q_(om, "deg/s"), n, rng).to("deg/s").magnitude

        def out(scale: float) -> float:
            return mean_output(
                self.truth,
                st.kind,
                {
                    **c,
                    **{k: Q_(condition_value(c, k, "deg/s", 0.0) * scale, "deg/s") for k in names},
                },
                self.latitude_deg,
            )

        w_mean = float(np.mean(w))
        h = 1e-6
        slope = (out(1 + h) - out(1 - h)) / (2 * h * om)
        arr, u = cols["output"]
        shifted = arr + (out(w_mean / om) - out(1.0)) + slope * (w - w_mean)
        return cols | {"output": (np.asarray(shifted, dtype=float), u)}

    #: the JJF 2014 step kinds this station simulates
    KINDS = (
        "rate",
        "rate-repeat",
        "rate-temperature",
        "rate-accel",
        "rate-shock",
        "rate-vibration",
        "threshold",
        "resolution",
        "misalignment",
        "static",
        "static-repeat",
        "static-temperature",
        "static-accel",
        "static-shock",
        "static-vibration",
        "angular-vibration",
        "startup",
    )

    def check(self, steps, *, items=None) -> None:
        """Refuse, before anything is simulated, a step kind this station does not simulate."""
        from .stations import refuse_unknown_kinds

        refuse_unknown_kinds(self.name, steps, self.KINDS, items=items)

    def acquire(self, steps: list[Step], *, progress=None) -> Campaign:
        from .stations import step_seed

        self.check(steps)
        t = self.truth
        segs = []
        for k, st in enumerate(steps):
            i = step_seed(st)  # the step's identity, not its place in the list, seeds its noise
            dt_ = float(st.interval.to("s").magnitude)
            n_full = int(round(float(st.duration.to("s").magnitude) / dt_))
            scale = self.duration_scale if st.kind.startswith("static") else 1.0
            n = max(10, int(round(n_full * scale)))
            rng = np.random.default_rng([t.seed, i])
            cols = simulate_segment(t, st.kind, st.conditions, n, dt_, self.latitude_deg, rng)
            if self.table_errors:
                cols = self._on_table(st, cols, n, np.random.default_rng([t.seed, i, 1]))
            if self.instrument_errors:
                cols = self._through_dmm(cols)
            if t.output_lsb_mV > 0:
                arr, u = cols["output"]
                cols = cols | {"output": (np.round(arr / t.output_lsb_mV) * t.output_lsb_mV, u)}
            conditions = dict(st.conditions)
            if t.ratiometric_supply_V > 0:
                arr, u = cols["output"]
                cols = cols | {
                    "output": (
                        np.asarray(Q_(arr, u).to("mV").magnitude) / t.ratiometric_supply_V,
                        "mV/V",
                    )
                }
                conditions["supply"] = f"{t.ratiometric_supply_V:g} V"
            h = hashlib.sha256()
            for name in sorted(cols):
                h.update(cols[name][0].tobytes())
            segs.append(
                Segment(
                    id=st.segment,
                    kind=st.kind,
                    conditions=conditions,
                    interval=Q_(dt_, "s"),
                    sha256=h.hexdigest(),
                    loader=(lambda c=cols: c),
                )
            )
            if progress is not None:
                progress("simulating", k + 1, len(steps))
        return simulated_campaign(
            self, "SIMULATED-JJF2014", segs, source="simulated station (simulated-jjf2014)",
            environment={"location": "simulated laboratory"},
            expected=expected_values(t, steps, self.latitude_deg, self.nonlinearity_spec),
        )


#: device classes (station option ``device_class=NAME``): what real vibratory gyros vary, as
#: presets.
#: A class is a population: each seed draws one device of it (:func:`draw_device`); options given
#: with the class override its values.  The output is analog in every class — JJF 2014's items read
#: a
#: voltage — digitised finely or coarsely, or ratiometric (mV/V of the supply).
DEVICE_CLASSES: Mapping[str, Mapping[str, Any]] = {
    # the default device: only the 7.2.4 / 7.2.15 repeats vary between power-ons; output not rounded
    "analog-fine": {},
    # every calibration and record a power-on of its own: K (1σ 2×10⁻⁴) and the bias (1σ 3.6 °/h)
    # differ between them, as the repeatability items 7.2.4 and 7.2.15 assume
    "analog-power-on": {"power_on_variation": True, "sf_repeat_rel": 2e-4, "bias_repeat_dps": 1e-3},
    # the output digitised to 0.02 mV (≈ 3.6 °/h at 20 mV/((°)/s)), about the noise of a 1 s sample
    "analog-coarse": {"output_lsb_mV": 0.02},
    # the output digitised to 0.2 mV (≈ 36 °/h at 20 mV/((°)/s), a 14-bit word over ±2 V): coarser
    # than the
    # noise of a 1 s sample (0.02 … 0.05 mV), so the rounding of the 1 s records (7.2.1, 7.2.9,
    # 7.2.10,
    # 7.2.15 …) does not average out; about 0.4 … 0.8 of the noise of a 0.1 s sample (7.2.13,
    # 7.2.20)
    "analog-coarser": {"output_lsb_mV": 0.2},
    # a ratiometric output, recorded in mV/V of a 5 V supply (read back into mV with the declared
    # supply)
    "analog-ratiometric": {"ratiometric_supply_V": 5.0},
}


def draw_device(device_class: str, seed: int) -> dict[str, Any]:
    """The truth fields of one device of ``device_class`` drawn with ``seed``: the class's values,
    then K uniform in 15 … 25 mV/((°)/s), a bias uniform in ±0.1 °/s and an angle random walk
    0.7 … 1.5 times the default's."""
    base = VibratoryTruth()
    rng = np.random.default_rng([int(seed), 2014])
    kw = device_class_fields(device_class, DEVICE_CLASSES)
    kw["K_mV_per_dps"] = float(rng.uniform(15.0, 25.0))
    kw["bias_dps"] = float(rng.uniform(-0.1, 0.1))
    kw["arw_deg_rt_h"] = base.arw_deg_rt_h * float(rng.uniform(0.7, 1.5))
    kw["device_class"] = device_class
    return kw


def station_factory(**options: Any) -> VibratoryStation:
    """Factory of the ``simulated-jjf2014`` station (options: seed, any VibratoryTruth field,
    latitude_deg, duration_scale, nonlinearity_spec, instrument_errors, table_errors, and
    ``device_class`` — one of :data:`DEVICE_CLASSES`, drawn by the seed)."""
    return drawn_station(
        "simulated-jjf2014", VibratoryTruth, VibratoryStation, draw_device, options,
        ("latitude_deg", "duration_scale", "nonlinearity_spec", "instrument_errors",
         "table_errors"),
    )


__all__ = [
    "DEVICE_CLASSES",
    "draw_device",
    "power_on_key",
    "EARTH_RATE_DEG_PER_H",
    "VibratoryStation",
    "VibratoryTruth",
    "expected_values",
    "mean_output",
    "misalignment_angles",
    "operating_point",
    "simulate_segment",
    "station_factory",
    "steady_output",
    "increment_gain",
    "static_noise",
    "SAME_POWER_ON",
    "largest_shift",
]

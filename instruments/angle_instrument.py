"""A simulated optical-gyro angle measuring instrument on a low-speed turntable (station
``simulated-ogam``, registered by the ``ogam`` plugin).

The instrument integrates the rate its optical gyro senses about the turntable axis and shows
the angle turned since it was zeroed.  For a turntable stopped at standard angle S (°), reached
at elapsed time t after zeroing while turning at rate v, the angle the gyro senses is::

    φ = θ + a₁·sin θ + a₂·sin(2θ + β) + (sin²ψ/8)·sin 2θ + g·(v − 60 °/s)/(60 °/s)·θ
        + (b + η·Ω_axis)·t + w(t) + n

* θ = S + p the true table angle, p the turntable positioning error (uniform, ± ``positioning``);
* a₁, a₂ the instrument's position-dependent (harmonic) errors;
* (sin²ψ/8)·sin 2θ the sensing-plane/turntable-plane tilt error of the draft's appendix A 4.2
  in its small-angle form (ψ the tilt);
* g the rate dependence of the integration (relative scale error per 60 °/s off the reference);
* b the residual zero drift after warm-up, η the relative error of the earth-rate compensation
  and Ω_axis the earth-rate component along the axis (up: Ω sin φ_lat, north/south: ±Ω cos φ_lat,
  east/west: 0);
* w an angle random walk of coefficient ``arw`` (°/√h) and n white reading noise.

The instrument's output counts are C = round(K·φ) with K its true scale factor (counts/°, written
``P/deg``); its reading is M = C'/K_nom rounded to ``resolution``, where C' is the unrounded
count and K_nom = K/(1 + ε) the scale factor it was programmed with (ε its scale-factor error).

``expected`` holds what an ideal evaluation of the deterministic part gives (positioning error,
random walk and noise set to zero), computed here from the model, not from the plugin's code.
"""

from __future__ import annotations

import hashlib
import math
from collections.abc import Mapping
from typing import Any

import attrs
import numpy as np

from metro.api import (
    EARTH_RATE_DEG_PER_H, Q_, Campaign, DeviceUnderTest, Equipment, Segment, Step, parse_quantity,
)

from .stations import device_class_fields, drawn_station, simulated_campaign, simulated_device

AXES = ("up", "north", "south", "east", "west")


@attrs.frozen
class AngleInstrumentTruth:
    """Declared truth of the simulated angle instrument (magnitudes in the units in the names)."""

    K_P_per_deg: float = 20000.0
    scale_factor_error: float = 4e-8
    a1_arcsec: float = 0.08
    a2_arcsec: float = 0.05
    a2_phase_deg: float = 30.0
    tilt_deg: float = 0.05
    rate_coeff: float = 1.5e-8
    drift_deg_h: float = 1.0e-4
    earth_comp_error: float = 1.0e-5
    arw_deg_rt_h: float = 2.0e-5
    reading_noise_arcsec: float = 0.02
    positioning_arcsec: float = 0.1
    resolution_arcsec: float = 0.01
    #: the class this instrument was drawn from (station option ``device_class``; "" = fields as
    #: given)
    device_class: str = ""
    seed: int = 20261122

    def quiet(self) -> AngleInstrumentTruth:
        """The same instrument with every random term off (for the expected values)."""
        return attrs.evolve(
            self,
            arw_deg_rt_h=0.0,
            reading_noise_arcsec=0.0,
            positioning_arcsec=0.0,
            resolution_arcsec=0.0,
        )

    def as_quantities(self) -> dict[str, Any]:
        return {
            "scale factor K": Q_(self.K_P_per_deg, "P/deg"),
            "scale-factor error ε (programmed K_nom = K/(1+ε))": self.scale_factor_error,
            "harmonic error a₁ (sin θ)": Q_(self.a1_arcsec, "arcsec"),
            "harmonic error a₂ (sin(2θ+β))": Q_(self.a2_arcsec, "arcsec"),
            "sensing-plane tilt ψ": Q_(self.tilt_deg, "deg"),
            "rate coefficient g": self.rate_coeff,
            "residual zero drift b": Q_(self.drift_deg_h, "deg/h"),
            "earth-rate compensation error η": self.earth_comp_error,
            "angle random walk": Q_(self.arw_deg_rt_h, "deg/hour**0.5"),
            "reading noise": Q_(self.reading_noise_arcsec, "arcsec"),
            "turntable positioning error (±)": Q_(self.positioning_arcsec, "arcsec"),
            "reading resolution": Q_(self.resolution_arcsec, "arcsec"),
            "device class": self.device_class or "(fields as given)",
            "seed": self.seed,
        }


def earth_rate_along(axis: str, latitude_deg: float) -> float:
    """Earth-rate component along a turntable axis pointing ``axis``, °/h."""
    lat = math.radians(latitude_deg)
    return {
        "up": math.sin(lat),
        "north": math.cos(lat),
        "south": -math.cos(lat),
        "east": 0.0,
        "west": 0.0,
    }[axis] * EARTH_RATE_DEG_PER_H


def sensed_error_arcsec(
    truth: AngleInstrumentTruth,
    theta_deg: np.ndarray,
    elapsed_s: np.ndarray,
    rate_deg_s: float,
    axis: str,
    latitude_deg: float,
) -> np.ndarray:
    """Deterministic part of φ − θ (module docstring), ″."""
    th = np.radians(np.asarray(theta_deg, dtype=float))
    t_h = np.asarray(elapsed_s, dtype=float) / 3600.0
    harm = truth.a1_arcsec * np.sin(th) + truth.a2_arcsec * np.sin(
        2 * th + math.radians(truth.a2_phase_deg)
    )
    tilt = math.degrees(math.sin(math.radians(truth.tilt_deg)) ** 2 / 8.0) * 3600.0 * np.sin(2 * th)
    rate = truth.rate_coeff * (rate_deg_s - 60.0) / 60.0 * np.degrees(th) * 3600.0
    drift = (
        (truth.drift_deg_h + truth.earth_comp_error * earth_rate_along(axis, latitude_deg))
        * 3600.0
        * t_h
    )
    return harm + tilt + rate + drift


def stop_times(stops_deg: np.ndarray, rate_deg_s: float, dwell_s: float = 60.0) -> np.ndarray:
    """Elapsed time at arrival at each stop of a sequential run 0 → S₁ → S₂ … (dwell at each)."""
    s = np.asarray(stops_deg, dtype=float)
    turn = np.diff(s, prepend=0.0) / rate_deg_s
    return np.cumsum(turn) + dwell_s * np.arange(s.size)


def _cond(step: Step, name: str, dim: str | None = None, default: Any = None) -> Any:
    v = step.conditions.get(name, default)
    if v is None:
        raise ValueError(f"step {step.segment!r} has no condition {name!r}")
    return parse_quantity(v, dimension=dim) if dim else v


@attrs.define
class AngleInstrumentStation:
    """Low-speed turntable (axis up/north/east), timer, and the virtual angle instrument."""

    truth: AngleInstrumentTruth = attrs.field(factory=AngleInstrumentTruth)
    latitude_deg: float = 39.98

    name = "simulated-ogam"

    def device(self) -> DeviceUnderTest:
        t = self.truth
        return simulated_device(
            t.seed, "SIM-OGAM-1", "virtual optical-gyro angle measuring instrument",
            technology="laser",
            output="pulse",
            properties={
                "scale_factor": Q_(t.K_P_per_deg / (1 + t.scale_factor_error), "P/deg"),
                "zero_stability": Q_(0.005, "deg/h"),
            },
        )

    def equipment(self) -> list[Equipment]:
        from .equipment import equipment_list
        from .kits import angle_instrument_equipment

        return equipment_list(angle_instrument_equipment(self.truth.positioning_arcsec))

    # -- one segment per step ---------------------------------------------------------------
    def _positions(self, step: Step, rng: np.random.Generator, truth: AngleInstrumentTruth):
        rate = float(_cond(step, "rate", "deg/s").to("deg/s").magnitude)
        axis = str(_cond(step, "axis", default="up")).strip().lower()
        inc = float(_cond(step, "step", "deg").to("deg").magnitude)
        stops = int(_cond(step, "stops"))
        S = inc * np.arange(1, stops + 1)
        t = stop_times(S, rate, float(step.interval.to("s").magnitude))
        p = rng.uniform(-1, 1, S.size) * truth.positioning_arcsec
        theta = S + p / 3600.0
        err = sensed_error_arcsec(truth, theta, t, rate, axis, self.latitude_deg)
        if truth.arw_deg_rt_h > 0:
            dt_h = np.diff(t, prepend=0.0) / 3600.0
            err = err + np.cumsum(
                rng.normal(0, 1, S.size) * truth.arw_deg_rt_h * 3600.0 * np.sqrt(dt_h)
            )
        err = (
            err + rng.normal(0, 1, S.size) * truth.reading_noise_arcsec
            if truth.reading_noise_arcsec
            else err
        )
        phi = theta + err / 3600.0
        return S, phi

    def _reading(self, phi: np.ndarray, truth: AngleInstrumentTruth) -> np.ndarray:
        m = phi * (1.0 + truth.scale_factor_error)  # C'/K_nom
        if truth.resolution_arcsec > 0:
            m = np.round(m * 3600.0 / truth.resolution_arcsec) * truth.resolution_arcsec / 3600.0
        return m

    def segment_data(
        self, step: Step, index: int, truth: AngleInstrumentTruth | None = None
    ) -> dict[str, tuple[np.ndarray, str]]:
        truth = truth or self.truth
        rng = np.random.default_rng([truth.seed, index])
        if step.kind == "scale-factor":
            S, phi = self._positions(step, rng, truth)
            counts = (
                np.round(truth.K_P_per_deg * phi)
                if truth.resolution_arcsec > 0
                else truth.K_P_per_deg * phi
            )
            return {"angle": (S, "deg"), "counts": (counts, "P")}
        if step.kind == "positioning":
            S, phi = self._positions(step, rng, truth)
            return {"standard": (S, "deg"), "reading": (self._reading(phi, truth), "deg")}
        if step.kind == "zero":
            dt_s = float(step.interval.to("s").magnitude)
            n = int(round(float(step.duration.to("s").magnitude) / dt_s)) + 1
            t = dt_s * np.arange(n)
            err = (
                truth.drift_deg_h
                + truth.earth_comp_error * earth_rate_along("up", self.latitude_deg)
            ) * t
            if truth.arw_deg_rt_h > 0:
                steps = rng.normal(0, 1, n) * truth.arw_deg_rt_h * 3600.0 * math.sqrt(dt_s / 3600.0)
                steps[0] = 0.0
                err = err + np.cumsum(steps)
            if truth.reading_noise_arcsec:
                err = err + rng.normal(0, 1, n) * truth.reading_noise_arcsec
            m = self._reading(err / 3600.0, truth) * 3600.0
            return {"time": (t / 60.0, "min"), "reading": (m, "arcsec")}
        raise ValueError(
            f"the simulated angle instrument cannot acquire steps of kind {step.kind!r}"
        )

    #: the step kinds of the draft's items this station simulates
    KINDS = ("scale-factor", "positioning", "zero")

    def check(self, steps, *, items=None) -> None:
        """Refuse, before anything is simulated, a step kind this station does not simulate."""
        from .stations import refuse_unknown_kinds

        refuse_unknown_kinds(self.name, steps, self.KINDS, items=items)

    def acquire(self, steps: list[Step], *, progress=None) -> Campaign:
        from .stations import step_seed

        self.check(steps)
        segments = []
        for i, step in enumerate(steps):
            data = self.segment_data(step, step_seed(step))
            digest = hashlib.sha256(
                b"".join(np.ascontiguousarray(a).tobytes() for a, _ in data.values())
            ).hexdigest()
            segments.append(
                Segment(
                    id=step.segment,
                    kind=step.kind,
                    conditions=dict(step.conditions),
                    interval=step.interval,
                    file=None,
                    sha256=digest,
                    loader=(lambda d=data: d),
                )
            )
            if progress is not None:
                progress("simulating angle instrument", i + 1, len(steps))
        return simulated_campaign(
            self, "SIMULATED-OGAM", segments, source="simulated station (angle instrument)",
            expected=self.expected(steps),
        )

    def expected(self, steps: list[Step]) -> Mapping[str, Any]:
        """What an ideal evaluation of the deterministic model gives, per metric key."""
        q = self.truth.quiet()
        out: dict[str, Any] = {}
        e_by: dict[tuple[float, str], float] = {}
        from .stations import step_seed

        for step in steps:
            d = self.segment_data(step, step_seed(step), q)
            if step.kind == "scale-factor":
                k_i = d["counts"][0] / d["angle"][0]
                out["K"] = Q_(float(np.mean(k_i)), "P/deg")
                out["Kl"] = Q_(
                    100.0 * float(k_i.max() - k_i.min()) / float(np.mean(k_i)), "percent"
                )
            elif step.kind == "zero":
                m = d["reading"][0]
                out["Bs"] = Q_(
                    float(np.std(m, ddof=1)) / 3600.0 / (float(step.duration.to("h").magnitude)),
                    "deg/h",
                )
            elif step.kind == "positioning":
                e = float(np.max(np.abs(d["reading"][0] - d["standard"][0]))) * 3600.0
                rate = float(_cond(step, "rate", "deg/s").to("deg/s").magnitude)
                axis = str(_cond(step, "axis", default="up")).lower()
                e_by[(rate, axis)] = e
                if rate == 60.0 and axis == "up":
                    out["E"] = Q_(e, "arcsec")
        rates = {r: e for (r, a), e in e_by.items() if a == "up"}
        if len(rates) > 1 and 60.0 in rates:
            out["Cv"] = Q_(
                100.0 * (max(rates.values()) - min(rates.values())) / rates[60.0], "percent"
            )
        axes = {a: e for (r, a), e in e_by.items() if r == 60.0}
        if len(axes) > 1 and "up" in axes:
            out["Cg"] = Q_(
                100.0 * (max(axes.values()) - min(axes.values())) / axes["up"], "percent"
            )
        return out


#: device classes (station option ``device_class=NAME``): what real optical-gyro angle instruments
#: vary, as presets.  A class is a population: each seed draws one instrument of it
#: (:func:`draw_device`); options given with the class override its values.  The output is pulse
#: counts (7.1) and an angle reading (7.3–7.7) in every class, resolved finely or coarsely.
DEVICE_CLASSES: Mapping[str, Mapping[str, Any]] = {
    # ring-laser instrument: 20 000 P/°, reading resolution 0.01″ (the default)
    "rlg-fine": {},
    # fibre instrument with a coarse count and reading: 2 000 P/° (1.8″ per count), reading to 0.1″
    "fog-coarse": {"K_P_per_deg": 2000.0, "resolution_arcsec": 0.1},
    # an instrument whose zero drifts ten times more and whose earth-rate compensation is 10× worse
    "rlg-drifting": {"drift_deg_h": 1e-3, "earth_comp_error": 1e-4},
}


def draw_device(device_class: str, seed: int) -> dict[str, Any]:
    """The truth fields of one instrument of ``device_class`` drawn with ``seed``: the class's
    values,
    then K within ±1 % of the class's, harmonic errors a₁, a₂ uniform in 0 … 0.1″, a sensing-plane
    tilt uniform in 0 … 0.1° and an angle random walk 0.7 … 1.5 times the default's."""
    base = AngleInstrumentTruth()
    rng = np.random.default_rng([int(seed), 7])
    kw = device_class_fields(device_class, DEVICE_CLASSES)
    kw["K_P_per_deg"] = float(kw.get("K_P_per_deg", base.K_P_per_deg)) * float(
        rng.uniform(0.99, 1.01)
    )
    kw["a1_arcsec"] = float(rng.uniform(0.0, 0.1))
    kw["a2_arcsec"] = float(rng.uniform(0.0, 0.1))
    kw["tilt_deg"] = float(rng.uniform(0.0, 0.1))
    kw["arw_deg_rt_h"] = base.arw_deg_rt_h * float(rng.uniform(0.7, 1.5))
    kw["device_class"] = device_class
    return kw


def station_factory(**options: Any) -> AngleInstrumentStation:
    """Factory of the ``simulated-ogam`` station (options: seed, latitude_deg, any truth field, and
    ``device_class`` — one of :data:`DEVICE_CLASSES`, drawn by the seed)."""
    return drawn_station(
        "simulated-ogam", AngleInstrumentTruth, AngleInstrumentStation, draw_device, options,
        ("latitude_deg",),
    )


__all__ = [
    "DEVICE_CLASSES",
    "draw_device",
    "AngleInstrumentStation",
    "AngleInstrumentTruth",
    "earth_rate_along",
    "sensed_error_arcsec",
    "station_factory",
    "stop_times",
]

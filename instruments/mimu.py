"""A simulated MIMU (three gyros + three accelerometers) on a three-axis position/rate table.

The MIMU follows the calibration models of JJF 2003—2022 exactly:

* gyros, eq. (1):           ω' = K_g·ω + B_g + G·a
* accelerometers, eq. (2):  a' = K_a·a + B_a + p·(ω∘ω)      (p with a zero diagonal)

with ω the angular rate of the MIMU body (table rate plus earth rate, in rad/s for the p
term, °/s for the gyro outputs) and ``a`` the specific force in gn (at rest the
accelerometers read +1 gn along the axis that points up).  White noise is added per
sample and the outputs are quantized by an N-bit acquisition over the stated full scales.

Mountings (all with the MIMU at the table centre, so there is no centripetal term):

* ``position`` segments: the MIMU axis ``up`` (``+x``, ``-x``, ``+y``, ``-y``, ``+z``, ``-z``)
  points to the zenith, the table at ``heading`` 0° or 180° about the vertical (JJF 2003
  7.2.2.1 a), appendix C).  The earth rate has a vertical part Ω·sin φ along the up axis
  and a horizontal part Ω·cos φ whose body direction turns with the heading.
* ``rate`` segments: the MIMU axis ``axis`` (x, y, z) along the vertical table axis, the
  table turning at ``rate`` (signed, right-handed about the +axis); the horizontal earth rate
  turns with the table and the vertical part adds to the rate (7.2.1.1, 7.2.5.1).

The truth is declared (:class:`MimuTruth`) and seeded; :func:`ideal_means` gives the exact
mean of each output for a segment, from which the station computes ``expected``.
"""

from __future__ import annotations

import hashlib
import math
from typing import Any, Mapping

import attrs
import numpy as np

from metro.core.model import Campaign, DeviceUnderTest, Equipment, Segment, Step
from metro.core.units import Q_

from metro.core.earth import EARTH_RATE_DEG_S, EARTH_RATE_RAD_S  # noqa: E402

AXES = ("x", "y", "z")
GYRO_COLUMNS = ("gx", "gy", "gz")
ACCEL_COLUMNS = ("ax", "ay", "az")
UPS = ("+x", "-x", "+y", "-y", "+z", "-z")


def _m(rows) -> tuple[tuple[float, ...], ...]:
    return tuple(tuple(float(v) for v in r) for r in rows)


@attrs.frozen
class MimuTruth:
    """Declared parameters of the simulated MIMU (units in the names; matrices row-major,
    row = output axis, column = input axis, as in eq. (1) and (2))."""

    K_g: tuple = _m([[1.0125, 0.0021, -0.0034], [-0.0015, 0.9963, 0.0027], [0.0041, -0.0019, 1.0048]])
    B_g_deg_s: tuple = (0.052, -0.031, 0.018)
    G_deg_s_per_gn: tuple = _m([[0.042, -0.013, 0.008], [0.011, -0.027, 0.016], [-0.009, 0.014, 0.035]])
    K_a: tuple = _m([[1.0032, 0.0045, -0.0026], [-0.0038, 0.9974, 0.0031], [0.0022, -0.0041, 1.0057]])
    B_a_gn: tuple = (0.0123, -0.0087, 0.0154)
    #: p with zero diagonal, gn per (rad/s)²
    p_gn_per_rad2_s2: tuple = _m([[0.0, 6.0e-4, -4.0e-4], [5.0e-4, 0.0, 7.0e-4], [-3.0e-4, 8.0e-4, 0.0]])
    gyro_noise_deg_s: float = 0.08
    accel_noise_gn: float = 0.002
    gyro_range_deg_s: float = 400.0
    accel_range_gn: float = 8.0
    bits: int = 16
    seed: int = 20260301

    def arrays(self) -> dict[str, np.ndarray]:
        return {
            "K_g": np.array(self.K_g, float), "B_g": np.array(self.B_g_deg_s, float),
            "G": np.array(self.G_deg_s_per_gn, float), "K_a": np.array(self.K_a, float),
            "B_a": np.array(self.B_a_gn, float), "p": np.array(self.p_gn_per_rad2_s2, float),
        }

    def as_quantities(self) -> dict[str, Any]:
        a = self.arrays()
        out: dict[str, Any] = {}
        for i, r in enumerate(AXES):
            out[f"B_g{r}"] = Q_(a["B_g"][i], "deg/s")
            out[f"B_a{r}"] = Q_(a["B_a"][i], "gn")
            for j, c in enumerate(AXES):
                out[f"K_g{r}{c}"] = Q_(a["K_g"][i, j], "")
                out[f"g_{r}{c}"] = Q_(a["G"][i, j], "deg/s/gn")
                out[f"K_a{r}{c}"] = Q_(a["K_a"][i, j], "")
                if i != j:
                    out[f"p_{r}{c}"] = Q_(a["p"][i, j], "gn/(rad/s)**2")
        out.update({"gyro noise (per sample)": Q_(self.gyro_noise_deg_s, "deg/s"),
                    "accelerometer noise (per sample)": Q_(self.accel_noise_gn, "gn"),
                    "acquisition bits": self.bits, "seed": self.seed})
        return out


def _unit(axis: str) -> np.ndarray:
    e = np.zeros(3)
    e[AXES.index(axis)] = 1.0
    return e


def _frame(up: str) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Body directions of (zenith, reference horizontal h1, h2 = zenith × h1) for an up axis."""
    sign = -1.0 if up.startswith("-") else 1.0
    ax = up[-1]
    e = sign * _unit(ax)
    h1 = _unit(AXES[(AXES.index(ax) + 1) % 3])
    h2 = np.cross(e, h1)
    return e, h1, h2


def segment_kinematics(conditions: Mapping[str, Any], latitude_deg: float, n: int, interval_s: float):
    """Body angular rate (°/s, shape (n, 3)) and specific force (gn, shape (3,)) for a segment."""
    phi = math.radians(latitude_deg)
    t = np.arange(n) * interval_s
    if "up" in conditions:  # static position, heading 0° / 180°
        up = str(conditions["up"])
        heading = math.radians(float(Q_(conditions["heading"]).to("deg").magnitude)
                               if not isinstance(conditions["heading"], (int, float)) else conditions["heading"])
        e, h1, h2 = _frame(up)
        north = math.cos(heading) * h1 - math.sin(heading) * h2
        w = EARTH_RATE_DEG_S * (math.sin(phi) * e + math.cos(phi) * north)
        omega = np.tile(w, (n, 1))
        force = e.copy()
    else:  # rate about a vertical MIMU axis
        axis = str(conditions["axis"])
        rate = conditions["rate"]
        r = float(rate.to("deg/s").magnitude) if hasattr(rate, "to") else float(rate)
        e, h1, h2 = _frame("+" + axis)
        ang = np.radians(r * t)
        horiz = EARTH_RATE_DEG_S * math.cos(phi) * (np.cos(ang)[:, None] * h1 - np.sin(ang)[:, None] * h2)
        omega = (r + EARTH_RATE_DEG_S * math.sin(phi)) * e[None, :] + horiz
        force = e.copy()
    return omega, force


def model_outputs(truth: MimuTruth, omega_deg_s: np.ndarray, force_gn: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Noise-free outputs of eq. (1) and (2) for body rates (n, 3) and a specific force (3,)."""
    a = truth.arrays()
    gyro = omega_deg_s @ a["K_g"].T + a["B_g"] + a["G"] @ force_gn
    w2 = np.radians(omega_deg_s) ** 2
    accel = a["K_a"] @ force_gn + a["B_a"] + w2 @ a["p"].T
    return gyro, accel


def ideal_means(truth: MimuTruth, conditions: Mapping[str, Any], latitude_deg: float,
                n: int, interval_s: float) -> tuple[np.ndarray, np.ndarray]:
    """Exact (noise-free, unquantized) mean outputs of a segment."""
    omega, force = segment_kinematics(conditions, latitude_deg, n, interval_s)
    g, acc = model_outputs(truth, omega, force)
    return g.mean(axis=0), acc.mean(axis=0)


def simulate_segment(truth: MimuTruth, conditions: Mapping[str, Any], latitude_deg: float, n: int,
                     interval_s: float, seed: int) -> dict[str, np.ndarray]:
    rng = np.random.default_rng(seed)
    omega, force = segment_kinematics(conditions, latitude_deg, n, interval_s)
    gyro, accel = model_outputs(truth, omega, force)
    gyro = gyro + rng.normal(0.0, truth.gyro_noise_deg_s, size=gyro.shape)
    accel = accel + rng.normal(0.0, truth.accel_noise_gn, size=accel.shape)
    qg = 2 * truth.gyro_range_deg_s / 2**truth.bits
    qa = 2 * truth.accel_range_gn / 2**truth.bits
    gyro = np.round(gyro / qg) * qg
    accel = np.round(accel / qa) * qa
    out = {}
    for i in range(3):
        out[GYRO_COLUMNS[i]] = np.ascontiguousarray(gyro[:, i])
        out[ACCEL_COLUMNS[i]] = np.ascontiguousarray(accel[:, i])
    return out


@attrs.define
class MimuStation:
    """Simulated MIMU calibration station: three-axis position/rate table + N-bit acquisition."""

    truth: MimuTruth = attrs.field(factory=MimuTruth)
    latitude_deg: float = 39.98
    duration_scale: float = 1.0

    name = "simulated-mimu"

    def device(self) -> DeviceUnderTest:
        t = self.truth
        return DeviceUnderTest(
            id="SIM-MIMU-1", model="virtual MEMS IMU", serial=f"seed {t.seed}", manufacturer="metro simulator",
            properties={"gyro_range": Q_(t.gyro_range_deg_s, "deg/s"), "accel_range": Q_(t.accel_range_gn, "gn")},
            technology="mems", output="rate",
        )

    def equipment(self) -> list[Equipment]:
        from .equipment import equipment_list, jjf2003_equipment

        return equipment_list(jjf2003_equipment(self.truth.bits))

    def acquire(self, steps: list[Step], *, progress=None) -> Campaign:
        t = self.truth
        segments = []
        for i, step in enumerate(steps):
            interval_s = float(step.interval.to("s").magnitude)
            n = max(2, int(round(float(step.duration.to("s").magnitude) * self.duration_scale / interval_s)))
            cols = simulate_segment(t, step.conditions, self.latitude_deg, n, interval_s, t.seed + 7919 * (i + 1))
            digest = hashlib.sha256(b"".join(cols[c].tobytes() for c in sorted(cols))).hexdigest()
            units = {c: ("deg/s" if c.startswith("g") else "gn") for c in cols}
            segments.append(Segment(
                id=step.segment, kind=step.kind, conditions=dict(step.conditions), interval=Q_(interval_s, "s"),
                sha256=digest, loader=(lambda c=cols, u=units: {k: (v, u[k]) for k, v in c.items()}),
            ))
            if progress is not None:
                progress("simulating MIMU", i + 1, len(steps))
        camp = Campaign(
            id="SIMULATED-MIMU", device=self.device(), equipment=self.equipment(),
            environment={"temperature": Q_(20.0, "degC"), "humidity": Q_(45.0, "percent")},
            site={"latitude": Q_(self.latitude_deg, "deg")}, segments=segments, source="simulated station",
            simulated=True, truth=t.as_quantities() | {"site latitude": Q_(self.latitude_deg, "deg")},
        )
        return attrs.evolve(camp, expected=_expected(self, camp))


def _expected(station: MimuStation, camp: Campaign) -> dict[str, Any]:
    """What an ideal evaluation gives: the plugin's own formulas applied to the exact means."""
    try:
        from metro.plugins.jjf2003.procedures import ideal_evaluation
    except ImportError:  # pragma: no cover - plugin not installed
        return {}
    return ideal_evaluation(camp, lambda seg: ideal_means(
        station.truth, seg.conditions, station.latitude_deg,
        max(2, int(np.shape(seg.columns()["gx"][0])[0])), float(seg.interval.to("s").magnitude)))


def station_factory(**options: Any) -> MimuStation:
    """Factory registered as ``simulated-mimu`` (options: seed, bits, latitude_deg, duration_scale, …)."""
    truth_kw = {k: v for k, v in options.items() if k in attrs.fields_dict(MimuTruth)}
    st_kw = {k: v for k, v in options.items() if k in ("latitude_deg", "duration_scale")}
    return MimuStation(truth=MimuTruth(**truth_kw), **st_kw)


__all__ = ["MimuTruth", "MimuStation", "station_factory", "ideal_means", "simulate_segment",
           "segment_kinematics", "model_outputs", "EARTH_RATE_DEG_S", "EARTH_RATE_RAD_S", "UPS"]

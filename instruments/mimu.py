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

The table is not perfect: it is the :class:`~metro.instruments.equipment.ThreeAxisTable` the
campaign declares (:func:`station_equipment`), and its simulated action is used.  Every mounting
is off by two small angles drawn by :meth:`ThreeAxisTable.position` (uniform within
±``position_accuracy``), which tilt the table axis (= the zenith) in the body frame; every rate
point turns at :meth:`ThreeAxisTable.actual_rate` (a fixed relative error per set point, drawn
within the band's ±error, plus ripple).  The bands are set so that the table's errors are as
large as its certificate says (U = 2×10⁻⁴, k = 2, appendix A.1.2.1), so the budget rows u₁ are
exercised by the simulation rather than merely added to it.

The truth is declared (:class:`MimuTruth`) and seeded; :func:`ideal_means` gives the exact
mean of each output for a segment, from which the station computes ``expected``.
"""

from __future__ import annotations

import datetime as dt
import hashlib
import math
import zlib
from typing import Any, Mapping

import attrs
import numpy as np

from metro.core.model.campaign import Campaign, DeviceUnderTest, Equipment, Segment
from metro.core.model.procedure import Step
from metro.core.base.units import Q_

from metro.core.stats.earth import EARTH_RATE_DEG_S, EARTH_RATE_RAD_S  # noqa: E402
from .stations import device_class_fields, drawn_station, simulated_campaign, simulated_device

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

    K_g: tuple = _m(
        [[1.0125, 0.0021, -0.0034], [-0.0015, 0.9963, 0.0027], [0.0041, -0.0019, 1.0048]]
    )
    B_g_deg_s: tuple = (0.052, -0.031, 0.018)
    G_deg_s_per_gn: tuple = _m(
        [[0.042, -0.013, 0.008], [0.011, -0.027, 0.016], [-0.009, 0.014, 0.035]]
    )
    K_a: tuple = _m(
        [[1.0032, 0.0045, -0.0026], [-0.0038, 0.9974, 0.0031], [0.0022, -0.0041, 1.0057]]
    )
    B_a_gn: tuple = (0.0123, -0.0087, 0.0154)
    #: p with zero diagonal, gn per (rad/s)²
    p_gn_per_rad2_s2: tuple = _m(
        [[0.0, 6.0e-4, -4.0e-4], [5.0e-4, 0.0, 7.0e-4], [-3.0e-4, 8.0e-4, 0.0]]
    )
    gyro_noise_deg_s: float = 0.08
    accel_noise_gn: float = 0.002
    gyro_range_deg_s: float = 400.0
    accel_range_gn: float = 8.0
    bits: int = 16
    #: relative 1σ of the gyro scale factors (K_g diagonal) between power-ons: each calibration
    #: (the 7.2.1 sweeps, each ``rate-repeat`` run) is one power-on with its own draw; 0: none
    sf_repeat_rel: float = 0.0
    #: 1σ (°/s) of the gyro biases between power-ons, drawn like ``sf_repeat_rel`` (rate segments)
    bias_repeat_deg_s: float = 0.0
    #: a MIMU still warming up (station option ``warmup_deg_s_per_h``): the gyro biases ramp during
    #: the
    #: campaign by this many °/s per hour times (1, −0.6, 0.8) for gyros x, y, z, linearly in the
    #: recording time (JJF 2003 7.2.1.1 b) waits only for the supply current); B_g is the bias at
    #: the
    #: middle of the twelve position records, what their mean measures; 0: a steady bias
    warmup_deg_s_per_h: float = attrs.field(
        default=0.0,
        validator=attrs.validators.and_(attrs.validators.ge(-10.0), attrs.validators.le(10.0)),
    )
    #: the class this device was drawn from (``device_class`` station option; "" = fields as given)
    device_class: str = ""
    seed: int = 20260301

    def arrays(self) -> dict[str, np.ndarray]:
        return {
            "K_g": np.array(self.K_g, float),
            "B_g": np.array(self.B_g_deg_s, float),
            "G": np.array(self.G_deg_s_per_gn, float),
            "K_a": np.array(self.K_a, float),
            "B_a": np.array(self.B_a_gn, float),
            "p": np.array(self.p_gn_per_rad2_s2, float),
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
        out.update(
            {
                "gyro noise (per sample)": Q_(self.gyro_noise_deg_s, "deg/s"),
                "accelerometer noise (per sample)": Q_(self.accel_noise_gn, "gn"),
                "acquisition bits": self.bits,
                "seed": self.seed,
                "scale-factor variation between power-ons (1σ, relative)": self.sf_repeat_rel,
                "bias variation between power-ons (1σ)": Q_(self.bias_repeat_deg_s, "deg/s"),
                "gyro bias warm-up ramp (gyro x; y, z × −0.6, 0.8)": Q_(
                    self.warmup_deg_s_per_h, "deg/s/hour"
                ),
                "device class": self.device_class or "(fields as given)",
            }
        )
        return out

    def powered_on(self, kind: str, conditions: Mapping[str, Any]) -> "MimuTruth":
        """The device as it is after the power-on of a segment: calibrations (kind ``rate`` = run 0,
        ``rate-repeat`` = its ``run``) each draw their own K_g diagonal and B_g (``sf_repeat_rel``,
        ``bias_repeat_deg_s``); other segments and a device without variation are the device
        itself."""
        if (self.sf_repeat_rel <= 0 and self.bias_repeat_deg_s <= 0) or kind not in (
            "rate",
            "rate-repeat",
        ):
            return self
        run = "0" if kind == "rate" else str(conditions.get("run", "0"))
        rng = np.random.default_rng([self.seed & 0xFFFFFFFF, 0x9E37, zlib.crc32(run.encode())])
        K = np.array(self.K_g, float)
        K[np.diag_indices(3)] *= 1.0 + self.sf_repeat_rel * rng.standard_normal(3)
        B = np.array(self.B_g_deg_s, float) + self.bias_repeat_deg_s * rng.standard_normal(3)
        return attrs.evolve(self, K_g=_m(K), B_g_deg_s=tuple(float(b) for b in B))


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


def _tilted(
    e: np.ndarray, h1: np.ndarray, h2: np.ndarray, tilt_rad
) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """The body frame (zenith, h1, h2) after the mounting is off by the small angles
    ``tilt_rad`` = (about h1, about h2): an exact rotation, so the three stay orthonormal."""
    if tilt_rad is None:
        return e, h1, h2
    a, b = (float(v) for v in tilt_rad)

    def rot(axis, ang, v):  # Rodrigues
        return (
            v * math.cos(ang)
            + np.cross(axis, v) * math.sin(ang)
            + axis * float(axis @ v) * (1 - math.cos(ang))
        )

    out = []
    for v in (e, h1, h2):
        out.append(rot(h2, b, rot(h1, a, v)))
    return out[0], out[1], out[2]


def _rate_of(conditions: Mapping[str, Any]) -> float:
    rate = conditions["rate"]
    if isinstance(rate, str):
        from metro.core.base.units import parse_quantity

        rate = parse_quantity(rate, dimension="deg/s")
    return float(rate.to("deg/s").magnitude) if hasattr(rate, "to") else float(rate)


def segment_kinematics(
    conditions: Mapping[str, Any],
    latitude_deg: float,
    n: int,
    interval_s: float,
    *,
    tilt_rad=None,
    rate_deg_s: np.ndarray | float | None = None,
):
    """Body angular rate (°/s, shape (n, 3)) and specific force (gn, shape (3,)) for a segment.

    ``tilt_rad``: the mounting's two small angle errors (the table axis / zenith is off the MIMU
    axis by them); ``rate_deg_s``: the rate the table actually turns at (a number or n samples;
    default the set point ``conditions["rate"]``)."""
    phi = math.radians(latitude_deg)
    if "up" in conditions:  # static position, heading 0° / 180°
        up = str(conditions["up"])
        heading = math.radians(
            float(Q_(conditions["heading"]).to("deg").magnitude)
            if not isinstance(conditions["heading"], (int, float))
            else conditions["heading"]
        )
        e, h1, h2 = _tilted(*_frame(up), tilt_rad)
        north = math.cos(heading) * h1 - math.sin(heading) * h2
        w = EARTH_RATE_DEG_S * (math.sin(phi) * e + math.cos(phi) * north)
        omega = np.tile(w, (n, 1))
        force = e.copy()
    else:  # rate about a vertical MIMU axis
        axis = str(conditions["axis"])
        r = _rate_of(conditions) if rate_deg_s is None else rate_deg_s
        r = np.broadcast_to(np.asarray(r, float), (n,))
        e, h1, h2 = _tilted(*_frame("+" + axis), tilt_rad)
        ang = (
            np.radians(np.concatenate([[0.0], np.cumsum(r[:-1])]) * interval_s)
            if n
            else np.zeros(0)
        )
        horiz = (
            EARTH_RATE_DEG_S
            * math.cos(phi)
            * (np.cos(ang)[:, None] * h1 - np.sin(ang)[:, None] * h2)
        )
        omega = (r + EARTH_RATE_DEG_S * math.sin(phi))[:, None] * e[None, :] + horiz
        force = e.copy()
    return omega, force


def model_outputs(
    truth: MimuTruth, omega_deg_s: np.ndarray, force_gn: np.ndarray
) -> tuple[np.ndarray, np.ndarray]:
    """Noise-free outputs of eq. (1) and (2) for body rates (n, 3) and a specific force (3,)."""
    a = truth.arrays()
    gyro = omega_deg_s @ a["K_g"].T + a["B_g"] + a["G"] @ force_gn
    w2 = np.radians(omega_deg_s) ** 2
    accel = a["K_a"] @ force_gn + a["B_a"] + w2 @ a["p"].T
    return gyro, accel


def ideal_means(
    truth: MimuTruth,
    conditions: Mapping[str, Any],
    latitude_deg: float,
    n: int,
    interval_s: float,
    *,
    tilt_rad=None,
    rate_deg_s: float | None = None,
) -> tuple[np.ndarray, np.ndarray]:
    """Exact (noise-free, unquantized) mean outputs of a segment (with the mounting's tilt and
    the table's mean rate, if given)."""
    omega, force = segment_kinematics(
        conditions, latitude_deg, n, interval_s, tilt_rad=tilt_rad, rate_deg_s=rate_deg_s
    )
    g, acc = model_outputs(truth, omega, force)
    return g.mean(axis=0), acc.mean(axis=0)


#: the gyros' share of the warm-up ramp (``MimuTruth.warmup_deg_s_per_h``)
WARMUP_PATTERN = np.array([1.0, -0.6, 0.8])
#: the table's time between two records (turning to the next position or rate and settling), s
RECORD_GAP_S = 20.0
#: the simulated acquisition's clock at the first record (the segments' ``started``)
CAMPAIGN_START = dt.datetime(2026, 3, 1, 9, 0, tzinfo=dt.timezone(dt.timedelta(hours=8)))


def simulate_segment(
    truth: MimuTruth,
    conditions: Mapping[str, Any],
    latitude_deg: float,
    n: int,
    interval_s: float,
    seed: int,
    *,
    tilt_rad=None,
    rate_deg_s: np.ndarray | None = None,
    t0_s: float = 0.0,
) -> dict[str, np.ndarray]:
    """Samples of one record; ``t0_s``: its first sample's time from the warm-up ramp's zero (s)."""
    rng = np.random.default_rng(seed)
    omega, force = segment_kinematics(
        conditions, latitude_deg, n, interval_s, tilt_rad=tilt_rad, rate_deg_s=rate_deg_s
    )
    gyro, accel = model_outputs(truth, omega, force)
    if truth.warmup_deg_s_per_h:
        t = t0_s + interval_s * np.arange(n)
        gyro = gyro + (truth.warmup_deg_s_per_h / 3600.0) * t[:, None] * WARMUP_PATTERN[None, :]
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
        return simulated_device(
            t.seed, "SIM-MIMU-1", "virtual MEMS IMU",
            properties={
                "gyro_range": Q_(t.gyro_range_deg_s, "deg/s"),
                "accel_range": Q_(t.accel_range_gn, "gn"),
            },
            technology="mems",
            output="rate",
        )

    def table(self):
        """The simulated three-axis table (:func:`station_table`) for this MIMU's seed."""
        return station_table(self.truth.seed)

    def equipment(self) -> list[Equipment]:
        from .equipment import ADC, equipment_list

        return equipment_list(
            [
                self.table(),
                ADC(
                    id="SIM-DAQ",
                    model=f"simulated {self.truth.bits}-bit acquisition",
                    bits=int(self.truth.bits),
                ),
            ]
        )

    def mounting(
        self, index: int, step: Step, n: int
    ) -> tuple[np.ndarray, np.ndarray | None, float | None]:
        """The table's action for step ``index``: the two tilt angles (rad) of the mounting, the
        n rate samples the table turns at (None for a position) and their set-point mean."""
        table = self.table()
        rng = np.random.default_rng([self.truth.seed & 0xFFFFFFFF, 0x7AB1E, index])
        tilt = np.radians(table.position(Q_([0.0, 0.0], "deg"), rng).to("deg").magnitude)
        if "rate" not in step.conditions:
            return tilt, None, None
        set_point = Q_(_rate_of(step.conditions), "deg/s")
        rates = table.actual_rate(set_point, n, rng).to("deg/s").magnitude
        mean = float(set_point.to("deg/s").magnitude) * (1.0 + table.systematic_error(set_point))
        return tilt, np.asarray(rates, float), mean

    #: the JJF 2003 step kinds this station simulates (a position or a rate of the three-axis table)
    KINDS = ("position", "rate", "rate-repeat")

    def check(self, steps, *, items=None) -> None:
        """Refuse, before anything is simulated, a step kind this station does not simulate."""
        from .stations import StationError, refuse_unknown_kinds

        refuse_unknown_kinds(self.name, steps, self.KINDS, items=items)
        need = {
            "position": ("up", "heading"),
            "rate": ("axis", "rate"),
            "rate-repeat": ("axis", "rate"),
        }
        for step in steps:
            missing = [c for c in need[step.kind] if c not in step.conditions]
            axis = str(step.conditions.get("up" if step.kind == "position" else "axis", "")).lower()
            ok_axis = axis in (
                ("x", "y", "z") if step.kind != "position" else ("+x", "-x", "+y", "-y", "+z", "-z")
            )
            if missing or not ok_axis:
                raise StationError(
                    f"station {self.name!r} cannot simulate step {step.segment!r} ({step.kind}): "
                    f"the three-axis "
                    f"table needs the conditions {', '.join(need[step.kind])}"
                    + (
                        f" (missing {', '.join(missing)})"
                        if missing
                        else f" (axis {axis!r} is not an IMU axis)"
                    )
                    + "; nothing was recorded",
                    hint="acquire these items on a station that simulates them (`metro plugins` "
                    "lists them)",
                )

    def acquire(self, steps: list[Step], *, progress=None) -> Campaign:
        from .stations import step_seed

        self.check(steps)
        t = self.truth
        segments = []
        realized: dict[str, tuple[np.ndarray, float | None]] = {}
        # the records are taken one after the other, RECORD_GAP_S apart; the warm-up ramp is zero at
        # the middle of the position records (B_g is their mean)
        sizes, starts, clock = [], [], 0.0
        for step in steps:
            interval_s = float(step.interval.to("s").magnitude)
            n = max(
                2,
                int(
                    round(float(step.duration.to("s").magnitude) * self.duration_scale / interval_s)
                ),
            )
            sizes.append((n, interval_s))
            starts.append(clock)
            clock += n * interval_s + RECORD_GAP_S
        mids = [
            s0 + 0.5 * (n - 1) * dt_s
            for s0, (n, dt_s), st in zip(starts, sizes, steps)
            if st.kind == "position"
        ]
        zero = float(np.mean(mids)) if mids else 0.0
        for k, step in enumerate(steps):
            i = step_seed(step)  # the step's identity, not its place in the list, seeds its noise
            n, interval_s = sizes[k]
            tilt, rates, mean_rate = self.mounting(i, step, n)
            realized[step.segment] = (tilt, mean_rate)
            cols = simulate_segment(
                t.powered_on(step.kind, step.conditions),
                step.conditions,
                self.latitude_deg,
                n,
                interval_s,
                t.seed + 7919 * (i + 1),
                tilt_rad=tilt,
                rate_deg_s=rates,
                t0_s=starts[k] - zero,
            )
            digest = hashlib.sha256(b"".join(cols[c].tobytes() for c in sorted(cols))).hexdigest()
            units = {c: ("deg/s" if c.startswith("g") else "gn") for c in cols}
            segments.append(
                Segment(
                    id=step.segment,
                    kind=step.kind,
                    conditions=dict(step.conditions),
                    interval=Q_(interval_s, "s"),
                    sha256=digest,
                    loader=(lambda c=cols, u=units: {k: (v, u[k]) for k, v in c.items()}),
                    started=CAMPAIGN_START + dt.timedelta(seconds=starts[k]),
                )
            )
            if progress is not None:
                progress("simulating MIMU", k + 1, len(steps))
        # the simulated specific force at rest is 1 g_n (segment_kinematics): the site says so, as
        # a real site gives its local gravity (JJF 2003 7.2.2/7.2.4 read it for Ā)
        camp = simulated_campaign(
            self, "SIMULATED-MIMU", segments, site={"gravity": Q_(9.80665, "m/s**2")}
        )
        return attrs.evolve(camp, expected=_expected(self, camp, realized))


def station_table(seed: int):
    """The simulated three-axis position/rate table (JJF 2003 table 1, appendix A.1.2.1).

    Certificate U = 2×10⁻⁴ (k = 2, relative rate) and positioning ±10″ (table 1), and errors of
    that size: one band to 14 000 °/s (clause 1) with a fixed relative error per set point within
    ±√3×10⁻⁴ (uniform, standard deviation 1×10⁻⁴ = U/k) and ripple 5×10⁻⁴ (table 1: 0.05 %)."""
    from .equipment import RateBand, ThreeAxisTable

    return ThreeAxisTable(
        id="SIM-3AXIS",
        model="simulated three-axis position/rate table",
        position_accuracy=Q_(10.0, "arcsec"),
        certificate="SIM-CAL-3AX",
        U=Q_(2e-4, ""),
        lab="simulated",
        seed=int(seed),
        bands=(RateBand("14000 deg/s", math.sqrt(3.0) * 1e-4, 5e-4),),
    )


def _expected(
    station: MimuStation, camp: Campaign, realized: Mapping[str, tuple]
) -> dict[str, Any]:
    """What an ideal evaluation gives: JJF 2003's own formulas (its plugin, through
    :func:`~metro.instruments.stations.standard_expected`) applied to the exact means of what the
    table did (each mounting's tilt, each rate point's mean rate) without noise."""
    from .stations import standard_expected

    def means(seg: Segment):
        return ideal_means(
            station.truth,
            seg.conditions,
            station.latitude_deg,
            max(2, int(np.shape(seg.columns()["gx"][0])[0])),
            float(seg.interval.to("s").magnitude),
            tilt_rad=realized[seg.id][0],
            rate_deg_s=realized[seg.id][1],
        )

    return standard_expected(camp, {"jjf2003:segment_means": means})


#: device classes (station option ``device_class=NAME``): what real MEMS IMUs vary, as presets.  A
#: class is a population: each seed draws one device of it (:func:`draw_device`); options given with
#: the class override its values.  The output is a rate (°/s) and a specific force (gn) in every
#: class,
#: digitised by the N-bit acquisition finely or coarsely.
DEVICE_CLASSES: Mapping[str, Any] = {
    # 16-bit acquisition: 1 LSB = 0.012 °/s, finer than the noise (the default device)
    "mems-16bit": {},
    # 12-bit acquisition (appendix A's N = 12): 1 LSB = 0.195 °/s, coarser than the 0.08 °/s noise
    "mems-12bit": {"bits": 12},
    # scale factors (1σ 5×10⁻⁴) and biases (1σ 0.005 °/s) change between power-ons (each
    # calibration)
    "mems-power-on": {"sf_repeat_rel": 5e-4, "bias_repeat_deg_s": 0.005},
    # still warming up: the gyro biases ramp by 1, −0.6, 0.8 °/s per hour during the campaign (a
    # MEMS
    # gyro minutes after power-on; JJF 2003 7.2.1.1 b) waits for the supply current only), enough to
    # move the g terms by 2 U; the records carry `started`
    "mems-warmup": {"warmup_deg_s_per_h": 1.0},
}


def draw_device(device_class: str, seed: int) -> dict[str, Any]:
    """The truth fields of one device of ``device_class`` drawn with ``seed``: the class's values,
    then gyro biases uniform in ±0.1 °/s, the K_g diagonal within ±2 % of 1, and noise 0.7 … 1.5
    times the default's."""
    base = MimuTruth()
    rng = np.random.default_rng([int(seed), 2003])
    kw = device_class_fields(device_class, DEVICE_CLASSES)
    K = np.array(base.K_g, float)
    K[np.diag_indices(3)] = 1.0 + rng.uniform(-0.02, 0.02, 3)
    kw["K_g"] = _m(K)
    kw["B_g_deg_s"] = tuple(float(x) for x in rng.uniform(-0.1, 0.1, 3))
    f = float(rng.uniform(0.7, 1.5))
    kw["gyro_noise_deg_s"] = base.gyro_noise_deg_s * f
    kw["accel_noise_gn"] = base.accel_noise_gn * f
    kw["device_class"] = device_class
    return kw


def station_factory(**options: Any) -> MimuStation:
    """Factory registered as ``simulated-mimu`` (options: seed, bits, latitude_deg, duration_scale,
    …,
    and ``device_class`` — one of :data:`DEVICE_CLASSES`, drawn by the seed)."""
    return drawn_station(
        "simulated-mimu", MimuTruth, MimuStation, draw_device, options,
        ("latitude_deg", "duration_scale"),
    )


__all__ = [
    "DEVICE_CLASSES",
    "draw_device",
    "MimuTruth",
    "MimuStation",
    "station_factory",
    "ideal_means",
    "simulate_segment",
    "segment_kinematics",
    "model_outputs",
    "station_table",
    "EARTH_RATE_DEG_S",
    "EARTH_RATE_RAD_S",
    "UPS",
]

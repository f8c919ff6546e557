"""The built-in simulated test station: a virtual optical gyro whose truth is declared and seeded.

The gyro sits on a levelled platform at a site of known latitude, input axis (IRA) up or
down.  Its indicated rate is::

    ω(t) = ±Ω_e·sin θ + B0 + w(t) + b(t) + r(t)

* ``Ω_e`` the earth rate (7.292115e-5 rad/s ≈ 15.04107 °/h, the physical value; the standard's
  formula subtracts 15.041 °/h, so a 0.00007·sin θ °/h difference is part of the truth);
* ``B0`` the bias, ``w`` white rate noise of angle random walk ``arw`` (°/√h): per sample of
  interval τ its standard deviation is arw/√τ;
* ``b`` a first-order Gauss–Markov bias wander of standard deviation ``gm_sigma`` and
  correlation time ``gm_tau`` (a stand-in for bias instability; zero by default);
* ``r`` rate random walk of coefficient ``rrw`` (°/h/√h), zero by default.

Pulse output integrates ω into angle and emits whole pulses of weight 1/K; the count read
at each sample is the integrated angle rounded at a random readout phase (as a dithered ring
laser gyro's is), so the remainder is carried, no angle is lost over the record, and the
quantization error is white angle noise of variance ≈ 1/(6K²) ″² (the α2 term of D.45).  Digital
output is ω·K rounded to LSB; ``rate`` output is ω in °/h.

Records are generated in chunks so an 8 h record at 1 kHz never needs several full copies.
"""

from __future__ import annotations

import hashlib
import math
from typing import Any, Mapping, Sequence

import attrs
import numpy as np

from metro.core.model.campaign import Campaign, DeviceUnderTest, Equipment, Segment
from metro.core.model.procedure import Step
from metro.core.base.units import Q_

from metro.core.stats.earth import EARTH_RATE_DEG_PER_H  # noqa: E402  15.04107 °/h, physical (IERS)

from .sim_registry import (expected_contributors, merge_records, record_expected_contributors,
                           record_simulators, register_expected, register_record_expected,
                           register_record_kind, register_step_kind, step_simulators)
from .stations import (memory_segment, simulated_campaign, simulated_device, step_seed,
                       with_device_class)
from .gyro_truth import (DEVICE_CLASSES, DIGITAL_DEFAULTS, GRADES, GRADE_NAMES, GyroTruth,
                         device_description, draw_device)


def simulate_static(
    truth: GyroTruth,
    *,
    n: int,
    interval_s: float,
    latitude_deg: float,
    orientation: str = "up",
    seed: int | None = None,
    chunk: int = 1 << 20,
    progress=None,
    bias_offset_deg_h: float = 0.0,
    extra_deg_h: np.ndarray | None = None,
) -> np.ndarray:
    """Raw output of a gyro at rest for ``n`` samples of ``interval_s``.

    ``bias_offset_deg_h`` adds to the bias (temperature, field, turn-on effects of the step);
    ``extra_deg_h`` (n values, °/h) to each sample's rate before the output is quantized.

    Returns float64 samples in the output's raw unit (P per interval, LSB, or °/h).
    """
    if n < 1 or interval_s <= 0:
        raise ValueError("n must be ≥ 1 and the interval > 0")
    rng = np.random.default_rng(truth.seed if seed is None else seed)
    sign = 1.0 if orientation == "up" else -1.0
    mean_rate = (
        sign * EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))
        + truth.bias_deg_h
        + bias_offset_deg_h
    )
    tau_h = interval_s / 3600.0
    white_sd = truth.arw_deg_rt_h / math.sqrt(tau_h)  # °/h per sample
    out = np.empty(n, dtype=np.float64)
    gm = 0.0
    gm_phi = math.exp(-interval_s / truth.gm_tau_s) if truth.gm_sigma_deg_h > 0 else 0.0
    gm_drive = truth.gm_sigma_deg_h * math.sqrt(1.0 - gm_phi**2)
    rrw = 0.0
    rrw_sd = truth.rrw_deg_h_rt_h * math.sqrt(tau_h)
    carry = 0.0  # angle not yet emitted, in pulses
    emitted = 0.0  # pulses emitted so far, relative to ``carry``
    K = truth.scale_factor_P_per_arcsec
    if truth.gm_sigma_deg_h > 0:
        gm = rng.normal(0.0, truth.gm_sigma_deg_h)
    for start in range(0, n, chunk):
        stop = min(n, start + chunk)
        k = stop - start
        w = rng.normal(mean_rate, white_sd, size=k) if white_sd > 0 else np.full(k, mean_rate)
        if truth.gm_sigma_deg_h > 0:
            e = rng.normal(0.0, gm_drive, size=k)
            # first-order recursion b_i = φ·b_{i-1} + e_i, solved per chunk with lfilter
            from scipy.signal import lfilter

            b, _ = lfilter([1.0], [1.0, -gm_phi], e, zi=[gm_phi * gm])
            w += b
            gm = float(b[-1])
        if extra_deg_h is not None:
            w += np.asarray(extra_deg_h[start:stop], dtype=np.float64)
        if truth.rrw_deg_h_rt_h > 0:
            r = rrw + np.cumsum(rng.normal(0.0, rrw_sd, size=k))
            w += r
            rrw = float(r[-1])
        if truth.output == "pulse":
            # angle increment per sample in pulses: rate[°/h = ″/s] · τ[s] · K[P/″]
            inc = w * (interval_s * K)
            cum = np.cumsum(inc) + carry
            whole = pulse_readout(truth, cum, rng)  # random readout phase when dithered
            out[start:stop] = np.diff(whole, prepend=emitted)
            emitted = float(whole[-1])
            # keep the running totals small: subtract the emitted whole pulses from both
            carry = float(cum[-1] - emitted)
            emitted = 0.0
        else:
            out[start:stop] = quantize_rate(truth, w, rng)
        if progress is not None:
            progress(stop, n)
    return out


_EXPECTED_UNITS = {
    "B0": "deg/h",
    "RWC": "deg/hour**0.5",
    "Br": "deg/h",
    "Bt": "deg/h/delta_degC",
    "Bh": "deg/h/mT",
    "K": "P/arcsec",
    "W": "P/arcsec/(deg/s)",
    "Kn": "",
    "Ka": "",
}


@attrs.define
class SimulatedStation:
    """A simulated test station: a levelled platform, a counter, and the virtual gyro."""

    truth: GyroTruth = attrs.field(factory=GyroTruth)
    latitude_deg: float = 39.98
    interval: Any = attrs.field(factory=lambda: Q_(1, "s"))
    duration_scale: float = 1.0  # <1 shortens every step (tests)
    #: the registered name (in messages): simulated, simulated-digital
    name: str = "simulated"

    def device(self) -> DeviceUnderTest:
        t = self.truth
        props: dict[str, Any] = {}
        if t.output == "pulse":
            props["scale_factor"] = Q_(t.scale_factor_P_per_arcsec, "P/arcsec")
            props["scale_factor_U"] = Q_(4e-6, "")  # as if from a D.1.1 calibration, k = 2
            props["scale_factor_k"] = 2.0
        elif t.output == "digital":
            props["scale_factor"] = Q_(t.lsb_per_deg_s, "LSB/(deg/s)")
            props["scale_factor_U"] = Q_(2e-5, "")
            props["scale_factor_k"] = 2.0
        elif t.rate_resolution > 0:
            props["resolution"] = Q_(t.rate_resolution, t.rate_unit)
        if (
            t.states_repeatability
        ):  # the data sheet's turn-on scatter, as from an earlier D.5.3 / D.1.4 (1σ)
            props["bias_repeatability"] = Q_(t.turn_on_sigma_deg_h, "deg/h")
            props["scale_factor_repeatability"] = Q_(t.sf_turn_on_sigma, "")
        return simulated_device(
            t.seed, "SIM-OG-1", device_description(t),
            # a pulse output is a ring-laser gyro's; a digital word or a digital rate a fibre
            # gyro's (6.2.7.1
            # then sends it to the rate method D.2, which takes LSB, Hz and °/s outputs)
            properties=props,
            technology="laser" if t.output == "pulse" else "fibre",
            application="aviation",
            output={"pulse": "pulse", "digital": "digital", "rate": "rate"}[t.output],
        )

    def equipment(self) -> list[Equipment]:
        from .equipment import equipment_list
        from .kits import gbt45570_equipment

        return equipment_list(gbt45570_equipment(seed=self.truth.seed))

    def kinds(self) -> tuple[str, ...]:
        """The step kinds this station simulates (:data:`STATIC_KINDS`, whole revolutions and the
        kinds the step modules register); revolution counts only for a pulse output."""
        kinds = (
            set(STATIC_KINDS)
            | set(step_simulators())
            | set(record_simulators())
            | {"rate-revolutions"}
        )
        if self.truth.output != "pulse":
            kinds -= set(PULSE_KINDS)
        return tuple(sorted(kinds))

    def check(self, steps, *, items=None) -> None:
        """Refuse, before anything is simulated, a step kind this station cannot simulate — among
        them whole-revolution pulse counts (angle method) when the virtual gyro's output is not a
        pulse output: it has no pulses to count, and its LSB or °/h are not P."""
        from .stations import StationError, refuse_unknown_kinds

        if self.truth.output != "pulse":
            for step in steps:
                if step.kind in PULSE_KINDS:
                    out = (
                        "digital (LSB)"
                        if self.truth.output == "digital"
                        else f"rate ({self.truth.rate_unit})"
                    )
                    raise StationError(
                        f"station {self.name!r} simulates a gyro with {out} output; steps of kind "
                        f"{step.kind!r} "
                        f"(segment {step.segment}) count the pulses of whole revolutions (angle "
                        f"method, GB/T 45570 "
                        "D.1), which only a pulse output gives; nothing was recorded",
                        hint="acquire the angle method on station simulated (pulse output), or the "
                        "rate method "
                        "(D.2, D.3 with -o method=rate) on this one",
                    )
        refuse_unknown_kinds(self.name, steps, self.kinds(), items=items)

    def acquire(self, steps: list[Step], *, progress=None) -> Campaign:
        """Run the steps on the virtual gyro; the campaign's segments hold the samples in memory."""
        self.check(steps)
        segments = []
        records: dict[str, Any] = {}
        t = self.truth
        repeat_durations_s: list[float] = []
        for step in steps:
            i = step_seed(step)  # the step's identity, not its place in the list, seeds its noise
            if step.is_record:
                take_down = record_simulators().get(step.kind)
                if take_down is None:
                    raise ValueError(f"the simulated station has no record of kind {step.kind!r}")
                merge_records(records, take_down(self, step, i))
                continue
            interval_s = (
                float(step.interval.to("s").magnitude)
                if step.interval is not None
                else float(self.interval.to("s").magnitude)
            )
            n = max(
                1,
                int(
                    round(float(step.duration.to("s").magnitude) * self.duration_scale / interval_s)
                ),
            )
            if step.kind == "static-repeat":
                repeat_durations_s.append(n * interval_s)
            orient = (
                str(step.conditions.get("orientation", "IRA up")).lower().replace("ira", "").strip()
            )
            cb = (
                (lambda d, tot, _s=step.segment: progress(f"simulating {_s}", d, tot))
                if progress
                else None
            )
            offset = bias_offset(t, step.conditions) + own_power_on_bias(t, step)
            custom = step_simulators().get(step.kind)
            if custom is not None:
                segments.append(
                    custom(
                        self,
                        step,
                        i,
                        interval_s=interval_s,
                        n=n,
                        orientation=orient,
                        bias_offset_deg_h=offset,
                        progress=cb,
                    )
                )
                continue
            if step.kind == "rate-revolutions":
                segments.append(self._revolutions(step, i, offset))
                continue
            segments.append(self.at_rest(
                step, i, n=n, interval_s=interval_s, orientation=orient, offset=offset, progress=cb
            ))
        if t.polarity < 0:
            segments = [_reversed(seg) for seg in segments]
        camp = simulated_campaign(
            self, "SIMULATED", segments, site={"latitude_uncertainty": Q_(0.001, "deg")},
            records=records,
        )
        return attrs.evolve(camp, expected=self.expected_values(camp, repeat_durations_s))

    def _revolutions(self, step: Step, i: int, offset: float) -> Segment:
        """Whole table revolutions (``rate-revolutions``): pulse counts and durations."""
        from metro.core.base.units import parse_quantity

        t = self.truth
        rate = float(
            parse_quantity(step.conditions["rate"], dimension="deg/s").to("deg/s").magnitude
        )
        direction = 1 if rate > 0 else -1
        counts, dur = simulate_revolutions(
            t,
            rate_deg_s=abs(rate),
            direction=direction,
            turns=int(step.conditions.get("turns", 5)),
            latitude_deg=self.latitude_deg,
            seed=t.seed + 7919 * (i + 1),
            bias_offset_deg_h=offset,
        )
        return memory_segment(
            step, float(dur[0]), {"count": (counts, "P"), "duration": (dur, "s")}
        )

    def at_rest(
        self, step: Step, index: int, *, n: int, interval_s: float, orientation: str = "up",
        latitude_deg: float | None = None, offset: float = 0.0, progress=None,
        extra_deg_h: np.ndarray | None = None,
    ) -> Segment:
        """The gyro at rest for ``step``: ``n`` samples of ``interval_s`` with IRA ``orientation``
        at ``latitude_deg`` (default: the station's), its bias shifted by ``offset`` (°/h) and by
        ``extra_deg_h`` per sample; its noise drawn with the truth's seed + ``index``."""
        t = self.truth
        data = simulate_static(
            t,
            n=n,
            interval_s=interval_s,
            latitude_deg=self.latitude_deg if latitude_deg is None else latitude_deg,
            orientation=orientation,
            seed=t.seed + index,
            progress=progress,
            bias_offset_deg_h=offset,
            extra_deg_h=extra_deg_h,
        )
        return memory_segment(step, interval_s, {"output": (data, output_unit(t))})

    def expected_values(
        self, camp: Campaign, repeat_durations_s: Sequence[float] = ()
    ) -> dict[str, Any]:
        """What an ideal evaluation of the truth gives for the items ``camp`` holds records of: the
        station's own (:func:`expected`, :func:`expected_scale_factor`) and the step modules'
        (:func:`register_expected`, :func:`register_record_expected`)."""
        t = self.truth
        exp = {
            k: Q_(v, _EXPECTED_UNITS[k.split("_")[0]])
            for k, v in expected(t, self.latitude_deg).items()
        }
        if repeat_durations_s:
            exp["Br"] = Q_(expected_bias_repeatability(t, repeat_durations_s), "deg/h")
        rates = [s.conditions["rate"] for s in camp.segments if s.kind == "rate-revolutions"]
        if rates:
            from metro.core.base.units import parse_quantity

            vals = [parse_quantity(r, dimension="deg/s").to("deg/s").magnitude for r in rates]
            exp |= {
                k: Q_(v, _EXPECTED_UNITS[k])
                for k, v in expected_scale_factor(t, vals, self.latitude_deg).items()
            }
        for contribute in expected_contributors():
            exp |= contribute(self, camp)
        for contribute in record_expected_contributors() if camp.records else ():
            exp |= contribute(self, camp)
        return exp


AXES = ("IRA", "XRA", "YRA")

#: step kinds the station records as the gyro at rest on its platform (conditions such as
#: temperature, field, run and orientation act through :func:`bias_offset`)
STATIC_KINDS = (
    "static",
    "static-zero",
    "rate-static",
    "static-repeat",
    "static-temperature",
    "static-field",
    "low-temperature",
    "high-temperature",
)
#: step kinds that count the pulses of whole table revolutions (GB/T 45570 D.1, D.3 angle method)
PULSE_KINDS = (
    "rate-revolutions",
    "revolutions-repeat",
    "revolutions-temperature",
    "revolutions-mounting",
)

#: the gyro's output columns, negated for a gyro of negative polarity
OUTPUT_COLUMNS = ("output", "count")


def _reversed(seg: Segment) -> Segment:
    """``seg`` as a gyro of negative polarity gives it: its output columns negated (the digest
    is of what the procedures read)."""
    cols = {
        name: ((-np.asarray(data) if name in OUTPUT_COLUMNS else data), unit)
        for name, (data, unit) in seg.columns().items()
    }
    digest = hashlib.sha256(
        b"".join(np.ascontiguousarray(d).tobytes() for d, _ in cols.values())
    ).hexdigest()
    return attrs.evolve(seg, sha256=digest, loader=lambda c=cols: c)


def scale_factor_at(truth: GyroTruth, rate_deg_s: float, direction: int) -> float:
    """The virtual gyro's scale factor (P/″) at |Ω| = ``rate_deg_s`` turning in ``direction``
    (±1)."""
    r = abs(rate_deg_s)
    return truth.scale_factor_P_per_arcsec * (
        1.0
        + truth.sf_slope_per_deg_s * r
        + truth.sf_quadratic * (r / 400.0) ** 2
        + direction * truth.sf_asymmetry / 2.0
    )


def simulate_revolutions(
    truth: GyroTruth,
    *,
    rate_deg_s: float,
    direction: int,
    turns: int,
    latitude_deg: float,
    seed: int,
    bias_offset_deg_h: float = 0.0,
) -> tuple[np.ndarray, np.ndarray]:
    """Pulses counted over each of ``turns`` whole table revolutions at ``rate_deg_s`` (GB/T 45570
    D.1.1.2 g)), IRA up along the table axis, and each revolution's duration (s).

    Per revolution the gyro sees the table's ±360° plus the vertical earth rate and its bias
    over the revolution time; its angle random walk adds white angle noise, and the count is read
    at a random readout phase (as in :func:`simulate_static`), so no pulse is lost between turns.
    """
    rng = np.random.default_rng(seed)
    t = 360.0 / abs(rate_deg_s)
    K = scale_factor_at(truth, rate_deg_s, direction)
    drift = (
        EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg))
        + truth.bias_deg_h
        + bias_offset_deg_h
    )
    angle = direction * 360.0 * 3600.0 + drift * t  # ″ per revolution (°/h = ″/s)
    noise_sd = (
        truth.arw_deg_rt_h * math.sqrt(t / 3600.0) * 3600.0
    )  # ″ of angle random walk per turn
    inc = K * (angle + rng.normal(0.0, noise_sd, size=turns))
    cum = np.cumsum(inc)
    whole = pulse_readout(truth, cum, rng)
    counts = np.diff(whole, prepend=0.0)
    return counts, np.full(turns, t)


def bias_offset(truth: GyroTruth, conditions) -> float:
    """The bias shift (°/h) a step's conditions cause on the virtual gyro.

    * ``temperature``: bias_tc·(T − T_ref) (linear; D.5.4 recovers bias_tc);
    * ``field_axis`` (IRA/XRA/YRA) and signed ``field`` (mT): sensitivity·H (D.5.5);
    * ``run`` = i: a turn-on bias drawn from N(0, σ) seeded by (seed, i) — each power-on
      of D.5.3 gives its own bias; segments without ``run`` get none.
    """
    from metro.core.base.units import parse_quantity

    off = 0.0
    if "temperature" in conditions:
        T = parse_quantity(conditions["temperature"], dimension="degC").to("degC").magnitude
        off += truth.bias_tc_deg_h_per_C * (float(T) - truth.temp_ref_C)
    if "field_axis" in conditions and "field" in conditions:
        H = float(parse_quantity(conditions["field"], dimension="mT").to("mT").magnitude)
        off += truth.mag_sens_deg_h_per_mT[AXES.index(str(conditions["field_axis"]).upper())] * H
    if "run" in conditions:
        r = np.random.default_rng([truth.seed, int(conditions["run"])])
        off += float(r.normal(0.0, truth.turn_on_sigma_deg_h))
    if truth.bias_mount_sigma_deg_h > 0 and mounting_key(conditions):
        r = np.random.default_rng([truth.seed, *mounting_key(conditions), 6047])
        off += float(r.normal(0.0, truth.bias_mount_sigma_deg_h))
    return off


#: record kinds whose clause switches the gyro on for each record: D.5.4.2 c) powers off between the
#: temperature points, D.5.5.2 takes each field record "by D.5.1.2"
OWN_POWER_ON_KINDS = ("static-temperature", "static-field")


def own_power_on_bias(truth: GyroTruth, step) -> float:
    """The turn-on bias (°/h) of a record that is a power-on of its own
    (:data:`OWN_POWER_ON_KINDS`):
    N(0, turn_on_sigma), seeded by the device and the record's kind and conditions — so the station
    makes what D.5.4 / D.5.5 meet on a real gyro (their results carry σ_on of D.5.3; truth stays the
    device's B_t, B_h).  Records with a ``run`` condition draw theirs in :func:`bias_offset`."""
    if (
        step.kind not in OWN_POWER_ON_KINDS
        or "run" in step.conditions
        or truth.turn_on_sigma_deg_h <= 0
    ):
        return 0.0
    key = step.kind + ";" + ";".join(f"{k}={step.conditions[k]}" for k in sorted(step.conditions))
    digest = int.from_bytes(hashlib.sha256(key.encode()).digest()[:4], "little")
    return float(
        np.random.default_rng([truth.seed, digest, 4099]).normal(0.0, truth.turn_on_sigma_deg_h)
    )


def mounting_key(conditions) -> tuple[int, ...]:
    """Integers naming a step's mounting (``axis_up`` and ``turn`` of D.1.6/D.2.6); () for the
    ordinary IRA-up mounting, whose bias and scale factor are the truth's own."""
    axis = str(conditions.get("axis_up", "")).upper().replace("+", "").strip()
    if axis in ("", "IRA"):
        return ()
    turn = str(conditions.get("turn", "0")).split()[0]
    try:
        t = int(round(float(turn))) % 360
    except ValueError:
        t = 0
    return (AXES.index(axis) if axis in AXES else 9, t)


def output_unit(truth: GyroTruth) -> str:
    """The unit of the virtual gyro's output column."""
    return {"pulse": "P", "digital": "LSB", "rate": truth.rate_unit}[truth.output]


def pulse_readout(truth: GyroTruth, cum: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """Whole pulses emitted by the time each sample is read, of the accumulated angle ``cum``
    (pulses): read at a random phase when ``dither`` (white quantization error, variance 1/6 P²
    per difference), else at a fixed phase (the leftover fraction then drifts with the rate — a
    sawtooth quantization error)."""
    return np.floor(cum + (rng.random(cum.size) if truth.dither else 0.5))


def quantize_rate(truth: GyroTruth, w_deg_h: np.ndarray, rng: np.random.Generator) -> np.ndarray:
    """LSB or rate output of indicated rates ``w_deg_h`` (°/h): the LSB word rounded (with a
    uniform ±½ LSB dither first when ``lsb_dither``), or the rate in ``rate_unit`` rounded to
    ``rate_resolution``."""
    w = np.asarray(w_deg_h, dtype=np.float64)
    if truth.output == "digital":
        x = w / 3600.0 * truth.lsb_per_deg_s
        if truth.lsb_dither:
            x = x + rng.random(x.size) - 0.5
        return np.round(x)
    x = w if truth.rate_unit == "deg/h" else w / 3600.0
    if truth.rate_resolution > 0:
        x = np.round(x / truth.rate_resolution) * truth.rate_resolution
    return x


def expected_scale_factor(truth: GyroTruth, rates_deg_s, latitude_deg: float) -> dict[str, float]:
    """What D.1.1–D.1.3 give on noise-free revolutions of the virtual gyro at these rate points:
    the truth the angle-method items must recover (K, W, K_n, K_a).  Fewer than two distinct rates
    define no straight line (D.1.1's least squares needs two): no truth, rather than a degenerate
    fit."""
    rates = np.asarray(sorted(set(abs(float(r)) for r in rates_deg_s)), dtype=float)
    if rates.size < 2:
        return {}
    d = EARTH_RATE_DEG_PER_H * math.sin(math.radians(latitude_deg)) + truth.bias_deg_h  # ″/s
    rev = 360.0 * 3600.0
    t = 360.0 / rates
    kp = np.array([scale_factor_at(truth, r, 1) for r in rates])
    km = np.array([scale_factor_at(truth, r, -1) for r in rates])
    n_plus, n_minus = kp * (rev + d * t), km * (-rev + d * t)
    Ki = (n_plus - n_minus) / (2 * rev)
    W, K = np.polyfit(rates, Ki, 1)
    n0 = truth.scale_factor_P_per_arcsec * d
    Kp = np.polyfit(rates, (n_plus - n0 * t) / rev, 1)[1]
    Km = np.polyfit(rates, (n_minus - n0 * t) / -rev, 1)[1]
    return {
        "K": float(K),
        "W": float(W),
        "Kn": float(np.max(np.abs(Ki - K)) / K),
        "Ka": float(abs(Kp - Km) / ((Kp + Km) / 2)),
    }


def station_factory(**options: Any) -> SimulatedStation:
    """Factory registered as the ``simulated`` station (options: seed, latitude, output,
    duration_scale,
    grade, device_class …).  ``grade`` (typical, marginal, failing; :data:`GRADES`) picks the unit;
    with ``device_class`` the device is drawn from that class by the seed (:func:`draw_device`);
    other
    options given override both."""
    from metro.core.base.options import station_options

    truth_kw, st_kw = station_options(
        "the simulated gyro station",
        GyroTruth,
        SimulatedStation,
        options,
        ("latitude_deg", "duration_scale"),
    )
    if truth_kw.get("device_class"):  # a class is drawn about the marginal unit (draw_device)
        truth_kw = with_device_class(truth_kw, draw_device, GyroTruth().seed)
    else:
        truth_kw.pop("device_class", None)
        truth_kw = dict(GRADES[truth_kw.get("grade", "typical")]) | truth_kw
    return SimulatedStation(truth=GyroTruth(**truth_kw), **st_kw)


def mean_noise_variance(truth: GyroTruth, duration_s: float) -> float:
    """Variance ((°/h)²) of the mean rate over ``duration_s`` of the device's noise: white rate
    noise (ARW²/T), a rate random walk started at each power-on (q²T/3) and Gauss–Markov wander
    (2σ²τ/T·[1 − τ/T·(1 − e^(−T/τ))])."""
    T_h = duration_s / 3600.0
    var = (
        truth.arw_deg_rt_h**2 / T_h + truth.rrw_deg_h_rt_h**2 * T_h / 3.0
    )  # a walk from 0: mean var q²T/3
    if truth.gm_sigma_deg_h > 0:
        r = truth.gm_tau_s / duration_s
        var += 2.0 * truth.gm_sigma_deg_h**2 * r * (1.0 - r * (1.0 - math.exp(-1.0 / r)))
    return var


def expected_bias_repeatability(truth: GyroTruth, durations_s: Sequence[float]) -> float:
    """What D.42 measures in expectation (interpretations.md, D.5.3): the scatter of the D.40 biases
    of the power-ons, each a mean over its record — the turn-on scatter and the within-run noise of
    each mean, √(σ_on² + mean var(mean))."""
    w = float(np.mean([mean_noise_variance(truth, d) for d in durations_s]))
    return math.sqrt(truth.turn_on_sigma_deg_h**2 + w)


def expected(truth: GyroTruth, latitude_deg: float) -> Mapping[str, float]:
    """What an ideal evaluation of the truth gives, per item (for tests and the CLI's
    comparison)."""
    out = {
        "B0": truth.bias_deg_h
        + (EARTH_RATE_DEG_PER_H - 15.041) * math.sin(math.radians(latitude_deg)),
        "RWC": truth.arw_deg_rt_h,
        "Br": truth.turn_on_sigma_deg_h,
        "Bt": truth.bias_tc_deg_h_per_C,
    }
    for ax, v in zip(AXES, truth.mag_sens_deg_h_per_mT):
        out[f"Bh_{ax}"] = abs(v)
    return out


__all__ = [
    "register_record_kind",
    "register_record_expected",
    "record_simulators",
    "merge_records",
    "register_expected",
    "expected_contributors",
    "register_step_kind",
    "step_simulators",
    "expected_scale_factor",
    "scale_factor_at",
    "simulate_revolutions",
    "GyroTruth",
    "SimulatedStation",
    "simulate_static",
    "station_factory",
    "DEVICE_CLASSES",
    "GRADES",
    "GRADE_NAMES",
    "device_description",
    "DIGITAL_DEFAULTS",
    "draw_device",
    "output_unit",
    "pulse_readout",
    "quantize_rate",
    "mounting_key",
    "expected",
    "expected_bias_repeatability",
    "mean_noise_variance",
    "bias_offset",
    "AXES",
]

"""The GB/T 45570 clause-5 type test on the simulated station: the records a lab would write for
the inspection items (5.2.3–5.2.8), the 5.4 tests done elsewhere (GB/T 2423.x …) and the
reliability evidence (5.5), plus the gyro's output before and after each of those tests.

Registered record kinds (``record:<section>.<part>``,
:func:`metro.instruments.simulated.register_record_kind`):
``record:inspection.{appearance,dimensions,mass,supply,interfaces,insulation}``,
``record:environmental_tests.<tag>`` (lts, hts, tsh, lp, acc, dh, mould, salt, tvac, rad, emc) and
``record:reliability.{mtbf,life}``; step kind ``type-env`` — a static record (IRA up) before or
after an environmental test, the bias shifted after it by :attr:`TypeTestTruth.env_shift_deg_h`.

The truth is declared in :class:`TypeTestTruth` and seeded by the station's seed: the instruments
(callipers, balance, megohmmeter: :func:`type_test_equipment`) read it with a fixed error drawn
within their certificate's U and round to their resolution; repeated readings add noise.
"""

from __future__ import annotations

import functools
import math
from typing import Any, Callable

import attrs
import numpy as np
import pint

from metro.core.base.units import Q_

from .gauges import type_test_equipment
from .simulated import (SimulatedStation, register_expected, register_record_expected,
                        register_record_kind, register_step_kind)
from .stations import memory_segment, standard_expected


@attrs.frozen
class TypeTestTruth:
    """What the simulated type test finds (declared; the items must recover it within U)."""

    #: (name, nominal mm, ± tolerance mm, true value mm)
    dimensions: tuple[tuple[str, float, float, float], ...] = (
        ("length", 80.0, 0.1, 80.031),
        ("width", 60.0, 0.1, 59.962),
        ("height", 45.0, 0.1, 45.018),
    )
    mass_g: float = 1234.6  # with the cable and the four mounting screws delivered with it
    mass_limit: str = "<= 1300 g"
    #: (terminal pair, true insulation resistance in MΩ); above the megohmmeter's 10 GΩ shows "> 10
    #: GΩ"
    insulation_Mohm: tuple[tuple[str, float], ...] = (
        ("power+ to case", 2200.0),
        ("signal to case", 5400.0),
        ("power+ to signal", 3.0e4),
    )
    insulation_voltage_V: float = 500.0
    #: bias change (°/h) after each 5.4 test done elsewhere, by the test's tag
    env_shift_deg_h: tuple[tuple[str, float], ...] = (
        ("lts", 0.004),
        ("hts", -0.006),
        ("tsh", 0.008),
        ("lp", 0.002),
        ("acc", -0.003),
        ("dh", 0.005),
        ("mould", 0.001),
        ("salt", -0.002),
        ("tvac", 0.006),
        ("rad", 0.007),
        ("emc", -0.001),
    )
    #: relative scale-factor change (ppm) after each test, by tag (the others: none)
    env_sf_shift_ppm: tuple[tuple[str, float], ...] = (
        ("lts", 6.0),
        ("hts", -4.0),
        ("tsh", 9.0),
        ("acc", 3.0),
    )
    operating_hours: float = 62_000.0  # accumulated by all units on the reliability test
    failures: int = 3
    plan: str = "time-terminated"
    confidence: float = 0.9
    working_life_h: float = 1500.0
    calendar_life_a: float = 8.0

    def shift(self, tag: str) -> float:
        return dict(self.env_shift_deg_h).get(tag, 0.0)

    def sf_shift(self, tag: str) -> float:
        """Relative scale-factor change after the test ``tag`` (a ratio, not ppm)."""
        return dict(self.env_sf_shift_ppm).get(tag, 0.0) * 1e-6


TRUTH = TypeTestTruth()


def _rng(station: SimulatedStation, *tag: Any) -> np.random.Generator:
    import zlib

    return np.random.default_rng([station.truth.seed] + [zlib.crc32(repr(t).encode()) for t in tag])


def _eq(station: SimulatedStation, role: str):
    return next(m for m in type_test_equipment(station.truth.seed) if m.ROLE == role)


def inspection_record(section: str) -> Callable[[Callable[..., Any]], Callable[..., dict]]:
    """Decorator: ``fn(station, step, index)`` returns what the inspection ``section`` found;
    registered as the record kind ``record:inspection.<section>``, whose table is
    ``{"inspection": {section: found}}``."""

    def deco(fn: Callable[..., Any]) -> Callable[..., dict]:
        @functools.wraps(fn)
        def take_down(station, step, index) -> dict:
            return {"inspection": {section: fn(station, step, index)}}

        return register_record_kind(f"record:inspection.{section}")(take_down)

    return deco


def _text(q: pint.Quantity, fmt: str = "g") -> str:
    return f"{q.magnitude:{fmt}} {q.units:~P}"


@inspection_record("appearance")
def rec_appearance(station, step, index) -> dict:
    return {
        "a": True,
        "b": True,
        "c": True,
        "d": True,
        "lighting": "normal lighting (≥ 500 lx)",
        "inspector": "simulated",
    }


@inspection_record("materials")
def rec_materials(station, step, index) -> dict:
    if station.device().technology == "laser":
        m = {
            "cavity": "glass-ceramic (微晶玻璃)",
            "mirrors": "glass-ceramic",
            "housing": "aluminium alloy 2A12",
        }
    else:
        m = {
            "fibre": "polarization-maintaining single-mode fibre",
            "potting": "organic silicone, modulus matched",
            "housing": "aluminium alloy with permalloy shield",
        }
    return m


@inspection_record("function")
def rec_function(station, step, index) -> dict:
    return {
        "senses": True,
        "outputs": True,
        "composition": [
            "optical sensor",
            "structural assembly",
            "control circuit with software",
        ],
    }


@inspection_record("dimensions")
def rec_dimensions(station, step, index) -> list:
    cal, rng, out = _eq(station, "calliper"), _rng(station, "dimensions"), []
    for name, nominal, tol, true in TRUTH.dimensions:
        vals = cal.read(Q_(true, "mm"), 3, rng, name)
        out.append(
            {
                "name": name,
                "nominal": f"{nominal:g} mm",
                "tolerance": f"± {tol:g} mm",
                "readings": [f"{v.magnitude:.2f} mm" for v in vals],
            }
        )
    return out


@inspection_record("mass")
def rec_mass(station, step, index) -> dict:
    vals = _eq(station, "balance").read(Q_(TRUTH.mass_g, "g"), 3, _rng(station, "mass"), "mass")
    parts = ["cable", "connector", "mounting screws"]
    return {
        "readings": [f"{v.magnitude:.1f} g" for v in vals],
        "includes": parts,
        "delivered_with": parts,
        "limit": TRUTH.mass_limit,
    }


@inspection_record("supply")
def rec_supply(station, step, index) -> dict:
    rng = _rng(station, "supply")
    rails = []
    for v, i in station.truth.power_supplies:
        reads = v * (1 + rng.normal(0.0, 2e-4, size=2))
        rails.append(
            {
                "nominal": f"{v:g} V",
                "tolerance": "± 5 %",
                "current": f"{abs(i) * 1.5:.3g} A",
                "readings": [f"{x:.3f} V" for x in reads],
            }
        )
    total = sum(abs(v * i) for v, i in station.truth.power_supplies)
    return {
        "voltage_type": "DC",
        "power": f"{math.ceil(total * 1.5):g} W",
        "rails": rails,
    }


@inspection_record("interfaces")
def rec_interfaces(station, step, index) -> dict:
    return {
        "mechanical_per_specification": True,
        "mounting_face_perpendicular": True,
        "electrical_per_specification": True,
        "protocol_per_specification": True,
        "communication": "RS-422",
        "output_content": ["rate", "voltage", "temperature", "status"],
    }


@inspection_record("insulation")
def rec_insulation(station, step, index) -> list:
    meg, rng, out = _eq(station, "megohmmeter"), _rng(station, "insulation"), []
    hi = float(meg.high.to("Mohm").magnitude)
    for pair, R in TRUTH.insulation_Mohm:
        vals = meg.read(Q_(R, "Mohm"), 2, rng, pair)
        texts = [
            f"> {hi / 1000:g} GΩ"
            if v.to("Mohm").magnitude > hi
            else f"{v.to('Mohm').magnitude:.0f} MΩ"
            for v in vals
        ]
        out.append(
            {
                "pair": pair,
                "voltage": f"{TRUTH.insulation_voltage_V:g} V",
                "state": "non-operating",
                "readings": texts,
            }
        )
    return out


#: the 5.4 tests done elsewhere that the simulated environmental lab reports: (tag, the record's
#: ``test``, the standard giving the method, the severity it applied).  The severities are table
#: C.1's aviation column where it states one (the simulated device is an aviation gyro), else
#: product-specification-like values (the lab's declaration, not read from the standard)
ENV_TESTS: tuple[tuple[str, str, str, dict[str, str]], ...] = (
    (
        "lts",
        "low-temperature storage",
        "GB/T 2423.1",
        {"temperature": "-55 degC", "duration": "16 h"},
    ),
    (
        "hts",
        "high-temperature storage",
        "GB/T 2423.2",
        {"temperature": "85 degC", "duration": "16 h"},
    ),
    (
        "tsh",
        "temperature shock",
        "GB/T 2423.22",
        {
            "low_temperature": "-55 degC",
            "high_temperature": "85 degC",
            "transfer_time": "2 min",
            "cycles": "3",
        },
    ),
    ("lp", "low pressure", "GB/T 2423.21", {"pressure": "3500 Pa", "duration": "2 h"}),
    ("acc", "acceleration", "GB/T 2423.15", {"acceleration": "15 gn", "duration": "1 min"}),
    (
        "dh",
        "damp heat",
        "GB/T 2423.3",
        {"temperature": "40 degC", "humidity": "93 %", "duration": "48 h"},
    ),
    ("mould", "mould", "GB/T 2423.16", {"duration": "28 day"}),
    ("salt", "salt fog", "GB/T 2423.17", {"duration": "48 h"}),
    (
        "tvac",
        "thermal vacuum",
        "GB/T 34522",
        {
            "pressure": "6.0e-3 Pa",
            "low_temperature": "-45 degC",
            "high_temperature": "85 degC",
            "cycles": "3",
        },
    ),
    ("rad", "radiation", "GB/T 4937.18", {"total_dose": "200 Gy"}),
    ("emc", "emc", "product specification", {}),
)


def _env_record(tag: str, key: str, method: str, severity: dict[str, str]):
    def take_down(station, step, index) -> dict:
        rec = {
            "test": key,
            "standard": method,
            "lab": "simulated environmental lab",
            "report": f"SIM-ENV-{tag.upper()}",
            "severity": dict(severity),
            "functional_check": True,
            "before": f"env-{tag}-before",
            "after": f"env-{tag}-after",
            "required": {
                "bias_change": "± 0.05 deg/h",
                "scale_factor_change": "± 30 ppm",
                "source": "simulated product specification",
            },
        }
        if key == "emc":
            rec["notes"] = "CE102/RE102/CS101/RS103 per the technical agreement"
        return {"environmental_tests": [rec]}

    return take_down


def _register_env() -> None:
    for tag, key, method, severity in ENV_TESTS:
        register_record_kind(f"record:environmental_tests.{tag}")(
            _env_record(tag, key, method, severity)
        )


@register_record_kind("record:reliability.mtbf")
def rec_mtbf(station, step, index) -> dict:
    return {
        "reliability": {
            "operating_hours": f"{TRUTH.operating_hours:g} h",
            "failures": TRUTH.failures,
            "plan": TRUTH.plan,
            "confidence": TRUTH.confidence,
            "source": "simulated reliability growth and demonstration records",
        }
    }


@register_record_kind("record:reliability.life")
def rec_life(station, step, index) -> dict:
    return {
        "reliability": {
            "working_life": f"{TRUTH.working_life_h:g} h",
            "calendar_life": f"{TRUTH.calendar_life_a:g} a",
        }
    }


@register_step_kind("type-env")
def sim_type_env(station, step, index, *, interval_s, n, bias_offset_deg_h, progress=None, **_):
    after = str(step.conditions.get("phase", "before")).lower() == "after"
    off = bias_offset_deg_h + (TRUTH.shift(str(step.conditions.get("test", ""))) if after else 0.0)
    return station.at_rest(step, index, n=n, interval_s=interval_s, offset=off, progress=progress)


def _after_station(station: SimulatedStation, step) -> SimulatedStation:
    """The station whose gyro has the scale factor it has after the test (before: unchanged)."""
    if str(step.conditions.get("phase", "before")).lower() != "after":
        return station
    t = station.truth
    f = 1.0 + TRUTH.sf_shift(str(step.conditions.get("test", "")))
    return attrs.evolve(
        station,
        truth=attrs.evolve(
            t,
            scale_factor_P_per_arcsec=t.scale_factor_P_per_arcsec * f,
            lsb_per_deg_s=t.lsb_per_deg_s * f,
        ),
    )


@register_step_kind("type-env-revolutions")
def sim_type_env_revolutions(station, step, index, *, bias_offset_deg_h, **_):
    """Whole revolutions before/after a test (the angle method's record, D.1.1.2 g))."""
    from metro.core.base.units import parse_quantity

    from .simulated import simulate_revolutions

    st = _after_station(station, step)
    rate = float(parse_quantity(step.conditions["rate"], dimension="deg/s").to("deg/s").magnitude)
    counts, dur = simulate_revolutions(
        st.truth,
        rate_deg_s=abs(rate),
        direction=1 if rate > 0 else -1,
        turns=int(step.conditions.get("turns", 3)),
        latitude_deg=st.latitude_deg,
        seed=st.truth.seed + 7919 * (index + 1),
        bias_offset_deg_h=bias_offset_deg_h,
    )
    return memory_segment(step, float(dur[0]), {"count": (counts, "P"), "duration": (dur, "s")})


@register_step_kind("type-env-rate-output")
def sim_type_env_rate_output(station, step, index, *, interval_s, n, bias_offset_deg_h, **_):
    """The output at a rate point before/after a test (the rate method's record, D.2.1.2 g))."""
    from .sim_gbt_rate import rate_samples

    return rate_samples(
        _after_station(station, step), step, index, n, interval_s, 1.0, bias_offset_deg_h
    )


@register_step_kind("type-env-rate-static")
def sim_type_env_rate_static(
    station, step, index, *, interval_s, n, bias_offset_deg_h, progress=None, **_
):
    return station.at_rest(
        step, index, n=n, interval_s=interval_s, offset=bias_offset_deg_h, progress=progress
    )


@register_expected
def expected_type_env(station, camp) -> dict[str, Any]:
    """ΔB₀ and ΔK/K of every 5.4 test done elsewhere whose before/after records were simulated."""
    tags = {str(s.conditions.get("test")) for s in camp.segments if s.kind == "type-env"}
    out = {f"{t}_dB0": Q_(TRUTH.shift(t), "deg/h") for t in tags}
    sf = {str(s.conditions.get("test")) for s in camp.segments if s.kind.startswith("type-env-r")}
    return out | {f"{t}_dK": Q_(TRUTH.sf_shift(t) * 1e6, "ppm") for t in sf}


@register_record_expected
def expected_records(station, camp) -> dict[str, Any]:
    """The truth of the measured inspection items, and the MTBF bound of the declared evidence
    (by the standard's formula, from its plugin)."""
    out: dict[str, Any] = {}
    insp = camp.records.get("inspection", {})
    if "mass" in insp:
        out["mass"] = Q_(TRUTH.mass_g, "g")
    if "dimensions" in insp:
        for name, _n, _t, true in TRUTH.dimensions:
            out[f"dim_{name}"] = Q_(true, "mm")
    if "insulation" in insp:
        import re

        for pair, R in TRUTH.insulation_Mohm:
            if R <= 10_000:
                out["R_ins_" + re.sub(r"[^0-9A-Za-z]+", "_", pair).strip("_")] = Q_(R, "Mohm")
    if "operating_hours" in camp.records.get("reliability", {}):
        evidence = {
            "operating_hours": TRUTH.operating_hours,
            "failures": TRUTH.failures,
            "confidence": TRUTH.confidence,
            "plan": TRUTH.plan,
        }
        out |= standard_expected(camp, {"gbt45570:reliability": evidence})
    return out


_register_env()

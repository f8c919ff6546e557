"""The equipment of each simulated station (its "kit"): the models of :mod:`.equipment` and
:mod:`.gauges` with their certificates, a ``seed`` drawing each instrument's fixed errors."""

from __future__ import annotations

import math

from metro.core.base.units import Q_

from .equipment import (AngleTurntable, AngularVibrationTable, Counter, DigitalMultimeter,
                        EquipmentModel, FieldGenerator, Fixture, LevelPlatform, LinearShaker,
                        PositionTable, RateBand, RateTable, ShockTable, TemperatureChamber,
                        TiltTable, Timer)
from .equipment_base import simulated_lab
from .gauges import type_test_equipment

__all__ = ["gbt45570_equipment", "jjf2014_equipment", "angle_instrument_equipment"]


def gbt45570_equipment(seed: int = 1) -> list[EquipmentModel]:
    """The simulated GB/T 45570 station: levelled platform, rate table with revolution pulses,
    temperature chamber, field generator, fixture, tilt table, vibration and shock tables,
    voltmeter and ammeter (power), counter; ``seed`` draws the instruments' fixed errors (another
    seed, another instrument of the same certificate)."""
    arcsec2 = Q_(2.0, "arcsec")
    return [
        LevelPlatform(id="SIM-PLATFORM", model="simulated levelled platform", levelness=arcsec2),
        RateTable(id="SIM-RATE-TABLE", model="simulated rate table with revolution pulses",
                  revolution_pulse_accuracy=arcsec2,
                  **simulated_lab(seed, "SIM-CAL-0004", Q_(1e-5, ""))),
        TemperatureChamber(id="SIM-CHAMBER", model="simulated temperature chamber",
                           **simulated_lab(seed, "SIM-CAL-0002", Q_(0.3, "K"))),
        FieldGenerator(id="SIM-FIELD", model="simulated DC magnetic field generator",
                       uniformity=Q_(5, "percent"),
                       **simulated_lab(seed, "SIM-CAL-0003", Q_(1e-2, ""))),
        Fixture(id="SIM-FIXTURE", model="simulated gyro fixture, 180° turn about IRA",
                reseat_tilt=Q_(3.0, "arcsec")),
        TiltTable(id="SIM-TILT", model="simulated two-axis tilt table", position_accuracy=arcsec2),
        LinearShaker(id="SIM-VIB", model="simulated vibration table", role="vibration_table",
                     **simulated_lab(seed, "SIM-CAL-0005", Q_(0.05, ""))),
        ShockTable(id="SIM-SHOCK", model="simulated shock table", role="shock_table",
                   duration_accuracy=Q_(1.0, "ms"),
                   **simulated_lab(seed, "SIM-CAL-0006", Q_(0.08, ""))),
        DigitalMultimeter(id="SIM-DVM", model="simulated voltmeter", role="voltmeter",
                          range=Q_(100.0, "V"),
                          **simulated_lab(seed, "SIM-CAL-0007", Q_(5e-4, ""))),
        DigitalMultimeter(id="SIM-AMM", model="simulated ammeter", role="ammeter",
                          range=Q_(3.0, "A"), reading_error=Q_(500.0, "ppm"),
                          range_error=Q_(100.0, "ppm"), digits=5.5,
                          **simulated_lab(seed, "SIM-CAL-0008", Q_(2e-3, ""))),
        Counter(id="SIM-COUNTER", model="simulated counter/time base",
                **simulated_lab(seed, "SIM-CAL-0001", Q_(1e-7, ""))),
    ] + type_test_equipment(seed)


def jjf2014_equipment(seed: int = 1) -> list[EquipmentModel]:
    """The simulated JJF 2014 station (rate table with chamber, DMM, tables, shock, vibration,
    timer); ``seed`` draws the instruments' fixed errors (another seed, another instrument of the
    same certificate)."""
    # errs as its certificate says (appendix B.1: U_rel = 1×10⁻⁴, k = 2): a fixed error per set
    # point uniform within ±√3 × 0.5×10⁻⁴ in every band; ripple within table 1's 速率平稳性
    err = math.sqrt(3.0) * 0.5e-4
    bands = (RateBand("1 deg/s", err, 1e-3), RateBand("10 deg/s", err, 1e-4),
             RateBand("1000 deg/s", err, 2e-5))
    return [
        RateTable(id="SIM-RT", model="simulated rate table with chamber", role="rate-table",
                  bands=bands, **simulated_lab(seed, "SIM-RT-001", Q_(1e-4, ""))),
        DigitalMultimeter(id="SIM-DMM", model="simulated 6½-digit DMM",
                          **simulated_lab(seed, "SIM-DMM-001", Q_(6e-5, ""))),
        TemperatureChamber(id="SIM-CH", model="simulated temperature chamber",
                           **simulated_lab(seed, "SIM-CH-001", Q_(0.5, "delta_degC"))),
        PositionTable(id="SIM-PT", model="simulated two-axis position table",
                      **simulated_lab(seed, "SIM-PT-001", Q_(3.0, "arcsec"))),
        AngularVibrationTable(id="SIM-AVT",
                              model="simulated angular vibration table + reference sensor",
                              phase_U=Q_(0.2, "deg"),
                              **simulated_lab(seed, "SIM-AVT-001", Q_(5e-3, ""))),
        ShockTable(id="SIM-SHOCK", model="simulated shock machine", seed=int(seed)),
        LinearShaker(id="SIM-VIB", model="simulated linear vibration table", seed=int(seed)),
        Timer(id="SIM-TIMER", model="simulated timer",
              **simulated_lab(seed, "SIM-TIMER-001", Q_(1e-6, ""))),
    ]


def angle_instrument_equipment(positioning_arcsec: float) -> list[EquipmentModel]:
    """The simulated angle-instrument station: low-speed turntable (uniform ±positioning error)
    and timer."""
    p = positioning_arcsec or 0.1
    return [
        AngleTurntable(id="SIM-TURNTABLE", model="simulated low-speed turntable",
                       position_accuracy=Q_(p, "arcsec"), axis_wobble=Q_(0.3, "arcsec"),
                       parallelism=Q_(0.1, "deg"), certificate="SIM-TT-0001",
                       U=Q_(p, "arcsec"), distribution="uniform", lab="simulated"),
        Timer(id="SIM-TIMER", model="simulated timer"),
    ]

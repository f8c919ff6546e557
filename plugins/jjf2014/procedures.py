"""JJF 2014—2022 clause 7.2 procedures (one class per calibration item of table 3).

Each class names its clause and equations; the formulas live in :mod:`.formulas`, the
appendix-B-style budgets in :mod:`.budgets`.  Data model (segment ``kind`` and the
conditions each item reads) is in docs/standards/jjf2014.md.  The device's output is an
analog voltage: every segment has an ``output`` column in mV (the angular vibration
segments also a ``reference`` column in °/s from the table's reference sensor).

The classes live by clause group: :mod:`.common` (what every item shares, the 7.2.1 fit),
:mod:`.scale_factor` (7.2.1–7.2.8), :mod:`.low_rate` (7.2.9–7.2.12), :mod:`.bias`
(7.2.13–7.2.19), :mod:`.dynamic` (7.2.20–7.2.22) and :mod:`.startup` (7.2.23); this module
collects them.
"""

from __future__ import annotations

from .bias import (Bias, BiasAcceleration, BiasRepeatability, BiasShock, BiasStability,
                   BiasTemperature, BiasVibration)
from .common import STANDARD, STATION, SFSet, scale_factor_for
from .dynamic import AngleRandomWalk, Bandwidth, OutputDelay
from .low_rate import Misalignment, MisalignmentRepeatability, Resolution, Threshold
from .scale_factor import (Asymmetry, NonlinearityRange, Repeatability, ScaleFactor,
                           SFAxialAcceleration, SFShock, SFTemperature, SFVibration)
from .startup import StartupTime

PROCEDURES = (ScaleFactor, NonlinearityRange, Asymmetry, Repeatability, SFTemperature,
              SFAxialAcceleration, SFShock, SFVibration, Threshold, Resolution, Misalignment,
              MisalignmentRepeatability, Bias, BiasStability, BiasRepeatability, BiasTemperature,
              BiasAcceleration, BiasShock, BiasVibration, AngleRandomWalk, Bandwidth, OutputDelay,
              StartupTime)

__all__ = ["PROCEDURES", "STANDARD", "STATION", "SFSet", "scale_factor_for",
           *(c.__name__ for c in PROCEDURES)]

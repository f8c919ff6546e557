"""metro's public plugin API: everything a standard plugin, a station or a reader builds or reads.

A plugin imports from here and from nowhere else in metro (the import contracts in
``.importlinter`` check it), so what is listed in ``__all__`` is the contract: it keeps its
meaning between minor versions, and anything not listed may change.  docs/api.md is generated
from the docstrings of these names and lists every field of every class.

The names, by what they are for:

* hooks: :data:`hookimpl` marks a plugin's hook implementations (docs/hooks.md lists the hooks);
* the domain (:mod:`metro.core.model`): :class:`Procedure` and what it declares
  (:class:`Step`, :class:`SegmentRequirement`, :class:`EquipmentRequirement`, :class:`Option`,
  :class:`Applicability`), what it reads (:class:`Campaign`, :class:`Segment`,
  :class:`DeviceUnderTest`, :class:`Equipment`, :class:`Calibration`, :class:`Series`,
  :class:`RunContext`) and
  what it returns (:class:`Outcome` of :class:`Result` for each :class:`Metric`, with
  :class:`PlotSpec` figures and :class:`TableSpec` tables);
* stations: a station factory returns a :class:`Station` (:class:`CheckingStation` when it can
  refuse a sequence before acquiring); docs/tutorial-station.md builds a simulated one;
* uncertainty (:mod:`metro.core.uncertainty`): :class:`UncertaintyBudget` of :class:`BudgetRow`,
  conformity :class:`Specification` and :func:`decide`, range selection helpers;
* formulas (:mod:`metro.core.stats`): :mod:`allan`, :mod:`settling`, least squares, sine fits,
  the earth's rate and gravity, rate conversions;
* units, messages and errors (:mod:`metro.core.base`): :data:`Q_`, :func:`unit`, :func:`msg`
  (a translatable text), :class:`DataError`, …;
* documents: helpers a plugin's report layout uses (:mod:`document`, :func:`group_notes`, …);
* validation (:mod:`metro.core.validation`): a :class:`ValidationCase` (with :class:`Figures`
  when the published values come with the computation) for the ``metro_validation_cases`` hook.

>>> from metro.api import Q_
>>> f"{Q_(3600, 'deg/h').to('deg/s').magnitude:g}"
'1'
"""

from __future__ import annotations

from metro.core import hookimpl
from metro.core.base import vocabulary
from metro.core.base.errors import DataError, MetroError, ProcedureError, UnitError
from metro.core.base.formatting import fmt_num, fmt_quantity, unit_text
from metro.core.base.locale import Text, hint, index, join, msg
from metro.core.base.options import check_options, convert_options, station_options
from metro.core.base.units import Q_, check_dimension, fmt_unit, parse_quantity, unit, ureg
from metro.core.documents import document
from metro.core.documents.context import plot_caption
from metro.core.documents.document import result_fields
from metro.core.documents.notes import group_notes
from metro.core.documents.text import display_symbol
from metro.core.model.campaign import (Calibration, Campaign, DeviceUnderTest, Equipment, Segment,
                                       Series)
from metro.core.model.procedure import (Applicability, EquipmentRequirement, Option, Procedure,
                                        RunContext, SegmentRequirement, Step)
from metro.core.model.results import Metric, Outcome, PlotSpec, Result, TableSpec
from metro.core.model.station import CheckingStation, Station
from metro.core.stats import allan, settling
from metro.core.stats.earth import (EARTH_RATE_DEG_PER_H, EARTH_RATE_DEG_S, STANDARD_GRAVITY_M_S2,
                                    normal_gravity)
from metro.core.stats.quantization import rounding_mean_bound
from metro.core.stats.lsq import LinearFit, fit_line, fit_linear
from metro.core.stats.settling import excursion_lobes, last_exit
from metro.core.stats.signals import (OUTPUT_UNITS, RateConversion, device_scale_factor,
                                      gyro_output, required_scale_factor)
from metro.core.stats.sinefit import fit_sine, wrap_phase
from metro.core.uncertainty.budget import (INF, BudgetRow, Coverage, UncertaintyBudget,
                                           between_variance, report_pair, round_uncertainty,
                                           std_sampling_u, std_upper_limit)
from metro.core.uncertainty.conformity import SIMPLE, Comparison, Specification, decide, parse_limit
from metro.core.validation.case import Figures, ValidationCase
from metro.core.uncertainty.selection import (MaxSelection, abs_change, abs_change_note,
                                              abs_change_rows, curve_scatter, max_abs_selection,
                                              max_slope_selection, selection_note, selection_rows,
                                              spread_rows, upper_sigma)

# The names below are objects metro does not document where they are defined (a marker, plain
# numbers); docs/api.md takes their documentation from these comments (tools/gen_api_docs.py).
#: hookimpl — the marker of a plugin's hook implementations (pluggy's, for the project "metro"):
#: decorate each ``metro_*`` function of the plugin module with ``@hookimpl``; docs/hooks.md
#: lists the hooks, their arguments and what they return.
#: EARTH_RATE_DEG_S — the earth's rotation rate Ω_e in °/s: 7.2921150×10⁻⁵ rad/s (IERS
#: conventions, the sidereal rate) ≈ 4.178×10⁻³ °/s ≈ 15.04107 °/h.  The standards' rounded
#: 15.041 °/h stays in their plugins, next to the equation that prints it.
#: EARTH_RATE_DEG_PER_H — the earth's rotation rate Ω_e in °/h, ≈ 15.04107 °/h (the physical
#: value, :data:`EARTH_RATE_DEG_S` × 3600).
#: ureg — metro's one pint unit registry (the standards' symbols, the units plugins add with
#: ``metro_unit_definitions``); make quantities with :data:`Q_` and units with :func:`unit`.
#: STANDARD_GRAVITY_M_S2 — standard gravity g_n = 9.80665 m/s² (CGPM 1901); the local gravity
#: at a latitude is :func:`normal_gravity`.
#: INF — infinite degrees of freedom (``math.inf``): the ``dof`` of a type B
#: :class:`BudgetRow` whose value is known exactly.
#: SIMPLE — the simple-acceptance decision rule (guard band w = 0), a
#: ``DecisionRule``: :func:`decide` compares the value with the limit and U does not enter.

__all__ = [
    "EARTH_RATE_DEG_PER_H",
    "EARTH_RATE_DEG_S",
    "INF",
    "OUTPUT_UNITS",
    "Q_",
    "SIMPLE",
    "STANDARD_GRAVITY_M_S2",
    "Applicability",
    "BudgetRow",
    "Calibration",
    "Campaign",
    "CheckingStation",
    "Comparison",
    "Coverage",
    "DataError",
    "DeviceUnderTest",
    "Equipment",
    "EquipmentRequirement",
    "Figures",
    "LinearFit",
    "MaxSelection",
    "Metric",
    "MetroError",
    "Option",
    "Outcome",
    "PlotSpec",
    "Procedure",
    "ProcedureError",
    "RateConversion",
    "Result",
    "RunContext",
    "Segment",
    "SegmentRequirement",
    "Series",
    "Specification",
    "Station",
    "Step",
    "TableSpec",
    "Text",
    "UncertaintyBudget",
    "UnitError",
    "ValidationCase",
    "abs_change",
    "abs_change_note",
    "abs_change_rows",
    "allan",
    "between_variance",
    "check_dimension",
    "check_options",
    "convert_options",
    "curve_scatter",
    "decide",
    "device_scale_factor",
    "display_symbol",
    "document",
    "excursion_lobes",
    "fit_line",
    "fit_linear",
    "fit_sine",
    "fmt_num",
    "fmt_quantity",
    "fmt_unit",
    "group_notes",
    "gyro_output",
    "hint",
    "hookimpl",
    "index",
    "join",
    "last_exit",
    "max_abs_selection",
    "max_slope_selection",
    "msg",
    "normal_gravity",
    "parse_limit",
    "parse_quantity",
    "plot_caption",
    "report_pair",
    "required_scale_factor",
    "result_fields",
    "round_uncertainty",
    "rounding_mean_bound",
    "selection_note",
    "selection_rows",
    "settling",
    "spread_rows",
    "station_options",
    "std_sampling_u",
    "std_upper_limit",
    "unit",
    "unit_text",
    "upper_sigma",
    "ureg",
    "vocabulary",
    "wrap_phase",
]

"""What an item produces: :class:`Metric` (what is measured), :class:`Result` (a value with
its standard uncertainty and budget), :class:`PlotSpec` and :class:`TableSpec` (figures and
tables for the report) and the item's :class:`Outcome`."""

from __future__ import annotations


import math
from typing import Any, Mapping

import attrs
import numpy as np
import pint

from ..uncertainty.budget import UncertaintyBudget, report_pair
from ..base.errors import ProcedureError
from ..base.units import check_dimension, difference_unit, fmt_unit
from .campaign import frozen_map

__all__ = ['Metric', 'BOUND_SIGNS', 'Result', 'PlotSpec', 'TableSpec', 'Outcome']


@attrs.frozen
class Metric:
    """A declared output of a procedure: what it is, its unit, and where its formula is."""

    key: str
    name: str
    symbol: str
    unit: str
    clause: str
    equation: str = ""
    description: str = ""

    @property
    def reference(self) -> str:
        """Where the formula is: the clause, and the equation when there is one (``D.5.1.3 (D.40)``)."""
        return f"{self.clause} ({self.equation})" if self.equation else self.clause


#: a bound as the terminal, the documents and the verdicts state it (:attr:`Result.bound`): the true
#: value is at least (``lower``) or at most (``upper``) the value shown
BOUND_SIGNS = {"lower": "≥", "upper": "≤"}


@attrs.frozen
class Result:
    """A metric's value with its standard uncertainty and budget."""

    metric: Metric
    value: pint.Quantity
    u: pint.Quantity | None = None
    budget: UncertaintyBudget | None = None
    note: str = ""
    #: False when the data show the method's model does not hold (misfit, unresolved response,
    #: quantization the budget cannot cover): the value is shown but not reported as a result.
    reportable: bool = True
    #: why the result is not reportable (required when ``reportable`` is False)
    reason: str = ""
    #: whether the earth's rate is contained in the value: "included", "removed", "not applicable"
    #: or "" (not stated by the procedure)
    earth_rate: str = ""
    #: for a result that is not reportable as a value but bounds the quantity (a reading beyond the
    #: instrument's range): "lower" — the true value is at least ``value``; "upper" — at most; "" — no
    #: bound (stated with :data:`BOUND_SIGNS`)
    bound: str = attrs.field(default="", validator=attrs.validators.in_(("", "lower", "upper")))

    @property
    def bound_sign(self) -> str:
        """How a bound is stated beside its value: ``≥`` (lower), ``≤`` (upper), ``""`` (a value).

        >>> BOUND_SIGNS["upper"], BOUND_SIGNS.get("", "")
        ('≤', '')
        """
        return BOUND_SIGNS.get(self.bound, "")

    def __attrs_post_init__(self) -> None:
        check_dimension(self.value, self.metric.unit, field=self.metric.key)
        if not self.reportable and not self.reason.strip():
            raise ProcedureError(f"{self.metric.key}: a result marked not reportable needs a reason")
        if not np.all(np.isfinite(np.asarray(self.value.magnitude, dtype=float))):
            raise ProcedureError(f"{self.metric.key}: result is not finite ({self.value})")

    @property
    def k(self) -> float | None:
        return self.budget.k if self.budget is not None else None

    @property
    def U(self) -> pint.Quantity | None:
        if self.budget is not None:
            return self.budget.expanded.to(difference_unit(self.metric.unit))  # °C: U in Δ°C
        return None

    def reported(self) -> tuple[str, str | None]:
        """(value text, U text) rounded as JJF 1059.1 asks, in the metric's unit."""
        v = float(self.value.to(self.metric.unit).magnitude)
        if self.U is None:
            if self.u is not None and float(self.u.magnitude) > 0:
                # no expanded U (no budget): the value still keeps the digits its u supports
                try:
                    u = float(self.u.to(difference_unit(self.metric.unit)).magnitude)
                except pint.errors.PintError:
                    u = float(self.u.to(self.metric.unit).magnitude)
                return report_pair(v, u)[0].text, None
            return f"{v:.6g}", None
        mode = self.budget.round_mode if self.budget else "half-even"
        rv, rU = report_pair(v, float(self.U.magnitude), mode=mode)
        return rv.text, rU.text

    def as_dict(self) -> dict:
        unit_ = self.metric.unit
        val = self.value.to(unit_).magnitude
        vtext, Utext = self.reported()
        return {
            "key": self.metric.key,
            "quantity": self.metric.name,
            "symbol": self.metric.symbol,
            "clause": self.metric.clause,
            "equation": self.metric.equation,
            "value": float(val),
            "unit": fmt_unit(unit_),
            "u": None if self.u is None else float(self.u.to(difference_unit(unit_)).magnitude),
            "U": None if self.U is None else float(self.U.magnitude),
            "k": self.k,
            "nu_eff": None if self.budget is None or math.isinf(self.budget.nu_eff) else self.budget.nu_eff,
            "reported": {"value": vtext, "U": Utext},
            "note": self.note,
            "reportable": self.reportable,
            "reason": self.reason or None,
            "earth_rate": self.earth_rate or None,
            "bound": self.bound or None,
        }


@attrs.frozen
class PlotSpec:
    """Data for one figure; reports render it (matplotlib), procedures only describe it."""

    name: str
    title: str
    xlabel: str
    ylabel: str
    series: tuple[Mapping[str, Any], ...] = attrs.field(converter=tuple)  # {label, x, y, style, yerr}
    logx: bool = False
    logy: bool = False


@attrs.frozen
class TableSpec:
    """A supplementary table (e.g. B_s(τ_k) per level)."""

    name: str
    title: str
    header: tuple[str, ...] = attrs.field(converter=tuple)
    rows: tuple[tuple[Any, ...], ...] = attrs.field(converter=lambda rs: tuple(tuple(r) for r in rs))


@attrs.frozen
class Outcome:
    """What one procedure produced from one campaign."""

    standard: str
    item: str
    title: str
    clause: str
    results: tuple[Result, ...] = attrs.field(converter=tuple)
    plots: tuple[PlotSpec, ...] = attrs.field(default=(), converter=tuple)
    tables: tuple[TableSpec, ...] = attrs.field(default=(), converter=tuple)
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    segments: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    options: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)

    @property
    def id(self) -> str:
        return f"{self.standard}:{self.item}"

    def result(self, key: str) -> Result:
        for r in self.results:
            if r.metric.key == key:
                return r
        raise KeyError(key)



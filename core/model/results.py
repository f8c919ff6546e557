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
from ..base.formatting import BOUND_SIGNS
from ..base.errors import ProcedureError
from ..base.units import check_dimension, difference_unit, fmt_unit
from .campaign import frozen_map

__all__ = ['Metric', 'BOUND_SIGNS', 'Result', 'PlotSpec', 'TableSpec', 'Outcome']


def same_unit_for_pint(text: str) -> None:
    """Refuse a metric's unit text that pint (which results are built with) reads otherwise than
    metro's parser (:func:`metro.core.base.units.unit`): ``"°/√h"`` is °/h to pint, silently.
    Plain pint syntax (ASCII) is read alike by both and is not re-parsed.

    >>> same_unit_for_pint("deg/hour**0.5")
    >>> try:
    ...     same_unit_for_pint("°/√h")
    ... except Exception as exc:
    ...     print("pint reads it as °/h" in str(exc))
    True
    """
    if not text or text.isascii():
        return
    from ..base.errors import UnitError
    from ..base.units import fmt_unit as fmt
    from ..base.units import unit, ureg

    mine = unit(text)
    try:
        theirs = ureg.Unit(text)
        alike = (theirs.dimensionality == mine.dimensionality
                 and (1 * theirs).to(mine).magnitude == 1)
    except (pint.PintError, ValueError, TypeError):
        theirs, alike = None, False
    if not alike:
        read = "cannot read it" if theirs is None else f"reads it as {fmt(theirs)}"
        raise UnitError(None, None, f"unit {text!r}: pint {read}, metro as {fmt(mine)}; "
                        'write it in pint syntax, e.g. "deg/hour**0.5"')


@attrs.frozen
class Metric:
    """A declared output of a procedure: what it is, its unit, and where its formula is.

    A procedure lists its metrics in ``Procedure.metrics`` and builds one :class:`Result` per
    metric it evaluates.

    >>> Metric("D", "warm-up drift", "D", "deg/h", "4.1", "(1)").reference
    '4.1 ((1))'
    """

    #: the metric's identifier within its standard (``"B0"``, ``"K_gxx"``): the key of
    #: ``--json`` results, of ``Campaign.expected``, of a ``Specification`` limit and of
    #: ``Outcome.result(key)``; an ``_`` starts a subscript when it is displayed
    key: str
    #: the quantity's name in words (``"bias"``), printed in tables (a :func:`msg` is translated)
    name: str
    #: the symbol the standard uses (``"B₀"``, ``"K_gxx"``), shown beside the value
    symbol: str
    #: the unit results are reported in, as pint parses it (``"deg/h"``, ``"P/arcsec"``, ``""``
    #: for a ratio); a result of another dimension is refused.  A text pint reads otherwise
    #: than metro's unit syntax (``"°/√h"``: pint reads °/h) is refused: write ``"deg/hour**0.5"``
    unit: str = attrs.field(validator=lambda inst, att, value: same_unit_for_pint(value))
    #: the clause of the standard that defines the quantity (``"D.5.1"``)
    clause: str
    #: the equation number in the standard (``"(D.40)"``), or ``""``
    equation: str = ""
    #: a longer description of the quantity, or ``""`` (documentation only)
    description: str = ""

    @property
    def reference(self) -> str:
        """Where the formula is: the clause, and the equation when there is one (``D.5.1.3
        (D.40)``)."""
        return f"{self.clause} ({self.equation})" if self.equation else self.clause




@attrs.frozen
class Result:
    """A metric's value with its standard uncertainty and budget.

    The value must have the metric's dimension and be finite; the expanded uncertainty
    :attr:`U` and its coverage factor :attr:`k` come from the budget.
    """

    #: the metric this is a value of (one of the procedure's ``metrics``)
    metric: Metric
    #: the value, a pint quantity of the metric's dimension (any compatible unit)
    value: pint.Quantity
    #: the combined standard uncertainty u_c (a quantity; of a temperature: a difference), or
    #: None; with a budget, ``budget.combined``
    u: pint.Quantity | None = None
    #: the uncertainty budget (rows, u_c, ν_eff, k, U) the report prints, or None (no U stated)
    budget: UncertaintyBudget | None = None
    #: a note printed with the result (a :func:`msg` is translated in documents), or ``""``
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
    #: instrument's range): "lower" — the true value is at least ``value``; "upper" — at most; "" —
    #: no bound (stated with :data:`BOUND_SIGNS`)
    bound: str = attrs.field(default="", validator=attrs.validators.in_(("", "lower", "upper")))
    #: the Monte Carlo check of the budget (JCGM 101 clause 8), a
    #: :class:`~metro.core.uncertainty.montecarlo_budget.BudgetCheck`, when the run asked for it
    #: (``metro run --monte-carlo``), else None
    monte_carlo: Any = None

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
            raise ProcedureError(
                f"{self.metric.key}: a result marked not reportable needs a reason")
        if not np.all(np.isfinite(np.asarray(self.value.magnitude, dtype=float))):
            raise ProcedureError(f"{self.metric.key}: result is not finite ({self.value})")

    @property
    def k(self) -> float | None:
        """The coverage factor of :attr:`U` (the budget's), or None without a budget."""
        return self.budget.k if self.budget is not None else None

    @property
    def U(self) -> pint.Quantity | None:
        """The expanded uncertainty U = k·u_c in the metric's unit (Δ°C for a temperature), or
        None without a budget."""
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
        """The result as ``--json`` writes it (key, quantity, value, unit, u, U, k, …)."""
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
            "nu_eff": None if self.budget is None or math.isinf(self.budget.nu_eff)
            else self.budget.nu_eff,
            "reported": {"value": vtext, "U": Utext},
            "note": self.note,
            "reportable": self.reportable,
            "reason": self.reason or None,
            "earth_rate": self.earth_rate or None,
            "bound": self.bound or None,
        } | ({} if self.monte_carlo is None else {"monte_carlo": self.monte_carlo_dict()})

    def monte_carlo_dict(self) -> dict:
        """The Monte Carlo check in the metric's unit, its interval about the value (``--json``'s
        ``monte_carlo``; docs/monte-carlo.md)."""
        unit_ = difference_unit(self.metric.unit)
        scale = float((1.0 * self.budget.unit).to(unit_).magnitude)
        return self.monte_carlo.as_dict(scale, float(self.value.to(self.metric.unit).magnitude))


@attrs.frozen
class PlotSpec:
    """Data for one figure; reports render it (matplotlib), procedures only describe it.

    Each entry of ``series`` is a mapping read with these keys (any other key is ignored):

    * ``"x"``, ``"y"`` (required) — sequences of numbers of the same length, or pint
      quantities (their magnitudes are drawn: convert to the unit the axis label states);
    * ``"label"`` — the legend text (a :func:`msg` is translated); no legend entry when absent
      or ``""``; ``K_i`` is drawn with a subscript;
    * ``"style"`` — ``"o"``, ``"s"``, ``"^"``, ``"v"``, ``"D"``, ``"x"``, ``"+"`` or ``"."``
      markers (with error bars when ``yerr`` is given), ``"-"`` a solid line (the default),
      ``"--"`` a dashed line, or any other matplotlib format string;
    * ``"yerr"`` — symmetric error bars for a marker style: one value per point, or one for
      all (numbers or a quantity); ignored for lines.

    >>> spec = PlotSpec("drift", "Warm-up", "t (s)", "ω (°/h)", [{"x": [0, 1], "y": [2, 3]}])
    >>> spec.series[0]["y"]
    [2, 3]
    """

    #: the figure's identifier within the item (``"adev"``; ``name`` in a Word template's context)
    name: str
    #: the title drawn above the figure and used in its caption (a :func:`msg` is translated)
    title: str
    #: the x-axis label, with its unit (``"τ (s)"``)
    xlabel: str
    #: the y-axis label, with its unit
    ylabel: str
    #: the curves: mappings with the keys ``x``, ``y``, ``label``, ``style``, ``yerr`` (above)
    series: tuple[Mapping[str, Any], ...] = attrs.field(converter=tuple)
    #: a logarithmic x axis (non-positive values are not drawn)
    logx: bool = False
    #: a logarithmic y axis (non-positive values are not drawn)
    logy: bool = False


@attrs.frozen
class TableSpec:
    """A supplementary table (e.g. B_s(τ_k) per level).

    >>> TableSpec("levels", "Levels", ["τ (s)", "B (°/h)"], [[1, "0.02"]]).rows
    ((1, '0.02'),)
    """

    #: the table's identifier within the item (``"levels"``; ``name`` in a Word template's context)
    name: str
    #: the title printed above the table (a :func:`msg` is translated)
    title: str
    #: the column headings, units included (``"τ (s)"``)
    header: tuple[str, ...] = attrs.field(converter=tuple)
    #: the rows, each a sequence of cells as long as ``header``; a cell is printed as ``str(cell)``
    #: (format numbers yourself, e.g. with :func:`fmt_num`)
    rows: tuple[tuple[Any, ...], ...] = attrs.field(
        converter=lambda rs: tuple(tuple(r) for r in rs))


@attrs.frozen
class Outcome:
    """What one procedure produced from one campaign: ``Procedure.evaluate`` returns it.

    Build it as ``Outcome(self.standard, self.item, self.title, self.clause, results, …)``.
    """

    #: the standard's id (``"gbt45570"``): the procedure's ``standard``
    standard: str
    #: the item's id within the standard (``"D.5.1"``): the procedure's ``item``
    item: str
    #: the item's title: the procedure's ``title``
    title: str
    #: the clause the item implements: the procedure's ``clause``
    clause: str
    #: one :class:`Result` per metric evaluated, in the order to report them
    results: tuple[Result, ...] = attrs.field(converter=tuple)
    #: the figures the report draws for the item
    plots: tuple[PlotSpec, ...] = attrs.field(default=(), converter=tuple)
    #: the supplementary tables the report prints for the item
    tables: tuple[TableSpec, ...] = attrs.field(default=(), converter=tuple)
    #: deviations and cautions about this evaluation (texts or :func:`msg`), printed in the
    #: terminal, ``--json`` and the report's notes
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: the ids of the campaign segments the item used (reported as its data)
    segments: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: the option values the item ran with, by option name (reported; quantities as text read best)
    options: Mapping[str, Any] = attrs.field(factory=dict, converter=frozen_map)

    @property
    def id(self) -> str:
        """The qualified item id, ``standard:item`` (``"gbt45570:D.5.1"``)."""
        return f"{self.standard}:{self.item}"

    def result(self, key: str) -> Result:
        """The result of the metric ``key``; a ``KeyError`` when the item did not produce it."""
        for r in self.results:
            if r.metric.key == key:
                return r
        raise KeyError(key)



"""Conformity with a specification: limits, decision rules and verdicts.

A :class:`Specification` states one limit on one metric (``Kn ≤ 10 ppm``, ``B0`` within
``−1 °/h … +1 °/h``) and where the limit comes from (a table of a standard, a product
specification).  A :class:`DecisionRule` says how a measured value *and its expanded
uncertainty U* are compared with the limit; :func:`decide` gives a :class:`Verdict` that
states the rule, the limit, the value, U and the reason in words, so a report can print it
as it is.

Two rules (the ideas of ILAC-G8:09/2019 and JJF 1059.1's reporting of U):

* **simple acceptance** (:data:`SIMPLE`) — the measured value alone is compared with the
  limit (guard band w = 0); a value on the limit passes.  Every result gets pass or fail.
* **guarded acceptance** (:data:`GUARDED`, metro's default) — the guard band is w = U: pass
  only if the whole interval value ± U lies within the limits, fail only if the whole
  interval lies outside; otherwise the verdict is *indeterminate* ("conditional pass" when
  the value itself is inside, "conditional fail" when it is outside).  Without U the rule
  cannot decide and says so.

Comparisons are unit-checked: the value and U are converted to the limit's unit (``ppm``
against ``1e-5``, ``″/s`` against ``°/h``); quantities of different kinds (an angle rate
against an angle, ``deg/h`` against ``Hz``) are a :class:`~metro.core.base.errors.UnitError`.

Plugins supply specifications through the ``metro_conformity_specifications`` hook; a
campaign manifest may give its own in a ``[specification]`` table (see docs/data-format.md),
read by :func:`parse_limit`.
"""

from __future__ import annotations

import enum
import math
import re
from typing import Any, Iterable, Mapping, Sequence

import attrs
import pint

from ..base.errors import DataError, UnitError
from ..base.locale import msg
from ..base.vocabulary import did_you_mean
from ..base.formatting import BOUND_SIGNS
from ..base.units import angle_power, fmt_unit, parse_quantity

__all__ = [
    "Comparison",
    "Status",
    "Specification",
    "DecisionRule",
    "SIMPLE",
    "GUARDED",
    "RULES",
    "DEFAULT_RULE",
    "rule_named",
    "Verdict",
    "Assessment",
    "decide",
    "not_reportable",
    "assess",
    "parse_limit",
    "specifications_from_table",
    "split_table",
    "StandardLimits",
    "owners_of",
    "limits_for",
    "merge_specifications",
]


class Comparison(enum.Enum):
    """How a value is compared with a specification's limit."""

    AT_MOST = "≤"
    AT_LEAST = "≥"
    RANGE = "range"


class Status(enum.Enum):
    """A verdict's outcome."""

    PASS = "pass"
    FAIL = "fail"
    INDETERMINATE = "indeterminate"


def _is_quantity(_inst: Any, attribute: attrs.Attribute, value: Any) -> None:
    if value is not None and not isinstance(value, pint.Quantity):
        raise TypeError(f"{attribute.name} must be a pint quantity, got {value!r}")


def compatible(a: pint.Quantity, b: pint.Quantity) -> bool:
    return a.dimensionality == b.dimensionality and angle_power(a.units) == angle_power(b.units)


def _in_unit(q: pint.Quantity, target: pint.Quantity, what: str, symbol: str) -> float:
    """``q`` as a plain number in ``target``'s unit; a clear error across kinds of quantity."""
    if not isinstance(q, pint.Quantity):
        raise UnitError(None, f"specification {symbol}", f"the {what} {q!r} has no unit")
    if not compatible(q, target):
        raise UnitError(
            None, f"specification {symbol}",
            f"the {what} is in {fmt_unit(q.units)} but the limit is in {fmt_unit(target.units)}: "
            "these are different kinds of quantity and cannot be compared",
            hint="state the limit in a unit of the same kind as the metric (metro never rescales "
            "between kinds)",
        )
    return float(q.to(target.units).magnitude)


def _difference_in_unit(q: pint.Quantity, target: pint.Quantity, what: str, symbol: str) -> float:
    """An uncertainty (a difference) in ``target``'s unit: U = 0.3 K against a limit in °C is
    0.3."""
    if not isinstance(q, pint.Quantity) or not compatible(q, target):
        return _in_unit(q, target, what, symbol)  # raises the clear error
    try:  # a limit in °C: the difference unit is Δ°C
        unit = target._REGISTRY.Unit(f"delta_{target.units}")
    except (pint.errors.UndefinedUnitError, ValueError, AttributeError):
        unit = target.units
    try:
        return float(q.to(unit).magnitude)
    except (pint.errors.DimensionalityError, pint.errors.OffsetUnitCalculusError) as exc:
        raise UnitError(None, f"specification {symbol}",
                        f"the {what} is in {fmt_unit(q.units)}, an absolute temperature; an "
                        "uncertainty is a temperature difference (K or Δ°C)") from exc


@attrs.frozen
class Specification:
    """One limit on one metric.

    ``symbol`` is the metric key the limit applies to (as in ``Metric.key``: ``Kn``,
    ``B0``); it also applies to the keyed variants ``symbol_*`` of the same metric
    (``Bh`` → ``Bh_IRA``, ``Bh_XRA``, ``Bh_YRA``; ``Bs`` → ``Bs_10s``), of the ``items`` named
    (all items when empty).  ``limit`` is the bound
    for ``≤``/``≥`` and the lower bound of a ``range`` (``upper`` its upper bound).  With
    ``magnitude`` the absolute value of the result is compared (sensitivities whose sign
    only says which way the output moves).  ``source`` cites where the limit comes from.
    """

    symbol: str
    #: how the value is compared with ``limit``: ``AT_MOST`` (≤), ``AT_LEAST`` (≥) or ``RANGE``
    #: (``limit`` ≤ value ≤ ``upper``); a value on a bound conforms
    comparison: Comparison = attrs.field(validator=attrs.validators.instance_of(Comparison))
    limit: pint.Quantity = attrs.field(validator=_is_quantity)
    upper: pint.Quantity | None = attrs.field(default=None, validator=_is_quantity)
    source: str = ""
    #: the limited quantity's name in words (``"insulation resistance"``), or ``""``; for a
    #: reader of the specification, verdicts and reports print ``symbol`` and ``source``
    name: str = ""
    magnitude: bool = False
    #: when given, only results of these items are judged (a table row names its test methods)
    items: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: the decision rule this limit is always judged by ("simple" for a test condition the lab sets,
    #: such as a test severity); "" (default) the run's rule
    rule: str = attrs.field(default="", validator=attrs.validators.in_(("", "simple", "guarded")))

    def __attrs_post_init__(self) -> None:
        if not self.symbol:
            raise ValueError("a specification needs the metric symbol it applies to")
        if not math.isfinite(float(self.limit.magnitude)):
            raise ValueError(f"specification {self.symbol}: the limit must be finite")
        if self.comparison is Comparison.RANGE:
            if self.upper is None:
                raise ValueError(f"specification {self.symbol}: a range needs an upper bound")
            hi = _in_unit(self.upper, self.limit, "upper bound", self.symbol)
            if not hi >= float(self.limit.magnitude):
                raise ValueError(f"specification {self.symbol}: the upper bound is below the lower "
                                 "bound")
        elif self.upper is not None:
            raise ValueError(f"specification {self.symbol}: only a range has an upper bound")

    def applies_to(self, key: str, item: str | None = None) -> bool:
        """Whether a result keyed ``key`` (of ``item``) is judged by this limit."""
        if self.items and item is not None and item not in self.items:
            return False
        return key == self.symbol or key.startswith(self.symbol + "_")

    @property
    def bounds(self) -> tuple[float, float]:
        """(lower, upper) in the limit's unit; ±∞ where unbounded."""
        lim = float(self.limit.magnitude)
        if self.comparison is Comparison.AT_MOST:
            return -math.inf, lim
        if self.comparison is Comparison.AT_LEAST:
            return lim, math.inf
        return lim, _in_unit(self.upper, self.limit, "upper bound", self.symbol)

    def text(self) -> str:
        """The limit as a report prints it: ``≤ 10 ppm``, ``−1 … 1 °/h``, ``|x| ≤ 0.1 (°/h)/mT``."""
        from ..base.formatting import fmt_num

        u = fmt_unit(self.limit.units)
        u = "" if u == "1" else f" {u}"
        lead = "|x| " if self.magnitude else ""
        if self.comparison is Comparison.RANGE:
            lo, hi = self.bounds
            return f"{lead}{fmt_num(lo)} … {fmt_num(hi)}{u}".replace("-", "−")
        return (
            f"{lead}{self.comparison.value} {fmt_num(float(self.limit.magnitude))}{u}".replace(
                "-", "−")
        )


@attrs.frozen
class DecisionRule:
    """How a value and its expanded uncertainty U are judged against a limit.

    ``guard_band`` is ``"U"`` (guarded acceptance) or ``"none"`` (simple acceptance).
    ``statement`` is the sentence a report prints to say which rule was applied.
    """

    #: the rule's identifier, ``"simple"`` or ``"guarded"``: its key in :data:`RULES`, as the
    #: command line, a batch job and a specification's ``rule`` name it
    name: str
    #: the rule's short name as a report heads it (``"guarded acceptance (guard band w = U)"``)
    title: str
    guard_band: str
    statement: str

    @property
    def guarded(self) -> bool:
        return self.guard_band == "U"


SIMPLE = DecisionRule(
    "simple", "simple acceptance (guard band w = 0)", "none",
    "Simple acceptance: the measured value is compared with the limit; a value on the limit "
    "conforms. The expanded uncertainty U is reported but does not enter the decision, so the "
    "risk of a wrong decision near a limit can reach 50 %.",
)
GUARDED = DecisionRule(
    "guarded", "guarded acceptance (guard band w = U)", "U",
    "Guarded acceptance with the guard band w = U: a result conforms only if the whole interval "
    "value ± U lies within the limits, and does not conform only if the whole interval lies "
    "outside them; otherwise conformity is indeterminate (conditional pass or conditional fail). "
    "With U at about 95 % coverage the risk of a wrong pass or fail is at most about 2.5 %.",
)
RULES: Mapping[str, DecisionRule] = {r.name: r for r in (SIMPLE, GUARDED)}
#: the rule used when neither the command line nor the manifest chooses one
DEFAULT_RULE = GUARDED


def rule_named(name: str | None) -> DecisionRule:
    """The decision rule called ``name`` (``simple`` or ``guarded``; ``None`` → the default)."""
    if name is None or name == "":
        return DEFAULT_RULE
    key = str(name).strip().lower()
    if key not in RULES:
        raise DataError(None, "decision_rule",
                        f"unknown decision rule {name!r}; use one of {', '.join(RULES)}")
    return RULES[key]


@attrs.frozen
class Verdict:
    """The judgement of one result against one specification, with its reason in words."""

    #: the specification (limit) the result was judged against
    spec: Specification
    #: the decision rule applied: the specification's own ``rule`` when it has one, else the run's
    rule: DecisionRule
    #: the key of the judged result's metric (``"B0_low"``; ``spec.symbol`` or a keyed variant)
    key: str
    #: the item (test method) whose result was judged, or ``""`` when not given
    item: str
    #: the measured value, in the result's own unit (compared in the limit's unit; its absolute
    #: value when ``spec.magnitude``)
    value: pint.Quantity
    #: the expanded uncertainty U of the value, or None when none was evaluated (guarded
    #: acceptance then cannot decide: indeterminate)
    U: pint.Quantity | None
    #: the coverage factor k of U, or None when not known
    k: float | None
    #: the outcome: pass, fail or indeterminate
    status: Status
    #: the outcome in a word or two: ``"pass"``, ``"fail"``, ``"conditional pass"``,
    #: ``"conditional fail"``, ``"no U"`` or ``"not reportable"``
    detail: str
    #: the sentence a report prints to justify the outcome: the value (± U) against the limit
    #: (a :func:`msg`, translated in documents)
    reason: str

    @property
    def passed(self) -> bool:
        return self.status is Status.PASS

    def in_limit_unit(self) -> tuple[float, float | None]:
        """(value, U) as plain numbers in the limit's unit."""
        v = _in_unit(self.value, self.spec.limit, "value", self.spec.symbol)
        U = None if self.U is None else _difference_in_unit(self.U, self.spec.limit, "U",
                                                            self.spec.symbol)
        return v, U

    def as_dict(self) -> dict[str, Any]:
        unit = self.spec.limit.units
        value, U = self.in_limit_unit()
        return {
            "item": self.item,
            "key": self.key,
            "symbol": self.spec.symbol,
            "limit": self.spec.text(),
            "source": self.spec.source,
            "rule": self.rule.name,
            "value": value,
            "U": U,
            "k": self.k,
            "unit": fmt_unit(unit),
            "status": self.status.value,
            "detail": self.detail,
            "reason": self.reason,
        }


def _fmt(x: float, unit_text: str, sig: int = 4) -> str:
    from ..base.formatting import fmt_num

    return (fmt_num(x, sig) + ("" if unit_text == "1" else f" {unit_text}")).replace("-", "−")


def _digits(x: float, U: float) -> int:
    """Significant digits that keep x − U and x + U apart in the text (4 at least)."""
    ratio = abs(x) / U if U > 0 else math.inf
    if x == 0 or not math.isfinite(ratio):
        return 4
    return int(min(12, max(4, math.ceil(math.log10(ratio)) + 2)))


def decide(
    spec: Specification,
    value: pint.Quantity,
    U: pint.Quantity | None,
    rule: DecisionRule = DEFAULT_RULE,
    *,
    key: str | None = None,
    item: str = "",
    k: float | None = None,
) -> Verdict:
    """Judge ``value`` (expanded uncertainty ``U``, coverage factor ``k``) against ``spec``."""
    v = _in_unit(value, spec.limit, "value", spec.symbol)
    Uv = None if U is None else _difference_in_unit(U, spec.limit, "expanded uncertainty U",
                                                    spec.symbol)
    if not math.isfinite(v):
        raise ValueError(f"specification {spec.symbol}: the value is not finite")
    if Uv is not None and not (math.isfinite(Uv) and Uv >= 0):
        raise ValueError(f"specification {spec.symbol}: U must be a finite non-negative quantity, "
                         f"got {Uv}")
    ut = fmt_unit(spec.limit.units)
    lo, hi = spec.bounds
    x = abs(v) if spec.magnitude else v
    what = f"|{key or spec.symbol}|" if spec.magnitude else (key or spec.symbol)
    inside = lo <= x <= hi
    limit_text = spec.text()
    if not rule.guarded:
        status = Status.PASS if inside else Status.FAIL
        detail = "pass" if inside else "fail"
        if Uv is not None:
            reason = (msg("{what} = {x} is within {limit} (U = {U} not used by simple acceptance)",
                          what=what,
                          x=_fmt(x, ut), limit=limit_text, U=_fmt(Uv, ut)) if inside else
                      msg("{what} = {x} is outside {limit} (U = {U} not used by simple acceptance)",
                          what=what,
                          x=_fmt(x, ut), limit=limit_text, U=_fmt(Uv, ut)))
        else:
            reason = (msg("{what} = {x} is within {limit}", what=what, x=_fmt(x, ut),
                          limit=limit_text) if inside
                      else msg("{what} = {x} is outside {limit}", what=what, x=_fmt(x, ut),
                               limit=limit_text))
    elif Uv is None:
        status = Status.INDETERMINATE
        detail = "no U"
        reason = msg("{what} = {x} but no expanded uncertainty was evaluated, so guarded "
                     "acceptance cannot decide",
                     what=what, x=_fmt(x, ut))
    else:
        # the interval of the compared quantity; |x| cannot go below zero
        x_lo = max(0.0, x - Uv) if spec.magnitude else x - Uv
        x_hi = x + Uv
        sig = _digits(max(abs(x_lo), abs(x_hi)), Uv)
        interval = f"[{_fmt(x_lo, '1', sig)}, {_fmt(x_hi, ut, sig)}]"
        if lo <= x_lo and x_hi <= hi:
            status, detail = Status.PASS, "pass"
            reason = msg("{what} ± U = {interval} lies wholly within {limit}", what=what,
                         interval=interval,
                         limit=limit_text)
        elif x_hi < lo or x_lo > hi:
            status, detail = Status.FAIL, "fail"
            reason = msg("{what} ± U = {interval} lies wholly outside {limit}", what=what,
                         interval=interval,
                         limit=limit_text)
        else:
            status = Status.INDETERMINATE
            detail = "conditional pass" if inside else "conditional fail"
            reason = (msg("{what} = {x} is within {limit} but {what} ± U = {interval} straddles a "
                          "limit (conditional pass)", what=what, x=_fmt(x, ut), limit=limit_text,
                          interval=interval)
                      if inside else
                      msg("{what} = {x} is outside {limit} but {what} ± U = {interval} straddles a "
                          "limit (conditional fail)", what=what, x=_fmt(x, ut), limit=limit_text,
                          interval=interval))
    return Verdict(spec, rule, key or spec.symbol, item, value, U, k, status, detail, reason)


@attrs.frozen
class Assessment:
    """All verdicts of one run, the rule used, and the specifications no result met."""

    rule: DecisionRule
    verdicts: tuple[Verdict, ...] = attrs.field(converter=tuple)
    not_assessed: tuple[Specification, ...] = attrs.field(default=(), converter=tuple)

    @property
    def overall(self) -> Status | None:
        """fail if any verdict fails, else indeterminate if any is, else pass; None without
        verdicts."""
        if not self.verdicts:
            return None
        states = {v.status for v in self.verdicts}
        for s in (Status.FAIL, Status.INDETERMINATE):
            if s in states:
                return s
        return Status.PASS

    def counts(self) -> dict[str, int]:
        out = {s.value: 0 for s in Status}
        for v in self.verdicts:
            out[v.status.value] += 1
        return out


def not_reportable(spec: Specification, result: Any, rule: DecisionRule = DEFAULT_RULE, *,
                   item: str = "") -> Verdict:
    """The verdict on a result its procedure declared **not reportable**.

    A value the procedure cannot stand behind (its reason says why: a rounding coarser than the
    noise, a model the data contradict) is not compared with the limit under either rule: a pass or
    a fail read from it would be a conformity statement on a number the report does not issue
    (ILAC-G8:09/2019 §4: a statement needs the measured value *and* its uncertainty). It is
    ``indeterminate``, detail ``not reportable``, with the procedure's reason, and so counts as
    neither a pass nor a fail.

    The one exception is a result that *bounds* the quantity (``result.bound``: a megohmmeter over
    its range shows R > 10 GΩ): the true value lies in [value − U, ∞) for a lower bound, (−∞, value
    + U] for an upper one ([0, …] for a magnitude). When that whole half-line lies within the limit
    it conforms, when it lies wholly outside it does not; otherwise no statement is made, as above.
    """
    key = result.metric.key
    what = f"|{key}|" if spec.magnitude else key
    bound = getattr(result, "bound", "")
    if bound:
        v = _in_unit(result.value, spec.limit, "value", spec.symbol)
        Uv = 0.0 if result.U is None else _difference_in_unit(result.U, spec.limit,
                                                              "expanded uncertainty U", spec.symbol)
        lo, hi = spec.bounds
        if spec.magnitude:
            v = abs(v)
        x_lo, x_hi = (v - Uv, math.inf) if bound == "lower" else (-math.inf, v + Uv)
        if spec.magnitude:
            x_lo = max(0.0, x_lo)
        ut = fmt_unit(spec.limit.units)
        sign = BOUND_SIGNS[bound]
        edge = x_lo if bound == "lower" else x_hi
        inside, outside = lo <= x_lo and x_hi <= hi, x_hi < lo or x_lo > hi
        if inside or outside:
            said = dict(what=what, sign=sign, x=_fmt(edge, ut), reason=result.reason,
                        limit=spec.text())
            text = (msg("{what} {sign} {x} (a bound: {reason}) lies wholly within {limit}", **said)
                    if inside else
                    msg("{what} {sign} {x} (a bound: {reason}) lies wholly outside {limit}",
                        **said))
            status, word = (Status.PASS, "pass") if inside else (Status.FAIL, "fail")
            return Verdict(spec, rule, key, item, result.value, result.U,
                           getattr(result, "k", None), status, word, text)
    # the why is the result's own reason, printed with it (results table, --json, the terminal's
    # note)
    reason = msg("{what} is not reportable (the result gives the reason), so no statement of "
                 "conformity with {limit} is made", what=what, limit=spec.text())
    return Verdict(spec, rule, key, item, result.value, result.U, getattr(result, "k", None),
                   Status.INDETERMINATE, "not reportable", reason)


def assess(outcomes: Iterable[Any], specs: Sequence[Specification],
           rule: DecisionRule = DEFAULT_RULE) -> Assessment:
    """Judge every result of ``outcomes`` that a specification applies to.

    Where several apply to one result the most specific wins (the longest symbol: a limit on
    ``B0_low`` judges ``B0_low``, not the limit on ``B0``). A limit with its own ``rule`` (a test
    condition: simple acceptance) is judged by it whatever ``rule`` is. Verdicts come in the order
    of ``specs``. A result declared not reportable gets :func:`not_reportable`'s verdict
    (indeterminate, no statement), never a pass or fail.
    """
    outcomes = list(outcomes)
    judged: dict[int, list[tuple[Any, Any]]] = {}
    for o in outcomes:
        for r in o.results:
            fits = [i for i, sp in enumerate(specs) if sp.applies_to(r.metric.key, o.item)]
            if not fits:
                continue
            longest = max(len(specs[i].symbol) for i in fits)
            for i in fits:
                if len(specs[i].symbol) == longest:
                    judged.setdefault(i, []).append((o, r))
    def rule_of(sp: Specification) -> DecisionRule:
        return RULES[sp.rule] if sp.rule else rule

    verdicts = [decide(specs[i], r.value, r.U, rule_of(specs[i]), key=r.metric.key, item=o.item,
                       k=r.k)
                if getattr(r, "reportable", True)
                else not_reportable(specs[i], r, rule_of(specs[i]), item=o.item)
                for i in sorted(judged) for o, r in judged[i]]
    return Assessment(rule, verdicts, [sp for i, sp in enumerate(specs) if i not in judged])


# --------------------------------------------------------------------------------------
# Limits written as text (a manifest's [specification] table)
# --------------------------------------------------------------------------------------

_PER_CELSIUS = re.compile(r"/\s*(?:\(\s*)?(?:°C|℃|degC|degree_Celsius)(?:\s*\))?")
_RANGE = re.compile(r"^(?P<lo>.+?)\s*(?:\.\.|…|~|～)\s*(?P<hi>.+)$")  # lo may have a decimal point


def _quantity(text: str, file: str | None, field: str) -> pint.Quantity:
    # "/°C" in a sensitivity is a temperature *difference*; pint would read degC as an offset
    return parse_quantity(_PER_CELSIUS.sub("/delta_degC", text.strip()), file=file, field=field)


def parse_limit(symbol: str, text: str, *, source: str = "", file: str | None = None,
                field: str | None = None) -> Specification:
    """A specification from text: ``"<= 10 ppm"``, ``"≥ 0.25 P/″"``, ``"-1 .. 1 deg/h"``,
    ``"-1 deg/h .. +1 deg/h"``, ``"± 1 deg/h"`` (a range), ``"|x| <= 0.1 deg/h/mT"`` (magnitude).

    A bound without a unit in a range takes the other bound's unit.  Errors name ``file`` and
    ``field``.
    """
    field = field or f"specification.{symbol}"
    if not isinstance(text, str) or not text.strip():
        raise DataError(file, field, f"a limit must be text such as \"<= 10 ppm\", got {text!r}")
    t = text.strip()
    magnitude = False
    if t.startswith("|x|"):
        magnitude, t = True, t[3:].strip()
    for op, cmp in (("<=", Comparison.AT_MOST), ("≤", Comparison.AT_MOST),
                    (">=", Comparison.AT_LEAST), ("≥", Comparison.AT_LEAST)):
        if t.startswith(op):
            q = _quantity(t[len(op):], file, field)
            return Specification(symbol, cmp, q, source=source, magnitude=magnitude)
    if t.startswith(("±", "+-", "+/-")):
        q = _quantity(t.lstrip("±+-/ "), file, field)
        return Specification(symbol, Comparison.RANGE, -abs(q), abs(q), source=source,
                             magnitude=magnitude)
    m = _RANGE.match(t)
    if m is None:
        raise DataError(file, field, f"cannot read the limit {text!r}",
                        hint="write \"<= 10 ppm\", \">= 0.25 P/arcsec\", \"-1 .. 1 deg/h\" or \"± "
                        "1 deg/h\"")
    hi = _quantity(m["hi"], file, field)
    lo = _quantity(m["lo"], file, field)
    if lo.unitless and not hi.unitless:  # "-1 .. 1 deg/h": the lower bound takes the upper's unit
        lo = float(lo.magnitude) * hi.units
    try:
        return Specification(symbol, Comparison.RANGE, lo, hi, source=source, magnitude=magnitude)
    except (ValueError, UnitError) as exc:
        raise DataError(file, field,
                        f"cannot use the range {text!r}: {getattr(exc, 'detail', exc)}") from exc


#: keys of a [specification] table that are settings, not limits
SETTINGS = ("decision_rule", "source")


def specifications_from_table(table: Mapping[str, Any], *, file: str | None = None,
                              fields: Mapping[str, str] | None = None) -> list[Specification]:
    """The limits of a flat ``[specification]`` table (``symbol = "limit"`` lines); ``fields``
    names the manifest field of a line where it is not ``specification.<symbol>`` (a line of a
    ``[specification.<standard>]`` table)."""
    source = str(table.get("source") or "product specification (campaign manifest)")
    where = fields or {}
    out = []
    for key, val in table.items():
        if key in SETTINGS:
            continue
        field = where.get(key, f"specification.{key}")
        out.append(parse_limit(key, val, source=source, file=file, field=field))
    return out


# --------------------------------------------------------------------------------------
# Limits by standard: [specification.<standard>], "<standard>:<key>", and the flat form
# --------------------------------------------------------------------------------------

#: one line of a [specification] table: (its manifest field, its text)
Line = tuple[str, str]


def split_table(table: Mapping[str, Any], *, file: str | None = None
                ) -> tuple[dict[str, Line], dict[str, dict[str, Line]]]:
    """A manifest's ``[specification]`` table as (flat lines, lines by standard).

    A sub-table ``[specification.<standard>]`` and a key ``"<standard>:<key>"`` give lines of
    that standard; every other line is flat (the old form; :func:`limits_for` says which
    standard it belongs to).  Each line is ``(field, text)``.  A value that is not text, a
    sub-table inside a standard's table, or one line given in both forms is a
    :class:`~metro.core.base.errors.DataError` naming its field.
    """
    flat: dict[str, Line] = {}
    by_std: dict[str, dict[str, Line]] = {}

    def text(field: str, val: Any) -> str:
        if not isinstance(val, str):
            raise DataError(file, field, f"must be text such as \"<= 10 ppm\", got {val!r}",
                            hint="a standard's own limits go in [specification.<standard>]"
                            if isinstance(val, dict) else None)
        return val

    def add(std: str, key: str, field: str, val: Any) -> None:
        if not std or not key:
            raise DataError(file, field, "a line of a standard is written \"<standard>:<key>\"",
                            hint='e.g. "gbt45570:K" = ">= 0.5 P/″", '
                                 'or K = "…" under [specification.gbt45570]')
        mine = by_std.setdefault(std, {})
        if key in mine:
            raise DataError(file, field,
                            f"{key!r} of {std!r} is given twice: as {mine[key][0]} too",
                            hint=f"keep one: [specification.{std}] {key} = \"…\"")
        mine[key] = (field, text(field, val))

    for key, val in table.items():
        if isinstance(val, Mapping):
            for k, v in val.items():
                add(key, k, f"specification.{key}.{k}", v)
        elif ":" in key:
            std, _, k = key.partition(":")
            add(std.strip(), k.strip(), f"specification.{key}", val)
        else:
            flat[key] = (f"specification.{key}", text(f"specification.{key}", val))
    return flat, by_std


@attrs.frozen
class StandardLimits:
    """The ``[specification]`` lines that apply to one standard's results (:func:`limits_for`).

    ``table`` is the flat table a standard's plugin reads (settings and ``symbol = "limit"``),
    ``fields`` the manifest field of each line, ``warnings`` what the manifest should say
    otherwise (a flat line more than one standard has, a table naming no loaded standard).
    """

    table: Mapping[str, str] = attrs.field(factory=dict)
    fields: Mapping[str, str] = attrs.field(factory=dict)
    warnings: tuple[str, ...] = attrs.field(default=(), converter=tuple)

    def specifications(self, file: str | None = None) -> list[Specification]:
        """The limits, parsed; an error names the manifest field of the line."""
        return specifications_from_table(self.table, file=file, fields=self.fields)


def owners_of(key: str, metric_keys: Mapping[str, Iterable[str]]) -> list[str]:
    """The standards (sorted) having a metric a flat limit keyed ``key`` judges (``B0`` judges
    ``B0`` and ``B0_low``): ``metric_keys`` gives each loaded standard's metric keys."""
    return sorted(std for std, keys in metric_keys.items()
                  if any(k == key or k.startswith(key + "_") for k in keys))


def limits_for(table: Mapping[str, Any], standard: str, metric_keys: Mapping[str, Iterable[str]],
               *, file: str | None = None) -> StandardLimits:
    """The lines of a manifest's ``[specification]`` that judge ``standard``'s results.

    ``[specification.<standard>]`` (or ``"<standard>:<key>"``) lines are that standard's; a
    flat line belongs to the standards having a metric of its key (:func:`owners_of`, over
    ``metric_keys``, every loaded standard's metric keys).  A flat line is used when
    ``standard`` has the key, or when no loaded standard has it (read as before); a flat line
    that more than one standard has is applied to ``standard`` with a warning — unless
    ``standard``'s own table gives the key, whose line replaces it.  Settings (``source``,
    ``decision_rule``) are read flat and from the standard's table, which prevails.
    """
    flat, by_std = split_table(table, file=file)
    own = by_std.get(standard, {})
    lines: dict[str, Line] = {}
    warnings = []
    for key, line in flat.items():
        owners = [] if key in SETTINGS else owners_of(key, metric_keys)
        if owners and standard not in owners:
            continue  # another standard's key
        if len(owners) > 1 and key not in own:
            names = ", ".join(owners[:-1]) + " and " + owners[-1]
            warnings.append(
                f"{file}: field '{line[0]}': {key!r} is a metric of {names}; this line is "
                f"applied to {standard}, the standard being run — write it under "
                f"[specification.{standard}] (docs/data-format.md)")
        lines[key] = line
    lines.update(own)
    for std in sorted(set(by_std) - set(metric_keys)):
        guess = did_you_mean(std, metric_keys)
        warnings.append(f"{file}: field 'specification.{std}': no loaded standard is called "
                        f"{std!r}; its lines are not applied"
                        + (f" — did you mean {guess!r}?" if guess else ""))
    return StandardLimits({k: t for k, (_, t) in lines.items()},
                          {k: f for k, (f, _) in lines.items()}, warnings)


def merge_specifications(*groups: Sequence[Specification]) -> list[Specification]:
    """Later groups replace earlier ones symbol by symbol (a product specification given in the
    manifest overrides a standard's typical table for the same metric)."""
    out: dict[str, list[Specification]] = {}
    for group in groups:
        mine: dict[str, list[Specification]] = {}
        for s in group:
            mine.setdefault(s.symbol, []).append(s)
        out.update(mine)
    return [s for specs in out.values() for s in specs]

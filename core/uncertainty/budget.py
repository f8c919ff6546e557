"""Uncertainty budgets (JJF 1059.1—2012, the GUM law of propagation for uncorrelated inputs).

A budget is a table of rows, one per source of uncertainty: its type (A or B), the
distribution assumed, the value as stated by the source (a half-width, an expanded
uncertainty, a standard deviation), the divisor that turns it into a standard uncertainty
u(x_i), the sensitivity coefficient c_i = ∂y/∂x_i, the contribution u_i(y) = |c_i|·u(x_i) and
the degrees of freedom ν_i.  From the rows:

* combined standard uncertainty  u_c(y) = sqrt(Σ u_i(y)²)                (JJF 1059.1, eq. (24))
* effective degrees of freedom   ν_eff = u_c⁴ / Σ (u_i⁴ / ν_i)            (Welch–Satterthwaite,
  JJF 1059.1 eq. (34)); rows with ν_i = ∞ add nothing
* coverage factor k: a fixed k (usually 2), or k = t_p(ν_eff) for a stated coverage
  probability p (JJF 1059.1 clause 5.3.4)
* expanded uncertainty U = k·u_c, reported with at most two significant digits and the
  result rounded to the same decimal place (JJF 1059.1 clause 5.3.8).  Rounding follows
  GB/T 8170 (round half to even) unless a procedure asks for "round up", which some
  appendices use to stay on the safe side.

Inputs are assumed uncorrelated; a procedure whose inputs are correlated folds the
correlation into one row (and says so in the row's note).

Rows are metro's own values (``attrs.frozen``); the ``uncertainties`` package may help a
procedure propagate, but the budget table is never built from its internals.
"""

from __future__ import annotations

import functools
import math
from decimal import ROUND_CEILING, ROUND_HALF_EVEN, ROUND_FLOOR, Decimal
from typing import TYPE_CHECKING, Callable, Literal

import attrs
import pint

from ..base.locale import msg
from ..base.formatting import power_of_ten
from ..base.units import Q_, fmt_unit, ureg

if TYPE_CHECKING:
    import numpy as np

Distribution = Literal["normal", "uniform", "triangular", "arcsine", "t", "rectangular"]
RoundMode = Literal["half-even", "up"]

#: the divisor that turns a bounded distribution's half-width a into u (GUM 4.3.7 and 4.3.9; the
#: arcsine after JCGM 101 6.4.6); ``None`` for a normal value, whose divisor is its stated k
DIVISORS = {
    "normal": None,
    "uniform": math.sqrt(3.0),
    "rectangular": math.sqrt(3.0),
    "triangular": math.sqrt(6.0),
    "arcsine": math.sqrt(2.0),
}

INF = math.inf


def _as_q(x: pint.Quantity | float | int, unit: str | pint.Unit = "") -> pint.Quantity:
    if isinstance(x, pint.Quantity):
        return x
    return Q_(float(x), unit)


def _positive_or_inf(instance, attribute, value) -> None:
    if not (value > 0):
        raise ValueError(
            f"{attribute.name} must be > 0 (use math.inf for an exactly known bound), got {value}"
        )


@attrs.frozen
class BudgetRow:
    """One source of uncertainty.

    ``value`` is as the source states it (a half-width ``a``, an expanded uncertainty ``U``
    or a standard deviation); ``divisor`` turns it into the standard uncertainty
    ``u(x) = value / divisor``; ``sensitivity`` is ``c = ∂y/∂x`` in output-unit per
    input-unit; the row's contribution to the output is ``|c|·u(x)``.
    """

    #: the source of uncertainty in words (``"resolution of the reading (±q/2)"``), the row's
    #: label in the budget table (a :func:`msg` is translated in documents)
    source: str
    #: the symbol of the input's standard uncertainty as the table prints it (``"u(q)"``,
    #: ``"u_rel(K)"``, ``"s(K_i)/√n"``)
    symbol: str
    #: the evaluation: ``"A"`` (statistical analysis of the measured data) or ``"B"`` (other
    #: information: a certificate, a resolution, a specified bound)
    type: Literal["A", "B"] = attrs.field(validator=attrs.validators.in_(("A", "B")))
    #: the distribution assumed for the input: ``"normal"`` (every type A row; a type B
    #: value with its k), ``"uniform"``/``"rectangular"`` (divisor √3), ``"triangular"`` (√6),
    #: ``"arcsine"`` (√2); printed only, ``divisor`` is what enters u(x_i)
    distribution: str
    value: pint.Quantity
    divisor: float = attrs.field(validator=_positive_or_inf)
    sensitivity: pint.Quantity
    #: the degrees of freedom ν_i of u(x_i), > 0 (n − 1 for a mean of n readings);
    #: ``math.inf`` (default) when u(x_i) is taken as exactly known, as for most type B rows:
    #: such a row adds nothing to the Welch–Satterthwaite sum of ν_eff
    dof: float = attrs.field(default=INF, validator=_positive_or_inf)
    #: a remark printed with the row (the certificate it comes from, a correlation folded into
    #: it), or ``""``
    note: str = ""

    @property
    def standard_uncertainty(self) -> pint.Quantity:
        """u(x_i) = value / divisor, in the input's unit."""
        return abs(self.value) / self.divisor

    @property
    def contribution(self) -> pint.Quantity:
        """u_i(y) = |c_i|·u(x_i), in the output's unit."""
        return abs(self.sensitivity) * self.standard_uncertainty

    # -- named constructors -------------------------------------------------------------
    @classmethod
    def type_a(
        cls,
        source: str,
        symbol: str,
        u: pint.Quantity,
        dof: float,
        sensitivity: pint.Quantity | float = 1.0,
        note: str = "",
    ) -> "BudgetRow":
        """A type A row: ``u`` is already a standard uncertainty from the data, with ``dof``."""
        return cls(
            source, symbol, "A", "normal", _as_q(u), 1.0, _as_q(sensitivity), float(dof), note
        )

    @classmethod
    def type_b(
        cls,
        source: str,
        symbol: str,
        value: pint.Quantity,
        *,
        distribution: str = "uniform",
        k: float | None = None,
        sensitivity: pint.Quantity | float = 1.0,
        dof: float = INF,
        note: str = "",
    ) -> "BudgetRow":
        """A type B row from a half-width (uniform/triangular/arcsine) or an expanded
        uncertainty with its ``k`` (normal).

        ``distribution`` is one of ``"uniform"`` or ``"rectangular"`` (divisor √3),
        ``"triangular"`` (√6), ``"arcsine"`` (√2), or ``"normal"`` (divisor ``k``, which is then
        required); another name raises :class:`ValueError`."""
        if distribution == "normal":
            if k is None:
                raise ValueError(f"{source}: a normal type B value needs its coverage factor k")
            divisor = float(k)
        else:
            if distribution not in DIVISORS:
                raise ValueError(f"{source}: unknown distribution {distribution!r}")
            divisor = DIVISORS[distribution]  # type: ignore[assignment]
        return cls(
            source, symbol, "B", distribution, _as_q(value), divisor, _as_q(sensitivity), dof, note
        )

    @classmethod
    def from_calibration(
        cls,
        source: str,
        symbol: str,
        calibration: "Calibration",  # noqa: F821 - metro.core.model.campaign.Calibration
        *,
        sensitivity: pint.Quantity | float = 1.0,
        note: str = "",
    ) -> "BudgetRow":
        """A type B row from a piece of equipment's calibration certificate (U and k)."""
        dist = calibration.distribution
        return cls.type_b(
            source,
            symbol,
            calibration.uncertainty,
            distribution=dist,
            k=calibration.k if dist == "normal" else None,
            sensitivity=sensitivity,
            note=note or msg("certificate {certificate}", certificate=calibration.certificate),
        )


@attrs.frozen
class Coverage:
    """How the coverage factor is chosen: a fixed ``k`` or ``t_p(ν_eff)`` for probability ``p``."""

    k: float | None = 2.0
    p: float | None = None

    @classmethod
    def fixed(cls, k: float = 2.0) -> "Coverage":
        return cls(k=float(k), p=None)

    @classmethod
    def probability(cls, p: float = 0.9545) -> "Coverage":
        if not 0.5 < p < 1:
            raise ValueError(f"coverage probability must be in (0.5, 1), got {p}")
        return cls(k=None, p=float(p))

    def factor(self, nu_eff: float) -> float:
        if self.k is not None:
            return self.k
        # scipy.special, not scipy.stats: the same quantiles without a 1–3 s import
        from scipy.special import ndtri, stdtrit

        q = (1.0 + self.p) / 2.0
        if math.isinf(nu_eff) or nu_eff > 1e7:
            return float(ndtri(q))
        return float(stdtrit(nu_eff, q))

    def describe(self) -> str:
        if self.k is not None:
            return f"k = {self.k:g}"
        return f"k = t_p(ν_eff), p = {self.p * 100:.2f} %"


@attrs.frozen
class UncertaintyBudget:
    """A complete budget for one measurand.

    ``unit`` is the output's unit; every row's contribution must convert to it (a row that
    does not is refused when the budget is built).
    """

    #: the output quantity y the budget is for, as a name or symbol (``"K"``, ``"mean of the
    #: static record"``); a report's budget title adds it to the result's name when it says more
    measurand: str
    unit: pint.Unit = attrs.field(
        converter=lambda u: ureg.Unit(u) if not isinstance(u, pint.Unit) else u
    )
    #: the sources of uncertainty, one :class:`BudgetRow` each, in the table's order; at least
    #: one; inputs are taken as uncorrelated
    rows: tuple[BudgetRow, ...] = attrs.field(converter=tuple)
    #: how the coverage factor k is chosen: a fixed k (default k = 2) or k = t_p(ν_eff) for a
    #: coverage probability p (:class:`Coverage`)
    coverage: Coverage = Coverage.fixed(2.0)
    #: how U is rounded to two significant digits: ``"half-even"`` (default, GB/T 8170) or
    #: ``"up"`` (rounded up, to stay on the safe side)
    round_mode: str = attrs.field(
        default="half-even", validator=attrs.validators.in_(("half-even", "up"))
    )
    #: True when u_c and U are relative (fractions of the value: ``unit`` is ``""``, ``ppm``,
    #: ``percent``); recorded with the budget, no computation depends on it
    relative: bool = False
    #: a remark printed under the budget table, or ``""``
    note: str = ""
    #: the measurement model where it is not the linear Σ c_i·x_i (a ratio, a maximum, a squared
    #: term), or None: a function of the rows' input deviations δx_i — an array of shape
    #: (rows, M), row i in the unit of its ``value``, drawn about 0 with u(x_i) — that returns the
    #: M deviations δy of the output from its estimate, in ``unit``.  It reads the rows it needs
    #: by position (a row appended later is drawn but need not be read).  Only the Monte Carlo
    #: check (:mod:`.montecarlo_budget`) uses it: u_c, ν_eff, k and U stay those of the rows
    model: Callable[[np.ndarray], np.ndarray] | None = attrs.field(
        default=None, kw_only=True, eq=False, repr=False
    )

    @rows.validator
    def _check_rows(self, attribute, rows) -> None:
        if not rows:
            raise ValueError(f"budget for {self.measurand!r} has no rows")
        for row in rows:
            c = row.contribution
            if c.dimensionality != self.unit.dimensionality:
                raise ValueError(
                    f"budget for {self.measurand!r}: row {row.source!r} contributes in "
                    f"{fmt_unit(c.units)}, which does not convert to {fmt_unit(self.unit)}"
                )

    def contributions(self) -> list[float]:
        """Each row's |c_i|·u(x_i), as magnitudes in the budget's unit."""
        return list(self._contributions)

    @functools.cached_property
    def _contributions(self) -> tuple[float, ...]:
        # computed once per budget (rows are frozen): u_c, ν_eff, k and U each need them, and a
        # report asks for those of every budget many times (pint arithmetic, ~0.3 ms a row)
        return tuple(float(r.contribution.to(self.unit).magnitude) for r in self.rows)

    @property
    def combined(self) -> pint.Quantity:
        """u_c(y) = sqrt(Σ u_i(y)²)  (JJF 1059.1 eq. (24), uncorrelated inputs)."""
        return Q_(math.sqrt(sum(c * c for c in self.contributions())), self.unit)

    @property
    def nu_eff(self) -> float:
        """Welch–Satterthwaite effective degrees of freedom (JJF 1059.1 eq. (34))."""
        uc = self.combined.magnitude
        denom = 0.0
        for c, row in zip(self.contributions(), self.rows):
            if not math.isinf(row.dof) and c > 0:
                denom += c**4 / row.dof
        if denom == 0.0 or uc == 0.0:
            return INF
        return uc**4 / denom

    @property
    def k(self) -> float:
        return self.coverage.factor(self.nu_eff)

    @property
    def expanded(self) -> pint.Quantity:
        """U = k·u_c (unrounded)."""
        return self.combined * self.k

    def expanded_reported(self) -> "Reported":
        """U rounded to at most two significant digits (JJF 1059.1 clause 5.3.8)."""
        return round_uncertainty(self.expanded.magnitude, mode=self.round_mode, unit=self.unit)

    def dominant(self) -> BudgetRow:
        """The row with the largest contribution."""
        cs = self.contributions()
        return self.rows[cs.index(max(cs))]

    def as_dict(self) -> dict:
        """A JSON-ready description of the budget (all numbers as floats, units as text)."""
        cs = self.contributions()
        nu = self.nu_eff
        rep = self.expanded_reported()
        return {
            "measurand": self.measurand,
            "unit": fmt_unit(self.unit),
            "relative": self.relative,
            "rows": [
                {
                    "source": r.source,
                    "symbol": r.symbol,
                    "type": r.type,
                    "distribution": r.distribution,
                    "value": float(r.value.magnitude),
                    "value_unit": fmt_unit(r.value.units),
                    "divisor": r.divisor,
                    "standard_uncertainty": float(r.standard_uncertainty.magnitude),
                    "sensitivity": float(r.sensitivity.magnitude),
                    "sensitivity_unit": fmt_unit(r.sensitivity.units),
                    "contribution": c,
                    "dof": None if math.isinf(r.dof) else r.dof,
                    "note": r.note,
                }
                for r, c in zip(self.rows, cs)
            ],
            "u_c": self.combined.magnitude,
            "nu_eff": None if math.isinf(nu) else nu,
            "k": self.k,
            "coverage": self.coverage.describe(),
            "U": self.expanded.magnitude,
            "U_reported": rep.text,
            "rounding": self.round_mode,
            "note": self.note,
        }


# --------------------------------------------------------------------------------------
# Rounding (JJF 1059.1—2012 clause 5.3.8; GB/T 8170 round-half-even unless "up")
# --------------------------------------------------------------------------------------


@attrs.frozen
class Reported:
    """A rounded number as it is printed, with the decimal exponent of its last digit."""

    #: the rounded number as a float, in ``unit``
    value: float
    #: the rounded number as printed, trailing zeros kept (``"0.00340"``, ``"1.4×10⁻⁶"``), without
    #: the unit
    text: str
    exponent: int  # the last kept digit is 10**exponent
    #: the unit of ``value``, or None when the number was rounded without one (a value rounded
    #: by :func:`report_pair`)
    unit: pint.Unit | None = None


#: Digits of a float beyond this many significant ones are taken as binary artefacts of the
#: arithmetic (0.1 + 0.2 = 0.30000000000000004), not as information: a relative 5×10⁻¹⁰ at most.
ARTEFACT_DIGITS = 10


def _without_artefact(x: Decimal, exponent: int) -> Decimal:
    """``x`` with the float artefact beyond :data:`ARTEFACT_DIGITS` significant digits removed
    (round half to even there), so that rounding *up* or a half-to-even tie at ``exponent``
    only sees digits that carry information; left as it is when the kept digits reach that far."""
    if x == 0:
        return x
    place = x.adjusted() - (ARTEFACT_DIGITS - 1)
    if place < exponent:
        return x.quantize(Decimal(1).scaleb(place), rounding=ROUND_HALF_EVEN)
    return x


def _decimal_round(x: Decimal, exponent: int, mode: str) -> Decimal:
    x = _without_artefact(x, exponent)
    q = Decimal(1).scaleb(exponent)
    if mode == "half-even":
        return x.quantize(q, rounding=ROUND_HALF_EVEN)
    if mode == "up":
        # "只进不舍": away from zero for a positive uncertainty
        return x.quantize(q, rounding=ROUND_CEILING if x >= 0 else ROUND_FLOOR)
    raise ValueError(f"unknown rounding mode {mode!r}")


def _fmt_decimal(d: Decimal, exponent: int) -> str:
    """Text of ``d`` keeping digits down to 10**exponent: plain, or ``1.4×10⁻⁶`` for large/small
    numbers (the way certificates print them)."""
    if d == 0:
        return "0" if exponent >= 0 else f"{0:.{-exponent}f}"
    lead = d.adjusted()
    if -5 <= lead < 6 and exponent > -10:
        if exponent >= 0:
            return f"{int(d):d}"
        return f"{d:.{-exponent}f}"
    # scientific: mantissa with (lead - exponent) decimals
    ndec = max(lead - exponent, 0)
    mant = d.scaleb(-lead)
    return power_of_ten(f"{mant:.{ndec}f}", lead)


def std_upper_limit(
    s: float, n_values: int | None = None, p: float = 0.02275, *, dof: float | None = None
) -> float:
    """Upper confidence limit of σ from a Bessel standard deviation ``s`` of ``n_values`` normal
    values (χ² with ν = n − 1), or with an effective ``dof`` ν instead (a Satterthwaite or Bartlett
    ν of correlated values, not an integer)::

        σ_upper = s·√(ν / χ²_p(ν)),   p = 0.02275 (the one-sided 97.7 %, k = 2 of a normal)

    At n = 7: 2.243·s; n = 6: 2.505·s (χ²₀.₀₂₂₇₅(5) = 0.797)."""
    from scipy.stats import chi2

    nu = float(dof) if dof is not None else int(n_values) - 1
    if not nu > 0:
        raise ValueError("a standard deviation needs at least two values (ν > 0)")
    return float(s) * math.sqrt(nu / float(chi2.ppf(p, nu)))


def std_sampling_u(s: float, n_values: int | None = None, *, dof: float | None = None) -> float:
    """Standard uncertainty of a repeatability s (a Bessel standard deviation of n values, or of
    effective ``dof`` ν) as an estimate of σ, from the χ² bound: (σ_upper − s)/2, entered with ν = ∞
    — s + 2u is the 97.7 % upper confidence limit.  The linear s/√(2(n − 1)) with ν = n − 1 covers σ
    in only ≈ 92 % of cases at n = 6 or 7 (its U is small exactly when s came out small); for large
    n the two agree (interpretations.md, "D.5.3 — what D.42 measures" and "Repeatabilities: the χ²
    bound")."""
    return (std_upper_limit(s, n_values, dof=dof) - float(s)) / 2.0


def between_variance(s2: float, within: float, dof: int) -> float:
    """The between-group variance σ_b² of a one-way random-effects analysis, as an uncertainty
    input:
    its posterior mean given the data, never 0 while ``within`` > 0.

    ``s2`` is the variance of the group values (ν = ``dof`` = Q − 1; e.g. B_r² of GB/T 45570 eq.
    (D.42) over Q power-ons), ``within`` the part of it that each value's own noise explains (mean
    u_A², taken as known: it rests on far more degrees of freedom than ``s2``).  τ = σ_b² + within
    is what ``s2`` estimates, ν·s2/τ ~ χ²(ν).  With the reference prior p(τ) ∝ 1/τ restricted to τ ≥
    within (Box & Tiao, *Bayesian Inference in Statistical Analysis*, 1973, §5.2: the one-way
    random-effect model), τ = ν·s2/X with X ~ χ²(ν) truncated to X ≤ c = ν·s2/within, and::

        E[σ_b² | data] = ν·s2·F_{ν−2}(c) / ((ν − 2)·F_ν(c)) − within        (F_m: the χ²(m) cdf)

    Well resolved (c → ∞) it is ν/(ν − 2)·s2 − within — the (n − 1)/(n − 3) of JCGM 101 6.4.9 for a
    variance from n values; unresolved (s2 → 0) 2·within/(ν − 2).  The moment estimate max(s2 −
    within, 0) (ISO 5725-2's s_L², set to 0 when negative) is 0 whenever s2 ≤ within, where the data
    only bound σ_b. E[σ_b²] is the variance of the predictive distribution of a further group's
    offset, so it enters a budget with ν = ∞ (interpretations.md, "σ_on — a variance component the
    data only bound").
    Needs ν ≥ 3 (the posterior mean is infinite with fewer): ValueError."""
    from scipy.stats import chi2

    nu = int(dof)
    if nu < 3:
        raise ValueError(
            "the posterior mean of a variance component needs at least 3 degrees of freedom, "
            f"got {nu}"
        )
    s2, within = float(s2), float(within)
    if not (s2 >= 0 and within >= 0 and math.isfinite(s2) and math.isfinite(within)):
        raise ValueError(
            f"variances must be finite and non-negative, got s2 = {s2!r}, within = {within!r}"
        )
    if within == 0.0:
        return nu * s2 / (nu - 2)
    if s2 == 0.0:
        return 2.0 * within / (nu - 2)
    c = nu * s2 / within
    tau = nu * s2 / (nu - 2) * math.exp(float(chi2.logcdf(c, nu - 2)) - float(chi2.logcdf(c, nu)))
    return max(tau - within, 0.0)


def round_uncertainty(U: float, *, digits: int = 2, mode: str = "half-even", unit=None) -> Reported:
    """Round an (expanded) uncertainty to ``digits`` significant digits (1 or 2).

    >>> round_uncertainty(0.0003367).text
    '0.00034'
    >>> round_uncertainty(4.24e-4, mode="up").text
    '0.00043'
    """
    if digits not in (1, 2):
        raise ValueError("JJF 1059.1 reports an uncertainty with one or two significant digits")
    if not math.isfinite(U) or U < 0:
        raise ValueError(f"uncertainty must be finite and non-negative, got {U}")
    if U == 0:
        return Reported(0.0, "0", 0, unit)
    d = Decimal(repr(float(U)))
    exponent = d.adjusted() - (digits - 1)
    r = _decimal_round(d, exponent, mode)
    if r.adjusted() > d.adjusted():  # 9.96 -> 10: keep `digits` significant digits
        exponent += 1
        r = _decimal_round(d, exponent, mode)
    return Reported(float(r), _fmt_decimal(r, exponent), exponent, unit)


def round_to(value: float, exponent: int, *, unit=None) -> Reported:
    """Round ``value`` to the decimal place 10**exponent (round half to even, GB/T 8170)."""
    if not math.isfinite(value):
        raise ValueError(f"value must be finite, got {value}")
    d = Decimal(repr(float(value)))
    r = _decimal_round(d, exponent, "half-even")
    return Reported(float(r), _fmt_decimal(r, exponent), exponent, unit)


def report_pair(
    value: float, U: float, *, digits: int = 2, mode: str = "half-even"
) -> tuple[Reported, Reported]:
    """Round U to ``digits`` significant digits and the value to the same decimal place."""
    rU = round_uncertainty(U, digits=digits, mode=mode)
    if U == 0:  # exact (a count, a value taken as declared): whole numbers whole, else 6 digits
        text = f"{int(value)}" if float(value).is_integer() else f"{float(value):.6g}"
        return Reported(value, text, 0), rU
    return round_to(value, rU.exponent), rU

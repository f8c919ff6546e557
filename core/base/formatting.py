"""Numbers and units as metro prints them: in reports, certificates, budgets and the terminal.

One notation everywhere: four significant digits unless asked, powers of ten as ``1.23×10⁻⁵``
(:func:`power_of_ten`), units as :func:`metro.core.base.units.fmt_unit` prints them and no
unit for a dimensionless quantity, a dash (:data:`DASH`) for what is missing.

Pure text functions: no document, no pint at import (:func:`unit_text` imports the unit
registry when first called), so every layer may use them.
"""

from __future__ import annotations

import math
import re
from typing import Any

__all__ = [
    "BOUND_SIGNS",
    "DASH",
    "power_of_ten",
    "fmt_num",
    "pretty_powers",
    "fmt_dof",
    "fmt_divisor",
    "unit_text",
    "with_unit",
    "fmt_quantity",
    "or_dash",
]

#: What a document prints for a missing value, fact or unit.
DASH = "—"

#: a bound as the terminal, the documents and the verdicts state it (``Result.bound``): the true
#: value is at least (``lower``) or at most (``upper``) the value shown
BOUND_SIGNS = {"lower": "≥", "upper": "≤"}

_SUPERSCRIPT = str.maketrans("0123456789-+", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻⁺")


def power_of_ten(mantissa: str, exponent: int) -> str:
    """``mantissa×10ⁿ`` as certificates print it (the one place metro writes a power of ten;
    budget rounding and :func:`fmt_num` use it).

    >>> power_of_ten("1.4", -6), power_of_ten("2", 12)
    ('1.4×10⁻⁶', '2×10¹²')
    """
    return f"{mantissa}×10{str(int(exponent)).translate(_SUPERSCRIPT)}"


def fmt_num(x: Any, sig: int = 4) -> str:
    """A number with ``sig`` significant digits, powers of ten as ``1.23×10⁻⁵``.

    ``None`` prints as a dash, infinity as ``∞``; integers print in full.

    >>> fmt_num(0.000012345), fmt_num(1234.5), fmt_num(2.0), fmt_num(None), fmt_num(float("inf"))
    ('1.234×10⁻⁵', '1234', '2', '—', '∞')
    """
    if x is None:
        return DASH
    if isinstance(x, bool):
        return str(x)
    if isinstance(x, int):
        return str(x)
    try:
        v = float(x)
    except (TypeError, ValueError):
        return str(x)
    if math.isnan(v):
        return "NaN"
    if math.isinf(v):
        return "∞" if v > 0 else "-∞"
    if v == 0:
        return "0"
    return pretty_powers(f"{v:.{sig}g}")


_SCI = re.compile(r"(?<![\w./\-])(-?\d+(?:\.\d+)?)[eE]([+-]\d{1,3})\b")


def pretty_powers(text: str) -> str:
    """Numbers written with Python's ``g`` format in free text (budget sources, notes,
    warnings) as a certificate prints them: ``±5e-06`` → ``±5×10⁻⁶``.

    Only a number standing alone is changed: hex digests and report numbers carry no sign
    after their ``e``, and a number glued to a name or path (``run-1e-5.csv``) is left as is.

    >>> pretty_powers("band ≤ 1000 °/s: ±5e-06 (uniform); 2.5E+03 s; run-1e-5.csv; sha 0e0a")
    'band ≤ 1000 °/s: ±5×10⁻⁶ (uniform); 2.5×10³ s; run-1e-5.csv; sha 0e0a'
    """
    return _SCI.sub(lambda m: power_of_ten(m.group(1), int(m.group(2))), text)


def fmt_dof(d: float | None) -> str:
    """Degrees of freedom: ``∞`` for none/infinite, whole numbers without decimals, a huge
    number with two significant digits (21776473 would read as precision it does not have).

    >>> fmt_dof(None), fmt_dof(6.0), fmt_dof(34.27), fmt_dof(3308.4), fmt_dof(21776473.0)
    ('∞', '6', '34.3', '3308', '2.2×10⁷')
    """
    if d is None or (isinstance(d, float) and math.isinf(d)):
        return "∞"
    d = float(d)
    if d >= 1e4:
        return fmt_num(d, 2)
    if abs(d - round(d)) < 1e-9 or d >= 100:
        return f"{d:.0f}"
    return f"{d:.3g}"


_ROOTS = ((math.sqrt(2.0), "√2"), (math.sqrt(3.0), "√3"), (math.sqrt(6.0), "√6"))


def fmt_divisor(d: float) -> str:
    """A budget row's divisor: the square roots of the usual distributions by name, else a number.

    >>> fmt_divisor(3 ** 0.5), fmt_divisor(2.0), fmt_divisor(1.0)
    ('√3', '2', '1')
    """
    for value, text in _ROOTS:
        if math.isclose(d, value, rel_tol=1e-9):
            return text
    return fmt_num(d)


def unit_text(u: Any) -> str:
    """A unit as :func:`metro.core.base.units.fmt_unit` prints it, empty for a dimensionless unit.

    >>> unit_text("deg/h"), unit_text("dimensionless")
    ('°/h', '')
    """
    from .units import fmt_unit

    text = fmt_unit(u)
    return "" if text in ("1", "") else text


def with_unit(num: str, unit: str) -> str:
    """``num unit``; a dimensionless or missing unit (empty, ``1`` or :data:`DASH`) is not printed.

    >>> with_unit("0.5", "°/h"), with_unit("3", "1"), with_unit("2", ""), with_unit("2", DASH)
    ('0.5 °/h', '3', '2', '2')
    """
    return num if unit in ("", "1", DASH) else f"{num} {unit}"


def fmt_quantity(q: Any, sig: int = 4) -> str:
    """A pint quantity (or anything else) as report text: ``20 ℃``, ``0.0012 °/√h``, ``1×10⁻⁷``.

    >>> from metro.core.base.units import Q_
    >>> fmt_quantity(Q_(45.0, "percent")), fmt_quantity(1e-7), fmt_quantity(None), fmt_quantity("x")
    ('45 %', '1×10⁻⁷', '—', 'x')
    """
    if hasattr(q, "magnitude") and hasattr(q, "units"):
        mag = q.magnitude
        if getattr(mag, "ndim", 0):
            numbers = ", ".join(fmt_num(m, sig) for m in mag.ravel())
            return f"[{numbers}] {unit_text(q.units)}".rstrip()
        return with_unit(fmt_num(mag, sig), unit_text(q.units))
    if isinstance(q, float):
        return fmt_num(q, sig)
    if q is None:
        return DASH
    return str(q)


def or_dash(v: Any) -> str:
    """Free text, or :data:`DASH` when empty or missing (a missing fact shows as missing).

    >>> or_dash("  Lab A "), or_dash(""), or_dash(None)
    ('Lab A', '—', '—')
    """
    s = "" if v is None else str(v).strip()
    return s or DASH

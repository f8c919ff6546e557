"""The application's single pint registry and unit helpers.

There is one :class:`pint.UnitRegistry` per process (``ureg``); it loads pint's defaults,
then ``units.txt`` next to this module, then every plugin's ``metro_unit_definitions``
lines.  All quantities in metro come from this registry; mixing registries is an error
in pint, and therefore an error here.

The field's units are available by their usual names::

    ureg("deg/h"), ureg("deg/s"), ureg("deg/hour**0.5"), ureg("arcsec"), ureg("arcmin"),
    ureg("P"), ureg("LSB"), ureg("mV"), ureg("g"), ureg("mT"), ureg("ppm"), ureg("1/degC")

Note 1 ″/s = 1 °/h exactly, which the GB/T 45570 pulse formulas rely on.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterable
from importlib import resources
from pathlib import Path
from typing import Any

import pint

from .errors import UnitError

__all__ = [
    "Q_",
    "Quantity",
    "UndefinedUnitTextError",
    "UnitTextError",
    "add_definitions",
    "angle_power",
    "check_dimension",
    "difference_unit",
    "fmt_unit",
    "normalise_unit_text",
    "parse_quantity",
    "unit",
    "ureg",
]


def _cache_folder() -> Path:
    """Where pint keeps its parsed definitions for *this* installation of pint.

    pint's own ``":auto:"`` folder is shared by every Python environment of the user, and the
    entries record the absolute path of the definitions file they were parsed from; once the
    environment that wrote them is deleted, every other environment with the same pint fails to
    build a registry (``FileNotFoundError: …/default_en.txt/constants_en.txt``, pint issue
    #1572).  A folder keyed by this pint's location and version keeps environments apart.
    ``METRO_CACHE_DIR`` overrides the user cache folder."""
    import hashlib
    import os

    root = os.environ.get("METRO_CACHE_DIR")
    if root:
        base = Path(root)
    else:
        import platformdirs

        base = platformdirs.user_cache_path(appname="metro", appauthor=False)
    where = f"{Path(pint.__file__).resolve().parent}|{pint.__version__}"
    key = hashlib.sha256(where.encode()).hexdigest()[:16]
    return base / "pint" / key


def _make_registry() -> pint.UnitRegistry:
    kw: dict[str, Any] = {"autoconvert_offset_to_baseunit": True, "non_int_type": float}
    try:
        reg = pint.UnitRegistry(**kw, cache_folder=_cache_folder())
    except Exception as exc:  # noqa: BLE001 - a damaged or unwritable cache only costs time
        import warnings

        warnings.warn(f"pint's definitions cache could not be used ({exc!r}); parsing without it",
                      stacklevel=2)
        reg = pint.UnitRegistry(**kw)
    text = resources.files(__package__).joinpath("units.txt").read_text(encoding="utf-8")
    _load_lines(reg, text.splitlines())
    reg.formatter.default_format = "~P"
    return reg


def _load_lines(reg: pint.UnitRegistry, lines: Iterable[str]) -> None:
    for raw in lines:
        line = raw.strip()
        if not line or line.startswith("#"):
            continue
        reg.define(line)


ureg: pint.UnitRegistry = _make_registry()


def Q_(value: Any, units: Any = None) -> pint.Quantity:
    """A quantity of the application registry; unit text may use the standards' symbols."""
    if isinstance(units, str):
        units = normalise_unit_text(units)
    if units is None:
        return ureg.Quantity(value)
    return ureg.Quantity(value, units)

Quantity = pint.Quantity
_added: set[str] = set()


def add_definitions(lines: Iterable[str], *, source: str = "plugin") -> None:
    """Add unit definition lines (pint syntax) to the application registry.

    Lines already added are skipped, so re-initialising plugins is harmless.
    """
    for line in lines:
        key = line.strip()
        if not key or key.startswith("#") or key in _added:
            continue
        try:
            ureg.define(key)
        except (pint.errors.RedefinitionError, pint.errors.DefinitionSyntaxError) as exc:
            raise UnitError(source, None, f"cannot add unit definition {key!r}: {exc}") from exc
        _added.add(key)


# Names (pint's canonical ones) of the units that measure a plane angle.  pint makes the
# radian dimensionless, so without this check "deg/h" and "Hz" (or "arcsec" and "ppm")
# would convert silently into each other.
_ANGLE_UNITS = frozenset(
    {"radian", "degree", "arcminute", "arcsecond", "milliradian", "microradian", "turn",
     "revolution", "gradian", "milliarcsecond", "microarcsecond"}
)


# --------------------------------------------------------------------------------------
# Reading unit text: the standards' symbols into pint syntax, strictly
# --------------------------------------------------------------------------------------

# Typographic symbols, longest first; each becomes a pint name.  "°C" before "°".
_SYMBOLS = (
    ("Δ°C", " delta_degC"),
    ("Δ℃", " delta_degC"),
    ("℃", " degC"),
    ("°C", " degC"),
    ("°", " deg"),
    ("″", " arcsec"),
    ("′", " arcmin"),
    ("gₙ", " gn"),
    ("g₀", " gn"),
    ("−", "-"),
)
_SUP_DIGITS = "⁰¹²³⁴⁵⁶⁷⁸⁹"
_SUP_ASCII = str.maketrans(_SUP_DIGITS + "⁻⁺⋅·.", "0123456789-+...")
# A superscript exponent: digits, with a decimal point written as pint prints it (⋅, U+22C5),
# as a middle dot (·) or as a full stop, between superscript digits only.
_SUP_EXP = re.compile(f"[⁻⁺]?[{_SUP_DIGITS}]+(?:[⋅·.][{_SUP_DIGITS}]+)?")
_PRODUCT_SIGNS = str.maketrans({"·": "*", "⋅": "*", "∙": "*", "×": "*"})
_TOKEN = re.compile(
    r"\s*(?:(?P<num>(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?)"
    r"|(?P<name>[^\W\d]\w*|%|‰)"
    r"|(?P<op>\*\*|\*|/|\^|\(|\)|\+|-))"
)
_BINARY = {"**", "*", "/", "^"}


class UnitTextError(UnitError, ValueError):
    """A text that is not a unit, or is ambiguous: a :class:`UnitError` naming the text, and a
    ``ValueError`` as pint's own parsing errors were, for callers that catch those.  Without a
    file or a field it says no "input:" (a caller wraps it in its own error naming them)."""

    def __init__(self, file: str | None, field: str | None, reason: str, *,
                 hint: str | None = None) -> None:
        super().__init__(file, field, reason, hint=hint)
        if file is None and not field:
            self.reason = reason


class UndefinedUnitTextError(UnitTextError, pint.errors.UndefinedUnitError):
    """A unit name metro does not know: a :class:`UnitTextError`, and pint's own
    ``UndefinedUnitError`` for callers that catch that."""


_HINT = ("write units as metro prints them (°/h, °/√h, °/h¹⋅⁵, P/″, LSB·s/°) or in pint syntax "
         "(deg/h, deg/hour**0.5, deg/h**1.5); see docs/data-format.md, Unit syntax")


def _bad(text: str, why: str, file: str | None, field: str | None,
         cls: type[UnitTextError] = UnitTextError) -> UnitTextError:
    return cls(file, field, f"cannot read the unit {text!r}: {why}", hint=_HINT)


def _sqrt(text: str, original: str, file: str | None, field: str | None) -> str:
    """``√h`` → ``((h)**0.5)``, ``√(Hz·s)`` → ``((Hz·s)**0.5)``: the root of the factor after it."""
    while "√" in text:
        i = text.index("√")
        j = i + 1
        while j < len(text) and text[j].isspace():
            j += 1
        if j < len(text) and text[j] == "(":
            depth, k = 0, j
            while k < len(text):
                depth += {"(": 1, ")": -1}.get(text[k], 0)
                if depth == 0:
                    break
                k += 1
            if depth:
                raise _bad(original, "unbalanced parentheses after √", file, field)
            end = k + 1
        else:
            m = re.compile(r"[^\W\d]\w*").match(text, j)
            if m is None:
                raise _bad(original, "√ must be followed by a unit or a parenthesised unit",
                           file, field)
            end = m.end()
        exp = re.compile(r"\*\*\((?:[^()]*)\)").match(text, end)  # √h³ = √(h³): root of the power
        if exp is not None:
            end = exp.end()
        text = f"{text[:i]}(({text[j:end]})**0.5){text[end:]}"
    return text


def _tokens(text: str, original: str, file: str | None, field: str | None) -> list[tuple[str, str]]:
    """``text`` (pint syntax) as (kind, token) pairs; any other character is an error."""
    out: list[tuple[str, str]] = []
    pos = 0
    while pos < len(text):
        if text[pos:].isspace():
            break
        m = _TOKEN.match(text, pos)
        if m is None or m.end() == pos:
            bad = text[pos:].lstrip()[:1]
            raise _bad(original, f"unexpected character {bad!r}", file, field)
        kind = m.lastgroup or ""
        out.append((kind, m.group(kind)))
        pos = m.end()
    return out


def _check_tokens(toks: list[tuple[str, str]], original: str, file: str | None,
                  field: str | None) -> None:
    """Refuse what pint would read silently as something else: ``deg//h``, a trailing or doubled
    operator, empty parentheses, and the ambiguous ``a/b·c`` (ISO 80000-1: a solidus is not
    followed by a product without parentheses; metro prints ``a·c/b``)."""
    if toks and (toks[-1][1] in _BINARY or toks[-1][1] in ("+", "-")):
        raise _bad(original, f"it ends with the operator {toks[-1][1]!r}", file, field)
    depth = 0
    after_slash = [False]  # per parenthesis level: the last operator at this level was "/"
    prev = ("", "")
    for kind, tok in toks:
        if kind == "op" and tok in _BINARY and (prev[1] in _BINARY or prev == ("", "")):
            raise _bad(original, f"operator {tok!r} where a unit is expected", file, field)
        if tok == "(":
            depth += 1
            after_slash.append(False)
        elif tok == ")":
            if prev[1] == "(":
                raise _bad(original, "empty parentheses", file, field)
            if prev[1] in _BINARY or depth == 0:
                raise _bad(original, "unbalanced parentheses", file, field)
            depth -= 1
            after_slash.pop()
        elif tok == "/":
            after_slash[-1] = True
        elif after_slash[-1] and (tok == "*" or (tok == "(" and prev[1] == ")")
                                  or (kind in ("name", "num") and prev[0] in ("name", "num"))):
            raise _bad(original, "ambiguous: a product after a solidus; write a·c/b or a/(b·c)",
                       file, field)
        prev = (kind, tok)
    if depth:
        raise _bad(original, "unbalanced parentheses", file, field)


def _pint_syntax(text: str, *, gravity: bool = False, file: str | None = None,
                 field: str | None = None) -> str:
    """``text`` in pint syntax, or :class:`UnitError` naming it (:func:`normalise_unit_text`)."""
    out = text
    for sym, rep in _SYMBOLS:
        out = out.replace(sym, rep)
    out = _SUP_EXP.sub(lambda m: f"**({m.group(0).translate(_SUP_ASCII)})", out)
    out = _sqrt(out, text, file, field)
    toks = _tokens(out.translate(_PRODUCT_SIGNS), text, file, field)
    _check_tokens(toks, text, file, field)
    names = {tok for kind, tok in toks if kind == "name"}
    if "g" in names and (gravity or len(names) > 1):
        # "g" with other units (°/h/g, mV·s/°/g) is standard gravity in the inertial field;
        # alone it is the gram, unless an acceleration is expected (parse_quantity).
        toks = [(k, "gn" if (k, t) == ("name", "g") else t) for k, t in toks]
    return " ".join(t for _, t in toks)


@functools.lru_cache(maxsize=4096)
def _cached_syntax(text: str) -> str:
    return _pint_syntax(text)


def normalise_unit_text(text: str) -> str:
    """Rewrite the standards' unit symbols into pint syntax; :class:`UnitError` for text that is
    not a unit or is ambiguous (never a silent simplification).

    ``"°/√h"`` -> ``"deg / ( ( h ) ** 0.5 )"``, ``"°/h¹⋅⁵"`` -> ``"deg / h ** ( 1.5 )"``,
    ``"P/″"`` -> ``"P / arcsec"``, ``"°/h/g"`` -> ``"deg / h / gn"``.  Accepted: the symbols
    °, ′, ″, ℃ (°C), Δ°C; superscript exponents with a decimal point written ⋅ (as pint prints
    it), · or .; √ of the factor after it; products ·, ⋅, ∙, ×, * or a space; quotients /;
    powers ** or ^; parentheses.  A bare ``g`` is the gram alone and standard gravity with other
    units; ``gn``, ``gₙ``, ``g_0`` are always standard gravity.  See docs/data-format.md, "Unit
    syntax".
    """
    return _cached_syntax(text)


def angle_power(unit: Any) -> float:
    """Exponent of plane angle in ``unit`` (1 for deg/h, 0 for Hz, -1 for P/″)."""
    if isinstance(unit, pint.Quantity):
        u = unit.units
    else:
        u = unit if isinstance(unit, pint.Unit) else ureg.Unit(unit)
    total = 0.0
    for name, exp in u._units.items():
        if name in _ANGLE_UNITS:
            total += exp
    return total


def difference_unit(u: Any) -> pint.Unit:
    """The unit of a difference or an uncertainty of quantities in ``u``: ``u`` itself, except
    for an offset unit (°C → Δ°C), whose values cannot be added or scaled."""
    uu = ureg.Unit(u) if not isinstance(u, pint.Unit) else u
    if Q_(1.0, uu)._is_multiplicative:
        return uu
    return ureg.Unit(" * ".join(f"delta_{name} ** {exp:g}" for name, exp in uu._units.items()))


def _syntax(text: str, gravity: bool, file: str | None, field: str | None) -> str:
    try:
        if gravity:
            return _pint_syntax(text, gravity=True, file=file, field=field)
        return _cached_syntax(text)
    except UnitError as exc:
        raise UnitTextError(file, field, exc.detail, hint=exc.hint) from None


def _wants_gravity(like: str | pint.Unit | None) -> bool:
    """Whether a lone ``g`` is standard gravity where a quantity like ``like`` is expected."""
    if like is None:
        return False
    want = like if isinstance(like, pint.Unit) else unit(like)
    return "[length]" in want.dimensionality and "[mass]" not in want.dimensionality


def unit(text: str | pint.Unit, *, like: str | pint.Unit | None = None, file: str | None = None,
         field: str | None = None) -> pint.Unit:
    """Parse a unit text (as metro prints it, the standards' symbols, or pint syntax) into a
    registry unit; :class:`UnitError` naming ``text`` (and ``file``, ``field``) for text that
    is not a unit or is ambiguous.  Every text :func:`fmt_unit` prints reads back to its unit.

    ``like`` is the unit expected there: where it is an acceleration, a lone ``g`` is standard
    gravity rather than the gram.

    >>> unit("°/h¹⋅⁵") == ureg.Unit("deg/hour**1.5"), unit("°/√h") == ureg.Unit("deg/hour**0.5")
    (True, True)
    """
    if isinstance(text, pint.Unit):
        return text
    if not isinstance(text, str):
        raise UnitError(file, field, f"a unit is text such as \"deg/h\", got {text!r}")
    syntax = _syntax(text, _wants_gravity(like), file, field)
    try:
        return ureg.Unit(syntax)
    except pint.errors.UndefinedUnitError as exc:
        err = _bad(text, str(exc), file, field, UndefinedUnitTextError)
        err.unit_names = exc.unit_names
        raise err from exc
    except Exception as exc:  # pint raises several types for bad text
        raise _bad(text, str(exc) or type(exc).__name__, file, field) from exc


def _split_number(syntax: str) -> tuple[float | int, str] | None:
    """``"1.5 deg / h"`` → ``(1.5, "deg / h")``; ``"1 * 10 ** ( - 6 ) deg"`` (1×10⁻⁶ °) → ``(1e-06,
    "deg")``; None when the text does not start with a number.  The unit is read apart from the
    number: pint, evaluating ``0.05 deg/h/degC`` as one expression, converts the °C (an offset
    unit) to 274.15 K instead of reading a temperature difference."""
    toks = syntax.split()
    i = 1 if toks[:1] in (["-"], ["+"]) else 0
    if i >= len(toks) or not re.fullmatch(r"[\d.]+(?:[eE][-+]?\d+)?", toks[i]):
        return None
    mantissa = "".join(toks[:i + 1])
    i += 1
    exponent = "0"
    if toks[i:i + 2] == ["*", "10"] and toks[i + 2:i + 3] in (["**"], ["^"]):  # 1×10⁻⁶, 1×10^-6
        j = i + 3
        paren = toks[j:j + 1] == ["("]
        j += paren
        k = j + (toks[j:j + 1] in (["-"], ["+"]))
        if k < len(toks) and toks[k].isdigit() and (not paren or toks[k + 1:k + 2] == [")"]):
            exponent = "".join(toks[j:k + 1])
            i = k + 1 + paren
    rest = toks[i:]
    if rest[:1] == ["*"]:
        rest = rest[1:]
    elif rest[:1] == ["/"]:
        rest = ["1", *rest]
    # the same arithmetic as pint's reading of the whole text: a whole number stays whole
    number = int(mantissa) if re.fullmatch(r"[-+]?\d+", mantissa) else float(mantissa)
    return (number * 10 ** int(exponent) if exponent != "0" else number), " ".join(rest)


def _split_unit(split: tuple[float | int, str] | None) -> pint.Unit | None:
    """The unit of :func:`_split_number`'s split, or None where there is none or it is not a unit
    alone (``2 ** 3 s``: then the whole text is read as pint reads it)."""
    if split is None:
        return None
    try:
        return ureg.Unit(split[1])
    except Exception:  # noqa: BLE001 - pint raises several types for text not a unit alone
        return None


def parse_quantity(
    value: Any,
    *,
    dimension: str | None = None,
    file: str | None = None,
    field: str | None = None,
) -> pint.Quantity:
    """Parse ``value`` ("1.5 deg/h", a number with no unit is refused) into a quantity.

    ``dimension`` is a unit whose dimensionality the value must share (e.g. ``"deg/h"``);
    a mismatch raises :class:`UnitError` naming ``file`` and ``field``.
    """
    if isinstance(value, pint.Quantity):
        q = value if value._REGISTRY is ureg else Q_(value.magnitude, str(value.units))
    elif isinstance(value, str):
        syntax = _syntax(value, _wants_gravity(dimension), file, field)
        split = _split_number(syntax)
        try:
            q = ureg.Quantity(syntax)  # the whole text, as pint reads it: the same numbers as ever
            u = _split_unit(split)
            if u is not None and isinstance(q, pint.Quantity) and q.units != u:
                # pint turned an offset unit into kelvin: "0.05 °/h/°C" read 1.8e-4 °/h/K
                q = ureg.Quantity(split[0], u)
            if not isinstance(q, pint.Quantity):
                q = ureg.Quantity(float(q), "")
        except Exception as exc:  # pint raises several types for bad strings
            raise UnitError(file, field, f"cannot read {value!r} as a quantity ({exc})") from exc
        if not isinstance(q, pint.Quantity):
            q = Q_(float(q), "")
    elif isinstance(value, (int, float)) and not isinstance(value, bool):
        if dimension is not None and not Q_(1, dimension).dimensionless:
            raise UnitError(
                file,
                field,
                f"the number {value!r} has no unit; write it with its unit, "
                f"e.g. \"{value} {dimension}\"",
            )
        q = Q_(float(value), "")
    else:
        raise UnitError(file, field,
                        f"expected a quantity such as \"1.5 {dimension or 'unit'}\", got {value!r}")
    if dimension is not None:
        check_dimension(q, dimension, file=file, field=field)
    return q


def check_dimension(q: pint.Quantity, dimension: str | pint.Unit, *, file: str | None = None,
                    field: str | None = None) -> None:
    """Raise :class:`UnitError` unless ``q`` has the dimensionality of the unit ``dimension`` (a
    unit text, or a registry unit: pass ``x.units`` rather than ``str(x.units)``, whose pint
    form writes a gram with other units as ``g``, which metro reads as standard gravity)."""
    want = unit(dimension) if dimension else ureg.Unit("")
    if (
        not isinstance(q, pint.Quantity)
        or q.dimensionality != want.dimensionality
        or angle_power(q.units) != angle_power(want)
    ):
        got = q.units if isinstance(q, pint.Quantity) else "no unit"
        raise UnitError(
            file,
            field,
            f"unit {fmt_unit(got)!s} is not compatible with {fmt_unit(want)} "
            f"(expected a quantity like {fmt_unit(want)}; "
            "metro never rescales between different kinds)",
        )


def is_voltage_ratio(u: Any) -> bool:
    """True for a ratiometric output's unit, a voltage over a voltage (``mV/V``, ``V/V``): pint
    reduces it to a plain number (``V/V`` to nothing at all), so it is told by its written form."""
    text = re.sub(r"\s+", "", str(u))
    text = text.replace("volt", "V").replace("milli", "m").replace("micro", "µ")
    return re.fullmatch(r"[mµuk]?V/V", text) is not None


# pint's short symbol of a unit -> the symbol the standards print
_PRETTY = {
    "deg": "°", "arcsec": "″", "arcmin": "′", "delta_degC": "°C", "Δ°C": "°C", "degC": "°C",
    "pulse": "P", "g_0": "g", "hr": "h",
}
_ROOTED = ("h", "s")  # printed √h, √s at the power 0.5
_FACTOR = re.compile(f"(?P<name>.*?)(?P<exp>⁻?[{_SUP_DIGITS}]+(?:⋅[{_SUP_DIGITS}]+)?)?")


def _pretty_factor(factor: str, names: set[str]) -> str:
    m = _FACTOR.fullmatch(factor)
    name, exp = (m["name"], m["exp"] or "") if m else (factor, "")
    if name == "g_0" and names == {"g_0"}:
        return "gn" + exp  # alone, "g" would read as the gram: standard gravity prints gn
    if name == "g" and len(names) > 1:
        return "gram" + exp  # with other units a bare "g" reads as standard gravity
    name = _PRETTY.get(name, name)
    if name in _ROOTED and exp == "⁰⋅⁵":
        return f"√{name}"
    return name + exp


def fmt_unit(u: Any) -> str:
    """Short, readable unit text as the standards print it (``°/h``, ``″``, ``P/″``, ``°/√h``,
    ``°/h¹⋅⁵``, ``°/h/g``); :func:`unit` reads every text it prints back to the same unit.

    Each factor of pint's short form is renamed whole (a prefixed ``mdeg`` is not touched).
    The one symbol the field writes for two units, ``g``, prints as the gram alone and as
    standard gravity with other units (``°/h/g``); standard gravity alone prints ``gn``.
    """
    if isinstance(u, pint.Quantity):
        u = u.units
    if not isinstance(u, pint.Unit):
        u = unit(str(u))
    text = f"{u:~P}"
    parts = re.split(r"([·/])", text)
    names = {p for p in (_FACTOR.fullmatch(f)["name"] for f in parts[::2] if _FACTOR.fullmatch(f))
             if p and p != "1"}
    text = "".join(p if i % 2 else _pretty_factor(p, names) for i, p in enumerate(parts))
    return text or "1"

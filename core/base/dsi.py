"""D-SI unit strings (PTB D-SI 2.2.1, ``si:unit``) from metro's units, and back.

A D-SI unit is a sequence of backslash tokens: an optional SI prefix (``\\milli``), a unit
(``\\volt``), an optional power (``\\tothe{-1}``); the factors multiply.  ``°/h`` is
``\\degree\\hour\\tothe{-1}``, ``°/√h`` is ``\\degree\\hour\\tothe{-0.5}``, ``ppm`` is ``\\ppm``.

The inertial field also writes units that are not SI nor accepted for use with it: the pulse
of a pulse-output gyro (``P``), the least significant bit of a digital output (``LSB``),
standard gravity (``gₙ``, a constant, not a unit of the SI) and the year.  D-SI marks such a
unit with a leading ``|``; metro writes the rest in the same token syntax, with its own
tokens ``\\pulse``, ``\\lsb``, ``\\standardgravity`` and ``\\year``: ``P/″`` is
``|\\pulse\\arcsecond\\tothe{-1}``.  Values are never rescaled to make a unit SI.

A temperature (°C) alone is ``\\degreecelsius``; with other factors (``°/h/°C``) it is a
temperature difference, which D-SI also writes ``\\degreecelsius``; a temperature difference
alone is ``\\kelvin``.  A unit with no mapping is refused with :class:`UnitError`, never
guessed.  docs/dcc.md gives the whole table.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Iterator

import pint

from .errors import UnitError
from .units import fmt_unit, unit, ureg

__all__ = ["DSI_PREFIXES", "DSI_UNITS", "NON_SI_MARK", "dsi_unit", "metro_unit"]

#: A D-SI unit string that starts with this character is not an SI unit (D-SI convention).
NON_SI_MARK = "|"

#: pint's canonical unit name -> (D-SI token, whether the token is SI or accepted with it).
DSI_UNITS: dict[str, tuple[str, bool]] = {
    "meter": ("metre", True), "gram": ("gram", True), "kilogram": ("kilogram", True),
    "second": ("second", True), "ampere": ("ampere", True), "kelvin": ("kelvin", True),
    "mole": ("mole", True), "candela": ("candela", True),
    "radian": ("radian", True), "steradian": ("steradian", True), "hertz": ("hertz", True),
    "newton": ("newton", True), "pascal": ("pascal", True), "joule": ("joule", True),
    "watt": ("watt", True), "coulomb": ("coulomb", True), "volt": ("volt", True),
    "farad": ("farad", True), "ohm": ("ohm", True), "siemens": ("siemens", True),
    "weber": ("weber", True), "tesla": ("tesla", True), "henry": ("henry", True),
    "degree_Celsius": ("degreecelsius", True), "lumen": ("lumen", True), "lux": ("lux", True),
    "becquerel": ("becquerel", True), "gray": ("gray", True), "sievert": ("sievert", True),
    "katal": ("katal", True),
    "minute": ("minute", True), "hour": ("hour", True), "day": ("day", True),
    "degree": ("degree", True), "arcminute": ("arcminute", True),
    "arcsecond": ("arcsecond", True), "liter": ("litre", True), "metric_ton": ("tonne", True),
    "electron_volt": ("electronvolt", True), "percent": ("percent", True),
    "ppm": ("ppm", True), "bit": ("bit", True), "byte": ("byte", True),
    "pulse": ("pulse", False), "LSB": ("lsb", False),
    "standard_gravity": ("standardgravity", False), "year": ("year", False),
}

#: pint's prefix name -> D-SI prefix token (the same words; ``deca`` is pint's ``deca``).
DSI_PREFIXES: dict[str, str] = {
    p: p for p in ("quetta", "ronna", "yotta", "zetta", "exa", "peta", "tera", "giga", "mega",
                   "kilo", "hecto", "deca", "deci", "centi", "milli", "micro", "nano", "pico",
                   "femto", "atto", "zepto", "yocto", "ronto", "quecto")
}

_TOKEN_TO_PINT = {token: name for name, (token, _) in DSI_UNITS.items()}
_DELTA_C = "delta_degree_Celsius"
_TOKEN = re.compile(r"\\([A-Za-z]+)(?:\{([^{}]*)\})?")


def _where(result: str | None) -> str:
    return f"result {result}" if result else "D-SI unit"


def _exponent(exp: float) -> str:
    """``-1`` → ``-1``, ``0.5`` → ``0.5``, ``-1.5`` → ``-1.5`` (a whole power prints whole)."""
    if float(exp).is_integer():
        return str(int(exp))
    return repr(float(exp))


def _factor(name: str, exp: float, text: str, result: str | None) -> tuple[str, bool]:
    """One factor of a pint unit as D-SI tokens, and whether it is SI."""
    parsed = ureg.parse_unit_name(name)
    prefix, base = (parsed[0][0], parsed[0][1]) if len(parsed) == 1 else ("", name)
    if name in DSI_UNITS:  # kilogram, before its split into kilo + gram
        prefix, base = "", name
    if base not in DSI_UNITS or (prefix and prefix not in DSI_PREFIXES):
        raise UnitError(None, _where(result),
                        f"the unit {text!r} has no D-SI mapping (its factor {name!r} is not in "
                        "metro's D-SI table); metro does not guess a unit",
                        hint="docs/dcc.md lists the units a DCC can carry")
    token, si = DSI_UNITS[base]
    out = (f"\\{DSI_PREFIXES[prefix]}" if prefix else "") + f"\\{token}"
    if exp != 1:
        out += f"\\tothe{{{_exponent(exp)}}}"
    return out, si


def dsi_unit(u: str | pint.Unit, *, result: str | None = None) -> str:
    """The D-SI unit string of a metro unit (text as metro prints it, or a registry unit).

    ``°/h`` → ``\\degree\\hour\\tothe{-1}``; ``LSB/(°/s)`` → ``|\\lsb\\second\\degree\\tothe{-1}``
    (marked not SI); dimensionless → ``\\one``.  :class:`UnitError` naming the unit (and
    ``result``, the quantity it belongs to, when given) for a unit with no mapping.
    """
    if isinstance(u, str):
        try:
            return _dsi_of_text(u)
        except UnitError as exc:  # the same refusal, naming the result
            raise UnitError(None, _where(result), exc.detail, hint=exc.hint) from None
    return _dsi_of_unit(u, fmt_unit(u), result)


@functools.lru_cache(maxsize=1024)
def _dsi_of_text(text: str) -> str:
    try:
        pu = unit(text)
    except UnitError as exc:
        raise UnitError(None, _where(None), f"the unit {text!r} has no D-SI mapping: "
                        f"{exc.detail}", hint=exc.hint) from exc
    return _dsi_of_unit(pu, text, None)


def _dsi_of_unit(pu: pint.Unit, text: str, result: str | None) -> str:
    items = list(pu._units.items())
    if not items:
        return "\\one"
    if items == [(_DELTA_C, 1)]:
        return "\\kelvin"  # a temperature difference alone
    parts: list[str] = []
    all_si = True
    # positive powers first, then negative ones: m·s⁻¹ reads as m/s
    for name, exp in sorted(items, key=lambda kv: kv[1] < 0):
        base = "degree_Celsius" if name == _DELTA_C else name
        token, si = _factor(base, exp, str(text), result)
        parts.append(token)
        all_si = all_si and si
    return ("" if all_si else NON_SI_MARK) + "".join(parts)


def _tokens(dsi: str) -> Iterator[tuple[str, str | None]]:
    """The (name, argument) tokens of a D-SI string; :class:`UnitError` for any other text."""
    pos = 0
    while pos < len(dsi):
        m = _TOKEN.match(dsi, pos)
        if m is None:
            raise UnitError(None, "D-SI unit",
                            f"cannot read the D-SI unit {dsi!r}: unexpected text at "
                            f"{dsi[pos:pos + 12]!r} (each token is \\name or \\tothe{{n}})")
        yield m.group(1), m.group(2)
        pos = m.end()


def _power(arg: str | None, dsi: str) -> float:
    try:
        return float(arg or "")
    except ValueError:
        raise UnitError(None, "D-SI unit",
                        f"cannot read the D-SI unit {dsi!r}: \\tothe{{{arg}}} is not a number"
                        ) from None


def _factors(dsi: str) -> list[tuple[str, float]]:
    """``\\milli\\volt\\second\\degree\\tothe{-1}`` → [(millivolt, 1), (second, 1), (degree, -1)];
    one ``\\per`` divides what precedes it by what follows it."""
    out: list[tuple[str, float]] = []
    prefix = ""
    per_at: int | None = None
    for name, arg in _tokens(dsi):
        if name == "tothe":
            if not out or prefix:
                raise UnitError(None, "D-SI unit",
                                f"cannot read the D-SI unit {dsi!r}: \\tothe follows no unit")
            last, exp = out[-1]
            out[-1] = (last, exp * _power(arg, dsi))
        elif name == "per":
            if per_at is not None or not out or prefix:
                raise UnitError(None, "D-SI unit", f"cannot read the D-SI unit {dsi!r}: "
                                "\\per must stand once, between units")
            per_at = len(out)
        elif name in DSI_PREFIXES.values() and not prefix:
            prefix = name
        elif name in _TOKEN_TO_PINT or name == "one":
            if name == "one" and prefix:
                raise UnitError(None, "D-SI unit", f"a prefix before \\one in {dsi!r}")
            out.append((prefix + _TOKEN_TO_PINT[name] if name != "one" else "", 1.0))
            prefix = ""
        else:
            raise UnitError(None, "D-SI unit",
                            f"the D-SI unit {dsi!r} has the token \\{name}, which metro does "
                            "not map to a unit", hint="docs/dcc.md lists the units metro reads")
    if prefix:
        raise UnitError(None, "D-SI unit", f"cannot read the D-SI unit {dsi!r}: a prefix "
                        "ends it")
    if per_at is not None:
        out[per_at:] = [(n, -e) for n, e in out[per_at:]]
    return [(n, e) for n, e in out if n]


def metro_unit(dsi: str) -> str:
    """The metro unit text of a D-SI unit string (the inverse of :func:`dsi_unit`): text that
    :func:`metro.core.base.units.unit` reads, as metro prints it (``\\degree\\hour\\tothe{-1}``
    → ``°/h``).  A leading ``|`` (not SI) is accepted; :class:`UnitError` for a token metro
    does not map or text that is not a D-SI unit."""
    text = dsi.strip()
    if text.startswith(NON_SI_MARK):
        text = text[1:].strip()
    if not text:
        raise UnitError(None, "D-SI unit", "the D-SI unit is empty; a value must state its unit")
    factors = _factors(text)
    celsius = [f for f in factors if f[0] == "degree_Celsius"]
    if celsius and (len(factors) > 1 or celsius[0][1] != 1):
        factors = [(_DELTA_C if n == "degree_Celsius" else n, e) for n, e in factors]
    result = ureg.Unit("")
    for name, exp in factors:
        result = result * ureg.Unit(name) ** (int(exp) if exp.is_integer() else exp)
    return fmt_unit(result) if factors else ""

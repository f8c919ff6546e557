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

import re
from importlib import resources
from pathlib import Path
from typing import Any, Iterable

import pint

from .errors import UnitError

__all__ = [
    "ureg", "Q_", "Quantity", "unit", "parse_quantity", "check_dimension", "add_definitions",
    "fmt_unit", "normalise_unit_text", "angle_power", "difference_unit",
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
    key = hashlib.sha256(f"{Path(pint.__file__).resolve().parent}|{pint.__version__}".encode()).hexdigest()[:16]
    return base / "pint" / key


def _make_registry() -> pint.UnitRegistry:
    kw: dict[str, Any] = {"autoconvert_offset_to_baseunit": True, "non_int_type": float}
    try:
        reg = pint.UnitRegistry(**kw, cache_folder=_cache_folder())
    except Exception as exc:  # noqa: BLE001 - a damaged or unwritable cache only costs time
        import warnings

        warnings.warn(f"pint's definitions cache could not be used ({exc!r}); parsing without it", stacklevel=2)
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


_SYMBOLS = [
    ("℃", " degC"),
    ("°C", " degC"),
    ("°/√h", " deg/hour**0.5"),
    ("√h", "hour**0.5"),
    ("√s", "second**0.5"),
    ("°", " deg"),
    ("″", " arcsec"),
    ("′", " arcmin"),
    ("²", "**2"),
    ("³", "**3"),
    ("·", "*"),
    ("×", "*"),
    ("−", "-"),
]

# Names (pint's canonical ones) of the units that measure a plane angle.  pint makes the
# radian dimensionless, so without this check "deg/h" and "Hz" (or "arcsec" and "ppm")
# would convert silently into each other.
_ANGLE_UNITS = frozenset(
    {"radian", "degree", "arcminute", "arcsecond", "milliradian", "microradian", "turn",
     "revolution", "gradian", "milliarcsecond", "microarcsecond"}
)


_G_AS_GRAVITY = re.compile(r"(?<![A-Za-z_])g(?![A-Za-z_0-9])")


def normalise_unit_text(text: str) -> str:
    """Rewrite the standards' typographic unit symbols into pint syntax.

    ``"(°)/h"`` -> ``"( deg)/h"``, ``"°/√h"`` -> ``"deg/hour**0.5"``, ``"P/″"`` -> ``"P/ arcsec"``.
    """
    out = text
    for sym, rep in _SYMBOLS:
        out = out.replace(sym, rep)
    return out.strip()


def angle_power(unit: Any) -> float:
    """Exponent of plane angle in ``unit`` (1 for deg/h, 0 for Hz, -1 for P/″)."""
    u = unit.units if isinstance(unit, pint.Quantity) else (unit if isinstance(unit, pint.Unit) else ureg.Unit(unit))
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


def unit(text: str) -> pint.Unit:
    """Parse a unit text (the standards' symbols allowed) into a registry unit."""
    return ureg.Unit(normalise_unit_text(text))


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
        try:
            q = ureg.Quantity(normalise_unit_text(value))
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
                f"the number {value!r} has no unit; write it with its unit, e.g. \"{value} {dimension}\"",
            )
        q = Q_(float(value), "")
    else:
        raise UnitError(file, field, f"expected a quantity such as \"1.5 {dimension or 'unit'}\", got {value!r}")
    if dimension is not None and isinstance(value, str) and _G_AS_GRAVITY.search(value):
        # The inertial-test field writes standard gravity as "g"; pint reads "g" as gram.
        # Where the expected quantity involves acceleration, read it as the field does.
        want = unit(dimension).dimensionality
        if q.dimensionality != want:
            alt = ureg.Quantity(normalise_unit_text(_G_AS_GRAVITY.sub("gn", value)))
            if alt.dimensionality == want:
                q = alt
    if dimension is not None:
        check_dimension(q, dimension, file=file, field=field)
    return q


def check_dimension(q: pint.Quantity, dimension: str, *, file: str | None = None, field: str | None = None) -> None:
    """Raise :class:`UnitError` unless ``q`` has the dimensionality of the unit ``dimension``."""
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
            f"(expected a quantity like {fmt_unit(want)}; metro never rescales between different kinds)",
        )


_PRETTY = [
    ("deg/h⁰⋅⁵", "°/√h"),
    ("h⁰⋅⁵", "√h"),
    ("s⁰⋅⁵", "√s"),
    ("arcsec", "″"),
    ("arcmin", "′"),
    ("delta_degC", "°C"),
    ("Δ°C", "°C"),
    ("degC", "°C"),
    ("deg", "°"),
    ("pulse", "P"),
    ("g_0", "g"),
    ("hr", "h"),
]


def is_voltage_ratio(u: Any) -> bool:
    """True for a ratiometric output's unit, a voltage over a voltage (``mV/V``, ``V/V``): pint
    reduces it to a plain number (``V/V`` to nothing at all), so it is told by its written form."""
    text = re.sub(r"\s+", "", str(u)).replace("volt", "V").replace("milli", "m").replace("micro", "µ")
    return re.fullmatch(r"[mµuk]?V/V", text) is not None


def fmt_unit(u: Any) -> str:
    """Short, readable unit text as the standards print it (``°/h``, ``″``, ``P/″``)."""
    if isinstance(u, pint.Quantity):
        u = u.units
    if not isinstance(u, pint.Unit):
        u = unit(str(u))
    text = f"{u:~P}"
    for a, b in _PRETTY:
        text = text.replace(a, b)
    return text or "1"

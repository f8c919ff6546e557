"""Options given as text — on the command line, in a bench file — checked and converted.

Stations and items declare what they take; a name they do not take, or a value that is not of
the declared form, is a :class:`~metro.core.base.errors.DataError` naming the option and showing its
form, never an option dropped without a word or a ``TypeError`` inside a simulation.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

from .errors import DataError


def check_options(owner: str, given: Iterable[str], accepted: Iterable[str], *,
                  kind: str = "station option") -> None:
    """Refuse option names that ``owner`` does not take.

    A misspelt option (``table_error=false`` for ``table_errors``) would otherwise be dropped
    without a word and the run would go ahead on defaults; the error names the option and lists
    the ones ``owner`` takes."""
    accepted = sorted(set(accepted))
    unknown = sorted(set(given) - set(accepted))
    if unknown:
        raise DataError(None, f"{kind} {unknown[0]}",
                        f"{owner} does not take {', '.join(unknown)}",
                        hint=f"{owner} takes: {', '.join(accepted)}")


def convert_options(owner: str, cls: type, options: Mapping[str, Any], *,
                    kind: str = "station option") -> dict[str, Any]:
    """The ``options`` that name fields of the attrs class ``cls``, each converted to the type of
    the field's default — from the command line every value comes as text.

    ``float``/``int`` fields take a (finite) number, ``bool`` fields true/false (1/0, yes/no,
    on/off), tuples of numbers as many comma-separated numbers as the default has; a nested tuple
    (a matrix) is set from Python.  A value that does not convert is a :class:`DataError` naming
    the option, not a ``TypeError`` deep inside a simulation.  Options that are not fields are
    left out (check them with :func:`check_options`)."""
    import attrs

    fields = attrs.fields_dict(cls)
    out: dict[str, Any] = {}
    for name, value in options.items():
        if name not in fields:
            continue
        default = fields[name].default
        if isinstance(default, attrs.Factory):  # type: ignore[arg-type]
            default = default.factory()
        out[name] = convert_value(owner, f"{kind} {name}", value, default)
    return out


def convert_value(owner: str, field: str, value: Any, default: Any) -> Any:
    """``value`` converted to the type of ``default`` (see :func:`convert_options`); ``field`` names
    it in errors."""
    def bad(what: str) -> DataError:
        example = (
            ",".join(f"{x:g}" for x in default)
            if isinstance(default, tuple)
            else str(default).lower()
        )
        return DataError(None, field, f"{value!r} is not {what}",
                         hint=f"{owner} takes it in the form of its default, "
                         f"{field.split()[-1]}={example}")

    if isinstance(default, bool):
        if isinstance(value, bool):
            return value
        text = str(value).strip().lower()
        if text in ("1", "true", "yes", "on"):
            return True
        if text in ("0", "false", "no", "off"):
            return False
        raise bad("true or false")
    if isinstance(default, (int, float)):  # bool was handled above
        whole = isinstance(default, int)
        what = "a whole number" if whole else "a number"
        if isinstance(value, bool):
            raise bad(what)
        try:
            f = float(value)
        except (TypeError, ValueError):
            raise bad(what) from None
        if not math.isfinite(f):
            raise bad(what if whole else "a finite number")
        if not whole:
            return f
        if f != int(f):
            raise bad(what)
        return int(f)
    if isinstance(default, tuple):
        if isinstance(value, (tuple, list)):
            return tuple(value)
        if any(isinstance(x, (tuple, list)) for x in default):
            raise DataError(None, field,
                            "a matrix is set from Python (a station factory argument), not as text")
        parts = [p for p in str(value).replace(";", ",").split(",") if p.strip()]
        try:
            nums = tuple(float(p) for p in parts)
        except ValueError:
            raise bad(f"{len(default)} comma-separated numbers") from None
        if len(nums) != len(default) or not all(math.isfinite(x) for x in nums):
            raise bad(f"{len(default)} comma-separated numbers")
        return nums
    if isinstance(default, str):
        return str(value)
    return value


def station_options(owner: str, truth_cls: type, station_cls: type, options: Mapping[str, Any],
                    station_fields: Iterable[str]) -> tuple[dict[str, Any], dict[str, Any]]:
    """``(truth keyword arguments, station keyword arguments)`` of a simulated station's factory:
    ``options`` may name any field of ``truth_cls`` and the ``station_fields`` of ``station_cls``
    (anything else is refused), each converted to its field's type."""
    import attrs

    station_fields = tuple(station_fields)
    check_options(owner, options, [*attrs.fields_dict(truth_cls), *station_fields])
    truth = convert_options(owner, truth_cls, options)
    station = convert_options(owner, station_cls,
                              {k: v for k, v in options.items() if k in station_fields})
    for name, value in (*truth.items(), *station.items()):
        check_range(owner, f"station option {name}", name, value)
    validate_fields(owner, truth_cls, truth)
    return truth, station


#: physical or practical ranges of option values a station takes, by option name:
#: (lowest, highest, lowest excluded).  duration_scale multiplies every step's duration: 0 or
#: less records nothing, and beyond 100 an hour's step becomes days of samples in memory.
RANGES: dict[str, tuple[float, float, bool]] = {
    "duration_scale": (0.0, 100.0, True),
    "latitude_deg": (-90.0, 90.0, False),
    "seed": (0.0, 2.0**63 - 1, False),
}


def check_range(owner: str, field: str, name: str, value: Any) -> None:
    """Refuse a number outside :data:`RANGES` for ``name`` (a :class:`DataError` naming it)."""
    if name not in RANGES or isinstance(value, bool) or not isinstance(value, (int, float)):
        return
    lo, hi, open_lo = RANGES[name]
    if not math.isfinite(value) or value > hi or value < lo or (open_lo and value == lo):
        raise DataError(None, field, f"{value!r} is out of range: {owner} takes "
                        f"{lo:.10g} {'<' if open_lo else '≤'} {name} ≤ {hi:.10g}")


def validate_fields(owner: str, cls: type, values: Mapping[str, Any], *,
                    kind: str = "station option") -> None:
    """Build ``cls(**values)`` once to run its attrs validators; a value a validator refuses
    (``output=analog``, ``polarity=2``) is a :class:`DataError` naming the option and what it
    takes, not a ``ValueError`` traceback from inside a station factory."""
    try:
        cls(**values)
    except (ValueError, TypeError) as exc:
        import attrs

        args = exc.args
        att = next((a for a in args if isinstance(a, attrs.Attribute)), None)
        name = att.name if att is not None else next((k for k in values if k in str(exc)), None)
        allowed = args[2] if len(args) >= 4 and att is not None else None
        reason = (f"{values.get(name)!r} is not one of {', '.join(map(str, allowed))}" if allowed
                  is not None
                  else str(args[0]) if args else str(exc))
        raise DataError(None, f"{kind} {name}" if name else kind, f"{owner}: {reason}") from None

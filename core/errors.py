"""Errors metro raises on purpose.

Every error a user can cause names *where* (file, field) and *why*, and says what to do
next where that is known.  The CLI turns these into a one-paragraph message and exit code 2;
anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any


class MetroError(Exception):
    """Base class of the errors metro reports to the user (exit code 2)."""

    def __init__(self, reason: str, *, hint: str | None = None) -> None:
        super().__init__(reason)
        self.reason = reason
        self.hint = hint

    def __str__(self) -> str:  # pragma: no cover - trivial
        text = self.reason
        if self.hint:
            text += f"\n  -> {self.hint}"
        return text


class DataError(MetroError):
    """Bad input data: names the file, the field (column, key, row) and the reason."""

    def __init__(
        self,
        file: str | None,
        field: str | None,
        reason: str,
        *,
        hint: str | None = None,
    ) -> None:
        self.file = str(file) if file is not None else None
        self.field = field
        where = []
        if self.file:
            where.append(self.file)
        if field:
            where.append(f"field '{field}'")
        prefix = ": ".join([", ".join(where)]) if where else "input"
        super().__init__(f"{prefix}: {reason}", hint=hint)
        self.detail = reason


class UnitError(DataError):
    """A quantity has the wrong dimension or a unit metro cannot parse."""


class PluginError(MetroError):
    """A plugin failed to load or registered something invalid (e.g. a duplicate item id)."""


class ProcedureError(MetroError):
    """A procedure cannot produce a result from the data it was given (e.g. a fit failed)."""


class DriverError(DataError):
    """A live instrument failed: names the resource (VISA address, serial port), what was being
    done (the command, the frame and its byte position) and why — a dropped connection, a
    malformed reply, an instrument error."""


def check_options(owner: str, given: Iterable[str], accepted: Iterable[str], *, kind: str = "station option") -> None:
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


def convert_options(owner: str, cls: type, options: Mapping[str, Any], *, kind: str = "station option") -> dict[str, Any]:
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
    """``value`` converted to the type of ``default`` (see :func:`convert_options`); ``field`` names it in errors."""
    def bad(what: str) -> DataError:
        example = ",".join(f"{x:g}" for x in default) if isinstance(default, tuple) else str(default).lower()
        return DataError(None, field, f"{value!r} is not {what}",
                         hint=f"{owner} takes it in the form of its default, {field.split()[-1]}={example}")

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
            raise DataError(None, field, "a matrix is set from Python (a station factory argument), not as text")
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

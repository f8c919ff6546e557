"""Errors metro raises on purpose.

Every error a user can cause names *where* (file, field) and *why*, and says what to do
next where that is known.  The CLI turns these into a one-paragraph message and exit code 2;
anything else is a bug and keeps its traceback.
"""

from __future__ import annotations

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


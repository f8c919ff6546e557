"""A validation case: one computation metro or a plugin ships with its reference value.

A case names its source (the standard's worked example, the NIST data set, the JCGM 101 clause),
gives the reference values as published and the tolerance they are compared at, and computes its
own values when it is run.  :meth:`ValidationCase.run` returns the case again with what it
computed and its verdict: ``pass`` when every value agrees with its reference within the
tolerance, ``fail`` when one does not, ``error`` when the computation raised.

Values are numbers or text.  Text (a value as the standard prints it, ``"0.00043"``) is compared
exactly; numbers agree when ``|computed − reference| ≤ atol + rtol·|reference|``.
"""

from __future__ import annotations

import math
import time
from typing import Any, Callable, Sequence

import attrs

__all__ = ["VERDICTS", "Figures", "ValidationCase", "agrees", "tolerance_text"]

#: a case's verdicts, in the order a summary gives them
VERDICTS = ("pass", "fail", "error")

#: a value a case computes or is compared with: a number, or text compared exactly
Value = float | str


def _values(v: Any) -> tuple[Value, ...]:
    if isinstance(v, (str, int, float)):
        v = (v,)
    return tuple(x if isinstance(x, str) else float(x) for x in v)


def agrees(computed: Value, reference: Value, rtol: float, atol: float) -> bool:
    """Whether ``computed`` agrees with ``reference``: text exactly, numbers within
    ``atol + rtol·|reference|`` (a NaN never agrees)."""
    if isinstance(reference, str) or isinstance(computed, str):
        return str(computed) == str(reference)
    if not (math.isfinite(computed) and math.isfinite(reference)):
        return computed == reference
    return abs(computed - reference) <= atol + rtol * abs(reference)


def tolerance_text(rtol: float, atol: float, text_only: bool = False) -> str:
    """The tolerance as the report prints it: ``exact (as printed)``, ``1e-12 relative``, …"""
    if text_only or (rtol == 0 and atol == 0):
        return "exact (as printed)"
    parts = []
    if rtol:
        parts.append(f"{rtol:.0e} relative".replace("e-0", "e-"))
    if atol:
        parts.append(f"{atol:g} absolute")
    return " + ".join(parts)


@attrs.frozen
class Figures:
    """What a case's computation returns when the published values come with it (a module that
    computes a published example and holds its figures): the computed values, the references,
    their absolute tolerances and labels, in one order."""

    #: the values computed
    computed: tuple[Value, ...] = attrs.field(converter=_values)
    #: the published values they are compared with
    reference: tuple[Value, ...] = attrs.field(converter=_values)
    #: the absolute tolerance of each value
    atol: tuple[float, ...] = attrs.field(converter=tuple)
    #: the name of each value
    labels: tuple[str, ...] = attrs.field(converter=tuple)


@attrs.frozen
class ValidationCase:
    """One validation case (ISO/IEC 17025 §7.11.2): what is computed, against which published
    values, from which source, at which tolerance; and, once run, the computed values and the
    verdict.

    Make a case with ``compute`` (a function of no argument returning the values, in the order
    of ``reference``); :meth:`run` gives a copy with ``computed``, ``verdict``, ``detail`` and
    ``seconds`` filled in.  Cases a plugin returns from the ``metro_validation_cases`` hook are
    run and reported like metro's own.
    """

    #: a short unique id, ``<group>:<name>`` (e.g. ``"nist:norris"``, ``"jjf2003:A.1"``)
    id: str
    #: what is validated, in a line
    title: str
    #: the published source of the reference values (document, clause, table)
    source: str
    #: the reference values, as published (empty when the computation returns them with its
    #: values, as :class:`Figures`)
    reference: tuple[Value, ...] = attrs.field(converter=_values)
    #: computes the values compared with ``reference`` (same length and order)
    compute: Callable[[], "Sequence[Value] | Value | Figures"] = attrs.field(eq=False, repr=False)
    #: relative tolerance of numbers
    rtol: float = 0.0
    #: absolute tolerance of numbers: one for every value, or one per value
    atol: float | tuple[float, ...] = attrs.field(
        default=0.0, converter=lambda a: a if isinstance(a, (int, float)) else tuple(a))
    #: the names of the values (one per reference value), for the report
    labels: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: the unit the values are in ("" for numbers without one)
    unit: str = ""
    #: run by ``metro validate --quick`` too (False for the longer statistical runs)
    quick: bool = True
    #: the plugin that contributed the case (filled in when the cases are collected)
    plugin: str = ""
    #: filled in by :meth:`run`: what was computed
    computed: tuple[Value, ...] | None = None
    #: filled in by :meth:`run`: ``pass``, ``fail`` or ``error`` (None before the case ran)
    verdict: str | None = None
    #: filled in by :meth:`run`: why a case failed or raised
    detail: str = ""
    #: filled in by :meth:`run`: how long the computation took
    seconds: float = 0.0

    @property
    def tolerance(self) -> str:
        """The tolerance as text (:func:`tolerance_text`)."""
        text_only = all(isinstance(r, str) for r in self.reference)
        if isinstance(self.atol, tuple):
            return "±(" + ", ".join(f"{a:.3g}" for a in self.atol) + ") absolute, per value"
        return tolerance_text(self.rtol, self.atol, text_only)

    def atol_of(self, i: int) -> float:
        """The absolute tolerance of value ``i``."""
        return self.atol[i] if isinstance(self.atol, tuple) else self.atol

    @property
    def passed(self) -> bool:
        """Whether the case ran and passed."""
        return self.verdict == "pass"

    def run(self) -> "ValidationCase":
        """Compute the values and judge them: a copy of the case with ``computed``, ``verdict``,
        ``detail`` and ``seconds``.  An exception in the computation is the verdict ``error``
        (its type and message in ``detail``), never raised."""
        t0 = time.perf_counter()
        case = self
        try:
            got = self.compute()
            if isinstance(got, Figures):  # the references come with the computation
                case = attrs.evolve(self, reference=got.reference, atol=got.atol,
                                    labels=got.labels)
                got = got.computed
            got = _values(got)
        except Exception as exc:  # noqa: BLE001 - a case that raises is reported, not hidden
            return attrs.evolve(self, computed=(), verdict="error",
                                detail=f"{type(exc).__name__}: {exc}"[:300],
                                seconds=time.perf_counter() - t0)
        return case.judge(got, time.perf_counter() - t0)

    def judge(self, got: tuple[Value, ...], seconds: float = 0.0) -> "ValidationCase":
        """The case with ``got`` as its computed values and the verdict on them."""
        if len(got) != len(self.reference):
            return attrs.evolve(self, computed=got, verdict="error", seconds=seconds,
                                detail=f"computed {len(got)} values for {len(self.reference)} "
                                "reference values")
        bad = [i for i, (c, r) in enumerate(zip(got, self.reference))
               if not agrees(c, r, self.rtol, self.atol_of(i))]
        detail = "; ".join(f"{self.label(i)}: {got[i]!r} ≠ {self.reference[i]!r}" for i in bad)
        return attrs.evolve(self, computed=got, verdict="fail" if bad else "pass",
                            detail=detail, seconds=seconds)

    def label(self, i: int) -> str:
        """The name of value ``i`` (its label, else its position)."""
        return self.labels[i] if i < len(self.labels) else f"value {i + 1}"

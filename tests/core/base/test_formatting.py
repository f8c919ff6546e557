"""metro.core.base.formatting: one notation for numbers and units, below every layer that prints
(budgets, conformity, documents, the terminal), and the documents package without cycles."""

from __future__ import annotations

import ast
import doctest
import importlib
from pathlib import Path

import pytest

from metro.core.base.formatting import (
    DASH, fmt_divisor, fmt_dof, fmt_num, fmt_quantity, or_dash, power_of_ten, pretty_powers,
    unit_text, with_unit,
)
from metro.core.base.units import Q_

CORE = Path(__file__).resolve().parents[3] / "core"


@pytest.mark.parametrize("module", [
    "metro.core.base.formatting", "metro.core.documents.text", "metro.core.documents.context",
    "metro.core.documents.document", "metro.core.documents.notes",
])
def test_the_examples_in_the_docstrings_hold(module):
    result = doctest.testmod(importlib.import_module(module))
    assert result.attempted > 0 and result.failed == 0


def test_numbers_print_as_a_certificate_prints_them():
    assert power_of_ten("1.4", -6) == "1.4×10⁻⁶"
    assert fmt_num(0.000012345) == "1.234×10⁻⁵" and fmt_num(123456.0) == "1.235×10⁵"
    assert fmt_num(-2.5e-9, 2) == "-2.5×10⁻⁹"
    assert (fmt_num(None), fmt_num(float("nan")), fmt_num(float("-inf")), fmt_num(7)) == \
        (DASH, "NaN", "-∞", "7")
    assert pretty_powers("±5e-06 and 1e+03; run-1e-5.csv") == "±5×10⁻⁶ and 1×10³; run-1e-5.csv"
    assert [fmt_dof(d) for d in (None, 6.0, 34.27, 3308.4, 21776473.0)] == \
        ["∞", "6", "34.3", "3308", "2.2×10⁷"]
    assert (fmt_divisor(2 ** 0.5), fmt_divisor(6 ** 0.5), fmt_divisor(2.0)) == ("√2", "√6", "2")


def test_one_rule_for_a_missing_or_dimensionless_unit():
    """with_unit is the one merge of the report's with_unit and the layouts' with_unit_text: no
    unit printed for an empty one, ``1`` or a dash."""
    assert with_unit("0.5", "°/h") == "0.5 °/h"
    assert [with_unit("3", u) for u in ("", "1", DASH)] == ["3", "3", "3"]
    assert unit_text("deg/h") == "°/h" and unit_text("dimensionless") == ""
    assert fmt_quantity(Q_(45.0, "percent")) == "45 %"
    assert fmt_quantity(Q_(2.0, "dimensionless")) == "2"
    assert (or_dash("  x "), or_dash(""), or_dash(None)) == ("x", DASH, DASH)


def _imports(path: Path) -> set[str]:
    """Every module ``path`` imports, at module level or inside a function, as absolute names."""
    package = "metro.core." + ".".join(path.relative_to(CORE).parent.parts)
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.ImportFrom):
            parts = package.split(".")
            base = parts[: len(parts) - node.level + 1] if node.level else []
            mod = ".".join(base + ([node.module] if node.module else []))
            out.add(mod)
            out.update(f"{mod}.{a.name}" for a in node.names)
        elif isinstance(node, ast.Import):
            out.update(a.name for a in node.names)
    return out


def test_budgets_and_verdicts_format_without_the_documents_layer():
    for path in sorted((CORE / "uncertainty").glob("*.py")):
        assert not [m for m in _imports(path) if m.startswith("metro.core.documents")], path.name


def test_the_context_is_below_the_document_and_the_document_below_the_writer():
    docs = CORE / "documents"
    assert not [m for m in _imports(docs / "context.py")
                if m.startswith(("metro.core.documents.document", "metro.core.documents.report",
                                 "metro.core.documents.builder"))]
    assert not [m for m in _imports(docs / "document.py")
                if m.startswith("metro.core.documents.report")]
    for low in ("text.py", "builder.py", "pdf.py"):
        assert not [m for m in _imports(docs / low)
                    if m.startswith(("metro.core.documents.document", "metro.core.documents.report",
                                     "metro.core.documents.context"))], low

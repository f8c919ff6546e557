"""Every unit metro prints reads back to the same unit (issue 30, point 4).

"The same unit" is the same dimension, the same power of plane angle (pint makes the radian
dimensionless) and the same scale: one of the printed unit, converted to the declared one, is 1
within 1e-12.  A temperature compares by its difference unit: metro prints a difference of °C
as °C (docs/interpretations.md).

The printing paths: ``fmt_unit`` (the terminal's tables and the documents' notes), the
documents' unit text and ``with_unit`` (a value with its unit), the ``--json`` document
(``Result.as_dict``, ``UncertaintyBudget.as_dict``, a quantity as ``{"value", "unit"}``) and the
lot CSV (``batch.result_rows`` written by ``csv``).  Text that is not a unit, or is ambiguous,
is a :class:`UnitError` naming it, never a silent simplification: before this,
``unit("deg/h⁰⋅⁵")`` read ``deg`` and ``unit("deg/h¹⋅⁵")`` read ``deg/h``.
"""

from __future__ import annotations

import csv
import io
import math

import pint
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from metro.core.base.errors import DataError, UnitError
from metro.core.base.formatting import unit_text, with_unit
from metro.core.base.units import (Q_, angle_power, difference_unit, fmt_unit, parse_quantity, unit,
                                   ureg)
from metro.core.model.record_json import json_value
from metro.core.model.results import Metric, Result
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.uncertainty.budget import BudgetRow, UncertaintyBudget


def _same_unit(got: pint.Unit, want: pint.Unit) -> bool:
    """Same dimension, same power of plane angle, and 1 ``got`` = 1 ``want`` within 1e-12."""
    if got.dimensionality != want.dimensionality or angle_power(got) != angle_power(want):
        return False
    one = Q_(1.0, difference_unit(got)).to(difference_unit(want)).magnitude
    return math.isclose(one, 1.0, rel_tol=1e-12, abs_tol=0.0)


def _csv_units(docs: list[dict]) -> list[str]:
    """The ``unit`` column of lot-results.csv for results given as ``--json`` result dicts."""
    from metro.core.cli.batch import RESULT_COLUMNS, result_rows

    outcome = {
        "status": "evaluated",
        "name": "dev",
        "campaign": "c.toml",
        "doc": {
            "device": {"id": "D1", "serial": "S1", "model": "M"},
            "report_number": "R1",
            "results": docs,
            "conformity": None,
        },
    }
    buf = io.StringIO()
    w = csv.DictWriter(buf, fieldnames=list(RESULT_COLUMNS))
    w.writeheader()
    w.writerows(result_rows([outcome]))
    return [row["unit"] for row in csv.DictReader(io.StringIO(buf.getvalue()))]


def _declared_units() -> dict[str, set[str]]:
    """Every unit a registered item declares (its metrics', its options'), and who declares it."""
    pm = get_plugin_manager()
    out: dict[str, set[str]] = {}
    for pid, info in pm.registry.procedures.items():
        for m in info.cls.metrics:
            out.setdefault(m.unit, set()).add(f"{pid} {m.key}")
        for o in getattr(info.cls, "options", ()) or ():
            if getattr(o, "unit", None):
                out.setdefault(o.unit, set()).add(f"{pid} -o {o.name}")
    return out


_DECLARED = _declared_units()


def _printed_texts(declared: str) -> dict[str, tuple[str, pint.Unit]]:
    """Every text metro prints for a result in ``declared``: path → (text, the unit meant)."""
    u = unit(declared)
    per_s = difference_unit(u) / ureg.s
    value = Q_(1.5, u)
    metric = Metric("x", "a quantity", "x", declared, "1")
    budget = UncertaintyBudget(
        "x",
        difference_unit(u),  # a budget of a temperature is in Δ°C
        [
            BudgetRow.type_b("a source", "x", Q_(0.1, difference_unit(u)), sensitivity=Q_(1.0, "")),
            BudgetRow.type_b("per second", "t", Q_(0.1, "s"), sensitivity=Q_(1.0, per_s)),
        ],
    )
    result_doc = Result(metric, value, budget=budget).as_dict()
    budget_doc = budget.as_dict()
    return {
        "fmt_unit (terminal, notes)": (fmt_unit(u), u),
        "document unit text": (unit_text(u), u),
        "json result": (result_doc["unit"], u),
        "json budget": (budget_doc["unit"], difference_unit(u)),
        "json budget row value": (budget_doc["rows"][0]["value_unit"], u),
        "json budget row sensitivity": (budget_doc["rows"][1]["sensitivity_unit"], per_s),
        "json quantity": (json_value(value)["unit"], u),
        "lot csv": (_csv_units([result_doc | {"item": "i"}])[0], u),
    }


@pytest.mark.parametrize("declared", sorted(_DECLARED), ids=lambda u: u or "dimensionless")
def test_every_declared_unit_reads_back_from_every_printing_path(declared):
    for path, (text, want) in _printed_texts(declared).items():
        got = unit(text)
        assert _same_unit(got, want), (
            f"{min(_DECLARED[declared])}: {want} printed by {path} as {text!r} reads as {got}"
        )


@pytest.mark.parametrize("declared", sorted(_DECLARED), ids=lambda u: u or "dimensionless")
def test_a_value_with_its_printed_unit_reads_back_as_the_same_quantity(declared):
    text = with_unit("1.5", unit_text(declared))
    q = parse_quantity(text)
    assert _same_unit(q.units, unit(declared)), f"{text!r} reads back as {q}"
    assert q.magnitude == 1.5


def test_the_registry_declares_the_units_the_issue_names():
    # the iteration above covers the cases it was written for
    for u in ("deg/hour**0.5", "deg/h/hour**0.5", "deg/s/gn", "gn", "g", "P/arcsec", "ppm"):
        assert u in _DECLARED, u


# -- (b) composed units with fractional exponents ------------------------------------------

_BASES = ("deg", "hour", "s", "Hz", "V", "gn", "ppm", "arcsec", "LSB", "pulse", "mV", "degC")
_EXPONENTS = (0.5, 1.5, -0.5, -1.5, 1, -1, 2, -2, 3, 2.5)


@settings(max_examples=400, deadline=None)
@given(
    st.lists(
        st.tuples(st.sampled_from(_BASES), st.sampled_from(_EXPONENTS)),
        min_size=1,
        max_size=4,
        unique_by=lambda t: t[0],
    )
)
def test_composed_units_with_fractional_exponents_read_back(factors):
    text = " * ".join(f"{name}**{exp}" for name, exp in factors)
    if "degC" in text and len(factors) > 1:  # an offset unit in a product is its difference
        text = text.replace("degC", "delta_degC")
    u = ureg.Unit(text)
    printed = fmt_unit(u)
    assert _same_unit(unit(printed), u), f"{text}: printed {printed!r}, read {unit(printed)}"
    assert fmt_unit(unit(printed)) == printed


# -- (c) the reported cases, and approx_quantity on °/√h -------------------------------------


@pytest.mark.parametrize(
    "text, pint_text",
    [
        ("deg/h⁰⋅⁵", "deg/hour**0.5"),
        ("deg/h¹⋅⁵", "deg/hour**1.5"),
        ("°/h¹⋅⁵", "deg/hour**1.5"),
        ("°/h¹·⁵", "deg/hour**1.5"),  # a middle dot as the decimal point
        ("°/h¹.⁵", "deg/hour**1.5"),
        ("°/h^1.5", "deg/hour**1.5"),
        ("°/√h", "deg/hour**0.5"),
        ("mV/√Hz", "mV/Hz**0.5"),
        ("1/√(Hz·s)", "1/(Hz*s)**0.5"),
        ("√h³", "hour**1.5"),
        ("h⁻⁰⋅⁵", "hour**-0.5"),
        ("°/h/g", "deg/h/gn"),  # g with other units: standard gravity
        ("s²·g/rad²", "s**2*gn/rad**2"),
        ("g", "gram"),  # alone: the gram
        ("gn", "gn"),
        ("gₙ", "gn"),
        ("g_0", "gn"),
        ("N⋅m", "N*m"),
        ("V×s", "V*s"),
        ("P/″", "pulse/arcsec"),
        ("P·s/″/°", "pulse*s/arcsec/deg"),
        ("LSB·s/°", "LSB*s/deg"),
        ("ppm/℃", "ppm/delta_degC"),
        ("Δ°C", "delta_degC"),
    ],
)
def test_the_reported_units_and_their_spellings(text, pint_text):
    assert _same_unit(unit(text), ureg.Unit(pint_text))


def test_approx_quantity_compares_angle_random_walks(approx_quantity):
    # °/√h: the unit text of the expected value reached check_dimension as "deg/h⁰⋅⁵" → deg
    assert approx_quantity(Q_(0.01, "deg/hour**0.5"), rel=1e-12) == Q_(0.6, "arcmin/hour**0.5")
    assert approx_quantity(Q_(2e-4, "deg/hour**1.5"), rel=1e-12) == Q_(0.72, "arcsec/hour**1.5")
    assert approx_quantity(Q_(0.01, "deg/hour**0.5"), rel=1e-3) != Q_(0.011, "deg/hour**0.5")
    with pytest.raises(UnitError):
        assert approx_quantity(Q_(0.01, "deg/hour**0.5")) == Q_(0.01, "deg/hour")


# -- (d) a [specification] limit written as metro prints it ----------------------------------


def test_a_limit_written_as_printed_judges_its_metric():
    from metro.core.uncertainty.conformity import Status, decide, specifications_from_table

    rrw, arw = fmt_unit("deg/h/hour**0.5"), fmt_unit("deg/hour**0.5")
    assert (rrw, arw) == ("°/h¹⋅⁵", "°/√h")
    specs = {
        s.symbol: s
        for s in specifications_from_table({"RRW": f"<= 0.05 {rrw}", "ARW": f"<= 0.01 {arw}"})
    }
    v = decide(specs["RRW"], Q_(0.03, "deg/h/hour**0.5"), Q_(0.005, "deg/h/hour**0.5"))
    assert v.status is Status.PASS
    v = decide(
        specs["ARW"], Q_(0.9, "arcmin/hour**0.5"), Q_(0.06, "arcmin/hour**0.5")
    )  # 0.015 °/√h
    assert v.status is Status.FAIL
    v = decide(specs["ARW"], Q_(0.3, "arcmin/hour**0.5"), Q_(0.03, "arcmin/hour**0.5"))
    assert v.status is Status.PASS
    with pytest.raises(UnitError, match="different kinds"):  # a bias rate is not a rate ramp
        decide(specs["RRW"], Q_(0.03, "deg/h"), None)


def test_a_gravity_limit_written_as_printed_judges_its_metric():
    from metro.core.uncertainty.conformity import Status, decide, parse_limit

    assert fmt_unit("gn") == "gn" and fmt_unit("deg/s/gn") == "°/s/g"
    spec = parse_limit("B_ax", f"<= 0.002 {fmt_unit('gn')}")
    assert decide(spec, Q_(0.001, "gn"), Q_(1e-4, "gn")).status is Status.PASS
    spec = parse_limit("g_xx", f"<= 0.01 {fmt_unit('deg/s/gn')}")
    assert decide(spec, Q_(0.005, "deg/s/gn"), Q_(1e-4, "deg/s/gn")).status is Status.PASS


# -- (e) text that is not a unit, or is ambiguous ------------------------------------------


@pytest.mark.parametrize(
    "text, why",
    [
        ("deg//h", "operator"),
        ("deg/h/", "ends with"),
        ("deg@h", "unexpected character '@'"),
        ("deg $ h", "unexpected character"),
        ("deg⋅⋅", "ends with"),
        ("h¹⋅", "ends with"),
        ("deg/h·s", "ambiguous"),
        ("deg/h s", "ambiguous"),
        ("√", "√"),
        ("√2", "√"),
        ("()", "empty parentheses"),
        ("(deg", "unbalanced"),
        ("deg)", "unbalanced"),
        ("Δ", "not defined"),
        ("bananas", "not defined"),
        ("degree_of_freedom", "not defined"),
    ],
)
def test_text_that_is_not_a_unit_is_an_error_naming_it(text, why):
    with pytest.raises(UnitError, match=why) as exc:
        unit(text)
    assert repr(text) in str(exc.value)


def test_a_bad_unit_in_a_manifest_field_names_the_file_and_the_field():
    with pytest.raises(DataError) as exc:
        parse_quantity(
            "0.05 °/h//h", dimension="deg/h", file="campaign.toml", field="specification.B0"
        )
    assert str(exc.value).startswith(
        "campaign.toml, field 'specification.B0': cannot read the unit '0.05 °/h//h'"
    )
    from metro.core.uncertainty.conformity import parse_limit

    with pytest.raises(DataError) as exc:
        parse_limit("RRW", "<= 0.05 °/h¹⋅", file="campaign.toml")
    assert "campaign.toml, field 'specification.RRW'" in str(exc.value)


def test_an_unreadable_unit_is_also_a_value_error_for_callers_that_catch_pint_errors():
    with pytest.raises(ValueError):
        unit("deg@h")
    with pytest.raises(pint.errors.UndefinedUnitError) as exc:  # as pint raised it before
        unit("deg/wibble")
    assert isinstance(exc.value, UnitError) and exc.value.unit_names == ("wibble",)


@pytest.mark.parametrize(
    "text, value, pint_unit",
    [
        ("0.05 °/h/°C", 0.05, "deg/h/delta_degC"),  # pint read the whole text as one expression:
        ("3 ppm/℃", 3.0, "ppm/delta_degC"),  # 1 °C became 274.15 K, the value 274× too small
        ("1.5 1/°C", 1.5, "1/delta_degC"),
        ("20 °C", 20.0, "degC"),
        ("1×10⁻⁶ °/h", 1e-6, "deg/h"),
        ("-2.5×10^3 s", -2500.0, "s"),
        ("2×10⁻³ °/h¹⋅⁵", 2e-3, "deg/hour**1.5"),
        ("-1.5e-3 °/h/g", -1.5e-3, "deg/h/gn"),
    ],
)
def test_a_value_is_read_apart_from_its_unit(text, value, pint_unit):
    q = parse_quantity(text)
    assert q.magnitude == pytest.approx(value, rel=1e-15)
    assert q.units == ureg.Unit(pint_unit)


@settings(max_examples=300, deadline=None)
@given(
    st.one_of(
        st.integers(min_value=-(10**9), max_value=10**9),
        st.floats(allow_nan=False, allow_infinity=False, width=64),
    ),
    st.sampled_from(("", ".6g", ".3e", ".12g")),
    st.sampled_from(("deg/h", "s", "ppm", "mV/(deg/s)", "")),
)
def test_a_number_reads_as_pint_read_it(x, spec, written_unit):
    # a value with an offset unit is read apart from its unit; every other must read the very
    # same number, of the same type, as pint's reading of the whole text did
    number = f"{x}" if isinstance(x, int) and spec else f"{x:{spec}}"
    text = f"{number} {written_unit}".strip()
    q = parse_quantity(text)
    before = ureg.Quantity(text)
    before_m = before.magnitude if isinstance(before, pint.Quantity) else float(before)
    assert q.magnitude == before_m and type(q.magnitude) is type(before_m)


def test_a_header_unit_that_is_not_a_unit_names_the_file_and_the_column():
    import numpy as np
    from metro.core.model.campaign import Segment

    def segment(column):
        """A segment of run1.csv whose ``output`` column reads ``column`` (values, header unit)."""
        return Segment("s", "static", {}, Q_(1, "s"), file="run1.csv", sha256="0" * 64,
                       loader=lambda: {"output": column})

    seg = segment((np.zeros(4), "°/h¹⋅"))
    with pytest.raises(DataError) as exc:
        seg.series("output", "deg/h")
    text = str(exc.value)
    assert text.startswith("run1.csv, field 'output': cannot read unit '°/h¹⋅' in the header")
    assert "input:" not in text and "ends with the operator" in text
    ok = segment((np.ones(4), "°/h¹⋅⁵"))
    assert ok.series("output", "deg/hour**1.5").data.units == ureg.Unit("deg/hour**1.5")


def test_a_gram_with_other_units_prints_gram_and_check_dimension_takes_a_unit():
    from metro.core.base.units import check_dimension

    per_s = ureg.Unit("gram/s")
    assert fmt_unit(per_s) == "gram/s" and unit("gram/s") == per_s
    assert unit("g/s") == ureg.Unit("gn/s")  # a bare g with other units: standard gravity
    check_dimension(Q_(2.0, per_s), per_s)  # a registry unit, not its pint text "g/s"
    with pytest.raises(UnitError):
        check_dimension(Q_(2.0, per_s), str(per_s))


def test_a_metric_unit_pint_would_read_otherwise_is_refused():
    """Results are built with pint, which reads "°/√h" as °/h without a word: a Metric declared
    with it is refused, naming the text; pint syntax and plain ASCII units are taken as before."""
    from metro.core.base.errors import UnitError
    from metro.core.model.results import Metric

    with pytest.raises(UnitError, match="pint reads it as °/h"):
        Metric("N", "angle random walk", "N", "°/√h", "D.5.6")
    assert Metric("N", "angle random walk", "N", "deg/hour**0.5", "D.5.6").unit == "deg/hour**0.5"
    assert Metric("B", "bias", "B", "°/h", "D.5.1").unit == "°/h"

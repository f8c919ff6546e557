"""Uncertainty budgets: GUM/JJF 1059.1 combination, Welch–Satterthwaite, k, rounding."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from metro.core.budget import (
    BudgetRow,
    Coverage,
    UncertaintyBudget,
    report_pair,
    round_to,
    round_uncertainty,
)
from metro.core.model import Calibration
from metro.core.units import Q_


def test_jjf2014_appendix_b1_scale_factor_budget():
    """JJF 2014—2022 appendix B.1: rate table 1e-4 (k=2), DMM 6e-5 (k=2), repeatability
    1.54e-4 → u_c = 1.65e-4 (as printed, 3 digits), U_rel = 3.3e-4 (k = 2)."""
    rows = [
        BudgetRow.type_b("rate table", "u1r", Q_(1e-4, ""), distribution="normal", k=2),
        BudgetRow.type_b("6½-digit DMM", "u2r", Q_(6e-5, ""), distribution="normal", k=2),
        BudgetRow.type_a("repeatability", "u3r", Q_(1.54e-4, ""), dof=math.inf),
    ]
    b = UncertaintyBudget("K", "", rows, coverage=Coverage.fixed(2), relative=True)
    assert f"{b.combined.magnitude:.2e}" == "1.65e-04"
    assert b.expanded_reported().text == "0.00033"
    assert b.k == 2


def test_jjf2014_appendix_b2_bias_budget_combined():
    """JJF 2014—2022 B.2: DMM 3e-5 and scale factor 1.65e-4 → u_c = 1.68e-4 (printed)."""
    rows = [
        BudgetRow.type_b("DMM", "u1r", Q_(6e-5, ""), distribution="normal", k=2),
        BudgetRow.type_a("scale factor", "u2r", Q_(1.65e-4, ""), dof=math.inf),
    ]
    b = UncertaintyBudget("B0", "", rows)
    assert f"{b.combined.magnitude:.2e}" == "1.68e-04"


def test_distributions_and_sensitivity_units():
    r = BudgetRow.type_b("levelling", "δ", Q_(2.0, "arcsec"), distribution="uniform",
                         sensitivity=Q_(11.5, "deg/h/rad"))
    u_rad = Q_(2.0, "arcsec").to("rad").magnitude / math.sqrt(3)
    assert r.contribution.to("deg/h").magnitude == pytest.approx(11.5 * u_rad, rel=1e-12)
    b = UncertaintyBudget("B0", "deg/h", [r])
    assert b.combined.to("deg/h").magnitude == pytest.approx(11.5 * u_rad, rel=1e-12)


def test_row_in_wrong_unit_is_refused():
    r = BudgetRow.type_a("x", "x", Q_(1.0, "deg/s"), dof=10)
    with pytest.raises(ValueError, match="does not convert"):
        UncertaintyBudget("RWC", "deg/hour**0.5", [r])


def test_welch_satterthwaite_hand_worked():
    # u1 = 3 (ν=4), u2 = 4 (ν=∞): u_c = 5; ν_eff = 5⁴ / (3⁴/4) = 625/20.25
    rows = [BudgetRow.type_a("a", "a", Q_(3.0, "mV"), dof=4), BudgetRow.type_b("b", "b", Q_(8.0, "mV"),
                                                                               distribution="normal", k=2)]
    b = UncertaintyBudget("y", "mV", rows, coverage=Coverage.probability(0.9545))
    assert b.combined.magnitude == pytest.approx(5.0)
    assert b.nu_eff == pytest.approx(625 / 20.25)
    from scipy import stats

    assert b.k == pytest.approx(stats.t.ppf(0.97725, 625 / 20.25))


def test_calibration_row():
    cal = Calibration("C-1", Q_(0.5, "arcsec"), k=2)
    r = BudgetRow.from_calibration("table", "u", cal)
    assert r.standard_uncertainty.to("arcsec").magnitude == pytest.approx(0.25)
    assert "C-1" in r.note


@pytest.mark.parametrize(
    "U, mode, text",
    [
        (0.0003367, "half-even", "0.00034"),
        (4.24e-4, "up", "0.00043"),  # JJF 2003 appendix A rounds 4.24e-4 up to 4.3e-4
        (1.004e-2, "up", "0.011"),  # 2×5.02e-3 → 1.1e-2
        (0.0125, "half-even", "0.012"),  # GB/T 8170: 5 followed by nothing → even
        (0.0135, "half-even", "0.014"),
        (9.96, "half-even", "10"),
        (0.0995, "half-even", "0.10"),
    ],
)
def test_round_uncertainty(U, mode, text):
    assert round_uncertainty(U, mode=mode).text == text


def test_result_rounded_to_the_decimal_of_U():
    v, U = report_pair(12.34567, 0.0236)
    assert (v.text, U.text) == ("12.346", "0.024")


@given(st.floats(min_value=1e-12, max_value=1e12))
def test_rounded_U_keeps_two_significant_digits_and_is_close(U):
    r = round_uncertainty(U)
    digits = r.text.replace(".", "").replace("-", "").lstrip("0").split("×")[0]
    assert len(digits.rstrip("0") or "0") <= 2
    assert abs(r.value - U) <= 0.05 * U + 1e-300
    up = round_uncertainty(U, mode="up")
    assert up.value >= U * (1 - 1e-12)


def test_small_and_large_numbers_print_with_powers_of_ten():
    """Certificates print 1.4×10⁻⁶, not 1.4e-6; the value keeps the decimal place of its U."""
    v, U = report_pair(0.79999987, 1.43e-6)
    assert (v.text, U.text) == ("0.7999999", "1.4×10⁻⁶")
    v, U = report_pair(2.01484e-6, 3.5e-7)
    assert (v.text, U.text) == ("2.01×10⁻⁶", "3.5×10⁻⁷")
    assert round_uncertainty(1.25e7).text == "1.2×10⁷"


def test_round_to():
    assert round_to(2.5, 0).text == "2"
    assert round_to(3.5, 0).text == "4"


def test_empty_budget_refused():
    with pytest.raises(ValueError, match="no rows"):
        UncertaintyBudget("x", "mV", [])

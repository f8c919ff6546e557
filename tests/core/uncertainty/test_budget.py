"""Uncertainty budgets: GUM/JJF 1059.1 combination, Welch–Satterthwaite, k, rounding."""

from __future__ import annotations

import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from metro.core.uncertainty.budget import (BudgetRow, Coverage, UncertaintyBudget, report_pair,
                                           round_to, round_uncertainty)
from metro.core.model.campaign import Calibration
from metro.core.base.units import Q_


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
    rows = [BudgetRow.type_a("a", "a", Q_(3.0, "mV"), dof=4),
            BudgetRow.type_b("b", "b", Q_(8.0, "mV"), distribution="normal", k=2)]
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
    # never below U beyond the float artefact that rounding ignores (core.budget.ARTEFACT_DIGITS)
    assert up.value >= U * (1 - 5e-10)


@pytest.mark.parametrize("U, mode, text", [
    (0.1 + 0.2, "up", "0.30"),  # 0.30000000000000004: a binary artefact, not a third digit
    (3.0000000000000008e-05, "up", "0.000030"),
    (0.30000001, "up", "0.31"),  # a genuine digit beyond the kept ones still rounds up
    (4.2300000000000004e-4, "up", "0.00043"),
    (0.0125 + 1e-18, "half-even", "0.012"),  # a tie hidden behind an artefact stays a tie
])
def test_rounding_ignores_float_artefacts(U, mode, text):
    """Issue 13: rounding up turned 0.1+0.2 into 0.31 and 3.0000000000000008e-05 into 0.000031."""
    assert round_uncertainty(U, mode=mode).text == text


@given(st.integers(min_value=10, max_value=99), st.integers(min_value=-12, max_value=8))
def test_exact_two_digit_U_is_not_rounded_up_by_its_float_representation(m, e):
    """A U that is exactly two digits in decimal (m×10^e) stays m×10^e when rounded up, whatever
    the binary arithmetic that produced it left in its last bits."""
    U = float(m) * 10.0**e
    U = U * (1 + 3e-16)  # the kind of artefact a product or a sum leaves
    r = round_uncertainty(U, mode="up")
    assert r.value == pytest.approx(m * 10.0**e, rel=1e-12)


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


_rows = st.lists(
    st.tuples(st.floats(min_value=1e-9, max_value=1e6),
              st.one_of(st.none(), st.integers(min_value=1, max_value=500)),
              st.floats(min_value=0.01, max_value=100.0),
              st.sampled_from(["normal", "uniform", "triangular"])),
    min_size=1, max_size=8)


def _budget(rows, p=0.9545):
    built = []
    for i, (u, dof, c, dist) in enumerate(rows):
        if dof is None:
            built.append(BudgetRow.type_b(f"b{i}", f"b{i}", Q_(u, "mV"), distribution=dist,
                                          k=2.0 if dist == "normal" else None,
                                          sensitivity=Q_(c, "deg/s/mV")))
        else:
            built.append(BudgetRow.type_a(f"a{i}", f"a{i}", Q_(u * c, "deg/s"), dof=dof))
    return UncertaintyBudget("y", "deg/s", built, coverage=Coverage.probability(p))


@given(_rows)
def test_budget_invariants(rows):
    """Properties of any budget (JJF 1059.1 / GUM 5.1.2, G.4): u_c² = Σ(c_i·u_i)²; u_c is at least
    the largest contribution and at most their sum; ν_eff lies between the smallest type A ν and
    ∞, and is ∞ exactly when every row is type B; k ≥ the normal quantile and U = k·u_c; the
    reported U keeps two significant digits and is within 5 % of U."""
    b = _budget(rows)
    contrib = [r.contribution.to("deg/s").magnitude for r in b.rows]
    uc = b.combined.to("deg/s").magnitude
    assert uc == pytest.approx(math.sqrt(sum(x * x for x in contrib)), rel=1e-12)
    assert max(contrib) * (1 - 1e-12) <= uc <= sum(contrib) * (1 + 1e-12)
    dofs = [r.dof for r in b.rows if r.dof is not None and math.isfinite(r.dof)]
    nu = b.nu_eff
    if dofs:
        assert min(dofs) * (1 - 1e-9) <= nu
    else:
        assert nu is None or math.isinf(nu)
    assert b.k >= 2.0 - 1e-9
    assert b.expanded.to("deg/s").magnitude == pytest.approx(b.k * uc, rel=1e-12)
    rep = b.expanded_reported()
    assert abs(rep.value - b.expanded.magnitude) <= 0.05 * b.expanded.magnitude


@given(_rows, st.floats(min_value=1e-3, max_value=1e3))
def test_budget_scales_with_its_inputs(rows, s):
    """Scaling every input uncertainty by s scales u_c and U by s and leaves ν_eff and k alone."""
    a = _budget(rows)
    b = _budget([(u * s, dof, c, dist) for u, dof, c, dist in rows])
    assert b.combined.magnitude == pytest.approx(s * a.combined.magnitude, rel=1e-9)
    if a.nu_eff is not None and math.isfinite(a.nu_eff):
        assert b.nu_eff == pytest.approx(a.nu_eff, rel=1e-9)
    assert b.k == pytest.approx(a.k, rel=1e-9)


def test_sampling_of_a_standard_deviation_chi_square_bound():
    """metro.core.uncertainty.budget.std_sampling_u: (σ_upper − s)/2 with σ_upper =
    s·√(ν/χ²₀.₀₂₂₇₅(ν)); χ² lower points from the printed table (NIST/SEMATECH e-Handbook 1.3.6.7.4,
    3 digits): ν = 5 → 0.797, ν = 6 → 1.19; for large n it tends to the linear s/√(2(n − 1))."""
    import math

    from metro.core.uncertainty.budget import std_sampling_u, std_upper_limit

    assert std_upper_limit(1.0, 6) == pytest.approx(math.sqrt(5 / 0.797), rel=1e-3)
    assert std_upper_limit(2.0, 7) == pytest.approx(2 * math.sqrt(6 / 1.19), rel=2e-3)
    assert std_sampling_u(1.0, 6) == pytest.approx((math.sqrt(5 / 0.797) - 1) / 2, rel=2e-3)
    assert std_sampling_u(1.0, 2001) == pytest.approx(1 / math.sqrt(2 * 2000), rel=0.05)


def test_between_variance_is_the_posterior_mean_of_a_variance_component():
    """metro.core.uncertainty.budget.between_variance (interpretations.md, "σ_on — a variance
    component the data only bound"): E[τ − w | τ ≥ w] for τ = ν·s²/X, X ~ χ²(ν) (reference prior
    1/τ, Box & Tiao 1973 §5.2). Worked by hand for ν = 6 at s² = w = 1 (where the moment estimate s²
    − w is 0): c = 6, F₄(6) = 1 − 4e⁻³, F₆(6) = 1 − 8.5e⁻³, E[τ] = 6·F₄/(4·F₆) = 2.082623; checked
    against a direct quadrature of the truncated posterior, and the two limits."""
    from scipy import integrate

    from metro.core.uncertainty.budget import between_variance

    e3 = math.exp(-3.0)
    assert between_variance(1.0, 1.0, 6) == pytest.approx(
        6 * (1 - 4 * e3) / (4 * (1 - 8.5 * e3)) - 1, rel=1e-12
    )
    assert between_variance(1.0, 1.0, 6) == pytest.approx(1.0826230, rel=1e-6)

    def by_quadrature(s2, w, nu):
        dens = lambda t: t ** (-nu / 2 - 1) * math.exp(-nu * s2 / (2 * t))  # noqa: E731
        z = integrate.quad(dens, w, math.inf)[0]
        return integrate.quad(lambda t: t * dens(t), w, math.inf)[0] / z - w

    for s2, w, nu in ((0.3, 1.0, 6), (4.0, 1.0, 6), (2.0, 1.0, 9), (1.0, 3.0, 4)):
        assert between_variance(s2, w, nu) == pytest.approx(by_quadrature(s2, w, nu), rel=1e-6)
    assert between_variance(2.0e-6, 1.0e-6, 9) == pytest.approx(
        1e-6 * between_variance(2.0, 1.0, 9), rel=1e-12
    )
    # never 0 while the runs have noise: s² → 0 gives 2w/(ν − 2); no within-run part gives ν/(ν −
    # 2)·s²
    assert between_variance(0.0, 1.0, 6) == pytest.approx(0.5)
    assert between_variance(1e-9, 1.0, 6) == pytest.approx(0.5, rel=1e-6)
    assert between_variance(1.0, 0.0, 6) == pytest.approx(1.5)
    # resolved: close to the t-inflated moment estimate ν/(ν − 2)·s² − w
    assert between_variance(50.0, 1.0, 6) == pytest.approx(1.5 * 50 - 1, rel=1e-6)
    with pytest.raises(ValueError, match="at least 3 degrees of freedom"):
        between_variance(1.0, 1.0, 2)
    with pytest.raises(ValueError, match="non-negative"):
        between_variance(-1.0, 1.0, 6)

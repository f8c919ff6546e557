"""The worked examples of JCGM 101:2008 clause 9, computed with :mod:`.montecarlo`.

:func:`jcgm101_examples` runs them and returns, per published figure, the case's name, the
published value, the tolerance and the computed value: the reference tests use it, and so can
a software validation (each case passes when |computed − reference| ≤ tolerance).

The tolerance of a figure is built from the numerical tolerance δ of JCGM 101 clause 7.9.2 at
the number of significant digits the figure is published with (½ unit of its last digit; an
interval's endpoints take the δ of the u(y) published with them): the published figure is
rounded to that digit (error ≤ δ) and metro's adaptive procedure (clause 7.9) stops when its
figure is within δ of the limit at about 95 % (2·s ≤ δ): 2δ.  Where the published figure is
itself a Monte Carlo result (JCGM 101 ran the same procedure), its own numerical error adds a
third δ: 3δ.  A fixed seed makes every run the same.

Sources of the published figures: JCGM 101:2008 clause 9 (9.2.2 Table 2, 9.2.3 Table 3, 9.3
Table 6, 9.4.1 and 9.4.2, 9.5 Table 15), as quoted in docs/monte-carlo.md.
"""

from __future__ import annotations

import math

import attrs
import numpy as np

from .montecarlo import Input, first_order_u, numerical_tolerance, propagate

#: the seed of every clause-9 run (a fixed seed makes the computed figures reproducible)
SEED = 20080101


@attrs.frozen
class ExampleFigure:
    """One published figure of JCGM 101 clause 9 beside the one metro computes."""

    #: the case, e.g. ``"JCGM 101 9.3 mass calibration: u(δm) Monte Carlo"``
    case: str
    #: the published figure
    reference: float
    #: |computed − reference| allowed: 2δ, or 3δ against a published Monte Carlo figure (δ from
    #: the published digits, clause 7.9.2)
    tolerance: float
    #: metro's figure
    computed: float
    #: the unit of the three numbers
    unit: str = ""

    @property
    def passed(self) -> bool:
        """True when |computed − reference| ≤ tolerance."""
        return abs(self.computed - self.reference) <= self.tolerance


def _figure(case: str, reference: float, delta: float, computed: float, unit: str = "",
            *, monte_carlo: bool = True) -> ExampleFigure:
    """A figure; ``monte_carlo`` when the published figure is a Monte Carlo result (3δ), else an
    exact or first-order figure (2δ)."""
    return ExampleFigure(case, reference, (3.0 if monte_carlo else 2.0) * delta,
                         float(computed), unit)


def additive(distribution: str) -> list[ExampleFigure]:
    """JCGM 101 9.2.2 (four N(0, 1)) and 9.2.3 (four rectangular, σ = 1): Y = X₁ + X₂ + X₃ + X₄,
    u(y) = 2.00 and the 95 % interval ±3.92 (normal) or ±3.88 (rectangular).

    >>> [round(f.computed, 2) for f in additive("normal")]
    [2.0, -3.92, 3.92]
    """
    r = propagate([Input(distribution, 0.0, 1.0)] * 4, p=0.95, digits=3, rng=SEED)
    # the output PDF is symmetric: the shortest interval is the probabilistically symmetric one
    # (JCGM 101 5.3.4), whose endpoints a finite sample locates far better
    half = 3.92 if distribution == "normal" else 3.88
    d = numerical_tolerance(2.00, 3)
    name = f"JCGM 101 9.2 additive model, four {distribution} inputs"
    return [
        _figure(f"{name}: u(y)", 2.00, d, r.u, monte_carlo=False),
        _figure(f"{name}: 95 % interval, low", -half, d, r.symmetric[0]),
        _figure(f"{name}: 95 % interval, high", half, d, r.symmetric[1]),
    ]


def mass_inputs() -> list[Input]:
    """The inputs of JCGM 101 9.3.1 (mg and kg/m³): m_R,c − m_nom, δm_R,c, ρ_a, ρ_W, ρ_R."""
    return [
        Input("normal", 0.0, 0.050),
        Input("normal", 1.234, 0.020),
        Input("rectangular", 1.20, 0.10 / math.sqrt(3)),
        Input("rectangular", 8000.0, 1000.0 / math.sqrt(3)),
        Input("rectangular", 8000.0, 50.0 / math.sqrt(3)),
    ]


def mass_model(x: np.ndarray) -> np.ndarray:
    """JCGM 101 eq. (22): δm = (m_R,c + δm_R,c)(1 + (ρ_a − ρ_a0)(1/ρ_W − 1/ρ_R)) − m_nom, with
    m_nom = 100 000 mg, ρ_a0 = 1.2 kg/m³, written about m_nom so as to keep the digits.

    >>> float(mass_model(np.array([[0.0], [1.234], [1.2], [8000.0], [8000.0]]))[0])
    1.234
    """
    dm, dmr, rho_a, rho_w, rho_r = x
    m = 100_000.0 + dm + dmr
    return dm + dmr + m * (rho_a - 1.2) * (1.0 / rho_w - 1.0 / rho_r)


def mass() -> list[ExampleFigure]:
    """JCGM 101 9.3: GUM (first order) u(δm) = 0.0539 mg, Monte Carlo u(δm) = 0.0754 mg."""
    inputs = mass_inputs()
    r = propagate(inputs, mass_model, p=0.95, digits=3, rng=SEED)
    gum = first_order_u(inputs, mass_model)  # ∂δm/∂ρ_W, ∂δm/∂ρ_R vanish at ρ_a = ρ_a0
    name = "JCGM 101 9.3 mass calibration"
    return [
        _figure(f"{name}: δm Monte Carlo", 1.234, numerical_tolerance(0.0754, 3), r.y, "mg"),
        _figure(f"{name}: u(δm) GUM", 0.0539, numerical_tolerance(0.0539, 3), gum, "mg",
                monte_carlo=False),
        _figure(f"{name}: u(δm) Monte Carlo", 0.0754, numerical_tolerance(0.0754, 3), r.u, "mg"),
    ]


def comparison_loss(x1: float) -> list[ExampleFigure]:
    """JCGM 101 9.4: δY = X₁² + X₂², X_i ~ N(x_i, 0.005²), x₂ = 0, uncorrelated.  x₁ = 0: Monte
    Carlo δy = u(δy) = 50×10⁻⁶, shortest 95 % interval [0, 150]×10⁻⁶ (GUM: 0 ± 0); x₁ = 0.010:
    GUM u = 100×10⁻⁶, Monte Carlo u = 112×10⁻⁶."""
    u = 0.005
    r = propagate([Input("normal", x1, u), Input("normal", 0.0, u)],
                  lambda x: x[0] ** 2 + x[1] ** 2, p=0.95, digits=2 if x1 == 0 else 3, rng=SEED)
    name = f"JCGM 101 9.4 comparison loss, x₁ = {x1:g}"
    if x1 == 0:
        d = numerical_tolerance(50e-6, 2)
        return [
            _figure(f"{name}: δy Monte Carlo", 50e-6, d, r.y, monte_carlo=False),  # 2u²
            _figure(f"{name}: u(δy) Monte Carlo", 50e-6, d, r.u, monte_carlo=False),  # 2u²
            _figure(f"{name}: shortest 95 % interval, low", 0.0, d, r.shortest[0],
                    monte_carlo=False),
            _figure(f"{name}: shortest 95 % interval, high", 150e-6, d, r.shortest[1]),
        ]
    gum = first_order_u([Input("normal", x1, u), Input("normal", 0.0, u)],
                        lambda x: x[0] ** 2 + x[1] ** 2)  # c₁ = 2x₁, c₂ = 2x₂ = 0
    return [
        _figure(f"{name}: u(δy) GUM", 100e-6, numerical_tolerance(100e-6, 3), gum,
                monte_carlo=False),
        _figure(f"{name}: u(δy) Monte Carlo", 112e-6, numerical_tolerance(112e-6, 3), r.u),
    ]


def gauge_inputs() -> list[Input]:
    """The inputs of JCGM 101 9.5.2 (nm, °C, °C⁻¹): L_s − L_nom, D̄, d₁, d₂ (scaled and shifted
    t), α_s (rectangular), θ₀ (normal), Δ (arcsine), δα and δθ (rectangular with inexactly
    known limits)."""
    return [
        Input("t", 623.0, 25.0, dof=18),
        Input("t", 215.0, 5.8, dof=24),
        Input("t", 0.0, 3.9, dof=5),
        Input("t", 0.0, 6.7, dof=8),
        Input("rectangular", 11.5e-6, 2e-6 / math.sqrt(3)),
        Input("normal", -0.1, 0.2),
        Input("arcsine", 0.0, 0.5 / math.sqrt(2)),
        Input("ctrap", 0.0, 1e-6, d=0.1e-6),
        Input("ctrap", 0.0, 0.050, d=0.025),
    ]


def gauge_model(x: np.ndarray) -> np.ndarray:
    """JCGM 101 9.5.1: L = [L_s(1 + α_s(θ − δθ)) + D] / (1 + (α_s + δα)θ), θ = θ₀ + Δ,
    D = D̄ + d₁ + d₂; returned as L − L_nom (nm), L_nom = 50 mm, written so as to keep the digits.

    >>> x = np.array([[623.0], [215.0], [0], [0], [11.5e-6], [-0.1], [0], [0], [0]])
    >>> round(float(gauge_model(x)[0]), 2)
    838.0
    """
    dls, dbar, d1, d2, alpha_s, theta0, cyc, dalpha, dtheta = x
    l_s = 50e6 + dls
    theta = theta0 + cyc
    alpha = alpha_s + dalpha
    num = dls + l_s * alpha_s * (theta - dtheta) + dbar + d1 + d2 - 50e6 * alpha * theta
    return num / (1.0 + alpha * theta)


def gauge_block() -> list[ExampleFigure]:
    """JCGM 101 9.5: GUM 838 nm, u = 32 nm; Monte Carlo 838 nm, u = 36 nm, 99 % interval
    [745, 932] nm."""
    r = propagate(gauge_inputs(), gauge_model, p=0.99, digits=2, rng=SEED)
    d = numerical_tolerance(36.0, 2)
    name = "JCGM 101 9.5 gauge block"
    gum = first_order_u(gauge_inputs(), gauge_model)
    return [
        _figure(f"{name}: u(δL) GUM", 32.0, numerical_tolerance(32.0, 2), gum, "nm",
                monte_carlo=False),
        _figure(f"{name}: δL Monte Carlo", 838.0, d, r.y, "nm"),
        _figure(f"{name}: u(δL) Monte Carlo", 36.0, d, r.u, "nm"),
        _figure(f"{name}: 99 % interval, low", 745.0, d, r.shortest[0], "nm"),
        _figure(f"{name}: 99 % interval, high", 932.0, d, r.shortest[1], "nm"),
    ]


def jcgm101_examples() -> list[ExampleFigure]:
    """Every published figure of JCGM 101 clause 9 that metro reproduces, each as an
    :class:`ExampleFigure` (case, reference, tolerance, computed, unit; ``passed``): 9.2 (normal
    and rectangular inputs), 9.3, 9.4 (x₁ = 0 and x₁ = 0.010) and 9.5.  A validation case per
    figure; a fixed seed (:data:`SEED`), a few seconds in all."""
    return [
        *additive("normal"), *additive("rectangular"), *mass(),
        *comparison_loss(0.0), *comparison_loss(0.010), *gauge_block(),
    ]

"""JJF 2003—2022 formulas as pure functions on plain numbers (numpy arrays).

Units are whatever the caller passes consistently (the procedures use °/s for gyro
outputs, gn for accelerometer outputs and rad/s for ω in eq. (12)).  Least squares is
:func:`metro.core.stats.lsq.fit_linear`.
"""

from __future__ import annotations

import math
from decimal import Decimal
from typing import Sequence

import numpy as np
from metro.api import LinearFit, fit_linear, round_uncertainty


def rate_sensitivity_model(p: float, coefficients: Sequence[float], rate_row: int | None):
    """The measurement model of p = (U₈ − U₇)/ω² (eq. (12), (13)) for the Monte Carlo check of its
    budget (JCGM 101): ω enters squared in the denominator, which the budget's linear row
    c(ω) = −2p/ω (A.12) is not.  Given the draws of the rows' deviations (rows × M, each in its
    row's unit), ``coefficients`` (each row's c_i in the budget's unit) and the index of the
    table's relative rate error ε (or None), the deviation of p: (p + Σ c_i·δx_i)/(1 + ε)² − p,
    the sum over the other rows.

    >>> import numpy as np
    >>> round(float(rate_sensitivity_model(1.0, [1.0, 2.0], 1)(np.array([[0.0], [0.01]]))[0]), 6)
    -0.019704
    """

    def model(d):
        lin = sum(c * d[i] for i, c in enumerate(coefficients) if i != rate_row)
        if rate_row is None:
            return lin
        return (p + lin) / (1.0 + d[rate_row]) ** 2 - p

    return model

#: Order of the six positions in the columns of Ā (7.2.2.2 and 7.2.4.2): X up, X down,
#: Y up, Y down, Z up, Z down.
SIX_POSITIONS = ("+x", "-x", "+y", "-y", "+z", "-z")


def mean_output_eq3(samples: Sequence[float]) -> float:
    """Mean output of one rate point, JJF 2003 7.2.1.2 eq. (3): U_k = (1/N) Σ U_ki."""
    a = np.asarray(samples, dtype=float)
    if a.size == 0:
        raise ValueError("eq. (3) needs at least one sample")
    return float(np.mean(a))


def scale_factor_eq5(rates: Sequence[float], means: Sequence[float]) -> LinearFit:
    """Scale factor and fitted bias by least squares, JJF 2003 7.2.1.2 eq. (4), (5)::

        U = K·X + b + ε,    [K b]ᵀ = (HᵀH)⁻¹ Hᵀ U,   H = [X 1]

    :param rates: X, the input rates of the n calibration points.
    :param means: U, the mean outputs (eq. (3)) at those rates.
    :return: the fit; ``coef = [K, b]`` and their covariance (scaled by the residual variance).
    """
    X = np.asarray(rates, dtype=float)
    U = np.asarray(means, dtype=float)
    H = np.column_stack([X, np.ones_like(X)])
    return fit_linear(H, U)


def six_position_design() -> np.ndarray:
    """The 4×6 input matrix Ā_g = Ā_a of 7.2.2.2 / 7.2.4.2 (rows a_X, a_Y, a_Z in gn, and 1)."""
    return np.array([
        [1, -1, 0, 0, 0, 0],
        [0, 0, 1, -1, 0, 0],
        [0, 0, 0, 0, 1, -1],
        [1, 1, 1, 1, 1, 1],
    ], dtype=float)


def pair_average(u_heading0: np.ndarray, u_heading180: np.ndarray) -> np.ndarray:
    """U_i of 7.2.2.1 a): the mean of the two mountings of a position that differ by a 180°
    turn about the vertical (cancels the horizontal earth rate and a level error)."""
    return 0.5 * (np.asarray(u_heading0, float) + np.asarray(u_heading180, float))


def six_position_eq7(U: np.ndarray, A: np.ndarray | None = None) -> np.ndarray:
    """Least-squares solution of U = Ḡ·Ā, JJF 2003 eq. (6)–(8) (gyros) and eq. (9)–(11)
    (accelerometers)::

        Ḡ = U·Āᵀ·(Ā·Āᵀ)⁻¹ = [G | B]

    :param U: 3×6 outputs (rows x, y, z; columns the six positions of :data:`SIX_POSITIONS`).
    :param A: the 4×m input matrix (default :func:`six_position_design`).
    :return: 3×4 matrix [G | B] (or [K_a | B_a]).
    :raises ValueError: if Ā·Āᵀ is singular (the positions do not span the three axes).
    """
    A = six_position_design() if A is None else np.asarray(A, float)
    U = np.asarray(U, float)
    M = A @ A.T
    if np.linalg.matrix_rank(M) < M.shape[0]:
        raise ValueError("Ā·Āᵀ is singular: the mounting positions do not determine all axes and "
                         "the bias")
    return U @ A.T @ np.linalg.inv(M)


def six_position_sensitivities(A: np.ndarray | None = None) -> np.ndarray:
    """∂Ḡ/∂U: the 6×4 matrix Āᵀ(ĀĀᵀ)⁻¹; column c gives the weight of each position's output in
    column c of Ḡ (1/2, −1/2 for the g terms as in (A.6); 1/6 each for the bias as in (A.4))."""
    A = six_position_design() if A is None else np.asarray(A, float)
    return A.T @ np.linalg.inv(A @ A.T)


def earth_rate_leak(K_g: np.ndarray, latitude_deg: float, earth_rate: float) -> np.ndarray:
    """Part of the eq. (7) g matrix that is earth rate, not g-sensitivity (per gn of input).

    With axis j up the vertical earth rate Ω·sin φ lies along +j; with axis j down along −j.
    It flips sign with gravity, so eq. (7) puts K_g[:, j]·Ω·sin φ into column j of G
    (mostly the diagonal, K_g ≈ I).  ``earth_rate`` is Ω in the gyro output's rate unit.
    """
    return np.asarray(K_g, float) * (earth_rate * math.sin(math.radians(latitude_deg)))


def rate_sensitivity_eq12(u_rest: float, u_turning: float, omega: float, *,
                          sign: str = "model") -> float:
    """Accelerometer angular-rate sensitivity, JJF 2003 7.2.5.2 eq. (12), (13).

    Printed: p_yx = (U_ay7 − U_ay8)/ω².  By the model of eq. (2), a'_Y contains + p_yx·ω_X², so
    U_ay8 − U_ay7 = p_yx·ω²: the printed form has the opposite sign.  ``sign="model"``
    (metro's default, docs/interpretations.md) returns (U8 − U7)/ω²; ``sign="as-printed"``
    returns (U7 − U8)/ω².
    """
    if omega == 0:
        raise ValueError("eq. (12) needs a non-zero table rate ω")
    d = (u_turning - u_rest) if sign == "model" else (u_rest - u_turning)
    if sign not in ("model", "as-printed"):
        raise ValueError(f"sign must be 'model' or 'as-printed', got {sign!r}")
    return d / omega**2


# ---------------------------------------------------------------------------------- appendix A


def quantization_u2(bits: int) -> float:
    """Appendix A.1.2.2: δ = 1/2^N (A.3), uniform, u₂ = δ/√3 (1.41×10⁻⁴ for N = 12)."""
    return (1.0 / 2**bits) / math.sqrt(3.0)


def combined_appendix_a(u1: float, u2: float, u3: float) -> float:
    """Appendix A (A.1.3, A.2.3, …): u_c = √(u₁² + u₂² + u₃²)."""
    return math.sqrt(u1 * u1 + u2 * u2 + u3 * u3)


def linear_sum_u3(us: Sequence[float]) -> float:
    """Appendix A.2.2.3, A.3.2.3, A.5.2.3: u₃ as the *linear* sum of the equal per-position
    repeatabilities (u₃ = u(U₁) + … + u(U₆) = 2.046×10⁻⁴), as printed."""
    return float(sum(us))


def sig_text(x: float, digits: int) -> str:
    """``x`` with ``digits`` significant digits as a×10^e text (e.g. '2.12e-04')."""
    return f"{x:.{digits - 1}e}"


def appendix_a_examples() -> dict[str, dict[str, object]]:
    """The five worked examples of appendix A, recomputed from their printed inputs.

    Each entry: u1, u2, u3, u_c, U (= 2·u_c, unrounded) and the texts as the appendix prints
    them: u_c to three significant digits; U rounded *up* to two significant digits (A.1.4,
    A.3.4, A.4.4, A.5.4), except A.2.4 which prints U = 2·u_c with three digits (5.36×10⁻⁴).
    """
    u1 = 2e-4 / 2  # A.1.2.1: table U = 2×10⁻⁴, k = 2
    u2 = quantization_u2(12)
    cases = {
        "A.1 scale factor": (u1, u2, 1.22e-4, 2),
        "A.2 bias": (u1, u2, linear_sum_u3([3.41e-5] * 6), 3),
        "A.3 g-sensitivity": (u1, u2, linear_sum_u3([2.51e-3] * 2), 2),
        "A.4 cross-coupling": (u1, u2, 1.22e-4, 2),
        "A.5 rate sensitivity p": (u1, u2, linear_sum_u3([2.51e-3] * 2), 2),
    }
    out = {}
    for name, (a, b, c, U_digits) in cases.items():
        uc = combined_appendix_a(a, b, c)
        U = 2.0 * uc
        if U_digits == 2:
            U_text = round_uncertainty(U, digits=2, mode="up").text
        else:  # A.2.4 keeps three significant digits
            step = Decimal(1).scaleb(Decimal(repr(U)).adjusted() - 2)
            U_text = f"{Decimal(repr(U)).quantize(step):f}"
        out[name] = {"u1": a, "u2": b, "u3": c, "u_c": uc, "U": U,
                     "u_c_text": sig_text(uc, 3), "U_text": U_text}
    return out

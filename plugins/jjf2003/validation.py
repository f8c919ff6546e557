"""JJF 2003—2022's worked examples as validation cases (``metro validate``): appendix A's five
budgets, u_c and U as the appendix prints them, recomputed by this plugin's formulas from the
appendix's printed inputs."""

from __future__ import annotations

import functools

from metro.api import ValidationCase

from . import formulas as F

#: (appendix item, u_c and U as printed)
APPENDIX_A = (
    ("A.1 scale factor", "2.12e-04", "0.00043"),
    ("A.2 bias", "2.68e-04", "0.000536"),
    ("A.3 g-sensitivity", "5.02e-03", "0.011"),
    ("A.4 cross-coupling", "2.12e-04", "0.00043"),
    ("A.5 rate sensitivity p", "5.02e-03", "0.011"),
)


def _appendix_a(name: str) -> list[str]:
    ex = F.appendix_a_examples()[name]
    return [str(ex["u_c_text"]), str(ex["U_text"])]


def _inputs() -> list[object]:
    return [f"{F.quantization_u2(12):.2e}", F.linear_sum_u3([3.41e-5] * 6)]


def validation_cases() -> list[ValidationCase]:
    """Appendix A.1–A.5 (u_c, U as printed, digit for digit) and the A.1.2.2 / A.2.2.3 inputs."""
    cases = [
        ValidationCase(f"jjf2003:{name.split()[0]}", f"appendix {name}: u_c and U as printed",
                       f"JJF 2003—2022 appendix {name.split()[0]}", [uc, U],
                       functools.partial(_appendix_a, name), labels=("u_c", "U"))
        for name, uc, U in APPENDIX_A
    ]
    cases.append(ValidationCase(
        "jjf2003:A.1.2.2", "quantization u₂ of a 12-bit converter and the six repeatabilities "
        "summed (u₃)", "JJF 2003—2022 appendix A.1.2.2 and A.2.2.3", ["1.41e-04", 2.046e-4],
        _inputs, rtol=1e-12, labels=("u₂ (N = 12)", "u₃ = Σ u(U_i)")))
    return cases

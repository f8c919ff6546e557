"""JJF 2003's validation cases (``metro validate``): appendix A reproduced digit for digit through
the hook, and a wrong formula failing the cases that use it."""

from __future__ import annotations

from metro.plugins.jjf2003 import formulas as F
from metro.plugins.jjf2003 import validation as V


def test_appendix_a_cases_pass_and_a_wrong_quantization_fails_them(monkeypatch):
    cases = V.validation_cases()
    assert [c.id for c in cases] == ["jjf2003:A.1", "jjf2003:A.2", "jjf2003:A.3", "jjf2003:A.4",
                                     "jjf2003:A.5", "jjf2003:A.1.2.2"]
    assert all(c.source.startswith("JJF 2003—2022 appendix A") for c in cases)
    done = [c.run() for c in cases]
    assert all(c.passed for c in done), [c.detail for c in done]
    assert done[0].computed == ("2.12e-04", "0.00043")
    # u₂ of A.1.2.2 5 % high: the input and the budgets it weighs in no longer reproduce; A.3 and
    # A.5 (u₃ = 5.02×10⁻³ dominates) still print the same digits
    real = F.quantization_u2
    monkeypatch.setattr(F, "quantization_u2", lambda n: 1.05 * real(n))
    assert [c.id for c in cases if not c.run().passed] == ["jjf2003:A.1", "jjf2003:A.2",
                                                           "jjf2003:A.4", "jjf2003:A.1.2.2"]

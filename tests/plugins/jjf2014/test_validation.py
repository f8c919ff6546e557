"""JJF 2014's validation cases (``metro validate``): appendix B reproduced as printed, and a
wrong budget failing them."""

from __future__ import annotations

from metro.plugins.jjf2014 import budgets as B
from metro.plugins.jjf2014 import validation as V


def test_appendix_b_cases_pass_and_a_wrong_budget_fails_them(monkeypatch):
    cases = V.validation_cases()
    assert [c.id for c in cases] == ["jjf2014:B.1", "jjf2014:B.2"]
    done = [c.run() for c in cases]
    assert all(c.passed for c in done), [c.detail for c in done]
    assert done[0].computed == ("1.65×10^-4", "3.3×10^-4", "0.00033")
    real = B.scale_factor_budget

    def doubled_repeatability(K, s, dof, **kw):
        return real(K, s * 2, dof, **kw)

    monkeypatch.setattr(B, "scale_factor_budget", doubled_repeatability)
    assert [c.id for c in cases if not c.run().passed] == ["jjf2014:B.1", "jjf2014:B.2"]

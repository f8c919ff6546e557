"""The ogam draft's validation cases (``metro validate``): appendix A's budget and tilt extreme
as printed, and a wrong drift term failing the cases that use it."""

from __future__ import annotations

from metro.plugins.ogam import formulas as F
from metro.plugins.ogam import validation as V


def test_appendix_a_cases_pass_and_a_wrong_drift_term_fails(monkeypatch):
    cases = V.validation_cases()
    assert [c.id for c in cases] == ["ogam:A-budget", "ogam:A-tilt"]
    done = [c.run() for c in cases]
    assert all(c.passed for c in done), [c.detail for c in done]
    assert done[0].computed[-1] == "0.30" and done[1].computed[0] == "0.08"
    real = F.zero_drift_error
    monkeypatch.setattr(F, "zero_drift_error", lambda rate, minutes: 2 * real(rate, minutes))
    failed = [c.run() for c in cases]
    assert "ogam:A-tilt" in [c.id for c in failed if not c.passed]
    assert "drift term" in next(c for c in failed if c.id == "ogam:A-tilt").detail

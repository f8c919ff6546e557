"""GB/T 45570's validation cases (``metro validate``): D.40–D.44 on hand-worked inputs and the
MTBF bound on the published χ² table, and a wrong formula failing its case."""

from __future__ import annotations

from metro.plugins.gbt45570 import formulas as F
from metro.plugins.gbt45570 import validation as V


def test_formula_cases_pass_and_a_wrong_d41_fails_its_case(monkeypatch):
    cases = V.validation_cases()
    assert [c.id for c in cases] == ["gbt45570:D.40-D.44", "gbt45570:5.5-MTBF"]
    done = [c.run() for c in cases]
    assert all(c.passed for c in done), [c.detail for c in done]
    real = F.bias_stability_d41
    monkeypatch.setattr(F, "bias_stability_d41", lambda *a: real(*a) * (1 + 1e-6))
    failed = [c.run() for c in cases]
    assert [c.id for c in failed if not c.passed] == ["gbt45570:D.40-D.44"]
    assert failed[0].detail.startswith("B_s (D.41), °/h")

"""``metro run --monte-carlo``: every budget checked by Monte Carlo (JCGM 101) in --json, on the
terminal and in the report; without the option the run is as before."""

from __future__ import annotations

import contextlib
import io
import json

import pytest


def _main(*argv: str) -> tuple[int, str]:
    from metro.core.cli.app import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out), contextlib.redirect_stderr(io.StringIO()):
        code = main(list(argv))
    return code, out.getvalue()


RUN = ("run", "-s", "ogam", "--all", "--no-progress", "--seed", "1", "--no-report")


@pytest.fixture(scope="module")
def docs() -> tuple[dict, dict]:
    plain = json.loads(_main(*RUN, "--json")[1])
    checked = json.loads(_main(*RUN, "--json", "--monte-carlo")[1])
    return plain, checked


def _without_run_specifics(doc: dict) -> dict:
    doc = json.loads(json.dumps(doc))
    for key in ("report_number", "timings_s", "provenance"):
        doc.pop(key)
    for r in doc["results"]:
        r.pop("monte_carlo", None)
    return doc


def test_the_option_only_adds_the_check(docs):
    plain, checked = docs
    assert not any("monte_carlo" in r for r in plain["results"])
    assert _without_run_specifics(plain) == _without_run_specifics(checked)


def test_every_result_with_a_budget_has_a_verdict(docs):
    _, checked = docs
    with_budget = [r for r in checked["results"] if r["budget"]]
    assert with_budget and all("monte_carlo" in r for r in with_budget)
    for r in with_budget:
        mc = r["monte_carlo"]
        assert mc["validated"] == (mc["d_low"] <= mc["delta"] and mc["d_high"] <= mc["delta"])
        assert mc["U_gum"] == pytest.approx(r["U"])
        assert mc["p"] == pytest.approx(0.9545, abs=1e-4)  # k = t_p(ν_eff) for p = 95.45 %
        low, high = mc["interval"]
        # d_low, d_high are the distances between the GUM and the Monte Carlo ends (eq. (27), (28))
        ulp = 1e-12 * max(abs(r["value"]), 1.0)
        assert mc["d_low"] == pytest.approx(abs(r["value"] - r["U"] - low), abs=ulp)
        assert mc["d_high"] == pytest.approx(abs(r["value"] + r["U"] - high), abs=ulp)
    verdicts = {r["item"]: r["monte_carlo"]["validated"] for r in with_budget}
    assert set(verdicts.values()) == {True, False}  # ogam has both (docs/monte-carlo.md)


def test_the_same_seed_gives_the_same_check(docs):
    _, checked = docs
    again = json.loads(_main(*RUN, "--json", "--monte-carlo")[1])
    assert [r.get("monte_carlo") for r in again["results"]] == [
        r.get("monte_carlo") for r in checked["results"]]


def test_terminal_summary_names_the_results_not_validated(monkeypatch):
    monkeypatch.setenv("COLUMNS", "250")
    code, out = _main(*RUN, "--monte-carlo")
    assert "Monte Carlo (JCGM 101): the GUM interval is validated for" in out
    assert "GUM not validated by MC" in out


def test_the_report_states_the_monte_carlo_interval_where_gum_is_not_validated():
    from metro.core.documents.context import report_context
    from metro.core.run.montecarlo_run import gum_not_validated, with_monte_carlo
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    pm = get_plugin_manager()
    record = run_items(pm, "ogam", ["7.1", "7.2"], station_options={"seed": 1})
    checked = with_monte_carlo(record, 1)
    plain_ctx = report_context(record)["outcomes"]
    ctx = report_context(checked)["outcomes"]
    failing = gum_not_validated(checked)
    assert failing  # 7.1's K: a t row (the rounds' scatter) makes the GUM interval too narrow
    for o_plain, o in zip(plain_ctx, ctx):
        for r_plain, r in zip(o_plain["results"], o["results"]):
            if (o["item"], r["key"]) in failing:
                assert r["k"] == "MC" and r["U"].startswith("[") and r["monte_carlo_p"] == "95.45"
                assert any("not validated by Monte Carlo" in str(n) for n in o["notes"])
            else:
                assert r["U"] == r_plain["U"] and r["k"] == r_plain["k"]
        for b in o["budgets"]:
            assert "Monte Carlo (JCGM 101" in str(b["note"])
    assert all("Monte Carlo" not in str(b["note"]) for o in plain_ctx for b in o["budgets"])

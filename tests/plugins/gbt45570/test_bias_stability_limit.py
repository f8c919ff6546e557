"""Issue 29: the built-in device conforms to its class, row 10 (bias stability) is judged at t = 100
s only, test levels are judged as set, and D.5.2's t must be positive.

docs/interpretations.md: "D.5.2 — which smoothing time the table's limit applies to",
"Conformity — test levels"; docs/standards/gbt45570.md: "The simulated device".
"""

from __future__ import annotations

import json
from types import SimpleNamespace

import attrs
import pytest

from metro.core.uncertainty.conformity import Status, assess
from metro.core.model.campaign import DeviceUnderTest
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.runner import judge, run_items
from metro.core.base.units import Q_
from metro.plugins.gbt45570.conformity import specifications

AVIATION_LASER = DeviceUnderTest(id="G1", technology="laser", application="aviation",
                                 output="pulse")


@pytest.fixture(scope="module")
def pm():
    return get_plugin_manager()


@pytest.fixture(scope="module")
def d52(pm):
    """D.5.2 on the default simulated device (t = 10 s and 100 s)."""
    return run_items(pm, "gbt45570", ["D.5.2"], station_options={"seed": 3})


def _verdicts(record):
    return {v.key: v for v in record.conformity.verdicts}


def test_row_10_judges_t_100_s_only(d52):
    keys = {r.metric.key for o in d52.outcomes for r in o.results}
    assert keys == {"Bs_10s", "Bs_100s"}  # both reported …
    v = _verdicts(d52)
    assert set(v) == {"Bs_100s"}  # … only t = 100 s judged; B_s(10 s) is informative
    assert v["Bs_100s"].spec.limit == Q_(0.007, "deg/h")
    assert "t = 100 s" in str(v["Bs_100s"].spec.source) and "informative" in str(v[
        "Bs_100s"].spec.source)
    # the default device conforms, with margin: value + U below the limit
    assert v["Bs_100s"].status is Status.PASS
    (bs,) = [r for o in d52.outcomes for r in o.results if r.metric.key == "Bs_100s"]
    assert float((bs.value + bs.U).to("deg/h").magnitude) < 0.007


def test_a_product_specification_of_bs_replaces_row_10(pm, d52):
    assert not [s for s in specifications(AVIATION_LASER, {"Bs_10s": "<= 0.05 deg/h"})
                if s.symbol.startswith("Bs")]
    assert [s.symbol for s in specifications(AVIATION_LASER)
            if s.symbol.startswith("Bs")] == ["Bs_100s"]
    own = attrs.evolve(d52.campaign, specification={"Bs_10s": "<= 0.05 deg/h"})
    v = {x.key: x for x in judge(pm, "gbt45570", own, d52.outcomes).verdicts}
    assert set(v) == {"Bs_10s"} and "product specification" in str(v["Bs_10s"].spec.source)
    # a bare Bs in the manifest judges every t, as the manifest says
    every = attrs.evolve(d52.campaign, specification={"Bs": "<= 1 deg/h"})
    assert {x.key for x in judge(pm, "gbt45570", every,
                                 d52.outcomes).verdicts} == {"Bs_10s", "Bs_100s"}


def test_without_t_100_s_row_10_is_not_assessed(pm):
    rec = run_items(pm, "gbt45570", ["D.5.2"], options={"t": "10 s"}, station_options={"seed": 3})
    assert rec.conformity is None or not [v for v in rec.conformity.verdicts
                                          if v.key.startswith("Bs")]
    assert "Bs_100s" in [s.symbol for s in rec.conformity.not_assessed]


def _outcome(item, key, value, U, unit, U_unit=None):
    metric = SimpleNamespace(key=key)
    res = SimpleNamespace(metric=metric, value=Q_(value, unit), U=Q_(U, U_unit or unit), k=2.0,
                          reportable=True)
    return SimpleNamespace(item=item, results=[res])


def test_test_levels_are_judged_as_set():
    specs = specifications(AVIATION_LASER)
    rules = {s.symbol: s.rule for s in specs}
    assert rules["T_low"] == rules["T_high"] == rules["vib_perf_level"] == rules[
        "Omega_max"] == "simple"
    # device properties keep the run's rule
    assert rules["RWC"] == rules["Bs_100s"] == rules["Kt"] == ""
    a = assess([_outcome("D.6.1", "T_low", -55.0, 0.3, "degC", "delta_degC"),
                _outcome("D.3", "Omega_max", 400.0, 0.0023, "deg/s"),
                _outcome("D.5.6", "RWC", 0.00151, 0.00027, "deg/hour**0.5")], specs)
    v = {x.key: x for x in a.verdicts}
    assert v["T_low"].status is Status.PASS and v["T_low"].rule.name == "simple"
    assert "not used by simple acceptance" in str(v["T_low"].reason)
    assert v["Omega_max"].status is Status.PASS
    assert v["RWC"].status is Status.INDETERMINATE and v["RWC"].rule.name == "guarded"
    # a severity set milder than the row still does not conform
    milder = assess([_outcome("D.6.1", "T_low", -50.0, 0.3, "degC", "delta_degC")], specs)
    assert milder.verdicts[0].status is Status.FAIL


@pytest.mark.parametrize("t", ["-10 s", "0 s", "10 s, -5 s"])
def test_d52_t_must_be_positive(run_cli, tmp_path, t):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.2", "-o", f"t={t}", "--no-report",
                             "-q")
    assert code == 2
    assert "option t" in err and "must be > 0" in err
    assert "whole number of sampling intervals" not in err and "Traceback" not in err


def test_the_readme_main_job_conforms_on_the_default_device(run_cli, tmp_path):
    """README: `metro run --standard gbt45570 --item D.5.6` — before issue 29 RWC = 0.00151 ±
    0.00027 (°)/h^½ against ≤ 0.0015: indeterminate (conditional fail)."""
    code, out, err = run_cli("run", "--standard", "gbt45570", "--item", "D.5.6", "--json",
                             "--no-report",
                             "--strict", "-q")
    assert code == 0, err
    doc = json.loads(out)
    assert doc["conformity"]["overall"] == "pass"
    assert "typical aviation-grade unit, conforms to table A.1" in doc["device"]["model"]


@pytest.mark.parametrize(("grade", "status"), [("typical", "pass"), ("marginal", "indeterminate"),
                                                ("failing", "fail")])
def test_grades_of_the_simulated_device(pm, grade, status):
    """The station option ``grade`` keeps the marginal and failing units available."""
    rec = run_items(pm, "gbt45570", ["D.5.6"], station_options={"seed": 20251122, "grade": grade})
    assert grade in rec.campaign.device.model or grade == "typical"
    assert rec.conformity.overall.value == status


def test_an_unknown_grade_is_refused(run_cli):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.6", "--station-option",
                             "grade=superb",
                             "--no-report", "-q")
    assert code == 2 and "grade" in err and "Traceback" not in err


def test_d4_unresolved_positions_bound_the_threshold(pm):
    """interpretations.md "D.4 — an upper bound when nothing below is resolved": with nothing
    resolved below the first resolved pass H, the threshold is reported as ≤ H (a bound, U of the
    input at H) and judged as (−∞, H + U]; before, it was not reportable and indeterminate on every
    such device."""
    from metro.plugins.gbt45570.threshold import parse_levels

    levels = parse_levels("0.002, 0.004, 0.006, 0.008, 0.01, 0.012, 0.015, 0.02, 0.03, 0.05")
    rec = run_items(pm, "gbt45570", ["D.4"], station_options={"seed": 1})
    (r,) = rec.outcomes[0].results
    assert r.bound == "upper" and not r.reportable and "stated as at most" in r.reason
    H = float(r.value.to("deg/h").magnitude)
    assert min(abs(H - x) for x in levels) < 1e-6 and H < 0.02  # a tested input (Ψ_i as set)
    # the input realised at H, no noise
    assert {row.symbol for row in r.budget.rows} <= {"δΨ", "u(θ)", "u_rel(K)"}
    (v,) = rec.conformity.verdicts
    assert v.status is Status.PASS and "bound" in str(v.reason)
    # the marginal unit's noise resolves no position below the limit: no statement
    worse = run_items(pm, "gbt45570", ["D.4"], station_options={"seed": 1, "grade": "marginal"})
    assert worse.conformity.verdicts[0].status is Status.INDETERMINATE


@pytest.mark.parametrize("seed", [1, 2, 3])
def test_acquired_campaign_of_the_default_device_conforms(run_cli, tmp_path, seed):
    """`metro acquire --standard gbt45570 --all --out DIR` then `metro run --standard gbt45570 --all
    --data DIR/manifest.toml`: recorded data (exit codes are not relaxed as on the station) conform
    — every verdict passes (before issue 29: D.5.2 failed, D.1.3, D.1.5, D.3, D.4, D.5.6,
    D.6.1–D.6.3 indeterminate)."""
    out = tmp_path / "camp"
    code, _, err = run_cli("acquire", "--standard", "gbt45570", "--all", "--out", str(out),
                           "--seed", str(seed), "-q")
    assert code == 0, err
    code, text, err = run_cli("run", "--standard", "gbt45570", "--all", "--data",
                              str(out / "manifest.toml"),
                              "--json", "--no-report", "-q")
    assert code == 0, err
    doc = json.loads(text)
    verdicts = doc["conformity"]["verdicts"]
    assert len(verdicts) > 80 and doc["conformity"]["overall"] == "pass"
    assert not [v for v in verdicts if v["status"] != "pass"]

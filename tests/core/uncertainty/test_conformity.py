"""Conformity: limits, decision rules (with property-based invariants), the specifications hook,
GB/T 45570 tables A.1/B.1/C.1 as data, the 6.2.7.1 method rule, --all and series."""

from __future__ import annotations

import math

import pytest
from hypothesis import assume, given, settings
from hypothesis import strategies as st

from metro.core.uncertainty import conformity as cf
from metro.core.uncertainty.conformity import (GUARDED, SIMPLE, Comparison, Specification, Status,
                                               decide, parse_limit)
from metro.core.base.errors import DataError, UnitError
from metro.core.model.campaign import DeviceUnderTest
from metro.core.base.units import Q_

# ---------------------------------------------------------------------------------------------
# Specifications and decisions, by hand
# ---------------------------------------------------------------------------------------------


def test_parse_limits_of_every_form():
    assert parse_limit("Kn", "<= 10 ppm").bounds == (-math.inf, 10)
    assert parse_limit("K", "≥ 0.25 P/″").comparison is Comparison.AT_LEAST
    r = parse_limit("B0", "-1 .. 1 deg/h")
    assert r.comparison is Comparison.RANGE and r.bounds == (-1,
                                                             1) and r.limit.units == Q_(
                                                                 1, "deg/h").units
    assert parse_limit("B0", "-1 deg/h .. +1 deg/h").bounds == (-1, 1)
    assert parse_limit("B0", "± 0.5 deg/h").bounds == (-0.5, 0.5)
    m = parse_limit("Bh", "|x| <= 0.1 deg/h/mT")
    assert m.magnitude and m.text() == "|x| ≤ 0.1 °/h/mT"
    # "/°C" in a sensitivity is a temperature difference, not 1/(274.15 K)
    bt = parse_limit("Bt", "<= 0.001 °/h/°C")
    assert bt.limit.to("deg/h/delta_degC").magnitude == pytest.approx(0.001)
    with pytest.raises(DataError, match="cannot read the limit"):
        parse_limit("Kn", "about ten ppm")
    with pytest.raises(DataError, match="upper bound is below"):
        parse_limit("B0", "1 .. -1 deg/h")


def test_specification_validates():
    with pytest.raises(TypeError):
        Specification("Kn", Comparison.AT_MOST, 10.0)
    with pytest.raises(ValueError, match="needs an upper bound"):
        Specification("B0", Comparison.RANGE, Q_(-1, "deg/h"))
    with pytest.raises(ValueError, match="only a range"):
        Specification("Kn", Comparison.AT_MOST, Q_(1, "ppm"), Q_(2, "ppm"))
    with pytest.raises(UnitError):
        Specification("B0", Comparison.RANGE, Q_(-1, "deg/h"), Q_(1, "arcsec"))


def test_guarded_and_simple_hand_worked():
    kn = parse_limit("Kn", "<= 10 ppm", source="test")
    v = decide(kn, Q_(8e-6, ""), Q_(1, "ppm"), GUARDED, item="D.1.2")  # compatible units: 1 and ppm
    assert v.status is Status.PASS and "[7, 9 ppm]" in v.reason and "wholly within" in v.reason
    v = decide(kn, Q_(9.5, "ppm"), Q_(1, "ppm"), GUARDED)
    assert v.status is Status.INDETERMINATE and v.detail == "conditional pass"
    v = decide(kn, Q_(10.5, "ppm"), Q_(1, "ppm"), GUARDED)
    assert v.status is Status.INDETERMINATE and v.detail == "conditional fail"
    assert decide(kn, Q_(12, "ppm"), Q_(1, "ppm"), GUARDED).status is Status.FAIL
    assert decide(kn, Q_(10.5, "ppm"), Q_(1, "ppm"), SIMPLE).status is Status.FAIL
    assert decide(kn, Q_(10, "ppm"), None, SIMPLE).status is Status.PASS  # on the limit conforms
    nou = decide(kn, Q_(1, "ppm"), None, GUARDED)
    assert nou.status is Status.INDETERMINATE and "no expanded uncertainty" in nou.reason
    # the interval is printed with digits enough to tell its ends apart
    k = decide(parse_limit("K", ">= 0.25 P/″"), Q_(0.8, "P/arcsec"), Q_(1.4e-6, "P/arcsec"))
    assert "[0.7999986, 0.8000014 P/″]" in k.reason
    # a range in °/h judged on a value in ″/s (1 ″/s = 1 °/h)
    b0 = parse_limit("B0", "-1 .. 1 deg/h")
    assert decide(b0, Q_(-0.5, "arcsec/s"), Q_(0.1, "deg/h")).status is Status.PASS
    assert decide(b0, Q_(-1.5, "arcsec/s"), Q_(0.1, "deg/h")).status is Status.FAIL
    # |x|: the interval of |x| stops at zero
    bh = parse_limit("Bh", "|x| <= 0.1 deg/h/mT")
    v = decide(bh, Q_(-0.05, "deg/h/mT"), Q_(0.02, "deg/h/mT"), key="Bh_IRA")
    assert v.status is Status.PASS and "|Bh_IRA|" in v.reason


def test_incompatible_units_are_a_clear_error():
    kn = parse_limit("Kn", "<= 10 ppm")
    with pytest.raises(UnitError, match="different kinds of quantity"):
        decide(kn, Q_(1, "deg/h"), None)
    rate = parse_limit("B0", "<= 1 deg/h")
    with pytest.raises(UnitError, match="different kinds"):  # pint alone would convert °/h to Hz
        decide(rate, Q_(1, "Hz"), None)
    with pytest.raises(UnitError, match="expanded uncertainty"):
        decide(rate, Q_(0.1, "deg/h"), Q_(1, "ppm"))


def test_assess_matches_keyed_variants_and_lists_unmet_limits():
    from metro.core.model.results import Metric, Outcome, Result

    def res(key, value, unit):
        return Result(Metric(key, key, key, unit, "X"), Q_(value, unit))

    out = Outcome("s", "D.5.5", "t", "c", [res("Bh_IRA", 0.01, "deg/h/mT"),
                                           res("Bh_XRA", 0.5, "deg/h/mT")])
    specs = [parse_limit("Bh", "|x| <= 0.1 deg/h/mT"), parse_limit("RWC", "<= 0.002 deg/hour**0.5")]
    a = cf.assess([out], specs, SIMPLE)
    assert [(v.key, v.status) for v in a.verdicts] == [
        ("Bh_IRA", Status.PASS),
        ("Bh_XRA", Status.FAIL),
    ]
    assert [s.symbol for s in a.not_assessed] == ["RWC"]
    assert a.overall is Status.FAIL and a.counts() == {"pass": 1, "fail": 1, "indeterminate": 0}
    # the most specific limit judges a result
    both = [parse_limit("Bh", "|x| <= 1 deg/h/mT"), parse_limit("Bh_XRA", "|x| <= 0.6 deg/h/mT")]
    a = cf.assess([out], both, SIMPLE)
    assert [(v.spec.symbol, v.key, v.status) for v in a.verdicts] == [
        ("Bh", "Bh_IRA", Status.PASS), ("Bh_XRA", "Bh_XRA", Status.PASS)]
    # a manifest's limit replaces the standard's for the same symbol
    merged = cf.merge_specifications(
        specs, [parse_limit("Bh", "<= 1 deg/h/mT", source="product spec")]
    )
    assert {s.symbol: s.source for s in merged} == {"Bh": "product spec", "RWC": ""}


def test_a_result_declared_not_reportable_gets_no_statement_of_conformity():
    """A value its procedure will not stand behind is neither a pass nor a fail under either rule.

    Seen on `metro run -s gbt45570 -i D.5.1,D.5.6 --station simulated-digital --seed 1`: RWC 0.0051
    °/√h, not reportable (rounding coarser than the noise), was judged "fail vs ≤ 0.0015 °/√h" and
    made the run "does not conform"; the station's truth is 0.0015.
    """
    import attrs

    from metro.core.uncertainty.budget import BudgetRow, Coverage, UncertaintyBudget
    from metro.core.model.results import Metric, Outcome, Result

    def res(key, unit, value, U):  # a budget of one normal row, k = 2: U as given
        row = BudgetRow.type_b("hand-worked", key, Q_(U, unit), distribution="normal", k=2)
        budget = UncertaintyBudget(key, unit, [row], coverage=Coverage.fixed(2))
        return Result(Metric(key, key, key, unit, "X"), Q_(value, unit), budget=budget)

    ok = res("B0", "deg/h", 0.2, 0.4)
    bad = attrs.evolve(res("RWC", "deg/hour**0.5", 0.0051, 0.0001),
                       reportable=False, reason="the output is rounded coarser than its noise")
    out = Outcome("s", "D.5.6", "t", "c", [ok, bad])
    specs = [parse_limit("B0", "|x| <= 1 deg/h"), parse_limit("RWC", "<= 0.0015 deg/hour**0.5")]
    for rule in (GUARDED, SIMPLE):
        a = cf.assess([out], specs, rule)
        v = {x.key: x for x in a.verdicts}
        assert v["B0"].status is Status.PASS
        assert v["RWC"].status is Status.INDETERMINATE and v["RWC"].detail == "not reportable"
        assert "RWC is not reportable (the result gives the reason)" in v["RWC"].reason
        assert "no statement of conformity" in v["RWC"].reason
        assert a.overall is Status.INDETERMINATE and a.counts() == {
            "pass": 1,
            "fail": 0,
            "indeterminate": 1,
        }
        assert v["RWC"].as_dict()["status"] == "indeterminate"
    # the same value, reportable, fails: the verdict above is the declaration's doing
    a = cf.assess([Outcome("s", "D.5.6", "t", "c",
                           [attrs.evolve(bad, reportable=True, reason="")])], specs, GUARDED)
    assert a.verdicts[0].status is Status.FAIL


def test_a_bound_beyond_an_instruments_range_is_judged_as_a_half_line():
    """R > 10 000 MΩ (a megohmmeter over its range) conforms to R ≥ 50 MΩ; hand-worked
    half-lines."""
    import attrs

    from metro.core.uncertainty.budget import BudgetRow, Coverage, UncertaintyBudget
    from metro.core.model.results import Metric, Outcome, Result

    def bounded(value, bound, U=0.0):
        row = BudgetRow.type_b("reading beyond the range", "R", Q_(U, "Mohm"),
                               distribution="normal", k=2)
        b = UncertaintyBudget("R", "Mohm", [row], coverage=Coverage.fixed(2))
        r = Result(Metric("R_ins", "R", "insulation resistance", "Mohm", "5.2.8"),
                   Q_(value, "Mohm"), budget=b)
        return attrs.evolve(r, reportable=False, reason="beyond the meter's range", bound=bound)

    def judged(result, limit):
        return cf.assess([Outcome("s", "6.2.5", "t", "c", [result])], [parse_limit("R_ins", limit)],
                         GUARDED).verdicts[0]

    v = judged(bounded(10000, "lower"), ">= 50 Mohm")
    assert v.status is Status.PASS and "R_ins ≥ 1×10⁴ MΩ" in v.reason and "a bound" in v.reason
    # R > 10 000 is over 5 000
    assert judged(bounded(10000, "lower"), "<= 5000 Mohm").status is Status.FAIL
    # R < 20 is under 50
    assert judged(bounded(20, "upper"), ">= 50 Mohm").status is Status.FAIL
    assert judged(bounded(20, "upper"), "<= 50 Mohm").status is Status.PASS
    # a bound that does not decide: no statement
    v = judged(bounded(30, "lower"), ">= 50 Mohm")
    assert v.status is Status.INDETERMINATE and v.detail == "not reportable"
    # its U widens the half-line: R > 52 ± 4 does not show R ≥ 50
    assert judged(bounded(52, "lower", U=4), ">= 50 Mohm").status is Status.INDETERMINATE
    assert judged(bounded(52, "lower", U=1), ">= 50 Mohm").status is Status.PASS
    with pytest.raises(ValueError):
        attrs.evolve(bounded(1, "lower"), bound="above")


def test_rule_names():
    assert cf.rule_named(None) is cf.DEFAULT_RULE is GUARDED
    assert cf.rule_named("Simple") is SIMPLE
    with pytest.raises(DataError, match="unknown decision rule"):
        cf.rule_named("lenient")


# ---------------------------------------------------------------------------------------------
# Decision-rule invariants (hypothesis)
# ---------------------------------------------------------------------------------------------

finite = st.floats(min_value=-1e6, max_value=1e6, allow_nan=False, allow_infinity=False)
nonneg = st.floats(min_value=0, max_value=1e6, allow_nan=False, allow_infinity=False)


@st.composite
def specs(draw):
    kind = draw(st.sampled_from(list(Comparison)))
    a = draw(finite)
    mag = draw(st.booleans()) and kind is Comparison.AT_MOST
    if kind is Comparison.RANGE:
        b = draw(finite)
        lo, hi = min(a, b), max(a, b)
        return Specification("X", kind, Q_(lo, "deg/h"), Q_(hi, "deg/h"))
    return Specification("X", kind, Q_(a, "deg/h"), magnitude=mag)


@settings(max_examples=100, deadline=None)
@given(specs(), finite, nonneg)
def test_guarded_verdicts_imply_simple_ones(spec, value, U):
    g = decide(spec, Q_(value, "deg/h"), Q_(U, "deg/h"), GUARDED).status
    s = decide(spec, Q_(value, "deg/h"), Q_(U, "deg/h"), SIMPLE).status
    assert s in (Status.PASS, Status.FAIL)  # simple acceptance always decides
    if g is Status.PASS:
        assert s is Status.PASS
    if g is Status.FAIL:
        assert s is Status.FAIL


@settings(max_examples=100, deadline=None)
@given(specs(), finite, nonneg, st.floats(min_value=0, max_value=1))
def test_a_smaller_U_never_turns_a_decision_around(spec, value, U, shrink):
    big = decide(spec, Q_(value, "deg/h"), Q_(U, "deg/h"), GUARDED).status
    small = decide(spec, Q_(value, "deg/h"), Q_(U * shrink, "deg/h"), GUARDED).status
    if big is not Status.INDETERMINATE:
        assert small is big


@settings(max_examples=100, deadline=None)
@given(specs(), finite)
def test_zero_U_guarded_equals_simple(spec, value):
    g = decide(spec, Q_(value, "deg/h"), Q_(0.0, "deg/h"), GUARDED).status
    assert g is decide(spec, Q_(value, "deg/h"), None, SIMPLE).status


@settings(max_examples=100, deadline=None)
@given(specs(), finite, nonneg)
def test_verdict_does_not_depend_on_the_unit_the_value_is_in(spec, value, U):
    lo, hi = spec.bounds
    x = abs(value) if spec.magnitude else value
    for edge in (x, (x - U) if not spec.magnitude else max(0.0, x - U), x + U):
        for b in (lo, hi):
            if math.isfinite(b) and math.isfinite(edge):
                assume(abs(edge - b) > 1e-6 * (1 + abs(b)))  # away from float ties at a limit
    in_deg_h = decide(spec, Q_(value, "deg/h"), Q_(U, "deg/h"), GUARDED).status
    in_arcsec_s = decide(spec, Q_(value, "deg/h").to("arcsec/s"), Q_(U, "deg/h").to("arcsec/min"),
                         GUARDED).status
    assert in_deg_h is in_arcsec_s


# ---------------------------------------------------------------------------------------------
# The hook, GB/T 45570 tables and the 6.2.7.1 rule
# ---------------------------------------------------------------------------------------------


def test_specifications_hook_collects_plugin_limits(pm):
    from metro.core.model.campaign import Campaign

    laser = DeviceUnderTest("G", technology="laser", application="aviation")
    camp = Campaign("c", laser, [], {}, {}, [])
    specs = pm.conformity_specifications("gbt45570", camp)
    by = {s.symbol: s for s in specs}
    bs = by["Bs_100s"]  # row 10 judges t = 100 s of D.5.2.2 (interpretations.md, issue 29)
    assert bs.limit == Q_(0.007, "deg/h") and "table A.1" in bs.source and "aviation" in bs.source
    assert by["B0"].bounds == (-1, 1)
    assert pm.conformity_specifications("jjf2014", camp) == []
    fibre = Campaign("c", DeviceUnderTest("F", technology="fibre", application="船舶"), [], {}, {},
                     [])
    by = {s.symbol: s for s in pm.conformity_specifications("gbt45570", fibre)}
    assert by["Kn"].limit == Q_(10, "ppm") and "table B.1" in by["Kn"].source
    assert by["K"].limit == Q_(5000, "LSB/(deg/s)")
    unknown = Campaign("c", DeviceUnderTest("U", technology="laser", application=""), [], {}, {},
                       [])
    # with no application no table applies, but 5.2.9 (positive polarity) holds for every gyro
    assert [s.symbol for s in pm.conformity_specifications("gbt45570",
                                                           unknown)] == ["polarity_ratio"]


def test_tables_hold_the_published_numbers():
    from metro.plugins.gbt45570.conformity import TABLE_A1, TABLE_B1, TABLE_C1

    a = {r.no: r for r in TABLE_A1}
    b = {r.no: r for r in TABLE_B1}
    assert len(a) == len(b) == len(TABLE_C1) == 16
    assert a[1].limits == {"aerospace": 0.25, "aviation": 0.25,
                           "marine": 0.50} and a[1].comparison is Comparison.AT_LEAST
    assert a[14].limits["marine"] == 0.0006 and b[14].limits["aviation"] == 0.0015
    assert a[7].limits["aerospace"] == 400 and b[7].limits == {"aerospace": 30, "aviation": 200,
                                                               "marine": 30}
    assert b[5].limits == {"aerospace": 5, "aviation": 3, "marine": 0.2}
    assert b[16].limits["marine"] == 50 and a[16].limits["marine"] == 8
    assert a[9].limits["aviation"] == (-1, 1)
    c = {r.no: r for r in TABLE_C1}
    assert c[1].severity["aviation"] == Q_(-55, "degC") and c[1].items == ("D.6.1",)
    assert c[6].severity["marine"] is None and c[11].items == ()


def test_every_table_row_maps_to_a_registered_metric_or_says_it_is_pending(pm):
    """A row whose item is registered must map to a metric that item declares (row_mapping raises
    otherwise); a row whose items no loaded plugin registers is marked NOT AVAILABLE, not
    skipped."""
    from metro.plugins.gbt45570.conformity import TABLE_A1, TABLE_B1, TABLE_C1, row_mapping

    for rows in (TABLE_A1, TABLE_B1, TABLE_C1):
        for m in row_mapping(pm, rows):
            assert m.registered or m.missing or not m.row.items
            if m.registered:
                assert m.status.startswith("implemented")
            elif m.row.items:
                assert m.status.startswith("NOT AVAILABLE") and all(i in m.status for i
                                                                    in m.missing)
    # every A.1/B.1 row and every C.1 severity reported as a metric is implemented by now
    for rows in (TABLE_A1, TABLE_B1):
        assert all(m.registered for m in row_mapping(pm, rows)), [m.status for m
                                                                  in row_mapping(pm, rows)]
    assert all(m.registered for m in row_mapping(pm, TABLE_C1) if m.row.key)
    keys = {r.no: r.key for r in TABLE_A1}
    assert keys[6] == "gamma" and keys[7] == "Omega_max" and keys[8] == "threshold" and keys[
        15] == "setup_time"


def test_method_rule_6271():
    from metro.plugins.gbt45570.method_rule import method_for

    assert method_for(DeviceUnderTest("L", technology="laser"))[0] == "angle"
    low = DeviceUnderTest("F", technology="fibre", properties={"nonlinearity": Q_(3, "ppm")})
    assert method_for(low) == ("angle", method_for(low)[1]) and "≤ 5×10⁻⁶" in method_for(low)[1]
    edge = DeviceUnderTest("F", technology="fibre", properties={"nonlinearity": Q_(5e-6, "")})
    assert method_for(edge)[0] == "angle"  # "不大于 5×10⁻⁶": 5×10⁻⁶ itself takes the angle method
    high = DeviceUnderTest("F", technology="fibre", properties={"nonlinearity": Q_(20, "ppm")})
    assert method_for(high)[0] == "rate"
    by_table = method_for(DeviceUnderTest("F", technology="fibre", application="marine"))
    assert by_table[0] == "rate" and "table B.1" in by_table[1]
    assert method_for(DeviceUnderTest("F", technology="fibre"))[0] == "rate"
    with pytest.raises(UnitError):
        method_for(DeviceUnderTest("F", technology="fibre",
                                   properties={"nonlinearity": Q_(3, "deg")}))


def test_applicability_hook_and_series(pm):
    from metro.core.run.runner import select_items

    laser = DeviceUnderTest("L", technology="laser", application="aviation")
    fibre = DeviceUnderTest("F", technology="fibre", application="aviation")
    d11 = pm.procedure("gbt45570", "D.1.1")
    assert pm.item_applicability(d11, laser).applies
    a = pm.item_applicability(d11, fibre)
    assert not a.applies and "rate method" in a.reason
    # not GB/T: default
    assert pm.item_applicability(pm.procedure("jjf2014", "7.2.1"), fibre).applies
    items, choices = select_items(pm, "gbt45570", ["scale-factor"], device=laser)
    assert items[:3] == ["D.1.1", "D.1.2", "D.1.3"]
    assert not any(i.startswith("D.2.") for i in items)
    why = {c.item: c for c in choices}
    assert why["D.1.1"].via == "series scale-factor" and "laser" in why["D.1.1"].reason
    assert not why["D.2.1"].run
    both, _ = select_items(pm, "gbt45570", ["scale-factor", "D.2.1"], device=laser)
    # an item named explicitly runs whatever the rule says
    assert "D.2.1" in both and "D.1.1" in both
    all_items, _ = select_items(pm, "gbt45570", [], run_all=True, device=laser)
    assert {"D.1.1", "D.5.1", "D.5.6"} <= set(all_items)
    from metro.core.base.errors import PluginError

    with pytest.raises(PluginError, match="no item 'D.9'"):
        select_items(pm, "gbt45570", ["D.9"], device=laser)


def test_manifest_specification_table(tmp_path):
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    src = (__import__("pathlib").Path(__file__).parents[3] / "docs" / "examples" / "campaign")
    text = (src / "manifest.toml").read_text(encoding="utf-8")
    (tmp_path / "static-1h.csv").write_bytes((src / "static-1h.csv").read_bytes())
    text += (
        '\n[specification]\nsource = "ACME OG-1 product specification"\ndecision_rule = '
        '"simple"\nB0 = "± 5 deg/h"\n'
    )
    (tmp_path / "manifest.toml").write_text(text, encoding="utf-8")
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "gbt45570", ["D.5.1"], data=tmp_path / "manifest.toml")
    a = rec.conformity
    assert a.rule is SIMPLE
    (v,) = [v for v in a.verdicts if v.key == "B0"]
    assert v.spec.source == "ACME OG-1 product specification" and v.spec.bounds == (-5, 5)
    bad = text.replace('B0 = "± 5 deg/h"', 'B0 = "<= 5 furlongs"')
    (tmp_path / "manifest.toml").write_text(bad, encoding="utf-8")
    with pytest.raises(DataError, match="specification.B0"):
        run_items(pm, "gbt45570", ["D.5.1"], data=tmp_path / "manifest.toml")


def test_items_on_two_stations_are_acquired_separately_and_merged():
    """Without --data each station the items need acquires its own campaign; campaigns of the same
    device are merged into one report, different devices are a clear error."""
    from metro.core.base.errors import ProcedureError
    from metro.core.run.plugin_manager import ProcedureInfo, StationInfo, get_plugin_manager
    from metro.core.run.runner import run_items
    from metro.instruments.simulated import SimulatedStation, station_factory

    pm = get_plugin_manager(autoload=False)

    class OtherBench(pm.procedure("gbt45570", "D.5.2")):
        station = "simulated-b"
        item = "X.2"

    pm.registry.procedures["gbt45570:X.2"] = ProcedureInfo(OtherBench, "test")
    pm.registry.stations["simulated-b"] = StationInfo("simulated-b", station_factory,
                                                      "a second bench", "test")
    rec = run_items(pm, "gbt45570", ["D.5.1", "X.2"], station_options={"duration_scale": 0.2})
    assert [o.item for o in rec.outcomes] == ["D.5.1", "X.2"]
    assert "simulated-b" in rec.campaign.source and rec.campaign.id == "SIMULATED+SIMULATED"

    class OtherDevice(SimulatedStation):
        def device(self):
            import attrs

            return attrs.evolve(super().device(), id="SIM-OTHER")

    pm.registry.stations["simulated-b"] = StationInfo("simulated-b",
                                                      lambda **kw: OtherDevice(duration_scale=0.2),
                                                      "another device", "test")
    with pytest.raises(ProcedureError, match="simulate different devices"):
        run_items(pm, "gbt45570", ["D.5.1", "X.2"], station_options={"duration_scale": 0.2})


def test_all_on_recorded_data_runs_the_items_the_campaign_has_data_for():
    from pathlib import Path

    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    manifest = Path(__file__).parents[3] / "docs" / "examples" / "campaign" / "manifest.toml"
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "gbt45570", ["bias"], data=manifest)
    assert [o.item for o in rec.outcomes] == ["D.5.1", "D.5.2"]
    why = {c.item: c for c in rec.selection}
    assert not why["D.5.3"].run and "no data" in why["D.5.3"].reason and "'static-repeat'" in why[
        "D.5.3"].reason
    assert why["D.5.1"].via == "series bias"
    keys = {v.key for v in rec.conformity.verdicts}
    # A.1, aviation (the example's device); t = 100 s
    assert keys >= {"B0", "Bs_100s"} and "Bs_10s" not in keys


def test_a_procedure_decides_its_own_applicability_when_no_plugin_answers():
    from metro.core.model.procedure import Applicability
    from metro.core.run.plugin_manager import ProcedureInfo, get_plugin_manager
    from metro.core.run.runner import select_items

    pm = get_plugin_manager(autoload=False)

    class MemsOnly(pm.procedure("jjf2014", "7.2.1")):
        item = "X.9"

        @classmethod
        def applies_to(cls, device):
            ok = device is not None and device.technology == "mems"
            return Applicability(ok, "for MEMS gyros only" if not ok else "a MEMS gyro")

    pm.registry.procedures["jjf2014:X.9"] = ProcedureInfo(MemsOnly, "test")
    items, choices = select_items(pm, "jjf2014", [], run_all=True,
                                  device=DeviceUnderTest("V", technology="vibratory"))
    assert "X.9" not in items and "7.2.1" in items
    assert {c.item: c.reason for c in choices}["X.9"] == "for MEMS gyros only"
    items, _ = select_items(pm, "jjf2014", ["X.9"],
                            device=DeviceUnderTest("V", technology="vibratory"))
    assert items == ["X.9"]  # named explicitly: it runs


@pytest.mark.parametrize("text, lo, hi", [("-0.5 .. 0.5 °/h", -0.5, 0.5),
                                          ("0.1 .. 0.25 °/h", 0.1, 0.25),
                                           ("0.1 °/h .. 0.2 °/h", 0.1, 0.2),
                                          ("-1 .. 1 °/h", -1, 1)])
def test_a_range_with_decimal_limits_is_read(text, lo, hi):
    """docs/data-format.md's own example "-0.5 .. 0.5 °/h" was refused: the low end could not
    hold a decimal point."""
    from metro.core.uncertainty import conformity as cf

    (sp,) = cf.specifications_from_table({"B0": text}, file="manifest.toml")
    assert sp.limit.to("deg/h").magnitude == pytest.approx(lo) and sp.upper.to(
        "deg/h").magnitude == pytest.approx(hi)

"""Validation cases (metro.core.validation): the case model and its verdicts, metro's own cases on
their shipped reference data, the JCGM 101 examples, the within-U runs, the cases a third-party
plugin contributes through ``metro_validation_cases``, and a broken formula named."""

from __future__ import annotations

import importlib.util
import math
from pathlib import Path

import numpy as np
import pytest

from metro.core.base.errors import PluginError
from metro.core.run.plugin_manager import MetroPluginManager
from metro.core.validation import suite
from metro.core.validation.case import Figures, ValidationCase, agrees

ROOT = Path(__file__).resolve().parents[3]


def _sample(name: str):
    path = ROOT / "tests" / "data" / "plugins" / f"{name}.py"
    spec = importlib.util.spec_from_file_location(f"metro_test_plugins.{name}", path)
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


def _pm(*extra):
    pm = MetroPluginManager().load(autoload=False)
    for name in extra:
        pm.add_plugin(_sample(name), name)
    pm.register_all()
    return pm


# ------------------------------------------------------------------------------ the case model


def test_a_case_passes_fails_or_errs_and_says_why():
    ok = ValidationCase("t:ok", "one", "a book", [1.0, "0.30"], lambda: [1.0 + 1e-13, "0.30"],
                        rtol=1e-12, labels=("x", "U"))
    assert ok.verdict is None and ok.computed is None
    done = ok.run()
    assert done.verdict == "pass" and done.passed and done.computed == (1.0 + 1e-13, "0.30")
    # text is compared digit for digit: "0.3" is not the printed "0.30"
    bad = ValidationCase("t:bad", "two", "a book", [1.0, "0.30"], lambda: [1.0, "0.3"],
                         rtol=1e-12, labels=("x", "U")).run()
    assert bad.verdict == "fail" and bad.detail == "U: '0.3' ≠ '0.30'"
    err = ValidationCase("t:err", "three", "a book", [1.0], lambda: 1 / 0).run()
    assert err.verdict == "error" and err.detail.startswith("ZeroDivisionError")
    short = ValidationCase("t:short", "four", "a book", [1.0, 2.0], lambda: [1.0]).run()
    assert short.verdict == "error" and "1 values for 2" in short.detail
    assert not agrees(math.nan, math.nan, 1.0, 1.0) and agrees(1.0, 1.1, 0.0, 0.1 + 1e-15)


def test_figures_bring_their_references_and_per_value_tolerances():
    case = ValidationCase("t:fig", "figures", "JCGM 101", (),
                          lambda: Figures([2.004, 3.9], [2.0, 3.92], [0.01, 0.015], ["u", "hi"]))
    done = case.run()
    assert done.reference == (2.0, 3.92) and done.labels == ("u", "hi")
    assert done.verdict == "fail" and done.detail.startswith("hi: 3.9 ≠ 3.92")
    assert done.tolerance == "±(0.01, 0.015) absolute, per value"


# ------------------------------------------------------------------------------ metro's own cases


def test_reference_data_ship_with_their_sources():
    from metro.core.validation import reference

    for name in ("Norris.dat", "Pontius.dat", "allan_nbs14.json"):
        assert reference.data_path(name).is_file(), name
    # the shipped Norris.dat is NIST's file as the tests' copy holds it
    assert reference.data_path("Norris.dat").read_bytes() == (
        ROOT / "tests" / "data" / "nist" / "Norris.dat").read_bytes()
    cert, x, y = reference.read_norris()
    assert x.size == 36 and cert["B1"] == 1.00211681802045
    for case in [*reference.nist_cases(), *reference.allan_cases(), *reference.unit_cases()]:
        assert case.source and case.reference, case.id
        assert case.run().verdict == "pass", (case.id, case.run().detail)


def test_the_nbs14_long_series_starts_at_the_seed():
    from metro.core.validation.reference import nbs14_long_series

    y = nbs14_long_series()
    assert y.size == 1000 and y[0] == 1234567890 / 2147483647
    assert y[1] == (16807 * 1234567890) % 2147483647 / 2147483647


def test_jcgm101_examples_pass_within_their_numerical_tolerance():
    from metro.core.validation.jcgm101 import jcgm101_cases

    cases = [c.run() for c in jcgm101_cases()]
    assert len(cases) == 6 and all(c.verdict == "pass" for c in cases), [c.detail for c in cases]
    mass = next(c for c in cases if c.id == "jcgm101:9.3-mass")
    assert 0.0754 in mass.reference and mass.unit == "mg"


def test_within_u_runs_name_every_device_class_of_the_simulated_stations():
    from metro.core.validation.coverage import CLASS_RUNS
    from metro.instruments import angle_instrument, gyro_truth, mimu, vibratory

    declared = {std: set(classes) for std, _, _, _, classes in CLASS_RUNS}
    assert declared == {"gbt45570": set(gyro_truth.DEVICE_CLASSES),
                        "jjf2014": set(vibratory.DEVICE_CLASSES),
                        "jjf2003": set(mimu.DEVICE_CLASSES),
                        "ogam": set(angle_instrument.DEVICE_CLASSES)}


def test_a_within_u_run_counts_results_outside_u():
    from metro.core.validation.coverage import covered_fraction

    pm = _pm()
    good = covered_fraction(pm, "ogam", ["7.1"], "simulated-ogam", {"device_class": "rlg-fine"},
                            [1, 2])
    assert good == 1.0
    # by hand: 1.02 ± 0.01 misses the truth 1; 1.005 ± 0.01 covers it; a result declared not
    # reportable counts as covered; one without U and reportable is left out
    from types import SimpleNamespace as NS

    from metro.core.base.units import Q_
    from metro.core.validation.coverage import covered

    def result(key, value, U, reportable=True):
        return NS(metric=NS(key=key), value=Q_(value, "deg"), U=None if U is None else Q_(U, "deg"),
                  reportable=reportable)

    rec = NS(campaign=NS(expected={"a": Q_(1.0, "deg"), "b": Q_(1.0, "deg"), "c": Q_(1, "deg"),
                                   "d": Q_(1, "deg")}),
             outcomes=[NS(results=[result("a", 1.02, 0.01), result("b", 1.005, 0.01),
                                   result("c", 9.0, None, False), result("d", 1.0, None),
                                   result("e", 5.0, 0.1)])])
    assert covered(rec) == [False, True, True]


# ------------------------------------------------------------------------------ collecting


def test_a_third_party_plugin_case_runs_and_reports_as_metro_own(monkeypatch, tmp_path):
    monkeypatch.setattr(suite, "core_cases", lambda pm, quick=False: [])
    pm = _pm("sample_vendor")
    run = suite.validate(pm, quick=True)
    vendor = [c for c in run.cases if c.plugin == "sample_vendor"]
    assert [c.id for c in vendor] == ["vendorx:tick"]
    assert vendor[0].verdict == "pass" and vendor[0].computed == (0.5, 3.5)
    # its file is hashed with metro's
    paths = [f["path"] for f in run.files]
    assert any("sample_vendor.py" in p for p in paths)
    assert any(p == "metro.core/validation/case.py" for p in paths)
    assert run.environment["libraries"]["numpy"] == np.__version__
    # reported as metro's own: a section under the plugin's name, its source, values and verdict
    import docx

    from metro.core.cli.validate_command import case_json
    from metro.core.validation.report import write_validation_report

    path = write_validation_report(tmp_path / "v.docx", run, number="VAL-T", lang="en")
    d = docx.Document(str(path))
    text = "\n".join([p.text for p in d.paragraphs]
                     + [c.text for t in d.tables for r in t.rows for c in r.cells])
    assert "Plugin sample_vendor" in text.replace("\xa0", " ")
    assert "vendorx:tick" in text and "VX-001 table 1" in text.replace("\xa0", " ")
    doc = case_json(vendor[0])
    assert doc["plugin"] == "sample_vendor" and doc["verdict"] == "pass"
    assert doc["reference"] == [0.5, 3.5] and doc["labels"] == ["1 vtick", "7 vtick"]


def test_two_cases_with_one_id_are_an_error_naming_both(monkeypatch):
    twin = ValidationCase("vendorx:tick", "twin", "nowhere", [1.0], lambda: 1.0, plugin="metro")
    monkeypatch.setattr(suite, "core_cases", lambda pm, quick=False: [twin])
    with pytest.raises(PluginError, match="given twice: by 'metro' and by 'sample_vendor'"):
        suite.collect(_pm("sample_vendor"))


def test_a_broken_formula_fails_validation_and_names_the_case(monkeypatch):
    """The least-squares fit made wrong in its last digits: the NIST cases fail, named, and
    nothing else does."""
    from metro.core.stats import lsq

    real = lsq.fit_line

    def off(x, y, **kw):
        return real(np.asarray(x), np.asarray(y) * (1 + 1e-9), **kw)

    from metro.core.validation.reference import allan_cases, nist_cases

    monkeypatch.setattr(lsq, "fit_line", off)
    cases = [c.run() for c in [*nist_cases(), *allan_cases()]]
    failed = [c.id for c in cases if not c.passed]
    assert failed == ["nist:norris"]
    assert "B0" in next(c for c in cases if c.id == "nist:norris").detail

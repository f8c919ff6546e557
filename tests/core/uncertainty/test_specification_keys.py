"""``[specification]`` limits belong to their standard (issue 30, point 5).

``[specification.<standard>]`` tables and ``"<standard>:<key>"`` lines judge that standard's
results only; a flat line (the old form) is read for the one standard having a metric of its key,
and, where more than one standard has it, applied to the standard being run with a warning
(docs/interpretations.md, "Specification keys by standard").
"""

from __future__ import annotations

from pathlib import Path

import pytest
from metro.core.base.errors import DataError
from metro.core.base.units import Q_
from metro.core.run.manifest import load_manifest
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.runner import run_items
from metro.core.uncertainty.conformity import limits_for, owners_of, split_table

#: a third party's standard keys rate random walk as ``K``, as GB/T 45570 keys its scale factor
KEYS = {"gbt45570": {"K", "Kn", "B0", "B0_low"}, "ieee952": {"K", "N"}, "jjf2003": {"K_gxx"}}
EXAMPLE = Path(__file__).parents[3] / "docs" / "examples" / "campaign"


def test_a_standards_table_judges_that_standard_only():
    table = {"gbt45570": {"K": ">= 0.5 P/″"}, "ieee952": {"K": "<= 0.01 deg/h^1.5"}}
    gbt = limits_for(table, "gbt45570", KEYS, file="m.toml")
    ieee = limits_for(table, "ieee952", KEYS, file="m.toml")
    assert dict(gbt.table) == {"K": ">= 0.5 P/″"} and not gbt.warnings
    assert dict(ieee.table) == {"K": "<= 0.01 deg/h^1.5"} and not ieee.warnings
    (k,) = ieee.specifications("m.toml")
    assert k.limit == Q_(0.01, "deg/h**1.5")
    assert dict(gbt.fields) == {"K": "specification.gbt45570.K"}


def test_a_standard_key_line_is_the_same_as_its_table():
    colon = limits_for({"ieee952:K": "<= 0.01 deg/h^1.5"}, "ieee952", KEYS, file="m.toml")
    assert dict(colon.table) == {"K": "<= 0.01 deg/h^1.5"}
    assert dict(colon.fields) == {"K": "specification.ieee952:K"}
    assert dict(limits_for({"ieee952:K": "<= 1 deg/h^1.5"}, "gbt45570", KEYS).table) == {}
    with pytest.raises(DataError, match="given twice"):
        split_table({"ieee952:K": "<= 1 deg/h^1.5", "ieee952": {"K": "<= 2 deg/h^1.5"}},
                    file="m.toml")


def test_a_flat_key_of_one_standard_is_read_for_it_without_a_warning():
    table = {"Kn": "<= 5 ppm", "N": "<= 0.1 deg/h^0.5", "source": "ACME spec rev. C"}
    gbt = limits_for(table, "gbt45570", KEYS, file="m.toml")
    assert dict(gbt.table) == {"Kn": "<= 5 ppm", "source": "ACME spec rev. C"} and not gbt.warnings
    ieee = limits_for(table, "ieee952", KEYS, file="m.toml")
    assert dict(ieee.table) == {"N": "<= 0.1 deg/h^0.5", "source": "ACME spec rev. C"}
    assert not ieee.warnings


def test_a_flat_key_of_several_standards_is_applied_to_the_one_run_with_a_warning():
    assert owners_of("K", KEYS) == ["gbt45570", "ieee952", "jjf2003"]  # K judges K_gxx too
    lim = limits_for({"K": ">= 0.5 P/″"}, "gbt45570", KEYS, file="m.toml")
    assert dict(lim.table) == {"K": ">= 0.5 P/″"}
    (w,) = lim.warnings
    assert "specification.K" in w and "'K' is a metric of gbt45570, ieee952 and jjf2003" in w
    assert "[specification.gbt45570]" in w and w.startswith("m.toml: ")
    # the standard's own line replaces the flat one: nothing is ambiguous for that standard
    own = limits_for({"K": ">= 0.5 P/″", "ieee952": {"K": "<= 1 deg/h^1.5"}}, "ieee952", KEYS)
    assert dict(own.table) == {"K": "<= 1 deg/h^1.5"} and not own.warnings


def test_a_key_no_standard_has_is_read_as_before_and_an_unknown_standard_is_named():
    lim = limits_for({"Bx": "<= 1 deg/h", "gbt4557": {"K": ">= 1 P/″"}}, "gbt45570", KEYS,
                     file="m.toml")
    assert dict(lim.table) == {"Bx": "<= 1 deg/h"}
    (w,) = lim.warnings
    assert "specification.gbt4557" in w and "did you mean 'gbt45570'" in w


def test_settings_of_a_standards_table_prevail():
    table = {"source": "common", "decision_rule": "guarded",
             "gbt45570": {"source": "GB/T product spec", "decision_rule": "simple",
                          "B0": "± 5 deg/h"}}
    lim = limits_for(table, "gbt45570", KEYS)
    assert dict(lim.table) == {"source": "GB/T product spec", "decision_rule": "simple",
                               "B0": "± 5 deg/h"}
    (b0,) = lim.specifications()
    assert b0.source == "GB/T product spec" and b0.bounds == (-5, 5)


def _manifest(tmp_path: Path, spec: str) -> Path:
    (tmp_path / "static-1h.csv").write_bytes((EXAMPLE / "static-1h.csv").read_bytes())
    text = (EXAMPLE / "manifest.toml").read_text(encoding="utf-8") + "\n" + spec
    (tmp_path / "manifest.toml").write_text(text, encoding="utf-8")
    return tmp_path / "manifest.toml"


@pytest.fixture(scope="module")
def builtin_pm():
    return get_plugin_manager(autoload=False)


def test_a_run_is_judged_by_its_own_standards_lines(tmp_path, builtin_pm):
    path = _manifest(tmp_path, '[specification.gbt45570]\nsource = "ACME OG-1"\nB0 = "± 5 deg/h"\n'
                               '[specification.jjf2014]\nB0 = "<= 1e-9 deg/h"\n')
    camp = load_manifest(path, builtin_pm.reader_for)
    assert dict(camp.specification["jjf2014"]) == {"B0": "<= 1e-9 deg/h"}  # kept as written
    rec = run_items(builtin_pm, "gbt45570", ["D.5.1"], data=path)
    (v,) = [v for v in rec.conformity.verdicts if v.key == "B0"]
    assert v.spec.source == "ACME OG-1" and v.spec.bounds == (-5, 5)  # not JJF 2014's limit
    assert not [w for w in rec.campaign.warnings if "specification" in w]


def test_a_run_warns_of_a_flat_line_several_standards_have(tmp_path, builtin_pm):
    path = _manifest(tmp_path, '[specification]\nB0 = "± 5 deg/h"\n')
    rec = run_items(builtin_pm, "gbt45570", ["D.5.1"], data=path)
    (v,) = [v for v in rec.conformity.verdicts if v.key == "B0"]
    assert v.spec.bounds == (-5, 5)
    (w,) = [w for w in rec.campaign.warnings if "specification.B0" in w]
    assert "'B0' is a metric of gbt45570 and jjf2014" in w and "[specification.gbt45570]" in w


def test_a_limit_of_the_wrong_kind_names_its_standards_field(tmp_path, builtin_pm):
    path = _manifest(tmp_path, '[specification.gbt45570]\nB0 = "<= 5 ppm"\n')
    with pytest.raises(DataError, match=r"specification\.gbt45570\.B0"):
        run_items(builtin_pm, "gbt45570", ["D.5.1"], data=path)
    # another standard's line is not this run's: not checked against gbt45570's B0
    path = _manifest(tmp_path, '[specification.jjf2014]\nK = "<= 5 °/h"\n')
    rec = run_items(builtin_pm, "gbt45570", ["D.5.1"], data=path)
    assert rec.conformity is None or not [v for v in rec.conformity.verdicts if v.key == "K"]


def test_a_manifest_refuses_a_bad_line_of_a_standards_table(tmp_path, builtin_pm):
    read = builtin_pm.reader_for
    with pytest.raises(DataError, match=r"specification\.gbt45570\.B0"):
        load_manifest(_manifest(tmp_path, '[specification.gbt45570]\nB0 = "about 5"\n'), read)
    with pytest.raises(DataError, match=r"specification\.gbt45570\.decision_rule"):
        load_manifest(_manifest(tmp_path, '[specification.gbt45570]\ndecision_rule = "lenient"\n'),
                      read)
    with pytest.raises(DataError, match=r"specification\.jjf2014\.B0"):
        load_manifest(_manifest(tmp_path, '[specification.jjf2014]\nB0 = 5\n'), read)

"""Equipment requirements are enforced (issue 13 item 4): a required role missing, or a
calibration U of a kind of unit the item cannot use, is an error naming the equipment, the role
and what is accepted; an optional role absent is a note row in the budget; an old role
spelling finds its equipment (before, `rate-table` where the item looks for `rate_table` dropped
the rate-table row and U(K) shrank without a word)."""

from __future__ import annotations

import json
import re
import shutil

import pytest


@pytest.fixture(scope="module")
def d21(tmp_path_factory):
    """A D.2.1 campaign acquired on the simulated digital station (short records)."""
    from metro.core.cli.app import main

    root = tmp_path_factory.mktemp("d21")
    assert main(["acquire", "-s", "gbt45570", "-i", "D.2.1", "--station", "simulated-digital",
                 "--station-option", "duration_scale=0.02", "--out", str(root / "c"),
                 "--no-progress"]) == 0
    return root / "c"


def _copy(src, dst, edit):
    shutil.copytree(src, dst)
    m = dst / "manifest.toml"
    m.write_text(edit(m.read_text(encoding="utf-8")), encoding="utf-8")
    return m


def _run_json(run_cli, m, item="D.2.1", *extra):
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", item, "--data", str(m), "--json",
                             "--no-report",
                             "--no-progress", *extra)
    return code, (json.loads(out) if out.strip() else None), err


def _result(doc, key):
    (r,) = [r for r in doc["results"] if r["key"] == key]
    return r


def test_a_required_role_missing_is_an_error_naming_it(tmp_path, d21, run_cli):
    m = _copy(d21, tmp_path / "c", lambda t: t.replace('role = "rate_table"', 'role = "turntable"'))
    out_dir = tmp_path / "out"
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.2.1", "--data", str(m), "--out",
                             str(out_dir),
                             "--no-progress")
    assert code == 2
    assert str(
        m) in err and "'rate_table'" in err and "gbt45570:D.2.1" in err and "Traceback" not in err
    assert not out_dir.exists()


def test_a_misspelt_required_role_is_named_with_did_you_mean(tmp_path, d21, run_cli):
    m = _copy(
        d21, tmp_path / "c", lambda t: t.replace('role = "rate_table"', 'role = "rate_tabel"')
    )
    code, _, err = _run_json(run_cli, m)
    assert code == 2 and "did you mean 'rate_table'" in err and "SIM-" in err


def test_an_old_role_spelling_keeps_its_budget_row(tmp_path, d21, run_cli):
    # evaluated: 0, or 3/4 when the conformity statement is "fails"/"indeterminate" — the simulated
    # gyro's K (≈ 5000 LSB/(°/s)) sits on table B.1's limit ≥ 5000, so its verdict is a draw
    code, ref, err = _run_json(run_cli, d21 / "manifest.toml")
    assert code in (0, 3, 4), err
    m = _copy(
        d21, tmp_path / "c", lambda t: t.replace('role = "rate_table"', 'role = "rate-table"')
    )
    code, doc, err = _run_json(run_cli, m)
    assert code in (0, 3, 4), err
    assert _result(doc, "K")["U"] == _result(ref, "K")["U"]  # the rate-table row is still there
    assert any("rate table" in row["source"].lower() or "rate-table" in row["source"].lower()
               for row in _result(doc, "K")["budget"]["rows"])
    assert any("'rate-table'" in w and "deprecated" in w for w in doc["manifest_warnings"])


@pytest.mark.parametrize("role, U, accepted", [
    ("counter", "2 °C", "relative"),
    ("counter", "1 ns", "relative"),
    ("rate_table", "0.01 °/s", "relative"),
])
def test_a_calibration_u_of_the_wrong_kind_is_an_error(tmp_path, d21, run_cli, role, U, accepted):
    text = (d21 / "manifest.toml").read_text(encoding="utf-8")
    # the U line of the equipment with this role
    block = re.search(rf'role = "{role}".*?\nU = "[^"]*"', text, re.S).group(0)
    m = _copy(d21, tmp_path / "c", lambda t: t.replace(block, re.sub(r'U = "[^"]*"$', f'U = "{U}"',
                                                                     block)))
    code, _, err = _run_json(run_cli, m)
    assert code == 2 and "Traceback" not in err
    assert str(m) in err and role in err and accepted in err and re.search(
        r"equipment\[\d+\]\.calibration\.U", err)


def test_the_counter_u_in_celsius_on_a_recorded_campaign(tmp_path, campaign_factory, run_cli):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.2,
                                        manifest_edit=lambda t: t.replace(
                                            'U = "2e-7"', 'U = "2 °C"'))
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m),
                             "--no-report", "--no-progress")
    assert code == 2
    assert "field 'equipment[1].calibration.U'" in err and "'CNT-1'" in err and "counter" in err


def test_an_optional_role_absent_is_a_note_row(tmp_path, campaign_factory, run_cli):
    def drop_counter(t):
        start = t.index('[[equipment]]\nid = "CNT-1"')
        return t[:start] + t[t.index("[[segments]]"):]

    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.2, manifest_edit=drop_counter)
    code, doc, err = _run_json(run_cli, m, "D.5.1")
    assert code == 0, err
    rows = _result(doc, "B0")["budget"]["rows"]
    (note,) = [r for r in rows if r["source"].startswith("counter: not given")]
    assert note["contribution"] == 0 and "not in this budget" in note["note"]
    # with the counter given, no such row
    m2 = campaign_factory.write_campaign(tmp_path / "c2", hours=0.2)
    code, doc2, err = _run_json(run_cli, m2, "D.5.1")
    assert not [r for r in _result(doc2, "B0")["budget"]["rows"] if "not given" in r["source"]]


def test_the_requirement_reads_required():
    """EquipmentRequirement.required is read: an item marked required refuses the campaign."""
    from metro.core.run.equipment_check import check_equipment
    from metro.core.base.errors import DataError
    from metro.core.model.campaign import Campaign, DeviceUnderTest
    from metro.core.model.procedure import EquipmentRequirement

    class P:
        equipment = (EquipmentRequirement("Rate-Table", "a table", required=True),)

        @staticmethod
        def qualified_id():
            return "x:1"

    camp = Campaign(id="c", device=DeviceUnderTest(id="d"), equipment=[], environment={}, site={},
                    segments=[],
                    source="m.toml")
    with pytest.raises(DataError, match="requires equipment with the role 'rate_table'"):
        check_equipment(camp, P)

    class Q(P):
        equipment = (EquipmentRequirement("rate_table", "a table", required=False),)

    assert [r.role for r in check_equipment(camp, Q)] == ["rate_table"]

"""`metro acquire` and the campaign writer: what a station acquires, written in the documented
format, evaluates to exactly the same results as the in-memory campaign."""

from __future__ import annotations

import tomllib

import numpy as np
import pytest

from metro.core.cli.app import main
from metro.core.base.errors import DataError
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.equipment_check import used_equipment
from metro.core.run.runner import load_campaign, run_items
from metro.core.run import manifest_writer as W


@pytest.fixture(scope="module")
def pm():
    return get_plugin_manager(autoload=False)


def _acquire(pm, standard, items, **station_options):
    procs = [pm.procedure(standard, i) for i in items]
    return load_campaign(pm, procs, [{} for _ in procs], data=None, station_options=station_options)


def _same_results(rec_mem, rec_disk):
    assert [o.item for o in rec_mem.outcomes] == [o.item for o in rec_disk.outcomes]
    n = 0
    for a, b in zip(rec_mem.outcomes, rec_disk.outcomes):
        assert [r.metric.key for r in a.results] == [r.metric.key for r in b.results]
        for ra, rb in zip(a.results, b.results):
            va = np.asarray(ra.value.to(ra.metric.unit).magnitude, dtype=float)
            vb = np.asarray(rb.value.to(ra.metric.unit).magnitude, dtype=float)
            np.testing.assert_allclose(vb, va, rtol=1e-12, atol=0,
                                       err_msg=f"{a.item} {ra.metric.key}")
            if ra.U is not None:
                assert rb.U is not None
                assert float(rb.U.magnitude) == pytest.approx(float(ra.U.magnitude), rel=1e-12)
            n += 1
    assert n > 0


# one or two items of every standard, on every station; short durations keep it fast
CASES = [
    ("gbt45570", ["D.5.1"], {"duration_scale": 0.05}, 10**9),
    ("gbt45570", ["D.1.1"], {}, 10**9),
    ("jjf2014", ["7.2.1"], {"duration_scale": 0.05}, 10**9),
    ("jjf2003", ["7.2.2"], {}, 10**9),
    ("ogam", ["7.1"], {}, 10**9),
    ("gbt45570", ["D.5.1"], {"duration_scale": 0.05}, 100),  # the same record as .npy
]


@pytest.mark.parametrize("standard,items,station_options,npy_rows", CASES,
                         ids=[f"{c[0]}-{'+'.join(c[1])}-{'npy' if c[3] < 1000 else 'csv'}" for c
                              in CASES])
def test_round_trip_gives_the_in_memory_results(pm, tmp_path, standard, items, station_options,
                                                npy_rows):
    camp = _acquire(pm, standard, items, **station_options)
    mem = run_items(pm, standard, items, campaign=camp)
    manifest = W.write_campaign(camp, tmp_path / "c", npy_rows=npy_rows)
    disk = run_items(pm, standard, items, data=manifest)
    _same_results(mem, disk)
    files = {p.suffix for p in manifest.parent.iterdir() if p.name != "manifest.toml"}
    assert files == ({".npy"} if npy_rows < 1000 else {".csv"})
    # data recorded on a simulated station stay marked as simulated (the report's banner)
    assert disk.campaign.simulated and disk.campaign.meta["simulated"] is True


def test_manifest_records_device_equipment_calibration_site_and_conditions(pm, tmp_path):
    camp = _acquire(pm, "jjf2014", ["7.2.1"], duration_scale=0.05)
    manifest = W.write_campaign(camp, tmp_path / "c")
    doc = tomllib.loads(manifest.read_text(encoding="utf-8"))
    assert doc["format"] == "metro-campaign/1"
    assert doc["device"]["id"] == camp.device.id and doc["device"]["output"] == "analog"
    roles = {e["role"]: e for e in doc["equipment"]}
    assert set(roles) == {e.role for e in camp.equipment}
    dmm = roles["dmm"]
    assert dmm["calibration"]["certificate"] and "U" in dmm["calibration"] and dmm["calibration"][
        "k"] == 2.0
    assert doc["site"]["latitude"].endswith("degree")
    assert {"temperature", "humidity"} <= set(doc["environment"])
    seg = doc["segments"][0]
    assert seg["conditions"] and seg["units"]["output"] == "mV"
    # and the loader reads them back as the same objects
    back = run_items(pm, "jjf2014", ["7.2.1"], data=manifest).campaign
    # (a run keeps the equipment its items use: metro.core.run.equipment_check.used_equipment)
    used = used_equipment(camp, [pm.procedure("jjf2014", "7.2.1")]).equipment
    assert len(used) < len(camp.equipment)
    assert [e.calibration for e in back.equipment] == [e.calibration for e in used]
    assert back.device.properties == camp.device.properties


def test_nothing_is_left_when_writing_fails(pm, tmp_path, monkeypatch):
    camp = _acquire(pm, "gbt45570", ["D.1.1"])
    calls = {"n": 0}
    real = W._write_samples

    def flaky(*args):
        calls["n"] += 1
        if calls["n"] == 3:
            raise OSError("disk full (simulated)")
        return real(*args)

    monkeypatch.setattr(W, "_write_samples", flaky)
    # said, not a traceback
    with pytest.raises(DataError, match="cannot write the campaign: disk full"):
        W.write_campaign(camp, tmp_path / "c")
    assert list(tmp_path.iterdir()) == []  # no target, no hidden temporary folder


def test_refuses_a_folder_that_is_not_empty(pm, tmp_path):
    (tmp_path / "c").mkdir()
    (tmp_path / "c" / "old.csv").write_text("x\n")
    camp = _acquire(pm, "ogam", ["7.1"])
    with pytest.raises(DataError, match="not empty"):
        W.write_campaign(camp, tmp_path / "c")
    assert sorted(p.name for p in (tmp_path / "c").iterdir()) == ["old.csv"]
    # an existing empty folder is fine
    (tmp_path / "d").mkdir()
    assert W.write_campaign(camp, tmp_path / "d").is_file()


def test_quantity_text_round_trips():
    from metro.core.base.units import Q_, parse_quantity

    for q in (Q_(20.0, "degC"), Q_(-40, "degC"), Q_(0.5, "delta_degC"), Q_(45.0, "percent"),
              Q_(4e-6, ""),
              Q_(0.8, "P/arcsec"), Q_(5000.0, "LSB/(deg/s)"), Q_(1 / 3, "s"),
              Q_(0.0015, "deg/hour**0.5")):
        back = parse_quantity(W.quantity_text(q))
        assert back.magnitude == q.magnitude and back.units == q.units
    with pytest.raises(DataError):
        W.quantity_text(Q_(float("nan"), "s"))


def test_cli_acquire_then_run(tmp_path, capsys):
    out = tmp_path / "camp"
    rc = main(["--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1", "--out",
               str(out),
               "--station-option", "duration_scale=0.05", "--seed", "7", "--no-progress"])
    assert rc == 0
    manifest = out / "manifest.toml"
    assert capsys.readouterr().out.strip() == str(manifest)
    doc = tomllib.loads(manifest.read_text(encoding="utf-8"))
    assert doc["campaign"]["station"] == "simulated" and doc["device"]["serial"] == "seed 7"
    rc = main(["--no-plugin-autoload", "run", "-s", "gbt45570", "-i", "D.5.1", "--data",
               str(manifest),
               "--no-report", "--json", "--no-progress"])
    assert rc == 0
    import json

    res = json.loads(capsys.readouterr().out)
    assert res["results"][0]["key"] == "B0" and res["simulated"]
    # a second acquire into the same folder is refused with a clear message, exit code 2
    rc = main(["--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1", "--out",
               str(out),
               "--no-progress"])
    assert rc == 2
    assert "not empty" in capsys.readouterr().err


def test_cli_acquire_unknown_item_is_a_clear_error(tmp_path, capsys):
    rc = main(["--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "Z.9", "--out",
               str(tmp_path / "x"),
               "--no-progress"])
    assert rc == 2 and "has no item 'Z.9'" in capsys.readouterr().err
    assert not (tmp_path / "x").exists()

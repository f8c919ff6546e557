"""JJF 2014 certificate: layout registered, appendix-A rows, items not performed marked, page x of
y."""

from __future__ import annotations

import json
import math
import zipfile
from pathlib import Path

import docx
import pytest
from metro.core.run.runner import merge_steps, run_items
from metro.instruments.vibratory import VibratoryStation
from metro.plugins.jjf2014 import certificate as C

ITEMS = ["7.2.1", "7.2.2", "7.2.13", "7.2.20", "7.2.21", "7.2.22"]
OPTS = {"records": 2, "frequencies": 10, "sample_rate": "2000 Hz"}


@pytest.fixture(scope="module")
def record():
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    procs = [pm.procedure("jjf2014", i) for i in ITEMS]
    from metro.core.run.runner import split_options

    per = split_options(procs, OPTS)
    camp = VibratoryStation(duration_scale=0.25).acquire(
        merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)]))
    return pm, run_items(pm, "jjf2014", ITEMS, campaign=camp, options=OPTS)


def test_rows_mark_items_not_performed(record):
    _, rec = record
    rows = C.certificate_rows(rec.outcomes)
    assert [r["no"] for r in rows] == [str(i) for i in range(1, 25)]
    done = {r["no"] for r in rows if r["performed"]}
    assert done == {"1", "2", "3", "14", "21", "22", "23"}
    for r in rows:
        if r["performed"]:
            assert r["U"] not in ("", "—") and r["k"] and r["value"] not in ("", "0")
        else:
            assert r["value"] == "" and r["U"] == ""


def test_certificate_written_with_the_registered_layout(record, tmp_path):
    pm, rec = record
    from metro.core.documents.report import write_report

    tpl = pm.template_for("jjf2014")
    assert tpl.name == "jjf2014-certificate" and tpl.path is None
    out = write_report(tmp_path / "cert.docx", rec, layout=tpl.layout,
                       designations={"jjf2014": "JJF 2014—2022"}, extend=pm.extend_report_context)
    d = docx.Document(out)
    text = "\n".join(p.text for p in d.paragraphs).replace("\u00a0", " ")
    # a bilingual header cell is two lines (Chinese above English): read it as one
    cells = "\n".join(c.text.replace("\n", " ") for t in d.tables for row in t.rows for c
                      in row.cells).replace("\u00a0", " ")
    assert "校准证书" in text
    assert ("本证书的校准结果仅对被校对象有效。" in text
            and "未经实验室书面批准，不得部分复制本证书。" in text)
    assert cells.count("未检测 not performed") == 24 - 7
    assert "标度因数" in cells and "启动时间" in cells and "JJF 2014—2022" in cells
    assert "签发人 Issued by" in cells and "职务 Title" in cells  # 8 n): signature and title
    header = d.sections[0].header.paragraphs[0]._p.xml
    assert rec.report_number in d.sections[0].header.paragraphs[0].text
    assert "PAGE" in header and "NUMPAGES" in header
    with zipfile.ZipFile(out) as z:
        images = [n for n in z.namelist() if n.startswith("word/media/")]
    assert len(images) >= 4  # scale-factor fit, Allan, amplitude ratio, phase
    assert "SIMULATED" in "".join(p.text for p in d.sections[0].header.paragraphs)


def test_cli_runs_an_item_on_the_simulated_station(run_cli, tmp_path):
    code, out, err = run_cli("--no-plugin-autoload", "run", "--standard", "jjf2014", "--item",
                             "7.2.1,7.2.3",
                             "--json", "--out", str(tmp_path))
    assert code == 0, err
    data = json.loads(out)
    assert "jjf2014" in json.dumps(data)
    assert list(tmp_path.glob("*.docx"))


def _write_recorded_campaign(root: Path) -> Path:
    """A recorded campaign on disk: manifest + one CSV per segment (output [mV]), written from
    the simulator with its noise, as a lab's acquisition would write it."""
    import numpy as np
    from metro.instruments.vibratory import VibratoryTruth, simulate_segment

    t = VibratoryTruth(seed=99)
    lines = ['format = "metro-campaign/1"', "", "[campaign]", 'id = "JJF-REC-1"',
             'customer = "ACME Navigation"',
             'lab = "Test lab"', "", "[device]", 'id = "MVG-7"', 'model = "MVG-100"',
             'serial = "7"',
             'output = "analog"', "", "[environment]", 'temperature = "20.5 °C"',
             'humidity = "40 %"', "",
             "[site]", 'latitude = "39.98°"', "",
             "[[equipment]]", 'id = "RT-1"', 'role = "rate-table"', "[equipment.calibration]",
             'certificate = "RT-CAL-1"', 'U = "1e-4"', "k = 2", "",
             "[[equipment]]", 'id = "DMM-1"', 'role = "dmm"', "[equipment.calibration]",
             'certificate = "DMM-CAL-1"', 'U = "6e-5"', "k = 2", ""]
    rng = np.random.default_rng(5)
    segs = [(f"r{sgn * r:+g}", "rate", {"rate": f"{sgn * r:g} °/s"}, 10, 1.0)
            for r in (0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100) for sgn in (1, -1)]
    segs.append(("static", "static", {"orientation": "IRA up"}, 3600, 1.0))
    for sid, kind, cond, n, dt_ in segs:
        cols = simulate_segment(t, kind, cond, n, dt_, 39.98, rng)
        fname = f"{sid}.csv"
        (root / fname).write_text("output [mV]\n"
                                  + "\n".join(f"{v:.6f}" for v in cols["output"][0]) + "\n",
                                  encoding="utf-8")
        lines += ["[[segments]]", f'id = "{sid}"', f'kind = "{kind}"', f'file = "{fname}"',
                  f'sample_interval = "{dt_:g} s"', "[segments.conditions]"]
        lines += [f'{k} = "{v}"' for k, v in cond.items()] + [""]
    (root / "manifest.toml").write_text("\n".join(lines), encoding="utf-8")
    return root / "manifest.toml"


def test_recorded_campaign_from_manifest(run_cli, tmp_path):
    from metro.instruments.vibratory import VibratoryTruth

    man = _write_recorded_campaign(tmp_path)
    code, out, err = run_cli("--no-plugin-autoload", "run", "-s", "jjf2014", "-i", "7.2.1,7.2.13",
                             "--data", str(man),
                             "--json", "--report", str(tmp_path / "cert.docx"))
    assert code == 0, err
    data = json.loads(out)
    assert not data["simulated"]
    res = {r["key"]: r for r in data["results"]}
    t = VibratoryTruth()
    assert abs(res["K"]["value"] - t.K_mV_per_dps) < 0.01
    # K budget: rate table 1e-4/2 and DMM 6e-5/2 of K, plus the fit's repeatability
    assert res["K"]["U"] > 2 * t.K_mV_per_dps * math.hypot(0.5e-4, 3e-5) * 0.999
    d = docx.Document(tmp_path / "cert.docx")
    cells = "\n".join(c.text for tb in d.tables for row in tb.rows for c in row.cells)
    assert "ACME Navigation" in cells and cells.count("未检测 not performed") == 22


def test_recorded_campaign_with_a_bad_unit_writes_nothing(run_cli, tmp_path):
    man = _write_recorded_campaign(tmp_path)
    p = tmp_path / "static.csv"
    p.write_text(p.read_text(encoding="utf-8").replace("output [mV]", "output [deg/h]"),
                 encoding="utf-8")
    code, out, err = run_cli("--no-plugin-autoload", "run", "-s", "jjf2014", "-i", "7.2.13",
                             "--data", str(man),
                             "--report", str(tmp_path / "cert.docx"))
    assert code == 2 and "output" in err
    assert not (tmp_path / "cert.docx").exists()


ALL = [f"7.2.{i}" for i in range(1, 24)]
ACQ_OPTS = ["-o", "records=2", "-o", "frequencies=10", "-o", "sample_rate=2000 Hz", "-o",
            "rates=1, 4, 16, 40, 100"]


@pytest.fixture(scope="module")
def acquired(tmp_path_factory):
    """`metro acquire` of all 23 items on the simulated station → a campaign folder on disk."""
    from metro.core.cli.app import main

    root = tmp_path_factory.mktemp("acq") / "c"
    code = main(["acquire", "-s", "jjf2014", "-i", ",".join(ALL), "--out", str(root), "--seed",
                 "11",
                 "--station-option", "duration_scale=0.25", "--no-progress", *ACQ_OPTS])
    assert code == 0
    return root / "manifest.toml"


def test_acquire_then_one_command_evaluates_the_campaign_and_writes_the_certificate(
    acquired, run_cli, tmp_path):
    """acquire → `metro run --all --data` (recorded data): the same values and U as the in-memory
    run on the same station, all 24 appendix-A rows filled, the five figures, page x of y."""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import split_options

    out = tmp_path / "cert.docx"
    code, stdout, err = run_cli("run", "-s", "jjf2014", "--all", "--data", str(acquired),
                                "--report", str(out),
                                "--no-progress", "--json")
    assert code == 0, err
    disk = {f"{r['key']}@{r['item']}": (r["value"], r["U"]) for r in json.loads(stdout)["results"]}
    assert len(disk) == 29  # 24 rows + F₀ + the four other Allan coefficients
    pm = get_plugin_manager(autoload=False)
    procs = [pm.procedure("jjf2014", i) for i in ALL]
    opts = {"records": 2, "frequencies": 10, "sample_rate": "2000 Hz", "rates": "1, 4, 16, 40, 100"}
    per = split_options(procs, opts)
    st = pm.station("simulated-jjf2014").factory(seed=11, duration_scale=0.25)
    camp = st.acquire(merge_steps([c().sequence(c.option_values(o)) for c, o in zip(procs, per)]))
    mem = run_items(pm, "jjf2014", ALL, campaign=camp)
    for o in mem.outcomes:
        for r in o.results:
            v, U = disk[f"{r.metric.key}@{o.item}"]
            assert v == pytest.approx(r.value.magnitude, rel=1e-6, abs=1e-12), r.metric.key
            assert U == pytest.approx(r.U.magnitude, rel=1e-5), r.metric.key
    d = docx.Document(out)
    cells = "\n".join(c.text for t in d.tables for row in t.rows for c in row.cells)
    assert "not performed" not in cells
    with zipfile.ZipFile(out) as z:
        assert len([n for n in z.namelist() if n.startswith("word/media/")]) >= 5
    header = d.sections[0].header.paragraphs[0]._p.xml
    assert "PAGE" in header and "NUMPAGES" in header


@pytest.mark.parametrize("old,new,field", [('position = "4"', 'position = "five"', "position"),
                                           ('trial = "rate"', 'trial = "warm"', "trial")])
def test_acquired_campaign_with_a_bad_condition_writes_nothing(acquired, run_cli, tmp_path, old,
                                                               new, field):
    import shutil

    root = tmp_path / "c"
    shutil.copytree(acquired.parent, root)
    man = root / "manifest.toml"
    text = man.read_text(encoding="utf-8")
    assert old in text
    man.write_text(text.replace(old, new, 1), encoding="utf-8")
    out = tmp_path / "cert.docx"
    code, _, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1,7.2.11,7.2.23", "--data", str(man),
                           "--report", str(out),
                           "--no-progress")
    # a condition is the manifest's field: the manifest is named, not the samples file (issue 14)
    assert code == 2 and f"conditions.{field}" in err and f"{man}, field" in err
    assert not out.exists()

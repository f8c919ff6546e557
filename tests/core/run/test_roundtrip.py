"""plan → acquire → run, through the CLI entry, for every item on every simulated station.

What acquire writes, run evaluates; what run would refuse, acquire refuses before writing
anything (exit 2, no --out folder).  Which station serves which item is written here from the
stations' devices and the standards, not read back from the code under test:

* GB/T 45570: ``simulated`` is a laser gyro with a pulse output (6.2.7.1: angle method D.1),
  ``simulated-digital`` a fibre gyro with an LSB output and K_n above 5×10⁻⁶ (rate method D.2);
  the other GB/T items (bias, threshold, environment, polarity, set-up time, power, D.3) run on
  both;
* JJF 2014 on ``simulated-jjf2014``, JJF 2003 on ``simulated-mimu``, the angle-instrument draft
  on ``simulated-ogam``; no station serves another standard's items.
"""

from __future__ import annotations

import hashlib
from pathlib import Path

import pytest

from metro.core.cli.app import main
from metro.core.run.plugin_manager import get_plugin_manager

STATIONS = ("simulated", "simulated-digital", "simulated-jjf2014", "simulated-mimu",
            "simulated-ogam")
#: short records where a station takes them and the items still evaluate (a record too short for
#: an item is refused by acquire: see test_too_short_a_record_is_refused_before_writing)
SCALE = {"simulated-jjf2014": 0.2, "simulated": 0.25, "simulated-digital": 0.25}
#: item options that keep the heaviest items short (as tests/plugins/jjf2014/test_items.py runs
#: them)
ITEM_OPTIONS = {("jjf2014", "7.2.21"): ["-o", "records=3", "-o", "sample_rate=2000 Hz"],
                ("jjf2014", "7.2.22"): ["-o", "records=3", "-o", "sample_rate=2000 Hz"]}
#: run's exit codes for "evaluated": conforms or nothing to judge (0), does not conform (3),
#: indeterminate (4)
EVALUATED = (0, 3, 4)
_ANGLE = {"D.1.1", "D.1.2", "D.1.3", "D.1.4", "D.1.5", "D.1.6"}
_RATE = {"D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.5", "D.2.6"}


def accepting(standard: str, item: str) -> set[str]:
    if standard == "gbt45570":
        if item in _ANGLE:
            return {"simulated"}
        if item in _RATE:
            return {"simulated-digital"}
        return {"simulated", "simulated-digital"}
    return {"jjf2014": {"simulated-jjf2014"}, "jjf2003": {"simulated-mimu"},
            "ogam": {"simulated-ogam"}}[standard]


def _items():
    pm = get_plugin_manager(autoload=False)
    return sorted((p.cls.standard, p.cls.item) for p in pm.registry.procedures.values()
                  if p.cls.standard in ("gbt45570", "jjf2014", "jjf2003", "ogam"))


ITEMS = _items()


#: items whose records must keep their full length (a settled part of 60 s, 10 batches of a supply)
FULL_LENGTH = {("gbt45570", "6.2.7.7"), ("gbt45570", "6.2.7.8")}


def _acquire_argv(standard, items, station, out, *extra):
    argv = ["acquire", "-s", standard, "-i", items, "--station", station, "--out", str(out),
            "--seed", "11",
            "--no-progress", *extra]
    if station in SCALE and (standard, items) not in FULL_LENGTH:
        argv += ["--station-option", f"duration_scale={SCALE[station]}"]
    return argv


@pytest.mark.parametrize("standard,item", ITEMS, ids=[f"{s}-{i}" for s, i in ITEMS])
def test_round_trip_on_every_station(standard, item, tmp_path, capsys):
    assert main(["plan", "-s", standard, "-i", item, "--json"]) == 0
    fits = accepting(standard, item)
    for station in STATIONS:
        out = tmp_path / station
        capsys.readouterr()
        opts = ITEM_OPTIONS.get((standard, item), [])
        rc = main(_acquire_argv(standard, item, station, out, *opts))
        err = capsys.readouterr().err
        if station in fits:
            assert rc == 0, f"{item} on {station}: {err}"
            rc = main(["run", "-s", standard, "-i", item, "--data", str(out / "manifest.toml"),
                       "--no-report",
                       "--json", "--no-progress", *opts])
            err = capsys.readouterr().err
            assert rc in EVALUATED, (
                f"{item} acquired on {station} but run refused it: rc {rc} {err}")
        else:
            assert rc == 2, f"{item} on {station} should be refused: rc {rc} {err}"
            assert not out.exists(), f"{item} on {station}: refused but wrote {out}"
            assert "metro: error:" in err and "Traceback" not in err
            assert station in err  # the refusal names the station it is about


def test_refusal_names_the_station_that_fits(tmp_path, capsys):
    # issue 14: D.2.1 on the laser gyro wrote 30 CSVs run could never evaluate
    assert main(_acquire_argv("gbt45570", "D.2.1", "simulated", tmp_path / "c")) == 2
    err = capsys.readouterr().err
    assert not (tmp_path / "c").exists()
    assert "6.2.7.1" in err and "simulated-digital" in err
    assert main(_acquire_argv("gbt45570", "D.1.1", "simulated-digital", tmp_path / "c")) == 2
    err = capsys.readouterr().err
    assert "stations that fit gbt45570:D.1.1: simulated " in err


def test_angle_and_rate_items_together_keep_every_record(tmp_path, capsys):
    """`-i D.1.1,D.3 -o method=rate`-like merges gave two `rate+1` segments whose files overwrote
    each other; merged ids are now distinct and every manifest entry has its own file."""
    from metro.core.run.runner import merge_steps

    pm = get_plugin_manager(autoload=False)
    seqs = [pm.procedure("gbt45570", i)().sequence(pm.procedure("gbt45570", i).option_values({}))
            for i in ("D.1.1", "D.2.1")]
    steps = merge_steps(seqs)
    assert len({s.segment for s in steps}) == len(steps) == len(seqs[0]) + len(seqs[1])
    assert {"rate+1@rate-revolutions", "rate+1@rate-output"} <= {s.segment for s in steps}
    # the same ids whatever the order
    assert {s.segment for s in merge_steps(seqs[::-1])} == {s.segment for s in steps}
    # all GB/T items on the digital station: one file per segment, run evaluates them
    out = tmp_path / "all"
    assert main(_acquire_argv("gbt45570", "D.2.1,D.3,D.5.1", "simulated-digital", out)) == 0
    import tomllib

    doc = tomllib.loads((out / "manifest.toml").read_text(encoding="utf-8"))
    files = [s["file"] for s in doc["segments"]]
    assert len(files) == len(set(files)) == len([p for p in out.iterdir() if p.name
                                                 != "manifest.toml"])


def test_writer_refuses_two_segments_with_one_id(tmp_path):
    import attrs

    from metro.core.base.errors import DataError
    from metro.core.run.runner import load_campaign
    from metro.core.run.manifest_writer import write_campaign

    pm = get_plugin_manager(autoload=False)
    camp = load_campaign(pm, [pm.procedure("gbt45570", "D.2.1")], [{}], data=None,
                         station="simulated-digital",
                         station_options={"duration_scale": 0.05})
    segs = list(camp.segments)
    twin = attrs.evolve(segs[1], id=segs[0].id)
    with pytest.raises(DataError, match="two segments have the id"):
        write_campaign(attrs.evolve(camp, segments=[segs[0], twin]), tmp_path / "c")
    assert not (tmp_path / "c").exists() and not list(tmp_path.iterdir())


def _digests(folder: Path) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir() if p.name
            != "manifest.toml"}


@pytest.mark.parametrize("standard,items,station", [
    ("gbt45570", ["D.5.1", "D.2.1"], "simulated-digital"),
    ("gbt45570", ["D.5.3", "D.1.1"], "simulated"),
    ("jjf2014", ["7.2.13", "7.2.1"], "simulated-jjf2014"),
    ("jjf2003", ["7.2.2", "7.2.1"], "simulated-mimu"),
    ("ogam", ["7.3", "7.1"], "simulated-ogam"),
], ids=lambda v: ",".join(v) if isinstance(v, list) else None)
def test_same_seed_same_data_whatever_the_order(standard, items, station, tmp_path):
    a, b = ",".join(items), ",".join(reversed(items))  # the same items, the other way round
    assert main(_acquire_argv(standard, a, station, tmp_path / "a")) == 0
    assert main(_acquire_argv(standard, b, station, tmp_path / "b")) == 0
    da, db = _digests(tmp_path / "a"), _digests(tmp_path / "b")
    assert da == db and len(da) > 1
    # and a segment's data do not depend on the other items acquired with it
    single = standard == "gbt45570" and "D.5.1" in a
    if single:
        assert main(_acquire_argv(standard, "D.5.1", station, tmp_path / "c")) == 0
        dc = _digests(tmp_path / "c")
        assert dc and all(da[k] == v for k, v in dc.items())


def test_acquire_all_and_series_select_as_run_does(tmp_path, capsys):
    out = tmp_path / "all"
    assert main(_acquire_argv("gbt45570", "scale-factor", "simulated-digital", out)) == 0
    capsys.readouterr()
    assert main(["run", "-s", "gbt45570", "-i", "scale-factor", "--data",
                 str(out / "manifest.toml"), "--no-report",
                 "--json", "--no-progress"]) in EVALUATED
    import json

    doc = json.loads(capsys.readouterr().out)
    ran = sorted(o["item"] for o in doc["items"])
    assert ran == ["D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.5"]
    out2 = tmp_path / "all2"
    assert main(["acquire", "-s", "gbt45570", "--all", "--station", "simulated-digital", "--out",
                 str(out2),
                 "--no-progress", "--seed", "3"]) == 0
    capsys.readouterr()
    assert main(["run", "-s", "gbt45570", "--all", "--data", str(out2 / "manifest.toml"),
                 "--no-report", "--json",
                 "--no-progress"]) in EVALUATED
    doc = json.loads(capsys.readouterr().out)
    ran = {o["item"] for o in doc["items"]}
    # the rate-method campaign has no whole revolutions: D.3 is selected through its alternative
    assert "D.3" in ran and _RATE <= ran and not (ran & _ANGLE)


def test_alternative_requirements_are_alternatives():
    from metro.core.run.runner import requirement_groups, select_items, unmet_requirements

    pm = get_plugin_manager(autoload=False)
    d3 = pm.procedure("gbt45570", "D.3")
    groups = requirement_groups(d3)
    assert len(groups) == 1 and {r.kind for r in groups[0]} == {"rate-output", "rate-revolutions"}
    from metro.core.run.runner import load_campaign

    camp = load_campaign(pm, [d3], [{"method": "rate"}], data=None, station="simulated-digital",
                         station_options={"duration_scale": 0.05})
    assert not camp.find_segments("rate-revolutions")
    assert unmet_requirements(d3, camp.segments) == []
    items, _ = select_items(pm, "gbt45570", [], run_all=True, campaign=camp)
    assert "D.3" in items


@pytest.mark.parametrize("station", STATIONS)
def test_stations_refuse_step_kinds_they_cannot_simulate(station):
    from metro.core.model.procedure import Step
    from metro.core.base.units import Q_
    from metro.instruments.stations import StationError

    pm = get_plugin_manager(autoload=False)
    st = pm.station(station).factory()
    step = Step("x", "warp-drive", "a kind no station knows", Q_(10, "s"), Q_(1, "s"))
    with pytest.raises(StationError,
                       match=f"station '{station}' cannot simulate steps of kind 'warp-drive'"):
        st.acquire([step])


def test_digital_and_rate_gyros_give_no_revolution_counts():
    from metro.core.model.procedure import Step
    from metro.core.base.units import Q_
    from metro.instruments.stations import StationError

    pm = get_plugin_manager(autoload=False)
    step = Step("rate+1", "rate-revolutions", "turns", Q_(10, "s"), Q_(1, "s"),
                {"rate": "1 deg/s", "turns": 2})
    for name, opts in (("simulated-digital", {}), ("simulated", {"output": "rate"})):
        with pytest.raises(StationError, match="only a pulse output gives"):
            pm.station(name).factory(**opts).acquire([step])
    seg = pm.station("simulated").factory().acquire([step]).segments[0]
    assert seg.columns()["count"][1] == "P"


def test_fibre_pulse_gyro_on_the_angle_method_is_judged_without_a_unit_clash():
    """6.2.7.1 sends a fibre gyro with K_n ≤ 5×10⁻⁶ to the angle method; its K is then in P/″, and
    table B.1's K limit (LSB/[(°)/s]) does not apply to it — the run completes and says so."""
    import attrs

    from metro.core.run.runner import load_campaign, run_items
    from metro.core.base.units import Q_

    pm = get_plugin_manager(autoload=False)
    d11 = pm.procedure("gbt45570", "D.1.1")
    camp = load_campaign(pm, [d11], [{}], data=None, station="simulated")
    dev = attrs.evolve(camp.device, technology="fibre",
                       properties=dict(camp.device.properties) | {"nonlinearity": Q_(3e-6, "")})
    rec = run_items(pm, "gbt45570", ["D.1.1"], campaign=attrs.evolve(camp, device=dev))
    assert rec.outcomes[0].result("K").value.units == Q_(1, "P/arcsec").units
    k_specs = [s for s in rec.conformity.not_assessed if s.symbol == "K"]
    assert k_specs and "D.2.1 only" in k_specs[0].source


def _run_json(capsys, manifest, items="D.2.1"):
    import json

    capsys.readouterr()
    assert main(["run", "-s", "gbt45570", "-i", items, "--data", str(manifest), "--no-report",
                 "--json",
                 "--no-progress"]) in EVALUATED
    return json.loads(capsys.readouterr().out)


def _result(doc, key):
    return next(r for r in doc["results"] if r["key"] == key)


def test_d2_takes_an_output_in_deg_per_s_and_in_hz(tmp_path, capsys):
    """D.2 takes a digital output in LSB, a frequency in Hz (D.23 names it) and a digital rate
    in °/s; K is then in LSB/[(°)/s], Hz/[(°)/s] or a ratio."""
    # °/s: the virtual fibre gyro with a digital rate output; its K is 1 within its scale-factor
    # errors (sf_slope·Ω + sf_quadratic·(Ω/400)² ≤ 4×10⁻⁵ at 400 °/s, fitted over ±400 °/s)
    out = tmp_path / "ds"
    assert main(["acquire", "-s", "gbt45570", "-i", "D.2.1,D.2.2", "--station", "simulated-digital",
                 "--station-option", "output=rate", "--station-option", "rate_unit=deg/s",
                 "--station-option",
                 "duration_scale=0.1", "--seed", "5", "--out", str(out), "--no-progress"]) == 0
    doc = _run_json(capsys, out / "manifest.toml", "D.2.1,D.2.2")
    k = _result(doc, "K")
    assert k["unit"] == "1" and abs(k["value"] - 1.0) < 1e-4 and 0 < k["U"] < 1e-4
    assert _result(doc, "F0")["unit"] == "°/s"
    # Hz: an LSB campaign whose output is declared a frequency gives the same number in Hz/(°/s)
    lsb = tmp_path / "lsb"
    assert main(_acquire_argv("gbt45570", "D.2.1", "simulated-digital", lsb)) == 0
    k_lsb = _result(_run_json(capsys, lsb / "manifest.toml"), "K")
    for p in lsb.iterdir():
        text = p.read_text(encoding="utf-8")
        if p.suffix == ".csv":
            p.write_text(text.replace("output [LSB]", "output [Hz]"), encoding="utf-8")
        else:
            p.write_text(text.replace('output = "LSB"', 'output = "Hz"'), encoding="utf-8")
    k_hz = _result(_run_json(capsys, lsb / "manifest.toml"), "K")
    assert k_lsb["unit"] == "LSB·s/°" and k_hz["unit"] == "Hz·s/°"
    assert k_hz["value"] == pytest.approx(k_lsb["value"], rel=1e-12)


def test_too_short_a_record_is_refused_before_writing(tmp_path, capsys):
    """6.2.7.7 needs a settled part of 60 s after the switch-on: a quarter-length record cannot
    give it, and acquire says so instead of writing what run would refuse."""
    out = tmp_path / "c"
    assert main(["acquire", "-s", "gbt45570", "-i", "6.2.7.7", "--station", "simulated",
                 "--station-option",
                 "duration_scale=0.25", "--out", str(out), "--no-progress"]) == 2
    err = capsys.readouterr().err
    assert "would not evaluate" in err and "too short" in err and not out.exists()


def test_a_series_without_a_station_is_acquired_where_run_would_simulate_it(tmp_path):
    """`run -i scale-factor` without --data simulates the standard's default station; acquire does
    the same and takes the members the 6.2.7.1 rule gives for its laser gyro (D.1.1–D.1.5)."""
    import tomllib

    out = tmp_path / "c"
    assert main(["acquire", "-s", "gbt45570", "-i", "scale-factor", "--out", str(out),
                 "--no-progress",
                 "--station-option", "duration_scale=0.25"]) == 0
    camp = tomllib.loads((out / "manifest.toml").read_text(encoding="utf-8"))["campaign"]
    assert camp["station"] == "simulated" and camp["items"] == "D.1.1,D.1.2,D.1.3,D.1.4,D.1.5"

"""Campaigns from the independent harness (benchmarks/independent_campaigns.py) read and evaluate.

The harness writes devices metro's simulators do not make — numpy generators written from the
documented format only — and scores the results against the truth it knows by construction.  Here
three short devices (a pulse gyro at 1 Hz in CSV with flicker noise, an LSB rate-method device at
10 Hz in .npy with scale-factor asymmetry, a ratiometric mV/V vibratory gyro at 400 Hz with coarse
rounding and a thermal wander): metro must read every documented field and file, give each result
in the unit the standard states, and either land within U of the truth or say why it cannot report
it.  The full sweep (30 devices per variant) and its table are in docs/independent-campaigns.md.
"""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

import numpy as np
import pytest

_PATH = Path(__file__).resolve().parents[1] / "benchmarks" / "independent_campaigns.py"


@pytest.fixture(scope="module")
def harness():
    spec = importlib.util.spec_from_file_location("independent_campaigns", _PATH)
    mod = importlib.util.module_from_spec(spec)
    sys.modules[spec.name] = mod  # its dataclasses look their module up
    spec.loader.exec_module(mod)
    return mod


def test_harness_does_not_use_metro_generators():
    """The point of the harness is independence: its generators import no part of metro."""
    text = _PATH.read_text(encoding="utf-8")
    imports = [ln for ln in text.splitlines() if ln.lstrip().startswith(("import ", "from "))]
    assert imports, "no imports found"
    for ln in imports:
        assert "metro.instruments" not in ln and "simulated" not in ln, ln
    metro_imports = [ln.strip() for ln in imports if "metro" in ln]
    assert metro_imports == ["from metro.core.cli.app import main"], metro_imports


def test_pulse_counter_keeps_every_pulse(harness):
    """The undithered counter loses nothing: the counts sum to the floor of the whole angle × K."""
    rng = np.random.default_rng(3)
    out = harness.Output("pulse", K=0.731)
    rate = 9.7 + rng.standard_normal(5000) * 0.3  # °/h
    counts = out.record(rate, 1.0, rng=np.random.default_rng(4))
    phase0 = np.random.default_rng(4).uniform(0, 1)
    total = math.floor(np.sum(rate * 1.0) * 0.731 + phase0) - math.floor(phase0)
    assert counts.sum() == total
    assert np.all(counts == np.round(counts))


DEVICES = [
    ("gbt45570", "D.5.1,D.5.3", 11,
     lambda h, f, rng: h.build_gbt_bias(f, rng, kind="pulse", dt=1.0, fmt="csv", flick=0.002,
                                        wander=0.0,
                                       lsb_deg_h=0, q_deg_h=0, quick=True)),
    ("gbt45570", "D.2.1", 12,
     lambda h, f, rng: h.build_gbt_rate(f, rng, dt=0.1, fmt="npy", lsb_deg_h=0.3, asym=2e-4,
                                        flick=0.01,
                                       wander=0.05, quick=True)),
    ("jjf2014", "7.2.1,7.2.4,7.2.13", 13,
     lambda h, f, rng: h.build_jjf(f, rng, dt_static=0.0025, dt_rate=0.0025, fmt="npy", kind="mV/V",
                                  flick=0.0, wander=5.0, q=0.01, asym=0.0, neg=False, static_s=300,
                                  quick=True)),
]


@pytest.mark.parametrize("standard,items,seed,build", DEVICES,
                         ids=["gbt-pulse-bias", "gbt-lsb-rate", "jjf-mVV"])
def test_independent_device_evaluates_within_U(harness, tmp_path, standard, items, seed, build,
                                                harness_device, evaluated_within_u):
    folder, truth = harness_device(harness, build, seed, items, tmp_path)
    evaluated_within_u(harness.run_metro, harness.score, folder, standard, items, truth)


def test_plan_lists_the_columns_a_campaign_writer_needs(run_cli, harness, tmp_path):
    """data-format.md says `metro plan` prints the column units each segment needs; it printed
    kinds and conditions only, so a D.1.1 campaign written from the documented `output [P]` column
    was refused ('no column count') with nothing documented to say what to write.  The plan lists
    the columns, and a campaign written from that listing is evaluated."""
    code, out, _ = run_cli("plan", "-s", "gbt45570", "-i", "D.1.1", "--json")
    assert code == 0
    steps = json.loads(out)["steps"]
    assert steps and all(s["kind"] == "rate-revolutions" for s in steps)
    assert all(s["columns"] == {"count": ["P"], "duration": ["s"]} for s in steps)
    code, out, _ = run_cli("plan", "-s", "jjf2014", "-i", "7.2.13")
    assert "kind=static duration=1 h interval=0.1 s orientation=IRA up; columns: output [mV]" in out
    code, out, _ = run_cli("plan", "-s", "gbt45570", "-i", "D.1.1")
    assert out.splitlines()[1].endswith("turns=5; columns: count [P], duration [s]")

    folder = tmp_path / "angle"
    folder.mkdir()
    truth = harness.build_gbt_angle(folder, np.random.default_rng(21), asym=2e-5, quick=True)
    written = (folder / "rate+1.csv").read_text(encoding="utf-8").splitlines()[0]
    assert written == "count [P],duration [s]"
    code, doc, err = harness.run_metro(folder / "manifest.toml", "gbt45570", "D.1.1")
    assert code in (0, 3, 4), err
    (row,) = harness.score(truth, doc)
    assert row["status"] == "ok" and abs(row["En"]) <= 1, row


def test_two_segments_of_one_kind_cannot_read_one_file(run_cli, harness, tmp_path):
    """The harness's first version cut file names at the dot ('rate+0.25' -> 'rate+0.csv'): the
    JJF 7.2.1 points at 0.1, 0.25 and 0.63 °/s all read the 0.63 °/s record and metro evaluated it
    (K within its U, the misfit absorbed).  One record cannot be two measurements of one kind: an
    error naming the manifest, the segment's file field and both segments (exit 2).  Different
    kinds may share a record (a D.5.1 static hour that is also the first D.5.3 power-on)."""
    folder = tmp_path / "jjf"
    folder.mkdir()
    harness.build_jjf(folder, np.random.default_rng(5), dt_static=0.01, dt_rate=1.0, fmt="csv",
                      kind="mV",
                      flick=0.0, wander=0.0, q=0.0, asym=0.0, neg=False, static_s=300, quick=True)
    manifest = folder / "manifest.toml"
    text = manifest.read_text(encoding="utf-8")
    assert text.count('file = "rate+0.25.csv"') == 1
    manifest.write_text(text.replace('file = "rate+0.25.csv"', 'file = "rate+0.1.csv"'),
                        encoding="utf-8")
    code, out, err = run_cli("run", "-s", "jjf2014", "-i", "7.2.1", "--data", str(manifest),
                             "--no-report", "--json")
    assert code == 2, err
    doc = json.loads(out)
    assert doc["field"].startswith("segments[") and doc["field"].endswith("].file"), doc
    assert "'rate+0.25'" in doc["message"] and "'rate+0.1'" in doc[
        "message"] and "rate+0.1.csv" in doc["message"]
    assert "Traceback" not in err

    bias = tmp_path / "bias"
    bias.mkdir()
    harness.build_gbt_bias(bias, np.random.default_rng(6), kind="pulse", dt=1.0, fmt="csv",
                           flick=0.0, wander=0.0,
                           lsb_deg_h=0, q_deg_h=0, quick=True)
    manifest = bias / "manifest.toml"
    text = manifest.read_text(encoding="utf-8")
    manifest.write_text(text.replace('file = "repeat-1.csv"', 'file = "static-1h.csv"'),
                        encoding="utf-8")
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.3", "--data", str(manifest),
                             "--no-report",
                             "--json")
    assert code in (0, 3, 4), err

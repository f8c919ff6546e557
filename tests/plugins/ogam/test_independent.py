"""Campaigns from the independent ogam harness (benchmarks/independent_ogam.py) read and evaluate.

The harness builds optical-gyro angle-measuring instruments metro's simulator does not make — numpy
generators written from docs/standards/ogam.md's data table and the draft's clauses only: pulse
equivalents from 0.018″ to 7.2″, harmonic angle errors of other orders, a tilted sensing plane at
any azimuth, residual earth-rate compensation errors of either sign, coarse and fine reading
resolution, stops reached from 0° or in one run, other 7.6 rate points, south/west axes — and scores
every result of 7.1–7.7 against the truth it knows by construction. Here one short instrument of
each variant (fewer Monte Carlo draws for the noise truths): metro must read it, give each result in
the draft's unit and land within U of the truth or say why it cannot report it. The sweep and its
table are in docs/independent-campaigns.md, "ogam: the angle-measuring instrument"."""

from __future__ import annotations

import importlib.util
import sys
import zlib
from pathlib import Path

import numpy as np
import pytest

_DIR = Path(__file__).resolve().parents[3] / "benchmarks"


@pytest.fixture(scope="module")
def harness():
    sys.path.insert(0, str(_DIR))
    for name in ("independent_campaigns", "independent_ogam"):
        spec = importlib.util.spec_from_file_location(name, _DIR / f"{name}.py")
        mod = importlib.util.module_from_spec(spec)
        sys.modules[spec.name] = mod  # its dataclasses look their module up
        spec.loader.exec_module(mod)
    return mod


def test_harness_does_not_use_metro_generators(benchmark_imports):
    """Independence: the ogam generators import nothing of metro (its one metro import, the command
    line, is in the shared independent_campaigns.py, which its own test keeps so)."""
    text, imports = benchmark_imports("independent_ogam")
    assert any("independent_campaigns" in ln for ln in imports), imports
    assert not [ln for ln in imports if "metro" in ln], imports
    assert "angle_instrument" not in text


def test_tilt_curve_is_the_appendix_extreme(harness):
    """The harness's own integration of appendix A eqs. (2)–(5): ψ = 0.1° gives the draft's 0.08″
    (sin²ψ/8 rad = 0.0785″)."""
    _, d = harness.tilt_curve(0.1)
    assert np.max(np.abs(d)) == pytest.approx(0.0785, abs=5e-4)


# one instrument per variant, seeds picked at random once (not tuned)
CASES = [("rlg-fine-fromzero", 7), ("fog-coarse-reading", 3), ("rlg-sequential-drifting", 5),
         ("rlg-tilted-harmonic", 2)]


@pytest.mark.parametrize("variant,seed", CASES)
def test_short_instrument_within_U_or_not_reportable(harness, tmp_path, variant, seed):
    v = harness.VARIANTS[variant]
    rng = np.random.default_rng([seed, zlib.crc32(v.name.encode())])
    truth = v.build(tmp_path, rng, True)
    code, doc, err = harness.IC.run_metro(tmp_path / "manifest.toml", v.standard, v.items)
    assert code in (0, 3, 4) and doc.get("results"), err
    rows = harness.IC.score(truth, doc)
    assert len(rows) == 7
    for r in rows:
        assert r["status"] in ("ok", "not reportable"), r
        if r["status"] == "ok":
            assert abs(r["En"]) <= 1.0, r

"""ogam: what the independent harness (benchmarks/independent_ogam.py) found, each with a hand-made
campaign whose right answer is worked out here (docs/independent-campaigns.md, "ogam: the
angle-measuring instrument"; interpretations.md, ogam section)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from metro.core.runner import run_items

S = 30.0 * np.arange(1, 13)  # the twelve stops of 7.4, °


def _manifest(root: Path, segments: list[str], K: str = "20000 P/°") -> Path:
    lines = ['format = "metro-campaign/1"', "[campaign]", 'id = "OGAM-FIX"', "[device]", 'id = "OGA-FIX"',
             'output = "pulse"', f'scale_factor = "{K}"', 'zero_stability = "0.005 °/h"',
             "[environment]", 'temperature = "20 °C"', 'humidity = "50 %"', "[site]", 'latitude = "30°"',
             "[[equipment]]", 'id = "TT-1"', 'role = "turntable"', 'parallelism = "0.1°"',
             "[equipment.calibration]", 'certificate = "TT-CAL-1"', 'U = "0.1″"', 'distribution = "uniform"',
             "[[equipment]]", 'id = "TIMER-1"', 'role = "timer"']
    (root / "manifest.toml").write_text("\n".join(lines + segments) + "\n", encoding="utf-8")
    return root / "manifest.toml"


def _round(root: Path, seg_id: str, rate: float, axis: str, rnd: int, err_arcsec: np.ndarray) -> list[str]:
    name = f"{seg_id}.csv"
    (root / name).write_text("standard [°],reading [°]\n" + "".join(
        f"{s!r},{s + e / 3600.0!r}\n" for s, e in zip(S.tolist(), err_arcsec.tolist())), encoding="utf-8")
    return ["[[segments]]", f'id = "{seg_id}"', 'kind = "positioning"', f'file = "{name}"', 'sample_interval = "60 s"',
            "[segments.conditions]", f'rate = "{rate:g} °/s"', f'axis = "{axis}"', f"round = {rnd}"]


def test_76_compares_the_rates_the_campaign_measured(pm, tmp_path):
    """Clause 7.6's rates are reference values (参考值): a campaign at 2, 5, 20, 60, 120 °/s is
    compared at those rates.  Before, only the printed 1, 10, 60, 100, … were looked for: this campaign
    was refused ("needs … at least two rates"), and one sharing only 60 and 300 °/s with the printed set
    compared those two alone, with a warning, whatever else it held (the harness's sequential variant:
    C_v within U in 55 % of instruments)."""
    rng = np.random.default_rng(76)
    base = 0.5 * np.sin(np.radians(S))  # ″: E = 0.5″ at 60 °/s
    segs = []
    for r in range(1, 4):
        segs += _round(tmp_path, f"p60-r{r}", 60.0, "up", r, base + rng.normal(0, 0.01, S.size))
    E_at = {2.0: 0.9, 5.0: 0.7, 20.0: 0.55, 120.0: 0.45}
    for v, E in E_at.items():
        segs += _round(tmp_path, f"p{v:g}", v, "up", 1, E / 0.5 * base)
    rec = run_items(pm, "ogam", ["7.6"], data=_manifest(tmp_path, segs))
    res = rec.outcomes[0].results[0]
    e60 = float(np.max(np.abs(np.loadtxt(tmp_path / "p60-r1.csv", delimiter=",", skiprows=1) @ [-3600.0, 3600.0])))
    expected = 100.0 * (0.9 - min(0.45, e60)) / e60
    assert res.value.to("percent").magnitude == pytest.approx(expected, rel=1e-6)
    assert any("5 rate points" in w for w in rec.outcomes[0].warnings), rec.outcomes[0].warnings


def test_75_repeatability_of_identical_rounds_is_not_reportable(pm, tmp_path):
    """Readings rounded to 1″ from an instrument whose noise is far below 1″: every round reads the
    same, R = 0 with U = 0 — a confident wrong number (the harness's coarse-reading instruments
    had σ up to 0.06″).  Now not reportable, with the reason; a round that differs keeps R."""
    err = np.round(0.8 * np.sin(np.radians(S)))
    segs = []
    for r in range(1, 11):
        segs += _round(tmp_path, f"p60-r{r}", 60.0, "up", r, err)
    res = run_items(pm, "ogam", ["7.5"], data=_manifest(tmp_path, segs)).outcomes[0].results[0]
    assert res.value.to("arcsec").magnitude == 0.0
    assert not res.reportable and "below the reading resolution" in res.reason
    other = tmp_path / "b"
    other.mkdir()
    segs = []
    for r in range(1, 11):
        segs += _round(other, f"p60-r{r}", 60.0, "up", r, err + (1.0 if r == 3 else 0.0) * (S == 90.0))
    res = run_items(pm, "ogam", ["7.5"], data=_manifest(other, segs)).outcomes[0].results[0]
    assert res.reportable and res.value.to("arcsec").magnitude == pytest.approx(math.sqrt(0.1 * 0.9 * 10 / 9))

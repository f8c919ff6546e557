"""A run's figures drawn in a second process while its items are evaluated
(metro.core.documents.figure_cache.DrawingAhead): the same PNG bytes as drawn in-process, taken by
the document when it asks for the same figure, drawn in-process whenever the worker cannot help, and
a caller's unguarded script is never run a second time by the worker."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest
from metro.core.documents import figure_cache, plots
from metro.core.model.results import PlotSpec


def _spec(k: float, title: str = "零偏稳定性 bias stability") -> PlotSpec:
    tau = np.array([1.0, 10.0, 100.0])
    return PlotSpec("adev", f"{title} {k}", "τ (s)", "σ (°/h)",
                    [{"x": tau, "y": np.array([9.0, 5.0, k]), "style": "o", "label": "σ(τ)"}],
                    logx=True, logy=True)


@pytest.fixture(autouse=True)
def _no_cache(monkeypatch):
    monkeypatch.setenv("METRO_FIGURE_CACHE", "off")
    monkeypatch.delenv("METRO_DRAW_AHEAD", raising=False)


def _wait_ready(ahead: figure_cache.DrawingAhead, seconds: float = 60.0) -> None:
    t0 = time.monotonic()
    while not ahead._ready.done():
        assert time.monotonic() - t0 < seconds, "the drawing process did not start"
        time.sleep(0.05)


def test_figures_drawn_ahead_are_the_in_process_bytes(monkeypatch):
    specs = [_spec(4.0), _spec(3.0)]
    with figure_cache.DrawingAhead() as ahead:
        assert ahead.enabled
        _wait_ready(ahead)
        for s in specs:
            ahead.submit(s)
        for f in list(ahead._futures.values()):
            f.result(timeout=60)
        drawn_here = []
        monkeypatch.setattr(plots, "png_bytes", lambda spec, **kw: drawn_here.append(spec) or b"")
        taken = [figure_cache.cached_png(s) for s in specs]
        assert ahead.take_count == 2 and drawn_here == []
    monkeypatch.undo()
    assert taken == [plots.png_bytes(s) for s in specs]


def test_a_figure_not_submitted_is_drawn_in_process(monkeypatch):
    with figure_cache.DrawingAhead() as ahead:
        _wait_ready(ahead)
        ahead.submit(_spec(4.0))
        assert ahead.take(_spec(5.0), dpi=plots.DPI) is None
        assert ahead.take_count == 0
    assert figure_cache._AHEAD == []


def test_not_ready_is_never_waited_for(monkeypatch):
    ahead = figure_cache.DrawingAhead()
    ahead._ready = _NeverDone()
    ahead._futures[figure_cache.spec_digest(_spec(1.0), dpi=plots.DPI)] = _NeverDone()
    assert ahead.take(_spec(1.0), dpi=plots.DPI) is None


class _NeverDone:
    def done(self) -> bool:
        return False

    def cancel(self) -> bool:
        return False

    def result(self, timeout=None):  # pragma: no cover - must not be called
        raise AssertionError("waited for a worker that is not ready")


@pytest.mark.parametrize("value", ["off", "0", "no"])
def test_turned_off(monkeypatch, value):
    monkeypatch.setenv("METRO_DRAW_AHEAD", value)
    with figure_cache.DrawingAhead() as ahead:
        ahead.submit(_spec(1.0))
        assert not ahead.enabled and ahead._pool is None


def test_one_core_draws_in_process(monkeypatch):
    monkeypatch.setattr("os.cpu_count", lambda: 1)
    assert not figure_cache.DrawingAhead().enabled


def test_an_unguarded_script_runs_once(tmp_path):
    """A "spawn" worker imports the caller's main module again; a script without the
    ``if __name__ == "__main__"`` guard would have done its work twice (two reports)."""
    marker = tmp_path / "runs.txt"
    script = tmp_path / "unguarded.py"
    script.write_text(textwrap.dedent(f"""
        import numpy as np
        from metro.core.documents import figure_cache
        from metro.core.model.results import PlotSpec

        with open({str(marker)!r}, "a") as f:
            f.write("ran\\n")
        spec = PlotSpec("lin", "t", "x", "y", [{{"x": np.arange(3.0), "y": np.arange(3.0)}}])
        with figure_cache.DrawingAhead() as ahead:
            ahead.submit(spec)
            ahead._ready.result(timeout=60)
            png = figure_cache.cached_png(spec)
            print(ahead.take_count, png[:4] == b"\\x89PNG")
    """))
    out = subprocess.run([sys.executable, str(script)], check=False, capture_output=True, text=True,
                         timeout=120,
                         env={**os.environ, "METRO_FIGURE_CACHE": "off"})
    assert out.returncode == 0, out.stderr
    assert out.stdout.split() == ["1", "True"]
    assert marker.read_text() == "ran\n"


def _spy(monkeypatch) -> tuple[list[str], list[str]]:
    """The digests of the figures handed to the worker, and of those the document asked for."""
    submitted: list[str] = []
    asked: list[str] = []
    submit, take = figure_cache.DrawingAhead.submit, figure_cache.DrawingAhead.take

    def spy_submit(self, spec, **kw):
        submitted.append(figure_cache.spec_digest(spec, dpi=plots.DPI))
        return submit(self, spec, **kw)

    def spy_take(self, spec, *, dpi):
        asked.append(figure_cache.spec_digest(spec, dpi=dpi))
        return take(self, spec, dpi=dpi)

    monkeypatch.setattr(figure_cache.DrawingAhead, "submit", spy_submit)
    monkeypatch.setattr(figure_cache.DrawingAhead, "take", spy_take)
    return submitted, asked


@pytest.mark.parametrize("lang", [None, "en", "zh"])
def test_run_hands_the_report_its_own_figures(monkeypatch, run_cli, tmp_path, lang):
    """``metro run`` with several items hands each item's figures to the worker as the item
    finishes, in the report's language: the very figures the document then asks for."""
    submitted, asked = _spy(monkeypatch)
    argv = ["run", "-s", "gbt45570", "-i", "D.5.1", "-i", "D.5.2", "-i", "D.5.6", "--out",
            str(tmp_path / "o")]
    code, _, err = run_cli(*argv, *(["--lang", lang] if lang else []))
    assert code == 0, err
    assert asked and sorted(submitted) == sorted(asked)


def test_one_item_or_no_report_starts_no_worker(monkeypatch, run_cli, tmp_path):
    submitted, asked = _spy(monkeypatch)
    assert run_cli("run", "-s", "gbt45570", "-i", "D.5.2", "--out", str(tmp_path / "a"))[0] == 0
    assert run_cli("run", "-s", "gbt45570", "--all", "--no-report")[0] == 0
    assert submitted == [] and asked == []

"""Figures draw Chinese with a CJK font even when matplotlib's font cache predates the font.

matplotlib lists the machine's fonts once, in a cache file (``fontlist-*.json`` in its config or
cache folder); a lab that installs its CJK fonts after the first use of matplotlib has a cache
without them, and before issue 29 every figure drew its Chinese as empty boxes with one
``UserWarning: Glyph … missing from font(s) DejaVu Sans`` per glyph. metro now adds the CJK font
files it finds to the running process (:func:`metro.core.documents.plots.register_cjk_fonts`), and a
machine with no CJK font at all gets one statement of metro's, never matplotlib's warnings.

Each case runs in a subprocess whose ``MPLCONFIGDIR`` holds a font cache built without the CJK
fonts (matplotlib's own cache format, its entries for the CJK font files removed).
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from metro.core.documents import plots

_CJK_FILES = plots.cjk_font_files()
needs_cjk = pytest.mark.skipif(not _CJK_FILES,
                               reason="no CJK font file on this machine (fonts-noto-cjk)")

@pytest.fixture(scope="module")
def stale_cache(tmp_path_factory):
    """An MPLCONFIGDIR whose font list was built as if no CJK font were installed."""
    from matplotlib import font_manager

    folder = tmp_path_factory.mktemp("mplconfig")
    target = folder / f"fontlist-v{font_manager.FontManager.__version__}.json"
    code = ("import re, sys\nfrom matplotlib import font_manager as fm\n"
            f"pat = re.compile({plots.CJK_FONT_FILE.pattern!r})\n"
            "m = fm.FontManager()\nm.ttflist = [f for f in m.ttflist if not pat.search(f.fname)]\n"
            "fm.json_dump(m, sys.argv[1])\n")
    env = dict(os.environ, MPLCONFIGDIR=str(folder))
    subprocess.run([sys.executable, "-c", code, str(target)], check=True, env=env,
                   capture_output=True)
    cached = json.loads(target.read_text(encoding="utf-8"))
    assert not [f for f in cached["ttflist"] if "CJK" in f["name"]]  # the cache really is stale
    return folder


def _run(code: str, mplconfig: Path, *args: str) -> subprocess.CompletedProcess:
    env = dict(os.environ, MPLCONFIGDIR=str(mplconfig), PYTHONWARNINGS="default")
    return subprocess.run([sys.executable, "-c", code, *args], env=env, capture_output=True,
                          text=True, timeout=600)


_DRAW = """
import sys
from matplotlib import font_manager as fm
from matplotlib.ft2font import FT2Font
from metro.core.documents import plots
from metro.core.model.results import PlotSpec

assert not any("CJK" in f.name for f in fm.fontManager.ttflist), "the cache is not stale"
spec = PlotSpec("zh", "零偏稳定性 bias stability", "平均时间 τ (s)", "零偏 B₀ (°/h)",
                [{"label": "测量值", "x": [1.0, 2.0, 3.0], "y": [0.1, 0.2, 0.15], "style": "o"}])
plots.render_png(spec, sys.argv[1], dpi=60)
# the font matplotlib draws 零 with: the first of the figure's families whose font has the glyph
families = plots.font_families()
files = [fm.findfont(fm.FontProperties(family=f), fallback_to_default=False) for f in families]
used = next(p for p in files if FT2Font(p).get_char_index(ord("零")))
print("FONT", used)
"""


@needs_cjk
def test_a_stale_font_cache_still_draws_chinese_with_a_cjk_font(stale_cache, tmp_path):
    proc = _run(_DRAW, stale_cache, str(tmp_path / "f.png"))
    assert proc.returncode == 0, proc.stderr
    assert "Warning" not in proc.stderr and "missing from font" not in proc.stderr, proc.stderr
    assert "no CJK font" not in proc.stderr, proc.stderr
    used = proc.stdout.split("FONT", 1)[1].strip()
    assert plots.CJK_FONT_FILE.search(used), used
    assert (tmp_path / "f.png").stat().st_size > 1000


@needs_cjk
def test_a_run_with_a_stale_font_cache_prints_no_python_warning(stale_cache, tmp_path):
    """``metro run`` of an item with figures, zh+en: stderr holds no Python warning."""
    code = "import sys; from metro.core.cli.app import main; sys.exit(main(sys.argv[1:]))"
    proc = _run(code, stale_cache, "run", "-s", "gbt45570", "-i", "D.5.6", "--station-option",
                "duration_scale=0.05",
                "--out", str(tmp_path), "--no-progress", "-q")
    assert proc.returncode in (0, 3, 4), proc.stderr
    import zipfile

    docx = next(tmp_path.glob("*.docx"))
    # the figure is drawn
    assert [n for n in zipfile.ZipFile(docx).namelist() if n.endswith(".png")]
    for text in (proc.stderr, proc.stdout):
        assert ("Warning" not in text and "missing from font" not in text
                and "no CJK font" not in text), text


def test_no_cjk_font_at_all_is_one_statement_not_a_warning_per_glyph(stale_cache, tmp_path):
    """Without any CJK font (the system's font list empty), figures still draw, and the run says
    once what is missing instead of matplotlib's warning per glyph and figure."""
    code = ("import sys\nfrom matplotlib import font_manager as fm\nfm.findSystemFonts = lambda "
            "*a, **k: []\nfrom metro.core.documents import plots\nfrom metro.core.model.results "
            "import PlotSpec\nspec = PlotSpec('zh', '零偏稳定性', 'τ (s)', '零偏 (°/h)', "
            "[{'x': [1.0, 2.0], 'y': [1.0, 2.0]}])\nfor i in range(3):\n    plots.render_png(spec, "
            "f'{sys.argv[1]}/{i}.png', dpi=40)\n")
    proc = _run(code, stale_cache, str(tmp_path))
    assert proc.returncode == 0, proc.stderr
    assert "Warning" not in proc.stderr and "missing from font" not in proc.stderr, proc.stderr
    assert proc.stderr.count("no CJK font found") == 1, proc.stderr
    assert len(list(tmp_path.glob("*.png"))) == 3


@pytest.fixture
def no_cjk_font_known(monkeypatch):
    """matplotlib's font list without CJK fonts, the machine's fonts found through a counting
    finder, and register_cjk_fonts' result forgotten before and after (other tests find the real
    fonts)."""
    from matplotlib import font_manager

    fm = font_manager.fontManager
    monkeypatch.setattr(fm, "ttflist", [f for f in fm.ttflist if
                                        not plots.CJK_FONT_FILE.search(f.fname)])
    searches = []
    plots.register_cjk_fonts.cache_clear()
    yield monkeypatch, searches
    plots.register_cjk_fonts.cache_clear()


def _counting_finder(monkeypatch, searches, found, delay=0.0):
    import time

    from matplotlib import font_manager

    def find(*a, **k):
        searches.append(1)
        time.sleep(delay)
        return list(found)

    monkeypatch.setattr(font_manager, "findSystemFonts", find)


@pytest.mark.parametrize("found", ["none", "cjk"])
def test_the_machine_is_searched_for_cjk_fonts_once_per_process(no_cjk_font_known, found):
    """Issue 29: with no CJK font known the search of the machine's fonts (fontconfig's fc-list and
    the font folders) must not run again for every figure — nor when it found none."""
    monkeypatch, searches = no_cjk_font_known
    files = _CJK_FILES[:1] if found == "cjk" else []
    if found == "cjk" and not files:
        pytest.skip("no CJK font file on this machine (fonts-noto-cjk)")
    _counting_finder(monkeypatch, searches, files)
    first = plots.register_cjk_fonts()
    assert first == tuple(files) and len(searches) == 1
    for _ in range(3):
        assert plots.register_cjk_fonts() == first
        plots.font_families()
    assert len(searches) == 1


def test_figures_drawn_at_once_from_threads_search_once(no_cjk_font_known):
    """`metro batch` writes documents from threads: their first figures, at the same moment, still
    search the machine once."""
    import threading

    monkeypatch, searches = no_cjk_font_known
    _counting_finder(monkeypatch, searches, _CJK_FILES[:1], delay=0.2)
    results = []
    threads = [threading.Thread(target=lambda: results.append(plots.register_cjk_fonts())) for _
               in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(searches) == 1
    assert results == [tuple(_CJK_FILES[:1])] * 4  # each font file added by one thread

"""Figures are drawn once per figure (not laid out twice by savefig) and a document written again
takes them from metro.core.documents.figure_cache: the same pixels as savefig's, never a stale
image."""

from __future__ import annotations

import io

import attrs
import numpy as np
import pytest

from metro.core.documents import figure_cache, plots
from metro.core.model.results import PlotSpec


def _spec(y_last: float = 3.0,
          title: str = "B_s(τ_k) 及 D.45 拟合 B_s(τ_k) and the D.45 fit") -> PlotSpec:
    tau = np.array([1.0, 10.0, 100.0, 1000.0])
    return PlotSpec("adev", title, "τ_k (s)", "B_s (°/h)",
                    [{"x": tau, "y": np.array([9.0, 5.0, 4.0, y_last]), "style": "o",
                      "label": "B_s(τ_k)",
                      "yerr": np.array([0.5, 0.4, 0.4, 0.3])},
                     {"x": tau, "y": np.array([9.1, 5.2, 3.9, 3.1]), "style": "--",
                      "label": "D.45"}],
                    logx=True, logy=True)


@pytest.fixture
def cache(tmp_path, monkeypatch):
    monkeypatch.setenv("METRO_CACHE_DIR", str(tmp_path))
    monkeypatch.delenv("METRO_FIGURE_CACHE", raising=False)
    return tmp_path / "figures"


def _savefig_png(spec: PlotSpec) -> bytes:
    """The former drawing: Figure.savefig (which lays the figure out and draws it twice)."""
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with matplotlib.rc_context({"font.family": plots.font_families()}), plots.MissingGlyphs():
        fig = Figure(figsize=plots.FIGSIZE_IN, dpi=plots.DPI, layout="constrained")
        FigureCanvasAgg(fig)
        plots._draw(fig, spec)
        out = io.BytesIO()
        fig.savefig(out, format="png", dpi=plots.DPI)
        return out.getvalue()


@pytest.mark.parametrize("spec", [_spec(), PlotSpec("lin", "Scale factor against temperature",
                                                    "T (°C)", "K (P/″)",
                                                    [{"x": [-40, 20, 60],
                                                      "y": [0.800001, 0.800002, 0.8000031]}])])
def test_one_draw_writes_the_pixels_savefig_wrote(spec, tmp_path):
    assert _same_image(plots.png_bytes(spec), _savefig_png(spec))
    assert _same_image(plots.render_png(spec, tmp_path / "f.png").read_bytes(), _savefig_png(spec))


def _same_image(a: bytes, b: bytes) -> bool:
    """The same pixels (mode, size, every value), resolution and text chunks."""
    from PIL import Image

    ia, ib = Image.open(io.BytesIO(a)), Image.open(io.BytesIO(b))
    return (ia.mode, ia.size, ia.info) == (ib.mode, ib.size,
                                           ib.info) and np.array_equal(np.asarray(ia), np.asarray(
                                               ib))


def test_png_encode_keeps_every_pixel():
    """png_encode is lossless whatever the pixels: noise, transparency, a single row or column."""
    from PIL import Image

    rng = np.random.default_rng(29)
    for shape in ((37, 53, 4), (1, 9, 4), (9, 1, 4), (300, 200, 4)):
        rgba = rng.integers(0, 256, size=shape, dtype=np.uint8)
        # runs, as a figure's white space
        rgba[: shape[0] // 2, : shape[1] // 2] = (255, 255, 255, 255)
        im = Image.open(io.BytesIO(plots.png_encode(rgba, dpi=300, text={"Software": "metro"})))
        assert im.mode == "RGBA" and im.size == (shape[1], shape[0])
        assert np.array_equal(np.asarray(im), rgba)
        assert im.info["Software"] == "metro" and round(im.info["dpi"][0]) == 300
    with pytest.raises(ValueError, match="RGBA"):
        plots.png_encode(np.zeros((4, 4, 3), dtype=np.uint8), dpi=300)


def test_png_encode_smaller_than_pillow_on_a_figure():
    """Filter "Up" and zlib level 6 on a drawn figure: no larger than Pillow's PNG of it."""
    assert len(plots.png_bytes(_spec())) <= len(_savefig_png(_spec()))


def test_figures_drawn_one_after_another_on_the_kept_renderer(tmp_path):
    """The renderer kept between figures (its text measurements and parsed mathtext) draws each
    figure as a renderer of its own did: a figure drawn after others is the figure drawn alone."""
    a, b = _spec(), PlotSpec("lin", "温度 T_{ref}", "T (°C)", "K_i (P/″)",
                             [{"x": [-40, 20, 60], "y": [0.5, 0.6, 0.7],
                               "style": "o", "yerr": 0.01}])
    drawn = [plots.png_bytes(x) for x in (a, b, a, b)]
    assert drawn[0] == drawn[2] and _same_image(drawn[0], _savefig_png(a))
    assert drawn[1] == drawn[3] and _same_image(drawn[1], _savefig_png(b))
    assert plots.png_bytes(b, dpi=60) != drawn[1]  # another size: a renderer of its own


def test_a_figure_drawn_before_is_not_drawn_again(cache, monkeypatch):
    first = figure_cache.cached_png(_spec())
    assert first == plots.png_bytes(_spec())
    assert len(list(cache.glob("*.png"))) == 1

    def no_drawing(*a, **k):
        raise AssertionError("drawn again")

    monkeypatch.setattr(plots, "png_bytes", no_drawing)
    assert figure_cache.cached_png(_spec()) == first


def figure_key_of(spec):
    return figure_cache.figure_key(spec, dpi=300)


@pytest.mark.parametrize("changed", [_spec(y_last=3.0000001), _spec(title="another title"),
                                     attrs.evolve(_spec(), logy=False),
                                     attrs.evolve(_spec(),
                                                  series=[dict(_spec().series[0], style="s")])])
def test_any_change_is_a_new_figure(cache, changed):
    figure_cache.cached_png(_spec())
    assert figure_key_of(changed) != figure_key_of(_spec())
    assert figure_cache.cached_png(changed) == plots.png_bytes(changed)


def test_key_follows_dpi_settings_and_drawing_code(cache, monkeypatch):
    import matplotlib

    key = figure_key_of(_spec())
    assert figure_cache.figure_key(_spec(), dpi=200) != key
    with matplotlib.rc_context({"lines.linewidth": 3.0}):
        assert figure_key_of(_spec()) != key
    monkeypatch.setattr(figure_cache, "_source_digest", lambda: "another plots.py")
    assert figure_key_of(_spec()) != key


def test_stored_context_finds_the_figure_drawn_at_issue(cache):
    """A figure of a registered report, written again from its stored context (series as JSON
    lists, NaN as null), has the key the run's figure had."""
    from metro.core.record.registering import decode_context, encode_context

    spec = _spec()
    spec = PlotSpec(spec.name, spec.title, spec.xlabel, spec.ylabel,
                    [dict(spec.series[0], y=np.array([9.0, np.nan, 4.0, 3.0]))]
                    + list(spec.series[1:]),
                    logx=True, logy=True)
    again = (
        decode_context(encode_context({"outcomes": [{"plots": [{"spec": spec}]}]}))["outcomes"][0][
            "plots"][0]["spec"]
    )
    assert figure_key_of(again) == figure_key_of(spec)


def test_a_damaged_file_is_drawn_again(cache):
    good = figure_cache.cached_png(_spec())
    (path,) = cache.glob("*.png")
    path.write_bytes(good[: len(good) // 2])  # cut short, as a crash while writing would leave it
    assert figure_cache.cached_png(_spec()) == good
    assert path.read_bytes() == good


def test_off_and_unwritable_cache_still_draw(tmp_path, monkeypatch):
    monkeypatch.setenv("METRO_CACHE_DIR", str(tmp_path))
    monkeypatch.setenv("METRO_FIGURE_CACHE", "off")
    assert figure_cache.cached_png(_spec()) == plots.png_bytes(_spec())
    assert not (tmp_path / "figures").exists()
    blocker = tmp_path / "file"
    blocker.write_text("not a folder")
    monkeypatch.setenv("METRO_CACHE_DIR", str(blocker))
    monkeypatch.delenv("METRO_FIGURE_CACHE")
    assert figure_cache.cached_png(_spec()) == plots.png_bytes(_spec())


def test_least_recently_used_go_first(cache, monkeypatch):
    import os

    monkeypatch.setattr(figure_cache, "MAX_FILES", 3)
    for i in range(3):
        figure_cache.cached_png(_spec(y_last=3.0 + i))
    oldest = figure_key_of(_spec(y_last=3.0))
    os.utime(cache / f"{oldest}.png", (1, 1))
    figure_cache.cached_png(_spec(y_last=9.0))  # a fourth: the oldest goes, 80 % of the limit stay
    names = {p.stem for p in cache.glob("*.png")}
    assert oldest not in names and figure_key_of(_spec(y_last=9.0)) in names and len(names) == 2

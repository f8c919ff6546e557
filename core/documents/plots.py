"""Render a :class:`~metro.core.model.results.PlotSpec` to a PNG file with matplotlib.

Procedures only *describe* figures (a :class:`PlotSpec`: title, axis labels, series);
this module draws them.  matplotlib is imported inside :func:`png_bytes` (which
:func:`render_png` calls), so importing this module costs nothing.  Drawing uses matplotlib's
object interface with the Agg canvas: no GUI backend, no display, and no change to the global
pyplot state of a program (or notebook) that imported metro — nothing is left open after a call
(an Agg renderer per figure size is kept for the next figure, see :func:`_canvas_class`).

A series is a mapping with the keys

* ``x``, ``y`` — sequences of numbers (or pint quantities, whose magnitudes are used);
* ``label`` — legend text (optional);
* ``style`` — ``"o"`` markers (with error bars when ``yerr`` is given), ``"-"`` a solid
  line, ``"--"`` a dashed line; any other matplotlib format string is passed through;
  default ``"-"``;
* ``yerr`` — optional symmetric error bars (one value per point, or one for all).

Labels may use any character of DejaVu Sans (matplotlib's default font), which covers the
field's symbols: ° √ τ α ν σ χ ₀…₉ ² ″.  Chinese text needs a CJK font on the machine
(one of :data:`FALLBACK_FONTS`).  matplotlib knows the fonts its shared cache
(``fontlist-*.json`` in its cache folder) listed when it was built, so fonts installed after
the first use of matplotlib stay invisible to it: :func:`register_cjk_fonts` adds the CJK font
files found on the machine to the running process, whatever that cache says.  Without any CJK
font, Chinese draws as boxes and metro says so once (``metro doctor`` tells what to install),
never as matplotlib's warning per glyph.
"""

from __future__ import annotations

import functools
import logging
import os
import re
import threading
import warnings
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from ..base.atomic import atomic_write

if TYPE_CHECKING:  # pragma: no cover
    from ..model.results import PlotSpec

__all__ = [
    "render_png",
    "png_bytes",
    "FIGSIZE_IN",
    "FALLBACK_FONTS",
    "register_cjk_fonts",
    "font_families",
    "cjk_font_files",
    "CJK_FONT_FILE",
    "MissingGlyphs",
    "png_encode",
]

#: Figure size in inches (about 16 cm × 10 cm: printed at 15 cm wide in reports).
FIGSIZE_IN = (6.3, 3.9)

_MARKER_STYLES = frozenset({"o", "s", "^", "v", "D", "x", "+", "."})

#: Fonts tried after DejaVu Sans for characters it lacks (Chinese titles), when installed.
FALLBACK_FONTS = (
    "Noto Sans CJK SC",
    "Noto Sans SC",
    "Source Han Sans SC",
    "WenQuanYi Zen Hei",
    "WenQuanYi Micro Hei",
    "SimHei",
    "Microsoft YaHei",
    "PingFang SC",
)


#: file names of the fallback fonts' files (Noto Sans/Serif CJK, Source Han Sans, WenQuanYi, SimHei,
#: Microsoft YaHei, PingFang): the files :func:`register_cjk_fonts` adds
CJK_FONT_FILE = re.compile(
    r"(?i)(noto(sans|serif)cjk|notosans-?sc|sourcehansans|wqy-?(zenhei|microhei)|simhei|msyh"
    r"|pingfang)[^/\\]*\.(ttc|otf|ttf)$"
)


#: held while the machine is searched for CJK fonts: figures drawn from threads (``metro batch``)
#: search once between them
_FONT_SEARCH = threading.Lock()


def register_cjk_fonts() -> tuple[str, ...]:
    """Make the CJK fonts on this machine known to matplotlib in this process; return the font
    files added (none when matplotlib already knows one of :data:`FALLBACK_FONTS`).

    The machine is searched once per process, whatever it finds (no CJK font too: the search runs
    fontconfig's ``fc-list``, far too slow to repeat for every figure), and once between threads;
    ``register_cjk_fonts.cache_clear()`` forgets the result (fonts installed since).

    matplotlib reads its font list from a cache built once (``fontlist-*.json`` in
    ``matplotlib.get_cachedir()``): a font installed after that cache was built is not in it,
    and Chinese then draws as empty boxes.  The machine's font files (fontconfig and the system
    font folders, :func:`matplotlib.font_manager.findSystemFonts`) whose names are those of the
    fallback fonts are added with ``fontManager.addfont``; the shared cache is not written."""
    with _FONT_SEARCH:
        return _cjk_fonts_added()


@functools.lru_cache(maxsize=1)
def _cjk_fonts_added() -> tuple[str, ...]:
    """:func:`register_cjk_fonts`' search, its result kept (an empty one too)."""
    from matplotlib import font_manager

    fm = font_manager.fontManager
    if any(f.name in FALLBACK_FONTS and os.path.isfile(f.fname) for f in fm.ttflist):
        return ()
    known = {os.path.realpath(f.fname) for f in fm.ttflist}
    added = []
    for path in cjk_font_files():
        if os.path.realpath(path) not in known:
            try:
                fm.addfont(path)
            except (OSError, RuntimeError, ValueError):  # an unreadable font file: skip it
                continue
            added.append(path)
    return tuple(added)


register_cjk_fonts.cache_clear = _cjk_fonts_added.cache_clear  # type: ignore[attr-defined]


def cjk_font_files() -> list[str]:
    """The machine's font files that hold one of :data:`FALLBACK_FONTS` (by file name), found
    through fontconfig and the system font folders, not through matplotlib's cache."""
    from matplotlib import font_manager

    return sorted(p for p in font_manager.findSystemFonts() if CJK_FONT_FILE.search(p))


def font_families() -> list[str]:
    """DejaVu Sans first, then the installed fallback fonts (matplotlib ≥ 3.6 falls back per glyph),
    after :func:`register_cjk_fonts`."""
    from matplotlib import font_manager

    register_cjk_fonts()
    installed = {f.name for f in font_manager.fontManager.ttflist}
    return ["DejaVu Sans"] + [f for f in FALLBACK_FONTS if f in installed]


_log = logging.getLogger("metro")


@functools.lru_cache(maxsize=1)
def _say_no_cjk_font() -> None:
    """Once per process: figures with Chinese have no font to draw it."""
    _log.warning(
        "figures: no CJK font found, Chinese text in figures is drawn as empty boxes; "
        "install one of "
        "%s (e.g. apt-get install fonts-noto-cjk) — `metro doctor` checks it",
        ", ".join(FALLBACK_FONTS[:2]),
    )


class MissingGlyphs(warnings.catch_warnings):
    """Inside: matplotlib's "Glyph … missing from font(s)" warnings are kept, not printed (one per
    glyph per figure); on leaving, one statement of metro's when there were any (no CJK font)."""

    def __init__(self) -> None:
        super().__init__(record=True)

    def __enter__(self):
        self._seen = super().__enter__()
        warnings.simplefilter("always")
        return self._seen

    def __exit__(self, *exc):
        super().__exit__(*exc)
        missing = [
            w
            for w in self._seen
            if issubclass(w.category, UserWarning)
            and re.match(r"Glyph \d+ .* missing from font", str(w.message))
        ]
        for w in self._seen:  # anything else is shown as it would have been
            if w not in missing:
                warnings.warn_explicit(w.message, w.category, w.filename, w.lineno)
        if missing:
            _say_no_cjk_font()
        return False


def _values(v: Any) -> Any:
    """Plain numbers from a sequence, a numpy array or a pint quantity."""
    import numpy as np

    mag = getattr(v, "magnitude", v)
    return np.asarray(mag, dtype=float)


def _draw_series(ax, s: Mapping[str, Any], index: int) -> bool:
    """Draw one series on ``ax``; return whether it has a legend label."""
    if "x" not in s or "y" not in s:
        raise ValueError(
            f"plot series {index} needs 'x' and 'y' (has: {', '.join(map(str, s)) or 'nothing'})"
        )
    x = _values(s["x"])
    y = _values(s["y"])
    if x.shape != y.shape:
        raise ValueError(f"plot series {index}: x has {x.size} values but y has {y.size}")
    style = str(s.get("style") or "-")
    label = s.get("label")
    label = None if label in (None, "") else str(label)
    yerr = s.get("yerr")
    if style in _MARKER_STYLES:
        if yerr is not None:
            ax.errorbar(
                x,
                y,
                yerr=_values(yerr),
                fmt=style,
                markersize=4,
                capsize=3,
                elinewidth=0.8,
                label=label,
            )
        else:
            ax.plot(x, y, style, markersize=4, label=label)
    elif style == "-":
        ax.plot(x, y, linestyle="-", linewidth=1.4, label=label)
    elif style == "--":
        ax.plot(x, y, linestyle="--", linewidth=1.2, label=label)
    else:
        ax.plot(x, y, style, label=label)  # any other matplotlib format string
    return label is not None


_CJK = re.compile(r"[\u3000-\u303f\u3400-\u9fff\uff00-\uffef]")
#: the subscript characters Unicode has (digits, and the letters below)
_UNI_SUB = dict(zip("0123456789aehijklmnoprstuvx+-=()", "₀₁₂₃₄₅₆₇₈₉ₐₑₕᵢⱼₖₗₘₙₒₚᵣₛₜᵤᵥₓ₊₋₌₍₎"))
_SUBSCRIPT = re.compile(r"(?<![\w$\\])([A-Za-zΔΩα-ω])_(\{[^{}$]{1,12}\}|[A-Za-z0-9]{1,4})(?![\w])")


def localized(spec: "PlotSpec", tr: Any) -> "PlotSpec":
    """The figure's own words — its title, axis labels and legend entries — in the document's
    language (``tr``: a :class:`metro.core.base.locale.Translator`); a plain text the catalog lacks
    stays
    as it is.  The caption under the figure is the document's; this is the text drawn inside it."""
    import attrs

    def t(x: Any) -> str:
        return tr.text(x) if x not in (None, "") else x

    series = tuple(dict(s, label=t(s["label"])) if s.get("label") else s for s in spec.series)
    return attrs.evolve(
        spec, title=t(spec.title), xlabel=t(spec.xlabel), ylabel=t(spec.ylabel), series=series
    )


def display_width(text: str) -> int:
    """Columns a text takes in the figure's font: a CJK character is as wide as two Latin ones."""
    return len(text) + len(_CJK.findall(text))


def title_lines(title: str, width: int = 70) -> list[str]:
    """The title wrapped to ``width`` columns of :func:`display_width` (a zh+en title wrapped by
    characters ran past the figure's edge and was clipped: "Scale factor: m")."""
    import textwrap

    lines: list[str] = []
    for line in textwrap.wrap(title, width):
        while display_width(line) > width:
            cut = len(line)
            while cut > 1 and display_width(line[:cut]) > width:
                cut -= 1
            sp = line.rfind(" ", 0, cut)
            cut = sp if sp > 0 else cut
            lines.append(line[:cut].rstrip())
            line = line[cut:].lstrip()
        lines.append(line)
    return lines


def plot_text(text: str) -> str:
    """Figure text with real subscripts: ``K_i`` → mathtext ``$\\mathregular{K_{i}}$`` (drawn
    in the text's own font), other text unchanged; ``$`` already present is left alone.

    >>> plot_text("K_i against rate"), plot_text("rate_table"), plot_text("cost $5")
    ('$\\mathregular{K_{i}}$ against rate', 'rate_table', 'cost $5')
    >>> plot_text("残差 v_i（mV）"), plot_text("温度 T_{ref}")
    ('残差 vᵢ（mV）', '温度 T_{ref}')
    """
    if "$" in text:
        return text
    if _CJK.search(text):
        # mathtext draws the whole string in its own font, which has no CJK glyphs (the zh title of
        # JJF 2014's
        # residual figure printed as boxes): Unicode subscripts where every character has one, else
        # as written
        def uni(m):
            sub = m.group(2).strip("{}")
            return (
                m.group(1) + "".join(_UNI_SUB[c] for c in sub)
                if all(c in _UNI_SUB for c in sub)
                else m.group(0)
            )

        return _SUBSCRIPT.sub(uni, text)
    return _SUBSCRIPT.sub(
        lambda m: "$\\mathregular{" + m.group(1) + "_{" + m.group(2).strip("{}") + "}}$", text
    )


def _axis_formatters(ax, spec: "PlotSpec") -> None:
    """No offset notation ("1e−6+8e−1"): plain numbers, a ×10ⁿ factor only when the numbers are
    large or small; on a log axis, labels on the decades only (minor ticks unlabelled)."""
    from matplotlib.ticker import LogLocator, NullFormatter, ScalarFormatter

    for axis, log in ((ax.xaxis, spec.logx), (ax.yaxis, spec.logy)):
        if log:
            axis.set_major_locator(LogLocator(base=10, numticks=8))
            axis.set_minor_locator(LogLocator(base=10, subs=tuple(range(2, 10)), numticks=12))
            axis.set_minor_formatter(NullFormatter())
        else:
            fmt = ScalarFormatter(useOffset=False, useMathText=True)
            fmt.set_powerlimits((-3, 4))
            axis.set_major_formatter(fmt)


def _draw(fig, spec: "PlotSpec") -> None:
    """Draw ``spec`` on an empty figure."""
    ax = fig.add_subplot()
    labelled = False
    for i, s in enumerate(spec.series):
        if s.get("label"):
            s = dict(s, label=plot_text(str(s["label"])))
        labelled = _draw_series(ax, s, i) or labelled
    if spec.logx:
        ax.set_xscale("log")
    if spec.logy:
        ax.set_yscale("log")
    _axis_formatters(ax, spec)
    ax.set_xlabel(plot_text(spec.xlabel))
    ax.set_ylabel(plot_text(spec.ylabel))
    if spec.title:
        ax.set_title(plot_text("\n".join(title_lines(spec.title))), fontsize="medium")
    ax.grid(True, which="major", linewidth=0.6, alpha=0.5)
    if spec.logx or spec.logy:
        ax.grid(True, which="minor", linewidth=0.4, alpha=0.25)
    if labelled:
        ax.legend(fontsize="small")


#: resolution of the figures in documents (300 dpi: print quality at 15 cm wide)
DPI = 300


def render_png(spec: "PlotSpec", path: str | os.PathLike[str], *, dpi: int = DPI) -> Path:
    """Draw ``spec`` and write it as a PNG to ``path`` (atomically); return ``path``.

    Log axes as ``spec.logx`` / ``spec.logy`` ask (non-positive values are not drawn on a
    log axis), a grid, the axis labels, the title and a legend when a series has a label.
    """
    data = png_bytes(spec, dpi=dpi)
    return atomic_write(path, lambda tmp: Path(tmp).write_bytes(data))


#: one Agg renderer per (width, height, dpi), kept between figures, and the lock drawing on it takes
_RENDERERS: dict[tuple, Any] = {}
_DRAWING = threading.Lock()


@functools.lru_cache(maxsize=1)
def _canvas_class() -> type:
    """An Agg canvas that draws on the renderer of its size kept from the figures before (the
    buffer is cleared for each figure): matplotlib keeps its text measurements and parsed
    mathtext per renderer, and a document's figures repeat their tick labels, so each new
    renderer measured and parsed them again (about 15 % of drawing a figure; the same pixels)."""
    from matplotlib.backends.backend_agg import FigureCanvasAgg, RendererAgg

    class KeptRendererCanvas(FigureCanvasAgg):
        def get_renderer(self):
            w, h = self.get_width_height(physical=True)
            key = (w, h, self.figure.dpi)
            renderer = _RENDERERS.get(key)
            if renderer is None:
                if len(_RENDERERS) >= 4:  # a few sizes at most (tests draw small ones)
                    _RENDERERS.clear()
                renderer = _RENDERERS[key] = RendererAgg(w, h, self.figure.dpi)
            return renderer

    return KeptRendererCanvas


def png_bytes(spec: "PlotSpec", *, dpi: int = DPI) -> bytes:
    """The PNG :func:`render_png` writes, as bytes (a document's figures go into its own temporary
    folder, where an atomic, synced write buys nothing)."""
    import matplotlib
    from matplotlib.figure import Figure

    # the families as font.family itself: matplotlib falls back glyph by glyph only along that list
    # (with the generic "sans-serif" a Chinese title drew as empty boxes)
    with _DRAWING, matplotlib.rc_context({"font.family": font_families()}), MissingGlyphs():
        fig = Figure(figsize=FIGSIZE_IN, dpi=dpi, layout="constrained")
        canvas = _canvas_class()(fig)  # Agg canvas: no GUI backend, nothing registered with pyplot
        _draw(fig, spec)
        # drawn once (savefig with a layout engine lays the figure out and draws it twice, for the
        # same
        # pixels), then the canvas's buffer written as a PNG: the pixels savefig writes
        # (FigureCanvasAgg.print_png,
        # imsave of that buffer), encoded faster (png_encode; the same pixels:
        # tests/core/documents/test_figure_cache.py)
        canvas.draw()
        return png_encode(
            canvas.buffer_rgba(),
            dpi=fig.dpi,
            text={
                "Software": f"Matplotlib version{matplotlib.__version__}, https://matplotlib.org/"
            },
        )


def _chunk(kind: bytes, data: bytes) -> bytes:
    import struct
    import zlib

    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))


def png_encode(rgba: Any, *, dpi: float, text: Mapping[str, str] | None = None) -> bytes:
    """A PNG of an 8-bit RGBA image (``rgba``: height × width × 4, e.g. the Agg canvas's buffer):
    the pixels as they are (lossless; the same pixels as ``matplotlib.image.imsave``, which savefig
    uses), the resolution ``dpi`` (``pHYs``), ``text`` as ``tEXt`` chunks.

    Every row is stored with the PNG filter "Up" (the difference from the row above: a figure's
    white space, grid lines and axes become runs of zeros) and deflated at zlib's default level 6.
    Pillow, which ``imsave`` calls, tries all five filters on every row and keeps the best; for a
    300 dpi figure that took 65 ms, the row differences in numpy and zlib take 25–30 ms for a file
    about 5 % smaller (docs/performance.md, "Writing documents")."""
    import struct
    import zlib

    import numpy as np

    pixels = np.asarray(rgba, dtype=np.uint8)
    if pixels.ndim != 3 or pixels.shape[2] != 4:
        raise ValueError(f"png_encode needs height × width × 4 (RGBA) pixels, not {pixels.shape}")
    h, w, _ = pixels.shape
    rows = pixels.reshape(h, w * 4)
    raw = np.empty((h, w * 4 + 1), dtype=np.uint8)
    # filter type 2, "Up": each byte minus the byte above it (modulo 256), 0 above the first row
    raw[:, 0] = 2
    raw[0, 1:] = rows[0]
    np.subtract(rows[1:], rows[:-1], out=raw[1:, 1:])
    ppm = int(dpi / 0.0254 + 0.5)  # pixels per metre, rounded as Pillow rounds it
    parts = [b"\x89PNG\r\n\x1a\n", _chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 6, 0, 0, 0))]
    parts += [
        _chunk(b"tEXt", k.encode("latin-1") + b"\0" + v.encode("latin-1"))
        for k, v in (text or {}).items()
    ]
    parts += [
        _chunk(b"pHYs", struct.pack(">IIB", ppm, ppm, 1)),
        _chunk(b"IDAT", zlib.compress(raw.data, 6)),
        _chunk(b"IEND", b""),
    ]
    return b"".join(parts)

"""Render a :class:`~metro.core.model.PlotSpec` to a PNG file with matplotlib.

Procedures only *describe* figures (a :class:`PlotSpec`: title, axis labels, series);
this module draws them.  matplotlib is imported inside :func:`render_png`, so importing
this module costs nothing.  Drawing uses matplotlib's object interface with the Agg
canvas: no GUI backend, no display, and no change to the global pyplot state of a
program (or notebook) that imported metro — nothing is left open after a call.

A series is a mapping with the keys

* ``x``, ``y`` — sequences of numbers (or pint quantities, whose magnitudes are used);
* ``label`` — legend text (optional);
* ``style`` — ``"o"`` markers (with error bars when ``yerr`` is given), ``"-"`` a solid
  line, ``"--"`` a dashed line; any other matplotlib format string is passed through;
  default ``"-"``;
* ``yerr`` — optional symmetric error bars (one value per point, or one for all).

Labels may use any character of DejaVu Sans (matplotlib's default font), which covers the
field's symbols: ° √ τ α ν σ χ ₀…₉ ² ″.  Chinese text needs a CJK font on the machine
(one of :data:`FALLBACK_FONTS`); without one matplotlib warns and draws boxes.
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import TYPE_CHECKING, Any, Mapping

from .atomic import atomic_write

if TYPE_CHECKING:  # pragma: no cover
    from .model import PlotSpec

__all__ = ["render_png", "FIGSIZE_IN", "FALLBACK_FONTS"]

#: Figure size in inches (about 16 cm × 10 cm: printed at 15 cm wide in reports).
FIGSIZE_IN = (6.3, 3.9)

_MARKER_STYLES = frozenset({"o", "s", "^", "v", "D", "x", "+", "."})

#: Fonts tried after DejaVu Sans for characters it lacks (Chinese titles), when installed.
FALLBACK_FONTS = ("Noto Sans CJK SC", "Noto Sans SC", "Source Han Sans SC", "WenQuanYi Zen Hei",
                  "WenQuanYi Micro Hei", "SimHei", "Microsoft YaHei", "PingFang SC")


def _font_families() -> list[str]:
    """DejaVu Sans first, then the installed fallback fonts (matplotlib ≥ 3.6 falls back per glyph)."""
    from matplotlib import font_manager

    installed = {f.name for f in font_manager.fontManager.ttflist}
    return ["DejaVu Sans"] + [f for f in FALLBACK_FONTS if f in installed]


def _values(v: Any) -> Any:
    """Plain numbers from a sequence, a numpy array or a pint quantity."""
    import numpy as np

    mag = getattr(v, "magnitude", v)
    return np.asarray(mag, dtype=float)


def _draw_series(ax, s: Mapping[str, Any], index: int) -> bool:
    """Draw one series on ``ax``; return whether it has a legend label."""
    if "x" not in s or "y" not in s:
        raise ValueError(f"plot series {index} needs 'x' and 'y' (has: {', '.join(map(str, s)) or 'nothing'})")
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
            ax.errorbar(x, y, yerr=_values(yerr), fmt=style, markersize=4, capsize=3,
                        elinewidth=0.8, label=label)
        else:
            ax.plot(x, y, style, markersize=4, label=label)
    elif style == "-":
        ax.plot(x, y, linestyle="-", linewidth=1.4, label=label)
    elif style == "--":
        ax.plot(x, y, linestyle="--", linewidth=1.2, label=label)
    else:
        ax.plot(x, y, style, label=label)  # any other matplotlib format string
    return label is not None


def _draw(fig, spec: "PlotSpec") -> None:
    """Draw ``spec`` on an empty figure."""
    ax = fig.add_subplot()
    labelled = False
    for i, s in enumerate(spec.series):
        labelled = _draw_series(ax, s, i) or labelled
    if spec.logx:
        ax.set_xscale("log")
    if spec.logy:
        ax.set_yscale("log")
    ax.set_xlabel(spec.xlabel)
    ax.set_ylabel(spec.ylabel)
    if spec.title:
        ax.set_title(spec.title)
    ax.grid(True, which="major", linewidth=0.6, alpha=0.5)
    if spec.logx or spec.logy:
        ax.grid(True, which="minor", linewidth=0.4, alpha=0.25)
    if labelled:
        ax.legend(fontsize="small")


def render_png(spec: "PlotSpec", path: str | os.PathLike[str], *, dpi: int = 150) -> Path:
    """Draw ``spec`` and write it as a PNG to ``path`` (atomically); return ``path``.

    Log axes as ``spec.logx`` / ``spec.logy`` ask (non-positive values are not drawn on a
    log axis), a grid, the axis labels, the title and a legend when a series has a label.
    """
    import matplotlib
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    with matplotlib.rc_context({"font.family": "sans-serif", "font.sans-serif": _font_families()}):
        fig = Figure(figsize=FIGSIZE_IN, dpi=dpi, layout="constrained")
        FigureCanvasAgg(fig)  # Agg canvas: no GUI backend, nothing registered with pyplot
        _draw(fig, spec)
        return atomic_write(path, lambda tmp: fig.savefig(tmp, format="png", dpi=dpi))

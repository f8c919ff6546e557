"""A cache of drawn figures, so a document written again draws none of them twice.

Drawing a figure (:func:`metro.core.plots.png_bytes`: matplotlib lays it out, renders it and
compresses the PNG) is most of the time a report takes to write: 0.2–0.3 s a figure, eight in a
GB/T 45570 ``--all`` report.  ``metro report NUMBER`` and ``metro amend`` write a registered
report again from its stored context, whose figures are the same ones: this cache gives their
PNG back without drawing.

The key is the SHA-256 of everything the pixels depend on: the figure's own text and numbers
(after translation), the resolution and size, the source of :mod:`metro.core.plots`, the
versions of matplotlib and Pillow, matplotlib's settings (``rcParams``) and the font files of the
families drawn with.  A changed input is a new key, never a stale image.

The files live in ``<user cache>/metro/figures/`` (``METRO_CACHE_DIR`` overrides the user cache
folder, as for pint's definitions); at most :data:`MAX_FILES` are kept, the least recently used go
first.  ``METRO_FIGURE_CACHE=off`` draws every figure every time.  A cache that cannot be read or
written only costs the drawing time: nothing is printed.
"""

from __future__ import annotations

import hashlib
import os
from pathlib import Path
from typing import TYPE_CHECKING

if TYPE_CHECKING:  # pragma: no cover
    from .model import PlotSpec

__all__ = ["cached_png", "cache_folder", "figure_key", "MAX_FILES"]

#: figures kept (about 110 kB each at 300 dpi); beyond it the least recently used are removed
MAX_FILES = 1000
#: bump when the key's contents change meaning
FORMAT = "metro-figure/1"

_PNG_HEAD = b"\x89PNG\r\n\x1a\n"
_PNG_TAIL = b"IEND\xaeB`\x82"


def cache_folder() -> Path | None:
    """``<user cache>/metro/figures`` (or ``$METRO_CACHE_DIR/figures``); None when
    ``METRO_FIGURE_CACHE`` is ``off`` (or ``0``, ``no``, ``false``)."""
    if os.environ.get("METRO_FIGURE_CACHE", "").strip().lower() in ("off", "0", "no", "false"):
        return None
    root = os.environ.get("METRO_CACHE_DIR")
    if root:
        return Path(root) / "figures"
    import platformdirs

    return platformdirs.user_cache_path(appname="metro", appauthor=False) / "figures"


def _environment(dpi: int) -> bytes:
    """What every figure's pixels depend on besides its own content."""
    import matplotlib
    import PIL
    from matplotlib import font_manager

    from . import plots

    families = plots.font_families()
    fonts = sorted({(f.fname, _stat(f.fname)) for f in font_manager.fontManager.ttflist if f.name in families})
    # the settings as stored (dict.items): reading rcParams["backend"] through the mapping would
    # resolve the backend, importing pyplot (1 s)
    rc = sorted((k, repr(v)) for k, v in dict.items(matplotlib.rcParams) if k != "backend")
    parts = [FORMAT, str(dpi), repr(plots.FIGSIZE_IN), matplotlib.__version__, PIL.__version__,
             repr(families), repr(fonts), repr(rc), _source_digest()]
    return "\x00".join(parts).encode("utf-8")


def _stat(path: str) -> tuple[int, int]:
    try:
        st = os.stat(path)
    except OSError:
        return (0, 0)
    return (st.st_size, st.st_mtime_ns)


def _source_digest() -> str:
    from . import plots

    return hashlib.sha256(Path(plots.__file__).read_bytes()).hexdigest()


def figure_key(spec: "PlotSpec", *, dpi: int) -> str:
    """The SHA-256 naming the PNG of ``spec`` (its text as drawn, its numbers as float64) at ``dpi``."""
    import numpy as np

    h = hashlib.sha256(_environment(dpi))
    h.update(repr((str(spec.title), str(spec.xlabel), str(spec.ylabel), bool(spec.logx), bool(spec.logy),
                   len(spec.series))).encode("utf-8"))
    for s in spec.series:
        for k in sorted(s, key=str):
            v = s[k]
            if k in ("x", "y", "yerr") and v is not None:
                a = np.asarray(getattr(v, "magnitude", v), dtype=float)
                h.update(f"\x00{k}{a.shape}".encode("utf-8"))
                h.update(np.ascontiguousarray(a).tobytes())
            else:
                h.update(f"\x00{k}={v!s}".encode("utf-8"))
    return h.hexdigest()


def _read(path: Path) -> bytes | None:
    try:
        data = path.read_bytes()
    except OSError:
        return None
    if not (data.startswith(_PNG_HEAD) and data.endswith(_PNG_TAIL)):
        return None  # cut short (a crash while writing it): drawn again
    try:
        os.utime(path)  # recently used
    except OSError:
        pass
    return data


def _write(folder: Path, path: Path, data: bytes) -> None:
    try:
        folder.mkdir(parents=True, exist_ok=True)
        tmp = path.with_name(f"{path.name}.{os.getpid()}.tmp")
        tmp.write_bytes(data)
        os.replace(tmp, path)
    except OSError:
        return
    _prune(folder)


def _prune(folder: Path, keep: int | None = None) -> None:
    """At most ``keep`` (:data:`MAX_FILES`) figures: the least recently used beyond it removed."""
    keep = MAX_FILES if keep is None else keep
    try:
        entries = list(os.scandir(folder))
    except OSError:
        return
    if len(entries) <= keep:
        return
    stamped = []
    for e in entries:
        try:
            stamped.append((e.stat().st_mtime_ns, e.path))
        except OSError:
            continue
    stamped.sort()
    for _, p in stamped[:len(stamped) - int(keep * 0.8)]:
        try:
            os.remove(p)
        except OSError:
            pass


def cached_png(spec: "PlotSpec", *, dpi: int | None = None) -> bytes:
    """The PNG of ``spec`` (:func:`metro.core.plots.png_bytes`), from the cache when it was drawn
    before with the same inputs, else drawn now and kept."""
    from . import plots

    dpi = plots.DPI if dpi is None else dpi
    folder = cache_folder()
    if folder is None:
        return plots.png_bytes(spec, dpi=dpi)
    path = folder / f"{figure_key(spec, dpi=dpi)}.png"
    data = _read(path)
    if data is None:
        data = plots.png_bytes(spec, dpi=dpi)
        _write(folder, path, data)
    return data

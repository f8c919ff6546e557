"""A cache of drawn figures, so a document written again draws none of them twice.

Drawing a figure (:func:`metro.core.documents.plots.png_bytes`: matplotlib lays it out, renders it
and compresses the PNG) is most of the time a report takes to write: 0.2–0.3 s a figure, eight in a
GB/T 45570 ``--all`` report. ``metro report NUMBER`` and ``metro amend`` write a registered report
again from its stored context, whose figures are the same ones: this cache gives their PNG back
without drawing.

The key is the SHA-256 of everything the pixels depend on: the figure's own text and numbers
(after translation), the resolution and size, the source of :mod:`metro.core.documents.plots`, the
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
from typing import TYPE_CHECKING, Self

if TYPE_CHECKING:  # pragma: no cover
    from ..model.results import PlotSpec

__all__ = ["MAX_FILES", "DrawingAhead", "cache_folder", "cached_png", "figure_key", "spec_digest"]

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
    fonts = sorted({(f.fname, _stat(f.fname)) for f in font_manager.fontManager.ttflist if f.name
                    in families})
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


def spec_digest(spec: PlotSpec, *, dpi: int) -> str:
    """The SHA-256 of a figure's own content — its text as drawn, its numbers as float64 — and
    ``dpi``: what :func:`figure_key` adds to the drawing environment. Reading it imports nothing."""
    import numpy as np

    h = hashlib.sha256(f"{FORMAT}\x00{dpi}".encode())
    h.update(repr((str(spec.title), str(spec.xlabel), str(spec.ylabel), bool(spec.logx),
                   bool(spec.logy),
                   len(spec.series))).encode("utf-8"))
    for s in spec.series:
        for k in sorted(s, key=str):
            v = s[k]
            if k in ("x", "y", "yerr") and v is not None:
                a = np.asarray(getattr(v, "magnitude", v), dtype=float)
                h.update(f"\x00{k}{a.shape}".encode())
                h.update(np.ascontiguousarray(a).tobytes())
            else:
                h.update(f"\x00{k}={v!s}".encode())
    return h.hexdigest()


def figure_key(spec: PlotSpec, *, dpi: int) -> str:
    """The SHA-256 naming the PNG of ``spec`` at ``dpi``: its content (:func:`spec_digest`) drawn
    in this environment (matplotlib, Pillow, settings, fonts, the drawing code)."""
    h = hashlib.sha256(_environment(dpi))
    h.update(spec_digest(spec, dpi=dpi).encode("ascii"))
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


def cached_png(spec: PlotSpec, *, dpi: int | None = None) -> bytes:
    """The PNG of ``spec`` (:func:`metro.core.documents.plots.png_bytes`): drawn ahead by the active
    :class:`DrawingAhead`, else from the cache when it was drawn before with the same inputs,
    else drawn now and kept."""
    from . import plots

    dpi = plots.DPI if dpi is None else dpi
    if _AHEAD:
        data = _AHEAD[-1].take(spec, dpi=dpi)
        if data is not None:
            return data
    folder = cache_folder()
    if folder is None:
        return plots.png_bytes(spec, dpi=dpi)
    path = folder / f"{figure_key(spec, dpi=dpi)}.png"
    data = _read(path)
    if data is None:
        data = plots.png_bytes(spec, dpi=dpi)
        _write(folder, path, data)
    return data


#: the :class:`DrawingAhead` in force (a stack: the innermost is asked first)
_AHEAD: list[DrawingAhead] = []


def _warm() -> bool:
    """Run first in the drawing process: matplotlib and the fonts loaded before any figure is asked
    for."""
    from matplotlib.figure import Figure  # noqa: F401  (imported for its import time)

    from . import plots

    plots.font_families()
    return True


def _draw(spec: PlotSpec, dpi: int) -> bytes:
    """In the drawing process: the figure's PNG, through the cache (which it fills)."""
    return cached_png(spec, dpi=dpi)


class DrawingAhead:
    """Figures drawn in a second process while the run's items are still being evaluated.

    A GB/T 45570 ``--all`` run evaluates its items for about 1.7 s and then drew its eight figures
    for about 1.5 s more, one core idle all the while.  Used as a context manager, this object
    draws each figure :meth:`submit` is given in one worker process (the standard library's
    :class:`concurrent.futures.ProcessPoolExecutor`, started with ``spawn`` so no thread of the
    run is copied), and :func:`cached_png` takes the PNG from it when the document asks for the
    same figure (same :func:`spec_digest`).  The worker draws with the same code, fonts and
    settings, through the same cache, so the pixels are the ones drawn in-process would be.

    It never makes a document wait for the worker to start: a figure asked for before the worker
    is ready, or one the worker failed on, is drawn in-process as before.  Dask is not used: it
    is an optional extra, and starting a cluster takes longer than the drawing it would save.

    >>> with DrawingAhead(enabled=False) as ahead:
    ...     ahead.take_count
    0
    """

    def __init__(self, *, enabled: bool = True) -> None:
        self.enabled = enabled and _can_draw_ahead()
        self._pool = None
        self._ready = None
        self._futures: dict[str, object] = {}
        #: figures the document took from the worker
        self.take_count = 0

    def __enter__(self) -> Self:
        _AHEAD.append(self)
        self._start()
        return self

    def _start(self) -> None:
        """Start the worker now, so it has loaded matplotlib by the time the first item is done."""
        if not self.enabled or self._pool is not None:
            return
        import multiprocessing
        import sys
        import types
        from concurrent.futures import ProcessPoolExecutor

        main = sys.modules.get("__main__")
        try:
            self._pool = ProcessPoolExecutor(max_workers=1,
                                             mp_context=multiprocessing.get_context("spawn"))
            # the worker needs nothing of the caller's main module: a "spawn" child would import it
            # again, and a caller's script without an ``if __name__ == "__main__"`` guard would run
            # its whole work twice.  The process starts inside this first submit (3.11: spawn
            # children are started by submit itself).
            sys.modules["__main__"] = types.ModuleType("__main__")
            self._ready = self._pool.submit(_warm)
        except Exception:  # noqa: BLE001 — no worker (no /dev/shm, process limit): drawn in-process
            self.enabled = False
            self._pool = None
        finally:
            if main is not None:
                sys.modules["__main__"] = main

    def __exit__(self, *exc: object) -> None:
        _AHEAD.remove(self)
        self.close()

    def submit(self, spec: PlotSpec, *, dpi: int | None = None) -> None:
        """Have ``spec`` (as the document will draw it: localized) drawn by the worker."""
        if not self.enabled:
            return
        from . import plots

        dpi = plots.DPI if dpi is None else dpi
        digest = spec_digest(spec, dpi=dpi)
        if digest in self._futures:
            return
        if self._pool is None:
            self._start()
        if self._pool is None:
            return
        try:
            self._futures[digest] = self._pool.submit(_draw, spec, dpi)
        except Exception:  # noqa: BLE001 — the worker is gone: drawn in-process
            self.enabled = False

    def take(self, spec: PlotSpec, *, dpi: int) -> bytes | None:
        """The PNG the worker drew for ``spec``, waiting for it when the worker is drawing it; None
        (drawn in-process) when it was not submitted, the worker has not started on it (it is
        taken back), the worker is not ready yet, or it failed."""
        future = self._futures.pop(spec_digest(spec, dpi=dpi), None) if self._futures else None
        if future is None or future.cancel() or self._ready is None or not self._ready.done():
            return None
        try:
            data = future.result()
        except Exception:  # noqa: BLE001 — the worker failed or was stopped: drawn in-process
            return None
        self.take_count += 1
        return data

    def close(self) -> None:
        """Stop the worker: figures not drawn yet are dropped, the one being drawn is finished."""
        if self._pool is not None:
            self._pool.shutdown(wait=False, cancel_futures=True)
            self._pool = None
        self._futures.clear()


def _can_draw_ahead() -> bool:
    """A second process helps: two cores or more, not turned off (``METRO_DRAW_AHEAD=off``), and
    this process may start one (a daemonic process, e.g. a multiprocessing worker, may not)."""
    import multiprocessing

    if os.environ.get("METRO_DRAW_AHEAD", "").strip().lower() in ("off", "0", "no", "false"):
        return False
    if (os.cpu_count() or 1) < 2:
        return False
    return not multiprocessing.current_process().daemon

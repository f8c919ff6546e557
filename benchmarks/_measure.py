"""Timing and peak-memory helper shared by metro's benchmark scripts (not a test).

``measure(fn, *args, **kwargs)`` runs ``fn`` ``repeat`` times untraced and reports the best
wall-clock and CPU time, then runs it once more with memory tracing and reports the peak
*extra* memory of that call, measured two ways:

* ``peak_traced`` -- tracemalloc's peak above the traced size at the start of the call.
  numpy reports its data buffers to tracemalloc, so this counts every numpy array the
  call allocates (including temporaries freed before it returns) and Python objects, but
  not memory allocated outside Python's tracing (numba's NRT allocations, BLAS buffers).
* ``peak_rss`` -- the kernel's resident-set high-water mark (VmHWM, reset through
  /proc/self/clear_refs before the call) minus the RSS at the start.  It counts every
  allocation that is touched, from any allocator; it is None where /proc is unavailable.
  Freed memory returned to the allocator but not to the OS can make it read low for a
  second call that reuses it, so treat it as a cross-check.

The timed runs are not traced (tracemalloc slows allocation-heavy Python code).
"""

from __future__ import annotations

import gc
import os
import time
import tracemalloc
from collections.abc import Callable
from dataclasses import dataclass, field
from typing import Any

__all__ = ["Measurement", "format_table", "measure", "reset_peak_rss", "rss_bytes"]

MiB = 1024.0 * 1024.0


def _status_kb(key: str) -> int | None:
    try:
        with open("/proc/self/status") as fh:
            for line in fh:
                if line.startswith(key + ":"):
                    return int(line.split()[1]) * 1024
    except OSError:
        return None
    return None


def rss_bytes() -> int | None:
    """Current resident set size of this process (None if /proc is unavailable)."""
    return _status_kb("VmRSS")


def reset_peak_rss() -> bool:
    """Reset this process's peak RSS (VmHWM, Linux); False where it cannot be.  ``ru_maxrss``
    cannot serve instead: it survives fork and exec, so a child would report its parent's peak."""
    try:
        with open("/proc/self/clear_refs", "w") as fh:
            fh.write("5")
        return True
    except OSError:
        return False


@dataclass
class Measurement:
    """Outcome of :func:`measure` (times in seconds, memory in bytes)."""

    label: str
    wall: float
    cpu: float
    walls: list[float] = field(default_factory=list)
    peak_traced: int | None = None
    peak_rss: int | None = None
    result: Any = None

    def row(self, input_bytes: int | None = None, ref_wall: float | None = None) -> list[str]:
        def mib(v: int | None) -> str:
            return "n/a" if v is None else f"{v / MiB:,.0f}"

        ratio = "n/a"
        if input_bytes and self.peak_traced is not None:
            ratio = f"{self.peak_traced / input_bytes:.2f}x"
        speed = "" if not ref_wall else f"{ref_wall / self.wall:.1f}x"
        return [
            self.label,
            f"{self.wall:.3f}",
            f"{self.cpu:.3f}",
            mib(self.peak_traced),
            mib(self.peak_rss),
            ratio,
            speed,
        ]


def measure(
    fn: Callable[..., Any],
    *args: Any,
    label: str = "",
    repeat: int = 3,
    warmup: int = 0,
    memory: bool = True,
    **kwargs: Any,
) -> Measurement:
    """Time ``fn(*args, **kwargs)`` (best of ``repeat``) and measure its peak extra memory.

    ``warmup`` untimed calls run first (JIT compilation, caches).  With ``memory=True`` an
    additional traced call measures the peak extra memory; the result of the last call is
    kept in ``Measurement.result``.
    """
    for _ in range(warmup):
        fn(*args, **kwargs)
    walls: list[float] = []
    cpus: list[float] = []
    result = None
    for _ in range(max(repeat, 0)):
        result = None
        gc.collect()
        t0, c0 = time.perf_counter(), time.process_time()
        result = fn(*args, **kwargs)
        walls.append(time.perf_counter() - t0)
        cpus.append(time.process_time() - c0)
    m = Measurement(
        label=label or getattr(fn, "__name__", "fn"),
        wall=min(walls) if walls else float("nan"),
        cpu=min(cpus) if cpus else float("nan"),
        walls=walls,
        result=result,
    )
    if memory:
        result = None
        m.result = None
        gc.collect()
        rss0 = rss_bytes()
        hwm_ok = reset_peak_rss()
        started = not tracemalloc.is_tracing()
        if started:
            tracemalloc.start()
        tracemalloc.reset_peak()
        base, _ = tracemalloc.get_traced_memory()
        t0, c0 = time.perf_counter(), time.process_time()
        result = fn(*args, **kwargs)
        if not walls:
            m.wall, m.cpu = time.perf_counter() - t0, time.process_time() - c0
        _, peak = tracemalloc.get_traced_memory()
        if started:
            tracemalloc.stop()
        m.peak_traced = peak - base
        hwm = _status_kb("VmHWM")
        if hwm_ok and hwm is not None and rss0 is not None:
            m.peak_rss = max(0, hwm - rss0)
        m.result = result
    return m


def format_table(rows: list[list[str]], header: list[str]) -> str:
    """Plain-text (Markdown-compatible) table."""
    widths = [max(len(str(r[i])) for r in [header, *rows]) for i in range(len(header))]

    def line(r: list[str]) -> str:
        return "| " + " | ".join(str(c).ljust(w) for c, w in zip(r, widths)) + " |"

    sep = "|" + "|".join("-" * (w + 2) for w in widths) + "|"
    return "\n".join([line(header), sep, *(line(r) for r in rows)])


if __name__ == "__main__":  # tiny self-check
    import numpy as np

    r = measure(lambda: np.ones(10_000_000).sum(), label="ones+sum", repeat=2)
    print(
        format_table([r.row()], ["what", "wall s", "cpu s", "traced MiB", "rss MiB", "x input", ""])
    )
    print("pid", os.getpid())

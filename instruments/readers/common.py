"""What every samples-file reader shares: the formats, :class:`SampleTable`, the header cell
rule, the background digest, and the checks of values and of the time column."""

from __future__ import annotations

import hashlib
import math
import os
import re
import threading
from collections.abc import Iterable, Iterator, Mapping, Sequence
from contextlib import contextmanager
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from metro.core.base.errors import DataError, UnitError


#: File suffix -> format name.  ``.txt`` is tab-separated unless its header says otherwise.
FORMATS = {
    ".csv": "csv",
    ".tsv": "tsv",
    ".txt": "tsv",
    ".npy": "npy",
    ".parquet": "parquet",
    ".pq": "parquet",
}

_CELL = re.compile(r"^\s*(?P<name>[^\[\]]*?)\s*\[(?P<unit>[^\[\]]*)\]\s*$")
MAX_EXACT_INT = 2**53
_CHECK_ROWS = 1 << 16  # rows per NaN/Inf and time-step check (fits in L2 cache)
_HASH_BUFFER = 1 << 20
_RELEASE_BYTES = 64 << 20  # return freed pyarrow memory to the OS every this many bytes


# --------------------------------------------------------------------------- result type


def _columns_repr(columns: Mapping[str, np.ndarray]) -> str:
    return "{" + ", ".join(f"{k!r}: <{v.shape[0]} x {v.dtype}>" for k, v in columns.items()) + "}"


class Digest:
    """SHA-256 of a file's bytes, computed in a daemon thread; ``result()`` waits for it.

    The file is opened when the thread starts; its (device, inode, size, mtime) must
    equal ``key``, the values seen when the read began, before and after hashing.
    """

    def __init__(self, path: Path, key: tuple[int, ...]) -> None:
        self._path = path
        self._key = key
        self._value: str | None = None
        self._error: BaseException | None = None
        self._cancelled = threading.Event()
        self._thread = threading.Thread(target=self._run, name="metro-sha256", daemon=True)

    def start(self) -> None:
        if self._thread.ident is None:
            self._thread.start()

    def _run(self) -> None:
        try:
            digest = hashlib.sha256()
            buf = bytearray(_HASH_BUFFER)
            view = memoryview(buf)
            with open(self._path, "rb", buffering=0) as f:
                if stat_key(os.fstat(f.fileno())) != self._key:
                    raise changed_error(self._path)
                while n := f.readinto(view):
                    if self._cancelled.is_set():
                        return
                    digest.update(view[:n])  # releases the GIL
                if stat_key(os.fstat(f.fileno())) != self._key:
                    raise changed_error(self._path)
            self._value = digest.hexdigest()
        except BaseException as exc:  # reported by result()
            self._error = exc

    def cancel(self) -> None:
        self._cancelled.set()

    def result(self) -> str:
        self.start()
        self._thread.join()
        if self._error is not None:
            if isinstance(self._error, DataError):
                raise self._error
            raise DataError(
                self._path, None, f"cannot read the file to hash it: {self._error}"
            ) from self._error
        if self._value is None:
            raise DataError(self._path, None, "hashing was cancelled")
        return self._value

    def __repr__(self) -> str:
        if self._thread.ident is None or self._thread.is_alive():
            return "<sha256 pending>"
        return repr(self._value) if self._error is None else "<sha256 failed>"


@attrs.frozen(eq=False)
class SampleTable:
    """One segment's samples.

    ``columns`` maps the column name (without unit) to a read-only 1-D float64 array, in
    file order (or the order requested); ``units`` maps the same names to the unit text
    exactly as written.  ``sha256`` is the hex digest of the raw file bytes (see the
    module notes: it may still be computing when the table is returned and is waited for
    on first access).  ``sample_interval_s`` is the sampling interval in the time column's
    own unit: the median time step (for uniformly sampled records, where every step is
    within ``rel_interval_tol`` of every other, the mean step); None without a time column
    or with fewer than two rows.
    """

    path: Path
    columns: dict[str, np.ndarray] = attrs.field(repr=_columns_repr)
    units: dict[str, str]
    _sha256: str | Digest = attrs.field(alias="sha256")
    n_rows: int
    format: str
    sample_interval_s: float | None = None

    @property
    def sha256(self) -> str:
        """Hex SHA-256 of the file's bytes (waits for the background hash if needed)."""
        if isinstance(self._sha256, Digest):
            return self._sha256.result()
        return self._sha256

    @property
    def names(self) -> tuple[str, ...]:
        return tuple(self.columns)

    def __getitem__(self, name: str) -> np.ndarray:
        return self.columns[name]

    def header_cell(self, name: str) -> str:
        """``'name [unit]'`` as it appears in the file header."""
        return f"{name} [{self.units[name]}]"


# --------------------------------------------------------------------------- helpers


def parse_header_cell(cell: str) -> tuple[str, str] | None:
    """Split ``'rate [°/h]'`` into ``('rate', '°/h')``; None if the cell is not of that form."""
    m = _CELL.match(cell)
    if m is None or not m.group("name"):
        return None
    return m.group("name"), m.group("unit")


def stat_key(st: os.stat_result) -> tuple[int, ...]:
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def changed_error(path: Path) -> DataError:
    return DataError(
        path,
        None,
        "the file changed while it was being read",
        hint="read it again once the program writing it has finished "
        "(writers should replace files atomically)",
    )


def cell_field(cell: str, row: int) -> str:
    return f"{cell}, row {row}"


def _fmt(x: float) -> str:
    """A sample value for a message: the shortest text that reads back exactly."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def normalize_columns(columns: Any) -> list[tuple[str, str | None]] | None:
    """``columns=`` as a list of (name, unit or None)."""
    if columns is None:
        return None
    if isinstance(columns, str):
        columns = [columns]
    items = columns.items() if isinstance(columns, Mapping) else columns
    out: list[tuple[str, str | None]] = []
    for item in items:
        if isinstance(item, str):
            out.append((item, None))
        else:
            name, unit = item
            out.append((str(name), None if unit is None else str(unit)))
    return out


def check_cells(path: Path, cells: Sequence[str], where: str) -> list[tuple[str, str]]:
    """Parse header cells / field names into (name, unit); reject bad and duplicate ones."""
    parsed: list[tuple[str, str]] = []
    first_seen: dict[str, int] = {}
    for i, cell in enumerate(cells, start=1):
        item = parse_header_cell(cell)
        if item is None:
            if not cell.strip():
                raise DataError(
                    path,
                    f"column {i}",
                    f"{where} {i} is empty",
                    hint="every column needs 'name [unit]'; remove stray delimiters",
                )
            problem = "is not of the form" if "[" in cell or "]" in cell else "has no unit:"
            raise DataError(
                path,
                cell.strip(),
                f"{where} '{cell.strip()}' {problem} 'name [unit]'",
                hint="write e.g. 'time [s]' or 'output [P]'; use '[1]' for a dimensionless column",
            )
        name, unit = item
        if not unit.strip():
            raise DataError(
                path,
                cell.strip(),
                f"{where} '{cell.strip()}' has an empty unit",
                hint="use '[1]' for a dimensionless column",
            )
        if name in first_seen:
            raise DataError(
                path,
                name,
                f"column name '{name}' appears twice (columns {first_seen[name]} and {i})",
                hint="give every column a distinct name",
            )
        first_seen[name] = i
        parsed.append((name, unit))
    return parsed


def select_columns(
    path: Path,
    available: list[tuple[str, str]],
    wanted: list[tuple[str, str | None]] | None,
) -> list[tuple[str, str]]:
    """Apply ``columns=`` to the columns a self-describing file has."""
    if wanted is None:
        return available
    units = dict(available)
    out = []
    for name, unit in wanted:
        if name not in units:
            have = ", ".join(f"'{n} [{u}]'" for n, u in available)
            raise DataError(
                path,
                name,
                f"column '{name}' is not in the file; it has {have}",
                hint="check the column names in the manifest against the file header",
            )
        if unit is not None and unit != units[name]:
            raise UnitError(
                path,
                f"{name} [{units[name]}]",
                f"the file gives column '{name}' the unit '{units[name]}' but "
                f"'{unit}' was declared",
                hint="declare the unit exactly as written in the file, or pass the "
                "name only and convert with pint",
            )
        out.append((name, units[name]))
    return out


def format_of(path: Path) -> str:
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise DataError(
            path,
            None,
            f"unknown sample file type '{path.suffix}'",
            hint="use one of " + ", ".join(sorted(FORMATS)),
        )
    return fmt


@contextmanager
def refused_as_data(
    errors: type[BaseException] | tuple[type[BaseException], ...],
    path: Path,
    field: str,
    message: str,
    hint: str = "",
) -> Iterator[None]:
    """Within the block, an error of the types ``errors`` becomes a :class:`DataError` on
    ``path`` and ``field`` saying ``message: <the error>`` with ``hint``.

    >>> try:
    ...     with refused_as_data(ValueError, Path("x.bin"), "data", "unreadable"):
    ...         int("seven")
    ... except DataError as exc:
    ...     print(exc.field, "|", exc.__cause__, "|", str(exc).split(": ", 1)[1])
    data | None | unreadable: invalid literal for int() with base 10: 'seven'
    """
    try:
        yield
    except errors as exc:
        raise DataError(path, field, f"{message}: {exc}", hint=hint) from None


def file_stat(path: Path) -> os.stat_result:
    try:
        st = path.stat()
    except FileNotFoundError:
        raise DataError(
            path, None, "file not found", hint="check the path in the manifest"
        ) from None
    except OSError as exc:
        raise DataError(path, None, f"cannot access the file: {exc.strerror}") from None
    if not path.is_file():
        raise DataError(path, None, "not a regular file (is it a directory?)")
    if st.st_size == 0:
        raise DataError(
            path,
            None,
            "the file is empty (0 bytes)",
            hint="the recording or the copy did not complete; record or copy it again",
        )
    return st


# --------------------------------------------------------------------------- numeric checks


def first_nonfinite(a: np.ndarray) -> int | None:
    """Index of the first NaN/Inf in ``a`` (checked in cache-sized chunks), or None."""
    with np.errstate(over="ignore", invalid="ignore"):
        for start in range(0, len(a), _CHECK_ROWS):
            part = a[start : start + _CHECK_ROWS]
            # The sum of a chunk is finite unless it holds NaN/Inf (or overflows, which the
            # exact check below then clears).  No BLAS here: its threads would fight the
            # parser's and the hash thread for the cores.
            if not math.isfinite(part.sum()):
                bad = np.flatnonzero(~np.isfinite(part))
                if bad.size:
                    return start + int(bad[0])
    return None


def float64_chunk(chunk: Any) -> np.ndarray:
    """Zero-copy numpy view of a null-free pyarrow float64 array.

    (``Array.to_numpy`` would do, but its first call imports pandas: 0.5 s.)
    """
    if chunk.null_count:  # pragma: no cover - the readers reject nulls before this
        raise AssertionError("nulls in a float64 chunk")
    data = chunk.buffers()[1]
    return np.frombuffer(data, dtype=np.float64, count=len(chunk), offset=chunk.offset * 8)


def drain(column: Any) -> Iterator[np.ndarray]:
    """Yield a pyarrow ChunkedArray's chunks as numpy views, dropping each one after use.

    The caller holds no other reference, so every arrow chunk is released as soon as it
    has been copied and peak memory stays near the size of the data, not twice it.
    """
    import pyarrow as pa

    pool = pa.default_memory_pool()
    chunks = column.chunks
    del column
    pool.release_unused()  # the parser's scratch blocks
    freed = 0
    for i in range(len(chunks)):
        chunk, chunks[i] = chunks[i], None
        view = float64_chunk(chunk)
        del chunk
        yield view
        freed += view.nbytes
        del view
        if freed >= _RELEASE_BYTES:  # the pool (mimalloc) keeps freed pages unless asked
            pool.release_unused()
            freed = 0
    pool.release_unused()


def assemble(parts: Iterable[np.ndarray], n: int) -> tuple[np.ndarray, int | None]:
    """Copy 1-D parts into one new float64 array, checking NaN/Inf on the way."""
    out = np.empty(n, dtype=np.float64)
    pos = 0
    bad: int | None = None
    for part in parts:
        m = len(part)
        dest = out[pos : pos + m]
        dest[...] = part
        if bad is None:
            k = first_nonfinite(dest)
            if k is not None:
                bad = pos + k
        pos += m
    if pos != n:  # pragma: no cover - internal consistency
        raise AssertionError(f"assembled {pos} rows, expected {n}")
    out.flags.writeable = False
    return out, bad


def nonfinite_error(path: Path, cell: str, row: int, value: float, where: str) -> DataError:
    kind = "NaN" if math.isnan(value) else ("+Inf" if value > 0 else "-Inf")
    return DataError(
        path,
        cell_field(cell, row),
        f"{kind} in row {row}{where}; samples must be finite numbers"
        + (" (a number too large for float64 also reads as Inf)" if kind != "NaN" else ""),
        hint="fix or cut the record where the instrument reported no valid value; "
        "metro does not fill missing samples",
    )


# --------------------------------------------------------------------------- time checks


def check_time(
    path: Path,
    cell: str,
    t: np.ndarray,
    *,
    expected_interval_s: float | None,
    rel_interval_tol: float | None,
    gap_factor: float,
    where,
) -> float | None:
    n = len(t)
    if n < 2:
        return None
    buf = np.empty(min(n - 1, _CHECK_ROWS))
    dmin, dmax = math.inf, -math.inf
    for start in range(1, n, _CHECK_ROWS):
        stop = min(start + _CHECK_ROWS, n)
        d = np.subtract(t[start:stop], t[start - 1 : stop - 1], out=buf[: stop - start])
        lo = float(d.min())
        if lo <= 0:
            i = start + int(np.flatnonzero(d <= 0)[0])  # index of the later sample
            r = i + 1
            if t[i] == t[i - 1]:
                raise DataError(
                    path,
                    cell_field(cell, r),
                    f"duplicate time stamp {_fmt(t[i])} in rows {r - 1} and {r}{where(i)}",
                    hint="the record repeats a sample (often a logger restart or a "
                    "concatenated file); remove the duplicate rows",
                )
            raise DataError(
                path,
                cell_field(cell, r),
                f"time goes backwards at row {r}{where(i)}: {_fmt(t[i - 1])} in row "
                f"{r - 1}, then {_fmt(t[i])}",
                hint="time stamps must increase; the file may be two records joined "
                "together or sorted wrongly",
            )
        dmin = min(dmin, lo)
        dmax = max(dmax, float(d.max()))

    tol = rel_interval_tol
    if tol is not None and dmax - dmin <= tol * dmin:
        # Every step is within the tolerance of every other, hence of the median too.
        interval = (float(t[-1]) - float(t[0])) / (n - 1)
    else:
        d = np.subtract(t[1:], t[:-1])
        interval = float(np.median(d, overwrite_input=True))
        np.subtract(t[1:], t[:-1], out=d)  # median reordered d; recompute
        if dmax > gap_factor * interval:
            gaps = np.flatnonzero(d > gap_factor * interval)
            i = int(gaps[0])
            r = i + 2  # row of the sample after the gap
            longest = int(gaps[np.argmax(d[gaps])])
            raise DataError(
                path,
                cell_field(cell, r),
                f"gap in the record before row {r}{where(i + 1)}: the time steps from "
                f"{_fmt(t[i])} to {_fmt(t[i + 1])} ({_fmt(d[i])}, "
                f"{d[i] / interval:.3g} x the median interval {_fmt(interval)}; limit "
                f"{gap_factor:g} x). {gaps.size} gap(s) in all, longest "
                f"{_fmt(d[longest])} before row {longest + 2}",
                hint="samples are missing; split the record at the gap or record again "
                "(metro does not interpolate)",
            )
        if tol is not None:
            dev = np.abs(d - interval)
            bad = np.flatnonzero(dev > tol * interval)
            if bad.size:
                i = int(bad[0])
                worst = int(bad[np.argmax(dev[bad])])
                raise DataError(
                    path,
                    cell_field(cell, i + 2),
                    f"non-uniform sampling at row {i + 2}{where(i + 1)}: step "
                    f"{_fmt(d[i])} differs from the median interval {_fmt(interval)} by "
                    f"{dev[i] / interval:.3g} (relative; tolerance {tol:g}). {bad.size} "
                    f"step(s) outside the tolerance, worst {dev[worst] / interval:.3g} "
                    f"at row {worst + 2}",
                    hint="if the time stamps jitter by design, pass rel_interval_tol=None "
                    "(gaps are still checked) or a larger tolerance",
                )
    if expected_interval_s is not None:
        etol = 1e-6 if tol is None else tol
        rel = abs(interval - expected_interval_s) / expected_interval_s
        if rel > etol:
            raise DataError(
                path,
                cell,
                f"the sampling interval is {_fmt(interval)} but {_fmt(expected_interval_s)} "
                f"was expected (relative difference {rel:.3g}, tolerance {etol:g})",
                hint="check the sample rate stated in the manifest against the recording",
            )
    return interval

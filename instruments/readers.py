"""Read and write measurement *segments*: sample files whose header states the units.

A segment is a table of samples: one column per recorded quantity, one row per sample
instant.  :func:`read_samples` returns a :class:`SampleTable` whose columns are 1-D
``float64`` arrays and whose units are the unit texts exactly as written in the file
(the caller parses them with pint).  Any defect in the file raises
:class:`metro.core.base.errors.DataError` naming the file, the field (column or row) and the
reason, with a hint where one is known.

File formats (chosen by the file suffix)
----------------------------------------

``.csv``, ``.tsv``, ``.txt`` -- delimited text, UTF-8.

* Lines starting with ``#`` before the header are comments and are ignored; so are
  blank lines there.  A ``#`` line *after* the header is data (and an error).
* The first other line is the header.  Every header cell is ``name [unit]``, e.g.
  ``time [s]``, ``output [P]``, ``rate [°/h]``, ``temperature [degC]``; a dimensionless
  column is written ``ratio [1]``.  The unit is everything between the brackets, kept
  exactly as written.  Names must be unique and may not contain ``[`` or ``]``.
  A header cell may be enclosed in double quotes.
* Delimiter: ``,`` for ``.csv``, tab for ``.tsv`` and ``.txt``.  If the header line does
  not contain that delimiter but contains the other one (tab or comma), the other one is
  used.  ``read_samples(..., delimiter=";")`` overrides both.
* Every data row has exactly as many cells as the header.  Cells are decimal numbers
  (``12``, ``-0.5``, ``1.5e-3``, optionally surrounded by spaces or double quotes).  An
  empty cell, text, NaN and Inf are errors.  Blank lines between data rows are ignored.
* The file ends with a newline.  A file whose last byte is not a newline was cut off
  mid-row (interrupted writer or copy) unless told otherwise
  (``require_final_newline=False``).
* Row numbers in messages count data rows from 1 (the first row after the header is
  row 1, blank lines are not counted); the message also gives the line number in the
  file, which is what a text editor shows.

``.npy`` -- NumPy array file, opened memory-mapped (nothing is copied until used).

* Preferred: a 1-D *structured* array whose field names are ``name [unit]`` (the same
  rule as a text header).  :func:`write_samples_npy` writes this form.
* A plain 1-D array (one column) or 2-D array of shape ``(n_rows, n_columns)`` carries
  no units, so the caller must declare them: ``read_samples(p, columns=[("output",
  "P")])`` (the campaign manifest states them).  Without that declaration a plain array
  is an error.
* Numeric fields are accepted (integers must be within +-2**53 so they convert to
  float64 exactly).  Native-endian float64 columns are returned as read-only views of
  the memory map (possibly strided); other types are converted to float64 copies.
* Row numbers in messages count from 1; the array index is given too.

``.parquet`` / ``.pq`` -- Apache Parquet.  Units are taken from the column *names*,
``name [unit]``, the same rule as a text header; parquet field metadata is not read.

Timing checks
-------------

When the table has a column named ``time_column`` (default ``"time"``) it must increase
strictly; the sampling interval is then checked: a step larger than ``gap_factor``
(1.5) times the median interval is a gap; any step differing from the median interval
by more than ``rel_interval_tol`` (relative) is non-uniform sampling; and, when
``expected_interval_s`` is given, the interval must agree with it within the same
relative tolerance (1e-6 if ``rel_interval_tol`` is None).  The time column's unit is
not interpreted here: ``expected_interval_s`` is compared with the numbers as stored.

Integrity
---------

``SampleTable.sha256`` is the SHA-256 of the raw file bytes.  It is computed in a
background thread started when the read starts (the hash costs more CPU than parsing on
machines without SHA instructions) and is waited for on first access to ``.sha256``;
``read_samples(..., background_hash=False)`` waits before returning.  The reader checks
that the file (device, inode, size, modification time) did not change while it was
parsed or hashed; if it did, a DataError is raised.  Writers in this module replace
files atomically, so a file being rewritten by them never shows a half-written state.
"""

from __future__ import annotations

import csv
import functools
import hashlib
import math
import os
import re
import threading
from collections.abc import Iterable, Iterator, Mapping, Sequence
from decimal import Decimal
from pathlib import Path
from typing import Any

import attrs
import numpy as np

from metro.core.base.atomic import atomic_path
from metro.core.base.errors import DataError, UnitError
from metro.core.base import extras

__all__ = [
    "FORMATS",
    "SampleTable",
    "parse_header_cell",
    "read_samples",
    "write_samples_csv",
    "write_samples_npy",
]

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
_MAX_EXACT_INT = 2**53
_BLOCK_BYTES = 4 << 20  # pyarrow CSV block size: ~0.4 M rows of one numeric column
_CHECK_ROWS = 1 << 16  # rows per NaN/Inf and time-step check (fits in L2 cache)
_WRITE_ROWS = 1 << 18  # rows formatted per writer task
_HASH_BUFFER = 1 << 20
_RELEASE_BYTES = 64 << 20  # return freed pyarrow memory to the OS every this many bytes


# --------------------------------------------------------------------------- result type


def _columns_repr(columns: Mapping[str, np.ndarray]) -> str:
    return "{" + ", ".join(f"{k!r}: <{v.shape[0]} x {v.dtype}>" for k, v in columns.items()) + "}"


class _Digest:
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
                if _stat_key(os.fstat(f.fileno())) != self._key:
                    raise _changed(self._path)
                while n := f.readinto(view):
                    if self._cancelled.is_set():
                        return
                    digest.update(view[:n])  # releases the GIL
                if _stat_key(os.fstat(f.fileno())) != self._key:
                    raise _changed(self._path)
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
    _sha256: str | _Digest = attrs.field(alias="sha256")
    n_rows: int
    format: str
    sample_interval_s: float | None = None

    @property
    def sha256(self) -> str:
        """Hex SHA-256 of the file's bytes (waits for the background hash if needed)."""
        if isinstance(self._sha256, _Digest):
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


def _stat_key(st: os.stat_result) -> tuple[int, ...]:
    return (st.st_dev, st.st_ino, st.st_size, st.st_mtime_ns)


def _changed(path: Path) -> DataError:
    return DataError(
        path,
        None,
        "the file changed while it was being read",
        hint="read it again once the program writing it has finished "
        "(writers should replace files atomically)",
    )


def _cell_field(cell: str, row: int) -> str:
    return f"{cell}, row {row}"


def _fmt(x: float) -> str:
    """A sample value for a message: the shortest text that reads back exactly."""
    text = repr(float(x))
    return text[:-2] if text.endswith(".0") else text


def _normalize_columns(columns: Any) -> list[tuple[str, str | None]] | None:
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


def _check_cells(path: Path, cells: Sequence[str], where: str) -> list[tuple[str, str]]:
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
                hint="write e.g. 'time [s]' or 'output [P]'; use '[1]' for a "
                "dimensionless column",
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


def _select(
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


def _format_of(path: Path) -> str:
    fmt = FORMATS.get(path.suffix.lower())
    if fmt is None:
        raise DataError(
            path,
            None,
            f"unknown sample file type '{path.suffix}'",
            hint="use one of " + ", ".join(sorted(FORMATS)),
        )
    return fmt


def _stat(path: Path) -> os.stat_result:
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


def _first_nonfinite(a: np.ndarray) -> int | None:
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


def _float64_chunk(chunk: Any) -> np.ndarray:
    """Zero-copy numpy view of a null-free pyarrow float64 array.

    (``Array.to_numpy`` would do, but its first call imports pandas: 0.5 s.)
    """
    if chunk.null_count:  # pragma: no cover - the readers reject nulls before this
        raise AssertionError("nulls in a float64 chunk")
    data = chunk.buffers()[1]
    return np.frombuffer(data, dtype=np.float64, count=len(chunk), offset=chunk.offset * 8)


def _drain(column: Any) -> Iterator[np.ndarray]:
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
        view = _float64_chunk(chunk)
        del chunk
        yield view
        freed += view.nbytes
        del view
        if freed >= _RELEASE_BYTES:  # the pool (mimalloc) keeps freed pages unless asked
            pool.release_unused()
            freed = 0
    pool.release_unused()


def _assemble(parts: Iterable[np.ndarray], n: int) -> tuple[np.ndarray, int | None]:
    """Copy 1-D parts into one new float64 array, checking NaN/Inf on the way."""
    out = np.empty(n, dtype=np.float64)
    pos = 0
    bad: int | None = None
    for part in parts:
        m = len(part)
        dest = out[pos : pos + m]
        dest[...] = part
        if bad is None:
            k = _first_nonfinite(dest)
            if k is not None:
                bad = pos + k
        pos += m
    if pos != n:  # pragma: no cover - internal consistency
        raise AssertionError(f"assembled {pos} rows, expected {n}")
    out.flags.writeable = False
    return out, bad


def _nonfinite_error(path: Path, cell: str, row: int, value: float, where: str) -> DataError:
    kind = "NaN" if math.isnan(value) else ("+Inf" if value > 0 else "-Inf")
    return DataError(
        path,
        _cell_field(cell, row),
        f"{kind} in row {row}{where}; samples must be finite numbers"
        + (" (a number too large for float64 also reads as Inf)" if kind != "NaN" else ""),
        hint="fix or cut the record where the instrument reported no valid value; "
        "metro does not fill missing samples",
    )


# --------------------------------------------------------------------------- time checks


def _check_time(
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
                    _cell_field(cell, r),
                    f"duplicate time stamp {_fmt(t[i])} in rows {r - 1} and {r}{where(i)}",
                    hint="the record repeats a sample (often a logger restart or a "
                    "concatenated file); remove the duplicate rows",
                )
            raise DataError(
                path,
                _cell_field(cell, r),
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
                _cell_field(cell, r),
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
                    _cell_field(cell, i + 2),
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


# --------------------------------------------------------------------------- text files


@attrs.frozen
class _TextLayout:
    path: Path
    delimiter: str
    cells: list[str]  # header cells as written (stripped)
    data_offset: int  # byte offset of the first data line
    first_data_line: int  # 1-based line number of the first line after the header


def _read_header(path: Path, fmt: str, delimiter: str | None) -> _TextLayout:
    offset = 0
    lineno = 0
    with open(path, "rb") as f:
        while True:
            raw = f.readline()
            if not raw:
                raise DataError(
                    path,
                    "header",
                    "no header line: the file holds only comments or blank lines",
                    hint="the first line that is not a '#' comment must be the header, "
                    "e.g. 'time [s],output [P]'",
                )
            lineno += 1
            offset += len(raw)
            if lineno == 1 and raw.startswith(b"\xef\xbb\xbf"):
                raw = raw[3:]
            stripped = raw.strip()
            if stripped and not stripped.startswith(b"#"):
                break
    if b"\0" in raw:
        raise DataError(
            path,
            "header",
            f"line {lineno} contains NUL bytes: this is not a text file",
            hint="check the file type; binary records must be .npy or .parquet",
        )
    try:
        line = raw.decode("utf-8").rstrip("\r\n")
    except UnicodeDecodeError as exc:
        raise DataError(
            path,
            "header",
            f"the header (line {lineno}) is not valid UTF-8 text "
            f"(byte 0x{raw[exc.start]:02x} at column {exc.start + 1})",
            hint="save the file as UTF-8; units such as '°/h' need it",
        ) from None
    delim = delimiter
    if delim is None:
        delim = "," if fmt == "csv" else "\t"
        if delim not in line:
            other = "\t" if delim == "," else ","
            if other in line:
                delim = other
    cells = [_unquote(c) for c in next(csv.reader([line], delimiter=delim))]
    if cells and all(_is_number(c) for c in cells):
        raise DataError(
            path,
            "header",
            f"no header: line {lineno} '{line[:60]}' looks like data",
            hint="add a header line naming each column with its unit, e.g. "
            "'time [s],output [P]'",
        )
    return _TextLayout(path, delim, cells, offset, lineno + 1)


def _show(text: str, limit: int = 60) -> str:
    """Quote a cell or row for a message, on one line."""
    text = text if len(text) <= limit else text[:limit] + "..."
    return repr(text) if any(c in text for c in "'\r\n\t") else f"'{text}'"


def _unquote(cell: str) -> str:
    cell = cell.strip()
    if len(cell) >= 2 and cell[0] == cell[-1] == '"':
        cell = cell[1:-1].replace('""', '"').strip()
    return cell


def _is_number(text: str) -> bool:
    try:
        float(text)
    except ValueError:
        return False
    return True


def _line_of_row(layout: _TextLayout, row: int) -> int | None:
    """1-based file line of data row ``row`` (blank lines skipped, as the parser does)."""
    seen = 0
    lines = 0
    cur_len = 0
    last_byte = 0
    with open(layout.path, "rb") as f:
        f.seek(layout.data_offset)
        while chunk := f.read(8 << 20):
            buf = np.frombuffer(chunk, dtype=np.uint8)
            nl = np.flatnonzero(buf == 10)
            if nl.size:
                lens = np.empty(nl.size, dtype=np.int64)
                lens[0] = cur_len + nl[0]
                lens[1:] = np.diff(nl) - 1
                before = np.where(nl > 0, buf[np.maximum(nl - 1, 0)], last_byte)
                blank = (lens == 0) | ((lens == 1) & (before == 13))
                cum = seen + np.cumsum(~blank)
                k = int(np.searchsorted(cum, row))
                if k < nl.size:
                    return layout.first_data_line + lines + k
                seen = int(cum[-1])
                lines += int(nl.size)
                cur_len = len(buf) - int(nl[-1]) - 1
            else:
                cur_len += len(buf)
            last_byte = int(buf[-1])
    if cur_len > 0 and seen + 1 == row:
        return layout.first_data_line + lines
    return None


def _text_where(layout: _TextLayout):
    def where(index: int) -> str:
        line = _line_of_row(layout, index + 1)
        return f" (line {line})" if line is not None else ""

    return where


# --------------------------------------------------------------------------- numpy text parser
#
# The reader without pyarrow (``pip install metro-inertial`` leaves it out; the ``fast`` extra
# brings it), and the diagnosis of a file pyarrow refused.  The text is cut into chunks ending at a
# line end; a chunk's fields are found from the delimiter and newline bytes, and every field of a
# column is read at once, one character position at a time, by a finite automaton over character
# classes (sign, digits, point, exponent, spaces, the field's end).  The digits accumulate into an
# integer mantissa m and a power of ten e, and m * 10**e (or m / 10**-e) is one correctly rounded
# float64 operation when m < 2**53 and |e| <= 22 (both factors are exact).  Other fields (17
# significant digits, far exponents) are rounded once in long double or by numpy's text
# conversion, nan, inf and quoted cells by float() with pyarrow's rules, so the values equal
# pyarrow's bit for bit.
# Chunks are parsed on a pool of Python threads that is joined before the reader returns or raises:
# nothing is left running at exit, and no Python code runs on a thread pyarrow owns.

_SP, _PLUS, _MINUS, _DG, _DOT, _EXP, _END, _OTHER = range(8)  # character classes
_CLASS = np.full(256, _OTHER, dtype=np.uint8)
_CLASS[[ord(c) for c in " \t\r"]] = _SP  # spaces and the CR of CRLF (a quoted cell goes to float())
_CLASS[ord("+")] = _PLUS
_CLASS[ord("-")] = _MINUS
_CLASS[ord("0") : ord("9") + 1] = _DG
_CLASS[ord(".")] = _DOT
_CLASS[[ord("e"), ord("E")]] = _EXP
_CLASS[ord("\n")] = _END  # and the delimiter: the end of a field
# states: 0 start, 1 sign, 2 integer digits, 3 point before any digit, 4 fraction, 5 exponent mark,
# 6 exponent sign, 7 exponent digits, 8 trailing spaces, 9 error, 10 done (the field was a number);
# 9 and 10 keep their state whatever follows (the next fields' characters)
_STEP = np.full((11, 8), 9, dtype=np.uint8)
_STEP[0, [_SP, _PLUS, _MINUS, _DG, _DOT]] = [0, 1, 1, 2, 3]
_STEP[1, [_DG, _DOT]] = [2, 3]
_STEP[2, [_DG, _DOT, _EXP, _SP, _END]] = [2, 4, 5, 8, 10]
_STEP[3, _DG] = 4
_STEP[4, [_DG, _EXP, _SP, _END]] = [4, 5, 8, 10]
_STEP[5, [_PLUS, _MINUS, _DG]] = [6, 6, 7]
_STEP[6, _DG] = 7
_STEP[7, [_DG, _SP, _END]] = [7, 8, 10]
_STEP[8, [_SP, _END]] = [8, 10]
_STEP[10, :] = 10
# what a character does in a state: 1 a mantissa digit, 2 a fraction digit, 4 an exponent digit,
# 8 the mantissa's minus, 16 the exponent's minus
_ACTION = np.zeros((11, 8), dtype=np.uint8)
_ACTION[[0, 1, 2], _DG] = 1
_ACTION[[3, 4], _DG] = 1 | 2
_ACTION[[5, 6, 7], _DG] = 4
_ACTION[0, _MINUS] = 8
_ACTION[5, _MINUS] = 16
_STEP_FLAT, _ACTION_FLAT = _STEP.ravel(), _ACTION.ravel()
_POW10 = 10.0 ** np.arange(23)  # exact in float64
_TEXT_CHUNK = 1 << 20


@functools.lru_cache(maxsize=8)
def _byte_steps(delimiter: int) -> np.ndarray:
    """The automaton over (state, byte): index state * 256 + byte, value the next state * 256."""
    classes = _CLASS.copy()
    classes[delimiter] = _END
    return (_STEP[:, classes].astype(np.uint16) * 256).ravel()


def _parse_fields(buf: np.ndarray, starts: np.ndarray, lens: np.ndarray, delimiter: int, *,
                  exponents: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Values of the fields ``buf[starts[i]:starts[i]+lens[i]]`` (each followed by the delimiter or
    a line end, and ``buf`` by line ends as long as the longest field) and a mask of the fields that
    are not plain decimal numbers (quoted, nan, inf, or not numbers at all), left to
    :func:`_cell_value`.  ``exponents=False``: ``buf`` holds no 'e' or 'E'."""
    n = len(starts)
    width = int(lens.max()) + 1 if n else 0
    if n > 4096:  # some long fields (12.345000000000001 among 12.345): read them apart if it pays
        short = np.cumsum(np.bincount(lens))  # fields of at most k characters
        cost = short * (np.arange(len(short)) + 1) + (n - short) * width
        cut = int(np.argmin(cost))
        if cost[cut] < 0.75 * n * width:
            values, other = np.empty(n), np.empty(n, dtype=bool)
            for part in (np.flatnonzero(lens <= cut), np.flatnonzero(lens > cut)):
                values[part], other[part] = _parse_fields(buf, starts[part], lens[part], delimiter,
                                                          exponents=exponents)
            return values, other
    step = _byte_steps(delimiter)
    state = np.zeros(n, dtype=np.uint16)  # the state times 256, plus the byte: the table's index
    mant = np.zeros(n, dtype=np.int64)
    ndig = np.zeros(n, dtype=np.uint8)
    nfrac = np.zeros(n, dtype=np.int16)
    expo = np.zeros(n, dtype=np.int64)
    neg = np.zeros(n, dtype=bool)
    eneg = np.zeros(n, dtype=bool)
    at = starts.astype(np.intp, copy=True)
    starting = True  # some field has not met its first non-space character yet
    for _ in range(width):  # the field's characters and the byte after it
        c = buf.take(at)
        at += 1
        digit = c - np.uint8(48)
        in_mant = (digit < 10) & (state < 5 * 256)
        mant *= in_mant * np.uint8(9) + np.uint8(1)  # wraps past 18 digits: see _exact_values
        mant += digit * in_mant
        ndig += in_mant
        nfrac += in_mant & (state >= 3 * 256)  # states 3, 4: after the point
        if starting:
            at_start = state == 0
            neg |= (c == ord("-")) & at_start
            starting = bool(at_start.any())
        if exponents:
            in_exp = (digit < 10) & (state >= 5 * 256) & (state < 8 * 256)
            np.copyto(expo, np.minimum(expo * 10 + digit, 1 << 20), where=in_exp)
            eneg |= (c == ord("-")) & (state == 5 * 256)
        state = step.take(state + c)
    state >>= 8
    e10 = np.where(eneg, -expo, expo) - nfrac
    number = state == 10
    fast = number & (ndig <= 18) & (mant < (1 << 53)) & (np.abs(e10) <= 22)
    scale = _POW10.take(np.minimum(np.abs(e10), 22))
    mf = mant.astype(np.float64)
    values = np.where(e10 >= 0, mf * scale, mf / scale)
    np.negative(values, out=values, where=neg)
    exact = np.flatnonzero(number & ~fast)
    if exact.size:  # 16-18 digits, far exponents
        values[exact] = _exact_values(buf, starts[exact], lens[exact], mant[exact], e10[exact],
                                      neg[exact], ndig[exact])
    return values, ~number


_WIDE = np.finfo(np.longdouble).nmant >= 63  # x87 extended (or quad): a 64-bit mantissa is exact
_POW10_WIDE = np.cumprod(np.r_[1, np.full(27, 10)].astype(np.longdouble))  # 10**0..10**27, exact


def _exact_values(buf: np.ndarray, starts: np.ndarray, lens: np.ndarray, mant: np.ndarray,
                  e10: np.ndarray, neg: np.ndarray, ndig: np.ndarray) -> np.ndarray:
    """Correctly rounded values of decimal fields the float64 fast path cannot take.  Up to 18
    digits and |e| <= 27, m and 10**|e| are exact in long double, so m * 10**e or m / 10**-e is one
    rounding to 64 bits; rounding that to float64 is right unless it fell exactly halfway between
    two doubles (double rounding), and those, with the rest, go through numpy's conversion of the
    text (correctly rounded, as float() is)."""
    out = np.empty(len(starts))
    rest = np.ones(len(starts), dtype=bool)
    if _WIDE:
        ok = (ndig <= 18) & (np.abs(e10) <= 27)
        m = mant.astype(np.longdouble)
        scale = _POW10_WIDE.take(np.minimum(np.abs(e10), 27))
        q = np.where(e10 >= 0, m * scale, m / scale)
        r = q.astype(np.float64)
        tie = np.abs(q - r.astype(np.longdouble)) == np.spacing(np.abs(r)).astype(np.longdouble) / 2
        rest = ~ok | tie
        out[:] = np.where(neg, -r, r)
    if rest.any():
        out[rest] = _field_texts(buf, starts[rest], lens[rest]).astype(np.float64)
    return out


def _field_texts(buf: np.ndarray, starts: np.ndarray, lens: np.ndarray) -> np.ndarray:
    """The fields as a fixed-width bytes array (NUL-padded)."""
    width = int(lens.max())
    out = np.zeros((len(starts), width), dtype=np.uint8)
    for j in range(width):
        out[:, j] = np.where(lens > j, buf.take(starts + j), 0)
    return out.view(f"S{width}").ravel()


def _text_chunks(path: Path, offset: int) -> Iterator[bytes]:
    """The data after ``offset`` in pieces of about 4 MB that end with a line end (the last piece
    gets one if the file has none)."""
    carry = b""
    with open(path, "rb") as f:
        f.seek(offset)
        while block := f.read(_TEXT_CHUNK):
            data = carry + block
            cut = data.rfind(b"\n") + 1
            carry = data[cut:]
            if cut:
                yield data[:cut]
    if carry:
        yield carry + b"\n"


def _shape_error(layout: _TextLayout, row: int, text: str, cells: int) -> DataError:
    """A data row with the wrong number of cells (``row`` counts data rows from 1)."""
    expected = len(layout.cells)
    line = _line_of_row(layout, row)
    at = f" (line {line})" if line is not None else ""
    if text.lstrip().startswith("#"):
        note = "; comment lines must come before the header"
        hint = "move the comment above the header line or delete it"
    elif cells < expected:
        last = line is not None and _line_of_row(layout, row + 1) is None
        note = " -- the file looks truncated" if last else ""
        hint = ("a short last row means the file was cut off: copy or record it again" if last
                else "fill in the missing cells or remove the row")
    else:
        note = ""
        hint = "remove the extra cells; check the delimiter and that the decimal separator is '.'"
    return DataError(layout.path, f"row {row}",
                     f"row {row}{at} has {cells} cell(s) but the header has {expected}: "
                     f"{_show(text)}{note}",
                     hint=hint)


def _value_error(layout: _TextLayout, cell: str, row: int, text: str) -> DataError:
    line = _line_of_row(layout, row)
    at = f" (line {line})" if line is not None else ""
    if not text.strip().strip('"').strip():
        what = "an empty cell"
        hint = "fill the cell or remove the row; metro does not fill gaps"
    else:
        what = f"{_show(text)}, which is not a number"
        hint = "cells must be plain decimal numbers such as -1.25e-3"
    return DataError(layout.path, _cell_field(cell, row),
                     f"row {row}{at} has {what} in column '{cell}'", hint=hint)


_NUMBER = re.compile(rb"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(nan|inf|infinity)",
                     re.IGNORECASE)


def _cell_value(cell: bytes) -> float:
    """One cell as pyarrow's CSV reader reads it: a double-quoted cell is unquoted (what follows the
    closing quote is kept, as pyarrow keeps it), spaces around the number are dropped, nan and
    inf(inity) are taken; anything else that is not a decimal number raises ValueError."""
    if cell.startswith(b'"'):
        end = cell.find(b'"', 1)
        if end < 0:
            raise ValueError
        cell = cell[1:end] + cell[end + 1 :]
    text = cell.strip(b" \t\r")
    if not _NUMBER.fullmatch(text):  # float() takes more: 1_000, other white space
        raise ValueError
    return float(text)


def _slow_values(chunk: bytes, starts: np.ndarray, lens: np.ndarray, values: np.ndarray,
                 slow: np.ndarray) -> int | None:
    """Fill ``values`` at ``slow`` with :func:`_cell_value`; the index of the first field that is
    no number."""
    for i in np.flatnonzero(slow):
        s = int(starts[i])
        try:
            values[i] = _cell_value(chunk[s : s + int(lens[i])])
        except ValueError:
            return int(i)
    return None


def _chunk_rows(b: np.ndarray, delim: int,
                ncols: int) -> tuple[np.ndarray, np.ndarray, int | None, int]:
    """Field starts and lengths (rows x ncols) of the lines of one chunk, blank lines left out, up
    to the first line with the wrong number of cells: (starts, lens, the byte offset of that line or
    None, its number of cells)."""
    ends = np.flatnonzero((b == delim) | (b == 10))
    starts = np.empty_like(ends)
    starts[:1] = 0
    starts[1:] = ends[:-1] + 1
    lens = ends - starts
    line_end = np.flatnonzero(b.take(ends) == 10)  # index of each line's last field
    per_line = np.diff(line_end, prepend=-1)
    first = line_end - per_line + 1
    span = ends.take(line_end) - starts.take(first)
    blank = (per_line == 1) & ((span == 0) | ((span == 1) & (b.take(starts.take(first)) == 13)))
    wrong = np.flatnonzero((per_line != ncols) & ~blank)
    bad_field, bad_cells = None, 0
    if wrong.size:
        k = int(wrong[0])
        cut, bad_cells = int(first[k]), int(per_line[k])
        bad_field = int(starts[cut])
        blank, per_line = blank[:k], per_line[:k]
        starts, lens = starts[:cut], lens[:cut]
    if blank.any():
        keep = np.repeat(~blank, per_line)
        starts, lens = starts[keep], lens[keep]
    return starts.reshape(-1, ncols), lens.reshape(-1, ncols), bad_field, bad_cells


def _parse_chunk(chunk: bytes, delim: int, ncols: int, columns: list[int]):
    """One chunk's rows: (rows, [values of each wanted column], the first cell that is no number as
    (row in chunk, column position in ``columns``, text) or None, the first line with the wrong
    number of cells as (its text, cells) or None)."""
    b = np.frombuffer(chunk, dtype=np.uint8)
    starts, lens, bad_at, bad_cells = _chunk_rows(b, delim, ncols)
    padded = np.concatenate((b, np.full(int(lens.max(initial=0)) + 1, 10, dtype=np.uint8)))
    exponents = chunk.find(b"e") >= 0 or chunk.find(b"E") >= 0
    out, first_bad = [], None
    for k, j in enumerate(columns):
        s, n = np.ascontiguousarray(starts[:, j]), np.ascontiguousarray(lens[:, j])
        values, slow = _parse_fields(padded, s, n, delim, exponents=exponents)
        i = _slow_values(chunk, s, n, values, slow) if slow.any() else None
        if i is not None and (first_bad is None or i < first_bad[0]):
            first_bad = (i, k, chunk[int(s[i]) : int(s[i] + n[i])].decode("utf-8", "replace"))
        out.append(values)
    shape = None
    if bad_at is not None:
        line = chunk[bad_at:].split(b"\n", 1)[0].rstrip(b"\r")
        shape = (line.decode("utf-8", "replace"), bad_cells)
    return len(starts), out, first_bad, shape


def _parse_text_numpy(layout: _TextLayout, names: list[str], wanted: list[str],
                      cells: Mapping[str, str]) -> tuple[dict[str, list[np.ndarray]], int]:
    """Read the wanted columns of a text file without pyarrow: ({name: float64 parts}, rows).

    Chunks are parsed on up to two threads (numpy releases the GIL; the pool is joined before this
    returns or raises), their results taken in file order.  Raises the DataError of the first bad
    row (wrong number of cells, a cell that is no number)."""
    from concurrent.futures import ThreadPoolExecutor

    columns = [names.index(n) for n in wanted]
    parts: dict[str, list[np.ndarray]] = {n: [] for n in wanted}
    args = (ord(layout.delimiter), len(names), columns)
    workers = max(1, min(os.cpu_count() or 1, 2))
    rows = 0
    with ThreadPoolExecutor(workers) as pool:
        pending = []
        chunks = _text_chunks(layout.path, layout.data_offset)
        while True:
            while len(pending) < 2 * workers and (chunk := next(chunks, None)) is not None:
                pending.append(pool.submit(_parse_chunk, chunk, *args))
            if not pending:
                break
            n, values, first_bad, shape = pending.pop(0).result()
            if first_bad is not None or shape is not None:
                for fut in pending:
                    fut.cancel()
            if first_bad is not None:
                i, k, text = first_bad
                raise _value_error(layout, cells[wanted[k]], rows + i + 1, text)
            for name, v in zip(wanted, values):
                parts[name].append(v)
            rows += n
            if shape is not None:
                raise _shape_error(layout, rows + 1, *shape)
    return parts, rows


def _diagnose_text(layout: _TextLayout, names: list[str], wanted: list[str],
                   cells: Mapping[str, str], exc: Exception) -> DataError:
    """Find the first bad row after pyarrow's fast parse failed (with the numpy parser: no Python
    callback runs on an arrow thread, which could still be running when the interpreter exits)."""
    try:
        _parse_text_numpy(layout, names, wanted, cells)
    except DataError as err:  # the first bad row
        return err
    return DataError(layout.path, None, f"cannot parse the data: {exc}")


def _arrow() -> bool:
    """Parse with pyarrow (the ``fast`` extra) if it is installed and METRO_NO_PYARROW unset."""
    return os.environ.get("METRO_NO_PYARROW", "") in ("", "0") and extras.available("pyarrow")


def _read_text_arrow(layout: _TextLayout, names: list[str], wanted: list[str],
                     cells: Mapping[str, str]) -> tuple[int, dict[str, Iterator[np.ndarray]]]:
    """pyarrow's multi-threaded parse: (rows, {name: float64 chunks, released as they are used})."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    read_options = pcsv.ReadOptions(column_names=names, use_threads=True, block_size=_BLOCK_BYTES)
    parse_options = pcsv.ParseOptions(delimiter=layout.delimiter)
    convert_options = pcsv.ConvertOptions(
        column_types={n: pa.float64() for n in wanted},
        include_columns=wanted,
        null_values=[],
        strings_can_be_null=False,
        quoted_strings_can_be_null=False,
    )
    try:
        with pa.OSFile(str(layout.path)) as f:
            f.seek(layout.data_offset)
            table = pcsv.read_csv(f, read_options=read_options, parse_options=parse_options,
                                  convert_options=convert_options)
    except pa.ArrowInvalid as exc:
        raise _diagnose_text(layout, names, wanted, cells, exc) from None
    n = table.num_rows
    chunked = {name: table.column(name) for name in wanted}
    del table
    return n, {name: _drain(chunked.pop(name)) for name in wanted}


def _read_text(
    path: Path,
    fmt: str,
    *,
    columns: list[tuple[str, str | None]] | None,
    delimiter: str | None,
    require_final_newline: bool,
    size: int,
    parsed=lambda: None,
):
    layout = _read_header(path, fmt, delimiter)
    available = _check_cells(path, layout.cells, "header cell")
    selected = _select(path, available, columns)
    names = [n for n, _ in available]
    wanted = [n for n, _ in selected]
    cells = {n: f"{n} [{u}]" for n, u in available}
    where = _text_where(layout)
    fmt = "csv" if layout.delimiter != "\t" else "tsv"

    with open(path, "rb") as f:
        if size - layout.data_offset <= 4096:
            f.seek(layout.data_offset)
            if not f.read().strip():  # the header and nothing else
                arrays = {n: np.empty(0) for n in wanted}
                for a in arrays.values():
                    a.flags.writeable = False
                return selected, arrays, 0, fmt, cells, where
        f.seek(-1, os.SEEK_END)
        last = f.read(1)
    if require_final_newline and last not in (b"\n", b"\r"):
        line = _count_lines(path)
        raise DataError(
            path,
            f"line {line}",
            f"the file ends mid-row: line {line}, the last, has no line end, so it may be "
            "cut short (interrupted writer or copy)",
            hint="copy or record the file again; if it is complete, pass "
            "require_final_newline=False",
        )

    if _arrow():
        n, sources = _read_text_arrow(layout, names, wanted, cells)
    else:
        parts, n = _parse_text_numpy(layout, names, wanted, cells)
        sources = {name: iter(parts.pop(name)) for name in wanted}
    parsed()
    arrays: dict[str, np.ndarray] = {}
    first_bad: tuple[int, str] | None = None
    for name in wanted:
        out, bad = _assemble(sources.pop(name), n)
        arrays[name] = out
        if bad is not None and (first_bad is None or bad < first_bad[0]):
            first_bad = (bad, name)
    if first_bad is not None:
        i, name = first_bad
        raise _nonfinite_error(path, cells[name], i + 1, float(arrays[name][i]), where(i))
    return selected, arrays, n, fmt, cells, where


def _count_lines(path: Path) -> int:
    count = 0
    with open(path, "rb") as f:
        while chunk := f.read(8 << 20):
            count += chunk.count(b"\n")
    return count + 1


# --------------------------------------------------------------------------- npy files


def _float_view(path: Path, cell: str, a: np.ndarray) -> np.ndarray:
    """A float64 1-D array for column ``a``: a view if possible, else a converted copy."""
    kind = a.dtype.kind
    if a.dtype == np.dtype(np.float64):  # native float64: a view of the memory map
        out = np.asarray(a).view()
        out.flags.writeable = False
        return out
    if kind not in "fiu" or (kind == "f" and a.dtype.itemsize > 8):
        raise DataError(
            path,
            cell,
            f"column '{cell}' has type {a.dtype}, not a real number type",
            hint="store samples as float64 (or integers within +-2**53)",
        )
    if kind in "iu":
        for start in range(0, len(a), 1 << 20):
            part = a[start : start + (1 << 20)]
            big = np.flatnonzero((part > _MAX_EXACT_INT) | (part < -_MAX_EXACT_INT))
            if big.size:
                r = start + int(big[0]) + 1
                raise DataError(
                    path,
                    _cell_field(cell, r),
                    f"integer {int(part[big[0]])} in row {r} is too large to convert to "
                    "float64 exactly (limit 2**53)",
                    hint="store the samples as float64 or rescale them",
                )
    out = np.empty(len(a), dtype=np.float64)
    for start in range(0, len(a), 1 << 20):
        out[start : start + (1 << 20)] = a[start : start + (1 << 20)]
    out.flags.writeable = False
    return out


def _read_npy(path: Path, columns: list[tuple[str, str | None]] | None):
    with open(path, "rb") as f:
        magic = f.read(6)
    if magic != b"\x93NUMPY":
        raise DataError(
            path,
            "header",
            "not a .npy file (the NumPy magic bytes are missing)",
            hint="write the file with numpy.save or metro's write_samples_npy",
        )
    try:
        arr = np.load(path, mmap_mode="r", allow_pickle=False)
    except (ValueError, EOFError, OSError, SyntaxError) as exc:
        msg = str(exc)
        if "mmap length" in msg or "size" in msg:
            raise DataError(
                path,
                "data",
                "the file is shorter than its header says: it is truncated",
                hint="copy or record the file again",
            ) from None
        raise DataError(path, "header", f"cannot read the .npy header: {msg}") from None
    where_idx = _index_where
    if arr.dtype.names is not None:
        if arr.ndim != 1:
            raise DataError(path, "shape", f"a structured array must be 1-D, not {arr.shape}")
        available = _check_cells(path, list(arr.dtype.names), "field name")
        selected = _select(path, available, columns)
        raw = {n: arr[f"{n} [{u}]"] for n, u in selected}
        if any(arr.dtype.fields[f"{n} [{u}]"][0].shape for n, u in selected):
            raise DataError(path, "dtype", "sub-array fields are not supported")
    else:
        if arr.ndim not in (1, 2):
            raise DataError(
                path, "shape", f"expected a 1-D or 2-D array, not shape {arr.shape}"
            )
        k = 1 if arr.ndim == 1 else arr.shape[1]
        if columns is None or any(u is None for _, u in columns):
            raise DataError(
                path,
                "columns",
                "a plain .npy array carries no column names or units",
                hint=f"declare its {k} column(s) with units, e.g. columns=[('output', 'P')]"
                ", or save a structured array with 'name [unit]' fields",
            )
        if len(columns) != k:
            raise DataError(
                path,
                "columns",
                f"the array has {k} column(s) but {len(columns)} were declared",
            )
        selected = [(n, str(u)) for n, u in columns]
        _check_cells(path, [f"{n} [{u}]" for n, u in selected], "declared column")
        raw = {n: (arr if arr.ndim == 1 else arr[:, j]) for j, (n, _) in enumerate(selected)}
    cells = {n: f"{n} [{u}]" for n, u in selected}
    arrays = {n: _float_view(path, cells[n], a) for n, a in raw.items()}
    n_rows = int(arr.shape[0])
    first_bad = None
    for name, a in arrays.items():
        i = _first_nonfinite(a)
        if i is not None and (first_bad is None or i < first_bad[0]):
            first_bad = (i, name)
    if first_bad is not None:
        i, name = first_bad
        raise _nonfinite_error(path, cells[name], i + 1, float(arrays[name][i]), where_idx(i))
    return selected, arrays, n_rows, "npy", cells, where_idx


def _index_where(index: int) -> str:
    return f" (index {index})"


# --------------------------------------------------------------------------- parquet


def _read_parquet(path: Path, columns: list[tuple[str, str | None]] | None, parsed=lambda: None):
    extras.require("pyarrow", f"reading the Parquet file {path}")
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    try:
        pf = pq.ParquetFile(path)
    except (pa.ArrowInvalid, OSError) as exc:
        raise DataError(
            path,
            "header",
            f"not a readable parquet file: {exc}",
            hint="the file may be truncated or of another type; copy or write it again",
        ) from None
    schema = pf.schema_arrow
    try:
        available = _check_cells(path, list(schema.names), "column name")
    except DataError as exc:
        field = schema.field(exc.field) if exc.field in schema.names else None
        if field is not None and field.metadata and b"unit" in field.metadata:
            exc.hint = (
                "metro reads the unit from the column name ('name [unit]'), not from the "
                "field metadata; rename the column"
            )
        raise
    selected = _select(path, available, columns)
    cells = {n: f"{n} [{u}]" for n, u in selected}
    try:
        table = pf.read(columns=list(cells.values()), use_threads=True)
    except (pa.ArrowInvalid, OSError) as exc:
        raise DataError(
            path, "data", f"cannot read the parquet data: {exc}",
            hint="the file may be truncated; copy or write it again",
        ) from None
    parsed()
    n = table.num_rows
    arrays: dict[str, np.ndarray] = {}
    first_bad = None
    for name, _ in selected:
        cell = cells[name]
        col = table.column(cell)
        typ = col.type
        if col.null_count:
            i = int(pc.index(pc.is_null(col), True).as_py())
            raise DataError(
                path,
                _cell_field(cell, i + 1),
                f"row {i + 1} (index {i}) of column '{cell}' is empty (null)",
                hint="fill the cell or cut the record; metro does not fill gaps",
            )
        if not (pa.types.is_floating(typ) or pa.types.is_integer(typ)):
            first = col[0].as_py() if len(col) else None
            raise DataError(
                path,
                _cell_field(cell, 1),
                f"column '{cell}' has type {typ}, not numbers (row 1 holds {first!r})",
                hint="store samples as float64 (time as seconds in a float column)",
            )
        if pa.types.is_integer(typ):
            mm = pc.min_max(col).as_py()
            if max(abs(mm["min"] or 0), abs(mm["max"] or 0)) > _MAX_EXACT_INT:
                raise DataError(
                    path,
                    cell,
                    f"column '{cell}' holds integers beyond 2**53 that float64 cannot "
                    "represent exactly",
                    hint="store the samples as float64 or rescale them",
                )
        parts = (_float64_chunk(pc.cast(c, pa.float64())) for c in col.chunks)
        out, bad = _assemble(parts, n)
        arrays[name] = out
        if bad is not None and (first_bad is None or bad < first_bad[0]):
            first_bad = (bad, name)
    del table
    if first_bad is not None:
        i, name = first_bad
        raise _nonfinite_error(
            path, cells[name], i + 1, float(arrays[name][i]), _index_where(i)
        )
    return selected, arrays, n, "parquet", cells, _index_where


# --------------------------------------------------------------------------- public reader


def read_samples(
    path: str | os.PathLike[str],
    *,
    columns: Sequence[str | tuple[str, str]] | Mapping[str, str] | None = None,
    time_column: str | None = "time",
    expected_interval_s: float | None = None,
    rel_interval_tol: float | None = 1e-6,
    gap_factor: float = 1.5,
    min_rows: int = 1,
    delimiter: str | None = None,
    require_final_newline: bool = True,
    background_hash: bool = True,
) -> SampleTable:
    """Read one segment's sample file (see the module notes for the conventions).

    ``columns`` -- for self-describing files, the columns to read, in order: names, or
    ``(name, unit)`` pairs whose unit must equal the file's text; default: all.  For a
    plain (unstructured) ``.npy`` array it declares every column: ``[(name, unit), ...]``.
    ``time_column`` -- name of the time column, checked if the table has it.
    ``expected_interval_s`` -- the sampling interval the manifest states.
    ``rel_interval_tol`` -- relative tolerance for uniform sampling and for
    ``expected_interval_s``; None skips the uniformity check (gaps are still checked).
    ``gap_factor`` -- a time step above this multiple of the median step is a gap.
    ``min_rows`` -- fewer data rows is an error.
    ``delimiter`` -- override the text delimiter.
    ``require_final_newline`` -- treat a text file not ending in a line end as truncated.
    ``background_hash`` -- return before the SHA-256 is complete (see the module notes).
    """
    p = Path(path)
    st = _stat(p)
    fmt = _format_of(p)
    wanted = _normalize_columns(columns)
    digest = _Digest(p, _stat_key(st))
    # Hashing (~200 MB/s without SHA instructions) would compete with pyarrow's parser
    # threads for the cores; in the background mode it starts once the bulk parse is done
    # and overlaps the single-threaded checks and the caller's own work.
    if not background_hash:
        digest.start()
    try:
        if fmt in ("csv", "tsv"):
            selected, arrays, n_rows, fmt, cells, where = _read_text(
                p,
                fmt,
                columns=wanted,
                delimiter=delimiter,
                require_final_newline=require_final_newline,
                size=st.st_size,
                parsed=digest.start,
            )
        elif fmt == "npy":
            digest.start()
            selected, arrays, n_rows, fmt, cells, where = _read_npy(p, wanted)
        else:
            selected, arrays, n_rows, fmt, cells, where = _read_parquet(
                p, wanted, parsed=digest.start
            )
        if _stat_key(_stat(p)) != _stat_key(st):
            raise _changed(p)
        if n_rows < min_rows:
            raise DataError(
                p,
                "rows",
                f"{n_rows} data row(s), fewer than the {min_rows} required",
                hint="the record is too short for this procedure; check that it is "
                "complete",
            )
        interval = None
        if time_column is not None and time_column in arrays:
            interval = _check_time(
                p,
                cells[time_column],
                arrays[time_column],
                expected_interval_s=expected_interval_s,
                rel_interval_tol=rel_interval_tol,
                gap_factor=gap_factor,
                where=where,
            )
    except BaseException:
        digest.cancel()
        raise
    digest.start()
    sha: str | _Digest = digest
    if not background_hash:
        sha = digest.result()
    return SampleTable(
        path=p,
        columns=arrays,
        units={n: u for n, u in selected},
        sha256=sha,
        n_rows=n_rows,
        format=fmt,
        sample_interval_s=interval,
    )


# --------------------------------------------------------------------------- writers


def _prepare_columns(
    path: Path, columns: Mapping[str, Any], units: Mapping[str, str]
) -> tuple[list[str], list[np.ndarray]]:
    if not columns:
        raise DataError(path, "columns", "nothing to write: no columns given")
    cells: list[str] = []
    arrays: list[np.ndarray] = []
    n = None
    for name, values in columns.items():
        if name not in units:
            raise DataError(path, name, f"no unit given for column '{name}'",
                            hint="pass units={name: unit, ...}; use '1' if dimensionless")
        cell = f"{name} [{units[name]}]"
        bad = set(name + str(units[name])) & set(",\t\r\n\"")
        if parse_header_cell(cell) != (name, str(units[name])) or bad or name != name.strip():
            raise DataError(
                path,
                name,
                f"'{cell}' cannot be written as a header cell",
                hint="names and units may not contain brackets, delimiters, quotes or "
                "line breaks, and names may not start or end with spaces",
            )
        a = np.asarray(values)
        if a.ndim != 1:
            raise DataError(path, name, f"column '{name}' is not 1-D (shape {a.shape})")
        if n is None:
            n = len(a)
        elif len(a) != n:
            raise DataError(path, name, f"column '{name}' has {len(a)} rows, others {n}")
        if a.dtype.kind == "b":
            a = a.astype(np.int64)
        if a.dtype.kind in "iu":
            if a.size and (a.max() > _MAX_EXACT_INT or a.min() < -_MAX_EXACT_INT):
                raise DataError(path, name, f"column '{name}' has integers beyond 2**53",
                                hint="they would not read back exactly as float64")
            a = a.astype(np.int64, copy=False)
        elif a.dtype.kind == "f":
            a = a.astype(np.float64, copy=False)
            i = _first_nonfinite(a)
            if i is not None:
                raise DataError(path, _cell_field(cell, i + 1),
                                f"cannot write {a[i]} (row {i + 1}): samples must be finite")
        else:
            raise DataError(path, name, f"column '{name}' has type {a.dtype}, not numbers")
        cells.append(cell)
        arrays.append(a)
    if cells and cells[0].startswith("#"):
        raise DataError(path, cells[0], "the first column name may not start with '#'")
    return cells, arrays


def write_samples_csv(
    path: str | os.PathLike[str],
    columns: Mapping[str, Any],
    units: Mapping[str, str],
    *,
    comments: Sequence[str] = (),
    delimiter: str | None = None,
) -> Path:
    """Write a sample file in the text format :func:`read_samples` reads, atomically.

    Floats are written as the shortest text that reads back as the same float64
    (exact round trip); integer and boolean columns as integers.  The delimiter follows
    the suffix (',' for .csv, tab for .tsv/.txt).  ``comments`` become '# ' lines
    before the header.  The file appears complete or not at all: it is written to a
    temporary file in the same directory, flushed to disk and renamed over ``path``.
    """
    from concurrent.futures import ThreadPoolExecutor

    p = Path(path)
    if delimiter is None:
        delimiter = "," if p.suffix.lower() == ".csv" else "\t"
    cells, arrays = _prepare_columns(p, columns, units)
    for cell in cells:
        if delimiter in cell:
            raise DataError(p, cell, f"header cell '{cell}' contains the delimiter {delimiter!r}")
    n = len(arrays[0])
    head = "".join(f"# {c}\n" for line in comments for c in str(line).splitlines() or [""])
    head += delimiter.join(cells) + "\n"
    render = _arrow_renderer(arrays, delimiter) if _arrow() else _numpy_renderer(arrays, delimiter)
    workers = max(1, min(os.cpu_count() or 1, 8)) if _arrow() else 1
    with atomic_path(p) as tmp, open(tmp, "wb") as f:
        f.write(head.encode("utf-8"))
        with ThreadPoolExecutor(workers) as pool:
            pending = []
            for start in range(0, n, _WRITE_ROWS):
                pending.append(pool.submit(render, start, min(start + _WRITE_ROWS, n)))
                if len(pending) > 2 * workers:
                    f.write(pending.pop(0).result())
            for fut in pending:
                f.write(fut.result())
    return p


def _arrow_renderer(arrays: Sequence[np.ndarray], delimiter: str):
    """Rows start:stop as CSV bytes, formatted by pyarrow (C++, releases the GIL)."""
    import pyarrow as pa
    import pyarrow.csv as pcsv

    options = pcsv.WriteOptions(include_header=False, delimiter=delimiter, quoting_style="none")
    col_names = [f"c{i}" for i in range(len(arrays))]

    def render(start: int, stop: int) -> Any:
        table = pa.table([pa.array(a[start:stop]) for a in arrays], names=col_names)
        sink = pa.BufferOutputStream()
        pcsv.write_csv(table, sink, options)
        return sink.getvalue()

    return render


def _float_text(s: str) -> str:
    """Python's shortest float text (``repr``) in the layout pyarrow writes, so a file is the same
    byte for byte with or without pyarrow: positional for exponents -6 to 9 without a trailing
    ".0" (1, -0, 0.00001, 1500000000), otherwise d.ddde±N (1e-7, 1.23456789015e+10)."""
    if "e" not in s:
        if s.endswith(".0"):
            s = s[:-2]
        if len(s.lstrip("-").split(".")[0]) <= 10:
            return s
    d = Decimal(s)
    e = d.adjusted()
    if -6 <= e <= 9:
        return format(d, "f")
    digits = "".join(map(str, d.as_tuple().digits)).rstrip("0") or "0"
    mant = digits[0] + ("." + digits[1:] if len(digits) > 1 else "")
    return f"{'-' if d.is_signed() else ''}{mant}e{e:+d}"


def _numpy_renderer(arrays: Sequence[np.ndarray], delimiter: str):
    """Rows start:stop as CSV bytes without pyarrow, in the text pyarrow writes."""

    def render(start: int, stop: int) -> bytes:
        cols = []
        for a in arrays:
            text = a[start:stop].astype(str).tolist()
            cols.append(list(map(_float_text, text)) if a.dtype.kind == "f" else text)
        rows = cols[0] if len(cols) == 1 else map(delimiter.join, zip(*cols))
        return ("\n".join(rows) + "\n").encode("ascii") if stop > start else b""

    return render


def write_samples_npy(
    path: str | os.PathLike[str],
    columns: Mapping[str, Any],
    units: Mapping[str, str],
) -> Path:
    """Write a structured float64 ``.npy`` with ``'name [unit]'`` fields, atomically."""
    p = Path(path)
    cells, arrays = _prepare_columns(p, columns, units)
    out = np.empty(len(arrays[0]), dtype=[(c, "<f8") for c in cells])
    for cell, a in zip(cells, arrays):
        out[cell] = a
    with atomic_path(p) as tmp, open(tmp, "wb") as f:
        np.save(f, out, allow_pickle=False)
    return p

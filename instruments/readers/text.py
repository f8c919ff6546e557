"""Reading delimited text samples (``.csv``, ``.tsv``, ``.txt``): the header, a NumPy parser
of the bytes (exact float64 values) and, when installed, pyarrow's CSV reader."""

from __future__ import annotations

import csv
import functools
import os
import re
from collections.abc import Iterator, Mapping
from pathlib import Path

import attrs
import numpy as np

from metro.core.base.errors import DataError
from metro.core.base import extras

from .common import assemble, cell_field, check_cells, drain, nonfinite_error, select_columns


_BLOCK_BYTES = 4 << 20  # pyarrow CSV block size: ~0.4 M rows of one numeric column


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
            hint="add a header line naming each column with its unit, e.g. 'time [s],output [P]'",
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


def _parse_fields(
    buf: np.ndarray, starts: np.ndarray, lens: np.ndarray, delimiter: int, *, exponents: bool = True
) -> tuple[np.ndarray, np.ndarray]:
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
                values[part], other[part] = _parse_fields(
                    buf, starts[part], lens[part], delimiter, exponents=exponents
                )
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
        values[exact] = _exact_values(
            buf, starts[exact], lens[exact], mant[exact], e10[exact], neg[exact], ndig[exact]
        )
    return values, ~number


_WIDE = np.finfo(np.longdouble).nmant >= 63  # x87 extended (or quad): a 64-bit mantissa is exact
_POW10_WIDE = np.cumprod(np.r_[1, np.full(27, 10)].astype(np.longdouble))  # 10**0..10**27, exact


def _exact_values(
    buf: np.ndarray,
    starts: np.ndarray,
    lens: np.ndarray,
    mant: np.ndarray,
    e10: np.ndarray,
    neg: np.ndarray,
    ndig: np.ndarray,
) -> np.ndarray:
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
        hint = (
            "a short last row means the file was cut off: copy or record it again"
            if last
            else "fill in the missing cells or remove the row"
        )
    else:
        note = ""
        hint = "remove the extra cells; check the delimiter and that the decimal separator is '.'"
    return DataError(
        layout.path,
        f"row {row}",
        f"row {row}{at} has {cells} cell(s) but the header has {expected}: {_show(text)}{note}",
        hint=hint,
    )


def _value_error(layout: _TextLayout, cell: str, row: int, text: str) -> DataError:
    line = _line_of_row(layout, row)
    at = f" (line {line})" if line is not None else ""
    if not text.strip().strip('"').strip():
        what = "an empty cell"
        hint = "fill the cell or remove the row; metro does not fill gaps"
    else:
        what = f"{_show(text)}, which is not a number"
        hint = "cells must be plain decimal numbers such as -1.25e-3"
    return DataError(
        layout.path,
        cell_field(cell, row),
        f"row {row}{at} has {what} in column '{cell}'",
        hint=hint,
    )


_NUMBER = re.compile(
    rb"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?|[+-]?(nan|inf|infinity)", re.IGNORECASE
)


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


def _slow_values(
    chunk: bytes, starts: np.ndarray, lens: np.ndarray, values: np.ndarray, slow: np.ndarray
) -> int | None:
    """Fill ``values`` at ``slow`` with :func:`_cell_value`; the index of the first field that is
    no number."""
    for i in np.flatnonzero(slow):
        s = int(starts[i])
        try:
            values[i] = _cell_value(chunk[s : s + int(lens[i])])
        except ValueError:
            return int(i)
    return None


def _chunk_rows(
    b: np.ndarray, delim: int, ncols: int
) -> tuple[np.ndarray, np.ndarray, int | None, int]:
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


def _parse_text_numpy(
    layout: _TextLayout, names: list[str], wanted: list[str], cells: Mapping[str, str]
) -> tuple[dict[str, list[np.ndarray]], int]:
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


def _diagnose_text(
    layout: _TextLayout,
    names: list[str],
    wanted: list[str],
    cells: Mapping[str, str],
    exc: Exception,
) -> DataError:
    """Find the first bad row after pyarrow's fast parse failed (with the numpy parser: no Python
    callback runs on an arrow thread, which could still be running when the interpreter exits)."""
    try:
        _parse_text_numpy(layout, names, wanted, cells)
    except DataError as err:  # the first bad row
        return err
    return DataError(layout.path, None, f"cannot parse the data: {exc}")


def have_arrow() -> bool:
    """Parse with pyarrow (the ``fast`` extra) if it is installed and METRO_NO_PYARROW unset."""
    return os.environ.get("METRO_NO_PYARROW", "") in ("", "0") and extras.available("pyarrow")


def _read_text_arrow(
    layout: _TextLayout, names: list[str], wanted: list[str], cells: Mapping[str, str]
) -> tuple[int, dict[str, Iterator[np.ndarray]]]:
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
            table = pcsv.read_csv(
                f,
                read_options=read_options,
                parse_options=parse_options,
                convert_options=convert_options,
            )
    except pa.ArrowInvalid as exc:
        raise _diagnose_text(layout, names, wanted, cells, exc) from None
    n = table.num_rows
    chunked = {name: table.column(name) for name in wanted}
    del table
    return n, {name: drain(chunked.pop(name)) for name in wanted}


def read_text(
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
    available = check_cells(path, layout.cells, "header cell")
    selected = select_columns(path, available, columns)
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

    if have_arrow():
        n, sources = _read_text_arrow(layout, names, wanted, cells)
    else:
        parts, n = _parse_text_numpy(layout, names, wanted, cells)
        sources = {name: iter(parts.pop(name)) for name in wanted}
    parsed()
    arrays: dict[str, np.ndarray] = {}
    first_bad: tuple[int, str] | None = None
    for name in wanted:
        out, bad = assemble(sources.pop(name), n)
        arrays[name] = out
        if bad is not None and (first_bad is None or bad < first_bad[0]):
            first_bad = (bad, name)
    if first_bad is not None:
        i, name = first_bad
        raise nonfinite_error(path, cells[name], i + 1, float(arrays[name][i]), where(i))
    return selected, arrays, n, fmt, cells, where


def _count_lines(path: Path) -> int:
    count = 0
    with open(path, "rb") as f:
        while chunk := f.read(8 << 20):
            count += chunk.count(b"\n")
    return count + 1

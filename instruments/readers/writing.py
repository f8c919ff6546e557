"""The writers: :func:`write_samples_csv` (shortest round-trip float text, atomically) and
:func:`write_samples_npy` (structured float64 ``name [unit]`` fields)."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from decimal import Decimal
from pathlib import Path
from typing import Any

import numpy as np

from metro.core.base.atomic import atomic_path
from metro.core.base.errors import DataError

from .common import MAX_EXACT_INT, cell_field, first_nonfinite, parse_header_cell
from .text import have_arrow


_WRITE_ROWS = 1 << 18  # rows formatted per writer task


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
            raise DataError(
                path,
                name,
                f"no unit given for column '{name}'",
                hint="pass units={name: unit, ...}; use '1' if dimensionless",
            )
        cell = f"{name} [{units[name]}]"
        bad = set(name + str(units[name])) & set(',\t\r\n"')
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
            if a.size and (a.max() > MAX_EXACT_INT or a.min() < -MAX_EXACT_INT):
                raise DataError(
                    path,
                    name,
                    f"column '{name}' has integers beyond 2**53",
                    hint="they would not read back exactly as float64",
                )
            a = a.astype(np.int64, copy=False)
        elif a.dtype.kind == "f":
            a = a.astype(np.float64, copy=False)
            i = first_nonfinite(a)
            if i is not None:
                raise DataError(
                    path,
                    cell_field(cell, i + 1),
                    f"cannot write {a[i]} (row {i + 1}): samples must be finite",
                )
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
    render = (
        _arrow_renderer(arrays, delimiter) if have_arrow() else _numpy_renderer(arrays, delimiter)
    )
    workers = max(1, min(os.cpu_count() or 1, 8)) if have_arrow() else 1
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

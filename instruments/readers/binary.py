"""Reading NumPy ``.npy`` (memory-mapped) and Apache Parquet samples."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from metro.core.base.errors import DataError
from metro.core.base import extras

from .common import (MAX_EXACT_INT, assemble, cell_field, check_cells, first_nonfinite,
                     float64_chunk, nonfinite_error, refused_as_data, select_columns)


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
            big = np.flatnonzero((part > MAX_EXACT_INT) | (part < -MAX_EXACT_INT))
            if big.size:
                r = start + int(big[0]) + 1
                raise DataError(
                    path,
                    cell_field(cell, r),
                    f"integer {int(part[big[0]])} in row {r} is too large to convert to "
                    "float64 exactly (limit 2**53)",
                    hint="store the samples as float64 or rescale them",
                )
    out = np.empty(len(a), dtype=np.float64)
    for start in range(0, len(a), 1 << 20):
        out[start : start + (1 << 20)] = a[start : start + (1 << 20)]
    out.flags.writeable = False
    return out


def read_npy(path: Path, columns: list[tuple[str, str | None]] | None):
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
        available = check_cells(path, list(arr.dtype.names), "field name")
        selected = select_columns(path, available, columns)
        raw = {n: arr[f"{n} [{u}]"] for n, u in selected}
        if any(arr.dtype.fields[f"{n} [{u}]"][0].shape for n, u in selected):
            raise DataError(path, "dtype", "sub-array fields are not supported")
    else:
        if arr.ndim not in (1, 2):
            raise DataError(path, "shape", f"expected a 1-D or 2-D array, not shape {arr.shape}")
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
        check_cells(path, [f"{n} [{u}]" for n, u in selected], "declared column")
        raw = {n: (arr if arr.ndim == 1 else arr[:, j]) for j, (n, _) in enumerate(selected)}
    cells = {n: f"{n} [{u}]" for n, u in selected}
    arrays = {n: _float_view(path, cells[n], a) for n, a in raw.items()}
    n_rows = int(arr.shape[0])
    first_bad = None
    for name, a in arrays.items():
        i = first_nonfinite(a)
        if i is not None and (first_bad is None or i < first_bad[0]):
            first_bad = (i, name)
    if first_bad is not None:
        i, name = first_bad
        raise nonfinite_error(path, cells[name], i + 1, float(arrays[name][i]), where_idx(i))
    return selected, arrays, n_rows, "npy", cells, where_idx


def _index_where(index: int) -> str:
    return f" (index {index})"


# --------------------------------------------------------------------------- parquet


def read_parquet(path: Path, columns: list[tuple[str, str | None]] | None, parsed=lambda: None):
    extras.require("pyarrow", f"reading the Parquet file {path}")
    import pyarrow as pa
    import pyarrow.compute as pc
    import pyarrow.parquet as pq

    with refused_as_data((pa.ArrowInvalid, OSError), path, "header", "not a readable parquet file",
                         "the file may be truncated or of another type; copy or write it again"):
        pf = pq.ParquetFile(path)
    schema = pf.schema_arrow
    try:
        available = check_cells(path, list(schema.names), "column name")
    except DataError as exc:
        field = schema.field(exc.field) if exc.field in schema.names else None
        if field is not None and field.metadata and b"unit" in field.metadata:
            exc.hint = (
                "metro reads the unit from the column name ('name [unit]'), not from the "
                "field metadata; rename the column"
            )
        raise
    selected = select_columns(path, available, columns)
    cells = {n: f"{n} [{u}]" for n, u in selected}
    with refused_as_data((pa.ArrowInvalid, OSError), path, "data", "cannot read the parquet data",
                         "the file may be truncated; copy or write it again"):
        table = pf.read(columns=list(cells.values()), use_threads=True)
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
                cell_field(cell, i + 1),
                f"row {i + 1} (index {i}) of column '{cell}' is empty (null)",
                hint="fill the cell or cut the record; metro does not fill gaps",
            )
        if not (pa.types.is_floating(typ) or pa.types.is_integer(typ)):
            first = col[0].as_py() if len(col) else None
            raise DataError(
                path,
                cell_field(cell, 1),
                f"column '{cell}' has type {typ}, not numbers (row 1 holds {first!r})",
                hint="store samples as float64 (time as seconds in a float column)",
            )
        if pa.types.is_integer(typ):
            mm = pc.min_max(col).as_py()
            if max(abs(mm["min"] or 0), abs(mm["max"] or 0)) > MAX_EXACT_INT:
                raise DataError(
                    path,
                    cell,
                    f"column '{cell}' holds integers beyond 2**53 that float64 cannot "
                    "represent exactly",
                    hint="store the samples as float64 or rescale them",
                )
        parts = (float64_chunk(pc.cast(c, pa.float64())) for c in col.chunks)
        out, bad = assemble(parts, n)
        arrays[name] = out
        if bad is not None and (first_bad is None or bad < first_bad[0]):
            first_bad = (bad, name)
    del table
    if first_bad is not None:
        i, name = first_bad
        raise nonfinite_error(path, cells[name], i + 1, float(arrays[name][i]), _index_where(i))
    return selected, arrays, n, "parquet", cells, _index_where

"""The public reader: :func:`read_samples` chooses the format by suffix and checks the time
column."""

from __future__ import annotations

import os
from collections.abc import Mapping, Sequence
from pathlib import Path


from metro.core.base.errors import DataError

from .common import (Digest, SampleTable, changed_error, check_time, file_stat, format_of,
                     normalize_columns, stat_key)
from .text import read_text
from .binary import read_npy, read_parquet


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
    st = file_stat(p)
    fmt = format_of(p)
    wanted = normalize_columns(columns)
    digest = Digest(p, stat_key(st))
    # Hashing (~200 MB/s without SHA instructions) would compete with pyarrow's parser
    # threads for the cores; in the background mode it starts once the bulk parse is done
    # and overlaps the single-threaded checks and the caller's own work.
    if not background_hash:
        digest.start()
    try:
        if fmt in ("csv", "tsv"):
            selected, arrays, n_rows, fmt, cells, where = read_text(
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
            selected, arrays, n_rows, fmt, cells, where = read_npy(p, wanted)
        else:
            selected, arrays, n_rows, fmt, cells, where = read_parquet(
                p, wanted, parsed=digest.start
            )
        if stat_key(file_stat(p)) != stat_key(st):
            raise changed_error(p)
        if n_rows < min_rows:
            raise DataError(
                p,
                "rows",
                f"{n_rows} data row(s), fewer than the {min_rows} required",
                hint="the record is too short for this procedure; check that it is complete",
            )
        interval = None
        if time_column is not None and time_column in arrays:
            interval = check_time(
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
    sha: str | Digest = digest
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

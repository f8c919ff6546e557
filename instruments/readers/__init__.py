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

from .common import FORMATS, SampleTable, parse_header_cell
from .reading import read_samples
from .writing import write_samples_csv, write_samples_npy

__all__ = [
    "FORMATS",
    "SampleTable",
    "parse_header_cell",
    "read_samples",
    "write_samples_csv",
    "write_samples_npy",
]

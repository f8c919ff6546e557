"""ACME's binary sample format, ``.acme`` (little-endian)::

    offset  size  field
    0       6     magic b"ACME1\\0"
    6       2     uint16 format version (1)
    8       8     float64 sample interval, s
    16      4     uint32 number of samples n
    20      16    ASCII unit of the samples, NUL-padded (e.g. "P")
    36      4·n   int32 samples

``read_acme`` returns what metro's manifest loader needs from a reader (``columns``,
``units``, ``sha256``) with columns ``time`` [s] and ``output`` [unit]; every problem is a
:class:`metro.core.base.errors.DataError` naming the file, the field and the reason.
"""

from __future__ import annotations

import hashlib
import struct
from pathlib import Path

import numpy as np
from metro.api import DataError

MAGIC = b"ACME1\0"
HEADER = struct.Struct("<6sHdI16s")


class AcmeTable:
    """The samples of one ``.acme`` file."""

    def __init__(self, path: Path, columns: dict, units: dict, sha256: str,
                 interval_s: float) -> None:
        self.path = path
        self.columns = columns
        self.units = units
        self.sha256 = sha256
        self.sample_interval_s = interval_s
        self.n_rows = len(columns["output"])
        self.format = "acme"


def write_acme(path, samples, interval_s: float, unit: str = "P") -> Path:
    """Write ``samples`` (whole numbers) as an ``.acme`` file (ACME's logger does this on the
    bench)."""
    a = np.asarray(samples)
    if not np.all(a == np.round(a)) or np.abs(a).max(initial=0) >= 2**31:
        raise ValueError("ACME files hold 32-bit whole-number samples")
    path = Path(path)
    path.write_bytes(HEADER.pack(MAGIC, 1, float(interval_s), a.size, unit.encode("ascii"))
                     + a.astype("<i4").tobytes())
    return path


def read_acme(path, **_kw) -> AcmeTable:
    path = Path(path)
    raw = path.read_bytes()
    if len(raw) < HEADER.size:
        raise DataError(str(path), "header",
                        f"file is {len(raw)} bytes, shorter than the {HEADER.size}-byte header")
    magic, version, interval, n, unit = HEADER.unpack_from(raw)
    if magic != MAGIC:
        raise DataError(str(path), "header.magic", f"not an ACME file (magic {magic!r})")
    if version != 1:
        raise DataError(str(path), "header.version",
                        f"format version {version} is not supported (only 1)")
    if not interval > 0:
        raise DataError(str(path), "header.interval",
                        f"sample interval {interval!r} s is not positive")
    body = raw[HEADER.size:]
    if len(body) != 4 * n:
        raise DataError(str(path), "samples",
                        f"the header announces {n} samples but the file holds "
                        f"{len(body) / 4:g}",
                        hint="the file is truncated or was not closed by the logger")
    data = np.frombuffer(body, dtype="<i4").astype(np.float64)
    data.flags.writeable = False
    unit_text = unit.rstrip(b"\0").decode("ascii", errors="replace")
    t = interval * np.arange(1, n + 1, dtype=np.float64)
    return AcmeTable(path, {"time": t, "output": data}, {"time": "s", "output": unit_text},
                     hashlib.sha256(raw).hexdigest(), interval)

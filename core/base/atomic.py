"""Atomic file writing: a file is either written completely or not at all.

Everything is written to a temporary file in the target's own directory (named ``.{name}.tmp-<8
random characters>``, so it is on the same file system and hidden from a plain ``ls``); only when
the writer has finished without an error is the temporary file flushed to disk and renamed onto the
target with :func:`os.replace`, which is atomic on POSIX and Windows. On any exception,
``KeyboardInterrupt`` included, the temporary file is removed and a file that already existed at the
target is left exactly as it was. A process killed outright (SIGKILL, power loss) cannot clean up:
the next atomic write into the same directory removes temporary files of that pattern older than
:data:`STALE_AFTER_S` (:func:`sweep_stale`).

>>> atomic_write_text(path, "hello\\n")                     # doctest: +SKIP
>>> atomic_write(path, lambda tmp: figure.savefig(tmp, format="png"))  # doctest: +SKIP
>>> with atomic_path("report.docx") as tmp:                 # doctest: +SKIP
...     document.save(tmp)
"""

from __future__ import annotations

import contextlib
import os
import re
import secrets
import stat
from pathlib import Path
from typing import Callable, Iterator

__all__ = ["atomic_path", "atomic_write", "atomic_write_text", "atomic_write_bytes", "TMP_MARKER",
           "sweep_stale", "STALE_AFTER_S", "write_failure"]

#: Every temporary file's name contains this marker: ``.{name}{TMP_MARKER}{8 hex digits}``.
TMP_MARKER = ".tmp-"

_TRIES = 100

#: a temporary file this old was left by a writer that was killed (a write takes seconds)
STALE_AFTER_S = 15 * 60

_TMP_NAME = re.compile(r"^\..+" + re.escape(TMP_MARKER) + r"[0-9a-f]{8}$")


def write_failure(exc: OSError) -> tuple[str, str]:
    """(reason, what to do) for an ``OSError`` met while writing, in words a user acts on: a full
    disk (ENOSPC) says so, as do a used-up quota, a read-only file system and a refused
    permission."""
    import errno

    code, said = exc.errno, exc.strerror or str(exc)
    if code == errno.ENOSPC:
        return (
            f"the disk is full ({said})", "free some space on that disk, or write to another folder"
        )
    if code == getattr(errno, "EDQUOT", None):
        return (
            f"your disk quota is used up ({said})",
            "free some space in your quota, or write to another folder"
        )
    if code == errno.EROFS:
        return f"the file system is read-only ({said})", "write to another folder"
    if code in (errno.EACCES, errno.EPERM):
        return (
            f"permission denied ({said})",
            "write to a folder you may write in, or ask for write access"
        )
    return said, "check the disk and the folder, or write to another folder"


def sweep_stale(directory: str | os.PathLike[str], *,
                older_than_s: float = STALE_AFTER_S) -> list[Path]:
    """Remove the temporary files (``.{name}.tmp-<8 hex digits>``) in ``directory`` that are older
    than ``older_than_s`` — left behind by a writer killed between writing and renaming — and
    return their paths.  Only regular files of exactly that pattern are touched."""
    import time

    removed: list[Path] = []
    now = time.time()
    try:
        entries = list(os.scandir(directory))
    except OSError:
        return removed
    for entry in entries:
        if not _TMP_NAME.match(entry.name):
            continue
        try:
            st = entry.stat(follow_symlinks=False)
            if not stat.S_ISREG(st.st_mode) or now - st.st_mtime < older_than_s:
                continue
            os.unlink(entry.path)
        except OSError:
            continue
        removed.append(Path(entry.path))
    return removed


def _create_temp(final: Path) -> Path:
    """Create (exclusively) an empty temporary file next to ``final`` and return its path.

    The file is created with mode 0o666 filtered by the process umask, like any new file,
    so the final file gets the usual permissions (``tempfile.mkstemp`` would give 0o600).
    """
    for _ in range(_TRIES):
        tmp = final.with_name(f".{final.name}{TMP_MARKER}{secrets.token_hex(4)}")
        try:
            fd = os.open(tmp, os.O_WRONLY | os.O_CREAT | os.O_EXCL | getattr(os, "O_BINARY", 0),
                         0o666)
        except FileExistsError:
            continue
        os.close(fd)
        return tmp
    raise FileExistsError(f"could not create a temporary file next to {final}")  # pragma: no cover


def _fsync_file(path: Path) -> None:
    fd = os.open(path, os.O_RDONLY | getattr(os, "O_BINARY", 0))
    try:
        os.fsync(fd)
    finally:
        os.close(fd)


def _fsync_dir(directory: Path) -> None:
    """Make the rename durable (POSIX); directories cannot be opened on Windows."""
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - Windows
        return
    try:
        os.fsync(fd)
    except OSError:  # pragma: no cover - some file systems refuse fsync on a directory
        pass
    finally:
        os.close(fd)


@contextlib.contextmanager
def atomic_path(path: str | os.PathLike[str]) -> Iterator[Path]:
    """Yield a temporary path to write; on success it replaces ``path`` atomically.

    The temporary file exists (empty) when the block starts; the block may overwrite it,
    e.g. ``document.save(tmp)``.  If the target exists, its permission bits are copied to
    the new file.  The target's directory must exist.  A symbolic link at the target is
    replaced by the new file, not followed.
    """
    final = Path(path)
    directory = final.parent
    if not directory.is_dir():
        raise FileNotFoundError(f"cannot write {final}: directory {directory} does not exist")
    sweep_stale(directory)
    tmp = _create_temp(final)
    try:
        yield tmp
        if not tmp.exists():
            raise FileNotFoundError(f"the writer for {final} removed its temporary file {tmp.name}")
        try:
            mode = stat.S_IMODE(os.stat(final).st_mode)
        except FileNotFoundError:
            pass
        else:
            os.chmod(tmp, mode)
        _fsync_file(tmp)
        os.replace(tmp, final)
    except BaseException:
        with contextlib.suppress(OSError):
            tmp.unlink()
        raise
    _fsync_dir(directory)


def atomic_write(path: str | os.PathLike[str], writer: Callable[[Path], None]) -> Path:
    """Call ``writer(tmp_path)`` and move what it wrote onto ``path`` atomically; return
    ``path``."""
    with atomic_path(path) as tmp:
        writer(tmp)
    return Path(path)


def atomic_write_bytes(path: str | os.PathLike[str], data: bytes) -> Path:
    """Write ``data`` to ``path`` atomically; return ``path``."""

    def _write(tmp: Path) -> None:
        with open(tmp, "wb") as fh:
            fh.write(data)

    return atomic_write(path, _write)


def atomic_write_text(
    path: str | os.PathLike[str],
    text: str,
    *,
    encoding: str = "utf-8",
    newline: str | None = None,
) -> Path:
    """Write ``text`` to ``path`` atomically (UTF-8 by default); return ``path``.

    ``newline`` is as for :func:`open`: ``None`` writes the platform's line ending for
    ``"\\n"``, ``""`` writes the text unchanged.
    """

    def _write(tmp: Path) -> None:
        with open(tmp, "w", encoding=encoding, newline=newline) as fh:
            fh.write(text)

    return atomic_write(path, _write)

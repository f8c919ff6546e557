"""Where a report goes: checked before anything is evaluated, so an output never destroys anything.

* the suffix decides the format (``.docx``; anything else is refused, naming what is taken);
* a report path that is an input of the run (the manifest, a samples file) is refused, even
  with ``--force``; any other existing file is refused unless ``--force`` (and a read-only one
  even then); a directory is not a report path;
* the output folder must be a folder that can be written (not under a file, not read-only):
  checked before the evaluation, not found out after it.

Nothing is created here: folders are made when the report is written.
"""

from __future__ import annotations

import contextlib
import os
import tomllib
from pathlib import Path
from typing import Iterable

import attrs

from ..base.errors import DataError

#: report formats metro writes, by suffix (lower case)
REPORT_FORMATS: dict[str, str] = {".docx": "Word (OOXML)", ".pdf": "PDF/A-2b through LibreOffice",
                                  ".xml": "PTB DCC 3.3.0 certificate"}  # core/cli/dcc_commands.py
#: suffixes refused with a specific reason
_NOT_YET: dict[str, str] = {
    ".doc": "metro writes Word 2007+ (.docx), not the old .doc format",
}


@attrs.frozen
class ReportTarget:
    """The report's path (``path``), or a folder (``directory``) where ``<report number>.docx``
    goes."""

    path: Path | None
    directory: Path
    force: bool = False

    def final(self, report_number: str) -> Path:
        return self.path if self.path is not None else self.directory / f"{report_number}.docx"


def _same(a: Path, b: Path) -> bool:
    try:
        if a.exists() and b.exists():
            return os.path.samefile(a, b)
    except OSError:
        pass
    return a.resolve() == b.resolve()


def manifest_inputs(manifest: str | os.PathLike[str] | None) -> list[Path]:
    """The manifest and the samples files it names (a light read, before the full check; a
    manifest that cannot be read gives just itself, and load_manifest reports why)."""
    if manifest is None:
        return []
    m = Path(manifest)
    out = [m]
    try:
        doc = tomllib.loads(m.read_text(encoding="utf-8-sig"))
    except (OSError, UnicodeDecodeError, tomllib.TOMLDecodeError):
        return out
    segs = doc.get("segments")
    if isinstance(segs, list):
        for s in segs:
            if isinstance(s, dict) and isinstance(s.get("file"), str):
                out.append(m.parent / s["file"])
    return out


def check_writable_folder(folder: Path, option: str, target: Path | None = None) -> None:
    """``folder`` (which may not exist yet) can be created and written: its nearest existing
    ancestor is a folder and writable.  Errors name ``target`` (the report) when given."""
    named = str(target if target is not None else folder)
    p = folder
    while not p.exists():
        if p.parent == p:
            break
        p = p.parent
    if p.exists() and not p.is_dir():
        raise DataError(named, option, f"{p} is a file, so no folder can be made under it",
                        hint="give a folder that is not under a file")
    if p.exists() and not os.access(p, os.W_OK | os.X_OK):
        raise DataError(named, option, f"the folder {p} is not writable",
                        hint="choose another output folder or ask for write access; nothing was "
                        "evaluated")


def check_report_path(path: Path, *, force: bool, inputs: Iterable[Path],
                      option: str = "--report") -> None:
    """Refuse a report path that would destroy something (see the module docstring)."""
    suffix = path.suffix.lower()
    if suffix not in REPORT_FORMATS:
        reason = _NOT_YET.get(suffix,
                              "metro cannot tell the format from the suffix "
                              f"{path.suffix or '(none)'!r}")
        raise DataError(str(path), option, f"{reason}; the report formats are "
                        + ", ".join(f"{s} ({n})" for s, n in REPORT_FORMATS.items()),
                        hint=f"name the report {path.stem or 'report'}.docx")
    for inp in inputs:
        if _same(path, Path(inp)):
            raise DataError(str(path), option,
                            f"is an input of this run ({inp}); metro never writes over its "
                            "own inputs, not even with --force",
                            hint="write the report to another path")
    if path.is_dir():
        raise DataError(str(path), option, "is a folder; --report names the report file",
                        hint=f"use --out {path} to write <report number>.docx into it")
    if path.exists() or path.is_symlink():
        if not force:
            raise DataError(str(path), option, "exists; metro never replaces a file unless told to",
                            hint="choose another path, or add --force to replace it")
        # root too: no write bit
        if not os.access(path, os.W_OK) or not (path.stat().st_mode & 0o222):
            raise DataError(str(path), option,
                            "exists and is read-only; metro does not replace a protected "
                            "file, even with --force", hint="choose another path")
    check_writable_folder(path.parent, option, path)


def plan_report(report: str | None, out: str, *, force: bool, inputs: Iterable[Path],
                pdf: bool = False) -> ReportTarget:
    """Check ``--report`` / ``--out`` before anything is evaluated; return where the report goes.
    With ``pdf`` (``--pdf``) the ``.pdf`` beside a ``--report`` ``.docx`` is checked the same way
    (never an input, an existing one only with ``--force``)."""
    inputs = list(inputs)
    if report is not None:
        p = Path(report)
        check_report_path(p, force=force, inputs=inputs)
        if pdf and p.suffix.lower() != ".pdf":
            check_report_path(p.with_suffix(".pdf"), force=force, inputs=inputs)
        return ReportTarget(p, p.parent, force)
    d = Path(out)
    if d.exists() and not d.is_dir():
        raise DataError(str(d), "--out", "is a file; --out names the folder the report goes into",
                        hint="give a folder, or --report PATH.docx for the file itself")
    check_writable_folder(d, "--out")
    return ReportTarget(None, d, force)


def write_checked(path: Path, campaign, writer, *, force: bool, option: str = "--report",
                  pdf: bool = False) -> Path:
    """Write the report with ``writer(path)`` after checking ``path`` once more against the
    campaign as read (its manifest and every samples file are inputs); folders made for it are
    removed again if the write fails, and an ``OSError`` (a full or read-only file system) is a
    :class:`~metro.core.base.errors.MetroError` saying nothing was written."""
    from ..base.errors import MetroError

    inputs = [Path(p) for p in (campaign.source if getattr(campaign, "manifest_sha256", "")
                                else None,
                                *(s.file for s in campaign.segments)) if p]
    check_report_path(path, force=force, inputs=inputs, option=option)
    # --pdf: the PDF beside the .docx, checked the same way
    if pdf and path.suffix.lower() != ".pdf":
        check_report_path(path.with_suffix(".pdf"), force=force, inputs=inputs, option=option)
    made = [p for p in (path.parent, *path.parent.parents) if not p.exists()]
    # the files this write makes (the .docx and, with --pdf, the PDF beside it, written one after
    # the other): on a failure the ones that were not there before go again, then their folders
    new = [p for p in dict.fromkeys((path, path.with_suffix(".pdf"))) if not p.exists()]
    try:
        path.parent.mkdir(parents=True, exist_ok=True)
        return writer(path)
    except BaseException as exc:
        for p in new:
            with contextlib.suppress(OSError):
                p.unlink()
        for p in made:
            try:
                p.rmdir()
            except OSError:
                break
        if not isinstance(exc, OSError):
            raise
        from ..base.atomic import write_failure

        reason, hint = write_failure(exc)
        raise MetroError(f"cannot write the report {path}: {reason}; nothing was written",
                         hint=f"{hint} (--out / --report)") from exc

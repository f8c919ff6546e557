"""The lab's imported equipment: one TOML file per piece of equipment, next to the lab profile.

``metro lab equipment import CERT.xml`` (:mod:`metro.core.record.dcc_import`) never edits the
user's ``lab.toml``: it writes ``<profile stem>.equipment/<id>.toml`` beside it (``lab.toml`` →
``lab.equipment/``), together with a copy of the certificate (``<id>.dcc.xml``).  Each file holds
one ``[equipment]`` table, read exactly as a ``[[equipment]]`` table of the profile
(:func:`metro.core.run.manifest.equipment_from_table`), and a ``[dcc]`` table with its provenance
(the DCC's SHA-256, its issuer, its identifier, the result taken, when it was imported).
:func:`metro.core.record.lab.load_lab` reads these files after the profile's own equipment, so a
manifest names imported equipment by id as it names the profile's.

Importing this module is cheap (tomllib); pint is imported only when a file is read.
"""

from __future__ import annotations

import re
import tomllib
from pathlib import Path
from typing import Any, Mapping

from ..base.errors import DataError, MetroError

__all__ = ["FORMAT", "store_folder", "entry_path", "stored_ids", "read_store", "entry_text",
           "write_entry"]

FORMAT = "metro-equipment/1"
_UNSAFE = re.compile(r"[^A-Za-z0-9._+-]+")


def store_folder(lab_path: str | Path) -> Path:
    """The folder of the imported equipment of the profile ``lab_path``: ``<stem>.equipment``
    beside it (``lab.toml`` → ``lab.equipment``)."""
    p = Path(lab_path)
    return p.parent / f"{p.stem}.equipment"


def entry_path(lab_path: str | Path, eid: str) -> Path:
    """The file that holds the imported equipment ``eid`` (characters a file name cannot hold
    replaced by ``_``)."""
    name = _UNSAFE.sub("_", eid).strip("._") or "equipment"
    return store_folder(lab_path) / f"{name}.toml"


def _entries(lab_path: str | Path) -> list[Path]:
    folder = store_folder(lab_path)
    if not folder.is_dir():
        return []
    return sorted(p for p in folder.glob("*.toml") if p.is_file() and not p.name.startswith("."))


def _read_table(path: Path) -> dict[str, Any]:
    src = str(path)
    try:
        doc = tomllib.loads(path.read_text(encoding="utf-8-sig"))
    except OSError as exc:
        raise DataError(src, None,
                        f"cannot read the imported equipment: {exc.strerror or exc}") from exc
    except UnicodeDecodeError as exc:
        raise DataError(src, None, f"not UTF-8 text ({exc})") from exc
    except tomllib.TOMLDecodeError as exc:
        raise DataError(src, None, f"not valid TOML: {exc}") from exc
    if doc.get("format") != FORMAT:
        raise DataError(src, "format", f"expected {FORMAT!r}, got {doc.get('format')!r}",
                        hint=f"{path.parent} holds only what `metro lab equipment import` wrote")
    if not isinstance(doc.get("equipment"), dict):
        raise DataError(src, "equipment", "missing: an imported equipment file has one "
                        "[equipment] table")
    return doc


def stored_ids(lab_path: str | Path) -> dict[str, Path]:
    """The ids of the imported equipment of the profile ``lab_path`` → the file holding each."""
    out: dict[str, Path] = {}
    for p in _entries(lab_path):
        eid = _read_table(p)["equipment"].get("id")
        if isinstance(eid, str):
            out[eid] = p
    return out


def read_store(lab_path: str | Path, seen: set[str] | None = None) -> list:
    """The imported equipment of the profile ``lab_path``
    (:class:`~metro.core.model.campaign.Equipment`, in file-name order); an id the profile or
    another file already gives (``seen``) is a :class:`DataError` naming the file."""
    from ..base.vocabulary import check_characters
    from ..run.manifest import equipment_from_table

    seen = set(seen or ())
    out = []
    for p in _entries(lab_path):
        doc = _read_table(p)
        check_characters(doc, str(p))
        eq = equipment_from_table(doc["equipment"], str(p), "equipment")
        if eq.id in seen:
            raise DataError(str(p), "equipment.id", f"duplicate equipment id {eq.id!r} (the lab "
                            "profile or another imported file gives it too)")
        if eq.calibration is None:
            raise DataError(str(p), "equipment.calibration", "missing")
        seen.add(eq.id)
        out.append(eq)
    return out


def entry_text(equipment: Mapping[str, Any], provenance: Mapping[str, Any]) -> str:
    """The TOML text of one imported equipment file: ``format``, ``[equipment]`` (with its
    ``[equipment.calibration]``) and ``[dcc]`` (provenance)."""
    import tomli_w

    head = ("# Imported by `metro lab equipment import` from a Digital Calibration Certificate.\n"
            "# [dcc] says where it came from; the copy of the certificate is beside this file.\n")
    return head + tomli_w.dumps({"format": FORMAT, "equipment": dict(equipment),
                                 "dcc": dict(provenance)})


def write_entry(lab_path: str | Path, eid: str, text: str, certificate: bytes, *,
                replace: bool = False) -> Path:
    """Write the imported equipment ``eid`` (``text``, from :func:`entry_text`) and the copy of
    its certificate, each atomically; an existing file is replaced only with ``replace`` (an
    earlier import of the same id), never otherwise."""
    from ..base.atomic import atomic_path, write_failure

    target = entry_path(lab_path, eid)
    xml = target.with_name(target.stem + ".dcc.xml")
    if target.exists() and not replace:
        raise MetroError(f"{target} exists; an import never replaces a file",
                         hint="give --replace to replace an earlier import of this id")
    new_xml = not xml.exists()
    try:
        target.parent.mkdir(exist_ok=True)
        with atomic_path(xml) as tmp:
            tmp.write_bytes(certificate)
        with atomic_path(target) as tmp:
            tmp.write_text(text, encoding="utf-8")
            if target.exists() and not replace:  # created meanwhile: still never replaced
                raise MetroError(f"{target} exists; an import never replaces a file")
    except BaseException as exc:
        if new_xml:  # nothing half-imported is left behind
            xml.unlink(missing_ok=True)
        if isinstance(exc, OSError):
            reason, hint = write_failure(exc)
            raise MetroError(f"cannot write {target}: {reason}", hint=hint) from exc
        raise
    return target

"""``python -P tools/catalog.py [--update]``: the message ids the code passes to ``tr(…)`` and
``msg(…)`` (Babel's Python extractor over metro.core and the package of every loaded plugin, found
through the plugin manager), and the quantity names and item titles every registered procedure
declares, that the catalogs lack: metro's ``core/base/locale/zh/LC_MESSAGES/metro.po`` and the
plugins' own (``locale/zh/LC_MESSAGES/*.po`` in a plugin's package); ``--update`` adds the
missing ids to metro's catalog with an empty translation, to be filled in.

Babel's extractor does not look inside f-strings before Python 3.12, so this list can miss some;
``tests/core/documents/test_report.py::test_every_document_string_is_in_the_catalog`` renders every
standard's document in Chinese and fails on any message id the catalog lacks."""

from __future__ import annotations

import importlib
import sys
from pathlib import Path
from typing import Any


def plugin_manager() -> Any:
    """The loaded plugins (with their catalogs added to the translator's)."""
    from metro.core.run.plugin_manager import get_plugin_manager

    return get_plugin_manager()


def scanned_packages(pm: Any) -> dict[str, Path]:
    """{package name: folder} of metro.core and of each loaded plugin's package (a package inside
    one already scanned, such as the built-in plugin's ``metro.core.run``, is left out)."""
    import metro.core

    out = {"metro.core": Path(metro.core.__file__).parent}
    for package in sorted(set(pm.plugin_packages().values())):
        folder = Path(importlib.import_module(package).__file__).parent
        if not any(folder == f or f in folder.parents for f in out.values()):
            out[package] = folder
    return out


def used_messages(pm: Any | None = None) -> dict[str, list[str]]:
    """{message id: [package/file:line, …]} of every ``tr("…")`` and ``msg("…")`` in metro's
    core and the loaded plugins' packages, and of every metric name and item title the registered
    procedures declare (``standard:item``)."""
    from babel.messages.extract import extract_from_dir

    pm = pm or plugin_manager()
    out: dict[str, list[str]] = {}
    for package, folder in scanned_packages(pm).items():
        for fname, lineno, msg, _comments, _ctx in extract_from_dir(
                str(folder), method_map=[("**.py", "python")], keywords={"tr": None, "msg": None}):
            if not isinstance(msg, str):
                continue
            line = (folder / fname).read_text(encoding="utf-8").splitlines()[lineno - 1]
            if f'["{msg}"]' in line or f"['{msg}']" in line:  # tr(row["status"]): a key
                continue
            out.setdefault(msg, []).append(f"{package}/{fname}:{lineno}")
    for msg, where in declared_names(pm).items():
        out.setdefault(msg, []).extend(where)
    return out


def declared_names(pm: Any | None = None) -> dict[str, list[str]]:
    """{text: [standard:item, …]} of the metric names and item titles of every procedure of the
    loaded standards (a document prints them, looked up in the catalog as they are)."""
    pm = pm or plugin_manager()
    out: dict[str, list[str]] = {}
    for std in sorted(pm.register_all().standards):
        for proc in pm.procedures_of(std):
            for text in [proc.title] + [m.name for m in proc.metrics]:
                if text and not hasattr(text, "msgid"):
                    out.setdefault(str(text), []).append(f"{std}:{proc.item}")
    return out


def metro_po() -> Path:
    """metro's own catalog (the one ``--update`` adds to)."""
    from metro.core.base import locale

    return Path(locale.__file__).parent / "zh" / "LC_MESSAGES" / "metro.po"


def missing_messages(pm: Any | None = None) -> dict[str, list[str]]:
    """{message id: [where, …]} of the ids used that neither metro's catalog nor a loaded
    plugin's translates."""
    from metro.core.base.locale import translations

    pm = pm or plugin_manager()  # loading the plugins adds their catalogs
    known = translations("zh")
    return {m: w for m, w in used_messages(pm).items() if not known.get(m)}


def main(argv: list[str]) -> int:
    """List the missing ids; with ``--update`` add them to metro.po (exit 1 when some are
    missing and not added)."""
    from metro.core.base.extras import require

    require("babel", "python -P tools/catalog.py", extra="test")
    from babel.messages.pofile import read_po, write_po

    po = metro_po()
    missing = missing_messages()
    for m, where in missing.items():
        print(f"{m!r}  ({', '.join(where[:2])})")
    if "--update" in argv:
        with po.open("rb") as fh:
            cat = read_po(fh, locale="zh")
        for m in missing:
            if m not in cat:
                cat.add(m, "")
        with po.open("wb") as fh:
            write_po(fh, cat, width=0, sort_output=True, omit_header=False)
    return 1 if missing and "--update" not in argv else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

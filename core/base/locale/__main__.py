"""``python -m metro.core.base.locale [--update]``: the message ids the code passes to ``tr(…)`` and
``msg(…)`` (Babel's Python extractor over metro.core, metro.plugins and metro.instruments), and
the quantity names and item titles every registered procedure declares, that
``zh/LC_MESSAGES/metro.po`` lacks; ``--update`` adds them to the catalog with an empty
translation, to be filled in.

Babel's extractor does not look inside f-strings before Python 3.12, so this list can miss some;
``tests/test_report.py::test_every_document_string_is_in_the_catalog`` renders every standard's
document in Chinese and fails on any message id the catalog lacks."""

from __future__ import annotations

import sys
from pathlib import Path


def used_messages() -> dict[str, list[str]]:
    """{message id: [file:line, …]} of every ``tr("…")`` and ``msg("…")`` in metro's core,
    plugins and instruments, and of every metric name and item title the registered procedures
    declare (``standard:item``)."""
    from babel.messages.extract import extract_from_dir

    import metro.core
    import metro.instruments
    import metro.plugins

    out: dict[str, list[str]] = {}
    for sub, pkg in (("core", metro.core), ("plugins", metro.plugins), ("instruments", metro.instruments)):
        for fname, lineno, msg, _comments, _ctx in extract_from_dir(
                str(Path(pkg.__file__).parent), method_map=[("**.py", "python")],
                keywords={"tr": None, "msg": None}):
            if not isinstance(msg, str):
                continue
            line = (Path(pkg.__file__).parent / fname).read_text(encoding="utf-8").splitlines()[lineno - 1]
            if f'["{msg}"]' in line or f"['{msg}']" in line:  # tr(row["status"]): a key, not a message
                continue
            out.setdefault(msg, []).append(f"{sub}/{fname}:{lineno}")
    for msg, where in declared_names().items():
        out.setdefault(msg, []).extend(where)
    return out


def declared_names() -> dict[str, list[str]]:
    """{text: [standard:item, …]} of the metric names and item titles of every procedure of the
    built-in standards (a document prints them, looked up in the catalog as they are)."""
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager()
    out: dict[str, list[str]] = {}
    for std in ("gbt45570", "jjf2014", "jjf2003", "ogam"):
        for proc in pm.procedures_of(std):
            for text in [proc.title] + [m.name for m in proc.metrics]:
                if text and not hasattr(text, "msgid"):
                    out.setdefault(str(text), []).append(f"{std}:{proc.item}")
    return out


def missing_messages() -> dict[str, list[str]]:
    """{message id: [where, …]} of the ids used that the catalog lacks (or leaves empty)."""
    from babel.messages.pofile import read_po

    po = Path(__file__).parent / "zh" / "LC_MESSAGES" / "metro.po"
    with po.open("rb") as fh:
        cat = read_po(fh, locale="zh")
    return {m: w for m, w in used_messages().items() if m not in cat or not cat[m].string}


def main(argv: list[str]) -> int:
    from metro.core.base.extras import require

    require("babel", "python -m metro.core.base.locale", extra="test")
    from babel.messages.pofile import read_po, write_po

    po = Path(__file__).parent / "zh" / "LC_MESSAGES" / "metro.po"
    with po.open("rb") as fh:
        cat = read_po(fh, locale="zh")
    used = used_messages()
    missing = [m for m in used if m not in cat or not cat[m].string]
    for m in missing:
        print(f"{m!r}  ({', '.join(used[m][:2])})")
    if "--update" in argv:
        for m in missing:
            if m not in cat:
                cat.add(m, "")
        with po.open("wb") as fh:
            write_po(fh, cat, width=0, sort_output=True, omit_header=False)
    return 1 if missing and "--update" not in argv else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

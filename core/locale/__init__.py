"""Message catalogs for documents: every label, heading and fixed sentence a report or
certificate prints goes through :func:`translator`.

Message ids are English; ``zh/LC_MESSAGES/metro.po`` holds the Chinese.  The catalog is read
at run time with :func:`babel.messages.pofile.read_po` (no compile step, so an editable install
or a wheel works as it is); ``python -m metro.core.locale`` lists message ids used in the code
that the catalog lacks.

Languages: ``"zh"``, ``"en"`` and ``"zh+en"`` (both, Chinese first: ``报告编号 Report No.``).
A message may hold ``{name}`` fields, filled by keyword arguments after translation.
"""

from __future__ import annotations

import functools
from importlib import resources
from typing import Any

__all__ = ["LANGS", "DEFAULT_LANG", "Msg", "Translator", "translator", "catalog"]

LANGS = ("zh", "en", "zh+en")
DEFAULT_LANG = "zh+en"


@functools.lru_cache(maxsize=None)
def catalog(locale: str = "zh") -> dict[str, str]:
    """{English message id: translation} from ``<locale>/LC_MESSAGES/metro.po`` (fuzzy and
    empty entries left out)."""
    from babel.messages.pofile import read_po

    path = resources.files(__package__) / locale / "LC_MESSAGES" / "metro.po"
    with path.open("rb") as fh:
        cat = read_po(fh, locale=locale)
    return {m.id: m.string for m in cat if m.id and m.string and not m.fuzzy and isinstance(m.id, str)}


class Msg:
    """A message id to translate inside another message (see :meth:`Translator.msg`)."""

    __slots__ = ("id",)

    def __init__(self, msgid: str):
        self.id = msgid


class Translator:
    """``tr("Report No.")`` → ``报告编号 Report No.`` (zh+en); ``tr.missing`` collects ids the
    catalog lacks (they print in English)."""

    def __init__(self, lang: str = DEFAULT_LANG):
        if lang not in LANGS:
            from ..errors import MetroError

            raise MetroError(f"unknown document language {lang!r}", hint=f"use one of {', '.join(LANGS)}")
        self.lang = lang
        self.missing: set[str] = set()
        self._zh = catalog("zh") if lang != "en" else {}

    def zh(self, msgid: str) -> str:
        text = self._zh.get(msgid)
        if text is None:
            self.missing.add(msgid)
            return msgid
        return text

    def __call__(self, msgid: str, /, **fields: Any) -> str:
        """The message in the document's language(s); ``fields`` fill its ``{name}`` places.
        A field given as :meth:`msg` is itself translated: in zh+en, the Chinese sentence gets
        the Chinese field and the English sentence the English one."""
        zh_fields = {k: self.zh(v.id) if isinstance(v, Msg) else v for k, v in fields.items()}
        en_fields = {k: v.id if isinstance(v, Msg) else v for k, v in fields.items()}
        if self.lang == "en":
            return msgid.format(**en_fields) if fields else msgid
        zh = self.zh(msgid)
        zh_text = zh.format(**zh_fields) if fields else zh
        if self.lang == "zh":
            return zh_text
        en_text = msgid.format(**en_fields) if fields else msgid
        return en_text if zh_text == en_text else f"{zh_text} {en_text}"

    @staticmethod
    def msg(msgid: str) -> "Msg":
        """A message to be translated where it is placed (a field of another message)."""
        return Msg(msgid)

    def pick(self, zh: str, en: str) -> str:
        """Text that comes in both languages from data (a standard's item names): the one(s) asked for."""
        if self.lang == "en":
            return en
        if self.lang == "zh":
            return zh
        return f"{zh} {en}" if zh and en and zh != en else (zh or en)


def translator(lang: str | None = None) -> Translator:
    return Translator(lang or DEFAULT_LANG)

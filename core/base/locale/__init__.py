"""Message catalogs for documents: every label, heading and fixed sentence a report or
certificate prints goes through :func:`translator`.

Message ids are English; ``zh/LC_MESSAGES/metro.po`` holds the Chinese.  The catalog is read
at run time by :func:`read_catalog` (no compile step, so an editable install or a wheel works as
it is); ``python -P tools/catalog.py`` lists message ids used in the code that the catalogs lack.

A plugin ships its own catalog in its package: ``locale/zh/LC_MESSAGES/<name>.po`` next to its
``__init__.py``.  The plugin manager finds it when the plugins are loaded and adds it with
:func:`add_catalogs`; a document's :class:`Translator` reads metro's catalog, then each plugin's
for the message ids metro's lacks (:func:`translations`).

Languages: ``"zh"``, ``"en"`` and ``"zh+en"`` (both, Chinese first: ``报告编号 Report No.``).
A message may hold ``{name}`` fields, filled by keyword arguments after translation.

Text made far from the document (a result's note, a not-reportable reason, a warning, a budget
component, a conformity reason, why a method was chosen) is a :class:`Text`, made by
:func:`msg`: it *is* the English string (the terminal, ``--json``, comparisons and tests see
plain English), and it keeps its message id and fields, so a document's :class:`Translator`
writes it in the document's language (``tr.text(value)``, or ``tr(value)``).

A field made by :func:`hint` is for the terminal only: advice about the software (a command, an
option, a manifest key) that the terminal and ``--json`` print and a document leaves out — a
certificate speaks to its reader, not to metro's user.
"""

from __future__ import annotations

import functools
import re
from collections.abc import Callable, Iterable
from importlib import resources
from typing import Any

__all__ = [
    "DEFAULT_LANG",
    "LANGS",
    "Hint",
    "Index",
    "Msg",
    "Text",
    "Translator",
    "add_catalogs",
    "catalog",
    "catalog_folders",
    "hint",
    "index",
    "join",
    "msg",
    "read_catalog",
    "translations",
    "translator",
]

LANGS = ("zh", "en", "zh+en")
_HAN = re.compile(r"[\u3400-\u9fff\uf900-\ufaff]")
DEFAULT_LANG = "zh+en"


@functools.cache
def catalog(locale: str = "zh") -> dict[str, str]:
    """{English message id: translation} from ``<locale>/LC_MESSAGES/metro.po`` (fuzzy and
    empty entries left out)."""
    path = resources.files(__package__) / locale / "LC_MESSAGES" / "metro.po"
    return read_catalog(path.read_text(encoding="utf-8"))


#: the ``locale`` folders of the plugins' own catalogs, in the order they were added
_FOLDERS: list[Any] = []


def add_catalogs(folder: Any) -> None:
    """Add a plugin's message catalogs: ``folder`` (a path or :mod:`importlib.resources`
    traversable) holds ``<locale>/LC_MESSAGES/*.po``.  Adding a folder twice changes nothing."""
    if str(folder) not in {str(f) for f in _FOLDERS}:
        _FOLDERS.append(folder)


def catalog_folders() -> list[Any]:
    """The plugins' ``locale`` folders added so far (:func:`add_catalogs`), in order."""
    return list(_FOLDERS)


def translations(locale: str = "zh") -> dict[str, str]:
    """{message id: translation} of metro's catalog and every plugin's (:func:`add_catalogs`):
    metro's translation of an id is kept; a plugin's adds the ids metro's catalog lacks (the
    first plugin catalog to give an id, in the order added, and ``*.po`` files by name).  The
    mapping is shared by every translator: read it, never change it."""
    return _merged(locale, tuple(str(f) for f in _FOLDERS))


@functools.cache
def _merged(locale: str, folders: tuple[str, ...]) -> dict[str, str]:
    out = dict(catalog(locale))
    by_name = {str(f): f for f in _FOLDERS}
    for name in folders:
        lc = by_name[name] / locale / "LC_MESSAGES"
        if not lc.is_dir():
            continue
        for po in sorted((p for p in lc.iterdir() if p.name.endswith(".po")), key=lambda p: p.name):
            for msgid, text in read_catalog(po.read_text(encoding="utf-8")).items():
                out.setdefault(msgid, text)
    return out


_PO_ESCAPES = {"n": "\n", "t": "\t", "r": "\r", '"': '"', "\\": "\\"}


def _po_string(line: str) -> str:
    """The text of one quoted .po string (``"..."``), escapes resolved."""
    body = line.strip()[1:-1]
    return re.sub(r"\\(.)", lambda m: _PO_ESCAPES.get(m.group(1), m.group(1)), body)


def read_catalog(text: str) -> dict[str, str]:
    """{msgid: msgstr} of a gettext .po file's text: what Babel's ``read_po`` gives for metro.po
    (the header, fuzzy, empty, plural, context-bound and obsolete entries left out), without
    Babel and its 36 MB of locale data in the core install (the catalog tool,
    ``tools/catalog.py``, still uses Babel)."""
    out: dict[str, str] = {}
    entry: dict[str, str] = {}
    flags = ""
    key = None

    def close() -> None:
        if entry.get("msgid") and entry.get("msgstr") and "fuzzy" not in flags and len(entry) == 2:
            out[entry["msgid"]] = entry["msgstr"]

    for line in text.splitlines() + [""]:
        line = line.strip()
        if line.startswith('"') and key is not None:
            entry[key] += _po_string(line)
            continue
        if not line or (line.startswith("#") and entry):  # an entry ends
            if entry:
                close()
            entry, flags, key = {}, "", None
        if line.startswith("#,"):
            flags += line[2:]
        elif line and not line.startswith("#"):
            key, _, rest = line.partition(" ")
            if key in ("msgctxt", "msgid") and any(k.startswith("msgstr") for k in entry):
                close()  # the next entry, with no blank line before it
                entry, flags = {}, ""
            entry[key] = _po_string(rest)
    return out


class Msg:
    """A message id to translate inside another message (see :meth:`Translator.msg`)."""

    __slots__ = ("id",)

    def __init__(self, msgid: str):
        self.id = msgid


class Index(str):
    """A message field that is an index (an axis letter, ``K_g{r}{c}``): where several results'
    notes differ only in such fields, a document states the sentence once in index form (``K_gij``;
    :func:`metro.core.documents.notes.group_notes`). Everywhere else it is the plain string."""

    __slots__ = ()

    def __reduce__(self):
        return (Index, (str(self),))


def index(value: Any) -> Index:
    """``msg("… into g_{r}{c}", r=index("x"), c=index("y"))``: the fields are indices."""
    return Index(str(value))


class Hint(str):
    """A message field for the terminal only (see :func:`hint`): its text in English wherever the
    message is a plain string (the terminal, ``--json``), nothing in a document."""

    __slots__ = ()

    def __reduce__(self):
        return (Hint, (str(self),))


def hint(value: Any) -> Hint:
    """``msg("… may be higher — test beyond it{hint}", hint=hint(" (plan with -o max_rate=…)"))``:
    advice about the software that the terminal prints and a document leaves out (the catalog's
    translation keeps the ``{hint}`` place, where a document puts nothing)."""
    return Hint(str(value))


class Text(str):
    """English text that remembers how it was made, to be written again in another language.

    A message: ``msgid`` (English, with ``{name}`` places, looked up in the catalog) and
    ``fields`` (values; a field that is itself a :class:`Text` is translated too).  A join:
    ``parts`` (each a Text or plain text) joined by ``sep``.  The string value is the English
    text, so every use of it as a ``str`` is unchanged; it pickles (dask) and goes into JSON as
    that English text (:meth:`encode` / :meth:`decode` keep the message, e.g. in the register).
    """

    msgid: str | None
    fields: dict[str, Any]
    sep: str
    parts: tuple

    def __new__(cls, msgid: str | None = None, fields: dict[str, Any] | None = None, *,
                sep: str = "", parts: tuple = (), english: str | None = None):
        fields = dict(fields or {})
        if english is not None:  # decoded from JSON, where a field may have lost its type
            pass
        elif msgid is None:
            english = sep.join(str(p) for p in parts)
        else:
            english = msgid.format(**fields) if fields else msgid
        self = super().__new__(cls, english)
        self.msgid, self.fields, self.sep, self.parts = msgid, fields, sep, tuple(parts)
        return self

    def __reduce__(self):
        return (_rebuild_text, (self.msgid, self.fields, self.sep, self.parts, str(self)))

    def map(self, fn: Callable[[str], str]) -> Text:
        """The same message with ``fn`` applied to every plain-text field and part (recursively)."""
        def one(v: Any) -> Any:
            if isinstance(v, Text):
                return v.map(fn)
            if isinstance(v, Index):
                return Index(fn(v))
            if isinstance(v, Hint):
                return Hint(fn(v))
            if isinstance(v, str):
                return fn(v)
            return v

        return Text(self.msgid, {k: one(v) for k, v in self.fields.items()}, sep=self.sep,
                    parts=tuple(one(p) for p in self.parts))

    def encode(self) -> dict[str, Any]:
        """JSON for the register: ``{"msgid", "fields"}`` or ``{"sep", "parts"}``; fields that are
        not JSON values (quantities, numpy numbers) as their English text."""
        import numbers

        def enc(v: Any) -> Any:
            if isinstance(v, Text):
                return {"text": v.encode()}
            if isinstance(v, Index):
                return {"index": str(v)}
            if isinstance(v, Hint):
                return {"hint": str(v)}
            if isinstance(v, str) or v is None or isinstance(v, bool):
                return str(v) if isinstance(v, str) else v
            if isinstance(v, numbers.Integral):
                return int(v)
            if isinstance(v, numbers.Real):  # numpy numbers too: a {x:.3g} place keeps its number
                return float(v)
            return str(v)

        if self.msgid is None:
            return {"sep": self.sep, "parts": [enc(p) for p in self.parts], "en": str(self)}
        return {"msgid": self.msgid, "fields": {k: enc(v) for k, v in self.fields.items()},
                "en": str(self)}

    @staticmethod
    def decode(doc: dict[str, Any]) -> Text:
        def dec(v: Any) -> Any:
            if isinstance(v, dict) and set(v) == {"index"}:
                return Index(v["index"])
            if isinstance(v, dict) and set(v) == {"hint"}:
                return Hint(v["hint"])
            return Text.decode(v["text"]) if isinstance(v, dict) and set(v) == {"text"} else v

        if "parts" in doc:
            return Text(None, sep=doc["sep"], parts=tuple(dec(p) for p in doc["parts"]),
                        english=doc.get("en"))
        return Text(doc["msgid"], {k: dec(v) for k, v in doc["fields"].items()},
                    english=doc.get("en"))


def _rebuild_text(msgid, fields, sep, parts, english=None) -> Text:
    return Text(msgid, fields, sep=sep, parts=parts, english=english)


def msg(msgid: str, /, **fields: Any) -> Text:
    """A message made far from the document: ``msg("χ²/ν = {chi2:.1f} exceeds {limit}", chi2=…,
    limit=…)`` is the English text, and a document writes it in its language.  ``msgid`` must be
    a literal (``tools/catalog.py`` finds it in the code and checks the catalogs)."""
    return Text(msgid, fields)


def join(sep: str, parts: Iterable[Any]) -> Text:
    """``sep.join(parts)`` keeping each part's message: a document translates each part (a
    :class:`Text`, or a fixed name the catalog holds)."""
    return Text(None, sep=sep, parts=tuple(parts))


class Translator:
    """``tr("Report No.")`` → ``报告编号 Report No.`` (zh+en); ``tr.missing`` collects ids the
    catalog lacks (they print in English)."""

    def __init__(self, lang: str = DEFAULT_LANG):
        if lang not in LANGS:
            from ..errors import MetroError

            raise MetroError(f"unknown document language {lang!r}",
                             hint=f"use one of {', '.join(LANGS)}")
        self.lang = lang
        self.missing: set[str] = set()
        self._zh = translations("zh") if lang != "en" else {}

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
        if isinstance(msgid, Text):
            return self.text(msgid)
        zh_fields = {k: self._field(v, "zh") for k, v in fields.items()}
        en_fields = {k: self._field(v, "en") for k, v in fields.items()}
        if self.lang == "en":
            return msgid.format(**en_fields) if fields else msgid
        zh = self.zh(msgid)
        zh_text = zh.format(**zh_fields) if fields else zh
        if self.lang == "zh":
            return zh_text
        en_text = msgid.format(**en_fields) if fields else msgid
        return en_text if zh_text == en_text else f"{zh_text} {en_text}"

    def _field(self, v: Any, lang: str) -> Any:
        if isinstance(v, Msg):
            return self.zh(v.id) if lang == "zh" else v.id
        if isinstance(v, str):  # a Text, or a fixed name the catalog may hold
            return self.render(v, lang)
        return v

    def render(self, value: Any, lang: str) -> str:
        """``value`` in one language (``zh`` or ``en``): a :class:`Text` looked up in the catalog
        and formatted with its fields (each translated in turn); plain text is looked up as a
        whole (a fixed name the catalog holds) and else kept as it is (data: names, files)."""
        if isinstance(value, Hint):  # for the terminal only
            return ""
        if isinstance(value, Text):
            if value.msgid is None:
                return value.sep.join(self.render(p, lang) for p in value.parts)
            fields = {k: self._field(v, lang) for k, v in value.fields.items()}
            pattern = value.msgid if lang == "en" else self.zh(value.msgid)
            try:
                return pattern.format(**fields) if value.fields else pattern
            # wrong places, a field that lost its type
            except (KeyError, IndexError, ValueError, TypeError):
                if lang != "en":
                    self.missing.add(value.msgid)
                return str(value)
        if value is None:
            return ""
        text = str(value)
        if lang == "zh" and text:
            return self._zh.get(text, text)
        return text

    def text(self, value: Any) -> str:
        """``value`` (a :class:`Text` or plain text) in the document's language(s): in zh+en,
        the Chinese then the English (once, when they are the same); a join in zh+en puts each
        part's two languages together."""
        if self.lang != "zh+en":
            return self.render(value, self.lang)
        if isinstance(value, Text) and value.msgid is None:
            return value.sep.join(self.text(p) for p in value.parts)
        zh, en = self.render(value, "zh"), self.render(value, "en")
        # a Chinese rendering with no Chinese in it (a pattern whose fields are English data, e.g.
        # "{source}（{note}）") is the English sentence again with other punctuation: printed once
        return en if zh == en or not _HAN.search(zh) else f"{zh} {en}"

    @staticmethod
    def msg(msgid: str) -> Msg:
        """A message to be translated where it is placed (a field of another message)."""
        return Msg(msgid)

    def pick(self, zh: str, en: str) -> str:
        """Text that comes in both languages from data (a standard's item names): the one(s) asked
        for."""
        if self.lang == "en":
            return en
        if self.lang == "zh":
            return zh
        return f"{zh} {en}" if zh and en and zh != en else (zh or en)


def translator(lang: str | None = None) -> Translator:
    return Translator(lang or DEFAULT_LANG)

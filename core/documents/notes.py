"""Notes and warnings stated once: the text, then the items and results it applies to.

A certificate's or report's notes come from every result (its note) and every item (its
warnings).  Many repeat: the same drift paragraph from each of three items, the same "corrected
for the drift by …" on each result of one gyro, one earth-rate sentence on nine results that
differ only in their indices.  :func:`group_notes` states each text that occurs more than once
once, labelled with where it applies (``K_gxx, K_gyy (7.2.1): …``, ``7.2.1, 7.2.2, 7.2.3: …``);
the texts that occur once stay on their item's line as before (``7.2.3: K_gxy: …; K_gxz: …``);
lines in the order their texts first appear; nothing is dropped.

* A note made of parts (a :func:`metro.core.base.locale.join` with ``"; "``) is taken apart: a part
  several results share is a line of its own, the parts only one result has stay together.
* A message whose fields are marked :func:`metro.core.base.locale.index` (an axis letter in
  ``K_g{r}{c}``) and that differs between results only in those fields is stated once in index
  form (``K_gij``, ``g_ij``: the varying fields as i, j, k, …), the results it applies to named.

Pure data: no document, no translator (``key`` gives the text a reader sees, e.g. ``tr.text``).
"""

from __future__ import annotations

import string
from typing import Any, Callable, Hashable, Iterable, Sequence

from ..base.locale import Index, Text, index, join  # noqa: F401  (Index, index: re-exported)

__all__ = ["Index", "index", "group_notes", "where_label", "parts_of", "INDEX_LETTERS"]

#: the letters a varying index field takes when a message is stated once for several results
INDEX_LETTERS = "ijklmn"
_HOLE = "\ufffc"  # stands for an index field in a message's key (never printed)


def parts_of(text: Any, sep: str = "; ") -> list[Any]:
    """The parts of a note joined with ``sep`` (nested joins flattened), empty parts left out;
    any other text as one part."""
    if isinstance(text, Text) and text.msgid is None and text.sep == sep:
        return [q for p in text.parts for q in parts_of(p, sep)]
    return [text] if str(text) != "" else []


def _field_order(msgid: str) -> list[str]:
    return list(dict.fromkeys(f for _, f, _, _ in string.Formatter().parse(msgid) if f))


def _index_fields(text: Any) -> tuple[str, ...]:
    if isinstance(text, Text) and text.msgid is not None:
        return tuple(k for k in _field_order(text.msgid) if isinstance(text.fields.get(k), Index))
    return ()


def _with(text: Text, values: dict[str, str]) -> Text:
    return Text(text.msgid, {**text.fields, **values})


def where_label(pairs: Sequence[tuple[str, str]]) -> str:
    """Where a text applies, from (item, symbol) pairs (symbol ``""``: the item itself, e.g. its
    warning): the symbols of each set of items, then those items in parentheses; an item's own
    texts as the item alone.

    >>> where_label([("7.2.1", "K_gxx"), ("7.2.3", "K_gxx"), ("7.2.3", "K_gxy"),
    ...              ("7.2.3", "K_gxz")])
    'K_gxx (7.2.1, 7.2.3); K_gxy, K_gxz (7.2.3)'
    >>> where_label([("7.2.1", ""), ("7.2.2", ""), ("7.2.3", "")])
    '7.2.1, 7.2.2, 7.2.3'
    >>> where_label([("", "g_xx"), ("", "g_xy")])  # results of no named item (one matrix's cells)
    'g_xx, g_xy'
    """
    items_of: dict[str, list[str]] = {}
    for item, sym in pairs:
        items_of.setdefault(sym, [])
        if item not in items_of[sym]:
            items_of[sym].append(item)
    by_items: dict[tuple[str, ...], list[str]] = {}
    for sym, items in items_of.items():
        by_items.setdefault(tuple(items), []).append(sym)
    out = []
    for items, syms in by_items.items():
        where = ", ".join(items)
        if "" in syms:
            out.append(where)
        named = [s for s in syms if s]
        if named:
            out.append(f"{', '.join(named)} ({where})" if where else ", ".join(named))
    return "; ".join(out)


def group_notes(
    entries: Iterable[tuple[str, str, Any]], key: Callable[[Any], Hashable] = str, sep: str = "; "
) -> list[tuple[str, Any]]:
    """``[(label, text)]``: each note or warning text once, labelled with where it applies.

    :param entries: ``(item, symbol, text)`` in document order: a result's note with its
        symbol, an item's warning with ``""``.
    :param key: what makes two texts the same (``str``: the English; a document passes its
        translator's ``tr.text``, the text as printed).
    :returns: lines in the order their texts first appear.  A text (or a part of a ``sep``
        join) that occurs more than once is one line labelled by :func:`where_label` (in index
        form when its occurrences differ only in :class:`Index` fields).  The texts that occur
        once stay together per item, as the item's line: label the item, text
        ``symbol: note; symbol: note; warning`` (a result's parts joined again, in their order).
    """
    entries = [(str(item), str(sym or ""), text) for item, sym, text in entries]

    def gkey(part: Any) -> Hashable:
        fields = _index_fields(part)
        if not fields:
            return ("=", key(part))
        return ("~", part.msgid, key(_with(part, {f: _HOLE for f in fields})))

    split = [
        (item, sym, [(gkey(p), p) for p in parts_of(text, sep)]) for item, sym, text in entries
    ]
    where: dict[Hashable, list[tuple[str, str]]] = {}
    members: dict[Hashable, list[Any]] = {}
    for item, sym, parts in split:
        for k, p in parts:
            members.setdefault(k, []).append(p)
            if (item, sym) not in where.setdefault(k, []):
                where[k].append((item, sym))
    shared = {k for k, m in members.items() if len(m) > 1}

    lines: list[list] = []  # [label, text] or, for an item's own line, [item, [(symbol, text), …]]
    placed: set[Hashable] = set()
    own_line: dict[str, list] = {}
    for item, sym, parts in split:
        mine = [p for k, p in parts if k not in shared]
        if mine:
            if item not in own_line:
                own_line[item] = [item, []]
                lines.append(own_line[item])
            own_line[item][1].append((sym, mine[0] if len(mine) == 1 else join(sep, mine)))
        for k, _ in parts:
            if k in shared and k not in placed:
                placed.add(k)
                lines.append([where_label(where[k]), _stated_once(members[k], key)])
    out = []
    for label, text in lines:
        if isinstance(text, list):
            text = join(sep, [join(": ", [s, t]) if s else t for s, t in text])
            text = text.parts[0] if len(text.parts) == 1 else text
        out.append((label, text))
    return out


def _stated_once(parts: list[Any], key: Callable[[Any], Hashable]) -> Any:
    """One text for parts that read the same, or that differ only in index fields (then in
    index form: each varying index field as i, j, …; a field the same in all keeps its value)."""
    first = parts[0]
    if len({key(p) for p in parts}) == 1:
        return first
    varying = [f for f in _index_fields(first) if len({str(p.fields.get(f)) for p in parts}) > 1]
    return _with(first, {f: INDEX_LETTERS[n % len(INDEX_LETTERS)] for n, f in enumerate(varying)})

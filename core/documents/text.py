"""Text as metro's documents set it: the page's geometry and type sizes, symbols with real
subscripts (``K_l``), no-break spaces where a line must not break, one notation for small numbers,
width estimates for table columns, and a result's name and symbol as a document prints them.

Pure text: :mod:`metro.core.documents.builder` writes what these functions return.
"""

from __future__ import annotations

import functools
import re
import unicodedata
from typing import Any, Sequence

from ..base.formatting import pretty_powers

__all__ = [
    "PAGE_W_MM",
    "PAGE_H_MM",
    "MARGIN_MM",
    "TEXT_WIDTH_MM",
    "BODY_PT",
    "TABLE_PT",
    "MIN_TABLE_PT",
    "CELL_MARGIN_MM",
    "HEAD_FILL",
    "LABEL_FILL",
    "LATIN_FONT",
    "CJK_FONT",
    "NBSP",
    "FIGURE_WIDTH_MM",
    "subscript_runs",
    "one_notation",
    "unit_may_wrap",
    "glue",
    "text_mm",
    "two_lines",
    "column_widths",
    "plain_symbol",
    "display_symbol",
    "quantity_name",
]

PAGE_W_MM, PAGE_H_MM, MARGIN_MM = 210.0, 297.0, 20.0
TEXT_WIDTH_MM = PAGE_W_MM - 2 * MARGIN_MM
BODY_PT = 9.5
TABLE_PT = 8.5
MIN_TABLE_PT = 6.5
CELL_MARGIN_MM = 1.2
HEAD_FILL = "D9E2EC"
LABEL_FILL = "EEF2F6"
LATIN_FONT = "Times New Roman"
CJK_FONT = "SimSun"
NBSP = "\u00a0"
FIGURE_WIDTH_MM = 150.0

# ----------------------------------------------------------------------------------------
# Text: subscripts, no-break spaces, width estimates
# ----------------------------------------------------------------------------------------

# a symbol with a subscript: one or two letters (Greek allowed, Δ prefix allowed), or max/min with a
# one-character subscript, "_",
# then 1–4 letters/digits or a braced group (s_{upper}); not inside a longer word or a file name (a
# Chinese
# character or a subscript digit before it is no word: 计数N_0, K₀₀ΔT_i).
_SUB = re.compile(
    r"(?<![A-Za-z0-9_./\\-])((?:max|min)(?=_[A-Za-z0-9](?!\w))|Δ?[A-Za-zΑ-Ωα-ω][A-Za-zΑ-Ωα-ω]?)_(?:\{([^{}]{1,8})\}|([A-Za-z0-9]{1,4}))(?![\w.\\/-]*\.\w{2,4}\b)(?!\w)"
)


def subscript_runs(text: str) -> list[tuple[str, bool]]:
    """``text`` cut into (piece, is_subscript): ``"K_l = 3"`` → [("K", False), ("l", True), (" = 3",
    False)].

    >>> subscript_runs("B_s and ΔB_V13; rate_table, t_startup, run_1.csv")
    ... # doctest: +NORMALIZE_WHITESPACE
    [('B', False), ('s', True), (' and ΔB', False), ('V13', True),
     ('; rate_table, t_startup, run_1.csv', False)]
    """
    out: list[tuple[str, bool]] = []
    pos = 0
    for m in _SUB.finditer(text):
        out.append((text[pos : m.start()] + m.group(1), False))
        out.append((m.group(2) or m.group(3), True))
        pos = m.end()
    out.append((text[pos:], False))
    merged: list[tuple[str, bool]] = []
    for piece, sub in out:
        if not piece:
            continue
        if merged and merged[-1][1] == sub:
            merged[-1] = (merged[-1][0] + piece, sub)
        else:
            merged.append((piece, sub))
    return merged


_NUM_UNIT = re.compile(r"(?<=[\d⁰¹²³⁴⁵⁶⁷⁸⁹%″′°∞]) (?=[^\s\d(=,;]{1,12}(?:[\s,;)]|$))")
_EQ = re.compile(
    r"(?<=\b[A-Za-zνΔ]) = (?=[-−±\d(])|(?<=\b[A-Za-zνΔ]{2}) = (?=[-−±\d(])|(?<=[uUkK]) = "
)


_SMALL = re.compile(r"(?<![\w.\-/])(-?)0\.(000+)(\d+)(?![\w.])")
_SUP = str.maketrans("0123456789-", "⁰¹²³⁴⁵⁶⁷⁸⁹⁻")


def one_notation(text: str) -> str:
    """Plain decimals below 0.001 as ×10ⁿ, so a value and its U print in one notation
    (``0.0006021`` next to ``6.6×10⁻⁶`` → ``6.021×10⁻⁴``); every digit is kept.

    >>> one_notation("0.0006021 and 6.6×10⁻⁶; 0.0012; run_0.0001.csv")
    '6.021×10⁻⁴ and 6.6×10⁻⁶; 0.0012; run_0.0001.csv'
    """

    def sub(m: re.Match) -> str:
        digits = m.group(3)
        exp = -(len(m.group(2)) + 1)
        mant = digits[0] + (f".{digits[1:]}" if len(digits) > 1 else "")
        return f"{m.group(1)}{mant}×10{str(exp).translate(_SUP)}"

    return _SMALL.sub(sub, text)


#: a number and its unit as :func:`glue` joins them (a no-break space between)
_NUM_NBSP_UNIT = re.compile(r"^([^\s\u00a0]*[\d⁰¹²³⁴⁵⁶⁷⁸⁹])\u00a0([^\s\d=]\S*)$")


def unit_may_wrap(cell: str) -> str:
    """``4.946×10⁻⁸ °/°C/h`` with an ordinary space before the unit (it may go under the number)
    and word joiners inside the unit (LibreOffice would break it at a slash)."""
    m = _NUM_NBSP_UNIT.match(cell)
    if m is None:
        return cell
    return f"{m.group(1)} " + "\u2060".join(m.group(2))


_NEG = re.compile(r"(?<![\w.\-/\u2060])-(?=\d)")


@functools.lru_cache(maxsize=8192)  # a report glues ~9 000 cell texts, most of them more than once
def glue(text: str) -> str:
    """No-break spaces where a line must not break: between a number and its unit
    (``1.2 ppm``) and around ``=`` in ``k = 2`` / ``U = 0.4``.

    >>> glue("U = 1.2 ppm (k = 2)") == "U\u00a0=\u00a01.2\u00a0ppm (k\u00a0=\u00a02)"
    True
    """
    text = _NUM_UNIT.sub(NBSP, _EQ.sub(f"{NBSP}={NBSP}", one_notation(pretty_powers(text))))
    # a minus sign written as a hyphen: LibreOffice breaks after it ("alpha0 = -" / "2.3…"),
    # a word joiner (U+2060, invisible) keeps it with its number
    return _NEG.sub("-\u2060", text)


@functools.lru_cache(maxsize=2)
def _metrics(bold: bool) -> Any:
    """DejaVu Serif (matplotlib ships it; LibreOffice draws Times New Roman with it where Times is
    not installed, and it is wider than Times, so widths measured with it fit either)."""
    from pathlib import Path

    import matplotlib
    from matplotlib.ft2font import FT2Font

    name = "DejaVuSerif-Bold.ttf" if bold else "DejaVuSerif.ttf"
    font = FT2Font(str(Path(matplotlib.get_data_path()) / "fonts" / "ttf" / name))
    font.set_size(100, 72)
    return font


@functools.lru_cache(maxsize=4096)
def _char_em(c: str, bold: bool = False) -> float:
    """Advance of one character in em: DejaVu Serif's, 1 em for CJK, 0.6 em for a glyph it lacks."""
    if unicodedata.east_asian_width(c) in ("W", "F"):
        return 1.0
    font = _metrics(bold)
    if not font.get_char_index(ord(c)):
        return 0.6
    glyph = font.load_char(ord(c))
    return glyph.linearHoriAdvance / 65536 / 100


def text_mm(text: str, pt: float, bold: bool = False) -> float:
    """Width of ``text`` set at ``pt`` points, in millimetres (DejaVu Serif metrics)."""
    return _text_em(text, bold) * pt * 25.4 / 72


@functools.lru_cache(maxsize=16384)
def _text_em(text: str, bold: bool) -> float:
    """Width of ``text`` in em (a table's column widths are measured again at each smaller size)."""
    return sum(_char_em(c, bold) for c in text)


#: a run of Chinese up to this many characters (a term: 正态, 类型，分布, 标度因数) is kept on one
#: line; a longer run may break, but a column holding one is at least CJK_CHUNK characters wide
CJK_WORD, CJK_CHUNK = 6, 4


def _words(text: str) -> list[str]:
    """The pieces a line may not break inside (for column widths): split at ordinary spaces, line
    breaks, before a full-width ``（`` and after ``）`` (a no-break space joins).  Chinese may
    break between any two characters, but a column one character wide prints a term one
    character per line (类/型/，/分/布): a run of Chinese up to :data:`CJK_WORD` characters
    counts as one piece, a longer run splits after full-width punctuation, and a longer
    stretch still in pieces of :data:`CJK_CHUNK`.

    >>> _words("chamber)（∂B/∂T）and 温箱 x B, 正态 类型，分布 "
    ...        "标度因数非线性度 低温贮存：施加的贮存温度")  # doctest: +NORMALIZE_WHITESPACE
    ['chamber)', '（∂B/∂T）', 'and', '温箱', 'x', 'B,', '正态', '类型，分布', '标度因数',
     '非线性度', '低温贮存：', '施加的贮', '存温度']
    """
    out: list[str] = []

    def run(r: str) -> None:
        if len(r) <= CJK_WORD:
            out.append(r)
            return
        for seg in re.findall(r"[^，。；：、！？]*[，。；：、！？]*", r):
            if len(seg) <= CJK_WORD:
                out.append(seg) if seg else None
            else:
                out.extend(seg[i : i + CJK_CHUNK] for i in range(0, len(seg), CJK_CHUNK))

    for part in re.split(r"[ \n\t]+", text):
        buf, cjk = "", ""
        for c in part:
            if c == "（":  # a line may break before a full-width opening parenthesis ...
                if buf:
                    out.append(buf)
                if cjk:
                    run(cjk)
                buf, cjk = c, ""
            elif c == "）":  # ... and after a closing one
                if cjk:
                    run(cjk + c)
                    cjk = ""
                else:
                    out.append(buf + c)
                    buf = ""
            elif unicodedata.east_asian_width(c) in ("W", "F"):
                if buf and buf != "（":
                    out.append(buf)
                    buf = ""
                cjk += buf + c
                buf = ""
            else:
                if cjk:
                    run(cjk)
                    cjk = ""
                buf += c
        if cjk:
            run(cjk)
        if buf:
            out.append(buf)
    return out


@functools.lru_cache(maxsize=8192)
def _words_of(text: str) -> tuple[str, ...]:
    """:func:`_words` of a cell, kept (a column's cells are split again at each smaller size)."""
    return tuple(_words(text))


_ZH_EN = re.compile(r"(?<=[\u3400-\u9fff）])[ \u00a0](?=[A-Za-zΑ-Ωα-ωνΔ(])")


def two_lines(header: str) -> str:
    """A bilingual header cell (``扩展不确定度 Expanded uncertainty``) as two lines, Chinese above
    English, so a narrow column does not wrap it mid-phrase.

    >>> two_lines("扩展不确定度 Expanded uncertainty").split("\\n"), two_lines("Source")
    (['扩展不确定度', 'Expanded uncertainty'], 'Source')
    """
    return _ZH_EN.sub("\n", header, count=1)


def column_widths(
    columns: Sequence[Sequence[str]],
    total_mm: float,
    pt: float,
    bold_first: bool = True,
    bold_column: bool = False,
    prefer: int | None = None,
    prefer_share: float = 0.6,
    squeeze: bool = False,
) -> list[float] | None:
    """Column widths (mm) summing to ``total_mm`` for cells ``columns[j][i]`` at ``pt`` points,
    or None when the longest unbreakable words alone do not fit.

    Each column gets at least its longest word plus the cell margins; what is left is shared in
    proportion to how much each column's longest cell still lacks, so short columns stay narrow
    and text columns take the room."""
    pad = 2 * CELL_MARGIN_MM + 0.8
    mins, wants = [], []
    for j, col in enumerate(columns):
        bold = [bold_first and i == 0 or bold_column and j == 0 for i in range(len(col))]
        mins.append(
            max(
                (text_mm(w, pt, b) for cell, b in zip(col, bold) for w in _words_of(cell)),
                default=0.0,
            )
            * 1.03
            + pad
        )
        wants.append(
            max((text_mm(cell, pt, b) for cell, b in zip(col, bold)), default=0.0) * 1.03 + pad
        )
    if sum(mins) > total_mm:
        # the longest words alone do not fit: None, or (squeeze) widths in proportion to them,
        # so the columns whose words are longest stay widest (a word may then break)
        return [m * total_mm / sum(mins) for m in mins] if squeeze else None
    wants = [max(w, m) for w, m in zip(wants, mins)]
    if sum(wants) <= total_mm:
        spare = total_mm - sum(wants)
        return [w + spare * w / sum(wants) for w in wants]
    room = total_mm - sum(mins)
    lack = [w - m for w, m in zip(wants, mins)]
    # water-filling: columns that lack little get all they lack, the others share the rest;
    # a preferred column (the text of a table, e.g. a budget's sources) first takes up to
    # ``prefer_share`` (60 %) of the room
    widths = list(mins)
    if prefer is not None and lack[prefer] > 0:
        take = min(lack[prefer], room * prefer_share)
        widths[prefer] += take
        room -= take
        lack[prefer] -= take
    open_ = [j for j in range(len(lack)) if lack[j] > 0]
    while open_ and room > 1e-6:
        share = room / len(open_)
        done = [j for j in open_ if lack[j] <= share]
        if not done:
            for j in open_:
                widths[j] += share
            room = 0
            break
        for j in done:
            widths[j] += lack[j]
            room -= lack[j]
            open_.remove(j)
    return widths


# ----------------------------------------------------------------------------------------
# Symbols and quantity names
# ----------------------------------------------------------------------------------------

_SUBDIGITS = str.maketrans("₀₁₂₃₄₅₆₇₈₉", "0123456789")
_CODE_KEY = re.compile(r"^[a-z][a-z0-9]*(?:_[a-z0-9]+)*$")


def plain_symbol(sym: str) -> str:
    """A symbol as typed in plain text: ``α₀`` and ``α_0`` and ``α_{0}`` → ``α0``."""
    return re.sub(r"[_{}]", "", sym.translate(_SUBDIGITS))


def display_symbol(sym: str) -> str:
    """The symbol a document prints: a code key given as a symbol (``low_temperature``,
    ``duration``: lower-case words of three or more letters) is not a symbol and prints as
    nothing (the quantity's name says it).

    >>> (display_symbol("ΔB_V13"), display_symbol("low_temperature"), display_symbol("n_nc"),
    ...  display_symbol("ARW"))
    ('ΔB_V13', '', 'n_nc', 'ARW')
    """
    sym = (sym or "").strip()
    if _CODE_KEY.match(sym) and max(len(p) for p in sym.split("_")) >= 4:
        return ""
    return sym


def quantity_name(r: dict) -> str:
    """A result's name for a document: its quantity name and its symbol once, never its code key.

    A name that already holds the symbol in plain text (``D.45 coefficient α0`` with symbol
    ``α₀``) gets the symbol in its place, with its real subscript, not a second time:

    >>> quantity_name({"quantity": "D.45 coefficient α0", "symbol": "α₀"})
    'D.45 coefficient α₀'
    >>> quantity_name({"quantity": "bias stability", "symbol": "B_s"})
    'bias stability B_s'
    >>> quantity_name({"quantity": "damp heat: duration applied", "symbol": "duration",
    ...                "key": "dh_duration"})
    'damp heat: duration applied'
    """
    name = (r.get("quantity") or "").strip()
    sym = display_symbol(r.get("symbol") or "")
    if not name:
        return sym or r.get("key", "")
    if not sym:
        return r.get("quantity")  # a Text stays one: the document writes the name in its language
    plain = plain_symbol(sym)
    tokens = name.split(" ")
    for i, tok in enumerate(tokens):
        core = tok.strip(",;:()")
        if core and (core == sym or plain_symbol(core) == plain):
            tokens[i] = tok.replace(core, sym)
            return " ".join(tokens)
    from ..base.locale import join

    return join(" ", [r.get("quantity"), sym])  # each part in the document's language

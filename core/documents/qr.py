"""The QR code a registered report carries: a link to its public verify page.

The lab profile's ``verify_url`` (``https://lab.example/verify/``) is the base; a registered
report's link is ``<verify_url>/<number>`` (:func:`verify_link`), the page ``metro serve`` shows at
``/verify/<number>``.  The code is drawn with segno (pure Python) as a QR code (never a Micro QR,
which phones rarely read), error correction level M, and written as a PNG
(:func:`qr_png`) that :class:`~metro.core.documents.builder.DocumentBuilder` places at the top
right of page 1.  The PNG's bytes depend only on the link, so a document written again from the
register (``metro report NUMBER``) is the same.
"""

from __future__ import annotations

from typing import Any
from urllib.parse import quote

__all__ = ["ERROR", "SCALE", "BORDER", "verify_link", "make_code", "qr_png", "float_top_right"]

#: error correction level (M: 15 % of the code words may be lost)
ERROR = "m"
#: pixels per module in the PNG, and the quiet zone around the code in modules (ISO/IEC 18004: 4)
SCALE, BORDER = 8, 4


def verify_link(base: str, number: str) -> str:
    """The verify URL of report ``number``: ``base`` and the number (percent-encoded) joined by
    one ``/``."""
    return base.rstrip("/") + "/" + quote(number, safe="")


def make_code(link: str) -> Any:
    """The segno QR code of ``link`` (always a full QR code, level M, the smallest version)."""
    import segno

    return segno.make_qr(link, error=ERROR, boost_error=False)


def qr_png(link: str) -> bytes:
    """The QR code of ``link`` as PNG bytes (black on white, :data:`SCALE` pixels a module, a
    :data:`BORDER`-module quiet zone)."""
    import io

    buf = io.BytesIO()
    make_code(link).save(buf, kind="png", scale=SCALE, border=BORDER)
    return buf.getvalue()


def float_top_right(paragraph: Any, png: bytes, size_mm: float, description: str) -> None:
    """Add ``png`` (``size_mm`` square) to ``paragraph`` as a picture floating at the top right of
    the page's text area, the text wrapping on its left (``wp:anchor``: python-docx writes only
    inline pictures, so the inline one is moved into an anchor); ``description`` is its
    alternative text."""
    import io

    from docx.oxml import OxmlElement
    from docx.oxml.ns import qn
    from docx.shared import Mm

    run = paragraph.add_run()
    run.add_picture(io.BytesIO(png), width=Mm(size_mm), height=Mm(size_mm))
    inline = run._r.find(".//" + qn("wp:inline"))
    anchor = OxmlElement("wp:anchor", attrs={
        "distT": "0", "distB": "0", "distL": "114300", "distR": "0", "simplePos": "0",
        "relativeHeight": "251659264", "behindDoc": "0", "locked": "0", "layoutInCell": "1",
        "allowOverlap": "0"})
    anchor.append(OxmlElement("wp:simplePos", attrs={"x": "0", "y": "0"}))
    for axis, tag, text in (("H", "wp:align", "right"), ("V", "wp:posOffset", "0")):
        pos = OxmlElement(f"wp:position{axis}", attrs={"relativeFrom": "margin"})
        value = OxmlElement(tag)
        value.text = text
        pos.append(value)
        anchor.append(pos)
    anchor.append(inline.find(qn("wp:extent")))
    anchor.append(OxmlElement("wp:effectExtent", attrs={"l": "0", "t": "0", "r": "0", "b": "0"}))
    anchor.append(OxmlElement("wp:wrapSquare", attrs={"wrapText": "left"}))
    doc_pr = inline.find(qn("wp:docPr"))
    doc_pr.set("descr", description)
    for child in (doc_pr, inline.find(qn("wp:cNvGraphicFramePr")), inline.find(qn("a:graphic"))):
        if child is not None:
            anchor.append(child)
    inline.getparent().replace(inline, anchor)

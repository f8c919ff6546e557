"""The DCC reference schemas for the tests of DCC output (tests/core/cli/test_dcc_cli.py,
tests/core/record/test_dcc_register.py, which load it with ``runpy.run_path``):
../shared/reference/dcc read with xmlschema, not the copy metro ships; the tests skip, saying why,
where that folder is absent (``needs_reference``), or LibreOffice is (``needs_soffice``).  Also
small readers of a DCC written (its identifier, the PDF it embeds, its content without that
PDF)."""

from __future__ import annotations

import base64
import functools
import shutil
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

REFERENCE = Path(__file__).resolve().parents[1].parent / "shared" / "reference" / "dcc"
#: why the schema tests skip (None: the reference folder is there)
SKIP_REASON = (None if (REFERENCE / "dcc.xsd").is_file()
               else f"the DCC reference schemas are not at {REFERENCE} (CI has them)")
needs_reference = pytest.mark.skipif(SKIP_REASON is not None, reason=str(SKIP_REASON))
needs_soffice = pytest.mark.skipif(
    not (shutil.which("soffice") or shutil.which("libreoffice")),
    reason="LibreOffice (soffice) makes the PDF a DCC embeds")
DCC = "{https://ptb.de/dcc}"


@functools.lru_cache(maxsize=1)
def schema():
    """dcc.xsd 3.3.0 with its imports mapped to the reference folder (its README's recipe)."""
    import xmlschema

    uri_map = {
        "https://ptb.de/si/v2.2.1/SI_Format.xsd": str(REFERENCE / "SI_Format.xsd"),
        "https://www.ptb.de/dcc/d-sig/xmldsig-core-schema.xsd":
            str(REFERENCE / "xmldsig-core-schema.xsd"),
        "https://www.ptb.de/si/v2.2.1/qudt/quantitykind.xsd": str(REFERENCE / "quantitykind.xsd"),
    }
    return xmlschema.XMLSchema(str(REFERENCE / "dcc.xsd"), uri_mapper=uri_map, allow="local")


def validate(path: str | Path) -> None:
    """Raise xmlschema's error when the file is not a valid DCC 3.3.0."""
    schema().validate(str(path))


def root(path: str | Path) -> ET.Element:
    return ET.parse(str(path)).getroot()


def core_text(path: str | Path, tag: str) -> str | None:
    """The text of ``dcc:coreData/dcc:<tag>`` (or of a deeper path under coreData)."""
    e = root(path).find(f"{DCC}administrativeData/{DCC}coreData/{tag}")
    return None if e is None else e.text


def embedded_pdf(path: str | Path) -> bytes:
    """The bytes of the report's PDF the DCC carries (``dcc:document/dcc:dataBase64``)."""
    e = root(path).find(f"{DCC}document/{DCC}dataBase64")
    assert e is not None and e.text, f"{path} embeds no document"
    return base64.b64decode(e.text)


def without_pdf(path: str | Path) -> bytes:
    """The DCC's XML with its embedded PDF left out (a PDF made again by LibreOffice differs in
    its creation time and document id)."""
    r = root(path)
    for doc in r.findall(f"{DCC}document"):
        r.remove(doc)
    return ET.tostring(r, encoding="utf-8")



@pytest.fixture
def unmapped_hour():
    """``hour`` out of metro's D-SI mapping for one test: °/h, the unit of GB/T 45570 D.5.6's
    results, then has no D-SI mapping.  What the module keeps cached is dropped before and after."""
    from metro.core.base import dsi

    def clear() -> None:
        for f in list(vars(dsi).values()):
            if callable(getattr(f, "cache_clear", None)):
                f.cache_clear()

    with pytest.MonkeyPatch.context() as mp:
        mp.delitem(dsi.DSI_UNITS, "hour")
        clear()
        yield
    clear()

"""Validation of a DCC against the schemas shipped in ``schema/`` (PTB DCC 3.3.0, D-SI 2.2.1,
LGPL v3: ``schema/COPYING.LESSER``), offline: the schemas' imports are mapped to the copies."""

from __future__ import annotations

import functools
from pathlib import Path
from typing import Any

from ...base.extras import require
from .xml import DccError

__all__ = ["SCHEMA_DIR", "IMPORTS", "schema", "validate_dcc"]

#: the folder of the shipped schema copies
SCHEMA_DIR = Path(__file__).resolve().parent / "schema"
#: each schema's published import location -> its file name here
IMPORTS = {
    "https://ptb.de/si/v2.2.1/SI_Format.xsd": "SI_Format.xsd",
    "https://www.ptb.de/dcc/d-sig/xmldsig-core-schema.xsd": "xmldsig-core-schema.xsd",
    "https://www.ptb.de/si/v2.2.1/qudt/quantitykind.xsd": "quantitykind.xsd",
}


@functools.lru_cache(maxsize=4)
def schema(folder: str | None = None) -> Any:
    """The DCC schema (an ``xmlschema.XMLSchema``) from ``folder`` (default: the shipped
    copies), its imports read from the same folder, never from the network."""
    xmlschema = require("xmlschema", "validating a DCC", extra="dcc")
    base = Path(folder) if folder else SCHEMA_DIR
    uri_map = {uri: str(base / name) for uri, name in IMPORTS.items()}
    return xmlschema.XMLSchema(str(base / "dcc.xsd"), uri_mapper=uri_map, allow="local")


def validate_dcc(xml: bytes, *, folder: str | None = None) -> None:
    """Check a DCC against the schema; :class:`DccError` naming the element path and the
    reason of the first error."""
    s = schema(folder)
    import io

    err = next(iter(s.iter_errors(io.BytesIO(xml))), None)
    if err is not None:
        raise DccError(f"the DCC does not follow the schema at {err.path}: {err.reason}")

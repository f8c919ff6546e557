"""A report as a PTB Digital Calibration Certificate (DCC 3.3.0, D-SI 2.2.1).

:func:`build_dcc` makes the XML of one report from the same document context the register stores
and ``write report`` renders (:func:`metro.core.documents.context.report_context`; its machine
values are ``context["data"]``, :func:`metro.core.documents.dcc.data.dcc_data`).
:func:`write_dcc` writes it to a file it never replaces; :func:`read_dcc_results` reads the
results of a DCC back; :func:`validate_dcc` checks one against the schema shipped in
``schema/`` (the ``dcc`` extra installs ``xmlschema``).  docs/dcc.md maps each field.
"""

from __future__ import annotations

import base64
import contextlib
import os
import secrets
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from .admin import CONFORMITY, administrative_data
from .data import DATA_VERSION, dcc_data
from .read import embedded_pdf, read_dcc_results
from .results import REF_BUDGET, REF_ITEM, REF_MATRIX, REF_TABLE, measurement_results
from .schema import SCHEMA_DIR, validate_dcc
from .xml import DCC_NS, SI_NS, DccError, Writer

__all__ = [
    "DCC_NS", "SI_NS", "SCHEMA_VERSION", "SCHEMA_DIR", "CONFORMITY", "DccError", "build_dcc",
    "write_dcc", "read_dcc_results", "embedded_pdf", "validate_dcc", "dcc_data",
]

#: the DCC schema version metro writes (``schemaVersion``)
SCHEMA_VERSION = "3.3.0"
_REFTYPES = ((REF_ITEM, "the item (clause) of the standard a measurement result belongs to"),
             (REF_MATRIX, "a 3×3 matrix of results, row by row, as a D-SI list"),
             (REF_BUDGET, "an uncertainty budget: one list per component, then u_c, ν_eff, k, U"),
             (REF_TABLE, "a table of records the report prints, one text per row"))


def _decoded(ctx: Mapping[str, Any]) -> Mapping[str, Any]:
    """The context as :func:`report_context` makes it: texts stored by the register as
    ``{"text": …}`` become translatable :class:`Text` again."""
    from ...base.locale import Text

    def dec(obj: Any) -> Any:
        if isinstance(obj, Mapping):
            if set(obj) == {"text"} and isinstance(obj["text"], Mapping):
                return Text.decode(obj["text"])
            return {k: dec(v) for k, v in obj.items()}
        if isinstance(obj, list):
            return [dec(v) for v in obj]
        return obj

    return dec(ctx)


def _check(ctx: Mapping[str, Any]) -> None:
    data = ctx.get("data")
    if not isinstance(data, Mapping):
        raise DccError(f"report {ctx.get('report_number', '?')} was stored without the machine "
                       "values a DCC needs (numbers, units, k, verdict codes): it was written "
                       "before metro wrote DCCs",
                       hint="issue the report again (metro register amend) to get a DCC")
    if data.get("version") != DATA_VERSION:
        raise DccError(f"report {ctx.get('report_number', '?')}: its machine values are of "
                       f"layout {data.get('version')!r}; this metro writes DCCs from layout "
                       f"{DATA_VERSION}")
    status = (ctx.get("register") or {}).get("status")
    if status == "withdrawn":
        raise DccError(f"report {ctx.get('report_number')} is withdrawn; a withdrawn report is "
                       "never issued as a DCC")


def _reftypes(w: Writer, adm: ET.Element) -> None:
    defs = w.el(adm, "refTypeDefinitions")
    for ref, what in _REFTYPES:
        d = w.el(defs, "refTypeDefinition", refType=ref)
        w.text(d, "name", ref)
        w.text(d, "description", what)
        w.el(d, "namespace", "metro")
        w.el(d, "link", "docs/dcc.md")


def build_dcc(context: Mapping[str, Any], *, pdf: bytes | None = None) -> bytes:
    """The DCC (UTF-8 XML) of one report, from its document context (as ``build_context``
    makes it or the register stores it).  ``pdf``, the same report as PDF, is embedded as
    ``dcc:document`` (base64).  :class:`DccError` for a context without machine values or of a
    withdrawn report; :class:`~metro.core.base.errors.UnitError` naming the unit and the result
    for a unit with no D-SI mapping."""
    ctx = _decoded(context)
    _check(ctx)
    w = Writer(str(ctx.get("lang") or "zh+en"))
    root = ET.Element(f"{{{DCC_NS}}}digitalCalibrationCertificate",
                      {"schemaVersion": SCHEMA_VERSION})
    administrative_data(w, root, ctx)
    _reftypes(w, root.find(f"{{{DCC_NS}}}administrativeData"))
    measurement_results(w, root, ctx)
    if pdf is not None:
        doc = w.el(root, "document")
        w.text(doc, "name", f"report {ctx['report_number']} (PDF)")
        w.el(doc, "fileName", f"{ctx['report_number']}.pdf")
        w.el(doc, "mimeType", "application/pdf")
        w.el(doc, "dataBase64", base64.b64encode(pdf).decode("ascii"))
    ET.indent(root, space=" ")
    return ET.tostring(root, encoding="utf-8", xml_declaration=True) + b"\n"


def write_dcc(context: Mapping[str, Any], target: str | os.PathLike[str], *,
              pdf: bytes | None = None) -> Path:
    """Write :func:`build_dcc` to ``target`` atomically (complete or not at all); never
    replaces a file: :class:`DccError` when ``target`` exists.  Returns ``target``."""
    final = Path(target)
    xml = build_dcc(context, pdf=pdf)
    if final.exists() or final.is_symlink():
        raise DccError(f"{final} exists; metro never replaces a certificate file",
                       hint="move it away or give another file name")
    tmp = final.parent / f".{final.name}.tmp-{secrets.token_hex(4)}"
    try:
        with open(tmp, "xb") as fh:
            fh.write(xml)
            fh.flush()
            os.fsync(fh.fileno())
        os.link(tmp, final)
    except FileExistsError as exc:
        raise DccError(f"{final} exists; metro never replaces a certificate file") from exc
    finally:
        with contextlib.suppress(OSError):
            tmp.unlink()
    return final

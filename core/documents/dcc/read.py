"""Reading the results of a DCC metro wrote (or any DCC laid out the same way) back."""

from __future__ import annotations

import xml.etree.ElementTree as ET
from typing import Any

from ...base.dsi import metro_unit
from .admin import CONFORMITY
from .xml import DCC_NS, SI_NS, DccError

__all__ = ["read_dcc_results", "embedded_pdf"]

_D = f"{{{DCC_NS}}}"
_S = f"{{{SI_NS}}}"
_VERDICT = {v: k for k, v in CONFORMITY.items()}


def _text(e: ET.Element | None) -> str:
    """A ``dcc:textType``'s content: the English one, else the first."""
    if e is None:
        return ""
    contents = e.findall(f"{_D}content")
    for c in contents:
        if c.get("lang") == "en":
            return (c.text or "").strip()
    return (contents[0].text or "").strip() if contents else ""


def _float(e: ET.Element | None, path: str) -> float | None:
    if e is None:
        return None
    x = e.find(path)
    if x is None or not (x.text or "").strip():
        return None
    return float(x.text)


def _item(mr: ET.Element) -> str:
    for md in mr.iter(f"{_D}metaData"):
        if "metro_item" in (md.get("refType") or "").split():
            return _text(md.find(f"{_D}declaration"))
    return ""


def _one(res: ET.Element, item: str, verdicts: dict[str, str]) -> dict[str, Any]:
    q = res.find(f"{_D}data/{_D}quantity")
    if q is None:
        raise DccError(f"result {res.get('id')!r} has no dcc:data/dcc:quantity")
    real = q.find(f"{_S}real")
    out: dict[str, Any] = {"item": item, "id": res.get("id"), "key": _text(q.find(f"{_D}name")),
                           "value": None, "U": None, "k": None, "p": None, "unit": None,
                           "dsi_unit": None, "reportable": real is not None, "reason": "",
                           "verdict": verdicts.get(res.get("id") or "")}
    if real is None:
        out["reason"] = _text(q.find(f"{_D}noQuantity"))
        return out
    dsi = (real.findtext(f"{_S}unit") or "").strip()
    mu = real.find(f"{_S}measurementUncertaintyUnivariate/{_S}expandedMU")
    out.update(key=(real.findtext(f"{_S}label") or out["key"]).strip(),
               value=_float(real, f"{_S}value"), dsi_unit=dsi, unit=metro_unit(dsi),
               U=_float(mu, f"{_S}valueExpandedMU"), k=_float(mu, f"{_S}coverageFactor"),
               p=_float(mu, f"{_S}coverageProbability"))
    return out


def read_dcc_results(xml: bytes) -> list[dict[str, Any]]:
    """Every result of a DCC, in document order: ``item``, ``key``, ``id``, ``value``, ``U``,
    ``k``, ``p`` (coverage probability), ``unit`` (metro's unit text,
    :func:`metro.core.base.dsi.metro_unit`), ``dsi_unit``, ``reportable`` (False for a
    ``dcc:noQuantity``), ``reason`` and ``verdict`` (metro's word for the conformity statement
    that refers to the result: ``pass``, ``fail``, ``conditional pass``, ``conditional fail``,
    or None).  Matrices (refType ``metro_matrix``) repeat results and are left out, as are
    tables (``metro_table``) and items that state no quantity.
    :class:`DccError` for text that is not a DCC; :class:`UnitError` for a unit metro does
    not map."""
    try:
        root = ET.fromstring(xml)
    except ET.ParseError as exc:
        raise DccError(f"not XML: {exc}") from None
    if root.tag != f"{_D}digitalCalibrationCertificate":
        raise DccError(f"not a DCC: the root element is {root.tag!r}")
    verdicts: dict[str, str] = {}
    for s in root.iter(f"{_D}statement"):
        conf = s.findtext(f"{_D}conformity")
        for ref in (s.get("refId") or "").split():
            if conf:
                verdicts[ref] = _VERDICT.get(conf.strip(), conf.strip())
    out = []
    for mr in root.iter(f"{_D}measurementResult"):
        item = _item(mr)
        for res in mr.findall(f"{_D}results/{_D}result"):
            if {"metro_matrix", "metro_table"} & set((res.get("refType") or "").split()):
                continue
            if res.find(f"{_D}data/{_D}quantity") is None:  # an item without a quantity
                continue
            out.append(_one(res, item, verdicts))
    return out


def embedded_pdf(xml: bytes) -> bytes | None:
    """The PDF a DCC carries as ``dcc:document`` (base64 in ``dataBase64``, ``mimeType``
    application/pdf or the data a PDF: what :func:`~metro.core.documents.dcc.build_dcc` embeds);
    None when it carries none or the XML does not parse.

    >>> embedded_pdf(b"<x/>") is None
    True
    """
    import base64
    import binascii

    try:
        root = ET.fromstring(xml)
    except ET.ParseError:
        return None
    for doc in root.iter(f"{_D}document"):
        try:
            data = base64.b64decode(doc.findtext(f"{_D}dataBase64") or "", validate=True)
        except (binascii.Error, ValueError):
            continue
        if data and (doc.findtext(f"{_D}mimeType") == "application/pdf"
                     or data.startswith(b"%PDF")):
            return data
    return None

"""Element builders of the DCC writer: namespaced elements, texts in the document's languages,
D-SI quantities (``si:real`` with ``si:expandedMU``, ``si:realListXMLList``) and identifiers."""

from __future__ import annotations

import math
import re
import xml.etree.ElementTree as ET
from collections.abc import Sequence
from typing import Any

from ...base.dsi import dsi_unit
from ...base.errors import MetroError
from ...base.locale import Translator, translator

__all__ = [
    "DCC_NS", "SI_NS", "DccError", "Writer", "decimal", "k_text", "p_text", "ncname",
]

#: the namespace of the DCC schema (prefix ``dcc``)
DCC_NS = "https://ptb.de/dcc"
#: the namespace of D-SI (prefix ``si``)
SI_NS = "https://ptb.de/si"
ET.register_namespace("dcc", DCC_NS)
ET.register_namespace("si", SI_NS)

_NOT_NAME = re.compile(r"[^A-Za-z0-9._-]+")
_K = re.compile(r"\+?(([1-9]\d*\.\d*)|([1-9]\d*))")


class DccError(MetroError):
    """A report that cannot be written as a DCC (a context without machine values, a withdrawn
    report, a unit or a number the schema cannot hold); the message names what and why."""


def decimal(x: float) -> str:
    """A float as D-SI decimal text that reads back to the same float (``repr``)."""
    if not math.isfinite(x):
        raise DccError(f"the number {x!r} cannot stand in a DCC (not finite)")
    return repr(float(x))


def k_text(k: float, where: str) -> str:
    """A coverage factor as ``si:kValueType`` text (≥ 1, no exponent)."""
    text = repr(float(k))
    if "e" in text:
        text = f"{float(k):.6f}"
    if not _K.fullmatch(text) or float(k) < 1:
        raise DccError(f"{where}: the coverage factor k = {k!r} cannot stand in a DCC "
                       "(D-SI asks k ≥ 1)")
    return text


def p_text(p: float) -> str:
    """A coverage probability as ``si:probabilityValueType`` text (0 … 1, no exponent)."""
    return f"{min(max(float(p), 0.0), 1.0):.4f}"


def ncname(*parts: Any) -> str:
    """An ``xs:ID``: the parts joined by ``-``, characters an XML name cannot hold as ``_``."""
    text = "-".join(_NOT_NAME.sub("_", str(p)) for p in parts if str(p))
    return text if re.match(r"[A-Za-z_]", text) else f"_{text}"


class Writer:
    """Makes the elements of one DCC in its languages (``zh``, ``en`` or both)."""

    def __init__(self, lang: str) -> None:
        self.langs: list[str] = ["zh", "en"] if lang == "zh+en" else [lang]
        self.tr: Translator = translator("zh+en")  # renders either language on demand
        self._seen: dict[str, list[tuple[str | None, str]]] = {}

    # --- plain elements --------------------------------------------------------------------
    @staticmethod
    def el(parent: ET.Element, tag: str, text: str | None = None,
           **attrib: str) -> ET.Element:
        """``<dcc:tag>`` (``si:tag`` when ``tag`` starts with ``si:``) under ``parent``."""
        ns, _, name = tag.rpartition(":")
        e = ET.SubElement(parent, f"{{{SI_NS if ns == 'si' else DCC_NS}}}{name}", attrib)
        if text is not None:
            e.text = text
        return e

    def texts(self, value: Any) -> list[tuple[str | None, str]]:
        """``value`` in each language of the document: [(lang, text)]; one entry without a
        language when every language reads the same."""
        plain = type(value) is str
        if plain and value in self._seen:
            return self._seen[value]
        out = self._texts(value)
        if plain:
            self._seen[value] = out
        return out

    def _texts(self, value: Any) -> list[tuple[str | None, str]]:
        """A text metro translates carries ``lang``; data (names, numbers, a text with no
        translation) is written once, without one, whatever the document's language."""
        both = {lang: " ".join(self.tr.render(value, lang).split()) for lang in ("zh", "en")}
        if both["zh"] == both["en"]:
            return [(None, both["en"])] if both["en"] else []
        return [(lang, both[lang]) for lang in self.langs if both[lang]]

    def contents(self, parent: ET.Element, value: Any) -> None:
        """A ``dcc:content`` per language of ``value`` under ``parent``."""
        for lang, text in self.texts(value):
            attrib = {"lang": lang} if lang else {}
            self.el(parent, "content", text, **attrib)

    def text(self, parent: ET.Element, tag: str, value: Any, fallback: str = "—",
             **attrib: str) -> ET.Element:
        """A ``dcc:textType`` (or ``richContentType``) element: ``value`` in each language, or
        ``fallback`` when it is empty (the schema wants content)."""
        e = self.el(parent, tag, **attrib)
        if self.texts(value):
            self.contents(e, value)
        else:
            self.el(e, "content", fallback)
        return e

    def maker(self, parent: ET.Element, manufacturer: Any, model: Any) -> None:
        """``dcc:manufacturer`` and ``dcc:model`` of an item or equipment, those that are
        given."""
        if manufacturer:
            self.text(self.el(parent, "manufacturer"), "name", manufacturer)
        if model:
            self.el(parent, "model", " ".join(str(model).split()))

    def identifications(self, parent: ET.Element,
                        rows: Sequence[tuple[str, Any, str]]) -> ET.Element:
        """``dcc:identifications``: one ``dcc:identification`` per (issuer, value, name) whose
        value is given."""
        ids = self.el(parent, "identifications")
        for issuer, value, name in rows:
            if value and str(value).strip():
                ident = self.el(ids, "identification")
                self.el(ident, "issuer", issuer)
                self.el(ident, "value", " ".join(str(value).split()))
                self.text(ident, "name", name)
        return ids

    # --- D-SI --------------------------------------------------------------------------------
    @staticmethod
    def unit(u: str, where: str) -> str:
        """The D-SI unit of metro's ``u``; :class:`UnitError` naming ``where`` when unmapped."""
        return dsi_unit(u, result=where)

    def real(self, parent: ET.Element, value: str, unit: str, *, where: str,
             label: str | None = None, U: str | None = None, k: float | None = None,
             p: float | None = None, u: float | None = None) -> ET.Element:
        """``si:real``: value and D-SI unit, with ``si:expandedMU`` (U, k, p) when U is given,
        else ``si:standardMU`` when only a standard uncertainty ``u`` is."""
        r = self.el(parent, "si:real")
        if label:
            self.el(r, "si:label", label)
        self.el(r, "si:value", value)
        self.el(r, "si:unit", self.unit(unit, where))
        if U is not None and k is not None and p is not None:
            mu = self.el(self.el(r, "si:measurementUncertaintyUnivariate"), "si:expandedMU")
            self.el(mu, "si:valueExpandedMU", U.lstrip("+"))
            self.el(mu, "si:coverageFactor", k_text(k, where))
            self.el(mu, "si:coverageProbability", p_text(p))
        elif u is not None and u >= 0:
            mu = self.el(self.el(r, "si:measurementUncertaintyUnivariate"), "si:standardMU")
            self.el(mu, "si:valueStandardMU", decimal(u))
        return r

    def real_list(self, parent: ET.Element, labels: Sequence[str], values: Sequence[str],
                  unit: str, Us: Sequence[str], ks: Sequence[float], ps: Sequence[float], *,
                  where: str) -> ET.Element:
        """``si:realListXMLList``: values with one unit and their expanded uncertainties."""
        r = self.el(parent, "si:realListXMLList")
        self.el(r, "si:labelXMLList", " ".join(labels))
        self.el(r, "si:valueXMLList", " ".join(values))
        self.el(r, "si:unitXMLList", self.unit(unit, where))
        mu = self.el(self.el(r, "si:measurementUncertaintyUnivariateXMLList"),
                     "si:expandedMUXMLList")
        self.el(mu, "si:valueExpandedMUXMLList", " ".join(u.lstrip("+") for u in Us))
        self.el(mu, "si:coverageFactorXMLList", " ".join(k_text(k, where) for k in ks))
        self.el(mu, "si:coverageProbabilityXMLList", " ".join(p_text(p) for p in ps))
        return r

    def quantity(self, parent: ET.Element, name: Any, *, refType: str | None = None,
                 **attrib: str) -> ET.Element:
        """A ``dcc:quantity`` with its name; the caller adds the D-SI element."""
        if refType:
            attrib["refType"] = refType
        q = self.el(parent, "quantity", **attrib)
        self.text(q, "name", name)
        return q

    def no_quantity(self, parent: ET.Element, name: Any, text: Any, **attrib: str) -> ET.Element:
        """A ``dcc:quantity`` that states text instead of a value (``dcc:noQuantity``)."""
        q = self.quantity(parent, name, **attrib)
        self.text(q, "noQuantity", text)
        return q

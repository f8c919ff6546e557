"""``dcc:administrativeData`` of a report: software, core data, the item, the laboratory, the
people, the customer and the statements (decision rule, verdicts, equipment, location)."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import Any

from .xml import DCC_NS, DccError, Writer, ncname

__all__ = ["administrative_data", "CONFORMITY", "result_ids", "influence_conditions",
           "NOT_STATED_COUNTRY"]

#: metro's verdict (``Verdict.detail``) -> the DCC's ``stringConformityStatementStatusType``;
#: a verdict with no U or on a result that is not reportable has no DCC value (text only)
CONFORMITY = {"pass": "pass", "fail": "fail", "conditional pass": "conditionalPass",
              "conditional fail": "conditionalFail"}
#: ISO 3166-1 user-assigned code written when neither the site nor the campaign names a country
NOT_STATED_COUNTRY = "ZZ"
_DATE = re.compile(r"\d{4}-\d{2}-\d{2}")
_ROLES = (("operator", "calibrated by", "operator_title"), ("checker", "checked by",
                                                             "checker_title"),
          ("approver", "approved by", "approver_title"))
_CONDITIONS = (("environment", "temperature"), ("environment", "humidity"),
               ("environment", "pressure"), ("environment", "magnetic_field"),
               ("site", "latitude"), ("site", "latitude_uncertainty"), ("site", "altitude"),
               ("site", "gravity"))


def result_ids(data: Mapping[str, Any]) -> list[str]:
    """The ``id`` of each result's ``dcc:result``, in ``data["results"]`` order (unique)."""
    seen: dict[str, int] = {}
    out = []
    for r in data["results"]:
        base = ncname("result", r["item"], r["key"])
        seen[base] = seen.get(base, 0) + 1
        out.append(base if seen[base] == 1 else f"{base}-{seen[base]}")
    return out


def influence_conditions(data: Mapping[str, Any]) -> list[tuple[str, str, dict[str, Any]]]:
    """(id, name, {value, unit}) of each influence condition: the environment's temperature,
    humidity, pressure and magnetic field, the site's latitude (and its uncertainty), altitude
    and gravity, the earth's rate Ω_e and its vertical component at the site's latitude."""
    cond = data["conditions"]
    found = [(name.replace("_", " "), cond[where][name]) for where, name in _CONDITIONS
             if name in cond.get(where, {})]
    found.append(("earth rate Ω_e", cond["earth_rate"]))
    if "earth_rate_vertical" in cond:
        found.append(("earth rate, vertical component Ω_e·sin φ at the site's latitude",
                      cond["earth_rate_vertical"]))
    return [(ncname("condition", i, name.split()[0]), name, q)
            for i, (name, q) in enumerate(found)]


def _date(text: Any) -> str | None:
    m = _DATE.match(str(text or ""))
    return m.group(0) if m else None


def _software(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    sw = w.el(parent, "dccSoftware")
    prov = ctx.get("provenance") or {}
    versions = {s["name"]: s["version"] for s in prov.get("software", [])}
    s = w.el(sw, "software")
    w.text(s, "name", "metro")
    w.el(s, "release", str(versions.get("metro") or "unknown"))
    w.el(s, "type", "application")
    for p in prov.get("plugins", []):
        s = w.el(sw, "software")
        w.text(s, "name", f"metro plugin {p['name']}")
        w.el(s, "release", str(p["version"]).split()[-1] or "unknown")
        w.el(s, "type", "library")
        w.text(s, "description", f"distribution: {p['version']}")


def _core(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    data, facts = ctx["data"], ctx.get("facts") or {}
    core = w.el(parent, "coreData")
    country = data.get("country") or NOT_STATED_COUNTRY
    if not re.fullmatch(r"[A-Z]{2}", country):
        raise DccError(f"the country {country!r} is not an ISO 3166-1 alpha-2 code",
                       hint="write country = \"CN\" (two capital letters) under [site]")
    w.el(core, "countryCodeISO3166_1", country)
    for tag in ("usedLangCodeISO639_1", "mandatoryLangCodeISO639_1"):
        for lang in w.langs:
            w.el(core, tag, lang)
    w.el(core, "uniqueIdentifier", str(ctx["report_number"]))
    ids = w.el(core, "identifications")
    ident = w.el(ids, "identification")
    w.el(ident, "issuer", "calibrationLaboratory")
    w.el(ident, "value", str((ctx.get("campaign") or {}).get("id") or ctx["report_number"]))
    w.text(ident, "name", "campaign")
    if _date(facts.get("received")):
        w.el(core, "receiptDate", _date(facts["received"]))
    w.el(core, "beginPerformanceDate", data["dates"]["begin"])
    w.el(core, "endPerformanceDate", data["dates"]["end"])
    w.el(core, "performanceLocation", "other" if facts.get("location") else "laboratory")
    if _date(facts.get("issued")):
        w.el(core, "issueDate", _date(facts["issued"]))
    replaced = (ctx.get("register") or {}).get("supersedes")
    if replaced:
        ras = w.el(core, "reportAmendedSubstituted")
        w.el(ras, "typeOfChange", "substituted")
        w.el(ras, "replacedUniqueIdentifier", str(replaced))


def _items(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    dev = ctx["data"]["device"]
    items = w.el(parent, "items")
    item = w.el(items, "item", id="item-device")
    w.text(item, "name", (ctx.get("device") or {}).get("description") or dev["id"])
    w.maker(item, dev.get("manufacturer"), dev.get("model"))
    w.identifications(item, (("manufacturer", dev.get("serial"), "serial number"),
                             ("calibrationLaboratory", dev.get("id"), "device id"),
                             ("customer", dev.get("customer_id"), "customer's id")))


def _contact(w: Writer, parent: ET.Element, tag: str, name: str, address: str,
             country: str | None) -> None:
    c = w.el(parent, tag)
    w.text(c, "name", name, fallback="not stated")
    loc = w.el(c, "location")
    if address:
        w.text(loc, "further", address)
    elif country:
        w.el(loc, "countryCode", country)
    else:
        w.text(loc, "further", "not stated")


def _people(w: Writer, parent: ET.Element, facts: Mapping[str, Any]) -> None:
    rp = w.el(parent, "respPersons")
    named = [(k, role, facts.get(t) or "") for k, role, t in _ROLES if facts.get(k)]
    if not named:
        p = w.el(rp, "respPerson")
        w.text(w.el(p, "person"), "name", "not stated")
        w.el(p, "role", "none named in the campaign or lab profile")
        return
    signer = named[-1][0] if any(k == "approver" for k, _, _ in named) else named[0][0]
    for key, role, title in named:
        p = w.el(rp, "respPerson", id=ncname("person", key))
        w.text(w.el(p, "person"), "name", facts[key])
        w.el(p, "role", f"{role}, {title}" if title else role)
        w.el(p, "mainSigner", "true" if key == signer else "false")


def _statement(w: Writer, parent: ET.Element, name: Any, declaration: Any = None, *,
               convention: str | None = None, norm: str | None = None,
               location: Any = None, **attrib: str) -> ET.Element:
    """A ``dcc:statement`` with its elements in the schema's order."""
    s = w.el(parent, "statement", **attrib)
    w.text(s, "name", name)
    if convention:
        w.el(s, "convention", convention)
    if norm:
        w.el(s, "norm", " ".join(norm.split()))
    if declaration is not None:
        w.text(s, "declaration", declaration)
    if location:
        w.text(w.el(s, "location"), "further", location)
    return s


def _reference(w: Writer, text: str) -> ET.Element:
    e = ET.Element(f"{{{DCC_NS}}}reference")
    e.text = " ".join(text.split())
    return e


def _verdicts(w: Writer, st: ET.Element, ctx: Mapping[str, Any]) -> None:
    data = ctx["data"]
    ids = {(r["item"], r["key"]): i for r, i in zip(data["results"], result_ids(data))}
    for v in data.get("verdicts", []):
        ref = ids.get((v["item"], v["key"]))
        attrib = {"refId": ref} if ref else {}
        s = w.el(st, "statement", **attrib)
        w.text(s, "name", f"conformity of {v['key']} ({v['item']}): {v['limit']}")
        w.text(s, "description", v["source"])
        w.el(s, "convention", v["rule"])
        w.text(s, "declaration", v["reason"] or v["detail"])
        if v["detail"] in CONFORMITY:
            w.el(s, "conformity", CONFORMITY[v["detail"]])


def _equipment(w: Writer, st: ET.Element, ctx: Mapping[str, Any]) -> None:
    on = ctx["data"]["dates"]["end"]
    for e in ctx["data"]["equipment"]:
        s = w.el(st, "statement", refId=ncname("equipment", e["id"]))
        w.text(s, "name", f"calibration of the measuring equipment {e['id']}")
        if e.get("certificate"):
            w.text(s, "description", e["certificate"] + (f" ({e['lab']})" if e["lab"] else ""))
            w.el(s, "traceable", "true")
            w.el(s, "reference", " ".join(str(e["certificate"]).split()))
            status = (f"certificate {e['certificate']}, valid until {e['due']}" if e["due"]
                      else f"certificate {e['certificate']}, no due date stated")
            w.text(s, "declaration", status)
            if e["due"]:
                w.el(s, "valid", "true" if e["due"] >= on else "false")
                w.el(s, "date", e["due"])
        else:
            w.text(s, "declaration", "no calibration data given")


def _statements(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    data, facts = ctx["data"], ctx.get("facts") or {}
    st = w.el(parent, "statements")
    if ctx.get("simulated"):
        _statement(w, st, "simulated", ctx.get("simulated_banner") or "simulated")
    rule = data.get("decision_rule")
    if rule:
        _statement(w, st, f"decision rule: {rule['title']}", rule["statement"],
                   convention=rule["name"])
    _verdicts(w, st, ctx)
    for std in ctx.get("standards", []):
        s = _statement(w, st, "method", f"{std['designation']} {std['items_text']}",
                       norm=str(std["designation"]))
        for o in ctx["outcomes"]:  # the clause of each item, before the declaration
            if o["standard"] == std["id"]:
                item = "" if o["item"] == o["clause"] else f" (item {o['item']})"
                s.insert(len(s) - 1, _reference(w, f"clause {o['clause']}{item}"))
    conditions = influence_conditions(data)
    s = _statement(w, st, "influence conditions", "; ".join(
        f"{name} {q['text'] if q.get('text') else q['value']}" for _, name, q in conditions),
        refId=" ".join(cid for cid, _, _ in conditions))
    _equipment(w, st, ctx)
    if facts.get("location"):
        _statement(w, st, "performance location", facts["location"],
                   location=facts["location"])
    if not data.get("country"):
        _statement(w, st, "country", "no country stated in the campaign ([site] country); "
                   f"the country code {NOT_STATED_COUNTRY} means not stated")
    for notice in (ctx.get("register") or {}).get("notices", []):
        _statement(w, st, "register", notice)


def administrative_data(w: Writer, root: ET.Element, ctx: Mapping[str, Any]) -> None:
    """``dcc:administrativeData`` of the report context ``ctx`` under ``root``."""
    facts = ctx.get("facts") or {}
    adm = w.el(root, "administrativeData")
    _software(w, adm, ctx)
    _core(w, adm, ctx)
    _items(w, adm, ctx)
    lab = w.el(adm, "calibrationLaboratory")
    country = ctx["data"].get("country") or None
    lab_name = facts.get("lab") or ("metro simulated test station" if ctx.get("simulated")
                                    else "")
    _contact(w, lab, "contact", lab_name, facts.get("lab_address") or "", country)
    _people(w, adm, facts)
    _contact(w, adm, "customer", facts.get("customer") or "", facts.get("customer_address")
             or "", country)
    _statements(w, adm, ctx)

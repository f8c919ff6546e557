"""``dcc:measurementResults`` of a report: the methods, software, equipment and influence
conditions, then one ``dcc:measurementResult`` per item with one ``dcc:result`` per quantity (its
budget as a table of components), and JJF 2003's 3×3 matrices as D-SI lists."""

from __future__ import annotations

import re
import xml.etree.ElementTree as ET
from collections.abc import Mapping
from typing import Any

from ...base.locale import join
from .admin import influence_conditions, result_ids
from .data import decimal_text
from .xml import DccError, Writer, decimal, ncname

__all__ = ["measurement_results", "matrices", "REF_ITEM", "REF_MATRIX", "REF_BUDGET",
           "REF_TABLE"]

#: refTypes metro gives its own elements (declared in ``dcc:refTypeDefinitions``): the item a
#: measurement result is of, a 3×3 matrix of results, a budget, a table of records
REF_ITEM = "metro_item"
#: see :data:`REF_ITEM`
REF_MATRIX = "metro_matrix"
#: see :data:`REF_ITEM`
REF_BUDGET = "metro_budget"
#: see :data:`REF_ITEM`
REF_TABLE = "metro_table"
_AXES = "xyz"
_MATRIX_KEY = re.compile(r"^(?P<base>.+?)(?P<row>[xyz])(?P<col>[xyz])$")
def _value_text(r: Mapping[str, Any]) -> str:
    """The value as the certificate states it (rounded to U's last digit), as decimal text."""
    return decimal_text(r["value_text"]) or decimal(r["value"])


def _u_text(r: Mapping[str, Any]) -> str | None:
    if r["U"] is None:
        return None
    return decimal_text(r["U_text"] or "") or decimal(r["U"])


def _methods(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    um = w.el(parent, "usedMethods")
    for o in ctx["outcomes"]:
        m = w.el(um, "usedMethod", id=ncname("method", o["number"], o["item"]))
        w.text(m, "name", f"{o['designation']} {o['item']} {o['title']}")
        if o.get("options_text"):
            w.text(m, "description", f"options: {o['options_text']}")
        w.el(m, "norm", " ".join(str(o["designation"]).split()))
        w.el(m, "reference", f"clause {o['clause']}")
        refs = {f"clause {r['clause']}" + (f", {r['equation']}" if r["equation"] else "")
                for r in ctx["data"]["results"] if r["item"] == o["item"] and r["clause"]}
        for ref in sorted(refs - {f"clause {o['clause']}"}):
            w.el(m, "reference", " ".join(ref.split()))


def _software(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    sw = [s for s in (ctx.get("provenance") or {}).get("software", []) if s["name"] != "metro"]
    if not sw:
        return
    us = w.el(parent, "usedSoftware")
    for s in sw:
        e = w.el(us, "software")
        w.text(e, "name", s["name"])
        w.el(e, "release", " ".join(str(s["version"]).split()) or "unknown")
        w.el(e, "type", "os" if s["name"] == "platform" else "library")


def _equipment(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    eqs = ctx["data"]["equipment"]
    if not eqs:
        return
    me = w.el(parent, "measuringEquipments")
    for e in eqs:
        m = w.el(me, "measuringEquipment", id=ncname("equipment", e["id"]))
        w.text(m, "name", e["description"] or e["id"])
        w.text(m, "description", f"role: {e['role']}" if e["role"] else e["id"])
        w.maker(m, e.get("manufacturer"), e.get("model"))
        w.identifications(m, (("calibrationLaboratory", e["id"], "equipment id"),
                              ("manufacturer", e.get("serial"), "serial number"),
                              ("other", e.get("certificate"), "calibration certificate")))
        if e.get("certificate") and e.get("U") is not None:
            qs = w.el(m, "measuringEquipmentQuantities")
            q = w.el(qs, "measuringEquipmentQuantity")
            w.text(q, "name", f"calibration uncertainty ({e['distribution']}, k = {e['k']:g})"
                   if e["distribution"] == "normal" else
                   f"calibration uncertainty ({e['distribution']}, half-width)")
            w.real(q, decimal(e["U"]), e["U_unit"] or "", where=f"equipment {e['id']}")


def _conditions(w: Writer, parent: ET.Element, ctx: Mapping[str, Any]) -> None:
    ic = w.el(parent, "influenceConditions")
    for cid, name, q in influence_conditions(ctx["data"]):
        c = w.el(ic, "influenceCondition", id=cid)
        w.text(c, "name", name)
        qe = w.quantity(w.el(c, "data"), name)
        w.real(qe, decimal(q["value"]), q["unit"], where=f"influence condition {name}")


def _budget(w: Writer, parent: ET.Element, r: Mapping[str, Any]) -> None:
    b = r["budget"]
    where = f"budget of {r['item']} {r['key']}"
    lst = w.el(parent, "list", refType=REF_BUDGET)
    what = r["symbol"] or r["key"]
    if b["measurand"] and b["measurand"] not in (r["symbol"], r["key"]):
        what = f"{what} ({b['measurand']})"
    w.text(lst, "name", f"uncertainty budget of {what}")
    unit = "" if b["unit"] in ("", "1") else f" {b['unit']}"
    w.text(lst, "description", f"coverage: {b['coverage']}; U = {b['U_text']}{unit}")
    for row in b["rows"]:
        comp = w.el(lst, "list")
        w.text(comp, "name", f"{row['symbol']}: {row['source']}")
        if row["note"]:
            w.text(comp, "description", row["note"])
        w.no_quantity(comp, "type of evaluation", row["type"])
        w.no_quantity(comp, "distribution", row["distribution"])
        for label, key, unit in (("value", "value", row["value_unit"]),
                                 ("divisor", "divisor", ""),
                                 ("standard uncertainty", "standard_uncertainty",
                                  row["value_unit"]),
                                 ("sensitivity coefficient", "sensitivity",
                                  row["sensitivity_unit"]),
                                 ("contribution", "contribution", b["unit"])):
            if row[key] is not None:
                w.real(w.quantity(comp, label), decimal(row[key]), unit, where=where)
        if row["dof"] is None:
            w.no_quantity(comp, "degrees of freedom", "∞")
        else:
            w.real(w.quantity(comp, "degrees of freedom"), decimal(row["dof"]), "", where=where)
    for label, key, unit in (("combined standard uncertainty", "u_c", b["unit"]),
                             ("effective degrees of freedom", "nu_eff", ""),
                             ("coverage factor", "k", ""),
                             ("expanded uncertainty (unrounded)", "U", b["unit"])):
        if b[key] is not None:
            w.real(w.quantity(lst, label), decimal(b[key]), unit, where=where)


def _result(w: Writer, parent: ET.Element, r: Mapping[str, Any], rid: str) -> None:
    res = w.el(parent, "result", id=rid)
    w.text(res, "name", f"{r['quantity']} {r['symbol']}".strip())
    ref = f"clause {r['clause']}" + (f", {r['equation']}" if r["equation"] else "")
    said = [ref] + [x for x in (r["note"], r["earth_rate"] and
                                f"earth rate: {r['earth_rate']}") if x]
    w.text(res, "description", join("; ", said))  # a note stays translatable
    d = w.el(res, "data")
    where = f"{r['item']} {r['key']}"
    if not r["reportable"]:
        w.no_quantity(d, r["key"], r["reason"] or "not reportable")
    else:
        q = w.quantity(d, r["key"])
        w.real(q, _value_text(r), r["unit"], where=where, label=r["key"], U=_u_text(r),
               k=r["k"], p=r["p"], u=r["u"] if r["U"] is None else None)
    if r["budget"] is not None:
        _budget(w, d, r)


def matrices(results: list[Mapping[str, Any]]) -> list[tuple[str, list[int]]]:
    """The 3×3 matrices among one item's results: (name, indexes row by row) for each base name
    (``K_g`` from ``K_gxx`` … ``K_gzz``) whose nine elements are all there, reportable, with U
    and in one unit."""
    found: dict[str, dict[tuple[str, str], int]] = {}
    for i, r in enumerate(results):
        m = _MATRIX_KEY.match(r["key"])
        if m:
            found.setdefault(m["base"], {})[(m["row"], m["col"])] = i
    out = []
    for base, cells in found.items():
        idx = [cells.get((a, b)) for a in _AXES for b in _AXES]
        if any(i is None for i in idx):
            continue
        rows = [results[i] for i in idx]
        if all(x["reportable"] and x["U"] is not None for x in rows) and \
                len({x["unit"] for x in rows}) == 1:
            out.append((base.rstrip("_"), [int(i) for i in idx]))
    return out


def _matrix(w: Writer, parent: ET.Element, name: str, rows: list[Mapping[str, Any]],
            n: int) -> None:
    res = w.el(parent, "result", id=ncname("matrix", rows[0]["item"], name, n),
               refType=REF_MATRIX)
    w.text(res, "name", f"{name} matrix (3×3, row by row: rows x, y, z; columns x, y, z)")
    w.text(res, "description", "the same values as the results "
           + ", ".join(x["key"] for x in rows))
    q = w.quantity(w.el(res, "data"), name)
    w.real_list(q, [x["key"] for x in rows], [_value_text(x) for x in rows], rows[0]["unit"],
                [_u_text(x) or "" for x in rows], [x["k"] for x in rows],
                [x["p"] for x in rows], where=f"{rows[0]['item']} {name}")


def _table(w: Writer, parent: ET.Element, o: Mapping[str, Any], t: Mapping[str, Any],
           n: int) -> None:
    """One of the item's tables (records the report prints): one text per row."""
    res = w.el(parent, "result", id=ncname("table", o["number"], o["item"], n),
               refType=REF_TABLE)
    w.text(res, "name", t["title"] or t["name"])
    d = w.el(res, "data")
    header = [str(h) for h in t["header"]]
    if not t["rows"]:
        w.text(d, "text", "no rows")
    for i, row in enumerate(t["rows"], start=1):
        cells = "; ".join(f"{h}: {c}" if h else str(c) for h, c in zip(header, row))
        w.no_quantity(d, f"row {i}", cells)


def _outcome(w: Writer, parent: ET.Element, o: Mapping[str, Any],
             results: list[tuple[Mapping[str, Any], str]]) -> None:
    mr = w.el(parent, "measurementResult", id=ncname("item", o["number"], o["item"]))
    w.text(mr, "name", f"{o['item']} {o['title']}")
    said = [f"segments: {o['segments_text']}", *o.get("warnings", [])]
    w.text(mr, "description", join("; ", said))
    um = w.el(w.el(mr, "usedMethods"), "usedMethod")
    w.text(um, "name", f"{o['designation']} {o['item']}")
    w.el(um, "norm", " ".join(str(o["designation"]).split()))
    w.el(um, "reference", f"clause {o['clause']}")
    rl = w.el(mr, "results")
    for r, rid in results:
        _result(w, rl, r, rid)
    for n, (name, idx) in enumerate(matrices([r for r, _ in results])):
        _matrix(w, rl, name, [results[i][0] for i in idx], n)
    for n, t in enumerate(o.get("tables", [])):
        _table(w, rl, o, t, n)
    if not len(rl):
        res = w.el(rl, "result", id=ncname("record", o["number"], o["item"]))
        w.text(res, "name", o["title"])
        w.text(w.el(res, "data"), "text", "this item states no quantity")
    meta = w.el(mr, "measurementMetaData")
    md = w.el(meta, "metaData", refType=REF_ITEM)
    w.text(md, "name", "item")
    w.text(md, "declaration", o["item"])


def measurement_results(w: Writer, root: ET.Element, ctx: Mapping[str, Any]) -> None:
    """``dcc:measurementResults`` of the report context ``ctx`` under ``root``."""
    data = ctx["data"]
    mrs = w.el(root, "measurementResults")
    _methods(w, mrs, ctx)
    _software(w, mrs, ctx)
    _equipment(w, mrs, ctx)
    _conditions(w, mrs, ctx)
    pairs = list(zip(data["results"], result_ids(data)))
    if not ctx["outcomes"]:
        raise DccError("the report has no results; a DCC needs at least one")
    start = 0
    for o in ctx["outcomes"]:
        n = sum(1 for _ in o["results"])
        mine = pairs[start:start + n]
        start += n
        if any(r["item"] != o["item"] for r, _ in mine):
            raise DccError(f"the report's machine values do not match item {o['item']}'s "
                           "results; write the report again from the run")
        _outcome(w, mrs, o, mine)

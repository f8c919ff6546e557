"""Importing a piece of equipment's Digital Calibration Certificate (PTB DCC 3.3.0).

``metro lab equipment import CERT.xml --role ROLE`` reads the XML certificate a calibration
provider issued for one of the lab's instruments (docs/dcc.md, "Importing an equipment DCC"):

1. the file is read (at most :data:`MAX_BYTES`), parsed with entities and external resources
   forbidden, and must have the root ``dcc:digitalCalibrationCertificate`` with
   ``schemaVersion="3.3.0"``;
2. it is validated against the DCC 3.3.0 / D-SI 2.2.1 schemas (:func:`schema_folder`), offline;
3. the item (manufacturer, model, serial, the lab's own id), the certificate's identifier and
   issuer (``calibrationLaboratory``), the calibration date (``endPerformanceDate``), the due date
   (a ``basic_recalibration`` statement) and every ``si:real`` result are read
   (:func:`read_dcc`);
4. the result the equipment's role uses as a type B input is chosen: the one named by
   ``--result``, else the only one whose unit is of a kind the role accepts
   (:data:`metro.core.base.vocabulary.ROLE_CALIBRATION`); its ``si:expandedMU`` gives U, k and the
   coverage probability, and its D-SI unit the metro unit
   (:func:`metro.core.base.dsi.metro_unit`) (:func:`plan_import`);
5. the equipment is written to the lab's equipment store with its provenance
   (:mod:`metro.core.record.equipment_store`), never into ``lab.toml`` (:func:`import_dcc`).

Every refusal is a :class:`~metro.core.base.errors.DataError` naming the file, the element path
(``/dcc:digitalCalibrationCertificate/dcc:measurementResults/…/si:unit``) and the reason; it
comes before anything is written, so a refused certificate imports nothing.
"""

from __future__ import annotations

import datetime as dt
import hashlib
import io
import math
import os
import re
from pathlib import Path
from typing import Any
from xml.etree.ElementTree import Element

import attrs

from ..base import vocabulary as voc
from ..base.errors import DataError, MetroError

__all__ = ["DCC_NS", "SI_NS", "SCHEMA_VERSION", "MAX_BYTES", "ENV_SCHEMA", "schema_folder",
           "DccResult", "EquipmentDcc", "ImportPlan", "read_dcc", "plan_import", "import_dcc"]

DCC_NS = "https://ptb.de/dcc"
SI_NS = "https://ptb.de/si"
SCHEMA_VERSION = "3.3.0"
#: a certificate larger than this is refused before it is parsed (an embedded PDF included)
MAX_BYTES = 64 * 1024 * 1024
#: the folder of the XSDs, when neither the package's nor the source tree's copy is to be used
ENV_SCHEMA = "METRO_DCC_SCHEMA"
ROOT = "/dcc:digitalCalibrationCertificate"
_PREFIX = {DCC_NS: "dcc", SI_NS: "si", "http://www.w3.org/2000/09/xmldsig#": "ds"}
_ITEM = f"{ROOT}/dcc:administrativeData/dcc:items/dcc:item"
#: a field of the imported equipment → the element of the certificate it is read from
_FROM = {
    "equipment.id": f"{_ITEM}/dcc:identifications",
    "equipment.manufacturer": f"{_ITEM}/dcc:manufacturer/dcc:name",
    "equipment.model": f"{_ITEM}/dcc:model",
    "equipment.serial": f"{_ITEM}/dcc:identifications",
    "equipment.calibration.certificate": f"{ROOT}/dcc:administrativeData/dcc:coreData/"
                                         "dcc:uniqueIdentifier",
    "equipment.calibration.lab": f"{ROOT}/dcc:administrativeData/dcc:calibrationLaboratory/"
                                 "dcc:contact/dcc:name",
}
#: the refType token of the statement whose date is the recommended recalibration (due) date
DUE_REFTYPE = "basic_recalibration"


# ------------------------------------------------------------------------------ the schema


def schema_folder() -> Path:
    """The folder holding dcc.xsd 3.3.0 and the schemas it imports: ``METRO_DCC_SCHEMA`` if set,
    else the copy shipped in the package (:data:`metro.core.documents.dcc.SCHEMA_DIR`), else the
    source tree's reference copy (``../shared/reference/dcc`` beside the checkout)."""
    from ..documents.dcc.schema import SCHEMA_DIR

    env = os.environ.get(ENV_SCHEMA)
    folders = ([Path(env)] if env else []) + [
        SCHEMA_DIR, Path(__file__).resolve().parents[3] / "shared" / "reference" / "dcc"]
    for folder in folders:
        if (folder / "dcc.xsd").is_file():
            return folder
    raise MetroError("the DCC 3.3.0 schema (dcc.xsd) is not installed; a certificate cannot be "
                     "checked, so it is not imported",
                     hint=f"set {ENV_SCHEMA} to a folder holding dcc.xsd, SI_Format.xsd, "
                     "quantitykind.xsd and xmldsig-core-schema.xsd")


def _schema() -> Any:
    """The DCC schema from :func:`schema_folder` (built once per folder)."""
    from ..documents.dcc.schema import schema

    return schema(str(schema_folder()))


# ------------------------------------------------------------------------------ reading


@attrs.frozen
class DccResult:
    """One ``si:real`` of the certificate's ``measurementResults``, as written there."""

    #: element path of the ``si:real``
    path: str
    #: the ``dcc:result``'s name (English if given) and ``id``, the quantity's name and label
    name: str
    ident: str
    quantity: str
    label: str
    value: float
    unit_dsi: str
    #: the expanded uncertainty, its coverage factor and probability; ``None`` when not stated
    U: float | None
    k: float | None
    p: float | None
    #: the element path of the uncertainty, and why none is usable when ``U`` is ``None``
    u_path: str
    missing: str = ""
    distribution: str = ""

    def names(self) -> set[str]:
        """What ``--result`` may name it by: the result's id and name, the quantity's name and
        label."""
        return {n for n in (self.ident, self.name, self.quantity, self.label) if n}


@attrs.frozen
class EquipmentDcc:
    """What metro reads from an equipment's DCC."""

    source: str
    sha256: str
    unique_identifier: str
    issuer: str
    calibration_date: dt.date
    begin_date: dt.date
    issue_date: dt.date | None
    due: dt.date | None
    due_path: str
    item_name: str
    manufacturer: str
    model: str
    serial: str
    #: the item's identification issued by the customer or owner (the lab's own id), or ""
    lab_id: str
    results: tuple[DccResult, ...]


class _Tree:
    """A parsed certificate with element paths in the schema validator's notation."""

    def __init__(self, root: Element, src: str) -> None:
        self.root = root
        self.src = src
        self.parent = {c: p for p in root.iter() for c in p}

    def path(self, e: Element) -> str:
        parts = []
        while e is not None:
            p = self.parent.get(e)
            step = _qname(e.tag)
            if p is not None:
                same = [c for c in p if c.tag == e.tag]
                if len(same) > 1:
                    step += f"[{same.index(e) + 1}]"
            parts.append(step)
            e = p
        return "/" + "/".join(reversed(parts))

    def error(self, e: Element | str, reason: str, hint: str | None = None) -> DataError:
        return DataError(self.src, e if isinstance(e, str) else self.path(e), reason, hint=hint)


def _qname(tag: str) -> str:
    if tag.startswith("{"):
        ns, local = tag[1:].split("}", 1)
        return f"{_PREFIX[ns]}:{local}" if ns in _PREFIX else tag
    return tag


def _q(path: str) -> str:
    """``dcc:a/si:b`` → the ElementTree path with namespaces."""
    return "/".join(re.sub(r"^(dcc|si):", lambda m: "{" + (DCC_NS if m.group(1) == "dcc"
                                                           else SI_NS) + "}", step)
                    for step in path.split("/"))


def _text(e: Element | None) -> str:
    return "" if e is None else " ".join((e.text or "").split())


def _content(e: Element | None) -> str:
    """The text of a ``dcc:textType`` element: its English ``dcc:content``, else the first."""
    if e is None:
        return ""
    contents = e.findall(_q("dcc:content"))
    en = [c for c in contents if c.get("lang", "").lower().startswith("en")]
    return _text((en or contents or [None])[0])


def _read_bytes(path: Path) -> bytes:
    src = str(path)
    if not path.is_file():
        raise DataError(src, None, "certificate not found" if not path.exists() else
                        "not a file")
    try:
        size = path.stat().st_size
        if size > MAX_BYTES:
            raise DataError(src, None, f"{size} bytes is too large for a DCC (at most "
                            f"{MAX_BYTES} bytes)")
        return path.read_bytes()
    except OSError as exc:
        raise DataError(src, None, f"cannot read the certificate: {exc.strerror or exc}") from exc


def _parse(raw: bytes, src: str) -> Any:
    """The parsed document (an ``xmlschema.XMLResource``): entities, DTDs and remote resources
    are refused."""
    _schema()  # a missing schema is said before the file is judged
    import xmlschema
    from xmlschema.exceptions import XMLResourceError, XMLResourceForbidden

    try:
        return xmlschema.XMLResource(io.BytesIO(raw), defuse="always", allow="none")
    except XMLResourceForbidden as exc:
        raise DataError(src, None, f"not accepted: {exc}",
                        hint="a DCC has no DTD or entity declarations") from exc
    except (XMLResourceError, SyntaxError) as exc:
        raise DataError(src, None, f"not XML: {exc}",
                        hint="give the certificate's .xml file (a DCC 3.3.0)") from exc


def _check_root(root: Element, src: str) -> None:
    if root.tag != f"{{{DCC_NS}}}digitalCalibrationCertificate":
        raise DataError(src, "/" + _qname(root.tag),
                        "not a DCC: the root element must be dcc:digitalCalibrationCertificate "
                        f"(namespace {DCC_NS})")
    version = root.get("schemaVersion")
    if version != SCHEMA_VERSION:
        raise DataError(src, f"{ROOT}/@schemaVersion",
                        f"schema version {version!r}; metro reads DCC {SCHEMA_VERSION}",
                        hint="ask the calibration provider for the certificate in DCC 3.3.0")


def _validate(resource: Any, src: str) -> None:
    errors = list(_schema().iter_errors(resource))
    if errors:
        first = errors[0]
        more = f" ({len(errors)} schema errors; the first)" if len(errors) > 1 else ""
        raise DataError(src, first.path or ROOT,
                        f"fails the DCC {SCHEMA_VERSION} schema{more}: {first.reason}")


def read_dcc(path: str | os.PathLike[str]) -> EquipmentDcc:
    """Read, check and validate an equipment's DCC; a :class:`DataError` names the file, the
    element path and the reason for anything metro cannot take from it."""
    p = Path(path)
    src = str(p)
    raw = _read_bytes(p)
    resource = _parse(raw, src)
    _check_root(resource.root, src)
    _validate(resource, src)
    t = _Tree(resource.root, src)
    adm = t.root.find(_q("dcc:administrativeData"))
    core = adm.find(_q("dcc:coreData"))
    items = adm.findall(_q("dcc:items/dcc:item"))
    if len(items) != 1:
        raise t.error(adm.find(_q("dcc:items")),
                      f"{len(items)} items; metro imports the certificate of one piece of "
                      "equipment")
    item = items[0]
    ids = [(_text(i.find(_q("dcc:issuer"))), _text(i.find(_q("dcc:value"))))
           for i in item.findall(_q("dcc:identifications/dcc:identification"))]
    manufacturer = (_content(item.find(_q("dcc:manufacturer/dcc:name")))
                    or _content(adm.find(_q("dcc:items/dcc:manufacturer/dcc:name"))))
    due, due_path = _due(t, adm)
    results = tuple(_results(t))
    if not results:
        raise t.error(f"{ROOT}/dcc:measurementResults",
                      "no result metro can read: no dcc:result has an si:real quantity in its "
                      "dcc:data")
    return EquipmentDcc(
        source=src, sha256=hashlib.sha256(raw).hexdigest(),
        unique_identifier=_text(core.find(_q("dcc:uniqueIdentifier"))),
        issuer=_content(adm.find(_q("dcc:calibrationLaboratory/dcc:contact/dcc:name"))),
        calibration_date=_date(t, core.find(_q("dcc:endPerformanceDate"))),
        begin_date=_date(t, core.find(_q("dcc:beginPerformanceDate"))),
        issue_date=_date(t, core.find(_q("dcc:issueDate"))),
        due=due, due_path=due_path, item_name=_content(item.find(_q("dcc:name"))),
        manufacturer=manufacturer, model=_text(item.find(_q("dcc:model"))),
        serial=next((v for who, v in ids if who == "manufacturer"), ""),
        lab_id=next((v for who, v in ids if who in ("customer", "owner")), ""),
        results=results,
    )


def _date(t: _Tree, e: Element | None) -> Any:
    if e is None:
        return None
    try:
        return dt.date.fromisoformat(_text(e)[:10])
    except ValueError as exc:
        raise t.error(e, f"not a date: {_text(e)!r}") from exc


def _due(t: _Tree, adm: Element) -> tuple[dt.date | None, str]:
    """The recommended recalibration date: the ``dcc:date`` of the first statement whose
    ``refType`` holds :data:`DUE_REFTYPE`."""
    for s in adm.findall(_q("dcc:statements/dcc:statement")):
        if DUE_REFTYPE in (s.get("refType") or "").split():
            d = s.find(_q("dcc:date"))
            if d is None:
                raise t.error(s, f"the {DUE_REFTYPE} statement has no dcc:date")
            return _date(t, d), t.path(d)
    return None, ""


def _number(t: _Tree, e: Element) -> float:
    try:
        x = float(_text(e))
    except ValueError as exc:
        raise t.error(e, f"not a number: {_text(e)!r}") from exc
    if not math.isfinite(x):
        raise t.error(e, f"{_text(e)} is not a value")
    return x


def _results(t: _Tree):
    """Every ``si:real`` that is a quantity of a result's data
    (``dcc:measurementResult/dcc:results/dcc:result/dcc:data/dcc:quantity/si:real``); quantities
    nested in a ``dcc:list`` (a table, a budget's components) are not results of their own."""
    for res in t.root.iterfind(_q("dcc:measurementResults/dcc:measurementResult/dcc:results/"
                                  "dcc:result")):
        name = _content(res.find(_q("dcc:name")))
        for quantity in res.iterfind(_q("dcc:data/dcc:quantity")):
            real = quantity.find(_q("si:real"))
            if real is not None:
                yield _result(t, res, name, real, _content(quantity.find(_q("dcc:name"))))


def _result(t: _Tree, res: Element, name: str, real: Element, quantity: str) -> DccResult:
    value_el = real.find(_q("si:value"))
    value = float(_text(value_el))  # the schema's decimal pattern: a number or NaN
    mu = real.find(_q("si:measurementUncertaintyUnivariate"))
    exp = None if mu is None else mu.find(_q("si:expandedMU"))
    values = ("si:valueExpandedMU", "si:coverageFactor", "si:coverageProbability")
    if exp is None and real.find(_q("si:expandedUnc")) is not None:  # deprecated, still read
        exp = real.find(_q("si:expandedUnc"))
        values = ("si:uncertainty", "si:coverageFactor", "si:coverageProbability")
    base = dict(path=t.path(real), name=name, ident=res.get("id") or "", quantity=quantity,
                label=_text(real.find(_q("si:label"))), value=value,
                unit_dsi=_text(real.find(_q("si:unit"))))
    if exp is None:
        why = ("states a standard uncertainty only (si:standardMU)" if mu is not None
               and mu.find(_q("si:standardMU")) is not None else
               "states a coverage interval, not an expanded uncertainty" if mu is not None
               else "states no uncertainty")
        return DccResult(**base, U=None, k=None, p=None, u_path=t.path(real), missing=why)
    U, k, p = (exp.find(_q(v)) for v in values)
    return DccResult(**base, U=float(_text(U)), k=float(_text(k)), p=float(_text(p)),
                     u_path=t.path(exp), distribution=_text(exp.find(_q("si:distribution"))))


# ------------------------------------------------------------------------------ choosing


@attrs.frozen
class ImportPlan:
    """What an import writes: the ``[equipment]`` table, the ``[dcc]`` provenance table, the
    equipment as a run reads it, and the warnings to print."""

    equipment: dict[str, Any]
    provenance: dict[str, Any]
    read: Any
    warnings: tuple[str, ...] = ()


def _kind_ok(q: Any, kinds: tuple[str, ...]) -> bool:
    """Whether ``q`` is of one of the kinds ``kinds`` ("" a ratio); an angle (″, rad) is not a
    ratio here, though pint counts both dimensionless."""
    from ..base.units import Q_, angle_power

    if not kinds:
        return True
    power = angle_power(q.units)
    return any(q.dimensionless and power == 0 if k == "" else
               q.dimensionality == Q_(1.0, k).dimensionality and power == angle_power(k)
               for k in kinds)


def _quantity(dcc: EquipmentDcc, r: DccResult, magnitude: float) -> Any:
    """``magnitude`` in the metro unit of ``r``'s D-SI unit (an offset unit as its difference:
    an uncertainty in °C is one in K)."""
    from ..base.dsi import metro_unit
    from ..base.errors import UnitError
    from ..base.units import Q_, difference_unit, unit

    try:
        text = metro_unit(r.unit_dsi)
        return Q_(magnitude, difference_unit(unit(text)))
    except UnitError as exc:
        raise DataError(dcc.source, f"{r.path}/si:unit",
                        f"unknown D-SI unit {r.unit_dsi}: {getattr(exc, 'detail', exc)}",
                        hint="docs/dcc.md lists the D-SI units metro reads") from exc


def _choose(dcc: EquipmentDcc, role: str, select: str | None) -> DccResult:
    kinds = voc.ROLE_CALIBRATION.get(role, ())
    if select:
        found = [r for r in dcc.results if select in r.names()]
        if len(found) != 1:
            given = "; ".join(" / ".join(sorted(r.names())) for r in dcc.results)
            raise DataError(dcc.source, f"{ROOT}/dcc:measurementResults",
                            f"{'no' if not found else len(found)} result(s) named {select!r}",
                            hint=f"the results (id / name / label): {given}")
        chosen = found[0]
        if not _kind_ok(_quantity(dcc, chosen, 1.0), kinds):
            raise _wrong_kind(dcc, chosen, role, kinds)
        return chosen
    fits = [r for r in dcc.results if _kind_ok(_quantity(dcc, r, 1.0), kinds)]
    if len(fits) == 1:
        return fits[0]
    if not fits:
        raise _wrong_kind(dcc, dcc.results[0], role, kinds)
    raise DataError(dcc.source, f"{ROOT}/dcc:measurementResults",
                    f"{len(fits)} results have a unit a {role} can use; metro does not guess "
                    "which one the equipment's calibration is",
                    hint="name one with --result: " + "; ".join(
                        r.ident or r.label or r.name for r in fits))


def _wrong_kind(dcc: EquipmentDcc, r: DccResult, role: str, kinds: tuple[str, ...]) -> DataError:
    accepted = " or ".join("relative (D-SI \\one, \\percent, \\ppm)" if k == "" else
                           f"in {k} or a unit of that kind" for k in kinds)
    return DataError(dcc.source, f"{r.path}/si:unit",
                     f"the unit {r.unit_dsi} is of another kind than a {role}'s calibration "
                     f"uses: its U must be {accepted}",
                     hint="--result names the result that states it; --role gives the "
                     "equipment's role")


def _check_uncertainty(dcc: EquipmentDcc, r: DccResult, role: str) -> None:
    """The chosen result states U with k (an expanded uncertainty, numbers, U ≥ 0)."""
    if r.U is None:
        raise DataError(dcc.source, r.u_path,
                        f"no expanded uncertainty for the value the {role} needs: the result "
                        f"{r.missing}",
                        hint="metro needs si:measurementUncertaintyUnivariate/si:expandedMU "
                        "with its coverage factor")
    for what, x in (("value", r.value), ("expanded uncertainty", r.U), ("coverage factor", r.k),
                    ("coverage probability", r.p)):
        if not math.isfinite(x):
            raise DataError(dcc.source, r.path if what == "value" else r.u_path,
                            f"the {what} is {x}, not a number")
    if r.U < 0 or r.k <= 0:
        raise DataError(dcc.source, r.u_path, f"U = {r.U} with k = {r.k}: an expanded "
                        "uncertainty is ≥ 0 and its coverage factor > 0")


def _validity(dcc: EquipmentDcc, today: dt.date, allow_expired: bool) -> list[str]:
    """Nothing when the certificate is not past its due date on ``today``; past it, a refusal,
    or with ``allow_expired`` a warning."""
    if dcc.due is None or dcc.due >= today:
        return []
    if not allow_expired:
        raise DataError(dcc.source, dcc.due_path,
                        f"the calibration was due on {dcc.due.isoformat()}: expired "
                        f"(today is {today.isoformat()})",
                        hint="import the current certificate; --allow-expired imports it "
                        "anyway (a run then refuses it unless --allow-expired)")
    return [f"{dcc.source}: the calibration was due on {dcc.due.isoformat()} (expired); "
            "imported because of --allow-expired"]


def plan_import(dcc: EquipmentDcc, *, role: str, eid: str | None = None,
                select: str | None = None, today: dt.date | None = None,
                allow_expired: bool = False) -> ImportPlan:
    """The equipment and provenance an import of ``dcc`` as ``role`` writes, checked: the result
    (:func:`_choose`), its expanded uncertainty, its unit's kind, the validity on ``today``."""
    from ..run.manifest import equipment_from_table
    from ..run.manifest_writer import quantity_text

    role = voc.canonical_role(role)
    if role not in voc.ROLES:
        near = voc.did_you_mean(role, voc.ROLES)
        raise MetroError(f"unknown equipment role {role!r}",
                         hint=f"did you mean {near!r}?" if near else
                         "roles: " + ", ".join(sorted(voc.ROLES)))
    eid = eid or dcc.lab_id
    if not eid:
        raise DataError(dcc.source, f"{_ITEM}/dcc:identifications",
                        "no identification issued by the customer or owner (the lab's own id)",
                        hint="give the equipment's id with --id")
    r = _choose(dcc, role, select)
    _check_uncertainty(dcc, r, role)
    warnings = _validity(dcc, today or dt.date.today(), allow_expired)
    table = {"id": eid, "role": role}
    table |= {k: v for k, v in (("manufacturer", dcc.manufacturer), ("model", dcc.model),
                                ("serial", dcc.serial)) if v}
    cal = {"certificate": dcc.unique_identifier, "U": quantity_text(_quantity(dcc, r, r.U)),
           "k": r.k, "lab": dcc.issuer, "distribution": "normal"}
    table["calibration"] = cal | ({"due": dcc.due} if dcc.due else {})
    try:
        read = equipment_from_table(table, dcc.source, "equipment")
    except DataError as exc:  # said of the element the text came from
        field = "--id" if exc.field == "equipment.id" and eid != dcc.lab_id else exc.field
        raise DataError(dcc.source, _FROM.get(field or "", field), exc.detail,
                        hint=exc.hint) from exc
    provenance = {
        "file": Path(dcc.source).name, "sha256": dcc.sha256, "issuer": dcc.issuer,
        "unique_identifier": dcc.unique_identifier,
        "calibration_date": dcc.calibration_date, "result": r.path,
        "result_name": r.name or r.label or r.ident, "value": r.value, "unit": r.unit_dsi,
        "U": r.U, "k": r.k, "coverage_probability": r.p,
        "imported": dt.datetime.now(dt.timezone.utc).replace(microsecond=0),
    }
    if dcc.issue_date:
        provenance["issue_date"] = dcc.issue_date
    return ImportPlan(table, provenance, read, tuple(warnings))


# ------------------------------------------------------------------------------ importing


def import_dcc(path: str | os.PathLike[str], lab_path: str | os.PathLike[str], *, role: str,
               eid: str | None = None, select: str | None = None, replace: bool = False,
               allow_expired: bool = False, dry_run: bool = False,
               today: dt.date | None = None) -> tuple[ImportPlan, Path]:
    """Import the DCC at ``path`` into the equipment store of the lab profile ``lab_path``:
    checked completely first (:func:`read_dcc`, :func:`plan_import`, the id unique among the
    profile's and the imported equipment), then written; ``dry_run`` writes nothing. Returns the
    plan and the file written (or that would be)."""
    from . import equipment_store as store
    from .lab import load_lab

    profile = load_lab(lab_path)
    dcc = read_dcc(path)
    plan = plan_import(dcc, role=role, eid=eid, select=select, today=today,
                       allow_expired=allow_expired)
    eid = plan.equipment["id"]
    imported = store.stored_ids(lab_path)
    if eid in profile.equipment_by_id() and eid not in imported:
        raise MetroError(f"duplicate equipment id {eid!r}: the lab profile {lab_path} lists it; an "
                         "import never edits the profile",
                         hint="give the imported equipment another id with --id, or remove the "
                         "entry from the profile first")
    if eid in imported and not replace:
        raise MetroError(f"duplicate equipment id {eid!r}: imported already ({imported[eid]})",
                         hint="--replace replaces that import (a new certificate of the same "
                         "equipment); --id gives this one another id")
    target = store.entry_path(lab_path, eid)
    if dry_run:
        return plan, target
    text = store.entry_text(plan.equipment, plan.provenance)
    raw = Path(path).read_bytes()
    if hashlib.sha256(raw).hexdigest() != dcc.sha256:
        raise DataError(str(path), None, "the file changed while it was being imported")
    return plan, store.write_entry(lab_path, eid, text, raw, replace=replace)

"""A :class:`~metro.core.model.provenance.RunRecord` as a report context: a plain dict of
strings, lists and dicts that a document layout (:mod:`metro.core.documents.document`) or a
docxtpl template prints as it is.

Every number is already formatted (results as :meth:`Result.reported` rounds them, budget figures
with four significant digits, units as :func:`~metro.core.base.units.fmt_unit` prints them); who,
where and when are in ``facts`` (:func:`record_facts`).  :func:`report_context` makes the context,
:func:`build_context` adds the plugins' additions and the register statement;
:mod:`metro.core.documents.report` writes it.

Dict keys are chosen not to clash with ``dict`` methods (Jinja looks attributes up first,
so a key called ``items`` or ``values`` would be shadowed in ``{{ x.items }}``).
"""

from __future__ import annotations

import datetime as dt
import re
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Iterable, Mapping

from ..base.formatting import (DASH, fmt_divisor, fmt_dof, fmt_num, fmt_quantity, or_dash,
                               pretty_powers, unit_text, with_unit)
from ..base.locale import Text, join, msg
from .text import plain_symbol, quantity_name

if TYPE_CHECKING:  # pragma: no cover
    from ..model.campaign import Equipment
    from ..model.provenance import RunRecord
    from ..model.results import Outcome, Result, TableSpec
    from ..uncertainty.budget import UncertaintyBudget

__all__ = [
    "SIMULATED_BANNER",
    "report_context",
    "build_context",
    "record_facts",
    "result_row",
    "budget_title",
    "plot_caption",
    "sanitize",
]

SIMULATED_BANNER = (
    "SIMULATED — Results from the built-in simulated test station — "
    "not a measurement of a real device."
)


def _pretty_context(obj: Any) -> Any:
    """:func:`pretty_powers` on every string of a report context (dicts, lists, tuples); other
    objects (plot specs, images) are kept as they are."""
    if isinstance(obj, Text):
        return obj.map(pretty_powers)
    if isinstance(obj, str):
        return pretty_powers(obj)
    if isinstance(obj, dict):
        return {k: _pretty_context(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [_pretty_context(v) for v in obj]
    if isinstance(obj, tuple):
        return tuple(_pretty_context(v) for v in obj)
    return obj


def _label(key: str) -> str:
    """``latitude_uncertainty`` -> ``Latitude uncertainty``."""
    s = str(key).replace("_", " ").strip()
    return s[:1].upper() + s[1:] if s else s


def _name_values(m: Mapping[str, Any], *, relabel: bool = True) -> list[dict[str, str]]:
    return [
        {"name": _label(k) if relabel else str(k), "value": fmt_quantity(v)} for k, v in m.items()
    ]


def _date_text(d: dt.datetime | dt.date) -> str:
    if isinstance(d, dt.datetime):
        text = d.strftime("%Y-%m-%d %H:%M")
        if d.tzinfo is not None:
            off = d.utcoffset()
            text += " UTC" if off == dt.timedelta(0) else d.strftime(" %z")
        return text
    return d.isoformat()


# --------------------------------------------------------------------------------------
# Sections
# --------------------------------------------------------------------------------------


def _equipment_row(e: "Equipment", on: dt.date) -> dict[str, Any]:
    cal = e.calibration
    status = e.status(on)
    if cal is not None:
        prefix = f"certificate {cal.certificate}, "
        if status.startswith(prefix):
            status = status[len(prefix) :]
        if cal.due is not None:  # the same words as Calibration.status, as a message
            status = (
                msg("EXPIRED on {date}", date=cal.due.isoformat())
                if cal.due < on
                else msg("valid until {date}", date=cal.due.isoformat())
            )
        elif status == "no due date stated":
            status = msg("no due date stated")
        if cal.distribution == "normal":
            U = f"{fmt_quantity(cal.uncertainty)} (k = {fmt_num(cal.k, 3)})"
        else:
            U = msg(
                "{U} ({distribution}, half-width)",
                U=fmt_quantity(cal.uncertainty),
                distribution=cal.distribution,
            )
        expired = not cal.is_valid(on)
        relative = (
            not unit_text(getattr(cal.uncertainty, "units", ""))
            if hasattr(cal.uncertainty, "units")
            else True
        )
    else:
        U = DASH
        expired = False
        relative = False
    certificate = DASH if cal is None else cal.certificate + (f" ({cal.lab})" if cal.lab else "")
    return {
        "id": e.id,
        "description": e.describe(),
        "role": or_dash(e.role),
        "certificate": certificate,
        "U": U,
        "U_relative": relative,
        "due": DASH if cal is None or cal.due is None else cal.due.isoformat(),
        "status": status,
        "expired": expired,
        "valid": cal is not None and not expired,
    }


def result_row(r: "Result") -> dict[str, Any]:
    """A result as the report context shows it: value and U with their unit, k,
    the clause and equation, whether reportable and why (:meth:`Result.reported` rounds)."""
    m = r.metric
    vtext, Utext = r.reported()
    if Utext is None and r.u is not None:
        u = float(r.u.to(m.unit).magnitude)
        Utext = f"u = {fmt_num(u, 2)}"  # a standard uncertainty without a budget: say so
    reference = m.clause + (f", {m.equation}" if m.equation else "")
    unit = unit_text(m.unit)
    k_text = DASH if r.k is None else fmt_num(r.k, 3)
    mc = monte_carlo_interval(r)
    if mc is not None:  # GUM not validated (JCGM 101 clause 8): the Monte Carlo interval instead
        Utext, k_text = mc, "MC"
    return {
        "reportable": bool(getattr(r, "reportable", True)),
        "reason": getattr(r, "reason", "") or "",
        "bound": getattr(r, "bound", "") or "",
        "earth_rate": str(getattr(r, "earth_rate", "") or ""),
        "value_unit": with_unit(vtext, unit),
        "U_unit": DASH
        if Utext is None
        else (Utext if Utext.startswith("u = ") else with_unit(Utext, unit)),
        "key": m.key,
        "quantity": m.name,
        "symbol": m.symbol,
        "value": vtext,
        "U": Utext if Utext is not None else DASH,
        "unit": unit_text(m.unit) or "1",
        "k": k_text,
        "clause": m.clause,
        "equation": m.equation,
        "reference": reference or DASH,
        "note": r.note,
    } | ({} if mc is None else {  # GUM not validated: the Monte Carlo interval's p in %
        "monte_carlo_p": fmt_num(100 * r.monte_carlo.p, 4)})


def monte_carlo_interval(r: "Result", *, always: bool = False) -> str | None:
    """The Monte Carlo coverage interval of a result as the certificate prints it, ``[low, high]``
    with both ends rounded to the place of two significant digits of its half-width (JJF 1059.1
    5.3.8) — for a result whose GUM interval the check did not validate (JCGM 101 clause 8), or
    for any checked result with ``always``; else None."""
    mc = getattr(r, "monte_carlo", None)
    if mc is None or (mc.validated and not always):
        return None
    from ..uncertainty.budget import round_to, round_uncertainty

    low, high = r.monte_carlo_dict()["interval"]
    place = round_uncertainty(abs(high - low) / 2).exponent if high > low else 0
    return f"[{round_to(low, place).text}, {round_to(high, place).text}]"


def monte_carlo_note(r: "Result") -> Any:
    """The budget's Monte Carlo line (JCGM 101): u and the shortest interval beside GUM's, and
    the clause-8 verdict; ``""`` without a check."""
    mc = getattr(r, "monte_carlo", None)
    if mc is None or mc.trials == 0:  # none, or an exact budget (u_c = 0): nothing to say
        return ""
    d = r.monte_carlo_dict()
    fields = {"u": fmt_num(d["u"], 3), "p": fmt_num(100 * d["p"], 4),
              "interval": monte_carlo_interval(r, always=True),
              "unit": unit_text(r.metric.unit) or "1", "trials": f"{d['trials']:,}",
              "d_low": fmt_num(d["d_low"], 2), "d_high": fmt_num(d["d_high"], 2),
              "delta": fmt_num(d["delta"], 1)}
    if mc.validated:
        return msg("Monte Carlo (JCGM 101, {trials} trials): u = {u}, shortest {p} % coverage "
                   "interval {interval} {unit}; the GUM interval is validated (d_low = {d_low}, "
                   "d_high = {d_high} ≤ δ = {delta}, JCGM 101 clause 8).", **fields)
    return msg("Monte Carlo (JCGM 101, {trials} trials): u = {u}, shortest {p} % coverage "
               "interval {interval} {unit}; the GUM interval is not validated (d_low = {d_low}, "
               "d_high = {d_high}, δ = {delta}, JCGM 101 clause 8): the result states the "
               "Monte Carlo interval.", **fields)


def budget_title(m: Any, measurand: str) -> str:
    """A budget's title: the result's name and symbol, then its measurand in parentheses only
    when the measurand says something the name does not (``scale factor K``, not ``scale factor K
    (scale factor K)``; ``fitted zero F₀``, not ``… (fitted zero F0)``).

    >>> from types import SimpleNamespace as N
    >>> budget_title(N(name="scale-factor nonlinearity", symbol="K_n", key="K_n"),
    ...              "nonlinearity Kn")
    'scale-factor nonlinearity K_n'
    >>> budget_title(N(name="bias", symbol="B₀", key="B0"), "mean of the static record")
    'bias B₀ (mean of the static record)'
    >>> budget_title(N(name="start-up time", symbol="t_s", key="t_startup"), "t_startup")
    'start-up time t_s'
    """
    title = quantity_name({"quantity": m.name, "symbol": m.symbol, "key": m.key})
    words = set(re.split(r"[\s()\-]+", plain_symbol(title).lower()))
    said = all(
        w in words for w in re.split(r"[\s()\-]+", plain_symbol(measurand or "").lower()) if w
    )
    # a measurand that is the result's code key (dB_shock, gamma_r, t_startup) says nothing a reader
    # reads
    key = measurand in (m.key, m.symbol) or re.fullmatch(
        r"[A-Za-z]+(?:_[A-Za-z0-9]+)+", measurand or ""
    )
    return (
        title
        if not measurand or said or key
        else msg("{name} ({measurand})", name=title, measurand=measurand)
    )


def _budget_block(r: "Result", budget: "UncertaintyBudget") -> dict[str, Any]:
    d = budget.as_dict()
    unit = d["unit"] if d["unit"] != "1" else ""
    rows = []
    for row in d["rows"]:
        rows.append(
            {
                "source": msg("{source} ({note})", source=row["source"], note=row["note"])
                if row["note"]
                else row["source"],
                "source_only": row["source"],
                "note": row["note"],  # apart, for a document to number repeated notes
                "symbol": row["symbol"],
                "type": row["type"],
                "distribution": row["distribution"],
                "value": with_unit(fmt_num(row["value"]), row["value_unit"]),
                "divisor": fmt_divisor(row["divisor"]),
                "sensitivity": with_unit(fmt_num(row["sensitivity"]), row["sensitivity_unit"]),
                "contribution": fmt_num(row["contribution"]),
                "dof": fmt_dof(row["dof"]),
            }
        )
    m = r.metric
    k_text = fmt_num(d["k"], 3)
    if d["coverage"] != f"k = {d['k']:g}":  # k from t_p(ν_eff): say how it was chosen
        k_text += f" ({d['coverage'].removeprefix('k = ')})"
    return {
        "title": budget_title(m, d["measurand"]),
        "measurand": d["measurand"],
        "result": m.key,
        "unit": unit or "1",
        "relative": d["relative"],
        "rows": rows,
        "u_c": fmt_num(d["u_c"]),
        "nu_eff": fmt_dof(d["nu_eff"]),
        "k": k_text,
        "coverage": d["coverage"],
        "U": d["U_reported"],
        "U_unrounded": fmt_num(d["U"]),
        "rounding": d["rounding"],
        "note": join(" ", [x for x in (d["note"], monte_carlo_note(r)) if x])
        if monte_carlo_note(r) else d["note"],
    }


def _cell(v: Any) -> str:
    if isinstance(v, str):
        return v
    if isinstance(v, float):
        return f"{v:.6g}"
    return fmt_quantity(v, 6)


def _table_block(t: "TableSpec") -> dict[str, Any]:
    return {
        "name": t.name,
        "title": t.title,
        "header": [h if isinstance(h, str) else str(h) for h in t.header],
        "rows": [[_cell(c) for c in row] for row in t.rows],
    }


def plot_caption(title: str, item: str) -> str:
    """A figure's caption: its title and the item it belongs to, ``(item)`` added once."""
    return title if title.endswith(f"({item})") else join(" ", [title, f"({item})"])


def _outcome_block(
    o: "Outcome", number: str, designation: str, first_figure: int
) -> dict[str, Any]:
    results = list(o.results)
    plots = [
        {
            "number": first_figure + i,
            "name": p.name,
            "title": p.title,
            "caption": plot_caption(p.title, o.item),
            "spec": p,
            "image": None,
        }
        for i, p in enumerate(o.plots)
    ]
    return {
        "number": number,
        "id": o.id,
        "standard": o.standard,
        "designation": designation,
        "item": o.item,
        "title": o.title,
        "clause": o.clause,
        "segments_text": ", ".join(o.segments) or DASH,
        "options": _name_values(o.options, relabel=False),
        "options_text": "; ".join(f"{k} = {fmt_quantity(v)}" for k, v in o.options.items()),
        "results": [result_row(r) for r in results],
        "notes": [
            join(": ", [r.metric.symbol or r.metric.name, r.note]) for r in results if r.note
        ] + [
            msg("{symbol}: the GUM interval (value ± U) is not validated by Monte Carlo (JCGM 101 "
                "clause 8); U gives the Monte Carlo {p} % coverage interval (shortest) instead.",
                symbol=r.metric.symbol or r.metric.name, p=fmt_num(100 * r.monte_carlo.p, 4))
            for r in results if monte_carlo_interval(r) is not None
        ],
        "budgets": [_budget_block(r, r.budget) for r in results if r.budget is not None],
        "tables": [_table_block(t) for t in o.tables],
        "plots": plots,
        "warnings": [w if isinstance(w, str) else str(w) for w in o.warnings],
    }


def sanitize(obj: Any) -> Any:
    """Drop the characters XML 1.0 cannot hold (:data:`metro.core.base.vocabulary.NOT_XML`: C0
    controls,
    lone surrogates, U+FFFE/U+FFFF) from every string of the context.  Manifests, bench files and
    lab profiles are refused with such a character at load; this keeps any other text (a sample
    file's header, a plugin's note) from stopping the document."""
    from ..base.vocabulary import NOT_XML

    if isinstance(obj, Text):
        return obj.map(lambda s: NOT_XML.sub("", s))
    if isinstance(obj, str):
        return NOT_XML.sub("", obj)
    if isinstance(obj, dict):
        return {k: sanitize(v) for k, v in obj.items()}
    if isinstance(obj, list):
        return [sanitize(v) for v in obj]
    return obj


def _conformity_block(a: Any) -> dict[str, Any] | None:
    """The verdicts as text (None when no specification applied)."""
    if a is None:
        return None
    return {
        "rule": a.rule.name,
        "rule_title": a.rule.title,
        "statement": a.rule.statement,
        "overall": a.overall.value if a.overall is not None else DASH,
        "verdicts": [
            {
                "item": v.item,
                "key": v.key,
                "limit": v.spec.text(),
                "source": v.spec.source,
                "status": v.status.value,
                "detail": v.detail,
                "reason": v.reason,
            }
            for v in a.verdicts
        ],
        "not_assessed": [
            msg("{symbol} {limit} ({source})", symbol=s.symbol, limit=s.text(), source=s.source)
            for s in a.not_assessed
        ],
    }


def _unique(seq: Iterable[str]) -> list[str]:
    return list(dict.fromkeys(seq))


def _data_files(record: "RunRecord") -> list[dict[str, str]]:
    """The manifest (first, when read from one) and every samples file, with their SHA-256: the
    manifest's hash proves which K, latitude and equipment produced the report."""
    files = list(record.data_files) or list(record.campaign.data_files())
    out = [{"file": f if isinstance(f, str) else str(f), "sha256": str(h)} for f, h in files]
    manifest = getattr(record.campaign, "manifest_sha256", "")
    if manifest:
        out.insert(0, {"file": f"{record.campaign.source} (manifest)", "sha256": manifest})
    if not out:  # a simulated campaign: its samples live in memory, still hashed
        out = [
            {
                "file": f"segment {s.id} "
                f"({'simulated, ' if record.campaign.simulated else ''}in memory)",
                "sha256": s.sha256,
            }
            for s in record.campaign.segments
            if s.sha256
        ]
    return out


def _fact_text(v: Any) -> str:
    if v is None:
        return ""
    if isinstance(v, (dt.date, dt.datetime)):
        return _date_text(v)
    return str(v).strip()


def record_facts(record: "RunRecord") -> dict[str, str]:
    """Who, where and when, from the campaign through the manifest vocabulary
    (:mod:`metro.core.base.vocabulary`; a lab profile in force has filled in what the manifest
    leaves out, :func:`metro.core.record.registering.with_lab`): ``lab``, ``lab_address``,
    ``location``, ``customer``, ``customer_address``, ``operator``, ``checker``, ``approver`` and
    their titles ``operator_title``, ``checker_title``, ``approver_title``, ``received``,
    ``measured`` (the measurement date,
    :attr:`RunRecord.test_date`; where it came from in ``measured_from``), ``issued`` (the
    manifest's ``issued``, else the day the document is written) and ``processed`` (the time of
    this run).  A missing fact is the empty string; documents print it as "—"."""
    from ..model.provenance import measurement_date

    camp = record.campaign
    meta = dict(camp.meta)
    people, lab, customer = camp.people, camp.lab, camp.customer
    received = camp.date_received
    out = {
        "lab": lab.name,
        "lab_address": lab.address,
        "location": lab.location,
        "customer": customer.name,
        "customer_address": customer.address,
        "operator": people.operator,
        "checker": people.checked_by,
        "approver": people.approved_by,
        "approver_title": people.approved_by_title,
        "operator_title": people.operator_title,
        "checker_title": people.checked_by_title,
        "received": received.isoformat() if received else "",
        "issued": _fact_text(meta.get("issued")),
        "logo": _fact_text(meta.get("lab_logo")),
    }
    measured = measurement_date(camp)
    if measured is not None:
        out["measured"] = measured.isoformat()
        out["measured_from"] = "campaign" if camp.measurement_date else "acquisition time"
    else:
        out["measured"] = record.test_date.isoformat()
        out["measured_from"] = "processing time"
    if not out["issued"]:
        out["issued"] = dt.date.today().isoformat()
    out["processed"] = _date_text(record.created)
    return {k: str(v or "") for k, v in out.items()}


def report_context(
    record: "RunRecord", *, designations: Mapping[str, str] | None = None
) -> dict[str, Any]:
    """Everything the report shows, as plain Python (strings, lists, dicts).

    ``designations`` maps a standard id to its designation (``{"gbt45570": "GB/T 45570—2025"}``,
    from the plugin registry's ``StandardInfo``); without it the standard id is shown.

    Keys: ``report_number``, ``created``, ``created_iso``, ``title``, ``footer``,
    ``generator``, ``standards`` (list of {id, designation, items}), ``standards_text``,
    ``items_text``, ``simulated``, ``simulated_banner``, ``truth`` ([{name, value}]),
    ``campaign`` {id, source}, ``device`` {id, manufacturer, model, serial, technology,
    application, output, description, properties}, ``environment`` and ``site``
    ([{name, value}]), ``latitude``, ``equipment`` ([{id, description, role, certificate, U,
    due, status, expired, valid}]), ``equipment_warnings``, ``outcomes`` (see below),
    ``provenance`` {source, software, plugins ([{name, version}]), data_files ([{file,
    sha256}])}, ``selection`` ([{item, run, reason, via}]: what ``--all``/a series chose and why),
    ``data`` (the machine values a DCC carries: :func:`metro.core.documents.dcc.data.dcc_data`)
    and ``conformity`` (None, or {rule, rule_title, statement, overall, verdicts ([{item, key,
    limit, source, status, detail, reason}]), not_assessed ([text])}).

    Each outcome: ``number`` ("5.1"), ``id``, ``standard``, ``designation``, ``item``,
    ``title``, ``clause``, ``segments_text``, ``options``, ``options_text``, ``results``
    ([{key, quantity, symbol, value, U, unit, k, clause, equation, reference, note}] — value
    and U as :meth:`Result.reported` gives them), ``notes``, ``budgets`` ([{title,
    measurand, result, unit, rows, u_c, nu_eff, k, coverage, U, U_unrounded, rounding,
    note}], each row {source, symbol, type, distribution, value, divisor, sensitivity,
    contribution, dof}), ``tables`` ([{name, title, header, rows}]), ``plots`` ([{number,
    name, title, caption, spec, image}]; ``caption`` is the title with the item, ``image`` is filled
    in by
    :func:`write_report`) and
    ``warnings``.
    """
    from .dcc.data import dcc_data

    designations = dict(designations or {})
    camp = record.campaign
    simulated = bool(record.simulated or camp.simulated)
    on = record.test_date

    std_list = _standards_block(record, designations)
    items_text = "; ".join(f"{s['designation']} {s['items_text']}" for s in std_list)
    title = "Test report — " + (items_text or camp.id)

    outcomes = _outcome_blocks(record, designations)
    equipment = [_equipment_row(e, on) for e in camp.equipment]

    truth = dict(camp.truth)
    truth.update(record.truth)
    site = dict(camp.site)
    latitude = fmt_quantity(site["latitude"]) if "latitude" in site else None

    software = dict(record.software)
    generator = f"metro {software['metro']}" if "metro" in software else "metro"
    source = camp.source or ("simulated station" if simulated else DASH)

    return sanitize(
        {
            "facts": record_facts(record),
            "report_number": record.report_number,
            "created": _date_text(record.created),
            "created_iso": record.created.isoformat(),
            "title": title,
            "footer": f"{title} · {record.report_number}",
            "generator": generator,
            "standards": std_list,
            "standards_text": ", ".join(s["designation"] for s in std_list) or DASH,
            "items_text": items_text or DASH,
            "simulated": simulated,
            "simulated_banner": SIMULATED_BANNER if simulated else "",
            "truth": _name_values(truth, relabel=False) if simulated else [],
            "campaign": {"id": camp.id, "source": source},
            "device": _device_block(camp.device),
            "environment": _name_values(camp.environment),
            "site": _name_values(site),
            "latitude": latitude,
            "equipment": equipment,
            "equipment_warnings": _equipment_warnings(equipment),
            "outcomes": outcomes,
            "selection": [
                {"item": c.item, "run": c.run, "reason": c.reason, "via": c.via}
                for c in getattr(record, "selection", ())
            ],
            "conformity": _conformity_block(getattr(record, "conformity", None)),
            "provenance": _provenance_block(record, source, software),
            # the numbers, units, k and verdict codes themselves, for a DCC (docs/dcc.md)
            "data": dcc_data(record),
        }
    )


def _standards_block(record: "RunRecord", designations: Mapping[str, str]) -> list[dict[str, str]]:
    """The standards and their items, in the order the outcomes came."""
    standards: dict[str, list[str]] = {}
    for o in record.outcomes:
        standards.setdefault(o.standard, []).append(o.item)
    return [
        {"id": s, "designation": designations.get(s) or s, "items_text": ", ".join(_unique(items))}
        for s, items in standards.items()
    ]


def _outcome_blocks(record: "RunRecord", designations: Mapping[str, str]) -> list[dict[str, Any]]:
    """Each outcome's block, numbered 5.1, 5.2 …, its figures numbered on from the last one's."""
    outcomes = []
    figure = 1
    for i, o in enumerate(record.outcomes, start=1):
        block = _outcome_block(o, f"5.{i}", designations.get(o.standard) or o.standard, figure)
        figure += len(block["plots"])
        outcomes.append(block)
    return outcomes


def _equipment_warnings(equipment: list[dict[str, Any]]) -> list[Any]:
    """A warning for each item of equipment whose calibration had expired on the test date."""
    return [
        msg(
            "The calibration of {id} ({certificate}) is {status}: results that depend on it "
            "are not "
            "traceable until it is recalibrated.",
            id=e["id"],
            certificate=e["certificate"],
            status=e["status"],
        )
        for e in equipment
        if e["expired"]
    ]


def _device_block(dev: Any) -> dict[str, Any]:
    """The device under test: its identity, a missing field as a dash."""
    return {
        "id": dev.id,
        "manufacturer": or_dash(dev.manufacturer),
        "model": or_dash(dev.model),
        "serial": or_dash(dev.serial),
        "technology": or_dash(dev.technology),
        "application": or_dash(dev.application),
        "output": or_dash(dev.output),
        "description": dev.describe(),
        "properties": _name_values(dev.properties),
    }


def _provenance_block(
    record: "RunRecord", source: str, software: Mapping[str, Any]
) -> dict[str, Any]:
    """Where the data came from, the software that evaluated them and every file's SHA-256."""
    return {
        "source": source,
        "software": [{"name": k, "version": str(v)} for k, v in software.items()],
        "plugins": [{"name": k, "version": str(v)} for k, v in dict(record.plugins).items()],
        "data_files": _data_files(record),
        "manifest": {
            "file": record.campaign.source,
            "sha256": getattr(record.campaign, "manifest_sha256", "") or "—",
        },
    }


def build_context(
    record: "RunRecord",
    *,
    designations: Mapping[str, str] | None = None,
    extend: Callable[["RunRecord", dict], None] | None = None,
    register: Mapping[str, Any] | None = None,
    lang: str | None = None,
) -> dict[str, Any]:
    """The context :func:`render_context` renders: :func:`report_context`, then the plugins'
    ``metro_extend_report_context`` (``extend``), numbers in free text as powers of ten.

    ``register`` is the register statement: ``{"registered": bool, "notices": [text, …]}``
    (:mod:`metro.core.record.registering`); each notice is printed at the top of the report.
    ``lang`` (``zh``, ``en``, ``zh+en``) is kept in the context (``ctx["lang"]``) so the same
    document can be written again; ``ctx["verify_url"]`` is the lab's verify page (the campaign's
    ``lab_verify_url``, from the lab profile), whose QR code a registered report prints.  The
    result is plain JSON apart from each figure's ``spec`` (a PlotSpec), so the register can keep
    it and write the same report again (``metro report NUMBER``)."""
    ctx = report_context(record, designations=designations)
    ctx["register"] = (
        dict(register) if register is not None else {"registered": False, "notices": []}
    )
    if lang is not None:
        ctx["lang"] = lang
    if extend is not None:  # plugins' metro_extend_report_context
        extend(record, ctx)
    ctx = _pretty_context(ctx)
    ctx["logo"] = _logo(
        ctx["facts"].get("logo", "")
    )  # after the text clean-up: image bytes as base64
    # the lab profile's verify page (with_lab): a registered report prints its QR code
    ctx["verify_url"] = str(record.campaign.meta.get("lab_verify_url") or "")
    return ctx


def _logo(path: str) -> dict[str, str] | None:
    """The lab's logo (``facts["logo"]``, from the lab profile) as ``{"file", "base64"}``: kept in
    the context itself so the register can write the same document again without the file."""
    import base64

    from ..base.errors import DataError

    if not path:
        return None
    p = Path(path)
    try:
        data = p.read_bytes()
    except OSError as exc:
        raise DataError(
            str(p), "lab.logo", f"cannot read the logo image: {exc.strerror or exc}"
        ) from exc
    return {"file": p.name, "base64": base64.b64encode(data).decode("ascii")}

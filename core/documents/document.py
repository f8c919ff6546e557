"""The sections every metro document shares, and the generic layout.

A plugin supplies only its appendix's content and order (a *layout*: a function
``layout(doc, ctx)`` given a :class:`~metro.core.documents.builder.DocumentBuilder` and the
report context of :mod:`metro.core.documents.context`); the sections here (identification,
results, environment, equipment, notes, conformity, signatures, the annexes) are the pieces it
picks from.  :func:`generic_layout` is the layout of a standard that brings none.

Numbers are formatted before they get here (:mod:`metro.core.base.formatting`: one notation,
``×10ⁿ``); text is set by :mod:`metro.core.documents.text`.
"""

from __future__ import annotations

from typing import Any, Mapping, Sequence

from ..base.formatting import DASH, or_dash, with_unit
from .builder import DocumentBuilder, Layout
from .context import result_row
from .text import FIGURE_WIDTH_MM, display_symbol, quantity_name

__all__ = [
    "DocumentBuilder",
    "Layout",
    "DASH",
    "or_dash",
    "with_unit",
    "not_reportable",
    "withheld_reasons",
    "status_text",
    "result_cells",
    "result_fields",
    "quantity_for",
    "identification",
    "results_table",
    "environment_table",
    "ROLE_LABELS",
    "role_label",
    "equipment_table",
    "notes_section",
    "signatory_rows",
    "signatures",
    "budgets_annex",
    "tables_annex",
    "figures_annex",
    "provenance_annex",
    "generic_layout",
    "conformity_section",
    "annexes",
    "layout_digest",
]

# ----------------------------------------------------------------------------------------
# Sections every document may use (a layout picks them and adds its appendix's own)
# ----------------------------------------------------------------------------------------


def not_reportable(tr, reason: Any) -> str:
    """ "not reportable: reason" in the document's language(s).  A reason made as a message
    (:class:`metro.core.base.locale.Text`) is written in each language; a plain one (data, in one
    language) is printed once, not once per language."""
    from ..base.locale import Text

    if tr.lang != "zh+en" or (
        isinstance(reason, Text) and tr.render(reason, "zh") != tr.render(reason, "en")
    ):
        return tr("not reportable: {reason}", reason=reason or DASH)
    head = tr("not reportable: {reason}", reason="").rstrip()
    return f"{head}{'' if head.endswith('：') else ' '}{reason or DASH}"


def withheld_reasons(
    doc: DocumentBuilder, withheld: Sequence[tuple[str, Any]], size: float = 8.5
) -> None:
    """Why the results of a table or matrix whose cells say "not reportable" are withheld, after it:
    ``withheld`` = (symbol, reason).  A reason, or a part of one (a "; " join: what a drifting gyro
    does, what to do), that several share is stated once naming them; the parts only one result
    has, on one line (:func:`metro.core.documents.notes.group_notes`)."""
    from .notes import group_notes

    tr = doc.tr
    for where, reason in group_notes([("", sym, r) for sym, r in withheld], key=tr.text):
        doc.para(
            f"{where}: {not_reportable(tr, reason)}" if where else not_reportable(tr, reason),
            size=size,
        )


def status_text(tr, status: Any) -> str:
    """An equipment status on the date of measurement, translated where it is a message."""
    from ..base.locale import Text

    return tr(status) if isinstance(status, Text) or status in _STATUS_MSGS else status


def result_cells(doc: DocumentBuilder, r: dict) -> tuple[str, str]:
    """(value with unit, "U = … (k = …)") of a result row of the report context; a result not
    reportable says so, with its reason, in place of its value; one that bounds the quantity (D.4's
    threshold ≤ H, a megohmmeter over its range) states the bound, with its U and why it is one."""
    from ..base.formatting import BOUND_SIGNS

    tr = doc.tr
    bound = "" if r.get("reportable", True) else r.get("bound") or ""
    if not r.get("reportable", True) and not bound:
        return not_reportable(tr, r.get("reason") or ""), DASH
    value = r["value_unit"]
    if bound:
        value = tr(
            "{sign} {value} (a bound: {reason})",
            sign=BOUND_SIGNS[bound],
            value=value,
            reason=r.get("reason") or DASH,
        )
    U = r.get("U_unit") or DASH
    if U == DASH:
        return value, tr("not evaluated")
    if U.startswith("u = "):
        return value, U
    if r.get("U") in ("0", "0.0"):  # a count or a value taken as declared: no k to state
        return value, tr("no uncertainty (exact)")
    if r.get("monte_carlo_p"):  # GUM not validated (JCGM 101 clause 8): the Monte Carlo interval
        return value, tr("{interval} (Monte Carlo, {p} %)", interval=U, p=r["monte_carlo_p"])
    return value, f"U = {U} (k = {r['k']})"


def result_fields(result: Any) -> dict:
    """A :class:`~metro.core.model.results.Result` as the report context shows it: ``value_unit``,
    ``U_unit`` (``—`` without a budget), ``k``, ``reportable``, ``reason``, ``earth_rate``,
    ``note``, ``quantity``, ``symbol`` … (numbers rounded as :meth:`Result.reported` rounds
    them)."""
    return result_row(result)


def quantity_for(ctx: dict, item: str, key: str) -> str:
    """The name and symbol of result ``key`` of ``item`` in the context (the key if not found)."""
    for o in ctx["outcomes"]:
        if o["item"] == item:
            for r in o["results"]:
                if r["key"] == key:
                    return quantity_name(r)
    return key


def identification(doc: DocumentBuilder, ctx: dict, rows: Sequence[tuple[str, str]] = ()) -> None:
    """Laboratory, customer, device, dates, then ``rows`` (the appendix's own)."""
    tr, f, dev = doc.tr, ctx["facts"], ctx["device"]
    pairs = [
        (tr("Report No."), ctx["report_number"]),
        (tr("Laboratory"), or_dash(f["lab"])),
        (tr("Laboratory address"), or_dash(f["lab_address"])),
        (tr("Customer"), or_dash(f["customer"])),
        (tr("Customer address"), or_dash(f["customer_address"])),
        (tr("Device"), f"{tr.text(dev['description'])} ({tr('id')} {dev['id']})"),
        (tr("Date of measurement"), or_dash(f["measured"])),
        (tr("Date received"), or_dash(f["received"])),
        (tr("Date of issue"), or_dash(f["issued"])),
    ]
    doc.kv(pairs + list(rows))


def results_table(
    doc: DocumentBuilder,
    ctx: dict,
    outcomes: Sequence[dict] | None = None,
    verdicts: dict | None = None,
) -> None:
    """One table of every result: item, quantity, value, U (k) [, verdict]."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    header = [tr("Item"), tr("Quantity"), tr("Result"), tr("Expanded uncertainty")]
    if verdicts is not None:
        header.append(tr("Verdict"))
    rows = []
    for o in outcomes:
        for r in o["results"]:
            v, U = result_cells(doc, r)
            row = [o["item"], quantity_name(r), v, U]
            if verdicts is not None:
                row.append(verdicts.get((o["item"], r["key"]), DASH))
            rows.append(row)
    doc.table(header, rows, prefer=1, prefer_share=0.8)


def environment_table(doc: DocumentBuilder, ctx: dict) -> None:
    """The environmental conditions and the site (latitude) of the campaign."""
    tr = doc.tr
    rows = [
        (tr(n["name"].capitalize()) if n["name"].islower() else n["name"], n["value"])
        for n in ctx["environment"]
    ]
    if rows:
        doc.kv(rows)
    else:
        doc.para(tr("not recorded"))


_STATUS_MSGS = ("no calibration data given", "no due date stated")

#: canonical equipment roles (metro.core.base.vocabulary) as a document names them (catalog ids)
ROLE_LABELS = {
    "rate_table": "rate table",
    "position_table": "position table",
    "tilt_table": "tilt table",
    "turntable": "turntable",
    "platform": "stable platform",
    "counter": "counter",
    "dmm": "digital multimeter",
    "acquisition": "data acquisition",
    "timer": "timer",
    "chamber": "temperature chamber",
    "field_generator": "magnetic field generator",
    "fixture": "fixture",
    "vibration_table": "vibration table",
    "angular_vibration_table": "angular vibration table",
    "shock_table": "shock table",
    "voltmeter": "voltmeter",
    "ammeter": "ammeter",
    "calliper": "callipers",
    "balance": "balance",
    "megohmmeter": "megohmmeter",
}


def role_label(tr, role: str) -> str:
    """An equipment role as words in the document's language(s) (``rate_table`` → ``速率转台 rate
    table``), never the code key; a role metro does not know prints with spaces for underscores."""
    role = (role or "").strip()
    if not role or role == DASH:
        return DASH
    label = ROLE_LABELS.get(role)
    return tr(label) if label else role.replace("_", " ")


def equipment_table(doc: DocumentBuilder, ctx: dict) -> None:
    """The measurement standards used, their certificates, U with unit and status on the day
    of measurement."""
    tr = doc.tr
    rows = [
        [
            f"{tr.text(e['description'])} ({e['id']})",
            role_label(tr, e["role"]),
            e["certificate"],
            e["U"] + (f" ({tr('relative')})" if e.get("U_relative") else ""),
            e["due"],
            status_text(tr, e["status"]),
        ]
        for e in ctx["equipment"]
    ]
    if not rows:
        doc.para(tr("No equipment recorded."))
        return
    doc.table(
        [
            tr("Equipment"),
            tr("Role"),
            tr("Certificate"),
            tr("Uncertainty"),
            tr("Due"),
            tr("Status on the date of measurement"),
        ],
        rows,
    )
    for w in ctx["equipment_warnings"]:
        doc.para(w, color="B01C1C")


def notes_section(
    doc: DocumentBuilder,
    ctx: dict,
    outcomes: Sequence[dict] | None = None,
    include_warnings: bool = True,
) -> None:
    """Result notes, earth-rate statements and warnings, each text once.

    Each note or warning text is one line naming the results and items it applies to
    (:func:`metro.core.documents.notes.group_notes`: ``K_gxx, K_gyy (7.2.1): …``, ``7.2.1, 7.2.2,
    7.2.3: …``), in the order the texts first appear; a part several results share (of a note joined
    with ``"; "``) is its own line, and a sentence that differs between results only in its indices
    is stated once in index form (``g_ij``).  The earth-rate statement is one line per kind naming
    the items it applies to."""
    from .notes import group_notes

    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    earth: dict[str, list[str]] = {}
    entries: list[tuple[str, str, Any]] = []
    for o in outcomes:
        for r in o["results"]:
            sym = display_symbol(r.get("symbol") or "") or r.get("quantity") or ""
            if r.get("note"):
                entries.append((o["item"], tr.text(sym) if sym else "", r["note"]))
            er = r.get("earth_rate")
            if er:
                earth.setdefault(er, []).append(o["item"])
        for w in o["warnings"] if include_warnings else ():
            entries.append((o["item"], "", w))
    lines = [f"{where}: {tr.text(text)}" for where, text in group_notes(entries, key=tr.text)]
    for how, items in earth.items():
        lines.append(
            f"{tr('Earth rate: {how}', how=tr.msg(how))}: {', '.join(dict.fromkeys(items))}"
        )
    if lines:
        doc.bullets(lines, size=8)
    else:
        doc.para(tr("none"))


def signatory_rows(facts: Mapping[str, Any], labels: Sequence[str]) -> list[tuple[str, str, str]]:
    """(role, name, title) of the three signatories in a context's ``facts``: who performed the
    measurement (``operator``), who checked it and who approved (issued) the document, each with
    the title the campaign or the lab profile gives (``operator_title``, ``checker_title``,
    ``approver_title``; a context kept by the register before titles were kept has none)."""
    keys = (
        ("operator", "operator_title"),
        ("checker", "checker_title"),
        ("approver", "approver_title"),
    )
    return [
        (label, str(facts.get(name) or ""), str(facts.get(title) or ""))
        for label, (name, title) in zip(labels, keys)
    ]


def signatures(
    doc: DocumentBuilder, roles: Sequence[tuple[str, ...]], *, titled: bool | None = None
) -> None:
    """Signature rows: (role, name) or (role, name, title — 职务); each row is tall enough to sign.
    The title column is there when a row has a title, or always with ``titled=True`` (a
    certificate's clause 8 n) asks for the issuer's title); a missing title prints "—"."""
    from docx.shared import Mm

    tr = doc.tr
    if titled is None:
        titled = any(len(r) > 2 and r[2] for r in roles)
    header = (
        [tr("Role"), tr("Name")] + ([tr("Title")] if titled else []) + [tr("Signature"), tr("Date")]
    )
    rows = [
        [r[0], or_dash(r[1])]
        + ([or_dash(r[2] if len(r) > 2 else "")] if titled else [])
        + ["\u2003" * 12, "\u2003" * 6]
        for r in roles
    ]
    t = doc.table(header, rows, font_pt=9)
    for row in t.rows[1:]:
        row.height = Mm(11)
    for row in t.rows[:-1]:  # the table on one page (Word and LibreOffice keep a row with the next)
        for cell in row.cells:
            for p in cell.paragraphs:
                p.paragraph_format.keep_with_next = True


def budgets_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    """Every uncertainty budget, in one table whose header (source, symbol, type and
    distribution, value, divisor, cᵢ, uᵢ(y), νᵢ) repeats on each page: per budget a title row
    (item, quantity, the unit of its uᵢ(y)), its rows, and a row with u_c, ν_eff, k and U.  A
    budget whose every contribution is zero (an exact count, a value taken as declared) is not a
    table: such budgets are listed first, those sharing one reason under it once.  In zh+en a
    row's distribution is printed in Chinese (the names in both languages once, above the table)."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    exact: dict[tuple, tuple[list, list[str]]] = {}
    tables: list[tuple[list, list[int], list[int]]] = []
    dists: dict[str, None] = {}
    numbered = _shared_notes(outcomes)
    notes: dict[str, tuple[int, Any]] = {}

    def source_of(x: dict) -> Any:
        if x.get("note") and str(x["note"]) in numbered:
            k = notes.setdefault(str(x["note"]), (len(notes) + 1, x["note"]))[0]
            return f"{tr.text(x['source_only'])} [{k}]"
        return x["source"]

    for o in outcomes:
        rows: list[list[str]] = []
        spans: list[int] = []
        titles: list[int] = []
        for b in o["budgets"]:
            name = f"{o['item']} {tr.text(b['title'])}"
            if all(x["contribution"] in ("0", "0.0") for x in b["rows"]):
                key = tuple(str(_generic(x["source"])) for x in b["rows"])
                exact.setdefault(key, ([x["source"] for x in b["rows"]], []))[1].append(name)
                continue
            unit = "" if b["unit"] == "1" else b["unit"]
            spans.append(len(rows))
            titles.append(len(rows))
            rows.append(
                [f"{o['item']} — {tr.text(b['title'])}" + (f"   [u_i(y): {unit}]" if unit else "")]
            )
            for x in b["rows"]:
                dists[x["distribution"]] = None
                dist = tr.zh(x["distribution"]) if tr.lang == "zh+en" else tr(x["distribution"])
                rows.append(
                    [
                        source_of(x),
                        x["symbol"],
                        f"{x['type']}, {dist}",
                        x["value"],
                        x["divisor"],
                        x["sensitivity"],
                        x["contribution"],
                        x["dof"],
                    ]
                )
            unit = f" {unit}" if unit else ""
            spans.append(len(rows))
            rows.append(
                [
                    f"u_c = {b['u_c']}{unit}, ν_eff = {b['nu_eff']}, k = {b['k']}, "
                    f"U = {b['U']}{unit}"
                    + (f". {tr.text(b['note'])}" if b.get("note") else "")
                ]
            )
        if rows:
            tables.append((rows, spans, titles))
    _exact_budgets_and_notes(doc, exact, notes)
    if tables and tr.lang == "zh+en":
        doc.para(
            f"{tr('Distribution')}: " + ", ".join(tr(d) for d in dists), size=7.5, keep_next=True
        )
    for i, (rows, spans, titles) in enumerate(tables):  # one table per item, widths its own
        if i:  # two tables with nothing between them are one table to LibreOffice and Word
            doc.para("", size=2)
        doc.table(
            [
                tr("Source"),
                tr("Symbol"),
                _type_distribution_header(tr),
                tr("Value"),
                tr("Divisor"),
                "c_i",
                "u_i(y)",
                "ν_i",
            ],
            rows,
            font_pt=7,
            prefer=0,
            prefer_share=1.0,
            spans=spans,
            bold_rows=titles,
            shade=titles,
            unit_break=(3, 5, 6),
        )


def _shared_notes(outcomes: Sequence[dict]) -> dict[str, None]:
    """The budget-row notes (over 40 characters) that several rows share: each is printed once,
    numbered, above the budget tables."""
    seen: dict[str, int] = {}
    for o in outcomes:
        for b in o["budgets"]:
            for x in b["rows"]:
                if x.get("note") and len(str(x["note"])) > 40:
                    seen[str(x["note"])] = seen.get(str(x["note"]), 0) + 1
    return {n: None for n, c in seen.items() if c > 1}


def _exact_budgets_and_notes(doc: DocumentBuilder, exact: dict[tuple, tuple[list, list[str]]],
                             notes: dict[str, tuple[int, Any]]) -> None:
    """Above the budget tables: the budgets with no uncertainty (those sharing one reason under
    it once), then the numbered notes that several rows share."""
    tr = doc.tr
    if exact:
        doc.para(f"{tr('no uncertainty (exact)')}:", size=7.5, keep_next=True)
        lines = []
        for sources, names in exact.values():
            why = "; ".join(tr.text(_generic(x) if len(names) > 1 else x) for x in sources)
            lines.append(f"{why}: {'; '.join(names)}")
        doc.bullets(lines, size=7.5)
    if notes:
        doc.para(f"{tr('Notes to several rows')}:", size=7.5, keep_next=True)
        for k, note in notes.values():
            p = doc.para(f"[{k}] {tr.text(note)}", size=7.5)
            p.paragraph_format.space_after = doc._pt(0)


def _generic(text: Any) -> Any:
    """A message with its data fields (a quantity's name, a count) left out as "…", to say once
    what several exact budgets share ("…: no uncertainty declared by the test lab"); a field with
    a number format keeps the message whole."""
    import string

    from ..base.locale import Text

    if not isinstance(text, Text):
        return text
    if text.msgid is None:
        return Text(None, sep=text.sep, parts=tuple(_generic(p) for p in text.parts))
    formatted = {
        f for _, f, spec, conv in string.Formatter().parse(text.msgid) if f and (spec or conv)
    }
    fields = {}
    for k, v in text.fields.items():
        if isinstance(v, Text):
            fields[k] = _generic(v)
        elif k in formatted:
            return text
        else:
            fields[k] = "…"
    return Text(text.msgid, fields)


def _type_distribution_header(tr) -> str:
    """One header for the type and distribution columns merged: ``类型，分布`` above
    ``Type, distribution``."""
    if tr.lang == "zh+en":
        return f"{tr.zh('Type')}，{tr.zh('Distribution')}\nType, distribution"
    if tr.lang == "zh":
        return f"{tr.zh('Type')}，{tr.zh('Distribution')}"
    return "Type, distribution"


def tables_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    """Each outcome's supplementary tables."""
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    for o in outcomes:
        for t in o["tables"]:
            doc.para(f"{o['item']} — {doc.tr.text(t['title'])}", bold=True, keep_next=True)
            doc.table(t["header"], t["rows"], font_pt=7.5)


def figures_annex(doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None) -> None:
    """Each outcome's figures with their captions."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    for o in outcomes:
        for p in o["plots"]:
            if p.get("image"):
                doc.figure(
                    p["image"],
                    f"{tr('Figure')} {p['number']}: {tr.text(p['caption'])}",
                    width_mm=FIGURE_WIDTH_MM,
                )


#: beyond this many data files (segments), the document prints the digest of their sorted list only
MAX_LISTED_DIGESTS = 240


def provenance_annex(doc: DocumentBuilder, ctx: dict) -> None:
    """Software and plugin versions, then the data's SHA-256 in one compact table (full digests
    for up to 24 files; beyond that the first 16 hex digits, three to a row; one SHA-256 over the
    sorted list, which alone is printed beyond :data:`MAX_LISTED_DIGESTS` files — the run record's
    --json output lists every digest in full)."""
    import hashlib

    tr = doc.tr
    prov = ctx["provenance"]
    sw = ", ".join(f"{s['name']} {s['version']}" for s in prov["software"])
    pl = ", ".join(f"{p['name']} {p['version']}" for p in prov["plugins"])
    doc.kv(
        [
            (tr("Software"), sw or DASH),
            (tr("Plugins"), pl or DASH),
            (tr("Data source"), or_dash(prov["source"])),
            (tr("Campaign"), ctx["campaign"]["id"]),
            (tr("Processed"), ctx["facts"]["processed"]),
        ],
        font_pt=8,
    )
    if ctx["truth"]:
        doc.para(tr("Declared truth of the simulated device"), bold=True, keep_next=True)
        doc.kv([(t["name"], t["value"]) for t in ctx["truth"]], font_pt=8)
    files = [f for f in prov["data_files"] if f.get("sha256")]
    if not files:
        return
    lines = sorted(f"{f['sha256']}  {f['file']}\n" for f in files)
    digest = hashlib.sha256("".join(lines).encode("utf-8")).hexdigest()
    doc.para(
        f"{tr('SHA-256 of the sorted list of data digests')}: {digest}", size=8, keep_next=True
    )
    # a file or segment name is an identifier: in one language (English in zh+en), not twice
    one = "zh" if tr.lang == "zh" else "en"
    if len(files) <= 24:
        names = [_short_name(tr.render(f["file"], one)) for f in files]
        prefix, suffix = _common_affixes(names)
        if prefix or suffix:
            doc.para(f"{tr('Data')}: {(prefix + '…' + suffix).strip()}", size=7.5, keep_next=True)
        doc.table(
            [tr("Data"), "SHA-256"],
            [
                [n[len(prefix) : len(n) - len(suffix)].strip(), f["sha256"]]
                for n, f in zip(names, files)
            ],
            font_pt=7,
        )
        return
    # many files (simulated segments): the name without what they all share, the first 16 hex
    # digits, three to a row (one line each at 6 pt); the shared words said once above the table
    if len(files) > MAX_LISTED_DIGESTS:
        # hundreds of segments (a JJF 2014 --all run has ~700): five pages of hex help no reader;
        # the digest over the sorted list above fixes them all, and the record lists each
        doc.para(
            tr(
                "{n} data files or segments: the SHA-256 above is over the sorted list of their "
                "digests, which the record of the run lists in full (the register keeps it with "
                "the "
                "report).",
                n=len(files),
            ),
            size=7.5,
        )
        return
    names = [_short_name(tr.render(f["file"], one)) for f in files]
    prefix, suffix = _common_affixes(names)
    title = tr("Data (SHA-256, first 16 hex digits)")
    if prefix or suffix:
        title += f"; {tr('Data')}: {(prefix + '…' + suffix).strip()}"
    doc.para(title, size=7.5, keep_next=True, bold=True)
    cells = [
        f"{n[len(prefix) : len(n) - len(suffix)].strip()} {f['sha256'][:16]}"
        for n, f in zip(names, files)
    ]
    rows = [cells[i : i + 3] for i in range(0, len(cells), 3)]
    doc.table(None, rows, font_pt=6)


def _common_affixes(names: Sequence[str]) -> tuple[str, str]:
    """The word-aligned prefix and suffix every name shares (``segment `` … `` (simulated, in
    memory)``).

    >>> _common_affixes(["segment a-1 (sim)", "segment b-22 (sim)"])
    ('segment ', ' (sim)')
    """
    import os

    if len(names) < 2:
        return "", ""
    pre = os.path.commonprefix(list(names))
    pre = pre[: pre.rfind(" ") + 1] if " " in pre else ""
    suf = os.path.commonprefix([n[::-1] for n in names])[::-1]
    suf = suf[suf.find(" ") :] if " " in suf else ""
    if any(len(n) <= len(pre) + len(suf) for n in names):
        return "", ""
    return pre, suf


def _short_name(name: str) -> str:
    import os

    return os.path.basename(name) if ("/" in name or "\\" in name) else name


def generic_layout(doc: DocumentBuilder, ctx: dict) -> None:
    """The report of a standard without a layout of its own."""
    tr = doc.tr
    doc.title_block(tr("Test report"), ctx["items_text"])
    identification(doc, ctx, [(tr("Standard"), ctx["standards_text"])])
    doc.heading(tr("Results"), 1)
    results_table(doc, ctx)
    doc.heading(tr("Notes"), 2)
    notes_section(doc, ctx)
    doc.heading(tr("Environment"), 2)
    environment_table(doc, ctx)
    doc.heading(tr("Equipment"), 2)
    equipment_table(doc, ctx)
    doc.heading(tr("Conformity"), 2)
    conformity_section(doc, ctx)
    doc.heading(tr("Signatures"), 2)
    f = ctx["facts"]
    signatures(doc, signatory_rows(f, [tr("Tested by"), tr("Checked by"), tr("Approved by")]))
    doc.para(
        tr(
            "The results relate only to the item tested. This report shall not be reproduced "
            "except in full without the written approval of the laboratory."
        ),
        size=8.5,
    )
    annexes(doc, ctx)


def conformity_section(doc: DocumentBuilder, ctx: dict) -> None:
    """The decision rule and every verdict with its reason (or: no statement is made)."""
    tr = doc.tr
    a = ctx["conformity"]
    if a is None:
        doc.para(tr("No specification was given: this report makes no statement of conformity."))
        return
    doc.para(f"{tr('Decision rule')}: {tr.text(a['rule_title'])}")
    doc.para(a["statement"], size=8.5)
    doc.para(f"{tr('Overall verdict')}: {tr(_VERDICT.get(a['overall'], a['overall']))}", bold=True)
    doc.table(
        [tr("Item"), tr("Quantity"), tr("Limit"), tr("Source"), tr("Verdict"), tr("Reason")],
        [
            [
                v["item"],
                quantity_for(ctx, v["item"], v["key"]),
                v["limit"],
                v["source"],
                tr(_VERDICT.get(v["status"], v["status"])),
                v["reason"],
            ]
            for v in a["verdicts"]
        ],
        font_pt=8,
    )
    if a["not_assessed"]:
        doc.para(
            f"{tr('Not assessed (item not performed)')}: "
            + "; ".join(tr.text(x) for x in a["not_assessed"]),
            size=8.5,
        )


_VERDICT = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate"}


def annexes(
    doc: DocumentBuilder, ctx: dict, outcomes: Sequence[dict] | None = None, first: str = "A"
) -> None:
    """Budgets, data tables, figures and provenance as annexes A, B, C, D."""
    tr = doc.tr
    outcomes = ctx["outcomes"] if outcomes is None else outcomes
    letter = ord(first)
    parts = [
        ("Uncertainty budgets", budgets_annex, any(o["budgets"] for o in outcomes)),
        ("Data tables", tables_annex, any(o["tables"] for o in outcomes)),
        ("Figures", figures_annex, any(o["plots"] for o in outcomes)),
        ("Provenance", lambda d, c, _o: provenance_annex(d, c), True),
    ]
    for title, fn, present in parts:
        if not present:
            continue
        doc.heading(f"{tr('Annex')} {chr(letter)} {tr(title)}", 1)
        fn(doc, ctx, outcomes)
        letter += 1


def layout_digest(layout: Any) -> str:
    """A SHA-256 that changes when a layout's document would: over the source of the layout's
    module, the document modules (this one, :mod:`~metro.core.documents.builder` and
    :mod:`~metro.core.documents.text`) and the message catalog (the register keeps it as the
    report's template identity, as it keeps a docxtpl template's file hash)."""
    import hashlib
    import importlib
    import inspect
    from importlib import resources
    from pathlib import Path

    if layout is None:
        module = __name__
    elif callable(layout):
        module = layout.__module__
    else:
        module = str(layout).partition(":")[0]
    h = hashlib.sha256()
    own = (__name__, f"{__package__}.builder", f"{__package__}.text")
    for mod in dict.fromkeys((module, *own)):
        h.update(Path(inspect.getfile(importlib.import_module(mod))).read_bytes())
    h.update(
        (resources.files("metro.core.base.locale") / "zh" / "LC_MESSAGES" / "metro.po").read_bytes()
    )
    return h.hexdigest()

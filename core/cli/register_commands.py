"""``metro lab``, ``metro register``, ``metro report``, ``metro amend``, ``metro withdraw`` and
``metro history``: the lab profile and the report register on the command line.

Kept out of :mod:`metro.core.cli.app` (which only wires these parsers in); like it, nothing heavy is
imported at module level, so ``metro --help`` stays fast.
"""

from __future__ import annotations

from typing import Any

from ..model.hookspec import hookimpl
from .dcc_commands import OutGiven, add_format_option

#: the top-level commands this module handles
COMMANDS = ("lab", "register", "report", "amend", "withdraw", "history")


def add_global_options(p) -> None:
    p.add_argument("--lab", metavar="PATH", default=None,
                   help="lab profile (TOML; default: METRO_LAB, else lab.toml in the user config "
                   "folder)")


def add_commands(sub) -> None:
    lab = sub.add_parser("lab", help="the lab profile: metro lab init PATH, metro lab show, "
                         "metro lab equipment import CERT.xml",
                         description="The lab profile names the lab, its signatories, numbering "
                         "scheme, register and equipment (docs/register.md).")
    lsub = lab.add_subparsers(dest="lab_command", metavar="SUBCOMMAND", required=True)
    li = lsub.add_parser("init",
                         help="write a commented lab profile template (never replaces a file)")
    li.add_argument("path", metavar="PATH")
    li.add_argument("--json", action="store_true")
    ls = lsub.add_parser("show", help="print the lab profile in force and where it was found")
    ls.add_argument("--json", action="store_true")
    from .lab_commands import add_equipment_commands

    add_equipment_commands(lsub)


    rg = sub.add_parser("register", help="the report register: list, show, verify",
                        description="Every registered report: number, status, results, provenance, "
                        "audit trail (docs/register.md).")
    rsub = rg.add_subparsers(dest="register_command", metavar="SUBCOMMAND", required=True)
    rl = rsub.add_parser("list", help="list the registered reports")
    rl.add_argument("--device", metavar="SERIAL",
                    help="only this device's reports (its serial number)")
    rl.add_argument("--standard", "-s", metavar="S", help="only reports of this standard")
    rl.add_argument("--since", metavar="DATE",
                    help="only reports measured on or after DATE (YYYY-MM-DD)")
    rl.add_argument("--json", action="store_true")
    rs = rsub.add_parser("show",
                         help="one report's register entry: results, verdicts, provenance, audit "
                         "trail")
    rs.add_argument("number", metavar="NUMBER")
    rs.add_argument("--json", action="store_true")
    rv = rsub.add_parser("verify",
                         help="check every report file against its stored SHA-256 (exit 6 if any "
                         "differs or is missing)")
    rv.add_argument("--json", action="store_true")

    rp = sub.add_parser("report", help="write a registered report again from the register",
                        description="Re-render report NUMBER from the register: the same numbers, "
                        "the same content.")
    rp.add_argument("number", metavar="NUMBER")
    rp.add_argument("--out", default="metro-out", metavar="DIR", action=OutGiven,
                    help="folder for NUMBER.docx, or NUMBER.xml with --format dcc (default: "
                    "metro-out)")
    add_format_option(rp, "what to write")
    rp.add_argument("--json", action="store_true")

    am = sub.add_parser("amend",
                        help="issue a report that replaces NUMBER (which becomes superseded)",
                        description="Issue an amended report replacing NUMBER and saying why; "
                        "NUMBER becomes superseded, never deleted. With --data the items are run "
                        "again on that manifest; without it the stored content is issued again "
                        "under a new number.")
    am.add_argument("number", metavar="NUMBER")
    am.add_argument("--reason", required=True,
                    help="why the report is amended (printed in the new report)")
    am.add_argument("--data", "-d", metavar="MANIFEST",
                    help="run the report's items again on this campaign")
    am.add_argument("--out", metavar="DIR",
                    help="folder of the new report (default: the replaced report's)")
    am.add_argument("--allow-expired", action="store_true",
                    help="issue even if equipment was past its calibration due date (the report "
                    "says so)")
    add_format_option(am, "also issue the new report's DCC (default: when NUMBER had one)")
    am.add_argument("--json", action="store_true")

    wd = sub.add_parser("withdraw",
                        help="withdraw an issued report (kept in the register, marked withdrawn)")
    wd.add_argument("number", metavar="NUMBER")
    wd.add_argument("--reason", required=True)
    wd.add_argument("--json", action="store_true")

    hi = sub.add_parser("history",
                        help="a device's calibrations over time, with drift flags and a plot",
                        description="List a device's issued reports and plot each result over time "
                        "with its U; a change between consecutive calibrations with |E_n| > 1 is "
                        "flagged as drift.")
    hi.add_argument("serial", metavar="SERIAL")
    hi.add_argument("--key", action="append", default=[], help="only this result key (repeatable)")
    hi.add_argument("--out", default="metro-out", metavar="DIR",
                    help="folder for history-SERIAL.png")
    hi.add_argument("--json", action="store_true")


def add_run_options(r) -> None:
    """Options of ``metro run`` about registration."""
    r.add_argument("--register-simulated", action="store_true",
                   help="register a simulated run too (needs a lab profile; by default simulated "
                   "runs are not registered)")
    r.add_argument("--allow-expired", action="store_true",
                   help="with a lab profile: run even if equipment is past its calibration due "
                   "date on the measurement date (the report says so)")


def dispatch(args) -> int:
    """Run one of :data:`COMMANDS` (``metro lab``, ``register``, ``report``, ``amend``, …)."""
    if args.command == "register":
        return {"list": _cmd_list, "show": _cmd_show,
                "verify": _cmd_verify}[args.register_command](args)
    command = {"lab": _cmd_lab, "report": _cmd_report, "amend": _cmd_amend,
               "withdraw": _cmd_withdraw, "history": _cmd_history}
    return command[args.command](args)


# ----------------------------------------------------------------------------------------
# metro run: writing (and registering) the report
# ----------------------------------------------------------------------------------------


def write_run_report(args, pm, record, prog=None):
    """Write the run's report: registered (a lab profile, and not simulated unless
    ``--register-simulated``) or with the "not registered" statement.  Returns (record with
    its final number, report path, registration summary for --json)."""
    import time
    from pathlib import Path

    from ..record import lab as labmod
    from ..base.errors import MetroError
    from ..record.registering import register_run, unregistered, with_lab

    lab = labmod.lab_in_force(getattr(args, "lab", None))
    if lab is not None:
        record = with_lab(record, lab)
    simulated = bool(record.simulated)
    register_simulated = getattr(args, "register_simulated", False)
    if register_simulated and lab is None:
        raise MetroError("--register-simulated needs a lab profile (its register and numbering "
                         "scheme)",
                         hint="give --lab PATH or METRO_LAB; `metro lab init PATH` writes a "
                         "template")
    registered = lab is not None and (not simulated or register_simulated)
    t0 = time.perf_counter()
    if prog:
        prog("writing report", 0, 1)
    from . import dcc_commands

    if registered:
        if args.report:
            raise dcc_commands.registered_report_error(args)
        writer = None
        if dcc_commands.wants_dcc(args):
            from ..record.dcc_out import DccWriter

            writer = DccWriter()
        issued, record = register_run(record, pm=pm, lab=lab, folder=Path(args.out),
                                      allow_expired=getattr(args, "allow_expired", False),
                                      options=_run_options(args), lang=getattr(args, "lang", None),
                                      dcc=writer)
        if getattr(args, "pdf", False):  # the registered .docx, as PDF beside it
            dcc_commands.registered_pdf(issued.path, writer)
        record.timings["write report"] = time.perf_counter() - t0
        summary = {"registered": True, "number": issued.number,
                   "register": labmod.redact_url(lab.register_url()), "sha256": issued.sha256}
        if writer is not None:
            summary["dcc"] = dcc_commands.dcc_summary(issued.dcc_path, issued.dcc_sha256)
        return record, issued.path, summary
    from ..documents.report import write_report

    if lab is not None:
        from ..record.registering import check_equipment, measurement_date

        check_equipment(record.campaign, measurement_date(record),
                        allow_expired=getattr(args, "allow_expired", False))
    why = "no lab profile" if lab is None else "simulated"
    if dcc_commands.wants_dcc(args):
        return dcc_commands.write_run_dcc(args, pm, record, lab, why, t0)
    from ..run.outputs import write_checked

    target = Path(args.report) if args.report else Path(args.out) / f"{record.report_number}.docx"
    info = pm.template_for(record.standard)
    designations = {s.id: s.designation for s in pm.registry.standards.values()}
    lang = getattr(args, "lang", None) or (lab.language if lab is not None else None)
    # core.outputs: never onto an input, an existing file only with --force; nothing left on failure
    path = write_checked(target, record.campaign, lambda p: write_report(
        p, record, template=info.path, layout=info.layout, designations=designations,
        extend=pm.extend_report_context, register=unregistered(record, why, lang or "zh+en"),
        lang=lang,
        pdf=getattr(args, "pdf", False)),
        force=getattr(args, "force", False), option="--report" if args.report else "--out",
        pdf=getattr(args, "pdf", False))
    record.timings["write report"] = time.perf_counter() - t0
    pm.report_written(path, record.outcomes)
    from ..record.registering import NOT_REGISTERED

    return record, path, {"registered": False, "number": record.report_number,
                          "why": NOT_REGISTERED[why][1]}


class FiguresAhead:
    """A run's figures drawn ahead (:class:`metro.core.documents.figure_cache.DrawingAhead`): each
    item's figures, in the report's language, go to the drawing process as soon as the item is
    evaluated (the ``metro_procedure_finished`` hook), while the next items are evaluated."""

    def __init__(self, ahead: Any, lang: str | None) -> None:
        from ..base.locale import translator

        self.ahead = ahead
        self.tr = translator(lang)

    @hookimpl
    def metro_procedure_finished(self, procedure: Any, outcome: Any) -> None:
        """Hand the item's figures to the drawing process."""
        from ..documents import plots

        for spec in outcome.plots:
            self.ahead.submit(plots.localized(spec, self.tr))


def drawing_ahead(args, pm, n_items: int):
    """A context manager for ``metro run``: the figures drawn in a second process while the items
    are evaluated, when a report will be written and there are several items (a single item's
    evaluation is too short to hide the drawing process's start), else nothing."""
    import contextlib

    from ..documents.figure_cache import DrawingAhead

    if args.no_report or not (args.run_all or n_items >= 3):
        return contextlib.nullcontext()
    try:
        from ..record import lab as labmod

        lab = labmod.lab_in_force(getattr(args, "lab", None))
    except Exception:  # noqa: BLE001 — a bad lab profile is reported where the report is written
        return contextlib.nullcontext()
    lang = getattr(args, "lang", None) or (lab.language if lab is not None else None)
    figures = FiguresAhead(DrawingAhead(), lang)
    stack = contextlib.ExitStack()
    stack.enter_context(figures.ahead)
    name = pm.pm.register(figures, name="metro-figures-ahead")
    stack.callback(pm.pm.unregister, name=name)
    return stack


def run_lab_options(args) -> dict[str, Any]:
    """Keyword arguments of :func:`metro.core.run.runner.run_items` from the lab profile in force:
    its equipment by id (a manifest may name it by id alone) and the refusal of equipment past
    its due date on the measurement date (unless ``--allow-expired``), before any evaluation."""
    from ..record import lab as labmod

    from ..base.errors import MetroError

    lab = labmod.lab_in_force(getattr(args, "lab", None))
    if lab is None:
        if getattr(args, "register_simulated", False):  # said before anything is evaluated
            raise MetroError("--register-simulated needs a lab profile (its register and numbering "
                             "scheme)",
                             hint="give --lab PATH or METRO_LAB; `metro lab init PATH` writes a "
                             "template")
        return {}

    def check(campaign) -> None:
        import datetime as dt

        from ..record.registering import check_equipment

        registered = not getattr(args, "no_report", False) and (
            not campaign.simulated or getattr(args, "register_simulated", False))
        if registered and getattr(args, "report", None):
            from .dcc_commands import registered_report_error

            raise registered_report_error(args)
        on = getattr(campaign, "measurement_date", None) or dt.datetime.now(dt.timezone.utc).date()
        check_equipment(campaign, on, allow_expired=getattr(args, "allow_expired", False))

    return {"lab_equipment": lab.equipment_by_id(), "check_campaign": check}


def _run_options(args) -> dict[str, Any]:
    from .common import parse_options

    return parse_options(getattr(args, "option", []) or [])


# ----------------------------------------------------------------------------------------
# register commands
# ----------------------------------------------------------------------------------------


def _lab(args, required: bool = False):
    from ..record import lab as labmod
    from ..base.errors import MetroError

    lab = labmod.lab_in_force(getattr(args, "lab", None))
    if lab is None and required:
        raise MetroError(f"metro {args.command} needs a lab profile (its numbering scheme and "
                         "register)",
                         hint="give --lab PATH or METRO_LAB; `metro lab init PATH` writes a "
                         "template")
    return lab


def register_url(args) -> str:
    """The register in force: the lab profile's (``METRO_REGISTER`` first), else the default one in
    the user data folder.  Only the profile's identity is read (its equipment needs pint)."""
    import os

    from ..record import lab as labmod

    lab = labmod.lab_in_force(getattr(args, "lab", None), equipment=False)
    return lab.register_url() if lab is not None else (os.environ.get(labmod.ENV_REGISTER)
                                                       or labmod.default_register_url())


def _open(args):
    """The register in force, which must exist: these commands read it or change a report's
    status, and never create one (only a registered run does)."""
    from ..record.register import open_register

    return open_register(register_url(args), create=False)


def _date(text: str | None, field: str):
    import datetime as dt

    from ..base.errors import MetroError

    if text is None:
        return None
    try:
        return dt.date.fromisoformat(text)
    except ValueError as exc:
        raise MetroError(f"{field} {text!r} is not a date (YYYY-MM-DD)") from exc


def _is_terminal() -> bool:
    import sys

    return sys.stdout.isatty()


def _table(title: str, cols, rows) -> None:
    """A table of the register: on a terminal a rich table whose cells wrap (an identifier is
    folded, never cut to "stand…"); piped or redirected, plain rows for scripts: a ``# title`` line,
    the header, then one line per row, cells separated by a tab, nothing padded, every value
    whole."""
    cells = [[("—" if v in (None, "") else str(v)) for v in r] for r in rows]
    if not _is_terminal():
        import sys

        def line(values) -> str:
            # one line per row, no tab inside a cell
            return "\t".join(" ".join(v.split()) for v in values)

        sys.stdout.write("\n".join([f"# {title}", line(cols), *(line(r) for r in cells)]) + "\n")
        return
    from rich.console import Console
    from rich.table import Table

    console = Console()
    # short identifiers (a report number, a date: up to 13 characters) are kept on one line when the
    # terminal is wide enough for all of them; else a cell folds onto the next line, never cut to
    # "stand…"
    short = [min(13, max([len(c)] + [len(r[i]) for r in cells])) for i, c in enumerate(cols)]
    # cells, their padding, the lines between them
    keep = sum(short) + 3 * len(cols) - 1 <= console.width
    t = Table(title=title, show_edge=False)  # no outer frame: two more columns for the cells
    for i, c in enumerate(cols):
        t.add_column(c, overflow="fold", no_wrap=False, min_width=short[i] if keep else None)
    for r in cells:
        t.add_row(*r)
    console.print(t)


def _cmd_list(args) -> int:
    with _open(args) as reg:
        rows = reg.list(device=args.device, standard=args.standard,
                        since=_date(args.since, "--since"))
        if args.json:
            _print_json({"register": reg.display_url, "reports": rows})
            return 0
        _table(f"register {reg.display_url}", ("number", "status", "standard", "items", "serial",
                                                "measured", "issued", "replaces / replaced by"),
               [(r["number"], r["status"], r["standard"], ", ".join(r["items"]),
                 r["device"]["serial"], r["measurement_date"], r["issued_at"][:10],
                 " / ".join(x or "—" for x in (r["supersedes"], r["superseded_by"]))
                 if (r["supersedes"] or r["superseded_by"]) else "") for r in rows])
    return 0


def _cmd_show(args) -> int:
    with _open(args) as reg:
        d = reg.get(args.number)
    if args.json:
        _print_json(d)
        return 0
    from rich.console import Console

    c = Console(soft_wrap=not _is_terminal())  # piped: each line whole (no wrapping at 80 columns)
    c.print(f"[bold]{d['number']}[/] — {d['status']}"
            + (f" (reason: {d['reason']})" if d["reason"] else ""))
    for label, key in (("replaces", "supersedes"), ("replaced by", "superseded_by")):
        if d[key]:
            c.print(f"  {label}: {d[key]}")
    dev = d["device"]
    c.print(f"  {d['standard']} {', '.join(d['items'])}; device {dev['manufacturer']} "
            f"{dev['model']} s/n {dev['serial']}; customer {d['customer'] or '—'}")
    c.print(f"  measured {d['measurement_date']}, issued {d['issued_at']} by {d['issued_by']}"
            + (" — SIMULATED" if d["simulated"] else "")
            + (" — issued with --allow-expired" if d["allow_expired"]
                                                            else ""))
    c.print(f"  file {d['report_path']} (sha256 {d['report_sha256']})")
    if d.get("dcc_path"):
        c.print(f"  DCC {d['dcc_path']} (sha256 {d['dcc_sha256']})")
    _table("results", ("item", "quantity", "value", "U", "k", "ν_eff", "unit", "reportable"),
           [(x["item"], f"{x['quantity']} {x['symbol']}", x["reported"]["value"],
             x["reported"]["U"],
             x["k"] and f"{x['k']:.3g}", x["nu_eff"] and f"{x['nu_eff']:.3g}", x["unit"],
             "yes" if x["reportable"] else f"no: {x['reason']}") for x in d["results"]])
    _table("equipment (status on the measurement date)",
           ("id", "role", "certificate", "due", "status"),
           [(e["id"], e["role"], e["certificate"], e["due"], e["status"]) for e in d["equipment"]])
    _table("audit trail", ("when", "who", "what", "detail"),
           [(a["at"], a["who"], a["action"], a["detail"]) for a in d["audit"]])
    return 0


def _cmd_verify(args) -> int:
    with _open(args) as reg:
        checks = reg.verify()
        bad = [c for c in checks if c["check"] != "ok"]
        if args.json:
            _print_json({"register": reg.display_url, "ok": not bad, "reports": checks})
        else:
            _table(f"verify {reg.display_url}", ("number", "status", "check", "file"),
                   [(c["number"], c["status"], c["check"], c["path"]) for c in checks])
            import sys

            print(f"{len(checks) - len(bad)} of {len(checks)} report files match their SHA-256"
                  + (f"; {len(bad)} do not: " + ", ".join(
                      f"{c['number']}{' DCC' if c['file'] == 'dcc' else ''} {c['check']}"
                      for c in bad) if bad else ""),
                  file=sys.stderr)
    from .common import EXIT_CHECK_FAILED, EXIT_OK

    return EXIT_CHECK_FAILED if bad else EXIT_OK


def _cmd_report(args) -> int:
    from .common import plugin_manager
    from ..record.registering import rerender, template_changed

    if args.format == "dcc":
        from .dcc_commands import cmd_report_dcc

        with _open(args) as reg:
            return cmd_report_dcc(args, reg, plugin_manager(args))
    pm = plugin_manager(args)
    with _open(args) as reg:
        path = rerender(reg, args.number, args.out, pm=pm)
        changed = template_changed(reg, args.number, pm)
    if args.json:
        _print_json({"number": args.number, "report": str(path), "template_changed": changed})
    else:
        if changed:
            import sys

            print(f"metro: warning: the template of {args.number} changed since it was issued: "
                  "same content, new layout", file=sys.stderr)
        print(path)
    return 0


def _cmd_amend(args) -> int:
    from .common import plugin_manager
    from ..record.registering import amend

    lab = _lab(args, required=True)
    pm = plugin_manager(args)
    with _open(args) as reg:
        record = None
        if args.data:
            from ..run.runner import run_items

            old = reg.get(args.number)
            given = old["options"].get("_given", {})
            record = run_items(pm, old["standard"], old["items"], data=args.data, options=given,
                               **run_lab_options(args))
        from ..record.dcc_out import amend_writer

        issued = amend(reg, args.number, args.reason, pm=pm, lab=lab, folder=args.out,
                       record=record,
                       allow_expired=args.allow_expired,
                       dcc=amend_writer(reg.get(args.number), args.format))
    from .dcc_commands import dcc_summary

    dcc = dcc_summary(issued.dcc_path, issued.dcc_sha256)
    if args.json:
        _print_json({"number": issued.number, "supersedes": args.number, "reason": args.reason,
                     "report": str(issued.path), "sha256": issued.sha256}
                    | ({"dcc": dcc} if dcc else {}))
    else:
        print(f"{issued.number} issued ({issued.path}"
              + (f"; DCC {issued.dcc_path}" if dcc else "")
              + f"); {args.number} is superseded by it")
    return 0


def _cmd_withdraw(args) -> int:
    with _open(args) as reg:
        reg.withdraw(args.number, args.reason)
    if args.json:
        _print_json({"number": args.number, "status": "withdrawn", "reason": args.reason})
    else:
        print(f"{args.number} withdrawn: {args.reason}")
    return 0


def _cmd_history(args) -> int:
    from pathlib import Path

    from ..record.registering import history, history_plot

    with _open(args) as reg:
        hist = history(reg, args.serial, keys=args.key or None)
    from ..base.errors import MetroError

    if not hist["calibrations"]:
        raise MetroError(
            f"no issued report of a device with serial {args.serial!r} in the register",
                         hint="`metro register list` shows the devices' serial numbers")
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    safe = "".join(ch if ch.isalnum() or ch in "-_." else "_" for ch in args.serial)
    png = history_plot(hist, out / f"history-{safe}.png")
    hist["plot"] = str(png)
    if args.json:
        _print_json(hist)
        return 0
    _table(f"calibrations of {args.serial}", ("number", "standard", "items", "measured", "issued"),
           [(c["number"], c["standard"], ", ".join(c["items"]), c["measurement_date"],
             c["issued_at"][:10])
            for c in hist["calibrations"]])
    rows = []
    for res in hist["results"]:
        for p in res["points"]:
            en = p.get("E_n")
            rows.append((f"{res['item']} {res['symbol'] or res['key']}", p["number"], p["date"],
                         p["reported"]["value"], p["reported"]["U"], res["unit"],
                         "—" if en is None else f"{en:.2f}", "DRIFT" if p.get("drift") else ""))
    _table("results over time (E_n against the previous calibration)",
           ("result", "report", "measured", "value", "U", "unit", "|E_n|", "drift"), rows)
    print(f"plot: {png}")
    return 0


def _print_json(doc: Any) -> None:
    from .schemas import print_json

    print_json(doc)


def _cmd_lab(args) -> int:
    from ..record import lab as labmod
    from ..base.errors import MetroError

    if args.lab_command == "equipment":
        from .lab_commands import equipment_command

        return equipment_command(args)
    if args.lab_command == "init":
        path = labmod.write_template(args.path)
        if args.json:
            _print_json({"written": str(path)})
        else:
            print(f"lab profile template written: {path} (edit it, then `metro --lab {path} lab "
                  "show`)")
        return 0
    where = labmod.find_lab_path(args.lab)
    if where is None:
        raise MetroError("no lab profile in force",
                         hint="give --lab PATH or METRO_LAB, or put lab.toml in "
                         f"{labmod.user_lab_path().parent}; `metro lab init PATH` writes a "
                         "template")
    profile = labmod.load_lab(where)
    doc = profile.as_dict()
    if args.json:  # each certificate's U as {"value", "unit"} (docs/json.md), not as its text
        _print_json(doc | {"equipment": [
            e | {"U": None if eq.calibration is None else eq.calibration.uncertainty}
            for e, eq in zip(doc["equipment"], profile.equipment)]})
        return 0
    from rich.console import Console
    from rich.table import Table

    c = Console()
    c.print(f"[bold]lab profile[/] {doc['source']}")
    t = Table(show_header=False)
    for key in ("name_zh", "name_en", "address", "accreditation_body", "accreditation_number",
                "logo",
                "language", "timezone", "register"):
        t.add_row(key, str(doc[key] or "—"))
    n = doc["numbering"]
    t.add_row("numbering", f"{n['scheme']} (prefix {n['prefix']}; e.g. {n['example']}"
              + ("; restarts each year)" if n["per_year"] else ")"))
    c.print(t)
    ts = Table(title="signatories")
    for col in ("name", "title", "role"):
        ts.add_column(col)
    for s in doc["signatories"]:
        ts.add_row(s["name"], s["title"] or "—", s["role"])
    c.print(ts)
    te = Table(title="equipment")
    for col in ("id", "role", "certificate", "U", "k", "due", "distribution"):
        te.add_column(col)
    for e in doc["equipment"]:
        te.add_row(e["id"], e["role"], e["certificate"] or "—", e["U"] or "—", str(e["k"]),
                   e["due"] or "—",
                   e["distribution"] or "—")
    c.print(te)
    return 0

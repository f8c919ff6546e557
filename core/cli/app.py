"""The ``metro`` command line.

Start-up is kept fast: only argparse is imported here at module level; numpy, pint,
scipy, docxtpl and the plugins load when a command needs them.
"""

from __future__ import annotations

import argparse
import os
import sys
from typing import Any, Sequence

from .common import (  # noqa: F401 — the exit codes and helpers are metro.core.cli.app's too
    EXIT_BROKEN_PIPE,
    EXIT_CAMPAIGN_FAILED,
    EXIT_CHECK_FAILED,
    EXIT_INDETERMINATE,
    EXIT_INTERRUPTED,
    EXIT_NONCONFORMING,
    EXIT_OK,
    EXIT_USER_ERROR,
    did_you_mean,
    exit_code_for,
    parse_options,
    plugin_manager,
    requested_items,
    resolve_items,
    resolve_standard,
    show_progress,
    split_items,
)

EXIT_CODES_TEXT = (
    "exit codes: 0 done, conforming or nothing to judge; 2 usage or data error; 3 does not "
    "conform; 4 indeterminate (nothing fails, some verdict is indeterminate); 5 batch: a campaign "
    "failed; 6 a check found a problem (register verify, doctor, validate); 130 interrupted; "
    "1 is an internal error (a bug: please report the traceback)."
)
#: `metro run` only: what its --strict changes
SIMULATED_EXIT_TEXT = ("  A run on the simulated station judges a virtual device: it exits 0 once "
                       "evaluated unless --strict")


class _Parser(argparse.ArgumentParser):
    """argparse with "did you mean" for a mistyped command or choice."""

    def error(self, message: str):  # type: ignore[override]
        import difflib
        import re

        m = re.search(r"invalid choice: '([^']*)' \(choose from (.*)\)", message)
        if m:
            choices = re.findall(r"'([^']*)'", m.group(2))
            close = difflib.get_close_matches(m.group(1), choices, n=1, cutoff=0.5)
            if close:
                message += f"; did you mean {close[0]!r}?"
        super().error(message)


def build_parser() -> argparse.ArgumentParser:
    """The parser of the whole `metro` command line (every command and its options)."""
    p = _Parser(
        prog="metro",
        description="Calibrate and test inertial sensors to published standards "
        "(GB/T 45570, JJF 2014, JJF 2003 …). Standards are plugins.",
        epilog="Example: metro run --standard gbt45570 --item D.5.6   "
        "(no --data: runs on the built-in simulated test station).  " + EXIT_CODES_TEXT
        + SIMULATED_EXIT_TEXT,
    )
    p.add_argument("--version", action="store_true",
                   help="print metro's version and the loaded plugins' versions")
    p.add_argument("--no-plugin-autoload", action="store_true",
                   help="load only metro's built-in plugins (also METRO_DISABLE_PLUGIN_AUTOLOAD=1)")
    p.add_argument("--block-plugin", action="append", default=[], metavar="NAME",
                   help="do not load the plugin NAME (repeatable; also METRO_BLOCK_PLUGINS=a,b)")
    # lab profile and report register commands (their own module)
    from . import register_commands as cli_register

    cli_register.add_global_options(p)
    sub = p.add_subparsers(dest="command", metavar="COMMAND", parser_class=_Parser)

    _add_run(sub)
    pl = sub.add_parser("plugins",
                        help="list loaded plugins and their versions, stations and drivers")
    pl.add_argument("--json", action="store_true")

    it = sub.add_parser("items", help="list the items of the loaded standards")
    it.add_argument("--standard", "-s", help="only this standard's items")
    it.add_argument("--json", action="store_true")

    pn = sub.add_parser("plan",
                        help="print items' test sequence (what to measure) and its total duration")
    pn.add_argument("--standard", "-s", help="standard id (may be left out with std:item ids)")
    pn.add_argument("--item", "-i", action="append", default=[], help="item ids or a series name")
    pn.add_argument("--all", action="store_true", dest="run_all",
                    help="every item of the standard that applies to the simulated station's "
                    "device")
    pn.add_argument("--json", action="store_true")

    aq = sub.add_parser("acquire",
                        help="run items' test sequence on a station and write the campaign",
                        description="Acquire the merged test sequence of one or more items on a "
                        "station (simulated or live) and write it as a campaign folder "
                        "(manifest.toml + samples, docs/data-format.md) that `metro run --data "
                        "DIR/manifest.toml` evaluates.")
    aq.add_argument("--standard", "-s", required=True, help="standard id, e.g. gbt45570")
    aq.add_argument("--item", "-i", action="append", default=[],
                    help="item id or series name, e.g. scale-factor (repeat or comma-separate for "
                    "several; shared steps are measured once)")
    aq.add_argument("--all", action="store_true", dest="run_all",
                    help="acquire every item of the standard that applies to the station's device")
    aq.add_argument("--station", help="registered station (default: the items' simulated station)")
    aq.add_argument("--out", required=True, metavar="DIR",
                    help="campaign folder to create (must not exist "
                    "or be empty)")
    aq.add_argument("--option", "-o", action="append", default=[], metavar="NAME=VALUE",
                    help="item option")
    aq.add_argument("--seed", type=int, help="seed of a simulated station")
    aq.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE",
                    help="station option, e.g. duration_scale=0.1 (numbers are read as numbers)")
    aq.add_argument("--npy-rows", type=int, default=None, metavar="N",
                    help="segments of N rows or more are written as .npy (default 100000), shorter "
                    "as CSV")
    _progress_args(aq)
    cli_register.add_commands(sub)

    _add_batch(sub)
    from . import doctor

    doctor.add_command(sub)
    from . import validate_command

    validate_command.add_command(sub)
    from . import serve_command

    serve_command.add_command(sub)
    _share_global_options(p)
    return p


def _add_run(sub: Any) -> None:
    """``metro run``: its options."""
    from . import register_commands as cli_register

    r = sub.add_parser("run", help="evaluate one or more items of a standard",
                       description="Evaluate items of a standard on a campaign (--data) or, "
                       "without --data, on the built-in simulated test station.",
                       epilog='Example: metro run -s gbt45570 -i D.5.6 -o min_blocks=20   '
                       + EXIT_CODES_TEXT
                       + SIMULATED_EXIT_TEXT)
    r.add_argument("--standard", "-s",
                   help="standard id, e.g. gbt45570 (case does not matter; may be left out "
                   "when every item is written std:item, as `metro items` prints them)")
    r.add_argument("--item", "-i", action="append", default=[],
                   help="item id, e.g. D.5.6 or gbt45570:D.5.6, or a series name, e.g. "
                   "scale-factor (repeat or comma-separate)")
    r.add_argument("--all", action="store_true", dest="run_all",
                   help="run every item of the standard that applies to the device")
    r.add_argument("--decision-rule", choices=("guarded", "simple"),
                   help="conformity decision rule (default: the manifest's, else guarded: w = U)")
    r.add_argument("--data", "-d", metavar="MANIFEST",
                   help="campaign manifest (TOML); see docs/data-format.md")
    r.add_argument("--option", "-o", action="append", default=[], metavar="NAME=VALUE",
                   help="item option, e.g. -o min_blocks=20 (D.5.6) or -o t=\"10 s, 100 s\" "
                   "(D.5.2); `metro items` lists them")
    r.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    from .dcc_commands import OutGiven, add_format_option

    r.add_argument("--out", default="metro-out", metavar="DIR", action=OutGiven,
                   help="where the Word report goes (default: metro-out)")
    r.add_argument("--report", metavar="PATH",
                   help="write the report to PATH instead; its suffix decides the format: .docx "
                   "Word, .pdf PDF, .xml a DCC (docs/dcc.md)")
    add_format_option(r, "the report's format")
    r.add_argument("--no-report", action="store_true", help="do not write a Word report")
    r.add_argument("--force", action="store_true",
                   help="replace an existing report file (never an input of "
                   "the run, never a read-only file)")
    r.add_argument("--pdf", action="store_true",
                   help="also write the report as PDF (through LibreOffice); a --report path "
                   "ending in .pdf writes the PDF only")
    r.add_argument("--lang", choices=("zh", "en", "zh+en"),
                   help="language of the report (default: the lab profile's, else zh+en)")
    r.add_argument("--seed", type=int, help="seed of the simulated station (no --data)")
    r.add_argument("--monte-carlo", action="store_true",
                   help="check every budget by Monte Carlo (JCGM 101): its u and shortest "
                   "interval beside GUM's, and whether GUM's interval is validated "
                   "(docs/monte-carlo.md)")
    r.add_argument("--strict", action="store_true",
                   help="on the simulated station too, exit 3/4 when the virtual device does not "
                   "conform or is indeterminate (recorded data always do)")
    r.add_argument("--station",
                   help="station to acquire on when no --data is given (default: the item's "
                   "simulated station)")
    r.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE",
                   help="station option when no --data is given, e.g. table_errors=false (as for "
                   "`metro acquire`)")
    _output_args(r)
    cli_register.add_run_options(r)


def _add_batch(sub: Any) -> None:
    """``metro batch``: its options."""
    from . import register_commands as cli_register

    b = sub.add_parser("batch",
                       help="evaluate many device campaigns (a production lot) on a Dask cluster",
                       description="Evaluate the same items on many recorded campaigns, one per "
                       "device, on a dask.distributed cluster: a local cluster of processes by "
                       "default, or an existing one (--scheduler). Each device gets its own report "
                       "exactly as `metro run --data` would write it; a campaign that fails is "
                       "listed with its error and the others go on; a batch run again with the "
                       "same --out skips the campaigns already evaluated (same manifest SHA-256). "
                       "The lot summary (all results as CSV and Parquet, statistics and yield per "
                       "quantity, histograms, a one-page lot report) goes to --out.",
                       epilog="Example: metro batch -s gbt45570 -i D.5.1,D.5.2 --data "
                       "'lot-7/*/manifest.toml' --workers 2 --out lot-7-out   " + EXIT_CODES_TEXT)
    b.add_argument("--standard", "-s", help="standard id (may be left out with std:item ids)")
    b.add_argument("--item", "-i", action="append", default=[],
                   help="item ids or series (repeat or comma-separate)")
    b.add_argument("--all", action="store_true", dest="run_all",
                   help="every item that applies to each device")
    b.add_argument("--data", "-d", action="append", default=[], required=True,
                   metavar="GLOB_OR_LIST",
                   help="campaigns: manifest files or campaign folders, a glob (quote it), or a "
                   "comma-separated list; repeatable")
    b.add_argument("--scheduler", metavar="ADDRESS",
                   help="an existing Dask scheduler, e.g. tcp://host:8786 "
                   "(workers must see --data and --out at the same paths); default: a local "
                   "cluster")
    b.add_argument("--workers", type=int, metavar="N", help="worker processes of the local cluster "
                   "(default: the number of CPUs)")
    b.add_argument("--out", default="metro-batch", metavar="DIR",
                   help="reports, lot summary and the resume "
                   "state (default: metro-batch)")
    b.add_argument("--option", "-o", action="append", default=[], metavar="NAME=VALUE",
                   help="item option")
    b.add_argument("--decision-rule", choices=("guarded", "simple"),
                   help="conformity decision rule")
    b.add_argument("--json", action="store_true",
                   help="print the lot summary as one JSON document on stdout")
    b.add_argument("--pdf", action="store_true",
                   help="also write each device's report as PDF (through LibreOffice)")
    b.add_argument("--lang", choices=("zh", "en", "zh+en"),
                   help="language of the reports (default: the lab profile's, else zh+en)")
    _output_args(b)
    cli_register.add_run_options(b)  # each device registered as `metro run` registers it (--lab)


#: the global options a command's own parser accepts too, after the command
#: (``metro register list --lab lab.toml``, as git and pytest users write them)
_SHARED_GLOBALS = ("--lab", "--no-plugin-autoload", "--block-plugin")


def _share_global_options(parser: argparse.ArgumentParser) -> None:
    """Every command's parser (and a command's subcommands) gets the global options with no
    default of its own (``SUPPRESS``), so a value given before the command is kept and one given
    after it is read; ``--block-plugin`` given after goes to ``block_plugin_after`` (added to the
    ones before it by :func:`_main`)."""
    top = {o: a for a in parser._actions for o in a.option_strings if o in _SHARED_GLOBALS}
    stack = [parser]
    while stack:
        for action in stack.pop()._actions:
            if not isinstance(action, argparse._SubParsersAction):
                continue
            for sub in dict.fromkeys(action.choices.values()):  # each parser once (aliases)
                group = sub.add_argument_group("global options (also accepted before the command)")
                for opt, a in top.items():
                    kw: dict[str, Any] = {"default": argparse.SUPPRESS, "help": a.help}
                    if isinstance(a, argparse._AppendAction):
                        kw.update(action="append", dest=a.dest + "_after", metavar=a.metavar)
                    elif isinstance(a, argparse._StoreTrueAction):
                        kw.update(action="store_true")
                    else:
                        kw.update(metavar=a.metavar)
                    group.add_argument(opt, **kw)
                stack.append(sub)


def _progress_args(p: argparse.ArgumentParser) -> None:
    """--quiet and --no-progress, the same on every command that shows progress (run, batch,
    acquire)."""
    p.add_argument("--quiet", "-q", action="store_true",
                   help="no progress display and no messages on stderr (errors and warnings still)")
    p.add_argument("--no-progress", action="store_true", help="no progress display")


def _output_args(p: argparse.ArgumentParser) -> None:
    _progress_args(p)
    p.add_argument("--verbose", "-v", action="store_true",
                   help="also print budgets, tables, item selection, truth checks and data file "
                   "hashes")


def _unknown_arguments(parser: argparse.ArgumentParser, command: str | None,
                       extra: Sequence[str]) -> None:
    """argparse's "unrecognized arguments" from the command's own parser, with suggestions."""
    target = parser
    for a in parser._actions:
        if isinstance(a, argparse._SubParsersAction) and command in a.choices:
            target = a.choices[command]
    names = [o for a in target._actions for o in a.option_strings if o.startswith("--")]
    msg = "unrecognized arguments: " + " ".join(extra)
    for word in extra:
        if word.startswith("-"):
            word = word.split("=", 1)[0]
            msg += did_you_mean(word, names).replace("; did you mean", f"; {word}: did you mean")
    target.error(msg)


class _Banner:
    """The SIMULATED-station banner on stderr, printed once, when work starts (so a usage error
    is never preceded by it) or, at the latest, before the results."""

    def __init__(self, text: str | None) -> None:
        self.text = text

    def __call__(self) -> None:
        if self.text:
            from rich.console import Console

            Console(stderr=True).print(self.text)
            self.text = None


def main(argv: Sequence[str] | None = None) -> int:
    try:
        code = _main(argv)
        sys.stdout.flush()  # a closed pipe is found here, not at interpreter exit
        return code
    except BrokenPipeError:
        # `metro plan … | head`: the reader stopped; no traceback, no "Exception ignored" at exit
        devnull = os.open(os.devnull, os.O_WRONLY)
        os.dup2(devnull, sys.stdout.fileno())
        return EXIT_BROKEN_PIPE
    except SystemExit as exc:  # argparse: --help (0) and usage errors (2)
        # rich's own broken-pipe exit (Console.on_broken_pipe)
        if exc.code == 1 and _stdout_is_devnull():
            return EXIT_BROKEN_PIPE
        return exc.code if isinstance(exc.code, int) else EXIT_USER_ERROR


def _stdout_is_devnull() -> bool:
    try:
        a, b = os.fstat(sys.stdout.fileno()), os.stat(os.devnull)
    except (OSError, ValueError, AttributeError):
        return False
    return (a.st_dev, a.st_ino) == (b.st_dev, b.st_ino)


def _main(argv: Sequence[str] | None) -> int:
    parser = build_parser()
    args, extra = parser.parse_known_args(argv)
    if extra:
        _unknown_arguments(parser, args.command, extra)
    args.block_plugin = [*args.block_plugin, *getattr(args, "block_plugin_after", [])]
    from ..base.errors import MetroError

    try:
        if args.version:
            return _cmd_version(args)
        if args.command is None:
            parser.print_help()
            return 0
        command = {"run": _cmd_run, "plugins": _cmd_plugins, "items": _cmd_items,
                   "plan": _cmd_plan, "acquire": _cmd_acquire, "batch": _cmd_batch}
        if args.command in command:
            return command[args.command](args)
        if args.command == "doctor":
            from .doctor import command

            return command(args)
        if args.command == "validate":
            from .validate_command import command as validate

            return validate(args)
        if args.command == "serve":
            from .serve_command import command as serve

            return serve(args)
        from . import register_commands as cli_register

        if args.command in cli_register.COMMANDS:
            return cli_register.dispatch(args)
    except MetroError as exc:
        if getattr(args, "json", False):  # one line (core/cli/schemas/error.schema.json)
            from .schemas import print_json

            print_json({"error": type(exc).__name__, "message": exc.reason, "hint": exc.hint,
                        "file": getattr(exc, "file", None), "field": getattr(exc, "field", None)},
                       indent=None)
        print(f"metro: error: {exc.reason}", file=sys.stderr)
        if exc.hint:
            print(f"  what to do: {exc.hint}", file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        if args.command == "batch":
            print(f"metro: interrupted; the campaigns finished so far are kept in {args.out} (the "
                  "same command resumes the batch)", file=sys.stderr)
        else:
            print("metro: interrupted; nothing was written", file=sys.stderr)
        return EXIT_INTERRUPTED
    raise AssertionError(f"command {args.command!r} has no handler")  # pragma: no cover


def _cmd_version(args) -> int:
    from .. import __version__

    print(f"metro {__version__}")
    from ..run.plugin_manager import MetroPluginManager

    # the plugins loaded as every command loads them, without their registration (their items'
    # modules): the versions are the distributions'
    pm = MetroPluginManager().load(autoload=False if args.no_plugin_autoload else None,
                                   block=args.block_plugin)
    for name, info in sorted(pm.plugins.items()):
        where = info.distribution or info.module
        print(f"  plugin {name}: {where} {info.version or ''}".rstrip())
    return 0


# ----------------------------------------------------------------------------------------


SIMULATED_BANNER = ("[bold yellow]No --data given: running on {stations}; a SIMULATED station's "
                    "device is virtual, with declared, seeded truth.[/]")


def station_banner(pm, args, items: Sequence[str]) -> str:
    """:data:`SIMULATED_BANNER` naming the station(s) a run without ``--data`` uses: ``--station``,
    else the ``station`` of each item (of a series' members; of every item for ``--all``), each
    with the plugin that registered it and its description."""
    from rich.markup import escape

    names = {args.station} if args.station else set()
    if not names:
        procs = []
        for i in items:
            ser = pm.series(args.standard, i)
            procs += [pm.procedure(args.standard, m) for m in ser.members] if ser else [
                pm.procedure(args.standard, i)]
        if args.run_all:
            procs += pm.procedures_of(args.standard)
        names = {cls.station for cls in procs} or {"simulated"}
    infos = [pm.station(n) for n in sorted(names)]
    what = "; ".join(f"station {i.name!r} of plugin {i.plugin}"
                     + (f" ({i.description})" if i.description else "") for i in infos)
    return SIMULATED_BANNER.format(stations=escape(what))


def _cmd_run(args) -> int:
    from . import present
    from ..run.runner import run_items

    pm = plugin_manager(args)
    items = requested_items(pm, args)
    options = parse_options(args.option)
    station_options = _station_options(args)
    if args.data is not None and (station_options or args.station):
        from ..base.errors import MetroError

        given = ", ".join(x for x, on in (("--station", args.station),
                                          ("--seed", args.seed is not None),
                                          ("--station-option", bool(args.station_option))) if on)
        raise MetroError(f"{given} acts on a station, and --data {args.data} was recorded already",
                         hint="drop --data to run on a station, or drop the station arguments to "
                         "evaluate the data")
    from .dcc_commands import check_run
    from ..run.outputs import manifest_inputs

    # checked before anything is evaluated (core.outputs; a DCC: core/cli/dcc_commands.py)
    if not check_run(args, manifest_inputs(args.data)) and not args.no_report:
        from ..run.outputs import plan_report

        plan_report(args.report, args.out, force=args.force, inputs=manifest_inputs(args.data),
                    pdf=getattr(args, "pdf", False))
        if getattr(args, "pdf", False) or str(args.report or "").lower().endswith(".pdf"):
            from ..documents.pdf import soffice_path

            soffice_path()  # no LibreOffice: said now, before anything is evaluated
    banner = _Banner(station_banner(pm, args, items)
                     if args.data is None and not args.json and not args.quiet else None)
    from .register_commands import drawing_ahead

    with drawing_ahead(args, pm, len(items)), present.progress(enabled=show_progress(args),
                                                               started=banner) as prog:
        record = run_items(pm, args.standard, items, data=args.data, options=options,
                           station=args.station,
                           station_options=station_options, progress=prog, run_all=args.run_all,
                           decision_rule=args.decision_rule, **_lab_options(args))
        if getattr(args, "monte_carlo", False):  # JCGM 101 clause 8 (core/run/montecarlo_run.py)
            from ..run.montecarlo_run import with_monte_carlo

            record = with_monte_carlo(record, args.seed)
        for w in record.campaign.warnings:  # deprecated spellings, unknown keys (core.vocabulary)
            print(f"metro: warning: {w}", file=sys.stderr)
        report_path = registration = None
        # registered with a lab profile, else "not registered" (core/cli/register_commands.py)
        if not args.no_report:
            from .register_commands import write_run_report

            record, report_path, registration = write_run_report(args, pm, record, prog)
    banner()
    if args.json:
        from .schemas import print_json

        doc = present.as_json(record, report_path)
        doc["register"] = registration
        print_json(doc)
    else:
        from pathlib import Path

        pdf_path = None  # --pdf: the PDF goes beside the Word report (or DCC), under the same name
        if report_path is not None and getattr(args, "pdf", False) and Path(
                report_path).suffix.lower() in (".docx", ".xml"):
            pdf_path = Path(report_path).with_suffix(".pdf")
        present.print_record(record, report_path, verbose=args.verbose, pdf_path=pdf_path)
        if registration is not None and not args.quiet:
            from rich.console import Console

            Console(stderr=True).print(f"registered as {registration['number']}"
                                       if registration["registered"]
                                       else f"not registered ({registration['why']})")
            if registration.get("dcc"):
                Console(stderr=True, highlight=False, soft_wrap=True).print(  # one line
                    f"DCC {registration['dcc']['path']} (sha256 {registration['dcc']['sha256']})")
    a = record.conformity
    code = exit_code_for(a.overall.value if a is not None and a.overall is not None else None)
    if code != EXIT_OK and args.data is None and not args.strict:
        # the verdict is about the simulated station's virtual device, not a device under test: the
        # evaluation itself succeeded (the statement is printed, in --json and in the report)
        if not args.json and not args.quiet:
            print("metro: the verdict is about the simulated station's virtual device; exit code "
                  f"0 (--strict gives {code})", file=sys.stderr)
        return EXIT_OK
    return code


def _lab_options(args) -> dict[str, Any]:
    from .register_commands import run_lab_options  # the lab profile's equipment and due-date check

    return run_lab_options(args)


def _cmd_plugins(args) -> int:
    pm = plugin_manager(args)
    reg = pm.registry
    rows = []
    for name, info in sorted(pm.plugins.items()):
        stds = sorted(s.id for s in reg.standards.values() if s.plugin == name)
        n_items = sum(1 for p in reg.procedures.values() if p.plugin == name)
        rows.append({"name": name, "distribution": info.distribution, "version": info.version,
                     "builtin": info.builtin, "module": info.module, "standards": stds,
                     "items": n_items})
    stations = [{"name": st.name, "plugin": st.plugin, "description": st.description}
                for _, st in sorted(reg.stations.items())]
    drivers = [{"name": d.name, "kind": d.kind, "plugin": d.plugin, "description": d.description,
                "class": f"{d.cls.__module__}.{d.cls.__qualname__}"} for _, d
               in sorted(reg.drivers.items())]
    if args.json:
        from .schemas import print_json

        print_json({"plugins": rows, "stations": stations, "drivers": drivers,
                    "autoload": not (args.no_plugin_autoload
                                     or os.environ.get("METRO_DISABLE_PLUGIN_AUTOLOAD"))})
        return 0
    from rich.console import Console
    from rich.table import Table

    t = Table(title="metro plugins")
    for col in ("plugin", "distribution", "version", "built-in", "standards", "items"):
        t.add_column(col)
    for r in rows:
        t.add_row(r["name"], r["distribution"] or "-", r["version"] or "-", "yes" if r["builtin"]
                  else "no",
                  ", ".join(r["standards"]) or "-", str(r["items"]))
    console = Console()
    console.print(t)
    ts = Table(title="stations (metro acquire --station NAME)")
    for col in ("station", "plugin", "description"):
        ts.add_column(col)
    for st in stations:
        ts.add_row(st["name"], st["plugin"], st["description"] or "-")
    console.print(ts)
    td = Table(title="drivers (live instruments; a bench file names them)")
    for col in ("driver", "kind", "plugin", "description"):
        td.add_column(col)
    for d in drivers:
        td.add_row(d["name"], d["kind"], d["plugin"], d["description"] or "-")
    console.print(td)
    return 0


def _option_text(name: str, o: dict) -> str:
    """``name = default`` for `metro items` (just ``name`` when there is no default); a number
    gets the option's unit, a text default carries its own."""
    d = o["default"]
    if d is None or d == "":
        return name
    unit = f" {o['unit']}" if o["unit"] and isinstance(d,
                                                       (int,
                                                        float)) and not isinstance(d, bool) else ""
    return f"{name} = {d}{unit}"


def _cmd_items(args) -> int:
    pm = plugin_manager(args)
    rows = []
    from ..run.plugin_manager import item_sort_key

    std = resolve_standard(pm, args.standard) if args.standard else None
    for pid, info in sorted(pm.registry.procedures.items(), key=lambda kv: item_sort_key(kv[0])):
        cls = info.cls
        if std and cls.standard != std:
            continue
        rows.append({"id": pid, "standard": cls.standard, "item": cls.item, "title": cls.title,
                     "clause": cls.clause, "plugin": info.plugin,
                     "options": {o.name: {"default": o.default, "unit": o.unit,
                                          "description": o.description}
                                 for o in cls.options}})
    series = [{"id": key, "standard": ser.standard, "name": ser.name, "members": list(ser.members),
               "description": ser.description, "plugin": ser.plugin}
              for key, ser in sorted(pm.registry.series.items())
              if not std or ser.standard == std]
    if args.json:  # option defaults as JSON values: None is null, a quantity {"value", "unit"}
        from .schemas import print_json

        print_json({"items": rows, "series": series})
        return 0
    from rich.console import Console
    from rich.table import Table

    con = Console(highlight=False)
    standards = pm.registry.standards
    for sid in sorted({r["standard"] for r in rows}):
        info = standards[sid]
        con.print(f"[bold]{sid}[/] — {info.designation or info.title}"
                  + (f": {info.title}" if info.designation and info.title else ""))
        con.print(f"[dim]run as: metro run -s {sid} -i ITEM (or -i {sid}:ITEM)[/]")
        grid = Table.grid(padding=(0, 2))
        grid.add_column(no_wrap=True)
        grid.add_column(overflow="fold")
        for r in rows:
            if r["standard"] != sid:
                continue
            text = r["title"] + (f" (clause {r['clause']})" if r["clause"] != r["item"] else "")
            if r["options"]:
                text += "\n[dim]options:[/] " + ", ".join(_option_text(k, o) for k, o
                                                          in r["options"].items())
            grid.add_row(r["item"], text)
        con.print(grid)
        mine = [ser for ser in series if ser["standard"] == sid]
        if mine:  # `metro run -s S -i NAME` runs the members that apply to the device
            con.print("[dim]series (-i NAME runs the members that apply to the device):[/]")
            sg = Table.grid(padding=(0, 2))
            sg.add_column(no_wrap=True)
            sg.add_column(overflow="fold")
            for ser in mine:
                sg.add_row(ser["name"], ", ".join(ser["members"])
                           + (f" — {ser['description']}" if ser["description"] else ""))
            con.print(sg)
        con.print()
    con.print("[dim]`metro items --json` gives each option's unit and description[/]")
    return 0


def _cmd_plan(args) -> int:
    from ..run.runner import merge_steps, select_items, station_device

    pm = plugin_manager(args)
    items = requested_items(pm, args)
    if args.run_all or any(pm.series(args.standard, i) is not None for i in items):
        # a series or --all: the members that apply to the station's device
        cands = pm.procedures_of(args.standard)
        device = station_device(pm, cands[0].station if cands else "simulated", {})
        items, _ = select_items(pm, args.standard, items, device=device, run_all=args.run_all)
    procs = [pm.procedure(args.standard, i) for i in items]
    steps = merge_steps([cls().sequence(cls.option_values({})) for cls in procs])
    columns = _plan_columns(procs)
    rows = [{"segment": s.segment, "kind": s.kind, "duration": f"{s.duration:~P}",
             "interval": f"{s.interval:~P}",
             "warmup": f"{s.warmup:~P}" if s.warmup is not None else None,
             "conditions": {k: str(v) for k, v in s.conditions.items()},
             "columns": columns.get(s.kind, {}),
             "description": s.description}
            for s in steps]
    record_s = sum(float(s.duration.to("s").magnitude) for s in steps)
    warmup_s = sum(float(s.warmup.to("s").magnitude) for s in steps if s.warmup is not None)
    total = {"steps": len(steps), "items": list(items), "recording_s": record_s,
             "warmup_s": warmup_s,
             "total_s": record_s + warmup_s}
    if args.json:  # durations as {"value", "unit"}, conditions as JSON values (docs/json.md)
        from .schemas import print_json

        print_json({"steps": [r | {"duration": s.duration, "interval": s.interval,
                                   "warmup": s.warmup, "conditions": dict(s.conditions)}
                              for r, s in zip(rows, steps)], "total": total})
        return 0
    for i, r in enumerate(rows, 1):
        print(f"{i}. [{r['segment']}] {r['description']}")
        print(f"   kind={r['kind']} duration={r['duration']} interval={r['interval']}"
              + (f" warm-up≥{r['warmup']}" if r["warmup"] else "")
              + "".join(f" {k}={v}" for k, v in r["conditions"].items())
              + ("; columns: " + ", ".join(f"{c} [{' or '.join(u)}]" for c, u
                                           in r["columns"].items())
                 if r["columns"] else ""))
    print(f"total: {len(steps)} steps for {len(items)} item(s): {_duration(record_s)} of recording"
          + (f" + {_duration(warmup_s)} of warm-up = {_duration(record_s + warmup_s)}" if warmup_s
             else "")
          + " (set-up time between steps not included)")
    return 0


def _plan_columns(procs) -> dict[str, dict[str, list[str]]]:
    """Per segment kind, the samples-file columns the items read and the units each accepts
    (any unit of the same kind is read): the units every item reading that kind accepts, or all of
    them when the items differ (data-format.md: `metro plan` says what each segment needs)."""
    from ..base.units import fmt_unit, unit

    out: dict[str, dict[str, list[str]]] = {}
    for cls in procs:
        for req in cls.requires:
            per = out.setdefault(req.kind, {})
            for name, accepted in req.columns.items():
                acc = [fmt_unit(unit(a)) for a in accepted]
                have = per.get(name)
                if have is None:
                    per[name] = acc
                else:
                    both = [a for a in have if a in acc]
                    per[name] = both or have + [a for a in acc if a not in have]
    return out


def _duration(seconds: float) -> str:
    """``36 h 20 min`` / ``12 min 30 s`` / ``45 s``."""
    s = int(round(seconds))
    h, rem = divmod(s, 3600)
    m, sec = divmod(rem, 60)
    parts = [f"{h} h" if h else "", f"{m} min" if m else "", f"{sec} s" if sec and not h else ""]
    return " ".join(p for p in parts if p) or "0 s"


def _number(text: str) -> Any:
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def _station_options(args) -> dict[str, Any]:
    """--station-option NAME=VALUE (numbers read as numbers) and --seed, for the station's
    factory."""
    opts = {k: _number(v) for k, v in parse_options(args.station_option).items()}
    if args.seed is not None:
        opts["seed"] = args.seed
    return opts


def _cmd_acquire(args) -> int:
    from rich.console import Console

    from metro.core.run.manifest_writer import NPY_ROWS, acquire_campaign

    from . import present

    pm = plugin_manager(args)
    args.standard, items = resolve_items(pm, args.standard, split_items(args.item))
    station_options = _station_options(args)
    with present.progress(enabled=show_progress(args)) as prog:
        manifest = acquire_campaign(pm, args.standard, items, args.out, station=args.station,
                                    options=parse_options(args.option),
                                    station_options=station_options,
                                    npy_rows=args.npy_rows or NPY_ROWS, progress=prog,
                                    run_all=args.run_all)
    if not args.quiet:
        Console(stderr=True).print(f"campaign written: {manifest}")
    print(manifest)
    return 0


def _cmd_batch(args) -> int:
    from .batch import command

    return command(args)


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

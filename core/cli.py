"""The ``metro`` command line.

Start-up is kept fast: only argparse is imported here at module level; numpy, pint,
scipy, docxtpl and the plugins load when a command needs them.
"""

from __future__ import annotations

import argparse
import json
import os
import sys
from typing import Any, Sequence

EXIT_USER_ERROR = 2


def _parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(
        prog="metro",
        description="Calibrate and test inertial sensors to published standards "
        "(GB/T 45570, JJF 2014, JJF 2003 …). Standards are plugins.",
        epilog="Example: metro run --standard gbt45570 --item D.5.6   "
        "(no --data: runs on the built-in simulated test station)",
    )
    p.add_argument("--no-plugin-autoload", action="store_true",
                   help="load only metro's built-in plugins (also METRO_DISABLE_PLUGIN_AUTOLOAD=1)")
    p.add_argument("--block-plugin", action="append", default=[], metavar="NAME",
                   help="do not load the plugin NAME (repeatable; also METRO_BLOCK_PLUGINS=a,b)")
    from . import cli_register  # lab profile and report register commands (their own module)

    cli_register.add_global_options(p)
    sub = p.add_subparsers(dest="command", metavar="COMMAND")

    r = sub.add_parser("run", help="evaluate one or more items of a standard",
                       description="Evaluate items of a standard on a campaign (--data) or, without --data, "
                       "on the built-in simulated test station.")
    r.add_argument("--standard", "-s", required=True, help="standard id, e.g. gbt45570")
    r.add_argument("--item", "-i", action="append", default=[],
                   help="item id, e.g. D.5.6, or a series name, e.g. scale-factor (repeat or comma-separate)")
    r.add_argument("--all", action="store_true", dest="run_all",
                   help="run every item of the standard that applies to the device")
    r.add_argument("--decision-rule", choices=("guarded", "simple"),
                   help="conformity decision rule (default: the manifest's, else guarded: w = U)")
    r.add_argument("--data", "-d", metavar="MANIFEST", help="campaign manifest (TOML); see docs/data-format.md")
    r.add_argument("--option", "-o", action="append", default=[], metavar="NAME=VALUE",
                   help="item option, e.g. -o t=\"100 s\" (see `metro items`)")
    r.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    r.add_argument("--out", default="metro-out", metavar="DIR", help="where the Word report goes (default: metro-out)")
    r.add_argument("--report", metavar="PATH", help="write the Word report to PATH instead")
    r.add_argument("--no-report", action="store_true", help="do not write a Word report")
    r.add_argument("--seed", type=int, help="seed of the simulated station (no --data)")
    r.add_argument("--station", help="station to acquire on when no --data is given (default: the item's "
                   "simulated station)")
    r.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE",
                   help="station option when no --data is given, e.g. table_errors=false (as for `metro acquire`)")
    r.add_argument("--no-progress", action="store_true", help="no progress bars")
    cli_register.add_run_options(r)

    pl = sub.add_parser("plugins", help="list loaded plugins and their versions, stations and drivers")
    pl.add_argument("--json", action="store_true")

    it = sub.add_parser("items", help="list the items of the loaded standards")
    it.add_argument("--standard", "-s")
    it.add_argument("--json", action="store_true")

    pn = sub.add_parser("plan", help="print an item's test sequence (what to measure)")
    pn.add_argument("--standard", "-s", required=True)
    pn.add_argument("--item", "-i", action="append", required=True, help="item ids or a series name")
    pn.add_argument("--json", action="store_true")

    aq = sub.add_parser("acquire", help="run items' test sequence on a station and write the campaign",
                        description="Acquire the merged test sequence of one or more items on a station "
                        "(simulated or live) and write it as a campaign folder (manifest.toml + samples, "
                        "docs/data-format.md) that `metro run --data DIR/manifest.toml` evaluates.")
    aq.add_argument("--standard", "-s", required=True, help="standard id, e.g. gbt45570")
    aq.add_argument("--item", "-i", action="append", required=True,
                    help="item id (repeat or comma-separate for several; shared steps are measured once)")
    aq.add_argument("--station", help="registered station (default: the items' simulated station)")
    aq.add_argument("--out", required=True, metavar="DIR", help="campaign folder to create (must not exist "
                    "or be empty)")
    aq.add_argument("--option", "-o", action="append", default=[], metavar="NAME=VALUE", help="item option")
    aq.add_argument("--seed", type=int, help="seed of a simulated station")
    aq.add_argument("--station-option", action="append", default=[], metavar="NAME=VALUE",
                    help="station option, e.g. duration_scale=0.1 (numbers are read as numbers)")
    aq.add_argument("--npy-rows", type=int, default=None, metavar="N",
                    help="segments of N rows or more are written as .npy (default 100000), shorter as CSV")
    aq.add_argument("--no-progress", action="store_true", help="no progress bar")
    cli_register.add_commands(sub)
    return p


def _items(values: Sequence[str]) -> list[str]:
    out: list[str] = []
    for v in values:
        out.extend(x.strip() for x in v.split(",") if x.strip())
    return out


def _options(values: Sequence[str]) -> dict[str, Any]:
    from .errors import MetroError

    out: dict[str, Any] = {}
    for v in values:
        if "=" not in v:
            raise MetroError(f"option {v!r} is not NAME=VALUE")
        k, val = v.split("=", 1)
        out[k.strip()] = val.strip()
    return out


def _pm(args):
    from .plugins import get_plugin_manager

    return get_plugin_manager(autoload=False if args.no_plugin_autoload else None, block=args.block_plugin)


def main(argv: Sequence[str] | None = None) -> int:
    args = _parser().parse_args(argv)
    if args.command is None:
        _parser().print_help()
        return 0
    from .errors import MetroError

    try:
        if args.command == "run":
            return _cmd_run(args)
        if args.command == "plugins":
            return _cmd_plugins(args)
        if args.command == "items":
            return _cmd_items(args)
        if args.command == "plan":
            return _cmd_plan(args)
        if args.command == "acquire":
            return _cmd_acquire(args)
        from . import cli_register

        if args.command in cli_register.COMMANDS:
            return cli_register.dispatch(args)
    except MetroError as exc:
        if getattr(args, "json", False):
            print(json.dumps({"error": type(exc).__name__, "message": exc.reason, "hint": exc.hint,
                              "file": getattr(exc, "file", None), "field": getattr(exc, "field", None)}))
        print(f"metro: error: {exc.reason}", file=sys.stderr)
        if exc.hint:
            print(f"  what to do: {exc.hint}", file=sys.stderr)
        return EXIT_USER_ERROR
    except KeyboardInterrupt:
        print("metro: interrupted; nothing was written", file=sys.stderr)
        return 130
    return 1


# ----------------------------------------------------------------------------------------


def _cmd_run(args) -> int:

    from rich.console import Console

    from . import present
    from .runner import run_items

    err = Console(stderr=True)
    pm = _pm(args)
    items = _items(args.item)
    if not items and not args.run_all:
        from .errors import MetroError

        raise MetroError("no item given", hint="use --item, e.g. --item D.5.6, a series name, or --all")
    options = _options(args.option)
    station_options = _station_options(args)
    if args.data is not None and (station_options or args.station):
        from .errors import MetroError

        given = ", ".join(x for x, on in (("--station", args.station), ("--seed", args.seed is not None),
                                          ("--station-option", bool(args.station_option))) if on)
        raise MetroError(f"{given} acts on a station, and --data {args.data} was recorded already",
                         hint="drop --data to run on a station, or drop the station arguments to evaluate the data")
    if args.data is None and not args.json:
        err.print("[bold yellow]No --data given: running on the built-in SIMULATED test station "
                  "(a virtual device with declared, seeded truth).[/]")
    with present.progress(enabled=not args.no_progress and sys.stderr.isatty()) as prog:
        record = run_items(pm, args.standard, items, data=args.data, options=options, station=args.station,
                           station_options=station_options, progress=prog, run_all=args.run_all,
                           decision_rule=args.decision_rule, **_lab_options(args))
        for w in record.campaign.warnings:  # deprecated spellings, unknown keys (core.vocabulary)
            print(f"metro: warning: {w}", file=sys.stderr)
        report_path = registration = None
        if not args.no_report:  # registered with a lab profile, else "not registered" (core/cli_register.py)
            from .cli_register import write_run_report

            record, report_path, registration = write_run_report(args, pm, record, prog)
    if args.json:
        doc = present.as_json(record, report_path)
        doc["register"] = registration
        print(json.dumps(doc, ensure_ascii=False, indent=2))
    else:
        present.print_record(record, report_path)
        if registration is not None:
            err.print(f"registered as {registration['number']}" if registration["registered"]
                      else f"not registered ({registration['why']})")
    return 0


def _lab_options(args) -> dict[str, Any]:
    from .cli_register import run_lab_options  # the lab profile's equipment and due-date check

    return run_lab_options(args)


def _cmd_plugins(args) -> int:
    pm = _pm(args)
    reg = pm.registry
    rows = []
    for name, info in sorted(pm.plugins.items()):
        stds = sorted(s.id for s in reg.standards.values() if s.plugin == name)
        n_items = sum(1 for p in reg.procedures.values() if p.plugin == name)
        rows.append({"name": name, "distribution": info.distribution, "version": info.version,
                     "builtin": info.builtin, "module": info.module, "standards": stds, "items": n_items})
    stations = [{"name": st.name, "plugin": st.plugin, "description": st.description}
                for _, st in sorted(reg.stations.items())]
    drivers = [{"name": d.name, "kind": d.kind, "plugin": d.plugin, "description": d.description,
                "class": f"{d.cls.__module__}.{d.cls.__qualname__}"} for _, d in sorted(reg.drivers.items())]
    if args.json:
        print(json.dumps({"plugins": rows, "stations": stations, "drivers": drivers,
                          "autoload": not (args.no_plugin_autoload or os.environ.get("METRO_DISABLE_PLUGIN_AUTOLOAD"))},
                         indent=2, ensure_ascii=False))
        return 0
    from rich.console import Console
    from rich.table import Table

    t = Table(title="metro plugins")
    for col in ("plugin", "distribution", "version", "built-in", "standards", "items"):
        t.add_column(col)
    for r in rows:
        t.add_row(r["name"], r["distribution"] or "-", r["version"] or "-", "yes" if r["builtin"] else "no",
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


def _cmd_items(args) -> int:
    pm = _pm(args)
    rows = []
    from .plugins import item_sort_key

    for pid, info in sorted(pm.registry.procedures.items(), key=lambda kv: item_sort_key(kv[0])):
        cls = info.cls
        if args.standard and cls.standard != args.standard:
            continue
        rows.append({"id": pid, "standard": cls.standard, "item": cls.item, "title": cls.title,
                     "clause": cls.clause, "plugin": info.plugin,
                     "options": {o.name: {"default": o.default, "unit": o.unit, "description": o.description}
                                 for o in cls.options}})
    series = [{"id": key, "standard": ser.standard, "name": ser.name, "members": list(ser.members),
               "description": ser.description, "plugin": ser.plugin}
              for key, ser in sorted(pm.registry.series.items())
              if not args.standard or ser.standard == args.standard]
    if args.json:
        print(json.dumps({"items": rows, "series": series}, ensure_ascii=False, indent=2))
        return 0
    from rich.console import Console
    from rich.table import Table

    t = Table(title="metro items")
    for col in ("id", "title", "clause", "plugin", "options"):
        t.add_column(col)
    for r in rows:
        t.add_row(r["id"], r["title"], r["clause"], r["plugin"],
                  "; ".join(f"{k} (default {v['default']})" for k, v in r["options"].items()) or "-")
    Console().print(t)
    for ser in series:  # `metro run -s S -i NAME` runs the members that apply to the device
        Console().print(f"series {ser['id']}: {', '.join(ser['members'])} — {ser['description']}")
    return 0


def _cmd_plan(args) -> int:
    from .runner import merge_steps

    pm = _pm(args)
    items = _items(args.item)
    if any(pm.series(args.standard, i) is not None for i in items):  # a series: its members for the station's device
        from .runner import select_items, station_device

        cands = pm.procedures_of(args.standard)
        device = station_device(pm, cands[0].station if cands else "simulated", {})
        items, _ = select_items(pm, args.standard, items, device=device)
    procs = [pm.procedure(args.standard, i) for i in items]
    steps = merge_steps([cls().sequence(cls.option_values({})) for cls in procs])
    rows = [{"segment": s.segment, "kind": s.kind, "duration": f"{s.duration:~P}", "interval": f"{s.interval:~P}",
             "warmup": f"{s.warmup:~P}" if s.warmup is not None else None,
             "conditions": {k: str(v) for k, v in s.conditions.items()}, "description": s.description}
            for s in steps]
    if args.json:
        print(json.dumps({"steps": rows}, ensure_ascii=False, indent=2))
        return 0
    for i, r in enumerate(rows, 1):
        print(f"{i}. [{r['segment']}] {r['description']}")
        print(f"   kind={r['kind']} duration={r['duration']} interval={r['interval']}"
              + (f" warm-up≥{r['warmup']}" if r["warmup"] else "")
              + "".join(f" {k}={v}" for k, v in r["conditions"].items()))
    return 0


def _number(text: str) -> Any:
    for conv in (int, float):
        try:
            return conv(text)
        except ValueError:
            pass
    return text


def _station_options(args) -> dict[str, Any]:
    """--station-option NAME=VALUE (numbers read as numbers) and --seed, for the station's factory."""
    opts = {k: _number(v) for k, v in _options(args.station_option).items()}
    if args.seed is not None:
        opts["seed"] = args.seed
    return opts


def _cmd_acquire(args) -> int:
    from rich.console import Console

    from metro.instruments.campaign_writer import NPY_ROWS, acquire_campaign

    from . import present

    pm = _pm(args)
    station_options = _station_options(args)
    with present.progress(enabled=not args.no_progress and sys.stderr.isatty()) as prog:
        manifest = acquire_campaign(pm, args.standard, _items(args.item), args.out, station=args.station,
                                    options=_options(args.option), station_options=station_options,
                                    npy_rows=args.npy_rows or NPY_ROWS, progress=prog)
    Console(stderr=True).print(f"campaign written: {manifest}")
    print(manifest)
    return 0


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())

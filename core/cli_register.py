"""``metro lab``, ``metro register``, ``metro report``, ``metro amend``, ``metro withdraw`` and
``metro history``: the lab profile and the report register on the command line.

Kept out of :mod:`metro.core.cli` (which only wires these parsers in); like it, nothing heavy is
imported at module level, so ``metro --help`` stays fast.
"""

from __future__ import annotations

import json
from typing import Any

#: the top-level commands this module handles
COMMANDS = ("lab",)


def add_global_options(p) -> None:
    p.add_argument("--lab", metavar="PATH", default=None,
                   help="lab profile (TOML; default: METRO_LAB, else lab.toml in the user config folder)")


def add_commands(sub) -> None:
    lab = sub.add_parser("lab", help="the lab profile: metro lab init PATH, metro lab show",
                         description="The lab profile names the lab, its signatories, numbering scheme, "
                         "register and equipment (docs/register.md).")
    lsub = lab.add_subparsers(dest="lab_command", metavar="SUBCOMMAND", required=True)
    li = lsub.add_parser("init", help="write a commented lab profile template (never replaces a file)")
    li.add_argument("path", metavar="PATH")
    li.add_argument("--json", action="store_true")
    ls = lsub.add_parser("show", help="print the lab profile in force and where it was found")
    ls.add_argument("--json", action="store_true")


def dispatch(args) -> int:
    if args.command == "lab":
        return _cmd_lab(args)
    raise AssertionError(args.command)  # pragma: no cover


def _print_json(doc: Any) -> None:
    print(json.dumps(doc, ensure_ascii=False, indent=2))


def _cmd_lab(args) -> int:
    from . import lab as labmod
    from .errors import MetroError

    if args.lab_command == "init":
        path = labmod.write_template(args.path)
        if args.json:
            _print_json({"written": str(path)})
        else:
            print(f"lab profile template written: {path} (edit it, then `metro --lab {path} lab show`)")
        return 0
    where = labmod.find_lab_path(args.lab)
    if where is None:
        raise MetroError("no lab profile in force",
                         hint="give --lab PATH or METRO_LAB, or put lab.toml in "
                         f"{labmod.user_lab_path().parent}; `metro lab init PATH` writes a template")
    profile = labmod.load_lab(where)
    doc = profile.as_dict()
    if args.json:
        _print_json(doc)
        return 0
    from rich.console import Console
    from rich.table import Table

    c = Console()
    c.print(f"[bold]lab profile[/] {doc['source']}")
    t = Table(show_header=False)
    for key in ("name_zh", "name_en", "address", "accreditation_body", "accreditation_number", "logo",
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
        te.add_row(e["id"], e["role"], e["certificate"] or "—", e["U"] or "—", str(e["k"]), e["due"] or "—",
                   e["distribution"] or "—")
    c.print(te)
    return 0

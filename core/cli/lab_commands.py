"""``metro lab equipment import CERT.xml``: a piece of equipment from its calibration provider's
Digital Calibration Certificate (PTB DCC 3.3.0) into the lab's equipment store.

Wired in by :mod:`metro.core.cli.register_commands` (``metro lab``); the work is done by
:mod:`metro.core.record.dcc_import`.  Like the other command modules, nothing heavy is imported
at module level.
"""

from __future__ import annotations

import sys

__all__ = ["add_equipment_commands", "equipment_command"]


def add_equipment_commands(lsub) -> None:
    """``metro lab equipment import`` under the ``metro lab`` subcommands ``lsub``."""
    text = "the lab's equipment: import a calibration certificate (DCC)"
    le = lsub.add_parser("equipment", help=text, description=text[0].upper() + text[1:]
                         + " from its calibration provider (docs/dcc.md).")
    esub = le.add_subparsers(dest="equipment_command", metavar="SUBCOMMAND", required=True)
    ei = esub.add_parser(
        "import", help="import an equipment's DCC 3.3.0 (XML) into the lab's equipment store",
        description="Read the DCC a calibration provider issued for one of the lab's instruments, "
        "check it against the DCC 3.3.0 schema, and store the equipment with its calibration (U, "
        "k, due date) and provenance (the DCC's SHA-256 and issuer) beside the lab profile, in "
        "<profile>.equipment/. A manifest then names it by id. Nothing is imported from a "
        "certificate that is refused.")
    ei.add_argument("certificate", metavar="CERT.xml", help="the DCC (XML) file")
    ei.add_argument("--role", required=True, metavar="ROLE",
                    help="the equipment's role (counter, rate_table, dmm, …): it decides which "
                    "result's unit is usable as the calibration U")
    ei.add_argument("--id", dest="equipment_id", metavar="ID", default=None,
                    help="the equipment's id (default: the item's identification issued by the "
                    "customer or owner)")
    ei.add_argument("--result", metavar="NAME", default=None,
                    help="the result to take (its id, name or label) when several fit the role")
    ei.add_argument("--replace", action="store_true",
                    help="replace an earlier import of the same id (never the lab profile's "
                    "equipment)")
    ei.add_argument("--allow-expired", action="store_true",
                    help="import a certificate past its recalibration date (with a warning)")
    ei.add_argument("--dry-run", action="store_true",
                    help="check and show what would be imported; write nothing")


def equipment_command(args) -> int:
    """Run ``metro lab equipment SUBCOMMAND``."""
    from ..base.errors import MetroError
    from ..record import lab as labmod
    from ..record.dcc_import import import_dcc
    from .common import plugin_manager

    where = labmod.find_lab_path(args.lab)
    if where is None:
        raise MetroError("metro lab equipment import needs a lab profile (the equipment is stored "
                         "beside it)",
                         hint="give --lab PATH or METRO_LAB; `metro lab init PATH` writes a "
                         "template")
    plugin_manager(args)  # the plugins' equipment roles (GB/T 45570's megohmmeter, …) are known
    plan, target = import_dcc(args.certificate, where, role=args.role, eid=args.equipment_id,
                              select=args.result, replace=args.replace,
                              allow_expired=args.allow_expired, dry_run=args.dry_run)
    for w in plan.warnings:
        print(f"metro: warning: {w}", file=sys.stderr)
    e, d = plan.equipment, plan.provenance
    cal = e["calibration"]
    due = cal.get("due")
    verb = "would import" if args.dry_run else "imported"
    print(f"{verb} {e['id']} ({e['role']}"
          + "".join(f", {e[k]}" for k in ("manufacturer", "model", "serial") if e.get(k)) + ")")
    print(f"  certificate {cal['certificate']} issued by {d['issuer'] or '(no name)'}, calibrated "
          f"{d['calibration_date'].isoformat()}, "
          + (f"due {due.isoformat()}" if due else "no due date stated"))
    print(f"  result {d['result_name']!r}: U = {cal['U']} (k = {cal['k']:g}, p = "
          f"{d['coverage_probability']:g})")
    print(f"  SHA-256 {d['sha256']}")
    print(f"  {'would write' if args.dry_run else 'written'}: {target}")
    return 0

"""``metro doctor``: is this machine ready for metro, and what to do where it is not.

Each check says what it found and, when it fails, what to do.  *Required* checks decide the
exit code (0 when they all pass, 6 when one fails: README "Exit codes"); *optional* ones say
which feature a missing program or extra would enable.  Nothing is written or created: the
register is inspected read-only (:func:`metro.core.record.register.register_state`).

Checks
    ``cjk-fonts`` (required)   a CJK font matplotlib draws Chinese with, as metro's figures use it
    ``soffice`` (optional)     LibreOffice, for ``--pdf`` and ``--report x.pdf``
    ``pdftotext`` (optional)   poppler, to read a PDF report as text (the document tests use it)
    ``extra:NAME`` (optional)  the optional Python packages (:mod:`metro.core.base.extras`): dask
                               (``metro batch``), psycopg (a PostgreSQL register), numba and
                               pyarrow (speed)
    ``lab-profile``            the lab profile in force is valid (required when one is in force)
    ``register``               the register is reachable and at the newest schema (required when
                               it exists; none yet is fine: the first registered run makes it)
"""

from __future__ import annotations

import sys
from typing import Any

#: optional packages: (import name, what it enables); the extra that installs each is
#: :data:`metro.core.base.extras.EXTRA_OF`'s
EXTRAS = (
    ("distributed", "metro batch (a production lot on a Dask cluster)"),
    ("psycopg", "a register on PostgreSQL shared by several stations"),
    ("numba", "compiled Allan and block statistics (a numpy fallback runs without it)"),
    ("pyarrow", "the multi-threaded CSV reader and Parquet files (a numpy reader runs without it)"),
    ("xmlschema", "checking DCCs against their schema (metro lab equipment import)"),
    ("starlette", "metro serve (the register in a browser)"),
    ("uvicorn", "metro serve's HTTP server"),
)

#: a character every CJK font of the figures must draw
_PROBE = "中"


def add_command(sub) -> None:
    d = sub.add_parser("doctor",
                       help="check the environment (fonts, LibreOffice, extras, lab profile, "
                       "register)",
                       description="Check what metro needs on this machine and say what to do for "
                       "each check that fails: CJK fonts for the figures, LibreOffice for PDF, "
                       "poppler, the optional extras, the lab profile (--lab, METRO_LAB) and its "
                       "register (read only: nothing is created or migrated).",
                       epilog="exit codes: 0 every required check passes; 6 a required check fails "
                       "(optional ones only inform); 2 usage error")
    d.add_argument("--json", action="store_true", help="print one JSON document on stdout")


def _check(name: str, ok: bool, detail: str, *, required: bool, fix: str = "") -> dict[str, Any]:
    return {"check": name, "ok": bool(ok), "required": required, "detail": detail, "fix": "" if ok
            else fix}


def check_fonts() -> dict[str, Any]:
    """A CJK font among the figures' fallback fonts that matplotlib finds and that draws Chinese."""
    from matplotlib import font_manager
    from matplotlib.ft2font import FT2Font

    from ..documents import plots

    plots.register_cjk_fonts()  # as the figures find them: not only through matplotlib's font cache
    found = []
    for family in plots.FALLBACK_FONTS:
        for f in font_manager.fontManager.ttflist:
            if f.name != family:
                continue
            try:
                if FT2Font(f.fname).get_char_index(ord(_PROBE)):
                    found.append(f"{family} ({f.fname})")
                    break
            except (OSError, RuntimeError):
                continue
    fix = ("install a CJK font, e.g. `apt-get install fonts-noto-cjk` (Debian/Ubuntu) or Noto Sans "
           "CJK SC; metro's figures look for " + ", ".join(plots.FALLBACK_FONTS))
    return _check("cjk-fonts", bool(found), "; ".join(found[:2]) if found else
                  "no CJK font found by matplotlib: Chinese in figures would be drawn as empty "
                  "boxes",
                  required=True, fix=fix)


def check_programs() -> list[dict[str, Any]]:
    import shutil

    from ..base.errors import MetroError

    out = []
    try:
        from ..documents.pdf import soffice_path

        exe: str | None = soffice_path()
    except MetroError:
        exe = None
    out.append(_check("soffice", exe is not None,
                      f"LibreOffice {exe} (PDF reports: --pdf, --report x.pdf)" if exe
                      else "no LibreOffice (soffice): PDF reports (--pdf, --report x.pdf) are "
                      "unavailable; Word reports are written as usual", required=False,
                      fix="install LibreOffice, e.g. `apt-get install libreoffice-writer-nogui`, "
                      "or set METRO_SOFFICE to its soffice"))
    pdftotext = shutil.which("pdftotext")
    out.append(_check("pdftotext", pdftotext is not None,
                      f"poppler {pdftotext} (reads a PDF report as text)"
                      if pdftotext
                      else "no pdftotext: the PDF checks of the test suite are skipped",
                      required=False, fix="install poppler, e.g. `apt-get install poppler-utils`"))
    return out


def check_extras() -> list[dict[str, Any]]:
    from ..base.extras import EXTRA_OF, available, install_line

    out = []
    for module, enables in EXTRAS:
        there = available(module)
        out.append(_check(f"extra:{module}", there, f"{module} installed: {enables}" if there
                          else f"{module} not installed: {enables} unavailable", required=False,
                          fix=install_line(EXTRA_OF[module])))
    return out


def check_lab(args) -> tuple[list[dict[str, Any]], Any]:
    """The lab profile in force (full read, equipment included); the profile or None."""
    import datetime as dt

    from ..record import lab as labmod
    from ..base.errors import MetroError

    where = labmod.find_lab_path(getattr(args, "lab", None))
    if where is None:
        return [_check("lab-profile", True,
                       "no lab profile in force: reports are written unregistered",
                       required=False)], None
    try:
        profile = labmod.load_lab(where)
    except MetroError as exc:
        return [_check("lab-profile", False, f"{where}: {exc.reason}", required=True,
                       fix=exc.hint
                       or "correct the profile (docs/register.md lists its keys)")], None
    out = [_check("lab-profile", True, f"{where}: {profile.name}", required=True)]
    today = dt.date.today()
    due = [f"{e.id} (due {e.calibration.due.isoformat()})" for e in profile.equipment
           if e.calibration is not None and not e.calibration.is_valid(today)]
    out.append(_check("lab-equipment", not due,
                      "every piece of the lab's equipment is within its calibration"
                      if not due else "past its calibration due date today: " + ", ".join(due),
                      required=False,
                      fix="recalibrate it and update the lab profile (a registered run refuses it "
                      "unless --allow-expired)"))
    return out, profile


def check_register(args, profile) -> dict[str, Any]:
    import os

    from ..record import lab as labmod
    from ..base.errors import MetroError
    from ..record.register import register_state

    url = profile.register_url() if profile is not None else (os.environ.get(labmod.ENV_REGISTER)
                                                              or labmod.default_register_url())
    shown = labmod.redact_url(url)
    try:
        st = register_state(url)
    except MetroError as exc:
        return _check("register", False, exc.reason, required=True,
                      fix="check the profile's register (or METRO_REGISTER) and that its database "
                      "server is reachable")
    if not st["exists"]:
        return _check("register", True,
                      f"no register at {shown} yet: the first registered run makes it",
                      required=False)
    if st["migrated"]:
        return _check("register", True,
                      f"{shown}: {st['reports']} report(s), schema {st['revision']} (newest)",
                      required=True)
    from ..record.register import SCHEMA_HEAD, SCHEMA_REVISIONS

    newer = st["revision"] not in SCHEMA_REVISIONS  # a revision this metro does not know
    return _check("register", False,
                  f"{shown}: schema {st['revision']}, this metro's newest is {SCHEMA_HEAD}",
                  required=newer, fix="upgrade metro (the register was written by a newer one)"
                  if newer
                  else "the next command that opens the register migrates it (a registered run, or "
                  "`metro register list`)")


def run_checks(args) -> list[dict[str, Any]]:
    from ..base.errors import MetroError

    checks = [check_fonts(), *check_programs(), *check_extras()]
    try:
        lab_checks, profile = check_lab(args)
    except MetroError as exc:  # pragma: no cover - find_lab_path itself refused
        lab_checks, profile = [_check("lab-profile", False, exc.reason, required=True, fix=exc.hint
                                      or "")], None
    checks += lab_checks
    if not any(c["check"] == "lab-profile" and not c["ok"] for c in checks):
        checks.append(check_register(args, profile))
    return checks


def command(args) -> int:
    from .common import EXIT_CHECK_FAILED, EXIT_OK

    checks = run_checks(args)
    failed = [c for c in checks if c["required"] and not c["ok"]]
    if args.json:
        from .schemas import print_json

        print_json({"ok": not failed, "checks": checks})
    else:
        width = max(len(c["check"]) for c in checks)
        for c in checks:
            state = "ok" if c["ok"] else ("FAIL" if c["required"] else "missing"
                                          if c["check"].startswith(
                ("extra:", "soffice", "pdftotext")) else "warn")
            print(f"{state:<7} {c['check']:<{width}}  {c['detail']}")
            if c["fix"]:
                print(f"{'':<7} {'':<{width}}  what to do: {c['fix']}")
        print(f"metro doctor: {len(failed)} required check(s) failed" if failed
              else "metro doctor: every required check passes", file=sys.stderr)
    return EXIT_CHECK_FAILED if failed else EXIT_OK

"""``metro validate``: run the validation cases metro and its plugins ship (ISO/IEC 17025 §7.11.2)
and write the validation report (Word and PDF); with a lab profile the report is registered
(docs/validation.md).

Exit codes: 0 every case passes; 6 a case failed or raised (each named); 2 usage error.
"""

from __future__ import annotations

import sys
from pathlib import Path
from typing import Any

__all__ = ["ProgressLine", "add_command", "case_json", "command"]


def add_command(sub: Any) -> None:
    """The ``validate`` subcommand and its options."""
    v = sub.add_parser(
        "validate", help="run the validation cases of metro and its plugins and write the "
        "validation report",
        description="Run every validation case metro and the loaded plugins ship (the standards' "
        "worked examples, NIST StRD regression, NBS14 Allan values, unit round trips, the JCGM "
        "101 clause-9 examples, a short within-U run per simulated device class) and write the "
        "validation report (.docx, and .pdf with LibreOffice). With a lab profile (--lab, "
        "METRO_LAB) the report is registered in the lab's register (docs/validation.md).",
        epilog="exit codes: 0 every case passes; 6 a case fails or raises (named); 2 usage error")
    v.add_argument("--quick", action="store_true",
                   help="only the quick cases (about 10 s; the within-U runs take one seed)")
    v.add_argument("--out", default="metro-out", metavar="DIR",
                   help="folder of the report (default metro-out)")
    v.add_argument("--lang", choices=("zh", "en", "zh+en"), default=None,
                   help="language of the report (default: the lab profile's, else zh+en)")
    v.add_argument("--no-pdf", action="store_true", help="write the .docx only")
    v.add_argument("--json", action="store_true", help="print one JSON document on stdout")
    v.add_argument("--no-progress", action="store_true", help="no progress display")


def case_json(c: Any) -> dict[str, Any]:
    """One case as the ``--json`` document gives it."""
    return {"id": c.id, "title": c.title, "source": c.source, "plugin": c.plugin,
            "labels": [c.label(i) for i in range(len(c.reference))], "unit": c.unit,
            "reference": list(c.reference), "computed": list(c.computed or ()),
            "tolerance": c.tolerance, "verdict": c.verdict, "detail": c.detail,
            "seconds": round(c.seconds, 3)}


class ProgressLine:
    """One line on stderr, redrawn in place and cut to the terminal's width: [i/n] the case."""

    def __init__(self, show: bool) -> None:
        import shutil

        self.show = show
        self.width = max(20, shutil.get_terminal_size((80, 24)).columns - 1)
        self.n = 0

    def collected(self, n: int) -> None:
        self.n = n

    def __call__(self, i: int, n: int, case: Any) -> None:
        if not self.show:
            return
        mark = "…" if case.verdict is None else "ok" if case.passed else case.verdict.upper()
        line = f"[{i}/{n}] {mark:5s} {case.id}"[: self.width]
        sys.stderr.write("\r" + line.ljust(self.width))
        if i == n and case.verdict is not None:
            sys.stderr.write("\r" + " " * self.width + "\r")
        sys.stderr.flush()


def _write_report(args: Any, run: Any) -> dict[str, Any]:
    """Write (and, with a lab profile, register) the report; what ``--json`` says of it."""
    from ..record import lab as labmod

    lab = labmod.lab_in_force(getattr(args, "lab", None), equipment=False)
    out = Path(args.out)
    pdf = not args.no_pdf and _soffice()
    if lab is not None:
        from ..validation.registering import register_validation

        issued = register_validation(run, lab, out, lang=args.lang, pdf=pdf)
        return {"registered": True, "number": issued.number, "docx": str(issued.path),
                "pdf": str(issued.path.with_suffix(".pdf")) if pdf else None,
                "sha256": issued.sha256, "register": labmod.redact_url(lab.register_url())}
    from ..validation.report import write_validation_report

    number = f"VAL-{run.started:%Y%m%d-%H%M%S}"
    out.mkdir(parents=True, exist_ok=True)
    docx = write_validation_report(out / f"{number}.docx", run, number=number,
                                   lang=args.lang or "zh+en")
    if pdf:
        from ..documents.pdf import to_pdf

        to_pdf(docx, docx.with_suffix(".pdf"))
    return {"registered": False, "number": number, "docx": str(docx),
            "pdf": str(docx.with_suffix(".pdf")) if pdf else None, "sha256": None,
            "register": None}


def _soffice() -> bool:
    from ..base.errors import MetroError
    from ..documents.pdf import soffice_path

    try:
        soffice_path()
    except MetroError as exc:
        print(f"metro validate: no PDF: {exc.reason}", file=sys.stderr)
        return False
    return True


def _summary(run: Any, report: dict[str, Any]) -> None:
    counts = run.counts()
    width = max(len(c.id) for c in run.cases) if run.cases else 10
    for c in run.failed():
        print(f"{c.verdict.upper():5s} {c.id:<{width}}  {c.title}")
        print(f"{'':5s} {'':<{width}}  {c.detail}")
    groups: dict[str, list] = {}
    for c in run.cases:
        groups.setdefault(c.plugin, []).append(c)
    for plugin, cases in groups.items():
        ok = sum(1 for c in cases if c.passed)
        print(f"{plugin:<14s} {ok:3d}/{len(cases):<3d} passed")
    state = "validated: every case passed" if run.passed else "NOT validated"
    print(f"metro validate: {len(run.cases)} cases, {counts['pass']} passed, {counts['fail']} "
          f"failed, {counts['error']} errors in {run.seconds:.0f} s: {state}")
    where = report["docx"] + (f" and {report['pdf']}" if report["pdf"] else "")
    reg = f" (registered {report['number']})" if report["registered"] else " (not registered: " \
        "no lab profile)"
    print(f"report: {where}{reg}")


def command(args: Any) -> int:
    """Run ``metro validate``; the exit code."""
    from ..validation.suite import validate
    from .common import EXIT_CHECK_FAILED, EXIT_OK, plugin_manager, show_progress

    pm = plugin_manager(args)
    prog = ProgressLine(show_progress(args) and not args.json)
    run = validate(pm, quick=args.quick, progress=prog, collected=prog.collected)
    report = _write_report(args, run)
    if args.json:
        from .schemas import print_json

        print_json({"ok": run.passed, "quick": run.quick, "seconds": round(run.seconds, 1),
                    "counts": run.counts(), "cases": [case_json(c) for c in run.cases],
                    "environment": run.environment, "files": len(run.files),
                    "report": report})
    else:
        _summary(run, report)
    return EXIT_OK if run.passed else EXIT_CHECK_FAILED

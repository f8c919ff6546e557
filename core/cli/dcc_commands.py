"""DCC output on the command line (docs/dcc.md): a report written as a PTB Digital Calibration
Certificate (DCC 3.3.0 XML, the report's PDF embedded).

* ``metro run … --report cert.xml`` — the suffix decides, as for ``.pdf``;
* ``metro run … --format dcc --out DIR`` — ``DIR/<report number>.xml``; a registered run writes its
  Word report and the DCC beside it, the register keeping the DCC's SHA-256
  (``metro register verify`` checks it);
* ``metro report NUMBER --format dcc --out DIR`` — written again from the register;
* ``metro amend NUMBER --format dcc`` — the amendment's DCC (by default when NUMBER had one).

A DCC never replaces a file (not even with ``--force``); a unit with no D-SI mapping is refused
before anything is written; a withdrawn report is never issued as a DCC.  Like the other command
modules, nothing heavy is imported at module level.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path
from typing import Any, Sequence

#: the values of ``--format``
FORMATS = ("docx", "dcc")


class OutGiven(argparse.Action):
    """``--out DIR`` that also records it was given (``args.out_given``): ``--format dcc`` needs
    it said."""

    def __call__(self, parser, namespace, values, option_string=None) -> None:
        setattr(namespace, self.dest, values)
        namespace.out_given = True


def add_format_option(p: argparse.ArgumentParser, what: str) -> None:
    """``--format {docx,dcc}`` of ``metro run``, ``report`` and ``amend``."""
    p.add_argument("--format", choices=FORMATS, default=None,
                   help=f"{what}: docx (Word, the default) or dcc (a PTB Digital Calibration "
                   "Certificate, DCC 3.3.0 XML with the report's PDF embedded, written to "
                   "--out DIR as <report number>.xml; needs LibreOffice; docs/dcc.md)")


def is_dcc_path(report: str | None) -> bool:
    """Whether ``--report`` names a DCC (its suffix is ``.xml``)."""
    return bool(report) and Path(str(report)).suffix.lower() == ".xml"


def wants_dcc(args: Any) -> bool:
    """Whether the run's report is a DCC: ``--format dcc`` or a ``--report`` ending in ``.xml``."""
    return getattr(args, "format", None) == "dcc" or is_dcc_path(getattr(args, "report", None))


def _no_dcc_without_out(args: Any) -> None:
    from ..base.errors import MetroError

    if getattr(args, "format", None) == "dcc" and not getattr(args, "out_given", False):
        raise MetroError("--format dcc needs --out DIR: the folder the DCC <report number>.xml "
                         "goes into", hint=f"add --out DIR, e.g. metro {args.command} … --format "
                         "dcc --out metro-out")


def check_run(args: Any, inputs: Sequence[Path]) -> bool:
    """``metro run``'s report options about a DCC, checked before anything is evaluated; True
    when the report is a DCC (then :func:`metro.core.run.outputs.plan_report` is not used for a
    ``--report`` path: a DCC is never replaced, not even with ``--force``)."""
    from ..base.errors import DataError, MetroError

    fmt, report = getattr(args, "format", None), getattr(args, "report", None)
    if fmt is not None and report:
        raise MetroError("--format goes with --out; with --report the file's suffix decides the "
                         "format", hint="drop --format (cert.xml is a DCC, cert.docx Word), or "
                         "give --out DIR instead of --report")
    if not wants_dcc(args):
        return False
    if args.no_report:
        raise MetroError("--no-report writes no report, and --format dcc or --report …xml asks "
                         "for one", hint="drop one of them")
    _no_dcc_without_out(args)
    if report:
        from ..record.dcc_out import refuse_existing
        from ..run.outputs import check_report_path, check_writable_folder

        p = Path(report)
        for inp in inputs:
            if p.resolve() == Path(inp).resolve():
                raise DataError(str(p), "--report", f"is an input of this run ({inp}); metro "
                                "never writes over its own inputs", hint="write the DCC to "
                                "another path")
        if p.is_dir():
            raise DataError(str(p), "--report", "is a folder; --report names the DCC file",
                            hint=f"use --format dcc --out {p} to write <report number>.xml "
                            "into it")
        refuse_existing(p, "--report")
        check_writable_folder(p.parent, "--report", p)
        if getattr(args, "pdf", False):
            check_report_path(p.with_suffix(".pdf"), force=args.force, inputs=inputs)
    else:
        from ..run.outputs import plan_report

        plan_report(None, args.out, force=args.force, inputs=inputs)
    from ..documents.pdf import soffice_path

    soffice_path()  # the DCC embeds the report's PDF: no LibreOffice is said now
    return True


def registered_report_error(args: Any) -> Exception:
    """The refusal of ``--report PATH`` for a registered report (named by its register
    number)."""
    from ..base.errors import MetroError

    hint = ("use --format dcc --out DIR (the DCC is DIR/<number>.xml, beside DIR/<number>.docx)"
            if is_dcc_path(getattr(args, "report", None))
            else "use --out DIR (the report is DIR/<number>.docx)")
    return MetroError("a registered report is named by its register number; --report PATH "
                      "cannot be used with a lab profile", hint=hint)


def dcc_summary(path: Path | None, sha256: str | None) -> dict[str, str] | None:
    """``{"path", "sha256"}`` of a DCC written (``--json``), None when there is none."""
    return None if path is None else {"path": str(path), "sha256": str(sha256)}


def write_run_dcc(args: Any, pm: Any, record: Any, lab: Any, why: str,
                  t0: float) -> tuple[Any, Path, dict[str, Any]]:
    """The DCC of a run that is not registered (``why``: no lab profile, simulated): to
    ``--report`` or ``--out DIR/<report number>.xml``.  Returns what
    :func:`metro.core.cli.register_commands.write_run_report` returns."""
    from ..documents.report import build_context
    from ..record.dcc_out import DCC_SUFFIX, write_unregistered
    from ..record.registering import NOT_REGISTERED, unregistered

    report = getattr(args, "report", None)
    target = Path(report) if report else Path(args.out) / f"{record.report_number}{DCC_SUFFIX}"
    info = pm.template_for(record.standard)
    designations = {s.id: s.designation for s in pm.registry.standards.values()}
    lang = getattr(args, "lang", None) or (lab.language if lab is not None else None)
    ctx = build_context(record, designations=designations, extend=pm.extend_report_context,
                        register=unregistered(record, why, lang or "zh+en"), lang=lang)
    path, digest = write_unregistered(ctx, target, template=info.path, layout=info.layout,
                                      pdf_beside=getattr(args, "pdf", False),
                                      option="--report" if report else "--out")
    record.timings["write report"] = time.perf_counter() - t0
    pm.report_written(path, record.outcomes)
    return record, path, {"registered": False, "number": record.report_number,
                          "why": NOT_REGISTERED[why][1], "dcc": dcc_summary(path, digest)}


def registered_pdf(issued_path: Path, writer: Any) -> None:
    """``--pdf`` of a registered run: the PDF beside its Word report; the one its DCC embeds
    when it has one (the same LibreOffice conversion, not run twice)."""
    from ..base.atomic import atomic_path

    with atomic_path(Path(issued_path).with_suffix(".pdf")) as tmp:
        if writer is not None and writer.pdf is not None:
            Path(tmp).write_bytes(writer.pdf)
        else:
            from ..documents.pdf import to_pdf

            to_pdf(issued_path, Path(tmp))


def cmd_report_dcc(args: Any, reg: Any, pm: Any) -> int:
    """``metro report NUMBER --format dcc --out DIR``: the DCC written again from the register."""
    from ..record.dcc_out import rerender_dcc
    from ..record.registering import template_changed
    from .schemas import print_json

    _no_dcc_without_out(args)
    path, digest = rerender_dcc(reg, args.number, args.out, pm=pm)
    changed = template_changed(reg, args.number, pm)
    if args.json:
        print_json({"number": args.number, "report": str(path), "template_changed": changed,
                    "dcc": dcc_summary(path, digest)})
    else:
        print(path)
    return 0

"""A report issued as a PTB Digital Calibration Certificate (DCC 3.3.0 XML, docs/dcc.md): the
register's side of it.

* :func:`dcc_context` — the document context as the register keeps it and reads it back (the
  same form for a run's DCC and for one written again from the register);
* :func:`check_dcc` — the DCC made once without its PDF, before anything is written or a number
  allocated, so that a unit with no D-SI mapping (:class:`~metro.core.base.errors.UnitError`) is
  refused with nothing written;
* :class:`DccWriter` — the DCC of a registered report, made inside the register's transaction from
  the Word file just written: its PDF (the LibreOffice conversion ``--report x.pdf`` uses), then
  the XML with that PDF embedded (:func:`~metro.core.record.registering.register_run` and
  ``amend`` take one as ``dcc``);
* :func:`amend_writer` — the DCC writer of an amendment: ``--format dcc``, or by default when the
  replaced report was issued with a DCC;
* :func:`write_unregistered` — ``metro run --report cert.xml`` (or ``--format dcc``) without a
  register;
* :func:`rerender_dcc` — ``metro report NUMBER --format dcc``: the stored context written again
  as a DCC.  A withdrawn report is never issued as a DCC.

The XML itself is built by :mod:`metro.core.documents.dcc` (``build_dcc``, ``write_dcc``).
"""

from __future__ import annotations

import os
import tempfile
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Mapping

from ..base.errors import MetroError

if TYPE_CHECKING:  # pragma: no cover
    from .register import Register
    from ..run.plugin_manager import MetroPluginManager

__all__ = ["DCC_SUFFIX", "dcc_context", "check_dcc", "docx_pdf", "context_pdf", "DccWriter",
           "amend_writer", "refuse_withdrawn", "refuse_existing", "write_unregistered",
           "rerender_dcc"]

#: the suffix of a DCC file (``--report cert.xml``; ``<number>.xml`` beside the Word report)
DCC_SUFFIX = ".xml"


def dcc_context(ctx: Mapping[str, Any]) -> dict[str, Any]:
    """``ctx`` (made by :func:`metro.core.documents.report.build_context`) as the register keeps
    it and reads it back (:func:`~metro.core.record.registering.encode_context`, then
    ``decode_context``): a DCC made from it equals one made later from the register."""
    from .registering import decode_context, encode_context

    return decode_context(encode_context(ctx))


def check_dcc(ctx: Mapping[str, Any]) -> None:
    """Build the DCC of ``ctx`` once, without its PDF, and throw it away: what would refuse it
    (a unit with no D-SI mapping, a context without machine values) is raised before any file
    is written and before the register allocates a number."""
    from ..documents.dcc import build_dcc

    build_dcc(ctx, pdf=None)


def docx_pdf(docx: str | os.PathLike[str]) -> bytes:
    """The PDF/A of a Word file, through LibreOffice (:func:`metro.core.documents.pdf.to_pdf`)."""
    from ..documents.pdf import to_pdf

    with tempfile.TemporaryDirectory(prefix="metro-dcc-") as tmp:
        pdf = Path(tmp) / "report.pdf"
        to_pdf(docx, pdf)
        return pdf.read_bytes()


def context_pdf(ctx: Mapping[str, Any], *, template: Any = None, layout: Any = None) -> bytes:
    """The PDF of a document context, written as ``--report x.pdf`` writes it
    (:func:`metro.core.documents.report.render_context` through LibreOffice)."""
    from ..documents.report import render_context

    with tempfile.TemporaryDirectory(prefix="metro-dcc-") as tmp:
        pdf = Path(tmp) / "report.pdf"
        render_context(pdf, ctx, template=template, layout=layout)
        return pdf.read_bytes()


class DccWriter:
    """The DCC of a registered report, made from its Word file once written (the register's
    :attr:`~metro.core.record.register.Draft.dcc`); the PDF it embeds is kept in :attr:`pdf` so
    that ``--pdf`` writes the same one beside the report."""

    def __init__(self) -> None:
        self.pdf: bytes | None = None

    def check(self, ctx: Mapping[str, Any]) -> None:
        """:func:`check_dcc` of ``ctx`` as the register will keep it, before the register's
        transaction."""
        check_dcc(dcc_context(ctx))

    def maker(self, ctx: Mapping[str, Any]) -> Callable[[Path], bytes]:
        """``make(docx)``: the DCC of ``ctx`` (a :func:`dcc_context`) with ``docx`` as its PDF."""
        from ..documents.dcc import build_dcc

        def make(docx: Path) -> bytes:
            self.pdf = docx_pdf(docx)
            return build_dcc(ctx, pdf=self.pdf)

        return make


def amend_writer(entry: Mapping[str, Any], fmt: str | None) -> DccWriter | None:
    """The DCC writer of an amendment of the register entry ``entry``: with ``fmt`` ``"dcc"``, or
    with no ``fmt`` when ``entry`` was issued with a DCC; None otherwise."""
    if fmt == "dcc" or (fmt is None and entry.get("dcc_path")):
        return DccWriter()
    return None


def refuse_withdrawn(entry: Mapping[str, Any]) -> None:
    """A :class:`MetroError` when the register entry ``entry`` is withdrawn: a withdrawn report is
    never issued as a DCC."""
    if entry["status"] == "withdrawn":
        raise MetroError(f"report {entry['number']} is withdrawn ({entry['reason']}); a withdrawn "
                         "report is never issued as a DCC",
                         hint="`metro register show "
                         f"{entry['number']}` shows its audit trail; a report that replaces it is "
                         "issued with `metro run … --format dcc`")


def refuse_existing(target: Path, option: str) -> None:
    """A DCC never replaces a file, not even with ``--force``."""
    from ..base.errors import DataError

    if target.exists() or target.is_symlink():
        raise DataError(str(target), option, "exists; metro never replaces a DCC file, not even "
                        "with --force", hint="choose another path or folder")


def write_unregistered(ctx: Mapping[str, Any], target: Path, *, template: Any = None,
                       layout: Any = None, pdf_beside: bool = False,
                       option: str = "--report") -> tuple[Path, str]:
    """Write ``ctx`` (a report that is not registered) as the DCC ``target`` with its PDF
    embedded; with ``pdf_beside`` the same PDF goes beside it.  Returns (path, SHA-256).  Nothing
    is written when the DCC is refused (checked before LibreOffice runs)."""
    from ..base.atomic import atomic_path
    from ..documents.dcc import write_dcc
    from .register import sha256_file

    refuse_existing(target, option)
    stored = dcc_context(ctx)
    check_dcc(stored)
    pdf = context_pdf(ctx, template=template, layout=layout)
    target.parent.mkdir(parents=True, exist_ok=True)
    path = Path(write_dcc(stored, target, pdf=pdf))
    if pdf_beside:
        with atomic_path(target.with_suffix(".pdf")) as tmp:
            Path(tmp).write_bytes(pdf)
    return path, sha256_file(path)


def rerender_dcc(reg: "Register", number: str, out: str | os.PathLike[str], *,
                 pm: "MetroPluginManager") -> tuple[Path, str]:
    """Write report ``number`` again from the register as the DCC ``out/<number>.xml`` (never
    replacing a file), its PDF rendered from the stored context; returns (path, SHA-256).  A
    withdrawn report is refused."""
    from ..documents.dcc import write_dcc
    from .register import sha256_file
    from .registering import decode_context, stored_context

    refuse_withdrawn(reg.get(number))
    doc, tpl = stored_context(reg, number, pm)
    target = Path(out) / f"{number}{DCC_SUFFIX}"
    refuse_existing(target, "--out")
    ctx = decode_context(doc)
    check_dcc(ctx)
    pdf = context_pdf(ctx, template=tpl.path, layout=tpl.layout)
    target.parent.mkdir(parents=True, exist_ok=True)
    path = Path(write_dcc(ctx, target, pdf=pdf))
    return path, sha256_file(path)

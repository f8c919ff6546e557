"""Word to PDF/A through LibreOffice (headless, one user profile per conversion)."""

from __future__ import annotations

__all__ = ["soffice_path", "to_pdf"]

# ----------------------------------------------------------------------------------------
# PDF through LibreOffice
# ----------------------------------------------------------------------------------------


def soffice_path() -> str:
    """The LibreOffice program (``soffice`` or ``libreoffice`` on PATH, or ``$METRO_SOFFICE``);
    a clear error when there is none."""
    import os
    import shutil

    from ..base.errors import MetroError

    given = os.environ.get("METRO_SOFFICE")
    for cand in ([given] if given else []) + ["soffice", "libreoffice"]:
        found = shutil.which(cand)
        if found:
            return found
    raise MetroError(
        "a PDF needs LibreOffice, and neither soffice nor libreoffice is on PATH",
        hint="install LibreOffice (e.g. apt-get install libreoffice-writer-nogui), set "
        "METRO_SOFFICE to its soffice, or write the .docx and convert it yourself",
    )


def to_pdf(docx_path, pdf_path, *, timeout: float = 300.0) -> None:
    """Convert ``docx_path`` to PDF/A-2b at ``pdf_path`` with LibreOffice headless.

    The conversion runs in a temporary directory with its own LibreOffice user profile
    (``-env:UserInstallation``), so several conversions at once do not collide."""
    import shutil
    import subprocess
    import tempfile
    from pathlib import Path

    from ..base.errors import MetroError

    exe = soffice_path()
    with tempfile.TemporaryDirectory(prefix="metro-pdf-") as tmp:
        tmp = Path(tmp)
        src = tmp / "document.docx"
        shutil.copyfile(docx_path, src)
        profile = (tmp / "profile").as_uri()
        # SelectPdfVersion 2 = PDF/A-2b (LibreOffice ≥ 7.4 reads the filter options as JSON)
        target = 'pdf:writer_pdf_Export:{"SelectPdfVersion":{"type":"long","value":"2"}}'
        cmd = [
            exe,
            f"-env:UserInstallation={profile}",
            "--headless",
            "--norestore",
            "--convert-to",
            target,
            "--outdir",
            str(tmp / "out"),
            str(src),
        ]
        try:
            proc = subprocess.run(cmd, capture_output=True, text=True, timeout=timeout)
        except subprocess.TimeoutExpired as exc:
            raise MetroError(
                f"LibreOffice did not convert {docx_path} to PDF within {timeout:g} s"
            ) from exc
        out = tmp / "out" / "document.pdf"
        if proc.returncode != 0 or not out.is_file():
            raise MetroError(
                f"LibreOffice could not convert {docx_path} to PDF (exit {proc.returncode})",
                hint=(proc.stderr or proc.stdout).strip()[-300:] or None,
            )
        shutil.copyfile(out, pdf_path)

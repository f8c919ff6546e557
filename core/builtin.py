"""The core's own plugin: the generic report template.

Registered through the ``metro`` entry-point group, as every built-in is.
"""

from __future__ import annotations

from importlib import resources
from pathlib import Path

from . import hookimpl


@hookimpl
def metro_register_templates(registrar) -> None:
    path = Path(str(resources.files(__package__).joinpath("templates", "report.docx")))
    registrar.add_template("generic-report", path, standard=None, kind="report")

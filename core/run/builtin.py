"""The core's own plugin: the generic report layout (metro.core.documents.document.generic_layout).

Registered through the ``metro`` entry-point group, as every built-in is.
"""

from __future__ import annotations

from .. import hookimpl


@hookimpl
def metro_register_templates(registrar) -> None:
    registrar.add_template("generic-report", standard=None, kind="report",
                           layout="metro.core.documents.document:generic_layout")

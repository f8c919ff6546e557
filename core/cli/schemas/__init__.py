"""The JSON documents metro prints (``--json``): their version and their JSON Schemas.

Every document carries ``schema_version`` (:data:`SCHEMA_VERSION`, ``major.minor``): a minor
version adds fields, a major one changes or removes them.  Each command's document is described
by ``<name>.schema.json`` in this folder (JSON Schema draft 2020-12; the shared definitions are in
``common.schema.json``, ``$id`` ``urn:metro:json:common``), listed in docs/json.md.
"""

from __future__ import annotations

import json
from collections.abc import Mapping
from importlib import resources
from typing import Any

#: the version of every JSON document metro prints (docs/json.md "Versions")
SCHEMA_VERSION = "1.1"

#: each schema's name and the command whose ``--json`` document it describes
SCHEMAS = {
    "run": "metro run", "items": "metro items", "plugins": "metro plugins", "plan": "metro plan",
    "batch": "metro batch", "register-list": "metro register list",
    "register-show": "metro register show", "register-verify": "metro register verify",
    "report": "metro report", "amend": "metro amend", "withdraw": "metro withdraw",
    "history": "metro history", "lab-init": "metro lab init", "lab-show": "metro lab show",
    "doctor": "metro doctor", "validate": "metro validate",
    "error": "any command, on a usage or data error (exit code 2)",
}


def schema(name: str) -> dict[str, Any]:
    """The JSON Schema ``name`` (a key of :data:`SCHEMAS`, or ``common``) as shipped."""
    text = resources.files(__name__).joinpath(f"{name}.schema.json").read_text(encoding="utf-8")
    return json.loads(text)


def validator(name: str) -> Any:
    """A ``jsonschema`` validator of the document ``name`` (its references to the shared
    definitions resolved from this folder); needs the ``jsonschema`` package."""
    from jsonschema import Draft202012Validator
    from referencing import Registry, Resource

    names = [*SCHEMAS, "common"]
    registry = Registry().with_resources(
        (f"urn:metro:json:{n}", Resource.from_contents(schema(n))) for n in names)
    return Draft202012Validator(schema(name), registry=registry)


def document(doc: Mapping[str, Any]) -> dict[str, Any]:
    """``doc`` as printed: ``schema_version`` first, then its fields as JSON values (None → null,
    a non-finite number → null, a quantity → ``{"value", "unit"}``:
    :func:`metro.core.model.record_json.json_value`)."""
    from ...model.record_json import json_value

    return {"schema_version": SCHEMA_VERSION, **json_value(dict(doc))}


def dumps(doc: Mapping[str, Any], *, indent: int | None = 2) -> str:
    """The document as strict JSON text (:func:`document`; never ``NaN``)."""
    return json.dumps(document(doc), ensure_ascii=False, indent=indent, allow_nan=False)


def print_json(doc: Mapping[str, Any], *, indent: int | None = 2) -> None:
    """Print the document on stdout (:func:`dumps`)."""
    print(dumps(doc, indent=indent))


__all__ = ["SCHEMAS", "SCHEMA_VERSION", "document", "dumps", "print_json", "schema", "validator"]

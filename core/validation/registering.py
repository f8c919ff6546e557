"""A validation report registered as a record of its own kind: in the lab's register, numbered
``VAL-`` and the lab's scheme in a counter of its own (scope ``validation:<year>``), with its
standard ``metro-validate``, one result row per case and the software it ran on in its
provenance.  No column is added: registers written before it stay readable.
"""

from __future__ import annotations

import datetime as dt
from pathlib import Path
from typing import TYPE_CHECKING, Any

if TYPE_CHECKING:  # pragma: no cover
    from ..record.lab import LabProfile
    from ..record.register import Issued
    from .suite import ValidationRun

__all__ = ["KIND", "NUMBER_PREFIX", "STANDARD", "register_validation", "validation_draft_fields"]

#: the register scope's kind, the number's prefix and the ``standard`` column of the record
KIND = "validation"
NUMBER_PREFIX = "VAL-"
STANDARD = "metro-validate"


def _lab(lab: "LabProfile") -> dict[str, Any]:
    return {"name_zh": lab.name_zh, "name_en": lab.name_en, "address": lab.address,
            "accreditation_body": lab.accreditation_body,
            "accreditation_number": lab.accreditation_number,
            "signatories": [s.as_dict() for s in lab.signatories], "source": lab.source}


def validation_draft_fields(run: "ValidationRun", lab: "LabProfile") -> tuple[dict, list]:
    """The register row (fields) and result rows of a validation run."""
    env = run.environment
    results = [{"item": c.id, "key": c.plugin, "quantity": c.title, "symbol": "",
                "value": None, "u": None, "U": None, "k": None, "nu_eff": None, "unit": c.unit,
                "value_text": c.verdict or "", "U_text": None, "reportable": c.passed,
                "reason": c.detail} for c in run.cases]
    fields = {
        "standard": STANDARD,
        "items": [c.id for c in run.cases],
        "options": {"quick": run.quick},
        "device_id": "metro",
        "device_manufacturer": "",
        "device_model": f"metro {env['metro']}",
        "device_serial": "metro",
        "customer": "",
        "measurement_date": run.started.date(),
        "simulated": False,
        "allow_expired": False,
        "lab": _lab(lab),
        "verdicts": {"overall": "pass" if run.passed else "fail", **run.counts()},
        "budgets": [],
        "provenance": {"environment": env, "files": list(run.files),
                       "seconds": round(run.seconds, 1)},
        "manifest_sha256": None,
        "equipment": [],
        "template": "validation",
    }
    return fields, results


def register_validation(run: "ValidationRun", lab: "LabProfile", folder: str | Path, *,
                        lang: str | None = None, pdf: bool = False) -> "Issued":
    """Issue the validation report in the lab's register: the next ``VAL-`` number, the .docx
    written to ``folder/<number>.docx`` and its row, all or nothing; with ``pdf`` the PDF beside
    it (after the commit: the register holds the Word file's SHA-256)."""
    from ..record.register import Draft, open_register
    from .report import write_validation_report

    language = lang or lab.language
    fields, results = validation_draft_fields(run, lab)

    def make(number: str, issued_at: dt.datetime) -> Draft:
        def write(tmp: Path) -> None:
            write_validation_report(tmp, run, number=number, lang=language, lab=lab)

        return Draft(fields=fields, results=results, write=write)

    with open_register(lab.register_url()) as reg:
        issued = reg.issue(make, folder=folder,
                           scheme=lambda seq, year: NUMBER_PREFIX + lab.format_number(seq, year),
                           per_year=lab.per_year(), timezone=lab.timezone, kind=KIND)
    if pdf:
        from ..documents.pdf import to_pdf

        to_pdf(issued.path, issued.path.with_suffix(".pdf"))
    return issued

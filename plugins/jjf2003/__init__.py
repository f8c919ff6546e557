"""JJF 2003—2022 微惯性测量组合(MIMU)校准规范 — plugin `jjf2003`."""

from __future__ import annotations

from metro.api import hookimpl

STANDARD_ID = "jjf2003"


@hookimpl
def metro_register_standards(registrar) -> None:
    from .procedures import PROCEDURES

    registrar.add_standard(
        STANDARD_ID,
        "微惯性测量组合(MIMU)校准规范 "
        "(Calibration specification for micro inertial measurement units)",
        designation="JJF 2003—2022",
        description="the eight items of table 2, clauses 7.2.1–7.2.5",
    )
    for cls in PROCEDURES:
        registrar.add_procedure(cls)


@hookimpl
def metro_register_templates(registrar) -> None:
    registrar.add_template("jjf2003-certificate", standard=STANDARD_ID, kind="report",
                           layout="metro.plugins.jjf2003.certificate:layout")


@hookimpl
def metro_extend_report_context(record, context: dict) -> None:
    from .certificate import certificate_context

    if any(o.standard == STANDARD_ID for o in record.outcomes):
        context[STANDARD_ID] = certificate_context(record)


@hookimpl
def metro_expected_values(campaign, ideal):
    from .expected import expected_values

    return expected_values(campaign, ideal)


@hookimpl
def metro_validation_cases():
    """This standard's worked examples as validation cases (``metro validate``)."""
    from .validation import validation_cases

    return validation_cases()

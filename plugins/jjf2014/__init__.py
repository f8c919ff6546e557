"""JJF 2014—2022 金属振子式速率陀螺校准规范 — plugin `jjf2014`.

All 24 calibration items of table 3 (clauses 7.2.1–7.2.23) as procedures, the simulated
station ``simulated-jjf2014`` (an analog-output vibratory rate gyro, in
:mod:`metro.instruments.vibratory`), the appendix-A/clause-8 certificate template and its
report-context extension (``context["jjf2014"]``).
"""

from __future__ import annotations

from metro.api import hookimpl

STANDARD_ID = "jjf2014"


@hookimpl
def metro_register_standards(registrar) -> None:
    from .procedures import PROCEDURES

    registrar.add_standard(
        STANDARD_ID,
        "金属振子式速率陀螺校准规范 (Calibration specification for metal-shell vibratory rate "
        "gyroscopes)",
        designation="JJF 2014—2022",
        description="calibration items of clause 7.2 (table 3); uncertainty after appendix B",
    )
    for cls in PROCEDURES:
        registrar.add_procedure(cls)


@hookimpl
def metro_register_templates(registrar) -> None:
    registrar.add_template("jjf2014-certificate", standard=STANDARD_ID, kind="report",
                           layout="metro.plugins.jjf2014.certificate:layout")


@hookimpl
def metro_extend_report_context(record, context) -> None:
    from .certificate import extend_context

    extend_context(record, context)


@hookimpl
def metro_validation_cases():
    """This standard's worked examples as validation cases (``metro validate``)."""
    from .validation import validation_cases

    return validation_cases()

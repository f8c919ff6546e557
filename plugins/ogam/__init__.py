"""Draft JJF 光学陀螺测角仪校准规范 (optical-gyro angle measuring instruments) — plugin `ogam`.

Written only against metro's public plugin API (the hooks of :mod:`metro.core.model.hookspec`):
the standard and its seven items 7.1–7.7, the ``simulated-ogam`` station (the virtual angle
instrument on a low-speed turntable, :mod:`metro.instruments.angle_instrument`), and the
appendix B certificate template with its report-context entries.
"""

from __future__ import annotations

from metro.api import hookimpl

STANDARD_ID = "ogam"


@hookimpl
def metro_register_standards(registrar) -> None:
    from .procedures import PROCEDURES

    registrar.add_standard(
        STANDARD_ID,
        "光学陀螺测角仪校准规范 (Calibration specification for optical-gyroscope angle measuring "
        "instruments)",
        designation="JJF xxxx—xxxx (征求意见稿)",
        description="draft; items 7.1–7.7, uncertainty example appendix A, certificate appendix B",
    )
    for cls in PROCEDURES:
        registrar.add_procedure(cls)


@hookimpl
def metro_register_templates(registrar) -> None:
    registrar.add_template("ogam-certificate", standard=STANDARD_ID, kind="report",
                           layout="metro.plugins.ogam.certificate:layout")


@hookimpl
def metro_extend_report_context(record, context) -> None:
    from .certificate import certificate_context

    if any(o.standard == STANDARD_ID for o in record.outcomes):
        context[STANDARD_ID] = certificate_context(record)


@hookimpl
def metro_validation_cases():
    """This standard's worked examples as validation cases (``metro validate``)."""
    from .validation import validation_cases

    return validation_cases()

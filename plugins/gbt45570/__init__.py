"""GB/T 45570—2025 光学陀螺仪通用技术要求 (optical gyroscopes) as a metro plugin.

Registered through the ``metro`` entry-point group, like any third-party plugin.
Items implemented so far: D.1.1–D.1.6 (angle method, pulse output, :mod:`.angle_method`),
D.2.1–D.2.6 (rate method, LSB output, on the ``simulated-digital`` station) and D.3 (maximum
input rate, either method; :mod:`.rate_method`), D.4 (threshold, :mod:`.threshold`),
D.5.1–D.5.6 (bias series, ARW), D.6.1–D.6.4 (environmental) and 6.2.7.7/6.2.7.8 (set-up time,
power; :mod:`.environmental`) and 6.2.6 (polarity, :mod:`.polarity`).
"""

from __future__ import annotations

from pathlib import Path

from metro.core import hookimpl

STANDARD_ID = "gbt45570"
REPORT_TEMPLATE = Path(__file__).parent / "templates" / "report.docx"


@hookimpl
def metro_register_standards(registrar) -> None:
    from . import angle_method, rate_method
    from .procedures import PROCEDURES

    registrar.add_standard(
        STANDARD_ID,
        "光学陀螺仪通用技术要求 (Optical gyroscopes — general technical requirements)",
        designation="GB/T 45570—2025",
        description="test methods of normative appendix D",
    )
    from . import environmental, polarity, threshold

    for cls in angle_method.PROCEDURES + rate_method.PROCEDURES + PROCEDURES + threshold.PROCEDURES + environmental.PROCEDURES + polarity.PROCEDURES:
        registrar.add_procedure(cls)

    from .method_rule import SERIES

    for name, (members, description) in SERIES.items():
        registrar.add_series(STANDARD_ID, name, members, description)


@hookimpl
def metro_item_applicability(procedure, device):
    from .method_rule import applicability

    return applicability(procedure, device)


@hookimpl
def metro_conformity_specifications(standard, campaign):
    if standard != STANDARD_ID:
        return None
    from .conformity import specifications

    return specifications(campaign.device)


@hookimpl
def metro_register_templates(registrar) -> None:
    if REPORT_TEMPLATE.is_file():
        registrar.add_template("gbt45570-report", REPORT_TEMPLATE, standard=STANDARD_ID, kind="report")


@hookimpl
def metro_extend_report_context(record, context) -> None:
    from .report import extend_context

    extend_context(record, context)

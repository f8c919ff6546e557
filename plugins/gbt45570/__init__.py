"""GB/T 45570—2025 光学陀螺仪通用技术要求 (optical gyroscopes) as a metro plugin.

Registered through the ``metro`` entry-point group, like any third-party plugin.
Items implemented so far: D.1.1–D.1.6 (angle method, pulse output, :mod:`.angle_method`),
D.2.1–D.2.6 (rate method, LSB output, on the ``simulated-digital`` station) and D.3 (maximum
input rate, either method; :mod:`.rate_method`), D.4 (threshold, :mod:`.threshold`),
D.5.1–D.5.6 (bias series, ARW), D.6.1–D.6.4 (environmental) and 6.2.7.7/6.2.7.8 (set-up time,
power; :mod:`.environmental`) and 6.2.6 (polarity, :mod:`.polarity`); the rest of the type test of
clause 5 from the campaign's records: 5.2.3–5.2.8 inspection (:mod:`.inspection`), the 5.4 tests
done by GB/T 2423.x and others (:mod:`.type_env`), 5.5 reliability (:mod:`.reliability`), and the
clause-5 table of the report (:mod:`.clause5`).
"""

from __future__ import annotations

from metro.api import hookimpl

STANDARD_ID = "gbt45570"


def _register_vocabulary() -> None:
    """The record sections and equipment roles of the clause-5 type test (so the manifest's
    unknown-key check knows them); light: core.vocabulary imports neither numpy nor pint."""
    from metro.api import vocabulary as voc

    for name, text in (
        ("inspection", "GB/T 45570 5.2.1–5.2.8 inspection records (appearance, dimensions, "
                       "mass, supply, interfaces, insulation resistance)"),
        ("environmental_tests", "GB/T 45570 5.4 tests done by GB/T 2423.x and others: severity, "
                                "functional check, segments before and after"),
        ("reliability", "GB/T 45570 5.5 reliability evidence: operating hours, failures, "
                        "test plan, life"),
    ):
        voc.register_section(name, text)
    voc.register_role("calliper", "callipers / gauges for outline dimensions (GB/T 45570 6.2.2)",
                      ("caliper", "calipers"), calibration=("", "mm"))
    voc.register_role("balance", "electronic balance (GB/T 45570 6.2.3)", ("scale",),
                      calibration=("", "g"))
    voc.register_role("megohmmeter", "insulation resistance tester (GB/T 45570 6.2.5)",
                      ("insulation_tester",), calibration=("", "ohm"))


_register_vocabulary()


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

    for cls in (angle_method.PROCEDURES + rate_method.PROCEDURES + PROCEDURES + threshold.PROCEDURES
                + environmental.PROCEDURES + polarity.PROCEDURES):
        registrar.add_procedure(cls)
    from . import declarations, inspection, reliability, type_env
    from .clause5 import TYPE_TEST_ITEMS

    for cls in (declarations.PROCEDURES + inspection.PROCEDURES + type_env.PROCEDURES
                + reliability.PROCEDURES):
        registrar.add_procedure(cls)
    registrar.add_series(STANDARD_ID, "type-test", TYPE_TEST_ITEMS,
                         "clause 5 type test: every item answering a requirement of 5.2–5.5 "
                         "that applies")

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
    from .clause5 import specifications as type_test_specifications
    from .conformity import specifications

    return (specifications(campaign.device, campaign.specification)
            + type_test_specifications(campaign))


@hookimpl
def metro_register_templates(registrar) -> None:
    registrar.add_template("gbt45570-report", standard=STANDARD_ID, kind="report",
                           layout="metro.plugins.gbt45570.report:layout")


@hookimpl
def metro_extend_report_context(record, context) -> None:
    from .report import extend_context

    extend_context(record, context)  # its clause-5 table comes from clause5.clause5_rows


@hookimpl
def metro_expected_values(campaign, ideal):
    from .expected import expected_values

    return expected_values(campaign, ideal)


@hookimpl
def metro_validation_cases():
    """This standard's worked examples as validation cases (``metro validate``)."""
    from .validation import validation_cases

    return validation_cases()

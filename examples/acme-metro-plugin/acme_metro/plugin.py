"""The hooks metro calls (entry point ``acme`` in group ``metro``)."""

from __future__ import annotations

from pathlib import Path

from metro.api import hookimpl

TEMPLATE = Path(__file__).parent / "templates" / "acme_certificate.docx"


@hookimpl
def metro_register_standards(registrar):
    from .procedures import AcmeAcceptance, AcmeBiasStability10s

    # a vendor item in an existing standard's family (gbt45570 is registered by metro)
    registrar.add_procedure(AcmeBiasStability10s)
    # and ACME's own acceptance standard, so its certificate template has a standard to belong to
    registrar.add_standard("acme", "ACME factory acceptance tests", designation="ACME AT-7")
    registrar.add_procedure(AcmeAcceptance)


@hookimpl
def metro_register_readers(registrar):
    from .acmefile import read_acme

    registrar.add_reader((".acme",), read_acme, "ACME binary logger files")


@hookimpl
def metro_register_templates(registrar):
    registrar.add_template("acme-certificate", TEMPLATE, standard="acme")


@hookimpl
def metro_extend_report_context(record, context):
    if any(o.standard == "acme" for o in record.outcomes):
        context["acme"] = {"lab": "ACME Inertial, final test", "spec": "AT-7 rev. C"}

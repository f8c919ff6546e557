"""A register of registered reports for the web pages (``web_register``), on SQLite and on
PostgreSQL (``register_url``), and a Starlette TestClient on it (``web``).

The reports, issued through the register's own API (``Register.issue``; their files are small
stand-ins, so no Word rendering is needed):

* ``first`` — gbt45570 A.1 on serial S1 (customer "Acme Instruments"), measured 2026-01-01,
  bias 1.0 ± 0.2 °/h; superseded by ``amended`` ("customer address corrected");
* ``amended`` — the same measurement, with a verdict, equipment and a DCC embedding a PDF;
* ``later`` — S1 again on 2026-01-10, bias 2.0 ± 0.2 °/h: |E_n| = 1/√0.08 ≈ 3.54 > 1, drift;
* ``odd`` — jjf2014 on a device whose model is ``<script>alert(1)</script>`` and customer
  ``Tom & Jerry <b>``; withdrawn ("wrong device").
"""

from __future__ import annotations

import base64
import datetime as dt
from pathlib import Path

import pytest

#: the PDF the amended report's DCC embeds
PDF = b"%PDF-1.7\n% a stand-in\n%%EOF\n"
SCRIPT = "<script>alert(1)</script>"


def dcc_xml(pdf: bytes) -> bytes:
    return (b'<?xml version="1.0"?><dcc:digitalCalibrationCertificate '
            b'xmlns:dcc="https://ptb.de/dcc"><dcc:document><dcc:fileName>r.pdf</dcc:fileName>'
            b"<dcc:dataBase64>" + base64.b64encode(pdf) + b"</dcc:dataBase64></dcc:document>"
            b"</dcc:digitalCalibrationCertificate>")


VERDICTS = {"rule": "simple", "rule_title": "Simple acceptance", "overall": "pass",
            "statement": "Conformity is declared when the measured value is within the limit.",
            "verdicts": [{"item": "A.1", "key": "bias", "limit": "≤ 5 °/h", "source": "spec",
                          "status": "pass", "detail": "", "reason": ""}], "not_assessed": []}
EQUIPMENT = [{"id": "RT-01", "role": "rate_table", "description": "Example Motion RT-300",
              "certificate": "CAL-2026-0001", "due": "2027-06-30", "status": "valid",
              "valid": True}]


def lab_profile(folder: Path, register_url: str) -> Path:
    """A lab profile (English by default) whose second instrument falls due in ten days."""
    from metro.core.record.lab import TEMPLATE

    soon = (dt.date.today() + dt.timedelta(days=10)).isoformat()
    text = (TEMPLATE.replace('language = "zh+en"', 'language = "en"')
            .replace('register = "register.sqlite"', f'register = "{register_url}"'))
    text += ('\n[[equipment]]\nid = "GY-02"\nrole = "reference_gyro"\nmanufacturer = "Example"\n'
             'model = "RG-1"\nserial = "77"\n  [equipment.calibration]\n'
             f'  certificate = "CAL-2026-0099"\n  U = "0.01 deg/h"\n  k = 2\n  due = {soon}\n')
    path = folder / "lab.toml"
    path.write_text(text, encoding="utf-8")
    return path


def fill(url: str, folder: Path, draft_rows) -> dict[str, str]:
    """Issue, amend and withdraw the reports above; their numbers by name."""
    from metro.core.record.register import Draft, open_register

    def scheme(seq: int, year: int) -> str:
        return f"WEB{year}-{seq:04d}"

    def issue(reg, fields, result, *, content: bytes, dcc=None, **kw) -> str:
        draft = Draft(fields, [result], lambda p: p.write_bytes(content), dcc=dcc)
        return reg.issue(lambda n, t: draft, folder=folder, scheme=scheme, per_year=True,
                         **kw).number

    numbers = {}
    with open_register(url) as reg:
        fields, result = draft_rows(standard="gbt45570", serial="S1", day=1, value=1.0)
        fields["customer"] = "Acme Instruments"
        numbers["first"] = issue(reg, fields, result, content=b"first report")
        fields = dict(fields, verdicts=VERDICTS, equipment=EQUIPMENT)
        numbers["amended"] = issue(reg, fields, result, content=b"amended report",
                                   dcc=lambda tmp: dcc_xml(PDF), supersedes=numbers["first"],
                                   reason="customer address corrected")
        fields, result = draft_rows(standard="gbt45570", serial="S1", day=10, value=2.0)
        fields["customer"] = "Acme Instruments"
        result["value_text"] = "2.0"
        numbers["later"] = issue(reg, fields, result, content=b"later report")
        fields, result = draft_rows(standard="jjf2014", serial="S2", day=5, value=3.0)
        fields.update(device_model=SCRIPT, customer="Tom & Jerry <b>")
        numbers["odd"] = issue(reg, fields, result, content=b"odd report")
        reg.withdraw(numbers["odd"], "wrong device", who="qm@lab")
    return numbers


@pytest.fixture
def web_register(register_url, tmp_path, draft_rows):
    """(register URL, lab profile path, numbers by name, reports folder)."""
    folder = tmp_path / "reports"
    numbers = fill(register_url, folder, draft_rows)
    return register_url, lab_profile(tmp_path, register_url), numbers, folder


@pytest.fixture
def web(web_register):
    """(TestClient, numbers by name, reports folder) of ``create_app`` on ``web_register``."""
    from starlette.testclient import TestClient

    from metro.core.web.app import create_app

    url, lab, numbers, folder = web_register
    with TestClient(create_app(url, lab=lab)) as client:
        yield client, numbers, folder

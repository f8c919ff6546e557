"""The pages of ``metro serve`` through Starlette's TestClient, on SQLite and PostgreSQL: the
list with its filters and paging, a report, its downloads (checked against the register's
SHA-256), a device's history, the equipment, verification and the language switch.

The register (tests/core/web/conftest.py): ``first`` superseded by ``amended`` (S1, 2026-01-01,
bias 1.0 ± 0.2), ``later`` (S1, 2026-01-10, bias 2.0 ± 0.2), ``odd`` (jjf2014, S2, withdrawn)."""

from __future__ import annotations

import base64
import datetime as dt
import hashlib
import math
import re

#: the stand-in PDF the amended report's DCC embeds (conftest.PDF, written out again here)
PDF = b"%PDF-1.7\n% a stand-in\n%%EOF\n"


def listed(html: str) -> list[str]:
    return re.findall(r'<tr class="report" data-number="([^"]+)"', html)


def test_the_list_filters_and_pages(web, monkeypatch):
    client, n, _ = web
    r = client.get("/", follow_redirects=False)
    assert r.status_code == 303 and r.headers["location"] == "/reports"
    page = client.get("/reports")
    assert page.status_code == 200 and 'id="reports"' in page.text
    # newest issue first
    assert listed(page.text) == [n["odd"], n["later"], n["amended"], n["first"]]
    assert 'data-total="4"' in page.text
    cases = {"standard=jjf2014": [n["odd"]],
             "serial=S1": [n["later"], n["amended"], n["first"]],
             "customer=ACME": [n["later"], n["amended"], n["first"]],
             "status=superseded": [n["first"]], "status=withdrawn": [n["odd"]],
             "from=2026-01-05": [n["odd"], n["later"]],
             "to=2026-01-04": [n["amended"], n["first"]],
             "from=2026-01-02&to=2026-01-09&standard=jjf2014": [n["odd"]],
             "serial=S1&status=issued": [n["later"], n["amended"]],
             "customer=nobody": []}
    for query, expected in cases.items():
        got = client.get(f"/reports?{query}")
        assert got.status_code == 200 and listed(got.text) == expected, query
    assert 'id="no-reports"' in client.get("/reports?customer=nobody").text
    for bad in ("from=2026-13-01", "status=lost", "page=x"):
        assert client.get(f"/reports?{bad}").status_code == 400, bad
    # two a page: two pages, the filters kept in the paging links
    from metro.core.web import queries

    monkeypatch.setattr(queries, "PAGE_SIZE", 2)
    first = client.get("/reports?serial=S1&status=issued")
    assert listed(first.text) == [n["later"], n["amended"]] and 'id="next"' not in first.text
    one = client.get("/reports")
    assert listed(one.text) == [n["odd"], n["later"]]
    assert 'data-page="1" data-pages="2"' in one.text and 'id="prev"' not in one.text
    nxt = re.search(r'id="next" rel="next" href="([^"]+)"', one.text).group(1)
    two = client.get(nxt.replace("&amp;", "&"))
    assert listed(two.text) == [n["amended"], n["first"]] and 'id="prev"' in two.text
    filtered = client.get("/reports?standard=gbt45570&page=1")
    assert "standard=gbt45570&amp;page=2" in filtered.text
    # a page past the end shows the last one
    assert listed(client.get("/reports?page=99").text) == [n["amended"], n["first"]]


def test_a_report_page_shows_chain_results_conformity_equipment_and_files(web):
    client, n, _ = web
    page = client.get(f"/reports/{n['amended']}")
    assert page.status_code == 200
    html = page.text
    assert f'<span id="report-number">{n["amended"]}</span>' in html
    assert 'id="report-status" data-status="issued"' in html
    chain = re.findall(r'<li class="chain-entry[^"]*" data-number="([^"]+)"', html)
    assert chain == [n["first"], n["amended"]]
    assert "customer address corrected" in html
    row = re.search(r'<tr class="result" data-item="A.1" data-key="bias">(.*?)</tr>', html,
                    re.S).group(1)
    assert re.search(r'class="n value">1.0<', row) and re.search(r'class="n U">0.2<', row)
    assert re.search(r'class="n k">2<', row)
    assert re.search(r'class="verdict" data-verdict="pass">conforms<', row)
    assert "Conformity is declared when the measured value is within the limit." in html
    assert '<span id="overall" data-verdict="pass">conforms</span>' in html
    assert "CAL-2026-0001" in html and 'class="cal-status">valid<' in html
    for kind in ("pdf", "docx", "dcc"):
        link = f'href="/reports/{n["amended"]}/files/{kind}"'
        assert f'id="download-{kind}" class="download" {link}' in html
    assert "Acme Instruments" in html and "2026-01-01" in html
    # the report it replaced: superseded, linking to its successor; no DCC to download
    old = client.get(f"/reports/{n['first']}").text
    assert 'data-status="superseded"' in old and f'href="/reports/{n["amended"]}"' in old
    assert 'id="download-dcc"' not in old and 'id="download-docx"' in old
    # a report without a specification: no statement of conformity; a withdrawn one says why
    assert "makes no statement of conformity" in client.get(f"/reports/{n['later']}").text
    odd = client.get(f"/reports/{n['odd']}").text
    assert 'id="withdrawn-reason"' in odd and "wrong device" in odd
    missing = client.get("/reports/EML2026-99999")
    assert missing.status_code == 404 and 'id="error" data-status="404"' in missing.text


def test_downloads_are_the_registered_files_checked_against_their_sha256(web, monkeypatch,
                                                                       tmp_path):
    client, n, folder = web
    url = f"/reports/{n['amended']}/files"
    docx = client.get(f"{url}/docx")
    assert docx.status_code == 200 and docx.content == b"amended report"
    assert docx.headers["x-sha256"] == hashlib.sha256(b"amended report").hexdigest()
    assert docx.headers["content-disposition"] == f'attachment; filename="{n["amended"]}.docx"'
    dcc = client.get(f"{url}/dcc")
    assert dcc.status_code == 200 and base64.b64encode(PDF) in dcc.content
    assert hashlib.sha256(dcc.content).hexdigest() == hashlib.sha256(
        (folder / f"{n['amended']}.xml").read_bytes()).hexdigest()
    pdf = client.get(f"{url}/pdf")  # the PDF the registered DCC embeds
    assert pdf.status_code == 200 and pdf.content == PDF
    assert pdf.headers["content-type"] == "application/pdf"
    assert client.get(f"/reports/{n['first']}/files/dcc").status_code == 404
    # a file changed after it was registered is refused, and said so
    (folder / f"{n['later']}.docx").write_bytes(b"later report, edited")
    changed = client.get(f"/reports/{n['later']}/files/docx")
    assert changed.status_code == 409 and b"edited" not in changed.content
    assert "does not match its SHA-256 in the register" in changed.text
    # so is its PDF (made from the Word file only once that is checked)
    assert client.get(f"/reports/{n['later']}/files/pdf").status_code == 409
    (folder / f"{n['amended']}.xml").write_bytes(dcc.content.replace(b"r.pdf", b"x.pdf"))
    assert client.get(f"{url}/dcc").status_code == 409
    assert client.get(f"{url}/pdf").status_code == 409
    (folder / f"{n['first']}.docx").unlink()
    gone = client.get(f"/reports/{n['first']}/files/docx")
    assert gone.status_code == 404 and "The registered file is missing." in gone.text
    # without LibreOffice a report without a DCC has no PDF (a clear 404, not a 500)
    monkeypatch.delenv("METRO_SOFFICE", raising=False)
    monkeypatch.setenv("PATH", str(tmp_path))
    none = client.get(f"/reports/{n['odd']}/files/pdf")
    assert none.status_code == 404 and 'id="error"' in none.text
    assert client.get(f"/reports/{n['odd']}/files/xlsx").status_code == 404


def test_a_device_history_has_u_drift_flags_and_its_plot(web):
    client, n, _ = web
    page = client.get("/devices/S1")
    assert page.status_code == 200
    points = re.findall(r'<tr class="point( drift)?">.*?<a href="/reports/([^"]+)"', page.text,
                        re.S)
    # the superseded report is not part of the history; the later one drifted
    assert points == [("", n["amended"]), (" drift", n["later"])]
    en = abs(2.0 - 1.0) / math.sqrt(0.2 ** 2 + 0.2 ** 2)
    assert f'class="n en">{en:.4g}<' in page.text
    assert '<img id="history-plot" src="/devices/S1/history.png"' in page.text
    png = client.get("/devices/S1/history.png")
    assert png.status_code == 200 and png.headers["content-type"] == "image/png"
    assert png.content.startswith(b"\x89PNG\r\n\x1a\n") and len(png.content) > 5000
    assert client.get("/devices/NO-SUCH").status_code == 404
    assert client.get("/devices/NO-SUCH/history.png").status_code == 404


def test_the_equipment_page_says_what_falls_due(web):
    client, _, _ = web
    html = client.get("/equipment").text
    states = dict(re.findall(r'<tr class="equipment [^"]*" data-id="([^"]+)" data-state="([^"]+)"',
                             html))
    days = (dt.date(2027, 6, 30) - dt.date.today()).days
    rt = "expired" if days < 0 else "due-soon" if days <= 30 else "ok"
    assert states == {"GY-02": "due-soon", "RT-01": rt}
    soon = html.split('id="due-soon"')[1].split("</section>")[0]
    assert 'data-id="GY-02"' in soon and "(10 d)" in soon
    assert list(states) == ["GY-02", "RT-01"]  # soonest first
    # the date the states are judged on is labelled
    assert re.search(r'id="as-of">[^<]*\S+ ' + dt.date.today().isoformat() + "<", html)


def test_verify_says_issued_superseded_or_withdrawn_and_checks_an_upload(web):
    client, n, folder = web
    old = client.get(f"/verify/{n['first']}")
    assert old.status_code == 200 and 'data-status="superseded"' in old.text
    assert f'<a id="superseded-by" href="/verify/{n["amended"]}">{n["amended"]}</a>' in old.text
    assert 'data-status="issued"' in client.get(f"/verify/{n['amended']}").text
    gone = client.get(f"/verify/{n['odd']}").text
    assert 'data-status="withdrawn"' in gone and "wrong device" in gone
    assert client.get("/verify/EML2026-99999").status_code == 404
    form = client.get("/verify?number=" + n["later"], follow_redirects=False)
    assert form.status_code == 303 and form.headers["location"] == f"/verify/{n['later']}"
    assert 'id="verify-number"' in client.get("/verify").text

    def upload(number: str, content: bytes) -> str:
        r = client.post(f"/verify/{number}", files={"file": ("report.docx", content)})
        assert r.status_code == 200
        return r.text

    same = upload(n["amended"], b"amended report")
    assert 'data-match="true"' in same and "matches: this file is the registered Word report" \
        in same
    dcc = upload(n["amended"], (folder / f"{n['amended']}.xml").read_bytes())
    assert "registered Digital calibration certificate (DCC)" in dcc
    changed = upload(n["amended"], b"amended report!")
    assert 'data-match="false"' in changed and "does not match" in changed
    assert hashlib.sha256(b"amended report!").hexdigest() in changed
    # another report's file is not this one's
    assert 'data-match="false"' in upload(n["first"], b"amended report")
    empty = client.post(f"/verify/{n['amended']}", data={"x": "1"})
    assert empty.status_code == 200 and "No file was received." in empty.text


def test_the_language_follows_the_lab_then_the_switch_then_the_cookie(web):
    client, n, _ = web
    en = client.get("/reports")
    assert '<html lang="en">' in en.text and "Reports" in en.text
    zh = client.get("/reports?lang=zh")
    assert '<html lang="zh-CN">' in zh.text and "报告" in zh.text
    assert "metro_lang=zh" in zh.headers["set-cookie"]
    # remembered: the next page is Chinese without asking
    assert f"报告 {n['first']} 已被替代" in client.get(f"/verify/{n['first']}").text
    assert '<html lang="en">' in client.get("/equipment?lang=en").text
    assert '<html lang="en">' in client.get("/equipment?lang=fr").text  # cookie: en again


def test_a_list_page_follows_the_register_within_a_second(web, web_register):
    import time

    from metro.core.record.register import open_register
    from metro.core.web.app import Site

    client, n, _ = web
    status = re.compile(rf'data-number="{n["later"]}" data-status="(\w+)"')
    assert status.search(client.get("/reports").text).group(1) == "issued"
    with open_register(web_register[0], create=False) as reg:
        reg.withdraw(n["later"], "a late correction", who="qm@lab")
    time.sleep(Site.VERSION_TTL + 0.05)
    assert status.search(client.get("/reports").text).group(1) == "withdrawn"
    assert status.search(client.get("/reports?lang=zh").text).group(1) == "withdrawn"


def test_a_really_registered_run_is_shown_as_the_register_holds_it(lab, register_url,
                                                                   monkeypatch, tmp_path, capsys):
    """``metro run --register-simulated`` (JJF 2014 7.2.3), then its page: every result's reported
    value and U as the register stores them, its verdicts, its equipment, its Word file."""
    import html as htmlmod
    import json

    from starlette.testclient import TestClient

    from metro.core.cli.app import main
    from metro.core.record.register import open_register
    from metro.core.web.app import create_app

    monkeypatch.setenv("METRO_REGISTER", register_url)
    code = main(["run", "-s", "jjf2014", "-i", "7.2.3", "--no-progress", "--seed", "2",
                 "--out", str(tmp_path / "out"), "--register-simulated", "--json"])
    assert code in (0, 3, 4)
    number = json.loads(capsys.readouterr().out)["register"]["number"]
    with open_register(register_url, create=False) as reg:
        stored = reg.get(number)
    with TestClient(create_app(register_url, lab=lab)) as client:
        page = htmlmod.unescape(client.get(f"/reports/{number}?lang=en").text)
        docx = client.get(f"/reports/{number}/files/docx")
        device = client.get(f"/devices/{stored['device']['serial']}")
    assert len(stored["results"]) >= 1
    rows = re.findall(r'<tr class="result" data-item="([^"]+)" data-key="([^"]+)">(.*?)</tr>',
                      page, re.S)
    assert [(i, k) for i, k, _ in rows] == [(x["item"], x["key"]) for x in stored["results"]]
    for (_, _, row), x in zip(rows, stored["results"]):
        if x["reportable"]:
            assert f'class="n value">{x["reported"]["value"]}<' in row
            assert f'class="n U">{x["reported"]["U"] or "—"}<' in row
        else:
            assert x["reason"] in row
    if stored["verdicts"] is None:  # no specification given: no statement, and said so
        assert "makes no statement of conformity" in page
    else:
        assert stored["verdicts"]["statement"] in page
    for e in stored["equipment"]:
        assert f"<td>{e['id']}</td>" in page and e["status"] in page
    assert hashlib.sha256(docx.content).hexdigest() == stored["report_sha256"]
    assert device.status_code == 200 and number in device.text

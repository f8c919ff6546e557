"""``metro serve`` in a real browser: Debian's chromium driven by Playwright for Python (its own
browser download is never used), on a register of really registered reports, on SQLite and on
PostgreSQL.

The register is filled as a lab fills it, through ``metro run`` and ``metro amend``: two
recorded GB/T 45570 D.5.1 campaigns of the gyro serial 0042, measured in January (issued with its
DCC and PDF) and in June (Word only, its bias drifted), then the January report amended (so it is
superseded).  The lab profile's
``verify_url`` points at the server under test, so the QR code of each certificate links to a
page of it.  uvicorn serves :func:`metro.core.web.app.create_app` on 127.0.0.1 in a thread.

The path (issue 33): the list, then a filter; a report's page, then its PDF (the bytes of the
registered one); the device's history with its plot drawn; the verify page of the superseded
report, reached through the QR code's link (superseded, and by which report); an upload of a
changed file ("does not match") and of the registered file ("matches").  Every page is
photographed at desktop and phone (390×844) size into ``METRO_WEB_SCREENSHOTS`` (a temporary
folder without it).
"""

from __future__ import annotations

import json
import os
import socket
import threading
import time
from pathlib import Path

import pytest

CHROMIUM = "/usr/bin/chromium"
PHONE = {"width": 390, "height": 844}
DESKTOP = {"width": 1280, "height": 900}
RUN = ["run", "-s", "gbt45570", "-i", "D.5.1", "--no-progress"]

pytestmark = pytest.mark.skipif(
    not Path(CHROMIUM).is_file(),
    reason=f"no chromium at {CHROMIUM} (Debian's package; .ci/run installs it with apt)")


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _cli(*argv: str) -> dict:
    """``metro ARGV --json`` in this process, its JSON document."""
    import contextlib
    import io

    from metro.core.cli.app import main

    out = io.StringIO()
    with contextlib.redirect_stdout(out):
        code = main([*argv, "--json"])
    assert code in (0, 3, 4), (argv, code)  # a run exits 0, 3 or 4 by its verdict
    return json.loads(out.getvalue())


def _campaign(factory, folder: Path, measured: str, bias_deg_h: float) -> Path:
    """A recorded half-hour static campaign of the gyro serial 0042, measured on ``measured``."""
    from metro.instruments.simulated import GyroTruth

    return factory.write_campaign(
        folder, hours=0.5, truth=GyroTruth(bias_deg_h=bias_deg_h),
        manifest_edit=lambda t: t.replace('[campaign]\n', f'[campaign]\nmeasurement_date = '
                                          f'{measured}\ncustomer = "Acme Instruments"\n', 1))


def _fill(folder: Path, url: str, port: int, factory) -> dict:
    """A lab profile on ``url`` whose verify page is the server's; the reports described above."""
    from metro.core.record.lab import TEMPLATE

    lab = folder / "lab.toml"
    lab.write_text(TEMPLATE.replace('register = "register.sqlite"', f'register = "{url}"').replace(
        '# verify_url = "https://lab.example/verify/"',
        f'verify_url = "http://127.0.0.1:{port}/verify/"'), encoding="utf-8")
    out = folder / "out"
    with pytest.MonkeyPatch.context() as mp:
        mp.setenv("METRO_LAB", str(lab))
        mp.delenv("METRO_REGISTER", raising=False)
        january = _campaign(factory, folder / "january", "2026-01-05", 0.12)
        june = _campaign(factory, folder / "june", "2026-06-05", 0.14)
        first = _cli(*RUN, "--data", str(january), "--out", str(out), "--format", "dcc", "--pdf")
        second = _cli(*RUN, "--data", str(june), "--out", str(out))
        amended = _cli("amend", first["report_number"], "--reason", "customer name corrected")
        show = _cli("register", "show", first["report_number"])
    return {"lab": lab, "out": out, "first": first["report_number"],
            "second": second["report_number"], "amended": amended["number"],
            "serial": show["device"]["serial"]}


@pytest.fixture(scope="module", params=["sqlite", "postgresql"])
def served(request, tmp_path_factory, campaign_factory):
    """(base URL, what :func:`_fill` made): the register served by uvicorn on 127.0.0.1."""
    import uvicorn

    from metro.core.web.app import create_app

    folder = tmp_path_factory.mktemp(f"web-{request.param}")
    if request.param == "sqlite":
        url = "sqlite:///" + str(folder / "register.sqlite")
    else:
        url = request.getfixturevalue("pg_server").new_database()
    port = _free_port()
    made = _fill(folder, url, port, campaign_factory)
    server = uvicorn.Server(uvicorn.Config(create_app(url, lab=made["lab"]), host="127.0.0.1",
                                           port=port, log_level="warning"))
    thread = threading.Thread(target=server.run, daemon=True)
    thread.start()
    deadline = time.monotonic() + 10
    while not server.started:
        assert thread.is_alive() and time.monotonic() < deadline, "uvicorn did not start"
        time.sleep(0.02)
    yield f"http://127.0.0.1:{port}", made | {"backend": request.param}
    server.should_exit = True
    thread.join(timeout=10)


@pytest.fixture(scope="module")
def browser():
    from playwright.sync_api import sync_playwright

    with sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM)
        yield b
        b.close()


def _qr_link(docx_path: Path) -> str:
    """The link the QR code of a registered .docx encodes (its picture's alternative text, which
    :func:`metro.core.documents.qr.float_top_right` sets to the encoded link)."""
    import docx

    (descr,) = docx.Document(str(docx_path)).element.body.xpath(".//wp:anchor/wp:docPr/@descr")
    return str(descr)


def test_the_register_in_a_browser(served, browser, tmp_path_factory):
    from playwright.sync_api import expect

    base, made = served
    n1, n2, n3, out = made["first"], made["second"], made["amended"], made["out"]
    shots = Path(os.environ.get("METRO_WEB_SCREENSHOTS") or tmp_path_factory.mktemp("shots"))
    shots = shots / made["backend"]
    shots.mkdir(parents=True, exist_ok=True)
    desk = browser.new_context(viewport=DESKTOP, accept_downloads=True)
    page = desk.new_page()
    visited: list[tuple[str, str]] = []

    def shot(name: str) -> None:
        page.screenshot(path=str(shots / f"{name}.png"), full_page=True)
        visited.append((name, page.url))
        # no Python object leaks into a page as text (a label once printed "<built-in method …>")
        assert " object at 0x" not in page.inner_text("body"), name

    # 1. the list in the lab's language (zh+en: Chinese first), switched to English, filtered
    page.goto(f"{base}/reports")
    expect(page.locator("html")).to_have_attribute("lang", "zh-CN")
    expect(page.locator("tr.report")).to_have_count(3)
    shot("1-list-zh")
    page.click("#lang-en")
    expect(page.locator("html")).to_have_attribute("lang", "en")
    assert page.locator("tr.report").evaluate_all(
        "rows => rows.map(r => r.dataset.number)") == [n3, n2, n1]
    page.select_option("#f-status", "superseded")
    page.click("#f-submit")
    expect(page.locator("tr.report")).to_have_count(1)
    expect(page.locator("tr.report")).to_have_attribute("data-number", n1)
    expect(page.locator("#count")).to_have_attribute("data-total", "1")
    shot("1-list-filtered")

    # 2. the report's page, then its PDF: the registered one, byte for byte
    page.click(f"tr.report[data-number='{n1}'] a.report-link")
    expect(page.locator("#report-number")).to_have_text(n1)
    expect(page.locator("#report-status")).to_have_attribute("data-status", "superseded")
    expect(page.locator("tr.result")).not_to_have_count(0)
    shot("2-report")
    with page.expect_download() as dl:
        page.click("#download-pdf")
    pdf = Path(dl.value.path()).read_bytes()
    assert pdf[:5] == b"%PDF-" and pdf == (out / f"{n1}.pdf").read_bytes()

    # 3. the device's history: the plot drawn (loaded, visible, not empty)
    page.click("#device-link")
    expect(page.locator("#serial")).to_have_text(made["serial"])
    expect(page.locator("#calibrations li")).to_have_count(2)  # the amendment, then June
    plot = page.locator("img#history-plot")
    expect(plot).to_be_visible()
    plot.scroll_into_view_if_needed()
    # decode() waits for the image (the pages' CSP forbids the string eval wait_for_function uses)
    assert plot.evaluate("img => img.decode().then(() => img.naturalWidth)") > 0
    box = plot.bounding_box()
    assert box is not None and box["width"] > 100 and box["height"] > 50
    shot("3-device")

    # 4. the superseded report's verify page, reached through its certificate's QR code
    link = _qr_link(out / f"{n1}.docx")
    assert link == f"{base}/verify/{n1}"
    page.goto(link)
    expect(page.locator("#verify-status")).to_have_attribute("data-status", "superseded")
    expect(page.locator("#verify-status")).to_contain_text("superseded")
    expect(page.locator("a#superseded-by")).to_have_text(n3)
    shot("4-verify-superseded")

    # 5. a changed file does not match; the registered one does
    registered = (out / f"{n1}.docx").read_bytes()
    for content, match, words in ((registered + b"\0", "false", "does not match"),
                                  (registered, "true", "matches")):
        page.set_input_files("#upload-file", files=[{
            "name": f"{n1}.docx", "mimeType": "application/octet-stream", "buffer": content}])
        page.click("#upload-submit")
        expect(page.locator("#upload-result")).to_have_attribute("data-match", match)
        expect(page.locator("#upload-result")).to_contain_text(words)
        shot(f"5-upload-{match}")
    page.goto(f"{base}/equipment")
    shot("6-equipment")

    # the same pages on a phone: photographed, and none wider than the screen
    phone = browser.new_context(viewport=PHONE, is_mobile=True, has_touch=True,
                                device_scale_factor=2)
    page = phone.new_page()
    wide = {}
    for name, url in [v for v in visited if not v[0].startswith("5-")]:
        lang = "zh" if name.endswith("-zh") else "en"
        page.goto(url + ("&" if "?" in url else "?") + f"lang={lang}")
        page.screenshot(path=str(shots / f"phone-{name}.png"), full_page=True)
        wide[name] = page.evaluate("document.documentElement.scrollWidth")
    assert all(w <= PHONE["width"] for w in wide.values()), wide
    phone.close()
    desk.close()

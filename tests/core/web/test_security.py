"""``metro serve`` changes nothing and serves nothing it should not: every HTTP method on every
route (only GET/HEAD, and POST on /verify/{number}, which changes nothing), everything escaped,
path traversal refused, only registered files downloadable, and 127.0.0.1 by default."""

from __future__ import annotations

import hashlib

import pytest

from metro.core.cli.app import main

METHODS = ("GET", "HEAD", "POST", "PUT", "PATCH", "DELETE", "OPTIONS", "TRACE", "PROPFIND")


def routes(n: dict[str, str]) -> dict[str, set[str]]:
    """Every route (with real parameters) and the methods it answers."""
    read = {"GET", "HEAD"}
    number = n["amended"]
    return {"/": read, "/reports": read, f"/reports/{number}": read,
            f"/reports/{number}/files/docx": read, "/devices/S1": read,
            "/devices/S1/history.png": read, "/equipment": read, "/verify": read,
            f"/verify/{number}": read | {"POST"}}


def snapshot(url: str, folder) -> tuple:
    """Everything a request could change: every row of the register (as the register reads it,
    with the audit trail) and every file in the reports folder."""
    from metro.core.record.register import open_register

    with open_register(url, create=False) as reg:
        rows = [reg.get(r["number"]) for r in reg.list()]
        audit = reg.audit()
    files = {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in folder.iterdir()}
    return rows, audit, files


def test_every_method_on_every_route_and_the_register_is_unchanged(web, web_register):
    client, n, folder = web
    url = web_register[0]
    before = snapshot(url, folder)
    for path, allowed in routes(n).items():
        for method in METHODS:
            kw = {"files": {"file": ("f", b"x")}} if method == "POST" else {}
            r = client.request(method, path, follow_redirects=False, **kw)
            if method in allowed:
                assert r.status_code in (200, 303), (method, path, r.status_code)
            else:
                assert r.status_code == 405, (method, path, r.status_code)
                assert set(r.headers["allow"].replace(" ", "").split(",")) == allowed, path
    assert snapshot(url, folder) == before


def test_a_script_in_a_device_name_is_text(web):
    client, n, _ = web
    pages = [f"/reports/{n['odd']}", f"/verify/{n['odd']}", "/reports", "/reports?serial=S2"]
    for path in pages:
        html = client.get(path).text
        assert "<script" not in html, path
        assert "&lt;script&gt;alert(1)&lt;/script&gt;" in html, path
    assert "Tom &amp; Jerry &lt;b&gt;" in client.get(f"/reports/{n['odd']}").text
    # what a reader types is escaped too
    echoed = client.get('/reports?customer="><script>x</script>').text
    assert "<script" not in echoed and "&#34;&gt;&lt;script&gt;" in echoed
    headers = client.get("/reports").headers
    assert "script-src" not in headers["content-security-policy"]
    assert "default-src 'none'" in headers["content-security-policy"]
    assert headers["x-content-type-options"] == "nosniff"


@pytest.mark.parametrize("path", [
    "/reports/..%2F..%2F..%2Fetc%2Fpasswd/files/docx",
    "/reports/../../../etc/passwd/files/docx",
    "/reports/{n}/files/..%2F..%2F..%2Fetc%2Fpasswd",
    "/reports/{n}/files/%2Fetc%2Fpasswd",
    "/reports/{n}/files/docx%00.txt",
    "/reports/..%2F{n}/files/docx",
    "/reports/{n}%2F..%2F..%2Fx/files/docx",
    "/reports/..%5C..%5Cetc%5Cpasswd/files/docx",
    "/reports/%2e%2e/files/docx",
    "/reports/{n}.docx/files/docx",
    "/devices/..%2F..%2Fetc%2Fpasswd/history.png",
    "/verify/..%2F..%2Fetc%2Fpasswd",
])
def test_path_traversal_is_refused(web, path):
    client, n, _ = web
    r = client.get(path.format(n=n["amended"]))
    assert r.status_code == 404, path
    assert b"root:" not in r.content and b"amended report" not in r.content


def test_only_registered_files_are_served(web):
    """A file beside the registered ones (here: one named as a report's PDF would be) is never
    served: the PDF comes from the checked DCC, and unknown kinds are 404."""
    client, n, folder = web
    (folder / f"{n['amended']}.pdf").write_bytes(b"%PDF a forgery")
    assert b"forgery" not in client.get(f"/reports/{n['amended']}/files/pdf").content
    for kind in ("xml", "sqlite", "toml", "DOCX", ""):
        assert client.get(f"/reports/{n['amended']}/files/{kind}").status_code == 404, kind


def test_serve_binds_to_localhost_unless_told(web_register, monkeypatch, tmp_path):
    import uvicorn

    url, lab, _, _ = web_register
    calls = []
    monkeypatch.setattr(uvicorn, "run", lambda app, **kw: calls.append((app, kw)))
    monkeypatch.delenv("METRO_REGISTER", raising=False)
    assert main(["--lab", str(lab), "serve"]) == 0
    assert main(["serve", "--lab", str(lab), "--host", "0.0.0.0", "--port", "8123"]) == 0
    assert [(c[1]["host"], c[1]["port"]) for c in calls] == [("127.0.0.1", 8000),
                                                             ("0.0.0.0", 8123)]
    assert calls[0][0].state.site.url == url


def test_serve_never_makes_a_register(tmp_path, monkeypatch, capsys):
    from metro.core.record.register import RegisterError
    from metro.core.web.app import create_app

    monkeypatch.delenv("METRO_REGISTER", raising=False)
    target = tmp_path / "none" / "register.sqlite"
    with pytest.raises(RegisterError, match="no register"):
        create_app(f"sqlite:///{target}")
    assert not target.parent.exists()
    lab = tmp_path / "lab.toml"
    assert main(["lab", "init", str(lab)]) == 0
    assert main(["--lab", str(lab), "serve"]) == 2
    assert "no register" in capsys.readouterr().err
    assert not (tmp_path / "register.sqlite").exists()


def test_an_upload_too_large_is_refused(web, monkeypatch):
    from metro.core.web import app

    client, n, _ = web
    monkeypatch.setattr(app, "MAX_UPLOAD", 1000)
    small = client.post(f"/verify/{n['amended']}", files={"file": ("f", b"x" * 1000)})
    assert small.status_code == 200 and 'data-match="false"' in small.text
    # larger than the limit: read, then refused; far larger: refused by its length alone
    for size in (1001, 100_000):
        big = client.post(f"/verify/{n['amended']}", files={"file": ("f", b"x" * size)})
        assert big.status_code == 413 and 'id="error" data-status="413"' in big.text, size


def test_the_kept_connections_are_read_only_and_closed_at_shutdown(web_register):
    """The register is read on connections that cannot write (SQLite ``mode=ro``, PostgreSQL
    ``default_transaction_read_only``), closed when the application stops."""
    from starlette.testclient import TestClient

    from metro.core.web import queries
    from metro.core.web.app import create_app

    url = web_register[0]
    with TestClient(create_app(url)) as client:
        assert client.get("/reports").status_code == 200
        with queries.reader(url) as r:
            with pytest.raises(Exception, match="(?i)read.only|readonly"):
                r.rows("UPDATE reports SET customer = 'x'")
        assert url in queries.POOLS
    assert url not in queries.POOLS

"""The Starlette application of ``metro serve`` (routes and their HTML ids:
:mod:`metro.core.web`).

Every route answers GET and HEAD only, except ``/verify/{number}``, which also takes the POST of
its upload form (the file is hashed and dropped; nothing is written).  Pages are Jinja2 templates
with autoescaping on; the register is read through :mod:`metro.core.web.queries`.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import hashlib
import math
import os
import re
import threading
import time
import urllib.parse
from pathlib import Path
from typing import Any, Mapping

from starlette.applications import Starlette
from starlette.concurrency import run_in_threadpool
from starlette.exceptions import HTTPException
from starlette.requests import Request
from starlette.responses import HTMLResponse, RedirectResponse, Response
from starlette.routing import Route

from ..record.lab import LabProfile, load_lab, redact_url
from ..record.register import RegisterError, register_state
from . import i18n, queries

__all__ = ["create_app", "MAX_UPLOAD"]

#: the largest file the verification form hashes (bytes)
MAX_UPLOAD = 64 * 1024 * 1024
#: the response headers of every page: no framing, no sniffing, scripts from nowhere
SECURITY_HEADERS = [
    (b"x-content-type-options", b"nosniff"),
    (b"x-frame-options", b"DENY"),
    (b"referrer-policy", b"same-origin"),
    (b"content-security-policy",
     b"default-src 'none'; img-src 'self'; style-src 'unsafe-inline'; form-action 'self'; "
     b"frame-ancestors 'none'; base-uri 'none'"),
]
MEDIA = {"docx": "application/vnd.openxmlformats-officedocument.wordprocessingml.document",
         "pdf": "application/pdf", "dcc": "application/xml"}


class _SecurityHeaders:
    """ASGI middleware adding :data:`SECURITY_HEADERS` to every response."""

    def __init__(self, app: Any) -> None:
        self.app = app

    async def __call__(self, scope: Any, receive: Any, send: Any) -> None:
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return

        async def sending(message: Any) -> None:
            if message["type"] == "http.response.start":
                message["headers"] = list(message.get("headers", [])) + SECURITY_HEADERS
            await send(message)

        await self.app(scope, receive, sending)


def _environment():
    import jinja2

    env = jinja2.Environment(
        loader=jinja2.FileSystemLoader(str(Path(__file__).parent / "templates")),
        autoescape=True, trim_blocks=True, lstrip_blocks=True, auto_reload=False)
    env.filters["q"] = _quote
    env.filters["num"] = _num
    return env


#: what needs no quoting in a path segment
_PLAIN = re.compile(r"[A-Za-z0-9_.~-]*\Z")


def _quote(v: Any) -> str:
    """A path segment: ``v`` percent-encoded (``/`` too)."""
    s = str(v)
    return s if _PLAIN.match(s) else urllib.parse.quote(s, safe="")


def _num(v: Any) -> str:
    if v is None:
        return "—"
    if isinstance(v, float):
        return f"{v:.4g}"
    return str(v)


def _with_lang(request: Request, lang: str) -> str:
    """This page's path and query with ``lang=`` (relative: the Host header is not trusted)."""
    query = {k: v for k, v in request.query_params.items() if k != "lang"}
    return request.url.path + "?" + urllib.parse.urlencode({**query, "lang": lang})


class Site:
    """The pages of one register (``url``) and lab profile (``lab``, may be None)."""

    #: how long a list page may lag the register (seconds)
    VERSION_TTL = 1.0

    def __init__(self, url: str, lab: LabProfile | None) -> None:
        self.url = url
        self.lab = lab
        self.env = _environment()
        self.default_lang = i18n.default_lang(lab.language if lab else None)
        self.plot_lock = threading.Lock()
        #: list pages as rendered, by query and language, with the register's version then
        self.pages: dict[tuple[str, str, int], tuple[tuple, bytes]] = {}
        self.seen: tuple[float, tuple] = (-math.inf, ())

    # -- rendering -----------------------------------------------------------------------
    def lang(self, request: Request) -> str:
        return i18n.pick_lang(request.query_params, request.cookies, self.default_lang)

    def render(self, request: Request, template: str, status: int = 200,
               **ctx: Any) -> Response:
        """A page in the request's language; ``?lang=`` is remembered in a cookie."""
        lang = self.lang(request)
        t = i18n.words(lang)
        lab_name = ""
        if self.lab is not None:
            lab_name = self.lab.name_zh if lang == "zh" and self.lab.name_zh else self.lab.name
        html = self.env.get_template(template).render(
            t=t, lang=lang, lab_name=lab_name, path=request.url.path,
            switch={x: _with_lang(request, x) for x in i18n.LANGS},
            **ctx)
        return self.remember_lang(request, HTMLResponse(html, status_code=status))

    def remember_lang(self, request: Request, resp: Response) -> Response:
        """``resp`` with the cookie that remembers ``?lang=`` when the request chose one."""
        lang = request.query_params.get("lang")
        if lang in i18n.LANGS:
            resp.set_cookie(i18n.COOKIE, lang, max_age=365 * 86400, httponly=True,
                            samesite="lax")
        return resp

    def error(self, request: Request, status: int, key: str, detail: str = "",
              headers: Mapping[str, str] | None = None) -> Response:
        resp = self.render(request, "error.html", status=status, status_code=status,
                           key=key, detail=detail)
        for k, v in (headers or {}).items():
            resp.headers[k] = v
        return resp

    # -- routes --------------------------------------------------------------------------
    def home(self, request: Request) -> Response:
        return RedirectResponse("/reports", status_code=303)

    async def reports(self, request: Request) -> Response:
        """A page is kept, by query and language, until the register changes
        (:func:`queries.version`, one query on indexed keys, read at most once a second): a kept
        page is answered on the event loop, a new one is read and rendered in the thread pool."""
        key = (str(request.query_params), self.lang(request), queries.PAGE_SIZE)
        version = self.version()
        kept = self.pages.get(key)
        if kept is not None and kept[0] == version:
            return self.remember_lang(request, HTMLResponse(kept[1]))
        resp = await run_in_threadpool(self.list_page, request)
        if resp.status_code == 200:
            if len(self.pages) >= 512:
                self.pages.pop(next(iter(self.pages)))
            self.pages[key] = (version, bytes(resp.body))
        return resp

    def version(self) -> tuple:
        """The register's version (:func:`queries.version`), read at most once a second."""
        now = time.monotonic()
        if now - self.seen[0] >= self.VERSION_TTL:
            self.seen = (now, queries.version(self.url))
        return self.seen[1]

    def list_page(self, request: Request) -> Response:
        q = request.query_params
        try:
            filters = queries.Filters.parse(q)
            page = int(q.get("page") or 1)
        except ValueError as exc:
            return self.error(request, 400, "error", str(exc))
        result = queries.list_reports(self.url, filters, page, queries.PAGE_SIZE)
        query = filters.query()

        def page_url(n: int) -> str:
            return "/reports?" + urllib.parse.urlencode({**query, "page": n})

        return self.render(request, "reports.html", page=result, filters=filters,
                           standards=queries.standards(self.url), statuses=queries.STATUSES,
                           page_url=page_url)

    def _report_or_404(self, request: Request) -> dict[str, Any] | Response:
        number = request.path_params["number"]
        if not queries.NUMBER_RE.match(number):
            return self.error(request, 404, "not_found", "not a report number")
        report = queries.get_report(self.url, number)
        if report is None:
            return self.error(request, 404, "verify_unknown", number)
        return report

    def report(self, request: Request) -> Response:
        report = self._report_or_404(request)
        if isinstance(report, Response):
            return report
        conformity = report.get("verdicts") if isinstance(report.get("verdicts"), dict) else None
        verdicts = {(v.get("item"), v.get("key")): v.get("status")
                    for v in (conformity or {}).get("verdicts", []) if isinstance(v, dict)}
        downloads = {k: _available(report, k) for k in queries.KINDS}
        return self.render(request, "report.html", r=report,
                           chain=queries.chain(self.url, report), conformity=conformity,
                           verdicts=verdicts, downloads=downloads)

    def file(self, request: Request) -> Response:
        kind = request.path_params["kind"]
        if kind not in queries.KINDS:
            return self.error(request, 404, "not_found", "no such download")
        report = self._report_or_404(request)
        if isinstance(report, Response):
            return report
        try:
            data, name = queries.checked_file(report, kind)
        except queries.FileProblem as exc:
            return self.error(request, exc.status, exc.key, exc.detail)
        return Response(data, media_type=MEDIA[kind],
                        headers={"content-disposition": f'attachment; filename="{name}"',
                                 "x-sha256": hashlib.sha256(data).hexdigest()})

    def device(self, request: Request) -> Response:
        serial = request.path_params["serial"]
        hist = queries.device_history(self.url, serial)
        if not hist["calibrations"]:
            return self.error(request, 404, "no_history", serial)
        return self.render(request, "device.html", hist=hist)

    def device_plot(self, request: Request) -> Response:
        hist = queries.device_history(self.url, request.path_params["serial"])
        if not hist["calibrations"]:
            return self.error(request, 404, "no_history")
        with self.plot_lock:  # matplotlib's rc settings are global
            png = queries.history_png(hist)
        return Response(png, media_type="image/png")

    def equipment(self, request: Request) -> Response:
        today = dt.date.today()
        rows = queries.lab_equipment_status(self.lab.equipment if self.lab else (), today)
        return self.render(request, "equipment.html", rows=rows, has_lab=self.lab is not None,
                           today=today.isoformat(), days=queries.DUE_DAYS)

    def verify_form(self, request: Request) -> Response:
        number = (request.query_params.get("number") or "").strip()
        if number and queries.NUMBER_RE.match(number):
            return RedirectResponse(f"/verify/{urllib.parse.quote(number)}", status_code=303)
        return self.render(request, "verify.html", r=None, number=number, upload=None)

    async def verify(self, request: Request) -> Response:
        report = await run_in_threadpool(self._report_or_404, request)
        if isinstance(report, Response):
            return report
        upload = None
        if request.method == "POST":
            upload = await self._upload(request, report)
            if isinstance(upload, Response):
                return upload
        return self.render(request, "verify.html", r=report, number=report["number"],
                           upload=upload)

    async def _upload(self, request: Request, report: Mapping[str, Any]) -> Any:
        """The uploaded file's SHA-256 against the register: {"match": kind or None, "sha256"}; a
        body larger than :data:`MAX_UPLOAD` is refused before it is read (413)."""
        length = request.headers.get("content-length", "")
        if length.isdigit() and int(length) > MAX_UPLOAD + 65536:
            return self.error(request, 413, "error", "file too large")
        async with request.form(max_files=1, max_fields=4) as form:
            upload = form.get("file")
            if upload is None or isinstance(upload, str):
                return {"match": None, "sha256": None, "missing": True}
            h, size = hashlib.sha256(), 0
            while chunk := await upload.read(1 << 20):
                size += len(chunk)
                if size > MAX_UPLOAD:
                    return self.error(request, 413, "error", "file too large")
                h.update(chunk)
        digest = h.hexdigest()
        return {"match": queries.upload_matches(report, digest), "sha256": digest,
                "missing": False}


def _available(report: Mapping[str, Any], kind: str) -> bool:
    """Whether the report page offers a ``kind`` download (a PDF: always, made when asked)."""
    if kind == "dcc":
        return bool(report.get("dcc_path"))
    return kind == "pdf" or Path(report["report_path"]).suffix.lower() == f".{kind}"


def create_app(register_url: str, *, lab: LabProfile | str | os.PathLike[str] | None = None
               ) -> Starlette:
    """The web application of the register at ``register_url`` (read only), with the lab profile
    ``lab`` (a profile or its path; its equipment and default language), for uvicorn or
    Starlette's TestClient.  A missing register, or one at an older schema, is a
    :class:`~metro.core.record.register.RegisterError` (nothing is made or migrated)."""
    if lab is not None and not isinstance(lab, LabProfile):
        lab = load_lab(lab)
    state = register_state(register_url)
    if not state["exists"]:
        raise RegisterError(f"no register at {redact_url(register_url)}",
                            hint="a register is made by the first registered run (docs/"
                            "register.md); `metro serve` only reads")
    if not state["migrated"]:
        raise RegisterError(f"register {redact_url(register_url)} is at schema "
                            f"{state['revision']}, not {state['head']}",
                            hint="`metro register list` brings it up to date once; `metro serve` "
                            "never changes the register")
    site = Site(register_url, lab)

    async def http_error(request: Request, exc: Exception) -> Response:
        assert isinstance(exc, HTTPException)
        key = "not_found" if exc.status_code == 404 else "error"
        return site.error(request, exc.status_code, key, str(exc.detail), exc.headers)

    get = ["GET"]
    routes = [
        Route("/", site.home, methods=get),
        Route("/reports", site.reports, methods=get),
        Route("/reports/{number}", site.report, methods=get),
        Route("/reports/{number}/files/{kind}", site.file, methods=get),
        Route("/devices/{serial}", site.device, methods=get),
        Route("/devices/{serial}/history.png", site.device_plot, methods=get),
        Route("/equipment", site.equipment, methods=get),
        Route("/verify", site.verify_form, methods=get),
        Route("/verify/{number}", site.verify, methods=["GET", "POST"]),
    ]
    @contextlib.asynccontextmanager
    async def lifespan(app: Starlette):
        yield
        queries.close(register_url)  # the kept connections

    app = Starlette(routes=routes, exception_handlers={HTTPException: http_error},
                    lifespan=lifespan)
    app.add_middleware(_SecurityHeaders)
    app.state.site = site
    return app

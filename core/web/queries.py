"""What the pages read from the register, through :mod:`metro.core.record` only and never
writing: a filtered, paged list; one report with its amendment chain; a device's history (as
``metro history`` computes it); the lab's equipment and what falls due; a registered file checked
against its SHA-256."""

from __future__ import annotations

import contextlib
import datetime as dt
import hashlib
import json
import re
import threading
from pathlib import Path
from typing import Any, Iterable, Iterator, Mapping

import attrs

from ..record.register import Register, report_dict, sqlite_path
from ..record.register.models import STATUSES
from ..record.register.reading import Reader, libpq_url

__all__ = ["PAGE_SIZE", "NUMBER_RE", "KINDS", "Filters", "Page", "list_reports", "standards",
           "get_report", "version", "reader", "close", "chain", "device_history",
           "lab_equipment_status", "checked_file", "FileProblem", "upload_matches", "history_png",
           "word_pdf"]

#: reports on one list page
PAGE_SIZE = 25
#: what a report number may look like in a URL (no slash, no dot-dot, no space)
NUMBER_RE = re.compile(r"^[A-Za-z0-9][A-Za-z0-9_\-]*(\.[A-Za-z0-9_\-]+)*$")
#: the downloads of a report
KINDS = ("docx", "pdf", "dcc")
#: how far ahead the equipment page looks for due dates
DUE_DAYS = 30


@attrs.frozen
class Filters:
    """The list page's filters (empty strings: no filter)."""

    standard: str = ""
    serial: str = ""
    customer: str = ""
    status: str = ""
    date_from: dt.date | None = None
    date_to: dt.date | None = None

    @classmethod
    def parse(cls, q: Mapping[str, str]) -> "Filters":
        """From a query string; a date that is not YYYY-MM-DD or an unknown status is a
        ValueError."""
        status = (q.get("status") or "").strip()
        if status and status not in STATUSES:
            raise ValueError(f"status must be one of {', '.join(STATUSES)}")
        return cls(standard=(q.get("standard") or "").strip(),
                   serial=(q.get("serial") or "").strip(),
                   customer=(q.get("customer") or "").strip(), status=status,
                   date_from=_date(q.get("from")), date_to=_date(q.get("to")))

    def where(self, sqlite: bool) -> tuple[str, list[Any]]:
        """The SQL condition (``?`` marks) and its parameters."""
        conds: list[str] = []
        params: list[Any] = []
        for cond, value in (("standard = ?", self.standard), ("device_serial = ?", self.serial),
                            ("status = ?", self.status)):
            if value:
                conds.append(cond)
                params.append(value)
        if self.customer:
            conds.append("lower(customer) LIKE ?")
            params.append("%" + self.customer.lower() + "%")
        for cond, day in (("measurement_date >= ?", self.date_from),
                          ("measurement_date <= ?", self.date_to)):
            if day is not None:
                conds.append(cond)
                params.append(day.isoformat() if sqlite else day)
        return ("WHERE " + " AND ".join(conds)) if conds else "", params

    def query(self) -> dict[str, str]:
        """The filters as query parameters (for paging links)."""
        out = {"standard": self.standard, "serial": self.serial, "customer": self.customer,
               "status": self.status,
               "from": self.date_from.isoformat() if self.date_from else "",
               "to": self.date_to.isoformat() if self.date_to else ""}
        return {k: v for k, v in out.items() if v}


def _date(text: str | None) -> dt.date | None:
    text = (text or "").strip()
    if not text:
        return None
    try:
        return dt.date.fromisoformat(text)
    except ValueError:
        raise ValueError(f"{text!r} is not a date (YYYY-MM-DD)") from None


@attrs.frozen
class Page:
    """One page of the list: its reports (newest first), the total and the page numbers."""

    reports: list[dict[str, Any]]
    total: int
    page: int
    pages: int


class _PooledReader(Reader):
    """A :class:`~metro.core.record.register.reading.Reader` on a kept connection."""

    def __init__(self, conn: Any, sqlite: bool) -> None:  # the connection is given
        self.conn = conn
        self.sqlite = sqlite
        self.mark = "?" if sqlite else "%s"


class _Pool:
    """Read-only connections to one register, kept between requests (a PostgreSQL connection
    costs a server process; an SQLite one is opened ``mode=ro``).  PostgreSQL sessions are set
    ``default_transaction_read_only``: the database itself refuses a write through them."""

    #: connections at most (a request waits for a free one: opening a PostgreSQL connection costs
    #: more than waiting for one)
    SIZE = 8

    def __init__(self, url: str) -> None:
        self.url = url
        self.file = sqlite_path(url)
        self.idle: list[Any] = []
        self.lock = threading.Lock()
        self.free = threading.BoundedSemaphore(self.SIZE)

    def _open(self) -> Any:
        if self.file is not None:
            import sqlite3
            import urllib.parse

            uri = "file:" + urllib.parse.quote(str(self.file)) + "?mode=ro"
            return sqlite3.connect(uri, uri=True, timeout=300, check_same_thread=False,
                                   isolation_level=None)
        import psycopg

        conn = psycopg.connect(libpq_url(self.url), autocommit=True)
        conn.execute("SET default_transaction_read_only = on")
        return conn

    @contextlib.contextmanager
    def reader(self) -> Iterator[Reader]:
        with self.free:
            with self.lock:
                conn = self.idle.pop() if self.idle else None
            if conn is None:
                conn = self._open()
            try:
                yield _PooledReader(conn, self.file is not None)
            except BaseException:
                conn.close()  # perhaps broken: never reused
                raise
            with self.lock:
                self.idle.append(conn)


#: the kept connections of each register being served, by URL
POOLS: dict[str, _Pool] = {}
_POOLS_LOCK = threading.Lock()


def close(url: str) -> None:
    """Close the kept connections to the register at ``url`` (the application's shutdown)."""
    with _POOLS_LOCK:
        pool = POOLS.pop(url, None)
    if pool is not None:
        with pool.lock:
            idle, pool.idle = pool.idle, []
        for conn in idle:
            conn.close()


def reader(url: str):
    """A reader of the register at ``url`` on a kept read-only connection."""
    with _POOLS_LOCK:
        pool = POOLS.get(url)
        if pool is None:
            pool = POOLS[url] = _Pool(url)
    return pool.reader()


#: the columns a list page shows (JSON columns other than ``items`` are not read)
LIST_COLUMNS = ("id", "number", "status", "superseded_by", "standard", "items",
                "device_manufacturer", "device_model", "device_serial", "customer",
                "measurement_date", "issued_at", "simulated")


def list_reports(url: str, filters: Filters, page: int = 1, size: int = PAGE_SIZE) -> Page:
    """The reports matching ``filters``, newest issue first, page ``page`` (from 1) of ``size``:
    each a dict of :data:`LIST_COLUMNS` with ``device`` (manufacturer, model, serial), the dates as
    text (``issued_at``: date and time in UTC)."""
    with reader(url) as r:
        where, params = filters.where(r.sqlite)
        total = r.rows(f"SELECT count(*) FROM reports {where}", params)[0][0]
        pages = max(1, -(-total // size))
        page = min(max(1, page), pages)
        names = ", ".join(f'"{c}"' for c in LIST_COLUMNS)
        found = r.rows(f"SELECT {names} FROM reports {where} ORDER BY id DESC "
                       f"LIMIT {int(size)} OFFSET {int((page - 1) * size)}", params)
        sqlite = r.sqlite
    reports = []
    for row in found:
        x = dict(zip(LIST_COLUMNS, row))
        # as the list shows them: dates as text (SQLite keeps them so), items a list
        x["measurement_date"] = str(x["measurement_date"])
        x["issued_at"] = str(x["issued_at"])
        x["items"] = json.loads(x["items"]) if sqlite else x["items"]
        x["device"] = {"manufacturer": x["device_manufacturer"], "model": x["device_model"],
                       "serial": x["device_serial"]}
        reports.append(x)
    return Page(reports=reports, total=total, page=page, pages=pages)


def version(url: str) -> tuple:
    """What changes whenever the register does (a report issued, amended or withdrawn: each
    writes an audit entry): the newest audit entry, the newest report and the number of reports,
    read in one query on indexed keys."""
    with reader(url) as r:
        return tuple(r.rows("SELECT (SELECT max(id) FROM audit), (SELECT max(id) FROM reports), "
                            "(SELECT count(*) FROM reports)")[0])


#: the standards of each register and when they were read (the filter's choices: a standard
#: new to the register shows within STANDARDS_TTL seconds)
_STANDARDS: dict[str, tuple[float, list[str]]] = {}
STANDARDS_TTL = 10.0


def standards(url: str) -> list[str]:
    """The standards in the register (for the filter's choices), read again every 10 s."""
    import time

    now = time.monotonic()
    cached = _STANDARDS.get(url)
    if cached is not None and now - cached[0] < STANDARDS_TTL:
        return cached[1]
    with reader(url) as r:
        found = [row[0] for row in r.rows("SELECT DISTINCT standard FROM reports ORDER BY "
                                          "standard")]
    _STANDARDS[url] = (now, found)
    return found


def get_report(url: str, number: str) -> dict[str, Any] | None:
    """Report ``number`` with its results and audit trail, None when it is not registered."""
    with reader(url) as r:
        found = r.reports("WHERE number = ?", [number], results=True)
        if not found:
            return None
        audit = [{"at": a.at, "who": a.who, "action": a.action, "detail": a.detail}
                 for a in r.audit(number)]
        return report_dict(found[0], results=True, audit=audit)


def chain(url: str, report: Mapping[str, Any]) -> list[dict[str, Any]]:
    """The amendment chain through ``report``, oldest first: each report's number, status,
    reason (why it replaced the one before, or why it was withdrawn) and measurement date."""
    found = {report["number"]: report}
    with reader(url) as r:
        def fetch(number: str) -> dict[str, Any] | None:
            if number not in found:
                rows = r.reports("WHERE number = ?", [number])
                if not rows:
                    return None
                found[number] = report_dict(rows[0])
            return found[number]

        def walk(link: str) -> list[dict[str, Any]]:
            """The reports reached by following ``link`` from ``report`` (at most 100)."""
            out, cur = [], report
            while cur.get(link) and len(out) < 100:
                cur = fetch(cur[link])
                if cur is None:
                    break
                out.append(cur)
            return out

        entries = [*reversed(walk("supersedes")), report, *walk("superseded_by")]
    return [{"number": e["number"], "status": e["status"], "reason": e["reason"],
             "supersedes": e["supersedes"], "superseded_by": e["superseded_by"],
             "current": e["number"] == report["number"]} for e in entries]


def device_history(url: str, serial: str) -> dict[str, Any]:
    """``metro history SERIAL``'s result: :func:`metro.core.record.registering.history`."""
    from ..record.registering import history

    return history(Register(url), serial)


def history_png(hist: Mapping[str, Any]) -> bytes:
    """The history plot ``metro history --plot`` draws, as PNG bytes."""
    import tempfile

    from ..record.registering import history_plot

    with tempfile.TemporaryDirectory(prefix="metro-web-") as tmp:
        return history_plot(hist, Path(tmp) / "history.png").read_bytes()


def lab_equipment_status(equipment: Iterable[Any], today: dt.date) -> list[dict[str, Any]]:
    """The lab's equipment, soonest due first: id, role, description, certificate, due date,
    days left and a state (``expired``, ``due-soon`` within 30 days, ``ok``, ``no-due``)."""
    out = []
    for e in equipment:
        cal = e.calibration
        due = cal.due if cal is not None else None
        days = (due - today).days if due is not None else None
        if days is None:
            state = "no-due"
        elif days < 0:
            state = "expired"
        elif days <= DUE_DAYS:
            state = "due-soon"
        else:
            state = "ok"
        out.append({"id": e.id, "role": e.role, "manufacturer": e.manufacturer,
                    "model": e.model, "serial": e.serial,
                    "certificate": cal.certificate if cal else "",
                    "U": f"{cal.uncertainty:~P}" if cal else "", "k": cal.k if cal else None,
                    "due": due.isoformat() if due else "", "days": days, "state": state})
    out.sort(key=lambda x: (x["days"] is None, x["days"] if x["days"] is not None else 0))
    return out


class FileProblem(Exception):
    """A registered file cannot be served: ``status`` 404 (none, or missing) or 409 (its SHA-256
    differs from the register's); ``key`` names the message."""

    def __init__(self, status: int, key: str, detail: str = "") -> None:
        super().__init__(detail or key)
        self.status = status
        self.key = key
        self.detail = detail


def _registered(report: Mapping[str, Any], kind: str) -> tuple[Path, str] | None:
    """The stored path and SHA-256 of a report's ``kind`` file (``docx``/``pdf``: the report
    file when it has that suffix; ``dcc``: its DCC)."""
    if kind == "dcc":
        if not report.get("dcc_path"):
            return None
        return Path(report["dcc_path"]), report["dcc_sha256"]
    path = Path(report["report_path"])
    return (path, report["report_sha256"]) if path.suffix.lower() == f".{kind}" else None


def _checked(path: Path, stored: str) -> bytes:
    if not path.is_file():
        raise FileProblem(404, "file_missing", str(path.name))
    data = path.read_bytes()
    if hashlib.sha256(data).hexdigest() != stored:
        raise FileProblem(409, "file_changed", str(path.name))
    return data


def checked_file(report: Mapping[str, Any], kind: str) -> tuple[bytes, str]:
    """The bytes and file name of a report's ``kind`` download, read only from the register's
    stored path and only when its SHA-256 matches the register's (else :class:`FileProblem`).

    The PDF: the registered report file when it is a PDF; else the PDF embedded in the
    registered DCC (which is checked first); else made from the checked Word file with
    LibreOffice (404 when LibreOffice is missing)."""
    if kind not in KINDS:
        raise FileProblem(404, "not_found")
    number = report["number"]
    found = _registered(report, kind)
    if found is not None:
        path, stored = found
        return _checked(path, stored), f"{number}{path.suffix}"
    if kind != "pdf":
        raise FileProblem(404, "no_file")
    dcc = _registered(report, "dcc")
    if dcc is not None:
        from ..documents.dcc import embedded_pdf

        embedded = embedded_pdf(_checked(*dcc))
        if embedded is not None:
            return embedded, f"{number}.pdf"
    docx = _registered(report, "docx")
    if docx is None:
        raise FileProblem(404, "no_file")
    return word_pdf(_checked(*docx), docx[1]), f"{number}.pdf"


#: PDFs made from checked Word files, by the Word file's SHA-256 (a few kept)
_PDF_CACHE: dict[str, bytes] = {}


def word_pdf(docx: bytes, sha256: str) -> bytes:
    """The PDF of a (checked) Word file, through LibreOffice; kept for the next request."""
    import tempfile

    from ..base.errors import MetroError
    from ..documents.pdf import to_pdf

    if sha256 in _PDF_CACHE:
        return _PDF_CACHE[sha256]
    try:
        with tempfile.TemporaryDirectory(prefix="metro-web-") as tmp:
            src, out = Path(tmp) / "report.docx", Path(tmp) / "report.pdf"
            src.write_bytes(docx)
            to_pdf(src, out)
            data = out.read_bytes()
    except MetroError as exc:
        raise FileProblem(404, "no_file", str(exc)) from exc
    if len(_PDF_CACHE) >= 16:
        _PDF_CACHE.pop(next(iter(_PDF_CACHE)))
    _PDF_CACHE[sha256] = data
    return data


def upload_matches(report: Mapping[str, Any], digest: str) -> str | None:
    """Which registered file of ``report`` has the SHA-256 ``digest`` (``docx``/``pdf`` for the
    report file, ``dcc``), None when none has."""
    for kind in KINDS:
        found = _registered(report, kind)
        if found is not None and found[1] == digest:
            return kind
    return None


"""The report register: every issued report, its numbers, status, results and audit trail.

A register is an SQLAlchemy database: an SQLite file for one station, or one PostgreSQL
database shared by several stations (``postgresql+psycopg://user@host:port/db``).  Opening it
runs the Alembic migrations shipped in this package (an empty database gets the whole
schema; a register written by an older metro is brought up to date).

Numbers (:meth:`Register.issue`)
    A number is allocated inside the transaction that inserts the report's row: the scope's
    counter row is locked (SQLite: the transaction starts with ``BEGIN IMMEDIATE``, one writer at
    a time; PostgreSQL: ``SELECT … FOR UPDATE`` on the counter row), incremented, and committed
    with the row — so two processes never share a number, and a failed run rolls the counter
    back (no gaps).

File and row together
    The report is written to a hidden temporary name beside its final path, the row inserted,
    the file linked into place (never replacing a file), then the transaction committed; a
    failure before the commit removes the temporary (or linked) file and rolls back.  So there
    is no row without a file and no visible file without a row.

The audit trail (table ``audit``) is append-only: database triggers refuse UPDATE and DELETE.
"""

from __future__ import annotations

import contextlib
import datetime as dt
import getpass
import hashlib
import math
import os
import secrets
import socket
from pathlib import Path
from typing import Any, Callable, Iterator, Mapping, Sequence

import attrs

from ...base.errors import MetroError

__all__ = ["open_register", "register_state", "Register", "Draft", "Issued", "sha256_file",
           "who_am_i",
           "RegisterError", "SCHEMA_HEAD", "SCHEMA_REVISIONS"]

#: the migrations' revisions, oldest first (``migrations/versions``;
#: tests/core/cli/test_cli_daily.py checks them against Alembic's own list); a register at the
#: newest is opened without loading Alembic
SCHEMA_REVISIONS = ("0001", "0002")
SCHEMA_HEAD = SCHEMA_REVISIONS[-1]


class RegisterError(MetroError):
    """The register cannot do what was asked (unknown number, wrong status, database
    unreachable)."""


def sha256_file(path: str | os.PathLike[str]) -> str:
    h = hashlib.sha256()
    with open(path, "rb") as fh:
        for block in iter(lambda: fh.read(1 << 20), b""):
            h.update(block)
    return h.hexdigest()


def who_am_i() -> str:
    """``user@host`` for the audit trail (``METRO_USER`` overrides the user)."""
    try:
        user = os.environ.get("METRO_USER") or getpass.getuser()
    except Exception:  # pragma: no cover - no user name in the environment
        user = "unknown"
    return f"{user}@{socket.gethostname()}"


def json_safe(obj: Any) -> Any:
    """Strict JSON values: non-finite floats become None (PostgreSQL's JSON has no NaN/∞)."""
    if isinstance(obj, float):
        return obj if math.isfinite(obj) else None
    if isinstance(obj, Mapping):
        return {str(k): json_safe(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [json_safe(v) for v in obj]
    if obj is None or isinstance(obj, (str, int, bool)):
        return obj
    if isinstance(obj, (dt.date, dt.datetime)):
        return obj.isoformat()
    return str(obj)


@attrs.frozen
class Draft:
    """What a report's row holds, and how to write its file, once its number is known.

    ``fields`` are columns of :class:`~metro.core.record.register.models.Report` (standard, items,
    device_*, customer, measurement_date, …); ``results`` are rows of ``results``;
    ``write(tmp)`` writes the report file to the temporary path ``tmp``.
    """

    fields: Mapping[str, Any]
    results: Sequence[Mapping[str, Any]]
    write: Callable[[Path], None]
    #: ``dcc(report)``: the report's DCC (XML bytes), made from the report file just written at
    #: the temporary path ``report``; None when the report is issued without a DCC
    dcc: Callable[[Path], bytes] | None = None


@attrs.frozen
class Issued:
    number: str
    path: Path
    sha256: str
    seq: int
    scope: str
    issued_at: dt.datetime
    dcc_path: Path | None = None
    dcc_sha256: str | None = None


def sqlite_path(url: str) -> Path | None:
    """The file of an SQLite URL (None for PostgreSQL or an in-memory database)."""
    if not url.startswith("sqlite"):
        return None
    path = url.split("///", 1)[1] if "///" in url else ""
    return Path(path) if path and path != ":memory:" else None


def _engine(url: str, create: bool = True):
    from sqlalchemy import create_engine, event

    if url.startswith("postgresql://") or url.startswith("postgres://"):
        url = "postgresql+psycopg://" + url.split("://", 1)[1]
    if url.startswith("sqlite"):
        path = sqlite_path(url)
        if path is not None and create:
            path.parent.mkdir(parents=True, exist_ok=True)
        engine = create_engine(url, connect_args={"timeout": 300})

        @event.listens_for(engine, "connect")
        def _connect(dbapi_connection, record):  # let SQLAlchemy, not sqlite3, open transactions
            dbapi_connection.isolation_level = None

        @event.listens_for(engine, "begin")
        def _begin(conn):  # one writer at a time: the counter is read and written under this lock
            conn.exec_driver_sql("BEGIN" if conn.get_execution_options().get("metro_read")
                                 else "BEGIN IMMEDIATE")

        return engine
    if url.startswith("postgresql+psycopg"):
        from ...base.extras import require

        require("psycopg", f"the register at {url.split('@')[-1]} (PostgreSQL)")
    return create_engine(url, pool_pre_ping=True)


def migrate(engine) -> None:
    """Bring the database to the newest schema with the packaged Alembic migrations."""
    from alembic import command
    from alembic.config import Config

    cfg = Config()
    cfg.set_main_option("script_location", str(Path(__file__).parent / "migrations"))
    with engine.begin() as conn:
        if conn.dialect.name == "postgresql":  # stations opening an empty database at once
            conn.exec_driver_sql("SELECT pg_advisory_xact_lock(7236005110)")
        cfg.attributes["connection"] = conn
        command.upgrade(cfg, "head")


def schema_revision(engine) -> str | None:
    """The register's schema revision (Alembic's ``alembic_version``), None when the database has
    no register tables yet; reads only."""
    from sqlalchemy import inspect, text

    with engine.connect() as conn:
        if not inspect(conn).has_table("alembic_version"):
            return None
        return conn.execute(text("SELECT version_num FROM alembic_version")).scalar()


#: what to do when there is no register yet (read-only commands create none)
NO_REGISTER_HINT = ("a register is made by the first registered run: write a lab profile with "
                    "`metro lab init lab.toml` (its `register` names the database), then `metro "
                    "--lab lab.toml run … --data MANIFEST`; or point --lab / METRO_LAB / "
                    "METRO_REGISTER at an existing register")


def _no_register(url: str, why: str) -> "RegisterError":
    from ..lab import redact_url

    return RegisterError(f"no register at {redact_url(url)} ({why})", hint=NO_REGISTER_HINT)


@contextlib.contextmanager
def _reading(url: str):
    """A :class:`~metro.core.record.register.reading.Reader` of the register at ``url`` (which must
    exist); a database that cannot be read is a :class:`RegisterError` saying why."""
    from ..lab import redact_url
    from .reading import reading

    try:
        with reading(url, sqlite_path(url)) as reader:
            yield reader
    except ImportError as exc:  # no PostgreSQL driver
        from ...base.extras import install_line

        raise RegisterError(f"register {redact_url(url)}: cannot open the database ({exc})",
                            hint="a PostgreSQL register needs the 'postgres' extra: "
                            f"{install_line('postgres')}") from exc
    except Exception as exc:
        if not exc.__class__.__module__.startswith(("sqlite3", "psycopg")):
            raise
        raise RegisterError(f"register {redact_url(url)}: cannot open the database "
                            f"({exc.__class__.__name__}: "
                            f"{str(exc).splitlines()[0] if str(exc) else ''})",
                            hint="check the lab profile's register (or METRO_REGISTER) and that "
                            "the database server is reachable") from exc


def _revision(url: str) -> str | None:
    """The schema revision of an existing database, read with its own driver (no SQLAlchemy)."""
    with _reading(url) as reader:
        return reader.revision()


def _open(url: str, create: bool) -> "Register":
    """A register at the newest schema is opened as it is (no SQLAlchemy until it writes);
    otherwise engine and migrations, the engine disposed again if they fail (no connection left
    open).  Without ``create`` an absent register is an error and nothing is made (no file, no
    folder, no table)."""
    path = sqlite_path(url)
    if path is None or path.is_file():
        revision = _revision(url)
        if revision == SCHEMA_HEAD:
            return Register(url)
        if revision is None and not create:
            raise _no_register(url, "the database has no register tables")
    elif not create:
        raise _no_register(url, "the file does not exist")
    engine = None
    try:
        engine = _engine(url, create)
        revision = schema_revision(engine)
        if revision is None and not create:
            raise _no_register(url, "the database has no register tables")
        # a new register, or one written by an older metro (Alembic only then)
        if revision != SCHEMA_HEAD:
            migrate(engine)
    except BaseException:
        if engine is not None:
            engine.dispose()
        raise
    return Register(url, engine)


def _check_scheme(url: str) -> None:
    from ..lab import redact_url

    scheme = url.split(":", 1)[0]
    if not (scheme.startswith("sqlite") or scheme.startswith("postgres")):
        raise RegisterError(f"register {redact_url(url)}: unsupported database {scheme!r}",
                            hint="an SQLite file (sqlite:////path/register.sqlite) or PostgreSQL "
                            "(postgresql+psycopg://user@host:port/db)")


def register_state(url: str) -> dict[str, Any]:
    """What is at ``url``, read only (``metro doctor``): ``exists``, its schema ``revision``, the
    newest one (``head``), ``migrated`` (at the newest) and the number of ``reports``; an
    unreachable database is a :class:`RegisterError`.  Creates nothing and migrates nothing."""
    from ..lab import redact_url

    _check_scheme(url)
    state: dict[str, Any] = {"url": redact_url(url), "exists": False, "revision": None,
                             "head": SCHEMA_HEAD,
                             "migrated": False, "reports": None}
    path = sqlite_path(url)
    if path is not None and not path.is_file():
        return state
    with _reading(url) as reader:
        revision = reader.revision()
        state.update(exists=revision is not None, revision=revision, migrated=revision
                     == SCHEMA_HEAD)
        if revision is not None:
            state["reports"] = reader.rows("SELECT count(*) FROM reports")[0][0]
    return state


def open_register(url: str, *, create: bool = True) -> "Register":
    """Open the register at the SQLAlchemy ``url``, migrating it to the newest schema when it is
    older; with ``create`` (a registered run) an absent register is made, without it (every
    command that only reads, amends or withdraws) it is a :class:`RegisterError` and nothing is
    made.  A database metro cannot use is a :class:`RegisterError` saying why."""
    from ..lab import redact_url

    _check_scheme(url)
    try:
        return _open(url, create)
    except (OSError, ImportError) as exc:
        raise RegisterError(f"register {redact_url(url)}: cannot open the database ({exc})",
                            hint="check the lab profile's register (or METRO_REGISTER): its folder "
                            "must be writable") from exc
    except Exception as exc:
        if not exc.__class__.__module__.startswith("sqlalchemy"):
            raise _alembic_error(url, exc) from exc
        raise RegisterError(f"register {redact_url(url)}: cannot open the database "
                            f"({exc.__class__.__name__}: {str(exc).splitlines()[0]})",
                            hint="check the lab profile's register (or METRO_REGISTER) and that "
                            "the database server is reachable") from exc


def _alembic_error(url: str, exc: Exception) -> Exception:
    """Alembic's error about a register written by a newer metro, said as such; any other as it
    is."""
    from ..lab import redact_url

    if exc.__class__.__module__.startswith("alembic"):
        err = RegisterError(f"register {redact_url(url)}: {exc}",
                            hint="the register was written by a newer metro; upgrade metro")
        err.__cause__ = exc
        return err
    return exc


class Register:
    """An open register.  Reading goes through the database's own driver
    (:mod:`metro.core.record.register.reading`, no SQLAlchemy); the SQLAlchemy engine that writes is
    made on first use."""

    def __init__(self, url: str, engine=None) -> None:
        self.url = url
        self._engine = engine

    @property
    def engine(self):
        if self._engine is None:
            self._engine = _engine(self.url, create=False)  # the register exists: opened before
        return self._engine

    def close(self) -> None:
        if self._engine is not None:
            self._engine.dispose()

    @contextlib.contextmanager
    def _reader(self):
        with _reading(self.url) as reader:
            yield reader

    def __enter__(self) -> "Register":
        return self

    def __exit__(self, *exc) -> None:
        self.close()

    # -- sessions ------------------------------------------------------------------------
    @contextlib.contextmanager
    def _session(self, *, read: bool = False) -> Iterator[Any]:
        """A transaction; ``read`` ones do not take SQLite's write lock (lists wait for no
        writer)."""
        from sqlalchemy.orm import Session

        bind = self.engine.execution_options(metro_read=True) if read else self.engine
        with Session(bind, expire_on_commit=False) as s:
            with s.begin():
                yield s

    def _allocate(self, s, scope: str) -> int:
        from sqlalchemy import select, update

        from .models import Counter

        if s.bind.dialect.name == "postgresql":
            from sqlalchemy.dialects.postgresql import insert
        else:
            from sqlalchemy.dialects.sqlite import insert
        s.execute(insert(Counter).values(scope=scope,
                                         last=0).on_conflict_do_nothing(index_elements=["scope"]))
        last = s.execute(select(Counter.last).where(Counter.scope
                                                    == scope).with_for_update()).scalar_one()
        s.execute(update(Counter).where(Counter.scope == scope).values(last=last + 1))
        return last + 1

    def _report(self, s, number: str, *, lock: bool = False):
        from sqlalchemy import select

        from .models import Report

        q = select(Report).where(Report.number == number)
        if lock:
            q = q.with_for_update()
        rep = s.execute(q).scalar_one_or_none()
        if rep is None:
            raise RegisterError(f"report {number} is not in the register {self.display_url}",
                                hint="`metro register list` shows the numbers in the register")
        return rep

    @property
    def display_url(self) -> str:
        from ..lab import redact_url

        return redact_url(self.url)

    def _audit(self, s, action: str, number: str, detail: str, who: str, at: dt.datetime) -> None:
        from .models import AuditEntry

        s.add(AuditEntry(at=at, who=who, action=action, number=number, detail=detail))

    # -- issuing -------------------------------------------------------------------------
    def issue(
        self,
        make: Callable[[str, dt.datetime], Draft],
        *,
        folder: str | os.PathLike[str],
        scheme: Callable[[int, int], str],
        per_year: bool,
        timezone: str = "UTC",
        supersedes: str | None = None,
        reason: str = "",
        who: str | None = None,
        suffix: str = ".docx",
        kind: str = "",
        _before_commit: Callable[[Path], None] | None = None,
    ) -> Issued:
        """Allocate the next number, write the report and insert its row, all or nothing.

        ``make(number, issued_at)`` returns the :class:`Draft`; ``scheme(seq, year)`` formats the
        number; the file goes to ``folder/<number><suffix>`` (and a draft's DCC to
        ``folder/<number>.xml``).  With ``supersedes`` the new report replaces that (issued)
        report, which becomes ``superseded`` in the same transaction.  A record of another
        ``kind`` than a calibration report (``"validation"``: ``metro validate``) is numbered in
        a counter of its own (scope ``<kind>:<year>`` or ``<kind>:all``), so the reports' numbers
        keep no gaps.
        """
        import zoneinfo

        from .models import Report, ResultRow

        who = who or who_am_i()
        folder = Path(folder)
        folder.mkdir(parents=True, exist_ok=True)
        files = _Staged(folder)
        try:
            with self._session() as s:
                issued_at = dt.datetime.now(dt.timezone.utc).replace(microsecond=0)
                year = issued_at.astimezone(zoneinfo.ZoneInfo(timezone)).year
                scope = str(year) if per_year else "all"
                scope = f"{kind}:{scope}" if kind else scope
                old = self._replaced(s, supersedes)
                seq = self._allocate(s, scope)
                number = scheme(seq, year)
                final = files.claim(f"{number}{suffix}")
                draft = make(number, issued_at)
                digest = files.stage(final, draft.write)
                dcc: dict[str, Any] = {}
                if draft.dcc is not None:  # the DCC, made from the report just written
                    report_tmp = files.tmp[final]
                    xml = files.claim(f"{number}.xml")
                    dcc = {"dcc_path": str(xml.resolve()), "dcc_sha256": files.stage(
                        xml, lambda tmp: tmp.write_bytes(draft.dcc(report_tmp)))}
                rep = Report(number=number, scope=scope, seq=seq, status="issued",
                             supersedes=supersedes,
                             reason=reason, issued_at=issued_at, issued_by=who,
                             report_path=str(final.resolve()),
                             report_sha256=digest, **dcc, **json_safe_fields(draft.fields))
                rep.results = [ResultRow(**json_safe_fields(r)) for r in draft.results]
                s.add(rep)
                if old is not None:
                    old.status = "superseded"
                    old.superseded_by = number
                    self._audit(s, "superseded", supersedes, f"superseded by {number}: {reason}",
                                who, issued_at)
                    self._audit(s, "amend", number, f"replaces {supersedes}: {reason}", who,
                                issued_at)
                else:
                    self._audit(s, "issue", number,
                                f"{rep.standard} {', '.join(rep.items)}; file {final} "
                                f"sha256 {digest}", who, issued_at)
                if dcc:
                    self._audit(s, "dcc", number, f"DCC {dcc['dcc_path']} sha256 "
                                f"{dcc['dcc_sha256']}", who, issued_at)
                s.flush()  # a constraint failure happens here, before the file is visible
                files.link()  # into place, never replacing a file
                if _before_commit is not None:
                    _before_commit(final)
            # committed
        except BaseException:
            files.discard()
            raise
        _fsync_dir(folder)
        return Issued(number=number, path=final, sha256=digest, seq=seq, scope=scope,
                      issued_at=issued_at, dcc_path=Path(dcc["dcc_path"]) if dcc else None,
                      dcc_sha256=dcc.get("dcc_sha256"))

    def _replaced(self, s, supersedes: str | None):
        """The row of the report an amendment replaces (locked; it must be issued), or None."""
        if supersedes is None:
            return None
        old = self._report(s, supersedes, lock=True)
        if old.status != "issued":
            raise RegisterError(f"report {supersedes} is {old.status}"
                                + (f" by {old.superseded_by}" if old.superseded_by else "")
                                + "; only an issued report can be amended",
                                hint=f"amend {old.superseded_by}" if old.superseded_by else None)
        return old

    # -- status changes ------------------------------------------------------------------
    def withdraw(self, number: str, reason: str, *, who: str | None = None) -> None:
        if not reason.strip():
            raise RegisterError("a withdrawal needs a reason (--reason TEXT)")
        who = who or who_am_i()
        with self._session() as s:
            rep = self._report(s, number, lock=True)
            if rep.status != "issued":
                raise RegisterError(f"report {number} is {rep.status}; only an issued report can "
                                    "be withdrawn")
            rep.status = "withdrawn"
            rep.reason = reason
            self._audit(s, "withdraw", number, reason, who,
                        dt.datetime.now(dt.timezone.utc).replace(microsecond=0))

    # -- reading (the database's own driver: metro.core.record.register.reading) ------------------
    def _unknown(self, number: str) -> RegisterError:
        return RegisterError(f"report {number} is not in the register {self.display_url}",
                             hint="`metro register list` shows the numbers in the register")

    def get(self, number: str) -> dict[str, Any]:
        with self._reader() as r:
            found = r.reports("WHERE number = ?", [number], results=True)
            if not found:
                raise self._unknown(number)
            return report_dict(found[0], results=True, audit=_audit_dicts(r.audit(number)))

    def context(self, number: str) -> tuple[dict[str, Any], str]:
        """The stored render context and template name of a report (for re-rendering)."""
        with self._reader() as r:
            found = r.records(("context", "template"),
                              "SELECT context, template FROM reports WHERE number = ?",
                              [number])
        if not found:
            raise self._unknown(number)
        return found[0].context, found[0].template

    def audit(self, number: str | None = None) -> list[dict[str, Any]]:
        with self._reader() as r:
            return _audit_dicts(r.audit(number))

    def list(self, *, device: str | None = None, standard: str | None = None,
             since: dt.date | None = None, results: bool = False) -> list[dict[str, Any]]:
        conditions, params = [], []
        for cond, value in (("device_serial = ?", device), ("standard = ?", standard),
                            ("measurement_date >= ?", since)):
            if value:
                conditions.append(cond)
                params.append(value)
        with self._reader() as r:
            if since and r.sqlite:  # SQLite keeps dates as ISO text, which sorts as the dates do
                params[-1] = since.isoformat()
            where = ("WHERE " + " AND ".join(conditions)) if conditions else ""
            return [report_dict(x, results=results) for x
                    in r.reports(where, params, results=results)]

    def verify(self) -> list[dict[str, Any]]:
        """Every report file, and every DCC issued with a report, against its stored SHA-256:
        ``ok``, ``modified`` or ``missing`` (``file``: ``report`` or ``dcc``)."""
        out = []
        for r in self.list():
            files = [("report", r["report_path"], r["report_sha256"])]
            if r.get("dcc_path"):
                files.append(("dcc", r["dcc_path"], r["dcc_sha256"]))
            for kind, path, stored in files:
                p = Path(path)
                if not p.is_file():
                    state, found = "missing", None
                else:
                    found = sha256_file(p)
                    state = "ok" if found == stored else "modified"
                out.append({"number": r["number"], "status": r["status"], "file": kind,
                            "path": str(p), "check": state, "sha256_stored": stored,
                            "sha256_found": found})
        return out


class _Staged:
    """The files of one issue, written to hidden temporary names in ``folder`` (each fsynced and
    hashed), then linked into place together, never replacing a file; :meth:`discard` removes
    whatever a failure left (temporary or linked)."""

    def __init__(self, folder: Path) -> None:
        self.folder = folder
        self.tmp: dict[Path, Path] = {}
        self.linked: list[Path] = []

    def claim(self, name: str) -> Path:
        """``folder/name``, which must not exist (a register never replaces a report file)."""
        final = self.folder / name
        if final.exists() or final.is_symlink():
            raise RegisterError(f"{final} exists already; a register never replaces a report file",
                                hint="move the file away or write reports to another --out "
                                "folder")
        return final

    def stage(self, final: Path, write: Callable[[Path], None]) -> str:
        """Write ``final``'s content with ``write(tmp)`` to a temporary name; its SHA-256."""
        tmp = self.folder / f".{final.name}.tmp-{secrets.token_hex(4)}"
        tmp.touch(exist_ok=False)
        self.tmp[final] = tmp
        write(tmp)
        with open(tmp, "rb") as fh:
            os.fsync(fh.fileno())
        return sha256_file(tmp)

    def link(self) -> None:
        for final, tmp in list(self.tmp.items()):
            os.link(tmp, final)
            self.linked.append(final)
            tmp.unlink()
            del self.tmp[final]

    def discard(self) -> None:
        for path in [*self.tmp.values(), *self.linked]:
            with contextlib.suppress(OSError):
                path.unlink()


def _audit_dicts(entries) -> list[dict[str, Any]]:
    return [{"at": _utc(a.at).isoformat(), "who": a.who, "action": a.action, "number": a.number,
             "detail": a.detail} for a in entries]


def _fsync_dir(directory: Path) -> None:
    try:
        fd = os.open(directory, os.O_RDONLY)
    except OSError:  # pragma: no cover - Windows
        return
    with contextlib.suppress(OSError):
        os.fsync(fd)
    os.close(fd)


def json_safe_fields(d: Mapping[str, Any]) -> dict[str, Any]:
    """Column values: JSON-shaped ones made strict JSON, dates and numbers kept as they are."""
    out = {}
    for k, v in d.items():
        if isinstance(v, (Mapping, list, tuple)):
            out[k] = json_safe(v)
        elif isinstance(v, float) and not math.isfinite(v):
            out[k] = None
        else:
            out[k] = v
    return out


def _utc(t: dt.datetime) -> dt.datetime:
    """SQLite hands datetimes back naive: they were stored in UTC."""
    return t.replace(tzinfo=dt.timezone.utc) if t.tzinfo is None else t.astimezone(dt.timezone.utc)


def report_dict(r, *, results: bool = False, audit: list | None = None) -> dict[str, Any]:
    d = {
        "number": r.number, "seq": r.seq, "scope": r.scope, "status": r.status,
        "supersedes": r.supersedes,
        "superseded_by": r.superseded_by, "reason": r.reason, "standard": r.standard,
        "items": list(r.items),
        "options": r.options,
        "device": {"id": r.device_id, "manufacturer": r.device_manufacturer,
                   "model": r.device_model,
                   "serial": r.device_serial},
        "customer": r.customer, "measurement_date": r.measurement_date.isoformat(),
        "issued_at": _utc(r.issued_at).isoformat(), "issued_by": r.issued_by,
        "simulated": r.simulated,
        "allow_expired": r.allow_expired, "lab": r.lab, "report_path": r.report_path,
        "report_sha256": r.report_sha256, "manifest_sha256": r.manifest_sha256,
        "dcc_path": getattr(r, "dcc_path", None), "dcc_sha256": getattr(r, "dcc_sha256", None),
        "template": r.template,
    }
    if results:
        d["results"] = [{"item": x.item, "key": x.key, "quantity": x.quantity, "symbol": x.symbol,
                         "value": x.value, "u": x.u, "U": x.U, "k": x.k, "nu_eff": x.nu_eff,
                         "unit": x.unit,
                         "reported": {"value": x.value_text, "U": x.U_text},
                         "reportable": x.reportable,
                         "reason": x.reason} for x in r.results]
        d["verdicts"] = r.verdicts
        d["budgets"] = r.budgets
        d["equipment"] = r.equipment
        d["provenance"] = r.provenance
    if audit is not None:
        d["audit"] = audit
    return d

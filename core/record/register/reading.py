"""Reading the register through the database's own driver (``sqlite3``, ``psycopg``), without
SQLAlchemy.

The commands that only read — ``register list/show/verify``, ``report N``, ``history`` — spend most
of their time importing SQLAlchemy's ORM (about 0.5 s of CPU), not querying. They read the same
tables with plain ``SELECT`` statements here and get rows with the attributes of the ORM models
(:mod:`metro.core.record.register.models`), so :func:`metro.core.record.register.report_dict` serves
both. Writing (issuing, amending, withdrawing) and migrations stay with SQLAlchemy and Alembic.

Column values come back as the ORM gives them: JSON columns parsed (SQLite keeps them as text,
PostgreSQL's driver parses them), dates and datetimes as :mod:`datetime` values (SQLite keeps
SQLAlchemy's ISO text), booleans as ``bool`` (SQLite keeps 0/1).
"""

from __future__ import annotations

import contextlib
import datetime as dt
import json
from pathlib import Path
from types import SimpleNamespace
from typing import Any, Iterator, Sequence

#: the ``reports`` columns a listing reads (``context``, the largest, only when asked for)
REPORT_COLUMNS = ("id", "number", "scope", "seq", "status", "supersedes", "superseded_by", "reason",
                  "standard",
                  "items", "options", "device_id", "device_manufacturer", "device_model",
                  "device_serial",
                  "customer", "measurement_date", "issued_at", "issued_by", "simulated",
                  "allow_expired", "lab",
                  "verdicts", "budgets", "provenance", "manifest_sha256", "equipment",
                  "report_path",
                  "report_sha256", "template", "dcc_path", "dcc_sha256")
#: the ``results`` columns, as (column, attribute): the expanded uncertainty's column is
#: ``U_expanded``
RESULT_COLUMNS = (("report_id", "report_id"), ("item", "item"), ("key", "key"),
                  ("quantity", "quantity"),
                  ("symbol", "symbol"), ("value", "value"), ("u", "u"), ("U_expanded", "U"),
                  ("k", "k"),
                  ("nu_eff", "nu_eff"), ("unit", "unit"), ("value_text", "value_text"),
                  ("U_text", "U_text"),
                  ("reportable", "reportable"), ("reason", "reason"))
JSON_COLUMNS = frozenset({"items", "options", "lab", "verdicts", "budgets", "provenance",
                          "equipment", "context"})
BOOL_COLUMNS = frozenset({"simulated", "allow_expired", "reportable"})
DATE_COLUMNS = frozenset({"measurement_date"})
DATETIME_COLUMNS = frozenset({"issued_at", "at"})


class Reader:
    """A read-only connection to the register at ``url`` (an SQLite file that must exist, or a
    PostgreSQL database); ``sqlite`` tells how column values come back."""

    def __init__(self, url: str, sqlite_file: Path | None) -> None:
        self.sqlite = sqlite_file is not None
        if self.sqlite:
            import sqlite3
            import urllib.parse

            # mode=rw: an existing file only (sqlite3 would otherwise create it)
            uri = "file:" + urllib.parse.quote(str(sqlite_file)) + "?mode=rw"
            self.conn = sqlite3.connect(uri, uri=True, timeout=300)
            self.mark = "?"
        else:
            import psycopg

            self.conn = psycopg.connect(libpq_url(url))
            self.mark = "%s"

    def close(self) -> None:
        self.conn.close()

    def rows(self, sql: str, params: Sequence[Any] = ()) -> list[tuple]:
        cur = self.conn.cursor()
        try:
            cur.execute(sql.replace("?", self.mark), tuple(params))
            return list(cur.fetchall())
        finally:
            cur.close()

    def value(self, column: str, v: Any) -> Any:
        """A column's value as the ORM gives it."""
        if v is None:
            return None
        if column in JSON_COLUMNS:
            return json.loads(v) if self.sqlite else v
        if column in BOOL_COLUMNS:
            return bool(v)
        if column in DATE_COLUMNS and isinstance(v, str):
            return dt.date.fromisoformat(v)
        if column in DATETIME_COLUMNS and isinstance(v, str):
            return dt.datetime.fromisoformat(v)
        return v

    def records(self, columns: Sequence[str], sql: str, params: Sequence[Any] = (),
                names: Sequence[str] | None = None) -> list[SimpleNamespace]:
        """Rows of ``sql`` (selecting ``columns``) as objects with the attributes ``names``."""
        names = names or columns
        return [SimpleNamespace(**{n: self.value(c, v) for c, n, v in zip(columns, names, row)})
                for row in self.rows(sql, params)]

    def revision(self) -> str | None:
        """The schema revision (Alembic's ``alembic_version``); None when there are no register
        tables."""
        if self.sqlite:
            there = (
                self.rows("SELECT count(*) FROM sqlite_master WHERE type = 'table' AND name = "
                          "'alembic_version'")
            )
        else:
            there = self.rows("SELECT count(*) FROM information_schema.tables WHERE table_name = "
                              "'alembic_version' AND table_schema = current_schema()")
        if not there[0][0]:
            return None
        found = self.rows("SELECT version_num FROM alembic_version")
        return found[0][0] if found else None

    # -- the queries of metro.core.record.register.Register's reading methods ---------------------
    def reports(self, where: str = "", params: Sequence[Any] = (), *, results: bool = False,
                context: bool = False) -> list[SimpleNamespace]:
        cols = REPORT_COLUMNS + (("context",) if context else ())
        reps = self.records(cols,
                            f"SELECT {_names(cols)} FROM reports {where} ORDER BY issued_at, id",
                            params)
        for r in reps:
            r.results = []
        if results and reps:
            by_id = {r.id: r for r in reps}
            marks = ", ".join("?" for _ in by_id)
            cols, names = zip(*RESULT_COLUMNS)
            for x in self.records(cols,
                                  f"SELECT {_names(cols)} FROM results WHERE report_id IN "
                                  f"({marks}) ORDER BY id", list(by_id), names):
                by_id[x.report_id].results.append(x)
        return reps

    def audit(self, number: str | None) -> list[SimpleNamespace]:
        cols = ("at", "who", "action", "number", "detail")
        where, params = ("WHERE number = ?", [number]) if number is not None else ("", [])
        return self.records(cols, f"SELECT {_names(cols)} FROM audit {where} ORDER BY id", params)


def _names(columns: Sequence[str]) -> str:
    """A select list; quoted, as SQLAlchemy created them (PostgreSQL folds ``U_expanded``
    otherwise)."""
    return ", ".join(f'"{c}"' for c in columns)


def libpq_url(url: str) -> str:
    """An SQLAlchemy PostgreSQL URL as libpq reads it (``postgresql+psycopg://`` → ``postgresql://``)."""
    scheme, rest = url.split("://", 1)
    return "postgresql://" + rest if scheme.startswith("postgres") else url


@contextlib.contextmanager
def reading(url: str, sqlite_file: Path | None) -> Iterator[Reader]:
    reader = Reader(url, sqlite_file)
    try:
        yield reader
    finally:
        reader.close()

"""The register's read path (metro.core.record.register.reading: plain SELECTs through sqlite3 /
psycopg) against the SQLAlchemy models that write it: the same columns, and the same values for
every column of every row, on SQLite and on a real PostgreSQL server. A column added to a model and
forgotten in the reader, or a type the reader converts differently (JSON, dates, booleans, the
``U_expanded`` column), fails here."""

from __future__ import annotations

import datetime as dt
import sqlite3
from pathlib import Path

import pytest

from metro.core.record.register import Draft, open_register, sqlite_path
from metro.core.record.register.models import AuditEntry, Report, ResultRow
from metro.core.record.register.reading import REPORT_COLUMNS, RESULT_COLUMNS, reading


def test_reader_columns_are_the_models_columns():
    assert set(REPORT_COLUMNS) | {"context"} == {c.name for c in Report.__table__.columns}
    attrs = {c.key for c in ResultRow.__mapper__.column_attrs} - {"id"}
    assert {a for _, a in RESULT_COLUMNS} == attrs
    assert {c for c, _ in RESULT_COLUMNS} == {c.name for c in ResultRow.__table__.columns} - {"id"}


def _draft(serial: str, value: float | None, reportable: bool):
    fields = {"standard": "gbt45570", "items": ["D.5.2", "D.5.6"],
              "options": {"t": "10 s", "nested": [1, 2.5]},
              "device_id": "dev-1", "device_manufacturer": "ACME 光电", "device_model": "FOG-9",
              "device_serial": serial, "customer": "客户 <x>",
              "measurement_date": dt.date(2026, 11, 23),
              "simulated": True, "allow_expired": False,
              "lab": {"name": "EML", "langs": ["zh", "en"]},
              "verdicts": {"overall": "conforms"}, "budgets": [{"rows": [["u1", 0.1]]}],
              "provenance": {"metro": "0.1.0"}, "manifest_sha256": "ab" * 32,
              "equipment": [{"id": "T1", "due": "2027-01-01"}], "template": "gbt45570",
              "context": {"k": "v"}}
    results = [{"item": "D.5.2", "key": "Bs_100", "quantity": "bias stability", "symbol": "B_s",
                "value": value,
                "u": None if value is None else 1e-4, "U": None if value is None else 2.3e-4,
                "k": 2.3,
                "nu_eff": float("inf"), "unit": "°/h", "value_text": "" if value is None
                else f"{value}",
                "U_text": None if value is None else "0.00023", "reportable": reportable,
                "reason": "" if reportable else "not reportable: too few records"}]

    def write(tmp: Path) -> None:
        tmp.write_text(f"report of {serial}", encoding="utf-8")

    return lambda number, at: Draft(fields, results, write)


def _fill(url: str, folder: Path) -> list[str]:
    with open_register(url) as reg:
        scheme = lambda seq, year: f"R{year}-{seq:04d}"  # noqa: E731
        a = reg.issue(_draft("S1", 0.0031, True), folder=folder, scheme=scheme, per_year=True)
        b = reg.issue(_draft("S2", None, False), folder=folder, scheme=scheme, per_year=True)
        c = reg.issue(_draft("S1", 0.0029, True), folder=folder, scheme=scheme, per_year=True,
                      supersedes=a.number, reason="typo in the customer's name")
        reg.withdraw(b.number, "device returned")
        return [a.number, b.number, c.number]


def _orm_rows(url: str):
    import sqlalchemy as sa
    from sqlalchemy.orm import Session

    engine = sa.create_engine(url)
    try:
        with Session(engine) as s:
            reports = {r.number: ({c.name: getattr(r, c.key) for c in Report.__table__.columns},
                                  [{a: getattr(x, a) for _, a in RESULT_COLUMNS}
                                   for x
                                   in s.scalars(sa.select(ResultRow).where(
                                       ResultRow.report_id == r.id)
                                                      .order_by(ResultRow.id))])
                       for r in s.scalars(sa.select(Report))}
            audit = [(a.at, a.who, a.action, a.number, a.detail)
                     for a in s.scalars(sa.select(AuditEntry).order_by(AuditEntry.id))]
    finally:
        engine.dispose()
    return reports, audit


def _utc(t: dt.datetime) -> dt.datetime:
    return t if t.tzinfo else t.replace(tzinfo=dt.timezone.utc)


def test_reader_gives_what_the_models_give(register_url, tmp_path):
    numbers = _fill(register_url, tmp_path / "out")
    orm_reports, orm_audit = _orm_rows(register_url)
    with reading(register_url, sqlite_path(register_url)) as r:
        got = {x.number: x for x in r.reports(results=True, context=True)}
        audit = [(a.at, a.who, a.action, a.number, a.detail) for a in r.audit(None)]
    assert sorted(got) == sorted(numbers) == sorted(orm_reports)
    for number, (cols, results) in orm_reports.items():
        rep = got[number]
        for name, want in cols.items():
            have = getattr(rep, name)
            if isinstance(want, dt.datetime):
                want, have = _utc(want), _utc(have)
            assert have == want and type(have) is type(want), (number, name, have, want)
        assert [{a: getattr(x, a) for _, a in RESULT_COLUMNS} for x in rep.results] == results
    assert [(_utc(a[0]),) + a[1:] for a in audit] == [(_utc(a[0]),) + a[1:] for a in orm_audit]
    # the states the reader must carry through: superseded, withdrawn, a result withheld
    assert {got[n].status for n in numbers} == {"superseded", "withdrawn", "issued"}
    assert got[numbers[1]].results[0].reportable is False and got[numbers[1]].results[
        0].value is None


def test_reader_never_creates_a_database(tmp_path):
    url = "sqlite:///" + str(tmp_path / "absent.sqlite")
    with pytest.raises(sqlite3.OperationalError, match="unable to open database file"):
        with reading(url, sqlite_path(url)):
            pass
    assert list(tmp_path.iterdir()) == []

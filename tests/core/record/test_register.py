"""The report register on SQLite and on a real PostgreSQL server: numbers, atomic file+row,
migrations, amendments, withdrawal, verify, the append-only audit trail."""

from __future__ import annotations

import datetime as dt
import subprocess
import sys
from pathlib import Path

import pytest
import sqlalchemy.exc

from metro.core.record.register import Draft, RegisterError, open_register
from metro.core.record.register.models import Base


@pytest.fixture
def opened():
    """open_register, with every register closed when the test ends (no connection left open)."""
    regs = []

    def op(url):
        regs.append(open_register(url))
        return regs[-1]

    yield op
    for r in regs:
        r.close()


def _scheme(seq, year):
    return f"T{year}-{seq:04d}"


def _draft(text="report", serial="S1", fail=False, value=1.0, date=dt.date(2026, 11, 23)):
    def write(tmp: Path) -> None:
        if fail:
            raise RuntimeError("renderer failed")
        tmp.write_text(text, encoding="utf-8")

    fields = {"standard": "std", "items": ["A.1"], "options": {}, "device_id": "d",
              "device_manufacturer": "m",
              "device_model": "M1", "device_serial": serial, "customer": "c",
              "measurement_date": date,
              "simulated": False, "allow_expired": False, "lab": {}, "verdicts": None,
              "budgets": [],
              "provenance": {}, "manifest_sha256": None, "equipment": [], "template": "",
              "context": {}}
    results = [{"item": "A.1", "key": "k", "quantity": "q", "symbol": "x", "value": value, "u": 0.1,
                "U": 0.2,
                "k": 2.0, "nu_eff": float("inf"), "unit": "°/h", "value_text": f"{value}",
                "U_text": "0.2",
                "reportable": True, "reason": ""}]
    return lambda number, at: Draft(fields, results, write)


def _issue(reg, folder, **kw):
    make = kw.pop("make", None) or _draft()
    return reg.issue(make, folder=folder, scheme=_scheme, per_year=True, **kw)


def test_migrations_from_an_empty_database(opened, register_url):
    import sqlalchemy as sa

    reg = opened(register_url)
    insp = sa.inspect(reg.engine)
    tables = set(insp.get_table_names())
    assert set(Base.metadata.tables) <= tables and "alembic_version" in tables
    with reg.engine.connect() as c:  # 0002: the DCC columns
        assert c.exec_driver_sql("SELECT version_num FROM alembic_version").scalar_one() == "0002"
    # the models and the migrated tables agree column by column
    for name, table in Base.metadata.tables.items():
        assert {c.name for c in table.columns} == {c["name"] for c in insp.get_columns(name)}, name
    reg.close()
    open_register(register_url).close()  # opening again migrates nothing and fails nothing


def test_sequential_numbers_and_no_gap_after_failure(opened, register_url, tmp_path):
    reg = opened(register_url)
    year = dt.datetime.now(dt.timezone.utc).year
    a = _issue(reg, tmp_path / "out")
    with pytest.raises(RuntimeError, match="renderer failed"):
        _issue(reg, tmp_path / "out", make=_draft(fail=True))
    b = _issue(reg, tmp_path / "out")
    assert (a.number, b.number) == (f"T{year}-0001", f"T{year}-0002")
    assert sorted(p.name for p in (tmp_path / "out").iterdir()) == [f"T{year}-0001.docx",
                                                                    f"T{year}-0002.docx"]
    rows = reg.list()
    assert [r["number"] for r in rows] == [a.number, b.number]
    got = reg.get(a.number)
    assert got["results"][0]["nu_eff"] is None and got["results"][0]["U"] == 0.2
    assert got["audit"][0]["action"] == "issue"


def test_failure_between_file_and_row_leaves_neither(opened, register_url, tmp_path):
    """The file is linked into place, then the commit fails: the file is removed, no row stays."""
    reg = opened(register_url)
    out = tmp_path / "out"
    seen = []

    def boom(final: Path) -> None:
        seen.append(final.is_file())
        raise OSError("disk full at commit")

    with pytest.raises(OSError, match="disk full"):
        _issue(reg, out, _before_commit=boom)
    assert seen == [True]
    assert list(out.iterdir()) == [] and reg.list() == [] and reg.audit() == []
    # a row that cannot be inserted (constraint) leaves no file either
    with pytest.raises(sqlalchemy.exc.IntegrityError):
        _issue(reg, out, make=_draft(date=None))
    assert list(out.iterdir()) == [] and reg.list() == []
    assert _issue(reg, out).seq == 1  # and the counter was rolled back each time


def test_existing_file_is_never_replaced(opened, register_url, tmp_path):
    reg = opened(register_url)
    out = tmp_path / "out"
    out.mkdir()
    year = dt.datetime.now(dt.timezone.utc).year
    (out / f"T{year}-0001.docx").write_text("someone else's", encoding="utf-8")
    with pytest.raises(RegisterError, match="never replaces"):
        _issue(reg, out)
    assert (out / f"T{year}-0001.docx").read_text(encoding="utf-8") == "someone else's"
    assert reg.list() == []


def test_amendment_chain_and_withdrawal(opened, register_url, tmp_path):
    reg = opened(register_url)
    out = tmp_path / "out"
    a = _issue(reg, out)
    b = _issue(reg, out, supersedes=a.number, reason="wrong serial number")
    c = _issue(reg, out, supersedes=b.number, reason="customer name corrected")
    ra, rb, rc = (reg.get(x.number) for x in (a, b, c))
    assert (ra["status"], ra["superseded_by"]) == ("superseded", b.number)
    assert (rb["status"], rb["supersedes"], rb["superseded_by"]) == ("superseded", a.number,
                                                                     c.number)
    assert (rc["status"], rc["supersedes"], rc["reason"]) == ("issued", b.number,
                                                              "customer name corrected")
    with pytest.raises(RegisterError, match="superseded"):
        _issue(reg, out, supersedes=a.number, reason="again")
    assert len(reg.list()) == 3  # the refused amendment took no number
    reg.withdraw(c.number, "device returned before calibration was complete")
    assert reg.get(c.number)["status"] == "withdrawn"
    with pytest.raises(RegisterError, match="withdrawn"):
        reg.withdraw(c.number, "twice")
    with pytest.raises(RegisterError, match="not in the register"):
        reg.get("T1999-0001")
    actions = [(e["action"], e["number"]) for e in reg.audit()]
    assert actions == [("issue", a.number), ("superseded", a.number), ("amend", b.number),
                       ("superseded", b.number), ("amend", c.number), ("withdraw", c.number)]
    assert all(Path(x.path).is_file() for x in (a, b, c))  # superseded reports are kept


def test_audit_trail_is_append_only(opened, register_url, tmp_path):
    import sqlalchemy as sa

    reg = opened(register_url)
    _issue(reg, tmp_path / "out")
    for stmt in ("UPDATE audit SET who = 'mallory'", "DELETE FROM audit"):
        with pytest.raises(sa.exc.DBAPIError, match="append-only"):
            with reg.engine.begin() as c:
                c.exec_driver_sql(stmt)
    assert len(reg.audit()) == 1 and reg.audit()[0]["who"] != "mallory"


def test_verify_catches_a_modified_and_a_missing_file(opened, register_url, tmp_path):
    reg = opened(register_url)
    a, b, c = (_issue(reg, tmp_path / "out", make=_draft(text=f"report {i}")) for i in range(3))
    assert {v["check"] for v in reg.verify()} == {"ok"}
    with open(b.path, "a", encoding="utf-8") as fh:
        fh.write(" tampered")
    c.path.unlink()
    checks = {v["number"]: v["check"] for v in reg.verify()}
    assert checks == {a.number: "ok", b.number: "modified", c.number: "missing"}


_WORKER = r"""
import sys, time
from pathlib import Path
sys.path.insert(0, {tests!r})
import test_register as t
from metro.core.record.register import open_register
reg = open_register(sys.argv[1])
while time.time() < float(sys.argv[3]):
    time.sleep(0.005)
issued = t._issue(reg, Path(sys.argv[2]))
print(issued.number)
"""


def test_concurrent_processes_get_distinct_consecutive_numbers(opened, register_url, tmp_path):
    import time

    open_register(register_url).close()  # migrated once; the workers race on numbers, not on DDL
    out = tmp_path / "out"
    script = tmp_path / "worker.py"
    script.write_text(_WORKER.format(tests=str(Path(__file__).parent)), encoding="utf-8")
    start = time.time() + 4.0  # all eight start issuing at the same moment
    procs = [subprocess.Popen([sys.executable, str(script), register_url, str(out), str(start)],
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) for _
             in range(8)]
    numbers = []
    for p in procs:
        o, e = p.communicate(timeout=300)
        assert p.returncode == 0, e
        numbers.append(o.strip())
    year = dt.datetime.now(dt.timezone.utc).year
    assert sorted(numbers) == [f"T{year}-{i:04d}" for i in range(1, 9)]
    assert sorted(p.name for p in out.iterdir()) == [f"{n}.docx" for n in sorted(numbers)]
    reg = opened(register_url)
    assert sorted(r["number"] for r in reg.list()) == sorted(numbers)


@pytest.mark.parametrize("url,reason", [
    ("mysql://a@b/c", "unsupported database 'mysql'"),
    ("sqlite:////proc/no-such-folder/r.sqlite", "cannot open the database"),
    ("postgresql+psycopg://metro@127.0.0.1:1/x", "cannot open the database"),
])
def test_unusable_register_is_a_clear_error(url, reason):
    with pytest.raises(RegisterError, match=reason):
        open_register(url)


def test_register_from_a_newer_metro_is_refused(tmp_path):
    url = "sqlite:///" + str(tmp_path / "r.sqlite")
    reg = open_register(url)
    with reg.engine.begin() as c:
        c.exec_driver_sql("UPDATE alembic_version SET version_num = '9999'")
    reg.close()
    with pytest.raises(RegisterError, match="newer metro"):
        open_register(url)


def test_readers_do_not_wait_for_a_writer(opened, register_url, tmp_path):
    """While a report is being committed (the writer holds the lock), `register list` from another
    connection answers at once with the reports committed before."""
    import threading

    reg, other = opened(register_url), opened(register_url)
    first = _issue(reg, tmp_path / "out")
    seen = []

    def during_commit(final: Path) -> None:
        t = threading.Thread(target=lambda: seen.append([r["number"] for r in other.list()]))
        t.start()
        t.join(timeout=20)
        assert not t.is_alive(), "a reader waited for the writer"

    _issue(reg, tmp_path / "out", _before_commit=during_commit)
    assert seen == [[first.number]]
    assert len(other.list()) == 2


def test_year_of_a_number_is_the_labs_and_numbers_restart_each_year(opened, register_url, tmp_path,
                                                                    monkeypatch):
    """31 December 16:30 UTC is 1 January 00:30 in Asia/Shanghai: numbered in the new year, from
    1."""
    import metro.core.record.register as regmod

    reg = opened(register_url)
    real = dt.datetime

    class Clock(dt.datetime):
        at = real(2026, 12, 31, 15, 0, tzinfo=dt.timezone.utc)

        @classmethod
        def now(cls, tz=None):
            return cls.at.astimezone(tz) if tz else cls.at

    class FakeDt:
        datetime, timezone, date, timedelta = Clock, dt.timezone, dt.date, dt.timedelta

    monkeypatch.setattr(regmod, "dt", FakeDt)
    kw = dict(folder=tmp_path / "out", scheme=_scheme, per_year=True, timezone="Asia/Shanghai")
    a = reg.issue(_draft(), **kw)  # 23:00 in Shanghai
    b = reg.issue(_draft(), **kw)
    Clock.at = real(2026, 12, 31, 16, 30, tzinfo=dt.timezone.utc)  # 00:30 on 1 January in Shanghai
    c = reg.issue(_draft(), **kw)
    d = reg.issue(_draft(), folder=tmp_path / "out2", scheme=_scheme, per_year=True, timezone="UTC")
    assert [x.number for x in (a, b, c, d)] == ["T2026-0001", "T2026-0002", "T2027-0001",
                                                "T2026-0003"]

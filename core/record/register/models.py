"""The register's tables (SQLAlchemy 2 typed declarative models).

The schema is created and changed only by the Alembic migrations in
``metro/core/register/migrations`` (run by :func:`metro.core.record.register.open_register`); these
classes describe the same tables for queries.  JSON columns keep what has no fixed shape
(budgets, verdicts, provenance, the report's render context).
"""

from __future__ import annotations

import datetime as dt
from typing import Any

from sqlalchemy import JSON, Boolean, Date, DateTime, Float, ForeignKey, Integer, String, Text
from sqlalchemy.orm import DeclarativeBase, Mapped, mapped_column, relationship

STATUSES = ("issued", "superseded", "withdrawn")


class Base(DeclarativeBase):
    pass


class Counter(Base):
    """The last sequence number issued in a numbering scope (a year, or ``all``).

    Allocating a number locks this row (``SELECT … FOR UPDATE`` on PostgreSQL; the whole
    database with ``BEGIN IMMEDIATE`` on SQLite) and is rolled back with the report's row, so
    a failed run leaves no gap."""

    __tablename__ = "counters"

    scope: Mapped[str] = mapped_column(String(32), primary_key=True)
    last: Mapped[int] = mapped_column(Integer, nullable=False, default=0)


class Report(Base):
    __tablename__ = "reports"

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    number: Mapped[str] = mapped_column(String(64), unique=True, nullable=False)
    scope: Mapped[str] = mapped_column(String(32), nullable=False)
    seq: Mapped[int] = mapped_column(Integer, nullable=False)
    status: Mapped[str] = mapped_column(String(16), nullable=False, default="issued")
    supersedes: Mapped[str | None] = mapped_column(String(64), nullable=True)
    superseded_by: Mapped[str | None] = mapped_column(String(64), nullable=True)
    reason: Mapped[str] = mapped_column(Text, nullable=False, default="")
    standard: Mapped[str] = mapped_column(String(64), nullable=False, index=True)
    items: Mapped[list[str]] = mapped_column(JSON, nullable=False, default=list)
    options: Mapped[dict[str, Any]] = mapped_column(JSON, nullable=False, default=dict)
    device_id: Mapped[str] = mapped_column(String(200), nullable=False, default="")
    device_manufacturer: Mapped[str] = mapped_column(String(200), nullable=False, default="")
    device_model: Mapped[str] = mapped_column(String(200), nullable=False, default="")
    device_serial: Mapped[str] = mapped_column(String(200), nullable=False, default="", index=True)
    customer: Mapped[str] = mapped_column(Text, nullable=False, default="")
    measurement_date: Mapped[dt.date] = mapped_column(Date, nullable=False)
    issued_at: Mapped[dt.datetime] = mapped_column(DateTime(timezone=True), nullable=False)
    issued_by: Mapped[str] = mapped_column(String(200), nullable=False, default="")
    simulated: Mapped[bool] = mapped_column(Boolean, nullable=False, default=False)
    allow_expired: Mapped[bool] = mapped_column(Boolean, nullable=False, default=False)
    lab: Mapped[dict[str, Any]] = mapped_column(JSON, nullable=False, default=dict)
    verdicts: Mapped[Any] = mapped_column(JSON, nullable=True)
    budgets: Mapped[list[Any]] = mapped_column(JSON, nullable=False, default=list)
    provenance: Mapped[dict[str, Any]] = mapped_column(JSON, nullable=False, default=dict)
    manifest_sha256: Mapped[str | None] = mapped_column(String(64), nullable=True)
    equipment: Mapped[list[Any]] = mapped_column(JSON, nullable=False, default=list)
    report_path: Mapped[str] = mapped_column(Text, nullable=False)
    report_sha256: Mapped[str] = mapped_column(String(64), nullable=False)
    #: the report's DCC (PTB Digital Calibration Certificate XML) when one was issued with it
    dcc_path: Mapped[str | None] = mapped_column(Text, nullable=True)
    dcc_sha256: Mapped[str | None] = mapped_column(String(64), nullable=True)
    template: Mapped[str] = mapped_column(Text, nullable=False, default="")
    #: everything the renderer needs to write the same report again (metro report NUMBER)
    context: Mapped[dict[str, Any]] = mapped_column(JSON, nullable=False, default=dict)

    results: Mapped[list["ResultRow"]] = relationship(back_populates="report",
                                                      order_by="ResultRow.id",
                                                      cascade="all, delete-orphan")


class ResultRow(Base):
    __tablename__ = "results"

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    report_id: Mapped[int] = mapped_column(ForeignKey("reports.id"), nullable=False, index=True)
    item: Mapped[str] = mapped_column(String(64), nullable=False)
    key: Mapped[str] = mapped_column(String(128), nullable=False)
    quantity: Mapped[str] = mapped_column(Text, nullable=False, default="")
    symbol: Mapped[str] = mapped_column(String(64), nullable=False, default="")
    value: Mapped[float | None] = mapped_column(Float, nullable=True)
    u: Mapped[float | None] = mapped_column(Float, nullable=True)
    U: Mapped[float | None] = mapped_column("U_expanded", Float, nullable=True)
    k: Mapped[float | None] = mapped_column(Float, nullable=True)
    nu_eff: Mapped[float | None] = mapped_column(Float, nullable=True)
    unit: Mapped[str] = mapped_column(String(64), nullable=False, default="")
    value_text: Mapped[str] = mapped_column(Text, nullable=False, default="")
    U_text: Mapped[str | None] = mapped_column(Text, nullable=True)
    reportable: Mapped[bool] = mapped_column(Boolean, nullable=False, default=True)
    reason: Mapped[str] = mapped_column(Text, nullable=False, default="")

    report: Mapped[Report] = relationship(back_populates="results")


class AuditEntry(Base):
    """Append-only: a database trigger refuses UPDATE and DELETE on this table."""

    __tablename__ = "audit"

    id: Mapped[int] = mapped_column(Integer, primary_key=True, autoincrement=True)
    at: Mapped[dt.datetime] = mapped_column(DateTime(timezone=True), nullable=False)
    who: Mapped[str] = mapped_column(String(200), nullable=False)
    action: Mapped[str] = mapped_column(String(32), nullable=False)
    number: Mapped[str] = mapped_column(String(64), nullable=False, index=True)
    detail: Mapped[str] = mapped_column(Text, nullable=False, default="")

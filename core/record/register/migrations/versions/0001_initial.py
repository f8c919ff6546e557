"""The first register schema: counters, reports, results, audit (append-only by trigger).

Revision ID: 0001
Revises:
"""

import sqlalchemy as sa
from alembic import op

revision = "0001"
down_revision = None
branch_labels = None
depends_on = None


def upgrade() -> None:
    op.create_table(
        "counters",
        sa.Column("scope", sa.String(32), primary_key=True),
        sa.Column("last", sa.Integer, nullable=False),
    )
    op.create_table(
        "reports",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("number", sa.String(64), nullable=False, unique=True),
        sa.Column("scope", sa.String(32), nullable=False),
        sa.Column("seq", sa.Integer, nullable=False),
        sa.Column("status", sa.String(16), nullable=False),
        sa.Column("supersedes", sa.String(64)),
        sa.Column("superseded_by", sa.String(64)),
        sa.Column("reason", sa.Text, nullable=False),
        sa.Column("standard", sa.String(64), nullable=False, index=True),
        sa.Column("items", sa.JSON, nullable=False),
        sa.Column("options", sa.JSON, nullable=False),
        sa.Column("device_id", sa.String(200), nullable=False),
        sa.Column("device_manufacturer", sa.String(200), nullable=False),
        sa.Column("device_model", sa.String(200), nullable=False),
        sa.Column("device_serial", sa.String(200), nullable=False, index=True),
        sa.Column("customer", sa.Text, nullable=False),
        sa.Column("measurement_date", sa.Date, nullable=False),
        sa.Column("issued_at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("issued_by", sa.String(200), nullable=False),
        sa.Column("simulated", sa.Boolean, nullable=False),
        sa.Column("allow_expired", sa.Boolean, nullable=False),
        sa.Column("lab", sa.JSON, nullable=False),
        sa.Column("verdicts", sa.JSON),
        sa.Column("budgets", sa.JSON, nullable=False),
        sa.Column("provenance", sa.JSON, nullable=False),
        sa.Column("manifest_sha256", sa.String(64)),
        sa.Column("equipment", sa.JSON, nullable=False),
        sa.Column("report_path", sa.Text, nullable=False),
        sa.Column("report_sha256", sa.String(64), nullable=False),
        sa.Column("template", sa.Text, nullable=False),
        sa.Column("context", sa.JSON, nullable=False),
        sa.UniqueConstraint("scope", "seq", name="uq_reports_scope_seq"),
        sa.CheckConstraint("status IN ('issued', 'superseded', 'withdrawn')",
                           name="ck_reports_status"),
    )
    op.create_table(
        "results",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("report_id", sa.Integer, sa.ForeignKey("reports.id"), nullable=False, index=True),
        sa.Column("item", sa.String(64), nullable=False),
        sa.Column("key", sa.String(128), nullable=False),
        sa.Column("quantity", sa.Text, nullable=False),
        sa.Column("symbol", sa.String(64), nullable=False),
        sa.Column("value", sa.Float),
        sa.Column("u", sa.Float),
        sa.Column("U_expanded", sa.Float),
        sa.Column("k", sa.Float),
        sa.Column("nu_eff", sa.Float),
        sa.Column("unit", sa.String(64), nullable=False),
        sa.Column("value_text", sa.Text, nullable=False),
        sa.Column("U_text", sa.Text),
        sa.Column("reportable", sa.Boolean, nullable=False),
        sa.Column("reason", sa.Text, nullable=False),
    )
    op.create_table(
        "audit",
        sa.Column("id", sa.Integer, primary_key=True, autoincrement=True),
        sa.Column("at", sa.DateTime(timezone=True), nullable=False),
        sa.Column("who", sa.String(200), nullable=False),
        sa.Column("action", sa.String(32), nullable=False),
        sa.Column("number", sa.String(64), nullable=False, index=True),
        sa.Column("detail", sa.Text, nullable=False),
    )
    # the audit trail is append-only: the database itself refuses to change or delete an entry
    if op.get_bind().dialect.name == "postgresql":
        op.execute(
            "CREATE FUNCTION metro_audit_append_only() RETURNS trigger AS $$ BEGIN "
            "RAISE EXCEPTION 'the audit trail is append-only'; END; $$ LANGUAGE plpgsql"
        )
        op.execute("CREATE TRIGGER audit_append_only BEFORE UPDATE OR DELETE ON audit "
                   "FOR EACH ROW EXECUTE FUNCTION metro_audit_append_only()")
    else:
        for what in ("UPDATE", "DELETE"):
            op.execute(f"CREATE TRIGGER audit_no_{what.lower()} BEFORE {what} ON audit "
                       "BEGIN SELECT RAISE(ABORT, 'the audit trail is append-only'); END")


def downgrade() -> None:
    op.drop_table("audit")
    op.drop_table("results")
    op.drop_table("reports")
    op.drop_table("counters")
    if op.get_bind().dialect.name == "postgresql":
        op.execute("DROP FUNCTION IF EXISTS metro_audit_append_only()")

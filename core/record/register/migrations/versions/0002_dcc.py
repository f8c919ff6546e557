"""A report's Digital Calibration Certificate (PTB DCC XML): its path and SHA-256.

Revision ID: 0002
Revises: 0001

Both columns are empty for a report issued without a DCC (every report of a register written
before this revision).
"""

import sqlalchemy as sa
from alembic import op

revision = "0002"
down_revision = "0001"
branch_labels = None
depends_on = None


def upgrade() -> None:
    with op.batch_alter_table("reports") as batch:
        batch.add_column(sa.Column("dcc_path", sa.Text, nullable=True))
        batch.add_column(sa.Column("dcc_sha256", sa.String(64), nullable=True))


def downgrade() -> None:
    with op.batch_alter_table("reports") as batch:
        batch.drop_column("dcc_sha256")
        batch.drop_column("dcc_path")

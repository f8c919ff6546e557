"""Layer 6 — what a lab keeps: its profile, the report register (SQLAlchemy + Alembic) and
registering, amending and withdrawing reports.
"""

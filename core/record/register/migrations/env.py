"""Alembic environment of the register: run programmatically by metro.core.record.register.migrate
on the connection it is given (``config.attributes["connection"]``); no alembic.ini is needed."""

from alembic import context

from metro.core.record.register.models import Base

config = context.config
connection = config.attributes["connection"]
context.configure(connection=connection, target_metadata=Base.metadata, render_as_batch=True)
with context.begin_transaction():
    context.run_migrations()

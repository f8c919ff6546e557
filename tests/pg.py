"""A throw-away PostgreSQL server for the tests (shared design notes, "PostgreSQL as root").

``start()`` runs ``initdb`` and ``pg_ctl start`` on a random free port on 127.0.0.1 (as the
``postgres`` user through ``runuser`` when the tests run as root, since PostgreSQL refuses to
run as root), with trust authentication for the user ``metro``; ``stop()`` stops it and removes
its folder.  ``SKIP_REASON`` is set when no server binary exists on this machine.
"""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import tempfile
import uuid
from pathlib import Path


def _binary(name: str) -> str | None:
    found = shutil.which(name)
    if found:
        return found
    for ver in ("17", "16", "15", "14", "13"):
        p = Path(f"/usr/lib/postgresql/{ver}/bin/{name}")
        if p.is_file():
            return str(p)
    return None


INITDB, PG_CTL = _binary("initdb"), _binary("pg_ctl")
SKIP_REASON = (
    None if INITDB and PG_CTL else "no PostgreSQL server binary (initdb/pg_ctl) on this machine"
)


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


class Server:
    def __init__(self) -> None:
        self.dir = Path(tempfile.mkdtemp(prefix="metro-pg-"))
        self.data = self.dir / "data"
        self.port = _free_port()
        self.as_root = os.geteuid() == 0

    def _run(self, *cmd: str) -> None:
        if self.as_root:
            cmd = ("runuser", "-u", "postgres", "--", *cmd)
        out = subprocess.run(cmd, capture_output=True, text=True, timeout=120)
        if out.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)} failed: {out.stdout}\n{out.stderr}")

    def start(self) -> "Server":
        if self.as_root:
            shutil.chown(self.dir, "postgres", "postgres")
        self._run(INITDB, "-D", str(self.data), "-U", "metro", "--auth=trust", "-E", "UTF8",
                  "--no-sync")
        self._run(PG_CTL, "-D", str(self.data), "-l", str(self.dir / "log"), "-o",
                  f"-p {self.port} -k {self.dir} -c listen_addresses=127.0.0.1 -c fsync=off", "-w",
                  "start")
        return self

    def url(self, db: str = "postgres") -> str:
        return f"postgresql+psycopg://metro@127.0.0.1:{self.port}/{db}"

    def new_database(self) -> str:
        """A fresh, empty database; its SQLAlchemy URL."""
        import psycopg

        name = "t_" + uuid.uuid4().hex[:12]
        with psycopg.connect(f"host=127.0.0.1 port={self.port} user=metro dbname=postgres",
                             autocommit=True) as c:
            c.execute(f'CREATE DATABASE "{name}"')
        return self.url(name)

    def stop(self) -> None:
        try:
            self._run(PG_CTL, "-D", str(self.data), "-m", "fast", "-w", "stop")
        finally:
            shutil.rmtree(self.dir, ignore_errors=True)

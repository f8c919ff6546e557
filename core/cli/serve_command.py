"""``metro serve``: the register in a browser, read only (:mod:`metro.core.web`).

It binds to 127.0.0.1 unless ``--host`` says otherwise; docs/register.md shows how to put the
internal pages behind a reverse proxy with authentication while ``/verify`` stays public.
Nothing heavy is imported until the command runs (Starlette, Jinja2 and uvicorn are the ``web``
extra).
"""

from __future__ import annotations

import sys

__all__ = ["add_command", "command"]


def add_command(sub) -> None:
    """``metro serve [--host 127.0.0.1] [--port 8000]`` under the subcommands ``sub``."""
    s = sub.add_parser(
        "serve", help="serve the register read-only in a browser (reports, devices, equipment, "
        "certificate verification)",
        description="Serve the register of the lab profile in force (SQLite or PostgreSQL) as "
        "read-only web pages: the reports with filters, each report with its files (served only "
        "after their SHA-256 is checked), a device's history, the lab's equipment, and the public "
        "page /verify/NUMBER that customers use to check a certificate (docs/register.md).")
    s.add_argument("--host", default="127.0.0.1",
                   help="address to listen on (default 127.0.0.1: this computer only; put a "
                   "reverse proxy with authentication in front before listening on others)")
    s.add_argument("--port", type=int, default=8000, help="port (default 8000)")


def command(args) -> int:
    """Run ``metro serve`` until interrupted."""
    from ..base.extras import require
    from ..record import lab as labmod
    from .register_commands import register_url

    require("starlette", "metro serve", extra="web")
    require("jinja2", "metro serve", extra="web")
    uvicorn = require("uvicorn", "metro serve", extra="web")
    from ..web.app import create_app

    where = labmod.find_lab_path(getattr(args, "lab", None))
    app = create_app(register_url(args), lab=where)
    print(f"metro serve: {labmod.redact_url(register_url(args))} on http://{args.host}:{args.port}"
          " (read only; Ctrl+C stops)", file=sys.stderr)
    uvicorn.run(app, host=args.host, port=args.port, log_level="warning")
    return 0

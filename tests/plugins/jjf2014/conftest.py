"""Fixtures of the JJF 2014 tests that write campaigns by hand."""

from __future__ import annotations

import contextlib
import io
import json
from pathlib import Path

import pytest


@pytest.fixture(scope="session")
def jjf_run():
    """``jjf_run(manifest, items)``: ``metro run -s jjf2014 -i items --data manifest --json`` in
    this process, which must evaluate (exit 0, 3 or 4); its results by key."""
    from metro.core.cli.app import main

    def run(manifest: Path, items: str) -> dict:
        out, err = io.StringIO(), io.StringIO()
        with contextlib.redirect_stdout(out), contextlib.redirect_stderr(err):
            code = main(["run", "-s", "jjf2014", "-i", items, "--data", str(manifest), "--json",
                         "--no-report", "--quiet"])
        assert code in (0, 3, 4), err.getvalue()[-2000:]
        return {r["key"]: r for r in json.loads(out.getvalue())["results"]}

    return run

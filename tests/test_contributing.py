"""CONTRIBUTING.md's commit rule: a subject of at most 72 characters, for every commit since the
commit that wrote the rule down in CONTRIBUTING.md (8f598ab)."""

from __future__ import annotations

import shutil
import subprocess
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
SINCE = "8f598ab"


def _subjects() -> list[str]:
    if shutil.which("git") is None or not (ROOT / ".git").exists():
        pytest.skip("not a git checkout (an unpacked sdist has no history)")
    known = subprocess.run(["git", "-C", str(ROOT), "cat-file", "-e", f"{SINCE}^{{commit}}"],
                           check=False,
                           capture_output=True)
    if known.returncode != 0:
        pytest.skip(f"a shallow clone without {SINCE}")
    out = subprocess.run(["git", "-C", str(ROOT), "log", "--format=%s", f"{SINCE}^..HEAD"],
                         check=True,
                         capture_output=True, text=True)
    return out.stdout.splitlines()


def test_commit_subjects_are_at_most_72_characters():
    subjects = _subjects()
    assert subjects, "no commit found since the rule was written"
    assert [s for s in subjects if len(s) > 72] == []


def test_contributing_states_the_rule():
    text = (ROOT / "CONTRIBUTING.md").read_text(encoding="utf-8")
    assert "at most 72 characters" in text and "what was measured" in text

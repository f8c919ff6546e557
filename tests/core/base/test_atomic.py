"""metro.core.base.atomic: a file is written completely or not at all."""

from __future__ import annotations

import os
import stat
import sys

import pytest

from metro.core.base.atomic import (TMP_MARKER, atomic_path, atomic_write, atomic_write_bytes,
                                    atomic_write_text)


def _leftovers(directory):
    return sorted(p.name for p in directory.iterdir() if TMP_MARKER in p.name)


def test_success_writes_the_file_and_leaves_no_temp(tmp_path):
    target = tmp_path / "out.txt"
    assert atomic_write_text(target, "hello\n", newline="") == target
    assert target.read_text(encoding="utf-8") == "hello\n"
    assert _leftovers(tmp_path) == []


def test_success_replaces_an_existing_file(tmp_path):
    target = tmp_path / "out.bin"
    target.write_bytes(b"old")
    atomic_write_bytes(target, b"new contents")
    assert target.read_bytes() == b"new contents"
    assert _leftovers(tmp_path) == []


def test_temp_file_is_hidden_next_to_the_target(tmp_path):
    target = tmp_path / "report.docx"
    with atomic_path(target) as tmp:
        assert tmp.parent == tmp_path
        assert tmp.name.startswith(".report.docx" + TMP_MARKER)
        assert tmp.exists() and not target.exists()
        tmp.write_bytes(b"x")
    assert target.read_bytes() == b"x"


def test_failing_writer_leaves_nothing(tmp_path):
    target = tmp_path / "out.txt"

    def writer(tmp):
        tmp.write_text("half of it")
        raise RuntimeError("disk on fire")

    with pytest.raises(RuntimeError, match="disk on fire"):
        atomic_write(target, writer)
    assert not target.exists()
    assert list(tmp_path.iterdir()) == []


def test_existing_file_survives_a_failed_overwrite(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("precious")

    def writer(tmp):
        tmp.write_text("garbage")
        raise ValueError("boom")

    with pytest.raises(ValueError):
        atomic_write(target, writer)
    assert target.read_text() == "precious"
    assert _leftovers(tmp_path) == []


def test_keyboard_interrupt_also_cleans_up(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("precious")
    with pytest.raises(KeyboardInterrupt):
        with atomic_path(target) as tmp:
            tmp.write_text("partial")
            raise KeyboardInterrupt
    assert target.read_text() == "precious"
    assert _leftovers(tmp_path) == []


def test_writer_that_removes_its_temp_file_is_an_error(tmp_path):
    target = tmp_path / "out.txt"
    with pytest.raises(FileNotFoundError):
        atomic_write(target, lambda tmp: tmp.unlink())
    assert list(tmp_path.iterdir()) == []


def test_missing_directory_is_a_clear_error(tmp_path):
    with pytest.raises(FileNotFoundError, match="does not exist"):
        atomic_write_text(tmp_path / "nope" / "out.txt", "x")


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX permission bits")
def test_permissions_of_an_existing_file_are_kept(tmp_path):
    target = tmp_path / "out.txt"
    target.write_text("old")
    os.chmod(target, 0o640)
    atomic_write_text(target, "new")
    assert stat.S_IMODE(os.stat(target).st_mode) == 0o640


@pytest.mark.skipif(sys.platform == "win32", reason="POSIX umask")
def test_new_file_gets_the_usual_permissions_not_0600(tmp_path):
    old = os.umask(0o022)
    try:
        target = atomic_write_text(tmp_path / "new.txt", "x")
    finally:
        os.umask(old)
    assert stat.S_IMODE(os.stat(target).st_mode) == 0o644

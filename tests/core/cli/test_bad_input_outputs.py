"""Outputs never destroy anything (issue 14): a report path that is an input of the run is refused
even with --force; an existing file is refused unless --force (a read-only one even then); the
suffix decides the format; the output folder is checked before the evaluation; a failed write
leaves nothing; stale temporary files of a killed write are swept."""

from __future__ import annotations

import errno
import hashlib
import os
import time

import pytest


@pytest.fixture
def camp(tmp_path, campaign_factory):
    return campaign_factory.write_campaign(tmp_path / "c", hours=0.1)


def _snapshot(root):
    return {str(p.relative_to(root)): (hashlib.sha256(p.read_bytes()).hexdigest() if p.is_file()
                                       else "dir")
            for p in sorted(root.rglob("*"))}


def _run(run_cli, manifest, *extra):
    return run_cli("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(manifest), "--no-progress",
                   *extra)


def _refused(run_cli, tmp_path, manifest, *extra, field="--report", where=None):
    before = _snapshot(tmp_path)
    code, out, err = _run(run_cli, manifest, *extra)
    assert code == 2, err
    assert "Traceback" not in err and f"field '{field}'" in err
    if where is not None:
        assert str(where) in err
    assert _snapshot(tmp_path) == before  # nothing written, nothing replaced
    return err


@pytest.mark.parametrize("force", [(), ("--force",)])
def test_the_manifest_is_never_the_report(tmp_path, campaign_factory, run_cli, force):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.1)
    docx_manifest = m.with_name("manifest.docx")  # a manifest whose name has the report's suffix
    m.rename(docx_manifest)
    err = _refused(run_cli, tmp_path, docx_manifest, "--report", str(docx_manifest), *force,
                   where=docx_manifest)
    assert "input of this run" in err


def test_a_samples_file_is_never_the_report(tmp_path, campaign_factory, run_cli):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.1)
    (m.parent / "static.csv").rename(m.parent / "static.docx")
    m.write_text(m.read_text(encoding="utf-8").replace("static.csv", "static.docx"),
                 encoding="utf-8")
    err = _refused(run_cli, tmp_path, m, "--report", str(m.parent / "static.docx"), "--force")
    assert "input of this run" in err


# .docx and .pdf are written
@pytest.mark.parametrize("suffix", [".doc", ".txt", ".csv", ".toml", ""])
def test_the_suffix_decides_the_format(tmp_path, camp, run_cli, suffix):
    err = _refused(run_cli, tmp_path, camp, "--report", str(tmp_path / f"r{suffix}"))
    assert ".docx" in err


def test_the_manifest_csv_suffixes_are_refused_before_anything(tmp_path, camp, run_cli):
    for target in (camp, camp.parent / "static.csv"):
        _refused(run_cli, tmp_path, camp, "--report", str(target), "--force")


def test_an_existing_report_is_replaced_only_with_force(tmp_path, camp, run_cli):
    r = tmp_path / "r.docx"
    r.write_bytes(b"an earlier report")
    err = _refused(run_cli, tmp_path, camp, "--report", str(r), where=r)
    assert "--force" in err
    code, _, err = _run(run_cli, camp, "--report", str(r), "--force")
    assert code == 0, err
    assert r.read_bytes()[:2] == b"PK"  # a Word file now


def test_a_read_only_report_is_not_replaced_even_with_force(tmp_path, camp, run_cli):
    r = tmp_path / "r.docx"
    r.write_bytes(b"signed report")
    r.chmod(0o444)
    try:
        err = _refused(run_cli, tmp_path, camp, "--report", str(r), "--force")
        assert "read-only" in err
    finally:
        r.chmod(0o644)


def test_a_folder_is_not_a_report_path(tmp_path, camp, run_cli):
    d = tmp_path / "reports.docx"
    d.mkdir()
    _refused(run_cli, tmp_path, camp, "--report", str(d), "--force")


def test_out_under_a_file_is_refused_before_evaluation(tmp_path, camp, run_cli, monkeypatch):
    import metro.core.run.runner as runner

    f = tmp_path / "afile"
    f.write_text("x")

    def boom(*a, **k):  # the evaluation must not start
        raise AssertionError("evaluated before the output folder was checked")

    monkeypatch.setattr(runner, "run_items", boom)
    _refused(run_cli, tmp_path, camp, "--out", str(f / "sub"), field="--out")
    _refused(run_cli, tmp_path, camp, "--out", str(f), field="--out")
    _refused(run_cli, tmp_path, camp, "--report", str(f / "r.docx"))


def test_an_unwritable_folder_is_refused_before_evaluation(tmp_path, camp, run_cli, monkeypatch):
    """A read-only folder (as root, os.access is the kernel's answer; here it is made to say no)."""
    import metro.core.run.outputs as outputs

    ro = tmp_path / "ro"
    ro.mkdir()
    real = os.access
    monkeypatch.setattr(outputs.os, "access", lambda p, mode: False if os.fspath(p) == str(ro)
                        else real(p, mode))
    err = _refused(run_cli, tmp_path, camp, "--out", str(ro / "reports"), field="--out")
    assert "not writable" in err


def test_a_full_file_system_leaves_nothing(tmp_path, camp, run_cli, monkeypatch):
    import metro.core.documents.report as report

    def full(path, *a, **k):
        raise OSError(errno.ENOSPC, "No space left on device")

    monkeypatch.setattr(report, "write_report", full)
    before = _snapshot(tmp_path)
    code, _, err = _run(run_cli, camp, "--out", str(tmp_path / "new" / "deeper"))
    assert code == 2 and "No space left" in err and "Traceback" not in err
    assert _snapshot(tmp_path) == before  # not even the folders made for it


def test_stale_temporaries_of_a_killed_write_are_swept(tmp_path, camp, run_cli):
    out = tmp_path / "out"
    out.mkdir()
    stale = out / ".MTR-old.docx.tmp-0123abcd"
    fresh = out / ".MTR-now.docx.tmp-89abcdef"
    other = out / ".notes.tmp-xyz"  # not the pattern: never touched
    for p in (stale, fresh, other):
        p.write_bytes(b"partial")
    old = time.time() - 2 * 3600
    os.utime(stale, (old, old))
    os.utime(other, (old, old))
    code, _, err = _run(run_cli, camp, "--out", str(out))
    assert code == 0, err
    assert not stale.exists() and fresh.exists() and other.exists()
    assert len(list(out.glob("MTR-*.docx"))) == 1

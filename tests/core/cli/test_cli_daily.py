"""What a new user and a lab meet in their first hour on the command line (issue 29, "Register
and command line"): read-only commands create nothing, `register verify`'s own exit code, tables
that scripts can read, global options after the command, the same progress flags on every
command, `acquire --out` making its parents, the report messages, and `metro doctor`."""

from __future__ import annotations

import json
from pathlib import Path

import pytest

from metro.core.cli.app import main

SIM_JJF = ["run", "-s", "jjf2014", "-i", "7.2.3", "--seed", "3"]
LONG_SERIAL = "SN-2026-ABCDEFGHIJKLMNOPQRSTUVWXYZ-0001"
LONG_STANDARD = "standard-with-a-long-identifier"


@pytest.fixture
def home(tmp_path, monkeypatch):
    """No lab profile, no register: the user folders are empty temporary ones."""
    monkeypatch.setenv("XDG_DATA_HOME", str(tmp_path / "data"))
    monkeypatch.setenv("XDG_CONFIG_HOME", str(tmp_path / "config"))
    for var in ("METRO_LAB", "METRO_REGISTER"):
        monkeypatch.delenv(var, raising=False)
    return tmp_path


@pytest.fixture
def lab(home, capsys):
    """A lab profile (the template) whose register file does not exist yet."""
    path = home / "lab" / "lab.toml"
    path.parent.mkdir()
    assert main(["lab", "init", str(path)]) == 0
    capsys.readouterr()
    return path


@pytest.fixture
def issue(draft_rows):
    """``issue(lab_path, out, serial=…, standard=…, n=…)``: ``n`` reports in the register of the
    profile (through the register's API: no evaluation); their numbers."""
    from metro.core.record.lab import load_lab
    from metro.core.record.register import Draft, open_register

    def run(lab_path: Path, out: Path, *, serial: str = LONG_SERIAL,
            standard: str = LONG_STANDARD, n: int = 1) -> list[str]:
        profile = load_lab(lab_path)
        numbers = []
        with open_register(profile.register_url()) as reg:
            for day in range(1, n + 1):
                fields, result = draft_rows(standard=standard, items=("A.1", "A.2"),
                                            serial=serial, day=day, value=1.0 + day / 10)
                issued = reg.issue(lambda num, t, f=fields,
                                   r=result: Draft(f, [r], lambda tmp: tmp.write_text("x")),
                                   folder=out, scheme=profile.format_number, per_year=True)
                numbers.append(issued.number)
        return numbers

    return run


def _files(root: Path) -> list[str]:
    return sorted(str(p.relative_to(root)) for p in root.rglob("*"))


# -- 1. read-only commands create nothing ----------------------------------------------------


READ_ONLY = (["register", "list"], ["register", "show", "EML2026-00001"], ["register", "verify"],
             ["report", "EML2026-00001"], ["history", "S1"],
             ["withdraw", "EML2026-00001", "--reason", "r"])


@pytest.mark.parametrize("argv", READ_ONLY, ids=lambda a: " ".join(a[:2]))
def test_read_only_commands_create_no_register(home, run_cli, argv):
    """Without a lab profile the register in force is the user data folder's; reading it when it
    does not exist is an error saying so and how one is made, and nothing is created."""
    before = _files(home)
    out = ["--out", str(home / "out")] if argv[0] in ("report", "history") else []
    code, stdout, err = run_cli(*argv, *out)
    assert code == 2, err
    assert ("no register at sqlite:///" in err and "register.sqlite" in err
            and "metro lab init" in err)
    assert "Traceback" not in err
    assert _files(home) == before  # no file, no folder
    code, stdout, _ = run_cli(*argv, *out, "--json")
    assert code == 2 and json.loads(stdout)["message"].startswith("no register at")
    assert _files(home) == before


def test_read_only_commands_with_a_profile_create_no_register(lab, run_cli):
    before = _files(lab.parent.parent)
    for argv in (["register", "list"], ["register", "verify"],
                 ["amend", "EML2026-00001", "--reason", "r"]):
        code, _, err = run_cli("--lab", str(lab), *argv)
        assert (code == 2 and f"{lab.parent / 'register.sqlite'}" in err
                and "does not exist" in err), err
    assert _files(lab.parent.parent) == before and not (lab.parent / "register.sqlite").exists()
    # a database with no register tables is not made one either
    (lab.parent / "register.sqlite").write_bytes(b"")
    code, _, err = run_cli("--lab", str(lab), "register", "list")
    assert code == 2 and "no register tables" in err
    assert (lab.parent / "register.sqlite").stat().st_size == 0


def test_schema_head_is_the_newest_migration():
    """open_register skips Alembic for a register at SCHEMA_HEAD: it must be the newest
    migration."""
    from alembic.config import Config
    from alembic.script import ScriptDirectory

    import metro.core.record.register as register

    cfg = Config()
    cfg.set_main_option("script_location", str(Path(register.__file__).parent / "migrations"))
    scripts = ScriptDirectory.from_config(cfg)
    assert scripts.get_current_head() == register.SCHEMA_HEAD
    assert tuple(reversed([r.revision for r
                           in scripts.walk_revisions()])) == register.SCHEMA_REVISIONS


# -- 2. register verify has its own exit code ------------------------------------------------


def test_verify_exits_6_on_a_modified_or_missing_file(lab, issue, run_cli, tmp_path):
    a, b = issue(lab, tmp_path / "reports", n=2)
    code, stdout, _ = run_cli("--lab", str(lab), "register", "verify", "--json")
    assert code == 0 and json.loads(stdout)["ok"] is True
    (tmp_path / "reports" / f"{a}.docx").write_text("changed")
    code, stdout, _ = run_cli("--lab", str(lab), "register", "verify", "--json")
    assert code == 6 and {r["number"]: r["check"] for r
                          in json.loads(stdout)["reports"]} == {a: "modified", b: "ok"}
    (tmp_path / "reports" / f"{b}.docx").unlink()
    code, _, err = run_cli("--lab", str(lab), "register", "verify")
    assert code == 6 and f"{b} missing" in err
    readme = (Path(__file__).resolve().parents[3] / "README.md").read_text(encoding="utf-8")
    assert "| 6 |" in readme and "register verify" in readme.split("| 6 |", 1)[1].splitlines()[0]


# -- 3. tables: complete plain rows when piped, folded (never cut) on a terminal --------------


def test_register_list_and_history_print_whole_rows_when_piped(lab, issue, run_cli, tmp_path):
    numbers = issue(lab, tmp_path / "reports", n=2)
    code, stdout, _ = run_cli("--lab", str(lab), "register", "list")
    assert code == 0
    lines = stdout.splitlines()
    assert lines[0].startswith("# register sqlite:///")
    assert lines[1].split("\t")[:5] == ["number", "status", "standard", "items", "serial"]
    rows = [ln.split("\t") for ln in lines[2:]]
    assert [r[0] for r in rows] == numbers
    assert all(r[2] == LONG_STANDARD and r[3] == "A.1, A.2" and r[4] == LONG_SERIAL for r in rows)
    assert all(len(r) == len(lines[1].split("\t")) for r in rows)
    # nothing cut, nothing padded
    assert "…" not in stdout and not any(ln != ln.rstrip() for ln in lines)
    code, stdout, _ = run_cli("--lab", str(lab), "history", LONG_SERIAL, "--out",
                              str(tmp_path / "h"))
    assert code == 0 and "…" not in stdout and not any(ln != ln.rstrip() for ln
                                                       in stdout.splitlines())
    assert f"{numbers[1]}\t{LONG_STANDARD}\tA.1, A.2\t2026-01-02" in stdout


def test_register_list_on_a_terminal_folds_identifiers(lab, issue, run_cli, tmp_path, monkeypatch):
    import metro.core.cli.register_commands as cr

    issue(lab, tmp_path / "reports", n=2)
    monkeypatch.setattr(cr, "_is_terminal", lambda: True)
    monkeypatch.setenv("COLUMNS", "80")
    code, stdout, _ = run_cli("--lab", str(lab), "register", "list")
    assert code == 0 and "…" not in stdout
    lines = stdout.splitlines()
    assert max(len(ln) for ln in lines) <= 80
    # a header folds too: its last line names every column
    header = [ln for ln in lines if "┃" in ln][-1]
    col = [c.strip() for c in header.split("┃")].index("serial")
    serial_column = "".join(ln.split("│")[col].strip() for ln in lines if ln.count("│") > col)
    # folded onto several lines, every character kept
    assert serial_column == LONG_SERIAL + LONG_SERIAL


# -- 4. global options after the command ------------------------------------------------------


def test_global_options_are_accepted_after_the_command(lab, issue, run_cli, tmp_path):
    (number,) = issue(lab, tmp_path / "reports")
    code, stdout, err = run_cli("register", "list", "--lab", str(lab), "--json")
    assert code == 0, err
    assert [r["number"] for r in json.loads(stdout)["reports"]] == [number]
    code, stdout, _ = run_cli("register", "show", number, "--json", "--lab", str(lab))
    assert code == 0 and json.loads(stdout)["number"] == number
    code, stdout, _ = run_cli("plugins", "--json", "--no-plugin-autoload")
    assert code == 0 and json.loads(stdout)["autoload"] is False
    # --block-plugin given before and after the command: both count
    code, stdout, _ = run_cli("--block-plugin", "ogam", "items", "--json", "--block-plugin",
                              "jjf2003")
    standards = {i["standard"] for i in json.loads(stdout)["items"]}
    assert (code == 0 and "ogam" not in standards and "jjf2003" not in standards
            and "gbt45570" in standards)


# -- 6. one set of progress flags ---------------------------------------------------------------


def test_run_batch_and_acquire_share_their_progress_flags(run_cli):
    helps = {}
    for cmd in ("run", "batch", "acquire"):
        code, stdout, _ = run_cli(cmd, "--help")
        assert code == 0
        helps[cmd] = stdout
        assert "--quiet" in stdout and "--no-progress" in stdout, cmd
    assert "--strict" in helps["run"]
    assert "--strict" not in helps["batch"] and "--strict" not in helps["acquire"]


def test_acquire_quiet_says_nothing_on_stderr(run_cli, tmp_path):
    out = tmp_path / "camp"
    code, stdout, err = run_cli("--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1",
                                "--out", str(out),
                                "--station-option", "duration_scale=0.05", "--seed", "7", "--quiet")
    assert code == 0 and stdout.strip() == str(out / "manifest.toml") and err == ""


# -- 7. acquire --out makes the missing parents -------------------------------------------------


def test_acquire_makes_missing_parent_folders(run_cli, tmp_path):
    out = tmp_path / "lot" / "line-2" / "dev1"
    code, stdout, err = run_cli("--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1",
                                "--out",
                                str(out), "--station-option", "duration_scale=0.05", "--seed", "7",
                                "--no-progress")
    assert code == 0, err
    assert (out / "manifest.toml").is_file()
    # a file in the way is an error, and nothing is made
    (tmp_path / "afile").write_text("x")
    code, _, err = run_cli("--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1",
                           "--out",
                           str(tmp_path / "afile" / "dev1"), "--no-progress")
    assert code == 2 and "afile is not a folder" in err
    # still never replacing anything: an existing campaign is refused
    code, _, err = run_cli("--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1",
                           "--out", str(out),
                           "--no-progress")
    assert code == 2 and "not empty" in err


def test_acquire_removes_the_parents_it_made_when_it_fails(tmp_path, monkeypatch, run_cli):
    import metro.core.run.manifest_writer as cw
    from metro.core.base.errors import DataError

    def full(path, *a, **k):  # the manifest cannot be written (the samples were)
        raise DataError(str(path), None, "no space left on device")

    monkeypatch.setattr(cw, "atomic_write_text", full)
    code, _, err = run_cli("--no-plugin-autoload", "acquire", "-s", "gbt45570", "-i", "D.5.1",
                           "--out",
                           str(tmp_path / "new" / "deeper" / "dev1"), "--station-option",
                           "duration_scale=0.05",
                           "--no-progress")
    assert code == 2 and "no space left" in err
    assert list(tmp_path.iterdir()) == []  # the parents it made are gone with the campaign


# -- 8. the report messages ---------------------------------------------------------------------


def test_a_pdf_report_is_called_one_and_no_report_has_no_number(run_cli, tmp_path, home):
    code, stdout, err = run_cli(*SIM_JJF, "--no-progress", "--no-report")
    assert code == 0, err
    assert ("no report written" in stdout and "report number" not in stdout
            and "Word report" not in stdout)
    pdf = tmp_path / "x.pdf"
    code, stdout, err = run_cli(*SIM_JJF, "--no-progress", "--report", str(pdf))
    assert code == 0, err
    assert f"PDF report {pdf}" in stdout.replace("\n", "") and "Word report" not in stdout
    assert pdf.read_bytes()[:5] == b"%PDF-"
    # --pdf: the Word report and the PDF beside it, both named
    out = tmp_path / "both"
    code, stdout, err = run_cli(*SIM_JJF, "--no-progress", "--out", str(out), "--pdf")
    assert code == 0, err
    (docx,) = out.glob("*.docx")
    assert f"Word report {docx} and PDF {docx.with_suffix('.pdf')}" in stdout.replace("\n", "")
    assert docx.with_suffix(".pdf").read_bytes()[:5] == b"%PDF-"


# -- 10. metro doctor -----------------------------------------------------------------------------


def _doctor(run_cli, *argv):
    code, stdout, err = run_cli(*argv, "doctor", "--json")
    doc = json.loads(stdout)
    return code, doc, {c["check"]: c for c in doc["checks"]}


def test_doctor_passes_here_and_creates_nothing(lab, run_cli):
    def files() -> list[str]:  # (matplotlib keeps its own configuration in the config folder)
        return [f for f in _files(lab.parent.parent) if not f.startswith("config")]

    before = files()
    code, doc, checks = _doctor(run_cli, "--lab", str(lab))
    assert code == 0 and doc["ok"] is True
    assert checks["cjk-fonts"]["ok"] and "Noto" in checks["cjk-fonts"]["detail"]
    assert checks["lab-profile"]["ok"] and str(lab) in checks["lab-profile"]["detail"]
    reg = checks["register"]
    assert reg["ok"] and "no register" in reg["detail"] and "first registered run" in reg["detail"]
    assert {f"extra:{m}" for m in ("distributed", "psycopg", "numba", "pyarrow")} <= set(checks)
    # read only: no register made
    assert files() == before and not (lab.parent / "register.sqlite").exists()


def test_doctor_reports_the_register_schema(lab, issue, run_cli, tmp_path):
    issue(lab, tmp_path / "reports", n=2)
    code, doc, checks = _doctor(run_cli, "--lab", str(lab))
    assert code == 0 and checks["register"]["ok"] and "2 report(s)" in checks["register"]["detail"]
    import sqlite3

    with sqlite3.connect(lab.parent / "register.sqlite") as db:  # as if written by a newer metro
        db.execute("UPDATE alembic_version SET version_num = '9999'")
    code, doc, checks = _doctor(run_cli, "--lab", str(lab))
    assert code == 6 and not checks["register"]["ok"] and "upgrade metro" in checks["register"][
        "fix"]


def test_doctor_fails_on_a_broken_profile_and_says_what_to_do(home, run_cli, capsys):
    bad = home / "bad.toml"
    bad.write_text('format = "metro-lab/1"\n[lab]\nname_en = "X"\ncolour = "red"\n',
                   encoding="utf-8")
    code, doc, checks = _doctor(run_cli, "--lab", str(bad))
    assert code == 6 and doc["ok"] is False
    assert not checks["lab-profile"]["ok"] and checks["lab-profile"]["required"]
    assert "colour" in checks["lab-profile"]["detail"] and checks["lab-profile"]["fix"]
    code, stdout, err = run_cli("--lab", str(bad), "doctor")
    assert (code == 6 and "FAIL" in stdout and "what to do:" in stdout
            and "required check(s) failed" in err)


def test_doctor_fails_without_a_cjk_font(home, run_cli, monkeypatch):
    import metro.core.documents.plots as plots

    monkeypatch.setattr(plots, "FALLBACK_FONTS", ("No Such CJK Font",))
    code, doc, checks = _doctor(run_cli)
    assert code == 6 and not checks["cjk-fonts"]["ok"] and "fonts-noto-cjk" in checks["cjk-fonts"][
        "fix"]


def test_doctor_names_the_extra_of_a_missing_package(home, run_cli, monkeypatch):
    import metro.core.base.extras as extras

    real = extras.available
    monkeypatch.setattr(extras, "available", lambda module: module != "numba" and real(module))
    code, doc, checks = _doctor(run_cli)
    numba = checks["extra:numba"]
    # optional: informs, does not fail
    assert code == 0 and not numba["ok"] and not numba["required"]
    assert numba["fix"] == "pip install 'metro-inertial[fast]'" and "numpy fallback" in numba[
        "detail"]
    code, stdout, _ = run_cli("doctor")
    assert "missing" in stdout and "metro-inertial[fast]" in stdout


def test_register_show_piped_keeps_each_line_whole(lab, issue, run_cli, tmp_path):
    (number,) = issue(lab, tmp_path / "a-folder-with-a-rather-long-name-for-its-reports")
    code, stdout, _ = run_cli("--lab", str(lab), "register", "show", number)
    assert code == 0
    line = next(ln for ln in stdout.splitlines() if ln.startswith("  file "))
    # one line, not wrapped at 80
    assert line.endswith(")") and "sha256 " in line and len(line) > 80
    assert "# results" in stdout and "# audit trail" in stdout and "…" not in stdout


def test_a_postgresql_register_without_its_driver_names_the_extra(home, run_cli, monkeypatch):
    # as if the 'postgres' extra were missing
    monkeypatch.setitem(__import__("sys").modules, "psycopg", None)
    monkeypatch.setenv("METRO_REGISTER", "postgresql+psycopg://metro@127.0.0.1:5/x")
    code, _, err = run_cli("register", "list")
    assert code == 2 and "pip install 'metro-inertial[postgres]'" in err and "Traceback" not in err

"""The install (issue 29): the core install is what one station needs and runs without the extras;
a command that needs a missing extra names it; the distribution is metro-inertial; the README's two
commands and .ci/run agree."""

from __future__ import annotations

import os
import subprocess
import sys
import textwrap
import tomllib
from importlib.metadata import version
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
OPTIONAL = ("numba", "llvmlite", "pyarrow", "dask", "distributed", "psycopg", "psycopg_binary")


def _project() -> dict:
    return tomllib.loads((ROOT / "pyproject.toml").read_text(encoding="utf-8"))["project"]


def _names(requirements) -> set[str]:
    import re

    return {re.split(r"[\[<>=!~; ]", r, maxsplit=1)[0].lower() for r in requirements}


def test_core_dependencies_leave_the_heavy_and_unused_packages_to_extras():
    project = _project()
    core = _names(project["dependencies"])
    assert not core & {"numba", "pyarrow", "dask", "psycopg", "uncertainties", "babel"}, core
    assert "tomli-w" in core
    extras = {k: _names(v) for k, v in project["optional-dependencies"].items()}
    assert {"numba", "pyarrow"} <= extras["fast"]
    assert {"dask", "pyarrow"} <= extras["batch"]
    assert extras["postgres"] == {"psycopg"}
    assert project["optional-dependencies"]["all"] == [
        "metro-inertial[fast,batch,postgres,drivers,dcc,web]"]


def test_distribution_name_and_version():
    from metro.core import __version__
    from metro.core.base.extras import DISTRIBUTION

    assert _project()["name"] == DISTRIBUTION == "metro-inertial"
    assert __version__ == version(DISTRIBUTION) != "0+unknown"


def test_readme_commands_and_ci():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    blocks = [b.split("```", 1)[0].strip() for b in readme.split("```sh\n")[1:3]]
    main_job, tests = blocks
    assert main_job.endswith(
        "metro run --standard gbt45570 --item D.5.6") and "pip install -e . " in main_job
    assert tests == ("python3 -m venv .venv && .venv/bin/pip install -e '.[all,test]' "
                     "&& .venv/bin/python -m pytest")
    assert tests in ci.splitlines()  # verbatim
    assert "libreoffice-writer-nogui poppler-utils fonts-noto-cjk" in " ".join(ci.split())
    for needs in ("libreoffice-writer-nogui poppler-utils", "fonts-noto-cjk",
                  "'metro-inertial[fast]'",
                  "'metro-inertial[batch]'", "'metro-inertial[postgres]'",
                  "pip install metro-inertial"):
        assert needs in readme, needs


def test_require_names_the_extra():
    from metro.core.base.errors import MetroError
    from metro.core.base.extras import available, require

    with pytest.raises(MetroError) as info:
        require("metro_no_such_module_29", "metro frobnicate", extra="batch")
    assert info.value.reason == ("metro frobnicate needs the 'batch' extra: "
                                 "pip install 'metro-inertial[batch]'")
    assert "metro_no_such_module_29 is not installed" in info.value.hint
    assert require("json", "x", extra="fast").dumps([1]) == "[1]"
    assert available("json") and not available("metro_no_such_module_29")


# A process in which the optional packages are not there, as in a core install.
BLOCK = textwrap.dedent("""
    import sys
    BLOCKED = sys.argv[1].split(",")
    for name in BLOCKED:  # "not installed": import fails, importlib.util.find_spec gives None
        sys.modules[name] = None
    from metro.core.cli.app import main
    code = main(sys.argv[2:])
    loaded = sorted(m for m, mod in sys.modules.items()
                    if mod is not None and m.split(".")[0] in BLOCKED)
    assert not loaded, loaded
    sys.exit(code)
""")


def _core_only(tmp_path: Path, *args: str, env: dict | None = None) -> subprocess.CompletedProcess:
    environ = {k: v for k, v in os.environ.items() if not k.startswith("METRO_")} | (env or {})
    return subprocess.run([sys.executable, "-c", BLOCK, ",".join(OPTIONAL), *args],
                          capture_output=True,
                          text=True, cwd=tmp_path, env=environ, timeout=900)


def test_main_job_and_a_recorded_campaign_without_the_extras(tmp_path):
    p = _core_only(tmp_path, "run", "--standard", "gbt45570", "--item", "D.5.6", "--no-progress")
    assert p.returncode == 0, p.stderr
    assert list((tmp_path / "metro-out").glob("*.docx"))
    p = _core_only(tmp_path, "acquire", "-s", "gbt45570", "-i", "D.5.1,D.5.6", "--out", "acq",
                   "--no-progress")
    assert p.returncode == 0, p.stderr
    p = _core_only(tmp_path, "run", "-s", "gbt45570", "-i", "D.5.1,D.5.6", "--data",
                   "acq/manifest.toml",
                   "--no-report", "--json", "--no-progress")
    assert p.returncode == 0, p.stderr
    assert "Traceback" not in p.stderr


def test_batch_without_dask_names_the_extra(tmp_path):
    p = _core_only(tmp_path, "batch", "-s", "gbt45570", "-i", "D.5.6", "--data",
                   "nothing/*/manifest.toml",
                   "--out", "lot")
    assert p.returncode == 2, p.stderr
    assert "metro batch needs the 'batch' extra: pip install 'metro-inertial[batch]'" in p.stderr
    assert not (tmp_path / "lot").exists() and "Traceback" not in p.stderr


def test_postgresql_register_without_psycopg_names_the_extra(tmp_path):
    p = _core_only(tmp_path, "register", "list", env={"METRO_REGISTER": "postgresql://metro:secret@127.0.0.1:1/metro"})
    assert p.returncode == 2, p.stderr
    assert "pip install 'metro-inertial[postgres]'" in p.stderr and "psycopg" in p.stderr
    assert "secret" not in p.stderr and "Traceback" not in p.stderr


def test_parquet_without_pyarrow_names_the_extra(tmp_path):
    data = tmp_path / "x.parquet"
    data.write_bytes(b"PAR1")
    code = textwrap.dedent(f"""
        from metro.core.base.errors import MetroError
        from metro.instruments.readers import read_samples
        try:
            read_samples({str(data)!r})
        except MetroError as exc:
            print(exc.reason)
    """)
    block = BLOCK.split("from metro.core.cli.app")[0]
    p = subprocess.run([sys.executable, "-c", block + code, ",".join(OPTIONAL)],
                       capture_output=True, text=True)
    assert "needs the 'fast' extra: pip install 'metro-inertial[fast]'" in p.stdout, p.stderr

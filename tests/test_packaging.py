"""Packaging: one `metro` namespace in the wheel, entry points, no top-level
core/run/plugin_manager/instruments."""

from __future__ import annotations

import subprocess
import sys
import time
import zipfile
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]


@pytest.fixture(scope="module")
def wheel(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("wheel")
    subprocess.run(
        [sys.executable, "-m", "pip", "wheel", "--no-deps", "--no-build-isolation", "-q", "-w",
         str(out), str(ROOT)],
        check=True, capture_output=True, text=True,
    )
    (whl,) = out.glob("metro_inertial-*.whl")  # the distribution metro-inertial
    return whl


def test_wheel_contains_only_the_metro_namespace(wheel):
    names = zipfile.ZipFile(wheel).namelist()
    top = {n.split("/")[0] for n in names}
    assert {t for t in top if not t.endswith(".dist-info")} == {"metro"}
    assert [t.split("-")[0] for t in top if t.endswith(".dist-info")] == ["metro_inertial"]
    for needed in (
        "metro/api.py", "metro/core/model/hookspec.py", "metro/core/base/units.txt",
        "metro/core/documents/templates/report.docx",
        "metro/core/base/locale/zh/LC_MESSAGES/metro.po",
        "metro/core/base/locale/__init__.py", "metro/core/cli/schemas/run.schema.json",
        "metro/plugins/gbt45570/procedures.py", "metro/plugins/jjf2014/__init__.py",
        "metro/plugins/jjf2003/__init__.py", "metro/instruments/simulated.py",
        # metro validate's reference data (docs/validation.md)
        "metro/core/validation/data/Norris.dat", "metro/core/validation/data/Pontius.dat",
        "metro/core/validation/data/allan_nbs14.json",
    ):
        assert needed in names, needed


def test_wheel_entry_points(wheel):
    z = zipfile.ZipFile(wheel)
    (ep,) = [n for n in z.namelist() if n.endswith("entry_points.txt")]
    text = z.read(ep).decode()
    assert "metro = metro.core.cli.app:main" in text
    assert "gbt45570 = metro.plugins.gbt45570" in text
    assert "instruments = metro.instruments.plugin" in text


def test_help_is_fast_and_imports_nothing_heavy():
    code = ("import sys, time; t=time.perf_counter(); from metro.core.cli.app import main; "
            "import contextlib, io\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    try: main(['--help'])\n"
            "    except SystemExit: pass\n"
            "heavy=[m for m in ('numpy','scipy','pint','docxtpl','matplotlib','numba','pyarrow') "
            "if m in sys.modules]\nprint(heavy)")
    t0 = time.perf_counter()
    out = subprocess.run([sys.executable, "-P", "-c", code], check=True, capture_output=True,
                         text=True)
    assert out.stdout.strip() == "[]"
    # generous for CI; docs/performance.md has the measured figure
    assert time.perf_counter() - t0 < 2.0


def test_wheel_gives_python_dash_m_metro_and_keeps_the_namespace(wheel):
    """`python -m metro`: the wheel has metro/__main__.py (from core/_metro/) and no
    metro/__init__.py, so third-party metro.* packages still join the namespace."""
    names = zipfile.ZipFile(wheel).namelist()
    assert "metro/__main__.py" in names and "metro/__init__.py" not in names
    assert not any(n.startswith("metro/core/_metro") for n in names)
    text = zipfile.ZipFile(wheel).read("metro/__main__.py").decode()
    assert "from metro.core.cli.app import main" in text

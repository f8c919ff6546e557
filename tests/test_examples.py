"""The example vendor distribution (examples/acme-metro-plugin) extends metro without changing it.

In-process tests exercise its item, reader and template through metro's public API; the venv
test pip-installs metro and the example into a fresh virtual environment (no system
site-packages, offline: ``--no-index``, third-party dependencies taken from the running
environment) and drives that environment's ``metro`` command.
"""

from __future__ import annotations

import importlib
import json
import os
import re
import shutil
import subprocess
import sys
import sysconfig
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[1]
EXAMPLE = ROOT / "examples" / "acme-metro-plugin"


@pytest.fixture(scope="module")
def acme():
    sys.path.insert(0, str(EXAMPLE))
    try:
        plugin = importlib.import_module("acme_metro.plugin")
        yield plugin
    finally:
        sys.path.remove(str(EXAMPLE))


def _modules():
    return (
        importlib.import_module("acme_metro.acmefile"),
        importlib.import_module("acme_metro.procedures")
    )


def test_smoothed_std_hand_worked(acme):
    _, proc = _modules()
    # moving averages of 2 over [0, 2, 0, 2, 0]: all 1 → s = 0; over [0, 0, 4, 0]: 0, 2, 2 → s =
    # 2/√3
    assert proc.smoothed_std(np.array([0, 2, 0, 2, 0.0]), 2)[0] == pytest.approx(0.0, abs=1e-12)
    s, m = proc.smoothed_std(np.array([0, 0, 4, 0.0]), 2)
    assert s == pytest.approx(np.std([0, 2, 2], ddof=1), rel=1e-12) and m == 2
    with pytest.raises(ValueError, match="too few"):
        proc.smoothed_std(np.zeros(3), 2)


def test_vendor_item_joins_the_gbt45570_family(acme, metro_pm_factory, simulated_station):
    from metro.core.run.runner import run_items

    _, proc = _modules()
    pm = metro_pm_factory(acme)
    assert pm.procedure("gbt45570", "ACME.BS10") is proc.AcmeBiasStability10s
    assert pm.registry.procedures["gbt45570:ACME.BS10"].plugin == acme.__name__
    assert ".acme" in pm.registry.readers and pm.template_for("acme").name == "acme-certificate"
    # the vendor does not take over GB/T reports
    assert pm.template_for("gbt45570").name != "acme-certificate"
    st = simulated_station(output="rate")
    rec = run_items(pm, "gbt45570", ["ACME.BS10", "D.5.2"], campaign=st.acquire(
        pm.procedure("gbt45570", "ACME.BS10")().sequence({})))
    bs10 = rec.outcomes[0].results[0].value.to("deg/h").magnitude
    d52 = rec.outcomes[1].results[0].value.to("deg/h").magnitude  # D.41 at t = 10 s
    # white rate noise: both estimate arw/√(10 s) (°/h) of the station's device
    assert bs10 == pytest.approx(st.truth.arw_deg_rt_h / np.sqrt(10 / 3600), rel=0.1)
    assert bs10 == pytest.approx(d52, rel=0.1)


def test_acme_reader_round_trip_and_bad_files(acme, tmp_path):
    from metro.core.base.errors import DataError

    f, _ = _modules()
    p = f.write_acme(tmp_path / "x.acme", [1, -2, 3], 0.5)
    t = f.read_acme(p)
    assert t.columns["output"].tolist() == [1.0, -2.0, 3.0] and t.units["output"] == "P"
    assert t.columns["time"].tolist() == [0.5, 1.0, 1.5]
    p.write_bytes(p.read_bytes()[:-2])
    with pytest.raises(DataError, match="announces 3 samples"):
        f.read_acme(p)
    (tmp_path / "y.acme").write_bytes(b"NOTACME" + bytes(40))
    with pytest.raises(DataError, match="not an ACME file"):
        f.read_acme(tmp_path / "y.acme")


def _acme_campaign(root: Path, acmefile) -> Path:
    from metro.instruments.simulated import GyroTruth, simulate_static

    data = simulate_static(GyroTruth(), n=1800, interval_s=1.0, latitude_deg=39.98)
    acmefile.write_acme(root / "static.acme", data, 1.0, "P")
    (root / "manifest.toml").write_text("""\
format = "metro-campaign/1"
[campaign]
id = "ACME-FAT-0042"
[device]
id = "RLG-0042"
manufacturer = "ACME Inertial"
model = "RLG-90"
output = "pulse"
scale_factor = "0.8 P/″"
[environment]
temperature = "20.5 °C"
humidity = "45 %"
[site]
latitude = "39.98°"
[[segments]]
id = "static-1"
kind = "static"
file = "static.acme"
sample_interval = "1 s"
[segments.conditions]
orientation = "IRA up"
""", encoding="utf-8")
    return root / "manifest.toml"


def test_vendor_certificate_on_recorded_binary_data(acme, metro_pm_factory, tmp_path):
    import docx
    from metro.core.documents.report import write_report
    from metro.core.run.runner import run_items

    f, _ = _modules()
    pm = metro_pm_factory(acme)
    rec = run_items(pm, "acme", ["FAT.1"], data=_acme_campaign(tmp_path, f))
    out = write_report(tmp_path / "cert.docx", rec, template=pm.template_for("acme").path,
                       extend=pm.extend_report_context)
    d = docx.Document(str(out))
    text = "\n".join(p.text for p in d.paragraphs)
    assert "ACME Inertial, final test" in text and "AT-7 rev. C" in text
    cells = [c.text for r in d.tables[0].rows for c in r.cells]
    assert "FAT.1" in cells
    assert rec.data_files and rec.data_files[0][0].endswith("static.acme")


def test_vendor_template_is_reproducible(acme):
    import importlib.util

    spec = importlib.util.spec_from_file_location("acme_make", EXAMPLE / "acme_metro" / "templates"
                                                  / "make_template.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    assert mod.build() == (EXAMPLE / "acme_metro" / "templates"
                           / "acme_certificate.docx").read_bytes()


# ----------------------------------------------------------------------- a fresh virtual
# environment

#: what the fresh environment must not inherit from the running one: metro itself (its
#: editable install), the example, and pip's own machinery
_NOT_SHARED = ("metro", "__editable__", "acme", "_acme", "pip", "__pycache__")


def _dependency_overlay(dest: Path) -> Path:
    """A directory of links to the third-party packages installed in the running environment
    (numpy, pint, pluggy, setuptools, …), without metro, the example or any ``.pth`` file.

    The fresh venv sees it through one ``.pth`` line, so installing metro and the example into
    it resolves every dependency offline (``--no-index``) and nothing can come from PyPI —
    neither metro's dependencies nor an unrelated distribution that happens to be called
    "metro".
    """
    dest.mkdir()
    for site in {Path(p) for p in (sysconfig.get_paths()["purelib"],
                                   sysconfig.get_paths()["platlib"])}:
        for entry in site.iterdir():
            low = entry.name.lower()
            if entry.suffix == ".pth" or low.startswith(_NOT_SHARED) or (
                dest / entry.name).exists():
                continue
            (dest / entry.name).symlink_to(entry, target_is_directory=entry.is_dir())
    return dest


def _source_copy(dest: Path) -> Path:
    """metro's source tree as a clean clone has it (the packaging files and the three package
    folders), so building the wheel writes nothing into the working tree."""
    ignore = shutil.ignore_patterns("__pycache__", "*.pyc", "*.egg-info", "build")
    dest.mkdir()
    for name in ("pyproject.toml", "setup.py", "README.md"):
        shutil.copy2(ROOT / name, dest / name)
    for name in ("core", "plugins", "instruments"):
        shutil.copytree(ROOT / name, dest / name, ignore=ignore)
    return dest


def test_installed_next_to_metro_in_a_fresh_venv(tmp_path):
    """`pip install` metro and the example into a new venv (no system site-packages, no
    network: ``--no-index``, dependencies from the running environment's packages), then the
    venv's own ``metro`` lists the plugin and runs its item."""
    venv = tmp_path / "venv"
    subprocess.run([sys.executable, "-m", "venv", "--without-pip", str(venv)], check=True,
                   capture_output=True)
    py = venv / "bin" / "python"
    site = Path(subprocess.run([str(py), "-c",
                                "import sysconfig; print(sysconfig.get_paths()['purelib'])"],
                               check=True, capture_output=True, text=True).stdout.strip())
    (site / "_metro_test_deps.pth").write_text(f"{_dependency_overlay(tmp_path / 'deps')}\n",
                                               encoding="utf-8")
    env = {k: v for k, v in os.environ.items()
           if not k.startswith(("METRO_", "PIP_")) and k not in ("PYTHONPATH", "VIRTUAL_ENV")}
    env["PIP_DISABLE_PIP_VERSION_CHECK"] = "1"
    src = _source_copy(tmp_path / "metro-src")
    example = shutil.copytree(EXAMPLE, tmp_path / "acme-src",
                              ignore=shutil.ignore_patterns("__pycache__", "*.egg-info", "build"))
    # the running pip installs into the venv (--python); metro first, then the example, whose
    # "metro>=0.1" requirement is then met by the metro just installed
    for what in (src, example):
        pip = subprocess.run([sys.executable, "-m", "pip", "--python", str(py), "install", "-q",
                              "--no-index",
                              "--no-build-isolation", "--no-cache-dir", str(what)],
                             capture_output=True, text=True, env=env, cwd=tmp_path, timeout=600)
        assert pip.returncode == 0, (
            f"pip install {what.name}:\n{pip.stdout[-2000:]}{pip.stderr[-3000:]}")
    metro = venv / "bin" / "metro"
    out = subprocess.run([str(metro), "plugins", "--json"], capture_output=True, text=True, env=env,
                         cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    plugins = {p["name"]: p for p in json.loads(out.stdout)["plugins"]}
    assert plugins["acme"]["distribution"] == "acme-metro-plugin" and not plugins["acme"]["builtin"]
    assert plugins["acme"]["standards"] == ["acme"] and plugins["acme"]["items"] == 2
    assert plugins["ogam"]["builtin"]
    out = subprocess.run([str(metro), "run", "-s", "gbt45570", "-i", "ACME.BS10", "--json",
                          "--no-progress",
                          "--no-report"], capture_output=True, text=True, env=env, cwd=tmp_path)
    assert out.returncode == 0, out.stderr
    res = json.loads(out.stdout)["results"]
    assert res[0]["key"] == "Bs_ma10" and res[0]["value"] > 0 and res[0]["U"] > 0
    # both came from the venv (installed copies), not from the repository or the test's environment
    where = subprocess.run([str(py), "-c",
                            "import acme_metro, metro.core; print(acme_metro.__file__); "
                            "print(metro.core.__file__)"], capture_output=True, text=True, env=env,
                           cwd=tmp_path)
    assert where.returncode == 0, where.stderr
    assert all(line.startswith(str(site)) for line in where.stdout.split()), where.stdout


# ----------------------------------------------------------------------- the writing tutorial


def _tutorial_blocks() -> tuple[str, str]:
    text = (ROOT / "docs" / "plugins-writing.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```python\n(.*?)```", text, re.DOTALL)
    plugin = "\n".join(b.split("\n", 1)[1] for b in blocks
                       if b.startswith("# file: demo_metro/plugin.py"))
    tests = [b for b in blocks if b.startswith("# tests/test_demo.py")]
    assert plugin and len(tests) == 1
    return plugin, tests[0]


def test_writing_tutorial_runs(tmp_path):
    """docs/plugins-writing.md: its plugin code is a working plugin and its tests — and the
    example of docs/plugins-testing.md — pass with metro's pytest plugin (run in a subprocess,
    as a plugin author would)."""
    plugin, tests = _tutorial_blocks()
    pkg = tmp_path / "demo_metro"
    pkg.mkdir()
    (pkg / "__init__.py").write_text("", encoding="utf-8")
    (pkg / "plugin.py").write_text(plugin, encoding="utf-8")
    (tmp_path / "test_demo.py").write_text(tests, encoding="utf-8")
    # docs/plugins-testing.md's example tests the same plugin with the same fixtures
    testing_doc = (ROOT / "docs" / "plugins-testing.md").read_text(encoding="utf-8")
    (doc_tests,) = re.findall(r"```python\n(.*?)```", testing_doc, re.DOTALL)
    (tmp_path / "test_testing_doc.py").write_text(doc_tests, encoding="utf-8")
    env = dict(os.environ, PYTHONPATH=str(tmp_path))
    out = subprocess.run([sys.executable, "-m", "pytest", "-q", "-p", "no:cacheprovider",
                          "--rootdir", str(tmp_path),
                          str(tmp_path / "test_demo.py"), str(tmp_path / "test_testing_doc.py")],
                         capture_output=True, text=True, env=env, cwd=tmp_path, timeout=300)
    assert out.returncode == 0, out.stdout[-3000:] + out.stderr[-2000:]
    assert "4 passed" in out.stdout
    # and through the CLI, loaded by METRO_PLUGINS without installing it
    env["METRO_PLUGINS"] = "demo_metro.plugin"
    out = subprocess.run([sys.executable, "-m", "metro.core.cli.app", "run", "-s", "demo", "-i",
                          "4.1", "--json",
                          "--no-report", "--no-progress"], capture_output=True, text=True, env=env,
                         cwd=tmp_path)
    no_main = "No module named metro.core.cli.app.__main__"
    if out.returncode != 0 and no_main in out.stderr:  # pragma: no cover
        pytest.skip("metro.core.cli.app is not runnable with -m")
    assert out.returncode == 0, out.stderr
    assert json.loads(out.stdout)["results"][0]["key"] == "D"

"""Collect, run and describe the validation cases: metro's own (reference data, unit round trips,
JCGM 101, within-U coverage) and those every plugin contributes through the
``metro_validation_cases`` hook; the software they ran on (versions, platform, the SHA-256 of
every installed file of metro and its plugins).
"""

from __future__ import annotations

import datetime as dt
import hashlib
import platform
import sys
import time
from pathlib import Path
from typing import TYPE_CHECKING, Any, Callable, Sequence

import attrs

from ..base.errors import PluginError
from .case import VERDICTS, ValidationCase

if TYPE_CHECKING:  # pragma: no cover
    from ..run.plugin_manager import MetroPluginManager

__all__ = ["CORE", "ValidationRun", "collect", "core_cases", "environment", "installed_files",
           "run_cases"]

#: the name metro's own cases are listed under (beside the plugins' names)
CORE = "metro"

#: packages whose files are metro's (the plugins' are added by name)
METRO_PACKAGES = ("metro.core", "metro.instruments", "metro.plugins")


def core_cases(pm: "MetroPluginManager", *, quick: bool = False) -> list[ValidationCase]:
    """metro's own cases: NIST StRD, the NBS14 Allan values, unit round trips, the JCGM 101
    clause-9 examples and a within-U run per device class of the simulated stations."""
    from .coverage import coverage_cases
    from .jcgm101 import jcgm101_cases
    from .reference import allan_cases, nist_cases, unit_cases

    cases = [*nist_cases(), *allan_cases(), *unit_cases(), *jcgm101_cases(),
             *coverage_cases(pm, quick=quick)]
    return [attrs.evolve(c, plugin=CORE) for c in cases]


def collect(pm: "MetroPluginManager", *, quick: bool = False) -> list[ValidationCase]:
    """Every case: metro's, then each plugin's (by plugin name), each marked with who gave it;
    with ``quick`` only the cases marked ``quick``.  Two cases with one id are an error naming
    both plugins."""
    pm.register_all()
    cases = core_cases(pm, quick=quick)
    caller = pm.pm.hook.metro_validation_cases
    for impl in sorted(caller.get_hookimpls(), key=lambda i: i.plugin_name):
        for c in impl.function() or ():
            if not isinstance(c, ValidationCase):
                raise PluginError(f"plugin {impl.plugin_name!r} returned {type(c).__name__} from "
                                  "metro_validation_cases, not a ValidationCase")
            cases.append(attrs.evolve(c, plugin=impl.plugin_name))
    seen: dict[str, str] = {}
    for c in cases:
        if c.id in seen:
            raise PluginError(f"validation case {c.id!r} given twice: by {seen[c.id]!r} and by "
                              f"{c.plugin!r}")
        seen[c.id] = c.plugin
    return [c for c in cases if c.quick or not quick]


def run_cases(cases: Sequence[ValidationCase],
              progress: Callable[[int, int, ValidationCase], None] | None = None
              ) -> list[ValidationCase]:
    """Run each case in turn; ``progress(i, n, case)`` before each (the case not yet run, its
    verdict None) and after it (the case as run)."""
    out = []
    for i, case in enumerate(cases, 1):
        if progress is not None:
            progress(i, len(cases), case)
        done = case.run()
        out.append(done)
        if progress is not None:
            progress(i, len(cases), done)
    return out


def _version(name: str) -> str:
    from importlib import metadata

    try:
        return metadata.version(name)
    except metadata.PackageNotFoundError:
        return "not installed"


def environment(pm: "MetroPluginManager") -> dict[str, Any]:
    """The software a validation ran on: metro's version, each plugin's, Python, numpy, scipy,
    pint and the platform."""
    from .. import __version__

    return {
        "metro": __version__,
        "plugins": pm.versions(),
        "python": f"{platform.python_implementation()} {platform.python_version()}",
        "libraries": {n: _version(n) for n in ("numpy", "scipy", "pint", "numba")},
        "platform": platform.platform(),
        "machine": platform.machine(),
        "executable": sys.executable,
    }


def _package_root(package: str) -> list[Path]:
    import importlib

    try:
        mod = importlib.import_module(package)
    except ImportError:
        return []
    paths = list(getattr(mod, "__path__", []))
    if paths:
        return [Path(p) for p in paths]
    return [Path(mod.__file__)] if getattr(mod, "__file__", None) else []


def installed_files(pm: "MetroPluginManager") -> list[dict[str, str]]:
    """Every installed file of metro and its plugins (their package folders, or the module file
    of a plugin that is a module; compiled caches left out), with its SHA-256, sorted by path.
    Paths are the package's dotted name, then the path inside it."""
    roots: dict[Path, str] = {}
    for package in (*METRO_PACKAGES, *pm.plugin_packages().values()):
        for root in _package_root(package):
            roots.setdefault(root.resolve(), package)
    for _, obj in pm.pm.list_name_plugin():  # plugins that are a single module
        where = getattr(obj, "__file__", None)
        if where and not hasattr(obj, "__path__"):
            roots.setdefault(Path(where).resolve(), getattr(obj, "__name__", "plugin"))
    files: dict[Path, str] = {}
    for root, package in roots.items():
        if root.is_file():
            files.setdefault(root, f"{package} ({root.name})")
            continue
        for p in sorted(root.rglob("*")):
            if not p.is_file() or "__pycache__" in p.parts or p.suffix in (".pyc", ".nbi", ".nbc"):
                continue
            files.setdefault(p, f"{package}/{p.relative_to(root).as_posix()}")
    out = [{"path": name, "sha256": hashlib.sha256(p.read_bytes()).hexdigest()}
           for p, name in files.items()]
    return sorted(out, key=lambda d: d["path"])


@attrs.frozen
class ValidationRun:
    """One ``metro validate``: the cases as run, when, how long, on what software."""

    cases: tuple[ValidationCase, ...] = attrs.field(converter=tuple)
    started: dt.datetime
    seconds: float
    quick: bool
    environment: dict[str, Any]
    files: tuple[dict[str, str], ...] = attrs.field(converter=tuple)

    @property
    def passed(self) -> bool:
        """Every case passed (and there was at least one)."""
        return bool(self.cases) and all(c.passed for c in self.cases)

    def counts(self) -> dict[str, int]:
        """{verdict: number of cases}."""
        return {v: sum(1 for c in self.cases if c.verdict == v) for v in VERDICTS}

    def failed(self) -> list[ValidationCase]:
        """The cases that failed or raised."""
        return [c for c in self.cases if not c.passed]


def validate(pm: "MetroPluginManager", *, quick: bool = False,
             progress: Callable[[int, int, ValidationCase], None] | None = None,
             collected: Callable[[int], None] | None = None) -> ValidationRun:
    """Collect and run every case (``quick``: the quick ones): a :class:`ValidationRun`.
    ``collected(n)`` is told how many cases will run."""
    started = dt.datetime.now(dt.timezone.utc).replace(microsecond=0)
    t0 = time.perf_counter()
    cases = collect(pm, quick=quick)
    if collected is not None:
        collected(len(cases))
    done = run_cases(cases, progress)
    return ValidationRun(done, started, time.perf_counter() - t0, quick, environment(pm),
                         installed_files(pm))

"""Documentation stays true: every hook documented and tested, docs generated files current."""

from __future__ import annotations

import re
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def _hooks():
    from metro.core.model import hookspec

    return [n for n in dir(hookspec) if n.startswith("metro_")]


def test_hook_reference_is_current(load_tool):
    rendered = load_tool("gen_hook_docs").render()
    assert (ROOT / "docs" / "hooks.md").read_text(encoding="utf-8") == rendered, (
        "docs/hooks.md is stale: run python -P tools/gen_hook_docs.py"
    )


def test_every_hook_is_documented():
    text = (ROOT / "docs" / "hooks.md").read_text(encoding="utf-8")
    for name in _hooks():
        assert f"## `{name}`" in text, name


def test_every_hook_is_implemented_by_the_sample_plugin_and_tested():
    sample = (ROOT / "tests" / "data" / "plugins" / "sample_vendor.py").read_text(encoding="utf-8")
    tests = (ROOT / "tests" / "core" / "run" / "test_plugins.py").read_text(encoding="utf-8")
    for name in _hooks():
        assert f"def {name}(" in sample, f"{name} has no sample implementation"
        assert name in tests, f"{name} is not named in tests/core/run/test_plugins.py"


def test_every_registered_procedure_is_documented_with_its_test():
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    for pid, info in pm.registry.procedures.items():
        std, item = pid.split(":")
        page = ROOT / "docs" / "standards" / f"{std}.md"
        assert page.is_file(), f"no docs page for standard {std}"
        text = page.read_text(encoding="utf-8")
        assert re.search(rf"\b{re.escape(item)}\b", text), f"{pid} missing from {page.name}"
        assert info.cls.__name__ in text, (
            f"{pid}: class {info.cls.__name__} not named in {page.name}")


def _test_sources() -> dict[str, str]:
    """Each top-level test function's source with its decorators (so a parametrize list
    counts), by name: a chunk starts at a top-level line, except inside a decorator before its
    ``def``."""
    out: dict[str, str] = {}
    for f in (ROOT / "tests").rglob("test_*.py"):
        chunks: list[list[str]] = []
        seen_def = False
        for line in f.read_text(encoding="utf-8").splitlines():
            top = bool(line) and not line[0].isspace()
            if top and (seen_def or not chunks or not chunks[-1][0].startswith("@")):
                chunks.append([line])
                seen_def = line.startswith(("def ", "class "))
            elif chunks:
                chunks[-1].append(line)
                seen_def = seen_def or (top and line.startswith("def "))
        for chunk in chunks:
            text = "\n".join(chunk)
            m = re.search(r"^def (test_\w+)\(", text, re.M)
            if m:
                out[m.group(1)] = text
    return out


def test_every_registered_procedure_has_a_reference_test():
    """Each registered procedure's row in its standard's page cites at least one existing test
    that exercises the item: the test (or its parametrize list) names the procedure class, its
    item id in quotes, or one of its metric keys in quotes — a clause → class → test hop that
    holds, not a class name mentioned anywhere."""
    from metro.core.run.plugin_manager import get_plugin_manager

    pm = get_plugin_manager(autoload=False)
    bodies = _test_sources()
    missing = []
    for pid, info in pm.registry.procedures.items():
        std, item = pid.split(":")
        page = (ROOT / "docs" / "standards" / f"{std}.md").read_text(encoding="utf-8")
        cited = {n for line in page.splitlines() if f"`{info.cls.__name__}`" in line
                 for n in re.findall(r"(test_\w+)", line)}
        marks = [info.cls.__name__] + [f"'{x}'" for x in [item]
                                       + [m.key for m in info.cls.metrics]] + \
                [f'"{x}"' for x in [item] + [m.key for m in info.cls.metrics]]
        if not any(n in bodies and any(k in bodies[n] for k in marks) for n in cited):
            missing.append(f"{pid} ({info.cls.__name__}): cites {sorted(cited) or 'no test'}")
    assert not missing, "procedures without a cited reference test: " + "; ".join(missing)


def test_readme_has_the_two_commands_and_ci_runs_the_test_one():
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    blocks = re.findall(r"```sh\n(.*?)\n```", readme, re.S)
    assert len(blocks) >= 2
    run_cmd, test_cmd = blocks[0].strip(), blocks[1].strip()
    assert "metro run" in run_cmd and "pytest" in test_cmd
    ci = (ROOT / ".ci" / "run").read_text(encoding="utf-8")
    assert test_cmd in ci


def test_worked_example_campaign_runs(run_cli):
    import json

    manifest = ROOT / "docs" / "examples" / "campaign" / "manifest.toml"
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.1,D.5.2", "--data", str(manifest),
                             "--json",
                             "--no-report", "--no-progress")
    assert code in (0, 3, 4), err  # evaluated (0 conforms, 3 does not conform, 4 indeterminate)
    doc = json.loads(out)
    b0 = [r for r in doc["results"] if r["key"] == "B0"][0]
    # the example's simulated truth: B0 = 0.12 °/h (+ 0.00007·sin θ); within U
    assert abs(b0["value"] - 0.12) <= b0["U"]


# ----------------------------------------------------------------------- the public plugin API

#: plugin code held to the public API: package name → (folder, the package's dotted name)
_API_CHECKED = {
    "ogam plugin": (ROOT / "plugins" / "ogam", "metro.plugins.ogam"),
    "ogam station": (ROOT / "instruments" / "angle_instrument.py", "metro.instruments"),
    "example vendor plugin": (ROOT / "examples" / "acme-metro-plugin" / "acme_metro", "acme_metro"),
}


def _public_modules() -> list[str]:
    """The first-column modules of the table in docs/plugins-writing.md section 9."""
    text = (ROOT / "docs" / "plugins-writing.md").read_text(encoding="utf-8")
    section = text.split("## 9. What a plugin may import", 1)[1].split("\n## ", 1)[0]
    mods = re.findall(r"^\| `(metro[\w.*<>]*)` \|", section, re.M)
    # metro.api is the one module of metro a plugin imports (its names come from core, listed below
    # it in the table, but are imported from metro.api); a standard's own modules may be reused
    assert mods == ["metro.api", "metro.plugins.<standard>"], mods
    return mods


def _is_public(module: str, public: list[str]) -> bool:
    for p in public:
        if p.endswith(".*") or p.endswith(".<standard>"):
            if module.startswith(p.rsplit(".", 1)[0] + "."):
                return True
        elif module == p:
            return True
    return False


def _metro_imports(path: Path, package: str):
    """(line, module, names) of every import of a metro module in ``path``, relative ones
    resolved."""
    import ast

    tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for a in node.names:
                if a.name.split(".")[0] == "metro":
                    yield node.lineno, a.name, []
        elif isinstance(node, ast.ImportFrom):
            mod = node.module or ""
            if node.level:
                base = package.split(".")
                base = base[: len(base) - (node.level - 1)] if node.level > 1 else base
                mod = ".".join(base + ([mod] if mod else []))
            names = [a.name for a in node.names]
            if mod.split(".")[0] == "metro":
                yield node.lineno, mod, names


def test_plugins_import_only_the_public_api():
    public = _public_modules()
    bad = []
    for what, (where, package) in _API_CHECKED.items():
        files = [where] if where.is_file() else sorted(where.rglob("*.py"))
        assert files, what
        for f in files:
            sub = f.parent.relative_to(where).parts if where.is_dir() else ()
            for line, mod, names in _metro_imports(f, ".".join((package, *sub))):
                own = mod == package or mod.startswith(package + ".")
                if not own and not _is_public(mod, public):
                    bad.append(
                        f"{f.relative_to(ROOT)}:{line}: {mod} is not in the public API table")
                if any(part.startswith("_") for part in mod.split(".")) or any(
                        n.startswith("_") for n in names):
                    bad.append(f"{f.relative_to(ROOT)}:{line}: private name from {mod}: {names}")
    assert not bad, "\n".join(bad)


def test_public_api_check_catches_a_private_import(tmp_path):
    (tmp_path / "p.py").write_text(
        "from metro.core.run.runner import run_items\nfrom metro.core.base.units "
        "import _x\n"
        "from .sibling import thing\n",
        encoding="utf-8",
    )
    got = list(_metro_imports(tmp_path / "p.py", "metro.plugins.zzz"))
    assert [m for _, m, _ in got] == ["metro.core.run.runner", "metro.core.base.units",
                                      "metro.plugins.zzz.sibling"]
    public = _public_modules()
    assert not _is_public("metro.core.run.runner",
                          public) and not _is_public("metro.core.cli.app", public)
    assert not _is_public("metro.core.model.results",
                          public) and not _is_public("metro.core", public)
    assert _is_public("metro.api", public) and _is_public("metro.plugins.gbt45570.formulas", public)


def test_every_test_a_doc_names_exists():
    """A doc that cites `test_x` (alone or as `tests/test_y.py::test_x`) cites a real test."""
    defs = set()
    for f in (ROOT / "tests").rglob("test_*.py"):
        defs |= set(re.findall(r"^\s*def (test_\w+)", f.read_text(encoding="utf-8"), re.M))
    missing = []
    for doc in sorted((ROOT / "docs").rglob("*.md")) + [ROOT / "README.md"]:
        for name in sorted(set(re.findall(r"`(?:[\w/.]*::)?(test_\w+)`",
                                          doc.read_text(encoding="utf-8")))):
            if name not in defs:
                missing.append(f"{doc.relative_to(ROOT)}: {name}")
    assert not missing, missing

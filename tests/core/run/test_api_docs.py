"""The public plugin API (metro.api) and its reference page docs/api.md hold each other to
account: every public name is documented and on the page, the page is what the generator
writes now, every field of every class is explained, and no page of docs/ names something
metro.api does not export."""

from __future__ import annotations

import inspect
import re
from pathlib import Path

import attrs
import pytest
from metro import api

ROOT = Path(__file__).resolve().parents[3]
DOCS = ROOT / "docs"


@pytest.fixture(scope="module")
def gen(load_tool):
    return load_tool("gen_api_docs")


@pytest.fixture(scope="module")
def page() -> str:
    return (DOCS / "api.md").read_text(encoding="utf-8")


def test_the_reference_page_is_what_the_generator_writes(gen, page):
    assert page == gen.render(), "docs/api.md is out of date: run python -P tools/gen_api_docs.py"


@pytest.mark.parametrize("name", sorted(api.__all__))
def test_every_public_name_is_documented_and_on_the_page(gen, page, name):
    doc = gen.doc_of(name)
    assert len(doc.split()) >= 4, f"metro.api.{name} has no documentation"
    kind = gen.kind_of(getattr(api, name))
    heading = {"class": f"### class `{name}`",
               "module": f"### module `{name}`"}.get(kind, f"### `{name}")
    assert heading in page, f"{name} is not in docs/api.md"


def _api_classes(gen):
    public = [(n, getattr(api, n)) for n in sorted(api.__all__)
              if inspect.isclass(getattr(api, n)) and getattr(api,
                                                              n).__module__.startswith("metro")]
    return public + gen.returned_classes()


def test_every_field_of_every_api_class_is_explained(gen, page):
    """Every field of every class of metro.api, and of the classes its functions return, has its
    meaning on the page."""
    missing = [f"{name}.{field}" for name, cls in _api_classes(gen)
               for field, _typ, _default, meaning in gen.field_rows(cls) if not meaning]
    assert not missing, f"fields without documentation: {', '.join(missing)}"
    assert "(undocumented)" not in page


def test_the_classes_a_procedure_builds_and_reads_have_every_field_on_the_page(gen, page):
    """The model's classes are complete with no exception: each attrs field is a row of its
    table with its meaning (what the issue found documented nowhere)."""
    for cls in (api.Result, api.Outcome, api.PlotSpec, api.TableSpec, api.Metric, api.Segment,
                api.Campaign, api.Step, api.Option, api.SegmentRequirement, api.DeviceUnderTest,
                api.Equipment, api.Calibration, api.Series, api.RunContext, api.Applicability,
                api.EquipmentRequirement):
        rows = {r[0]: r for r in gen.field_rows(cls)}
        public = [f.name for f in attrs.fields(cls) if f.init and not f.name.startswith("_")]
        assert set(rows) == set(public), cls.__name__
        for field in public:
            assert rows[field][3], f"{cls.__name__}.{field}"
            assert f"| `{field}` |" in page


def test_the_plot_series_keys_are_those_the_renderer_reads(page):
    """PlotSpec's documentation lists exactly the keys core/documents/plots.py reads."""
    src = (ROOT / "core" / "documents" / "plots.py").read_text(encoding="utf-8")
    read = set(re.findall(r'\bs(?:\.get\(|\[)"(\w+)"', src))
    assert read == {"x", "y", "style", "label", "yerr"}
    doc = inspect.getdoc(api.PlotSpec)
    assert {k for k in re.findall(r'``"(\w+)"``', doc)} >= read
    section = page.split("### class `PlotSpec`")[1].split("\n### ")[0]
    for key in read:
        assert f'``"{key}"``' in section


def test_the_station_protocol_is_what_the_runner_calls():
    """The runner calls ``acquire(steps, progress=…)`` and ``device()``: the protocol says so,
    a built-in station satisfies it, and the hook reference no longer gives the old call."""
    sig = inspect.signature(api.Station.acquire)
    assert list(sig.parameters) == ["self", "steps", "progress"]
    assert sig.parameters["progress"].kind is inspect.Parameter.KEYWORD_ONLY
    assert list(inspect.signature(api.Station.device).parameters) == ["self"]
    runner = (ROOT / "core" / "run" / "runner.py").read_text(encoding="utf-8")
    writer = (ROOT / "core" / "run" / "manifest_writer.py").read_text(encoding="utf-8")
    assert ".acquire(steps, progress=" in runner and ".acquire(steps, progress=" in writer
    hooks = (DOCS / "hooks.md").read_text(encoding="utf-8")
    assert "acquire(procedure, steps, ctx)" not in hooks
    assert "acquire(steps, *, progress=None)" in hooks
    from metro.core.run.plugin_manager import get_plugin_manager

    st = get_plugin_manager(autoload=False).station("simulated").factory(seed=1)
    assert isinstance(st, api.Station) and isinstance(st, api.CheckingStation)


_MENTION = re.compile(r"\bmetro\.api\.([A-Za-z_]\w*)|\bfrom metro\.api import \(?([^)\n]+)")


def _mentions(text: str) -> set[str]:
    names: set[str] = set()
    for m in re.finditer(r"from metro\.api import \(([^)]*)\)", text):
        names |= {w.split(" as ")[0].strip() for w in m.group(1).split(",") if w.strip()}
    for dotted, imported in _MENTION.findall(text):
        if dotted:
            names.add(dotted)
        elif not imported.lstrip().startswith("("):
            names |= {w.split(" as ")[0].strip() for w in imported.split(",") if w.strip()}
    return {n for n in names if re.fullmatch(r"[A-Za-z_]\w*", n)}


def test_the_mention_finder_reads_every_spelling():
    text = ("see `metro.api.Station` and `metro.api.Nope`\n"
            "from metro.api import Q_, Result as R\n"
            "from metro.api import (\n    Campaign,\n    Segment,\n)\n")
    assert _mentions(text) == {"Station", "Nope", "Q_", "Result", "Campaign", "Segment"}


def test_the_docs_name_only_public_names():
    """Every ``metro.api.X`` and ``from metro.api import X`` in docs/ is in metro.api.__all__."""
    bad = []
    for md in sorted(DOCS.rglob("*.md")):
        for name in sorted(_mentions(md.read_text(encoding="utf-8"))):
            if name not in api.__all__:
                bad.append(f"{md.relative_to(ROOT)}: metro.api.{name}")
    assert not bad, "the docs name what metro.api does not export: " + "; ".join(bad)


#: the pages a plugin author reads: every dotted metro name they write must exist
PLUGIN_PAGES = ("plugins-writing.md", "plugins-testing.md", "tutorial-station.md", "api.md")
_FILE_SUFFIXES = {"po", "git", "toml", "md", "py", "txt", "docx", "csv"}


def _resolves(dotted: str) -> bool:
    """Whether ``metro.a.b.c`` is a module, or an attribute path from the longest importable
    module prefix."""
    import importlib

    parts = dotted.split(".")
    for i in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:i]))
        except ImportError:
            continue
        for attr in parts[i:]:
            if not hasattr(obj, attr):
                return False
            obj = getattr(obj, attr)
        return True
    return False


def test_the_plugin_pages_name_only_what_exists():
    """A module or name moved (the layers split core/ in folders) leaves no stale dotted name on
    the pages a plugin author reads: ``metro.core.model.Metric`` there was an ImportError."""
    bad = []
    for page in PLUGIN_PAGES:
        text = (DOCS / page).read_text(encoding="utf-8")
        for dotted in sorted(set(re.findall(r"\bmetro(?:\.[A-Za-z_]\w*)+", text))):
            if dotted.rsplit(".", 1)[-1] in _FILE_SUFFIXES:
                continue  # a file name: metro.po, metro.git
            if not _resolves(dotted):
                bad.append(f"docs/{page}: {dotted}")
        for module, names in _imports(text):
            bad += [f"docs/{page}: from {module} import {n}" for n in names
                    if not _resolves(f"{module}.{n}")]
    assert not bad, "; ".join(bad)


def _imports(text: str) -> list[tuple[str, list[str]]]:
    """``from metro… import a, b as c`` statements of a page: (module, [a, b])."""
    out = []
    for module, names in re.findall(r"^\s*from (metro(?:\.\w+)+) import (\([^)]*\)|[^\n]+)",
                                    text, re.MULTILINE):
        words = [w.split(" as ")[0].strip() for w in names.strip("()").split("#")[0].split(",")]
        out.append((module, [w for w in words if re.fullmatch(r"[A-Za-z_]\w*", w)]))
    return out


def test_the_stale_name_check_catches_a_moved_name():
    """What the plugin-writing tutorial said before the layers: an import that fails now."""
    old = "from metro.core.model import Metric, Option\nfrom metro.api import (\n    Q_,\n)\n"
    assert _imports(old) == [("metro.core.model", ["Metric", "Option"]), ("metro.api", ["Q_"])]
    assert not _resolves("metro.core.model.Metric") and _resolves("metro.core.model.results.Metric")


_FIELDS = '''
class C:
    """Doc naming ``d``."""

    #: the first field,
    #: on two lines
    a: int
    b: float  # an end-of-line comment
    #              continued inside the comment
    # a plain block above c
    # on two lines
    c: str
    d: str = ""
    e: int = 0
'''


def test_the_generator_reads_each_way_a_field_is_documented(gen):
    import ast

    cdef = ast.parse(_FIELDS).body[0]
    docs = gen._statement_docs(cdef.body, gen._comments(_FIELDS))
    assert docs == {"a": "the first field, on two lines",
                    "b": "an end-of-line comment continued inside the comment",
                    "c": "a plain block above c on two lines"}

"""Generate docs/api.md from the docstrings of metro.api (run: python -P tools/gen_api_docs.py).

Every name of ``metro.api.__all__`` gets a section: a class its signature, its docstring, a
table of its fields (attrs fields, or a class's annotated attributes) with type, default and
meaning, and its public methods; a function its signature and docstring; a module its
docstring and the names it exports (a function with its signature and first paragraph, a class
with its fields and methods); a constant its value and its ``#:`` comment.

A field's meaning is read, in this order, from a ``#:`` comment above it, a ``#`` comment at
the end of its line, the ``Attributes`` section of the class docstring, or a mention of the
field as ``name`` in the class docstring ("see above").  A constant, or an object metro does not
define (``hookimpl``), is documented by a ``#: NAME — text`` comment in core/_metro/api.py, or by
a ``#:`` comment above its assignment in the module it comes from.

tests/core/run/test_api_docs.py fails when docs/api.md is out of date or a name is undocumented.
"""

from __future__ import annotations

import ast
import enum
import inspect
import io
import re
import sys
import textwrap
import tokenize
from pathlib import Path
from typing import Any

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "docs" / "api.md"

#: the page's sections: title, and the module prefixes whose names it holds (first match wins)
SECTIONS: tuple[tuple[str, tuple[str, ...]], ...] = (
    ("Hooks", ("metro.core",)),
    ("Procedures: what an item declares", ("metro.core.model.procedure",)),
    ("Campaigns: what an item reads", ("metro.core.model.campaign",)),
    ("Results: what an item returns", ("metro.core.model.results",)),
    ("Stations", ("metro.core.model.station",)),
    ("Uncertainty and conformity", ("metro.core.uncertainty",)),
    ("Formulas", ("metro.core.stats",)),
    ("Units, messages and errors", ("metro.core.base",)),
    ("Documents", ("metro.core.documents",)),
)


# ------------------------------------------------------------------------------- sources


def api_origins() -> dict[str, tuple[str, str]]:
    """Public name → (the module it is imported from, its name there), read from api.py."""
    from metro import api

    tree = ast.parse(Path(api.__file__).read_text(encoding="utf-8"))
    out: dict[str, tuple[str, str]] = {}
    for node in tree.body:
        if isinstance(node, ast.ImportFrom) and node.module:
            for a in node.names:
                out[a.asname or a.name] = (node.module, a.name)
    return out


def _comments(src: str) -> dict[int, tuple[str, bool]]:
    """Line number (1-based) → (comment text, whether the comment is the whole line)."""
    out: dict[int, tuple[str, bool]] = {}
    lines = src.splitlines()
    try:
        for tok in tokenize.generate_tokens(io.StringIO(src).readline):
            if tok.type == tokenize.COMMENT:
                row, col = tok.start
                whole = not lines[row - 1][:col].strip()
                out[row] = (tok.string, whole)
    except (tokenize.TokenError, IndentationError):  # pragma: no cover - a fragment
        pass
    return out


#: a comment line that continues the one above it (its text indented inside the comment)
_CONTINUED = re.compile(r"#\s{2,}\S")


def _comment_above(lineno: int, comments: dict[int, tuple[str, bool]]) -> str:
    """The whole-line comments right above line ``lineno``: its ``#:`` lines, or, when there
    are none, its plain ``#`` lines (up to a line continuing a comment further up)."""
    block: list[str] = []
    row = lineno - 1
    while row in comments and comments[row][1] and not _CONTINUED.match(comments[row][0]):
        block.insert(0, comments[row][0])
        row -= 1
    marked = []
    for line in reversed(block):
        if not line.startswith("#:"):
            break
        marked.insert(0, line[2:].strip())
    if marked:
        return " ".join(marked)
    if block and not any(line.startswith("#:") for line in block):
        return " ".join(line.lstrip("#").strip() for line in block)
    return ""


def _statement_docs(body: list[ast.stmt], comments: dict[int, tuple[str, bool]]) -> dict[str, str]:
    """The comment documentation of each assigned name of ``body`` (see the module docstring)."""
    out: dict[str, str] = {}
    for node in body:
        if isinstance(node, ast.AnnAssign) and isinstance(node.target, ast.Name):
            name = node.target.id
        elif isinstance(node, ast.Assign) and len(node.targets) == 1 and isinstance(
                node.targets[0], ast.Name):
            name = node.targets[0].id
        else:
            continue
        text = _comment_above(node.lineno, comments)
        end = node.end_lineno or node.lineno
        if not text and end in comments and not comments[end][1]:
            parts = [comments[end][0].lstrip("#").strip()]
            row = end + 1  # continued on lines indented inside the comment: "#      more"
            while row in comments and comments[row][1] and _CONTINUED.match(comments[row][0]):
                parts.append(comments[row][0].lstrip("#").strip())
                row += 1
            text = " ".join(p for p in parts if p)
        if text:
            out[name] = text
    return out


def class_comment_docs(cls: type) -> dict[str, str]:
    """Field name → its comment documentation, over the metro classes of ``cls``'s MRO."""
    out: dict[str, str] = {}
    for klass in reversed(cls.__mro__):
        if not klass.__module__.startswith("metro"):
            continue
        try:
            src = textwrap.dedent(inspect.getsource(klass))
        except (OSError, TypeError):  # pragma: no cover
            continue
        tree = ast.parse(src)
        cdef = tree.body[0]
        if isinstance(cdef, ast.ClassDef):
            out.update(_statement_docs(cdef.body, _comments(src)))
    return out


def docstring_attributes(doc: str) -> dict[str, str]:
    """The numpy-style ``Attributes`` section of a docstring: name → text."""
    m = re.search(r"^Attributes\n-+\n(.*?)(?:\n\S[^\n]*\n-+\n|\Z)", doc, re.DOTALL | re.MULTILINE)
    if not m:
        return {}
    out: dict[str, str] = {}
    name = None
    for line in m.group(1).splitlines():
        head = re.match(r"^(\w+)\s*:", line)
        if head:
            name = head.group(1)
            out[name] = ""
        elif name and line.strip():
            out[name] = (out[name] + " " + line.strip()).strip()
    return out


def module_data_doc(module: str, name: str) -> str:
    """The ``#:`` comment above ``name``'s assignment in ``module`` ('' when there is none)."""
    import importlib

    try:
        src = inspect.getsource(importlib.import_module(module))
    except (OSError, TypeError, ImportError):  # pragma: no cover
        return ""
    return _statement_docs(ast.parse(src).body, _comments(src)).get(name, "")


def api_comment_docs() -> dict[str, str]:
    """``#: NAME — text`` comments of core/_metro/api.py (continued on further ``#:`` lines)."""
    from metro import api

    out: dict[str, str] = {}
    name = None
    for line in Path(api.__file__).read_text(encoding="utf-8").splitlines():
        m = re.match(r"^#: (\w+) — (.*)$", line)
        if m:
            name = m.group(1)
            out[name] = m.group(2).strip()
        elif name and line.startswith("#:"):
            out[name] += " " + line[2:].strip()
        else:
            name = None
    return out


# ------------------------------------------------------------------------------- values


def _ann(a: Any) -> str:
    if a is inspect.Parameter.empty:
        return ""
    if isinstance(a, str):
        return a
    if hasattr(a, "__forward_arg__"):  # a NamedTuple's field under ``from __future__``
        return str(a.__forward_arg__)
    return getattr(a, "__name__", None) or repr(a).replace("typing.", "")


def _value(v: Any) -> str:
    """A default value as source text, never with a memory address."""
    import attrs

    if v is attrs.NOTHING:
        return "…"
    if isinstance(v, attrs.Factory):  # type: ignore[arg-type]
        f = v.factory
        return f"{getattr(f, '__qualname__', type(f).__name__)}()"
    if isinstance(v, enum.Enum):
        return f"{type(v).__name__}.{v.name}"
    if inspect.isclass(v) or inspect.isfunction(v):
        return v.__qualname__
    text = repr(v)
    if " at 0x" in text or len(text) > 60:
        return f"{type(v).__name__}(…)"
    return text


def signature(obj: Any) -> str:
    """``(a: int, *, b: str = 'x') -> T`` with annotations as written (no quotes added)."""
    try:
        sig = inspect.signature(obj)
    except (TypeError, ValueError):
        return "(…)"
    parts: list[str] = []
    star = False
    for p in sig.parameters.values():
        if p.name in ("self", "cls"):
            continue
        text = p.name
        if p.kind is p.VAR_POSITIONAL:
            text, star = "*" + text, True
        elif p.kind is p.VAR_KEYWORD:
            text = "**" + text
        elif p.kind is p.KEYWORD_ONLY and not star:
            parts.append("*")
            star = True
        ann = _ann(p.annotation)
        if ann:
            text += f": {ann}"
        if p.default is not p.empty:
            text += (" = " if ann else "=") + _value(p.default)
        parts.append(text)
    ret = _ann(sig.return_annotation)
    shown = bool(ret) and not inspect.isclass(obj)
    return f"({', '.join(parts)})" + (f" -> {ret}" if shown else "")


def _cell(text: str) -> str:
    return " ".join(text.split()).replace("|", "\\|")


# ------------------------------------------------------------------------------- classes


def field_rows(cls: type) -> list[tuple[str, str, str, str]]:
    """(name, type, default, meaning) of every field of ``cls``: attrs fields, else its
    annotated class attributes.  Private fields (``_name``, not in ``__init__``) are left out."""
    import attrs

    comments = class_comment_docs(cls)
    doc = inspect.getdoc(cls) or ""
    attributes = docstring_attributes(doc)
    rows = []
    if attrs.has(cls):
        fields = [(f.name, _ann(f.type), "required" if f.default is attrs.NOTHING else _value(
            f.default)) for f in attrs.fields(cls) if f.init and not f.name.startswith("_")]
    else:
        fields = []
        seen: set[str] = set()
        for klass in reversed(cls.__mro__):
            if not klass.__module__.startswith("metro") or klass.__name__ in (
                "Protocol", "Generic"):
                continue
            for name, ann in vars(klass).get("__annotations__", {}).items():
                if name.startswith("_") or name in seen:
                    continue
                seen.add(name)
                default = (getattr(cls, "_field_defaults", {}).get(name, attrs.NOTHING)
                           if issubclass(cls, tuple) else getattr(cls, name, attrs.NOTHING))
                fields.append((name, _ann(ann), "required" if default is attrs.NOTHING
                               else _value(default)))
    for name, typ, default in fields:
        meaning = comments.get(name) or attributes.get(name) or (
            "see the description above" if f"``{name}``" in doc else "")
        rows.append((name, typ, default, meaning))
    return rows


def _members(cls: type) -> list[tuple[str, Any]]:
    """The public methods and properties of ``cls`` that metro defines (inherited ones too)."""
    import attrs

    fields = {f.name for f in attrs.fields(cls)} if attrs.has(cls) else set()
    out: dict[str, Any] = {}
    for klass in reversed(cls.__mro__):
        if not klass.__module__.startswith("metro"):
            continue
        for name, val in vars(klass).items():
            if name.startswith("_") or name in fields:
                continue
            if isinstance(val, (staticmethod, classmethod)):
                val = val.__func__
            if inspect.isfunction(val) or isinstance(val, property):
                out[name] = val
    return sorted(out.items(), key=lambda kv: _line(kv[1]))


def _line(obj: Any) -> int:
    fn = obj.fget if isinstance(obj, property) else obj
    try:
        return inspect.getsourcelines(fn)[1]
    except (OSError, TypeError):  # pragma: no cover
        return 0


def render_class(name: str, cls: type) -> list[str]:
    """The section of one class."""
    lines = [f"### class `{name}`", ""]
    if issubclass(cls, BaseException):
        lines += [f"`{name}({', '.join(b.__name__ for b in cls.__bases__)})` — an exception", ""]
    elif not issubclass(cls, enum.Enum) and "Protocol" not in [b.__name__ for b in cls.__mro__]:
        lines += ["```python", f"{name}{signature(cls)}", "```", ""]
    lines += [inspect.getdoc(cls) or "", ""]
    if issubclass(cls, enum.Enum):
        lines += ["| member | value |", "|---|---|"]
        lines += [f"| `{m.name}` | `{m.value!r}` |" for m in cls] + [""]
        return lines
    rows = field_rows(cls)
    if rows:
        lines += ["| field | type | default | meaning |", "|---|---|---|---|"]
        lines += [f"| `{n}` | `{_cell(t)}` | `{_cell(d)}` | {_cell(m) or '(undocumented)'} |"
                  for n, t, d, m in rows] + [""]
    for mname, member in _members(cls):
        if isinstance(member, property):
            head = f"`{name}.{mname}` (property)"
            doc = inspect.getdoc(member) or ""
        else:
            head = f"`{name}.{mname}{signature(member)}`"
            doc = inspect.getdoc(member) or ""
        lines += [f"* {head}" + (" — " + textwrap.indent(doc, "  ").lstrip() if doc else ""), ""]
    return lines


# ------------------------------------------------------------------------------- the page


def kind_of(obj: Any) -> str:
    """``class``, ``function``, ``module`` or ``data`` (anything metro does not define is data)."""
    if inspect.ismodule(obj):
        return "module"
    defined_here = str(getattr(obj, "__module__", "") or "").startswith("metro")
    if inspect.isclass(obj) and defined_here:
        return "class"
    if callable(obj) and defined_here and (inspect.isfunction(obj) or inspect.isbuiltin(obj)):
        return "function"
    return "data"


def data_doc(name: str, origins: dict[str, tuple[str, str]]) -> str:
    """A constant's documentation: api.py's ``#: NAME — …`` comment, else its module's."""
    own = api_comment_docs().get(name, "")
    if own:
        return own
    module, orig = origins.get(name, ("", name))
    return module_data_doc(module, orig) if module else ""


def doc_of(name: str) -> str:
    """The documentation of a public name, as docs/api.md shows it ('' when it has none)."""
    from metro import api

    obj = getattr(api, name)
    if kind_of(obj) == "data":
        return data_doc(name, api_origins())
    return inspect.getdoc(obj) or ""


def render_name(name: str, obj: Any, origins: dict[str, tuple[str, str]]) -> list[str]:
    """The section of one public name."""
    kind = kind_of(obj)
    if kind == "class":
        return render_class(name, obj)
    if kind == "function":
        return [f"### `{name}{signature(obj)}`", "", inspect.getdoc(obj) or "", ""]
    if kind == "module":
        lines = [f"### module `{name}`", "", f"`metro.api.{name}` is `{obj.__name__}`.", "",
                 inspect.getdoc(obj) or "", ""]
        return lines + render_module_members(name, obj)
    text = _value(obj) if not callable(obj) else type(obj).__name__
    return [f"### `{name}`", "", f"`{name} = {text}`" if not callable(obj) else "",
            "", data_doc(name, origins), ""]


def _first_paragraph(obj: Any) -> str:
    return " ".join((inspect.getdoc(obj) or "").split("\n\n")[0].split())


def render_module_members(name: str, module: Any) -> list[str]:
    """The names a module of ``metro.api`` exports: each function its signature and the first
    paragraph of its docstring, each class its signature, docstring, field table and methods (a
    class of :data:`RETURNED` points to its section there), each constant its ``#:`` comment."""
    returned = {cls for _, cls in returned_classes()}
    lines: list[str] = []
    for n in (n for n in getattr(module, "__all__", ()) if not n.startswith("_")):
        member = getattr(module, n, None)
        if inspect.isfunction(member):
            lines += [f"#### `{name}.{n}{signature(member)}`", "", _first_paragraph(member), ""]
        elif inspect.isclass(member):
            lines += [f"#### class `{name}.{n}`", ""]
            if member in returned:
                lines += [f"See [`{n}`](#class-{n.lower()}) under Classes the API returns.", ""]
                continue
            if not issubclass(member, enum.Enum):
                lines += ["```python", f"{n}{signature(member)}", "```", ""]
            lines += [inspect.getdoc(member) or "", ""]
            rows = field_rows(member)
            if rows:  # a field without a comment of its own is told of in the description
                lines += ["| field | type | default | meaning |", "|---|---|---|---|"]
                lines += [f"| `{f}` | `{_cell(t)}` | `{_cell(d)}` | "
                          f"{_cell(m) or 'see the description above'} |" for f, t, d, m in rows]
                lines += [""]
            for mname, meth in _members(member):
                head = (f"`{n}.{mname}` (property)" if isinstance(meth, property)
                        else f"`{n}.{mname}{signature(meth)}`")
                first = _first_paragraph(meth.fget if isinstance(meth, property) else meth)
                lines += [f"* {head}" + (f" — {first}" if first else "")]
            lines += [""]
        else:
            doc = " ".join(module_data_doc(module.__name__, n).split())
            lines += [f"* `{name}.{n}`" + (f" — {doc}" if doc else ""), ""]
    return lines


def section_of(name: str, obj: Any, origins: dict[str, tuple[str, str]]) -> str:
    """The title of the section ``name`` belongs in (by the module it is imported from)."""
    module = origins.get(name, ("", name))[0]
    if inspect.ismodule(obj):
        module = obj.__name__
    best = ""
    title = SECTIONS[-1][0]
    for t, prefixes in SECTIONS:
        for p in prefixes:
            if (module == p or module.startswith(p + ".")) and len(p) > len(best):
                best, title = p, t
    return title


_ORDER = {"class": 0, "function": 1, "data": 2, "module": 3}

#: classes a plugin reads but does not build or import: what API functions and properties
#: return (``decide`` a Verdict, ``report_pair`` Reported values, ``fit_sine`` a SineFit,
#: ``excursion_lobes`` Lobes, ``Campaign.people`` People …), by defining module
RETURNED: tuple[tuple[str, str], ...] = (
    ("metro.core.uncertainty.conformity", "Verdict"),
    ("metro.core.uncertainty.conformity", "Status"),
    ("metro.core.uncertainty.conformity", "DecisionRule"),
    ("metro.core.uncertainty.budget", "Reported"),
    ("metro.core.stats.sinefit", "SineFit"),
    ("metro.core.stats.settling", "Lobe"),
    ("metro.core.base.vocabulary", "People"),
    ("metro.core.base.vocabulary", "Lab"),
    ("metro.core.base.vocabulary", "Customer"),
)


def returned_classes() -> list[tuple[str, type]]:
    """The :data:`RETURNED` classes, imported."""
    import importlib

    return [(name, getattr(importlib.import_module(module), name)) for module, name in RETURNED]


def render() -> str:
    """docs/api.md."""
    from metro import api

    origins = api_origins()
    by_section: dict[str, list[str]] = {t: [] for t, _ in SECTIONS}
    for name in api.__all__:
        by_section[section_of(name, getattr(api, name), origins)].append(name)
    lines = [
        "# Plugin API reference (`metro.api`)",
        "",
        "Generated from the docstrings of `metro.api` by `tools/gen_api_docs.py`; do not edit.",
        "",
        inspect.getdoc(api) or "",
        "",
        "Contents: " + ", ".join(f"[{t}](#{_anchor(t)})" for t, _ in SECTIONS if by_section[t])
        + ", [Classes the API returns](#classes-the-api-returns).",
        "",
    ]
    for title, _ in SECTIONS:
        names = by_section[title]
        if not names:
            continue
        names.sort(key=lambda n: (_ORDER[kind_of(getattr(api, n))], n.lower()))
        lines += [f"## {title}", ""]
        for n in names:
            lines += render_name(n, getattr(api, n), origins)
    lines += ["## Classes the API returns", "",
              ("What a plugin reads but neither builds nor imports: the values API functions and "
               "properties return. Their fields are part of the contract like those above."), ""]
    for name, cls in returned_classes():
        lines += render_class(name, cls)
    text = "\n".join(lines)
    return re.sub(r"\n{3,}", "\n\n", text).rstrip() + "\n"


def _anchor(title: str) -> str:
    return re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")


if __name__ == "__main__":
    OUT.write_text(render(), encoding="utf-8")
    sys.stdout.write(f"wrote {OUT}\n")

"""Generate docs/hooks.md from the hookspec docstrings (run: python -P tools/gen_hook_docs.py).

tests/test_docs.py fails when docs/hooks.md is out of date or a hook is undocumented.
"""

from __future__ import annotations

import inspect
import sys
from pathlib import Path


def render() -> str:
    from metro.core.model import hookspec

    src = inspect.getsource(hookspec)
    names = [n for n in dir(hookspec) if n.startswith("metro_")]
    names.sort(key=lambda n: src.index(f"def {n}("))
    lines = [
        "# Hook reference",
        "",
        "Generated from `core/model/hookspec.py` by `tools/gen_hook_docs.py`; do not edit by hand.",
        "",
        inspect.getdoc(hookspec) or "",
        "",
    ]
    for n in names:
        fn = getattr(hookspec, n)
        sig = str(inspect.signature(fn)).replace("'", "")
        opts = fn.metro_spec if hasattr(fn, "metro_spec") else {}
        lines += [f"## `{n}`", "", f"```python\n@hookimpl\ndef {n}{sig}\n```", ""]
        if opts.get("firstresult"):
            lines += ["*firstresult*: the first non-None answer is used.", ""]
        lines += [inspect.getdoc(fn) or "", ""]
    return "\n".join(lines).rstrip() + "\n"


if __name__ == "__main__":
    out = Path(__file__).resolve().parents[1] / "docs" / "hooks.md"
    out.write_text(render(), encoding="utf-8")
    sys.stdout.write(f"wrote {out}\n")

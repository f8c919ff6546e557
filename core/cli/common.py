"""What the commands of the command line share: the exit codes, reading ``--item`` and
``--option``, the plugin manager, resolving standard and item ids, the progress display.

Below :mod:`metro.core.cli.app` and the command modules (batch, doctor, register_commands),
which import it; it imports none of them.  Like them, nothing heavy is imported at module level.
"""

from __future__ import annotations

import sys
from collections.abc import Sequence
from typing import Any

#: Exit codes (README "Exit codes"; scripts may rely on them):
EXIT_OK = 0  # done; the results conform, or there was nothing to judge (no specification)
# 1 is left to Python: an uncaught exception (a bug in metro or a plugin) exits 1 with a traceback,
# so a crash can never be read as a verdict
EXIT_USER_ERROR = 2  # usage or data error: nothing was evaluated, nothing partial written
EXIT_NONCONFORMING = 3  # done; the overall statement is "does not conform" (a verdict fails)
EXIT_INDETERMINATE = 4  # done; nothing fails but a verdict is indeterminate (conformity not shown)
EXIT_CAMPAIGN_FAILED = 5  # `metro batch`: at least one campaign could not be evaluated (listed)
EXIT_CHECK_FAILED = 6  # a check found a problem: `register verify` (a report file differs or is
# missing), `doctor` (a required check fails)
EXIT_INTERRUPTED = 130  # Ctrl-C (128 + SIGINT)
EXIT_BROKEN_PIPE = 141  # the reader of stdout went away (128 + SIGPIPE), e.g. `metro plan … | head`


def exit_code_for(overall: str | None) -> int:
    """The exit code of a finished evaluation from its overall conformity status
    (``pass``/``fail``/``indeterminate``, None when nothing was judged)."""
    codes = {"fail": EXIT_NONCONFORMING, "indeterminate": EXIT_INDETERMINATE}
    return codes.get(overall or "", EXIT_OK)


def split_items(values: Sequence[str]) -> list[str]:
    """``-i A,B -i C`` as ``[A, B, C]``."""
    out: list[str] = []
    for v in values:
        out.extend(x.strip() for x in v.split(",") if x.strip())
    return out


def parse_options(values: Sequence[str]) -> dict[str, Any]:
    """``-o NAME=VALUE`` (repeated) as ``{NAME: VALUE}``, the values as text."""
    from ..base.errors import MetroError

    out: dict[str, Any] = {}
    for v in values:
        if "=" not in v:
            raise MetroError(f"option {v!r} is not NAME=VALUE")
        k, val = v.split("=", 1)
        out[k.strip()] = val.strip()
    return out


def plugin_manager(args: Any) -> Any:
    """The plugin manager the command line asks for (--no-plugin-autoload, --block-plugin)."""
    from ..run.plugin_manager import get_plugin_manager

    return get_plugin_manager(autoload=False if args.no_plugin_autoload else None,
                              block=args.block_plugin)


def did_you_mean(word: str, choices: Sequence[str]) -> str:
    """ "; did you mean 'X'?" for the closest of ``choices`` (case-insensitive), else ""."""
    import difflib

    low = {c.lower(): c for c in choices}
    close = difflib.get_close_matches(word.lower(), list(low), n=1, cutoff=0.6)
    return f"; did you mean {low[close[0]]!r}?" if close else ""


def resolve_standard(pm, name: str) -> str:
    """A standard id as registered, from any case or with its punctuation (``GBT45570``,
    ``gb/t 45570``); an unknown one is an error that suggests the closest loaded standard."""
    import re

    from ..base.errors import PluginError

    stds = sorted(pm.register_all().standards)
    if name in stds:
        return name

    def key(x: str) -> str:
        return re.sub(r"[^0-9a-z]", "", x.lower())

    for s in stds:
        if key(s) == key(name):
            return s
    raise PluginError(f"unknown standard {name!r}{did_you_mean(name, stds)}; "
                      f"loaded: {', '.join(stds) or 'none'}",
                      hint="`metro plugins` lists the loaded plugins; "
                      "`metro items` lists every item")


def resolve_items(pm, standard: str | None, names: Sequence[str]) -> tuple[str, list[str]]:
    """(standard, item and series ids as registered) from what the user typed: ids in any case,
    ``std:item`` as `metro items` prints them (the standard then may be left out).  An unknown
    one is an error with the closest id and the list of the standard's items."""
    from ..base.errors import MetroError, PluginError
    from ..run.plugin_manager import item_sort_key

    std = resolve_standard(pm, standard) if standard else None
    plain: list[str] = []
    for n in names:
        if ":" in n:
            pre, n = n.split(":", 1)
            s2 = resolve_standard(pm, pre)
            if std is not None and s2 != std:
                raise MetroError(f"item {pre}:{n} belongs to {s2}, not to --standard {std}",
                                 hint="give items of one standard per run")
            std = s2
        plain.append(n)
    if std is None:
        raise MetroError("no --standard given",
                         hint="e.g. --standard gbt45570, or write items as gbt45570:D.5.6 "
                         "(`metro items` lists them)")
    reg = pm.register_all()
    items = sorted((c.item for c in pm.procedures_of(std)), key=item_sort_key)
    series = sorted(ser.name for ser in reg.series.values() if ser.standard == std)
    known = {x.lower(): x for x in items + series}
    out = []
    for n in plain:
        if n in items or n in series:
            out.append(n)
        elif n.lower() in known:
            out.append(known[n.lower()])
        else:
            also = f"; its series: {', '.join(series)}" if series else ""
            close = did_you_mean(n, items + series)
            raise PluginError(f"standard {std!r} has no item {n!r}{close}; "
                              f"its items: {', '.join(items)}{also}",
                              hint=f"`metro items --standard {std}` lists the items "
                              "with their options")
    return std, out


def requested_items(pm, args) -> list[str]:
    """The item and series ids of ``--standard``/``--item`` (``resolve_items``, which also sets
    ``args.standard``); none without ``--all`` is an error.  Shared by run, plan and batch."""
    from ..base.errors import MetroError

    args.standard, items = resolve_items(pm, args.standard, split_items(args.item))
    if not items and not args.run_all:
        raise MetroError("no item given",
                         hint="use --item, e.g. --item D.5.6, a series name, or --all")
    return items


def show_progress(args: Any) -> bool:
    """Whether to draw the progress display: on a terminal, unless --no-progress or --quiet."""
    quiet = getattr(args, "no_progress", False) or getattr(args, "quiet", False)
    return not quiet and sys.stderr.isatty()

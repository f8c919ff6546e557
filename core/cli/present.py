"""Terminal and JSON presentation of a run record (rich tables, progress bars)."""

from __future__ import annotations

import contextlib
import math
from pathlib import Path
from typing import Any, Callable, Iterator

from ..model.provenance import RunRecord
from ..model.record_json import record_document as as_json, truth_checks
from ..base.formatting import fmt_dof, fmt_num, fmt_quantity, pretty_powers, with_unit
from ..base.units import fmt_unit


#: progress events with these task names count towards the overall bar (core.runner, core.batch)
OVERALL_TASKS = ("segments", "items", "campaigns")


@contextlib.contextmanager
def progress(enabled: bool = True, started: Callable[[], None] | None = None,
             console: Any = None) -> Iterator[Any]:
    """A ``progress(task, done, total)`` callback for a terminal: two lines on stderr, no more —
    one overall bar (the ``segments``/``items``/``campaigns`` events summed: done of total, elapsed,
    remaining) and the current step (the latest other task, with its own fraction). The display is
    removed at the end; ``console`` is rich's (default: stderr). ``started`` is called at the first
    event (the banner of a simulated run), also when the display is disabled. Disabled: no output at
    all."""
    first = [started]

    def start() -> None:
        if first[0] is not None:
            first[0]()
            first[0] = None

    if not enabled:
        if started is None:
            yield None
            return

        def quiet(task: str, done: float, total: float) -> None:
            start()

        yield quiet
        return
    from rich.console import Console
    from rich.progress import (BarColumn, Progress, TextColumn, TimeElapsedColumn,
                               TimeRemainingColumn)
    from rich.table import Column

    console = console or Console(stderr=True)
    width = max(20, console.width - 60)
    bar = Progress(TextColumn("{task.description}", table_column=Column(no_wrap=True, width=width)),
                   BarColumn(bar_width=20), TextColumn("{task.fields[count]}",
                                                       table_column=Column(no_wrap=True)),
                   TimeElapsedColumn(), TimeRemainingColumn(), console=console, transient=True)
    counts: dict[str, list[float]] = {}
    state: dict[str, Any] = {"overall": None, "step": None}

    def clip(text: str) -> str:
        return text if len(text) <= width else text[: width - 1] + "…"

    def update(task: str, done: float, total: float) -> None:
        start()
        if task in OVERALL_TASKS:
            counts[task] = [float(done), float(total)]
            d = sum(c[0] for c in counts.values())
            t = sum(c[1] for c in counts.values()) or 1
            text = ", ".join(f"{int(c[0])}/{int(c[1])} {k}" for k, c in counts.items() if c[1])
            if state["overall"] is None:
                state["overall"] = bar.add_task("overall", total=t, count="")
            bar.update(state["overall"], completed=d, total=t, description=clip("overall"),
                       count=text)
            return
        if state["step"] is None:
            state["step"] = bar.add_task("", total=1, count="")
        frac = f"{100 * done / total:5.1f}%" if total else ""
        bar.update(state["step"], description=clip(task), completed=done, total=total or 1,
                   count=frac)

    update.display = bar  # type: ignore[attr-defined]  # for tests: the rich Progress and its tasks
    with bar:
        yield update


OVERALL_TEXT = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate"}


def verdict_line(assessment: Any) -> str:
    """The overall statement with its counts: ``does not conform: 17 pass, 2 fail, 6
    indeterminate``."""
    if assessment is None or assessment.overall is None:
        return "not judged: no specification applies to these results"
    c = assessment.counts()
    line = f"{OVERALL_TEXT[assessment.overall.value]}: " + ", ".join(
        f"{c[k]} {k}" for k in ("pass", "fail", "indeterminate") if c.get(k))
    if assessment.not_assessed:
        line += f"; {len(assessment.not_assessed)} not assessed (items not run)"
    return line + f" ({assessment.rule.name} rule)"


def print_record(record: RunRecord, report_path: Path | None, *, verbose: bool = False,
                 pdf_path: Path | None = None) -> None:
    """The run on the terminal: one results table (with each result's verdict), warnings, the
    overall verdict line and where the report went (``pdf_path``: the PDF written beside a Word
    report, ``--pdf``); ``verbose`` adds item selection, budgets, tables, truth checks, the
    conformity reasons and the data files' SHA-256."""
    from rich.console import Console
    from rich.markup import escape as esc  # messages and file names are text, not markup

    con = Console(highlight=False)
    c = record.campaign
    con.print(f"[bold]{record.standard}[/] on {esc(c.device.describe())} — campaign "
              f"{esc(str(c.id))} ({esc(str(c.source))})")
    _print_selection(con, record, verbose)
    withheld = _print_results(con, record)
    from ..documents.notes import group_notes

    for where, reason in (group_notes(withheld) if len(withheld) > 1 else ()):
        con.print(f"[yellow]not reportable ({esc(where)}):[/] {esc(pretty_powers(str(reason)))}")
    if verbose:
        for o in record.outcomes:
            _print_budgets_and_tables(con, o)
    _print_warnings(con, record)
    _print_simulated(con, record, verbose)
    a = record.conformity
    _print_conformity(con, a, verbose)
    if verbose:
        for f, h in record.data_files:
            con.print(f"data: {esc(str(f))}  sha256 {h}")
    overall = a.overall.value if a is not None and a.overall is not None else None
    style = VERDICT_COLOUR.get(overall or "", "bold")
    # one line: scripts grep it
    con.print(f"[bold {style}]{esc(verdict_line(a))}[/]", soft_wrap=True)
    # the kind of document by its file name (a --report PATH ending in .pdf is a PDF, .xml a DCC)
    if report_path:
        suffix = Path(report_path).suffix.lower()
        kind = {".pdf": "PDF report", ".xml": "DCC"}.get(suffix, "Word report")
        also = (
            f" and PDF {esc(str(pdf_path))}" if pdf_path is not None and kind != "PDF report"
            else ""
        )
        con.print(f"report number {record.report_number}: {kind} {esc(str(report_path))}{also}",
                  soft_wrap=True)
    else:  # --no-report: no document, so no number either
        con.print("no report written", soft_wrap=True)




#: the colour of each verdict on the terminal
VERDICT_COLOUR = {"pass": "green", "fail": "red", "indeterminate": "yellow"}


def _print_selection(con: Any, record: RunRecord, verbose: bool) -> None:
    """Which candidate items ran (all of them with ``verbose``; else only how many did not)."""
    from rich.markup import escape as esc

    if record.selection:
        ran = sum(1 for ch in record.selection if ch.run)
        if verbose:
            for ch in record.selection:
                mark = "[green]run[/]" if ch.run else "[dim]not run[/]"
                con.print(f"  {ch.item} ({esc(str(ch.via))}): {mark} — {esc(str(ch.reason))}")
        elif ran < len(record.selection):
            con.print(f"{ran} of {len(record.selection)} candidate items run; not run: "
                      + ", ".join(ch.item for ch in record.selection if not ch.run)
                      + " (--verbose says why)")


def _print_results(con: Any, record: RunRecord) -> list[tuple[str, str, Any]]:
    """The results table; returns (item, symbol, reason) of the results not reportable."""
    from rich.markup import escape as esc
    from rich.table import Table

    from ..documents.context import monte_carlo_interval

    colour = VERDICT_COLOUR
    verdicts: dict[tuple[str, str], Any] = {}
    if record.conformity is not None:
        for v in record.conformity.verdicts:
            verdicts[(v.item, v.key)] = v
    t = Table(title="Results", title_justify="left")
    # (item, symbol, reason) of the results not reportable: one says why in its row; several, below
    # the table, a reason (or a part of one) they share stated once (core.notes.group_notes) (a
    # result that states a bound says why in its own row: it is issued as the bound)
    withheld: list[tuple[str, str, Any]] = [(o.item, r.metric.symbol, r.reason) for o
                                            in record.outcomes
                                            for r in o.results if not r.reportable and not r.bound]
    for col in ("item", "quantity", "value", "U (k)", "unit", "verdict / note"):
        t.add_column(col, justify="right" if col in ("value", "U (k)") else "left",
                     overflow="fold", no_wrap=col in ("value", "U (k)"))
    for o in record.outcomes:
        for r in o.results:
            v, U = r.reported()
            if U is not None:
                u_text = f"{U} ({r.k:.2f})" if r.k else U
            else:
                u_text = f"u = {fmt_num(float(r.u.magnitude), 2)}" if r.u is not None else "-"
            notes = []
            ver = verdicts.get((o.item, r.metric.key))
            if ver is not None:
                st = ver.status.value
                notes.append(f"[{colour[st]}]{st}[/]"
                             + (f" ({esc(ver.detail)})" if ver.detail not in ("pass", "fail")
                                else "")
                             + f" vs {esc(ver.spec.text())}")
            if r.bound:
                v = f"{r.bound_sign} {v}"
                notes.append(f"a bound: {esc(r.reason)}")
            elif not r.reportable:
                notes.append(f"[yellow]not reportable:[/] {esc(r.reason)}" if len(withheld) == 1
                             else
                             "[yellow]not reportable[/] (why: below)")
            if r.earth_rate:
                notes.append(f"earth rate {r.earth_rate}")
            if r.monte_carlo is not None:  # --monte-carlo (JCGM 101 clause 8)
                notes.append("GUM validated by MC" if r.monte_carlo.validated else
                             "[yellow]GUM not validated by MC[/]")
            t.add_row(o.item, esc(f"{r.metric.name} {r.metric.symbol}"), esc(str(v)),
                      esc(str(u_text)),
                      esc(fmt_unit(r.metric.unit)), "; ".join(notes))
    con.print(t)
    checked = [(o.item, r) for o in record.outcomes for r in o.results
               if r.monte_carlo is not None]
    if checked:
        failed = [f"{item} {r.metric.symbol or r.metric.key} {monte_carlo_interval(r)}"
                  for item, r in checked if not r.monte_carlo.validated]
        con.print(f"Monte Carlo (JCGM 101): the GUM interval is validated for "
                  f"{len(checked) - len(failed)} of {len(checked)} budgets"
                  + (f"; not for {esc('; '.join(failed))} (the Monte Carlo interval, which "
                     "the report states)" if failed else ""))
    return withheld


def _print_warnings(con: Any, record: RunRecord) -> None:
    """The items' warnings (one said by several items printed once, naming them) and equipment past
    its due date on the measurement date."""
    from rich.markup import escape as esc

    c = record.campaign
    # a warning several items give (a campaign's drift seen by 7.2.1, 7.2.2 and 7.2.3) is printed
    # once, naming them, where its first item's warnings are
    said: dict[str, list[str]] = {}
    for o in record.outcomes:
        for w in o.warnings:
            items = said.setdefault(str(w), [])
            if o.item not in items:
                items.append(o.item)
    for text, items in said.items():
        con.print(f"[yellow]warning ({', '.join(items)}):[/] {esc(pretty_powers(text))}")
    for e in c.equipment:
        if e.calibration is not None and not e.calibration.is_valid(record.test_date):
            con.print(f"[bold red]equipment {esc(str(e.id))}[/]: {esc(e.status(record.test_date))} "
                      "— results that depend on it are not traceable; recalibrate it or use other "
                      "equipment")


def _print_simulated(con: Any, record: RunRecord, verbose: bool) -> None:
    """On a simulated station: how many results recovered the declared truth within U."""
    checks = truth_checks(record)
    if record.simulated and not record.truth:
        con.print("[bold yellow]SIMULATED data[/]: the campaign was recorded on a simulated "
                  "station (its manifest says simulated = true); the report carries the SIMULATED "
                  "banner")
    elif record.simulated:
        judged = [ch for ch in checks if ch["reportable"]]
        inside = sum(1 for ch in judged if ch["within_U"])
        withheld = len(checks) - len(judged)
        con.print("[bold yellow]SIMULATED station[/]: "
                  + (f"declared truth recovered within U by {inside} of "
                  f"{len(judged)} reportable results" if checks
                                                           else "the station declared its truth")
                  + (f" ({withheld} not reportable)" if withheld else "")
                  + ("" if verbose else " (--verbose shows them)"))
        if verbose:
            con.print("  declared truth " + ", ".join(f"{k} = {_fmt(v)}" for k, v
                                                      in record.truth.items()))
            for ch in checks:
                mark = ("[green]within U[/]" if ch["within_U"] else "[red]OUTSIDE U[/]") + (
                    "" if ch["reportable"] else " [yellow](not reportable)[/]")
                con.print(f"  {ch['item']} {ch['key']}: result {fmt_num(ch['value'], 5)} vs truth "
                          f"{fmt_num(ch['truth'], 5)} {ch['unit']} (U = {fmt_num(ch['U'], 2)}) → "
                          f"{mark}")


def _print_conformity(con: Any, a: Any, verbose: bool) -> None:
    """With ``verbose``: the conformity table (limit, source, verdict, why) and what was not
    assessed."""
    from rich.markup import escape as esc
    from rich.table import Table

    colour = VERDICT_COLOUR
    if a is not None and verbose:
        ct = Table(title=f"Conformity — {a.rule.title}", title_justify="left")
        for col in ("item", "result", "limit", "source", "verdict", "why"):
            ct.add_column(col)
        for v in a.verdicts:
            st = v.status.value
            ct.add_row(v.item, v.key, esc(v.spec.text()), esc(v.spec.source),
                       f"[{colour[st]}]{st}[/]" + (f" ({esc(v.detail)})" if v.detail
                                                   not in ("pass", "fail") else ""),
                       esc(v.reason))
        con.print(ct)
        if a.not_assessed:
            con.print("not assessed (item not performed): "
                      + ", ".join(f"{sp.symbol} {sp.text()}" for sp in a.not_assessed))


def _print_budgets_and_tables(con: Any, o: Any) -> None:
    from rich.markup import escape as esc
    from rich.table import Table

    for r in o.results:
        if r.budget is None:
            continue
        b = r.budget.as_dict()
        bt = Table(title=esc(f"Budget {o.item} {r.metric.symbol} [{b['unit']}]"))
        for col in ("source", "type", "dist.", "u(xᵢ)", "cᵢ", "uᵢ(y)", "ν"):
            bt.add_column(col)
        for row in b["rows"]:
            bt.add_row(esc(row["source"]), row["type"], row["distribution"],
                       with_unit(fmt_num(row["standard_uncertainty"], 3), row["value_unit"]),
                       with_unit(fmt_num(row["sensitivity"], 3), row["sensitivity_unit"]),
                       fmt_num(row["contribution"], 3),
                       fmt_dof(row["dof"]))
        unit_ = "" if b["unit"] == "1" else f" {b['unit']}"
        bt.caption = (f"u_c = {fmt_num(b['u_c'], 3)}{unit_}, ν_eff = {fmt_dof(b['nu_eff'])}, k = "
                      f"{b['k']:.2f}, U = {b['U_reported']}{unit_}")
        con.print(bt)
    for tab in o.tables:
        tt = Table(title=esc(str(tab.title)))
        for h in tab.header:
            tt.add_column(esc(str(h)), justify="right")
        for row in tab.rows:
            tt.add_row(*(esc(str(x)) for x in row))
        con.print(tt)


def _fmt(v: Any) -> str:
    """A declared truth value on the terminal: a quantity with its unit, powers of ten as ×10ⁿ."""
    return pretty_powers(fmt_quantity(v, 6))


__all__ = ["progress", "as_json", "print_record", "truth_checks", "verdict_line", "math"]

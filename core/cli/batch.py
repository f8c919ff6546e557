"""``metro batch``: a production lot — many device campaigns — on a dask.distributed cluster.

Each campaign is evaluated on a worker exactly as ``metro run --data`` evaluates it
(:func:`metro.core.run.runner.run_items`, then
:func:`metro.core.cli.register_commands.write_run_report`): the same report, the same ``--json``
document (kept next to the report). What goes to a worker is small: the job (standard, items,
options, decision rule, where reports go, which plugins to load) and one manifest path; the worker
reads the campaign's files itself and writes the device's report into ``OUT/devices/<name>/``, so
the client, the scheduler and the workers must see the same paths (one machine, or a shared file
system). What comes back is the device's JSON document.

The client keeps a state file (``OUT/batch-state.json``): every campaign's manifest path with its
SHA-256 and outcome, written after each campaign. A batch started again with the same ``--out``
skips the campaigns evaluated before whose manifest is unchanged (same SHA-256) and evaluates the
new, changed or failed ones. (A samples file replaced under an unchanged manifest is not noticed
before evaluation; each report records the SHA-256 of the files it read.) At the end it writes the
lot summary: every result of every device (CSV and Parquet), per-quantity statistics with the yield
against the specification, one histogram per judged quantity, and a one-page lot report (Word).
"""

from __future__ import annotations

import csv
import glob
import hashlib
import json
import math
import os
import threading
import time
import traceback
from pathlib import Path
from typing import Any, Callable, Mapping, Sequence

import attrs

from ..base.errors import DataError, MetroError

STATE_FILE = "batch-state.json"
SUMMARY_FILES = ("lot-results.csv", "lot-results.parquet", "lot-statistics.csv", "lot-report.docx")


@attrs.frozen
class Job:
    """What every campaign of the lot is evaluated for (sent to each worker with a manifest
    path)."""

    standard: str
    items: tuple[str, ...] = attrs.field(converter=tuple)
    run_all: bool = False
    options: Mapping[str, Any] = attrs.field(factory=dict)
    decision_rule: str | None = None
    out: str = "metro-batch"
    autoload: bool | None = None
    block: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    #: the lab profile in force on the client (its register numbers and keeps each device's report)
    lab: str | None = None
    register_simulated: bool = False
    allow_expired: bool = False
    #: the report's language (None: the lab profile's, else zh+en) and whether a PDF goes beside it
    lang: str | None = None
    pdf: bool = False

    def run_args(self, folder: Path) -> Any:
        """The arguments `metro run --data … --out FOLDER` would hold for this job (for the
        register's ``run_lab_options`` and ``write_run_report``, the one way runs write reports)."""
        from types import SimpleNamespace

        return SimpleNamespace(command="batch", lab=self.lab, report=None, out=str(folder),
                               no_report=False,
                               force=False, register_simulated=self.register_simulated,
                               allow_expired=self.allow_expired, lang=self.lang, pdf=self.pdf,
                               option=[f"{k}={v}" for k, v in self.options.items()])

    def fingerprint(self) -> dict[str, Any]:
        """The part of the job a resumed batch must share with the first run (not where it runs)."""
        return {"standard": self.standard, "items": list(self.items), "all": self.run_all,
                "options": {k: str(v) for k, v in sorted(self.options.items())},
                "decision_rule": self.decision_rule}


# -- the campaigns --------------------------------------------------------------------------


def find_campaigns(specs: Sequence[str]) -> list[Path]:
    """Manifest paths from ``--data`` values: each a manifest, a campaign folder (its
    ``manifest.toml``), a glob of either, or a comma-separated list of those; in the order given,
    each once.  A name that matches nothing is an error naming it."""
    out: list[Path] = []
    for spec in specs:
        for part in (p.strip() for p in spec.split(",")):
            if not part:
                continue
            matches = sorted(glob.glob(os.path.expanduser(part),
                                       recursive=True)) if glob.has_magic(part) else [part]
            if not matches:
                raise DataError(part, None, "no campaign matches this pattern",
                                hint="quote the glob so the shell does not expand it, e.g. --data "
                                "'lot/*/manifest.toml'")
            for m in matches:
                p = Path(m)
                if p.is_dir():
                    p = p / "manifest.toml"
                if not p.is_file():
                    raise DataError(str(p), None, "no such campaign manifest",
                                    hint="give manifest files or campaign folders holding "
                                    "manifest.toml")
                p = p.resolve()
                if p not in out:
                    out.append(p)
    if not out:
        raise DataError(None, "--data", "no campaign given")
    return out


def device_names(manifests: Sequence[Path]) -> list[str]:
    """A folder name per campaign (its folder's name; ``-2``, ``-3`` … where two share one)."""
    names: list[str] = []
    for m in manifests:
        base = m.parent.name or m.stem
        name, n = base, 1
        while name in names:
            n += 1
            name = f"{base}-{n}"
        names.append(name)
    return names


def sha256_of(path: Path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


# -- on a worker ----------------------------------------------------------------------------

_PMS: dict[tuple, Any] = {}
#: one campaign at a time per worker process: matplotlib (report figures) and the plugin
#: manager's hooks are not thread-safe, so a worker started with several threads still
#: evaluates one campaign at a time (start workers with --nthreads 1 and more --nworkers)
_ONE_AT_A_TIME = threading.Lock()


def _worker_pm(autoload: bool | None, block: tuple[str, ...]):
    """One loaded plugin manager per worker process (loading plugins is the costly start-up)."""
    key = (autoload, tuple(block))
    if key not in _PMS:
        from ..run.plugin_manager import get_plugin_manager

        _PMS[key] = get_plugin_manager(autoload=autoload, block=block)
    return _PMS[key]


#: records evaluated on this worker whose report waits for its turn (``evaluate_only``), by campaign
_EVALUATED: dict[str, tuple[Any, float, float]] = {}


def evaluate_campaign(job: Job, manifest: str, name: str, sha256: str) -> dict[str, Any]:
    """Evaluate one campaign as ``metro run --data MANIFEST`` does and write its report and JSON
    document under ``OUT/devices/NAME/``.  Never raises: an error comes back as
    ``{"status": "error", …}`` with its type, message and hint (a traceback for a bug)."""
    with _ONE_AT_A_TIME:
        return _evaluate(job, manifest, name, sha256)


def evaluate_only(job: Job, manifest: str, name: str, sha256: str) -> dict[str, Any]:
    """The first half of :func:`evaluate_campaign` when reports are numbered by a register: the
    campaign evaluated, its record kept on this worker (``{"status": "pending", "worker": …}``)
    until :func:`report_evaluated` writes and registers its report in the lot's order."""
    with _ONE_AT_A_TIME:
        return _evaluate(job, manifest, name, sha256, report=False)


def report_evaluated(job: Job, manifest: str, name: str, sha256: str) -> dict[str, Any]:
    """The second half: the report of a campaign :func:`evaluate_only` evaluated on this worker
    (evaluated again here when it ran on another worker, e.g. one that has gone)."""
    with _ONE_AT_A_TIME:
        return _evaluate(job, manifest, name, sha256,
                         kept=_EVALUATED.pop(_campaign_key(manifest, sha256), None))


def _campaign_key(manifest: str, sha256: str) -> str:
    return f"{sha256}:{manifest}"


def _evaluate(job: Job, manifest: str, name: str, sha256: str, *, report: bool = True,
              kept: tuple[Any, float, float] | None = None) -> dict[str, Any]:
    """Evaluate (or take the ``kept`` record, with the seconds its evaluation took) and, with
    ``report``, write the report; without, keep the record for :func:`report_evaluated`."""
    from . import present
    from .common import exit_code_for
    from .schemas import document, dumps
    from .register_commands import run_lab_options, write_run_report
    from ..run.runner import run_items

    t0, c0 = time.perf_counter(), time.process_time()
    base = {"campaign": manifest, "name": name, "sha256": sha256, "worker_pid": os.getpid()}
    try:
        pm = _worker_pm(job.autoload, job.block)
        folder = Path(job.out) / "devices" / name
        args = job.run_args(folder)
        if kept is not None:
            record, seconds, cpu = kept
            t0, c0 = t0 - seconds, c0 - cpu
        else:  # evaluated and checked against the lab profile as `metro run --out FOLDER` does
            record = run_items(pm, job.standard, list(job.items), data=manifest,
                               options=dict(job.options),
                               run_all=job.run_all, decision_rule=job.decision_rule,
                               **run_lab_options(args))
        if not report:
            from distributed import get_worker

            _EVALUATED[_campaign_key(manifest, sha256)] = (record, time.perf_counter() - t0,
                                                           time.process_time() - c0)
            return base | {"status": "pending", "worker": get_worker().address}
        # reported and registered as `metro run --out FOLDER` does
        record, report, registration = write_run_report(args, pm, record)
        doc = document(present.as_json(record, report) | {"register": registration})
        doc_path = folder / "result.json"
        doc_path.write_text(dumps(doc), encoding="utf-8")  # as `metro run --json` prints it
        overall = (doc["conformity"] or {}).get("overall")
        return base | {"status": "evaluated", "overall": overall,
                       "exit_code": exit_code_for(overall),
                       "report": str(report), "json": str(doc_path),
                       "report_number": record.report_number,
                       "registered": bool(registration and registration.get("registered")),
                       "seconds": time.perf_counter() - t0, "cpu_seconds": time.process_time() - c0,
                       "doc": doc}
    except MetroError as exc:
        return base | {"status": "error", "error": type(exc).__name__, "message": exc.reason,
                       "hint": exc.hint,
                       "seconds": time.perf_counter() - t0}
    # a bug in metro or a plugin: listed with its traceback, the lot goes on
    except Exception as exc:
        return base | {"status": "error", "error": type(exc).__name__, "message": str(exc)
                       or repr(exc),
                       "hint": "an internal error: please report it with the traceback in "
                       "batch-state.json",
                       "traceback": traceback.format_exc(), "seconds": time.perf_counter() - t0}


# -- the state file -------------------------------------------------------------------------


def _write_json_atomically(path: Path, doc: Any) -> None:
    tmp = path.with_name(path.name + ".tmp")
    tmp.write_text(json.dumps(doc, ensure_ascii=False, indent=2), encoding="utf-8")
    os.replace(tmp, path)


def load_state(out: Path, job: Job) -> dict[str, Any]:
    """The resume state of ``out`` (empty for a new batch).  A state written for another job
    (other standard, items, options or rule) is an error: its lot summary would mix two jobs."""
    path = out / STATE_FILE
    if not path.exists():
        return {"job": job.fingerprint(), "campaigns": {}}
    try:
        state = json.loads(path.read_text(encoding="utf-8"))
        state["campaigns"]
    except (ValueError, KeyError, TypeError) as exc:
        hint = "give another --out, or remove the file to start the batch afresh"
        raise DataError(str(path), None, f"not a metro batch state file ({exc})",
                        hint=hint) from exc
    if state.get("job") != job.fingerprint():
        raise DataError(str(path), "job",
                        f"this --out holds a batch of another job ({state.get('job')}); "
                        f"this one is {job.fingerprint()}",
                        hint="give another --out for a different job")
    return state


def already_done(state: Mapping[str, Any], manifest: str, sha: str) -> dict[str, Any] | None:
    """The earlier outcome of this manifest if it was evaluated with the same SHA-256 (the
    manifest unchanged) and its document is still there; failed campaigns are tried again."""
    entry = state["campaigns"].get(manifest)
    if (entry and entry.get("sha256") == sha and entry.get("status") == "evaluated"
            and Path(entry.get("json", "")).is_file()):
        return entry
    return None


# -- the batch ------------------------------------------------------------------------------


def run_batch(job: Job, manifests: Sequence[Path], *, scheduler: str | None = None, workers: int
              | None = None,
              progress: Callable[[str, float, float], None] | None = None) -> dict[str, Any]:
    """Evaluate ``manifests`` on a Dask cluster (a local cluster of ``workers`` processes, or the
    one at ``scheduler``), skip those already evaluated in ``job.out``, write the lot summary;
    return the summary document."""
    out = Path(job.out)
    out.mkdir(parents=True, exist_ok=True)
    state = load_state(out, job)
    names = device_names(manifests)
    todo, outcomes = [], {}
    for m, name in zip(manifests, names):
        sha = sha256_of(m)
        prior = already_done(state, str(m), sha)
        if prior is not None:
            doc = json.loads(Path(prior["json"]).read_text(encoding="utf-8"))
            outcomes[str(m)] = prior | {"skipped": True, "doc": doc, "campaign": str(m)}
        else:
            todo.append((str(m), name, sha))
    total = len(manifests)
    done = len(outcomes)
    if progress is not None:
        progress("campaigns", done, total)
    t0 = time.perf_counter()
    timing: dict[str, float] = {"cluster_start_s": 0.0}
    if todo:
        for res in _evaluate_on_dask(job, todo, scheduler=scheduler, workers=workers,
                                     timing=timing):
            outcomes[res["campaign"]] = res
            entry = {k: v for k, v in res.items() if k != "doc"}
            state["campaigns"][res["campaign"]] = entry
            _write_json_atomically(out / STATE_FILE, state)  # resumable from here on
            done += 1
            if progress is not None:
                progress(f"{res['name']}: {res.get('overall') or res['status']}", 1, 1)
                progress("campaigns", done, total)
    elapsed = time.perf_counter() - t0
    ordered = [outcomes[str(m)] for m in manifests]
    summary = write_lot_summary(job, ordered, out)
    summary["timing"] = {"seconds": elapsed, "cluster_start_s": timing["cluster_start_s"],
                         "evaluated_now": len(todo), "skipped": total - len(todo),
                         "workers": workers,
                         "scheduler": scheduler or "local"}
    from .schemas import document

    _write_json_atomically(out / "lot-summary.json", document(summary))
    return summary


def _evaluate_on_dask(job: Job, todo: Sequence[tuple[str, str, str]], *, scheduler: str | None,
                      workers: int | None, timing: dict[str, float]):
    """Yield each campaign's outcome as its worker finishes it, or, with a lab profile (a register
    numbers the reports), in the lot's order (``timing["cluster_start_s"]``: the time to start or
    reach the cluster)."""
    import logging

    from distributed import Client, LocalCluster

    t0 = time.perf_counter()
    cluster = None
    if scheduler:
        try:
            client = Client(scheduler, timeout="20s")
        except OSError as exc:
            raise MetroError(f"cannot reach the Dask scheduler at {scheduler}: {exc}",
                             hint="start one (`dask scheduler`, then `dask worker ADDRESS`) or "
                             "leave out --scheduler for a local cluster") from exc
    else:
        n = workers or os.cpu_count() or 1
        cluster = LocalCluster(n_workers=n, threads_per_worker=1, processes=True,
                               dashboard_address="127.0.0.1:0",
                               silence_logs=logging.ERROR)
        client = Client(cluster)
        client.wait_for_workers(n)
    timing["cluster_start_s"] = time.perf_counter() - t0
    try:
        if job.lab is None:  # no register numbers: each device reported as soon as it is evaluated
            yield from _as_finished(client, job, todo)
        else:
            yield from _in_lot_order(client, job, todo)
    finally:
        client.close()
        if cluster is not None:
            cluster.close()


def _outcome(fut, campaign: tuple[str, str, str]) -> dict[str, Any]:
    """A task's result; a worker that died (KilledWorker, lost connection) gives the campaign's
    error."""
    m, name, sha = campaign
    try:
        return fut.result()
    except Exception as exc:  # listed, the lot goes on
        return {"campaign": m, "name": name, "sha256": sha, "status": "error",
                "error": type(exc).__name__,
                "message": str(exc) or repr(exc),
                "hint": "the Dask worker failed while evaluating it"}


def _as_finished(client, job: Job, todo: Sequence[tuple[str, str, str]]):
    from distributed import as_completed

    futures = {client.submit(evaluate_campaign, job, m, name, sha, pure=False,
                             key=f"metro-{sha[:16]}-{name}"):
               (m, name, sha) for m, name, sha in todo}
    for fut in as_completed(futures):
        yield _outcome(fut, futures[fut])


def _in_lot_order(client, job: Job, todo: Sequence[tuple[str, str, str]]):
    """Every campaign evaluated at once on the workers; the reports written, and numbered by the
    register, one after the other in the lot's order (the order of --data, then of the paths a
    glob finds), each on the worker that holds its record.  Issuing was one at a time already (the
    register's lock is held while a report is written), so the lot loses no parallel work."""
    evaluations = [client.submit(evaluate_only, job, m, name, sha, pure=False,
                                 key=f"metro-eval-{sha[:16]}-{name}") for m, name, sha in todo]
    for campaign, fut in zip(todo, evaluations):
        res = _outcome(fut, campaign)
        if res.get("status") == "pending":
            m, name, sha = campaign
            written = client.submit(report_evaluated, job, m, name, sha, pure=False,
                                    key=f"metro-report-{sha[:16]}-{name}", workers=[res["worker"]],
                                    allow_other_workers=True, priority=10)
            res = _outcome(written, campaign)
        yield res


# -- the lot summary ------------------------------------------------------------------------

RESULT_COLUMNS = ("device", "campaign", "device_id", "serial", "model", "report_number", "item",
                  "key", "symbol",
                  "quantity", "value", "unit", "u", "U", "k", "reportable", "reason", "earth_rate",
                  "limit",
                  "verdict")


def result_rows(outcomes: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Every result of every evaluated device, one row each, with its verdict where judged."""
    rows = []
    for o in outcomes:
        if o.get("status") != "evaluated":
            continue
        doc = o["doc"]
        verdicts = {(v["item"], v["key"]): v for v
                    in ((doc.get("conformity") or {}).get("verdicts") or [])}
        for r in doc["results"]:
            v = verdicts.get((r["item"], r["key"]))
            rows.append({"device": o["name"], "campaign": o["campaign"],
                         "device_id": doc["device"]["id"],
                         "serial": doc["device"]["serial"], "model": doc["device"]["model"],
                         "report_number": doc["report_number"], "item": r["item"], "key": r["key"],
                         "symbol": r["symbol"], "quantity": r["quantity"], "value": r["value"],
                         "unit": r["unit"],
                         "u": r["u"], "U": r["U"], "k": r["k"],
                         "reportable": r.get("reportable", True),
                         "reason": r.get("reason") or "", "earth_rate": r.get("earth_rate") or "",
                         "limit": v["limit"] if v else "", "verdict": v["status"] if v else ""})
    return rows


def statistics(rows: Sequence[Mapping[str, Any]]) -> list[dict[str, Any]]:
    """Per quantity (item, key, unit) across the lot: n, mean, σ (sample, n − 1), min, max of the
    reportable values, and the yield: the fraction of judged devices whose verdict is pass."""
    import numpy as np

    groups: dict[tuple[str, str, str], list[Mapping[str, Any]]] = {}
    for r in rows:
        groups.setdefault((r["item"], r["key"], r["unit"]), []).append(r)
    out = []
    for (item, key, unit), rs in groups.items():
        vals = np.array([r["value"] for r in rs if r["reportable"]], dtype=float)
        judged = [r for r in rs if r["verdict"]]
        counts = {s: sum(1 for r in judged if r["verdict"] == s) for s
                  in ("pass", "fail", "indeterminate")}
        out.append({"item": item, "key": key, "symbol": rs[0]["symbol"],
                    "quantity": rs[0]["quantity"],
                    "unit": unit, "n": int(vals.size), "not_reportable": len(rs) - int(vals.size),
                    "mean": float(vals.mean()) if vals.size else None,
                    "std": float(vals.std(ddof=1)) if vals.size > 1 else None,
                    "min": float(vals.min()) if vals.size else None,
                    "max": float(vals.max()) if vals.size else None,
                    "limit": "; ".join(sorted({r["limit"] for r in judged})),
                    "judged": len(judged), **counts,
                    "yield": counts["pass"] / len(judged) if judged else None})
    return out


def _write_csv(path: Path, rows: Sequence[Mapping[str, Any]], columns: Sequence[str]) -> None:
    with path.open("w", newline="", encoding="utf-8") as fh:
        w = csv.DictWriter(fh, fieldnames=list(columns))
        w.writeheader()
        for r in rows:
            w.writerow({k: ("" if r.get(k) is None else r.get(k)) for k in columns})


def _write_parquet(path: Path, rows: Sequence[Mapping[str, Any]], columns: Sequence[str]) -> None:
    import pyarrow as pa
    import pyarrow.parquet as pq

    types = {"value": pa.float64(), "u": pa.float64(), "U": pa.float64(), "k": pa.float64(),
             "reportable": pa.bool_()}
    schema = pa.schema([(c, types.get(c, pa.string())) for c in columns])
    table = pa.Table.from_pylist([{c: r.get(c) for c in columns} for r in rows], schema=schema)
    pq.write_table(table, path)


def _histograms(stats: Sequence[Mapping[str, Any]], rows: Sequence[Mapping[str, Any]],
                folder: Path) -> list[str]:
    """One PNG per judged quantity (per quantity when nothing is judged), values across the lot."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    keyed = [s for s in stats if s["judged"]] or list(stats)
    folder.mkdir(parents=True, exist_ok=True)
    paths = []
    for s in keyed:
        vals = [r["value"] for r in rows if (r["item"], r["key"], r["unit"])
                == (s["item"], s["key"], s["unit"])
                and r["reportable"]]
        if not vals:
            continue
        fig, ax = plt.subplots(figsize=(5, 3.2), dpi=100)
        ax.hist(vals, bins=max(5, min(30, int(math.sqrt(len(vals))) + 3)), color="#4878a8",
                edgecolor="white")
        ax.set_xlabel(f"{s['symbol']} [{s['unit']}]")
        ax.set_ylabel("devices")
        title = f"{s['item']} {s['quantity']} — {len(vals)} devices"
        if s["limit"]:
            title += f"\nlimit {s['limit']}, yield {100 * s['yield']:.0f} %"
        ax.set_title(title, fontsize=9)
        fig.tight_layout()
        safe = "".join(ch if ch.isalnum() or ch in "._-" else "_" for ch
                       in f"{s['item']}_{s['key']}")
        p = folder / f"{safe}.png"
        fig.savefig(p)
        plt.close(fig)
        paths.append(str(p))
    return paths


def _fmt(x: float | None) -> str:
    from ..base.formatting import fmt_num

    return "–" if x is None else fmt_num(x, 4)


def _lot_report(path: Path, job: Job, summary: Mapping[str, Any],
                stats: Sequence[Mapping[str, Any]]) -> None:
    """A one-page Word lot report: what was evaluated, the lot's verdicts, the judged quantities'
    statistics and yield, the campaigns that failed; the per-device reports hold the detail. Laid
    out by :class:`metro.core.documents.document.DocumentBuilder` as every metro document is (A4,
    the header with "page x of y", columns that fit their numbers, symbols with subscripts); in
    English (a lab's internal summary: the devices' reports carry the document language)."""
    import datetime as dt

    from .. import __version__
    from ..documents.builder import DocumentBuilder
    from ..documents.text import quantity_name
    from ..base.locale import translator

    now = dt.datetime.now(dt.timezone.utc)
    doc = DocumentBuilder(number=f"LOT-{job.standard}-{now:%Y%m%d-%H%M}", title="Lot summary",
                          tr=translator("en"), footer=f"metro {__version__}")
    doc.heading(f"Lot summary — {job.standard}", 1)
    c = summary["counts"]
    items = "every applicable item" if job.run_all else ", ".join(job.items)
    doc.para(f"Items: {items}. Campaigns: {summary['campaigns']} ({c['evaluated']} evaluated, "
             f"{c['error']} failed). Devices: {c['pass']} conform, {c['fail']} do not conform, "
             f"{c['indeterminate']} indeterminate, {c['not judged']} not judged. "
             f"Written {now:%Y-%m-%d %H:%M} UTC by metro {__version__}.")
    shown = [s for s in stats if s["judged"]] or list(stats)
    shown = shown[:28]  # one page; lot-statistics.csv has every quantity
    heads = ("Item", "Quantity", "Unit", "n", "Mean", "σ", "Min", "Max", "Limit", "Yield")
    rows = [(s["item"], quantity_name({"quantity": s["quantity"], "symbol": s["symbol"],
                                       "key": s.get("key", "")}),
             s["unit"], str(s["n"]), _fmt(s["mean"]), _fmt(s["std"]), _fmt(s["min"]),
             _fmt(s["max"]),
             s["limit"] or "–", "–" if s["yield"] is None
             else f"{100 * s['yield']:.0f} % ({s['pass']}/{s['judged']})")
            for s in shown]
    if rows:
        doc.table(heads, rows, font_pt=8, prefer=1)
    if len(shown) < len([s for s in stats if s["judged"]] or stats):
        doc.para("… more quantities in lot-statistics.csv.")
    failed = [o for o in summary["devices"] if o["status"] == "error"]
    if failed:
        doc.para("Campaigns that could not be evaluated:", keep_next=True)
        doc.bullets([f"{o['name']} ({o['campaign']}): {o['error']}: {o['message']}" for o
                     in failed], size=8.5)
    doc.para("Yield: devices whose verdict is pass, of those judged, per quantity. Each device's "
             "report (devices/<name>/) carries its results, budgets and verdicts; "
             "lot-results.csv/.parquet list every result; histograms/ plots the judged quantities.",
             size=8.5)
    doc.save(path)


def write_lot_summary(job: Job, outcomes: Sequence[Mapping[str, Any]], out: Path) -> dict[str, Any]:
    rows = result_rows(outcomes)
    stats = statistics(rows)
    _write_csv(out / "lot-results.csv", rows, RESULT_COLUMNS)
    _write_parquet(out / "lot-results.parquet", rows, RESULT_COLUMNS)
    stat_cols = ("item", "key", "symbol", "quantity", "unit", "n", "not_reportable", "mean", "std",
                 "min", "max",
                 "limit", "judged", "pass", "fail", "indeterminate", "yield")
    _write_csv(out / "lot-statistics.csv", stats, stat_cols)
    hists = _histograms(stats, rows, out / "histograms") if rows else []
    counts = {"evaluated": 0, "error": 0, "pass": 0, "fail": 0, "indeterminate": 0, "not judged": 0}
    devices = []
    for o in outcomes:
        counts[o["status"]] += 1
        if o["status"] == "evaluated":
            counts[o.get("overall") or "not judged"] += 1
        devices.append({k: o.get(k) for k in ("name", "campaign", "sha256", "status", "overall",
                                              "report", "json",
                                              "report_number", "registered", "error", "message",
                                              "hint", "skipped",
                                              "seconds", "cpu_seconds")})
    summary = {"standard": job.standard, "items": list(job.items), "all": job.run_all,
               "campaigns": len(outcomes),
               "counts": counts, "devices": devices, "statistics": stats, "histograms": hists,
               "files": {name: str(out / name) for name in SUMMARY_FILES}}
    _lot_report(out / "lot-report.docx", job, summary, stats)
    return summary


def exit_code(summary: Mapping[str, Any]) -> int:
    """5 when a campaign failed, else the worst verdict's code (3 fail, 4 indeterminate), else 0."""
    from .common import EXIT_CAMPAIGN_FAILED, EXIT_INDETERMINATE, EXIT_NONCONFORMING, EXIT_OK

    c = summary["counts"]
    if c["error"]:
        return EXIT_CAMPAIGN_FAILED
    if c["fail"]:
        return EXIT_NONCONFORMING
    if c["indeterminate"]:
        return EXIT_INDETERMINATE
    return EXIT_OK


# -- the command ----------------------------------------------------------------------------


def command(args) -> int:
    """``metro batch`` (arguments parsed by metro.core.cli.app)."""
    from . import present
    from .common import parse_options, plugin_manager, requested_items, show_progress
    from ..base.extras import require

    require("distributed", "metro batch")  # before any work: the lot needs a Dask cluster
    require("pyarrow.parquet", "metro batch", extra="batch")  # lot-results.parquet
    pm = plugin_manager(args)
    items = requested_items(pm, args)
    if args.workers is not None and args.workers < 1:
        raise MetroError(f"--workers {args.workers}: give at least 1")
    if args.scheduler and args.workers:
        raise MetroError("--workers sizes the local cluster; an existing cluster (--scheduler) has "
                         "its own workers",
                         hint="drop --workers, or drop --scheduler to run on this machine")
    manifests = find_campaigns(args.data)
    from ..record.lab import find_lab_path, load_lab

    lab = find_lab_path(getattr(args, "lab", None))
    if lab is not None:
        load_lab(lab)  # a broken profile is an error here, before any worker starts
    job = Job(args.standard, items, args.run_all, parse_options(args.option), args.decision_rule,
              str(Path(args.out).resolve()), False if args.no_plugin_autoload else None,
              args.block_plugin,
              lab=None if lab is None else str(Path(lab).resolve()),
              register_simulated=getattr(args, "register_simulated", False),
              allow_expired=getattr(args, "allow_expired", False), lang=args.lang, pdf=args.pdf)
    with present.progress(enabled=show_progress(args)) as prog:
        summary = run_batch(job, manifests, scheduler=args.scheduler, workers=args.workers,
                            progress=prog)
    code = exit_code(summary)
    summary["exit_code"] = code
    if args.json:
        from .schemas import print_json

        print_json(summary)
    else:
        print_summary(summary, Path(job.out), verbose=args.verbose)
    return code


def print_summary(summary: Mapping[str, Any], out: Path, *, verbose: bool = False) -> None:
    from rich.console import Console
    from rich.table import Table

    con = Console(highlight=False)
    colour = {"pass": "green", "fail": "red", "indeterminate": "yellow", "error": "bold red"}
    t = Table(title=f"metro batch — {summary['standard']}", title_justify="left")
    for col in ("device", "verdict", "report or error"):
        t.add_column(col, overflow="fold")
    for d in summary["devices"]:
        st = d["overall"] if d["status"] == "evaluated" else "error"
        text = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate",
                "error": "FAILED", None: "not judged"}[st]
        where = d["report"] if d["status"] == "evaluated" else f"{d['error']}: {d['message']}"
        if d.get("skipped"):
            text += " (earlier run)"
        t.add_row(d["name"], f"[{colour.get(st or '', 'bold')}]{text}[/]", where)
    con.print(t)
    if verbose:
        st = Table(title="lot statistics", title_justify="left")
        for col in ("item", "quantity", "n", "mean", "σ", "min", "max", "unit", "yield"):
            st.add_column(col, justify="right" if col not in ("item", "quantity", "unit")
                          else "left")
        for s in summary["statistics"]:
            st.add_row(s["item"], s["symbol"], str(s["n"]), _fmt(s["mean"]), _fmt(s["std"]),
                       _fmt(s["min"]), _fmt(s["max"]), s["unit"],
                       "–" if s["yield"] is None else f"{100 * s['yield']:.0f} %")
        con.print(st)
    c = summary["counts"]
    con.print(f"[bold]lot: {summary['campaigns']} campaigns: {c['pass']} conform, {c['fail']} do "
              f"not conform, {c['indeterminate']} indeterminate, {c['not judged']} not judged, "
              f"{c['error']} failed[/]", soft_wrap=True)
    con.print(f"lot summary in {out}: lot-report.docx, lot-results.csv/.parquet, "
              "lot-statistics.csv, histograms/",
              soft_wrap=True)

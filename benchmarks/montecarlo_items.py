"""The results whose GUM interval Monte Carlo does not validate, and why: a Markdown table.

Run:  metro run -s STANDARD --all --monte-carlo --json --no-report --seed 1 > STANDARD.json
      .venv/bin/python benchmarks/montecarlo_items.py STANDARD.json [...]

For each result with ``monte_carlo.validated`` false: GUM's U, the Monte Carlo interval's
half-width against it (wider or narrower), the larger of d_low, d_high in units of δ, and the
component that explains the difference, read from the budget: where the Monte Carlo interval is
wider, the t row (a finite ν_i) with the largest share of u_c² — its heavy tails; where it is
narrower, the bounded row (rectangular, triangular, arcsine) with the largest share — a sum
dominated by a bounded input has shorter tails than the normal k = 2 assumes.  The tables are
in docs/monte-carlo.md.
"""

from __future__ import annotations

import json
import sys

BOUNDED = ("uniform", "rectangular", "triangular", "arcsine")


def cause(budget: dict, wider: bool) -> str:
    """The row that explains a wider (t tails) or narrower (bounded input) interval."""
    total = sum(r["contribution"] ** 2 for r in budget["rows"]) or 1.0
    if wider:
        rows = [r for r in budget["rows"] if r["dof"] is not None and r["distribution"] not in
                BOUNDED]
    else:
        rows = [r for r in budget["rows"] if r["distribution"] in BOUNDED]
    if not rows:
        return "—"
    top = max(rows, key=lambda r: r["contribution"])
    share = 100 * top["contribution"] ** 2 / total
    nu = f", ν = {top['dof']:.3g}" if top["dof"] is not None else ""
    return f"{top['source']} ({top['distribution']}{nu}; {share:.0f} % of u_c²)"


def table(doc: dict) -> list[str]:
    """The Markdown rows of one run's results that are not validated."""
    out = []
    for r in doc["results"]:
        mc = r.get("monte_carlo")
        if not mc or mc["validated"]:
            continue
        half = (mc["interval"][1] - mc["interval"][0]) / 2
        wider = half > r["U"]
        d = max(mc["d_low"], mc["d_high"]) / mc["delta"] if mc["delta"] else float("inf")
        u = "—" if mc["u"] is None else f"{mc['u'] / r['u']:.2f}"
        why = ("the measurement model (budget `model`)" if mc["model"] == "model"
               and cause(r["budget"], wider) == "—" else cause(r["budget"], wider))
        out.append(f"| {r['item']} | {r['symbol'] or r['key']} | {u} | {half / r['U']:.2f} "
                   f"({'wider' if wider else 'narrower'}) | {d:.1f} | "
                   f"{why} |")
    return out


def main() -> None:
    for path in sys.argv[1:]:
        with open(path, encoding="utf-8") as f:
            doc = json.load(f)
        checked = sum(1 for r in doc["results"] if r.get("monte_carlo"))
        rows = table(doc)
        print(f"\n{doc['standard']}: {len(rows)} of {checked} budgets not validated\n")
        print("| item | result | u_MC / u_c | MC half-width / U | max(d)/δ | component |")
        print("|---|---|---|---|---|---|")
        print("\n".join(rows))


if __name__ == "__main__":
    main()

"""Benchmark of metro's Monte Carlo propagation (JCGM 101) on a 10-component budget.

Run:  .venv/bin/python benchmarks/bench_montecarlo.py [--trials M] [--repeat R]

The budget has two inputs of each distribution metro draws (normal, rectangular, triangular,
arcsine, t with ν = 9) and the linear model Y = Σ c_i·X_i.  Prints the best wall time of R runs
of ``propagate(..., trials=M)`` (draws, model, sorting, both coverage intervals) and of each of
its stages, and the adaptive run (clause 7.9) of the same budget.  Target: ≤ 0.5 s at M = 10⁶.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from metro.core.uncertainty.montecarlo import Input, linear_model, propagate, summarise


def best(f, repeat: int) -> float:
    """The best wall time of ``repeat`` calls of ``f``."""
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        f()
        times.append(time.perf_counter() - t0)
    return min(times)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--trials", type=int, default=1_000_000)
    ap.add_argument("--repeat", type=int, default=5)
    args = ap.parse_args()
    m = args.trials
    inputs = [Input(d, 0.0, 1.0, dof=9)
              for d in ("normal", "rectangular", "triangular", "arcsine", "t") * 2]
    model = linear_model(np.arange(1.0, 11.0))
    rng = np.random.default_rng(1)
    draws = np.empty((len(inputs), m))

    def draw() -> None:
        for i, x in enumerate(inputs):
            draws[i] = x.draw(m, rng)

    draw()
    values = model(draws)
    rows = [
        ("propagate, 10 inputs", best(lambda: propagate(inputs, model, trials=m, rng=1),
                                      args.repeat)),
        ("  draws", best(draw, args.repeat)),
        ("  model Σ c_i·x_i", best(lambda: model(draws), args.repeat)),
        ("  sort + intervals + u", best(lambda: summarise(values, 0.95), args.repeat)),
    ]
    t0 = time.perf_counter()
    r = propagate(inputs, model, rng=1)
    adaptive = time.perf_counter() - t0
    print(f"M = {m:,} trials, best of {args.repeat}")
    for name, t in rows:
        print(f"{name:<28} {t:8.3f} s")
    print(f"{'adaptive (7.9), 2 digits':<28} {adaptive:8.3f} s  ({r.trials:,} trials)")


if __name__ == "__main__":
    main()

"""Run a benchmark with JJF 2003's drift rules switched to an alternative that issue 13 measured.

Run: nice -n 10 .venv/bin/python benchmarks/jjf2003_drift_modes.py [--correct
always|significant|never]
          [--no-times budget|significant|material|verdict|bound] SCRIPT [its arguments …]

``--correct`` (with recording times): ``significant`` (metro's rule: a result is corrected where the
drift's effect on it is resolved, |Δ| ≥ Z_CORRECT·u(Δ)), ``always`` (every result corrected:
Z_CORRECT = 0), ``never`` (the uncorrected row √(d̂² + u²)·|τ| of 03df5ef and before).
``--no-times`` (without them): ``budget`` (metro's rule: each K_g and g carries u_b = (|d̂| +
2u(d̂))·|τ_plan| and is not reportable where a significant drift moves it by MATERIAL = 0.1 of U or
more in the plan's order), ``significant`` (u_b; every result of a significant drift withheld),
``material`` (u_b; withheld only from half of U), ``verdict`` (the rule before the ninth round: no
u_b, withheld from half of U), ``bound`` (no u_b; not reportable wherever (|d̂| + 2u(d̂))·|τ_plan|
reaches half of U, significant or not).  A fourth rule measured in
the eighth round, ``order`` (a row √(d̂² + u²)·|τ| with τ from the manifest's order), needed code in
the procedures and is only in this script's history (71d6f49).  The figures are in
docs/interpretations.md and docs/standards/jjf2003.md, "Gyro bias drift during the campaign".
Example:

  benchmarks/jjf2003_drift_modes.py --no-times verdict benchmarks/independent_jjf2003.py --devices
  200 \\
      --seed 1001 --variants mimu-24bit-warmup-ramp --json verdict.json
"""

from __future__ import annotations

import argparse
import runpy
import sys


def _bound_reason(D):
    """Not reportable wherever the drift the trends cannot exclude could move the result by half of
    U."""

    def reason(drift, i, tau_plan, U, unit):
        if not U > 0:
            return None
        reach = D.drift_bound(drift, i) * abs(tau_plan)
        if reach < 0.5 * U:
            return None
        return f"bound: (|d̂| + 2u)·|τ| = {reach:.3g}{unit} ≥ 0.5 U"

    return reason


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--correct", choices=("significant", "always", "never"), default="significant")
    ap.add_argument("--no-times", choices=("budget", "significant", "material", "verdict", "bound"),
                    default="budget")
    ap.add_argument("script")
    ap.add_argument("args", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    from metro.plugins.jjf2003 import drift as D

    if a.correct == "never":
        D.GyroDrift.corrects = lambda self, i: False  # the pooled row, uncorrected
    elif a.correct == "always":
        D.Z_CORRECT = 0.0
    if a.no_times in ("verdict", "bound"):
        D.bound_row = lambda *args, **kw: None
    if a.no_times in ("verdict", "material"):
        D.MATERIAL = 0.5
    elif a.no_times == "significant":
        D.MATERIAL = 0.0
    if a.no_times == "bound":
        D.not_reportable_reason = _bound_reason(D)
    sys.argv = [a.script, *a.args]
    runpy.run_path(a.script, run_name="__main__")


if __name__ == "__main__":
    main()

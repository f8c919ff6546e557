"""Run a benchmark with JJF 2003's drift rules switched to an alternative that issue 13 measured.

Run:  nice -n 10 .venv/bin/python benchmarks/jjf2003_drift_modes.py [--correct always|significant|never]
          [--no-times budget|material|verdict|bound] SCRIPT [its arguments …]

``--correct`` (with recording times): ``significant`` (metro's rule: a result is corrected where the
drift's effect on it is resolved, |Δ| ≥ Z_CORRECT·u(Δ)), ``always`` (every result corrected:
Z_CORRECT = 0), ``never`` (the uncorrected row √(d̂² + u²)·|τ| of 03df5ef and before).
``--no-times`` (without them): ``budget`` (metro's rule: each K_g and g carries u_b = (|d̂| +
2u(d̂))·|τ_plan| and is not reportable where the drift is significant), ``material`` (u_b, but not
reportable only where a significant drift also moves the result by half of U or more in the plan's
order), ``verdict`` (the rule before the ninth round: that verdict alone, no u_b), ``bound`` (no u_b;
not reportable wherever (|d̂| + 2u(d̂))·|τ_plan| reaches half of U, significant or not).  A fourth rule measured in
the eighth round, ``order`` (a row √(d̂² + u²)·|τ| with τ from the manifest's order), needed code in
the procedures and is only in this script's history (71d6f49).  The figures are in
docs/interpretations.md and docs/standards/jjf2003.md, "Gyro bias drift during the campaign".
Example:

  benchmarks/jjf2003_drift_modes.py --no-times verdict benchmarks/independent_jjf2003.py --devices 200 \\
      --seed 1001 --variants mimu-24bit-warmup-ramp --json verdict.json
"""

from __future__ import annotations

import argparse
import math
import runpy
import sys


#: the share of U the rules before the ninth round called material
MATERIAL = 0.5


def _verdict_reason(D, original):
    """The eighth round's rule: not reportable where the drift is significant and its effect in the
    plan's order reaches MATERIAL of U (metro now withholds every result of a significant drift)."""

    def reason(drift, i, tau_plan, U, unit):
        if math.isfinite(drift.u[i]) and abs(drift.d[i] * tau_plan) < MATERIAL * U:
            return None
        return original(drift, i, tau_plan, U, unit)

    return reason


def _bound_reason(D):
    """Not reportable wherever the drift the trends cannot exclude could move the result by half of U."""

    def reason(drift, i, tau_plan, U, unit):
        if not U > 0:
            return None
        reach = D.drift_bound(drift, i) * abs(tau_plan)
        if reach < MATERIAL * U:
            return None
        return f"bound: (|d̂| + 2u)·|τ| = {reach:.3g}{unit} ≥ {MATERIAL} U"

    return reason


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--correct", choices=("significant", "always", "never"), default="significant")
    ap.add_argument("--no-times", choices=("budget", "material", "verdict", "bound"), default="budget")
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
        D.not_reportable_reason = _verdict_reason(D, D.not_reportable_reason)
    if a.no_times == "bound":
        D.not_reportable_reason = _bound_reason(D)
    sys.argv = [a.script, *a.args]
    runpy.run_path(a.script, run_name="__main__")


if __name__ == "__main__":
    main()

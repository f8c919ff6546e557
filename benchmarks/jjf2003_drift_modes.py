"""Run a benchmark with JJF 2003's drift rules switched to an alternative that issue 13 measured.

Run:  nice -n 10 .venv/bin/python benchmarks/jjf2003_drift_modes.py [--correct always|significant|never]
          [--no-times verdict|bound|order] SCRIPT [its arguments …]

``--correct`` (with recording times): ``significant`` (metro's rule: a result is corrected where the
drift's effect on it is resolved), ``always`` (every result corrected), ``never`` (the uncorrected
row √(d̂² + u²)·|τ| of 03df5ef and before).  ``--no-times`` (without them): ``verdict`` (metro's rule:
not reportable where the drift is significant and material in the plan's order), ``bound`` (not
reportable where (|d̂| + 2u(d̂))·|τ| in the plan's order reaches half of U, significant or not),
``order`` (also a row √(d̂² + u²)·|τ| with τ from the manifest's order, the records back to back).
The figures are in docs/interpretations.md and docs/standards/jjf2003.md, "Gyro bias drift during
the campaign".  Example:

  benchmarks/jjf2003_drift_modes.py --no-times order benchmarks/independent_jjf2003.py --devices 200 \\
      --seed 1001 --variants mimu-24bit-warmup-ramp,mimu-24bit-warmup-ramp-shuffled --json order.json
"""

from __future__ import annotations

import argparse
import runpy
import sys


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--correct", choices=("significant", "always", "never"), default="significant")
    ap.add_argument("--no-times", choices=("verdict", "bound", "order"), default="verdict")
    ap.add_argument("script")
    ap.add_argument("args", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    from metro.plugins.jjf2003 import drift as D

    if a.correct == "never":
        D.GyroDrift.corrects = lambda self, i: False  # the pooled row, uncorrected
    else:
        D.CORRECT = a.correct
    D.NO_TIMES = a.no_times
    sys.argv = [a.script, *a.args]
    runpy.run_path(a.script, run_name="__main__")


if __name__ == "__main__":
    main()

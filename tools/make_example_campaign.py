"""Write the worked example campaign of docs/data-format.md (run: python -P
tools/make_example_campaign.py).

One hour of a simulated laser gyro at rest (pulse output, τ = 1 s), seed 4557.
"""

from __future__ import annotations

from pathlib import Path

import numpy as np

from metro.instruments.simulated import GyroTruth, simulate_static

OUT = Path(__file__).resolve().parents[1] / "docs" / "examples" / "campaign"


def main() -> None:
    truth = GyroTruth(seed=4557)
    data = simulate_static(truth, n=3600, interval_s=1.0, latitude_deg=39.98)
    lines = ["# one hour at rest, IRA up; pulses accumulated over each 1 s interval",
             "time [s],output [P]"]
    lines += [f"{i + 1},{int(v)}" for i, v in enumerate(np.asarray(data))]
    (OUT / "static-1h.csv").write_text("\n".join(lines) + "\n", encoding="utf-8")


if __name__ == "__main__":
    main()

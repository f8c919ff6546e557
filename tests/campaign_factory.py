"""Write small valid campaigns (manifest + samples) for tests; each test then breaks one thing."""

from __future__ import annotations

from pathlib import Path


from metro.instruments.simulated import GyroTruth, simulate_static

MANIFEST = """\
format = "metro-campaign/1"

[campaign]
id = "TEST-001"
operator = "test"

[device]
id = "LG-0042"
manufacturer = "Acme Inertial"
model = "RLG-90"
serial = "0042"
technology = "laser"
application = "aviation"
output = "pulse"
scale_factor = "{K} P/″"
scale_factor_U = "4 ppm"
scale_factor_k = 2

[environment]
temperature = "20.5 °C"
humidity = "45 %"

[site]
latitude = "{lat}°"
latitude_uncertainty = "0.001°"

[[equipment]]
id = "PLAT-1"
role = "platform"
model = "granite platform"
levelness = "2″"

[[equipment]]
id = "CNT-1"
role = "counter"
manufacturer = "Keysight"
model = "53230A"
serial = "MY1234"
[equipment.calibration]
certificate = "CNAS-2026-0815"
U = "2e-7"
k = 2
due = 2027-08-15
lab = "NIM"

[[segments]]
id = "static-1"
kind = "static"
file = "static.csv"
sample_interval = "1 s"
[segments.conditions]
orientation = "IRA up"
temperature = "20 °C"
warmup = "30 min"
"""


def write_campaign(
    root: Path,
    *,
    hours: float = 1.0,
    truth: GyroTruth | None = None,
    lat: float = 39.98,
    time_column: bool = True,
    manifest_edit=None,
    data_edit=None,
) -> Path:
    """Write ``manifest.toml`` and ``static.csv`` under ``root``; return the manifest path."""
    truth = truth or GyroTruth()
    n = int(hours * 3600)
    data = simulate_static(truth, n=n, interval_s=1.0, latitude_deg=lat)
    text = MANIFEST.format(K=truth.scale_factor_P_per_arcsec, lat=lat)
    if manifest_edit:
        text = manifest_edit(text)
    root.mkdir(parents=True, exist_ok=True)
    lines = []
    if time_column:
        lines.append("time [s],output [P]")
        lines += [f"{i + 1},{int(v)}" for i, v in enumerate(data)]
    else:
        lines.append("output [P]")
        lines += [f"{int(v)}" for v in data]
    csv = "\n".join(lines) + "\n"
    if data_edit:
        csv = data_edit(csv)
    (root / "static.csv").write_text(csv, encoding="utf-8")
    (root / "manifest.toml").write_text(text, encoding="utf-8")
    return root / "manifest.toml"

"""Write small valid campaigns (manifest + samples) for tests; each test then breaks one thing."""

from __future__ import annotations

from pathlib import Path

from metro.instruments.simulated import GyroTruth, simulate_static

# the manifest, with {K} and {lat} to fill in
MANIFEST = (Path(__file__).parent / "data" / "campaign_manifest.toml").read_text(encoding="utf-8")


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

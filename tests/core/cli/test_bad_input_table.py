"""A table of bad inputs through the real command line (issue 14, "Bad input").

Every case: exit code 2, a message naming the right file and field, no traceback, and nothing
written — the folder holding the campaign and the output folder are compared byte for byte
before and after.  Cases cover the manifest, samples in CSV, .npy and Parquet, item options,
station options, output paths and plugins.  Most run in-process (``metro.core.cli.app.main``); a few
run ``metro`` as a real subprocess.

Each case is (id, edit, expected file, expected field, extra CLI arguments):
* ``edit`` changes the base campaign (campaign_factory: one static segment of a laser gyro,
  D.5.1): ``M(old, new)`` replaces text in the manifest, ``C(...)`` in the CSV, ``NPY(...)`` /
  ``PQ(...)`` write the samples as .npy / Parquet with a defect;
* the expected file is ``"manifest"``, ``"samples"`` or ``None`` (an option: no file);
* the expected field is the text the message shows as ``field '…'`` (``None``: no field).
"""

from __future__ import annotations

import hashlib
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

ITEM = ("-s", "gbt45570", "-i", "D.5.1")


# -----------------------------------------------------------------------------------------
# edits of the base campaign
# -----------------------------------------------------------------------------------------


def M(old: str, new: str, count: int = 1):
    """Replace ``old`` by ``new`` in the manifest (must occur)."""
    def edit(root: Path):
        m = root / "manifest.toml"
        t = m.read_text(encoding="utf-8")
        assert old in t, old
        m.write_text(t.replace(old, new, count), encoding="utf-8")
    return edit


def MB(data: bytes):
    """The manifest replaced by these bytes."""
    def edit(root: Path):
        (root / "manifest.toml").write_bytes(data)
    return edit


def CELL(value: str, row: int = 5, col: int = 1):
    """Row ``row`` (1 = first data row), column ``col`` of the CSV set to ``value``."""
    def edit(root: Path):
        p = root / "static.csv"
        lines = p.read_text(encoding="utf-8").split("\n")
        cells = lines[row].split(",")
        cells[col] = value
        lines[row] = ",".join(cells)
        p.write_text("\n".join(lines), encoding="utf-8")
    return edit


def C(fn):
    """The CSV text through ``fn``."""
    def edit(root: Path):
        p = root / "static.csv"
        p.write_text(fn(p.read_text(encoding="utf-8")), encoding="utf-8")
    return edit


def CB(fn):
    """The CSV bytes through ``fn``."""
    def edit(root: Path):
        p = root / "static.csv"
        p.write_bytes(fn(p.read_bytes()))
    return edit


def _columns(root: Path) -> tuple[np.ndarray, np.ndarray]:
    data = np.loadtxt(root / "static.csv", delimiter=",", skiprows=1)
    return data[:, 0], data[:, 1]


def _point_to(root: Path, name: str) -> None:
    m = root / "manifest.toml"
    m.write_text(m.read_text(encoding="utf-8").replace('file = "static.csv"', f'file = "{name}"'),
                 encoding="utf-8")
    (root / "static.csv").unlink()


def NPY(fn, *, raw: bytes | None = None):
    """Samples as a structured .npy: ``fn(time, output)`` returns the array to save (or, with
    ``raw``, the file's bytes are these)."""
    def edit(root: Path):
        t, o = _columns(root)
        p = root / "static.npy"
        if raw is not None:
            p.write_bytes(raw)
        else:
            arr = fn(t, o)
            np.save(p, arr, allow_pickle=True)
        _point_to(root, "static.npy")
    return edit


def _struct(t, o, names=("time [s]", "output [P]"), dtype=float):
    a = np.zeros(t.size, dtype=[(names[0], float), (names[1], dtype)])
    a[names[0]] = t
    a[names[1]] = o
    return a


def PQ(fn=None, *, raw: bytes | None = None):
    """Samples as Parquet: ``fn(time, output)`` returns {column name: values}."""
    def edit(root: Path):
        import pyarrow as pa
        import pyarrow.parquet as pq

        t, o = _columns(root)
        p = root / "static.parquet"
        if raw is not None:
            p.write_bytes(raw)
        else:
            pq.write_table(pa.table(fn(t, o)), p)
        _point_to(root, "static.parquet")
    return edit


def _npy_truncated(root_bytes_fn):
    return root_bytes_fn


def NPY_CUT(keep: int):
    def edit(root: Path):
        t, o = _columns(root)
        p = root / "static.npy"
        np.save(p, _struct(t, o))
        p.write_bytes(p.read_bytes()[:keep])
        _point_to(root, "static.npy")
    return edit


def PQ_CUT(keep: int):
    def edit(root: Path):
        import pyarrow as pa
        import pyarrow.parquet as pq

        t, o = _columns(root)
        p = root / "static.parquet"
        pq.write_table(pa.table({"time [s]": t, "output [P]": o}), p)
        p.write_bytes(p.read_bytes()[:keep])
        _point_to(root, "static.parquet")
    return edit


def NOTHING(root: Path) -> None:
    pass


def TOP(line: str, *more):
    """A top-level line at the start of the manifest, then the edits ``more``."""
    def edit(root: Path):
        m = root / "manifest.toml"
        m.write_text(line + "\n" + m.read_text(encoding="utf-8"), encoding="utf-8")
        for e in more:
            e(root)
    return edit


BIG = "D" * 1_000_000

# -----------------------------------------------------------------------------------------
# the table
# -----------------------------------------------------------------------------------------

MANIFEST_CASES = [
    # file-level
    ("toml-syntax", M('id = "TEST-001"', 'id = "TEST-001'), "manifest", None),
    ("format-version", M('format = "metro-campaign/1"', 'format = "metro-campaign/2"'), "manifest",
     "format"),
    ("format-number", M('format = "metro-campaign/1"', "format = 1"), "manifest", "format"),
    ("not-utf8", MB(b'format = "metro-campaign/1"\n[device]\nid = "\xff\xfe"\n'), "manifest", None),
    ("empty-manifest", MB(b""), "manifest", "[device]"),
    ("binary-manifest", MB(bytes(range(256)) * 4), "manifest", None),
    # [campaign]
    ("campaign-not-table", M("[campaign]\n", 'campaign = "x"\n[campaign-old]\n'), "manifest",
     "campaign"),
    ("campaign-simulated-text", M('operator = "test"', 'operator = "test"\nsimulated = "yes"'),
     "manifest",
     "campaign.simulated"),
    ("campaign-date-text", M('operator = "test"', 'measurement_date = "yesterday"'), "manifest",
     "campaign.measurement_date"),
    ("campaign-old-date-bad", M('operator = "test"', 'date = "20/11/2026"'), "manifest",
     "campaign.date"),
    ("campaign-received-bad", M('operator = "test"', 'date_received = 42'), "manifest",
     "campaign.date_received"),
    ("campaign-operator-number", M('operator = "test"', "operator = 42"), "manifest",
     "campaign.operator"),
    ("campaign-lab-array", M('operator = "test"', 'lab = ["a", "b"]'), "manifest", "campaign.lab"),
    ("campaign-both-spellings", M('operator = "test"', 'lab = "A"\nlaboratory = "B"'), "manifest",
     "campaign.laboratory"),
    ("campaign-both-people", M('operator = "test"', 'operator = "A"\ntested_by = "B"'), "manifest",
     "campaign.tested_by"),
    ("campaign-customer-long", M('operator = "test"', 'customer = "' + "c" * 600 + '"'), "manifest",
     "campaign.customer"),
    ("campaign-id-long", M('id = "TEST-001"', 'id = "' + "i" * 501 + '"'), "manifest",
     "campaign.id"),
    # [device]
    ("device-missing", M("[device]", "[devices]"), "manifest", "[device]"),
    ("device-not-table", TOP('device = "x"', M("[device]", "[device-old]")), "manifest", "device"),
    ("device-id-missing", M('id = "LG-0042"\n', ""), "manifest", "device.id"),
    ("device-id-empty", M('id = "LG-0042"', 'id = ""'), "manifest", "device.id"),
    ("device-id-blank", M('id = "LG-0042"', 'id = "  "'), "manifest", "device.id"),
    ("device-id-bool", M('id = "LG-0042"', "id = true"), "manifest", "device.id"),
    ("device-id-1MB", M('id = "LG-0042"', f'id = "{BIG}"'), "manifest", "device.id"),
    ("device-id-control", M('id = "LG-0042"', 'id = "LG\\u0007"'), "manifest", "device.id"),
    ("device-model-long", M('model = "RLG-90"', 'model = "' + "m" * 501 + '"'), "manifest",
     "device.model"),
    ("device-serial-table", M('serial = "0042"', "serial = {a = 1}"), "manifest", "device.serial"),
    ("device-technology", M('technology = "laser"', 'technology = "quantum"'), "manifest",
     "device.technology"),
    ("device-output", M('output = "pulse"', 'output = "optical"'), "manifest", "device.output"),
    ("device-application", M('application = "aviation"', 'application = "submarine"'), "manifest",
     "device.application"),
    ("device-application-typo", M('application = "aviation"', 'application = "aviaton"'),
     "manifest",
     "device.application"),
    ("K-zero", M('scale_factor = "', 'scale_factor = "0 P/″" #'), "manifest",
     "device.scale_factor"),
    ("K-negative", M('scale_factor = "', 'scale_factor = "-0.8 P/″" #'), "manifest",
     "device.scale_factor"),
    ("K-inf", M('scale_factor = "', 'scale_factor = "inf P/″" #'), "manifest",
     "device.scale_factor"),
    ("K-nan", M('scale_factor = "', 'scale_factor = "nan P/″" #'), "manifest",
     "device.scale_factor"),
    ("K-bananas", M('scale_factor = "', 'scale_factor = "0.8 bananas" #'), "manifest",
     "device.scale_factor"),
    ("K-array", M('scale_factor = "', 'scale_factor = [1, 2] #'), "manifest",
     "device.scale_factor"),
    ("K-bool", M('scale_factor = "', 'scale_factor = true #'), "manifest", "device.scale_factor"),
    ("K-wrong-kind", M('scale_factor = "', 'scale_factor = "0.8 P/s" #'), "manifest",
     "device.scale_factor"),
    ("K-U-negative", M('scale_factor_U = "4 ppm"', 'scale_factor_U = "-4 ppm"'), "manifest",
     "device.scale_factor_U"),
    ("K-U-inf", M('scale_factor_U = "4 ppm"', 'scale_factor_U = "inf ppm"'), "manifest",
     "device.scale_factor_U"),
    ("K-k-zero", M("scale_factor_k = 2", "scale_factor_k = 0"), "manifest",
     "device.scale_factor_k"),
    ("K-k-text", M("scale_factor_k = 2", 'scale_factor_k = "two"'), "manifest",
     "device.scale_factor_k"),
    ("K-k-negative", M("scale_factor_k = 2", "scale_factor_k = -2"), "manifest",
     "device.scale_factor_k"),
    ("device-prop-inf", M('technology = "laser"', 'technology = "laser"\nnonlinearity = "inf ppm"'),
     "manifest",
     "device.nonlinearity"),
    ("device-prop-nan-float", M('technology = "laser"', 'technology = "laser"\ngain = nan'),
     "manifest",
     "device.gain"),
    ("device-prop-long-text", M('technology = "laser"', 'technology = "laser"\nnote = "' + "n"
                                * 600 + '"'),
     "manifest", "device.note"),
    # [environment]
    ("env-missing", M("[environment]", "[environ]"), "manifest", "[environment]"),
    ("env-temperature-missing", M('temperature = "20.5 °C"\n', ""), "manifest",
     "environment.temperature"),
    ("env-temperature-inf", M('temperature = "20.5 °C"', 'temperature = "inf °C"'), "manifest",
     "environment.temperature"),
    ("env-temperature-nan", M('temperature = "20.5 °C"', 'temperature = "nan °C"'), "manifest",
     "environment.temperature"),
    ("env-temperature-300", M('temperature = "20.5 °C"', 'temperature = "-300 °C"'), "manifest",
     "environment.temperature"),
    ("env-temperature-0K", M('temperature = "20.5 °C"', 'temperature = "0 K"'), "manifest",
     "environment.temperature"),
    ("env-temperature-5000", M('temperature = "20.5 °C"', 'temperature = "5000 °C"'), "manifest",
     "environment.temperature"),
    ("env-temperature-metres", M('temperature = "20.5 °C"', 'temperature = "20 m"'), "manifest",
     "environment.temperature"),
    ("env-temperature-bare", M('temperature = "20.5 °C"', "temperature = 20"), "manifest",
     "environment.temperature"),
    ("env-humidity-150", M('humidity = "45 %"', 'humidity = "150 %"'), "manifest",
     "environment.humidity"),
    ("env-humidity-negative", M('humidity = "45 %"', 'humidity = "-5 %"'), "manifest",
     "environment.humidity"),
    ("env-humidity-missing", M('humidity = "45 %"\n', ""), "manifest", "environment.humidity"),
    ("env-humidity-kelvin", M('humidity = "45 %"', 'humidity = "45 K"'), "manifest",
     "environment.humidity"),
    ("env-pressure-negative", M('humidity = "45 %"', 'humidity = "45 %"\npressure = "-1 kPa"'),
     "manifest",
     "environment.pressure"),
    ("env-pressure-mass", M('humidity = "45 %"', 'humidity = "45 %"\npressure = "101 kg"'),
     "manifest",
     "environment.pressure"),
    ("env-field-nan", M('humidity = "45 %"', 'humidity = "45 %"\nmagnetic_field = "nan mT"'),
     "manifest",
     "environment.magnetic_field"),
    # [site]
    ("site-missing", M("[site]", "[place]"), "manifest", "[site]"),
    ("site-latitude-missing", M('latitude = "', 'lat = "'), "manifest", "site.latitude"),
    ("site-latitude-95", M('latitude = "39.98°"', 'latitude = "95°"'), "manifest", "site.latitude"),
    ("site-latitude-metres", M('latitude = "39.98°"', 'latitude = "39.98 m"'), "manifest",
     "site.latitude"),
    ("site-latitude-inf", M('latitude = "39.98°"', 'latitude = "inf°"'), "manifest",
     "site.latitude"),
    ("site-latitude-nan", M('latitude = "39.98°"', 'latitude = "nan°"'), "manifest",
     "site.latitude"),
    ("site-latitude-bare", M('latitude = "39.98°"', "latitude = 39.98"), "manifest",
     "site.latitude"),
    ("site-latU-negative", M('latitude_uncertainty = "0.001°"', 'latitude_uncertainty = "-0.001°"'),
     "manifest",
     "site.latitude_uncertainty"),
    ("site-latU-metres", M('latitude_uncertainty = "0.001°"', 'latitude_uncertainty = "1 m"'),
     "manifest",
     "site.latitude_uncertainty"),
    ("site-latU-text", M('latitude_uncertainty = "0.001°"', 'latitude_uncertainty = "small"'),
     "manifest",
     "site.latitude_uncertainty"),
    ("site-latU-huge", M('latitude_uncertainty = "0.001°"', 'latitude_uncertainty = "100°"'),
     "manifest",
     "site.latitude_uncertainty"),
    ("site-altitude-inf", M('latitude_uncertainty = "0.001°"',
                            'latitude_uncertainty = "0.001°"\naltitude = "inf m"'),
     "manifest", "site.altitude"),
    # [[equipment]]
    ("equipment-not-array", TOP("equipment = 3", M("[[equipment]]", "[[equipment-x]]", 2),
                                                 M("[equipment.calibration]",
                                                   "[equipment-x.calibration]")), "manifest",
     "equipment"),
    ("equipment-id-missing", M('id = "PLAT-1"\n', ""), "manifest", "equipment[0].id"),
    ("equipment-id-empty", M('id = "PLAT-1"', 'id = ""'), "manifest", "equipment[0].id"),
    ("equipment-id-duplicate", M('id = "CNT-1"', 'id = "PLAT-1"'), "manifest", "equipment[1].id"),
    ("equipment-role-missing", M('role = "platform"\n', ""), "manifest", "equipment[0].role"),
    ("equipment-role-bool", M('role = "platform"', "role = true"), "manifest", "equipment[0].role"),
    ("equipment-prop-inf", M('levelness = "2″"', 'levelness = "inf″"'), "manifest",
     "equipment[0].levelness"),
    ("calibration-not-table", M("[equipment.calibration]\n",
                                "calibration = 5\n[equipment-calibration]\n"),
     "manifest", "equipment[1].calibration"),
    ("calibration-U-missing", M('U = "2e-7"\n', ""), "manifest", "equipment[1].calibration.U"),
    ("calibration-U-negative", M('U = "2e-7"', 'U = "-2e-7"'), "manifest",
     "equipment[1].calibration.U"),
    ("calibration-U-inf", M('U = "2e-7"', 'U = "inf"'), "manifest", "equipment[1].calibration.U"),
    ("calibration-U-bananas", M('U = "2e-7"', 'U = "2 bananas"'), "manifest",
     "equipment[1].calibration.U"),
    ("calibration-U-array", M('U = "2e-7"', "U = [1]"), "manifest", "equipment[1].calibration.U"),
    ("calibration-U-celsius", M('U = "2e-7"', 'U = "2 °C"'), "manifest",
     "equipment[1].calibration.U"),
    ("calibration-U-seconds", M('U = "2e-7"', 'U = "1 ns"'), "manifest",
     "equipment[1].calibration.U"),
    ("calibration-k-zero", M("\nk = 2\n", "\nk = 0\n"), "manifest", "equipment[1].calibration.k"),
    ("calibration-k-negative", M("\nk = 2\n", "\nk = -2\n"), "manifest",
     "equipment[1].calibration.k"),
    ("calibration-k-bool", M("\nk = 2\n", "\nk = true\n"), "manifest",
     "equipment[1].calibration.k"),
    ("calibration-k-inf", M("\nk = 2\n", "\nk = inf\n"), "manifest", "equipment[1].calibration.k"),
    ("K-k-bool", M("scale_factor_k = 2", "scale_factor_k = true"), "manifest",
     "device.scale_factor_k"),
    ("K-k-inf", M("scale_factor_k = 2", "scale_factor_k = inf"), "manifest",
     "device.scale_factor_k"),
    ("calibration-due-text", M("due = 2027-08-15", 'due = "next year"'), "manifest",
     "equipment[1].calibration.due"),
    ("calibration-distribution", M('lab = "NIM"', 'lab = "NIM"\ndistribution = "cauchy"'),
     "manifest",
     "equipment[1].calibration.distribution"),
    ("calibration-certificate-missing", M('certificate = "CNAS-2026-0815"\n', ""), "manifest",
     "equipment[1].calibration.certificate"),
    # [[segments]]
    ("segments-missing", M("[[segments]]", "[[segment]]"), "manifest", "segments"),
    ("segments-not-array", M("[[segments]]\nid", "segments = 3\n[[segx]]\nid"), "manifest",
     "segments"),
    ("segment-id-missing", M('id = "static-1"\n', ""), "manifest", "segments[0].id"),
    ("segment-id-empty", M('id = "static-1"', 'id = ""'), "manifest", "segments[0].id"),
    ("segment-kind-missing", M('kind = "static"\n', ""), "manifest", "segments[0].kind"),
    ("segment-file-missing", M('file = "static.csv"\n', ""), "manifest", "segments[0].file"),
    ("segment-file-absent", M('file = "static.csv"', 'file = "nope.csv"'), "manifest",
     "segments[0].file"),
    ("segment-file-folder", M('file = "static.csv"', 'file = "."'), "manifest", "segments[0].file"),
    ("segment-file-suffix", M('file = "static.csv"', 'file = "manifest.toml"'), "manifest", None),
    ("interval-missing", M('sample_interval = "1 s"\n', ""), "manifest",
     "segments[0].sample_interval"),
    ("interval-zero", M('sample_interval = "1 s"', 'sample_interval = "0 s"'), "manifest",
     "segments[0].sample_interval"),
    ("interval-negative", M('sample_interval = "1 s"', 'sample_interval = "-1 s"'), "manifest",
     "segments[0].sample_interval"),
    ("interval-inf", M('sample_interval = "1 s"', 'sample_interval = "inf s"'), "manifest",
     "segments[0].sample_interval"),
    ("interval-metres", M('sample_interval = "1 s"', 'sample_interval = "1 m"'), "manifest",
     "segments[0].sample_interval"),
    ("interval-bare", M('sample_interval = "1 s"', "sample_interval = 1"), "manifest",
     "segments[0].sample_interval"),
    ("interval-vs-time", M('sample_interval = "1 s"', 'sample_interval = "2 s"'), "samples",
     "time"),
    ("conditions-not-table", M("[segments.conditions]\n",
                               "conditions = 1\n[segments-conditions]\n"), "manifest",
     "segments[0].conditions"),
    ("condition-orientation", M('orientation = "IRA up"', 'orientation = "sideways"'), "manifest",
     "segments.static-1.conditions.orientation"),
    ("condition-temperature-inf", M('temperature = "20 °C"', 'temperature = "inf °C"'), "manifest",
     "segments[0].conditions.temperature"),
    ("units-bananas", M('warmup = "30 min"',
                        'warmup = "30 min"\n[segments.units]\noutput = "bananas"'), "manifest",
     "segments[0].units.output"),
    ("units-number", M('warmup = "30 min"', 'warmup = "30 min"\n[segments.units]\noutput = 5'),
     "manifest",
     "segments[0].units.output"),
    ("units-not-header", M('warmup = "30 min"',
                           'warmup = "30 min"\n[segments.units]\noutput = "LSB"'), "samples",
     "output"),
    ("segment-id-duplicate", M("[[segments]]",
                               '[[segments]]\nid = "static-1"\nkind = "static"\nfile = '
                               '"static.csv"\nsample_interval = "1 s"\n\n[[segments]]'), "manifest",
     "segments[1].id"),
    # [specification]
    ("spec-wrong-kind", M("[[segments]]", '[specification]\nB0 = "<= 5 ppm"\n\n[[segments]]'),
     "manifest",
     "specification.B0"),
    ("spec-wrong-kind-Kn", M("[[segments]]", '[specification]\nKn = "<= 5 °/h"\n\n[[segments]]'),
     "manifest",
     "specification.Kn"),
    ("spec-unreadable", M("[[segments]]", '[specification]\nB0 = "about 5"\n\n[[segments]]'),
     "manifest",
     "specification.B0"),
    ("spec-number", M("[[segments]]", "[specification]\nB0 = 5\n\n[[segments]]"), "manifest",
     "specification.B0"),
    ("spec-rule", M("[[segments]]", '[specification]\ndecision_rule = "lenient"\n\n[[segments]]'),
     "manifest",
     "specification.decision_rule"),
    ("spec-inverted-range", M("[[segments]]",
                              '[specification]\nB0 = "1 .. -1 °/h"\n\n[[segments]]'), "manifest",
     "specification.B0"),
]

CSV_CASES = [
    ("csv-empty-cell", CELL(""), "samples", "output [P], row 5"),
    ("csv-text", CELL("abc"), "samples", "output [P], row 5"),
    ("csv-nan", CELL("nan"), "samples", "output [P], row 5"),
    ("csv-inf", CELL("inf"), "samples", "output [P], row 5"),
    ("csv-1e20", CELL("1e20"), "samples", "output"),
    ("csv-1e308", CELL("1e308"), "samples", "output"),
    ("csv-minus-1e308", CELL("-1e308"), "samples", "output"),
    ("csv-1e309", CELL("1e309"), "samples", "output [P], row 5"),
    ("csv-header-no-unit", C(lambda t: t.replace("output [P]", "output", 1)), "samples", None),
    ("csv-header-bananas", C(lambda t: t.replace("output [P]", "output [bananas]", 1)), "samples",
     "output"),
    ("csv-header-celsius", C(lambda t: t.replace("output [P]", "output [°C]", 1)), "samples",
     "output"),
    ("csv-no-output", C(lambda t: t.replace("output [P]", "signal [P]", 1)), "samples", "output"),
    ("csv-duplicate-column", C(lambda t: t.replace("time [s],output [P]", "output [P],output [P]",
                                                   1)), "samples",
     None),
    ("csv-time-metres", C(lambda t: t.replace("time [s]", "time [m]", 1)), "samples", "time"),
    ("csv-time-backwards", C(lambda t: t.replace("\n5,", "\n3,", 1)), "samples", "time"),
    ("csv-time-gap", C(lambda t: "\n".join(
        [line if i < 10 or not line else f"{int(line.split(',')[0]) + 50},{line.split(',')[1]}"
         for i, line in enumerate(t.split("\n"))])), "samples", "time"),
    ("csv-extra-cell", CELL("1,2"), "samples", "row 5"),
    ("csv-truncated", CB(lambda b: b.rstrip(b"\n")[:-1]), "samples", None),
    ("csv-empty-file", CB(lambda b: b""), "samples", None),
    ("csv-header-only", CB(lambda b: b.split(b"\n")[0] + b"\n"), "samples", None),
    ("csv-not-utf8", CB(lambda b: b.replace(b"output", b"outp\xffut", 1)), "samples", None),
    ("csv-nul-byte", CB(lambda b: b.replace(b"\n5,", b"\n5\x00,", 1)), "samples", None),
    ("csv-two-rows", CB(lambda b: b"\n".join(b.split(b"\n")[:3]) + b"\n"), "samples", "output"),
    ("csv-comment-after-header", C(lambda t: t.replace("\n5,", "\n# note\n5,", 1)), "samples",
     None),
    ("csv-hex", CELL("0x10"), "samples", "output [P], row 5"),
]

NPY_CASES = [
    ("npy-no-units", NPY(lambda t, o: _struct(t, o, names=("time", "output"))), "samples", None),
    ("npy-plain-array", NPY(lambda t, o: o), "samples", None),
    ("npy-nan", NPY(lambda t, o: _struct(t, np.where(np.arange(o.size) == 4, np.nan, o))),
     "samples", None),
    ("npy-1e20", NPY(lambda t, o: _struct(t, np.where(np.arange(o.size) == 4, 1e20, o))), "samples",
     "output"),
    ("npy-1e308", NPY(lambda t, o: _struct(t, np.where(np.arange(o.size) == 4, -1e308, o))),
     "samples", "output"),
    ("npy-object", NPY(lambda t, o: np.array([{"a": 1}] * 3, dtype=object)), "samples", None),
    ("npy-wrong-unit", NPY(lambda t, o: _struct(t, o, names=("time [s]", "output [°C]"))),
     "samples", "output"),
    ("npy-no-output", NPY(lambda t, o: _struct(t, o, names=("time [s]", "signal [P]"))), "samples",
     "output"),
    ("npy-truncated", NPY_CUT(200), "samples", None),
    ("npy-header-only", NPY_CUT(64), "samples", None),
    ("npy-garbage", NPY(None, raw=b"not a numpy file at all"), "samples", None),
    ("npy-big-int", NPY(lambda t, o: _struct(t, np.full(o.size, 2**60), dtype=np.int64)), "samples",
     None),
    ("npy-time-backwards", NPY(lambda t, o: _struct(t[::-1].copy(), o)), "samples", "time"),
]

PARQUET_CASES = [
    ("pq-no-units", PQ(lambda t, o: {"time": t, "output": o}), "samples", None),
    ("pq-nan", PQ(lambda t, o: {"time [s]": t,
                                "output [P]": np.where(np.arange(o.size) == 4, np.nan, o)}),
     "samples", None),
    ("pq-1e20", PQ(lambda t, o: {"time [s]": t,
                                 "output [P]": np.where(np.arange(o.size) == 4, 1e20, o)}),
     "samples", "output"),
    ("pq-text-column", PQ(lambda t, o: {"time [s]": t, "output [P]": [str(x) for x in o]}),
     "samples", None),
    ("pq-no-output", PQ(lambda t, o: {"time [s]": t, "signal [P]": o}), "samples", "output"),
    ("pq-wrong-unit", PQ(lambda t, o: {"time [s]": t, "output [°/s/s]": o}), "samples", "output"),
    ("pq-truncated", PQ_CUT(100), "samples", None),
    ("pq-garbage", PQ(raw=b"PAR1 this is not parquet PAR1"), "samples", None),
    ("pq-time-gap", PQ(lambda t, o: {"time [s]": np.where(t > 100, t + 50, t), "output [P]": o}),
     "samples", "time"),
]

# item options (-o) on a recorded campaign: no file; the field names the option
OPTION_CASES = [
    ("option-unknown", NOTHING, None, None, ("-o", "batchs=20")),
    ("option-not-name-value", NOTHING, None, None, ("-o", "batches")),
    ("option-batches-text", NOTHING, None, "option batches", ("-o", "batches=many")),
    ("option-batches-zero", NOTHING, None, "option batches", ("-o", "batches=0")),
    ("option-batches-negative", NOTHING, None, "option batches", ("-o", "batches=-3")),
    ("option-batches-fraction", NOTHING, None, "option batches", ("-o", "batches=2.5")),
    ("option-segment-unknown", NOTHING, None, None, ("-o", "segment=nope")),
    ("decision-rule-cli", NOTHING, None, None, ("--decision-rule", "lenient")),
]

# station options (no --data): refused before anything is simulated
STATION_CASES = [
    ("station-output-analog", ("output=analog",), "station option output"),
    ("station-polarity-2", ("polarity=2",), "station option polarity"),
    ("station-duration-zero", ("duration_scale=0",), "station option duration_scale"),
    ("station-duration-negative", ("duration_scale=-1",), "station option duration_scale"),
    ("station-duration-1e9", ("duration_scale=1e9",), "station option duration_scale"),
    ("station-duration-inf", ("duration_scale=inf",), "station option duration_scale"),
    ("station-duration-nan", ("duration_scale=nan",), "station option duration_scale"),
    ("station-duration-text", ("duration_scale=short",), "station option duration_scale"),
    ("station-latitude-95", ("latitude_deg=95",), "station option latitude_deg"),
    ("station-unknown", ("table_error=false",), "station option table_error"),
    ("station-bool", ("table_errors=maybe",), "station option table_errors"),
    ("station-not-name-value", ("duration_scale",), None),
]

OUTPUT_CASES = [
    ("report-txt", "r.txt", (), "--report"),
    ("report-no-suffix", "report", (), "--report"),
    ("report-doc", "r.doc", (), "--report"),
    ("report-onto-manifest", "{camp}/manifest.toml", ("--force",), "--report"),
    ("report-onto-samples", "{camp}/static.csv", ("--force",), "--report"),
    ("report-existing", "{root}/old.docx", (), "--report"),
    ("report-existing-readonly", "{root}/ro.docx", ("--force",), "--report"),
    ("report-is-folder", "{root}/folder.docx", ("--force",), "--report"),
    ("report-under-file", "{root}/afile/r.docx", (), "--report"),
]


def _snapshot(root: Path) -> dict[str, str]:
    out = {}
    for p in sorted(root.rglob("*")):
        rel = str(p.relative_to(root))
        if p.is_symlink():
            out[rel] = "link"
        elif p.is_dir():
            out[rel] = "dir"
        else:
            out[rel] = hashlib.sha256(p.read_bytes()).hexdigest() + oct(p.stat().st_mode)
    return out


def _check(code, out, err, before, root, file, field):
    assert code == 2, f"exit {code}, stderr:\n{err}"
    assert "Traceback" not in err and "Traceback" not in out
    assert "metro: error:" in err
    if file is not None:
        assert str(file) in err, f"{file} not named in:\n{err}"
    if field is not None:
        assert f"field '{field}" in err, f"field {field!r} not named in:\n{err}"
    assert len(err) < 5000  # the message never quotes a megabyte
    assert _snapshot(root) == before, "something was written or changed"


@pytest.fixture
def base(tmp_path, campaign_factory):
    """(root, campaign folder, output folder): a valid D.5.1 campaign to break."""
    camp = tmp_path / "c"
    campaign_factory.write_campaign(camp, hours=0.1)
    return tmp_path, camp, tmp_path / "out"


def _sample_file(camp: Path) -> Path:
    for name in ("static.csv", "static.npy", "static.parquet"):
        if (camp / name).exists():
            return camp / name
    return camp / "static.csv"


@pytest.mark.parametrize("case", MANIFEST_CASES + CSV_CASES + NPY_CASES + PARQUET_CASES,
                         ids=lambda c: c[0])
def test_bad_campaign(case, base, run_cli):
    name, edit, which, field = case
    root, camp, out = base
    edit(camp)
    before = _snapshot(root)
    m = camp / "manifest.toml"
    code, stdout, err = run_cli("run", *ITEM, "--data", str(m), "--out", str(out), "--no-progress")
    file = {"manifest": m, "samples": _sample_file(camp).resolve(), None: None}[which]
    _check(code, stdout, err, before, root, file, field)


@pytest.mark.parametrize("case", OPTION_CASES, ids=lambda c: c[0])
def test_bad_option(case, base, run_cli):
    name, edit, which, field, extra = case
    root, camp, out = base
    before = _snapshot(root)
    argv = ("run", *ITEM, "--data", str(camp / "manifest.toml"), "--out", str(out), "--no-progress",
            *extra)
    if name == "decision-rule-cli":  # argparse's own refusal: exit 2, no traceback
        from metro.core.cli.app import main

        try:
            code = main(list(argv))
        except SystemExit as exc:  # argparse's exit, when main does not turn it into a code
            code = exc.code
        assert code == 2 and _snapshot(root) == before
        return
    code, stdout, err = run_cli(*argv)
    _check(code, stdout, err, before, root, None, field)
    if field is None:
        assert extra[1].split("=")[0] in err


@pytest.mark.parametrize("case", STATION_CASES, ids=lambda c: c[0])
def test_bad_station_option(case, tmp_path, run_cli):
    name, opts, field = case
    out = tmp_path / "out"
    before = _snapshot(tmp_path)
    args = [a for o in opts for a in ("--station-option", o)]
    code, stdout, err = run_cli("run", *ITEM, "--out", str(out), "--no-progress", *args)
    _check(code, stdout, err, before, tmp_path, None, field)


@pytest.mark.parametrize("case", OUTPUT_CASES, ids=lambda c: c[0])
def test_bad_output_path(case, base, run_cli):
    name, target, extra, field = case
    root, camp, out = base
    (root / "old.docx").write_bytes(b"an earlier report")
    (root / "ro.docx").write_bytes(b"a signed report")
    (root / "ro.docx").chmod(0o444)
    (root / "folder.docx").mkdir()
    (root / "afile").write_text("x")
    path = target.format(root=root, camp=camp) if "{" in target else str(root / target)
    before = _snapshot(root)
    try:
        code, stdout, err = run_cli("run", *ITEM, "--data", str(camp / "manifest.toml"), "--report",
                                    path,
                                    "--no-progress", *extra)
        _check(code, stdout, err, before, root, path, field)
    finally:
        (root / "ro.docx").chmod(0o644)


@pytest.mark.parametrize("args, field", [
    (("run", "-s", "nostandard", "-i", "D.5.1", "--no-report"), None),
    (("run", "-s", "gbt45570", "-i", "D.99", "--no-report"), None),
    (("run", "-s", "gbt45570", "--no-report"), None),
    (("run", "-s", "gbt45570", "-i", "D.5.1", "--station", "nostation", "--no-report"), None),
    (("run", "-s", "gbt45570", "-i", "D.5.1", "--data", "{root}/none.toml", "--no-report"), None),
    (("run", "-s", "gbt45570", "-i", "D.5.1", "--data", "{root}", "--no-report"), None),
    (("run", "-s", "gbt45570", "-i", "D.5.1", "--data", "{camp}/manifest.toml", "--station",
      "simulated",
      "--no-report"), None),
    (("plan", "-s", "gbt45570", "-i", "D.99"), None),
    (("acquire", "-s", "gbt45570", "-i", "D.5.1", "--out", "{camp}"), None),
], ids=["unknown-standard", "unknown-item", "no-item", "unknown-station", "manifest-absent",
        "manifest-is-folder", "data-and-station", "plan-unknown-item", "acquire-onto-campaign"])
def test_bad_command_line(args, field, base, run_cli):
    root, camp, out = base
    before = _snapshot(root)
    code, stdout, err = run_cli(*[a.format(root=root, camp=camp) for a in args], "--no-progress"
                                if args[0] in ("run", "acquire") else "--json")
    _check(code, stdout, err, before, root, None, field)


# -----------------------------------------------------------------------------------------
# plugins and real processes
# -----------------------------------------------------------------------------------------


def _metro(*args, env_extra=None, cwd=None):
    env = dict(os.environ)
    env.update(env_extra or {})
    return subprocess.run([sys.executable, "-m", "metro.core.cli.app", *args], capture_output=True,
                          text=True,
                          env=env, cwd=cwd, timeout=300)


@pytest.mark.parametrize("plugins, code_wanted", [
    ("no.such.module", 2),
    ("metro.plugins.gbt45570", 0),  # an installed plugin named by its module: loaded once, no clash
    ("metro.plugins.gbt45570,metro.plugins.jjf2014", 0),
])
def test_metro_plugins_environment(plugins, code_wanted, tmp_path):
    before = _snapshot(tmp_path)
    r = _metro("items", "--json", env_extra={"METRO_PLUGINS": plugins}, cwd=tmp_path)
    assert r.returncode == code_wanted, r.stderr
    assert "Traceback" not in r.stderr
    if code_wanted == 2:
        assert "no.such.module" in r.stderr
    assert _snapshot(tmp_path) == before


def test_blocked_plugin_standard_is_a_clean_error(tmp_path, run_cli):
    code, out, err = run_cli("--block-plugin", "gbt45570", "run", "-s", "gbt45570", "-i", "D.5.1",
                             "--no-report",
                             "--no-progress")
    assert code == 2 and "Traceback" not in err and "gbt45570" in err


def test_a_closed_stdout_ends_quietly(monkeypatch):
    """`metro plan … | head`: the reader has gone, the next write raises BrokenPipeError; metro
    ends with 141 (as a shell reports SIGPIPE) instead of a traceback."""
    from metro.core.cli.app import main

    r, w = os.pipe()

    class Closed:
        def write(self, text):
            raise BrokenPipeError(32, "Broken pipe")

        def flush(self):
            pass

        def fileno(self):
            return w

    monkeypatch.setattr(sys, "stdout", Closed())
    try:
        assert main(["plan", "-s", "gbt45570", "-i", "D.5.1", "--json"]) == 141
    finally:
        os.close(r)
        os.close(w)


def test_plan_into_a_closed_pipe_is_quiet(tmp_path):
    """The same through a real pipe: `metro items --json | head -c 1`."""
    cmd = f"{sys.executable} -m metro.core.cli.app items --json | head -c 1 > /dev/null"
    r = subprocess.run(["bash", "-c", cmd], capture_output=True, text=True, timeout=300)
    assert "Traceback" not in r.stderr and "BrokenPipe" not in r.stderr, r.stderr


def test_bad_manifest_in_a_real_process(tmp_path, campaign_factory):
    m = campaign_factory.write_campaign(tmp_path / "c", hours=0.05,
                                        manifest_edit=lambda t: t.replace(
                                            'humidity = "45 %"', 'humidity = "150 %"'))
    before = _snapshot(tmp_path)
    r = _metro("run", "-s", "gbt45570", "-i", "D.5.1", "--data", str(m), "--out",
               str(tmp_path / "out"),
               "--no-progress")
    assert r.returncode == 2 and "Traceback" not in r.stderr
    assert str(m) in r.stderr and "field 'environment.humidity'" in r.stderr
    assert _snapshot(tmp_path) == before


def test_the_table_has_at_least_150_cases():
    n = (len(MANIFEST_CASES) + len(CSV_CASES) + len(NPY_CASES) + len(PARQUET_CASES)
         + len(OPTION_CASES)
         + len(STATION_CASES) + len(OUTPUT_CASES) + 9 + 3 + 4)
    assert n >= 150, n

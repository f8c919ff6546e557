"""GB/T 45570—2025 clause 5 type test: inspection items 5.2.3–5.2.8, the 5.4 tests done elsewhere,
5.5 reliability, the clause-5 rows of the report; hand-worked values, the simulated station's
records, bad records."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest
from metro.core.run.manifest import load_manifest
from metro.core.base.errors import DataError
from metro.core.run.runner import run_items
from metro.plugins.gbt45570 import clause5, inspection, reliability

HEAD = """\
format = "metro-campaign/1"

[campaign]
id = "TYPE-001"

[device]
id = "FOG-7"
technology = "fibre"
application = "aviation"
output = "rate"

[environment]
temperature = "21 °C"
humidity = "40 %"

[site]
latitude = "30°"

[[equipment]]
id = "CAL-1"
role = "calliper"
resolution = "0.01 mm"
[equipment.calibration]
certificate = "C-1"
U = "0.02 mm"
k = 2

[[equipment]]
id = "BAL-1"
role = "balance"
resolution = "0.1 g"
[equipment.calibration]
certificate = "B-1"
U = "0.2 g"
k = 2

[[equipment]]
id = "MEG-1"
role = "megohmmeter"
resolution = "1 Mohm"
[equipment.calibration]
certificate = "M-1"
U = "5 %"
k = 2
"""

INSPECTION = """
[inspection.appearance]
a = true
b = "yes"
c = true
d = true
lighting = "normal"

[[inspection.dimensions]]
name = "length"
nominal = "80 mm"
tolerance = "± 0.1 mm"
readings = ["80.02 mm", "80.04 mm", "80.03 mm"]

[[inspection.dimensions]]
name = "height"
nominal = "45 mm"
upper = "+0.2 mm"
lower = "-0.2 mm"
readings = ["45.01 mm"]

[inspection.mass]
readings = ["1234.5 g", "1234.7 g", "1234.6 g"]
includes = ["cable", "screws"]
delivered_with = ["cable", "screws"]
limit = "<= 1.3 kg"

[[inspection.insulation]]
pair = "power+ to case"
voltage = "500 V"
state = "non-operating"
readings = ["2000 MΩ", "2100 MΩ"]

[[inspection.insulation]]
pair = "signal to case"
voltage = "500 V"
state = "non-operating"
readings = ["> 10 GΩ"]
"""

RELIABILITY = """
[reliability]
operating_hours = "62000 h"
failures = 3
plan = "time-terminated"
confidence = 0.9
working_life = "1500 h"
calendar_life = "8 a"
"""


def _write(tmp: Path, text: str, files: dict[str, str] | None = None) -> Path:
    tmp.mkdir(parents=True, exist_ok=True)
    for name, body in (files or {}).items():
        (tmp / name).write_text(body, encoding="utf-8")
    p = tmp / "manifest.toml"
    p.write_text(text, encoding="utf-8")
    return p


def _run(pm, path: Path, items: list[str]):
    return run_items(pm, "gbt45570", items, data=path)


def _result(record, key):
    for o in record.outcomes:
        for r in o.results:
            if r.metric.key == key:
                return r
    raise KeyError(key)


def _verdict(record, key):
    return next(v for v in record.conformity.verdicts if v.key == key)


# --------------------------------------------------------------------------------- inspection,
# hand-worked


def test_mass_hand_worked(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + INSPECTION), ["6.2.3"])
    r = _result(rec, "mass")
    # mean 1234.6 g; s = 0.1 g → s/√3 = 0.057735; balance U/k = 0.1 g; resolution 0.1 g → 0.05/√3
    assert float(r.value.to("g").magnitude) == pytest.approx(1234.6, abs=1e-9)
    uc = math.sqrt((0.1 / math.sqrt(3)) ** 2 + 0.1**2 + (0.05 / math.sqrt(3)) ** 2)
    assert float(r.u.to("g").magnitude) == pytest.approx(uc, rel=1e-9)  # 0.119024 g
    # ν_eff = u_c⁴ / (u_A⁴/2) = 36.1 (only the type A row has finite ν)
    assert r.budget.nu_eff == pytest.approx(uc**4 / ((0.1 / math.sqrt(3)) ** 4 / 2), rel=1e-9)
    v = _verdict(rec, "mass")
    assert v.status.value == "pass" and "1300" in v.spec.text().replace(
        " ", "") or "1.3" in v.spec.text()


def test_dimensions_hand_worked_and_it12(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + INSPECTION), ["6.2.2"])
    r = _result(rec, "dim_length")
    assert float(r.value.to("mm").magnitude) == pytest.approx(80.03, abs=1e-9)
    # 0.0119024 mm
    uc = math.sqrt((0.01 / math.sqrt(3)) ** 2 + 0.01**2 + (0.005 / math.sqrt(3)) ** 2)
    assert float(r.u.to("mm").magnitude) == pytest.approx(uc, rel=1e-9)
    # IT12: 0.30 mm for 50 … 80 mm, 0.25 mm for 30 … 50 mm (GB/T 1800.1—2020 table 1)
    assert float(_result(rec, "itgrade_length").value.magnitude) == pytest.approx(0.2 / 0.30)
    assert float(_result(rec, "itgrade_height").value.magnitude) == pytest.approx(0.4 / 0.25)
    assert _verdict(rec, "itgrade_length").status.value == "pass"
    # ± 0.2 mm at 45 mm is coarser than IT12
    assert _verdict(rec, "itgrade_height").status.value == "fail"
    assert _verdict(rec, "dim_length").status.value == "pass"  # [80.006, 80.054] within 79.9 … 80.1
    # one reading: no repeatability row, a note says so
    assert "repeatability not evaluated" in _result(rec, "dim_height").note


def test_it12_table_against_the_formula():
    """IT12 = 160·i, i = 0.45·D^(1/3) + 0.001·D (µm, D the geometric mean of the range, GB/T 1800.1
    annex): the tabulated values lie within 5 % of it above 3 mm (the table rounds to preferred
    values)."""
    lower = 3
    for upper, value in inspection.IT12_MM[1:13]:
        D = math.sqrt(lower * upper)
        formula_mm = 160 * (0.45 * D ** (1 / 3) + 0.001 * D) / 1000
        assert value == pytest.approx(formula_mm, rel=0.05), upper
        assert inspection.it12(upper) == value and inspection.it12(lower + 1e-9) == value
        lower = upper
    with pytest.raises(ValueError):
        inspection.it12(1200)


def test_insulation_hand_worked_and_over_range(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + INSPECTION), ["6.2.5"])
    r = _result(rec, "R_ins_power_to_case")
    assert float(r.value.to("Mohm").magnitude) == pytest.approx(2050.0)
    # s = 70.711 → 50 MΩ; 5 % (k = 2) of 2050 → 51.25 MΩ; resolution 1 MΩ → 0.5/√3
    uc = math.sqrt(50.0**2 + 51.25**2 + (0.5 / math.sqrt(3)) ** 2)
    assert float(r.u.to("Mohm").magnitude) == pytest.approx(uc, rel=1e-9)
    over = _result(rec, "R_ins_signal_to_case")
    assert not over.reportable and "over" in over.reason and float(over.value.to(
        "Mohm").magnitude) == 10000
    assert _verdict(rec, "R_ins_signal_to_case").status.value == "pass"
    assert _verdict(rec, "R_ins_power_to_case").status.value == "pass"


INTERFACES = """
[inspection.interfaces]
mechanical_per_specification = true
mounting_face_perpendicular = false
electrical_per_specification = true
protocol_per_specification = true
communication = "CAN"
output_content = ["temperature", "status"]
"""


def test_appearance_and_interfaces_checklists(pm, tmp_path):
    text = HEAD + INSPECTION.replace('d = true', 'd = "no"') + INTERFACES
    rec = _run(pm, _write(tmp_path, text), ["6.2.1", "6.2.4"])
    assert float(_result(rec, "appearance_nc").value.magnitude) == 1
    assert _verdict(rec, "appearance_nc").status.value == "fail"
    # "宜" is a note, not a nonconformity
    assert float(_result(rec, "mech_interface_nc").value.magnitude) == 0
    # no angle/rate in the output
    assert float(_result(rec, "elec_interface_nc").value.magnitude) == 1
    o = next(o for o in rec.outcomes if o.item == "6.2.4")
    assert any("RS-422/RS-485" in w for w in o.warnings) and any("perpendicular" in w for w
                                                                 in o.warnings)


SUPPLY = """
[[equipment]]
id = "DVM-1"
role = "voltmeter"
[equipment.calibration]
certificate = "V-1"
U = "1e-4"
k = 2

[inspection.supply]
voltage_type = "DC"
power = "5 W"
[[inspection.supply.rails]]
nominal = "5 V"
tolerance = "± 5 %"
current = "0.4 A"
readings = ["5.01 V", "5.03 V"]
[[inspection.supply.rails]]
nominal = "-15 V"
tolerance = "± 0.5 V"
"""


def test_supply_statements_and_measured_voltage(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + SUPPLY), ["5.2.6"])
    # the −15 V current is not stated
    assert float(_result(rec, "supply_missing").value.magnitude) == 1
    r = _result(rec, "supply_V_5V")
    assert float(r.value.to("V").magnitude) == pytest.approx(5.02)
    # s/√2 = 0.01 V; 1e-4 (k = 2) of 5.02 V = 2.51e-4 V
    assert float(r.u.to("V").magnitude) == pytest.approx(math.hypot(0.01, 2.51e-4), rel=1e-9)
    assert _verdict(rec, "supply_V_5V").status.value == "pass"  # within 4.75 … 5.25 V


DECLARED = """
[inspection.materials]
fibre = "single-mode fibre"
potting = "epoxy"
housing = "titanium"

[inspection.function]
senses = true
outputs = false
composition = ["optical sensor", "control circuit"]
"""


def test_materials_and_function_records(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + DECLARED), ["5.2.1", "5.2.2"])
    mat = next(o for o in rec.outcomes if o.item == "5.2.1")
    assert not mat.results and any("titanium" in w and "by product specification" in w for w
                                   in mat.warnings)
    assert float(_result(rec, "function_nc").value.magnitude) == 1  # "outputs" is a shall (应)
    assert _verdict(rec, "function_nc").status.value == "fail"
    fn = next(o for o in rec.outcomes if o.item == "5.2.2")
    assert any("structure" in w for w in fn.warnings)  # composition: generally (一般), a note
    rows = {r["clause"]: r for r in clause5.clause5_rows(rec)}
    assert rows["5.2.1"]["status"] == "by product specification" and "titanium" in rows["5.2.1"][
        "result"]
    assert rows["5.2.2"]["verdict"] == "does not conform"


# --------------------------------------------------------------------------------- reliability


#: NIST/SEMATECH e-Handbook of Statistical Methods, 1.3.6.7.4 "Critical values of the chi-square
#: distribution", upper-tail probability α: χ²(1 − α; ν), printed to 3 decimals (tolerance ±0.0005)
CHI2_TABLE = {(0.90, 2): 4.605, (0.90, 4): 7.779, (0.90, 6): 10.645, (0.90, 8): 13.362,
              (0.95, 6): 12.592}


def test_mtbf_lower_bound_against_published_chi2_table():
    from scipy.stats import chi2

    for (c, nu), value in CHI2_TABLE.items():
        assert chi2.ppf(c, nu) == pytest.approx(value, abs=5e-4)
    T = 62000.0
    # time-terminated, r = 3, 90 %: 2T/χ²(0.9; 8) = 124000/13.362 = 9280.1 h (table's ±0.0005 →
    # ±0.35 h)
    assert reliability.mtbf_lower_bound(T, 3, 0.9,
                                        "time-terminated") == pytest.approx(2 * T / 13.362, abs=0.4)
    # failure-terminated, r = 3: 2T/χ²(0.9; 6) = 11648.7 h
    assert reliability.mtbf_lower_bound(T, 3, 0.9,
                                        "failure-terminated") == pytest.approx(
                                            2 * T / 10.645, abs=0.6)
    # no failure in 10 000 h: 20000/χ²(0.9; 2) = 4343.1 h, below 5 000 h
    assert reliability.mtbf_lower_bound(10000.0, 0, 0.9,
                                        "time-terminated") == pytest.approx(20000 / 4.605, abs=0.5)
    assert reliability.mtbf_point(T, 3) == pytest.approx(20666.667, abs=1e-3)
    assert reliability.mtbf_point(T, 0) is None


def test_reliability_items_and_verdicts(pm, tmp_path):
    rec = _run(pm, _write(tmp_path, HEAD + RELIABILITY), ["6.2.9.1", "6.2.9.2"])
    assert float(_result(rec,
                         "mtbf_lower").value.to("h").magnitude) == pytest.approx(
                             2 * 62000 / 13.362, abs=0.4)
    assert _verdict(rec, "mtbf_lower").status.value == "pass"
    assert _verdict(rec, "working_life").status.value == "pass"
    assert _verdict(rec, "calendar_life").status.value == "pass"
    zero = RELIABILITY.replace('operating_hours = "62000 h"',
                               'operating_hours = "10000 h"').replace(
        "failures = 3", "failures = 0").replace('calendar_life = "8 a"', 'calendar_life = "4 a"')
    rec = _run(pm, _write(tmp_path / "z", HEAD + zero), ["6.2.9.1", "6.2.9.2"])
    assert _verdict(rec, "mtbf_lower").status.value == "fail"  # 4343 h < 5 000 h
    assert _verdict(rec, "calendar_life").status.value == "fail"
    with pytest.raises(KeyError):
        _result(rec, "mtbf_point")  # no failure: no point estimate


# --------------------------------------------------------------------------------- 5.4 tests done
# elsewhere


def _segment_csv(level: float) -> str:
    # rate output: ± 0.01 °/h about the level, 40 samples; mean exactly the level
    vals = [level + (0.01 if i % 2 else -0.01) for i in range(40)]
    return "output [deg/h]\n" + "\n".join(f"{v!r}" for v in vals) + "\n"


ENV = """
[[segments]]
id = "lts-before"
kind = "type-env"
file = "before.csv"
sample_interval = "1 s"
[segments.conditions]
orientation = "IRA up"

[[segments]]
id = "lts-after"
kind = "type-env"
file = "after.csv"
sample_interval = "1 s"
[segments.conditions]
orientation = "IRA up"

[[environmental_tests]]
test = "low-temperature storage"
functional_check = true
before = "lts-before"
after = "lts-after"
[environmental_tests.severity]
temperature = "{T}"
duration = "16 h"
[environmental_tests.required]
bias_change = "± 0.05 deg/h"
"""


def test_storage_severity_and_bias_change_hand_worked(pm, tmp_path):
    files = {"before.csv": _segment_csv(0.10), "after.csv": _segment_csv(0.13)}
    rec = _run(pm, _write(tmp_path, HEAD + ENV.format(T="-55 degC"), files), ["6.2.8.2"])
    d = _result(rec, "lts_dB0")
    # B₀ = mean − 15.041·sin 30° for both; ΔB₀ = 0.13 − 0.10 = 0.03 °/h
    assert float(d.value.to("deg/h").magnitude) == pytest.approx(0.03, abs=1e-12)
    # −55 °C ≤ −55 °C (C.1 row 2, aviation)
    assert _verdict(rec, "lts_temperature").status.value == "pass"
    assert _verdict(rec, "lts_dB0").status.value in ("pass", "indeterminate")
    assert _verdict(rec, "lts_function").status.value == "pass"


def test_severity_weaker_than_table_c1_does_not_conform(pm, tmp_path):
    files = {"before.csv": _segment_csv(0.10), "after.csv": _segment_csv(0.10)}
    rec = _run(pm, _write(tmp_path, HEAD + ENV.format(T="-40 degC"), files), ["6.2.8.2"])
    v = _verdict(rec, "lts_temperature")
    assert v.status.value == "fail" and "C.1 row 2" in v.spec.source
    rows = {r["clause"]: r for r in clause5.clause5_rows(rec)}
    assert rows["5.4 b)"]["verdict"] == "does not conform"


def test_product_specification_severity_replaces_table_c1(pm, tmp_path):
    text = HEAD + ENV.format(T="-40 degC").replace('[environmental_tests.required]',
                                                   '[environmental_tests.required]\ntemperature = '
                                                   '"<= -40 degC"')
    files = {"before.csv": _segment_csv(0.10), "after.csv": _segment_csv(0.10)}
    rec = _run(pm, _write(tmp_path, text, files), ["6.2.8.2"])
    assert _verdict(rec, "lts_temperature").status.value == "pass"


@pytest.mark.parametrize("item, tag", [
    ("6.2.8.2", "lts"), ("6.2.8.4", "hts"), ("6.2.8.5", "tsh"), ("6.2.8.6", "lp"),
    ("6.2.8.7", "acc"),
    ("6.2.8.10", "dh"), ("6.2.8.11", "mould"), ("6.2.8.12", "salt"), ("6.2.8.13", "tvac"),
    ("6.2.8.14", "rad"),
    ("6.2.8.15", "emc")])
def test_each_54_test_on_the_simulated_station(pm, item, tag):
    """Every 5.4 test done elsewhere: its record on the simulated station (aviation gyro: table
    C.1's aviation column where it states one), the bias change against the declared truth within U,
    the functional check, and the clause-5 row."""
    from metro.instruments.sim_gbt_type import TRUTH

    rec = run_items(pm, "gbt45570", [item], station_options={"duration_scale": 0.25})
    d = _result(rec, f"{tag}_dB0")
    assert abs(float(d.value.to("deg/h").magnitude)
               - TRUTH.shift(tag)) <= float(d.U.to("deg/h").magnitude)
    assert float(_result(rec, f"{tag}_function").value.magnitude) == 0
    statuses = {v.key: v.status.value for v in rec.conformity.verdicts}
    assert statuses[f"{tag}_function"] == "pass" and "fail" not in statuses.values()
    row = next(r for r in clause5.clause5_rows(rec) if item in r["method"].split(" / "))
    assert row["status"] == "performed"


def test_scale_factor_change_hand_worked():
    from metro.core.model.results import Metric
    from metro.plugins.gbt45570.type_env import scale_factor_change

    m = Metric("lts_dK", "scale-factor change", "ΔK/K", "ppm", "D.1.1.3")
    # K 1.0 → 1.00001 (u = 1e-6 each, ν = 10 and 20): ΔK/K = 10 ppm, u = √(1² + 1.00001²)·1e-6 → ppm
    r = scale_factor_change(m, (1.0, 1e-6, 10, "P/arcsec", "D.1.1"),
                            (1.00001, 1e-6, 20, "P/arcsec", "D.1.1"))
    assert float(r.value.to("ppm").magnitude) == pytest.approx(10.0, rel=1e-9)
    u = math.hypot(1.0, 1.00001)
    assert float(r.u.to("ppm").magnitude) == pytest.approx(u, rel=1e-9)
    assert r.budget.nu_eff == pytest.approx(u**4 / (1.0**4 / 20 + 1.00001**4 / 10), rel=1e-9)


def test_scale_factor_change_from_revolutions_has_the_degrees_of_freedom_of_its_counts(pm):
    """ΔK/K by D.1.1 on 3 revolutions per direction at 10 °/s and 100 °/s: each direction's mean
    count is s/√3 with ν = 2, so ν_eff of ΔK/K is a few and k = t_95.45(ν_eff), not 2 (it was ν =
    ∞). Hand-worked from the campaign's own counts: K = K_10·100/90 − K_100·10/90 per phase."""
    from scipy.stats import t as student

    from metro.core.run.runner import load_campaign

    cls = pm.procedure("gbt45570", "6.2.8.5")
    so = {"device_class": "pulse-fine-undithered", "seed": 3, "arw_deg_rt_h": 0.005}
    camp = load_campaign(pm, [cls], [{}], data=None, station_options=so)
    R2 = 2 * 1296000.0
    parts, K = [], {}
    for phase in ("before", "after"):
        ks = {}
        for rate, c in ((10.0, 100 / 90), (100.0, -10 / 90)):
            n = {}
            for sign in (1, -1):
                sg = next(s for s in camp.segments if s.kind == "type-env-revolutions"
                          and s.conditions["phase"] == phase
                          and float(s.conditions["rate"].split()[0]) == sign * rate)
                cnt = np.asarray(sg.series("count", "P").data.magnitude, dtype=float)
                assert cnt.size == 3
                n[sign] = cnt.mean()
                parts.append((phase, abs(c) * np.std(cnt, ddof=1) / math.sqrt(3) / R2, 2))
            ks[rate] = (n[1] - n[-1]) / R2
        K[phase] = ks[10.0] * 100 / 90 - ks[100.0] * 10 / 90
    # ΔK/K = K_a/K_b − 1: c = 1/K_b on the after parts, K_a/K_b² on the before parts
    u = [(p / K["before"] if ph == "after" else p * K["after"] / K["before"] ** 2) * 1e6 for ph, p,
         _ in parts]
    uc = math.sqrt(sum(x * x for x in u))
    nu = uc**4 / sum(x**4 / 2 for x in u)
    rec = run_items(pm, "gbt45570", ["6.2.8.5"], campaign=camp)
    r = _result(rec, "tsh_dK")
    assert float(r.value.to("ppm").magnitude) == pytest.approx((K["after"] / K["before"] - 1) * 1e6,
                                                               rel=1e-6)
    assert float(r.u.to("ppm").magnitude) == pytest.approx(uc, rel=1e-9)
    assert r.budget.nu_eff == pytest.approx(nu, rel=1e-9)
    assert 2 <= nu < 8  # a handful of revolutions: far from ∞
    assert r.budget.k == pytest.approx(float(student.ppf(0.97725, nu)), rel=1e-6)
    assert r.budget.k > 2.2


@pytest.mark.parametrize("station, how", [("simulated", "angle"), ("simulated-digital", "rate")])
def test_scale_factor_change_by_d11_and_d21(pm, station, how):
    """ΔK/K before/after the temperature shock: whole revolutions by D.1.1 on the pulse gyro, the
    output at rate points by D.2.1 on the LSB gyro; the declared 9 ppm within U."""
    from metro.instruments.sim_gbt_type import TRUTH

    # seed 1 on the LSB gyro: segments are seeded by their step's identity since issue 14, and the
    # default seed's draw put ΔK/K 1.08 U from the truth (seeds 1–7: 0.0 … 0.89 U)
    rec = run_items(pm, "gbt45570", ["6.2.8.5"], station=station, options={"scale_factor": how},
                    station_options={"duration_scale": 0.25}
                    | ({"seed": 1} if how == "rate" else {}))
    r = _result(rec, "tsh_dK")
    assert ("D.1.1" if how == "angle" else "D.2.1") in r.note
    assert abs(float(r.value.to("ppm").magnitude)
               - TRUTH.sf_shift("tsh") * 1e6) <= float(r.U.to("ppm").magnitude)


def test_revolutions_of_a_digital_gyro_are_not_read_as_pulses(pm):
    rec = run_items(pm, "gbt45570", ["6.2.8.5"], station="simulated-digital",
                    station_options={"duration_scale": 0.25})
    with pytest.raises(KeyError):
        _result(rec, "tsh_dK")
    assert any("scale_factor = rate" in w for o in rec.outcomes for w in o.warnings)


def test_scale_factor_records_on_one_side_only(pm):
    import attrs

    from metro.core.run.runner import load_campaign

    cls = pm.procedure("gbt45570", "6.2.8.2")
    camp = load_campaign(pm, [cls], [{}], data=None, station_options={"duration_scale": 0.2})
    # drop the revolutions after the test: the before ones alone are an error naming what is missing
    kept = [sg for sg in camp.segments
            if not (sg.kind == "type-env-revolutions" and sg.conditions.get("phase") == "after")]
    with pytest.raises(DataError, match="none after it"):
        run_items(pm, "gbt45570", ["6.2.8.2"], campaign=attrs.evolve(camp, segments=kept))


# --------------------------------------------------------------------------------- bad records


@pytest.mark.parametrize("edit, field, words", [
    (lambda t: t.replace('"1234.5 g"', '"1234.5"'), "inspection.mass.readings[0]", "no unit"),
    (lambda t: t.replace('"1234.5 g"', '1234.5'), "inspection.mass.readings[0]", "no unit"),
    (lambda t: t.replace('includes = ["cable", "screws"]', 'includes = ["cable"]'),
     "inspection.mass.includes",
     "screws"),
])
def test_bad_mass_records(pm, tmp_path, edit, field, words):
    with pytest.raises(DataError) as e:
        _run(pm, _write(tmp_path, edit(HEAD + INSPECTION)), ["6.2.3"])
    assert e.value.field == field and words in e.value.detail and e.value.file.endswith(
        "manifest.toml")


def test_insulation_below_range(pm, tmp_path):
    low = (HEAD + INSPECTION).replace('readings = ["2000 MΩ", "2100 MΩ"]', 'readings = ["< 1 MΩ"]')
    rec = _run(pm, _write(tmp_path, low), ["6.2.5"])
    r = _result(rec, "R_ins_power_to_case")
    assert not r.reportable and "below" in r.reason
    assert _verdict(rec, "R_ins_power_to_case").status.value == "fail"
    # a range that starts above 50 MΩ says nothing: an error naming the field
    worse = (HEAD + INSPECTION).replace('readings = ["2000 MΩ", "2100 MΩ"]',
                                        'readings = ["< 100 MΩ"]')
    with pytest.raises(DataError) as e:
        _run(pm, _write(tmp_path / "b", worse), ["6.2.5"])
    assert (e.value.field == "inspection.insulation[0].readings"
            and "below the megohmmeter's range" in e.value.detail)
    over = (HEAD + INSPECTION).replace('readings = ["> 10 GΩ"]', 'readings = ["> 20 MΩ"]')
    with pytest.raises(DataError, match="over the megohmmeter's range"):
        _run(pm, _write(tmp_path / "c", over), ["6.2.5"])
    operating = (HEAD + INSPECTION).replace('state = "non-operating"', 'state = "operating"', 1)
    with pytest.raises(DataError, match="not operating"):
        _run(pm, _write(tmp_path / "d", operating), ["6.2.5"])


def test_measured_item_without_equipment(pm, tmp_path):
    no_balance = (HEAD + INSPECTION).replace('role = "balance"', 'role = "scale-of-another-kind"')
    with pytest.raises(DataError) as e:
        _run(pm, _write(tmp_path, no_balance), ["6.2.3"])
    assert e.value.field == "equipment" and "balance" in e.value.detail
    no_cal = (HEAD
              + INSPECTION).replace('[equipment.calibration]\ncertificate = "M-1"\nU = "5 %"\nk = '
                                    '2\n', "")
    with pytest.raises(DataError, match="no calibration data"):
        _run(pm, _write(tmp_path / "b", no_cal), ["6.2.5"])


def test_bad_reliability_records(pm, tmp_path):
    ft = RELIABILITY.replace("failures = 3", "failures = 0").replace(
        "time-terminated", "failure-terminated"
    )
    with pytest.raises(DataError) as e:
        _run(pm, _write(tmp_path, HEAD + ft), ["6.2.9.1"])
    assert e.value.field == "reliability.failures"
    with pytest.raises(DataError) as e:
        _run(pm, _write(tmp_path / "b", HEAD + RELIABILITY.replace('"62000 h"', "62000")),
             ["6.2.9.1"])
    assert e.value.field == "reliability.operating_hours" and "no unit" in e.value.detail


def test_cli_bad_record_exit_2_and_nothing_written(run_cli, tmp_path):
    p = _write(tmp_path, (HEAD + INSPECTION).replace('"1234.5 g"', '"1234.5"'))
    out = tmp_path / "out"
    code, _o, err = run_cli("run", "-s", "gbt45570", "-i", "6.2.3", "--data", str(p), "--out",
                            str(out),
                            "--no-progress")
    assert code == 2 and "inspection.mass.readings[0]" in err and "Traceback" not in err
    assert not out.exists()


# --------------------------------------------------------------------------------- coverage of
# clause 5


def test_every_clause5_requirement_has_a_row_and_an_item(pm):
    clauses = [r.clause for r in clause5.REQUIREMENTS]
    # 5.1, 5.2.1–5.2.9 (5.2.7 as .1 and .2), 5.3 a)–p), 5.4 a)–p), 5.5.1, 5.5.2 a), b)
    expected = (["5.1", "5.2.1", "5.2.2", "5.2.3", "5.2.4", "5.2.5", "5.2.6", "5.2.7.1", "5.2.7.2",
                 "5.2.8", "5.2.9"]
                + [f"5.3 {c})" for c in "abcdefghijklmnop"]
                + [f"5.4 {c})" for c in "abcdefghijklmnop"]
                + ["5.5.1", "5.5.2 a)", "5.5.2 b)"])
    assert clauses == expected
    registered = {cls.item for cls in pm.procedures_of("gbt45570")}
    for r in clause5.REQUIREMENTS:
        assert r.items or r.by_spec, r.clause
        assert set(r.items) <= registered, r.clause
    assert pm.series("gbt45570", "type-test").members == clause5.TYPE_TEST_ITEMS


def test_simulated_station_records_cover_the_type_test(pm):
    items = ["5.2.1", "5.2.2", "6.2.1", "6.2.2", "6.2.3", "5.2.6", "6.2.4", "6.2.5", "6.2.8.2",
             "6.2.8.15", "6.2.9.1",
             "6.2.9.2"]
    # a device whose data sheet states no turn-on scatter (the default simulated device states it:
    # issue 29)
    rec = run_items(pm, "gbt45570", items, station_options={"duration_scale": 0.2,
                                                            "states_repeatability": False})
    assert rec.campaign.simulated and set(rec.campaign.records) == {
        "inspection",
        "environmental_tests",
        "reliability",
    }
    exp = rec.campaign.expected
    for key in ("mass", "dim_length", "R_ins_power_to_case", "mtbf_lower", "lts_dB0"):
        r = _result(rec, key)
        assert abs(float((r.value
                          - exp[key]).to(r.metric.unit).magnitude)) <= float(r.U.to(
                              r.metric.unit).magnitude), key
    statuses = {v.key: v.status.value for v in rec.conformity.verdicts}
    assert "fail" not in statuses.values()
    # a ΔB₀/ΔK/K across two power-ons without their turn-on scatter is not reportable: no statement
    withheld = {v.key for v in rec.conformity.verdicts if v.detail == "not reportable"}
    assert withheld == {"lts_dK", "lts_dB0", "emc_dK", "emc_dB0"}
    assert all(statuses[k] == "indeterminate" for k in withheld)
    # the records' own verdicts are definite; only a bias change on 2-min records may be
    # indeterminate
    assert {s for k, s in statuses.items() if not k.endswith("_dB0") and k
            not in withheld} == {"pass"}
    rows = clause5.clause5_rows(rec)
    assert [r["clause"] for r in rows] == [r.clause for r in clause5.REQUIREMENTS]
    by = {r["clause"]: r for r in rows}
    assert by["5.2.5"]["status"] == "performed" and by["5.2.5"]["verdict"] == "conforms"
    assert by["5.2.1"]["status"] == "by product specification"
    assert by["5.3 i)"]["status"] == "not performed" and by["5.3 i)"][
        "reason"] == "not requested in this run"


def test_acquire_writes_records_that_run_reads_back(pm, tmp_path):
    from metro.core.run.manifest_writer import acquire_campaign

    items = ["6.2.3", "6.2.5", "6.2.8.2", "6.2.9.1"]
    manifest = acquire_campaign(pm, "gbt45570", items, tmp_path / "camp",
                                station_options={"duration_scale": 0.2})
    camp = load_manifest(manifest, pm.reader_for)
    assert camp.records["inspection"]["mass"]["readings"]
    direct = run_items(pm, "gbt45570", items, station_options={"duration_scale": 0.2})
    again = run_items(pm, "gbt45570", items, data=manifest)
    for key in ("mass", "R_ins_power_to_case", "mtbf_lower", "lts_temperature", "lts_dB0"):
        a, b = _result(direct, key), _result(again, key)
        assert float(b.value.to(a.metric.unit).magnitude) == pytest.approx(float(a.value.to(
            a.metric.unit).magnitude),
                                                                           rel=1e-12), key


def test_all_on_records_only_skips_items_without_records(pm, tmp_path):
    rec = run_items(pm, "gbt45570", [], data=_write(tmp_path, HEAD + RELIABILITY), run_all=True)
    ran = {o.item for o in rec.outcomes}
    assert ran == {"6.2.9.1", "6.2.9.2"}
    why = {c.item: c.reason for c in rec.selection}
    assert "no record" in why["6.2.3"] and "[inspection.mass]" in why["6.2.3"]
    rows = {r["clause"]: r for r in clause5.clause5_rows(rec)}
    assert rows["5.2.5"]["status"] == "not performed" and "[inspection.mass]" in rows["5.2.5"][
        "reason"]
    assert rows["5.5.1"]["verdict"] == "conforms"


def test_report_with_every_clause5_item_is_written(pm, tmp_path):
    """A run of every type-test item writes the GB/T report: the .docx title property (≤ 255
    characters, python-docx refuses more) is cut, the pages keep every item; the context has the
    clause-5 rows."""
    import docx
    from metro.core.documents.context import report_context
    from metro.core.documents.report import write_report

    items = list(clause5.TYPE_TEST_ITEMS[:7]) + [i for i in clause5.TYPE_TEST_ITEMS
                                                 if i.startswith(("6.2.8", "6.2.9"))]
    rec = run_items(pm, "gbt45570", items, station_options={"duration_scale": 0.25},
                    options={"scale_factor": "none"})
    long = (
        {"gbt45570": "GB/T 45570—2025 光学陀螺仪通用技术要求 (optical gyroscopes — general "
         "technical requirements)"}
    )
    ctx = report_context(rec, designations=long)
    pm.extend_report_context(rec, ctx)
    assert [r["clause"] for r in ctx["gbt45570"]["clause5"]] == [r.clause for r
                                                                 in clause5.REQUIREMENTS]
    assert len(ctx["title"]) > 255
    tpl = pm.template_for("gbt45570")
    # built or docxtpl
    how = {"layout": tpl.layout} if getattr(tpl, "layout", None) else {"template": tpl.path}
    path = write_report(tmp_path / "r.docx", rec, designations=long,
                        extend=pm.extend_report_context, **how)
    doc = docx.Document(str(path))
    assert len(doc.core_properties.title) == 255 and doc.core_properties.title.endswith("…")
    # the clause-5 table: every requirement in a row of its own, in order
    want = [q.clause for q in clause5.REQUIREMENTS]
    tables = [[[c.text.replace("\xa0", " ").strip() for c in row.cells] for row in t.rows] for t
              in doc.tables]
    table = next(rows for rows in tables if [r[0] for r in rows[1:]] == want)
    mass = next(r for r in table if r[0] == "5.2.5")
    assert any("mass = 1234" in c for c in mass) and any("conforms" in c or "合格" in c for c
                                                         in mass)


def test_plan_of_the_whole_standard_includes_the_type_test(pm):
    """What `metro plan -s gbt45570 --all` prints: every clause-5 item's steps, the records to take
    down (kind record:…) with the gyro's records before and after each 5.4 test."""
    from metro.core.run.runner import merge_steps, select_items, station_device

    items, _ = select_items(pm, "gbt45570", [], run_all=True,
                            device=station_device(pm, "simulated", {}))
    assert set(clause5.TYPE_TEST_ITEMS) - {"D.2.1", "D.2.2", "D.2.3", "D.2.4", "D.2.5",
                                           "D.2.6"} <= set(items)
    procs = [pm.procedure("gbt45570", i) for i in items]
    steps = merge_steps([c().sequence(c.option_values({})) for c in procs])
    kinds = {s.kind for s in steps}
    wanted = {f"record:inspection.{p}" for p in ("materials", "function", "appearance",
                                                 "dimensions", "mass", "supply",
                                                 "interfaces", "insulation")}
    wanted |= {
        f"record:environmental_tests.{t}"
        for t in ("lts", "hts", "tsh", "lp", "acc", "dh", "mould", "salt", "tvac", "rad", "emc")
    }
    wanted |= {"record:reliability.mtbf", "record:reliability.life", "type-env",
               "type-env-revolutions"}
    assert wanted <= kinds
    assert all(s.duration.magnitude == 0 for s in steps if s.is_record)


def test_metro_items_lists_the_clause5_items_and_the_type_test_series(run_cli):
    import json

    code, out, _err = run_cli("items", "-s", "gbt45570", "--json")
    assert code == 0
    doc = json.loads(out)
    by_item = {i["item"]: i for i in doc["items"]}
    assert set(clause5.TYPE_TEST_ITEMS) <= set(by_item)
    # the new items name the clause-5 requirement they answer
    assert by_item["6.2.3"]["clause"] == "5.2.5" and by_item["6.2.8.2"]["clause"] == "5.4 b)"
    assert by_item["6.2.9.1"]["clause"] == "5.5.1" and by_item["5.2.1"]["clause"] == "5.2.1"
    series = {s["name"]: s for s in doc["series"]}
    assert tuple(series["type-test"]["members"]) == clause5.TYPE_TEST_ITEMS


def test_metro_plan_all_prints_the_records(run_cli):
    code, out, _err = run_cli("plan", "-s", "gbt45570", "--all")
    assert code == 0
    for kind in ("record:inspection.mass", "record:inspection.insulation",
                 "record:environmental_tests.lts",
                 "record:environmental_tests.emc", "record:reliability.mtbf", "kind=type-env "):
        assert kind in out, kind


def test_before_and_after_a_54_test_carry_two_power_ons(pm):
    """interpretations.md "6.2.8 — before and after are two power-ons": with D.5.3 and D.1.4 repeats
    in the campaign, ΔB₀ and ΔK/K of a 5.4 test carry √2 × one power-on's turn-on scatter (σ_on of
    D.5.3 with its within-run part removed; K_r of D.1.4 in ppm); without them, the note says the
    row is absent."""
    import math

    from metro.plugins.gbt45570.repeatability import bias_repeat_row, scale_factor_angle_repeat_row

    alone = run_items(pm, "gbt45570", ["6.2.8.2"],
                      station_options={"duration_scale": 0.25, "states_repeatability": False})
    assert "no D.1.4 repeats" in str(_result(alone, "lts_dK").note)
    assert "no D.5.3 repeats" in str(_result(alone, "lts_dB0").note)
    # interpretations.md "GB/T 45570 — a difference of power-ons needs their turn-on scatter":
    # neither measured nor stated, the two changes are not reportable, saying what to record or
    # state
    for key, item, field in (("lts_dK", "D.1.4", "scale_factor_repeatability"),
                             ("lts_dB0", "D.5.3", "bias_repeatability")):
        r = _result(alone, key)
        assert (r.reportable is False and item in r.reason
                and f"[device] {field}" in r.reason), r.reason
    rec = run_items(pm, "gbt45570", ["D.5.3", "D.1.4", "6.2.8.2"],
                    station_options={"duration_scale": 0.25})
    dk = _result(rec, "lts_dK")
    row = next(r for r in dk.budget.rows if r.symbol == "√2·σ_on")
    Kb = float(str(dk.note).split("K before ")[1].split(",")[0])
    one = scale_factor_angle_repeat_row(rec.campaign, Kb, "")[0][0]
    assert row.contribution.m_as("ppm") == pytest.approx(
        math.sqrt(2) * one.contribution.magnitude / Kb * 1e6, rel=1e-9
    )
    assert dk.budget.combined.m_as("ppm") > row.contribution.m_as("ppm") > 1.0
    db = _result(rec, "lts_dB0")
    brow = next(r for r in db.budget.rows if r.symbol == "√2·σ_on")
    sigma_on = bias_repeat_row(rec.campaign, 20, None)[0][0]
    assert brow.contribution.m_as("deg/h") == pytest.approx(
        math.sqrt(2) * sigma_on.contribution.m_as("deg/h"), rel=1e-9)


def test_54_changes_take_a_stated_repeatability(pm, tmp_path):
    """Without repeats, [device] bias_repeatability and scale_factor_repeatability (measured before)
    stand for the turn-on scatter: ΔB₀ and ΔK/K are reportable, with type B rows √2 × the stated
    σ."""
    from metro.core.cli.app import main

    out = tmp_path / "camp"
    assert main(["acquire", "-s", "gbt45570", "-i", "6.2.8.2", "--out", str(out),
                 "--station-option",
                 "duration_scale=0.25", "--station-option", "states_repeatability=false"]) == 0
    m = out / "manifest.toml"
    text = m.read_text(encoding="utf-8")
    assert "\n[device]\n" in text
    m.write_text(text.replace("\n[device]\n", '\n[device]\nbias_repeatability = "0.003 °/h"\n'
                              'scale_factor_repeatability = "4e-6"\n', 1), encoding="utf-8")
    rec = _run(pm, m, ["6.2.8.2"])
    dk, db = _result(rec, "lts_dK"), _result(rec, "lts_dB0")
    assert dk.reportable and db.reportable, (dk.reason, db.reason)
    (rk,) = [r for r in dk.budget.rows if r.symbol == "√2·σ_on"]
    (rb,) = [r for r in db.budget.rows if r.symbol == "√2·σ_on"]
    assert rk.type == "B" and rk.contribution.m_as("ppm") == pytest.approx(math.sqrt(2) * 4.0,
                                                                           rel=1e-9)
    assert rb.type == "B" and rb.contribution.m_as("deg/h") == pytest.approx(
        math.sqrt(2) * 0.003, rel=1e-9)


@pytest.mark.parametrize("item, tag", [("6.2.8.7", "acc"), ("6.2.8.10", "dh"), ("6.2.8.14", "rad")])
def test_scale_factor_records_whose_tag_is_also_a_unit_survive_the_manifest(
    pm, tmp_path, item, tag):
    """The tags acc, dh and rad are units to pint (attocubic centimetre, decihour, radian): a
    manifest's ``test = "acc"`` was read as the quantity 1 acc, matched no test, and ΔK/K of
    6.2.8.7, 6.2.8.10 and 6.2.8.14 vanished without a word on every written campaign (``metro
    acquire`` then ``run --data``; found by benchmarks/independent_gbt_env.py). A condition without
    a digit stays text."""
    from metro.core.cli.app import main

    out = tmp_path / "camp"
    assert main(["acquire", "-s", "gbt45570", "-i", item, "--out", str(out), "--station-option",
                 "duration_scale=0.25"]) == 0
    camp = load_manifest(out / "manifest.toml", pm.reader_for)
    revs = [s for s in camp.segments if s.kind == "type-env-revolutions"]
    assert revs and all(s.conditions["test"] == tag for s in revs)
    rec = _run(pm, out / "manifest.toml", [item])
    r = _result(rec, f"{tag}_dK")
    assert math.isfinite(float(r.value.to("ppm").magnitude)) and float(r.U.to("ppm").magnitude) > 0
    # a quantity condition is still read with its unit, and a bare non-finite one still refused
    assert float(next(s for s in revs).condition("rate", "deg/s").to("deg/s").magnitude) != 0


def test_54_bias_change_turn_on_row_is_never_zero_where_d53_only_bounds_sigma_on(pm):
    """interpretations.md "σ_on — a variance component the data only bound": where D.5.3's Q
    power-ons scatter less than their within-run noise (B_r² < mean u_A²) the moment estimate
    √max(B_r² − mean u_A²,
    0) is 0 and ΔB₀ carried no turn-on row (independent harness env-rate-lsb: within U on 91.9 % of
    such devices' ΔB₀, 222 results, against 96.8 % elsewhere). Now σ_on² is the posterior mean of
    the variance component given the runs (reference prior, τ = σ_on² + u_A² ≥ u_A²), entered with ν
    = ∞; worked here by hand for Q = 7 from the closed χ²(4) and χ²(6) cdfs."""
    import math

    from metro.plugins.gbt45570 import formulas as F
    from metro.plugins.gbt45570.static_bias import segment_bias

    # no turn-on scatter on the station: D.5.3's B_r comes out below the runs' own noise (seed 3:
    # B_r²/u_A² = 0.54)
    rec = run_items(pm, "gbt45570", ["D.5.3", "6.2.8.2"],
                    station_options={"duration_scale": 0.25, "turn_on_sigma_deg_h": 0.0, "seed": 3})
    db = _result(rec, "lts_dB0")
    (row,) = [r for r in db.budget.rows if r.symbol == "√2·σ_on"]
    ests = [segment_bias(s, rec.campaign, 20) for s in rec.campaign.find_segments("static-repeat")]
    assert len(ests) == 7
    b2 = F.bias_repeatability_d42([e.B0 for e in ests]) ** 2
    w = sum(e.u_A**2 for e in ests) / 7
    assert b2 < w  # the precondition: the moment estimate is 0 here (no row before this change)
    c = 6 * b2 / w
    F4 = 1 - math.exp(-c / 2) * (1 + c / 2)
    F6 = 1 - math.exp(-c / 2) * (1 + c / 2 + c * c / 8)
    s_on2 = 6 * b2 * F4 / (4 * F6) - w
    # between the limits 2w/(ν − 2) (B_r → 0) and 1.08·w (B_r² = w)
    assert 0.5 * w < s_on2 < 1.1 * w
    assert row.contribution.m_as("deg/h") == pytest.approx(math.sqrt(2 * s_on2), rel=1e-9)
    assert row.dof == math.inf
    assert "not resolved from the within-run noise" in row.note

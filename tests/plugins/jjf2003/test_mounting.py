"""JJF 2003: what the site, the table and the fixture put into the matrices
(plugins/jjf2003/mounting.py).

Found by the independent harness (benchmarks/independent_jjf2003.py, docs/independent-campaigns.md
"JJF 2003: MIMU matrices"): K_a's diagonal was off by g/g_n − 1 (up to ±2.6×10⁻³, 15–660 U) because
Ā's ±1 were taken as 1 g_n; 7.2.3's cross-coupling had no row for the swept axis's alignment (a
table as good as table 1 asks: 44 % within U); 7.2.4's cross-coupling none for the fixture; 7.2.5's
p none for the table axis leaning at rest.  Each test writes a noise-free MIMU whose error is
known by hand and fails without its fix.
"""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from metro.core.stats.earth import normal_gravity

GN = 9.80665
ARCSEC = math.pi / 180 / 3600
RATES = (-400, -200, -100, -50, 0, 50, 100, 200, 400)
KG = np.array([[1.02, 0.003, -0.002], [0.001, -0.98, 0.004], [-0.003, 0.002, 1.05]])
KA = np.array([[1.01, 0.002, -0.001], [-0.002, 0.99, 0.003], [0.001, -0.002, -1.03]])
BG, BA = np.array([0.1, -0.2, 0.05]), np.array([0.01, -0.02, 0.005])
P = np.array([[0, 2e-4, -1e-4], [1e-4, 0, 3e-4], [-2e-4, 1e-4, 0]])
UP = {"+x": (0, 1), "-x": (0, -1), "+y": (1, 1), "-y": (1, -1), "+z": (2, 1), "-z": (2, -1)}
HEAD = "gx [°/s],gy [°/s],gz [°/s],ax [gn],ay [gn],az [gn]"  # the CSV header of every record


def _write(root, *, g_loc=GN, site=(), table_U="2e-5", sweep_misalign=0.0, rest_tilt=0.0,
           extra_table=(), lat=0.0):
    """A noise-free MIMU (eq. (1), (2); G = 0, no earth rate) at latitude 0: positions feel ±g_loc
    along the up axis; the sweep about j turns about e_j tilted by ``sweep_misalign`` (rad) towards
    the next axis; at rest the table axis leans by ``rest_tilt`` (rad) towards the next axis."""
    root.mkdir()
    f = g_loc / GN
    lines = ['format = "metro-campaign/1"', "[device]", 'id = "M"', 'output = "rate"',
             'gyro_range = "400 °/s"',
             'accel_range = "8 gn"', "[environment]", 'temperature = "20 °C"', 'humidity = "40 %"',
             "[site]",
             f'latitude = "{lat!r}°"', *site, "[[equipment]]", 'id = "T"', 'role = "rate_table"',
             'position_accuracy = "10″"',
             *extra_table, "[equipment.calibration]", 'certificate = "C"', f'U = "{table_U}"',
             "k = 2",
             "[[equipment]]", 'id = "D"', 'role = "acquisition"', "bits = 24", ""]
    wiggle = 1e-9 * np.where(np.arange(40) % 2, 1.0, -1.0)

    def seg(sid, kind, w, a, cond):
        data = np.column_stack([np.full(40, v) + wiggle for v in list(w) + list(a)])
        rows = "\n".join(",".join(repr(float(x)) for x in r) for r in data)
        (root / f"{sid}.csv").write_text(f"{HEAD}\n{rows}\n", encoding="utf-8")
        lines.extend(["[[segments]]", f'id = "{sid}"', f'kind = "{kind}"', f'file = "{sid}.csv"',
                      'sample_interval = "1 s"', "[segments.conditions]",
                      *(f"{k} = {json.dumps(v, ensure_ascii=False)}" for k, v in cond.items()), ""])

    wv = math.degrees(7.2921150e-5) * math.sin(math.radians(lat))  # vertical earth rate, °/s
    for up, (j, s) in UP.items():
        force = np.zeros(3)
        force[j] = s * f
        for h in (0, 180):
            seg(f"pos{up}-h{h}", "position", KG @ (force / f * wv) + BG, KA @ force + BA,
                {"up": up, "heading": f"{h}°"})
    for j, a in enumerate("xyz"):
        axis = np.zeros(3)
        axis[j] = 1.0
        axis[(j + 1) % 3] = sweep_misalign
        force = np.zeros(3)
        force[j] = f
        lean = np.zeros(3)
        lean[(j + 1) % 3] = rest_tilt * f
        for r in RATES:
            w = math.radians(r)
            acc = KA @ (force + (lean if r == 0 else 0)) + BA + P @ (w * axis) ** 2
            seg(f"rate-{a}-{r}", "rate", KG @ (r * axis) + BG, acc, {"axis": a, "rate": f"{r} °/s"})
    (root / "manifest.toml").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return root / "manifest.toml"


def _run(run_cli, manifest, items):
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", items, "--data", str(manifest), "--json",
                             "--no-report")
    assert code in (0, 3, 4), err
    doc = json.loads(out)
    return {(r["item"], r["key"]): r for r in doc["results"]}, doc


def test_six_position_divides_by_the_local_gravity(run_cli, tmp_path):
    """Ā's ±1 are the local gravity: at the equator g = 9.7803 m/s², 0.27 % below g_n, and an exact
    accelerometer read K_axx = 0.99730 (U 1.5×10⁻⁴ on a 16-bit MIMU) before.  With `[site] gravity`
    the matrix is exact; without it GRS 80 normal gravity at the latitude (and altitude) is used and
    its anomaly is a budget row."""
    g_eq = normal_gravity(0.0)
    res, _ = _run(run_cli, _write(tmp_path / "stated", g_loc=9.7803,
                                  site=['gravity = "9.7803 m/s²"',
                                                                          'gravity_uncertainty = '
                                                                              '"0.00001 m/s²"']),
                  "7.2.2,7.2.4")
    for i, r in enumerate("xyz"):
        for j, c in enumerate("xyz"):
            assert res[("7.2.4", f"K_a{r}{c}")]["value"] == pytest.approx(KA[i, j], abs=1e-9)
        assert res[("7.2.4", f"B_a{r}")]["value"] == pytest.approx(BA[i], abs=1e-9)
    row = next(x for x in res[("7.2.4", "K_axx")]["budget"]["rows"] if x["symbol"] == "u_g")
    assert row["value"] == pytest.approx(1e-5 / 9.7803) and row["distribution"] == "uniform"

    res, _ = _run(run_cli, _write(tmp_path / "normal", g_loc=g_eq), "7.2.4")
    assert res[("7.2.4", "K_axx")]["value"] == pytest.approx(KA[0, 0], abs=1e-9)
    row = next(x for x in res[("7.2.4", "K_azz")]["budget"]["rows"] if x["symbol"] == "u_g")
    assert row["value"] == pytest.approx(3e-4 + 3.1e-4)  # anomaly ± no altitude given (0 m assumed)
    assert row["contribution"] == pytest.approx(abs(KA[2, 2]) * 6.1e-4 / math.sqrt(3), rel=1e-6)

    res, _ = _run(run_cli, _write(tmp_path / "high", g_loc=normal_gravity(0.0, 2000.0),
                                  site=['altitude = "2000 m"']), "7.2.4")
    assert res[("7.2.4", "K_ayy")]["value"] == pytest.approx(KA[1, 1], abs=1e-9)


def test_bad_site_gravity_is_refused(run_cli, tmp_path):
    manifest = _write(tmp_path / "bad", site=['gravity = "1 gn"'])
    manifest.write_text(
        manifest.read_text(encoding="utf-8").replace('gravity = "1 gn"', 'gravity = "9.1 m/s²"'),
        encoding="utf-8",
    )
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.4", "--data", str(manifest),
                             "--json", "--no-report")
    assert code == 2 and "Traceback" not in err
    doc = json.loads(out)
    assert doc["field"] == "site.gravity" and "9.1" in doc["message"]


def test_cross_coupling_budget_covers_the_swept_axis_alignment(run_cli, tmp_path):
    """A sweep axis 15″ off the MIMU's axis (within table 1's ±10″ positioning and ±10″ axis
    perpendicularity and 6.2's 10″ fixture) puts K_ii·7.3×10⁻⁵ into K_g[i, j]; with a table of
    U = 2×10⁻⁵ the budget was u₁ + u₂ + u₃ ≈ 1×10⁻⁵ and missed it by 3–7 U."""
    d = 15 * ARCSEC
    res, _ = _run(run_cli, _write(tmp_path / "m", sweep_misalign=d), "7.2.3")
    for j, c in enumerate("xyz"):
        i = (j + 1) % 3
        r = res[("7.2.3", f"K_g{'xyz'[i]}{c}")]
        assert r["value"] - KG[i, j] == pytest.approx(KG[i, i] * d, rel=1e-3)
        assert abs(r["value"] - KG[i, j]) < r["U"]
        syms = {x["symbol"]: x for x in r["budget"]["rows"]}
        assert {"u_δ", "u_f"} <= set(syms)
        assert syms["u_f"]["sensitivity"] == pytest.approx(abs(KG[i, i]), rel=1e-6)
    diag = res[("7.2.3", "K_gxx")]["budget"]["rows"]
    assert not any(x["symbol"] in ("u_δ", "u_f") for x in diag)  # second order on the diagonal


def test_cross_coupling_alignment_rows_read_the_equipment(run_cli, tmp_path):
    manifest = _write(tmp_path / "eq", extra_table=['axis_perpendicularity = "3″"'])
    text = manifest.read_text(encoding="utf-8").replace(
        "[[equipment]]\nid = \"D\"",
        "[[equipment]]\nid = \"F\"\nrole = \"fixture\"\nperpendicularity = \"4″\"\n\n"
        "[[equipment]]\nid = \"D\"")
    manifest.write_text(text, encoding="utf-8")
    res, _ = _run(run_cli, manifest, "7.2.3")
    rows = res[("7.2.3", "K_gyx")]["budget"]["rows"]
    hw = sorted(round(x["value"] / ARCSEC, 6) for x in rows if x["symbol"] in ("u_δ", "u_f"))
    assert hw == [3.0, 4.0, 10.0]


def test_p_budget_covers_the_table_axis_leaning_at_rest(run_cli, tmp_path):
    """U₇ is read at rest: a table axis leaning 8″ puts K_ii·g·δ = 3.9×10⁻⁵ g_n on accelerometer i,
    which turning at ω averages out of U₈: p errs by 8×10⁻⁷ g_n/(rad/s)², where the 24-bit
    noise-free budget was 2×10⁻⁸."""
    d = 8 * ARCSEC
    res, _ = _run(run_cli, _write(tmp_path / "p", rest_tilt=d), "7.2.5")
    w2 = math.radians(400) ** 2
    for j, c in enumerate("xyz"):
        i = (j + 1) % 3
        r = res[("7.2.5", f"p_{'xyz'[i]}{c}")]
        assert r["value"] - P[i, j] == pytest.approx(-KA[i, i] * d / w2, rel=1e-3)
        assert abs(r["value"] - P[i, j]) < r["U"]
        assert any(x["symbol"] == "u_t" for x in r["budget"]["rows"])


def test_earth_rate_is_in_every_g_term_of_its_column(run_cli, tmp_path):
    """With axis j up the vertical earth rate lies along +j and flips with it, so eq. (7) puts
    K_g[:, j]·Ω_e·sin φ into the whole column j of the g matrix: the cross terms hold the
    cross-coupling times it (8×10⁻⁵ (°/s)/gn for 2 % at 80°, 0.75 U on a quiet MIMU), and were
    labelled earth rate "not applicable". Here G = 0: every g term is the leak."""
    lat = 60.0
    wv = math.degrees(7.2921150e-5) * math.sin(math.radians(lat))
    manifest = _write(tmp_path / "e", lat=lat, site=['gravity = "9.80665 m/s²"'])
    res, _ = _run(run_cli, manifest, "7.2.2")
    for i, r in enumerate("xyz"):
        for j, c in enumerate("xyz"):
            g = res[("7.2.2", f"g_{r}{c}")]
            assert g["value"] == pytest.approx(KG[i, j] * wv, abs=1e-12)
            assert g["earth_rate"] == "included", (r, c, g["earth_rate"])
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.2", "--data", str(manifest),
                             "--json", "--no-report",
                             "-o", "earth_rate=yes")
    assert code in (0, 3, 4), err
    for x in json.loads(out)["results"]:
        if x["key"].startswith("g_"):
            assert x["earth_rate"] == "removed" and abs(x["value"]) < 1e-12, x

"""JJF 2003: a gyro bias that drifts during the campaign (plugins/jjf2003/drift.py, segments'
`started`).

Found by the independent harness (docs/independent-campaigns.md, "JJF 2003: MIMU matrices", item 7):
a warm-up ramp of 0.1–0.3 °/s per hour is confounded with a sweep recorded in rate order (K_g's
diagonal 0 of 90 within U) and with the ±j differences of eq. (7) (g terms 1–2 %), and metro printed
confident numbers.  Each test writes a MIMU whose drift and recording times are known, so the error
the drift makes is known by hand.
"""

from __future__ import annotations

import datetime as dt
import json
import math
import re

import numpy as np
import pytest

GN = 9.80665
RATES = (-400, -200, -100, -50, 0, 50, 100, 200, 400)
KG = np.array([[1.02, 0.003, -0.002], [0.001, -0.98, 0.004], [-0.003, 0.002, 1.05]])
KA = np.array([[1.01, 0.002, -0.001], [-0.002, 0.99, 0.003], [0.001, -0.002, -1.03]])
BG, BA = np.array([0.1, -0.2, 0.05]), np.array([0.01, -0.02, 0.005])
UP = {"+x": (0, 1), "-x": (0, -1), "+y": (1, 1), "-y": (1, -1), "+z": (2, 1), "-z": (2, -1)}
HEAD = "gx [°/s],gy [°/s],gz [°/s],ax [gn],ay [gn],az [gn]"  # the CSV header of every record
N, STEP = 40, 50.0          # 40 samples at 1 s per record, a record begins every 50 s
#: a warm-up drift of 0.36, −0.25 and 0.18 °/s per hour (°/s per s)
DRIFT = np.array([0.36, -0.25, 0.18]) / 3600.0
T0 = dt.datetime(2026, 11, 24, 10, 15, tzinfo=dt.timezone(dt.timedelta(hours=8)))
#: eq. (5) turns a drift d into d·β: β = least-squares slope of the records' times on their rates;
#: by hand with records 50 s apart in rate order: 50·Σ(k − 4)·r_k / Σ r_k² = 50·4900/425000 s per
#: °/s
BETA = 50 * 4900 / 425000
#: eq. (7): g[:, x] = (U(+x) − U(−x))/2 of the pair means; the −x pair is recorded 100 s after +x
TAU_G = -50.0


def _write(root, *, drift=DRIFT, started=True, noise=1e-4, seed=7, times=None, bias=None):
    """A MIMU (eq. (1), (2), G = 0, no earth rate, local g = g_n) recorded in the plan's order (the
    twelve positions, then each sweep from −400 to +400 °/s), each record 40 s, one every 50 s; the
    gyro outputs drift by ``drift``·t (or by ``bias``(t), n × 3 °/s, where given) and carry white
    noise ``noise`` (°/s per sample)."""
    root.mkdir()
    rng = np.random.default_rng(seed)
    lines = ['format = "metro-campaign/1"', "[device]", 'id = "M"', 'output = "rate"',
             'gyro_range = "400 °/s"',
             'accel_range = "8 gn"', "[environment]", 'temperature = "20 °C"', 'humidity = "40 %"',
             "[site]",
             'latitude = "0.0°"', 'gravity = "9.80665 m/s²"', "[[equipment]]", 'id = "T"',
             'role = "rate_table"',
             'position_accuracy = "10″"', "[equipment.calibration]", 'certificate = "C"',
             'U = "2e-5"', "k = 2",
             "[[equipment]]", 'id = "D"', 'role = "acquisition"', "bits = 24", ""]
    k = [0]

    def seg(sid, kind, w, a, cond):
        t = k[0] * STEP + np.arange(N)
        change = bias(t) if bias is not None else drift[None, :] * t[:, None]
        g = w[None, :] + change + noise * rng.standard_normal((N, 3))
        data = np.column_stack([g, np.tile(a, (N, 1))])
        rows = "\n".join(",".join(repr(float(x)) for x in r) for r in data)
        (root / f"{sid}.csv").write_text(f"{HEAD}\n{rows}\n", encoding="utf-8")
        lines.extend(["[[segments]]", f'id = "{sid}"', f'kind = "{kind}"', f'file = "{sid}.csv"',
                      'sample_interval = "1 s"'])
        if started:
            when = (times or {}).get(sid, (T0 + dt.timedelta(seconds=k[0] * STEP)).isoformat())
            if when is not None:
                lines.append(f"started = {when}")
        lines.extend(["[segments.conditions]", *(f"{c} = {json.dumps(v, ensure_ascii=False)}" for c,
                                                 v in cond.items()),
                      ""])
        k[0] += 1

    for up, (j, s) in UP.items():
        force = np.zeros(3)
        force[j] = s
        for h in (0, 180):
            seg(f"pos{up}-h{h}", "position", BG.copy(), KA @ force + BA,
                {"up": up, "heading": f"{h}°"})
    for j, a in enumerate("xyz"):
        axis = np.zeros(3)
        axis[j] = 1.0
        for r in RATES:
            seg(f"rate-{a}-{r}", "rate", KG @ (r * axis) + BG, KA @ axis + BA,
                {"axis": a, "rate": f"{r} °/s"})
    (root / "manifest.toml").write_text("\n".join(lines) + "\n", encoding="utf-8")
    return root / "manifest.toml"


def _run(run_cli, manifest, items="7.2.1,7.2.2,7.2.3,7.2.4"):
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", items, "--data", str(manifest), "--json",
                             "--no-report")
    assert code in (0, 3, 4), err
    doc = json.loads(out)
    return {(r["item"], r["key"]): r for r in doc["results"]}, doc


def test_pooled_within_record_trend_finds_the_drift(tmp_path):
    """Each record's own trend, pooled: the drift of every gyro to its standard error (white noise
    1×10⁻⁴ °/s over 40 s: 1.4×10⁻⁶ °/s per s a record), from positions, rests and the gyros across
    a turning table (27 + 6·2 records per gyro; 7 of each sweep's 9 turn at least once in 40 s)."""
    from metro.core.run.manifest import load_manifest
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.plugins.jjf2003 import drift as D

    camp = load_manifest(_write(tmp_path / "d"), get_plugin_manager().reader_for)
    d = D.campaign_drift(camp)
    for i in range(3):
        assert d.d[i] == pytest.approx(DRIFT[i], abs=4 * d.u[i])
        assert d.u[i] < 1e-6 and d.significant(i)
        # positions, rests, the two sweeps across it (±50 °/s: 2000°)
        assert d.records[i] == 12 + 3 + 2 * 8
    assert d.mid_times["pos+x-h0"] == pytest.approx(19.5) and d.mid_times[
        "rate-z-400"] == pytest.approx(38 * STEP + 19.5)

    # a steady MIMU (seed 1: z = 1.3, 0.5, 0.5; over seeds 1–40 of this writer the z of the 120
    # gyros have rms 1.00 and one exceeds Z_CRIT = 2.5, as a normal z does 1.2 % of the time)
    steady = load_manifest(_write(tmp_path / "s", drift=np.zeros(3), started=False, seed=1),
                           get_plugin_manager().reader_for)
    s = D.campaign_drift(steady)
    assert s.mid_times is None and not any(s.significant(i) for i in range(3))


def _rows(result, symbol):
    return [x for x in result["budget"]["rows"] if x["symbol"] == symbol]


def test_drift_is_corrected_in_the_sweep_and_the_six_positions(run_cli, tmp_path):
    """With `started`, eq. (5) puts d_i·β into K_g[i, j] (β by hand, 0.5765 s per °/s: 1.8×10⁻⁵ …
    5.8×10⁻⁵ of K against a table of 2×10⁻⁵) and eq. (7) d_i·(−50 s) into g[i, x] (up to 0.018
    (°/s)/gn against U ≈ 6×10⁻⁴): the results are corrected for it (they printed the error, with a
    row √(d̂² + u²)·|τ| of its size, before) and carry the correction's uncertainty u_d, far below
    the effect (no model-error row: a line in time fits these trends)."""
    res, doc = _run(run_cli, _write(tmp_path / "t"))
    for i, r in enumerate("xyz"):
        for j, c in enumerate("xyz"):
            k = res[("7.2.3", f"K_g{r}{c}")]
            assert abs(k["value"] - KG[i, j]) < 0.02 * abs(DRIFT[i]) * BETA + 2e-7, (r, c)
            (u_d,) = _rows(k, "u_d")
            assert abs(u_d["contribution"]) < 0.02 * abs(DRIFT[i]) * BETA
            # a linear drift: the line in time fits the trends, no model error
            assert not _rows(k, "u_dm")
            # a constant rate (its change in time not resolved): that change budgeted, not corrected
            (u_c,) = _rows(k, "u_dc")
            assert abs(u_c["contribution"]) < 0.02 * abs(DRIFT[i]) * BETA
            assert f"τ = {BETA:.4g} s/(°/s)" in u_d["note"] and "corrected" in k["note"]
            assert abs(k["value"] - KG[i, j]) < k["U"] and k["reportable"]
        g = res[("7.2.2", f"g_{r}x")]
        assert abs(g["value"]) < 0.02 * abs(DRIFT[i] * TAU_G), r
        (u_d,) = _rows(g, "u_d")
        assert abs(u_d["contribution"]) < 0.02 * abs(DRIFT[i] * TAU_G) and "τ = -50 s/gn" in u_d[
            "note"]
        assert abs(g["value"]) < g["U"] and g["reportable"]
        # the biases and the accelerometers do not difference records: no drift row, not corrected
        for key in (("7.2.2", f"B_g{r}"), ("7.2.4", f"K_a{r}{r}")):
            assert not any(x["symbol"] in ("u_d", "u_dm") for x
                           in res[key]["budget"]["rows"]) and res[key]["reportable"]
            assert "corrected" not in res[key]["note"]
    warnings = [w for it in doc["items"] for w in it["warnings"]]
    assert any("gyro x's bias drifts by 0.36" in w and "corrected" in w for w in warnings)
    # a key of the format, not unknown
    assert not any("started" in str(w) for w in doc["manifest_warnings"])


@pytest.mark.parametrize("settle_s", [300.0, 900.0])
def test_a_settling_warm_up_is_covered_by_the_model_error_row(run_cli, tmp_path, settle_s):
    """A MEMS warm-up settles exponentially: β(t) = d₀·T·(1 − e^(−t/T)), its rate falling from d₀ to
    e^(−1950 s/T)·d₀ over the campaign (T = 5 and 15 min). A drift rate that is a line in time
    follows it only roughly (the g terms, recorded in the first 600 s where it bends most, are off
    by up to 1.5 U without more); the row u_dm — the trends' residuals from the line, integrated
    over time — covers what the line leaves out: every K_g and g within U (over seeds 0–3 of this
    writer: 100 % of 72 g terms within U, max |E_n| 0.51; before the row, T = 5 min: 33 %, max
    2.3)."""
    d0 = DRIFT
    res, _ = _run(run_cli, _write(tmp_path / "e", bias=lambda t: d0[None, :] * settle_s
                                  * (1 - np.exp(-t[:, None] / settle_s))),
                  "7.2.2,7.2.3")
    worst = 0.0
    for i, r in enumerate("xyz"):
        for j, c in enumerate("xyz"):
            k, g = res[("7.2.3", f"K_g{r}{c}")], res[("7.2.2", f"g_{r}{c}")]
            worst = max(worst, abs(k["value"] - KG[i, j]) / k["U"], abs(g["value"]) / g["U"])
            assert _rows(k, "u_dm") and _rows(g, "u_dm")
    assert worst < 1.0


def _u_b(result):
    return [x for x in result["budget"]["rows"] if x["symbol"] == "u_b"]


def _U_without_u_b(result):
    """U of a result without its u_b row (the same k): what the material test compares with."""
    rows = result["budget"]["rows"]
    u0 = math.sqrt(sum(x["contribution"] ** 2 for x in rows if x["symbol"] != "u_b"))
    return result["U"] * u0 / result["u"]


def test_without_recording_times_a_significant_drift_is_not_reportable(run_cli, tmp_path):
    res, _ = _run(run_cli, _write(tmp_path / "n", started=False))
    for i, r in enumerate("xyz"):
        for key in [("7.2.1", f"K_g{r}{r}"), ("7.2.3", f"K_g{r}{r}"), ("7.2.2", f"g_{r}z")]:
            assert res[key]["reportable"] is False, key
            assert "`started`" in res[key]["reason"] and "warm up" in res[key]["reason"]
        # a cross term too, though its U (alignment rows) is large against what the drift does with
        # the 40-s records back to back (β = 40·4900/425000): gaps between the records, which no
        # manifest without times states, would lengthen that lever arm without bound. It carries the
        # row u_b = (|d̂| + 2u(d̂))·β (d̂ + 2u(d̂) within 2 % of the true drift)
        for c in "xyz":
            k = res[("7.2.3", f"K_g{r}{c}")]
            effect = abs(DRIFT[i]) * 40 * 4900 / 425000
            assert k["reportable"] is False and "by more with gaps between them" in k["reason"], (
                r, c)
            assert _u_b(k)[0]["contribution"] == pytest.approx(effect, rel=0.02), (r, c)
            said = float(re.search(r"\(([0-9.]+) × its U without the drift\)",
                                   k["reason"]).group(1))
            # 2 digits; k of U without u_b differs a little
            assert said == pytest.approx(effect / _U_without_u_b(k), rel=0.1), (k["reason"], r, c)
        for key in (("7.2.2", f"B_g{r}"), ("7.2.4", f"K_a{r}{r}"), ("7.2.4", f"B_a{r}")):
            assert res[key]["reportable"] is True, key
            assert not _u_b(res[key]), key


def test_without_recording_times_a_seen_drift_that_barely_moves_a_result_leaves_it_reportable(
    run_cli, tmp_path):
    """A drift of 0.018 °/s per hour (20 standard errors) moves g by several U, but a cross term of
    K_g, whose U holds the alignment rows, by 1–3 % of it with the records back to back: gaps would
    have to lengthen the lever arm tenfold before that mattered (drift.MATERIAL), and u_b carries
    it."""
    from metro.plugins.jjf2003 import drift as D

    res, _ = _run(run_cli, _write(tmp_path / "w", drift=DRIFT * 0.05, started=False, seed=3),
                  "7.2.2,7.2.3")
    for i, r in enumerate("xyz"):
        for c in "xyz":
            g = res[("7.2.2", f"g_{r}{c}")]
            assert g["reportable"] is False and "gaps between them" in g["reason"], (r, c)
            if r == c:
                continue
            k = res[("7.2.3", f"K_g{r}{c}")]
            effect = abs(DRIFT[i] * 0.05) * 40 * 4900 / 425000
            assert effect < 0.05 * _U_without_u_b(k) < D.MATERIAL * _U_without_u_b(k), (r, c)
            assert k["reportable"] is True and _u_b(k), (r, c)


def test_without_recording_times_the_drift_the_trends_cannot_exclude_is_budgeted(run_cli, tmp_path):
    """A steady MIMU, no times: every result reportable; each K_g and g carries u_b = (|d̂| +
    2u(d̂))·|τ|, d̂ and u(d̂) the pooled within-record trend (drift.campaign_drift) and τ by hand
    for 40-s records back to back in the plan's order: eq. (5) 40·4900/425000 s per °/s; eq. (7)
    column x: the +x pair's mid-time 40 s, the −x pair's 120 s, (40 − 120)/2 = −40 s per g_n."""
    from metro.core.run.manifest import load_manifest
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.plugins.jjf2003 import drift as D

    manifest = _write(tmp_path / "s", drift=np.zeros(3), started=False, seed=1)
    res, _ = _run(run_cli, manifest)
    assert all(r["reportable"] for r in res.values())
    est = D.campaign_drift(load_manifest(manifest, get_plugin_manager().reader_for))
    for i, r in enumerate("xyz"):
        bound = abs(est.d[i]) + 2 * est.u[i]
        assert 0 < abs(est.d[i]) < D.Z_CRIT * est.u[i]  # not seen
        for c in "xyz":
            (k,) = _u_b(res[("7.2.3", f"K_g{r}{c}")])
            assert k["contribution"] == pytest.approx(bound * 40 * 4900 / 425000, rel=1e-9), (r, c)
            assert k["type"] == "B" and k["dof"] == est.dof[i]
        (g,) = _u_b(res[("7.2.2", f"g_{r}x")])
        assert g["contribution"] == pytest.approx(bound * 40.0, rel=1e-9), r
    # a gyro of the same MIMU given its recording times has no u_b (the drift is evaluated instead)
    res, _ = _run(run_cli, _write(tmp_path / "t", drift=np.zeros(3), seed=1))
    assert not any(_u_b(r) for r in res.values())


def test_times_on_some_records_only_are_not_used(run_cli, tmp_path):
    res, doc = _run(run_cli, _write(tmp_path / "p", times={"rate-y-0": None}), "7.2.1")
    warnings = [w for it in doc["items"] for w in it["warnings"]]
    assert any("`started` is given on 38 of the 39 records only" in w for w in warnings)
    assert all(not r["reportable"] and not any(x["symbol"] == "u_d" for x in r["budget"]["rows"])
               for r in res.values())


@pytest.mark.parametrize("value, message", [
    ('"24.11.2026 10:15"', "not a date and time"),
    ("2026-11-24T10:15:00", "no UTC offset"),
    ('"2026-11-24T10:15:00"', "no UTC offset"),
    ("2026-11-24", "without the time of day"),
    ("42", "not a date and time"),
])
def test_bad_started_is_refused(run_cli, tmp_path, value, message):
    manifest = _write(tmp_path / "b", times={"pos+y-h0": value})
    out = tmp_path / "cert.docx"
    code, stdout, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.1", "--data", str(manifest),
                                "--report", str(out),
                                "--no-progress")
    assert code == 2 and "Traceback" not in err
    assert "segments[4].started" in err and message in err and "manifest.toml" in err
    assert not out.exists()


def test_overlapping_records_are_refused(run_cli, tmp_path):
    """Record 3 (pos-x-h0) said to begin 30 s after record 2, which lasts 40 s."""
    manifest = _write(
        tmp_path / "o", times={"pos-x-h0": (T0 + dt.timedelta(seconds=STEP + 30)).isoformat()}
    )
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.2", "--data", str(manifest),
                             "--json", "--no-report")
    assert code == 2 and "Traceback" not in err
    doc = json.loads(out)
    assert doc["field"] == "segments.pos-x-h0.started" and "cannot overlap" in doc["message"]


def test_started_is_written_back_by_the_campaign_writer(tmp_path):
    from metro.core.run.manifest import load_manifest
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.manifest_writer import manifest_text

    camp = load_manifest(_write(tmp_path / "w"), get_plugin_manager().reader_for)
    text = manifest_text(camp, {s.id: (f"{s.id}.csv", {}) for s in camp.segments})
    import tomllib

    written = [s.get("started") for s in tomllib.loads(text)["segments"]]  # a TOML offset date-time
    assert written == [s.started for s in camp.segments] and None not in written
    assert dt.datetime.fromisoformat("2026-11-24T10:15:50+08:00") in written
    assert camp.segments[1].started == T0 + dt.timedelta(seconds=STEP)
    assert not math.isnan(camp.segments[1].started.timestamp())


def test_simulated_station_warm_up_is_corrected_from_its_recording_times(tmp_path, run_cli):
    """plan → acquire → run on the simulated MIMU still warming up (class mems-warmup: 1, −0.6,
    0.8 °/s per hour): the station writes `started`; K_g and g are corrected for the drift (the g
    terms it moves by 2 U, K_gxx by 0.4 U; before the correction they sat at mean E_n ±0.3 … 0.5
    within an uncorrected row); the same records without their times make K_g and g not reportable
    (the drift is seen, its lever arm not known), B_g stays reportable."""
    import attrs

    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.cli.present import truth_checks
    from metro.core.run.runner import merge_steps, run_items
    from metro.instruments.mimu import station_factory

    code, _, err = run_cli("acquire", "-s", "jjf2003", "-i", "7.2.1,7.2.2", "--out",
                           str(tmp_path / "c"), "--seed", "3",
                           "--station-option", "device_class=mems-warmup", "--no-progress")
    assert code == 0, err
    text = (tmp_path / "c" / "manifest.toml").read_text(encoding="utf-8")
    import tomllib

    started = [s.get("started") for s in tomllib.loads(text)["segments"]]  # TOML offset date-times
    assert len(started) == 27 + 12 and None not in started
    assert started.count(dt.datetime.fromisoformat("2026-03-01T09:00:00+08:00")) == 1
    pm = get_plugin_manager(autoload=False)
    procs = [pm.procedure("jjf2003", i) for i in ("7.2.1", "7.2.2")]
    steps = merge_steps([c().sequence(c.option_values({})) for c in procs])
    camp = station_factory(seed=3, device_class="mems-warmup").acquire(steps)
    rec = run_items(pm, "jjf2003", ["7.2.1", "7.2.2"], campaign=camp)
    checks = {c["key"]: c for c in truth_checks(rec)}
    for r in "xyz":
        assert checks[f"K_g{r}{r}"]["within_U"] and checks[f"g_{r}{r}"]["within_U"], r
    kxx = rec.outcomes[0].result("K_gxx")
    # by hand: 1 °/s/h over a ±400 °/s sweep in rate order, 30 s records every 50 s: β =
    # 50·4900/425000
    effect = 1.0 / 3600 * 50 * 4900 / 425000
    u_d = next(x for x in kxx.budget.rows if x.symbol == "u_d").contribution.magnitude
    assert u_d < 0.25 * effect and "corrected for the gyro bias drift" in str(kxx.note)
    # eq. (7): the ±x pair means 100 s apart: 50 s × the drift ≈ 1–2 U
    for r, share in zip("xyz", (1.0, -0.6, 0.8)):
        g = rec.outcomes[1].result(f"g_{r}x")
        effect = share / 3600 * 50.0
        assert abs(g.value.magnitude - checks[f"g_{r}x"]["truth"]) < 0.4 * abs(effect), r
        assert abs(g.value.magnitude - checks[f"g_{r}x"]["truth"]) < float(g.U.magnitude), r
        assert "corrected for the gyro bias drift" in str(g.note)
    bare = attrs.evolve(camp, segments=[attrs.evolve(s, started=None) for s in camp.segments])
    rec2 = run_items(pm, "jjf2003", ["7.2.1", "7.2.2"], campaign=bare)
    out = {r.metric.key: r for o in rec2.outcomes for r in o.results}
    assert not out["K_gxx"].reportable and not any(x.symbol == "u_d" for x
                                                   in out["K_gxx"].budget.rows)
    assert any(x.symbol == "u_b" for x in out["K_gxx"].budget.rows)
    assert not out["g_xx"].reportable and "`started`" in out["g_xx"].reason and out[
        "B_gx"].reportable


def test_certificate_gives_the_reason_in_its_language(run_cli, tmp_path):
    """The JJF 2003 certificate wrote a not-reportable result's reason as plain English text in a
    Chinese certificate (the message was turned into a str before the document translated it)."""
    import docx

    out = tmp_path / "cert.docx"
    code, _, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.1", "--data",
                           str(_write(tmp_path / "c", started=False)),
                           "--report", str(out), "--lang", "zh", "--no-progress")
    assert code in (0, 3, 4), err
    doc = docx.Document(str(out))
    cells = "\n".join(c.text for t in doc.tables for row in t.rows for c in row.cells)
    text = "\n".join(p.text for p in doc.paragraphs)
    # the result's cell says it is withheld; why follows the table, in the certificate's language
    assert "不予报告" in cells and "漂移 0.36" not in cells
    assert "陀螺 x 的零偏在本批次测量中漂移 0.36" in text and "gyro x's bias drifts" not in text


def test_certificate_matrix_withholds_the_cells_that_are_not_reportable(run_cli, tmp_path):
    """The g matrix printed every g_ij with its U although the drift had made them not reportable
    (seen on a rendered mems-warmup certificate without `started`): each such cell now reads "not
    reportable", its U "—", and the reason follows the matrix."""
    import docx

    out = tmp_path / "cert.docx"
    code, stdout, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.2", "--data",
                                str(_write(tmp_path / "c", started=False)), "--report", str(out),
                                "--lang", "en",
                                "--no-progress", "--json")
    assert code in (0, 3, 4), err
    results = {r["key"]: r for r in json.loads(stdout)["results"]}
    withheld = sorted(k for k, r in results.items() if k.startswith("g_") and not r["reportable"])
    assert withheld, "the drift should make some g terms not reportable"
    doc = docx.Document(str(out))
    cells = [c.text for t in doc.tables for row in t.rows for c in row.cells]
    assert cells.count("not reportable") == len(withheld)
    for k in withheld:  # no withheld value is printed as a result
        assert results[k]["reported"]["value"] not in cells, k
    paras = "\n".join(p.text for p in doc.paragraphs)
    assert "not reportable: gyro" in paras and "drifts" in paras
    # the reasons' shared parts once: what each gyro does, named with its withheld cells, and what
    # to do, once for all of them (core.notes.group_notes); what the drift does to each cell stays
    # per cell
    assert paras.count("the manifest gives no recording times") == 1, paras
    for r in "xyz":
        cells_r = [k for k in withheld if k[2] == r]
        if cells_r:
            assert paras.count(f"not reportable: gyro {r}'s bias drifts by") == 1, paras
            # the document sets g_xx as g with subscript xx
            shown = ", ".join(k.replace("_", "") for k in cells_r)
            assert f"{shown}: not reportable: gyro {r}'s bias drifts by" in paras, paras
    assert paras.count("recorded back to back in the plan's order the drift would move this result "
                       "by") < len(withheld)


def test_terminal_states_a_drift_warning_once_for_the_items_that_give_it(run_cli, tmp_path):
    """7.2.1, 7.2.2 and 7.2.3 each see the campaign's drift; the terminal says so once per gyro,
    naming the three items (core.present), not nine times."""
    code, out, err = run_cli("run", "-s", "jjf2003", "-i", "7.2.1,7.2.2,7.2.3", "--data",
                             str(_write(tmp_path / "w", started=False)), "--no-report",
                             "--no-progress")
    assert code in (0, 3, 4), err
    flat = " ".join(out.split())
    assert flat.count("warning (7.2.1, 7.2.2, 7.2.3): gyro x's bias drifts") == 1, flat[-3000:]
    assert flat.count("gyro x's bias drifts by 0.36 ±") == 1
    assert "warning (7.2.1): gyro" not in flat
    # the K_g and g that drift makes not reportable say so in their rows; why, below the table, each
    # shared part of the reasons once (core.notes.group_notes): the advice once for all 21 results
    assert flat.count("below)") == 21  # "not reportable (why: below)", wrapped in the table's cells
    assert flat.count("the manifest gives no recording times (`started` on the segments) to budget "
                      "the drift") == 1
    assert flat.count("not reportable (K_gxx (7.2.1, 7.2.3); g_xx, g_xy, g_xz (7.2.2); K_gxy, "
                      "K_gxz (7.2.3)): gyro x's bias drifts by 0.36") == 1, flat


def test_without_times_a_gyro_no_record_gives_a_trend_is_withheld():
    """Fewer than two records give a gyro a within-record trend (a 7.2.1 sweep alone whose turning
    records cover less than one revolution each): its drift can be neither seen nor bounded, so
    without recording times no u_b can be formed and its results are withheld, saying why."""
    from metro.plugins.jjf2003 import drift as D

    d = D.GyroDrift(d=(0.0, 1e-6, 0.0), u=(math.inf, 1e-6, 1e-7), dof=(0, 10, 10),
                    records=(1, 12, 12),
                    mid_times=None, durations={})
    assert D.bound_row(d, 0, 5.0, "", "sweep", "s/(°/s)") is None
    reason = str(D.not_reportable_reason(d, 0, 5.0, 1e-4, ""))
    assert ("fewer than two of the records give gyro x a within-record trend" in reason
            and "`started`" in reason)
    # gyro z: not significant (z = 0), so reportable; its u_b by hand: (0 + 2·1e-7)·5 s/(°/s)
    assert D.not_reportable_reason(d, 2, 5.0, 1e-4, "") is None
    assert D.bound_row(d, 2, -5.0, "", "sweep",
                       "s/(°/s)").contribution.magnitude == pytest.approx(1e-6, rel=1e-12)
    # gyro y: 1 standard error is not seen: reportable, u_b = (1e-6 + 2·1e-6)·5
    assert D.not_reportable_reason(d, 1, 5.0, 1e-4, "") is None
    assert D.bound_row(d, 1, 5.0, "", "sweep",
                       "s/(°/s)").contribution.magnitude == pytest.approx(1.5e-5, rel=1e-12)
    # a seen drift (z = 10) moving the result by 5e-5 against U = 1e-4 (half of U, ≥ MATERIAL):
    # withheld
    d2 = D.GyroDrift(d=(1e-5, 0.0, 0.0), u=(1e-6, 1e-6, 1e-6), dof=(10, 10, 10),
                     records=(12, 12, 12),
                     mid_times=None, durations={})
    assert "by more with gaps between them" in str(D.not_reportable_reason(d2, 0, 5.0, 1e-4, ""))
    # 5e-5 against 1e-3: below a tenth of U
    assert D.not_reportable_reason(d2, 0, 5.0, 1e-3, "") is None


def test_a_drift_effect_is_corrected_beyond_the_t_quantile_of_its_model(monkeypatch):
    """The correction threshold follows the drift model's ν (drift.correct_threshold): the two-sided
    t quantile at the false rate Z_CORRECT has for a normal variable. Reference: Student's t table,
    t(0.975; 10) = 2.228 and t(0.975; 30) = 2.042 for the normal 1.960; and an effect at 2.8 u(Δ) is
    corrected with ν = 1000 but not with ν = 10 (threshold 3.04: twelve six-position records
    alone)."""
    from metro.plugins.jjf2003 import drift as D

    assert D.correct_threshold(math.inf) == pytest.approx(2.5, abs=1e-9)
    monkeypatch.setattr(D, "Z_CORRECT", 1.959964)
    assert D.correct_threshold(10) == pytest.approx(2.228, abs=1e-3)
    assert D.correct_threshold(30) == pytest.approx(2.042, abs=1e-3)
    monkeypatch.undo()
    assert D.correct_threshold(10) == pytest.approx(3.04, abs=0.01)

    def model(dof):
        return D.RateModel(a=2.8e-6, c=0.0, cov=((1e-12, 0.0), (0.0, 0.0)), dof=dof, t_ref=0.0,
                           birge=1.0,
                           line=False, records=dof + 1)

    for dof, corrected in ((1000, True), (10, False)):
        drift = D.GyroDrift(d=(2.8e-6, 0.0, 0.0), u=(1e-6, 1.0, 1.0), dof=(dof, 1, 1),
                            records=(dof + 1, 2, 2),
                            mid_times={}, durations={}, models=(model(dof), None, None))
        delta, rows = D.correction(drift, 0, np.array([1.0, 0.0, 0.0]), "", "test", "s")
        assert (delta != 0.0) is corrected, dof
        assert delta == pytest.approx(2.8e-6 if corrected else 0.0)

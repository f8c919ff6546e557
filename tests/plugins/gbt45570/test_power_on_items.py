"""GB/T 45570 D.5.4: every temperature point is a power-on of its own.

D.5.4.2 c) powers the gyro off while the chamber moves to the next temperature, so each B_i of
eq. (D.43) carries the device's turn-on scatter σ_on, which D.5.3 (eq. D.42) measures on the same
campaign.  The independent harness (benchmarks/independent_gbt_more.py, variant bt-bh-pulse-1Hz)
found B_t within U on 63 % of 200 devices with U built from each record's batch means alone; with
the turn-on row (and the Satterthwaite degrees of freedom of σ_on² = B_r² − mean u_A²) 96 % and
96.5 % on two sets of 200.  Here devices are written with numpy in the documented format (rate
output in °/h, no rounding): a bias linear in T, a turn-on scatter five times the record noise.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

OMEGA_E = 15.041  # °/h, eq. (D.40)


def _campaign(folder: Path, rng, *, sigma_on: float, arw: float, slope: float, repeats: bool | int,
              seconds: int = 600, stated: str = "") -> float:
    """Three temperature points (−40, 20, 60 °C), optionally D.5.3's repeats at 20 °C (True: 7, or
    that many); returns the true B_t = |slope| (a bias linear in T: D.43's every slope is the
    same)."""
    lat = 30.0
    earth = OMEGA_E * math.sin(math.radians(lat))
    segs = []

    def record(name, bias):
        x = bias + earth + rng.standard_normal(seconds) * arw * 60.0
        t = np.arange(1, seconds + 1)
        (folder / f"{name}.csv").write_text("time [s],output [°/h]\n" + "\n".join(
            f"{a},{b!r}" for a, b in zip(t.tolist(), x.tolist())) + "\n", encoding="utf-8")
        return f"{name}.csv"

    b0 = 0.3
    for i, T in enumerate((-40.0, 20.0, 60.0)):
        f = record(f"temperature-{i + 1}", b0 + slope * (T - 20.0) + sigma_on
                   * rng.standard_normal())
        segs.append(f'[[segments]]\nid = "temperature-{i + 1}"\nkind = "static-temperature"\nfile '
                    f'= "{f}"\nsample_interval = "1 s"\n[segments.conditions]\norientation = "IRA '
                    f'up"\ntemperature = "{T:g} °C"\n')
    if repeats:
        for j in range(1, (7 if repeats is True else int(repeats)) + 1):
            f = record(f"repeat-{j}", b0 + sigma_on * rng.standard_normal())
            segs.append(f'[[segments]]\nid = "repeat-{j}"\nkind = "static-repeat"\nfile = "{f}"\n'
                        'sample_interval = "1 s"\n[segments.conditions]\norientation = "IRA '
                        f'up"\nrun = {j}\n')
    (folder / "manifest.toml").write_text(
        '[device]\nid = "BT-1"\noutput = "rate"\n'
        + (f'bias_repeatability = "{stated}"\n' if stated else "")
        + '\n[environment]\ntemperature = "20 °C"\nhumidity = "40 %"\n\n'
        f'[site]\nlatitude = "{lat}°"\n\n[[equipment]]\nid = "CH-1"\nrole = "chamber"\n'
        '[equipment.calibration]\ncertificate = "CH-CERT"\nU = "0.5 K"\nk = 2\n\n'
        + "\n".join(segs),
        encoding="utf-8")
    return abs(slope)


def _run(run_cli, folder: Path, items: str = "D.5.4") -> dict:
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", items, "--data",
                             str(folder / "manifest.toml"),
                             "--json", "--no-report", "--quiet")
    assert code in (0, 3, 4), err
    return {r["key"]: r for r in json.loads(out)["results"]}


def _bt(run_cli, folder: Path) -> dict:
    return _run(run_cli, folder)["Bt"]


def test_d54_budget_has_the_turn_on_scatter_of_d53(run_cli, tmp_path):
    """Each point's u holds σ_on of the D.5.3 repeats on the same campaign: σ_on² = B_r² − mean u_A²
    (as D.5.3's own note states it) entered as the posterior mean of that variance component given
    the runs, ν = ∞ (interpretations.md, "σ_on — a variance component the data only bound"), so U is
    at least k·√2·σ_on/|ΔT| at the maximising point."""
    rng = np.random.default_rng(7)
    folder = tmp_path / "dev"
    folder.mkdir()
    _campaign(folder, rng, sigma_on=0.01, arw=0.002, slope=1e-4, repeats=True)
    res = _run(run_cli, folder, "D.5.3,D.5.4")
    br, bt = res["Br"], res["Bt"]
    s_d53 = float(br["note"].split("√(B_r² − mean u_A²) = ")[1].split(" ")[0])
    w = float(br["note"].split("√(mean u_A²) = ")[1].split(" ")[0])
    assert 0.003 < s_d53 < 0.03  # the device's 0.01 °/h, estimated from 7 power-ons
    (row,) = [r for r in bt["budget"]["rows"] if "σ_on = " in r["note"]]
    s_on = float(row["note"].split("σ_on = ")[1].split(" ")[0])
    # the posterior mean by hand from D.5.3's printed B_r and within-run part (Q = 7, ν = 6): the
    # χ²(4) and χ²(6) cdfs in closed form, F₄(c) = 1 − e^(−c/2)(1 + c/2), F₆(c) = 1 − e^(−c/2)(1 +
    # c/2 + c²/8)
    b2 = br["value"] ** 2
    c = 6 * b2 / w**2
    F4 = 1 - math.exp(-c / 2) * (1 + c / 2)
    F6 = 1 - math.exp(-c / 2) * (1 + c / 2 + c * c / 8)
    # 3–4 printed digits
    assert s_on == pytest.approx(math.sqrt(6 * b2 * F4 / (4 * F6) - w**2), rel=5e-3)
    # resolved here: about √(1.5·B_r² − u_A²), the t tail of 6 degrees of freedom
    assert s_on > s_d53
    T = float(bt["note"].split("largest at T = ")[1].split(" ")[0])
    dT = abs(T - 20.0)  # the maximising point against room temperature
    assert row["standard_uncertainty"] >= math.sqrt(2) * s_on / dT * (1 - 1e-3)
    assert "(ν = inf)" in row["note"]
    assert bt["U"] >= 2 * math.sqrt(2) * s_on / dT


def test_d54_three_power_ons_cannot_bound_the_turn_on_scatter(run_cli, tmp_path):
    """interpretations.md "σ_on — a variance component the data only bound": the posterior mean of
    σ_on² from Q power-ons is infinite for Q < 4, so three static-repeat runs leave the difference
    of two power-ons unbounded: not reportable, the reason saying so (before, σ_on came from any two
    runs); a stated device.bias_repeatability still stands for it."""
    folder = tmp_path / "three"
    folder.mkdir()
    _campaign(folder, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=3)
    res = _bt(run_cli, folder)
    assert res["reportable"] is False
    assert "3 D.5.3 power-ons cannot bound the turn-on scatter" in res["reason"], res["reason"]
    stated = tmp_path / "three-stated"
    stated.mkdir()
    _campaign(stated, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=3,
              stated="0.01 °/h")
    res = _bt(run_cli, stated)
    assert res["reportable"] is True
    assert [r for r in res["budget"]["rows"] if "stated for the device (device.bias_repeatability)"
            in r["note"]]


def test_d54_without_the_turn_on_scatter_is_not_reportable(run_cli, tmp_path):
    """interpretations.md "D.5.4 / D.5.5 — without the turn-on scatter": no D.5.3 repeats and no
    stated device.bias_repeatability leave the difference of two power-ons unbounded (the
    independent harness's bt-bh devices without repeats: B_t within U on 52 %, B_h 87–89 %, reported
    with a note): not reportable, saying what to record or state."""
    folder = tmp_path / "dev"
    folder.mkdir()
    _campaign(folder, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=False)
    res = _bt(run_cli, folder)
    assert res["reportable"] is False
    assert "D.5.3" in res["reason"] and "bias_repeatability" in res[
        "reason"] and "static-repeat" in res["reason"]
    assert not [r for r in res["budget"]["rows"] if "σ_on = " in r["note"]]


def test_d54_takes_a_stated_bias_repeatability(run_cli, tmp_path):
    """Without repeats, [device] bias_repeatability (a B_r measured before) stands for σ_on as a
    type B row: reportable, U holds k·√2·σ_on/|ΔT|; a bad value is refused naming the field."""
    folder = tmp_path / "dev"
    folder.mkdir()
    _campaign(folder, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=False,
              stated="0.012 °/h")
    res = _bt(run_cli, folder)
    assert res["reportable"] is True and not res["reason"]
    T = float(res["note"].split("largest at T = ")[1].split(" ")[0])
    (row,) = [r for r in res["budget"]["rows"] if "device.bias_repeatability" in r["note"]]
    assert row["standard_uncertainty"] >= math.sqrt(2) * 0.012 / abs(T - 20.0) * (1 - 1e-9)
    assert res["U"] >= 2 * math.sqrt(2) * 0.012 / abs(T - 20.0)
    bad = tmp_path / "bad"
    bad.mkdir()
    _campaign(bad, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=False,
              stated="-1 °/h")
    before = (bad / "manifest.toml").read_bytes()
    from metro.core.cli.app import main

    code = main(["run", "-s", "gbt45570", "-i", "D.5.4", "--data", str(bad / "manifest.toml"),
                 "--no-report", "--quiet"])
    assert code == 2 and (bad / "manifest.toml").read_bytes() == before


def test_d54_d55_plan_the_d53_power_ons(run_cli):
    """metro plan lists D.5.3's power-ons with D.5.4 / D.5.5 (measured once when D.5.3 runs too)."""
    for items, n in (("D.5.4", 3 + 7), ("D.5.5", 6 + 7), ("D.5.3,D.5.4,D.5.5", 3 + 6 + 7)):
        code, out, err = run_cli("plan", "-s", "gbt45570", "-i", items, "--json")
        assert code == 0, err
        steps = json.loads(out)["steps"]
        assert len(steps) == n and sum(s["kind"] == "static-repeat" for s in steps) == 7


def test_d54_covers_the_turn_on_scatter_over_devices(run_cli, tmp_path):
    """σ_on = 0.01 °/h against a 10 min record's 0.002 °/h: without σ_on in each point's u, U
    covered B_t on 22 of these 30 devices (measured before the fix); with it, at least 27."""
    within = 0
    for seed in range(30):
        rng = np.random.default_rng([54, seed])
        folder = tmp_path / f"dev{seed}"
        folder.mkdir()
        truth = _campaign(folder, rng, sigma_on=0.01, arw=0.002,
                          slope=float(rng.uniform(-3e-4, 3e-4)),
                          repeats=True)
        res = _bt(run_cli, folder)
        within += abs(res["value"] - truth) <= res["U"]
    assert within >= 27, within


# --------------------------------------------------------------------------------------------
# D.1.5 / D.2.5: every temperature point is a power-on of its own, so each K_i carries K's turn-on
# scatter, which D.1.4 / D.2.4 measure on the same campaign
# --------------------------------------------------------------------------------------------

@pytest.fixture(scope="module")
def harness(gbt_more_harness):
    return gbt_more_harness


def _kt_within_u(run_cli, tmp_path: Path, build, item: str, stream: int, prefix: str) -> int:
    """How many of 12 harness devices (``build``, seeds ``[stream, 0…11]``) read ``item``'s K_t
    within U; each K_t is in ppm/°C and its budget has the turn-on scatter of K."""
    within = 0
    for seed in range(12):
        folder = tmp_path / f"{prefix}{seed}"
        folder.mkdir()
        truth = build(folder, np.random.default_rng([stream, seed]), quick=True)
        res = _run(run_cli, folder, item)["Kt"]
        t = truth[(item, "Kt")][0]
        assert res["unit"] in ("ppm/°C", "ppm/Δ°C"), res["unit"]
        within += abs(res["value"] - t) <= res["U"]
        (row,) = [r for r in res["budget"]["rows"] if r["symbol"] == "s(max_i |ΔK_i/(K₀₀ΔT_i)|)"]
        assert "turn-on scatter of K" in row["note"], row["note"]
    return within


def test_d25_covers_the_turn_on_scatter_of_k_over_devices(run_cli, tmp_path, harness):
    """The independent harness's rate-method gyro (benchmarks/independent_gbt_more.py,
    kt-rate-lsb-1Hz): 5 or 6 temperature points, each a power-on with K's scatter σ_K 5–100 ppm,
    D.2.4's 7 runs in the campaign.  Before, U held the fits' noise alone (≈ 1 ppm of K): K_t within
    U on 15 of 100 devices, mean E_n +3.1, up to 45; with σ_K from D.2.4 in each K_i's u, 97 of 100.
    Here 12 short devices (20 s per rate point; 10 of 12 within U after the fix)."""
    within = _kt_within_u(run_cli, tmp_path, harness.build_kt, "D.2.5", 25, "kt")
    assert within >= 10, within


def _kt_without_repeats(run_cli, folder: Path, build, item: str, stream: int, repeats: str):
    """A harness device without the ``repeats`` item's runs: ``item``'s K_t says the turn-on
    scatter of K is not in U, and is not reportable (interpretations.md "GB/T 45570 — a difference
    of power-ons needs their turn-on scatter")."""
    folder.mkdir()
    build(folder, np.random.default_rng([stream, 99]), quick=True, repeats=False)
    res = _run(run_cli, folder, item)["Kt"]
    assert "turn-on scatter of K not in U" in res["note"] and repeats in res["note"], res["note"]
    assert (res["reportable"] is False and repeats in res["reason"]
            and "scale_factor_repeatability" in res["reason"])


def test_d25_without_d24_runs_says_the_turn_on_scatter_is_not_in_u(run_cli, tmp_path, harness):
    _kt_without_repeats(run_cli, tmp_path / "kt", harness.build_kt, "D.2.5", 25, "D.2.4")


def test_d15_covers_the_turn_on_scatter_of_k_over_devices(run_cli, tmp_path, harness):
    """The harness's angle-method laser gyro (benchmarks/independent_gbt_more.py, kt-angle-pulse): 3
    or 5 temperature points, each a power-on with K's scatter σ_K 1–20 ppm (D.1.5.2 c)), D.1.4's 7
    runs in the campaign.  With U from the sweeps' fits alone K_t was within U on 0 of 4 such
    devices (mean E_n −8); with D.1.4's K_r in each K_i's u 95–97 % of 100.  Here 12 short devices
    (11 rate points, m = 3; 12 of 12 within U after the fix, 4 of 12 before)."""
    within = _kt_within_u(run_cli, tmp_path, harness.build_kt_angle, "D.1.5", 15, "kta")
    assert within >= 10, within


def test_d15_without_d14_runs_says_the_turn_on_scatter_is_not_in_u(run_cli, tmp_path, harness):
    _kt_without_repeats(run_cli, tmp_path / "kta", harness.build_kt_angle, "D.1.5", 15, "D.1.4")


def _field_campaign(folder: Path, rng, *, sigma_on: float, repeats: bool,
                    seconds: int = 600) -> None:
    """D.5.5: ±1 mT along IRA, XRA, YRA, each record a power-on of its own (turn-on scatter σ_on),
    no magnetic sensitivity; optionally D.5.3's 7 repeats."""
    lat, arw = 30.0, 0.002
    earth = OMEGA_E * math.sin(math.radians(lat))
    segs = []

    def record(name, bias):
        x = bias + earth + rng.standard_normal(seconds) * arw * 60.0
        (folder / f"{name}.csv").write_text("time [s],output [°/h]\n" + "\n".join(
            f"{a},{b!r}" for a, b in zip(range(1, seconds + 1), x.tolist())) + "\n",
                                            encoding="utf-8")
        return f"{name}.csv"

    for ax in ("IRA", "XRA", "YRA"):
        for h in (1, -1):
            sid = f"field-{ax}-{'plus' if h > 0 else 'minus'}"
            f = record(sid, 0.3 + sigma_on * rng.standard_normal())
            segs.append(f'[[segments]]\nid = "{sid}"\nkind = "static-field"\nfile = '
                        f'"{f}"\nsample_interval = "1 s"\n[segments.conditions]\norientation = '
                        f'"IRA up"\nfield_axis = "{ax}"\nfield = "{h} mT"\n')
    if repeats:
        for j in range(1, (7 if repeats is True else int(repeats)) + 1):
            f = record(f"repeat-{j}", 0.3 + sigma_on * rng.standard_normal())
            segs.append(f'[[segments]]\nid = "repeat-{j}"\nkind = "static-repeat"\nfile = "{f}"\n'
                        'sample_interval = "1 s"\n[segments.conditions]\norientation = "IRA '
                        f'up"\nrun = {j}\n')
    (folder / "manifest.toml").write_text(
        '[device]\nid = "BH-1"\noutput = "rate"\n\n[environment]\ntemperature = "20 °C"\nhumidity '
        f'= "40 %"\n\n[site]\nlatitude = "{lat}°"\n\n[[equipment]]\nid = "FG-1"\nrole = '
        '"field_generator"\nuniformity = "3 %"\n\n'
        + "\n".join(segs), encoding="utf-8")


def test_d55_field_records_carry_the_turn_on_scatter_of_d53(run_cli, tmp_path):
    """interpretations.md "D.5.5 — each field record a power-on": B_0+ and B_0− are taken "by
    D.5.1.2", each a power-on of its own, so B_h's budget carries √2·σ_on/(2H_b) with D.5.3's σ_on;
    without D.5.3 repeats the result says the turn-on scatter is not in U. (Independent harness,
    bt-bh-lsb-10Hz-flicker: B_h within U 88–95 % → 98–100 % of 100.)"""
    a, b = tmp_path / "a", tmp_path / "b"
    a.mkdir()
    b.mkdir()
    _field_campaign(a, np.random.default_rng(5), sigma_on=0.02, repeats=True)
    bh = _run(run_cli, a, "D.5.3,D.5.5")["Bh_IRA"]
    row = [x for x in bh["budget"]["rows"] if x["symbol"] == "√2·σ_on/(2H_b)"]
    assert len(row) == 1 and "D.5.3" in row[0]["source"]
    s_on = float(row[0]["source"].split("σ_on = ")[1].split(" ")[0])
    assert row[0]["contribution"] == pytest.approx(math.sqrt(2) * s_on / 2.0, rel=1e-3)
    assert 0.005 < s_on < 0.05  # the drawn σ_on = 0.02 °/h, from 7 repeats
    _field_campaign(b, np.random.default_rng(5), sigma_on=0.02, repeats=False)
    bh = _run(run_cli, b, "D.5.5")["Bh_IRA"]
    assert not [x for x in bh["budget"]["rows"] if x["symbol"] == "√2·σ_on/(2H_b)"]
    assert bh["reportable"] is False and "D.5.3" in bh["reason"] and "bias_repeatability" in bh[
        "reason"]


def test_terminal_keeps_bracketed_text_of_messages(run_cli, tmp_path):
    """The not-reportable reason names "[device] bias_repeatability": the terminal table prints it
    as text (rich read "[device]" as a markup tag and dropped it before)."""
    folder = tmp_path / "dev"
    folder.mkdir()
    _campaign(folder, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=False)
    code, out, err = run_cli("run", "-s", "gbt45570", "-i", "D.5.4", "--data",
                             str(folder / "manifest.toml"),
                             "--no-report", "--quiet", "--verbose")
    assert code == 0, err
    assert "[device]" in out and "not reportable" in out


def _noise_u(res: dict, noise_symbols: tuple[str, ...]) -> float:
    return math.sqrt(sum(r["standard_uncertainty"] ** 2 for r in res["budget"]["rows"]
                         if r["symbol"] in noise_symbols))


def _folded_expected(res: dict, noise_symbols: tuple[str, ...]) -> tuple[float, float]:
    """(printed |d|, the value expected after the folded-normal correction), recomputed by hand from
    the result's note and its noise rows with scipy's folded normal: δ̂ = √max(0, d² − u²), value =
    max(0, |d| − (E|N(δ̂, u²)| − δ̂)) (interpretations.md "D.5.5 / D.6.3 / D.6.4 — the absolute
    value of one noisy difference")."""
    from scipy.stats import foldnorm

    printed = float(res["note"].split("as printed by the formula ")[1].split(" ")[0])
    u = _noise_u(res, noise_symbols)
    m = math.sqrt(max(0.0, printed**2 - u**2))
    return printed, max(0.0, printed - (foldnorm.mean(m / u, scale=u) - m))


def test_d55_absolute_value_of_a_noisy_difference_is_corrected(run_cli, tmp_path):
    """D.44 takes |B_0+ − B_0−|: with no magnetic sensitivity (true B_h = 0) it reads high by ≈ 0.8
    of the difference's u (a folded normal; harness bt-bh-*: mean E_n +0.17 … +0.26). Six devices,
    three axes: each value is |d| less the folded-normal bias about √max(0, d² − u²), recomputed by
    hand from the note's printed value and the noise rows (4 significant digits in the note); the
    budget carries the correction (normal, u = √(u·bias + bias²/4)); mean E_n against the true 0
    falls by more than 0.1, to under 0.25 (measured: 0.17 → 0.02)."""
    noise = ("√(u²₊+u²₋)/(2H_b)", "√2·σ_on/(2H_b)", "√(u_q²₊+u_q²₋)/(2H_b)")
    en, en_printed = [], []
    for seed in range(6):
        folder = tmp_path / f"d{seed}"
        folder.mkdir()
        _field_campaign(folder, np.random.default_rng(100 + seed), sigma_on=0.004, repeats=True)
        res = _run(run_cli, folder, "D.5.3,D.5.5")
        for ax in ("IRA", "XRA", "YRA"):
            r = res[f"Bh_{ax}"]
            printed, expected = _folded_expected(r, noise)
            assert r["value"] >= 0.0
            assert r["value"] == pytest.approx(expected, abs=2e-3 * printed + 1e-12)
            row = [x for x in r["budget"]["rows"] if x["symbol"] == "δ_abs"]
            assert len(row) == 1 and row[0]["distribution"] == "normal"
            if r["value"] > 0:  # the row's u from the bias removed: √(u·bias + bias²/4)
                b = printed - r["value"]
                assert row[0]["standard_uncertainty"] == pytest.approx(math.sqrt(_noise_u(
                    r, noise) * b + b * b / 4),
                                                                       rel=5e-3)
            en.append(r["value"] / r["U"])
            en_printed.append(printed / r["U"])
    assert np.mean(en) <= 0.25 and np.mean(en_printed) - np.mean(en) > 0.1, (np.mean(en), np.mean(
        en_printed))


def test_a_bad_stated_repeatability_is_an_error_even_with_repeats(tmp_path):
    """[device] bias_repeatability = "abc" is refused (exit 2, the field named, the manifest
    untouched) even when the campaign's own D.5.3 repeats make it unused — before, it was silently
    ignored."""
    from metro.core.cli.app import main

    folder = tmp_path / "dev"
    folder.mkdir()
    _campaign(folder, np.random.default_rng(8), sigma_on=0.01, arw=0.002, slope=1e-4, repeats=True,
              stated="abc")
    before = (folder / "manifest.toml").read_bytes()
    code = main(["run", "-s", "gbt45570", "-i", "D.5.3,D.5.4", "--data",
                 str(folder / "manifest.toml"), "--no-report",
                 "--quiet"])
    assert code == 2 and (folder / "manifest.toml").read_bytes() == before


# -------------------------------------------------------------------------------------------- σ_K
# of D.1.5 / D.2.5: the posterior mean of the turn-on variance, never 0 where the runs only bound it
# (interpretations.md "σ_K — K's turn-on scatter, a variance component the runs only bound")
# --------------------------------------------------------------------------------------------

def _d25_station(pm, seed: int):
    from metro.core.run.runner import run_items

    # no turn-on scatter of K on the station: D.2.4's K_r is the runs' own noise, and at seed 2
    # below it
    return run_items(pm, "gbt45570", ["D.2.4", "D.2.5"], station="simulated",
                     station_options={"seed": seed, "device_class": "lsb-fine",
                                      "sf_turn_on_sigma": 0.0,
                                      "duration_scale": 0.25})


def test_d25_turn_on_scatter_of_k_is_never_zero_where_d24_only_bounds_it(pm):
    """D.2.4's seven runs scatter less than their own fits' noise (K_r² = 0.48·mean (u(K_j)/K_j)²):
    the moment estimate √max(K_r² − mean (u(K_j)/K_j)², 0) was 0 and D.2.5's points carried no
    turn-on part at all. Now σ_K² is the posterior mean of the variance component given the runs,
    worked here by hand for Q = 7 from the closed χ²(4) and χ²(6) cdfs (as σ_on of D.5.3), with ν =
    ∞."""
    from metro.plugins.gbt45570 import formulas_rate as F2
    from metro.plugins.gbt45570.common import group_of
    from metro.plugins.gbt45570.rate_data import collect_rate_data, fit_scale_factor
    from metro.plugins.gbt45570.rate_method import ScaleFactorRepeatabilityD24
    from metro.plugins.gbt45570.repeatability import scale_factor_turn_on

    rec = _d25_station(pm, 2)
    runs = sorted({group_of(s)[0] for s in rec.campaign.find_segments("rate-output")
                   if group_of(s)[0]
                   and not group_of(s)[1]}, key=lambda r: (len(r), r))
    assert len(runs) == 7
    fits = [fit_scale_factor(collect_rate_data(ScaleFactorRepeatabilityD24, rec.campaign, 11,
                                               (r, ""), "")) for r in runs]
    b2 = F2.scale_factor_repeatability_d28([f.K for f in fits]) ** 2
    w = sum((f.uK / f.K) ** 2 for f in fits) / 7
    # the precondition: the moment estimate is 0 here (no turn-on part before this change)
    assert b2 < 0.6 * w
    c = 6 * b2 / w
    F4 = 1 - math.exp(-c / 2) * (1 + c / 2)
    F6 = 1 - math.exp(-c / 2) * (1 + c / 2 + c * c / 8)
    s2 = 6 * b2 * F4 / (4 * F6) - w
    assert 0.5 * w < s2 < 1.1 * w  # between 2w/(ν − 2) (K_r → 0) and 1.08·w (K_r² = w)
    on = scale_factor_turn_on(rec.campaign, 11, "rate")
    assert on.sigma == pytest.approx(math.sqrt(s2),
                                     rel=1e-9) and on.nu == math.inf and on.known and on.dof == 6
    kt = rec.outcomes[1].results[0]
    assert rec.outcomes[1].item == "D.2.5" and kt.reportable
    note = kt.budget.rows[0].note
    assert "not resolved from the runs' own noise" in note, note
    scatter_ppm = float(note.split("turn-on scatter of K, ")[1].split(" ppm")[0])
    assert scatter_ppm == pytest.approx(math.sqrt(s2) * 1e6, rel=5e-3)


def test_d25_three_d24_power_ons_cannot_bound_the_turn_on_scatter_of_k(pm):
    """As σ_on of D.5.3 (MIN_BIAS_RUNS): the posterior mean of a variance from Q values needs Q ≥ 4,
    so D.2.5 with three D.2.4 runs is not reportable, saying why (before: σ_K from the 3 runs with ν
    ≥ 1); with [device] scale_factor_repeatability it is reportable, the stated value standing for
    σ_K."""
    import attrs

    from metro.core.run.runner import run_items

    rec = _d25_station(pm, 2)
    keep = {"1", "2", "3"}
    camp = attrs.evolve(rec.campaign, segments=[s for s in rec.campaign.segments if s.kind
                                                != "rate-output"
                                                or str(s.conditions.get("run", "")) in ("", *keep)
                                                or s.conditions.get("temperature")])
    kt = run_items(pm, "gbt45570", ["D.2.5"], campaign=camp).outcomes[0].results[0]
    assert not kt.reportable
    assert ("3 D.2.4 power-ons cannot bound it" in kt.reason
            and "scale_factor_repeatability" in kt.reason), kt.reason
    dev = attrs.evolve(camp.device, properties=dict(camp.device.properties)
                       | {"scale_factor_repeatability": "5e-6"})
    kt = (
        run_items(pm, "gbt45570", ["D.2.5"], campaign=attrs.evolve(camp, device=dev))
        .outcomes[0]
        .results[0]
    )
    assert kt.reportable, kt.reason
    assert "5 ppm stated for the device (device.scale_factor_repeatability)" in kt.budget.rows[
        0].note, kt.budget.rows[0].note


def test_turn_on_sigma_covers_a_difference_of_power_ons_where_the_runs_only_bound_it():
    """A small Monte Carlo of what D.1.5 / D.2.5 (and 6.2.8, D.5.4 with σ_on) do with a turn-on
    scatter: devices whose true σ_K is 0.5 … 1.5 times the runs' own u(K_j) (so 7 runs often scatter
    less than their noise), two power-ons measured with half that noise, their difference against U
    = 2·√(2σ̂_K² + 2u²). The moment estimate with its Satterthwaite ν (k = t(ν_eff), the rule
    before) covers it on 92.1 %, and on 70.7 % of the 819 devices where it came out 0; the posterior
    mean with ν = ∞ (repeatability.turn_on_sigma) on 98.3 % and 96.3 % (4 000 devices; 40 000 gave
    91.4 / 69.2 % and 97.9 / 95.5 %)."""
    from scipy.stats import t as student

    from metro.plugins.gbt45570.repeatability import turn_on_sigma

    rng = np.random.default_rng(45570)
    u, up, q = 1e-6, 0.5e-6, 7
    old = new = old0 = new0 = zero = 0
    n = 4000
    for _ in range(n):
        sig = rng.uniform(0.5, 1.5) * u
        Kj = 1.0 + sig * rng.standard_normal(q) + u * rng.standard_normal(q)
        d = sig * (rng.standard_normal()
                   - rng.standard_normal()) + up * (rng.standard_normal() - rng.standard_normal())
        s_new, s2, w, dof = turn_on_sigma(list(Kj), [u / k for k in Kj])
        m = max(s2 - w, 0.0)
        nu_on = max(dof * (m / s2) ** 2, 1.0)
        u2 = 2 * m + 2 * up * up
        k = student.ppf(0.97725, u2**2 / ((2 * m) ** 2 / nu_on)) if m > 0 else 2.0
        hit_old = abs(d) <= k * math.sqrt(u2)
        hit_new = abs(d) <= 2.0 * math.sqrt(2 * s_new**2 + 2 * up * up)
        old, new = old + hit_old, new + hit_new
        if m == 0:
            zero, old0, new0 = zero + 1, old0 + hit_old, new0 + hit_new
    assert zero > 0.15 * n  # the runs only bound σ_K on a fifth of these devices
    # the rule before: short, and shortest where the estimate is 0
    assert old / n < 0.93 and old0 / zero < 0.80
    assert new / n > 0.96 and new0 / zero > 0.93

"""An independent harness for JJF 2003—2022 (MIMU): devices metro's simulator does not make.

Run:  nice -n 10 .venv/bin/python benchmarks/independent_jjf2003.py [--devices 30]
      [--variants A,B] [--seed 1] [--json F] [--keep DIR] [--quick]
      .venv/bin/python benchmarks/independent_jjf2003.py --markdown F1.json [F2.json …]

The JJF 2003 companion of ``benchmarks/independent_campaigns.py`` (GB/T 45570, JJF 2014), whose
shared pieces it imports (``Campaign`` for the manifest's head, ``flicker``, ``score``,
``summarise``, ``Variant``).  The generators were written from the documentation only —
docs/data-format.md, docs/standards/jjf2003.md ("Data: segment layout"), ``metro plan -s jjf2003``'s
step list — and from JJF 2003—2022's clauses (eq. (1), (2), 7.2.1–7.2.5, table 1, 6.2); numpy alone
makes the samples, never ``metro.instruments`` or any of metro's simulators.

The device is eq. (1) and (2) with every matrix built here, and the samples come from the
kinematics of the table, not from the standard's design matrices:

* body angular rate ω_b = r′·u_j + C_LB(t)ᵀ·Ω_L (r′ the table rate with its set-point error, u_j the
  table axis as seen in the MIMU's reference frame — misaligned by the mounting and the table's
  axis perpendicularity — and the earth rate Ω_L = Ω_e(0, cos φ, sin φ) turned into the body
  sample by sample);
* specific force f_b = C_LB(t)ᵀ·(0, 0, g_loc/g_n) in g_n, with g_loc the *local* gravity
  (normal gravity at the latitude, the free-air gradient at the altitude and an anomaly);
* each mounting of the twelve positions tilted by two angles within ±``position_accuracy``
  (uniform), the MIMU seated in its fixture with a constant misalignment (≤ the fixture
  perpendicularity of 6.2, 10″) that is redrawn at each remount;
* ω′ = K_g·ω_b + B_g(t) + G·f_b + noise, a′ = K_a·f_b + B_a + p·ω_b² + noise (ω in rad/s),
  quantized to the LSB of an N-bit converter over ±FS (2·FS/2^N), in the column's own unit.

Truth (the standard's measurand of the constructed device; see docs/independent-campaigns.md, "JJF
2003: MIMU matrices"): K_g[i, j], G[i, j], K_a[i, j], p[i, j] as built (the device's matrices in its
own reference frame, per g_n of specific force); B_g the mean of the gyro bias over the twelve
position records (a slow thermal wander is bias); B_a as built. Where metro says a g term has the
earth rate ``included`` (eq. (7) as printed), its truth is G[i, j] + K_g[i, j]·Ω_e·sin φ·g_n/g, the
rate eq. (7) cannot separate from g-sensitivity (the whole column j, not the diagonal alone). No
truth depends on noise, so none needs Monte Carlo.
"""

from __future__ import annotations

import datetime
import importlib.util
import json
import math
import sys
import zlib
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

_HERE = Path(__file__).resolve().parent
if "independent_campaigns" in sys.modules:
    ic = sys.modules["independent_campaigns"]
else:
    _spec = importlib.util.spec_from_file_location("independent_campaigns", _HERE
                                                   / "independent_campaigns.py")
    ic = importlib.util.module_from_spec(_spec)
    sys.modules["independent_campaigns"] = ic  # its dataclasses look their module up
    _spec.loader.exec_module(ic)

Campaign, Variant, score, summarise = ic.Campaign, ic.Variant, ic.score, ic.summarise
build_with, text, variants = ic.build_with, ic.text, ic.variants

OMEGA_E_RAD_S = 7.2921150e-5            # IERS sidereal rate
OMEGA_E_DEG_S = math.degrees(OMEGA_E_RAD_S)
G_N = 9.80665                           # m/s², standard gravity (the manifest's gn)
AXES = "xyz"
POSITIONS = ("+x", "-x", "+y", "-y", "+z", "-z")     # 7.2.2.2's columns of Ā
ARCSEC = math.pi / 180 / 3600

# the units metro writes in --json for the JJF 2003 results, and their spellings
ic.UNIT_ALIASES.setdefault("°/s", {"°/s", "deg/s", "degree / second", "(°)/s", "degree/second"})
ic.UNIT_ALIASES.setdefault("gn", {"gn", "g", "g_n", "standard_gravity", "g₀"})
ic.UNIT_ALIASES.setdefault("(°/s)/gn", {"(°/s)/gn", "deg/s/gn",
                                        "degree / second / standard_gravity",
                                        "°/s/gn", "(°/s)/g", "°/s/g", "°/(s·gn)",
                                        "degree / standard_gravity / second"})
ic.UNIT_ALIASES.setdefault("gn/(rad/s)²", {"gn/(rad/s)²", "gn/(rad/s)**2", "gn s²/rad²",
                                           "gn·s²/rad²",
                                           "standard_gravity * second ** 2 / radian ** 2",
                                           "gn/(rad/s)^2", "g/(rad/s)²", "s²·g/rad²"})


# --------------------------------------------------------------------------------------------
# geometry (numpy only)
# --------------------------------------------------------------------------------------------

def rot(axis: int, angle: float) -> np.ndarray:
    """Right-handed rotation by ``angle`` (rad) about coordinate axis 0, 1, 2 (active)."""
    c, s = math.cos(angle), math.sin(angle)
    if axis == 0:
        return np.array([[1, 0, 0], [0, c, -s], [0, s, c]])
    if axis == 1:
        return np.array([[c, 0, s], [0, 1, 0], [-s, 0, c]])
    return np.array([[c, -s, 0], [s, c, 0], [0, 0, 1]])


def small_rotation(angles) -> np.ndarray:
    """Rotation by small angles about x, y, z in turn (rad)."""
    R = np.eye(3)
    for k, a in enumerate(angles):
        R = rot(k, a) @ R
    return R


def up_nominal(up: str) -> np.ndarray:
    """C_LB (body → local level ENU) that puts body axis ``up`` (±x, ±y, ±z) on the zenith."""
    return {"+z": np.eye(3), "-z": rot(0, math.pi), "+x": rot(1, -math.pi / 2),
            "-x": rot(1, math.pi / 2),
            "+y": rot(0, math.pi / 2), "-y": rot(0, -math.pi / 2)}[up]


def rodrigues_many(k: np.ndarray, theta: np.ndarray, v: np.ndarray) -> np.ndarray:
    """v turned by each angle θ about the unit axis k (n × 3)."""
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    return v * c + np.cross(k, v)[None, :] * s + (k * (k @ v))[None, :] * (1 - c)


def normal_gravity(lat_deg: float, altitude_m: float = 0.0) -> float:
    """GRS 80 normal gravity (Somigliana) at the latitude, free-air gradient −3.086×10⁻⁶ s⁻² per
    m."""
    s2 = math.sin(math.radians(lat_deg)) ** 2
    g0 = 9.7803267715 * (1 + 0.001931851353 * s2) / math.sqrt(1 - 0.0066943800229 * s2)
    return g0 - 3.086e-6 * altitude_m


# --------------------------------------------------------------------------------------------
# the device
# --------------------------------------------------------------------------------------------

@dataclass
class Mimu:
    Kg: np.ndarray
    Bg: np.ndarray            # °/s
    G: np.ndarray             # (°/s)/gn
    Ka: np.ndarray
    Ba: np.ndarray            # gn
    p: np.ndarray             # gn/(rad/s)², zero diagonal
    arw: np.ndarray           # °/s/√Hz per gyro (σ of a T-second mean = arw/√T)
    vrw: np.ndarray           # gn/√Hz per accelerometer
    wander: np.ndarray        # gyro bias thermal wander amplitude, °/s
    wander_period: float      # s
    wander_phase: np.ndarray
    fs_g: float               # gyro full scale, °/s
    fs_a: float               # accelerometer full scale, gn
    bits: int
    gyro_unit: str = "deg/s"  # the columns' unit (quantized in it)
    acc_unit: str = "gn"

    def bias_g(self, t: np.ndarray) -> np.ndarray:
        """B_g(t), n × 3 (°/s)."""
        return self.Bg[None, :] + self.wander[None, :] * np.sin(
            2 * math.pi * t[:, None] / self.wander_period + self.wander_phase[None, :])

    def outputs(self, t: np.ndarray, w_b_deg_s: np.ndarray, f_b_gn: np.ndarray, dt: float, rng):
        """Gyro (°/s) and accelerometer (gn) samples, quantized in the column units."""
        n = t.size
        w = w_b_deg_s @ self.Kg.T + self.bias_g(t) + f_b_gn @ self.G.T
        w = w + rng.standard_normal((n, 3)) * (self.arw / math.sqrt(dt))[None, :]
        a = f_b_gn @ self.Ka.T + self.Ba[None, :] + (np.radians(w_b_deg_s) ** 2) @ self.p.T
        a = a + rng.standard_normal((n, 3)) * (self.vrw / math.sqrt(dt))[None, :]
        gscale = 1.0 if self.gyro_unit == "deg/s" else math.pi / 180      # °/s → rad/s
        ascale = 1.0 if self.acc_unit == "gn" else G_N                   # gn → m/s²
        wq, aq = w * gscale, a * ascale
        if self.bits:
            qg = 2 * self.fs_g * gscale / 2 ** self.bits
            qa = 2 * self.fs_a * ascale / 2 ** self.bits
            wq = np.round(wq / qg) * qg
            aq = np.round(aq / qa) * qa
        return wq, aq


def draw_mimu(rng, *, xc_g: float, xc_a: float, g_sens: float, p_mag: float, arw: tuple, vrw: tuple,
              wander: float, bits: int, fs_g: float, fs_a: float, flip: float = 0.3,
              gyro_unit="deg/s", acc_unit="gn", ramp: bool = False) -> Mimu:
    """Matrices of eq. (1), (2): scale factors 0.9–1.1 (or 0.95–1.05), an axis read inverted with
    probability ``flip`` per axis, cross terms uniform within ±xc (non-orthogonal sensitive axes and
    electrical cross-coupling of either sign), g-sensitivity within ±g_sens, p within ±p_mag."""
    def mat(lo, hi, xc):
        M = rng.uniform(-xc, xc, (3, 3))
        d = rng.uniform(lo, hi, 3) * np.where(rng.uniform(size=3) < flip, -1.0, 1.0)
        M[np.diag_indices(3)] = d
        return M
    p = rng.uniform(-p_mag, p_mag, (3, 3))
    p[np.diag_indices(3)] = 0.0
    return Mimu(Kg=mat(0.9, 1.1, xc_g), Bg=rng.uniform(-0.5, 0.5, 3),
                G=rng.uniform(-g_sens, g_sens, (3, 3)),
                Ka=mat(0.95, 1.05, xc_a), Ba=rng.uniform(-0.03, 0.03, 3), p=p,
                arw=rng.uniform(*arw, 3), vrw=rng.uniform(*vrw, 3),
                wander=wander * rng.uniform(0.5, 1.5, 3) * (rng.choice([-1.0, 1.0], 3) if ramp
                                                            else 1.0),
                wander_period=float(rng.uniform(600, 3600)) if not ramp else 4 * 3600.0,
                # ramp: a warm-up drift — the sinusoid's steepest part (a quarter period is 1 h)
                wander_phase=rng.uniform(0, 2 * math.pi, 3) if not ramp else np.zeros(3), fs_g=fs_g,
                fs_a=fs_a, bits=bits,
                gyro_unit=gyro_unit, acc_unit=acc_unit)


# --------------------------------------------------------------------------------------------
# writing the campaign (data-format.md, docs/standards/jjf2003.md "Data: segment layout")
# --------------------------------------------------------------------------------------------

def write_six(path: Path, gyro: np.ndarray, acc: np.ndarray, dt: float, fmt: str, gunit: str,
              aunit: str,
              with_time: bool) -> str:
    """One segment's samples: gx, gy, gz, ax, ay, az with units in the header (CSV) or field names
    (.npy)."""
    gh = {"deg/s": "°/s", "rad/s": "rad/s"}[gunit]
    ah = {"gn": "gn", "m/s2": "m/s²"}[aunit]
    names = [f"g{a} [{gh}]" for a in AXES] + [f"a{a} [{ah}]" for a in AXES]
    data = np.hstack([gyro, acc])
    if fmt == "csv":
        name = path.parent / (path.name + ".csv")
        cols = (["time [s]"] if with_time else []) + names
        with open(name, "w", encoding="utf-8", newline="\n") as fh:
            fh.write("# written by benchmarks/independent_jjf2003.py\n")
            fh.write(",".join(cols) + "\n")
            t = dt * np.arange(1, data.shape[0] + 1)
            for k in range(data.shape[0]):
                row = ([repr(float(t[k]))] if with_time else []) + [repr(float(x)) for x in data[k]]
                fh.write(",".join(row) + "\n")
    else:
        name = path.parent / (path.name + ".npy")
        arr = np.zeros(data.shape[0], dtype=[(nm, "f8") for nm in names])
        for k, nm in enumerate(names):
            arr[nm] = data[:, k]
        np.save(name, arr)
    return name.name


@dataclass
class Lab:
    """What the lab's equipment is and does: the rate table's certificate (relative U, k = 2) and
    its positioning accuracy, the fixture's perpendicularity (6.2: 10″), and how well each is
    met."""
    table_U: float = 2e-4           # relative, k = 2 (appendix A.1.2.1)
    position_accuracy: float = 10.0  # ″ (table 1: ±10″)
    fixture: float = 10.0            # ″, 6.2 (the MIMU seated in it, per mounting)
    axis_perp: float = 10.0          # ″, table 1 轴线垂直度 (axis of a sweep against the MIMU axis)
    state_axis_perp: bool = False    # the table's axis_perpendicularity written in the manifest


#: the lab a campaign is built in when none is given
DEFAULT_LAB = Lab()


@dataclass
class MimuCampaign:
    folder: Path
    device: dict
    site: dict
    equipment: list
    # (id, kind, file, dt, conditions, started or None)
    segments: list = field(default_factory=list)

    def write_manifest(self) -> Path:
        # the head (device, environment, site, equipment) as the shared harness writes it, then
        # the six-column segments
        head = Campaign(self.folder, self.device, float(self.site["latitude"]), self.equipment)
        text = head.write_manifest().read_text(encoding="utf-8")
        extra = "".join(f'{k} = {json.dumps(v, ensure_ascii=False)}\n' for k, v in self.site.items()
                        if k != "latitude")
        text = text.replace(f'latitude = "{float(self.site["latitude"])!r}°"\n',
                            f'latitude = "{float(self.site["latitude"])!r}°"\n' + extra)
        lines = [text.rstrip("\n"), ""]
        for sid, kind, fname, dt, cond, started in self.segments:
            lines += ["[[segments]]", f'id = "{sid}"', f'kind = "{kind}"', f'file = "{fname}"',
                      f'sample_interval = "{dt!r} s"']
            if started is not None:   # data-format.md: the first sample's time, with its UTC offset
                lines.append(f"started = {started.isoformat()}")
            lines.append("[segments.conditions]")
            lines += [f"{k} = {json.dumps(v, ensure_ascii=False)}" for k, v in cond.items()]
            lines.append("")
        path = self.folder / "manifest.toml"
        path.write_text("\n".join(lines) + "\n", encoding="utf-8")
        return path


def build_mimu(folder: Path, rng, *, dt: float, seconds: float, fmt: str, bits: int, fs_g: float,
               fs_a: float, rates: tuple, xc_g: float, xc_a: float, g_sens: float, p_mag: float,
               arw: tuple, vrw: tuple, wander: float = 0.0, lab: Lab = DEFAULT_LAB,
               lat_range=(-70.0, 70.0), altitude: tuple = (0.0, 0.0), anomaly_mgal: float = 30.0,
               write_gravity: bool = False, gyro_unit="deg/s", acc_unit="gn",
               with_time: bool = True, quick: bool = False, flip: float = 0.3,
               items: str = "7.2.1,7.2.2,7.2.3,7.2.4,7.2.5", repeats: int = 0,
               sigma_K: float = 0.0, sigma_B: float = 0.0, ramp: bool = False,
               started: bool = False, shuffle: bool = False,
               either_hemisphere: bool = False) -> dict:
    """One MIMU written as a campaign of the 27 (3 axes × the rate set) rate segments and the twelve
    positions; returns the truth {(item, key): (value, unit, earth)} and ``options``. With
    ``either_hemisphere`` the latitude is drawn in ``lat_range`` or its mirror south, evenly."""
    if either_hemisphere and rng.uniform() >= 0.5:
        lat_range = (-lat_range[1], -lat_range[0])
    lat = float(rng.uniform(*lat_range))
    alt = float(rng.uniform(*altitude))
    g_loc = normal_gravity(lat, alt) + rng.uniform(-1, 1) * anomaly_mgal * 1e-5
    # specific force at rest, gn
    f_up = g_loc / G_N
    dev = draw_mimu(rng, xc_g=xc_g, xc_a=xc_a, g_sens=g_sens, p_mag=p_mag, arw=arw, vrw=vrw,
                    wander=wander,
                    bits=bits, fs_g=fs_g, fs_a=fs_a, flip=flip, gyro_unit=gyro_unit,
                    acc_unit=acc_unit, ramp=ramp)
    device = {"id": folder.name, "manufacturer": "independent", "technology": "mems",
              "output": "rate",
              "gyro_range": f"{fs_g!r} °/s", "accel_range": f"{fs_a!r} gn"}
    site = {"latitude": lat}
    if altitude != (0.0, 0.0):
        site["altitude"] = f"{alt:.1f} m"
    if write_gravity:   # a lab that knows its local g (a gravimeter's value, ±0.01 mGal)
        site["gravity"] = f"{g_loc:.6f} m/s²"
    table = {"id": "TBL-X", "role": "rate_table", "model": "three-axis position/rate table",
             "position_accuracy": f"{lab.position_accuracy!r}″",
             "calibration": {"certificate": "IND-TBL-1", "U": f"{lab.table_U!r}", "k": 2}}
    if lab.state_axis_perp:
        table = {k: v for k, v in table.items() if k != "calibration"} | {
            "axis_perpendicularity": f"{lab.axis_perp!r}″", "calibration": table["calibration"]}
    daq = {"id": "DAQ-X", "role": "acquisition", "bits": bits}
    fixture = {"id": "FIX-X", "role": "fixture", "perpendicularity": f"{lab.fixture!r}″"}
    camp = MimuCampaign(folder, device, site, [table, daq, fixture])
    n = int(round(seconds / dt)) if not quick else int(round(30.0 / dt))
    W_L = OMEGA_E_DEG_S * np.array([0.0, math.cos(math.radians(lat)), math.sin(math.radians(lat))])
    F_L = np.array([0.0, 0.0, f_up])
    # body → fixture, one mounting
    mount = small_rotation(rng.uniform(-1, 1, 3) * lab.fixture * ARCSEC)
    clock = [0.0]
    # the acquisition's clock: the campaign begins some morning in a UTC+8 lab (times to the ms)
    # (drawn only when written, so that the other variants' devices stay those of their seeds)
    t_begin = datetime.datetime(2026, 11, 24, 8, 0,
                                tzinfo=datetime.timezone(datetime.timedelta(hours=8))) + \
        datetime.timedelta(seconds=float(rng.uniform(0, 4 * 3600))) if started else None

    def tilt():
        a = rng.uniform(-1, 1, 2) * lab.position_accuracy * ARCSEC
        return rot(0, a[0]) @ rot(1, a[1])

    def record(sid, kind, C0, axis_L, rate, cond):
        """C_LB(t) = Rot(axis_L, θ(t))·C0; rate in °/s about axis_L (0 at rest)."""
        t = clock[0] + dt * (np.arange(n) + 0.5)
        clock[0] += n * dt + 20.0
        # a sweep starts wherever the table is; a position is held at its heading (θ = 0)
        theta = np.radians(rate) * (t - t[0]) + (rng.uniform(0, 2 * math.pi) if kind != "position"
                                                 else 0.0)
        W_b = rodrigues_many(axis_L, -theta, W_L) @ C0          # C0ᵀ·Rot(−θ)·v, row-vector form
        F_b = rodrigues_many(axis_L, -theta, F_L) @ C0          # (Rot(θ)·C0 is C_LB(t))
        w_b = W_b + rate * (C0.T @ axis_L)[None, :]
        g, a = dev.outputs(t, w_b, F_b, dt, rng)
        fname = write_six(folder / sid, g, a, dt, fmt, gyro_unit, acc_unit, with_time)
        when = (
            (t_begin + datetime.timedelta(milliseconds=round(1000 * (t[0] - 0.5 * dt))))
            if started
            else None
        )
        camp.segments.append((sid, kind, fname, dt, cond, when))
        return t

    # the twelve positions (7.2.2.1 a), appendix C): each mounting tilted within ±position_accuracy
    pos_times = []
    for up in POSITIONS:
        for h in (0.0, 180.0):
            C0 = tilt() @ rot(2, math.radians(h)) @ up_nominal(up) @ mount
            pos_times.append(record(f"pos{up}-h{h:g}", "position", C0, np.array([0.0, 0.0, 1.0]),
                                    0.0,
                                    {"up": up, "heading": f"{h:g}°"}))
    # the sweeps (7.2.1.1): axis j up along the table axis; the table axis (as the MIMU sees it)
    # errs by the axis perpendicularity and the mounting; each rate point errs within ±√3·U/k
    # (7.2.5 reads the rest and ω points of the same sweeps).  The table axis leans from the
    # vertical within ±position_accuracy (T); the MIMU axis lies off the table axis by the table's
    # positioning and axis perpendicularity and the fixture (perp, mount): at rest the leaning axis
    # puts a horizontal component of g on the other accelerometers that turning averages away.
    def sweeps(mount, prefix: str, kind: str, cond: dict) -> None:
        for a in AXES:
            T = tilt()
            perp = small_rotation(rng.uniform(-1, 1, 3) * lab.position_accuracy * ARCSEC) \
                @ small_rotation(rng.uniform(-1, 1, 3) * lab.axis_perp * ARCSEC)
            for r in rates:
                eps = rng.uniform(-1, 1) * math.sqrt(3) * lab.table_U / 2
                C0 = T @ up_nominal("+" + a) @ perp @ mount
                record(f"{prefix}{a}-{r:g}", kind, C0, T @ np.array([0.0, 0.0, 1.0]),
                       r * (1 + eps), {"axis": a, "rate": f"{r:g} °/s"} | cond)

    sweeps(mount, "rate-", "rate", {})
    # repeated calibrations (kind rate-repeat, condition run; docs/standards/jjf2003.md, option
    # repeats): power off, remount — a new seat in the fixture, another power-on's K_g diagonal
    # (relative σ_K) and B_g (σ_B).  The truth stays the first calibration's power-on.
    Kg0, Bg0 = dev.Kg.copy(), dev.Bg.copy()
    for run in range(1, repeats + 1):
        mount = small_rotation(rng.uniform(-1, 1, 3) * lab.fixture * ARCSEC)
        dev.Kg = Kg0.copy()
        dev.Kg[np.diag_indices(3)] *= 1 + sigma_K * rng.standard_normal(3)
        dev.Bg = Bg0 + sigma_B * rng.standard_normal(3)
        sweeps(mount, f"rate-repeat#{run}-", "rate-repeat", {"run": str(run)})
    dev.Kg, dev.Bg = Kg0, Bg0
    # the manifest lists the records in an order of its own, not the recording order (its
    if shuffle:
        # own generator: the devices stay those of their seeds)
        order = (
            np.random.default_rng(zlib.crc32(folder.name.encode())).permutation(len(camp.segments))
        )
        camp.segments = [camp.segments[k] for k in order]
    camp.write_manifest()

    # truth
    t_pos = np.concatenate(pos_times)
    Bg_truth = dev.bias_g(t_pos).mean(axis=0)
    sin_lat = math.sin(math.radians(lat))
    truth: dict = {}
    want = set(items.split(","))
    for i, r in enumerate(AXES):
        if "7.2.1" in want:
            truth[("7.2.1", f"K_g{r}{r}")] = (float(dev.Kg[i, i]), "", "")
        if "7.2.2" in want:
            truth[("7.2.2", f"B_g{r}")] = (float(Bg_truth[i]), "°/s", "")
        if "7.2.4" in want:
            truth[("7.2.4", f"B_a{r}")] = (float(dev.Ba[i]), "gn", "")
        for j, c in enumerate(AXES):
            if "7.2.3" in want:
                truth[("7.2.3", f"K_g{r}{c}")] = (float(dev.Kg[i, j]), "", "")
            if "7.2.2" in want:
                # per g_n of specific force
                leak = float(dev.Kg[i, j]) * OMEGA_E_DEG_S * sin_lat / f_up
                truth[("7.2.2", f"g_{r}{c}")] = (float(dev.G[i, j]), "(°/s)/gn", ("earth", leak))
            if "7.2.4" in want:
                truth[("7.2.4", f"K_a{r}{c}")] = (float(dev.Ka[i, j]), "", "")
            if "7.2.5" in want and i != j:
                truth[("7.2.5", f"p_{r}{c}")] = (float(dev.p[i, j]), "gn/(rad/s)²", "")
    return truth


# --------------------------------------------------------------------------------------------
# variants
# --------------------------------------------------------------------------------------------

ITEMS = "7.2.1,7.2.2,7.2.3,7.2.4,7.2.5"
DEFAULT_RATES = (-400, -200, -100, -50, 0, 50, 100, 200, 400)


@dataclass
class MimuVariant:
    name: str
    describe: str
    build: object                 # callable(folder, rng, quick) -> truth
    options: tuple = ()           # metro run -o NAME=VALUE
    items: str = ITEMS
    standard: str = "jjf2003"


VARIANTS = variants(
    MimuVariant("mimu-16bit-100Hz-skewed",
                text("""
                    16-bit over ±400 °/s / ±8 gn (finer than the noise), 100 Hz CSV, 30 s per
                    record, the plan's nine rates; non-orthogonal axes and cross-coupling
                    within ±5×10⁻³, an axis read inverted (30 %), g-sensitivity ±0.05 (°/s)/gn,
                    p ±5×10⁻⁴; table U 2×10⁻⁴ (k = 2), ±10″; latitude ±70°"""),
                build_with(build_mimu, dt=0.01, seconds=30.0, fmt="csv", bits=16, fs_g=400.0,
                           fs_a=8.0, rates=DEFAULT_RATES, xc_g=5e-3, xc_a=5e-3, g_sens=0.05,
                           p_mag=5e-4, arw=(0.005, 0.02), vrw=(5e-5, 2e-4))),
    MimuVariant("mimu-24bit-200Hz-goodtable-gravity",
                text("""
                    24-bit (fine) at 200 Hz in .npy, 60 s per record, a quiet MIMU (0.002–0.005
                    °/s/√Hz, 20–50 µg/√Hz); a table as table 1 asks (rate U 2×10⁻⁵, k = 2;
                    ±5″); the lab's measured local g in [site] gravity"""),
                build_with(build_mimu, dt=0.005, seconds=60.0, fmt="npy", bits=24, fs_g=400.0,
                           fs_a=8.0, rates=DEFAULT_RATES, xc_g=5e-3, xc_a=5e-3, g_sens=0.02,
                           p_mag=2e-4, arw=(0.002, 0.005), vrw=(2e-5, 5e-5),
                           lab=Lab(table_U=2e-5, position_accuracy=5.0, fixture=10.0,
                                   axis_perp=10.0), write_gravity=True)),
    MimuVariant("mimu-12bit-50Hz-coarse-rad-ms2",
                text("""
                    12-bit (appendix A's N) over ±300 °/s / ±4 gn: 1 LSB 0.15 °/s, 2 mg,
                    coarser than the noise (undithered); columns in rad/s and m/s², 50 Hz CSV
                    without a time column; 7 rates ±300, ±150, ±50, 0 (ω = 300 °/s for 7.2.5)"""),
                build_with(build_mimu, dt=0.02, seconds=40.0, fmt="csv", bits=12, fs_g=300.0,
                           fs_a=4.0, rates=(-300, -150, -50, 0, 50, 150, 300), xc_g=1e-2, xc_a=1e-2,
                           g_sens=0.05, p_mag=5e-4, arw=(0.002, 0.01), vrw=(5e-5, 2e-4),
                           gyro_unit="rad/s", acc_unit="m/s2", with_time=False),
                options=("omega=300 deg/s",)),
    MimuVariant("mimu-1kHz-wander-polar-altitude",
                text("""
                    1 kHz .npy, 16 bits over ±2000 °/s / ±16 gn, 11 rates up to ±2000 °/s (ω =
                    1000 °/s for 7.2.5), a gyro-bias thermal wander 0.01 °/s (period 10–60
                    min), large cross terms (±2×10⁻²), g-sensitivity ±0.1, p ±1×10⁻³; latitude
                    60–89° either hemisphere, altitude 0–3000 m, no [site] gravity"""),
                build_with(build_mimu, dt=0.001, seconds=30.0, fmt="npy", bits=16, fs_g=2000.0,
                           fs_a=16.0,
                           rates=(-2000, -1000, -500, -200, -100, 0, 100, 200, 500, 1000, 2000),
                           xc_g=2e-2, xc_a=2e-2, g_sens=0.1, p_mag=1e-3, arw=(0.01, 0.03),
                           vrw=(1e-4, 3e-4), wander=0.01, altitude=(0.0, 3000.0),
                           lat_range=(60.0, 89.0), either_hemisphere=True),
                options=("omega=1000 deg/s",)),
    MimuVariant("mimu-24bit-quiet-skewed-repeats",
                text("""
                    a quiet MIMU (0.0003–0.001 °/s/√Hz, 10–30 µg/√Hz), 24-bit at 50 Hz .npy, 60
                    s records, large cross terms (±2×10⁻², non-orthogonal axes) at latitude
                    ±(50–85)°; three repeated calibrations (rate-repeat, remounted in the
                    fixture, K_g diagonal σ 2×10⁻⁴ and B_g σ 0.01 °/s per power-on); table U
                    5×10⁻⁵, ±5″, fixture 5″, axis perpendicularity 5″ stated"""),
                build_with(build_mimu, dt=0.02, seconds=60.0, fmt="npy", bits=24, fs_g=500.0,
                           fs_a=10.0, rates=(-500, -250, -100, -20, 0, 20, 100, 250, 500),
                           xc_g=2e-2, xc_a=2e-2, g_sens=0.01, p_mag=2e-4, arw=(3e-4, 1e-3),
                           vrw=(1e-5, 3e-5),
                           lab=Lab(table_U=5e-5, position_accuracy=5.0, fixture=5.0, axis_perp=5.0,
                                   state_axis_perp=True),
                           lat_range=(50.0, 85.0), either_hemisphere=True, repeats=3, sigma_K=2e-4,
                           sigma_B=0.01),
                options=("omega=500 deg/s",)),
)


def _warmup(started: bool, shuffle: bool = False):
    return lambda f, rng, quick: build_mimu(
        f, rng, dt=0.01, seconds=30.0, fmt="npy", bits=24, fs_g=125.0, fs_a=8.0,
        rates=(-125, -60, -20, 0, 20, 60, 125), xc_g=5e-3, xc_a=5e-3, g_sens=0.02, p_mag=2e-4,
        # slope A·2π/4 h = 0.2 °/s/h at t = 0
        arw=(0.002, 0.005), vrw=(2e-5, 5e-5), wander=0.2 * 4 / (2 * math.pi),
        lab=Lab(table_U=2e-5, position_accuracy=5.0, fixture=10.0, axis_perp=10.0),
        write_gravity=True, ramp=True,
        started=started, shuffle=shuffle, quick=quick)


_WARMUP = ("a MIMU still warming up: each gyro bias ramps by 0.1–0.3 °/s per hour of either sign "
           "(the campaign's 33 min, recorded in the plan's order: positions, then each sweep from "
           "−125 to +125 °/s); 24 bits over ±125 °/s at 100 Hz .npy, 30 s records, 7 rates; table "
           "U 2×10⁻⁵, ±5″; g stated")
VARIANTS["mimu-24bit-warmup-ramp"] = MimuVariant(
    "mimu-24bit-warmup-ramp", _WARMUP + "; no recording times", _warmup(False),
    options=("omega=125 deg/s",))
VARIANTS["mimu-24bit-warmup-ramp-started"] = MimuVariant(
    "mimu-24bit-warmup-ramp-started", _WARMUP
    + "; each segment's `started` (the acquisition's clock, UTC+8)",
    _warmup(True), options=("omega=125 deg/s",))
VARIANTS["mimu-24bit-warmup-ramp-shuffled"] = MimuVariant(
    "mimu-24bit-warmup-ramp-shuffled", _WARMUP
    + "; no recording times, and the manifest lists the segments in a "
    "random order (recorded in the plan's)", _warmup(False, shuffle=True),
    options=("omega=125 deg/s",))


# --------------------------------------------------------------------------------------------
# running metro and scoring
# --------------------------------------------------------------------------------------------

def run_metro(manifest: Path, standard: str, items: str, options=()) -> tuple[int, dict, str]:
    """:func:`independent_campaigns.run_metro` in-process on metro's command line, with item
    ``options``."""
    from metro.core.cli.app import main

    return ic.run_metro(manifest, standard, items, options=options, main=main)


def run_variant(variant: MimuVariant, devices: int, seed0: int, workdir: Path, quick: bool = False,
                keep: bool = False) -> list[dict]:
    """:func:`independent_campaigns.run_variant` with the variant's item options on metro's command
    line."""
    return ic.run_variant(variant, devices, seed0, workdir, quick=quick, keep=keep,
                          metro=lambda m: run_metro(m, variant.standard, variant.items,
                                                    variant.options))


GROUPS = (("7.2.1", "K_g diagonal", lambda k: k[3] == k[4]),
          ("7.2.3", "K_g diagonal", lambda k: k[3] == k[4]),
          ("7.2.3", "K_g off-diagonal", lambda k: k[3] != k[4]),
          ("7.2.2", "B_g", lambda k: k.startswith("B_g")),
          ("7.2.2", "g diagonal", lambda k: k.startswith("g_") and k[2] == k[3]),
          ("7.2.2", "g off-diagonal", lambda k: k.startswith("g_") and k[2] != k[3]),
          ("7.2.4", "B_a", lambda k: k.startswith("B_a")),
          ("7.2.4", "K_a diagonal", lambda k: k.startswith("K_a") and k[3] == k[4]),
          ("7.2.4", "K_a off-diagonal", lambda k: k.startswith("K_a") and k[3] != k[4]),
          ("7.2.5", "p", lambda k: k.startswith("p_")))


def grouped(rows: list[dict]) -> list[dict]:
    """The rows pooled per variant and result group (the nine K_g terms of 7.2.3 are 3 + 6 …)."""
    out = []
    for v in dict.fromkeys(r["variant"] for r in rows):
        vr = [r for r in rows if r["variant"] == v]
        runs = [r for r in vr if "item" not in r]
        for item, name, pred in GROUPS:
            sel = [dict(r, key=name) for r in vr if r.get("item") == item and pred(r["key"])]
            if sel or runs:
                for s in summarise(sel + [dict(r, item=item, key=name) for r in runs]):
                    out.append(s)
    return out


def markdown(rows: list[dict]) -> str:
    out = ["| variant | item | results | values | not reportable | within U (or not reportable) | "
           "mean E_n | rms E_n | max abs E_n |", "|---|---|---|---|---|---|---|---|---|"]
    out += [ic.table_row(s, alt=False, other_chars=200) for s in grouped(rows)]
    return "\n".join(out)


def main(argv=None) -> int:
    return ic.cli(argv, VARIANTS, __doc__.split("\n\n")[0], prefix="indep-mimu-",
                  quick_help="30 s records (a smoke run)",
                  run=lambda v, a, work: run_variant(v, a.devices, a.seed, work, quick=a.quick,
                                                     keep=a.keep is not None),
                  summary=lambda rows, a: summarise(rows) if a.per_result else grouped(rows),
                  table=lambda rows, a: ic.markdown(rows) if a.per_result else markdown(rows),
                  add_arguments=lambda ap: ap.add_argument(
                      "--per-result", action="store_true",
                      help="print every result, not the groups"))

if __name__ == "__main__":
    sys.exit(main())

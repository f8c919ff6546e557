"""JJF 2014—2022 clause 7.2: what every item shares — option parsing, segment access, the 7.2.1
scale-factor set (eqs. (2)–(5)) and the K that items 7.2.9–7.2.23 divide by."""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from typing import Any

import attrs
import numpy as np
from metro.api import (INF, Q_, BudgetRow, Campaign, DataError, EquipmentRequirement, Option,
                       Outcome, PlotSpec, Procedure, ProcedureError, Segment, Step,
                       device_scale_factor, hint, join, msg, parse_quantity)

from . import budgets as B
from . import formulas as F

STANDARD = "jjf2014"
STATION = "simulated-jjf2014"
KU = "mV/(deg/s)"
AXES = ("X", "Y", "Z")

DEFAULT_RATES = "0.1, 0.25, 0.63, 1.6, 4, 10, 16, 25, 40, 63, 100"


def parse_floats(text: Any, what: str) -> list[float]:
    try:
        vals = [float(x) for x in str(text).replace(";", ",").split(",") if x.strip()]
    except ValueError as exc:
        raise ProcedureError(f"option {what}: {text!r} is not a comma-separated list of "
                             "numbers") from exc
    if not vals:
        raise ProcedureError(f"option {what} is empty")
    return vals


def parse_magnitudes(text: Any, what: str) -> list[float]:
    """A list option of rate magnitudes (°/s), each applied in both directions (7.2.1.1 b),
    7.2.9, 7.2.10): every value positive and finite."""
    vals = parse_floats(text, what)
    if not all(v > 0 and math.isfinite(v) for v in vals):
        raise ProcedureError(f"option {what}: every value must be a positive magnitude in °/s, got "
                             f"{text!r}")
    return vals


def quantity_text(v: float, unit: str) -> str:
    return f"{v:g} {unit}"


def num_option(options: Mapping[str, Any], name: str, lo: float, *, integer: bool = False) -> float:
    """A numeric option, checked: ≥ ``lo`` and (when ``integer``) whole."""
    raw = options[name]
    try:
        v = float(raw)
    except (TypeError, ValueError) as exc:
        raise ProcedureError(f"option {name}: {raw!r} is not a number") from exc
    if not math.isfinite(v) or v < lo or (integer and v != int(v)):
        raise ProcedureError(f"option {name}: {raw!r} must be "
                             f"{'a whole number ' if integer else ''}≥ {lo:g}")
    return int(v) if integer else v


def flag_option(options: Mapping[str, Any], name: str) -> bool:
    """An on/off option."""
    t = str(options[name]).strip().lower()
    if t in ("on", "true", "yes", "1"):
        return True
    if t in ("off", "false", "no", "0", ""):
        return False
    raise ProcedureError(f"option {name} must be on or off, got {options[name]!r}")


# ------------------------------------------------------------------------------- data access


def read_output(seg: Segment, column: str = "output", unit: str = "mV") -> tuple[np.ndarray, float]:
    """The segment's column as floats in ``unit`` (checked finite) and its interval in s."""
    s = seg.series(column, unit)
    x = np.asarray(s.data.to(unit).magnitude, dtype=float)
    ok = np.isfinite(x)
    if not ok.all():
        i = int(np.argmin(ok))
        raise DataError(seg.file or f"segment {seg.id}", column, f"sample {i + 1} is {x[i]!r}")
    if x.size < 2:
        raise DataError(seg.file or f"segment {seg.id}", column, f"only {x.size} sample(s)")
    return x, float(s.interval.to("s").magnitude)


def mean_and_u(seg: Segment) -> tuple[float, float, int]:
    """F̄ (eq. (2)), its standard uncertainty s/√N, and N."""
    x, _ = read_output(seg)
    return F.mean_output_eq2(x), float(np.std(x, ddof=1) / math.sqrt(x.size)), x.size


def output_step(campaign: Campaign, arrays: Iterable[np.ndarray]) -> tuple[float, str]:
    """The step q (mV) the analog output was digitised to, and where it comes from:
    ``device.output_resolution`` if the manifest states it, else read from the data — the
    smallest difference between two values of one record, when every value of every record is a
    whole number of it — else 0 (a continuous reading: no rounding row)."""
    v = campaign.device.properties.get("output_resolution")
    if v not in (None, ""):
        q = parse_quantity(v, dimension="mV", file=campaign.source,
                           field="device.output_resolution")
        x = float(q.to("mV").magnitude)
        if not (x >= 0 and math.isfinite(x)):
            raise DataError(campaign.source, "device.output_resolution",
                            f"must be a non-negative voltage step, got {v!r}")
        return x, msg("device.output_resolution = {v}", v=v)
    vals = [np.unique(np.asarray(a, dtype=float)[:200_000]) for a in arrays]
    steps = [float(np.min(np.diff(u))) for u in vals if u.size > 1]
    if not steps:
        return 0.0, msg("the data (no record with two distinct values)")
    q = min(steps)
    allv = np.concatenate(vals)
    if not q > 1e-9 * max(float(np.max(np.abs(allv))), 1e-300):
        return 0.0, msg("the data (no common step)")
    ratio = (allv - allv[0]) / q
    # every value within a thousandth of a step of the grid (a continuous reading's smallest
    # difference leaves the others at random fractions of it)
    if np.max(np.abs(ratio)) < 1e9 and np.all(np.abs(ratio - np.round(ratio)) < 1e-3):
        return q, msg("the data (every value a whole number of this step)")
    return 0.0, msg("the data (no common step)")


def rounding_note(q: float, s: float, hw: float, dithered: bool, source: str) -> str:
    """What a rounding row says: the step, the noise and whether it dithers the rounding."""
    if dithered:
        return msg("noise s = {s:.3g} mV ≥ q/2 (q = {q:.3g} mV, {source}) dithers the rounding: "
                   "offset of a mean ≤ Σ(q/πk)e^(−2π²k²σ²/q²) = {hw:.3g} mV", s=s, q=q,
                   source=source, hw=hw)
    return msg("noise s = {s:.3g} mV < q/2 (q = {q:.3g} mV, {source}): the rounding does not "
               "average out, ±q/2 on a mean", s=s, q=q, source=source)


def rounding_row_mean(campaign: Campaign, x: np.ndarray, what: str, scale: float, unit: str,
                      q: tuple[float, str] | None = None) -> list[BudgetRow]:
    """The rounding row of a result c·F̄ read from one record x of the digitised output
    (``scale`` = |c| in ``unit`` per mV); nothing when the output has no step."""
    qq, src = q if q is not None else output_step(campaign, [x])
    if qq <= 0:
        return []
    sd = float(np.std(x, ddof=1))
    hw, dith = F.rounding_half_width(qq, sd)
    return [BudgetRow.type_b(msg("output step {q:.3g} mV: rounding of {what}", q=qq, what=what),
                             "δF_q", Q_(hw * abs(scale), unit),
                             distribution="uniform", note=rounding_note(qq, sd, hw, dith, src))]


def condition_in(seg: Segment, name: str, unit: str) -> float:
    return float(seg.condition(name, unit).to(unit).magnitude)


def need_segments(campaign: Campaign, proc: type[Procedure], kind: str,
                  **conditions) -> list[Segment]:
    segs = campaign.find_segments(kind, **conditions)
    if not segs:
        extra = ", ".join(f"{k} = {v!r}" for k, v in conditions.items())
        raise DataError(campaign.source, "segments",
                        f"{proc.qualified_id()} needs segments of kind "
                        f"{kind!r}{' with ' + extra if extra else ''}; none found",
                        hint=f"`metro plan --standard jjf2014 --item {proc.item}` lists what to "
                             "measure")
    return segs


def calibration_of(campaign: Campaign, role: str):
    e = campaign.equipment_for(role)
    return None if e is None else e.calibration


def group_by(segs: Iterable[Segment], name: str) -> dict[str, list[Segment]]:
    out: dict[str, list[Segment]] = {}
    for s in segs:
        out.setdefault(str(s.condition(name)), []).append(s)
    return out


def axis_of(seg: Segment) -> str:
    a = str(seg.condition("axis")).strip().upper()
    if a not in AXES:
        raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.axis",
                        f"must be X, Y or Z, got {a!r}")
    return a


def phase_of(seg: Segment) -> str:
    p = str(seg.condition("phase")).strip().lower()
    if p not in ("before", "after"):
        raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.phase",
                        f"must be \"before\" or \"after\", got {p!r}")
    return p


def before_after_change(values: Mapping[tuple[str, str], float], item: str,
                        source: str | None) -> tuple[dict[str, float], dict[str, float], float,
                                                     str, dict[str, float]]:
    """The values before and after the test by axis (``values`` keyed by (axis, phase)) and the
    largest change over the axes, eqs. (12)/(13) (7.2.7, 7.2.8; 7.2.18, 7.2.19 by eqs. (32)/(33)
    alike): (before, after, printed, worst axis, change per axis); an axis without both phases is
    a DataError naming ``item``."""
    before = {a: values[(a, "before")] for a in AXES if (a, "before") in values}
    after = {a: values[(a, "after")] for a in AXES if (a, "after") in values}
    try:
        printed, worst, per = F.max_change_eq12_13(before, after)
    except ValueError as exc:
        raise DataError(source, "segments", f"{item}: {exc}") from exc
    return before, after, printed, worst, per


def up_or_down(seg: Segment) -> str:
    o = str(seg.condition("orientation")).lower()
    if "up" in o:
        return "up"
    if "down" in o:
        return "down"
    raise DataError(seg.file or seg.id, f"segments.{seg.id}.conditions.orientation",
                    f"must say up or down, got {o!r}")


# ------------------------------------------------------------------------------- scale factor sets


class SFSet:
    """One 7.2.1 calibration: the mean output at each input rate and the eq. (4)/(5) fit."""

    def __init__(self, segs: list[Segment]):
        if len(segs) < 3:
            raise DataError(segs[0].file if segs else None, "segments",
                            "a scale-factor calibration needs at least 3 input rates, got "
                            f"{len(segs)}")
        rows = []
        for s in segs:
            om = condition_in(s, "rate", "deg/s")
            x, _ = read_output(s)
            rows.append((om, F.mean_output_eq2(x), float(np.std(x, ddof=1) / math.sqrt(x.size)),
                         x.size, s.id,
                         float(np.std(x, ddof=1)), np.unique(x[:200_000])))
        rows.sort(key=lambda r: r[0])
        self.sd = np.array([r[5] for r in rows])
        self._values = [r[6] for r in rows]
        self.omega = np.array([r[0] for r in rows])
        if np.unique(self.omega).size != self.omega.size:
            raise DataError(segs[0].file, "segments",
                            "two segments of one calibration have the same input rate")
        self.F = np.array([r[1] for r in rows])
        self.uF = np.array([r[2] for r in rows])
        self.n = [r[3] for r in rows]
        self.ids = [r[4] for r in rows]
        try:
            self.fit = F.scale_factor_eq4_5(self.omega, self.F)
        except ValueError as exc:
            raise ProcedureError(f"7.2.1 fit: {exc}") from exc

    @property
    def K(self) -> float:
        return self.fit.K

    def rounding_rows(self, campaign: Campaign) -> tuple[list[BudgetRow], list[BudgetRow]]:
        """The rounding rows of K and of F₀ (interpretations.md, "JJF 2014 — output quantization"):
        each F̄_i is off by up to its half-width (Widrow bound when the noise dithers the rounding,
        else ±q/2), independently between input rates; K = Σc_iF̄_i and F₀ = Σd_iF̄_i (eqs. (4),
        (5), c_i = (Ω_i − Ω̄)/Σ(Ω − Ω̄)², d_i = 1/n − Ω̄c_i), so the half-width of each is
        √Σ(c_i·a_i)² (a uniform row with that standard uncertainty).  Nothing when the output has
        no step."""
        q, src = output_step(campaign, self._values)
        if q <= 0:
            return [], []
        hw = np.array([F.rounding_half_width(q, sd)[0] for sd in self.sd])
        dith = [F.rounding_half_width(q, sd)[1] for sd in self.sd]
        w = self.omega - self.omega.mean()
        c = w / float(np.sum(w * w))
        d = 1.0 / self.omega.size - self.omega.mean() * c
        n_und = len(dith) - sum(dith)
        note = msg("q = {q:.3g} mV ({src}); {n} of {total} means not dithered by their noise "
                   "(±q/2), the others within the Widrow bound; noise s = {lo:.3g} … {hi:.3g} mV",
                   q=q, src=src, n=n_und, total=len(dith),
                   lo=self.sd.min(), hi=self.sd.max())
        kr = BudgetRow.type_b(msg("output step {q:.3g} mV: rounding of the F̄_i through eq. (4)",
                                  q=q), "u_q",
                              Q_(float(np.sqrt(np.sum((c * hw) ** 2))), KU), distribution="uniform",
                              note=note)
        fr = BudgetRow.type_b(msg("output step {q:.3g} mV: rounding of the F̄_i through eq. (5)",
                                  q=q), "u_q",
                              Q_(float(np.sqrt(np.sum((d * hw) ** 2))), "mV"),
                              distribution="uniform", note=note)
        return [kr], [fr]

    def budget(self, campaign: Campaign, warnings: list[str] | None = None,
               rep: "Spread | None | bool" = True):
        """Appendix B.1 budget of this K.  u₃ (B.1.2.2 3)) is the *repeatability* of K, as the
        appendix's 1.54×10⁻⁴ is: K_r·|K| from the campaign's own repeated calibrations (7.2.4,
        kind ``rate-repeat``), else ``device.scale_factor_repeatability``; never less than the
        eq. (3) fit's standard error, which alone is the fallback (with a warning) when neither
        exists (interpretations.md, "7.2.1 — u₃ is a repeatability")."""
        if rep is True:
            rep = sf_repeatability(campaign)
        u, dof, src, typ = self.u_single(rep)
        if rep is None and warnings is not None:
            warnings.append(msg("no repeated calibrations (7.2.4) and no stated repeatability of "
                                "K: u₃ of K is the eq. (3) fit's standard error, which leaves out "
                                "the variation of K between power-ons{hint}",
                                hint=hint(" (rate-repeat runs or "
                                          "device.scale_factor_repeatability)")))
        src = join(" ", [src, "(B.1.2.2 3))"])
        row = (BudgetRow.type_a(src, "u₃", Q_(u, KU), dof) if typ == "A" else
               BudgetRow.type_b(src, "u₃", Q_(u, KU), distribution="normal", k=1.0))
        return B.scale_factor_budget(Q_(self.K, KU), None, 0,
                                     rate_table=calibration_of(campaign, "rate_table"),
                                     dmm=calibration_of(campaign, "dmm"), warnings=warnings,
                                     rep_row=row,
                                     extra=self.rounding_rows(campaign)[0])

    def u_single(self, rep: "Spread | None") -> tuple[float, float, str, str]:
        """Standard uncertainty of this one calibration's K as an estimate of the device's K:
        (u in mV/((°)/s), ν, what it is, type "A"/"B").  The larger of the repeatability
        K_r·|K| (which already holds the within-run scatter) and the fit's standard error."""
        fit_u = self.fit.u_K
        if rep is not None and rep.value * abs(self.K) >= fit_u:
            return rep.value * abs(self.K), rep.dof, msg("repeatability of K: K_r·K, {source}",
                                                         source=rep.source), rep.type
        if rep is not None:
            return fit_u, self.fit.dof, msg("residual scatter of the eq. (3) fit (larger than the "
                                            "repeatability K_r·K, {source})",
                                            source=rep.source), "A"
        return fit_u, self.fit.dof, msg("residual scatter of the eq. (3) fit (no repeatability of "
                                        "K available)"), "A"


@attrs.frozen
class Spread:
    """The 1σ spread of one determination of a quantity, as the standard's own repeatability
    or reproducibility item measures it (K_r of 7.2.4, B_r of 7.2.15, γ_mr of 7.2.12) on this
    campaign (type A, ν = Q − 1), or as the device's manifest states it (type B, ν = ∞).
    ``value`` is relative for K and in the quantity's unit otherwise."""

    value: float
    dof: float
    source: str
    type: str = "A"

    def row(self, source: str, symbol: str, u: float, unit: str,
            sensitivity: float = 1.0) -> BudgetRow:
        """A budget row of standard uncertainty ``u`` (in ``unit``) that comes from this spread."""
        if self.type == "A":
            return BudgetRow.type_a(join(", ", [source, self.source]), symbol, Q_(u, unit),
                                    self.dof,
                                    sensitivity=Q_(sensitivity, ""))
        return BudgetRow.type_b(join(", ", [source, self.source]), symbol, Q_(u, unit),
                                distribution="normal", k=1.0,
                                sensitivity=Q_(sensitivity, ""))


def stated_spread(campaign: Campaign, key: str, unit: str, what: str) -> Spread | None:
    v = campaign.device.properties.get(key)
    if v in (None, ""):
        return None
    q = parse_quantity(v, dimension=unit, file=campaign.source, field=f"device.{key}")
    x = float(q.to(unit).magnitude)
    if not (x >= 0 and math.isfinite(x)):
        raise DataError(campaign.source, f"device.{key}",
                        f"must be a non-negative {what}, got {v!r}")
    return Spread(x, INF, msg("stated for the device{hint}", hint=hint(f" (device.{key})")), "B")


def sf_repeatability(campaign: Campaign) -> Spread | None:
    """K_r (relative, 1σ of one calibration's K, eq. (10)) from the campaign's 7.2.4 runs
    (kind ``rate-repeat``, ≥ 2 runs), else ``device.scale_factor_repeatability``, else None."""
    runs = group_by(campaign.find_segments("rate-repeat"), "run")
    # checked even if unused
    stated = stated_spread(campaign, "scale_factor_repeatability", "",
                           "relative repeatability of K")
    if len(runs) >= 2:
        Ks = [SFSet(g).K for _, g in sorted(runs.items())]
        return Spread(F.relative_repeatability_eq10(Ks), len(Ks) - 1,
                      msg("K_r = {Kr:.3g} from this campaign's {n} calibrations (7.2.4)",
                          Kr=F.relative_repeatability_eq10(Ks), n=len(Ks)))
    return stated


def bias_repeatability(campaign: Campaign, K: float) -> Spread | None:
    """B_r (°/h, 1σ of one bias, eq. (30)) from the campaign's 7.2.15 runs (kind
    ``static-repeat``, ≥ 2 runs of one record each), else ``device.bias_repeatability``."""
    runs = group_by(campaign.find_segments("static-repeat"), "run")
    # checked even if unused
    stated = stated_spread(campaign, "bias_repeatability", "deg/h", "bias repeatability in °/h")
    if len(runs) >= 2 and all(len(g) == 1 for g in runs.values()):
        b0 = [F.bias_eq27_28(read_output(g[0])[0], K) * 3600.0 for _, g in sorted(runs.items())]
        br = F.std_bessel(b0, "eq. (30)")
        return Spread(br, len(b0) - 1, msg("B_r = {Br:.3g} °/h from this campaign's {n} runs "
                                           "(7.2.15)", Br=br, n=len(b0)))
    return stated


def with_scatter(rep: Spread | None, s: float, dof: float, what: str) -> Spread | None:
    """The repeatability of one calibration (``rep``: K_r of 7.2.4, B_r of 7.2.15, or stated) where
    the item's own calibrations show more: ``s`` is their observed 1σ scatter (the same unit as
    ``rep.value``: relative for K) with ``dof`` degrees of freedom — the K or biases before a
    shock or vibration over the axes (one device, separate power-ons), the temperature points'
    scatter about a straight line.  When s exceeds the repeatability, the two are pooled,
    √((ν_r·K_r² + ν·s²)/(ν_r + ν)) with ν_r + ν degrees of freedom (a stated repeatability: s
    alone); never smaller than the repeatability item's own spread (interpretations.md,
    "JJF 2014 — the largest of noisy slopes and changes")."""
    if not (dof >= 1 and math.isfinite(s) and s > 0):
        return rep
    if rep is None or rep.type != "A" or not math.isfinite(rep.dof):
        if rep is not None and s <= rep.value:
            return rep
        return Spread(s, float(dof),
                      msg("scatter {s:.3g} of {what} (ν = {nu:g})", s=s, what=what, nu=dof))
    if s <= rep.value:
        return rep
    v = math.sqrt((rep.dof * rep.value ** 2 + dof * s * s) / (rep.dof + dof))
    return Spread(v, rep.dof + dof, msg("{src}, pooled with the larger scatter {s:.3g} of {what} "
                                        "(ν = {nu:g}): {v:.3g}",
                                        src=rep.source, s=s, what=what, nu=dof, v=v))


def main_set(campaign: Campaign, proc) -> SFSet:
    return SFSet(need_segments(campaign, proc, "rate"))


@attrs.frozen
class KValue:
    """K (mV/[(°)/s]) for the items that divide by it, its relative standard uncertainty and
    ν_eff, and where it came from."""

    K: float
    u_rel: float
    source: str
    dof: float = INF
    #: K_r (7.2.4 of this campaign, or stated): how far another power-on's K lies from this one
    kr: "Spread | None" = None
    #: whether u_rel already holds that K_r (as u₃ of the 7.2.1 budget): one estimate, one ν
    kr_in_u: bool = False

    def __iter__(self):  # K, u_rel, source = scale_factor_for(...)
        return iter((self.K, self.u_rel, self.source))

    def power_on_u(self, value: float) -> float:
        """u (the unit of ``value``) of ``value`` = F̄/K for a record made at another power-on than
        the 7.2.1 calibration: its own K differs from the calibrated one by K_r, so |value|·K_r (0
        without K_r)."""
        return abs(value) * self.kr.value if self.kr is not None else 0.0

    def power_on_rows(self, value: float, scale: float, unit: str, what: str) -> list[BudgetRow]:
        """The row of :meth:`power_on_u`, times ``scale`` (a result's sensitivity to this record's
        B₀): the record is its own power-on, whose K differs from the 7.2.1 calibration's by the
        power-on repeatability K_r (7.2.4).  When u_rel(K) already holds K_r (u₃ of the 7.2.1
        budget) the row shares that one estimate: ν_r/3 makes Welch–Satterthwaite count it once
        ((2c²)²/ν_r = c⁴/ν_r + c⁴/(ν_r/3)).  Without K_r, nothing (the caller notes it)
        (interpretations.md, "7.2.13 — the static record is another power-on")."""
        if self.kr is None:
            return []
        dof = self.kr.dof / 3.0 if (self.kr_in_u and self.kr.type == "A"
                                    and math.isfinite(self.kr.dof)) else self.kr.dof
        src = join(", ",
                   [msg("{what}: its power-on's K differs from the calibration's by K_r",
                        what=what), self.kr.source])
        if self.kr.type == "A":
            return [BudgetRow.type_a(src, "K_r·B·c",
                                     Q_(self.kr.value * abs(value) * abs(scale), unit), dof,
                                     note=msg("one estimate with u(K)'s K_r: ν = {nu:g} of {nr:g}",
                                              nu=dof, nr=self.kr.dof)
                                     if self.kr_in_u else "")]
        return [BudgetRow.type_b(src, "K_r·B·c", Q_(self.kr.value * abs(value) * abs(scale), unit),
                                 distribution="normal", k=1.0)]

    def row(self, sensitivity: float, unit: str, source: str = "scale factor K",
            symbol: str = "u_rel(K)") -> BudgetRow:
        """The row of a result y ∝ 1/K (or ∝ K): relative u(K) times |y|, with K's ν_eff."""
        return BudgetRow.type_b(source, symbol, Q_(self.u_rel, ""), distribution="normal", k=1.0,
                                sensitivity=Q_(abs(sensitivity), unit), dof=self.dof,
                                note=msg("K from {source}", source=self.source))


def scale_factor_for(campaign: Campaign, proc) -> KValue:
    """K (mV/[(°)/s]) and its relative standard uncertainty for items that divide by K: from
    the campaign's 7.2.1 segments (kind "rate") if any — with the 7.2.1 budget, whose u₃ is the
    repeatability of K — else from ``device.scale_factor``."""
    kr = sf_repeatability(campaign)
    if campaign.find_segments("rate"):
        s = SFSet(campaign.find_segments("rate"))
        b = s.budget(campaign, rep=kr)
        return KValue(s.K, float(b.combined.to(KU).magnitude) / abs(s.K),
                      "7.2.1 segments of this campaign",
                      b.nu_eff, kr, kr is not None and kr.value * abs(s.K) >= s.fit.u_K)
    K, urel = device_scale_factor(campaign.device, campaign.source)
    if K is None:
        raise DataError(campaign.source, "device.scale_factor",
                        f"{proc.qualified_id()} needs the scale factor K: give 7.2.1 segments "
                        "(kind \"rate\") or device.scale_factor in mV/((°)/s)")
    return KValue(float(parse_quantity(K, dimension=KU).to(KU).magnitude), urel,
                  "device.scale_factor", INF, kr)


def rate_steps(kind: str, rates: list[float], extra: Mapping[str, Any] | None = None, tag: str = "",
                seconds: float = 10.0) -> list[Step]:
    steps = []
    for r in rates:
        for sgn in (1, -1):
            c = {"rate": quantity_text(sgn * r, "deg/s")} | dict(extra or {})
            sid = f"{kind}{tag}{'+' if sgn > 0 else '-'}{r:g}"
            steps.append(Step(sid, kind, f"table at {sgn * r:+g} °/s, record {seconds:g} samples "
                                         "at 1 s (7.2.1.1)",
                              Q_(seconds, "s"), Q_(1, "s"), c))
    return steps


RATE_OPTS = (Option("rates", DEFAULT_RATES, None,
                    "input rate magnitudes (°/s), both directions (7.2.1.1 b))"),)


def budget_row_a(source, symbol, u, unit, dof, note=""):
    return BudgetRow.type_a(source, symbol, Q_(u, unit), dof, note=note)


class JJFItem(Procedure):
    standard = STANDARD
    station = STATION
    equipment = (
        EquipmentRequirement("rate_table",
                             "rate table (table 2 no. 1); relative calibration U enters the "
                             "budgets"),
        EquipmentRequirement("dmm", "data acquisition, 6½-digit DMM; relative calibration U enters "
                                    "the budgets"),
    )

    def _outcome(self, results, *, plots=(), tables=(), warnings=(), segments=(),
                 opts=None) -> Outcome:
        # a result that does not state the earth rate is one it cancels from (slopes, differences at
        # one orientation, spreads, dynamics): "not applicable" (interpretations.md, "Earth rate
        # disclosed")
        results = [r if r.earth_rate else attrs.evolve(r, earth_rate="not applicable")
                   for r in results]
        return Outcome(STANDARD, self.item, self.title, self.clause, results, plots=list(plots),
                       tables=list(tables), warnings=list(warnings), segments=list(segments),
                       options={k: str(v) for k, v in (opts or {}).items()})


def sf_plots(s: SFSet) -> list[PlotSpec]:
    """7.2.1 figures: the mean outputs with the eq. (6) line, and the eq. (3) residuals v_i on
    their own axis (at the outputs' scale a residual of µV would be invisible)."""
    fit = s.fit
    return [PlotSpec("sf_fit", msg("Scale factor: mean outputs F̄_i (eq. (2)) and the fitted line "
                                   "F̂ = KΩ + F₀ (eq. (6))"),
                     msg("input rate Ω (°/s)"), msg("output (mV)"),
                     [{"label": "F̄_i (eq. (2))", "x": s.omega.tolist(), "y": s.F.tolist(),
                       "style": "o"},
                      {"label": f"F̂ = KΩ + F₀, K = {fit.K:.6g} mV/((°)/s), F₀ = {fit.F0:.4g} mV",
                       "x": s.omega.tolist(), "y": fit.predict(s.omega).tolist(), "style": "-"}]),
            PlotSpec("sf_residuals", msg("Scale factor: residuals v_i = F̄_i − (KΩ_i + F₀) of the "
                                         "eq. (3) fit"),
                     msg("input rate Ω (°/s)"), msg("residual v_i (mV)"),
                     [{"label": "v_i", "x": s.omega.tolist(), "y": fit.residuals.tolist(),
                       "style": "o",
                       "yerr": s.uF.tolist()},
                      {"label": "0", "x": [float(s.omega.min()), float(s.omega.max())],
                       "y": [0.0, 0.0],
                       "style": ":"}])]



def check_distinct(campaign: Campaign, values: np.ndarray, what: str) -> None:
    """Levels applied in decreasing order must differ (two records of one level: which one?)."""
    mags = np.abs(values)
    if np.unique(mags).size != mags.size:
        dup = sorted({float(v) for v in mags if np.sum(mags == v) > 1})
        raise DataError(campaign.source, "segments",
                        f"{what}: the level(s) {', '.join(f'{v:g}' for v in dup)} °/s appear more "
                        "than once; give one record per level")


def chamber_temperatures(groups: Mapping[str, list[Segment]], what: str) -> dict[str, float]:
    """The chamber temperature (°C) of each group, parsed from its first segment's condition;
    two groups at the same temperature (e.g. "20 °C" and "20 degC") are an error."""
    T = {k: condition_in(g[0], "temperature", "degC") for k, g in groups.items()}
    seen: dict[float, str] = {}
    for k, t in T.items():
        if t in seen:
            raise DataError(where_of(groups[k][0]),
                            f"segments.{groups[k][0].id}.conditions.temperature",
                            f"{what}: {k!r} and {seen[t]!r} are the same temperature; one "
                            "calibration per point")
        seen[t] = k
    return T


def where_of(seg: Segment) -> str:
    return seg.file or seg.id


def room_index(temps: list[float], Tm: float, what: str) -> int:
    i = int(np.argmin([abs(t - Tm) for t in temps]))
    if abs(temps[i] - Tm) > 2.0:
        raise DataError(None, "segments.conditions.temperature",
                        f"{what} needs a point at room temperature T_m = {Tm:g} °C (within 2 °C); "
                        f"temperatures given: {', '.join(f'{t:g}' for t in temps)}")
    return i


def chamber_rows(campaign, sens: float, unit: str) -> list[BudgetRow]:
    cal = calibration_of(campaign, "chamber")
    if cal is None or cal.uncertainty.dimensionless:
        return []
    return [BudgetRow.from_calibration("chamber temperature T_i (table 2 no. 2)", "u(T_i)", cal,
                                       sensitivity=Q_(abs(sens), f"{unit}/delta_degC"))]


def one_estimate(rows: Iterable[BudgetRow], spread: Spread | None) -> list[BudgetRow]:
    """Rows drawn from one repeatability estimate (K_r or B_r of the same runs: the two members of a
    difference or of a ratio) share its degrees of freedom: ν is apportioned among them,
    ν_i = ν·u_i²/Σu_j², so that Welch–Satterthwaite counts the estimate once (Σu_i⁴/ν_i =
    (Σu_i²)²/ν). Two rows of ν = 5 each gave ν_eff ≈ 10 and k ≈ 2.28 where t(5) = 2.65 is due
    (interpretations.md, "JJF 2014 — one estimate, one ν")."""
    out = list(rows)
    if spread is None or not math.isfinite(spread.dof):
        return out
    tag = str(spread.source)
    idx = [i for i,
           r in enumerate(out) if r.type == "A" and r.dof == spread.dof
           and str(r.source).endswith(tag)]
    if len(idx) < 2:
        return out
    c2 = [float(out[i].contribution.magnitude) ** 2 for i in idx]
    total = sum(c2)
    for i, c in zip(idx, c2):
        out[i] = attrs.evolve(out[i], dof=spread.dof * c / total if total > 0 else spread.dof,
                              note=join("; ", [out[i].note, msg("one estimate shared with {n} "
                                                                "rows: ν = {nu:g} apportioned",
                                                                n=len(idx), nu=spread.dof)]))
    return out

"""GB/T 45570—2025 typical product limits as data: tables A.1 (laser), B.1 (fibre), C.1
(environment).

Appendices A, B and C are informative (资料性): they give *typical* indices of laser and fibre
gyros by application — 航天 aerospace, 航空 aviation, 船舶 marine.  metro judges results
against them when the campaign gives no product specification of its own; a manifest's
``[specification]`` table replaces them metric by metric (see docs/standards/gbt45570.md).

Each row of A.1/B.1 names the metric key (``Metric.key``) the plugin's procedures produce
for that quantity and the appendix-D items that produce it (angle method D.1, rate method
D.2, …).  Rows of C.1 are test *severities* (the conditions of the environmental tests), not
limits on a measured value: they are listed with the D.6 item that applies them, or "no
method in appendix D" where the standard leaves the test to the product specification.
:func:`row_mapping` tells, for the loaded plugins, which rows map to a registered metric and
which name an item no loaded plugin registers — reports print those as not available.
"""

from __future__ import annotations

from typing import Any, Mapping

import attrs
from metro.api import Q_, Comparison, Specification, Text, msg, parse_limit

STANDARD = "gbt45570"
APPLICATIONS = ("aerospace", "aviation", "marine")
APPLICATION_CN = {"aerospace": "航天", "aviation": "航空", "marine": "船舶"}
#: what a manifest's device.application may say, mapped to the tables' three columns
_APPLICATION_WORDS = {
    "aerospace": "aerospace", "space": "aerospace", "航天": "aerospace",
    "aviation": "aviation", "aeronautics": "aviation", "aircraft": "aviation", "航空": "aviation",
    "marine": "marine", "naval": "marine", "ship": "marine", "shipborne": "marine",
                      "船舶": "marine",
}


def application_of(text: str | None) -> str | None:
    """The table column (aerospace/aviation/marine) a device's ``application`` names, or None."""
    return _APPLICATION_WORDS.get(str(text or "").strip().lower())


# Where a limit comes from (Specification.source), as messages, not English to be parsed: the
# report merges them by their fields (report.limit_sources) and prints them in its language.
#: message ids of the sources (each written once more, literally, in the function that makes it)
ROW_SOURCE = "GB/T 45570—2025 table {table} row {row} ({name}), {application}"
CLAUSE_SOURCE = "GB/T 45570—2025 {clause}"
CLAUSE_WHY_SOURCE = "GB/T 45570—2025 {clause} ({why})"
REMARK_SOURCE = "{source}; {remark}"
PRODUCT_SOURCE = "product specification ({where})"


def row_source(table: str, no: int, name_en: str, application: str) -> Text:
    """``GB/T 45570—2025 table A.1 row 4 (scale factor repeatability), aviation`` (the row name
    and the application are in the catalog, so a document prints them in its language)."""
    return msg("GB/T 45570—2025 table {table} row {row} ({name}), {application}", table=table,
               row=no,
               name=name_en, application=application)


def clause_source(clause: str, why: Any = None) -> Text:
    """``GB/T 45570—2025 5.2.8 (insulation resistance ≥ 50 MΩ)``; ``why`` a message, or None."""
    if why is None:
        return msg("GB/T 45570—2025 {clause}", clause=clause)
    return msg("GB/T 45570—2025 {clause} ({why})", clause=clause, why=why)


def product_source(where: Any) -> Text:
    """``product specification (inspection.mass.limit)``: the manifest field holding the limit."""
    return msg("product specification ({where})", where=where)


def with_remark(source: Any, remark: Any) -> Text:
    """A source and a remark on how it applies (``…; applies to D.1.1 only (…)``)."""
    return msg("{source}; {remark}", source=source, remark=remark)


@attrs.frozen
class LimitRow:
    """One row of table A.1 or B.1: a quantity, its metric key and the three applications' limits.

    ``limits`` maps an application to the bound (``≤``/``≥``) or to (lower, upper) for a range,
    in ``unit``.  ``magnitude``: the table bounds a sensitivity or angle whose sign only tells a
    direction, so |value| is compared.
    """

    table: str
    no: int
    name_cn: str
    name_en: str
    key: str
    unit: str
    comparison: Comparison
    limits: Mapping[str, Any] = attrs.field(converter=dict)
    items: tuple[str, ...] = attrs.field(converter=tuple)
    clause: str = ""
    magnitude: bool = False

    def __attrs_post_init__(self) -> None:
        if set(self.limits) != set(APPLICATIONS):
            raise ValueError(f"table {self.table} row {self.no}: limits for {sorted(self.limits)}")

    def source(self, application: str) -> Text:
        return row_source(self.table, self.no, self.name_en, application)

    def specification(self, application: str) -> Specification:
        v = self.limits[application]
        src = self.source(application)
        if self.comparison is Comparison.RANGE:
            lo, hi = v
            return Specification(self.key, Comparison.RANGE, Q_(lo, self.unit), Q_(hi, self.unit),
                                 source=src,
                                 name=self.name_en, magnitude=self.magnitude, items=self.items)
        return Specification(self.key, self.comparison, Q_(v, self.unit), source=src,
                             name=self.name_en,
                             magnitude=self.magnitude, items=self.items)


LE, GE, RANGE = Comparison.AT_MOST, Comparison.AT_LEAST, Comparison.RANGE


def _rows(table: str, k_unit: str, k: tuple, kn: tuple, ka: tuple, kt: tuple, omega: tuple,
          bt: tuple,
          bh: tuple, power: tuple) -> tuple[LimitRow, ...]:
    """The 16 rows shared by tables A.1 and B.1 (same quantities, own limits per column)."""

    def col(v: tuple) -> dict[str, Any]:
        return dict(zip(APPLICATIONS, v))

    return (
        LimitRow(table, 1, "标度因数", "scale factor", "K", k_unit, GE, col(k), ("D.1.1", "D.2.1"),
                 "6.2.7.1.1"),
        LimitRow(table, 2, "标度因数非线性度", "scale factor nonlinearity", "Kn", "ppm", LE,
                 col(kn),
                 ("D.1.2", "D.2.2"), "6.2.7.1.2"),
        LimitRow(table, 3, "标度因数不对称度", "scale factor asymmetry", "Ka", "ppm", LE, col(ka),
                 ("D.1.3", "D.2.3"), "6.2.7.1.3"),
        LimitRow(table, 4, "标度因数重复性", "scale factor repeatability", "Kr", "ppm", LE, col((10,
                                                                                          10,
                                                                                          5)),
                 ("D.1.4", "D.2.4"), "6.2.7.1.4"),
        LimitRow(table, 5, "标度因数温度灵敏度", "scale factor temperature sensitivity", "Kt",
                 "ppm/delta_degC",
                 LE, col(kt), ("D.1.5", "D.2.5"), "6.2.7.1.5", magnitude=True),
        LimitRow(table, 6, "输入轴失准角", "input axis misalignment", "gamma", "deg", LE, col((0.5,
                                                                                         0.5,
                                                                                         0.5)),
                 ("D.1.6", "D.2.6"), "6.2.7.2", magnitude=True),
        LimitRow(table, 7, "最大输入角速率", "maximum input rate", "Omega_max", "deg/s", GE,
                 col(omega),
                 ("D.3",), "6.2.7.3"),
        LimitRow(table, 8, "阈值", "threshold", "threshold", "deg/h", LE, col((0.02, 0.02, 0.01)),
                 ("D.4",),
                 "6.2.7.4"),
        LimitRow(table, 9, "零偏", "bias", "B0", "deg/h", RANGE, col(((-1, 1),) * 3), ("D.5.1",),
                 "6.2.7.5.1"),
        LimitRow(table, 10, "零偏稳定性", "bias stability", "Bs", "deg/h", LE, col((0.01, 0.007,
                                                                               0.003)),
                 ("D.5.2",), "6.2.7.5.2"),
        LimitRow(table, 11, "零偏重复性", "bias repeatability", "Br", "deg/h", LE, col((0.01, 0.007,
                                                                                   0.003)),
                 ("D.5.3",), "6.2.7.5.3"),
        LimitRow(table, 12, "零偏温度灵敏度", "bias temperature sensitivity", "Bt",
                 "deg/h/delta_degC", LE,
                 col(bt), ("D.5.4",), "6.2.7.5.4", magnitude=True),
        LimitRow(table, 13, "零偏磁场灵敏度", "bias magnetic sensitivity", "Bh", "deg/h/mT", LE,
                 col(bh),
                 ("D.5.5",), "6.2.7.5.5", magnitude=True),
        LimitRow(table, 14, "角度随机游走", "angle random walk", "RWC", "deg/hour**0.5", LE,
                 col((0.002, 0.0015, 0.0006)), ("D.5.6",), "6.2.7.6"),
        LimitRow(table, 15, "准备时间", "set-up time", "setup_time", "s", LE, col((10, 10, 60)),
                 ("6.2.7.7",),
                 "6.2.7.7"),
        LimitRow(table, 16, "功耗", "power consumption", "P", "W", LE, col(power), ("6.2.7.8",),
                 "6.2.7.8"),
    )


#: GB/T 45570—2025 table A.1, typical laser gyros
TABLE_A1 = _rows("A.1", "P/arcsec", k=(0.25, 0.25, 0.50), kn=(10, 10, 5), ka=(10, 10, 5), kt=(0.5,
                                                                                              0.5,
                                                                                              0.2),
                 omega=(400, 400, 30), bt=(0.001, 0.001, 0.0005), bh=(0.1, 0.1, 0.03), power=(3, 3,
                                                                                              8))
#: GB/T 45570—2025 table B.1, typical fibre gyros
TABLE_B1 = _rows("B.1", "LSB/(deg/s)", k=(5000, 5000, 5000), kn=(50, 50, 10), ka=(50, 50, 10),
                 kt=(5, 3, 0.2),
                 omega=(30, 200, 30), bt=(0.01, 0.01, 0.005), bh=(0.1, 0.2, 0.03), power=(5, 5, 50))
TABLES = {"laser": TABLE_A1, "fibre": TABLE_B1}


@attrs.frozen
class SeverityRow:
    """One row of table C.1: an environmental test and its severity per application.

    ``severity`` maps an application to a quantity (the test level), to text where the table
    gives a profile or "√" (set by the technical agreement), or to ``None`` ("—", no requirement).
    ``items`` are the appendix-D methods that apply it; empty when appendix D has none.  Where
    the D.6 item reports the level it applied as a metric (``key``), the row is also a
    specification on that level: ``comparison`` says which way is at least as severe (a low
    temperature at most −45 °C, a vibration at least 3 g rms); ``extra`` adds text per application.
    """

    no: int
    name_cn: str
    name_en: str
    severity: Mapping[str, Any] = attrs.field(converter=dict)
    items: tuple[str, ...] = attrs.field(default=(), converter=tuple)
    clause: str = ""
    key: str = ""
    comparison: Comparison | None = None
    extra: Mapping[str, str] = attrs.field(factory=dict, converter=dict)

    table = "C.1"

    def source(self, application: str) -> Text:
        return row_source("C.1", self.no, self.name_en, application)

    def specification(self, application: str) -> Specification | None:
        v = self.severity[application]
        if not self.key or self.comparison is None or not hasattr(v, "magnitude"):
            return None
        # a severity is a condition the lab sets, not a result of the device: the level as set is
        # compared
        # with the row (simple acceptance; its U is reported) — docs/interpretations.md, "Conformity
        # — test levels"
        return Specification(self.key, self.comparison, v, source=self.source(application),
                             name=f"{self.name_en} (test severity)", items=self.items,
                             rule="simple")

    def text(self, application: str) -> str:
        v = self.severity[application]
        if v is None:
            return "— (no requirement)"
        spec = self.specification(application)
        if spec is not None:
            text = spec.text()
        else:
            from metro.api import fmt_quantity

            text = fmt_quantity(v) if hasattr(v, "magnitude") else str(v)
        extra = self.extra.get(application)
        return f"{text} ({extra})" if extra else text


def _sev(a: Any, b: Any, c: Any) -> dict[str, Any]:
    return dict(zip(APPLICATIONS, (a, b, c)))


_AGREED = "√ (by technical agreement, verified with the system)"
_SHOCK_CYCLE = "{lo} °C ~ +{hi} °C, transfer ≤ 2 min, ≥ 3 cycles"

#: GB/T 45570—2025 table C.1, typical environmental severities (temperatures in °C, absolute)
TABLE_C1 = (
    SeverityRow(1, "低温工作", "low temperature, operating", _sev(Q_(-45, "degC"), Q_(-55, "degC"),
                                                              Q_(-20, "degC")),
                ("D.6.1",), "6.2.8.1", key="T_low", comparison=LE),
    SeverityRow(2, "低温贮存", "low temperature, storage", _sev(Q_(-55, "degC"), Q_(-55, "degC"),
                                                            Q_(-20, "degC"))),
    SeverityRow(3, "高温工作", "high temperature, operating", _sev(Q_(70, "degC"), Q_(85, "degC"),
                                                               Q_(60, "degC")),
                ("D.6.2",), "6.2.8.2", key="T_high", comparison=GE),
    SeverityRow(4, "高温贮存", "high temperature, storage", _sev(Q_(85, "degC"), Q_(85, "degC"),
                                                             Q_(60,
                                                                                                "degC"))),
    SeverityRow(5, "温度冲击", "thermal shock", _sev(_SHOCK_CYCLE.format(lo=-55, hi=85),
                                                   _SHOCK_CYCLE.format(lo=-55, hi=85),
                                                   _SHOCK_CYCLE.format(lo=-20, hi=60))),
    SeverityRow(6, "低气压", "low pressure", _sev(Q_(1.33e-3, "Pa"), "≤ 3500 Pa", None)),
    SeverityRow(7, "加速度", "acceleration", _sev("≥ 18 g", "≥ 15 g", None)),
    SeverityRow(8, "性能振动", "vibration, operating", _sev(Q_(3, "gn"), Q_(6.6, "gn"), Q_(3.3,
                                                                                       "gn")),
                ("D.6.3",), "6.2.8", key="vib_perf_level", comparison=GE, extra=_sev("rms", "rms",
                                                                                     "rms")),
    SeverityRow(9, "耐久振动", "vibration, endurance", _sev(Q_(9, "gn"), Q_(8.4, "gn"), Q_(7.9,
                                                                                       "gn")),
                ("D.6.3",), "6.2.8", key="vib_end_level", comparison=GE, extra=_sev("rms", "rms",
                                                                                    "rms")),
    SeverityRow(10, "机械冲击", "mechanical shock", _sev(Q_(40, "gn"), Q_(15, "gn"), Q_(15, "gn")),
                ("D.6.4",), "6.2.8", key="shock_level", comparison=GE,
                extra=_sev("20 ms pulse", "11 ms pulse", "11 ms pulse")),
    SeverityRow(11, "湿热", "damp heat", _sev(_AGREED, _AGREED, _AGREED)),
    SeverityRow(12, "霉菌", "mould", _sev(_AGREED, _AGREED, _AGREED)),
    SeverityRow(13, "盐雾", "salt fog", _sev(_AGREED, _AGREED, _AGREED)),
    SeverityRow(14, "热真空", "thermal vacuum",
                _sev("≤ 6.65×10⁻³ Pa; −45 °C ~ +85 °C; ≥ 3 cycles", None, None)),
    SeverityRow(15, "抗辐照", "radiation hardness",
                _sev("total dose ≥ 20 krad(Si); single event ≥ 10 keV (or per mission "
                     "specification)", None, None)),
    SeverityRow(16, "电磁兼容性", "electromagnetic compatibility", _sev(_AGREED, _AGREED, _AGREED)),
)


def table_for(technology: str | None) -> tuple[LimitRow, ...] | None:
    """Table A.1 for laser gyros, B.1 for fibre gyros, None for other technologies."""
    tech = str(technology or "").lower()
    return TABLES.get("fibre" if tech == "fiber" else tech)


def specifications(device, given: Mapping[str, Any] | None = None) -> list[Specification]:
    """The typical limits of the device's technology and application (table A.1 or B.1) and the
    C.1 severities of its application that a D.6 item reports; empty if either is unknown.

    ``given`` is the campaign's own ``[specification]`` table: where it limits the bias stability
    (``Bs`` or ``Bs_<t>``) the product specification states its smoothing time, and row 10 is left
    out
    (:func:`_bias_stability_at`)."""
    rows = table_for(device.technology)
    app = application_of(device.application)
    if rows is None or app is None:
        return [POLARITY]
    own_bs = any(k == "Bs" or str(k).startswith("Bs_") for k in (given or {}))
    severities = [r.specification(app) for r in TABLE_C1]
    typical = [_bias_stability_at(r, _by_method(r, r.specification(app))) for r in rows
               if not (own_bs and r.key == "Bs")]
    return typical + [s for s in severities if s is not None] + [POLARITY]


#: the smoothing time t of D.5.2.2 that row 10 (零偏稳定性) of tables A.1 and B.1 is judged at
#: (docs/interpretations.md, "D.5.2 — which smoothing time the table's limit applies to")
TABLE_SMOOTHING_S = 100


def _bias_stability_at(row: LimitRow, spec: Specification) -> Specification:
    """Row 10 states no smoothing time, and D.5.2.2 gives two (t = 100 s or t = 10 s).  The limit is
    judged at t = 100 s — the time the clause names first, and the one at which the same table's
    angle random walk (row 14) is nearly consistent with it: for white rate noise B_s(t) = RWC·60/√t
    (t in s), so row 14's aviation 0.0015 (°)/h^½ gives 0.009 (°)/h at 100 s but 0.028 (°)/h at 10
    s,
    against row 10's 0.007 (°)/h.  B_s at any other t is reported without a verdict
    (informative)."""
    if row.key != "Bs":
        return spec
    t = f"{TABLE_SMOOTHING_S} s"
    return attrs.evolve(spec, symbol=f"Bs_{TABLE_SMOOTHING_S}s", source=with_remark(spec.source,
                                                                                    msg(
        "judged at t = {t} of D.5.2.2; B_s at another t is informative", t=t)))


def _by_method(row: LimitRow, spec: Specification) -> Specification:
    """Row 1 (标度因数 K) is in P/″ in table A.1 and in LSB/[(°)/s] in table B.1: a limit judges the
    scale factor of the method whose output kind it is written in — A.1's the angle method's
    (D.1.1, pulses), B.1's the rate method's (D.2.1, LSB).  A fibre gyro with a pulse output sent to
    the angle method by 6.2.7.1 gives K in P/″, which B.1's LSB limit does not apply to (there is no
    conversion between pulses per arcsecond and LSB per °/s); the assessment lists that limit as
    not judged instead of failing on the unit (docs/interpretations.md)."""
    if row.key == "Omega_max":
        # D.3's Ω_max is the largest rate the lab set whose range meets K_n: a test level, judged as
        # set
        # (docs/interpretations.md, "Conformity — test levels")
        return attrs.evolve(spec, rule="simple")
    if row.key != "K":
        return spec
    item = "D.1.1" if row.unit == "P/arcsec" else "D.2.1"
    other = "D.2.1" if item == "D.1.1" else "D.1.1"
    return attrs.evolve(spec, items=(item,), source=with_remark(
        spec.source, msg("applies to {item} only (a K from {other} is in another output unit)",
                         item=item, other=other)))


#: 5.2.9 极性: the polarity shall be positive — 6.2.6's response ratio r (output change over the
#: applied counter-clockwise rate) must be above zero, whatever the device's technology
POLARITY = parse_limit("polarity_ratio", ">= 0", source=clause_source("5.2.9",
                                                                      msg("the polarity shall be "
                                                                          "positive")))


@attrs.frozen
class RowMapping:
    """How one table row maps onto the loaded plugins: the registered items that produce its
    metric, and the listed items that are not registered (yet)."""

    row: Any
    registered: tuple[str, ...]
    missing: tuple[str, ...]

    @property
    def status(self) -> str:
        if not self.row.items:
            return "no test method in appendix D (product specification)"
        if self.registered:
            return "implemented: " + ", ".join(self.registered)
        return "NOT AVAILABLE: " + ", ".join(self.missing) + " not registered by the loaded plugins"


def _metric_keys(cls) -> set[str]:
    return {m.key for m in getattr(cls, "metrics", ())}


def row_mapping(pm, rows) -> list[RowMapping]:
    """For each row, which of its items are registered (and, for A.1/B.1 rows, declare a metric
    the row's key applies to) and which are not."""
    procs = {cls.item: cls for cls in pm.procedures_of(STANDARD)}
    out = []
    for row in rows:
        reg, miss = [], []
        for item in row.items:
            cls = procs.get(item)
            if cls is None:
                miss.append(item)
                continue
            if row.key:
                spec_key = row.key
                keys = _metric_keys(cls)
                if not any(k == spec_key or k.startswith(spec_key + "_") for k in keys):
                    raise ValueError(
                        f"table {row.table} row {row.no} ({row.name_en}) expects metric "
                        f"{spec_key!r} from {STANDARD}:{item}, which declares {sorted(keys)}")
            reg.append(item)
        out.append(RowMapping(row, tuple(reg), tuple(miss)))
    return out

"""GB/T 45570—2025 clause 5 requirement by requirement: which item answers it, and the row a type
test report prints for it — the result and verdict, "not performed" with the reason, or "by
product specification".

:data:`REQUIREMENTS` lists every requirement of clause 5 in the standard's order (5.1 … 5.5.2 b)),
each with the item(s) of clause 6 / appendix D that answer it and the metric keys of their results
that the requirement is about.  :func:`clause5_rows` turns a run record into the rows; the report
context carries them as ``context["gbt45570"]["clause5"]``.  :func:`specifications` gives the
limits of the type-test items (inspection, 5.4 tests done elsewhere, reliability) that the
campaign's records call for.
"""

from __future__ import annotations

import re

import attrs
from metro.api import Q_, Comparison, Specification, join, msg

from . import records as R
from .conformity import clause_source

STANDARD = "gbt45570"
NOT_PERFORMED = "not performed"
BY_SPEC = "by product specification"
PERFORMED = "performed"
VERDICT_TEXT = {"pass": "conforms", "fail": "does not conform", "indeterminate": "indeterminate"}


@attrs.frozen
class Requirement:
    clause: str
    text_cn: str
    text_en: str
    items: tuple[str, ...] = ()
    # metric keys (or key prefixes) of the results this requirement is about
    keys: tuple[str, ...] = ()
    by_spec: str = ""  # why the requirement is the product specification's (no test item)

    @property
    def text(self) -> str:
        return f"{self.text_cn} {self.text_en}"


def _q(clause, cn, en, items=(), keys=(), by_spec=""):
    return Requirement(clause, cn, en, tuple(items), tuple(keys), by_spec)


_SF = ("D.1.1", "D.2.1")
REQUIREMENTS: tuple[Requirement, ...] = (
    _q("5.1", "通则",
       "general: this standard and the product specification; the product specification prevails",
       by_spec="a rule of precedence: the product specification's limits replace the typical ones "
               "(applied in every verdict below)"),
    _q("5.2.1", "材料", "materials", ("5.2.1",),
       by_spec="5.2.1 names the usual materials (一般选取) and leaves the choice to the product "
               "specification; clause 6 gives no test method"),
    _q("5.2.2", "功能与组成", "function and composition (senses and outputs rate or angle)",
       ("5.2.2",),
       ("function_nc",)),
    _q("5.2.3", "外观质量", "appearance a)–d)", ("6.2.1",), ("appearance_nc",)),
    _q("5.2.4", "外形尺寸", "dimensions per product specification, tolerance grade ≤ IT12",
       ("6.2.2",),
       ("dim", "itgrade")),
    _q("5.2.5", "重量", "mass per product specification (cables, connectors, screws included)",
       ("6.2.3",), ("mass",)),
    _q("5.2.6", "供电要求", "supply requirements: voltage kind and accuracy, current, power",
       ("5.2.6",
                                                                                           ),
       ("supply_missing", "supply_V")),
    _q("5.2.7.1", "机械接口", "mechanical interface", ("6.2.4",), ("mech_interface_nc",)),
    _q("5.2.7.2", "电气接口", "electrical interface (RS-422/RS-485, output content)", ("6.2.4",),
       ("elec_interface_nc",)),
    _q("5.2.8", "绝缘电阻", "insulation resistance ≥ 50 MΩ", ("6.2.5",), ("R_ins",)),
    _q("5.2.9", "极性", "polarity positive", ("6.2.6",)),
    _q("5.3 a)", "标度因数", "scale factor", _SF, ("K",)),
    _q("5.3 b)", "标度因数非线性度", "scale-factor nonlinearity", ("D.1.2", "D.2.2"), ("Kn",)),
    _q("5.3 c)", "标度因数不对称度", "scale-factor asymmetry", ("D.1.3", "D.2.3"), ("Ka",)),
    _q("5.3 d)", "标度因数重复性", "scale-factor repeatability", ("D.1.4", "D.2.4"), ("Kr",)),
    _q("5.3 e)", "标度因数温度灵敏度", "scale-factor temperature sensitivity", ("D.1.5", "D.2.5"),
       ("Kt",)),
    _q("5.3 f)", "输入轴失准角", "input-axis misalignment", ("D.1.6", "D.2.6")),
    _q("5.3 g)", "最大输入角速率", "maximum input rate", ("D.3",)),
    _q("5.3 h)", "阈值", "threshold", ("D.4",)),
    _q("5.3 i)", "零偏", "bias", ("D.5.1",)),
    _q("5.3 j)", "零偏稳定性", "bias stability", ("D.5.2",)),
    _q("5.3 k)", "零偏重复性", "bias repeatability", ("D.5.3",)),
    _q("5.3 l)", "零偏温度灵敏度", "bias temperature sensitivity", ("D.5.4",)),
    _q("5.3 m)", "零偏磁场灵敏度", "bias magnetic sensitivity", ("D.5.5",)),
    _q("5.3 n)", "角度随机游走", "angle random walk", ("D.5.6",)),
    _q("5.3 o)", "准备时间", "set-up time", ("6.2.7.7",)),
    _q("5.3 p)", "功耗", "power consumption", ("6.2.7.8",)),
    _q("5.4 a)", "低温工作", "low-temperature operation", ("D.6.1",)),
    _q("5.4 b)", "低温贮存", "low-temperature storage", ("6.2.8.2",)),
    _q("5.4 c)", "高温工作", "high-temperature operation", ("D.6.2",)),
    _q("5.4 d)", "高温贮存", "high-temperature storage", ("6.2.8.4",)),
    _q("5.4 e)", "温度冲击", "temperature shock", ("6.2.8.5",)),
    _q("5.4 f)", "低气压(高度)", "low pressure (altitude)", ("6.2.8.6",)),
    _q("5.4 g)", "加速度", "acceleration", ("6.2.8.7",)),
    _q("5.4 h)", "性能振动", "performance vibration", ("D.6.3",), ("vib_perf_level", "dBV12",
                                                               "dBV13_")),
    _q("5.4 i)", "耐久振动", "endurance vibration", ("D.6.3",), ("vib_end_level", "dBV13end")),
    _q("5.4 j)", "机械冲击", "mechanical shock", ("D.6.4",)),
    _q("5.4 k)", "湿热", "damp heat", ("6.2.8.10",)),
    _q("5.4 l)", "霉菌", "mould", ("6.2.8.11",)),
    _q("5.4 m)", "盐雾", "salt fog", ("6.2.8.12",)),
    _q("5.4 n)", "热真空", "thermal vacuum", ("6.2.8.13",)),
    _q("5.4 o)", "抗辐照", "radiation hardness", ("6.2.8.14",)),
    _q("5.4 p)", "电磁兼容性", "electromagnetic compatibility", ("6.2.8.15",)),
    _q("5.5.1", "平均故障间隔时间", "MTBF ≥ 5 000 h", ("6.2.9.1",), ("mtbf",)),
    _q("5.5.2 a)", "工作寿命", "working life ≥ 1 000 h", ("6.2.9.2",), ("working_life",)),
    _q("5.5.2 b)", "日历寿命", "calendar life ≥ 5 a", ("6.2.9.2",), ("calendar_life",)),
)

#: every item that answers a clause-5 requirement (the ``type-test`` series)
TYPE_TEST_ITEMS: tuple[str, ...] = tuple(dict.fromkeys(i for r in REQUIREMENTS for i in r.items))

RELIABILITY_SPECS = tuple(
    Specification(key, Comparison.AT_LEAST, Q_(value, unit), source=clause_source(*clause),
                  name=name, items=(item,))
    for key, value, unit, clause, name, item in (
        ("mtbf_lower", 5000, "h", ("5.5.1", "MTBF ≥ 5 000 h"), "MTBF, lower confidence bound",
         "6.2.9.1"),
        ("working_life", 1000, "h", ("5.5.2 a)",), "working life", "6.2.9.2"),
        ("calendar_life", 5, "year", ("5.5.2 b)",), "calendar life", "6.2.9.2"),
    )
)


def specifications(campaign) -> list[Specification]:
    """The limits of the type-test items that the campaign's records call for."""
    from . import inspection, type_env

    out: list[Specification] = []
    if R.has(campaign, "inspection"):
        paths = {"appearance_nc": "appearance", "supply_missing": "supply",
                 "mech_interface_nc": "interfaces",
                 "elec_interface_nc": "interfaces"}
        out += [s for s in inspection.COUNT_SPECS if R.has(campaign,
                                                           f"inspection.{paths[s.symbol]}")]
        if R.has(campaign, "inspection.function"):
            from .declarations import FUNCTION_SPEC

            out.append(FUNCTION_SPEC)
        if R.has(campaign, "inspection.insulation"):
            out.append(inspection.INSULATION_SPEC)
        out += (inspection.dimension_specifications(campaign)
                + inspection.mass_specifications(campaign)
                + inspection.supply_specifications(campaign))
    if type_env.SECTION in campaign.records:
        out += type_env.specifications(campaign)
    if R.has(campaign, "reliability"):
        out += list(RELIABILITY_SPECS)
    return out


def _matches(key: str, keys: tuple[str, ...]) -> bool:
    return not keys or any(key == k or key.startswith(k if k.endswith("_") else k + "_")
                           for k in keys)


def _result_text(r) -> str:
    from metro.api import fmt_num, unit_text

    v, U = r.reported()
    ut = unit_text(r.metric.unit)
    # exact (a count, a declared value, a ratio of specs)
    if r.U is None or float(r.U.magnitude) == 0:
        v = fmt_num(float(r.value.to(r.metric.unit).magnitude), 6)
    text = f"{r.metric.key} = {v}{(' ' + ut) if ut else ''}"
    if U is not None and float(r.U.magnitude) > 0:
        text += f" (U = {U}{(' ' + ut) if ut else ''}, k = {r.k:.2f})"
    # the reason is the row's note (the item's warning); the document translates the mark
    if not r.reportable:
        text += " [not reportable]"
    # a minus sign, not a hyphen: a line may break after a hyphen and split the number in two
    return re.sub(r"(?<![\w.])-(?=\d)", "\u2212", text)


def _combine(statuses: list[str]) -> str:
    for s in ("fail", "indeterminate", "pass"):
        if s in statuses:
            return s
    return ""


def clause5_rows(record, *, limit: int = 4) -> list[dict[str, str]]:
    """One row per clause-5 requirement, in the standard's order: ``clause``, ``requirement``,
    ``method`` (the items), ``status`` (performed / not performed / by product specification),
    ``result`` (the results, at most ``limit`` listed), ``verdict`` (conforms / does not conform /
    indeterminate / "no limit given", or the status where nothing was judged) and ``reason`` (also
    as ``note``)."""
    outs = [o for o in record.outcomes if o.standard == STANDARD]
    a = record.conformity
    verdicts = {} if a is None else {}
    if a is not None:
        for v in a.verdicts:
            verdicts.setdefault((v.item, v.key), []).append(v)
    choices = {c.item: c for c in getattr(record, "selection", ())}
    rows = []
    for req in REQUIREMENTS:
        row = {"clause": req.clause, "requirement": req.text, "requirement_cn": req.text_cn,
               "requirement_en": req.text_en, "method": " / ".join(req.items) or "—"}
        if not req.items:  # 5.1
            rows.append(row | {"status": BY_SPEC, "result": "—", "verdict": BY_SPEC,
                               "reason": req.by_spec})
            continue
        mine = [(o,
                 r) for o in outs if o.item in req.items for r in o.results
                if _matches(r.metric.key, req.keys)]
        ran = [o for o in outs if o.item in req.items]
        if req.by_spec and ran:  # reported, not judged (5.2.1): what the records declare
            shown = [" / ".join(str(c) for c in row[:2]) for o in ran for t in o.tables
                     for row in t.rows]
            rows.append(row | {"status": BY_SPEC, "result": "; ".join(shown) or "—",
                               "verdict": BY_SPEC,
                               "reason": "; ".join([req.by_spec] + [w for o in ran
                                                                    for w in o.warnings])})
            continue
        if not ran:
            reasons = [f"{i}: {choices[i].reason}" for i in req.items if i in choices]
            rows.append(row | {"status": NOT_PERFORMED, "result": "—", "verdict": NOT_PERFORMED,
                               "reason": "; ".join(reasons) or "not requested in this run"})
            continue
        if not mine:
            notes = [w for o in ran for w in o.warnings]
            rows.append(row | {"status": NOT_PERFORMED, "result": "—", "verdict": NOT_PERFORMED,
                               "reason": "; ".join(notes)
                               or "the item gave no result for this requirement"})
            continue
        texts = [_result_text(r) for _, r in mine]
        if len(texts) > limit:
            texts = texts[:limit] + [f"… and {len(mine) - limit} more (see the item's section)"]
        judged = [v for o, r in mine for v in verdicts.get((o.item, r.metric.key), [])]
        status = _combine([v.status.value for v in judged])
        unjudged = [r.metric.key for o, r in mine if (o.item, r.metric.key) not in verdicts]
        if status:
            verdict = VERDICT_TEXT[status]
            worst = [v for v in judged if v.status.value == status]
            parts = [v.reason for v in worst[:2]]
            if unjudged:
                parts.append(msg("no limit for {keys}",
                                 keys=", ".join(unjudged[:3]) + (" …" if len(unjudged) > 3
                                                                 else "")))
        else:
            verdict = "no limit given"
            parts = [msg("by product specification: give the limit (manifest [specification] or "
                         "the record) to judge it")]
        warnings = [w for o in ran for w in o.warnings]
        # each part keeps its message, so the document writes the reason in its language
        reason = join("; ", parts + warnings[:2])
        rows.append(row | {"status": PERFORMED, "result": "; ".join(texts), "verdict": verdict,
                           "reason": reason})
    for r in rows:
        r["note"] = r["reason"]  # the report's clause-5 table prints it as the row's note
    return rows


"""GB/T 45570—2025 5.2.1 materials and 5.2.2 function and composition, from the campaign's
``[inspection.materials]`` and ``[inspection.function]`` records.

Clause 6 gives no test method for either.  5.2.1 names the materials usually chosen (一般选取) and
leaves the rest to the product specification, so the declared materials are reported against the
usual ones — a difference is a note, never a nonconformity (the row says "by product
specification").  5.2.2 *requires* (应) that the gyro senses the angular rate or angle of its
carrier and outputs it; its composition (optical sensor, structure, control circuit with software)
is what it *generally* (一般) consists of.  The two "shall" answers give a count of requirements
not met (exact), judged ≤ 0; a different composition is a note.
"""

from __future__ import annotations

from metro.api import (Q_, BudgetRow, Campaign, Comparison, Metric, Outcome, RunContext,
                       Specification, TableSpec, UncertaintyBudget, msg)

from . import records as R
from .common import COVERAGE, STANDARD
from .conformity import clause_source

#: 5.2.1: the usual materials by technology (key in the record -> (what, the usual material, words
#: that match it))
USUAL = {
    "laser": {"cavity": ("resonator cavity", "glass-ceramic (微晶玻璃)", ("glass-ceramic",
                                                                      "glass ceramic", "微晶玻璃",
                                                                      "zerodur")),
              "mirrors": ("mirrors", "glass-ceramic (微晶玻璃)", ("glass-ceramic", "glass ceramic",
                                                              "微晶玻璃", "zerodur")),
              "housing": ("housing", "aluminium alloy (铝合金)", ("aluminium", "aluminum",
                                                               "铝合金"))},
    "fibre": {"fibre": ("sensing fibre", "single-mode fibre (单模光纤)", ("single-mode",
                                                                      "single mode",
                                                                      "单模", "pm fibre",
                                                                   "polarization-maintaining",
                                                                      "polarisation-maintaining")),
              "potting": ("coil potting", "organic material matched to the fibre coating's modulus",
                          ("organic", "epoxy", "silicone", "有机")),
              "housing": ("housing", "aluminium alloy or soft-magnetic material (铝合金或软磁材料)",
                          ("aluminium", "aluminum", "铝合金", "soft-magnetic", "soft magnetic",
                           "permalloy", "软磁"))},
}

COMPOSITION = {"optical sensor": ("optical", "光学传感器", "sensor"), "structure": ("structur",
                                                                               "结构"),
               "control circuit": ("circuit", "electronics", "控制电路")}


class Materials521(R.InspectionRecord):
    """GB/T 45570—2025 5.2.1 材料 (materials): the declared materials against those 5.2.1 names as
    usual for the device's technology (laser: glass-ceramic cavity and mirrors, aluminium-alloy
    housing; fibre: single-mode fibre, organic potting matched to the coating, aluminium-alloy or
    soft-magnetic housing).  No method in clause 6 and no limit: reported, by product
    specification."""

    item = "5.2.1"
    clause = "5.2.1"
    title = "Materials (材料)"
    metrics = ()
    path = "materials"
    step = ("from the product specification and the build records: the materials of the optical "
            "sensor and the housing (5.2.1)")

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.1")
        tech = "fibre" if campaign.device.technology in ("fibre",
                                                         "fiber") else campaign.device.technology
        usual = USUAL.get(tech, {})
        rows, warnings = [], []
        for key in rec:
            R.text(rec, key, src, where)
        for key, (what, typical, words) in usual.items():
            declared = R.text(rec, key, src, where, required=False, default="")
            if not declared:
                warnings.append(msg("5.2.1: the {what} material is not declared "
                                    "(usually {typical})", what=what, typical=typical))
                rows.append([what, "not declared", typical, "—"])
                continue
            same = any(w in declared.lower() for w in words)
            if not same:
                warnings.append(msg("5.2.1: {what} of {declared}, not the usual {typical}: by "
                                    "product specification", what=what,
                                    declared=repr(declared), typical=typical))
            rows.append([what, declared, typical, "usual" if same else "per product specification"])
        for key in rec:
            if key not in usual:
                rows.append([key, str(rec[key]), "—", "per product specification"])
        if not usual:
            warnings.append(msg("5.2.1 names usual materials for laser and fibre gyros only, not "
                                "{tech}",
                                tech=tech or msg("unstated")))
        tab = TableSpec("materials", "Materials (5.2.1): declared and usual", ["part", "declared",
                                                                               "usual (一般选取)",
                                                                                "status"], rows)
        return Outcome(STANDARD, self.item, self.title, self.clause, [], tables=[tab],
                       warnings=warnings)


class Function522(R.InspectionRecord):
    """GB/T 45570—2025 5.2.2 功能与组成 (function and composition): the gyro shall sense the angular
    rate
    or angle of its carrier and output it (``senses``, ``outputs``: the count of those not met,
    exact,
    judged ≤ 0); it generally consists of an optical sensor, a structural assembly and a control
    circuit with software (``composition``: a difference is a note)."""

    item = "5.2.2"
    clause = "5.2.2"
    title = "Function and composition (功能与组成)"
    metrics = (Metric("function_nc", "function requirements of 5.2.2 not met", "n_f", "", "5.2.2"),)
    path = "function"
    step = "check that the gyro senses and outputs angular rate or angle and list its parts (5.2.2)"

    def evaluate(self, campaign: Campaign, ctx: RunContext) -> Outcome:
        src, where, rec = self.record(campaign, "5.2.2")
        failed = [text for key, text in (("senses", "senses the carrier's angular rate or angle"),
                                         ("outputs", "outputs angular rate or angle information"))
                  if not R.answer(rec, key, src, where)]
        parts = rec.get("composition", [])
        if isinstance(parts, str):
            parts = [parts]
        if not isinstance(parts, list) or not all(isinstance(p, str) for p in parts):
            from metro.api import DataError

            raise DataError(src, f"{where}.composition", f"must be a list of parts, got {parts!r}")
        low = [p.lower() for p in parts]
        lacking = [name for name,
                   words in COMPOSITION.items() if not any(w in p for p in low for w in words)]
        warnings = [msg("5.2.2: the composition lists no {parts} (generally part of a gyro, 一般)",
                        parts=", ".join(lacking))] if lacking \
            else []
        b = UncertaintyBudget("n_f", "", [BudgetRow.type_b(msg("observed answers, a count (exact)"),
                                                           "u(n_f)", Q_(0.0, ""),
                                                           distribution="uniform")],
                              coverage=COVERAGE)
        res = R.na_result(self.metrics[0], Q_(float(len(failed)), ""), b.combined, b,
                          note="not met: " + "; ".join(failed) if failed else "senses and outputs")
        tab = TableSpec("composition", "Composition (5.2.2)", ["part"],
                        [[p] for p in parts] or [["not listed"]])
        return Outcome(STANDARD, self.item, self.title, self.clause, [res], tables=[tab],
                       warnings=warnings)


FUNCTION_SPEC = Specification("function_nc", Comparison.AT_MOST, Q_(0, ""),
                              source=clause_source("5.2.2"),
                              name="function (senses and outputs rate or angle)", items=("5.2.2",))
PROCEDURES = (Materials521, Function522)

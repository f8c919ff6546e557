"""Equipment requirements (GB/T 45570 6.1.2, JJF 2014 8 j)): the roles an item requires, the
kinds of calibration U it can use, and the equipment a run keeps.

Checked before an item is evaluated: a missing required role or a U of the wrong kind is a
:class:`~metro.core.base.errors.DataError` naming the equipment and the role; an absent optional
role becomes a note row in the item's budgets, never a row dropped without a word.
"""

from __future__ import annotations

from typing import Any, Iterable

import attrs

from ..base import vocabulary as voc
from ..base.errors import DataError
from ..base.locale import msg
from ..model.campaign import Campaign

__all__ = ["check_equipment", "used_equipment", "note_absent_equipment"]


def _kind_text(kinds) -> str:
    return " or ".join("relative (a number such as \"2e-7\")" if k == ""
                       else f"in {k} (or a unit of that kind)"
                       for k in kinds)


def check_equipment(campaign: Campaign, proc) -> list:
    """Check ``proc``'s equipment requirements against ``campaign`` before it is evaluated.

    A required role the campaign does not list, or a calibration U of a kind of unit the item
    cannot use (a counter's U in °C), is a :class:`DataError` naming the equipment, the role and
    what is accepted — never a budget row dropped without a word.  Returns the optional
    requirements that are absent and ``noted`` (the runner adds a note row for each to the item's
    budgets)."""
    from ..base.units import Q_

    absent = []
    src = campaign.source or "campaign"
    for req in getattr(proc, "equipment", ()):
        found = [(i, e) for i, e in enumerate(campaign.equipment) if e.role == req.role]
        if not found:
            if req.required:
                near = voc.did_you_mean(req.role, [e.role for e in campaign.equipment if e.role])
                hint = (f"equipment {[e.id for e in campaign.equipment if e.role == near][0]!r} "
                        f"has the role {near!r}; did you mean {req.role!r}?" if near else
                        f"add [[equipment]] with role = \"{req.role}\" and its "
                        "[equipment.calibration]")
                given = ", ".join(sorted({e.role for e in campaign.equipment}))
                raise DataError(src, "equipment",
                                f"{proc.qualified_id()} requires equipment with the role "
                                f"{req.role!r} ({req.description}); the campaign lists none "
                                f"(roles given: {given or 'none'})",
                                hint=hint)
            if req.noted:
                absent.append(req)
            continue
        kinds = req.calibration or voc.ROLE_CALIBRATION.get(req.role, ())
        if not kinds:
            continue
        for i, e in found:
            cal = e.calibration
            if cal is None:
                continue
            U = cal.uncertainty
            ok = any(U.dimensionless if k == "" else U.dimensionality == Q_(1.0, k).dimensionality
                     for k in kinds)
            if not ok:
                where = f"equipment[{i}].calibration.U" if campaign.source.endswith(".toml") else \
                    f"equipment {e.id}.calibration.U"
                raise DataError(src, where,
                                f"the {req.role} {e.id!r} has U = {U:~P}, which "
                                f"{proc.qualified_id()} cannot use: a {req.role}'s U must be "
                                f"{_kind_text(kinds)}",
                                hint=f"give the calibration certificate's U {_kind_text(kinds)}")
    return absent


def used_equipment(campaign: Campaign, procs: Iterable[Any]) -> Campaign:
    """``campaign`` with only the equipment the items ``procs`` use — the roles their
    :attr:`~metro.core.model.procedure.Procedure.equipment` requirements name — in the campaign's
    order. A report lists the equipment its items used (GB/T 45570 6.1.2, JJF 2014 8 j)), not every
    instrument of the station or every line of the manifest; ``metro acquire`` writes the same."""
    roles = {req.role for cls in procs for req in getattr(cls, "equipment", ())}
    kept = [e for e in campaign.equipment if e.role in roles]
    return (
        campaign if len(kept) == len(campaign.equipment) else attrs.evolve(campaign, equipment=kept)
    )


def note_absent_equipment(outcome, absent) -> Any:
    """``outcome`` with one note row per absent optional role in each of its budgets (zero
    contribution: the budget says what is not in it instead of leaving it out silently)."""
    if not absent:
        return outcome
    from ..uncertainty.budget import BudgetRow
    from ..base.units import Q_

    results = []
    for r in outcome.results:
        b = r.budget
        if b is None:
            results.append(r)
            continue
        rows = list(b.rows)
        for req in absent:
            if any(req.role in row.source for row in rows):
                continue
            rows.append(BudgetRow.type_b(
                msg("{role}: not given in the campaign", role=req.role), "—", Q_(0.0, b.unit),
                distribution="uniform",
                note=msg("no equipment with role {role!r} ({description}): its uncertainty is not "
                         "in this budget",
                         role=req.role, description=req.description)))
        results.append(attrs.evolve(r, budget=attrs.evolve(b, rows=rows)))
    return attrs.evolve(outcome, results=results)

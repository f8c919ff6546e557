"""A report lists the equipment its items used, not the whole station (issue 29).

A D.5.1/D.5.2/D.5.6 report listed the vibration table, shock table, callipers, balance and
megohmmeter: ``metro acquire`` wrote every instrument of the simulated station into the manifest,
and the report printed every line of the manifest. The equipment an item uses is the roles of its
``equipment`` requirements (:class:`metro.core.model.procedure.EquipmentRequirement`); ``acquire``
writes those and a run keeps those (:func:`metro.core.run.equipment_check.used_equipment`), so a
manifest with more equipment still gets a table of what was used, while a required role that is
missing stays an error. The declarations are complete: every role an item looks up while it
evaluates is one it declares.
"""

from __future__ import annotations

import shutil
import subprocess
import tomllib
from pathlib import Path

import pytest

from metro.core.base.errors import DataError
from metro.core.model.campaign import Campaign
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.documents.report import write_report
from metro.core.run.runner import run_items

# a vibration table and a megohmmeter that no D.5 item uses
EXTRA = "\n" + (Path(__file__).parents[1] / "data" / "extra_equipment.toml").read_text(
    encoding="utf-8")


def test_acquire_writes_the_equipment_of_the_items_only(tmp_path):
    from metro.core.run.manifest_writer import acquire_campaign

    pm = get_plugin_manager(autoload=False)
    manifest = acquire_campaign(pm, "gbt45570", ["D.5.1", "D.5.2", "D.5.6"], tmp_path / "camp",
                                station_options={"duration_scale": 0.05})
    doc = tomllib.loads(manifest.read_text(encoding="utf-8"))
    # 13 station instruments before
    assert sorted(e["role"] for e in doc["equipment"]) == ["counter", "platform"]


@pytest.mark.skipif(not (shutil.which("soffice") or shutil.which("libreoffice")) or
                    not shutil.which("pdftotext"),
                    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and "
                    "read the PDF")
def test_a_manifest_with_more_equipment_gets_a_table_of_what_was_used(tmp_path, campaign_factory):
    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.5,
                                               manifest_edit=lambda t: t + EXTRA)
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "gbt45570", ["D.5.1"], data=manifest)
    assert [e.role for e in rec.campaign.equipment] == ["platform", "counter"]
    pdf = write_report(tmp_path / "r.pdf", rec, layout=pm.template_for("gbt45570").layout,
                       extend=pm.extend_report_context)
    text = subprocess.run(["pdftotext", "-enc", "UTF-8", str(pdf), "-"], capture_output=True,
                          text=True,
                          check=True).stdout
    assert ("VIB-9" not in text and "MEG-1" not in text and "V-100" not in text
            and "M-500" not in text)
    listed = text[text.index("Test equipment and measuring instruments"):]
    assert "counter" in listed and "platform" in listed


def test_a_missing_required_role_stays_an_error_beside_extra_equipment(tmp_path, campaign_factory):
    manifest = campaign_factory.write_campaign(tmp_path / "camp", hours=0.2,
                                               manifest_edit=lambda t: t + EXTRA)
    pm = get_plugin_manager(autoload=False)
    with pytest.raises(DataError, match="requires equipment with the role 'rate_table'"):
        run_items(pm, "gbt45570", ["D.1.1"], data=manifest)


# items whose lookups were not declared before (the platform of D.6 and 6.2.8's biases, the
# voltmeter of 5.2.6, the fixture of JJF 2003 7.2.2–7.2.4 and JJF 2014 7.2.11, the chamber of JJF
# 2014 7.2.5 / 7.2.16) and a few whose declarations always held
LOOKUPS = [
    ("gbt45570", ["D.5.1", "D.6.3", "D.6.4", "6.2.8.2", "6.2.8.10", "5.2.6"]),
    ("jjf2003", ["7.2.1", "7.2.2", "7.2.3", "7.2.4"]),
    ("jjf2014", ["7.2.5", "7.2.11", "7.2.16"]),
    ("ogam", ["7.1"]),
]


@pytest.fixture
def looked_up(monkeypatch) -> list[str]:
    """The roles items look up (``Campaign.equipment_for``), in order, as they run."""
    roles: list[str] = []
    real = Campaign.equipment_for

    def spy(self, role):
        roles.append(role)
        return real(self, role)

    monkeypatch.setattr(Campaign, "equipment_for", spy)
    return roles


@pytest.mark.parametrize("standard, items", LOOKUPS, ids=[c[0] for c in LOOKUPS])
def test_every_role_an_item_looks_up_is_one_it_declares(looked_up, standard, items):
    pm = get_plugin_manager(autoload=False)
    for item in items:
        looked_up.clear()
        run_items(pm, standard, [item])
        declared = {r.role for r in pm.procedure(standard, item).equipment}
        assert looked_up, (standard, item)  # the item does use equipment
        assert set(looked_up) <= declared, (standard, item, sorted(set(looked_up) - declared))


@pytest.mark.slow
@pytest.mark.parametrize("standard", ["gbt45570", "jjf2003", "jjf2014", "ogam"])
def test_every_item_declares_every_role_it_looks_up(looked_up, standard):
    """Each item of each built-in standard alone on its simulated station (2 min for the four)."""
    pm = get_plugin_manager(autoload=False)
    undeclared = {}
    for cls in pm.procedures_of(standard):
        looked_up.clear()
        run_items(pm, standard, [cls.item])
        extra = set(looked_up) - {r.role for r in cls.equipment}
        if extra:
            undeclared[cls.item] = sorted(extra)
    assert not undeclared, undeclared

"""Every signatory's title prints beside their name (issue 29: only the approver's did).

A lab profile gives a title to each signatory (calibrated_by, checked_by, approved_by); the
campaign's ``operator_title`` / ``checked_by_title`` / ``approved_by_title`` override it, and a
person the campaign names gets no title from the profile (the title goes with the person).  Read
on the PDF that LibreOffice renders (pdftotext -layout: a signature row is one line).
"""

from __future__ import annotations

import shutil
import subprocess

import attrs
import pytest

from metro.core.cli.app import main
from metro.core.record.lab import load_lab
from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.record.registering import with_lab
from metro.core.documents.report import write_report
from metro.core.run.runner import run_items

pytestmark = pytest.mark.skipif(
    not (shutil.which("soffice") or shutil.which("libreoffice")) or not shutil.which("pdftotext"),
    reason="LibreOffice (soffice) and poppler (pdftotext) are needed to render and read the PDF",
)

TITLES = {"张三": "高级工程师", "李四": "质量主管", "王五": "实验室主任"}


@pytest.fixture(scope="module")
def lab(tmp_path_factory):
    path = tmp_path_factory.mktemp("lab") / "lab.toml"
    assert main(["lab", "init", str(path)]) == 0
    text = path.read_text(encoding="utf-8")
    for old, new in (("校准员", TITLES["张三"]), ("核验员", TITLES["李四"]),
                     ("技术负责人", TITLES["王五"])):
        text = text.replace(f'title = "{old}"', f'title = "{new}"')
    path.write_text(text, encoding="utf-8")
    return load_lab(path)


def _signature_lines(pdf) -> dict[str, str]:
    text = subprocess.run(["pdftotext", "-layout", "-enc", "UTF-8", str(pdf), "-"],
                          capture_output=True, text=True,
                          check=True).stdout
    start = text.rindex("Signature")
    return {name: next((ln for ln in text[start:].splitlines() if name in ln), "") for name
            in TITLES}


CASES = [("gbt45570", ["D.5.1"], {"duration_scale": 0.05, "seed": 2}),
         ("jjf2014", ["7.2.3"], {"seed": 2}),
         ("ogam", ["7.1"], {})]


@pytest.mark.parametrize("standard, items, station", CASES, ids=[c[0] for c in CASES])
def test_each_signatory_prints_with_the_title_the_lab_profile_gives(lab, tmp_path, standard, items,
                                                                    station):
    pm = get_plugin_manager(autoload=False)
    rec = with_lab(run_items(pm, standard, items, station_options=station), lab)
    out = write_report(tmp_path / "doc.pdf", rec, layout=pm.template_for(standard).layout,
                       extend=pm.extend_report_context)
    lines = _signature_lines(out)
    for name, title in TITLES.items():
        assert name in lines[name] and title in lines[name], (standard, name, lines[name])


def test_a_person_the_campaign_names_brings_their_own_title(lab, tmp_path):
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "ogam", ["7.1"])
    meta = {**dict(rec.campaign.meta), "operator": "赵六", "checked_by": "钱七",
            "checked_by_title": "工程师"}
    rec = with_lab(attrs.evolve(rec, campaign=attrs.evolve(rec.campaign, meta=meta)), lab)
    assert rec.campaign.people.operator_title == ""  # not 张三's title
    assert rec.campaign.people.checked_by_title == "工程师"
    out = write_report(tmp_path / "doc.pdf", rec, layout=pm.template_for("ogam").layout,
                       extend=pm.extend_report_context)
    text = subprocess.run(["pdftotext", "-layout", "-enc", "UTF-8", str(out), "-"],
                          capture_output=True, text=True,
                          check=True).stdout
    tail = text[text.rindex("Signature"):]
    row = {who: next(ln for ln in tail.splitlines() if who in ln) for who
           in ("赵六", "钱七", "王五")}
    assert TITLES["张三"] not in row["赵六"] and "—" in row["赵六"]
    assert "工程师" in row["钱七"] and TITLES["李四"] not in row["钱七"]
    assert TITLES["王五"] in row["王五"]

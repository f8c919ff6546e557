"""The manifest `metro acquire` writes (core/run/manifest_writer.py, TOML by tomli-w) reads back
to the same campaign, Chinese text and characters TOML must escape included."""

from __future__ import annotations

import tomllib
from pathlib import Path

import attrs

from metro.core.run.plugin_manager import get_plugin_manager
from metro.core.run.runner import load_campaign
from metro.core.base.units import Q_
from metro.core.run.manifest_writer import write_campaign

EXAMPLE = Path(__file__).resolve().parents[3] / "docs" / "examples" / "campaign" / "manifest.toml"

# quotes, a backslash, a tab, a line break, '#', '=', brackets, full-width punctuation, a character
# outside the BMP (the manifest refuses other control characters)
TRICKY = 'Acme "惯导" \\ 公司\t第二行\n#1 = [x] （零偏）℃ 😀'


def _load(path: Path):
    pm = get_plugin_manager(autoload=False)
    return load_campaign(pm, [pm.procedure("gbt45570", "D.5.2")], [{}], data=path)


def _tricky(camp):
    dev = attrs.evolve(camp.device, manufacturer="北京某惯性技术有限公司", model=TRICKY,
                       properties=dict(camp.device.properties)
                       | {"备注 note": TRICKY, "rate [°/s]": Q_(10.0, "degree / second")})
    eq = [attrs.evolve(e, properties=dict(e.properties) | {"位置": "实验室 2 号台"}) for e
          in camp.equipment]
    records = {"inspection": {"appearance": "外观完好，无划痕", "marking": TRICKY,
                              "items": [{"name": "尺寸", "value": "90 mm"},
                                        {"name": 'say "ok"', "value": "1 kg"}]},
               "environmental_tests": [{"clause": "5.4.1", "note": "高温 +70 ℃",
                                        "severity": {"temperature": "70 °C"}}]}
    meta = dict(camp.meta) | {"operator": "张三", "remark": TRICKY}
    return attrs.evolve(camp, device=dev, equipment=eq, records=records, meta=meta)


def _doc(manifest: Path) -> dict:
    return tomllib.loads(manifest.read_text(encoding="utf-8"))


def test_manifest_round_trip_keeps_chinese_and_special_characters(tmp_path):
    camp = _tricky(_load(EXAMPLE))
    first = write_campaign(camp, tmp_path / "one")
    back = _load(first)
    assert back.device.manufacturer == "北京某惯性技术有限公司"
    assert back.device.model == TRICKY
    assert back.device.properties["备注 note"] == TRICKY
    assert back.meta["remark"] == TRICKY and back.meta["operator"] == "张三"
    assert back.records["inspection"]["marking"] == TRICKY
    assert back.records["inspection"]["items"][1]["name"] == 'say "ok"'
    assert back.records["environmental_tests"][0]["severity"]["temperature"] == "70 °C"
    assert [e.properties.get("位置") for e
            in back.equipment] == ["实验室 2 号台"] * len(camp.equipment)
    assert [(e.id, e.role, e.calibration) for e in back.equipment] == [(e.id, e.role, e.calibration)
                                                                        for e in camp.equipment]
    assert dict(back.environment) == dict(camp.environment) and dict(back.site) == dict(camp.site)
    assert [(s.id, s.kind, s.interval, dict(s.conditions)) for s in back.segments] == \
        [(s.id, s.kind, s.interval, dict(s.conditions)) for s in camp.segments]
    # written again from what was read: the same manifest, value for value
    second = write_campaign(back, tmp_path / "two")
    assert _doc(second) == _doc(first)
    text = first.read_text(encoding="utf-8")
    assert "北京某惯性技术有限公司" in text and "😀" in text  # written as UTF-8, not escaped


def test_writer_uses_tomli_w():
    import inspect

    from metro.core.run import manifest_writer as campaign_writer

    assert "tomli_w" in inspect.getsource(campaign_writer.manifest_text)

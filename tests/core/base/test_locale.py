"""The message catalog and :class:`metro.core.base.locale.Text`: text made far from the document
(notes, reasons, warnings, budget components) stays English everywhere but a document, which writes
it in its language."""

from __future__ import annotations

import json
import pickle
import re
import string

import numpy as np

from metro.core.base.locale import Text, catalog, join, msg, translator


def test_a_message_is_its_english_text_everywhere_but_a_document():
    t = msg("{n} rounds; clause 7.5 asks for {rounds}", n=np.int64(3), rounds=10)
    assert t == "3 rounds; clause 7.5 asks for 10" and isinstance(t, str)
    assert json.dumps({"note": t}) == '{"note": "3 rounds; clause 7.5 asks for 10"}'
    assert f"{t}" == str(t) == "3 rounds; clause 7.5 asks for 10"
    assert translator("en").text(t) == "3 rounds; clause 7.5 asks for 10"
    assert translator("zh").text(t) == "3 轮；7.5 要求 10 轮"
    assert translator("zh+en").text(t) == "3 轮；7.5 要求 10 轮 3 rounds; clause 7.5 asks for 10"


def test_fields_that_are_messages_or_catalog_names_translate_too():
    inner = msg("sampling of a standard deviation of {n} rounds", n=10)
    t = msg("{source} ({note})", source=inner, note="round")  # a plain field the catalog holds
    assert t == "sampling of a standard deviation of 10 rounds (round)"
    assert translator("zh").text(t) == "10 轮标准偏差的抽样（轮次）"
    # the translator's own messages take a Text field, each language getting its own
    tr = translator("zh+en")
    assert tr("not reportable: {reason}", reason=msg("{n} rounds", n=2)) == \
        "不予报告：2 轮 not reportable: 2 rounds"
    # data (a file name, a device id) stay as they are
    assert translator("zh").text("run_1.csv") == "run_1.csv"


def test_a_join_translates_each_part():
    j = join("; ", [msg("{n} rounds", n=6), "SIM-TT-0001", "scale factor"])
    assert j == "6 rounds; SIM-TT-0001; scale factor"
    assert translator("zh").text(j) == "6 轮; SIM-TT-0001; 标度因数"
    assert translator("zh+en").text(j) == "6 轮 6 rounds; SIM-TT-0001; 标度因数 scale factor"


def test_a_message_pickles_and_survives_the_register_json():
    from metro.core.record.registering import decode_context, encode_context

    t = join("; ", [msg("fitted bias b = {b:.5g} °/s", b=np.float64(0.1017512)), "x"])
    back = pickle.loads(pickle.dumps(t))
    assert back == t and isinstance(back, Text) and back.parts[0].fields == {"b": 0.1017512}
    doc = json.loads(json.dumps(encode_context({"outcomes": [], "note": t})))
    again = decode_context(doc)["note"]
    assert again == t and translator("zh").text(again) == "拟合零偏 b = 0.10175 °/s; x"


def test_a_catalog_entry_with_wrong_places_falls_back_to_english_and_is_reported(monkeypatch):
    tr = translator("zh")
    monkeypatch.setitem(tr._zh, "{n} rounds", "{m} 轮")
    assert tr.text(msg("{n} rounds", n=3)) == "3 rounds" and "{n} rounds" in tr.missing


def _places(text: str) -> set[str]:
    return {f for _, f, _, _ in string.Formatter().parse(text) if f is not None}


def test_every_translation_has_the_places_of_its_message_id():
    """A msgstr must fill the same {fields} as its msgid (else a document would fall back to
    English)."""
    bad = {k: v for k, v in catalog("zh").items() if _places(k) != _places(v)}
    assert not bad, bad


def test_the_catalog_lacks_no_message_id_the_code_uses():
    """``tools/catalog.py`` finds every tr("…") and msg("…") in core and the loaded plugins'
    packages (plugins and instruments), and every metric name and item title the procedures
    declare."""
    import importlib.util
    from pathlib import Path

    path = Path(__file__).parents[3] / "tools" / "catalog.py"
    spec = importlib.util.spec_from_file_location("metro_catalog_tool", path)
    tool = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(tool)
    missing_messages, used_messages = tool.missing_messages, tool.used_messages

    pm = tool.plugin_manager()  # the packages scanned are found through the plugin manager
    scanned = set(tool.scanned_packages(pm))
    assert {"metro.core", "metro.instruments", "metro.plugins.gbt45570"} <= scanned
    used = used_messages(pm)
    assert "{n} rounds; clause 7.5 asks for {rounds}" in used  # a msg(…) of a plugin
    assert "scale factor" in used  # a metric name
    assert not missing_messages(), sorted(missing_messages())[:40]


def test_no_message_is_built_from_an_f_string():
    """msg(f"…") cannot be found by the extractor, nor translated: the code has none."""
    from pathlib import Path

    import metro.core

    root = Path(metro.core.__file__).resolve().parent.parent
    bad = [f"{p.relative_to(root)}" for p in root.rglob("*.py") if ".venv" not in p.parts
           and "tests" not in p.parts
           if re.search(r"\bmsg\(\s*f[\"']", p.read_text(encoding="utf-8"))]
    assert not bad, bad


def test_no_catalog_entry_claims_percent_formatting():
    """metro's messages are ``str.format`` templates ({fields}); an entry flagged ``python-format``
    makes ``msgfmt --check`` read "50 % 判定" as a broken %-directive and refuse the catalog — three
    such flags had crept in with hand-appended entries."""
    from importlib import resources

    path = resources.files("metro.core.base.locale") / "zh" / "LC_MESSAGES" / "metro.po"
    lines = path.read_text(encoding="utf-8").splitlines()
    flagged = [n for n, line in enumerate(lines, 1) if line.startswith("#,") and "python-format"
               in line]
    assert not flagged, f"metro.po lines {flagged}: drop the python-format flag"


def test_catalog_reader_gives_what_babel_gives():
    """The core install reads metro.po without Babel (core.locale.read_catalog); Babel's own
    reader (in the test extra) must give the same {msgid: msgstr} on the shipped catalog and on
    entries that test the edges: fuzzy, empty, plural, context, obsolete, continued and escaped
    strings."""
    import io
    from importlib import resources

    from babel.messages.pofile import read_po

    from metro.core.base.locale import read_catalog

    def babel_map(text: str) -> dict[str, str]:
        cat = read_po(io.StringIO(text))
        return {m.id: m.string for m in cat if m.id and isinstance(m.id, str) and m.string
                and not m.fuzzy and not m.context}

    shipped = (resources.files("metro.core.base.locale") / "zh" / "LC_MESSAGES"
               / "metro.po").read_text(encoding="utf-8")
    assert read_catalog(shipped) == babel_map(shipped)
    assert len(read_catalog(shipped)) > 1000
    edges = "\n".join([
        'msgid ""', 'msgstr ""', '"Content-Type: text/plain; charset=UTF-8\\n"', "",
        'msgid "plain"', 'msgstr "平"', "",
        "#, fuzzy", 'msgid "fuzzy one"', 'msgstr "模糊"', "",
        'msgid "empty"', 'msgstr ""', "",
        'msgid "continued "', '"over lines"', 'msgstr "续"', '"行"', "",
        'msgid "say \\"q\\"\\n\\ttab"', 'msgstr "引\\"号\\"\\n"', "",
        'msgctxt "ctx"', 'msgid "in context"', 'msgstr "上下文"', "",
        'msgid "one"', 'msgid_plural "many"', 'msgstr[0] "一"', "",
        '#~ msgid "obsolete"', '#~ msgstr "废"', "",
        "# a translator's comment", "#: core/x.py:1", 'msgid "after comments"', 'msgstr "注释后"',
        ""])
    assert read_catalog(edges) == babel_map(edges) == {
        "plain": "平", "continued over lines": "续行", 'say "q"\n\ttab': '引"号"\n',
        "after comments": "注释后"}

"""A plugin ships its own message catalog (issue 30, point 5): ``locale/zh/LC_MESSAGES/<name>.po``
in its package, found by the plugin manager among the loaded plugins' packages — no entry point.
A note the plugin makes then prints in Chinese in a zh+en document; metro's own catalog keeps
its translations."""

from __future__ import annotations

import importlib
import sys
import textwrap

import pytest
from metro.core.base import locale
from metro.core.base.locale import catalog, translator
from metro.core.run.plugin_manager import MetroPluginManager

PLUGIN = '''
from metro.api import Metric, Outcome, Procedure, Q_, Result, hookimpl, msg


class ToyCount(Procedure):
    """Toy item T.1: how many times the toy's output was read."""

    standard = "toycat"
    item = "T.1"
    title = "Toy count"
    clause = "T.1"
    metrics = (Metric("N_read", "toy read count", "N", "1", "T.1", "T-1"),)
    requires = ()

    def sequence(self, options):
        return []

    def evaluate(self, campaign, ctx):
        note = msg("the toy's output was read {n} times", n=3)
        r = Result(self.metrics[0], Q_(3.0, "1"), Q_(0.0, "1"), note=note)
        return Outcome(self.standard, self.item, self.title, self.clause, [r], warnings=[note])


@hookimpl
def metro_register_standards(registrar):
    registrar.add_standard("toycat", "Toy catalog standard", designation="TOY-1")
    registrar.add_procedure(ToyCount)
'''

PO = '''
msgid ""
msgstr ""
"Content-Type: text/plain; charset=UTF-8\\n"

msgid "the toy's output was read {n} times"
msgstr "玩具输出读取了 {n} 次"

msgid "Report No."
msgstr "不是 metro 的译文"
'''


@pytest.fixture
def toycat(tmp_path, monkeypatch):
    """The plugin package ``toycat`` with its catalog, importable from ``tmp_path``; the catalogs
    added while the test runs are dropped after it."""
    pkg = tmp_path / "toycat"
    (pkg / "locale" / "zh" / "LC_MESSAGES").mkdir(parents=True)
    (pkg / "__init__.py").write_text(textwrap.dedent(PLUGIN), encoding="utf-8")
    (pkg / "locale" / "zh" / "LC_MESSAGES" / "toycat.po").write_text(PO, encoding="utf-8")
    monkeypatch.syspath_prepend(str(tmp_path))
    monkeypatch.setattr(locale, "_FOLDERS", list(locale.catalog_folders()))
    monkeypatch.delitem(sys.modules, "toycat", raising=False)
    mod = importlib.import_module("toycat")
    yield mod
    sys.modules.pop("toycat", None)


def _pm(mod):
    pm = MetroPluginManager().load(autoload=False)
    pm.add_plugin(mod, "toycat")
    pm.register_all()
    return pm


def test_the_plugin_manager_finds_a_plugins_catalog_in_its_package(toycat, tmp_path):
    pm = _pm(toycat)
    assert pm.plugin_packages()["toycat"] == "toycat"
    assert pm.plugin_packages()["gbt45570"] == "metro.plugins.gbt45570"
    folders = pm.catalog_folders()
    assert set(folders) == {"toycat"}  # the built-in standards' texts are in metro's catalog
    assert str(folders["toycat"]) == str(tmp_path / "toycat" / "locale")


def test_a_plugins_note_prints_in_chinese_in_a_zh_en_document(toycat):
    pm = _pm(toycat)
    outcome = pm.procedure("toycat", "T.1")().evaluate(None, None)
    (note,) = outcome.warnings
    tr = translator("zh+en")
    assert tr.text(note) == "玩具输出读取了 3 次 the toy's output was read 3 times"
    assert tr.text(outcome.results[0].note) == tr.text(note) and not tr.missing
    assert translator("zh").text(note) == "玩具输出读取了 3 次"
    assert translator("en").text(note) == "the toy's output was read 3 times"


def test_metros_own_translation_is_kept(toycat):
    _pm(toycat)
    assert translator("zh")("Report No.") == catalog("zh")["Report No."] != "不是 metro 的译文"


def test_a_plugin_outside_a_package_has_no_catalog(toycat, monkeypatch):
    """A top-level module or an object of one is no package: no catalog, no error; an object of a
    class of the package gives the package."""
    import types

    loose = types.ModuleType("loose_plugin")
    monkeypatch.setitem(sys.modules, "loose_plugin", loose)
    pm = MetroPluginManager().load(autoload=False)
    pm.add_plugin(loose, "loose")
    pm.add_plugin(toycat.ToyCount(), "toy-object")  # an object: its class's module's package
    assert "loose" not in pm.plugin_packages()
    assert pm.plugin_packages()["toy-object"] == "toycat"
    assert set(pm.catalog_folders()) == {"toy-object"}

"""The words of the web pages: every label a template uses exists in Chinese and English (and is
not a name a dict already has: ``t.items`` would be the method), and the language a request gets."""

from __future__ import annotations

import re
from pathlib import Path

from metro.core.web import i18n

TEMPLATES = Path(i18n.__file__).parent / "templates"


def test_every_label_a_template_uses_exists_in_both_languages():
    used = set()
    for page in TEMPLATES.glob("*.html"):
        used |= set(re.findall(r"\bt\.(\w+)", page.read_text(encoding="utf-8")))
    assert used, "no labels found"
    assert used <= set(i18n.WORDS), used - set(i18n.WORDS)
    assert not set(i18n.WORDS) & set(dir(dict)), set(i18n.WORDS) & set(dir(dict))
    for key, (zh, en) in i18n.WORDS.items():
        assert zh and en and zh != en or key in {"dcc"}, key
        # the same placeholders in both languages
        assert re.findall(r"{\w+}", zh) == re.findall(r"{\w+}", en), key


def test_the_language_a_request_gets():
    assert i18n.default_lang("zh+en") == "zh" and i18n.default_lang("en") == "en"
    assert i18n.default_lang(None) == "zh"
    assert i18n.pick_lang({"lang": "en"}, {i18n.COOKIE: "zh"}, "zh") == "en"
    assert i18n.pick_lang({"lang": "fr"}, {i18n.COOKIE: "en"}, "zh") == "en"
    assert i18n.pick_lang({}, {i18n.COOKIE: "xx"}, "zh") == "zh"

"""Notes and warnings stated once, naming where they apply (metro.core.documents.notes, issue 13
follow-up).

A JJF 2003 certificate of 7.2.1–7.2.3 on a drifting MIMU (simulated class mems-warmup, seed 3)
printed its notes block over 2⅓ pages (13 pages in all, zh+en): each item repeated the three
per-gyro drift paragraphs, 7.2.1 and 7.2.3 the no-repeat warning, each g_ij its earth-rate
sentence and each result of one gyro its "corrected for the drift by …".  Here: the grouping by
hand-made cases, then the real certificate's notes block, read from the .docx.
"""

from __future__ import annotations

import pickle
import re

import pytest

from metro.core.base.locale import Index, Text, hint, index, join, msg, translator
from metro.core.documents.notes import group_notes, parts_of, where_label


def test_a_warning_several_items_share_is_stated_once_naming_them():
    w = msg("gyro {gyro}'s bias drifts by {d:.3g} °/s per hour", gyro="x", d=1.06)
    other = msg("no repeated calibrations")
    lines = group_notes([("7.2.1", "", w), ("7.2.1", "", other), ("7.2.2", "", w), ("7.2.3", "", w),
                         ("7.2.3", "", other)])
    assert lines == [("7.2.1, 7.2.2, 7.2.3", w), ("7.2.1, 7.2.3", other)]


def test_a_shared_part_of_a_note_is_its_own_line_the_rest_stays_with_its_result():
    corr = msg("corrected for the gyro bias drift during the campaign by {delta:.3g}{unit} (from "
               "the recording times)", delta=-1.7e-4, unit="")
    fit = {s: msg("fitted bias b = {b:.5g} °/s", b=b) for s, b
           in (("K_gxx", -0.34072), ("K_gxy", -0.2817))}
    entries = [("7.2.1", "K_gxx", join("; ", [fit["K_gxx"], corr])),
               ("7.2.3", "K_gxx", join("; ", [fit["K_gxx"], corr])),
               ("7.2.3", "K_gxy", join("; ", [fit["K_gxy"], corr]))]
    lines = [(w, str(t)) for w, t in group_notes(entries)]
    assert lines == [("K_gxx (7.2.1, 7.2.3)", str(fit["K_gxx"])),
                     ("K_gxx (7.2.1, 7.2.3); K_gxy (7.2.3)", str(corr)),
                     # what only one result says: its item's line
                     ("7.2.3", "K_gxy: fitted bias b = -0.2817 °/s")]
    # the texts said once stay on their item's line, a result's parts together, as its note has them
    own = group_notes([("D.6.3", "ΔB_V12", join("; ", [msg("eq. ({eq})", eq="D.47"),
                                                       msg("largest at {T} °C", T=60)])),
                       ("D.6.3", "ΔB_V13", msg("eq. ({eq})", eq="D.48")),
                       ("D.6.3", "", msg("no repeats"))])
    assert [(w, str(t)) for w, t in own] == [
        ("D.6.3", "ΔB_V12: eq. (D.47); largest at 60 °C; ΔB_V13: eq. (D.48); no repeats")
    ]
    # two results of one symbol in one item (three supplies' U) saying the same: once
    u = [("5.2.6", "U", join("; ", [msg("nominal {v} V", v=v), msg("at the connector")])) for v
         in (5, 15)]
    assert [(w, str(t)) for w, t in group_notes(u)] == [("5.2.6",
                                                         "U: nominal 5 V; U: nominal 15 V"),
                                                        ("U (5.2.6)", "at the connector")]


def _earth(r, c):
    return msg("earth rate included: eq. (7) puts the cross-coupling K_g{r}{c} × Ω_e·sin φ "
               "({v:.3g} (°/s)/gn at φ = {lat:g}°) into g_{r}{c}{hint}", r=index(r), c=index(c),
               v=0.00268, lat=39.98, hint=hint("; option earth_rate = yes removes it"))


def test_a_sentence_differing_only_in_its_indices_is_stated_once_in_index_form():
    pairs = [("x", "y"), ("x", "z"), ("y", "x"), ("y", "z"), ("z", "x"), ("z", "y")]
    lines = group_notes([("7.2.2", f"g_{r}{c}", _earth(r, c)) for r, c in pairs])
    assert len(lines) == 1
    where, text = lines[0]
    assert where == "g_xy, g_xz, g_yx, g_yz, g_zx, g_zy (7.2.2)"
    assert "K_gij × Ω_e·sin φ (0.00268 (°/s)/gn at φ = 39.98°) into g_ij" in str(text)
    # in Chinese too: the catalog's sentence with the same index letters
    zh = translator("zh").text(text)
    assert "K_gij" in zh and "g_ij" in zh and "0.00268" in zh
    # an index the same in every result keeps its value: g_xz, g_yz → K_giz
    (_, two), = group_notes([("7.2.2", "g_xz", _earth("x", "z")),
                             ("7.2.2", "g_yz", _earth("y", "z"))])
    assert "K_giz" in str(two) and "g_iz" in str(two)
    # one result alone: its own sentence, indices as given; other numbers: not merged
    assert [(w, str(t)) for w, t in group_notes([("7.2.2", "g_xy", _earth("x", "y"))])] == \
        [("7.2.2", f"g_xy: {_earth('x', 'y')}")]
    other = msg("earth rate included: eq. (7) puts the cross-coupling K_g{r}{c} × Ω_e·sin φ "
                "({v:.3g} (°/s)/gn at φ = {lat:g}°) into g_{r}{c}{hint}", r=index("x"),
                c=index("z"),
                v=0.00275, lat=45.0, hint=hint("; option earth_rate = yes removes it"))
    (_, both), = group_notes([("7.2.2", "g_xy", _earth("x", "y")), ("7.2.2", "g_xz", other)])
    assert str(both) == f"g_xy: {_earth('x', 'y')}; g_xz: {other}"


def test_an_index_field_survives_the_register_and_pickling():
    t = _earth("x", "y")
    assert str(t) == str(Text.decode(t.encode())) and isinstance(Text.decode(t.encode()).fields[
        "r"], Index)
    assert isinstance(pickle.loads(pickle.dumps(t)).fields["c"], Index)
    assert isinstance(t.map(str.upper).fields["r"], Index)


def test_labels():
    assert where_label([("7.2.1", ""), ("7.2.2", "B_gx"),
                        ("7.2.2", "B_gy")]) == "7.2.1; B_gx, B_gy (7.2.2)"
    assert parts_of(join("; ", [msg("a"), join("; ", [msg("b"), ""]),
                                join(": ", [msg("c"), msg("d")])])) == \
        ["a", "b", "c: d"]


# ---------------------------------------------------------------------------------------------
# The real certificate: JJF 2003 7.2.1–7.2.3 on a MIMU still warming up
# ---------------------------------------------------------------------------------------------

class _Lines:
    """Stands for the document builder: keeps the lines :func:`notes_section` writes."""

    def __init__(self, lang: str):
        self.tr = translator(lang)
        self.lines: list[str] = []

    def bullets(self, lines, size=None):
        self.lines.extend(self.tr.text(x) for x in lines)

    def para(self, text, **kw):
        self.lines.append(text)


@pytest.fixture(scope="module")
def warmup():
    from metro.core.documents.document import notes_section
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.documents.report import build_context
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "jjf2003", ["7.2.1", "7.2.2", "7.2.3"],
                    station_options={"device_class": "mems-warmup", "seed": 3})
    ctx = build_context(rec, extend=pm.extend_report_context, lang="en")
    doc = _Lines("en")
    notes_section(doc, ctx)  # as the JJF 2003 certificate calls it
    return rec, doc.lines


def test_certificate_notes_state_each_text_once_and_lose_none(warmup):
    rec, lines = warmup
    # every distinct warning, and every distinct part of a result note, of the run ...
    texts: dict[str, list[tuple[str, str]]] = {}
    en = translator("en").text  # as the document prints it (a terminal hint left out)
    for o in rec.outcomes:
        for w in o.warnings:
            texts.setdefault(en(w), []).append((o.item, ""))
        for r in o.results:
            for p in parts_of(r.note):
                texts.setdefault(en(p), []).append((o.item, r.metric.symbol))
    assert any(len(where) == 3 for where in texts.values())  # the drift paragraphs: one per item
    earth = re.compile(r"K_g([xyz])([xyz])|g_([xyz])([xyz])")

    def index_form(m):
        i, j = (m.group(1), m.group(2)) if m.group(1) else (m.group(3), m.group(4))
        return ("K_g" if m.group(1) else "g_") + ("ii" if i == j else "ij")

    block = "\n".join(lines)
    for text, where in texts.items():
        # ... is in the block once: as it is, or (a sentence on several results differing in their
        # indices only) once in index form
        generic = earth.sub(index_form, text)
        found = [t for t in (text, generic) if block.count(t) == 1]
        assert found and block.count(text) + (block.count(generic) if generic != text
                                              else 0) == 1, text
        line = next(ln for ln in lines if found[0] in ln)
        label = line[:line.index(found[0])]
        for item, sym in where:  # naming every result and item it applies to
            assert item in label and sym in label, (text, label, item, sym)
    # the drift paragraph of each gyro once (it was in each item: 3 times), 7.2.1–7.2.3 named
    drift = [ln for ln in lines if "bias drifts by" in ln]
    assert len(drift) == 3 and all(ln.startswith("7.2.1, 7.2.2, 7.2.3: gyro ") for ln in drift)
    # the nine g earth-rate sentences: two lines, diagonal and cross-coupling
    g = [ln for ln in lines if "earth rate included" in ln]
    assert [ln.split(" (7.2.2)")[0] for ln in g] == [
        "g_xx, g_yy, g_zz",
        "g_xy, g_xz, g_yx, g_yz, g_zx, g_zy",
    ]
    # 52 lines before the grouping (2⅓ pages of the zh+en certificate), each text once now: 20
    assert len(lines) <= 20, len(lines)

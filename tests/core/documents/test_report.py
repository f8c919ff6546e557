"""metro.core.documents.report (context + Word rendering), metro.core.documents.plots and the
template generator."""

from __future__ import annotations

import datetime as dt
import io
import subprocess
import sys
import warnings
import zipfile
from pathlib import Path

import docx
import pytest

from metro.core.documents import context, plots, report
from metro.core.base import formatting
from metro.core.base.atomic import TMP_MARKER
from metro.core.uncertainty.budget import BudgetRow, Coverage, UncertaintyBudget
from metro.core.model.campaign import Calibration, Campaign, DeviceUnderTest, Equipment
from metro.core.model.results import Metric, Outcome, PlotSpec, Result, TableSpec
from metro.core.model.provenance import RunRecord
from metro.core.base.units import Q_

REPORT_NO = "MTR-20250301-101500-0A1B2C"
SHA = "3f" * 32
DESIGNATIONS = {"gbt45570": "GB/T 45570—2025"}


def make_record(*, simulated: bool = False, with_plot: bool = True) -> RunRecord:
    device = DeviceUnderTest(
        id="DUT-42", model="FOG-300", serial="S/N 0042", manufacturer="Acme Inertial",
        properties={"scale_factor": Q_(0.8, "P/arcsec")},
        technology="fibre", application="aerospace", output="pulse",
    )
    equipment = [
        Equipment(id="CNT-1", model="53230A", manufacturer="Keysight", serial="MY555",
                  role="counter",
                  calibration=Calibration("CERT-2023-0117", Q_(1e-7, ""), k=2.0,
                                          due=dt.date(2024, 6, 30))),
        Equipment(id="PLAT-1", model="granite table", role="platform",
                  calibration=Calibration("CERT-2025-0009", Q_(2.0, "arcsec"),
                                          distribution="uniform",
                                          due=dt.date(2030, 1, 1))),
    ]
    campaign = Campaign(
        id="CAMP-7", device=device, equipment=equipment,
        environment={"temperature": Q_(20.0, "degC"), "humidity": Q_(45.0, "percent")},
        site={"latitude": Q_(39.95, "deg")},
        segments=[],
        source="simulated station" if simulated else "/lab/camp7/manifest.toml",
        simulated=simulated,
        truth={"angle random walk": Q_(0.0012, "deg/hour**0.5"), "seed": 7} if simulated else {},
    )
    metric = Metric("RWC", "Random walk coefficient", "RWC", "deg/hour**0.5", "D.5.6", "D.45")
    rows = [
        BudgetRow.type_a("Fit of B_s(τ_k) over the levels", "u(α₁)", Q_(3.3e-5, "deg/hour**0.5"),
                         12),
        BudgetRow.type_b("Counter time base", "u(T)", Q_(1e-7, ""), distribution="normal", k=2,
                         sensitivity=Q_(0.0012, "deg/hour**0.5")),
        BudgetRow.type_b("Platform levelness", "u(θ)", Q_(2.0, "arcsec"),
                         sensitivity=Q_(1e-6, "deg/hour**0.5/arcsec")),
    ]
    budget = UncertaintyBudget("RWC", "deg/hour**0.5", rows, coverage=Coverage.fixed(2.0))
    result = Result(metric, Q_(0.00123456, "deg/hour**0.5"), budget.combined, budget)
    plot = PlotSpec(
        "bs_tau", "B_s(τ_k) and the fit", "τ_k (s)", "B_s (°/h)",
        [
            {"label": "B_s(τ_k)", "x": [1, 10, 100], "y": [0.1, 0.03, 0.01],
             "yerr": [0.01, 0.003, 0.001],
             "style": "o"},
            {"label": "fit √(α₀ + α₁/τ)", "x": [1, 10, 100], "y": [0.1, 0.032, 0.01], "style": "-"},
            {"label": "ARW term", "x": [1, 10, 100], "y": [0.09, 0.03, 0.009], "style": "--"},
        ],
        logx=True, logy=True,
    )
    table = TableSpec("levels", "B_s(τ_k) per level", ["k", "τ_k (s)", "B_s (°/h)"],
                      [[1, "10", "0.031"], [2, "100", "0.0101"]])
    outcome = Outcome(
        "gbt45570", "D.5.6", "Angle random walk", "D.5.6", [result],
        plots=[plot] if with_plot else [], tables=[table],
        warnings=["the record is shorter than the standard asks"], segments=["static-1"],
    )
    return RunRecord(
        REPORT_NO, dt.datetime(2025, 3, 1, 10, 15, tzinfo=dt.timezone.utc), campaign, [outcome],
        software={"metro": "0.1.0", "numpy": "2.0"}, plugins={"gbt45570": "metro 0.1.0"},
        data_files=[("/lab/camp7/static-1.csv", SHA)], simulated=simulated,
    )


def docx_text(path: Path, raw: bool = False) -> str:
    """All text of a .docx: body paragraphs, table cells, headers and footers (no-break spaces
    as spaces unless ``raw``)."""
    d = docx.Document(str(path))
    parts = [p.text for p in d.paragraphs]
    for t in d.tables:
        for row in t.rows:
            parts.extend(c.text for c in row.cells)
    for s in d.sections:
        parts.extend(p.text for p in s.header.paragraphs)
        parts.extend(p.text for p in s.footer.paragraphs)
    text = "\n".join(parts)
    return text if raw else text.replace("\u00a0", " ").replace("\u2060", "")


# --------------------------------------------------------------------------------------
# report_context
# --------------------------------------------------------------------------------------


def test_context_has_every_section():
    ctx = context.report_context(make_record(), designations=DESIGNATIONS)
    for key in ("report_number", "created", "title", "device", "environment", "site", "equipment",
                "outcomes", "provenance", "simulated", "truth"):
        assert key in ctx
    assert ctx["report_number"] == REPORT_NO
    assert ctx["created"] == "2025-03-01 10:15 UTC"
    assert ctx["title"] == "Test report — GB/T 45570—2025 D.5.6"
    assert ctx["device"]["serial"] == "S/N 0042"
    assert ctx["device"]["technology"] == "fibre"
    assert {"name": "Temperature", "value": "20 °C"} in ctx["environment"]
    assert ctx["latitude"] == "39.95 °"
    assert ctx["simulated"] is False and ctx["simulated_banner"] == "" and ctx["truth"] == []
    prov = ctx["provenance"]
    assert prov["data_files"] == [{"file": "/lab/camp7/static-1.csv", "sha256": SHA}]
    assert prov["source"] == "/lab/camp7/manifest.toml"
    assert {"name": "gbt45570", "version": "metro 0.1.0"} in prov["plugins"]


def test_context_without_designations_uses_the_standard_id():
    ctx = context.report_context(make_record())
    assert ctx["title"] == "Test report — gbt45570 D.5.6"


def test_context_numbers_follow_the_model():
    rec = make_record()
    res = rec.outcomes[0].results[0]
    ctx = context.report_context(rec)
    (o,) = ctx["outcomes"]
    assert o["number"] == "5.1" and o["clause"] == "D.5.6"
    (r,) = o["results"]
    assert (r["value"], r["U"]) == res.reported()
    assert r["unit"] == "°/√h" and r["k"] == "2" and r["reference"] == "D.5.6, D.45"
    (b,) = o["budgets"]
    d = res.budget.as_dict()
    assert b["U"] == d["U_reported"]
    assert [row["source"] for row in b["rows"]] == [row.source for row in res.budget.rows]
    assert [row["type"] for row in b["rows"]] == ["A", "B", "B"]
    assert [row["divisor"] for row in b["rows"]] == ["1", "2", "√3"]
    assert [row["dof"] for row in b["rows"]] == ["12", "∞", "∞"]
    assert b["rows"][2]["value"] == "2 ″"
    assert b["u_c"] == formatting.fmt_num(d["u_c"])
    assert o["tables"][0]["header"] == ["k", "τ_k (s)", "B_s (°/h)"]
    assert o["tables"][0]["rows"][0] == ["1", "10", "0.031"]
    assert o["plots"][0]["number"] == 1 and o["plots"][0]["image"] is None
    assert o["warnings"] == ["the record is shorter than the standard asks"]


def test_context_equipment_status():
    eq = {e["id"]: e for e in context.report_context(make_record())["equipment"]}
    assert eq["CNT-1"]["certificate"] == "CERT-2023-0117"
    assert eq["CNT-1"]["expired"] is True
    assert eq["CNT-1"]["status"].startswith("EXPIRED")
    assert eq["CNT-1"]["U"] == "1×10⁻⁷ (k = 2)"
    assert eq["CNT-1"]["description"] == "Keysight 53230A (s/n MY555)"
    assert eq["PLAT-1"]["status"] == "valid until 2030-01-01"


def test_context_simulated_has_banner_and_truth():
    ctx = context.report_context(make_record(simulated=True))
    assert ctx["simulated"] is True
    assert "built-in simulated test station" in ctx["simulated_banner"]
    assert {"name": "angle random walk", "value": "0.0012 °/√h"} in ctx["truth"]


def test_context_strips_characters_xml_cannot_hold():
    rec = make_record()
    bad = Outcome("gbt45570", "D.5.6", "Angle\x0b random walk", "D.5.6", rec.outcomes[0].results,
                  warnings=["bell\x07 rang"])
    rec = RunRecord(REPORT_NO, rec.created, rec.campaign, [bad])
    (o,) = context.report_context(rec)["outcomes"]
    assert o["title"] == "Angle random walk" and o["warnings"] == ["bell rang"]


def test_fmt_num():
    assert formatting.fmt_num(0.000012345) == "1.234×10⁻⁵"
    assert formatting.fmt_num(123456.0) == "1.235×10⁵"
    assert formatting.fmt_num(0.5) == "0.5"
    assert formatting.fmt_num(3) == "3"
    assert formatting.fmt_num(None) == "—"
    assert formatting.fmt_num(float("inf")) == "∞"
    assert formatting.fmt_quantity(Q_(45.0, "percent")) == "45 %"


# --------------------------------------------------------------------------------------
# write_report
# --------------------------------------------------------------------------------------


@pytest.fixture(scope="module")
def simulated_docx(tmp_path_factory) -> Path:
    out = tmp_path_factory.mktemp("report") / "report.docx"
    assert report.write_report(out, make_record(simulated=True), designations=DESIGNATIONS) == out
    return out


def test_docx_contents(simulated_docx):
    text = docx_text(simulated_docx)
    assert "0.0012\u00a0°/√h" in docx_text(simulated_docx, raw=True)  # number and unit never split
    assert REPORT_NO in text
    assert SHA in text
    assert "CERT-2023-0117" in text
    assert "EXPIRED" in text
    # in the header, so on every page
    assert "SIMULATED — not a measurement of a real device" in text
    assert "0.0012 °/√h" in text  # the declared truth
    for source in ("Fit of Bs(τk) over the levels", "Counter time base", "Platform levelness"):
        assert source in text  # B_s printed as B with a subscript s
    assert "Bs(τk) per level" in text and "τk (s)" in text
    assert "The results relate only to the item tested" in text
    assert "{{" not in text and "{%" not in text and "_" not in text.replace("MTR-", "")


def test_docx_has_the_figure_and_page_fields(simulated_docx):
    with zipfile.ZipFile(simulated_docx) as z:
        names = z.namelist()
        assert any(n.startswith("word/media/") and n.endswith(".png") for n in names)
        headers = [z.read(n).decode("utf-8") for n in names if n.startswith("word/header")]
    assert any(REPORT_NO in h and "PAGE" in h and "NUMPAGES" in h for h in headers)
    d = docx.Document(str(simulated_docx))
    assert len(d.inline_shapes) == 1
    assert abs(d.inline_shapes[0].width.mm - 150) < 0.5
    assert d.core_properties.identifier == REPORT_NO


def test_real_campaign_has_no_banner(tmp_path):
    out = report.write_report(tmp_path / "r.docx", make_record(simulated=False, with_plot=False))
    text = docx_text(out)
    assert "simulated test station" not in text
    assert "/lab/camp7/manifest.toml" in text


def test_failure_while_rendering_leaves_nothing(tmp_path, monkeypatch):
    def broken(*a, **kw):
        raise RuntimeError("renderer broke")

    monkeypatch.setattr(plots, "png_bytes", broken)
    target = tmp_path / "report.docx"
    with pytest.raises(RuntimeError, match="renderer broke"):
        report.write_report(target, make_record())
    assert list(tmp_path.iterdir()) == []


def test_failure_while_saving_keeps_the_previous_report(tmp_path, monkeypatch):
    from metro.core.documents.document import DocumentBuilder

    target = tmp_path / "report.docx"
    target.write_bytes(b"previous report")

    def broken_save(self, filename, *a, **kw):
        Path(filename).write_bytes(b"half a zip")
        raise OSError("disk full")

    monkeypatch.setattr(DocumentBuilder, "save", broken_save)
    with pytest.raises(OSError, match="disk full"):
        report.write_report(target, make_record(with_plot=False))
    assert target.read_bytes() == b"previous report"
    assert [p.name for p in tmp_path.iterdir() if TMP_MARKER in p.name] == []


def test_bad_custom_template_is_a_metro_error(tmp_path):
    from metro.core.base.errors import MetroError

    bad = docx.Document()
    bad.add_paragraph("{{ report_number ")  # unterminated tag
    tpl = tmp_path / "bad.docx"
    bad.save(str(tpl))
    with pytest.raises(MetroError, match="bad.docx"):
        report.write_report(tmp_path / "out.docx", make_record(with_plot=False), template=tpl)
    assert not (tmp_path / "out.docx").exists()


def test_import_is_cheap():
    code = (
        "import sys, metro.core.documents.report, metro.core.documents.plots; "
        "print(sorted(m for m in ('docxtpl', 'docx', 'matplotlib', 'pint') if m in sys.modules))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert out.stdout.strip() == "[]"


# --------------------------------------------------------------------------------------
# plots and the template
# --------------------------------------------------------------------------------------


def test_render_png_with_unicode_labels(tmp_path):
    spec = PlotSpec("u", "σ(τ) — α₀ and √h", "τ (s)", "B (°/h), ARW (°/√h)",
                    [{"label": "α₀ ″", "x": Q_([1.0, 2.0, 4.0], "s"), "y": [3.0, 2.0, 1.0],
                      "yerr": 0.1, "style": "o"},
                     {"x": [1, 4], "y": [3, 1], "style": "--"}],
                    logx=True)
    with warnings.catch_warnings():
        warnings.simplefilter("error")  # a missing glyph is a warning in matplotlib
        out = plots.render_png(spec, tmp_path / "fig.png", dpi=60)
    assert out.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    assert [p.name for p in tmp_path.iterdir()] == ["fig.png"]


def test_cjk_figure_text_with_subscripts_keeps_its_glyphs(tmp_path, caplog):
    """A subscript in a Chinese figure text (JJF 2014 7.2.1's "残差 v_i（mV）") was turned into
    mathtext, which draws the whole string in its own font: every Chinese character printed as a box
    (seen on the rendered zh+en certificate, page 5). With CJK in the text the subscript is a
    Unicode one where it exists, else the text stays as written; English keeps mathtext."""
    import logging

    assert plots.plot_text("残差 v_i（mV）") == "残差 vᵢ（mV）"
    # no Unicode subscript for every letter: as written
    assert plots.plot_text("温度 T_{ref}") == "温度 T_{ref}"
    assert plots.plot_text("residual v_i (mV)") == "residual $\\mathregular{v_{i}}$ (mV)"
    spec = PlotSpec("r", "标度因数：式（3）拟合的残差 v_i", "输入角速率 Ω (°/s)", "残差 v_i（mV）",
                    [{"label": "v_i", "x": [1.0, 2.0], "y": [0.1, -0.1], "style": "o"}])
    with caplog.at_level(logging.WARNING, logger="matplotlib"):
        plots.render_png(spec, tmp_path / "zh.png", dpi=50)
    if len(plots.font_families()) > 1:  # a CJK font is installed (CI installs fonts-noto-cjk)
        assert not [r for r in caplog.records if "does not have a glyph"
                    in r.getMessage()], caplog.records[:2]


def test_render_png_rejects_mismatched_series(tmp_path):
    spec = PlotSpec("bad", "", "x", "y", [{"x": [1, 2], "y": [1, 2, 3]}])
    with pytest.raises(ValueError, match="series 0"):
        plots.render_png(spec, tmp_path / "bad.png")
    assert list(tmp_path.iterdir()) == []


def test_committed_template_is_what_the_generator_builds():
    """The docxtpl template a lab may start a custom template from (``--template``-style use of
    write_report(template=…)); metro's own documents are built by metro.core.documents.document."""
    from metro.core.documents.templates import make_templates

    buf = io.BytesIO()
    make_templates.build().save(buf)
    fresh = zipfile.ZipFile(io.BytesIO(make_templates._reproducible_zip(buf.getvalue())))
    committed = zipfile.ZipFile(io.BytesIO(report.default_template().read_bytes()))
    assert fresh.namelist() == committed.namelist()
    for name in fresh.namelist():
        assert fresh.read(name) == committed.read(name), f"{name} differs: re-run make_templates.py"


def test_metric_reference_names_the_equation_only_when_there_is_one():
    assert Metric("B0", "bias", "B₀", "deg/h", "D.5.1.3", "D.40").reference == "D.5.1.3 (D.40)"
    assert Metric("t_s", "set-up time", "t_s", "s", "6.2.7.7").reference == "6.2.7.7"


def test_generic_report_states_the_decision_rule_and_each_verdict(tmp_path):
    import attrs

    from metro.core.uncertainty import conformity as cf

    record = make_record(with_plot=False)
    specs = [cf.parse_limit("RWC", "<= 0.002 deg/hour**0.5", source="product spec FOG-300 rev B"),
             cf.parse_limit("B0", "|x| <= 0.5 deg/h", source="product spec FOG-300 rev B")]
    assessed = attrs.evolve(record, conformity=cf.assess(record.outcomes, specs, cf.GUARDED))
    text = docx_text(report.write_report(tmp_path / "judged.docx", assessed))
    assert cf.GUARDED.title in text and cf.GUARDED.statement in text
    assert "product spec FOG-300 rev B" in text and "≤ 0.002" in text
    verdict = assessed.conformity.verdicts[0]
    assert verdict.reason in text and verdict.status.value in text
    assert "B0" in text  # a limit with no result of this run is listed as not assessed
    assert "makes no statement of conformity" not in text
    # without a specification the report says it makes no statement, rather than leaving a gap
    plain = docx_text(report.write_report(tmp_path / "plain.docx", record))
    assert "makes no statement of conformity" in plain and cf.GUARDED.statement not in plain


def test_degrees_of_freedom_print_without_false_precision():
    from metro.core.base.formatting import fmt_dof

    assert [fmt_dof(x) for x in (None, float("inf"), 6.0, 34.27, 3308.4, 21776473.0)] == \
        ["∞", "∞", "6", "34.3", "3308", "2.2×10⁷"]


@pytest.mark.parametrize("standard, items, station_options", [
    ("gbt45570", ["D.1.1", "D.5.1", "D.5.2"], {"duration_scale": 0.1}),
    ("gbt45570", ["D.2.1"], {"duration_scale": 0.1}),
    ("jjf2014", ["7.2.1", "7.2.13"], {"duration_scale": 0.1}),
    ("jjf2003", ["7.2.1", "7.2.2"], {}),
    ("ogam", ["7.1", "7.4"], {}),
])
def test_every_standards_document_prints_no_code_artefacts(tmp_path, standard, items,
                                                           station_options):
    """Each standard's own report or certificate, rendered from a simulated run, holds no Python
    repr (a Jinja ``r.items`` on a dict once printed "<built-in method items of dict …>" in the
    GB/T typical-indices table), no unrendered tag, no None/NaN and no 1e-06-style number."""
    import re

    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.documents.report import write_report
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, standard, items, station_options=station_options)
    tpl = pm.template_for(standard)
    path = write_report(tmp_path / "doc.docx", rec, layout=tpl.layout,
                        extend=pm.extend_report_context)
    text = docx_text(path)
    for bad in ("object at 0x", "built-in method", "bound method", "{{", "}}", "{%", "%}",
                "Traceback"):
        assert bad not in text, f"{standard}: {bad!r} in the document"
    for word in (r"\bNone\b", r"\b[Nn]a[Nn]\b", r"\binf\b"):
        assert not re.search(word, text), re.search(r".{40}" + word + r".{10}", text)
    sci = r"(?<![0-9A-Za-z.])\d+(?:\.\d+)?[eE][+-]\d{1,3}\b"  # 1.4e-06 (hex digests carry no sign)
    assert not re.search(sci, text), re.search(r".{40}" + sci + r".{10}", text)
    if standard in ("gbt45570", "jjf2014"):  # documents that print the budgets print them whole
        d = docx.Document(str(path))
        budgets = [t for t in d.tables if "ui(y)" in " ".join(c.text for c in t.rows[0].cells)]
        assert budgets
        for t in budgets:
            head = [c.text for c in t.rows[0].cells]
            for col in ("Type", "distribution", "Value", "Divisor", "ci", "νi"):
                assert any(col in h for h in head), (standard, col)
            # type and distribution merged
            dist = next(i for i, h in enumerate(head) if "distribution" in h)
            # a budget's title and its u_c … U line span the table; the rows between give the
            # distribution in Chinese (zh+en: the names in both languages once, above the tables)
            rows = [r for r in t.rows[1:] if len({id(c._tc) for c in r.cells}) > 1]
            assert rows and all(re.fullmatch(r"[AB], (正态|均匀|三角|反正弦)", r.cells[dist].text)
                                for r in rows), \
                [r.cells[dist].text for r in rows]
            spans = [r.cells[0].text.replace("\xa0", " ") for r in t.rows[1:]
                     if len({id(c._tc) for c in r.cells}) == 1]
            assert spans and all("U = " in x or " — " in x for x in spans), spans
        assert re.search(r"分布 Distribution: 正态 normal",
                         text), "the distributions' names in both languages"


def test_pretty_powers_changes_free_standing_numbers_only():
    from metro.core.base.formatting import pretty_powers

    assert pretty_powers("band ≤ 1000 °/s: ±5e-06 (uniform); 2.5E+03 s; run-1e-5.csv; sha 0e0a; "
                         "x=-3e-07") == \
        "band ≤ 1000 °/s: ±5×10⁻⁶ (uniform); 2.5×10³ s; run-1e-5.csv; sha 0e0a; x=-3×10⁻⁷"


# --------------------------------------------------------------------------------------
# metro.core.documents.document: the one builder
# --------------------------------------------------------------------------------------


def test_symbols_get_real_subscripts_and_numbers_stay_whole():
    from metro.core.documents.text import NBSP, glue, one_notation, subscript_runs

    assert subscript_runs("K_l = 3, B_{s} and K_gxx") == [
        ("K", False), ("l", True), (" = 3, B", False), ("s", True), (" and K", False),
        ("gxx", True)]
    # names, options and files keep their underscores
    for text in ("rate_table", "t_startup", "min_blocks", "run_1.csv", "option max_rate",
                 "earth_rate", "dB_shock"):
        assert subscript_runs(text) == [(text, False)], text
    # after a Chinese character or a subscript digit, max/min with one letter, a braced subscript
    # (the rendered zh budgets printed 计数N_0, K₀₀ΔT_i, max_i and s_upper with their underscores)
    assert subscript_runs("计数N_0") == [("计数N", False), ("0", True)]
    assert subscript_runs("max_i |ΔK_i/(K₀₀ΔT_i)|") == [("max", False), ("i", True),
                                                        (" |ΔK", False), ("i", True),
                                                         ("/(K₀₀ΔT", False), ("i", True),
                                                        (")|", False)]
    assert subscript_runs("(s_{upper} − B_r)/2") == [("(s", False), ("upper", True),
                                                     (" − B", False), ("r", True),
                                                     (")/2", False)]
    assert glue("U = 1.2 ppm (k = 2)") == f"U{NBSP}={NBSP}1.2{NBSP}ppm (k{NBSP}={NBSP}2)"
    # one notation: a value below 0.001 as ×10ⁿ like its U, every digit kept
    assert one_notation("0.0006021 ± 6.6×10⁻⁶; 0.00010; 0.0012; -0.000305") == \
        "6.021×10⁻⁴ ± 6.6×10⁻⁶; 1.0×10⁻⁴; 0.0012; -3.05×10⁻⁴"


def test_column_widths_fit_the_longest_word_and_the_page():
    from metro.core.documents.text import TEXT_WIDTH_MM, column_widths, text_mm

    cols = [["Item", "D.1.1", "D.5.6"], ["Quantity", "scale factor nonlinearity Kn",
                                         "angle random walk"],
            ["Result", "3.292×10⁻⁵ °/h", "0.8000000 P/″"]]
    w = column_widths(cols, TEXT_WIDTH_MM, 8.5)
    assert sum(w) == pytest.approx(TEXT_WIDTH_MM)
    assert w[2] > text_mm("3.292×10⁻⁵", 8.5) + 2  # the longest number fits on one line
    assert w[0] < w[1]  # a short column stays narrow
    # cannot fit: the caller shrinks the font
    assert column_widths([["x" * 400]], TEXT_WIDTH_MM, 8.5) is None


def test_a_chinese_term_is_not_broken_one_character_per_line():
    """A zh budget table: the source column takes all the room it wants (prefer, share 1), and the
    "类型，分布" column kept only its widest single character (Chinese may break anywhere), so
    LibreOffice printed 类/型/，/分/布 one character per line. A run of Chinese up to six characters
    now counts as one word; a longer run gives the column at least four characters."""
    from metro.core.documents.text import CELL_MARGIN_MM, TEXT_WIDTH_MM, column_widths, text_mm

    source = (
        "两个零偏的分散性（分组平均值）（地球自转角速度、纬度和调平对两次记录相同，相互抵消）" * 3
    )
    cols = [["来源", source, source], ["类型，分布", "A, 正态", "B, 均匀"],
            ["量值", "0.008388 °/h", "2×10⁻⁶"]]
    w = column_widths(cols, TEXT_WIDTH_MM, 7, prefer=0, prefer_share=1.0)
    assert w[1] >= text_mm("类型，分布", 7, bold=True) + 2 * CELL_MARGIN_MM, w
    assert w[1] >= text_mm("B, 均匀", 7) + 2 * CELL_MARGIN_MM, w
    # a long Chinese name may wrap, but not narrower than four characters
    w = column_widths([["名称", "标度因数非线性度标度因数不对称度"], ["值", "some words " * 40]],
                      TEXT_WIDTH_MM, 7)
    assert w[0] >= text_mm("标度因数", 7) + 2 * CELL_MARGIN_MM, w


def test_every_table_declares_grid_widths_that_agree_with_its_cells(simulated_docx):
    """LibreOffice draws by w:tblGrid, Word by w:tcW: they must agree; the header row repeats on
    each page, no row splits across pages, headings keep with what follows."""
    from docx.oxml.ns import qn

    d = docx.Document(str(simulated_docx))
    assert d.tables
    for t in d.tables:
        grid = [int(g.get(qn("w:w"))) for g in t._tbl.tblGrid.findall(qn("w:gridCol"))]
        assert sum(grid) <= 170 / 25.4 * 1440 + 5
        for row in t.rows:
            cells, want, pos = [], [], 0
            # a cell spanning columns (a budget's title) is as wide as they are
            for tc in row._tr.tc_lst:
                span = tc.tcPr.find(qn("w:gridSpan"))
                n = 1 if span is None else int(span.get(qn("w:val")))
                cells.append(int(tc.tcPr.find(qn("w:tcW")).get(qn("w:w"))))
                want.append(sum(grid[pos:pos + n]))
                pos += n
            assert cells == want and pos == len(grid)
            assert row._tr.trPr.find(qn("w:cantSplit")) is not None
        # only label/value tables lack a header
        if t.rows[0]._tr.trPr.find(qn("w:tblHeader")) is None:
            assert len(t.columns) == 2
    heads = [p for p in d.paragraphs if p.style.name.startswith("Heading")]
    assert heads and all(p.paragraph_format.keep_with_next for p in heads)
    sec = d.sections[0]
    assert (round(sec.page_width.mm), round(sec.page_height.mm)) == (210, 297)


def test_every_document_string_is_in_the_catalog(tmp_path):
    """In zh, no label of any standard's document falls back to English: the catalog has them
    all."""
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    cases = [("gbt45570", ["D.1.1", "D.5.1"], {"duration_scale": 0.1}),
             ("jjf2014", ["7.2.13"], {"duration_scale": 0.1}),
             ("jjf2003", ["7.2.1"], {}), ("ogam", ["7.1", "7.4"], {})]
    missing = set()
    for standard, items, so in cases:
        rec = run_items(pm, standard, items, station_options=so)
        ctx = report.build_context(rec, extend=pm.extend_report_context)
        for layout in (pm.template_for(standard).layout, None):
            (tmp_path / f"{standard}-{layout}").mkdir()
            doc = report.build_document(ctx, tmp_path / f"{standard}-{layout}", layout=layout,
                                        lang="zh")
            missing |= doc.tr.missing
    assert not missing, sorted(missing)


def test_languages_and_an_unknown_one():
    from metro.core.base.errors import MetroError
    from metro.core.base.locale import translator

    assert translator("zh")("Report No.") == "报告编号"
    assert translator("en")("Report No.") == "Report No."
    assert translator("zh+en")("Report No.") == "报告编号 Report No."
    tr = translator("zh+en")
    assert tr("Recommended recalibration interval: {interval}", interval=tr.msg("1 year")) == \
        "建议复校时间间隔：1 年 Recommended recalibration interval: 1 year"
    with pytest.raises(MetroError, match="unknown document language 'fr'"):
        translator("fr")


def test_pdf_without_libreoffice_is_a_clear_error_and_writes_nothing(tmp_path, monkeypatch):
    import shutil as sh

    from metro.core.base.errors import MetroError

    monkeypatch.delenv("METRO_SOFFICE", raising=False)
    monkeypatch.setattr(sh, "which", lambda name: None)
    for target, kw in ((tmp_path / "r.pdf", {}), (tmp_path / "r.docx", {"pdf": True})):
        with pytest.raises(MetroError, match="LibreOffice"):
            report.write_report(target, make_record(with_plot=False), **kw)
    assert list(tmp_path.iterdir()) == []


def test_not_reportable_result_says_so_in_its_row(tmp_path):
    import attrs

    rec = make_record(with_plot=False)
    (o,) = rec.outcomes
    (r,) = o.results
    bad = attrs.evolve(r, reportable=False, reason="the D.45 fit is ill-conditioned (χ²/ν = 31)")
    rec = attrs.evolve(rec, outcomes=[attrs.evolve(o, results=[bad])])
    text = docx_text(report.write_report(tmp_path / "r.docx", rec, lang="en"))
    assert "not reportable: the D.45 fit is ill-conditioned (χ²/ν = 31)" in text
    assert "0.00123" not in text


def _png(width: int = 8, height: int = 4) -> bytes:
    """A small valid PNG (red), written by hand: signature, IHDR, IDAT, IEND."""
    import struct
    import zlib

    def chunk(kind: bytes, data: bytes) -> bytes:
        return struct.pack(">I",
                           len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data)
                                                                  & 0xFFFFFFFF)

    raw = b"".join(b"\x00" + b"\xff\x00\x00" * width for _ in range(height))
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 2, 0, 0,
                                                              0))
            + chunk(b"IDAT", zlib.compress(raw)) + chunk(b"IEND", b""))


def test_lab_logo_is_drawn_above_the_title(tmp_path, capsys):
    """A lab profile's ``logo`` is drawn above the title of page 1 (the image part is in the
    .docx, byte for byte); the context keeps it, so the register writes the same document again
    without the file; no profile, no logo."""
    import zipfile

    from metro.core.record import lab as labmod
    from metro.core.cli.app import main
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.record.registering import with_lab
    from metro.core.documents.report import build_context, render_context, write_report
    from metro.core.run.runner import run_items

    profile = tmp_path / "lab.toml"
    assert main(["lab", "init", str(profile)]) == 0
    capsys.readouterr()
    logo = _png()
    (tmp_path / "logo.png").write_bytes(logo)
    profile.write_text(
        profile.read_text(encoding="utf-8").replace('# logo = "logo.png"', 'logo = "logo.png"'),
        encoding="utf-8",
    )
    lab = labmod.load_lab(profile)
    assert lab.logo == tmp_path / "logo.png"
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "jjf2014", ["7.2.13"], station_options={"duration_scale": 0.1})
    layout = pm.template_for("jjf2014").layout

    def drawn(path) -> list[bytes]:
        d = docx.Document(str(path))
        first = next(p for p in d.paragraphs if p.text.strip() or p._p.xpath(".//w:drawing"))
        rids = first._p.xpath(".//a:blip/@r:embed")
        return [d.part.related_parts[r].blob for r in rids]

    with_logo = write_report(tmp_path / "a.docx", with_lab(rec, lab), layout=layout,
                             extend=pm.extend_report_context)
    assert drawn(with_logo) == [logo]
    with zipfile.ZipFile(with_logo) as z:
        assert any(z.read(n) == logo for n in z.namelist() if n.startswith("word/media/"))
    ctx = build_context(with_lab(rec, lab), extend=pm.extend_report_context)
    (tmp_path / "logo.png").unlink()  # written again from the context alone
    again = render_context(tmp_path / "b.docx", ctx, layout=layout)
    assert drawn(again) == [logo]
    plain = write_report(tmp_path / "c.docx", rec, layout=layout, extend=pm.extend_report_context)
    assert drawn(plain) == []
    # the register's statement goes under the logo, the logo stays at the top of page 1
    ctx["register"] = {"registered": False, "notices": ["NOT REGISTERED notice"]}
    d = docx.Document(str(render_context(tmp_path / "d.docx", ctx, layout=layout)))
    assert d.paragraphs[0]._p.xpath(".//w:drawing") and d.paragraphs[
        1].text == "NOT REGISTERED notice"


def test_zh_en_text_without_chinese_is_printed_once():
    """In zh+en a message whose Chinese pattern only changes punctuation around English data
    (``{source}（{note}）``) is the English sentence once, not twice; one with Chinese in it keeps
    both languages."""
    from metro.core.base.locale import msg, translator

    tr = translator("zh+en")
    text = tr.text(msg("{source} ({note})", source="scatter of the two biases",
                       note="the terms cancel"))
    assert text == "scatter of the two biases (the terms cancel)"
    assert tr.text(msg("not performed")) == "未检测 not performed"


def test_an_exact_result_says_so_instead_of_u_zero_with_a_k():
    """A count or a declared value (U = 0) prints 'no uncertainty (exact)', not 'U = 0 °C (k =
    2)'."""
    from metro.core.documents.document import DocumentBuilder, result_cells
    from metro.core.base.locale import translator

    doc = DocumentBuilder(number="N", title="T", tr=translator("en"))
    exact = {"value_unit": "-55 °C", "U_unit": "0 °C", "U": "0", "k": "2", "reportable": True}
    assert result_cells(doc, exact) == ("-55 °C", "no uncertainty (exact)")
    measured = dict(exact, U_unit="0.30 °C", U="0.30")
    assert result_cells(doc, measured) == ("-55 °C", "U = 0.30 °C (k = 2)")


def test_budgets_annex_says_a_shared_note_once_and_groups_exact_budgets(tmp_path):
    """GB/T type test (--all), zh+en: a row note several budget rows share ("the two biases'
    rounding errors do not cancel in the difference", in each environmental test's ΔB₀ budget)
    is printed once, numbered, and the rows cite its number; the exact budgets sharing one reason
    ("no uncertainty declared by the test lab") say it once; one table per item, each budget a
    title row, its rows and its u_c … U row (before: a table, a header and a paragraph per budget,
    the notes in full in every row)."""
    import re

    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.documents.report import write_report
    from metro.core.run.runner import run_items

    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "gbt45570", [], run_all=True)
    path = write_report(tmp_path / "all.docx", rec, layout=pm.template_for("gbt45570").layout,
                        extend=pm.extend_report_context)
    d = docx.Document(str(path))
    cells = [c.text for t in d.tables for row in t.rows for c
             in {id(c._tc): c for c in row.cells}.values()]
    paras = [p.text for p in d.paragraphs]
    note = "the two biases' rounding errors do not cancel in the difference"
    rows_with = [c for c in cells if "quantization of the output" in c]
    assert len(rows_with) > 4 and not [c for c in rows_with if note in c], rows_with[:3]
    (listed,) = [p for p in paras if note in p]
    k = re.match(r"\[(\d+)\]", listed).group(1)
    assert all(f"[{k}]" in c for c in rows_with if "B₀ before" in c or "B₀ after" in c)
    said = [p for p in paras if "no uncertainty declared by the test lab" in p]
    assert len(said) == 1 and said[0].count("no uncertainty declared by the test lab") == 1, said
    budgets = sum(1 for o in rec.outcomes for r in o.results if r.budget is not None
                  and r.budget.combined.magnitude > 0)
    tables = [t for t in d.tables if any("Divisor" in c.text for c in t.rows[0].cells)]
    assert len(tables) == len({o.item for o in rec.outcomes
                               if any(r.budget is not None and r.budget.combined.magnitude > 0
                                      for r in o.results)})
    assert len(tables) < budgets


def test_a_budget_title_leaves_out_a_code_key_measurand():
    """JJF 2014's budgets were titled 'start-up time t_s (t_startup)', 'bias change after shock ΔB_i
    (dB_shock)': the measurand was the result's code key."""
    from types import SimpleNamespace as N

    from metro.core.documents.context import budget_title as _budget_title

    assert str(_budget_title(N(name="start-up time", symbol="t_s", key="t_startup"),
                             "t_startup")) == "start-up time t_s"
    assert "dB_shock" not in str(_budget_title(N(name="bias change after shock", symbol="ΔB_i",
                                                 key="dB_shock"),
                                               "dB_shock"))
    assert str(_budget_title(N(name="bias", symbol="B₀", key="B0"),
                             "mean of the static record")) == \
        "bias B₀ (mean of the static record)"


def test_the_signature_table_stays_on_one_page():
    """A rendered JJF 2003 certificate had 'Calibrated by' at a page foot and 'Checked by', 'Issued
    by' on the next page: every row but the last keeps with the next (LibreOffice and Word)."""
    from metro.core.documents.document import DocumentBuilder, signatures
    from metro.core.base.locale import translator

    doc = DocumentBuilder(number="N-1", title="T", tr=translator("en"))
    signatures(doc, [("Calibrated by", "A"), ("Checked by", "B"), ("Issued by", "C", "Manager")])
    t = doc.doc.tables[-1]
    keep = [all(p.paragraph_format.keep_with_next for c in row.cells for p in c.paragraphs) for row
            in t.rows]
    assert keep == [True, True, True, False]


def test_zh_en_figure_title_wraps_by_display_width():
    """A zh+en title wrapped at 70 characters ran past the figure's edge (a CJK character is two
    columns wide) and was clipped — JJF 2014 7.2.1's first figure read "Scale factor: m" on the
    rendered page."""
    t = ("标度因数：平均输出 F̄_i（式（2））及拟合直线 F̂ = KΩ + F₀（式（6）） Scale factor: mean "
         "outputs F̄_i (eq. (2)) and the fitted line F̂ = KΩ + F₀ (eq. (6))")
    lines = plots.title_lines(t)
    assert all(plots.display_width(x) <= 70 for x in lines), lines
    assert " ".join(lines).split() == t.split()  # nothing lost
    assert plots.title_lines("K against rate") == ["K against rate"]

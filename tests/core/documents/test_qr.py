"""The verify QR code of a registered report: its payload (segno's own data, compared with a code
made here from the expected URL) and the picture in the .docx only when the lab profile gives a
verify URL and the report is registered."""

from __future__ import annotations

import io

import attrs
import docx
import segno

from metro.core.documents import qr

NUMBER = "EML2026-00007"
URL = "https://lab.example/verify/EML2026-00007"


def test_verify_link_joins_base_and_number_with_one_slash():
    assert qr.verify_link("https://lab.example/verify/", NUMBER) == URL
    assert qr.verify_link("https://lab.example/verify", NUMBER) == URL
    # a number is a file name: a space or # in it is percent-encoded, never a URL part
    assert qr.verify_link("http://h/v", "A 1#2") == "http://h/v/A%201%232"


def test_code_carries_the_url():
    code = qr.make_code(URL)
    fresh = segno.make(URL, error="m", micro=False, boost_error=False)
    assert not code.is_micro and code.designator == fresh.designator == "3-M"
    assert code.matrix == fresh.matrix
    assert code.matrix != segno.make(URL + "8", error="m", micro=False).matrix


def _matrix_of_png(png: bytes) -> tuple[bytearray, ...]:
    """The modules of a PNG drawn at :data:`qr.SCALE` pixels a module inside a
    :data:`qr.BORDER`-module quiet zone: 1 where the module's centre pixel is dark."""
    from PIL import Image

    img = Image.open(io.BytesIO(png)).convert("L")
    n = img.width // qr.SCALE - 2 * qr.BORDER
    assert img.width == img.height == (n + 2 * qr.BORDER) * qr.SCALE

    def dark(i: int, j: int) -> int:
        x, y = ((qr.BORDER + k) * qr.SCALE + qr.SCALE // 2 for k in (j, i))
        return int(img.getpixel((x, y)) < 128)

    return tuple(bytearray(dark(i, j) for j in range(n)) for i in range(n))


def _floating_pictures(path) -> list[tuple[str, bytes]]:
    """(alternative text, image bytes) of each floating picture (``wp:anchor``) on page 1."""
    d = docx.Document(str(path))
    out = []
    for anchor in d.element.body.xpath(".//wp:anchor"):
        descr = anchor.xpath("./wp:docPr/@descr")[0]
        (rid,) = anchor.xpath(".//a:blip/@r:embed")
        out.append((descr, d.part.related_parts[rid].blob))
    return out


def test_registered_report_prints_the_qr_code_only_with_a_verify_url(tmp_path, capsys):
    from metro.core.cli.app import main
    from metro.core.documents.report import build_context, render_context
    from metro.core.record import lab as labmod
    from metro.core.record.registering import with_lab
    from metro.core.run.plugin_manager import get_plugin_manager
    from metro.core.run.runner import run_items

    profile = tmp_path / "lab.toml"
    assert main(["lab", "init", str(profile)]) == 0
    capsys.readouterr()
    plain_lab = labmod.load_lab(profile, equipment=False)
    profile.write_text(profile.read_text(encoding="utf-8").replace(
        '# verify_url = "https://lab.example/verify/"', 'verify_url = "https://lab.example/verify/"'),
        encoding="utf-8")
    lab = labmod.load_lab(profile, equipment=False)
    pm = get_plugin_manager(autoload=False)
    rec = run_items(pm, "jjf2014", ["7.2.13"], station_options={"duration_scale": 0.1})
    rec = attrs.evolve(rec, report_number=NUMBER)
    layout = pm.template_for("jjf2014").layout
    registered = {"registered": True, "notices": ["REGISTERED notice"]}

    def write(name: str, profile_lab, register, template=None) -> object:
        ctx = build_context(with_lab(rec, profile_lab), extend=pm.extend_report_context,
                            register=register)
        return render_context(tmp_path / name, ctx, layout=layout, template=template)

    with_url = write("a.docx", lab, registered)
    ((descr, png),) = _floating_pictures(with_url)
    assert descr == URL
    assert png == qr.qr_png(URL)
    # the modules drawn are those of a code made here from the URL the number gives
    assert _matrix_of_png(png) == segno.make(URL, error="m", micro=False).matrix
    # the register statement stays the first paragraph, the title after it
    d = docx.Document(str(with_url))
    assert d.paragraphs[0].text == "REGISTERED notice"
    assert d.paragraphs[1]._p.xpath(".//wp:anchor")
    # no verify URL in the profile, or a report not registered: no QR code
    assert _floating_pictures(write("b.docx", plain_lab, registered)) == []
    assert _floating_pictures(write("c.docx", lab, {"registered": False, "notices": []})) == []
    # a lab's docxtpl template: {{ verify_qr }} and {{ verify_link }} (the packaged one has them)
    from metro.core.documents.report import default_template

    with default_template().open("rb") as fh:
        (tmp_path / "template.docx").write_bytes(fh.read())
    template = tmp_path / "template.docx"
    d = docx.Document(str(write("d.docx", lab, registered, template)))
    assert f"Verify this report: {URL}" in [p.text for p in d.paragraphs]
    images = [d.part.related_parts[r].blob for r in d.element.body.xpath(".//a:blip/@r:embed")]
    assert qr.qr_png(URL) in images
    d = docx.Document(str(write("e.docx", plain_lab, registered, template)))
    assert not any(p.text.startswith("Verify this report") for p in d.paragraphs)

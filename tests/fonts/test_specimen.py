"""morph.fonts.specimen: the OUT.html page next to every written font.

The slow test opens it in headless Chromium and compares the screenshot's sample line
with Pillow's rendering of the same text in the same font file (FreeType): the ink
must be where Pillow puts it, and not where the source font would put it.
"""

import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner
from fontTools.ttLib import TTFont
from PIL import Image, ImageDraw, ImageFont

from morph.cli import main
from morph.fonts.specimen import (SAMPLE_MARGIN, SAMPLE_POS, SAMPLE_PX, WATERFALL,
                                  write_specimen)
from morph.parse import default_font_path
from tests import RELIEF_SUBSET

TEXT = "Hamburg"


@pytest.fixture(scope="module")
def brushed(tmp_path_factory):
    folder = tmp_path_factory.mktemp("spec")
    out = folder / "Spec.woff2"
    r = CliRunner().invoke(main, ["brush", "-o", str(out), "--glyphs", "H,a,m,b,u,r,g",
                                  "--sample", TEXT, "--jobs", "1"])
    assert r.exit_code == 0, r.output
    return out


def test_specimen_page(brushed):
    page = brushed.with_name(brushed.name + ".html").read_text()
    assert '@font-face { font-family: "MorphResult"; src: url("Spec.woff2") format("woff2")' \
        in page
    assert "data:font/woff;base64," in page  # the source, embedded (zlib: fast)
    for px in WATERFALL:
        assert 'class="res" style="font-size:%dpx"' % px in page
        assert 'class="src" style="font-size:%dpx"' % px in page
    cmap = TTFont(str(brushed)).getBestCmap()
    assert page.count('class="cell"') == sum(1 for c in cmap if chr(c).isprintable()
                                             and not chr(c).isspace())
    assert "U+0041" in page and ">H</p>" not in page


def test_specimen_without_source(tmp_path):
    path = write_specimen(default_font_path(), None, sample="<&>",
                          html_path=tmp_path / "x.html")
    text = path.read_text()
    assert "data:font" not in text and "&lt;&amp;&gt;" in text


def _chromium():
    for name in ("chromium", "chromium-browser", "google-chrome", "chrome"):
        path = shutil.which(name)
        if path:
            return path
    return None


def _ink(img):
    """Boolean ink mask cropped to its bounding box."""
    a = np.asarray(img.convert("L")) < 128
    ys, xs = np.nonzero(a)
    return a[ys.min():ys.max() + 1, xs.min():xs.max() + 1]


def _iou(a, b):
    h, w = max(a.shape[0], b.shape[0]), max(a.shape[1], b.shape[1])
    pa, pb = np.zeros((h, w), bool), np.zeros((h, w), bool)
    pa[:a.shape[0], :a.shape[1]] = a
    pb[:b.shape[0], :b.shape[1]] = b
    return (pa & pb).sum() / (pa | pb).sum()


def _pillow(font_file, text, px=SAMPLE_PX):
    fnt = ImageFont.truetype(str(font_file), px)
    img = Image.new("L", (px * len(text) * 2, px * 3), 255)
    ImageDraw.Draw(img).text((px // 2, px // 2), text, font=fnt, fill=0)
    return img


@pytest.mark.slow
def test_specimen_in_chromium(brushed, tmp_path):
    """Headless Chromium shows the new font's ink where Pillow's rendering has it."""
    browser = _chromium()
    if browser is None:
        pytest.skip("no Chromium installed (apt-get install chromium) to open the specimen")
    shot = tmp_path / "shot.png"
    cmd = [browser, "--headless", "--no-sandbox", "--disable-gpu", "--no-first-run",
           "--disable-background-networking", "--disable-component-update", "--disable-sync",
           "--user-data-dir=%s" % (tmp_path / "profile"), "--hide-scrollbars",
           "--force-device-scale-factor=1", "--window-size=1200,400",
           "--screenshot=%s" % shot, brushed.with_name(brushed.name + ".html").as_uri()]
    subprocess.run(cmd, capture_output=True, timeout=120, check=False)
    assert shot.exists(), "Chromium wrote no screenshot"
    x, y = SAMPLE_POS
    line = Image.open(shot).crop((0, 0, 1200, y + SAMPLE_PX + SAMPLE_MARGIN - 4))
    browser_ink = _ink(line)
    ttf = tmp_path / "Spec.ttf"  # FreeType in Pillow may lack WOFF2: the same font as .ttf
    font = TTFont(str(brushed))
    font.flavor = None
    font.save(str(ttf))
    result = _iou(browser_ink, _ink(_pillow(ttf, TEXT)))
    source = _iou(browser_ink, _ink(_pillow(default_font_path(), TEXT)))
    print("IoU with Pillow: result font %.3f, source font %.3f" % (result, source))
    assert result >= 0.85, (result, source)
    assert source < result - 0.1, (result, source)  # it is the new font, not the source
    w_browser, w_pillow = browser_ink.shape[1], _ink(_pillow(ttf, TEXT)).shape[1]
    assert abs(w_browser - w_pillow) <= 3


@pytest.mark.parametrize("suffix", ["ttf", "otf"])
def test_ink_test_reads_the_data_as_a_control_box_pen_draws(suffix, tmp_path):
    """Whether a glyph has ink, told from its glyf header (a composite by its
    components) or its charstring's operators, is what drawing it into a
    control-box pen says, for every glyph of the bundled font (composites and
    empty glyphs among them) and of a stroked CFF font (subroutinized by tx)."""
    from fontTools.pens.boundsPen import ControlBoundsPen

    from morph.fonts.specimen import _ink_test

    paths = [Path(default_font_path()).with_suffix("." + suffix)]
    if suffix == "otf":
        out = tmp_path / "s.otf"
        r = CliRunner().invoke(main, ["stroke", str(RELIEF_SUBSET), "-o", str(out), "--glyphs",
                                      "a,o,eacute", "--jobs", "1"])
        assert r.exit_code == 0, r.output
        paths.append(out)
    for path in paths:
        font = TTFont(str(path), lazy=True)
        glyph_set = font.getGlyphSet()
        _, has_ink = _ink_test(font)
        kinds = set()
        for name in font.getGlyphOrder():
            pen = ControlBoundsPen(glyph_set)
            glyph_set[name].draw(pen)
            kinds.add(pen.bounds is not None)
            assert has_ink(name) == (pen.bounds is not None), (path.name, name)
        assert kinds == {True, False}


def test_sample_png_holds_the_images_pixels(brushed, tmp_path):
    """The sample PNG (morph's own writer, save_png) reads back as the image Pillow
    drew: grayscale for black text on white, RGB when a pixel has colour; a
    different image does not compare equal."""
    from morph.fonts.specimen import save_png, write_sample_image

    img = write_sample_image(brushed, TEXT, tmp_path / "s.png")
    back = Image.open(tmp_path / "s.png")
    assert back.format == "PNG" and back.mode == "L" and back.size == img.size
    assert np.array_equal(np.asarray(back.convert("RGB")), np.asarray(img))
    assert np.asarray(back).min() == 0 and np.asarray(back).max() == 255  # ink and paper
    colour = img.copy()
    ImageDraw.Draw(colour).rectangle((2, 3, 9, 7), fill=(200, 30, 60))
    save_png(colour, tmp_path / "c.png")
    back = Image.open(tmp_path / "c.png")
    assert back.mode == "RGB" and np.array_equal(np.asarray(back), np.asarray(colour))
    assert not np.array_equal(np.asarray(back), np.asarray(img))
    with pytest.raises(ValueError):
        save_png(img.convert("L"), tmp_path / "l.png")


def test_specimen_escapes_as_html_escape():
    import html

    from morph.fonts.specimen import _escape

    for text in ("a&b<c>d\"e'f", "&amp;", "plain", "", "<'\">&"):
        assert _escape(text) == html.escape(text, quote=True)
        assert _escape(text, quote=False) == html.escape(text, quote=False)

"""Brush fonts: written glyph = glyph ⊕ nib (Hausdorff <= 1 font unit vs Clipper)."""

import numpy as np
import pytest
from click.testing import CliRunner
from fontTools.pens.areaPen import AreaPen
from fontTools.ttLib import TTFont
from PIL import Image, ImageDraw, ImageFont

from morph import piece as pc
from morph.cli import main
from morph.errors import MorphError
from morph.fonts.brush import (brush_font, check_convex_nib, ellipse_nib, parse_glyph_spec,
                               region_extent)
from morph.parse import cubic_test_font_path, default_font_path, glyph_region
from tests.reference import hausdorff, polygon_minkowski_sum, region_to_shapely

NIB = (80.0, 30.0, 30.0)
CHARS = "oTg"


@pytest.fixture(scope="module", params=["ttf", "otf"])
def brushed(request, tmp_path_factory):
    src = default_font_path() if request.param == "ttf" else cubic_test_font_path()
    out = tmp_path_factory.mktemp("brush") / ("b." + request.param)
    seen = []
    stats = brush_font(src, out, ellipse_nib(*NIB), list(CHARS) + [" "], tol=0.5,
                       family_name="Test Brush", progress=seen.append)
    assert len(seen) == len(CHARS) + 1 and stats["glyphs"] == len(CHARS) + 1
    return src, out


def test_outlines_equal_glyph_plus_nib(brushed):
    src, out = brushed
    nib = ellipse_nib(*NIB)
    shift = -region_extent(nib)[0]
    nib = [[pc.translate(p, (shift, 0.0)) for p in nib[0]]]
    for ch in CHARS:
        got = glyph_region(ch, font=str(out)).region
        ref = polygon_minkowski_sum(glyph_region(ch, font=src).region, nib, 0.25)
        assert hausdorff(region_to_shapely(got, 0.05), ref, 0.5) <= 1.0, ch


def test_metrics_names_and_directions(brushed):
    src, out = brushed
    a, b = TTFont(str(src)), TTFont(str(out))
    nib_w = region_extent(ellipse_nib(*NIB))
    nib_w = nib_w[2] - nib_w[0]
    cmap = a.getBestCmap()
    for ch in CHARS + " ":
        name = cmap[ord(ch)]
        assert b["hmtx"][name][0] == round(a["hmtx"][name][0] + nib_w)
        if ch != " ":  # left side bearing kept (outline shifted by the nib's left extent)
            assert abs(b["hmtx"][name][1] - a["hmtx"][name][1]) <= 1
    assert b["name"].getDebugName(1) == "Test Brush"
    assert b["name"].getDebugName(6).startswith("TestBrush")
    # contour direction of the format: TrueType outer clockwise (AreaPen < 0),
    # CFF outer counter-clockwise (> 0); the bundled test .otf keeps TrueType directions
    want = -1.0 if "glyf" in b else 1.0
    for ch in CHARS:
        name = cmap[ord(ch)]
        pa, pb = AreaPen(a.getGlyphSet()), AreaPen(b.getGlyphSet())
        a.getGlyphSet()[name].draw(pa)
        b.getGlyphSet()[name].draw(pb)
        assert np.sign(pb.value) == want
        assert abs(pb.value) > abs(pa.value)
    # untouched glyph stays
    assert b["hmtx"]["A"] == a["hmtx"]["A"]


def test_pillow_renders(brushed):
    _, out = brushed
    fnt = ImageFont.truetype(str(out), 48)
    img = Image.new("L", (200, 70), 255)
    ImageDraw.Draw(img).text((5, 5), "oTg", font=fnt, fill=0)
    assert np.asarray(img).min() == 0


def test_nonconvex_nib_rejected():
    star = [[pc.line(a, b) for a, b in zip(pts, np.roll(pts, -1, axis=0))]
            for pts in [np.array([[0, 0], [10, 0], [5, 2], [10, 10], [0, 10]], float)]]
    with pytest.raises(MorphError, match="not convex"):
        check_convex_nib(star)
    check_convex_nib(ellipse_nib(10, 5, 20))


def test_parse_glyph_spec():
    assert parse_glyph_spec("a-c,X,ampersand") == ["a", "b", "c", "X", "ampersand"]


def test_cli_brush(tmp_path):
    out = tmp_path / "f.ttf"
    r = CliRunner().invoke(main, ["brush", "-o", str(out), "--glyphs", "T,o",
                                  "--nib", "ellipse:60,20,45", "--sample", "ToT"])
    assert r.exit_code == 0, r.output
    assert TTFont(str(out))["name"].getDebugName(1).endswith("Brush")
    assert (tmp_path / "f.png").stat().st_size > 0
    nib = tmp_path / "nib.svg"
    nib.write_text('<svg xmlns="http://www.w3.org/2000/svg"><path '
                   'd="M0 0 L20 0 L10 5 L20 20 L0 20 Z"/></svg>')
    r = CliRunner().invoke(main, ["brush", "-o", str(tmp_path / "g.ttf"), "--glyphs", "T",
                                  "--nib-svg", str(nib)])
    assert r.exit_code == 2
    assert "not convex" in r.output

"""Brush fonts: written glyph = glyph ⊕ nib (Hausdorff <= 1 font unit vs Clipper).

A-Z, a-z of both bundled fonts are checked the same way by ``python -m bench.brush``
(bench/brush.md); here a few glyphs, kept cheap.
"""

import numpy as np
import pytest
from click.testing import CliRunner
from fontTools.pens.areaPen import AreaPen
from fontTools.ttLib import TTFont
from PIL import Image, ImageDraw, ImageFont

from morph import piece as pc
from morph.cli import main
from morph.errors import MorphError
from morph.fonts.brush import (brush_font, check_convex_nib, composite_plan, ellipse_nib,
                               parse_glyph_spec, region_extent)
from morph.parse import cubic_test_font_path, default_font_path, glyph_region
from tests.reference import hausdorff, polygon_minkowski_sum, region_to_shapely

NIB = (80.0, 30.0, 30.0)
CHARS = "oTgSWe"


@pytest.fixture(scope="module", params=["ttf", "otf"])
def brushed(request, tmp_path_factory):
    src = default_font_path() if request.param == "ttf" else cubic_test_font_path()
    out = tmp_path_factory.mktemp("brush") / ("b." + request.param)
    seen = []
    stats = brush_font(src, out, ellipse_nib(*NIB), list(CHARS) + [" "], tol=0.5,
                       family_name="Test Brush", progress=seen.append)
    assert len(seen) == len(CHARS) + 1 and stats["glyphs"] == len(CHARS) + 1
    return src, out


def _shifted_nib():
    nib = ellipse_nib(*NIB)
    shift = -region_extent(nib)[0]
    return [[pc.translate(p, (shift, 0.0)) for p in nib[0]]]


def _assert_sum(src, out, ch_or_name):
    got = glyph_region(ch_or_name, font=str(out)).region
    ref = polygon_minkowski_sum(glyph_region(ch_or_name, font=src).region, _shifted_nib(),
                                0.25)
    assert hausdorff(region_to_shapely(got, 0.05), ref, 0.5) <= 1.0, ch_or_name


def test_outlines_equal_glyph_plus_nib(brushed):
    src, out = brushed
    for ch in CHARS:
        _assert_sum(src, out, ch)


def _bounds(font, name):
    from fontTools.pens.boundsPen import BoundsPen

    pen = BoundsPen(font.getGlyphSet())
    font.getGlyphSet()[name].draw(pen)
    return pen.bounds


def test_composites_follow_swept_components(brushed):
    """TrueType oacute = o + acute: o swept, oacute grows like o, acute stays centred.

    CFF has no composites (the bundled .otf has no seac either): its accented letters
    are plain outlines and stay as they are when their base letter is swept.
    """
    src, out = brushed
    a, b = TTFont(str(src)), TTFont(str(out))
    if "glyf" not in a:
        for name in ("oacute", "eacute"):
            assert b["hmtx"][name] == a["hmtx"][name]
            assert _bounds(b, name) == _bounds(a, name)
        return
    x0, _, x1, _ = region_extent(ellipse_nib(*NIB))
    assert composite_plan(a, ["o"]) == (["ograve", "oacute", "ocircumflex", "otilde",
                                          "odieresis"], [])
    for name in ("ograve", "oacute", "ocircumflex", "otilde", "odieresis"):
        g = b["glyf"][name]
        assert g.isComposite()
        assert b["hmtx"][name][0] == b["hmtx"]["o"][0] == round(a["hmtx"][name][0] + x1 - x0)
        assert b["hmtx"][name][1] == _bounds(b, name)[0]
        mark = [c for c in g.components if c.glyphName != "o"][0]
        old = [c for c in a["glyf"][name].components if c.glyphName == mark.glyphName][0]
        assert (mark.x - old.x, mark.y - old.y) == (round((x1 - x0) / 2), 0)
        # the mark keeps its place over the (widened) o: centres agree as before
        (ox0, _, ox1, _), (px0, _, px1, _) = _bounds(a, "o"), _bounds(b, "o")
        assert abs((px0 + px1) / 2 - (ox0 + ox1) / 2 - mark.x + old.x) <= 1
        assert _bounds(b, name)[2] <= b["hmtx"][name][0]  # ink inside the advance
    # unrelated composites and the accents themselves are untouched
    for name in ("Eacute", "acute"):
        assert b["hmtx"][name] == a["hmtx"][name]
    # Pillow: "oó" in the new font, no ink clipped at the right edge of the advance
    fnt = ImageFont.truetype(str(out), 100)
    adv = fnt.getlength("ó")
    img = Image.new("L", (int(adv) + 40, 160), 255)
    ImageDraw.Draw(img).text((20, 20), "ó", font=fnt, fill=0)
    ink = np.nonzero(np.asarray(img).min(axis=0) < 128)[0]
    assert ink[0] >= 20 and ink[-1] <= 20 + adv


def test_chosen_composite_is_decomposed_and_swept(tmp_path):
    """A chosen composite becomes glyph ⊕ nib of its decomposed outline (accent too)."""
    src, out = default_font_path(), tmp_path / "c.ttf"
    stats = brush_font(src, out, ellipse_nib(*NIB), ["eacute", "Y"], tol=0.5,
                       composites="sweep")
    assert (stats["glyphs"], stats["followed"], stats["decomposed"]) == (2, 0, 1)
    b = TTFont(str(out))
    for name in ("eacute", "Yacute"):  # chosen / decomposed because Y was swept
        assert not b["glyf"][name].isComposite()
        _assert_sum(src, out, name)
    with pytest.raises(MorphError, match="composites"):
        brush_font(src, "unused.ttf", ellipse_nib(*NIB), ["Y"], composites="keep")


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


def test_cli_brush_composites(tmp_path):
    """--composites sweep decomposes eacute and sweeps it (a simple glyph in the
    output); follow keeps it a composite (TrueType)."""
    for mode, composite in (("follow", True), ("sweep", False)):
        out = tmp_path / (mode + ".ttf")
        r = CliRunner().invoke(main, ["brush", "-o", str(out), "--glyphs", "e",
                                      "--composites", mode, "--sample", "e"])
        assert r.exit_code == 0, r.output
        f = TTFont(str(out))
        name = f.getBestCmap()[ord("é")]
        assert f["glyf"][name].isComposite() == composite, mode
    r = CliRunner().invoke(main, ["brush", "-o", str(tmp_path / "x.ttf"), "--composites", "no"])
    assert r.exit_code == 2

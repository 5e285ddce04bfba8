"""morph.parse.glyphs: glyphs of TrueType and CFF fonts: areas against shapely, orientation
rules, every bad input."""

import math
import string
from functools import reduce

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely

from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.errors import ParseError
from morph.parse import cubic_test_font_path, default_font_path, glyph_region, load_font

FONTS = {"ttf": default_font_path(), "otf": cubic_test_font_path()}


def fine_polyline(loop, delta):
    """Polyline within ``delta`` of a loop of polynomial pieces (uniform parameters).

    A chord over a parameter step h deviates at most max|P''| h^2 / 8 from the curve,
    and max|P''| <= n (n-1) max_i |P_{i+2} - 2 P_{i+1} + P_i|.
    """
    out = []
    for p in loop:
        assert pc.is_polynomial(p)
        c = pc.cartesian(p)
        n = len(c) - 1
        if n == 1:
            out.append(c[:1])
            continue
        m2 = n * (n - 1) * np.hypot(*np.diff(c, 2, axis=0).T).max()
        k = max(2, int(math.ceil(math.sqrt(m2 / (8 * delta)))))
        out.append(pc.evaluate(p, np.linspace(0, 1, k + 1)[:-1]))
    return np.concatenate(out)


def evenodd_area(loops, delta):
    """Area of the even-odd fill of the loops by shapely (orientation-independent)."""
    polys = [shapely.Polygon(fine_polyline(l, delta)) for l in loops]
    return reduce(lambda a, b: a.symmetric_difference(b), polys).area


@pytest.mark.parametrize("font", sorted(FONTS))
def test_glyph_areas_match_shapely_every_letter(font):
    """Every glyph A-Z, a-z: exact area (Green) == shapely area of a 1e-4-unit polyline."""
    path = FONTS[font]
    for ch in string.ascii_letters:
        g = glyph_region(ch, path)
        exact = mo.region_area(g.region)
        ref = evenodd_area(g.region, 1e-4)
        assert exact > 0, ch
        assert abs(exact - ref) <= 1e-6 * ref, (font, ch, exact, ref)


@pytest.mark.parametrize("font", sorted(FONTS))
@pytest.mark.parametrize("ch, holes", [("O", 1), ("B", 2), ("8", 2), ("g", 1), ("o", 1),
                                       ("e", 1), ("l", 0)])
def test_orientation_outer_ccw_holes_cw(font, ch, holes):
    g = glyph_region(ch, FONTS[font])
    signs = [np.sign(mo.loop_area(l)) for l in g.region]
    assert signs.count(-1) == holes and signs.count(1) == len(signs) - holes
    # the biggest loop is the outer one; every hole lies inside an outer loop
    assert mo.loop_area(max(g.region, key=lambda l: abs(mo.loop_area(l)))) > 0
    outers = [shapely.Polygon(pl.flatten_loop(l, 0.5)) for l in g.region if mo.loop_area(l) > 0]
    for l in g.region:
        if mo.loop_area(l) < 0:
            probe = shapely.Point(pc.evaluate(l[0], 0.5)[0])
            assert any(o.contains(probe) for o in outers)


def test_glyph_pieces_by_font_kind_and_joins():
    tt = glyph_region("g", FONTS["ttf"])
    cff = glyph_region("g", FONTS["otf"])
    assert {len(p) for l in tt.region for p in l} == {2, 3}  # lines, quadratics
    assert {len(p) for l in cff.region for p in l} == {2, 4}  # lines, cubics
    for g in (tt, cff):
        for loop in g.region:
            for a, b in zip(loop, loop[1:] + loop[:1]):
                assert np.array_equal(pc.end(a), pc.start(b))
    assert (tt.name, tt.advance_width, tt.units_per_em) == ("g", 615, 1000)
    # the two fonts are the same design: areas agree to the quadratic/cubic conversion
    assert mo.region_area(tt.region) == pytest.approx(mo.region_area(cff.region), rel=1e-3)


def test_glyph_by_name_and_composite():
    amp = glyph_region("ampersand")
    assert amp.name == "ampersand"
    agrave = glyph_region("\u00e0")  # composite: a + grave, decomposed
    a = glyph_region("a")
    assert len(agrave.region) == len(a.region) + 1
    assert mo.region_area(agrave.region) > mo.region_area(a.region)


def test_load_font_cached_and_errors(tmp_path):
    assert load_font() is load_font(default_font_path())
    with pytest.raises(ParseError, match="no such file") as info:
        load_font(tmp_path / "missing.ttf")
    assert "missing.ttf" in str(info.value)
    bad = tmp_path / "garbage.ttf"
    bad.write_bytes(b"this is not a font")
    with pytest.raises(ParseError, match="garbage.ttf"):
        load_font(bad)


def test_missing_and_empty_glyphs():
    with pytest.raises(ParseError, match=r"has no glyph for '\u4e00'"):
        glyph_region("\u4e00")
    with pytest.raises(ParseError, match="no glyph for 'notaglyphname'"):
        glyph_region("notaglyphname")
    with pytest.raises(ParseError, match="empty"):
        glyph_region(" ")
    with pytest.raises(ParseError):
        glyph_region("")


@pytest.mark.parametrize("font", sorted(FONTS))
def test_read_glyphs_is_the_one_glyph_reader_of_each_to_the_bit(font):
    """read_glyphs (pieces of all glyphs built at once, contours oriented together)
    gives, glyph by glyph, what the one-glyph way gives: the pen's pieces one by one
    (record_contours), _filled_loop, orient_region; the errors of the bad names
    returned in their places, the others read."""
    from morph.parse import read_glyphs
    from morph.parse.glyphs import _filled_loop, glyph_name
    from morph.parse.pens import record_contours
    from morph.region import orient_region
    from morph.trim import fill_region

    f = load_font(FONTS[font])
    names = [glyph_name(f, c) for c in string.ascii_letters + string.digits + "&%@\u00e0"]
    names = names + ["space", "notaglyphname"] + names[:3]
    got = read_glyphs(f, names)
    glyphs = f.getGlyphSet()
    for name, shape in zip(names, got):
        if name in ("space", "notaglyphname"):
            assert isinstance(shape, ParseError)
            assert ("empty" if name == "space" else "no glyph named") in str(shape)
            continue
        contours = record_contours(glyphs[name].draw, name, glyphs)
        loops = [lp for lp in (_filled_loop(c, name) for c in contours) if lp]
        want = orient_region(loops, "nonzero", on_crossing=fill_region)
        assert len(shape.region) == len(want) and shape.region.validated, name
        for la, lb in zip(shape.region, want):
            assert len(la) == len(lb)
            assert all(p.shape == q.shape and p.tobytes() == np.ascontiguousarray(q).tobytes()
                       for p, q in zip(la, lb)), name
        assert (shape.advance_width, shape.lsb) == tuple(f["hmtx"][name])

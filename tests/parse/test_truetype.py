"""morph.parse.truetype: simple TrueType glyphs decoded from their bytes give the
pieces that drawing them on the pen gives (morph.parse.glyphs), value for value."""

import numpy as np
import pytest
from fontTools.pens.ttGlyphPen import TTGlyphPen
from fontTools.ttLib import TTFont

from morph.parse import default_font_path
from morph.parse import glyphs as G
from morph.parse.truetype import simple_glyph_loops


def _drawn(font, names):
    """The loops of each glyph drawn on the recording pen, as read_glyphs draws them."""
    gs = font.getGlyphSet()
    return G._filled_loops([G._glyph_segments(gs, n, n, "test") for n in names], names)


def _same(a, b):
    return len(a) == len(b) and all(
        len(p) == len(q) and all(np.array_equal(x, y) for x, y in zip(p, q))
        for p, q in zip(a, b))


@pytest.mark.parametrize("expanded", [False, True])
def test_every_simple_glyph_of_the_bundled_font_as_drawn(expanded):
    """All glyphs of Noto Sans, stored (decoded from their bytes) or already
    expanded by fontTools (read from its arrays); composites left to the pen."""
    font = TTFont(default_font_path())
    names = font.getGlyphOrder()
    if expanded:
        for n in names:
            font["glyf"][n]
    got = simple_glyph_loops(font, names)
    drawn = _drawn(font, names)
    glyf = font["glyf"]
    for name, loops, want in zip(names, got, drawn):
        if glyf[name].isComposite():
            assert loops is None, name
        else:
            assert loops is not None and _same(loops, want), name
    assert sum(1 for loops in got if loops) > 100


def _glyph(contours):
    pen = TTGlyphPen(None)
    for pts in contours:
        pen.moveTo(pts[0])
        for p in pts[1:]:
            pen.lineTo(p) if not isinstance(p, list) else pen.qCurveTo(*p)
        pen.closePath()
    return pen.glyph()


def test_runs_offsets_and_contours_left_to_the_pen():
    """Quadratic runs (implied on-curve points at odd midpoints), a repeated
    point (zero-length piece dropped), a long coordinate, a one-point contour,
    an lsb unlike xMin (the outline moves by their difference, as fontTools draws
    it); a contour of off-curve points only is left to the pen."""
    font = TTFont(default_font_path())
    glyf, hmtx = font["glyf"], font["hmtx"]
    glyf["t1"] = _glyph([[(0, 0), (0, 0), (1001, 3), [(1201, 300), (1000, 601), (5, 603)]],
                         [(40, 40)], [(-3000, 7), (20, 9), [(13, 13), (-7, 27), (-3000, 7)]]])
    glyf["t2"] = _glyph([[(10, 10), (300, 10), (300, 300)]])
    glyf["t3"] = _glyph([[(10, 10)]])
    hmtx["t1"], hmtx["t2"], hmtx["t3"] = (1200, -3000), (400, 25), (100, 10)
    for name in ("t1", "t2", "t3"):
        glyf[name].recalcBounds(glyf)
    font.setGlyphOrder(font.getGlyphOrder() + ["t1", "t2", "t3"])
    names = ["t1", "t2", "t3"]
    for stored in (False, True):
        if stored:   # the glyphs as bytes again, decoded by the module
            for name in names:
                data = glyf[name].compile(glyf)
                glyf.glyphs[name] = glyf[name].__class__(data)
        got = simple_glyph_loops(font, names)
        assert all(_same(a, b) for a, b in zip(got, _drawn(font, names)))
        assert [len(loops) for loops in got] == [2, 1, 0]
        assert got[1][0][0][0, 0] == 25.0   # moved by lsb - xMin
    # a contour of off-curve points only (TrueType's implied start point)
    from fontTools.ttLib.tables._g_l_y_f import GlyphCoordinates

    ring = [(0, 0), (100, 0), (100, 100), (0, 100)]
    off = glyf["t3"].__class__()
    off.coordinates = GlyphCoordinates(ring)
    off.flags = bytearray([0] * 4)
    off.endPtsOfContours = [3]
    off.numberOfContours = 1
    off.program = glyf["t2"].program
    off.recalcBounds(glyf)
    glyf["t4"] = off
    hmtx["t4"] = (100, 0)
    assert simple_glyph_loops(font, ["t4", "nosuchglyph"]) == [None, None]

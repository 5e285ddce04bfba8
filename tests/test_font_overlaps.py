"""Static fonts written by ``morph stroke`` and ``morph brush`` are trimmed and free of
overlaps: no two contours of a glyph cover a region twice by more than the outline's
error allows (``tests/oracles/overlaps.py``; bench/stroke_overlaps.py runs the same
check on whole skeleton sets).

The oracle is first shown to fail on known shapes (squares crossing by more than the
bound, a hole poking out, a twisted contour), read from a font file as the written
fonts are, and to pass nested contours; then a few bundled glyphs are stroked and
brushed and checked."""

import pytest
from fontTools.fontBuilder import FontBuilder
from fontTools.pens.recordingPen import RecordingPen
from fontTools.pens.ttGlyphPen import TTGlyphPen

from morph.fonts.brush import brush_font, ellipse_nib
from morph.fonts.stroke import stroke_ufo
from tests import RELIEF_SUBSET
from tests.fontfixtures import finish_tables
from tests.oracles.overlaps import (FLAT, ROUNDING, font_overlaps, glyph_overlaps,
                                    overlap_bound)

TOL = 0.5  # the commands' default, 0.0005 em, at 1000 units per em
BOUND = overlap_bound(TOL)


def square(x, y, size, ccw=True):
    pts = [(x, y), (x + size, y), (x + size, y + size), (x, y + size)]
    return pts if ccw else pts[::-1]


def drawing(*contours):
    pen = RecordingPen()
    for c in contours:
        pen.moveTo(c[0])
        for p in c[1:]:
            pen.lineTo(p)
        pen.closePath()
    return pen


def write_font(path, glyphs):
    """A TrueType font of ``glyphs`` {name: [contours]} (integer points), as a written
    font is read back."""
    order = [".notdef"] + list(glyphs)
    fb = FontBuilder(1000, isTTF=True)
    fb.setupGlyphOrder(order)
    fb.setupCharacterMap({0x41 + k: n for k, n in enumerate(glyphs)})
    outlines = {}
    for name in order:
        pen = TTGlyphPen(None)
        drawing(*glyphs.get(name, [])).replay(pen)
        outlines[name] = pen.glyph()
    fb.setupGlyf(outlines)
    finish_tables(fb, order, "Overlaps", 600, 800, -200)
    fb.save(str(path))
    return path


def test_bound_is_twice_tol_and_rounding():
    assert BOUND == pytest.approx(2 * (TOL + ROUNDING))


@pytest.mark.parametrize("ccw", [True, False])
@pytest.mark.parametrize("factor", [1.5, 0.5])
def test_two_outer_contours_crossing_are_measured(tmp_path, factor, ccw):
    """Two outer squares crossing by ``factor`` x the bound: one lens of that width
    and 100 x that area, over the bound only at 1.5 x; pathops' excess on the curves
    is the lens area too.  Both orientations (CFF's and TrueType's outer contours)."""
    width = round(factor * BOUND)
    glyph = [square(0, 0, 100, ccw), square(100 - width, 0, 100, ccw)]
    (g,) = font_overlaps(write_font(tmp_path / "two.ttf", {"two": glyph}), ["two"])
    assert len(g.overlaps) == 1
    o = g.overlaps[0]
    assert o.width == pytest.approx(width, abs=2 * FLAT)
    assert o.area == pytest.approx(100 * width, rel=1e-6)
    assert o.winding == 2
    assert g.excess == pytest.approx(o.area, rel=1e-6)
    assert (g.width > BOUND) == (factor > 1)


def test_touching_and_nested_contours_are_no_overlap():
    """An outer contour in the hole of another (回, both orientations), and two outer
    contours sharing an edge, cover nothing twice."""
    hui = [square(0, 0, 100), square(10, 10, 80, False), square(30, 30, 40),
           square(40, 40, 20, False)]
    flipped = [c[::-1] for c in hui]
    touching = [square(0, 0, 100), square(100, 20, 50)]
    for contours in (hui, flipped, touching):
        g = glyph_overlaps("g", drawing(*contours))
        assert g.overlaps == [] and g.excess == pytest.approx(0, abs=1e-9), contours


def test_poking_hole_and_twisted_contour_are_overlaps():
    """A hole that leaves its outer contour, and a figure-eight contour, are flagged
    (a winding number of the wrong sign), with the exact excess alike."""
    poke = glyph_overlaps("poke", drawing(square(0, 0, 100), square(90, 10, 20, False)))
    assert [round(o.area) for o in poke.overlaps] == [200] and poke.width > BOUND
    assert poke.overlaps[0].winding == -1
    assert poke.excess == pytest.approx(-400) == poke.overlaps[0].excess
    twist = glyph_overlaps("twist", drawing([(0, 0), (100, 100), (100, 0), (0, 100)]))
    assert twist.overlaps and twist.width > BOUND
    assert twist.disagreement < 1e-6


def _no_wide_overlap(path, names):
    found = font_overlaps(path, names)
    assert [g.name for g in found] == names
    wide = [(g.name, g.width, g.area) for g in found if g.width > BOUND]
    assert not wide, "%s: overlaps wider than %.2f: %s" % (path.name, BOUND, wide)
    # the faces and pathops' curves agree (about the flattening's error)
    assert max(g.disagreement for g in found) < 0.05
    return found


# glyphs drawn by their own contours only
STROKED = ["a", "e", "eight", "B", "k", "s", "g.ss01"]


@pytest.mark.parametrize("suffix", [".otf", ".ttf"])
def test_stroked_glyphs_have_no_overlap_beyond_the_bound(tmp_path, suffix):
    out = tmp_path / ("Stroke" + suffix)
    stats = stroke_ufo(RELIEF_SUBSET, out, ellipse_nib(90.0, 20.0, 30.0), STROKED, tol=TOL)
    assert not stats["fallback"]
    found = _no_wide_overlap(out, STROKED)
    assert all(g.contours for g in found)


def test_brushed_glyphs_have_no_overlap_beyond_the_bound(tmp_path):
    out = tmp_path / "Brush.ttf"
    stats = brush_font(None, out, ellipse_nib(80.0, 30.0, 30.0), list("aegBO8&"), tol=TOL)
    assert not stats["fallback"]
    names = ["a", "e", "g", "B", "O", "eight", "ampersand"]
    found = _no_wide_overlap(out, names)
    assert all(g.contours for g in found)


# composites: a component beside the glyph's own centre lines (g, n, b, Q), or two
# components (eacute, i); kept as components only where their strokes stay apart
COMPOSITES = ["g", "n", "b", "Q", "eacute", "i"]


@pytest.mark.parametrize("suffix", [".otf", ".ttf"])
def test_stroked_composites_have_no_overlap_beyond_the_bound(tmp_path, suffix):
    """Relief's g was written as the separate strokes of its component and its own
    centre line, overlapping in a lens 70 units wide."""
    out = tmp_path / ("Composite" + suffix)
    stats = stroke_ufo(RELIEF_SUBSET, out, ellipse_nib(90.0, 20.0, 30.0), COMPOSITES,
                       tol=TOL)
    assert not stats["fallback"]
    _no_wide_overlap(out, COMPOSITES)

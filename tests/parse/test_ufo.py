"""morph.parse.ufo: skeleton contours (open paths) read from a UFO: the Relief SingleLine
subset (tests/data/relief) and glyphs drawn with a point pen."""

import numpy as np
import pytest
import ufoLib2

from morph import piece as pc
from morph.errors import ParseError
from morph.parse.ufo import component_paths, contour_paths, glyph_names_for, glyph_paths, load_ufo
from tests import RELIEF_SUBSET as SUBSET


def test_open_skeleton_contours(skeleton):
    paths = glyph_paths(skeleton["o"])
    assert len(paths) == 1
    pieces, closed = paths[0]
    assert not closed and len(pieces) == 4 and all(pc.degree(p) == 3 for p in pieces)
    pts = [(p.x, p.y) for p in skeleton["o"].contours[0].points]
    assert np.allclose(pc.start(pieces[0]), pts[0]) and np.allclose(pc.end(pieces[-1]), pts[-1])
    for a, b in zip(pieces, pieces[1:]):
        assert np.array_equal(pc.end(a), pc.start(b))
    # the i's dot: a 2-unit line
    dot = glyph_paths(skeleton["uni0307"])
    assert [len(p) for p, _ in dot] == [1, 1] and not any(c for _, c in dot)


def _glyph(draw):
    g = ufoLib2.objects.Glyph("test")
    draw(g.getPointPen())
    return g


def test_single_point_closed_and_quadratic_contours():
    def single(pp):
        pp.beginPath()
        pp.addPoint((10, 20), "move")
        pp.endPath()

    (pieces, closed), = glyph_paths(_glyph(single))
    assert not closed and len(pieces) == 1
    assert np.array_equal(pc.start(pieces[0]), [10, 20]) and np.array_equal(pc.end(pieces[0]), [10, 20])

    def square(pp):  # closed: a closing line is added
        pp.beginPath()
        for x, y in [(0, 0), (100, 0), (100, 100), (0, 100)]:
            pp.addPoint((x, y), "line")
        pp.endPath()

    (pieces, closed), = glyph_paths(_glyph(square))
    assert closed and len(pieces) == 4 and np.array_equal(pc.end(pieces[-1]), [0, 0])

    def quad(pp):  # a TrueType run with an implied on-curve point, open
        pp.beginPath()
        pp.addPoint((0, 0), "move")
        pp.addPoint((50, 100))
        pp.addPoint((150, 100))
        pp.addPoint((200, 0), "qcurve")
        pp.endPath()

    (pieces, closed), = glyph_paths(_glyph(quad))
    assert not closed and [pc.degree(p) for p in pieces] == [2, 2]
    assert np.allclose(pc.end(pieces[0]), (100, 100))

    def zero_segments(pp):  # a dot drawn as a zero-length line
        pp.beginPath()
        pp.addPoint((5, 5), "move")
        pp.addPoint((5, 5), "line")
        pp.endPath()

    (pieces, closed), = glyph_paths(_glyph(zero_segments))
    assert not closed and len(pieces) == 1 and np.all(pc.cartesian(pieces[0]) == 5)


def test_components_and_names(skeleton):
    six = glyph_paths(skeleton["six"])
    (nine,) = [c for c in skeleton["nine"].components]
    rotated = component_paths(skeleton, nine)
    xx, xy, yx, yy, dx, dy = tuple(nine.transformation)
    assert (xx, yy) == (-1, -1)
    p0 = pc.start(six[0][0][0])
    assert np.allclose(pc.start(rotated[0][0][0]), (-p0[0] + dx, -p0[1] + dy))
    assert glyph_names_for(skeleton, ["A", "0", "eacute", "g.ss01"]) == \
        ["A", "zero", "eacute", "g.ss01"]
    with pytest.raises(ParseError):
        glyph_names_for(skeleton, ["Ω"])
    with pytest.raises(ParseError):
        load_ufo(SUBSET.parent / "missing.ufo")
    with pytest.raises(ParseError):
        contour_paths([object()])

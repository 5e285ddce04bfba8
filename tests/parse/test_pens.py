"""morph.parse.pens: recording and drawing contours, and the glyph and skeleton readers'
rules for open contours."""

import numpy as np
import pytest

from morph import piece as pc
from morph.errors import ParseError


def test_recording_pen_round_trip_and_glyph_contour_rules():
    """draw_paths then record_contours gives back the pieces (BasePen splits a
    TrueType run at its implied on-curve point); the glyph reader refuses an open
    contour that does not end at its start, the skeleton reader keeps it open."""
    from morph.parse.glyphs import _filled_loop
    from morph.parse.pens import closing_line, draw_paths, record_contours
    from morph.parse.ufo import _skeleton_path

    tri = [pc.line((0, 0), (4, 0)), pc.quadratic((4, 0), (5, 3), (2, 4)),
           pc.cubic((2, 4), (1, 4), (0, 2), (0, 1))]
    hook = [pc.line((10, 0), (12, 0)), pc.cubic((12, 0), (13, 1), (13, 2), (12, 3))]
    contours = record_contours(lambda pen: draw_paths(pen, [(tri, True), (hook, False)]), "t")
    assert [c.closed for c in contours] == [True, False]
    for got, want in ((contours[0].pieces, tri), (contours[1].pieces, hook)):
        assert len(got) == len(want)
        assert all(np.array_equal(pc.cartesian(a), pc.cartesian(b)) for a, b in zip(got, want))
    closed = closing_line(contours[0])
    assert len(closed) == 4 and np.array_equal(pc.end(closed[-1]), [0, 0])
    assert len(_filled_loop(contours[0], "t")) == 4
    with pytest.raises(ParseError, match="open contour"):
        _filled_loop(contours[1], "t")
    pieces, is_closed = _skeleton_path(contours[1])
    assert not is_closed and len(pieces) == 2

    def qrun(pen):  # one TrueType run with an implied on-curve point at (2, 2)
        pen.moveTo((0, 0))
        pen.qCurveTo((1, 2), (3, 2), (4, 0))
        pen.closePath()

    (run,) = record_contours(qrun, "q")
    assert [pc.degree(p) for p in run.pieces] == [2, 2]
    assert np.allclose(pc.end(run.pieces[0]), (2, 2))

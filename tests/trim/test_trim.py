"""morph.trim's API: fill_region (a region's loops filled under a fill rule) against
exact areas and an independent winding count; orient_region hands it crossing loops."""

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
from shapely.geometry import LineString

from morph import piece as pc
from morph import moments as mo
from morph.region import orient_region, reverse_loop
from morph.trim import fill_region


def _square(x, y, s):
    pts = [(x, y), (x + s, y), (x + s, y + s), (x, y + s)]
    return [pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)]


def test_fill_region_overlapping_squares():
    """Two overlapping squares (same direction): nonzero is the union (one loop),
    even-odd the union minus the overlap (the lens becomes a hole: two loops that
    touch at the crossings, or one figure; area 100 + 100 - 2 * 25)."""
    from morph.trim import fill_region

    loops = [_square(0, 0, 10), _square(5, 5, 10)]
    union = fill_region(loops, "nonzero")
    assert len(union) == 1 and abs(mo.region_area(union) - 175.0) < 1e-9
    xor = fill_region(loops, "evenodd")
    assert abs(mo.region_area(xor) - 150.0) < 1e-9
    # orient_region routes crossing loops to on_crossing, and refuses them without it
    assert abs(mo.region_area(orient_region(loops, "nonzero", fill_region)) - 175.0) < 1e-9
    with pytest.raises(ValueError, match="cross"):
        orient_region(loops, "nonzero")


def test_fill_region_figure_eight_and_opposite_squares():
    from morph.trim import fill_region

    eight = [[pc.line((0, 0), (20, 20)), pc.line((20, 20), (20, 0)),
              pc.line((20, 0), (0, 10)), pc.line((0, 10), (0, 0))]]
    out = fill_region(eight, "nonzero")
    # both lobes filled, each counter-clockwise
    assert len(out) == 2 and all(mo.loop_area(l) > 0 for l in out)
    # a square and an opposite-direction square inside crossing it: nonzero keeps
    # only where the windings do not cancel
    outer = _square(0, 0, 10)
    inner = reverse_loop(_square(5, 2, 10))
    out = fill_region([outer, inner], "nonzero")
    assert abs(mo.region_area(out) - (100 + 100 - 2 * 40)) < 1e-9


def _winding(x, pts):
    """Signed crossing count of a closed polygon around point x (independent)."""
    a, b = np.asarray(pts, float), np.roll(np.asarray(pts, float), -1, axis=0)
    w = 0
    for (ax, ay), (bx, by) in zip(a, b):
        if (ay <= x[1] < by) or (by <= x[1] < ay):
            cx = ax + (x[1] - ay) * (bx - ax) / (by - ay)
            if cx > x[0]:
                w += 1 if by > ay else -1
    return w


def test_fill_region_bow_tie_and_star_rules():
    bow = [pc.line((0, 0), (80, 80)), pc.line((80, 80), (80, 0)), pc.line((80, 0), (0, 80)),
           pc.line((0, 80), (0, 0))]
    got = fill_region([bow], "nonzero")
    assert len(got) == 2 and mo.region_area(got) == pytest.approx(3200.0, rel=1e-9)
    star_pts = [(50, 0), (79, 90), (2, 35), (98, 35), (21, 90)]
    star = [pc.line(star_pts[i], star_pts[(i + 1) % 5]) for i in range(5)]
    faces = shapely.polygonize([shapely.unary_union(LineString(star_pts + star_pts[:1]))])
    wind = [(_winding(f.representative_point().coords[0], star_pts), f.area)
            for f in faces.geoms]
    assert len(wind) == 6
    nonzero = sum(a for w, a in wind if w != 0)
    evenodd = sum(a for w, a in wind if w % 2)
    assert mo.region_area(fill_region([star], "nonzero")) == pytest.approx(nonzero, rel=1e-9)
    assert mo.region_area(fill_region([star], "evenodd")) == pytest.approx(evenodd, rel=1e-9)

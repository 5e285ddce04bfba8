"""The parts of the trimming engine (morph.trim.*) against independent computations:
shapely for areas and distances, analytic crossings and depths."""

import numpy as np
import pytest
import shapely
from shapely.geometry import LineString, Point, Polygon

from morph import piece as pc
from morph.trim import boundary, fill_region
from morph.trim.flatten import tag_loops
from morph.trim.holes import Membership, deepest_point
from morph.trim.lift import newton_crossings
from morph.trim.topology import drop_slivers, fill_holes, filled_rings, ring_area


def _square(x0, y0, s, ccw=True):
    p = [(x0, y0), (x0 + s, y0), (x0 + s, y0 + s), (x0, y0 + s)]
    if not ccw:
        p = p[::-1]
    return [pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]


def _poly(loop, tol=1e-4):
    return pc.flatten_loop(loop, tol)


# ------------------------------------------------------------------ flatten

def test_tags_lie_on_their_pieces():
    loop = list(pc.circle((3.0, -2.0), 5.0)) + []
    eps, grid = 1e-3, 1e-3
    tg = tag_loops([loop], eps, grid)
    pts = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
    assert np.abs(tg.to_float(tg.q) - pts).max() <= grid / np.sqrt(2) + 1e-12
    # every segment's middle is within eps + grid of the circle (flattening bound)
    mid = tg.to_float(0.5 * (tg.q + tg.q[tg.nxt]))
    r = np.hypot(mid[:, 0] - 3.0, mid[:, 1] + 2.0)
    assert np.abs(r - 5.0).max() <= eps + grid
    # segment parameter ranges tile every piece
    for k in range(len(loop)):
        sel = tg.piece == k
        assert tg.t0[sel].min() == 0.0 and tg.t1[sel].max() == 1.0


def test_pieces_shorter_than_the_grid_vanish_but_loops_stay_closed():
    p = [(0, 0), (1, 0), (1, 1e-9), (1, 1), (0, 1)]
    loop = [pc.line(p[i], p[(i + 1) % 5]) for i in range(5)]
    tg = tag_loops([loop], 1e-4, 1e-4)
    assert len(tg.q) == 4 and 1 not in set(tg.piece.tolist())


# ------------------------------------------------------------------ topology

@pytest.mark.parametrize("rule, area", [("positive", 7.0), ("nonzero", 7.0), ("evenodd", 6.0)])
def test_fill_rules_on_overlapping_squares(rule, area):
    tg = tag_loops([_square(0, 0, 2), _square(1, 1, 2)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), rule)
    got = sum(ring_area(r.q) for r in rings) * tg.grid ** 2
    assert got == pytest.approx(area, rel=1e-6)
    assert all((ring_area(r.q) > 0) != r.hole for r in rings)


def test_positive_ignores_negative_loops():
    tg = tag_loops([_square(0, 0, 2), _square(5, 0, 2, ccw=False)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), "positive")
    assert len(rings) == 1 and ring_area(rings[0].q) * tg.grid ** 2 == pytest.approx(4.0)


def test_slivers_dropped_and_holes_filled():
    tg = tag_loops([_square(0, 0, 10), _square(2, 2, 3, ccw=False),
                    _square(12, 12, 1e-3 * 4, ccw=True)], 1e-4, 1e-3)
    rings = filled_rings(tg.paths(), "nonzero")
    assert sorted(r.hole for r in rings) == [False, False, True]
    thin = drop_slivers(rings, 1.5)  # the 4-unit square (mean width 2) is no sliver...
    assert len(thin) == 3
    assert len(drop_slivers(rings, 4.0)) == 2  # ...at a width threshold of 4 units it is
    hole = [i for i, r in enumerate(thin) if r.hole]
    assert len(fill_holes(thin, hole)) == 2


# ------------------------------------------------------------------ lift

def test_batched_newton_finds_line_circle_crossings():
    circle = pc.circle((0.0, 0.0), 1.0)  # four quarter arcs
    line = pc.line((-2.0, 0.5), (2.0, 0.5))
    stacked = pc.stack([circle[0], circle[1], line])
    # the line crosses the first two quarters at x = +-sqrt(3)/2
    s, u, ok = newton_crossings(stacked, np.array([0, 1]), np.array([0.6, 0.4]),
                                np.array([2, 2]), np.array([0.7, 0.3]),
                                np.array([[0.87, 0.5], [-0.87, 0.5]]), 0.1, 1e-12)
    assert ok.all()
    x = pc.jet_many(stacked, np.array([0, 1]), s)[0]
    assert np.allclose(x, [[np.sqrt(3) / 2, 0.5], [-np.sqrt(3) / 2, 0.5]], atol=1e-12)


@pytest.mark.parametrize("angle_deg", [0.5, 3.0, 20.0])
def test_newton_reaches_shallow_crossings_as_far_as_the_polylines_can_slide(angle_deg):
    # two lines crossing at the origin at a small angle; a polyline crossing of
    # copies moved by d across each lies up to d / sin(alpha / 2) along the wedge
    a = np.radians(angle_deg)
    p = pc.line((-1.0, 0.0), (1.0, 0.0))
    q = pc.line((-np.cos(a), -np.sin(a)), (np.cos(a), np.sin(a)))
    stacked = pc.stack([p, q])
    d = 1e-4
    slide = d / np.sin(a / 2)
    for off, accept in ((0.9 * slide, True), (3.0 * slide, False)):
        guess = np.array([[off, 0.0]])
        args = (stacked, np.array([0]), np.array([0.5 + off / 2]), np.array([1]),
                np.array([0.5 + off / 2]), guess)
        s, u, ok = newton_crossings(*args, reach=d, atol=1e-12, shallow=d)
        assert bool(ok[0]) == accept
        if accept:
            assert np.allclose(pc.jet_many(stacked, np.array([0]), s)[0], 0.0, atol=1e-12)
        # without the allowance only a guess within reach is taken
        assert not newton_crossings(*args, reach=d, atol=1e-12)[2][0]


def test_spike_cut_keeps_the_larger_part_when_the_long_side_is_flanked():
    # a hole ring (clockwise) of five runs: the neighbours of the long left side
    # (bottom and right sides) cross near the far corner, where two short runs
    # close a sliver; the cut must keep the triangle, not the sliver
    from morph.trim.lift import _cut_spikes

    pts = [(1.006, -0.874), (1.045, -0.765), (1.008, -0.729), (-0.767, -0.729),
           (0.019, 1.161), (1.064, -1.087)]
    out = [pc.line(pts[0], pts[1]), pc.line(pts[2], pts[3]), pc.line(pts[3], pts[4]),
           pc.line(pts[4], pts[5]), pc.line(pts[5], pts[0])]
    ends = [0.5 * (pc.end(out[k]) + pc.start(out[(k + 1) % 5])) for k in range(5)]
    runs = [(out, ends)]
    _cut_spikes(runs, 0.05)
    loop, _ = runs[0]
    # the bottom and the right side cross at y = -0.729
    x_cross = 0.019 + (1.161 + 0.729) / (1.161 + 1.087) * (1.064 - 0.019)
    triangle = 0.5 * (x_cross + 0.767) * (1.161 + 0.729)
    assert len(loop) == 3
    assert pc.loop_area(loop) == pytest.approx(-triangle, rel=1e-9)


def test_boundary_of_two_crossing_circles_is_exact_arcs():
    a = list(pc.circle((0.0, 0.0), 1.0))
    b = list(pc.circle((1.0, 0.0), 1.0))
    loops = boundary([a, b], 1e-4, 1e-4, "nonzero")
    assert len(loops) == 1
    area = pc.region_area(loops)
    exact = 2 * np.pi - (2 * np.pi / 3 - np.sqrt(3) / 2)  # union of two unit disks
    assert area == pytest.approx(exact, abs=1e-9)
    for loop in loops:
        for p in loop:  # every output point on one of the circles, to rounding
            x = pc.evaluate(p, np.linspace(0, 1, 9))
            d = np.minimum(np.abs(np.hypot(*x.T) - 1), np.abs(np.hypot(x[:, 0] - 1, x[:, 1]) - 1))
            assert d.max() < 1e-9


# ------------------------------------------------------------------ holes

def test_deepest_point_of_a_square_hole_with_an_island():
    ring = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    island = np.array([[4, 4], [6, 4], [6, 6], [4, 6]], float)
    x, depth = deepest_point(ring, [island])
    poly = Polygon(ring, [island])
    assert poly.contains(Point(x))
    assert depth == pytest.approx(poly.boundary.distance(Point(x)), abs=1e-9)
    # the best points lie on the diagonals, equally far from the outer corner's sides
    # and the island's corner: a = sqrt(2) (4 - a)
    assert depth == pytest.approx(4 * np.sqrt(2) / (1 + np.sqrt(2)), abs=1e-3)


def test_membership_with_an_open_path():
    path = pc.cubic((0, 0), (3, 4), (6, -4), (10, 0))
    a = [[path, pc.reverse(path)]]  # a path traced forward and back: a curve
    b = [list(pc.circle((0.0, 0.0), 1.0))]
    member = Membership(a, b, 0.01)
    line = LineString(pc.flatten(path, 1e-5)[0])
    rng = np.random.default_rng(1)
    for x in rng.uniform([-2, -4], [12, 4], size=(60, 2)):
        d = line.distance(Point(x))
        if abs(d - 1.0) > 0.02:
            assert member(x) == (d < 1.0), (x, d)


# ------------------------------------------------------------------ fill_region

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
    assert len(got) == 2 and pc.region_area(got) == pytest.approx(3200.0, rel=1e-9)
    star_pts = [(50, 0), (79, 90), (2, 35), (98, 35), (21, 90)]
    star = [pc.line(star_pts[i], star_pts[(i + 1) % 5]) for i in range(5)]
    faces = shapely.polygonize([shapely.unary_union(LineString(star_pts + star_pts[:1]))])
    wind = [(_winding(f.representative_point().coords[0], star_pts), f.area)
            for f in faces.geoms]
    assert len(wind) == 6
    nonzero = sum(a for w, a in wind if w != 0)
    evenodd = sum(a for w, a in wind if w % 2)
    assert pc.region_area(fill_region([star], "nonzero")) == pytest.approx(nonzero, rel=1e-9)
    assert pc.region_area(fill_region([star], "evenodd")) == pytest.approx(evenodd, rel=1e-9)

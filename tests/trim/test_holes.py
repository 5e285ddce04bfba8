"""morph.trim.holes: the deepest point of a hole and the exact membership test, against
shapely distances and analytic depths."""

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
from shapely.geometry import LineString, Point, Polygon

from morph import piece as pc
from morph import polyline as pl
from morph.trim.holes import DEPTH_REL, Membership, deepest_point


def test_deepest_point_of_a_square_hole_with_an_island():
    ring = np.array([[0, 0], [10, 0], [10, 10], [0, 10]], float)
    island = np.array([[4, 4], [6, 4], [6, 6], [4, 6]], float)
    x, depth = deepest_point(ring, [island])
    poly = Polygon(ring, [island])
    assert poly.contains(Point(x))
    assert depth == pytest.approx(poly.boundary.distance(Point(x)), abs=1e-9)
    # the best points lie on the diagonals, equally far from the outer corner's sides
    # and the island's corner: a = sqrt(2) (4 - a); the search stops once its cells
    # are below DEPTH_REL of the depth found (holes.DEPTH_REL: a point that deep is
    # all the hole test needs)
    best = 4 * np.sqrt(2) / (1 + np.sqrt(2))
    assert best * (1 - DEPTH_REL) <= depth <= best + 1e-9


@pytest.mark.parametrize("seed", range(8))
def test_deepest_point_of_a_thin_annulus_around_an_island(seed):
    """A round hole around an island (both polygons) leaving an annulus 0.1-4 units
    wide: the point is in the annulus (not in the island, which every scanline
    across the hole ring crosses) and about width / 2 deep."""
    rng = np.random.default_rng(seed)
    radius, width = rng.uniform(40, 120), rng.uniform(0.1, 4.0)
    t = np.linspace(0, 2 * np.pi, int(rng.integers(100, 400)), endpoint=False)
    c = rng.uniform(-300, 300, 2)
    ring = np.c_[radius * np.cos(t), radius * np.sin(t)] + c
    island = np.c_[(radius - width) * np.cos(t + 0.01), (radius - width) * np.sin(t + 0.01)] + c
    x, depth = deepest_point(ring, [island])
    poly = Polygon(ring, [island])
    assert poly.contains(Point(x))
    assert depth == pytest.approx(poly.boundary.distance(Point(x)), abs=1e-9)
    sag = radius * (1 - np.cos(np.pi / len(t)))  # the polygons' chords widen the gap
    assert 0.3 * width <= depth <= 0.5 * width + sag


def test_membership_with_loops_that_round_to_a_point_or_a_line():
    """Loops of A with no area on the predicate's grid (a square 1e-9 wide, a
    sliver 1e-9 thin, and a path traced forward and back that is 1e-9 long) are
    still A: the points within B's reach of them are in A ⊕ B (Clipper refuses
    such paths: a ClipperException from an inset, exit 1)."""
    b = [list(pc.circle((0.0, 0.0), 1.0))]
    sq = [pc.line((5, 0), (5 + 1e-9, 0)), pc.line((5 + 1e-9, 0), (5 + 1e-9, 1e-9)),
          pc.line((5 + 1e-9, 1e-9), (5, 1e-9)), pc.line((5, 1e-9), (5, 0))]
    sliver = [pc.line((0, 5), (3, 5)), pc.line((3, 5), (3, 5 + 1e-9)),
              pc.line((3, 5 + 1e-9), (0, 5 + 1e-9)), pc.line((0, 5 + 1e-9), (0, 5))]
    dash = pc.line((-5, 0), (-5 + 1e-9, 0))
    member = Membership([sq, sliver, [dash, pc.reverse(dash)]], b, 0.01)
    for x, inside in (((5.5, 0.5), True), ((6.2, 0.0), False), ((1.5, 5.9), True),
                      ((1.5, 6.2), False), ((-5.0, 0.9), True), ((-5.0, 1.2), False),
                      ((0.0, 0.0), False)):
        assert member(np.array(x)) == inside, x


def test_membership_with_an_open_path():
    path = pc.cubic((0, 0), (3, 4), (6, -4), (10, 0))
    a = [[path, pc.reverse(path)]]  # a path traced forward and back: a curve
    b = [list(pc.circle((0.0, 0.0), 1.0))]
    member = Membership(a, b, 0.01)
    line = LineString(pl.flatten(path, 1e-5)[0])
    rng = np.random.default_rng(1)
    for x in rng.uniform([-2, -4], [12, 4], size=(60, 2)):
        d = line.distance(Point(x))
        if abs(d - 1.0) > 0.02:
            assert member(x) == (d < 1.0), (x, d)


def test_membership_of_scattered_loops_against_shapely():
    # loops of A far apart and a hole-less B: the test reads only the loops of A
    # near x - B, and must agree with the exact distance everywhere
    rng = np.random.default_rng(7)
    centres = rng.uniform(-200, 200, size=(12, 2))
    a = [list(pc.circle(c, r)) for c, r in zip(centres, rng.uniform(1, 6, 12))]
    b = [list(pc.circle((0.0, 0.0), 2.0))]
    member = Membership(a, b, 0.01)
    union = shapely.union_all([Polygon(pl.flatten_loop(loop, 1e-4)) for loop in a])
    xs = np.concatenate([rng.uniform(-210, 210, size=(150, 2)),
                         centres + rng.uniform(-9, 9, size=(12, 2))])
    d = np.array([union.distance(Point(x)) for x in xs])
    clear = np.abs(d - 2.0) > 0.05
    for x, dx in zip(xs[clear], d[clear]):
        assert member(x) == (dx < 2.0), (x, dx)
    # all the points at once (their loops found together), as one at a time
    got = member.many(xs)
    assert np.array_equal(got[clear], d[clear] < 2.0) and got[clear].any()


@pytest.mark.parametrize("direct", [0, 1 << 20])
def test_meeting_boxes_found_through_a_grid_as_one_by_one(direct, monkeypatch):
    """:func:`morph.trim.holes._meeting_many`: the boxes meeting each query box
    (touching counts), only those marked ok, found through a grid of all the
    boxes (``direct`` 0) or query by query against every box (MEETING_DIRECT
    above the pairs' count), as a loop over the queries finds them; a query
    meeting nothing has none."""
    from morph.trim import holes
    from morph.trim.holes import _meeting_many

    monkeypatch.setattr(holes, "MEETING_DIRECT", direct)

    rng = np.random.default_rng(3)
    lo = rng.integers(0, 100, (40, 2))
    boxes = np.concatenate([lo, lo + rng.integers(0, 30, (40, 2))], axis=1)
    boxes[5] = [20, 20, 20, 20]          # a point
    boxes[6] = [0, 50, 100, 50]          # a line
    ok = rng.random(40) < 0.7
    ok[5] = ok[6] = True
    qlo = rng.integers(-20, 120, (25, 2))
    qhi = qlo + rng.integers(0, 25, (25, 2))
    qlo[0], qhi[0] = (500, 500), (510, 510)   # far from every box
    qlo[1], qhi[1] = (10, 20), (20, 30)       # touching the point box at a corner
    ids, first = _meeting_many(boxes, qlo, qhi, ok)
    for i in range(len(qlo)):
        want = [k for k in range(40) if ok[k] and np.all(boxes[k, :2] <= qhi[i])
                and np.all(boxes[k, 2:] >= qlo[i])]
        assert ids[first[i]:first[i + 1]].tolist() == want
    assert first[1] == first[0] and len(ids) > 25 and 5 in ids[first[1]:first[2]]


def _star(rng, c, r, n, inner=0.5):
    """A star-shaped polygon (clockwise when ``cw``) round c: n vertices at radii
    between inner r and r."""
    t = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = r * rng.uniform(inner, 1.0, n)
    return np.c_[rad * np.cos(t), rad * np.sin(t)] + c


def test_deepest_points_together_are_those_of_one_hole_at_a_time():
    """All holes' grid searches in one batch give the very points and depths of
    :func:`deepest_point` called hole by hole: star-shaped holes with and without
    islands, large ones (the search on thinned polygons first), thin annuli (the
    first round finds no point inside: the scanline fallback), on integer grid
    vertices as the trimming gives them, with and without ``enough``.  The
    comparison sees a point moved by one ulp."""
    from morph.trim.holes import deepest_points

    rng = np.random.default_rng(5)
    holes = []
    for k in range(40):
        c = rng.uniform(-500, 500, 2)
        r = rng.uniform(5, 60)
        ring = _star(rng, c, r, int(rng.integers(3, 40 if k % 5 else 700)))
        if k % 7 == 0:
            ring = np.rint(ring)
        islands = []
        if k % 3 == 0:
            islands = [_star(rng, c, 0.3 * r, 12, inner=0.9)]
        if k % 11 == 5:   # an annulus narrower than the grid's cells
            t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
            ring = np.c_[r * np.cos(t), r * np.sin(t)] + c
            islands = [np.c_[(r - 0.05) * np.cos(t + 0.01), (r - 0.05) * np.sin(t + 0.01)] + c]
        holes.append((ring, islands))
    for enough in (np.inf, 4.0):
        x, d = deepest_points(holes, enough=enough)
        for h, (ring, islands) in enumerate(holes):
            x1, d1 = deepest_point(ring, islands, enough=enough)
            assert np.array_equal(x[h], x1) and d[h] == d1, h
    assert not np.array_equal(np.nextafter(x[0], np.inf), deepest_point(*holes[0], enough=4.0)[0])
    assert deepest_points([], enough=1.0)[0].shape == (0, 2)


def _membership_loop_by_loop(m, region_a, depth, areas):
    """The rounded loops, paths and boxes of :class:`Membership` written loop by
    loop (the reference for the arrays it builds them with)."""
    pa = pl.flatten_loops(region_a, depth / 10.0)
    size = min(float(np.ptp(np.concatenate(p), axis=0).max()) for p in (pa, m.pb))
    flat = (np.abs(areas) <= 1e-9 * size * size).tolist()
    closed = [m._int(p) for p, f in zip(pa, flat) if not f]
    curves = [m._int(np.vstack([p, p[:1]]))[:len(p) // 2 + 1] for p, f in zip(pa, flat) if f]

    def boxes(polys):
        if not polys:
            return np.zeros((0, 4), np.int64)
        return np.array([np.concatenate([p.min(axis=0), p.max(axis=0)]) for p in polys])

    return closed, curves, boxes(closed), boxes(curves)


@pytest.mark.parametrize("seed", range(4))
def test_membership_rounds_all_loops_at_once_as_loop_by_loop(seed):
    """The operand's loops rounded, split into closed loops and paths (traced forward
    and back: their first half) and boxed all at once, as loop by loop: random
    polygons and strokes, at a few depths (a path cut one point short, its far end
    left out of it and of its box, is seen)."""
    from morph import moments as mo

    rng = np.random.default_rng(seed)
    region = []
    for _ in range(int(rng.integers(3, 12))):
        pts = rng.uniform(-50, 50, (int(rng.integers(2, 7)), 2)) + rng.uniform(-500, 500, 2)
        if rng.random() < 0.5:   # a stroke: there and back, no area
            pts = np.vstack([pts, pts[-2:0:-1] + rng.normal(0, 1e-9, (len(pts) - 2, 2))])
        region.append([pc.line(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))])
    nib = [list(pc.circle((0.0, 0.0), 5.0))]
    areas = mo.loop_areas(region)
    for depth in (0.05, 0.4, 3.0):
        m = Membership(region, nib, depth, areas)
        closed, curves, box_a, box_c = _membership_loop_by_loop(m, region, depth, areas)
        assert len(m.pa) == len(closed) and len(m.curves) == len(curves) and curves
        assert all(np.array_equal(a, b) for a, b in zip(m.pa, closed))
        assert all(np.array_equal(a, b) for a, b in zip(m.curves, curves))
        assert np.array_equal(m.box_a, box_a) and np.array_equal(m.box_c, box_c)
        assert box_a.dtype == m.box_a.dtype == np.int64


@pytest.mark.parametrize("nib", ["square", "circle"])
def test_membership_without_clipper_where_apart_as_clipper(nib, monkeypatch):
    """Membership.many answers the points where the rounded loops of A and x − B
    are apart without Clipper (:meth:`Membership._apart`): on every point it gives
    Clipper's answer on all the loops (closed polygons, strokes traced there and
    back, a stroke that rounds to one point), on points of the predicate's own
    grid, so that many touch a loop exactly.  Most points are decided apart, and
    a contact test that missed touching segments would be seen (square nib)."""
    import morph.trim.holes as ho

    rng = np.random.default_rng(11 if nib == "square" else 12)
    region = []
    for c in ((0, 0), (30, 5), (10, 30)):
        p = np.rint(_star(rng, np.array(c, float), 8.0, 9))
        region.append([pc.line(p[k], p[(k + 1) % len(p)]) for k in range(len(p))])
    for c in ((-20, 20), (40, 30)):
        p = np.rint(np.array(c, float) + rng.uniform(-10, 10, (4, 2)))
        path = [pc.line(p[k], p[k + 1]) for k in range(3)]
        region.append(path + [pc.reverse(q) for q in path[::-1]])
    dot = pc.line((20.0, -15.0), (20.0 + 1e-9, -15.0))
    region.append([dot, pc.reverse(dot)])
    if nib == "square":
        s = [(-2, -2), (2, -2), (2, 2), (-2, 2)]
        b = [[pc.line(s[k], s[(k + 1) % 4]) for k in range(4)]]
    else:
        b = [list(pc.circle((0.0, 0.0), 2.5))]
    m = Membership(region, b, 1.0)   # grid 0.05: the points below are on it
    xs = np.rint(rng.uniform([-35, -25], [55, 45], (500, 2)) / m.grid) * m.grid
    xs[:40] = np.rint(np.array([[20.0, -15.0]]) + rng.integers(-3, 4, (40, 2)))  # round the dot
    every = m._all()  # the closed loops and the paths of A, all of them
    want = np.array([m._meets(x, *every) for x in xs])
    assert np.array_equal(m.many(xs), want)
    assert 0.1 < want.mean() < 0.9
    # how many the numpy test decided, and what a contact test blind to touching gives
    calls = []
    orig = ho.Membership._meets
    monkeypatch.setattr(ho.Membership, "_meets",
                        lambda self, *a: calls.append(1) or orig(self, *a))
    m2 = Membership(region, b, 1.0)
    m2.many(xs)
    assert len(calls) < 0.5 * len(xs)
    if nib != "square":
        return  # the square's sides lie on the grid: they touch the loops exactly
    monkeypatch.setattr(ho, "_segments_meet", lambda a, b_, c, d: (
        (ho._orient(a, b_, c) * ho._orient(a, b_, d) < 0)
        & (ho._orient(c, d, a) * ho._orient(c, d, b_) < 0)))
    assert not np.array_equal(Membership(region, b, 1.0).many(xs), want)


def _ring_loop(c, radius, n, cw=False):
    """A regular n-gon round c as a loop of lines (clockwise when ``cw``)."""
    t = np.linspace(0, 2 * np.pi, n, endpoint=False) * (-1 if cw else 1)
    p = np.rint(np.c_[radius * np.cos(t), radius * np.sin(t)] + c)
    return [pc.line(p[k], p[(k + 1) % n]) for k in range(n)]


def test_membership_decides_counters_by_the_summed_winding(monkeypatch):
    """Points in a glyph's counters (a nib inside an O's inner loop is inside its
    outer loop too) are decided apart without Clipper, by the winding numbers of
    all the glyph's loops summed: an O, a figure with two counters, and two
    loops overlapping (winding 2 where they overlap: inside, as Clipper's nonzero
    rule fills them; an even-odd sum would call it outside).  Every answer is
    Clipper's on all the loops, and the points outside (in counters too) need
    almost no Clipper call (the test decides "apart" only: points inside go to
    Clipper)."""
    import morph.trim.holes as ho

    region = [_ring_loop((0, 0), 40, 48), _ring_loop((0, 0), 25, 40, cw=True),
              _ring_loop((120, 0), 45, 48), _ring_loop((105, 0), 12, 24, cw=True),
              _ring_loop((135, 0), 12, 24, cw=True),
              _ring_loop((0, 100), 30, 36), _ring_loop((30, 100), 30, 36)]
    b = [list(pc.circle((0.0, 0.0), 4.0))]
    m = Membership(region, b, 1.0)
    rng = np.random.default_rng(5)
    xs = np.rint(rng.uniform([-50, -50], [170, 140], (300, 2)) / m.grid) * m.grid
    inner = np.array([[0, 0], [5, -3], [105, 0], [135, 2], [15, 100], [14, 96]], float)
    xs = np.vstack([inner, xs])
    want = np.array([m._meets(x, *m._all()) for x in xs])
    calls = []
    orig = ho.Membership._meets
    monkeypatch.setattr(ho.Membership, "_meets",
                        lambda self, *a: calls.append(a) or orig(self, *a))
    got = Membership(region, b, 1.0).many(xs)
    assert np.array_equal(got, want)
    assert list(want[:len(inner)]) == [False] * 4 + [True] * 2
    out = {tuple(x) for x, w in zip(xs, want) if not w}
    assert len([a for a in calls if tuple(a[0]) in out]) < 0.1 * len(out)
    calls.clear()
    Membership(region, b, 1.0).many(inner[:4])   # the counters
    assert not calls


def test_points_deep_enough_are_inside_and_deep_enough_or_the_deepest():
    """points_deep_enough: each point lies inside its hole at the depth it reports
    (measured again on the polygons); it is at least ``enough`` deep where the
    full search (deepest_point) gets that deep, and is the full search's point
    elsewhere (thin annuli: the coarse grid finds nothing inside them)."""
    from morph.trim.holes import _depth, points_deep_enough

    rng = np.random.default_rng(9)
    holes = []
    for k in range(30):
        c = rng.uniform(-500, 500, 2)
        r = rng.uniform(5, 60)
        ring = _star(rng, c, r, int(rng.integers(3, 40)))
        islands = [_star(rng, c, 0.3 * r, 12, inner=0.9)] if k % 3 == 0 else []
        if k % 7 == 5:
            t = np.linspace(0, 2 * np.pi, 90, endpoint=False)
            ring = np.c_[r * np.cos(t), r * np.sin(t)] + c
            islands = [np.c_[(r - 0.05) * np.cos(t + 0.01), (r - 0.05) * np.sin(t + 0.01)] + c]
        holes.append((ring, islands))
    for enough in (2.0, 6.0):
        x, d = points_deep_enough(holes, enough)
        coarse = 0
        for h, (ring, islands) in enumerate(holes):
            assert d[h] == _depth(x[h], ring, islands) and d[h] > 0, h
            x1, d1 = deepest_point(ring, islands, enough=enough)
            if d1 >= enough:
                assert d[h] >= enough
                coarse += not np.array_equal(x[h], x1)
            else:
                assert np.array_equal(x[h], x1) and d[h] == d1, h
        assert coarse > 5 and (d < enough).any()
    assert points_deep_enough([], 1.0)[0].shape == (0, 2)

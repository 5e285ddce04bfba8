"""morph.trim.flatten: tagged flattening on the integer grid, against the exact pieces."""

import numpy as np
import pytest

from morph import piece as pc
from morph import polyline as pl
from morph.trim.flatten import COARSE, tag_loops


def test_tags_lie_on_their_pieces():
    loop = list(pc.circle((3.0, -2.0), 5.0)) + []
    eps, grid = 1e-3, 1e-3
    tg = tag_loops([loop], eps, grid)
    pts = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
    assert np.abs(tg.to_float(tg.q) - pts).max() <= grid / np.sqrt(2) + 1e-12
    # every segment's middle is within COARSE eps + grid of the circle (a lone circle
    # is a simple arc nothing comes near: flattened coarsely, and only so)
    mid = tg.to_float(0.5 * (tg.q + tg.q[tg.nxt]))
    r = np.hypot(mid[:, 0] - 3.0, mid[:, 1] + 2.0)
    assert np.abs(r - 5.0).max() <= COARSE * eps + grid
    assert np.abs(r - 5.0).max() > 4 * eps
    # segment parameter ranges tile every piece
    for k in range(len(loop)):
        sel = tg.piece == k
        assert tg.t0[sel].min() == 0.0 and tg.t1[sel].max() == 1.0


def test_pieces_shorter_than_the_grid_vanish_but_loops_stay_closed():
    p = [(0, 0), (1, 0), (1, 1e-9), (1, 1), (0, 1)]
    loop = [pc.line(p[i], p[(i + 1) % 5]) for i in range(5)]
    tg = tag_loops([loop], 1e-4, 1e-4)
    assert len(tg.q) == 4 and 1 not in set(tg.piece.tolist())


def _needle(angle, width, shift):
    """A closed needle: out along one leg, a short tip, back along the other,
    ``width`` apart (the out leg on the right of the back one), rotated and shifted."""
    rot = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    pts = [(0.0, 0.0), (-0.1, -width), (89.3, -width), (89.4, 0.0)]
    pts = [tuple(rot @ np.array(p) + shift) for p in pts]
    return [pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)], rot


def _heights(tg, rot, pieces_of_leg, s):
    """Height across the needle of the rounded polyline along the given pieces, at
    distances s along it (linear between its vertices)."""
    sel = np.isin(tg.piece, pieces_of_leg)
    a, b = tg.to_float(tg.q[sel]), tg.to_float(tg.q[tg.nxt[sel]])
    a, b = a @ rot, b @ rot  # back to the needle's frame
    out = np.full(len(s), np.nan)
    for (x0, y0), (x1, y1) in zip(a, b):
        lo, hi = min(x0, x1), max(x0, x1)
        m = (s >= lo) & (s <= hi) & (hi > lo)
        out[m] = y0 + (s[m] - x0) / (x1 - x0) * (y1 - y0)
    return out


def test_legs_closer_than_the_grid_keep_their_order():
    """Two legs of a needle closer than a grid step, whose ends round independently,
    must not swap sides (the needle's inside would change winding: an open crack in
    a filled region, as in amiri uniFDB3 + uniFCE4): rounded through the same hot
    pixels they coincide or keep their order, at every angle and offset."""
    rng = np.random.default_rng(7)
    grid = 0.014
    s = np.linspace(1.0, 88.0, 400)
    swapped = 0
    for _ in range(60):
        loop, rot = _needle(rng.uniform(0, 2 * np.pi), 10.0 ** rng.uniform(-5, -2.5),
                            rng.uniform(-1, 1, 2))
        tg = tag_loops([loop], 1e-3, grid)
        out, back = _heights(tg, rot, [1], s), _heights(tg, rot, [3], s)
        swapped += np.any(out > back + 1e-9)
        # every vertex still within half a grid diagonal of its own piece
        pts = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
        assert np.abs(tg.to_float(tg.q) - pts).max() <= grid * np.sqrt(2) + 1e-9
    assert swapped == 0


def test_pixel_crossing_test_agrees_with_shapely():
    """The hot-pixel test (segment box overlaps the unit square and the line passes
    closer than |d_x|/2 + |d_y|/2 across) against shapely's segment-square
    intersection, on random segments and pixels (touching cases excluded: measure
    zero)."""
    pytest.importorskip("shapely")
    import shapely

    from morph.trim.flatten import _line_crosses_square

    rng = np.random.default_rng(3)
    a = rng.uniform(-3, 3, (4000, 2))
    b = a + rng.normal(0, 2, (4000, 2)) * rng.choice([0.1, 1.0, 5.0], (4000, 1))
    c = np.rint(rng.uniform(-4, 4, (4000, 2)))
    lo, hi = np.minimum(a, b), np.maximum(a, b)
    boxes = np.all((lo < c + 0.5) & (hi > c - 0.5), axis=1)
    ours = boxes & _line_crosses_square(a, b, c)
    lines = shapely.linestrings(np.stack([a, b], axis=1))
    squares = shapely.box(c[:, 0] - 0.5, c[:, 1] - 0.5, c[:, 0] + 0.5, c[:, 1] + 0.5)
    theirs = shapely.intersects(lines, squares)
    assert 200 < theirs.sum() < 3800  # both outcomes well represented
    assert np.array_equal(ours, theirs)


def test_segment_ranges_end_near_their_next_vertex_with_hot_pixels():
    # loops that meet at joints one grid unit apart (a piece ending beside another's
    # start: hot pixels put vertices on segments at their start, with the start's
    # parameter).  Every segment's range [t0, t1] must map near its two vertices; a
    # vertex sharing its successor's parameter was given t1 = 1 (a whole piece for a
    # one-unit edge: EB Garamond w + i lifted a spike 15 tol long)
    rng = np.random.default_rng(8)
    eps, grid = 1e-3, 1e-2
    checked = 0
    for _ in range(40):
        c = rng.uniform(-1, 1, 2)
        a = rng.uniform(0, 2 * np.pi)
        d = np.array([np.cos(a), np.sin(a)])
        n = np.array([-d[1], d[0]])
        off = rng.uniform(0.3, 1.2) * grid * n   # the second loop's joint one unit away
        p0, p1, p2 = c - 3 * d, c, c + 3 * d + 2 * n
        loops = [[pc.line(p0, p1), pc.quadratic(p1, p1 + 2 * d - n, p2), pc.line(p2, p0)],
                 [pc.line(p1 + off, p1 + off + 3 * n), pc.line(p1 + off + 3 * n, p1 + off - 3 * d),
                  pc.line(p1 + off - 3 * d, p1 + off)]]
        tg = tag_loops(loops, eps, grid)
        x0 = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t0)])
        x1 = np.array([pc.evaluate(tg.pieces[k], t)[0] for k, t in zip(tg.piece, tg.t1)])
        reach = eps + grid
        assert np.hypot(*(x0 - tg.to_float(tg.q)).T).max() <= reach
        assert np.hypot(*(x1 - tg.to_float(tg.q[tg.nxt])).T).max() <= reach
        checked += int(np.sum(tg.t0 == tg.t0[tg.nxt]))
    assert checked > 0   # vertices sharing a parameter occurred


def _segment_gaps(tg, centre, radius):
    """Distance of each segment's middle from a circle."""
    mid = tg.to_float(0.5 * (tg.q + tg.q[tg.nxt]))
    return np.abs(np.hypot(mid[:, 0] - centre[0], mid[:, 1] - centre[1]) - radius)


def test_parts_near_another_loop_are_flattened_finer_the_nearer_they_are():
    """Two circles 0.5 eps apart at one point: where they meet the segments are
    within eps (+ rounding) of their own circle; elsewhere a segment is never
    farther from its own circle than it is from the other one (a part decided at
    tolerance e is more than 2 e + 2 (eps + grid) from every other part), so the
    flattening coarsens level by level away from the meeting point, to COARSE eps
    on the far side."""
    eps, grid = 1e-4, 1e-5
    ca, cb = (0.0, 0.0), (2.0 + 0.5 * eps, 0.0)
    a, b = pc.circle(ca, 1.0), pc.circle(cb, 1.0)
    tg = tag_loops([list(a), list(b)], eps, grid)
    first = tg.piece < len(a)
    own = np.where(first, _segment_gaps(tg, ca, 1.0), _segment_gaps(tg, cb, 1.0))
    other = np.where(first, _segment_gaps(tg, cb, 1.0), _segment_gaps(tg, ca, 1.0))
    close = other < 8 * eps
    assert close.sum() >= 8
    assert own[close].max() <= eps + grid
    assert np.all(own <= np.maximum(eps, other) + grid)
    # the intermediate levels are used: coarser than eps, yet within 2 COARSE eps
    mid = (other < 2 * COARSE * eps) & (own > 1.5 * (eps + grid))
    assert mid.sum() > 2
    assert own[other > 2 * COARSE * eps].max() > 4 * eps


def _random_loops(rng):
    """1-3 closed loops of 2-6 rational quadratics and cubics with random control
    points and weights: curls, cusps, crossings and near contacts."""
    loops = []
    for _ in range(int(rng.integers(1, 4))):
        n = int(rng.integers(2, 7))
        pts = rng.uniform(0, 10, (n, 2))
        loop = []
        for k in range(n):
            inner = rng.uniform(-2, 12, (int(rng.integers(1, 3)), 2))
            ctrl = np.vstack([pts[k], inner, pts[(k + 1) % n]])
            w = np.ones(len(ctrl))
            w[1:-1] = rng.uniform(0.3, 3.0, len(ctrl) - 2)
            loop.append(np.column_stack([ctrl * w[:, None], w]))
        loops.append(loop)
    return loops


def _membership(points, loops, rule, flat, reach):
    """Filled or not under ``rule`` at each point, the loops flattened within
    ``flat``; and whether each point is farther than ``reach`` from those polylines."""
    from morph.polyline import distance_to_others, winding_number

    polys = [pl.flatten_loop(loop, flat) for loop in loops]
    if not polys:
        return np.zeros(len(points), bool), np.ones(len(points), bool)
    w = winding_number(points, polys)
    far = np.isinf(distance_to_others(points, np.full(len(points), -1), polys, reach))
    return (w % 2 == 1) if rule == "evenodd" else (w != 0), far


def test_adaptive_flattening_fills_by_the_rule(monkeypatch):
    """Random crossing, curling, cusped loops filled (both rules) with the adaptive
    flattening: at 5000 random points farther than 3 (eps + grid) from every input
    curve the output loops are filled exactly where the input's winding rule fills
    (thinner features may merge, as with the flattening within eps everywhere,
    which is held to the same test)."""
    import morph.trim.flatten as F
    from morph.trim import boundary

    rng = np.random.default_rng(5)
    for trial in range(24):
        loops = _random_loops(rng)
        rule = ("nonzero", "evenodd")[trial % 2]
        eps = 10.0 ** rng.uniform(-4, -2.5)
        x = rng.uniform(-3, 13, (5000, 2))
        want, far = _membership(x, loops, rule, 0.1 * eps, 3 * (eps + eps))
        # the levels of 4 (32, 8, 2 eps), one step from COARSE to eps, eps everywhere
        for coarse, step in ((F.COARSE, F.LEVEL_STEP), (F.COARSE, F.COARSE), (1.0, 2.0)):
            monkeypatch.setattr(F, "COARSE", coarse)
            monkeypatch.setattr(F, "LEVEL_STEP", step)
            got, _ = _membership(x, boundary(loops, eps, eps, rule), "nonzero", 0.1 * eps, 0.0)
            assert np.array_equal(got[far], want[far]), (trial, coarse, step)
        monkeypatch.undo()


def test_adaptive_flattening_sums_as_flattening_everywhere_within_eps(monkeypatch):
    """Minkowski sums of glyphs at random angles and scales (convolution loops full
    of swallowtails, cusps and near contacts) with the adaptive flattening and with
    the flattening within eps everywhere: each within tol of the exact sum, so at
    random points farther than 2 tol from both boundaries they fill alike."""
    import morph.trim.flatten as F
    from morph.minkowski import minkowski_sum
    from morph.parse import glyph_region
    from morph.region import region_bbox, transform_region

    rng = np.random.default_rng(12)
    for a, b in [("S", "g"), ("a", "W"), ("ampersand", "e"), ("k", "B")]:
        angle, scale = rng.uniform(0, 2 * np.pi), rng.uniform(0.3, 1.5)
        m = scale * np.array([[np.cos(angle), -np.sin(angle), 0.0],
                              [np.sin(angle), np.cos(angle), 0.0]])
        ra = transform_region(glyph_region(a).region, m)
        rb = glyph_region(b).region
        tol = 10.0 ** rng.uniform(-2.5, 0)
        got = minkowski_sum(ra, rb, tol)
        monkeypatch.setattr(F, "COARSE", 1.0)
        want = minkowski_sum(ra, rb, tol)
        monkeypatch.undo()
        x0, y0, x1, y1 = region_bbox(want)
        x = np.column_stack([rng.uniform(x0, x1, 20000), rng.uniform(y0, y1, 20000)])
        in_got, far_got = _membership(x, got, "nonzero", 0.1 * tol, 2 * tol)
        in_want, far_want = _membership(x, want, "nonzero", 0.1 * tol, 2 * tol)
        far = far_got & far_want
        assert far.sum() > 10000 and in_want[far].any()
        assert np.array_equal(in_got[far], in_want[far])


@pytest.mark.parametrize("rule", ["nonzero", "evenodd"])
@pytest.mark.parametrize("side", [-1.0, 1.0])
def test_a_curl_finer_than_the_coarse_flattening_fills_by_the_rule(side, rule):
    """A square whose bottom side makes a small curl out of it or into it (a loop
    cubic whose control points lie within COARSE eps of its chord: one coarse
    segment would pass straight over it): the curl's tangents leave the chord's
    cone, so it is cut within eps, and its lobe (winding 2 inside the square, -1
    outside) is filled as the rule says, 2 eps in from its edges."""
    from morph.polyline import min_segment_distance, winding_number
    from morph.trim import boundary

    eps = 1e-4
    h, d = 8e-4, 2e-3 * side  # the control points within COARSE eps of the chord
    assert np.hypot(2 * h, d) < COARSE * eps
    curl = pc.from_points(np.array([(0.5 - h, 0.0), (0.5 + 3 * h, d), (0.5 - 3 * h, d),
                                    (0.5 + h, 0.0)]))
    loop = [pc.line((0, 0), (0.5 - h, 0)), curl, pc.line((0.5 + h, 0), (1, 0)),
            pc.line((1, 0), (1, 1)), pc.line((1, 1), (0, 1)), pc.line((0, 1), (0, 0))]
    xs, ys = np.meshgrid(np.linspace(0.5 - 3 * h, 0.5 + 3 * h, 61), np.linspace(-abs(d), abs(d), 81))
    x = np.column_stack([xs.ravel(), ys.ravel()])
    poly = pl.flatten_loop(loop, 1e-7)
    w = winding_number(x, [poly])
    lobe = w == (2 if side > 0 else -1)  # the curl's lobe
    deep = lobe & (min_segment_distance(x, poly, np.roll(poly, -1, axis=0)) > 2 * eps)
    assert deep.sum() > 5
    want = (w[deep] % 2 == 1) if rule == "evenodd" else (w[deep] != 0)
    out = boundary([loop], eps, eps, rule)
    got = winding_number(x[deep], [pl.flatten_loop(lp, 1e-7) for lp in out]) != 0
    assert np.array_equal(got, want)


def test_a_lens_thinner_than_the_coarse_flattening_is_kept():
    """A lens of two arcs 20 eps apart at its middle: each arc is one coarse segment,
    a loop of two vertices that would enclose nothing; loops of fewer than four
    coarse segments are cut within eps, and the lens is filled along its middle."""
    from morph.polyline import winding_number
    from morph.trim import boundary

    eps = 1e-4
    w = 20 * eps
    upper = pc.from_points(np.array([(0.0, 0.0), (0.5, w), (1.0, 0.0)]))  # bulges w / 2
    lower = pc.from_points(np.array([(1.0, 0.0), (0.5, -w), (0.0, 0.0)]))
    out = boundary([[upper, lower]], eps, eps, "nonzero")
    x = np.column_stack([np.linspace(0.2, 0.8, 13), np.zeros(13)])
    assert len(out) == 1
    assert (winding_number(x, [pl.flatten_loop(lp, 1e-7) for lp in out]) != 0).all()


def _merge_equal_loop_by_loop(q, is_start, loop_of):
    """The rule of _merge_equal written loop by loop (the reference)."""
    keep = []
    bounds = np.flatnonzero(np.diff(loop_of)) + 1
    for a, b in zip(np.concatenate([[0], bounds]), np.concatenate([bounds, [len(q)]])):
        lq = q[a:b]
        same = np.all(lq == np.roll(lq, 1, axis=0), axis=1)
        if same.all():
            continue
        r = int(np.argmin(same))
        order = np.roll(np.arange(a, b), -r)
        same = np.roll(same, -r)
        run_first = np.flatnonzero(~same)
        cand = np.where(is_start[order], np.arange(len(order)), -1)
        best = np.maximum.reduceat(cand, run_first)
        keep.append(order[np.where(best >= 0, best, run_first)])
    return np.sort(np.concatenate(keep)) if keep else np.zeros(0, np.int64)


def test_merge_equal_all_loops_at_once_matches_loop_by_loop():
    """Runs of equal grid points (wrapping round the loop's end, whole loops of one
    point, single-vertex loops) merged all at once as the loop-by-loop rule does;
    a wrong choice in one run is seen."""
    from morph.trim.flatten import _merge_equal

    rng = np.random.default_rng(11)
    for trial in range(200):
        sizes = rng.integers(1, 9, rng.integers(1, 6))
        loop_of = np.repeat(np.arange(len(sizes)), sizes)
        q = rng.integers(0, 2, (len(loop_of), 2)) if trial % 2 else \
            np.repeat(rng.integers(0, 3, (len(loop_of), 2)), 1, axis=0)
        q = np.where(rng.random((len(q), 1)) < 0.4, 0, q)   # many equal neighbours
        is_start = rng.random(len(q)) < 0.3
        want = _merge_equal_loop_by_loop(q, is_start, loop_of)
        assert np.array_equal(_merge_equal(q, is_start, loop_of), want)
    q = np.array([[0, 0], [0, 0], [1, 0], [1, 0], [0, 1]])
    got = _merge_equal(q, np.array([False, True, False, False, False]), np.zeros(5, int))
    assert list(got) == [1, 2, 4]
    assert not np.array_equal(got, [0, 2, 4])


def _random_polylines(rng):
    """Closed polylines (1-5, 1-30 vertices) of random walks: crossings, touches,
    repeated vertices and near contacts at every scale."""
    polys = []
    for _ in range(int(rng.integers(1, 6))):
        n = int(rng.integers(1, 31))
        steps = rng.normal(0, 1, (n, 2)) * rng.choice([0.01, 0.3, 2.0], (n, 1))
        p = np.cumsum(steps, axis=0) + rng.uniform(-3, 3, 2)
        if n > 3 and rng.random() < 0.3:
            p[int(rng.integers(2, n))] = p[0]  # a vertex visited twice
        polys.append(p)
    return polys


def test_near_others_matches_touching_edges():
    """The level test's near pairs (:func:`_near_others`, on the segments of the
    vertex arrays, all pending) are those of :func:`morph.polyline.touching_edges`
    (edges not consecutive along their polyline that cross, touch or come within
    reach), on random polylines; and on a subset of pending segments, the pairs
    among them.  Exempting also the pairs two apart along a loop is seen."""
    from morph.trim.flatten import _links, _near_others

    def near(polys, reach, exempt_two=False):
        xy = np.concatenate(polys)
        loop_of = np.repeat(np.arange(len(polys)), [len(p) for p in polys])
        nxt, _, _ = _links(loop_of)
        todo = np.arange(len(xy))
        if not exempt_two:
            return _near_others(xy, nxt, todo, reach)
        weak = np.array(nxt)
        return _near_others(xy, weak[weak], todo, reach) & _near_others(xy, nxt, todo, reach)

    rng = np.random.default_rng(21)
    hits = differ = 0
    for _ in range(300):
        polys = _random_polylines(rng)
        reach = 10.0 ** rng.uniform(-3, 0)
        many = [p for p in polys if len(p) >= 2]
        sizes = np.array([len(p) for p in polys])
        edge = np.flatnonzero(np.repeat(sizes >= 2, sizes))   # edges of touching_edges
        want = np.zeros(len(edge), bool)
        want[pl.touching_edges(many, reach).ravel()] = True
        got = near(polys, reach)
        assert np.array_equal(got[edge], want)
        hits += int(want.sum())
        if len(edge):
            differ += not np.array_equal(near(polys, reach, exempt_two=True)[edge], want)
    assert hits > 1000 and differ > 10

    # a subset of the segments: the pairs among them only
    from morph.trim.flatten import _near_others as near_others

    polys = _random_polylines(np.random.default_rng(4))
    xy = np.concatenate(polys)
    loop_of = np.repeat(np.arange(len(polys)), [len(p) for p in polys])
    from morph.trim.flatten import _links as links

    nxt, _, _ = links(loop_of)
    full = near_others(xy, nxt, np.arange(len(xy)), 0.5)
    todo = np.flatnonzero(full)[::2]
    sub = near_others(xy, nxt, todo, 0.5)
    ref = np.zeros(len(todo), bool)
    for x, i in enumerate(todo):
        for j in todo:
            if i != j and nxt[i] != j and nxt[j] != i:
                a, b, c, d = xy[i], xy[nxt[i]], xy[j], xy[nxt[j]]
                gap = min(pl.segment_distance(a[None], c[None], d[None])[0],
                          pl.segment_distance(b[None], c[None], d[None])[0],
                          pl.segment_distance(c[None], a[None], b[None])[0],
                          pl.segment_distance(d[None], a[None], b[None])[0])
                cross = len(pl.segment_crossings(np.array([a, c]), np.array([b, d]),
                                                 np.array([[0, 1]]))[0]) > 0
                ref[x] |= gap <= 0.5 or cross
    assert np.array_equal(sub, ref) and ref.any() and not ref.all()



def test_near_others_leaves_out_the_pairs_of_two_lines():
    """With ``line`` given, :func:`_near_others` finds the pairs of
    :func:`morph.polyline.touching_edges` (an independent search) among the pending
    segments, but those of two lines (the lines go last in its grid and are not
    paired with each other: a line still meets every other segment, before or after
    it); the pairs of two lines alone make segments near on random polylines."""
    from morph.trim.flatten import _links, _near_others

    rng = np.random.default_rng(29)
    hits = only_lines = 0
    for _ in range(300):
        polys = [p for p in _random_polylines(rng) if len(p) >= 2]
        if not polys:
            continue
        xy = np.concatenate(polys)
        nxt = _links(np.repeat(np.arange(len(polys)), [len(p) for p in polys]))[0]
        reach = 10.0 ** rng.uniform(-3, 0)
        line = rng.random(len(xy)) < 0.5
        todo = np.flatnonzero(rng.random(len(xy)) < 0.8)
        pending = np.zeros(len(xy), bool)
        pending[todo] = True
        pairs = pl.touching_edges(polys, reach)
        pairs = pairs[pending[pairs[:, 0]] & pending[pairs[:, 1]]]
        both = line[pairs[:, 0]] & line[pairs[:, 1]]
        want = np.zeros(len(xy), bool)
        want[pairs[~both].ravel()] = True
        got = _near_others(xy, nxt, todo, reach, line=line)
        assert np.array_equal(got, want[todo])
        hits += int(got.sum())
        only_lines += int((_near_others(xy, nxt, todo, reach) & ~got).sum())
    assert hits > 500 and only_lines > 50


def test_cell_pairs_from_solo_on_are_not_paired_with_each_other():
    """:func:`morph.polyline._cell_pair_columns` with ``solo``: the overlapping box
    pairs (all pairs compared) but those of two boxes from ``solo`` on, each once."""
    rng = np.random.default_rng(5)
    for _ in range(50):
        n = int(rng.integers(2, 200))
        lo = rng.uniform(0, 10, (n, 2))
        hi = lo + rng.uniform(0, 3, (n, 2)) ** 2
        solo = int(rng.integers(0, n + 1))
        i, j = np.triu_indices(n, 1)
        over = np.all(lo[i] <= hi[j], axis=1) & np.all(lo[j] <= hi[i], axis=1)
        want = {(a, b) for a, b in zip(i[over], j[over]) if a < solo or b < solo}
        found = [(int(a), int(b)) for ci, cj in
                 pl._cell_pair_columns(pl.BoxGrid(lo, hi), first=64, solo=solo)
                 for a, b in zip(ci, cj)]
        assert len(found) == len(set(found)) and set(found) == want

def _sum_loops(a, b, tol):
    """The chained convolution loops of glyph a + glyph b (loops that turn and meet,
    with swallowtails and near contacts), as (pieces, loop of each piece)."""
    from morph.convolve import chain, convolution, gauss_pair_of, with_pair_table
    from morph.parse import glyph_region

    ra, rb = glyph_region(a).region, glyph_region(b).region
    gp = with_pair_table(gauss_pair_of(ra, rb, ("a", "b")))
    conv = convolution(ra, rb, 0.5 * tol, keep_type3=True, gauss_pair=gp)
    loops = chain([c.piece for c in conv], 0.01 * tol)
    pieces = pc.Pieces.of([p for loop in loops for p in loop])
    return pieces, np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])


def _ends(pid, ts, nxt):
    return np.where((pid[nxt] == pid) & (ts[nxt] > ts), ts[nxt], 1.0)


def _part_points(rows, pid, t0, t1, n=65):
    """n points of each segment's part, evenly in parameter: (segments, n, 2)."""
    u = np.linspace(0.0, 1.0, n)
    return np.array([pc.evaluate(rows[k], a + (b - a) * u) for k, a, b in zip(pid, t0, t1)])


def _to_segment(x, a, b):
    """Distances of points x (..., 2) from the segment a-b."""
    d = b - a
    u = np.clip(((x - a) @ d) / max(float(d @ d), 1e-300), 0.0, 1.0)
    return np.hypot(*np.moveaxis(x - a - u[..., None] * d, -1, 0))


def test_refined_stretches_are_within_the_finer_tolerance():
    """:func:`_refined` on coarse flattenings (8 eps) of random loops and glyph-sum
    loops, random segments marked: every segment it marks refined is within eps of
    its part (65 points of the part against the chord), every vertex of the
    pieces' own flattening within eps inside a marked segment is kept (also one at
    a coarse vertex between two marked segments: the 8 eps and eps flattenings of a
    piece cut at 1/2 share it), and the unmarked segments are left as they were."""
    import morph.trim.flatten as F

    rng = np.random.default_rng(17)
    cases = [_random_loops(rng) for _ in range(12)]
    cases = [(pc.Pieces.of([p for lp in loops for p in lp]),
              np.repeat(np.arange(len(loops)), [len(lp) for lp in loops]), 10.0 ** rng.uniform(-3, -2))
             for loops in cases]
    cases.append(_sum_loops("S", "o", 0.5) + (0.175,))
    shared = 0
    for pieces, piece_loop, eps in cases:
        rows = pieces.rows()
        pid, ts, xy = pl.flat_starts(pieces, 8 * eps)
        nxt, prv, _ = F._links(piece_loop[pid])
        fine = rng.random(len(pid)) < 0.5
        mp, mt, mx, refined = F._refined(pieces, pid, ts, xy, fine, prv, eps)
        mn = F._links(piece_loop[mp])[0]
        me = _ends(mp, mt, mn)
        pts = _part_points(rows, mp, mt, me)
        err = np.array([_to_segment(p, mx[k], mx[mn[k]]).max() for k, p in enumerate(pts)])
        assert err[refined].max() <= eps * (1 + 1e-9)
        # the unmarked coarse segments, unchanged
        coarse = set(zip(pid[~fine].tolist(), ts[~fine].tolist(), _ends(pid, ts, nxt)[~fine].tolist()))
        got = set(zip(mp[~refined].tolist(), mt[~refined].tolist(), me[~refined].tolist()))
        assert coarse == got
        # every vertex of the flattening within eps inside a marked segment is kept
        fp, fts, _ = pl.flat_starts(pieces, eps)
        seg = np.searchsorted(pid * 2.0 + ts, fp * 2.0 + fts, side="right") - 1
        inside = fine[seg] & ((fts > ts[seg]) | (fine[prv[seg]] & (ts[seg] > 0.0)))
        have = set(zip(mp.tolist(), mt.tolist()))
        assert all((p, t) in have for p, t in zip(fp[inside].tolist(), fts[inside].tolist()))
        shared += int(np.sum(inside & (fts == ts[seg])))
    assert shared > 10   # coarse vertices shared with the finer flattening occurred


def _levels_recorded(monkeypatch, pieces, piece_loop, eps, grid):
    """:func:`adaptive_starts` with each level's test recorded: (piece, t, point) of
    the result, and per level (e, the segments' (piece, t0, t1), nxt, prv, pending,
    not certain)."""
    import morph.trim.flatten as F

    levels, test = [], F._uncertain

    def recorded(pieces, pid, ts, xy, loop_of, nxt, prv, starts, pending, e, eps, grid):
        fine = test(pieces, pid, ts, xy, loop_of, nxt, prv, starts, pending, e, eps, grid)
        levels.append((e, list(zip(pid.tolist(), ts.tolist(), _ends(pid, ts, nxt).tolist())),
                       nxt, prv, pending, fine))
        return fine

    monkeypatch.setattr(F, "_uncertain", recorded)
    out = F.adaptive_starts(pieces, piece_loop, eps, grid)
    monkeypatch.undo()
    return out, levels


def _monotone_between(pts, nxt, i, j, steps=64):
    """Whether the parts from segment i to segment j along their loop (or from j to
    i), at most ``steps`` segments, advance along one direction: the directions
    of the steps between their sampled points (``pts``, (segments, n, 2)) lie
    within less than 180 degrees of each other (unwrapped along the chain)."""
    for a, b in ((i, j), (j, i)):
        chain, k = [a], a
        while k != b and len(chain) <= steps:
            k = nxt[k]
            chain.append(k)
        if k != b:
            continue
        x = np.concatenate([pts[c] for c in chain])
        d = np.diff(x, axis=0)
        d = d[np.hypot(d[:, 0], d[:, 1]) > 0]
        ang = np.unwrap(np.arctan2(d[:, 1], d[:, 0]))
        if ang.max() - ang.min() < np.pi:
            return True
    return False


def _level_violations(pieces, piece_loop, eps, grid, result, levels):
    """The two guarantees of :func:`adaptive_starts`, measured on 65 points of each
    part: (segments farther from their part than the tolerance of the level that
    decided them (eps if none did), pairs (decided, other) nearer than
    e + 2 (eps + grid) where the other segment was still pending at level e and is
    not cut from the decided one's neighbours at that level, nor joined to the
    decided one along their loop by parts that advance along one direction (their
    sampled steps within less than 180 degrees: such a chain meets itself nowhere,
    at any level), nor both parts of lines (exact at every level)), and how many
    segments each level decided."""
    import morph.trim.flatten as F

    pid, ts, xy = result
    nxt = F._links(piece_loop[pid])[0]
    ends = _ends(pid, ts, nxt)
    index = {s: i for i, s in enumerate(zip(pid.tolist(), ts.tolist(), ends.tolist()))}
    tol = np.full(len(pid), eps)
    level = np.full(len(pid), len(levels))      # the level that decided each segment
    decided = []
    for k, (e, segs, lnxt, lprv, pending, fine) in enumerate(levels):
        for i in np.flatnonzero(pending & ~fine):
            j = index[segs[i]]       # a decided segment stays as it is
            tol[j], level[j] = e, k
            decided.append((j, k, e, [segs[lnxt[i]], segs[lprv[i]]]))
    pts = _part_points(pieces.rows(), pid, ts, ends)
    err = np.array([_to_segment(p, xy[k], xy[nxt[k]]).max() for k, p in enumerate(pts)])
    far_off = np.flatnonzero(err > tol * (1 + 1e-9))
    line = np.array([len(pieces.rows()[p]) == 2 for p in pid])
    near = []
    for j, k, e, neighbours in decided:
        other = level >= k
        other[j] = False
        if line[j]:
            other &= ~line   # two lines: their polylines are the lines at every level
        for p, a, b in neighbours:
            other &= ~((pid == p) & (ts >= a) & (ends <= b))
        x = np.flatnonzero(other)
        d = _to_segment(pts[x], xy[j], xy[nxt[j]]).min(axis=1)
        near += [(j, int(i)) for i in x[d <= e + 2 * (eps + grid)]
                 if not _monotone_between(pts, nxt, j, int(i))]
    return far_off, near, np.bincount(level, minlength=len(levels) + 1)


def test_levels_keep_their_guarantees(monkeypatch):
    """:func:`adaptive_starts` on glyph-sum convolution loops (swallowtails, cusps,
    near contacts): every segment is within the tolerance of the level that
    decided it (eps where none did); a part decided at level e is farther than
    e + 2 (eps + grid) from every part still pending at that level, but those cut
    from its neighbours there and those a chain of parts advancing along one
    direction joins to it.  Every level decides some parts.  The second check
    fails when the levels test a quarter of their reach, or take chains that turn
    through 300 degrees for monotone; the first failed when a
    refined stretch dropped the finer vertex at a coarse vertex between two
    refined segments (segments 2-17 eps from parts said within eps or 8 eps)."""
    import morph.trim.flatten as F

    tol = 0.5
    eps, grid = 0.35 * tol, 0.1 * np.sqrt(2) * tol
    for a, b in [("S", "o"), ("k", "B")]:
        pieces, piece_loop = _sum_loops(a, b, tol)
        result, levels = _levels_recorded(monkeypatch, pieces, piece_loop, eps, grid)
        assert [e / eps for e, *_ in levels] == [F.COARSE, F.COARSE / F.LEVEL_STEP]
        far_off, near, per_level = _level_violations(pieces, piece_loop, eps, grid, result, levels)
        assert not len(far_off) and not near, (a, b, far_off, near)
        assert np.all(per_level[:-1] > 10), per_level

    # the near check can fail: levels testing a quarter of their reach
    near_others = F._near_others
    monkeypatch.setattr(F, "_near_others", lambda xy, nxt, todo, reach, *rest:
                        near_others(xy, nxt, todo, 0.25 * reach, *rest))
    result, levels = _levels_recorded(monkeypatch, pieces, piece_loop, eps, grid)
    assert _level_violations(pieces, piece_loop, eps, grid, result, levels)[1]
    monkeypatch.undo()
    # and so can the chains': chains whose chords turn through up to 300 degrees
    monkeypatch.setattr(F, "CHAIN", np.radians(300.0))
    monkeypatch.setattr(F, "CHAIN_STEPS", 8)
    result, levels = _levels_recorded(monkeypatch, pieces, piece_loop, eps, grid)
    monkeypatch.undo()
    assert _level_violations(pieces, piece_loop, eps, grid, result, levels)[1]


def test_levels_flatten_no_finer_than_their_test_needs():
    """Every vertex of the adaptive flattening lies on its piece (the tags), every
    segment within COARSE eps of its part (its control points' chord distance), and
    the levels cut fewer vertices than one step from COARSE to eps, which cuts fewer
    than eps everywhere, on loops that turn and meet: a glyph sum's convolution
    loops."""
    import morph.trim.flatten as F
    from morph.convolve import chain, convolution, gauss_pair_of, with_pair_table
    from morph.parse import glyph_region

    a, b = glyph_region("S").region, glyph_region("o").region
    gp = with_pair_table(gauss_pair_of(a, b, ("a", "b")))
    tol = 0.5
    conv = convolution(a, b, 0.5 * tol, keep_type3=True, gauss_pair=gp)
    loops = chain([c.piece for c in conv], 0.01 * tol)
    pieces = pc.Pieces.of([p for loop in loops for p in loop])
    piece_loop = np.repeat(np.arange(len(loops)), [len(loop) for loop in loops])
    eps, grid = 0.35 * tol, 0.1 * np.sqrt(2) * tol
    pid, ts, xy = F.adaptive_starts(pieces, piece_loop, eps, grid)
    rows = pieces.rows()
    pts = np.array([pc.evaluate(rows[k], t)[0] for k, t in zip(pid, ts)])
    assert np.abs(pts - xy).max() <= 1e-9 * np.abs(xy).max()
    loop_of = piece_loop[pid]
    nxt = F._links(loop_of)[0]
    t_end = np.where((pid[nxt] == pid) & (ts[nxt] > ts), ts[nxt], 1.0)
    err = np.zeros(len(pid))
    for k, parts in F._segment_parts(pieces, pid, ts, t_end):
        err[k] = pl._chord_distance(parts)
    assert err.max() <= F.COARSE * eps * (1 + 1e-9)
    assert np.sum(err > eps * (1 + 1e-9)) > 10   # some parts are decided coarser
    one = F.LEVEL_STEP
    F.LEVEL_STEP = F.COARSE
    try:
        pid1, _, _ = F.adaptive_starts(pieces, piece_loop, eps, grid)
    finally:
        F.LEVEL_STEP = one
    fine, _, _ = pl.flat_starts(pieces, eps)
    assert len(pid) < len(pid1) < len(fine)

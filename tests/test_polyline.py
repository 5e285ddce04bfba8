"""morph.polyline against shapely: segment pairs, crossings, and the loop crossing test."""

import pytest
import numpy as np
pytest.importorskip("shapely")
import shapely
from shapely.geometry import LineString

from morph import piece as pc
from morph import polyline as pl
from morph.polyline import (flatten_segments, polylines_apart, polylines_cross, polylines_touch,
                            segment_crossings, segment_pairs)


def _random_segments(rng, n):
    p0 = rng.uniform(0, 10, (n, 2))
    p1 = p0 + rng.normal(0, 1.5, (n, 2))
    return p0, p1


def test_segment_pairs_hold_every_intersecting_pair():
    """Every pair of segments that shapely finds intersecting is among the box pairs."""
    rng = np.random.default_rng(3)
    p0, p1 = _random_segments(rng, 300)
    pairs = {tuple(p) for p in segment_pairs(p0, p1, np.arange(len(p0)), True)}
    lines = [LineString([a, b]) for a, b in zip(p0, p1)]
    tree = shapely.STRtree(lines)
    left, right = tree.query(lines, predicate="intersects")
    truth = {(int(i), int(j)) for i, j in zip(left, right) if i < j}
    assert truth and truth <= pairs


def test_box_pairs_in_chunks_are_the_overlapping_pairs():
    """BoxGrid's pairs, whole and in growing chunks (an early exit's unit), are
    exactly the pairs of boxes that overlap (all pairs compared), for boxes of mixed
    sizes and chunk sizes down to one pair."""
    from morph.polyline import BoxGrid, _cell_pair_chunks, _cell_pairs

    rng = np.random.default_rng(11)
    for n in (1, 40, 1500):
        lo = rng.uniform(0, 100, (n, 2))
        hi = lo + rng.uniform(0, 1, (n, 2)) ** 3 * 30
        grid = BoxGrid(lo, hi)
        i, j = np.triu_indices(n, 1)
        overlap = np.all(lo[i] <= hi[j], axis=1) & np.all(lo[j] <= hi[i], axis=1)
        truth = np.stack([i[overlap], j[overlap]], axis=1)
        assert np.array_equal(_cell_pairs(grid), truth)
        for limit, first in ((1, 1), (50, 3), (1 << 20, 1 << 12)):
            chunks = list(_cell_pair_chunks(grid, limit, first))
            got = np.unique(np.concatenate(chunks), axis=0) if chunks else np.zeros((0, 2))
            assert np.array_equal(got.reshape(-1, 2), truth)
        assert n < 1500 or len(truth) > 1000


def test_winding_of_others_on_slabs_is_the_all_pairs_count():
    """Windings counted over the edges found on horizontal slabs equal the plain
    count over every (point, edge) pair, on random integer polylines (horizontal
    edges, repeated vertices, points on vertices and edges: every tie of the
    crossing rule) with random owners, in blocks down to one point."""
    from morph.polyline import _owned_edges, winding_of_others

    def all_pairs(pts, owner, polys):
        a, b, edge_owner = _owned_edges(polys)
        p = pts[:, None, :]
        ay, by = a[None, :, 1], b[None, :, 1]
        cross = ((b[None, :, 0] - a[None, :, 0]) * (p[..., 1] - ay)
                 - (by - ay) * (p[..., 0] - a[None, :, 0]))
        other = owner[:, None] != edge_owner[None, :]
        up = (ay <= p[..., 1]) & (by > p[..., 1]) & (cross > 0) & other
        down = (ay > p[..., 1]) & (by <= p[..., 1]) & (cross < 0) & other
        return up.sum(axis=1) - down.sum(axis=1)

    rng = np.random.default_rng(5)
    wound = 0
    for _ in range(20):
        polys = [rng.integers(0, 20, (int(rng.integers(2, 12)), 2)) * rng.choice([1.0, 0.5])
                 for _ in range(int(rng.integers(1, 8)))]
        pts = np.vstack([rng.uniform(-2, 22, (300, 2)), np.concatenate(polys),
                         rng.integers(0, 20, (100, 2)).astype(float)])
        owner = rng.integers(-1, len(polys), len(pts))
        want = all_pairs(pts, owner, polys)
        wound += np.abs(want).max() >= 1
        for chunk in (2_000_000, 64, 1):
            assert np.array_equal(winding_of_others(pts, owner, polys, chunk), want)
    assert wound >= 15


def test_segment_crossings_points_agree_with_shapely():
    rng = np.random.default_rng(4)
    p0, p1 = _random_segments(rng, 200)
    pairs = segment_pairs(p0, p1, np.arange(len(p0)), True)
    k, u, v = segment_crossings(p0, p1, pairs)
    i, j = pairs[k, 0], pairs[k, 1]
    x = p0[i] + u[:, None] * (p1[i] - p0[i])
    y = p0[j] + v[:, None] * (p1[j] - p0[j])
    assert len(k) > 20
    assert np.abs(x - y).max() < 1e-9
    for a, b, pt in zip(i[:50], j[:50], x[:50]):
        inter = LineString([p0[a], p1[a]]).intersection(LineString([p0[b], p1[b]]))
        assert inter.distance(shapely.Point(pt)) < 1e-9


def test_flatten_segments_cover_the_pieces():
    loop = pc.circle((1.0, 2.0), 3.0)
    p0, p1, ids, t0, t1 = flatten_segments(loop, 1e-3)
    assert set(ids) == {0, 1, 2, 3}
    mid = 0.5 * (p0 + p1)
    # chords of a circle lie inside it, within the flattening tolerance
    r = np.hypot(mid[:, 0] - 1.0, mid[:, 1] - 2.0)
    assert (r <= 3.0 + 1e-12).all() and (r >= 3.0 - 1e-3).all()
    assert np.all(t1 > t0)


def test_polylines_cross_figure_eight_and_disjoint_circles():
    eight = [pc.line((0, 0), (2, 2)), pc.line((2, 2), (2, 0)), pc.line((2, 0), (0, 2)),
             pc.line((0, 2), (0, 0))]
    assert polylines_cross(eight, 1e-6)
    assert not polylines_cross(pc.circle((0, 0), 1.0) + pc.circle((5, 0), 1.0), 1e-6)
    assert polylines_cross(pc.circle((0, 0), 1.0) + pc.circle((1.5, 0), 1.0), 1e-6)


def test_polylines_apart_is_a_sufficient_test():
    """Apart means that the exact curves keep a gap (shapely, on curves flattened far
    finer): pairs of circles at random gaps, their polylines within tol; never apart
    where the curves cross, always where they stay more than 4 tol apart (the
    polylines then more than 2 tol), and a single loop (consecutive edges share a
    vertex) is apart from itself; loops touching at a point and a figure eight are
    not apart."""

    def apart(*loops):
        return polylines_apart(pl.flatten_loops(list(loops), tol), tol)

    tol = 1e-2
    rng = np.random.default_rng(11)
    seen = set()
    for _ in range(60):
        r1, r2 = rng.uniform(0.5, 2.0, 2)
        gap = rng.uniform(-0.1, 0.1)
        ang = rng.uniform(0, 2 * np.pi)
        c2 = (r1 + r2 + gap) * np.array([np.cos(ang), np.sin(ang)])
        a, b = pc.circle((0.0, 0.0), r1), pc.circle(c2, r2)
        got = apart(a, b)
        true_gap = shapely.Polygon(pl.flatten_loop(a, 1e-6)).distance(
            shapely.Polygon(pl.flatten_loop(b, 1e-6)))
        if got:   # each arc within tol of its segments, the segments over 2 tol apart
            assert true_gap > 0, (gap, true_gap)
        if true_gap > 4 * tol:   # the polylines (within tol) more than 2 tol apart
            assert got, (gap, true_gap)
        seen.add(got)
        if gap < 0:
            assert not got and polylines_cross(a + b, 1e-6)
    assert seen == {True, False}
    assert apart(pc.circle((0.0, 0.0), 1.0))
    # a loop touching another at a shared point, and a figure eight, are not apart
    square = [pc.line((0, 0), (1, 0)), pc.line((1, 0), (1, 1)), pc.line((1, 1), (0, 1)),
              pc.line((0, 1), (0, 0))]
    other = [pc.line((1, 1), (2, 1)), pc.line((2, 1), (2, 2)), pc.line((2, 2), (1, 2)),
             pc.line((1, 2), (1, 1))]
    assert not apart(square, other)
    eight = [pc.line((0, 0), (2, 2)), pc.line((2, 2), (2, 0)), pc.line((2, 0), (0, 2)),
             pc.line((0, 2), (0, 0))]
    assert not apart(eight)


def test_polylines_touch_against_shapely_distances():
    """polylines_touch says whether two edges, not neighbours along one polyline, come
    within reach: against shapely's distance of every such pair of edges, on random
    closed polylines (random walks: they cross, touch and overlap themselves), on
    polylines that visit a vertex twice (a figure-8 through a joint, two squares on a
    shared edge), and on simple ones far apart."""
    rng = np.random.default_rng(5)

    def truth(polys, reach):
        edges = [(k, i, p[i], p[(i + 1) % len(p)]) for k, p in enumerate(polys)
                 for i in range(len(p))]
        for x in range(len(edges)):
            for y in range(x + 1, len(edges)):
                (k, i, a, b), (m, j, c, d) = edges[x], edges[y]
                n = len(polys[k])
                if k == m and (abs(i - j) == 1 or abs(i - j) == n - 1):
                    continue
                if LineString([a, b]).distance(LineString([c, d])) <= reach:
                    return True
        return False

    seen = set()
    for _ in range(150):
        polys = [np.cumsum(rng.normal(0, 1, (rng.integers(3, 9), 2)), axis=0) + rng.uniform(0, 30, 2)
                 for _ in range(rng.integers(1, 3))]
        reach = float(rng.choice([1e-9, 0.05, 0.5]))
        got = polylines_touch(polys, reach)
        assert got == truth(polys, reach)
        seen.add(got)
    assert seen == {True, False}
    eight = np.array([[0, 0], [1, 1], [2, 0], [1, -1], [0, 0], [-1, 1], [-2, 0], [-1, -1.0]])
    assert polylines_touch([eight], 1e-12)          # through the joint at the origin
    square = np.array([[0, 0], [1, 0], [1, 1], [0, 1.0]])
    assert polylines_touch([square, square + [1, 0]], 1e-12)   # a shared edge
    assert not polylines_touch([square, square + [1.5, 0]], 0.1)
    assert not polylines_touch([square], 1e-12)     # neighbours along a polyline meet


# ------------------------------------------------------------------ flattening

def test_flatten_many_equals_flatten():
    """The batched flattening gives each piece exactly what flatten gives it."""
    pieces = (pc.ellipse([0.0, 0.0], 30.0, 4.0, 0.3)
              + [pc.cubic((0, 0), (1, 3), (2, -3), (3, 0)), pc.line((0, 0), (5, 1)),
                 pc.quadratic((0, 0), (1, 2), (2, 0)), pc.cubic((0, 0), (2, 1), (1, 1), (3, 0))])
    for tol in (1e-1, 1e-3):
        for p, (q, t) in zip(pieces, pl.flatten_many(pieces, tol)):
            q2, t2 = pl.flatten(p, tol)
            assert np.array_equal(t, t2)
            assert np.allclose(q, q2, atol=1e-12)


def test_flat_starts_are_the_polylines_without_their_ends():
    """flat_starts: every piece's flatten polyline but its end point, all in arrays
    sorted by (piece, t), pieces of mixed degrees in their given order."""
    pieces = [pc.line((0, 0), (5, 1)), pc.cubic((5, 1), (6, 3), (7, -3), (8, 0))] \
        + pc.ellipse([0.0, 0.0], 30.0, 4.0, 0.3) + [pc.quadratic((0, 0), (1, 2), (2, 0))]
    owner, t, pts = pl.flat_starts(pieces, 1e-3)
    assert np.all(np.diff(owner) >= 0)
    for k, p in enumerate(pieces):
        q, tk = pl.flatten(p, 1e-3)
        assert np.array_equal(t[owner == k], tk[:-1])
        assert np.allclose(pts[owner == k], q[:-1], atol=1e-12)
    empty = pl.flat_starts([], 1e-3)
    assert [len(a) for a in empty] == [0, 0, 0]


def test_flat_starts_keep_gives_the_whole_flattening_where_kept():
    """flat_starts with ``keep`` (parts left out of the subdivision where False) gives
    exactly the vertices of the whole flattening inside the kept ranges, and only
    vertices of the whole flattening."""
    rng = np.random.default_rng(21)
    pieces = []
    for _ in range(30):
        n = int(rng.integers(3, 6))
        w = np.ones(n)
        w[1:-1] = rng.uniform(0.3, 3.0, n - 2)
        ctrl = rng.uniform(0, 10, (n, 2))
        pieces.append(np.column_stack([ctrl * w[:, None], w]))
    lo = rng.uniform(0, 0.8, len(pieces))
    hi = lo + rng.uniform(0.01, 0.2, len(pieces))

    def keep(owner, t0, width):
        return (t0 <= hi[owner]) & (t0 + width >= lo[owner])

    full = pl.flat_starts(pieces, 1e-3)
    part = pl.flat_starts(pieces, 1e-3, keep=keep)
    whole = {(int(o), float(t)): tuple(p) for o, t, p in zip(*full)}
    got = {(int(o), float(t)): tuple(p) for o, t, p in zip(*part)}
    assert all(whole.get(k) == v for k, v in got.items())
    inside = {k for k in whole if lo[k[0]] < k[1] < hi[k[0]]}
    assert inside and inside <= set(got)
    assert len(got) < 0.6 * len(whole)


def _superposed_sets(seed, sets=6):
    """Closed random polylines in ``sets`` sets that lie on top of each other (as the
    glyphs of a font do), each set a few polylines, and the set of each."""
    rng = np.random.default_rng(seed)
    polys, group = [], []
    for g in range(sets):
        for _ in range(int(rng.integers(1, 4))):
            c = rng.uniform(0, 10, 2)
            r = rng.uniform(1, 4)
            t = np.sort(rng.uniform(0, 2 * np.pi, int(rng.integers(3, 12))))
            polys.append(c + (r * rng.uniform(0.5, 1.0, len(t)))[:, None]
                         * np.stack([np.cos(t), np.sin(t)], axis=1))
            group.append(g)
    return polys, np.array(group)


@pytest.mark.parametrize("seed", range(4))
def test_grouped_searches_equal_each_set_alone(seed):
    """near_segment_pairs_grouped, distance_to_others_grouped and
    winding_of_others_grouped: what near_segments, distance_to_others and
    winding_of_others find in each set alone, every set in one grid."""
    from morph.polyline import (distance_to_others, distance_to_others_grouped,
                                near_segment_pairs_grouped, near_segments, polyline_edges,
                                winding_of_others, winding_of_others_grouped)

    polys, group = _superposed_sets(seed)
    sets = int(group.max()) + 1
    reach = np.linspace(0.3, 2.0, sets)
    a, b = polyline_edges(polys)
    edge_set = np.repeat(group, [len(p) for p in polys])
    got = {tuple(p) for p in near_segment_pairs_grouped(a, b, edge_set, reach).tolist()}
    want = set()
    for g in range(sets):
        idx = np.flatnonzero(edge_set == g)
        want |= {(int(idx[i]), int(idx[j]))
                 for i, j in near_segments(a[idx], b[idx], reach[g]).tolist()}
    assert got == want and len(want) > 0
    rng = np.random.default_rng(seed)
    owner = np.repeat(np.arange(len(polys)), 5)
    pts = np.concatenate([np.vstack([p[rng.integers(0, len(p), 2)] + rng.normal(0, 0.3, (2, 2)),
                                     rng.uniform(0, 10, (3, 2))]) for p in polys])
    dist = distance_to_others_grouped(pts, owner, polys, group, reach)
    wind = winding_of_others_grouped(pts, owner, polys, group, sets)
    for g in range(sets):
        mine = np.flatnonzero(group == g)
        local = np.full(len(polys), -1)
        local[mine] = np.arange(len(mine))
        sel = np.flatnonzero(group[owner] == g)
        others = [polys[m] for m in mine]
        assert np.array_equal(dist[sel], distance_to_others(pts[sel], local[owner[sel]],
                                                            others, reach[g]))
        assert np.array_equal(wind[sel], winding_of_others(pts[sel], local[owner[sel]], others))
    assert np.isfinite(dist).any() and (wind != 0).any()


def test_set_extents_are_ufunc_at_of_sorted_and_unsorted_sets():
    """set_extents (runs of a sorted group, else ufunc.at): the corners np.minimum.at
    / np.maximum.at give, empty sets at inf / -inf; a moved box moves its set's."""
    rng = np.random.default_rng(3)
    for sort in (True, False):
        group = rng.integers(0, 9, 200)
        group = np.sort(group) if sort else group
        lo = rng.normal(0, 5, (200, 2))
        hi = lo + rng.uniform(0, 2, (200, 2))
        want_lo, want_hi = np.full((10, 2), np.inf), np.full((10, 2), -np.inf)
        np.minimum.at(want_lo, group, lo)
        np.maximum.at(want_hi, group, hi)
        got_lo, got_hi = pl.set_extents(lo, hi, group, 10)
        assert np.array_equal(got_lo, want_lo) and np.array_equal(got_hi, want_hi)
        assert np.isinf(got_lo[9]).all() or (group == 9).any()
        k = int(np.argmin(lo[:, 0]))
        lo[k, 0] -= 1.0
        assert pl.set_extents(lo, hi, group, 10)[0][group[k], 0] == want_lo[group[k], 0] - 1.0


def test_flatten_loop_pieces_of_stacks_is_flatten_loops():
    """Loops given as their stacked pieces and sizes flatten as the lists do, to the
    bit, with one tolerance per loop."""
    loops = [list(pc.circle((0, 0), 5)), [pc.line((0, 0), (3, 0)), pc.line((3, 0), (0, 2)),
                                          pc.line((0, 2), (0, 0))],
             list(pc.circle((20, 1), 2))]
    tols = np.array([0.01, 0.5, 0.001])
    want = pl.flatten_loops(loops, tols)
    stacked = pc.Pieces.of([p for loop in loops for p in loop])
    got = pl.flatten_loop_pieces(stacked, [len(loop) for loop in loops], tols)
    assert len(got) == len(want)
    assert all(np.array_equal(a, b) for a, b in zip(got, want))
    assert not np.array_equal(pl.flatten_loop_pieces(stacked, [4, 3, 4], 0.5)[0], want[0])


def test_member_and_unique_match_numpy():
    """``member`` and ``unique`` (kept off numpy.ma's import) give numpy's isin and
    unique on random integers with repeats, empty sets and values past both ends."""
    rng = np.random.default_rng(5)
    for _ in range(50):
        values = rng.integers(-5, 30, rng.integers(0, 40))
        pool = rng.integers(0, 25, rng.integers(0, 20))
        s = pl.unique(pool)
        assert np.array_equal(s, np.unique(pool))
        assert np.array_equal(pl.member(values, s), np.isin(values, pool))


def _farthest_from_polyline(piece, pts, samples=4001):
    """The largest distance of the piece (densely sampled) from the polyline pts."""
    curve = pc.evaluate(np.asarray(piece, float), np.linspace(0.0, 1.0, samples))
    return float(pl.min_segment_distance(curve, pts[:-1], pts[1:]).max())


def test_flattening_is_within_tol_and_cuts_a_part_the_curve_leaves_by_more(monkeypatch):
    """flatten is a certified bound: densely sampled, every piece (rational quadratics
    and cubics with heavy inner weights, whose curves come within 10 % of their
    control polygons) lies within tol of its polyline.  A part whose curve leaves
    its chord by more than tol is cut: a rational quadratic whose arc is 1.05 tol
    from its chord (its middle control point 1.16 tol) gets inner vertices.  The
    check can fail: with the control-polygon bound loosened to 0.8 of itself that
    arc is taken as its chord, 1.05 tol away.  (The random pieces alone would not
    show it: their parts are cut into ceil(sqrt(d / tol)) steps, most well inside
    tol.)"""
    rng = np.random.default_rng(29)
    pieces = []
    for _ in range(60):
        n = int(rng.integers(3, 5))
        pts = rng.uniform(0, 10, (n, 2))
        w = np.concatenate([[1.0], rng.uniform(1.0, 12.0, n - 2), [1.0]])
        pieces.append(pc.from_points(pts, w))
    w = 10.0   # arc height w / (1 + w) of the middle control point's distance
    arc = pc.from_points([(0.0, 0.0), (1.0, 1.05 * (1 + w) / w), (2.0, 0.0)], [1.0, w, 1.0])

    def worst(tol):
        return max(_farthest_from_polyline(p, q) / tol
                   for p, (q, _) in zip(pieces, pl.flatten_many(pieces, tol)))

    for tol in (0.3, 0.03):
        assert worst(tol) <= 1.0 + 1e-9
    q, t = pl.flatten(arc, 1.0)
    assert len(q) > 2 and _farthest_from_polyline(arc, q) <= 1.0 + 1e-9
    assert _farthest_from_polyline(arc, q[[0, -1]]) > 1.0   # the chord alone is too far

    loose = pl._chord_distance
    monkeypatch.setattr(pl, "_chord_distance", lambda parts: 0.8 * loose(parts))
    q = pl.flatten(arc, 1.0)[0]
    assert len(q) == 2 and _farthest_from_polyline(arc, q) > 1.0


def test_piece_order_is_lexsort():
    """piece_order gives np.lexsort((t, owner)) on sorted runs, shuffled input, ties
    and parameters nearer than the float key resolves (its fallback)."""
    rng = np.random.default_rng(31)
    for case in range(40):
        n = int(rng.integers(0, 300))
        owner = rng.integers(0, 50000 if case % 2 else 20, n)
        t = rng.choice([0.0, 0.25, 0.5], n) if case % 3 == 0 else rng.uniform(0, 1, n)
        if case % 4 == 1 and n > 1:   # two parameters of one piece 1e-15 apart
            owner[1], t[1] = owner[0], t[0] + 1e-15 if t[0] < 0.5 else t[0] - 1e-15
            owner[:2], t[:2] = owner[1::-1].copy(), t[1::-1].copy()
        if case % 5 == 0:
            o = np.lexsort((t, owner))
            owner, t = owner[o], t[o]
            cut = n // 3
            owner = np.concatenate([owner[cut:], owner[:cut]])
            t = np.concatenate([t[cut:], t[:cut]])
        assert np.array_equal(pl.piece_order(owner, t), np.lexsort((t, owner)))


def test_within_on_columns_is_the_crossing_and_distance_test():
    """_within (on coordinate columns) gives exactly what segment_crossings and the
    four segment_distance values give, on random segments with shared, collinear
    and degenerate ones."""
    rng = np.random.default_rng(37)
    p0 = rng.integers(0, 12, (400, 2)).astype(float)
    p1 = p0 + rng.integers(-3, 4, (400, 2))
    p1[::17] = p0[::17]
    pairs = np.stack(np.triu_indices(400, 1), axis=1)[::7]
    i, j = pairs[:, 0], pairs[:, 1]
    for reach in (0.0, 0.7, np.full(len(pairs), 1.3)):
        hit = np.zeros(len(pairs), bool)
        hit[segment_crossings(p0, p1, pairs)[0]] = True
        gap = np.minimum(np.minimum(pl.segment_distance(p0[i], p0[j], p1[j]),
                                    pl.segment_distance(p1[i], p0[j], p1[j])),
                         np.minimum(pl.segment_distance(p0[j], p0[i], p1[i]),
                                    pl.segment_distance(p1[j], p0[i], p1[i])))
        want = hit | (gap <= reach)
        assert np.array_equal(pl._within(p0, p1, pairs, reach), want)
        assert 0 < want.sum() < len(want)


def test_equal_parts_match_einsum_whatever_the_grouping(monkeypatch):
    """The parts of every step count cut column by column or in the gathered pass
    (in one block or in many), and some steps only (``every`` False): the same bits
    as each part through each of its steps' matrices by einsum."""
    rng = np.random.default_rng(3)
    for n, m in ((2, 40), (7, 120)):
        steps = np.sort(rng.choice([2, 3, 5], m)).astype(np.int64)
        parts = rng.normal(size=(m, n + 1, 3))
        rep, j = pl._step_rows(steps)
        want = np.concatenate([
            np.einsum("kij,mjc->mkic", pl._equal_split_matrices(n, k),
                      parts[steps == k]).reshape(-1, n + 1, 3)
            for k in sorted(set(steps.tolist()))])
        for group in (0, 10 ** 9):         # every step count on its own; all gathered
            monkeypatch.setattr(pl, "EQUAL_GROUP", group)
            for block in (1 << 13, 24):    # the gathered steps in one block; in many
                monkeypatch.setattr(pl, "EQUAL_BLOCK", block)
                assert np.array_equal(pl._equal_parts(parts, steps, rep, j), want)
                some = rng.random(len(rep)) < 0.3
                assert np.array_equal(pl._equal_parts(parts, steps, rep[some], j[some],
                                                      every=False), want[some])


def test_chord_distance_planes_match_the_columns():
    """_chord_distance's one pass over a small stack's inner points gives the bits of
    its column by column pass (random rational parts, some with zero-length chords
    and inner points beyond either end), and small stacks of degree 5 or more take
    it."""
    rng = np.random.default_rng(41)
    for n in (2, 3, 5, 7, 9):
        for m in (1, 3, 40, 300):
            parts = rng.normal(size=(m, n + 1, 3))
            parts[:, :, 2] = rng.uniform(0.3, 3.0, (m, n + 1))
            parts[: m // 3, -1] = parts[: m // 3, 0]       # zero-length chords
            want = pl._chord_distance_columns(parts)
            assert np.array_equal(pl._chord_distance_planes(parts), want)
            assert np.array_equal(pl._chord_distance(parts), want)
            assert want.max() > 0

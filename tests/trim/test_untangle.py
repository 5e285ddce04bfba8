"""morph.trim.untangle: lobes cut where the exact pieces of a lifted loop cross."""

import numpy as np

from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.polyline import polylines_cross
from morph.trim.untangle import untangle


def _bow_tie(x, y, w=10.0):
    """A loop of four lines crossing itself once, at (x + w/2, y + w/2): a
    counter-clockwise triangle and a clockwise one (a twist)."""
    p = np.array([[0, 0], [w, w], [w, 0], [0, w]], float) + (x, y)
    return [pc.line(p[k], p[(k + 1) % 4]) for k in range(4)]


def test_every_loop_is_untangled_however_many_cross():
    """70 twisted loops, more than max_rounds: each loop gets its own rounds, so none
    keeps its crossing (one crossing per round over all loops used to leave 6)."""
    loops = [_bow_tie(30.0 * (k % 10), 30.0 * (k // 10)) for k in range(70)]
    assert all(polylines_cross(loop, 1e-3) for loop in loops)
    out = untangle(loops, 1e-3, max_rounds=64)
    assert not any(polylines_cross(loop, 1e-3) for loop in out)
    # the twist (the clockwise triangle) goes, the counter-clockwise one stays
    assert len(out) == 70
    assert all(mo.loop_area(loop) > 0 for loop in out)
    centres = np.array([np.mean([pc.start(p) for p in loop], axis=0) for loop in out])
    assert len(np.unique(np.round(centres // 30.0), axis=0)) == 70   # one per place


def test_loops_without_crossings_are_kept_in_order():
    sq = [pc.line(a, b) for a, b in [((0, 0), (1, 0)), ((1, 0), (1, 1)), ((1, 1), (0, 1)),
                                      ((0, 1), (0, 0))]]
    moved = [[pc.translate(p, (5.0, 0.0)) for p in sq]]
    out = untangle([sq, _bow_tie(20.0, 0.0)] + moved, 1e-3)
    assert len(out) == 3
    assert all(np.array_equal(p, q) for p, q in zip(out[0], sq))
    assert all(np.array_equal(p, q) for p, q in zip(out[2], moved[0]))


def test_subdivision_gives_up_only_the_near_coincident_pairs():
    """Two pieces 1e-9 apart (every level doubles their items) are given up alone;
    the other pair's crossing is still found by subdivision."""
    from morph.trim.crossing import PAIRS, _crowded, subdivided_crossings

    c = pc.cubic((0, 0), (3, 4), (7, 4), (10, 0))
    twin = pc.translate(c, (0.0, 1e-9))
    cross = pc.line((5.0, -1.0), (5.0, 5.0))
    pairs = np.array([[0, 1], [0, 2]])
    org, s, u, gave_up = subdivided_crossings([c, twin, cross], pairs,
                                              np.array([PAIRS, PAIRS]), 1e-4)
    assert list(gave_up) == [0]
    assert set(org) == {1}
    x = pc.evaluate(c, s[org == 1][:1])[0]
    assert np.allclose(x[0], 5.0, atol=1e-3)
    # the budget: pairs above pair_items, then the most crowded while over max_items
    assert list(_crowded(np.array([5, 2000, 7, 1]), 1024, 100)) == [1]
    assert list(_crowded(np.array([50, 20, 70, 1]), 1024, 60)) == [0, 2]


def test_a_hook_the_next_piece_runs_along_is_zipped_off():
    """A piece that runs past its end and doubles back (x: 0 -> 10.67 -> 9) onto a
    line that starts there and runs on along the same points: both legs of the hook
    coincide with the line, so no polyline or subdivision sees where the line
    leaves the outgoing leg.  remove_folds cuts both where the legs part (the
    hook's turning point) and the loop is simple, of the triangle's area; the
    swallowtail-like fold of legs that part at once (a tip) is left alone."""
    from shapely.geometry import LineString

    from morph.trim.untangle import remove_folds

    hook = pc.cubic((0, 0), (12, 0), (12, 0), (9, 0))
    loop = [hook, pc.line((9, 0), (20, 0)), pc.line((20, 0), (10, 5)), pc.line((10, 5), (0, 0))]
    out = remove_folds(loop, 0.07)
    assert len(out) == 4
    assert np.allclose(pc.end(out[0]), (32.0 / 3.0, 0.0), atol=0.07)  # the turning point
    assert np.allclose(pc.start(out[1]), pc.end(out[0])) and np.allclose(pc.end(out[1]), (20, 0))
    ring = pl.flatten_loop(out, 1e-4)
    assert LineString(np.vstack([ring, ring[:1]])).is_simple
    assert abs(mo.loop_area(out) - 50.0) < 1e-6
    # legs that coincide and then part without a turn (a veers off towards (14, 6)):
    # cut where they part (y_a = 7e-5, x = 9.2), not further back along a
    veer = pc.cubic((14, 6), (12, 0), (12, 0), (9, 0))
    loop = [veer, pc.line((9, 0), (20, 0)), pc.line((20, 0), (14, 6))]
    out = remove_folds(loop, 0.07)
    assert len(out) == 3 and 9.15 < pc.end(out[0])[0] < 9.25
    ring = pl.flatten_loop(out, 1e-4)
    assert LineString(np.vstack([ring, ring[:1]])).is_simple
    assert abs(mo.loop_area(out) - mo.loop_area(loop)) < 1e-3
    # a tip: the legs part at once (a turn of pi, not a spike), kept as it is
    tip = [pc.quadratic((0, 0), (5, 0.1), (10, 0)), pc.quadratic((10, 0), (5, -0.1), (1, -0.5)),
           pc.line((1, -0.5), (0, 0))]
    assert np.dot(pc.end_tangents(tip[0])[1], pc.end_tangents(tip[1])[0]) < -0.999  # a fold
    out = remove_folds(tip, 0.07)
    assert len(out) == 3 and all(np.array_equal(p, q) for p, q in zip(out, tip))


def test_two_outer_loops_crossing_in_a_lens_become_their_union():
    """Two unit circles 1.999 apart cross twice (a lens 0.001 wide, what the integer
    union keeps as two rings when it is under a grid step): merge_lenses gives one
    simple loop of the union's area (shapely, flattened within 1e-6); holes, and
    loops that do not cross, are left as they are."""
    from shapely.geometry import LineString, Polygon

    from morph.trim.untangle import merge_lenses

    a, b = pc.circle((0.0, 0.0), 1.0), pc.circle((1.999, 0.0), 1.0)
    out = merge_lenses([a, b], [True, True], 0.01)
    assert len(out) == 1
    ring = pl.flatten_loop(out[0], 1e-6)
    assert LineString(np.vstack([ring, ring[:1]])).is_simple
    union = Polygon(pl.flatten_loop(a, 1e-6)).union(Polygon(pl.flatten_loop(b, 1e-6)))
    assert abs(mo.loop_area(out[0]) - union.area) < 1e-5
    assert len(merge_lenses([a, b], [True, False], 0.01)) == 2
    # only the pairs said to be near are searched (boundary passes those whose rings
    # come within twice the lift's error)
    assert len(merge_lenses([a, b], [True, True], 0.01, near=set())) == 2
    assert len(merge_lenses([a, b], [True, True], 0.01, near={(1, 0)})) == 1
    far = pc.circle((2.5, 0.0), 1.0)
    assert len(merge_lenses([a, far], [True, True], 0.01)) == 2


def test_near_ring_pairs_match_shapely_distances():
    """trim._near_ring_pairs (which rings merge_lenses searches): exactly the pairs
    of closed polylines within reach of each other, by shapely's distances, on random
    circles; empty polylines have no neighbours."""
    from shapely.geometry import LinearRing

    from morph.trim import _near_ring_pairs

    def _near_pairs(polylines, reach):  # the polylines' vertices stacked, as boundary does
        sizes = np.array([len(p) for p in polylines], np.int64)
        pts = np.concatenate([np.reshape(p, (-1, 2)) for p in polylines] or [np.zeros((0, 2))])
        return _near_ring_pairs(pts, sizes, reach)

    for seed in range(12):  # boxes apart, boxes overlapping with rings apart, rings near
        rng = np.random.default_rng(seed)
        polys = []
        for _ in range(7):
            c, r = rng.uniform(0, 10, 2), rng.uniform(0.5, 2.0)
            t = np.linspace(0.0, 2 * np.pi, 40, endpoint=False)
            polys.append(np.stack([c[0] + r * np.cos(t), c[1] + r * np.sin(t)], 1))
        polys[3] = []
        want = {(i, j) for i in range(7) for j in range(i + 1, 7)
                if len(polys[i]) and len(polys[j])
                and LinearRing(polys[i]).distance(LinearRing(polys[j])) <= 0.3}
        assert _near_pairs(polys, 0.3) == want
    assert _near_pairs([], 0.3) == set() and _near_pairs([polys[0], []], 0.3) == set()


def test_a_comb_of_spikes_folds_back_to_its_square():
    """A square whose bottom edge carries 60 zero-width spikes (up and back down),
    some of two pieces each way (a fold behind a fold), one across the loop's wrap
    (its last piece runs up, its first back down): remove_folds leaves the square,
    every join turning by less than the fold angle and every point on the square's
    boundary, of area 10,000 (shapely: a simple ring)."""
    from shapely.geometry import LineString

    from morph.trim.untangle import FOLD_COS, remove_folds

    loop = [pc.line((0.5, 10), (0.5, 0)), pc.line((0.5, 0), (1, 0))]
    xs = np.linspace(1, 99, 61)
    for k, (x, x1) in enumerate(zip(xs[:-1], xs[1:])):
        if k % 3 == 0:
            loop += [pc.line((x, 0), (x, 5)), pc.line((x, 5), (x, 9)),
                     pc.line((x, 9), (x, 5)), pc.line((x, 5), (x, 0))]
        else:
            loop += [pc.line((x, 0), (x, 7)), pc.line((x, 7), (x, 0))]
        loop.append(pc.line((x, 0), (x1, 0)))
    loop += [pc.line((99, 0), (100, 0)), pc.line((100, 0), (100, 100)),
             pc.line((100, 100), (0, 100)), pc.line((0, 100), (0, 0)), pc.line((0, 0), (0.5, 0)),
             pc.line((0.5, 0), (0.5, 10))]
    out = remove_folds(loop, 1e-3)
    assert abs(mo.loop_area(out) - 10000.0) < 1e-9
    first, last = pc.end_tangents_many(out)
    assert (np.einsum("ij,ij->i", last, np.roll(first, -1, axis=0)) > FOLD_COS).all()
    ring = pl.flatten_loop(out, 1e-6)
    on_edge = (np.isclose(ring[:, 1], 0) | np.isclose(ring[:, 1], 100)
               | np.isclose(ring[:, 0], 0) | np.isclose(ring[:, 0], 100))
    assert on_edge.all()
    assert LineString(np.vstack([ring, ring[:1]])).is_simple


def _random_curved_loop(rng, n):
    """A closed loop of n rational quadratics and cubics through random points (curls
    and self-crossings included), joined exactly."""
    pts = rng.uniform(-10, 10, (n, 2))
    loop = []
    for k in range(n):
        a, b = pts[k], pts[(k + 1) % n]
        inner = rng.uniform(-12, 12, (int(rng.integers(1, 3)), 2))
        ctrl = np.vstack([a, inner, b])
        w = np.ones(len(ctrl))
        w[1:-1] = rng.uniform(0.3, 3.0, len(ctrl) - 2)
        loop.append(np.column_stack([ctrl * w[:, None], w]))
    return loop


def test_ray_winding_equals_the_winding_number_of_the_whole_flattened_loop():
    """The winding at a probe counted from the pieces whose boxes meet its ray equals
    the count over every edge of the loop flattened within the same tolerance
    (probes on the loop's own vertices and heights included)."""
    from morph.polyline import winding_number
    from morph.trim.untangle import _ray_winding

    rng = np.random.default_rng(7)
    for _ in range(30):
        loop = _random_curved_loop(rng, int(rng.integers(3, 12)))
        flat = 10.0 ** rng.uniform(-4, -1)
        poly = pl.flatten_loop(loop, flat)
        probes = np.vstack([rng.uniform(-12, 12, (60, 2)), poly[rng.integers(0, len(poly), 10)],
                            np.column_stack([rng.uniform(-12, 12, 10), poly[:10, 1]])])
        want = winding_number(probes, [poly])
        got = [_ray_winding(x, loop, flat) for x in probes]
        assert list(got) == list(want)


def test_snap_joins_every_piece_to_its_neighbours_and_drops_short_ones():
    """Snapping against a plain per-piece rule: pieces no longer than min_len go,
    each join is the midpoint of the two ends that meet, and only moved ends change."""
    from morph.trim.untangle import _snap

    rng = np.random.default_rng(3)
    for _ in range(20):
        loop = _random_curved_loop(rng, int(rng.integers(3, 9)))
        loop = [pc.with_endpoints(p, pc.start(p) + rng.normal(0, 1e-6, 2) * (k % 2),
                                  pc.end(p)) for k, p in enumerate(loop)]
        tiny = pc.line((0.0, 0.0), (1e-9, 0.0))
        loop.insert(int(rng.integers(0, len(loop))), pc.translate(tiny, pc.end(loop[0])))
        out = _snap(loop, 1e-7)
        assert len(out) == len(loop) - 1
        for k, p in enumerate(out):
            assert np.array_equal(pc.end(out[k - 1]), pc.start(p))
        kept = [p for p in loop if pc.length_bound(p) > 1e-7]
        for p, q in zip(kept, out):
            assert np.allclose(pc.cartesian(p)[1:-1], pc.cartesian(q)[1:-1], atol=0, rtol=0)
        assert not any(pc.length_bound(p) <= 1e-7 for p in out)


def test_hulls_apart_only_where_the_pieces_are():
    """_hulls_apart (the control polygons' hulls apart along some axis) on random
    pairs of cubics and rational conics: every pair it calls apart is apart on
    polylines within 1e-5 (shapely distance positive), no pair whose polylines
    meet is called apart, and it calls most of the far pairs apart; a conic with a
    negative weight (no hull property) is never apart."""
    import shapely
    from morph.trim.untangle import _hulls_apart

    rng = np.random.default_rng(4)
    pieces = []
    for k in range(60):
        c = rng.uniform(0, 40, 2)
        p = c + rng.uniform(-6, 6, (4, 2))
        if k % 3:
            pieces.append(pc.cubic(*p))
        else:
            h = np.c_[p[:3], np.ones(3)]
            h[1] *= rng.uniform(0.3, 3.0)
            pieces.append(h)
    neg = np.c_[np.array([[50.0, 0], [60, 10], [70, 0]]), [1.0, -0.5, 1.0]]
    neg[1, :2] *= -0.5
    pieces.append(neg)
    i, j = np.triu_indices(len(pieces), 1)
    pairs = np.stack([i, j], axis=1)
    apart = _hulls_apart(pc.Pieces.of(pieces), pairs)
    lines = [shapely.LineString(pl.flatten(p, 1e-5)[0]) for p in pieces]
    meeting = far = 0
    for (a, b), sep in zip(pairs, apart):
        d = lines[a].distance(lines[b])
        if sep:
            assert d > 0.0, (a, b)
        if d == 0.0:
            meeting += 1
            assert not sep, (a, b)
        far += d > 3.0
    assert meeting > 20 and apart.sum() > 0.8 * far
    assert not apart[(pairs == len(pieces) - 1).any(axis=1)].any()


def _split_items_one_by_one(it, keep, split_a):
    """The subdivision's next items, written out child by child (the reference for
    the batched :func:`morph.trim.crossing._split_items`): per slot, the children
    of every item of that slot's kind in item order."""
    from morph.trim.crossing import JOINED, PAIRS, SELF

    rows = [{k: v[i] for k, v in it.items()} for i in np.flatnonzero(keep)]
    halves = [bool(split_a[i]) for i in np.flatnonzero(keep)]
    slots = [(lambda r, h: r["kind"] == PAIRS and h, [dict(a1="am"), dict(a0="am")]),
             (lambda r, h: r["kind"] == PAIRS and not h, [dict(b1="bm"), dict(b0="bm")]),
             (lambda r, h: r["kind"] == JOINED,
              [dict(a0="am", b1="bm"), dict(a1="am", b1="bm", kind=PAIRS),
               dict(a0="am", b0="bm", kind=PAIRS), dict(a1="am", b0="bm", kind=PAIRS)]),
             (lambda r, h: r["kind"] == SELF,
              [dict(a1="am", b1="bm"), dict(a0="am", b0="bm"),
               dict(a1="am", b0="bm", kind=JOINED)])]
    out = []
    for test, children in slots:
        for child in children:
            for r, h in zip(rows, halves):
                if test(r, h):
                    mid = {"am": 0.5 * (r["a0"] + r["a1"]), "bm": 0.5 * (r["b0"] + r["b1"])}
                    new = dict(r)
                    for k, v in child.items():
                        new[k] = mid[v] if isinstance(v, str) else v
                    out.append(new)
    return {k: np.array([row[k] for row in out]) for k in it}


def test_split_items_batched_matches_child_by_child():
    """The subdivision's items split all at once (one sort of the children by slot)
    are those written out child by child, in the same order, to the bit, and each
    child's parts are its item's or their halves (de Casteljau at 1/2 one item at a
    time); a wrong midpoint (a child's interval not halved) differs."""
    from morph import bernstein as bz
    from morph.trim import crossing as cr

    rng = np.random.default_rng(7)
    n, deg = 200, 5
    a0, b0 = rng.random(n) * 0.5, rng.random(n) * 0.5
    it = dict(org=np.arange(n), a0=a0, a1=a0 + rng.random(n) * 0.5, b0=b0,
              b1=b0 + rng.random(n) * 0.5, kind=rng.integers(0, 3, n), row=np.arange(n))
    h = rng.random((n, 2, 3, deg + 1)) + 0.5
    items = cr._Items(it["org"], it["kind"], np.stack([it[k] for k in ("a0", "a1", "b0", "b1")],
                                                      axis=1), h)
    keep, split_a = rng.random(n) < 0.8, rng.random(n) < 0.5
    got, want = cr._split_items(items, keep, split_a), _split_items_one_by_one(it, keep, split_a)
    assert np.array_equal(got.org, want["org"]) and np.array_equal(got.kind, want["kind"])
    for col, k in enumerate(("a0", "a1", "b0", "b1")):
        assert np.array_equal(got.t[:, col], want[k])
    assert len(got.org) > 2 * keep.sum()     # joined and self items give more
    for c, row in enumerate(want["row"]):
        for part, (lo, hi) in enumerate((("a0", "a1"), ("b0", "b1"))):
            mid = 0.5 * (it[lo][row] + it[hi][row])
            left, right = bz.split_many(h[row, part].T[None], 0.5)
            ref = {(it[lo][row], it[hi][row]): h[row, part].T, (it[lo][row], mid): left[0],
                   (mid, it[hi][row]): right[0]}[(want[lo][c], want[hi][c])]
            assert np.allclose(got.h[c, part].T, ref, rtol=0, atol=1e-14)
    bad = got.t[:, 1] + np.where(got.kind == cr.SELF, 1e-3, 0.0)
    assert not np.array_equal(bad, want["a1"])


def test_stack_rows_is_the_stack_of_all_pieces_at_those_rows():
    """crossing.stack_rows: the rows of pc.stack of all the pieces (elevated to the
    degree of the highest of all, not of those taken), bit for bit, for a list and
    for packed pieces; taken from the rows' own degree it would differ."""
    from morph.trim.crossing import stack_rows

    pieces = [pc.line((0, 0), (1, 2)), pc.cubic((0, 0), (1, 3), (2, 3), (4, 0)),
              pc.line((3, 1), (5, 5)), pc.from_points([(0, 0), (1, 1), (2, 0)], [1.0, 0.7, 1.0]),
              pc.line((1, 1), (2, 2))]
    rows = np.array([0, 2, 3])
    for given in (pieces, pc.Pieces.of(pieces)):
        got = stack_rows(given, rows)
        assert np.array_equal(got, pc.stack(pieces)[rows])
    lines = stack_rows(pieces, np.array([0, 2]))
    assert lines.shape[1] == 4 and not np.array_equal(lines, pc.stack([pieces[0], pieces[2]]))


def test_untangle_of_the_packed_pieces_is_untangle_of_the_loops():
    """untangle(..., pieces=) (the lift's packed pieces searched as they are) gives
    the loops untangle gives gathering them itself; a pack of other pieces (squares
    for the twisted loops: nothing crosses) would leave the twists: the search
    reads the pack."""
    loops = [_bow_tie(30.0 * k, 0.0) for k in range(3)]
    sq = [pc.line(a, b) for a, b in [((0, 40), (1, 40)), ((1, 40), (1, 41)), ((1, 41), (0, 41)),
                                      ((0, 41), (0, 40))]]
    loops.append(sq)
    want = untangle(loops, 1e-3)
    got = untangle(loops, 1e-3, pieces=pc.Pieces.of([p for loop in loops for p in loop]))
    assert len(got) == len(want)
    assert all(len(a) == len(b) and all(np.array_equal(p, q) for p, q in zip(a, b))
               for a, b in zip(got, want))
    assert not any(polylines_cross(loop, 1e-3) for loop in got)
    squares = [pc.translate(p, (30.0 * k, 0.0)) for k in range(3) for p in sq] + sq
    wrong = untangle(loops, 1e-3, pieces=pc.Pieces.of(squares))
    assert any(polylines_cross(loop, 1e-3) for loop in wrong)


def _curly(a, b, d):
    """A cubic from a to b that overshoots both ends by a fifth of the chord, d off it:
    it crosses itself once in a curl of area about d / 15 (on a chord of 10)."""
    a, b = np.asarray(a, float), np.asarray(b, float)
    v = b - a
    n = np.array([-v[1], v[0]]) / np.hypot(*v)
    return pc.cubic(a, a + 1.2 * v + d * n, a - 0.2 * v + d * n, b)


def _two_curls(d, x=0.0):
    """A 10 x 10 square whose bottom and top sides each carry a curl (:func:`_curly`)."""
    c = np.array([(0, 0), (10, 0), (10, 10), (0, 10)], float) + (x, 0.0)
    return [_curly(c[0], c[1], d), pc.line(c[1], c[2]), _curly(c[2], c[3], d),
            pc.line(c[3], c[0])]


def test_curls_of_one_loop_go_in_one_round_as_one_by_one(monkeypatch):
    """A loop with two curls on two pieces: the round that cuts one also cuts the
    other (both below eps^2: they go in any order), so one round leaves no crossing,
    where cutting one curl a round leaves one; and the result is that of one curl a
    round, to 1e-12.  Curls above eps^2 are cut one a round either way."""
    import morph.trim.untangle as ut

    eps = 0.05
    loops = [_two_curls(1e-3), _two_curls(0.5, 20.0)]   # small curls, then large ones
    assert all(len(ut._first_crossings([loop], eps)) == 1 for loop in loops)
    batched = untangle(loops, eps)
    one_round = untangle(loops, eps, max_rounds=1)
    assert not ut._first_crossings(one_round[:1], eps)       # both small curls went
    assert len(ut._first_crossings(one_round[1:], eps)) == 1  # a large one is left
    monkeypatch.setattr(ut, "_batch_curls", lambda *a: {})
    assert len(ut._first_crossings(untangle(loops, eps, max_rounds=1)[:1], eps)) == 1
    one_by_one = untangle(loops, eps)
    assert [len(lp) for lp in batched] == [len(lp) for lp in one_by_one]
    for la, lb in zip(batched, one_by_one):
        for p, q in zip(la, lb):
            assert p.shape == q.shape and np.allclose(p, q, rtol=0.0, atol=1e-12)
    assert not ut._first_crossings(batched, eps)


def test_lens_merges_of_many_pairs_are_those_of_each_pair_alone():
    """Three lenses apart from each other and a chain of three circles (the merged
    loop of the first two crosses the third in a lens): merge_lenses searches every
    pair of a round together, and its loops are, in order and to the bit, those of
    each group merged alone (the group's merged loop last, one round a merge)."""
    from morph.trim.untangle import merge_lenses

    def lens(x):
        return [pc.circle((x, 0.0), 1.0), pc.circle((x + 1.999, 0.0), 1.0)]

    chain = [pc.circle((20.0 + 1.999 * k, 0.0), 1.0) for k in range(3)]
    groups = [lens(0.0), lens(6.0), chain, lens(12.0)]
    loops = [c for g in groups for c in g] + [pc.circle((40.0, 0.0), 1.0)]
    out = merge_lenses(loops, [True] * len(loops), 0.01)
    alone = [merge_lenses(g, [True] * len(g), 0.01) for g in groups]
    assert [len(g) for g in alone] == [1, 1, 1, 1]
    want = [loops[-1]] + [g[0] for g in alone]   # the merged loops last, in merge order
    assert len(out) == len(want)
    for got, exp in zip(out, want):
        assert len(got) == len(exp)
        assert all(p.shape == q.shape and np.array_equal(p, q) for p, q in zip(got, exp))


def test_fold_cuts_of_a_run_skip_every_other_fold():
    """Folds at consecutive joins share a piece: from a loop's last fold back, one
    whose second piece the next fold's cut took waits for the next pass, and a fold
    with no cut is left (not skipped) only where the next fold did not take its
    piece."""
    from morph.trim.untangle import _taken_folds

    g, i = np.array([0, 0, 0, 1]), np.array([2, 3, 4, 0])
    taken, skipped = _taken_folds(g, i, np.array([True, True, True, True]))
    assert taken.tolist() == [True, False, True, True]
    assert skipped.tolist() == [False, True, False, False]
    taken, skipped = _taken_folds(g, i, np.array([True, True, False, True]))
    assert taken.tolist() == [False, True, False, True]
    assert skipped.tolist() == [True, False, False, False]


def test_crossings_reported_twice_count_once():
    """_first_apart keeps a point unless an earlier kept point of its group lies
    within d: of three points 0.6 d apart in a row the middle one goes and the last
    stays (the one near it went); the same point in another group stays."""
    from morph.trim.untangle import _first_apart

    d = 1e-3
    pts = np.array([[0.0, 0.0], [0.6 * d, 0.0], [1.2 * d, 0.0], [0.0, 0.0]])
    assert _first_apart(pts, np.array([0, 0, 0, 1]), d).tolist() == [True, False, True, True]

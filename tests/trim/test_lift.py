"""morph.trim.lift: exact pieces and Newton crossings behind the integer rings, against
analytic crossings and exact areas."""

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph import nearest as nr
from morph.trim import boundary
from morph.trim import lift as L
from morph.trim.lift import newton_crossings


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
    assert mo.loop_area(loop) == pytest.approx(-triangle, rel=1e-9)


def test_boundary_of_two_crossing_circles_is_exact_arcs():
    a = list(pc.circle((0.0, 0.0), 1.0))
    b = list(pc.circle((1.0, 0.0), 1.0))
    loops = boundary([a, b], 1e-4, 1e-4, "nonzero")
    assert len(loops) == 1
    area = mo.region_area(loops)
    exact = 2 * np.pi - (2 * np.pi / 3 - np.sqrt(3) / 2)  # union of two unit disks
    assert area == pytest.approx(exact, abs=1e-9)
    for loop in loops:
        for p in loop:  # every output point on one of the circles, to rounding
            x = pc.evaluate(p, np.linspace(0, 1, 9))
            d = np.minimum(np.abs(np.hypot(*x.T) - 1), np.abs(np.hypot(x[:, 0] - 1, x[:, 1]) - 1))
            assert d.max() < 1e-9


def test_nearest_in_range_against_dense_sampling():
    """nr.nearest_params_in_range (where a crossing's Newton fails, each run ends
    at its piece's point nearest to the grid point within its segment's range) against
    the nearest of 20001 samples of the range, on random rational pieces of uneven
    speed."""

    rng = np.random.default_rng(5)
    m = 200
    ctrl = rng.uniform(-1, 1, (m, 7, 2)).cumsum(axis=1)
    w = rng.uniform(0.2, 5.0, (m, 7))
    stacked = np.concatenate([ctrl * w[..., None], w[..., None]], axis=2)
    lo = rng.uniform(0, 0.8, m)
    hi = np.minimum(lo + rng.uniform(0.01, 0.4, m), 1.0)
    mid = np.array([pc.evaluate(stacked[i], 0.5 * (lo[i] + hi[i]))[0] for i in range(m)])
    pts = mid + rng.normal(0, 0.05, (m, 2))
    s = nr.nearest_params_in_range(stacked, pts, lo, hi)
    assert np.all((s >= lo) & (s <= hi))
    got = np.hypot(*(np.array([pc.evaluate(stacked[i], s[i])[0] for i in range(m)]) - pts).T)
    dense = np.array([np.hypot(*(pc.evaluate(stacked[i], np.linspace(lo[i], hi[i], 20001))
                                 - pts[i]).T).min() for i in range(m)])
    assert np.all(got <= dense + 1e-9)
    # what the lift did before: the parameter interpolated along the chord, a point
    # up to ~0.2 farther on these pieces (the hump of cormorant U + a thin nib)
    a = np.array([pc.evaluate(stacked[i], lo[i])[0] for i in range(m)])
    b = np.array([pc.evaluate(stacked[i], hi[i])[0] for i in range(m)])
    u = np.clip(np.einsum("ij,ij->i", pts - a, b - a) / np.einsum("ij,ij->i", b - a, b - a),
                0.0, 1.0)
    t = lo + u * (hi - lo)
    naive = np.hypot(*(np.array([pc.evaluate(stacked[i], t[i])[0] for i in range(m)])
                       - pts).T)
    assert (naive - dense).max() > 0.05


def _newton_every_row(stacked, ia, ta, ib, tb, iters=12):
    """The iteration of :func:`newton_crossings` on every row every time (the
    reference for the one that drops rows at a fixed point; the step itself is
    :func:`morph.trim.lift.newton_step`, shared)."""
    from morph.trim.lift import newton_step

    s, u = np.array(ta, float), np.array(tb, float)
    ha, hb = stacked[ia], stacked[ib]
    n = stacked.shape[1] - 1
    dha, dhb = n * np.diff(ha, axis=1), n * np.diff(hb, axis=1)
    for _ in range(iters):
        s, u = newton_step(ha, dha, s, hb, dhb, u)
    return s, u


@pytest.mark.parametrize("iters", [12, 3])
def test_newton_dropping_rows_at_fixed_points_gives_the_same_bits(iters):
    """Rows leave the batch once a step leaves them where they are (converged to
    the last bit, or clamped at an end): s and u are the same bits as iterating
    every row (random crossing, touching, parallel and far apart cubic pairs;
    many rows converge early, many keep moving to the end)."""
    import morph.trim.lift as L

    rng = np.random.default_rng(17)
    m = 3000
    pts = rng.uniform(-1, 1, (2 * m, 4, 2))
    pts[m:] += rng.choice([0.0, 0.05, 3.0], (m, 1, 1))   # some far apart
    pts[m:m // 4 + m] = pts[:m // 4] + 1e-9                # some near-coincident
    w = rng.uniform(0.5, 2.0, (2 * m, 4, 1))
    w[:, [0, -1]] = 1.0
    stacked = np.concatenate([pts * w, w], axis=2)
    ia, ib = np.arange(m), np.arange(m, 2 * m)
    ta, tb = rng.choice([0.0, 1.0, 0.5], m), rng.uniform(0, 1, m)
    want = _newton_every_row(stacked, ia, ta, ib, tb, iters)
    got = L.newton_crossings(stacked, ia, ta, ib, tb, np.zeros((m, 2)), 1.0, 1e-9, iters=iters)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])
    moved = _newton_every_row(stacked, ia, ta, ib, tb, iters - 1)
    still = (moved[0] != want[0]) | (moved[1] != want[1])
    assert 0.1 * m < still.sum() < 0.9 * m   # both kinds of rows occur


def test_best_fits_take_each_edges_first_least_score():
    """_best_fits (two unbuffered reductions) takes what a stable sort by (edge,
    score) takes first: each edge's least score, ties to the first candidate; edges
    without candidates keep score inf and segment 0."""
    rng = np.random.default_rng(41)
    for _ in range(30):
        n, m = int(rng.integers(1, 40)), int(rng.integers(0, 200))
        e = rng.integers(0, n, m)
        score = rng.choice([0.5, 1.0, 2.0], m) if m % 2 else rng.uniform(0, 3, m)
        s, fwd = rng.integers(0, 1000, m), rng.random(m) < 0.5
        best, seg, direction = L._best_fits(n, e, s, score, fwd)
        want_best, want_seg, want_dir = np.full(n, np.inf), np.zeros(n, np.int64), np.ones(n, bool)
        order = np.lexsort((score, e))
        take = order[np.r_[True, np.diff(e[order]) != 0]] if m else order
        want_best[e[take]], want_seg[e[take]], want_dir[e[take]] = score[take], s[take], fwd[take]
        assert np.array_equal(best, want_best) and np.array_equal(seg, want_seg)
        assert np.array_equal(direction, want_dir)


def test_unique_vertex_finds_keys_met_once():
    """_unique_vertex (one search) gives the vertex of keys found exactly once, -1
    for keys found never or several times, past both ends included."""
    rng = np.random.default_rng(43)
    keys = rng.integers(0, 60, 80)
    order = np.argsort(keys, kind="stable")
    sk = keys[order]
    probe = rng.integers(-5, 70, 300)
    got = L._unique_vertex(sk, order, probe)
    count = np.array([(keys == k).sum() for k in probe])
    want = np.array([int(np.flatnonzero(keys == k)[0]) if c == 1 else -1
                     for k, c in zip(probe, count)])
    assert np.array_equal(got, want) and (want >= 0).any() and (count > 1).any()
    assert np.array_equal(L._unique_vertex(sk[:0], order[:0], probe), np.full(300, -1))


def test_newton_rows_that_settle_stop_within_a_hair_of_the_fixed_point():
    """With ``settle``, rows leave once a step moves them by at most that: the
    crossings found (ok) are the same rows, their points within 10 settle of the
    iteration run to its fixed points, in fewer row-steps; pieces far from the
    origin, whose iterates never reach a fixed point, included."""
    import morph.trim.lift as lift

    rng = np.random.default_rng(47)
    m = 2000
    pts = rng.uniform(-1, 1, (m, 3, 2)) + 5e4          # far from the origin
    w = rng.uniform(0.5, 2.0, (m, 3, 1))
    w[:, [0, -1]] = 1.0
    arcs = np.concatenate([pts * w, w], axis=2)
    # straight pieces through a point of each arc, at random angles: real crossings
    s_true = rng.uniform(0.2, 0.8, m)
    x = pc.jet_many(arcs, np.arange(m), s_true)[0]
    v = rng.normal(0, 1, (m, 2))
    lines = np.ones((m, 3, 3))
    lines[:, :, :2] = x[:, None] + np.array([-1.0, 0.0, 1.0])[None, :, None] * v[:, None]
    stacked = np.concatenate([arcs, lines])
    ia, ib = np.arange(m), np.arange(m, 2 * m)
    ta, tb = s_true + rng.uniform(-0.05, 0.05, m), 0.5 + rng.uniform(-0.05, 0.05, m)
    steps = []
    real = lift._newton_step

    def counted(*a):
        steps.append(len(a[2]))
        return real(*a)

    lift._newton_step = counted
    try:
        s0, u0, ok0 = lift.newton_crossings(stacked, ia, ta, ib, tb, x, 1.0, 1e-6)
        full = sum(steps)
        steps.clear()
        settle = 1e-9
        s1, u1, ok1 = lift.newton_crossings(stacked, ia, ta, ib, tb, x, 1.0, 1e-6,
                                            settle=settle)
    finally:
        lift._newton_step = real
    assert np.array_equal(ok0, ok1) and ok0.sum() > 0.9 * m
    a0 = pc.jet_many(stacked, ia, s0)[0]
    a1 = pc.jet_many(stacked, ia, s1)[0]
    assert np.hypot(*(a0 - a1)[ok0].T).max() <= 10 * settle
    assert sum(steps) < 0.7 * full


def test_nearest_segments_from_the_snap_rounding_grid_are_a_grid_of_their_own():
    """The lift's search for the segments near an edge, on the snap rounding's grid
    (segments before hot pixels cut them, grown by SEGMENT_REACH), gives what a grid
    of the cut segments gives, on loops of near-coincident and crossing circles
    (many hot pixels) with edges from random grid points."""
    from morph.trim.flatten import SEGMENT_REACH, tag_loops

    assert L.MATCH_UNITS + 0.5 <= SEGMENT_REACH
    loops = [pc.circle((0.0, 0.0), 1.0), pc.circle((0.003, 0.0), 1.0),
             pc.circle((1.2, 0.3), 0.8), [pc.reverse(p) for p in pc.circle((0.5, 0.1), 0.4)]]
    tg = tag_loops(loops, 1e-3, 1e-3)
    assert tg.seg_grid is not None and (tg.seg_count > 1).any()
    rng = np.random.default_rng(53)
    k = rng.integers(0, len(tg.q), 400)
    p = tg.q[k] + rng.integers(-4, 5, (400, 2))
    q = tg.q[tg.nxt[k]] + rng.integers(-4, 5, (400, 2))
    sa, sb = tg.q, tg.q[tg.nxt]
    got = L._nearest_segments(p.astype(float), q.astype(float), sa, sb, tg)
    want = L._nearest_segments(p.astype(float), q.astype(float), sa, sb)
    assert np.array_equal(got[0], want[0]) and np.array_equal(got[1], want[1])


def test_spikes_cut_in_place_of_the_packed_runs_match_the_lists():
    """lift._with_spikes_cut (only the flagged rings taken out as lists, the others
    kept in the packed stacks, all put back in ring order) gives the runs that
    cutting every ring as lists gives (_as_runs, _cut_flagged, _flat_runs), bit for
    bit; the spiked ring between two square rings loses its sliver.  Put back in
    the wrong place (the cut ring last) the runs would differ."""
    from morph.trim.lift import (_as_runs, _cut_flagged, _flat_runs, _spike_triples,
                                 _with_spikes_cut)

    def square(x):
        p = [(x, 0.0), (x + 1.0, 0.0), (x + 1.0, 1.0), (x, 1.0)]
        return [pc.line(p[k], p[(k + 1) % 4]) for k in range(4)]

    pts = [(1.006, -0.874), (1.045, -0.765), (1.008, -0.729), (-0.767, -0.729),
           (0.019, 1.161), (1.064, -1.087)]
    spiked = [pc.line(pts[0], pts[1]), pc.line(pts[2], pts[3]), pc.line(pts[3], pts[4]),
              pc.line(pts[4], pts[5]), pc.line(pts[5], pts[0])]
    rings = [square(5.0), spiked, square(-5.0)]
    pieces = [p for r in rings for p in r]
    ends = np.array([0.5 * (pc.end(r[k]) + pc.start(r[(k + 1) % len(r)]))
                     for r in rings for k in range(len(r))])
    flat = (pc.Pieces.of(pieces), ends, np.array([len(r) for r in rings]))
    flagged = _spike_triples(flat, 0.05)
    assert {r for r, _ in flagged} == {1}
    got = _with_spikes_cut(flat, flagged, 0.05)
    runs = _as_runs(flat)
    _cut_flagged(runs, flagged, 0.05)
    want = _flat_runs(runs)
    assert list(got[2]) == list(want[2]) == [4, 3, 4]
    assert np.array_equal(got[1], want[1])
    assert all(np.array_equal(p, q) for p, q in zip(got[0], want[0]))
    moved = [want[0][k] for k in [0, 1, 2, 3, 7, 8, 9, 10, 4, 5, 6]]
    assert not all(np.array_equal(p, q) for p, q in zip(got[0], moved))

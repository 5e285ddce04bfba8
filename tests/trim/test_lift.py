"""morph.trim.lift: exact pieces and Newton crossings behind the integer rings, against
analytic crossings and exact areas."""

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph import nearest as nr
from morph.trim import boundary
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

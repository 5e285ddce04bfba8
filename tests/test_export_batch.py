"""The batched export (all loops of many glyphs in per-degree arrays, the certificate
started from the fitter's rays) against independent computations.

The oracles are those of tests/test_export.py: exact closest distances to rational
and Bézier curves (roots of the closest-point polynomial), plain Bernstein sums, the
circle's own formula.  Every check is shown to fail on a curve displaced by twice
the tolerance.
"""

import math

import numpy as np
import pytest

from morph import piece as pc
from morph.export import certify as certify_mod
from morph.export import loop_to_beziers, loops_to_beziers
from morph.export.bank import Bank, plan_runs
from morph.export.fit import Parts, _quadrature, moment_cubics
from morph.export.search import chains_segments
from tests.test_export import (bernstein, closest_distances, rational, reparam_values,
                                sampled_panel_error)
from tests.test_export_greedy import g1_chain


def circle_loop(center, r, n, start=0.0, elevate=()):
    """A circle as n rational quadratic arcs starting at angle ``start``; the arcs
    listed in ``elevate`` degree-elevated (exactly) by one, so that one smooth run
    holds pieces of two degrees."""
    arcs = [pc.ellipse_arc(center, r, r, 0.0, start + 2 * math.pi * k / n, 2 * math.pi / n)[0]
            for k in range(n)]
    return [pc.elevate(a) if k in elevate else a for k, a in enumerate(arcs)]


def slot_loop(x0, length, r):
    """A stadium (two lines, two half circles of two arcs each): runs 1, 2, 1, 2."""
    return ([pc.line((x0, -r), (x0 + length, -r))]
            + pc.ellipse_arc((x0 + length, 0), r, r, 0.0, -np.pi / 2, np.pi)
            + [pc.line((x0 + length, r), (x0, r))]
            + pc.ellipse_arc((x0, 0), r, r, 0.0, np.pi / 2, np.pi))


def d_loop(x0):
    """A D shape starting in the middle of its arc: wrapped, the arc is one run."""
    upper = pc.ellipse_arc((x0, 0), 1.0, 1.0, 0.0, 0.0, np.pi / 2)
    lower = pc.ellipse_arc((x0, 0), 1.0, 1.0, 0.0, -np.pi / 2, np.pi / 2)
    return upper + [pc.line((x0, 1), (x0, -1))] + lower


def batch():
    return [circle_loop((0.0, 0.0), 3.0, 7, 0.3, elevate=(2, 5)), slot_loop(10.0, 4.0, 1.5),
            d_loop(20.0), circle_loop((30.0, 5.0), 0.5, 4), [pc.line((0, 0), (1, 0)),
                                                             pc.line((1, 0), (0, 1)),
                                                             pc.line((0, 1), (0, 0))]]


def test_plan_runs_of_a_batch_are_the_loops_known_runs():
    """The runs planned for all loops at once are those each loop has by
    construction: the stadium splits at its four lines' ends (1, 2, 1, 2), the D at
    its corners (wrapped: the arc halves are one run), a circle is one run (its
    start is a smooth join: wrapped, nothing is split), mixed degrees in one run, a
    triangle is three lines (exact); an arc turned by 0.01 rad is a corner at both
    its ends."""
    _, runs = plan_runs(batch(), 1e-6, wrap=True)
    sizes = [[len(r) for r, _ in loop] for loop in runs]
    assert sizes == [[7], [1, 2, 1, 2], [2, 1], [4], [1, 1, 1]]
    assert [[e for _, e in loop] for loop in runs][4] == [True, True, True]
    assert [e for _, e in runs[1]] == [True, False, True, False]
    _, plain = plan_runs(batch(), 1e-6, wrap=False)
    assert [[len(r) for r, _ in loop] for loop in plain][2] == [1, 1, 1]
    # a corner: a circle whose fourth arc is turned by 0.01 rad is split there
    arcs = circle_loop((0.0, 0.0), 1.0, 6)
    arcs[3] = pc.transform(arcs[3], np.array([[math.cos(0.01), -math.sin(0.01), 0.0],
                                              [math.sin(0.01), math.cos(0.01), 0.0]]))
    arcs[3] = pc.translate(arcs[3], pc.end(arcs[2]) - pc.start(arcs[3]))
    _, (split,) = plan_runs([arcs], 1e-6, wrap=True)
    assert [r.tolist() for r, _ in split] == [[4, 5, 0, 1, 2], [3]]


def test_bank_names_a_bad_piece():
    good = pc.line((0, 0), (1, 0))
    bad = np.array([[0.0, 0.0, 1.0], [1.0, 1.0, -1.0], [2.0, 0.0, 1.0]])
    with pytest.raises(ValueError, match="positive weights"):
        Bank([good, bad])
    with pytest.raises(ValueError, match="finite"):
        Bank([good, np.array([[0.0, 0.0, 1.0], [np.nan, 0.0, 1.0]])])


def _two_sided(beziers, loop):
    """Two-sided Hausdorff distance (on samples, exact closest points) between the
    written curves and the loop's exact pieces."""
    pts = np.vstack([bernstein(b, np.linspace(0, 1, 33)) for b in beziers])
    back = np.vstack([rational(p)(np.linspace(0, 1, 33)) for p in loop])
    return max(closest_distances(pts, loop).max(), closest_distances(back, beziers).max())


@pytest.mark.parametrize("tol", [1e-2, 1e-5])
def test_batched_loops_within_tol_as_loop_by_loop(tol):
    """All loops in one batch: each written loop is within tol of its exact loop
    (two-sided, exact closest points), closed end to start, with as many curves as
    the loop fitted alone; one curve displaced by 2 tol fails the same check."""
    loops = batch()
    together = loops_to_beziers(loops, tol, wrap=True)
    for loop, out in zip(loops, together):
        alone = loop_to_beziers(loop, tol, wrap=True)
        assert len(out) == len(alone)
        for a, b in zip(out, out[1:] + out[:1]):
            assert np.allclose(a[-1], b[0], atol=1e-12)
        assert _two_sided(out, loop) <= tol * (1 + 1e-9)
    # the oracle can fail: a cubic of the first circle pushed outward by 2 tol
    out = [b.copy() for b in together[0]]
    k = next(i for i, b in enumerate(out) if len(b) == 4)
    mid = bernstein(out[k], [0.5])[0]
    out[k][1:3] += 2.0 * tol * mid / np.hypot(*mid) * 4.0 / 3.0
    assert _two_sided(out, loops[0]) > tol


def _ray_fit(pieces, tol):
    """The fitter's cubic for one whole chain as one range, with its rays' feet."""
    bank = Bank(pieces)
    n = len(pieces)
    parts = Parts(np.zeros(n, int), np.arange(n), np.zeros(n), np.ones(n))
    starts, ends = bank.first[:1], bank.last[-1:]
    cubic, dist, fitted, rays = moment_cubics(bank, parts, starts, ends, np.array([1e-12]), tol)
    assert fitted[0]
    return bank, cubic[0], rays


def test_certificate_from_the_fitters_rays_is_a_certificate():
    """An eighth of a circle (one rational piece): the certificate started from the
    fitter's rays gives the same bound as the one started from dense samples (the
    feet Newton finds are the same), the bound is >= |R(phi(s)) - C(s)| on dense
    samples (plain Bernstein sums), and the cubic displaced by 2 tol does not
    certify (its bound > tol), from either start."""
    tol = 1e-3
    arc = pc.ellipse_arc((0.0, 0.0), 10.0, 10.0, 0.0, 0.2, math.pi / 4)[0]
    bank, cubic, rays = _ray_fit([arc], tol)
    start = certify_mod.start_at_nodes(rays.feet, _quadrature().gx)
    assert np.all(np.isfinite(start))
    groups = [(np.array([0]), arc[None])]
    fast = certify_mod.certify_batch(groups, cubic[None], tol, start=start)
    dense = certify_mod.certify_batch(groups, cubic[None], tol)
    assert fast.bound[0] <= tol
    assert fast.bound[0] == pytest.approx(dense.bound[0], rel=1e-6)
    for s0, s1, phi in fast.panels(0):
        s = np.linspace(s0, s1, 2001)
        u = reparam_values(phi, (s - s0) / (s1 - s0))
        err = np.hypot(*(rational(arc)(u) - bernstein(cubic, s)).T).max()
        assert err <= fast.bound[0] * (1 + 1e-9)
    # a start far from the feet (reversed) may give a looser bound, never a wrong one
    wrong = certify_mod.certify_batch(groups, cubic[None], tol, start=start[:, ::-1].copy())
    for s0, s1, phi in wrong.panels(0):
        s = np.linspace(s0, s1, 2001)
        u = reparam_values(phi, (s - s0) / (s1 - s0))
        err = np.hypot(*(rational(arc)(u) - bernstein(cubic, s)).T).max()
        assert err <= wrong.bound[0] * (1 + 1e-9)
    # displaced by 2 tol along the normal at the middle: no certificate
    mid = bernstein(cubic, [0.5])[0]
    moved = cubic.copy()
    moved[1:3] += 2.0 * tol * mid / np.hypot(*mid) * 4.0 / 3.0
    for s in (start, None):
        assert certify_mod.certify_batch(groups, moved[None], tol, start=s).bound[0] > tol


def test_rays_start_near_the_true_feet():
    """The starting feet built from the fitter's rays are within a small share of the
    parameter range of the exact feet of the cubic's nodes on the piece (closest
    points from dense sampling and ternary refinement here, not Newton)."""
    tol = 1e-3
    arc = pc.ellipse_arc((0.0, 0.0), 5.0, 3.0, 0.4, 0.0, 1.4)[0]
    _, cubic, rays = _ray_fit([arc], tol)
    start = certify_mod.start_at_nodes(rays.feet, _quadrature().gx)[0]
    nodes = bernstein(cubic, certify_mod._NODES)
    t = np.linspace(0, 1, 20001)
    curve = rational(arc)(t)
    true = t[np.argmin(((nodes[:, None] - curve[None]) ** 2).sum(-1), axis=1)]
    assert np.abs(start - true).max() < 0.02


def test_certificate_from_the_fitters_pairs_is_a_certificate(monkeypatch):
    """phi fitted to the pairs of parameters the fitter's rays found (the piece not
    evaluated again): on an ellipse arc and on a rational piece of uneven speed (a
    Möbius map needed), the bound is >= |R(phi(s)) - C(s)| on dense samples, within
    tol and close to the bound from Newton's feet; the cubic displaced by 2 tol
    along its middle normal does not certify."""
    tol = 1e-3
    arc = pc.ellipse_arc((0.0, 0.0), 5.0, 3.0, 0.4, 0.0, 1.4)[0]
    uneven = arc.copy()
    uneven *= np.array([1.0, 3.0, 9.0])[:, None]   # the same curve, weights c^i
    for piece in (arc, uneven):
        bank, cubic, rays = _ray_fit([piece], tol)
        gx = _quadrature().gx
        pairs = (rays.feet, gx, rays.speed, rays.gap)
        assert np.all(np.isfinite(rays.feet)) and np.all(rays.gap <= tol)
        groups = [(np.array([0]), piece[None])]
        with monkeypatch.context() as m:   # phi from the pairs alone: no Newton search
            m.setattr(certify_mod, "_newton_reparams", None)
            composed = certify_mod.certify_batch(groups, cubic[None], tol, pairs=pairs,
                                                 panel=False)
            m.setattr(certify_mod, "PANEL_DEGREE", 2)      # a conic on the ray panels too
            paneled = certify_mod.certify_batch(groups, cubic[None], tol, pairs=pairs)
        assert (composed.c[0] != 1.0) == (piece is uneven)
        # the ray panels certify the arc; the uneven piece, whose feet no Möbius map
        # per panel follows within tol, falls back to the composed map
        assert paneled.cuts is not None and (paneled.other[0] < 0 or piece is uneven)
        newton = certify_mod.certify_batch(groups, cubic[None], tol,
                                           start=certify_mod.start_at_nodes(rays.feet, gx))
        for res in (composed, paneled):
            assert res.bound[0] <= tol
            assert res.bound[0] <= 2.0 * newton.bound[0]
            for s0, s1, phi in res.panels(0):
                s = np.linspace(s0, s1, 4001)
                u = reparam_values(phi, (s - s0) / (s1 - s0))
                err = np.hypot(*(rational(piece)(u) - bernstein(cubic, s)).T).max()
                assert err <= res.bound[0] * (1 + 1e-9)
        # the speed and the gaps are the piece's own (independent evaluation)
        pts = rational(piece)(gx)
        assert np.allclose(np.hypot(*(bernstein(cubic, rays.feet[0]) - pts).T), rays.gap[0],
                           rtol=1e-9, atol=1e-12)
        mid = bernstein(cubic, [0.5])[0] - bernstein(cubic, [0.5 - 1e-6])[0]
        normal = np.array([-mid[1], mid[0]]) / np.hypot(*mid)
        moved = cubic.copy()
        moved[1:3] += 2.0 * tol * normal * 4.0 / 3.0
        assert certify_mod.certify_batch(groups, moved[None], tol, pairs=pairs).bound[0] > tol


@pytest.mark.parametrize("seed", [0, 1])
def test_chains_segments_panels_certified(seed):
    """Many G1 chains of mixed degree searched in one batch: every segment's bound
    holds on dense samples of |R(phi(s)) - C(s)| of its panels (R by plain Bernstein
    sums) and is <= tol; shifting the cubic by 2 tol breaks that sampled check."""
    rng = np.random.default_rng(seed)
    tol = 1e-4
    chains = []
    for _ in range(4):
        radii = rng.uniform(0.5, 3.0, rng.integers(2, 5))
        pieces, p, ang = [], np.array([0.0, 0.0]), rng.uniform(0, 6)
        for r in radii:
            c = p - r * np.array([math.cos(ang), math.sin(ang)])
            arc = pc.ellipse_arc(tuple(c), r, r, 0.0, ang, 0.8)[0]
            pieces.append(pc.elevate(arc) if rng.random() < 0.4 else arc)
            ang += 0.8
            p = c + r * np.array([math.cos(ang), math.sin(ang)])
        chains.append(pieces)
    for pieces, segs in zip(chains, chains_segments(chains, tol)):
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        for seg in segs:
            assert seg.bound <= tol and seg.reparam
            worst, moved = sampled_panel_error(pieces, seg, [0, 2 * tol])
            assert worst <= seg.bound * (1 + 1e-9) + 1e-13
            assert moved > tol


def test_cubic_integrals_are_the_bernstein_sums_and_the_curves_moments():
    """The fitter's area and moment polynomials: the same numbers as the whole
    Bernstein sums over every index (np.einsum of the documented formula: the terms
    left out are zeros), and, for handle lengths (d0, d1), the signed area int y dx
    and moment int x y dx of the frame cubic itself (Gauss-Legendre on the cubic,
    exact for these degrees); a moment off by 1 % of its size fails the check."""
    from morph.export.fit import _cubic_integrals

    rng = np.random.default_rng(21)
    n = 500
    a0, a1 = rng.uniform(-3, 3, n), rng.uniform(-3, 3, n)
    t0 = np.stack([np.cos(a0), np.sin(a0)], 1)
    t1 = np.stack([np.cos(a1), np.sin(a1)], 1)
    t0[0], t1[0] = [1.0, 0.0], [1.0, 0.0]                          # straight: zeros
    ta, tm = _cubic_integrals(t0, t1)
    c0, s0, c1, s1 = t0[:, 0], t0[:, 1], t1[:, 0], -t1[:, 1]
    zero, one = np.zeros(n), np.ones(n)
    xs = np.stack([np.stack([zero, zero, one, one], 1), np.stack([zero, c0, zero, zero], 1),
                   np.stack([zero, zero, -c1, zero], 1)], 1)
    ys = np.stack([np.stack([zero, s0, zero, zero], 1), np.stack([zero, zero, s1, zero], 1)], 1)
    quad = _quadrature()
    assert np.array_equal(ta, np.einsum("rbj,rck,jk->rbc", ys, xs, quad.i2))
    assert np.array_equal(tm, np.einsum("rai,rbj,rck,ijk->rabc", xs, ys, xs, quad.i3))
    d0, d1 = rng.uniform(0.1, 1.5, n), rng.uniform(0.1, 1.5, n)
    ctrl = np.zeros((n, 4, 2))
    ctrl[:, 1] = d0[:, None] * t0
    ctrl[:, 2] = [1.0, 0.0] - d1[:, None] * t1
    ctrl[:, 3] = [1.0, 0.0]
    x, w = np.polynomial.legendre.leggauss(12)
    s = 0.5 + 0.5 * x
    p = np.stack([bernstein(c, s) for c in ctrl])
    dp = np.stack([bernstein(3.0 * np.diff(c, axis=0), s) for c in ctrl])
    area = (0.5 * w * p[..., 1] * dp[..., 0]).sum(1)
    moment = (0.5 * w * p[..., 0] * p[..., 1] * dp[..., 0]).sum(1)
    m = np.stack([one, d0, d1], 1)
    dd = np.stack([d0, d1], 1)
    assert np.allclose(np.einsum("rb,rbc,rc->r", dd, ta, m), area, rtol=0, atol=1e-12)
    got = np.einsum("ra,rb,rc,rabc->r", m, dd, m, tm)
    assert np.allclose(got, moment, rtol=0, atol=1e-12)
    assert not np.allclose(got * 1.01, moment, rtol=0, atol=1e-12)


def test_pruned_rays_pick_what_every_ray_picks(monkeypatch):
    """The fitter casts every candidate's rays at four samples first and the rest
    only for candidates that can still be picked (:func:`morph.export.fit.
    _ray_distance`).  On every round of a batch of G1 chains, each range's pick, its
    sampled distance and the rays kept for the certificate are those of casting
    every ray of every candidate (each candidate measured alone, nothing to rule it
    out), a candidate measured is measured exactly so, and some candidates were
    dropped (the pruning was exercised)."""
    from morph.export import fit as fit_mod

    real = fit_mod._ray_distance
    seen = {"rounds": 0, "dropped": 0, "others": 0}

    def checked(ctrl, cr, sam, req, width, length, scale, acc):
        err, rays = real(ctrl, cr, sam, req, width, length, scale, acc)
        cand, _, stages = rays
        every = _every_ray(real, ctrl, cr, sam, req, width, length)
        full = np.array([d for d, _ in every])
        measured = np.isfinite(err)
        assert np.array_equal(err[measured], full[measured])
        score_all, score = full * length * scale, err * length * scale
        for r in np.unique(cr):
            mine = np.nonzero(cr == r)[0]
            picks = []
            for sc in (score_all, score):
                ok = mine[sc[mine] < acc[mine]]
                picks.append(ok[np.argmin(sc[ok])] if len(ok) else -1)
            assert picks[0] == picks[1]
            if picks[0] >= 0:                  # the pick's rays: all cast, as alone
                rows = np.nonzero(cand == picks[0])[0]
                have = np.full((len(rows), sam.speed.shape[0]), np.nan)
                for pairs, cols, s, _ in stages:
                    at = np.nonzero(np.isin(pairs, rows))[0]
                    have[np.ix_(np.searchsorted(rows, pairs[at]), cols)] = s[at]
                assert np.array_equal(have, every[picks[0]][1])
        seen["rounds"] += 1
        seen["dropped"] += int((~measured).sum())
        seen["others"] += int(measured.sum()) - len(np.unique(cr[measured]))
        return err, rays

    monkeypatch.setattr(fit_mod, "_ray_distance", checked)
    rng = np.random.default_rng(7)
    chains_segments([g1_chain(rng, int(rng.integers(1, 9))) for _ in range(12)], 1e-3)
    # some candidates dropped, some measured besides their range's best
    assert seen["rounds"] > 3 and seen["dropped"] > 0 and seen["others"] > 0


def _every_ray(real, ctrl, cr, sam, req, width, length):
    """Per candidate (distance, s (its parts, 16)) with every ray cast: the
    candidate measured alone with an infinite acceptance distance."""
    out = []
    for c in range(len(cr)):
        err, (cand, _, stages) = real(ctrl[c:c + 1], cr[c:c + 1], sam, req, width,
                                      length[c:c + 1], np.ones(1), np.full(1, np.inf))
        s = np.full((len(cand), sam.speed.shape[0]), np.nan)
        for pairs, cols, ss, _ in stages:
            s[np.ix_(pairs, cols)] = ss
        assert not np.isnan(s).any()
        out.append((err[0], s))
    return out


def test_node_planes_are_the_jets_of_the_pieces():
    """The bank's samples at the fitter's nodes, made once per piece and kept, are
    the points and derivatives of :meth:`Bank.jet` at those parameters (to
    rounding), whatever the order and repetition in which pieces are asked for."""
    bank = Bank([p for loop in batch() for p in loop])
    t = _quadrature().gx
    gids = np.array([3, 1, 3, 7, 0])
    planes = bank.node_planes(gids, t)                  # (4, nodes, pieces)
    p1, d1 = planes[:2].T, planes[2:].T
    p2 = bank.node_planes(np.array([7, 2, 1]), t)[:2].T
    assert np.array_equal(p2[0], p1[3]) and np.array_equal(p2[2], p1[1])
    for g, p, d in zip(gids, p1, d1):
        pe, de = bank.jet(np.full(len(t), g), t)
        assert np.allclose(p, pe, rtol=0, atol=1e-12) and np.allclose(d, de, rtol=1e-12,
                                                                       atol=1e-12)
    assert not np.allclose(p1[0], p1[1])

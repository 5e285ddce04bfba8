"""The "one segment fewer" refinement as arrays (morph/export/refine.py): its array
helpers against numpy's own functions called row by row (the same numbers, bit for
bit, so that a chain's cuts do not depend on the other chains of its batch), its
arc lengths against a dense polyline, and the refined segments against exact
closest distances (tests/test_export.py), a check shown to fail on a cubic displaced
by twice the tolerance."""

import math

import numpy as np
import pytest

from morph import piece as pc
from morph.export.bank import Bank
from morph.export.fit import make_chains
from morph.export.refine import (arc_lengths, chain_points, interp_rows, per_row, ranges,
                                 spaced_rows)
from morph.export.search import chains_segments
from tests.test_export import bernstein, closest_distances, rational
from tests.test_export_greedy import g1_chain


def test_interp_rows_is_np_interp_bit_for_bit():
    """Every row's values are np.interp's on that row alone: inside, on knots, at and
    beyond both ends, flat stretches, NaN; rows of 2 to 40 knots in one call."""
    rng = np.random.default_rng(3)
    xs, fps, queries, rows = [], [], [], []
    for r in range(60):
        n = int(rng.integers(2, 41))
        xp = np.cumsum(rng.uniform(1e-3, 2.0, n)) - 5.0
        fp = rng.normal(0, 10, n)
        if r % 5 == 0:
            fp[n // 2:] = fp[n // 2]                                # a flat stretch
        q = np.concatenate([rng.uniform(xp[0] - 1, xp[-1] + 1, 25), xp[[0, -1]],
                            xp[rng.integers(0, n, 3)], [np.nan, xp[0] - 1e-300]])
        xs.append(xp)
        fps.append(fp)
        queries.append(q)
        rows.append(np.full(len(q), r))
    hi = np.cumsum([len(x) for x in xs])
    lo = hi - [len(x) for x in xs]
    got = interp_rows(np.concatenate(queries), np.concatenate(rows), lo, hi,
                      np.concatenate(xs), np.concatenate(fps))
    want = np.concatenate([np.interp(q, x, f) for q, x, f in zip(queries, xs, fps)])
    assert np.array_equal(got, want, equal_nan=True)
    # an oracle that can fail: one knot moved changes the values near it
    moved = np.concatenate(fps)
    moved[lo[1] + 1] += 1.0
    assert not np.array_equal(interp_rows(np.concatenate(queries), np.concatenate(rows), lo,
                                          hi, np.concatenate(xs), moved), want,
                              equal_nan=True)


def test_per_row_and_spaced_rows_are_numpy_row_by_row():
    """Sums and running sums of rows stacked by length, and np.linspace of many rows,
    equal numpy on each row alone, bit for bit (lengths 1 to 20: pairwise sums from
    8 on)."""
    rng = np.random.default_rng(4)
    count = rng.integers(1, 21, 80)
    start = np.cumsum(count) - count
    values = rng.uniform(0, 1, int(count.sum())) ** 5 * 1e3
    blocks = [values[s:s + c] for s, c in zip(start, count)]
    for func in (np.sum, np.cumsum):
        got = [None] * len(count)
        for rows, res in per_row(values, start, count, func):
            for r, v in zip(rows, res):
                got[r] = v
        for g, b in zip(got, blocks):
            assert np.array_equal(g, func(b))
    stop = rng.uniform(0.1, 50, 40)
    num = rng.integers(2, 12, 40)
    want = np.concatenate([np.linspace(0.0, s, n) for s, n in zip(stop, num)])
    assert np.array_equal(spaced_rows(stop, num), want)
    assert np.array_equal(ranges(np.array([5, 0, 9]), np.array([2, 0, 3])),
                          [5, 6, 9, 10, 11])


def _chains(rng, count):
    pieces = [g1_chain(rng, int(rng.integers(1, 6))) for _ in range(count)]
    bank = Bank([p for c in pieces for p in c])
    sizes = [len(c) for c in pieces]
    offs = np.concatenate([[0], np.cumsum(sizes)]).astype(int)
    return pieces, make_chains(bank, [np.arange(a, b) for a, b in zip(offs[:-1], offs[1:])])


def test_chain_points_are_the_pieces_evaluated_alone():
    """A chain's point at T is piece floor(T) evaluated alone at T - floor(T)
    (morph.piece.evaluate, the same numbers), its first control point at an integer
    T and the chain's last point at its end."""
    rng = np.random.default_rng(5)
    pieces, chains = _chains(rng, 9)
    chain = np.repeat(np.arange(9), 6)
    k = chains.k[chain]
    t = rng.uniform(0, 1, len(chain)) * k
    t[::6] = np.floor(t[::6])                       # integers, 0 among them
    t[1::6] = k[1::6]                               # the ends
    got = chain_points(chains, chain, t)
    for c, tt, g in zip(chain, t, got):
        ps = pieces[c]
        if tt >= len(ps):
            want = pc.cartesian(ps[-1])[-1]
        elif tt == math.floor(tt):
            want = pc.cartesian(ps[int(tt)])[0]
        else:
            want = pc.evaluate(ps[int(math.floor(tt))], tt - math.floor(tt))[0]
        assert np.array_equal(g, want)


def test_arc_lengths_against_a_dense_polyline():
    """The tables' knots run j + c_i on piece j (c_i the running sums of the 16-point
    Gauss-Legendre weights, from 0) up to the chain's piece count, the lengths
    increase from 0 and end at the chain's length (a polyline of 20001 points a
    piece, to 1e-7 relative); at every knot the table is within 0.1 % of the chain's
    length of the polyline's length there; a table ten percent short fails the same
    check."""
    from morph.export.fit import _quadrature

    rng = np.random.default_rng(6)
    pieces, chains = _chains(rng, 7)
    t, s, lo, hi = arc_lengths(chains.bank, chains.off, chains.k)
    u = np.linspace(0, 1, 20001)
    c_i = np.concatenate([[0.0], np.cumsum(_quadrature().gw)[:-1]])
    for c, ps in enumerate(pieces):
        tc, sc = t[lo[c]:hi[c]], s[lo[c]:hi[c]]
        want_t = np.concatenate([j + c_i for j in range(len(ps))] + [[len(ps)]])
        assert np.array_equal(tc, want_t)
        assert sc[0] == 0.0 and np.all(np.diff(sc) > 0)
        steps = [np.hypot(*np.diff(rational(p)(u), axis=0).T) for p in ps]
        dense = sum(x.sum() for x in steps)
        assert sc[-1] == pytest.approx(dense, rel=1e-7)
        assert 0.9 * sc[-1] != pytest.approx(dense, rel=1e-7)
        # the polyline's length at every knot: its running sum at the knot's point
        run = np.concatenate([[0.0]] + [before + np.cumsum(x) for before, x in
                                        zip(np.cumsum([0.0] + [x.sum() for x in steps]), steps)])
        at = np.concatenate([j * 20000 + np.rint(c_i * 20000).astype(int)
                             for j in range(len(ps))] + [[len(ps) * 20000]])
        want = run[at]
        assert np.max(np.abs(sc - want)) <= 1e-3 * dense
        assert np.max(np.abs(0.9 * sc - want)) > 1e-3 * dense


def test_refined_segments_hold_tol_and_never_add_segments(monkeypatch):
    """Chains refined in one batch: each keeps at most the segment count it was handed
    over with (the greedy search's, or that of its equal cuts: the refinement only
    takes fewer), all certified within tol, joined end to start, within tol of their
    chain by exact closest distances; a cubic displaced by 2 tol fails that check."""
    from morph.export import search

    rng = np.random.default_rng(8)
    chains = [g1_chain(rng, int(rng.integers(2, 9))) for _ in range(16)]
    tol = 1e-4
    handed = {}                # chain: the count it was last handed over with
    add, split = search.Refine.add, search.Refine.split

    def spy_add(self, chain, seg_chain, *rest):
        handed.update(zip(chain.tolist(), np.bincount(seg_chain)[chain].tolist()))
        return add(self, chain, seg_chain, *rest)

    def spy_split(self, chain, count):
        handed.update(zip(chain.tolist(), count.tolist()))
        return split(self, chain, count)

    monkeypatch.setattr(search.Refine, "add", spy_add)
    monkeypatch.setattr(search.Refine, "split", spy_split)
    together = chains_segments(chains, tol)
    many = [c for c, segs in enumerate(together) if len(segs) >= 2]
    assert set(many) <= set(handed) and many
    assert all(len(together[c]) <= handed[c] for c in many)
    for pieces, segs in zip(chains, together):
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        assert all(a.t1 == b.t0 for a, b in zip(segs, segs[1:]))
        assert all(s.bound <= tol for s in segs)
        s = np.linspace(0, 1, 41)
        pts = np.vstack([bernstein(seg.cubic, s) for seg in segs])
        assert closest_distances(pts, pieces).max() <= tol * (1 + 1e-9)
    segs = max(together, key=len)
    pieces = chains[together.index(segs)]
    moved = segs[0].cubic.copy()
    d = bernstein(moved, [0.51])[0] - bernstein(moved, [0.49])[0]
    moved[1:3] += 2.0 * tol * np.array([-d[1], d[0]]) / math.hypot(*d) * 4.0 / 3.0
    assert closest_distances(bernstein(moved, s), pieces).max() > tol


def test_a_broken_fit_fails_the_certificate(monkeypatch):
    """The fitter's cubics displaced by 3 tol (inner control points along the chord's
    normal: the midpoint moves 3 tol) but reported with the fitter's own sampled
    distances and rays: not one of them certifies within tol (the certificate bounds
    the cubic it is given, from the fitter's feet, not the fitter's word), over ranges
    across a join (no same-parameter fallback there); the same requests unbroken
    certify."""
    from morph.export import search as search_mod

    rng = np.random.default_rng(12)
    pieces = [g1_chain(rng, 3) for _ in range(6)]
    bank = Bank([p for c in pieces for p in c])
    chains = make_chains(bank, [np.arange(3 * i, 3 * i + 3) for i in range(6)])
    tol = 0.02
    chain = np.repeat(np.arange(6), 3)
    t0 = np.tile([0.5, 0.75, 1.25], 6)
    t1 = t0 + 1.0
    req = search_mod.Requests(chain, t0, t1, search_mod._chain_points(chains, chain, t0),
                              search_mod._chain_points(chains, chain, t1),
                              np.zeros(len(chain)))
    good = search_mod._fit_batch(chains, req, tol)
    assert np.all(good.kind == search_mod.FITTED) and np.all(good.bound <= tol)
    real = search_mod.moment_cubics

    def broken(*args):
        cubic, dist, fitted, rays = real(*args)
        chord = cubic[:, 3] - cubic[:, 0]
        normal = np.stack([-chord[:, 1], chord[:, 0]], 1) / np.hypot(*chord.T)[:, None]
        cubic = cubic.copy()
        cubic[:, 1:3] += (3.0 * tol * 4.0 / 3.0) * normal[:, None]
        return cubic, dist, fitted, rays

    monkeypatch.setattr(search_mod, "moment_cubics", broken)
    bad = search_mod._fit_batch(chains, req, tol)
    assert np.all(bad.kind == search_mod.FITTED)
    assert np.all(bad.bound > tol) and not np.any(bad.cert & (bad.bound <= tol))

"""The greedy search as one array state machine (morph/export/greedy.py) and the
certificate's halves, against independent computations.

Oracles: the error model written out scalar by scalar from its documentation;
exact closest distances to the rational pieces (roots of the closest-point
polynomial, tests/test_export.py); plain Bernstein sums of the certificate's panels.
Every distance check is shown to fail on a curve displaced by twice the tolerance.
"""

import math

import numpy as np
import pytest

from morph import piece as pc
from morph.errors import ToleranceNotMetError
from morph.export import certify as certify_mod
from morph.export import greedy
from morph.export import search
from morph.export.search import chain_segments, chains_segments
from tests.test_export import (bernstein, closest_distances, rational, reparam_values,
                                sampled_panel_error)


def _model(t0, w, bound, last, good, bad, top, tol):
    """The next end of the documented model, one chain at a time (None: stop)."""
    p = greedy.ERROR_POWER
    if (last is not None and abs(last[0] - w) > greedy.SAME_WIDTH * w and last[1] > 0
            and bound > 0 and math.isfinite(bound) and math.isfinite(last[1])):
        p = min(greedy.P_MAX, max(greedy.P_MIN, math.log(bound / last[1]) / math.log(w / last[0])))
    if not math.isfinite(bound):
        ratio = greedy.SHRINK
    else:
        ratio = (greedy.AIM * tol / bound) ** (1.0 / p) if bound > 0 else greedy.STEP_MAX
    target = min(top, t0 + w * min(greedy.STEP_MAX, max(greedy.STEP_MIN, ratio)))
    lo = good if good is not None else t0
    hi = bad if bad is not None else top
    if bad is not None and not lo < target < hi:
        target = 0.5 * (lo + hi)
    if good is not None and (target <= lo or (bad is not None
                                              and hi - lo <= greedy.BRACKET_REL * (lo - t0))):
        return None
    return target


def test_next_tries_is_the_model_for_every_row():
    """One array call gives, row by row, the end the scalar model gives: random
    widths, bounds (zero, infinite, above and below tol), previous fits and
    brackets, present or not."""
    rng = np.random.default_rng(3)
    n, tol = 4000, 1e-3
    t0 = rng.uniform(0, 3, n)
    top = t0 + rng.uniform(0.1, 4, n)
    w = rng.uniform(1e-3, 1.0, n) * (top - t0)
    bound = tol * np.exp(rng.uniform(-6, 3, n))
    bound[rng.random(n) < 0.05] = np.inf
    bound[rng.random(n) < 0.05] = 0.0
    last_w = np.where(rng.random(n) < 0.5, np.nan, w * rng.uniform(0.3, 2, n))
    last_w[rng.random(n) < 0.05] = w[rng.random(n) < 0.05].mean()
    last_b = np.where(np.isnan(last_w), np.nan, tol * np.exp(rng.uniform(-6, 3, n)))
    good = np.where(rng.random(n) < 0.5, np.nan, t0 + rng.uniform(0.2, 1, n) * w)
    bad = np.where(rng.random(n) < 0.5, np.nan, t0 + rng.uniform(0.5, 1.5, n) * (top - t0))
    got = greedy.next_tries(t0, w, bound, last_w, last_b, good, bad, top, tol)
    stops = 0
    for i in range(n):
        last = None if np.isnan(last_w[i]) else (last_w[i], last_b[i])
        want = _model(t0[i], w[i], bound[i], last, None if np.isnan(good[i]) else good[i],
                      None if np.isnan(bad[i]) else bad[i], top[i], tol)
        if want is None:
            stops += 1
            assert np.isnan(got[i]), i
        else:
            assert got[i] == pytest.approx(want, rel=1e-12, abs=1e-12), i
    assert 0 < stops < n


def g1_chain(rng, count):
    """Circular arcs of random radii joined tangent-continuously, some degree-elevated
    (exactly): one smooth chain of rational pieces of two degrees."""
    pieces, p, ang = [], np.array([0.0, 0.0]), rng.uniform(0, 6)
    for r in rng.uniform(0.3, 3.0, count):
        c = p - r * np.array([math.cos(ang), math.sin(ang)])
        sweep = rng.uniform(0.3, 1.2)
        arc = pc.ellipse_arc(tuple(c), r, r, 0.0, ang, sweep)[0]
        pieces.append(pc.elevate(arc) if rng.random() < 0.4 else arc)
        ang += sweep
        p = c + r * np.array([math.cos(ang), math.sin(ang)])
    return pieces


def _hausdorff(cubics, pieces):
    """Two-sided distance (exact closest points, on samples) between the cubics and
    the chain's pieces."""
    s = np.linspace(0, 1, 41)
    pts = np.vstack([bernstein(c, s) for c in cubics])
    back = np.vstack([rational(p)(s) for p in pieces])
    return max(closest_distances(pts, pieces).max(), closest_distances(back, cubics).max())


@pytest.mark.parametrize("tol", [1e-3, 1e-6])
def test_batched_search_is_the_chain_by_chain_search(tol):
    """Twelve chains searched in one batch (the state machine advancing all of them
    each round) give, chain by chain, as many segments as the chain searched alone
    (at tol 1e-3 the same ends to 1e-9; at 1e-6 the rounding of batched array calls
    can flip a decision taken at a bound within rounding of tol, and the ends move:
    the search did so before it was an array machine too), each run within tol of
    its chain by
    exact closest distances, joined end to start; one cubic displaced by 2 tol breaks
    the same check."""
    rng = np.random.default_rng(7)
    chains = [g1_chain(rng, int(rng.integers(1, 9))) for _ in range(12)]
    together = chains_segments(chains, tol)
    for pieces, segs in zip(chains, together):
        alone = chain_segments(pieces, tol)
        assert len(segs) == len(alone)
        if tol >= 1e-3:
            assert np.allclose([s.t1 for s in segs], [s.t1 for s in alone], rtol=0, atol=1e-9)
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        for a, b in zip(segs, segs[1:]):
            assert a.t1 == b.t0 and np.array_equal(a.cubic[-1], b.cubic[0])
        cubics = [s.cubic for s in segs]
        assert all(s.bound <= tol for s in segs)
        assert _hausdorff(cubics, pieces) <= tol * (1 + 1e-9)
    pieces, segs = max(zip(chains, together), key=lambda ps: len(ps[1]))
    moved = [s.cubic.copy() for s in segs]
    mid = bernstein(moved[0], [0.5])[0]
    d = bernstein(moved[0], [0.51])[0] - bernstein(moved[0], [0.49])[0]
    normal = np.array([-d[1], d[0]]) / math.hypot(*d)
    moved[0][1:3] += 2.0 * tol * normal * 4.0 / 3.0
    assert _hausdorff(moved, pieces) > tol
    assert np.hypot(*(bernstein(moved[0], [0.5])[0] - mid)) == pytest.approx(2.0 * tol,
                                                                             rel=1e-6)


def test_the_panels_of_every_segment_hold_their_bound():
    """Every segment's panels (phi mapping the cubic onto the chain) sampled densely:
    |R(phi(s)) - C(s)| by plain Bernstein sums stays within the segment's bound; the
    cubic shifted by 2 tol does not."""
    rng = np.random.default_rng(11)
    tol = 1e-4
    chains = [g1_chain(rng, 5) for _ in range(3)]
    for pieces, segs in zip(chains, chains_segments(chains, tol)):
        for seg in segs:
            worst, moved = sampled_panel_error(pieces, seg, [2 * tol, 0])
            assert worst <= seg.bound * (1 + 1e-9) + 1e-13 and seg.bound <= tol
            assert moved > tol


def test_no_certified_interval_names_the_piece():
    """A tolerance no cubic reaches on intervals down to the minimal width: the state
    machine halves the shortest failed interval and raises ToleranceNotMetError with
    the chain's piece and the bound it achieved."""
    pieces = g1_chain(np.random.default_rng(2), 3)
    with pytest.raises(ToleranceNotMetError) as err:
        chain_segments(pieces, 1e-13, max_depth=3)
    assert err.value.achieved > 1e-13
    assert any(np.array_equal(err.value.piece, p) for p in pieces)


#: A brushed Noto Sans outline's piece (degree 6, rational: a TrueType quadratic
#: convolved with the brush's ellipse arc) and the cubic the search fitted to it at
#: tol 0.1875: no single reparametrisation certifies it, its halves do.
BRUSH_PIECE = np.array([
    [5.7113928840548813e+07, 1.6020476167605162e+07, 1.6044787223522595e+05],
    [1.0940121356516337e+08, 2.7617660605728626e+07, 2.7659570376966015e+05],
    [1.8228714979209006e+08, 4.5487918907599449e+07, 4.3612614937951043e+05],
    [2.7100796766450572e+08, 6.8231527681564093e+07, 6.3177992203612637e+05],
    [3.7703770058309150e+08, 9.5731545201224327e+07, 8.6912315412476030e+05],
    [5.0423965222984791e+08, 1.2855446936085796e+08, 1.1575699120801932e+06],
    [6.5645163239676571e+08, 1.6757174543801641e+08, 1.5052848387700128e+06]])
BRUSH_CUBIC = np.array([[355.9656357225882, 99.84848003542365],
                        [414.654087750752, 99.84848003542237],
                        [435.7217560498777, 111.11993715517261],
                        [436.0979500286209, 111.32228341244797]])


def test_halves_certified_from_the_parents_feet():
    """A pair whose certificate needs halving (a brushed outline's piece): the halves,
    their Newton searches started from the parent's feet (nothing sampled again),
    certify; the bound holds on dense samples of the halves' panels (R by plain
    Bernstein sums), and the cubic displaced by 2 tol does not certify."""
    tol = 0.1875
    groups = [(np.array([0]), BRUSH_PIECE[None])]
    res = certify_mod.certify_batch(groups, BRUSH_CUBIC[None], tol)
    assert res.bound[0] <= tol and res.half[0] >= 0
    worst = 0.0
    for s0, s1, phi in res.panels(0):
        s = np.linspace(s0, s1, 1025)
        u = reparam_values(phi, (s - s0) / (s1 - s0))
        err = np.hypot(*(rational(BRUSH_PIECE)(u) - bernstein(BRUSH_CUBIC, s)).T).max()
        worst = max(worst, err)
    assert worst <= res.bound[0] * (1 + 1e-9)
    # the certified cubic is within tol of the piece by exact closest distances too
    pts = bernstein(BRUSH_CUBIC, np.linspace(0, 1, 201))
    assert closest_distances(pts, [BRUSH_PIECE]).max() <= res.bound[0] * (1 + 1e-9)
    moved = BRUSH_CUBIC + [0.0, 2 * tol]
    assert certify_mod.certify_batch(groups, moved[None], tol).bound[0] > tol


def _rounds(monkeypatch):
    """Count the rounds of the search (calls of its batch fit)."""
    calls = [0]
    fit = search._fit_batch

    def counted(*args):
        calls[0] += 1
        return fit(*args)

    monkeypatch.setattr(search, "_fit_batch", counted)
    return calls


def test_search_from_both_ends_joins_exactly(monkeypatch):
    """Chains of 6 to 16 pieces searched from both ends at once take fewer rounds than
    searched from the start alone, and no more segments in all (at most one more on a
    chain: both stop short of their reach, as the greedy search does); the segments
    cover [0, K] end to start exactly, each certified within tol and within tol of
    its chain by exact closest distances (a cubic displaced by 2 tol is not)."""
    rng = np.random.default_rng(5)
    tol = 1e-3
    chains = [g1_chain(rng, int(rng.integers(6, 17))) for _ in range(10)]
    calls = _rounds(monkeypatch)
    both = chains_segments(chains, tol)
    rounds_both, calls[0] = calls[0], 0
    monkeypatch.setattr(search, "BOTH_WAYS", math.inf)
    one = chains_segments(chains, tol)
    assert rounds_both < calls[0]
    assert sum(map(len, both)) <= sum(map(len, one))
    for pieces, segs, alone in zip(chains, both, one):
        assert len(segs) <= len(alone) + 1
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        for a, b in zip(segs, segs[1:]):
            assert a.t1 == b.t0 and np.array_equal(a.cubic[-1], b.cubic[0])
        assert all(s.bound <= tol for s in segs)
        assert _hausdorff([s.cubic for s in segs], pieces) <= tol * (1 + 1e-9)
    pieces, segs = chains[0], both[0]
    moved = [s.cubic.copy() for s in segs]
    d = bernstein(moved[-1], [0.51])[0] - bernstein(moved[-1], [0.49])[0]
    moved[-1][1:3] += 2.0 * tol * np.array([-d[1], d[0]]) / math.hypot(*d) * 4.0 / 3.0
    assert _hausdorff(moved, pieces) > tol


def test_a_join_that_does_not_certify_searches_the_gap_again(monkeypatch):
    """Where the join of the two searches does not certify (forced here: every join
    made to need a refit of the path's first segment, every refit reported failed),
    the path keeps its segments from the failed one's end to the chain's end and the
    gap before them is searched again: the chain's segments run from 0 to its end,
    joined end to start, each within tol of the chain by exact closest distances; the
    last segment is the two-way search's (kept, not searched again)."""
    rng = np.random.default_rng(9)
    tol = 1e-3
    chains = [g1_chain(rng, 10) for _ in range(3)]
    both = chains_segments(chains, tol)
    path = search._Join._path
    update = search._Join.update

    def overlapping(self, c, segs, f):
        path(self, c, segs, f)
        self._ask(c, 0, 0, 0.0, self.paths[c][0][1])       # a refit for every join
        self.paths[c][0] = None

    def failing(self, fits, offset, round_no):
        j = offset + np.arange(len(self.requests()[0]))
        fits.cert = fits.cert.copy()
        fits.cert[j] = False
        return update(self, fits, offset, round_no)

    monkeypatch.setattr(search._Join, "_path", overlapping)
    monkeypatch.setattr(search._Join, "update", failing)
    again = chains_segments(chains, tol)
    for pieces, segs, two in zip(chains, again, both):
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        for a, b in zip(segs, segs[1:]):
            assert a.t1 == b.t0 and np.array_equal(a.cubic[-1], b.cubic[0])
        assert all(s.bound <= tol for s in segs)
        assert _hausdorff([s.cubic for s in segs], pieces) <= tol * (1 + 1e-9)
        assert (segs[-1].t0, segs[-1].t1) == (two[-1].t0, two[-1].t1)
        assert np.array_equal(segs[-1].cubic, two[-1].cubic)


def test_a_round_of_chords_shorter_than_tol_is_fitted():
    """A round whose every range is shorter than tol (the gap two searches of a chain
    leave between them can be) gets straight cubics, certified within tol and within
    tol of the range by exact closest distances; moved by 2 tol they are not."""
    from morph.export.bank import Bank
    from morph.export.fit import make_chains

    tol = 0.1
    arc = pc.ellipse_arc((0.0, 0.0), 1.0, 1.0, 0.0, 0.0, 1.0)[0]
    chains = make_chains(Bank([arc]), [np.array([0])])
    t0, t1 = np.array([0.40015583]), np.array([0.45])
    pts = search._chain_points(chains, np.zeros(2, int), np.concatenate([t0, t1]))
    assert np.hypot(*(pts[1] - pts[0])) < tol
    req = search.Requests(np.zeros(1, int), t0, t1, pts[:1], pts[1:], np.zeros(1))
    out = search._fit_batch(chains, req, tol)
    assert out.cert[0] and out.bound[0] <= tol
    assert np.allclose(out.cubic[0][[0, -1]], pts)
    sub = pc.subsegment(arc, 0.40015583, 0.45)
    s = np.linspace(0, 1, 41)
    assert closest_distances(bernstein(out.cubic[0], s), [sub]).max() <= tol
    moved = out.cubic[0] + np.array([0.0, 2.0 * tol])
    assert closest_distances(bernstein(moved, s), [sub]).max() > tol

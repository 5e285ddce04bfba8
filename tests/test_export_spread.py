"""Several tries a round for a segment that takes many (morph/export/greedy.py,
``Greedy._spread`` and ``Greedy._pick``), against a scalar oracle of what a round
may accept.

The greedy machine is driven by a made-up fitter whose bound grows as width^5 and
jumps at the joins of pieces (where a sum's curvature jumps): a try sampled below
PROVISIONAL tol is provisional (not certified), any other try is certified with
its bound.  Oracle: every segment the machine accepts is a try it asked, certified,
within tol, from its row's last end; the segments of a row run from 0 to its end.
A pick rule that takes the longest try whatever it is (a provisional or failing try
accepted) breaks the same check.
"""

import math

import numpy as np
import pytest

from morph.export import greedy
from morph.export import search
from morph.export.search import chains_segments
from tests.test_export import bernstein, closest_distances, rational
from tests.test_export_greedy import g1_chain


def _fitter(tol, rng, rows):
    """A made-up fit per row: bound c (width)^5, times 20 past a join inside the
    range (the jump the model does not see); provisional below PROVISIONAL tol."""
    scale = np.exp(rng.uniform(-2.0, 1.0, rows)) * tol

    def fit(row, t0, t1, need):
        w = t1 - t0
        jump = np.where(np.floor(t0 + 1e-9) + 1.0 < t1 - 1e-9, 20.0, 1.0)
        bound = scale[row] * w ** 5 * jump
        cert = ~(bound < need * tol)
        return bound, cert
    return fit


def _drive(tol, top, fit, pick=None):
    """Run the machine to its end; returns [(row, t0, t1, bound, certified)] of the
    accepted segments and the asked tries {(round, request): (row, t0, t1, bound,
    certified)}; ``pick`` replaces the machine's pick rule."""
    n = len(top)
    g = greedy.Greedy(top, np.zeros((n, 2)), tol, 2.0 ** -16, _no_fail, width=np.ones(n))
    if pick is not None:
        g._pick = pick.__get__(g)
    asked, accepted, rnd = {}, [], 0
    spread = False
    while g.active.any():
        rows, t0, t1, _, need = g.requests()
        spread |= len(rows) > len(np.unique(rows))
        bound, cert = fit(rows, t0, t1, need)
        at = np.stack([np.full(len(rows), rnd), np.arange(len(rows))], axis=1)
        for j in range(len(rows)):
            asked[rnd, j] = (int(rows[j]), float(t0[j]), float(t1[j]), float(bound[j]),
                             bool(cert[j]))
        out = g.update(rows, np.zeros((len(rows), 2)), (np.zeros((len(rows), 4, 2)), bound,
                                                        cert), at)
        for r, a, b, _, e, (i, j) in zip(out[0].tolist(), out[1].tolist(), out[2].tolist(),
                                         out[3], out[4].tolist(), out[5].tolist()):
            accepted.append((r, a, b, float(e), asked[i, j]))
        rnd += 1
        assert rnd < 500
    return accepted, spread


def _no_fail(*args):
    raise AssertionError("no interval certified: %r" % (args,))


def _check(accepted, top, tol):
    """The oracle: each accepted segment is a certified try within tol of its row,
    from the row's last end, the rows covered from 0 to their ends."""
    reach = {}
    for r, a, b, bound, (row, t0, t1, fit_bound, cert) in accepted:
        assert (row, t0, t1, fit_bound) == (r, a, b, bound)
        assert cert and fit_bound <= tol
        assert a == reach.get(r, 0.0)
        reach[r] = b
    assert all(reach[r] == top[r] for r in range(len(top)))


def test_spread_tries_accept_only_certified_segments():
    """Forty rows of 3 to 12 pieces: some rounds ask several tries of a row, and every
    accepted segment passes the oracle; with the pick replaced by 'the longest try'
    the oracle fails."""
    rng = np.random.default_rng(4)
    tol = 1e-3
    top = rng.integers(3, 13, 40).astype(float)
    fit = _fitter(tol, rng, len(top))
    accepted, spread = _drive(tol, top, fit)
    assert spread
    _check(accepted, top, tol)

    def longest(self, rows, end, fits, at):
        asked, t1 = self.asked
        last = np.ones(len(rows), bool)
        last[:-1] = rows[1:] != rows[:-1]            # the row's last: the longest here
        order = np.lexsort((t1, rows))
        pick = order[last]
        self.t1[rows[pick]] = t1[pick]
        certified = (fits[0][pick], fits[1][pick], np.ones(len(pick), bool))
        return rows[pick], end[pick], certified, at[pick]

    broken, _ = _drive(tol, top, fit, pick=longest)
    with pytest.raises(AssertionError):
        _check(broken, top, tol)


def test_spread_tries_cut_rounds_and_keep_the_cubics_within_tol(monkeypatch):
    """G1 chains of 10 to 30 pieces: the search with spread tries takes fewer rounds
    than one try a round and no more segments in all; its cubics are within tol of
    their chains by exact closest distances (a cubic displaced by 2 tol is not)."""
    rng = np.random.default_rng(12)
    tol = 1e-4
    chains = [g1_chain(rng, int(rng.integers(10, 31))) for _ in range(6)]
    calls = [0]
    real = search._fit_batch

    def counted(*args):
        calls[0] += 1
        return real(*args)

    monkeypatch.setattr(search, "_fit_batch", counted)
    spread = chains_segments(chains, tol)
    rounds_spread, calls[0] = calls[0], 0
    monkeypatch.setattr(greedy, "SPREAD_FROM", math.inf)
    single = chains_segments(chains, tol)
    assert rounds_spread < calls[0]
    assert sum(map(len, spread)) <= sum(map(len, single))
    s = np.linspace(0, 1, 41)
    for pieces, segs in zip(chains, spread):
        assert segs[0].t0 == 0.0 and segs[-1].t1 == len(pieces)
        assert all(a.t1 == b.t0 for a, b in zip(segs, segs[1:]))
        assert all(seg.bound <= tol for seg in segs)
        pts = np.vstack([bernstein(seg.cubic, s) for seg in segs])
        back = np.vstack([rational(p)(s) for p in pieces])
        assert closest_distances(pts, pieces).max() <= tol * (1 + 1e-9)
        assert closest_distances(back, [seg.cubic for seg in segs]).max() <= tol * (1 + 1e-9)
    pieces, segs = chains[0], spread[0]
    moved = segs[0].cubic.copy()
    d = bernstein(moved, [0.51])[0] - bernstein(moved, [0.49])[0]
    moved[1:3] += 2.0 * tol * np.array([-d[1], d[0]]) / math.hypot(*d) * 4.0 / 3.0
    assert closest_distances(bernstein(moved, s), pieces).max() > tol

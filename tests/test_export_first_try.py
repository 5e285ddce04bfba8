"""The segment search's first try (:func:`morph.export.search.first_widths`: the whole
chain where its pieces' bend says one cubic may do) and the refinement's memory of
failed whole-chain fits, counted on the fits the search asks; the cubics checked by
exact closest distances (tests/test_export.py), which a cubic displaced by 2 tol
fails."""

import math

import numpy as np

from morph import piece as pc
from morph.export import search
from morph.export.bank import Bank
from morph.export.search import chains_segments
from tests.test_export import bernstein, closest_distances, rational


def arc_chain(radius, sweep, count):
    """One circular arc of ``sweep`` radians cut into ``count`` equal rational pieces."""
    step = sweep / count
    return [pc.ellipse_arc((0.0, 0.0), radius, radius, 0.0, i * step, step)[0]
            for i in range(count)]


def counted_fits(monkeypatch):
    """Record the (chain, t0, t1) of every fit the search asks."""
    asked = []
    real = search._fit_batch

    def fits(chains, req, tol):
        asked.extend(zip(req.chain.tolist(), req.t0.tolist(), req.t1.tolist()))
        return real(chains, req, tol)

    monkeypatch.setattr(search, "_fit_batch", fits)
    return asked


def hausdorff(cubics, pieces):
    s = np.linspace(0, 1, 41)
    pts = np.vstack([bernstein(c, s) for c in cubics])
    back = np.vstack([rational(p)(s) for p in pieces])
    return max(closest_distances(pts, pieces).max(), closest_distances(back, cubics).max())


def test_an_easy_chain_is_one_fit(monkeypatch):
    """A quarter circle of radius 10 in 4 pieces at tol 0.05 (one cubic misses it by
    ~0.003): its bend guesses one cubic, so the first fit spans the whole chain and is
    the only one; with the first try two pieces wide (the guess switched off) the
    search needs more fits.  The cubic is within tol of the arc; displaced by 2 tol
    it is not."""
    tol = 0.05
    pieces = arc_chain(10.0, 0.5 * math.pi, 4)
    asked = counted_fits(monkeypatch)
    (segs,) = chains_segments([pieces], tol)
    assert asked == [(0, 0.0, 4.0)]
    assert len(segs) == 1 and segs[0].bound <= tol
    assert hausdorff([segs[0].cubic], pieces) <= tol
    moved = segs[0].cubic + np.array([0.0, 2.0 * tol])
    assert hausdorff([moved], pieces) > tol
    asked.clear()
    monkeypatch.setattr(search, "first_widths",
                        lambda chains, tol: np.minimum(chains.k, 2.0))
    chains_segments([pieces], tol)
    assert len(asked) > 1


def test_first_width_follows_the_bend():
    """The guessed width: the whole chain for a gentle arc, a share of it for an arc
    that turns a lot at a small tol, never more than FIRST_MAX pieces."""
    gentle = arc_chain(10.0, 0.5, 3)
    tight = arc_chain(10.0, 2.0 * math.pi, 6)
    bank = Bank(gentle + tight)
    chains = search.make_chains(bank, [np.arange(3), np.arange(3, 9)])
    width = search.first_widths(chains, 1e-4)
    assert width[0] == 3.0
    assert width[1] < 6.0 and width[1] <= search.FIRST_MAX


def test_refinement_never_refits_a_failed_whole_chain(monkeypatch):
    """Chains whose whole fit is tried first and fails (a half circle of radius 10 in
    2 to 5 pieces at tol 0.05, beyond any one cubic): no range is asked twice,
    the whole chain once; the chains still come out within tol.  Without the memory
    the refinement asks the whole chain again."""
    tol = 0.05
    chains = [arc_chain(10.0, math.pi, k) for k in (2, 3, 4, 5)]
    asked = counted_fits(monkeypatch)
    out = chains_segments(chains, tol)
    assert len(asked) == len(set(asked))
    assert all((c, 0.0, float(len(p))) in asked for c, p in enumerate(chains))
    for pieces, segs in zip(chains, out):
        assert len(segs) >= 2 and all(s.bound <= tol for s in segs)
        assert hausdorff([s.cubic for s in segs], pieces) <= tol * (1 + 1e-9)
    asked.clear()
    real = search.Refine

    def forgetful(chains, tol, whole_failed=None):
        return real(chains, tol)

    # the greedy search's segments refined without the memory (no equal cuts first:
    # a chain cut in two equal halves that fit is done without the refinement asking)
    monkeypatch.setattr(search, "Refine", forgetful)
    monkeypatch.setattr(search, "_split_wholes", lambda *args: None)
    chains_segments(chains, tol)
    assert len(asked) > len(set(asked))


def test_a_failed_whole_chain_is_cut_into_equal_arc_lengths(monkeypatch):
    """A half circle of radius 10 in 4 equal pieces at tol 0.05: its whole fit fails,
    and the next round fits the two halves of equal length (cut at T = 2) and
    keeps them: three fits in two rounds, both cubics within tol of the arc by exact
    closest distances; displaced by 2 tol one is not."""
    tol = 0.05
    pieces = arc_chain(10.0, math.pi, 4)
    asked = counted_fits(monkeypatch)
    (segs,) = chains_segments([pieces], tol)
    assert len(asked) == 3 and asked[0] == (0, 0.0, 4.0)
    (_, a0, cut), (_, b0, b1) = sorted(asked[1:])
    assert a0 == 0.0 and b1 == 4.0 and b0 == cut and abs(cut - 2.0) < 1e-9
    assert [(s.t0, s.t1) for s in segs] == [(0.0, cut), (cut, 4.0)]
    assert all(s.bound <= tol for s in segs)
    assert hausdorff([s.cubic for s in segs], pieces) <= tol * (1 + 1e-9)
    moved = segs[0].cubic + np.array([0.0, 2.0 * tol])
    assert hausdorff([moved, segs[1].cubic], pieces) > tol


def test_failed_cuts_give_the_chain_back_to_the_greedy_search(monkeypatch):
    """A full circle of radius 10 in 4 pieces at tol 1e-3, its first try the whole
    circle: the whole fit fails, so do the two equal halves (a half circle needs
    several cubics), and the greedy search goes on from the first half's fit as its
    try (no range asked twice, the next try shorter than the half); the cubics come
    out within tol of the circle."""
    tol = 1e-3
    pieces = arc_chain(10.0, 2.0 * math.pi, 4)
    monkeypatch.setattr(search, "first_widths", lambda chains, tol: chains.k.astype(float))
    asked = counted_fits(monkeypatch)
    (segs,) = chains_segments([pieces], tol)
    assert asked[0] == (0, 0.0, 4.0) and sorted(asked[1:3]) == [(0, 0.0, 2.0), (0, 2.0, 4.0)]
    assert len(asked) == len(set(asked))
    assert asked[3][1] == 0.0 and asked[3][2] < 2.0
    assert len(segs) >= 4 and all(s.bound <= tol for s in segs)
    assert segs[0].t0 == 0.0 and segs[-1].t1 == 4.0
    assert all(a.t1 == b.t0 for a, b in zip(segs, segs[1:]))
    assert hausdorff([s.cubic for s in segs], pieces) <= tol * (1 + 1e-9)

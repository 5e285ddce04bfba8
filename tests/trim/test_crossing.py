"""morph.trim.crossing.subdivided_crossings: the items of all pairs subdivided together
(one set of arrays a level, each item carrying its parts' control points) find the
candidates a plain pair-by-pair subdivision finds."""

import numpy as np
import pytest

from morph import piece as pc
from morph.trim.crossing import (JOINED, PAIRS, SELF, first_items, subdivide,
                                 subdivided_crossings)


def _cartesian(h):
    return h[:, :2] / h[:, 2:]


def _narrow(points):
    """The nonzero differences of later minus earlier control points (both parts)
    lie in a cone narrower than pi: the largest circular gap between their angles
    exceeds pi."""
    d = np.concatenate([p[j] - p[i] for p in points
                        for i in range(len(p)) for j in range(i + 1, len(p))]).reshape(-1, 2)
    norm = np.hypot(d[:, 0], d[:, 1])
    d = d[norm > 1e-12 * norm.max()]
    if not len(d):
        return False
    ang = np.sort(np.arctan2(d[:, 1], d[:, 0]))
    gaps = np.diff(np.concatenate([ang, [ang[0] + 2 * np.pi]]))
    return gaps.max() > np.pi * (1 + 1e-9)


def _children(a0, a1, b0, b1, kind, split_a):
    am, bm = 0.5 * (a0 + a1), 0.5 * (b0 + b1)
    if kind == PAIRS:
        return ([(a0, am, b0, b1, PAIRS), (am, a1, b0, b1, PAIRS)] if split_a
                else [(a0, a1, b0, bm, PAIRS), (a0, a1, bm, b1, PAIRS)])
    if kind == JOINED:     # a ends where b starts: the halves at the join stay joined
        return [(am, a1, b0, bm, JOINED), (a0, am, b0, bm, PAIRS),
                (am, a1, bm, b1, PAIRS), (a0, am, bm, b1, PAIRS)]
    return [(a0, am, a0, am, SELF), (am, a1, am, a1, SELF), (a0, am, am, a1, JOINED)]


def _one_pair(a, b, kind, res, max_depth=60):
    """The candidates (s, u) of one pair, item by item: each item's parts cut from
    the whole pieces (pc.subsegment), boxes compared, the cone test for joined and
    self items, the larger part halved."""
    level, out = [(0.0, 1.0, 0.0, 1.0, kind)], []
    for depth in range(max_depth):
        nxt = []
        for a0, a1, b0, b1, k in level:
            ca = _cartesian(pc.subsegment(a, a0, a1))
            cb = _cartesian(pc.subsegment(b, b0, b1))
            lo_a, hi_a, lo_b, hi_b = ca.min(0), ca.max(0), cb.min(0), cb.max(0)
            if np.any(lo_a > hi_b + 1e-9 * res) or np.any(lo_b > hi_a + 1e-9 * res):
                continue
            size_a, size_b = np.hypot(*(hi_a - lo_a)), np.hypot(*(hi_b - lo_b))
            small = size_a <= res and size_b <= res
            if k != PAIRS and (small or _narrow([ca, cb])):
                continue
            if k == PAIRS and (small or depth == max_depth - 1):
                out.append((0.5 * (a0 + a1), 0.5 * (b0 + b1)))
                continue
            nxt += _children(a0, a1, b0, b1, k, size_a >= size_b)
        level = nxt
    return sorted(out)


def _cases():
    """Pieces and (pair, kind): crossings at random, a near-tangent pair (two
    crossings close together), a loop of one cubic (SELF), a cubic whose successor
    starts at its end and crosses it (JOINED), a pair sharing an end without
    crossing, and a pair whose boxes overlap without crossing."""
    rng = np.random.default_rng(11)
    pieces, pairs = [], []
    for _ in range(8):
        p = rng.random((4, 2)) * 10.0
        q = rng.random((4, 2)) * 10.0
        pieces += [pc.cubic(*p), pc.cubic(*q)]
        pairs.append((len(pieces) - 2, len(pieces) - 1, PAIRS))
    arc = pc.cubic((0, 0), (3, 2), (7, 2), (10, 0))
    pieces += [arc, pc.cubic((0, 1.45), (3, 1.45 - 0.02), (7, 1.45 + 0.02), (10, 1.45))]
    pairs.append((len(pieces) - 2, len(pieces) - 1, PAIRS))              # near-tangent
    pieces.append(pc.cubic((0, 0), (12, 6), (-2, 6), (10, 0)))
    pairs.append((len(pieces) - 1, len(pieces) - 1, SELF))               # a loop
    pieces += [pc.cubic((0, 0), (6, 0), (8, 4), (4, 6)),
               pc.cubic((4, 6), (0, 4), (2, -3), (5, -4))]
    pairs.append((len(pieces) - 2, len(pieces) - 1, JOINED))             # joined, crossing
    pieces += [pc.cubic((0, 0), (1, 3), (3, 3), (4, 0)),
               pc.cubic((4, 0), (5, -3), (7, -3), (8, 0))]
    pairs.append((len(pieces) - 2, len(pieces) - 1, JOINED))             # joined, no crossing
    pieces += [pc.cubic((0, 0), (1, 4), (3, 4), (4, 0)),
               pc.cubic((0.5, 0), (1.5, 2), (2.5, 2), (3.5, 0))]
    pairs.append((len(pieces) - 2, len(pieces) - 1, PAIRS))              # nested, apart
    return pieces, np.array([p[:2] for p in pairs]), np.array([p[2] for p in pairs])


def _same(got, want):
    return len(got) == len(want) and all(g == w for g, w in zip(got, want))


def test_batched_subdivision_finds_what_pair_by_pair_finds():
    """All pairs subdivided together give, pair by pair, the candidates of a plain
    per-pair subdivision, to the bit (the parameters are dyadic): transversal,
    near-tangent, self and joined crossings, and none where there is none.  A
    candidate moved by one item's width no longer matches."""
    pieces, pairs, kinds = _cases()
    res = 1e-3
    org, s, u, gave_up = subdivided_crossings(pieces, pairs, kinds, res)
    assert not len(gave_up)
    counts = []
    for k, ((i, j), kind) in enumerate(zip(pairs, kinds)):
        got = sorted(zip(s[org == k].tolist(), u[org == k].tolist()))
        want = _one_pair(pieces[i], pieces[j], kind, res)
        assert _same(got, want), k
        counts.append(len(want))
    assert sum(c > 0 for c in counts[:8]) >= 3          # random pairs that cross
    assert counts[8] >= 2 and counts[9] >= 1 and counts[10] >= 1  # near-tangent, loop, joined
    assert counts[11] == 0 and counts[12] == 0
    # the comparison sees one crossing parameter moved by the width of its item
    k = 8
    got = sorted(zip(s[org == k].tolist(), u[org == k].tolist()))
    want = _one_pair(pieces[pairs[k, 0]], pieces[pairs[k, 1]], kinds[k], res)
    width = 2.0 ** -np.ceil(np.log2(10.0 / res))
    moved = [(got[0][0] + width, got[0][1])] + got[1:]
    assert _same(got, want) and not _same(moved, want)



def test_parked_items_resumed_give_the_candidates_of_one_run():
    """crossing.subdivide parks a pair's items at its first level with candidates;
    the parked items joining a second call at their levels give, pair by pair, the
    rest of the candidates of one uninterrupted run, at the same levels and in the
    same order, to the bit (untangle resumes a loop whose first candidates Newton
    rejects).  The first call gives each pair candidates of one level only."""
    from morph.polyline import unique

    rng = np.random.default_rng(7)   # cubics crossing where one runs slowly: two levels
    pieces = []
    for _ in range(30):
        a = pc.cubic(*rng.uniform(-10, 10, (4, 2)))
        pts = rng.uniform(-10, 10, (4, 2))
        pts[1] = pts[0] + 0.05 * (pts[1] - pts[0])
        pieces += [a, pc.cubic(*pts)]
    pairs = np.arange(60).reshape(30, 2)
    kinds = np.full(30, PAIRS)
    res, n = 1e-3, len(pairs)
    whole = subdivide(first_items(pieces, pairs, kinds), n, res)
    first = subdivide(first_items(pieces, pairs, kinds), n, res,
                      park=lambda k, s, u, depth: unique(k))
    empty = first_items(pieces, pairs, kinds).take(np.zeros(0, np.int64))
    rest = subdivide(empty, n, res, joining=first[5])
    resumed = 0
    for k in range(n):
        want = [(s, u, d) for o, s, u, d in zip(*(whole[i].tolist() for i in (0, 1, 2, 4)))
                if o == k]
        got = [[(s, u, d) for o, s, u, d in zip(*(part[i].tolist() for i in (0, 1, 2, 4)))
                if o == k] for part in (first, rest)]
        assert got[0] + got[1] == want, k
        assert len({d for _, _, d in got[0]}) <= 1, k
        resumed += bool(got[1])
    assert resumed >= 1 and len(whole[0]) > len(first[0])


def _first_crossings_all_at_once(loops, eps):
    """untangle._first_crossings written plainly: every candidate of the whole
    subdivision refined by Newton in one call, then each loop's first crossing in
    candidate order (not the shared end of consecutive pieces, nor a piece meeting
    itself at one parameter)."""
    from morph.polyline import unique
    from morph.trim.crossing import uncertain_pairs
    from morph.trim.lift import newton_crossings
    from morph.trim.untangle import _hulls_apart, _oriented

    pieces = pc.Pieces.of([p for loop in loops for p in loop])
    sizes = np.array([len(loop) for loop in loops])
    owner = np.repeat(np.arange(len(loops)), sizes)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    suspects = uncertain_pairs(loops, pieces)
    suspects = suspects[~_hulls_apart(pieces, suspects)]
    pairs, kinds = _oriented(suspects, owner, first, sizes)
    k, ta, tb, crowded = subdivided_crossings(pieces, pairs, kinds, 1e-3 * eps)
    assert not len(crowded)
    used = unique(pairs)
    stacked = pc.stack(pieces.take(used))
    pa, pb = pairs[k, 0], pairs[k, 1]
    ia, ib = np.searchsorted(used, pa), np.searchsorted(used, pb)
    guess = pc.jet_many(stacked, ia, ta)[0]
    s, w, ok = newton_crossings(stacked, ia, ta, ib, tb, guess, 2.0 * eps, 1e-6 * eps)
    hits = {}
    for n in np.flatnonzero(ok):
        gi, gj, si, wj = pa[n], pb[n], s[n], w[n]
        if gi > gj or (gi == gj and si > wj):
            gi, gj, si, wj = gj, gi, wj, si
        li = int(owner[gi])
        i, j = gi - first[li], gj - first[li]
        if li in hits or (j == i + 1 and si >= 1 - 1e-9 and wj <= 1e-9) or \
           (i == 0 and j == sizes[li] - 1 and si <= 1e-9 and wj >= 1 - 1e-9) or \
           (i == j and abs(si - wj) <= 1e-9):
            continue
        hits[li] = (i, si, j, wj, pc.jet_many(stacked, ia[n:n + 1], s[n:n + 1])[0][0])
    return hits


@pytest.mark.parametrize("seed, eps, passes", [(5, 1e-3, 1), (14, 0.1, 3), (26, 0.1, 3)])
def test_first_crossings_level_by_level_are_those_of_all_candidates_at_once(
        seed, eps, passes, monkeypatch):
    """untangle._first_crossings ends a loop's subdivision at its first level with
    candidates, refines them, and resumes the loops none of them is a crossing of:
    the crossing it picks for every loop is the one refining all candidates at once
    picks, to the bit (random cubic loops with curls and crossings, several in one
    call; ``passes`` subdivision passes, the later ones resumed)."""
    import morph.trim.untangle as ut

    rng = np.random.default_rng(seed)
    loops = []
    for _ in range(24):
        n = int(rng.integers(2, 7))
        pts = rng.uniform(-10, 10, (n, 2)) + 40.0 * rng.integers(0, 5, 2)
        loops.append([pc.cubic(pts[k], *rng.uniform(-12, 12, (2, 2)) + pts[k],
                               pts[(k + 1) % n]) for k in range(n)])
    calls = []
    monkeypatch.setattr(ut, "subdivide", lambda *a, **k: calls.append(1) or subdivide(*a, **k))
    got, want = ut._first_crossings(loops, eps), _first_crossings_all_at_once(loops, eps)
    assert len(calls) == passes
    assert len(want) >= 10 and sorted(got) == sorted(want)
    for li, (i, s, j, u, x) in want.items():
        gi, gs, gj, gu, gx = got[li]
        assert (gi, gs, gj, gu) == (i, s, j, u) and np.array_equal(gx, x), li


@pytest.mark.parametrize("m, longest", [(1, 1), (2, 3), (37, 5), (37, 38), (300, 64), (300, 1000)])
def test_range_spans_from_the_tables_are_those_of_each_range(m, longest):
    """crossing._range_span from crossing._span_tables: max(hi[a..b]) - min(lo[a..b])
    of every range up to ``longest`` entries, as each range's own slice gives it
    (the same bits: min and max are exact)."""
    from morph.trim.crossing import _range_span, _span_tables

    rng = np.random.default_rng(m + longest)
    lo = rng.normal(size=m)
    hi = lo + rng.random(m)
    a = rng.integers(0, m, 400)
    b = np.minimum(a + rng.integers(0, min(longest, m), 400), m - 1)
    got = _range_span(_span_tables(lo, hi, longest), a, b)
    want = np.array([hi[i:j + 1].max() - lo[i:j + 1].min() for i, j in zip(a, b)])
    assert np.array_equal(got, want)
    # a displaced window is another range's span: the comparison can fail
    assert not np.array_equal(_range_span(_span_tables(lo, hi, longest), a, np.maximum(b - 1, a)),
                              want) or m <= 2

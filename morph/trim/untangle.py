"""Lobes cut out of lifted loops where their exact pieces cross.

The topology is decided on polylines within eps of the pieces; where two exact
pieces cross twice within that distance (a small swallowtail of the convolution
curve, two near-tangent pieces), the lifted loop can keep a tiny lobe: a twist or
a curl.  Such crossings are found on polylines far finer than eps, refined by
Newton on the exact pieces, and the loop is split there into the lobe and the
rest.  Under the fill rule of the sums (winding > 0) a lobe of the opposite
orientation (a twist) or nested in the rest (a curl) bounds nothing and goes; a
lobe beside the rest with the same orientation (two parts touching at a point) is
kept as a loop of its own.  Zero-width spikes (a piece folding back onto its
neighbour) are removed first.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

import itertools

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from .. import polyline as pl
from ..polyline import (flatten_segments, pair_rows, ray_crossings, segment_crossings,
                        segment_pairs, unique, winding_number)
from ..quadrature import gauss_legendre
from .crossing import (JOINED, PAIRS, SELF, _upper, first_items, subdivide,
                       uncertain_pairs)
from .lift import _jet_rows, newton_crossings


def untangle(loops, eps, max_rounds=64, hole_test=None, pieces=None):
    """Loops with their self-crossings resolved (see the module docstring).

    eps: the polylines' bound used to find crossings (absolute); hole_test: as for
    :func:`morph.trim.boundary`, decides a lobe that would be a hole of the rest
    (None: winding numbers decide).  Each round splits every loop that still
    crosses itself at one crossing (so a loop gets up to ``max_rounds`` splits
    however many other loops there are), and where that crossing is a curl (a
    piece crossing itself), at the round's other curls of the loop that go
    whatever the order of the cuts (:func:`_cut_curls`); loops found free of
    crossings are not searched again.  ``pieces``: the loops' pieces one loop after another as a
    :class:`morph.piece.Pieces` where the caller has them
    (:func:`.lift.lift_rings`): the first round searches them as they are."""
    out = list(map(list, loops))
    idx = list(range(len(out)))   # the loops searched in a round: all, then those split
    for round_ in range(max_rounds):
        if not idx:
            break
        # the active loops' pieces stacked and their tangent cones taken once for
        # the fold test and the crossing search; where folds were cut, the cut
        # loops' again, put after the others (the search is loop by loop).  Per
        # loop, only C-level passes (map, comprehensions without calls): a chunk's
        # first round holds every loop of its glyphs
        sel = [out[k] for k in idx]
        sizes = list(map(len, sel))
        if pieces is None or len(idx) != len(out):
            pieces = pc.Pieces.of([p for loop in sel for p in loop])
        cones = pc.tangent_cones(pieces)
        if not round_:   # later rounds' loops had their folds cut as they were split off
            cut = _cut_folds(out, list(itertools.compress(
                idx, _may_fold(sel, cones, sizes).tolist())), eps)
            if cut:
                pieces, cones, idx = _recut(pieces, cones, idx, sizes, out, cut)
        found = {}
        local = _first_crossings([out[k] for k in idx], eps, pieces, cones, found)
        hits = {idx[a]: h for a, h in local.items()}
        curls = [found[a] if a in found else () for a in local] if found else None
        split = dict(zip(hits, _split_off_many([out[k] for k in hits], list(hits.values()),
                                               eps, hole_test, curls)))
        out, idx = _replaced(out, split)
        # a curl cut off leaves a spike: the parts' folds go before the next round
        # takes their cones, the parts with folds cut after the others (as :func:`_recut`)
        cut = set(_cut_folds(out, idx, eps) if idx and round_ + 1 < max_rounds else ())
        idx = [k for k in idx if k not in cut] + [k for k in idx if k in cut]
        pieces = None
    return out


def _cut_folds(out, ks, eps):
    """The loops ``ks`` of ``out`` with their folds removed (:func:`remove_folds`,
    width 2 eps), in place; returns those changed, in the order of ``ks``."""
    if not ks:
        return []
    loops, changed = _remove_folds([out[k] for k in ks], 2.0 * eps)
    cut = [ks[g] for g in sorted(changed)]
    for g in changed:
        out[ks[g]] = loops[g]
    return cut


def _replaced(loops, split):
    """(loops with each loop k of ``split`` replaced by its parts split[k], the
    indices of those parts): the loops searched next round.  The parts' indices
    by arrays; per loop split, list slices only (no call)."""
    ks = sorted(split)
    out, prev = [], 0
    for k in ks:
        out += loops[prev:k]
        out += split[k]
        prev = k + 1
    out += loops[prev:]
    n = _sizes([split[k] for k in ks])
    # the parts of the i-th loop split start past the parts before it, less the i
    # loops they replace
    at = np.array(ks, np.int64) + (n.cumsum() - n) - np.arange(len(ks))
    return out, (at.repeat(n) + np.arange(int(n.sum())) - (n.cumsum() - n).repeat(n)).tolist()


def _sizes(loops):
    """The lengths of ``loops`` as an int64 array, in one C-level pass."""
    return np.fromiter(map(len, loops), np.int64, len(loops))


def _recut(pieces, cones, idx, sizes, out, cut):
    """(pieces, cones, loop order) of the loops ``idx`` (their pieces stacked in
    ``pieces``, ``sizes`` pieces each, with tangent ``cones``) after the loops
    ``cut`` got new pieces (in ``out``): the other loops' pieces and cones as they
    were, then the cut loops', gathered and measured alone."""
    cut_set = set(cut)
    kept = np.array([k not in cut_set for k in idx])
    rows = kept.repeat(sizes).ravel().nonzero()[0]
    new = [p for k in cut for p in out[k]]
    new_cones = pc.tangent_cones(new)
    cones = tuple(np.concatenate([c[rows], n]) for c, n in zip(cones, new_cones))
    order = [k for k in idx if k not in cut_set] + list(cut)
    return pieces.take(rows).then(new), cones, order


def merge_lenses(loops, outer, eps, near=None, max_rounds=64):
    """The loops with every two outer loops that cross each other twice replaced by
    their union; ``outer``: which loops are outer (not holes); ``near``: the index
    pairs (i < j) that may cross (None: all pairs).

    The integer union decides which parts touch on a grid; two sums that overlap by
    less than a grid step (two marks a nib's width apart) can come out as two rings,
    and their exact pieces then cross in a thin lens (winding 2 inside it).  Their
    union is the outside arc of each between the two crossings (found on polylines
    within eps / 10, refined by Newton on the exact pieces; the outside arc is the
    one whose middle the other loop does not wind around).  Only outer loops in a
    ``near`` pair whose control boxes overlap are searched; pairs crossing any
    other number of times are left as they are.  A round merges the first such
    pair (by their places in the list, the merged loop put last); the crossings of
    every pair a round searches are found together (:func:`_pair_crossings`) and
    kept for the later rounds, which search only the pairs with a merged loop."""
    out = [list(loop) for loop in loops]
    outer = np.array(outer, bool).reshape(-1)
    if near is not None:
        near = np.array(sorted(near), np.int64).reshape(-1, 2)
        if not len(near):
            return out
    where = np.arange(len(out))   # the place of each given loop's loop in ``out``
    uid = np.arange(len(out))     # a loop's identity (a merged loop gets a new one)
    known = {}                    # (uid, uid) -> (crossings, whether exactly two)
    for _ in range(max_rounds):
        pairs = _lens_candidates(out, outer, where, near)
        keys = list(zip(uid[pairs[:, 0]].tolist(), uid[pairs[:, 1]].tolist()))
        new = [n for n, key in enumerate(keys) if key not in known]
        if new:
            known.update(zip([keys[n] for n in new], _pair_crossings(out, pairs[new], eps)))
        twice = [n for n, key in enumerate(keys) if known[key][1]]
        if not twice:
            break
        (a, b), (ca, cb) = pairs[twice[0]].tolist(), known[keys[twice[0]]][0]
        merged = _union_arcs(out[a], out[b], ca, cb, eps)
        if merged is None:
            break
        keep = np.ones(len(out), bool)
        keep[[a, b]] = False
        at = np.full(len(out), int(keep.sum()))   # a and b go to the merged loop, last
        at[keep] = np.arange(len(at) - 2)
        out = [out[k] for k in keep.ravel().nonzero()[0].tolist()] + [merged]
        outer, uid = np.append(outer[keep], True), np.append(uid[keep], uid.max() + 1)
        where = at[where]
    return out


def _lens_candidates(loops, outer, where, near):
    """The pairs (a, b), a < b, in order, of outer non-empty ``loops`` whose control
    boxes overlap and, where ``near`` (pairs of the given loops) is not None, that
    hold a near pair (``where``: the place of each given loop's loop)."""
    ok = outer & (_sizes(loops) > 0)
    if near is None:
        k = ok.ravel().nonzero()[0]
        i, j = np.triu_indices(len(k), 1)
        pairs = pair_rows(k[i], k[j])
    else:
        pairs = np.sort(where[near], axis=1)
        pairs = pairs[(pairs[:, 0] != pairs[:, 1]) & ok[pairs[:, 0]] & ok[pairs[:, 1]]]
        keys = unique(pairs[:, 0] * len(loops) + pairs[:, 1])
        pairs = pair_rows(keys // len(loops), keys % len(loops))
    if not len(pairs):
        return pairs
    used = unique(pairs)
    sel = [loops[k] for k in used.tolist()]
    sizes = _sizes(sel)
    pb = pc.bboxes([p for loop in sel for p in loop])
    starts = sizes.cumsum() - sizes
    lo, hi = np.minimum.reduceat(pb[:, :2], starts), np.maximum.reduceat(pb[:, 2:], starts)
    i, j = np.searchsorted(used, pairs[:, 0]), np.searchsorted(used, pairs[:, 1])
    meet = np.logical_and.reduce((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)
    return pairs[meet]


def _pair_crossings(loops, pairs, eps):
    """[(crossings, whether exactly two)] of each pair (a, b) of ``loops``: the
    crossings of a's pieces with b's, ([(piece, s)] on a, [(piece, u)] on b) in
    order along a, or None where Newton does not confirm one.  Candidates: the
    crossings of the two loops' polylines within eps / 10, one per point
    (:func:`_first_apart`), refined by Newton on the exact pieces.  All pairs at
    once: each loop's pieces flattened once, the segments' pairs, crossings and
    Newton of all together (the pieces of a pair at their highest degree)."""
    used = unique(pairs)
    sel = [loops[k] for k in used.tolist()]
    sizes = _sizes(sel)
    flat = [p for loop in sel for p in loop]
    first = sizes.cumsum() - sizes
    owner = np.arange(len(sel)).repeat(sizes)        # each piece's loop, in ``used``
    pa_loop, pb_loop = np.searchsorted(used, pairs[:, 0]), np.searchsorted(used, pairs[:, 1])
    p0, p1, ids, t0, t1 = flatten_segments(flat, eps / 10.0)
    seg = segment_pairs(p0, p1, ids, False)          # (i < j): a's before b's
    li, lj = owner[ids[seg[:, 0]]], owner[ids[seg[:, 1]]]
    code = pa_loop * len(sel) + pb_loop               # the pairs, ascending (a < b)
    g = np.minimum(np.searchsorted(code, li * len(sel) + lj), len(code) - 1)
    mine = code[g] == li * len(sel) + lj
    seg, g = seg[mine], g[mine]
    order = g.argsort(kind="stable")                 # by pair, each in its own order
    seg, g = seg[order], g[order]
    k, u, v = segment_crossings(p0, p1, seg)
    a, b, g = seg[k, 0], seg[k, 1], g[k]
    ta, tb = t0[a] + u * (t1[a] - t0[a]), t0[b] + v * (t1[b] - t0[b])
    guess = p0[a] + u[:, None] * (p1[a] - p0[a])
    keep = _first_apart(guess, g, eps / 10.0)
    pa, pb, ta, tb, guess, g = ids[a][keep], ids[b][keep], ta[keep], tb[keep], guess[keep], g[keep]
    s, w, ok = _newton_by_degree(flat, pa, ta, pb, tb, guess, g, owner, (pa_loop, pb_loop), eps)
    bad = np.bincount(g[~ok], minlength=len(pairs)) > 0
    count = np.bincount(g, minlength=len(pairs))
    order = np.lexsort((s, pa, g))
    g, a_side = g[order], list(zip((pa - first[owner[pa]])[order].tolist(), s[order].tolist()))
    b_side = list(zip((pb - first[owner[pb]])[order].tolist(), w[order].tolist()))
    at = np.searchsorted(g, np.arange(len(pairs) + 1)).tolist()
    return [(None, False) if x else ((a_side[i:j], b_side[i:j]), n == 2)
            for x, n, i, j in zip(bad.tolist(), count.tolist(), at[:-1], at[1:])]


def _first_apart(points, group, d):
    """Which points to keep, one per place: a point of a group goes where an earlier
    point of its group that is kept lies within ``d`` (segment ends shared by two
    segments report a crossing twice).  All groups at once: the pairs within
    ``d``, then the kept points settled from each group's first on, a step per
    point of the longest chain of near points."""
    n = len(points)
    cnt = np.bincount(group, minlength=int(group.max(initial=-1)) + 1)
    start = cnt.cumsum() - cnt
    # each point with every earlier point of its group (group rows are contiguous)
    later = np.arange(n).repeat(np.arange(n) - start[group])
    earlier = start[group].repeat(np.arange(n) - start[group]) + pl._ranks(
        np.arange(n) - start[group])
    close = np.hypot(*(points[earlier] - points[later]).T) <= d
    later, earlier = later[close], earlier[close]
    keep = np.ones(n, bool)
    while True:
        gone = np.zeros(n, bool)
        np.logical_or.at(gone, later, keep[earlier])
        if np.array_equal(~gone, keep):
            return keep
        keep = ~gone


def _newton_by_degree(flat, pa, ta, pb, tb, guess, g, owner, sides, eps):
    """:func:`.lift.newton_crossings` of crossings of pieces pa, pb of ``flat`` (row
    groups ``g``: the pairs of loops (sides[0][g], sides[1][g]), ``owner`` each
    piece's loop), each pair's pieces stacked at the highest degree of the pair's
    two loops, as :func:`_loop_crossings` stacks them: one call per degree."""
    s, w, ok = ta.copy(), tb.copy(), np.zeros(len(pa), bool)
    if not len(pa):
        return s, w, ok
    deg = _sizes(flat) - 1
    top = np.zeros(int(owner.max()) + 1, np.int64)
    np.maximum.at(top, owner, deg)
    pair_deg = np.maximum(top[sides[0]], top[sides[1]])[g]
    for d in unique(pair_deg).tolist():
        r = (pair_deg == d).ravel().nonzero()[0]
        used = unique(np.concatenate([pa[r], pb[r]]))
        # a piece of the pair's degree among them, so that the stack is at d
        mine = (deg == d).ravel().nonzero()[0][:1]
        used = unique(np.concatenate([used, mine]))
        stacked = pc.stack([flat[x] for x in used.tolist()])
        # each polyline is within eps / 10 of its piece: a crossing at angle alpha
        # moves by up to 2 (eps / 10) / sin(alpha / 2) (newton_crossings' allowance)
        s[r], w[r], ok[r] = newton_crossings(stacked, np.searchsorted(used, pa[r]), ta[r],
                                             np.searchsorted(used, pb[r]), tb[r], guess[r],
                                             eps, 1e-6 * eps, shallow=2.0 * eps / 10.0)
    return s, w, ok


def _arc(loop, start, end):
    """The pieces of a loop from (piece, t) ``start`` to (piece, t) ``end``, forwards
    (cyclically)."""
    (i, s), (j, u) = start, end
    if i == j and s < u:
        return [pc.subsegment(loop[i], s, u)]
    middle = [loop[k % len(loop)] for k in range(i + 1, j + (len(loop) if j <= i else 0))]
    return [pc.subsegment(loop[i], s, 1.0)] + middle + [pc.subsegment(loop[j], 0.0, u)]


def _union_arcs(la, lb, ca, cb, eps):
    """The union of two outer loops crossing at two points (ca on la, cb on lb, in
    la's order): the arc of each outside the other, joined at the crossings; None
    when each loop's two arcs are both inside or both outside the other."""
    arcs_a = [_arc(la, ca[0], ca[1]), _arc(la, ca[1], ca[0])]
    # on lb, the arc from the crossing la meets first to the other, and back
    arcs_b = [_arc(lb, cb[0], cb[1]), _arc(lb, cb[1], cb[0])]
    poly_a, poly_b = pl.flatten_loop(la, eps / 10.0), pl.flatten_loop(lb, eps / 10.0)

    def outside(arc, poly):
        mid = arc[len(arc) // 2]
        return winding_number(pc.evaluate(mid, np.array([0.5])), [poly])[0] == 0

    out_a = [outside(arc, poly_b) for arc in arcs_a]
    out_b = [outside(arc, poly_a) for arc in arcs_b]
    if out_a[0] == out_a[1] or out_b[0] == out_b[1]:
        return None
    # la's outside arc ends at crossing 1 (or 0); lb's outside arc must start there
    a_arc = arcs_a[0] if out_a[0] else arcs_a[1]
    ends_at = 1 if out_a[0] else 0
    b_arc = arcs_b[1] if ends_at == 1 else arcs_b[0]
    if not out_b[1 if ends_at == 1 else 0]:
        return None
    return _snap(a_arc + b_arc, 1e-6 * eps)


def _split_off_many(loops, hits, eps, hole_test, curls=None):
    """The parts of each loop kept after splitting it at its crossing (i, s, j, u, x)
    of ``hits``: the larger part, and the smaller (the lobe) where
    :func:`_keep_lobes` says so.  All loops at once: the cuts, the snapping, the
    areas and the lobes' tests of all together.  ``curls``: per loop, more curls
    [(piece, s, u)] to cut off first (:func:`_cut_curls`), or None."""
    if curls is not None:
        loops, hits = _cut_curls(loops, hits, curls, eps)
    lobes, rests = _split_many(loops, hits, 1e-6 * eps)
    areas = _loop_areas(lobes + rests)
    a_lobe, a_rest = areas[:len(loops)], areas[len(loops):]
    # the lobe is the smaller part, wherever the cut is
    swap = ((_sizes(lobes) > 0) & (_sizes(rests) > 0)
            & (np.abs(a_lobe) > np.abs(a_rest))).reshape(-1)
    w = swap.tolist()
    lobes, rests = ([r if x else lb for lb, r, x in zip(lobes, rests, w)],
                    [lb if x else r for lb, r, x in zip(lobes, rests, w)])
    a_lobe, a_rest = np.where(swap, a_rest, a_lobe), np.where(swap, a_lobe, a_rest)
    keep = _keep_lobes(lobes, rests, a_lobe, a_rest, eps, hole_test)
    return [[part for part in ([r, lb] if k else [r]) if part]
            for lb, r, k in zip(lobes, rests, keep)]


def _cut_curls(loops, hits, curls, eps):
    """(loops, hits) with the curls [(piece, s, u)] of each loop (``curls``, one list
    per loop) cut off first where they go whatever the order of the cuts: the
    lobe i[s:u] of area at most eps^2 (:func:`_keep_lobes` drops it) and no larger
    than the rest of its loop (so the lobe is the part that goes).  The curl's piece
    becomes i[:s], i[u:] (:func:`_split_many` snaps their join with its own cut's);
    each loop's crossing of ``hits`` (on another piece) is renumbered past the
    pieces added before it."""
    rows = [(n, i, s, u) for n, cs in enumerate(curls) for i, s, u in cs]
    if not rows:
        return loops, hits
    n, i, s, u = (np.array(c) for c in zip(*rows))
    order = np.lexsort((i, n))    # by loop, then piece: cut from the last piece back
    n, i, s, u = n[order], i[order], s[order], u[order]
    src = [loops[a][b] for a, b in zip(n.tolist(), i.tolist())]
    lobe = pc.subsegments(src, np.arange(len(src)), s, u)
    a_lobe = _loop_areas([[p] for p in lobe])
    a_loop = _loop_areas([loops[k] for k in n.tolist()])   # per row: its loop's area
    small = np.abs(a_lobe) <= eps * eps
    rest = a_loop - np.bincount(n, weights=np.where(small, a_lobe, 0.0), minlength=len(loops))[n]
    go = (small & (np.abs(a_lobe) <= np.abs(rest))).nonzero()[0]
    if not len(go):
        return loops, hits
    cut = pc.subsegments([src[k] for k in go.tolist()] * 2, np.arange(2 * len(go)),
                         np.concatenate([np.zeros(len(go)), u[go]]),
                         np.concatenate([s[go], np.ones(len(go))]))
    loops, hits, m = list(loops), list(hits), len(go)
    rows = list(zip(range(m), n[go].tolist(), i[go].tolist()))
    for g, a, b in rows[::-1]:   # per curl cut, last first: list slices only (no call)
        loops[a] = loops[a][:b] + [cut[g], cut[m + g]] + loops[a][b + 1:]
        hi, hs, hj, hu, hx = hits[a]
        hits[a] = (hi + (hi > b), hs, hj + (hj > b), hu, hx)
    return loops, hits


def _first_crossings(loops, eps, pieces=None, cones=None, curls=None):
    """{loop: (piece i, s, piece j, u, point)}: one crossing of two pieces of each
    loop that has one, away from their shared ends (i < j, or i == j for a piece
    crossing itself), refined on the exact pieces.

    Only pairs that no monotone chain holds (:func:`.crossing.uncertain_pairs`) and
    whose control polygons' hulls are not apart (:func:`_hulls_apart`) are
    searched, by subdivision to 1e-3 eps (:func:`_subdivision_hits`), and on
    polylines within eps / 10 the pairs where subdivision would not end (pieces that
    nearly coincide) of the loops it found no crossing of.  A loop takes the first of
    its candidates in their order (level by level, then those of the polylines)
    that Newton confirms on the exact pieces.  ``pieces`` (a
    :class:`morph.piece.Pieces`) and ``cones`` (their tangent cones): the loops'
    pieces in order, when known.  ``curls``: a dict that gets, for each loop whose
    crossing is a curl (i == j), the other curls on other pieces that its batch
    of candidates holds, {loop: [(piece, s, u)]} (:func:`_batch_curls`)."""
    if pieces is None:
        pieces = pc.Pieces.of([p for loop in loops for p in loop])  # stacked once
    sizes = _sizes(loops)
    owner = np.arange(len(loops)).repeat(sizes)
    first = np.concatenate([[0], sizes.cumsum()[:-1]])
    suspects = uncertain_pairs(loops, pieces, cones)  # the other pairs cannot cross
    if len(suspects):
        suspects = suspects[~_hulls_apart(pieces, suspects)]
    if not len(suspects):
        return {}
    pairs, kinds = _oriented(suspects, owner, first, sizes)
    used = unique(pairs)
    stacked = pc.stack(pieces.take(used))
    loc = (owner, first, sizes)
    hits, crowded = _subdivision_hits(pieces, (stacked, used), pairs, kinds, eps, loc, curls)
    crowded = crowded[~pl.member(owner[pairs[crowded, 0]], _keys(hits))]
    near = _polyline_crossings(pieces, np.sort(pairs[crowded], axis=1), eps / 10.0)
    fresh = (~pl.member(owner[near[0]], _keys(hits))).ravel().nonzero()[0]
    if len(fresh):
        pa, pb, ta, tb, guess = (x[fresh] for x in near)
        hits.update(_refined_hits((stacked, used), (pa, ta), (pb, tb), guess,
                                  np.zeros(len(fresh), np.int64), eps, loc, curls))
    return hits


def _subdivision_hits(pieces, rows, pairs, kinds, eps, loc, curls):
    """({loop: crossing} of :func:`_first_crossings` from the subdivision's
    candidates, the pairs it gave up on (indices, sorted)).  A pass subdivides
    (:func:`.crossing.subdivide`) and parks a loop's items at the first level that
    gives it candidates; Newton then refines the pass's candidates, all levels at
    once (:func:`_refined_hits`); the parked items of the loops left without a
    crossing go on in the next pass.  A loop's candidates come from its own pairs'
    items only (in their order): each loop gets the crossing that refining every
    level's candidates as they come gives.  ``rows``: (stacked, used), the pieces
    ``used`` stacked; ``loc``: (owner, first, sizes) of the loops' pieces."""
    owner = loc[0]
    of_pair = owner[pairs[:, 0]]
    it = first_items(pieces, pairs, kinds)
    hits, gave_up, joining = {}, [], ()

    def park(k, s, u, depth):    # the pairs of the loops with candidates
        return pl.member(of_pair, unique(of_pair[k])).ravel().nonzero()[0]

    while True:
        k, s, u, crowded, level, parked = subdivide(it, len(pairs), 1e-3 * eps, joining, park)
        gave_up.append(crowded)
        if not len(k):
            break
        loop = of_pair[k]
        got = _refined_hits(rows, (pairs[k, 0], s), (pairs[k, 1], u), None, level, eps, loc,
                            curls)
        hits.update(got)
        failed = unique(loop[~pl.member(loop, _keys(got))])   # candidates, no crossing
        joining = [(d, items.take(pl.member(of_pair[items.org], failed)))
                   for d, items in parked] if len(failed) else []
        joining = [(d, items) for d, items in joining if len(items.org)]
        if not joining:
            break
        it = it.take(np.zeros(0, np.int64))
    return hits, (unique(np.concatenate(gave_up)) if len(gave_up) > 1 else unique(gave_up[0]))


def _refined_hits(rows, a, b, guess, level, eps, loc, curls=None):
    """{loop: (piece i, s, piece j, u, point)} of :func:`_first_crossings` from its
    candidates in order: a = (piece, parameter) on one side, b on the other
    (pieces: ``rows`` = (stacked, used), the pieces ``used`` stacked), refined by
    Newton from ``guess`` (None: the point of a); ``level``: the subdivision level
    of each (ascending); ``loc``: (owner, first, sizes) of the loops' pieces.

    A loop's candidates of one level are a batch, its first FIRST_TRIES of the
    batch before its others: a loop takes its first crossing in the first of those
    parts that holds one.  Newton works row by row, so all levels' first parts are
    refined together, then the others of the levels before a loop's first
    crossing: the same crossings as refining part after part and stopping a loop
    at its first, in two Newton calls, with fewer rows where a loop has many
    candidates (legs that nearly coincide give hundreds).  ``curls``: see
    :func:`_first_crossings`, from the batch part of each loop's crossing."""
    (stacked, used), (pa, ta), (pb, tb), (owner, first, sizes) = rows, a, b, loc
    if not len(pa):
        return {}
    loop = owner[pa]
    ia, ib = np.searchsorted(used, pa), np.searchsorted(used, pb)
    # a batch part's key: twice the level, plus one for a loop's candidates past its
    # first FIRST_TRIES of the level
    key = 2 * level + (_ranks(loop * (int(level.max(initial=0)) + 1) + level) >= FIRST_TRIES)
    settled = np.full(len(sizes), 2 * int(level.max(initial=0)) + 2)   # past every key
    s, w, ok, done = ta.copy(), tb.copy(), np.zeros(len(pa), bool), np.zeros(len(pa), bool)
    for part in (0, 1):
        c = ((key % 2 == part) & (key < settled[loop])).ravel().nonzero()[0]
        if not len(c):
            continue
        x0 = pc.jet_many(stacked, ia[c], ta[c])[0] if guess is None else guess[c]
        s[c], w[c], ok[c] = newton_crossings(stacked, ia[c], ta[c], ib[c], tb[c], x0,
                                             2.0 * eps, 1e-6 * eps)
        done[c] = True
        valid = c[_valid_rows(pa[c], pb[c], s[c], w[c], ok[c], owner, first, sizes)[1]]
        np.minimum.at(settled, loop[valid], key[valid])
    c = (done & (key == settled[loop])).ravel().nonzero()[0]   # each loop's batch part
    got, valid, (gi, gj, si, wj) = _valid_rows(pa[c], pb[c], s[c], w[c], ok[c], owner, first,
                                                sizes)
    if curls is not None and len(got):
        curls.update(_batch_curls(got, valid, gi, gj, si, wj, owner, first))
    x = pc.jet_many(stacked, ia[c[got]], s[c[got]])[0]
    return _hits_of(gi[got], gj[got], si[got], wj[got], x, owner, first)


#: Crossing candidates of each loop that :func:`_first_crossings` refines first;
#: the loop's others only when none of those is a crossing.
FIRST_TRIES = 8


def _ranks(group):
    """Each entry's rank among the entries of its group, in order."""
    order = np.argsort(group, kind="stable")
    g = group[order]
    start = np.r_[True, g[1:] != g[:-1]].ravel().nonzero()[0]
    rank = np.empty(len(group), np.int64)
    rank[order] = np.arange(len(g)) - start.repeat(np.diff(np.r_[start, len(g)]))
    return rank


def _first_valid(pa, pb, s, w, ok, owner, first, sizes):
    """Indices of the first refined candidate of each loop that is a crossing: ok,
    and not the shared end of consecutive pieces nor a piece meeting itself at one
    parameter."""
    return _valid_rows(pa, pb, s, w, ok, owner, first, sizes)[0]


def _batch_curls(got, valid, gi, gj, si, wj, owner, first):
    """{loop: [(piece, s, u)]}: for each loop whose first crossing (``got``, rows of
    the batch) is a curl (a piece crossing itself, gi == gj), the batch's other
    crossings (``valid`` rows, in candidate order) that are curls on other pieces
    of the loop, the first of each piece; rows ordered as :func:`_valid_rows`
    gives them (i <= j, s <= u)."""
    curl_loops = unique(owner[gi[got][gi[got] == gj[got]]])
    rows = valid[(gi[valid] == gj[valid]) & pl.member(owner[gi[valid]], curl_loops)
                 & ~pl.member(gi[valid], unique(gi[got]))]
    if not len(rows):
        return {}
    order = gi[rows].argsort(kind="stable")      # the first row of each piece
    g = gi[rows][order]
    rows = np.sort(rows[order[np.concatenate(([True], g[1:] != g[:-1]))]])
    li = owner[gi[rows]]
    by = li.argsort(kind="stable")    # each loop's curls together, in row order
    rows, li = rows[by], li[by]
    curls = list(zip((gi[rows] - first[li]).tolist(), si[rows].tolist(), wj[rows].tolist()))
    at = np.append(np.r_[True, li[1:] != li[:-1]].ravel().nonzero()[0], len(li)).tolist()
    return {k: curls[a:b] for k, a, b in zip(li[at[:-1]].tolist(), at[:-1], at[1:])}


def _valid_rows(pa, pb, s, w, ok, owner, first, sizes):
    """(:func:`_first_valid`'s rows, every valid row in order, and the rows as
    (gi, gj, si, wj): the two pieces and parameters ordered i <= j, s <= u on one
    piece)."""
    swap = (pa > pb) | ((pa == pb) & (s > w))
    gi, gj = np.where(swap, pb, pa), np.where(swap, pa, pb)
    si, wj = np.where(swap, w, s), np.where(swap, s, w)
    li = owner[gi]
    i, j = gi - first[li], gj - first[li]
    end = (((j == i + 1) & (si >= 1 - 1e-9) & (wj <= 1e-9))
           | ((i == 0) & (j == sizes[li] - 1) & (si <= 1e-9) & (wj >= 1 - 1e-9))
           | ((i == j) & (np.abs(si - wj) <= 1e-9)))
    valid = (ok & ~end).ravel().nonzero()[0]
    order = valid[np.argsort(li[valid], kind="stable")]    # by loop, then candidate order
    got = order[np.concatenate(([True], li[order][1:] != li[order][:-1]))[:len(order)]]
    return got, valid, (gi, gj, si, wj)


def _keys(hits):
    """The loops of ``hits`` as a sorted integer array, for :func:`morph.polyline.member`
    (``np.isin`` with a list, empty or not, sorts it by ``np.unique``, which loads
    ``numpy.ma``: font workers must not)."""
    return np.array(sorted(hits), np.int64)


def _hits_of(gi, gj, si, wj, x, owner, first):
    """{loop: (piece i, s, piece j, u, point)} of crossings of pieces gi at si and gj
    at wj (indices in the stacked loops, i <= j, s <= u for i == j; ``x`` their
    points), one a loop: all at once, per crossing a tuple (no call)."""
    li = owner[gi]
    return dict(zip(li.tolist(), zip((gi - first[li]).tolist(), si.tolist(),
                                     (gj - first[li]).tolist(), wj.tolist(), x)))


def _hulls_apart(pieces, pairs):
    """Whether the convex hulls of the control points of each pair of pieces
    (``pieces`` a :class:`morph.piece.Pieces`, ``pairs`` (k, 2) indices) are
    apart: a piece with positive weights lies in that hull, so two such pieces
    cannot meet.  Separating axes: the normals of every line through two control
    points of either piece (the hulls' edges among them), a gap of more than 1e-9
    of the projections' size (rounding far below the crossings' 1e-6 eps).

    Most pairs that no monotone chain holds are the two sides of a stroke where it
    turns round its end: boxes overlap, hulls do not."""
    used = unique(pairs)
    inv = np.searchsorted(used, pairs)
    h = pc.stack(pc.Pieces.of(pieces).take(used))
    positive = np.all(h[..., 2] > 0.0, axis=1)
    x = h[..., :2] / np.where(positive[:, None, None], h[..., 2:], 1.0)
    i, j = _upper(x.shape[1])
    d = x[:, j] - x[:, i]
    axes = np.concatenate([d[inv[:, 0]], d[inv[:, 1]]], axis=1)  # normals (-dy, dx) of these
    xt = x.transpose(1, 0, 2)    # control point first: the extremes are taken across slabs
    pa, pb = (-axes[..., 1] * p[..., None, 0] + axes[..., 0] * p[..., None, 1]
              for p in (xt[:, inv[:, 0]], xt[:, inv[:, 1]]))  # (n+1, pairs, axes)
    size = np.abs(pa).max(axis=0) + np.abs(pb).max(axis=0)
    gap = np.maximum(pb.min(axis=0) - pa.max(axis=0), pa.min(axis=0) - pb.max(axis=0))
    apart = np.any(gap > 1e-9 * size, axis=1)
    return apart & positive[inv[:, 0]] & positive[inv[:, 1]]


def _oriented(pairs, owner, first, sizes):
    """Suspect pairs with their subdivision kinds: a piece with itself (SELF), a
    piece and the next one of its loop in that order (JOINED), others (PAIRS)."""
    i, j = pairs[:, 0].copy(), pairs[:, 1].copy()
    nxt = lambda k: first[owner[k]] + (k - first[owner[k]] + 1) % sizes[owner[k]]  # noqa: E731
    kinds = np.full(len(i), PAIRS)
    back = (nxt(j) == i) & (nxt(i) != j)
    i[back], j[back] = pairs[back, 1], pairs[back, 0]
    kinds[nxt(i) == j] = JOINED
    kinds[i == j] = SELF
    return np.stack([i, j], axis=1), kinds


def _polyline_crossings(pieces, suspects, flat):
    """Crossings of the suspect pairs' polylines within ``flat``: (piece a, piece b,
    t on a, u on b, point), away from shared polyline vertices."""
    pairs = np.zeros((0, 2), int)
    if len(suspects):
        used = unique(suspects)
        p0, p1, ids, t0, t1 = flatten_segments(pieces.take(used) if isinstance(
            pieces, pc.Pieces) else [pieces[k] for k in used], flat)
        ids = used[ids]
        pairs = segment_pairs(p0, p1, ids, True)
    if len(pairs):
        key = np.sort(ids[pairs], axis=1) @ np.array([len(pieces), 1])
        pairs = pairs[pl.member(key, np.sort(suspects @ np.array([len(pieces), 1])))]
    if not len(pairs):
        empty = np.zeros(0, int)
        return empty, empty, np.zeros(0), np.zeros(0), np.zeros((0, 2))
    k, u, v = segment_crossings(p0, p1, pairs)
    a, b = pairs[k, 0], pairs[k, 1]
    sel = ~(((u <= 1e-9) | (u >= 1 - 1e-9)) & ((v <= 1e-9) | (v >= 1 - 1e-9)))
    a, b, u, v = a[sel], b[sel], u[sel], v[sel]
    ta, tb = t0[a] + u * (t1[a] - t0[a]), t0[b] + v * (t1[b] - t0[b])
    return ids[a], ids[b], ta, tb, p0[a] + u[:, None] * (p1[a] - p0[a])


FOLD_COS = -0.99  # consecutive pieces meeting at a turn this close to pi fold back


def _may_fold(loops, cones=None, sizes=None):
    """Per loop: whether some join turns by nearly pi (see :func:`remove_folds`; all
    joins at once, with a margin over its test), a bool array; ``cones``: the
    :func:`morph.piece.tangent_cones` of the loops' pieces in order when known;
    ``sizes``: their lengths when known."""
    sizes = _sizes(loops) if sizes is None else np.asarray(sizes, np.int64)
    n = int(np.add.reduce(sizes))
    if not n:
        return np.zeros(len(loops), bool)
    start, _, _, end = cones if cones is not None else pc.tangent_cones(
        [p for loop in loops for p in loop])
    owner = np.arange(len(loops)).repeat(sizes)
    first = np.concatenate([[0], sizes.cumsum()[:-1]])
    nxt = first[owner] + (np.arange(n) - first[owner] + 1) % sizes[owner]
    fold = np.cos(start[nxt] - start - end) <= FOLD_COS + 1e-6
    return np.bincount(owner, weights=fold, minlength=len(loops)) > 0


def remove_folds(loop, width):
    """The loop without zero-width spikes, where a piece folds back onto its
    neighbour (turn of nearly pi at their join):

    - the shorter piece lies within ``width`` of the longer: it goes, and the
      longer is cut where the shorter one began (or ended);
    - else, the two legs of the spike coincide from the join (within COINCIDE
      ``width`` at equal arc lengths) for at least ``width`` of arc length (a hook
      at a piece's end that the next piece runs along, :func:`_zip_many`): both are cut
      where they part, a piece zipped whole goes.

    Such spikes enclose no area; the polygon engine keeps them because it preserves
    collinear vertices, and legs that coincide hide any crossing on them from the
    polylines and from subdivision (the crossing search gives such pairs up).

    Each pass finds every fold at once and cuts those that share no piece, from
    the last to the first (earlier indices stay valid; a fold at the wrap, piece -1
    to piece 0, is cut alone in its pass); a fold left as it is (legs neither close
    nor zipped) is not looked at again while its two pieces are unchanged
    (:func:`_snap` keeps a piece whose ends stay).  Passes repeat until no fold is
    left to cut.  :func:`remove_folds_many` of one loop."""
    return remove_folds_many([loop], width)[0]


def remove_folds_many(loops, width):
    """:func:`remove_folds` of every loop, each pass over all loops at once: the
    joins of all their pieces tested together (:func:`_fold_joins_many`), the
    cuts of all the folds found computed together (:func:`_fold_cuts`) and applied
    together (:func:`_cut_fold_rows`) as :func:`remove_folds` says (the cuts of one
    pass use the pieces as the pass found them: a fold whose second piece a later
    fold's cut changed is skipped, :func:`_taken_folds`)."""
    return _remove_folds(loops, width)[0]


def _remove_folds(loops, width):
    """(:func:`remove_folds_many` of the loops, the set of the indices of those it
    changed).  A pass's folds are rows of arrays over all loops (loop, join); a fold
    left as it is is remembered by its loop and the identities of its two pieces
    (kept alive with it, so that no other piece takes their ids)."""
    out = [list(loop) for loop in loops]
    changed_any = set()
    left, alive = set(), []   # (loop, id(a), id(b)) of folds left as they are, their pieces
    todo = (_sizes(out) >= 3).ravel().nonzero()[0]
    while len(todo):
        flat, starts, sizes, g, i = _fold_joins_many([out[k] for k in todo.tolist()])
        ia, ib = starts[g] + i, starts[g] + (i + 1) % sizes[g]
        ids = list(map(id, flat))
        keys = list(zip(todo[g].tolist(), [ids[x] for x in ia.tolist()],
                        [ids[x] for x in ib.tolist()]))
        fresh = np.array([key not in left for key in keys], bool).reshape(-1)
        # a fold at the wrap (piece -1 to piece 0) is cut alone in its pass: its cut
        # may delete piece 0 and move every index
        wrap = fresh & (i == sizes[g] - 1)
        row = (fresh & (~pl.member(g, unique(g[wrap])) | wrap)).ravel().nonzero()[0]
        if not len(row):
            break
        g, i, ia, ib = g[row], i[row], ia[row], ib[row]
        s, u, cut = _fold_cuts([flat[x] for x in ia.tolist()], [flat[x] for x in ib.tolist()],
                               width)
        taken, skipped = _taken_folds(g, i, cut)
        stay = (~cut & ~skipped).ravel().nonzero()[0]
        left.update([keys[r] for r in row[stay].tolist()])
        alive += [flat[x] for x in np.concatenate([ia[stay], ib[stay]]).tolist()]
        t = taken.ravel().nonzero()[0]
        changed = todo[unique(g[t])]
        flat, keep = _cut_fold_rows(flat, ia[t], ib[t], s[t], u[t])
        _store_loops(out, changed, flat, keep, starts, sizes, todo)
        # a cut at a piece's end leaves nothing
        for k, loop in zip(changed.tolist(), _snap_many([out[k] for k in changed.tolist()],
                                                        5e-7 * width)):
            out[k] = loop
        changed_any.update(changed.tolist())
        todo = changed[_sizes([out[k] for k in changed.tolist()]) >= 3]
    return out, changed_any


def _taken_folds(g, i, cut):
    """(taken, skipped) of a pass's folds (rows by loop ``g``, then join ``i``, with
    ``cut`` where a cut was found): from each loop's last fold back, a fold whose
    second piece the cut of the fold after it took is skipped, the others with a cut
    are taken.  Runs of folds at consecutive joins settle from their ends, one run
    position a step (runs are a few folds long)."""
    nxt = np.append((g[1:] == g[:-1]) & (i[1:] == i[:-1] + 1), False)
    succ = np.minimum(np.arange(1, len(g) + 1), len(g) - 1)
    taken = cut & ~nxt
    while True:
        again = cut & ~(nxt & taken[succ])
        if np.array_equal(again, taken):
            return taken, nxt & taken[succ]
        taken = again


def _cut_fold_rows(flat, ia, ib, s, u):
    """(pieces, keep) after cutting the folds (a = flat[ia], ending, b = flat[ib],
    starting, cut at s and u, no two sharing a piece): a cut at s and b at u, both
    joined at the mean of the two cut points; s = 0: a goes and b starts where a
    started; else u = 1: b goes and a ends where b ended.  All folds at once (the
    cuts in one :func:`morph.piece.subsegments`, the points in one product per
    degree): the pieces of ``flat`` with those replaced, and ``keep`` False at the
    pieces that go."""
    flat, keep = list(flat), np.ones(len(flat), bool)
    if not len(ia):
        return flat, keep
    a_goes, b_goes = s <= 0.0, (s > 0.0) & (u >= 1.0)
    on_a, on_b = (~a_goes).ravel().nonzero()[0], (~b_goes).ravel().nonzero()[0]
    src = [flat[x] for x in ia[on_a].tolist()] + [flat[x] for x in ib[on_b].tolist()]
    parts = pc.subsegments(src, np.arange(len(src)), np.concatenate([np.zeros(len(on_a)),
                                                                     u[on_b]]),
                           np.concatenate([s[on_a], np.ones(len(on_b))]), packed=True)
    starts, ends = pc.end_points(pc.Pieces.of([flat[x] for x in ia.tolist()]
                                              + [flat[x] for x in ib.tolist()]))
    a0, b1 = starts[:len(ia)], ends[len(ia):]
    both = (~a_goes & ~b_goes).ravel().nonzero()[0]
    x = b1.copy()             # where a piece goes, the other keeps the far end of both
    x[a_goes] = a0[a_goes]
    x[both] = 0.5 * (_points_at([flat[k] for k in ia[both].tolist()], s[both])
                     + _points_at([flat[k] for k in ib[both].tolist()], u[both]))
    p0 = np.concatenate([a0[on_a], x[on_b]])
    p1 = np.concatenate([x[on_a], b1[on_b]])
    rows = _with_ends_where(parts, p0, p1, np.ones(len(src), bool)).rows()
    for at, piece in zip(np.concatenate([ia[on_a], ib[on_b]]).tolist(), rows):
        flat[at] = piece
    keep[ia[a_goes]] = False
    keep[ib[b_goes]] = False
    return flat, keep


def _points_at(pieces, t):
    """:func:`morph.piece.evaluate` of each piece k at t[k], (k, 2): one product per
    degree (a row of the basis times the piece's control points, as there)."""
    out = np.empty((len(pieces), 2))
    for ks, h in pc.degree_groups(pieces):
        v = np.matmul(bz.basis(h.shape[1] - 1, t[ks])[:, None, :], h)[:, 0]
        out[ks] = v[:, :2] / v[:, 2:3]
    return out


def _store_loops(out, changed, flat, keep, starts, sizes, todo):
    """out[k] for each loop k of ``changed`` (among ``todo``, whose pieces ``flat`` are
    stacked from ``starts``, ``sizes`` each): its pieces that ``keep`` holds."""
    at = np.searchsorted(todo, changed)
    mine = np.zeros(len(flat), bool)
    mine[(starts[at].repeat(sizes[at])
          + np.arange(int(sizes[at].sum())) - (sizes[at].cumsum() - sizes[at]).repeat(
              sizes[at]))] = True
    rows = (mine & keep).ravel().nonzero()[0]
    n = np.bincount(np.searchsorted(starts[at], rows, "right") - 1, minlength=len(at))
    pieces = [flat[x] for x in rows.tolist()]
    bounds = np.append(n.cumsum() - n, len(rows)).tolist()
    for j, k in enumerate(changed.tolist()):
        out[k] = pieces[bounds[j]:bounds[j + 1]]


def _fold_joins_many(loops):
    """(pieces, starts, sizes, loop, join): the loops' pieces one loop after another
    (each loop's first at ``starts``, ``sizes`` each) and the joins (piece i, piece
    i + 1, cyclic) that turn by nearly pi (unit end tangents with dot product at
    most FOLD_COS), by loop then join; the joins of all loops at once."""
    sizes = _sizes(loops)
    flat = [p for loop in loops for p in loop]
    first, last = pc.end_tangents_many(flat)
    starts = sizes.cumsum() - sizes
    owner = np.arange(len(loops)).repeat(sizes)
    at = np.arange(len(owner)) - starts[owner]
    nxt = starts[owner] + (at + 1) % sizes[owner]
    fold = (np.einsum("ij,ij->i", last, first[nxt]) <= FOLD_COS).ravel().nonzero()[0]
    return flat, starts, sizes, owner[fold], at[fold]


def _fold_cuts(a_s, b_s, width):
    """Where to cut each fold (a of ``a_s`` ending, b of ``b_s`` starting), as
    (s, u, cut): a cut at s, b at u where ``cut`` (see :func:`remove_folds`; else the
    fold is left): the shorter leg within ``width`` of the longer at nine points
    goes, the longer cut at its point closest to the shorter's far end (the closest
    points of all folds found at once, :func:`_closest_many`); else where the legs
    part, if they are zipped (:func:`_zip_many`, :func:`_parting_many`)."""
    lengths = pc.length_bounds(a_s + b_s)
    la, lb = lengths[:len(a_s)], lengths[len(a_s):]
    a_short = la <= lb
    shorts = [a if s else b for a, b, s in zip(a_s, b_s, a_short)]
    longs = [b if s else a for a, b, s in zip(a_s, b_s, a_short)]
    pts = _evaluate_many(shorts, np.linspace(0.0, 1.0, 9))
    near, t_near = _closest_many(longs, pts)
    close = near.max(axis=1) <= width
    s = np.where(a_short, 0.0, t_near[:, -1])
    u = np.where(a_short, t_near[:, 0], 1.0)
    cut = close.copy()
    rest = (~close).ravel().nonzero()[0]
    if len(rest):
        ra, rb = [a_s[f] for f in rest.tolist()], [b_s[f] for f in rest.tolist()]
        zs, zu, window, zipped = _zip_many(ra, rb, COINCIDE * width, width)
        zs, zu = _parting_many(ra, rb, zs, zu, window, zipped)
        s[rest], u[rest], cut[rest] = zs, zu, zipped
    return s, u, cut


def _evaluate_many(pieces, t):
    """:func:`morph.piece.evaluate` of each piece at the parameters ``t``: (k, m, 2),
    all pieces at once (stacked at their highest degree, :func:`morph.piece.stack`)."""
    if not len(pieces):
        return np.zeros((0, len(t), 2))
    h = pc.stack(pieces)
    v = bz.basis(h.shape[1] - 1, t) @ h
    return v[..., :2] / v[..., 2:3]


def _closest_many(pieces, points, samples=257):
    """Distances from points (k, m, 2) to their pieces and the parameters of the
    closest points (k, m): the nearest of ``samples`` points of each piece, then
    Newton on the squared distance (:func:`_newton_nearest`), all pieces at once
    (stacked at their highest degree)."""
    k, m = points.shape[:2]
    if not k:
        return np.zeros((0, m)), np.zeros((0, m))
    t = np.linspace(0.0, 1.0, samples)
    h = pc.stack(pieces)
    curve = bz.basis(h.shape[1] - 1, t) @ h
    curve = curve[..., :2] / curve[..., 2:3]
    d2 = ((points[:, :, None, :] - curve[:, None, :, :]) ** 2).sum(axis=3)
    u = t[np.argmin(d2, axis=2)].ravel()
    d, u = _newton_nearest(h, np.arange(k).repeat(m), u, points.reshape(-1, 2))
    return d.reshape(k, m), u.reshape(k, m)


#: Legs of a fold closer than this share of remove_folds' width coincide (:func:`_zip_many`).
COINCIDE = 1e-3
#: Samples per piece of :func:`_zip_many`'s arc-length tables.
ZIP_SAMPLES = 257


def _parting_many(a_s, b_s, s, u, window, zipped):
    """The cut of each zipped fold (``zipped``, (s, u) and ``window`` from
    :func:`_zip_many`) placed where its legs part, if that is a turning point of
    ``a``: its point farthest along b's start direction among 4097 in the window
    (parameters of ``a``), taken when it lies inside the window (the sample before
    it, so that ``a`` does not turn back), with ``b`` cut at its point closest to
    it; else the zip's own cut (s, u), also where a piece goes whole.  All folds at
    once."""
    s, u = s.copy(), u.copy()
    rows = (zipped & (s > 0.0) & (u < 1.0)).ravel().nonzero()[0]
    if not len(rows):
        return s, u
    ra, rb = [a_s[f] for f in rows.tolist()], [b_s[f] for f in rows.tolist()]
    d = pc.end_tangents_many(rb)[0]
    t = np.linspace(window[rows, 0], window[rows, 1], 4097, axis=1)
    k = np.argmax(np.einsum("kqj,kj->kq", _evaluate_rows(ra, t), d), axis=1)
    inner = ((k > 0) & (k < t.shape[1] - 1)).ravel().nonzero()[0]
    if not len(inner):
        return s, u
    s_new = t[inner, k[inner] - 1]
    pts = _evaluate_rows([ra[i] for i in inner.tolist()], s_new[:, None])
    _, t_b = _closest_many([rb[i] for i in inner.tolist()], pts)
    s[rows[inner]], u[rows[inner]] = s_new, t_b[:, 0]
    return s, u


def _evaluate_rows(pieces, t):
    """Each piece k evaluated at its own parameters t[k] (k, m): (k, m, 2), all pieces
    at once (stacked at their highest degree)."""
    out = np.zeros(t.shape + (2,))
    if len(pieces):
        h = pc.stack(pieces)
        n = h.shape[1] - 1
        v = np.einsum("kqi,kij->kqj", bz.basis(n, t.ravel()).reshape(len(h), -1, n + 1), h)
        out[:] = v[..., :2] / v[..., 2:3]
    return out


def _interp_rows(x, xp, fp):
    """np.interp(x[k], xp[k], fp[k]) of every row k at once (xp ascending in each
    row, x (k, m) clamped to its row's range; fp (k, p) or (k, p, c), each column
    interpolated): one search of all rows' knots, each row shifted past the one
    before it."""
    k, p = xp.shape
    cols = fp.shape[2:]
    fp = np.broadcast_to(fp, xp.shape + cols).reshape(k * p, -1)
    x = np.clip(x, xp[:, :1], xp[:, -1:])
    lo = xp[:, :1]
    off = 2.0 * (float((xp[:, -1] - xp[:, 0]).max()) + 1.0) * np.arange(k)[:, None]
    j = np.searchsorted(((xp - lo) + off).ravel(), ((x - lo) + off).ravel(), "right") - 1
    base = (np.arange(k) * p).repeat(x.shape[1])
    j = np.clip(j, base, base + p - 2)
    x0, x1 = xp.ravel()[j], xp.ravel()[j + 1]
    with np.errstate(invalid="ignore", divide="ignore"):
        frac = np.where(x1 > x0, (x.ravel() - x0) / (x1 - x0), 1.0)[:, None]
    f0 = fp.take(j, axis=0)
    return (f0 + frac * (fp.take(j + 1, axis=0) - f0)).reshape(x.shape + cols)


def _zip_many(a_s, b_s, close, min_length):
    """(s, u, window, zipped) of each fold (a ending, b starting): where its legs
    part, the points at arc length L back from a's end and L on from b's start,
    for the largest L (at most the shorter piece's length) with the two within
    ``close`` at every arc length up to L (s = 0 or u = 1 when a piece is zipped
    whole), and the parameters of ``a`` within four comparison steps of arc length
    of s; ``zipped`` False where L < ``min_length``.  Arc lengths from ZIP_SAMPLES
    points per piece, compared at 4 ZIP_SAMPLES arc lengths; all folds at once."""
    t = np.linspace(0.0, 1.0, ZIP_SAMPLES)
    pa, pb = _evaluate_many(a_s, t[::-1]), _evaluate_many(b_s, t)  # from the join outwards
    la, lb = (np.concatenate([np.zeros((len(a_s), 1)), np.cumsum(np.hypot(
        *np.diff(q, axis=1).transpose(2, 0, 1)), axis=1)], axis=1) for q in (pa, pb))
    top = np.minimum(la[:, -1], lb[:, -1])
    ok = top >= min_length
    ell = np.linspace(0.0, np.where(ok, top, 1.0), 4 * ZIP_SAMPLES, axis=1)
    xa, xb = _interp_rows(ell, la, pa), _interp_rows(ell, lb, pb)
    apart = np.hypot(*(xa - xb).transpose(2, 0, 1)) > close
    any_apart = apart.any(axis=1)
    first = np.argmax(apart, axis=1)
    ok &= ~(any_apart & (first == 0))
    L = np.where(any_apart, ell[np.arange(len(a_s)), np.maximum(first - 1, 0)], top)
    ok &= L >= min_length
    step = 4.0 * (ell[:, 1] - ell[:, 0])
    # a's parameters at L and at the window's ends, b's at L
    on_a = _interp_rows(np.stack([L, L + step, np.maximum(L - step, 0.0)], axis=1), la,
                        np.broadcast_to(t[::-1], la.shape))
    on_b = _interp_rows(L[:, None], lb, np.broadcast_to(t, lb.shape))
    s = np.where(~any_apart & (la[:, -1] <= lb[:, -1]), 0.0, on_a[:, 0])
    u = np.where(~any_apart & (lb[:, -1] < la[:, -1]), 1.0, on_b[:, 0])
    return s, u, on_a[:, 1:], ok


def _newton_nearest(stacked, idx, u, points):
    """Distances from ``points`` to the pieces ``stacked[idx]`` and the parameters of
    the nearest points: up to 8 Newton steps on the squared distance from ``u`` (a
    dense sample's nearest), kept in [0, 1], all rows together until a step leaves
    every row where it is."""
    h = stacked.take(idx, axis=0)
    dh = (h.shape[1] - 1) * np.diff(h, axis=1)
    for _ in range(8):
        x, dx = _jet_rows(h, u, dh)
        r = x - points
        step = np.add.reduce(r * dx, axis=1) / np.maximum(np.add.reduce(dx * dx, axis=1),
                                                          1e-300)
        u2 = np.minimum(np.maximum(u - step, 0.0), 1.0)   # kept in [0, 1]
        if np.logical_and.reduce(u2 == u):
            break
        u = u2
    x, _ = _jet_rows(h, u, dh)
    return np.hypot(*(x - points).T), u


def _split_many(loops, hits, min_len):
    """(lobes, rests): each loop cut at its crossing (i, s, j, u, x) of ``hits`` (i <=
    j): the lobe i[s:] .. j[:u] (i[s:u] where i == j) and the rest .. i[:s],
    j[u:] .., snapped (:func:`_snap_many`).  The four cut pieces of every loop
    (i[s:1] or i[s:u], j[:u], i[:s], j[u:]) in one :func:`morph.piece.subsegments`."""
    if not loops:
        return [], []
    i, s, j, u = (np.array([h[n] for h in hits]) for n in range(4))
    same = i == j
    src = [p for loop, a, b in zip(loops, i.tolist(), j.tolist()) for p in
           (loop[a], loop[b], loop[a], loop[b])]
    t0 = np.stack([s, np.zeros_like(s), np.zeros_like(s), u], axis=1).ravel()
    t1 = np.stack([np.where(same, u, 1.0), u, s, np.ones_like(s)], axis=1).ravel()
    cut = pc.subsegments(src, np.arange(len(src)), t0, t1)
    rows = list(zip(loops, i.tolist(), j.tolist(), cut[0::4], cut[1::4], cut[2::4], cut[3::4]))
    lobes = [[c0] if a == b else [c0] + loop[a + 1:b] + [c1]
             for loop, a, b, c0, c1, _, _ in rows]
    rests = [loop[:a] + [c2, c3] + loop[b + 1:] for loop, a, b, _, _, c2, c3 in rows]
    snapped = _snap_many(lobes + rests, min_len)
    return snapped[:len(loops)], snapped[len(loops):]


def _snap(loop, min_len):
    """:func:`_snap_many` of one loop."""
    return _snap_many([loop], min_len)[0]


def _snap_many(loops, min_len):
    """Each loop with its pieces no longer than ``min_len`` dropped and every join
    snapped to the mean of its two ends (the cut point where the cut was made);
    again while snapping leaves a piece that short.  All loops at once: each pass
    measures and snaps the pieces of every loop still going together (a loop's
    pass is the same arithmetic as alone; a loop whose snapped pieces are all
    longer than ``min_len`` is done)."""
    out = [list(loop) for loop in loops]
    going = [k for k, loop in enumerate(out) if loop]
    while going:
        flat = [p for k in going for p in out[k]]
        sizes = _sizes([out[k] for k in going])
        keep = pc.length_bounds(flat) > min_len
        owner = np.arange(len(going)).repeat(sizes)[keep]
        idx = keep.ravel().nonzero()[0]
        per = np.bincount(owner, minlength=len(going))
        first = per.cumsum() - per
        at = np.arange(len(idx)) - first[owner]
        prev = first[owner] + (at - 1) % np.maximum(per[owner], 1)
        nxt = first[owner] + (at + 1) % np.maximum(per[owner], 1)
        kept = pc.Pieces.of([flat[i] for i in idx.tolist()])
        starts, ends = pc.end_points(kept)
        a = 0.5 * (starts + ends.take(prev, axis=0))
        b = 0.5 * (ends + starts.take(nxt, axis=0))
        moved = np.any(a != starts, axis=1) | np.any(b != ends, axis=1)
        snapped = _with_ends_where(kept, a, b, moved)
        rows = snapped.rows()
        # a loop goes on where a snapped piece came out that short
        short = moved & (pc.length_bounds(snapped) <= min_len)
        again = np.bincount(owner[short], minlength=len(going)) > 0
        bounds = np.append(first, len(idx)).tolist()
        for g, k in enumerate(going):
            out[k] = rows[bounds[g]:bounds[g + 1]]
        going = [k for g, k in enumerate(going) if again[g] and out[k]]
    return out


def _with_ends_where(pieces, p0, p1, mask):
    """:class:`morph.piece.Pieces` ``pieces`` with the first and last control points
    of those in ``mask`` moved to p0 and p1 (:func:`morph.piece.with_endpoints`),
    the others as they are (the same bits)."""
    groups = []
    for ks, h in pieces.groups:
        m = mask[ks]
        if m.any():
            h = h.copy()
            h[m, 0, :2] = p0.take(ks[m], axis=0) * h[m, 0, 2:]
            h[m, -1, :2] = p1.take(ks[m], axis=0) * h[m, -1, 2:]
        groups.append((ks, h))
    return pc.Pieces(groups, len(pieces))


def _ray_winding(x, loop, flat):
    """:func:`_ray_windings` of one point and loop."""
    return int(_ray_windings(np.asarray(x, float)[None], [loop], flat)[0])


def _ray_windings(xs, loops, flat):
    """The winding number of each loop flattened within ``flat`` at its point xs[k]
    (:func:`morph.polyline.winding_number`'s rule), from the pieces whose control
    boxes meet the ray from the point to the right only: no other edge can cross
    it (the rest of a loop after many lobes is long, the ray short).  All loops'
    pieces at once."""
    sizes = _sizes(loops)
    out = np.zeros(len(loops), np.int64)
    if not sizes.sum():
        return out
    flat_pieces = [p for loop in loops for p in loop]
    owner = np.arange(len(loops)).repeat(sizes)
    box, x = pc.bboxes(flat_pieces), xs[owner]
    meet = ((box[:, 1] <= x[:, 1]) & (box[:, 3] >= x[:, 1])
            & (box[:, 2] >= x[:, 0])).nonzero()[0]
    if not len(meet):
        return out
    met = pc.Pieces.of(flat_pieces).take(meet)
    o, _, a = pl.flat_starts(met, flat)
    # each vertex's edge runs to the next vertex of its piece, or to the piece's end
    b = np.empty_like(a)
    b[:-1] = a[1:]
    last = np.append(o[1:] != o[:-1], True)
    b[last] = pc.end_points(met)[1][o[last]]
    hit = ray_crossings(xs[owner[meet[o]]], a, b)
    return np.bincount(owner[meet[o]], weights=hit, minlength=len(loops)).astype(np.int64)


#: Gauss-Legendre nodes per piece of :func:`_loop_areas`
AREA_NODES = 24


def _loop_areas(loops):
    """The signed area of each loop (:func:`morph.moments.loop_area`, about the loop's
    first point), by AREA_NODES-point Gauss-Legendre on every piece at once: exact
    for polynomial pieces up to degree 24 (the integrand x y' - y x' is a
    polynomial of degree 2n - 1), to the rule's error on rational ones (no
    adaptive halving: the areas only say which part of a split loop is the smaller
    and whether a lobe's area exceeds eps^2, :func:`_keep_lobes`)."""
    sizes = _sizes(loops)
    if not sizes.sum():
        return np.zeros(len(loops))
    flat = [p for loop in loops for p in loop]
    owner = np.arange(len(loops)).repeat(sizes)
    h = pc.stack(flat)
    origin = h[sizes.cumsum()[sizes > 0] - sizes[sizes > 0], 0]  # first point of each loop
    origin = origin[(sizes > 0).cumsum() - 1][owner]
    h[..., :2] -= origin[:, None, :2] / origin[:, None, 2:] * h[..., 2:]
    x, w = gauss_legendre(AREA_NODES)
    t = 0.5 * (x + 1.0)
    n = h.shape[1] - 1
    val = np.einsum("qi,kij->kqj", bz.basis(n, t), h)
    dval = np.einsum("qi,kij->kqj", bz.basis(n - 1, t), n * np.diff(h, axis=1))
    # x y' - y x' of P = (X, Y) / W: (X Y' - Y X') / W^2
    cross = (val[..., 0] * dval[..., 1] - val[..., 1] * dval[..., 0]) / val[..., 2] ** 2
    return np.bincount(owner, weights=0.25 * cross @ w, minlength=len(loops))


def _keep_lobes(lobes, rests, a_lobe, a_rest, eps, hole_test=None):
    """Is each lobe cut off its rest a boundary of the filled set?  Beside the rest
    with the same orientation, it is a part of its own; nested in the rest with the
    opposite one, it bounds a hole (winding 0: two parts of the rest touching within
    eps around it), which ``hole_test`` may find filled.  A lobe of the opposite
    orientation beside the rest (a twist) or nested with the same one (a curl)
    bounds nothing; nor does one of area below eps^2 (or none).  ``a_lobe``,
    ``a_rest``: their signed areas.  The probes (each lobe's middle piece at 0.5),
    the windings and the hole tests of all lobes at once."""
    keep = np.zeros(len(lobes), bool)
    sizes = _sizes(lobes)
    test = ((sizes > 0) & (np.abs(a_lobe) > eps * eps)).nonzero()[0]
    if not len(test):
        return keep
    mids = [lobes[k][m] for k, m in zip(test.tolist(), (sizes[test] // 2).tolist())]
    probes = pc.jet_many(pc.stack(mids), np.arange(len(mids)), np.full(len(mids), 0.5))[0]
    nested = _ray_windings(probes, [rests[k] for k in test.tolist()], eps / 10) != 0
    same = np.sign(a_lobe[test]) == np.sign(a_rest[test])
    keep[test] = np.where(same, ~nested, nested)
    holes = test[~same & nested]
    if len(holes) and hole_test is not None:
        rings = pl.flatten_loops([lobes[k] for k in holes.tolist()], eps / 10)
        many = getattr(hole_test, "many", None)
        filled = (many([(r, []) for r in rings]) if many is not None
                  else [hole_test(r, []) for r in rings])
        keep[holes] = ~np.asarray(filled, bool)
    return keep

"""A cheap crossing test on polylines, for deciding whether loops need filling.

Segments are bucketed on a grid (hashing their bounding boxes) and candidate pairs
tested with orientation predicates, all vectorised.
"""

import numpy as np

from .. import bernstein as bz
from .. import piece as pc


def _flatten_all(pieces, tol):
    """Segments of all pieces: arrays p0 (N,2), p1 (N,2), piece id, t0, t1."""
    p0s, p1s, ids, t0s, t1s = [], [], [], [], []
    for k, (pts, ts) in enumerate(pc.flatten_many(pieces, tol)):
        if len(pts) < 2:
            continue
        p0s.append(pts[:-1])
        p1s.append(pts[1:])
        ids.append(np.full(len(pts) - 1, k))
        t0s.append(ts[:-1])
        t1s.append(ts[1:])
    return (np.concatenate(p0s), np.concatenate(p1s), np.concatenate(ids),
            np.concatenate(t0s), np.concatenate(t1s))


def _segment_pairs(p0, p1, ids, same_piece_ok):
    """Index pairs (i < j) of segments whose bounding boxes overlap (grid hashing)."""
    lo = np.minimum(p0, p1)
    hi = np.maximum(p0, p1)
    n = len(p0)
    span = np.maximum(hi.max(axis=0) - lo.min(axis=0), 1e-300)
    lengths = np.maximum(hi - lo, 0).max(axis=1)
    # cells about as large as the typical segment (few segments per cell), grown
    # while long segments would cover more than 8 cells per segment on average
    cell = max(float(np.median(lengths)) * 2.0, span.max() * 1e-9)
    origin = lo.min(axis=0)
    while True:
        c0 = np.floor((lo - origin) / cell).astype(np.int64)
        c1 = np.floor((hi - origin) / cell).astype(np.int64)
        nx = c1[:, 0] - c0[:, 0] + 1
        ny = c1[:, 1] - c0[:, 1] + 1
        counts = nx * ny
        if counts.sum() <= 8 * n + 64:
            break
        cell *= 2.0
    seg = np.repeat(np.arange(n), counts)
    # enumerate cells covered by each segment's box
    offs = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    cx = c0[seg, 0] + offs % nx[seg]
    cy = c0[seg, 1] + offs // nx[seg]
    key = cx * 1_000_003 + cy
    order = np.argsort(key, kind="stable")
    key, seg = key[order], seg[order]
    # all pairs within each run of equal keys: position i pairs with i+1 .. end-1
    bounds = np.flatnonzero(np.diff(key)) + 1
    ends = np.repeat(np.concatenate([bounds, [len(key)]]),
                     np.diff(np.concatenate([[0], bounds, [len(key)]])))
    cnt = ends - np.arange(len(key)) - 1
    if cnt.sum() == 0:
        return np.zeros((0, 2), np.int64)
    first = np.repeat(np.arange(len(key)), cnt)
    second = first + 1 + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    pairs = np.sort(np.stack([seg[first], seg[second]], axis=1), axis=1)
    pairs = np.unique(pairs, axis=0)
    i, j = pairs[:, 0], pairs[:, 1]
    keep = np.all(lo[i] <= hi[j] + 1e-12 * span.max(), axis=1) & np.all(lo[j] <= hi[i] + 1e-12 * span.max(), axis=1)
    return pairs[keep]


def uncertain_pairs(loops):
    """Pairs (i, j), i <= j, of pieces (indices into the loops' pieces in order) of
    one loop that may cross or touch away from a shared end: their control boxes
    overlap and no monotone chain holds both.

    A chain of consecutive pieces whose tangents stay in a cone narrower than pi
    (:func:`morph.piece.tangent_cones`, corners included) is monotone along the
    cone's bisector, so it is a simple arc: two of its pieces meet at most at a
    shared end.  Either way round the loop from i to j may be that chain.
    """
    pieces = [p for loop in loops for p in loop]
    sizes = np.array([len(loop) for loop in loops])
    owner = np.repeat(np.arange(len(loops)), sizes)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    local = np.arange(len(pieces)) - first[owner]
    start, lo, hi, end = pc.tangent_cones(pieces)
    nxt = first[owner] + (local + 1) % sizes[owner]
    turn = end + np.angle(np.exp(1j * (start[nxt] - start - end)))
    csum = np.cumsum(turn) - turn
    base = csum - csum[first][owner]  # unwrapped start angle of each piece in its loop
    total = np.add.reduceat(turn, first) if len(first) else turn
    # each loop twice in a row, the second copy one total turn further on
    pos = 2 * first[owner] + local
    m = 2 * len(pieces)
    lo2, hi2 = np.empty(m), np.empty(m)
    lo2[pos], hi2[pos] = base + lo, base + hi
    lo2[pos + sizes[owner]] = base + lo + total[owner]
    hi2[pos + sizes[owner]] = base + hi + total[owner]
    i, j = _box_pairs(pieces, owner)
    a, b = pos[i], pos[j]
    narrow = np.pi * (1.0 - 1e-9)
    fwd = _range_span(lo2, hi2, a, b) < narrow
    back = _range_span(lo2, hi2, b, a + sizes[owner[i]]) < narrow
    keep = ~(fwd | back)
    return np.stack([i[keep], j[keep]], axis=1)


def _box_pairs(pieces, owner):
    """(i, j), i <= j, of pieces of one loop whose control boxes overlap (i == j
    included)."""
    boxes = np.array([pc.bbox(p) for p in pieces])
    n = len(pieces)
    pairs = _segment_pairs(boxes[:, :2], boxes[:, 2:], np.arange(n), True) if n > 1 \
        else np.zeros((0, 2), np.int64)
    pairs = pairs[owner[pairs[:, 0]] == owner[pairs[:, 1]]]
    i = np.concatenate([np.arange(n), pairs[:, 0]])
    j = np.concatenate([np.arange(n), pairs[:, 1]])
    return i, j


def _range_span(lo, hi, a, b):
    """max(hi[a..b]) - min(lo[a..b]) for index ranges a <= b (inclusive), all at
    once (sparse tables)."""
    lows, highs = [lo], [hi]
    while 2 ** len(lows) <= len(lo):
        w = 2 ** (len(lows) - 1)
        lows.append(np.minimum(lows[-1][:-w], lows[-1][w:]))
        highs.append(np.maximum(highs[-1][:-w], highs[-1][w:]))
    k = np.floor(np.log2(b - a + 1)).astype(int)
    out = np.empty(len(a))
    for level in np.unique(k):
        s = k == level
        w = 2 ** level
        mn = np.minimum(lows[level][a[s]], lows[level][b[s] - w + 1])
        mx = np.maximum(highs[level][a[s]], highs[level][b[s] - w + 1])
        out[s] = mx - mn
    return out


def _crossings(p0, p1, pairs):
    """Proper or touching crossings of segment pairs: (pair index, u, v) parameters."""
    i, j = pairs[:, 0], pairs[:, 1]
    r = p1[i] - p0[i]
    s = p1[j] - p0[j]
    qp = p0[j] - p0[i]
    den = pc.cross2(r, s)
    ok = np.abs(den) > 1e-300
    den_safe = np.where(ok, den, 1.0)
    u = pc.cross2(qp, s) / den_safe
    v = pc.cross2(qp, r) / den_safe
    eps = 1e-9
    hit = ok & (u >= -eps) & (u <= 1 + eps) & (v >= -eps) & (v <= 1 + eps)
    return np.flatnonzero(hit), np.clip(u[hit], 0, 1), np.clip(v[hit], 0, 1)


def polylines_cross(pieces, tol):
    """True if the pieces' polylines (within tol) cross at interior points of both
    segments: a cheap test for pieces that cross each other or themselves."""
    if not pieces:
        return False
    p0, p1, ids, _, _ = _flatten_all(pieces, tol)
    pairs = _segment_pairs(p0, p1, ids, True)
    if not len(pairs):
        return False
    k, u, v = _crossings(p0, p1, pairs)
    return bool(np.any((u > 1e-9) & (u < 1 - 1e-9) & (v > 1e-9) & (v < 1 - 1e-9)))


PAIRS, JOINED, SELF = 0, 1, 2  # kinds of subdivision items (see subdivided_crossings)


def subdivided_crossings(pieces, pairs, kinds, res, max_items=1 << 18, max_depth=60):
    """Candidate crossings of pairs of pieces, by subdivision (vectorised level by
    level); None when the work would exceed ``max_items`` (near-coincident pieces).

    pairs (k, 2) index ``pieces``; kinds: ``PAIRS`` (two pieces), ``JOINED`` (the
    first piece ends where the second starts: only crossings away from that join
    count), ``SELF`` (a piece with itself).  An item (two parameter intervals) is
    dropped when the control boxes of its parts do not overlap, or, for a joined or
    self item, when the tangents of the parts stay in a cone narrower than pi (a
    monotone arc: it meets itself nowhere but at the join).  Otherwise the larger
    part is halved (a joined item gives a joined item at the join and three plain
    ones, a self item two self items and one joined).  Items whose parts are both
    smaller than ``res`` are the candidates: (pair index, s, u) at their centres.
    """
    stacked = pc.stack(pieces)
    n = len(pairs)
    it = dict(org=np.arange(n), ia=pairs[:, 0].copy(), ib=pairs[:, 1].copy(),
              a0=np.zeros(n), a1=np.ones(n), b0=np.zeros(n), b1=np.ones(n),
              kind=np.asarray(kinds, int).copy())
    found = []
    for depth in range(max_depth):
        if not len(it["org"]):
            break
        if len(it["org"]) > max_items:
            return None
        ca = _cartesian(stacked, it["ia"], it["a0"], it["a1"])
        cb = _cartesian(stacked, it["ib"], it["b0"], it["b1"])
        lo_a, hi_a, lo_b, hi_b = ca.min(1), ca.max(1), cb.min(1), cb.max(1)
        size_a = np.hypot(*(hi_a - lo_a).T)
        size_b = np.hypot(*(hi_b - lo_b).T)
        slack = 1e-9 * res
        meet = np.all(lo_a <= hi_b + slack, axis=1) & np.all(lo_b <= hi_a + slack, axis=1)
        kind = it["kind"]
        small = (size_a <= res) & (size_b <= res)
        narrow = np.zeros(len(kind), bool)
        j = kind != PAIRS
        narrow[j] = _narrow_cone(np.concatenate([_diffs(ca[j]), _diffs(cb[j])], axis=1))
        live = meet & ~narrow & ~(small & (kind != PAIRS))
        hit = live & (kind == PAIRS) & (small | (depth == max_depth - 1))
        found.append((it["org"][hit], 0.5 * (it["a0"][hit] + it["a1"][hit]),
                      0.5 * (it["b0"][hit] + it["b1"][hit])))
        it = _split_items(it, live & ~hit, size_a >= size_b)
    org, s, u = (np.concatenate(z) for z in zip(*found)) if found else (np.zeros(0, int),) * 3
    return org.astype(int), s, u


def _cartesian(stacked, idx, t0, t1):
    h = bz.subsegment_many(stacked[idx], t0, t1)
    return h[..., :2] / h[..., 2:]


def _diffs(c):
    """All differences c_j - c_i, j > i, of control points (m, k, 2): their cone holds
    every tangent of a positive-weight rational Bézier (for j > i, B_j / B_i
    increases, so X'W - XW' = sum_{i<j} w_i w_j (B_j' B_i - B_j B_i') (P_j - P_i))."""
    i, j = np.triu_indices(c.shape[1], 1)
    return c[:, j] - c[:, i]


def _narrow_cone(v):
    """Per row of vectors (m, k, 2): all nonzero ones within a cone narrower than pi."""
    norm = np.hypot(v[..., 0], v[..., 1])
    live = norm > 1e-12 * np.maximum(norm.max(axis=1, keepdims=True), 1e-300)
    ang = np.arctan2(v[..., 1], v[..., 0])
    ref = ang[np.arange(len(v)), np.argmax(live, axis=1)]
    rel = np.angle(np.exp(1j * (ang - ref[:, None])))
    lo = np.where(live, rel, 0.0).min(axis=1)
    hi = np.where(live, rel, 0.0).max(axis=1)
    return (hi - lo < np.pi * (1.0 - 1e-9)) & live.any(axis=1)


def _split_items(it, keep, split_a):
    """The next level's items (see :func:`subdivided_crossings`)."""
    it = {k: v[keep] for k, v in it.items()}
    split_a = split_a[keep]
    am, bm = 0.5 * (it["a0"] + it["a1"]), 0.5 * (it["b0"] + it["b1"])
    out = []
    plain = it["kind"] == PAIRS
    pa, pb = plain & split_a, plain & ~split_a
    out.append(_items(it, pa, a1=am[pa]))
    out.append(_items(it, pa, a0=am[pa]))
    out.append(_items(it, pb, b1=bm[pb]))
    out.append(_items(it, pb, b0=bm[pb]))
    jn = it["kind"] == JOINED  # a ends at the join, b starts there
    out.append(_items(it, jn, a0=am[jn], b1=bm[jn]))  # the halves at the join
    out.append(_items(it, jn, a1=am[jn], b1=bm[jn], kind=PAIRS))
    out.append(_items(it, jn, a0=am[jn], b0=bm[jn], kind=PAIRS))
    out.append(_items(it, jn, a1=am[jn], b0=bm[jn], kind=PAIRS))
    sf = it["kind"] == SELF
    out.append(_items(it, sf, a1=am[sf], b1=bm[sf]))
    out.append(_items(it, sf, a0=am[sf], b0=bm[sf]))
    out.append(_items(it, sf, a1=am[sf], b0=bm[sf], kind=JOINED))
    return {k: np.concatenate([o[k] for o in out]) for k in it}


def _items(it, sel, kind=None, **bounds):
    new = {k: v[sel].copy() for k, v in it.items()}
    for k, v in bounds.items():
        new[k] = v
    if kind is not None:
        new["kind"] = np.full(int(sel.sum()), kind)
    return new

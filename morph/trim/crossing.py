"""Which pieces of the lifted loops may cross, and where: monotone chains certify
the pairs that cannot (tangent cones), subdivision finds the crossings of the rest.
"""

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..polyline import segment_pairs, unique


def uncertain_pairs(loops, pieces=None, cones=None):
    """Pairs (i, j), i <= j, of pieces (indices into the loops' pieces in order) of
    one loop that may cross or touch away from a shared end: their control boxes
    overlap and no monotone chain holds both.

    A chain of consecutive pieces whose tangents stay in a cone narrower than pi
    (:func:`morph.piece.tangent_cones`, corners included) is monotone along the
    cone's bisector, so it is a simple arc: two of its pieces meet at most at a
    shared end.  Either way round the loop from i to j may be that chain.
    ``pieces``: the loops' pieces in order when known (a :class:`morph.piece.Pieces`);
    ``cones``: their :func:`morph.piece.tangent_cones` when known.
    """
    if pieces is None:
        pieces = [p for loop in loops for p in loop]
    sizes = np.array([len(loop) for loop in loops])
    owner = np.repeat(np.arange(len(loops)), sizes)
    first = np.concatenate([[0], np.cumsum(sizes)[:-1]])
    local = np.arange(len(pieces)) - first[owner]
    start, lo, hi, end = cones if cones is not None else pc.tangent_cones(pieces)
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
    boxes = pc.bboxes(pieces)
    n = len(pieces)
    pairs = segment_pairs(boxes[:, :2], boxes[:, 2:], np.arange(n), True) if n > 1 \
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
    for level in unique(k):
        s = k == level
        w = 2 ** level
        mn = np.minimum(lows[level][a[s]], lows[level][b[s] - w + 1])
        mx = np.maximum(highs[level][a[s]], highs[level][b[s] - w + 1])
        out[s] = mx - mn
    return out


PAIRS, JOINED, SELF = 0, 1, 2  # kinds of subdivision items (see subdivided_crossings)


#: A pair whose subdivision holds more items than this at one level nearly coincides
#: (two pieces within ``res`` of each other along a stretch: every level doubles its
#: items); it is left to the caller's polyline search.
PAIR_ITEMS = 1024


def subdivided_crossings(pieces, pairs, kinds, res, max_items=1 << 18, max_depth=60,
                         pair_items=PAIR_ITEMS):
    """Candidate crossings of pairs of pieces, by subdivision (vectorised level by
    level), and the pairs it gave up on.

    pairs (k, 2) index ``pieces``; kinds: ``PAIRS`` (two pieces), ``JOINED`` (the
    first piece ends where the second starts: only crossings away from that join
    count), ``SELF`` (a piece with itself).  An item (two parameter intervals) is
    dropped when the control boxes of its parts do not overlap, or, for a joined or
    self item, when the tangents of the parts stay in a cone narrower than pi (a
    monotone arc: it meets itself nowhere but at the join).  Otherwise the larger
    part is halved (a joined item gives a joined item at the join and three plain
    ones, a self item two self items and one joined).  Items whose parts are both
    smaller than ``res`` are the candidates.  A pair whose items at one level
    exceed ``pair_items`` (near-coincident pieces), and the most crowded pairs while
    all items exceed ``max_items``, are given up.  Returns (pair index, s, u) of
    the candidates at their items' centres and the indices of the pairs given up.
    """
    used = unique(pairs)
    stacked = stack_rows(pieces, used)
    inv = np.searchsorted(used, pairs)
    n = len(pairs)
    it = dict(org=np.arange(n), ia=inv[:, 0].copy(), ib=inv[:, 1].copy(),
              a0=np.zeros(n), a1=np.ones(n), b0=np.zeros(n), b1=np.ones(n),
              kind=np.asarray(kinds, int).copy())
    found, crowded = [], []
    for depth in range(max_depth):
        over = _crowded(np.bincount(it["org"], minlength=n), pair_items, max_items)
        if len(over):
            crowded.append(over)
            keep = ~np.isin(it["org"], over)
            it = {key: v[keep] for key, v in it.items()}
        if not len(it["org"]):
            break
        ca = _cartesian(stacked, it["ia"], it["a0"], it["a1"])
        cb = _cartesian(stacked, it["ib"], it["b0"], it["b1"])
        lo_a, hi_a, lo_b, hi_b = ca.min(1), ca.max(1), cb.min(1), cb.max(1)
        size_a = np.hypot(*(hi_a - lo_a).T)
        size_b = np.hypot(*(hi_b - lo_b).T)
        slack = 1e-9 * res
        ha, hb = hi_a + slack, hi_b + slack
        meet = ((lo_a[:, 0] <= hb[:, 0]) & (lo_a[:, 1] <= hb[:, 1])
                & (lo_b[:, 0] <= ha[:, 0]) & (lo_b[:, 1] <= ha[:, 1]))
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
    gave_up = np.concatenate(crowded) if crowded else np.zeros(0, int)
    return org.astype(int), s, u, gave_up


def stack_rows(pieces, rows):
    """``pc.stack(pieces)[rows]`` without stacking the other pieces: the pieces
    ``rows`` (ascending indices) elevated to the highest degree of all ``pieces``
    (the same bits: elevation is row by row)."""
    pieces = pc.Pieces.of(pieces)
    deg = max((h.shape[1] for _, h in pieces.groups), default=1) - 1
    out = np.empty((len(rows), deg + 1, 3))
    for ks, h in pieces.groups:
        at = np.searchsorted(ks, rows)
        hit = np.flatnonzero(ks[np.minimum(at, len(ks) - 1)] == rows) if len(ks) else at[:0]
        if len(hit):
            out[hit] = bz.elevate_many(h[at[hit]], deg + 1 - h.shape[1])
    return out


def _crowded(counts, pair_items, max_items):
    """Pairs (by their item counts) to give up: those above ``pair_items``, and the
    most crowded others while the rest exceeds ``max_items`` in all."""
    over = counts > pair_items
    rest = np.where(over, 0, counts)
    if rest.sum() > max_items:
        order = np.argsort(-rest, kind="stable")
        drop = np.cumsum(rest[order]) > rest.sum() - max_items
        cut = int(np.argmax(drop)) + 1           # the fewest largest whose removal fits
        over[order[:cut]] = True
    return np.flatnonzero(over)


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


#: the children of an item (:func:`_split_items`), by slot: (category of the item
#: split: plain halving a, plain halving b, joined, self; whether a0, a1, b0, b1
#: become the midpoint of their interval; the child's kind, -1 the item's own)
_SLOTS = np.array([
    (0, 0, 1, 0, 0, -1), (0, 1, 0, 0, 0, -1),              # a plain item: a halved
    (1, 0, 0, 0, 1, -1), (1, 0, 0, 1, 0, -1),              # ... b halved
    (2, 1, 0, 0, 1, -1), (2, 0, 1, 0, 1, PAIRS),           # joined: the halves at the
    (2, 1, 0, 1, 0, PAIRS), (2, 0, 1, 1, 0, PAIRS),        # join, and three plain ones
    (3, 0, 1, 0, 1, -1), (3, 1, 0, 1, 0, -1), (3, 0, 1, 1, 0, JOINED)])  # self
#: the first slot and the number of slots of each category
_SLOT_FIRST, _SLOT_COUNT = np.array([0, 2, 4, 8]), np.array([2, 2, 4, 3])


def _split_items(it, keep, split_a):
    """The next level's items (see :func:`subdivided_crossings`), slot by slot
    (:data:`_SLOTS`: a plain item gives the two halves of its larger part, a
    joined one the halves at the join and three plain items, a self item two self
    items and one joined), each slot's children in the order of their items: all
    at once, one stable sort of the children by slot."""
    it = {k: v[keep] for k, v in it.items()}
    kind = it["kind"]
    cat = np.where(kind == PAIRS, np.where(split_a[keep], 0, 1), np.where(kind == JOINED, 2, 3))
    count = _SLOT_COUNT[cat]
    item = np.repeat(np.arange(len(cat)), count)
    slot = np.repeat(_SLOT_FIRST[cat], count) + (np.arange(len(item)) - np.repeat(
        np.cumsum(count) - count, count))
    order = np.argsort(slot, kind="stable")
    item, table = item[order], _SLOTS[slot[order]]
    out = {k: v[item] for k, v in it.items()}
    for name, col in (("a0", 1), ("a1", 2), ("b0", 3), ("b1", 4)):
        mid = 0.5 * (it[name[0] + "0"] + it[name[0] + "1"])[item]
        out[name] = np.where(table[:, col] == 1, mid, out[name])
    out["kind"] = np.where(table[:, 5] >= 0, table[:, 5], out["kind"])
    return out

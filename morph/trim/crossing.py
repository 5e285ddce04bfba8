"""Which pieces of the lifted loops may cross, and where: monotone chains certify
the pairs that cannot (tangent cones), subdivision finds the crossings of the rest.

Rows of multi-dimensional arrays are gathered by ``take`` / ``compress`` (see
:mod:`morph.polyline`).
"""

from functools import lru_cache

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..polyline import member, pair_rows, segment_pairs, unique


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
    sizes = np.fromiter(map(len, loops), np.int64, len(loops))
    owner = np.arange(len(loops)).repeat(sizes)
    first = np.concatenate([[0], sizes.cumsum()[:-1]])
    local = np.arange(len(pieces)) - first[owner]
    start, lo, hi, end = cones if cones is not None else pc.tangent_cones(pieces)
    nxt = first[owner] + (local + 1) % sizes[owner]
    turn = end + np.angle(np.exp(1j * (start[nxt] - start - end)))
    csum = turn.cumsum() - turn
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
    # a query spans at most a loop and one piece: the tables' levels up to that length
    tables = _span_tables(lo2, hi2, int(np.maximum.reduce(sizes, initial=0)) + 1)
    # the way back round the loop only for the pairs the way forward does not hold (a
    # piece with itself, with the next one: mostly held)
    wide = (~(_range_span(tables, a, b) < narrow)).ravel().nonzero()[0]
    i, j = i.take(wide), j.take(wide)
    keep = ~(_range_span(tables, b.take(wide), a.take(wide) + sizes[owner[i]]) < narrow)
    return pair_rows(i[keep], j[keep])


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


def _span_tables(lo, hi, longest):
    """The sparse tables of :func:`_range_span`: (L + 1, len(lo)) arrays whose row
    ``level`` holds the min of lo (the max of hi) over the 2^level entries from each
    index on (the row's last 2^level - 1 entries unset), the windows up to
    ``longest`` entries (the longest range asked) and the array's length."""
    m = len(lo)
    top = max(min(m, longest), 1).bit_length() - 1
    lows, highs = np.empty((top + 1, m)), np.empty((top + 1, m))
    lows[0], highs[0] = lo, hi
    for level in range(1, top + 1):
        w = 1 << (level - 1)
        n = m - 2 * w + 1       # the windows of 2w entries: two of w, w apart
        np.minimum(lows[level - 1, :n], lows[level - 1, w:w + n], out=lows[level, :n])
        np.maximum(highs[level - 1, :n], highs[level - 1, w:w + n], out=highs[level, :n])
    return lows, highs


def _range_span(tables, a, b):
    """max(hi[a..b]) - min(lo[a..b]) for index ranges a <= b (inclusive), all at
    once, from the sparse tables of lo and hi (:func:`_span_tables`, holding
    windows as long as the longest range): two overlapping windows a range, each
    gathered from the flattened tables in one ``take``."""
    lows, highs = tables
    k = np.floor(np.log2(b - a + 1)).astype(np.int64)
    first = k * lows.shape[1] + a             # the window from a, the one ending at b
    last = k * lows.shape[1] + (b - np.left_shift(1, k) + 1)
    mn = np.minimum(lows.take(first), lows.take(last))
    return np.maximum(highs.take(first), highs.take(last)) - mn


PAIRS, JOINED, SELF = 0, 1, 2  # kinds of subdivision items (see subdivided_crossings)


#: A pair whose subdivision holds more items than this at one level nearly coincides
#: (two pieces within ``res`` of each other along a stretch: every level doubles its
#: items); it is left to the caller's polyline search.
PAIR_ITEMS = 1024


def subdivided_crossings(pieces, pairs, kinds, res, max_items=1 << 18, max_depth=60,
                         pair_items=PAIR_ITEMS):
    """Candidate crossings of pairs of pieces, by subdivision, and the pairs it gave
    up on: the items of all pairs are one set of arrays, each level tested and split
    at once (a fixed number of numpy calls a level, whatever the number of pairs).

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
    the candidates at their items' centres and the indices of the pairs given up
    (:func:`first_items` and :func:`subdivide`).

    Each item carries the control points of its two parts and a split halves them
    (de Casteljau at 1/2, :func:`_halves`): one small product per part, at any depth.
    """
    found = subdivide(first_items(pieces, pairs, kinds), len(pairs), res, max_items=max_items,
                      max_depth=max_depth, pair_items=pair_items)
    return found[:4]


def first_items(pieces, pairs, kinds):
    """The items of :func:`subdivided_crossings` at level 0: each pair (k, 2) of
    ``pieces`` whole, of its kind."""
    used = unique(pairs)
    stacked = stack_rows(pieces, used)
    inv = np.searchsorted(used, pairs)
    n = len(pairs)
    coords = stacked.transpose(0, 2, 1)          # (k, 3, n+1): a coordinate's points in a row
    return _Items(np.arange(n), np.asarray(kinds, int).copy(),
                  np.tile([0.0, 1.0, 0.0, 1.0], (n, 1)),
                  np.stack([coords[inv[:, 0]], coords[inv[:, 1]]], axis=1))


def subdivide(it, n, res, joining=(), park=None, max_items=1 << 18, max_depth=60,
              pair_items=PAIR_ITEMS):
    """The levels of :func:`subdivided_crossings` from items ``it`` at level 0 (of
    ``n`` pairs), and from ``joining`` [(level, items)] at their levels:
    (pair index, s, u, pairs given up, level of each candidate, parked).  ``park(pair
    index, s, u, level)``, when given, is called with each level's candidates and
    returns pairs (indices) whose items leave: they are ``parked`` [(level, items)],
    to join a later call where their search goes on.  A pair's items come from its
    own only, in their order, whichever others are there."""
    joining = dict(joining)
    found, crowded, parked = [], [], []
    depth = 0
    while depth < max_depth:
        if depth in joining:
            it = it.join(joining.pop(depth))
        # (no pair can be crowded while all items together are within both bounds)
        over = _crowded(np.bincount(it.org, minlength=n), pair_items, max_items) \
            if len(it.org) > min(pair_items, max_items) else ()
        if len(over):
            crowded.append(over)
            it = it.take(~member(it.org, np.sort(over)))
        if not len(it.org):
            if not joining:
                break
            depth = min(joining)
            continue
        live, small, split_a = _level_tests(it, res)
        hit = live & (it.kind == PAIRS) & (small | (depth == max_depth - 1))
        t = it.t.compress(hit, axis=0)
        found.append((it.org[hit], 0.5 * (t[:, 0] + t[:, 1]), 0.5 * (t[:, 2] + t[:, 3]), depth))
        it = _split_items(it, live & ~hit, split_a)
        depth += 1
        if park is not None and hit.any():
            out = member(it.org, np.sort(park(*found[-1])))
            if out.any():
                parked.append((depth, it.take(out)))
                it = it.take(~out)
    return _found(found, crowded) + (parked,)


def _found(found, crowded):
    """(pair index, s, u, pairs given up, level) of :func:`subdivide` from its
    levels' (pair index, s, u, level) ``found`` and its ``crowded`` lists."""
    gave_up = np.concatenate(crowded) if crowded else np.zeros(0, int)
    if not found:
        return (np.zeros(0, int), np.zeros(0), np.zeros(0), gave_up, np.zeros(0, int))
    org, s, u, depth = zip(*found)
    sizes = np.fromiter(map(len, org), np.int64, len(org))
    return (np.concatenate(org).astype(int), np.concatenate(s), np.concatenate(u), gave_up,
            np.array(depth, np.int64).repeat(sizes))


class _Items:
    """The items of a subdivision: pair index ``org`` (m,), ``kind`` (m,), parameter
    intervals ``t`` (m, 4: a0, a1, b0, b1) and the homogeneous control points of
    the two parts ``h`` (m, 2, 3, n+1), by coordinate (x w, y w, w)."""

    __slots__ = ("org", "kind", "t", "h")

    def __init__(self, org, kind, t, h):
        self.org, self.kind, self.t, self.h = org, kind, t, h

    def take(self, rows):
        """The items where the mask ``rows`` holds."""
        return _Items(self.org[rows], self.kind[rows], self.t.compress(rows, axis=0),
                      self.h.compress(rows, axis=0))

    def join(self, other):
        """These items, then ``other``'s."""
        return _Items(*(np.concatenate([getattr(self, a), getattr(other, a)])
                        for a in self.__slots__))


def _level_tests(it, res):
    """(live, small, split_a) of the items of one level: live, their parts' control
    boxes overlap (within 1e-9 res) and, for a joined or self item, their tangents
    are not in a cone narrower than pi, nor are both parts small; small, both parts
    at most ``res`` across (their boxes' diagonals); split_a, part a the larger."""
    c = it.h[:, :, :2] / it.h[:, :, 2:]
    lo, hi = np.minimum.reduce(c, axis=3), np.maximum.reduce(c, axis=3)  # (m, 2 parts, 2 coords)
    size = np.hypot(hi[..., 0] - lo[..., 0], hi[..., 1] - lo[..., 1])
    hi = hi + 1e-9 * res
    meet = ((lo[:, 0, 0] <= hi[:, 1, 0]) & (lo[:, 0, 1] <= hi[:, 1, 1])
            & (lo[:, 1, 0] <= hi[:, 0, 0]) & (lo[:, 1, 1] <= hi[:, 0, 1]))
    kind = it.kind
    small = (size[:, 0] <= res) & (size[:, 1] <= res)
    narrow = np.zeros(len(kind), bool)
    j = (kind != PAIRS).nonzero()[0]
    if len(j):
        d = _diffs(c.take(j, axis=0).swapaxes(2, 3).reshape(2 * len(j), -1, 2))  # a's, then b's
        narrow[j] = _narrow_cone(d.reshape(len(j), -1, 2))
    live = meet & ~narrow & ~(small & (kind != PAIRS))
    return live, small, size[:, 0] >= size[:, 1]


def stack_rows(pieces, rows):
    """``pc.stack(pieces)[rows]`` without stacking the other pieces: the pieces
    ``rows`` (ascending indices) elevated to the highest degree of all ``pieces``
    (the same bits: elevation is row by row)."""
    pieces = pc.Pieces.of(pieces)
    deg = max((h.shape[1] for _, h in pieces.groups), default=1) - 1
    out = np.empty((len(rows), deg + 1, 3))
    for ks, h in pieces.groups:
        at = np.searchsorted(ks, rows)
        hit = (ks[np.minimum(at, len(ks) - 1)] == rows).ravel().nonzero()[0] if len(ks) else at[:0]
        if len(hit):
            out[hit] = bz.elevate_many(h.take(at[hit], axis=0), deg + 1 - h.shape[1])
    return out


def _crowded(counts, pair_items, max_items):
    """Pairs (by their item counts) to give up: those above ``pair_items``, and the
    most crowded others while the rest exceeds ``max_items`` in all."""
    over = counts > pair_items
    rest = np.where(over, 0, counts)
    if rest.sum() > max_items:
        order = np.argsort(-rest, kind="stable")
        drop = rest[order].cumsum() > rest.sum() - max_items
        cut = int(np.argmax(drop)) + 1           # the fewest largest whose removal fits
        over[order[:cut]] = True
    return over.ravel().nonzero()[0]


def _diffs(c):
    """All differences c_j - c_i, j > i, of control points (m, k, 2): their cone holds
    every tangent of a positive-weight rational Bézier (for j > i, B_j / B_i
    increases, so X'W - XW' = sum_{i<j} w_i w_j (B_j' B_i - B_j B_i') (P_j - P_i))."""
    i, j = _upper(c.shape[1])
    return c[:, j] - c[:, i]


@lru_cache(maxsize=None)
def _upper(k):
    """np.triu_indices(k, 1), made once per k."""
    return np.triu_indices(k, 1)


def _narrow_cone(v):
    """Per row of vectors (m, k, 2): all nonzero ones within a cone narrower than pi."""
    norm = np.hypot(v[..., 0], v[..., 1])
    live = norm > 1e-12 * np.maximum(np.maximum.reduce(norm, axis=1, keepdims=True), 1e-300)
    ang = np.arctan2(v[..., 1], v[..., 0])
    ref = ang[np.arange(len(v)), live.argmax(axis=1)]
    z = np.exp(1j * (ang - ref[:, None]))
    rel = np.where(live, np.arctan2(z.imag, z.real), 0.0)      # np.angle of z
    lo, hi = np.minimum.reduce(rel, axis=1), np.maximum.reduce(rel, axis=1)
    return (hi - lo < np.pi * (1.0 - 1e-9)) & np.logical_or.reduce(live, axis=1)


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
    at once, one stable sort of the children by slot.  A child's part is its
    item's, or the left or right half of it (:func:`_halves` of the items kept)."""
    rows = keep.nonzero()[0]
    kind = it.kind[rows]
    # category: a plain item 0 (a halved) or 1 (b halved), joined 2, self 3 (the
    # kinds PAIRS, JOINED, SELF are 0, 1, 2)
    cat = kind + (kind != PAIRS) + ((kind == PAIRS) & ~split_a[rows])
    count = _SLOT_COUNT[cat]
    item = np.arange(len(cat)).repeat(count)
    slot = _SLOT_FIRST[cat].repeat(count) + (np.arange(len(item)) - (
        count.cumsum() - count).repeat(count))
    order = slot.argsort(kind="stable")
    item, table = item[order], _SLOTS[slot[order]]
    t = it.t.take(rows, axis=0)
    mid = 0.5 * (t[:, 0::2] + t[:, 1::2])         # (k, 2): the parts' midpoints
    out_t = t.take(item, axis=0)
    at_mid = table[:, 1:5] == 1
    out_t[at_mid] = mid.take(item, axis=0)[:, [0, 0, 1, 1]][at_mid]
    out_kind = kind[item]
    own = table[:, 5] >= 0
    out_kind[own] = table[own, 5]
    # which version of each part: 0 the item's, 1 its left half (end moved to the
    # midpoint), 2 its right half (start moved)
    version = table[:, [2, 4]] + 2 * table[:, [1, 3]]
    h = it.h.take(rows, axis=0)
    options = np.concatenate([h[None], _halves(h)])  # (3, k, 2, 3, n+1)
    at = (version * len(rows) + item[:, None]) * 2 + np.arange(2)
    out_h = options.reshape(-1, *h.shape[2:]).take(at.ravel(), axis=0).reshape(-1, *h.shape[1:])
    return _Items(it.org[rows][item], out_kind, out_t, out_h)


def _halves(h):
    """(left, right) halves (de Casteljau at 1/2) of control points by coordinate
    (..., n+1): (2, ...), each half one 2-D product of all rows (a stacked product
    would make one small one per row)."""
    left, right = _half_matrices(h.shape[-1] - 1)
    rows = h.reshape(-1, h.shape[-1])
    return np.stack([rows @ left, rows @ right]).reshape((2,) + h.shape)


@lru_cache(maxsize=None)
def _half_matrices(n):
    """(2, n+1, n+1): the matrices M with (points by coordinate) @ M the left and
    the right half of a degree-n control polygon (de Casteljau at 1/2: dyadic
    entries, exact in binary)."""
    left, right = bz.split_many(np.eye(n + 1)[None], 0.5)
    return np.stack([left[0].T, right[0].T])

"""Polylines of pieces and their crossings: a cheap test, all vectorised.

Pieces are flattened within a tolerance (:func:`flatten_many`), to segments, the segments
bucketed on a grid (hashing their bounding boxes) and candidate pairs tested with
orientation predicates.  A low-level module: ``region`` uses it to tell crossing
loops, the trimming engine to search crossings on polylines.

Rows of (n, 2) and (n, k, 3) arrays are gathered by ``take`` / ``compress`` along
axis 0: an index or mask array in ``a[idx]`` walks numpy's general iterator row by
row, 5 to 7 times the instructions of ``take`` (the same rows).
"""

import functools

import numpy as np

from . import bernstein as bz
from . import piece as pc


# ------------------------------------------------------------------ flattening

def flatten(piece, tol, max_depth=16):
    """Polyline through the piece within ``tol`` of it, with parameters.

    Returns (points (m, 2), params (m,)); see :func:`flatten_many`.
    """
    return flatten_many([piece], tol, max_depth)[0]


def flatten_many(pieces, tol, max_depth=16):
    """Polylines through many pieces, each within ``tol`` of its piece, with their
    parameters: a list of (points (m, 2), params (m,)), one per piece.

    Each piece is cut into parts until the control polygon of every part lies
    within tol of its chord (a bound on the curve's distance, by the convex hull
    property of positive-weight rational Béziers), so the polyline is within tol of
    the curve.  A part whose polygon is d > tol from its chord is cut into
    ceil(sqrt(d / tol)) equal parameter steps at once (the distance of a smooth
    curve's polygon falls with the square of the step) and checked again.  Parts
    are never narrower than 2^-max_depth in parameter; at that width they are
    accepted as they are.  Pieces of one degree are processed together.
    """
    owner, ts, starts = flat_starts(pieces, tol, max_depth)
    bounds = np.searchsorted(owner, np.arange(len(pieces) + 1))
    out = []
    for k, p in enumerate(pieces):
        a, b = bounds[k], bounds[k + 1]
        out.append((np.vstack([starts[a:b], pc.end(np.asarray(p, float))]),
                    np.append(ts[a:b], 1.0)))
    return out


def flat_starts(pieces, tol, max_depth=16, keep=None):
    """The polylines of :func:`flatten_many` without each piece's end point (the next
    piece's start, in a loop), all in three arrays: (owner (m,), t (m,), points (m,
    2)), sorted by (owner, t); owner indexes ``pieces``.  Pieces of one degree are
    processed together.  ``keep(owner, t0, width) -> mask``: parts of the
    subdivision left out (with all they would be cut into) where False; the vertices
    of the parts kept are those of the whole flattening.  ``tol``: a number, or one
    per piece (an array: the pieces of many regions, each flattened within its own)."""
    owners, params, points = [np.zeros(0, np.intp)], [np.zeros(0)], [np.zeros((0, 2))]
    tols = np.asarray(tol, float)
    for ks_arr, stack in pc.degree_groups(pieces):
        ks = ks_arr
        part_keep = None if keep is None else (lambda o, t, w, ks_arr=ks_arr: keep(ks_arr[o], t, w))
        owner, ts, starts = _flat_params(stack, tols[ks] if tols.ndim else tol,
                                         2.0 ** -max_depth, part_keep)
        owners.append(np.asarray(ks)[owner])
        params.append(ts)
        points.append(starts)
    owner, ts, pts = np.concatenate(owners), np.concatenate(params), np.concatenate(points)
    order = piece_order(owner, ts)
    return owner[order], ts[order], pts.take(order, axis=0)


def piece_order(owner, t):
    """``np.lexsort((t, owner))`` for piece indices ``owner`` >= 0 and parameters t
    in [0, 1]: a stable argsort of the one float owner * 2 + t (one pass, and a
    merge where the input is sorted runs, as the vertices of a flattening and the
    ones added to it are: a few times faster than lexsort's two), checked in one
    pass to be in (owner, t) order; lexsort where it is not (parameters of one
    piece nearer than the float's resolution there)."""
    order = (owner * 2.0 + t).argsort(kind="stable")
    o, s = owner[order], t[order]
    if len(o) < 2 or bool(np.logical_and.reduce(
            (o[1:] > o[:-1]) | ((o[1:] == o[:-1]) & (s[1:] >= s[:-1])))):
        return order
    return np.lexsort((t, owner))


def _flat_params(stack, tol, min_width, keep=None):
    """(owner, t0, start point) of the flat parts of a stack of pieces (see
    :func:`flatten_many`); a part's start point is its first control point.
    ``keep(owner, t0, width)``: the parts to cut further (see :func:`flat_starts`).
    ``tol``: a number, or an array of one per piece of the stack.  Each level makes
    a fixed number of numpy calls, array methods and ufuncs where numpy's Python
    wrappers (np.repeat, np.clip, ...) would add calls of their own: a small
    flattening's cost is its levels' calls."""
    parts, owner = stack, np.arange(len(stack))
    t0, width = np.zeros(len(stack)), np.empty(len(stack))
    width[:] = 1.0
    done_owner, done_t, done_p = [], [], []
    per_piece = getattr(tol, "ndim", 0) > 0
    while len(parts):
        dist = _chord_distance(parts)
        part_tol = tol[owner] if per_piece else tol
        flat = (dist <= part_tol) | (width <= min_width * 1.5)
        if np.logical_and.reduce(flat):   # the last level (a flattening's levels end with one)
            first = parts[:, 0]
            done_owner.append(owner)
            done_t.append(t0)
            done_p.append(first[:, :2] / first[:, 2:])
            break
        done_owner.append(owner[flat])
        done_t.append(t0[flat])
        first = parts[:, 0].compress(flat, axis=0)
        done_p.append(first[:, :2] / first[:, 2:])
        rest = ~flat
        parts, owner, t0, width, dist = (parts.compress(rest, axis=0), owner[rest], t0[rest],
                                         width[rest], dist[rest])
        steps = np.ceil(np.sqrt(dist / (tol[owner] if per_piece else tol)))
        # np.clip(np.nan_to_num(steps, nan=2.0), 2, ...) (fmax takes 2 for nan): an
        # infinite step count is clipped to the upper bound either way
        steps = np.minimum(np.fmax(steps, 2.0), np.maximum(width / min_width, 2.0))
        steps = steps.astype(np.int64)
        order = steps.argsort(kind="stable")
        parts, owner, t0, width, steps = (parts.take(order, axis=0), owner[order], t0[order],
                                          width[order], steps[order])
        rep, j = _step_rows(steps)
        if keep is not None:  # the sub-parts a caller needs, before they are cut
            t_sub = t0[rep] + j / steps[rep] * width[rep]
            m = keep(owner[rep], t_sub, width[rep] / steps[rep])
            rep, j = rep[m], j[m]   # only the steps kept are cut (each step's points are its own)
            needed = np.bincount(rep, minlength=len(parts)) > 0
            parts, owner, t0, width, steps = (parts.compress(needed, axis=0), owner[needed],
                                              t0[needed], width[needed], steps[needed])
            rep = (needed.cumsum() - 1)[rep]   # the parts' ranks among those needed
        parts = _equal_parts(parts, steps, rep, j, every=keep is None)
        owner, t0 = owner[rep], t0[rep] + j / steps[rep] * width[rep]
        width = width[rep] / steps[rep]
    return np.concatenate(done_owner), np.concatenate(done_t), np.concatenate(done_p)


def _step_rows(steps):
    """(part of each step, its rank in the part) of parts cut into ``steps`` each."""
    rep = np.arange(len(steps)).repeat(steps)
    return rep, np.arange(len(rep)) - (steps.cumsum() - steps).repeat(steps)


#: Numbers in one block of :func:`_gathered_rows`' products ((n+1) x 3 a step):
#: numpy's ufunc buffer size (a larger broadcast product goes through its buffered
#: iterator, about twice the instructions a number).
EQUAL_BLOCK = 1 << 13
#: Parts of one step count, per (n+1)^2, from which :func:`_equal_parts` cuts them on
#: their own (:func:`_loop_rows`: a scalar times a long column per matrix entry,
#: (n+1)^2 k multiplies and adds) rather than in the pass that gathers every
#: step's matrix (:func:`_gathered_rows`): the crossing point of the two in
#: callgrind's instructions, 6-10 (n+1)^2 parts at degrees 2, 3 and 7.
EQUAL_GROUP = 6


def _equal_parts(parts, steps, rep, j, every=True):
    """Each of a stack of pieces (sorted by ``steps``) cut into ``steps`` equal
    parameter steps, in order (``rep``, ``j``: the part and rank of each step,
    :func:`_step_rows`): each step's control points through its matrix
    (:func:`_equal_split_matrices`), the sum over j in order (einsum's bits).  The
    step counts held by EQUAL_GROUP (n+1)^2 parts or more by :func:`_loop_rows`,
    the rest all together by :func:`_gathered_rows`.  ``every`` False: ``rep``, ``j``
    are some of the steps only (in order), all cut by :func:`_gathered_rows` (the
    same numbers: both sum over j in order)."""
    n = parts.shape[1] - 1
    if not len(parts):
        return parts
    # the runs of one step count: their first parts and sizes
    bounds = np.concatenate(([0], (steps[1:] != steps[:-1]).nonzero()[0] + 1, [len(steps)]))
    first = bounds[:-1]
    counts, sizes = steps[first], bounds[1:] - bounds[:-1]
    _make_splits(n, counts.tolist())   # the new counts' matrices in one call
    offset = (counts.cumsum() - counts).repeat(sizes)   # each part's first matrix
    if not every:
        return _gathered_rows(_step_table(n, counts), offset[rep] + j, parts, rep)
    big = sizes >= EQUAL_GROUP * (n + 1) ** 2
    if len(counts) == 1 and big[0]:
        return _loop_rows(_equal_split_matrices(n, int(counts[0])), parts)
    out = np.empty((len(rep), n + 1, parts.shape[2]))
    start = np.concatenate(([0], (counts * sizes).cumsum())).tolist()
    for g in big.nonzero()[0].tolist():
        out[start[g]:start[g + 1]] = _loop_rows(_equal_split_matrices(n, int(counts[g])),
                                                parts[first[g]:first[g] + sizes[g]])
    if not big.all():
        table = _step_table(n, counts)
        which = offset[rep] + j
        sel = (~big).repeat(counts * sizes).nonzero()[0]
        out[sel] = _gathered_rows(table, which[sel], parts, rep[sel])
    return out


def _step_table(n, counts):
    """The matrices of cutting into each of ``counts`` steps, one after another, as
    (n+1, n+1, sum(counts)) (:func:`_split_columns`)."""
    if len(counts) == 1:
        return _split_columns(n, int(counts[0]))
    return np.concatenate([_split_columns(n, k) for k in counts.tolist()], axis=2)


def _loop_rows(mats, parts):
    """Each of ``parts`` (m, n+1, c) through each of ``mats`` (k, n+1, n+1): (m k,
    n+1, c), the sum over j in order on the parts held coordinate-first, one long
    column per (j, c)."""
    k, rows, _ = mats.shape
    pts = parts.transpose(1, 2, 0).copy()        # (n+1, c, m)
    out = np.empty((k, rows) + pts.shape[1:])
    for a in range(k):
        for i in range(rows):
            acc = mats[a, i, 0] * pts[0]
            for j in range(1, pts.shape[0]):
                acc = acc + mats[a, i, j] * pts[j]
            out[a, i] = acc
    return out.transpose(3, 0, 1, 2).reshape(-1, rows, parts.shape[2])


def _gathered_rows(table, which, parts, rep):
    """Steps ``rep`` of ``parts`` through the matrices ``which`` of ``table`` ((n+1,
    n+1, K), :func:`_split_columns`): (len(rep), n+1, c), the matrices and the
    points gathered step by step, the sum over j in order, EQUAL_BLOCK numbers a
    control point at a time."""
    n = table.shape[0] - 1
    cols = parts.transpose(1, 2, 0)
    out = np.empty((len(rep), n + 1, parts.shape[2]))
    block = max(1, EQUAL_BLOCK // (3 * (n + 1)))
    for a in range(0, len(rep), block):
        mats = table.take(which[a:a + block], axis=2)        # (n+1, n+1, steps)
        pts = cols.take(rep[a:a + block], axis=2)           # (n+1, c, steps)
        acc = mats[:, 0, None, :] * pts[0]
        for k in range(1, n + 1):
            acc += mats[:, k, None, :] * pts[k]
        out[a:a + block] = acc.transpose(2, 0, 1)
    return out


@functools.lru_cache(maxsize=256)
def _split_columns(n, k):
    """:func:`_equal_split_matrices` (k, n+1, n+1) as (n+1, n+1, k): entry (i, j)
    of every step's matrix in one row."""
    return _equal_split_matrices(n, k).transpose(1, 2, 0).copy()


#: :func:`_equal_split_matrices` made so far, by (n, k); emptied past SPLITS_KEPT
_SPLITS = {}
SPLITS_KEPT = 256


def _equal_split_matrices(n, k):
    """M_j (j < k) with M_j @ c the Bernstein coefficients of c on [j/k, (j+1)/k]."""
    if (n, k) not in _SPLITS:
        _make_splits(n, [k])
    return _SPLITS[n, k]


def _make_splits(n, counts):
    """:func:`_equal_split_matrices` of degree n for the step counts of ``counts`` not
    made yet, all in one :func:`morph.bernstein.subsegment_many` call (row by row:
    the numbers of a call per count).  The rows of the basis vectors e_0 .. e_n
    restricted to each step: row (j, i) of a count's block is e_i on step j, column
    i of M_j."""
    new = [k for k in dict.fromkeys(counts) if (n, k) not in _SPLITS]
    if not new:
        return
    if len(_SPLITS) + len(new) > SPLITS_KEPT:
        _SPLITS.clear()
    ts = [np.arange(k + 1) / k for k in new]
    t0 = np.concatenate([t[:-1] for t in ts]).repeat(n + 1)
    t1 = np.concatenate([t[1:] for t in ts]).repeat(n + 1)
    cols = bz.subsegment_many(np.tile(np.eye(n + 1), (len(t0) // (n + 1), 1)), t0, t1)
    at = 0
    for k in new:
        block = cols[at:at + k * (n + 1)]
        _SPLITS[n, k] = block.reshape(k, n + 1, n + 1).transpose(0, 2, 1).copy()
        at += k * (n + 1)


#: Parts of degree 5 or more up to which :func:`_chord_distance` takes a stack's inner
#: control points in one pass (:func:`_chord_distance_planes`): callgrind's
#: instructions a call against the columns' at degree 7, 16 parts 0.39 x, 170 parts
#: 0.82 x; at degree 5, 250 parts 1.17 x
CHORD_PLANES = 128


def _chord_distance_planes(parts):
    """:func:`_chord_distance` of a stack of pieces of degree 2 or more, its inner
    control points all at once (:func:`_to_chords` on the (m, n-1) planes: the same
    operations on each point as the columns', so the same numbers; a maximum is
    exact in any order)."""
    px, py = parts[:, :, 0] / parts[:, :, 2], parts[:, :, 1] / parts[:, :, 2]
    ends = px[:, :1], py[:, :1], px[:, -1:], py[:, -1:]
    dist = _to_chords(px[:, 1:-1], py[:, 1:-1], ends, _chord_frame(*ends))
    return np.maximum(np.maximum.reduce(dist, axis=1), 0.0)


def _chord_frame(ax, ay, bx, by):
    """(cx, cy, safe, point) of the chords from (ax, ay) to (bx, by): their vectors,
    lengths (1 where 0) and whether the chord is a point."""
    cx, cy = bx - ax, by - ay
    length = np.hypot(cx, cy)
    return cx, cy, np.where(length > 0, length, 1.0), length == 0


def _to_chords(px, py, ends, frame):
    """The distances of points (px, py) to the chords ``ends`` (ax, ay, bx, by), whose
    :func:`_chord_frame` is ``frame`` (broadcast against the points): to the chord's
    line where the point projects within it, else to the nearer end (to a where the
    chord is a point)."""
    ax, ay, bx, by = ends
    cx, cy, safe, point = frame
    rx, ry = px - ax, py - ay
    dist = np.abs(cx * ry - cy * rx) / safe
    along = (rx * cx + ry * cy) / safe / safe  # no underflow of safe^2
    dist = np.where((along < 0) | point, np.hypot(rx, ry), dist)
    return np.where((along > 1) & ~point, np.hypot(px - bx, py - by), dist)


def _chord_distance(parts):
    """For a stack (m, n+1, 3) of pieces: the largest distance of a control point to
    the chord (segment) of its part.  The inner control points one at a time, on
    (m,) columns (the ends lie on the chord; numpy reduces a short last axis row
    by row); each point's coordinates divided by its weight column by column (1-D
    strided loops; the (m, n+1) planes would go through numpy's buffered iterator).
    Lines have no inner control point: 0.  A stack of at most CHORD_PLANES parts of
    degree 5 or more in one pass over the (m, n-1) planes of its inner points
    (:func:`_chord_distance_planes`: the same numbers in a fixed dozen calls, where
    the columns take a dozen per point)."""
    if parts.shape[1] <= 2:
        return np.zeros(len(parts))
    if parts.shape[1] >= 6 and len(parts) <= CHORD_PLANES:
        return _chord_distance_planes(parts)
    return _chord_distance_columns(parts)


def _chord_distance_columns(parts):
    """:func:`_chord_distance` of a stack of pieces of degree 2 or more, its inner
    control points one at a time (:func:`_to_chords` on (m,) columns)."""
    ends = (parts[:, 0, 0] / parts[:, 0, 2], parts[:, 0, 1] / parts[:, 0, 2],
            parts[:, -1, 0] / parts[:, -1, 2], parts[:, -1, 1] / parts[:, -1, 2])
    frame = _chord_frame(*ends)
    out = np.zeros(len(parts))
    for j in range(1, parts.shape[1] - 1):
        pjx, pjy = parts[:, j, 0] / parts[:, j, 2], parts[:, j, 1] / parts[:, j, 2]
        np.maximum(out, _to_chords(pjx, pjy, ends, frame), out=out)
    return out


def flatten_loop(pieces, tol):
    """Closed polyline (without repeating the first point) of a loop within tol."""
    return flatten_loops([pieces], tol)[0]


def flatten_loops(loops, tol):
    """:func:`flatten_loop` of every loop, all pieces flattened at once; ``tol``: a
    number, or one per loop."""
    return flatten_loop_pieces([p for loop in loops for p in loop],
                               [len(loop) for loop in loops], tol)


def flatten_loop_pieces(pieces, sizes, tol):
    """:func:`flatten_loops` of loops given as their pieces one loop after another
    (a list, or a :class:`morph.piece.Pieces` already stacked) and the number of
    pieces of each."""
    sizes = np.asarray(sizes, np.int64)
    tols = np.asarray(tol, float)
    owner, _, pts = flat_starts(pieces, tols.repeat(sizes) if tols.ndim else tol)
    loop_of = np.arange(len(sizes)).repeat(sizes)[owner]
    bounds = np.searchsorted(loop_of, np.arange(len(sizes) + 1))
    return [pts[a:b] for a, b in zip(bounds[:-1], bounds[1:])]


# ------------------------------------------------------------------ segments


def flatten_segments(pieces, tol):
    """Segments of all pieces: arrays p0 (N,2), p1 (N,2), piece id, t0, t1: the
    polylines of :func:`flatten_many`, each vertex to the next of its piece (the
    last to the piece's end), all pieces at once (:func:`flat_starts`)."""
    owner, ts, starts = flat_starts(pieces, tol)
    last = np.append(owner[1:] != owner[:-1], True)[:len(owner)]   # its piece's last vertex
    p1, t1 = np.empty_like(starts), np.empty_like(ts)
    p1[:-1], t1[:-1] = starts[1:], ts[1:]
    p1[last], t1[last] = pc.end_points(pieces)[1][owner[last]], 1.0
    return starts, p1, owner, ts, t1


def unique(values):
    """Sorted distinct values of an array of numbers without NaN, flattened: the
    result of ``np.unique(values)``, without its cost: numpy 2.4's ``np.unique``
    imports ``numpy.ma`` on first use, ~10 ms of every process."""
    a = np.array(values).ravel()   # a copy, sorted in place
    a.sort()
    if len(a) > 1:
        a = a[np.concatenate(([True], a[1:] != a[:-1]))]
    return a


def member(values, sorted_set):
    """Whether each of ``values`` is in ``sorted_set`` (a sorted array without NaN):
    ``np.isin(values, sorted_set)``, which imports ``numpy.ma`` (:func:`unique`)."""
    values = np.asarray(values)
    if not len(sorted_set):
        return np.zeros(values.shape, bool)
    at = np.minimum(np.searchsorted(sorted_set, values), len(sorted_set) - 1)
    return sorted_set[at] == values


class BoxGrid:
    """Axis-aligned boxes hashed on a uniform grid, for all-at-once candidate searches.

    lo, hi: (n, 2) box corners.  Cells are about ``scale`` times the median box's
    larger side (2: few boxes per cell), grown while long boxes would cover more
    than 8 cells per box on average; the boxes found are the same at any cell size.
    ``items`` and ``keys``: the box of each (box, covered cell) entry and its cell
    key, sorted by key.
    """

    def __init__(self, lo, hi, scale=2.0):
        n = len(lo)
        self.lo, self.hi = lo, hi
        self.origin = col_min(lo)
        self.span = np.maximum(col_max(hi) - self.origin, 1e-300)
        lengths = np.maximum(np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1]), 0)
        # the median by np.partition: np.median imports numpy.ma (~10 ms of every process)
        lengths.partition([(n - 1) // 2, n // 2])
        median = 0.5 * (lengths[(n - 1) // 2] + lengths[n // 2])
        self.cell = max(float(median) * scale, np.maximum.reduce(self.span) * 1e-9)
        while True:
            x0, y0 = self._cells(lo[:, 0], lo[:, 1])
            x1, y1 = self._cells(hi[:, 0], hi[:, 1])
            nx = x1 - x0 + 1
            counts = nx * (y1 - y0 + 1)
            if np.add.reduce(counts) <= 8 * n + 64:
                break
            self.cell *= 2.0
        # each box's first cell, then the further cells of the boxes that cover more
        # (row by row): the divisions only for those
        multi = (counts > 1).nonzero()[0]
        key = _key(x0, y0)
        item = np.arange(n)
        if len(multi):
            more = counts[multi] - 1
            box = multi.repeat(more)
            offs = _ranks(more) + 1
            width = nx[box]
            row, col = np.divmod(offs, width)
            key = np.concatenate([key, _key(x0[box] + col, y0[box] + row)])
            item = np.concatenate([item, box])
        self.keys, self.items = _sorted_entries(key, item, n)

    def _cells(self, x, y):
        """The cells' columns and rows of points given as coordinate columns (1-D
        loops: an (n, 2) array less the origin goes through numpy's buffered
        iterator).  A floor: monotone in each coordinate."""
        return (np.floor((x - self.origin[0]) / self.cell).astype(np.int64),
                np.floor((y - self.origin[1]) / self.cell).astype(np.int64))

    def at_points(self, points):
        """(point index, box index) of every box whose cell holds the point: a
        superset of the boxes that contain it."""
        points = np.asarray(points, float)
        lo, hi = _search_both(self.keys, _key(*self._cells(points[:, 0], points[:, 1])))
        cnt = hi - lo
        pt = np.arange(len(points)).repeat(cnt)
        # entry lo[p] + rank: the point's offsets repeated once, plus the running count
        return pt, self.items[(lo - (cnt.cumsum() - cnt)).repeat(cnt)
                              + np.arange(np.add.reduce(cnt))]


def _key(cx, cy):
    return cx * 1_000_003 + cy


def search_sorted(sorted_keys, k, side="left"):
    """np.searchsorted(sorted_keys, k, side), the queries sorted first where there
    are many (:func:`_search_both`)."""
    if len(k) < 256:
        return sorted_keys.searchsorted(k, side)
    order = k.argsort()
    out = np.empty(len(k), np.int64)
    out[order] = sorted_keys.searchsorted(k[order], side)
    return out


def _search_both(sorted_keys, k):
    """(np.searchsorted(sorted_keys, k, "left"), ... "right"): the queries sorted
    first, where there are many (binary searches in the order of the keys walk the
    array's cache lines in order: a quarter of the time of searching in any order,
    sort included)."""
    if len(k) < 256:
        return sorted_keys.searchsorted(k, "left"), sorted_keys.searchsorted(k, "right")
    order = k.argsort()
    ks = k[order]
    lo, hi = np.empty(len(k), np.int64), np.empty(len(k), np.int64)
    lo[order] = sorted_keys.searchsorted(ks, "left")
    hi[order] = sorted_keys.searchsorted(ks, "right")
    return lo, hi


def col_min(x):
    """x.min(axis=0) of an (n, 2) array, column by column: numpy reduces a short
    last axis row by row, 30 times slower."""
    return np.array([np.minimum.reduce(x[:, 0]), np.minimum.reduce(x[:, 1])])


def col_max(x):
    """x.max(axis=0) of an (n, 2) array, column by column (see :func:`col_min`)."""
    return np.array([np.maximum.reduce(x[:, 0]), np.maximum.reduce(x[:, 1])])


def _sorted_entries(key, item, n):
    """(keys, items) of a grid's (cell key, box) entries sorted by key, each key's
    boxes in ascending order (items below ``n``).  Both as one integer
    ((key - min) << b) | item, 2^b >= n, sorted by value, a third of the time of a
    stable argsort, where that fits 62 bits (split again by a shift and a mask, no
    integer division); a lexsort where it does not."""
    if not len(key):
        return key, item
    k0 = int(np.minimum.reduce(key))
    b = max(n - 1, 0).bit_length()
    if (int(np.maximum.reduce(key)) - k0 + 1) << b < 2 ** 62:
        both = (key - k0) << b
        both |= item
        both.sort()
        return (both >> b) + k0, both & ((1 << b) - 1)
    order = np.lexsort((item, key))
    return key[order], item[order]


def _ranks(counts):
    """0, 1, .., counts[0]-1, 0, 1, .., counts[1]-1, ... (one range per count)."""
    return np.arange(np.add.reduce(counts)) - (counts.cumsum() - counts).repeat(counts)


def segment_pairs(p0, p1, ids, same_piece_ok):
    """Index pairs (i < j) of segments whose bounding boxes overlap (grid hashing)."""
    return _cell_pairs(BoxGrid(np.minimum(p0, p1), np.maximum(p0, p1)))


def _cell_pairs(grid):
    """Index pairs (i < j) of a BoxGrid's boxes that share a cell and overlap."""
    chunks = list(_cell_pair_chunks(grid))
    if not chunks:
        return np.zeros((0, 2), np.int64)
    n = len(grid.lo)
    keys = unique(np.concatenate([c[:, 0] * n + c[:, 1] for c in chunks]))  # (i, j) order
    return pair_rows(keys // n, keys % n)


def _cell_pair_chunks(grid, limit=1 << 20, first=1 << 12):
    """:func:`_cell_pair_columns` as (k, 2) arrays."""
    for i, j in _cell_pair_columns(grid, limit, first):
        yield pair_rows(i, j)


def pair_rows(i, j):
    """``np.stack([i, j], axis=1)`` of two index arrays of one dtype, in one call."""
    out = np.empty((len(i), 2), i.dtype)
    out[:, 0], out[:, 1] = i, j
    return out


def columns(*cols):
    """``np.stack(cols, axis=1)`` of 1-D arrays of one length: one allocation and a
    copy per column (np.stack makes a dozen Python calls)."""
    out = np.empty((len(cols[0]), len(cols)), np.result_type(*cols))
    for k, c in enumerate(cols):
        out[:, k] = c
    return out


@functools.lru_cache(maxsize=8)
def _chunk_marks(first, limit):
    """The running totals of :func:`_cell_pair_columns`' chunk sizes (``first``, 4
    ``first``, 16 ``first``, ..., at most ``limit``), made once per setting."""
    marks = np.minimum(first * 4.0 ** np.arange(64), limit).cumsum()
    marks.flags.writeable = False
    return marks


def _cell_pair_columns(grid, limit=1 << 20, first=1 << 12, solo=None):
    """The pairs of :func:`_cell_pairs` in chunks of cells holding about ``first``,
    4 ``first``, 16 ``first``, ... candidate pairs, at most ``limit``: a caller that
    needs one pair stops at the first chunk that has it, having paid for little more
    than that chunk.  Each pair comes once, from the first cell the two boxes share
    (the one at the larger of their first cells' columns and rows: a pair of boxes
    that share a cell share that one), without sorting the pairs found; only where
    two cells' keys coincide (more than 10^6 rows) can a pair come twice.  ``solo``:
    the boxes from this index on are not paired with each other (each still with
    the boxes before it)."""
    lo, hi = grid.lo, grid.hi
    key, seg = grid.keys, grid.items
    # all pairs within each run of equal keys: position i pairs with i+1 .. end-1
    # (a run's boxes ascend: a box from ``solo`` on is followed by such boxes only)
    bounds = (key[1:] != key[:-1]).nonzero()[0] + 1
    starts = np.concatenate(([0], bounds))
    run_ends = np.concatenate((bounds, [len(key)]))
    cnt = run_ends.repeat(run_ends - starts) - np.arange(len(key)) - 1
    if solo is not None:
        cnt[seg >= solo] = 0
    total = cnt.cumsum()
    if not len(cnt) or total[-1] == 0:
        return
    # chunk borders at run starts, every ~limit pairs (a run is never split)
    before = np.concatenate(([0], total))[starts]  # pairs before each run
    marks = _chunk_marks(first, limit)
    marks = marks[:marks.searchsorted(total[-1]) + 1]
    cut = starts[np.minimum(before.searchsorted(marks), len(starts) - 1)]
    borders = unique(np.concatenate(([0], cut, [len(key)])))
    slack = 1e-12 * np.maximum.reduce(grid.span)
    # the boxes' columns as contiguous arrays: gathering from them is several times
    # faster than gathering rows of (n, 2) arrays
    lo_x, lo_y = np.ascontiguousarray(lo[:, 0]), np.ascontiguousarray(lo[:, 1])
    hi_x, hi_y = hi[:, 0] + slack, hi[:, 1] + slack
    for s0, s1 in zip(borders[:-1], borders[1:]):
        c = cnt[s0:s1]
        if np.add.reduce(c) == 0:
            continue
        at = s0 + np.arange(s1 - s0)
        first = at.repeat(c)
        # first + 1 + its rank in the run: one repeat of the offsets, plus the running count
        second = (at + 1 - (c.cumsum() - c)).repeat(c) + np.arange(len(first))
        i, j = seg[first], seg[second]   # i < j: a run's boxes are ascending
        lxi, lxj, lyi, lyj = lo_x[i], lo_x[j], lo_y[i], lo_y[j]
        # the first shared cell: that of the larger lower corner (the cell of a
        # coordinate is a floor, monotone: the larger of the two boxes' first cells)
        shared = _key(*grid._cells(np.maximum(lxi, lxj), np.maximum(lyi, lyj)))
        keep = ((lxi <= hi_x[j]) & (lyi <= hi_y[j]) & (lxj <= hi_x[i]) & (lyj <= hi_y[i])
                & (shared == key[first]))
        yield i[keep], j[keep]


def segment_crossings(p0, p1, pairs):
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
    return hit.ravel().nonzero()[0], np.clip(u[hit], 0, 1), np.clip(v[hit], 0, 1)


def polylines_cross(pieces, tol):
    """True if the pieces' polylines (within tol) cross at interior points of both
    segments: a cheap test for pieces that cross each other or themselves."""
    if not pieces:
        return False
    p0, p1, ids, _, _ = flatten_segments(pieces, tol)
    pairs = segment_pairs(p0, p1, ids, True)
    if not len(pairs):
        return False
    k, u, v = segment_crossings(p0, p1, pairs)
    return bool(np.any((u > 1e-9) & (u < 1 - 1e-9) & (v > 1e-9) & (v < 1 - 1e-9)))


def polylines_touch(polylines, reach):
    """True if two edges of the closed ``polylines`` that are not consecutive along
    one of them come within ``reach`` of each other: crossing, overlapping, touching
    (a vertex visited twice, a loop's vertex on another's edge) or nearer than
    ``reach``.  For polylines within ``reach / 2`` of their loops of curves, False
    proves that the loops neither cross nor touch one another or themselves.  Unlike
    :func:`near_segments`, only neighbours along a polyline are exempt, not every pair
    that shares a point: a figure-8 whose lobes meet at a joint touches."""
    # the first chunk with a touching pair decides
    return any(len(p) for p in _touching_chunks(polylines, reach))


def touching_edges(polylines, reach):
    """Index pairs (i < j), shape (k, 2), into the edges of
    :func:`polyline_edges` ``(polylines)`` of the edges that :func:`polylines_touch`
    looks for: not consecutive along one polyline, and crossing, touching or nearer
    than ``reach``."""
    chunks = [p for p in _touching_chunks(polylines, reach) if len(p)]
    if not chunks:
        return np.zeros((0, 2), np.int64)
    n = sum(len(p) for p in polylines if len(p) >= 2)
    keys = unique(np.concatenate([c[:, 0] * n + c[:, 1] for c in chunks]))
    return np.stack([keys // n, keys % n], axis=1)


def _touching_chunks(polylines, reach):
    """The pairs of :func:`touching_edges`, chunk by chunk of candidates
    (:func:`_cell_pair_chunks`)."""
    polys = [np.asarray(p, float) for p in polylines if len(p) >= 2]
    if not polys:
        return
    a, b = polyline_edges(polys)
    sizes = np.array([len(p) for p in polys])
    first = (sizes.cumsum() - sizes).repeat(sizes)
    size = sizes.repeat(sizes)
    grid = BoxGrid(np.minimum(a, b) - 0.5 * reach, np.maximum(a, b) + 0.5 * reach)
    for pairs in _cell_pair_chunks(grid):
        i, j = pairs[:, 0], pairs[:, 1]
        step = np.abs(i - j)
        pairs = pairs[(first[i] != first[j]) | ((step != 1) & (step != size[i] - 1))]
        yield pairs[_within(a, b, pairs, reach)] if len(pairs) else pairs


def polylines_apart(polylines, tol):
    """True if no two edges of closed ``polylines`` (each within tol of its loop of
    curves: :func:`morph.polyline.flatten_loops`) that share no vertex come within 2 tol
    of each other: then the loops neither cross nor touch one another or themselves
    (each arc lies within tol of its edge; a sufficient test, cheap at a coarse tol;
    False says nothing)."""
    a, b = polyline_edges(polylines)
    if not len(a):
        return True
    # the first chunk of candidates with a near pair decides
    return not any(len(p) for p in _near_segment_chunks(a, b, 2.0 * tol))


def near_segments(p0, p1, reach):
    """Index pairs (i < j) of segments p0[k] p1[k] that come within ``reach`` of each
    other (crossing ones included), except pairs that share a vertex (consecutive
    along a polyline: the end of one the start of the other).  Pairs that meet
    elsewhere, such as two loops touching at a point, are included (distance 0)."""
    chunks = [p for p in _near_segment_chunks(p0, p1, reach) if len(p)]
    if not chunks:
        return np.zeros((0, 2), np.int64)
    n = len(p0)
    keys = unique(np.concatenate([c[:, 0] * n + c[:, 1] for c in chunks]))
    return np.stack([keys // n, keys % n], axis=1)


class GroupGrid:
    """Axis-aligned boxes of many sets at once (box k in set ``group[k]``), hashed
    on a grid whose cells are those of each set: about twice its median box's larger
    side, at least 2^-20 of its extent (so that a cell index fits 21 bits), doubled
    while its boxes would cover more than 8 cells per box on average (as
    :class:`BoxGrid` of the set alone); a cell's key holds its set, so sets that lie
    on top of each other (the glyphs of a font) do not meet in a cell.  ``span``: each
    set's extent (the larger side of its boxes' bounding box, BoxGrid's
    ``span.max()``); ``keys`` and ``items`` as BoxGrid's."""

    def __init__(self, lo, hi, group, sets):
        self.lo, self.hi = lo, hi
        self.group = group = np.asarray(group, np.int64)
        glo, ghi = set_extents(lo, hi, group, sets)
        self.span = np.maximum(ghi - glo, 1e-300).max(axis=1)
        self.origin = np.where(np.isfinite(glo), glo, 0.0)
        d = hi - lo   # the larger side, column by column (a short last axis reduces slowly)
        lengths = np.maximum(np.maximum(d[:, 0], d[:, 1]), 0.0)
        count = np.bincount(group, minlength=sets)
        # each set's lengths in order: one sort of (set, length) pairs as complex
        # numbers, which numpy orders by real part, then imaginary (a lexsort's order)
        ranked = np.sort(group + 1j * lengths)
        first = np.searchsorted(ranked.real, np.arange(sets))
        last = max(len(ranked) - 1, 0)
        median = np.zeros(sets)
        if len(ranked):
            m0 = ranked.imag[np.minimum(first + (count - 1) // 2, last)]
            m1 = ranked.imag[np.minimum(first + count // 2, last)]
            median = np.where(count > 0, 0.5 * (m0 + m1), 0.0)
        self.cell = np.where(count > 0, np.maximum(2.0 * median, self.span * 2.0 ** -20), 1.0)
        while True:
            c0, c1 = self._cell(lo, group), self._cell(hi, group)
            nx = c1[:, 0] - c0[:, 0] + 1
            covered = nx * (c1[:, 1] - c0[:, 1] + 1)
            over = np.bincount(group, weights=covered, minlength=sets) > 8 * count + 64
            if not over.any():
                break
            self.cell[over] *= 2.0
        item = np.arange(len(lo)).repeat(covered)
        offs = _ranks(covered)
        key = self._key(group[item], c0[item, 0] + offs % nx[item], c0[item, 1] + offs // nx[item])
        self.keys, self.items = _sorted_entries(key, item, len(lo))

    def _cell(self, x, group):
        return np.floor((x - self.origin[group]) / self.cell[group][:, None]).astype(np.int64)

    @staticmethod
    def _key(group, cx, cy):
        # np.clip's checks cost more than the two ufuncs it comes to
        return ((group << 42) + (np.minimum(np.maximum(cx, -1), 1 << 20) << 21)
                + np.minimum(np.maximum(cy, -1), 1 << 20))

    def at_points(self, points, group):
        """(point index, box index) of every box of the point's set (``group[k]``)
        whose cell holds the point: a superset of the boxes that contain it."""
        group = np.asarray(group, np.int64)
        c = self._cell(np.asarray(points, float), group)
        k = self._key(group, c[:, 0], c[:, 1])
        lo = np.searchsorted(self.keys, k, "left")
        cnt = np.searchsorted(self.keys, k, "right") - lo
        pt = np.arange(len(k)).repeat(cnt)
        box = self.items[lo.repeat(cnt) + _ranks(cnt)]
        same = self.group[box] == group[pt]
        return pt[same], box[same]

    def pairs(self):
        """Index pairs (i < j) of boxes of one set that share a cell and overlap
        (within 1e-12 of the set's extent, as :func:`_cell_pairs`)."""
        key, seg = self.keys, self.items
        bounds = np.diff(key).ravel().nonzero()[0] + 1
        ends = np.concatenate([bounds, [len(key)]]).repeat(
            np.diff(np.concatenate([[0], bounds, [len(key)]])))
        cnt = ends - np.arange(len(key)) - 1
        first = np.arange(len(key)).repeat(cnt)
        a, b = seg[first], seg[first + 1 + _ranks(cnt)]
        n = len(self.lo)
        keys = unique(np.minimum(a, b) * n + np.maximum(a, b))
        i, j = keys // n, keys % n
        gi = self.group[i]
        slack = 1e-12 * self.span[gi]
        keep = gi == self.group[j]
        # a column at a time: numpy reduces a short last axis row by row
        for axis in (0, 1):
            lo, hi = self.lo[:, axis], self.hi[:, axis]
            keep &= (lo[i] <= hi[j] + slack) & (lo[j] <= hi[i] + slack)
        return np.stack([i[keep], j[keep]], axis=1)


def set_extents(lo, hi, group, sets):
    """The lowest ``lo`` and highest ``hi`` corner of each set's boxes, (sets, 2) each
    (inf / -inf for a set without boxes): by runs of ``group`` where it is sorted (the
    sets of a font's glyphs come in order; ``ufunc.at`` costs ten times as much), else
    by ``ufunc.at``.  Minima and maxima: the same numbers either way."""
    glo, ghi = np.full((sets, 2), np.inf), np.full((sets, 2), -np.inf)
    if not len(group):
        return glo, ghi
    if bool(np.logical_and.reduce(group[1:] >= group[:-1])):
        starts = np.flatnonzero(np.concatenate([[True], group[1:] != group[:-1]]))
        glo[group[starts]] = np.minimum.reduceat(lo, starts, axis=0)
        ghi[group[starts]] = np.maximum.reduceat(hi, starts, axis=0)
        return glo, ghi
    np.minimum.at(glo, group, lo)
    np.maximum.at(ghi, group, hi)
    return glo, ghi


def near_segment_pairs_grouped(p0, p1, group, reach):
    """:func:`near_segments` of many sets of segments at once: segment k belongs to
    set ``group[k]``, ``reach`` is one per set, and only pairs of one set are looked
    at (:class:`GroupGrid`).  Returns index pairs (i < j), shape (k, 2): the pairs
    :func:`near_segments` finds in each set alone (its rule for segments that share
    a vertex, at 1e-12 of the set's extent)."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    group = np.asarray(group, np.int64)
    reach = np.asarray(reach, float)
    if len(p0) < 2:
        return np.zeros((0, 2), np.int64)
    half = 0.5 * reach[group][:, None]
    grid = GroupGrid(np.minimum(p0, p1) - half, np.maximum(p0, p1) + half, group, len(reach))
    pairs = grid.pairs()
    i, j = pairs[:, 0], pairs[:, 1]
    join = 1e-12 * grid.span[group[i]]
    cols = _columns(p0, p1)
    pairs = pairs[~(_chained(cols, i, j, join) | _chained(cols, j, i, join))]
    if not len(pairs):
        return pairs
    return pairs[_within_columns(cols, pairs[:, 0], pairs[:, 1], reach[group[pairs[:, 0]]])]


def _chained(cols, i, j, join):
    """Whether segment i ends where segment j starts, within ``join`` in each
    coordinate (segments as columns, :func:`_columns`)."""
    x0, y0, x1, y1 = cols
    return np.maximum(np.abs(x1[i] - x0[j]), np.abs(y1[i] - y0[j])) <= join


def _near_segment_chunks(p0, p1, reach):
    """The pairs of :func:`near_segments`, chunk by chunk of candidates
    (:func:`_cell_pair_chunks`)."""
    grid = BoxGrid(np.minimum(p0, p1) - 0.5 * reach, np.maximum(p0, p1) + 0.5 * reach)
    join = 1e-12 * float(grid.span.max())
    for pairs in _cell_pair_chunks(grid):
        i, j = pairs[:, 0], pairs[:, 1]
        chained = ((np.abs(p1[i] - p0[j]).max(axis=1) <= join)
                   | (np.abs(p1[j] - p0[i]).max(axis=1) <= join))
        pairs = pairs[~chained]
        if len(pairs):
            yield pairs[_within(p0, p1, pairs, reach)]


def _within(p0, p1, pairs, reach):
    """Mask of the segment pairs (i, j) that cross or come within ``reach``: the
    crossings of :func:`segment_crossings` and the least of the four end-to-segment
    distances of :func:`segment_distance`, the same arithmetic on contiguous
    coordinate columns (gathering rows of (n, 2) arrays and reducing their short
    last axis cost several times as much)."""
    return _within_columns(_columns(p0, p1), pairs[:, 0], pairs[:, 1], reach)


def _columns(p0, p1):
    """The coordinates of segments p0[k] p1[k] as four contiguous columns."""
    return (np.ascontiguousarray(p0[:, 0]), np.ascontiguousarray(p0[:, 1]),
            np.ascontiguousarray(p1[:, 0]), np.ascontiguousarray(p1[:, 1]))


def _within_columns(cols, i, j, reach):
    """:func:`_within` of the pairs (i[k], j[k]) of segments given as columns
    (:func:`_columns`)."""
    x0, y0, x1, y1 = cols
    ax, ay, bx, by = x0[i], y0[i], x1[i], y1[i]
    cx, cy, dx, dy = x0[j], y0[j], x1[j], y1[j]
    rx, ry = bx - ax, by - ay
    sx, sy = dx - cx, dy - cy
    qx, qy = cx - ax, cy - ay
    den = rx * sy - ry * sx
    ok = np.abs(den) > 1e-300
    den_safe = np.where(ok, den, 1.0)
    u = (qx * sy - qy * sx) / den_safe
    v = (qx * ry - qy * rx) / den_safe
    eps = 1e-9
    hit = ok & (u >= -eps) & (u <= 1 + eps) & (v >= -eps) & (v <= 1 + eps)
    gap = np.minimum(np.minimum(_point_segment(ax, ay, cx, cy, sx, sy),
                                _point_segment(bx, by, cx, cy, sx, sy)),
                     np.minimum(_point_segment(cx, cy, ax, ay, rx, ry),
                                _point_segment(dx, dy, ax, ay, rx, ry)))
    return hit | (gap <= reach)


def _point_segment(px, py, ax, ay, abx, aby):
    """:func:`segment_distance` from points (px, py) to segments from (ax, ay) along
    (abx, aby), on columns."""
    ll = np.maximum(abx * abx + aby * aby, 1e-300)
    t = np.minimum(np.maximum(((px - ax) * abx + (py - ay) * aby) / ll, 0.0), 1.0)
    return np.hypot(ax + t * abx - px, ay + t * aby - py)


def polyline_edges(polylines):
    """The edges of closed polylines as two (e, 2) arrays ``a, b``: edge k runs from
    ``a[k]`` to ``b[k]``, each polyline closed from its last point to its first
    (polylines with fewer than 2 points have no edge)."""
    polys = [np.asarray(p, float) for p in polylines if len(p) >= 2]
    if not polys:
        return np.zeros((0, 2)), np.zeros((0, 2))
    a = np.concatenate(polys)
    sizes = np.array([len(p) for p in polys], np.int64)
    last = sizes.cumsum() - 1
    following = np.arange(1, len(a) + 1)
    following[last] = last - sizes + 1   # each polyline closed: its last point to its first
    return a, a[following]


def winding_number(points, polylines, chunk=2_000_000):
    """Winding numbers of points with respect to closed polylines, shape (m,) int.

    ``polylines`` is a list of (k, 2) arrays (closed implicitly, first point not
    repeated).  Crossing rule: an edge going up across the point's horizontal line
    with the point on its left counts +1, going down with the point on its right -1.
    Vectorised over points x edges (in chunks of about ``chunk`` pairs).
    """
    pts = np.atleast_2d(np.asarray(points, float))
    return winding_of_others(pts, np.full(len(pts), -1), polylines, chunk)


def near_point_pairs(points, reach):
    """Index pairs (i < j), shape (k, 2), of points within ``reach`` of each other
    in each coordinate (a grid search, no all-pairs loop)."""
    pts = np.asarray(points, float)
    if len(pts) < 2:
        return np.zeros((0, 2), np.int64)
    return _cell_pairs(BoxGrid(pts - 0.5 * reach, pts + 0.5 * reach))


def winding_of_others(points, owner, polylines, chunk=2_000_000):
    """Winding number at each point of the closed ``polylines`` other than its own
    (``owner[k]``: the index of point k's polyline, whose edges it does not count;
    -1: all count), shape (m,) int; the crossing rule of :func:`winding_number`.

    Only the edges that span a point's height can cross its ray: they are found on
    horizontal slabs (a :class:`BoxGrid` of the edges' y-ranges, all at one x), in
    blocks of points of about ``chunk`` (point, edge) pairs, not points x edges."""
    pts = np.atleast_2d(np.asarray(points, float))
    a, b, edge_owner = _owned_edges(polylines)
    out = np.zeros(len(pts), int)
    if not len(a) or not len(pts):
        return out
    ys = np.stack([a[:, 1], b[:, 1]], axis=1)
    zero = np.zeros((len(a), 1))
    grid = BoxGrid(np.hstack([zero, ys.min(axis=1, keepdims=True)]),
                   np.hstack([zero, ys.max(axis=1, keepdims=True)]))
    probe = np.stack([np.zeros(len(pts)), pts[:, 1]], axis=1)
    owner = np.broadcast_to(np.asarray(owner), (len(pts),))
    step = max(1, chunk // 64)  # points per block: ~64 candidate edges a point or fewer
    for s in range(0, len(pts), step):
        k, e = grid.at_points(probe[s:s + step])
        k = k + s
        sign = ray_crossings(pts[k], a[e], b[e]) * (owner[k] != edge_owner[e])
        out += np.bincount(k, weights=sign, minlength=len(pts)).astype(int)
    return out


def winding_of_others_grouped(points, owner, polylines, group, sets):
    """:func:`winding_of_others` for polylines of many sets at once: polyline m
    belongs to set ``group[m]``; point k counts the polylines of its own polyline's
    set (``group[owner[k]]``) other than ``owner[k]``.  The edges that span a
    point's height are found on horizontal slabs (a :class:`GroupGrid` of their
    y-ranges): the same crossings, so the same numbers."""
    pts = np.atleast_2d(np.asarray(points, float))
    a, b, edge_owner = _owned_edges(polylines)
    out = np.zeros(len(pts), int)
    if not len(a) or not len(pts):
        return out
    group = np.asarray(group, np.int64)
    owner = np.asarray(owner, np.int64)
    zero = np.zeros((len(a), 1))
    ys = np.stack([a[:, 1], b[:, 1]], axis=1)
    grid = GroupGrid(np.hstack([zero, ys.min(axis=1, keepdims=True)]),
                     np.hstack([zero, ys.max(axis=1, keepdims=True)]), group[edge_owner], sets)
    probe = np.stack([np.zeros(len(pts)), pts[:, 1]], axis=1)
    k, e = grid.at_points(probe, group[owner])
    sign = ray_crossings(pts[k], a[e], b[e]) * (owner[k] != edge_owner[e])
    return np.bincount(k, weights=sign, minlength=len(pts)).astype(int)


def distance_to_others_grouped(points, owner, polylines, group, reach):
    """:func:`distance_to_others` for polylines of many sets at once (polyline m in
    set ``group[m]``, ``reach`` one per set): from point k to the edges of the
    polylines of its own polyline's set other than ``owner[k]``."""
    pts = np.atleast_2d(np.asarray(points, float))
    a, b, edge_owner = _owned_edges(polylines)
    out = np.full(len(pts), np.inf)
    if not len(a) or not len(pts):
        return out
    group = np.asarray(group, np.int64)
    owner = np.asarray(owner, np.int64)
    reach = np.asarray(reach, float)
    r = reach[group[edge_owner]][:, None]
    grid = GroupGrid(np.minimum(a, b) - r, np.maximum(a, b) + r, group[edge_owner], len(reach))
    k, e = grid.at_points(pts, group[owner])
    keep = owner[k] != edge_owner[e]
    k, e = k[keep], e[keep]
    d = segment_distance(pts[k], a[e], b[e])
    near = d <= reach[group[owner[k]]]
    np.minimum.at(out, k[near], d[near])
    return out


def ray_crossings(p, a, b):
    """The crossing rule of :func:`winding_number` for pairs of a point p[i] and an
    edge a[i] b[i]: +1 where the edge goes up across the point's horizontal line with
    the point on its left, -1 where it goes down with the point on its right, else
    0, shape (m,) int."""
    cross = (b[:, 0] - a[:, 0]) * (p[:, 1] - a[:, 1]) - (b[:, 1] - a[:, 1]) * (p[:, 0] - a[:, 0])
    up = (a[:, 1] <= p[:, 1]) & (b[:, 1] > p[:, 1]) & (cross > 0)
    down = (a[:, 1] > p[:, 1]) & (b[:, 1] <= p[:, 1]) & (cross < 0)
    return up.astype(int) - down.astype(int)


def _owned_edges(polylines):
    """:func:`polyline_edges` and the index of each edge's polyline."""
    sizes = np.array([len(p) if len(p) >= 2 else 0 for p in polylines], np.int64)
    a, b = polyline_edges(polylines)
    return a, b, np.arange(len(polylines)).repeat(sizes)


def distance_to_others(points, owner, polylines, reach):
    """Distance from each point to the nearest edge of the closed ``polylines`` other
    than its own (``owner[k]``), shape (m,), where that is at most ``reach``; inf
    where no other edge comes within ``reach``.  Edges near each point found on a
    grid (:class:`BoxGrid` of the edges' boxes grown by ``reach``): no all-pairs
    product."""
    pts = np.atleast_2d(np.asarray(points, float))
    a, b, edge_owner = _owned_edges(polylines)
    out = np.full(len(pts), np.inf)
    if not len(a) or not len(pts):
        return out
    grid = BoxGrid(np.minimum(a, b) - reach, np.maximum(a, b) + reach)
    k, e = grid.at_points(pts)
    keep = np.asarray(owner)[k] != edge_owner[e]
    k, e = k[keep], e[keep]
    d = segment_distance(pts[k], a[e], b[e])
    near = d <= reach
    np.minimum.at(out, k[near], d[near])
    return out


def project(x, a, b):
    """Parameter in [0, 1] of the point of segment ab nearest to x (broadcasting)."""
    ab, ax = b - a, x - a
    # the two products added as columns: a sum over a last axis of 2 is a slow
    # reduction in numpy (a loop per row), and the same bits
    ll = np.maximum(ab[..., 0] * ab[..., 0] + ab[..., 1] * ab[..., 1], 1e-300)
    return np.minimum(np.maximum((ax[..., 0] * ab[..., 0] + ax[..., 1] * ab[..., 1]) / ll, 0.0),
                      1.0)


def segment_distance(x, a, b):
    """Distance from x to segment ab (broadcasting over leading axes)."""
    x, a, b = (np.asarray(z, float) for z in (x, a, b))
    d = a + project(x, a, b)[..., None] * (b - a) - x
    return np.hypot(d[..., 0], d[..., 1])


def min_segment_distance(points, a, b, chunk=1 << 22):
    """Distance from each point (m, 2) to the nearest of the segments a[k] b[k],
    in chunks of about ``chunk`` point-segment pairs."""
    out = np.empty(len(points))
    step = max(1, chunk // max(len(a), 1))
    for i in range(0, len(points), step):
        out[i:i + step] = segment_distance(points[i:i + step, None, :], a, b).min(axis=1)
    return out

"""Trimming convolution curves to the Minkowski sum boundary (Secs. 3.3.1 and 6).

Pipeline, all on the rational pieces (polylines are used only to find where to look
and to count windings):

1. Convolution pieces of all types, type 3 kept so the pieces close into loops
   (:mod:`morph.convolve`); exact copies merged into one piece with a weight.
2. Intersections: every pair of pieces (and every piece with itself, which finds the
   local self-intersection loops of rule 3 near cusps) is searched on flattened
   polylines, crossings and near misses alike; each is refined by Newton iteration
   on the exact rational pieces (the paper's way, Fig. 33) inside its segments'
   parameter box.  Where two pieces fold back at a shared end (a cusp), the ends are
   searched again 64 times finer.  End points of one piece lying on another
   (T-junctions) are projected onto it.
3. Pieces are cut at those parameters and stay rational Béziers; sub-pieces shorter
   than tol / 10 are contracted to a node.
4. The winding number just left and right of the middle of every sub-piece is
   counted directly (ray crossings with fine polylines of all sub-pieces); a side
   is in the sum if its winding is positive.  A side with winding <= 0 next to a
   filled side is decided exactly, x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ (winding numbers
   miss holes of one operand that the other fills, Sec. 6), once per face.
5. Sub-pieces with the sum on exactly one side are chained into loops, with the sum
   on their left: outer loops counter-clockwise, holes clockwise.

:func:`fill_region` uses steps 2-5 to fill self-intersecting or overlapping loops by
the nonzero or even-odd rule.
"""

import numpy as np

from . import piece as pc
from .convolve import convolution, snap_loop
from .errors import TopologyError


# -------------------------------------------------------------- polylines

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
    cell = max(np.median(lengths) * 4.0, span.max() / 2048.0)
    origin = lo.min(axis=0)
    c0 = np.floor((lo - origin) / cell).astype(np.int64)
    c1 = np.floor((hi - origin) / cell).astype(np.int64)
    nx = c1[:, 0] - c0[:, 0] + 1
    ny = c1[:, 1] - c0[:, 1] + 1
    counts = nx * ny
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


def _candidates(p0, p1, pairs, reach):
    """Newton starts for segment pairs: proper crossings, and near misses closer
    than ``reach`` (closest points).  Returns (pair index, u, v, is_crossing)."""
    if not len(pairs):
        z = np.zeros(0)
        return z.astype(int), z, z, z.astype(bool)
    k, u, v = _crossings(p0, p1, pairs)
    miss = np.ones(len(pairs), bool)
    miss[k] = False
    m = np.flatnonzero(miss)
    i, j = pairs[m, 0], pairs[m, 1]
    # closest points of two non-crossing segments: one end of one to the other
    best = np.full(len(m), np.inf)
    bu, bv = np.zeros(len(m)), np.zeros(len(m))
    for q, s0, s1, q_is_i, qt in ((p0[i], p0[j], p1[j], True, 0.0), (p1[i], p0[j], p1[j], True, 1.0),
                                  (p0[j], p0[i], p1[i], False, 0.0), (p1[j], p0[i], p1[i], False, 1.0)):
        d = s1 - s0
        ll = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        w = np.clip(np.einsum("ij,ij->i", q - s0, d) / ll, 0.0, 1.0)
        dist = np.hypot(*(s0 + w[:, None] * d - q).T)
        better = dist < best
        best = np.where(better, dist, best)
        bu = np.where(better, qt if q_is_i else w, bu)
        bv = np.where(better, w if q_is_i else qt, bv)
    near = best <= reach
    return (np.concatenate([k, m[near]]), np.concatenate([u, bu[near]]),
            np.concatenate([v, bv[near]]),
            np.concatenate([np.ones(len(k), bool), np.zeros(int(near.sum()), bool)]))


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


def _folded_joints(pieces, ids, t0, t1, p0, p1, snap):
    """Pairs of pieces meeting end to end whose polylines turn back there (the end
    segments make an angle under 90 degrees): (a, b, box) with box the parameter
    ranges of the two end segments, widened by their width on each side."""
    first = np.flatnonzero(np.r_[True, ids[1:] != ids[:-1]])
    last = np.flatnonzero(np.r_[ids[1:] != ids[:-1], True])
    segs = {}
    for f, l in zip(first, last):
        segs[(ids[f], 0)] = (f, p1[f] - p0[f])   # leaves the start
        segs[(ids[l], 1)] = (l, p0[l] - p1[l])   # leaves the end
    keys = list(segs)
    ends = np.array([pc.start(pieces[k]) if e == 0 else pc.end(pieces[k]) for k, e in keys])
    cluster = _cluster_points(ends, 10 * snap)
    out = []
    for c in np.unique(cluster):
        members = [keys[m] for m in np.flatnonzero(cluster == c)]
        for x in range(len(members)):
            for y in range(x + 1, len(members)):
                (a, ea), (b, eb) = members[x], members[y]
                if a == b:
                    continue
                sa, da = segs[(a, ea)]
                sb, db = segs[(b, eb)]
                # both segments leave the shared point: folded if they point alike
                if da @ db <= 0:
                    continue
                wa, wb = t1[sa] - t0[sa], t1[sb] - t0[sb]
                out.append((a, b, (t0[sa] - wa, t1[sa] + wa, t0[sb] - wb, t1[sb] + wb)))
    return out


def _trivial(a, b, ta, tb, end_eps):
    """A meeting that is no crossing to cut at: end meets end, or a piece meets
    itself at the same parameter."""
    if (ta < end_eps or ta > 1 - end_eps) and (tb < end_eps or tb > 1 - end_eps):
        return True
    return a == b and abs(ta - tb) < 1e-7


def _roots_in_box(pa, pb, box, tol, max_roots=64):
    """Solutions of P_a(ta) = P_b(tb) in box (parameter ranges), from crossings of
    the two restricted pieces flattened 64 times finer than tol, each refined by
    Newton in its segments' range.  Returns [(ta, tb, err)]."""
    a0, a1 = max(box[0], 0.0), min(box[1], 1.0)
    b0, b1 = max(box[2], 0.0), min(box[3], 1.0)
    qa, ua = pc.flatten(pc.subsegment(pa, a0, a1), tol / 64)
    qb, ub = pc.flatten(pc.subsegment(pb, b0, b1), tol / 64)
    ta, tb = a0 + (a1 - a0) * ua, b0 + (b1 - b0) * ub
    i, j = np.meshgrid(np.arange(len(qa) - 1), np.arange(len(qb) - 1), indexing="ij")
    i, j = i.ravel(), j.ravel()
    p0 = np.concatenate([qa[:-1], qb[:-1]])
    p1 = np.concatenate([qa[1:], qb[1:]])
    pairs = np.column_stack([i, j + len(qa) - 1])
    k, u, v = _crossings(p0, p1, pairs)
    out = []
    for kk, uu, vv in list(zip(k, u, v))[:max_roots]:
        si, sj = i[kk], j[kk]
        box_k = (ta[si], ta[si + 1], tb[sj], tb[sj + 1])
        wa, wb = box_k[1] - box_k[0], box_k[3] - box_k[2]
        (ra, rb), err = _newton(pa, pb, box_k[0] + uu * wa, box_k[2] + vv * wb,
                                box=(box_k[0] - wa, box_k[1] + wa, box_k[2] - wb, box_k[3] + wb))
        out.append((ra, rb, err))
    return out


def _newton(pa, pb, ta, tb, iters=12, box=(0.0, 1.0, 0.0, 1.0)):
    """Refine P_a(ta) = P_b(tb) by Newton iteration on the exact pieces (Fig. 33).

    The iteration stays in ``box`` = (ta_lo, ta_hi, tb_lo, tb_hi) (clamped to
    [0, 1]), so a crossing seen on two polyline segments is not traded for another
    crossing of the same pieces nearby (e.g. their shared end)."""
    a_lo, a_hi = max(box[0], 0.0), min(box[1], 1.0)
    b_lo, b_hi = max(box[2], 0.0), min(box[3], 1.0)
    best = (ta, tb)
    fa = pc.evaluate(pa, ta)[0] - pc.evaluate(pb, tb)[0]
    best_err = np.hypot(*fa)
    for _ in range(iters):
        da = pc.derivative(pa, ta)[0]
        db = pc.derivative(pb, tb)[0]
        jac = np.column_stack([da, -db])
        det = np.linalg.det(jac)
        if abs(det) < 1e-300:
            break
        step = np.linalg.solve(jac, fa)
        ta, tb = ta - step[0], tb - step[1]
        if not (a_lo - 1e-9 <= ta <= a_hi + 1e-9 and b_lo - 1e-9 <= tb <= b_hi + 1e-9):
            break
        ta, tb = min(max(ta, a_lo), a_hi), min(max(tb, b_lo), b_hi)
        fa = pc.evaluate(pa, ta)[0] - pc.evaluate(pb, tb)[0]
        err = np.hypot(*fa)
        if err < best_err:
            best, best_err = (ta, tb), err
        if err < 1e-13:
            break
    return best, best_err


def _project(piece, point, t_guess, iters=10):
    """Parameter of the closest point of piece to point, by Newton from t_guess.

    Closed form for polynomial degree-1 pieces.
    """
    if len(piece) == 2 and piece[0, 2] == piece[1, 2]:
        a, b = pc.cartesian(piece)
        d = b - a
        dd = d @ d
        return float(np.clip((point - a) @ d / dd, 0.0, 1.0)) if dd > 0 else 0.0
    t = t_guess
    for _ in range(iters):
        d = pc.evaluate(piece, t)[0] - point
        d1 = pc.derivative(piece, t)[0]
        d2 = pc.second_derivative(piece, t)[0]
        g = d @ d1
        h = d1 @ d1 + d @ d2
        if abs(h) < 1e-300:
            break
        t = min(max(t - g / h, 0.0), 1.0)
    return t


# ------------------------------------------------------------- arrangement

def split_parameters(pieces, tol, scale, junction=0.0, folded_only=False):
    """Parameters where each piece must be cut: intersections and T-junctions.

    ``tol`` is the flattening tolerance of the search; an end point of one piece
    closer than ``junction`` (at least 1e-3 tol) to another piece's interior cuts
    it there (a T-junction).  ``folded_only``: only the fine search where two
    pieces leave a shared end side by side.  Returns a list (per piece) of lists
    of (t, point) with refined points.
    """
    cuts = [[] for _ in pieces]
    if not pieces:
        return cuts
    p0, p1, ids, t0, t1 = _flatten_all(pieces, tol)
    # each polyline is within tol of its piece, so two pieces that meet have
    # segments within 2 tol of each other there: boxes padded by tol find them all
    pairs = np.zeros((0, 2), np.int64) if folded_only else \
        _segment_pairs(np.minimum(p0, p1) - tol, np.maximum(p0, p1) + tol, ids, True)
    if len(pairs):
        # drop pairs of neighbouring segments of one piece (they share an end)
        same = ids[pairs[:, 0]] == ids[pairs[:, 1]]
        adjacent = same & (np.abs(pairs[:, 0] - pairs[:, 1]) <= 1)
        pairs = pairs[~adjacent]
    k, u, v, crossing = _candidates(p0, p1, pairs, 2.0 * tol)
    end_eps = 1e-9
    snap = scale * 1e-9
    seen = set()

    def record(a, b, roots, limit):
        """Cut pieces a and b at each new, non-trivial root with error <= limit."""
        for ra, rb, err in roots:
            key = (a, b, round(ra * 1e9), round(rb * 1e9))
            if err > limit or key in seen or _trivial(a, b, ra, rb, end_eps):
                continue
            seen.add(key)
            pt = 0.5 * (pc.evaluate(pieces[a], ra)[0] + pc.evaluate(pieces[b], rb)[0])
            for piece_id, t in ((a, ra), (b, rb)):
                if end_eps <= t <= 1 - end_eps:
                    cuts[piece_id].append((t, pt))

    for kk, uu, vv, cr in zip(k, u, v, crossing):
        i, j = pairs[kk]
        a, b = ids[i], ids[j]
        ta = t0[i] + uu * (t1[i] - t0[i])
        tb = t0[j] + vv * (t1[j] - t0[j])
        wa, wb = t1[i] - t0[i], t1[j] - t0[j]
        box = (t0[i] - wa, t1[i] + wa, t0[j] - wb, t1[j] + wb)
        (ra, rb), err = _newton(pieces[a], pieces[b], ta, tb, box=box)
        roots = [(ra, rb, err)]
        seen_at = p0[i] + uu * (p1[i] - p0[i])
        if _trivial(a, b, ra, rb, end_eps) and \
                np.hypot(*(pc.evaluate(pieces[a], ra)[0] - seen_at)) > 100 * snap:
            # Newton fell into the shared end (or the diagonal of a self-pair) from
            # a crossing seen elsewhere: search the box finely
            roots = _roots_in_box(pieces[a], pieces[b], box, tol)
        # a polyline crossing may be an exact near-touch within tol (cut and snap
        # both there); a near miss of the polylines counts only if Newton converges
        record(a, b, roots, max(tol, snap) if cr else max(10 * snap, 1e-6 * tol))
    # folded joints (cusps where one piece ends and another starts, rule 3): the
    # polylines only touch at the shared end, but the pieces may cross close by
    for a, b, box in _folded_joints(pieces, ids, t0, t1, p0, p1, snap):
        record(a, b, _roots_in_box(pieces[a], pieces[b], box, tol), max(10 * snap, 1e-6 * tol))
    if folded_only:
        return cuts
    # T-junctions: an end point of one piece lying on another piece's interior
    ends = np.array([[pc.start(p), pc.end(p)] for p in pieces]).reshape(-1, 2)
    seg_lo = np.minimum(p0, p1) - tol
    seg_hi = np.maximum(p0, p1) + tol
    near_end = 10 * snap
    for e_idx, q in enumerate(ends):
        owner = e_idx // 2
        inside = np.all((q >= seg_lo) & (q <= seg_hi), axis=1)
        cand = np.flatnonzero(inside & (ids != owner))
        if cand.size == 0:
            continue
        # a piece whose own end is at q meets q there: no cut needed
        pe = ends.reshape(-1, 2, 2)[ids[cand]]
        at_end = np.minimum(np.hypot(*(pe[:, 0] - q).T), np.hypot(*(pe[:, 1] - q).T)) <= near_end
        cand = cand[~at_end]
        if cand.size == 0:
            continue
        d = p1[cand] - p0[cand]
        ll = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        w = np.clip(np.einsum("ij,ij->i", q - p0[cand], d) / ll, 0, 1)
        dist = np.hypot(*(p0[cand] + w[:, None] * d - q).T)
        # closest segment per piece only
        order = np.lexsort((dist, ids[cand]))
        first = np.ones(len(order), bool)
        first[1:] = ids[cand][order][1:] != ids[cand][order][:-1]
        for c, ww, dd in zip(cand[order][first], w[order][first], dist[order][first]):
            if dd > tol:
                continue
            b = ids[c]
            tb = _project(pieces[b], q, t0[c] + ww * (t1[c] - t0[c]))
            if np.hypot(*(pc.evaluate(pieces[b], tb)[0] - q)) > max(snap * 10, tol * 1e-3, junction):
                continue
            if end_eps < tb < 1 - end_eps:
                cuts[b].append((tb, q.copy()))
    return cuts


def merge_coincident(pieces, tol):
    """Merge pieces that trace the same curve (either direction) into one.

    A self-sum A ⊕ A makes every piece twice (edge i with edge j, and j with i),
    with different parametrisations; intersecting a curve with its own copy is
    meaningless, so copies become one piece with a weight: the number of copies
    along it minus those against it.  Returns (pieces, weights).
    """
    ends = np.array([[pc.start(p), pc.end(p)] for p in pieces])
    keep, weights = [], []
    buckets = {}
    for k, p in enumerate(pieces):
        key = tuple(sorted([tuple(np.round(ends[k, 0] / (tol * 100))),
                            tuple(np.round(ends[k, 1] / (tol * 100)))]))
        found = None
        for j in buckets.get(key, ()):
            q = pieces[keep[j]]
            if _same_curve(p, q, tol):
                found = j
                break
        if found is None:
            buckets.setdefault(key, []).append(len(keep))
            keep.append(k)
            weights.append(1)
        else:
            along = np.hypot(*(ends[k, 0] - ends[keep[found], 0])) <= tol
            weights[found] += 1 if along else -1
    return [pieces[k] for k in keep], weights


def _same_curve(p, q, tol):
    """True if p's points at t = 1/4, 1/2, 3/4 lie on q within tol (ends checked by caller)."""
    sp, ep, sq, eq = pc.start(p), pc.end(p), pc.start(q), pc.end(q)
    if np.hypot(*(sp - sq)) <= tol and np.hypot(*(ep - eq)) <= tol:
        rev = False
    elif np.hypot(*(sp - eq)) <= tol and np.hypot(*(ep - sq)) <= tol:
        rev = True
    else:
        return False
    for t in (0.25, 0.5, 0.75):
        x = pc.evaluate(p, t)[0]
        u = _project(q, x, 1.0 - t if rev else t)
        if np.hypot(*(pc.evaluate(q, u)[0] - x)) > tol:
            return False
    return True


def cut_pieces(pieces, cuts):
    """Cut each piece at its parameters.

    Returns (sub-pieces with snapped end points, origin) where origin[k] is
    (source piece index, t0, t1) of sub-piece k.
    """
    out, origin = [], []
    for src, (p, cut) in enumerate(zip(pieces, cuts)):
        ts = [0.0]
        pts = [pc.start(p)]
        for t, q in sorted(cut, key=lambda c: c[0]):
            if t - ts[-1] < 1e-10:
                continue
            ts.append(t)
            pts.append(q)
        if len(ts) > 1 and 1.0 - ts[-1] < 1e-10:
            ts.pop()
            pts.pop()
        ts.append(1.0)
        pts.append(pc.end(p))
        for k in range(len(ts) - 1):
            sub = pc.subsegment(p, ts[k], ts[k + 1]) if len(ts) > 2 else p
            out.append(pc.with_endpoints(sub, pts[k], pts[k + 1]))
            origin.append((src, ts[k], ts[k + 1]))
    return out, origin


# -------------------------------------------------------------- membership

def _loops_polylines(region, tol):
    return [pc.flatten_loop(loop, tol) for loop in region]


def _winding(points, polylines):
    """Winding numbers of points with respect to closed polylines (vectorised)."""
    return _open_winding(points, [np.vstack([p, p[:1]]) for p in polylines])


class SegmentGrid:
    """Uniform-grid index of line segments for batched crossing queries."""

    def __init__(self, s0, s1):
        self.s0, self.s1 = s0, s1
        lo = np.minimum(s0, s1)
        hi = np.maximum(s0, s1)
        self.lo_all, self.hi_all = lo.min(axis=0), hi.max(axis=0)
        span = max(float((self.hi_all - self.lo_all).max()), 1e-300)
        seg_len = float(np.median(np.maximum(hi - lo, 0).max(axis=1))) if len(s0) else span
        self.h = max(2.0 * seg_len, span / 512.0)
        self.origin = self.lo_all
        keys, segs = self._cells(lo, hi)
        order = np.argsort(keys, kind="stable")
        keys, self.segs = keys[order], segs[order]
        self.ukeys, self.starts, counts = np.unique(keys, return_index=True, return_counts=True)
        self.counts = counts

    def _cells(self, lo, hi):
        c0 = np.floor((lo - self.origin) / self.h).astype(np.int64)
        c1 = np.floor((hi - self.origin) / self.h).astype(np.int64)
        nx = c1[:, 0] - c0[:, 0] + 1
        ny = c1[:, 1] - c0[:, 1] + 1
        cnt = nx * ny
        seg = np.repeat(np.arange(len(lo)), cnt)
        offs = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        cx = c0[seg, 0] + offs % nx[seg]
        cy = c0[seg, 1] + offs // nx[seg]
        return cx * 2_000_003 + cy, seg

    def any_crossing(self, q0, q1):
        """True if any query segment (q0[i], q1[i]) meets any indexed segment."""
        lo = np.minimum(q0, q1)
        hi = np.maximum(q0, q1)
        near = np.all((hi >= self.lo_all) & (lo <= self.hi_all), axis=1)
        if not near.any():
            return False
        q0, q1, lo, hi = q0[near], q1[near], lo[near], hi[near]
        keys, qseg = self._cells(lo, hi)
        pos = np.searchsorted(self.ukeys, keys)
        pos = np.minimum(pos, len(self.ukeys) - 1)
        found = self.ukeys[pos] == keys
        pos, qseg = pos[found], qseg[found]
        if pos.size == 0:
            return False
        cnt = self.counts[pos]
        qi = np.repeat(qseg, cnt)
        offs = np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
        si = self.segs[np.repeat(self.starts[pos], cnt) + offs]
        a0, a1 = self.s0[si], self.s1[si]
        b0, b1 = q0[qi], q1[qi]
        r = a1 - a0
        sv = b1 - b0
        qp = b0 - a0
        den = pc.cross2(r, sv)
        with np.errstate(divide="ignore", invalid="ignore"):
            u = pc.cross2(qp, sv) / den
            v = pc.cross2(qp, r) / den
        return bool(np.any((u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)))


class _Membership:
    """Exact set membership x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, on fine polylines.

    A ∩ (x − B) ≠ ∅ iff the boundaries cross, or a point of some loop of x − B is in
    A, or a point of some loop of A is in x − B (one point per loop: a component may
    meet the other set only through one of its hole loops).
    """

    def __init__(self, region_a, region_b, tol):
        self.pa = _loops_polylines(region_a, tol)
        self.pb = _loops_polylines(region_b, tol)
        sa0 = np.concatenate(self.pa)
        sa1 = np.concatenate([np.roll(p, -1, axis=0) for p in self.pa])
        self.sb0 = np.concatenate(self.pb)
        self.sb1 = np.concatenate([np.roll(p, -1, axis=0) for p in self.pb])
        self.a_pts = np.array([p[0] for p in self.pa])
        self.b_pts = np.array([p[0] for p in self.pb])
        self.grid = SegmentGrid(sa0, sa1)

    def __call__(self, points):
        points = np.atleast_2d(points)
        inside = np.zeros(len(points), bool)
        for b in self.b_pts:
            inside |= _winding(points - b, self.pa) != 0
        for a in self.a_pts:
            inside |= _winding(points - a, self.pb) != 0
        for k in np.flatnonzero(~inside):
            x = points[k]
            inside[k] = self.grid.any_crossing(x - self.sb0, x - self.sb1)
        return inside


# --------------------------------------------------------------- arrangement

def _cluster_points(points, tol):
    """Cluster ids of points closer than tol (grid hashing + union-find)."""
    n = len(points)
    parent = np.arange(n)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    cells = np.floor(points / tol).astype(np.int64)
    buckets = {}
    for i, (cx, cy) in enumerate(cells):
        for dx in (-1, 0, 1):
            for dy in (-1, 0, 1):
                for j in buckets.get((cx + dx, cy + dy), ()):
                    if np.hypot(*(points[i] - points[j])) <= tol:
                        ri, rj = find(i), find(j)
                        if ri != rj:
                            parent[ri] = rj
        buckets.setdefault((cx, cy), []).append(i)
    roots = np.array([find(i) for i in range(n)])
    _, ids = np.unique(roots, return_inverse=True)
    return ids


def _near_copy(p, q, mid_p, mid_q, dist):
    """True if p (whose ends are q's ends) runs within dist of q: its points at
    1/4, 1/2, 3/4 are that close to q (parametrisations may differ)."""
    if np.hypot(*(mid_p - mid_q)) <= dist:
        return True
    for t in (0.5, 0.25, 0.75):
        x = pc.evaluate(p, t)[0]
        u = _project(q, x, t)
        if np.hypot(*(pc.evaluate(q, u)[0] - x)) > dist:
            u = _project(q, x, 1.0 - t)
            if np.hypot(*(pc.evaluate(q, u)[0] - x)) > dist:
                return False
    return True


def _contract(node, subs, length):
    """Node ids with the two ends of every sub-piece shorter than ``length`` merged.

    Sub-pieces far below the tolerance (between nearly coincident crossings near
    cusps and thin nib ends) have no reliable direction or sides; contracting them
    moves the boundary by less than their length.
    """
    if length <= 0:
        return node
    _, node = np.unique(node, return_inverse=True)
    parent = np.arange(node.max() + 1)

    def find(i):
        while parent[i] != i:
            parent[i] = parent[parent[i]]
            i = parent[i]
        return i

    for k, p in enumerate(subs):
        if pc.length_bound(p) < length:
            ra, rb = find(node[2 * k]), find(node[2 * k + 1])
            parent[ra] = rb
    return np.unique([find(i) for i in node], return_inverse=True)[1]


class Arrangement:
    """Half-edge structure of oriented sub-pieces, faces and winding numbers (Sec. 6).

    Sub-piece k gives half-edges 2k (its own direction) and 2k+1 (reversed).  Faces
    lie to the left of their half-edges.  The winding number of the face left of a
    forward half-edge is one more than that of the face on its right; each connected
    component's outer face gets the winding number of the other components there.
    """

    def __init__(self, subs, node_tol, weights=None, contract=0.0):
        ends = np.array([[pc.start(p), pc.end(p)] for p in subs]).reshape(-1, 2)
        node = _contract(_cluster_points(ends, node_tol), subs, contract)
        # merge coincident sub-pieces (same end nodes, same middle) into one edge
        # whose weight is the sum of their orientations (+1 along, -1 against)
        mids = np.array([pc.evaluate(p, 0.5)[0] for p in subs])
        w0 = np.ones(len(subs), int) if weights is None else np.asarray(weights, int)
        keep, weight, groups = [], [], {}
        for k in range(len(subs)):
            u, v = node[2 * k], node[2 * k + 1]
            if u == v and pc.length_bound(subs[k]) <= max(1e3 * node_tol, 10 * contract):
                # a closed sub-piece shorter than 10 contract encloses less than a
                # disk of diameter 5 contract: a loop below the tolerance
                continue  # a zero-length piece (tiny arc) would be a self-loop
            key = (min(u, v), max(u, v))
            found = None
            for j in groups.get(key, ()):
                if _near_copy(subs[k], subs[keep[j]], mids[k], mids[keep[j]],
                              max(10 * node_tol, contract)):
                    found = j
                    break
            if found is None:
                groups.setdefault(key, []).append(len(keep))
                keep.append(k)
                weight.append(w0[k])
            else:
                same = node[2 * keep[found]] == u
                weight[found] += w0[k] if same else -w0[k]
        keep = np.array(keep)
        self.weight = np.array(weight)
        self.kept = keep
        subs = [subs[k] for k in keep]
        node = node.reshape(-1, 2)[keep].reshape(-1)
        self.subs = subs
        m = len(subs)
        ends = ends.reshape(-1, 2, 2)[keep].reshape(-1, 2)
        self.node_of = node  # half-edge h starts at node_of[h]: 2k -> start, 2k+1 -> end
        self.nodes = np.zeros((node.max() + 1, 2))
        self.nodes[node] = ends
        # direction keys of every half-edge leaving its node
        t0, t1, k0, k1 = _end_geometry(subs)
        dirs = np.empty((2 * m, 2))
        dirs[0::2] = t0
        dirs[1::2] = -t1
        curv = np.empty(2 * m)
        curv[0::2] = k0
        curv[1::2] = -k1
        ang = np.arctan2(dirs[:, 1], dirs[:, 0])
        self.angle = ang
        # sort outgoing half-edges around each node counter-clockwise
        order = np.lexsort((curv, np.round(ang, 11), node))
        self.ccw_next = np.empty(2 * m, int)
        self.ccw_prev = np.empty(2 * m, int)
        bounds = np.flatnonzero(np.diff(node[order])) + 1
        for grp in np.split(order, bounds):
            self.ccw_next[grp] = np.roll(grp, -1)
            self.ccw_prev[grp] = np.roll(grp, 1)
        self.twin = np.arange(2 * m) ^ 1
        # face traversal: next(h) = clockwise neighbour of twin(h) at h's end node
        self.next = self.ccw_prev[self.twin]
        self.face = -np.ones(2 * m, int)
        faces = []
        for h in range(2 * m):
            if self.face[h] >= 0:
                continue
            cyc = []
            g = h
            while self.face[g] < 0:
                self.face[g] = len(faces)
                cyc.append(g)
                g = self.next[g]
            faces.append(cyc)
        self.faces = faces
        # area term of each sub-piece once; the reversed half-edge contributes minus it
        term = np.array([pc.piece_area_term(p, 8) for p in subs])
        sign_term = np.empty(2 * m)
        sign_term[0::2] = term
        sign_term[1::2] = -term
        self.face_area = np.array([sign_term[c].sum() for c in faces])

    def half_piece(self, h):
        p = self.subs[h >> 1]
        return p if h % 2 == 0 else pc.reverse(p)

    def _area(self, cyc):
        return sum(pc.piece_area_term(self.half_piece(h), 8) for h in cyc)

    def sample_point(self, hs, depth, flat_tol):
        """A point left of half-edges hs (of one face), as deep as ``depth`` from
        every edge if possible.

        Candidates lie left of the longest four of hs at 1/4, 1/2, 3/4, at
        distances 4, 2, 1.5, 1, 1/2, 1/4, 1/16 x depth; the first whose distance to
        all sub-pieces' polylines (within flat_tol) is at least 0.9 x its offset is
        taken.  A probe deeper than the convolution's error is on the same side of
        the exact boundary as of ours.
        """
        if getattr(self, "_segs", None) is None or self._segs[0] != flat_tol:
            polys = [q for q, _ in pc.flatten_many(self.subs, flat_tol)]
            self._segs = (flat_tol, np.concatenate([q[:-1] for q in polys]),
                          np.concatenate([q[1:] for q in polys]))
        _, a, b = self._segs
        hs = sorted(hs, key=lambda h: -pc.length_bound(self.subs[h >> 1]))[:4]
        fallback = None
        for scale in (4.0, 2.0, 1.5, 1.0, 0.5, 0.25, 0.0625):
            off = scale * depth
            for h in hs:
                p = self.half_piece(h)
                off_h = min(off, 0.25 * pc.length_bound(p))
                for t in (0.5, 0.25, 0.75):
                    x = pc.evaluate(p, t)[0]
                    d = pc.derivative(p, t)[0]
                    x = x + off_h * np.array([-d[1], d[0]]) / max(np.hypot(*d), 1e-300)
                    if fallback is None:
                        fallback = x
                    if off_h == off and _point_segment_dist(x, a, b).min() >= 0.9 * off:
                        return x
        return fallback

    def _balanced(self, is_b, tiny):
        """Boundary flags with every node entered as often as left.

        Near-coincident sub-pieces (slivers far thinner than the tolerance) can be
        classified inconsistently.  A half-edge shorter than ``tiny`` from a node
        left too often to a node entered too often is dropped from the boundary
        (one of two near-coincident paths), one from a node entered too often to a
        node left too often is added; then boundary half-edges shorter than
        5 tiny that no loop can pass (nothing arrives at their start or leaves
        their end) are pruned.
        """
        is_b = is_b.copy()
        tail = self.node_of
        head = self.node_of[self.twin]
        excess = np.zeros(len(self.nodes), int)       # out - in
        np.add.at(excess, tail[is_b], 1)
        np.add.at(excess, head[is_b], -1)
        if not excess.any():
            return is_b
        short = np.array([pc.length_bound(p) <= tiny for p in self.subs]).repeat(2)
        for _ in range(4 * int(np.abs(excess).sum())):
            fix = np.flatnonzero(short & (
                (is_b & (excess[tail] > 0) & (excess[head] < 0))
                | (~is_b & ~is_b[self.twin] & (excess[tail] < 0) & (excess[head] > 0))))
            if not len(fix):
                break
            h = fix[0]
            step = -1 if is_b[h] else 1
            is_b[h] = not is_b[h]
            excess[tail[h]] += step
            excess[head[h]] -= step
        # two near-coincident paths of several short sub-pieces: drop the path of
        # short boundary half-edges from a node left too often to one entered too often
        for u in np.flatnonzero(excess > 0):
            while excess[u] > 0:
                path = self._short_path(u, is_b & short, excess < 0)
                if path is None:
                    break
                is_b[path] = False
                excess[u] -= 1
                excess[head[path[-1]]] += 1
        # a short boundary half-edge that starts where no boundary arrives or ends
        # where none leaves cannot be on any loop (a sliver's side): prune it
        short = np.array([pc.length_bound(p) <= 5 * tiny for p in self.subs]).repeat(2)
        while True:
            n_in = np.bincount(head[is_b], minlength=len(self.nodes))
            n_out = np.bincount(tail[is_b], minlength=len(self.nodes))
            dead = is_b & short & ((n_in[tail] == 0) | (n_out[head] == 0))
            if not dead.any():
                return is_b
            is_b &= ~dead

    def _short_path(self, u, allowed, goal, max_edges=8):
        """Half-edges of a shortest path (breadth first, at most max_edges) from
        node u along allowed half-edges to a node where goal holds, or None."""
        came = {u: None}
        frontier = [u]
        out_of = {}
        for h in np.flatnonzero(allowed):
            out_of.setdefault(self.node_of[h], []).append(h)
        for _ in range(max_edges):
            nxt = []
            for v in frontier:
                for h in out_of.get(v, ()):
                    x = self.node_of[self.twin[h]]
                    if x in came:
                        continue
                    came[x] = h
                    if goal[x]:
                        path = []
                        while x != u:
                            path.append(came[x])
                            x = self.node_of[came[x]]
                        return path[::-1]
                    nxt.append(x)
            frontier = nxt
        return None

    def boundary_loops(self, inside, tiny=0.0):
        """Closed loops of half-edges with the sum on their left and not on their right.

        ``inside[h]`` says whether the side left of half-edge h is in the sum;
        ``tiny`` is the length below which inconsistent classification is repaired
        (:meth:`_balanced`).
        """
        m2 = len(self.face)
        is_b = self._balanced(inside & ~inside[self.twin], tiny)
        used = np.zeros(m2, bool)
        loops = []
        for h0 in np.flatnonzero(is_b):
            if used[h0]:
                continue
            loop = []
            h = h0
            while True:
                used[h] = True
                loop.append(h)
                # next: the first unused boundary half-edge clockwise from h's twin
                # around the end node (h0 itself closes the loop)
                g = self.ccw_prev[self.twin[h]]
                for _ in range(m2):
                    if is_b[g] and (not used[g] or g == h0):
                        break
                    g = self.ccw_prev[g]
                else:
                    raise TopologyError("boundary does not close at %s"
                                        % (self.nodes[self.node_of[self.twin[h]]],))
                if g == h0:
                    break
                h = g
            loops.append(loop)
        return loops


def side_windings(arr, flat_tol, delta):
    """Winding number of the convolution just left of every half-edge (Sec. 6).

    For each sub-piece, the points mid ± delta·normal at its middle are tested
    against polylines of all sub-pieces (within ``flat_tol``, the middle a vertex of
    its own polyline, ends snapped to their nodes), weighted by the number of
    coincident copies.  Returns an array indexed by half-edge (2k: left of sub-piece
    k, 2k + 1: its right).
    """
    polys, mids, normals = [], [], []
    halves = [h for p in arr.subs for h in pc.split(p, 0.5)]
    flat = pc.flatten_many(halves, flat_tol)
    for k, p in enumerate(arr.subs):
        pl, pr = flat[2 * k][0], flat[2 * k + 1][0]
        pl[0] = arr.nodes[arr.node_of[2 * k]]
        pr[-1] = arr.nodes[arr.node_of[2 * k + 1]]
        pr[0] = pl[-1]
        polys.append(np.vstack([pl, pr[1:]]))
        d = pc.derivative(p, 0.5)[0]
        mids.append(pl[-1])
        normals.append(np.array([-d[1], d[0]]) / max(np.hypot(*d), 1e-300))
    mids, normals = np.array(mids), np.array(normals)
    seg_w = np.concatenate([np.full(len(q) - 1, wt) for q, wt in zip(polys, arr.weight)])
    a = np.concatenate([q[:-1] for q in polys])
    b = np.concatenate([q[1:] for q in polys])
    pts = np.empty((2 * len(mids), 2))
    pts[0::2] = mids + delta * normals
    pts[1::2] = mids - delta * normals
    return ray_winding(pts, a, b, seg_w)


def ray_winding(points, a, b, weight, strips=256):
    """Weighted winding numbers of points w.r.t. segments a -> b whose union closes.

    Crossing rule on the ray to +x (half-open in y, so a ray through a shared vertex
    counts once).  Segments are bucketed into horizontal strips, so each point only
    meets the segments that span its height.
    """
    out = np.zeros(len(points), np.int64)
    if not len(points) or not len(a):
        return out
    ylo = np.minimum(a[:, 1], b[:, 1])
    yhi = np.maximum(a[:, 1], b[:, 1])
    y0, y1 = float(ylo.min()), float(yhi.max())
    h = max((y1 - y0) / strips, 1e-300)
    s_lo = np.clip(((ylo - y0) / h).astype(np.int64), 0, strips - 1)
    s_hi = np.clip(((yhi - y0) / h).astype(np.int64), 0, strips - 1)
    p_s = np.clip(np.floor((points[:, 1] - y0) / h).astype(np.int64), -1, strips)
    for s in np.unique(p_s):
        if s < 0 or s >= strips:
            continue
        pi = np.flatnonzero(p_s == s)
        si = np.flatnonzero((s_lo <= s) & (s_hi >= s))
        if not len(si):
            continue
        px, py = points[pi, 0:1], points[pi, 1:2]
        ax, ay, bx, by = a[si, 0], a[si, 1], b[si, 0], b[si, 1]
        cr = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
        up = (ay <= py) & (by > py) & (cr > 0)
        down = (ay > py) & (by <= py) & (cr < 0)
        out[pi] = (up.astype(np.int64) - down) @ weight[si].astype(np.int64)
    return out


def _end_geometry(subs):
    """End derivatives and signed curvatures of all pieces from their control points:
    P'(0) = n w1/w0 (p1 - p0), kappa(0) = (n-1)/n w0 w2/w1^2 cross(p1-p0, p2-p1)/|p1-p0|^3
    (and mirrored at t = 1); falls back to evaluation where p1 = p0 (degenerate ends)."""
    m = len(subs)
    t0, t1 = np.empty((m, 2)), np.empty((m, 2))
    k0, k1 = np.zeros(m), np.zeros(m)
    for k, p in enumerate(subs):
        n = len(p) - 1
        w = p[:, 2]
        c = p[:, :2] / w[:, None]
        for end, (i0, i1, i2, tt, td, kk, sgn) in enumerate(
                ((0, 1, 2, 0.0, t0, k0, 1.0), (n, n - 1, n - 2, 1.0, t1, k1, -1.0))):
            d = c[i1] - c[i0]
            ln = np.hypot(*d)
            if ln <= 1e-12 * (1.0 + np.abs(c).max()):
                td[k] = pc.derivative(p, tt)[0]
                kk[k] = _signed_curvature(p, tt)
                continue
            td[k] = sgn * n * w[i1] / w[i0] * d
            if n >= 2:
                e = c[i2] - c[i1]
                # at t = 1 the formula walks (p_n, p_{n-1}, p_{n-2}) backwards, which
                # flips the sign of the curvature
                kk[k] = sgn * ((n - 1) / n * w[i0] * w[i2] / w[i1] ** 2
                         * float(pc.cross2(d, e)) / ln ** 3)
    return t0, t1, k0, k1


def _signed_curvature(p, t):
    d1 = pc.derivative(p, t)[0]
    d2 = pc.second_derivative(p, t)[0]
    sp = np.hypot(*d1)
    if sp == 0:
        return 0.0
    return float(pc.cross2(d1, d2) / sp ** 3)


def _open_winding(points, polylines):
    """Winding numbers of points w.r.t. a set of open polylines that together close."""
    w = np.zeros(len(points), int)
    if not polylines:
        return w
    a = np.concatenate([p[:-1] for p in polylines])
    b = np.concatenate([p[1:] for p in polylines])
    px = points[:, 0:1]
    py = points[:, 1:2]
    ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
    cr = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
    up = (ay <= py) & (by > py) & (cr > 0)
    down = (ay > py) & (by <= py) & (cr < 0)
    return w + up.sum(axis=1) - down.sum(axis=1)


# ------------------------------------------------------------------ driver

def minkowski_sum(region_a, region_b, tol, method="qac", return_debug=False):
    """Boundary of A ⊕ B as a region of rational Bézier pieces (Secs. 3-6).

    Each output piece lies within ``tol`` of the exact boundary: it is a sub-piece
    of a convolution piece whose a-priori bound (Eqs. 39-40) is <= 0.9 tol, cut at
    intersections refined by Newton iteration; sub-pieces shorter than 0.1 tol
    (between near-coincident crossings) are contracted to a point, which moves
    the ends of their neighbours by less than that.  tol is absolute, in input units.
    Outer loops are counter-clockwise, holes clockwise.

    Faces of the arrangement of all convolution pieces get winding numbers by
    propagation; a face with w > 0 is in the sum, and a bounded face with w <= 0 is
    tested exactly (x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅), which closes holes of one operand
    smaller than the other (the weak spot of winding numbers, Sec. 6).  ``method``
    names the convolution method of Sec. 4 (:data:`morph.methods.METHODS`; only
    "qac" keeps the a-priori bound and exact normals).  Raises
    TopologyError if the boundary cannot be assembled into closed loops.
    """
    if tol <= 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    if not region_a or not region_b:
        raise ValueError("both regions must have at least one loop")
    # 0.9 tol for the convolution, 0.1 tol for snapping the arrangement's nodes
    conv = convolution(region_a, region_b, 0.9 * tol, keep_type3=True, method=method)
    pieces = [c.piece for c in conv]
    scale = _scale(pieces)
    pieces, weights = merge_coincident(pieces, scale * 1e-8)
    arr, origin, w = _arrange(pieces, weights, min(tol, scale * 1e-4), scale, 0.1 * tol)
    inside = w > 0
    # a side with w <= 0 next to an inside side may still be in the sum (a hole of
    # one operand smaller than the other): decide it exactly, once per face
    unbounded = int(np.argmin(arr.face_area))
    doubt = np.flatnonzero(~inside & inside[arr.twin] & (arr.face != unbounded))
    if len(doubt):
        # one probe per face whose half-edges agree on the winding number; one per
        # half-edge in a face that mixes windings (near-tangent pieces can make the
        # angular order, and so the face traversal, inconsistent)
        groups = []
        for f in np.unique(arr.face[doubt]):
            hs = doubt[arr.face[doubt] == f]
            if len(np.unique(w[arr.faces[f]])) == 1:
                groups.append(hs)
            else:
                groups.extend([h] for h in hs)
        member = _Membership(region_a, region_b, scale * 2e-6)
        pts = np.array([arr.sample_point(g, tol, min(0.1 * tol, scale * 1e-4)) for g in groups])
        for g, closed in zip(groups, member(pts)):
            inside[g] = closed
    loops = [_assemble(arr, loop, origin, pieces)
             for loop in arr.boundary_loops(inside, 2 * tol)]
    loops = _drop_slivers(loops, tol)
    if return_debug:
        return loops, {"convolution": conv, "arrangement": arr, "winding": w, "inside": inside}
    return loops


def fill_region(loops, fill_rule="nonzero"):
    """The region filled by closed loops that may cross themselves and each other.

    SVG and font fill semantics: a point is filled when the winding number of all
    loops there is nonzero (``"nonzero"``) or odd (``"evenodd"``).  The loops are
    cut at their intersections (refined on the exact pieces) and the filled set's
    boundary is assembled from the sub-pieces, which stay rational Béziers: outer
    loops counter-clockwise, holes clockwise.
    """
    pieces = [np.asarray(p, float) for loop in loops for p in loop]
    if not pieces:
        return []
    scale = _scale(pieces)
    arr, origin, w = _arrange(pieces, [1] * len(pieces), scale * 1e-4, scale, 0.0)
    inside = (w != 0) if fill_rule == "nonzero" else (w % 2 == 1)
    return [_assemble(arr, loop, origin, pieces) for loop in arr.boundary_loops(inside)]


def _scale(pieces):
    pts = np.concatenate([pc.cartesian(p) for p in pieces])
    return max(float(np.ptp(pts, axis=0).max()), 1e-300)


def _arrange(pieces, weights, flat_tol, scale, contract):
    """Pieces cut at their crossings, their arrangement, and side winding numbers.

    Returns (arrangement, origin of each kept sub-piece, winding left of each
    half-edge).  Winding numbers are sampled on each side of each sub-piece
    directly, not propagated across faces (which near-tangent pieces can make
    inconsistent); sub-pieces shorter than ``contract`` are contracted.
    """
    cuts = split_parameters(pieces, flat_tol, scale, junction=contract)
    subs, origin = cut_pieces(pieces, cuts)
    # a second pass on the sub-pieces finds crossings close to the new nodes (two
    # sub-pieces leaving a node side by side and crossing just after it)
    cuts = split_parameters(subs, flat_tol, scale, junction=contract, folded_only=True)
    if any(cuts):
        subs, second = cut_pieces(subs, cuts)
        origin = [(origin[k][0], origin[k][1] + (origin[k][2] - origin[k][1]) * u0,
                   origin[k][1] + (origin[k][2] - origin[k][1]) * u1) for k, u0, u1 in second]
    sub_w = [weights[src] for src, _, _ in origin]
    arr = Arrangement(subs, scale * 1e-9, sub_w, contract=contract)
    origin = [origin[k] for k in arr.kept]
    # polylines fine enough to resolve slivers of sub-pieces just above `contract`
    fine = min(flat_tol, scale * 1e-6, 0.01 * contract if contract > 0 else np.inf)
    w = side_windings(arr, fine, min(scale * 1e-8, 0.5 * fine))
    return arr, origin, w


def _drop_slivers(loops, tol):
    """Loops thinner than tol on average (area < tol * perimeter / 2) that are also
    tiny or lie within tol of the other loops: slivers between nearly coincident
    convolution pieces.  Dropping them moves the boundary by less than tol."""
    polys = [pc.flatten_loop(l, tol / 4) for l in loops]
    keep = []
    for k, (loop, poly) in enumerate(zip(loops, polys)):
        perimeter = sum(pc.length_bound(p) for p in loop)
        if abs(pc.loop_area(loop)) > 0.5 * tol * perimeter:
            keep.append(loop)
            continue
        if float(np.ptp(poly, axis=0).max()) <= tol:
            continue
        others = [q for j, q in enumerate(polys) if j != k and len(q) >= 2]
        if others:
            a = np.concatenate(others)
            b = np.concatenate([np.roll(q, -1, axis=0) for q in others])
            far = max(np.min(_point_segment_dist(x, a, b)) for x in poly)
            if far <= tol:
                continue
        keep.append(loop)
    return keep


def _point_segment_dist(x, a, b):
    d = b - a
    ll = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
    u = np.clip(np.einsum("ij,ij->i", x - a, d) / ll, 0.0, 1.0)
    return np.hypot(*(a + u[:, None] * d - x).T)


def _assemble(arr, loop, origin, pieces):
    """Pieces of one boundary loop, merging consecutive runs of one source piece."""
    out = []
    run = None  # (source index, t_start, t_end, forward)
    for h in loop:
        src, ta, tb = origin[h >> 1]
        if h % 2:
            ta, tb = tb, ta
        if run is not None and run[0] == src and abs(run[2] - ta) < 1e-12:
            run = (src, run[1], tb)
        else:
            if run is not None:
                out.append(run)
            run = (src, ta, tb)
    if run is not None:
        if out and out[0][0] == run[0] and abs(run[2] - out[0][1]) < 1e-12 and len(out) > 0:
            first = out.pop(0)
            run = (run[0], run[1], first[2])
        out.append(run)
    result = []
    for src, ta, tb in out:
        result.append(pc.subsegment(pieces[src], ta, tb))
    return snap_loop(result)

"""Trimming convolution curves to the Minkowski sum boundary (Secs. 3.3.1 and 6).

Pipeline, all on the rational pieces (polylines are used only to find where to look):

1. Convolution pieces of types 1 and 2 (type 3 never reaches the boundary, rules
   1-2); see :mod:`morph.convolve`.
2. Intersections: every pair of pieces (and every piece with itself, which finds the
   local self-intersection loops of rule 3 near cusps) is intersected on flattened
   polylines; each crossing is refined by Newton iteration on the exact rational
   pieces (the paper's way, Fig. 33).  End points of one piece lying on another
   (T-junctions, overlapping collinear pieces) are projected onto it.
3. Pieces are cut at those parameters and stay rational Béziers.
4. Each sub-piece is classified by membership of two points just left and right of
   its middle: it belongs to the boundary iff exactly one side lies in A ⊕ B.
   Membership is decided exactly as x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ (not by winding
   numbers, which misclassify holes smaller than the other operand, Sec. 6), on
   polylines within ``membership_tol`` of the input boundaries.
5. Boundary sub-pieces are oriented with the sum on their left, duplicates of
   coincident pieces removed, and chained into loops: outer loops counter-clockwise,
   holes clockwise.
"""

import numpy as np

from . import piece as pc
from .convolve import chain, convolution
from .errors import TopologyError


# -------------------------------------------------------------- polylines

def _flatten_all(pieces, tol):
    """Segments of all pieces: arrays p0 (N,2), p1 (N,2), piece id, t0, t1."""
    p0s, p1s, ids, t0s, t1s = [], [], [], [], []
    for k, p in enumerate(pieces):
        pts, ts = pc.flatten(p, tol)
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
    bounds = np.flatnonzero(np.diff(key)) + 1
    starts = np.concatenate([[0], bounds])
    ends = np.concatenate([bounds, [len(key)]])
    pairs = []
    for s, e in zip(starts, ends):
        if e - s < 2:
            continue
        members = seg[s:e]
        a, b = np.triu_indices(len(members), 1)
        pairs.append(np.stack([members[a], members[b]], axis=1))
    if not pairs:
        return np.zeros((0, 2), np.int64)
    pairs = np.concatenate(pairs)
    pairs = np.sort(pairs, axis=1)
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


def _newton(pa, pb, ta, tb, iters=12):
    """Refine P_a(ta) = P_b(tb) by Newton iteration on the exact pieces (Fig. 33)."""
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
        if not (-1e-9 <= ta <= 1 + 1e-9 and -1e-9 <= tb <= 1 + 1e-9):
            break
        ta, tb = min(max(ta, 0.0), 1.0), min(max(tb, 0.0), 1.0)
        fa = pc.evaluate(pa, ta)[0] - pc.evaluate(pb, tb)[0]
        err = np.hypot(*fa)
        if err < best_err:
            best, best_err = (ta, tb), err
        if err < 1e-13:
            break
    return best, best_err


def _project(piece, point, t_guess, iters=10):
    """Parameter of the closest point of piece to point, by Newton from t_guess."""
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

def split_parameters(pieces, tol, scale):
    """Parameters where each piece must be cut: intersections and T-junctions.

    Returns a list (per piece) of lists of (t, point) with refined points.
    """
    cuts = [[] for _ in pieces]
    if not pieces:
        return cuts
    p0, p1, ids, t0, t1 = _flatten_all(pieces, tol)
    pairs = _segment_pairs(p0, p1, ids, True)
    if len(pairs):
        # drop pairs of neighbouring segments of one piece (they share an end)
        same = ids[pairs[:, 0]] == ids[pairs[:, 1]]
        adjacent = same & (np.abs(pairs[:, 0] - pairs[:, 1]) <= 1)
        pairs = pairs[~adjacent]
    k, u, v = _crossings(p0, p1, pairs) if len(pairs) else ([], [], [])
    end_eps = 1e-9
    snap = scale * 1e-9
    for kk, uu, vv in zip(k, u, v):
        i, j = pairs[kk]
        a, b = ids[i], ids[j]
        ta = t0[i] + uu * (t1[i] - t0[i])
        tb = t0[j] + vv * (t1[j] - t0[j])
        (ta, tb), err = _newton(pieces[a], pieces[b], ta, tb)
        if err > max(tol, snap):
            continue  # polyline artefact: the exact curves do not meet here
        pt = 0.5 * (pc.evaluate(pieces[a], ta)[0] + pc.evaluate(pieces[b], tb)[0])
        a_end = ta < end_eps or ta > 1 - end_eps
        b_end = tb < end_eps or tb > 1 - end_eps
        if a_end and b_end:
            if a != b:
                # ends meeting ends: already joints, but record for snapping
                pass
            continue
        if a == b and abs(ta - tb) < 1e-7:
            continue
        if not a_end:
            cuts[a].append((ta, pt))
        if not b_end:
            cuts[b].append((tb, pt))
    # T-junctions: an end point of one piece lying on another piece's interior
    ends = np.array([[pc.start(p), pc.end(p)] for p in pieces]).reshape(-1, 2)
    seg_lo = np.minimum(p0, p1) - tol
    seg_hi = np.maximum(p0, p1) + tol
    for e_idx, q in enumerate(ends):
        owner = e_idx // 2
        inside = np.all((q >= seg_lo) & (q <= seg_hi), axis=1)
        cand = np.flatnonzero(inside & (ids != owner))
        if cand.size == 0:
            continue
        d = p1[cand] - p0[cand]
        ll = np.maximum(np.einsum("ij,ij->i", d, d), 1e-300)
        w = np.clip(np.einsum("ij,ij->i", q - p0[cand], d) / ll, 0, 1)
        dist = np.hypot(*(p0[cand] + w[:, None] * d - q).T)
        for c, ww, dd in zip(cand, w, dist):
            if dd > tol:
                continue
            b = ids[c]
            tb = _project(pieces[b], q, t0[c] + ww * (t1[c] - t0[c]))
            if np.hypot(*(pc.evaluate(pieces[b], tb)[0] - q)) > max(snap * 10, tol * 1e-3):
                continue
            if end_eps < tb < 1 - end_eps:
                cuts[b].append((tb, q.copy()))
    return cuts


def cut_pieces(pieces, cuts, min_len):
    """Cut each piece at its parameters; returns sub-pieces with snapped end points."""
    out = []
    for p, cut in zip(pieces, cuts):
        if not cut:
            out.append(p)
            continue
        cut = sorted(cut, key=lambda c: c[0])
        ts = [0.0]
        pts = [pc.start(p)]
        for t, q in cut:
            if t - ts[-1] < 1e-10:
                continue
            ts.append(t)
            pts.append(q)
        if 1.0 - ts[-1] < 1e-10:
            ts.pop()
            pts.pop()
        ts.append(1.0)
        pts.append(pc.end(p))
        for k in range(len(ts) - 1):
            sub = pc.subsegment(p, ts[k], ts[k + 1])
            sub = pc.with_endpoints(sub, pts[k], pts[k + 1])
            if pc.length_bound(sub) < min_len:
                continue
            out.append(sub)
    return out


# -------------------------------------------------------------- membership

def _loops_polylines(region, tol):
    return [pc.flatten_loop(loop, tol) for loop in region]


def _winding(points, polylines):
    """Winding numbers of points with respect to closed polylines (vectorised)."""
    w = np.zeros(len(points), int)
    for poly in polylines:
        a = poly
        b = np.roll(poly, -1, axis=0)
        px = points[:, 0:1]
        py = points[:, 1:2]
        ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
        cr = (bx - ax) * (py - ay) - (px - ax) * (by - ay)
        up = (ay <= py) & (by > py) & (cr > 0)
        down = (ay > py) & (by <= py) & (cr < 0)
        w += up.sum(axis=1) - down.sum(axis=1)
    return w


class _Membership:
    """Exact set membership x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅, on fine polylines.

    A ∩ (x − B) ≠ ∅ iff the boundaries cross, or a point of a component of x − B is
    in A, or a point of a component of A is in x − B.  One point per outer loop
    stands for its component.
    """

    def __init__(self, region_a, region_b, tol):
        self.pa = _loops_polylines(region_a, tol)
        self.pb = _loops_polylines(region_b, tol)
        self.sa0 = np.concatenate(self.pa)
        self.sa1 = np.concatenate([np.roll(p, -1, axis=0) for p in self.pa])
        self.sb0 = np.concatenate(self.pb)
        self.sb1 = np.concatenate([np.roll(p, -1, axis=0) for p in self.pb])
        self.a_pts = np.array([p[0] for p, l in zip(self.pa, region_a) if pc.loop_area(l) > 0])
        self.b_pts = np.array([p[0] for p, l in zip(self.pb, region_b) if pc.loop_area(l) > 0])
        self.a_lo = np.minimum(self.sa0, self.sa1)
        self.a_hi = np.maximum(self.sa0, self.sa1)
        self.b_lo = np.minimum(self.sb0, self.sb1)
        self.b_hi = np.maximum(self.sb0, self.sb1)
        self.bbox_b = (self.b_lo.min(axis=0), self.b_hi.max(axis=0))

    def __call__(self, points):
        points = np.atleast_2d(points)
        inside = np.zeros(len(points), bool)
        for b in self.b_pts:
            inside |= _winding(points - b, self.pa) != 0
        for a in self.a_pts:
            inside |= _winding(points - a, self.pb) != 0
        for k in np.flatnonzero(~inside):
            inside[k] = self._boundaries_cross(points[k])
        return inside

    def _boundaries_cross(self, x):
        # x - B: segments x - sb; bbox [x - bmax, x - bmin]
        bmin, bmax = self.bbox_b
        lo, hi = x - bmax, x - bmin
        sel_a = np.flatnonzero(np.all((self.a_hi >= lo) & (self.a_lo <= hi), axis=1))
        if sel_a.size == 0:
            return False
        alo, ahi = self.a_lo[sel_a].min(axis=0), self.a_hi[sel_a].max(axis=0)
        # segments of x - B within A's selected bbox: x - b in [alo, ahi] <=> b in [x-ahi, x-alo]
        sel_b = np.flatnonzero(np.all((self.b_hi >= x - ahi) & (self.b_lo <= x - alo), axis=1))
        if sel_b.size == 0:
            return False
        a0, a1 = self.sa0[sel_a], self.sa1[sel_a]
        b0, b1 = x - self.sb0[sel_b], x - self.sb1[sel_b]
        chunk = max(1, 4_000_000 // max(len(sel_b), 1))
        for s in range(0, len(a0), chunk):
            r = (a1[s:s + chunk] - a0[s:s + chunk])[:, None, :]
            sv = (b1 - b0)[None, :, :]
            qp = b0[None, :, :] - a0[s:s + chunk][:, None, :]
            den = pc.cross2(r, sv)
            with np.errstate(divide="ignore", invalid="ignore"):
                u = pc.cross2(qp, sv) / den
                v = pc.cross2(qp, r) / den
            if np.any((u >= 0) & (u <= 1) & (v >= 0) & (v <= 1)):
                return True
        return False


# ------------------------------------------------------------------ driver

def classify(subpieces, member, eps):
    """For each sub-piece: +1 keep as is, -1 keep reversed, 0 drop (Sec. 6)."""
    if not subpieces:
        return np.zeros(0, int)
    mids = np.array([pc.evaluate(p, 0.5)[0] for p in subpieces])
    tans = np.array([pc.derivative(p, 0.5)[0] for p in subpieces])
    norm = np.hypot(tans[:, 0], tans[:, 1])
    bad = norm == 0
    norm[bad] = 1.0
    left = np.column_stack([-tans[:, 1], tans[:, 0]]) / norm[:, None]
    lens = np.array([pc.length_bound(p) for p in subpieces])
    e = np.minimum(eps, 0.25 * lens)[:, None]
    pts = np.concatenate([mids + e * left, mids - e * left])
    ins = member(pts)
    n = len(subpieces)
    lin, rin = ins[:n], ins[n:]
    out = np.where(lin & ~rin, 1, np.where(rin & ~lin, -1, 0))
    out[bad] = 0
    return out


def _dedupe(pieces, tol):
    keep = []
    sigs = []
    for p in pieces:
        sig = np.concatenate([pc.start(p), pc.evaluate(p, 0.5)[0], pc.end(p)])
        if any(np.max(np.abs(sig - s)) < tol for s in sigs):
            continue
        sigs.append(sig)
        keep.append(p)
    return keep


def minkowski_sum(region_a, region_b, tol, return_debug=False):
    """Boundary of A ⊕ B as a region of rational Bézier pieces (Secs. 3-6).

    Each output piece lies within ``tol`` of the exact boundary: it is a sub-piece
    of a convolution piece whose a-priori bound (Eqs. 39-40) is <= tol, cut at
    intersections refined by Newton iteration to ~1e-12.  tol is absolute, in input
    units.  Outer loops are counter-clockwise, holes clockwise.  Raises
    TopologyError if the boundary pieces cannot be chained into closed loops.
    """
    if tol <= 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    if not region_a or not region_b:
        raise ValueError("both regions must have at least one loop")
    conv = convolution(region_a, region_b, tol, keep_type3=False)
    pieces = [c.piece for c in conv]
    pts = np.concatenate([pc.cartesian(p) for p in pieces])
    scale = float(np.ptp(pts, axis=0).max())
    flat_tol = min(tol, scale * 1e-4)
    cuts = split_parameters(pieces, flat_tol, scale)
    subs = cut_pieces(pieces, cuts, min_len=scale * 1e-10)
    member_tol = scale * 2e-6
    member = _Membership(region_a, region_b, member_tol)
    eps = scale * 5e-5
    cls = classify(subs, member, eps)
    kept = [s if c > 0 else pc.reverse(s) for s, c in zip(subs, cls) if c != 0]
    kept = _dedupe(kept, scale * 1e-9)
    loops = _chain_boundary(kept, scale * 1e-7)
    if return_debug:
        return loops, {"convolution": conv, "subpieces": subs, "classes": cls}
    return loops


def _chain_boundary(pieces, join_tol):
    try:
        loops = chain(pieces, join_tol)
    except TopologyError:
        loops = chain(pieces, join_tol * 1e3)
    return [_merge_collinear(loop) for loop in loops]


def _merge_collinear(loop):
    return loop

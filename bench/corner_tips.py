"""The error at a sharp corner of a trimmed sum, measured on the two pieces that cross
there (:func:`tip_bounds`): what :mod:`bench.corner_pass` compares with the corner
pass's a-priori bound e / cos(phi / 2) (:func:`morph.minkowski._tip_tolerances`).

Two convolution pieces ka and kb, within e_a and e_b of their exact curves, cross at
a junction J of the trimmed boundary; the exact curves cross at the exact corner X.
X lies on both exact curves, so within e_a of a point of ka that is within
e_a + e_b of kb, and within e_b of such a point of kb: in the part of the two
pieces where they come within e_a + e_b of each other (their thin part).  Where the
connected thin part T around J stays in a box of diagonal D, X is within e + D of
every point of T, J among them (e = max(e_a, e_b)): the corner's error is at most
e + D, whatever the shapes of the pieces.  For two lines meeting at a turn phi, T
reaches about e / cos(phi / 2) along each side from J, the a-priori bound the
corner pass uses; at the cusps of a convolution curve (where a skeleton's radius
of curvature equals the nib's at the same normal) the boundary turns by nearly pi
at a spike a hundredth of a unit long, beyond which the pieces part at once: there
T is far smaller than e / cos(phi / 2), and the corner needs no finer pieces.

Computed on polylines within FLAT_TIP tol of the pieces (vertices on the curves,
:func:`morph.polyline.flat_starts`): a segment counts as thin where it comes within
e_a + e_b + 2 FLAT_TIP tol of the other polyline, and T's box is grown by FLAT_TIP
tol.  T must end inside both pieces: where it runs to an end of a piece that is not
the other's start or end (a chain junction, an exact point of both curves), it may
go on into other pieces and the junction is not measured (infinite bound).
"""

import numpy as np

from morph import piece as pc
from morph.polyline import flat_starts, segment_distance

#: Flattening of the pieces through a measured corner, in tol: the polylines'
#: distance to the pieces, added to the thin threshold (twice) and to T's box
FLAT_TIP = 0.01


def tip_bounds(flat, junctions, nxt, conv, corner, piece, tol):
    """Measured error bound (module docstring) of each junction of ``junctions``
    (indices into ``flat``, the trimmed boundary's pieces one loop after another; the
    junction is the end of flat[k] and the start of flat[nxt[k]]); ``corner``,
    ``piece``: (junction position, convolution piece) pairs, the pieces of ``conv``
    near each junction, among which its two sources are found.  (len(junctions),)
    floats, inf where the junction is not measured."""
    junctions = np.asarray(junctions, np.int64)
    out = np.full(len(junctions), np.inf)
    if not len(junctions):
        return out
    f = FLAT_TIP * tol
    cand = np.unique(piece)
    poly, n_pts = _padded(conv.pieces.take(cand), f)
    where = np.searchsorted(cand, piece)
    mids = pc.end_points(pc.subsegments(flat, np.concatenate([junctions, nxt[junctions]]),
                                        np.full(2 * len(junctions), 0.5),
                                        np.ones(2 * len(junctions)), packed=True))[0]
    ka = _source(mids[:len(junctions)], poly, corner, where, len(junctions), f)
    kb = _source(mids[len(junctions):], poly, corner, where, len(junctions), f)
    ok = np.flatnonzero((ka >= 0) & (kb >= 0) & (ka != kb))
    if not len(ok):
        return out
    e = np.maximum(conv.bound[cand[ka[ok]]], conv.bound[cand[kb[ok]]])
    thr = conv.bound[cand[ka[ok]]] + conv.bound[cand[kb[ok]]] + 2.0 * f
    jpt = pc.end_points(flat.take(junctions[ok]) if isinstance(flat, pc.Pieces)
                        else [flat[k] for k in junctions[ok].tolist()])[1]
    # ends of consecutive convolution pieces are chained within 0.01 tol
    diag = _thin_extent(poly[ka[ok]], n_pts[ka[ok]], poly[kb[ok]], n_pts[kb[ok]], jpt,
                        thr, f, 0.01 * tol)
    out[ok] = e + diag
    return out


def _padded(pieces, f):
    """Polylines of ``pieces`` within ``f`` (vertices on the pieces, the end point
    included) as one (n, L, 2) array padded with NaN, and their vertex counts."""
    owner, _, starts = flat_starts(pieces, f)
    ends = pc.end_points(pieces)[1]
    n_pts = np.bincount(owner, minlength=len(pieces)) + 1
    first = np.cumsum(n_pts - 1) - (n_pts - 1)
    out = np.full((len(pieces), int(n_pts.max()), 2), np.nan)
    out[owner, np.arange(len(owner)) - first[owner]] = starts
    out[np.arange(len(pieces)), n_pts - 1] = ends
    return out, n_pts


def _seg_dist(points, poly):
    """Distance from each point (m, k, 2) to the polyline of its row (m, L, 2), NaN
    padded: (m, k)."""
    a, b = poly[:, None, :-1], poly[:, None, 1:]
    d = segment_distance(points[:, :, None, :], a, b)
    return np.where(np.isnan(d), np.inf, d).min(axis=2)


def _source(mids, poly, corner, where, n, f):
    """For each of ``n`` junctions, the candidate (index into ``poly``) whose polyline
    passes within ``f`` of the output piece's mid point ``mids`` (the output piece is
    a part of it), -1 where none or more than one does."""
    d = _seg_dist(mids[corner][:, None, :], poly[where])[:, 0]
    on = d <= 2.0 * f          # the polyline within f of the piece, rounding inside f
    count = np.bincount(corner[on], minlength=n)
    out = np.full(n, -1)
    out[corner[on]] = where[on]
    out[count != 1] = -1
    return out


def _thin_extent(pa, na, pb, nb, jpt, thr, f, join):
    """Diagonal of the box (grown by ``f``) of the thin part around the junction
    ``jpt`` of the polylines ``pa`` and ``pb`` (m, L, 2, NaN padded, ``na``, ``nb``
    vertices), thin meaning within ``thr`` of the other; inf where it runs to an end
    of a polyline that is not an end of the other (ends within ``join``)."""
    lo_a, hi_a, end_a = _thin_run(pa, na, pb, jpt, thr)
    lo_b, hi_b, end_b = _thin_run(pb, nb, pa, jpt, thr)
    # an end the run reaches must be shared with the other polyline (a chain
    # junction) and reached by the other's run too: T closes there
    a0, a1 = pa[np.arange(len(pa)), 0], pa[np.arange(len(pa)), na - 1]
    b0, b1 = pb[np.arange(len(pb)), 0], pb[np.arange(len(pb)), nb - 1]
    a1b0 = np.hypot(*(a1 - b0).T) <= join
    a0b1 = np.hypot(*(a0 - b1).T) <= join
    closed = (~end_a[:, 1] | (a1b0 & end_b[:, 0])) & (~end_b[:, 0] | (a1b0 & end_a[:, 1]))
    closed &= (~end_a[:, 0] | (a0b1 & end_b[:, 1])) & (~end_b[:, 1] | (a0b1 & end_a[:, 0]))
    lo = np.minimum(_run_box(pa, lo_a, hi_a, np.fmin), _run_box(pb, lo_b, hi_b, np.fmin))
    hi = np.maximum(_run_box(pa, lo_a, hi_a, np.fmax), _run_box(pb, lo_b, hi_b, np.fmax))
    diag = np.hypot(*(hi - lo + 2.0 * f).T)
    return np.where(closed, diag, np.inf)


def _thin_run(p, n, q, jpt, thr):
    """(first, last segment, (reaches start, reaches end)) of the run of segments of
    ``p`` around the one nearest ``jpt`` that come within ``thr`` of ``q``."""
    m, length = p.shape[0], p.shape[1] - 1
    seg = np.arange(length)
    a, b = p[:, :-1], p[:, 1:]
    near = segment_distance(jpt[:, None, :], a, b)
    at = np.where(np.isnan(near), np.inf, near).argmin(axis=1)
    # segment to polyline: 0 where they cross, else the least end-to-segment distance
    d = np.minimum(_seg_dist(a, q), _seg_dist(b, q))
    d = np.minimum(d, _seg_dist_rev(q, a, b))
    d[_crossing_any(a, b, q)] = 0.0
    thin = (d <= thr[:, None]) & (seg[None, :] < (n - 1)[:, None])
    before = np.where(~thin & (seg[None, :] < at[:, None]), seg[None, :], -1).max(axis=1)
    after = np.where(~thin & (seg[None, :] > at[:, None]), seg[None, :], length).min(axis=1)
    lo, hi = before + 1, np.minimum(after, n - 1) - 1
    return lo, hi, np.stack([before < 0, after >= n - 1], axis=1)


def _seg_dist_rev(q, a, b):
    """Distance from each segment a[i] b[i] (m, k, 2) to the vertices of q (m, L, 2):
    (m, k), the least over q's vertices."""
    d = segment_distance(q[:, None, :, :], a[:, :, None, :], b[:, :, None, :])
    return np.where(np.isnan(d), np.inf, d).min(axis=2)


def _crossing_any(a, b, q):
    """Whether each segment a[i] b[i] (m, k, 2) crosses a segment of q (m, L, 2)."""
    c, d = q[:, None, :-1], q[:, None, 1:]
    a, b = a[:, :, None], b[:, :, None]

    def side(o, u, v):
        return (u[..., 0] - o[..., 0]) * (v[..., 1] - o[..., 1]) - \
            (u[..., 1] - o[..., 1]) * (v[..., 0] - o[..., 0])

    s1, s2 = side(a, b, c), side(a, b, d)
    s3, s4 = side(c, d, a), side(c, d, b)
    with np.errstate(invalid="ignore"):
        return ((s1 * s2 <= 0) & (s3 * s4 <= 0)).any(axis=2)


def _run_box(p, lo, hi, op):
    """op-reduction (np.fmin / np.fmax) of the vertices of segments lo..hi of each
    polyline (m, L, 2): (m, 2)."""
    idx = np.arange(p.shape[1])[None, :]
    inside = (idx >= lo[:, None]) & (idx <= hi[:, None] + 1)
    fill = np.inf if op is np.fmin else -np.inf
    return op.reduce(np.where(inside[:, :, None], p, fill), axis=1)

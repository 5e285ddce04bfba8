"""The turn of the corner a junction of a trimmed sum stands for
(:func:`corner_turns`) and the error of the pieces along their parts there
(:func:`local_bounds`), for the corner pass of :mod:`morph.minkowski`.

The corner pass bounds the error at a corner of the boundary of what the
convolution pieces fill (the trimmed approximations) by e / cos(phi / 2), phi the
turn there.  A junction of the trimmed output is such a corner where it is a
crossing of two pieces: the trimming solved it by Newton on the pieces
(:mod:`morph.trim.lift`) and it lies on both.  Where that iteration did not
converge, the junction was left on its grid point, within the trimming's topology
share (FLAT_SHARE + GRID_SHARE tol, TIP_REACH tol with the contraction) of the
approximations' boundary, and its turn is that of the polylines, not of a corner
of the pieces: at the cusps of a convolution curve (near the tight end of a broad
nib) the polylines of two consecutive pieces cross near their joint where the
pieces do not, and the output has a spike turning by nearly pi there, while the
pieces cross nearby at a turn of a few degrees (the boundary of their
swallowtail).  For such a junction the corners of the pieces are found where they
are: the crossings of the near pieces within TIP_REACH tol of the junction, on
polylines of the pieces' parts there (within FLAT_TIP tol, crossings at their
joints not counted: a joint is an exact point of both curves); the sharpest one's
turn is the junction's.  Where none is found the junction keeps its own turn.

e there is the error of the pieces along their parts near the junction, not
along the whole pieces: a QAC piece's error is 0 at its ends and peaks inside, and
the corners of a sum (where two pieces cross) are often near a piece's end, so
the part's certified bound is often a small fraction of the piece's and the pair
needs no finer approximation (and the sum no second trimming).
"""

import numpy as np

from . import bernstein as bz
from . import piece as pc
from . import qac
from .budget import GRID_SHARE, TIP_REACH
from .nearest import distance_bound_many, nearest_params_in_range
from .polyline import flat_starts

#: A junction is a crossing of two pieces where it lies within ON_PIECE tol of
#: both: twice the trimming's Newton tolerance (a hundredth of its grid step,
#: :func:`morph.trim.lift._crossing_points`)
ON_PIECE = 2.0 * 0.01 * GRID_SHARE * np.sqrt(2.0)
#: Flattening of the pieces' parts near a junction, in tol: their crossings at a
#: turn phi lie within FLAT_TIP tol / sin(phi / 2) of the polylines'
FLAT_TIP = 1e-3
#: Parameters sampled per piece to find its part within TIP_REACH tol of the junction
SAMPLES = 65
#: :func:`local_bounds` cuts a piece into this many parts of equal parameter length;
#: those whose control box comes within the reach hold its part there
LOCAL_PARTS = 128


def corner_turns(pts, cos_half, corner, piece, conv, tol):
    """cos(phi / 2) of the corner each junction (``pts`` (m, 2), its own turn
    ``cos_half``) stands for (module docstring), given the pieces of ``conv`` near
    each ((junction, piece) index pairs ``corner``, ``piece``)."""
    out = np.array(cos_half, float)
    stacked = pc.stack(conv.pieces.take(piece))
    p = pts[corner]
    t = nearest_params_in_range(stacked, p, np.zeros(len(p)), np.ones(len(p)), samples=SAMPLES)
    on = np.hypot(*(pc.jet_many(stacked, np.arange(len(p)), t)[0] - p).T) <= ON_PIECE * tol
    crossing = np.bincount(corner[on], minlength=len(pts)) >= 2
    look = ~crossing[corner]
    if not look.any():
        return out
    found = _sharpest(stacked[look], pts, corner[look], tol)
    has = np.isfinite(found)
    out[has] = found[has]
    return out


def _sharpest(stacked, pts, corner, tol):
    """The least cos(phi / 2) of the crossings of the pieces ``stacked`` (one per
    (junction, piece) pair, ``corner`` their junctions) with the other pieces of
    their junction within TIP_REACH tol of it; inf where none."""
    reach = TIP_REACH * tol
    s = np.linspace(0.0, 1.0, SAMPLES)
    x = _samples(stacked, s)
    near = np.hypot(*np.moveaxis(x - pts[corner][:, None, :], 2, 0)) <= reach
    has = near.any(axis=1)
    idx = np.arange(SAMPLES)
    lo = np.where(near, idx, SAMPLES).min(axis=1)
    hi = np.where(near, idx, -1).max(axis=1)
    # the samples either side: the part reaches the edge of the disc
    t0, t1 = s[np.maximum(lo - 1, 0)], s[np.minimum(hi + 1, SAMPLES - 1)]
    k = np.flatnonzero(has)
    out = np.full(len(pts), np.inf)
    if not len(k):
        return out
    parts = pc.Pieces.of(list(stacked[k]))
    parts = pc.subsegments(parts, np.arange(len(k)), t0[k], t1[k], packed=True)
    owner, _, starts = flat_starts(parts, FLAT_TIP * tol)
    ends = pc.end_points(parts)[1]
    n_pts = np.bincount(owner, minlength=len(k)) + 1
    base = np.cumsum(n_pts) - n_pts
    first = np.cumsum(n_pts - 1) - (n_pts - 1)
    flat = np.empty((int(n_pts.sum()), 2))
    flat[base[owner] + np.arange(len(owner)) - first[owner]] = starts
    flat[base + n_pts - 1] = ends
    last = np.zeros(len(flat), bool)
    last[base + n_pts - 1] = True
    seg = np.flatnonzero(~last)                         # segment seg -> seg + 1
    part = np.searchsorted(base, seg, "right") - 1
    cos = _crossing_turns(flat, seg, part, corner[k][part], pts, reach)
    np.minimum.at(out, corner[k][part][cos[0]], cos[1])
    return out


def _samples(stacked, t):
    """Points (k, len(t), 2) of the stacked pieces (k, n + 1, 3) at the parameters t."""
    h = np.einsum("tk,pkc->ptc", bz.basis(stacked.shape[1] - 1, t), stacked)
    return h[..., :2] / h[..., 2:]


def _crossing_turns(flat, seg, part, junction, pts, reach):
    """(segment positions, cos(phi / 2)) of the proper crossings of the segments
    ``seg`` (flat[seg] -> flat[seg + 1]; ``part`` each one's part, ``junction`` its
    junction) with the segments of the other parts of the same junction, within
    ``reach`` of the junction ``pts``: phi the turn between the two directions."""
    order = np.argsort(junction, kind="stable")
    seg, part, junction = seg[order], part[order], junction[order]
    lo = np.searchsorted(junction, junction, "left")
    cnt = np.searchsorted(junction, junction, "right") - lo
    i = np.repeat(np.arange(len(seg)), cnt)
    j = np.repeat(lo, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    keep = part[i] < part[j]
    i, j = i[keep], j[keep]
    p0, p1 = flat[seg[i]], flat[seg[i] + 1]
    q0, q1 = flat[seg[j]], flat[seg[j] + 1]
    da, db = p1 - p0, q1 - q0
    s1, s2 = pc.cross2(da, q0 - p0), pc.cross2(da, q1 - p0)
    s3, s4 = pc.cross2(db, p0 - q0), pc.cross2(db, p1 - q0)
    cross = (s1 * s2 < 0.0) & (s3 * s4 < 0.0)     # proper: not where parts meet at a joint
    with np.errstate(invalid="ignore", divide="ignore"):
        at = p0 + (s3 / (s3 - s4))[:, None] * da
    cross &= np.hypot(*(at - pts[junction[i]]).T) <= reach
    i, da, db = i[cross], da[cross], db[cross]
    cos = np.einsum("ij,ij->i", da, db) / np.maximum(np.hypot(*da.T) * np.hypot(*db.T),
                                                     1e-300)
    return order[i], np.sqrt(np.clip(0.5 * (1.0 + cos), 0.0, 1.0))


def local_bounds(conv, pts, reach, corner, piece):
    """A bound of the error of each piece ``piece`` (indices into ``conv``, a
    :class:`morph.convolve.ConvPieces`) along its part within ``reach[corner]`` of
    the junction ``pts[corner]``: at most the piece's bound, 0 where no part of it
    comes that near.

    A QAC piece is C1(t) + Q2(s(t)) with exact normals (:mod:`morph.qac`); at t
    its distance to the exact convolution curve is at most dist(Q2(s(t)), C2), so
    the certificate of |Q2(s) - C2(r(s))| over the range of s(t) of the part bounds
    the part's error (r the piece's reparametrisation map, or r(s) = s).  The part
    is a superset: the parts of LOCAL_PARTS equal parameter steps whose control
    boxes (the pieces' weights are positive) come within the reach; s at its ends
    is where Q2's tangent is parallel to the piece's (s(t) is monotone).  The
    error at a QAC piece's ends is 0 and grows into it, so near a junction close
    to an end the part's bound is a fraction of the piece's.  Pieces of other kinds,
    or of a ``conv`` without Q2 (``conv.qac`` None), keep their bound."""
    out = np.array(conv.bound[piece], float)
    if conv.qac is None or not len(piece):
        return out
    q2 = conv.qac[1][piece]
    k = np.flatnonzero(np.isfinite(q2).all(axis=(1, 2)))
    if not len(k):
        return out
    stacked = pc.stack(conv.pieces.take(piece[k]))
    t, near = _near_params(stacked, pts[corner[k]], reach[corner[k]])
    s = _q2_params(stacked, t, q2[k])
    e = _part_bounds(pc.stack(conv.qac[0].take(piece[k])), q2[k], s)
    out[k] = np.where(near, np.minimum(out[k], e), 0.0)
    return out


def _near_params(stacked, pts, reach):
    """(t (k, 2), near (k,)): the parameter range of the parts of LOCAL_PARTS whose
    control boxes come within ``reach`` of ``pts`` (a superset of the piece's part
    that near), and whether there is one."""
    k, m = len(stacked), LOCAL_PARTS
    edges = np.linspace(0.0, 1.0, m + 1)
    parts = bz.subsegment_many(np.repeat(stacked, m, axis=0), np.tile(edges[:-1], k),
                               np.tile(edges[1:], k))
    xy = parts[:, :, :2] / parts[:, :, 2:]
    gap = np.maximum(np.maximum(xy.min(axis=1) - np.repeat(pts, m, axis=0),
                                np.repeat(pts, m, axis=0) - xy.max(axis=1)), 0.0)
    hit = (np.hypot(*gap.T) <= np.repeat(reach, m)).reshape(k, m)
    near = hit.any(axis=1)
    first = np.argmax(hit, axis=1)
    last = m - 1 - np.argmax(hit[:, ::-1], axis=1)
    return np.stack([edges[first], edges[last + 1]], axis=1), near


def _q2_params(stacked, t, q2):
    """(k, 2): the parameters s of Q2 where its tangent is parallel to the piece's
    at t (k, 2), ordered, widened by 1e-9 into [0, 1]; [0, 1] where undefined."""
    k = len(stacked)
    d = pc.jet_many(stacked, np.repeat(np.arange(k), 2), t.ravel())[1].reshape(k, 2, 2)
    a, b = (q2[:, 1] - q2[:, 0])[:, None], (q2[:, 2] - q2[:, 1])[:, None]
    ca, cb = pc.cross2(a, d), pc.cross2(b, d)
    with np.errstate(invalid="ignore", divide="ignore"):
        s = ca / (ca - cb)
    s = np.where(np.isfinite(s).all(axis=1)[:, None], np.sort(s, axis=1), [[0.0, 1.0]])
    return np.clip(s + [[-1e-9, 1e-9]], 0.0, 1.0)


def _part_bounds(c2, q2, s):
    """Certified max |Q2(s) - C2(r(s))| over s in [s0, s1] (rows of ``s``), r the
    map :func:`morph.qac.qac_error_bound` fits, or r(s) = s where it has none."""
    origin = c2[:, 0, :2] / c2[:, 0, 2:3]
    c = c2.copy()
    c[:, :, :2] -= c[:, :, 2:3] * origin[:, None]
    q = q2 - origin[:, None]
    with np.errstate(all="ignore"):
        r, fine = qac._reparam_maps(c, q)
    q = bz.subsegment_many(q, s[:, 0], s[:, 1])
    out = np.empty(len(c))
    for rows in (np.flatnonzero(fine), np.flatnonzero(~fine)):
        if len(rows):
            cr = bz.compose_many(c[rows], r[rows]) if fine[rows[0]] else c[rows]
            part = bz.subsegment_many(cr, s[rows, 0], s[rows, 1])
            out[rows] = distance_bound_many(part, q[rows])[0]
    return out

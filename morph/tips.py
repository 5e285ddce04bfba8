"""The turn of the corner a junction of a trimmed sum stands for
(:func:`corner_turns`), for the corner pass of :mod:`morph.minkowski`.

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
"""

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .budget import GRID_SHARE, TIP_REACH
from .nearest import nearest_params_in_range
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

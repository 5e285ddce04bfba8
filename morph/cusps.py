"""The corners at the cusps of a convolution curve, found before the first trim
(:func:`cusp_tolerances`), so that the corner pass of :mod:`morph.minkowski` finds
them approximated finely enough already and the sum is trimmed once.

Where a skeleton's radius of curvature equals the nib's at the same normal (near
the tight end of a broad nib) the convolution curve has a cusp, two close together
a swallowtail, which may be far smaller than the convolution's error e.  Two
consecutive convolution pieces around such a joint, each through one of the cusps,
then cross near the joint at a small angle; the trimmed boundary keeps a spike
there that turns by nearly pi, whose tip the corner pass's rule refines
(e <= CONV_SHARE tol TIP_MARGIN cos(phi / 2), :func:`morph.minkowski._tip_tolerances`).
That crossing is seen on the pieces themselves: for every pair of consecutive
pieces (end to start within the chaining distance, 0.01 tol) one of which turns by
more than a right angle (a cusp among them: the tangent turns back), the polylines
of the two (within FLAT_CUSP tol, vertices on the pieces) are crossed within
CONV_SHARE tol of the joint, and the rule is applied to the turn from the first
piece to the second there.  A corner this misses, or one the refined pieces make,
is left to the corner pass after the trim, which holds the budget either way.
"""

from math import comb

import numpy as np

from . import piece as pc
from .budget import CONV_SHARE, TIP_FLOOR, TIP_MARGIN
from .convolve import _near_pairs
from .polyline import flat_starts

#: Flattening of the pieces' parts near a joint, in tol: a spike's crossing lies
#: about a hundredth of tol from the joint at tol = 1 (Relief at --tol 4), at an
#: angle of a few degrees; polylines within 1e-4 tol cross there too
FLAT_CUSP = 1e-4
#: The pieces are sampled at this many equally spaced parameters to find their
#: parts within CONV_SHARE tol of the joint
SAMPLES = 65
#: Consecutive convolution pieces are chained within JOIN_SHARE tol
#: (:func:`morph.minkowski._trimmed`)
JOIN_SHARE = 0.01


def cusp_tolerances(conv, tol):
    """{table row: tolerance} for the pairs of the convolution pieces ``conv``
    (:class:`morph.convolve.ConvPieces`) that cross at a cusp spike (module
    docstring) with a bound above what the corner pass's rule wants there."""
    first, last = pc.end_tangents_many(conv.pieces, strict=False)
    turned = np.flatnonzero(np.einsum("ij,ij->i", first, last) < 0.0)
    if not len(turned):
        return {}
    starts, ends = pc.end_points(conv.pieces)
    i, j, _ = _near_pairs(ends[turned], starts[turned], JOIN_SHARE * tol)
    a, b = turned[i], turned[j]                          # a turned piece, then the next
    keep = a != b
    a, b = a[keep], b[keep]
    if not len(a):
        return {}
    cos_half = _spike_turns(conv.pieces, a, b, ends[a], tol)
    # the turn measured on polylines: one more TIP_MARGIN on the rule's
    want = CONV_SHARE * tol * TIP_MARGIN ** 2 * np.maximum(cos_half, TIP_FLOOR)
    pieces = np.concatenate([a, b])
    want = np.concatenate([want, want])
    hit = conv.bound[pieces] > want
    rows = conv.row[pieces[hit]]
    if not len(rows):
        return {}
    order = np.lexsort((want[hit], rows))               # each row's least tolerance first
    rows, want = rows[order], want[hit][order]
    lead = np.flatnonzero(np.diff(rows, prepend=-1) != 0)
    return dict(zip(rows[lead].tolist(), want[lead].tolist()))


def _spike_turns(pieces, a, b, joint, tol):
    """cos(phi / 2) at the sharpest crossing of the pieces a[i] and b[i] within
    CONV_SHARE tol of their joint ``joint[i]`` (from a's direction to b's; 1.0 where
    they do not cross there): their parts from the joint to the first of SAMPLES
    equally spaced parameters farther away, flattened within FLAT_CUSP tol."""
    reach = CONV_SHARE * tol
    t = np.linspace(0.0, 1.0, SAMPLES)
    m = len(a)
    stacked = pc.stack(pieces.take(np.concatenate([a, b])))
    pts = _samples(stacked, t)
    far = np.hypot(*np.moveaxis(pts - np.concatenate([joint, joint])[:, None, :], 2, 0)) > reach
    idx = np.arange(SAMPLES)
    # a: from its last far sample to its end; b: from its start to its first far one
    lo = np.where(far[:m], idx, 0).max(axis=1)
    hi = np.where(far[m:], idx, SAMPLES - 1).min(axis=1)
    t0 = np.concatenate([t[lo], np.zeros(m)])
    t1 = np.concatenate([np.ones(m), t[hi]])
    parts = pc.subsegments(pieces, np.concatenate([a, b]), t0, t1, packed=True)
    owner, _, starts = flat_starts(parts, FLAT_CUSP * tol)
    ends = pc.end_points(parts)[1]
    n_pts = np.bincount(owner, minlength=2 * m) + 1
    base = np.cumsum(n_pts) - n_pts
    first = np.cumsum(n_pts - 1) - (n_pts - 1)           # of each part's starts
    flat = np.empty((int(n_pts.sum()), 2))
    flat[base[owner] + np.arange(len(owner)) - first[owner]] = starts
    flat[base + n_pts - 1] = ends
    last = np.zeros(len(flat), bool)
    last[base + n_pts - 1] = True
    seg = np.flatnonzero(~last)                         # segment seg -> seg + 1
    part = np.searchsorted(base, seg, "right") - 1
    in_a = part < m
    return _sharpest_crossing(flat, (part[in_a], seg[in_a]), (part[~in_a] - m, seg[~in_a]), m)


def _samples(stacked, t):
    """Points (k, len(t), 2) of the stacked pieces (k, n + 1, 3) at the parameters t."""
    n = stacked.shape[1] - 1
    k = np.arange(n + 1)
    basis = np.array([comb(n, i) for i in range(n + 1)]) * t[:, None] ** k \
        * (1.0 - t[:, None]) ** (n - k)
    h = np.einsum("tk,pkc->ptc", basis, stacked)
    return h[..., :2] / h[..., 2:]


def _sharpest_crossing(flat, sa, sb, n_pairs):
    """Least cos(phi / 2) per pair of the proper crossings of its segments ``sa``
    with its segments ``sb`` ((pair, segment start) each), phi the turn from the
    first's direction to the second's; 1.0 where none cross."""
    pa, ga = sa
    pb, gb = sb
    out = np.ones(n_pairs)
    if not len(pa) or not len(pb):
        return out
    # all (a segment, b segment) pairs of the same pair: sorted by pair, by ranges
    order = np.argsort(pb, kind="stable")
    pb, gb = pb[order], gb[order]
    lo, hi = np.searchsorted(pb, pa, "left"), np.searchsorted(pb, pa, "right")
    cnt = hi - lo
    i = np.repeat(np.arange(len(pa)), cnt)
    j = np.repeat(lo, cnt) + np.arange(cnt.sum()) - np.repeat(np.cumsum(cnt) - cnt, cnt)
    p0, p1 = flat[ga[i]], flat[ga[i] + 1]
    q0, q1 = flat[gb[j]], flat[gb[j] + 1]
    da, db = p1 - p0, q1 - q0
    s1, s2 = pc.cross2(da, q0 - p0), pc.cross2(da, q1 - p0)
    s3, s4 = pc.cross2(db, p0 - q0), pc.cross2(db, p1 - q0)
    cross = (s1 * s2 < 0.0) & (s3 * s4 < 0.0)     # proper: not at a shared end
    if not cross.any():
        return out
    da, db = da[cross], db[cross]
    cos = np.einsum("ij,ij->i", da, db) / np.maximum(np.hypot(*da.T) * np.hypot(*db.T), 1e-300)
    np.minimum.at(out, pa[i[cross]], np.sqrt(np.clip(0.5 * (1.0 + cos), 0.0, 1.0)))
    return out

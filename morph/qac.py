"""QAC: the quadratic approximation of a convolution piece and its bounds (Sec. 4.4).

Given a compatible pair C1(t), C2(s) (the same range of tangent angles, Sec. 3.2),
QAC replaces C2 by the quadratic Q2 of Eq. 38 (end points of C2, middle control
point at the intersection of its end tangents).  Q2' is linear, so the parallel
condition gives s(t) in closed form (Eq. 36) and C1(t) + Q2(s(t)) is one rational
Bézier curve (degree 3d - 2 for a polynomial C1 of degree d, 5d - 4 for a rational
one) whose normals are exact.  Its distance to the exact convolution is at most the
distance from Q2 to C2, which is bounded a priori (Eqs. 39-40; the reparametrised
form of :func:`qac_error_bound`).

Contents, all array functions on stacks ``(k, n+1, 3)`` of pieces of one degree
(the one-piece forms are the stacked ones on a stack of one):

- :func:`quadratic_approximation` (Eq. 38), :func:`convolve_qac_piece` (Eqs. 34-37);
- :func:`qac_parametric_bound` (Eqs. 39-40), :func:`qac_error_bound` (certified
  distance from Q2 to the curve C2);
- :func:`choose_roles`: which piece of a pair is replaced by a quadratic;
- the three callables of Algorithm 4.1 for the driver
  :func:`morph.subdivide.subdivide_nodes`: :func:`bound_nodes`, :func:`piece_nodes`,
  :func:`split_nodes` (the split at the angle where the bound peaks).

This module is a leaf: it imports only :mod:`morph.bernstein`, :mod:`morph.piece`
and :mod:`morph.gauss`; :mod:`morph.convolve` and :mod:`morph.subdivide` import it.
"""

import functools

import numpy as np

from . import bernstein as bz
from . import gauss
from . import piece as pc
from . import nearest as nr

TINY_SWEEP = 1e-7    # below this common sweep (radians) a pair is treated as straight
REPARAM_DEGREE = 4   # degree of the parameter map r(s) of :func:`qac_error_bound`
_FIT_S = 0.5 - 0.5 * np.cos(np.pi * (np.arange(9) + 0.5) / 9)   # Chebyshev nodes

# kinds of node pieces (:func:`bound_nodes`), by their names in morph.convolve
QAC, CORNER, CHORD = 0, 1, 2
KIND_NAMES = ("qac", "translate", "chord")


def _filled(k, value):
    """A float array of k copies of ``value`` (np.full's numbers in two C calls)."""
    out = np.empty(k)
    out.fill(value)
    return out


# ------------------------------------------------------------------ Q2 (Eq. 38)

def quadratic_approximation_many(c2):
    """Q2 of Eq. 38 for each row of a stack c2: (q2 (k, 3, 2), ok (k,)).

    Q2's control points are C2's end points and the intersection of its end tangents
    (the first and last nonzero control-point differences, as for the limit
    tangents).  ok is False where the end tangents are parallel (C2 straight or
    turning by pi) or the piece has no length.
    """
    c2 = np.asarray(c2, float)
    p = c2[:, :, :2] / c2[:, :, 2:3]
    size = np.maximum((p.max(axis=1) - p.min(axis=1)).max(axis=1), 1e-300)   # np.ptp's
    d = np.diff(p, axis=1)
    norms = np.hypot(d[..., 0], d[..., 1])
    nz = norms > 1e-12 * size[:, None]
    first = nz.argmax(axis=1)
    last = nz.shape[1] - 1 - nz[:, ::-1].argmax(axis=1)
    rows = np.arange(len(p))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = d[rows, first] / norms[rows, first, None]
        t1 = d[rows, last] / norms[rows, last, None]
        q0, q2 = p[:, 0], p[:, -1]
        det = pc.cross2(t0, t1)
        ok = nz.any(axis=1) & (size > 1e-300) & (np.abs(det) >= 1e-14)
        # q0 + a t0 = q2 - b t1  ->  a = cross(q2 - q0, t1) / cross(t0, t1)
        a = pc.cross2(q2 - q0, t1) / np.where(ok, det, 1.0)     # Eq. 38
    q = np.empty((len(p), 3, 2))
    q[:, 0], q[:, 1], q[:, 2] = q0, q0 + a[:, None] * t0, q2
    return q, ok


def quadratic_approximation(c2):
    """Q2 of Eq. 38 for one piece: its (3, 2) control points.

    Raises ValueError when the end tangents are parallel (no tangent intersection).
    """
    q, ok = quadratic_approximation_many(np.asarray(c2, float)[None])
    if not ok[0]:
        raise ValueError("end tangents are parallel: no tangent intersection")
    return q[0]


# -------------------------------------------------------- the bounds (Eqs. 39-40)

def _sq_norm_many(g):
    """|g|^2 of planar Bernstein polynomials g (k, m+1, 2): (k, 2m+1)."""
    return bz.multiply_many(g[..., 0], g[..., 0]) + bz.multiply_many(g[..., 1], g[..., 1])


def qac_parametric_bound_many(c2, q2):
    """A-priori bound of max_s |C2(s) - Q2(s)| at equal parameters (Eqs. 39-40).

    e(s)^2 = |X2(s) - W2(s) Q2(s)|^2 / W2(s)^2: both are Bernstein polynomials, and
    the largest ratio of their coefficients (degree-matched, on the two halves of
    [0, 1]: :func:`morph.bernstein.ratio_bound_many`) bounds e^2; at least as tight
    as the paper's Eq. 40 (largest numerator coefficient over the smallest weight
    coefficient).  Returns (bound (k,), s_peak (k,)), s_peak the parameter of C2
    where the bound peaks.  Loose for cubic C2: it measures the mismatch of the
    parametrisations too, O(h^2) on a piece of size h (see :func:`qac_error_bound`).
    """
    return nr.distance_bound_many(c2, q2)


def qac_parametric_bound(c2, q2):
    """:func:`qac_parametric_bound_many` of one piece: (bound, s_peak)."""
    b, s = qac_parametric_bound_many(np.asarray(c2, float)[None], np.asarray(q2, float)[None])
    return float(b[0]), float(s[0])


def _reparam_maps(c, q):
    """The maps r(s) of :func:`qac_error_bound` for C2 (origin-shifted) and Q2:
    (r (k, REPARAM_DEGREE+1), finite (k,)).  Least squares with r(0) = 0, r(1) = 1
    (:func:`morph.bernstein.fit_fixed_ends`, all rows at once) to the parameters of
    C2 nearest to Q2 at the Chebyshev nodes _FIT_S (Newton, jets from the power
    basis up to degree 12), coefficients clamped to [0, 1]."""
    # Q2's points at the nodes, (k, 9, 2): one 2-D product for all rows
    pts = (_fit_basis() @ q.transpose(1, 0, 2).reshape(3, -1)).reshape(
        len(_FIT_S), len(q), 2).transpose(1, 0, 2)
    jet = pc.jet2_power_many if c.shape[1] <= 13 else pc.jet2_many
    sig = nr.closest_params_many(c, pts, _FIT_S[None].repeat(len(c), axis=0), jet=jet)
    r = bz.fit_fixed_ends(_FIT_S, sig.T, REPARAM_DEGREE, 0.0, 1.0).T
    fine = np.isfinite(r).all(axis=1)
    return np.where(fine[:, None], r.clip(0.0, 1.0), 0.0), fine


@functools.lru_cache(maxsize=None)
def _fit_basis():
    """The quadratic Bernstein basis at the nodes _FIT_S (Q2's points there), made once."""
    return bz.basis(2, _FIT_S)


def _composed_ratio(cr, q):
    """Squared-distance certificate of |C2(r(s)) - Q2(s)| for the composed C2(r(s))
    = X / W (rows of cr) against Q2: (bound^2 (k,), s (k,)).  Rational rows by
    :func:`morph.nearest.distance_bound_many`; where W is constant (polynomial C2)
    the same ratio of |X / W - Q2|^2 at the lower degree."""
    x, w = cr[:, :, :2], cr[:, :, 2]
    flat = w.max(axis=1) - w.min(axis=1) <= 1e-14 * np.abs(w[:, 0])   # polynomial C2: W
    ratio, s = _filled(len(cr), np.inf), _filled(len(cr), 0.5)             # constant
    for rows, poly in ((np.nonzero(flat)[0], True), (np.nonzero(~flat)[0], False)):
        if not len(rows):
            continue
        if poly:
            g = x[rows] / w[rows, :1, None] - bz.elevate_many(q[rows], x.shape[1] - 3)
            a = _sq_norm_many(g)
            ratio[rows], s[rows] = bz.ratio_bound_many(a, np.ones_like(a))
        else:
            b, s[rows] = nr.distance_bound_many(cr[rows], q[rows])
            ratio[rows] = b * b
    return ratio, s


def _reparam_bound_many(c2, q2, par, s_par):
    """The reparametrised bound of :func:`qac_error_bound` of each row, where it is
    smaller than the parametric bound ``par`` (else (par, s_par) is kept)."""
    origin = c2[:, 0, :2] / c2[:, 0, 2:3]
    c = c2.copy()
    c[:, :, :2] -= c[:, :, 2:3] * origin[:, None]
    q = q2 - origin[:, None]
    bound, s_out = np.array(par, float), np.array(s_par, float)
    with np.errstate(all="ignore"):
        r, fine = _reparam_maps(c, q)
        ratio, s = _composed_ratio(bz.compose_many(c, r), q)
        bnd = np.sqrt(np.maximum(ratio, 0.0))
        better = fine & (bnd < bound)
        bound[better] = bnd[better]
        s_out[better] = bz.evaluate_many(r[better], s[better])
    return bound, s_out


def qac_error_bound_many(c2, q2, tol=None):
    """Certified bound of the distance from each Q2 to its curve C2 (Sec. 4.4).

    A QAC piece is C1(t) + Q2(s(t)) (exact normals), so its distance measure
    (Eqs. 49-53: the point minus C1(t), distance to the curve C2) is at most
    max_s dist(Q2(s), C2) <= max_s |Q2(s) - C2(r(s))| for *any* map r of [0, 1]
    into [0, 1].  Eq. 40 takes r(s) = s, which also counts the mismatch of the two
    parametrisations (O(h^2) on a piece of size h, against O(h^4) for the geometric
    distance): ~400x too much on small cubic pieces.  Here r is a polynomial of
    degree REPARAM_DEGREE with r(0) = 0, r(1) = 1, fitted by least squares to the
    nearest-point parameters of C2 at a few points of Q2, its Bernstein coefficients
    clamped to [0, 1] (so r(s) stays in [0, 1]).  The fit is only a choice of r; the
    bound is certified for the r chosen: C2(r(s)) = X(s) / W(s) is an exact
    Bernstein composition, and the coefficient-ratio certificate
    (:func:`morph.bernstein.ratio_bound_many`) of |X - W Q2|^2 over W^2 bounds the
    squared distance.  The result is the smaller of this and
    :func:`qac_parametric_bound_many` (both are upper bounds, rigorous up to
    rounding); rows whose parametric bound already meets ``tol`` keep it without
    the fit.

    Returns (bound (k,), s_peak (k,)): s_peak is C2's parameter where the bound
    peaks, the place Algorithm 4.1 subdivides.
    """
    c2 = np.asarray(c2, float)
    q2 = np.asarray(q2, float)
    par, s_par = qac_parametric_bound_many(c2, q2)
    need = (par > 0.0) & np.isfinite(par)
    if tol is not None:
        need &= par > tol
    rows = np.nonzero(need)[0]
    if len(rows):
        par[rows], s_par[rows] = _reparam_bound_many(c2[rows], q2[rows], par[rows], s_par[rows])
    return par, s_par


def qac_error_bound(c2, q2, tol=None):
    """:func:`qac_error_bound_many` of one piece: (bound, s_peak)."""
    b, s = qac_error_bound_many(np.asarray(c2, float)[None], np.asarray(q2, float)[None], tol)
    return float(b[0]), float(s[0])


# ----------------------------------------------------------- roles (Sec. 4.4)

def _role(c1, c2, tol):
    """One role (C2 replaced by a quadratic) for rows of stacks: [bound, output
    degree, q2, s_peak, ok]; degree = max int64 where there is no Q2 (no candidate:
    it loses every tie)."""
    k = len(c2)
    q2, ok = quadratic_approximation_many(c2)
    bound, s = _filled(k, np.inf), _filled(k, 0.5)
    if ok.any():
        bound[ok], s[ok] = qac_parametric_bound_many(c2[ok], q2[ok])
    d = c1.shape[1] - 1
    degree = np.where(pc.is_polynomial_many(c1), 3 * d - 2, 5 * d - 4)
    degree = np.where(ok, degree, np.iinfo(np.int64).max)
    return [bound, degree, q2, s, ok]


def roles_many(ca, cb, tol=None):
    """Role choice of each pair of rows of stacks ca, cb (Sec. 4.4).

    The bound (:func:`qac_error_bound_many`) depends only on the piece replaced by
    a quadratic, so C2 is the piece with the smaller bound (a polynomial quadratic,
    e.g. a TrueType segment, gives 0: exact); ties go to the lower output degree,
    then to ca as C1.  With ``tol``, the cheap parametric bound decides where one
    role meets tol with it; elsewhere both roles get the reparametrised bound.
    Returns (swap, q2, bound, s_peak, ok): swap is True where cb plays C1; ok is
    False where neither piece has a tangent intersection (bound inf).
    """
    ca, cb = np.asarray(ca, float), np.asarray(cb, float)
    cands = [_role(ca, cb, tol), _role(cb, ca, tol)]
    need = np.minimum(cands[0][0], cands[1][0]) > (-np.inf if tol is None else tol)
    for cand, c2 in zip(cands, (cb, ca)):
        bound, _, q2, s, ok = cand
        sel = np.nonzero(need & ok & (bound > 0) & (bound < np.inf))[0]
        if len(sel):
            bound[sel], s[sel] = _reparam_bound_many(c2[sel], q2[sel], bound[sel], s[sel])
    (b0, d0, q0, s0, ok0), (b1, d1, q1, s1, ok1) = cands
    swap = (b1 < b0) | ((b1 == b0) & (d1 < d0))
    q2 = np.where(swap[:, None, None], q1, q0)
    return swap, q2, np.where(swap, b1, b0), np.where(swap, s1, s0), ok0 | ok1


def choose_roles(ca, cb, tol=None):
    """Pick which piece plays C2 (the one replaced by a quadratic), Sec. 4.4.

    One pair of :func:`roles_many`.  Returns (swap, q2): swap is True when cb plays
    C1; q2 is None when neither piece has a tangent intersection.
    """
    swap, q2, _, _, ok = roles_many(np.asarray(ca, float)[None], np.asarray(cb, float)[None], tol)
    return bool(swap[0]), (q2[0] if ok[0] else None)


# ---------------------------------------------------- the QAC piece (Eqs. 34-37)

def _qac_from_numerator(c1, h1, q):
    """C1(t) + Q2(s(t)) for stacks c1 (k, n+1, 3), tangent numerators h1 (k, m+1, 2)
    of C1 and quadratics q (k, 3, 2) (:func:`convolve_qac_piece`)."""
    x1, xq, w = qac_parts(c1, h1, q)
    return np.concatenate([x1 + xq, w[:, :, None]], axis=2)


def qac_parts(c1, h1, q):
    """The two terms of :func:`_qac_from_numerator`'s piece and its weights:
    (X1 (k, m+1, 2), XQ (k, m+1, 2), W (k, m+1)), the piece (X1 + XQ, W).  X1 is
    C1's term (C1's control points times D^2), XQ is Q2's (C1's weights times the
    D^2 Q2(N / D)), and W does not depend on where the points of C1 or Q2 are, only
    on the directions of C1's tangents and Q2's legs: C1 scaled by a and Q2 by b
    (a, b > 0) give the piece (a X1 + b XQ, W) up to a common factor of its rows
    (what frames of scaled copies blend, :mod:`morph.frames`)."""
    d0, d1 = q[:, 1] - q[:, 0], q[:, 2] - q[:, 1]
    num = h1[:, :, 0] * d0[:, None, 1] - h1[:, :, 1] * d0[:, None, 0]   # Eq. 36 numerator
    dd = d0 - d1
    den = h1[:, :, 0] * dd[:, None, 1] - h1[:, :, 1] * dd[:, None, 0]   # Eq. 36 denominator
    flip = np.where(np.mean(den, axis=1) < 0, -1.0, 1.0)[:, None]
    num, den = num * flip, den * flip
    num = _exact_end_params(num, den)
    m0 = bz.multiply_many(den - num, den - num)
    m1 = 2.0 * bz.multiply_many(num, den - num)
    m2 = bz.multiply_many(num, num)
    dsq = m0 + m1 + m2                                                  # = D^2
    qpart = (m0[:, :, None] * q[:, None, 0] + m1[:, :, None] * q[:, None, 1]
             + m2[:, :, None] * q[:, None, 2])
    w1 = c1[:, :, 2]
    return (bz.multiply_many(c1[:, :, :2], dsq[:, :, None]),
            bz.multiply_many(w1[:, :, None], qpart), bz.multiply_many(w1, dsq))


def _exact_end_params(num, den):
    """N with s(t) = N / D exactly 0 or 1 at t = 0 and t = 1 (Eq. 36's ends).

    The pair is compatible: C1's end tangents are parallel to Q2's (C2's), so s is
    0 or 1 at each end, whichever the computed ratio is nearer.  The computed N(0),
    N(1) are cross products of nearly parallel vectors, and where C1 or C2 is much
    shorter than the other and the common sweep small, their rounding (relative to
    the coordinates' magnitude) is large against D = cross(H1, D0 - D1): the piece's
    ends slipped along it, 1.3e-6 for 2e-5 of a cubic ⊕ 0.3 of a quadratic over
    1.25e-3 rad at 500 units from the origin, more than the 0.01 tol the loops are
    chained within.  Setting the end coefficients puts the ends on the exact sums
    C1(end) + C2(end); inside, s moves along Q2, so the piece stays on the surface
    C1(t) + Q2(s) the bound of Eqs. 39-40 is about."""
    num = num.copy()
    for k in (0, -1):
        d = den[:, k]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = num[:, k] / d
        ok = np.isfinite(s)
        num[ok, k] = np.where(s[ok] < 0.5, 0.0, d[ok])
    return num


def convolve_qac_piece(c1, c2, q2=None):
    """C1(t) + Q2(s(t)) as one rational Bézier (Sec. 4.4, Eqs. 34-37).

    Q2'(s) = 2((1-s) D0 + s D1) with D0 = Q1 - Q0, D1 = Q2 - Q1 is linear in s, so the
    parallel condition cross(C1'(t), Q2'(s)) = 0 gives (Eq. 36)
        s(t) = N(t) / D(t),  N = cross(H1, D0),  D = cross(H1, D0 - D1),
    with H1 the hodograph direction of C1.  Substituting into Q2 and clearing the
    denominator D^2:
        Q2(s(t)) = ((D-N)^2 Q0 + 2 N (D-N) Q1 + N^2 Q2) / D^2,
    so the result is exact symbolic Bernstein arithmetic: degree 3d-2 for a
    polynomial C1 of degree d, 5d-4 for a rational one.  The tangent of the result is
    parallel to C1'(t): normals are exact.  C1 and C2 must have the same tangent
    angle range (compatible, Sec. 3.2).  Raises ValueError when Q2 does not exist.
    """
    c1 = np.asarray(c1, float)
    q = quadratic_approximation(c2) if q2 is None else np.asarray(q2, float)
    h1 = pc.tangent_numerator(c1)
    return _qac_from_numerator(c1[None], h1[None], q[None])[0]


def qac_pieces(c1, q2):
    """QAC pieces of the rows of a stack c1 (one degree) with quadratics q2: a list.

    Polynomial and rational rows are built together in two stacks; rows whose
    tangent numerator vanishes at an end use the one-piece form."""
    out = [None] * len(c1)
    for rows, _, h, odd in pc.numerator_groups(c1):
        res = _qac_from_numerator(c1[rows], h, q2[rows])
        for r, row in enumerate(rows):
            out[row] = convolve_qac_piece(c1[row], None, q2[row]) if odd[r] else res[r]
    return out


# ------------------------------------------- Algorithm 4.1 as driver callables
# A node is one compatible sub-pair; nodes are dicts of arrays with one row per
# node (the protocol of morph.subdivide.subdivide_nodes).  Columns read here:
#   ca, cb (k, n+1, 3): the sub-pieces, each in its own edge's direction;
#   ha, hb (k, m+1, 2): their tangent numerators (any positive multiple);
#   sa, sb (k,): +1 convex, -1 concave (the tangent turns left / right);
#   lo, hi (k,): the common range of tangent angles, in ca's lifted angles;
#   t0, t1 (k,): ca's parameter interval on the original piece;
#   depth (k,): halvings left (the driver's).
# bound_nodes adds kind, swap, q2; piece_nodes returns pieces along ca.

def _sagitta_many(c):
    """Largest distance of each piece's control points from its chord (k,)."""
    p = c[:, :, :2] / c[:, :, 2:3]
    chord = p[:, -1] - p[:, 0]
    length = np.hypot(chord[:, 0], chord[:, 1])
    rel = p - p[:, :1]
    far = np.hypot(rel[..., 0], rel[..., 1]).max(axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        off = np.abs(pc.cross2(chord[:, None], rel)).max(axis=1) / length
    return np.where(length == 0, far, off)


def bound_nodes(nodes, tol):
    """Error bound of each node's approximation (Algorithm 4.1): (bound, s_peak).

    - a sub-piece shorter than 1e-7 of the other (or than tol/4, or tol/2 at the
      last level) acts as a corner: the other piece translated (kind CORNER), bound
      twice the short one's control-polygon length;
    - a common sweep below TINY_SWEEP: the chord of the sums (kind CHORD), bound
      the two sagittas, where that meets tol;
    - else QAC with the role of :func:`roles_many` (kind QAC), bound of
      :func:`qac_error_bound_many`, s_peak its peak on C2.
    Sets the columns kind, swap (cb plays C1: QAC's role, or the longer piece of a
    corner) and q2.
    """
    ca, cb = nodes["ca"], nodes["cb"]
    k = len(ca)
    tol = np.broadcast_to(np.asarray(tol, float), (k,))
    la, lb = pc.length_bounds(ca), pc.length_bounds(cb)
    short = (np.minimum(la, lb) <= np.minimum(0.25 * tol, 1e-7 * np.maximum(la, lb))) | (
        (nodes["depth"] == 0) & (2 * np.minimum(la, lb) <= tol))
    bound, s_peak = np.where(short, 2.0 * np.minimum(la, lb), np.inf), _filled(k, 0.5)
    kind = np.where(short, CORNER, QAC)
    swap, q2 = short & (la <= lb), np.zeros((k, 3, 2))
    tiny = np.nonzero(~short & (nodes["hi"] - nodes["lo"] < TINY_SWEEP))[0]
    if len(tiny):
        chord = _sagitta_many(ca[tiny]) + _sagitta_many(cb[tiny])
        fits = chord <= tol[tiny]
        bound[tiny[fits]], kind[tiny[fits]] = chord[fits], CHORD
    rows = np.nonzero(kind == QAC)[0]
    if len(rows):
        got = roles_many(ca[rows], cb[rows], tol[rows])
        swap[rows], q2[rows], bound[rows], s_peak[rows] = got[:4]
    nodes.update(kind=kind, swap=swap, q2=q2)
    return bound, s_peak


def _corner_piece(ca, cb, sa, sb, long_is_b):
    """A corner node's piece along ca: the longer piece translated by the shorter's
    start, its ends moved to the angle-matched sums of the end points."""
    same = sa == sb
    short, long_ = (ca, cb) if long_is_b else (cb, ca)
    m0 = pc.start(short) if same else pc.end(short)
    m1 = pc.end(short) if same else pc.start(short)
    moved = pc.translate(long_, pc.start(short))
    moved = pc.with_endpoints(moved, pc.start(long_) + m0, pc.end(long_) + m1)
    return moved if (same or not long_is_b) else pc.reverse(moved)


def chord_piece(ca, cb, sa, sb):
    """A nearly straight pair (common sweep below TINY_SWEEP) as one segment along
    ca: the chord between the sums of the angle-matched end points; bound: the two
    sagittas (largest distance of a control point from its chord).  (piece, bound)."""
    b0, b1 = (pc.start(cb), pc.end(cb)) if sa == sb else (pc.end(cb), pc.start(cb))
    bound = float(_sagitta_many(np.asarray(ca, float)[None])[0]
                  + _sagitta_many(np.asarray(cb, float)[None])[0])
    return pc.line(pc.start(ca) + b0, pc.end(ca) + b1), bound


def piece_nodes(nodes):
    """The pieces of nodes accepted by :func:`bound_nodes`, each along ca (its
    direction of travel): a list, None where a QAC piece has a weight <= 0
    (:func:`piece_stacks`'s pieces, row views of its stacks)."""
    ok, groups = piece_stacks(nodes)
    out = [None] * len(ok)
    for rows, stack in groups:
        list(map(out.__setitem__, rows.tolist(), stack))
    return out


def piece_stacks(nodes):
    """:func:`piece_nodes` on arrays: (ok, groups), ``ok`` (k,) True for the nodes
    with a piece, ``groups`` [(rows, stack (len(rows), m+1, 3))] their pieces, each
    node of ``ok`` in one group: the corners (by role), the chords and the QAC pieces
    (by role and form), each kind built for all its nodes at once
    (:func:`corner_pieces`, :func:`chord_pieces`, :func:`qac_stacks`)."""
    ca, cb, sa, sb = nodes["ca"], nodes["cb"], nodes["sa"], nodes["sb"]
    kind, swap = nodes["kind"], nodes["swap"]
    same = sa == sb
    groups = []
    for long_is_b in (False, True):
        rows = np.flatnonzero((kind == CORNER) & (swap == long_is_b))
        if len(rows):
            groups.append((rows, corner_pieces(ca[rows], cb[rows], same[rows], long_is_b)))
    rows = np.flatnonzero(kind == CHORD)
    if len(rows):
        groups.append((rows, chord_pieces(ca[rows], cb[rows], same[rows])))
    for sw in (False, True):
        sel = np.flatnonzero((kind == QAC) & (swap == sw))
        if not len(sel):
            continue
        for rows, stack in qac_stacks((cb if sw else ca)[sel], nodes["q2"][sel]):
            # C1 = cb runs against ca where the two turn opposite ways
            back = ~same[sel[rows]] if sw else np.zeros(len(rows), bool)
            if back.any():
                stack[back] = stack[back][:, ::-1]
            groups.append((sel[rows], stack))
    ok = np.zeros(len(ca), bool)
    for rows, _ in groups:
        ok[rows] = True
    return ok, groups


def _ends(stack):
    """(start, end) points (k, 2) of a stack of pieces (:func:`morph.piece.start`,
    :func:`morph.piece.end` row by row)."""
    return stack[:, 0, :2] / stack[:, 0, 2:], stack[:, -1, :2] / stack[:, -1, 2:]


def corner_pieces(ca, cb, same, long_is_b):
    """:func:`_corner_piece` of the rows of stacks ``ca``, ``cb`` (``same``: sa == sb
    row by row), the same operations on arrays: (k, n+1, 3)."""
    short, long_ = (ca, cb) if long_is_b else (cb, ca)
    s0, s1 = _ends(short)
    m0 = np.where(same[:, None], s0, s1)
    m1 = np.where(same[:, None], s1, s0)
    moved = np.array(long_, float)
    moved[:, :, 0] += s0[:, 0:1] * moved[:, :, 2]
    moved[:, :, 1] += s0[:, 1:2] * moved[:, :, 2]
    l0, l1 = _ends(long_)
    moved[:, 0, :2] = (l0 + m0) * moved[:, 0, 2:]
    moved[:, -1, :2] = (l1 + m1) * moved[:, -1, 2:]
    if long_is_b:
        moved[~same] = moved[~same][:, ::-1]
    return moved


def chord_pieces(ca, cb, same):
    """The pieces of :func:`chord_piece` of the rows of stacks (``same``: sa == sb
    row by row): lines (k, 2, 3)."""
    a0, a1 = _ends(ca)
    c0, c1 = _ends(cb)
    out = np.ones((len(ca), 2, 3))
    out[:, 0, :2] = a0 + np.where(same[:, None], c0, c1)
    out[:, 1, :2] = a1 + np.where(same[:, None], c1, c0)
    return out


def qac_stacks(c1, q2):
    """The pieces of :func:`qac_pieces` whose weights are all positive, as groups
    [(rows of c1, stack)]: the polynomial and the rational rows each in one stack;
    a row whose tangent numerator vanishes at an end (its zero divided out, a lower
    degree) in a group of its own."""
    groups = []
    for rows, _, h, odd in pc.numerator_groups(c1):
        res = _qac_from_numerator(c1[rows], h, q2[rows])
        good = (res[:, :, 2] > 0).all(axis=1) & ~odd
        if good.any():
            groups.append((rows[good], res[good]))
        for r in rows[odd].tolist():
            piece = convolve_qac_piece(c1[r], None, q2[r])
            if np.all(piece[:, 2] > 0):
                groups.append((np.array([r]), piece[None]))
    return groups


def role_pair(nodes, r):
    """(c1, c2) of an accepted node as its piece approximates c1(t) + c2(s(t)): c1
    parametrised like the piece (cb, reversed if need be, where QAC chose cb as C1
    or a corner translates cb)."""
    ca, cb = nodes["ca"][r], nodes["cb"][r]
    if not nodes["swap"][r]:
        return ca, cb
    return (cb if nodes["sa"][r] == nodes["sb"][r] else pc.reverse(cb)), ca


def split_nodes(nodes, s_peak):
    """Split each node at the tangent angle of C2 at its bound's peak (Algorithm 4.1).

    s_peak is clamped to [0.2, 0.8]; the angle is C2's tangent angle there, taken
    in (lo, hi) (the middle of the range where rounding puts it outside); both
    sub-pieces are cut where their tangent has that angle (Eq. 27 on each piece,
    :func:`morph.gauss.angle_params`), so both children are compatible again.
    Returns (left, right): the children over [lo, angle] and [angle, hi].
    The two sides' tangent numerators (and pieces) of one shape are solved and split
    in one call (:func:`stacked_calls`): each row's root and split are its own.
    """
    lo, hi, sa, sb = nodes["lo"], nodes["hi"], nodes["sa"], nodes["sb"]
    s = s_peak.clip(0.2, 0.8)
    ha, hb, swap = nodes["ha"], nodes["hb"], nodes["swap"]
    if ha.shape == hb.shape:   # C2's numerator of each row, evaluated once
        hv = bz.evaluate_many(np.where(swap[:, None, None], ha, hb), s)
    else:
        hv = np.where(swap[:, None], bz.evaluate_many(ha, s), bz.evaluate_many(hb, s))
    th = np.arctan2(hv[:, 1], hv[:, 0])
    th = lo + gauss._wrap(th - lo)
    th = np.where((lo < th) & (th < hi), th, 0.5 * (lo + hi))
    ua, ub = stacked_calls(gauss.angle_params, [(ha, th), (hb, th)])
    cols = ("ca", "ha", "cb", "hb")
    parts = stacked_calls(bz.split_many, [(nodes[c], u) for c, u in zip(cols, (ua, ua, ub, ub))])
    left, right = {"lo": lo, "hi": th}, {"lo": th, "hi": hi}
    for col, (p0, p1), sign in zip(cols, parts, (sa, sa, sb, sb)):
        first = (sign > 0).reshape((-1, 1, 1))    # the part at u < u_split has angles < th
        left[col], right[col] = np.where(first, p0, p1), np.where(first, p1, p0)
    t0, t1 = nodes["t0"], nodes["t1"]
    tm = t0 + ua * (t1 - t0)
    left["t0"], left["t1"] = np.where(sa > 0, t0, tm), np.where(sa > 0, tm, t1)
    right["t0"], right["t1"] = np.where(sa > 0, tm, t0), np.where(sa > 0, t1, tm)
    return left, right


def stacked_calls(func, args):
    """[func(*a) for a in args], the calls whose first arrays have one shape past
    their rows made as one call on the arguments concatenated row-wise (rows of any
    number), its result (an array or a tuple of arrays) cut back: for row-wise
    functions (each row's result its own, as :func:`morph.gauss.angle_params`,
    :func:`morph.bernstein.split_many`, :func:`morph.bernstein.subsegment_many`),
    the same numbers in fewer calls."""
    out = [None] * len(args)
    shapes = [a[0].shape[1:] for a in args]
    for shape in dict.fromkeys(shapes):
        which = [k for k, sh in enumerate(shapes) if sh == shape]
        if len(which) == 1:
            out[which[0]] = func(*args[which[0]])
            continue
        got = func(*(np.concatenate([args[k][c] for k in which])
                     for c in range(len(args[which[0]]))))
        ends = np.cumsum([len(args[k][0]) for k in which]).tolist()
        for k, a, b in zip(which, [0] + ends[:-1], ends):
            out[k] = tuple(g[a:b] for g in got) if isinstance(got, tuple) else got[a:b]
    return out

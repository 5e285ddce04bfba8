"""Convolution curves of two regions (Sec. 3.3) with the QAC method (Sec. 4.4).

The convolution C1 * C2 is the set of sums C1(t) + C2(s) where the tangents (so the
normals) point the same way (Def. 1.1, Eqs. 2-4).  Each loop is first turned into its
Gauss map (:mod:`morph.gauss`); every pair of edges of the two Gauss maps whose angle
ranges overlap contributes one convolution piece:

- curve + curve: approximated by QAC (:func:`convolve_qac`), normals exact;
- curve + vertex: the curve translated by the vertex (exact);
- line + anything: the segment translated by the other edge's point at its angle;
- vertex + vertex: a single point, dropped.

Direction (Figs. 18-19): a piece made from edge X (traversed as in its loop) and edge
Y runs along X's own direction when Y is convex (sign > 0) and against it when Y is
concave, as in polygon convolution (edge + vertex takes the sign of the vertex's
turn).  This gives convex/convex pairs their inherited direction, reverses
concave/convex pairs where the concave side has the larger curvature, and reverses
concave/concave pairs, so every convolution loop is consistently oriented.

Type (Fig. 20): 1 for convex/convex (straight segments count as convex here), 2 for
convex/concave, 3 for concave/concave or concave/straight pairs and pairs with a
concave vertex.  Type 3 pieces never reach the Minkowski sum boundary.

Equal angles are resolved by a symbolic perturbation: every angle of the second shape
is taken as if increased by an infinitesimal epsilon, so a straight edge of A at
angle theta pairs with the edge of B whose range is (lo, hi] around theta, a straight
edge of B with A's [lo, hi), and two parallel segments never pair directly.  This
keeps the pieces of one loop pair chained end to end.
"""

from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np

from . import bernstein as bz
from . import gauss
from . import piece as pc
from .errors import ToleranceNotMetError

ANGLE_EQ = 1e-9      # angles closer than this are equal (radians)
TINY_SWEEP = 1e-7    # below this common sweep two curves are treated as straight


@dataclass
class ConvPiece:
    """One oriented piece of a convolution curve.

    piece: (n+1, 3) homogeneous control points, already in travel direction.
    kind: "qac", "translate", "chord".  type: 1, 2 or 3 (Fig. 20).  bound: a-priori
    bound on its distance to the exact convolution (0 for exact pieces).
    source: (loop index in A, edge index, loop index in B, edge index).
    """

    piece: np.ndarray
    kind: str
    type: int
    bound: float = 0.0
    source: tuple = field(default_factory=tuple)


# ------------------------------------------------------------------------- QAC

def quadratic_approximation(c2):
    """Q2 of Eq. 38: end points of C2 and the intersection of its end tangents.

    Returns the (3, 2) control points.  Raises ValueError when the end tangents are
    parallel (C2 straight or turning by pi).
    """
    p = pc.cartesian(c2)
    t0, t1 = pc.end_tangents(c2)
    q0, q2 = p[0], p[-1]
    det = pc.cross2(t0, t1)
    if abs(det) < 1e-14:
        raise ValueError("end tangents are parallel: no tangent intersection")
    # q0 + a t0 = q2 - b t1  ->  a t0 + b t1 = q2 - q0   (Eq. 38: tangent intersection)
    a = pc.cross2(q2 - q0, t1) / det
    return np.array([q0, q0 + a * t0, q2])


def _product_scatter(m, n):
    """Matrix S with S @ outer(a, b).ravel() = Bernstein product of degrees m and n."""
    key = (m, n)
    s = _SCATTER.get(key)
    if s is None:
        w = bz._product_matrix(m, n)
        i, j = np.meshgrid(np.arange(m + 1), np.arange(n + 1), indexing="ij")
        s = np.zeros((m + n + 1, (m + 1) * (n + 1)))
        s[(i + j).ravel(), np.arange((m + 1) * (n + 1))] = w.ravel()
        _SCATTER[key] = s
    return s


_SCATTER = {}
_SPLIT_HALF = {}


def _mul(a, b):
    """Bernstein product (as :func:`morph.bernstein.multiply`) as one matrix product.

    a, b: (m+1,) or (m+1, d) and (n+1,) or (n+1, d) (one of them may be 1-D).
    """
    m, n = len(a) - 1, len(b) - 1
    s = _product_scatter(m, n)
    if a.ndim == 1 and b.ndim == 1:
        return s @ np.outer(a, b).ravel()
    a2 = a if a.ndim == 2 else a[:, None]
    b2 = b if b.ndim == 2 else b[:, None]
    return s @ (a2[:, None, :] * b2[None, :, :]).reshape((m + 1) * (n + 1), -1)


def _halves(c):
    """Coefficients of c on [0, 1/2] and [1/2, 1] (de Casteljau at 1/2, as matrices)."""
    n = len(c) - 1
    mats = _SPLIT_HALF.get(n)
    if mats is None:
        mats = bz.split(np.eye(n + 1), 0.5)
        _SPLIT_HALF[n] = mats
    return mats[0] @ c, mats[1] @ c


def _ratio_bound(a, b, halvings=1):
    """Upper bound of max a(s) / b(s) on [0, 1] for Bernstein a, b of one degree, b > 0.

    sum a_i B_i / sum b_i B_i <= max_i a_i / b_i when every b_i > 0 (mediant
    inequality, the convex hull property with weights); the bound is taken on each
    of 2**halvings equal sub-intervals (de Casteljau), which tightens it.  Returns
    (bound, s) with s the parameter of the largest ratio, or (inf, 0.5) when a
    coefficient of b is not positive.
    """
    parts = [(a, b, 0.0, 1.0)]
    for _ in range(halvings):
        nxt = []
        for pa, pb, s0, s1 in parts:
            (la, ra), (lb, rb) = _halves(pa), _halves(pb)
            sm = 0.5 * (s0 + s1)
            nxt += [(la, lb, s0, sm), (ra, rb, sm, s1)]
        parts = nxt
    ratios, where = [], []
    for pa, pb, s0, s1 in parts:
        if not np.all(pb > 0):
            return np.inf, 0.5
        ratios.append(pa / pb)
        where.append(s0 + (s1 - s0) * np.arange(len(pa)) / (len(pa) - 1))
    r, s = np.concatenate(ratios), np.concatenate(where)
    best = float(r.max())
    # the first coefficient within RATIO_TIE of the largest: near-ties (symmetric
    # pieces) are decided the same way whatever the rounding
    k = int(np.argmax(r >= best - RATIO_TIE * abs(best)))
    return best, float(s[k])


RATIO_TIE = 1e-9


def _sq_norm(g):
    """|g|^2 of a planar Bernstein polynomial g (shape (m+1, 2)), degree 2m."""
    return _mul(g[:, 0], g[:, 0]) + _mul(g[:, 1], g[:, 1])


def qac_parametric_bound(c2, q2):
    """A-priori bound of max_s |C2(s) - Q2(s)| at equal parameters (Eqs. 39-40).

    e(s)^2 = |X2(s) - W2(s) Q2(s)|^2 / W2(s)^2: both are Bernstein polynomials, and
    the largest ratio of their coefficients (degree-matched, on the two halves of
    [0, 1]) bounds e^2 (:func:`_ratio_bound`; this is at least as tight as dividing
    the largest numerator coefficient by the smallest weight coefficient, the
    paper's Eq. 40).  Returns (bound, s_peak) with s_peak the parameter of C2 where
    the bound peaks.  Loose for cubic C2 (it measures the parametrisations' mismatch
    too, O(h^2) on a piece of size h); :func:`qac_error_bound` is the geometric one.
    """
    origin = c2[0, :2] / c2[0, 2]
    w = c2[:, 2]
    x = c2[:, :2] - w[:, None] * origin
    num = bz.elevate(x, 2) - _mul(w, q2 - origin)
    sq = _sq_norm(num)
    den = bz.to_degree(_mul(w, w), len(sq) - 1)
    r, s = _ratio_bound(sq, den)
    return float(np.sqrt(max(r, 0.0))), s


REPARAM_DEGREE = 4   # degree of the parameter map r(s) of :func:`qac_error_bound`
_FIT_S = 0.5 - 0.5 * np.cos(np.pi * (np.arange(9) + 0.5) / 9)   # Chebyshev nodes


def _compose(c, r):
    """Bernstein coefficients of c(r(s)) (c: (n+1, d), r: (k+1,) with values in [0,1])."""
    n = len(c) - 1
    if n == 0:
        return np.repeat(c, len(r), axis=0)
    u = 1.0 - r
    pr, pu = [None, r], [None, u]
    for _ in range(2, n + 1):
        pr.append(_mul(pr[-1], r))
        pu.append(_mul(pu[-1], u))
    binom = bz._binomials(n)
    rows = [binom[0] * pu[n]]
    rows += [binom[i] * _mul(pr[i], pu[n - i]) for i in range(1, n)]
    rows.append(binom[n] * pr[n])
    return np.column_stack(rows) @ c


def _foot_params(c2, pts, sig, iters=6):
    """Parameters of C2 nearest to pts by Newton on (C2 - p) . C2' = 0 from sig."""
    d1 = bz.derivative(c2)
    d2 = bz.derivative(d1) if len(d1) > 1 else np.zeros((1, 3))
    for _ in range(iters):
        v, v1, v2 = bz.evaluate(c2, sig), bz.evaluate(d1, sig), bz.evaluate(d2, sig)
        w, w1, w2 = v[:, 2:], v1[:, 2:], v2[:, 2:]
        p = v[:, :2] / w
        d = (v1[:, :2] - w1 * p) / w
        dd = (v2[:, :2] - 2.0 * w1 * d - w2 * p) / w
        diff = p - pts
        f = np.sum(diff * d, axis=1)
        fp = np.sum(d * d, axis=1) + np.sum(diff * dd, axis=1)
        ok = fp > 0
        sig = np.clip(sig - np.where(ok, f / np.where(ok, fp, 1.0), 0.0), 0.0, 1.0)
    return sig


def qac_error_bound(c2, q2, tol=None):
    """Certified bound of the distance from the quadratic Q2 to the curve C2 (Sec. 4.4).

    A QAC piece is C1(t) + Q2(s(t)) (exact normals), so its distance measure
    (Eqs. 49-53: the point minus C1(t), distance to the curve C2) is at most
    max_s dist(Q2(s), C2) <= max_s |Q2(s) - C2(r(s))| for *any* map r of [0, 1]
    into [0, 1].  Eq. 40 takes r(s) = s, which also counts the mismatch of the two
    parametrisations (O(h^2) on a piece of size h, against O(h^4) for the geometric
    distance): ~400x too much on small cubic pieces.  Here r is a polynomial of
    degree REPARAM_DEGREE with r(0) = 0, r(1) = 1, fitted by least squares to the
    nearest-point parameters of C2 at a few points of Q2, its Bernstein coefficients
    clamped to [0, 1] (so r(s) stays in [0, 1]).  The fit is only a choice of r; the
    bound is certified for the r chosen: C2(r(s)) = X(s) / W(s) is an exact rational
    Bernstein composition, |X - W Q2|^2 and W^2 are Bernstein polynomials, and the
    largest ratio of their coefficients on the two halves of [0, 1] bounds the
    squared distance (:func:`_ratio_bound`).  The result is the smaller of this and
    :func:`qac_parametric_bound` (both are upper bounds); when ``tol`` is given and
    the parametric bound already meets it, that one is returned without the fit.

    Returns (bound, s_peak): s_peak is C2's parameter where the bound peaks, the
    place Algorithm 4.1 subdivides.
    """
    par, s_par = qac_parametric_bound(c2, q2)
    if (tol is not None and par <= tol) or par <= 0.0 or not np.isfinite(par):
        return par, s_par
    return _reparam_bound(c2, q2, par, s_par)


def _reparam_bound(c2, q2, par, s_par):
    """The reparametrised bound of :func:`qac_error_bound`, or (par, s_par) if larger."""
    origin = c2[0, :2] / c2[0, 2]
    c = c2.copy()
    c[:, :2] -= c[:, 2:3] * origin
    q = q2 - origin
    k = REPARAM_DEGREE
    try:
        sig = _foot_params(c, bz.evaluate(q, _FIT_S), _FIT_S.copy())
    except FloatingPointError:
        return par, s_par
    basis = bz.basis(k, _FIT_S)
    coef = np.linalg.lstsq(basis[:, 1:k], sig - basis[:, k], rcond=None)[0]
    if not np.all(np.isfinite(coef)):
        return par, s_par
    r = np.concatenate([[0.0], np.clip(coef, 0.0, 1.0), [1.0]])
    cr = _compose(c, r)
    x, w = cr[:, :2], cr[:, 2]
    if np.ptp(w) <= 1e-14 * abs(w[0]):           # polynomial C2: W constant
        g = x / w[0] - bz.to_degree(q, len(x) - 1)
        a = _sq_norm(g)
        b = np.ones(len(a))
    else:
        g = bz.elevate(x, 2) - _mul(w, q)
        a = _sq_norm(g)
        b = bz.to_degree(_mul(w, w), len(a) - 1)
    ratio, s = _ratio_bound(a, b)
    bound = float(np.sqrt(max(ratio, 0.0)))
    if not bound < par:
        return par, s_par
    return bound, float(bz.evaluate(r, [s])[0])


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
    angle range (compatible, Sec. 3.2).
    """
    q = quadratic_approximation(c2) if q2 is None else q2
    h1 = pc.tangent_numerator(c1)
    d0, d1 = q[1] - q[0], q[2] - q[1]
    num = h1[:, 0] * d0[1] - h1[:, 1] * d0[0]          # Eq. 36 numerator
    dd = d0 - d1
    den = h1[:, 0] * dd[1] - h1[:, 1] * dd[0]          # Eq. 36 denominator
    if np.mean(den) < 0:
        num, den = -num, -den
    m0 = bz.multiply(den - num, den - num)
    m1 = 2.0 * bz.multiply(num, den - num)
    m2 = bz.multiply(num, num)
    dsq = m0 + m1 + m2                                  # = D^2
    qpart = (m0[:, None] * q[0] + m1[:, None] * q[1] + m2[:, None] * q[2])
    w1 = c1[:, 2]
    x = bz.multiply(c1[:, :2], dsq[:, None]) + bz.multiply(w1[:, None], qpart)
    w = bz.multiply(w1, dsq)
    return np.column_stack([x, w])


def _out_degree(c1):
    d = len(c1) - 1
    return 3 * d - 2 if pc.is_polynomial(c1) else 5 * d - 4


def _roles(ca, cb, tol=None):
    """Role choice of :func:`choose_roles`, with the chosen bound and its peak.

    Returns (swap, q2, bound, s_peak); q2 is None (bound inf) when neither piece has
    a tangent intersection.  With ``tol``, the cheap parametric bound decides when
    one role meets tol with it; otherwise both roles get the geometric bound.
    """
    cand = []
    for swap, c1, c2 in ((False, ca, cb), (True, cb, ca)):
        try:
            q2 = quadratic_approximation(c2)
        except ValueError:
            continue
        bound, s = qac_parametric_bound(c2, q2)
        cand.append([bound, _out_degree(c1), swap, q2, s, c2])
    if not cand:
        return False, None, np.inf, 0.5
    if tol is None or min(c[0] for c in cand) > tol:
        for c in cand:
            if 0.0 < c[0] < np.inf:
                c[0], c[4] = _reparam_bound(c[5], c[3], c[0], c[4])
    # smaller bound first, then the lower output degree; swap=False on a tie
    best = min(cand, key=lambda c: (c[0], c[1], c[2]))
    return best[2], best[3], best[0], best[4]


def choose_roles(ca, cb, tol=None):
    """Pick which piece plays C2 (the one replaced by a quadratic), Sec. 4.4.

    The bound (:func:`qac_error_bound`) depends only on C2, so C2 is the piece with
    the smaller bound (a polynomial quadratic, e.g. a TrueType segment, gives 0:
    exact); ties go to the lower output degree.  Returns (swap, q2): swap is True
    when cb plays C1.
    """
    swap, q2, _, _ = _roles(ca, cb, tol)
    return swap, q2


# ------------------------------------------------------------- batched QAC forms
# The functions above take one pair; these take stacks (k, n+1, 3) of pieces of one
# degree and give the same results row by row (tests/test_convolve.py checks them
# against each other).  Algorithm 4.1 (:func:`_qac_driver`) calls only these.

def quadratic_approximation_many(c2):
    """:func:`quadratic_approximation` of each row of a stack: (q2 (k, 3, 2), ok (k,)).

    ok is False where the end tangents are parallel (or the piece has no length)."""
    p = c2[:, :, :2] / c2[:, :, 2:3]
    size = np.maximum(np.ptp(p, axis=1).max(axis=1), 1e-300)
    d = np.diff(p, axis=1)
    norms = np.hypot(d[..., 0], d[..., 1])
    nz = norms > 1e-12 * size[:, None]
    first = np.argmax(nz, axis=1)
    last = nz.shape[1] - 1 - np.argmax(nz[:, ::-1], axis=1)
    rows = np.arange(len(p))
    with np.errstate(divide="ignore", invalid="ignore"):
        t0 = d[rows, first] / norms[rows, first, None]
        t1 = d[rows, last] / norms[rows, last, None]
        q0, q2 = p[:, 0], p[:, -1]
        det = pc.cross2(t0, t1)
        ok = nz.any(axis=1) & (size > 1e-300) & (np.abs(det) >= 1e-14)
        a = pc.cross2(q2 - q0, t1) / np.where(ok, det, 1.0)   # Eq. 38
    q = np.stack([q0, q0 + a[:, None] * t0, q2], axis=1)
    return q, ok


def _ratio_bound_many(a, b):
    """:func:`_ratio_bound` (one halving) of each row of stacks a, b (k, n+1)."""
    n = a.shape[1] - 1
    la, ra = bz.halves_many(a)
    lb, rb = bz.halves_many(b)
    num = np.concatenate([la, ra], axis=1)
    den = np.concatenate([lb, rb], axis=1)
    good = np.all(den > 0, axis=1)
    with np.errstate(divide="ignore", invalid="ignore"):
        r = num / np.where(den > 0, den, 1.0)
    best = r.max(axis=1)
    k = np.argmax(r >= (best - RATIO_TIE * np.abs(best))[:, None], axis=1)
    s = np.where(k <= n, 0.5 * k / n, 0.5 + 0.5 * (k - n - 1) / n)
    return np.where(good, best, np.inf), np.where(good, s, 0.5)


def _sq_norm_many(g):
    return bz.multiply_many(g[..., 0], g[..., 0]) + bz.multiply_many(g[..., 1], g[..., 1])


def qac_parametric_bound_many(c2, q2):
    """:func:`qac_parametric_bound` of each row: (bound (k,), s_peak (k,))."""
    origin = c2[:, 0, :2] / c2[:, 0, 2:3]
    w = c2[:, :, 2]
    x = c2[:, :, :2] - w[:, :, None] * origin[:, None]
    num = bz.elevate_many(x, 2) - bz.multiply_many(w, q2 - origin[:, None])
    sq = _sq_norm_many(num)
    den = bz.elevate_many(bz.multiply_many(w, w), sq.shape[1] - 2 * w.shape[1] + 1)
    r, s = _ratio_bound_many(sq, den)
    return np.sqrt(np.maximum(r, 0.0)), s


@lru_cache(maxsize=None)
def _fit_matrices():
    basis = bz.basis(REPARAM_DEGREE, _FIT_S)
    k = REPARAM_DEGREE
    return np.linalg.pinv(basis[:, 1:k]), basis[:, k], bz.basis(2, _FIT_S)


def _compose_many(c, r):
    """:func:`_compose` row by row: c (k, n+1, d), r (k, m+1) -> (k, n m + 1, d)."""
    n = c.shape[1] - 1
    u = 1.0 - r
    pr, pu = [None, r], [None, u]
    for _ in range(2, n + 1):
        pr.append(bz.multiply_many(pr[-1], r))
        pu.append(bz.multiply_many(pu[-1], u))
    binom = bz._binomials(n)
    rows = [binom[0] * pu[n]]
    rows += [binom[i] * bz.multiply_many(pr[i], pu[n - i]) for i in range(1, n)]
    rows.append(binom[n] * pr[n])
    return np.sum(np.stack(rows, axis=2)[..., None] * c[:, None], axis=2)


def _foot_params_many(c2, pts, sig, iters=6):
    """:func:`_foot_params` row by row: c2 (k, n+1, 3), pts (k, m, 2), sig (k, m)."""
    n = c2.shape[1] - 1
    for _ in range(iters):
        v, v1, v2 = _jet2(c2, sig, n)
        w, w1, w2 = v[..., 2:], v1[..., 2:], v2[..., 2:]
        p = v[..., :2] / w
        d = (v1[..., :2] - w1 * p) / w
        dd = (v2[..., :2] - 2.0 * w1 * d - w2 * p) / w
        diff = p - pts
        f = np.sum(diff * d, axis=2)
        fp = np.sum(d * d, axis=2) + np.sum(diff * dd, axis=2)
        ok = fp > 0
        sig = np.clip(sig - np.where(ok, f / np.where(ok, fp, 1.0), 0.0), 0.0, 1.0)
    return sig


def _jet2(c, s, n):
    """Values, first and second derivatives of the stack c (k, n+1, 3) at the
    parameters s (k, m), by de Casteljau: the last three levels of the triangle
    give them (P' = n (b1 - b0), P'' = n (n-1) (b2 - 2 b1 + b0) one level up)."""
    t = s[:, :, None, None]
    work = np.broadcast_to(c[:, None], (c.shape[0], s.shape[1]) + c.shape[1:])
    for _ in range(max(n - 2, 0)):
        work = work[:, :, :-1] + t * (work[:, :, 1:] - work[:, :, :-1])
    if n < 2:
        lev1 = work
        zero = np.zeros(work.shape[:2] + work.shape[3:])
        if n == 0:
            return work[:, :, 0], zero, zero
        return (lev1[:, :, 0] + s[..., None] * (lev1[:, :, 1] - lev1[:, :, 0]),
                lev1[:, :, 1] - lev1[:, :, 0], zero)
    lev1 = work[:, :, :-1] + t * (work[:, :, 1:] - work[:, :, :-1])
    d2 = n * (n - 1) * (work[:, :, 2] - 2 * work[:, :, 1] + work[:, :, 0])
    d1 = n * (lev1[:, :, 1] - lev1[:, :, 0])
    v = lev1[:, :, 0] + s[..., None] * (lev1[:, :, 1] - lev1[:, :, 0])
    return v, d1, d2


def _reparam_bound_many(c2, q2, par, s_par):
    """:func:`_reparam_bound` of each row: (bound, s_peak), (par, s_par) kept where
    the reparametrised bound is not smaller."""
    pinv, last, qbasis = _fit_matrices()
    origin = c2[:, 0, :2] / c2[:, 0, 2:3]
    c = c2.copy()
    c[:, :, :2] -= c[:, :, 2:3] * origin[:, None]
    q = q2 - origin[:, None]
    bound, s_out = par.copy(), s_par.copy()
    with np.errstate(all="ignore"):
        sig = _foot_params_many(c, np.matmul(qbasis, q),
                                np.tile(_FIT_S, (len(c), 1)))
        coef = (sig - last) @ pinv.T
        fine = np.all(np.isfinite(coef), axis=1)
        r = np.concatenate([np.zeros((len(c), 1)), np.clip(coef, 0.0, 1.0),
                            np.ones((len(c), 1))], axis=1)
        cr = _compose_many(c, np.where(fine[:, None], r, 0.0))
        x, w = cr[:, :, :2], cr[:, :, 2]
        flat = np.ptp(w, axis=1) <= 1e-14 * np.abs(w[:, 0])      # polynomial C2
        for rows, poly in ((np.nonzero(flat)[0], True), (np.nonzero(~flat)[0], False)):
            if not len(rows):
                continue
            if poly:
                g = x[rows] / w[rows, :1, None] - bz.elevate_many(q[rows], x.shape[1] - 3)
                a = _sq_norm_many(g)
                b = np.ones_like(a)
            else:
                g = bz.elevate_many(x[rows], 2) - bz.multiply_many(w[rows], q[rows])
                a = _sq_norm_many(g)
                ww = bz.multiply_many(w[rows], w[rows])
                b = bz.elevate_many(ww, a.shape[1] - ww.shape[1])
            ratio, s = _ratio_bound_many(a, b)
            bnd = np.sqrt(np.maximum(ratio, 0.0))
            better = fine[rows] & (bnd < par[rows])
            sel = rows[better]
            bound[sel] = bnd[better]
            s_out[sel] = bz.evaluate_many(r[sel], s[better])
    return bound, s_out


def convolve_qac_many(c1, q2, rational):
    """:func:`convolve_qac_piece` of each row of a stack c1 (k, n+1, 3) (all
    polynomial, or all rational: ``rational``) with the quadratics q2 (k, 3, 2).
    Rows whose tangent numerator vanishes at an end (``pc.end_zero_rows``) must go
    through :func:`convolve_qac_piece` (their numerator has a lower degree)."""
    h1 = pc.tangent_numerator_many(c1, rational)
    d0, d1 = q2[:, 1] - q2[:, 0], q2[:, 2] - q2[:, 1]
    num = h1[:, :, 0] * d0[:, None, 1] - h1[:, :, 1] * d0[:, None, 0]   # Eq. 36
    dd = d0 - d1
    den = h1[:, :, 0] * dd[:, None, 1] - h1[:, :, 1] * dd[:, None, 0]
    flip = np.where(np.mean(den, axis=1) < 0, -1.0, 1.0)[:, None]
    num, den = num * flip, den * flip
    m0 = bz.multiply_many(den - num, den - num)
    m1 = 2.0 * bz.multiply_many(num, den - num)
    m2 = bz.multiply_many(num, num)
    dsq = m0 + m1 + m2
    qpart = (m0[:, :, None] * q2[:, None, 0] + m1[:, :, None] * q2[:, None, 1]
             + m2[:, :, None] * q2[:, None, 2])
    w1 = c1[:, :, 2]
    x = bz.multiply_many(c1[:, :, :2], dsq[:, :, None]) + bz.multiply_many(w1[:, :, None], qpart)
    w = bz.multiply_many(w1, dsq)
    return np.concatenate([x, w[:, :, None]], axis=2)


# ---------------------------------------------------------------- edge pairing

class _EdgeTable:
    """The edges of several loops' Gauss maps as arrays, one row per edge.

    loop, index: the loop and the edge's index in it.  curved: curve edges that
    turn (sweep != 0); straight: curve edges with sweep 0; vertex: corners.
    deg, slot: each curve edge's piece is ``stacks[deg][slot]``.  h: tangent
    numerators of the curved edges (``piece.tangent_numerator``), elevated to one
    degree (zeros elsewhere), for :func:`morph.gauss.angle_params`.
    """

    def __init__(self, maps):
        edges = [e for m in maps for e in m]
        self.edges = edges
        self.loop = np.repeat(np.arange(len(maps)), [len(m) for m in maps])
        self.index = np.concatenate([np.arange(len(m)) for m in maps]) if maps else np.zeros(0, int)
        is_curve = np.array([e.kind == "curve" for e in edges], bool)
        self.theta = np.array([e.theta for e in edges], float)
        self.sweep = np.array([e.sweep for e in edges], float)
        self.lo = np.minimum(self.theta, self.theta + self.sweep)
        self.hi = np.maximum(self.theta, self.theta + self.sweep)
        self.sign = np.sign(self.sweep).astype(int)
        self.point = np.array([np.asarray(e.point, float) for e in edges]).reshape(-1, 2)
        self.vertex = ~is_curve
        self.straight = is_curve & (self.sweep == 0.0)
        self.curved = is_curve & (self.sweep != 0.0)
        n = len(edges)
        self.deg = np.full(n, -1)
        self.slot = np.zeros(n, int)
        self.stacks = {}
        lists = {}
        for i in np.nonzero(is_curve)[0]:
            p = np.asarray(edges[i].piece, float)
            d = len(p) - 1
            lst = lists.setdefault(d, [])
            self.deg[i], self.slot[i] = d, len(lst)
            lst.append(p)
        self.stacks = {d: np.array(lst) for d, lst in lists.items()}
        self.h = self._tangent_numerators()

    def pieces(self, idx):
        """Stacks of the pieces of edges idx, grouped by degree: [(rows, stack)]."""
        out = []
        deg = self.deg[idx]
        for d in np.unique(deg):
            rows = np.nonzero(deg == d)[0]
            out.append((rows, self.stacks[d][self.slot[idx[rows]]]))
        return out

    def _tangent_numerators(self):
        idx = np.nonzero(self.curved)[0]
        parts = []
        for rows, st in self.pieces(idx):
            poly = pc.is_polynomial_many(st)
            for sel, rational in ((poly, False), (~poly, True)):
                if sel.any():
                    h = pc.tangent_numerator_many(st[sel], rational)
                    hs = list(h)
                    for r in np.nonzero(pc.end_zero_rows(h))[0]:
                        hs[r] = pc.tangent_numerator(st[sel][r])   # ends divided out
                    parts.append((idx[rows[sel]], hs))
        deg = max([len(h) - 1 for _, hs in parts for h in hs], default=0)
        out = np.zeros((len(self.edges), deg + 1, 2))
        for ids, hs in parts:
            for i, h in zip(ids, hs):
                out[i] = bz.to_degree(h, deg)
        return out

    def params(self, idx, angle):
        """Parameters of the curved edges idx where their tangent angle is ``angle``
        (an angle within 1e-13 of the edge's start or end angle gives that end, as
        :func:`morph.gauss.restrict`)."""
        t = gauss.angle_params(self.h[idx], angle) if len(idx) else np.zeros(0)
        t = np.where(np.abs(angle - (self.theta[idx] + self.sweep[idx])) < 1e-13, 1.0, t)
        return np.where(np.abs(angle - self.theta[idx]) < 1e-13, 0.0, t)

    def restricted(self, idx, t_lo, t_hi):
        """Sub-pieces of the curved edges idx between the parameters at their angles
        lo and hi, in each edge's direction: [(rows, stack)] by degree."""
        conv = self.sweep[idx] > 0
        t0 = np.where(conv, t_lo, t_hi)
        t1 = np.where(conv, t_hi, t_lo)
        out = []
        for rows, st in self.pieces(idx):
            out.append((rows, bz.subsegment_many(st, t0[rows], t1[rows])))
        return out

    def points_at(self, idx, angle):
        """Point of each edge idx with tangent angle ``angle`` (:func:`gauss.point_at_angle`)."""
        pts = self.point[idx].copy()
        cur = np.nonzero(self.curved[idx])[0]
        if len(cur):
            t = self.params(idx[cur], angle[cur])
            for rows, st in self.pieces(idx[cur]):
                v = bz.evaluate_many(st, t[rows])
                pts[cur[rows]] = v[:, :2] / v[:, 2:3]
        return pts


def _pair_table(ta, tb, block=1 << 21):
    """All compatible pairs of the edges of two tables (every loop of A with every
    loop of B): arrays (i, j, lo, hi, k) in the order of :func:`compatible_pairs`
    applied loop pair by loop pair (loops of A, then of B; proper pairs, then A's
    straight edges, then B's; row-major within each)."""
    out = [[] for _ in range(6)]
    a_line_all = ta.straight
    b_line = tb.straight[None, :]
    bmid = 0.5 * (tb.lo + tb.hi)
    step = max(1, block // max(1, len(tb.lo)))
    for s in range(0, len(ta.lo), step):
        alo, ahi = ta.lo[s:s + step, None], ta.hi[s:s + step, None]
        amid = 0.5 * (alo + ahi)
        k = np.round((amid - bmid[None, :]) / gauss.TWO_PI)
        sblo = tb.lo[None, :] + gauss.TWO_PI * k
        sbhi = tb.hi[None, :] + gauss.TWO_PI * k
        lo = np.maximum(alo, sblo)
        hi = np.minimum(ahi, sbhi)
        a_line = a_line_all[s:s + step, None]
        proper = (hi - lo > ANGLE_EQ) & ~a_line & ~b_line
        # straight edge of A at theta: B range (lo, hi]  (B perturbed by +eps)
        a_match = a_line & ~b_line & (alo - sblo > ANGLE_EQ) & (alo - sbhi <= ANGLE_EQ)
        # straight edge of B at theta: A range [lo, hi)
        b_match = b_line & ~a_line & (sblo - alo >= -ANGLE_EQ) & (ahi - sblo > ANGLE_EQ)
        for cls, (mask, plo, phi) in enumerate(((proper, lo, hi),
                                                (a_match, np.broadcast_to(alo, lo.shape),
                                                 np.broadcast_to(alo, lo.shape)),
                                                (b_match, sblo, sblo))):
            ii, jj = np.nonzero(mask)
            out[0].append(ii + s)
            out[1].append(jj)
            out[2].append(plo[ii, jj])
            out[3].append(phi[ii, jj])
            out[4].append(k[ii, jj])
            out[5].append(np.full(len(ii), cls))
    i, j, lo, hi, k, cls = (np.concatenate(x) if x else np.zeros(0) for x in out)
    i, j, cls = i.astype(int), j.astype(int), cls.astype(int)
    order = np.lexsort((j, i, cls, tb.loop[j], ta.loop[i]))
    return i[order], j[order], lo[order], hi[order], k[order]


def compatible_pairs(edges_a, edges_b):
    """Pairs (i, j, lo, hi, k) of edges whose tangent-angle ranges overlap (Sec. 3.2).

    lo, hi are in A's lifted angles; B's angles are shifted by 2 pi k.  Uses the
    epsilon rule of the module docstring for equal angles; a zero-length overlap
    (lo == hi) is returned only for straight edges, whose convolution is a
    translated segment.
    """
    i, j, lo, hi, k = _pair_table(_EdgeTable([edges_a]), _EdgeTable([edges_b]))
    return list(zip(i.tolist(), j.tolist(), lo.tolist(), hi.tolist(), k.tolist()))


def pair_type(sa, sb, a_vertex=False, b_vertex=False):
    """Fig. 20 type of a pair from the signs of its two edges (+1, 0, -1).

    Type 3 (never on the boundary): concave/concave or concave/straight pairs, and
    any pair with a concave vertex.  Works elementwise on arrays too.
    """
    sa, sb = np.asarray(sa), np.asarray(sb)
    t3 = ((np.asarray(a_vertex) & (sa < 0)) | (np.asarray(b_vertex) & (sb < 0))
          | ((sa < 0) & (sb <= 0)) | ((sb < 0) & (sa <= 0)))
    typ = np.where(t3, 3, np.where((sa >= 0) & (sb >= 0), 1, 2))
    return int(typ) if typ.ndim == 0 else typ


def _oriented(piece, forward):
    return piece if forward else pc.reverse(piece)


def _translate_many(st, offset):
    """Pieces of a stack moved by offsets (k, 2) (exact: X += ox W, Y += oy W)."""
    out = st.copy()
    out[:, :, :2] += offset[:, None, :] * st[:, :, 2:3]
    return out


def convolve_edges(ea, eb, lo, hi, shift, tol, max_depth=30, method="qac"):
    """Convolution pieces of one compatible pair of edges (A's angles lo..hi).

    ``shift`` is the multiple of 2 pi added to B's angles.  Returns a list of
    (piece, kind, bound).  Curve + curve pairs go through QAC with subdivision of
    the angle range where the error of Eq. 40 peaks (Algorithm 4.1) until every
    bound <= tol; raises ToleranceNotMetError past ``max_depth`` halvings.
    """
    ta, tb = _EdgeTable([[ea]]), _EdgeTable([[eb]])
    pairs = tuple(np.array([x]) for x in (0, 0, lo, hi, shift))
    res = _convolve_table(ta, tb, pairs, tol, max_depth, method)
    return [(p, kind, b) for _, p, kind, b in res]


def _convolve_table(ta, tb, pairs, tol, max_depth=30, method="qac"):
    """Convolution pieces of the pairs (i, j, lo, hi, k) of two edge tables, all at
    once: [(pair position, piece, kind, bound)] in the pairs' order, each pair's
    pieces in travel order (the cases of the module docstring)."""
    i, j, lo, hi, k = pairs
    off = gauss.TWO_PI * np.asarray(k, float)
    sa, sb = ta.sign[i], tb.sign[j]
    a_line, b_line = ta.straight[i], tb.straight[j]
    a_curve, b_curve = ta.curved[i], tb.curved[j]
    out = []   # (pair position, sort key, piece, kind, bound)

    def emit(pos, stack, forward, kind, bounds=None):
        for r, p in enumerate(stack):
            out.append((pos[r], 0.0, p if forward[r] else p[::-1].copy(), kind,
                        0.0 if bounds is None else float(bounds[r])))

    # segment of A translated by B's point at that angle; direction by B's sign
    pos = np.nonzero(a_line)[0]
    if len(pos):
        pts = tb.points_at(j[pos], lo[pos] - off[pos])
        for rows, st in ta.pieces(i[pos]):
            emit(pos[rows], _translate_many(st, pts[rows]), sb[pos[rows]] > 0, "translate")
    pos = np.nonzero(b_line & ~a_line)[0]
    if len(pos):
        pts = ta.points_at(i[pos], lo[pos])
        for rows, st in tb.pieces(j[pos]):
            emit(pos[rows], _translate_many(st, pts[rows]), sa[pos[rows]] > 0, "translate")
    # curve + vertex: the restricted curve translated by the vertex
    pos = np.nonzero(a_curve & tb.vertex[j])[0]
    if len(pos):
        ii = i[pos]
        subs = ta.restricted(ii, ta.params(ii, lo[pos]), ta.params(ii, hi[pos]))
        for rows, st in subs:
            p = pos[rows]
            emit(p, _translate_many(st, tb.point[j[p]]), sb[p] > 0, "translate")
    pos = np.nonzero(b_curve & ta.vertex[i])[0]
    if len(pos):
        jj = j[pos]
        subs = tb.restricted(jj, tb.params(jj, lo[pos] - off[pos]),
                             tb.params(jj, hi[pos] - off[pos]))
        for rows, st in subs:
            p = pos[rows]
            emit(p, _translate_many(st, ta.point[i[p]]), sa[p] > 0, "translate")
    pos = np.nonzero(a_curve & b_curve)[0]
    if len(pos):
        if method != "qac":
            for p in pos:
                ea, eb = ta.edges[i[p]], tb.edges[j[p]]
                for r, (piece, kind, bound) in enumerate(
                        _method_range(ea, eb, lo[p], hi[p], off[p], tol, max_depth, method)):
                    out.append((p, float(r), piece, kind, bound))
        else:
            out.extend(_qac_driver(ta, tb, pos, i[pos], j[pos], lo[pos], hi[pos], off[pos],
                                   tol, max_depth))
    order = sorted(range(len(out)), key=lambda r: (out[r][0], out[r][1]))
    return [(int(out[r][0]),) + tuple(out[r][2:]) for r in order]


def _method_range(ea, eb, lo, hi, off, tol, depth, method):
    """Curve + curve pair by one of the other methods of Sec. 4 (morph.methods).

    Algorithm 5.1 on the pair (A's edge is C1); each piece's ``bound`` is the error it
    reached, sampled (not a bound) for every method but QAC.  Pieces come in A's
    direction of travel and are reversed, with their order, when B is concave.
    """
    from . import methods   # here, not at the top: methods imports this module

    ca = gauss.restrict(ea, lo, hi)[0]
    cb = gauss.restrict(eb, lo - off, hi - off)[0]
    if hi - lo < TINY_SWEEP:
        return [_chord(ca, cb, ea.sign, eb.sign)]
    segs = methods.convolve_pair_segments(ca, cb, tol, method, max_depth=depth)
    forward = eb.sign > 0
    out = [(_oriented(s.piece, forward), method, s.error) for s in segs]
    return out if forward else out[::-1]


def _qac_driver(ta, tb, pos, i, j, lo, hi, off, tol, max_depth):
    """Algorithm 4.1 on curve + curve pairs, all pairs and sub-ranges of one level
    together: restrict both edges to each angle range, QAC with the better role
    (:func:`_roles_many`), and split every range whose bound exceeds tol at the
    angle where its error peaks.  Returns [(pair position, sort key, piece, kind,
    bound)]; the sort key orders each pair's pieces along its travel direction
    (increasing angle when the two edges turn the same way).

    Before QAC, as in the scalar form: a sub-piece shorter than 1e-7 of the other
    (or than tol/4, or tol/2 once the halvings are used up) acts as a corner (the
    other piece translated, ends snapped to the angle-matched sums, bound twice its
    length); a common sweep below TINY_SWEEP gives the chord where its bound meets tol.
    """
    out = []
    ta_lo, ta_hi = ta.params(i, lo), ta.params(i, hi)
    tb_lo, tb_hi = tb.params(j, lo - off), tb.params(j, hi - off)
    depth = np.full(len(pos), max_depth)
    while len(pos):
        sa, sb = ta.sign[i], tb.sign[j]
        key = np.where(sa * sb > 0, lo, -lo)
        ca_all = ta.restricted(i, ta_lo, ta_hi)
        cb_all = tb.restricted(j, tb_lo, tb_hi)
        # rows of (degree of A's piece, degree of B's piece) groups
        ga = np.zeros(len(pos), int)
        gb = np.zeros(len(pos), int)
        for g, (rows, _) in enumerate(ca_all):
            ga[rows] = g
        for g, (rows, _) in enumerate(cb_all):
            gb[rows] = g
        a_row = np.zeros(len(pos), int)
        b_row = np.zeros(len(pos), int)
        for rows, _ in ca_all:
            a_row[rows] = np.arange(len(rows))
        for rows, _ in cb_all:
            b_row[rows] = np.arange(len(rows))
        split = np.zeros(len(pos), bool)
        th = np.zeros(len(pos))
        for g1 in range(len(ca_all)):
            for g2 in range(len(cb_all)):
                rows = np.nonzero((ga == g1) & (gb == g2))[0]
                if not len(rows):
                    continue
                ca = ca_all[g1][1][a_row[rows]]
                cb = cb_all[g2][1][b_row[rows]]
                done, fail, t_split = _qac_level(
                    ca, cb, sa[rows], sb[rows], lo[rows], hi[rows], off[rows], depth[rows],
                    tol, ta, tb, i[rows], j[rows], ta_lo[rows], ta_hi[rows], tb_lo[rows],
                    tb_hi[rows])
                for r, piece, kind, bound in done:
                    out.append((pos[rows[r]], key[rows[r]], piece, kind, bound))
                split[rows[fail]] = True
                th[rows[fail]] = t_split
        if not split.any():
            break
        s = np.nonzero(split)[0]
        t_a = ta.params(i[s], th[s])
        t_b = tb.params(j[s], th[s] - off[s])
        two = lambda x, y: np.concatenate([x, y])  # noqa: E731
        pos, i, j, off = (two(x[s], x[s]) for x in (pos, i, j, off))
        lo, hi = two(lo[s], th[s]), two(th[s], hi[s])
        ta_lo, ta_hi = two(ta_lo[s], t_a), two(t_a, ta_hi[s])
        tb_lo, tb_hi = two(tb_lo[s], t_b), two(t_b, tb_hi[s])
        depth = two(depth[s], depth[s]) - 1
    return out


def _length_bounds(st):
    p = st[:, :, :2] / st[:, :, 2:3]
    return np.sum(np.hypot(*np.moveaxis(np.diff(p, axis=1), 2, 0)), axis=1)


def _qac_level(ca, cb, sa, sb, lo, hi, off, depth, tol, ta, tb, i, j, ta_lo, ta_hi,
               tb_lo, tb_hi):
    """One level of :func:`_qac_driver` on rows whose A and B sub-pieces have one
    degree each.  Returns (done, fail, th): done = [(row, piece, kind, bound)],
    fail = rows to split, th = their split angles (A's lifted angles)."""
    done = []
    la, lb = _length_bounds(ca), _length_bounds(cb)
    short = (np.minimum(la, lb) <= np.minimum(0.25 * tol, 1e-7 * np.maximum(la, lb))) | (
        (depth == 0) & (2 * np.minimum(la, lb) <= tol))
    for r in np.nonzero(short)[0]:
        done.append((r,) + _corner_piece(ca[r], cb[r], la[r], lb[r], sa[r], sb[r]))
    rest = ~short
    tiny = rest & (hi - lo < TINY_SWEEP)
    for r in np.nonzero(tiny)[0]:
        chord = _chord(ca[r], cb[r], sa[r], sb[r])
        if chord[2] <= tol:
            done.append((r,) + chord)
            rest[r] = False
    rows = np.nonzero(rest)[0]
    if not len(rows):
        return done, np.zeros(0, int), np.zeros(0)
    ca, cb = ca[rows], cb[rows]
    swap, q2, bound, s_peak = _roles_many(ca, cb, tol)
    accept = bound <= tol
    s_other = np.where(swap, sa[rows], sb[rows])
    for sw in (False, True):
        sel = np.nonzero(accept & (swap == sw))[0]
        if not len(sel):
            continue
        c1 = (cb if sw else ca)[sel]
        res = _qac_pieces(c1, (ca if sw else cb)[sel], q2[sel])
        for r, piece in zip(sel, res):
            if np.all(piece[:, 2] > 0):
                done.append((rows[r], _oriented(piece, s_other[r] > 0), "qac", float(bound[r])))
            else:
                accept[r] = False
    fail = np.nonzero(~accept)[0]
    if not len(fail):
        return done, np.zeros(0, int), np.zeros(0)
    if np.any(depth[rows[fail]] == 0):
        r = fail[np.argmax(depth[rows[fail]] == 0)]
        c2 = ca[r] if swap[r] else cb[r]
        raise ToleranceNotMetError(
            "QAC did not reach tolerance %g (best %g)" % (tol, bound[r]), piece=c2,
            achieved=float(bound[r]))
    # split the angle range where the error of C2 peaks (Algorithm 4.1): the tangent
    # angle of C2 at s_peak, from its edge's tangent numerator at the same point
    fr = rows[fail]
    s = np.clip(s_peak[fail], 0.2, 0.8)
    sw = swap[fail]
    t_a = ta_lo[fr] + s * (ta_hi[fr] - ta_lo[fr])
    t_a = np.where(ta.sweep[i[fr]] > 0, t_a, ta_hi[fr] + s * (ta_lo[fr] - ta_hi[fr]))
    t_b = tb_lo[fr] + s * (tb_hi[fr] - tb_lo[fr])
    t_b = np.where(tb.sweep[j[fr]] > 0, t_b, tb_hi[fr] + s * (tb_lo[fr] - tb_hi[fr]))
    hv = np.where(sw[:, None], bz.evaluate_many(ta.h[i[fr]], t_a),
                  bz.evaluate_many(tb.h[j[fr]], t_b))
    th = np.arctan2(hv[:, 1], hv[:, 0])
    # express the split angle in A's lifted angles
    ref = np.where(sw, lo[fr] - off[fr], lo[fr])
    th = ref + gauss._wrap(th - ref) + np.where(sw, off[fr], 0.0)
    bad = ~((lo[fr] < th) & (th < hi[fr]))
    th = np.where(bad, 0.5 * (lo[fr] + hi[fr]), th)
    return done, fr, th


def _corner_piece(ca, cb, la, lb, sa, sb):
    """A degenerate sub-piece acts as a corner (see :func:`_qac_driver`)."""
    same = sa == sb
    if la <= lb:
        short, long_, s_long = ca, cb, sa
    else:
        short, long_, s_long = cb, ca, sb
    m0 = pc.start(short) if same else pc.end(short)
    m1 = pc.end(short) if same else pc.start(short)
    moved = pc.translate(long_, pc.start(short))
    moved = pc.with_endpoints(moved, pc.start(long_) + m0, pc.end(long_) + m1)
    return _oriented(moved, s_long > 0), "translate", 2.0 * min(la, lb)


def _qac_pieces(c1, c2, q2):
    """QAC pieces of rows of stacks c1, c2 (one degree each): a list of arrays."""
    out = [None] * len(c1)
    poly = pc.is_polynomial_many(c1)
    for sel, rational in ((poly, False), (~poly, True)):
        rows = np.nonzero(sel)[0]
        if not len(rows):
            continue
        h = pc.tangent_numerator_many(c1[rows], rational)
        odd = pc.end_zero_rows(h)
        res = convolve_qac_many(c1[rows], q2[rows], rational)
        for r, row in enumerate(rows):
            out[row] = (convolve_qac_piece(c1[row], c2[row], q2[row]) if odd[r] else res[r])
    return out


def _roles_many(ca, cb, tol):
    """:func:`_roles` of each row of stacks ca, cb: (swap, q2, bound, s_peak)."""
    k = len(ca)
    cands = []
    for swap, c1, c2 in ((False, ca, cb), (True, cb, ca)):
        q2, ok = quadratic_approximation_many(c2)
        bound, s = np.full(k, np.inf), np.full(k, 0.5)
        if ok.any():
            bound[ok], s[ok] = qac_parametric_bound_many(c2[ok], q2[ok])
        d = c1.shape[1] - 1
        degree = np.where(pc.is_polynomial_many(c1), 3 * d - 2, 5 * d - 4)
        # a role without a tangent intersection is no candidate: it loses every tie
        degree = np.where(ok, degree, np.iinfo(np.int64).max)
        cands.append([bound, degree, q2, s, c2, ok])
    need = np.minimum(cands[0][0], cands[1][0]) > tol
    for c in cands:
        bound, _, q2, s, c2, ok = c
        sel = np.nonzero(need & ok & (bound > 0) & (bound < np.inf))[0]
        if len(sel):
            bound[sel], s[sel] = _reparam_bound_many(c2[sel], q2[sel], bound[sel], s[sel])
    # smaller bound first, then the lower output degree; swap=False on a tie
    b0, d0 = cands[0][0], cands[0][1]
    b1, d1 = cands[1][0], cands[1][1]
    swap = (b1 < b0) | ((b1 == b0) & (d1 < d0))
    q2 = np.where(swap[:, None, None], cands[1][2], cands[0][2])
    return swap, q2, np.where(swap, b1, b0), np.where(swap, cands[1][3], cands[0][3])


def _chord(ca, cb, sa, sb):
    """Nearly straight pair (common sweep < TINY_SWEEP): the chord of the sums."""
    # pair ends by angle: ca runs from lo to hi if convex, else hi to lo
    a0, a1 = pc.start(ca), pc.end(ca)
    b0, b1 = pc.start(cb), pc.end(cb)
    if sa != sb:
        b0, b1 = b1, b0
    seg = pc.line(a0 + b0, a1 + b1)
    bound = _sagitta(ca) + _sagitta(cb)
    return (_oriented(seg, sb > 0), "chord", bound)


def _sagitta(piece):
    p = pc.cartesian(piece)
    chord = p[-1] - p[0]
    length = np.hypot(*chord)
    if length == 0:
        return float(np.hypot(*(p - p[0]).T).max())
    return float(np.abs(pc.cross2(chord, p - p[0])).max() / length)


# ------------------------------------------------------------------ whole loops

def convolve_loops(edges_a, edges_b, tol, keep_type3=False, source=(0, 0), method="qac",
                   pairs=None):
    """All convolution pieces of two loops' Gauss maps, oriented and typed.

    ``pairs``: the result of ``compatible_pairs(edges_a, edges_b)`` if known (it
    depends on the angles only).
    """
    ta, tb = _EdgeTable([edges_a]), _EdgeTable([edges_b])
    if pairs is None:
        table = _pair_table(ta, tb)
    else:
        table = tuple(np.array([p[c] for p in pairs], float if c >= 2 else int)
                      for c in range(5))
    conv = _convolve_all(ta, tb, table, tol, keep_type3, method)
    for c in conv:
        c.source = (source[0], c.source[1], source[1], c.source[3])
    return conv


def _convolve_all(ta, tb, table, tol, keep_type3, method):
    """ConvPieces of all pairs of a pair table, typed (Fig. 20), in its order."""
    i, j = table[0], table[1]
    typ = pair_type(ta.sign[i], tb.sign[j], ta.vertex[i], tb.vertex[j])
    if not keep_type3:
        keep = typ != 3
        table = tuple(x[keep] for x in table)
        typ, i, j = typ[keep], i[keep], j[keep]
    res = _convolve_table(ta, tb, table, tol, method=method)
    la, ia, lb, ib = ta.loop[i], ta.index[i], tb.loop[j], tb.index[j]
    return [ConvPiece(piece, kind, int(typ[p]), bound,
                      (int(la[p]), int(ia[p]), int(lb[p]), int(ib[p])))
            for p, piece, kind, bound in res]


def convolution(region_a, region_b, tol, keep_type3=True, method="qac"):
    """Convolution pieces of two regions (lists of loops), Sec. 3.3.

    Each returned piece P has max distance to the exact convolution curve <= tol
    (a-priori bound of Eqs. 39-40; see :func:`qac_error_bound`); normals are exact
    except on "chord" pieces (common sweep below 1e-7 rad).  tol is absolute, in
    input units.  With keep_type3 the pieces form closed, consistently oriented
    loops (:func:`chain`); without it type-3 pieces (never on the boundary) are
    dropped early.  All edge pairs of all loop pairs are handled together (the
    pairs found with one array comparison, Algorithm 4.1 level by level on arrays),
    in the order of the loops of A, then of B.
    """
    if tol <= 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    ta = _EdgeTable(_gauss_maps(region_a))
    tb = _EdgeTable(_gauss_maps(region_b))
    cache = getattr(region_a, "pair_cache", None)
    if cache is None or cache is not getattr(region_b, "pair_cache", None):
        cache = None
    if cache is not None:
        key = (id(region_a.base), id(region_b.base))
        table = cache.get(key)
        if table is None:
            table = cache[key] = _pair_table(ta, tb)
    else:
        table = _pair_table(ta, tb)
    return _convolve_all(ta, tb, table, tol, keep_type3, method)


# ------------------------------------------------- Gauss maps shared by scaled copies

class GaussRegion(list):
    """A region (list of loops) that carries its loops' Gauss maps.

    Made by :func:`scaled_gauss_region`; :func:`convolution` uses ``gauss_maps``
    instead of recomputing them, and ``compatible_pairs`` results from
    ``pair_cache`` (a dict shared by the operands) keyed by the unscaled maps
    ``base``.  Everything else sees a plain list of loops.
    """

    def __init__(self, loops, gauss_maps, base, pair_cache):
        super().__init__(loops)
        self.gauss_maps = gauss_maps
        self.base = base
        self.pair_cache = pair_cache


def _gauss_maps(region):
    maps = getattr(region, "gauss_maps", None)
    if maps is not None:
        return maps
    return [gauss.gauss_map(loop) for loop in region]


def scale_edges(edges, factor):
    """The Gauss map of a loop scaled by factor > 0 about the origin: the same angles,
    scaled positions (scaling does not turn tangents)."""
    if not factor > 0:
        raise ValueError("scale factor must be positive, got %r" % (factor,))
    m = [[factor, 0.0, 0.0], [0.0, factor, 0.0]]
    return [gauss.Edge(e.kind, None if e.piece is None else pc.transform(e.piece, m),
                       factor * np.asarray(e.point, float), e.theta, e.sweep) for e in edges]


def scaled_gauss_region(loops, base, factor, pair_cache):
    """``loops`` (already scaled by ``factor``) as a :class:`GaussRegion` whose Gauss
    maps are ``base`` (the unscaled loops' Gauss maps, computed once) scaled.

    Tangent angles do not change under scaling, so the Gauss maps and the
    compatible pairs of two such regions (``pair_cache``, a dict shared by both
    operands across calls) are computed once for all scale factors; the pieces of
    Algorithm 4.1, which depend on tol relative to the sizes, are not cached.
    """
    return GaussRegion(loops, [scale_edges(edges, factor) for edges in base], base,
                       pair_cache)


def chain(pieces, tol):
    """Join oriented pieces end to start into closed loops (lists of arrays).

    Each end is paired with a start closer than ``tol`` (nearest pairs first, each
    start used once; found by hashing the points on a grid of cell ``tol``), and the
    two are snapped to their mean.  Where several starts meet one end (loops
    touching at a point) any pairing closes the loops with the same edges, so the
    same winding numbers.  Raises TopologyError if an end has no start within tol.
    """
    from .errors import TopologyError

    pieces = [np.asarray(p, float) for p in pieces]
    n = len(pieces)
    if n == 0:
        return []
    starts = np.array([pc.start(p) for p in pieces])
    ends = np.array([pc.end(p) for p in pieces])
    e, s, d = _near_pairs(ends, starts, tol)
    succ = np.full(n, -1)
    taken = np.zeros(n, bool)
    for i, j in zip(e[np.argsort(d, kind="stable")], s[np.argsort(d, kind="stable")]):
        if succ[i] < 0 and not taken[j]:
            succ[i], taken[j] = j, True
    if (succ < 0).any():
        raise TopologyError("open convolution chain at %s" % (ends[np.argmax(succ < 0)],))
    loops, seen = [], np.zeros(n, bool)
    for first in range(n):
        if seen[first]:
            continue
        loop, cur = [], first
        while not seen[cur]:
            seen[cur] = True
            loop.append(pieces[cur])
            cur = succ[cur]
        loops.append(snap_loop(loop))
    return loops


def _near_pairs(a, b, tol):
    """Index pairs (i, j, distance) with |a_i - b_j| <= tol (grid hashing, cell tol)."""
    cell_a = np.floor(a / tol).astype(np.int64)
    cell_b = np.floor(b / tol).astype(np.int64)
    keys_b = cell_b[:, 0] * 3_000_017 + cell_b[:, 1]
    order = np.argsort(keys_b, kind="stable")
    sorted_keys = keys_b[order]
    ii, jj = [], []
    for dx in (-1, 0, 1):
        for dy in (-1, 0, 1):
            k = (cell_a[:, 0] + dx) * 3_000_017 + cell_a[:, 1] + dy
            lo = np.searchsorted(sorted_keys, k, "left")
            hi = np.searchsorted(sorted_keys, k, "right")
            cnt = hi - lo
            ii.append(np.repeat(np.arange(len(a)), cnt))
            jj.append(order[np.repeat(lo, cnt) + np.arange(cnt.sum())
                            - np.repeat(np.cumsum(cnt) - cnt, cnt)])
    i, j = np.concatenate(ii), np.concatenate(jj)
    d = np.hypot(*(a[i] - b[j]).T)
    near = d <= tol
    return i[near], j[near], d[near]


def snap_loop(loop):
    """The loop with each join snapped to the mean of the two ends meeting there."""
    out = [p.copy() for p in loop]
    for i in range(len(out)):
        j = (i + 1) % len(out)
        m = 0.5 * (pc.end(out[i]) + pc.start(out[j]))
        out[i] = pc.with_endpoints(out[i], pc.start(out[i]), m)
        out[j] = pc.with_endpoints(out[j], m, pc.end(out[j]))
    return out

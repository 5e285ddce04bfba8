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
    best, s_best = -np.inf, 0.5
    for pa, pb, s0, s1 in parts:
        if not np.all(pb > 0):
            return np.inf, 0.5
        r = pa / pb
        k = int(np.argmax(r))
        if r[k] > best:
            best, s_best = float(r[k]), s0 + (s1 - s0) * k / (len(r) - 1)
    return best, s_best


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


def _positive_weights(piece):
    return bool(np.all(piece[:, 2] > 0))


# ---------------------------------------------------------------- edge pairing

def _edge_arrays(edges):
    lo = np.array([e.lo for e in edges])
    hi = np.array([e.hi for e in edges])
    return lo, hi


def compatible_pairs(edges_a, edges_b):
    """Pairs (i, j, lo, hi) of edges whose tangent-angle ranges overlap (Sec. 3.2).

    lo, hi are in A's lifted angles.  Uses the epsilon rule of the module docstring
    for equal angles; a zero-length overlap (lo == hi) is returned only for straight
    edges, whose convolution is a translated segment.
    """
    alo, ahi = _edge_arrays(edges_a)
    blo, bhi = _edge_arrays(edges_b)
    amid = 0.5 * (alo + ahi)
    bmid = 0.5 * (blo + bhi)
    k = np.round((amid[:, None] - bmid[None, :]) / gauss.TWO_PI)
    sblo = blo[None, :] + gauss.TWO_PI * k
    sbhi = bhi[None, :] + gauss.TWO_PI * k
    lo = np.maximum(alo[:, None], sblo)
    hi = np.minimum(ahi[:, None], sbhi)
    a_line = (ahi - alo == 0.0)[:, None] & np.array([e.kind == "curve" for e in edges_a])[:, None]
    b_line = (bhi - blo == 0.0)[None, :] & np.array([e.kind == "curve" for e in edges_b])[None, :]
    proper = (hi - lo > ANGLE_EQ) & ~a_line & ~b_line
    # straight edge of A at theta: B range (lo, hi]  (B perturbed by +eps)
    th_a = alo[:, None]
    a_match = a_line & ~b_line & (th_a - sblo > ANGLE_EQ) & (th_a - sbhi <= ANGLE_EQ)
    # straight edge of B at theta: A range [lo, hi)
    th_b = sblo
    b_match = b_line & ~a_line & (th_b - alo[:, None] >= -ANGLE_EQ) & (ahi[:, None] - th_b > ANGLE_EQ)
    out = []
    for mask, kind in ((proper, "proper"), (a_match, "a_line"), (b_match, "b_line")):
        ii, jj = np.nonzero(mask)
        for i, j in zip(ii, jj):
            if kind == "proper":
                out.append((i, j, lo[i, j], hi[i, j], k[i, j]))
            elif kind == "a_line":
                out.append((i, j, alo[i], alo[i], k[i, j]))
            else:
                out.append((i, j, sblo[i, j], sblo[i, j], k[i, j]))
    return out


def pair_type(sa, sb, a_vertex=False, b_vertex=False):
    """Fig. 20 type of a pair from the signs of its two edges (+1, 0, -1).

    Type 3 (never on the boundary): concave/concave or concave/straight pairs, and
    any pair with a concave vertex.
    """
    if (a_vertex and sa < 0) or (b_vertex and sb < 0):
        return 3
    if (sa < 0 and sb <= 0) or (sb < 0 and sa <= 0):
        return 3
    if sa >= 0 and sb >= 0:
        return 1
    return 2


def _oriented(piece, forward):
    return piece if forward else pc.reverse(piece)


def convolve_edges(ea, eb, lo, hi, shift, tol, max_depth=30, method="qac"):
    """Convolution pieces of one compatible pair of edges (A's angles lo..hi).

    ``shift`` is the multiple of 2 pi added to B's angles.  Returns a list of
    (piece, kind, bound).  Curve + curve pairs go through QAC with subdivision of
    the angle range where the error of Eq. 40 peaks (Algorithm 4.1) until every
    bound <= tol; raises ToleranceNotMetError past ``max_depth`` halvings.
    """
    sa, sb = ea.sign, eb.sign
    off = gauss.TWO_PI * shift
    a_curve = ea.kind == "curve" and ea.sweep != 0.0
    b_curve = eb.kind == "curve" and eb.sweep != 0.0
    a_line = ea.kind == "curve" and ea.sweep == 0.0
    b_line = eb.kind == "curve" and eb.sweep == 0.0
    if a_line:
        # segment of A translated by B's point at that angle; direction by B's sign
        pt = gauss.point_at_angle(eb, lo - off)
        return [(_oriented(pc.translate(ea.piece, pt), sb > 0), "translate", 0.0)]
    if b_line:
        pt = gauss.point_at_angle(ea, lo)
        return [(_oriented(pc.translate(eb.piece, pt), sa > 0), "translate", 0.0)]
    if a_curve and not b_curve:
        sub = gauss.restrict(ea, lo, hi)[0]
        return [(_oriented(pc.translate(sub, eb.point), sb > 0), "translate", 0.0)]
    if b_curve and not a_curve:
        sub = gauss.restrict(eb, lo - off, hi - off)[0]
        return [(_oriented(pc.translate(sub, ea.point), sa > 0), "translate", 0.0)]
    if not a_curve and not b_curve:
        return []
    if method != "qac":
        return _method_range(ea, eb, lo, hi, off, tol, max_depth, method)
    return _qac_range(ea, eb, lo, hi, off, tol, max_depth)


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


def _qac_range(ea, eb, lo, hi, off, tol, depth):
    """Algorithm 4.1 on the angle range [lo, hi]: QAC, split at the peak, recurse."""
    ca = gauss.restrict(ea, lo, hi)[0]
    cb = gauss.restrict(eb, lo - off, hi - off)[0]
    # a degenerate sub-piece (1e-7 of the other's length, e.g. next to a repeated
    # control point, where the tangent swings through its range within a tiny
    # length), or any sub-piece shorter than tol/2 once the halvings are used up,
    # acts as a corner: the
    # other piece translated by its start is within its length of the exact
    # convolution, and keeps exact normals (the other piece has the matching normal)
    # (ends snapped to the exact sums of the angle-matched end points: bound 2 * length)
    la, lb = pc.length_bound(ca), pc.length_bound(cb)
    if min(la, lb) <= min(0.25 * tol, 1e-7 * max(la, lb)) or (depth == 0 and 2 * min(la, lb) <= tol):
        same = ea.sign == eb.sign
        if la <= lb:
            short, long_, s_long = ca, cb, ea.sign
        else:
            short, long_, s_long = cb, ca, eb.sign
        m0 = pc.start(short) if same else pc.end(short)
        m1 = pc.end(short) if same else pc.start(short)
        moved = pc.translate(long_, pc.start(short))
        moved = pc.with_endpoints(moved, pc.start(long_) + m0, pc.end(long_) + m1)
        return [(_oriented(moved, s_long > 0), "translate", 2.0 * min(la, lb))]
    if hi - lo < TINY_SWEEP:
        chord = _chord(ca, cb, ea.sign, eb.sign)
        if chord[2] <= tol:
            return [chord]
        # long, nearly straight pieces: the chord is too far; QAC may still do
    swap, q2, bound, s_peak = _roles(ca, cb, tol)
    c1, c2 = (cb, ca) if swap else (ca, cb)
    s_other = ea.sign if swap else eb.sign
    if bound <= tol:
        res = convolve_qac_piece(c1, c2, q2)
        if _positive_weights(res):
            return [(_oriented(res, s_other > 0), "qac", bound)]
    if depth == 0:
        raise ToleranceNotMetError(
            "QAC did not reach tolerance %g (best %g)" % (tol, bound), piece=c2, achieved=bound)
    # split the angle range where the error of C2 peaks (Algorithm 4.1)
    s_peak = min(max(s_peak, 0.2), 0.8)
    th = float(pc.tangent_angle(c2, s_peak)[0])
    # express the split angle in A's lifted angles
    ref = lo if not swap else lo - off
    th = ref + gauss._wrap(th - ref)
    if swap:
        th += off
    if not (lo < th < hi):
        th = 0.5 * (lo + hi)
    left = _qac_range(ea, eb, lo, th, off, tol, depth - 1)
    right = _qac_range(ea, eb, th, hi, off, tol, depth - 1)
    # order along the travel direction: increasing angle when sa*sb > 0
    if ea.sign * eb.sign > 0:
        return left + right
    return right + left


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
    out = []
    if pairs is None:
        pairs = compatible_pairs(edges_a, edges_b)
    for i, j, lo, hi, k in pairs:
        ea, eb = edges_a[i], edges_b[j]
        typ = pair_type(ea.sign, eb.sign, ea.kind == "vertex", eb.kind == "vertex")
        if typ == 3 and not keep_type3:
            continue
        for piece, kind, bound in convolve_edges(ea, eb, lo, hi, k, tol, method=method):
            out.append(ConvPiece(piece, kind, typ, bound, (source[0], i, source[1], j)))
    return out


def convolution(region_a, region_b, tol, keep_type3=True, method="qac"):
    """Convolution pieces of two regions (lists of loops), Sec. 3.3.

    Each returned piece P has max distance to the exact convolution curve <= tol
    (a-priori bound of Eqs. 39-40; see :func:`qac_error_bound`); normals are exact
    except on "chord" pieces (common sweep below 1e-7 rad).  tol is absolute, in
    input units.  With keep_type3 the pieces form closed, consistently oriented
    loops (:func:`chain`); without it type-3 pieces (never on the boundary) are
    dropped early.
    """
    if tol <= 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    ga = _gauss_maps(region_a)
    gb = _gauss_maps(region_b)
    cache = getattr(region_a, "pair_cache", None)
    if cache is None or cache is not getattr(region_b, "pair_cache", None):
        cache = None
    out = []
    for ia, ea in enumerate(ga):
        for ib, eb in enumerate(gb):
            pairs = None
            if cache is not None:
                key = (id(region_a.base), id(region_b.base), ia, ib)
                pairs = cache.get(key)
                if pairs is None:
                    pairs = cache[key] = compatible_pairs(ea, eb)
            out.extend(convolve_loops(ea, eb, tol, keep_type3, (ia, ib), method, pairs))
    return out


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

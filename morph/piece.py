"""Rational Bézier pieces as ``(n+1, 3)`` arrays of homogeneous control points.

A piece of degree n is ``P(t) = sum_i B_i^n(t) (w_i x_i, w_i y_i, w_i)`` divided by its
last coordinate.  Polynomial pieces have all ``w_i = 1``.  One representation holds
lines, quadratics, cubics, conic arcs (exact circles and ellipses) and the rational
QAC output (degree 3d-2 or 5d-4), so every algorithm is written once.

Weights are kept positive; the convex hull property then holds for the Cartesian
control points ``(x_i, y_i)``, which bounding boxes and hull tests rely on.
"""

import functools
import itertools
import operator

import numpy as np

from . import bernstein as bz
from .errors import DegenerateCurveError


def cross2(a, b):
    """z-component of the cross product of 2D vectors (broadcasting)."""
    a = np.asarray(a, float)
    b = np.asarray(b, float)
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


# --------------------------------------------------------------------------- build

def from_points(points, weights=None):
    """Homogeneous piece from Cartesian control points (and optional weights).

    ``points`` has shape (n+1, 2); weights default to 1 (a polynomial piece).
    """
    p = np.asarray(points, float).reshape(-1, 2)
    w = np.ones(len(p)) if weights is None else np.asarray(weights, float)
    if np.any(w <= 0):
        raise ValueError("weights must be positive, got %r" % (w,))
    return np.column_stack([p * w[:, None], w])


def line(p0, p1):
    """Degree-1 piece from p0 to p1."""
    return from_points([p0, p1])


def quadratic(p0, p1, p2):
    """Polynomial quadratic Bézier."""
    return from_points([p0, p1, p2])


def cubic(p0, p1, p2, p3):
    """Polynomial cubic Bézier."""
    return from_points([p0, p1, p2, p3])


def ellipse_arc(center, rx, ry, rotation, theta0, dtheta):
    """Exact elliptical arc as a list of rational quadratic pieces.

    The arc is ``center + R(rotation) (rx cos th, ry sin th)`` for th from theta0 to
    theta0 + dtheta (radians, dtheta may be negative).  It is cut into pieces of at
    most 90 degrees; each is the standard conic: middle weight cos(half angle).
    """
    if rx <= 0 or ry <= 0:
        raise ValueError("ellipse radii must be positive, got %r, %r" % (rx, ry))
    nseg = max(1, int(np.ceil(abs(dtheta) / (np.pi / 2) - 1e-9)))
    step = dtheta / nseg
    c, s = np.cos(rotation), np.sin(rotation)
    rot = np.array([[c, -s], [s, c]])
    center = np.asarray(center, float)
    out = []
    for k in range(nseg):
        a0 = theta0 + k * step
        a1 = a0 + step
        h = step / 2
        pts_unit = np.array([
            [np.cos(a0), np.sin(a0)],
            [np.cos(a0 + h) / np.cos(h), np.sin(a0 + h) / np.cos(h)],
            [np.cos(a1), np.sin(a1)],
        ])
        pts = (pts_unit * [rx, ry]) @ rot.T + center
        out.append(from_points(pts, [1.0, np.cos(h), 1.0]))
    return out


def circle(center, radius):
    """Exact counter-clockwise circle: four rational quadratic quarter arcs."""
    return ellipse_arc(center, radius, radius, 0.0, 0.0, 2 * np.pi)


def ellipse(center, rx, ry, rotation=0.0):
    """Exact counter-clockwise ellipse rotated by ``rotation`` radians."""
    return ellipse_arc(center, rx, ry, rotation, 0.0, 2 * np.pi)


# ------------------------------------------------------------------ basic queries

def degree(piece):
    return len(piece) - 1


def cartesian(piece):
    """Cartesian control points (x_i, y_i), shape (n+1, 2)."""
    piece = np.asarray(piece, float)
    return piece[..., :2] / piece[..., 2:3]


def is_polynomial(piece, rtol=1e-12):
    w = piece[:, 2]
    return bool(np.all(np.abs(w - w[0]) <= rtol * abs(w[0])))


def start(piece):
    return piece[0, :2] / piece[0, 2]


def end(piece):
    return piece[-1, :2] / piece[-1, 2]


def evaluate(piece, t):
    """Points P(t), shape (len(t), 2); t a scalar or array in [0, 1]."""
    h = bz.evaluate(piece, np.atleast_1d(t))
    return h[:, :2] / h[:, 2:3]


def derivative(piece, t):
    """First derivative P'(t) = (X' W - X W') / W^2, shape (len(t), 2)."""
    t = np.atleast_1d(t)
    h = bz.evaluate(piece, t)
    dh = bz.evaluate(bz.derivative(piece), t)
    w = h[:, 2:3]
    return (dh[:, :2] * w - h[:, :2] * dh[:, 2:3]) / w ** 2


def stack(pieces):
    """Pieces elevated to their common highest degree D, stacked: (len(pieces), D+1, 3).

    Degree elevation is exact on homogeneous control points, so one array holds
    pieces of mixed degree for the batched evaluations below.
    """
    groups = degree_groups(pieces)
    deg = max(h.shape[1] for _, h in groups) - 1
    out = np.empty((len(pieces), deg + 1, 3))
    for ks, h in groups:
        out[ks] = bz.elevate_many(h, deg + 1 - h.shape[1])
    return out


def jet_many(stacked, idx, t):
    """Points and first derivatives of pieces ``stacked[idx[i]]`` at ``t[i]``, all at
    once: P = X/W and P' = (X' W - X W') / W^2, shapes (m, 2) and (m, 2)."""
    return jet_rows(stacked[idx], t)


def jet_rows(h, t, dh=None):
    """:func:`jet_many` of pieces already gathered, h[i] (m, n+1, 3) at t[i]; ``dh``:
    their hodographs n (h[:, 1:] - h[:, :-1]) when known (an iteration evaluating the
    same pieces again and again computes them once)."""
    n = h.shape[1] - 1
    if dh is None:
        dh = n * np.diff(h, axis=1)
    t = np.asarray(t, float)
    val = np.einsum("mi,mij->mj", bz.basis(n, t), h)
    dval = np.einsum("mi,mij->mj", bz.basis(n - 1, t), dh)
    w = val[:, 2:3]
    return val[:, :2] / w, (dval[:, :2] * w - val[:, :2] * dval[:, 2:3]) / w ** 2


def second_derivative(piece, t):
    """Second derivative of the rational curve (quotient rule twice, :func:`jet2_many`)."""
    t = np.atleast_1d(np.asarray(t, float))
    return jet2_many(np.asarray(piece, float)[None], t[None])[2][0]


def jet2_many(c, s):
    """P, P' and P'' of each piece of a stack c (k, n+1, 3) at its parameters s (k, m):
    three arrays (k, m, 2).

    The homogeneous value and derivatives come from the last three levels of de
    Casteljau's triangle (H' = n (b1 - b0), H'' = n (n-1) (b2 - 2 b1 + b0) one level
    up); then the quotient rule on P = X / W: P' = (X' - W' P) / W,
    P'' = (X'' - 2 W' P' - W'' P) / W.
    """
    c = np.asarray(c, float)
    s = np.asarray(s, float)
    n = c.shape[1] - 1
    t = s[:, :, None, None]
    work = np.broadcast_to(c[:, None], (c.shape[0], s.shape[1]) + c.shape[1:])
    for _ in range(max(n - 2, 0)):
        work = work[:, :, :-1] + t * (work[:, :, 1:] - work[:, :, :-1])
    zero = np.zeros(work.shape[:2] + work.shape[3:])
    if n == 0:
        v, v1, v2 = work[:, :, 0], zero, zero
    elif n == 1:
        v1, v2 = work[:, :, 1] - work[:, :, 0], zero
        v = work[:, :, 0] + s[..., None] * v1
    else:
        lev1 = work[:, :, :-1] + t * (work[:, :, 1:] - work[:, :, :-1])
        v2 = n * (n - 1) * (work[:, :, 2] - 2.0 * work[:, :, 1] + work[:, :, 0])
        v1 = n * (lev1[:, :, 1] - lev1[:, :, 0])
        v = lev1[:, :, 0] + s[..., None] * (lev1[:, :, 1] - lev1[:, :, 0])
    return _quotient_jet(v, v1, v2)


def _quotient_jet(v, v1, v2):
    """P, P', P'' of P = X / W from the homogeneous H = (X, W) and its derivatives
    (last axis x, y, w): P' = (X' - W' P) / W, P'' = (X'' - 2 W' P' - W'' P) / W."""
    w, w1, w2 = v[..., 2:], v1[..., 2:], v2[..., 2:]
    p = v[..., :2] / w
    p1 = (v1[..., :2] - w1 * p) / w
    return p, p1, (v2[..., :2] - 2.0 * w1 * p1 - w2 * p) / w


def jet2_power_many(c, s):
    """P, P' and P'' as :func:`jet2_many`, from the power-basis coefficients of the
    homogeneous curves (:func:`power_coefficients`, :func:`power_jets`), then the
    quotient rule: faster on small stacks; meant for moderate degrees (<= ~12, where
    the power basis on [0, 1] keeps ~1e-12 relative accuracy)."""
    c = np.asarray(c, float)
    s = np.asarray(s, float)
    n = c.shape[1] - 1
    if n < 2:
        return jet2_many(c, s)
    st = s.reshape(len(s), -1).T                                 # (m, k)
    jets = power_jets(power_coefficients(c), power_table(st, n))
    return tuple(np.stack([x.T, y.T], axis=-1).reshape(s.shape + (2,)) for x, y in jets)


def power_coefficients(c):
    """Power-basis coefficients of a stack c (k, n+1, 3), n >= 2, and of its first
    two derivatives, coefficient-major: shapes (n+1, 3, k), (n, 3, k), (n-1, 3, k)."""
    n = c.shape[1] - 1
    a = np.ascontiguousarray(bz._apply(bz._to_power_matrix(n), c).transpose(1, 2, 0))
    j = np.arange(n + 1, dtype=float)
    a1 = a[1:] * j[1:, None, None]
    return a, a1, a1[1:] * j[1:-1, None, None]


def power_exponents(n, shape):
    """The exponents 2..n of :func:`power_table` for parameters of a shape,
    materialised (n-1,) + shape: numpy squares where it sees one exponent 2 (s * s),
    which differs from pow(s, 2) in the last bit now and then."""
    exps = np.empty((n - 1,) + shape)
    exps[...] = np.arange(2, n + 1, dtype=float).reshape((-1,) + (1,) * len(shape))
    return exps


def power_table(st, n, exps=None):
    """The powers s^0 .. s^n (n+1,) + st.shape of parameters st, s^0 = 1 and s^1 = s
    written rather than raised (the same values: a power that is exact is exact);
    ``exps``: :func:`power_exponents` (n, st.shape) when made already."""
    powers = np.empty((n + 1,) + st.shape)
    powers[0], powers[1] = 1.0, st
    np.power(st, power_exponents(n, st.shape) if exps is None else exps, out=powers[2:])
    return powers


def power_jets(coef, powers, second=True):
    """P, P' (and P'') of the pieces with power coefficients ``coef``
    (:func:`power_coefficients`) at parameters laid out (m, k), one column a piece,
    from their powers s^j (n+1, m, k): ((x, y), (x', y')[, (x'', y'')]), each (m, k).

    The homogeneous values are sums over j of s^j times a coefficient row (k,)
    broadcast down the m rows, in the order j = 0, 1, ...: whole-stack products with
    long contiguous rows, not k small matrix products; then the quotient rule.  The
    three columns (x, y, w) are summed together, (3, m, k) per term, and x, y divided
    together: each element gets the same operations in the same order as one column
    at a time, in a third of the numpy calls (small stacks are call-bound)."""
    def values(b):
        out = powers[0] * b[0][:, None, :]
        for j in range(1, len(b)):
            out += powers[j] * b[j][:, None, :]
        return out

    a, a1, a2 = coef
    v, v1 = values(a), values(a1)
    w, w1 = v[2], v1[2]
    p = v[:2] / w
    p1 = (v1[:2] - w1 * p) / w
    if not second:
        return (p[0], p[1]), (p1[0], p1[1])
    v2 = values(a2)
    p2 = (v2[:2] - 2.0 * w1 * p1 - v2[2] * p) / w
    return (p[0], p[1]), (p1[0], p1[1]), (p2[0], p2[1])


def tangent_numerator(piece):
    """Bernstein coefficients (shape (m+1, 2)) of a polynomial parallel to P'(t).

    Sec. 3.2: the hodograph direction.  For a polynomial piece this is the hodograph
    ``n (P_{i+1} - P_i)`` (degree n-1); for a rational one it is ``X' W - X W'``
    (degree 2n-2: the leading terms cancel), which differs from P'(t) by
    the positive factor W^2.  Its direction is the tangent direction everywhere.
    """
    if is_polynomial(piece):
        h = bz.derivative(cartesian(piece))
    else:
        d = bz.derivative(piece)
        full = bz.multiply(d[:, :2], piece[:, 2:3]) - bz.multiply(piece[:, :2], d[:, 2:3])
        h = bz.reduce_exact(full, 1)  # degree 2n-2: the t^(2n-1) terms cancel
    return _deflate_ends(h)


def _deflate_ends(h, rel=1e-12):
    """H(t) / (t^a (1-t)^b) where H has zeros of order a at t=0 and b at t=1.

    A control point on its own end point (common in real drawings) makes the
    hodograph vanish there; the quotient has the same direction inside and the
    limit tangent (the first nonzero derivative's direction) at the ends.  In the
    Bernstein basis, sum_{i>=1} c_i B_i^n = t sum_{i>=1} (n/i) c_i B_{i-1}^{n-1} and
    sum_{i<n} c_i B_i^n = (1-t) sum_{i<n} n/(n-i) c_i B_i^{n-1}.
    """
    scale = np.abs(h).max()
    while len(h) > 1 and np.abs(h[0]).max() <= rel * scale:
        n = len(h) - 1
        h = h[1:] * (n / np.arange(1, n + 1))[:, None]
    while len(h) > 1 and np.abs(h[-1]).max() <= rel * scale:
        n = len(h) - 1
        h = h[:-1] * (n / (n - np.arange(n)))[:, None]
    return h


def curvature_numerator(piece):
    """Bernstein coefficients of a polynomial with the sign of x'y'' - x''y' (Def. 3.2).

    Computed as cross(H, H') for the tangent numerator H, which has the sign of the
    curvature of P because H = W^2 P' up to a positive factor on the tangent line.
    """
    h = tangent_numerator(piece)
    if len(h) == 1:
        return np.zeros(1)
    dh = bz.derivative(h)
    return bz.multiply(h[:, :1], dh[:, 1:2])[:, 0] - bz.multiply(h[:, 1:2], dh[:, :1])[:, 0]


# ------------------------------------------------ batched forms (stacks of one degree)

def is_polynomial_many(stacked, rtol=1e-12):
    """:func:`is_polynomial` of each piece of a stack (k, n+1, 3): (k,) bools."""
    w = stacked[:, :, 2]
    return np.logical_and.reduce(np.abs(w - w[:, :1]) <= rtol * np.abs(w[:, :1]), axis=1)


@functools.lru_cache(maxsize=None)
def _reduce_pinv(n):
    """Pseudo-inverse of the elevation n-1 -> n (least squares of bz.reduce_exact)."""
    return np.linalg.pinv(bz._elevation_matrix(n - 1, 1))


def tangent_numerator_many(stacked, rational):
    """:func:`tangent_numerator` of a stack (k, n+1, 3) of pieces that are all
    polynomial (``rational`` False: degree n-1) or all rational (degree 2n-2),
    before any division by end zeros (see :func:`end_zero_rows`): the same direction
    inside (0, 1)."""
    stacked = np.asarray(stacked, float)
    if not rational:
        return bz.derivative_many(stacked[:, :, :2] / stacked[:, :, 2:3])
    d = bz.derivative_many(stacked)
    full = (bz.multiply_many(d[:, :, :2], stacked[:, :, 2:3])
            - bz.multiply_many(stacked[:, :, :2], d[:, :, 2:3]))
    # degree 2n-2: the t^(2n-1) terms cancel (least squares, as bz.reduce_exact)
    return bz._apply(_reduce_pinv(full.shape[1] - 1), full)


def tangent_cones(pieces, rel=1e-12):
    """Cones holding every tangent direction of each piece, for monotonicity tests.

    The tangent numerator H (:func:`tangent_numerator_many`) is a positive
    combination of its Bernstein coefficients, so every tangent direction lies in
    the cone they span.  Per piece: ``start`` (angle of the first nonzero
    coefficient: the start tangent, also at a zero end derivative), ``lo <= 0 <=
    hi`` (the cone's angles relative to ``start``), ``end`` (the end tangent,
    relative to ``start``).  Where the cone spans pi or more, lo = -inf, hi = inf.
    A curve whose tangents stay in a cone narrower than pi is monotone along its
    bisector and cannot cross itself.
    """
    n = len(pieces)
    start, lo, hi, end = (np.zeros(n) for _ in range(4))
    for ks, stack, rational in kind_groups(pieces):
        start[ks], lo[ks], hi[ks], end[ks] = _cones(tangent_numerator_many(stack, rational), rel)
    return start, lo, hi, end


def _cones(h, rel):
    """:func:`tangent_cones` of a stack of tangent numerators (k, m+1, 2)."""
    norm = np.hypot(h[..., 0], h[..., 1])
    live = norm > rel * np.maximum(norm.max(axis=1, keepdims=True), 1e-300)
    ang = np.arctan2(h[..., 1], h[..., 0])
    first = live.argmax(axis=1)
    last = h.shape[1] - 1 - live[:, ::-1].argmax(axis=1)
    rows = np.arange(len(h))
    start = ang[rows, first]
    turned = np.exp(1j * (ang - start[:, None]))
    relang = np.arctan2(turned.imag, turned.real)   # np.angle's arithmetic
    lo = np.where(live, relang, 0.0).min(axis=1)
    hi = np.where(live, relang, 0.0).max(axis=1)
    wide = hi - lo >= np.pi * (1.0 - 1e-9)
    return start, np.where(wide, -np.inf, lo), np.where(wide, np.inf, hi), relang[rows, last]


def end_zero_rows(h, rel=1e-12):
    """Rows of a stack of tangent numerators (k, m+1, 2) that vanish at an end (to
    ``rel`` of their largest coefficient): where :func:`tangent_numerator` divides
    the end zeros out, so the stacked (undivided) form is not what it returns."""
    scale = np.abs(h).max(axis=(1, 2))
    return ((np.abs(h[:, 0]).max(axis=1) <= rel * scale)
            | (np.abs(h[:, -1]).max(axis=1) <= rel * scale))


def numerator_groups(stack):
    """The rows of a stack of pieces (k, n+1, 3) in two groups, polynomial then
    rational, each as (rows, rational, h, odd): h the group's stacked tangent
    numerators (:func:`tangent_numerator_many`), odd the rows among them whose
    numerator vanishes at an end (:func:`end_zero_rows`), which callers build one
    by one.  Empty groups are left out."""
    poly = is_polynomial_many(stack)
    for sel, rational in ((poly, False), (~poly, True)):
        rows = np.flatnonzero(sel)
        if len(rows):
            h = tangent_numerator_many(stack[rows], rational)
            yield rows, rational, h, end_zero_rows(h)


def curvature_numerator_many(h):
    """cross(H, H') of a stack of tangent numerators h (k, m+1, 2): (k, 2m) (as
    :func:`curvature_numerator`; (k, 1) zeros when m = 0)."""
    if h.shape[1] == 1:
        return np.zeros((len(h), 1))
    dh = bz.derivative_many(h)
    return (bz.multiply_many(h[:, :, 0], dh[:, :, 1]) - bz.multiply_many(h[:, :, 1], dh[:, :, 0]))


# -------------------------------------------------------------------- operations

def split(piece, t):
    """de Casteljau split of the homogeneous control points at t."""
    return bz.split(piece, t)


def split_at(piece, params):
    """The piece cut at sorted interior parameters: len(params) + 1 consecutive parts
    (de Casteljau, each cut on the rest reparametrised to [0, 1])."""
    out, rest, t_prev = [], piece, 0.0
    for t in params:
        left, rest = split(rest, (t - t_prev) / (1.0 - t_prev))
        out.append(left)
        t_prev = t
    out.append(rest)
    return out


def subsegment(piece, t0, t1):
    """The piece restricted to [t0, t1] (t1 < t0 gives the reversed restriction)."""
    return bz.subsegment(piece, t0, t1)


def subsegments(pieces, idx, t0, t1, packed=False):
    """pieces[idx[k]] restricted to [t0[k], t1[k]] (reversed where t1 < t0), a list
    (those of one degree at once); with ``packed`` a :class:`Pieces`."""
    idx = np.asarray(idx, np.int64)
    t0, t1 = np.asarray(t0, float), np.asarray(t1, float)
    out = []
    if isinstance(pieces, Pieces):
        src = pieces.take(idx).groups
    else:
        src = degree_groups([pieces[i] for i in idx.tolist()])
    for ks, h in src:
        out.append((ks, bz.subsegment_many(h, t0[ks], t1[ks])))
    result = Pieces(out, len(idx))
    return result if packed else result.rows()


def elevate(piece, r=1):
    """Same curve at degree n + r."""
    return bz.elevate(piece, r)


def reverse(piece):
    """Same curve traversed from end to start."""
    return np.asarray(piece)[::-1].copy()


def translate(piece, offset):
    """The piece moved by offset (exact: X += ox W, Y += oy W)."""
    piece = np.array(piece, float)
    piece[:, 0] += offset[0] * piece[:, 2]
    piece[:, 1] += offset[1] * piece[:, 2]
    return piece


def transform(piece, matrix):
    """Apply an affine map [[a, b, e], [c, d, f]] (exact on homogeneous points)."""
    m = np.asarray(matrix, float)
    piece = np.asarray(piece, float)
    out = piece.copy()
    out[:, 0] = m[0, 0] * piece[:, 0] + m[0, 1] * piece[:, 1] + m[0, 2] * piece[:, 2]
    out[:, 1] = m[1, 0] * piece[:, 0] + m[1, 1] * piece[:, 1] + m[1, 2] * piece[:, 2]
    return out


def bbox(piece):
    """(xmin, ymin, xmax, ymax) of the Cartesian control points (contains the curve)."""
    p = cartesian(piece)
    return np.array([p[:, 0].min(), p[:, 1].min(), p[:, 0].max(), p[:, 1].max()])


def by_degree(pieces):
    """{number of control points: indices (int64 array, ascending)} of a list of
    pieces (the groups that batched functions stack), the groups in the order of
    their first piece.  A :class:`Pieces` knows its groups; for a list the lengths
    are read in one C-level pass and grouped by a stable sort (no per-piece Python
    statement: a chunk of a font holds tens of thousands of pieces)."""
    if isinstance(pieces, Pieces):
        return {int(h.shape[1]): ks for ks, h in pieces.groups}
    n = len(pieces)
    if n == 0:
        return {}
    lens = np.fromiter(map(len, pieces), np.int64, n)
    if not np.logical_or.reduce(lens != lens[0]):
        return {int(lens[0]): np.arange(n)}
    order = lens.argsort(kind="stable")
    sizes = lens[order]
    cuts = [0] + ((sizes[1:] != sizes[:-1]).nonzero()[0] + 1).tolist() + [n]
    parts = [order[a:b] for a, b in zip(cuts[:-1], cuts[1:])]
    parts.sort(key=operator.itemgetter(0))
    return {int(lens[ks[0]]): ks for ks in parts}


def degree_groups(pieces):
    """[(indices (k,), stack (k, n+1, 3))] of the pieces by number of control points
    (:func:`by_degree`), the stacks built once: those of a :class:`Pieces` as they
    are (no copy), a list's gathered."""
    if isinstance(pieces, Pieces):
        return pieces.groups
    return [(ks, _gather(pieces, ks)) for ks in by_degree(pieces).values()]


def _gather(pieces, ks):
    """np.array of pieces[ks] (one degree): (k, n+1, 3) floats."""
    if len(ks) == len(pieces):
        return np.array(pieces, float)
    return np.array(list(map(pieces.__getitem__, ks.tolist())), float)


class Pieces:
    """A sequence of pieces held as one stack per degree: ``groups`` [(indices,
    stack (k, n+1, 3))], the indices of all groups a partition of range(len).

    What the batched functions of this module (and of :mod:`morph.polyline`,
    :mod:`morph.trim`) take for a list of pieces without stacking it again: a
    chunk of a font's convolution is tens of thousands of pieces, and gathering
    a list into stacks costs about a microsecond a piece each time.  Indexing and
    iterating give the rows of the stacks (views: treat them as read-only), in
    order, made once when first asked for."""

    __slots__ = ("groups", "_n", "_rows", "_where")

    def __init__(self, groups, n):
        self.groups = [(np.asarray(ks, np.int64), h) for ks, h in groups]
        self._n = int(n)
        self._rows = None
        self._where = None

    @classmethod
    def of(cls, pieces):
        """``pieces`` as a :class:`Pieces` (itself when it is one)."""
        if isinstance(pieces, Pieces):
            return pieces
        return cls(degree_groups(pieces), len(pieces))

    def __len__(self):
        return self._n

    def rows(self):
        """The pieces as a list (views of the stacks), in order."""
        if self._rows is None:
            # the stacks' rows one group after another (iterating a stack makes its
            # row views in C), then put in order by one gather: no per-piece statement
            rows = list(itertools.chain.from_iterable(h for _, h in self.groups))
            order = np.concatenate([ks for ks, _ in self.groups]) if self.groups else \
                np.zeros(0, np.int64)
            if (order != np.arange(len(order))).any():
                where = np.empty(self._n, np.int64)
                where[order] = np.arange(len(order))
                rows = list(map(rows.__getitem__, where.tolist()))
            self._rows = rows
        return self._rows

    def __getitem__(self, k):
        return self.rows()[k]

    def __iter__(self):
        return iter(self.rows())

    def then(self, more):
        """These pieces followed by ``more`` (a list of pieces), as a :class:`Pieces`:
        the groups :func:`degree_groups` makes of the whole list (by number of
        control points, in the order of their first piece, indices ascending),
        ``more`` gathered alone (a region's pieces followed by a nib's few)."""
        n = self._n
        more = degree_groups(more)
        mine = {int(h.shape[1]): (ks, h) for ks, h in self.groups}
        out = []
        for ks, h in self.groups:
            extra = [(n + k2, h2) for k2, h2 in more if h2.shape[1] == h.shape[1]]
            if extra:
                ks = np.concatenate([ks] + [k2 for k2, _ in extra])
                h = np.concatenate([h] + [h2 for _, h2 in extra])
            out.append((ks, h))
        out += [(n + k2, h2) for k2, h2 in more if int(h2.shape[1]) not in mine]
        return Pieces(out, n + sum(len(k2) for k2, _ in more))

    def take(self, idx):
        """The pieces ``idx`` (an index array), as a :class:`Pieces`."""
        idx = np.asarray(idx, np.int64)
        group, row = self._index()
        gi = group[idx]
        out = []
        for g, (_, h) in enumerate(self.groups):
            sel = (gi == g).nonzero()[0]
            if len(sel):
                out.append((sel, h.take(row[idx[sel]], axis=0)))   # rows: a fifth of h[...]'s work
        return Pieces(out, len(idx))

    def _index(self):
        """(group, row) of each piece: the index of its stack in ``groups`` and its row
        there, made once (the trimming takes parts of one Pieces several times)."""
        if self._where is None:
            group = np.empty(self._n, np.int64)
            row = np.empty(self._n, np.int64)
            for g, (ks, _) in enumerate(self.groups):
                group[ks] = g
                row[ks] = np.arange(len(ks))
            self._where = group, row
        return self._where


def kind_groups(pieces):
    """The pieces in groups of one degree and kind, the unit of the batched
    functions: a list of (indices (k,), stack (k, n+1, 3), rational), ``rational``
    False where every piece of the group is polynomial (:func:`is_polynomial`)."""
    out = []
    for ks, stack in degree_groups(pieces):
        rational = ~is_polynomial_many(stack)
        for kind in (False, True):
            if (rational == kind).any():
                out.append((ks[rational == kind], stack[rational == kind], kind))
    return out


def bboxes(pieces):
    """:func:`bbox` of many pieces (those of one degree at once): (k, 4)."""
    out = np.zeros((len(pieces), 4))
    for ks, h in degree_groups(pieces):
        # control points one at a time on (k,) columns: numpy reduces a short axis
        # row by row
        x, y = h[:, :, 0] / h[:, :, 2], h[:, :, 1] / h[:, :, 2]
        x0, y0, x1, y1 = x[:, 0].copy(), y[:, 0].copy(), x[:, 0].copy(), y[:, 0].copy()
        for j in range(1, h.shape[1]):
            np.minimum(x0, x[:, j], out=x0)
            np.minimum(y0, y[:, j], out=y0)
            np.maximum(x1, x[:, j], out=x1)
            np.maximum(y1, y[:, j], out=y1)
        out[ks, 0], out[ks, 1], out[ks, 2], out[ks, 3] = x0, y0, x1, y1
    return out


def end_points(pieces):
    """(starts, ends), (k, 2) each: the first and last points of many pieces."""
    starts, ends = np.zeros((len(pieces), 2)), np.zeros((len(pieces), 2))
    for ks, h in degree_groups(pieces):
        starts[ks], ends[ks] = h[:, 0, :2] / h[:, 0, 2:], h[:, -1, :2] / h[:, -1, 2:]
    return starts, ends


def length_bound(piece):
    """Length of the Cartesian control polygon (an upper bound of the arc length)."""
    return float(np.sum(np.hypot(*np.diff(cartesian(piece), axis=0).T)))


def length_bounds(pieces):
    """:func:`length_bound` of many pieces (those of one degree at once): (k,)."""
    out = np.zeros(len(pieces))
    for ks, h in degree_groups(pieces):
        x = h[:, :, :2] / h[:, :, 2:]
        d = x[:, 1:] - x[:, :-1]
        out[ks] = np.add.reduce(np.hypot(d[..., 0], d[..., 1]), axis=1)
    return out


def with_endpoints(piece, p0, p1):
    """The piece with its first/last control point moved to p0/p1 (snapping joins)."""
    piece = np.array(piece, float)
    piece[0, :2] = np.asarray(p0) * piece[0, 2]
    piece[-1, :2] = np.asarray(p1) * piece[-1, 2]
    return piece


def tangent_angle(piece, t):
    """Angles of the tangent direction at t (atan2 of the tangent numerator)."""
    d = bz.evaluate(tangent_numerator(piece), np.atleast_1d(t))
    return np.arctan2(d[:, 1], d[:, 0])


def end_tangents(piece, eps=1e-12):
    """Unit tangent directions at t=0 and t=1, robust where the hodograph vanishes:
    :func:`end_tangents_many` of one piece.  Raises DegenerateCurveError when all
    control points coincide."""
    first, last = end_tangents_many([piece], eps)
    return first[0], last[0]


def column_extremes(x):
    """(min, max) over axis 1 of a stack (k, m, ...) (the control points of pieces),
    one control point at a time: numpy reduces a short middle axis row by row, at
    several times the cost; the same values."""
    lo = hi = x[:, 0]
    for i in range(1, x.shape[1]):
        lo, hi = np.minimum(lo, x[:, i]), np.maximum(hi, x[:, i])
    return lo, hi


def end_tangents_many(pieces, rel=1e-12, strict=True):
    """Unit tangents at t = 0 and t = 1 of each piece, (k, 2) each: along the first
    and the last control-point difference longer than ``rel`` times the piece's
    size (the limit direction where the hodograph vanishes), pieces of one degree
    at once.  A piece whose control points all coincide raises
    DegenerateCurveError (``strict``) or gets zero vectors."""
    first, last = np.zeros((len(pieces), 2)), np.zeros((len(pieces), 2))
    for ks, h in degree_groups(pieces):
        x = h[..., :2] / h[..., 2:]
        d = x[:, 1:] - x[:, :-1]
        n = np.hypot(d[..., 0], d[..., 1])
        lo, hi = column_extremes(x)
        size = np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1])
        ok = n > rel * size[:, None]
        dead = ~np.logical_or.reduce(ok, axis=1) | (size <= 1e-300)
        if strict and np.logical_or.reduce(dead):
            raise DegenerateCurveError("zero-length curve piece", h[np.argmax(dead)])
        i0 = ok.argmax(axis=1)
        i1 = d.shape[1] - 1 - ok[:, ::-1].argmax(axis=1)
        r = np.arange(len(ks))
        for out, i in ((first, i0), (last, i1)):
            length = np.where(dead, 1.0, n[r, i])
            out[ks] = np.where(dead[:, None], 0.0, d[r, i] / length[:, None])
    return first, last


def sample(piece, n):
    """n points at uniform parameters (including both ends)."""
    return evaluate(piece, np.linspace(0.0, 1.0, n))

"""Export: rational pieces -> polynomial cubic / quadratic Béziers with a certified bound.

SVG path data and font outlines hold polynomial cubics (CFF, SVG) or quadratics
(TrueType); the pipeline's pieces are rational.  Each rational piece R = X / W is
covered by few cubics C, fitted by kurbo's curve fitter (``kurbopy.fit_to_bezpath``:
end points and end tangents of the piece, signed area and x-moment matched, the
classic approach of R. Levien's "fitting cubic Béziers" work), and every cubic is
then *certified* against the exact piece, never only sampled:

**The certificate.**  For a cubic C fitted to R on the parameter interval [a, b] a
reparametrisation is chosen: an increasing polynomial bijection
``phi: [0, 1] -> [a, b]`` of degree m <= 9 (least-squares fit to the closest-point
feet of C on R, Bernstein coefficients strictly increasing, so phi' > 0), or, where
one polynomial does not follow the two parametrisations closely enough, a
continuous piecewise one: C is cut exactly (de Casteljau) at s values, R at the
feet of those points, and each panel gets its own polynomial.  On a panel R o phi
is again a rational Bézier curve X~ / W~ (degree n m, weights positive), and the
error

    |R(phi(s)) - C(s)| = |X~(s) - W~(s) C(s)| / W~(s)

is bounded without sampling: E = X~ - W~ C is a Bernstein polynomial, and so are
``|E|^2 = E_x^2 + E_y^2`` and ``W~^2`` (coefficients e_k and v_k > 0).  If
``b^2 v_k - e_k >= 0`` for every k then ``b^2 W~^2 - |E|^2 >= 0`` on [0, 1] (a
non-negative combination of the non-negative Bernstein basis), i.e.

    max_{s in [0,1]} |R(phi(s)) - C(s)| <= b = sqrt(max_k e_k / v_k)     (cubic_bound)

The coefficients are first subdivided (de Casteljau, 2^refine panels, default 8) and
the worst panel taken: the same certificate, tighter because Bernstein coefficients
converge to the polynomial under subdivision.

**What is bounded.**  A bound b of the parametric distance under the monotone
reparametrisation phi bounds the Fréchet distance between C and R restricted to
[a, b], hence the Hausdorff distance: every point of C is within b of R([a, b]) and
every point of R([a, b]) is within b of C.  With phi = identity on [a, b] (no
reparametrisation: :func:`cubic_bound` without ``reparam``) it is the plain
same-parameter distance.  Rounding aside (relative ~1e-15 of the coordinates in the
coefficient products), the bound is rigorous.

**Search.**  Per piece (or per run of pieces with smooth joins, see below),
segments are chosen greedily from the start: the longest parameter interval whose
certified bound is <= tol is looked for with a few fits (error predicted from the
previous fits as ~ h^p, a segment accepted once its bound reaches 0.8 tol), then one
segment fewer is tried while the segments' bounds say it may fit (cuts at equal
shares of the modelled difficulty, :func:`_balanced_split`), or of equal arc length
after a short last segment.  A 90° arc of radius 2 takes 1 / 2 / 2 / 3 / 5 / 7
cubics at tol 1e-3 ... 1e-8 (kurbo's own halving: 1 / 2 / 2 / 4 / 8 / 8; the
classic circle cubic 1 / 2 / 2 / 3 / 5 / 7; bench/export.md).  Where kurbo
finds no cubic, or its cubic does not certify, the same-parameter fit of
:func:`fit_cubic` (Hermite / least squares) is tried, and the interval shrinks until
one certifies.

**Loops.**  A sum splits one smooth convolution curve into many pieces; fitting
piece by piece spends one cubic or more on each.  :func:`loop_to_beziers` splits a
loop at its corners only (:func:`smooth_runs`) and lets cubics span the smooth joins
(:func:`chain_segments`): the certificate cuts the cubic at the feet of the join
points and certifies each part against its piece, phi mapping the cut to the join.
Writers of whole outlines (SVG, fonts) call the loop functions with ``wrap=True`` (a
smooth closing join is spanned as well) and the export share of the user's
tolerance (:func:`split_tolerance`, or :func:`export_tolerance` when the geometry
has a certified error below its share).
"""

import bisect
import math
from collections import namedtuple
from functools import lru_cache

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .errors import DegenerateCurveError, ToleranceNotMetError

__all__ = ["JOIN_ANGLE", "QUADRATIC_CUBIC_SHARE", "SUM_SHARE", "Segment", "chain_segments",
           "cubic_bound", "cubic_segments", "export_tolerance", "fit_cubic", "loop_to_beziers",
           "loop_to_cubics", "loop_to_quadratics", "piece_to_cubics", "piece_to_quadratics",
           "smooth_runs", "split_tolerance"]

#: Share of a user's tolerance given to the geometry (sum, offset, morph frame); the
#: rest goes to the export (cubic fit and coordinate rounding).  See split_tolerance.
#: A quarter: the cubics must follow the sum's pieces, ripples of the QAC
#: approximation included, so export slack is what lets one cubic span several
#: pieces (CFF O offset by 40 units at 0.1 unit: 17 cubics at 0.5, 14 at 0.25; the
#: sum takes ~20 % longer; bench/export.md).
SUM_SHARE = 0.25


def split_tolerance(tol, share=SUM_SHARE):
    """Split a total tolerance into ``(geometry_tol, export_tol)``, summing to ``tol``.

    The one place where the error budget of a written file is divided: a command
    that computes a shape within ``geometry_tol`` of the exact result (Hausdorff
    distance, e.g. :func:`morph.minkowski.minkowski_sum`) and writes it with an exporter
    bounded by ``export_tol`` (Fréchet, hence Hausdorff, distance between the written
    curves and the computed pieces, e.g. :func:`morph.render.write_svg`, the font
    writers) produces a file within ``tol`` of the exact result by the triangle
    inequality of the Hausdorff distance.

    Raises:
        ValueError: tol not positive and finite, or share not in (0, 1).
    """
    tol = float(tol)
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    if not 0.0 < share < 1.0:
        raise ValueError("share must be in (0, 1), got %r" % (share,))
    geometry = share * tol
    return geometry, tol - geometry


def export_tolerance(tol, geometry_bound):
    """The export's share of a total ``tol`` once the geometry's error is bounded.

    ``geometry_bound`` must be a stated upper bound of the Hausdorff distance between
    the computed pieces and the exact shape (never a measurement), e.g. for
    :func:`morph.minkowski.minkowski_sum` at ``geometry_tol``: the largest a-priori
    bound of its convolution pieces (``ConvPiece.bound``, 0 for exact ones such as
    a TrueType glyph ⊕ disk) plus the shares of ``geometry_tol`` it spends on
    anything else (``(1 - CONV_SHARE) * geometry_tol``).  The result is ``tol -
    geometry_bound``: an exporter within it keeps the written file within ``tol``
    of the exact shape (triangle inequality), as :func:`split_tolerance` does with
    the whole geometry share.

    Raises:
        ValueError: tol not positive and finite, or geometry_bound not in [0, tol).
    """
    tol, bound = float(tol), float(geometry_bound)
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    if not 0.0 <= bound < tol:
        raise ValueError("geometry_bound must be in [0, tol), got %r" % (geometry_bound,))
    return tol - bound


#: One certified cubic of a piece: ``cubic`` (4, 2) approximates the piece on
#: [t0, t1] with ``max_s |R(phi(s)) - C(s)| <= bound`` for the continuous increasing
#: phi: [0, 1] -> [t0, t1] given by ``reparam``, a tuple of panels ``(s0, s1,
#: coefficients)`` (phi on [s0, s1] is the polynomial with these Bernstein
#: coefficients in (s - s0) / (s1 - s0)); see :func:`cubic_bound`.
Segment = namedtuple("Segment", "t0 t1 cubic bound reparam")


def _check(piece):
    piece = np.asarray(piece, float)
    if piece.ndim != 2 or piece.shape[1] != 3 or len(piece) < 2:
        raise ValueError("a piece is an (n+1, 3) array with n >= 1, got shape %r"
                         % (piece.shape,))
    if not np.all(np.isfinite(piece)):
        raise ValueError("export needs finite control points, got %r" % (piece,))
    if np.any(piece[:, 2] <= 0):
        raise ValueError("export needs positive weights, got %r" % (piece[:, 2],))
    return piece


# ------------------------------------------------------------------ the certificate

def compose(c, phi):
    """Bernstein coefficients of ``c(phi(s))``: degree n m for c of degree n, phi of m.

    de Casteljau's recursion with the polynomial phi in place of the parameter,
    ``b_i^r = (1 - phi) b_i^{r-1} + phi b_{i+1}^{r-1}`` (products by
    :func:`bernstein.multiply`); trailing axes of ``c`` are carried.  With phi's
    coefficients in [0, 1] every product has non-negative factors, so positive
    weights stay positive.
    """
    c = np.asarray(c, float)
    phi = np.asarray(phi, float)
    if len(phi) == 2 and phi[0] == 0.0 and phi[1] == 1.0:
        return c.copy()
    m = len(phi) - 1
    bm = bz._binomials(m)
    p1 = (bm * phi)[:, None, None]            # binomial-scaled, for the product formula
    p0 = (bm * (1.0 - phi))[:, None, None]
    flat = c.reshape(len(c), -1)
    b = flat[None]                    # axis 0: coefficients of the polynomial entries
    while b.shape[1] > 1:
        d = len(b) - 1
        lo = b[:, :-1] * bz._binomials(d)[:, None, None]
        hi = b[:, 1:] * bz._binomials(d)[:, None, None]
        out = np.zeros((d + m + 1,) + lo.shape[1:])
        for i in range(m + 1):                # sum_{i+j=k} C(m,i) C(d,j) a_i b_j / C(m+d,k)
            out[i:i + d + 1] += p0[i] * lo + p1[i] * hi
        b = out / bz._binomials(d + m)[:, None, None]
    return b[:, 0].reshape((len(b),) + c.shape[1:])


def _error_poly(piece, cubic):
    """Bernstein coefficients of E = X - W C, shape (n + 4, 2)."""
    x = bz.elevate(piece[:, :2], 3)
    wc = bz.multiply(piece[:, 2:3], np.asarray(cubic, float))
    return x - wc


def _square(c):
    """Bernstein coefficients of c^2 (degree 2n) for a scalar Bernstein polynomial c."""
    n = len(c) - 1
    b = bz._binomials(n)
    return np.convolve(b * c, b * c) / bz._binomials(2 * n)


@lru_cache(maxsize=None)
def _panel_matrix(n, refine):
    """Stacked de Casteljau subdivision matrices of degree n onto 2^refine equal panels:
    shape (2^refine, n + 1, n + 1), panel k's coefficients = M[k] @ c."""
    k = 2 ** refine
    eye = np.eye(n + 1)
    return np.stack([bz.subsegment(eye, i / k, (i + 1) / k) for i in range(k)])


def _bound_from_error(e, w, refine=3):
    """sqrt of the smallest b2 with b2 W^2 - |E|^2 >= 0 coefficient-wise on 2^refine panels."""
    e2 = _square(e[:, 0]) + _square(e[:, 1])
    w2 = bz.to_degree(_square(w[:, 0]), len(e2) - 1)
    if refine > 0:
        m = _panel_matrix(len(e2) - 1, refine)
        e2, w2 = m @ e2, m @ w2
    return float(np.sqrt(max(float(np.max(e2 / w2)), 0.0)))


def _normalized_reparam(phi, t0, t1):
    """phi on [t0, t1] as increasing coefficients on [0, 1] (checked)."""
    phi = np.asarray(phi, float)
    u = (phi - t0) / (t1 - t0)
    if abs(u[0]) > 1e-12 or abs(u[-1] - 1.0) > 1e-12 or np.any(np.diff(u) <= 0):
        raise ValueError("a reparametrisation needs increasing Bernstein coefficients")
    u[0], u[-1] = 0.0, 1.0
    return np.clip(u, 0.0, 1.0)


def _panels(reparam):
    """A reparam argument as a list of (s0, s1, phi) panels (checked contiguous)."""
    if isinstance(reparam, np.ndarray) or (len(reparam) and np.isscalar(reparam[0])):
        return [(0.0, 1.0, np.asarray(reparam, float))]
    panels = [(float(a), float(b), np.asarray(f, float)) for a, b, f in reparam]
    ok = panels[0][0] == 0.0 and panels[-1][1] == 1.0 and all(
        p[1] == q[0] and p[2][-1] == q[2][0] and p[0] < p[1]
        for p, q in zip(panels, panels[1:] + [(1.0, 2.0, panels[-1][2][-1:])]))
    if not ok:
        raise ValueError("reparam panels must cover [0, 1] and join continuously")
    return panels


def cubic_bound(piece, cubic, reparam=None, refine=3):
    """Certified bound on the distance between a piece R and a cubic C.

    Without ``reparam``: ``max_{t in [0,1]} |R(t) - C(t)|`` (same parameter).  With
    ``reparam``: ``max_{s in [0,1]} |R(phi(s)) - C(s)|`` for the continuous increasing
    phi it describes, which bounds the Fréchet and Hausdorff distances between C
    and R on [phi(0), phi(1)].  ``reparam`` is either the Bernstein coefficients of
    one increasing polynomial phi (values in [0, 1]) or, as in :class:`Segment`, a
    sequence of panels ``(s0, s1, coefficients)``: phi on [s0, s1] is the polynomial
    in (s - s0) / (s1 - s0).  ``cubic`` is a (4, 2) array of Cartesian control
    points.  The bound is the Bernstein-coefficient certificate of the module
    docstring (never below the true maximum, rounding aside), the largest over the
    panels.

    Raises:
        ValueError: bad piece (shape, weights) or a reparam that is not increasing.
    """
    piece = _check(piece)
    cubic = np.asarray(cubic, float)
    if reparam is None:
        return _bound_from_error(_error_poly(piece, cubic), piece[:, 2:3], refine)
    worst = 0.0
    for s0, s1, phi in _panels(reparam):
        t0, t1 = float(phi[0]), float(phi[-1])
        if not 0.0 <= t0 < t1 <= 1.0:
            raise ValueError("reparam must map [0, 1] into [0, 1] increasingly")
        sub = piece if (t0, t1) == (0.0, 1.0) else pc.subsegment(piece, t0, t1)
        comp = compose(sub, _normalized_reparam(phi, t0, t1))
        c = cubic if (s0, s1) == (0.0, 1.0) else bz.subsegment(cubic, s0, s1)
        worst = max(worst, _bound_from_error(_error_poly(comp, c), comp[:, 2:3], refine))
    return worst


# ------------------------------------------------------------------ fitting

def fit_cubic(piece):
    """Same-parameter cubic with the piece's end points and tangents; (cubic, bound).

    Two candidates are built and the one with the smaller :func:`cubic_bound`
    (same parameter, no reparametrisation) is returned: the Hermite cubic (end
    derivatives matched: P1 = P0 + R'(0)/3, P2 = P3 - R'(1)/3, error O(h^4) under
    subdivision) and the cubic whose two handle lengths minimise the sum of squared
    Bernstein coefficients of E = X - W C (a 2x2 least-squares problem, kept only if
    both lengths are positive so the tangent directions are preserved).  This is the
    fallback of :func:`cubic_segments` where kurbo's fit does not certify (e.g. near
    a zero derivative, where the parametrisations of R and a fitted cubic differ
    too much for a polynomial reparametrisation).
    """
    piece = _check(piece)
    p = pc.cartesian(piece)
    p0, p3 = p[0], p[-1]
    d = pc.derivative(piece, np.array([0.0, 1.0]))
    hermite = np.array([p0, p0 + d[0] / 3.0, p3 - d[1] / 3.0, p3])
    best = (hermite, _bound_from_error(_error_poly(piece, hermite), piece[:, 2:3]))

    n0, n1 = np.hypot(*d[0]), np.hypot(*d[1])
    if n0 > 0 and n1 > 0:
        t0, t1 = d[0] / n0, d[1] / n1
        e0 = _error_poly(piece, np.array([p0, p0, p3, p3]))
        # E(alpha, beta) = e0 - alpha W B1 t0 + beta W B2 t1 (B_i cubic Bernstein basis)
        wb1 = bz.multiply(piece[:, 2:3], np.array([[0.0], [1.0], [0.0], [0.0]]))
        wb2 = bz.multiply(piece[:, 2:3], np.array([[0.0], [0.0], [1.0], [0.0]]))
        mat = np.column_stack([(-wb1 * t0).ravel(), (wb2 * t1).ravel()])
        sol, *_ = np.linalg.lstsq(mat, -e0.ravel(), rcond=None)
        alpha, beta = sol
        if alpha > 0 and beta > 0 and np.all(np.isfinite(sol)):
            cand = np.array([p0, p0 + alpha * t0, p3 - beta * t1, p3])
            bound = _bound_from_error(_error_poly(piece, cand), piece[:, 2:3])
            if bound < best[1]:
                best = (cand, bound)
    return best


class _SubSource:
    """One sub-piece in the power basis, evaluated by Horner's rule in plain floats."""

    def __init__(self, sub):
        self.sub = sub
        power = bz.to_power(sub)
        self.desc = [tuple(float(v) for v in row) for row in power[::-1]]
        self._h = None

    def eval(self, t):
        """X, Y, W and their derivatives at t (Horner's rule with the derivative)."""
        X = Y = W = dX = dY = dW = 0.0
        for cx, cy, cw in self.desc:
            dX, dY, dW = dX * t + X, dY * t + Y, dW * t + W
            X, Y, W = X * t + cx, Y * t + cy, W * t + cw
        return X, Y, W, dX, dY, dW

    @property
    def h(self):
        """Power coefficients of the tangent numerator and its first derivatives (only
        needed where the derivative vanishes)."""
        if self._h is None:
            self._h = []
            hp = bz.to_power(pc.tangent_numerator(self.sub))
            while len(hp) and len(self._h) < 4:
                self._h.append([[float(v) for v in hp[:, k]] for k in range(2)])
                hp = hp[1:] * np.arange(1, len(hp))[:, None]
        return self._h


def _horner(c, t):
    v = 0.0
    for x in reversed(c):
        v = v * t + x
    return v


class _KurboSource:
    """Sub-pieces joined end to end as kurbo's ``ParamCurveFit`` source.

    kurbopy calls ``sample_pt_tangent(u, sign)``, ``sample_pt_deriv(u)`` (each a
    (Point, Vec2) tuple) and ``break_cusp(u0, u1)`` (a parameter or None).  One
    sub-piece keeps its own parameter (u = v).  Several are parametrised by arc
    length (u = s / L): kurbo integrates area and moment by 16-point Gauss-Legendre
    quadrature in u, which a kink of the parametrisation at a join spoils (1e-4
    relative with the pieces' own parameters, enough to miss the best cubic); v(s)
    is a C1 cubic Hermite interpolant of the inverse arc length on 16 intervals per
    sub-piece (lengths by 8-point Gauss-Legendre), its derivative used in the
    chain rule, so samples and derivatives stay consistent.  Each sub-piece is held
    in the power basis and evaluated by Horner's rule in plain floats.  Where the
    derivative vanishes the tangent is the first non-zero higher derivative of the
    tangent numerator X'W - XW', signed by ``sign`` (the one-sided limit).
    """

    _GL = np.polynomial.legendre.leggauss(8)

    def __init__(self, subs):
        import kurbopy

        self._point, self._vec = kurbopy.Point, kurbopy.Vec2
        self._subs = [_SubSource(sub) for sub in subs]
        p = np.vstack([pc.cartesian(sub) for sub in subs])
        self._tiny = 1e-12 * max(float(np.ptp(p[:, 0])), float(np.ptp(p[:, 1])), 1e-300)
        self._tables = self._arclength_tables(subs) if len(subs) > 1 else None

    def _arclength_tables(self, subs, m=16):
        tables, total = [], 0.0
        x, w = self._GL
        for sub in subs:
            v = np.linspace(0.0, 1.0, m + 1)
            speed = np.hypot(*pc.derivative(sub, v).T)
            if not np.all(speed > 0):
                return None
            q = (v[:-1, None] + (x[None] + 1.0) * 0.5 / m).ravel()
            seg = (np.hypot(*pc.derivative(sub, q).T).reshape(m, -1) @ w) * 0.5 / m
            cum = np.concatenate([[0.0], np.cumsum(seg)])
            tables.append((total, [float(c) for c in cum], [float(a) for a in v],
                           [1.0 / float(a) for a in speed]))
            total += float(cum[-1])
        self._total = total
        return tables if total > 0 else None

    def _locate(self, u, sign):
        """(sub-piece, its parameter v, dv/du)."""
        if self._tables is None:
            return 0, min(max(u, 0.0), 1.0), 1.0
        s = min(max(u, 0.0), 1.0) * self._total
        j = 0
        while j + 1 < len(self._tables) and (s > self._tables[j + 1][0] or
                                             (s == self._tables[j + 1][0] and sign > 0)):
            j += 1
        start, cum, v, inv = self._tables[j]
        ell = min(max(s - start, 0.0), cum[-1])
        i = min(max(bisect.bisect_right(cum, ell) - 1, 0), len(cum) - 2)
        h = cum[i + 1] - cum[i]
        t = (ell - cum[i]) / h if h > 0 else 0.0
        t2, t3 = t * t, t * t * t
        val = ((2 * t3 - 3 * t2 + 1) * v[i] + (t3 - 2 * t2 + t) * h * inv[i]
               + (-2 * t3 + 3 * t2) * v[i + 1] + (t3 - t2) * h * inv[i + 1])
        der = ((6 * t2 - 6 * t) * (v[i] - v[i + 1]) / h if h > 0 else 0.0) \
            + (3 * t2 - 4 * t + 1) * inv[i] + (3 * t2 - 2 * t) * inv[i + 1]
        return j, min(max(val, 0.0), 1.0), der * self._total

    def _eval(self, u, sign=1.0):
        j, v, scale = self._locate(u, sign)
        src = self._subs[j]
        X, Y, W, dX, dY, dW = src.eval(v)
        x, y = X / W, Y / W
        return x, y, scale * (dX - x * dW) / W, scale * (dY - y * dW) / W, src, v

    def sample_pt_deriv(self, u):
        x, y, dx, dy, _, _ = self._eval(u)
        return self._point(x, y), self._vec(dx, dy)

    def sample_pt_tangent(self, u, sign):
        x, y, dx, dy, src, v = self._eval(u, sign)
        if math.hypot(dx, dy) <= self._tiny:
            for k, (cx, cy) in enumerate(src.h[1:], start=1):
                s = sign ** k
                dx, dy = s * _horner(cx, v), s * _horner(cy, v)
                if math.hypot(dx, dy) > self._tiny:
                    break
        return self._point(x, y), self._vec(dx, dy)

    def break_cusp(self, u0, u1):
        return None


def _kurbo_cubic(subs, tol):
    """kurbo's best single cubic for the sub-pieces joined, (4, 2) array, or None.

    The accuracy handed to kurbo is loose (half the chord, at least tol) so that it
    returns its best candidate; whether the cubic is good enough is decided by the
    certificate, not by kurbo's sampled error.
    """
    import kurbopy

    p0, p1 = pc.start(subs[0]), pc.end(subs[-1])
    chord = math.hypot(*(p1 - p0))
    accuracy = max(tol, 0.5 * chord)
    try:
        path = kurbopy.fit_to_bezpath(_KurboSource(subs), accuracy)
    except BaseException as exc:  # pyo3 turns panics in callbacks into PanicException
        if isinstance(exc, (KeyboardInterrupt, SystemExit)):
            raise
        return None
    segs = list(path.segments())
    if len(segs) != 1 or not hasattr(segs[0], "p3"):
        return None
    c = segs[0]
    out = np.array([[q.x, q.y] for q in (c.p0, c.p1, c.p2, c.p3)], float)
    out[0], out[-1] = p0, p1
    return out if np.all(np.isfinite(out)) else None


_NODES = 0.5 - 0.5 * np.cos(np.pi * (np.arange(24) + 0.5) / 24)   # Chebyshev nodes
_DENSE = np.linspace(0.0, 1.0, 65)


def _feet(sub, points, iters=4):
    """Parameters u in [0, 1] of the closest points of ``sub`` to ``points``.

    Start at the nearest of 65 samples, then Newton on (R(u) - p) . R'(u) = 0 with
    the rational derivatives from the homogeneous ones (quotient rule), evaluated in
    the power basis by Horner's rule over all points at once.  Returns (u, |R'(u)|).
    """
    desc = bz.to_power(sub)[::-1]
    dense = pc.evaluate(sub, _DENSE)
    u = _DENSE[np.argmin(((points[:, None] - dense[None]) ** 2).sum(-1), axis=1)]

    def jet(u):
        uu = u[:, None]
        h = np.zeros((len(u), 3))
        h1, h2 = h.copy(), h.copy()
        for c in desc:
            h2 = h2 * uu + 2.0 * h1
            h1 = h1 * uu + h
            h = h * uu + c
        w, w1, w2 = h[:, 2:3], h1[:, 2:3], h2[:, 2:3]
        p = h[:, :2] / w
        p1 = (h1[:, :2] - p * w1) / w
        p2 = (h2[:, :2] - 2.0 * p1 * w1 - p * w2) / w
        return p, p1, p2

    for _ in range(iters):
        p, p1, p2 = jet(u)
        r = p - points
        f = (r * p1).sum(1)
        fp = (p1 * p1).sum(1) + (r * p2).sum(1)
        ok = fp > 0
        u = np.clip(u - np.where(ok, f / np.where(ok, fp, 1.0), 0.0), 0.0, 1.0)
    return u, np.hypot(*jet(u)[1].T)


@lru_cache(maxsize=None)
def _node_fit(m):
    """Bernstein basis of degree m at the nodes and the least-squares solver for the
    inner coefficients (end coefficients fixed at 0 and 1)."""
    basis = bz.basis(m, _NODES)
    return basis, np.linalg.pinv(basis[:, 1:-1])


def _reparam_for(sub, cubic, tol):
    """phi: [0,1] -> [0,1] matching C(s) to its closest points R(phi(s)).

    Returns ``(phi, normal)``: phi's increasing Bernstein coefficients, of the lowest
    degree in 1, 3, 5, 7, 9 whose tangential mismatch |phi(s_j) - u_j| |R'(u_j)| at
    24 Chebyshev nodes is below tol / 5 (else the best increasing one), and the
    largest foot distance |R(u_j) - C(s_j)| (what no reparametrisation can beat).
    """
    pts = bz.evaluate(cubic, _NODES)
    u, speed = _feet(sub, pts)
    normal = float(np.max(np.hypot(*(pc.evaluate(sub, u) - pts).T)))
    best = (float(np.max(np.abs(_NODES - u) * speed)), np.array([0.0, 1.0]))
    if best[0] > 0.2 * tol:
        for m in (3, 5, 7, 9):
            basis, pinv = _node_fit(m)
            phi = np.concatenate([[0.0], pinv @ (u - basis[:, -1]), [1.0]])
            if not np.all(np.diff(phi) > 0):
                continue
            miss = float(np.max(np.abs(basis @ phi - u) * speed))
            if miss < best[0]:
                best = (miss, phi)
            if miss <= 0.2 * tol:
                break
    return best[1], normal


def _certify(sub, cubic, tol, depth=3):
    """Certified bound of a cubic against a sub-piece: (bound, panels).

    ``panels`` is a list of ``(s0, s1, phi)``: on s in [s0, s1] the reparametrisation
    is the polynomial with Bernstein coefficients phi (in the local variable
    (s - s0) / (s1 - s0), values in the sub-piece's [0, 1]); together they form one
    continuous increasing phi.  One panel is tried first; when its bound exceeds tol
    although the cubic is within tol of the curve at the nodes (the parametrisations
    differ more than a polynomial of degree 9 follows: rational straight pieces,
    zero end derivatives) the cubic is halved exactly at s = 1/2 (de Casteljau), the
    sub-piece at the foot of C(1/2), and each half certified alone, ``depth`` times.
    A bound <= tol is certified; above tol it may be a sampled distance (a cubic
    farther than tol from the curve at a node is not composed at all).
    """
    phi, normal = _reparam_for(sub, cubic, tol)
    if normal > tol:
        # the cubic is farther than tol from the curve at a node: no reparametrisation
        # can certify it; the sampled distance (a lower bound) guides the search
        return normal, [(0.0, 1.0, phi)]
    comp = compose(sub, phi)
    bound = _bound_from_error(_error_poly(comp, cubic), comp[:, 2:3])
    single = (bound, [(0.0, 1.0, phi)])
    if bound <= tol or depth <= 0 or normal > 0.95 * tol:
        return single
    um = float(_feet(sub, bz.evaluate(cubic, [0.5]))[0][0])
    if not 0.0 < um < 1.0:
        return single
    halves = bz.split(cubic, 0.5)
    subs = pc.split(sub, um)
    (b0, p0), (b1, p1) = (_certify(s, c, tol, depth - 1) for s, c in zip(subs, halves))
    if max(b0, b1) >= bound:
        return single
    panels = [(0.5 * a, 0.5 * b, um * f) for a, b, f in p0] + \
        [(0.5 + 0.5 * a, 0.5 + 0.5 * b, um + (1.0 - um) * f) for a, b, f in p1]
    return max(b0, b1), panels


def _cubic_feet(cubic, points, iters=6):
    """Parameters s in [0, 1] of the closest points of a cubic to ``points`` (Newton)."""
    dense = bz.evaluate(cubic, _DENSE)
    s = _DENSE[np.argmin(((points[:, None] - dense[None]) ** 2).sum(-1), axis=1)]
    d1, d2 = bz.derivative(cubic), bz.derivative(bz.derivative(cubic))
    for _ in range(iters):
        r = bz.evaluate(cubic, s) - points
        p1, p2 = bz.evaluate(d1, s), bz.evaluate(d2, s)
        fp = (p1 * p1).sum(1) + (r * p2).sum(1)
        ok = fp > 0
        s = np.clip(s - np.where(ok, (r * p1).sum(1) / np.where(ok, fp, 1.0), 0.0), 0, 1)
    return s


class _Chain:
    """Consecutive pieces as one curve: parameter T in [0, K], piece k on [k, k + 1]."""

    def __init__(self, pieces):
        self.pieces = [_check(p) for p in pieces]
        self.k = len(self.pieces)

    def point(self, t):
        if t >= self.k:
            return pc.end(self.pieces[-1])
        k = int(math.floor(t))
        if t == k:
            return pc.start(self.pieces[k])
        return pc.evaluate(self.pieces[k], t - k)[0]

    def parts(self, t0, t1):
        """[(k, a, b, sub-piece)]: piece k restricted to local [a, b] covers [t0, t1]."""
        out = []
        for k in range(int(math.floor(t0)), min(self.k, int(math.ceil(t1)))):
            a, b = max(t0 - k, 0.0), min(t1 - k, 1.0)
            if b > a:
                p = self.pieces[k]
                out.append((k, a, b, p if (a, b) == (0.0, 1.0) else pc.subsegment(p, a, b)))
        return out


def _fit_range(chain, t0, t1, tol, ends):
    """Best certified cubic for the chain on [t0, t1]: (cubic, bound, panels).

    Panels carry chain parameters T.  Across joins of the chain the cubic is cut at
    the closest points s_k to the join points (increasing, else no certificate) and
    each part certified against its piece by :func:`_certify`: phi is continuous
    (it maps s_k to the join) and increasing.
    """
    parts = chain.parts(t0, t1)
    subs = [p[3] for p in parts]
    cands = []
    cubic = _kurbo_cubic(subs, tol)
    if cubic is not None:
        cubic[0], cubic[-1] = ends
        if len(parts) == 1:
            bound, panels = _certify(subs[0], cubic, tol)
            panels = [(a, b, (0, f)) for a, b, f in panels]
        else:
            joins = np.array([pc.start(sub) for sub in subs[1:]])
            cuts = np.concatenate([[0.0], _cubic_feet(cubic, joins), [1.0]])
            bound, panels = np.inf, []
            if np.all(np.diff(cuts) > 0):
                bound = 0.0
                for j, sub in enumerate(subs):
                    s0, s1 = cuts[j], cuts[j + 1]
                    b, pj = _certify(sub, bz.subsegment(cubic, s0, s1), tol)
                    bound = max(bound, b)
                    panels += [(s0 + a * (s1 - s0), s0 + b_ * (s1 - s0), (j, f))
                               for a, b_, f in pj]
                    if bound > tol:
                        break
        cands.append((cubic, bound, panels))
    if len(parts) == 1 and (not cands or cands[0][1] > tol):
        cubic, _ = fit_cubic(subs[0])
        cubic[0], cubic[-1] = ends
        bound = _bound_from_error(_error_poly(subs[0], cubic), subs[0][:, 2:3])
        cands.append((cubic, bound, [(0.0, 1.0, (0, np.array([0.0, 1.0])))]))
    if not cands:
        return None, np.inf, None
    cubic, bound, panels = min(cands, key=lambda c: c[1])
    out = []
    for a, b, (j, f) in panels:
        k, lo, hi, _ = parts[j]
        out.append((a, b, k + lo + (hi - lo) * f))
    return cubic, bound, tuple(out)


def _exact_cubic(piece):
    """(4, 2) control points of a polynomial piece of degree <= 3, else None."""
    if len(piece) > 4 or not pc.is_polynomial(piece):
        return None
    return bz.to_degree(pc.cartesian(piece), 3)


def cubic_segments(piece, tol, max_depth=16):
    """Certified cubics covering a piece: a list of :class:`Segment`.

    Segment k has parameter interval [t0, t1] (consecutive, from 0 to 1), a (4, 2)
    cubic C, its ``bound`` <= tol and ``reparam`` (panels of a continuous increasing
    piecewise-polynomial phi from t0 to t1, see :class:`Segment`) with

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    (certified, :func:`cubic_bound` with ``reparam``): the Fréchet and hence the
    Hausdorff distance between C and R on [t0, t1] are <= tol.  Exact pieces
    (polynomial, degree <= 3) give one segment with bound 0.  Raises as
    :func:`piece_to_cubics`.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    piece = _check(piece)
    exact = _exact_cubic(piece)
    if exact is not None:
        return [Segment(0.0, 1.0, exact, 0.0, ((0.0, 1.0, np.array([0.0, 1.0])),))]
    return chain_segments([piece], tol, max_depth)


def chain_segments(pieces, tol, max_depth=16):
    """Certified cubics covering consecutive pieces as one curve: a list of Segment.

    The pieces (end of one = start of the next) form one curve of parameter T in
    [0, K], piece k on [k, k + 1]; cubics may span joins.  Segment intervals
    [t0, t1] and the values of its ``reparam`` panels are such T, and

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    with R the chain and phi continuous and increasing: the Fréchet (hence
    Hausdorff) distance between each cubic and the chain on [t0, t1] is <= tol.
    Spanning a join pays where the join is G1 (tangent continuous: one smooth curve
    split into pieces, as sums produce); at corners the fits fail and the search
    ends segments near them, so callers split chains at corners
    (:func:`loop_to_beziers` does).  Raises as :func:`piece_to_cubics`.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    chain = _Chain(pieces)
    min_width = 2.0 ** -max_depth
    out = []
    t0, start, width = 0.0, pc.start(chain.pieces[0]), min(float(chain.k), 2.0)
    while t0 < chain.k:
        t1, cubic, bound, reparam, end = _next_segment(chain, t0, start, width, tol,
                                                       min_width)
        out.append(Segment(t0, t1, cubic, bound, reparam))
        width = t1 - t0
        t0, start = t1, end
    # the greedy search stops each segment a little short of its longest reach: try
    # one segment fewer, cut where the greedy segments' bounds say it may fit
    while len(out) >= 2:
        fewer = _balanced_split(chain, out, tol)
        if fewer is None:
            break
        out = fewer
    widths = [seg.t1 - seg.t0 for seg in out]
    if len(out) >= 2 and widths[-1] < 0.5 * max(widths[:-1]):
        # a short last one is left: try one segment fewer, equal in arc length
        t, cum = _arclength_table(chain)
        if cum[-1] > 0:
            fewer = _split_at(chain, np.interp(np.linspace(0.0, cum[-1], len(out)), cum, t),
                              tol)
            out = out if fewer is None else fewer
    return out


#: Error model of :func:`_balanced_split`: a cubic's bound grows like the P-th power
#: of the arc length it spans.
ERROR_POWER = 5.0
#: One segment fewer is tried when the greedy segments' shares add up to at most this
#: many segments fewer than there are (the greedy segments stop short of their reach).
FEWER_SLACK = 1.0


def _arclength_table(chain, per=16):
    """(T, cumulative arc length) at ``per`` samples per piece (chords)."""
    t = np.concatenate([k + np.linspace(0.0, 1.0, per + 1)[:-1] for k in range(chain.k)]
                       + [[float(chain.k)]])
    pts = np.vstack([pc.evaluate(p, np.linspace(0.0, 1.0, per + 1)[:-1])
                     for p in chain.pieces] + [pc.end(chain.pieces[-1])[None]])
    return t, np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])


def _balanced_split(chain, segs, tol):
    """len(segs) - 1 certified segments, or None (not plausible, or one fails).

    Segment i of ``segs`` (bound b_i over arc length L_i) counts as d_i = (b_i /
    tol)^(1/P) of a segment that just reaches tol (model bound ~ L^P, P =
    :data:`ERROR_POWER`), spread evenly over its arc length.  When the d_i add up to
    at most len(segs) - 1, the cuts are placed at equal shares of that sum (equal arc
    lengths where the curve is equally hard) and every new cubic is fitted and
    certified as usual; any failure keeps ``segs``."""
    n = len(segs) - 1
    d = np.array([(max(seg.bound, 1e-3 * tol) / tol) ** (1.0 / ERROR_POWER)
                  for seg in segs])
    if not (n >= 1 and d.sum() <= len(segs) - FEWER_SLACK):
        return None
    t, cum = _arclength_table(chain)
    if not cum[-1] > 0:
        return None
    edges = np.interp([segs[0].t0] + [seg.t1 for seg in segs], t, cum)
    hard = np.concatenate([[0.0], np.cumsum(d)])
    cuts = np.interp(np.interp(np.linspace(0.0, hard[-1], n + 1), hard, edges), cum, t)
    return _split_at(chain, cuts, tol)


def _split_at(chain, cuts, tol):
    """Certified segments between the chain parameters ``cuts``, or None if one fails."""
    cuts = np.array(cuts, float)
    cuts[0], cuts[-1] = 0.0, float(chain.k)
    if np.any(np.diff(cuts) <= 0):
        return None
    out, start = [], pc.start(chain.pieces[0])
    for t0, t1 in zip(cuts[:-1], cuts[1:]):
        t0, t1 = float(t0), float(t1)
        end = chain.point(t1)
        cubic, bound, reparam = _fit_range(chain, t0, t1, tol, (start, end))
        if not bound <= tol:
            return None
        out.append(Segment(t0, t1, cubic, bound, reparam))
        start = end
    return out


#: The search stops at a certified segment whose bound is at least this share of tol
#: (higher: longer segments, more fits).
ACCEPT = 0.8


def _next_segment(chain, t0, start, width, tol, min_width):
    """The longest certified segment from t0 found with a few fits: (t1, cubic, bound,
    reparam, end point).  The first try spans ``width``; later ones follow the model
    bound ~ width^p, p from the last two fits (2 <= p <= 8, 5 at first), bracketed
    by the longest certified and the shortest failed interval."""
    top = float(chain.k)

    def attempt(t1):
        end = chain.point(t1)
        cubic, bound, reparam = _fit_range(chain, t0, t1, tol, (start, end))
        return (t1, cubic, bound, reparam, end)

    t1 = min(top, t0 + width)
    if top - t1 < 0.3 * (t1 - t0):
        t1 = top
    good, bad, last, fit = None, None, None, None
    for _ in range(8):
        fit = attempt(t1)
        w, bound = t1 - t0, fit[2]
        if bound <= tol:
            good = fit if good is None or t1 > good[0] else good
            if t1 == top or bound >= ACCEPT * tol:
                break
        else:
            bad = t1 if bad is None else min(bad, t1)
        p = 5.0
        if (last is not None and abs(last[0] - w) > 0.01 * w and last[1] > 0 and bound > 0
                and math.isfinite(bound) and math.isfinite(last[1])):
            p = math.log(bound / last[1]) / math.log(w / last[0])
            p = min(8.0, max(2.0, p))
        last = (w, bound)
        if not math.isfinite(bound):
            ratio = 0.5
        else:
            ratio = (0.9 * tol / bound) ** (1.0 / p) if bound > 0 else 4.0
        target = min(top, t0 + w * min(4.0, max(0.125, ratio)))
        lo = good[0] if good is not None else t0
        hi = bad if bad is not None else top
        if bad is not None and not lo < target < hi:
            target = 0.5 * (lo + hi)
        if good is not None and (target <= lo or (bad is not None and
                                                  hi - lo <= 0.02 * (lo - t0))):
            break
        if target - t0 < min_width:
            break
        t1 = target
    while good is None:
        # no certified fit yet: halve the shortest failed interval down to min_width
        t1 = t0 + 0.5 * (bad - t0)
        if t1 - t0 < min_width:
            raise ToleranceNotMetError(
                "cubic export did not reach tol %.3g on a parameter interval of width "
                "%.3g (bound %.3g)" % (tol, bad - t0, fit[2]),
                piece=chain.pieces[min(int(t0), chain.k - 1)], achieved=fit[2])
        fit = attempt(t1)
        if fit[2] <= tol:
            good = fit
        else:
            bad = t1
    return good


def piece_to_cubics(piece, tol, max_depth=16):
    """Polynomial cubics within ``tol`` of a (rational) piece, list of (4, 2) arrays.

    Each returned cubic C_k covers the piece's parameter interval [t_k, t_k+1] with
    ``max_s |R(phi_k(s)) - C_k(s)| <= tol`` for an increasing polynomial
    reparametrisation phi_k of [0, 1] onto [t_k, t_k+1] (a-priori bound of
    :func:`cubic_bound`, not sampled; see :func:`cubic_segments`): the Fréchet
    distance, and so the Hausdorff distance, between the cubics and the piece is
    <= tol.  The cubics keep the piece's end points exactly and their joins are exact
    (G1 where the piece is regular: end tangent directions are matched).
    Polynomial pieces of degree <= 3 are returned exactly (degree-elevated).  tol is
    absolute, in the piece's units.

    Raises:
        ValueError: tol not positive and finite, or weights not positive.
        ToleranceNotMetError: no cubic certifies on a parameter interval narrower
            than ``2**-max_depth`` (e.g. tol below floating-point resolution of the
            coordinates); ``.achieved`` holds its bound.
    """
    return [seg.cubic for seg in cubic_segments(piece, tol, max_depth)]


#: Joins whose tangent directions differ by less than this angle (radians) are smooth:
#: the loop exporters let cubics span them.
JOIN_ANGLE = 1e-6


def _smooth_join(p, q, angle):
    try:
        a, b = pc.end_tangents(p)[1], pc.end_tangents(q)[0]
    except DegenerateCurveError:
        return False
    ends = np.vstack([pc.cartesian(p), pc.cartesian(q)])
    gap = np.hypot(*(pc.end(p) - pc.start(q)))
    return (float(a @ b) > 0 and abs(float(a[0] * b[1] - a[1] * b[0])) <= math.sin(angle)
            and gap <= 1e-12 * (1.0 + float(np.abs(ends).max())))


def smooth_runs(pieces, join_angle=JOIN_ANGLE):
    """Consecutive pieces split at corners into maximal runs of smooth (G1) joins.

    A join is smooth when the pieces meet (within 1e-12 of the coordinates) and their
    tangent directions there differ by less than ``join_angle`` radians.  A straight
    polynomial piece (a line) is a run of its own: written as a line it costs one
    point, which no cubic spanning it beats (brushed M: 46 points instead of 78).
    ``join_angle <= 0``: every piece is a run of its own (fitting piece by piece:
    about 4 times less CPU than spanning joins, about twice the cubics).
    Returns a list of lists of pieces, in order (a closed loop is not wrapped
    around: its first run starts at its first piece).
    """
    runs = []
    line_before = True
    for p in pieces:
        p = np.asarray(p, float)
        line = len(p) == 2 and pc.is_polynomial(p)
        if (runs and join_angle > 0 and not line and not line_before
                and _smooth_join(runs[-1][-1], p, join_angle)):
            runs[-1].append(p)
        else:
            runs.append([p])
        line_before = line
    return runs


def _wrap_runs(runs, join_angle):
    """Runs of a closed loop with the last run joined to the first when the loop's
    closing join is smooth (the loop's start is then not a break of the fit)."""
    if len(runs) < 2:
        return runs
    last, first = runs[-1][-1], runs[0][0]
    if any(len(p) == 2 and pc.is_polynomial(p) for p in (last, first)):
        return runs
    if not _smooth_join(last, first, join_angle):
        return runs
    return [runs[-1] + runs[0]] + runs[1:-1]


def loop_to_beziers(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Polynomial Béziers within ``tol`` of a loop (or any chain of consecutive pieces).

    Returns (2, 2) lines, (3, 2) quadratics and (4, 2) cubics in order, end to start,
    the first starting at the loop's start.  The loop is split into runs at its
    corners (:func:`smooth_runs`).  With ``wrap`` (a closed loop, the last piece
    ending where the first starts, written by a caller that does not need the output
    to start at the loop's start: SVG subpaths, font contours) a smooth closing join
    is spanned too: the last run and the first are one, and the output starts at
    the start of the loop's last run (at the loop's start when a corner is there).
    A run of polynomial pieces of degree <= 3 is returned
    exactly (lines stay lines, quadratics quadratics: no fitting time is spent on
    what is exact already, e.g. TrueType glyph sums), every other run becomes
    certified cubics (:func:`chain_segments`) that may span its smooth joins: each
    cubic is within ``tol`` of the run in Fréchet, hence Hausdorff, distance, so the
    whole output is within ``tol`` of the loop.  This is what writers of whole
    outlines should call: a smooth curve that the sum split into many pieces needs
    far fewer cubics than the pieces one by one (:func:`piece_to_cubics`).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    out = []
    runs = smooth_runs(loop, join_angle)
    if wrap and join_angle > 0:
        runs = _wrap_runs(runs, join_angle)
    for run in runs:
        if all(len(p) <= 4 and pc.is_polynomial(_check(p)) for p in run):
            out.extend(pc.cartesian(p) for p in run)     # exact already: no fitting
            continue
        out.extend(seg.cubic for seg in chain_segments(run, tol, max_depth))
    return out


def loop_to_cubics(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Cubics within ``tol`` of a loop, in order: :func:`loop_to_beziers` with every
    line and quadratic degree-elevated (exactly)."""
    return [bz.to_degree(b, 3)
            for b in loop_to_beziers(loop, tol, max_depth, join_angle, wrap)]


#: Share of piece_to_quadratics' tolerance given to the cubic stage.
QUADRATIC_CUBIC_SHARE = 0.5


def _cubics_to_quadratics(cubics, tol):
    """cu2qu on each cubic within tol; (3, 2) quadratics with explicit on-curve points."""
    from fontTools.cu2qu import curve_to_quadratic
    from fontTools.cu2qu.errors import Error as Cu2QuError

    out = []
    for cubic in cubics:
        try:
            spline = curve_to_quadratic([tuple(p) for p in cubic], tol, all_quadratic=True)
        except Cu2QuError as exc:
            raise ToleranceNotMetError("cu2qu found no quadratic spline within %.3g"
                                       % tol, piece=cubic) from exc
        spline = np.asarray(spline, float)
        offs = spline[1:-1]
        ons = [spline[0]] + [0.5 * (offs[i] + offs[i + 1]) for i in range(len(offs) - 1)] \
            + [spline[-1]]
        for i, off in enumerate(offs):
            out.append(np.array([ons[i], off, ons[i + 1]]))
    return out


def piece_to_quadratics(piece, tol, max_depth=16):
    """Polynomial quadratics within ``tol`` of a piece, list of (3, 2) arrays.

    The budget is split: cubics within ``QUADRATIC_CUBIC_SHARE * tol``
    (:func:`piece_to_cubics`, certified Fréchet bound), then each cubic to a
    quadratic spline within the rest with ``fontTools.cu2qu.curve_to_quadratic``.
    cu2qu's check is on a common parameter and certified up to rounding: it tests
    the difference curve's control points against the tolerance disk (convex hull)
    and subdivides.  The two errors add (Fréchet distance obeys the triangle
    inequality): the quadratics are within tol of the piece (Fréchet, hence
    Hausdorff).  Polynomial pieces of degree <= 2 are returned exactly.

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics; also when cu2qu finds
            no spline within its limit of segments.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    piece = _check(piece)
    if len(piece) <= 3 and pc.is_polynomial(piece):
        return [bz.to_degree(pc.cartesian(piece), 2)]
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    return _cubics_to_quadratics(piece_to_cubics(piece, cubic_tol, max_depth),
                                 tol - cubic_tol)


def loop_to_quadratics(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Quadratics (and lines) within ``tol`` of a loop, for TrueType outlines.

    :func:`loop_to_beziers` within ``QUADRATIC_CUBIC_SHARE * tol`` (certified Fréchet
    bound; cubics may span smooth joins), then every cubic to quadratics with cu2qu
    within the rest (its own certified same-parameter bound): the errors add, so
    every returned curve is within ``tol`` of the loop (Fréchet, hence Hausdorff).
    Lines come back as (2, 2) arrays and polynomial quadratics exactly; the rest
    are (3, 2) quadratics with explicit on-curve points (a TrueType writer may drop
    the implied midpoints).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_quadratics.
    """
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    out = []
    for b in loop_to_beziers(loop, cubic_tol, max_depth, join_angle, wrap):
        if len(b) <= 3:
            out.append(b)
        else:
            out.extend(_cubics_to_quadratics([b], tol - cubic_tol))
    return out

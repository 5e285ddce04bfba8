"""Export: rational pieces -> polynomial cubic / quadratic Béziers with a certified bound.

SVG path data and font outlines hold polynomial cubics (CFF, SVG) or quadratics
(TrueType); the pipeline's pieces are rational.  Each rational piece R = X / W is
covered by few cubics C, fitted by the method of kurbo's curve fitter (end points
and end tangents of the piece, signed area and x-moment matched: R. Levien's
"fitting cubic Béziers" work), done here in numpy for many ranges at once
(:func:`_moment_cubics`), and every cubic is then *certified* against the exact
piece, never only sampled:

**The certificate.**  For a cubic C fitted to R on the parameter interval [a, b] a
reparametrisation is chosen: an increasing polynomial bijection
``phi: [0, 1] -> [a, b]`` of degree m <= 9 (least-squares fit to the closest-point
feet of C on R, Bernstein coefficients strictly increasing, so phi' > 0), composed
with a Möbius map mu(v) = c v / ((c - 1) v + 1) where no polynomial alone follows
the feet (R o mu is R with its weights scaled by c^i: the same curve, exactly), or,
where that does not follow the two parametrisations closely enough either, a
continuous piecewise one: C is cut exactly (de Casteljau) at s values, R at the
feet of those points, and each panel gets its own map.  On a panel R o mu o phi
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
converge to the polynomial under subdivision.  The curve math is the shared layer's:
R o phi by :func:`morph.bernstein.compose_many`, the certificate by
:func:`morph.piece.distance_bound_many`, the feet by
:func:`morph.piece.nearest_params_many`, phi by :func:`morph.bernstein.fit_fixed_ends`.

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
previous fits as ~ h^p, a segment accepted once its bound reaches 0.7 tol), then one
segment fewer is tried while the segments' bounds say it may fit (cuts at equal
shares of the modelled difficulty, :func:`_balanced_cuts`), or of equal arc length
after a short last segment.  The searches of all runs of a loop go in lockstep
(:func:`_drive`), over all loops of a region or of many glyphs
(:func:`loops_to_beziers`): each round fits the pending ranges of every run in one
batch (:func:`_moment_cubics`, no callbacks), certifies all their cubics in one
batch (:func:`_certify_many`; a cubic whose sampled distance exceeds SCREEN tol
is not certified, nor is a try whose sampled distance is below PROVISIONAL tol:
the search extends it anyway, and certifies it only if it ends there).  A 90° arc of radius 2 takes 1 / 2 / 2 / 3 / 5 / 7
cubics at tol 1e-3 ... 1e-8 (kurbo's own halving: 1 / 2 / 2 / 4 / 8 / 8; the
classic circle cubic 1 / 2 / 2 / 3 / 5 / 7; bench/export.md).  Where the fit
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
tolerance (:func:`morph.budget.plan`, or :meth:`morph.budget.Budget.after` when the
geometry has a certified error below its share).
"""

import functools
import math
from collections import namedtuple

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .budget import PHI_SHARE, QUADRATIC_CUBIC_SHARE
from .errors import ToleranceNotMetError

__all__ = ["JOIN_ANGLE", "CubicFit", "chain_segments",
           "cubic_bound", "cubic_segments", "fit_cubic", "loop_to_beziers",
           "loop_to_cubics", "loop_to_quadratics", "loops_to_beziers",
           "loops_to_quadratics", "piece_to_cubics", "piece_to_quadratics",
           "smooth_runs"]

#: One certified cubic of a piece or chain: ``cubic`` (4, 2) approximates it on
#: [t0, t1] with ``max_s |R(phi(s)) - C(s)| <= bound`` for the continuous increasing
#: phi: [0, 1] -> [t0, t1] given by ``reparam``, a tuple of panels ``(s0, s1,
#: coefficients)`` (phi on [s0, s1] is the rational Bézier function of (s - s0) /
#: (s1 - s0) with these (m+1, 2) [numerator, weight] coefficients: a polynomial
#: composed with a Möbius map, see :func:`_reparams`); see :func:`cubic_bound`.
CubicFit = namedtuple("CubicFit", "t0 t1 cubic bound reparam")


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

#: de Casteljau halvings of the certificate's coefficients (2^REFINE panels).
REFINE = 3


def homogeneous_reparam(phi):
    """A reparametrisation's coefficients as an (m+1, 2) array [numerator, weight]:
    (m+1,) Bernstein coefficients of a polynomial get weights 1; an (m+1, 2) array
    (a rational Bézier function, value numerator / weight) is checked and returned."""
    phi = np.asarray(phi, float)
    if phi.ndim == 1:
        return np.stack([phi, np.ones_like(phi)], axis=1)
    if phi.ndim != 2 or phi.shape[1] != 2 or not np.all(phi[:, 1] > 0):
        raise ValueError("a reparametrisation is (m+1,) Bernstein coefficients or (m+1, 2) "
                         "[numerator, weight] with positive weights")
    return phi


def _affine(h, a, b):
    """Homogeneous reparametrisation coefficients of a + b phi (h those of phi)."""
    out = h.copy()
    out[:, 0] = a * h[:, 1] + b * h[:, 0]
    return out


def _normalized_reparam(phi, t0, t1):
    """phi on [t0, t1] as increasing homogeneous coefficients on [0, 1] (checked).

    A rational Bézier function with positive weights and increasing values
    numerator_i / weight_i is increasing (its derivative's numerator has
    non-negative Bernstein coefficients)."""
    h = _affine(homogeneous_reparam(phi), -t0 / (t1 - t0), 1.0 / (t1 - t0))
    u = h[:, 0] / h[:, 1]
    if abs(u[0]) > 1e-12 or abs(u[-1] - 1.0) > 1e-12 or np.any(np.diff(u) <= 0):
        raise ValueError("a reparametrisation needs increasing Bernstein coefficients")
    h[0, 0], h[-1, 0] = 0.0, h[-1, 1]
    h[:, 0] = np.clip(h[:, 0], 0.0, h[:, 1])
    return h


def _value(h, i):
    return float(h[i, 0] / h[i, 1])


def _panels(reparam):
    """A reparam argument as a list of (s0, s1, homogeneous phi) panels (checked
    contiguous: values at the panels' joins equal to 1e-12)."""
    if isinstance(reparam, np.ndarray) or (len(reparam) and np.isscalar(reparam[0])):
        return [(0.0, 1.0, homogeneous_reparam(reparam))]
    panels = [(float(a), float(b), homogeneous_reparam(f)) for a, b, f in reparam]
    ok = panels[0][0] == 0.0 and panels[-1][0] < panels[-1][1] == 1.0 and all(
        p[0] < p[1] and p[1] == q[0] and abs(_value(p[2], -1) - _value(q[2], 0)) <= 1e-12
        for p, q in zip(panels, panels[1:]))
    if not ok:
        raise ValueError("reparam panels must cover [0, 1] and join continuously")
    return panels


def _same_param_bound(piece, cubic, refine=REFINE):
    """:func:`morph.piece.distance_bound_many` of one piece and one cubic."""
    return float(pc.distance_bound_many(piece[None], np.asarray(cubic, float)[None],
                                        refine)[0][0])


def cubic_bound(piece, cubic, reparam=None, refine=REFINE):
    """Certified bound on the distance between a piece R and a cubic C.

    Without ``reparam``: ``max_{t in [0,1]} |R(t) - C(t)|`` (same parameter).  With
    ``reparam``: ``max_{s in [0,1]} |R(phi(s)) - C(s)|`` for the continuous increasing
    phi it describes, which bounds the Fréchet and Hausdorff distances between C
    and R on [phi(0), phi(1)].  ``reparam`` is either the coefficients of one
    increasing phi (values in [0, 1]) or, as in :class:`CubicFit`, a sequence of
    panels ``(s0, s1, coefficients)``: phi on [s0, s1] is the function of (s - s0)
    / (s1 - s0) with these coefficients, (m+1,) Bernstein coefficients of a
    polynomial or (m+1, 2) [numerator, weight] of a rational Bézier function
    (:func:`homogeneous_reparam`).  ``cubic`` is a (4, 2) array of Cartesian control
    points.  On each panel R o phi is composed exactly
    (:func:`morph.bernstein.compose`) and the coefficient-ratio certificate
    :func:`morph.piece.distance_bound_many` applied on 2^refine panels (never below
    the true maximum, rounding aside); the largest over the panels is returned.

    Raises:
        ValueError: bad piece (shape, weights) or a reparam that is not increasing.
    """
    piece = _check(piece)
    cubic = np.asarray(cubic, float)
    if reparam is None:
        return _same_param_bound(piece, cubic, refine)
    worst = 0.0
    for s0, s1, phi in _panels(reparam):
        t0, t1 = _value(phi, 0), _value(phi, -1)
        if not 0.0 <= t0 < t1 <= 1.0:
            raise ValueError("reparam must map [0, 1] into [0, 1] increasingly")
        sub = piece if (t0, t1) == (0.0, 1.0) else pc.subsegment(piece, t0, t1)
        h = _normalized_reparam(phi, t0, t1)
        comp = bz.compose_many(sub[None], h[None, :, 0], h[None, :, 1])[0]
        c = cubic if (s0, s1) == (0.0, 1.0) else bz.subsegment(cubic, s0, s1)
        worst = max(worst, _same_param_bound(comp, c, refine))
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
    fallback of :func:`cubic_segments` where the moment fit does not certify (e.g. near
    a zero derivative, where the parametrisations of R and a fitted cubic differ
    too much for a polynomial reparametrisation).
    """
    piece = _check(piece)
    p = pc.cartesian(piece)
    p0, p3 = p[0], p[-1]
    d = pc.derivative(piece, np.array([0.0, 1.0]))
    hermite = np.array([p0, p0 + d[0] / 3.0, p3 - d[1] / 3.0, p3])
    best = (hermite, _same_param_bound(piece, hermite))

    n0, n1 = np.hypot(*d[0]), np.hypot(*d[1])
    if n0 > 0 and n1 > 0:
        t0, t1 = d[0] / n0, d[1] / n1
        w = piece[:, 2:3]
        e0 = bz.elevate(piece[:, :2], 3) - bz.multiply(w, np.array([p0, p0, p3, p3]))
        # E(alpha, beta) = e0 - alpha W B1 t0 + beta W B2 t1 (B_i cubic Bernstein basis)
        wb1 = bz.multiply(w, np.array([[0.0], [1.0], [0.0], [0.0]]))
        wb2 = bz.multiply(w, np.array([[0.0], [0.0], [1.0], [0.0]]))
        mat = np.column_stack([(-wb1 * t0).ravel(), (wb2 * t1).ravel()])
        sol, *_ = np.linalg.lstsq(mat, -e0.ravel(), rcond=None)
        alpha, beta = sol
        if alpha > 0 and beta > 0 and np.all(np.isfinite(sol)):
            cand = np.array([p0, p0 + alpha * t0, p3 - beta * t1, p3])
            bound = _same_param_bound(piece, cand)
            if bound < best[1]:
                best = (cand, bound)
    return best


#: Intervals per piece of a chain's arc-length table (lengths by 8-point
#: Gauss-Legendre on each).
ARC_INTERVALS = 32


class _Chain:
    """Consecutive pieces as one curve: parameter T in [0, K], piece k on [k, k + 1].

    Set up once per chain, used by every fit on it: its pieces, where they sit in
    the per-degree stacks of the batch (``banks``, ``where``: set by
    :func:`_chains_segments`) and an arc-length table (:meth:`arc_table`):
    ARC_INTERVALS equal parameter intervals per piece with their lengths and the
    speeds at their ends.
    """

    def __init__(self, pieces):
        self.pieces = [_check(p) for p in pieces]
        self.k = len(self.pieces)
        self.stack = pc.stack(self.pieces)
        p = np.vstack([pc.cartesian(q) for q in self.pieces])
        self.tiny = 1e-12 * max(float(np.ptp(p[:, 0])), float(np.ptp(p[:, 1])), 1e-300)
        self._arc = None

    def point(self, t):
        if t >= self.k:
            return pc.end(self.pieces[-1])
        k = int(math.floor(t))
        if t == k:
            return pc.start(self.pieces[k])
        return pc.evaluate(self.pieces[k], t - k)[0]

    def arc_table(self):
        """(T_left, T_right, s_left, s_right, v_left, v_right): per interval (all
        pieces, in order) its chain parameters, cumulative arc lengths and speeds
        |dP/dT| at both ends; arrays of K * ARC_INTERVALS."""
        if self._arc is None:
            m, (x, w) = ARC_INTERVALS, _quadrature().gl8
            knots = np.linspace(0.0, 1.0, m + 1)
            q = (knots[:-1, None] + (x[None] + 1.0) * 0.5 / m).ravel()
            ks = np.arange(self.k)
            _, d = pc.jet_many(self.stack, np.repeat(ks, len(q)), np.tile(q, self.k))
            seg = (np.hypot(*d.T).reshape(self.k, m, len(x)) @ w) * 0.5 / m
            _, dk = pc.jet_many(self.stack, np.repeat(ks, m + 1), np.tile(knots, self.k))
            speed = np.hypot(*dk.T).reshape(self.k, m + 1)
            cum = np.concatenate([[0.0], np.cumsum(seg.ravel())])
            tl = (ks[:, None] + knots[None, :-1]).ravel()
            self._arc = (tl, tl + 1.0 / m, cum[:-1], cum[1:], speed[:, :-1].ravel(),
                         speed[:, 1:].ravel())
        return self._arc

def _limit_tangent(piece, t, sign, tiny):
    """Direction of travel of a piece at t where its derivative vanishes: the first
    derivative of the tangent numerator H = X'W - XW' (:func:`morph.piece.
    tangent_numerator`, zeros at the ends divided out) that is not zero, k-th
    signed by sign^k (the one-sided limit from the side ``sign``)."""
    h = pc.tangent_numerator(piece)
    for k in range(4):
        v = bz.evaluate(h, [t])[0]
        if math.hypot(*v) > tiny or len(h) == 1:
            return sign ** k * v
        h = bz.derivative(h)
    return v


# ------------------------------------------------------------------ the batched fitter

_Quadrature = namedtuple("_Quadrature", "gl8 gx gw i2 i3")


@functools.lru_cache(maxsize=1)
def _quadrature():
    """The fitter's constants, made on first use (numpy.polynomial, which gives the
    Gauss-Legendre rules, takes ~4 ms to import: a process that fits nothing, such
    as a TrueType sum written exactly, does not pay it): ``gl8`` the 8-point rule on
    [-1, 1]; ``gx``, ``gw`` the 16-point rule on [0, 1]; ``i2[j, k]`` = int B_j B_k'
    and ``i3[i, j, k]`` = int B_i B_j B_k' over [0, 1] for the cubic Bernstein basis
    (the 8-point rule, exact for these degrees)."""
    gl8 = np.polynomial.legendre.leggauss(8)
    x, w = 0.5 + 0.5 * gl8[0], 0.5 * gl8[1]
    b = bz.basis(3, x)                                             # (8, 4)
    diff = 3.0 * (np.eye(3, 4, 1) - np.eye(3, 4))                  # B3_k' in B2
    db = bz.basis(2, x) @ diff
    gx, gw = np.polynomial.legendre.leggauss(16)
    return _Quadrature(gl8, 0.5 + 0.5 * gx, 0.5 * gw,
                       np.einsum("g,gj,gk->jk", w, b, db),
                       np.einsum("g,gi,gj,gk->ijk", w, b, b, db))


#: Handle lengths d0 (in chord lengths) where the moment equation is solved.
_D0_GRID = np.linspace(0.0, 2.0, 81)[1:]
#: kurbo's handle-length penalty: the sampled error is scaled by
#: (1 + max(d - elbow, 0) * slope)^2 for the longer handle d (in chord lengths).
D_ELBOW, D_SLOPE = 0.65, 2.0
#: The fitter's acceptance distance is at most this multiple of tol (a cubic 16 tol
#: away certifies nothing; the search then halves its step).
FIT_SLACK = 16.0
#: Candidate cubics kept per range (roots of the moment equation).
MAX_CANDIDATES = 6


def _frame(v, chord, chord2):
    """Vectors v (..., 2) in the unit-chord frame: x along the chord, y to its left,
    divided by the chord length (``chord`` (..., 2), ``chord2`` its squared length)."""
    return np.stack([(v * chord).sum(-1), chord[..., 0] * v[..., 1] - chord[..., 1] * v[..., 0]],
                    axis=-1) / chord2[..., None]


def _moment_cubics(items, tol):
    """Fitted cubics for many chain ranges at once (no callbacks): for each item
    ``(chain, parts, (start, end))`` a (4, 2) cubic with those end points and its
    sampled distance (below), or None.

    R. Levien's area-and-moment fit, as kurbo's ``fit_to_cubic`` does it (kurbo's
    fit.rs): in the frame where the chord runs from (0, 0) to (1, 0), the cubic
    with the range's end tangent directions (angles th0, th1) and handle lengths
    d0, d1 is chosen so that its signed area int y dx and moment int x y dx equal
    the range's.  The range's integrals are Gauss-Legendre sums (16 nodes on each
    part, in the part's own parameter: the integrals do not depend on the
    parametrisation); the cubic's are polynomials in (d0, d1) (exact Bernstein
    integrals of :func:`_quadrature`).  The area is linear in d1, so d1 = d1(d0)
    and the moment equation becomes one equation in d0, solved on a grid of d0
    (sign changes, refined by regula falsi; without one, the grid point of least
    residual, like kurbo's real part of a complex root pair).  Of the candidates
    the one with the least sampled distance wins: rays from the range's samples
    along their normals to the cubic (Newton), scaled by kurbo's penalty on long
    handles, kept if below the acceptance distance (half the chord, at least tol,
    at most FIT_SLACK tol).  A chord shorter than that gets its straight line.
    Nothing here is a certificate: the caller certifies (:func:`_certify_many`).
    """
    n = len(items)
    if not n:
        return []
    starts = np.array([e[0] for _, _, e in items], float)
    ends = np.array([e[1] for _, _, e in items], float)
    chord = ends - starts
    chord2 = (chord * chord).sum(1)
    length = np.sqrt(chord2)
    acc = np.maximum(tol, np.minimum(0.5 * length, FIT_SLACK * tol))
    short = length <= acc
    good = ~short & (chord2 > 0)
    safe2 = np.where(good, chord2, 1.0)
    sam = _range_samples(items, starts, chord, safe2)
    ta, tm = _cubic_integrals(sam["t0"], sam["t1"])
    cr, cd0, cd1 = _handle_candidates(sam["area"], sam["moment"], ta, tm, good)
    t0, t1 = sam["t0"], sam["t1"]
    ctrl = np.zeros((len(cr), 4, 2))
    ctrl[:, 1] = cd0[:, None] * t0[cr]
    ctrl[:, 2, 0] = 1.0 - cd1 * t1[cr, 0]
    ctrl[:, 2, 1] = -cd1 * t1[cr, 1]
    ctrl[:, 3, 0] = 1.0
    # sampled distance: rays along the samples' normals to the candidate cubic
    err = _ray_distance(ctrl, cr, sam["q"], sam["dq"], sam["req"], sam["width"]) * length[cr]
    scale = (1.0 + np.maximum(np.maximum(cd0, cd1) - D_ELBOW, 0.0) * D_SLOPE) ** 2
    return _picked_cubics(err * scale, err, cr, ctrl, acc, short, starts, ends, chord)


def _range_samples(items, starts, chord, safe2):
    """The ranges' samples for :func:`_moment_cubics`, in the chord frames: 16
    Gauss-Legendre nodes on each part (one evaluation for all), their points ``q``
    and derivatives ``dq`` (P, 16, 2) with the owning range ``req`` and the parts'
    parameter ``width``; each range's ``area`` and ``moment`` (Gauss-Legendre sums)
    and its unit end tangents ``t0``, ``t1`` (one-sided limits where the derivative
    vanishes)."""
    n = len(items)
    banks = items[0][0].banks
    req, deg, idx, lo, width, first, last = [], [], [], [], [], [], []
    for r, (chain, parts, _) in enumerate(items):
        first.append(len(idx))
        for k, a, b, _ in parts:
            req.append(r)
            deg.append(chain.where[k][0])
            idx.append(chain.where[k][1])
            lo.append(a)
            width.append(b - a)
        last.append(len(idx) - 1)
    req, deg, idx = np.array(req), np.array(deg), np.array(idx)
    lo, width = np.array(lo), np.array(width)
    first, last = np.array(first), np.array(last)
    quad = _quadrature()
    m = len(quad.gx)
    params = lo[:, None] + width[:, None] * quad.gx[None]
    p, d = _bank_jet(banks, np.repeat(deg, m), np.repeat(idx, m), params.ravel())
    ends_at = np.concatenate([first, last])
    _, de = _bank_jet(banks, deg[ends_at], idx[ends_at],
                      np.concatenate([lo[first], lo[last] + width[last]]))
    for j in np.nonzero(np.hypot(*de.T) <= np.array([c.tiny for c, _, _ in items] * 2))[0]:
        r, sign = j % n, (1.0 if j < n else -1.0)
        chain, parts, _ = items[r]
        k, a, b, _ = parts[0] if sign > 0 else parts[-1]
        de[j] = _limit_tangent(chain.pieces[k], a if sign > 0 else b, sign, chain.tiny)
    q = _frame(p.reshape(-1, m, 2) - starts[req][:, None], chord[req][:, None],
               safe2[req][:, None])                                # (P, m, 2)
    dq = _frame(d.reshape(-1, m, 2), chord[req][:, None], safe2[req][:, None])
    wgt = quad.gw[None] * width[:, None]
    t0 = _frame(de[:n], chord, safe2)
    t1 = _frame(de[n:], chord, safe2)
    t0 /= np.maximum(np.hypot(*t0.T), 1e-300)[:, None]
    t1 /= np.maximum(np.hypot(*t1.T), 1e-300)[:, None]
    return {"q": q, "dq": dq, "req": req, "width": width, "t0": t0, "t1": t1,
            "area": np.bincount(req, (wgt * q[..., 1] * dq[..., 0]).sum(1), n),
            "moment": np.bincount(req, (wgt * q[..., 0] * q[..., 1] * dq[..., 0]).sum(1), n)}


def _cubic_integrals(t0, t1):
    """Area and moment of the frame cubics K + d0 U + d1 V (end tangents t0, t1) as
    polynomials in (d0, d1): ``ta`` (n, 2, 3) area terms d_b m_c and ``tm``
    (n, 3, 2, 3) moment terms m_a d_b m_c, m = (1, d0, d1) (exact Bernstein
    integrals of :func:`_quadrature`)."""
    n = len(t0)
    c0, s0, c1, s1 = t0[:, 0], t0[:, 1], t1[:, 0], -t1[:, 1]
    zero, one = np.zeros(n), np.ones(n)
    xs = np.stack([np.stack([zero, zero, one, one], 1), np.stack([zero, c0, zero, zero], 1),
                   np.stack([zero, zero, -c1, zero], 1)], 1)       # (n, 3, 4): K, U, V
    ys = np.stack([np.stack([zero, s0, zero, zero], 1),
                   np.stack([zero, zero, s1, zero], 1)], 1)        # (n, 2, 4): U, V
    quad = _quadrature()
    ta = np.einsum("rbj,rck,jk->rbc", ys, xs, quad.i2)
    tm = np.einsum("rai,rbj,rck,ijk->rabc", xs, ys, xs, quad.i3)
    return ta, tm


def _handle_candidates(area, moment, ta, tm, good):
    """Candidate handle lengths (range, d0, d1) of :func:`_moment_cubics`: the roots
    of the moment residual in d0 on :data:`_D0_GRID` (sign changes refined by regula
    falsi), its local minima that do not cross zero, and handles of a third where
    nothing solves; at most MAX_CANDIDATES per range, positive and finite."""
    n = len(area)

    def resid(d0, d1, rows=slice(None)):
        mm = np.stack([np.ones_like(d0), d0, d1], -1)
        nn = np.stack([d0, d1], -1)
        return np.einsum("rga,rgb,rgc,rabc->rg", mm, nn, mm, tm[rows]) - moment[rows, None]

    d0 = np.broadcast_to(_D0_GRID[None], (n, len(_D0_GRID)))
    d1 = _d1_of(d0, np.arange(n)[:, None], area, ta)
    ok = np.isfinite(d1) & (d1 > 0)
    f = np.where(ok, resid(d0, np.where(ok, d1, 0.0)), np.nan)
    cross = ok[:, :-1] & ok[:, 1:] & (np.sign(f[:, :-1]) != np.sign(f[:, 1:]))
    cross &= good[:, None]
    rr, gg = np.nonzero(cross)
    a, b = _D0_GRID[gg], _D0_GRID[gg + 1]
    fa, fb = f[rr, gg], f[rr, gg + 1]
    for _ in range(4):                                             # regula falsi
        x = (a * fb - b * fa) / (fb - fa)
        fx = resid(x[:, None], _d1_of(x, rr, area, ta)[:, None], rr)[:, 0]
        left = np.sign(fx) == np.sign(fa)
        a, fa = np.where(left, x, a), np.where(left, fx, fa)
        b, fb = np.where(left, b, x), np.where(left, fb, fx)
    roots = (a * fb - b * fa) / (fb - fa) if len(rr) else np.zeros(0)
    # local minima of |f| that do not cross zero (kurbo: the real part of a complex
    # root pair, a near-double root): the grid points where |f| is least
    af = np.where(ok, np.abs(f), np.inf)
    dip = np.zeros_like(ok)
    dip[:, 1:-1] = (af[:, 1:-1] <= af[:, :-2]) & (af[:, 1:-1] <= af[:, 2:]) & ok[:, 1:-1]
    dip[:, 0] = ok[:, 0] & (af[:, 0] <= af[:, 1])
    near = np.zeros_like(ok)
    near[:, :-1] |= cross
    near[:, 1:] |= cross
    dip &= ~near & good[:, None]
    rn, gn = np.nonzero(dip)
    none = np.zeros(n, bool)
    none[rn] = True
    # nothing solves (e.g. a straight range: area and moment vanish): handles of a
    # third, the straight cubic when the tangents run along the chord
    rt = np.nonzero(good & ~np.any(cross, 1) & ~none)[0]
    cr = np.concatenate([rr, rn, rt])
    cd0 = np.concatenate([roots, _D0_GRID[gn], np.full(len(rt), 1.0 / 3.0)])
    thirds = np.arange(len(cr)) >= len(cr) - len(rt)
    keep = np.zeros(len(cr), bool)
    count = {}
    for i, r in enumerate(cr.tolist()):                   # at most MAX_CANDIDATES per range
        count[r] = count.get(r, 0) + 1
        keep[i] = count[r] <= MAX_CANDIDATES
    cr, cd0, thirds = cr[keep], cd0[keep], thirds[keep]
    cd1 = np.where(thirds, 1.0 / 3.0, _d1_of(cd0, cr, area, ta))
    fine = np.isfinite(cd1) & (cd1 > 0) & (cd0 > 0)
    return cr[fine], cd0[fine], cd1[fine]


def _picked_cubics(score, err, cr, ctrl, acc, short, starts, ends, chord):
    """Per range the candidate of least score below its acceptance distance, mapped
    back from the chord frame (the straight cubic for a short chord), with its
    sampled distance; None where none is accepted."""
    n = len(starts)
    out = [None] * n
    best = np.full(n, np.inf)
    pick = np.full(n, -1)
    for i in np.argsort(score, kind="stable"):
        r = cr[i]
        if pick[r] < 0 and score[i] < acc[r]:
            pick[r], best[r] = i, score[i]
    for r in range(n):
        if pick[r] >= 0:
            c = ctrl[pick[r]]
            cubic = (starts[r] + c[:, :1] * chord[r]
                     + c[:, 1:] * np.array([-chord[r, 1], chord[r, 0]]))
        elif short[r]:
            cubic = np.array([starts[r], starts[r] + chord[r] / 3.0,
                              ends[r] - chord[r] / 3.0, ends[r]])
        else:
            continue
        cubic[0], cubic[-1] = starts[r], ends[r]
        if np.all(np.isfinite(cubic)):
            out[r] = (cubic, float(err[pick[r]]) if pick[r] >= 0 else 0.0)
    return out


def _bank_jet(banks, deg, idx, t):
    """:func:`morph.piece.jet_many` of pieces ``banks[deg[i]][idx[i]]`` at ``t[i]``:
    each degree evaluated at its own degree (the result of a piece does not depend
    on the other pieces of a batch)."""
    p, d = np.empty((len(t), 2)), np.empty((len(t), 2))
    for g in np.unique(deg):
        rows = np.nonzero(deg == g)[0]
        p[rows], d[rows] = pc.jet_many(banks[g], idx[rows], t[rows])
    return p, d


def _degree_groups(subs):
    """Rows of ``subs`` by degree: [(rows, stacked pieces)] (stacks of one degree, so
    that batched results do not depend on the other pieces of a batch)."""
    groups = {}
    for i, sub in enumerate(subs):
        groups.setdefault(len(sub), []).append(i)
    return [(np.array(rows), np.array([subs[i] for i in rows], float))
            for rows in groups.values()]


def _d1_of(d0, rows, area, ta):
    """d1 from the area equation (linear in d1) for handle lengths d0 of the ranges
    ``rows`` (arrays of one shape)."""
    num = area[rows] - d0 * ta[rows, 0, 0] - d0 * d0 * ta[rows, 0, 1]
    den = ta[rows, 1, 0] + d0 * (ta[rows, 0, 2] + ta[rows, 1, 1])
    with np.errstate(divide="ignore", invalid="ignore"):
        return num / den


#: Power coefficients of a cubic from its Bernstein coefficients.
_POWER3 = np.array([[1.0, 0, 0, 0], [-3, 3, 0, 0], [3, -6, 3, 0], [-1, 3, -3, 1]])


def _ray_distance(ctrl, cr, q, dq, req, width):
    """Largest distance (frame units) from each candidate's range samples to the
    candidate cubic along the samples' normals: Newton on (C(s) - q) . q' = 0 from
    the sample's share of the range's arc length, s clipped to [0, 1]."""
    if not len(cr):
        return np.zeros(0)
    m = q.shape[1]
    pts, tan = q.reshape(-1, 2), dq.reshape(-1, 2)
    speed = np.hypot(*tan.T) * np.repeat(width, m) * np.tile(_quadrature().gw, len(width))
    sreq = np.repeat(req, m)
    cum = np.cumsum(speed)
    tot = np.bincount(sreq, speed)
    base = np.concatenate([[0.0], np.cumsum(tot)])[:-1]
    frac = (cum - 0.5 * speed - base[sreq]) / np.maximum(tot[sreq], 1e-300)
    start = np.searchsorted(sreq, np.arange(len(tot)))           # samples grouped by range
    cnt = np.bincount(sreq, minlength=len(tot))
    counts = cnt[cr]
    owner = np.repeat(np.arange(len(cr)), counts)
    offs = np.arange(counts.sum()) - np.repeat(np.cumsum(counts) - counts, counts)
    si = start[cr][owner] + offs
    power = np.matmul(_POWER3, ctrl)[owner]                       # (S, 4, 2): C(s) = sum a_k s^k
    p, t = pts[si], tan[si]
    s = frac[si]
    g = (power * t[:, None]).sum(2)                               # (C(s) - p) . t, power form
    g[:, 0] -= (p * t).sum(1)
    for _ in range(5):
        gv = ((g[:, 3] * s + g[:, 2]) * s + g[:, 1]) * s + g[:, 0]
        gd = (3.0 * g[:, 3] * s + 2.0 * g[:, 2]) * s + g[:, 1]
        s = np.clip(s - gv / np.where(np.abs(gd) > 1e-300, gd, 1e-300), 0.0, 1.0)
    s = s[:, None]
    c = ((power[:, 3] * s + power[:, 2]) * s + power[:, 1]) * s + power[:, 0]
    dist = np.hypot(*(c - p).T)
    out = np.zeros(len(cr))
    np.maximum.at(out, owner, dist)
    return out


#: Fits whose sampled distance exceeds this multiple of tol are not certified.  The
#: sampled distance is nearly a lower bound of the certified one: on the Relief
#: strokes at tol 0.5, 1 of 50 fits sampled within 1-1.1 tol certified, none above
#: (of ~130); at 1 instead of 1.25 the export spends 18 % fewer certificates, for
#: the same points there and on the brush, O ⊕ disk and O ⊕ ellipse.
SCREEN = 1.0

_NODES = 0.5 - 0.5 * np.cos(np.pi * (np.arange(24) + 0.5) / 24)   # Chebyshev nodes
_NODE_BASIS = bz.basis(3, _NODES)
#: Degrees of the reparametrisation phi tried in turn (the lowest that follows the
#: feet within PHI_SHARE * tol).
PHI_DEGREES = (3, 5, 7, 9)
#: Largest |log c| of the Möbius factor of :func:`_reparams`.
MOEBIUS_LOG = 5.0
#: Dense samples of the closest-point start of :func:`_reparams` (the cubic is
#: within about tol of the piece: a coarse start is in Newton's basin).
REPARAM_SAMPLES = 33


def _moebius(u):
    """Per row the factor c of the Möbius map mu(v) = c v / ((c - 1) v + 1) of [0, 1]
    closest to the feet u (k, 24) at the nodes: the median over the nodes of
    log(u (1 - s) / (s (1 - u))), c = 1 where it is within 5 % of 1 (or undefined)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        logs = np.log(u * (1.0 - _NODES) / (_NODES * (1.0 - u)))
    fine = np.isfinite(logs)
    logs = np.sort(np.where(fine, logs, np.inf), axis=1)         # undefined ones last
    count = fine.sum(axis=1)
    mid = np.where(count > 0, logs[np.arange(len(logs)), np.maximum(count - 1, 0) // 2], 0.0)
    mid = np.clip(mid, -MOEBIUS_LOG, MOEBIUS_LOG)
    return np.where(np.abs(mid) > 0.05, np.exp(mid), 1.0)


def _reparams(subs, cubics, tol):
    """phi: [0,1] -> [0,1] matching each cubic C(s) to its closest points R(phi(s)).

    Returns ``(phis, c, normal)``: for each (sub-piece, cubic) pair phi's increasing
    Bernstein coefficients of the lowest degree in 1, 3, 5, 7, 9 whose tangential
    mismatch |phi(s_j) - u_j| |R'(u_j)| at 24 Chebyshev nodes s_j is below
    PHI_SHARE * tol (:func:`_phi_fits`), a Möbius factor c, and the largest foot
    distance |R(u_j) - C(s_j)| (what no reparametrisation can beat).  Where no
    polynomial follows the feet that closely (a rational piece whose speed varies by
    30x along it: QAC pieces of a stroke), phi is fitted again in the parameter v
    of a Möbius map u = mu(v) = c v / ((c - 1) v + 1) (:func:`_moebius`; on
    homogeneous control points R o mu is R with w_i scaled by c^i, the same curve)
    and kept if it follows better; elsewhere c = 1.  The feet u_j of all
    pairs come from one batched search (:func:`morph.piece.nearest_params_many`),
    phi from one least-squares solve per degree (:func:`morph.bernstein.
    fit_fixed_ends`, ends fixed at 0 and 1).
    """
    pts = np.matmul(_NODE_BASIS, cubics)                        # (k, 24, 2)
    u, p, d = np.empty(pts.shape[:2]), np.empty(pts.shape), np.empty(pts.shape)
    for rows, stack in _degree_groups(subs):
        u[rows] = pc.nearest_params_many(stack, pts[rows], samples=REPARAM_SAMPLES)
        p[rows], d[rows], _ = (pc.jet2_power_many if stack.shape[1] <= 13
                               else pc.jet2_many)(stack, u[rows])
    speed = np.hypot(d[..., 0], d[..., 1])
    normal = np.hypot(*np.moveaxis(p - pts, -1, 0)).max(axis=1)
    c = np.ones(len(subs))
    phis, miss = _phi_fits(u, speed, tol)
    retry = np.nonzero(miss > PHI_SHARE * tol)[0]
    cm = _moebius(u[retry])
    retry, cm = retry[cm != 1.0], cm[cm != 1.0]
    if len(retry):
        v = u[retry] / (cm[:, None] - (cm[:, None] - 1.0) * u[retry])     # mu^-1(u)
        dv = speed[retry] * cm[:, None] / ((cm[:, None] - 1.0) * v + 1.0) ** 2
        again, miss2 = _phi_fits(v, dv, tol)
        for j in np.nonzero(miss2 < miss[retry])[0]:
            i = retry[j]
            phis[i], c[i], miss[i] = again[j], cm[j], miss2[j]
    return phis, c, normal


def _phi_fits(v, speed, tol):
    """Per row the increasing Bernstein coefficients of phi fitted to the feet v
    (k, 24) at the nodes, of the lowest degree in 1, 3, 5, 7, 9 whose tangential
    mismatch |phi(s_j) - v_j| speed_j is below PHI_SHARE * tol (else the increasing
    one of least mismatch), and that mismatch: (list of arrays, (k,))."""
    miss = (np.abs(_NODES - v) * speed).max(axis=1)
    phis = [np.array([0.0, 1.0])] * len(v)
    todo = miss > PHI_SHARE * tol
    for m in PHI_DEGREES:
        rows = np.nonzero(todo)[0]
        if not len(rows):
            break
        phi = bz.fit_fixed_ends(_NODES, v[rows].T, m, 0.0, 1.0).T   # (r, m + 1)
        mono = np.all(np.diff(phi, axis=1) > 0, axis=1)
        err = (np.abs(phi @ bz.basis(m, _NODES).T - v[rows]) * speed[rows]).max(axis=1)
        for j in np.nonzero(mono & (err < miss[rows]))[0]:
            phis[rows[j]], miss[rows[j]] = phi[j], err[j]
        todo[rows[mono & (err <= PHI_SHARE * tol)]] = False
    return phis, miss


def _certify_many(subs, cubics, tol, depth=3):
    """Certified bounds of cubics against sub-pieces, all pairs at once: a list of
    (bound, panels), one per pair.

    ``panels`` is a list of ``(s0, s1, phi)``: on s in [s0, s1] the reparametrisation
    is the rational Bézier function with homogeneous coefficients phi (m+1, 2) in
    the local variable (s - s0) / (s1 - s0), values in the sub-piece's [0, 1]: the
    Möbius map of :func:`_reparams` composed with its polynomial; together they
    form one continuous increasing phi.  The bound is the certificate of the module
    docstring on the exact composition R o mu o phi (R with weights scaled by c^i,
    then :func:`morph.bernstein.compose_many`, one call per pair of degrees, then
    :func:`morph.piece.distance_bound_many`).  Where it exceeds tol although the
    cubic is within tol of the curve at the nodes (the parametrisations differ more
    than a polynomial of degree 9 follows: rational straight pieces, zero end
    derivatives) the cubic is halved exactly at s = 1/2 (de Casteljau), the
    sub-piece at the foot of C(1/2), and the halves certified alone, ``depth``
    times.  A bound <= tol is certified; above tol it may be a sampled distance (a
    cubic farther than tol from the curve at a node is not composed at all).
    """
    cubics = np.asarray(cubics, float)
    phis, cs, normal = _reparams(subs, cubics, tol)
    bound = normal.copy()
    groups = {}
    for i in np.nonzero(normal <= tol)[0]:
        groups.setdefault((len(subs[i]), len(phis[i])), []).append(i)
    for (n, m), rows in groups.items():
        comp = np.array([subs[i] for i in rows]) * (
            cs[rows, None] ** np.arange(n))[:, :, None]         # R o mu: w_i c^i
        if m > 2:
            comp = bz.compose_many(comp, np.array([phis[i] for i in rows]))
        bound[rows] = pc.distance_bound_many(comp, cubics[rows], REFINE)[0]
    homog = [np.stack([c * f, (c - 1.0) * f + 1.0], axis=1) for f, c in zip(phis, cs)]
    out = [(float(b), [(0.0, 1.0, h)]) for b, h in zip(bound, homog)]
    rows = np.nonzero((bound > tol) & (normal <= 0.95 * tol))[0] if depth > 0 else []
    if not len(rows):
        return out
    mids = np.matmul(bz.basis(3, [0.5]), cubics[rows])             # (r, 1, 2)
    um = np.empty(len(rows))
    for grp, stack in _degree_groups([subs[i] for i in rows]):
        um[grp] = pc.nearest_params_many(stack, mids[grp])[:, 0]
    rows, um = rows[(um > 0) & (um < 1)], um[(um > 0) & (um < 1)]
    if not len(rows):
        return out
    left, right = bz.split_many(cubics[rows], np.full(len(rows), 0.5))
    halves = [pc.split(subs[i], u) for i, u in zip(rows, um)]
    res = _certify_many([h[0] for h in halves] + [h[1] for h in halves],
                        np.concatenate([left, right]), tol, depth - 1)
    for j, (i, u) in enumerate(zip(rows, um)):
        (b0, p0), (b1, p1) = res[j], res[len(rows) + j]
        if max(b0, b1) < out[i][0]:
            out[i] = (max(b0, b1),
                      [(0.5 * a, 0.5 * b, _affine(f, 0.0, u)) for a, b, f in p0]
                      + [(0.5 + 0.5 * a, 0.5 + 0.5 * b, _affine(f, u, 1.0 - u))
                         for a, b, f in p1])
    return out


def _parts_many(requests):
    """For every request ``(chain, t0, t1, ends)`` its parts ``[(k, a, b, sub)]``:
    piece k of the chain restricted to its local [a, b] (``sub``) covers [t0, t1];
    the sub-pieces of all requests cut in one de Casteljau call per degree."""
    out, todo = [], {}
    for chain, t0, t1, *_ in requests:
        parts = []
        for k in range(int(math.floor(t0)), min(chain.k, int(math.ceil(t1)))):
            a, b = max(t0 - k, 0.0), min(t1 - k, 1.0)
            if b > a:
                p = chain.pieces[k]
                parts.append([k, a, b, p])
                if (a, b) != (0.0, 1.0):
                    todo.setdefault(len(p), []).append(parts[-1])
        out.append(parts)
    for rows in todo.values():
        subs = bz.subsegment_many(np.array([r[3] for r in rows]), [r[1] for r in rows],
                                  [r[2] for r in rows])
        for r, sub in zip(rows, subs):
            r[3] = sub
    return [[tuple(p) for p in parts] for parts in out]


def _join_feet(plans, skip):
    """{range: parameters on its fitted cubic nearest to the joins of its parts}, for
    the multi-part ranges not skipped, all at once (padded to one count)."""
    multi = [r for r, (parts, cubic) in enumerate(plans)
             if cubic is not None and len(parts) > 1 and not skip[r]]
    if not multi:
        return {}
    n = max(len(plans[r][0]) - 1 for r in multi)
    joins = np.array([[pc.start(p[3]) for p in plans[r][0][1:]]
                      + [pc.start(plans[r][0][-1][3])] * (n + 1 - len(plans[r][0]))
                      for r in multi])
    s = pc.nearest_params_many(np.array([pc.from_points(plans[r][1]) for r in multi]),
                               joins, iters=6)
    return {r: s[i, :len(plans[r][0]) - 1] for i, r in enumerate(multi)}


def _fit_ranges(requests, tol):
    """Best certified cubics for many chain ranges at once: for each request
    ``(chain, t0, t1, (start, end)[, need])`` a result (cubic, bound, panels); where
    the fitted cubic's sampled distance is below ``need`` tol it is returned as is,
    not certified: (cubic, sampled distance, None).

    All ranges are fitted in one call (:func:`_moment_cubics`); then every part of
    every fitted cubic is certified in one batch (:func:`_certify_many`), except
    cubics whose sampled distance exceeds SCREEN tol (their sampled distance is
    returned as the bound: they fail).  Panels
    carry chain parameters T.  Across joins of a chain the cubic is cut at the
    closest points s_k to the join points (increasing, else no certificate) and
    each part certified against its piece: phi is continuous (it maps s_k to the
    join) and increasing.  A single-piece range whose fitted cubic does not certify
    also gets the same-parameter fit of :func:`fit_cubic`; the smaller bound wins.
    """
    parts = _parts_many(requests)
    fits = _moment_cubics(
        [(r[0], pr, r[3]) for pr, r in zip(parts, requests)], tol)
    plans = [(pr, None if f is None else f[0]) for pr, f in zip(parts, fits)]
    sampled = [0.0 if f is None else f[1] for f in fits]
    # a cubic whose sampled distance already exceeds tol well is not certified: its
    # sampled distance is reported (the search only needs to know it fails)
    # a cubic whose sampled distance is below the request's ``need`` share of tol is
    # not certified either: the search will try a longer one (a provisional result)
    short = [f is not None and len(r) > 4 and e < r[4] * tol
             for f, e, r in zip(fits, sampled, requests)]
    skip = [e > SCREEN * tol or sh for e, sh in zip(sampled, short)]
    feet = _join_feet(plans, skip)
    subs, pieces, cut_list = [], [], []
    for r, (parts, cubic) in enumerate(plans):
        cuts = None
        if cubic is not None and not skip[r]:
            cuts = np.concatenate([[0.0], feet.get(r, []), [1.0]])
            if np.all(np.diff(cuts) > 0):
                subs += [p[3] for p in parts]
                pieces.append(cubic[None] if len(parts) == 1 else bz.subsegment_many(
                    np.repeat(cubic[None], len(parts), axis=0), cuts[:-1], cuts[1:]))
            else:
                cuts = None
        cut_list.append(cuts)
    res = _certify_many(subs, np.concatenate(pieces), tol) if subs else []
    out, i = [], 0
    for r, ((parts, cubic), cuts) in enumerate(zip(plans, cut_list)):
        mine = []
        if cubic is not None and cuts is not None:
            mine, i = res[i:i + len(parts)], i + len(parts)
        if short[r]:
            out.append((cubic, sampled[r], None))
            continue
        fallback = sampled[r] if skip[r] else np.inf
        out.append(_chosen_fit(parts, cubic, cuts, mine, fallback, requests[r][3], tol))
    return out


def _chosen_fit(parts, cubic, cuts, certified, fallback, ends, tol):
    """One range's result (cubic, bound, panels) of :func:`_fit_ranges`: the moment
    fit with the worst bound of its certified parts (``fallback`` when it was not
    certified), and for a single piece that fails tol also the same-parameter fit
    of :func:`fit_cubic`; the smaller bound wins.  Panels map back to chain
    parameters T."""
    cands = []
    if cubic is not None:
        bound, panels = fallback, []
        if cuts is not None:
            bound = max(b for b, _ in certified)
            for j, (_, pj) in enumerate(certified):
                s0, s1 = cuts[j], cuts[j + 1]
                panels += [(s0 + a * (s1 - s0), s0 + b * (s1 - s0), (j, f)) for a, b, f in pj]
        cands.append((cubic, bound, panels))
    if len(parts) == 1 and (not cands or cands[0][1] > tol):
        sub = parts[0][3]
        c, bound = fit_cubic(sub)
        c[0], c[-1] = ends
        if not np.array_equal(c[[0, -1]], pc.cartesian(sub)[[0, -1]]):
            bound = _same_param_bound(sub, c)
        cands.append((c, bound, [(0.0, 1.0, (0, np.array([[0.0, 1.0], [1.0, 1.0]])))]))
    if not cands:
        return (None, np.inf, None)
    cubic, bound, panels = min(cands, key=lambda c: c[1])
    return (cubic, bound, tuple(
        (a, b, _affine(f, parts[j][0] + parts[j][1], parts[j][2] - parts[j][1]))
        for a, b, (j, f) in panels))


def _drive(searches, tol):
    """Run search generators in lockstep and return their results in order.

    A search (:func:`_search`) yields a list of fit requests and is sent back their
    results; the pending requests of all searches are fitted and certified together
    (:func:`_fit_ranges`), so the numerical work is one batch per round, not one
    call per fit."""
    results = [None] * len(searches)
    pending = {}
    for i, g in enumerate(searches):
        try:
            pending[i] = next(g)
        except StopIteration as stop:
            results[i] = stop.value
    while pending:
        order = [(i, len(reqs)) for i, reqs in pending.items()]
        fits = _fit_ranges([r for reqs in pending.values() for r in reqs], tol)
        pending, k = {}, 0
        for i, n in order:
            try:
                pending[i] = searches[i].send(fits[k:k + n])
            except StopIteration as stop:
                results[i] = stop.value
            k += n
    return results


def _exact_cubic(piece):
    """(4, 2) control points of a polynomial piece of degree <= 3, else None."""
    if len(piece) > 4 or not pc.is_polynomial(piece):
        return None
    return bz.to_degree(pc.cartesian(piece), 3)


def cubic_segments(piece, tol, max_depth=16):
    """Certified cubics covering a piece: a list of :class:`CubicFit`.

    Fit k has parameter interval [t0, t1] (consecutive, from 0 to 1), a (4, 2)
    cubic C, its ``bound`` <= tol and ``reparam`` (panels of a continuous increasing
    piecewise-polynomial phi from t0 to t1, see :class:`CubicFit`) with

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    (certified, :func:`cubic_bound` with ``reparam``): the Fréchet and hence the
    Hausdorff distance between C and R on [t0, t1] are <= tol.  Exact pieces
    (polynomial, degree <= 3) give one fit with bound 0.  Raises as
    :func:`piece_to_cubics`.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    piece = _check(piece)
    exact = _exact_cubic(piece)
    if exact is not None:
        return [CubicFit(0.0, 1.0, exact, 0.0, ((0.0, 1.0, np.array([[0.0, 1.0], [1.0, 1.0]])),))]
    return chain_segments([piece], tol, max_depth)


def chain_segments(pieces, tol, max_depth=16):
    """Certified cubics covering consecutive pieces as one curve: a list of CubicFit.

    The pieces (end of one = start of the next) form one curve of parameter T in
    [0, K], piece k on [k, k + 1]; cubics may span joins.  Fit intervals [t0, t1]
    and the values of its ``reparam`` panels are such T, and

        max_{s in [0,1]} |R(phi(s)) - C(s)| <= bound <= tol

    with R the chain and phi continuous and increasing: the Fréchet (hence
    Hausdorff) distance between each cubic and the chain on [t0, t1] is <= tol.
    Spanning a join pays where the join is G1 (tangent continuous: one smooth curve
    split into pieces, as sums produce); at corners the fits fail and the search
    ends segments near them, so callers split chains at corners
    (:func:`loop_to_beziers` does).  Raises as :func:`piece_to_cubics`.
    """
    return _chains_segments([pieces], tol, max_depth)[0]


def _chains_segments(chains, tol, max_depth=16):
    """:func:`chain_segments` of several chains, searched in lockstep (:func:`_drive`)."""
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    chains = [_Chain(p) for p in chains]
    banks = {}                      # one stack per degree of all pieces, for the fitter
    for c in chains:
        c.banks, c.where = banks, []
        for p in c.pieces:
            banks.setdefault(len(p), []).append(p)
            c.where.append((len(p), len(banks[len(p)]) - 1))
    for n in banks:
        banks[n] = np.array(banks[n], float)
    return _drive([_search(c, tol, 2.0 ** -max_depth) for c in chains], tol)


def _search(chain, tol, min_width):
    """The segment search of one chain, a generator for :func:`_drive`: yields lists
    of fit requests ``(chain, t0, t1, (start, end))``, is sent their results, and
    returns the chain's list of CubicFit.

    Segments are found greedily from the start (:func:`_next_segment`); then one
    segment fewer is tried while the segments' bounds say it may fit
    (:func:`_balanced_cuts`), and after a short last segment one fewer of equal
    arc length."""
    out = []
    t0, start, width = 0.0, pc.start(chain.pieces[0]), min(float(chain.k), 2.0)
    while t0 < chain.k:
        t1, cubic, bound, reparam, end = yield from _next_segment(
            chain, t0, start, width, tol, min_width)
        out.append(CubicFit(t0, t1, cubic, bound, reparam))
        width = t1 - t0
        t0, start = t1, end
    # the greedy search stops each segment a little short of its longest reach: try
    # one segment fewer, cut where the greedy segments' bounds say it may fit
    while len(out) >= 2:
        cuts = _balanced_cuts(chain, out, tol)
        fewer = None if cuts is None else (yield from _split_at(chain, cuts, tol))
        if fewer is None:
            break
        out = fewer
    widths = [seg.t1 - seg.t0 for seg in out]
    if len(out) == 2 and widths[-1] < 0.5 * widths[0]:
        # a short last one is left: try one cubic for the whole chain (for more
        # segments, n - 1 of equal arc length where the model said no fitted 4 of
        # 92 times on the Relief strokes, all of them two into one, for 10 % of the
        # export's fits)
        t, cum = _arclength_table(chain)
        if cum[-1] > 0:
            fewer = yield from _split_at(
                chain, np.interp(np.linspace(0.0, cum[-1], len(out)), cum, t), tol)
            out = out if fewer is None else fewer
    return out


#: Error model of :func:`_balanced_cuts`: a cubic's bound grows like the P-th power
#: of the arc length it spans.
ERROR_POWER = 5.0
#: One segment fewer is tried when the greedy segments' shares add up to at most this
#: many segments fewer than there are (the greedy segments stop short of their reach).
FEWER_SLACK = 1.0


def _arclength_table(chain):
    """(T, cumulative arc length) at the knots of the chain's arc-length table."""
    tl, tr, sl, sr, _, _ = chain.arc_table()
    return np.append(tl, tr[-1]), np.append(sl, sr[-1])


def _balanced_cuts(chain, segs, tol):
    """Cuts of len(segs) - 1 segments, or None (not plausible).

    Segment i of ``segs`` (bound b_i over arc length L_i) counts as d_i = (b_i /
    tol)^(1/P) of a segment that just reaches tol (model bound ~ L^P, P =
    :data:`ERROR_POWER`), spread evenly over its arc length.  When the d_i add up to
    at most len(segs) - 1, the cuts are placed at equal shares of that sum (equal arc
    lengths where the curve is equally hard); the caller fits and certifies them
    (:func:`_split_at`) and keeps ``segs`` if any fails."""
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
    return np.interp(np.interp(np.linspace(0.0, hard[-1], n + 1), hard, edges), cum, t)


def _split_at(chain, cuts, tol):
    """Certified segments between the chain parameters ``cuts`` (all fitted in one
    request list), or None if one fails; a generator step of :func:`_search`."""
    cuts = np.array(cuts, float)
    cuts[0], cuts[-1] = 0.0, float(chain.k)
    if np.any(np.diff(cuts) <= 0):
        return None
    points = [pc.start(chain.pieces[0])] + [chain.point(float(t)) for t in cuts[1:]]
    fits = yield [(chain, float(t0), float(t1), (p0, p1))
                  for t0, t1, p0, p1 in zip(cuts[:-1], cuts[1:], points[:-1], points[1:])]
    if not all(bound <= tol for _, bound, _ in fits):
        return None
    return [CubicFit(float(t0), float(t1), cubic, bound, reparam)
            for t0, t1, (cubic, bound, reparam) in zip(cuts[:-1], cuts[1:], fits)]


#: The search stops at a certified segment whose bound is at least this share of tol
#: (higher: longer segments, more fits).  At PROVISIONAL, a try that is certified at
#: all ends the first pass (tries sampled below PROVISIONAL tol are not certified):
#: Relief strokes at tol 0.5 take 8 % fewer fits and 16 % fewer certificates than
#: at 0.8, for 0.3 % more points (brush 0.4 %, O ⊕ disk / ellipse the same;
#: bench/export_profile.py).
ACCEPT = 0.7


#: The search for a segment's end stops once the bracket (longest certified, shortest
#: failed end) is this narrow relative to the certified width.
BRACKET_REL = 0.02


def _next_try(t0, w, bound, last, good, bad, top, tol):
    """The next end to try after a fit of width w with ``bound`` (``last``: the
    previous (width, bound); ``good``: the longest certified fit; ``bad``: the
    shortest failed end), or None when the bracket is tight enough.  The model is
    bound ~ width^p with p from the last two fits (2 <= p <= 8, 5 without them),
    aimed at 0.9 tol, the step kept within 1/8 to 4 times the width and inside
    the bracket (bisecting it otherwise)."""
    p = 5.0
    if (last is not None and abs(last[0] - w) > 0.01 * w and last[1] > 0 and bound > 0
            and math.isfinite(bound) and math.isfinite(last[1])):
        p = min(8.0, max(2.0, math.log(bound / last[1]) / math.log(w / last[0])))
    if not math.isfinite(bound):
        ratio = 0.5
    else:
        ratio = (0.9 * tol / bound) ** (1.0 / p) if bound > 0 else 4.0
    target = min(top, t0 + w * min(4.0, max(0.125, ratio)))
    lo = good[0] if good is not None else t0
    hi = bad if bad is not None else top
    if bad is not None and not lo < target < hi:
        target = 0.5 * (lo + hi)
    if good is not None and (target <= lo or (bad is not None and hi - lo <= BRACKET_REL * (lo - t0))):
        return None
    return target


#: A try whose sampled distance is below this share of tol is not certified (the
#: search extends it anyway); the longest such try is certified once the search
#: would end on it.
PROVISIONAL = 0.7


def _next_segment(chain, t0, start, width, tol, min_width):
    """The longest certified segment from t0 found with a few fits: (t1, cubic, bound,
    reparam, end point); a generator step of :func:`_search`.  The first try spans
    ``width``; later ones follow the model bound ~ width^p, p from the last two fits
    (2 <= p <= 8, 5 at first), bracketed by the longest certified (or provisional:
    sampled below PROVISIONAL tol, certified only if the search ends on it) and the
    shortest failed interval."""
    top = float(chain.k)

    def attempt(t1, need):
        end = chain.point(t1)
        (cubic, bound, reparam), = yield [(chain, t0, t1, (start, end), need)]
        return (t1, cubic, bound, reparam, end)

    t1 = min(top, t0 + width)
    if top - t1 < 0.3 * (t1 - t0):
        t1 = top
    good, bad, last, fit = None, None, None, None
    for provisional in (PROVISIONAL, 0.0):
        for _ in range(8):
            fit = yield from attempt(t1, 0.0 if t1 == top else provisional)
            w, bound = t1 - t0, fit[2]
            if bound <= tol:
                good = fit if good is None or t1 > good[0] else good
                if fit[3] is not None and (t1 == top or bound >= ACCEPT * tol):
                    break
            else:
                bad = t1 if bad is None else min(bad, t1)
            target = _next_try(t0, w, bound, last, good, bad, top, tol)
            last = (w, bound)
            if target is None or target - t0 < min_width:
                break
            t1 = target
        if good is None or good[3] is not None:
            break
        # the search ends on a provisional try: certify it; where that fails (the
        # certificate is loose here), search again certifying every try
        fit = yield from attempt(good[0], 0.0)
        if fit[2] <= tol:
            return fit
        bad, last = good[0], (good[0] - t0, fit[2])
        t1 = _next_try(t0, good[0] - t0, fit[2], None, None, bad, top, tol) or 0.5 * (t0 + bad)
        good = None
    while good is None:
        # no certified fit yet: halve the shortest failed interval down to min_width
        t1 = t0 + 0.5 * (bad - t0)
        if t1 - t0 < min_width:
            raise ToleranceNotMetError(
                "cubic export did not reach tol %.3g on a parameter interval of width "
                "%.3g (bound %.3g)" % (tol, bad - t0, fit[2]),
                piece=chain.pieces[min(int(t0), chain.k - 1)], achieved=fit[2])
        fit = yield from attempt(t1, 0.0)
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


def _smooth_flags(pieces, angle):
    """Whether each join of consecutive pieces is smooth (see :func:`smooth_runs`):
    entry i for piece i to piece i + 1, the last for the closing join (last piece
    to first); all pieces' end tangents in one batch (a piece without a direction
    joins nothing smoothly)."""
    first, last = pc.end_tangents_many(pieces, strict=False)
    nxt = np.roll(np.arange(len(pieces)), -1)
    a, b = last, first[nxt]
    cart = [pc.cartesian(p) for p in pieces]
    start = np.array([c[0] for c in cart])
    end = np.array([c[-1] for c in cart])
    scale = np.array([np.abs(c).max() for c in cart])
    gap = np.hypot(*(end - start[nxt]).T)
    return (((a * b).sum(axis=1) > 0)
            & (np.abs(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0]) <= math.sin(angle))
            & (gap <= 1e-12 * (1.0 + np.maximum(scale, scale[nxt]))))


def _smooth_join(p, q, angle):
    return bool(_smooth_flags([np.asarray(p, float), np.asarray(q, float)], angle)[0])


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
    pieces = [np.asarray(p, float) for p in pieces]
    if not pieces:
        return []
    line = [len(p) == 2 and pc.is_polynomial(p) for p in pieces]
    smooth = (_smooth_flags(pieces, join_angle) if join_angle > 0
              else np.zeros(len(pieces), bool))
    runs = []
    for i, p in enumerate(pieces):
        if runs and not line[i] and not line[i - 1] and smooth[i - 1]:
            runs[-1].append(p)
        else:
            runs.append([p])
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
    far fewer cubics than the pieces one by one (:func:`piece_to_cubics`).  Writers
    of several loops call :func:`loops_to_beziers` (the same, all loops' runs
    fitted in one batch).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics.
    """
    return loops_to_beziers([loop], tol, max_depth, join_angle, wrap)[0]


def loops_to_beziers(loops, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """:func:`loop_to_beziers` of every loop of a region (a list per loop), with the
    segment searches of all their runs in lockstep: each round's fits of the whole
    region are fitted and certified in one batch (the numerical work is a few array
    calls per round, not per loop; callers batch the loops of many glyphs too).
    Every curve is certified within tol as loop by loop; the curves themselves may
    differ from loop-by-loop ones by rounding (batched array calls).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    plans = []
    for loop in loops:
        runs = smooth_runs(loop, join_angle)
        if wrap and join_angle > 0:
            runs = _wrap_runs(runs, join_angle)
        plans.append([(run, all(len(p) <= 4 and pc.is_polynomial(_check(p)) for p in run))
                      for run in runs])
    fitted = iter(_chains_segments([r for plan in plans for r, e in plan if not e],
                                   tol, max_depth))
    out = []
    for plan in plans:
        beziers = []
        for run, e in plan:
            if e:
                beziers.extend(pc.cartesian(p) for p in run)   # exact already: no fitting
            else:
                beziers.extend(seg.cubic for seg in next(fitted))
        out.append(beziers)
    return out


def loop_to_cubics(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Cubics within ``tol`` of a loop, in order: :func:`loop_to_beziers` with every
    line and quadratic degree-elevated (exactly)."""
    return [bz.to_degree(b, 3)
            for b in loop_to_beziers(loop, tol, max_depth, join_angle, wrap)]


def _cubics_to_quadratics(cubics, tol, splines=False):
    """cu2qu on each cubic within tol; (3, 2) quadratics with explicit on-curve points,
    or with ``splines`` one (n + 2, 2) TrueType spline per cubic: its end points and
    its n off-curve points, the on-curve points between them implied (midpoints)."""
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
        if splines:
            out.append(spline)
            continue
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
    the implied midpoints).  :func:`loops_to_quadratics` does several loops in one
    batch.

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_quadratics.
    """
    return loops_to_quadratics([loop], tol, max_depth, join_angle, wrap)[0]


def loops_to_quadratics(loops, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False,
                        splines=False):
    """:func:`loop_to_quadratics` of every loop (a list per loop), the cubic stage
    batched over all loops as in :func:`loops_to_beziers`; with ``splines`` each
    converted cubic is one TrueType spline (:func:`_cubics_to_quadratics`)."""
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    out = []
    for beziers in loops_to_beziers(loops, cubic_tol, max_depth, join_angle, wrap):
        quads = []
        for b in beziers:
            if len(b) <= 3:
                quads.append(b)
            else:
                quads.extend(_cubics_to_quadratics([b], tol - cubic_tol, splines))
        out.append(quads)
    return out

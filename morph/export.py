"""Export: rational pieces -> polynomial cubic / quadratic Béziers with a certified bound.

SVG path data and font outlines hold polynomial cubics (CFF, SVG) or quadratics
(TrueType); the pipeline's pieces are rational.  Each rational piece R = X / W is
replaced by cubics C fitted on the *same parameter* and the error

    |R(t) - C(t)| = |X(t) - W(t) C(t)| / W(t)

is bounded without sampling: E = X - W C is a Bernstein polynomial of degree n + 3,
and so are ``|E|^2 = E_x^2 + E_y^2`` and ``W^2`` (degree 2n + 6 after elevation,
coefficients e_k and v_k, v_k > 0 for positive weights).  If ``b^2 v_k - e_k >= 0``
for every k then ``b^2 W^2 - |E|^2 >= 0`` on [0, 1] (a non-negative combination of
the non-negative Bernstein basis), i.e.

    max_t |R(t) - C(t)| <= b = sqrt(max_k e_k / v_k)              (cubic_bound)

The coefficients are first subdivided (de Casteljau, 2^refine panels, default 8) and
the worst panel taken: the same certificate, tighter because Bernstein coefficients
converge to the polynomial under subdivision.  (It is never worse than
``sqrt(max_k e_k) / min_i w_i``.)

The parametric distance bounds the Hausdorff distance between the curves.  Pieces are
halved at t = 0.5 until the bound is <= tol.
"""

import numpy as np

from . import bernstein as bz
from . import piece as pc
from .errors import ToleranceNotMetError

__all__ = ["cubic_bound", "cubic_segments", "fit_cubic", "loop_to_cubics", "piece_to_cubics",
           "piece_to_quadratics"]


def _check(piece):
    piece = np.asarray(piece, float)
    if piece.ndim != 2 or piece.shape[1] != 3 or len(piece) < 2:
        raise ValueError("a piece is an (n+1, 3) array with n >= 1, got shape %r"
                         % (piece.shape,))
    if np.any(piece[:, 2] <= 0):
        raise ValueError("export needs positive weights, got %r" % (piece[:, 2],))
    return piece


def _error_poly(piece, cubic):
    """Bernstein coefficients of E = X - W C, shape (n + 4, 2)."""
    n = len(piece) - 1
    x = bz.elevate(piece[:, :2], 3)
    wc = bz.multiply(piece[:, 2:3], np.asarray(cubic, float))
    return x - wc, n


def _bound_from_error(e, w, refine=3):
    """sqrt of the smallest b2 with b2 W^2 - |E|^2 >= 0 coefficient-wise on 2^refine panels."""
    e2 = bz.multiply(e[:, :1], e[:, :1])[:, 0] + bz.multiply(e[:, 1:2], e[:, 1:2])[:, 0]
    w2 = bz.to_degree(bz.multiply(w, w), len(e2) - 1)
    both = np.column_stack([e2, w2])
    panels = [both]
    for _ in range(refine):
        panels = [half for p in panels for half in bz.split(p, 0.5)]
    worst = max(float(np.max(p[:, 0] / p[:, 1])) for p in panels)
    return float(np.sqrt(max(worst, 0.0)))


def cubic_bound(piece, cubic, refine=3):
    """Certified bound on max_{t in [0,1]} |R(t) - C(t)| for a piece R and cubic C.

    ``cubic`` is a (4, 2) array of Cartesian control points compared on the same
    parameter t.  Returns ``sqrt(max coefficient of |X - W C|^2) / min weight``,
    which is >= the true maximum (convex hull property of Bernstein polynomials).
    Exact arithmetic aside, the only error is floating-point rounding in the
    coefficient products (relative ~1e-15 of the coordinates).
    """
    piece = _check(piece)
    e, _ = _error_poly(piece, cubic)
    return _bound_from_error(e, piece[:, 2:3], refine)


def fit_cubic(piece):
    """Cubic with the piece's end points and end tangent directions; (cubic, bound).

    Two candidates are built and the one with the smaller :func:`cubic_bound` is
    returned: the Hermite cubic (end derivatives matched: P1 = P0 + R'(0)/3,
    P2 = P3 - R'(1)/3, error O(h^4) under subdivision) and the cubic whose two handle
    lengths minimise the sum of squared Bernstein coefficients of E = X - W C (a 2x2
    least-squares problem, kept only if both lengths are positive so the tangent
    directions are preserved).
    """
    piece = _check(piece)
    p = pc.cartesian(piece)
    p0, p3 = p[0], p[-1]
    d = pc.derivative(piece, np.array([0.0, 1.0]))
    hermite = np.array([p0, p0 + d[0] / 3.0, p3 - d[1] / 3.0, p3])
    e_h, _ = _error_poly(piece, hermite)
    best = (hermite, _bound_from_error(e_h, piece[:, 2:3]))

    n0, n1 = np.hypot(*d[0]), np.hypot(*d[1])
    if n0 > 0 and n1 > 0:
        t0, t1 = d[0] / n0, d[1] / n1
        base = np.array([p0, p0, p3, p3])
        e0, _ = _error_poly(piece, base)
        # E(alpha, beta) = e0 - alpha W B1 t0 + beta W B2 t1 (B_i cubic Bernstein basis)
        wb1 = bz.multiply(piece[:, 2:3], np.array([[0.0], [1.0], [0.0], [0.0]]))
        wb2 = bz.multiply(piece[:, 2:3], np.array([[0.0], [0.0], [1.0], [0.0]]))
        a_col = (-wb1 * t0).ravel()
        b_col = (wb2 * t1).ravel()
        mat = np.column_stack([a_col, b_col])
        sol, *_ = np.linalg.lstsq(mat, -e0.ravel(), rcond=None)
        alpha, beta = sol
        if alpha > 0 and beta > 0 and np.all(np.isfinite(sol)):
            cand = np.array([p0, p0 + alpha * t0, p3 - beta * t1, p3])
            e_c, _ = _error_poly(piece, cand)
            bound = _bound_from_error(e_c, piece[:, 2:3])
            if bound < best[1]:
                best = (cand, bound)
    return best


def _exact_cubic(piece):
    """(4, 2) control points of a polynomial piece of degree <= 3, else None."""
    if len(piece) > 4 or not pc.is_polynomial(piece):
        return None
    return bz.to_degree(pc.cartesian(piece), 3)


def cubic_segments(piece, tol, max_depth=16):
    """Cubics within ``tol`` of a piece with their parameter intervals and bounds.

    Returns a list of ``(t0, t1, cubic, bound)``: the (4, 2) cubic C approximates the
    piece on [t0, t1] with ``max_{u in [0,1]} |R(t0 + u (t1 - t0)) - C(u)| <= bound
    <= tol`` (certified, :func:`cubic_bound`).  Exact pieces (polynomial, degree <= 3)
    give one segment with bound 0.  Raises as :func:`piece_to_cubics`.
    """
    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    piece = _check(piece)
    exact = _exact_cubic(piece)
    if exact is not None:
        return [(0.0, 1.0, exact, 0.0)]
    out = []
    stack = [(piece, 0.0, 1.0, 0)]
    while stack:
        sub, t0, t1, depth = stack.pop()
        cubic, bound = fit_cubic(sub)
        if bound <= tol:
            out.append((t0, t1, cubic, bound))
            continue
        if depth >= max_depth:
            raise ToleranceNotMetError(
                "cubic export did not reach tol %.3g after %d halvings (bound %.3g)"
                % (tol, max_depth, bound), piece=piece, achieved=bound)
        left, right = pc.split(sub, 0.5)
        tm = 0.5 * (t0 + t1)
        stack.append((right, tm, t1, depth + 1))
        stack.append((left, t0, tm, depth + 1))
    return out


def piece_to_cubics(piece, tol, max_depth=16):
    """Polynomial cubics within ``tol`` of a (rational) piece, list of (4, 2) arrays.

    Each returned cubic C_k approximates the piece restricted to its parameter
    interval I_k with max_{t in I_k} |R(t) - C_k(t)| <= tol (a-priori bound of
    :func:`cubic_bound`, not sampled).  The cubics keep the piece's end points
    exactly and their joins are exact (G1 where the piece is regular: end tangent
    directions are matched).  Polynomial pieces of degree <= 3 are returned exactly
    (degree-elevated).  tol is absolute, in the piece's units.

    Raises:
        ValueError: tol <= 0 or weights not positive.
        ToleranceNotMetError: a sub-piece still exceeds tol after ``max_depth``
            halvings (e.g. tol below floating-point resolution of the coordinates);
            ``.achieved`` holds its bound.
    """
    return [seg[2] for seg in cubic_segments(piece, tol, max_depth)]


def loop_to_cubics(loop, tol, max_depth=16):
    """All cubics of a loop, in order (each piece within tol, see piece_to_cubics)."""
    return [c for p in loop for c in piece_to_cubics(p, tol, max_depth)]


def piece_to_quadratics(piece, tol, max_depth=16):
    """Polynomial quadratics within ``tol`` of a piece, list of (3, 2) arrays.

    The budget is split in halves: cubics within tol/2 (:func:`piece_to_cubics`,
    certified bound), then each cubic to a quadratic spline within tol/2 with
    ``fontTools.cu2qu.curve_to_quadratic``.  cu2qu's check is also on a common
    parameter and certified up to rounding: it tests the difference curve's control
    points against the tolerance disk (convex hull) and subdivides.  By the triangle
    inequality every quadratic is within tol of the piece on the corresponding
    parameter interval.  Polynomial pieces of degree <= 2 are returned exactly.

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics; also when cu2qu finds
            no spline within its limit of segments.
    """
    from fontTools.cu2qu import curve_to_quadratic
    from fontTools.cu2qu.errors import Error as Cu2QuError

    if not tol > 0:
        raise ValueError("tol must be positive, got %r" % (tol,))
    piece = _check(piece)
    if len(piece) <= 3 and pc.is_polynomial(piece):
        return [bz.to_degree(pc.cartesian(piece), 2)]
    out = []
    for cubic in piece_to_cubics(piece, tol / 2.0, max_depth):
        try:
            spline = curve_to_quadratic([tuple(p) for p in cubic], tol / 2.0,
                                        all_quadratic=True)
        except Cu2QuError as exc:
            raise ToleranceNotMetError("cu2qu found no quadratic spline within %.3g"
                                       % (tol / 2.0), piece=cubic) from exc
        spline = np.asarray(spline, float)
        offs = spline[1:-1]
        ons = [spline[0]] + [0.5 * (offs[i] + offs[i + 1]) for i in range(len(offs) - 1)] \
            + [spline[-1]]
        for i, off in enumerate(offs):
            out.append(np.array([ons[i], off, ons[i + 1]]))
    return out

"""TrueType quadratic splines of a whole batch of cubics with a few array calls:
fontTools' cu2qu algorithm (``fontTools.cu2qu.cu2qu.curve_to_quadratic`` with
``all_quadratic=True``) on arrays.

For n = 1, 2, ... :data:`MAX_N` every cubic not yet converted is split into n equal
parameter parts; each part's quadratic control point is the intersection of its
end tangents (n = 1, ``cubic_approx_quadratic``) or a point on the line through its
tangent handles, the on-curve points between parts implied at the midpoints
(``cubic_approx_spline``).  The spline is accepted when every part's difference
with its quadratic (raised to a cubic, a same-parameter difference) lies within
``tol`` of the origin (``cubic_farthest_fit_inside``: the control points of the
difference inside the tolerance disk, else split in two, as a worklist of arrays
here), so the accepted spline is within ``tol`` of the cubic at the same
parameter, hence in Fréchet and Hausdorff distance.  One round per n over the
cubics not yet accepted.  The arithmetic is cu2qu's, operation for operation, on
complex arrays multiplied by real numbers only (as exact as cu2qu's complex times
real), divided by 3 part by part and measured with C's hypot, so the splines are
cu2qu's: the same n and the same points for finite input.  A non-finite cubic
gets no spline (cu2qu's recursion would not end on it).
"""

import numpy as np

from ..errors import ToleranceNotMetError

#: cu2qu's limit of quadratic segments per cubic (fontTools.cu2qu.cu2qu.MAX_N).
MAX_N = 100
#: cu2qu's dot product below this absolute value counts as 0 (its ``dot``): lines
#: that near parallel have no intersection.
DOT_ZERO = 1e-15
#: Levels of the fit-inside worklist before an undecided difference counts as
#: outside: finite input is decided once the halves shrink to single floats
#: (at most ~1100 halvings from the largest to the smallest double).
MAX_SPLITS = 1200


def _stacked(*parts):
    """(4, len(parts), ...) complex array of parts of four (...) control points each
    (one allocation; the control point axis first, each point's array contiguous:
    numpy's complex loops are several times slower on strided arrays)."""
    out = np.empty((4, len(parts)) + np.shape(parts[0][0]), complex)
    for r, part in enumerate(parts):
        for k, v in enumerate(part):
            out[k, r] = v
    return out


def _third(z):
    """z / 3 part by part, as cu2qu's ``_complex_div_by_real`` (numpy's complex
    division rounds differently)."""
    out = np.empty(np.shape(z), complex)
    out.real, out.imag = z.real / 3.0, z.imag / 3.0
    return out


def _split_two(p):
    """cu2qu's ``split_cubic_into_two``: (4, ...) cubics as (4, 2, ...) halves."""
    p0, p1, p2, p3 = p
    mid = (p0 + 3 * (p1 + p2) + p3) * 0.125
    deriv3 = (p3 + p2 - p1 - p0) * 0.125
    return _stacked((p0, (p0 + p1) * 0.5, mid - deriv3, mid),
                    (mid, mid + deriv3, (p2 + p3) * 0.5, p3))


def _split_three(p):
    """cu2qu's ``split_cubic_into_three``: (4, ...) cubics as (4, 3, ...) thirds."""
    p0, p1, p2, p3 = p
    mid1 = (8 * p0 + 12 * p1 + 6 * p2 + p3) * (1 / 27)
    deriv1 = (p3 + 3 * p2 - 4 * p0) * (1 / 27)
    mid2 = (p0 + 6 * p1 + 12 * p2 + 8 * p3) * (1 / 27)
    deriv2 = (4 * p3 - 3 * p1 - p0) * (1 / 27)
    return _stacked((p0, _third(2 * p0 + p1), mid1 - deriv1, mid1),
                    (mid1, mid1 + deriv1, mid2 - deriv2, mid2),
                    (mid2, mid2 + deriv2, _third(p2 + 2 * p3), p3))


def _split_n(p, n):
    """cu2qu's ``_split_cubic_into_n_gen``: (4, m) cubics as (4, n, m) parts from
    the power basis (a t^3 + b t^2 + c t + d) shifted and scaled per part."""
    p0, p1, p2, p3 = p
    c = (p1 - p0) * 3.0
    b = (p2 - p1) * 3.0 - c
    d = p0
    a = p3 - d - c - b
    dt = 1 / n
    delta_2 = dt * dt
    delta_3 = dt * delta_2
    t1 = (np.arange(n) * dt)[:, None]
    t1_2 = t1 * t1
    b1 = (3 * a * t1 + b) * delta_2
    c1 = (2 * b * t1 + c + 3 * a * t1_2) * dt
    d1 = a * t1 * t1_2 + b * t1_2 + c * t1 + d
    _2 = _third(c1) + d1                          # cu2qu's calc_cubic_points
    return np.stack([d1, _2, _third(b1 + c1) + _2, a * delta_3 + d1 + c1 + b1])


def split_cubics(p, n):
    """(4, m) complex cubics split into n equal parameter parts, (4, n, m), by cu2qu's
    ``split_cubic_into_n_iter`` (its formulas for n = 2, 3, 4, 6, else the power
    basis)."""
    if n == 1:
        return p[:, None]
    if n in (2, 4):
        halves = _split_two(p)
        # the halves of the first half, then of the second
        return halves if n == 2 else _split_two(halves).swapaxes(1, 2).reshape(4, 4, -1)
    if n in (3, 6):
        return _split_three(p) if n == 3 else \
            _split_three(_split_two(p)).swapaxes(1, 2).reshape(4, 6, -1)
    return _split_n(p, n)


def _norm(z):
    """|z| of complex arrays as cu2qu's ``abs`` (C hypot; numpy's complex abs may
    round differently)."""
    return np.hypot(z.real, z.imag)


def fit_inside(owner, diff, tol, m):
    """cu2qu's ``cubic_farthest_fit_inside`` of every (4, k) complex difference cubic
    ``diff`` (its end points already checked), as one worklist of arrays: a
    difference whose inner control points are within tol of the origin is inside
    (convex hull), one whose midpoint is not is outside, the others are split in
    two.  Returns (m,) booleans: every difference of ``owner`` (k,) indices in
    range(m) inside.  A non-finite difference counts as outside."""
    bad = np.zeros(m, bool)
    for _ in range(MAX_SPLITS):
        if not len(owner):
            return ~bad
        split = ~((_norm(diff[2]) <= tol) & (_norm(diff[1]) <= tol))
        halves = _split_two(diff[:, split])
        owner = owner[split]
        outside = ~(_norm(halves[3, 0]) <= tol)       # the midpoint; NaN: outside
        bad[owner[outside]] = True
        go = ~bad[owner]
        owner = np.concatenate((owner[go], owner[go]))
        diff = halves[:, :, go].reshape(4, -1)        # first halves, then second
    bad[owner] = True
    return ~bad


def _intersections(c):
    """cu2qu's ``calc_intersect`` of each (4, m) cubic's end tangents: (m,) points,
    NaN where the tangents are parallel (unless 3 or 4 points coincide)."""
    a, b, cc, d = c
    ab, cd, ac = b - a, d - cc, a - cc
    pr, pi = -ab.imag, ab.real                    # ab * 1j
    num = pr * ac.real + pi * ac.imag             # cu2qu's dot
    den = pr * cd.real + pi * cd.imag
    num[np.abs(num) < DOT_ZERO] = 0.0
    den[np.abs(den) < DOT_ZERO] = 0.0
    zero = den == 0.0
    q1 = cc + cd * (num / np.where(zero, 1.0, den))
    coincide = (b == cc) & ((a == b) | (cc == d))
    return np.where(zero, np.where(coincide, b, complex(np.nan, np.nan)), q1)


def _try_one(c, tol):
    """cu2qu's ``cubic_approx_quadratic`` of (4, m) cubics: (accepted (m,),
    splines (3, m))."""
    q1 = _intersections(c)
    found = ~np.isnan(q1.imag)
    c0, c3 = c[0], c[3]
    diff = np.zeros(c.shape, complex)
    diff[1] = c0 + (q1 - c0) * (2 / 3) - c[1]
    diff[2] = c3 + (q1 - c3) * (2 / 3) - c[2]
    idx = found.nonzero()[0]
    found[idx] = fit_inside(idx, diff[:, idx], tol, c.shape[1])[idx]
    return found, np.stack([c0, q1, c3])


def _try_n(c, n, tol):
    """cu2qu's ``cubic_approx_spline`` of (4, m) cubics with n >= 2 quadratics:
    (accepted (m,), splines (n + 2, m): end points and n off-curve points)."""
    m = c.shape[1]
    p0, p1, p2, p3 = split_cubics(c, n)           # each (n, m)
    t = (np.arange(n) / (n - 1))[:, None]
    h1 = p0 + (p1 - p0) * 1.5                     # cubic_approx_control
    h2 = p3 + (p2 - p3) * 1.5
    q1 = h1 + (h2 - h1) * t
    q2 = np.empty((n, m), complex)                # the implied on-curve points
    q2[:-1] = (q1[:-1] + q1[1:]) * 0.5
    q2[-1] = p3[-1]
    diff = np.empty((4, n, m), complex)
    diff[3] = d1 = q2 - p3                        # their error
    diff[0, 0] = 0.0
    diff[0, 1:] = d1[:-1]
    diff[1, 0] = c[0] + (q1[0] - c[0]) * (2 / 3) - p1[0]
    diff[1, 1:] = q2[:-1] + (q1[1:] - q2[:-1]) * (2 / 3) - p1[1:]
    diff[2] = q2 + (q1 - q2) * (2 / 3) - p2
    ends = (_norm(d1) <= tol).all(0)              # NaN: not within
    idx = ends.nonzero()[0]
    ends[idx] = fit_inside(np.tile(idx, n), diff[:, :, idx].reshape(4, -1), tol, m)[idx]
    return ends, np.concatenate([c[:1], q1, c[3:]])


def find_splines(cubics, tol):
    """cu2qu's quadratic spline of every cubic within ``tol``
    (``curve_to_quadratic(cubic, tol, all_quadratic=True)``), one round of array
    calls per number of segments n over the cubics not yet converted.

    Returns ``(counts, blocks)``: counts (m,) each cubic's n, 0 where no spline of
    at most :data:`MAX_N` quadratics is within tol; blocks one ``(index, splines)``
    pair per round that converted some: the cubics' indices (k,) and their splines
    (k, n + 2, 2), each its end points and its n off-curve points (TrueType: the
    on-curve points between them implied, midpoints).
    """
    points = np.asarray(cubics, float).reshape(-1, 4, 2)
    cubics = np.empty((4, len(points)), complex)
    cubics.real, cubics.imag = points.T
    counts = np.zeros(len(points), np.int64)
    blocks, todo = [], np.arange(len(points))
    with np.errstate(invalid="ignore", over="ignore"):      # non-finite: no spline
        for n in range(1, MAX_N + 1):
            if not len(todo):
                break
            c = cubics[:, todo]
            ok, splines = _try_one(c, tol) if n == 1 else _try_n(c, n, tol)
            if ok.any():
                counts[todo[ok]] = n
                splines = splines[:, ok].T
                blocks.append((todo[ok], np.stack([splines.real, splines.imag], -1)))
            todo = todo[~ok]
    return counts, blocks


def cubic_splines(cubics, tol):
    """:func:`find_splines` of every cubic, which must all convert.

    Raises:
        ToleranceNotMetError: no spline of at most :data:`MAX_N` quadratics within
            tol for some cubic (``piece``: the first such, (4, 2)).
    """
    counts, blocks = find_splines(cubics, tol)
    missing = (counts == 0).nonzero()[0]
    if len(missing):
        raise ToleranceNotMetError("cu2qu found no quadratic spline within %.3g" % tol,
                                   piece=np.asarray(cubics, float).reshape(-1, 4, 2)[missing[0]])
    return counts, blocks


def spline_quadratics(splines):
    """(k, n + 2, 2) TrueType splines as (k, n, 3, 2) quadratics with explicit
    on-curve points (the implied ones: midpoints of consecutive off-curve points)."""
    offs = splines[:, 1:-1]
    ons = np.concatenate([splines[:, :1], 0.5 * (offs[:, :-1] + offs[:, 1:]),
                          splines[:, -1:]], 1)
    return np.stack([ons[:, :-1], offs, ons[:, 1:]], 2)

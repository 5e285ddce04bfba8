"""Independent reference computations that the project's tests compare against.

Nothing here calls the project's geometric algorithms.  The only project code used is
``morph.polyline.flatten`` (to turn input curves into polylines for the polygon
references), which is tested on its own; curve points and derivatives are computed here
from the Bernstein basis directly (``bezier_eval``), so a bug in ``morph.bernstein`` or
``morph.piece`` cannot cancel out.

Contents
--------
Curves
    bezier_eval(piece, t, nder=0)              points (and derivatives), own implementation
    exact_convolution_points(c1, c2, ts)       -> (points, s): C1(t) + C2(s), C2'(s) || C1'(t), same way
    distance_to_convolution(points, ts, c1, c2) -> distance from p(t) - C1(t) to the curve C2
    approx_convolution_error(approx, c1, c2)   max of the above on samples of a piece (Sec. 5.2)
    random_compatible_pair(rng, kind)          random convex pieces with equal tangent ranges
Polygons (pyclipper / shapely)
    region_polylines(region, tol)              flattened closed polylines of a region's loops
    region_to_shapely(region, tol)             nonzero-fill polygon of a region
    polygon_minkowski_sum(region_a, region_b, tol)
    polyline_minkowski_sum(loops_a, loops_b, scale)   same on polylines / shapely polygons
    brute_force_minkowski_sum(poly_a, poly_b)  shapely only: union of hulls of triangle pairs
Measures
    hausdorff(a, b, spacing)                   two-sided boundary Hausdorff distance
    max_boundary_distance(points, geom)        max distance of points to geom.boundary
    winding_number(points, loops)              vectorised crossing count
    count_outer_and_holes(geom)                (number of polygons, number of holes)

About pyclipper.MinkowskiSum (Clipper 6.4.2)
--------------------------------------------
``MinkowskiSum(pattern, path, True)`` builds, for every edge of ``pattern`` (always taken
as closed) and every edge of ``path`` (closed when the flag is True), the parallelogram
edge ⊕ edge, and returns their nonzero union.  That is the sum of the two *boundaries*
∂P ⊕ ∂Q, not of the two regions: a big square ⊕ a small square comes back as a square
frame with a hole (the interior of the big square is never covered).  The full sum of
two polygonal regions A, B (with holes and several components) is

    A ⊕ B = (∂A ⊕ ∂B)  ∪  ⋃_{loops L of B} (A + b_L)  ∪  ⋃_{loops K of A} (a_K + B)

with b_L a point of loop L and a_K a point of loop K.  Proof sketch: for x in A ⊕ B not in
∂A ⊕ ∂B, the set A ∩ (x - B) is non-empty while ∂A and ∂(x - B) are disjoint.  If some
loop K of ∂A meets x - B it lies inside it entirely (K is connected and does not cross
∂(x - B)), so x - a_K ∈ B.  Otherwise a component of x - B meets A but not ∂A, so it lies
in A, and so does its outer loop L: x - b_L ∈ A.  One point per *loop* is needed: a single
point a0 of A is not enough when A has several components or when only a hole loop of A
lies inside x - B (disk ⊕ ring: x = centre).
"""

import numpy as np
import pyclipper

from tests.oracles import need

shapely = need("shapely", "polygon references and the membership predicate")
need("scipy", "exact convolution points and binomial coefficients")
from scipy.optimize import brentq, minimize_scalar  # noqa: E402 - after the checks above
from scipy.special import comb  # noqa: E402
from shapely.geometry import MultiPolygon, Polygon  # noqa: E402

from morph import polyline as pl  # noqa: E402


# =========================================================================== curves

def bezier_eval(piece, t, nder=0):
    """Points of a rational Bézier piece and up to two derivatives (own implementation).

    ``piece`` is ``(n+1, 3)`` homogeneous ``(w x, w y, w)``.  Returns a list
    ``[C(t), C'(t), C''(t)][:nder+1]`` of ``(m, 2)`` arrays, from explicit Bernstein
    sums and the quotient rule (independent of ``morph.bernstein``).
    """
    piece = np.asarray(piece, float)
    t = np.atleast_1d(np.asarray(t, float))
    n = len(piece) - 1

    def bsum(ctrl):
        k = len(ctrl) - 1
        if k < 0:
            return np.zeros((len(t), 3))
        i = np.arange(k + 1)
        basis = comb(k, i) * t[:, None] ** i * (1 - t[:, None]) ** (k - i)
        return basis @ ctrl

    h = [bsum(piece)]
    d = piece
    for r in range(1, nder + 1):
        d = np.diff(d, axis=0) * (n - r + 1)
        h.append(bsum(d) if len(d) else np.zeros((len(t), 3)))
    w = h[0][:, 2:3]
    p = h[0][:, :2] / w
    out = [p]
    if nder >= 1:
        w1 = h[1][:, 2:3]
        p1 = (h[1][:, :2] - p * w1) / w
        out.append(p1)
    if nder >= 2:
        w2 = h[2][:, 2:3]
        out.append((h[2][:, :2] - 2 * p1 * w1 - p * w2) / w)
    return out


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _tangent_dirs(piece, t):
    """Tangent directions at t; where C'(t) vanishes, the limit direction (chord)."""
    _, d = bezier_eval(piece, t, 1)
    t = np.atleast_1d(t)
    bad = np.hypot(d[:, 0], d[:, 1]) <= 1e-300
    if np.any(bad):
        h = 1e-7
        tb = t[bad]
        lo = np.clip(tb - h, 0, 1)
        hi = np.clip(tb + h, 0, 1)
        d[bad] = bezier_eval(piece, hi)[0] - bezier_eval(piece, lo)[0]
    return d


def solve_parallel(c2, direction, samples=2049, angle_tol=1e-9, _table=None):
    """Parameters s in [0, 1] of C2 whose tangent is parallel to ``direction`` and points
    the same way (cross = 0, dot > 0).  Returns a sorted list (usually one element).

    Dense sampling of the signed angle between ``direction`` and C2'(s) brackets every
    crossing of zero; brentq refines each on the cross product.  Parameters where the
    angle is within ``angle_tol`` of zero at an end of [0, 1] (equal end tangents of a
    compatible pair) are accepted as roots at that end.
    """
    u = np.asarray(direction, float)
    u = u / np.hypot(*u)
    if _table is None:
        _table = _tangent_table(c2, samples)
    ss, d2 = _table
    ang = np.arctan2(_cross(u, d2), d2 @ u)

    def f(s):
        d = _tangent_dirs(c2, [s])[0]
        return _cross(u, d) / np.hypot(*d)

    a0, a1 = ang[:-1], ang[1:]
    near = (np.abs(a0) <= np.pi / 2) & (np.abs(a1) <= np.pi / 2)  # not the antiparallel jump
    roots = [float(ss[k]) for k in np.nonzero(near & (a0 == 0.0))[0]]
    for k in np.nonzero(near & (a0 * a1 < 0))[0]:
        roots.append(brentq(f, ss[k], ss[k + 1], xtol=1e-16, rtol=1e-15, maxiter=200))
    if ang[-1] == 0.0:
        roots.append(1.0)
    # end tolerance: a root just outside [0, 1] by rounding
    if not roots or roots[0] > ss[1]:
        if abs(ang[0]) <= angle_tol:
            roots.insert(0, 0.0)
    if not roots or roots[-1] < ss[-2]:
        if abs(ang[-1]) <= angle_tol:
            roots.append(1.0)
    out = []
    for r in sorted(roots):
        if not out or r - out[-1] > 1e-12:
            out.append(float(r))
    return out


def _tangent_table(c2, samples):
    ss = np.linspace(0.0, 1.0, samples)
    return ss, _tangent_dirs(c2, ss)


def exact_convolution_points(c1, c2, ts, samples=2049, angle_tol=1e-9):
    """Exact convolution points of a compatible pair (Eqs. 2-4, 27), solved numerically.

    For each t in ts, find s in [0, 1] with C2'(s) parallel to C1'(t) and pointing the
    same way; returns ``(points (m, 2), s (m,))`` with ``points = C1(t) + C2(s)``.  Where
    no such s exists, the row is NaN.  If several exist (C2 not convex), the first.
    """
    ts = np.atleast_1d(np.asarray(ts, float))
    u = _tangent_dirs(c1, ts)
    s = np.full(len(ts), np.nan)
    table = _tangent_table(c2, samples)
    for k in range(len(ts)):
        roots = solve_parallel(c2, u[k], samples, angle_tol, table)
        if roots:
            s[k] = roots[0]
    pts = np.full((len(ts), 2), np.nan)
    ok = ~np.isnan(s)
    if np.any(ok):
        pts[ok] = bezier_eval(c1, ts[ok])[0] + bezier_eval(c2, s[ok])[0]
    return pts, s


def point_curve_distance(q, curve, samples=1025):
    """Distances of points q (m, 2) to the rational curve (min over s in [0, 1]).

    Dense sampling locates the nearest sample, bounded Brent minimisation refines it on
    the neighbouring interval, then Newton steps on (C(s) - q)·C'(s) polish s (kept only
    when they decrease the distance).  Returns (distances (m,), s (m,)).
    """
    q = np.atleast_2d(np.asarray(q, float))
    ss = np.linspace(0.0, 1.0, samples)
    cs = bezier_eval(curve, ss)[0]
    dist = np.empty(len(q))
    sbest = np.empty(len(q))
    for k, p in enumerate(q):
        d2 = np.sum((cs - p) ** 2, axis=1)
        i = int(np.argmin(d2))
        lo, hi = ss[max(i - 1, 0)], ss[min(i + 1, samples - 1)]

        def g(s):
            c = bezier_eval(curve, [s])[0][0]
            return float(np.sum((c - p) ** 2))

        res = minimize_scalar(g, bounds=(lo, hi), method="bounded",
                              options={"xatol": 1e-14, "maxiter": 500})
        s, best = float(res.x), float(res.fun)
        if d2[i] < best:
            s, best = float(ss[i]), float(d2[i])
        for _ in range(6):
            c, c1, c2_ = (v[0] for v in bezier_eval(curve, [s], 2))
            r = c - p
            gp = r @ c1
            gpp = c1 @ c1 + r @ c2_
            if gpp <= 0:
                break
            s_new = min(max(s - gp / gpp, 0.0), 1.0)
            val = g(s_new)
            if val <= best:
                s, best = s_new, val
            else:
                break
        dist[k] = np.sqrt(best)
        sbest[k] = s
    return dist, sbest


def distance_to_convolution(points, ts, c1, c2, samples=1025):
    """The paper's distance measure (Sec. 5.2, Eqs. 49-53) for approximate points.

    ``points[k]`` approximates the convolution point at parameter ``ts[k]`` of C1; the
    translated point q = p - C1(t) should lie on C2.  Returns the distance from each q
    to the curve C2 (array (m,)); the error of the approximation is its maximum.
    """
    ts = np.atleast_1d(np.asarray(ts, float))
    q = np.atleast_2d(np.asarray(points, float)) - bezier_eval(c1, ts)[0]
    return point_curve_distance(q, c2, samples)[0]


def approx_convolution_error(approx, c1, c2, n=200):
    """Max distance measure of an approximating piece whose parameter is C1's t."""
    ts = np.linspace(0.0, 1.0, n)
    return float(np.max(distance_to_convolution(bezier_eval(approx, ts)[0], ts, c1, c2)))


# ------------------------------------------------------------- random compatible pairs

PAIR_KINDS = ("cubic-cubic", "quad-quad", "cubic-quad", "conic-quad", "conic-cubic")


def _unit(a):
    return np.array([np.cos(a), np.sin(a)])


def _random_convex_piece(rng, kind, a0, a1, origin, size):
    """A convex piece with tangent angle running monotonically from a0 to a1."""
    u0, u1 = _unit(a0), _unit(a1)
    p0 = np.asarray(origin, float)
    if kind == "quad":
        l0, l1 = size * rng.uniform(0.3, 1.0, 2)
        pts = [p0, p0 + l0 * u0, p0 + l0 * u0 + l1 * u1]
        return np.column_stack([pts, np.ones(3)])
    if kind == "conic":
        if rng.uniform() < 0.5:        # exact circular arc
            l0 = l1 = size * rng.uniform(0.3, 1.0)
            w = np.cos(abs(a1 - a0) / 2)
        else:                          # general conic (ellipse / hyperbola arc)
            l0, l1 = size * rng.uniform(0.3, 1.0, 2)
            w = rng.uniform(0.3, 2.5)
        pts = np.array([p0, p0 + l0 * u0, p0 + l0 * u0 + l1 * u1])
        wts = np.array([1.0, w, 1.0])
        return np.column_stack([pts * wts[:, None], wts])
    if kind == "cubic":
        # hodograph control vectors a*u0, c*um, b*u1 with um strictly between u0, u1:
        # all cross products of consecutive ones share a sign -> no inflection.
        f = rng.uniform(0.15, 0.85)
        um = _unit(a0 + f * (a1 - a0))
        a, c, b = size * rng.uniform(0.2, 1.0, 3)
        pts = [p0, p0 + a * u0, p0 + a * u0 + c * um, p0 + a * u0 + c * um + b * u1]
        return np.column_stack([pts, np.ones(4)])
    raise ValueError(kind)


def random_compatible_pair(rng, kind, min_sweep=np.radians(10), max_sweep=np.radians(85)):
    """Random compatible pair (c1, c2) for QAC tests; ``kind`` is 'c1type-c2type'.

    Both pieces are convex (no inflection, constant curvature sign), their tangent angle
    runs monotonically over the same range [a0, a0 + sweep] with |sweep| in
    [min_sweep, max_sweep] (< 90 degrees) and random sign (counter-clockwise or clockwise
    turning).  'conic' is a rational quadratic (half the time an exact circular arc).
    """
    if kind not in PAIR_KINDS:
        raise ValueError("kind must be one of %r" % (PAIR_KINDS,))
    k1, k2 = kind.split("-")
    a0 = rng.uniform(-np.pi, np.pi)
    sweep = rng.uniform(min_sweep, max_sweep) * rng.choice([-1.0, 1.0])
    a1 = a0 + sweep
    c2 = _random_convex_piece(rng, k2, a0, a1, rng.uniform(-2, 2, 2), rng.uniform(0.5, 2.0))
    c1 = _random_convex_piece(rng, k1, a0, a1, rng.uniform(-5, 5, 2), rng.uniform(0.5, 4.0))
    return c1, c2


def tangent_angle_profile(piece, n=501):
    """Unwrapped tangent angles at n uniform parameters (for property checks)."""
    d = _tangent_dirs(piece, np.linspace(0, 1, n))
    return np.unwrap(np.arctan2(d[:, 1], d[:, 0]))


def curvature_sign_values(piece, n=501):
    """x'y'' - x''y' at n uniform parameters."""
    _, d1, d2 = bezier_eval(piece, np.linspace(0, 1, n), 2)
    return _cross(d1, d2)


# ========================================================================= polygons

def region_polylines(region, tol):
    """Closed polylines (each (m, 2), first point not repeated) of a region's loops,
    each within tol of its curves (morph.polyline.flatten)."""
    out = []
    for loop in region:
        pts = [pl.flatten(np.asarray(p, float), tol)[0][:-1] for p in loop]
        pts = np.concatenate(pts) if pts else np.zeros((0, 2))
        if len(pts) >= 3:
            out.append(pts)
    return out


_HI_RANGE = 0x3FFFFFFFFFFFFFFF  # Clipper 6.4.2 hiRange


def _to_clipper(loops, scale):
    paths = []
    for loop in loops:
        loop = np.asarray(loop, float)
        if len(loop) > 1 and np.all(loop[0] == loop[-1]):
            loop = loop[:-1]
        ip = np.round(loop * scale)
        if np.any(np.abs(ip) > _HI_RANGE // 4):
            raise ValueError("coordinates too large for Clipper at scale %g" % scale)
        paths.append([(int(x), int(y)) for x, y in ip])
    return paths


def _loops_of(geom_or_loops):
    """List of closed (m, 2) loops: from shapely polygons (oriented CCW / holes CW)
    or a list of arrays (taken as they are)."""
    if isinstance(geom_or_loops, shapely.Geometry):
        loops = []
        for poly in _polygons(geom_or_loops):
            poly = shapely.geometry.polygon.orient(poly, 1.0)
            loops.append(np.asarray(poly.exterior.coords)[:-1])
            loops.extend(np.asarray(r.coords)[:-1] for r in poly.interiors)
        return loops
    return [np.asarray(l, float) for l in geom_or_loops]


def _polygons(geom):
    if geom.is_empty:
        return []
    if isinstance(geom, Polygon):
        return [geom]
    if hasattr(geom, "geoms"):
        return [p for g in geom.geoms for p in _polygons(g)]
    return []


def _clipper_union(paths, scale, sliver=4.0):
    """Nonzero union of integer paths -> shapely (Multi)Polygon in original units.

    Clipper rounds every intersection to the integer grid, so nearly coincident edges
    of the united parts leave slivers thinner than a grid unit: holes (and islands)
    narrower than ``sliver`` grid units (a disk of that diameter does not fit) are
    dropped as rounding artefacts.
    """
    pc = pyclipper.Pyclipper()
    pc.StrictlySimple = True
    paths = [p for p in paths if len(p) >= 3]
    if not paths:
        return MultiPolygon()
    pc.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    tree = pc.Execute2(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    polys = []

    def walk(node):
        for child in node.Childs:          # outer contours
            shell = np.asarray(child.Contour, float) / scale
            holes = [np.asarray(h.Contour, float) / scale for h in child.Childs]
            holes = [h for h in holes if len(h) >= 3 and not _thin(h, sliver / scale)]
            if len(shell) >= 3 and not _thin(shell, sliver / scale):
                polys.append(Polygon(shell, holes))
            for h in child.Childs:        # islands inside holes
                walk(h)

    walk(tree)
    geom = MultiPolygon(polys) if len(polys) != 1 else polys[0]
    if not geom.is_valid:
        geom = shapely.make_valid(geom)
    return geom


def _thin(ring, width):
    """True when no disk of diameter ``width`` fits in the polygon of the ring."""
    if width <= 0:
        return False
    poly = Polygon(ring)
    if not poly.is_valid:
        poly = shapely.make_valid(poly)
    if poly.area > 1e3 * width * width and poly.area > 2 * width * poly.length:
        return False
    return poly.buffer(-width / 2, quad_segs=2).is_empty


def _normalized_paths(loops, scale):
    """Integer paths of the nonzero-fill region of loops (outer +, holes -)."""
    pc = pyclipper.Pyclipper()
    paths = [p for p in _to_clipper(loops, scale) if len(p) >= 3]
    if not paths:
        return []
    pc.AddPaths(paths, pyclipper.PT_SUBJECT, True)
    return pc.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)


def default_scale(tol):
    """Clipper units per length unit: one unit is tol / 100."""
    return 100.0 / tol


def region_to_shapely(region, tol, scale=None):
    """Nonzero-fill polygon of a region of pieces (loops flattened within tol).

    Built by a Clipper union with the nonzero rule (so overlapping outer loops and the
    usual CCW outer / CW hole convention both come out right), one Clipper unit being
    tol/100 unless ``scale`` is given.
    """
    scale = default_scale(tol) if scale is None else scale
    return _clipper_union(_to_clipper(region_polylines(region, tol), scale), scale)


def polyline_minkowski_sum(a, b, scale):
    """Minkowski sum of two polygonal regions with pyclipper (nonzero fill).

    ``a`` and ``b`` are shapely (Multi)Polygons or lists of closed (m, 2) loops (outer
    counter-clockwise, holes clockwise).  Coordinates are rounded to 1/scale.  Computes
    (∂A ⊕ ∂B) ∪ ⋃_L (A + b_L) ∪ ⋃_K (a_K + B) (see the module docstring) and returns a
    shapely (Multi)Polygon.
    """
    pa = _normalized_paths(_loops_of(a), scale)
    pb = _normalized_paths(_loops_of(b), scale)
    if not pa or not pb:
        return MultiPolygon()
    pieces = []
    for k in pa:
        for l in pb:
            pieces.extend(pyclipper.MinkowskiSum(k, l, True))
    for l in pb:
        bx, by = l[0]
        pieces.extend([[(x + bx, y + by) for x, y in p] for p in pa])
    for k in pa:
        ax, ay = k[0]
        pieces.extend([[(x + ax, y + ay) for x, y in p] for p in pb])
    return _clipper_union(pieces, scale)


def polygon_minkowski_sum(region_a, region_b, tol, scale=None):
    """Polygon reference of the Minkowski sum of two regions of pieces.

    Each region's loops are flattened within tol/2 (so the sum of the two flattenings is
    within tol of the exact sum in Hausdorff distance, plus 2/scale of rounding), then
    summed exactly in Clipper's integer arithmetic by ``polyline_minkowski_sum``.
    One Clipper unit is tol/100 unless ``scale`` is given.
    """
    scale = default_scale(tol) if scale is None else scale
    la = region_polylines(region_a, tol / 2)
    lb = region_polylines(region_b, tol / 2)
    return polyline_minkowski_sum(la, lb, scale)


def brute_force_minkowski_sum(poly_a, poly_b):
    """Shapely-only Minkowski sum of two polygons (with holes): triangulate both
    (constrained Delaunay), sum every pair of triangles as the convex hull of the nine
    vertex sums, union everything.  O(n m) hulls: small inputs only."""
    def tris(g):
        t = shapely.constrained_delaunay_triangles(g)
        return [np.asarray(p.exterior.coords)[:3] for p in _polygons(t)]

    ta, tb = tris(poly_a), tris(poly_b)
    hulls = []
    for x in ta:
        for y in tb:
            pts = (x[:, None, :] + y[None, :, :]).reshape(-1, 2)
            hulls.append(shapely.MultiPoint(pts).convex_hull)
    return shapely.unary_union(hulls)


# ========================================================================= measures

def _as_geometry(a):
    """Shapely geometry from a geometry, an (m, 2) point array (MultiPoint) or a list of
    (m, 2) arrays (closed rings, as a MultiLineString)."""
    if isinstance(a, shapely.Geometry):
        return a
    if isinstance(a, np.ndarray) and a.ndim == 2:
        return shapely.MultiPoint(a)
    rings = []
    for r in a:
        r = np.asarray(r, float)
        rings.append(shapely.LineString(np.vstack([r, r[:1]])))
    return shapely.MultiLineString(rings)


def _linework(g):
    """Boundary of areal parts, lines and points unchanged."""
    if isinstance(g, (Polygon, MultiPolygon)):
        return g.boundary
    if hasattr(g, "geoms") and not isinstance(g, (shapely.MultiPoint, shapely.MultiLineString)):
        return shapely.GeometryCollection([_linework(x) for x in g.geoms])
    return g


def _sample_points(g, spacing):
    g = shapely.segmentize(g, spacing) if spacing else g
    return shapely.get_coordinates(g)


def max_boundary_distance(points, geom):
    """Max over points (m, 2) of the distance to ``geom.boundary`` (or to geom itself
    for line / point geometries): the one-sided, point-sampled Hausdorff distance."""
    points = np.atleast_2d(np.asarray(points, float))
    line = _linework(geom)
    if len(points) == 0:
        return 0.0
    return float(np.max(shapely.distance(shapely.points(points), line)))


def hausdorff(a, b, spacing=None):
    """Two-sided Hausdorff distance between the *boundaries* of a and b.

    ``a`` / ``b``: shapely geometries (polygons are replaced by their boundaries) or
    (m, 2) point arrays (MultiPoint) or lists of closed (m, 2) rings.  Both linework
    sets are densified to vertices at most ``spacing`` apart (shapely.segmentize) and
    the max point-to-linework distance is taken both ways, so the result is within
    spacing/2 below the exact value (GEOS distances to the other side are exact).
    Without ``spacing``: shapely.hausdorff_distance (vertices only, densify=None).
    """
    ga, gb = _linework(_as_geometry(a)), _linework(_as_geometry(b))
    if spacing is None:
        return float(shapely.hausdorff_distance(ga, gb))
    return max(max_boundary_distance(_sample_points(ga, spacing), gb),
               max_boundary_distance(_sample_points(gb, spacing), ga))


def winding_number(points, loops):
    """Winding numbers of points (m, 2) around closed polylines (vectorised).

    ``loops``: one (k, 2) array or a list of them (each closed implicitly; a repeated
    first point is harmless).  Signed crossings of the rightward horizontal ray: an
    edge going up across the point's height with the point on its left adds 1, one
    going down with the point on its right subtracts 1 (half-open rule in y).
    Points on an edge get an arbitrary neighbouring value.
    """
    points = np.atleast_2d(np.asarray(points, float))
    if isinstance(loops, np.ndarray) and loops.ndim == 2:
        loops = [loops]
    total = np.zeros(len(points), dtype=np.int64)
    px = points[:, 0:1]
    py = points[:, 1:2]
    chunk = max(1, 2_000_000 // max(1, sum(len(l) for l in loops)))
    for loop in loops:
        loop = np.asarray(loop, float)
        a = loop
        b = np.roll(loop, -1, axis=0)
        for i0 in range(0, len(points), chunk):
            x, y = px[i0:i0 + chunk], py[i0:i0 + chunk]
            ax, ay, bx, by = a[:, 0], a[:, 1], b[:, 0], b[:, 1]
            side = (bx - ax) * (y - ay) - (x - ax) * (by - ay)
            up = (ay <= y) & (by > y) & (side > 0)
            down = (ay > y) & (by <= y) & (side < 0)
            total[i0:i0 + chunk] += up.sum(axis=1) - down.sum(axis=1)
    return total


def count_outer_and_holes(geom, min_area=0.0):
    """(number of polygons, number of holes) of a shapely geometry's areal parts.

    Polygons and holes with area <= min_area are ignored (sliver noise)."""
    n_outer = n_holes = 0
    for poly in _polygons(geom):
        if poly.area <= min_area:
            continue
        n_outer += 1
        n_holes += sum(1 for r in poly.interiors if Polygon(r).area > min_area)
    return n_outer, n_holes

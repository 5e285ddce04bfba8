"""Convolution curves with QAC (Secs. 3.3, 4.4) against independent references.

What is measured, and how (all references in ``tests/reference.py`` or below; none
calls morph's evaluation or root finding):

- QAC itself (Q2, bounds, pieces on 1000 random pairs): tests/test_qac.py.
- ``minkowski_sum`` (areas and loop counts on glyph pairs, disk offsets):
  tests/test_minkowski.py.
- The driver (``convolve_edges``, Algorithm 4.1) at tol 1e-2 ... 1e-6: every piece's
  bound <= tol, sampled error <= its bound, pieces chained end to start from one end
  convolution point to the other, oriented as the module docstring says.
- Region level (``convolution``): bounds <= tol and sampled error <= tol on glyph pairs.
- Convex shapes: the chained convolution is the Minkowski boundary.  Checked against
  the support function (p . n = h_A(n) + h_B(n) at the result's own normal n) on
  densely flattened inputs, against ``R.polygon_minkowski_sum`` by Hausdorff distance
  (<= tol + flattening), and for a disk + a convex polygon against the exact area
  area(K) + r perimeter(K) + pi r^2.
- Glyph pairs with type-3 pieces kept: the pieces form closed loops (every junction
  has as many pieces arriving as leaving; ``chain`` uses each piece once); winding
  numbers are 0 outside the reference sum and >= 1 inside it, away from the zones
  where a hole of one operand meets the other (holes that close, Sec. 6).
"""

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely

from morph import convolve
from morph import gauss
from morph import parse
from morph import piece as pc
from morph import moments as mo
from morph import minkowski
from morph.errors import ToleranceNotMetError

from tests.oracles import reference as R
from tests.helpers import loop_polygons as _loop_polys
from tests.helpers import polygon_region as _polygon_region
from tests.helpers import region_size as _size
from tests.helpers import shoelace as _shoelace
from tests.test_qac import random_pairs

SEED = 20240604
TS = np.linspace(0.0, 1.0, 7)


# ======================================================================== helpers

def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _unit(v):
    v = np.atleast_2d(np.asarray(v, float))
    return v / np.hypot(v[:, 0], v[:, 1])[:, None]


def _edge(c):
    """A curve Edge of a monotone piece, angles measured by the reference."""
    prof = R.tangent_angle_profile(c, 65)
    return gauss.Edge("curve", c, R.bezier_eval(c, [0.0])[0][0], prof[0], prof[-1] - prof[0])


def param_with_tangent(c, u):
    """Parameters t where the monotone piece c (tangent turning < pi) has tangent +-u.

    The sign of u is chosen to agree with c's middle tangent; bisection on the signed
    angle (60 halvings, vectorised), an end when u is (numerically) outside the range.
    """
    u = _unit(u)
    mid = R.bezier_eval(c, [0.5], 1)[1][0]
    u = np.where((u @ mid)[:, None] < 0, -u, u)

    def g(t):
        d = R._tangent_dirs(c, t)
        return _cross(u, d) / np.hypot(d[:, 0], d[:, 1])

    m = len(u)
    lo, hi = np.zeros(m), np.ones(m)
    g0, g1 = g(lo), g(hi)
    glo = g0.copy()
    for _ in range(60):
        mid_t = 0.5 * (lo + hi)
        gm = g(mid_t)
        left = np.sign(gm) == np.sign(glo)
        lo = np.where(left, mid_t, lo)
        glo = np.where(left, gm, glo)
        hi = np.where(left, hi, mid_t)
    t = 0.5 * (lo + hi)
    outside = np.sign(g0) == np.sign(g1)
    return np.where(outside, np.where(np.abs(g0) < np.abs(g1), 0.0, 1.0), t)


def _edge_point(edge, u):
    """Point of an edge with tangent +-u: a vertex's position, a curve's solved point;
    None for a straight segment (no unique point)."""
    if edge.kind == "vertex":
        return np.tile(edge.point, (len(u), 1))
    if edge.sweep == 0.0:
        return None
    return R.bezier_eval(edge.piece, param_with_tangent(edge.piece, u))[0]


def _edge_distance(edge, q):
    if edge.kind == "vertex":
        return np.hypot(*(q - edge.point).T)
    return R.point_curve_distance(q, edge.piece, samples=513)[0]


def pair_error(points, tangents, ea, eb, stop=0.0):
    """Distance measure (Eqs. 49-53) of points claimed on the convolution of ea, eb.

    With the role of C1 taken by either edge: q = p - C1(t) (t: C1's parameter with the
    point's tangent) should lie on C2; returns the smaller of the two per point (which
    edge was approximated is the implementation's choice).  The second role is only
    evaluated where the first exceeds ``stop``.
    """
    best = np.full(len(points), np.inf)
    for x, y in ((ea, eb), (eb, ea)):
        todo = best > stop
        if not np.any(todo):
            break
        px = _edge_point(x, tangents[todo])
        if px is None:
            continue
        best[todo] = np.minimum(best[todo], _edge_distance(y, points[todo] - px))
    return best


# ============================================================ Algorithm 4.1 driver

# (tol, number of pairs): more pairs where they are cheap (1e-6 needs ~100 pieces a pair)
DRIVER_CASES = [(1e-2, 160), (1e-3, 120), (1e-4, 80), (1e-5, 30), (1e-6, 12)]
DRIVER_SAMPLES = 8


@pytest.mark.parametrize("tol, n", DRIVER_CASES, ids=[str(t) for t, _ in DRIVER_CASES])
def test_convolve_edges_within_tolerance(tol, n):
    rng = np.random.default_rng([SEED, int(-np.log10(tol))])
    worst = 0.0
    for k in range(n):
        kind = R.PAIR_KINDS[k % len(R.PAIR_KINDS)]
        c1, c2 = R.random_compatible_pair(rng, kind)
        ea, eb = _edge(c1), _edge(c2)
        pairs = convolve.compatible_pairs([ea], [eb])
        assert len(pairs) == 1, (k, kind)
        _, _, lo, hi, shift = pairs[0]
        assert hi - lo == pytest.approx(abs(ea.sweep), abs=1e-12)
        out = [(c.piece, c.kind, c.bound)
               for c in convolve.convolve_edges(ea, eb, lo, hi, shift, tol)]
        assert out
        size = max(_size([[c1]]), _size([[c2]]))
        bounds = np.array([b for _, _, b in out])
        assert np.all(bounds <= tol), (k, kind, bounds.max())
        assert {kd for _, kd, _ in out} == {"qac"}
        # chained end to start, from one end convolution point to the other,
        # forward for a convex (left-turning) pair, reversed for a concave one
        starts = np.array([R.bezier_eval(p, [0.0])[0][0] for p, _, _ in out])
        ends = np.array([R.bezier_eval(p, [1.0])[0][0] for p, _, _ in out])
        assert np.abs(ends[:-1] - starts[1:]).max(initial=0.0) <= 1e-9 * size, (k, kind)
        p0 = R.bezier_eval(c1, [0.0])[0][0] + R.bezier_eval(c2, [0.0])[0][0]
        p1 = R.bezier_eval(c1, [1.0])[0][0] + R.bezier_eval(c2, [1.0])[0][0]
        first, last = (p0, p1) if ea.sweep > 0 else (p1, p0)
        assert np.allclose(starts[0], first, atol=1e-9 * size), (k, kind)
        assert np.allclose(ends[-1], last, atol=1e-9 * size), (k, kind)
        # sampled distance measure of random points <= that piece's bound
        which = rng.integers(0, len(out), DRIVER_SAMPLES)
        ts = rng.uniform(0.0, 1.0, DRIVER_SAMPLES)
        pts = np.empty((DRIVER_SAMPLES, 2))
        tan = np.empty((DRIVER_SAMPLES, 2))
        for m, (w, t) in enumerate(zip(which, ts)):
            p, d = R.bezier_eval(out[w][0], [t], 1)
            pts[m], tan[m] = p[0], d[0]
        err = pair_error(pts, tan, ea, eb, stop=tol * 1e-3)
        assert np.all(err <= bounds[which] + 1e-12), (k, kind, err.max(), tol)
        worst = max(worst, float(err.max()))
    assert worst <= tol


# ============================================================ region convolution

def _check_region_errors(region_a, region_b, conv, tol, rng, n_samples=60):
    """Sampled distance measure of random points of the convolution pieces <= tol."""
    ga = [gauss.gauss_map(loop) for loop in region_a]
    gb = [gauss.gauss_map(loop) for loop in region_b]
    picks = rng.integers(0, len(conv), n_samples)
    ts = rng.uniform(0.0, 1.0, n_samples)
    worst = 0.0
    for w, t in zip(picks, ts):
        c = conv[w]
        ia, i, ib, j = c.source
        p, d = R.bezier_eval(c.piece, [t], 1)
        err = pair_error(p, d, ga[ia][i], gb[ib][j])
        assert err[0] <= tol + 1e-9 * _size(region_a), (c.kind, c.type, err[0])
        worst = max(worst, float(err[0]))
    return worst


@pytest.mark.parametrize("tol", [1.0, 1e-2])
def test_convolution_of_cubic_glyphs_within_tolerance(tol):
    font = parse.cubic_test_font_path()
    a = parse.glyph_region("S", font).region
    b = parse.glyph_region("o", font).region
    conv = convolve.convolution(a, b, tol)
    assert {c.type for c in conv} == {1, 2, 3}
    assert all(c.bound <= tol for c in conv)
    assert all(c.bound == 0.0 for c in conv if c.kind == "translate")
    _check_region_errors(a, b, conv, tol, np.random.default_rng(SEED + 2))


@pytest.mark.parametrize("sa, sb, expect", [
    (1, 1, 1), (1, 0, 1), (0, 1, 1), (0, 0, 1),      # convex / straight
    (1, -1, 2), (-1, 1, 2),                          # convex / concave
    (-1, -1, 3), (0, -1, 3), (-1, 0, 3),             # concave / concave or straight
])
def test_pair_type_table(sa, sb, expect):
    # Fig. 20 as stated in the convolve module docstring (curve signs)
    assert convolve.pair_type(sa, sb) == expect


def test_concave_vertex_pairs_are_type3():
    """Fig. 20 / module docstring: any pair with a concave vertex is type 3 (never on
    the boundary).  L-shaped hexagon (one reflex corner) + a disk: the arc translated
    to the reflex corner lies strictly inside the sum, yet it comes out as type 2."""
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    ell = [[pc.line(pts[i], pts[(i + 1) % 6]) for i in range(6)]]
    r = 0.3
    disk = [pc.circle((0.0, 0.0), r)]
    conv = convolve.convolution(ell, disk, 1e-6)
    ga = gauss.gauss_map(ell[0])
    hexagon = shapely.Polygon(pts)
    reflex = []
    for c in conv:
        _, i, _, j = c.source
        if ga[i].kind == "vertex" and ga[i].sign < 0:
            reflex.append(c)
            # geometrically inside: the arc around the reflex corner (1, 1)
            mid = R.bezier_eval(c.piece, np.linspace(0.1, 0.9, 9))[0]
            assert np.all(shapely.distance(shapely.points(mid), hexagon) < r - 1e-3)
    assert len(reflex) == 1
    assert [c.type for c in reflex] == [3]
    # so keep_type3=False drops it
    kept = convolve.convolution(ell, disk, 1e-6, keep_type3=False)
    assert len(kept) == len(conv) - 1


def test_convolution_drops_type3_on_request():
    a = parse.glyph_region("S").region
    b = parse.glyph_region("g").region
    full = convolve.convolution(a, b, 0.1, keep_type3=True)
    kept = convolve.convolution(a, b, 0.1, keep_type3=False)
    assert any(c.type == 3 for c in full)
    assert all(c.type in (1, 2) for c in kept)
    assert len(kept) == sum(1 for c in full if c.type != 3)


def test_convolution_rejects_bad_tolerance():
    with pytest.raises(ValueError):
        convolve.convolution([pc.circle((0, 0), 1)], [pc.circle((0, 0), 1)], 0.0)


def test_tiny_common_sweep_meets_tolerance():
    """A compatible pair whose common angle range is below TINY_SWEEP (1e-7 rad).

    Two long, nearly straight parabolic arcs (1000 and 667 units, sweep 5e-8 rad):
    QAC is exact for them (C2 quadratic), but the driver replaces the pair by the chord
    of the sums, whose own bound (2.1e-5) exceeds tol and whose true error is 1.0e-5.
    Contract of convolve_edges: every returned bound <= tol, or ToleranceNotMetError.
    """
    length, d = 1000.0, 2.5e-8
    c1 = pc.quadratic((0.0, 0.0), (length / 2, 0.0), (length, length * d))
    c2 = pc.quadratic((5.0, 5.0), (5.0 + length / 3, 5.0),
                      (5.0 + 2 * length / 3, 5.0 + 2 * length / 3 * d))
    ea, eb = _edge(c1), _edge(c2)
    assert 0 < ea.sweep < 1e-7 and 0 < eb.sweep < 1e-7
    (_, _, lo, hi, shift), = convolve.compatible_pairs([ea], [eb])
    # exact convolution points (Eq. 27 solved by the reference) and the output polyline
    exact, s = R.exact_convolution_points(c1, c2, np.linspace(0.0, 1.0, 21))
    assert not np.any(np.isnan(s))
    for tol in (1e-3, 1e-6, 1e-8):
        try:
            out = [(c.piece, c.kind, c.bound)
               for c in convolve.convolve_edges(ea, eb, lo, hi, shift, tol)]
        except ToleranceNotMetError:
            continue
        bounds = [b for _, _, b in out]
        poly = np.concatenate([R.bezier_eval(p, np.linspace(0.0, 1.0, 200))[0] for p, _, _ in out])
        err = R.max_boundary_distance(exact, shapely.LineString(poly))
        assert max(bounds) <= tol and err <= tol, (tol, [k for _, k, _ in out], bounds, err)


# ======================================================= polygons (exact reference)

def _random_simple_polygon(rng, n, r0, r1, centre):
    while True:
        ang = np.sort(rng.uniform(0.0, 2 * np.pi, n))
        r = rng.uniform(r0, r1, n)
        p = np.column_stack([centre[0] + r * np.cos(ang), centre[1] + r * np.sin(ang)])
        poly = shapely.Polygon(p)
        if poly.is_valid and poly.area > 0.05:
            return p if _shoelace(p) > 0 else p[::-1]


def test_random_polygons_exact():
    """Simple polygons: convolution and sum are exact, the reference is exact
    (Clipper on integers at 1e-7), and the convolution's winding number is positive
    exactly on the sum (Guibas-Ramshaw-Stolfi for simple polygons)."""
    rng = np.random.default_rng(SEED + 5)
    for k in range(40):
        a = _random_simple_polygon(rng, int(rng.integers(4, 12)), 1.0, 3.0, (0.0, 0.0))
        b = _random_simple_polygon(rng, int(rng.integers(3, 9)), 0.5, 2.0, (0.3, -0.2))
        ra, rb = _polygon_region(a), _polygon_region(b)
        conv = convolve.convolution(ra, rb, 1e-6)
        assert {c.kind for c in conv} == {"translate"}
        pieces = [c.piece for c in conv]
        _balanced_junctions(pieces, 1e-12)
        loops = convolve.chain(pieces, 1e-9)
        ref = R.polyline_minkowski_sum([a], [b], 1e7)
        polys = [np.array([pc.start(p) for p in loop]) for loop in loops]
        pts = rng.uniform(-7.0, 7.0, (1500, 2))
        geo = shapely.points(pts)
        far = shapely.distance(geo, ref.boundary) > 1e-5
        inside = shapely.contains(ref, geo)
        w = R.winding_number(pts, polys)
        assert np.all(w[far & ~inside] == 0), k
        assert np.all(w[far & inside] >= 1), k
        loops_sum = minkowski.minkowski_sum(ra, rb, 1e-6)
        # Clipper rounds coordinates to 1e-7: area within perimeter x 1e-7
        assert mo.region_area(loops_sum) == pytest.approx(ref.area, abs=1e-7 * ref.length), k
        corners = [np.array([pc.start(p) for p in loop]) for loop in loops_sum]
        assert R.hausdorff(ref, corners, spacing=0.01) <= 1e-6, k


def test_convolution_commutes_and_translates():
    ra, rb = parse.glyph_region("O").region, parse.glyph_region("M").region
    size = _size(ra) + _size(rb)

    def signed_area(conv):
        loops = convolve.chain([c.piece for c in conv], 1e-9 * size)
        return sum(mo.loop_area(loop) for loop in loops)

    ab = convolve.convolution(ra, rb, 0.1)
    ba = convolve.convolution(rb, ra, 0.1)
    assert len(ab) == len(ba)
    assert signed_area(ab) == pytest.approx(signed_area(ba), rel=1e-12)
    v = np.array([123.25, -48.5])
    moved = [[pc.translate(p, v) for p in loop] for loop in ra]
    ab_v = convolve.convolution(moved, rb, 0.1)
    assert len(ab_v) == len(ab)
    for c, cv in zip(ab, ab_v):
        # same curve moved by v (the parametrisation may differ: exact QAC either way)
        assert np.allclose(R.bezier_eval(cv.piece, [0.0, 1.0])[0],
                           R.bezier_eval(c.piece, [0.0, 1.0])[0] + v, atol=1e-9 * size)
        xv = R.bezier_eval(cv.piece, TS)[0]
        assert R.point_curve_distance(xv - v, c.piece, 257)[0].max() <= 1e-9 * size


# ================================================================= convex shapes

def _support(region, normals, flat):
    """h(n) = max_x x . n over a region flattened within ``flat`` (inscribed: the
    true support is at most ``flat`` larger)."""
    pts = np.concatenate(R.region_polylines(region, flat))
    return np.max(normals @ pts.T, axis=1)


def _convex_check(region_a, region_b, tol, flat_fine, flat_ref, n_samples=400):
    conv = convolve.convolution(region_a, region_b, tol)
    assert all(c.type == 1 for c in conv)
    assert all(c.bound <= tol for c in conv)
    loops = convolve.chain([c.piece for c in conv], 1e-9 * _size(region_a))
    assert len(loops) == 1
    loop = loops[0]
    assert mo.loop_area(loop) > 0
    # support function at the result's own outward normal (Eq. 20: right of travel)
    ts = np.linspace(0.0, 1.0, max(3, n_samples // len(loop)))
    pts, tan = [], []
    for p in loop:
        x, d = R.bezier_eval(p, ts, 1)
        pts.append(x)
        tan.append(d)
    pts, tan = np.concatenate(pts), np.concatenate(tan)
    n = _unit(np.column_stack([tan[:, 1], -tan[:, 0]]))
    h = _support(region_a, n, flat_fine) + _support(region_b, n, flat_fine)
    gap = np.sum(pts * n, axis=1) - h
    assert gap.max() <= tol + 2 * flat_fine + 1e-9, gap.max()
    assert gap.min() >= -tol - 1e-9, gap.min()
    # Hausdorff distance to the polygon Minkowski sum (inputs flattened within flat_ref/2)
    ref = R.polygon_minkowski_sum(region_a, region_b, flat_ref)
    poly = _loop_polys(loops, flat_ref / 10)
    hd = R.hausdorff(ref, poly, spacing=flat_ref / 2)
    assert hd <= tol + flat_ref + flat_ref / 10 + flat_ref / 4, hd
    return loop, ref, hd


def _outer_loop(ch, font):
    region = parse.glyph_region(ch, font).region
    outer = [l for l in region if mo.loop_area(l) > 0]
    assert len(outer) == 1
    return [outer[0]]


# The CFF 'O' outer loop is not convex (a -0.68 degree corner at (207, 679) in the font
# data), so the cubic font uses 'o', whose outer loop is.
@pytest.mark.parametrize("font, ch", [("ttf", "O"), ("cff", "o")])
@pytest.mark.parametrize("tol", [1.0, 1e-2, 1e-4])
def test_convex_o_outer_plus_ellipse_is_minkowski_boundary(font, ch, tol):
    path = None if font == "ttf" else parse.cubic_test_font_path()
    a = _outer_loop(ch, path)
    assert all(e.sweep >= 0 for e in gauss.gauss_map(a[0]))
    b = [pc.ellipse((0.0, 0.0), 60.0, 25.0, 0.4)]
    _convex_check(a, b, tol, flat_fine=1e-3, flat_ref=0.5)


def _blob_a():
    """Convex loop of three cubics, tangent-continuous at one join, corners at two."""
    return [[pc.cubic((2.0, 0.0), (2.0, 0.75), (0.9, 1.2), (0.0, 1.2)),
             pc.cubic((0.0, 1.2), (-1.5, 1.2), (-2.0, 0.6), (-2.0, 0.0)),
             pc.cubic((-2.0, 0.0), (-1.0, -0.9), (1.3, -0.7), (2.0, 0.0))]]


def _blob_b():
    """Rounded triangle of three convex cubics (three corners)."""
    p = np.array([(0.0, 0.0), (1.5, -0.2), (0.6, 1.1)])
    c = p.mean(axis=0)
    loop = []
    for i in range(3):
        a, b = p[i], p[(i + 1) % 3]
        out = _unit((a + b) / 2 - c)[0]
        loop.append(pc.cubic(a, a + (b - a) / 3 + 0.25 * out, a + 2 * (b - a) / 3 + 0.15 * out, b))
    return [loop]


@pytest.mark.parametrize("tol", [1e-2, 1e-4, 1e-5])
def test_convex_bezier_blobs_are_minkowski_boundary(tol):
    a, b = _blob_a(), _blob_b()
    for region in (a, b):   # the test shapes are convex
        edges = gauss.gauss_map(region[0])
        assert all(e.sweep >= 0 for e in edges)
    loop, ref, hd = _convex_check(a, b, tol, flat_fine=1e-6, flat_ref=2e-3)
    conv = convolve.convolution(a, b, tol)
    _check_region_errors(a, b, conv, tol, np.random.default_rng(SEED + 3), n_samples=40)


def _convex_hull_region(ch, flat=0.5):
    poly = R.region_to_shapely(parse.glyph_region(ch).region, flat)
    hull = shapely.geometry.polygon.orient(poly.convex_hull, 1.0)
    pts = np.asarray(hull.exterior.coords)[:-1]
    return [[pc.line(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]], hull


@pytest.mark.parametrize("ch, r", [("g", 40.0), ("A", 7.5), ("O", 250.0)])
def test_disk_plus_convex_hull_is_exact(ch, r):
    k_region, hull = _convex_hull_region(ch)
    disk = [pc.circle((12.0, -3.0), r)]
    conv = convolve.convolution(disk, k_region, 1e-6)
    assert {c.kind for c in conv} == {"translate"}
    loops = convolve.chain([c.piece for c in conv], 1e-9 * r)
    assert len(loops) == 1
    # area(K) + r perimeter(K) + pi r^2, from the exact rational arcs
    expect = hull.area + r * hull.length + np.pi * r * r
    assert mo.loop_area(loops[0]) == pytest.approx(expect, rel=1e-12)
    # boundary = buffer of the hull (shifted by the centre), to within the buffer's chords
    quad = 1024
    ref = shapely.affinity.translate(hull.buffer(r, quad_segs=quad), 12.0, -3.0)
    chord = r * (1 - np.cos(np.pi / (4 * quad)))
    flat = 1e-3
    hd = R.hausdorff(ref, _loop_polys(loops, flat), spacing=1.0)
    assert hd <= 2 * chord + flat, hd  # GEOS may space arc vertices unevenly
    # and the polygon Minkowski sum reference (inputs flattened within 0.25)
    ref2 = R.polygon_minkowski_sum(disk, k_region, 0.5)
    hd2 = R.hausdorff(ref2, _loop_polys(loops, flat), spacing=1.0)
    assert hd2 <= 0.5 + flat + 0.01, hd2


# ================================================== closed, consistently oriented

GLYPH_PAIRS = [("T", "M"), ("O", "M"), ("S", "g")]


def _balanced_junctions(pieces, eps):
    """Every point where pieces end has as many pieces starting there (closed loops)."""
    starts = np.array([R.bezier_eval(p, [0.0])[0][0] for p in pieces])
    ends = np.array([R.bezier_eval(p, [1.0])[0][0] for p in pieces])
    for e in ends:
        n_end = int(np.sum(np.hypot(*(ends - e).T) <= eps))
        n_start = int(np.sum(np.hypot(*(starts - e).T) <= eps))
        assert n_start == n_end, (e, n_start, n_end)


def _hole_zones(region_a, region_b, flat):
    """Union of (filled hole of one operand) + (other operand): where holes may close."""
    zones = []
    for x, y in ((region_a, region_b), (region_b, region_a)):
        for loop in x:
            if mo.loop_area(loop) < 0:
                filled = [[pc.reverse(p) for p in reversed(loop)]]
                zones.append(R.polygon_minkowski_sum(filled, y, flat))
    return shapely.unary_union(zones) if zones else shapely.GeometryCollection()


@pytest.mark.parametrize("a, b", GLYPH_PAIRS, ids=["%s+%s" % p for p in GLYPH_PAIRS])
def test_convolution_loops_closed_and_oriented(a, b):
    ra, rb = parse.glyph_region(a).region, parse.glyph_region(b).region
    conv = convolve.convolution(ra, rb, 0.1, keep_type3=True)
    pieces = [c.piece for c in conv]
    size = _size(ra) + _size(rb)
    _balanced_junctions(pieces, 1e-9 * size)
    loops = convolve.chain(pieces, 1e-9 * size)
    assert sum(len(l) for l in loops) == len(pieces)
    for loop in loops:
        for p, q in zip(loop, loop[1:] + loop[:1]):
            assert np.allclose(pc.end(p), pc.start(q), atol=1e-9 * size)
    # winding numbers of the flattened loops against the polygon reference sum
    flat, margin = 1.0, 3.0
    ref = R.polygon_minkowski_sum(ra, rb, flat)
    polys = _loop_polys(loops, 0.2)
    rng = np.random.default_rng(SEED + 4)
    x0, y0, x1, y1 = ref.bounds
    pts = rng.uniform([x0 - 100, y0 - 100], [x1 + 100, y1 + 100], (3000, 2))
    geo = shapely.points(pts)
    far = shapely.distance(geo, ref.boundary) > margin
    inside = shapely.contains(ref, geo) & far
    outside = ~shapely.contains(ref, geo) & far
    zone = shapely.intersects(_hole_zones(ra, rb, flat).buffer(margin), geo)
    w = R.winding_number(pts, polys)
    assert inside.sum() > 300 and outside.sum() > 300
    assert np.all(w[outside] == 0), np.unique(w[outside], return_counts=True)
    assert np.all(w[inside & ~zone] >= 1), np.unique(w[inside & ~zone], return_counts=True)
    # far outside the bounding box: nothing
    ring = np.array([[x0 - 500, y0 - 500], [x1 + 500, y1 + 500], [x0 - 500, y1 + 500],
                     [x1 + 500, y0 - 500]])
    assert np.all(R.winding_number(ring, polys) == 0)


# ============================================================== batched driver

def test_batched_driver_matches_pair_by_pair():
    """Algorithm 4.1 on all pairs at once (one edge table per side) gives each pair
    the pieces of the one-pair driver, in the same order, every bound <= tol."""
    pairs = [(c1, c2) for _, c1, c2 in random_pairs(60, SEED + 2)]
    tol = 1e-4
    ea = [_edge(c1) for c1, _ in pairs]
    eb = [_edge(c2) for _, c2 in pairs]
    ta, tb = convolve._EdgeTable([ea]), convolve._EdgeTable([eb])
    table = []
    for k in range(len(pairs)):
        (i, j, lo, hi, shift), = convolve.compatible_pairs([ea[k]], [eb[k]])
        table.append((k, k, lo, hi, shift))
    arrays = tuple(np.array([p[c] for p in table]) for c in range(5))
    res = convolve._convolve_table(ta, tb, arrays, tol)
    for k in range(len(pairs)):
        got = [(c.piece, c.kind, c.bound) for c in res if c.row == k]
        ref = [(c.piece, c.kind, c.bound)
               for c in convolve.convolve_edges(ea[k], eb[k], *table[k][2:], tol)]
        assert len(got) == len(ref) > 0
        for (p, kind, b), (p_ref, kind_ref, b_ref) in zip(got, ref):
            assert kind == kind_ref and p.shape == p_ref.shape and b <= tol
            assert np.allclose(pc.cartesian(p), pc.cartesian(p_ref), atol=1e-9)


def _flags(region_a, region_b, reach=1e-3):
    pair = convolve.with_pair_table(convolve.gauss_pair_of(region_a, region_b))
    return convolve.crossing_rows(pair, reach)


def test_crossing_rows_none_for_disjoint_convex_loops():
    """Convex counter-clockwise loops whose sums' boxes are apart: no convolution
    piece can meet another, no row is flagged; moved close enough for their boxes to
    overlap, every row is."""
    disk = [pc.circle((0.0, 0.0), 0.25)]
    apart = [pc.circle((0.0, 0.0), 1.0), pc.circle((3.0, 0.0), 1.0)]
    near = [pc.circle((0.0, 0.0), 1.0), pc.circle((2.4, 0.0), 1.0)]   # sums 0.1 apart, boxes overlap
    assert not _flags(apart, disk).any()
    assert _flags(near, disk).all()


def test_crossing_rows_flag_non_convex_and_clockwise_loops():
    """A glyph's loops (not convex) and a hole (clockwise) can meet themselves: all
    their rows are flagged."""
    disk = [pc.circle((0.0, 0.0), 20.0)]
    assert _flags(parse.glyph_region("S").region, disk).all()
    hole = [pc.reverse(p) for p in pc.circle((0.0, 0.0), 1.0)][::-1]
    assert _flags([pc.circle((0.0, 0.0), 3.0), hole], [pc.circle((0.0, 0.0), 0.25)]).all()


def test_first_round_keeps_the_whole_budget_away_from_corners():
    """Disjoint circles ⊕ disk: the first round's pieces are those of the whole
    budget (no row can reach a corner), not the finer ones of FIRST_SHARE."""
    region = [pc.circle((3.0 * k, 0.0), 1.0) for k in range(3)]
    disk = [pc.circle((0.0, 0.0), 0.25)]
    out = minkowski.minkowski_sum(region, disk, 1e-4)
    conv = convolve.convolution(region, disk, minkowski.CONV_SHARE * 1e-4)
    assert sum(len(loop) for loop in out) == len(conv)

"""The reference computations of tests/reference.py on cases with known answers."""

import numpy as np
import pyclipper
import pytest
pytest.importorskip("shapely")
import shapely
from shapely.geometry import Point, Polygon, box

from morph import piece as mp

from tests.oracles import reference as R


# ------------------------------------------------------------------------- helpers

def arc(center, r, theta0, dtheta):
    (p,) = mp.ellipse_arc(center, r, r, 0.0, theta0, dtheta)
    return p


def square_region(x0, y0, side):
    c = [(x0, y0), (x0 + side, y0), (x0 + side, y0 + side), (x0, y0 + side)]
    return [[mp.line(c[i], c[(i + 1) % 4]) for i in range(4)]]


def hole_loop(center, r):
    """Clockwise circle (a hole)."""
    return [mp.reverse(p) for p in reversed(mp.circle(center, r))]


def star(rng, center, rmin, rmax, n):
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    rad = rng.uniform(rmin, rmax, n)
    return np.column_stack([np.cos(ang) * rad, np.sin(ang) * rad]) + center


# ------------------------------------------------------------------ bezier_eval

def test_bezier_eval_matches_circle_and_project_evaluate():
    p = arc((1.0, -2.0), 3.0, 0.3, 1.2)
    t = np.linspace(0, 1, 33)
    pts, d1, d2 = R.bezier_eval(p, t, 2)
    assert np.allclose(np.hypot(*(pts - [1, -2]).T), 3.0, atol=1e-14)
    # tangent perpendicular to radius, acceleration has a centripetal part
    assert np.allclose(np.sum((pts - [1, -2]) * d1, axis=1), 0, atol=1e-12)
    speed2 = np.sum(d1 * d1, axis=1)
    curv = (d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / speed2 ** 1.5
    assert np.allclose(curv, 1 / 3.0, rtol=1e-10)
    assert np.allclose(pts, mp.evaluate(p, t), atol=1e-14)
    c = mp.cubic((0, 0), (1, 2), (3, 2), (4, 0))
    assert np.allclose(R.bezier_eval(c, t, 1)[1], mp.derivative(c, t), atol=1e-12)


# ------------------------------------------------------------ exact convolution

@pytest.mark.parametrize("theta0,dtheta", [(0.0, np.pi / 2), (2.0, -1.0), (-2.5, 0.4)])
def test_convolution_of_concentric_arcs_is_arc_of_summed_radius(theta0, dtheta):
    r1, r2 = 1.5, 0.7
    o1, o2 = np.array([2.0, 1.0]), np.array([-1.0, 3.0])
    c1 = arc(o1, r1, theta0, dtheta)
    c2 = arc(o2, r2, theta0, dtheta)
    ts = np.linspace(0, 1, 41)
    pts, s = R.exact_convolution_points(c1, c2, ts)
    assert not np.any(np.isnan(s))
    assert abs(s[0]) < 1e-12 and abs(s[-1] - 1) < 1e-12
    # same parametrisation (same angles, same weights): s == t
    assert np.allclose(s, ts, atol=1e-12)
    rel = pts - (o1 + o2)
    assert np.allclose(np.hypot(*rel.T), r1 + r2, atol=1e-12)
    # the point has the same normal direction as C1(t)
    n1 = R.bezier_eval(c1, ts)[0] - o1
    assert np.allclose(R._cross(rel, n1), 0, atol=1e-12)
    assert np.all(np.sum(rel * n1, axis=1) > 0)


def test_convolution_with_longer_c2_arc():
    # c1's tangent range strictly inside c2's: s in (0, 1), still the r1+r2 arc
    c1 = arc((0, 0), 1.0, 0.5, 0.8)
    c2 = arc((5, 5), 2.0, 0.2, 1.4)
    ts = np.linspace(0, 1, 17)
    pts, s = R.exact_convolution_points(c1, c2, ts)
    assert np.all((s > 0) & (s < 1))
    assert np.allclose(np.hypot(*(pts - [5, 5]).T), 3.0, atol=1e-12)
    p1 = R.bezier_eval(c1, ts)[0]
    assert np.allclose(np.arctan2(pts[:, 1] - 5, pts[:, 0] - 5),
                       np.arctan2(p1[:, 1], p1[:, 0]), atol=1e-12)


def test_quadratic_c2_closed_form_s():
    # Q2'(s) = 2((1-s) h0 + s h1): cross(u, Q2') = 0 gives s = x0 / (x0 - x1) (Eq. 36)
    rng = np.random.default_rng(5)
    for _ in range(20):
        c1, c2 = R.random_compatible_pair(rng, "cubic-quad")
        ts = np.linspace(0, 1, 23)
        _, s = R.exact_convolution_points(c1, c2, ts)
        q = mp.cartesian(c2)
        h0, h1 = q[1] - q[0], q[2] - q[1]
        u = R.bezier_eval(c1, ts, 1)[1]
        x0, x1 = R._cross(u, h0), R._cross(u, h1)
        expect = np.clip(x0 / (x0 - x1), 0, 1)
        assert np.allclose(s, expect, atol=1e-10)


def test_no_parallel_tangent_gives_nan():
    c1 = arc((0, 0), 1.0, 0.0, 0.5)
    c2 = arc((0, 0), 1.0, 1.0, 0.5)          # disjoint tangent ranges
    pts, s = R.exact_convolution_points(c1, c2, [0.0, 0.5, 1.0])
    assert np.all(np.isnan(s)) and np.all(np.isnan(pts))
    # opposite orientation (antiparallel tangents) is not a solution either
    c3 = mp.reverse(arc((0, 0), 1.0, 0.0, 0.5))
    _, s = R.exact_convolution_points(c1, c3, [0.0, 0.5, 1.0])
    assert np.all(np.isnan(s))


def test_distance_to_convolution_exact_and_offset():
    rng = np.random.default_rng(1)
    for kind in R.PAIR_KINDS:
        c1, c2 = R.random_compatible_pair(rng, kind)
        ts = np.linspace(0, 1, 25)
        pts, s = R.exact_convolution_points(c1, c2, ts)
        assert np.max(R.distance_to_convolution(pts, ts, c1, c2)) < 1e-12
        # push the points along C2's normal by delta: the distance is delta
        _, d2 = R.bezier_eval(c2, s, 1)
        nrm = np.column_stack([d2[:, 1], -d2[:, 0]]) / np.hypot(*d2.T)[:, None]
        delta = 1e-3
        inner = ts[(ts > 0.05) & (ts < 0.95)]
        sel = np.isin(ts, inner)
        for sign in (1, -1):
            d = R.distance_to_convolution(pts[sel] + sign * delta * nrm[sel], ts[sel], c1, c2)
            assert np.allclose(d, delta, rtol=1e-9)


def test_distance_to_convolution_circle_known_value():
    c1 = arc((0, 0), 1.0, 0.0, np.pi / 2)
    c2 = arc((0, 0), 2.0, 0.0, np.pi / 2)
    ts = np.linspace(0, 1, 9)
    pts, _ = R.exact_convolution_points(c1, c2, ts)
    # scaling the exact points about the origin by (3 + e)/3 moves q radially by e
    e = 0.01
    d = R.distance_to_convolution(pts * (3 + e) / 3, ts, c1, c2)
    assert np.allclose(d, e, atol=1e-12)
    # approx_convolution_error of the exact arc of radius 3 (same parametrisation) ~ 0
    assert R.approx_convolution_error(arc((0, 0), 3.0, 0.0, np.pi / 2), c1, c2, n=50) < 1e-12


# -------------------------------------------------------- random compatible pairs

@pytest.mark.parametrize("kind", R.PAIR_KINDS)
def test_random_compatible_pair_properties(kind):
    rng = np.random.default_rng(R.PAIR_KINDS.index(kind))
    for _ in range(25):
        c1, c2 = R.random_compatible_pair(rng, kind)
        size = {"cubic": 4, "quad": 3, "conic": 3}
        k1, k2 = kind.split("-")
        assert c1.shape == (size[k1], 3) and c2.shape == (size[k2], 3)
        assert np.all(c1[:, 2] > 0) and np.all(c2[:, 2] > 0)
        if k1 != "conic":
            assert np.allclose(c1[:, 2], 1)
        assert np.allclose(c2[:, 2], 1)          # c2 is always polynomial here
        a1, a2 = R.tangent_angle_profile(c1), R.tangent_angle_profile(c2)
        # same start and end tangent angles (mod 2 pi)
        for x, y in ((a1[0], a2[0]), (a1[-1], a2[-1])):
            assert abs(np.angle(np.exp(1j * (x - y)))) < 1e-9
        sweep1, sweep2 = a1[-1] - a1[0], a2[-1] - a2[0]
        assert abs(sweep1 - sweep2) < 1e-9
        assert np.radians(10) - 1e-9 <= abs(sweep1) < np.pi / 2
        # monotone tangent angle, strictly signed curvature: no inflection
        for a, c in ((a1, c1), (a2, c2)):
            assert np.all(np.diff(a) * np.sign(sweep1) > 0)
            k = R.curvature_sign_values(c)
            assert np.all(k * np.sign(sweep1) > 0)
        # every t has exactly one matching s
        ts = np.linspace(0, 1, 7)
        for t in ts:
            u = R.bezier_eval(c1, [t], 1)[1][0]
            assert len(R.solve_parallel(c2, u)) == 1


def test_random_pair_kinds_rejects_unknown():
    with pytest.raises(ValueError):
        R.random_compatible_pair(np.random.default_rng(0), "cubic-line")


# ---------------------------------------------------------------- Clipper semantics

def test_pyclipper_minkowski_sum_is_boundary_sum_only():
    """Documents the surprise: Clipper's MinkowskiSum sums the two boundaries."""
    big = [(0, 0), (100, 0), (100, 100), (0, 100)]
    small = [(0, 0), (10, 0), (10, 10), (0, 10)]
    out = pyclipper.MinkowskiSum(big, small, True)
    areas = sorted(pyclipper.Area(p) for p in out)
    assert areas == [-8100.0, 12100.0]          # 110x110 square with a 90x90 hole
    full = R.polyline_minkowski_sum([np.array(big, float)], [np.array(small, float)], 1.0)
    assert R.count_outer_and_holes(full) == (1, 0)
    assert full.area == pytest.approx(110 * 110)


# ------------------------------------------------------------------ polygon sums

def test_rectangles_exact():
    a = [np.array([(0, 0), (3, 0), (3, 1), (0, 1)], float)]
    b = [np.array([(-1, -1), (1, -1), (1, 2.5), (-1, 2.5)], float)]
    s = R.polyline_minkowski_sum(a, b, 1000.0)
    assert s.area == pytest.approx(5 * 4.5, abs=1e-9)
    assert s.symmetric_difference(box(-1, -1, 4, 3.5)).area < 1e-9
    # region (pieces) version with lines: flattening exact
    s2 = R.polygon_minkowski_sum(square_region(0, 0, 2), square_region(1, 1, 0.5), 1e-3)
    assert s2.symmetric_difference(box(1, 1, 3.5, 3.5)).area < 1e-9


def test_convex_polygons_equal_hull_of_vertex_sums():
    rng = np.random.default_rng(3)
    for _ in range(5):
        pa = shapely.MultiPoint(rng.uniform(-1, 1, (9, 2))).convex_hull
        pb = shapely.MultiPoint(rng.uniform(-2, 2, (7, 2))).convex_hull
        va = np.asarray(pa.exterior.coords)[:-1]
        vb = np.asarray(pb.exterior.coords)[:-1]
        hull = shapely.MultiPoint((va[:, None] + vb[None]).reshape(-1, 2)).convex_hull
        s = R.polyline_minkowski_sum(pa, pb, 1e6)
        assert s.symmetric_difference(hull).area < 1e-5
        assert R.brute_force_minkowski_sum(pa, pb).symmetric_difference(hull).area < 1e-9


def test_disk_plus_square_area():
    r, a, tol = 0.75, 2.0, 1e-3
    disk = [mp.circle((0.3, -0.2), r)]
    s = R.polygon_minkowski_sum(disk, square_region(0, 0, a), tol)
    exact = a * a + 4 * a * r + np.pi * r * r
    # flattened disk lies inside the disk, within tol/2: area deficit <= perimeter * tol/2
    assert exact - (4 * a + 2 * np.pi * r) * tol / 2 - 1e-6 <= s.area <= exact + 1e-6
    assert R.count_outer_and_holes(s) == (1, 0)


def test_ring_with_small_hole_plus_large_disk_has_no_hole():
    ring = [mp.circle((0, 0), 2.0), hole_loop((0, 0), 0.5)]
    disk = [mp.circle((1, 1), 1.0)]
    s = R.polygon_minkowski_sum(ring, disk, 2e-3)
    assert R.count_outer_and_holes(s) == (1, 0)
    assert s.area == pytest.approx(np.pi * 9, rel=2e-3)
    assert R.hausdorff(s, Point(1, 1).buffer(3.0, 256), spacing=0.01) < 2e-3


def test_ring_with_large_hole_plus_small_disk_keeps_hole():
    ring = [mp.circle((0, 0), 3.0), hole_loop((0, 0), 2.0)]
    disk = [mp.circle((0, 0), 0.5)]
    s = R.polygon_minkowski_sum(ring, disk, 2e-3)
    assert R.count_outer_and_holes(s) == (1, 1)
    assert s.area == pytest.approx(np.pi * (3.5 ** 2 - 1.5 ** 2), rel=2e-3)
    assert np.asarray(s.interiors[0].coords)[:, 0].max() == pytest.approx(1.5, abs=2e-3)


def test_disk_plus_annulus_needs_a_point_on_every_loop():
    # x = centre: -B is the annulus, it contains the disk's boundary but not the disk
    disk = Point(0, 0).buffer(2.0, 12)
    ann = Point(0, 0).buffer(3.0, 12).difference(Point(0, 0).buffer(1.0, 12))
    s = R.polyline_minkowski_sum(disk, ann, 1e6)
    assert R.count_outer_and_holes(s) == (1, 0)
    assert s.contains(Point(0, 0))
    assert s.symmetric_difference(R.brute_force_minkowski_sum(disk, ann)).area < 1e-4


def test_small_shape_inside_big_one_and_several_components():
    a = shapely.MultiPolygon([box(0, 0, 1, 1), box(5, 0, 6, 1)])
    b = box(0, 0, 0.2, 0.2)
    s = R.polyline_minkowski_sum(a, b, 1e6)
    assert R.count_outer_and_holes(s) == (2, 0)
    assert s.area == pytest.approx(2 * 1.2 ** 2)


def test_random_polygons_with_holes_match_brute_force():
    rng = np.random.default_rng(7)
    for case in range(6):
        outer = star(rng, (0, 0), 1.0, 2.0, 10)
        hole = star(rng, (0, 0), 0.3, 0.6, 6)[::-1]
        pa = Polygon(outer, [hole] if case % 2 == 0 else [])
        pb = Polygon(star(rng, (3, 1), 0.1 + 0.3 * (case % 3), 0.9, 7))
        assert pa.is_valid and pb.is_valid
        ref = R.brute_force_minkowski_sum(pa, pb)
        s = R.polyline_minkowski_sum(pa, pb, 1e6)
        assert s.symmetric_difference(ref).area < 1e-4
        assert R.count_outer_and_holes(s, 1e-9) == R.count_outer_and_holes(ref, 1e-9)
        # loops-as-arrays input gives the same result as shapely input
        loops = [np.asarray(pa.exterior.coords)[:-1]] + \
            [np.asarray(r.coords)[:-1] for r in pa.interiors]
        loops = [l if Polygon(l).exterior.is_ccw == (i == 0) else l[::-1]
                 for i, l in enumerate(loops)]
        s2 = R.polyline_minkowski_sum(loops, pb, 1e6)
        assert s2.symmetric_difference(s).area < 1e-9


def test_brute_force_hole_case():
    ring = box(0, 0, 4, 4).difference(box(1, 1, 3, 3))
    assert R.count_outer_and_holes(R.brute_force_minkowski_sum(ring, box(0, 0, 1, 1))) == (1, 1)
    assert R.count_outer_and_holes(R.brute_force_minkowski_sum(ring, box(0, 0, 2.5, 2.5))) == (1, 0)


# -------------------------------------------------------------------- measures

def test_region_to_shapely():
    tol = 1e-3
    g = R.region_to_shapely([mp.circle((0, 0), 2.0), hole_loop((0, 0), 1.0)], tol)
    assert R.count_outer_and_holes(g) == (1, 1)
    assert g.area == pytest.approx(3 * np.pi, rel=2 * tol)
    # overlapping outer loops: nonzero fill gives their union
    g2 = R.region_to_shapely(square_region(0, 0, 2) + square_region(1, 1, 2), tol)
    assert g2.area == pytest.approx(7.0)


def test_hausdorff_and_boundary_distance():
    c1 = Point(0, 0).buffer(1.0, 512)
    c2 = Point(0, 0).buffer(1.3, 512)
    assert R.hausdorff(c1, c2, spacing=0.01) == pytest.approx(0.3, abs=1e-4)
    assert R.hausdorff(c1, c2) == pytest.approx(0.3, abs=1e-4)
    # boundary distance, not set distance: c1 is inside c2 yet far from its boundary
    pts = np.array([[0, 0], [1.3, 0], [0, -1.0]])
    assert R.max_boundary_distance(pts, c2) == pytest.approx(1.3, abs=1e-3)
    assert R.max_boundary_distance(pts[1:2], c2) < 1e-9
    # densified vs shapely's own densify on polylines
    sq = box(0, 0, 1, 1)
    tri = Polygon([(0, 0), (1, 0), (0, 1)])
    expect = float(shapely.hausdorff_distance(sq.boundary, tri.boundary, densify=0.001))
    assert R.hausdorff(sq, tri, spacing=0.001) == pytest.approx(expect, abs=1e-3)
    assert expect == pytest.approx(np.sqrt(0.5), abs=1e-3)
    # arrays of points and lists of rings are accepted
    ring = np.asarray(c1.exterior.coords)[:-1]
    assert R.hausdorff([ring], c1) < 1e-12


def test_winding_number():
    sq = np.array([(0, 0), (1, 0), (1, 1), (0, 1)], float)
    pts = np.array([(0.5, 0.5), (2, 0.5), (-1, 0.5), (0.5, 2), (0.5, -1)])
    assert list(R.winding_number(pts, sq)) == [1, 0, 0, 0, 0]
    assert list(R.winding_number(pts, sq[::-1])) == [-1, 0, 0, 0, 0]
    assert list(R.winding_number(pts, [sq, sq])) == [2, 0, 0, 0, 0]
    twice = np.vstack([sq, sq])                   # one loop going round twice
    assert R.winding_number(pts[:1], twice)[0] == 2
    rng = np.random.default_rng(2)
    poly = star(rng, (0, 0), 0.5, 2.0, 30)
    q = rng.uniform(-2, 2, (2000, 2))
    w = R.winding_number(q, poly)
    inside = shapely.contains_xy(Polygon(poly), q[:, 0], q[:, 1])
    assert np.array_equal(w != 0, inside)
    assert set(np.unique(w)) <= {0, 1}


def test_count_outer_and_holes():
    g = shapely.MultiPolygon([box(0, 0, 4, 4).difference(box(1, 1, 2, 2)).difference(box(2.5, 2.5, 3, 3)),
                              box(10, 10, 11, 11)])
    assert R.count_outer_and_holes(g) == (2, 2)
    assert R.count_outer_and_holes(g, min_area=0.3) == (2, 1)
    assert R.count_outer_and_holes(shapely.GeometryCollection()) == (0, 0)

"""Gauss maps of loops (Sec. 3.2, Defs. 3.2-3.4) against independent measurements.

Every property is checked on sampled geometry computed with ``tests/reference.py``
(its own Bernstein evaluation), not with morph's evaluation code:

- total turning of a loop is +2 pi (counter-clockwise outer) or -2 pi (hole), with the
  sign of the loop's shoelace area;
- every curve edge has monotone tangent angle (dense samples), |sweep| <= pi/2 within
  one quadrant, constant curvature sign matching ``sign``;
- vertex sweeps equal the measured tangent jumps, convex corners turn left (> 0);
- edges chain in position (end of one = start of the next) and in lifted angle;
- the curve edges are the loop (same exact area, midpoints on the loop);
- ``angle_param`` inverts the tangent angle; ``restrict`` keeps the angle range;
- ``split_monotone`` splits at a numerically found inflection and at the hodograph's
  axis crossings, not at a flat point; an interior cusp raises.

Glyphs come from both bundled fonts (TrueType quadratics, CFF cubics).
"""

import numpy as np
import pytest
pytest.importorskip("scipy")
from scipy.optimize import brentq

from morph import gauss
from morph import parse
from morph import piece as pc
from morph import moments as mo
from morph.errors import DegenerateCurveError

from tests.oracles import reference as R

TWO_PI = 2.0 * np.pi
GLYPHS = "SOgB8a&@"
FONTS = {"ttf": None, "cff": parse.cubic_test_font_path()}
ANGLE_EPS = 1e-9      # radians: agreement of angles computed two ways
SAMPLES = 257         # tangent samples per curve edge


def _wrap(a):
    """Angle wrapped into (-pi, pi]."""
    return np.angle(np.exp(1j * np.asarray(a, float)))


def _cross(a, b):
    return a[..., 0] * b[..., 1] - a[..., 1] * b[..., 0]


def _shoelace(poly):
    x, y = poly[:, 0], poly[:, 1]
    return 0.5 * float(np.sum(x * np.roll(y, -1) - np.roll(x, -1) * y))


def _tangent_angle_at(piece, t):
    d = R._tangent_dirs(piece, np.atleast_1d(float(t)))[0]
    return float(np.arctan2(d[1], d[0]))


def _end_angles(piece):
    """Tangent angles at t = 0 and t = 1 (reference evaluation, limit direction)."""
    prof = R.tangent_angle_profile(piece, 3)
    return prof[0], prof[-1]


def _glyph_loops():
    cases = []
    for label, font in FONTS.items():
        for ch in GLYPHS:
            for k, loop in enumerate(parse.glyph_region(ch, font).region):
                cases.append(pytest.param(loop, id="%s-%s-%d" % (label, ch, k)))
    return cases


def _conic_loops():
    return [
        pytest.param(pc.circle((3.0, -1.0), 2.0), id="circle"),
        pytest.param(pc.ellipse((0.0, 0.0), 5.0, 1.5, 0.3), id="ellipse"),
        pytest.param([pc.reverse(p) for p in reversed(pc.ellipse((1.0, 2.0), 1.0, 4.0, -1.1))],
                     id="ellipse-cw"),
    ]


LOOPS = _glyph_loops() + _conic_loops()


def _size(loop):
    pts = np.concatenate([pc.cartesian(p) for p in loop])
    return float(np.ptp(pts, axis=0).max())


# ------------------------------------------------------------------ whole loops

@pytest.mark.parametrize("loop", LOOPS)
def test_total_turning_is_two_pi_with_orientation(loop):
    edges = gauss.gauss_map(loop)
    area = _shoelace(np.concatenate(R.region_polylines([loop], 1e-3 * _size(loop))))
    assert area != 0.0
    assert gauss.total_turning(edges) == pytest.approx(np.sign(area) * TWO_PI, abs=1e-9)


@pytest.mark.parametrize("loop", LOOPS)
def test_curve_edges_monotone_in_one_quadrant(loop):
    edges = gauss.gauss_map(loop)
    size = _size(loop)
    for k, e in enumerate(edges):
        if e.kind != "curve":
            continue
        prof = R.tangent_angle_profile(e.piece, SAMPLES)
        # the lifted start angle is the measured one up to a multiple of 2 pi
        assert abs(_wrap(prof[0] - e.theta)) < ANGLE_EPS, k
        assert prof[-1] - prof[0] == pytest.approx(e.sweep, abs=ANGLE_EPS), k
        assert abs(e.sweep) <= np.pi / 2 + ANGLE_EPS, k
        # monotone: no sampled step against the sweep's direction
        steps = np.diff(prof)
        if e.sweep == 0.0:
            assert np.abs(prof - prof[0]).max() < 1e-8, k
        else:
            assert np.all(steps * np.sign(e.sweep) >= -1e-12), (k, steps.min(), steps.max())
            # within one quadrant (boundaries at multiples of pi/2 in lifted angles)
            q_lo = np.floor(e.lo / (np.pi / 2) + 1e-9)
            q_hi = np.ceil(e.hi / (np.pi / 2) - 1e-9)
            assert q_hi - q_lo <= 1, (k, e.lo, e.hi)
        # curvature sign constant and equal to the edge's sign (Def. 3.2)
        kv = R.curvature_sign_values(e.piece, SAMPLES)
        scale = np.abs(kv).max()
        if e.sweep != 0.0:
            assert np.all(kv * e.sign >= -1e-9 * scale), k
        else:
            assert scale <= 1e-9 * size ** 2 * 1e3, k


@pytest.mark.parametrize("loop", LOOPS)
def test_vertex_sweeps_are_tangent_jumps(loop):
    edges = gauss.gauss_map(loop)
    curves = [i for i, e in enumerate(edges) if e.kind == "curve"]
    n = len(edges)
    for idx, i in enumerate(curves):
        j = curves[(idx + 1) % len(curves)]
        between = [(i + m) % n for m in range(1, (j - i) % n or n)]
        jump = _wrap(_end_angles(edges[j].piece)[0] - _end_angles(edges[i].piece)[1])
        verts = [edges[m] for m in between]
        assert all(v.kind == "vertex" for v in verts)
        assert len(verts) <= 1, "two vertices in a row at edge %d" % i
        if verts:
            v = verts[0]
            assert v.sweep == pytest.approx(jump, abs=ANGLE_EPS), i
            assert 0 < abs(v.sweep) < np.pi
            # Def. 3.4: a left turn (convex corner) sweeps counter-clockwise
            t_in = R.bezier_eval(edges[i].piece, [1.0], 1)[1][0]
            t_out = R.bezier_eval(edges[j].piece, [0.0], 1)[1][0]
            if np.hypot(*t_in) > 0 and np.hypot(*t_out) > 0 and abs(jump) > 1e-6:
                assert np.sign(v.sweep) == np.sign(_cross(t_in, t_out)), i
        else:
            # tangent-continuous join: no vertex only when the jump is negligible
            assert abs(jump) < 1e-8, (i, jump)


@pytest.mark.parametrize("loop", LOOPS)
def test_edges_chain_in_position_and_angle(loop):
    edges = gauss.gauss_map(loop)
    size = _size(loop)
    n = len(edges)
    total = gauss.total_turning(edges)
    for i, e in enumerate(edges):
        nxt = edges[(i + 1) % n]
        end = R.bezier_eval(e.piece, [1.0])[0][0] if e.kind == "curve" else e.point
        start = R.bezier_eval(nxt.piece, [0.0])[0][0] if nxt.kind == "curve" else nxt.point
        assert np.hypot(*(end - start)) <= 1e-12 * size, i
        if e.kind == "curve":
            assert np.allclose(e.point, R.bezier_eval(e.piece, [0.0])[0][0], atol=1e-12 * size)
        # lifted angles continue from one edge to the next (wrapping once per loop)
        expect = nxt.theta + (total if i == n - 1 else 0.0)
        assert e.theta + e.sweep == pytest.approx(expect, abs=ANGLE_EPS), i


@pytest.mark.parametrize("loop", LOOPS)
def test_curve_edges_cover_the_loop(loop):
    edges = gauss.gauss_map(loop)
    curves = [e.piece for e in edges if e.kind == "curve"]
    assert mo.loop_area(curves) == pytest.approx(mo.loop_area(loop), rel=1e-12, abs=1e-9)
    size = _size(loop)
    mids = np.array([R.bezier_eval(c, [0.5])[0][0] for c in curves])
    # nearest original piece by dense samples, then the exact distance to it
    ss = np.linspace(0.0, 1.0, 513)
    near = np.array([np.min(np.hypot(*(R.bezier_eval(p, ss)[0][None] - mids[:, None]).T), axis=0)
                     for p in loop])
    owner = np.argmin(near, axis=0)
    for m, k in zip(mids, owner):
        assert R.point_curve_distance(m[None], loop[k], samples=257)[0][0] <= 1e-9 * size


@pytest.mark.parametrize("loop", LOOPS)
def test_angle_param_inverts_tangent_angle(loop):
    edges = gauss.gauss_map(loop)
    fr = np.linspace(0.0, 1.0, 11)
    for k, e in enumerate(edges):
        if e.kind != "curve" or e.sweep == 0.0:
            continue
        for f in fr:
            th = e.theta + f * e.sweep
            t = gauss.angle_param(e.piece, th)
            assert 0.0 <= t <= 1.0
            got = _tangent_angle_at(e.piece, t)
            assert abs(_wrap(got - th)) < 1e-8, (k, f, got, th)
        # round trip through sampled parameters where the angle moves fast enough
        ts = np.linspace(0.05, 0.95, 7)
        prof = R.tangent_angle_profile(e.piece, 1001)
        th_s = e.theta + np.interp(ts, np.linspace(0, 1, 1001), prof - prof[0])
        _, d1, d2 = R.bezier_eval(e.piece, ts, 2)
        rate = np.abs(_cross(d1, d2)) / np.sum(d1 * d1, axis=1)   # dtheta/dt
        for t0, th, r in zip(ts, th_s, rate):
            t = gauss.angle_param(e.piece, th)
            if r > 1e-2:
                assert t == pytest.approx(t0, abs=1e-5 / r + 1e-9), (k, t0, t)


@pytest.mark.parametrize("loop", LOOPS[::3])
def test_restrict_keeps_the_angle_range(loop):
    edges = gauss.gauss_map(loop)
    for k, e in enumerate(edges):
        if e.kind != "curve" or abs(e.sweep) < 1e-3:
            continue
        lo = e.lo + 0.2 * (e.hi - e.lo)
        hi = e.lo + 0.7 * (e.hi - e.lo)
        sub, point, th, sweep = gauss.restrict(e, lo, hi)
        prof = R.tangent_angle_profile(sub, 33)
        assert abs(_wrap(prof[0] - th)) < 1e-8, k
        assert prof[-1] - prof[0] == pytest.approx(sweep, abs=1e-8), k
        assert abs(sweep) == pytest.approx(hi - lo, abs=1e-12)
        assert np.sign(sweep) == e.sign
        assert np.allclose(point, R.bezier_eval(sub, [0.0])[0][0])
        # the restricted piece lies on the edge
        d = R.point_curve_distance(R.bezier_eval(sub, np.linspace(0, 1, 9))[0], e.piece)[0]
        assert d.max() <= 1e-9 * _size(loop)


# ------------------------------------------------------------ split_monotone

def _curvature(piece):
    def f(t):
        _, d1, d2 = R.bezier_eval(piece, [t], 2)
        return float(_cross(d1[0], d2[0]))
    return f


def _junctions(parts):
    return np.array([R.bezier_eval(p, [1.0])[0][0] for p in parts[:-1]])


def _axis_crossings(piece):
    """Interior parameters where x'(t) or y'(t) changes sign (dense sampling + brentq)."""
    out = []
    ts = np.linspace(0, 1, 4001)
    for axis in (0, 1):
        def g(t, axis=axis):
            return float(R.bezier_eval(piece, [t], 1)[1][0, axis])
        v = R.bezier_eval(piece, ts, 1)[1][:, axis]
        out.extend(ts[1:-1][v[1:-1] == 0.0])
        for k in np.nonzero(v[:-1] * v[1:] < 0)[0]:
            out.append(brentq(g, ts[k], ts[k + 1], xtol=1e-15))
    return sorted(out)


INFLECTED = {
    "cubic": pc.cubic((0.0, 0.0), (1.0, 2.0), (2.5, -1.5), (4.0, 0.5)),
    "cubic-steep": pc.cubic((0.0, 0.0), (0.2, 3.0), (1.0, -2.0), (1.3, 1.0)),
    "rational-cubic": pc.from_points([(0.0, 0.0), (1.0, 2.0), (2.5, -1.5), (4.0, 0.5)],
                                     [1.0, 2.0, 0.5, 1.0]),
}


@pytest.mark.parametrize("name", sorted(INFLECTED))
def test_split_monotone_splits_at_the_inflection(name):
    piece = INFLECTED[name]
    f = _curvature(piece)
    ts = np.linspace(0, 1, 2001)
    vals = np.array([f(t) for t in ts])
    ks = np.nonzero(vals[:-1] * vals[1:] < 0)[0]
    assert len(ks) == 1, "test curve must have exactly one inflection"
    t_star = brentq(f, ts[ks[0]], ts[ks[0] + 1], xtol=1e-15)
    infl = _inflection_params(piece)
    assert len(infl) == 1 and infl[0] == pytest.approx(t_star, abs=1e-9)
    expected = sorted([t_star] + _axis_crossings(piece))
    parts = gauss.split_monotone(piece)
    assert len(parts) == len(expected) + 1
    want = R.bezier_eval(piece, expected)[0]
    got = _junctions(parts)
    assert np.allclose(got, want, atol=1e-9)
    # every part has one curvature sign and turns by at most pi/2
    signs = []
    for p in parts:
        kv = R.curvature_sign_values(p, 201)
        s = np.sign(kv[100])
        assert np.all(kv * s >= -1e-9 * np.abs(kv).max())
        signs.append(s)
        prof = R.tangent_angle_profile(p, 201)
        assert abs(prof[-1] - prof[0]) <= np.pi / 2 + 1e-12
    # the sign flips exactly at the inflection junction
    k_star = int(np.argmin(np.hypot(*(got - R.bezier_eval(piece, [t_star])[0][0]).T)))
    assert signs[k_star] == -signs[k_star + 1]


def test_flat_point_is_not_an_inflection():
    # x = t, y = (2t - 1)^4: curvature x'y'' - x''y' = 48 (2t - 1)^2 >= 0, double root
    piece = pc.from_points([(i / 4.0, (-1.0) ** i) for i in range(5)])
    assert _inflection_params(piece).size == 0
    parts = gauss.split_monotone(piece)
    # only the axis crossing of y' at t = 1/2 (the flat point itself) splits
    assert len(parts) == 2
    assert np.allclose(_junctions(parts), [[0.5, 0.0]], atol=1e-12)


def test_interior_cusp_is_split_off_and_carried_as_a_corner():
    # P'(1/2) = 0: both hodograph components vanish there, so split_monotone cuts at
    # the cusp; the loop turns through pi there, a corner of the Gauss map
    cusp = pc.cubic((0.0, 0.0), (1.0, 1.0), (0.0, 1.0), (1.0, 0.0))
    parts = gauss.split_monotone(cusp)
    assert np.allclose(_junctions(parts), R.bezier_eval(cusp, [0.5])[0], atol=1e-12)
    loop = [cusp, pc.line((1.0, 0.0), (0.5, -1.0)), pc.line((0.5, -1.0), (0.0, 0.0))]
    edges = gauss.gauss_map(loop)
    area = mo.loop_area(loop)
    assert gauss.total_turning(edges) == pytest.approx(np.sign(area) * TWO_PI)
    assert any(abs(abs(e.sweep) - np.pi) < 1e-6 for e in edges if e.kind == "vertex")


def test_spike_is_a_corner_of_pi():
    # a loop that reverses direction (a zero-width spike) turns through +pi there
    loop = [pc.line((0.0, 0.0), (2.0, 0.0)), pc.line((2.0, 0.0), (1.0, 0.0)),
            pc.line((1.0, 0.0), (1.0, 1.0)), pc.line((1.0, 1.0), (0.0, 0.0))]
    edges = gauss.gauss_map(loop)
    assert gauss.total_turning(edges) == pytest.approx(TWO_PI)
    assert [e.sweep for e in edges if e.kind == "vertex"][0] == pytest.approx(np.pi)


@pytest.mark.parametrize("mirror", [1.0, -1.0])
def test_the_tip_of_a_part_of_zero_width_turns_as_the_traced_set_has_it(mirror):
    """Where a loop runs back along itself, the tip turns +pi when it sticks out of
    the loop and -pi when it is cut into it (times the loop's orientation: the
    mirror image, a clockwise loop, turns the other way), read from the winding
    number beyond the tip; a part of zero width crossing the rest of its loop
    then turns the loop twice, which the convolution refuses (it was summed with
    its tip's disk missing)."""
    def loop(points):
        pts = [(mirror * x, y) for x, y in points]
        return [pc.line(pts[i], pts[(i + 1) % len(pts)]) for i in range(len(pts))]

    def tip_turns(points):
        return [e.sweep / np.pi for e in gauss.gauss_map(loop(points))
                if e.kind == "vertex" and abs(abs(e.sweep) - np.pi) < 1e-9]

    spike = [(0, 0), (10, 0), (10, 5), (14, 5), (10, 5), (10, 10), (0, 10)]
    slit = [(0, 0), (10, 0), (10, 5), (6, 5), (10, 5), (10, 10), (0, 10)]
    assert tip_turns(spike) == [pytest.approx(mirror)]
    assert tip_turns(slit) == [pytest.approx(-mirror)]
    crossing = [(8, 10), (0, 1), (9, 10), (2, 3), (9, 4)]
    assert gauss.total_turning(gauss.gauss_map(loop(crossing))) == pytest.approx(
        mirror * 2 * TWO_PI)



def test_a_closed_path_traced_out_and_back_turns_once_at_any_angle():
    """A closed path that runs on smoothly through its start, traced out and back
    (:func:`morph.stroke.path_loop`, given as a plain loop: no ``traced`` flag) has
    both tips at that point, where the trace goes on through them: a probe beyond
    either lies on the trace itself.  The loop has area 0 and winds 0 round every
    point off its trace, so both tips stick out (+pi) and it turns once, at every
    angle and scale (the probe read one tip as -pi at about one angle in four)."""
    from morph.stroke import path_loop
    from tests.helpers import pencil_path

    rng = np.random.default_rng(7)
    for _ in range(40):
        path = pencil_path(rng.uniform(0, 360), float(np.exp(rng.uniform(-3, 5))))
        edges = gauss.gauss_map(path_loop(path))
        assert gauss.total_turning(edges) == pytest.approx(TWO_PI)
        tips = [e.sweep for e in edges if e.kind == "vertex" and abs(e.sweep) > 3.0]
        assert tips == [pytest.approx(np.pi)] * 2

def test_a_centre_line_running_back_over_itself_is_refused_not_summed_without_a_cap():
    """A stroke's centre line traced out and back whose path itself turns back
    ((0, 0) -> (10, 0) -> (5, 0)): its inner tip lies on its own trace, so the
    loop turns twice and the convolution refuses it (the turns used to be chosen to
    add up to one turn, and the sum lacked a cap: area 20.0 for 20 + pi); a plain
    centre line still sums to its capsule."""
    from morph.errors import SelfCrossingError
    from morph.minkowski import minkowski_sum

    disk = [pc.circle((0.0, 0.0), 1.0)]
    path = [pc.line((0, 0), (10, 0)), pc.line((10, 0), (5, 0))]
    with pytest.raises(SelfCrossingError, match="loop 0 turns 2 times"):
        minkowski_sum([path + [pc.reverse(p) for p in reversed(path)]], disk, 1e-3)
    line = [pc.line((0, 0), (10, 0)), pc.line((10, 0), (0, 0))]
    assert mo.region_area(minkowski_sum([line], disk, 1e-3)) == pytest.approx(20 + np.pi,
                                                                              abs=1e-2)


def test_convex_and_concave_corners():
    # an L-shaped hexagon: five left turns of +pi/2 and one right turn of -pi/2
    pts = [(0, 0), (2, 0), (2, 1), (1, 1), (1, 2), (0, 2)]
    loop = [pc.line(pts[i], pts[(i + 1) % 6]) for i in range(6)]
    edges = gauss.gauss_map(loop)
    sweeps = [e.sweep for e in edges if e.kind == "vertex"]
    assert sorted(np.round(np.array(sweeps) / (np.pi / 2)).astype(int)) == [-1, 1, 1, 1, 1, 1]
    assert all(e.sweep == 0.0 for e in edges if e.kind == "curve")
    assert gauss.total_turning(edges) == pytest.approx(TWO_PI)


@pytest.mark.parametrize("turn", [1e-3, 1e-6, 1e-9])
def test_small_corners_are_vertices(turn):
    # a quadrilateral whose corner at (2, 0) turns by only `turn` radians: the Gauss map
    # must keep it as a vertex (only turns below angle_tol = 1e-10 are joins)
    p1 = (2.0 + 2.0 * np.cos(turn), 2.0 * np.sin(turn))
    pts = [(0.0, 0.0), (2.0, 0.0), p1, (0.0, 3.0)]
    loop = [pc.line(pts[i], pts[(i + 1) % 4]) for i in range(4)]
    edges = gauss.gauss_map(loop)
    verts = [e for e in edges if e.kind == "vertex"]
    assert len(verts) == 4
    small = min(verts, key=lambda e: abs(e.sweep))
    assert small.sweep == pytest.approx(turn, rel=1e-6)
    assert np.allclose(small.point, (2.0, 0.0))
    assert gauss.total_turning(edges) == pytest.approx(TWO_PI)


# ------------------------------------------------------------------ cusps (turns of pi)

def _polyline_loop(points):
    return [pc.line(points[i], points[(i + 1) % len(points)]) for i in range(len(points))]


@pytest.mark.parametrize("points, cusp", [
    # a spike out of the top of a square: the way back is on the left, +pi
    ([(0, 0), (10, 0), (10, 10), (6, 10), (5, 20), (4, 10), (0, 10)], None),
    # zero-width spike and zero-width slit: decided by the total turning
    ([(0, 0), (10, 0), (10, 10), (5, 10), (5, 20), (5, 10), (0, 10)], 1.0),
    ([(0, 0), (10, 0), (10, 10), (5, 10), (5, 3), (5, 10), (0, 10)], -1.0),
])
def test_cusps_are_corners_of_plus_or_minus_pi(points, cusp):
    edges = gauss.gauss_map(_polyline_loop(points))
    assert gauss.total_turning(edges) == pytest.approx(2 * np.pi)
    if cusp is not None:
        sweeps = [e.sweep / np.pi for e in edges if e.kind == "vertex"]
        assert cusp in [pytest.approx(s) for s in sweeps]


def test_open_path_forward_and_back_turns_plus_pi_at_both_ends():
    c = pc.cubic((0, 0), (30, 40), (60, -40), (100, 0))
    edges = gauss.gauss_map([c, pc.reverse(c)])
    ends = [e.sweep for e in edges if e.kind == "vertex" and abs(abs(e.sweep) - np.pi) < 1e-6]
    assert ends == [pytest.approx(np.pi), pytest.approx(np.pi)]
    assert gauss.total_turning(edges) == pytest.approx(2 * np.pi)


@pytest.mark.parametrize("offset", [(0.0, 0.0), (2296.554, -3243.444), (-4092.47, 803.324),
                                    (1e5 + 0.3, -7e4 - 0.7)])
def test_short_line_forward_and_back_turns_plus_pi_anywhere(offset):
    """A 2-unit line traced back on itself, far from the origin: both ends turn +pi
    (the side of a cusp is decided about the cusp point, not on absolute
    coordinates, whose rounding reads as a turn to a random side)."""
    a, b = np.add((141.0, 785.0), offset), np.add((139.0, 785.0), offset)
    edges = gauss.gauss_map([pc.line(a, b), pc.line(b, a)])
    ends = [e.sweep for e in edges if e.kind == "vertex" and abs(abs(e.sweep) - np.pi) < 1e-6]
    assert ends == [pytest.approx(np.pi), pytest.approx(np.pi)]
    assert abs(mo.loop_area([pc.line(a, b), pc.line(b, a)])) == 0.0


def test_zero_end_derivative_uses_the_limit_tangent():
    # a control point on its own end point: the tangent there is P2 - P0's direction
    c = pc.cubic((0, 0), (0, 0), (10, 10), (20, 0))
    edges = gauss.gauss_map([c, pc.line((20, 0), (0, 0))])
    first = edges[0]
    assert first.theta == pytest.approx(np.pi / 4)
    # and the angle solver finds interior points, not t = 0, for other angles
    t = gauss.angle_param(first.piece, first.theta + 0.5 * first.sweep)
    assert 0.05 < t < 0.95


# ------------------------------------------------------------------------ batched forms

def _random_pieces(rng, n):
    out = []
    for k in range(n):
        deg = 1 + k % 4
        p = rng.uniform(-3, 3, (deg + 1, 2))
        w = rng.uniform(0.3, 2.0, deg + 1) if k % 3 == 0 else None
        out.append(pc.from_points(p, w))
    return out


def _all_glyph_pieces():
    return [np.asarray(p, float) for font in FONTS.values() for ch in GLYPHS
            for loop in parse.glyph_region(ch, font).region for p in loop]


def test_split_monotone_many_matches_piece_by_piece():
    """The batched split (all pieces of one degree together) gives the parts of the
    per-piece one (which skips root finding when no coefficient changes sign)."""
    rng = np.random.default_rng(3)
    pieces = _all_glyph_pieces() + _random_pieces(rng, 200)
    many = gauss.split_monotone_many(pieces, check=False)
    for p, parts in zip(pieces, many):
        try:
            single = gauss.split_monotone(p)
        except DegenerateCurveError:
            continue
        assert len(single) == len(parts)
        for a, b in zip(single, parts):
            assert np.allclose(a, b, atol=1e-12 * max(1.0, np.abs(a).max()))


def test_quick_monotone_test_never_hides_a_split():
    rng = np.random.default_rng(4)
    pieces = _all_glyph_pieces() + _random_pieces(rng, 300)
    params = gauss._split_params_many(pieces)
    for p, ts in zip(pieces, params):
        if ts.size:
            assert gauss._may_split(p)


def test_angle_params_batched_over_edges_of_mixed_degree():
    """angle_params on the tangent numerators of all curve edges of several loops,
    elevated to one degree, inverts the tangent angle (reference evaluation)."""
    edges = [e for ch in "Sg&" for loop in parse.glyph_region(ch, FONTS["cff"]).region
             for e in gauss.gauss_map(loop) if e.kind == "curve" and e.sweep != 0.0]
    edges += [e for e in gauss.gauss_map(pc.ellipse((0.0, 0.0), 5.0, 1.5, 0.3))]
    hs = [pc.tangent_numerator(e.piece) for e in edges]
    deg = max(len(h) for h in hs) - 1
    from morph import bernstein as bz
    h = np.array([bz.to_degree(x, deg) for x in hs])
    rng = np.random.default_rng(5)
    f = rng.uniform(0, 1, len(edges))
    theta = np.array([e.theta + x * e.sweep for e, x in zip(edges, f)])
    t = gauss.angle_params(h, theta)
    for e, tk, th in zip(edges, t, theta):
        assert abs(_wrap(_tangent_angle_at(e.piece, tk) - th)) < 1e-8
        assert tk == pytest.approx(gauss.angle_param(e.piece, th), abs=1e-12)


@pytest.mark.parametrize("eps", [2.4e-4, 1e-6])
def test_a_cusp_whose_sides_cross_a_hair_from_its_point_turns_by_where_they_run(eps):
    """A wedge tip whose end tangents turn by +(pi - eps) (the way out a hair left of
    the way in) while the way out crosses to the right of the way in at t ~ 5 eps and
    runs there (bootstrap-icons bluesky's notch, rounded SVG coordinates): the tip
    turns by -(pi + eps), the loop's total turning is -2 pi as for the clockwise
    wedge it is, not 0 (the tip read as a convex corner by its tangents)."""
    c_in = pc.quadratic((-1.0, 0.1), (-0.5, 0.0), (0.0, 0.0))          # y = 0.1 x^2
    c_out = pc.quadratic((0.0, 0.0), (-0.5, 0.5 * eps), (-1.0, -0.1))
    loop = [c_in, c_out, pc.line((-1.0, -0.1), (-1.0, 0.1))]
    edges = gauss.gauss_map(loop)
    tip = [e for e in edges if e.kind == "vertex" and np.allclose(e.point, 0.0)]
    assert len(tip) == 1 and tip[0].sweep == pytest.approx(-(np.pi + eps), abs=1e-9)
    assert gauss.total_turning(edges) == pytest.approx(-2 * np.pi, abs=1e-9)


def _inflection_params(piece):
    """Interior parameters where x'y'' - x''y' changes sign (Def. 3.2)."""
    return gauss._split_params_many([np.asarray(piece, float)], axes=False)[0]


def test_repeated_rows_are_solved_once_to_the_same_bits():
    """angle_params solves each distinct row once (_solved_once): the roots equal
    solve_bracketed row by row, to the bit, with rows repeated, rows differing in
    one bit and a -0.0 against a 0.0 kept apart."""
    from morph import bernstein as bz
    from morph.gauss import _solved_once

    rng = np.random.default_rng(3)
    base = np.stack([rng.uniform(0.1, 1, 50), rng.uniform(-1, 1, 50),
                     -rng.uniform(0.1, 1, 50)], axis=1)
    rows = base[rng.integers(0, 50, 300)]
    near = rows[:5].copy()
    near[:, 1] = np.nextafter(near[:, 1], 2.0)          # one bit apart
    signed = np.array([[1.0, 0.0, -1.0], [1.0, -0.0, -1.0]])
    f = np.concatenate([rows, near, signed])
    got = _solved_once(f)
    want = np.array([bz.solve_bracketed(r[None])[0] for r in f])
    assert np.array_equal(got, want)
    # the comparison can fail: a root displaced by one ulp is seen
    assert not np.array_equal(np.nextafter(got, 2.0), want)

"""Rational Bézier pieces against sampled values, finite differences and exact conics."""

import numpy as np
import pytest
pytest.importorskip("hypothesis")
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.errors import DegenerateCurveError

T = np.linspace(0.0, 1.0, 101)


@st.composite
def rational_pieces(draw, max_degree=5):
    n = draw(st.integers(1, max_degree))
    pts = draw(arrays(float, (n + 1, 2), elements=st.floats(-5, 5)))
    w = draw(arrays(float, (n + 1,), elements=st.floats(0.25, 4.0)))
    return pc.from_points(pts, w)


def test_from_points_and_cartesian_round_trip():
    pts = np.array([[0.0, 0.0], [1.0, 2.0], [3.0, -1.0]])
    p = pc.from_points(pts, [1.0, 0.5, 2.0])
    assert np.allclose(pc.cartesian(p), pts)
    assert not pc.is_polynomial(p)
    assert pc.is_polynomial(pc.quadratic(*pts))
    with pytest.raises(ValueError):
        pc.from_points(pts, [1.0, -1.0, 1.0])


def test_cubic_evaluate_matches_formula():
    p0, p1, p2, p3 = np.array([[0.0, 0.0], [1.0, 3.0], [4.0, 3.0], [5.0, 0.0]])
    c = pc.cubic(p0, p1, p2, p3)
    t = T[:, None]
    expect = (1 - t) ** 3 * p0 + 3 * t * (1 - t) ** 2 * p1 + 3 * t ** 2 * (1 - t) * p2 + t ** 3 * p3
    assert np.allclose(pc.evaluate(c, T), expect, atol=1e-14)
    assert np.array_equal(pc.start(c), p0) and np.array_equal(pc.end(c), p3)


def test_rational_quadratic_matches_formula():
    pts = np.array([[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]])
    w = np.array([1.0, np.sqrt(0.5), 1.0])
    p = pc.from_points(pts, w)
    b = np.column_stack([(1 - T) ** 2, 2 * T * (1 - T), T ** 2])
    expect = (b * w) @ pts / (b @ w)[:, None]
    assert np.allclose(pc.evaluate(p, T), expect, atol=1e-14)
    # a quarter circle: every point at distance 1
    assert np.allclose(np.hypot(*pc.evaluate(p, T).T), 1.0, atol=1e-14)


# (derivative, its antiderivative, step, parameters): P' by differences of P, P'' of P'
DERIVATIVES = [(pc.derivative, pc.evaluate, 1e-6, np.linspace(0.02, 0.98, 17)),
               (pc.second_derivative, pc.derivative, 1e-4, np.linspace(0.05, 0.95, 9))]


@pytest.mark.parametrize("deriv, lower, h, t", DERIVATIVES, ids=["first", "second"])
@settings(max_examples=40)
@given(p=rational_pieces())
def test_derivatives_match_finite_differences(deriv, lower, h, t, p):
    fd = (lower(p, t + h) - lower(p, t - h)) / (2 * h)
    scale = 1 + np.abs(fd).max()
    assert np.allclose(deriv(p, t), fd, atol=1e-4 * scale)


@given(rational_pieces())
def test_tangent_numerator_is_parallel_to_derivative(p):
    t = np.linspace(0.0, 1.0, 13)
    d = pc.derivative(p, t)
    from morph import bernstein as bz
    h = bz.evaluate(pc.tangent_numerator(p), t)
    cross = d[:, 0] * h[:, 1] - d[:, 1] * h[:, 0]
    dot = (d * h).sum(axis=1)
    scale = np.hypot(*d.T) * np.hypot(*h.T) + 1e-12
    assert np.all(np.abs(cross) <= 1e-8 * scale + 1e-9)
    # the direction is compared where P' does not vanish (a control point on its own
    # end point makes P'(0) = 0; the tangent numerator then has the limit direction)
    moving = np.hypot(*d.T) > 1e-9 * np.hypot(*d.T).max()
    assert np.all(dot[moving] >= -1e-9 * scale[moving])


@given(rational_pieces(), st.floats(0.05, 0.95))
def test_split_reproduces_curve(p, t):
    left, right = pc.split(p, t)
    u = np.linspace(0, 1, 21)
    assert np.allclose(pc.evaluate(left, u), pc.evaluate(p, t * u), atol=1e-9)
    assert np.allclose(pc.evaluate(right, u), pc.evaluate(p, t + (1 - t) * u), atol=1e-9)
    assert np.array_equal(left[-1], right[0])


@given(rational_pieces(), st.floats(0.0, 0.4), st.floats(0.6, 1.0))
def test_subsegment_reproduces_curve(p, t0, t1):
    u = np.linspace(0, 1, 21)
    assert np.allclose(pc.evaluate(pc.subsegment(p, t0, t1), u),
                       pc.evaluate(p, t0 + (t1 - t0) * u), atol=1e-8)


@given(rational_pieces(), st.integers(1, 4))
def test_elevate_same_curve(p, r):
    e = pc.elevate(p, r)
    assert len(e) == len(p) + r
    assert np.allclose(pc.evaluate(e, T), pc.evaluate(p, T), atol=1e-9)


@given(rational_pieces())
def test_reverse(p):
    assert np.allclose(pc.evaluate(pc.reverse(p), T), pc.evaluate(p, 1 - T), atol=1e-12)


@pytest.mark.parametrize("rx, ry, rot, th0, dth", [
    (1.0, 1.0, 0.0, 0.0, 2 * np.pi),
    (3.0, 1.5, 0.4, 0.3, 2.5),
    (2.0, 5.0, -1.0, 1.0, -4.0),
    (1.0, 0.2, 2.0, -0.5, 0.3),
])
def test_ellipse_arc_points_on_ellipse_and_tangent_continuous(rx, ry, rot, th0, dth):
    center = np.array([1.5, -2.0])
    arcs = pc.ellipse_arc(center, rx, ry, rot, th0, dth)
    c, s = np.cos(rot), np.sin(rot)
    for a in arcs:
        assert len(a) == 3 and np.all(a[:, 2] > 0)
        q = (pc.evaluate(a, T) - center) @ np.array([[c, -s], [s, c]])  # rotate back
        assert np.allclose((q[:, 0] / rx) ** 2 + (q[:, 1] / ry) ** 2, 1.0, atol=1e-13)
    def on(th):
        return center + np.array([[c, -s], [s, c]]) @ [rx * np.cos(th), ry * np.sin(th)]
    assert np.allclose(pc.start(arcs[0]), on(th0), atol=1e-13)
    assert np.allclose(pc.end(arcs[-1]), on(th0 + dth), atol=1e-13)
    for a, b in zip(arcs, arcs[1:]):
        assert np.allclose(pc.end(a), pc.start(b), atol=1e-14)
        ta = pc.end_tangents(a)[1]
        tb = pc.end_tangents(b)[0]
        assert np.allclose(ta, tb, atol=1e-12)
    # the sweep direction follows the sign of dth
    area = float(np.sum(mo.area_terms(arcs)))
    e, s0 = pc.end(arcs[-1]), pc.start(arcs[0])
    assert np.sign(area + 0.5 * (e[0] * s0[1] - e[1] * s0[0])) == np.sign(dth)


@given(rational_pieces())
def test_transform_is_affine_map_of_points(p):
    m = np.array([[1.5, -0.3, 2.0], [0.4, 0.8, -1.0]])
    q = pc.transform(p, m)
    expect = pc.evaluate(p, T) @ m[:, :2].T + m[:, 2]
    assert np.allclose(pc.evaluate(q, T), expect, atol=1e-9)
    assert np.allclose(pc.evaluate(pc.translate(p, (1.0, -2.0)), T),
                       pc.evaluate(p, T) + [1.0, -2.0], atol=1e-12)


@given(rational_pieces())
def test_bbox_contains_curve(p):
    box = pc.bbox(p)
    pts = pc.evaluate(p, T)
    assert np.all(pts >= box[:2] - 1e-12) and np.all(pts <= box[2:] + 1e-12)


@settings(max_examples=30)
@given(rational_pieces(max_degree=4), st.sampled_from([1e-1, 1e-2, 1e-3]))
def test_flatten_within_tol(p, tol):
    pts, params = pl.flatten(p, tol)
    assert params[0] == 0.0 and params[-1] == 1.0 and np.all(np.diff(params) > 0)
    # curve points between consecutive params are within tol of the chord
    for a, b, ta, tb in zip(pts[:-1], pts[1:], params[:-1], params[1:]):
        q = pc.evaluate(p, np.linspace(ta, tb, 9))
        d = b - a
        L2 = d @ d
        u = np.clip((q - a) @ d / L2, 0, 1) if L2 > 0 else np.zeros(len(q))
        dist = np.hypot(*(q - (a + u[:, None] * d)).T)
        assert dist.max() <= tol * (1 + 1e-9) + 1e-12


def test_end_tangents_with_repeated_control_point_and_degenerate():
    c = pc.cubic((0, 0), (0, 0), (1, 1), (2, 0))
    t0, t1 = pc.end_tangents(c)
    assert np.allclose(t0, np.array([1, 1]) / np.sqrt(2))
    assert np.allclose(t1, np.array([1, -1]) / np.sqrt(2))
    with pytest.raises(DegenerateCurveError):
        pc.end_tangents(pc.cubic((1, 1), (1, 1), (1, 1), (1, 1)))


def test_with_endpoints_moves_only_ends():
    p = pc.from_points([[0, 0], [1, 1], [2, 0]], [1.0, 2.0, 0.5])
    q = pc.with_endpoints(p, (0.5, 0.5), (3.0, 1.0))
    assert np.allclose(pc.start(q), [0.5, 0.5]) and np.allclose(pc.end(q), [3.0, 1.0])
    assert np.array_equal(q[1], p[1]) and np.array_equal(q[:, 2], p[:, 2])


def test_kind_groups_partition_pieces_by_degree_and_kind():
    """Every piece in exactly one group, with its own control points, of its degree
    and kind (an arc is rational, a weight-2 everywhere quadratic is polynomial)."""
    pieces = [pc.line((0, 0), (1, 0)), pc.circle((0, 0), 1.0)[0], pc.quadratic((0, 0), (1, 1), (2, 0)),
              2.0 * pc.quadratic((0, 0), (1, 2), (2, 0)), pc.cubic((0, 0), (1, 1), (2, 1), (3, 0)),
              pc.circle((5, 5), 2.0)[1]]
    seen = []
    for ks, stack, rational in pc.kind_groups(pieces):
        assert len({len(pieces[k]) for k in ks}) == 1
        for k, h in zip(ks, stack):
            assert np.array_equal(h, pieces[k])
            assert rational == (not pc.is_polynomial(pieces[k]))
        seen += list(ks)
    assert sorted(seen) == list(range(len(pieces)))
    assert pc.kind_groups([]) == []


# ------------------------------------------ closest points and the distance certificate

def _random_rational_stack(rng, k, n):
    pts = rng.uniform(-1, 1, (k, n + 1, 2))
    w = rng.uniform(0.3, 3.0, (k, n + 1, 1))
    return np.concatenate([pts * w, w], axis=2)


def _plain_eval(c, t):
    """R(t) of one homogeneous piece by a plain Bernstein sum (math.comb)."""
    import math

    n = len(c) - 1
    h = sum(math.comb(n, i) * t[:, None] ** i * (1 - t[:, None]) ** (n - i) * c[i]
            for i in range(n + 1))
    return h[:, :2] / h[:, 2:]


def test_jet2_power_many_matches_de_casteljau_jets():
    rng = np.random.default_rng(3)
    for n in (2, 3, 7, 12):
        c = _random_rational_stack(rng, 4, n)
        s = rng.uniform(0, 1, (4, 9))
        for a, b in zip(pc.jet2_many(c, s), pc.jet2_power_many(c, s)):
            assert np.allclose(a, b, rtol=1e-9, atol=1e-9 * (1 + np.abs(a).max()))




def _mixed_pieces(rng, k):
    """k pieces of degrees 1-4 in random order, some rational."""
    out = []
    for n in rng.integers(1, 5, k):
        pts = rng.uniform(-3, 3, (n + 1, 2))
        w = rng.uniform(0.5, 2.0, n + 1) if rng.random() < 0.5 else None
        out.append(pc.from_points(pts, w))
    return out


def test_by_degree_groups_each_piece_once_in_first_seen_order():
    """The vectorised grouping against a plain dict built piece by piece: the same
    keys in the same order (first piece of each degree), the same indices."""
    rng = np.random.default_rng(3)
    for k in (0, 1, 7, 300):
        pieces = _mixed_pieces(rng, k)
        plain = {}
        for i, p in enumerate(pieces):
            plain.setdefault(len(p), []).append(i)
        got = pc.by_degree(pieces)
        assert list(got) == list(plain)
        assert all(list(got[n]) == plain[n] for n in plain)
    same = [pc.line((0, 0), (1, k)) for k in range(5)]
    assert list(pc.by_degree(same)[2]) == list(range(5))


def test_packed_pieces_match_the_list():
    """A Pieces holds the same control points in the same order as the list it was
    made of; take() picks rows by index (repeats allowed); the batched functions
    give the same bits on the packed form and on the list; subsegments packed or
    not agree with the one-piece subsegment."""
    rng = np.random.default_rng(4)
    pieces = _mixed_pieces(rng, 200)
    packed = pc.Pieces.of(pieces)
    assert len(packed) == len(pieces) and pc.Pieces.of(packed) is packed
    assert all(np.array_equal(a, b) for a, b in zip(packed, pieces))
    idx = rng.integers(0, len(pieces), 120)
    sub = packed.take(idx)
    assert all(np.array_equal(sub[j], pieces[i]) for j, i in enumerate(idx))
    for f in (pc.bboxes, pc.length_bounds, pc.stack):
        assert np.array_equal(f(packed), f(pieces))
    for a, b in zip(pc.end_points(packed), pc.end_points(pieces)):
        assert np.array_equal(a, b)
    t0, t1 = rng.uniform(0, 1, len(idx)), rng.uniform(0, 1, len(idx))
    one = [pc.subsegment(pieces[i], a, b) for i, a, b in zip(idx, t0, t1)]
    for got in (pc.subsegments(pieces, idx, t0, t1), pc.subsegments(packed, idx, t0, t1),
                pc.subsegments(packed, idx, t0, t1, packed=True)):
        assert len(got) == len(one)
        assert all(np.allclose(a, b, rtol=0, atol=1e-12) for a, b in zip(got, one))
    # a displaced row is seen (the comparison can fail)
    moved = [p.copy() for p in pieces]
    moved[17][0, 0] += 1e-9
    assert not np.array_equal(pc.end_points(pc.Pieces.of(moved))[0], pc.end_points(packed)[0])


@pytest.mark.parametrize("split", [0, 1, 37, 150, 200])
def test_pieces_then_groups_as_the_whole_list(split):
    """Pieces.of(a).then(b) has the groups, indices and stacks of Pieces.of(a + b):
    the degrees in the order of their first piece, a degree only b has after a's,
    every stack to the bit (what the Gauss map of a packed region with a nib
    takes)."""
    rng = np.random.default_rng(9)
    pieces = _mixed_pieces(rng, 200)
    more = pieces[split:]
    head = pieces[:split]
    got = pc.Pieces.of(head).then(more)
    want = pc.Pieces.of(pieces)
    assert len(got) == len(want) and len(got.groups) == len(want.groups)
    for (ka, ha), (kb, hb) in zip(got.groups, want.groups):
        assert np.array_equal(ka, kb) and np.array_equal(ha, hb)
    # only lines first, then a curve: the curve's degree comes after
    lines = [p for p in pieces if len(p) == 2][:5]
    curves = [p for p in pieces if len(p) == 4][:2]
    mixed = pc.Pieces.of(lines).then(curves + lines[:1])
    assert [h.shape[1] for _, h in mixed.groups] == [2, 4]
    assert np.array_equal(mixed.groups[0][0], [0, 1, 2, 3, 4, 7])


def test_column_extremes_equal_numpys_reductions():
    """column_extremes gives min and max over the control points to the bit
    (numpy's short-axis reduction is what it replaces), and the spans and largest
    |coordinate| derived from them equal np.ptp's and np.abs().max's."""
    rng = np.random.default_rng(0)
    for n in (1, 2, 3, 4, 7):
        x = rng.normal(size=(500, n, 2)) * rng.uniform(0, 1e3, (500, 1, 1))
        x[::7] = np.abs(x[::7])
        x[::11] = -np.abs(x[::11])
        lo, hi = pc.column_extremes(x)
        assert np.array_equal(lo, x.min(axis=1)) and np.array_equal(hi, x.max(axis=1))
        assert np.array_equal(np.maximum(-lo, hi).max(axis=1), np.abs(x).max(axis=(1, 2)))
        assert np.array_equal(np.maximum(hi[:, 0] - lo[:, 0], hi[:, 1] - lo[:, 1]),
                              np.ptp(x, axis=1).max(axis=1))
    x[3, 0, 1] = np.nan
    assert np.isnan(pc.column_extremes(x)[0][3, 1])

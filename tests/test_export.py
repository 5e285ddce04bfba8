"""Cubic / quadratic export: the certified bound holds (>= sampled error) and meets tol."""

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from morph import bernstein as bz
from morph import piece as pc
from morph.errors import ToleranceNotMetError
from morph.export import (cubic_bound, cubic_segments, fit_cubic, loop_to_cubics,
                          piece_to_cubics, piece_to_quadratics)

TOLS = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6]
U = np.linspace(0.0, 1.0, 257)


def sampled_error(piece, t0, t1, cubic):
    """max over samples of |R(t0 + u (t1 - t0)) - C(u)| (same parameter)."""
    return float(np.hypot(*(pc.evaluate(piece, t0 + (t1 - t0) * U) - bz.evaluate(cubic, U)).T).max())


def check_segments(piece, tol):
    segs = cubic_segments(piece, tol)
    assert segs[0][0] == 0.0 and segs[-1][1] == 1.0
    for (a0, a1, ca, _), (b0, b1, cb, _) in zip(segs, segs[1:]):
        assert a1 == b0 and np.array_equal(ca[-1], cb[0])  # exact joins
    assert np.allclose(segs[0][2][0], pc.start(piece), atol=1e-12)
    assert np.allclose(segs[-1][2][-1], pc.end(piece), atol=1e-12)
    for t0, t1, cubic, bound in segs:
        err = sampled_error(piece, t0, t1, cubic)
        # the bound is certified: never below the sampled error (rounding aside)
        assert err <= bound * (1 + 1e-9) + 1e-13, (err, bound)
        assert bound <= tol
    return segs


ARCS = [
    pc.ellipse_arc((0, 0), 1.0, 1.0, 0.0, 0.0, np.pi / 2)[0],
    pc.ellipse_arc((2, -1), 3.0, 1.0, 0.3, 0.2, 1.4)[0],
    pc.ellipse_arc((0, 0), 500.0, 200.0, -1.0, 2.0, 1.5)[0],
    pc.ellipse_arc((5, 5), 0.01, 0.05, 0.7, -1.0, 0.5)[0],
]


@pytest.mark.parametrize("tol", TOLS)
@pytest.mark.parametrize("arc", range(len(ARCS)))
def test_ellipse_arcs_bound_holds_and_meets_tol(arc, tol):
    check_segments(ARCS[arc], tol)


@st.composite
def rational_pieces(draw):
    n = draw(st.integers(2, 4))
    rng = np.random.default_rng(draw(st.integers(0, 2 ** 32 - 1)))
    pts = rng.uniform(-1, 1, (n + 1, 2))
    w = rng.uniform(0.3, 3.0, n + 1)
    return pc.from_points(pts, w)


@settings(max_examples=15, deadline=None)
@given(rational_pieces(), st.sampled_from(TOLS))
def test_random_rational_pieces_bound_holds(piece, tol):
    check_segments(piece, tol)


def test_tolerance_sweep_piece_counts_grow_slowly():
    """As kurbo's sweep: error < tol at every tol, and counts grow like tol^(-1/4..-1/3)."""
    counts = [len(check_segments(ARCS[1], tol)) for tol in TOLS]
    assert counts == sorted(counts)
    assert counts[-1] <= 40


def test_polynomial_pieces_exact():
    q = pc.quadratic((0, 0), (1, 2), (3, 0))
    (c,) = piece_to_cubics(q, 1e-9)
    assert np.allclose(bz.evaluate(c, U), pc.evaluate(q, U), atol=1e-14)
    (c,) = piece_to_cubics(pc.line((0, 0), (1, 1)), 1e-9)
    assert np.allclose(c, [[0, 0], [1 / 3, 1 / 3], [2 / 3, 2 / 3], [1, 1]])
    cub = pc.cubic((0, 0), (1, 2), (2, -1), (3, 0))
    assert np.array_equal(piece_to_cubics(cub, 1e-3)[0], pc.cartesian(cub))
    # scaled homogeneous coordinates (constant weight 2) are still polynomial
    assert len(piece_to_cubics(cub * 2.0, 1e-12)) == 1
    # a polynomial quartic is approximated
    quart = pc.from_points([[0, 0], [1, 3], [2, -3], [3, 3], [4, 0]])
    check_segments(quart, 1e-5)


def test_cubic_bound_is_zero_for_exact_and_scale_invariant():
    cub = pc.cubic((0, 0), (1, 2), (2, -1), (3, 0))
    assert cubic_bound(cub, pc.cartesian(cub)) == pytest.approx(0, abs=1e-14)
    arc = ARCS[1]
    c, b = fit_cubic(arc)
    assert cubic_bound(arc * 7.5, c) == pytest.approx(b, rel=1e-12)
    # refining the certificate never loosens it
    assert cubic_bound(arc, c, refine=0) >= cubic_bound(arc, c, refine=4) >= \
        sampled_error(arc, 0, 1, c) * (1 - 1e-12)


def test_fit_keeps_end_tangent_directions():
    arc = ARCS[1]
    c, _ = fit_cubic(arc)
    t0, t1 = pc.end_tangents(arc)
    d0, d1 = c[1] - c[0], c[3] - c[2]
    assert np.allclose(d0 / np.hypot(*d0), t0, atol=1e-12)
    assert np.allclose(d1 / np.hypot(*d1), t1, atol=1e-12)


def test_loop_to_cubics_closed_circle():
    circle = pc.circle((1, 1), 2.0)
    cubics = loop_to_cubics(circle, 1e-6)
    for a, b in zip(cubics, cubics[1:] + cubics[:1]):
        assert np.allclose(a[-1], b[0], atol=1e-15)
    pts = np.concatenate([bz.evaluate(c, U) for c in cubics])
    assert np.abs(np.hypot(pts[:, 0] - 1, pts[:, 1] - 1) - 2.0).max() <= 1e-6


@pytest.mark.parametrize("tol", [1e-2, 1e-4, 1e-6])
def test_quadratics_within_tol(tol):
    arc = ARCS[1]
    quads = piece_to_quadratics(arc, tol)
    assert all(q.shape == (3, 2) for q in quads)
    assert np.allclose(quads[0][0], pc.start(arc)) and np.allclose(quads[-1][-1], pc.end(arc))
    for a, b in zip(quads, quads[1:]):
        assert np.array_equal(a[-1], b[0])
    # distance from quadratic points to the curve (dense polyline, chord error ~2e-9)
    pts = np.concatenate([bz.evaluate(q, np.linspace(0, 1, 33)) for q in quads])
    assert distance_to_curve(pts, arc).max() <= tol * (1 + 1e-6) + 1e-8


def distance_to_curve(points, piece, n=20001):
    """Distance of points to a dense polyline of the piece (nearest vertex's segments)."""
    poly = pc.evaluate(piece, np.linspace(0, 1, n))
    out = np.empty(len(points))
    for s in range(0, len(points), 200):
        p = points[s:s + 200]
        near = np.argmin(((p[:, None, :] - poly[None]) ** 2).sum(axis=2), axis=1)
        best = np.full(len(p), np.inf)
        for lo in (near - 1, near):
            lo = np.clip(lo, 0, n - 2)
            a, b = poly[lo], poly[lo + 1]
            d = b - a
            u = np.clip(((p - a) * d).sum(axis=1) / (d * d).sum(axis=1), 0, 1)
            best = np.minimum(best, np.hypot(*(p - a - u[:, None] * d).T))
        out[s:s + 200] = best
    return out


def test_quadratics_exact_for_polynomial_quadratics_and_lines():
    q = pc.quadratic((0, 0), (1, 2), (3, 0))
    assert np.array_equal(piece_to_quadratics(q, 1e-9)[0], pc.cartesian(q))
    assert np.allclose(piece_to_quadratics(pc.line((0, 0), (2, 2)), 1e-9)[0],
                       [[0, 0], [1, 1], [2, 2]])


def test_errors():
    arc = ARCS[0]
    with pytest.raises(ValueError):
        piece_to_cubics(arc, 0.0)
    with pytest.raises(ValueError):
        piece_to_cubics(pc.from_points([[0, 0], [1, 1], [2, 0]], [1, 1, 1]) * [1, 1, -1], 1e-3)
    with pytest.raises(ToleranceNotMetError) as info:
        piece_to_cubics(ARCS[2], 1e-9, max_depth=2)
    assert info.value.achieved > 1e-9 and info.value.piece is not None

"""Property-based tests of morph.minkowski.minkowski_sum: hypothesis, small and fast
(derandomized, a smoke test), and a slow test with fresh randomness each run.

Operands are random star-shaped blobs: radii at sorted random angles joined by
polynomial or rational quadratic / cubic pieces (control points inside each angular
wedge, random weights), convex and not, with near-tangent joins and tiny features
(close angles, small radii) coming from the strategies' edge cases; plus ellipses
and squares.  Only simple loops are kept (assume).  Properties:

- A + b ⊂ A ⊕ B and a + B ⊂ A ⊕ B for sample points a ∈ A, b ∈ B (winding number of
  the flattened result, points within tol of its boundary excepted);
- area(A ⊕ B) >= max(area A, area B);
- A ⊕ B = B ⊕ A: areas within tol * perimeter;
- translation covariance: (A + t) ⊕ B = (A ⊕ B) + t (area, bounding box).
"""

import os
import random

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
pytest.importorskip("hypothesis")
from hypothesis import HealthCheck, assume, given, settings
from hypothesis import strategies as st
from shapely.geometry import Polygon

from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.minkowski import minkowski_sum
from tests.oracles import reference as R

TOL = 1e-2
REF_TOL = 0.5
SETTINGS = settings(max_examples=6, deadline=None, derandomize=True,
                    suppress_health_check=list(HealthCheck))


@st.composite
def blobs(draw, size=100.0):
    n = draw(st.integers(3, 7))
    gaps = np.array(draw(st.lists(st.floats(0.02, 1.0), min_size=n, max_size=n)))
    if gaps.max() / gaps.sum() > 0.45:  # every wedge < pi: pieces stay in their wedge
        gaps = np.minimum(gaps, 0.45 * gaps.sum())
    ang = draw(st.floats(0, 2 * np.pi)) + np.concatenate([[0], np.cumsum(gaps)[:-1]]) \
        * 2 * np.pi / gaps.sum()
    radii = np.array(draw(st.lists(st.floats(0.05, 1.0), min_size=n, max_size=n))) * size
    pts = np.column_stack([radii * np.cos(ang), radii * np.sin(ang)])
    pieces = []
    for i in range(n):
        j = (i + 1) % n
        a0, a1 = ang[i], ang[i] + (ang[j] - ang[i]) % (2 * np.pi)
        kind = draw(st.sampled_from(["line", "quad", "cubic"]))
        rational = draw(st.booleans())
        k = {"line": 0, "quad": 1, "cubic": 2}[kind]
        ctrl = []
        for m in range(k):
            f = draw(st.floats(0.05, 0.95))
            th = a0 + (m + f) / k * (a1 - a0)
            r = draw(st.floats(0.05, 1.3)) * size
            ctrl.append((r * np.cos(th), r * np.sin(th)))
        cp = np.array([pts[i], *ctrl, pts[j]])
        w = np.ones(len(cp))
        if rational and k:
            w[1:-1] = draw(st.lists(st.floats(0.3, 3.0), min_size=k, max_size=k))
        pieces.append(pc.from_points(cp, w))
    loop = pieces
    ring = pl.flatten_loop(loop, 0.01)
    poly = Polygon(ring)
    assume(poly.is_valid and poly.area > 1.0)
    if mo.loop_area(loop) < 0:  # CCW outer
        loop = [pc.reverse(p) for p in loop[::-1]]
    off = draw(st.tuples(st.floats(-50, 50), st.floats(-50, 50)))
    return [[pc.translate(p, np.array(off)) for p in loop]]


@st.composite
def convex(draw):
    kind = draw(st.sampled_from(["ellipse", "square"]))
    if kind == "ellipse":
        rx, ry = draw(st.floats(1.0, 60.0)), draw(st.floats(0.5, 60.0))
        return [pc.ellipse([0.0, 0.0], rx, ry, draw(st.floats(0, np.pi)))]
    h = draw(st.floats(0.5, 40.0))
    p = [(-h, -h), (h, -h), (h, h), (-h, h)]
    return [[pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]]


shapes = st.one_of(blobs(), blobs(), convex())


def _polys(loops):
    return [pl.flatten_loop(l, TOL / 10) for l in loops]


def _interior_points(region, rng, n):
    polys = _polys(region)
    allp = np.concatenate(polys)
    lo, hi = allp.min(axis=0), allp.max(axis=0)
    x = rng.uniform(lo, hi, size=(40 * n, 2))
    x = x[R.winding_number(x, polys) != 0]
    bnd = np.concatenate([pc.evaluate(p, np.linspace(0, 1, 5)) for l in region for p in l])
    return np.concatenate([x[:n], bnd])  # interior samples and boundary points


def _contained(loops, x):
    polys = _polys(loops)
    inside = R.winding_number(x, polys) != 0
    lines = shapely.MultiLineString([np.vstack([p, p[:1]]) for p in polys])
    near = shapely.distance(shapely.points(x), lines) <= 2 * TOL
    return inside | near


def _perimeter(loops):
    return sum(pc.length_bound(p) for l in loops for p in l)


@SETTINGS
@given(a=shapes, b=shapes, seed=st.integers(0, 2 ** 16))
def test_sum_contains_translates(a, b, seed):
    loops = minkowski_sum(a, b, TOL)
    rng = np.random.default_rng(seed)
    pa, pb = _interior_points(a, rng, 8), _interior_points(b, rng, 8)
    x = (pa[:, None, :] + pb[None, :, :]).reshape(-1, 2)
    ok = _contained(loops, x)
    assert ok.all(), "a + b outside A ⊕ B at %s" % (x[~ok][:3],)


@SETTINGS
@given(a=shapes, b=shapes)
def test_area_bounds_and_symmetry(a, b):
    ab = minkowski_sum(a, b, TOL)
    ba = minkowski_sum(b, a, TOL)
    area_ab, area_ba = mo.region_area(ab), mo.region_area(ba)
    assert area_ab >= max(mo.region_area(a), mo.region_area(b)) - TOL * _perimeter(ab)
    assert abs(area_ab - area_ba) <= TOL * max(_perimeter(ab), _perimeter(ba))
    assert sum(mo.loop_area(l) > 0 for l in ab) == sum(mo.loop_area(l) > 0 for l in ba)


@SETTINGS
@given(a=shapes, b=shapes, t=st.tuples(st.floats(-500, 500), st.floats(-500, 500)))
def test_translation_covariance(a, b, t):
    t = np.array(t)
    ab = minkowski_sum(a, b, TOL)
    moved = [[pc.translate(p, t) for p in l] for l in a]
    ab2 = minkowski_sum(moved, b, TOL)
    assert abs(mo.region_area(ab2) - mo.region_area(ab)) <= TOL * _perimeter(ab)
    box1 = np.min([pc.bbox(p)[:2] for l in ab for p in l], axis=0)
    box2 = np.min([pc.bbox(p)[:2] for l in ab2 for p in l], axis=0)
    assert np.allclose(box2 - box1, t, atol=2 * TOL)


@SETTINGS
@given(a=shapes, b=shapes)
def test_sum_area_matches_polygon_reference(a, b):
    """Area and component counts against a coarse Clipper sum (inputs flattened to
    REF_TOL: the fine one costs N·M)."""
    loops = minkowski_sum(a, b, TOL)
    ref = R.polygon_minkowski_sum(a, b, REF_TOL)
    area = mo.region_area(loops)
    per = _perimeter(loops)
    assert abs(area - ref.area) <= REF_TOL * per, (area, ref.area)
    outer, holes = R.count_outer_and_holes(ref, min_area=REF_TOL * per)
    assert sum(mo.loop_area(l) > REF_TOL * per for l in loops) == outer


# ---------------------------------------------------------------- real randomness (slow)

def _rng_blob(rng, size):
    """A random star-shaped blob (as :func:`blobs`) drawn from a numpy generator."""
    while True:
        n = int(rng.integers(3, 8))
        gaps = np.minimum(rng.uniform(0.02, 1.0, n), 0.45 * rng.uniform(0.02, 1.0, n).sum() + 0.45)
        gaps = np.minimum(gaps, 0.45 * gaps.sum())
        ang = rng.uniform(0, 2 * np.pi) + np.concatenate([[0], np.cumsum(gaps)[:-1]]) \
            * 2 * np.pi / gaps.sum()
        radii = rng.uniform(0.05, 1.0, n) * size
        pts = np.column_stack([radii * np.cos(ang), radii * np.sin(ang)])
        loop = []
        for i in range(n):
            j = (i + 1) % n
            a0, a1 = ang[i], ang[i] + (ang[j] - ang[i]) % (2 * np.pi)
            k = int(rng.integers(0, 3))
            th = a0 + (np.arange(k) + rng.uniform(0.05, 0.95, k)) / max(k, 1) * (a1 - a0)
            r = rng.uniform(0.05, 1.3, k) * size
            cp = np.array([pts[i], *np.column_stack([r * np.cos(th), r * np.sin(th)]), pts[j]])
            w = np.ones(len(cp))
            if k and rng.random() < 0.5:
                w[1:-1] = rng.uniform(0.3, 3.0, k)
            loop.append(pc.from_points(cp, w))
        poly = Polygon(pl.flatten_loop(loop, 1e-3 * size))
        if poly.is_valid and poly.area > 1e-3 * size * size:
            return [loop] if mo.loop_area(loop) > 0 else [[pc.reverse(p) for p in loop[::-1]]]


def _rotated(region, theta, scale):
    c, s = np.cos(theta) * scale, np.sin(theta) * scale
    return [[pc.transform(p, [[c, -s, 0.0], [s, c, 0.0]]) for p in loop] for loop in region]


@pytest.mark.slow
def test_random_rotated_scaled_sums_against_polygon_reference():
    """Blob ⊕ blob and blob ⊕ ellipse with random rotation, scale (1e-2 .. 1e2) and
    nib angle, from a fresh seed each run (printed; rerun one with MORPH_SEED=N): the
    sum contains a + b for sample points, its area is within tol x perimeter (+ the
    reference's own flattening) of a Clipper sum, and it is symmetric in area."""
    seed = int(os.environ.get("MORPH_SEED", random.SystemRandom().randrange(2 ** 32)))
    print("MORPH_SEED=%d" % seed)
    rng = np.random.default_rng(seed)
    for case in range(12):
        scale = 10.0 ** rng.uniform(-2, 2)
        a = _rotated(_rng_blob(rng, 100.0), rng.uniform(0, 2 * np.pi), scale)
        if rng.random() < 0.5:
            b = _rotated(_rng_blob(rng, 60.0), rng.uniform(0, 2 * np.pi), scale)
        else:
            rx, ry = rng.uniform(1, 60, 2) * scale
            b = [pc.ellipse([0.0, 0.0], rx, ry, rng.uniform(0, np.pi))]
        tol = 1e-3 * 100.0 * scale
        where = "MORPH_SEED=%d case %d" % (seed, case)
        loops = minkowski_sum(a, b, tol)
        x = (_interior_points(a, rng, 6)[:, None, :] + _interior_points(b, rng, 6)[None]).reshape(-1, 2)
        polys = [pl.flatten_loop(l, tol / 10) for l in loops]
        inside = R.winding_number(x, polys) != 0
        lines = shapely.MultiLineString([np.vstack([p, p[:1]]) for p in polys])
        assert (inside | (shapely.distance(shapely.points(x), lines) <= 2 * tol)).all(), where
        ref_flat = 5 * tol  # the reference (flattened operands) is within this of exact
        ref = R.polygon_minkowski_sum(a, b, ref_flat)
        per = _perimeter(loops)
        assert abs(mo.region_area(loops) - ref.area) <= (tol + 2 * ref_flat) * per, where
        ba = minkowski_sum(b, a, tol)
        assert abs(mo.region_area(ba) - mo.region_area(loops)) <= 2 * tol * per, where

"""Short arcs between two lines written as the lines' corner (morph.export.corners),
checked against independent computations: the distance of every written point to the
polygon a rounded polygon is made of, and dense samples of the dropped arcs against
the corner they are replaced by."""

import math

import numpy as np
import pytest

from morph.export import loops_to_beziers
from morph.export.bank import plan_run_arrays
from morph.export.corners import cut_corners


def _line(a, b):
    return np.array([[a[0], a[1], 1.0], [b[0], b[1], 1.0]])


def _conic(a, p, b, w):
    """The rational quadratic from a to b with middle control point p, weight w."""
    return np.array([[a[0], a[1], 1.0], [p[0] * w, p[1] * w, w], [b[0], b[1], 1.0]])


def _rounded_polygon(n, radius, r, phase=0.0):
    """Loop of the regular n-gon (circumradius ``radius``) plus the disk of radius r:
    offset edges and exact circular arcs; and the polygon's vertices."""
    ang = phase + 2 * np.pi * np.arange(n) / n
    v = radius * np.stack([np.cos(ang), np.sin(ang)], axis=1)
    normals = []
    for k in range(n):
        e = v[(k + 1) % n] - v[k]
        normals.append(np.array([e[1], -e[0]]) / np.hypot(*e))
    loop = []
    for k in range(n):
        n0, n1 = normals[k], normals[(k + 1) % n]
        vk, vn = v[k], v[(k + 1) % n]
        loop.append(_line(vk + r * n0, vn + r * n0))
        half = math.acos(np.clip(n0 @ n1, -1, 1)) / 2
        mid = (n0 + n1) / np.hypot(*(n0 + n1))
        loop.append(_conic(vn + r * n0, vn + r * mid / math.cos(half), vn + r * n1,
                           math.cos(half)))
    return loop, v


def _samples(segments, k=64, lines=None):
    """k points of each segment (``lines``: that many of a line)."""
    out = []
    for s in segments:
        s = np.asarray(s, float)
        n = len(s) - 1
        t = np.linspace(0, 1, lines if n == 1 and lines else k)[:, None]
        basis = np.stack([math.comb(n, i) * t[:, 0] ** i * (1 - t[:, 0]) ** (n - i)
                          for i in range(n + 1)], axis=1)
        out.append(basis @ s)
    return np.concatenate(out)


def _polygon_distance(x, v):
    """Distance of points x to the convex polygon's boundary-or-inside (0 inside)."""
    d = np.full(len(x), np.inf)
    for k in range(len(v)):
        a, b = v[k], v[(k + 1) % len(v)]
        e = b - a
        t = np.clip(((x - a) @ e) / (e @ e), 0, 1)
        d = np.minimum(d, np.hypot(*(x - a - t[:, None] * e).T))
    return d


def _exact_points(loop, k=64):
    """Dense samples of the exact loop (lines and rational arcs)."""
    t = np.linspace(0, 1, k)
    out = []
    for p in loop:
        n = len(p) - 1
        basis = np.stack([math.comb(n, i) * t ** i * (1 - t) ** (n - i)
                          for i in range(n + 1)], axis=1)
        h = basis @ p
        out.append(h[:, :2] / h[:, 2:])
    return np.concatenate(out)


def _to_polyline(x, line, block=256):
    """Distance of points x to the polyline through the points ``line``."""
    a, e = line[:-1], np.diff(line, axis=0)
    ee = np.maximum((e * e).sum(axis=1), 1e-300)
    out = []
    for k in range(0, len(x), block):
        q = x[k:k + block, None] - a[None]                       # (m, s, 2)
        t = np.clip((q * e[None]).sum(axis=2) / ee[None], 0, 1)
        out.append(np.hypot(*np.moveaxis(q - t[..., None] * e[None], 2, 0)).min(axis=1))
    return np.concatenate(out)


def _nearest(x, y):
    """Distance of each point x to the nearest point y."""
    return np.hypot(*np.moveaxis(x[:, None] - y[None], 2, 0)).min(axis=1)


def _off_by(loop, v, r, out, tol):
    """The largest distance between the written outline ``out`` and the exact sum
    (both ways): written points against |dist to polygon - r|, exact points against
    the written outline (its lines exact, its curves as polylines of 40 points)."""
    written = _samples(out)
    one = np.abs(_polygon_distance(written, v) - r).max()
    other = _to_polyline(_exact_points(loop), _samples(out, 40, lines=2)).max()
    return max(one, other)


@pytest.mark.parametrize("n,r,tol", [(40, 20.0, 0.5), (24, 6.0, 0.3), (60, 35.0, 0.25)])
def test_corners_of_a_rounded_polygon_stay_within_tol(n, r, tol):
    """Arcs whose corner is within tol become corners (lines only are written, fewer
    points); the outline stays within tol of the exact sum, and the same outline
    pushed out by 2 tol fails the check (the oracle can fail)."""
    loop, v = _rounded_polygon(n, 500.0, r, phase=0.3)
    half = math.pi / n
    h = r * (1 / math.cos(half) - math.cos(half))      # the corner's bound
    assert h <= tol    # these cases drop every arc
    out = loops_to_beziers([loop], tol, wrap=True)[0]
    assert all(len(s) == 2 for s in out) and len(out) == n
    assert _off_by(loop, v, r, out, tol) <= tol
    pushed = [np.asarray(s) * (1 + 2 * tol / 500.0) for s in out]
    assert _off_by(loop, v, r, pushed, tol) > tol


def test_arcs_whose_corner_is_too_far_are_fitted():
    """A tolerance below the corners' bound: every arc is kept (fitted, certified)."""
    n, r = 40, 20.0
    loop, v = _rounded_polygon(n, 500.0, r)
    half = math.pi / n
    h = r * (1 / math.cos(half) - math.cos(half))
    out = loops_to_beziers([loop], 0.5 * h, wrap=True)[0]
    assert sum(len(s) == 4 for s in out) >= n
    assert _off_by(loop, v, r, out, 0.5 * h) <= 0.5 * h


def test_the_bound_holds_on_random_corners():
    """Random conic arcs (weights 0.1-3, turns up to 120 degrees, random scale and
    rotation) between two lines: where :func:`cut_corners` drops the arc, the dense
    Hausdorff distance between the arc and the corner is within tol; turns beyond a
    right angle are never dropped."""
    rng = np.random.default_rng(3)
    dropped = 0
    for _ in range(200):
        turn = rng.uniform(0.01, 2.1)
        scale = 10 ** rng.uniform(-1, 3)
        rot = rng.uniform(0, 2 * np.pi)
        a = np.zeros(2)
        d1 = np.array([1.0, 0.0])
        d2 = np.array([math.cos(turn), math.sin(turn)])
        s, t = rng.uniform(0.2, 1.0, 2) * scale
        p = a + s * d1
        b = p + t * d2
        rm = np.array([[math.cos(rot), -math.sin(rot)], [math.sin(rot), math.cos(rot)]])
        a, p, b = a @ rm.T, p @ rm.T, b @ rm.T
        d1, d2 = d1 @ rm.T, d2 @ rm.T
        w = rng.uniform(0.1, 3.0)
        arc = _conic(a, p, b, w)
        loop = [_line(a - 3 * scale * d1, a), arc, _line(b, b + 3 * scale * d2),
                _line(b + 3 * scale * d2, a - 3 * scale * d1)]
        tol = rng.uniform(0.001, 0.3) * scale
        bank, runs = plan_run_arrays([loop], 1e-6, wrap=True)
        keep = cut_corners(bank, runs, tol, wrap=True)
        if keep.all():
            continue
        dropped += 1
        assert turn <= math.pi / 2 + 1e-9
        corner = _samples([[a, p], [p, b]], 400)
        exact = _exact_points([arc], 400)
        gap = max(_nearest(exact, corner).max(), _nearest(corner, exact).max())
        assert gap <= tol + 1e-9 * scale
    assert dropped > 20


def test_a_run_outside_its_corner_triangle_is_kept():
    """An arc that bulges beyond the lines' corner (control point outside the
    triangle) is not dropped, however large the tolerance."""
    a, b = np.array([0.0, 0.0]), np.array([10.0, 1.0])
    bulge = np.array([5.0, 8.0])   # far outside the corner triangle of the two lines
    loop = [_line([-20.0, 0.0], a), _conic(a, bulge, b, 1.0),
            _line(b, [30.0, 5.0]), _line([30.0, 5.0], [-20.0, 0.0])]
    bank, runs = plan_run_arrays([loop], 1e-6, wrap=True)
    assert cut_corners(bank, runs, 100.0, wrap=True).all()

"""Contour clean-up after the exact stroke (morph.fonts.tables.clean_contour) never
turns a correct outline into a failure: it assumed segments that meet exactly, while
converted segments meet within float noise, and a join at x.5 +- 1e-12 rounded from
its two sides fell on two integers ("contour cleaning broke the chain")."""

import numpy as np
import pytest

from morph import piece as pc
from morph.fonts.tables import clean_contour, contours_from_loops


def _chained(contour):
    return all(np.array_equal(a[-1], b[0]) for a, b in zip(contour, contour[1:] + contour[:1]))


@pytest.mark.parametrize("seed", range(20))
def test_clean_contour_with_joins_within_float_noise(seed):
    """Random closed chains of lines, quadratics and cubics whose joins sit on half
    integers and differ between the two segments by 1e-12: cleaned to a chain."""
    rng = np.random.default_rng(seed)
    n = int(rng.integers(3, 9))
    ang = np.sort(rng.uniform(0, 2 * np.pi, n))
    joins = np.round(np.column_stack([np.cos(ang), np.sin(ang)]) * 200) + 0.5
    segs = []
    for k in range(n):
        a, b = joins[k], joins[(k + 1) % n]
        inner = [a + (b - a) * t + rng.normal(0, 20, 2) for t in
                 np.linspace(0, 1, int(rng.integers(2, 5)))[1:-1]]
        seg = np.array([a] + inner + [b], float)
        seg[0] += rng.choice([-1e-12, 1e-12], 2)  # the start within noise of the last end
        segs.append(seg)
    contour = clean_contour(segs)
    assert len(contour) >= 2 and _chained(contour)


def _polyline(rng):
    """A pen path of short segments (0.3-50 units) with sharp turns (up to reversals)."""
    p = [rng.uniform(100, 900, 2)]
    ang = rng.uniform(0, 2 * np.pi)
    for _ in range(int(rng.integers(3, 25))):
        ang += rng.choice([rng.uniform(-0.3, 0.3), rng.uniform(2.0, 3.14) * rng.choice([-1, 1])])
        p.append(p[-1] + 10 ** rng.uniform(-0.5, 1.7) * np.array([np.cos(ang), np.sin(ang)]))
    return [pc.line(a, b) for a, b in zip(p, p[1:])]


@pytest.mark.parametrize("seed", range(12))
@pytest.mark.parametrize("quadratic", [False, True])
def test_stroked_polylines_clean_up(seed, quadratic):
    """Random stroked polylines (CJK medians are such: short segments, sharp turns):
    the exact stroke converts and cleans without an error, every contour chained,
    and the written outline (integer Bézier segments) has the stroke's area within
    the rounding (0.71 unit along its length)."""
    from morph.fonts.brush import ellipse_nib
    from morph.stroke import stroke_paths
    from tests.oracles.reference import region_to_shapely

    rng = np.random.default_rng(100 + seed)
    paths = [(_polyline(rng), False) for _ in range(int(rng.integers(1, 4)))]
    region = stroke_paths(paths, ellipse_nib(90, 20, 30), 0.25)
    contours = contours_from_loops(region, 0.25, quadratic, reverse=False)
    assert contours and all(_chained(c) for c in contours)
    written = [[np.column_stack([seg, np.ones(len(seg))]) for seg in c] for c in contours]
    ours, exact = region_to_shapely(written, 0.05), region_to_shapely(region, 0.05)
    assert abs(ours.area - exact.area) <= 0.75 * exact.length

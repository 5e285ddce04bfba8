"""morph.nib: the nib in the geometry layer; stroke_paths checks convexity as its
docstring requires (a non-convex nib's sum with a path is not what a pen draws)."""

import numpy as np
import pytest

from morph import piece as pc
from morph.errors import NibError
from morph.nib import check_convex_nib, ellipse_nib, nib_is_symmetric, region_extent
from morph.stroke import stroke_paths


def _polygon(points):
    pts = [np.asarray(p, float) for p in points]
    return [[pc.line(a, b) for a, b in zip(pts, pts[1:] + pts[:1])]]


def test_stroke_paths_refuses_a_non_convex_nib():
    path = [([pc.line((0.0, 0.0), (100.0, 0.0))], False)]
    dart = _polygon([(0, 0), (10, -10), (0, 10), (-10, -10)])  # turns clockwise at the origin
    with pytest.raises(NibError, match="not convex"):
        stroke_paths(path, dart, 0.01)
    with pytest.raises(NibError, match="one closed convex shape"):
        stroke_paths(path, ellipse_nib(4, 2) + ellipse_nib(2, 2), 0.01)
    assert stroke_paths(path, ellipse_nib(4, 2, 30), 0.01)


def test_nib_helpers():
    n = ellipse_nib(90, 20, 0)
    check_convex_nib(n)
    assert np.allclose(region_extent(n), (-45, -10, 45, 10))
    assert nib_is_symmetric(n)
    assert not nib_is_symmetric(_polygon([(0, 0), (10, 0), (0, 10)]))
    with pytest.raises(NibError):
        ellipse_nib(0, 1)

"""morph.nib: the nib in the geometry layer; stroke_paths checks convexity as its
docstring requires (a non-convex nib's sum with a path is not what a pen draws)."""

import numpy as np
import pytest

from morph import piece as pc
from morph.errors import NibError
from morph.nib import (check_convex_nib, convex_region, ellipse_nib, nib_is_symmetric,
                       region_extent)
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


def test_nib_symmetry_with_and_without_pieces_that_pair_up():
    """The half turn maps an ellipse's quarters and a centred square's sides onto
    pieces of the nib (no flattening needed); a centred square whose sides are cut
    unevenly does not pair up and is judged by the sampled support function (still
    symmetric); an ellipse off the origin, or a square with one corner moved by
    ten times the tolerance, is not symmetric either way."""
    from morph.nib import _pieces_map_to_pieces

    for args in [(90, 20, 30), (31, 7, 77.3), (50, 50, 0)]:
        n = ellipse_nib(*args)
        assert _pieces_map_to_pieces(n, 1e-7 * args[0]) and nib_is_symmetric(n)
    square = [(-10, -10), (10, -10), (10, 10), (-10, 10)]
    assert _pieces_map_to_pieces(_polygon(square), 1e-6) and nib_is_symmetric(_polygon(square))
    cut = [(-10, -10), (3, -10), (10, -10), (10, 10), (-10, 10)]
    assert not _pieces_map_to_pieces(_polygon(cut), 1e-6) and nib_is_symmetric(_polygon(cut))
    off = [pc.ellipse((3.0, 0.0), 45.0, 10.0, 0.5)]
    assert not nib_is_symmetric(off)
    moved = [(-10, -10), (10, -10), (10, 10 + 10 * 2e-6), (-10, 10)]
    assert not _pieces_map_to_pieces(_polygon(moved), 2e-6)
    assert not nib_is_symmetric(_polygon(moved))


def test_a_nib_found_convex_is_not_checked_again(monkeypatch):
    """check_convex_nib keeps the nibs it found convex: an equal nib (a new object
    of the same pieces) is not mapped again; a nib that differs (a dart, an ellipse
    with one control point moved) is, and a non-convex one is still refused."""
    import morph.gauss as gauss

    calls = []
    real = gauss.gauss_map
    monkeypatch.setattr(gauss, "gauss_map", lambda loop: calls.append(1) or real(loop))
    check_convex_nib(ellipse_nib(37, 11, 17))
    check_convex_nib(ellipse_nib(37, 11, 17))
    assert len(calls) == 1
    moved = ellipse_nib(37, 11, 17)
    moved[0][0] = moved[0][0].copy()
    moved[0][0][1, 0] += 1e-9
    check_convex_nib(moved)
    assert len(calls) == 2
    dart = _polygon([(0, 0), (10, -10), (0, 10), (-10, -10)])
    for _ in range(2):
        with pytest.raises(NibError, match="not convex"):
            check_convex_nib(dart)
    assert len(calls) == 4


def test_convex_region_is_the_nib_validated_and_refuses_others():
    """A convex nib comes back as a validated Region of the same pieces (the sums
    skip its winding test, which it passes: winding_fault finds nothing); a
    non-convex one raises as check_convex_nib does."""
    from morph.operands import winding_fault
    from morph.region import Region

    nib = ellipse_nib(80, 30, 30)
    got = convex_region(nib)
    assert isinstance(got, Region) and got.validated and convex_region(got) is got
    assert [[np.array_equal(p, q) for p, q in zip(a, b)] for a, b in zip(got, nib)] == \
        [[True] * len(nib[0])]
    assert winding_fault(nib) is None
    with pytest.raises(NibError, match="not convex"):
        convex_region(_polygon([(0, 0), (10, -10), (0, 10), (-10, -10)]))


def test_region_extent_kept_per_region():
    """region_extent answers from what it measured for the same pieces, and each
    region gets its own box (a moved nib, a turned one)."""
    from morph.region import region_bbox, translate_region

    nib = ellipse_nib(80, 30, 30)
    first = region_extent(nib)
    assert first == tuple(float(v) for v in region_bbox(nib))
    assert region_extent(ellipse_nib(80, 30, 30)) == first
    moved = region_extent(translate_region(nib, (5.0, 0.0)))
    assert np.allclose(moved, (first[0] + 5.0, first[1], first[2] + 5.0, first[3]),
                       rtol=0, atol=1e-9) and moved != first
    assert region_extent(ellipse_nib(80, 30, 60)) != first

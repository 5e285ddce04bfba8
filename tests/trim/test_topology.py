"""morph.trim.topology: fill rules, slivers and holes on the integer rings, against
exact areas."""

import pytest

from morph import piece as pc
from morph.trim.flatten import tag_loops
from morph.trim.topology import drop_slivers, fill_holes, filled_rings, ring_area


def _square(x0, y0, s, ccw=True):
    p = [(x0, y0), (x0 + s, y0), (x0 + s, y0 + s), (x0, y0 + s)]
    if not ccw:
        p = p[::-1]
    return [pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]


@pytest.mark.parametrize("rule, area", [("positive", 7.0), ("nonzero", 7.0), ("evenodd", 6.0)])
def test_fill_rules_on_overlapping_squares(rule, area):
    tg = tag_loops([_square(0, 0, 2), _square(1, 1, 2)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), rule)
    got = sum(ring_area(r.q) for r in rings) * tg.grid ** 2
    assert got == pytest.approx(area, rel=1e-6)
    assert all((ring_area(r.q) > 0) != r.hole for r in rings)


def test_positive_ignores_negative_loops():
    tg = tag_loops([_square(0, 0, 2), _square(5, 0, 2, ccw=False)], 1e-3, 1e-3)
    rings = filled_rings(tg.paths(), "positive")
    assert len(rings) == 1 and ring_area(rings[0].q) * tg.grid ** 2 == pytest.approx(4.0)


def test_slivers_dropped_and_holes_filled():
    tg = tag_loops([_square(0, 0, 10), _square(2, 2, 3, ccw=False),
                    _square(12, 12, 1e-3 * 4, ccw=True)], 1e-4, 1e-3)
    rings = filled_rings(tg.paths(), "nonzero")
    assert sorted(r.hole for r in rings) == [False, False, True]
    thin = drop_slivers(rings, 1.5)  # the 4-unit square (mean width 2) is no sliver...
    assert len(thin) == 3
    assert len(drop_slivers(rings, 4.0)) == 2  # ...at a width threshold of 4 units it is
    hole = [i for i, r in enumerate(thin) if r.hole]
    assert len(fill_holes(thin, hole)) == 2


def test_paths_on_one_line_fill_nothing():
    # Clipper refuses a batch whose every path is invalid (collinear after rounding):
    # a stroke with a nib far below tol ended in its ClipperException (exit 1)
    import numpy as np

    flat = [np.array([[0, 0], [5, 5], [9, 9], [5, 5]], np.int64),
            np.array([[0, 3], [4, 3], [8, 3]], np.int64)]
    assert filled_rings(flat, "nonzero") == []
    square = np.array([[0, 0], [4, 0], [4, 4], [0, 4]], np.int64)
    rings = filled_rings(flat + [square], "nonzero")
    assert len(rings) == 1 and ring_area(rings[0].q) == 16


def test_sum_with_a_nib_far_below_tol_is_refused_with_a_suggestion():
    from morph.errors import LimitError
    from morph.stroke import stroke_paths

    path = [pc.line((0, 0), (50, 50)), pc.line((50, 50), (90, 10))]
    tiny = [[pc.line((0, 0), (1e-9, 0)), pc.line((1e-9, 0), (1e-9, 1e-9)),
             pc.line((1e-9, 1e-9), (0, 1e-9)), pc.line((0, 1e-9), (0, 0))]]
    with pytest.raises(LimitError, match="thinner than the tolerance") as err:
        stroke_paths([(path, False)], tiny, 1e-4)
    assert err.value.suggestion < 1e-4

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

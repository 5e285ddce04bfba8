"""morph.moments: areas exact for polynomial pieces and conics, orientation by sign."""

import numpy as np
import pytest

from morph import moments as mo
from morph import piece as pc


@pytest.mark.parametrize("r", [1.0, 0.37, 250.0])
def test_circle_area_exact(r):
    circle = pc.circle((3.0, -4.0), r)
    assert abs(mo.loop_area(circle) - np.pi * r * r) <= 1e-12 * np.pi * r * r
    ell = pc.ellipse((0.0, 0.0), 2 * r, r, 0.7)
    assert abs(mo.loop_area(ell) - 2 * np.pi * r * r) <= 1e-12 * 2 * np.pi * r * r


def test_polygon_area_exact_and_orientation():
    sq = [pc.line((0, 0), (2, 0)), pc.line((2, 0), (2, 3)), pc.line((2, 3), (0, 3)),
          pc.line((0, 3), (0, 0))]
    assert mo.loop_area(sq) == 6.0
    rev = [pc.reverse(p) for p in reversed(sq)]
    assert mo.loop_area(rev) == -6.0
    assert mo.region_area([sq, [pc.translate(p, (0.5, 0.5)) for p in
                                [pc.line((0, 0), (0, 1)), pc.line((0, 1), (1, 1)),
                                 pc.line((1, 1), (1, 0)), pc.line((1, 0), (0, 0))]]]) == 5.0

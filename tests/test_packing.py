"""morph.packing: regions laid out side by side, and results sorted back."""

import numpy as np
import pytest

from morph import piece as pc
from morph.packing import Packing, control_box


def _regions(rng, n):
    out = []
    for _ in range(n):
        c = rng.uniform(-50, 50, 2)
        out.append([pc.ellipse(c, rng.uniform(0.1, 20), rng.uniform(0.1, 5), rng.uniform(0, 3))])
    return out


@pytest.mark.parametrize("n", [1, 2, 5, 17])
def test_slots_are_disjoint_and_at_least_the_margin_apart(n):
    rng = np.random.default_rng(n)
    margin = np.array([3.0, 7.0])
    lay = Packing(_regions(rng, n), [-1.0, -2.0, 3.0, 1.0], margin)
    moved = np.array([control_box([lp]) for lp in lay.packed])
    reach = np.array([4.0, 3.0])  # the size of the reach box
    for i in range(n):
        # the slot box holds the moved region plus the reach box
        assert np.all(lay.slot_boxes[i, :2] <= moved[i, :2] + [-1.0, -2.0])
        assert np.all(lay.slot_boxes[i, 2:] >= moved[i, 2:] + [3.0, 1.0])
        for j in range(i + 1, n):
            gap_x = max(moved[j, 0] - moved[i, 2], moved[i, 0] - moved[j, 2])
            gap_y = max(moved[j, 1] - moved[i, 3], moved[i, 1] - moved[j, 3])
            assert (gap_x >= reach[0] + margin[0] - 1e-9) or (gap_y >= reach[1] + margin[1] - 1e-9)
            si, sj = lay.slot_boxes[i], lay.slot_boxes[j]
            half = 0.5 * margin - 1e-9
            assert (si[2] + half[0] <= sj[0] or sj[2] + half[0] <= si[0]
                    or si[3] + half[1] <= sj[1] or sj[3] + half[1] <= si[1])


def test_slot_of_points_and_split_round_trip():
    rng = np.random.default_rng(3)
    regions = _regions(rng, 9)
    lay = Packing(regions, [0.0, 0.0, 5.0, 5.0], 2.0)
    # every point within margin / 4 of a moved region plus the reach box is in its
    # slot, others in none
    for i, lp in enumerate(lay.packed):
        x0, y0, x1, y1 = control_box([lp])
        pts = rng.uniform([x0 - 0.49, y0 - 0.49], [x1 + 5.49, y1 + 5.49], (50, 2))
        assert (lay.slot_of(pts) == i).all()
    assert (lay.slot_of([[1e9, 1e9], [-1e9, 0.0]]) == -1).all()
    back = lay.split([lp for lp in reversed(lay.packed)])
    for r, b in zip(regions, back):
        assert len(b) == 1
        assert np.allclose(b[0][0], r[0][0], atol=1e-12)


def test_split_refuses_a_loop_outside_every_slot():
    lay = Packing(_regions(np.random.default_rng(1), 3), [0.0, 0.0, 1.0, 1.0], 1.0)
    far = [pc.translate(p, (1e6, 0.0)) for p in lay.packed[0]]
    with pytest.raises(ValueError, match="outside every slot"):
        lay.split([far])

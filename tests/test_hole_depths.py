"""morph.minkowski's hole test flattens for its point's depth: the answers against the
exact predicate (shapely on operands flattened far below tol, tests/oracles/membership).

A hole's point ``depth`` deep in its ring is at least depth - tol from the exact
boundary, and the flattened, rounded operands are within 0.14 of the key each
(:func:`morph.minkowski._membership_depths`): holes of a ring ⊕ disk, one filled (the
ring's hole smaller than the disk) and one not, tested at keys far coarser than tol.
"""

import numpy as np

from morph import minkowski
from morph import piece as pc
from tests.oracles.membership import Oracle


def _ring(r_out, r_in):
    return [pc.circle([0, 0], r_out), [pc.reverse(p) for p in pc.circle([0, 0], r_in)[::-1]]]


def _holes(ring, disk, tol):
    _, debug = minkowski.minkowski_sum_debug(ring, disk, tol)
    holes = debug["holes"]
    points = np.array([p for p, _, _ in holes], float).reshape(-1, 2)
    return points, np.array([d for _, d, _ in holes]), [f for _, _, f in holes]


def test_coarse_hole_tests_give_the_exact_answers():
    tol = 1e-4
    for r_in, r_disk, filled in ((3.0, 4.0, True), (6.0, 2.0, False)):
        ring, disk = _ring(10.0, r_in), [pc.circle([0, 0], r_disk)]
        points, depths, answers = _holes(ring, disk, tol)
        assert len(points) and answers == [filled] * len(points)
        keys = minkowski._membership_depths(depths, tol)
        assert np.all(keys >= 16 * tol)             # far coarser than tol / 10 flattenings
        assert np.all(0.28 * keys < depths - tol)   # the bound that makes them exact
        oracle = Oracle(ring, disk, 1e-7)
        assert list(oracle(points)) == answers
        # the check can fail: 2 tol beyond the exact hole's edge (radius r_in - r_disk)
        # the predicate answers True
        edge = max(r_in - r_disk, 0.0) + 2 * tol
        assert bool(oracle(np.array([[edge, 0.0]]))[0])


def test_membership_depths_are_no_finer_than_tol_and_no_coarser_than_the_depth_allows():
    tol = 0.5
    depths = np.array([0.01, 0.3, 0.5, 1.0, 1.4, 1.6, 4.0, 40.0, 1e6])
    keys = minkowski._membership_depths(depths, tol)
    # shallow points keep a tenth of min(depth, tol) (down to tol / 8)
    old = tol * 2.0 ** np.clip(np.floor(np.log2(depths / tol)), -3, 0)
    assert np.all(keys >= old)
    assert np.all(keys[depths < 3 * tol] == old[depths < 3 * tol])
    deep = depths >= 3 * tol
    assert np.all(0.28 * keys[deep] < depths[deep] - tol)
    assert np.all(keys <= minkowski.HOLE_COARSEST * tol)
    assert np.allclose(np.log2(keys / tol), np.round(np.log2(keys / tol)))   # shared keys

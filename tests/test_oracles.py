"""The oracles can fail: a wrong answer is rejected by the same check that passes the
right one (a check that passes everything would prove nothing)."""

import numpy as np
import pytest

from tests.oracles import need

need("shapely", "the membership predicate")

from morph.minkowski import minkowski_sum  # noqa: E402 - after the check above
from morph.parse import glyph_region  # noqa: E402
from morph.region import translate_region  # noqa: E402
from tests.oracles.membership import Oracle, boundary_samples, straddle  # noqa: E402

TOL = 1.0      # font units (1e-3 em)
FLAT = 0.01    # the oracle's flattening of the operands
N = 40         # boundary samples probed


@pytest.fixture(scope="module")
def case():
    a, b = glyph_region("T").region, glyph_region("o").region
    return a, b, Oracle(a, b, FLAT), minkowski_sum(a, b, TOL)


def straddles(oracle, loops):
    """Per sampled boundary point: the exact sum has points in and out within tol."""
    pts, nrm = boundary_samples(loops, per_piece=1)
    pick = np.random.default_rng(0).choice(len(pts), min(N, len(pts)), replace=False)
    inside = straddle(oracle, pts[pick], nrm[pick], TOL + 2 * FLAT)
    return inside.any(axis=1) & (~inside).any(axis=1)


def test_the_straddle_check_passes_the_sum(case):
    _, _, oracle, loops = case
    assert straddles(oracle, loops).all()


@pytest.mark.parametrize("dx, dy", [(2 * TOL, 0.0), (0.0, -2 * TOL), (1.5 * TOL, 1.5 * TOL)])
def test_the_straddle_check_rejects_the_sum_moved_by_2_tol(case, dx, dy):
    _, _, oracle, loops = case
    assert not straddles(oracle, translate_region(loops, (dx, dy))).all()


def test_the_membership_predicate_rejects_a_wrong_operand(case):
    a, _, oracle, _ = case
    wrong = minkowski_sum(a, glyph_region("c").region, TOL)   # o with a gap: c
    assert not straddles(oracle, wrong).all()


def test_reference_distance_at_thin_notch_tips():
    """The coarse polygon reference's notch tips run on (its walls move by its
    flattening error e, a tip of angle phi by e / sin(phi / 2)); reference_distance
    then judges against a reference 25 times finer.  Generated squares with a thin
    V notch (1.5-3 degrees, random depth and turn) ⊕ a small disk: some coarse
    distances exceed the old limit, every sum passes, and the sum moved by twice
    the limit fails."""
    import math

    import shapely.affinity

    from morph import piece as pc
    from tests.oracles import reference as R
    from tests.oracles.sweep import REF_TOL, reference_distance

    rng = np.random.default_rng(11)
    tol, overshoots = 0.1, 0
    for _ in range(8):
        phi, depth = math.radians(rng.uniform(1.5, 3.0)), rng.uniform(600, 900)
        half = depth * math.tan(phi / 2)
        pts = np.array([(0, 0), (2000, 0), (2000, 1000), (1000 + half, 1000),
                        (1000, 1000 - depth), (1000 - half, 1000), (0, 1000)], float)
        turn = rng.uniform(0, 2 * math.pi)
        pts = pts @ np.array([[math.cos(turn), math.sin(turn)],
                              [-math.sin(turn), math.cos(turn)]])
        a = [[pc.line(pts[k], pts[(k + 1) % len(pts)]) for k in range(len(pts))]]
        b = [pc.circle((0.0, 0.0), rng.uniform(4, 8))]
        ours = R.region_to_shapely(minkowski_sum(a, b, tol), tol / 4)
        ref = R.polygon_minkowski_sum(a, b, REF_TOL)
        overshoots += R.hausdorff(ours, ref, spacing=2.0) > tol + REF_TOL + 1.0
        h, limit = reference_distance(ours, a, b, tol, ref)
        assert h <= limit
        moved = shapely.affinity.translate(ours, 2 * limit, 0.0)
        h, limit = reference_distance(moved, a, b, tol, ref)
        assert h > limit
    assert overshoots >= 2

"""The error budget: one split of a writer's tolerance, and the export's share."""

import pytest

from morph import budget
from morph.budget import SUM_SHARE, export_tolerance, plan


def test_plan_splits_the_total():
    b = plan(1e-4)
    assert b.geometry + b.export == pytest.approx(1e-4, rel=1e-15) and b.total == 1e-4
    assert b.geometry == pytest.approx(SUM_SHARE * 1e-4) and 0 < SUM_SHARE <= 0.5
    assert (b.cubic, b.cu2qu) == (b.export, 0.0)
    assert plan(1.0, share=0.25)[:2] == (0.25, 0.75)
    q = plan(1.0, quadratic=True)
    assert q.cubic == budget.QUADRATIC_CUBIC_SHARE * 0.75 and q.cubic + q.cu2qu == 0.75
    for bad in (0.0, -1.0, float("nan"), float("inf")):
        with pytest.raises(ValueError):
            plan(bad)
    with pytest.raises(ValueError):
        plan(1.0, share=1.0)


def test_export_tolerance():
    assert export_tolerance(1.0, 0.25) == 0.75 and export_tolerance(1e-4, 0.0) == 1e-4
    assert plan(1.0).after(0.1) == 0.9
    for tol, bound in ((0.0, 0.0), (1.0, 1.0), (1.0, -0.1), (float("nan"), 0.0),
                       (1.0, float("nan"))):
        with pytest.raises(ValueError):
            export_tolerance(tol, bound)


def test_sum_shares_add_up_to_one():
    """A sum's tolerance is spent on the convolution, the flattening, the grid and
    the contraction, nothing more (morph.minkowski)."""
    total = budget.CONV_SHARE + budget.FLAT_SHARE + budget.GRID_SHARE + budget.CONTRACT_SHARE
    assert total == pytest.approx(1.0, rel=1e-15)
    for share in (budget.FIRST_SHARE, budget.TIP_MARGIN, budget.RETRY_SHARE, budget.TURN_SHARE,
                  budget.POLYGON_SHARE, budget.ROUND_SHARE, budget.PHI_SHARE,
                  budget.QUADRATIC_CUBIC_SHARE):
        assert 0.0 < share <= 1.0

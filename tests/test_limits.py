"""morph.limits: the library's tolerance validation (the CLI's guards are in
tests/test_hostile.py)."""

import pytest

from morph.parse import svg_region
from tests.helpers import square_path_data


def test_check_tolerance_library():
    """The library's validation function: same rules, LimitError (a ValueError)."""
    from morph.errors import LimitError
    from morph.limits import check_tolerance

    sq = svg_region(square_path_data(0, 0, 10))
    assert check_tolerance(1e-3, sq, sq) > 0
    for tol, word in [(0, "positive"), (float("nan"), "positive"), (100, "larger"),
                      (1e-13, "at least")]:
        with pytest.raises(LimitError, match=word):
            check_tolerance(tol, sq, sq)
    far = svg_region(square_path_data(1e12, 0, 10))  # far from the origin: fp resolution
    with pytest.raises(LimitError, match="floating-point resolution") as info:
        check_tolerance(1e-5, far)
    assert info.value.suggestion > 1e-5


def test_point_estimate_and_extent_of_mixed_pieces():
    """estimate_points: one point per line and ceil(sqrt(n (n-1) max|second
    difference| / (8 tol))) per curve (the chord bound of uniform steps), summed over
    pieces of any degree and kind; region_extent: the control points' box side and
    largest |coordinate|, LimitError for NaN."""
    import math

    import numpy as np

    from morph import piece as pc
    from morph.errors import LimitError
    from morph.limits import estimate_points, region_extent

    loop = ([pc.line((0, 0), (40, 0)), pc.quadratic((40, 0), (60, 10), (40, 20)),
             pc.cubic((40, 20), (30, 40), (10, 40), (0, 20))] + pc.circle((5, 5), 3.0)[:2]
            + [pc.line((0, 20), (0, 0))])
    tol = 1e-3
    want = 0
    for p in loop:
        c = pc.cartesian(p)
        n = len(c) - 1
        dd = np.abs(np.diff(c, 2, axis=0)).max() * n * (n - 1) if n >= 2 else 0.0
        want += math.ceil(math.sqrt(dd / (8 * tol))) if dd > 0 else 1
    assert estimate_points([loop], tol) == want
    size, mag = region_extent([loop])
    pts = np.concatenate([pc.cartesian(p) for p in loop])
    assert size == np.ptp(pts, axis=0).max() and mag == np.abs(pts).max()
    assert region_extent([]) == (0.0, 0.0)
    bad = [pc.line((0, 0), (float("nan"), 1.0)), pc.line((float("nan"), 1.0), (0, 0))]
    with pytest.raises(LimitError, match="non-finite"):
        region_extent([bad])


@pytest.mark.parametrize("chars,unit", [("og", 1000.0), ("&g", 1000.0), ("MW", 1.0)])
def test_the_suggested_tolerance_passes_the_budget(chars, unit):
    # the suggestion was tol x (points / budget)^2 printed to two digits: the lines'
    # one point per piece and the rounding down made it fail again (o + g at 1e-9 em
    # suggested 7.7e-09, refused again at 7.7e-09)
    from morph.errors import LimitError
    from morph.limits import check_tolerance
    from morph.parse import glyph_region

    a, b = (glyph_region(c).region for c in chars)
    for tol_em in (1e-9, 1e-8, 3e-8):
        try:
            check_tolerance(tol_em * unit, a, b, unit=unit, unit_name="em")
            continue
        except LimitError as exc:
            suggested = float(str(exc).split("at least ")[1].split()[0])
            assert suggested * unit == pytest.approx(exc.suggestion, rel=1e-9)
        assert check_tolerance(suggested * unit, a, b, unit=unit) > 0   # as printed

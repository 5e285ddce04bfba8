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

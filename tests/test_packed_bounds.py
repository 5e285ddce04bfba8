"""The ``bound`` of each region of morph.minkowski.minkowski_sums, which morph brush's
curve conversion takes the rest of tol from (morph.budget.Budget.after): an upper
bound of what each sum achieves alone (:func:`morph.minkowski._achieved_bound`), and
half the sum's tol where the convolution is exact (TrueType glyphs ⊕ an ellipse)."""

import pytest

from morph import minkowski
from morph.budget import CONV_SHARE, plan
from morph.fonts.brush import _export_tolerance, ellipse_nib
from morph.parse import cubic_test_font_path, default_font_path, glyph_region

NIB = (80, 30, 30)
CHARS = "oTgSWe8"


@pytest.mark.parametrize("font", [default_font_path(), cubic_test_font_path()])
def test_packed_bounds_hold_each_sums_own(font):
    tol = 0.125
    regions = [glyph_region(ch, font=font).region for ch in CHARS]
    nib = ellipse_nib(*NIB)
    packed = minkowski.minkowski_sums(regions, nib, tol)
    for ch, region, got in zip(CHARS, regions, packed):
        alone = minkowski.minkowski_sum(region, nib, tol).bound
        assert alone <= got.bound <= tol, ch
    if font == default_font_path():   # quadratics ⊕ a conic: exact QAC pieces
        assert all(r.bound == pytest.approx((1.0 - CONV_SHARE) * tol, rel=1e-6)
                   for r in packed)


def test_brush_converts_within_what_the_sums_leave():
    tol = 0.5
    g = plan(tol).geometry
    regions = [glyph_region(ch).region for ch in CHARS]
    done = list(enumerate(minkowski.minkowski_sums(regions, ellipse_nib(*NIB), g)))
    export = _export_tolerance(tol, done)
    assert export + max(r.bound for _, r in done) <= tol   # the triangle inequality's sum
    assert export == pytest.approx(tol - (1.0 - CONV_SHARE) * g, rel=1e-6)
    assert export > plan(tol).export

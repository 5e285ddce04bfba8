"""morph.compatible: untrimmed convolutions with ellipses, fitted compatibly.

The nonzero fill of the untrimmed loops is checked against the exact membership
predicate (tests/oracles/varfont.py) at random points, for skeleton glyphs and
filled glyphs, and the check is shown to fail on a displaced outline."""

import numpy as np
import pytest

from morph.compatible import (Ellipse, IncompatibleMasters, blend_nib, convolve_masters,
                              fit_elements, interpolation_error, region_elements,
                              skeleton_elements)
from tests.oracles.varfont import bezier_points, classify_against_predicate

TOL = 0.3


def _lines(paths):
    out = []
    for pieces, _ in paths:
        pts = [bezier_points(np.asarray(p, float)[:, :2], 256) for p in pieces]
        out.append(np.vstack(pts))
    return out


def _points(loops, n, seed):
    pts = np.vstack([lp.reshape(-1, 2) for lp in loops])
    lo, hi = pts.min(axis=0) - 5, pts.max(axis=0) + 5
    return np.random.default_rng(seed).uniform(lo, hi, size=(n, 2))


@pytest.mark.parametrize("name,nib", [("a", (80, 20, 30)), ("g", (120, 30, -20)),
                                      ("s", (40, 10, 30)), ("e", (60, 60, 0)),
                                      ("period", (90, 20, 70))])
def test_skeleton_winding_is_the_sum(skeleton, name, nib):
    """Winding of the untrimmed loops >= 0 everywhere and >= 1 exactly on
    skeleton ⊕ nib (points decided by more than 2 tol)."""
    paths = _skeleton_paths(skeleton, name)
    loops = convolve_masters([paths], [Ellipse(*nib)], tol=TOL)[0]
    pts = _points(loops, 3000, seed=hash(name) % 1000)
    checked, wrong, negative = classify_against_predicate(pts, loops, _lines(paths), nib,
                                                          margin=2 * TOL)
    assert checked > 2000
    assert wrong == 0 and negative == 0
    # the oracle can fail: the outline moved by 2 margins (in the nib's metric, where
    # points are decided) misclassifies points
    shift = 4 * 2 * TOL * max(nib[:2]) / min(nib[:2])
    moved = [lp + np.array([shift, shift]) for lp in loops]
    assert classify_against_predicate(pts, moved, _lines(paths), nib, 2 * TOL)[1] > 0


def _skeleton_paths(font, name):
    from morph.parse.ufo import decomposed_paths

    return decomposed_paths(font, name)


@pytest.mark.parametrize("char,nib", [("g", (80, 20, 30)), ("a", (80, 20, 30)),
                                      ("O", (80, 20, 30)), ("B", (50, 50, 0))])
def test_region_winding_is_the_sum(char, nib):
    """A filled glyph (bundled Noto Sans) ⊕ ellipse: untrimmed loops filled nonzero
    equal the sum (the region's inside or within the nib of its boundary)."""
    from morph.parse import glyph_region

    shape = glyph_region(char)
    loops_in = [[np.asarray(p, float) for p in loop] for loop in shape.region]
    loops = fit_elements(region_elements([loops_in]), [Ellipse(*nib)], tol=TOL)[0]
    boundary = [np.vstack([bezier_points(p[:, :2] / p[:, 2:], 128) for p in loop])
                for loop in loops_in]
    pts = _points(loops, 3000, seed=7)
    checked, wrong, negative = classify_against_predicate(
        pts, loops, [np.vstack([b, b[:1]]) for b in boundary], nib, 2 * TOL,
        region=boundary)
    assert checked > 2000 and wrong == 0 and negative == 0


def test_masters_are_compatible_and_uniform_scale_is_exact(skeleton):
    """Nibs of one aspect and angle fitted together: the same structure, and the
    middle master is exactly the mean of the outer two (x = c + s E_1: the axis
    interpolates exactly); with the angle changed it is not (the check can fail)."""
    paths = _skeleton_paths(skeleton, "a")
    small, big = Ellipse(40, 10, 30), Ellipse(120, 30, 30)
    m0, mid, m1 = convolve_masters([paths], [small, blend_nib(small, big, 0.5), big],
                                   tol=TOL)
    assert [lp.shape for lp in m0] == [lp.shape for lp in m1] == [lp.shape for lp in mid]
    assert max(float(np.abs((a + b) / 2 - c).max()) for a, b, c in zip(m0, m1, mid)) < 1e-9
    assert interpolation_error(small, big) < 1e-12
    turned = Ellipse(120, 30, 60)
    m0, mid, m1 = convolve_masters([paths], [small, blend_nib(small, turned, 0.5), turned],
                                   tol=TOL)
    assert max(float(np.abs((a + b) / 2 - c).max()) for a, b, c in zip(m0, m1, mid)) > 1.0


def test_nonuniform_blend_is_measured():
    """An angle change does not interpolate: the blend error is positive and shrinks
    four times when the interval halves (second order)."""
    a, b = Ellipse(80, 20, 0), Ellipse(80, 20, 8)
    e1 = interpolation_error(a, b)
    e2 = interpolation_error(a, blend_nib(a, b, 0.5))
    assert e1 > 1.0
    assert 3.5 < e1 / e2 < 4.5


def test_incompatible_masters_name_the_difference():
    from morph import piece as pc

    p = [([pc.line((0, 0), (100, 0))], False)]
    q = [([pc.quadratic((0, 0), (50, 50), (100, 0))], False)]
    with pytest.raises(IncompatibleMasters, match="degree 2 in master 1, 1 in master 0"):
        skeleton_elements([p, q], label="glyph 'x'")
    with pytest.raises(IncompatibleMasters, match="master 1 has 2 paths"):
        skeleton_elements([p, p + p])

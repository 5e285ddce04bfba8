"""morph.minkowski: the error budget at sharp corners of the boundary.

Where the boundary turns by phi at a junction of two approximated pieces, each
within e of its exact curve, the junction can be e / cos(phi / 2) from the exact
corner.  ``minkowski_sum`` approximates the pairs through such corners again until
e / cos(phi / 2) fits the convolution share of tol.  Checked here with corners
and distances measured independently of the library (finite differences of dense
samples, nearest sampled points), on glyph pairs where the first pass leaves
corners whose pieces are too coarse (S + g of the bundled CFF font: a 132 degree turn whose pieces had
e = 0.73 tol).
"""

import numpy as np
import pytest

from morph import minkowski, parse
from morph import piece as pc

TOL = 0.1  # font units (1e-4 em)


def _region(ch):
    """A glyph of the bundled CFF font (cubic: its QAC pieces have nonzero bounds)."""
    return parse.glyph_region(ch, parse.cubic_test_font_path()).region


def _corners(loops):
    """(points, cos(phi / 2)) at every junction, tangents from samples 1e-6 apart."""
    pts, cos_half = [], []
    h = 1e-6
    for loop in loops:
        for k, p in enumerate(loop):
            q = loop[(k + 1) % len(loop)]
            a = pc.evaluate(p, np.array([1.0 - h, 1.0]))
            b = pc.evaluate(q, np.array([0.0, h]))
            ta, tb = a[1] - a[0], b[1] - b[0]
            c = ta @ tb / (np.linalg.norm(ta) * np.linalg.norm(tb))
            pts.append(a[1])
            cos_half.append(np.sqrt(max(0.0, 0.5 * (1.0 + c))))
    return np.array(pts), np.array(cos_half)


@pytest.mark.parametrize("a, b", [("S", "g"), ("e", "s"), ("B", "8")])
def test_pieces_through_sharp_corners_fit_the_budget(a, b):
    ra, rb = _region(a), _region(b)
    out, dbg = minkowski.minkowski_sum(ra, rb, TOL, return_debug=True)
    conv = dbg["convolution"]
    samples = [pc.evaluate(c.piece, np.linspace(0.0, 1.0, 4001)) for c in conv]
    pts, cos_half = _corners(out)
    budget = minkowski.CONV_SHARE * TOL
    checked = 0
    for x, c in zip(pts, cos_half):
        for piece, s in zip(conv, samples):
            if np.hypot(*(s - x).T).min() <= 0.3 * TOL:
                assert piece.bound <= budget * max(c, minkowski.TIP_FLOOR) * (1 + 1e-9), (
                    "piece of bound %.3g tol through a corner of cos(phi/2) = %.3f at %s"
                    % (piece.bound / TOL, c, x))
                checked += c < 1 - 1e-6
    assert checked > 0


def test_s_plus_g_needed_the_second_pass():
    # the case above can fail: without the second pass its corner is too coarse
    ra, rb = _region("S"), _region("g")
    old = minkowski.TIP_ROUNDS
    try:
        minkowski.TIP_ROUNDS = 0
        out, dbg = minkowski.minkowski_sum(ra, rb, TOL, return_debug=True)
    finally:
        minkowski.TIP_ROUNDS = old
    pts, cos_half = _corners(out)
    worst = max(c.bound for c in dbg["convolution"])
    assert (worst / cos_half.clip(1e-3) > minkowski.CONV_SHARE * TOL).any()

"""morph.render.svg: SVG path data and documents, parsed back by morph.parse."""

import re

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph.parse import glyph_region, svg_region
from morph.region import region_bbox, reverse_loop
from morph.render import svg_path_data, write_svg
from morph.budget import ROUND_SHARE


def test_svg_path_data_round_trip():
    """Parse our own SVG back: same region (y flipped twice) within tol."""
    circle_hole = [pc.circle((5, 5), 4.0), reverse_loop(pc.circle((5, 5), 1.0))]
    g = glyph_region("g").region
    for loops, tol in [(circle_hole, 1e-6), (g, 1e-3)]:
        d = svg_path_data(loops, tol)
        assert d.startswith("M") and d.count("M") == len(loops) and d.count("Z") == len(loops)
        back = svg_region(d)
        assert len(back) == len(loops)
        ref = mo.region_area(loops)
        assert abs(mo.region_area(back) - ref) <= 1e-6 * abs(ref) + 10 * tol
        assert np.allclose(region_bbox(back), region_bbox(loops), atol=tol)
    # polynomial input is written exactly: lines as L, quadratics as Q
    d = svg_path_data(g, 1e-3)
    assert "Q" in d and "L" in d and "C" not in d
    assert "C" in svg_path_data(circle_hole, 1e-3)


def _written_beziers(d):
    """The Béziers of path data as svgpathtools reads them (an independent parser:
    it implies T / S control points itself), y up again."""
    pytest.importorskip("svgpathtools")
    from svgpathtools import parse_path
    return [np.array([(p.real, -p.imag) for p in seg.bpoints()]) for seg in parse_path(d)]


def _quad_loop(kink):
    """Two quadratics joined at (2, 0) (smooth when kink = 0: the second's control
    point is the first's reflected) closed by a line."""
    a = [[0, 0, 1], [1, 1, 1], [2, 0, 1]]
    b = [[2, 0, 1], [3, -1 - kink, 1], [4, 0, 1]]
    return [[np.array(a, float), np.array(b, float), np.array([[4, 0, 1], [0, 0, 1]], float)]]


def test_reflected_controls_are_written_T_or_S_and_read_back_exactly():
    """T / S only where the reader's implied control point is the one Q / C would
    write: svgpathtools' Béziers equal the exported ones rounded to the written
    decimals (rounding moves a point by at most r)."""
    from morph.export import loops_to_beziers
    from morph.render.svg import rounding
    g = glyph_region("o").region  # TrueType quadratics with implied on-curve points
    for loops, tol, letter in [(g, 1e-3, "T"), (_quad_loop(0.0), 1e-2, "T"),
                               (_quad_loop(1e-9), 1e-2, "T")]:
        d = svg_path_data(loops, tol)
        assert letter in d
        _, r = rounding(tol)
        ref = [b for loop in loops_to_beziers(loops, tol - r, wrap=True) for b in loop]
        got = _written_beziers(d)
        assert len(got) == len(ref)
        assert max(np.abs(x - y).max() for x, y in zip(got, ref)) <= r
    # off by more than the written decimals: Q with its control point
    d = svg_path_data(_quad_loop(0.02), 1e-2)
    assert "T" not in d and d.count("Q") == 2
    # a cubic after a cubic with a reflected control point: S
    c1 = np.array([[0, 0, 1], [1, 1, 1], [2, 1, 1], [3, 0, 1]], float)
    c2 = np.array([[3, 0, 1], [4, -1, 1], [5, 0, 1], [6, 0, 1]], float)
    line = np.array([[6, 0, 1], [0, 0, 1]], float)
    d = svg_path_data([[c1, c2, line]], 1e-3)
    assert "S" in d and d.count("C") == 1
    got = _written_beziers(d)
    assert np.allclose(got[1], c2[:, :2], atol=1e-3)


def test_T_commands_store_fewer_points_than_the_quadratics():
    """A TrueType glyph's quadratics stored as the font stores them: one point per
    quadratic in a smooth run, as its implied on-curve points do."""
    d = svg_path_data(glyph_region("o").region, 1e-3)
    stored = len(re.findall(r"-?[0-9.]+", d)) // 2
    assert stored < len(_written_beziers(d)) * 2 * 0.75


def test_svg_path_data_decimals_follow_tol():
    loops = [pc.circle((0, 0), 1.0)]
    coarse = svg_path_data(loops, 1e-2)
    fine = svg_path_data(loops, 1e-7)
    # rounding to d decimals moves a point by 0.5 10^-d sqrt 2: at most the rounding
    # share of tol, and one decimal fewer would exceed it
    for tol, d in ((1e-2, coarse), (1e-7, fine)):
        places = max(len(tok.split(".")[-1]) for tok in re.split("[MLQTCSZ ]", d) if "." in tok)
        assert 0.5 * 10.0 ** -places * 2 ** 0.5 <= ROUND_SHARE * tol
        assert 0.5 * 10.0 ** (1 - places) * 2 ** 0.5 > ROUND_SHARE * tol
    assert len(fine) > len(coarse)
    with pytest.raises(ValueError):
        svg_path_data(loops, 0)


def test_write_svg_document(tmp_path):
    out = tmp_path / "x.svg"
    write_svg(out, [(glyph_region("o").region, {"fill": "red", "stroke": "black"})],
              size=300, background="white")
    text = out.read_text()
    assert 'fill-rule="nonzero"' in text and 'fill="red"' in text and 'stroke="black"' in text
    assert 'height="300"' in text and "viewBox=" in text and "<rect" in text
    # our own file parses back: the filled union is the background rect; the glyph's
    # element alone is its outer loop and hole
    assert len(svg_region(out)) == 1
    from morph.parse import svg_elements
    rect, glyph = svg_elements(out)
    assert glyph.filled and glyph.stroked and len(glyph.subpaths) == 2


def test_frames_fitted_in_one_batch_stay_within_each_tolerance():
    """fitted_regions converts several regions' curves in one batch; each region's
    SVG written from its fitted Béziers at its own tol is within that tol of the
    region: circles (rational arcs, which must be fitted) at random centres, radii
    and tolerances, the written path read back by an independent parser and its
    points' distance to the exact circle measured (moving them by 2 tol fails)."""
    from math import comb

    from morph.render.svg import fitted_regions

    rng = np.random.default_rng(7)
    regions, tols, circles = [], [], []
    for _ in range(6):
        c, r = rng.uniform(-50, 50, 2), 10.0 ** rng.uniform(-1, 2)
        hole = r * rng.uniform(0.2, 0.8)
        regions.append([pc.circle(c, r), reverse_loop(pc.circle(c, hole))])
        tols.append(r * 10.0 ** rng.uniform(-5, -2))
        circles.append((c, r, hole))
    fitted = fitted_regions(regions, tols)
    for loops, tol, (c, r, hole) in zip(fitted, tols, circles):
        assert all(len(p) <= 4 and np.all(p[:, 2] == 1.0) for loop in loops for p in loop)
        d = svg_path_data(loops, tol)
        assert d.count("C") + d.count("S") == sum(map(len, loops))   # written as they are
        t = np.linspace(0.0, 1.0, 41)[:, None]
        worst, moved = 0.0, 0.0
        for b in _written_beziers(d):
            n = len(b) - 1
            pts = sum(comb(n, k) * t ** k * (1 - t) ** (n - k) * b[k] for k in range(n + 1))
            rho = np.hypot(*(pts - c).T)
            err = np.minimum(abs(rho - r), abs(rho - hole))
            worst = max(worst, err.max())
            rho2 = np.hypot(*(pts + [2 * tol, 0.0] - c).T)
            moved = max(moved, np.minimum(abs(rho2 - r), abs(rho2 - hole)).max())
        assert worst <= tol and moved > tol

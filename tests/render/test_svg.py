"""morph.render.svg: SVG path data and documents, parsed back by morph.parse."""

import re

import numpy as np
import pytest

from morph import piece as pc
from morph.parse import glyph_region, svg_region
from morph.region import region_bbox, reverse_loop
from morph.render import svg_path_data, write_svg
from morph.render.svg import ROUND_SHARE


def test_svg_path_data_round_trip():
    """Parse our own SVG back: same region (y flipped twice) within tol."""
    circle_hole = [pc.circle((5, 5), 4.0), reverse_loop(pc.circle((5, 5), 1.0))]
    g = glyph_region("g").region
    for loops, tol in [(circle_hole, 1e-6), (g, 1e-3)]:
        d = svg_path_data(loops, tol)
        assert d.startswith("M") and d.count("M") == len(loops) and d.count("Z") == len(loops)
        back = svg_region(d)
        assert len(back) == len(loops)
        ref = pc.region_area(loops)
        assert abs(pc.region_area(back) - ref) <= 1e-6 * abs(ref) + 10 * tol
        assert np.allclose(region_bbox(back), region_bbox(loops), atol=tol)
    # polynomial input is written exactly: lines as L, quadratics as Q
    d = svg_path_data(g, 1e-3)
    assert "Q" in d and "L" in d and "C" not in d
    assert "C" in svg_path_data(circle_hole, 1e-3)


def test_svg_path_data_decimals_follow_tol():
    loops = [pc.circle((0, 0), 1.0)]
    coarse = svg_path_data(loops, 1e-2)
    fine = svg_path_data(loops, 1e-7)
    # rounding to d decimals moves a point by 0.5 10^-d sqrt 2: at most the rounding
    # share of tol, and one decimal fewer would exceed it
    for tol, d in ((1e-2, coarse), (1e-7, fine)):
        places = max(len(tok.split(".")[-1]) for tok in re.split("[MLQCZ ]", d) if "." in tok)
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

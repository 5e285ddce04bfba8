"""morph.render.svg: SVG path data and documents, parsed back by morph.parse."""

import numpy as np
import pytest

from morph import piece as pc
from morph.parse import glyph_region, svg_region
from morph.region import region_bbox, reverse_loop
from morph.render import svg_path_data, write_svg


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
    assert max(len(tok.split(".")[-1]) for tok in coarse.replace("C", " ").split()
               if "." in tok) <= 3
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

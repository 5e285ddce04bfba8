"""Offsets: region ⊕ disk(R); every boundary sample lies at distance R from the input."""

import re

import numpy as np
import pytest
from click.testing import CliRunner
from shapely.geometry import LineString, MultiLineString, Point

from morph import piece as pc
from morph.cli import main
from morph.offset import offset_region
from morph.parse import glyph_region, svg_region
from tests.reference import region_polylines

SVG = """<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 200 200">
<path d="M 20 100 C 20 40 80 20 100 60 C 120 20 180 40 180 100 C 180 150 130 150 100 180
         C 70 150 20 150 20 100 Z"/></svg>"""


def boundary_lines(region, tol):
    return MultiLineString([LineString(np.vstack([p, p[:1]]))
                            for p in region_polylines(region, tol)])


def boundary_samples(region, n_per_piece=12):
    pts = [pc.evaluate(p, np.linspace(0, 1, n_per_piece, endpoint=False))
           for loop in region for p in loop]
    return np.vstack(pts)


def check_offset(region, radius, tol):
    out = offset_region(region, radius, tol)
    flat = tol / 20
    lines = boundary_lines(region, flat)
    pts = boundary_samples(out)
    d = np.array([lines.distance(Point(p)) for p in pts])
    # result within tol of the exact offset; input flattened within flat
    assert np.abs(d - radius).max() <= tol + flat + 1e-9, np.abs(d - radius).max()
    return out


@pytest.mark.parametrize("char,radius", [("o", 40.0), ("e", 45.0)])
def test_glyph_offset_at_distance_r(char, radius):
    region = glyph_region(char).region
    out = check_offset(region, radius, 0.2)
    assert len(out) == 2  # the hole survives, smaller
    assert pc.region_area(out) > pc.region_area(region)


def test_svg_offset_at_distance_r():
    region = svg_region(SVG)
    out = check_offset(region, 7.5, 0.01)
    assert len(out) == 1


def test_hole_kept_at_radius_30():
    out = offset_region(glyph_region("o").region, 30.0, 0.2)
    assert len(out) == 2


def test_large_radius_closes_hole():
    out = offset_region(glyph_region("o").region, 200.0, 0.5)
    assert len(out) == 1


def test_zero_and_negative_radius():
    region = glyph_region("o").region
    assert offset_region(region, 0.0, 0.1) == region
    with pytest.raises(ValueError, match="not supported"):
        offset_region(region, -5.0, 0.1)


def test_cli_offset(tmp_path):
    runner = CliRunner()
    out = tmp_path / "o.png"
    r = runner.invoke(main, ["offset", "o", "--radius", "0.03", "-o", str(out),
                             "--size", "64"])
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 0
    r = runner.invoke(main, ["offset", "o", "--radius", "-0.03", "-o",
                             str(tmp_path / "n.png")])
    assert r.exit_code == 2
    assert "not supported" in r.output


def test_offset_bound_and_the_written_svg(tmp_path):
    """offset_region's achieved bound (return_bound) is at most its tol, 0 at radius
    0; `morph offset -o x.svg` writes its export with the rest of --tol, and the
    written outline (svgpathtools samples, y flipped back) is within --tol of the
    exact offset of the SVG shape: distance to its boundary = radius (the shape
    flattened within tol / 20)."""
    from svgpathtools import parse_path

    region = svg_region(SVG)
    out, bound = offset_region(region, 7.5, 0.01, return_bound=True)
    plain = offset_region(region, 7.5, 0.01)
    assert [len(lp) for lp in out] == [len(lp) for lp in plain]
    assert all(np.array_equal(p, q) for lp, lq in zip(out, plain) for p, q in zip(lp, lq))
    assert 0.0 < bound <= 0.01
    assert offset_region(region, 0.0, 0.01, return_bound=True)[1] == 0.0
    src = tmp_path / "shape.svg"
    src.write_text(SVG)
    dst = tmp_path / "grown.svg"
    tol = 0.04
    r = CliRunner().invoke(main, ["offset", str(src), "--radius", "7.5", "--tol", str(tol),
                                  "-o", str(dst)])
    assert r.exit_code == 0, r.output
    paths = re.findall(r' d="([^"]+)"', dst.read_text())
    grown = parse_path(paths[0])
    z = np.array([seg.point(t) for seg in grown for t in np.linspace(0, 1, 17)])
    lines = boundary_lines(region, tol / 20)
    d = np.array([lines.distance(Point(x, -y)) for x, y in zip(z.real, z.imag)])
    assert np.abs(d - 7.5).max() <= tol + tol / 20 + 1e-9


def test_radius_far_below_tol_returns_the_region():
    # a disk of radius 1e-300 has no curve of nonzero length ("loop has no curve of
    # nonzero length", naming no input); the region is within r of its offset
    from morph.offset import offset_region
    from morph.parse import glyph_region

    o = glyph_region("o").region
    for r in (1e-300, 1e-12):
        out, bound = offset_region(o, r, 0.05, return_bound=True)
        assert bound == r and pc.region_area(out) == pytest.approx(pc.region_area(o))
    out, bound = offset_region(o, 1e-6, 0.05, return_bound=True)  # computed: area grows
    assert pc.region_area(out) > pc.region_area(o) and bound <= 0.05

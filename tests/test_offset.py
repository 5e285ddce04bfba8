"""Offsets: region ⊕ disk(R); every boundary sample lies at distance R from the input."""

import re

import numpy as np
import pytest
pytest.importorskip("shapely")
import shapely
from click.testing import CliRunner
from shapely.geometry import LineString, MultiLineString, Point

from morph import piece as pc
from morph import moments as mo
from morph.cli import main
from morph.offset import inset_region, offset_region
from morph.parse import glyph_region, svg_region
from tests.oracles.reference import region_polylines

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
    d = shapely.distance(shapely.points(pts), lines)
    # result within tol of the exact offset; input flattened within flat
    assert np.abs(d - radius).max() <= tol + flat + 1e-9, np.abs(d - radius).max()
    return out


@pytest.mark.parametrize("char,radius", [("o", 40.0), ("e", 45.0)])
def test_glyph_offset_at_distance_r(char, radius):
    region = glyph_region(char).region
    out = check_offset(region, radius, 0.2)
    assert len(out) == 2  # the hole survives, smaller
    assert mo.region_area(out) > mo.region_area(region)


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


def test_zero_and_bad_radius():
    region = glyph_region("o").region
    assert offset_region(region, 0.0, 0.1) == region
    for r in (np.nan, np.inf, -np.inf):
        with pytest.raises(ValueError, match="finite"):
            offset_region(region, r, 0.1)
    with pytest.raises(ValueError, match="positive"):
        inset_region(region, 0.0, 0.1)


def test_cli_offset(tmp_path):
    runner = CliRunner()
    out = tmp_path / "o.png"
    r = runner.invoke(main, ["offset", "o", "--radius", "0.03", "-o", str(out),
                             "--size", "64"])
    assert r.exit_code == 0, r.output
    assert out.stat().st_size > 0
    r = runner.invoke(main, ["offset", "o", "--radius", "-0.03", "-o",
                             str(tmp_path / "n.png"), "--size", "64"])
    assert r.exit_code == 0, r.output
    r = runner.invoke(main, ["offset", "o", "--radius", "-0.3", "-o",
                             str(tmp_path / "gone.png")])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1
    assert "erodes all of glyph 'o'" in r.output and not (tmp_path / "gone.png").exists()


def test_offset_bound_and_the_written_svg(tmp_path):
    """offset_region's achieved bound (.bound) is at most its tol, 0 at radius
    0; `morph offset -o x.svg` writes its export with the rest of --tol, and the
    written outline (svgpathtools samples, y flipped back) is within --tol of the
    exact offset of the SVG shape: distance to its boundary = radius (the shape
    flattened within tol / 20)."""
    pytest.importorskip("svgpathtools")
    from svgpathtools import parse_path

    region = svg_region(SVG)
    out = offset_region(region, 7.5, 0.01)
    bound = out.bound
    plain = offset_region(region, 7.5, 0.01)
    assert [len(lp) for lp in out] == [len(lp) for lp in plain]
    assert all(np.array_equal(p, q) for lp, lq in zip(out, plain) for p, q in zip(lp, lq))
    assert 0.0 < bound <= 0.01
    assert offset_region(region, 0.0, 0.01).bound == 0.0
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
    from morph.offset import inset_region, offset_region
    from morph.parse import glyph_region

    o = glyph_region("o").region
    for r in (1e-300, 1e-12, -1e-300, -1e-12, -1e-320):
        out = offset_region(o, r, 0.05)
        bound = out.bound
        assert bound == abs(r) and mo.region_area(out) == pytest.approx(mo.region_area(o))
    out = offset_region(o, 1e-6, 0.05)  # computed: area grows
    bound = out.bound
    assert mo.region_area(out) > mo.region_area(o) and bound <= 0.05


def _inset_against_shapely(region, radius, tol):
    """The inset against shapely's buffer(-radius) of the region flattened within
    tol / 20 (arcs as 256 segments a quarter: their error radius * 2e-5): every
    boundary sample of the inset lies at distance ``radius`` from the input's
    boundary (within tol + the flattening) and inside the input (nonzero winding),
    and the two regions differ by an area of at most (tol + flattening) times the
    perimeter (nothing missing, no extra part)."""
    pytest.importorskip("shapely")
    from shapely.geometry import Polygon

    from tests.oracles.reference import region_to_shapely

    out = inset_region(region, radius, tol)
    flat = tol / 20
    pts = boundary_samples(out)
    d = shapely.distance(shapely.points(pts), boundary_lines(region, flat))
    assert np.abs(d - radius).max() <= tol + flat + 1e-9, np.abs(d - radius).max()
    ref = region_to_shapely(region, flat).buffer(-radius, quad_segs=256)
    mine = region_to_shapely(out, flat) if out else Polygon()
    slack = (tol + 2 * flat + radius * 2e-5) * max(ref.length, 1.0)
    assert mine.symmetric_difference(ref).area <= slack, (mine.symmetric_difference(ref).area,
                                                          slack)
    return out


@pytest.mark.parametrize("char,radius,loops", [("o", 20.0, 2), ("e", 15.0, 2), ("S", 25.0, 1),
                                               ("B", 20.0, 3), ("B", 30.0, 1),
                                               ("m", 35.0, 3)])
def test_glyph_inset_against_shapely(char, radius, loops):
    """Insets of glyphs: holes grow, thin parts vanish (m's stems 2 x 35 units wide
    are split from its arches; at 30 units B's bowls part where they meet on the
    right, opening both counters: one loop), measured against shapely."""
    out = _inset_against_shapely(glyph_region(char).region, radius, 0.1)
    assert len(out) == loops


def test_inset_of_a_square_keeps_its_corners_and_of_an_annulus_its_circles():
    sq = [[pc.line(a, b) for a, b in zip([(0, 0), (100, 0), (100, 100), (0, 100)],
                                         [(100, 0), (100, 100), (0, 100), (0, 0)])]]
    out = inset_region(sq, 10.0, 1e-3)
    assert len(out) == 1 and mo.region_area(out) == pytest.approx(6400.0, abs=1e-6)
    from morph.region import region_bbox, reverse_loop
    assert np.allclose(region_bbox(out), [10, 10, 90, 90], atol=1e-9)
    ring = [pc.circle((0, 0), 50), reverse_loop(pc.circle((0, 0), 20))]
    out = inset_region(ring, 5.0, 1e-4)
    bound = out.bound
    assert 0 < bound <= 1e-4 and len(out) == 2
    perimeter = 2 * np.pi * (45 + 25)
    assert mo.region_area(out) == pytest.approx(np.pi * (45 ** 2 - 25 ** 2), abs=perimeter * 1e-4)
    assert len(inset_region(ring, 15.5, 1e-4)) == 0     # the ring is 30 wide


@pytest.mark.parametrize("seed", [3, 11])
def test_inset_at_random_angles_and_scales(seed):
    """Inputs not tuned on: an SVG shape and a CFF glyph turned by a random angle and
    scaled by a random factor, inset by a random radius, against shapely."""
    from morph.parse import cubic_test_font_path
    from morph.region import region_bbox, transform_region

    rng = np.random.default_rng(seed)
    for region in (svg_region(SVG), glyph_region("g", cubic_test_font_path()).region):
        a, k = rng.uniform(0, 2 * np.pi), rng.uniform(0.2, 5.0)
        m = k * np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0]])
        turned = transform_region(region, m)
        x0, y0, x1, y1 = region_bbox(turned)
        size = max(x1 - x0, y1 - y0)
        _inset_against_shapely(turned, rng.uniform(0.005, 0.03) * size, 1e-4 * size)


def test_offsets_and_insets_of_near_cusps_against_shapely():
    """Wedges whose two sides meet at a turn of pi +- eps (eps from 1e-7 to 5e-4 rad,
    either sign: the sides cross a hair from the point, or just miss), random
    curvatures and directions, as rounded SVG coordinates make them (bootstrap-icons
    bluesky): the outward offset (every boundary sample at distance r) and the inset
    (against shapely's negative buffer) of the filled side, and of the notch cut into
    a box (the same wedge as a hole's tip)."""
    from morph.region import orient_region, reverse_loop, transform_region
    from morph.trim import fill_region

    rng = np.random.default_rng(2024)
    for _ in range(6):
        eps = rng.choice([-1, 1]) * 10 ** rng.uniform(-7, np.log10(5e-4))
        k1, k2 = rng.uniform(0.05, 0.4, 2)
        c_in = pc.quadratic((-1.0, k1), (-0.5, 0.0), (0.0, 0.0))
        c_out = pc.quadratic((0.0, 0.0), (-0.5, 0.5 * eps), (-1.0, -k2))
        wedge = [c_in, c_out, pc.line((-1.0, -k2), (-1.0, k1))]
        a = rng.uniform(0, 2 * np.pi)
        m = 10.0 * np.array([[np.cos(a), -np.sin(a), 0.0], [np.sin(a), np.cos(a), 0.0]])
        spike = orient_region(transform_region([wedge], m), on_crossing=fill_region)
        check_offset(spike, 0.3, 0.01)
        box = [pc.line(p, q) for p, q in zip([(-2, -2), (1, -2), (1, 2), (-2, 2)],
                                             [(1, -2), (1, 2), (-2, 2), (-2, -2)])]
        notch = [wedge[0], wedge[1], pc.line((-1.0, -k2), (-2.0, -k2)),
                 pc.line((-2.0, -k2), (-2.0, k1)), pc.line((-2.0, k1), (-1.0, k1))]
        holed = orient_region(transform_region([box, reverse_loop(notch)], m),
                              on_crossing=fill_region)
        _inset_against_shapely(holed, 0.5, 0.01)
        check_offset(holed, 0.5, 0.01)


@pytest.mark.parametrize("seed", range(6))
def test_thin_annular_gap_around_an_island_stays_open(seed):
    """A disk inside the round hole of a ring, offset so that the gap left between
    them is 40-200 tol wide but thinner than the hole test's first grid: the gap
    (a hole with an island) stays open, and the area is shapely's buffer.  The
    hole's probe point used to be taken in the island (the middle of a scanline
    across the hole ring, islands ignored), which filled the gap (a 4-unit gap in
    ionicons' ribbon)."""
    from tests.oracles.reference import region_to_shapely

    rng = np.random.default_rng(seed)
    c = rng.uniform(-100, 100, 2)
    r_disk, r_hole = rng.uniform(20, 60), rng.uniform(70, 90)
    tol = rng.choice([0.005, 0.01, 0.02])
    gap = rng.uniform(40, 200) * tol
    radius = 0.5 * (r_hole - r_disk - gap)
    region = [list(pc.circle(c, r_hole + 60)), list(pc.circle(c, r_hole))[::-1],
              list(pc.circle(c, r_disk))]
    region[1] = [pc.reverse(p) for p in region[1]]
    out = offset_region(region, radius, tol)
    assert len(out) == 3
    flat = tol / 20
    ref = region_to_shapely(region, flat).buffer(radius, quad_segs=256)
    mine = region_to_shapely(out, flat)
    assert mine.symmetric_difference(ref).area <= 2 * (tol + flat) * ref.length

"""morph.parse.svg: SVG shapes, transforms, arcs and fill rules against exact areas and
bounding boxes, every bad input (painting rules against a browser-like raster:
test_svg_semantics.py)."""

import math

import numpy as np
import pytest

from morph import piece as pc
from morph import moments as mo
from morph.errors import ParseError
from morph.parse import cubic_test_font_path, load_shape, svg_region, svg_shape, validate_path_data
from morph.region import region_bbox

SVG_NS = 'xmlns="http://www.w3.org/2000/svg"'


def test_svg_rect_with_group_transforms_and_y_flip():
    svg = ('<svg %s><g transform="translate(10,20)"><g transform="scale(2)">'
           '<rect x="0" y="0" width="3" height="4"/></g></g></svg>' % SVG_NS)
    loops = svg_region(svg)
    assert mo.region_area(loops) == pytest.approx(48.0, rel=1e-14)
    assert np.allclose(region_bbox(loops), [10, -28, 16, -20])


@pytest.mark.parametrize("r", [5.0, 0.25])
def test_svg_circle_is_exact(r):
    loops = svg_region('<svg %s><circle cx="3" cy="4" r="%r"/></svg>' % (SVG_NS, r))
    assert all(len(p) == 3 and not pc.is_polynomial(p) for p in loops[0])
    assert abs(mo.region_area(loops) - math.pi * r * r) <= 1e-12 * math.pi * r * r
    pts = pc.evaluate(loops[0][1], np.linspace(0, 1, 50))
    assert np.allclose(np.hypot(pts[:, 0] - 3, pts[:, 1] + 4), r, atol=1e-12 * max(r, 1))


def test_svg_ellipse_under_rotation_and_shear():
    svg = ('<svg %s><g transform="matrix(2 0.5 0.3 1 5 7)"><ellipse cx="1" cy="2" rx="4" '
           'ry="1.5" transform="rotate(25)"/></g></svg>' % SVG_NS)
    det = 2 * 1 - 0.5 * 0.3
    assert mo.region_area(svg_region(svg)) == pytest.approx(math.pi * 6 * det, rel=1e-12)


def test_svg_arc_commands_half_disk():
    # upper half disk in SVG coordinates (y down): sweep through y < 0
    loops = svg_region("M -2 0 A 2 2 0 0 1 2 0 Z")
    assert mo.region_area(loops) == pytest.approx(2 * math.pi, rel=1e-12)
    assert np.allclose(region_bbox(loops), [-2, 0, 2, 2], atol=1e-12)  # flipped up
    # rotated elliptical arc, large-arc flag, relative commands
    loops = svg_region("m 0 0 a 3 1 30 1 0 4 1 z")
    assert mo.region_area(loops) > 0


@pytest.mark.parametrize("rule_attr, expect", [
    ('fill-rule="evenodd"', 64 - 16),
    ('style="fill:red;fill-rule:evenodd"', 64 - 16),
    ('fill-rule="nonzero"', 64),
    ("", 64),
])
def test_svg_fill_rules(rule_attr, expect):
    d = "M0 0 H8 V8 H0 Z M2 2 H6 V6 H2 Z"  # both subpaths in the same direction
    loops = svg_region('<svg %s><path %s d="%s"/></svg>' % (SVG_NS, rule_attr, d))
    assert mo.region_area(loops) == pytest.approx(expect)


def test_svg_fill_rule_inherited_and_override():
    d = "M0 0 H8 V8 H0 Z M2 2 H6 V6 H2 Z"
    svg = '<svg %s><g fill-rule="evenodd"><path d="%s"/></g></svg>' % (SVG_NS, d)
    assert mo.region_area(svg_region(svg)) == pytest.approx(48)
    assert mo.region_area(svg_region(svg, fill_rule="nonzero")) == pytest.approx(64)
    # opposite directions: a hole under both rules
    d2 = "M0 0 H8 V8 H0 Z M2 2 V6 H6 V2 Z"
    assert mo.region_area(svg_region(d2)) == pytest.approx(48)
    assert mo.region_area(svg_region(d2, fill_rule="evenodd")) == pytest.approx(48)


def test_svg_subpaths_sharing_a_start_point_and_zero_length_segments():
    loops = svg_region("M0 0 L1 0 L1 1 Z M0 0 L-1 0 L-1 -1 Z")
    assert len(loops) == 2 and mo.region_area(loops) == pytest.approx(1.0)
    loops = svg_region("M0 0 L0 0 L4 0 L4 0 C4 0 4 0 4 0 L4 4 Z")
    assert [len(l) for l in loops] == [3]


def test_svg_file_and_load_shape(tmp_path):
    f = tmp_path / "shape.svg"
    f.write_text('<svg %s><path d="M0 0 H10 V5 H0 Z"/></svg>' % SVG_NS)
    for src in (f, str(f)):
        assert mo.region_area(svg_region(src)) == pytest.approx(50)
    s = load_shape(str(f))
    assert s.kind == "svg" and s.units_per_em is None and s.source == str(f)
    assert s.name == "shape" and s.advance_width == pytest.approx(10) and s.lsb == 0
    assert s.em_to_units(0.5) == 0.5 and s.slug == "shape"
    g = load_shape("g")
    assert g.kind == "glyph" and g.units_per_em == 1000 and g.advance_width == 615
    assert g.source == "g" and g.lsb == 55 and g.em_to_units(1e-3) == 1.0
    s = load_shape("g", cubic_test_font_path())
    assert {len(p) for l in s.region for p in l} == {2, 4}
    assert svg_shape("M 1 0 H 4 V 2 Z").name == "path"


@pytest.mark.parametrize("d", ["M 0 0 L 1 x 1 Z", "L 0 0 1 1 Z", "M 0 0 L 1 Z",
                               "M 0 0 A 1 1 0 2 1 3 3 Z", "M 0 0 Q 1 1 Z", "M0 0 L 1,,1 Z",
                               "M 0 0 L nan 1 L 1 1 Z"])
def test_malformed_path_data(d):
    with pytest.raises(ParseError, match="malformed"):
        svg_region(d)


def test_valid_path_data_forms():
    for d in ["M0,0L1,1", "M.5.5l-1e-2.3z", "M0 0 a1 1 0 1 0 2 2", "M0 0 A1 1 0 1120 20",
              "M0 0 h1 v1 H0 V0 z", "M 0 0 C 1 1 2 2 3 3 S 4 4 5 5 Q 6 6 7 7 T 8 8"]:
        validate_path_data(d)


def test_open_subpaths_are_filled_as_if_closed(tmp_path):
    """SVG fills an open subpath as if closed by a straight line (implicit close)."""
    f = tmp_path / "open.svg"
    f.write_text('<svg %s><path d="M0 0 H10 V5 H0 Z M 20 20 H 30 V 30"/></svg>' % SVG_NS)
    assert abs(mo.region_area(svg_region(f)) - (50 + 50)) < 1e-9
    assert abs(mo.region_area(svg_region("M0 0 L 1 0 L 1 1")) - 0.5) < 1e-12
    # the open zero-area subpath M 5 5 L 6 6 fills nothing; the triangle stays
    assert abs(mo.region_area(svg_region("M0 0 L 1 0 M 5 5 L 6 6 L 5 6 Z")) - 0.5) < 1e-12


def test_non_finite_coordinates():
    with pytest.raises(ParseError, match="non-finite"):
        svg_region("M 0 0 L 1e999 0 L 1 1 Z")
    with pytest.raises(ParseError, match="transform"):
        svg_region('<svg %s><path transform="scale(1e999)" d="M0 0 H1 V1 Z"/></svg>' % SVG_NS)
    with pytest.raises(ParseError, match="transform"):
        svg_region('<svg %s><path transform="matrix(nan 0 0 1 0 0)" d="M0 0 H1 V1 Z"/></svg>'
                   % SVG_NS)


def test_empty_and_unreadable_svg(tmp_path):
    with pytest.raises(ParseError, match="no path"):
        svg_region("<svg %s></svg>" % SVG_NS)
    with pytest.raises(ParseError, match="no closed path"):
        svg_region('<svg %s><path d="M0 0 L1 1 L0 0 Z"/></svg>' % SVG_NS)  # zero area
    with pytest.raises(ParseError, match="no such file"):
        svg_region(tmp_path / "missing.svg")
    bad = tmp_path / "bad.svg"
    bad.write_text("<svg><path d=")
    with pytest.raises(ParseError, match="bad.svg"):
        svg_region(bad)
    with pytest.raises(ParseError, match="no path"):
        svg_region("")
    with pytest.raises(ParseError):
        load_shape(str(tmp_path / "missing.svg"))

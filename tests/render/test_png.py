"""Rendering: golden PNGs, an independent rasteriser (cairosvg), SVG round trips."""

import io
import math

import numpy as np
import pytest
from PIL import Image

from tests.imagediff import assert_matches_golden
from morph import piece as pc
from morph.parse import cubic_test_font_path, glyph_region, svg_region
from morph.region import Region, region_bbox, reverse_loop, translate_region
from morph.render import (frame_bbox, frames_to_gif, normalize_shapes, render_png,
                          save_animation, svg_document, svg_path_data, write_png, write_svg)
from morph.render.png import coverage_mask

SVG_NS = 'xmlns="http://www.w3.org/2000/svg"'
ARC_SVG = ('<svg %s><path d="M 0 0 A 50 30 20 1 1 60 40 L 30 80 Z '
           'M 20 10 v 10 h 10 v -10 z"/></svg>' % SVG_NS)


def gray(image):
    return np.asarray(image.convert("L"), float)


# --------------------------------------------------------------------------- goldens

def test_golden_g_ttf():
    assert_matches_golden(render_png(glyph_region("g").region, size=128), "g-ttf-128")


def test_golden_B_cff():
    img = render_png(glyph_region("B", cubic_test_font_path()).region, size=128)
    assert_matches_golden(img, "B-otf-128")


def test_golden_svg_arc_with_hole_and_stroke():
    loops = svg_region(ARC_SVG)
    img = render_png([(loops, {"fill": "navy", "stroke": "red", "stroke_width": 2})],
                     size=128)
    assert_matches_golden(img, "arc-svg-128")


def test_golden_two_shapes_one_canvas():
    a = glyph_region("a").region
    b = translate_region(glyph_region("b").region, (700, 0))
    img = render_png([(a, {"fill": (200, 30, 30)}), (b, {"fill": "#2060c0", "opacity": 0.6})],
                     size=(160, 96), background="#f0f0e0")
    assert img.size == (160, 96)
    assert_matches_golden(img, "ab-two-shapes")


# --------------------------------------------------------------------------- behaviour

@pytest.mark.parametrize("ch", ["o", "g", "B", "8"])
def test_holes_render_as_holes(ch):
    loops = glyph_region(ch).region
    frame = frame_bbox(loops)
    img = gray(render_png(loops, size=200))
    scale = 200 / max(frame[2] - frame[0], frame[3] - frame[1])
    for loop in loops:
        if pc.loop_area(loop) < 0:  # a hole: its centre is background
            cx, cy = np.mean(pc.flatten_loop(loop, 1.0), axis=0)
            col = int((cx - frame[0]) * scale)
            row = int((frame[3] - cy) * scale)
            assert img[row, col] == 255, (ch, row, col)
    assert img.min() == 0 and len(np.unique(img)) > 8  # filled and anti-aliased


def test_renderer_agrees_with_cairosvg():
    """Independent check: our PNG vs cairosvg's rasterisation of our SVG."""
    cairosvg = pytest.importorskip("cairosvg")
    shapes = {"g": glyph_region("g").region,
              "B-cff": glyph_region("B", cubic_test_font_path()).region,
              "arc": svg_region(ARC_SVG),
              "circle-hole": [pc.circle((0, 0), 10), reverse_loop(pc.circle((3, 0), 4))]}
    for name, loops in shapes.items():
        ours = render_png(loops, size=200)
        png = cairosvg.svg2png(bytestring=svg_document(loops, size=200).encode(),
                               background_color="white")
        theirs = Image.open(io.BytesIO(png))
        assert ours.size == theirs.size, name
        diff = np.abs(gray(ours) - gray(theirs))
        assert diff.mean() < 1.5, (name, diff.mean())
        assert (diff > 64).mean() < 0.002, name


def test_coverage_mask_is_exact_for_aligned_square_and_area_for_disk():
    sq = [np.array([[2.0, 3.0], [7.0, 3.0], [7.0, 9.0], [2.0, 9.0]])]
    m = coverage_mask(sq, 12, 10)
    assert m.sum() == 30 and m[3:9, 2:7].all()
    # clockwise and counter-clockwise give the same fill; nested opposite = hole
    assert coverage_mask([sq[0][::-1]], 12, 10).sum() == 30
    inner = np.array([[3.0, 4.0], [3.0, 6.0], [5.0, 6.0], [5.0, 4.0]])
    assert coverage_mask([sq[0], inner], 12, 10).sum() == 26
    # a disk: pixel-centre count close to the area
    t = np.linspace(0, 2 * np.pi, 2000, endpoint=False)
    disk = np.column_stack([100 + 60 * np.cos(t), 100 + 60 * np.sin(t)])
    assert abs(coverage_mask([disk], 200, 200).sum() - math.pi * 3600) < 0.002 * math.pi * 3600
    # edges outside the image are clipped
    big = [np.array([[-50.0, -50.0], [50.0, -50.0], [50.0, 50.0], [-50.0, 50.0]])]
    assert coverage_mask(big, 10, 10).all()


def test_fixed_bbox_frames_align():
    disk = [pc.circle((0, 0), 1.0)]
    moved = translate_region(disk, (2.0, 0.0))
    box = (-1.5, -1.5, 3.5, 1.5)
    a = gray(render_png(disk, size=100, bbox=box, margin=0))
    b = gray(render_png(moved, size=100, bbox=box, margin=0))
    assert a.shape == b.shape == (60, 100)
    # 2 units = 40 px to the right
    assert np.abs(np.roll(a, 40, axis=1)[:, 45:] - b[:, 45:]).max() <= 1


def test_transparent_background_and_rgba():
    img = render_png([pc.circle((0, 0), 1.0)], size=64, background=None, fill="green")
    assert img.mode == "RGBA"
    arr = np.asarray(img)
    assert arr[0, 0, 3] == 0 and arr[32, 32, 3] == 255
    assert tuple(arr[32, 32, :3]) == (0, 128, 0)


def test_region_object_and_list_of_regions_accepted(tmp_path):
    r = Region([pc.circle((0, 0), 1.0)])
    assert len(normalize_shapes(r)) == 1
    assert len(normalize_shapes([r, r.loops])) == 2
    with pytest.raises(ValueError):
        normalize_shapes([])
    with pytest.raises(ValueError):
        normalize_shapes([[1, 2, 3]])
    write_png(tmp_path / "r.png", r, size=32)
    assert Image.open(tmp_path / "r.png").size == (32, 32)


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


def test_animations(tmp_path):
    frames = [render_png([pc.circle((0, 0), r)], size=48, bbox=(-2, -2, 2, 2))
              for r in (0.5, 1.0, 1.5)]
    gif = tmp_path / "a.gif"
    frames_to_gif(frames, gif, duration=40)
    with Image.open(gif) as im:
        assert im.n_frames == 3
    apng = tmp_path / "a.png"
    save_animation(frames, apng, duration=40)
    with Image.open(apng) as im:
        assert getattr(im, "n_frames", 1) == 3
    save_animation(frames, tmp_path / "b.gif")
    with pytest.raises(ValueError):
        save_animation(frames, tmp_path / "a.mp4")
    with pytest.raises(ValueError):
        frames_to_gif([], tmp_path / "c.gif")


def test_png_fill_none_like_svg():
    """fill "none" (as in SVG) paints nothing; a stroke still shows."""
    from morph.render import render_png
    sq = [[pc.line(a, b) for a, b in zip([(0, 0), (1, 0), (1, 1), (0, 1)],
                                          [(1, 0), (1, 1), (0, 1), (0, 0)])]]
    img = np.asarray(render_png([(sq, {"fill": "none", "stroke": "black"})], size=64))
    assert img[32, 32].min() == 255     # centre: nothing painted (white background)
    assert img.min() < 128              # the outline is drawn (anti-aliased)


def test_cspace_figure_places_robots_on_the_boundary():
    """cspace_figure: the C-space region, the obstacle, then a robot outline and a dot
    at each of ``samples`` points of the C-space boundary, evenly spread by length."""
    from morph.render import cspace_figure

    obstacle = [pc.circle((0.0, 0.0), 2.0)]
    robot = [pc.circle((0.0, 0.0), 0.5)]
    cspace = [pc.circle((0.0, 0.0), 2.5)]
    shapes = cspace_figure(obstacle, robot, cspace, 1e-3, samples=4)
    assert len(shapes) == 2 + 2 * 4 and shapes[1][0] is obstacle
    dots = [region_bbox(loops) for loops, style in shapes[3::2]]
    centres = np.array([[(b[0] + b[2]) / 2, (b[1] + b[3]) / 2] for b in dots])
    assert np.allclose(np.hypot(*centres.T), 2.5, atol=2e-3)  # on the boundary
    angles = np.sort(np.arctan2(centres[:, 1], centres[:, 0]))
    assert np.allclose(np.diff(angles), np.pi / 2, atol=2e-3)  # evenly spread
    assert len(cspace_figure(obstacle, robot, cspace, 1e-3, samples=0)) == 2


def test_write_frames(tmp_path):
    from morph.render import write_frames

    regions = [[pc.circle((0.0, 0.0), r)] for r in (1.0, 2.0, 3.0)]
    write_frames(tmp_path, regions, size=64, tol=1e-3, duration=50)
    names = sorted(p.name for p in tmp_path.iterdir())
    assert names == ["frame-000.png", "frame-000.svg", "frame-001.png", "frame-001.svg",
                     "frame-002.png", "frame-002.svg", "morph.gif"]
    small, large = (gray(Image.open(tmp_path / n)) for n in ("frame-000.png", "frame-002.png"))
    assert small.shape == large.shape and (small < 128).sum() < (large < 128).sum()

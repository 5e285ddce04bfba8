"""morph.render.png: golden PNGs, an independent rasteriser (cairosvg), coverage,
frames, animations."""

import io
import math

import numpy as np
import pytest
from PIL import Image

from tests.imagediff import assert_matches_golden, gray
from morph import piece as pc
from morph import moments as mo
from morph import polyline as pl
from morph.parse import cubic_test_font_path, glyph_region, svg_region
from morph.region import reverse_loop, translate_region
from morph.render import frame_bbox, frames_to_gif, render_png, save_animation, svg_document
from morph.render.png import (_box_sum, coverage_counts, coverage_mask, gif_frame,
                              render_palette)

SVG_NS = 'xmlns="http://www.w3.org/2000/svg"'
ARC_SVG = ('<svg %s><path d="M 0 0 A 50 30 20 1 1 60 40 L 30 80 Z '
           'M 20 10 v 10 h 10 v -10 z"/></svg>' % SVG_NS)


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
        if mo.loop_area(loop) < 0:  # a hole: its centre is background
            cx, cy = np.mean(pl.flatten_loop(loop, 1.0), axis=0)
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


def test_coverage_counts_equal_the_box_sums_of_the_sample_mask():
    """The pixel counts gathered from each sample row's runs equal the k x k box sums
    of the sample-by-sample mask, exactly: random polygons (crossing, nested, either
    direction) with vertices on sample centres and half-way between (ties of the
    crossing rule), reaching out of the image on every side, k = 1..5."""
    rng = np.random.default_rng(11)
    for trial in range(400):
        k = int(rng.integers(1, 6))
        h, w = int(rng.integers(1, 25)), int(rng.integers(1, 25))
        polys = []
        for _ in range(int(rng.integers(1, 4))):
            n = int(rng.integers(3, 12))
            if trial % 2:
                p = rng.integers(-3, max(h, w) * k + 3, (n, 2)) + 0.5 * rng.integers(0, 2, (n, 2))
            else:
                p = rng.uniform(-5, max(h, w) * k + 5, (n, 2))
            polys.append(p.astype(float))
        want = _box_sum(coverage_mask(polys, h * k, w * k).view(np.uint8), k)
        got = coverage_counts(polys, h, w, k)
        assert got.dtype == np.uint16 and got.shape == (h, w)
        assert np.array_equal(got, want)
    assert not coverage_counts([], 3, 4, 2).any()


def test_gif_frames_keep_the_colours_of_a_frame():
    """A frame of at most 256 colours is written with exactly its colours; one of
    more is quantised to 256."""
    img = render_png([(glyph_region("g").region, {"fill": "#3060c0"})], size=120)
    frame = gif_frame(img)
    assert frame.mode == "P"
    assert np.array_equal(np.asarray(frame.convert("RGB")), np.asarray(img))
    greys = np.repeat(np.arange(256, dtype=np.uint8).reshape(16, 16, 1), 3, axis=2)
    frame = gif_frame(Image.fromarray(greys, "RGB"))  # 256 colours, one level apart
    assert frame.mode == "P" and np.array_equal(np.asarray(frame.convert("RGB")), greys)
    ramp = np.zeros((40, 40, 3), np.uint8)
    ramp[..., 0] = np.arange(40)[:, None] * 6
    ramp[..., 1] = np.arange(40)[None, :] * 6
    many = Image.fromarray(ramp, "RGB")  # 1600 colours
    assert many.getcolors(256) is None
    frame = gif_frame(many)
    assert frame.mode == "P" and len(frame.getcolors(256)) <= 256
    assert np.abs(np.asarray(frame.convert("RGB"), int) - ramp.astype(int)).mean() < 8


def test_palette_render_has_the_pixels_of_the_full_render():
    """render_palette (a frame's PNG and GIF frame: the count of covered samples per
    pixel, with a palette of the k^2 + 1 composited colours) gives render_png's RGB
    pixels exactly: a glyph with holes, a CFF glyph, a fill with alpha on a coloured
    background, supersampling 1, 3, 4 and the fallback past 256 levels (16 x 16);
    a fill of "none" is the background.  A palette made with the wrong alpha
    rounding (floor) fails it."""
    import morph.render.png as P

    cases = [(glyph_region("g").region, {}), (glyph_region("B", cubic_test_font_path()).region,
                                              {"supersample": 3}),
             (svg_region(ARC_SVG), {"fill": (40, 90, 200, 150), "background": "#f0e0a0",
                                    "supersample": 1}),
             (glyph_region("a").region, {"fill": "none"}),
             (glyph_region("&").region, {"size": 40, "supersample": 16})]
    for region, kw in cases:
        size = kw.pop("size", 96)
        bbox = frame_bbox([region], margin=0.1)
        want = np.asarray(render_png([region], size=size, bbox=bbox, **kw))
        got = render_palette([region], size=size, bbox=bbox, **kw)
        assert got.mode == "P", kw
        assert np.array_equal(np.asarray(got.convert("RGB")), want), kw
    with pytest.raises(ValueError):
        render_palette([glyph_region("g").region], background=None)
    region = glyph_region("g").region
    real = P._alpha
    try:
        P._alpha = lambda hits, color, k: (hits.astype(np.uint32) * color[3] // (k * k)).astype(np.uint8)
        got = np.asarray(render_palette([region], size=96).convert("RGB"))
    finally:
        P._alpha = real
    assert not np.array_equal(got, np.asarray(render_png([region], size=96)))


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


def test_supersampling_lowered_to_the_sample_cap(monkeypatch):
    # --size 16384 at 4 x 4 samples per pixel ran out of the memory budget: the
    # samples per image are capped (MAX_SAMPLES), the supersampling lowered to fit
    import morph.render.png as P

    shape = [pc.circle((0.0, 0.0), 1.0)]
    full = np.asarray(P.render_png(shape, size=64, supersample=2))
    monkeypatch.setattr(P, "MAX_SAMPLES", 64 * 64 * 4)  # room for 2 x 2, not 4 x 4
    assert np.array_equal(np.asarray(P.render_png(shape, size=64, supersample=4)), full)
    monkeypatch.setattr(P, "MAX_SAMPLES", 1)             # never below one sample
    one = np.asarray(P.render_png(shape, size=64, supersample=1))
    assert np.array_equal(np.asarray(P.render_png(shape, size=64, supersample=4)), one)

"""Regenerate the gallery: the paper's figures in spirit, as PNG and SVG.

    python gallery/make_gallery.py [--size 900] [--only NAME ...]

Figures (file stems in gallery/):
  fig01_convex      convex sum: ellipse ⊕ convex blob (Fig. 1)
  fig02_nonconvex   'C' ⊕ ellipse: convolution curve before trimming (left, all
                    pieces including type 3 as strokes) and the trimmed sum (right) (Fig. 2)
  fig37_offsets     'e' offset by exact disks of several radii (Fig. 37)
  fig37_insets      'e' inset by exact disks of several radii (its erosions)
  fig38_cspace      C-space obstacle of 'O' for a translating 'v' robot (Figs. 4, 38)
  fig05_brush       sample text swept by an elliptical nib (Fig. 5)
  fig05_skeleton    a Relief SingleLine skeleton, the nib along it, skeleton ⊕ nib (Fig. 5)
  fig05_stroke_text "Hamburgefonstiv" of Relief stroked by a broad nib at 30 degrees
                    and by a round nib (`morph stroke`)
  fig35_nib_axis    Relief 'g' in a variable font with a nib axis (`morph stroke
                    --vary-nib`): five instances from fontTools' instancer, their
                    overlapping contours drawn over each other, thin to broad nib
  fig06_t_to_m      T -> M morph sequence, (1-a)·T ⊕ a·M (Fig. 6)
  fig36_bird_butterfly  bird -> butterfly morph sequence (Fig. 36)

Every figure function returns (shapes, tol) for morph.render; tests/test_gallery.py
diffs some of them against golden images.
"""

import argparse
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.frames import centered, morph_frames  # noqa: E402 - after sys.path gets the repo root
from morph.parse import glyph_region, svg_region  # noqa: E402 - after sys.path gets the repo root
from morph.region import region_bbox, translate_region  # noqa: E402 - after sys.path gets the repo root
from morph.minkowski import minkowski_sum  # noqa: E402 - after sys.path gets the repo root

DATA = HERE.parent / "morph" / "data"
BLUE, ORANGE, GREY, RED = "#1f5fa8", "#f2c894", "#404040", "#d62728"


def moved(loops, dx, dy=0.0):
    return translate_region(loops, (dx, dy))


def row(regions, gap):
    """Regions laid out left to right with ``gap`` between their boxes."""
    out, x = [], 0.0
    for r in regions:
        b = region_bbox(r)
        out.append(moved(r, x - b[0], -0.5 * (b[1] + b[3])))
        x += (b[2] - b[0]) + gap
    return out


def convex_blob():
    """A convex closed cubic spline (rounded triangle), counter-clockwise."""
    pts = [(0, 0), (60, -10), (100, 20), (70, 70), (20, 80), (-20, 40)]
    p = np.array(pts, float)
    n = len(p)
    loop = []
    for i in range(n):
        a, b = (p[i - 1] + p[i]) / 2, (p[i] + p[(i + 1) % n]) / 2
        loop.append(pc.quadratic(a, p[i], b))
    return [loop]


def fig01_convex():
    a = convex_blob()
    b = [pc.ellipse((0, 0), 40, 18, 0.5)]
    s = minkowski_sum(a, b, 0.01)
    ra, rb, rs = row([a, b, s], 50)
    return [(ra, {"fill": ORANGE, "stroke": GREY}), (rb, {"fill": ORANGE, "stroke": GREY}),
            (rs, {"fill": "#9bbbd4", "stroke": BLUE, "stroke_width": 1.5})], 0.01


def fig02_nonconvex():
    from morph.convolve import chain, convolution

    tol = 0.5
    a = glyph_region("C").region
    b = [pc.ellipse((0, 0), 170, 40, np.radians(30))]
    conv = convolution(a, b, tol, keep_type3=True)
    loops = chain([c.piece for c in conv], 10 * tol)
    s = minkowski_sum(a, b, tol)
    box = region_bbox(s)
    dx = (box[2] - box[0]) * 1.15
    return [(s, {"fill": "#dde7f0"}),
            (loops, {"fill": None, "stroke": RED, "stroke_width": 1.6}),
            (moved(s, dx), {"fill": "#9bbbd4", "stroke": BLUE, "stroke_width": 1.5}),
            (moved(a, dx), {"fill": GREY})], tol


def fig37_offsets():
    from morph.offset import offset_region

    tol = 0.5
    a = glyph_region("e").region
    shapes = []
    colours = ["#dbe6f1", "#b5cde3", "#8fb3d5", "#6999c7"]
    for r, c in zip([90, 60, 35, 15], colours):
        shapes.append((offset_region(a, r, tol), {"fill": c, "stroke": BLUE,
                                                  "stroke_width": 0.8}))
    shapes.append((a, {"fill": "black"}))
    return shapes, tol


def fig37_insets():
    from morph.offset import inset_region

    tol = 0.5
    a = glyph_region("e").region
    shapes = [(a, {"fill": "#dbe6f1", "stroke": BLUE, "stroke_width": 0.8})]
    colours = ["#b5cde3", "#8fb3d5", "#6999c7", "black"]
    for r, c in zip([8, 16, 24, 32], colours):
        shapes.append((inset_region(a, r, tol), {"fill": c, "stroke": BLUE,
                                                 "stroke_width": 0.8}))
    return shapes, tol


def fig38_cspace():
    from morph.render import cspace_figure
    from morph.cspace import cspace_obstacle
    from morph.frames import scale_region
    from morph.region import region_centroid

    tol = 0.5
    obstacle = glyph_region("O").region
    robot = scale_region(glyph_region("v").region, 0.6)
    ref = region_centroid(robot)
    cs = cspace_obstacle(obstacle, robot, tol, reference=ref)
    return cspace_figure(obstacle, robot, cs, tol, samples=7, reference=ref), tol


def fig05_brush(text="Hamburgefonstiv"):
    from morph.fonts.brush import ellipse_nib, region_extent
    from morph.parse import load_font

    tol = 0.5
    nib = ellipse_nib(80, 30, 30)
    nx0, _, nx1, _ = region_extent(nib)
    font = load_font()
    x, plain, swept = 0.0, [], []
    for ch in text:
        g = glyph_region(ch, font)
        s = minkowski_sum(g.region, nib, tol)
        swept.extend(moved(s, x - nx0))
        plain.extend(moved(g.region, x - nx0, -1250))
        x += g.advance_width + (nx1 - nx0)
    return [(plain, {"fill": "#909090"}), (swept, {"fill": "black"})], tol


RELIEF = HERE.parent / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"


def fig05_skeleton(name="a"):
    """Paper Fig. 5 from a Relief SingleLine skeleton: the centre line with the nib
    (left), the nib swept along it (middle), the outline = skeleton ⊕ nib (right)."""
    from morph.fonts.brush import ellipse_nib
    from morph.parse.ufo import decomposed_paths, load_ufo
    from morph.stroke import path_loop, stroke_paths

    tol = 0.25
    font = load_ufo(RELIEF)
    paths = decomposed_paths(font, name)
    nib = ellipse_nib(90, 20, 30)
    outline = stroke_paths(paths, nib, tol)
    line = [path_loop(pieces) for pieces, _ in paths]  # the centre line, drawn as a loop
    b = region_bbox(outline)
    gap = 0.35 * (b[2] - b[0])
    step = (b[2] - b[0]) + gap
    shapes = []
    # left: the skeleton and the nib at its start
    start = pc.start(paths[0][0][0])
    shapes.append((moved(nib, *start), {"fill": ORANGE}))
    shapes.append((line, {"fill": "none", "stroke": RED, "stroke_width": 1.5}))
    # middle: nib copies along the centre line over the outline
    shapes.append((moved(outline, step), {"fill": "#e6e6e6"}))
    for pieces, _ in paths:
        for p in pieces:
            for t in (0.0, 0.25, 0.5, 0.75):
                x, y = pc.evaluate(p, np.array([t]))[0]
                shapes.append((moved(nib, x + step, y), {"fill": "none", "stroke": BLUE,
                                                         "stroke_width": 0.8}))
    shapes.append((moved(line, step), {"fill": "none", "stroke": RED, "stroke_width": 1.0}))
    # right: the outline
    shapes.append((moved(outline, 2 * step), {"fill": "black"}))
    return shapes, tol


def fig05_stroke_text(text="Hamburgefonstiv"):
    """Relief SingleLine stroked with a broad nib at 30 degrees (top) and a round nib
    (bottom), as `morph stroke` writes the fonts (advance + nib width)."""
    from morph.fonts.brush import ellipse_nib, region_extent
    from morph.parse.ufo import decomposed_paths, glyph_names_for, load_ufo
    from morph.stroke import stroke_paths

    tol = 0.25
    font = load_ufo(RELIEF)
    names = glyph_names_for(font, list(dict.fromkeys(text)))
    by_char = dict(zip(dict.fromkeys(text), names))
    shapes = []
    for row_y, nib in ((0.0, ellipse_nib(90, 20, 30)), (-1000.0, ellipse_nib(60, 60, 0))):
        nx0, _, nx1, _ = region_extent(nib)
        cache, x, ink = {}, 0.0, []
        for ch in text:
            n = by_char[ch]
            if n not in cache:
                cache[n] = stroke_paths(decomposed_paths(font, n), nib, tol)
            ink.extend(moved(cache[n], x - nx0, row_y))
            x += font[n].width + (nx1 - nx0)
        shapes.append((ink, {"fill": "black"}))
    return shapes, tol


def _glyph_loops(glyph_set, name):
    """A glyph's contours (TrueType quadratics, lines) as loops of pieces."""
    from fontTools.pens.basePen import decomposeQuadraticSegment
    from fontTools.pens.recordingPen import DecomposingRecordingPen

    rec = DecomposingRecordingPen(glyph_set)
    glyph_set[name].draw(rec)
    loops, cur, at = [], [], None
    for op, args in rec.value:
        if op == "moveTo":
            cur, at = [], args[0]
        elif op == "lineTo":
            cur.append(pc.line(at, args[0]))
            at = args[0]
        elif op == "qCurveTo":
            for b, c in decomposeQuadraticSegment(args):
                cur.append(pc.quadratic(at, b, c))
                at = c
        elif op == "curveTo":
            cur.append(pc.cubic(at, *args))
            at = args[-1]
        elif op == "closePath":
            if np.any(pc.cartesian(cur[0])[0] != pc.cartesian(cur[-1])[-1]):
                cur.append(pc.line(at, pc.cartesian(cur[0])[0]))
            loops.append(cur)
    return loops


def fig35_nib_axis(name="g", values=(40, 60, 80, 100, 120)):
    """A variable calligraphic font (nib axis from ellipse 40 x 10 to 120 x 30 at 30
    degrees), glyph ``name`` instanced at five positions: the untrimmed, overlapping
    contours of each instance drawn over each other (thin nib light, broad nib dark),
    the broadest filled in grey below; they are the same contours moving."""
    import logging
    import tempfile

    from fontTools.ttLib import TTFont
    from fontTools.varLib import instancer

    from morph.fonts.variable import stroke_variable

    for lib in ("ufo2ft", "fontTools"):
        logging.getLogger(lib).setLevel(logging.ERROR)
    tol = 0.25
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "Nib.ttf"
        stroke_variable(str(RELIEF), out, (40, 10, 30), (120, 30, 30), glyphs=[name], tol=0.5)
        font = TTFont(str(out))
        loops = [_glyph_loops(instancer.instantiateVariableFont(font, {"NIBW": v})
                              .getGlyphSet(), name) for v in values]
    shapes = [(loops[-1], {"fill": "#e0e0e0"})]
    shades = ["#9ecae1", "#6baed6", "#3182bd", "#08519c", "#08306b"]
    for lp, colour in zip(loops, shades):
        shapes.append((lp, {"fill": "none", "stroke": colour, "stroke_width": 1.2}))
    return shapes, tol


def _sheet(a, b, n, tol, gap):
    frames = morph_frames(a, b, n, tol)
    return [(r, {"fill": "black"}) for r in row([centered(f) for f in frames], gap)]


def fig06_t_to_m():
    tol = 0.5
    return _sheet(glyph_region("T").region, glyph_region("M").region, 6, tol, 120), tol


def fig36_bird_butterfly():
    tol = 0.05
    return _sheet(svg_region(str(DATA / "bird.svg")), svg_region(str(DATA / "butterfly.svg")),
                  6, tol, 25), tol


FIGURES = [fig01_convex, fig02_nonconvex, fig37_offsets, fig37_insets, fig38_cspace, fig05_brush,
           fig05_skeleton, fig05_stroke_text, fig35_nib_axis, fig06_t_to_m,
           fig36_bird_butterfly]


def render(fig, size):
    from morph.render import render_png

    shapes, tol = fig()
    return render_png(shapes, size=size), shapes, tol


def main(argv=None):
    from morph.render import write_svg

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--size", type=int, default=900)
    ap.add_argument("--only", nargs="*", default=None)
    args = ap.parse_args(argv)
    for fig in FIGURES:
        if args.only and fig.__name__ not in args.only:
            continue
        t0 = time.perf_counter()
        img, shapes, tol = render(fig, args.size)
        img.save(str(HERE / (fig.__name__ + ".png")))
        write_svg(str(HERE / (fig.__name__ + ".svg")), shapes, size=args.size, tol=tol)
        print("%-22s %.1f s" % (fig.__name__, time.perf_counter() - t0))


if __name__ == "__main__":
    main()

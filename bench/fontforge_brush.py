"""FontForge brush worker for bench/brush_fontforge.py (run with Debian's python3).

    /usr/bin/python3 bench/fontforge_brush.py < job.json > result.json

Input JSON: ``{"font": PATH, "nib": [W, H, ANGLE_DEG], "accuracy": A, "glyphs":
[name, ...]}``.  The font is opened in FontForge and its outlines made cubic (not
timed).  Each glyph A is brushed as FontForge users do it: Expand Stroke of its
outline with the elliptical nib (``glyph.stroke("elliptical", W, H, angle, "nib",
"nib", removeoverlap="layer", accuracy=A)``: the band ∂A ⊕ nib, both sides of every
contour), then the original contours added back in the band's orientation and Remove
Overlap (``glyph.removeOverlap()``), which fills the inside: A ⊕ nib = A ∪ (∂A ⊕ nib).  The
CPU time (process_time) of those steps is measured.  With ``"generate": PATH`` in the
job, the font is then saved there by ``font.generate`` (as a user's script ends: the
worker process's CPU time then covers a whole workflow, like ``morph brush``'s
command writing its font).  Output JSON: ``{name:
{"seconds": s, "points": n, "contours": [[segment, ...], ...]}}``, segments as in
bench/fontforge_stroke.py (lists of 2 or 4 points).
"""

import functools
import json
import math
import sys

import fontforge

sys.path.insert(0, __file__.rsplit("/", 1)[0])
from fontforge_stroke import write_timed  # noqa: E402 - this folder first


def _largest(layer):
    """The contour of ``layer`` with the largest bounding box (an outer contour)."""
    def area(c):
        x0, y0, x1, y1 = c.boundingBox()
        return (x1 - x0) * (y1 - y0)
    return max(layer, key=area)


def _brush(g, original, w, h, angle, acc):
    g.stroke("elliptical", w, h, math.radians(angle), "nib", "nib", accuracy=acc,
             removeoverlap="layer")
    layer = g.foreground
    # the fill added in the band's orientation (FontForge writes outer contours
    # clockwise, the CFF source has them counter-clockwise): else the nonzero
    # union cancels the inside instead of filling it
    if len(layer) and len(original):
        flip = _largest(layer).isClockwise() != _largest(original).isClockwise()
    else:
        flip = False
    for c in original:
        c = c.dup()
        if flip:
            c.reverseDirection()
        layer += c
    g.foreground = layer
    g.removeOverlap()


def _brush_steps(job, opened):
    font = fontforge.open(job["font"])
    opened.append(font)
    font.is_quadratic = False
    w, h, angle = (float(v) for v in job["nib"])
    acc = float(job["accuracy"])
    for name in job["glyphs"]:
        g = font[name]
        original = g.foreground.dup()
        yield name, g, functools.partial(_brush, g, original, w, h, angle, acc)


def main():
    job, opened = json.load(sys.stdin), []
    write_timed(_brush_steps(job, opened))
    if job.get("generate"):     # the font saved, as a user's script ends
        opened[0].generate(job["generate"])


if __name__ == "__main__":
    main()

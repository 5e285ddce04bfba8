"""FontForge Expand Stroke worker for bench/stroke.py (run with Debian's python3).

    /usr/bin/python3 bench/fontforge_stroke.py < job.json > result.json

Needs ``python3-fontforge`` (``apt-get install python3-fontforge``), which installs
the ``fontforge`` module for the system Python only, hence a subprocess.  Input JSON:
``{"nib": ["elliptical", W, H, ANGLE_DEG] | ["circular", D], "accuracy": A,
"glyphs": {name: [[segments, closed], ...]}}`` with segments lists of 2 (line) or 4
(cubic) points.  Each glyph's skeleton is drawn with FontForge's glyph pen (open
contours stay open) and stroked by ``glyph.stroke(...)`` with caps and joins "nib" (the nib's own shape
at ends and corners, so that the result is the Minkowski sum path ⊕ nib; FontForge's
"round" cap is a half-disk across the stroke, larger than a broad nib),
``removeoverlap="layer"`` (FontForge's default), ``accuracy=A`` (its target error in
font units); the CPU time of that call alone is measured (process_time).  Output JSON:
``{name: {"seconds": s, "points": n, "contours": [[segment, ...], ...], "bbox": [xmin,
ymin, xmax, ymax]}}`` (FontForge's own bounding box of the result, curves included) with
segments as above (quadratic segments do not occur: FontForge strokes in cubics).
"""

import functools
import json
import math
import sys
import time

import fontforge


def draw(glyph, paths):
    pen = glyph.glyphPen()
    for segments, closed in paths:
        pen.moveTo(tuple(segments[0][0]))
        for seg in segments:
            if len(seg) == 2:
                pen.lineTo(tuple(seg[1]))
            else:
                pen.curveTo(tuple(seg[1]), tuple(seg[2]), tuple(seg[3]))
        if closed:
            pen.closePath()
        else:
            pen.endPath()
    pen = None  # FontForge commits the drawing when the pen goes away


def segments_of(contour):
    pts = [(p.x, p.y, bool(p.on_curve)) for p in contour]
    if not pts:
        return []
    k = next(i for i, p in enumerate(pts) if p[2])
    pts = pts[k:] + pts[:k] + [pts[k]]  # start on-curve, closed
    segs, cur, offs = [], pts[0][:2], []
    for x, y, on in pts[1:]:
        if on:
            if not offs:
                segs.append([cur, (x, y)])
            elif len(offs) == 2:
                segs.append([cur, offs[0], offs[1], (x, y)])
            else:  # quadratic (not produced by stroke): keep as a 3-point segment
                segs.append([cur] + offs + [(x, y)])
            cur, offs = (x, y), []
        else:
            offs.append((x, y))
    return segs


def write_timed(steps):
    """Run every ``(name, glyph, step)`` of ``steps`` (``step()`` changes ``glyph``'s
    outline; whatever the iteration does before yielding it is not timed) and write
    the output JSON of the module docstring to stdout: the CPU time (process_time)
    of ``step()`` alone, the points, the contours and the bounding box of the glyph
    after it."""
    out = {}
    for name, glyph, step in steps:
        t0 = time.process_time()
        step()
        seconds = time.process_time() - t0
        layer = glyph.foreground
        out[name] = {"seconds": seconds, "points": sum(len(c) for c in layer),
                     "contours": [segments_of(c) for c in layer],
                     "bbox": list(glyph.boundingBox())}
    json.dump(out, sys.stdout)


def _stroke_steps(job):
    font = fontforge.font()
    font.em = 1000
    nib = job["nib"]
    acc = float(job["accuracy"])
    for k, (name, paths) in enumerate(job["glyphs"].items()):
        g = font.createChar(-1, "g%d" % k)
        draw(g, paths)
        if nib[0] == "elliptical":
            yield name, g, functools.partial(
                g.stroke, "elliptical", float(nib[1]), float(nib[2]),
                math.radians(float(nib[3])), "nib", "nib", accuracy=acc,
                removeoverlap="layer")
        else:
            yield name, g, functools.partial(g.stroke, "circular", float(nib[1]), "nib", "nib",
                                             accuracy=acc, removeoverlap="layer")


def main():
    write_timed(_stroke_steps(json.load(sys.stdin)))


if __name__ == "__main__":
    main()

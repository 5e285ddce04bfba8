"""FontForge's whole stroke workflow for bench/stroke.py (run with Debian's python3).

    /usr/bin/python3 bench/fontforge_font.py SKELETON.ufo OUT.otf --nib W,H,ANGLE|D
        [--accuracy 0.25] [--glyphs NAME,NAME,...] [--flags no-hints,round] [--autohint]

What a type designer's FontForge script does for the job of ``morph stroke SKELETON.ufo
-o OUT.otf``: ``fontforge.open`` the skeleton UFO (its open contours stay open, point
for point), stroke every glyph with contours (``--glyphs``: those chosen and the bases
of their references; the others' contours are cleared, their advances and references
kept, as ``morph stroke --glyphs`` leaves them empty) by the call of
``bench/fontforge_stroke.py``, ``glyph.stroke("elliptical", W, H, ANGLE, "nib",
"nib", accuracy=A, removeoverlap="layer")`` (``--nib D``: ``"circular", D``), then
``font.generate(OUT.otf, flags=FLAGS)``: OpenType CFF.  A reference is kept, as a
reference to its stroked base, only where the stroke commutes with its transformation
(the identity, or a half turn: both nibs are centrally symmetric); the others are
unlinked first (``glyph.unlinkRef``) and their outlines stroked in their glyph, since
the stroke of a scaled, slanted or mirrored base is not the stroke of the scaled,
slanted or mirrored skeleton (its nib would be transformed too).  This is
``morph stroke``'s rule (``morph.fonts.stroke.keep_component``; morph also
decomposes a kept component whose stroke would overlap the rest of its glyph's,
where FontForge leaves overlapping references).  morph writes no hints and
integer coordinates, hence the defaults, the strongest fair setting: FontForge's
autohinter off before generating (``fontforge.setPrefs("AutoHint", 0)``; FontForge's
default autohints every changed glyph before generating, even with the ``no-hints``
flag, which then drops the hints: 5.6 of 12.4 s CPU on the 300 hanzi, for the same
outlines; ``--autohint`` keeps it on), ``--flags`` (comma separated) ``no-hints,round``:
no hints written, coordinates rounded to integers (FontForge writes a CFF's fractional
coordinates as they are otherwise, 3 times the bytes); ``--flags "" --autohint`` is
FontForge's own default.  Prints one JSON line: the process's own CPU time
(process_time: Python's startup, ``import fontforge``, opening, stroking,
generating), each step's, and the glyphs stroked."""

import argparse
import json
import math
import time

import fontforge


def with_bases(font, names):
    """``names`` and the glyphs their references use, to any depth (a composite's
    outline is its bases': they are stroked with it)."""
    chosen, todo = set(), list(names)
    while todo:
        name = todo.pop()
        if name not in chosen and name in font:
            chosen.add(name)
            todo += [ref[0] for ref in font[name].references]
    return chosen


def unlink_transformed(font, names=None):
    """Unlink, in the glyphs ``names`` (None: all), every reference whose
    transformation is neither the identity nor a half turn (see the module doc; by
    base name, so a kept reference to the same base is unlinked with it); the number
    of glyphs changed."""
    keep = ((1.0, 0.0, 0.0, 1.0), (-1.0, 0.0, 0.0, -1.0))
    changed = 0
    for glyph in font.glyphs():
        if names is not None and glyph.glyphname not in names:
            continue
        moved = {ref[0] for ref in glyph.references
                 if tuple(round(float(v), 9) for v in ref[1][:4]) not in keep}
        for base in sorted(moved):
            glyph.unlinkRef(base)
        changed += bool(moved)
    return changed


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("skeleton")
    ap.add_argument("output")
    ap.add_argument("--nib", required=True, help="W,H,ANGLE: an elliptical nib in font "
                                                 "units, long axis ANGLE degrees; D: a disk")
    ap.add_argument("--accuracy", type=float, default=0.25, help="font units")
    ap.add_argument("--glyphs", default="", help="glyph names to stroke (default: all)")
    ap.add_argument("--flags", default="no-hints,round")
    ap.add_argument("--autohint", action="store_true", help="autohint before generating")
    opt = ap.parse_args()
    nib = [float(v) for v in opt.nib.split(",")]
    nib = ["elliptical", nib[0], nib[1], math.radians(nib[2])] if len(nib) == 3 else [
        "circular", nib[0]]
    steps = {"start": time.process_time()}
    font = fontforge.open(opt.skeleton)
    steps["open"] = time.process_time()
    unlinked = unlink_transformed(font, set(opt.glyphs.split(",")) if opt.glyphs else None)
    chosen = with_bases(font, opt.glyphs.split(",")) if opt.glyphs else None
    stroked = 0
    for glyph in font.glyphs():
        if not len(glyph.foreground):
            continue
        if chosen is not None and glyph.glyphname not in chosen:
            glyph.foreground = fontforge.layer()
            continue
        glyph.stroke(*nib, "nib", "nib", accuracy=opt.accuracy, removeoverlap="layer")
        stroked += 1
    steps["stroke"] = time.process_time()
    fontforge.setPrefs("AutoHint", int(opt.autohint))
    font.generate(opt.output, flags=tuple(f for f in opt.flags.split(",") if f))
    steps["generate"] = time.process_time()
    print(json.dumps({"cpu": steps["generate"], "glyphs": stroked, "unlinked": unlinked,
                      "steps": {k: steps[k] - steps[p] for p, k in zip(steps, list(steps)[1:])},
                      "startup": steps["start"]}))


if __name__ == "__main__":
    main()

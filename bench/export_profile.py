"""Time and profile the certified exporter on the inputs of the font and SVG commands.

    python -m bench.export_profile [--cases stroke,brush,sumOM,Odisk,Oellipse]
                                   [--glyphs A-Z,a-z,0-9] [--rev REV] [--profile]
                                   [--top 30] [--check] [--cache FILE] [--batch N]

The geometry (sums, strokes) is computed once and cached in ``--cache`` (default
morph_export_profile.pkl in the system temporary folder; delete it to recompute), so
that exporters are timed on the same input even while the sum code changes.  ``--rev REV`` times the exporter of a
git revision (``git show REV:morph/export.py``, run against today's bernstein/piece)
instead of the working tree's.  Times are CPU seconds of this process
(``time.process_time``), one warm run.  Cases (tol in font units, glyphs in font
units):

- ``stroke``: Relief SingleLine subset (tests/data/relief) glyphs ``--glyphs`` stroked
  with the default nib of ``morph stroke`` (ellipse 90 x 20 at 30 degrees) at tol 0.5:
  ``stroke_paths(paths, nib, 0.125)``, export ``loop_to_beziers(loop, 0.375,
  wrap=True)`` (bench/stroke.py's morph rows);
- ``stroke-round``: the same with the disk of diameter 60;
- ``brush``: bundled Noto Sans (TrueType) glyphs A-Z, a-z ⊕ the ``morph brush`` nib
  (ellipse 80 x 30 at 30 degrees), tol 0.5: ``minkowski_sum(region, nib, 0.25)``, export
  ``contours_from_loops(loops, 0.25, quadratic=True)`` (what ``sweep_glyph`` does);
- ``sumOM``: ``morph sum O M -o x.svg`` at 1e-4 em: sum at 0.025, ``svg_path_data``
  within 0.075 units;
- ``Odisk``, ``Oellipse``: CFF O ⊕ disk r = 40 / ellipse 80 x 30 at 30 degrees at 1e-4
  em, written as SVG path data (bench/peers.py section 4).

Points: on- and off-curve points of the written curves (a line 1, a quadratic 2, a
cubic 3).  ``--check`` measures the largest distance from dense samples (64 per
written curve) to the input loops sampled densely (2048 per piece), a lower bound of
the error, to compare with tol.
"""

import argparse
import cProfile
import io
import json
import os
import pickle
import pstats
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")    # as the CLI does, before numpy

import numpy as np  # noqa: E402 - after OPENBLAS_NUM_THREADS is set, before numpy loads

from morph import bernstein as bz  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.render.svg import rounding as svg_rounding  # noqa: E402 - after sys.path gets the repo root

RELIEF = ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"
CASES = ("stroke", "brush", "sumOM", "Odisk", "Oellipse")


def glyph_names(spec):
    from morph.fonts.brush import parse_glyph_spec

    return parse_glyph_spec(spec)


def build_inputs(case, glyphs):
    """[(label, loops, export tol, kind)]: kind 'beziers', 'svg' or 'quadratic'."""
    from morph.budget import plan
    from morph.fonts.brush import ellipse_nib
    from morph.minkowski import minkowski_sum
    from morph.parse import cubic_test_font_path, glyph_region

    out = []
    if case.startswith("stroke"):
        from morph.parse.ufo import decomposed_paths, glyph_names_for, load_ufo
        from morph.stroke import stroke_paths

        font = load_ufo(str(RELIEF), lazy=False)
        nib = ellipse_nib(90, 20, 30) if case == "stroke" else ellipse_nib(60, 60, 0)
        geometry, export = plan(0.5)[:2]
        for name in glyph_names_for(font, glyph_names(glyphs)):
            region = stroke_paths(decomposed_paths(font, name), nib, geometry)
            out.append((name, region, export, "beziers"))
    elif case == "brush":
        from morph.parse import read_glyph
        from fontTools.ttLib import TTFont
        from morph.parse import default_font_path

        font = TTFont(default_font_path())
        nib = ellipse_nib(80, 30, 30)
        for name in glyph_names("A-Z,a-z"):
            region = read_glyph(font, name).region
            out.append((name, minkowski_sum(region, nib, 0.25), 0.25, "quadratic"))
    elif case == "sumOM":
        a, b = glyph_region("O").region, glyph_region("M").region
        st, et = plan(0.1)[:2]
        out.append(("O+M", minkowski_sum(a, b, st), et, "svg"))
    elif case in ("Odisk", "Oellipse"):
        o = glyph_region("O", font=str(cubic_test_font_path())).region
        nib = [pc.circle((0.0, 0.0), 40.0)] if case == "Odisk" else ellipse_nib(80, 30, 30)
        st, et = plan(0.1)[:2]
        out.append((case, minkowski_sum(o, nib, st), et, "svg"))
    else:
        raise SystemExit("unknown case %r" % case)
    return out


def exporter(rev):
    if rev is None:
        import morph.export as mod
        return mod
    from bench.export import exporter_at

    return exporter_at(rev)


def export(ex, loops, tol, kind):
    """Written curves of one glyph / shape: list of (k, 2) arrays."""
    curves = []
    batched = hasattr(ex, "loops_to_beziers")         # older revisions: loop by loop
    if kind == "quadratic":
        from morph.region import reverse_loop
        loops = [reverse_loop(loop) for loop in loops]
        if batched:
            return [c for cs in ex.loops_to_quadratics(loops, tol, wrap=True) for c in cs]
        for loop in loops:
            curves += ex.loop_to_quadratics(loop, tol, wrap=True)
    else:
        t = tol - svg_rounding(tol)[1] if kind == "svg" else tol   # svg_path_data's share
        if batched:
            return [c for cs in ex.loops_to_beziers(loops, t, wrap=True) for c in cs]
        for loop in loops:
            curves += ex.loop_to_beziers(loop, t, wrap=True)
    return curves


def points(curves):
    return sum(len(c) - 1 for c in curves)


def measured_error(loops, curves):
    """Largest distance from 64 samples per curve to the loops, each piece a polyline
    of 2048 chords (nearest vertex by a k-d tree, then the distance to its two
    chords): a lower bound of the one-sided Hausdorff distance up to the chords'
    sagitta."""
    from scipy.spatial import cKDTree

    polys = [pc.evaluate(p, np.linspace(0, 1, 2049)) for lp in loops for p in lp]
    a = np.vstack([q[:-1] for q in polys])
    b = np.vstack([q[1:] for q in polys])
    tree = cKDTree(np.vstack([a, b]))
    s = np.linspace(0, 1, 65)
    pts = np.vstack([bz.evaluate(np.asarray(c, float), s) for c in curves])
    _, idx = tree.query(pts, k=4)
    seg = idx % len(a)
    best = np.full(len(pts), np.inf)
    for j in range(idx.shape[1]):
        for off in (-1, 0, 1):
            k = np.clip(seg[:, j] + off, 0, len(a) - 1)
            d = b[k] - a[k]
            u = np.clip(((pts - a[k]) * d).sum(1) / np.maximum((d * d).sum(1), 1e-300), 0, 1)
            best = np.minimum(best, np.hypot(*(a[k] + u[:, None] * d - pts).T))
    return float(best.max())


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default=",".join(CASES))
    ap.add_argument("--glyphs", default="A-Z,a-z,0-9", help="stroke cases only")
    ap.add_argument("--rev", default=None)
    ap.add_argument("--profile", action="store_true")
    ap.add_argument("--top", type=int, default=30)
    ap.add_argument("--check", action="store_true")
    ap.add_argument("--cache", default=os.path.join(tempfile.gettempdir(),
                                                    "morph_export_profile.pkl"))
    ap.add_argument("--save", default=None, help="write {case: {shape: points}} as JSON")
    ap.add_argument("--batch", type=int, default=1,
                    help="also time the export of N shapes per call (the loops of N "
                         "glyphs in one loops_to_beziers call, as morph stroke / brush "
                         "do): the totals printed are then those")
    args = ap.parse_args()

    cache = {}
    if os.path.exists(args.cache):
        with open(args.cache, "rb") as f:
            cache = pickle.load(f)
    ex = exporter(args.rev)
    saved = {}
    print("exporter: %s; load %s" % (args.rev or "working tree",
                                     " ".join("%.1f" % v for v in os.getloadavg())))
    for case in args.cases.split(","):
        key = (case, args.glyphs if case.startswith("stroke") else "")
        if key not in cache:
            t0 = time.process_time()
            cache[key] = build_inputs(case, args.glyphs)
            print("%s: geometry computed in %.2f s CPU" % (case, time.process_time() - t0))
            with open(args.cache, "wb") as f:
                pickle.dump(cache, f)
        items = cache[key]
        export(ex, items[0][1], items[0][2], items[0][3])     # warm-up (imports, caches)
        prof = cProfile.Profile() if args.profile else None
        total, npts, worst = 0.0, 0, 0.0
        per = []
        for label, loops, tol, kind in items:
            t0 = time.process_time()
            if prof:
                prof.enable()
            curves = export(ex, loops, tol, kind)
            if prof:
                prof.disable()
            dt = time.process_time() - t0
            total += dt
            npts += points(curves)
            if args.check:
                e = measured_error(loops, curves) / tol
                worst = max(worst, e)
            per.append((dt, label))
            saved.setdefault(case, {})[label] = points(curves)
        if args.batch > 1:        # shapes converted N at a time, as the font commands do
            total, npts = 0.0, 0
            for c in range(0, len(items), args.batch):
                chunk = items[c:c + args.batch]
                t0 = time.process_time()
                if prof:
                    prof.enable()
                curves = export(ex, [lp for _, loops, _, _ in chunk for lp in loops],
                                chunk[0][2], chunk[0][3])
                if prof:
                    prof.disable()
                total += time.process_time() - t0
                npts += points(curves)
        n = len(items)
        print("%-9s %3d shapes: export %.3f s CPU, %.1f ms/shape, %.1f points/shape%s"
              % (case, n, total, 1e3 * total / n, npts / n,
                 "; worst sampled error/tol %.3f" % worst if args.check else ""))
        print("          slowest: " + ", ".join("%s %.0f ms" % (lb, 1e3 * dt)
                                                  for dt, lb in sorted(per)[::-1][:5]))
        if prof:
            s = io.StringIO()
            pstats.Stats(prof, stream=s).sort_stats("cumulative").print_stats(args.top)
            print(s.getvalue())
            s = io.StringIO()
            pstats.Stats(prof, stream=s).sort_stats("tottime").print_stats(args.top)
            print(s.getvalue())
    if args.save:
        with open(args.save, "w") as f:
            json.dump(saved, f, indent=0)


if __name__ == "__main__":
    main()

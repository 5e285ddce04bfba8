"""Cubic export: cubics per piece, certified totals.

    python bench/export.py [--md bench/export.md | --no-write] [--quick]

Measures, in one run:

1. A 90° circular arc of radius 2 (one exact rational quadratic) at tol 1e-3 ... 1e-8:
   cubics from ``morph.export.piece_to_cubics`` (kurbo's fit, certified), from
   kurbo alone (``kurbopy.fit_to_bezpath`` on the exact arc, its own sampled error
   metric), from the classic curvature-matching (κ) cubic (end tangents and end
   curvatures of the circle, equal arcs, fewest that meet tol), and from the previous
   exporter (same-parameter Hermite / least-squares fit halved at t = 1/2, the
   code before commit 2043d8b, loaded from git).  The error column is measured
   independently: max | |C(t)| - 2 | over 257 samples per cubic (exact distance to
   the circle).
2. ``morph offset O --radius 0.04`` as the command writes it (sum within
   ``plan(tol).geometry``, SVG path data within the export share) on the bundled
   Noto Sans TrueType and CFF fonts, at tol 1e-4 em (the default, 0.1 unit) and
   1e-5 em: the number of SVG path commands (C / Q / L) of the offset outline, against
   ``kurbopy.offset_cubic`` applied to each cubic of the CFF O (40 units, accuracy
   0.1 and 0.01 unit; untrimmed per-segment offsets, so a lower bound of what a
   kurbo-based offsetter writes) and the previous exporter on the same pieces.
3. Brushed glyphs (the ``morph brush`` default nib: ellipse 80 x 30 units rotated
   30°, total tol 0.5 unit, split by ``plan``): outline points (on- and
   off-curve, cubics) per glyph, new exporter against the previous one.  The issue
   quotes FontForge's Expand Stroke at 51-95 points for such glyphs.
4. The certified total: circle ⊕ circle written as SVG through the command's path
   (split budget), error of the written file against the exact circle (parsed back
   with svgpathtools, 200 samples per segment), against the previous behaviour
   (sum at tol and export at tol, previous exporter).
5. The split itself: the O offset with the sum given 0.5, 0.25 or 0.1 of tol.
6. Points at equal measured error: the TrueType O ⊕ disk (r = 40
   units) and O ⊕ ellipse (semi-axes 40 and 15 at 30°): morph (``minkowski_sum`` at
   the sum share, ``loop_to_beziers(wrap=True)`` at the export share), FontForge's
   Expand Stroke (Debian's python3-fontforge: the O's contours stroked with the nib,
   the O drawn again and ``removeOverlap``: O ⊕ nib = O ∪ (∂O ⊕ nib)) at several
   ``accuracy`` values, Skia (skia-pathops: the O mapped by the inverse of the
   ellipse's linear map, stroked with round joins, united with the filled O, mapped
   back, conics to quadratics; scaled up 1 / 4 / 16 times for precision).  Error: the
   two-sided Hausdorff distance of each output (flattened within 0.005) from an
   independent Clipper polygon (the O's outline ⊕ nib, ``tests.oracles.stroke_reference``,
   flattened within 0.005, united with the filled O), boundaries sampled every 0.25
   unit.  Points: on- and off-curve points (a line 1, a quadratic 2, a cubic 3).
"""

import argparse
import math
import subprocess
import sys
import time
import types
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import kurbopy  # noqa: E402 - after sys.path gets the repo root

from morph import bernstein as bz  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.budget import SUM_SHARE, plan  # noqa: E402 - after sys.path gets the repo root
from morph.export import loop_to_beziers, piece_to_cubics  # noqa: E402 - after sys.path gets the repo root
from morph.render.svg import svg_path_data  # noqa: E402 - after sys.path gets the repo root

PREVIOUS = "2043d8b~1"      # the exporter before kurbo's fit


def exporter_at(rev):
    """morph.export as it was at git revision ``rev`` (git show REV:morph/export.py),
    loaded as a module of the package (its relative imports resolve to today's)."""
    src = subprocess.run(["git", "-C", str(ROOT), "show", rev + ":morph/export.py"],
                         capture_output=True, text=True, check=True).stdout
    mod = types.ModuleType("morph.export_at_" + rev)
    mod.__package__ = "morph"
    exec(compile(src, "morph/export.py@" + rev, "exec"), mod.__dict__)
    return mod


def previous_exporter():
    """The previous morph.export module (at PREVIOUS)."""
    return exporter_at(PREVIOUS)


def previous_beziers(old):
    """The previous SVG writer's curves: polynomial pieces of degree <= 3 as they are,
    every other piece by itself through the previous exporter."""
    def loop_to_beziers(loop, tol, wrap=False):
        out = []
        for p in loop:
            p = np.asarray(p, float)
            if pc.is_polynomial(p) and len(p) <= 4:
                out.append(pc.cartesian(p))
            else:
                out.extend(old.piece_to_cubics(p, tol))
        return out
    return loop_to_beziers


# ------------------------------------------------------------------ 1. the arc

class ArcSource:
    """kurbo fitting source for the exact circular arc (trig formula)."""

    def __init__(self, radius, sweep):
        self.r, self.a = radius, sweep

    def sample_pt_deriv(self, t):
        th = self.a * t
        return (kurbopy.Point(self.r * math.cos(th), self.r * math.sin(th)),
                kurbopy.Vec2(-self.r * self.a * math.sin(th), self.r * self.a * math.cos(th)))

    def sample_pt_tangent(self, t, sign):
        return self.sample_pt_deriv(t)

    def break_cusp(self, t0, t1):
        return None


def kappa_cubic_error(theta, r=1.0):
    """Radial error of the symmetric cubic matching end tangents and curvature 1/r."""
    from scipy.optimize import brentq

    h = theta / 2
    p0, t0 = np.array([math.cos(h), -math.sin(h)]), np.array([math.sin(h), math.cos(h)])
    p3, t3 = np.array([math.cos(h), math.sin(h)]), np.array([-math.sin(h), math.cos(h)])

    def ctrl(d):
        return np.array([p0, p0 + d * t0, p3 - d * t3, p3])

    def curv(d):
        c = ctrl(d)
        a, b = c[1] - c[0], c[2] - c[1]
        return 2.0 / 3.0 * abs(a[0] * b[1] - a[1] * b[0]) / np.hypot(*a) ** 3 - 1.0

    ds = np.linspace(1e-3, 2 * math.sin(h), 400)
    vals = [curv(d) for d in ds]
    roots = [brentq(curv, ds[i], ds[i + 1]) for i in range(len(ds) - 1)
             if vals[i] * vals[i + 1] < 0]
    err = min(np.abs(np.hypot(*bz.evaluate(ctrl(d), np.linspace(0, 1, 2001)).T) - 1).max()
              for d in roots)
    return r * err


def classic_count(sweep, r, tol):
    """Equal arcs with the classic circle cubic (handles 4/3 tan(theta/4) r): fewest
    meeting tol (radial error, 2001 samples)."""
    k = 1
    while True:
        th = sweep / k
        d = 4.0 / 3.0 * math.tan(th / 4)
        c = np.array([[1, 0], [1, d], [math.cos(th) + d * math.sin(th),
                      math.sin(th) - d * math.cos(th)], [math.cos(th), math.sin(th)]])
        if r * np.abs(np.hypot(*bz.evaluate(c, np.linspace(0, 1, 2001)).T) - 1).max() <= tol:
            return k
        k += 1


def kappa_count(sweep, r, tol):
    k = 1
    while kappa_cubic_error(sweep / k, r) > tol:
        k += 1
    return k


def arc_table(old):
    arc = pc.ellipse_arc((0, 0), 2.0, 2.0, 0.0, 0.0, np.pi / 2)[0]
    rows = []
    for i in range(3, 9):
        tol = 10.0 ** -i
        t = time.perf_counter()
        cubics = piece_to_cubics(arc, tol)
        ms = (time.perf_counter() - t) * 1e3
        pts = np.vstack([bz.evaluate(c, np.linspace(0, 1, 257)) for c in cubics])
        err = np.abs(np.hypot(*pts.T) - 2.0).max()
        kurbo = len(list(kurbopy.fit_to_bezpath(ArcSource(2.0, np.pi / 2), tol).segments()))
        rows.append((tol, len(cubics), err / tol, ms, kurbo, kappa_count(np.pi / 2, 2.0, tol),
                     classic_count(np.pi / 2, 2.0, tol), len(old.piece_to_cubics(arc, tol))))
    return rows


# ------------------------------------------------------------------ 2. offset O

def font_paths():
    from morph.parse import default_font_path

    ttf = Path(default_font_path())
    return {"ttf": ttf, "cff": ttf.with_suffix(".otf")}


def commands(d):
    return sum(d.count(c) for c in "CQL")


def offset_table(old, tols):
    from morph.offset import offset_region
    from morph.parse import glyph_region

    rows = []
    for key, path in font_paths().items():
        g = glyph_region("O", str(path))
        upm = 1000.0
        for tol_em in tols:
            tol = tol_em * upm
            st, et = plan(tol)[:2]
            t = time.process_time()
            loops = offset_region(g.region, 0.04 * upm, st)
            d = svg_path_data(loops, et)
            sec = time.process_time() - t
            # previous behaviour: sum at tol, previous exporter within 0.8 tol (+ rounding)
            prev_loops = offset_region(g.region, 0.04 * upm, tol)
            prev = sum(1 if (pc.is_polynomial(p) and len(p) <= 3) else
                       len(old.piece_to_cubics(p, 0.8 * tol)) for lp in prev_loops for p in lp)
            rows.append((key, tol_em, tol, commands(d), sum(map(len, loops)), prev, sec))
    return rows


def kurbo_offset_counts(accuracies):
    """kurbopy.offset_cubic on every cubic (and line) of the CFF O, 40 units outward."""
    from fontTools.pens.recordingPen import RecordingPen
    from fontTools.ttLib import TTFont

    font = TTFont(str(font_paths()["cff"]))
    gs = font.getGlyphSet()
    pen = RecordingPen()
    gs[font.getBestCmap()[ord("O")]].draw(pen)
    segs, cur, start = [], None, None
    for op, args in pen.value:
        if op == "moveTo":
            cur = start = args[0]
        elif op == "lineTo":
            segs.append((cur, args[0]))
            cur = args[0]
        elif op == "curveTo":
            segs.append((cur,) + tuple(args))
            cur = args[-1]
        elif op in ("closePath", "endPath"):
            if cur != start:
                segs.append((cur, start))
            cur = start
    out = {}
    for acc in accuracies:
        n = 0
        for s in segs:
            if len(s) == 2:
                n += 1
                continue
            c = kurbopy.CubicBez(*[kurbopy.Point(*p) for p in s])
            # kurbo offsets to the left of the direction of travel: CFF outer contours
            # run counter-clockwise in y-up, so -40 is outward for them.
            n += len(list(kurbopy.offset_cubic(c, -40.0, acc).segments()))
        out[acc] = (n, len(segs))
    return out


# ------------------------------------------------------------------ 3. brushed glyphs

def brush_table(old, chars, tol=0.5):
    from morph.fonts.brush import ellipse_nib
    from morph.minkowski import minkowski_sum
    from morph.parse import glyph_region

    nib = ellipse_nib(80, 30, 30)
    st, et = plan(tol)[:2]
    rows = []
    for key, path in font_paths().items():
        for ch in chars:
            g = glyph_region(ch, str(path))
            loops = minkowski_sum(g.region, nib, st)
            t = time.process_time()

            def points(conv, tol_fit):
                n = 0
                for lp in loops:
                    for p in lp:
                        if pc.is_polynomial(p) and len(p) == 2:
                            n += 1
                        else:
                            n += 3 * len(conv(p, tol_fit))
                return n
            new = sum(len(b) - 1 for lp in loops for b in loop_to_beziers(lp, et, wrap=True))
            sec = time.process_time() - t
            per_piece = points(piece_to_cubics, et)
            prev = points(old.piece_to_cubics, tol)
            rows.append((key, ch, sum(map(len, loops)), new, per_piece, prev, sec))
    return rows


# ------------------------------------------------------------------ 6. O ⊕ nib vs peers

#: The nibs of section 6 (font units): the disk of `morph offset O --radius 0.04` and
#: bench/peers.py's ellipse (semi-axes 40 and 15, long axis at 30°).
PEER_NIBS = (("disk", 40.0, 40.0, 0.0), ("ellipse", 40.0, 15.0, 30.0))

FF_WORKER = r"""
import json, math, sys, time
import fontforge
job = json.load(sys.stdin)
font = fontforge.font()
font.em = 1000
out = []
for acc in job["accuracies"]:
    g = font.createChar(-1, "g%d" % len(out))
    for rep in range(2):
        pen = g.glyphPen(replace=False)
        for segs in job["contours"]:
            segs = [s[::-1] for s in segs[::-1]]  # outer contours clockwise in FontForge
            pen.moveTo(tuple(segs[0][0]))
            for s in segs:
                if len(s) == 2:
                    pen.lineTo(tuple(s[1]))
                else:
                    pen.curveTo(tuple(s[1]), tuple(s[2]), tuple(s[3]))
            pen.closePath()
        pen = None
        if rep == 0:
            t0 = time.process_time()
            rx, ry, ang = job["nib"]
            if rx == ry:
                g.stroke("circular", 2 * rx, "round", "round", accuracy=acc,
                         removeoverlap="layer")
            else:
                g.stroke("elliptical", 2 * rx, 2 * ry, math.radians(ang), "nib", "nib",
                         accuracy=acc, removeoverlap="layer")
    g.removeOverlap()
    sec = time.process_time() - t0
    cs = []
    for c in g.foreground:
        pts = [(p.x, p.y, bool(p.on_curve)) for p in c]
        k = next(i for i, q in enumerate(pts) if q[2])
        pts = pts[k:] + pts[:k] + [pts[k]]
        segs, cur, offs = [], pts[0][:2], []
        for x, y, on in pts[1:]:
            if on:
                segs.append([cur] + offs + [(x, y)])
                cur, offs = (x, y), []
            else:
                offs.append((x, y))
        cs.append(segs)
    out.append({"accuracy": acc, "seconds": sec, "contours": cs,
                "points": sum(len(c) for c in g.foreground)})
json.dump(out, sys.stdout)
"""


def _o_contours():
    """The TrueType O's contours as cubic segments (exact degree elevation)."""
    from morph.parse import glyph_region

    g = glyph_region("O", str(font_paths()["ttf"]))
    return g.region, [[bz.to_degree(pc.cartesian(p), 3) if len(p) > 2 else pc.cartesian(p)
                       for p in loop] for loop in g.region]


def _nib_region(rx, ry, ang):
    return [pc.ellipse((0.0, 0.0), rx, ry, math.radians(ang))]


def _reference(region, nib, flat=0.005):
    """Independent polygon of O ⊕ nib: the O's outline stroked in Clipper
    (tests.oracles.stroke_reference, closed paths) united with the filled O (shapely)."""
    from tests.oracles.reference import region_to_shapely
    from tests.oracles.stroke_reference import stroke_polygon

    ring = stroke_polygon([(loop, True) for loop in region], nib, flat)
    return ring.union(region_to_shapely(region, flat))


def _measure(beziers, ref):
    """Hausdorff distance of closed Bézier contours from the reference polygon."""
    from tests.oracles.reference import hausdorff, region_to_shapely

    loops = [[pc.from_points(np.asarray(b, float)) for b in c] for c in beziers]
    return hausdorff(region_to_shapely(loops, 0.005), ref, 0.25)


def _skia_o(region, rx, ry, ang, scale):
    """Skia's recipe for O ⊕ ellipse: map the ellipse to a disk (A^-1), stroke with
    round caps and joins, union with the filled O, map back (A), conics to quads."""
    import pathops
    from fontTools.pens.recordingPen import RecordingPen

    c, s_ = math.cos(math.radians(ang)), math.sin(math.radians(ang))
    m = np.array([[c, -s_], [s_, c]]) @ np.diag([1.0, ry / rx])   # disk(rx) -> the nib
    inv = np.linalg.inv(m) * scale            # scaled up: Skia's precision is fixed
    a = m / scale
    t0 = time.process_time()
    path = pathops.Path()
    pen = path.getPen()
    for loop in region:
        pts = [pc.cartesian(p) @ inv.T for p in loop]
        pen.moveTo(tuple(pts[0][0]))
        for q in pts:
            if len(q) == 2:
                pen.lineTo(tuple(q[1]))
            elif len(q) == 3:
                pen.qCurveTo(tuple(q[1]), tuple(q[2]))
            else:
                pen.curveTo(tuple(q[1]), tuple(q[2]), tuple(q[3]))
        pen.closePath()
    fill = pathops.Path()
    path.draw(fill.getPen())
    path.stroke(2.0 * rx * scale, pathops.LineCap.ROUND_CAP, pathops.LineJoin.ROUND_JOIN, 4)
    res = pathops.op(path, fill, pathops.PathOp.UNION)
    res = res.transform(a[0, 0], a[1, 0], a[0, 1], a[1, 1], 0.0, 0.0)  # a new path
    res.convertConicsToQuads(0.25)
    res.simplify()
    sec = time.process_time() - t0
    rec = RecordingPen()
    res.draw(rec)
    contours, cur, start = [], None, None
    for op, args in rec.value:
        if op == "moveTo":
            cur = start = args[0]
            segs = []
        elif op == "lineTo":
            segs.append([cur, args[0]])
            cur = args[0]
        elif op == "qCurveTo":
            pts = [cur] + list(args)
            for k in range(1, len(pts) - 1):
                p0 = pts[k - 1] if k == 1 else tuple(np.add(pts[k - 1], pts[k]) / 2)
                p2 = pts[k + 1] if k == len(pts) - 2 else tuple(np.add(pts[k], pts[k + 1]) / 2)
                segs.append([p0, pts[k], p2])
            cur = args[-1]
        elif op == "curveTo":
            segs.append([cur] + list(args))
            cur = args[-1]
        elif op == "closePath":
            if cur != start:
                segs.append([cur, start])
            contours.append(segs)
    return [[np.asarray(q, float) for q in c] for c in contours], sec


def peer_table(morph_tols, ff_accuracies, skia_scales):
    """O ⊕ disk and O ⊕ ellipse: points and measured error of morph (sum +
    loop_to_beziers at plan), FontForge Expand Stroke + remove overlap with
    the O, Skia stroke + union with the O."""
    import json
    import os

    from morph.minkowski import minkowski_sum

    region, contours = _o_contours()
    rows = []
    for name, rx, ry, ang in PEER_NIBS:
        nib = _nib_region(rx, ry, ang)
        ref = _reference(region, nib)
        for tol in morph_tols:
            st, et = plan(tol)[:2]
            t0 = time.process_time()
            loops = minkowski_sum(region, nib, st)
            bez = [loop_to_beziers(lp, et, wrap=True) for lp in loops]
            sec = time.process_time() - t0
            pts = sum(len(b) - 1 for c in bez for b in c)
            rows.append((name, "morph", "tol %g" % tol, pts, _measure(bez, ref), sec))
        if os.path.exists("/usr/bin/python3"):
            job = json.dumps({"nib": [rx, ry, ang], "accuracies": list(ff_accuracies),
                              "contours": [[q.tolist() for q in c] for c in contours]})
            proc = subprocess.run(["/usr/bin/python3", "-c", FF_WORKER], input=job,
                                  capture_output=True, text=True)
            if proc.returncode == 0:
                for r in json.loads(proc.stdout):
                    rows.append((name, "FontForge", "accuracy %g" % r["accuracy"],
                                 r["points"], _measure(r["contours"], ref), r["seconds"]))
            else:
                print("FontForge failed:", proc.stderr.strip()[-300:])
        for k in skia_scales:
            cs, sec = _skia_o(region, rx, ry, ang, k)
            pts = sum(len(q) - 1 for c in cs for q in c)
            rows.append((name, "Skia", "scale %g" % k, pts, _measure(cs, ref), sec))
    return rows


# ------------------------------------------------------------------ 4. certified total

def circle_total(old, tols):
    from svgpathtools import parse_path

    from morph.minkowski import minkowski_sum

    rows = []
    for r1, r2 in ((10.0, 4.0), (100.0, 37.0), (1.0, 1.0)):
        for tol in tols:
            a, b = pc.circle((3.0, 2.0), r1), pc.circle((-1.0, 1.0), r2)
            res = []
            for mode in ("split", "previous"):
                if mode == "split":
                    st, et = plan(tol)[:2]
                    d = svg_path_data(minkowski_sum([a], [b], st), et)
                else:
                    loops = minkowski_sum([a], [b], tol)
                    import morph.render.svg as svgmod
                    keep = svgmod.loop_to_beziers
                    svgmod.loop_to_beziers = previous_beziers(old)
                    try:
                        d = svg_path_data(loops, tol)
                    finally:
                        svgmod.loop_to_beziers = keep
                path = parse_path(d)
                z = np.concatenate([[seg.point(t) for t in np.linspace(0, 1, 200)]
                                    for seg in path])
                # the SVG is y-down: the centre (2, 3) is at (2, -3)
                err = np.abs(np.abs(z - complex(2.0, -3.0)) - (r1 + r2)).max()
                res.append((err / tol, commands(d)))
            rows.append((r1, r2, tol) + res[0] + res[1])
    return rows


def share_table(tols, shares=(0.5, 0.25, 0.1)):
    from morph.offset import offset_region
    from morph.parse import glyph_region

    rows = []
    for key, path in font_paths().items():
        g = glyph_region("O", str(path))
        for tol in tols:
            for share in shares:
                st, et = plan(tol, share=share)[:2]
                t = time.process_time()
                loops = offset_region(g.region, 40.0, st)
                t1 = time.process_time()
                d = svg_path_data(loops, et)
                rows.append((key, tol, share, sum(map(len, loops)), commands(d), t1 - t,
                             time.process_time() - t1))
    return rows


def markdown(arc, offs, kurbo, brush, total, shares, seconds):
    head = subprocess.run(["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"],
                          capture_output=True, text=True).stdout.strip()
    out = ["# Cubic export (bench/export.py)", "",
           "Command: `python bench/export.py` (code at %s, %.0f s).  The exporter fits "
           "cubics with kurbo's fitter (`kurbopy.fit_to_bezpath`, area and moment "
           "matching) and certifies each one against the exact rational piece: "
           "`max_s |R(phi(s)) - C(s)| <= tol` for a monotone piecewise-polynomial "
           "reparametrisation phi (a Fréchet, hence Hausdorff, bound; "
           "`morph/export.py`).  'previous' is the exporter before (same-parameter "
           "Hermite / least-squares cubic, halved at t = 1/2)." % (head, seconds), "",
           "## 1. A 90° circular arc of radius 2, cubics per piece", "",
           "| tol | morph (certified) | measured error / tol | ms | kurbo alone | "
           "G2 (κ) cubic | classic 4/3 tan(θ/4) cubic | previous |",
           "|---|---|---|---|---|---|---|---|"]
    for tol, n, e, ms, k, kap, cla, prev in arc:
        out.append("| %.0e | %d | %.2f | %.1f | %d | %d | %d | %d |"
                   % (tol, n, e, ms, k, kap, cla, prev))
    out += ["", "Measured error: max | |C(t)| - 2 | over 257 samples per cubic.  kurbo alone "
            "measures its own error by sampling (no bound); the G2 cubic is the symmetric "
            "cubic with the circle's end tangents and end curvature, the classic one has "
            "handles 4/3 tan(θ/4) r (midpoint on the circle), both on equal sub-arcs.  "
            "Times: wall clock (ms, section 1) or CPU seconds (process_time, the other "
            "sections) on a shared 2-core machine under load.",
            "", "## 2. `morph offset O --radius 0.04` (40 units), SVG path commands", "",
            "| font | tol (em) | sum tol / export tol (units) | commands written | "
            "sum pieces | previous (sum at tol, previous exporter) | CPU s (sum + export) |",
            "|---|---|---|---|---|---|---|"]
    for key, tol_em, tol, n, pieces, prev, sec in offs:
        st, et = plan(tol)[:2]
        out.append("| %s | %.0e | %.3g / %.3g | %d | %d | %d | %.2f |"
                   % (key, tol_em, st, et, n, pieces, prev, sec))
    out += ["", "kurbo's `offset_cubic` on each segment of the CFF O (40 units, no trimming "
            "or joins, so a lower bound): " + ", ".join(
                "%d cubics at accuracy %g unit (%d source segments)" % (n, acc, segs)
                for acc, (n, segs) in kurbo.items()) + ".", "",
            "## 3. Brushed glyphs (ellipse 80 x 30 rotated 30°, tol 0.5 unit), outline points",
            "", "Points: on- and off-curve points of the cubic outline (a line 1, a cubic "
            "3).  Sum within %.2g unit, export within %.2g unit (plan); the "
            "previous exporter is given the whole 0.5 unit, as before.  FontForge's "
            "Expand Stroke: 51-95 points." % plan(0.5)[:2], "",
            "| font | glyph | sum pieces | points (morph, loop_to_beziers) | points (new "
            "fitter piece by piece) | points (previous) | export CPU s (loop_to_beziers) |",
            "|---|---|---|---|---|---|---|"]
    for key, ch, pieces, new, per_piece, prev, sec in brush:
        out.append("| %s | %s | %d | %d | %d | %d | %.2f |"
                   % (key, ch, pieces, new, per_piece, prev, sec))
    out += ["", "## 4. The certified total: circle ⊕ circle written as SVG", "",
            "Error of the written path data against the exact circle of radius r1 + r2 "
            "(svgpathtools, 200 samples per segment), in units of the requested tol. "
            "'split': the commands' path (`plan`: sum at %g tol, SVG export "
            "at the rest, certified).  'previous': sum at tol and the previous exporter "
            "at tol (no total bound)." % SUM_SHARE, "",
            "| r1 + r2 | tol | split: error / tol | split: commands | previous: error / tol "
            "| previous: commands |", "|---|---|---|---|---|---|"]
    for r1, r2, tol, e1, n1, e2, n2 in total:
        out.append("| %g + %g | %.0e | %.2f | %d | %.2f | %d |" % (r1, r2, tol, e1, n1, e2, n2))
    out += ["", "## 5. The split: share of tol given to the sum (offset O by 40 units)", "",
            "The cubics must follow the sum's pieces, ripples of the QAC approximation "
            "included; a smaller sum share leaves the export slack to span several pieces "
            "with one cubic, at the price of a longer sum.  The TrueType O ⊕ circle is "
            "exact (rational degree 6), so its pieces do not depend on the sum tol.  "
            "SUM_SHARE = %g." % SUM_SHARE, "",
            "| font | tol (units) | sum share | sum pieces | commands written | sum CPU s | "
            "export CPU s |", "|---|---|---|---|---|---|---|"]
    for row in shares:
        out.append("| %s | %g | %.2f | %d | %d | %.2f | %.2f |" % row)
    return "\n".join(out) + "\n"


def peer_markdown(rows):
    out = ["", "## 6. O ⊕ disk and O ⊕ ellipse against FontForge and Skia, points at equal "
           "measured error", "",
           "TrueType O (Noto Sans, font units); disk r = 40, ellipse semi-axes 40 x 15 at "
           "30°.  Recipes and error measure: the script's docstring.  CPU s: the "
           "peer's call alone / morph's sum + export.", "",
           "| nib | tool | setting | points | measured error (units) | CPU s |",
           "|---|---|---|---|---|---|"]
    for name, tool, setting, pts, err, sec in rows:
        out.append("| %s | %s | %s | %d | %.3f | %.3f |" % (name, tool, setting, pts, err, sec))
    out += ["", "At equal measured error (morph's fewest-points row whose error is no larger "
            "than the peer's):", "",
            "| nib | peer | peer points | peer error | morph setting | morph points | "
            "morph error | peer / morph points |", "|---|---|---|---|---|---|---|---|"]
    for name in dict.fromkeys(r[0] for r in rows):
        mine = [r for r in rows if r[0] == name and r[1] == "morph"]
        for r in rows:
            if r[0] != name or r[1] == "morph":
                continue
            ok = [m for m in mine if m[4] <= r[4]]
            if not ok:
                out.append("| %s | %s %s | %d | %.3f | none reaches it | | | |"
                           % (name, r[1], r[2], r[3], r[4]))
                continue
            m = min(ok, key=lambda m: m[3])
            out.append("| %s | %s %s | %d | %.3f | %s | %d | %.3f | %.2f |"
                       % (name, r[1], r[2], r[3], r[4], m[2], m[3], m[4], r[3] / m[3]))
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--md", default=str(ROOT / "bench" / "export.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--quick", action="store_true", help="fewer glyphs and tolerances")
    opt = ap.parse_args(argv)
    t0 = time.perf_counter()
    old = previous_exporter()
    arc = arc_table(old)
    offs = offset_table(old, [1e-4] if opt.quick else [1e-4, 1e-5])
    kurbo = kurbo_offset_counts([0.1, 0.01])
    brush = brush_table(old, "OS" if opt.quick else "OSaegM")
    total = circle_total(old, [1e-2, 1e-4] if opt.quick else [1e-2, 1e-3, 1e-4, 1e-5])
    shares = share_table([0.1] if opt.quick else [0.1, 0.01])
    peers = peer_table([1.0, 0.3, 0.1] if opt.quick else [1.0, 0.5, 0.3, 0.2, 0.1, 0.05, 0.03],
                       [1.0, 0.25, 0.1] if opt.quick else [2.0, 1.0, 0.25, 0.1, 0.03],
                       [1, 4] if opt.quick else [1, 4, 16])
    text = markdown(arc, offs, kurbo, brush, total, shares, time.perf_counter() - t0)
    text += "\n".join(peer_markdown(peers)) + "\n"
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()

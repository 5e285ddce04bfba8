"""morph against the strongest way to use each peer: time, output size, certified error.

    python bench/peers.py              # full run (~8-10 min on the shared 2-core machine)
    python bench/peers.py --quick      # O+M, S+g at 1e-4 em, the nibs at 1e-4 em, no brush
    python bench/peers.py --sections glyphs,nibs,cli --no-write

Everything is measured in the same run, on the bundled Noto Sans (upm 1000, font
units; tolerances and errors in em).  Sections:

glyphs  T+M, O+M, S+g at 1e-3, 1e-4, 1e-5 em (TrueType).
        - morph: ``minkowski_sum(a, b, tol)`` in-process; size = control points (sum of
          len(piece)), and the SVG ``morph sum A B -o x.svg --tol T`` writes (sum at
          ``plan``'s share, ``svg_path_data`` with the rest of tol beyond
          the sum's achieved bound, :func:`morph_svg`): path commands and outline
          points (on + off curve points stored; T / S imply their first control
          point as TrueType implies on-curve points, counted as the peers' are).
        - dc (the strongest polygon recipe, ``bench/dc_sum.py``): flatten both glyphs
          within tol/2, pyclipper nonzero union, mapbox-earcut triangles merged into
          convex pieces (Hertel-Mehlhorn), Minkowski sum of every convex pair by merging
          edge angles (numpy, all pairs of one size at once), pyclipper union in a tree
          of 8-input unions.
        - dc-one: the same with ONE pyclipper union of all pair sums (the recipe as
          usually written; Clipper's sweep degrades on heavily overlapping input), as a
          process, killed at --budget s.
        - Clipper MinkowskiSum: the old whole-polygon recipe
          (``tests.oracles.reference.polygon_minkowski_sum``: pyclipper.MinkowskiSum of every
          loop pair plus translated copies, one union), skipped when predicted over
          --budget s.
        - processes: ``python -m morph.cli sum A B --tol T -o a.svg`` against
          ``python bench/dc_sum.py A B --font F --tol T -o b.svg``, run in turn A B A B
          (wall clock and the child's CPU from rusage), start-up and imports included.
nibs    the CFF O (cubics, so that kurbo applies) ⊕ disk r = 40 units and ⊕ the
        ``morph brush`` nib (ellipse 80 x 30 rotated 30 deg), at error levels 1e-4 and
        1e-5 em.  Each method runs a ladder of its accuracy setting; reported is the
        smallest output whose measured error is within the level (and its time; "within":
        bound <= level + 2e-6 em, the oracle's own flattening):
        - morph: ``minkowski_sum`` + ``svg_path_data`` as ``morph sum`` writes its
          SVG (:func:`morph_svg`) at tol = level x {4, 2, 1, 3/4}.
        - Skia (skia-pathops): ``Path.stroke(2r, round cap, round join)`` of the glyph,
          united with the glyph (``pathops.op`` UNION); Skia's stroker works to about
          1/4 unit, so the path is scaled by k = 1 ... 4096 before and 1/k after
          (the ellipse: the glyph is mapped by the inverse of the nib's affine map,
          stroked with a circle, mapped back).  Conics converted to quadratics.
        - FontForge Expand Stroke (python3-fontforge, ``bench/fontforge_stroke.py``'s
          drawing): ``glyph.stroke("circular" | "elliptical", ..., "nib", "nib",
          accuracy=a, removeoverlap="layer")``, the glyph's own contours added and
          ``removeOverlap()``; a = level x {8, 4, 2, 1, 1/2, 1/4} in font units.
        - shapely (disk only): ``buffer(r, quad_segs=q)`` of the glyph flattened
          within level/4, q = 2 ... 256.
        - kurbo (disk only): ``kurbopy.offset_cubic(c, r, accuracy)`` of every cubic
          of the O (a smooth outline: no joins or trimming needed), accuracy =
          level x {4, 2, 1, 3/4, 1/2}.
        - dc polygon at tol = level x {4, 2, 1, 3/4} (the nib flattened within tol/2).
cli     wall time of ``morph glyph T M --frames 10`` and of ``morph brush -o x.ttf
        --glyphs A-Z,a-z`` (``--jobs 1`` and the default), min and median of runs;
        for scale, Skia and FontForge stroking the same 52 glyphs with the same nib.

Error (tests/oracles/measure.py, independent of morph.trim): a certified upper bound on the
distance from the output boundary to the exact boundary of A ⊕ B, by the straddle
test with the exact predicate x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ on operands flattened
within 1e-6 em (resolution ~2e-6 em).  Samples: 16 per curve segment, edge midpoints
of polygons (at most 4000).  Times: min and median of --repeats runs (perf_counter
wall and process_time CPU); ratios use minimums.  The machine has 2 cores shared with
other jobs, so wall times are upper bounds.  Processes run with bytecode cached in a
private folder (PYTHONPYCACHEPREFIX, after one warm-up run), as after a pip install.
"""

import argparse
import json
import math
import os
import re
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
import pathops
import shapely
from fontTools.pens.recordingPen import DecomposingRecordingPen
from fontTools.ttLib import TTFont

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "bench"))

import kurbopy  # noqa: E402 - after sys.path gets the repo root

import dc_sum as DC  # noqa: E402 - bench/dc_sum.py, the peer recipe
from tests.oracles import measure as ME  # noqa: E402 - after sys.path gets the repo root
from morph import parse  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.budget import export_tolerance, plan  # noqa: E402 - after sys.path gets the repo root
from morph.fonts.brush import ellipse_nib  # noqa: E402 - after sys.path gets the repo root
from morph.minkowski import minkowski_sum  # noqa: E402 - after sys.path gets the repo root
from morph.render.svg import svg_path_data  # noqa: E402 - after sys.path gets the repo root
from tests.oracles import reference as R  # noqa: E402 - after sys.path gets the repo root

UPM = 1000.0
TTF = parse.default_font_path()
CFF = parse.cubic_test_font_path()
ELLIPSE = (80.0, 30.0, 30.0)       # the morph brush default nib: width, height, degrees
DISK_R = 40.0                      # = morph offset O --radius 0.04
ORACLE_FLAT = 1e-6 * UPM
E_MAX = 0.05 * UPM


def within(err, level):
    """Measured error within the level: the bound is e + 2 flat with e on the measure's
    ladder; 2 flat is the oracle's own flattening of the operands, not the method's."""
    return err <= level + 2 * ORACLE_FLAT + 1e-9 * level
FF_PYTHON = "/usr/bin/python3"     # Debian's python3-fontforge is for the system Python
# Subprocesses: the repo on the path, and bytecode cached (in a private folder) as
# after a pip install; this machine sets PYTHONDONTWRITEBYTECODE, under which every
# morph process compiles its ~40 modules again (~0.4 s).  One warm-up run per command.
PYCACHE = tempfile.mkdtemp(prefix="peers-pycache-")
ENV = dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""),
           PYTHONPYCACHEPREFIX=PYCACHE)
ENV.pop("PYTHONDONTWRITEBYTECODE", None)

# ------------------------------------------------------------------------- helpers


def glyph(ch, font=TTF):
    return parse.glyph_region(ch, font).region


def morph_svg(a, b, tol):
    """The path data `morph sum A B -o x.svg --tol T` writes: the sum at its share of
    tol (plan), the export with the rest beyond the error the sum
    achieved (export_tolerance of its bound)."""
    out = minkowski_sum(a, b, plan(tol).geometry)
    return svg_path_data(out, export_tolerance(tol, out.bound))


def ctrl_points(loops):
    return int(sum(len(p) for loop in loops for p in loop))


def timed(fn, repeats):
    """(min wall, median wall, min CPU, last result) over ``repeats`` calls."""
    walls, cpus, out = [], [], None
    for _ in range(max(1, repeats)):
        t, c = time.perf_counter(), time.process_time()
        out = fn()
        cpus.append(time.process_time() - c)
        walls.append(time.perf_counter() - t)
    return min(walls), statistics.median(walls), min(cpus), out


def run_process(cmd, timeout=None, cwd=None):
    """Wall seconds and the child's CPU seconds (rusage), or (None, None) on timeout."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    t = time.perf_counter()
    try:
        p = subprocess.run(cmd, env=ENV, capture_output=True, text=True, timeout=timeout,
                           cwd=cwd)
    except subprocess.TimeoutExpired:
        return None, None
    wall = time.perf_counter() - t
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode not in (0, 1):
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-500:]))
    return wall, (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def proc_stats(walls, cpus):
    return dict(wmin=min(walls), wmed=statistics.median(walls), cmin=min(cpus), n=len(walls))


def fmt_t(s):
    if s is None:
        return "-"
    return "%.0f ms" % (s * 1e3) if s < 1 else "%.2f s" % s


def fmt_e(units):
    return "-" if units is None else ("%.2g" % (units / UPM))


# ------------------------------------------------------------------ error measure

def _bez_to_pieces(loops):
    """Loops of (k, 2) polynomial Béziers -> loops of homogeneous pieces (w = 1)."""
    return [[np.column_stack([np.asarray(b, float), np.ones(len(b))]) for b in lp]
            for lp in loops]


def err_pieces(loops, oracle, per_piece=16):
    p, n = ME.sample_pieces(loops, per_piece)
    return float(ME.certified_error(p, n, oracle, oracle.flat / 10, E_MAX).max())


def err_beziers(loops, oracle):
    return err_pieces(_bez_to_pieces(loops), oracle)


def rings_geometry(rings):
    polys = [shapely.Polygon(o, hs) for o, hs in rings]
    return shapely.make_valid(shapely.MultiPolygon(polys) if len(polys) != 1 else polys[0])


def err_polygon(geom, oracle):
    p, n = ME.sample_polygon(geom, 4000)
    return float(ME.certified_error(p, n, oracle, oracle.flat / 10, E_MAX).max())


def poly_vertices(geom):
    n = 0
    for poly in R._polygons(geom):
        n += len(poly.exterior.coords) - 1
        n += sum(len(r.coords) - 1 for r in poly.interiors)
    return n


# ------------------------------------------------------- curve outlines: parsing

_CMD = re.compile(r"([MLQCTSZ])([^MLQCTSZ]*)")


def svg_beziers(d):
    """Loops of (k, 2) Béziers (y up again) from morph's path data, and outline
    points: the points the file stores (T and S imply their first control point, the
    reflection of the previous one, as TrueType implies on-curve points; counted as
    :func:`segments_beziers` counts a peer's implied points)."""
    loops, cur, npts, start, last, ctrl = [], None, 0, None, None, None
    for c, args in _CMD.findall(d):
        xy = np.array(args.split(), float).reshape(-1, 2) * [1, -1] if args.strip() else None
        if c == "M":
            cur, start = [], xy[0]
        elif c == "Z":
            if not np.allclose(last, start):
                cur.append(np.array([last, start]))
                npts += 1
            loops.append(cur)
        else:
            if c in "TS":  # after Q / T resp. C / S only, as morph writes them
                xy = np.vstack([2 * last - ctrl, xy])
                npts -= 1
            cur.append(np.vstack([last, xy]))
            npts += len(xy)
            ctrl = xy[-2] if len(xy) > 1 else None
        if xy is not None:
            last = xy[-1]
    return loops, npts


def segments_beziers(segments):
    """Loops of (k, 2) Béziers and outline points from fontTools-style segments
    (pathops ``Path.segments``, a RecordingPen value); conics must be gone."""
    loops, cur, npts, start, last = [], None, 0, None, None
    for verb, pts in segments:
        if verb == "moveTo":
            cur, start, last = [], pts[0], pts[0]
        elif verb in ("closePath", "endPath"):
            if cur is None:
                continue
            if not np.allclose(last, start):
                cur.append(np.array([last, start]))
                npts += 1
            if cur:
                loops.append(cur)
            cur = None
        elif verb == "lineTo":
            cur.append(np.array([last, pts[0]]))
            npts, last = npts + 1, pts[0]
        elif verb == "qCurveTo":
            pts = list(pts)
            if len(pts) > 2:  # implied on-curve points (TrueType style)
                from fontTools.pens.basePen import decomposeQuadraticSegment
                parts = decomposeQuadraticSegment(pts)
            else:
                parts = [tuple(pts)]
            for q in parts:
                cur.append(np.array([last, q[0], q[1]]))
                last = q[1]
            npts += len(pts)
        elif verb == "curveTo":
            cur.append(np.array([last] + list(pts)))
            npts, last = npts + 3, pts[-1]
        else:
            raise ValueError("unexpected verb %r" % verb)
    return loops, npts


def glyph_segments(font_path, ch):
    f = TTFont(font_path)
    gs = f.getGlyphSet()
    pen = DecomposingRecordingPen(gs)
    gs[f.getBestCmap()[ord(ch)]].draw(pen)
    return pen.value


# ------------------------------------------------------------ section 1: glyphs

class Budget:
    """Predicts the old Clipper recipe's time from its last run (grows ~ (N M)^2)."""

    def __init__(self, limit):
        self.limit, self.last = limit, None

    def fits(self, nprod):
        return self.last is None or self.last[0] * (nprod / self.last[1]) ** 2 <= self.limit

    def record(self, t, nprod):
        self.last = (t, nprod)


def dc_inprocess(font, a, b, tol, fan=DC.FAN):
    la = DC.glyph_polylines(font, a, tol / 2)
    lb = DC.glyph_polylines(font, b, tol / 2)
    stats = {}
    rings = DC.dc_sum(la, lb, tol, stats, fan)
    return rings, stats


def glyph_case(a, b, tol_em, args, log, budget):
    tol = tol_em * UPM
    A, B = glyph(a), glyph(b)
    oracle = ME.Oracle(A, B, ORACLE_FLAT)
    reps = args.repeats if tol_em >= 1e-4 else max(2, args.repeats // 2)
    row = dict(case="%s + %s" % (a, b), tol=tol_em)
    # morph in-process
    w, wm, c, out = timed(lambda: minkowski_sum(A, B, tol), reps)
    row.update(m_wmin=w, m_wmed=wm, m_cmin=c, m_ctrl=ctrl_points(out), m_err=err_pieces(out, oracle))
    # what `morph sum A B -o x.svg --tol T` writes
    d = morph_svg(A, B, tol)
    bez, npts = svg_beziers(d)
    row.update(m_cmds=sum(len(lp) for lp in bez), m_pts=npts, m_svg_err=err_beziers(bez, oracle))
    # dc, strongest: tree union
    font = TTFont(TTF)
    w, wm, c, (rings, stats) = timed(lambda: dc_inprocess(font, a, b, tol), reps)
    geom = rings_geometry(rings)
    row.update(dc_wmin=w, dc_wmed=wm, dc_cmin=c, dc_n=poly_vertices(geom),
               dc_err=err_polygon(geom, oracle), dc_pairs=stats["pairs"],
               dc_pieces="%d + %d" % (stats["pieces_a"], stats["pieces_b"]))
    # old whole-polygon MinkowskiSum recipe
    nprod = (sum(map(len, R.region_polylines(A, tol / 2)))
             * sum(map(len, R.region_polylines(B, tol / 2))))
    if budget.fits(nprod):
        t0 = time.perf_counter()
        g = R.polygon_minkowski_sum(A, B, tol)
        row.update(old_w=time.perf_counter() - t0, old_n=poly_vertices(g))
        budget.record(row["old_w"], nprod)
    else:
        row.update(old_w=None, old_n=None)
    # processes: morph sum vs dc_sum.py (strongest), in turn; dc-one once with a timeout
    with tempfile.TemporaryDirectory() as tmp:
        cm = [sys.executable, "-m", "morph.cli", "sum", a, b, "--tol", "%g" % tol_em,
              "-o", os.path.join(tmp, "m.svg"), "--force"]
        cd = [sys.executable, str(ROOT / "bench" / "dc_sum.py"), a, b, "--font", TTF,
              "--tol", "%g" % tol_em, "-o", os.path.join(tmp, "d.svg")]
        mw, mc, dw, dcp = [], [], [], []
        run_process(cm, cwd=tmp), run_process(cd, cwd=tmp)      # warm-up, not counted
        for _ in range(args.proc_repeats if tol_em >= 1e-4 else max(2, args.proc_repeats - 2)):
            x, y = run_process(cm, cwd=tmp)
            mw.append(x), mc.append(y)
            x, y = run_process(cd, cwd=tmp)
            dw.append(x), dcp.append(y)
        row["p_morph"], row["p_dc"] = proc_stats(mw, mc), proc_stats(dw, dcp)
        if stats["pairs"] <= args.one_max_pairs:
            x, y = run_process(cd + ["--fan", "0"], timeout=args.budget, cwd=tmp)
            row["p_one"] = None if x is None else dict(wmin=x, cmin=y)
            row["one_note"] = "" if x is not None else "> %g s" % args.budget
        else:
            row["p_one"], row["one_note"] = None, "not run (%d pairs)" % stats["pairs"]
    log("glyphs %s %g: morph %s (%d pts, err %s), svg %d cmds, dc %s (%d v, err %s), process "
        "morph %s dc %s" % (row["case"], tol_em, fmt_t(row["m_wmin"]), row["m_ctrl"],
                            fmt_e(row["m_err"]), row["m_cmds"], fmt_t(row["dc_wmin"]),
                            row["dc_n"], fmt_e(row["dc_err"]), fmt_t(row["p_morph"]["wmin"]),
                            fmt_t(row["p_dc"]["wmin"])))
    return row


def glyph_ladder(a, b, level_em, oracle, A, B, font):
    """Smallest morph SVG and dc polygon with measured error <= level (tol x 1, 2, 4)."""
    best = {}
    for f in (4, 2, 1, 0.75):
        tol = level_em * UPM * f
        bez, npts = svg_beziers(morph_svg(A, B, tol))
        e = err_beziers(bez, oracle)
        if within(e, level_em * UPM) and "morph" not in best:
            best["morph"] = (npts, f, e)
        rings, _ = dc_inprocess(font, a, b, tol)
        geom = rings_geometry(rings)
        e = err_polygon(geom, oracle)
        if within(e, level_em * UPM) and "dc" not in best:
            best["dc"] = (poly_vertices(geom), f, e)
    return best


# -------------------------------------------------------------- section 2: nibs

def nib_affine():
    """2x2 matrix M with the ellipse nib = M (unit disk)."""
    w, h, deg = ELLIPSE
    c, s = math.cos(math.radians(deg)), math.sin(math.radians(deg))
    return np.array([[c, -s], [s, c]]) @ np.diag([w / 2, h / 2])


def skia_sum(segs, kind, k):
    """Skia: glyph stroked with the nib (round caps/joins), united with the glyph."""
    src = pathops.Path()
    pen = src.getPen()
    from fontTools.pens.recordingPen import replayRecording
    replayRecording(segs, pen)
    if kind == "disk":
        m, r = np.eye(2) * k, DISK_R * k
    else:
        m, r = np.linalg.inv(nib_affine()) * k, k
    fwd = (m[0, 0], m[1, 0], m[0, 1], m[1, 1], 0.0, 0.0)
    mi = np.linalg.inv(m)
    back = (mi[0, 0], mi[1, 0], mi[0, 1], mi[1, 1], 0.0, 0.0)
    g = src.transform(*fwd)
    s = pathops.Path(g)
    s.stroke(2 * r, pathops.LineCap.ROUND_CAP, pathops.LineJoin.ROUND_JOIN, 4)
    s.convertConicsToQuads()   # pathops.op cannot take the round joins' conics
    u = pathops.op(s, g, pathops.PathOp.UNION).transform(*back)
    u.convertConicsToQuads()
    return u


def kurbo_offset(segs, acc):
    """kurbopy.offset_cubic on every cubic of a smooth closed outline, outward: kurbo
    offsets to the left of travel for a positive distance, which is outward when the
    outer contours run clockwise (y up; the bundled CFF O does, area < 0)."""
    from fontTools.pens.areaPen import AreaPen
    from fontTools.pens.recordingPen import RecordingPen, replayRecording
    ap = AreaPen()
    replayRecording(segs, ap)
    dist = DISK_R if ap.value < 0 else -DISK_R
    loops, cur, last = [], None, None
    for verb, pts in segs:
        if verb == "moveTo":
            cur, last = [], pts[0]
        elif verb == "curveTo":
            c = kurbopy.CubicBez(*[kurbopy.Point(*p) for p in (last,) + tuple(pts)])
            rp = RecordingPen()
            kurbopy.offset_cubic(c, dist, acc).draw(rp)
            p0 = None
            for verb, pts2 in rp.value:   # moveTo, curveTo..., endPath (open)
                if verb == "moveTo":
                    p0 = pts2[0]
                elif verb == "curveTo":
                    cur.append(np.array((p0,) + tuple(pts2), float))
                    p0 = pts2[-1]
                elif verb == "lineTo":
                    cur.append(np.array((p0, pts2[0]), float))
                    p0 = pts2[0]
            last = pts[-1]
        elif verb == "lineTo":
            raise ValueError("kurbo offset: lines not handled (the O has none)")
        elif verb in ("closePath", "endPath"):
            loops.append(cur)
    # outline points: on-curve points are shared between neighbours (3 per cubic)
    return loops, sum(len(b) - 1 for lp in loops for b in lp)


FF_WORKER = r"""
import json, sys, time
sys.path.insert(0, sys.argv[1])
import fontforge
from fontforge_stroke import draw
job = json.load(sys.stdin)
font = fontforge.font(); font.em = 1000
out = []
for k, (paths, nib, acc) in enumerate(job):
    g = font.createChar(-1, "g%d" % k)
    draw(g, paths)
    t0 = time.process_time()
    if nib[0] == "elliptical":
        g.stroke("elliptical", nib[1], nib[2], nib[3], "nib", "nib", accuracy=acc,
                 removeoverlap="layer")
    else:
        g.stroke("circular", nib[1], "nib", "nib", accuracy=acc, removeoverlap="layer")
    stroked = g.foreground
    h = font.createChar(-1, "h%d" % k)
    draw(h, paths)
    layer = stroked + h.foreground
    g.foreground = layer
    g.removeOverlap()
    sec = time.process_time() - t0
    segs = []
    for c in g.foreground:
        pts = [(p.x, p.y, bool(p.on_curve)) for p in c]
        segs.append(pts)
    out.append({"seconds": sec, "contours": segs})
json.dump(out, sys.stdout)
"""


def ff_available():
    try:
        return subprocess.run([FF_PYTHON, "-c", "import fontforge"], capture_output=True,
                              timeout=60).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return False


def ff_paths(segs):
    """fontforge_stroke.draw's input: [(segments, closed)] with 2- or 4-point segments."""
    paths, cur, last, start = [], None, None, None
    for verb, pts in segs:
        if verb == "moveTo":
            cur, last, start = [], pts[0], pts[0]
        elif verb == "lineTo":
            cur.append([last, pts[0]])
            last = pts[0]
        elif verb == "curveTo":
            cur.append([last] + list(pts))
            last = pts[-1]
        elif verb == "qCurveTo":
            from fontTools.pens.basePen import decomposeQuadraticSegment
            for q1, q2 in decomposeQuadraticSegment(list(pts)):   # exact elevation
                p0, q1, q2 = np.array(last), np.array(q1), np.array(q2)
                cur.append([tuple(p0), tuple(p0 + 2 / 3 * (q1 - p0)),
                            tuple(q2 + 2 / 3 * (q1 - q2)), tuple(q2)])
                last = tuple(q2)
        elif verb in ("closePath", "endPath"):
            if not np.allclose(last, start):
                cur.append([last, start])
            paths.append([[list(map(float, p)) for p in s] for s in cur])
    return [[p, True] for p in paths]


def ff_run(jobs):
    """[(paths, nib, accuracy)] -> [(seconds, loops of Béziers, points)]."""
    p = subprocess.run([FF_PYTHON, "-c", FF_WORKER, str(ROOT / "bench")],
                       input=json.dumps(jobs), capture_output=True, text=True, timeout=600)
    if p.returncode:
        raise RuntimeError("FontForge worker: " + p.stderr[-800:])
    out = []
    for r in json.loads(p.stdout):
        loops, npts = [], 0
        for pts in r["contours"]:
            npts += len(pts)
            k = next(i for i, q in enumerate(pts) if q[2])
            pts = pts[k:] + pts[:k] + [pts[k]]
            lp, seg = [], [pts[0][:2]]
            for q in pts[1:]:
                seg.append(q[:2])
                if q[2]:
                    lp.append(np.array(seg, float))
                    seg = [q[:2]]
            loops.append(lp)
        out.append((r["seconds"], loops, npts))
    return out


def nib_case(kind, level_em, args, log, ff_ok):
    level = level_em * UPM
    O = glyph("O", CFF)
    nib = [pc.circle((0.0, 0.0), DISK_R)] if kind == "disk" else ellipse_nib(*ELLIPSE)
    oracle = ME.Oracle(O, nib, ORACLE_FLAT)
    segs = glyph_segments(CFF, "O")
    res = {}                     # method -> list of (setting, seconds, points, err)

    def add(method, setting, sec, npts, err):
        res.setdefault(method, []).append((setting, sec, npts, err))

    reps = args.repeats
    for f in (4, 2, 1, 0.75):
        tol = level * f
        w, _, _, d = timed(lambda: morph_svg(O, nib, tol), reps)
        bez, npts = svg_beziers(d)
        add("morph (sum + SVG export)", "tol %g em" % (tol / UPM), w, npts, err_beziers(bez, oracle))
        w, _, _, out = timed(lambda: minkowski_sum(O, nib, tol), reps)
        add("morph pieces (minkowski_sum, ctrl pts)", "tol %g em" % (tol / UPM), w,
            ctrl_points(out), err_pieces(out, oracle))
        # dc polygon
        nib_poly = R.region_polylines(nib, tol / 2)
        font = TTFont(CFF)

        def dc():
            la = DC.glyph_polylines(font, "O", tol / 2)
            return DC.dc_sum(la, nib_poly, tol)
        w, _, _, rings = timed(dc, reps)
        geom = rings_geometry(rings)
        add("dc polygon (flatten, convex pieces, union)", "tol %g em" % (tol / UPM), w,
            poly_vertices(geom), err_polygon(geom, oracle))
    k = 1
    while k <= 4096:
        w, _, _, u = timed(lambda: skia_sum(segs, kind, k), reps)
        bez, npts = segments_beziers(list(u.segments))
        e = err_beziers(bez, oracle)
        add("Skia stroke + union", "scale %d" % k, w, npts, e)
        if e <= level / 4:
            break
        k *= 2
    if kind == "disk":
        font = TTFont(CFF)
        la = DC.glyph_polylines(font, "O", level / 4)
        base = shapely.make_valid(rings_geometry(DC._polygons_with_holes(la, 100 / level)))
        q = 2
        while q <= 256:
            w, _, _, g = timed(lambda: base.buffer(DISK_R, quad_segs=q), reps)
            e = err_polygon(g, oracle)
            add("shapely buffer (glyph flattened within level/4)", "quad_segs %d" % q, w,
                poly_vertices(g), e)
            if e <= level / 2:
                break
            q *= 2
        for f in (4, 2, 1, 0.75, 0.5):
            acc = level * f
            w, _, _, (loops, npts) = timed(lambda: kurbo_offset(segs, acc), reps)
            add("kurbo offset_cubic", "accuracy %g em" % (acc / UPM), w, npts,
                err_beziers(loops, oracle))
    if ff_ok:
        paths = ff_paths(segs)
        nibspec = (["circular", 2 * DISK_R] if kind == "disk"
                   else ["elliptical", ELLIPSE[0], ELLIPSE[1], math.radians(ELLIPSE[2])])
        accs = [level * f for f in (8, 4, 2, 1, 0.5, 0.25)]
        for acc, (sec, loops, npts) in zip(accs, ff_run([(paths, nibspec, a) for a in accs])):
            add("FontForge Expand Stroke", "accuracy %g em" % (acc / UPM), sec, npts,
                err_beziers(loops, oracle) if loops else math.inf)
    best = {}
    for m, rows in res.items():
        ok = [r for r in rows if within(r[3], level)]
        best[m] = min(ok, key=lambda r: r[2]) if ok else None
    for m, b in best.items():
        log("nibs O ⊕ %s %g: %s: %s" % (kind, level_em, m, "none within" if b is None else
                                        "%s, %s, %d pts, err %s" % (b[0], fmt_t(b[1]), b[2],
                                                                    fmt_e(b[3]))))
    return dict(kind=kind, level=level_em, runs=res, best=best)


# --------------------------------------------------------------- section 3: cli

def cli_section(args, log):
    out = {}
    with tempfile.TemporaryDirectory() as tmp:
        cmd = [sys.executable, "-m", "morph.cli", "glyph", "T", "M", "--frames", "10",
               "-o", os.path.join(tmp, "tm"), "--force"]
        ws, cs = [], []
        run_process(cmd, cwd=tmp)                               # warm-up, not counted
        for _ in range(args.proc_repeats):
            w, c = run_process(cmd, cwd=tmp)
            ws.append(w), cs.append(c)
        out["frames"] = proc_stats(ws, cs)
        log("cli frames: %s" % out["frames"])
        if not args.quick:
            for jobs in ("1", None):
                cmd = [sys.executable, "-m", "morph.cli", "brush", "-o",
                       os.path.join(tmp, "b.ttf"), "--glyphs", "A-Z,a-z", "--force"]
                if jobs:
                    cmd += ["--jobs", jobs]
                ws, cs = [], []
                for _ in range(args.brush_repeats):
                    w, c = run_process(cmd, cwd=tmp, timeout=600)
                    ws.append(w), cs.append(c)
                out["brush-jobs%s" % (jobs or "default")] = proc_stats(ws, cs)
                log("cli brush jobs %s: %s" % (jobs, out["brush-jobs%s" % (jobs or "default")]))
    if not args.quick:
        try:
            out.update(_peers52(args))
        except Exception as exc:  # noqa: BLE001 - context figures only; say why, go on
            log("52-glyph peers failed: %s: %s" % (type(exc).__name__, exc))
    return out


def _peers52(args):
    out = {}
    if True:
        chars = [chr(c) for c in range(65, 91)] + [chr(c) for c in range(97, 123)]
        segs = {ch: glyph_segments(TTF, ch) for ch in chars}
        t = time.process_time()
        npts = 0
        for ch in chars:
            u = skia_sum(segs[ch], "ellipse", 1)
            npts += segments_beziers(list(u.segments))[1]
        out["skia52"] = (time.process_time() - t, npts)
        if args.ff_ok:
            nibspec = ["elliptical", ELLIPSE[0], ELLIPSE[1], math.radians(ELLIPSE[2])]
            r = ff_run([(ff_paths(segs[ch]), nibspec, 0.5) for ch in chars])
            out["ff52"] = (sum(x[0] for x in r), sum(x[2] for x in r))
        print("cli 52 glyphs: skia %s ff %s" % (out["skia52"], out.get("ff52")), flush=True)
    return out


# ----------------------------------------------------------------------- report

def ratio(a, b):
    return None if (a is None or b is None or b == 0) else a / b


def markdown(glyph_rows, ladders, nibs, cli, args, seconds, load):
    L = ["# morph against its peers, strongest recipes (bench/peers.py)", "",
         "Command: `python bench/peers.py %s` (%.0f s).  Machine: 2 cores shared with other "
         "engineers' jobs, load average %s during the run: **times were taken under load**; "
         "wall times are upper bounds, ratios use the minimum of several runs.  Font: bundled "
         "Noto Sans (upm 1000).  Errors: certified upper bounds (tests/oracles/measure.py, exact "
         "membership predicate on operands flattened within 1e-6 em, resolution ~2e-6 em)."
         % (" ".join(args.argv), seconds, load), ""]
    L += targets(glyph_rows, ladders, nibs, cli)
    L += ["", "## 1. Glyph sums (TrueType), in-process", "",
          "Recipes: **morph** `minkowski_sum(a, b, tol)`; **dc** = flatten both within tol/2, "
          "pyclipper nonzero union, mapbox-earcut triangles merged to convex pieces "
          "(Hertel-Mehlhorn), convex pair sums by merged edge angles (numpy), pyclipper union "
          "as a tree of 8-input unions (`bench/dc_sum.py`); **Clipper MinkowskiSum** = the "
          "old whole-polygon recipe (`tests.oracles.reference.polygon_minkowski_sum`, one run, "
          "skipped when predicted over %g s).  Times: min (median) wall, min CPU." % args.budget,
          "",
          "| case | tol (em) | morph wall min (med) | morph CPU | morph ctrl pts | morph err | "
          "SVG cmds / points | SVG err | dc wall min (med) | dc CPU | dc vertices | dc err | "
          "dc pieces, pairs | MinkowskiSum wall | its vertices |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in glyph_rows:
        L.append("| %s | %g | %s (%s) | %s | %d | %s | %d / %d | %s | %s (%s) | %s | %d | %s | "
                 "%s, %d | %s | %s |" % (
                     r["case"], r["tol"], fmt_t(r["m_wmin"]), fmt_t(r["m_wmed"]),
                     fmt_t(r["m_cmin"]), r["m_ctrl"], fmt_e(r["m_err"]), r["m_cmds"],
                     r["m_pts"], fmt_e(r["m_svg_err"]), fmt_t(r["dc_wmin"]),
                     fmt_t(r["dc_wmed"]), fmt_t(r["dc_cmin"]), r["dc_n"], fmt_e(r["dc_err"]),
                     r["dc_pieces"], r["dc_pairs"],
                     "skipped" if r["old_w"] is None else fmt_t(r["old_w"]),
                     "-" if r["old_n"] is None else r["old_n"]))
    L += ["", "## 2. Glyph sums as processes (start-up, font reading and SVG writing included)",
          "",
          "`python -m morph.cli sum A B --tol T -o a.svg` against `python bench/dc_sum.py A B "
          "--font NotoSans-Regular.ttf --tol T -o b.svg`, run in turn after one warm-up "
          "each, bytecode cached as after a pip install; dc-one = dc_sum.py "
          "`--fan 0` (one pyclipper union of all pair sums), one run, killed at %g s.  "
          "Ratio = morph min wall / dc min wall (< 1: morph faster)." % args.budget, "",
          "| case | tol (em) | runs | morph wall min (med) | morph CPU min | dc wall min (med) | "
          "dc CPU min | ratio morph/dc | dc-one wall |",
          "|---|---|---|---|---|---|---|---|---|"]
    for r in glyph_rows:
        m, d = r["p_morph"], r["p_dc"]
        one = fmt_t(r["p_one"]["wmin"]) if r["p_one"] else r["one_note"]
        L.append("| %s | %g | %d | %s (%s) | %s | %s (%s) | %s | %.2f | %s |" % (
            r["case"], r["tol"], m["n"], fmt_t(m["wmin"]), fmt_t(m["wmed"]), fmt_t(m["cmin"]),
            fmt_t(d["wmin"]), fmt_t(d["wmed"]), fmt_t(d["cmin"]), m["wmin"] / d["wmin"], one))
    if ladders:
        L += ["", "## 3. Glyph sums: size at equal measured error", "",
              "Each method at tol = level x 4, 2, 1, 3/4; the smallest output whose measured error "
              "is within the level (bound <= level + 2e-6 em, the oracle's own flattening).  morph: outline points (on + off curve) the SVG the command "
              "writes stores (a T / S command implies its first control point, as TrueType "
              "implies on-curve points and as the peers' points are counted); dc: polygon "
              "vertices.", "",
              "| case | level (em) | morph SVG points (tol factor, err) | dc vertices (tol "
              "factor, err) | dc / morph |", "|---|---|---|---|---|"]
        for (case, level), best in ladders.items():
            m, d = best.get("morph"), best.get("dc")
            L.append("| %s | %g | %s | %s | %s |" % (
                case, level, "-" if m is None else "%d (x%g, %s)" % (m[0], m[1], fmt_e(m[2])),
                "-" if d is None else "%d (x%g, %s)" % (d[0], d[1], fmt_e(d[2])),
                "-" if (m is None or d is None) else "%.1f" % (d[0] / m[0])))
    if nibs:
        L += ["", "## 4. Glyph ⊕ nib (CFF O ⊕ disk r = 40, O ⊕ ellipse 80 x 30 at 30°)", "",
              "Best = the smallest output (outline points, polygon vertices) among the "
              "method's settings whose measured error is within the level (bound <= level + "
              "2e-6 em, the oracle's own flattening); its time is the min "
              "wall of %d in-process runs (FontForge: the CPU time of its stroke + "
              "removeOverlap calls, one run)." % args.repeats, ""]
        for n in nibs:
            L += ["### O ⊕ %s, level %g em" % (n["kind"], n["level"]), "",
                  "| method | best setting | points | error (em) | time | all runs: setting: "
                  "points / err |", "|---|---|---|---|---|---|"]
            for m, rows in n["runs"].items():
                b = n["best"][m]
                allr = "; ".join("%s: %d / %s" % (s, p, fmt_e(e)) for s, _, p, e in rows)
                if b is None:
                    L.append("| %s | none within the level | - | - | - | %s |" % (m, allr))
                else:
                    L.append("| %s | %s | %d | %s | %s | %s |" % (m, b[0], b[2], fmt_e(b[3]),
                                                                fmt_t(b[1]), allr))
            L.append("")
    if cli:
        L += ["## 5. Command-line walls", "", "| command | runs | wall min (median) | CPU min |",
              "|---|---|---|---|"]
        names = {"frames": "`morph glyph T M --frames 10`",
                 "brush-jobs1": "`morph brush -o x.ttf --glyphs A-Z,a-z --jobs 1` (52 glyphs)",
                 "brush-jobsdefault": "`morph brush -o x.ttf --glyphs A-Z,a-z` (2 jobs)"}
        for k, name in names.items():
            if k in cli:
                s = cli[k]
                L.append("| %s | %d | %s (%s) | %s |" % (name, s["n"], fmt_t(s["wmin"]),
                                                         fmt_t(s["wmed"]), fmt_t(s["cmin"])))
        if "skia52" in cli:
            L += ["", "For scale, the same 52 TrueType glyphs ⊕ the same ellipse in-process: Skia "
                  "stroke + union %s CPU (%d outline points, scale 1: ~1/4-unit accuracy)"
                  % (fmt_t(cli["skia52"][0]), cli["skia52"][1])
                  + ("; FontForge Expand Stroke + removeOverlap at accuracy 0.5 unit %s CPU "
                     "(%d points)." % (fmt_t(cli["ff52"][0]), cli["ff52"][1])
                     if "ff52" in cli else ".")]
    return "\n".join(L) + "\n"


def targets(glyph_rows, ladders, nibs, cli):
    """The headline figures, met / not met with the ratio."""
    T = ["## Headline figures", "",
         "| target | measured | ratio | met? |", "|---|---|---|---|"]

    def row(name, meas, r, ok):
        T.append("| %s | %s | %s | %s |" % (name, meas, r, "**met**" if ok else "**not met**"))

    g = {(r["case"], r["tol"]): r for r in glyph_rows}
    for case, lim in (("O + M", 0.05), ("S + g", 0.10)):
        r = g.get((case, 1e-4))
        if r:
            name = "`minkowski_sum` %s at 1e-4 em <= %d ms" % (case, lim * 1e3)
            row(name + " (wall, under load)", "%s wall min" % fmt_t(r["m_wmin"]),
                "%.2fx the limit" % (r["m_wmin"] / lim), r["m_wmin"] <= lim)
            row(name + " (CPU)", "%s CPU min" % fmt_t(r["m_cmin"]),
                "%.2fx the limit" % (r["m_cmin"] / lim), r["m_cmin"] <= lim)
    for case in ("O + M", "S + g"):
        r = g.get((case, 1e-4))
        if r:
            x = r["p_morph"]["wmin"] / r["p_dc"]["wmin"]
            row("`morph sum %s` process no slower than dc at 1e-4 em" % case.replace(" + ", " "),
                "%s vs %s" % (fmt_t(r["p_morph"]["wmin"]), fmt_t(r["p_dc"]["wmin"])),
                "morph/dc %.2f" % x, x <= 1.0)
        r = g.get((case, 1e-5))
        if r:
            x = r["p_dc"]["wmin"] / r["p_morph"]["wmin"]
            row("`morph sum %s` process >= 10x faster than dc at 1e-5 em"
                % case.replace(" + ", " "),
                "%s vs %s" % (fmt_t(r["p_morph"]["wmin"]), fmt_t(r["p_dc"]["wmin"])),
                "dc/morph %.1f" % x, x >= 10)
    if cli and "frames" in cli:
        w = cli["frames"]["wmin"]
        row("`morph glyph T M --frames 10` < 1 s wall", fmt_t(w), "%.2fx the limit" % w, w < 1)
    for k, name in (("brush-jobs1", "52-glyph brush < 3 s (--jobs 1)"),
                    ("brush-jobsdefault", "52-glyph brush < 3 s (2 jobs)")):
        if cli and k in cli:
            w = cli[k]["wmin"]
            row(name, "%s wall (CPU %s)" % (fmt_t(w), fmt_t(cli[k]["cmin"])),
                "%.1fx the limit" % (w / 3), w < 3)
    for (case, level), best in ladders.items():
        m, d = best.get("morph"), best.get("dc")
        if m and d:
            x = d[0] / m[0]
            row("points >= 5x fewer than dc, %s at <= %g em" % (case, level),
                "%d vs %d" % (m[0], d[0]), "dc/morph %.1f" % x, x >= 5)
    for n in nibs:
        m = n["best"].get("morph (sum + SVG export)")
        for peer, need in (("Skia stroke + union", 1.5), ("FontForge Expand Stroke", 1.5),
                           ("kurbo offset_cubic", 1.0),
                           ("dc polygon (flatten, convex pieces, union)", 5.0)):
            if peer not in n["best"]:
                continue
            p = n["best"][peer]
            if p is None and m is not None:
                T.append("| points vs %s, O ⊕ %s at <= %g em | morph %d; the peer never "
                         "within the level at the settings tried (section 4) | - | n/a |"
                         % (peer.split(" (")[0], n["kind"], n["level"], m[2]))
                continue
            if m is None or p is None:
                row("points vs %s, O ⊕ %s at <= %g em" % (peer, n["kind"], n["level"]),
                    "morph %s, peer %s" % ("-" if m is None else m[2], "-" if p is None else p[2]),
                    "-", False)
                continue
            x = p[2] / m[2]
            word = ("no more than" if need == 1.0 else ">= %gx fewer than" % need)
            row("points %s %s, O ⊕ %s at <= %g em" % (word, peer.split(" (")[0], n["kind"],
                                                     n["level"]),
                "%d vs %d" % (m[2], p[2]), "peer/morph %.2f" % x, x >= need)
    return T


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sections", default="glyphs,nibs,cli")
    ap.add_argument("--cases", default="TM,OM,Sg")
    ap.add_argument("--tols", default="1e-3,1e-4,1e-5", help="em, glyph sums")
    ap.add_argument("--levels", default="1e-4,1e-5", help="em, nib error levels")
    ap.add_argument("--ladder-levels", default="1e-4,1e-5",
                    help="em, glyph size-at-equal-error levels (O+M, S+g)")
    ap.add_argument("--repeats", type=int, default=5, help="in-process runs (min, median)")
    ap.add_argument("--proc-repeats", type=int, default=5, help="process runs (min, median)")
    ap.add_argument("--brush-repeats", type=int, default=2)
    ap.add_argument("--budget", type=float, default=20.0,
                    help="seconds: kill dc-one / skip the old MinkowskiSum recipe beyond")
    ap.add_argument("--one-max-pairs", type=int, default=40000,
                    help="run dc-one only up to this many pair sums")
    ap.add_argument("--quick", action="store_true",
                    help="O+M, S+g at 1e-4 em, nibs at 1e-4 em, 3 runs, no brush")
    ap.add_argument("--md", default=str(ROOT / "bench" / "peers.md"))
    ap.add_argument("--no-write", dest="write", action="store_false")
    ap.add_argument("--json", help="also dump every figure to this file")
    ap.add_argument("--from-json", help="write the markdown from a --json dump, no runs")
    args = ap.parse_args(argv)
    args.argv = list(argv if argv is not None else sys.argv[1:])
    if args.from_json:
        d = json.loads(Path(args.from_json).read_text())
        args.argv = d["argv"]
        ladders = {(c, lv): v for c, lv, v in d["ladders"]}
        text = markdown(d["glyphs"], ladders, d["nibs"], d["cli"], args, d["seconds"], d["load"])
        Path(args.md).write_text(text)
        print(text)
        return
    if args.quick:
        args.cases, args.tols, args.levels, args.ladder_levels = "OM,Sg", "1e-4", "1e-4", "1e-4"
        args.repeats = args.proc_repeats = 3
    args.ff_ok = ff_available()
    t_start = time.perf_counter()
    loads = []

    def log(s):
        loads.append(os.getloadavg()[0])
        print(s, flush=True)

    if not args.ff_ok:
        log("FontForge not importable by %s: its rows are left out "
            "(apt-get install python3-fontforge)" % FF_PYTHON)
    sections = args.sections.split(",")
    pairs = {"TM": ("T", "M"), "OM": ("O", "M"), "Sg": ("S", "g")}
    glyph_rows, ladders, nibs, cli = [], {}, [], None
    if "glyphs" in sections:
        for key in args.cases.split(","):
            budget = Budget(args.budget)
            for t in [float(x) for x in args.tols.split(",")]:
                glyph_rows.append(glyph_case(*pairs[key], t, args, log, budget))
        font = TTFont(TTF)
        for key in args.cases.split(","):
            if key == "TM":
                continue
            a, b = pairs[key]
            A, B = glyph(a), glyph(b)
            oracle = ME.Oracle(A, B, ORACLE_FLAT)
            for lv in [float(x) for x in args.ladder_levels.split(",")]:
                ladders[("%s + %s" % (a, b), lv)] = glyph_ladder(a, b, lv, oracle, A, B, font)
                log("ladder %s %g: %s" % (key, lv, ladders[("%s + %s" % (a, b), lv)]))
    if "nibs" in sections:
        for kind in ("disk", "ellipse"):
            for lv in [float(x) for x in args.levels.split(",")]:
                nibs.append(nib_case(kind, lv, args, log, args.ff_ok))
    if "cli" in sections:
        cli = cli_section(args, log)
    seconds = time.perf_counter() - t_start
    load = "%.1f-%.1f" % (min(loads), max(loads)) if loads else "?"
    if args.json:
        Path(args.json).write_text(json.dumps(dict(glyphs=glyph_rows, ladders=[[k[0], k[1], v] for k, v
                                                                   in ladders.items()],
                                        nibs=nibs, cli=cli, seconds=seconds, load=load,
                                        argv=args.argv), default=float, indent=1))
    text = markdown(glyph_rows, ladders, nibs, cli, args, seconds, load)
    print(text)
    if args.write:
        Path(args.md).write_text(text)
        print("wrote", args.md)


if __name__ == "__main__":
    main()

"""Overlapping contours inside the glyphs of written static fonts (stroke and brush).

    python -m bench.stroke_overlaps [--runs SET:FORMAT,...] [--unrounded SET,...]
                                    [--jobs 1] [--keep DIR] [--strict]
                                    [--written SET:JOBS:PATH,...]
                                    [--md bench/stroke_overlaps.md | --no-write]

Static outputs of ``morph stroke`` and ``morph brush`` are trimmed: one outline per
glyph, free of overlaps.  The union-based measures (the Hausdorff distance to the
Clipper reference of bench/stroke.py, the exact membership predicate of
bench/stroke_exact.py) cannot see two outer contours of one glyph that overlap: their
nonzero fill is the union, which can be right.  This script writes each font with
the command a user runs, reads every glyph back and checks its contours with
:mod:`tests.oracles.overlaps`: the faces of the contours' arrangement covered twice
by same-orientation contours, or with the wrong sign (a hole poking out, a twist),
each with its area and width (twice its largest inscribed circle's radius), decided
against ``2 (tol + 0.71)`` (``tol`` the command's default, 0.0005 em, in font units;
0.71 the integer rounding): the widest lens two contours, each within tol + 0.71 of
the exact boundary, can make across a gap of the exact sum.  skia-pathops' excess on
the exact curves (the contours' signed areas minus their nonzero union)
cross-checks the faces.

Runs (``SET:FORMAT``, FORMAT otf, ttf or ufo): the skeleton sets of
:mod:`bench.skeletons` (hershey-sans, hershey-script, hanzi-N, hanzi-all; fetched with
npm at bench time), ``relief`` (the whole Relief SingleLine UFO, else the bundled
subset) stroked by ``morph stroke SET.ufo -o OUT --jobs J``, and ``noto-brush``
(``morph brush -o OUT``: the bundled Noto Sans, TrueType for ttf, its CFF version for
otf).  ``--unrounded``: the same sets stroked in process as the command strokes them
(``bench.stroke.run_morph``: chunks, ``stroke_many`` and ``loops_to_beziers``), before
any rounding, so that an overlap of the written font can be told apart from one the
rounding made.  A control run shows the check failing: one glyph of the first font
with a copy of its first contour moved by 1 unit.  Writes the report and a figure
(the report's path with .png); exits 1 when the control is not flagged, and with
``--strict`` when a glyph has an overlap over the bound.
"""

import argparse
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

DEFAULT_RUNS = ("hershey-sans:otf,hershey-sans:ttf,hershey-script:otf,hershey-script:ttf,"
                "hanzi-300:otf,hanzi-300:ttf,relief:otf,relief:ttf,relief:ufo,"
                "noto-brush:ttf,noto-brush:otf")
DEFAULT_UNROUNDED = "hershey-sans,hershey-script,hanzi-300,relief"
LISTED = 30  # overlaps listed per run


def source(name):
    """The skeleton UFO (or, for noto-brush, the font) of a set."""
    if name == "relief":
        from bench.stroke_profile import relief_ufo

        return relief_ufo()
    if name == "noto-brush":
        return None
    from bench.skeletons import skeleton_ufo

    return skeleton_ufo(name)


def command(name, fmt, out, jobs):
    """The ``morph`` command line writing set ``name`` as ``fmt`` to ``out``."""
    base = [sys.executable, "-m", "morph.cli"]
    if name == "noto-brush":
        from morph.parse import cubic_test_font_path

        src = [str(cubic_test_font_path())] if fmt == "otf" else []
        return base + ["brush"] + src + ["-o", str(out), "--jobs", str(jobs), "--force"]
    return base + ["stroke", str(source(name)), "-o", str(out), "--jobs", str(jobs),
                   "--force"]


def shown(cmd):
    """A command line as a reader runs it (no interpreter or temporary paths)."""
    out = ["morph"] + cmd[3:]
    return " ".join(Path(a).name if os.path.isabs(a) else a for a in out)


def units_per_em(path):
    if Path(path).suffix == ".ufo":
        import ufoLib2

        return float(ufoLib2.Font.open(str(path)).info.unitsPerEm or 1000)
    from fontTools.ttLib import TTFont

    return float(TTFont(str(path))["head"].unitsPerEm)


def check_run(name, fmt, workdir, jobs, written=None):
    """Write set ``name`` as ``fmt`` with the command and check every glyph;
    ``written``: a font the command wrote before (e.g. ``bench.stroke_memory
    --keep``), checked as it is."""
    from morph.cli.options import FONT_TOL
    from tests.oracles.overlaps import font_overlaps, overlap_bound

    if written:
        out = Path(written)
        row = {"set": name, "format": fmt, "command": shown(command(name, fmt, out, jobs))
               .replace(" --force", ""), "rc": 0, "line": "", "written": True,
               "command_cpu": float("nan"), "path": str(out)}
    else:
        out = Path(workdir) / ("%s.%s" % (name, fmt))
        cmd = command(name, fmt, out, jobs)
        env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
                   PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT))
        r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
        proc = subprocess.run(cmd, env=env, capture_output=True, text=True, cwd=str(workdir))
        r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
        cpu = (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)
        lines = (proc.stdout + proc.stderr).strip().splitlines()
        row = {"set": name, "format": fmt, "command": shown(cmd), "rc": proc.returncode,
               "line": lines[-1] if lines else "", "command_cpu": cpu, "path": str(out)}
    if row["rc"] not in (0, 1) or not out.exists():
        row["glyphs"] = None
        return row
    upm = units_per_em(out)
    tol = FONT_TOL * upm
    t0 = time.process_time()
    res = [g for g in font_overlaps(out) if g.contours]
    row.update(check_cpu=time.process_time() - t0, upm=upm, tol=tol,
               bound=overlap_bound(tol), glyphs=len(res), results=res)
    return row


def unrounded(name):
    """The set stroked in process as the command strokes it, before rounding: the
    :class:`GlyphOverlaps` of every glyph, and the tol."""
    from bench.stroke import BROAD, run_morph
    from morph.cli.options import FONT_TOL
    from morph.parse.ufo import load_ufo
    from tests.oracles.overlaps import glyph_overlaps

    font = load_ufo(source(name), lazy=False)
    names = [g.name for g in sorted(font, key=lambda g: g.name)
             if any(len(c) > 1 for c in g.contours)]
    upm = float(font.info.unitsPerEm or 1000)
    k = upm / 1000.0
    spec = ("ellipse", BROAD[1] * k, BROAD[2] * k, BROAD[3])
    tol = FONT_TOL * upm
    found = {}

    def judge(contours, glyph, _tol):
        found[glyph] = glyph_overlaps(glyph, _segments_pen(contours))
        return found[glyph].width, found[glyph].width

    rows = run_morph(font, names, spec, [tol], {}, judge)
    return {"set": name, "tol": tol, "glyphs": len(names), "results": list(found.values()),
            "failures": rows[0]["fails"] if rows else ["no row"]}


def _segments_pen(contours):
    """A recording of contours given as lists of segments ((k, 2) control points: a
    line, a quadratic or a cubic)."""
    from fontTools.pens.recordingPen import RecordingPen

    pen = RecordingPen()
    for segs in contours:
        segs = [[tuple(map(float, p)) for p in s] for s in segs]
        if not segs:
            continue
        pen.moveTo(segs[0][0])
        for s in segs:
            if len(s) == 2:
                pen.lineTo(s[1])
            elif len(s) == 3:
                pen.qCurveTo(*s[1:])
            else:
                pen.curveTo(*s[1:])
        pen.closePath()
    return pen


def control(row):
    """The check failing on purpose: the first glyph of a written font with contours
    (not .notdef), plus a copy of its first contour moved 1 unit right."""
    from fontTools.pens.recordingPen import RecordingPen

    from tests.oracles.overlaps import font_glyphs, glyph_overlaps

    for name, drawing in font_glyphs(row["path"]):
        if not drawing.value or name.startswith("."):
            continue
        first = []
        for op, args in drawing.value:
            first.append((op, args))
            if op in ("closePath", "endPath"):
                break
        moved = RecordingPen()
        drawing.replay(moved)
        for op, args in first:
            moved.value.append((op, tuple((x + 1.0, y) for x, y in args)))
        g = glyph_overlaps(name, moved)
        return {"font": "%s.%s" % (row["set"], row["format"]), "glyph": name,
                "width": g.width, "area": g.area, "bound": row["bound"],
                "flagged": g.width > row["bound"]}
    return None


CELL = 360


def figure(rows, path):
    """A PNG: per set, the glyph with the widest overlap of its first format, whole and
    zoomed on the overlap: the nonzero fill grey, the overlaps (faces covered twice or
    with the wrong sign) red, the contours black, the widest overlap's inscribed
    circle circled in red."""
    import numpy as np
    import shapely
    from PIL import Image, ImageDraw

    from tests.oracles.overlaps import faces, flattened, font_glyphs

    picks, seen = [], set()
    for r in rows:
        if r.get("glyphs") is None or r["set"] in seen:
            continue
        found = [g for g in r["results"] if g.overlaps]
        if found:
            seen.add(r["set"])
            picks.append((r, max(found, key=lambda g: g.width)))
    if not picks:
        return None
    img = Image.new("RGB", (2 * CELL, (CELL + 20) * len(picks)), "white")
    for k, (r, g) in enumerate(picks):
        (_, drawing), = font_glyphs(r["path"], [g.name])
        contours = flattened(drawing)
        found, ws = faces(contours)
        o = g.overlaps[0]
        allp = np.vstack(contours)
        (x0, y0), (x1, y1) = allp.min(axis=0), allp.max(axis=0)
        half = max(6.0 * o.width, 1.5 * o.area ** 0.5, 3.0)
        views = [((x0 + x1) / 2, (y0 + y1) / 2, 0.55 * max(x1 - x0, y1 - y0)),
                 (o.x, o.y, half)]
        top = k * (CELL + 20)
        ImageDraw.Draw(img).text((6, top + 4), "%s.%s %s: overlap %.3f wide, area %.3f; "
                                 "right: zoom x%.0f" % (r["set"], r["format"], g.name,
                                                        o.width, o.area, views[0][2] / half),
                                 fill=(0, 0, 0))
        for v, (cx, cy, h) in enumerate(views):
            sc = (CELL / 2 - 10) / h
            m = 1.2 * h  # everything clipped to a box a little larger than the view

            def tr(p):
                return (CELL / 2 + (p[0] - cx) * sc, CELL / 2 - (p[1] - cy) * sc)

            cell = Image.new("RGB", (CELL, CELL), "white")
            d = ImageDraw.Draw(cell)
            for face, w in zip(found, ws):
                if w == 0:
                    continue
                part = shapely.clip_by_rect(face, cx - m, cy - m, cx + m, cy + m)
                for poly in getattr(part, "geoms", [part]):
                    if poly.geom_type != "Polygon" or poly.is_empty:
                        continue
                    d.polygon([tr(p) for p in poly.exterior.coords],
                              fill=(200, 200, 200) if w == 1 else (235, 40, 40))
                    for hole in poly.interiors:
                        d.polygon([tr(p) for p in hole.coords], fill=(255, 255, 255))
            for c in contours:
                line = shapely.clip_by_rect(shapely.LineString(np.vstack([c, c[:1]])),
                                            cx - m, cy - m, cx + m, cy + m)
                for part in getattr(line, "geoms", [line]):
                    if part.geom_type == "LineString" and not part.is_empty:
                        d.line([tr(p) for p in part.coords], fill=(0, 0, 0), width=1)
            rad = max(4.0, o.width / 2 * sc)
            px, py = tr((o.x, o.y))
            d.ellipse([px - rad, py - rad, px + rad, py + rad], outline=(255, 0, 0), width=2)
            d.rectangle([0, 0, CELL - 1, CELL - 1], outline=(180, 180, 180))
            img.paste(cell, (v * CELL, top + 20))
    img.save(str(path))
    return path


def composites(name, glyphs):
    """(how many of ``glyphs`` have components in the source of set ``name``, [the
    others]); the brushed font's source is the bundled TrueType Noto Sans."""
    if name == "noto-brush":
        from fontTools.ttLib import TTFont

        from morph.parse import default_font_path

        glyf = TTFont(str(default_font_path()))["glyf"]
        comp = {g for g in glyphs if glyf[g].isComposite()}
    else:
        import ufoLib2

        font = ufoLib2.Font.open(str(source(name)))
        comp = {g for g in glyphs if g in font and font[g].components}
    return len(comp), [g for g in glyphs if g not in comp]


def summary(results, bound):
    with_ov = [g for g in results if g.overlaps]
    over = [g for g in with_ov if g.width > bound]
    widest = max(with_ov, key=lambda g: g.width, default=None)
    largest = max(with_ov, key=lambda g: g.area, default=None)
    return {"with": len(with_ov), "over": len(over), "over_names": [g.name for g in over],
            "widest": widest, "largest": largest,
            "total_area": sum(g.area for g in with_ov),
            "disagree": max((g.disagreement for g in results), default=0.0),
            "max_excess": max((abs(g.excess) for g in results), default=0.0)}


def _cpu(v):
    return "-" if v != v else "%.1f" % v


def _g(g, what):
    return "-" if g is None else "%.3f (%s)" % (getattr(g, what), g.name)


def markdown(rows, unr, ctl, argv, elapsed):
    from bench.stamp import stamp

    md = ["# Overlapping contours in written static fonts (bench/stroke_overlaps.py)", "",
          stamp("python -m bench.stroke_overlaps" + "".join(" " + a for a in argv),
                elapsed),
          "", "Every glyph of each font written by the command shown is read back "
          "(components decomposed) and its contours checked by "
          "`tests/oracles/overlaps.py`: the faces of the contours' arrangement (flattened "
          "within 0.01 unit) whose winding number, signed so that outer contours count +1, "
          "is 2 or more (two outer contours crossing, a contour looping over itself) or "
          "negative (a hole poking out of its outer, a twist) are overlaps; nested contours "
          "(an outer in the hole of another) are none.  **width** = twice the radius of an "
          "overlap's largest inscribed circle, **area** its area (font units).  The bound "
          "bounds the width: 2 (tol + 0.71), tol the commands' default 0.0005 em in font "
          "units and 0.71 the integer rounding; each written contour is within tol + 0.71 "
          "of the exact boundary, whose loops never cross, so two contours on the sides "
          "of a narrow gap of the exact sum can cross it by at most that much together "
          "(the engine's documented narrow-feature limit: such a gap may close).  The "
          "area is not bounded (a lens can be long).  **pathops check** = the largest "
          "difference, over the glyphs, between skia-pathops' excess on the exact "
          "curves (the contours' signed areas minus their nonzero union) and the faces' "
          "excess: about the flattening's error, so the two computations agree.  CPU "
          "times: the command's process tree (user + sys) and the check in this process; "
          "the machine is shared, so wall times are not given.", ""]
    md += ["## Written fonts", "",
           "| set | format | command | glyphs | glyphs with an overlap | over the bound "
           "| bound | widest overlap (glyph) | largest overlap area (glyph) | total area "
           "| pathops check | command CPU s | check CPU s | exit |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if r.get("glyphs") is None:
            md.append("| %s | %s | `%s` | failed: %s | | | | | | | | %.1f | | %d |"
                      % (r["set"], r["format"], r["command"], r["line"][:120],
                         r["command_cpu"], r["rc"]))
            continue
        s = summary(r["results"], r["bound"])
        md.append("| %s | %s | `%s`%s | %d | %d | %d | %.2f | %s | %s | %.3f | %.1e | %s "
                  "| %.1f | %d |"
                  % (r["set"], r["format"], r["command"],
                     " (written before, checked as it is)" if r.get("written") else "",
                     r["glyphs"], s["with"], s["over"],
                     r["bound"], _g(s["widest"], "width"), _g(s["largest"], "area"),
                     s["total_area"], s["disagree"], _cpu(r["command_cpu"]), r["check_cpu"],
                     r["rc"]))
    if unr:
        md += ["", "## Before rounding (in process)", "",
               "The same sets stroked in process as `morph stroke` strokes them "
               "(`bench.stroke.run_morph`: the command's chunks, `stroke_many` at the "
               "geometry share of tol, `loops_to_beziers` at the export share), the "
               "contours checked before any rounding.  Bound here: 2 tol (no rounding).  "
               "Glyphs drawn by their own contours (with or without components); "
               "`run_morph` strokes a glyph's paths and its components' together, so a "
               "composite is trimmed as one outline here, where the command keeps its "
               "components as components.", "",
               "| set | glyphs | tol | glyphs with an overlap | over 2 tol | widest overlap "
               "(glyph) | largest overlap area (glyph) | total area | pathops check | "
               "failures |",
               "|---|---|---|---|---|---|---|---|---|---|"]
        for u in unr:
            s = summary(u["results"], 2 * u["tol"])
            md.append("| %s | %d | %.3f | %d | %d | %s | %s | %.3f | %.1e | %s |"
                      % (u["set"], u["glyphs"], u["tol"], s["with"], s["over"],
                         _g(s["widest"], "width"), _g(s["largest"], "area"),
                         s["total_area"], s["disagree"], ", ".join(u["failures"]) or "none"))
    if ctl:
        md += ["", "## Control: the check fails", "",
               "Glyph %s of %s with a copy of its first contour moved 1 unit right: widest "
               "overlap %.2f units, area %.1f, against the bound %.2f: %s."
               % (ctl["glyph"], ctl["font"], ctl["width"], ctl["area"], ctl["bound"],
                  "flagged" if ctl["flagged"] else "NOT flagged (the check is broken)"),
               "`tests/test_font_overlaps.py` checks this on known shapes (two squares "
               "crossing by 1.5 x the bound fail, by 0.5 x pass with the lens reported; "
               "nested squares pass; a poking hole and a twisted contour fail)."]
    md += ["", "## Overlaps", "",
           "`bench/stroke_overlaps.png`: per set, the glyph with the widest overlap, whole "
           "and zoomed on it (the nonzero fill grey, the overlaps red, the contours black, "
           "the widest overlap circled in red).", "",
           "Per font, the glyphs with an overlap (widest first; at most %d listed): "
           "width / area at the inscribed circle's centre (x, y), w = the winding "
           "number signed as above." % LISTED, ""]
    for r in rows:
        if r.get("glyphs") is None:
            continue
        found = sorted((g for g in r["results"] if g.overlaps), key=lambda g: -g.width)
        if not found:
            md.append("- %s.%s: none." % (r["set"], r["format"]))
            continue
        items = []
        for g in found[:LISTED]:
            o = g.overlaps[0]
            items.append("%s %.3f / %.3f at (%.1f, %.1f) w %d%s"
                         % (g.name, o.width, o.area, o.x, o.y, o.winding,
                            "" if len(g.overlaps) == 1 else " (+%d more)" % (len(g.overlaps) - 1)))
        md.append("- %s.%s (%d): %s%s" % (r["set"], r["format"], len(found), "; ".join(items),
                                           "; ..." if len(found) > LISTED else ""))
    for u in unr:
        found = sorted((g for g in u["results"] if g.overlaps), key=lambda g: -g.width)
        md.append("- %s before rounding (%d): %s" % (
            u["set"], len(found), "; ".join("%s %.3f / %.3f" % (g.name, g.width, g.area)
                                            for g in found[:LISTED]) or "none."))
    md += ["", "## Over the bound", ""]
    by_set = {}
    for r in rows:
        if r.get("glyphs") is None:
            continue
        for g in r["results"]:
            if g.width > r["bound"]:
                by_set.setdefault(r["set"], {}).setdefault(g.name, []).append(
                    (r["format"], g.width))
    if not by_set:
        md.append("No overlap wider than the bound in any font.")
    for name, found in by_set.items():
        order = sorted(found, key=lambda n: -max(w for _, w in found[n]))
        kinds = composites(name, order)
        fmts = sorted({f for v in found.values() for f, _ in v})
        md.append("- %s (%s): %d glyphs, widest first: %s.  In the source, %d of them are "
                  "composites (components kept as components, or beside contours of their "
                  "own: the parts are stroked separately and not trimmed together), %d "
                  "not.  Reproduce: `%s --glyphs %s`, then `python -c \"from "
                  "tests.oracles.overlaps import font_overlaps; "
                  "print(font_overlaps('%s.%s', ['%s']))\"`."
                  % (name, ", ".join(fmts), len(order), ", ".join(order), kinds[0],
                     len(order) - kinds[0],
                     shown(command(name, fmts[0], "%s.%s" % (order[0], fmts[0]), 1))
                     .replace(" --jobs 1", ""), order[0], order[0], fmts[0], order[0]))
        if kinds[1]:
            md.append("  Not composites in the source: %s." % ", ".join(kinds[1]))
    return "\n".join(md) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--runs", default=DEFAULT_RUNS)
    ap.add_argument("--unrounded", default=DEFAULT_UNROUNDED,
                    help="sets also checked in process before rounding ('' for none)")
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--written", help="SET:JOBS:PATH,...: fonts the command wrote before "
                    "(with --jobs JOBS), checked as they are (e.g. hanzi-all from "
                    "bench.stroke_memory --keep)")
    ap.add_argument("--keep", help="write the fonts into this folder (kept)")
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke_overlaps.md"))
    ap.add_argument("--png", help="the figure, written with the report (default: the "
                    "report's path with .png)")
    ap.add_argument("--strict", action="store_true",
                    help="exit 1 when a glyph has an overlap over the bound")
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    shown_argv = [a or "''" for a in argv if a not in ("--no-write", "--strict")]
    if "--written" in shown_argv:  # the fonts' names, not the machine's paths
        i = shown_argv.index("--written") + 1
        shown_argv[i] = ",".join(w.rsplit(":", 1)[0] + ":" + Path(w.rsplit(":", 1)[1]).name
                                 for w in shown_argv[i].split(",") if w)
    for flag in ("--md", "--keep", "--png"):
        if flag in shown_argv:
            i = shown_argv.index(flag)
            del shown_argv[i:i + 2]
    t0 = time.perf_counter()
    rows, unr = [], []
    with tempfile.TemporaryDirectory() as tmp:
        workdir = Path(opt.keep or tmp)
        workdir.mkdir(parents=True, exist_ok=True)
        runs = [(r.split(":")[0], r.split(":")[1], None) for r in opt.runs.split(",") if r]
        for w in filter(None, (opt.written or "").split(",")):
            name, jobs, path = w.split(":", 2)
            runs.append((name, Path(path).suffix[1:], (int(jobs), path)))
        for name, fmt, written in runs:
            r = (check_run(name, fmt, workdir, written[0], written[1]) if written else
                 check_run(name, fmt, workdir, opt.jobs))
            if r.get("glyphs") is not None:
                s = summary(r["results"], r["bound"])
                print("%s.%s: %d glyphs, %d with an overlap, %d over %.2f; widest %s"
                      % (name, fmt, r["glyphs"], s["with"], s["over"], r["bound"],
                         _g(s["widest"], "width")), flush=True)
            else:
                print("%s.%s: the command failed: %s" % (name, fmt, r["line"]), flush=True)
            rows.append(r)
        ctl = next((control(r) for r in rows if r.get("glyphs")), None)
        for name in filter(None, opt.unrounded.split(",")):
            u = unrounded(name)
            s = summary(u["results"], 2 * u["tol"])
            print("%s before rounding: %d glyphs, %d with an overlap; widest %s"
                  % (name, u["glyphs"], s["with"], _g(s["widest"], "width")), flush=True)
            unr.append(u)
        text = markdown(rows, unr, ctl, shown_argv, time.perf_counter() - t0)
        if not opt.no_write:
            Path(opt.md).write_text(text)
            png = opt.png or str(Path(opt.md).with_suffix(".png"))
            if figure(rows, png):
                print("figure", png)
    print(text)
    bad = any(summary(r["results"], r["bound"])["over"] for r in rows if r.get("glyphs"))
    return 1 if (bad and opt.strict) or (ctl and not ctl["flagged"]) else 0


if __name__ == "__main__":
    sys.exit(main())

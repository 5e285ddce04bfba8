"""``morph brush`` against FontForge's Expand Stroke + Remove Overlap, on the same glyphs.

    python -m bench.brush_fontforge [--glyphs A-Z,a-z,0-9] [--nib 80,30,30] [--tol 0.5]
                                    [--ff-accuracy 1,0.25] [--md bench/brush_fontforge.md]

Source: the bundled Noto Sans in its CFF version (``morph.parse.cubic_test_font_path``,
upm 1000), so that both tools write cubics and their points compare.  Nib: the
default of ``morph brush`` (exact ellipse 80 x 30 units, 30 degrees).

- morph: the whole command ``morph brush FONT -o OUT.otf --glyphs ... --jobs 1`` in a
  fresh process (user + sys CPU of the process, from the kernel: reading, planning,
  the sums, export, certificate, tables, saving, the sample image and specimen),
  and ``morph.fonts.brush.brush_font`` in this process (``process_time`` of the call:
  reading the source, the sums, saving the font), both divided by the glyphs.
- FontForge: ``bench/fontforge_brush.py`` in Debian's python3: Expand Stroke of the
  outline with the elliptical nib, then the original contours added and Remove
  Overlap (A ⊕ nib = A ∪ (∂A ⊕ nib)); the CPU time of those calls per glyph, at
  each ``--ff-accuracy`` (FontForge's target error in font units).

Errors: every written glyph against an independent reference, the Clipper sum of the
source glyph and the nib flattened within ``--ref-tol`` (``tests.oracles.reference.
polygon_minkowski_sum``; morph's glyphs shifted by the nib's left extent, as it
writes them), two-sided boundary Hausdorff distance (``tests.oracles.reference.
hausdorff``), morph's glyphs read back from the saved font (integer coordinates),
FontForge's as it returns them (unrounded).  Points: on- and off-curve points of
the written contours.  CPU times, not wall times: the machine is shared.
"""

import argparse
import json
import os
import resource
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402 - after sys.path gets the repo root

SYSTEM_PYTHON = "/usr/bin/python3"


def _chars(spec):
    from morph.fonts.brush import parse_glyph_spec

    return parse_glyph_spec(spec)


def run_command(src, chars, nib, tol, out):
    """(CPU seconds of the whole ``morph brush`` process, its last line)."""
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1",
               PYTHONPATH=os.environ.get("PYTHONPATH") or str(ROOT))
    proc = subprocess.run([sys.executable, "-m", "morph.cli", "brush", str(src), "-o", str(out),
                           "--glyphs", ",".join(chars), "--nib", "ellipse:%g,%g,%g" % nib,
                           "--tol", repr(tol / 1000.0), "--jobs", "1", "--force"],
                          env=env, capture_output=True, text=True)
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    lines = (proc.stdout + proc.stderr).strip().splitlines()
    return cpu, (lines[-1] if lines else "") + ("" if proc.returncode == 0 else
                                                 " (exit %d)" % proc.returncode)


def morph_in_process(src, chars, nib, tol, out):
    from morph.fonts.brush import brush_font, ellipse_nib

    t0 = time.process_time()
    stats = brush_font(str(src), str(out), ellipse_nib(*nib), chars, tol=tol, jobs=1)
    return time.process_time() - t0, stats


def written_points(out, names):
    from fontTools.pens.recordingPen import DecomposingRecordingPen
    from fontTools.ttLib import TTFont

    gs = TTFont(str(out)).getGlyphSet()
    points = []
    for n in names:
        pen = DecomposingRecordingPen(gs)
        gs[n].draw(pen)
        points.append(sum(len(args) for op, args in pen.value if op != "closePath"))
    return points


def run_fontforge(src, names, nib, accuracy):
    job = json.dumps({"font": str(src), "nib": list(nib), "accuracy": accuracy,
                      "glyphs": names})
    proc = subprocess.run([SYSTEM_PYTHON, str(ROOT / "bench" / "fontforge_brush.py")],
                          input=job, capture_output=True, text=True)
    if proc.returncode != 0:
        raise RuntimeError("FontForge failed: %s" % proc.stderr.strip().splitlines()[-1:])
    return json.loads(proc.stdout), proc.stderr


def main(argv=None):
    from bench.stroke import segments_to_region
    from bench.stroke_profile import code_version, shown_args
    from morph.fonts.brush import ellipse_nib, region_extent
    from morph.parse import cubic_test_font_path, glyph_region
    from morph.region import translate_region
    from tests.oracles.reference import hausdorff, polygon_minkowski_sum, region_to_shapely

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glyphs", default="A-Z,a-z,0-9")
    ap.add_argument("--nib", default="80,30,30")
    ap.add_argument("--tol", type=float, default=0.5, help="font units")
    ap.add_argument("--ref-tol", type=float, default=0.25, help="font units")
    ap.add_argument("--ff-accuracy", default="1,0.25")
    ap.add_argument("--md", default=str(ROOT / "bench" / "brush_fontforge.md"))
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    src = cubic_test_font_path()
    chars = _chars(opt.glyphs)
    nib_spec = tuple(float(v) for v in opt.nib.split(","))
    nib = ellipse_nib(*nib_spec)
    from fontTools.ttLib import TTFont

    cmap = TTFont(str(src)).getBestCmap()
    names = [cmap[ord(c)] for c in chars]
    x0 = region_extent(nib)[0]
    refs = {n: polygon_minkowski_sum(glyph_region(c, font=str(src)).region, nib, opt.ref_tol)
            for c, n in zip(chars, names)}
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        out = Path(tmp) / "brush.otf"
        cmd_cpu, line = run_command(src, chars, nib_spec, opt.tol, Path(tmp) / "cmd.otf")
        cpu, stats = morph_in_process(src, chars, nib_spec, opt.tol, out)
        errs = []
        for c, n in zip(chars, names):
            got = region_to_shapely(translate_region(glyph_region(c, font=str(out)).region,
                                                     (x0, 0.0)), 0.05)
            errs.append(hausdorff(got, refs[n], 0.5))
        pts = written_points(out, names)
        rows.append({"tool": "morph brush (whole command, --jobs 1)", "ms": 1000 * cmd_cpu
                     / len(names), "median": None, "points": None, "errs": None})
        rows.append({"tool": "morph brush_font (in process)", "ms": 1000 * cpu / len(names),
                     "median": None, "points": float(np.mean(pts)), "errs": errs,
                     "fallback": len(stats["fallback"])})
        for acc in [float(a) for a in opt.ff_accuracy.split(",")]:
            res, log = run_fontforge(src, names, nib_spec, acc)
            secs = [res[n]["seconds"] for n in names]
            ferrs = [hausdorff(region_to_shapely(segments_to_region(res[n]["contours"]),
                                                 0.05), refs[n], 0.5) for n in names]
            rows.append({"tool": "FontForge Expand Stroke + Remove Overlap, accuracy %g" % acc,
                         "ms": 1000 * float(np.mean(secs)),
                         "median": 1000 * float(np.median(secs)),
                         "points": float(np.mean([res[n]["points"] for n in names])),
                         "errs": ferrs, "internal": log.count("Internal Error")})
            print(rows[-1]["tool"], rows[-1]["ms"], max(ferrs), flush=True)
    md = ["# `morph brush` against FontForge's Expand Stroke + Remove Overlap "
          "(bench/brush_fontforge.py)", "",
          "Command: `python -m bench.brush_fontforge%s`; measured %s UTC at %s.  Machine: "
          "%d CPUs shared with other jobs (load average %s at the end): CPU times, not "
          "wall times.  Source: Noto Sans (CFF), %d glyphs (%s); nib ellipse %g x %g at "
          "%g degrees; morph at --tol %g units; errors against the Clipper reference "
          "(ref-tol %g)."
          % ("".join(" " + a for a in shown_args(argv)),
             time.strftime("%Y-%m-%d %H:%M", time.gmtime()), code_version(),
             os.cpu_count() or 1, ", ".join("%.1f" % v for v in os.getloadavg()),
             len(names), opt.glyphs, nib_spec[0], nib_spec[1], nib_spec[2], opt.tol,
             opt.ref_tol), "",
          "| tool | ms / glyph (mean) | ms / glyph (median) | points / glyph | worst error | "
          "mean error | glyphs over 1 unit |", "|---|---|---|---|---|---|---|"]

    def worst(e):
        """The largest error and its glyph's name."""
        return "%.2f (%s)" % (max(e), names[int(np.argmax(e))])

    for r in rows:
        e = r["errs"]
        md.append("| %s | %.1f | %s | %s | %s | %s | %s |" % (
            r["tool"], r["ms"], "-" if r["median"] is None else "%.1f" % r["median"],
            "-" if r["points"] is None else "%.0f" % r["points"],
            "-" if e is None else worst(e), "-" if e is None else "%.3f" % np.mean(e),
            "-" if e is None else ", ".join(n for n, v in zip(names, e) if v > 1.0) or "0"))
    md += ["", "The command's last line: `%s`." % line,
           "FontForge printed \"Internal Error\" %s times."
           % ", ".join(str(r.get("internal", 0)) for r in rows[2:]),
           "morph's in-process time includes reading the source and saving the font; "
           "FontForge's is its two calls per glyph only (opening the font and converting "
           "it to cubics not counted)."]
    text = "\n".join(md) + "\n"
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""Brush-swept fonts (issue #6): a whole A-Z, a-z font brushed, timed and checked.

    python -m bench.brush [--fonts ttf,cff] [--glyphs A-Z,a-z] [--nib 80,30,30]
                          [--tol 0.5] [--ref-tol 0.25] [--md bench/brush.md | --no-write]

For each bundled font -- the TrueType Noto Sans (``ttf``,
``morph.parse.default_font_path()``) and its CFF version (``cff``,
``morph.parse.cubic_test_font_path()``), both upm 1000 -- every chosen glyph is
brushed with ``morph.fonts.brush.brush_font`` in one call (the default nib of
``morph brush``: exact ellipse 80 x 30 font units rotated 30 degrees; total outline
tolerance ``--tol`` font units), and the wall time of that call is reported
(perf_counter, one run, single process; it includes reading the source outlines and
saving the font), with its CPU time (process_time: less sensitive to other load).

Then every written glyph is read back from the saved font (``morph.parse.glyph_region``:
the quadratics / cubics actually stored, on integer coordinates) and compared with an
independent polygon reference, ``tests.reference.polygon_minkowski_sum`` of the source
glyph and the nib (both flattened within ``--ref-tol`` units, summed with Clipper),
shifted like the written glyph (right by the nib's left extent).  The measure is the
two-sided boundary Hausdorff distance ``tests.reference.hausdorff`` (our curves
flattened within 0.05 units, boundaries sampled every 0.5 units).  The issue's
criterion: Hausdorff <= 1 font unit for every glyph; a glyph above it is a failure.
Advance widths are checked too (original + nib width, rounded).  A glyph whose sum
raises is a failure; the font is then brushed again without it (and timed again).

Writes the summary and a per-glyph table to bench/brush.md.
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from fontTools.ttLib import TTFont  # noqa: E402 - after sys.path gets the repo root

from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.errors import MorphError  # noqa: E402 - after sys.path gets the repo root
from morph.fonts.brush import (brush_font, ellipse_nib, parse_glyph_spec,  # noqa: E402 - after sys.path gets the repo root
                               region_extent)
from morph.parse import cubic_test_font_path, default_font_path, glyph_region  # noqa: E402 - after sys.path gets the repo root
from tests.reference import hausdorff, polygon_minkowski_sum, region_to_shapely  # noqa: E402 - after sys.path gets the repo root

LIMIT = 1.0          # font units: the criterion at upm 1000
FONTS = {"ttf": default_font_path, "cff": cubic_test_font_path}


def check_glyph(src, out, ch, nib_shifted, ref_tol):
    """Hausdorff distance (font units) between the written glyph and the reference."""
    got = glyph_region(ch, font=str(out)).region
    ref = polygon_minkowski_sum(glyph_region(ch, font=src).region, nib_shifted, ref_tol)
    return hausdorff(region_to_shapely(got, 0.05), ref, 0.5)


def run_font(key, chars, nib_spec, tol, ref_tol, workdir):
    src = FONTS[key]()
    out = Path(workdir) / ("brush-%s%s" % (key, ".ttf" if key == "ttf" else ".otf"))
    nib = ellipse_nib(*nib_spec)
    raised = {}  # glyph -> error of brush_font; the font is brushed again without it
    while True:
        todo = [c for c in chars if c not in raised]
        done = []
        t0, c0 = time.perf_counter(), time.process_time()
        try:
            stats = brush_font(src, out, nib, todo, tol=tol, family_name="Bench Brush",
                               progress=done.append)
        except MorphError as exc:
            raised[todo[len(done)]] = "%s: %s" % (type(exc).__name__, exc)
            print("%s %s raised: %s" % (key, todo[len(done)], exc), flush=True)
            continue
        seconds, cpu = time.perf_counter() - t0, time.process_time() - c0
        break
    x0, _, x1, _ = region_extent(nib)
    nib_shifted = [[pc.translate(p, (-x0, 0.0)) for p in nib[0]]]
    a, b = TTFont(src), TTFont(str(out))
    cmap = a.getBestCmap()
    rows = []
    t1 = time.perf_counter()
    for ch in chars:
        name = cmap[ord(ch)]
        if ch in raised:
            rows.append({"char": ch, "err": None, "fail": True, "note": raised[ch]})
            continue
        err, note = None, ""
        try:
            err = check_glyph(src, out, ch, nib_shifted, ref_tol)
        except Exception as exc:  # noqa: BLE001 - reported as a failure of this glyph
            note = "%s: %s" % (type(exc).__name__, exc)
        adv_ok = b["hmtx"][name][0] == round(a["hmtx"][name][0] + (x1 - x0))
        if not adv_ok:
            note = (note + "; " if note else "") + "advance %d, want %d" % (
                b["hmtx"][name][0], round(a["hmtx"][name][0] + (x1 - x0)))
        fail = err is None or err > LIMIT or not adv_ok
        rows.append({"char": ch, "err": err, "fail": fail, "note": note})
        print("%s %s: %s%s" % (key, ch, "-" if err is None else "%.3f" % err,
                               "  FAIL " + note if fail else ""), flush=True)
    check_seconds = time.perf_counter() - t1
    errs = [r["err"] for r in rows if r["err"] is not None]
    return {"font": key, "src": Path(src).name, "seconds": seconds, "cpu": cpu,
            "stats": stats,
            "rows": rows, "worst": max(errs) if errs else float("nan"),
            "worst_char": max((r for r in rows if r["err"] is not None),
                              key=lambda r: r["err"])["char"] if errs else "-",
            "failures": [r for r in rows if r["fail"]], "check_seconds": check_seconds,
            "raised": sorted(raised),
            "size": out.stat().st_size}


def code_version():
    """'commit abc1234' of the measured tree, '+ uncommitted changes in morph/' if so."""
    import subprocess

    def git(*args):
        return subprocess.run(["git", "-C", str(ROOT)] + list(args), capture_output=True,
                              text=True).stdout.strip()

    head = git("rev-parse", "--short", "HEAD")
    if not head:
        return "unknown commit"
    dirty = git("status", "--porcelain", "--", "morph")
    return "commit %s%s" % (head, " + uncommitted changes in morph/" if dirty else "")


def markdown(results, opt, chars):
    md = ["# Brush-swept fonts (bench/brush.py)", "",
          "Command: `python -m bench.brush%s` (code: %s)" % (opt.argline, code_version()),
          "",
          "Nib: exact ellipse %g x %g font units rotated %g degrees (the default of "
          "`morph brush`); outline tolerance %g font units; %d glyphs (%s) per font; "
          "upm 1000.  Reference: Clipper sum of the source glyph and the nib flattened "
          "within %g units; criterion Hausdorff <= %g font unit for every glyph, and "
          "advance width = original + nib width."
          % (opt.nib[0], opt.nib[1], opt.nib[2], opt.tol, len(chars), opt.glyphs,
             opt.ref_tol, LIMIT), "",
          "| font | glyphs | brush wall time (s) | brush CPU time (s) | CPU s / glyph | "
          "contours | segments | worst Hausdorff (units) | failures | check time (s) |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        md.append("| %s (%s) | %d | %.1f | %.1f | %.2f | %d | %d | %.3f (%s) | %d | %.1f |"
                  % (r["font"], r["src"], r["stats"]["glyphs"], r["seconds"], r["cpu"],
                     r["cpu"] / max(1, r["stats"]["glyphs"]), r["stats"]["contours"],
            r["stats"]["segments"], r["worst"], r["worst_char"], len(r["failures"]),
            r["check_seconds"]))
    md += ["", "Brush time: one `brush_font` call, single process, including reading the "
           "source outlines and saving the font; the check (read back + reference sum + "
           "Hausdorff) is not included.  Wall time depends on what else the machine runs "
           "(load average %s at the end of the run, %d CPUs); CPU time much less."
           % (", ".join("%.1f" % v for v in os.getloadavg()), os.cpu_count() or 1)
           + "  A glyph whose sum raises stops `brush_font`; it is then counted as a "
           "failure and the font is brushed again without it (the time is that of the "
           "last, complete call)."]
    for r in results:
        if r["raised"]:
            md.append("%s: brushed without %s (raised)." % (r["font"], ", ".join(r["raised"])))
    md.append("")
    for r in results:
        if r["failures"]:
            md += ["## Failures (%s)" % r["font"], "", "| glyph | Hausdorff | note |",
                   "|---|---|---|"]
            md += ["| %s | %s | %s |" % (f["char"], "-" if f["err"] is None
                                         else "%.3f" % f["err"], f["note"])
                   for f in r["failures"]]
            md.append("")
    md += ["## Hausdorff per glyph (font units)", "",
           "| glyph | " + " | ".join(r["font"] for r in results) + " |",
           "|---|" + "---|" * len(results)]
    for i, ch in enumerate(chars):
        md.append("| %s | %s |" % (ch, " | ".join(
            "-" if r["rows"][i]["err"] is None else "%.3f" % r["rows"][i]["err"]
            for r in results)))
    return "\n".join(md) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fonts", default="ttf,cff", help="ttf, cff or both")
    ap.add_argument("--glyphs", default="A-Z,a-z", help="characters and ranges")
    ap.add_argument("--nib", default="80,30,30", help="ellipse width,height,angle")
    ap.add_argument("--tol", type=float, default=0.5, help="outline tolerance, font units")
    ap.add_argument("--ref-tol", type=float, default=0.25,
                    help="flattening of the polygon reference, font units")
    ap.add_argument("--md", default=str(ROOT / "bench" / "brush.md"))
    ap.add_argument("--no-write", action="store_true", help="do not write the markdown")
    opt = ap.parse_args(argv)
    opt.nib = tuple(float(v) for v in opt.nib.split(","))
    argv = sys.argv[1:] if argv is None else argv
    opt.argline = (" " + " ".join(argv)) if argv else ""
    chars = [c for c in parse_glyph_spec(opt.glyphs) if len(c) == 1]
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        for key in [k.strip() for k in opt.fonts.split(",") if k.strip()]:
            results.append(run_font(key, chars, opt.nib, opt.tol, opt.ref_tol, tmp))
    for r in results:
        print("%s: %d glyphs brushed in %.1f s (CPU %.1f s); worst Hausdorff %.3f units "
              "(%s); %d failures" % (r["font"], r["stats"]["glyphs"], r["seconds"], r["cpu"],
                                     r["worst"], r["worst_char"], len(r["failures"])))
    if not opt.no_write:
        Path(opt.md).write_text(markdown(results, opt, chars))
        print("wrote %s" % opt.md)
    return 1 if any(r["failures"] for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())

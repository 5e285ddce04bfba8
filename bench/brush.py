"""Brush-swept fonts (issues #6, #16): whole A-Z, a-z fonts brushed, timed and checked.

    python -m bench.brush [--fonts ttf,cff,ebg] [--glyphs A-Z,a-z] [--nibs 80,30,30;60,8,30]
                          [--tol 0.5] [--ref-tol 0.25] [--jobs 1] [--compare-jobs]
                          [--fontbakery] [--md bench/brush.md | --no-write]

Fonts: the bundled TrueType Noto Sans (``ttf``, ``morph.parse.default_font_path()``),
its CFF version (``cff``, ``morph.parse.cubic_test_font_path()``), both upm 1000, and
EB Garamond (``ebg``, the variable ``EBGaramond[wght].ttf`` of the PyPI package
fontpkg-eb-garamond, brushed at its default instance, made static by
``morph.parse.instantiate_font``; upm 1000).  For each font and each nib (exact
ellipse width,height,angle in font units/degrees; the first is the default of
``morph brush``) every chosen glyph is brushed with ``morph.fonts.brush.brush_font``
in one call (total outline tolerance ``--tol`` font units, ``--jobs`` processes); the
wall time of that call is reported (perf_counter, one run; it includes reading the
source outlines and saving the font), with the CPU time of this process (with
``--jobs`` > 1 the workers' CPU time is not in it).

A glyph whose sum raises no longer stops the font: ``brush_font`` writes it with the
polygon fallback (``morph.fonts.jobs.polygon_sum``) and names it in its result; the
table lists such glyphs, and they are checked like the others.

Then every written glyph is read back from the saved font (``morph.parse.glyph_region``:
the quadratics / cubics actually stored, on integer coordinates) and compared with an
independent polygon reference, ``tests.oracles.reference.polygon_minkowski_sum`` of the source
glyph and the nib (both flattened within ``--ref-tol`` units, summed with Clipper),
shifted like the written glyph (right by the nib's left extent).  The measure is the
two-sided boundary Hausdorff distance ``tests.oracles.reference.hausdorff`` (our curves
flattened within 0.05 units, boundaries sampled every 0.5 units).  The criterion:
Hausdorff <= 1 font unit for every glyph; a glyph above it is a failure.  Advance
widths are checked too (original + nib width, rounded).

``--compare-jobs``: the first font and nib are brushed again with ``--jobs 1`` and
``--jobs 2``; the two fonts' glyf/CFF, hmtx and GPOS tables must be byte-identical,
and both wall times are reported.  ``--fontbakery``: ``fontbakery check-universal
--skip-network`` on every source and output; the WARN/FAIL checks the output has and
the source has not are listed (the issue's criterion: none).

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

from morph.fonts.brush import (brush_font, ellipse_nib, open_source,  # noqa: E402 - after sys.path gets the repo root
                               parse_glyph_spec, region_extent)
from morph.parse import cubic_test_font_path, default_font_path, glyph_region  # noqa: E402 - after sys.path gets the repo root
from morph.region import translate_region  # noqa: E402 - after sys.path gets the repo root
from tests.oracles.reference import hausdorff, polygon_minkowski_sum, region_to_shapely  # noqa: E402 - after sys.path gets the repo root

LIMIT = 1.0          # font units: the criterion at upm 1000


def _ebg():
    import fontpkg_eb_garamond

    return str(fontpkg_eb_garamond.ROOT / "files" / "EBGaramond[wght].ttf")


FONTS = {"ttf": default_font_path, "cff": cubic_test_font_path, "ebg": _ebg}
SUFFIX = {"ttf": ".ttf", "cff": ".otf", "ebg": ".ttf"}


def check_glyph(src, out, ch, nib_shifted, ref_tol):
    """Hausdorff distance (font units) between the written glyph and the reference."""
    got = glyph_region(ch, font=str(out)).region
    ref = polygon_minkowski_sum(glyph_region(ch, font=src).region, nib_shifted, ref_tol)
    return hausdorff(region_to_shapely(got, 0.05), ref, 0.5)


def brush_timed(src, out, nib, chars, tol, jobs):
    t0, c0 = time.perf_counter(), time.process_time()
    stats = brush_font(src, out, nib, chars, tol=tol, family_name="Bench Brush", jobs=jobs)
    return stats, time.perf_counter() - t0, time.process_time() - c0


def run_font(key, chars, nib_spec, tol, ref_tol, workdir, jobs=1):
    src = FONTS[key]()
    tag = "%s-%g-%g-%g" % ((key,) + tuple(nib_spec))
    out = Path(workdir) / ("brush-%s%s" % (tag, SUFFIX[key]))
    nib = ellipse_nib(*nib_spec)
    stats, seconds, cpu = brush_timed(src, out, nib, chars, tol, jobs)
    fallback = stats["fallback"]
    for name, (kind, err) in sorted(fallback.items()):
        print("%s %s fell back (%s): %s" % (tag, name, kind, err), flush=True)
    x0, _, x1, _ = region_extent(nib)
    nib_shifted = translate_region(nib, (-x0, 0.0))
    a, b = TTFont(src), TTFont(str(out))
    cmap = a.getBestCmap()
    rows = []
    t1 = time.perf_counter()
    for ch in chars:
        name = cmap[ord(ch)]
        err, note = None, ""
        if name in fallback:
            note = "fallback %s: %s" % fallback[name]
        try:
            err = check_glyph(src, out, ch, nib_shifted, ref_tol)
        except Exception as exc:  # noqa: BLE001 - reported as a failure of this glyph
            note = (note + "; " if note else "") + "%s: %s" % (type(exc).__name__, exc)
        want = round(a["hmtx"][name][0] + (x1 - x0))
        adv_ok = b["hmtx"][name][0] == want
        if not adv_ok:
            note = (note + "; " if note else "") + "advance %d, want %d" % (
                b["hmtx"][name][0], want)
        fail = err is None or err > LIMIT or not adv_ok
        rows.append({"char": ch, "err": err, "fail": fail, "note": note})
        print("%s %s: %s%s" % (tag, ch, "-" if err is None else "%.3f" % err,
                               "  FAIL " + note if fail else ""), flush=True)
    check_seconds = time.perf_counter() - t1
    errs = [r["err"] for r in rows if r["err"] is not None]
    return {"font": key, "tag": tag, "nib": nib_spec, "src": Path(src).name,
            "seconds": seconds, "cpu": cpu, "stats": stats, "out": out, "src_path": src,
            "rows": rows, "worst": max(errs) if errs else float("nan"),
            "worst_char": max((r for r in rows if r["err"] is not None),
                              key=lambda r: r["err"])["char"] if errs else "-",
            "failures": [r for r in rows if r["fail"]], "check_seconds": check_seconds,
            "fallback": fallback, "size": out.stat().st_size}


def compare_jobs(key, chars, nib_spec, tol, workdir):
    """Brush with --jobs 1 and 2: identical tables?  Returns a dict for the report."""
    src, nib = FONTS[key](), ellipse_nib(*nib_spec)
    import resource

    res, cpu = {}, {}
    for jobs in (1, 2):
        out = Path(workdir) / ("jobs%d%s" % (jobs, SUFFIX[key]))
        child0 = resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime
        _, seconds, own = brush_timed(src, out, nib, chars, tol, jobs)
        cpu[jobs] = own + resource.getrusage(resource.RUSAGE_CHILDREN).ru_utime - child0
        res[jobs] = (seconds, TTFont(str(out)))
    tags = [t for t in ("glyf", "CFF ", "hmtx", "GPOS") if t in res[1][1]]
    same = {t: res[1][1].getTableData(t) == res[2][1].getTableData(t) for t in tags}
    print("jobs 1: %.1f s, jobs 2: %.1f s, identical: %s" % (res[1][0], res[2][0], same))
    return {"font": key, "nib": nib_spec, "glyphs": len(chars), "t1": res[1][0],
            "t2": res[2][0], "same": same, "cpu1": cpu[1], "cpu2": cpu[2]}


def static_source(src, workdir):
    """The source as brushed: a variable font's default instance saved as a file."""
    font = TTFont(src)
    if "fvar" not in font:
        return src
    out = Path(workdir) / (Path(src).stem.replace("[", "-").replace("]", "") + "-static.ttf")
    if not out.exists():
        open_source(font).save(str(out))
    return str(out)


def fontbakery(path, workdir):
    """fontbakery check-universal on ``path``: ({(check, status)} of its WARN / FAIL /
    ERROR results, {glyph: (contours, expected)} of its contour_count list)."""
    import json
    import re
    import subprocess

    report = Path(workdir) / (Path(path).name + ".fb.json")
    subprocess.run([sys.executable, "-m", "fontbakery", "check-universal", "--skip-network",
                    "-F", "-l", "WARN", "--json", str(report), str(path)],
                   capture_output=True, timeout=900, check=False)
    data = json.loads(report.read_text())
    results, contours = set(), {}
    for sec in data["sections"]:
        for c in sec["checks"]:
            check = c["key"][1].split(":")[-1].rstrip(">")
            if c["result"] in ("WARN", "FAIL", "ERROR", "FATAL"):
                results.add((check, c["result"]))
            if check == "contour_count":
                for log in c["logs"]:
                    for g, n, e in re.findall(r"Glyph name: (\S+)\s+Contours detected: (\d+)"
                                              r"\s+Expected: ([0-9 or]+)",
                                              log["message"]["message"]):
                        contours[g] = (int(n), e.strip())
    return results, contours


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


def jobs_markdown(jobs_cmp, opt):
    return ["", "## --jobs 2 against --jobs 1", "",
            "%s, nib %g x %g @ %g, %d glyphs: `--jobs 1` %.1f s, `--jobs 2` %.1f s wall "
            "(x%.2f); CPU time (this process + workers) %.1f s and %.1f s; tables "
            "byte-identical: %s.  Command: `python -m bench.brush%s` (code: %s); load "
            "average %s at the end, %d CPUs (with a load above the CPU count, the other "
            "processes take the second core and wall times cannot show the speed-up)."
            % (jobs_cmp["font"], jobs_cmp["nib"][0], jobs_cmp["nib"][1],
               jobs_cmp["nib"][2], jobs_cmp["glyphs"], jobs_cmp["t1"], jobs_cmp["t2"],
               jobs_cmp["t1"] / jobs_cmp["t2"], jobs_cmp["cpu1"], jobs_cmp["cpu2"],
               ", ".join("%s %s" % (t, "yes" if v else "NO")
                         for t, v in jobs_cmp["same"].items()),
               opt.argline, code_version(),
               ", ".join("%.1f" % v for v in os.getloadavg()), os.cpu_count() or 1)]


def markdown(results, opt, chars, jobs_cmp=None, bakery=None):
    md = ["# Brush-swept fonts (bench/brush.py)", "",
          "Command: `python -m bench.brush%s` (code: %s)" % (opt.argline, code_version()),
          "",
          "Nibs: exact ellipses (width x height font units, rotated; %s); outline "
          "tolerance %g font units; %d glyphs (%s) per font; upm 1000; `--jobs %d`.  "
          "Reference: Clipper sum of the source glyph and the nib flattened within %g "
          "units; criterion Hausdorff <= %g font unit for every glyph, and advance width "
          "= original + nib width.  ebg = EB Garamond (fontpkg-eb-garamond), static "
          "default instance."
          % ("; ".join("%g x %g at %g deg" % n for n in opt.nibs), opt.tol, len(chars),
             opt.glyphs, opt.jobs, opt.ref_tol, LIMIT), "",
          "| font | nib | glyphs | brush wall time (s) | brush CPU time (s) | contours | "
          "segments | worst Hausdorff (units) | failures | fell back | check time (s) |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in results:
        md.append("| %s (%s) | %g x %g @ %g | %d | %.1f | %.1f | %d | %d | %.3f (%s) | %d "
                  "| %s | %.1f |"
                  % (r["font"], r["src"], r["nib"][0], r["nib"][1], r["nib"][2],
                     r["stats"]["glyphs"], r["seconds"], r["cpu"], r["stats"]["contours"],
                     r["stats"]["segments"], r["worst"], r["worst_char"], len(r["failures"]),
                     ", ".join("%s (%s)" % (n, k) for n, (k, _) in sorted(r["fallback"].items()))
                     or "none", r["check_seconds"]))
    md += ["", "Brush time: one `brush_font` call including reading (and, for ebg, "
           "instancing) the source and saving the font; the check (read back + reference "
           "sum + Hausdorff) is not included.  Wall time depends on what else the machine "
           "runs (load average %s at the end of the run, %d CPUs)."
           % (", ".join("%.1f" % v for v in os.getloadavg()), os.cpu_count() or 1)]
    fell = [(r["tag"], n, k, e) for r in results for n, (k, e) in sorted(r["fallback"].items())]
    if fell:
        md += ["", "## Glyphs that fell back", "", "| font-nib | glyph | written by | error |",
               "|---|---|---|---|"]
        md += ["| %s | %s | %s | %s |" % (t, n, k, e.replace("|", "/")) for t, n, k, e in fell]
    if jobs_cmp:
        md += jobs_markdown(jobs_cmp, opt)
    if bakery:
        md += ["", "## fontbakery check-universal (--skip-network)", "",
               "On the source as brushed (ebg: its static default instance) and on the "
               "output.  The last column lists glyphs that the output's contour_count "
               "WARN names and the source's does not (contours found, expected).", "",
               "| font | source WARN/FAIL | output WARN/FAIL the source lacks | "
               "contour_count: glyphs newly listed |", "|---|---|---|---|"]
        for tag, ((before, cb), (after, ca)) in bakery.items():
            new_cc = sorted(g for g in ca if g not in cb)
            md.append("| %s | %s | %s | %s |" % (
                tag, ", ".join("%s %s" % (s, c) for c, s in sorted(before)) or "none",
                ", ".join("%s %s" % (s, c) for c, s in sorted(after - before)) or "none",
                ", ".join("%s (%d, %s)" % ((g,) + ca[g]) for g in new_cc[:12])
                + (" and %d more" % (len(new_cc) - 12) if len(new_cc) > 12 else "")
                or "none"))
    md.append("")
    for r in results:
        if r["failures"]:
            md += ["## Failures (%s)" % r["tag"], "", "| glyph | Hausdorff | note |",
                   "|---|---|---|"]
            md += ["| %s | %s | %s |" % (f["char"], "-" if f["err"] is None
                                         else "%.3f" % f["err"], f["note"].replace("|", "/"))
                   for f in r["failures"]]
            md.append("")
    md += ["## Hausdorff per glyph (font units)", "",
           "| glyph | " + " | ".join(r["tag"] for r in results) + " |",
           "|---|" + "---|" * len(results)]
    for i, ch in enumerate(chars):
        md.append("| %s | %s |" % (ch, " | ".join(
            "-" if r["rows"][i]["err"] is None else "%.3f" % r["rows"][i]["err"]
            for r in results)))
    return "\n".join(md) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fonts", default="ttf,cff", help="ttf, cff, ebg, comma separated")
    ap.add_argument("--glyphs", default="A-Z,a-z", help="characters and ranges")
    ap.add_argument("--nibs", default="80,30,30",
                    help="ellipses width,height,angle separated by ';'")
    ap.add_argument("--tol", type=float, default=0.5, help="outline tolerance, font units")
    ap.add_argument("--ref-tol", type=float, default=0.25,
                    help="flattening of the polygon reference, font units")
    ap.add_argument("--jobs", type=int, default=1, help="processes per brush_font call")
    ap.add_argument("--compare-jobs", action="store_true",
                    help="also brush the first font with --jobs 1 and 2 and compare")
    ap.add_argument("--jobs-only", action="store_true",
                    help="only the --compare-jobs run; its section of --md is replaced")
    ap.add_argument("--fontbakery", action="store_true",
                    help="fontbakery check-universal on every source and output")
    ap.add_argument("--md", default=str(ROOT / "bench" / "brush.md"))
    ap.add_argument("--no-write", action="store_true", help="do not write the markdown")
    opt = ap.parse_args(argv)
    opt.nibs = [tuple(float(v) for v in n.split(",")) for n in opt.nibs.split(";") if n]
    argv = sys.argv[1:] if argv is None else argv
    opt.argline = (" " + " ".join(argv)) if argv else ""
    chars = [c for c in parse_glyph_spec(opt.glyphs) if len(c) == 1]
    keys = [k.strip() for k in opt.fonts.split(",") if k.strip()]
    results, jobs_cmp, bakery = [], None, {}
    if opt.jobs_only:
        with tempfile.TemporaryDirectory() as tmp:
            jobs_cmp = compare_jobs(keys[0], chars, opt.nibs[0], opt.tol, tmp)
        section = jobs_markdown(jobs_cmp, opt)
        if not opt.no_write:
            text = Path(opt.md).read_text()
            start = text.index("## --jobs 2 against --jobs 1")
            end = text.index("\n## ", start + 3)
            Path(opt.md).write_text(text[:start] + "\n".join(section[1:]) + "\n" + text[end:])
            print("updated %s" % opt.md)
        return 0 if all(jobs_cmp["same"].values()) else 1
    with tempfile.TemporaryDirectory() as tmp:
        for key in keys:
            for nib in opt.nibs:
                r = run_font(key, chars, nib, opt.tol, opt.ref_tol, tmp, opt.jobs)
                results.append(r)
                if opt.fontbakery:
                    bakery[r["tag"]] = (fontbakery(static_source(r["src_path"], tmp), tmp),
                                        fontbakery(r["out"], tmp))
        if opt.compare_jobs:
            jobs_cmp = compare_jobs(keys[0], chars, opt.nibs[0], opt.tol, tmp)
    for r in results:
        print("%s: %d glyphs brushed in %.1f s (CPU %.1f s); worst Hausdorff %.3f units "
              "(%s); %d failures; fell back: %s"
              % (r["tag"], r["stats"]["glyphs"], r["seconds"], r["cpu"], r["worst"],
                 r["worst_char"], len(r["failures"]), sorted(r["fallback"]) or "none"))
    if not opt.no_write:
        Path(opt.md).write_text(markdown(results, opt, chars, jobs_cmp, bakery))
        print("wrote %s" % opt.md)
    return 1 if any(r["failures"] for r in results) else 0


if __name__ == "__main__":
    sys.exit(main())

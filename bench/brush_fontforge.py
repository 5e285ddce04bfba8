"""``morph brush`` against FontForge's Expand Stroke + Remove Overlap, on the same glyphs.

    python -m bench.brush_fontforge [--glyphs A-Z,a-z,0-9] [--nib 80,30,30] [--tol 0.5]
                                    [--ff-accuracy 1,0.25] [--repeat 3]
                                    [--md bench/brush_fontforge.md]

Source: the bundled Noto Sans in its CFF version (``morph.parse.cubic_test_font_path``,
upm 1000), so that both tools write cubics and their points compare.  Nib: the
default of ``morph brush`` (exact ellipse 80 x 30 units, 30 degrees).

- morph: the whole command ``morph brush FONT -o OUT.otf --glyphs ... --jobs 1`` in a
  fresh process, started as after a pip install: a virtual environment's site, its
  modules' bytecode cached (:mod:`bench.pycache`; user + sys CPU of the process, from
  the kernel: reading, planning,
  the sums, export, certificate, tables, saving, the sample image and specimen),
  and ``morph.fonts.brush.brush_font`` in this process (``process_time`` of the call:
  reading the source, the sums, saving the font), both divided by the glyphs, each
  the median of ``--repeat`` runs (one pass varies by +-20 % on a shared machine).
- FontForge: ``bench/fontforge_brush.py`` in Debian's python3: Expand Stroke of the
  outline with the elliptical nib, then the original contours added and Remove
  Overlap (A ⊕ nib = A ∪ (∂A ⊕ nib)); the CPU time of those calls per glyph, at
  each ``--ff-accuracy`` (FontForge's target error in font units); and the worker's
  whole process, which opens the font, brushes the glyphs and saves the font
  (``font.generate``, .otf), as ``morph brush`` does.

The two are timed in the same run, interleaved (:mod:`bench.paired`): ``--repeat``
rounds, each morph's command, FontForge's worker at every accuracy, then morph's
``brush_font``; each time is the median of its rounds, and the table gives the median
of the per-round ratios morph / FontForge, which the shared machine's drift (20-40 %
between hours) hits alike on both sides.  FontForge's outlines, points, errors and
"Internal Error" counts do not depend on the machine's state and come from the bench
cache (:mod:`bench.peer_cache`) when made before; its times never do.

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
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402 - after sys.path gets the repo root

SYSTEM_PYTHON = "/usr/bin/python3"
WORKER = ROOT / "bench" / "fontforge_brush.py"


def _chars(spec):
    from morph.fonts.brush import parse_glyph_spec

    return parse_glyph_spec(spec)


def command_runner(src, chars, nib, tol, out):
    """A function running the whole ``morph brush`` process once: (CPU seconds, its
    last line), its own user + sys time (:func:`bench.paired.child_run`).  The process
    starts with a virtual environment's site and loads its modules' bytecode from a
    cache that an untimed first run fills (:mod:`bench.pycache`), as after a pip
    install; FontForge's Python loads its own compiled modules too."""
    from bench.paired import child_run
    from bench.pycache import cached_env, installed_python

    env = cached_env("brush-fontforge-pycache-", OPENBLAS_NUM_THREADS="1")
    cmd = [installed_python(), "-m", "morph.cli", "brush", str(src), "-o", str(out),
           "--glyphs", ",".join(chars), "--nib", "ellipse:%g,%g,%g" % nib,
           "--tol", repr(tol / 1000.0), "--jobs", "1", "--force"]
    child_run(cmd, env=env)   # fills the cache

    def run():
        cpu, _, code, stdout, stderr = child_run(cmd, env=env)
        lines = (stdout + stderr).strip().splitlines()
        return cpu, (lines[-1] if lines else "") + ("" if code == 0 else " (exit %d)" % code)
    run.env = env
    return run


def morph_in_process(src, chars, nib, tol, out):
    """(CPU seconds of ``brush_font``, CPU seconds of its sweep alone, stats): the
    sweep (``morph.fonts.brush._sweep_font``: the sums and the certified export of
    the glyphs by the command's chunks, ``jobs=1``) is timed inside the call.  What
    the bench holds is frozen out of the collector's passes meanwhile, as ``morph``'s
    commands freeze what their process holds when they start (:mod:`morph.cli.group`)."""
    import gc

    from morph.fonts import brush

    swept = []
    sweep = brush._sweep_font

    def timed_sweep(*args, **kwargs):
        t0 = time.process_time()
        try:
            return sweep(*args, **kwargs)
        finally:
            swept.append(time.process_time() - t0)

    brush._sweep_font = timed_sweep
    gc.freeze()
    try:
        t0 = time.process_time()
        stats = brush.brush_font(str(src), str(out), brush.ellipse_nib(*nib), chars, tol=tol,
                                 jobs=1)
        total = time.process_time() - t0
    finally:
        gc.unfreeze()
        brush._sweep_font = sweep
    return total, sum(swept), stats


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
    """(FontForge's outlines, the cache entry's provenance, its key, made now): from the
    bench cache (:mod:`bench.peer_cache`) when made before from the same font file (its
    bytes), glyphs, nib, accuracy, FontForge version and worker scripts, else by one
    untimed run of the worker; the value holds {"results": {glyph: {"points",
    "contours"}}, "internal_errors"}, no time (FontForge's times are measured in every
    run, interleaved with morph's: :func:`timed_rounds`)."""
    from bench import peer_cache
    from bench.paired import child_run

    version = peer_cache.fontforge_version()
    if version is None:
        raise RuntimeError("no fontforge module in %s" % SYSTEM_PYTHON)
    key = peer_cache.digest("fontforge-brush", Path(src).read_bytes(), list(names),
                            list(nib), accuracy, version,
                            peer_cache.file_digest("bench/fontforge_brush.py",
                                                   "bench/fontforge_stroke.py"))
    hit = peer_cache.get("fontforge-brush", key)
    if hit is not None:
        return hit["value"], hit["provenance"], key, False
    prov = peer_cache.provenance(version)
    with tempfile.TemporaryDirectory() as tmp:
        _, _, code, out, err = child_run([SYSTEM_PYTHON, str(WORKER)], json.dumps(
            _job(src, names, nib, accuracy, Path(tmp) / "ff.otf")))
        generated = (Path(tmp) / "ff.otf").is_file()
    if code != 0:
        raise RuntimeError("FontForge failed: %s" % err.strip().splitlines()[-1:])
    if not generated:
        raise RuntimeError("FontForge wrote no font: %s" % err.strip().splitlines()[-1:])
    results = {n: {k: v for k, v in g.items() if k != "seconds"}
               for n, g in json.loads(out).items()}
    value = {"results": results, "internal_errors": err.count("Internal Error")}
    peer_cache.put("fontforge-brush", key, {"value": value, "provenance": prov})
    return value, prov, key, True


def _job(src, names, nib, accuracy, generate):
    """The job of ``bench/fontforge_brush.py``: brush ``names`` of ``src``, save the font
    to ``generate``."""
    return {"font": str(src), "nib": list(nib), "accuracy": accuracy, "glyphs": list(names),
            "generate": str(generate)}


def timed_rounds(src, chars, names, nib_spec, opt, accs, tmp):
    """morph and FontForge timed in ``opt.repeat`` rounds (:mod:`bench.paired`): each
    round runs morph's whole command once, FontForge's worker once at each accuracy of
    ``accs`` (in process: the brush's CPU time per glyph; the worker's whole process,
    which saves the font), then morph's ``brush_font`` once.  (morph's figures: the
    command's "cmd" and the in-process "sweep" and "brush_font" ms per glyph of every
    round, the median pass, the command's last line; FontForge's: {accuracy: {"ms",
    "median", "process": ms per glyph of every round}})."""
    from bench.paired import interpreter_starts, warm_fontforge, worker_times

    n = len(names)
    command = command_runner(src, chars, nib_spec, opt.tol, Path(tmp) / "cmd.otf")
    warm_fontforge()
    morph = {"cmd": [], "sweep": [], "brush_font": [], "passes": [], "starts": []}
    ff = {acc: {"ms": [], "median": [], "process": []} for acc in accs}
    for _ in range(opt.repeat):
        cpu, morph["line"] = command()
        morph["cmd"].append(1000 * cpu / n)
        for acc in accs:
            t = worker_times(WORKER, _job(src, names, nib_spec, acc, Path(tmp) / "ff.otf"),
                             names)
            ff[acc]["ms"].append(1000 * t["mean"])
            ff[acc]["median"].append(1000 * t["median"])
            ff[acc]["process"].append(1000 * t["process"] / n)
        one = morph_in_process(src, chars, nib_spec, opt.tol, Path(tmp) / "brush.otf")
        morph["passes"].append(one)
        morph["brush_font"].append(1000 * one[0] / n)
        morph["sweep"].append(1000 * one[1] / n)
        morph["starts"].append(interpreter_starts(command.env))
    morph["line"] = morph["line"].replace(str(tmp) + os.sep, "")  # no machine path
    return morph, ff


def brush_references(src, chars, names, nib, ref_tol):
    """({glyph: Clipper sum of the source glyph and the nib}, {glyph: key}, note), each
    from the bench cache when made before from the same font file, glyph, nib outline,
    ``ref_tol`` and oracle version."""
    from bench import peer_cache
    from morph.parse import glyph_region
    from tests.oracles.reference import polygon_minkowski_sum

    import shapely

    version = peer_cache.oracle_version()
    font_key = peer_cache.digest(Path(src).read_bytes())
    nib_key = [np.asarray(p, float) for p in nib[0]]
    refs, keys, provs, fresh = {}, {}, [], 0
    for c, n in zip(chars, names):
        key = peer_cache.digest("brush-reference", font_key, c, n, nib_key, ref_tol, version)
        wkb, prov, new = peer_cache.cached(
            "brush-reference", key, lambda: shapely.to_wkb(polygon_minkowski_sum(
                glyph_region(c, font=str(src)).region, nib, ref_tol)), version)
        refs[n], keys[n] = shapely.from_wkb(wkb), key
        provs.append(prov)
        fresh += new
    return refs, keys, peer_cache.measured_note(provs, fresh)


def _morph_row(morph, src, chars, names, refs, x0, out, opt):
    """morph's row: the median in-process pass (by its sweep's time), the command's
    median, the saved font's points and errors (read back from ``out``)."""
    from bench.paired import median
    from bench.stroke import boundary_hausdorff
    from morph.parse import glyph_region
    from morph.region import translate_region
    from tests.oracles.reference import region_to_shapely

    n = len(names)
    cpu, sweep_cpu, stats = sorted(morph["passes"], key=lambda p: p[1])[len(morph["passes"])
                                                                         // 2]
    errs = []
    for c, name in zip(chars, names):
        got = region_to_shapely(translate_region(glyph_region(c, font=str(out)).region,
                                                 (x0, 0.0)), 0.05)
        errs.append(boundary_hausdorff(got, refs[name], 0.5))
    return {"tool": "morph", "setting": "tol %g" % opt.tol, "ms": 1000 * sweep_cpu / n,
            "median": None, "whole": median(morph["cmd"]), "brush_font": 1000 * cpu / n,
            "points": float(np.mean(written_points(out, names))), "errs": errs,
            "fallback": len(stats["fallback"])}


def _fontforge_row(value, prov, key, fresh, acc, names, refs, ref_keys, times):
    """(row, note) of FontForge at accuracy ``acc``: its outlines ``value`` (of the cache
    entry ``key``) judged against ``refs`` (the errors cached too), its ``times`` of
    every round (:func:`timed_rounds`)."""
    from bench import peer_cache
    from bench.paired import median
    from bench.stroke import boundary_hausdorff, segments_to_region
    from tests.oracles.reference import region_to_shapely

    res = value["results"]
    judge_src = peer_cache.source_digest(boundary_hausdorff, segments_to_region)
    jkey = peer_cache.digest("fontforge-brush-judged", key, sorted(ref_keys.items()),
                             0.05, 0.5, judge_src,
                             peer_cache.file_digest("tests/oracles/reference.py"))
    ferrs = (peer_cache.get("fontforge-brush-judged", jkey) or {}).get("value")
    if ferrs is None:
        ferrs = [boundary_hausdorff(region_to_shapely(segments_to_region(
            res[n]["contours"]), 0.05), refs[n], 0.5) for n in names]
        peer_cache.put("fontforge-brush-judged", jkey, {
            "value": ferrs, "provenance": peer_cache.provenance(prov["peer"])})
    row = {"tool": "FontForge Expand Stroke + Remove Overlap", "setting": "accuracy %g" % acc,
           "ms": median(times["ms"]), "median": median(times["median"]),
           "whole": median(times["process"]), "times": times,
           "points": float(np.mean([res[n]["points"] for n in names])), "errs": ferrs}
    n_int = value["internal_errors"]
    note = ("FontForge, accuracy %g: outlines, points and errors %s; it printed \"Internal "
            "Error\" %s; its times measured in this run, interleaved with morph's (%d rounds)."
            % (acc, peer_cache.measured_note([prov], int(fresh)),
               "once" if n_int == 1 else "%d times" % n_int, len(times["ms"])))
    return row, note


def _parser():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--glyphs", default="A-Z,a-z,0-9")
    ap.add_argument("--nib", default="80,30,30")
    ap.add_argument("--tol", type=float, default=0.5, help="font units")
    ap.add_argument("--ref-tol", type=float, default=0.25, help="font units")
    ap.add_argument("--ff-accuracy", default="1,0.25")
    ap.add_argument("--md", default=str(ROOT / "bench" / "brush_fontforge.md"))
    ap.add_argument("--repeat", type=int, default=9,
                    help="rounds: morph's command, FontForge's worker and morph's in-process "
                         "pass each run this many times, interleaved: the medians and the "
                         "median of the per-round ratios (9: a whole brush command's CPU "
                         "time varies by 25 %% between runs on an idle machine, and the "
                         "verdict is near a ratio of 1)")
    ap.add_argument("--no-write", action="store_true")
    return ap


def main(argv=None):
    from bench.stroke_profile import code_version
    from morph.fonts.brush import ellipse_nib, region_extent
    from morph.parse import cubic_test_font_path

    opt = _parser().parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    t_start = time.perf_counter()
    src = cubic_test_font_path()
    chars = _chars(opt.glyphs)
    nib_spec = tuple(float(v) for v in opt.nib.split(","))
    nib = ellipse_nib(*nib_spec)
    from fontTools.ttLib import TTFont

    cmap = TTFont(str(src)).getBestCmap()
    names = [cmap[ord(c)] for c in chars]
    refs, ref_keys, ref_note = brush_references(src, chars, names, nib, opt.ref_tol)
    version = code_version()
    accs = [float(a) for a in opt.ff_accuracy.split(",")]
    outlines = {acc: run_fontforge(src, names, nib_spec, acc) for acc in accs}
    with tempfile.TemporaryDirectory() as tmp:
        morph, times = timed_rounds(src, chars, names, nib_spec, opt, accs, tmp)
        rows = [_morph_row(morph, src, chars, names, refs, region_extent(nib)[0],
                           Path(tmp) / "brush.otf", opt)]
    from bench.paired import starts_note

    notes = [starts_note(morph["starts"], len(names))]
    for acc in accs:
        row, note = _fontforge_row(*outlines[acc], acc, names, refs, ref_keys, times[acc])
        rows.append(row)
        notes.append(note)
        print(row["tool"], acc, row["ms"], max(row["errs"]), flush=True)
    text = markdown(opt, argv, names, rows, morph, notes, ref_note, version,
                    time.perf_counter() - t_start)
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)
    return 0


def markdown(opt, argv, names, rows, morph, notes, ref_note, version, elapsed):
    """The report."""
    from bench.paired import ratio_cell
    from bench.stroke_profile import shown_args

    nib_spec = tuple(float(v) for v in opt.nib.split(","))
    md = ["# `morph brush` against FontForge's Expand Stroke + Remove Overlap "
          "(bench/brush_fontforge.py)", "",
          "Command: `python -m bench.brush_fontforge%s`; morph and FontForge measured %s "
          "UTC at %s (%.0f s).  Machine: %d CPUs shared with other jobs (load average %s "
          "at the end): CPU times, not wall times.  Source: Noto Sans (CFF), %d glyphs "
          "(%s); nib ellipse %g x %g at %g degrees; morph at --tol %g units; errors against "
          "the Clipper reference (ref-tol %g)."
          % ("".join(" " + a for a in shown_args(argv)),
             time.strftime("%Y-%m-%d %H:%M", time.gmtime()), version, elapsed,
             os.cpu_count() or 1, ", ".join("%.1f" % v for v in os.getloadavg()),
             len(names), opt.glyphs, nib_spec[0], nib_spec[1], nib_spec[2], opt.tol,
             opt.ref_tol), "", TIMES % (opt.repeat, opt.repeat, rows[0]["brush_font"]), "",
          "| tool | setting | in process: mean ms / glyph | in process: median ms / glyph | "
          "whole command ms / glyph | points / glyph | worst error | mean error | "
          "glyphs over 1 unit | morph / FontForge: in process; whole command |",
          "|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        e = r["errs"]
        t = r.get("times")
        md.append("| %s | %s | %.1f | %s | %.1f | %.0f | %.2f (%s) | %.3f | %s | %s |" % (
            r["tool"], r["setting"], r["ms"],
            "(chunks)" if r["median"] is None else "%.1f" % r["median"], r["whole"],
            r["points"], max(e), names[int(np.argmax(e))], np.mean(e),
            ", ".join(n for n, v in zip(names, e) if v > 1.0) or "0",
            "%s; %s" % (ratio_cell(morph["sweep"], t["ms"]),
                        ratio_cell(morph["cmd"], t["process"])) if t else ""))
    md += ["", "morph's points and errors are of the saved font (integer coordinates, read "
           "back), FontForge's of its outlines as it returns them (unrounded).  The "
           "command's last line: `%s`." % morph["line"], "",
           "The Clipper references and FontForge's outlines, points, errors and "
           "\"Internal Error\" counts do not depend on morph's code nor on the machine's "
           "load; they come from the bench cache (`bench/peer_cache.py`, keyed by the font "
           "file's bytes, the glyphs, the nib, the tolerance and the peer's version) when "
           "measured before.  Every time is measured in this run:", "",
           "- Clipper reference: %s." % ref_note] + ["- " + n for n in notes]
    return "\n".join(md) + "\n"


TIMES = (
    "Times, two kinds, each the same for both tools: **in process** = the computation "
    "alone (morph: `morph.fonts.brush._sweep_font`, the sums and the certified export by "
    "the command's chunks, whose glyphs are computed together, so a mean per glyph and "
    "no median: compare it with FontForge's mean; FontForge: Expand Stroke, the outline "
    "added back and Remove Overlap, glyph by glyph); **whole command** = a whole process "
    "divided by the glyphs (morph: `morph brush NotoSans.otf -o OUT.otf --glyphs ... "
    "--jobs 1`, started as after a pip install (a virtual environment's site, bytecode "
    "cached: `bench/pycache.py`), "
    "reading, the sweep, tables, saving, sample image and specimen; FontForge: its worker "
    "process, Python's startup, `import fontforge`, opening the font and converting it "
    "to cubics, the brush, writing the outlines as JSON, saving the font as .otf with "
    "`font.generate`: its whole workflow).  morph and FontForge are timed in the same "
    "run, interleaved: %d rounds, each morph's command, FontForge's worker at every "
    "accuracy, then morph's in-process pass, so that the shared machine's drift hits "
    "both alike; each time is the median of its %d rounds, and **morph / FontForge** is "
    "the median of the per-round ratios (below 1: morph faster).  morph's `brush_font` "
    "in process (reading the source, the sweep, saving the font): %.1f ms / glyph.")


if __name__ == "__main__":
    sys.exit(main())

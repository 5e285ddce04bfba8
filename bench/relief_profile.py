"""Where the milliseconds of a Relief glyph go in process, per phase, and how many
Python calls each phase makes per glyph.

    python -m bench.relief_profile [--tols 4,2,0.5,0.25] [--nib broad|round] [--repeat 5]
                                   [--md bench/relief_profile.md | --no-write]

What is measured is what ``bench/stroke.py`` times in process: the Relief SingleLine
subset (tests/data/relief, 62 glyphs A-Z, a-z, 0-9, every contour an open cubic
path) stroked as the command strokes a chunk (``stroke_many`` of all the glyphs at
the geometry share of ``plan(tol)``), then all loops exported in one
``loops_to_beziers(..., wrap=True)`` call.  The phases are those of
``bench/stroke_profile.py`` (the same timers wrapped round the same functions,
exclusive CPU time, the corner pass sticky); ``Gauss map`` and ``convolution``
there include the skeleton loops' tables and the convolution pieces' chaining.

Per tolerance, for each phase:

- **ms / glyph**: the phase's CPU time (process_time) in a chunk of all 62 glyphs
  divided by them, the median of ``--repeat`` passes after one untimed pass (the
  machine is shared: CPU time, not wall time);
- **ms per added glyph** and **ms per chunk (fixed)**: the same of a chunk of the
  first 31 glyphs gives the line time(n) = fixed + n x added through the two: what
  one more glyph of a chunk costs, and what a chunk costs whatever its glyphs (the
  Python and numpy calls of rounds and steps that run once per chunk);
- **calls / glyph**: the Python-level calls made in the phase (Python functions and
  C functions such as numpy's, the bench's own timers not counted) in the chunk of
  62, per glyph;
- **calls per added glyph** (and **per added piece**, by the skeleton pieces of the
  31 glyphs added): (calls of the 62 - calls of the 31) / 31.  A phase whose every
  step works on arrays holding all the glyphs of a chunk adds no call per glyph (a
  few where a while loop runs one more round); one that loops over glyphs or pieces
  in Python adds calls in proportion.  The two halves are not alike, so a growth
  may be content, not a loop: loops of the second half (g, h, m, n) cross
  themselves at tol 4 and 2, which switches untangle's subdivision, Newton
  refinement and a second round on, and its glyphs need more Newton iterations of
  the convolution's slowest row; a chunk of the 62 glyphs twice makes about the
  calls of one at tol 2 (untangle 6,371 against 6,327), each step working on the
  whole chunk.

Below the table, the innermost morph functions of the CPU time of each phase, from
stack samples taken every millisecond of CPU over the timed passes.
"""

import argparse
import collections
import os
import statistics
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the morph command sets it

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))  # after PYTHONPATH: a checkout named there is measured

from bench.stroke_profile import (ORDER, Clock,  # noqa: E402 - needs sys.path with the repo root
                                  install, shown_args)
from bench.stamp import commit, emit, machine  # noqa: E402 - needs sys.path with the repo root

SUBSET = ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"
NIBS = {"broad": ("ellipse", 90.0, 20.0, 30.0), "round": ("disk", 60.0)}
NIB_NAMES = {"broad": "ellipse 90 x 20 at 30 degrees", "round": "disk of diameter 60"}
#: the phases a stroke_many + loops_to_beziers pass runs (startup, parse of the
#: UFO, font tables, compile, sample are not in it)
SHOWN = [p for p in ORDER if p not in ("startup", "font tables", "compile",
                                       "sample + specimen", "imports (lazy)")]


def _inputs(nib_name):
    from bench.stroke import nib_region
    from morph.fonts.brush import parse_glyph_spec
    from morph.parse.ufo import decomposed_paths, glyph_names_for, load_ufo

    font = load_ufo(SUBSET, lazy=False)
    names = glyph_names_for(font, parse_glyph_spec("A-Z,a-z,0-9"))
    return [decomposed_paths(font, n) for n in names], nib_region(NIBS[nib_name])


def python_calls(fn):
    """``(fn(), the Python-level calls it made)``: Python functions and C functions
    such as numpy's (``sys.setprofile``), a count the machine's load does not
    change."""
    count = [0]

    def prof(frame, event, arg):
        if event in ("call", "c_call"):
            count[0] += 1

    sys.setprofile(prof)
    try:
        out = fn()
    finally:
        sys.setprofile(None)
    return out, count[0]


def _pass(sets, nib, tol):
    from morph.budget import plan
    from morph.export import loops_to_beziers
    from morph.stroke import stroke_many

    geometry, export = plan(tol)[:2]
    regions = stroke_many(sets, nib, geometry)
    return loops_to_beziers([lp for r in regions for lp in r], export, wrap=True)


def timed(clock, sets, nib, tol, repeat):
    """{phase: median CPU s of ``repeat`` passes}, and the stack samples."""
    import signal

    _pass(sets, nib, tol)   # untimed: lazy imports, caches of quadrature nodes
    samples = collections.Counter()

    def handler(sig, frame):
        inner = None
        while frame is not None and inner is None:
            if frame.f_globals.get("__name__", "").startswith("morph"):
                code = frame.f_code
                inner = "%s:%s" % (frame.f_globals["__name__"],
                                   getattr(code, "co_qualname", code.co_name))
            frame = frame.f_back
        samples[(clock.stack[-1], inner or "(outside morph)")] += 1

    signal.signal(signal.SIGPROF, handler)
    signal.setitimer(signal.ITIMER_PROF, 0.001, 0.001)
    try:
        passes = clock.passes(lambda: _pass(sets, nib, tol), repeat)
    finally:
        signal.setitimer(signal.ITIMER_PROF, 0, 0)
    return {p: statistics.median(s.get(p, 0.0) for s in passes) for p in ORDER}, samples


def counted(clock, sets, nib, tol):
    """{phase: Python-level calls} of one pass (the timers' own calls left out)."""
    calls = collections.Counter()
    mine = (__file__, sys.modules["bench.stroke_profile"].__file__)

    def prof(frame, event, arg):
        if event == "call":
            if frame.f_code.co_filename not in mine:
                calls[clock.stack[-1]] += 1
        elif event == "c_call":
            if frame.f_code.co_filename not in mine:
                calls[clock.stack[-1]] += 1

    clock.spent = {}
    clock.last = time.process_time()
    sys.setprofile(prof)
    try:
        _pass(sets, nib, tol)
    finally:
        sys.setprofile(None)
    return calls


def pieces(sets):
    return sum(len(ps) for paths in sets for ps, _ in paths)


def measure(nib_name, tols, repeat):
    sets, nib = _inputs(nib_name)
    clock = Clock()
    install(clock)
    half = sets[:len(sets) // 2]
    out = []
    for tol in tols:
        spent, samples = timed(clock, sets, nib, tol, repeat)
        half_spent, _ = timed(clock, half, nib, tol, repeat)
        full, part = counted(clock, sets, nib, tol), counted(clock, half, nib, tol)
        out.append({"tol": tol, "spent": spent, "half_spent": half_spent, "samples": samples, "calls": full,
                    "half_calls": part, "glyphs": len(sets), "half": len(half),
                    "pieces": pieces(sets), "added_pieces": pieces(sets) - pieces(half)})
        print("tol %g: %.2f ms / glyph, %d calls / glyph" % (
            tol, 1000 * sum(spent.values()) / len(sets),
            sum(full.values()) / len(sets)), flush=True)
    return out


def markdown(nib_name, rows, argline, elapsed, repeat):
    md = ["# Where the ms of a Relief glyph go in process (bench/relief_profile.py)", "",
          "Made by `python -m bench.relief_profile%s` at commit %s on %s UTC, on %s, in "
          "%.0f s.  CPU time (process_time), the median of %d passes; the machine is "
          "shared with other jobs." % (argline, commit(("morph", "bench")),
                                       time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                                       machine(), elapsed, repeat), "",
          "Relief SingleLine subset, %d glyphs (%d skeleton pieces), %s nib (%s), "
          "`stroke_many` + `loops_to_beziers` of all glyphs in one chunk, as "
          "`bench/stroke.py` times them.  See the script's docstring for the columns: "
          "a chunk of n glyphs costs about *fixed* + n x *added*, from the times of the "
          "62 glyphs and of the first 31; on a loaded machine these two carry the noise "
          "of a difference (a small negative value is noise).  The calls are counted, "
          "not timed: they do not depend on the load."
          % (rows[0]["glyphs"], rows[0]["pieces"], nib_name, NIB_NAMES[nib_name]), ""]
    for r in rows:
        md += ["### tol %g" % r["tol"], "",
               "| phase | ms / glyph | ms per added glyph | ms per chunk (fixed) | "
               "calls / glyph | calls per added glyph | calls per added piece |",
               "|---|---|---|---|---|---|---|"]
        for p in SHOWN + ["total"]:
            c = _cells(r, p)
            cells = ["%.2f" % c[0], "%.2f" % c[1], "%.0f" % c[2], "%.0f" % c[3],
                     "%.1f" % c[4], "%.2f" % c[5]]
            if p == "total":
                cells = ["**%s**" % x for x in cells]
            md.append("| %s | %s |" % ("**total**" if p == "total" else p, " | ".join(cells)))
        md.append("")
    for r in rows:
        md += ["", "Innermost morph functions of each phase's CPU time at tol %g (stack "
               "samples every 1 ms of CPU over the %d passes; the phases' largest first, "
               "their 4 largest functions):" % (r["tol"], repeat), ""]
        by = collections.defaultdict(collections.Counter)
        for (phase, where), n in r["samples"].items():
            by[phase][where] += n
        total = max(1, sum(r["samples"].values()))
        for phase, funcs in sorted(by.items(), key=lambda kv: -sum(kv[1].values())):
            share = 100.0 * sum(funcs.values()) / total
            if share < 2:
                continue
            md.append("- %s (%.0f %%): %s" % (phase, share, ", ".join(
                "`%s` %.0f %%" % (f.replace("morph.", ""), 100.0 * n / total)
                for f, n in funcs.most_common(4))))
    return "\n".join(md) + "\n"


def _cells(r, p):
    """(ms / glyph, ms per added glyph, fixed ms per chunk, calls / glyph, calls per
    added glyph, calls per added piece) of phase ``p`` (or the total) of row ``r``:
    a chunk of n glyphs costs about fixed + n x added (from the 62 and the first 31)."""
    keys = SHOWN if p == "total" else [p]
    full = 1000.0 * sum(r["spent"].get(k, 0.0) for k in keys)
    half = 1000.0 * sum(r["half_spent"].get(k, 0.0) for k in keys)
    n, h = r["glyphs"], r["half"]
    added = (full - half) / (n - h)
    calls = sum(r["calls"].get(k, 0) for k in keys)
    half_calls = sum(r["half_calls"].get(k, 0) for k in keys)
    return (full / n, added, full - n * added, calls / n, (calls - half_calls) / (n - h),
            (calls - half_calls) / max(r["added_pieces"], 1))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tols", default="4,2,0.5,0.25")
    ap.add_argument("--nib", default="broad", choices=sorted(NIBS))
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--md", default=str(ROOT / "bench" / "relief_profile.md"))
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args(argv)
    argv = sys.argv[1:] if argv is None else argv
    t0 = time.perf_counter()
    rows = measure(opt.nib, [float(t) for t in opt.tols.split(",")], opt.repeat)
    text = markdown(opt.nib, rows, "".join(" " + a for a in shown_args(argv)),
                    time.perf_counter() - t0, opt.repeat)
    return emit(text, opt)


if __name__ == "__main__":
    sys.exit(main())

"""Where a glyph's milliseconds go in ``morph stroke`` and ``morph brush``, per phase.

    python -m bench.stroke_profile [--runs stroke:relief,stroke:hanzi-300,...]
                                   [--repeat 3] [--md bench/stroke_profile.md | --no-write]
                                   [--explain-other]

Each run is the command itself (``morph.cli.main`` with ``--jobs 1``), in a fresh
Python process (``python -m bench.stroke_profile --worker``), with timers wrapped
round the functions that start each phase (:data:`PHASES`).  A phase's time is
*exclusive*: the CPU time (``time.process_time``) spent in it and not in a phase it
calls; the ``corner pass`` is sticky: everything under the second and later
trimming rounds of a sum (:func:`morph.minkowski._sum`) and under the corner pass's
convolution counts there.  Imports done during the run (fontTools, ufo2ft, Pillow
... are imported lazily) count as ``imports (lazy)``; ``startup`` is the process's
CPU time before the command starts (interpreter and ``import morph.cli``, from
``resource.getrusage``).  ``packing + rounds`` is the batched sums' own work:
a chunk's glyphs packed into one sum and split again, the result regions checked,
the trimming rounds' bookkeeping; ``trim: rest`` the trimming's own work between
its parts.  The phases add up to the process's CPU time; the rest, not inside any
timed function, is ``other`` (the CLI, the job loop, the sample text's choice);
``--explain-other`` samples the stacks of that time and lists them, to find what
the phase map misses.  A timer costs about a microsecond a call, far below the
phases' times.

The timers only wrap functions (every module attribute that is the function, so
``from .x import f`` call sites are timed too; names that a version of the code
lacks, and modules it lacks, are skipped); no code of morph is changed.
Runs (``--runs``, comma separated ``command:set``):

- ``stroke:relief``: the whole Relief SingleLine UFO (``relief-singleline`` in the
  shared data folder, else ``tests/data/relief``'s subset), the default nib, to .otf;
- ``stroke:hershey-sans``, ``stroke:hershey-script``, ``stroke:hanzi-300``: the
  skeleton sets of :mod:`bench.skeletons` (fetched at bench time), to .otf;
- ``brush:noto``: the bundled Noto Sans (.ttf, the command's default font), its
  Latin letters and digits, the default nib.

Every run is repeated ``--repeat`` times (fresh processes, after one untimed run that
fills a private bytecode cache; a virtual environment's site: :mod:`bench.pycache`, as
a pip install would have it) and the
table shows the median of each phase; the machine is shared, so CPU time and not wall
time.
"""

# the timed worker process (--worker) imports only what it needs: the modules this
# file imports count in its "startup", which is the command's own
import json
import os
import resource
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]

#: (phase, "module:qualname") pairs: the function's time (exclusive of the phases it
#: calls) counts for the phase.  Order is the report's.
PHASES = [
    ("parse", ["morph.parse.ufo:load_ufo", "morph.parse.ufo:decomposed_paths",
               "morph.parse.ufo:glyph_paths", "morph.fonts.stroke:stroke_plan",
               "morph.fonts.stroke:_stroke_work", "morph.fonts.brush:_source_regions",
               "morph.fonts.brush:open_source", "morph.fonts.brush:_brush_plan",
               "morph.stroke:_loops_and_dots", "morph.stroke:_loops_and_dots_many",
               "morph.fonts.stream:SkeletonSource.shell_font",
               "morph.fonts.stream:SkeletonSource.__getitem__"]),
    ("operand checks", ["morph.minkowski:check_operand", "morph.operands:check_operand",
                        "morph.minkowski:check_operands", "morph.operands:check_operands",
                        "morph.limits:check_tolerance"]),
    ("Gauss map", ["morph.convolve:gauss_pair_of", "morph.gauss:gauss_maps",
                   "morph.convolve:with_pair_table", "morph.convolve:crossing_rows"]),
    ("convolution", ["morph.convolve:convolution", "morph.convolve:chain"]),
    ("trim: flatten", ["morph.trim.flatten:tag_loops"]),
    ("trim: Clipper", ["morph.trim.topology:packed_filled_rings",
                       "morph.trim.topology:drop_slivers"]),
    ("trim: holes", ["morph.minkowski:_HoleTest.__call__", "morph.minkowski:_HoleTest.many",
                     "morph.trim:_filled_holes", "morph.trim.topology:fill_holes"]),
    ("trim: lift", ["morph.trim.lift:lift_rings"]),
    ("trim: untangle", ["morph.trim.untangle:merge_lenses", "morph.trim.untangle:untangle",
                        "morph.trim:_near_ring_pairs"]),
    ("trim: rest", ["morph.minkowski:_trimmed", "morph.trim:boundary"]),
    ("corner pass", ["morph.minkowski:_tip_tolerances"]),
    ("packing + rounds", ["morph.stroke:stroke_many", "morph.minkowski:minkowski_sums",
                          "morph.minkowski:_packed_sums", "morph.minkowski:_sum",
                          "morph.packing:Packing.__init__",
                          "morph.packing:Packing.split", "morph.packing:Packing.slot_of",
                          "morph.limits:fits_precision"]),
    ("export fit", ["morph.export:loops_to_beziers", "morph.export:loops_to_quadratics"]),
    ("certificate", ["morph.export:_reparams", "morph.export:_certify_many",
                     "morph.export.certify:_reparams", "morph.export.certify:certify_many",
                     "morph.export.certify:certify_batch"]),
    ("font tables", ["morph.fonts.tables:contours_from_regions",
                     "morph.fonts.stroke:_write_strokes", "morph.fonts.stroke:_open_copy",
                     "morph.fonts.stroke:_move_furniture", "morph.fonts.ufo_tables:grow_win_metrics",
                     "morph.fonts.brush:_store_outlines", "morph.fonts.stroke:_finish_shells",
                     "morph.fonts.stroke:_StreamedGlyphs.add",
                     "morph.fonts.stroke:_streamed_chunk", "morph.fonts.ufo_tables:widen_extent",
                     "morph.fonts.stream:UfoGlyphWriter.write"]),
    ("compile", ["morph.fonts.stroke:_save", "morph.fonts.tables:save_font",
                 "morph.fonts.tables:_CFFOutlines.saving",
                 "morph.fonts.tables:_TrueTypeOutlines.saving",
                 "morph.fonts.stream:compile_outline", "morph.fonts.stream:compile_outlines",
                 "morph.fonts.stroke:_StreamedGlyphs.finish"]),
    ("sample + specimen", ["morph.fonts.specimen:write_sample_image",
                           "morph.fonts.specimen:write_specimen"]),
]
STICKY = "corner pass"
ORDER = (["startup"] + [p for p, _ in PHASES] + ["imports (lazy)", "other"])
TRIM = ("trim: flatten", "trim: Clipper", "trim: holes", "trim: lift", "trim: untangle",
        "trim: rest")


# =========================================================================== timers

class Clock:
    """Exclusive CPU time per phase, with a stack of the phases entered."""

    def __init__(self):
        self.spent = {}
        self.stack = ["other"]
        self.last = time.process_time()
        self.sum_round = []   # trimming rounds of the _sum calls in progress

    def _charge(self):
        now = time.process_time()
        self.spent[self.stack[-1]] = self.spent.get(self.stack[-1], 0.0) + now - self.last
        self.last = now

    def enter(self, phase):
        self._charge()
        if STICKY in self.stack:
            phase = STICKY
        self.stack.append(phase)

    def leave(self):
        self._charge()
        self.stack.pop()

    def passes(self, work, repeat):
        """[{phase: CPU s}] of ``repeat`` calls of ``work()``, one dict a call."""
        out = []
        for _ in range(repeat):
            self.spent = {}
            self.last = time.process_time()
            work()
            self._charge()
            out.append(dict(self.spent))
        return out


def _wrap(clock, phase, func):
    import functools

    @functools.wraps(func)
    def timed(*args, **kwargs):
        clock.enter(phase)
        try:
            return func(*args, **kwargs)
        finally:
            clock.leave()

    timed.__wrapped_phase__ = phase
    return timed


def _replace_everywhere(orig, new):
    """Every attribute of a loaded morph module that is ``orig`` becomes ``new``."""
    for name, mod in list(sys.modules.items()):
        if not name.startswith("morph") or mod is None:
            continue
        for attr, val in list(vars(mod).items()):
            if val is orig:
                setattr(mod, attr, new)


def install(clock):
    import importlib

    for phase, targets in PHASES:
        for target in targets:
            modname, qual = target.split(":")
            try:
                mod = importlib.import_module(modname)
            except ImportError:  # a module of another version of the code
                continue
            owner = mod
            *path, attr = qual.split(".")
            for p in path:
                owner = getattr(owner, p)
            orig = getattr(owner, attr, None)
            if orig is None:  # a function of another version of the code
                continue
            new = _wrap(clock, phase, orig)
            setattr(owner, attr, new)
            if owner is mod:
                _replace_everywhere(orig, new)
    # the corner pass: the second and later trimming rounds of a sum, and the
    # convolution of the rows it refines (``rows=`` given)
    import morph.convolve as cv
    import morph.minkowski as mk

    sum_, trimmed, conv = mk._sum, mk._trimmed, mk.convolution

    def timed_sum(*a, **k):
        clock.sum_round.append(0)
        try:
            return sum_(*a, **k)
        finally:
            clock.sum_round.pop()

    def timed_trimmed(*a, **k):
        later = bool(clock.sum_round) and clock.sum_round[-1] > 0
        if clock.sum_round:
            clock.sum_round[-1] += 1
        if not later:
            return trimmed(*a, **k)
        clock.enter(STICKY)
        try:
            return trimmed(*a, **k)
        finally:
            clock.leave()

    def timed_conv(*a, **k):
        if k.get("rows") is None:
            return conv(*a, **k)
        clock.enter(STICKY)
        try:
            return conv(*a, **k)
        finally:
            clock.leave()

    mk._sum, mk._trimmed, mk.convolution = timed_sum, timed_trimmed, timed_conv
    del cv
    # imports first done during the run
    import builtins

    real_import = builtins.__import__

    def timed_import(name, globals=None, locals=None, fromlist=(), level=0):
        if level == 0 and name in sys.modules:
            return real_import(name, globals, locals, fromlist, level)
        clock.enter("imports (lazy)")
        try:
            return real_import(name, globals, locals, fromlist, level)
        finally:
            clock.leave()

    builtins.__import__ = timed_import


# =========================================================================== runs

def relief_ufo():
    """The whole Relief SingleLine UFO of the shared data folder, else the subset in
    tests/data."""
    from bench.skeletons import shared_relief

    return shared_relief() or ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"


def run_args(run, out_dir):
    """(CLI arguments, glyphs description) of a ``command:set`` run."""
    cmd, what = run.split(":")
    if cmd == "stroke":
        if what == "relief":
            src = relief_ufo()
        else:
            from bench.skeletons import skeleton_ufo

            src = skeleton_ufo(what)
        return ["stroke", str(src), "-o", str(Path(out_dir) / "out.otf"), "--force",
                "--jobs", "1"], what
    if cmd == "brush":
        return ["brush", "-o", str(Path(out_dir) / "out.ttf"), "--force", "--jobs", "1",
                "--glyphs", "A-Z,a-z,0-9"], "Noto Sans A-Z, a-z, 0-9"
    raise SystemExit("unknown run %r" % run)


def _sample_other(clock, interval=0.002):
    """Sample the stack every ``interval`` s of CPU while the clock is in ``other``:
    a Counter of the innermost three morph functions of each sample (innermost
    first), to find what the phase map misses (``--explain-other``)."""
    import collections
    import signal

    counts = collections.Counter()

    def handler(sig, frame):
        if clock.stack[-1] != "other":
            return
        names = []
        while frame is not None and len(names) < 3:
            if frame.f_globals.get("__name__", "").startswith("morph"):
                code = frame.f_code
                names.append("%s:%s" % (frame.f_globals["__name__"],
                                         getattr(code, "co_qualname", code.co_name)))
            frame = frame.f_back
        counts[" < ".join(names) or "(no morph function)"] += 1

    signal.signal(signal.SIGPROF, handler)
    signal.setitimer(signal.ITIMER_PROF, interval, interval)
    return counts


def worker(args_json, explain=False):
    """One run in this (fresh) process; prints the phases as JSON (with ``explain``,
    also the sampled stacks of ``other``: :func:`_sample_other`)."""
    start = resource.getrusage(resource.RUSAGE_SELF)
    startup_cpu = start.ru_utime + start.ru_stime
    c0 = time.process_time()
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import morph.cli as cli  # noqa: F401 - the command's own imports are startup

    startup_cpu += time.process_time() - c0
    args = json.loads(args_json)
    clock = Clock()
    install(clock)
    import io
    from contextlib import redirect_stdout

    clock.last = time.process_time()
    samples = _sample_other(clock) if explain else None
    out = io.StringIO()
    with redirect_stdout(out):
        try:
            cli.main(args, standalone_mode=False)
        except SystemExit:
            pass
    clock._charge()
    if samples is not None:
        import signal

        signal.setitimer(signal.ITIMER_PROF, 0, 0)
    spent = dict(clock.spent)
    spent["startup"] = startup_cpu
    end = resource.getrusage(resource.RUSAGE_SELF)
    text = out.getvalue()
    json.dump({"spent": spent, "total": end.ru_utime + end.ru_stime,
               "maxrss_kb": end.ru_maxrss, "message": text.strip().splitlines()[-1:],
               "other_samples": samples.most_common(25) if samples is not None else None},
              sys.stdout)


def glyph_count(message):
    import re

    m = re.search(r"\((\d+) glyphs? (?:stroked|brushed|swept)", message)
    if m:
        return int(m.group(1))
    m = re.search(r"\((\d+) glyphs?", message)
    return int(m.group(1)) if m else 0


def measure(run, repeat, explain=False):
    import statistics
    import subprocess
    import tempfile

    from bench.pycache import cached_env, installed_python

    with tempfile.TemporaryDirectory() as tmp:
        args, what = run_args(run, tmp)
        results = []
        env = cached_env("stroke-profile-pycache-", OPENBLAS_NUM_THREADS="1")
        for k in range(repeat + 1):     # run 0 fills the bytecode cache and is not counted
            proc = subprocess.run([installed_python(), "-m", "bench.stroke_profile", "--worker",
                                   json.dumps(args)] + (["--explain-other"] if explain else []),
                                  capture_output=True, text=True, cwd=tmp, env=env)
            if proc.returncode != 0:
                raise SystemExit("run %s failed:\n%s" % (run, proc.stderr[-3000:]))
            if not k:
                continue
            results.append(json.loads(proc.stdout.strip().splitlines()[-1]))
            print(run, "%.2f s CPU" % results[-1]["total"], results[-1]["message"], flush=True)
    msg = results[0]["message"][0] if results[0]["message"] else ""
    n = glyph_count(msg)
    phases = {p: statistics.median(r["spent"].get(p, 0.0) for r in results) for p in ORDER}
    return {"run": run, "what": what, "glyphs": n, "message": msg, "phases": phases,
            "total": statistics.median(r["total"] for r in results),
            "maxrss_mb": max(r["maxrss_kb"] for r in results) / 1024.0,
            "repeat": repeat, "other_samples": results[0].get("other_samples")}


def code_version():
    import subprocess

    def git(*args):
        return subprocess.run(["git", "-C", str(ROOT)] + list(args), capture_output=True,
                              text=True).stdout.strip()

    import morph

    if Path(morph.__file__).resolve().parents[1] != ROOT:  # PYTHONPATH put another first
        return "morph/ of %s" % os.environ.get("MORPH_CODE_LABEL", "another checkout")
    head = git("rev-parse", "--short", "HEAD")
    dirty = git("status", "--porcelain", "--", "morph")
    return "commit %s%s" % (head or "?", " + uncommitted changes in morph/" if dirty else "")


def measured_line(argline, elapsed, rows, version=None):
    """The report's first line; ``version``: the code measured (:func:`code_version`
    as the runs began; None: now)."""
    return ("Command: `python -m bench.stroke_profile%s`; measured %s UTC at %s (%.0f s). "
            "Machine: %d CPUs shared with other jobs (load average %s at the end), so CPU "
            "time (process_time), the median of %d fresh processes per run, not wall time."
            % (argline, time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
               version or code_version(), elapsed, os.cpu_count() or 1,
               ", ".join("%.1f" % v for v in os.getloadavg()),
               rows[0]["repeat"] if rows else 0))


def markdown(rows, argline, elapsed, measured=None):
    md = ["# Where the milliseconds of a glyph go (bench/stroke_profile.py)", "",
          measured or measured_line(argline, elapsed, rows), "",
          "Each column is one whole command (`--jobs 1`, .otf output for stroke, .ttf for "
          "brush), ms of CPU per glyph written, by phase (exclusive times: a phase's own "
          "time, not that of the phases it calls; see the script's docstring for which "
          "functions start each phase).", ""]
    head = "| phase | " + " | ".join("%s %s (%d glyphs)" % (r["run"].split(":")[0], r["what"],
                                                             r["glyphs"]) for r in rows) + " |"
    md += [head, "|---|" + "---|" * len(rows)]
    for p in ORDER:
        cells = []
        for r in rows:
            ms = 1000.0 * r["phases"][p] / max(1, r["glyphs"])
            share = 100.0 * r["phases"][p] / max(r["total"], 1e-9)
            cells.append("%.2f (%.0f %%)" % (ms, share))
        md.append("| %s | %s |" % (p, " | ".join(cells)))
    for label, keys in (("of which trimming", TRIM),):
        md.append("| **%s** | %s |" % (label, " | ".join(
            "**%.2f**" % (1000.0 * sum(r["phases"][k] for k in keys) / max(1, r["glyphs"]))
            for r in rows)))
    md.append("| **whole process** | %s |" % " | ".join(
        "**%.2f** (%.1f s)" % (1000.0 * r["total"] / max(1, r["glyphs"]), r["total"])
        for r in rows))
    md.append("| peak RSS MB | %s |" % " | ".join("%.0f" % r["maxrss_mb"] for r in rows))
    md += ["", "The commands' own lines:", ""] + ["- %s: `%s`" % (r["run"], r["message"])
                                                  for r in rows]
    md += other_samples_md(rows)
    return "\n".join(md) + "\n"


def other_samples_md(rows):
    """With ``--explain-other``: the innermost morph functions (and two callers) of
    the stack samples taken while the clock was in ``other``, per run (the first
    process of each)."""
    md = []
    for r in rows:
        samples = r.get("other_samples")
        if not samples:
            continue
        total = sum(n for _, n in samples)
        md += ["", "`other` of %s, sampled every 2 ms of CPU (%d samples; innermost first):"
               % (r["run"], total), ""]
        md += ["- %.0f %%: `%s`" % (100.0 * n / total, where) for where, n in samples[:12]]
    return md


def shown_args(argv, outputs=("--md", "--json", "--sets-md", "--before", "--keep")):
    """The command-line arguments without the output-file options (their paths are
    the machine's, not the measurement's)."""
    out, skip = [], False
    for a in argv:
        if skip:
            skip = False
        elif a in outputs:
            skip = True
        elif not any(a.startswith(o + "=") for o in outputs):
            out.append(a)
    return out


def compare(rows, before, label, path):
    """A table of the whole-process ms per glyph and of each phase, earlier and now."""
    old = {r["run"]: r for r in before}
    both = [(old[r["run"]], r) for r in rows if r["run"] in old]
    if not both:
        return ""
    md = ["", "## Against %s (`%s`, measured the same way)" % (label, path), "",
          "ms of CPU per glyph, then -> now.", "",
          "| phase | " + " | ".join("%s %s" % tuple(r["run"].split(":")) for _, r in both)
          + " |", "|---|" + "---|" * len(both)]
    for p in ORDER + ["whole process"]:
        cells = []
        for b, a in both:
            def ms(r):
                v = r["total"] if p == "whole process" else r["phases"].get(p, 0.0)
                return 1000.0 * v / max(1, r["glyphs"])
            cells.append("%.2f -> %.2f" % (ms(b), ms(a)))
        md.append("| %s | %s |" % (p, " | ".join(cells)))
    return "\n".join(md) + "\n"


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if argv[:1] == ["--worker"]:   # a timed run: no argument parser imported
        return worker(argv[1], "--explain-other" in argv[2:])
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--worker")
    ap.add_argument("--explain-other", action="store_true",
                    help="sample the stacks of the time no phase holds and list them")
    ap.add_argument("--runs", default="stroke:relief,stroke:hershey-sans,stroke:hershey-script,"
                                      "stroke:hanzi-300,brush:noto")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke_profile.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--json", help="also write the measured phases here (for comparisons)")
    ap.add_argument("--before", default=str(ROOT / "bench" / "stroke_profile_base.json"),
                    help="phases measured earlier (--json of another run), shown beside")
    ap.add_argument("--before-label", default="the base commit 72a07e6")
    ap.add_argument("--from-json", help="report the phases of an earlier run's --json "
                                        "instead of measuring")
    opt = ap.parse_args(argv)
    if opt.worker:
        return worker(opt.worker, opt.explain_other)
    argline = "".join(" " + a for a in shown_args(argv))
    t0 = time.perf_counter()
    if opt.from_json:   # a report of phases measured before (a --json of a run)
        saved = json.loads(Path(opt.from_json).read_text())
        rows, measured = saved["rows"], saved["measured"]
        measured += "  This report: `python -m bench.stroke_profile%s`." % argline
    else:
        version = code_version()    # the code measured: a commit made meanwhile is not
        rows = [measure(run, opt.repeat, opt.explain_other) for run in opt.runs.split(",")]
        measured = measured_line(argline, time.perf_counter() - t0, rows, version)
    text = markdown(rows, argline, 0.0, measured)
    if opt.before and os.path.exists(opt.before):
        before = json.loads(Path(opt.before).read_text())
        text += compare(rows, before["rows"] if isinstance(before, dict) else before,
                        opt.before_label, os.path.relpath(opt.before, ROOT))
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)
    if opt.json:
        Path(opt.json).write_text(json.dumps({"measured": measured, "rows": rows}, indent=1))
    return 0


if __name__ == "__main__":
    sys.exit(main())

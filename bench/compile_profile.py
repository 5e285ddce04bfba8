"""Where the font compile of ``morph stroke`` spends its time, by part, for a source
with kerning, groups, anchors and composites (Relief SingleLine): compiled by morph
(:mod:`morph.fonts.tables_static`, the command's way for such a source when
ufo2ft's feature writers add nothing) and by ufo2ft (the source read by ufoLib2).

    python -m bench.compile_profile [--repeat 3] [--ufo SRC.ufo] [--kind .otf .ttf]
                                    [--md bench/compile_profile.md | --no-write]

Each run is ``morph stroke SRC -o OUT --jobs 1`` in a fresh process (the command
itself, ``morph.cli.main``), the ufo2ft one with the source opened by ufoLib2
(:class:`morph.fonts.stream.SkeletonSource` without ``light``).  Timers wrap the
functions that start each part (:data:`PARTS`, exclusive CPU time as in
:mod:`bench.stroke_profile`, whose clock this uses); imports first done during the
compile count as ``imports`` (ufo2ft and ufoLib2 apart); ``tx`` is the
subroutinizer's child process (its CPU from the kernel's child accounting).
``compile, rest`` is the compile's own time outside the timed parts (the tables
built from the font info, the glyph order, cmap, OS/2...).  ``before the compile``
is the rest of the process (startup, reading, strokes, sample image), shown for
scale.  The median of ``--repeat`` runs after one untimed run (bytecode cache).
For each output kind (``--kind``, a table each) the report says whether morph
compiled the font itself or left it to ufo2ft, and why
(:func:`morph.fonts.tables_static.left_to_ufo2ft`'s reason).
"""

import argparse
import json
import os
import resource
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

from bench.stroke_profile import Clock, _wrap, code_version, relief_ufo

ROOT = Path(__file__).resolve().parents[1]

#: (part, "module:qualname" of the functions that start it)
PARTS = [
    ("feature writers (ufo2ft) / their check (morph)", [
        "ufo2ft.featureWriters.baseFeatureWriter:BaseFeatureWriter.write",
        "morph.fonts.tables_static:left_to_ufo2ft", "morph.fonts.kern_static:KernWriter.write",
        "morph.fonts.mark_static:MarkWriter.write"]),
    ("ufo2ft filters (preprocess)", ["ufo2ft._compilers.baseCompiler:BaseCompiler.preprocess"]),
    ("glyph programs (composites decomposed)", [
        "morph.fonts.stored:StoredCFF.compileGlyphs", "morph.fonts.stored:StoredGlyf.compileGlyphs",
        "morph.fonts.tables_static:_Compiler._cff_programs",
        "morph.fonts.tables_static:_Compiler._glyf_glyphs"]),
    ("feaLib build (GSUB, GPOS, GDEF)", [
        "fontTools.feaLib.builder:addOpenTypeFeaturesFromString",
        "fontTools.feaLib.builder:addOpenTypeFeatures"]),
    ("subroutinizer (this process)", ["cffsubr:subroutinize", "cffsubr:_tx_subroutinize"]),
    ("production names (ufo2ft's reload)", [
        "ufo2ft.postProcessor:PostProcessor.process_glyph_names"]),
    ("save", ["fontTools.ttLib.ttFont:TTFont.save"]),
]
COMPILE = "compile, rest"
ORDER = ([p for p, _ in PARTS] + ["imports: ufo2ft", "imports: ufoLib2", "imports: other",
                                   COMPILE, "tx (child process)"])


def _install(clock, inside):
    """Timers round :data:`PARTS` (every module attribute that is the function,
    so that ``from x import f`` call sites are timed too) and round imports first
    done inside the compile (``inside()``)."""
    import builtins

    for part, targets in PARTS:
        for target in targets:
            modname, qual = target.split(":")
            mod = sys.modules.get(modname)   # a module this way has not loaded is not run
            if mod is None:
                continue
            owner = mod
            *path, attr = qual.split(".")
            for p in path:
                owner = getattr(owner, p)
            orig = getattr(owner, attr, None)
            if orig is None:
                continue
            new = _wrap(clock, part, orig)
            setattr(owner, attr, new)
            for m in list(sys.modules.values()):
                if m is not None and vars(m).get(attr) is orig:
                    setattr(m, attr, new)
    real_import = builtins.__import__

    def timed_import(name, globals=None, locals=None, fromlist=(), level=0):
        if not inside() or (level == 0 and name in sys.modules):
            return real_import(name, globals, locals, fromlist, level)
        top = name.split(".")[0] if level == 0 else ""
        clock.enter("imports: " + (top if top in ("ufo2ft", "ufoLib2") else "other"))
        try:
            return real_import(name, globals, locals, fromlist, level)
        finally:
            clock.leave()

    builtins.__import__ = timed_import


#: modules each way imports, loaded (and timed) before the command so that the
#: timers can wrap them: by import part
PRELOAD = {"morph": [("imports: other", ["fontTools.feaLib.builder", "cffsubr",
                                         "fontTools.ttLib.ttFont", "morph.fonts.kern_static",
                                         "morph.fonts.mark_static",
                                         "morph.fonts.glyf_static"])],
           "ufo2ft": [("imports: other", ["fontTools.feaLib.builder", "cffsubr",
                                          "fontTools.ttLib.ttFont"]),
                      ("imports: ufoLib2", ["ufoLib2"]),
                      ("imports: ufo2ft", ["ufo2ft", "ufo2ft.featureWriters",
                                           "ufo2ft.postProcessor", "morph.fonts.stored"])]}


def _preload(clock, way):
    import importlib

    for part, names in PRELOAD[way]:
        t = time.process_time()
        for name in names:
            importlib.import_module(name)
        clock.spent[part] = clock.spent.get(part, 0.0) + time.process_time() - t


def _timed_finish(clock, state, finish):
    """``_StreamedGlyphs.finish`` (the compile and save) timed as the compile, with
    the CPU of its child processes (``tx``)."""
    def timed(self, *a, **k):
        state["in"] = True
        children = resource.getrusage(resource.RUSAGE_CHILDREN)
        clock.enter(COMPILE)
        try:
            return finish(self, *a, **k)
        finally:
            clock.leave()
            state["in"] = False
            end = resource.getrusage(resource.RUSAGE_CHILDREN)
            clock.spent["tx (child process)"] = (end.ru_utime - children.ru_utime
                                                 + end.ru_stime - children.ru_stime)
    return timed


def _record_reason(state):
    """``state["way"]``: how the light font was compiled, set when
    ``left_to_ufo2ft`` answers."""
    from morph.fonts import tables_static

    decide = tables_static.left_to_ufo2ft

    def recorded(*args, **kwargs):
        reason, writers = decide(*args, **kwargs)
        state["way"] = ("morph (no ufo2ft)" if reason is None
                        else "left to ufo2ft: %s" % reason)
        return reason, writers

    tables_static.left_to_ufo2ft = recorded


def worker(args):
    """One run in this fresh process; prints its parts as JSON."""
    import importlib

    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import morph.cli as cli
    from morph.fonts import stream
    from morph.fonts import stroke as fs

    importlib.import_module("morph.fonts.tables_static")   # a module the timers wrap

    clock = Clock()
    _preload(clock, args["way"])
    if args["way"] == "ufo2ft":
        class Heavy(stream.SkeletonSource):
            def __init__(self, src, light=False):
                super().__init__(src, light=False)

        stream.SkeletonSource = Heavy
    state = {"in": False, "way": "ufo2ft (the source read by ufoLib2)"}
    fs._StreamedGlyphs.finish = _timed_finish(clock, state, fs._StreamedGlyphs.finish)
    _install(clock, lambda: state["in"])
    _record_reason(state)
    import io
    from contextlib import redirect_stdout

    out = io.StringIO()
    clock.last = time.process_time()
    with redirect_stdout(out):
        try:
            cli.main(["stroke", args["ufo"], "-o", args["out"], "--force", "--jobs", "1"],
                     standalone_mode=False)
        except SystemExit:
            pass
    clock._charge()
    spent = {k: v for k, v in clock.spent.items() if k != "other"}
    start = resource.getrusage(resource.RUSAGE_SELF)
    json.dump({"spent": spent, "total": start.ru_utime + start.ru_stime, "way": state["way"],
               "message": out.getvalue().strip().splitlines()[-1][:300]}, sys.stdout)


def measure(way, ufo, kind, repeat):
    from bench.pycache import cached_env

    env = cached_env("compile-profile-pycache-", OPENBLAS_NUM_THREADS="1")
    results = []
    with tempfile.TemporaryDirectory() as tmp:
        args = {"way": way, "ufo": str(ufo), "out": str(Path(tmp) / ("out" + kind))}
        for k in range(repeat + 1):
            proc = subprocess.run([sys.executable, "-m", "bench.compile_profile", "--worker",
                                   json.dumps(args)], capture_output=True, text=True,
                                  cwd=tmp, env=env)
            if proc.returncode != 0:
                raise SystemExit("%s failed:\n%s" % (way, proc.stderr[-3000:]))
            if k:
                results.append(json.loads(proc.stdout.strip().splitlines()[-1]))
                print(way, "%.2f s CPU" % results[-1]["total"], flush=True)
    parts = {p: statistics.median(r["spent"].get(p, 0.0) for r in results) for p in ORDER}
    total = statistics.median(r["total"] for r in results)
    return {"parts": parts, "total": total, "message": results[0]["message"],
            "way": results[0]["way"]}


def markdown(opt, ufo, by_kind, elapsed):
    lines = ["# Where the font compile's time goes (bench/compile_profile.py)", "",
             "Command: `python -m bench.compile_profile --repeat %d --kind %s`; measured %s "
             "UTC at %s (%.0f s).  Source: %s.  Machine: %d CPUs shared with other jobs "
             "(load average %s at the end): CPU time, the median of %d fresh processes."
             % (opt.repeat, " ".join(opt.kind), time.strftime("%Y-%m-%d %H:%M", time.gmtime()),
                code_version(), elapsed, Path(ufo).name, os.cpu_count() or 1,
                ", ".join("%.1f" % v for v in os.getloadavg()), opt.repeat)]
    for kind, rows in by_kind.items():
        lines += ["", "## %s" % kind, ""] + _table(kind, rows)
    return "\n".join(lines) + "\n"


def _table(kind, rows):
    ways = list(rows)
    lines = ["ms of CPU of the whole command (`morph stroke SRC -o OUT%s --jobs 1`), "
             "by part of the compile (see the script's docstring); compiled by: %s."
             % (kind, "; ".join("%s way, %s" % (w, rows[w]["way"]) for w in ways)), "",
             "| part | " + " | ".join(ways) + " |", "|---|" + "---|" * len(ways)]
    for p in ORDER:
        lines.append("| %s | " % p + " | ".join(
            "%.0f" % (1000 * rows[w]["parts"][p]) for w in ways) + " |")
    comp = {w: sum(v for k, v in rows[w]["parts"].items() if k != "tx (child process)")
            for w in ways}
    lines.append("| **the compile (this process)** | " + " | ".join(
        "**%.0f**" % (1000 * comp[w]) for w in ways) + " |")
    lines.append("| before the compile | " + " | ".join(
        "%.0f" % (1000 * (rows[w]["total"] - comp[w])) for w in ways) + " |")
    lines.append("| **whole process (this process)** | " + " | ".join(
        "**%.0f**" % (1000 * rows[w]["total"]) for w in ways) + " |")
    lines += ["", "The command's line (morph): `%s`" % rows[ways[0]]["message"]]
    return lines


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--worker")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--ufo", default=None, help="default: Relief SingleLine")
    ap.add_argument("--kind", nargs="+", default=[".otf", ".ttf"], choices=(".otf", ".ttf"))
    ap.add_argument("--md", default=str(ROOT / "bench" / "compile_profile.md"))
    ap.add_argument("--no-write", action="store_true")
    opt = ap.parse_args()
    if opt.worker:
        worker(json.loads(opt.worker))
        return
    ufo = Path(opt.ufo).resolve() if opt.ufo else relief_ufo()
    t0 = time.time()
    by_kind = {kind: {"morph": measure("morph", ufo, kind, opt.repeat),
                      "ufo2ft": measure("ufo2ft", ufo, kind, opt.repeat)}
               for kind in opt.kind}
    text = markdown(opt, ufo, by_kind, time.time() - t0)
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)


if __name__ == "__main__":
    main()

"""The frame commands' CPU time: whole processes, and where a process spends it.

    python bench/frames_profile.py                      # 7 runs of each command
    python bench/frames_profile.py --against ../other   # alternated with another checkout
    python bench/frames_profile.py --phases             # CPU of each phase, in one process
    python bench/frames_profile.py --flattening         # what sharing flattenings would give

The commands are the bundled morph and the README's glyph morph,

    morph svg morph/data/bird.svg morph/data/butterfly.svg --frames 10
    morph glyph T M --frames 10

each into a fresh temporary folder.  A process's CPU is its user + system time from
rusage; it runs with bytecode cached in a private folder (as after a pip install) and
again without bytecode (PYTHONDONTWRITEBYTECODE, as this machine's shells set it:
every module compiled again).  With ``--against ROOT`` the same commands of the
checkout at ROOT (its own ``morph`` package) run in turn with this one's, run by run,
so that a drift of a shared machine's speed touches both; the median of the run-by-run
ratios is reported.  ``--phases`` times the phases of the svg command inside one warm
process (imports done): the sums' convolution and trimming, the SVG export, the PNG
and animation writers.  ``--flattening`` measures what the trimming of the packed
frames flattens (the largest phase): the polyline vertices of the frames' convolution
pieces flattened uniformly at the trimming's three levels, against what one subdivision
shared by every frame would make (each blended piece cut as finely as its finest
frame needs: a bound that holds for every a), and the trimming's own vertices by
the pieces' pair type (Fig. 20; type 3 never reaches the boundary).  Output: markdown
tables on stdout; CPU time only (a shared machine's wall time says little).
"""

import argparse
import functools
import importlib
import os
import resource
import shutil
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
DATA = ROOT / "morph" / "data"
COMMANDS = {
    "svg bird butterfly --frames 10": ["svg", str(DATA / "bird.svg"), str(DATA / "butterfly.svg"),
                                       "--frames", "10"],
    "glyph T M --frames 10": ["glyph", "T", "M", "--frames", "10"],
}
#: (module, function) timed by --phases, in the order shown
PHASES = [("morph.minkowski", "_first_round", "convolution (first round)"),
          ("morph.minkowski", "_trimmed", "trimming"),
          ("morph.render.svg", "fitted_regions", "SVG export: cubic fit"),
          ("morph.render.svg", "write_svg", "SVG export: writing"),
          ("morph.render.png", "render_palettes", "PNG: drawing"),
          ("morph.render.png", "save_animation", "animation")]


def cpu_of(cmd, env, cwd):
    """CPU seconds (user + system) of one child process; raises when it fails."""
    r0 = resource.getrusage(resource.RUSAGE_CHILDREN)
    p = subprocess.run(cmd, env=env, cwd=cwd, capture_output=True, text=True)
    r1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    if p.returncode != 0:
        raise RuntimeError("%s failed (%d): %s" % (" ".join(cmd), p.returncode, p.stderr[-500:]))
    return (r1.ru_utime - r0.ru_utime) + (r1.ru_stime - r0.ru_stime)


def environments(root):
    """{"bytecode cached": env, "no bytecode": env} running the morph of ``root``."""
    base = dict(os.environ, PYTHONPATH=str(root))
    cached = dict(base, PYTHONPYCACHEPREFIX=tempfile.mkdtemp(prefix="frames-pycache-"))
    cached.pop("PYTHONDONTWRITEBYTECODE", None)
    return {"bytecode cached": cached, "no bytecode": dict(base, PYTHONDONTWRITEBYTECODE="1")}


def processes(roots, runs):
    """{(command, setting, root): [CPU s per run]}, the roots alternated run by run."""
    out = {}
    envs = {r: environments(r) for r in roots}
    with tempfile.TemporaryDirectory() as tmp:
        for name, args in COMMANDS.items():
            for setting in ("bytecode cached", "no bytecode"):
                for i in range(runs + 1):       # run 0 warms the cache and the page cache
                    order = roots if i % 2 else roots[::-1]
                    for r in order:
                        folder = os.path.join(tmp, "frames")
                        shutil.rmtree(folder, ignore_errors=True)
                        cmd = [sys.executable, "-m", "morph.cli"] + args + ["-o", folder]
                        t = cpu_of(cmd, envs[r][setting], tmp)
                        if i:
                            out.setdefault((name, setting, r), []).append(t)
    return out


def phases(runs):
    """{phase: median CPU s} of the svg command in this process, after one warm-up run,
    and "whole command"."""
    sys.path.insert(0, str(ROOT))   # this checkout's morph
    import morph.cli

    spent = {}

    def timed(module, name, label):
        m = importlib.import_module(module)
        f = getattr(m, name)

        @functools.wraps(f)
        def wrapper(*args, **kwargs):
            t = time.process_time()
            try:
                return f(*args, **kwargs)
            finally:
                spent[label] = spent.get(label, 0.0) + time.process_time() - t
        setattr(m, name, wrapper)

    with tempfile.TemporaryDirectory() as tmp:
        args = COMMANDS["svg bird butterfly --frames 10"] + ["-o", os.path.join(tmp, "f")]

        def once():
            shutil.rmtree(os.path.join(tmp, "f"), ignore_errors=True)
            t = time.process_time()
            morph.cli.main(args, standalone_mode=False)
            return time.process_time() - t

        once()
        for spec in PHASES:
            timed(*spec)
        rows = {}
        for _ in range(runs):
            spent.clear()
            whole = once()
            for label, t in list(spent.items()) + [("whole command", whole)]:
                rows.setdefault(label, []).append(t)
    return {k: statistics.median(v) for k, v in rows.items()}


def flattening():
    """(rows of the uniform flattening table, {pair type: trimming vertices}) of the
    svg command's packed frames (one group of 8 inner frames)."""
    sys.path.insert(0, str(ROOT))
    import numpy as np

    import morph.minkowski as mk
    import morph.trim as trim
    from morph import piece as pc
    from morph import polyline as pl
    from morph.budget import plan
    from morph.frames import morph_frames
    from morph.parse import load_shape

    got = {}
    trimmed, tag_loops = mk._trimmed, trim.tag_loops

    def keep_conv(conv, tol, member, *inside):
        got["conv"], got["tol"] = conv, tol
        return trimmed(conv, tol, member, *inside)

    def keep_tags(loops, *args, **kwargs):
        tg = tag_loops(loops, *args, **kwargs)
        got["loops"], got["tags"] = loops, tg
        return tg

    mk._trimmed, trim.tag_loops = keep_conv, keep_tags
    try:
        a, b = (load_shape(str(DATA / n)) for n in ("bird.svg", "butterfly.svg"))
        morph_frames(a.region, b.region, 10, plan(a.tolerance(None, b.region)).geometry)
    finally:
        mk._trimmed, trim.tag_loops = trimmed, tag_loops
    conv, tol = got["conv"], got["tol"]
    eps = mk.FLAT_SHARE * tol
    frames = 8
    rows = []
    for level in (32.0, 8.0, 1.0):
        t = time.process_time()
        owner = pl.flat_starts(conv.pieces, level * eps)[0]
        cpu = time.process_time() - t
        count = np.bincount(owner, minlength=len(conv)).reshape(frames, -1)
        rows.append((level, count.sum(), cpu, frames * count.max(axis=0).sum()))
    # the chained pieces are the convolution's with their ends snapped: matched to
    # their pair type by their end points (rounded)
    starts, ends = pc.end_points(conv.pieces)
    kind = {(tuple(np.round(s, 6)), tuple(np.round(e, 6))): int(k)
            for s, e, k in zip(starts, ends, conv.type)}
    flat = [q for loop in got["loops"] for q in loop]
    cs, ce = pc.end_points(flat)
    of = np.array([kind.get((tuple(np.round(s, 6)), tuple(np.round(e, 6))), 0)
                   for s, e in zip(cs, ce)])
    per_type = np.bincount(of[got["tags"].piece], minlength=4)
    return rows, {"type 1": per_type[1], "type 2": per_type[2], "type 3": per_type[3],
                  "unmatched": per_type[0]}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", type=int, default=7)
    ap.add_argument("--against", type=Path, help="another checkout's root, run alternately")
    ap.add_argument("--phases", action="store_true",
                    help="instead: CPU of each phase of the svg command in one warm process")
    ap.add_argument("--flattening", action="store_true",
                    help="instead: the packed frames' flattening, own against shared")
    args = ap.parse_args(argv)
    if args.flattening:
        rows, per_type = flattening()
        print("| level (eps) | vertices, each frame its own | CPU ms | one subdivision for "
              "all frames | ratio |")
        print("|---|---|---|---|---|")
        for level, own, cpu, shared in rows:
            print("| %g | %d | %.0f | %d | %.2f |" % (level, own, cpu * 1e3, shared,
                                                    shared / own))
        total = sum(per_type.values())
        print()
        print("| trimming vertices of pieces of | count | share |")
        print("|---|---|---|")
        for name, n in per_type.items():
            print("| %s | %d | %.0f %% |" % (name, n, 100.0 * n / total))
        return 0
    if args.phases:
        import contextlib
        import io

        with contextlib.redirect_stdout(io.StringIO()):
            got = phases(args.runs)
        print("| phase of `morph svg bird butterfly --frames 10` (warm process) | CPU ms |")
        print("|---|---|")
        for label, t in got.items():
            print("| %s | %.0f |" % (label, t * 1e3))
        return 0
    roots = [ROOT] + ([args.against.resolve()] if args.against else [])
    got = processes(roots, args.runs)
    head = "| command | bytecode | CPU s (median, min) |"
    if args.against:
        head += " %s: CPU s (median, min) | ratio (median of runs) |" % args.against.name
    print(head)
    print("|---|---|---|" + ("---|---|" if args.against else ""))
    for name in COMMANDS:
        for setting in ("bytecode cached", "no bytecode"):
            mine = got[(name, setting, ROOT)]
            line = "| %s | %s | %.2f, %.2f |" % (name, setting, statistics.median(mine),
                                                 min(mine))
            if args.against:
                other = got[(name, setting, roots[1])]
                line += " %.2f, %.2f | %.2f |" % (
                    statistics.median(other), min(other),
                    statistics.median([x / y for x, y in zip(mine, other)]))
            print(line, flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main())

"""The trimming's phases alone, in-process, on the sums of a whole ``morph stroke`` run.

    python -m bench.trim_phases [--sets hanzi-300,hershey-script,relief] [--repeat 3]
                                [--levels 32 | --levels 32,8] [--calls FILE.pickle]
                                [--count]

Each set is stroked once (``morph stroke --jobs 1``, the command's own chunks) with
:func:`morph.trim.boundary` recorded; then every recorded call is trimmed again
``--repeat`` times, timing each phase exclusively (CPU time, ``time.process_time``):
flatten (``tag_loops``), Clipper (``packed_filled_rings``, ``drop_slivers``), holes
(``_filled_holes``, ``fill_holes``), lift (``lift_rings``), untangle (``merge_lenses``,
``untangle``, ``_near_ring_pairs``).  Printed: ms per glyph, each phase's minimum over the
repeats, and the polyline vertices of the flattening.  ``--levels``: the flattening's
test levels (in eps, :func:`morph.trim.flatten._levels`) instead of the default, to
compare two settings on the same calls in one process.  The machine is shared, so
CPU time, and settings compared in one process, alternating.  ``--count``: also the
function calls (Python and C, ``sys.setprofile``) of each phase per glyph, in one
more pass: a measure of the per-call work that the machine's load does not change.
"""

import argparse
import functools
import os
import tempfile
import time
from pathlib import Path

GLYPHS = {}
PHASES = {"flatten": ["tag_loops"], "Clipper": ["packed_filled_rings", "drop_slivers"],
          "holes": ["_filled_holes", "fill_holes"], "lift": ["lift_rings"],
          "untangle": ["merge_lenses", "untangle_loops", "_near_ring_pairs"]}


def source(name):
    if name == "relief":
        from bench.stroke_profile import relief_ufo

        return relief_ufo()
    from bench.skeletons import skeleton_ufo

    return skeleton_ufo(name)


def record(name):
    """(the boundary calls of one ``morph stroke`` run, glyphs stroked)."""
    import io
    import re
    from contextlib import redirect_stdout

    import morph.cli as cli
    import morph.minkowski as mk

    calls, orig = [], mk.boundary

    def rec(*args, **kwargs):
        calls.append((args, kwargs))
        return orig(*args, **kwargs)

    mk.boundary = rec
    out = io.StringIO()
    try:
        with tempfile.TemporaryDirectory() as tmp, redirect_stdout(out):
            cli.main(["stroke", str(source(name)), "-o", str(Path(tmp) / "out.otf"),
                      "--force", "--jobs", "1"], standalone_mode=False)
    except SystemExit:
        pass
    finally:
        mk.boundary = orig
    m = re.search(r"\((\d+) glyphs? stroked", out.getvalue())
    return calls, int(m.group(1)) if m else 1


def timed_phases():
    """Wrap the phases' functions in morph.trim; returns the dict they add to."""
    import morph.trim as tr

    spent, stack, last = {}, ["rest"], [time.process_time()]

    def charge():
        now = time.process_time()
        spent[stack[-1]] = spent.get(stack[-1], 0.0) + now - last[0]
        last[0] = now

    def wrap(phase, f):
        @functools.wraps(f)
        def g(*a, **k):
            charge()
            stack.append(phase)
            try:
                return f(*a, **k)
            finally:
                charge()
                stack.pop()
        return g

    for phase, names in PHASES.items():
        for n in names:
            setattr(tr, n, wrap(phase, getattr(tr, n)))
    return spent, charge, last, stack


def counted(calls, stack):
    """{phase: function calls (Python and C)} of trimming ``calls`` once; ``stack``:
    the phases' stack of :func:`timed_phases`."""
    import sys

    import morph.trim as tr

    counts = {}

    def hook(frame, event, arg):
        if event in ("call", "c_call"):
            counts[stack[-1]] = counts.get(stack[-1], 0) + 1

    sys.setprofile(hook)
    try:
        for a, k in calls:
            tr.boundary(*fresh(a), **k)
    finally:
        sys.setprofile(None)
    counts["total"] = sum(counts.values())
    return counts


def recorded_calls(names, path=None):
    """{set: (calls, glyphs)}, from the pickle ``path`` where it exists, else recorded
    (and written there)."""
    import pickle

    if path and Path(path).exists():
        with open(path, "rb") as f:
            return pickle.load(f)
    out = {name: record(name) for name in names}
    if path:
        with open(path, "wb") as f:
            pickle.dump(out, f)
    return out


def fresh(args):
    """The recorded arguments with a new hole test (a :class:`morph.minkowski._HoleTest`
    caches its flattenings: each repeat starts without them)."""
    import morph.minkowski as mk

    args = list(args)
    if len(args) > 4 and isinstance(args[4], mk._HoleTest):
        h = args[4]
        args[4] = mk._HoleTest(h.a, h.b, h.tol)
    return args


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sets", default="hanzi-300,hershey-script,relief")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--levels", help="comma separated test levels in eps, e.g. 32 or 32,8")
    ap.add_argument("--calls", help="a pickle of the recorded calls: read where it exists, "
                    "else written (to time changes of the trimming on the same calls)")
    ap.add_argument("--count", action="store_true",
                    help="also count each phase's function calls per glyph (one more pass)")
    args = ap.parse_args(argv)
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import morph.trim as tr
    import morph.trim.flatten as fl

    if args.levels:
        levels = [float(v) for v in args.levels.split(",")]
        fl._levels = lambda coarse: list(levels)
    recorded = recorded_calls(args.sets.split(","), args.calls)
    spent, charge, last, stack = timed_phases()
    for name, (calls, glyphs) in recorded.items():
        best, vertices = {}, 0
        for _ in range(args.repeat):
            spent.clear()
            last[0] = t0 = time.process_time()
            for a, k in calls:
                tr.boundary(*fresh(a), **k)
            charge()
            spent["total"] = time.process_time() - t0
            best = {k: min(v, best.get(k, v)) for k, v in spent.items()}
        vertices = sum(len(fl.tag_loops(*a[:3], pieces=k.get("pieces")).q) for a, k in calls)
        print("%s (%d glyphs, %d calls, %d polyline vertices): %s ms/glyph" % (
            name, glyphs, len(calls), vertices, ", ".join(
                "%s %.2f" % (k, 1000.0 * best.get(k, 0.0) / glyphs)
                for k in list(PHASES) + ["rest", "total"])), flush=True)
        if args.count:
            counts = counted(calls, stack)
            print("%s function calls per glyph: %s" % (name, ", ".join(
                "%s %.1f" % (k, counts.get(k, 0) / glyphs)
                for k in list(PHASES) + ["rest", "total"])), flush=True)


if __name__ == "__main__":
    main()

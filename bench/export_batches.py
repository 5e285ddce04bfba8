"""Export fit and certificate of ``morph stroke`` on the command's own batches.

    python -m bench.export_batches [--sets hanzi-300,relief] [--repeat 3] [--batches N]
                                   [--profile]

``morph stroke`` exports each chunk of glyphs in one ``loops_to_beziers`` call (a
batch).  This script runs the command once per set (``--jobs 1``), keeps the loops of
every batch (pickled in the bench cache, ``MORPH_BENCH_CACHE`` or the system's
temporary folder: delete the file to capture again), then exports those batches again
in this process and reports the CPU time (``time.process_time``, the least of
``--repeat`` runs) of the export fit and of the certificate (the time inside
``certify_batch``) per glyph written, with the cubics and points of the curves: the
two phases of ``bench/stroke_profile.py`` without the rest of the command, so that
two revisions compare on the same input even on a loaded machine.  ``--batches N``
exports the same loops in N batches instead of the command's (consecutive batches
joined or split): what the chunk size costs.  Sets: ``hanzi-300``, ``hershey-sans``,
``hershey-script`` (bench/skeletons.py, fetched into the cache) and ``relief`` (the
Relief SingleLine UFO of bench/stroke_profile.py).
"""

import argparse
import contextlib
import cProfile
import io
import os
import pickle
import pstats
import re
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")    # as the CLI does, before numpy


def source(name):
    if name == "relief":
        from bench.stroke_profile import relief_ufo

        return relief_ufo()
    from bench.skeletons import skeleton_ufo

    return skeleton_ufo(name)


def cache_file(name):
    folder = Path(os.environ.get("MORPH_BENCH_CACHE") or tempfile.gettempdir())
    return folder / ("export-batches-%s.pickle" % name)


def capture(name):
    """(glyphs written, [(loops, tol, kwargs)]): the batches of one ``morph stroke``
    run of the set, from the cache or captured now."""
    path = cache_file(name)
    if path.exists():
        with open(path, "rb") as f:
            return pickle.load(f)
    import morph.export as ex
    import morph.export.loops as lp
    from morph.cli import main

    calls, real = [], lp.loops_to_beziers

    def kept(loops, tol, *args, **kwargs):
        calls.append((loops, tol, args, kwargs))
        return real(loops, tol, *args, **kwargs)

    ex.loops_to_beziers = lp.loops_to_beziers = kept
    out = io.StringIO()
    try:
        with tempfile.TemporaryDirectory() as tmp, contextlib.redirect_stdout(out):
            main(["stroke", str(source(name)), "-o", str(Path(tmp) / "out.otf"), "--force",
                  "--jobs", "1"], standalone_mode=False)
    finally:
        ex.loops_to_beziers = lp.loops_to_beziers = real
    found = re.search(r"\((\d+) glyphs", out.getvalue())
    if not found:
        raise SystemExit("morph stroke %s wrote no font: %s" % (name, out.getvalue()))
    data = (int(found.group(1)), calls)
    with open(path, "wb") as f:
        pickle.dump(data, f)
    return data


def regroup(calls, count):
    """The loops of ``calls`` in ``count`` batches of consecutive calls (a call cut
    only when there are more batches than calls)."""
    loops = [loop for c in calls for loop in c[0]]
    if count >= len(calls):
        edges = [round(i * len(loops) / count) for i in range(count + 1)]
    else:
        sizes = [len(c[0]) for c in calls]
        cuts = [round(i * len(calls) / count) for i in range(count + 1)]
        edges = [sum(sizes[:k]) for k in cuts]
    tol, args, kwargs = calls[0][1:]
    return [(loops[a:b], tol, args, kwargs) for a, b in zip(edges, edges[1:])]


def timed_export(calls, repeat):
    """(total CPU s, certificate CPU s, written curves) of the least total of
    ``repeat`` exports of the batches."""
    import morph.export.certify as ce
    import morph.export.loops as lp
    import morph.export.search as se

    real, spent, depth = se.certify_batch, [0.0], [0]

    def certify(*args, **kwargs):
        depth[0] += 1
        t = time.process_time()
        try:
            return real(*args, **kwargs)
        finally:
            depth[0] -= 1
            if not depth[0]:
                spent[0] += time.process_time() - t

    se.certify_batch = ce.certify_batch = certify
    best = None
    try:
        for _ in range(repeat):
            spent[0] = 0.0
            t = time.process_time()
            out = [lp.loops_to_beziers(loops, tol, *a, **k) for loops, tol, a, k in calls]
            total = time.process_time() - t
            if best is None or total < best[0]:
                best = (total, spent[0])
    finally:
        se.certify_batch = ce.certify_batch = real
    return best[0], best[1], [c for batch in out for loop in batch for c in loop]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--sets", default="hanzi-300,relief")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--batches", type=int, default=None,
                    help="export the loops in this many batches instead of the command's")
    ap.add_argument("--profile", action="store_true", help="cProfile one more export")
    args = ap.parse_args()
    print("load %s" % " ".join("%.1f" % v for v in os.getloadavg()))
    for name in args.sets.split(","):
        glyphs, calls = capture(name)
        if args.batches:
            calls = regroup(calls, args.batches)
        total, cert, curves = timed_export(calls, args.repeat)
        cubics = sum(1 for c in curves if len(c) == 4)
        points = sum(len(c) - 1 for c in curves)
        print("%s: %d glyphs, %d batches: export fit %.2f ms a glyph, certificate %.2f, "
              "together %.2f (CPU); %d cubics, %d points"
              % (name, glyphs, len(calls), 1e3 * (total - cert) / glyphs,
                 1e3 * cert / glyphs, 1e3 * total / glyphs, cubics, points))
        if args.profile:
            import morph.export.loops as lp

            prof = cProfile.Profile()
            prof.enable()
            for loops, tol, a, k in calls:
                lp.loops_to_beziers(loops, tol, *a, **k)
            prof.disable()
            pstats.Stats(prof).sort_stats("tottime").print_stats(25)


if __name__ == "__main__":
    main()

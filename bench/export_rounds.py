"""The certified export of the font commands replayed on their own inputs: rounds of
array calls, fits, certificate pairs, cubics and CPU time.

    python -m bench.export_rounds [--runs brush:noto,stroke:hanzi-300,stroke:relief]
                                  [--repeat 3] [--cache DIR] [--calls]

Each run (``command:set`` as in :mod:`bench.stroke_profile`) is the command itself,
once, in a fresh process with ``morph.fonts.tables.contours_from_regions`` wrapped
so that its arguments (every chunk's regions, tolerance, output kind) are saved
(``--cache``, default a folder in the system temporary folder; delete it to capture
again).  The saved calls are then converted again in this process ``--repeat``
times, and the fastest is reported: the CPU time (``time.process_time``) of the
conversion per glyph, of it the certificate's (``certify_batch``), the rounds of
the segment search (its batched fits, ``morph.export.search._fit_batch``), the fits
asked, the (sub-piece, cubic) pairs certified, the cubics written, the points of the
written outlines (on-curve and off-curve, a closed contour's start counted once) and
the largest certified bound of a fitted cubic (the worst error the certificates
allow); with ``--calls``, the Python-level calls (Python functions and C
functions such as numpy's) of one more conversion.  The
conversion is what ``morph stroke`` and ``morph brush`` do, on the same inputs
however the sums change, so that exporters can be compared on equal terms
(``PYTHONPATH`` another checkout to time its exporter).  The machine is shared:
CPU time, not wall time.
"""

import argparse
import json
import os
import pickle
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def capture(run, cache):
    """The saved contours_from_regions calls of ``run`` (made once, in a fresh
    process)."""
    path = Path(cache) / (run.replace(":", "_") + ".pkl")
    if not path.exists():
        Path(cache).mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryDirectory() as tmp:
            from bench.stroke_profile import run_args

            args, _ = run_args(run, tmp)
            proc = subprocess.run([sys.executable, "-m", "bench.export_rounds", "--capture",
                                   str(path), json.dumps(args)], capture_output=True,
                                  text=True, cwd=tmp)
            if proc.returncode != 0:
                raise SystemExit("run %s failed:\n%s" % (run, proc.stderr[-3000:]))
    with open(path, "rb") as f:
        return pickle.load(f)


def capture_worker(path, args_json):
    """Run the command, saving every contours_from_regions call's arguments."""
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    import morph.cli as cli
    import morph.fonts.tables as tables

    calls, real = [], tables.contours_from_regions

    def saving(regions, tol, quadratic, offsets=None, reverse=None, splines=False):
        calls.append((regions, tol, quadratic, offsets, reverse, splines))
        return real(regions, tol, quadratic, offsets, reverse, splines)

    tables.contours_from_regions = saving
    try:
        cli.main(json.loads(args_json), standalone_mode=False)
    except SystemExit:
        pass
    with open(path, "wb") as f:
        pickle.dump(calls, f)


#: What the wrapped functions counted since the last reset (:func:`_install`).
COUNT = {}


def _install():
    """Wrap the search's batched fit, the certificate and the cubic stage once: rounds,
    fits, pairs certified (and their CPU time), cubics written, into COUNT."""
    import morph.export.quadratic as quad_mod
    import morph.export.search as search

    if getattr(search, "_rounds_counted", False):
        return
    fit, certify, beziers = search._fit_batch, search.certify_batch, quad_mod.loops_to_beziers
    arrays = search._cubic_arrays

    def fits(chains, req, tol):
        COUNT["rounds"] = COUNT.get("rounds", 0) + 1
        COUNT["fits"] = COUNT.get("fits", 0) + len(req.chain)
        return fit(chains, req, tol)

    def certified(groups, cubics, *args, **kwargs):
        t0 = time.process_time()
        try:
            return certify(groups, cubics, *args, **kwargs)
        finally:
            COUNT["certificate s"] = COUNT.get("certificate s", 0.0) + time.process_time() - t0
            COUNT["pairs"] = COUNT.get("pairs", 0) + len(cubics)

    def cubics(*args, **kwargs):
        out = beziers(*args, **kwargs)
        COUNT["cubics"] = COUNT.get("cubics", 0) + sum(len(b) == 4 for bs in out for b in bs)
        return out

    def bounded(n, final, rounds):
        worst = max((float(seg[3].max()) for seg in final if len(seg[3])), default=0.0)
        COUNT["worst"] = max(COUNT.get("worst", 0.0), worst)
        return arrays(n, final, rounds)

    search._fit_batch, search.certify_batch, search._cubic_arrays = fits, certified, bounded
    quad_mod.loops_to_beziers = cubics
    search._rounds_counted = True


def _convert(calls):
    """Convert the saved calls once: the points of the written outlines."""
    import morph.export as export
    import morph.export.quadratic as quad_mod
    from morph.region import reverse_loop

    points = 0
    for regions, tol, quadratic, offsets, reverse, splines in calls:
        flip = quadratic if reverse is None else reverse
        lps = [reverse_loop(lp) if flip else lp for r in regions for lp in r]
        if quadratic:
            out = export.loops_to_quadratics(lps, tol, wrap=True, splines=splines)
        else:
            out = quad_mod.loops_to_beziers(lps, tol, wrap=True)
        points += sum(len(b) - 1 for loop in out for b in loop)
    return points


def counted_calls(calls):
    """The Python-level calls of one conversion of the saved calls: Python functions
    and C functions such as numpy's (``sys.setprofile``; numpy's operators and
    ufuncs called as operators are not seen), those of this script's counting
    wrappers left out: a count the machine's load does not change."""
    count = [0]
    mine = __file__

    def prof(frame, event, arg):
        if event in ("call", "c_call") and frame.f_code.co_filename != mine:
            count[0] += 1

    sys.setprofile(prof)
    try:
        _convert(calls)
    finally:
        sys.setprofile(None)
    return count[0]


def replay(calls, repeat):
    """The fastest of ``repeat`` conversions of the saved calls (after one that warms
    caches): (CPU seconds, COUNT of that conversion)."""
    _install()
    best = None
    for k in range(repeat + 1):
        COUNT.clear()
        t0 = time.process_time()
        points = _convert(calls)
        spent = time.process_time() - t0
        COUNT["points"] = points
        if k and (best is None or spent < best[0]):
            best = (spent, dict(COUNT))
    return best


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", default="brush:noto,stroke:hanzi-300,stroke:relief")
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--cache", default=os.path.join(tempfile.gettempdir(),
                                                    "morph_export_rounds"))
    ap.add_argument("--calls", action="store_true",
                    help="also count the Python-level calls of one conversion")
    ap.add_argument("--capture", nargs=2, help=argparse.SUPPRESS)
    args = ap.parse_args()
    if args.capture:
        capture_worker(*args.capture)
        return
    os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")
    print("load %s" % " ".join("%.1f" % v for v in os.getloadavg()))
    for run in args.runs.split(","):
        calls = capture(run, args.cache)
        glyphs = sum(len(c[0]) for c in calls)
        spent, c = replay(calls, args.repeat)
        ncalls = counted_calls(calls) if args.calls else 0
        print("%-18s %4d glyphs: export %.2f ms/glyph CPU (certificate %.2f), %d rounds, "
              "%d fits, %d pairs certified, %d cubics, %.1f points/glyph, worst bound %.6g%s"
              % (run, glyphs, 1e3 * spent / glyphs, 1e3 * c.get("certificate s", 0.0) / glyphs,
                 c.get("rounds", 0), c.get("fits", 0), c.get("pairs", 0), c.get("cubics", 0),
                 c.get("points", 0) / glyphs, c.get("worst", 0.0),
                 ", %d calls" % ncalls if args.calls else ""), flush=True)


if __name__ == "__main__":
    main()

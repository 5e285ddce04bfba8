"""What the certificate of the export costs, and which path each pair takes, on the
font commands' own inputs.

    python -m bench.certify_cost [--runs stroke:hanzi-300,brush:noto,stroke:relief]
                                 [--repeat 5] [--cache DIR]

For each run (``command:set`` as in :mod:`bench.export_rounds`, whose saved
``contours_from_regions`` calls it replays), and for the Relief subset of
:mod:`bench.relief_profile` (broad nib, tol 0.5) as one chunk of its 62 glyphs and
one of its first 31, the export is replayed once with every
``morph.export.search.certify_batch`` call recorded; the recorded calls are then
certified again ``--repeat`` times and the fastest kept.  Reported per run:

- the certificate calls (one per round of the segment search) and the (sub-piece,
  cubic) pairs certified;
- the share of pairs on each path: ``same`` (phi = identity, the fitter's pairs
  already matched), ``panels`` (Möbius panels cut at the fitter's rays), ``fine
  panels`` (the retry on panels cut at every ray, where the first panels fail),
  ``composed`` (the composed-map fallback, Newton feet and polynomial phi), and
  ``failed`` (bound above tol);
- CPU ms of the certificate (``time.process_time``, the fastest replay; the
  machine is shared: CPU time, not wall time) and per pair;
- Python-level calls (functions and C functions such as numpy's) per certificate
  call: these do not depend on the load, and a chunk's fixed cost is mostly them.

The Relief line gives the fixed cost per chunk: the line time(n) = fixed + n x added
through the chunks of 31 and 62 glyphs (CPU and calls).  ``PYTHONPATH`` another
checkout to measure its certificate on the same inputs.
"""

import argparse
import os
import sys
import tempfile
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the morph command sets it

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))  # after PYTHONPATH: a checkout named there is measured

PATHS = ("same", "panels", "fine panels", "composed", "failed")


def record(run, cache):
    """The arguments of every certify_batch call of ``run``'s export: a list of
    (groups, cubics, tol, kwargs)."""
    import morph.export.search as search

    calls, real = [], search.certify_batch

    def saving(groups, cubics, tol, **kw):
        calls.append((groups, cubics, tol, kw))
        return real(groups, cubics, tol, **kw)

    search.certify_batch = saving
    try:
        if run.startswith("relief:"):
            _relief(int(run.split(":")[1]))
        else:
            from bench.export_rounds import capture, replay
            replay(capture(run, cache), 0)
    finally:
        search.certify_batch = real
    return calls


def _relief(glyphs):
    """Export the first ``glyphs`` of the Relief subset, broad nib, tol 0.5, in one
    chunk (as :mod:`bench.relief_profile` does)."""
    from bench.relief_profile import _inputs
    from morph.budget import plan
    from morph.export import loops_to_beziers
    from morph.stroke import stroke_many

    sets, nib = _inputs("broad")
    geometry, export = plan(0.5)[:2]
    regions = stroke_many(sets[:glyphs], nib, geometry)
    loops_to_beziers([lp for r in regions for lp in r], export, wrap=True)


def path_of(res, tol):
    """The path of each pair of a Certified: indices into PATHS."""
    import numpy as np

    k = len(res.bound)
    out = np.full(k, 1)
    same = getattr(res, "same", None)
    if same is not None:
        out[same] = 0
    elif res.paneled is not None:
        out[~res.paneled] = 0
    other = res.other >= 0
    if other.any():
        rest = res.rest
        fine = rest.paneled is not None
        sub = np.where(fine, 2, 3) * np.ones(k, int)
        if fine and (rest.other >= 0).any():
            sub[other] = np.where(rest.other[res.other[other]] >= 0, 3, 2)
        out[other] = sub[other]
    out[~(res.bound <= tol)] = 4
    return out


def measure(calls, repeat):
    """(pairs per path, CPU s of the fastest replay, Python calls) of the calls."""
    import numpy as np

    import morph.export.certify as certify

    def go():
        return [certify.certify_batch(g, c, t, **kw) for g, c, t, kw in calls]

    res = go()
    paths = np.zeros(len(PATHS), int)
    for (_, _, tol, _), r in zip(calls, res):
        paths += np.bincount(path_of(r, tol), minlength=len(PATHS))
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        go()
        best = min(best, time.process_time() - t0)
    from bench.relief_profile import python_calls

    return paths, best, python_calls(go)[1]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--runs", default="stroke:hanzi-300,brush:noto,stroke:relief")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--cache", default=os.path.join(tempfile.gettempdir(),
                                                    "morph_export_rounds"))
    args = ap.parse_args()
    print("load %s" % " ".join("%.1f" % v for v in os.getloadavg()))
    print("| run | calls | pairs | %s | certificate ms CPU | us / pair | Python calls / call |"
          % " | ".join(PATHS))
    print("|---" * (6 + len(PATHS)) + "|")
    rows = {}
    for run in args.runs.split(",") + ["relief:31", "relief:62"]:
        calls = record(run, args.cache)
        paths, spent, count = measure(calls, args.repeat)
        pairs = int(paths.sum())
        rows[run] = (len(calls), spent, count)
        print("| %s | %d | %d | %s | %.1f | %.1f | %.0f |" % (
            run, len(calls), pairs, " | ".join("%.2f %%" % (100.0 * p / pairs) for p in paths),
            1e3 * spent, 1e6 * spent / pairs, count / len(calls)), flush=True)
    (_, t31, c31), (_, t62, c62) = rows["relief:31"], rows["relief:62"]
    print("\nRelief chunk, tol 0.5: fixed %.1f ms CPU and %.0f Python calls per chunk "
          "(line through the chunks of 31 and 62 glyphs)"
          % (1e3 * (2 * t31 - t62), 2 * c31 - c62))


if __name__ == "__main__":
    main()

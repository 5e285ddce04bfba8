"""What a chunk of the export fit costs whatever it holds, and what a glyph adds, on
Relief: rounds, fits, Python-level calls, points and CPU time.

    python bench/export_fixed.py [--tol 0.5] [--repeat 7]

The Relief SingleLine subset (tests/data/relief, 62 glyphs A-Z, a-z, 0-9) and its
first 31 glyphs are stroked once with the broad nib of ``morph stroke`` (as
``bench/relief_profile.py`` strokes them, at the geometry share of ``plan(tol)``);
then each set's loops are exported by ``loops_to_beziers(..., wrap=True)`` at the
export share, ``--repeat`` times after one untimed pass.  Reported per set: the
fewest CPU seconds (``time.process_time``) of the export and of it without the
certificate (``certify_batch``), the rounds of the segment search
(``morph.export.search._fit_batch``), the fits asked, the Python-level calls of one
export (Python functions and C functions such as numpy's, counted by
``sys.setprofile``: they do not depend on the machine's load) and the points
written.  The line time(n) = fixed + n x added through the two sets gives the fit's
cost per chunk and per added glyph (on a loaded machine these carry the noise of a
difference; the calls do not).  ``PYTHONPATH`` names the checkout measured (this
file runs another checkout's ``morph``, and its ``bench.relief_profile``).
"""

import argparse
import os
import sys
import time
from pathlib import Path

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")  # as the morph command sets it
sys.path.append(str(Path(__file__).resolve().parents[1]))  # after PYTHONPATH


def loops_of(sets, nib, tol):
    """The loops of the stroked glyphs ``sets`` and the export tolerance."""
    from morph.budget import plan
    from morph.stroke import stroke_many

    geometry, export = plan(tol)[:2]
    return [lp for r in stroke_many(sets, nib, geometry) for lp in r], export


def measure(loops, tol, repeat):
    """(export s, fit s without the certificate, rounds, fits, calls, points)."""
    import morph.export.search as search
    from morph.export import loops_to_beziers

    count = {}
    fit, certify = search._fit_batch, search.certify_batch

    def fits(chains, req, t):
        count["rounds"] = count.get("rounds", 0) + 1
        count["fits"] = count.get("fits", 0) + len(req.chain)
        return fit(chains, req, t)

    def certified(*args, **kwargs):
        t0 = time.process_time()
        try:
            return certify(*args, **kwargs)
        finally:
            count["cert"] = count.get("cert", 0.0) + time.process_time() - t0

    search._fit_batch, search.certify_batch = fits, certified
    try:
        out = loops_to_beziers(loops, tol, wrap=True)
        best = None
        for _ in range(repeat):
            count.clear()
            t0 = time.process_time()
            loops_to_beziers(loops, tol, wrap=True)
            spent = time.process_time() - t0
            if best is None or spent - count["cert"] < best[1]:
                best = (spent, spent - count["cert"], count["rounds"], count["fits"])
        from bench.relief_profile import python_calls

        calls = python_calls(lambda: loops_to_beziers(loops, tol, wrap=True))[1]
    finally:
        search._fit_batch, search.certify_batch = fit, certify
    return best + (calls, sum(len(b) - 1 for loop in out for b in loop))


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--tol", type=float, default=0.5, help="font units")
    ap.add_argument("--repeat", type=int, default=7)
    args = ap.parse_args(argv)
    from bench.relief_profile import _inputs

    sets, nib = _inputs("broad")
    print("load %s" % " ".join("%.1f" % v for v in os.getloadavg()))
    rows = {}
    for name, glyphs in (("all", sets), ("half", sets[:len(sets) // 2])):
        loops, export = loops_of(glyphs, nib, args.tol)
        rows[name] = (len(glyphs),) + measure(loops, export, args.repeat)
        n, spent, fit, rounds, fits, calls, points = rows[name]
        print("%2d glyphs: export %.1f ms CPU (fit without certificate %.1f), %d rounds, "
              "%d fits, %d calls, %d points" % (n, 1e3 * spent, 1e3 * fit, rounds, fits, calls,
                                                points), flush=True)
    (na, _, fa, _, _, ca, _), (nh, _, fh, _, _, ch, _) = rows["all"], rows["half"]
    added, added_calls = (fa - fh) / (na - nh), (ca - ch) / (na - nh)
    print("fit without certificate: %.1f ms per chunk + %.2f ms per glyph; calls %d per "
          "chunk + %.1f per glyph" % (1e3 * (fa - na * added), 1e3 * added,
                                      ca - na * added_calls, added_calls))


if __name__ == "__main__":
    main()

"""The stroke sum alone per glyph of Relief SingleLine, as ``morph stroke`` computes it.

    python -m bench.stroke_sum [--tol 0.5] [--alone] [--profile cumulative|tottime]

Relief A-Z, a-z, 0-9 (the full UFO from ../shared/data when present, else the subset
in tests/data), the default broad nib of ``morph stroke`` (ellipse 90 x 20 at 30
degrees), the geometry share of --tol (``morph.budget.plan``): CPU ms per
glyph of one pass after a warm-up pass, in-process; the glyphs in the command's
chunks (``morph.fonts.brush.glyph_chunks``), each chunk stroked together
(``morph.stroke.stroke_many``), or with ``--alone`` one glyph at a time
(``stroke_paths``).  The export and the font
compilation are not included (``bench/export_profile.py``, ``bench/stroke.py``).
"""

import argparse
import cProfile
import os
import pstats
import time

os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")    # as the command, before numpy loads

from bench.stroke import BROAD, nib_region  # noqa: E402 - after the BLAS thread count is set
from tests.oracles.sweep import relief_font  # noqa: E402 - after the BLAS thread count is set
from morph.budget import plan  # noqa: E402 - after the BLAS thread count is set
from morph.parse.ufo import decomposed_paths  # noqa: E402 - after the BLAS thread count is set
from morph.fonts.brush import glyph_chunks  # noqa: E402 - after the BLAS thread count is set
from morph.fonts.stroke import CHUNK  # noqa: E402 - after the BLAS thread count is set
from morph.stroke import stroke_many, stroke_paths  # noqa: E402 - after the BLAS thread count is set

NAMES = list("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz") + [
    "zero", "one", "two", "three", "four", "five", "six", "seven", "eight", "nine"]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, default=0.5)
    ap.add_argument("--alone", action="store_true", help="one glyph at a time")
    ap.add_argument("--profile", choices=("cumulative", "tottime"))
    opt = ap.parse_args(argv)
    font, _ = relief_font()
    have = {g.name for g in font}
    names = [n for n in NAMES if n in have]
    nib = nib_region(BROAD)
    geometry, _ = plan(opt.tol)[:2]
    paths = {n: decomposed_paths(font, n) for n in names}

    def run():
        if opt.alone:
            for n in names:
                stroke_paths(paths[n], nib, geometry)
            return
        for chunk in glyph_chunks(names, CHUNK):
            stroke_many([paths[n] for n in chunk], nib, geometry)

    run()
    t = time.process_time()
    run()
    dt = time.process_time() - t
    print("%d glyphs, %.1f ms/glyph CPU (%s at tol %g)"
          % (len(names), dt / len(names) * 1e3,
             "stroke_paths" if opt.alone else "stroke_many by chunks", geometry))
    if opt.profile:
        prof = cProfile.Profile()
        prof.runcall(run)
        pstats.Stats(prof).sort_stats(opt.profile).print_stats(30)


if __name__ == "__main__":
    main()

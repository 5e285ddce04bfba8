"""Sub-grid shift sweep: each random-mode case of bench.sweep summed again after
translations by up to ``--by`` tol in x and y, every result checked by
:func:`tests.oracles.sweep.verify` against the translated exact predicate.

    python -m bench.shifts --seed 424 --n 40 --shifts 5
    python -m bench.shifts --mode fonts --seed 303 --n 10 --shifts 3

``--mode random`` (glyph ⊕ nib, :func:`bench.sweep.draw_random_cases`) or ``fonts``
(glyph pairs of Lobster, Cormorant and Amiri at 1e-4 em, ``--n`` per font,
:func:`bench.sweep.draw_font_pairs`; the first glyph is translated, the translation
oracle checks 150 boundary samples and every sharp junction, as the fonts sweep does).

The trimming rounds to an integer grid of 0.14 tol: a topology that the rounding
alone decides (a crossing landing on a joint's grid point, two legs of a needle
swapping sides) passes at one offset and fails at another, so a case that fails at
some shifts and not at others is a rounding dependence, one that fails at every
shift is systematic (cormorant U ⊕ a thin nib failed at 30 of 30 shifts
after the snap rounding, 0 of 30 before; fixed in morph.trim.lift).  Prints one
line per failure and a summary; exit status 1 when any failed.
"""

import argparse
import sys

import numpy as np


def main(argv=None):
    import shapely.affinity

    from bench.sweep import draw_random_cases
    from tests.oracles.sweep import (ORACLE_SHARE, RANDOM_FONTS, NibOracle, _nib_region,
                                     case_inputs, parse_case, raw_glyph_polygon,
                                     region_size, verify)
    from morph.errors import LimitError
    from morph.minkowski import minkowski_sum
    from morph.region import transform_region

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mode", choices=("random", "fonts"), default="random")
    ap.add_argument("--seed", type=int, default=424)
    ap.add_argument("--n", type=int, default=40, help="random-mode cases")
    ap.add_argument("--shifts", type=int, default=5, help="translations per case")
    ap.add_argument("--by", type=float, default=1.0, help="largest shift, in tol")
    opt = ap.parse_args(argv)
    rng = np.random.default_rng(opt.seed)
    if opt.mode == "fonts":
        return _font_pairs(opt, rng)
    runs = bad = 0
    for spec in draw_random_cases("random", opt.n, opt.seed, RANDOM_FONTS):
        c = parse_case(spec)
        a, nib, tol = case_inputs(spec)
        rx, ry, theta = _nib_region(c)[1]
        f = ORACLE_SHARE * tol
        geom = raw_glyph_polygon(c["font"], c["glyph"], f, c["s"])
        for k in range(opt.shifts):
            dx, dy = rng.uniform(-1, 1, 2) * opt.by * tol
            moved = transform_region(a, np.array([[1, 0, dx], [0, 1, dy]], float))
            try:
                loops = minkowski_sum(moved, nib, tol)
            except LimitError:
                continue  # a documented refusal (bench.sweep checks its suggestion)
            runs += 1
            oracle = NibOracle(shapely.affinity.translate(geom, dx, dy), rx, ry, theta)
            chk = verify(loops, oracle, tol, f, region_size(moved), np.random.default_rng(k))
            if chk["fail"]:
                bad += 1
                print("FAIL %s shift (%.4g, %.4g): %s" % (spec, dx, dy, chk["fail"][0][:200]),
                      flush=True)
    print("%d of %d shifted sums failed (seed %d, %d cases x %d shifts of up to %g tol)"
          % (bad, runs, opt.seed, opt.n, opt.shifts, opt.by))
    return 1 if bad else 0


def _font_pairs(opt, rng):
    """The fonts mode of :func:`main`."""
    import shapely.affinity

    from bench.sweep import draw_font_pairs
    from tests.oracles.sweep import (ORACLE_SHARE, UPM, PairOracle, glyph, parse_case,
                                     raw_glyph_polygon, region_size, verify)
    from morph.minkowski import minkowski_sum
    from morph.region import transform_region

    runs = bad = 0
    for spec in draw_font_pairs(opt.n, opt.seed):
        c = parse_case(spec)
        a, b = glyph(c["font"], c["a"]), glyph(c["font"], c["b"])
        tol = c["tol"] * UPM
        f = ORACLE_SHARE * tol
        pa = raw_glyph_polygon(c["font"], c["a"], f)
        pb = raw_glyph_polygon(c["font"], c["b"], f)
        for k in range(opt.shifts):
            dx, dy = rng.uniform(-1, 1, 2) * opt.by * tol
            moved = transform_region(a, np.array([[1, 0, dx], [0, 1, dy]], float))
            loops = minkowski_sum(moved, b, tol)
            runs += 1
            oracle = PairOracle(shapely.affinity.translate(pa, dx, dy), pb)
            chk = verify(loops, oracle, tol, 2 * f, region_size(moved) + region_size(b),
                         np.random.default_rng(k), n_boundary=150, n_random=100,
                         ladder=(1.0,))
            if chk["fail"]:
                bad += 1
                print("FAIL %s shift (%.4g, %.4g): %s" % (spec, dx, dy, chk["fail"][0][:200]),
                      flush=True)
    print("%d of %d shifted sums failed (fonts, seed %d, %d pairs per font x %d shifts of "
          "up to %g tol)" % (bad, runs, opt.seed, opt.n, opt.shifts, opt.by))
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

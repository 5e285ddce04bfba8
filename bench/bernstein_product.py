"""CPU time per call of the two Bernstein product methods of :mod:`morph.bernstein`.

    python -m bench.bernstein_product [--reps N]

For stacks of k rows (k = 1, 4, 16, 64), factor degrees (m, n) with product degree
m + n from 2 to 114, balanced (m = n or n + 1) and lopsided (n = 1, 3, 6: the
reparametrisation and piece degrees of the export certificate), it times
``multiply_many(..., method="scatter")`` and ``method="direct"`` by process CPU time
(best of 7 alternating batches) and prints, per k and shape, the smallest product degree from
which the direct product is faster at every measured degree.  The crossover
:data:`morph.bernstein.PRODUCT_DIRECT_DEGREE` (and ``_TAIL``, with trailing axes) are
taken from this table.  Takes ~4 min of wall time on a loaded machine.
"""

import argparse
import time

import numpy as np

from morph import bernstein as bz

DEGREES = [2, 4, 6, 8, 10, 12, 14, 16, 20, 24, 32, 42, 57, 80, 114]


def ratio(a, b, reps, rounds=7):
    """Best CPU time per call of the scatter product over the direct one, the two
    timed in alternating batches (a loaded machine slows both alike)."""
    best = {"scatter": np.inf, "direct": np.inf}
    for method in best:
        bz.multiply_many(a, b, method)                # caches filled
    for _ in range(rounds):
        for method in best:
            t0 = time.process_time()
            for _ in range(reps):
                bz.multiply_many(a, b, method)
            best[method] = min(best[method], (time.process_time() - t0) / reps)
    return best["scatter"] / best["direct"]


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--reps", type=int, default=40)
    args = ap.parse_args()
    rng = np.random.default_rng(0)
    print("k  shape     " + " ".join("%6d" % d for d in DEGREES) + "   crossover")
    for k in (1, 4, 16, 64):
        for shape in ("balanced", "n=1", "n=3", "n=6", "xy*w"):
            ratios = []
            for d in DEGREES:
                if shape in ("balanced", "xy*w"):
                    n = d // 2
                else:
                    n = int(shape[2:])
                m = d - n
                if m < n:
                    ratios.append(np.nan)
                    continue
                tails = ((2,), (1,)) if shape == "xy*w" else ((), ())
                a = rng.normal(size=(k, m + 1) + tails[0])
                b = rng.normal(size=(k, n + 1) + tails[1])
                ratios.append(ratio(a, b, args.reps))
            faster = [r > 1.0 or np.isnan(r) for r in ratios]
            cross = next((d for i, d in enumerate(DEGREES) if all(faster[i:])), None)
            print("%-3d%-9s " % (k, shape) + " ".join("%6.2f" % r for r in ratios)
                  + "   %s" % cross)
    print("(scatter time / direct time per call; > 1: direct faster)")


if __name__ == "__main__":
    main()

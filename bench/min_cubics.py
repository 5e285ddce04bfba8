"""How few tangent-continuous cubics can hold a glyph ⊕ nib outline.

    python -m bench.min_cubics [--char O] [--accuracy 1e-4] [--starts 6]

The target "1.5x fewer points than FontForge's Expand Stroke on O ⊕ ellipse at 1e-4
em" asks for 30 points (10 cubics) where FontForge writes 45 and morph 42.  This
measures the floor independently of morph's exporter: the exact sum (the CFF O of
the test font ⊕ the ``morph brush`` nib, ellipse 80 x 30 units at 30°, computed at
1e-6 em) is sampled densely along each loop; a cubic spans [i, j] with its ends on
the curve and its end tangents the curve's (a G1 join: what a smooth outline is
made of), its two handle lengths optimised (Nelder-Mead from three starts) for the
smallest two-sided distance to the samples (point-to-polyline on both sides); the
greedy cover (from a start point, the longest span within the accuracy, then the
next: optimal for a fixed start, the span error growing with its length) is run from
``--starts`` start points spread along each loop, and the fewest cubics reported.
The whole accuracy goes to the fit (morph gives part of it to the sum), so the floor
is optimistic for morph.  A run takes ~15 minutes.

Measured 2026-11-24 at 1e-4 em (0.1 unit): outer loop 6 cubics from every start
(one start 7), inner loop 8 from every start: 14 cubics, 42 points, what ``morph
sum O ellipse`` writes; 30 points would need cubics that kink at their joins.
"""

import argparse
import time

import numpy as np
from scipy.optimize import minimize
from scipy.spatial import cKDTree

from morph import parse
from morph import piece as pc
from morph.fonts.brush import ellipse_nib
from morph.minkowski import minkowski_sum

UPM = 1000.0
ELLIPSE = (80.0, 30.0, 30.0)
PER_PIECE = 200
CUBIC_SAMPLES = 1500
U = np.linspace(0.0, 1.0, CUBIC_SAMPLES)
BASIS = np.stack([(1 - U) ** 3, 3 * U * (1 - U) ** 2, 3 * U ** 2 * (1 - U), U ** 3], axis=1)


def dense(loop):
    """Samples of a loop (PER_PIECE per piece) and their unit tangents."""
    t = np.linspace(0.0, 1.0, PER_PIECE, endpoint=False)
    pts = np.vstack([pc.evaluate(p, t) for p in loop])
    tan = np.vstack([pc.derivative(p, t) for p in loop])
    return pts, tan / np.linalg.norm(tan, axis=1)[:, None]


def distance_to_polyline(q, poly):
    """Distance of each point of q to the polyline through poly (its nearest vertex's
    two edges: exact for a polyline much finer than the distances' scale)."""
    k = cKDTree(poly).query(q)[1]
    best = np.full(len(q), np.inf)
    for i, j in ((np.maximum(k - 1, 0), k), (k, np.minimum(k + 1, len(poly) - 1))):
        a, ab = poly[i], poly[j] - poly[i]
        den = np.where((ab * ab).sum(1) > 0, (ab * ab).sum(1), 1.0)
        s = np.clip(((q - a) * ab).sum(1) / den, 0.0, 1.0)
        best = np.minimum(best, np.linalg.norm(q - a - s[:, None] * ab, axis=1))
    return best


def span_error(q, ta, tb, handles):
    ctrl = np.array([q[0], q[0] + handles[0] * ta, q[-1] - handles[1] * tb, q[-1]])
    c = BASIS @ ctrl
    return max(distance_to_polyline(q, c).max(), distance_to_polyline(c[::3], q).max())


def best_span(pts, tan, i, j):
    """Smallest error of a G1 cubic from sample i to sample j (cyclic)."""
    n = len(pts)
    q = pts[np.arange(i, j + 1) % n]
    length = np.hypot(*np.diff(q, axis=0).T).sum()

    def error(handles):
        return span_error(q, tan[i % n], tan[j % n], handles)

    return min(minimize(error, g, method="Nelder-Mead",
                        options=dict(xatol=1e-4 * length, fatol=1e-4)).fun
               for g in ([length / 3, length / 3], [length / 2, length / 5],
                         [length / 5, length / 2]))


def cover(pts, tan, acc, start):
    """Cubics of the greedy cover of the closed loop from sample ``start``."""
    n, i, count = len(pts), start, 0
    while True:
        lo, hi = i + 1, start + n
        if best_span(pts, tan, i, hi) <= acc:
            return count + 1
        while hi - lo > 1:
            mid = (lo + hi) // 2
            lo, hi = (mid, hi) if best_span(pts, tan, i, mid) <= acc else (lo, mid)
        i, count = lo, count + 1


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--char", default="O")
    ap.add_argument("--accuracy", type=float, default=1e-4, help="em")
    ap.add_argument("--starts", type=int, default=6)
    args = ap.parse_args(argv)
    region = parse.glyph_region(args.char, parse.cubic_test_font_path()).region
    out = minkowski_sum(region, ellipse_nib(*ELLIPSE), 1e-6 * UPM)
    acc = args.accuracy * UPM
    total = 0
    for k, loop in enumerate(out):
        t0 = time.time()
        pts, tan = dense(loop)
        counts = [cover(pts, tan, acc, s) for s in range(0, len(pts), len(pts) // args.starts)]
        total += min(counts)
        print("loop %d: fewest G1 cubics within %g em: %d (per start: %s; %.0f s)"
              % (k, args.accuracy, min(counts), counts, time.time() - t0), flush=True)
    print("%s ⊕ ellipse %s: %d cubics, %d points" % (args.char, ELLIPSE, total, 3 * total))


if __name__ == "__main__":
    main()

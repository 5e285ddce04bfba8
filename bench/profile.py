"""Profile of the convolution stage and of whole Minkowski sums.

    python bench/profile.py                 # times table + cProfile top entries
    python bench/profile.py --scaling       # n log n table: 10 ... 3000 circles + disk
    python bench/profile.py --case O+M --top 30

Times are CPU seconds of this process (``time.process_time``, best of ``--repeat``
runs, warm: one call before timing), so other jobs on the machine change them less
than wall time; the machine load at the start is printed with them.

Cases (tol in input units):

- ``O+M``, ``S+g``: glyphs of the bundled Noto Sans (TrueType, 1000 units per em),
  ``minkowski_sum(glyph_region(a).region, glyph_region(b).region, 0.1)``: 1e-4 em;
- ``circles300``: 300 disjoint unit circles (exact conics, a 4-unit grid) + a disk of
  radius 0.5, tol 1e-3;
- ``cubics1000``: one closed star-shaped path of 1000 cubic Béziers (Hermite
  interpolation of r(phi) = 10 (1 + 0.15 sin 7 phi), so with inflections) + a disk of
  radius 0.5, tol 1e-3.

For each: ``convolution(A, B, 0.75 tol)`` alone (what ``minkowski_sum`` calls) and the
whole ``minkowski_sum``.
"""

import sys
from pathlib import Path

# this file is named like the stdlib module ``profile`` that cProfile imports: take
# its own directory off the path first
sys.path[:] = [p for p in sys.path if Path(p or ".").resolve() != Path(__file__).resolve().parent]

import argparse  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)
import cProfile  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)
import io  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)
import os  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)
import pstats  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)
import time  # noqa: E402 - after this folder leaves sys.path (cProfile imports profile)

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import morph  # noqa: E402 - after sys.path gets the repo root
from morph import convolve  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.minkowski import CONV_SHARE  # noqa: E402 - after sys.path gets the repo root


def circles(n, spacing=4.0, radius=1.0):
    """n disjoint circles on a square grid (10 per row up to 100, then sqrt(n))."""
    row = max(10, int(np.ceil(np.sqrt(n))))
    return [list(pc.circle((spacing * (i % row), spacing * (i // row)), radius))
            for i in range(n)]


def disk(radius=0.5):
    return [list(pc.circle((0.0, 0.0), radius))]


def star_cubics(n=1000, radius=10.0, amp=0.15, lobes=7):
    """A closed loop of n cubics: Hermite interpolation of r(phi) = R (1 + a sin k phi)."""
    phi = np.linspace(0.0, 2 * np.pi, n + 1)
    r = radius * (1 + amp * np.sin(lobes * phi))
    dr = radius * amp * lobes * np.cos(lobes * phi)
    p = np.column_stack([r * np.cos(phi), r * np.sin(phi)])
    dp = np.column_stack([dr * np.cos(phi) - r * np.sin(phi), dr * np.sin(phi) + r * np.cos(phi)])
    h = 2 * np.pi / n
    loop = [pc.cubic(p[i], p[i] + dp[i] * h / 3, p[i + 1] - dp[i + 1] * h / 3, p[i + 1])
            for i in range(n)]
    last = loop[-1].copy()
    last[-1] = loop[0][0]
    loop[-1] = last
    return [loop]


def glyph(ch):
    return morph.glyph_region(ch).region


def cases():
    return {
        "O+M": lambda: (glyph("O"), glyph("M"), 0.1),
        "S+g": lambda: (glyph("S"), glyph("g"), 0.1),
        "circles300": lambda: (circles(300), disk(), 1e-3),
        "cubics1000": lambda: (star_cubics(1000), disk(), 1e-3),
    }


def best_time(fn, repeat):
    fn()  # warm (caches, imports)
    best = np.inf
    for _ in range(repeat):
        t0 = time.process_time()
        fn()
        best = min(best, time.process_time() - t0)
    return best


def time_case(a, b, tol, repeat):
    conv = best_time(lambda: convolve.convolution(a, b, CONV_SHARE * tol), repeat)
    total = best_time(lambda: morph.minkowski_sum(a, b, tol), repeat)
    return conv, total


def profile(fn, top):
    fn()
    prof = cProfile.Profile()
    prof.enable()
    fn()
    prof.disable()
    out = io.StringIO()
    st = pstats.Stats(prof, stream=out)
    st.sort_stats("tottime").print_stats(top)
    return out.getvalue()


def scaling(ns, repeat, conv_only=False):
    """n circles + disk at tol 1e-3: CPU seconds and ms / (n ln n) of the convolution
    and (unless conv_only) of the whole sum."""
    rows = []
    for n in ns:
        a, b = circles(n), disk()
        rep = repeat if n <= 300 else 1
        conv = best_time(lambda: convolve.convolution(a, b, CONV_SHARE * 1e-3), rep)
        total = np.nan if conv_only else best_time(lambda: morph.minkowski_sum(a, b, 1e-3), rep)
        nl = n * np.log(n)
        rows.append((n, conv, total))
        print("| %d | %.3f | %.2f | %.3f | %.2f |" % (n, conv, 1e3 * conv / nl, total,
                                                    1e3 * total / nl), flush=True)
    return rows


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--case", action="append", help="case name (default: all)")
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--top", type=int, default=0, help="cProfile entries (0: none)")
    ap.add_argument("--conv-only", action="store_true",
                    help="profile (or, with --scaling, time) the convolution only")
    ap.add_argument("--scaling", action="store_true")
    args = ap.parse_args(argv)
    print("load average at start: %.2f %.2f %.2f" % os.getloadavg())
    if args.scaling:
        print("| circles | convolution s | ms / (n ln n) | minkowski_sum s | ms / (n ln n) |")
        print("|---|---|---|---|---|")
        scaling([10, 30, 100, 300, 1000, 3000], args.repeat, args.conv_only)
        return
    all_cases = cases()
    names = args.case or list(all_cases)
    print("| case | convolution s | minkowski_sum s |")
    print("|---|---|---|")
    for name in names:
        a, b, tol = all_cases[name]()
        conv, total = time_case(a, b, tol, args.repeat)
        print("| %s | %.3f | %.3f |" % (name, conv, total), flush=True)
    if args.top:
        for name in names:
            a, b, tol = all_cases[name]()
            if args.conv_only:
                fn = lambda: convolve.convolution(a, b, CONV_SHARE * tol)  # noqa: E731
            else:
                fn = lambda: morph.minkowski_sum(a, b, tol)  # noqa: E731
            print("\n### %s\n\n```" % name)
            print(profile(fn, args.top).strip())
            print("```")


if __name__ == "__main__":
    main()

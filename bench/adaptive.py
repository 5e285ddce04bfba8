"""The trimming's adaptive flattening against flattening within eps everywhere.

    python -m bench.adaptive [--repeat 5] [--md bench/adaptive.md]

For each case and tolerance, ``minkowski_sum`` runs with ``morph.trim.flatten.COARSE``
at its value and at 1 (every piece flattened within eps, the engine before the
adaptive flattening), alternating, in one process: the minimum wall time of each,
the polyline points the trimming builds (``tag_loops``) and whether the two outputs
agree (the same loops of the same number of pieces, sampled points within 1e-9 of
the size of each other).  Cases: the bundled bird and butterfly SVGs at half size
each (frame 5 of ``morph svg bird.svg butterfly.svg``), glyph pairs of the bundled
font, in user units / font units.
"""

import argparse
import time
from pathlib import Path

import numpy as np

from morph import piece as pc
from morph.minkowski import minkowski_sum
from morph.parse import load_shape
from morph.region import scale_region
import morph.trim as trim
import morph.trim.flatten as flatten

DATA = Path(__file__).resolve().parents[1] / "morph" / "data"


def cases():
    bird = load_shape(str(DATA / "bird.svg")).region
    fly = load_shape(str(DATA / "butterfly.svg")).region
    half = (scale_region(bird, 0.5), scale_region(fly, 0.5))
    out = [("bird/2 + butterfly/2 (user units)", half, t) for t in (2.5e-3, 2.5e-4, 2.5e-5)]
    for a, b in (("O", "M"), ("S", "g")):
        pair = (load_shape(a).region, load_shape(b).region)
        out += [("%s + %s (font units)" % (a, b), pair, t) for t in (0.25, 0.025, 0.0025)]
    return out


def run(regions, tol, coarse):
    flatten.COARSE = coarse
    t = time.perf_counter()
    loops = minkowski_sum(regions[0], regions[1], tol)
    return time.perf_counter() - t, loops


def count_points():
    """Wrap trim.tag_loops to record the points of each call."""
    seen = []
    original = trim.tag_loops

    def spy(loops, eps, grid, origin=None):
        tg = original(loops, eps, grid, origin)
        seen.append(len(tg.q))
        return tg

    trim.tag_loops = spy
    return seen


def agree(a, b):
    if sorted(len(l) for l in a) != sorted(len(l) for l in b):
        return False
    pa = np.vstack([pc.evaluate(p, np.linspace(0, 1, 20)) for l in a for p in l])
    pb = np.vstack([pc.evaluate(p, np.linspace(0, 1, 20)) for l in b for p in l])
    size = float(np.ptp(pa, axis=0).max())
    from scipy.spatial import cKDTree

    d = max(cKDTree(pb).query(pa)[0].max(), cKDTree(pa).query(pb)[0].max())
    return d <= 1e-9 * size


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--repeat", type=int, default=5)
    ap.add_argument("--md", default=None)
    args = ap.parse_args(argv)
    default = flatten.COARSE
    seen = count_points()
    rows = ["| case | tol | points (adaptive / within eps) | wall min (adaptive / within eps) | speed-up | same output |",
            "|---|---|---|---|---|---|"]
    for name, regions, tol in cases():
        best = {}
        points = {}
        outs = {}
        for _ in range(args.repeat):
            for c in (default, 1.0):
                del seen[:]
                dt, loops = run(regions, tol, c)
                best[c] = min(best.get(c, np.inf), dt)
                points[c], outs[c] = sum(seen), loops
        flatten.COARSE = default
        row = "| %s | %g | %d / %d | %.0f / %.0f ms | %.2fx | %s |" % (
            name, tol, points[default], points[1.0], 1e3 * best[default], 1e3 * best[1.0],
            best[1.0] / best[default], "yes" if agree(outs[default], outs[1.0]) else "**no**")
        rows.append(row)
        print(row, flush=True)
    text = ("# Adaptive flattening in the trimming (bench/adaptive.py)\n\n"
            "Command: `python -m bench.adaptive --repeat %d`.  COARSE = %g.  In-process "
            "`minkowski_sum`, min wall of the runs, both settings alternating in one process.\n\n"
            % (args.repeat, default) + "\n".join(rows) + "\n")
    if args.md:
        Path(args.md).write_text(text)


if __name__ == "__main__":
    main()

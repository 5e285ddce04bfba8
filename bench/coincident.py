"""Copies of one path: reading time and result against the single path.

    python -m bench.coincident [--md bench/coincident.md] [--repeat 3] [--timeout 600]

SVG documents drawn the way editors and scripts leave them: one path drawn many
times (exact copies, the same curve from another start point or split into more
pieces, either direction), three copies a hair apart in opposite directions, and a
chain of lenses each shifted by 0.001 of the size (every arc crossing the others).
Each case is read with :func:`morph.parse.svg_region` in a fresh subprocess (the
whole process timed, min of ``--repeat``), and its area is compared with the area
the winding numbers give (the single blob's area times whether the copies' summed
winding is filled; for the lenses, shapely's union of lenses sampled at 20,000
points an arc), within 1e-6 of the drawing's size squared: the copies must add up
as any renderer adds them, not merely fast.  Writes a markdown table with ``--md``.
"""

import argparse
import subprocess
import sys
import time

import numpy as np

BLOB = [(20, 50), (20, 20), (45, 12), (60, 15), (85, 20), (90, 40), (85, 60), (80, 85),
        (50, 92), (35, 80), (20, 70), (20, 60), (20, 50)]
BLOB_AREA = 3824.5

SCRIPT = ("import sys\nfrom morph.parse import svg_region\nfrom morph import moments as mo\n"
          "from morph.errors import ParseError\n"
          "try:\n    r = svg_region(open(sys.argv[1]).read())\n"
          "    print(len(r), mo.region_area(r))\n"
          "except ParseError:\n    print(0, 0.0)\n")


def blob_path(start=0, backwards=False, split=None, dx=0.0):
    """The blob as path data from cubic ``start``, either way, cubic ``split`` cut
    at its middle, moved by ``dx``."""
    segs = [BLOB[3 * k:3 * k + 4] for k in range(4)]
    segs = segs[start:] + segs[:start]
    if backwards:
        segs = [s[::-1] for s in segs[::-1]]
    segs = [np.asarray(s, float) + (dx, 0.0) for s in segs]
    if split is not None:
        p0, p1, p2, p3 = segs[split]
        a, b, c = (p0 + p1) / 2, (p1 + p2) / 2, (p2 + p3) / 2
        m = ((a + b) / 2 + (b + c) / 2) / 2
        segs[split:split + 1] = [np.array([p0, a, (a + b) / 2, m]),
                                 np.array([m, (b + c) / 2, c, p3])]
    text = "M%.9g %.9g " % tuple(segs[0][0])
    return text + " ".join("C" + " ".join("%.9g %.9g" % tuple(p) for p in s[1:]) for s in segs) + " Z"


def lens_chain(n):
    """n lenses of two arcs (radius 1, chord 1.2), each 0.001 right of the last."""
    return " ".join("M %g 0 A 1 1 0 0 1 %g 0 A 1 1 0 0 1 %g 0 Z" % (0.001 * i, 0.001 * i + 1.2,
                                                                   0.001 * i) for i in range(n))


def lens_union_area(n, samples=20000):
    """The lens chain's area by shapely: each arc sampled at ``samples`` points (the
    chords' area error ~ 1e-9 per lens), united."""
    import shapely
    from shapely.geometry import Polygon

    half = np.arcsin(0.6)
    t = np.linspace(-half, half, samples)
    # upper arc: centre (0.6, -0.8); lower arc: centre (0.6, 0.8)
    up = np.c_[0.6 + np.sin(t), -0.8 + np.cos(t)]
    down = np.c_[0.6 - np.sin(t), 0.8 - np.cos(t)]
    ring = np.vstack([up, down])
    return shapely.union_all([Polygon(ring + (0.001 * i, 0.0)) for i in range(n)]).area


def cases():
    """(name, path data, fill rule, expected area)."""
    out = []
    for n in (10, 100, 1000):
        out.append(("%d exact copies" % n, " ".join([blob_path()] * n), "nonzero", BLOB_AREA))
    d = " ".join(blob_path(k % 4, k % 3 == 2, (k // 3) % 4) for k in range(300))
    out.append(("300 copies, other starts and splits, 100 reversed", d, "nonzero", BLOB_AREA))
    d = " ".join(blob_path(k % 4, k % 2 == 1, k % 4) for k in range(300))
    out.append(("300 copies, 150 each way (winding 0)", d, "nonzero", 0.0))
    d = " ".join(blob_path(k % 4, False, k % 4) for k in range(301))
    out.append(("301 copies, evenodd (odd)", d, "evenodd", BLOB_AREA))
    for dx in (1e-6, 1e-5, 1e-4):
        d = " ".join([blob_path(), blob_path(backwards=True, dx=dx), blob_path(backwards=True, dx=-dx)])
        out.append(("3 copies %g apart, +1 -1 -1" % dx, d, "nonzero", BLOB_AREA))
    for n in (40, 100):
        out.append(("%d lenses shifted by 0.001" % n, lens_chain(n), "nonzero",
                    lens_union_area(n)))
    dots = " ".join("M %d %d a 1 1 0 1 0 2 0 a 1 1 0 1 0 -2 0 Z" % (3 * i, 3 * j)
                    for i in range(45) for j in range(45))
    out.append(("2025 disjoint dots (no copies: the probes' grid search)", dots, "nonzero",
                2025 * np.pi))
    return out


def run(d, rule, repeat, timeout):
    import tempfile

    svg = '<svg xmlns="http://www.w3.org/2000/svg"><path fill-rule="%s" d="%s"/></svg>' % (rule, d)
    with tempfile.NamedTemporaryFile("w", suffix=".svg", delete=False) as fh:
        fh.write(svg)
    best, out = np.inf, None
    for _ in range(repeat):
        t = time.perf_counter()
        try:
            res = subprocess.run([sys.executable, "-c", SCRIPT, fh.name], capture_output=True,
                                 text=True, timeout=timeout)
        except subprocess.TimeoutExpired:
            return timeout, None, "timeout (%g s)" % timeout
        best = min(best, time.perf_counter() - t)
        if res.returncode:
            return best, None, res.stderr.strip().splitlines()[-1]
        out = res.stdout.split()
    return best, (int(out[0]), float(out[1])), ""


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--md", default=None)
    ap.add_argument("--repeat", type=int, default=3)
    ap.add_argument("--timeout", type=float, default=600.0, help="seconds per process")
    args = ap.parse_args(argv)
    rows = ["| case | rule | process wall (min of %d) | loops | area | expected | ok |" % args.repeat,
            "|---|---|---|---|---|---|---|"]
    bad = 0
    for name, d, rule, expected in cases():
        wall, got, err = run(d, rule, args.repeat, args.timeout)
        if got is None:
            ok, loops, area = False, "-", err
        else:
            loops, area = got
            # the area within 1e-6 of the drawing's size squared (80 units; lenses 1.3,
            # dots 134)
            size = 1.3 if "lenses" in name else 134.0 if "dots" in name else 80.0
            ok = abs(area - expected) <= 1e-6 * size ** 2
        bad += not ok
        row = "| %s | %s | %.2f s | %s | %s | %s | %s |" % (
            name, rule, wall, loops, area if isinstance(area, str) else "%.4f" % area,
            "%.4f" % expected, "yes" if ok else "**no**")
        print(row, flush=True)
        rows.append(row)
    if args.md:
        with open(args.md, "w") as fh:
            fh.write("# Copies of one path (bench/coincident.py)\n\n")
            fh.write("Command: `python -m bench.coincident --md bench/coincident.md`.  "
                     "Whole `svg_region` processes (start-up ~0.3 s included).\n\n")
            fh.write("\n".join(rows) + "\n")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())

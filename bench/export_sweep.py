"""Random sweep of the certified cubic export (not a default test: thousands of cases).

    python bench/export_sweep.py [--cases 3000] [--seed 0] [--md bench/export_sweep.md]
                                 [--no-write] [--failures FILE.json]

Each case is a random piece (or a chain of pieces) in the plane, scaled by 10^U(-3, 4)
and shifted, and a tolerance tol = size * 10^U(-7, -1.5) (size: the largest extent of
the control points).  Kinds:

- ``rational``: degree 2-6, random points in [-1, 1]^2, weights U(0.3, 3) (as the
  Hypothesis test ``test_random_rational_pieces_within_tol``);
- ``rational-wide``: the same with weights 10^U(-1.3, 1.3) (0.05 ... 20);
- ``polynomial``: degree 4-7 (degree <= 3 is written exactly);
- ``chain``: a rational piece (weights U(0.3, 3)) split at 1-3 random parameters
  into consecutive pieces, exported with ``chain_segments`` (cubics span the joins).

For every case ``cubic_segments`` / ``chain_segments`` is run and checked against
oracles computed outside the module (tests/test_export.py: plain Bernstein sums with
math.comb, exact closest points by polynomial roots):

1. every segment's bound <= tol;
2. the certificate: for every panel of every segment, |R(phi(s)) - C(s)| at 1025
   samples <= bound (relative slack 1e-9, plus 1e-13 of the coordinates for rounding:
   a short last segment can have a bound of 2e-15 at coordinates 0.05, where the
   sampled difference is rounding too);
3. the two-sided Hausdorff distance between the cubics and the exact curve, with exact
   point-to-curve distances (closest_distances) from 129 samples per cubic and as many
   on the curve, <= tol;
4. exact ends and joins.

ToleranceNotMetError (the exporter refusing a tol it cannot certify) is counted apart:
it is an honest refusal, not a wrong answer.
"""

import argparse
import importlib.util
import json
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.errors import ToleranceNotMetError  # noqa: E402 - after sys.path gets the repo root
from morph.export import chain_segments, cubic_segments  # noqa: E402 - after sys.path gets the repo root


def _oracles():
    """The independent oracles of tests/test_export.py (bernstein, rational,
    closest_distances), loaded by path (tests/ is not a package)."""
    spec = importlib.util.spec_from_file_location("_export_oracles",
                                                  ROOT / "tests" / "test_export.py")
    mod = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(mod)
    return mod


KINDS = ("rational", "rational-wide", "polynomial", "chain")


def random_case(rng, kind):
    """(pieces, tol, description) for one random case."""
    if kind == "polynomial":
        n = int(rng.integers(4, 8))
        w = np.ones(n + 1)
    else:
        n = int(rng.integers(2, 7))
        w = (10.0 ** rng.uniform(-1.3, 1.3, n + 1) if kind == "rational-wide"
             else rng.uniform(0.3, 3.0, n + 1))
    scale = 10.0 ** rng.uniform(-3, 4)
    shift = rng.uniform(-10, 10, 2) * scale
    pts = rng.uniform(-1, 1, (n + 1, 2)) * scale + shift
    piece = pc.from_points(pts, w)
    size = float(np.ptp(pts, axis=0).max())
    tol = size * 10.0 ** rng.uniform(-7, -1.5)
    if kind == "chain":
        pieces = pc.split_at(piece, np.sort(rng.uniform(0.1, 0.9, int(rng.integers(1, 4)))))
    else:
        pieces = [piece]
    return pieces, tol


def check_case(o, pieces, tol):
    """(segments, export CPU seconds, worst certificate ratio sampled / bound,
    Hausdorff / tol, problems)."""
    problems = []
    t0 = time.process_time()
    segs = (cubic_segments(pieces[0], tol) if len(pieces) == 1
            else chain_segments(pieces, tol))
    seconds = time.process_time() - t0
    k = len(pieces)
    coords = max(float(np.abs(pc.cartesian(p)).max()) for p in pieces)
    if segs[0].t0 != 0.0 or segs[-1].t1 != float(k):
        problems.append("segments do not cover [0, %d]" % k)
    for a, b in zip(segs, segs[1:]):
        if a.t1 != b.t0 or not np.array_equal(a.cubic[-1], b.cubic[0]):
            problems.append("inexact join at T=%r" % a.t1)
    for end, want in ((segs[0].cubic[0], pc.start(pieces[0])),
                      (segs[-1].cubic[-1], pc.end(pieces[-1]))):
        if np.abs(end - want).max() > 1e-12 * (1.0 + coords):
            problems.append("end moved by %.3g" % np.abs(end - want).max())

    def chain_point(T):
        T = np.asarray(T, float)
        j = np.clip(np.floor(T).astype(int), 0, k - 1)
        out = np.empty((len(T), 2))
        for i in range(k):
            sel = j == i
            if sel.any():
                out[sel] = o.rational(pieces[i])(T[sel] - i)
        return out

    cert = 0.0
    for seg in segs:
        if not seg.bound <= tol:
            problems.append("bound %.6g > tol %.6g" % (seg.bound, tol))
        for s0, s1, phi in seg.reparam:
            s = np.linspace(s0, s1, 1025)
            ph, x = np.asarray(phi, float), (s - s0) / (s1 - s0)
            if ph.ndim == 2:   # homogeneous [numerator, weight]: a Möbius factor
                v = o.bernstein(ph, x)
                u = v[:, 0] / v[:, 1]
            else:
                u = o.bernstein(ph[:, None], x)[:, 0]
            err = float(np.hypot(*(chain_point(u) - o.bernstein(seg.cubic, s)).T).max())
            cert = max(cert, err / (seg.bound + 1e-13 * coords))
            if err > seg.bound * (1 + 1e-9) + 1e-13 * coords:
                problems.append("certificate: sampled %.6g > bound %.6g on panel [%g, %g]"
                                % (err, seg.bound, s0, s1))
    cubics = [seg.cubic for seg in segs]
    on_cubics = np.vstack([o.bernstein(c, np.linspace(0, 1, 129)) for c in cubics])
    on_curve = chain_point(np.linspace(0.0, float(k), 129 * len(cubics)))
    haus = max(float(o.closest_distances(on_cubics, pieces).max()),
               float(o.closest_distances(on_curve, cubics).max()))
    if haus > tol * (1 + 1e-9):
        problems.append("Hausdorff %.6g > tol %.6g" % (haus, tol))
    return segs, seconds, cert, haus / tol, problems


def run(cases, seed, failures_path=None):
    o = _oracles()
    rng = np.random.default_rng(seed)
    stats = {k: dict(cases=0, cubics=0, seconds=0.0, refused=0, failed=0, cert=0.0,
                     haus=0.0, ratios=[]) for k in KINDS}
    failures = []
    t_all = time.perf_counter()
    for i in range(cases):
        kind = KINDS[i % len(KINDS)]
        pieces, tol = random_case(rng, kind)
        st = stats[kind]
        st["cases"] += 1
        try:
            segs, seconds, cert, haus, problems = check_case(o, pieces, tol)
        except ToleranceNotMetError as exc:
            st["refused"] += 1
            failures.append(dict(case=i, kind=kind, tol=tol, refused=str(exc),
                                 pieces=[p.tolist() for p in pieces]))
            continue
        st["seconds"] += seconds
        st["cubics"] += len(segs)
        st["cert"] = max(st["cert"], cert)
        st["haus"] = max(st["haus"], haus)
        st["ratios"].append(haus)
        if problems:
            st["failed"] += 1
            failures.append(dict(case=i, kind=kind, tol=tol, problems=problems,
                                 pieces=[p.tolist() for p in pieces]))
            print("case %d (%s, tol %.3g): %s" % (i, kind, tol, "; ".join(problems[:3])),
                  flush=True)
    if failures_path:
        Path(failures_path).write_text(json.dumps(failures, indent=1))
    return stats, failures, time.perf_counter() - t_all


def markdown(stats, cases, seed, wall):
    lines = ["# Certified cubic export: random sweep (bench/export_sweep.py)", "",
             "Command: `python bench/export_sweep.py --cases %d --seed %d` (%.0f s wall, "
             "shared 2-core machine).  Checks and oracles: see the script's docstring "
             "(certificate sampled at 1025 points per panel; Hausdorff distance with "
             "exact closest points, 129 samples per cubic)." % (cases, seed, wall), "",
             "| kind | cases | failed | refused (ToleranceNotMetError) | cubics | "
             "export CPU s | worst sampled / (bound + 1e-13 coords) | worst Hausdorff / tol | "
             "median Hausdorff / tol |",
             "|---|---|---|---|---|---|---|---|---|"]
    for kind in KINDS:
        st = stats[kind]
        med = float(np.median(st["ratios"])) if st["ratios"] else float("nan")
        lines.append("| %s | %d | %d | %d | %d | %.1f | %.6f | %.4f | %.3f |" % (
            kind, st["cases"], st["failed"], st["refused"], st["cubics"], st["seconds"],
            st["cert"], st["haus"], med))
    lines += ["", "A case fails when a segment's bound exceeds tol, a panel's sampled error "
              "exceeds its bound (beyond 1e-9 relative and 1e-13 of the coordinates), the "
              "Hausdorff distance exceeds tol, or an end or join is not exact.  Export CPU: "
              "process time of cubic_segments / chain_segments alone.", "",
              "History: the Hypothesis test `test_random_rational_pieces_within_tol` "
              "failed on a rational cubic with a near-cusp (tests/test_export.py "
              "`NEAR_CUSP`: 2.1e-4 measured at tol 1e-4); its oracle, a ternary search "
              "between arc-length samples, put both branches of the hairpin in one bracket "
              "and found the far one (exact distance 9.25e-5, within the certified 9.25e-5). "
              "A first exact oracle with power-basis roots then flagged 8 'rational-wide' "
              "cases of the first 1345 (up to 150 tol on a degree-6 piece with weights "
              "0.05 ... 19 at coordinates ~1e5): ill-conditioned roots, not the export; "
              "roots in the Chebyshev basis (colleague matrix) measure them at <= 0.9953 "
              "tol.  The exporter itself was not changed."]
    return "\n".join(lines) + "\n"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--cases", type=int, default=3000)
    ap.add_argument("--seed", type=int, default=0)
    ap.add_argument("--md", default=str(ROOT / "bench" / "export_sweep.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--failures", default=None, help="write failing cases to this JSON")
    args = ap.parse_args(argv)
    stats, failures, wall = run(args.cases, args.seed, args.failures)
    md = markdown(stats, args.cases, args.seed, wall)
    print(md)
    if not args.no_write:
        Path(args.md).write_text(md)
    return 1 if any(st["failed"] for st in stats.values()) else 0


if __name__ == "__main__":
    sys.exit(main())

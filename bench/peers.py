"""morph vs flatten-then-Clipper polygon peers: time, output size and measured error.

    python bench/peers.py                       # full run (about 8-10 min), writes bench/peers.md
    python bench/peers.py --cases TM,OM --tols 1e-3,1e-4 --no-write   # a subset
    python bench/peers.py --quick               # T+M, O+M, S+g at 1e-3, 1e-4 only

Cases (bundled Noto Sans TrueType, upm 1000, font units): T+M, O+M, S+g, O + nib,
a 10-frame T->M morph, and a brush-swept A-Z (each capital ⊕ nib).  The nib is the
exact rational ellipse rx 40, ry 15, rotated 30 degrees.  Tolerances are in em
(x 1000 font units).

Methods
- ``morph``: ``morph.trim.minkowski_sum(a, b, tol)`` (``morph_frames`` for the morph).
  Size = control points (sum over pieces of len(piece)).
- ``clipper``: flatten both regions within tol/2 and sum them with pyclipper
  (MinkowskiSum of every loop pair + union with translated copies so holes come out
  right) -- ``tests.reference.polygon_minkowski_sum``.  Size = polygon vertices.
- ``cdt-hull``: convex decomposition + union: constrained Delaunay triangulation of both
  flattened regions (shapely), convex hull of every triangle pair, unary union
  (``tests.reference.brute_force_minkowski_sum``).  O(N*M) hulls: only run where the
  triangle-pair count is below --cdt-max-pairs; otherwise reported as skipped.

Runs whose predicted time exceeds --budget seconds (the Clipper peer grows ~N*M with
the vertex counts; the prediction scales the previous tolerance's time by the square
of the vertex ratio) are skipped and say so.

Error = two-sided Hausdorff distance between boundaries, against a reference polygon
(``polygon_minkowski_sum`` at the finest tolerance whose predicted time fits
--ref-budget, 1e-6 em when possible; the reference tolerance is printed per case, and
errors below it are not resolved).  Our curves are flattened at tol/50 for the
measurement.  Boundaries are sampled every ``spacing`` = max(tol/4, ref tol) units
and the distance to the other side is exact (shapely STRtree of segments).

Times: median of --repeats runs (default 5) for the single sums, 1 run for the morph
and A-Z (stated in the table); perf_counter, font loading excluded.
"""

import argparse
import statistics
import sys
import time
from pathlib import Path

import numpy as np
import shapely

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph import parse, trim  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.frames import centered, morph_frames, scale_region  # noqa: E402 - after sys.path gets the repo root
from tests import reference as R  # noqa: E402 - after sys.path gets the repo root

UPM = 1000.0
TOLS_EM = (1e-2, 1e-3, 1e-4, 1e-5)
NIB = [pc.ellipse((0.0, 0.0), 40.0, 15.0, np.radians(30.0))]
FRAMES = 10
# measured: the Clipper union of N*M edge quads grows like (N*M)**2.4 on these glyphs
# (O+M: 3e4 pairs 3 s, 2.2e5 pairs 388 s); 2.0 is used for the prediction
GROWTH = 2.0


def glyph(ch):
    return parse.glyph_region(ch).region


def ctrl_points(loops):
    return int(sum(len(p) for loop in loops for p in loop))


def poly_vertices(geom):
    n = 0
    for poly in R._polygons(geom):
        n += len(poly.exterior.coords) - 1
        n += sum(len(r.coords) - 1 for r in poly.interiors)
    return n


def timed(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t)
    return statistics.median(times), out


# ----------------------------------------------------------------- error measure

def _rings(x, flat):
    """List of closed (m, 2) rings: from shapely polygons or from loops of pieces."""
    if isinstance(x, shapely.Geometry):
        return R._loops_of(x)
    return [pc.flatten_loop(loop, flat) for loop in x]


def _segments(rings):
    a = np.concatenate(rings)
    b = np.concatenate([np.roll(r, -1, axis=0) for r in rings])
    return a, b


def _densify(rings, spacing):
    pts = []
    for r in rings:
        a, b = r, np.roll(r, -1, axis=0)
        n = np.maximum(np.ceil(np.hypot(*(b - a).T) / spacing), 1).astype(int)
        k = np.repeat(np.arange(len(a)), n)
        f = (np.arange(n.sum()) - np.repeat(np.cumsum(n) - n, n)) / np.repeat(n, n)
        pts.append(a[k] + f[:, None] * (b[k] - a[k]))
    return np.concatenate(pts)


def _one_sided(points, tree, geoms):
    idx, dist = tree.query_nearest(shapely.points(points), return_distance=True, all_matches=False)
    out = np.full(len(points), np.inf)
    np.minimum.at(out, idx[0], dist)
    return float(out.max())


def boundary_hausdorff(rings_a, rings_b, spacing):
    """Two-sided Hausdorff distance of two sets of closed rings (boundary sampling)."""
    trees = []
    for rings in (rings_a, rings_b):
        a, b = _segments(rings)
        geoms = shapely.linestrings(np.stack([a, b], axis=1))
        trees.append((shapely.STRtree(geoms), geoms))
    pa = _densify(rings_a, spacing)
    pb = _densify(rings_b, spacing)
    return max(_one_sided(pa, *trees[1]), _one_sided(pb, *trees[0]))


# ----------------------------------------------------------------------- runners

class Budget:
    """Predicts the next Clipper time from the last one and the vertex counts."""

    def __init__(self, limit):
        self.limit = limit
        self.last = None  # (time, flattened vertex product)

    def fits(self, nprod):
        if self.last is None:
            return True
        t, n = self.last
        return t * (nprod / max(n, 1)) ** GROWTH <= self.limit

    def record(self, t, nprod):
        self.last = (t, nprod)


def flat_count(region, tol):
    return sum(len(p) for p in R.region_polylines(region, tol))


def reference(a, b, budget, log):
    """Finest feasible polygon reference: coarse to fine (1e-3 ... 1e-6 em), stopping
    before a run predicted (from the previous one) to exceed the budget."""
    best, last = None, None
    for tol_em in (1e-3, 1e-4, 1e-5, 1e-6):
        tol = tol_em * UPM
        nprod = flat_count(a, tol / 2) * flat_count(b, tol / 2)
        if last is not None and last[0] * (nprod / last[1]) ** GROWTH > budget:
            break
        t = time.perf_counter()
        geom = R.polygon_minkowski_sum(a, b, tol)
        last = (max(time.perf_counter() - t, 1e-3), nprod)
        best = (tol_em, R._loops_of(geom))
    log("  reference at %g em (%.1f s)" % (best[0], last[0]))
    return best


def run_sum_case(name, a, b, tols, args, log, repeats):
    ref_em, ref_rings = reference(a, b, args.ref_budget, log)
    ref_tol = ref_em * UPM
    rows = []
    budget = Budget(args.budget)
    for tol_em in tols:
        tol = tol_em * UPM
        spacing = max(tol / 4, ref_tol)
        t_ours, loops = timed(lambda: trim.minkowski_sum(a, b, tol), repeats)
        err_ours = boundary_hausdorff(_rings(loops, tol / 50), ref_rings, spacing)
        row = dict(case=name, tol=tol_em, ref=ref_em, repeats=repeats, t_ours=t_ours,
                   n_ours=ctrl_points(loops), e_ours=err_ours)
        nprod = flat_count(a, tol / 2) * flat_count(b, tol / 2)
        if budget.fits(nprod):
            rep = repeats if (budget.last is None or budget.last[0] < 2.0) else 1
            t_peer, geom = timed(lambda: R.polygon_minkowski_sum(a, b, tol), rep)
            budget.record(t_peer, nprod)
            row.update(t_peer=t_peer, n_peer=poly_vertices(geom), peer_rep=rep,
                       e_peer=boundary_hausdorff(R._loops_of(geom), ref_rings, spacing))
        else:
            row.update(t_peer=None, n_peer=None, e_peer=None, peer_rep=0)
        if args.cdt and nprod <= args.cdt_max_pairs:
            pa = R.region_to_shapely(a, tol / 2)
            pb = R.region_to_shapely(b, tol / 2)
            t_cdt, g2 = timed(lambda: R.brute_force_minkowski_sum(pa, pb), 1)
            row.update(t_cdt=t_cdt, n_cdt=poly_vertices(g2),
                       e_cdt=boundary_hausdorff(R._loops_of(g2), ref_rings, spacing))
        else:
            row.update(t_cdt=None, n_cdt=None, e_cdt=None)
        rows.append(row)
        log(fmt_row(row))
    return rows


def run_morph(tols, args, log):
    """10-frame T->M: total time of the 8 inner sums; error = max over frames."""
    a, b = centered(glyph("T")), centered(glyph("M"))
    alphas = np.linspace(0, 1, FRAMES)[1:-1]
    pairs = [(scale_region(a, 1 - al), scale_region(b, al)) for al in alphas]
    refs = []
    t0 = time.perf_counter()
    for fa, fb in pairs:
        refs.append(reference(fa, fb, args.ref_budget / len(pairs), lambda s: None))
    log("  morph references: %.1f s, finest %g em" % (time.perf_counter() - t0,
                                                      max(r[0] for r in refs)))
    ref_em = max(r[0] for r in refs)
    rows = []
    budget = Budget(args.budget)
    for tol_em in tols:
        tol = tol_em * UPM
        spacing = max(tol / 4, ref_em * UPM)
        t_ours, frames = timed(lambda: morph_frames(glyph("T"), glyph("M"), FRAMES, tol), 1)
        inner = frames[1:-1]
        e_ours = max(boundary_hausdorff(_rings(f, tol / 50), r[1], spacing)
                     for f, r in zip(inner, refs))
        row = dict(case="T->M morph, %d frames" % FRAMES, tol=tol_em, ref=ref_em, repeats=1,
                   t_ours=t_ours, n_ours=sum(ctrl_points(f) for f in inner), e_ours=e_ours,
                   t_cdt=None, n_cdt=None, e_cdt=None)
        _peer_columns(row, pairs, refs, tol, spacing, budget)
        rows.append(row)
        log(fmt_row(row))
    return rows


def _peer_columns(row, pairs, refs, tol, spacing, budget):
    """Run flatten+Clipper on (a, b) pairs once if the budget allows; fill row's peer columns."""
    nprod = sum(flat_count(fa, tol / 2) * flat_count(fb, tol / 2) for fa, fb in pairs)
    if not budget.fits(nprod):
        row.update(t_peer=None, n_peer=None, e_peer=None, peer_rep=0)
        return
    t = time.perf_counter()
    geoms = [R.polygon_minkowski_sum(fa, fb, tol) for fa, fb in pairs]
    budget.record(time.perf_counter() - t, nprod)
    row.update(t_peer=budget.last[0], peer_rep=1,
               n_peer=sum(poly_vertices(g) for g in geoms),
               e_peer=max(boundary_hausdorff(R._loops_of(g), r[1], spacing)
                          for g, r in zip(geoms, refs)))


def run_az(tols, args, log):
    """Brush-swept A-Z: each capital ⊕ nib; totals over the 26 sums, error = max."""
    letters = [chr(c) for c in range(ord("A"), ord("Z") + 1)]
    regions = [glyph(c) for c in letters]
    refs = [reference(g, NIB, args.ref_budget / 26, lambda s: None) for g in regions]
    ref_em = max(r[0] for r in refs)
    log("  A-Z references: finest common %g em" % ref_em)
    rows = []
    budget = Budget(args.budget)
    for tol_em in tols:
        tol = tol_em * UPM
        spacing = max(tol / 4, ref_em * UPM)
        t = time.perf_counter()
        outs = [trim.minkowski_sum(g, NIB, tol) for g in regions]
        t_ours = time.perf_counter() - t
        e_ours = max(boundary_hausdorff(_rings(o, tol / 50), r[1], spacing)
                     for o, r in zip(outs, refs))
        row = dict(case="A-Z ⊕ nib (26 sums)", tol=tol_em, ref=ref_em, repeats=1,
                   t_ours=t_ours, n_ours=sum(ctrl_points(o) for o in outs), e_ours=e_ours,
                   t_cdt=None, n_cdt=None, e_cdt=None)
        _peer_columns(row, [(g, NIB) for g in regions], refs, tol, spacing, budget)
        rows.append(row)
        log(fmt_row(row))
    return rows


# ------------------------------------------------------------------------ output

def _f(x, spec):
    return "skipped" if x is None else format(x, spec)


def _ratio(a, b, spec=".2g"):
    return "-" if (a is None or b is None or b == 0) else format(a / b, spec)


HEADER = ("| case | tol (em) | ref (em) | runs | morph time (s) | Clipper time (s) | time ratio "
          "| morph ctrl pts | Clipper vertices | size ratio | morph error (em) "
          "| Clipper error (em) | CDT+hull time (s) | CDT+hull vertices | CDT+hull error (em) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def fmt_row(r):
    runs = "%d / %d" % (r["repeats"], r.get("peer_rep", 0))
    e = lambda x: None if x is None else x / UPM  # noqa: E731
    return "| %s | %g | %g | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        r["case"], r["tol"], r["ref"], runs, _f(r["t_ours"], ".3f"), _f(r["t_peer"], ".3f"),
        _ratio(r["t_ours"], r["t_peer"]), r["n_ours"], _f(r["n_peer"], "d"),
        _ratio(r["n_ours"], r["n_peer"]), _f(e(r["e_ours"]), ".2g"), _f(e(r["e_peer"]), ".2g"),
        _f(r["t_cdt"], ".3f"), _f(r["n_cdt"], "d"), _f(e(r["e_cdt"]), ".2g"))


CASES = {
    "TM": ("T + M", lambda: (glyph("T"), glyph("M"))),
    "OM": ("O + M", lambda: (glyph("O"), glyph("M"))),
    "Sg": ("S + g", lambda: (glyph("S"), glyph("g"))),
    "Onib": ("O ⊕ nib", lambda: (glyph("O"), NIB)),
}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="TM,OM,Sg,Onib,morph,AZ",
                    help="comma list of TM, OM, Sg, Onib, morph, AZ")
    ap.add_argument("--tols", default=",".join("%g" % t for t in TOLS_EM), help="em")
    ap.add_argument("--repeats", type=int, default=5, help="runs per small case (median)")
    ap.add_argument("--budget", type=float, default=25.0,
                    help="skip a Clipper run predicted to take longer (s)")
    ap.add_argument("--ref-budget", type=float, default=25.0,
                    help="time allowed for each case's reference polygon (s)")
    ap.add_argument("--no-cdt", dest="cdt", action="store_false")
    ap.add_argument("--cdt-max-pairs", type=float, default=4e4,
                    help="run CDT+hull only when vertex product <= this")
    ap.add_argument("--quick", action="store_true", help="TM,OM,Sg at 1e-3,1e-4")
    ap.add_argument("--no-write", dest="write", action="store_false")
    args = ap.parse_args(argv)
    if args.quick:
        args.cases, args.tols = "TM,OM,Sg", "1e-3,1e-4"
    tols = [float(t) for t in args.tols.split(",")]
    lines = []

    def log(s):
        print(s, flush=True)
        if s.startswith("|"):
            lines.append(s)

    t_start = time.perf_counter()
    print(HEADER, flush=True)
    rows = []
    for key in args.cases.split(","):
        if key in CASES:
            name, make = CASES[key]
            a, b = make()
            rows += run_sum_case(name, a, b, tols, args, log, args.repeats)
        elif key == "morph":
            rows += run_morph(tols, args, log)
        elif key == "AZ":
            rows += run_az(tols, args, log)
        else:
            raise SystemExit("unknown case %r" % key)
    total = time.perf_counter() - t_start

    # ratios at equal measured error: smallest peer output whose error <= ours
    summary = ["| case | tol (em) | morph ctrl pts | morph error (em) | Clipper vertices at "
               "error <= ours (tol) | ratio Clipper / morph |", "|---|---|---|---|---|---|"]
    for r in rows:
        same = [q for q in rows if q["case"] == r["case"] and q["e_peer"] is not None
                and q["e_peer"] <= max(r["e_ours"], q["ref"] * UPM)]
        if same:
            q = min(same, key=lambda q: q["n_peer"])
            summary.append("| %s | %g | %d | %.2g | %d (%g) | %.1f |" % (
                r["case"], r["tol"], r["n_ours"], r["e_ours"] / UPM, q["n_peer"], q["tol"],
                q["n_peer"] / r["n_ours"]))
        else:
            summary.append("| %s | %g | %d | %.2g | none measured (skipped or all coarser) | - |"
                           % (r["case"], r["tol"], r["n_ours"], r["e_ours"] / UPM))
    print()
    print("\n".join(summary))
    print("\ntotal %.0f s" % total)
    if args.write:
        out = ROOT / "bench" / "peers.md"
        text = ["# morph vs flatten-then-Clipper: time, size, measured error", "",
                "Generated by `python bench/peers.py %s` in %.0f s on this machine (%s)."
                % (" ".join(argv if argv is not None else sys.argv[1:]), total,
                   "2 cores"), "",
                "Times: 'runs' = morph runs / Clipper runs (median); ratios are morph / peer. "
                "Errors are two-sided boundary Hausdorff distances to the reference polygon "
                "('ref', Clipper at that tolerance): errors below 'ref' are not resolved. "
                "'skipped' = predicted over the time budget. CDT+hull = constrained Delaunay "
                "triangles of both flattened operands, hull of each pair, union; run only "
                "where the pair count is small.", "",
                HEADER] + lines + ["", "## Size at equal measured error", "",
                                   "For each morph row, the smallest Clipper polygon (any "
                                   "tolerance) whose measured error is <= the morph error "
                                   "(or the reference resolution).", ""] + summary
        out.write_text("\n".join(text) + "\n")
        print("wrote", out)


if __name__ == "__main__":
    main()

"""morph vs flatten-then-Clipper polygon peers: time, output size and certified error.

    python bench/peers.py                       # full run (about 6-9 min), writes bench/peers.md
    python bench/peers.py --cases TM,OM --tols 1e-3,1e-4 --no-write   # a subset
    python bench/peers.py --quick               # T+M, O+M, S+g at 1e-3, 1e-4, no CLI

Cases (bundled Noto Sans TrueType, upm 1000, font units): T+M, O+M, S+g, O + nib,
a 10-frame T->M morph (the 8 inner sums), a brush-swept A-Z (each capital ⊕ nib) and
the CLI run ``morph glyph T M --frames 10`` (SVG + PNG + GIF, wall time).  The nib is
the exact rational ellipse rx 40, ry 15, rotated 30 degrees.  Tolerances in em
(x 1000 font units).

Methods
- ``morph``: ``morph.trim.minkowski_sum(a, b, tol)`` (``morph_frames`` for the morph).
  Size = control points (sum over pieces of len(piece)).
- ``clipper``: flatten both regions within tol/2 and sum them with pyclipper
  (MinkowskiSum of every loop pair + union with translated copies so holes come out
  right) -- ``tests.reference.polygon_minkowski_sum``.  Size = polygon vertices.
- ``cdt-hull``: constrained Delaunay triangles of both flattened regions (shapely),
  hull of every triangle pair, union (``tests.reference.brute_force_minkowski_sum``);
  only where the vertex product is below --cdt-max-pairs.

Error (bench/measure.py; independent of morph.trim and of any coarse polygon): a
certified upper bound on the distance from the output boundary to the exact boundary
of A ⊕ B, by the straddle test with the exact predicate x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅
on the operands flattened within --oracle-flat em (default 1e-6 em).  Resolution:
bounds are e + 2*flat with e on a ladder of ratio 1.33 starting at flat/10, so nothing
below ~2.1e-6 em is resolved at the default.  Samples: 16 parameters per output piece
(8 for A-Z), edge midpoints of the polygons (at most 4000 per polygon, random subset
beyond).  One-sided (output -> exact boundary): a missing part of the boundary is not
measured here (tests/test_trim.py checks membership on random points for that).

Size at equal error: for a morph row with certified error e, the peer's vertex count
at error <= e is (measured) the smallest Clipper polygon whose certified error is <= e;
otherwise two labelled estimates: (LB) a lower bound for any polygon within e of
morph's boundary, integral of sqrt(curvature / (16 e)) ds (an edge may deviate +-e,
sagitta 2e; the sqrt(k / (8 e)) count of a polygon with vertices on the curve is
printed too), and (fit) a power law n = c e**-p fitted to the measured Clipper
(error, vertices) rows of that case, extrapolated to e.

Runs whose predicted time exceeds --budget seconds (the Clipper peer grows ~N*M with
the vertex counts; the prediction scales the previous tolerance's time by the square
of the vertex ratio) are skipped and say so.  Times: median of --repeats runs
(default 5) for the single sums (Clipper: 1 run when predicted to take > 2 s),
1 run for the morph and A-Z; perf_counter, font loading and measuring excluded.
"""

import argparse
import os
import statistics
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np
ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

from morph import parse, trim  # noqa: E402 - after sys.path gets the repo root
from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.frames import centered, morph_frames, scale_region  # noqa: E402 - after sys.path gets the repo root
from tests import reference as R  # noqa: E402 - after sys.path gets the repo root
from bench import measure as ME  # noqa: E402 - after sys.path gets the repo root

UPM = 1000.0
TOLS_EM = (1e-2, 1e-3, 1e-4, 1e-5)
NIB = [pc.ellipse((0.0, 0.0), 40.0, 15.0, np.radians(30.0))]
FRAMES = 10
# measured: the Clipper union of N*M edge quads grows like (N*M)**2.4 on these glyphs
# (O+M: 3e4 pairs 3 s, 2.2e5 pairs 388 s); 2.0 is used for the prediction
GROWTH = 2.0
E_MAX = 0.05 * UPM  # largest error the ladder looks for (units)


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

def err_curves(loops, oracles, per_piece=16):
    """Certified error (units) of morph output: max over samples, several sums."""
    out = 0.0
    for lp, o in zip(loops, oracles):
        p, n = ME.sample_pieces(lp, per_piece)
        out = max(out, float(ME.certified_error(p, n, o, o.flat / 10, E_MAX).max()))
    return out


def err_polys(geoms, oracles):
    """Certified error (units) of polygons (edge midpoints), max over several sums."""
    out = 0.0
    for g, o in zip(geoms, oracles):
        p, n = ME.sample_polygon(g, 4000)
        out = max(out, float(ME.certified_error(p, n, o, o.flat / 10, E_MAX).max()))
    return out


# ----------------------------------------------------------------------- runners

class Budget:
    """Predicts the next Clipper time from the last one and the vertex counts."""

    def __init__(self, limit):
        self.limit = limit
        self.last = None  # (time, flattened vertex product)

    def predict(self, nprod):
        t, n = self.last
        return t * (nprod / max(n, 1)) ** GROWTH

    def fits(self, nprod):
        return self.last is None or self.predict(nprod) <= self.limit

    def record(self, t, nprod):
        self.last = (t, nprod)


def flat_count(region, tol):
    return sum(len(p) for p in R.region_polylines(region, tol))


def run_pairs(name, pairs, tols, args, log, repeats, per_piece=16, morph_fn=None):
    """One table block: morph vs Clipper (and CDT+hull) on a list of (A, B) pairs whose
    sizes and times add up and whose errors are the max over the pairs."""
    t0 = time.perf_counter()
    oracles = [ME.Oracle(a, b, args.oracle_flat * UPM) for a, b in pairs]
    log("  %s: %d oracle(s) at %g em built in %.1f s" % (name, len(oracles), args.oracle_flat,
                                                          time.perf_counter() - t0))
    rows = []
    budget = Budget(args.budget)
    for tol_em in tols:
        tol = tol_em * UPM
        try:
            if morph_fn is None:
                t_ours, outs = timed(lambda: [trim.minkowski_sum(a, b, tol) for a, b in pairs],
                                     repeats)
            else:
                t_ours, outs = timed(lambda: morph_fn(tol), repeats)
        except Exception as exc:  # a core failure is a result: report it, go on
            log("  %s at %g em: morph FAILED: %s: %s" % (name, tol_em, type(exc).__name__, exc))
            continue
        row = dict(case=name, tol=tol_em, repeats=repeats, t_ours=t_ours,
                   n_ours=sum(ctrl_points(o) for o in outs),
                   e_ours=err_curves(outs, oracles, per_piece), outs=outs)
        nprod = sum(flat_count(a, tol / 2) * flat_count(b, tol / 2) for a, b in pairs)
        if budget.fits(nprod):
            rep = repeats if (budget.last is None or budget.predict(nprod) < 2.0) else 1
            t_peer, geoms = timed(lambda: [R.polygon_minkowski_sum(a, b, tol) for a, b in pairs],
                                  rep)
            budget.record(t_peer, nprod)
            row.update(t_peer=t_peer, n_peer=sum(poly_vertices(g) for g in geoms), peer_rep=rep,
                       e_peer=err_polys(geoms, oracles))
        else:
            row.update(t_peer=None, n_peer=None, e_peer=None, peer_rep=0)
        if args.cdt and len(pairs) == 1 and nprod <= args.cdt_max_pairs:
            a, b = pairs[0]
            pa, pb = R.region_to_shapely(a, tol / 2), R.region_to_shapely(b, tol / 2)
            t_cdt, g2 = timed(lambda: R.brute_force_minkowski_sum(pa, pb), 1)
            row.update(t_cdt=t_cdt, n_cdt=poly_vertices(g2), e_cdt=err_polys([g2], oracles))
        else:
            row.update(t_cdt=None, n_cdt=None, e_cdt=None)
        rows.append(row)
        log(fmt_row(row))
    return rows


def run_morph(tols, args, log):
    """10-frame T->M: the 8 inner sums (1-a)T ⊕ aM; morph_frames timed as a whole."""
    a, b = centered(glyph("T")), centered(glyph("M"))
    alphas = np.linspace(0, 1, FRAMES)[1:-1]
    pairs = [(scale_region(a, 1 - al), scale_region(b, al)) for al in alphas]
    gt, gm = glyph("T"), glyph("M")
    return run_pairs("T->M morph, %d frames" % FRAMES, pairs, tols, args, log, 1,
                     morph_fn=lambda tol: morph_frames(gt, gm, FRAMES, tol)[1:-1])


def run_az(tols, args, log):
    letters = [chr(c) for c in range(ord("A"), ord("Z") + 1)]
    pairs = [(glyph(c), NIB) for c in letters]
    return run_pairs("A-Z ⊕ nib (26 sums)", pairs, tols, args, log, 1, per_piece=8)


def run_cli(args, log):
    """Wall time of `morph glyph T M --frames 10` (SVG, PNG, GIF), median of --cli-repeats."""
    times = []
    with tempfile.TemporaryDirectory() as tmp:
        for k in range(args.cli_repeats):
            out = os.path.join(tmp, "r%d" % k)
            t = time.perf_counter()
            subprocess.run([sys.executable, "-m", "morph.cli", "glyph", "T", "M", "--frames",
                            str(FRAMES), "-o", out], check=True, capture_output=True)
            times.append(time.perf_counter() - t)
            npng = len([f for f in os.listdir(out) if f.endswith(".png")])
    line = ("CLI `morph glyph T M --frames %d` (default tol, %d PNGs + SVGs + GIF): wall %.2f s "
            "median of %d (min %.2f, max %.2f; includes Python start-up and imports)"
            % (FRAMES, npng, statistics.median(times), len(times), min(times), max(times)))
    log(line)
    return line


# ------------------------------------------------------------------------ output

def _f(x, spec):
    return "skipped" if x is None else format(x, spec)


def _ratio(a, b, spec=".2g"):
    return "-" if (a is None or b is None or b == 0) else format(a / b, spec)


def _e(x):
    return None if x is None else x / UPM


HEADER = ("| case | tol (em) | runs | morph time (s) | Clipper time (s) | time ratio "
          "| morph ctrl pts | Clipper vertices | morph error <= (em) "
          "| Clipper error <= (em) | CDT+hull time (s) | CDT+hull vertices | CDT+hull error <= (em) |\n"
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|")


def fmt_row(r):
    runs = "%d / %d" % (r["repeats"], r.get("peer_rep", 0))
    return "| %s | %g | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
        r["case"], r["tol"], runs, _f(r["t_ours"], ".3f"), _f(r["t_peer"], ".3f"),
        _ratio(r["t_ours"], r["t_peer"]), r["n_ours"], _f(r["n_peer"], "d"),
        _f(_e(r["e_ours"]), ".2g"), _f(_e(r["e_peer"]), ".2g"),
        _f(r["t_cdt"], ".3f"), _f(r["n_cdt"], "d"), _f(_e(r["e_cdt"]), ".2g"))


EQ_HEADER = ("| case | tol (em) | morph ctrl pts | morph error <= (em) | Clipper measured at "
             "error <= ours: vertices (tol) | ratio | LB any polygon | ratio LB | inscribed "
             "chords | fit: Clipper extrapolated (n = c e^-p) | ratio fit |\n"
             "|---|---|---|---|---|---|---|---|---|---|---|")


def equal_error_rows(rows):
    out = []
    for r in rows:
        e = r["e_ours"]
        peers = [q for q in rows if q["case"] == r["case"] and q["e_peer"] is not None]
        # errors at the oracle's resolution (<= 3 flat) are not distinguished
        ok = [q for q in peers if q["e_peer"] <= max(e, 3 * _ARGS.oracle_flat * UPM)]
        if ok:
            q = min(ok, key=lambda q: q["n_peer"])
            meas, mratio = "%d (%g)" % (q["n_peer"], q["tol"]), "%.1f" % (q["n_peer"] / r["n_ours"])
        else:
            meas, mratio = "not reached", "-"
        lb, ins = ME.chord_counts([lp for o in r["outs"] for lp in o], e)
        fit = ME.powerlaw([q["e_peer"] for q in peers if q["e_peer"] > 1.5 * e_floor(r)],
                          [q["n_peer"] for q in peers if q["e_peer"] > 1.5 * e_floor(r)])
        if fit is not None and not ok:
            nfit = fit[0] * e ** (-fit[1])
            fits, fratio = "%.3g (p = %.2f)" % (nfit, fit[1]), "%.1f" % (nfit / r["n_ours"])
        else:
            fits, fratio = ("-" if ok else "too few points"), "-"
        out.append("| %s | %g | %d | %.2g | %s | %s | %d | %.1f | %d | %s | %s |" % (
            r["case"], r["tol"], r["n_ours"], e / UPM, meas, mratio, lb, lb / r["n_ours"], ins,
            fits, fratio))
    return out


def e_floor(r):
    return _ARGS.oracle_flat * UPM * 2.1


_ARGS = None

CASES = {
    "TM": ("T + M", lambda: (glyph("T"), glyph("M"))),
    "OM": ("O + M", lambda: (glyph("O"), glyph("M"))),
    "Sg": ("S + g", lambda: (glyph("S"), glyph("g"))),
    "Onib": ("O ⊕ nib", lambda: (glyph("O"), NIB)),
}


def main(argv=None):
    global _ARGS
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--cases", default="TM,OM,Sg,Onib,morph,AZ,cli",
                    help="comma list of TM, OM, Sg, Onib, morph, AZ, cli")
    ap.add_argument("--tols", default=",".join("%g" % t for t in TOLS_EM), help="em")
    ap.add_argument("--repeats", type=int, default=5, help="runs per small case (median)")
    ap.add_argument("--budget", type=float, default=160.0,
                    help="skip a Clipper run predicted to take longer (s)")
    ap.add_argument("--oracle-flat", type=float, default=1e-6,
                    help="flattening of the operands for the exact-membership oracle (em)")
    ap.add_argument("--no-cdt", dest="cdt", action="store_false")
    ap.add_argument("--cdt-max-pairs", type=float, default=4e4,
                    help="run CDT+hull only when vertex product <= this")
    ap.add_argument("--cli-repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="TM,OM,Sg at 1e-3,1e-4")
    ap.add_argument("--no-write", dest="write", action="store_false")
    args = ap.parse_args(argv)
    _ARGS = args
    if args.quick:
        args.cases, args.tols = "TM,OM,Sg", "1e-3,1e-4"
    tols = [float(t) for t in args.tols.split(",")]
    lines, notes = [], []

    def log(s):
        print(s, flush=True)
        if s.startswith("|"):
            lines.append(s)
        elif not s.startswith("CLI"):
            notes.append(s.strip())

    t_start = time.perf_counter()
    print(HEADER, flush=True)
    rows, cli = [], None
    for key in args.cases.split(","):
        if key in CASES:
            name, make = CASES[key]
            rows += run_pairs(name, [make()], tols, args, log, args.repeats)
        elif key == "morph":
            rows += run_morph(tols, args, log)
        elif key == "AZ":
            rows += run_az(tols, args, log)
        elif key == "cli":
            cli = run_cli(args, log)
        else:
            raise SystemExit("unknown case %r" % key)
    total = time.perf_counter() - t_start

    summary = [EQ_HEADER] + equal_error_rows(rows)
    print()
    print("\n".join(summary))
    print("\ntotal %.0f s" % total)
    if args.write:
        out = ROOT / "bench" / "peers.md"
        text = ["# morph vs flatten-then-Clipper: time, size, certified error", "",
                "Generated by `python bench/peers.py %s` in %.0f s on this machine (2 cores, "
                "shared with other jobs: times are noisy)."
                % (" ".join(argv if argv is not None else sys.argv[1:]), total), "",
                "Times: 'runs' = morph runs / Clipper runs (median); time ratio = morph / "
                "Clipper. 'error <=' = certified upper bound on the distance from the output "
                "boundary to the exact boundary of A ⊕ B (bench/measure.py: straddle test "
                "with the exact predicate on operands flattened within %g em; resolution "
                "~%.2g em, nothing below is resolved). 'skipped' = predicted over the %g s "
                "budget. CDT+hull = constrained Delaunay triangles of both flattened operands, "
                "hull of each pair, union; run only where the pair count is small."
                % (args.oracle_flat, 2.1 * args.oracle_flat, args.budget), "",
                HEADER] + lines + [""] + (["## CLI", "", cli, ""] if cli else []) + [
                "## Size at equal certified error", "",
                "For each morph row with certified error e: 'Clipper measured' = the smallest "
                "Clipper polygon actually run whose certified error is <= e (same measure); "
                "'LB any polygon' = lower bound for ANY polygon within e of morph's boundary, "
                "integral of sqrt(curvature / (16 e)) ds (an estimate computed on morph's "
                "curves, not a run); 'inscribed chords' = the same with 8 e (vertices on the "
                "curve, as flatten-then-Clipper does); 'fit' = power law n = c e^-p fitted to "
                "the Clipper rows of the case with error above the resolution and "
                "extrapolated to e (an estimate; only where no measured polygon reaches e). "
                "Ratios are peer / morph (>= 5 is the target).", ""] + summary + [
                "", "Log notes: " + "; ".join(n for n in notes if n)]
        out.write_text("\n".join(text) + "\n")
        print("wrote", out)


if __name__ == "__main__":
    main()

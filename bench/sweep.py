"""Robustness sweep: every ordered glyph pair and every glyph ⊕ nib, checked.

    python -m bench.sweep [--fonts ttf,cff] [--set upper|lower|both] [--nibs|--no-nibs]
                          [--pairs|--no-pairs] [--limit N] [--tol EM] [--jobs J]
                          [--budget SECONDS] [--cases ttf:W:nib:ellipse,cff:C:S]

Jobs: every ordered pair A-Z x A-Z (``--set upper``) and/or a-z x a-z (``lower``) in
the bundled TrueType font (``ttf``) and its CFF version (``cff``,
``morph.parse.cubic_test_font_path()``), and every glyph of the set ⊕ three nibs
(disk r=30, thin ellipse 60x8 rotated 30 degrees, square 40x40; font units).

Each result of ``morph.trim.minkowski_sum(a, b, tol)`` is checked independently:

- closed loops (consecutive piece ends meet), each loop simple (its flattening is a
  valid shapely ring);
- straddle: sample points of the boundary pushed by tol + slack (slack = 1e-5 em +
  2e-3 units: flattening of the oracle) must see both the inside and the outside of
  the exact sum x ∈ A ⊕ B ⇔ A ∩ (x − B) ≠ ∅ (``tests.test_trim.Oracle``, inputs
  flattened to 1e-3 units);
- membership at random points in the box (winding number of our flattened loops vs
  the oracle); points within tol+slack of our boundary are not counted;
- against a coarse Clipper polygon sum (inputs flattened to ``REF_TOL`` units):
  outer/hole counts (components larger than tol*100 units^2), relative area
  (must be < 2e-3: the coarse reference is only that good) and Hausdorff distance
  (<= tol + REF_TOL + 1 unit, reported as "error").

Prints one summary line (jobs tried, failures, worst error, time); writes each
failure as bench/sweep_failures/<font>-<a>-<b>.png (ours black fill, reference red
outline) and a summary table to bench/sweep.md.  Jobs still queued when --budget
seconds have passed are reported as not run.
"""

import argparse
import os
import string
import sys
import time
import traceback
from concurrent.futures import ProcessPoolExecutor, as_completed
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

UPM = 1000.0
REF_TOL = 0.5          # units: flattening of the coarse Clipper reference
OUT_DIR = ROOT / "bench" / "sweep_failures"
NIBS = ("disk", "ellipse", "square")

_cache = {}


def nib(name):
    from morph import piece as pc

    if name == "disk":
        return [pc.circle([0.0, 0.0], 30.0)]
    if name == "ellipse":
        return [pc.ellipse([0.0, 0.0], 30.0, 4.0, np.radians(30.0))]
    if name == "square":
        p = [(-20.0, -20.0), (20.0, -20.0), (20.0, 20.0), (-20.0, 20.0)]
        return [[pc.line(p[i], p[(i + 1) % 4]) for i in range(4)]]
    raise ValueError(name)


def shape(font, name):
    key = (font, name)
    if key not in _cache:
        if name.startswith("nib:"):
            _cache[key] = nib(name[4:])
        else:
            from morph.parse import cubic_test_font_path, glyph_region

            path = cubic_test_font_path() if font == "cff" else None
            _cache[key] = glyph_region(name, path).region
    return _cache[key]


def _closed(loops, eps):
    from morph import piece as pc

    for loop in loops:
        for p, q in zip(loop, loop[1:] + loop[:1]):
            if np.hypot(*(pc.end(p) - pc.start(q))) > eps:
                return False
    return True


def check(font, a_name, b_name, tol, seed=0):
    """Run and check one sum; returns a dict (failures: list of strings)."""
    import shapely
    from shapely.geometry import Polygon

    from morph import piece as pc
    from morph.trim import minkowski_sum
    from tests import reference as R
    from tests.test_trim import Oracle, _boundary_samples, _inside, straddle

    a, b = shape(font, a_name), shape(font, b_name)
    res = {"font": font, "a": a_name, "b": b_name, "fail": [], "error": 0.0}
    t0 = time.time()
    try:
        loops = minkowski_sum(a, b, tol)
    except Exception as exc:  # noqa: BLE001 - every crash is a finding
        res["fail"].append("exception %s: %s" % (type(exc).__name__,
                                                  " ".join(str(exc).split())[:200]))
        res["trace"] = traceback.format_exc()
        res["time"] = time.time() - t0
        return res
    res["time_sum"] = time.time() - t0
    res["loops"] = loops
    if not loops:
        res["fail"].append("empty result")
        return res
    scale = max(np.ptp(np.concatenate([pc.cartesian(p) for l in loops for p in l]), axis=0))
    if not _closed(loops, 1e-9 * scale + 1e-9):
        res["fail"].append("open loop")
    for k, loop in enumerate(loops):
        ring = pc.flatten_loop(loop, tol / 4)
        if len(ring) < 3 or not Polygon(ring).is_valid:
            res["fail"].append("loop %d not simple" % k)
            break
    rng = np.random.default_rng(seed)
    slack = 1e-5 * UPM + 2e-3
    d = tol + slack
    oracle = Oracle(a, b, 1e-3)
    pts, nrm = _boundary_samples(loops)
    if len(pts) > 40:
        pick = rng.choice(len(pts), 40, replace=False)
        pts, nrm = pts[pick], nrm[pick]
    inside = straddle(oracle, pts, nrm, d)
    bad_out = ~inside.any(axis=1)
    bad_in = inside.all(axis=1)
    if bad_out.any():
        res["fail"].append("straddle: %d boundary points > tol+slack outside the sum, e.g. %s"
                           % (bad_out.sum(), np.round(pts[bad_out][0], 3).tolist()))
    if bad_in.any():
        res["fail"].append("straddle: %d boundary points > tol+slack inside the sum, e.g. %s"
                           % (bad_in.sum(), np.round(pts[bad_in][0], 3).tolist()))
    lo = np.min([pc.bbox(p)[:2] for l in loops for p in l], axis=0) - 20
    hi = np.max([pc.bbox(p)[2:] for l in loops for p in l], axis=0) + 20
    x = rng.uniform(lo, hi, size=(60, 2))
    ours_poly = R.region_to_shapely(loops, tol / 4)
    near = shapely.distance(shapely.points(x), ours_poly.boundary) <= d
    x = x[~near]
    if len(x):
        ours = _inside(loops, x)
        truth = oracle(x)
        if not np.array_equal(ours, truth):
            res["fail"].append("membership differs at %d points, e.g. %s"
                               % ((ours != truth).sum(),
                                  np.round(x[ours != truth][0], 3).tolist()))
    # coarse Clipper reference
    ref = R.polygon_minkowski_sum(a, b, REF_TOL)
    res["ref"] = ref
    area = pc.region_area(loops)
    rel = abs(area - ref.area) / ref.area
    res["area_rel"] = rel
    if rel > 2e-3:
        res["fail"].append("area %.6g vs reference %.6g (rel %.2e)" % (area, ref.area, rel))
    min_area = 100 * tol
    ref_counts = R.count_outer_and_holes(ref, min_area)
    ours_counts = (sum(pc.loop_area(l) > min_area for l in loops),
                   sum(pc.loop_area(l) < -min_area for l in loops))
    if ours_counts != ref_counts:
        res["fail"].append("outer/holes %s vs reference %s" % (ours_counts, ref_counts))
    h = R.hausdorff(ours_poly, ref, spacing=2.0)
    res["error"] = h
    if h > tol + REF_TOL + 1.0:
        res["fail"].append("Hausdorff to reference %.4g > %.4g" % (h, tol + REF_TOL + 1.0))
    res["time"] = time.time() - t0
    return res


def _safe(name):
    return name.replace("nib:", "nib-")


def picture(res, path):
    from morph.render import write_png
    from tests import reference as R

    shapes = []
    if res.get("loops"):
        shapes.append((res["loops"], {"fill": "black"}))
    ref = res.get("ref")
    if ref is None:
        try:
            from morph.parse import cubic_test_font_path  # noqa: F401
            ref = R.polygon_minkowski_sum(shape(res["font"], res["a"]),
                                          shape(res["font"], res["b"]), REF_TOL)
        except Exception:  # noqa: BLE001
            ref = None
    if ref is not None and not ref.is_empty:
        from morph import piece as pc

        rings = []
        for poly in getattr(ref, "geoms", [ref]):
            for r in [poly.exterior, *poly.interiors]:
                c = np.asarray(r.coords)[:-1]
                rings.append([pc.line(c[i], c[(i + 1) % len(c)]) for i in range(len(c))])
        shapes.append((rings, {"fill": None, "stroke": "red", "stroke_width": 1.0}))
    if shapes:
        write_png(str(path), shapes, size=600)


def _job(args):
    font, a, b, tol = args
    try:
        res = check(font, a, b, tol)
    except Exception as exc:  # noqa: BLE001 - a crash of the checker itself
        res = {"font": font, "a": a, "b": b, "fail": ["checker crashed: %s: %s"
                                                      % (type(exc).__name__, exc)],
               "error": 0.0, "trace": traceback.format_exc()}
    if res["fail"]:
        OUT_DIR.mkdir(parents=True, exist_ok=True)
        stem = OUT_DIR / ("%s-%s-%s" % (font, _safe(a), _safe(b)))
        try:
            picture(res, str(stem) + ".png")
        except Exception as exc:  # noqa: BLE001
            res["fail"].append("picture failed: %s" % exc)
        if "trace" in res:
            Path(str(stem) + ".txt").write_text(res["trace"])
    res.pop("loops", None)
    res.pop("ref", None)
    return res


def jobs(fonts, sets, pairs, nibs, tol):
    """Nib jobs first (cheap, all fonts), then the pairs font by font, set by set."""
    out = []
    for stage in ("nibs", "pairs"):
        for font in fonts:
            for s in sets:
                letters = string.ascii_uppercase if s == "upper" else string.ascii_lowercase
                if stage == "pairs" and pairs:
                    out += [(font, a, b, tol) for a in letters for b in letters]
                if stage == "nibs" and nibs:
                    out += [(font, a, "nib:" + n, tol) for a in letters for n in NIBS]
    return out


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--fonts", default="ttf,cff")
    ap.add_argument("--set", default="both", choices=["upper", "lower", "both"])
    ap.add_argument("--nibs", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--pairs", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--limit", type=int, default=None, help="run only the first N jobs")
    ap.add_argument("--tol", type=float, default=1e-4, help="tolerance in em")
    ap.add_argument("--jobs", type=int, default=max(1, (os.cpu_count() or 1)))
    ap.add_argument("--budget", type=float, default=None, help="seconds")
    ap.add_argument("--md", default=str(ROOT / "bench" / "sweep.md"))
    ap.add_argument("--cases", default=None,
                    help="only these jobs: font:A:B,... (B may be nib:disk etc.)")
    opt = ap.parse_args(argv)
    fonts = [f.strip() for f in opt.fonts.split(",") if f.strip()]
    sets = ["upper", "lower"] if opt.set == "both" else [opt.set]
    todo = jobs(fonts, sets, opt.pairs, opt.nibs, opt.tol * UPM)
    if opt.cases:
        todo = [tuple(c.split(":", 2)) + (opt.tol * UPM,) for c in opt.cases.split(",")]
    if opt.limit is not None:
        todo = todo[:opt.limit]
    t0 = time.time()
    results = []
    with ProcessPoolExecutor(max_workers=opt.jobs) as ex:
        futs = [ex.submit(_job, j) for j in todo]
        for fut in as_completed(futs):
            results.append(fut.result())
            r = results[-1]
            if r["fail"]:
                print("FAIL %s %s+%s: %s" % (r["font"], r["a"], r["b"], "; ".join(r["fail"])),
                      flush=True)
            if opt.budget and time.time() - t0 > opt.budget:
                for f in futs:
                    f.cancel()
                break
    elapsed = time.time() - t0
    fails = [r for r in results if r["fail"]]
    worst = max(results, key=lambda r: r["error"]) if results else None
    line = ("sweep: %d of %d jobs tried, %d failures, worst Hausdorff to coarse reference "
            "%.4g units (%s %s+%s), %.1f s"
            % (len(results), len(todo), len(fails), worst["error"] if worst else 0.0,
               worst["font"] if worst else "-", worst["a"] if worst else "-",
               worst["b"] if worst else "-", elapsed))
    print(line)
    md = ["# Robustness sweep (bench/sweep.py)", "",
          "Command: `python -m bench.sweep %s`" % " ".join(argv if argv is not None
                                                             else sys.argv[1:]),
          "", line, "",
          "tol = %g em; checks: closed and simple loops, straddle within tol + 1e-5 em "
          "+ 2e-3 against the exact predicate, membership at random points, outer/hole "
          "counts, area and Hausdorff against a Clipper sum of inputs flattened to %g "
          "units." % (opt.tol, REF_TOL), ""]
    if fails:
        md += ["| font | A | B | failure | picture |", "|---|---|---|---|---|"]
        for r in sorted(fails, key=lambda r: (r["font"], r["a"], r["b"])):
            md.append("| %s | %s | %s | %s | sweep_failures/%s-%s-%s.png |"
                      % (r["font"], r["a"], r["b"], "; ".join(r["fail"]).replace("|", "/"),
                         r["font"], _safe(r["a"]), _safe(r["b"])))
    else:
        md.append("No failures.")
    Path(opt.md).write_text("\n".join(md) + "\n")
    return 1 if fails else 0


if __name__ == "__main__":
    sys.exit(main())

"""Real icons: parse, offset and ⊕ an ellipse, checked against a polygon reference.

Icon sets are fetched with ``npm pack`` into a temporary folder (not committed):
bootstrap-icons and @mdi/svg (filled), feather-icons (stroke-only centre lines).
For every chosen filled icon (size s = the larger side of its bounding box):

- ``svg_region`` must parse it (a parse failure is a failure of morph.parse);
- offset: ``morph.offset.offset_region(region, 0.05 s, tol)``;
- sum: ``morph.trim.minkowski_sum(region, ellipse(0.04 s, 0.015 s, 30°), tol)``;

at tol = 1e-3 s.  Reference: the region flattened within tol/20 (tests/reference.py,
Clipper nonzero union), then ``shapely.buffer`` for the offset (64 segments per
quarter circle) and Clipper's Minkowski sum with the ellipse flattened within tol/20
for the sum.  A result passes when the two-sided Hausdorff distance between the
boundaries (densified to tol/4) is <= 1.25 tol (tol plus the reference's own error
and the densification) and the numbers of outer loops and holes agree (ignoring
reference parts smaller than tol²); it is a *wrong shape* otherwise.  Each icon runs
in its own process with a time limit (a *hang* when exceeded); exceptions are
recorded with their type and message.

For the stroke set, ``svg_region`` must refuse each icon with the stroke-only line
and ``svg_paths`` must give its centre lines (open subpaths stay open).

    python -m bench.icons [--per-set 150] [--timeout 60] [--jobs 2] [-o bench/icons.md]
"""

import argparse
import glob
import multiprocessing as mp
import os
import subprocess
import sys
import tempfile
import time
import traceback
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

SETS = {  # npm package -> (glob of icon files inside the package, kind)
    "bootstrap-icons": ("package/icons/*.svg", "fill"),
    "@mdi/svg": ("package/svg/*.svg", "fill"),
    "feather-icons": ("package/dist/icons/*.svg", "stroke"),
}


def fetch(pkg, dest):
    """npm pack PKG into dest and unpack it; returns the package folder."""
    out = subprocess.run(["npm", "pack", pkg, "--silent"], cwd=dest, check=True,
                         capture_output=True, text=True).stdout.strip().splitlines()[-1]
    folder = Path(dest) / pkg.replace("/", "_").replace("@", "")
    folder.mkdir(exist_ok=True)
    subprocess.run(["tar", "xzf", str(Path(dest) / out), "-C", str(folder)], check=True)
    return folder, out


def choose(files, n):
    files = sorted(files)
    if len(files) <= n:
        return files
    idx = np.linspace(0, len(files) - 1, n).round().astype(int)
    return [files[i] for i in np.unique(idx)]


# =========================================================================== one icon

def check_filled(path, rec):
    from morph import piece as pc
    from morph.offset import offset_region
    from morph.region import region_bbox
    from morph.trim import minkowski_sum
    from morph.parse import svg_region
    from tests import reference as R

    t0 = time.perf_counter()
    region = svg_region(path)
    box = region_bbox(region)
    s = float(max(box[2] - box[0], box[3] - box[1]))
    tol = 1e-3 * s
    rec["parse_s"] = time.perf_counter() - t0
    ref_a = R.region_to_shapely(region, tol / 20)
    r = 0.05 * s
    nib = [pc.ellipse((0.0, 0.0), 0.04 * s, 0.015 * s, np.radians(30))]
    for name in ("offset", "ellipse"):
        rec["stage"] = name
        t0 = time.perf_counter()
        if name == "offset":
            out = offset_region(region, r, tol)
            ref = ref_a.buffer(r, quad_segs=64)
        else:
            out = minkowski_sum(region, nib, tol)
            ref = R.polyline_minkowski_sum(R.region_polylines(region, tol / 20),
                                           R.region_polylines(nib, tol / 20),
                                           R.default_scale(tol))
        rec[name + "_s"] = time.perf_counter() - t0
        got = R.region_to_shapely(out, tol / 20)
        d = R.hausdorff(got, ref, spacing=tol / 4)
        topo = (R.count_outer_and_holes(got, tol * tol), R.count_outer_and_holes(ref, tol * tol))
        rec[name + "_err"] = d / tol
        rec[name + "_topo"] = topo
        if d > 1.25 * tol or topo[0] != topo[1]:
            rec["wrong"] = "%s: Hausdorff %.3g tol, loops/holes %s vs reference %s" % (
                name, d / tol, topo[0], topo[1])
            return rec
    rec["stage"] = "done"
    return rec


def check_stroke(path, rec):
    from morph.errors import ParseError
    from morph.parse import svg_paths, svg_region

    t0 = time.perf_counter()
    try:
        svg_region(path)
        rec["wrong"] = "svg_region filled a stroke-only icon"
        return rec
    except ParseError as exc:
        if "stroke-only" not in str(exc):
            raise
    paths = svg_paths(path)
    rec["parse_s"] = time.perf_counter() - t0
    rec["paths"] = len(paths)
    rec["open"] = sum(1 for _, closed in paths if not closed)
    rec["stage"] = "done"
    return rec


def _worker(kind, path, queue):
    rec = {"icon": path, "stage": "parse"}
    try:
        rec = (check_filled if kind == "fill" else check_stroke)(path, rec)
    except Exception as exc:  # recorded, not raised: the bench goes on
        rec["error"] = "%s: %s" % (type(exc).__name__, " ".join(str(exc).split())[:200])
        rec["trace"] = traceback.format_exc(limit=-3)
    queue.put(rec)


def run_one(kind, path, timeout):
    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    proc = ctx.Process(target=_worker, args=(kind, path, queue))
    t0 = time.perf_counter()
    proc.start()
    proc.join(timeout)
    if proc.is_alive():
        proc.kill()
        proc.join()
        return {"icon": path, "hang": True, "wall_s": timeout}
    try:
        rec = queue.get(timeout=5)
    except Exception:
        rec = {"icon": path, "error": "worker died (exit code %s)" % proc.exitcode}
    rec["wall_s"] = time.perf_counter() - t0
    return rec


# =========================================================================== report

def classify(rec):
    if rec.get("hang"):
        return "hang"
    if "error" in rec:
        return "parse error" if rec.get("stage", "parse") == "parse" and \
            "ParseError" in rec["error"] else "exception"
    if "wrong" in rec:
        return "wrong shape"
    return "pass"


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-set", type=int, default=150)
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("-o", "--output", default=str(ROOT / "bench" / "icons.md"))
    args = ap.parse_args(argv)

    from concurrent.futures import ThreadPoolExecutor

    results = {}
    versions = {}
    with tempfile.TemporaryDirectory() as tmp:
        jobs = []
        for pkg, (pattern, kind) in SETS.items():
            folder, tgz = fetch(pkg, tmp)
            versions[pkg] = tgz
            for f in choose(glob.glob(str(folder / pattern)), args.per_set):
                jobs.append((pkg, kind, f))
        t_all = time.perf_counter()
        with ThreadPoolExecutor(args.jobs) as pool:  # each job forks its own process
            futs = [(pkg, kind, pool.submit(run_one, kind, f, args.timeout))
                    for pkg, kind, f in jobs]
            for pkg, kind, fut in futs:
                rec = fut.result()
                rec["icon"] = os.path.basename(rec["icon"])
                results.setdefault(pkg, []).append(rec)
                print(pkg, rec["icon"], classify(rec), rec.get("error", rec.get("wrong", "")),
                      flush=True)
        total = time.perf_counter() - t_all

    lines = ["# Real icons: parse, offset, ⊕ ellipse (bench/icons.py)", "",
             "`python -m bench.icons --per-set %d --timeout %g --jobs %d` (%.0f s wall). "
             "Packages: %s. tol = 1e-3 of the icon's size; offset radius 0.05 size; "
             "ellipse 0.04 x 0.015 size at 30°. Pass: Hausdorff <= 1.25 tol against the "
             "polygon reference and the same numbers of loops and holes."
             % (args.per_set, args.timeout, args.jobs, total, ", ".join(versions.values())),
             "", "| set | icons | pass | parse errors | exceptions | wrong shapes | hangs | "
             "median s/icon | max s/icon | worst err/tol |", "|---|---|---|---|---|---|---|---|---|---|"]
    for pkg, recs in results.items():
        cls = [classify(r) for r in recs]
        walls = [r["wall_s"] for r in recs if not r.get("hang")]
        errs = [max(r.get("offset_err", 0), r.get("ellipse_err", 0)) for r in recs
                if classify(r) == "pass"]
        lines.append("| %s | %d | %d | %d | %d | %d | %d | %.2f | %.1f | %s |" % (
            pkg, len(recs), cls.count("pass"), cls.count("parse error"),
            cls.count("exception"), cls.count("wrong shape"), cls.count("hang"),
            float(np.median(walls)) if walls else 0, max(walls) if walls else 0,
            "%.2f" % max(errs) if errs else "-"))
    lines += ["", "Stroke set: a pass is `svg_region` refusing the icon with the stroke-only "
              "line and `svg_paths` returning its centre lines.", "", "## Failures", ""]
    for pkg, recs in results.items():
        for r in recs:
            c = classify(r)
            if c != "pass":
                detail = r.get("wrong") or r.get("error") or "no result in %g s" % args.timeout
                lines.append("- %s `%s`: %s (stage %s): %s" % (pkg, r["icon"], c,
                                                             r.get("stage", "?"), detail))
    Path(args.output).write_text("\n".join(lines) + "\n")
    print("wrote", args.output)


if __name__ == "__main__":
    main()

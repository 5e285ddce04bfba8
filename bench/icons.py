"""Real icons: parse, offset, ⊕ an ellipse and inset, checked against a polygon reference.

Icon sets are fetched with ``npm pack`` into a temporary folder (not committed):
bootstrap-icons and @mdi/svg (filled), feather-icons (stroke-only centre lines).
For every chosen filled icon (size s = the larger side of its bounding box):

- ``svg_region`` must parse it (a parse failure is a failure of morph.parse);
- offset: ``morph.offset.offset_region(region, 0.05 s, tol)``;
- sum: ``morph.minkowski.minkowski_sum(region, ellipse(0.04 s, 0.015 s, 30°), tol)``;
- inset: ``morph.offset.offset_region(region, -0.02 s, tol)`` (the erosion);

at tol = 1e-3 s.  Reference: the region flattened within tol/20 (tests/reference.py,
Clipper nonzero union; tol/200 for the inset, which keeps the input's cracks), then
``shapely.buffer`` for the offset and the inset (64 segments per quarter circle; a
negative distance for the inset) and Clipper's Minkowski sum with the ellipse flattened within tol/20
for the sum.  A result passes (:func:`compare`, the contract of ``minkowski_sum``)
when, with both boundaries densified to tol/4:

- every point of our boundary is within 1.25 tol of the reference's (tol plus the
  reference's own error and the densification): the certified direction, reported
  as "err/tol";
  except points in a gap of ours narrower than 0.2 tol that the reference fills (its
  own flattening error closes such hairline gaps where two parts touch tangentially:
  @mdi/svg power-socket-de offset); these are counted, and a spurious slit of ours
  that narrow would go unnoticed;
- every point of the reference's boundary is within 1.25 tol of ours, except where
  the reference has a gap, notch or hole narrower than 2 GAP tol = 1.1 tol (the engine
  may close those: its docstring's 1 tol plus the reference's flattening), i.e. points
  inside the reference's morphological closing by GAP tol (an earlier version compared the
  plain two-sided Hausdorff distance and failed correct results at tangent notches,
  e.g. two rounded corners touching, and at reference slivers of 1e-5 tol²);
- the numbers of outer loops and holes (parts <= tol² not counted) of ours, or of ours
  with its hairline gaps (< 0.2 tol) closed, lie between those of the reference, of
  its closing and of its opening by GAP tol (where two parts of the exact sum touch at
  a point, e.g. @mdi/svg book-arrow-up and power-socket-de offset, ours keeps them
  apart by a hair, the reference merges them);

it is a *wrong shape* otherwise, except when the only fault is our boundary more
than 1.25 tol from the reference's at points inside a gap of ours narrower than 2 GAP
tol that the reference fills: the tip of a narrow wedge running on, which
``minkowski_sum``'s docstring states as a limit (0.5 tol / sin(theta/2)); such icons
count as *documented limit*, listed with the failures.  Each icon runs
in its own process limited to ``--timeout`` seconds of CPU (a *hang* when exceeded;
CPU, not wall time, so that other work on a shared machine does not make hangs) and
4 GiB of address space; exceptions are recorded with their type and message.

For the stroke set, ``svg_region`` must refuse each icon with the stroke-only line
and ``svg_paths`` must give its centre lines (open subpaths stay open).

    python -m bench.icons [--per-set 150] [--seed S] [--timeout 60] [--jobs 2] [-o bench/icons.md]
    python -m bench.icons --reduce ICON.svg --op offset|ellipse|inset --save tests/data/icons/X.json
    python -m bench.icons --case tests/data/icons/X.json     # rerun a saved reproducer

A failing icon is reduced (``--reduce``, :func:`reduce_case`) by dropping loops while
the failure kind stays (hang, the exception's type, or which criteria a wrong shape
fails) and saved as json (:func:`save_case`): the reproducers of tests/data/icons/,
run by tests/test_sweep_regressions.py.
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

from morph import moments as mo  # noqa: E402 - after sys.path gets the repo root
from tests.oracles.icons import (  # noqa: E402 - after sys.path gets the repo root
    GAP, OPS, check_filled, check_op, icon_size, load_case, save_case)

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


def choose(files, n, seed=None):
    """``n`` of ``files``: evenly spaced in name order (the icons earlier runs
    checked), or with ``seed`` a random sample of them (icons nobody looked at)."""
    files = sorted(files)
    if len(files) <= n:
        return files
    if seed is not None:
        idx = np.random.default_rng(seed).choice(len(files), n, replace=False)
        return [files[i] for i in sorted(idx)]
    idx = np.linspace(0, len(files) - 1, n).round().astype(int)
    return [files[i] for i in np.unique(idx)]


# =========================================================================== one icon

def _case_worker(region, op, s, queue):
    rec = {}
    try:
        check_op(region, op, s, rec)
    except Exception as exc:
        rec["error"] = "%s: %s" % (type(exc).__name__, " ".join(str(exc).split())[:200])
    queue.put(rec)


def run_case(region, op, s, timeout):
    """check_op in a forked, limited process (:func:`run_limited`)."""
    return run_limited(_case_worker, (region, op, s), timeout)


def failure_kind(rec):
    """What a reduced input must keep showing: hang, the exception type, or a wrong
    shape (with the criteria that failed)."""
    if rec.get("hang"):
        return "hang"
    if "error" in rec:
        return rec["error"].split(":")[0]
    if "wrong" in rec:
        w = rec["wrong"]
        return "wrong " + ",".join(k for k, m in (("boundary", "output boundary"),
                                                 ("missing", "reference boundary"),
                                                 ("topology", "loops/holes")) if m in w)
    if "limit" in rec:
        return "limit"
    return "pass"


def reduce_case(region, op, s, timeout, log=print):
    """Greedy delta debugging over loops: drop each loop in turn while the failure kind
    stays the same (a loop whose removal leaves an invalid region simply stays), then
    replace each remaining loop of more than 4 pieces by its bounding box where the
    failure stays.  Returns (region, record of the last failing run)."""
    from morph import piece as pc
    from morph.region import orient_region, region_bbox
    from morph.trim import fill_region

    base = run_case(region, op, s, timeout)
    kind = failure_kind(base)
    log("full input: %d loops, %s" % (len(region), kind))
    if kind == "pass":
        return region, base
    i = 0
    while i < len(region) and len(region) > 1:
        trial = region[:i] + region[i + 1:]
        try:
            trial = orient_region(trial, on_crossing=fill_region)
        except Exception:
            i += 1
            continue
        rec = run_case(trial, op, s, timeout)
        if failure_kind(rec) == kind:
            region, base = trial, rec
            log("  dropped loop %d: %d loops left" % (i, len(region)))
        else:
            i += 1
    for i in range(len(region)):  # a loop replaced by its bounding box (4 lines)
        if len(region[i]) <= 4:
            continue
        x0, y0, x1, y1 = region_bbox([region[i]])
        corners = [(x0, y0), (x1, y0), (x1, y1), (x0, y1)]
        if mo.loop_area(region[i]) < 0:
            corners = corners[::-1]
        box = [pc.line(corners[k], corners[(k + 1) % 4]) for k in range(4)]
        trial = region[:i] + [box] + region[i + 1:]
        rec = run_case(trial, op, s, timeout)
        if failure_kind(rec) == kind:
            region, base = trial, rec
            log("  loop %d replaced by its bounding box" % i)
    return region, base


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
    c0 = time.process_time()
    try:
        rec = (check_filled if kind == "fill" else check_stroke)(path, rec)
    except Exception as exc:  # recorded, not raised: the bench goes on
        rec["error"] = "%s: %s" % (type(exc).__name__, " ".join(str(exc).split())[:200])
        rec["trace"] = traceback.format_exc(limit=-3)
    rec["cpu_s"] = time.process_time() - c0
    queue.put(rec)


def run_one(kind, path, timeout):
    rec = run_limited(_worker, (kind, path), timeout)
    rec.setdefault("icon", path)
    return rec


MEMORY = 4 * 2 ** 30  # address space of one icon's process
WALL_FACTOR = 20      # wall-clock guard, x the CPU limit (the machine may be loaded)


def _limited(target, args, queue, cpu):
    import resource

    lim = int(np.ceil(cpu))
    resource.setrlimit(resource.RLIMIT_CPU, (lim, lim + 5))
    resource.setrlimit(resource.RLIMIT_AS, (MEMORY, MEMORY))
    target(*args, queue)


def run_limited(target, args, timeout):
    """``target(*args, queue)`` in a forked process limited to ``timeout`` seconds of CPU
    (a *hang* when it is killed for it: load on a shared machine does not count) and
    MEMORY bytes of address space (a MemoryError is recorded as an exception).  Returns
    the record the target put on the queue, with wall_s."""
    import queue as queue_mod
    import signal

    ctx = mp.get_context("fork")
    queue = ctx.Queue()
    proc = ctx.Process(target=_limited, args=(target, args, queue, timeout))
    t0 = time.perf_counter()
    proc.start()
    rec = None
    while rec is None:
        try:
            rec = queue.get(timeout=1.0)
        except queue_mod.Empty:
            if not proc.is_alive() or time.perf_counter() - t0 > WALL_FACTOR * timeout:
                break
    proc.join(5)
    if proc.is_alive():
        proc.kill()
        proc.join()
    wall = time.perf_counter() - t0
    if rec is None:
        if proc.exitcode == -signal.SIGXCPU or wall > WALL_FACTOR * timeout:
            rec = {"hang": True, "hang_why": "more than %g s CPU" % timeout
                   if proc.exitcode == -signal.SIGXCPU else "more than %g s wall"
                   % (WALL_FACTOR * timeout)}
        else:
            rec = {"error": "worker died (exit code %s)" % proc.exitcode}
    rec["wall_s"] = wall
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
    if "limit" in rec:
        return "documented limit"
    return "pass"


def kind_of(pkg):
    return SETS[pkg][1]


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--per-set", type=int, default=150)
    ap.add_argument("--seed", type=int, default=None, help="a random sample of each set "
                    "(default: evenly spaced in name order)")
    ap.add_argument("--timeout", type=float, default=60.0)
    ap.add_argument("--jobs", type=int, default=2)
    ap.add_argument("-o", "--output", default=str(ROOT / "bench" / "icons.md"))
    ap.add_argument("--records", metavar="JSON", help="also write every icon's record")
    ap.add_argument("--reduce", metavar="SVG", help="reduce one failing icon to the fewest "
                    "loops that still fail the same way (with --op, --save, --source)")
    ap.add_argument("--op", choices=OPS)
    ap.add_argument("--save", metavar="JSON", help="where --reduce writes the case")
    ap.add_argument("--source", default="", help="icon set, version and file, for the case")
    ap.add_argument("--case", metavar="JSON", help="rerun a saved case and print its record")
    args = ap.parse_args(argv)

    if args.case:
        region, op, s, meta = load_case(args.case)
        rec = run_case(region, op, s, args.timeout)
        print(meta.get("source", ""), op, failure_kind(rec), rec)
        return
    if args.reduce:
        from morph.parse import svg_region

        if args.reduce.endswith(".json"):  # a saved case, reduced further
            region, _op, s, _meta = load_case(args.reduce)
        else:
            region = svg_region(args.reduce)
            s = icon_size(region)
        small, rec = reduce_case(region, args.op, s, args.timeout)
        print("reduced:", len(small), "loops,", sum(len(lp) for lp in small), "pieces:",
              failure_kind(rec), rec.get("wrong") or rec.get("error") or "")
        if args.save:
            save_case(args.save, small, args.op, s, source=args.source,
                      found=rec.get("wrong") or rec.get("error") or failure_kind(rec))
            print("wrote", args.save)
        return

    from concurrent.futures import ThreadPoolExecutor

    # imported once here, inherited by every forked icon process (saves ~0.7 s CPU each)
    import importlib

    for mod in ("morph.offset", "morph.parse", "morph.trim", "tests.oracles.reference"):
        importlib.import_module(mod)

    results = {}
    versions = {}
    with tempfile.TemporaryDirectory() as tmp:
        jobs = []
        for pkg, (pattern, kind) in SETS.items():
            folder, tgz = fetch(pkg, tmp)
            versions[pkg] = tgz
            for f in choose(glob.glob(str(folder / pattern)), args.per_set, args.seed):
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

    lines = ["# Real icons: parse, offset, ⊕ ellipse, inset (bench/icons.py)", "",
             "`python -m bench.icons --per-set %d%s --timeout %g --jobs %d` (%.0f s wall). "
             "Packages: %s. tol = 1e-3 of the icon's size; offset radius 0.05 size; "
             "ellipse 0.04 x 0.015 size at 30°; inset radius 0.02 size. Pass (see the script's docstring): our boundary "
             "within 1.25 tol of the polygon reference's, the reference's within 1.25 tol of "
             "ours except in gaps narrower than %.2g tol, loop and hole counts between the "
             "reference's and those of its closing over such gaps and opening at such necks."
             % (args.per_set, "" if args.seed is None else " --seed %d" % args.seed,
                args.timeout, args.jobs, total, ", ".join(versions.values()), 2 * GAP),
             "", "CPU s/icon: the icon's whole process (parse, offset, ellipse sum, inset, "
             "polygon references and checks); engine CPU s: the three operations only. "
             "err/tol: our boundary's distance to the reference's (the certified direction); "
             "back/tol: the reference's to ours outside narrow gaps. Both over passing icons.",
             "", "| set | icons | pass | parse errors | exceptions | wrong shapes | hangs | "
             "documented limit | median CPU s/icon | max CPU s/icon | median engine CPU s | "
             "median wall s/icon | worst err/tol | worst back/tol |", "|---" * 14 + "|"]

    def fmt(vals, f=np.median, spec="%.2f"):
        return spec % f(vals) if vals else "-"

    for pkg, recs in results.items():
        cls = [classify(r) for r in recs]
        walls = [r["wall_s"] for r in recs if not r.get("hang")]
        cpus = [r["cpu_s"] for r in recs if "cpu_s" in r]
        eng = [sum(r.get(op + "_cpu", 0) for op in OPS) for r in recs if "inset_cpu" in r]
        ok = [r for r in recs if classify(r) == "pass"]
        errs = [max(r.get(op + "_err", 0) for op in OPS) for r in ok]
        backs = [max(r.get(op + "_back", 0) for op in OPS) for r in ok]
        lines.append("| %s | %d | %d | %d | %d | %d | %d | %d | %s | %s | %s | %s | %s | %s |"
                     % (pkg, len(recs), len(ok), cls.count("parse error"),
                        cls.count("exception"), cls.count("wrong shape"), cls.count("hang"),
                        cls.count("documented limit"),
                        fmt(cpus), fmt(cpus, max, "%.1f"), fmt(eng), fmt(walls),
                        fmt(errs, max) if kind_of(pkg) == "fill" else "-",
                        fmt(backs, max) if kind_of(pkg) == "fill" else "-"))
    if args.records:
        import json

        Path(args.records).write_text(json.dumps(results, indent=0, default=str))
    lines += ["", "Stroke set: a pass is `svg_region` refusing the icon with the stroke-only "
              "line and `svg_paths` returning its centre lines.", "", "## Failures", ""]
    for pkg, recs in results.items():
        for r in recs:
            c = classify(r)
            if c != "pass":
                detail = r.get("wrong") or r.get("error") or "; ".join(r.get("limit", [])) \
                    or r.get("hang_why", "hang")
                lines.append("- %s `%s`: %s (stage %s): %s" % (pkg, r["icon"], c,
                                                             r.get("stage", "?"), detail))
    Path(args.output).write_text("\n".join(lines) + "\n")
    print("wrote", args.output)


if __name__ == "__main__":
    main()

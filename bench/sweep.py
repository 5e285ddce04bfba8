"""Robustness sweep of Minkowski sums and strokes (the acceptance sweeps), checked.

    python -m bench.sweep [--mode pairs|random|stroke|fonts] [--jobs 1] [--timeout S]
                          [--n N] [--seed S] [--cases SPEC,SPEC...] [--md bench/sweep.md]
                          [--packed]
    pairs only:  [--fonts ttf,cff] [--set upper|lower|both] [--nibs|--no-nibs]
                 [--pairs|--no-pairs] [--limit N] [--tol EM] [--budget SECONDS]
                 (with --seed the jobs run in a shuffled order, so that a --budget or
                 --limit run samples every font, set and nib)

Modes (each writes its own section of bench/sweep.md):

``pairs`` (the original sweep): every ordered pair A-Z x A-Z (``--set upper``) and/or
a-z x a-z (``lower``) in the bundled TrueType font (``ttf``) and its CFF version
(``cff``, ``morph.parse.cubic_test_font_path()``), and every glyph of the set ⊕ three
nibs (disk r=30, thin ellipse 60x8 rotated 30 degrees, square 40x40; font units), at
``--tol`` em; checked by ``tests.oracles.sweep.check`` (straddle against the exact
predicate ``tests.oracles.membership.Oracle``, membership at random points, a coarse
Clipper sum; where the coarse sum's boundary is beyond its limit, one flattened 25
times finer decides: a coarse reference's thin notch runs on past its tip,
``tests.oracles.sweep.reference_distance``).

``random``: ``--n`` jobs drawn with ``--seed`` (printed; random if not given): a glyph
of a font (``--fonts``, default ttf,cff,lobster,cormorant,amiri: the bundled Noto Sans
TrueType and CFF, and fonts from PyPI: fontpkg-lobster, fontpkg-cormorant (variable,
default instance), fontpkg-amiri (Arabic naskh; the Arabic letters and presentation
forms of its cmap)) ⊕ an exact ellipse nib W x H font units (80x30, 60x8 or 40x40) at
an angle 1.7 k degrees (0 <= angle < 180), at tol = r x (glyph size: the longer side
of its bounding box), r log-uniform in [1e-5, 1e-1], everything (glyph, nib, tol)
scaled by s log-uniform in [1e-3, 1e3].  Checked by ``tests.oracles.sweep.verify``
against the exact
predicate for an ellipse nib E = M·disk:

    x ∈ A ⊕ E  ⇔  A ∩ (x − E) ≠ ∅  ⇔  dist(M⁻¹x, M⁻¹A) ≤ 1,

with A the glyph drawn by fontTools' own pen (components decomposed, TrueType implied
points by fontTools) and flattened within f = tol/64 by a chord bound on the second
differences, contours united nonzero by Clipper: nothing of morph's parsing, fill
or trimming is used by the oracle, and it is wrong only within f of the true boundary.

``stroke``: ``--n`` jobs: a glyph of the Relief SingleLine skeleton font (open cubic
centre lines; the full font named by the environment variable MORPH_RELIEF_UFO, else
the subset in tests/data) ⊕ an
ellipse nib as above, by ``morph.stroke.stroke_paths``, at tol r x size (r in [1e-4,
1e-2]), scaled by s.  Checked by ``verify`` against the exact predicate (P the
union of the centre lines flattened within tol/64, dist(M⁻¹x, M⁻¹P) ≤ 1), and against
a polygon reference: pyclipper's MinkowskiSum of the flattened path with the nib
polygon, united (``tests.oracles.stroke_reference.stroke_polygon``): area within (tol +
reference flattening) x perimeter, Hausdorff distance within tol + reference error.

``fonts``: ``--n`` ordered pairs glyph ⊕ glyph drawn from each other font
(lobster, cormorant, amiri) at ``--tol`` em, checked by :func:`check`.

:func:`verify` (random and stroke modes) checks, for one output region:

- the call raised nothing and returned within ``--timeout`` seconds (each job runs in
  its own forked process with a 4 GiB address-space limit; a hang is killed and is a
  failure);
- loops closed (gap between consecutive pieces <= 1e-9 x size) and simple, and no two
  loops cross or touch (the loops flattened within tol/64 form a simple linework;
  a crossing is confirmed at tol/1024 before it counts);
- orientation: the winding number of the output loops is 0 or 1 everywhere probed;
- straddle (budget): for boundary samples (4 per piece, up to 600, every junction
  turning by more than 45 degrees among them: a spike's or crack's tip), the disk of
  radius d = tol + 2f around the point (both normal points and 24 points of its
  circle; where these miss, 1440 dense probes) must hold points in and out of the
  exact sum.  The same test on a ladder of
  radii c·tol + 2f (c = 1, 1/2, ... 1/64) gives each point's error bound; the worst,
  over tol, is reported (it includes the oracle slack 2f = tol/32);
- dense (budget; random and stroke modes, whose oracle gives distances: every
  vertex of the loops flattened within tol/64, not a sample:
  a thin spike or crack has its tip at a junction, a vertex): a lower bound of the
  vertex's distance to the exact boundary (``NibOracle.distance_bound``: |d - 1| or
  d + 1 in M⁻¹ space times the smaller radius, less f and tol/64) must not exceed
  tol + 2f;
- membership (holes right): random points in the box, points 0.6 tol inside and
  outside the reference boundary, and the label (deepest) point of every hole and
  every filled part, both ours and the reference's: wherever the point is farther
  than tol + 2f from our boundary, our winding number (!= 0) must agree with the
  exact predicate, unless the point lies within THIN tol + 2f of the true boundary
  (the documented rule: features thinner than 2 THIN tol = 0.9 tol, twice the
  flattening and grid shares of ``morph.minkowski``, may merge; such points are
  counted as "thin");
- a polygon reference (random: the flattened glyph buffered by the unit disk in
  M⁻¹ space with 256 segments per quarter circle, mapped back; GEOS simplifies the
  buffer's input by 1 % of the distance, so its error is f + (4.7e-6 + 0.01) x max
  radius, more where that closes a notch; stroke: the Clipper sum above):
  |area - reference area| <= (tol + reference error) x reference perimeter; the
  distances between the reference boundary and ours are reported, not judged.

``--packed`` (random and stroke modes): each case's region is computed in one packed
call (``morph.minkowski.minkowski_sums`` / ``morph.stroke.stroke_many``, as the font
commands do) together with three transformed copies of itself (mirrored, turned by
90 degrees, halved), and its own result is checked as above.

Failures print a one-line reproducer, ``run_case(SPEC)`` (the check) and
``case_inputs(SPEC)`` (the arguments of ``minkowski_sum`` / ``stroke_paths``); with
``--failures FILE`` they are appended to FILE as soon as found.  A summary (counts,
worst error/tol, time per job by tolerance and scale) replaces the mode's section of
``--md``.
"""

import os

for _v in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_v, "1")  # the machine is shared; forked jobs stay one thread

import argparse  # noqa: E402 - after the BLAS thread counts are set
import math  # noqa: E402 - after the BLAS thread counts are set
import string  # noqa: E402 - after the BLAS thread counts are set
import sys  # noqa: E402 - after the BLAS thread counts are set
import time  # noqa: E402 - after the BLAS thread counts are set
import traceback  # noqa: E402 - after the BLAS thread counts are set
from pathlib import Path  # noqa: E402 - after the BLAS thread counts are set

import numpy as np  # noqa: E402 - after the BLAS thread counts are set

ROOT = Path(__file__).resolve().parent.parent
sys.path.insert(0, str(ROOT))

# the cases and their check: the oracles of the test suite
from tests.oracles.sweep import (  # noqa: E402 - after sys.path gets the repo root
    ANGLE_STEP, ASPECTS, LADDER, NIBS, ORACLE_SHARE, PACKED_ENV, RANDOM_FONTS, REF_TOL,
    SKELETONS, THIN, UPM, glyph, glyph_pool, parse_case, run_case, shape)

OUT_DIR = ROOT / "bench" / "sweep_failures"

def _safe(name):
    return name.replace("nib:", "nib-")


def picture(res, path):
    from morph.render import write_png
    from tests.oracles import reference as R

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




# ============================================================================ cases
#
# A case is one string (the reproducer):
#   nib/FONT/GLYPH/WxH/ANGLE/S/R      glyph ⊕ ellipse nib W x H at ANGLE degrees,
#                                     everything scaled by S, tol = R x glyph size x S
#   stroke/SRC/NAME/WxH/ANGLE/S/R    skeleton NAME of SRC (relief: a Relief glyph; feather:
#                                     a Feather icon) stroked by that nib
#   pair/FONT/A/B/TOL_EM              glyph ⊕ glyph, checked by check()

def repro_line(spec):
    """One line of Python (run in the repository root) that reruns a case."""
    c = parse_case(spec)
    if c["kind"] == "stroke":
        call = "from morph.stroke import stroke_paths as f"
    else:
        call = "from morph.minkowski import minkowski_sum as f"
    return ("python -c \"from tests.oracles.sweep import case_inputs, run_case; %s; "
            "f(*case_inputs('%s'))\"  # check: run_case('%s')['fail']" % (call, spec, spec))


def draw_random_cases(mode, n, seed, fonts):
    """n case strings drawn with ``seed`` (module docstring)."""
    rng = np.random.default_rng(seed)
    pools = {}
    out = []
    while len(out) < n:
        if mode == "stroke":
            font = fonts[rng.integers(len(fonts))]
            if font not in pools:
                pools[font] = SKELETONS[font][0]()
            r = float("%.2g" % 10 ** rng.uniform(-4, -2))
        else:
            font = fonts[rng.integers(len(fonts))]
            if font not in pools:
                pools[font] = glyph_pool(font)
            r = float("%.2g" % 10 ** rng.uniform(-5, -1))
        g = pools[font][rng.integers(len(pools[font]))]
        w, h = ASPECTS[rng.integers(len(ASPECTS))]
        angle = round(ANGLE_STEP * rng.integers(0, int(math.ceil(180 / ANGLE_STEP))), 1)
        s = float("%.3g" % 10 ** rng.uniform(-3, 3))
        spec = "%s/%s/%s/%gx%g/%g/%g/%g" % ("stroke" if mode == "stroke" else "nib", font, g,
                                            w, h, angle, s, r)
        if mode != "stroke":
            try:
                glyph(font, g)
            except Exception:  # noqa: BLE001 - an empty glyph (no contours): draw again
                pools[font].remove(g)
                continue
        else:
            try:
                if not any(len(p) for p, _ in SKELETONS[font][1](g)):
                    pools[font].remove(g)
                    continue
            except Exception:  # noqa: BLE001
                pools[font].remove(g)
                continue
        out.append(spec)
    return out


def draw_font_pairs(n, seed, fonts=("lobster", "cormorant", "amiri"), tol_em=1e-4):
    rng = np.random.default_rng(seed)
    out = []
    for font in fonts:
        pool = glyph_pool(font)
        k = 0
        while k < n:
            a, b = pool[rng.integers(len(pool))], pool[rng.integers(len(pool))]
            try:
                glyph(font, a), glyph(font, b)
            except Exception:  # noqa: BLE001
                continue
            out.append("pair/%s/%s/%s/%g" % (font, a, b, tol_em))
            k += 1
    return out


# ============================================================================ pool

def _child(spec, conn, memory):
    import resource

    try:
        resource.setrlimit(resource.RLIMIT_AS, (memory, memory))
    except (ValueError, OSError):
        pass
    try:
        res = run_case(spec)
    except BaseException as exc:  # noqa: BLE001 - a crash of the checker itself
        res = {"spec": spec, "fail": ["checker crashed: %s: %s" % (type(exc).__name__,
                                                                  " ".join(str(exc).split())[:300])],
               "trace": traceback.format_exc()}
    try:
        conn.send(res)
    finally:
        conn.close()


def run_pool(specs, workers=1, timeout=300.0, memory=4 * 2 ** 30, on_result=None,
             budget=None):
    """Run ``run_case`` on every spec, each in its own forked process (at most
    ``workers`` at once) with ``timeout`` seconds and ``memory`` bytes of address
    space; a job over time is killed and reported as failed.  Returns the results
    in completion order; ``on_result(res)`` is called as each arrives.  With
    ``budget`` (seconds), jobs not started by then are not run."""
    import multiprocessing as mp
    from multiprocessing.connection import wait

    ctx = mp.get_context("fork")
    queue = list(specs)[::-1]
    running = {}          # conn -> (proc, spec, start)
    results = []
    t_start = time.time()

    def finish(res):
        results.append(res)
        if on_result:
            on_result(res)

    while queue or running:
        while queue and len(running) < workers and not (budget and time.time() - t_start > budget):
            spec = queue.pop()
            rd, wr = ctx.Pipe(duplex=False)
            p = ctx.Process(target=_child, args=(spec, wr, memory), daemon=True)
            p.start()
            wr.close()
            running[rd] = (p, spec, time.time())
        if not running:
            break
        now = time.time()
        next_deadline = min(st + timeout for _, _, st in running.values())
        ready = wait(list(running), timeout=max(0.0, next_deadline - now))
        for conn in ready:
            p, spec, st = running.pop(conn)
            try:
                res = conn.recv()
            except EOFError:
                p.join(5)
                res = {"spec": spec, "fail": ["process died (exit code %s; memory limit %d "
                                              "GiB?)" % (p.exitcode, memory >> 30)]}
            conn.close()
            p.join(5)
            res["wall"] = time.time() - st
            finish(res)
        now = time.time()
        for conn in [c for c, (_, _, st) in running.items() if now - st > timeout]:
            p, spec, st = running.pop(conn)
            p.kill()
            p.join(5)
            conn.close()
            finish({"spec": spec, "fail": ["timeout: no result after %.0f s (killed)"
                                           % timeout], "wall": now - st})
    return results


# ============================================================================ report

def _commit():
    import subprocess

    try:
        head = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=ROOT,
                              capture_output=True, text=True).stdout.strip()
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no",
                                "morph"], cwd=ROOT, capture_output=True,
                               text=True).stdout.strip()
        return head + (" + uncommitted changes in morph/" if dirty else "")
    except OSError:
        return "?"


def record_failure(path, res, mode):
    """Append one failure (reproducer, what failed) to ``path`` (for the lead)."""
    spec = res["spec"]
    line = ("- [%s, %s, code %s] `%s`: %s\n  `%s`\n"
            % (time.strftime("%Y-%m-%d %H:%M"), mode, _commit(), spec,
               "; ".join(res["fail"]).replace("\n", " ")[:600],
               repro_line(spec)))
    with open(path, "a") as fh:
        fh.write(line)


def _fmt_stats(vals):
    vals = np.asarray([v for v in vals if v is not None and np.isfinite(v)], float)
    if not len(vals):
        return "-"
    return "%.2f / %.2f / %.2f" % (np.median(vals), vals.mean(), vals.max())


def summarize(mode, results, todo, elapsed, command, seed, workers, timeout):
    fails = [r for r in results if r["fail"]]
    exc = [r for r in fails if any(f.startswith(("exception", "process died", "checker"))
                                   for f in r["fail"])]
    tout = [r for r in fails if any(f.startswith("timeout") for f in r["fail"])]
    lines = ["Command: `%s` (code: commit %s; %d worker%s, timeout %g s per job; %s)"
             % (command, _commit(), workers, "s" if workers > 1 else "", timeout,
                time.strftime("%Y-%m-%d")), ""]
    if seed is not None:
        lines += ["Seed: %d" % seed, ""]
    lines.append("%d of %d jobs run, %d failed (%d exceptions or crashes, %d timeouts), "
                 "%.0f s wall." % (len(results), len(todo), len(fails), len(exc), len(tout),
                                   elapsed))
    refused = [r for r in results if r.get("refused")]
    if refused:
        lines.append("%d refused their tolerance with a LimitError and passed at the tolerance "
                     "it suggested: %s." % (len(refused), ", ".join(
                         "`%s` (%.3g)" % (r["spec"], r["refused"]) for r in refused[:5])))
    lines.append("")
    meas = [r for r in results if np.isfinite(r.get("ref_dist/tol", np.nan))]
    if meas:
        w = max(meas, key=lambda r: r["ref_dist/tol"])
        lines.append("Distance from sampled output boundary points to the polygon "
                     "reference's boundary / tol (informative only: GEOS simplifies the "
                     "buffer's input by 1 %% of the nib radius and can close notches): "
                     "worst %.3f (`%s`), median over jobs %.3f."
                     % (w["ref_dist/tol"], w["spec"],
                        float(np.median([r["ref_dist/tol"] for r in meas]))))
    errs = [r for r in results if np.isfinite(r.get("err/tol", np.nan))]
    if errs:
        w = max(errs, key=lambda r: r["err/tol"])
        lines.append("Worst error bound / tol over all sampled boundary points "
                     "(straddle ladder, includes the oracle slack 2f = tol/32): "
                     "**%.3f** (`%s`)." % (w["err/tol"], w["spec"]))
        hist = {}
        for r in errs:
            k = min((c for c in LADDER if r["err/tol"] <= c + ORACLE_SHARE * 2 + 1e-12),
                    default=r["err/tol"] - 2 * ORACLE_SHARE)
            hist[k] = hist.get(k, 0) + 1
        lines.append("Jobs by worst error bound / tol: " + ", ".join(
            "<= %.3g: %d" % (k + 2 * ORACLE_SHARE, hist[k]) for k in sorted(hist)) + ".")
        pm = sum(r.get("probe_misses", 0) for r in results)
        lines.append("Straddle probe misses (a hole's tip narrower than 15 degrees; "
                     "confirmed within tol + 2f by 1440 dense probes of the exact "
                     "predicate): %d points." % pm)
        th = sum(r.get("thin", 0) for r in results)
        lines.append("Membership points on the wrong side inside features thinner than "
                     "%.2g tol (allowed by the budget): %d." % (2 * THIN, th))
        if any("hausdorff/tol" in r for r in results):
            hh = max(r.get("hausdorff/tol", 0.0) for r in results)
            lines.append("Worst Hausdorff distance to the Clipper reference / tol: %.3f." % hh)
        lines.append("")
    if mode == "pairs" or any(r["spec"].startswith("pair/") for r in results):
        pr = [r for r in results if r["spec"].startswith("pair/")]
        if pr:
            w = max(pr, key=lambda r: r.get("error", 0.0))
            lines.append("Pairs: worst Hausdorff to the Clipper reference (coarse, or 25 "
                         "times finer where the coarse one is beyond its limit) %.4g units "
                         "(`%s`)." % (w.get("error", 0.0), w["spec"]))
            lines.append("")
    # time per job, by group
    def group_table(title, key):
        groups = {}
        for r in results:
            k = key(r)
            if k is not None:
                groups.setdefault(k, []).append(r)
        if not groups:
            return []
        out = ["| %s | jobs | failed | sum time s (median / mean / max) | check time s "
               "(median / mean / max) | worst error bound / tol |" % title,
               "|---|---|---|---|---|---|"]
        for k in sorted(groups):
            g = groups[k]
            we = [r["err/tol"] for r in g if np.isfinite(r.get("err/tol", np.nan))]
            out.append("| %s | %d | %d | %s | %s | %s |"
                       % (k, len(g), sum(1 for r in g if r["fail"]),
                          _fmt_stats([r.get("time_sum") for r in g]),
                          _fmt_stats([r.get("time_check") for r in g]),
                          "%.3f" % max(we) if we else "-"))
        return out + [""]

    def decade(v):
        return "1e%+d" % int(math.floor(math.log10(v) + 1e-9))

    parsed = {r["spec"]: parse_case(r["spec"]) for r in results}
    if mode in ("random", "stroke"):
        lines += group_table("font", lambda r: parsed[r["spec"]]["font"])
        lines += group_table("tol / size", lambda r: decade(parsed[r["spec"]]["r"]))
        lines += group_table("scale", lambda r: decade(parsed[r["spec"]]["s"]))
        lines += group_table("nib", lambda r: "%gx%g" % (parsed[r["spec"]]["w"],
                                                          parsed[r["spec"]]["h"]))
    else:
        lines += group_table("font", lambda r: parsed[r["spec"]]["font"])
    if fails:
        lines += ["Failures (reproducer: `%s`):" % "python -c \"from tests.oracles.sweep import "
                  "run_case; print(run_case(SPEC)['fail'])\"", "",
                  "| case | failure |", "|---|---|"]
        for r in sorted(fails, key=lambda r: r["spec"]):
            lines.append("| `%s` | %s |" % (r["spec"], "; ".join(r["fail"]).replace("|", "/")))
    else:
        lines.append("No failures.")
    return lines, len(fails)


def write_section(md_path, mode, title, body):
    """Replace (or append) the section of ``mode`` in md_path."""
    md_path = Path(md_path)
    text = md_path.read_text() if md_path.exists() else "# Robustness sweep (bench/sweep.py)\n"
    begin, end = "<!-- sweep:%s -->" % mode, "<!-- /sweep:%s -->" % mode
    block = "\n".join([begin, "## %s" % title, ""] + body + [end])
    if begin in text and end in text:
        i, j = text.index(begin), text.index(end) + len(end)
        text = text[:i] + block + text[j:]
    elif "<!-- sections -->" in text:   # new sections go before the history
        i = text.index("<!-- sections -->")
        text = text[:i] + block + "\n\n" + text[i:]
    else:
        text = text.rstrip("\n") + "\n\n" + block + "\n"
    md_path.write_text(text)


TITLES = {"pairs": "Glyph pairs and fixed nibs (bundled fonts, one tolerance)",
          "random": "Randomised: glyph ⊕ ellipse nib, angles, aspects, tolerances, scales",
          "stroke": "Strokes: skeletons (Relief SingleLine, Feather icons) ⊕ ellipse nibs "
                    "(stroke_paths)",
          "fonts": "Glyph pairs of other fonts (Lobster, Cormorant, Amiri)"}


def main(argv=None):
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--mode", default="pairs", choices=sorted(TITLES))
    ap.add_argument("--fonts", default=None,
                    help="pairs: ttf,cff (default); random: %s (default); fonts: "
                    "lobster,cormorant,amiri (default); ebg (EB Garamond) is not in any default; "
                    "stroke: relief (default), feather (stroke-only icons, fetched with npm)"
                    % ",".join(RANDOM_FONTS))
    ap.add_argument("--set", default="both", choices=["upper", "lower", "both"])
    ap.add_argument("--nibs", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--pairs", action=argparse.BooleanOptionalAction, default=True)
    ap.add_argument("--limit", type=int, default=None, help="run only the first N jobs")
    ap.add_argument("--tol", type=float, default=1e-4, help="tolerance in em (pairs, fonts)")
    ap.add_argument("--n", type=int, default=100, help="random/stroke: jobs; fonts: pairs "
                    "per font")
    ap.add_argument("--seed", type=int, default=None, help="random seed (printed)")
    ap.add_argument("--jobs", type=int, default=1, help="worker processes (default 1: the "
                    "machine is shared)")
    ap.add_argument("--timeout", type=float, default=300.0, help="seconds per job")
    ap.add_argument("--budget", type=float, default=None, help="seconds: start no job after")
    ap.add_argument("--packed", action="store_true",
                    help="random/stroke: each case in one packed call with copies of itself")
    ap.add_argument("--md", default=str(ROOT / "bench" / "sweep.md"))
    ap.add_argument("--no-md", action="store_true", help="do not write the summary")
    ap.add_argument("--failures", default=None,
                    help="append each failure (reproducer) to this file as found")
    ap.add_argument("--cases", default=None,
                    help="only these jobs, comma separated: specs (nib/..., stroke/..., "
                    "pair/...) or font:A:B (pairs mode, B may be nib:disk etc.)")
    opt = ap.parse_args(argv)
    if opt.packed:
        os.environ[PACKED_ENV] = "1"
    command = "python -m bench.sweep " + " ".join(argv if argv is not None else sys.argv[1:])
    seed = opt.seed
    if opt.mode in ("random", "stroke", "fonts") and seed is None:
        seed = int(np.random.SeedSequence().entropy % 2 ** 31)
    if opt.cases:
        todo = []
        for c in opt.cases.split(","):
            c = c.strip()
            if c.split("/")[0] in ("nib", "stroke", "pair"):
                todo.append(c)
            else:
                font, a, b = c.split(":", 2)
                todo.append("pair/%s/%s/%s/%g" % (font, a, b, opt.tol))
    elif opt.mode == "pairs":
        fonts = [f.strip() for f in (opt.fonts or "ttf,cff").split(",") if f.strip()]
        sets = ["upper", "lower"] if opt.set == "both" else [opt.set]
        todo = ["pair/%s/%s/%s/%g" % (f, a, b, opt.tol)
                for f, a, b, _ in jobs(fonts, sets, opt.pairs, opt.nibs, opt.tol * UPM)]
    elif opt.mode == "fonts":
        fonts = [f.strip() for f in (opt.fonts or "lobster,cormorant,amiri").split(",")
                 if f.strip()]
        todo = draw_font_pairs(opt.n, seed, fonts, tol_em=opt.tol)
    else:
        default = "relief" if opt.mode == "stroke" else ",".join(RANDOM_FONTS)
        fonts = [f.strip() for f in (opt.fonts or default).split(",") if f.strip()]
        todo = draw_random_cases(opt.mode, opt.n, seed, fonts)
    if opt.mode == "pairs" and opt.seed is not None and not opt.cases:
        # a budgeted or limited run then samples every font, set and nib evenly
        todo = [todo[i] for i in np.random.default_rng(opt.seed).permutation(len(todo))]
    if opt.limit is not None:
        todo = todo[:opt.limit]
    print("bench.sweep: mode %s, %d jobs%s, %d worker(s), timeout %g s"
          % (opt.mode, len(todo), ", seed %d" % seed if seed is not None else "", opt.jobs,
             opt.timeout), flush=True)
    t0 = time.time()

    def on_result(r):
        tag = "FAIL" if r["fail"] else "ok  "
        extra = ""
        if "err/tol" in r:
            extra = " err/tol %.3f" % r["err/tol"]
        print("%s %-52s sum %6.2f s%s%s" % (tag, r["spec"], r.get("time_sum", float("nan")),
                                          extra, (": " + "; ".join(r["fail"])) if r["fail"]
                                          else ""), flush=True)
        if r["fail"] and opt.failures:
            record_failure(opt.failures, r, opt.mode)
        if r["fail"] and r["spec"].startswith("pair/"):
            _pair_picture(r)

    _preload()
    results = run_pool(todo, opt.jobs, opt.timeout, on_result=on_result, budget=opt.budget)
    elapsed = time.time() - t0
    body, nfail = summarize(opt.mode, results, todo, elapsed, command, seed, opt.jobs,
                            opt.timeout)
    print("\n".join(body[:8]))
    if not opt.no_md:
        write_section(opt.md, opt.mode, TITLES[opt.mode], body)
    return 1 if nfail else 0


def _preload():
    """Import what every job needs once, before the jobs are forked."""
    import shapely.ops  # noqa: F401

    import morph.minkowski  # noqa: F401
    import morph.stroke  # noqa: F401
    import tests.oracles.reference  # noqa: F401
    import tests.oracles.stroke_reference  # noqa: F401
    import tests.oracles.membership  # noqa: F401
    import tests.oracles.sweep  # noqa: F401


def _pair_picture(r):
    c = parse_case(r["spec"])
    try:
        OUT_DIR.mkdir(parents=True, exist_ok=True)
        picture({"font": c["font"], "a": c["a"], "b": c["b"]},
                OUT_DIR / ("%s-%s-%s.png" % (c["font"], _safe(c["a"]), _safe(c["b"]))))
    except Exception:  # noqa: BLE001 - a picture is a convenience
        pass


if __name__ == "__main__":
    sys.exit(main())

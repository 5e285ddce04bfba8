"""Calligraphic fonts from skeletons: accuracy sweep and peers.

    python -m bench.stroke [--glyphs A-Z,a-z,0-9] [--tol 0.5] [--ref-tol 0.02]
                           [--no-peers] [--md bench/stroke.md | --no-write]
    python -m bench.stroke --only-sets [--sets hershey-sans,hershey-script,hanzi-300]
                           [--sets-md bench/stroke_sets.md]

Skeleton: the Relief SingleLine subset in tests/data/relief (every contour an open
cubic path, upm 1000; SIL OFL).  Part 1, the issue's criterion: every chosen glyph
stroked by ``morph.fonts.stroke.stroke_ufo`` with the default nib of ``morph stroke``
(exact ellipse 90 x 20 units, long axis at 30 degrees) at ``--tol`` font units, one
process, into .otf and .ttf; each glyph read back from the compiled font (integer
coordinates; composites decomposed) and compared with an independent Clipper polygon
of the skeleton flattened within ``--ref-tol`` ⊕ the nib flattened within
``--ref-tol`` (``tests.oracles.stroke_reference.stroke_polygon``), shifted like the written
glyph.  Measures: two-sided boundary Hausdorff distance (``tests.oracles.reference.hausdorff``,
written curves flattened within 0.02, boundaries sampled every 0.25 unit) against
``tol + 0.71`` (integer rounding) ``+ ref-tol``; number of holes equal (counters of
o, e, a, 8 ...), each hole's area within perimeter x that bound.

Part 2, peers (``--no-peers`` skips it), at equal measured error, on the same glyphs
(each morph row also timed as the whole ``morph stroke`` command at its tol and nib,
each FontForge row as its whole worker process and as its whole workflow,
``bench/fontforge_font.py``: a FontForge script opening the skeleton UFO, stroking the
same glyphs and generating a CFF font; every time the median of ``--morph-repeat``
rounds, morph's and FontForge's interleaved, see below):

- broad nib (the ellipse above): morph (``stroke_many`` + certified cubic export
  ``loops_to_beziers``, several tolerances, run as ``morph stroke`` runs them: see
  below) vs FontForge Expand Stroke (``elliptical`` nib, caps and joins
  "nib" = path ⊕ nib, overlap removed, several ``accuracy`` values), run by Debian's
  python3-fontforge in a subprocess (``bench/fontforge_stroke.py``);
- round nib (disk, diameter 60): the same two, and Skia's stroker (skia-pathops
  ``Path.stroke`` with round caps and joins, conics converted to quadratics, then
  ``simplify`` to remove overlaps), at scale factors 1, 4, 16 (the path is scaled up
  before stroking and the result down: Skia's own precision knob is fixed).

Part 3, skeleton sets (``--sets``, default with ``--only-sets``: hershey-sans,
hershey-script, hanzi-300 of :mod:`bench.skeletons`, fetched at bench time, and the
whole Relief SingleLine where the shared data folder is;
``--only-sets`` runs only this part, parts 1 and 2 run without it; writes
bench/stroke_sets.md): per set the whole ``morph stroke`` command's CPU time
per glyph (a fresh process, ``--jobs 1``, the median of ``--morph-repeat`` runs), the
in-process stroke + export by chunks
(a mean: a chunk's glyphs are computed together) at the command's tolerance and at
``--set-tols-more`` multiples of it (for the comparison at equal measured error: morph's
fewest points whose worst error is no larger than FontForge's), points per glyph, the
worst error of the unrounded outlines and of the written font against the Clipper
reference (gaps narrower than the engine's documented narrow-feature limit excused
alike for every tool, :func:`excused_error`; the raw error beside it), and
FontForge's Expand Stroke (``--ff-accuracy-sets``) beside it: in process (mean and
median per glyph), its whole worker process and its whole workflow
(``bench/fontforge_font.py``, :class:`FontForgeRounds`: ``fontforge.open`` of the
set's UFO, the same ``glyph.stroke`` on every glyph, ``font.generate`` of a CFF font
with no hints, as morph writes none, and integer coordinates; the median of
``--morph-repeat`` runs, as the command's).  ``bench/stroke_exact.py`` checks a
written font again with the exact membership predicate, without Clipper.

morph and FontForge are timed in the same run, interleaved (:mod:`bench.paired`): in
``--morph-repeat`` rounds, each morph's in-process pass over all its settings, its
whole command (at every tolerance on Relief, at the set's tolerance on a set), then
FontForge's worker and its whole workflow at every accuracy
(:class:`FontForgeRounds`); each time is the median of its rounds, and the tables
give the median of the per-round ratios morph / FontForge, which the shared
machine's drift (20-40 % between hours) hits alike on both sides.  The Clipper
references and FontForge's outlines, points, "Internal Error" counts and their
errors against the references depend neither on morph's code nor on the machine's
load: they are kept in the bench cache (:mod:`bench.peer_cache`) keyed by the
skeletons' numbers, the nib, the tolerance and the peer's version, so that a remade
report judges only morph's outlines again; the reports say when, at which commit and
with which FontForge each was measured, and that the times are measured in the run.
Distances are GEOS's point-to-segment distances through an STRtree
(:func:`linework_distances`, the same numbers as ``shapely.distance``).

Outputs are compared unrounded (floats) with the polygon reference by the same
Hausdorff measure; ms per glyph are the CPU time (process_time, robust to the load
of a shared machine) of the stroking calls alone, single core.  morph is timed as
the ``morph stroke`` command works (``morph.fonts.stroke._chunk_job``): the glyphs
in the command's chunks of at most ``morph.fonts.stroke.CHUNK`` (96; two chunks
from 96 glyphs on, one below: ``morph.fonts.jobs.glyph_chunks``), the glyphs of a
chunk stroked together
(``stroke_many`` at the geometry share of ``plan(tol)[:2]``: its CPU time
divided by the chunk's glyphs is each glyph's stroke ms), then
all loops of the chunk exported in one ``loops_to_beziers(loops, export_tol,
wrap=True)`` call (the segment searches of all loops in lockstep; the call's CPU
time divided by the chunk's glyphs is each glyph's export ms) and split back per
glyph; the row's ms / glyph is stroke + export.  Every chunk at every tolerance is
computed ``--morph-repeat`` times (3), in passes over all the settings, and each of
the two times is the median of its passes: a single pass of 62 glyphs scattered by
half on a loaded machine, and a busy spell then falls on one pass of every setting.  FontForge: ``glyph.stroke``
inside FontForge; Skia: stroke + conic conversion + simplify.  Points per glyph
are on- and off-curve points of the output contours (morph: lines and quadratics
as the exporter returns them), the error is measured glyph by glyph.  A morph
failure (a glyph's stroke, a chunk's export) is reported with its traceback, not
worked around.  Writes bench/stroke.md.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.append(str(ROOT))  # after PYTHONPATH: a checkout named there is measured
# one BLAS thread, as the morph command sets before numpy loads: otherwise OpenBLAS's
# second thread spins through numpy's larger products and counts in process_time
# (the export at tol 0.5 measured 18.7 instead of 13.9 ms per glyph)
os.environ.setdefault("OPENBLAS_NUM_THREADS", "1")

import numpy as np  # noqa: E402 - after sys.path gets the repo root
import shapely  # noqa: E402 - after sys.path gets the repo root
import shapely.affinity  # noqa: E402 - after sys.path gets the repo root

from morph import piece as pc  # noqa: E402 - after sys.path gets the repo root
from morph.fonts.brush import ellipse_nib, parse_glyph_spec, region_extent  # noqa: E402 - after sys.path gets the repo root
from morph.parse import glyph_region  # noqa: E402 - after sys.path gets the repo root
from morph.parse.pens import closing_line, draw_paths, record_contours  # noqa: E402 - after sys.path gets the repo root
from morph.parse.ufo import decomposed_paths, glyph_names_for, load_ufo  # noqa: E402 - after sys.path gets the repo root
from tests.oracles.reference import count_outer_and_holes, region_to_shapely  # noqa: E402 - after sys.path gets the repo root
from tests.oracles.icons import GAP  # noqa: E402 - after sys.path gets the repo root
from tests.oracles.stroke_reference import stroke_polygon  # noqa: E402 - after sys.path gets the repo root

SUBSET = ROOT / "tests" / "data" / "relief" / "Relief-SingleLine-subset.ufo"
ROUNDING = 0.71
BROAD = ("ellipse", 90.0, 20.0, 30.0)
ROUND = ("disk", 60.0)
SYSTEM_PYTHON = "/usr/bin/python3"
WORKER = ROOT / "bench" / "fontforge_stroke.py"
WORKFLOW = ROOT / "bench" / "fontforge_font.py"
MEASURE_FLAT = 0.02
SPACING = 0.25


def code_version():
    def git(*args):
        return subprocess.run(["git", "-C", str(ROOT)] + list(args), capture_output=True,
                              text=True).stdout.strip()

    import morph

    if Path(morph.__file__).resolve().parents[1] != ROOT:  # PYTHONPATH put another first
        return "morph/ of %s" % os.environ.get("MORPH_CODE_LABEL", "another checkout")
    head = git("rev-parse", "--short", "HEAD")
    dirty = git("status", "--porcelain", "--", "morph")
    return "commit %s%s" % (head or "?", " + uncommitted changes in morph/" if dirty else "")


def nib_axes(spec):
    """(width, height, angle in degrees) of a nib spec, as ``morph stroke --nib``
    takes them (a disk: an ellipse of equal axes)."""
    return tuple(spec[1:4]) if spec[0] == "ellipse" else (spec[1], spec[1], 0.0)


def nib_region(spec):
    if spec[0] == "ellipse":
        return ellipse_nib(*spec[1:])
    return ellipse_nib(spec[1], spec[1], 0.0)


def holes(geom):
    polys = getattr(geom, "geoms", [geom])
    return sorted((shapely.Polygon(r).area, shapely.Polygon(r).length)
                  for p in polys for r in p.interiors)


def segments_to_region(contours):
    """Contours of polynomial segments ((k, 2) point lists) -> loops of pieces."""
    loops = []
    for segs in contours:
        loop = [pc.from_points(np.asarray(s, float)) for s in segs
                if not np.all(np.asarray(s, float) == np.asarray(s, float)[0])]
        if loop:
            loops.append(loop)
    return loops


def linework_distances(points, line):
    """Distances of ``points`` (m, 2) to the linework ``line``: the same numbers as
    ``shapely.distance(shapely.points(points), line)`` (GEOS's point-segment distance,
    minimised over the segments), found through an STRtree of the segments instead of
    every point against every segment (3-5 times faster on a hanzi's ~30,000
    samples)."""
    pts = shapely.points(np.asarray(points, float).reshape(-1, 2))
    parts = shapely.get_parts(line)
    if len(pts) == 0:
        return np.zeros(0)
    if not len(parts) or not all(shapely.get_type_id(parts) == 1):  # not only LineStrings
        return shapely.distance(pts, line)
    segs = []
    for part in parts:
        c = shapely.get_coordinates(part)
        segs.append(np.stack([c[:-1], c[1:]], 1))
    segs = np.concatenate(segs)
    if not len(segs):
        return shapely.distance(pts, line)
    tree = shapely.STRtree(shapely.linestrings(segs))
    _, dist = tree.query_nearest(pts, return_distance=True, all_matches=False)
    return dist


def boundary_hausdorff(got, ref, spacing=SPACING):
    """``tests.oracles.reference.hausdorff(got, ref, spacing)`` (two-sided, boundaries
    sampled every ``spacing``) through :func:`linework_distances`."""
    from tests.oracles.reference import _linework, _sample_points

    ga, gr = _linework(got), _linework(ref)
    fwd = linework_distances(_sample_points(ga, spacing), gr)
    back = linework_distances(_sample_points(gr, spacing), ga)
    return max(float(fwd.max()) if len(fwd) else 0.0, float(back.max()) if len(back) else 0.0)


def measure(contours, ref):
    got = region_to_shapely(segments_to_region(contours), MEASURE_FLAT)
    return boundary_hausdorff(got, ref, SPACING), got


# =========================================================================== part 1

def accuracy_sweep(font, names, tol, ref_tol, refs, workdir):
    from morph.fonts.stroke import stroke_ufo

    nib = nib_region(BROAD)
    x0, _, x1, _ = region_extent(nib)
    grow = int(round(x1 - x0))
    out = {}
    for suffix in (".otf", ".ttf"):
        path = Path(workdir) / ("Relief-Stroke" + suffix)
        t0, c0 = time.perf_counter(), time.process_time()
        stats = stroke_ufo(font, path, nib, names, tol=tol, overwrite=True)
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        rows = []
        limit = tol + ROUNDING + ref_tol
        for n in names:
            shift = int(round(-x0)) - (grow if font[n].width == 0 else 0)
            ref = shapely.affinity.translate(refs[n], shift, 0.0)
            got = region_to_shapely(glyph_region(n, font=str(path)).region, MEASURE_FLAT)
            d = boundary_hausdorff(got, ref, SPACING)
            h_got, h_ref = count_outer_and_holes(got, 1.0), count_outer_and_holes(ref, 1.0)
            area_ok = all(abs(a - b) <= per * limit
                          for (a, _), (b, per) in zip(holes(got), holes(ref)))
            fail = d > limit or h_got != h_ref or not area_ok or n in stats["fallback"]
            rows.append({"name": n, "err": d, "holes": h_got[1], "ref_holes": h_ref[1],
                         "fail": fail, "fallback": stats["fallback"].get(n, "")})
            print("%s %s: %.3f holes %d/%d%s" % (suffix, n, d, h_got[1], h_ref[1],
                                                 "  FAIL" if fail else ""), flush=True)
        out[suffix] = {"stats": stats, "wall": wall, "cpu": cpu, "rows": rows,
                       "limit": limit, "size": path.stat().st_size}
    return out


# =========================================================================== part 2

def run_morph(font, names, spec, tols, refs, judge=None, repeat=3, between=None):
    """morph's rows, timed as ``morph stroke`` works (:func:`morph.fonts.stroke._chunk_job`,
    one process): the glyphs in the command's chunks (:func:`command_chunks`: at most
    96 glyphs' worth of skeleton contours each), the glyphs of a chunk stroked together
    (``stroke_many``), then
    all loops of the chunk exported in one ``loops_to_beziers(..., export_tol,
    wrap=True)`` call and split back per glyph.  Every chunk at every tolerance is
    computed ``repeat`` times, in passes over all of them (:func:`_timed_passes`): per
    glyph, the median of its chunk's stroke and of its export CPU times, divided by
    the chunk's glyphs, and their sum (the ms compared with the peers); ``pass_ms``:
    each pass's stroke + export ms per glyph, for the ratios to a peer timed in the
    same rounds.  ``between(i)``, when given, runs after pass ``i`` (the peer's timing
    runs of round ``i``, :mod:`bench.paired`).
    ``judge(contours, name, tol) -> (error, raw error)`` measures a glyph (default:
    :func:`measure` against ``refs``, both the same)."""
    judge = judge or _plain_judge(refs)
    chunks = command_chunks(font, names)
    timed = _timed_passes(chunks, nib_region(spec), tols, repeat, between)
    rows = []
    for tol in tols:
        stroke_s, export_s, points, errs, fails = [], [], [], [], []
        passes = np.zeros(max(1, repeat))
        for chunk, _ in chunks:
            got = timed[tol, chunk[0]]
            if isinstance(got, dict):
                fails.append(got)
                continue
            regions, converted, secs, share, each = got
            passes += each
            it = iter(converted)
            for n, region in zip(chunk, regions):
                contours = [next(it) for _ in region]
                stroke_s.append(secs / len(chunk))
                export_s.append(share / len(chunk))
                points.append(sum(len(s) - 1 for segs in contours for s in segs))
                errs.append((n,) + tuple(judge(contours, n, tol)))
        row = summary("morph", "tol %g" % tol, [a + b for a, b in zip(stroke_s, export_s)],
                      points, errs, [f["short"] for f in fails])
        row["stroke_ms"] = 1000 * float(np.mean(stroke_s)) if stroke_s else float("nan")
        row["export_ms"] = 1000 * float(np.mean(export_s)) if export_s else float("nan")
        row["tracebacks"] = [f["long"] for f in fails]
        row["repeat"] = repeat
        row["pass_ms"] = (1000 * passes / len(stroke_s)).tolist() if stroke_s else []
        rows.append(row)
    return rows


def command_chunks(font, names):
    """[(glyph names, their skeleton paths)] of ``names`` in ``font``, in the chunks
    ``morph stroke`` strokes together (:func:`morph.fonts.jobs.glyph_chunks`, each
    glyph weighed by its skeleton contours as :func:`morph.fonts.stroke._stroke_weights`
    weighs it; here every contour counts, the glyphs decomposed)."""
    from morph.fonts.jobs import glyph_chunks
    from morph.fonts.stroke import CHUNK, CONTOURS_PER_GLYPH

    paths = {n: decomposed_paths(font, n) for n in names}
    weights = [len(paths[n]) / CONTOURS_PER_GLYPH for n in names]
    return [(c, [paths[n] for n in c]) for c in glyph_chunks(list(names), CHUNK, weights)]


def _timed_passes(chunks, nib, tols, repeat, between=None):
    """{(tol, first glyph of the chunk): (regions, converted loops, stroke CPU s,
    export CPU s, each pass's stroke + export CPU s)} of every chunk ``(names,
    skeleton paths)`` at every tolerance, or the :func:`_failure` of its first failed
    pass.  ``repeat`` passes, each over every tolerance and chunk in turn
    (:func:`_timed_chunk`), each time the median of the passes: a busy spell of a
    loaded machine then falls on one pass of every setting, not on all the passes of
    one (a single pass of 62 glyphs scattered by half); the results of the first pass
    (the passes compute the same).  ``between(i)`` runs after pass ``i``."""
    from morph.budget import plan

    times = {}
    for i in range(max(1, repeat)):
        for tol in tols:
            geometry, export = plan(tol)[:2]
            for chunk, sets in chunks:
                key = (tol, chunk[0])
                if isinstance(times.get(key), dict):
                    continue
                got = _timed_chunk(chunk, sets, nib, geometry, export, tol)
                if isinstance(got, dict):
                    times[key] = got
                    continue
                first = times.setdefault(key, [got[:2], [], []])
                first[1].append(got[2])
                first[2].append(got[3])
        if between is not None:
            between(i)
    return {k: v if isinstance(v, dict) else v[0] + (float(np.median(v[1])),
                                                      float(np.median(v[2])),
                                                      np.add(v[1], v[2]))
            for k, v in times.items()}


def _timed_chunk(chunk, sets, nib, geometry, export, tol):
    """(regions, converted loops, stroke CPU s, export CPU s) of one pass over a chunk
    of glyphs ``chunk`` with skeleton paths ``sets``: ``stroke_many`` then
    ``loops_to_beziers`` of all its loops; a failure: its :func:`_failure`.  What the
    bench holds (references, peers' outlines, earlier passes) is frozen out of the
    collector's passes while the chunk is timed, as ``morph``'s commands freeze what
    their process holds when they start (:mod:`morph.cli.group`): the bench's own
    objects would otherwise make morph's collections walk them."""
    import gc
    import traceback

    gc.freeze()
    try:
        return _timed_chunk_unfrozen(chunk, sets, nib, geometry, export, tol, traceback)
    finally:
        gc.unfreeze()


def _timed_chunk_unfrozen(chunk, sets, nib, geometry, export, tol, traceback):
    """:func:`_timed_chunk`'s work and times."""
    from morph.export import loops_to_beziers
    from morph.stroke import stroke_many

    t0 = time.process_time()
    try:
        regions = stroke_many(sets, nib, geometry)
    except Exception as exc:  # noqa: BLE001 - reported, not worked around
        return _failure("stroke of the chunk %s-%s" % (chunk[0], chunk[-1]),
                        None, tol, exc, traceback.format_exc())
    t1 = time.process_time()
    try:
        converted = loops_to_beziers([lp for r in regions for lp in r], export, wrap=True)
    except Exception as exc:  # noqa: BLE001 - reported, not worked around
        return _failure("export of the chunk %s-%s" % (chunk[0], chunk[-1]),
                        None, tol, exc, traceback.format_exc())
    return regions, converted, t1 - t0, time.process_time() - t1


def _failure(stage, name, tol, exc, tb):
    """A morph failure of the peer rows, as the row's short note and the full report."""
    what = stage if name is None else "%s of %s" % (stage, name)
    print("morph failed: %s at tol %g\n%s" % (what, tol, tb), file=sys.stderr, flush=True)
    return {"short": "%s (%s)" % (name or stage, type(exc).__name__),
            "long": "%s at tol %g:\n\n```\n%s```" % (what, tol, tb)}


def fontforge_jobs(font, names, spec, accuracies):
    """The jobs of ``bench/fontforge_stroke.py``: the skeletons of ``names`` (their
    segments' numbers) stroked with the nib ``spec`` at each of ``accuracies``."""
    glyphs = {n: [[[pc.cartesian(p).tolist() for p in pieces], closed]
                  for pieces, closed in decomposed_paths(font, n)] for n in names}
    nib = (["elliptical", spec[1], spec[2], spec[3]] if spec[0] == "ellipse"
           else ["circular", spec[1]])
    return [{"nib": nib, "accuracy": acc, "glyphs": glyphs} for acc in accuracies]


def run_fontforge(font, names, spec, accuracies, refs, judge=None):
    """FontForge's rows (``bench/fontforge_stroke.py``) without their times (a
    :class:`FontForgeRounds` timed in the same run as morph adds them), a glyph
    measured by ``judge`` as in :func:`run_morph` (its tol argument: the setting's
    accuracy).

    FontForge's outlines of a whole set at one accuracy, their points and its
    "Internal Error" count come from the bench cache (:func:`_fontforge_outlines`)
    when made before from the same skeletons (their numbers, not their names), nib,
    accuracy, FontForge version and worker script; so do the errors ``judge`` gave
    them, when the judge has a ``key`` (its parameters, references and source).
    Each row says when, at which commit and with which FontForge its outlines were
    made (``row["measured"]``)."""
    from bench import peer_cache

    judge = judge or _plain_judge(refs)
    version = peer_cache.fontforge_version()
    if version is None:
        return [], "no fontforge module in %s" % SYSTEM_PYTHON
    rows = []
    for job in fontforge_jobs(font, names, spec, accuracies):
        try:
            hit, key, fresh = _fontforge_outlines(job, version)
        except RuntimeError as exc:
            return rows, str(exc)
        res = hit["value"]["results"]
        judged = _fontforge_judged(res, names, judge, key, job["accuracy"], version)
        row = summary("FontForge", "accuracy %g" % job["accuracy"], [],
                      [res[n]["points"] for n in names],
                      [(n,) + tuple(judged[n]) for n in names], [])
        row["internal_errors"] = hit["value"]["internal_errors"]
        row["measured"] = peer_cache.measured_note([hit["provenance"]], int(fresh))
        row["outline_key"] = key
        if row["worst_glyph"] and "bbox" in res[row["worst_glyph"]]:
            # FontForge's own box of its worst glyph beside the reference's: a stray
            # curve far outside the glyph is in FontForge's outline, not in the measure
            row["worst_bbox"] = res[row["worst_glyph"]]["bbox"]
            row["worst_ref_bbox"] = list(refs[row["worst_glyph"]].bounds)
        rows.append(row)
    return rows, ""


def _fontforge_outlines(job, version):
    """(cache entry, key, made now) of FontForge's outlines of ``job``: the entry's
    value holds {"results": {glyph: {"points", "contours", "bbox"}}, "internal_errors"},
    from the bench cache (:mod:`bench.peer_cache`) or one untimed run of the worker,
    stored without its times (FontForge's times are measured in every run, interleaved
    with morph's: :class:`FontForgeRounds`).  Raises RuntimeError when FontForge
    fails."""
    from bench import peer_cache
    from bench.paired import child_run

    key = peer_cache.digest("fontforge-stroke", job, version,
                            peer_cache.file_digest("bench/fontforge_stroke.py"))
    hit = peer_cache.get("fontforge-stroke", key)
    if hit is not None:
        return hit, key, False
    prov = peer_cache.provenance(version)
    _, _, code, out, err = child_run([SYSTEM_PYTHON, str(WORKER)], json.dumps(job))
    if code != 0:
        raise RuntimeError("FontForge failed: %s" % err.strip().splitlines()[-1:])
    results = {n: {k: v for k, v in g.items() if k != "seconds"}
               for n, g in json.loads(out).items()}
    return peer_cache.put("fontforge-stroke", key, {"value": {
        "results": results, "internal_errors": err.count("Internal Error")},
        "provenance": prov}), key, True


def _fontforge_judged(res, names, judge, key, acc, version):
    """{glyph: (error, raw error)} of FontForge's outlines ``res`` (of the cache entry
    ``key``) by ``judge``, from the bench cache when the judge has a ``key``."""
    from bench import peer_cache

    jkey = getattr(judge, "key", None)
    if jkey is not None:
        jkey = peer_cache.digest("fontforge-judged", key, jkey)
        judged = (peer_cache.get("fontforge-judged", jkey) or {}).get("value")
        if judged is not None:
            return judged
    judged = {n: tuple(judge(res[n]["contours"], n, acc)) for n in names}
    if jkey is not None:
        peer_cache.put("fontforge-judged", jkey,
                       {"value": judged, "provenance": peer_cache.provenance(version)})
    return judged


class FontForgeRounds:
    """FontForge's times, measured in rounds interleaved with morph's (:mod:`bench.paired`):
    each call is one round that times, at every accuracy, the worker
    ``bench/fontforge_stroke.py`` once (``glyph.stroke``'s CPU time per glyph, mean
    and median, and the worker's whole process) and FontForge's whole workflow
    ``bench/fontforge_font.py`` once (open the skeleton UFO ``ufo``, stroke every
    glyph, or those of ``glyphs`` and their bases, generate a CFF font in
    ``workdir``: the kernel's user + sys CPU of the process); the first round's
    workflow also gives its glyphs stroked, the written font's glyphs with an outline
    (read back by fontTools) and its "Internal Error" count.  :meth:`fill` puts the
    medians (ms per glyph) and each round's figures into FontForge's rows."""

    def __init__(self, jobs, names, ufo, spec, workdir, glyphs=()):
        from bench.paired import warm_fontforge

        self.jobs, self.names = jobs, list(names)
        self.runs = [{"ms": [], "median": [], "process": [], "workflow": []} for _ in jobs]
        self.facts = [None] * len(jobs)
        nib = ",".join("%r" % float(v) for v in spec[1:4])  # as fontforge_stroke.py's
        self.args = [[str(ufo), str(Path(workdir) / "fontforge.otf"), "--nib", nib,
                      "--accuracy", repr(float(j["accuracy"]))]
                     + (["--glyphs", ",".join(glyphs)] if glyphs else []) for j in jobs]
        if jobs:
            warm_fontforge()

    def __call__(self, _round=None):
        from bench.paired import child_run, worker_times

        n = len(self.names)
        for job, runs in zip(self.jobs, self.runs):
            t = worker_times(WORKER, job, self.names)
            runs["ms"].append(1000 * t["mean"])
            runs["median"].append(1000 * t["median"])
            runs["process"].append(1000 * t["process"] / n)
        for k, (args, runs) in enumerate(zip(self.args, self.runs)):
            cpu, _, code, out, err = child_run([SYSTEM_PYTHON, str(WORKFLOW)] + args)
            if code != 0:
                raise RuntimeError("bench/fontforge_font.py failed: %s" % err[-2000:])
            runs["workflow"].append(1000 * cpu / n)
            if self.facts[k] is None:
                self.facts[k] = {"glyphs": json.loads(out.strip().splitlines()[-1])["glyphs"],
                                 "font_glyphs": _inked_glyphs(args[1]),
                                 "internal_errors": err.count("Internal Error")}

    def fill(self, rows):
        """Put the times into FontForge's ``rows`` (those of the jobs, in order):
        ``ms``, ``median_ms``, ``process_ms``, ``workflow_ms`` (medians over the
        rounds) and ``ms_runs``, ``process_runs``, ``workflow_runs`` (each round's, for
        :func:`bench.paired.ratio`), ``workflow`` (the first round's facts)."""
        from bench.paired import median

        for r, runs, facts in zip(rows, self.runs, self.facts):
            r.update(ms=median(runs["ms"]), median_ms=median(runs["median"]),
                     process_ms=median(runs["process"]),
                     workflow_ms=median(runs["workflow"]), ms_runs=runs["ms"],
                     process_runs=runs["process"], workflow_runs=runs["workflow"],
                     workflow=facts, rounds=len(runs["ms"]))


def _inked_glyphs(path):
    """The glyphs with an outline of the font at ``path``, read back by fontTools."""
    from fontTools.pens.boundsPen import ControlBoundsPen
    from fontTools.ttLib import TTFont

    glyph_set = TTFont(path).getGlyphSet()
    inked = 0
    for name in glyph_set.keys():
        pen = ControlBoundsPen(glyph_set)
        glyph_set[name].draw(pen)
        inked += pen.bounds is not None
    return inked


def references(font, names, spec, ref_tol):
    """({glyph: Clipper reference}, {glyph: cache key}, note): the references
    (:func:`tests.oracles.stroke_reference.stroke_polygon`) of the glyphs stroked
    with the nib ``spec``, each from the bench cache (:mod:`bench.peer_cache`) when
    made before from the same skeleton (its numbers), nib outline, ``ref_tol`` and
    oracle version; the note says when, at which commits they were made."""
    from bench import peer_cache

    nib = nib_region(spec)
    version = peer_cache.oracle_version()
    nib_key = [np.asarray(p, float) for p in nib[0]]
    refs, keys, provs, fresh = {}, {}, [], 0
    for n in names:
        paths = decomposed_paths(font, n)
        key = peer_cache.digest("stroke-reference",
                                [([np.asarray(p, float) for p in pieces], bool(closed))
                                 for pieces, closed in paths], nib_key, ref_tol, version)
        wkb, prov, new = peer_cache.cached(
            "stroke-reference", key,
            lambda: shapely.to_wkb(stroke_polygon(paths, nib, ref_tol)), version)
        refs[n], keys[n] = shapely.from_wkb(wkb), key
        provs.append(prov)
        fresh += new
    return refs, keys, peer_cache.measured_note(provs, fresh)


def _skia_contours(path):
    """Contours of segment point arrays of a pathops path (closed by a line where a
    contour ends away from its start), read by morph's recording pen."""
    return [[pc.cartesian(p) for p in closing_line(c)]
            for c in record_contours(path.draw, "skia path")]


def run_skia(font, names, diameter, scales, refs):
    import pathops

    rows = []
    for k in scales:
        secs, points, errs = [], [], []
        for n in names:
            t0 = time.process_time()
            path = pathops.Path()
            draw_paths(path.getPen(), [([pc.transform(p, [[k, 0, 0], [0, k, 0]]) for p in pieces],
                                        closed) for pieces, closed in decomposed_paths(font, n)])
            path.stroke(diameter * k, pathops.LineCap.ROUND_CAP, pathops.LineJoin.ROUND_JOIN, 4)
            path.convertConicsToQuads(0.25)
            path.simplify()
            secs.append(time.process_time() - t0)
            contours = [[np.asarray(s, float) / k for s in segs] for segs in _skia_contours(path)]
            points.append(sum(len(s) - 1 for segs in contours for s in segs))
            e = measure(contours, refs[n])[0]
            errs.append((n, e, e))
        rows.append(summary("Skia", "scale %g" % k, secs, points, errs, []))
    return rows


def _judge_key(kind, keys, *params):
    """The cache key of a judge (:mod:`bench.peer_cache`): its kind and parameters,
    the keys of its references, and the source of the measure."""
    from bench import peer_cache

    if keys is None:
        return None
    return peer_cache.digest(kind, sorted(keys.items()), params, MEASURE_FLAT, SPACING,
                             peer_cache.source_digest(excused_error, linework_distances,
                                                      boundary_hausdorff, measure,
                                                      segments_to_region),
                             peer_cache.file_digest("tests/oracles/reference.py"))


def _plain_judge(refs, keys=None):
    """A ``judge``: :func:`measure` against ``refs`` (error and raw error the same);
    ``keys``: the references' cache keys, which let FontForge's judged errors be
    cached."""
    def judge(contours, name, tol):
        e = measure(contours, refs[name])[0]
        return e, e
    judge.key = _judge_key("plain", keys)
    return judge


def summary(tool, setting, secs, points, judged, fails):
    """A row: ``judged`` holds (glyph, error, raw error) per measured glyph (the raw
    error without the narrow-gap excuse of :func:`excused_error`, where used)."""
    errs = [e for _, e, _ in judged]
    raw = [r for _, _, r in judged]
    worst = max(range(len(errs)), key=errs.__getitem__) if errs else None
    worst_raw = max(range(len(raw)), key=raw.__getitem__) if raw else None
    return {"tool": tool, "setting": setting,
            "worst_glyph": judged[worst][0] if errs else "",
            "raw_max_err": raw[worst_raw] if raw else float("nan"),
            "raw_worst_glyph": judged[worst_raw][0] if raw else "",
            "raw_errs": [float(r) for r in raw],
            "glyph_names": [g for g, _, _ in judged],
            "ms": 1000 * float(np.mean(secs)) if secs else float("nan"),
            "median_ms": 1000 * float(np.median(secs)) if secs else float("nan"),
            "errs": [float(e) for e in errs],
            "points": float(np.mean(points)) if points else float("nan"),
            "max_err": float(np.max(errs)) if errs else float("nan"),
            "mean_err": float(np.mean(errs)) if errs else float("nan"),
            "fails": fails}


def equal_error(rows):
    """For every peer row, morph's fewest-points row with max error <= the peer's."""
    out = []
    morph_rows = [r for r in rows if r["tool"] == "morph" and not r["fails"]]
    for r in rows:
        if r["tool"] == "morph":
            continue
        ok = [m for m in morph_rows if m["max_err"] <= r["max_err"]]
        m = min(ok, key=lambda m: m["points"]) if ok else None
        out.append((r, m))
    return out


def equal_error_md(rows):
    """The lines of the table of :func:`equal_error` (a heading line first)."""
    md = ["At equal measured error (morph's fewest-points setting whose worst "
          "error is no larger than the peer's; ms: in process, means):", "",
          "| peer | peer error | peer points | peer ms | morph setting | morph error | "
          "morph points | morph ms |", "|---|---|---|---|---|---|---|---|"]
    for r, m in equal_error(rows):
        if m is None:
            md.append("| %s %s | %.3f | %.0f | %.1f | none reaches it | | | |"
                      % (r["tool"], r["setting"], r["max_err"], r["points"], r["ms"]))
        else:
            md.append("| %s %s | %.3f | %.0f | %.1f | %s | %.3f | %.0f | %.1f |"
                      % (r["tool"], r["setting"], r["max_err"], r["points"], r["ms"],
                         m["setting"], m["max_err"], m["points"], m["ms"]))
    return md


# =========================================================================== part 3

#: The skeleton sets of part 3 (``relief``: only where the shared data folder is,
#: :func:`bench.skeletons.available`).
SETS = ("hershey-sans", "hershey-script", "hanzi-300", "relief")


def _command_runner(ufo, out_path, first_glyph, extra=(), env=None):
    """A function running ``morph stroke UFO -o OUT --jobs 1 [extra]`` once in a fresh
    process: (CPU seconds, peak RSS MB, last line, exit status), its own user + sys
    time and peak resident set (:func:`bench.paired.child_run`).  Its site and its
    bytecode cache are as after a pip install (:mod:`bench.pycache`): an untimed run of
    ``first_glyph`` alone fills the cache first, unless the environment ``env`` of
    another runner, whose cache is filled, is given."""
    from bench.paired import child_run
    from bench.pycache import cached_env, installed_python

    command = [installed_python(), "-m", "morph.cli", "stroke", str(ufo), "-o",
               str(out_path), "--jobs", "1", "--force"]
    extra = list(extra)
    if env is None:
        env = cached_env("stroke-pycache-", OPENBLAS_NUM_THREADS="1")
        warm = []   # extra without its --glyphs choice: the warm-up strokes first_glyph
        for k, a in enumerate(extra):
            if a != "--glyphs" and (k == 0 or extra[k - 1] != "--glyphs"):
                warm.append(a)
        child_run(command + warm + ["--glyphs", first_glyph],
                  cwd=str(Path(out_path).parent), env=env)

    def run():
        cpu, rss, code, out, err = child_run(command + extra, cwd=str(Path(out_path).parent),
                                             env=env)
        # the command's own last line ("wrote ..."), not its progress line on stderr
        lines = (out.strip() or err.strip()).splitlines()
        return cpu, rss, lines[-1] if lines else "", code
    run.env = env
    return run


def excused_error(got, ref, tol, r):
    """(error, raw error, narrow) of an outline ``got`` against the reference ``ref``
    (shapely): the two-sided boundary Hausdorff distance (sampled every SPACING),
    except that reference boundary points farther than tol from ours and strictly
    inside the reference's morphological closing by ``r`` (``tests.oracles.icons``:
    a gap or hole narrower than 2 r, which the engine may fill) are not measured in
    the error; the raw error measures them; ``narrow``: some were excused.  Our
    boundary is always measured in full."""
    from tests.oracles.reference import _linework, _sample_points

    ga, gr = _linework(got), _linework(ref)
    fwd = linework_distances(_sample_points(ga, SPACING), gr)
    fwd = float(fwd.max()) if len(fwd) else 0.0
    pts = _sample_points(gr, SPACING)
    back = linework_distances(pts, ga)
    raw = max(fwd, float(back.max()) if len(back) else 0.0)
    far = np.flatnonzero(back > tol)
    narrow = False
    if len(far):
        closed = ref.buffer(r, quad_segs=16).buffer(-r, quad_segs=16)
        q = shapely.points(pts[far])
        inner = shapely.contains(closed, q) & (shapely.distance(q, closed.boundary) > tol / 20)
        narrow = bool(inner.any())
        back[far[inner]] = 0.0
    return max(fwd, float(back.max()) if len(back) else 0.0), raw, narrow


def _narrow_judge(refs, tol, keys=None):
    """A ``judge`` for :func:`run_morph` / :func:`run_fontforge` on unrounded outlines:
    :func:`excused_error` with the engine's documented narrow-feature limit
    (r = GAP tol: gaps narrower than 2 GAP tol may close, ``minkowski_sum``), the
    same excuse for every tool; ``keys`` as for :func:`_plain_judge`."""
    def judge(contours, name, _):
        got = region_to_shapely(segments_to_region(contours), MEASURE_FLAT)
        return excused_error(got, refs[name], tol, GAP * tol)[:2]
    judge.key = _judge_key("narrow", keys, tol, GAP)
    return judge


def _written_errors(out_path, names, refs, shift, tol, renamed=None):
    """({glyph: error}, [glyphs with a narrow gap or hole filled]) of the glyphs read
    back from the compiled font (integer coordinates; ``renamed``: the source's
    ``public.postscriptNames``, the written font's names) against the references shifted
    as the command shifts them (``shift``: {glyph: x shift}, ``morph.fonts.stroke``'s
    rule: the nib's left extent, a zero-width glyph's less the nib's width):
    :func:`excused_error` with r = GAP tol + ROUNDING (the gaps and holes narrower than
    the engine's documented narrow-feature limit, which it may fill, widened by the
    integer rounding, which moves each side of a gap by up to ROUNDING); such glyphs
    are listed."""
    errs, narrow = {}, []
    for n in names:
        got = glyph_region((renamed or {}).get(n, n), font=str(out_path)).region
        got = region_to_shapely(got, MEASURE_FLAT)
        ref = shapely.affinity.translate(refs[n], shift[n], 0.0)
        errs[n], _, filled = excused_error(got, ref, tol, GAP * tol + ROUNDING)
        if filled:
            narrow.append(n)
    return errs, narrow


def skeleton_set(name, opt, workdir):
    """The rows of one skeleton set of :mod:`bench.skeletons` (see the module doc).
    FontForge's outlines and errors come from the bench cache when made before; the
    times are measured now, in ``--morph-repeat`` rounds (:mod:`bench.paired`): morph's
    in-process pass, then its whole command, then FontForge's worker and its whole
    workflow at every accuracy."""
    from bench.paired import interpreter_starts, starts_note
    from bench.skeletons import skeleton_ufo

    ufo = skeleton_ufo(name)
    font = load_ufo(ufo, lazy=False)
    names = [g.name for g in sorted(font, key=lambda g: g.name) if len(g.contours)]
    names = [n for n in names if any(len(c) > 1 for c in font[n].contours)]
    upm = float(font.info.unitsPerEm or 1000)
    k = upm / 1000.0
    spec = ("ellipse", BROAD[1] * k, BROAD[2] * k, BROAD[3])
    tol = opt.set_tol * upm
    t0 = time.process_time()
    refs, keys, ref_note = references(font, names, spec, opt.ref_tol)
    print("%s: %d glyphs, references %.1f s (%s)" % (name, len(names),
                                                     time.process_time() - t0, ref_note),
          flush=True)
    out = {"name": name, "glyphs": len(names), "upm": upm, "tol": tol, "nib": spec,
           "rows": [], "reference_measured": ref_note}
    judge = _narrow_judge(refs, tol, keys)
    accs = _floats(opt.ff_accuracy_sets)
    ff, out["ff_note"] = run_fontforge(font, names, spec, accs, refs, judge)
    rounds = FontForgeRounds(fontforge_jobs(font, names, spec, accs[:len(ff)]), names, ufo,
                             spec, workdir)
    otf = Path(workdir) / (name + ".otf")
    command, runs, starts = _command_runner(ufo, otf, names[0]), [], []

    def between(_round):   # after each in-process pass: the command, then FontForge
        runs.append(command())
        rounds()
        starts.append(interpreter_starts(command.env))

    # in-process, as the command strokes chunks (a chunk's glyphs are computed
    # together: its CPU time divided by its glyphs is each glyph's)
    tols = [tol] + [f * tol for f in _floats(opt.set_tols_more)]
    out["rows"] += run_morph(font, names, spec, tols, refs, judge, opt.morph_repeat, between)
    for r, t in zip(out["rows"], tols):
        r["tol"] = t    # the first: the command's tolerance, as the command ran
    rounds.fill(ff)
    out["rows"] += ff
    skipped = set(font.lib.get("public.skipExportGlyphs", ()))   # bases only, not written
    _command_figures(out, runs, otf, ([n for n in names if n not in skipped],
                                      font.lib.get("public.postscriptNames"),
                                      {n for n in names if not font[n].width}), refs, opt,
                     workdir)
    out["starts_note"] = starts_note(starts, len(names))
    for r in out["rows"]:
        print("%s %s %s: %.1f ms (median %.1f), whole workflow %s ms, %.0f points, max err "
              "%.3f" % (name, r["tool"], r["setting"], r["ms"], r["median_ms"],
                        _ms(r.get("workflow_ms")), r["points"], r["max_err"]), flush=True)
    return out


def _command_figures(out, runs, otf, named, refs, opt, workdir):
    """Put the whole command's figures into the set ``out``: its ``runs`` ((CPU s, peak
    RSS MB, last line, exit status), one a round; ``command_cpu`` their median CPU s,
    ``command_runs`` each round's ms per glyph) and the errors of the font it wrote to
    ``otf`` (integer coordinates, read back) against the references ``refs`` of the
    glyphs ``named`` (names, the source's production names or None, the zero-width
    glyphs)."""
    from bench.paired import median

    names, renamed, marks = named
    tol, cpu = out["tol"], median([r[0] for r in runs])
    rss, line, rc = max(r[1] for r in runs), runs[-1][2], runs[-1][3]
    x0, _, x1, _ = region_extent(nib_region(out["nib"]))
    shift = {n: int(round(-x0)) - (int(round(x1 - x0)) if n in marks else 0) for n in names}
    written, narrow = (_written_errors(otf, names, refs, shift, tol, renamed)
                       if rc in (0, 1) else ({}, []))
    line = line.replace(str(workdir) + os.sep, "")   # no machine path in the report
    out.update(command_cpu=cpu, command_runs=[1000 * r[0] / len(names) for r in runs],
               command_rss=rss, command_line=line, command_rc=rc,
               written_worst=max(written.values()) if written else float("nan"),
               written_worst_glyph=max(written, key=written.get) if written else "",
               written_limit=tol + ROUNDING + opt.ref_tol,
               written_over=sum(e > tol + ROUNDING + opt.ref_tol for e in written.values()),
               written_narrow=narrow)
    print("%s: command %.1f s CPU (%.1f ms / glyph), %.0f MB; written worst %.3f"
          % (out["name"], cpu, 1000 * cpu / len(names), rss, out["written_worst"]),
          flush=True)


def _floats(text):
    return [float(v) for v in text.split(",") if v.strip()]


def measured_set(name, opt, workdir):
    """:func:`skeleton_set` with the line saying when, at which commit and at which
    load it was measured; with ``--sets-json DIR``, a set saved there (NAME.json) is
    reported as it was measured, and a set measured now is saved there, so that
    long sets can be measured in runs of their own and reported together."""
    saved = Path(opt.sets_json) / (name + ".json") if opt.sets_json else None
    if saved is not None and saved.exists():
        print("%s: as measured before (%s)" % (name, saved), flush=True)
        return json.loads(saved.read_text())
    t0 = time.perf_counter()
    st = skeleton_set(name, opt, workdir)
    st["measured"] = ("measured %s UTC at %s in %.0f s (`python -m bench.stroke --only-sets "
                      "--sets %s`), load average %s at the end"
                      % (time.strftime("%Y-%m-%d %H:%M", time.gmtime()), code_version(),
                         time.perf_counter() - t0, name,
                         ", ".join("%.1f" % v for v in os.getloadavg())))
    if saved is not None:
        saved.parent.mkdir(parents=True, exist_ok=True)
        saved.write_text(json.dumps(st, default=float))
    return st


def _times(n):
    """"once", "N times"."""
    return "once" if n == 1 else "%d times" % n


def _ms(v):
    """A time in ms for a table cell ("" when not measured)."""
    return "" if v is None else "%.1f" % v


def _box(b):
    return "(%.0f, %.0f)-(%.0f, %.0f)" % tuple(b)


def sets_markdown(opt, sets, elapsed):
    """The report of the skeleton sets (bench/stroke_sets.md)."""
    md = _sets_intro(opt, elapsed) + _sets_summary(sets) + [""]
    for st in sets:
        md += _set_section(st, opt) + _set_notes(st, opt) + [""]
    return "\n".join(md) + "\n"


def _sets_intro(opt, elapsed):
    md = ["# Stroke speed and accuracy on skeleton sets (bench/stroke.py, part 3)", "",
          "Command: `python -m bench.stroke --only-sets%s` (report written at %s; %s UTC; "
          "%.0f s; each set below says when, at which commit and load it was measured). "
          "Machine: %d CPUs shared with other jobs (load average %s at the end): every time "
          "is CPU time (process_time, or the kernel's user + sys of a child process), "
          "which the load inflates less than wall time, but does inflate (caches, "
          "hyper-threads)." % (opt.set_argline, code_version(),
                               time.strftime("%Y-%m-%d %H:%M", time.gmtime()), elapsed,
                               os.cpu_count() or 1,
                               ", ".join("%.1f" % v for v in os.getloadavg())), "",
          "Sets (`bench/skeletons.py`, fetched with `npm pack` at bench time, not "
          "committed): Hershey Sans 1-stroke and Script 1-stroke (npm `hersheytext`, ASCII "
          "33-126), and 300 characters of hanzi-writer-data's stroke medians (Make Me a "
          "Hanzi, Arphic licence; spread evenly over the code points); and, where the "
          "shared data folder is, the whole Relief SingleLine (SIL OFL, 584 glyphs of "
          "which 384 composites: its in-process rows stroke the glyphs with contours, "
          "the whole command and workflow the font; FontForge's workflow unlinks the "
          "references whose transformation the stroke does not commute with, as morph "
          "decomposes them, see `bench/fontforge_font.py`).  Nib: `morph "
          "stroke`'s default (ellipse 90 x 20 at 30 degrees per 1000 units per em), tol "
          "%g em (the command's default)." % opt.set_tol, "",
          "Columns, two kinds of time, each the same for both tools: **in process** = "
          "the computation alone: for morph `stroke_many` + `loops_to_beziers` by the "
          "command's chunks (`bench.stroke.run_morph`; a chunk's glyphs are computed "
          "together, so morph has a mean per glyph, not a median: compare it with "
          "FontForge's mean; FontForge's median is beside it; each chunk computed "
          "%d times, the median of its passes), for FontForge "
          "`glyph.stroke(\"elliptical\", ..., \"nib\", \"nib\", removeoverlap=\"layer\")` "
          "glyph by glyph in FontForge's Python (`bench/fontforge_stroke.py`); **whole "
          "command** = a whole process divided by the glyphs: for morph `morph stroke "
          "SET.ufo -o SET.otf --jobs 1` started as installed (a virtual environment's site, "
          "bytecode cached: `bench/pycache.py`; startup, parse, stroke, export, font tables, "
          "compile, sample image and specimen; the median of %d runs), for FontForge its "
          "worker process (Python's startup, `import fontforge`, drawing the skeletons, "
          "stroking, writing the outlines as JSON; no font file); **whole workflow** "
          "(FontForge) = a FontForge script doing the command's job as a whole process "
          "divided by the glyphs (`bench/fontforge_font.py`: Python's startup, `import "
          "fontforge`, `fontforge.open(SET.ufo)`, the same `glyph.stroke` on every glyph, "
          "`font.generate(SET.otf, flags=(\"no-hints\", \"round\"))` with the autohinter "
          "off, as morph writes no hints and integer coordinates; no sample image nor "
          "specimen; the median of %d runs).  morph and FontForge are timed in the same "
          "run, interleaved: %d rounds, each morph's in-process pass, its command, then "
          "FontForge's worker and its whole workflow at every accuracy, so that the shared "
          "machine's drift (20-40 %% between hours) hits both alike; FontForge's times are "
          "the medians of its %d runs, and **morph / FontForge** is the median of the "
          "per-round ratios (below 1: morph faster).  Errors: "
          "two-sided boundary Hausdorff distance (font units) of the unrounded output "
          "against the independent Clipper reference (`tests/oracles/stroke_reference.py`, "
          "flattened within %g), sampled every %g unit, except, for every tool alike, the "
          "reference's boundary in gaps and holes narrower than the engine's documented "
          "narrow-feature limit (inside the reference's closing by %g tol: such a gap may "
          "close); *raw* measures those too (the tips of the thin wedges where two "
          "strokes nearly touch); *over* = glyphs whose error exceeds tol + %g.  Points: "
          "on- and off-curve points per glyph."
          % ((opt.morph_repeat,) * 5 + (opt.ref_tol, SPACING, GAP, opt.ref_tol)), "",
          "The Clipper references and FontForge's outlines, points, \"Internal Error\" "
          "counts and errors do not depend on morph's code nor on the machine's load: "
          "they come from the bench cache (`bench/peer_cache.py`, keyed by the "
          "skeletons' numbers, the nib, the tolerance and the peer's version) when "
          "measured before; each set says when, at which commit and with which FontForge "
          "they were measured.  Every time, morph's and FontForge's, is measured in this "
          "run."]
    return md


def _sets_summary(sets):
    """The summary table of the skeleton sets: one row per FontForge setting."""
    md = ["", "## Summary", "",
          "ms of CPU per glyph; in process: morph's mean by chunks against FontForge's "
          "mean (median), morph at its fewest-points setting whose worst error is no "
          "larger than FontForge's (at the command's tolerance where none is); whole "
          "command: `morph stroke` at its default tolerance against FontForge's worker "
          "process; whole workflow: FontForge opening the skeleton UFO, stroking and "
          "generating the font.  Both timed in this run, interleaved; morph / FontForge: "
          "the median of the per-round ratios (below 1: morph faster).", "",
          "| set | FontForge setting | morph setting | in process: morph | in process: "
          "FontForge mean (median) | in process: morph / FontForge | whole command: morph "
          "| whole command: FontForge worker | whole command: morph / FontForge worker | "
          "whole workflow: FontForge | whole workflow: morph / FontForge | points: morph / "
          "FontForge | worst error: morph / FontForge |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for st in sets:
        first = next((r for r in st["rows"] if r["tool"] == "morph"), None)
        for r, m in equal_error(st["rows"]):
            m = m or first   # morph's fewest points at no larger error, else its default
            if m is None:
                continue
            inproc, worker, workflow = _paired(m, r, st.get("command_runs"))
            md.append("| %s | %s | %s | %.1f | %s (%s) | %s | %.1f | %s | %s | %s | %s | "
                      "%.0f / %.0f | %.3f / %.3f |"
                      % (st["name"], r["setting"], m["setting"], m["ms"], _ms(r["ms"]),
                         _ms(r["median_ms"]), inproc, 1000 * st["command_cpu"] / st["glyphs"],
                         _ms(r.get("process_ms")), worker, _ms(r.get("workflow_ms")),
                         workflow, m["points"], r["points"], m["max_err"], r["max_err"]))
    return md


def _paired(m, r, command_runs):
    """The cells of the ratios morph / FontForge (:func:`bench.paired.ratio`: the
    median of the per-round ratios) of the morph row ``m`` and FontForge's row ``r``:
    in process, morph's whole command (``command_runs``, ms per glyph a round)
    against FontForge's worker process, and against FontForge's whole workflow."""
    from bench.paired import ratio_cell

    return (ratio_cell(m.get("pass_ms"), r.get("ms_runs")),
            ratio_cell(command_runs, r.get("process_runs")),
            ratio_cell(command_runs, r.get("workflow_runs")))


def _fontforge_measured(rows):
    """The notes saying when FontForge's outlines (from the cache or now) and its times
    (in this run) were measured, and its whole workflow's: [(setting, note, workflow's
    note)], one a FontForge row."""
    return [(r["setting"],
             "outlines, points and errors %s, \"Internal Error\" printed %s; its times "
             "measured in this run, %s" % (r["measured"], _times(r.get("internal_errors", 0)),
                                           _rounds(r)),
             "%s, %d glyphs stroked, %d with an outline (.notdef included) in the font read "
             "back by fontTools, \"Internal Error\" printed %s"
             % (r["workflow"].get("measured", "measured in this run"), r["workflow"]["glyphs"],
                r["workflow"]["font_glyphs"], _times(r["workflow"]["internal_errors"]))
             if r.get("workflow") else "not measured")
            for r in rows if r["tool"] != "morph" and r.get("measured")]


def _rounds(r):
    """How a FontForge row's times were taken."""
    return ("interleaved with morph's (%d rounds)" % r["rounds"] if r.get("rounds")
            else "(not in rounds)")


def _set_section(st, opt):
    """A skeleton set's heading, provenance and table of rows."""
    md = ["## %s (%d glyphs, upm %g, tol %.3g units)" % (st["name"], st["glyphs"],
                                                          st["upm"], st["tol"]), "",
          "morph's outlines and the times of both tools: %s." % st["measured"], ""]
    if st.get("reference_measured"):
        md += ["Clipper reference: %s." % st["reference_measured"], ""]
    ff = _fontforge_measured(st["rows"])
    if ff:
        md += ["FontForge %s." % "; ".join("%s: %s" % (s, f) for s, f, _ in ff), "",
               "FontForge's whole workflow (`bench/fontforge_font.py`) %s."
               % "; ".join("%s: %s" % (s, w) for s, _, w in ff), ""]
    md += ["| tool | setting | in process: mean ms / glyph | in process: median ms / "
           "glyph | whole command ms / glyph | whole workflow ms / glyph | points / glyph | "
           "worst error | mean error | over | raw worst | raw over | morph / FontForge: in "
           "process; command / worker; command / workflow |",
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    pairs = {id(r): m for r, m in equal_error(st["rows"])}
    first = next((r for r in st["rows"] if r["tool"] == "morph"), None)
    for r in st["rows"]:
        t = r.get("tol", st["tol"])    # a morph row's own tolerance
        over = sum(e > t + opt.ref_tol for e in r["errs"])
        if "raw_errs" in r:
            worst = "%.3f (%s)" % (r["max_err"], r["worst_glyph"])
            raw = "| %.3f (%s) | %d |" % (r["raw_max_err"], r["raw_worst_glyph"],
                                          sum(e > t + opt.ref_tol for e in r["raw_errs"]))
        else:  # measured before the narrow-gap excuse: raw
            worst, raw = "%.3f" % r["max_err"], "| (raw) | (raw) |"
        if r["tool"] == "morph":   # the command is morph's whole workflow
            whole = ("%.1f" % (1000 * st["command_cpu"] / st["glyphs"])
                     if t == st["tol"] else "")
            md.append("| morph | tol %.3g | %.1f | (chunks) | %s | %s | %.0f | %s | %.3f | %d %s"
                      "  |" % (t, r["ms"], whole, whole, r["points"], worst, r["mean_err"],
                               over, raw))
        else:
            m = pairs.get(id(r)) or first
            md.append("| %s | %s | %s | %s | %s | %s | %.0f | %s | %.3f | %d %s %s |"
                      % (r["tool"], r["setting"], _ms(r["ms"]), _ms(r["median_ms"]),
                         _ms(r.get("process_ms")), _ms(r.get("workflow_ms")), r["points"],
                         worst, r["mean_err"], over, raw, "; ".join(
                             _paired(m, r, st.get("command_runs")) if m else ())))
    return md + [""] + equal_error_md(st["rows"])


def _set_notes(st, opt):
    """A skeleton set's notes below its tables: FontForge's worst glyphs far off, the
    written font, the narrow gaps."""
    md, limit = [], st["tol"] + opt.ref_tol
    for r in st["rows"]:
        if "worst_bbox" in r and r["max_err"] > 10 * limit:
            apart = np.abs(np.subtract(r["worst_bbox"], r["worst_ref_bbox"])).max() > limit
            md += ["", "%s %s's worst glyph %s: FontForge's own bounding box of its "
                   "result (`glyph.boundingBox()`) is %s, the reference's %s: %s"
                   % (r["tool"], r["setting"], r["worst_glyph"], _box(r["worst_bbox"]),
                      _box(r["worst_ref_bbox"]),
                      "the error is in FontForge's outline (a curve beyond the exact "
                      "stroke's extent), not in the measure." if apart else
                      "the boxes agree, so the error lies inside the stroke's extent."
                      )]
    if not all("raw_errs" in r for r in st["rows"]):
        md += ["", "(raw): this set was measured before the narrow-gap excuse; its errors "
               "are raw."]
    md += ["", "Written font (integer coordinates, read back): worst %.3f units (%s), "
           "%d glyphs over tol + 0.71 + %g = %.2f; command %.1f s CPU, peak RSS %.0f MB; "
           "`%s`" % (st["written_worst"], st["written_worst_glyph"], st["written_over"],
                     opt.ref_tol, st["written_limit"], st["command_cpu"],
                     st["command_rss"], st["command_line"])]
    if st.get("starts_note"):
        md += ["", st["starts_note"]]
    if st.get("written_narrow"):
        md += ["", "Gaps or holes of the exact stroke narrower than the documented "
               "narrow-feature limit (2 x (%g tol + 0.71)), filled in the written font and not "
               "measured there: %s." % (GAP, ", ".join(st["written_narrow"]))]
    if st["ff_note"]:
        md += ["", "FontForge not run (%s)." % st["ff_note"]]
    return md


# =========================================================================== report

def markdown(opt, names, acc, peers, notes, elapsed):
    md = _relief_intro(opt, names, elapsed) + (_accuracy_md(opt, acc) if acc else [])
    tracebacks = []
    for title, rows in peers:
        md += _peer_table(title, rows, opt) + [""] + equal_error_md(rows) + [""]
        tracebacks += [t for r in rows for t in r.get("tracebacks", [])]
    if tracebacks:
        md += ["## morph failures", ""] + ["- " + t for t in tracebacks] + [""]
    if notes:
        md += ["## When the peers' figures were measured", ""] + ["- " + n for n in notes] + [""]
    return "\n".join(md) + "\n"


def _relief_intro(opt, names, elapsed):
    """The report's title and its paragraphs on the skeleton and the times."""
    return ["# Calligraphic fonts from skeletons (bench/stroke.py)", "",
            "Command: `python -m bench.stroke%s`; morph measured %s UTC at %s (%.0f s)."
            % (opt.argline, time.strftime("%Y-%m-%d %H:%M", time.gmtime()), code_version(),
               elapsed), "",
            "Skeleton: Relief SingleLine subset (tests/data/relief, SIL OFL), %d glyphs (%s), "
            "upm 1000, every contour an open cubic path.  Machine: %d CPUs shared with other "
            "jobs, load average %s at the end: every time is CPU time (process_time, or the "
            "kernel's user + sys of a child process)." % (
                len(names), opt.glyphs, os.cpu_count() or 1,
                ", ".join("%.1f" % v for v in os.getloadavg())), "",
            "Times, two kinds, each the same for morph and FontForge: **in process** = the "
            "computation alone (morph: `stroke_many` + `loops_to_beziers` by the command's "
            "chunks, whose glyphs are computed together, so a mean per glyph and no median: "
            "compare it with FontForge's mean; each chunk computed %d times in passes over "
            "all the settings, the median of its passes' CPU times; FontForge: `glyph.stroke` "
            "glyph by glyph; Skia: stroke + conic conversion + simplify); **whole command** = "
            "a whole process divided by the glyphs (morph: `morph stroke "
            "Relief-SingleLine-subset.ufo -o OUT.otf --glyphs %s --tol T --nib ... --jobs 1`, "
            "started as installed: a virtual environment's site, bytecode cached "
            "(`bench/pycache.py`), every composite that follows included; FontForge: its "
            "worker process, Python's "
            "startup, `import fontforge`, drawing, stroking and writing the outlines as "
            "JSON); **whole workflow** = the job as a whole process (morph: its command; "
            "FontForge: `bench/fontforge_font.py`, `fontforge.open` of the UFO, the same "
            "`glyph.stroke` on the same glyphs and the bases of their components, "
            "`font.generate` of a CFF font, autohinter off, no hints, coordinates rounded).  "
            "morph and FontForge are timed in the same run, interleaved: %d rounds, each "
            "morph's in-process pass over all its settings, its command at every tolerance, "
            "then FontForge's worker and its whole workflow at every accuracy, so that the "
            "shared machine's drift hits both alike; each time is the median of its %d "
            "rounds, and **morph / FontForge** the median of the per-round ratios (below 1: "
            "morph faster), morph at its fewest-points setting whose worst error is no "
            "larger than FontForge's (at --tol where none is).  The Clipper references and "
            "FontForge's outlines, points, \"Internal Error\" counts and errors come from "
            "the bench cache (`bench/peer_cache.py`) when measured before on the same "
            "skeletons, nib, tolerance and peer version; the notes at the end say when and "
            "at which commit they were measured.  Every time is measured in this run."
            % (opt.morph_repeat, opt.glyphs, opt.morph_repeat, opt.morph_repeat), ""]


def _accuracy_md(opt, acc):
    """The section on the accuracy of the written fonts (part 1)."""
    md = ["## Accuracy of the written fonts", "",
          "Default nib of `morph stroke` (ellipse 90 x 20 units at 30 degrees), tol %g "
          "units; written glyphs (integer coordinates) against the Clipper reference "
          "(flattened within %g): criterion Hausdorff <= tol + 0.71 + %g = %.2f units, "
          "same number of holes, hole areas within perimeter x bound."
          % (opt.tol, opt.ref_tol, opt.ref_tol, opt.tol + ROUNDING + opt.ref_tol), "",
          "| font | glyphs stroked | wall s | CPU s | stroke + export CPU / glyph | "
          "points / glyph | worst Hausdorff | mean | holes kept | failures | file bytes |",
          "|---|---|---|---|---|---|---|---|---|---|---|"]
    for suffix, r in acc.items():
        errs = [x["err"] for x in r["rows"]]
        worst = max(r["rows"], key=lambda x: x["err"])
        st = r["stats"]
        md.append("| %s | %d | %.1f | %.1f | %.1f ms | %.0f | %.3f (%s) | %.3f | %d / %d | "
                  "%d | %d |" % (suffix, st["glyphs"], r["wall"], r["cpu"],
                                 1000 * st["stroke_seconds"] / max(1, st["glyphs"]),
                                 st["points"] / max(1, st["glyphs"]), worst["err"],
                                 worst["name"], float(np.mean(errs)),
                                 sum(x["holes"] == x["ref_holes"] for x in r["rows"]),
                                 len(r["rows"]), sum(x["fail"] for x in r["rows"]),
                                 r["size"]))
    md.append("")
    fails = [(s, x) for s, r in acc.items() for x in r["rows"] if x["fail"]]
    if fails:
        md += ["Failures:", ""] + ["- %s %s: Hausdorff %.3f, holes %d (reference %d) %s"
                                   % (s, x["name"], x["err"], x["holes"], x["ref_holes"],
                                      x["fallback"]) for s, x in fails] + [""]
    counters = [x for x in acc[".otf"]["rows"] if x["name"] in ("o", "e", "a", "eight")]
    return md + ["Counters: " + ", ".join("%s %d (reference %d)" % (x["name"], x["holes"],
                                                                 x["ref_holes"])
                                          for x in counters) + ".", ""]


def _peer_table(title, rows, opt):
    """The table of a nib's rows (morph, FontForge, Skia) on Relief."""
    md = ["## %s" % title, "",
          "| tool | setting | in process: mean ms / glyph | in process: median ms / "
          "glyph | whole command ms / glyph | whole workflow ms / glyph | morph: "
          "stroke + export ms | points / glyph | max Hausdorff | mean | failures | "
          "morph / FontForge: in process; command / worker; command / workflow |",
          "|---|---|---|---|---|---|---|---|---|---|---|---|"]
    pairs = {id(r): m for r, m in equal_error(rows)}
    default = next((r for r in rows if r["tool"] == "morph" and r["setting"] == "tol %g"
                    % opt.tol), None)
    for r in rows:
        split = ("%.1f + %.1f" % (r["stroke_ms"], r["export_ms"])
                 if "stroke_ms" in r else "")
        median = "(chunks)" if r["tool"] == "morph" else _ms(r["median_ms"])
        m = (pairs.get(id(r)) or default) if r["tool"] == "FontForge" else None
        ratios = "; ".join(_paired(m, r, m.get("command_runs"))) if m else ""
        md.append("| %s | %s | %s | %s | %s | %s | %s | %.0f | %.3f | %.3f | %s | %s |"
                  % (r["tool"], r["setting"], _ms(r["ms"]), median,
                     _ms(r.get("command_ms", r.get("process_ms"))),
                     _ms(r.get("command_ms", r.get("workflow_ms"))), split, r["points"],
                     r["max_err"], r["mean_err"], ", ".join(r["fails"]) or "0", ratios))
    return md


def _relief_peers(font, names, spec, title, refs, keys, opt):
    """(rows, notes) of one nib on Relief: FontForge's outlines and errors (cached),
    then ``--morph-repeat`` rounds of morph's in-process pass over ``--morph-tols``,
    its command at each of them, FontForge's worker and its whole workflow at each
    ``--ff-accuracy`` (:mod:`bench.paired`); Skia for the round nib."""
    from bench.paired import median

    tols, accs = _floats(opt.morph_tols), _floats(opt.ff_accuracy)
    ff, why = run_fontforge(font, names, spec, accs, refs, _plain_judge(refs, keys))
    runs = {tol: [] for tol in tols}
    with tempfile.TemporaryDirectory() as tmp:
        rounds = FontForgeRounds(fontforge_jobs(font, names, spec, accs[:len(ff)]), names,
                                 SUBSET, spec, tmp, glyphs=names)
        commands, shared = {}, None
        for tol in tols:   # one warm-up fills the bytecode cache they share
            commands[tol] = _command_runner(
                SUBSET, Path(tmp) / "relief.otf", names[0],
                ["--glyphs", opt.glyphs, "--tol", repr(tol / 1000.0),
                 "--nib", "ellipse:%g,%g,%g" % nib_axes(spec)], shared)
            shared = commands[tol].env

        def between(_round):   # after each in-process pass: the commands, then FontForge
            for tol in tols:
                cpu, _, _, rc = commands[tol]()
                runs[tol].append(1000 * cpu / len(names) if rc in (0, 1) else None)
            rounds()

        rows = run_morph(font, names, spec, tols, refs, repeat=opt.morph_repeat,
                         between=between)
        rounds.fill(ff)
    for r, tol in zip(rows, tols):
        ok = [v for v in runs[tol] if v is not None]
        r["command_runs"], r["command_ms"] = runs[tol], median(ok)
    notes = ["FontForge not run (%s)." % why] if why else []
    notes += ["FontForge, %s, %s: %s; its whole workflow (`bench/fontforge_font.py`): %s."
              % (title.split(":")[0].lower(), s, f, w) for s, f, w in _fontforge_measured(ff)]
    rows += ff
    if spec is ROUND:
        rows += run_skia(font, names, spec[1], _floats(opt.skia_scales), refs)
    return rows, notes


def _parser():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--glyphs", default="A-Z,a-z,0-9")
    ap.add_argument("--tol", type=float, default=0.5, help="font units")
    ap.add_argument("--ref-tol", type=float, default=0.02, help="font units")
    ap.add_argument("--morph-tols", default="4,2,1,0.5,0.25")
    ap.add_argument("--ff-accuracy", default="2,1,0.25,0.1")
    ap.add_argument("--skia-scales", default="1,4,16")
    ap.add_argument("--no-peers", action="store_true")
    ap.add_argument("--no-accuracy", action="store_true")
    ap.add_argument("--md", default=str(ROOT / "bench" / "stroke.md"))
    ap.add_argument("--no-write", action="store_true")
    ap.add_argument("--morph-repeat", type=int, default=3,
                    help="rounds of the timings, morph's and FontForge's interleaved (each "
                         "time the median of its rounds)")
    ap.add_argument("--sets", default=None,
                    help="skeleton sets of bench/skeletons.py for part 3 (default: %s with "
                         "--only-sets, none without)" % ",".join(SETS))
    ap.add_argument("--set-tol", type=float, default=0.0005, help="em, part 3")
    ap.add_argument("--set-tols-more", default="2",
                    help="part 3: morph also at these multiples of --set-tol (comma "
                         "separated; empty: none), for the comparison at equal measured error")
    ap.add_argument("--ff-accuracy-sets", default="1,0.25")
    ap.add_argument("--only-sets", action="store_true", help="part 3 only")
    ap.add_argument("--sets-md", default=str(ROOT / "bench" / "stroke_sets.md"))
    ap.add_argument("--sets-json", help="a folder: sets saved there are reported as "
                                        "measured then, sets measured now are saved there")
    return ap


def main(argv=None):
    opt = _parser().parse_args(argv)
    if opt.sets is None:
        from bench.skeletons import available

        opt.sets = ",".join(available(SETS)) if opt.only_sets else ""
    argv = sys.argv[1:] if argv is None else argv
    opt.argline = (" " + " ".join(argv)) if argv else ""
    from bench.stroke_profile import shown_args

    opt.set_argline = "".join(" " + a for a in shown_args(argv, ("--md", "--sets-md",
                                                                 "--sets-json"))
                              if a != "--only-sets")
    import logging

    for name in ("ufo2ft", "fontTools"):
        logging.getLogger(name).setLevel(logging.ERROR)
    t_start = time.perf_counter()
    if opt.sets:
        with tempfile.TemporaryDirectory() as tmp:
            sets = [measured_set(s, opt, tmp) for s in opt.sets.split(",")]
        text = sets_markdown(opt, sets, time.perf_counter() - t_start)
        print(text)
        if not opt.no_write:
            Path(opt.sets_md).write_text(text)
    if opt.only_sets:
        return 0
    font = load_ufo(SUBSET, lazy=False)
    names = glyph_names_for(font, parse_glyph_spec(opt.glyphs))
    notes = []
    refs, keys = {}, {}
    for spec in (BROAD, ROUND):
        refs[spec], keys[spec], note = references(font, names, spec, opt.ref_tol)
        notes.append("Clipper reference, %s nib: %s." % (spec[0], note))
        print("reference %s: %d glyphs, %s" % (spec[0], len(names), note), flush=True)
    acc = {}
    if not opt.no_accuracy:
        with tempfile.TemporaryDirectory() as tmp:
            acc = accuracy_sweep(font, names, opt.tol, opt.ref_tol, refs[BROAD], tmp)
    peers = []
    for spec, title in (() if opt.no_peers else (
            (BROAD, "Broad nib: ellipse 90 x 20 at 30 degrees"),
            (ROUND, "Round nib: disk of diameter 60"))):
        rows, more = _relief_peers(font, names, spec, title, refs[spec], keys[spec], opt)
        notes += more
        for r in rows:
            print("%s %s %s: %s ms, %.0f points, max err %.3f" % (
                title.split(":")[0], r["tool"], r["setting"], _ms(r["ms"]), r["points"],
                r["max_err"]), flush=True)
        peers.append((title, rows))
    text = markdown(opt, names, acc, peers, notes, time.perf_counter() - t_start)
    print(text)
    if not opt.no_write:
        Path(opt.md).write_text(text)
    failures = sum(x["fail"] for r in acc.values() for x in r["rows"])

    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

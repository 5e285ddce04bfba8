"""Per-glyph work for font commands (brush, stroke): one job runner, one fallback
ladder and a polygon fallback, so that one failing glyph never loses the font.

:func:`run_glyph_jobs` is the runner both font writers use: the glyphs' jobs in
chunks of at most :data:`CHUNK` (:func:`glyph_chunks`, by the number of glyphs
alone), each chunk a process-pool job (:func:`run_jobs`), every glyph's result
handed to a callback as its chunk is done.  While a chunk runs, its job reports
the work it has done (:func:`glyph_progress`: its sums, then its batched curve
conversion as the segment searches end, :func:`converting`) to the calling
process through a queue, so that progress moves within a chunk: smaller chunks
would cost throughput (the batch's rounds cost the same however many glyphs share
them: 288 stroked Relief glyphs in batches of 96 / 48 / 24 took 5.1 / 6.0 / 6.2 s
of CPU).  :func:`fallback_ladder` is the policy
both use when a glyph's exact computation fails: the next rung is tried on a
:class:`morph.errors.MorphError` only (the geometry saying it cannot, within its
budget); any other exception is a programming error and propagates, so the command
fails with an internal error (exit 1, the traceback under MORPH_DEBUG) instead of
hiding it in a fallback.

:func:`run_jobs` maps a module-level function over glyph jobs in ``jobs`` worker
processes and returns the results in input order: every job is computed by the same
code on the same input, so the output does not depend on ``jobs`` (tested against
``jobs=1``).  A job whose worker dies (e.g. killed for memory) is run again in the
calling process.

:func:`polygon_sum` is the documented fallback for a sum that raised: the operands
are flattened (chords within ``tol / 2`` of each curve, so the result is within
``tol`` of the exact A ⊕ B in Hausdorff distance) and summed exactly on Clipper's
integer grid (1/16 font unit): (∂A ⊕ ∂B) ∪ (A + b0) ∪ (a0 + B) for every loop.  The
result is polygonal: correct to tol, but made of short lines where the exact method
writes a few curves (several times more points, no smooth joins).
"""

import itertools
import math
import os

import numpy as np

from ..budget import POLYGON_SHARE
from ..region import polyline_edges, region_polylines

__all__ = ["default_jobs", "run_jobs", "run_glyph_jobs", "glyph_chunks", "CHUNK", "MIN_SPLIT",
           "glyph_progress", "converting", "SUM_SHARE", "fallback_ladder", "error_text",
           "polygon_sum", "polylines_to_contours"]

_SCALE = 16.0  # Clipper integer units per font unit


def default_jobs():
    """The number of processes to use by default: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


# ====================================================================== progress
#
# A job (a chunk of glyphs) reports the work it has done before it returns with
# glyph_progress(units): in a worker process the message (job index, units) goes to
# the calling process through a queue (a few bytes per message), in the calling
# process (jobs=1) straight to the runner's ``partial`` callback.

_REPORT = None      # this process's reporter: units -> None (None: nobody listens)


def glyph_progress(units):
    """Say that the job running in this process has done ``units`` glyphs' worth
    of its work (e.g. ``SUM_SHARE * n`` once the sums of its n glyphs are done):
    handed to the ``partial`` callback of :func:`run_jobs` in the calling process.
    A no-op when nobody listens."""
    if _REPORT is not None and units:
        _REPORT(float(units))


#: A glyph's sum (brush) or stroke (stroke) is about this share of its work, its
#: curve conversion the rest: measured 0.26 (brush of the bundled font, 196
#: glyphs) and 0.29 (stroke of Relief SingleLine, 584 glyphs) of the CPU time of
#: the chunk jobs.  A job reports this much per glyph once its sums are done, so
#: that progress moves within a chunk.
SUM_SHARE = 0.3



def converting(glyphs):
    """A context for the batched curve conversion of ``glyphs`` glyphs in a job:
    as the batch's segment searches end (:func:`morph.export.search.
    observe_searches`), the job reports their share of the glyphs' remaining
    work, ``(1 - SUM_SHARE) x glyphs x searches done / searches`` in all (never
    more: a second batch in the block reports only what goes beyond the first)."""
    from ..export.search import observe_searches

    if _REPORT is None or not glyphs:
        import contextlib

        return contextlib.nullcontext()
    sent = [0.0]
    whole = (1.0 - SUM_SHARE) * glyphs

    def report(done, total):
        units = whole * done / max(total, 1)
        if units > sent[0]:
            glyph_progress(units - sent[0])
            sent[0] = units
    return observe_searches(report)


_QUEUE = None       # a worker's queue to the calling process (set by _init_worker)


def _init_worker(queue):
    global _QUEUE
    _QUEUE = queue


def _queued_call(func, k, arg):
    """``func(arg)`` in a worker, its :func:`glyph_progress` sent as ``(k, units)``."""
    global _REPORT
    _REPORT = (lambda units: _QUEUE.put((k, units))) if _QUEUE is not None else None
    try:
        return func(arg)
    finally:
        _REPORT = None


def _local_call(func, k, arg, partial):
    """``func(arg)`` in this process, its :func:`glyph_progress` to ``partial(k, units)``."""
    global _REPORT
    before = _REPORT
    _REPORT = None if partial is None else (lambda units: partial(k, units))
    try:
        return func(arg)
    finally:
        _REPORT = before


def run_jobs(func, args, jobs=1, progress=None, keep=True, partial=None, preload=()):
    """``[func(a) for a in args]``, computed by ``jobs`` processes, in input order.

    ``func`` must be a module-level function (it is pickled by reference) and its
    arguments and results picklable.  ``args``: any iterable; it is consumed as the
    processes need work (at most ``2 * jobs`` jobs ahead of the results), so a
    generator's arguments are made as they are needed, not all first.  ``jobs <= 1``
    (or one job) runs in this process.  ``progress(index, result)`` is called in
    this process as each job finishes (in completion order).  ``partial(index,
    units)`` is called in this process (from a thread of its own when there are
    workers) for every :func:`glyph_progress` a job makes while it runs; such a
    message may come after the job's ``progress``.  ``keep=False`` streams: each
    result is dropped once ``progress`` has had it (the list returned holds None), so
    that memory does not grow with the number of jobs.  An exception raised by
    ``func`` propagates; a job whose worker process died is run again here, and all
    of them when no process pool can be started.  ``preload``: names of the modules
    ``func`` imports as it runs, imported here before the workers start
    (:func:`preload_modules`).
    """
    args = iter(args)
    results = []

    def done(k, result):
        if progress is not None:
            progress(k, result)
        if keep:
            results[k] = result

    first = list(itertools.islice(args, 2))
    args = itertools.chain(first, args)
    pool = _pool(int(jobs or 1), partial, preload) if len(first) > 1 else None
    if pool is None:                     # one process, or no process pool here
        for k, a in enumerate(args):
            results.append(None)
            done(k, _local_call(func, k, a, partial))
        return results
    lost = _pooled(pool, func, args, int(jobs), results, done, partial)
    for k, a in sorted(lost, key=lambda ka: ka[0]):
        done(k, _local_call(func, k, a, partial))
    return results


def preload_modules(names):
    """Import the modules ``names`` in this process when its worker processes are
    forked (the start method on Linux up to Python 3.13): the workers then share
    them, where each would import them itself (a stroke worker's geometry, curve
    fitting and CFF modules: about 70 ms of CPU per worker, the calling process
    needing most of them later anyway).  Under another start method the workers
    start from a fresh interpreter and import what they need: nothing is done."""
    import importlib
    import multiprocessing

    if names and multiprocessing.get_start_method() == "fork":
        for name in names:
            importlib.import_module(name)


def _pool(jobs, partial, preload=()):
    """``(ProcessPoolExecutor, queue)`` of ``jobs`` workers, the queue (None without
    ``partial``) carrying their :func:`glyph_progress` to this process; None for one
    job or where no process pool can be started.  The modules ``preload`` are
    imported first (:func:`preload_modules`)."""
    if jobs <= 1:
        return None
    import multiprocessing
    from concurrent.futures import ProcessPoolExecutor

    preload_modules(preload)

    try:
        queue = multiprocessing.SimpleQueue() if partial is not None else None
        return ProcessPoolExecutor(max_workers=jobs, initializer=_init_worker,
                                   initargs=(queue,)), queue
    except (OSError, NotImplementedError, ImportError):
        return None


def _pooled(pool, func, args, jobs, results, done, partial):
    """The jobs of ``args`` submitted to the pool (``pool`` from :func:`_pool`) as
    its workers need them, at most ``2 * jobs`` in flight; each result handed to
    ``done(index, result)`` as it comes, the progress messages to ``partial`` by a
    listening thread.  Returns the (index, argument) of the jobs whose worker died,
    for the caller to run."""
    import functools
    import threading
    from concurrent.futures import FIRST_COMPLETED, wait
    from concurrent.futures.process import BrokenProcessPool

    pool, queue = pool
    lost = []
    listener = None
    if queue is not None:
        def listen():
            for message in iter(queue.get, None):
                partial(*message)
        listener = threading.Thread(target=listen, daemon=True)
        listener.start()
    call = functools.partial(_queued_call, func)
    try:
        with pool:
            pending = {}                  # future -> (index, argument), while it runs
            for k, a in enumerate(args):
                results.append(None)
                try:
                    pending[pool.submit(call, k, a)] = (k, a)
                except BrokenProcessPool:  # a worker died: the pool takes no more
                    lost.append((k, a))
                    continue
                while len(pending) >= 2 * jobs:
                    _collect(pending, wait(pending, return_when=FIRST_COMPLETED)[0], done,
                             lost)
            while pending:
                _collect(pending, wait(pending, return_when=FIRST_COMPLETED)[0], done, lost)
    finally:
        if listener is not None:        # the workers are gone: their messages are in
            queue.put(None)
            listener.join()
    return lost


def _collect(pending, finished, done, lost):
    """Hand the ``finished`` futures' results to ``done`` (index, result) and drop
    them from ``pending``; a job whose worker died goes to ``lost``."""
    from concurrent.futures.process import BrokenProcessPool

    for fut in finished:
        k, a = pending.pop(fut)           # the future, and its result, go when done
        try:
            result = fut.result()
        except BrokenProcessPool:
            lost.append((k, a))
            continue
        done(k, result)


#: At most this many glyphs per job of :func:`run_glyph_jobs` (their curve
#: conversions go in one batch: a batch's rounds cost the same however many glyphs
#: share them, so its cost per glyph falls with its size: 62 stroked Relief glyphs
#: 26 / 19 / 13 ms each in batches of 16 / 48 / 124); equal chunks by the number of
#: glyphs alone (or by their weights), not by the number of processes: the font does
#: not depend on it (:func:`glyph_chunks`).
CHUNK = 96
#: A font is cut in two chunks (two processes share it) only when each gets at least
#: this many glyphs (or glyphs' worth of weight): a batch's export rounds cost about
#: the same however few glyphs share them (62 brushed Noto Sans letters and digits:
#: 15.5 ms of export CPU a glyph in two batches of 31, 11.1 in one; Relief's 321
#: glyphs with contours, 45 glyphs' worth: 4.5-4.9 s of CPU for the whole font in two
#: chunks, 4.3 in one), so a smaller font is one chunk, one batch.
MIN_SPLIT = CHUNK // 2


def glyph_chunks(work, size=CHUNK, weights=None):
    """``work`` in consecutive chunks of equal length (within one), at most ``size``
    each; two chunks rather than one (so that two processes share the font) when
    each gets at least :data:`MIN_SPLIT` glyphs.  By the number of glyphs alone: the
    batches, hence the font, do not depend on the number of processes.

    ``weights`` (one per glyph, in glyphs of average work; None: 1 each): the
    chunks are of equal weight (within one glyph's), at most ``size`` in weight, and
    two when each gets :data:`MIN_SPLIT` in weight, so that as many glyphs share a
    batch as memory allows however light or heavy they are (a stroke font's glyphs
    weigh their skeleton contours, :func:`morph.fonts.stroke._stroke_weights`)."""
    n = len(work)
    w = np.ones(n) if weights is None else np.asarray(weights, float)
    cum = np.concatenate([[0.0], np.cumsum(w)])
    if w.shape != (n,) or not np.all(np.isfinite(w)) or np.any(w < 0):
        raise ValueError("glyph_chunks: weights must be one finite weight >= 0 per glyph")
    halves = int(cum[-1] // MIN_SPLIT) if MIN_SPLIT > 0 else 2
    count = min(n, max(1, int(math.ceil(cum[-1] / size)), min(2, halves)))
    if not count:
        return []
    # edge i: the glyph boundary where the weight so far is nearest to i / count of it
    # (a tie to the even boundary: with weights 1, Python's round(i n / count))
    goal = cum[-1] * np.arange(1, count) / count
    right = np.clip(np.searchsorted(cum, goal), 1, n)
    below, above = goal - cum[right - 1], cum[right] - goal
    edges = np.where((below < above) | ((below == above) & (right % 2 == 1)), right - 1, right)
    edges = [0] + sorted(set(edges.tolist()) - {0, n}) + [n]
    return [work[a:b] for a, b in zip(edges, edges[1:])]


def run_glyph_jobs(func, work, jobs=1, each=None, keep=True, prepare=None, in_flight=None,
                   preload=(), weights=None):
    """The font writers' job runner: ``func`` (module-level, a list of glyph jobs ->
    a list of their results) over ``work`` in :func:`glyph_chunks`, computed by
    ``jobs`` processes (:func:`run_jobs`).  ``prepare`` (None: the chunks as they
    are) makes a chunk's jobs from its part of ``work`` in this process, when the
    processes need it (e.g. ``work`` glyph names, the jobs their outlines read then).
    ``each(result)`` is called in this process for every glyph's result, in input
    order within a chunk, as its chunk is done.  ``in_flight(units)``: the change in
    the glyphs' worth of work that chunks not yet done have reported
    (:func:`glyph_progress`): positive as they report, minus a chunk's reports just
    before its glyphs go to ``each``; a progress display adds it to the glyphs done.
    Returns the results in input order, or with ``keep=False`` nothing (each chunk's
    results dropped once ``each`` had them: memory does not grow with the number of
    glyphs).  ``preload``: the modules ``func`` imports, imported here before the
    processes start (:func:`preload_modules`).  ``weights``: the glyphs' weights for
    :func:`glyph_chunks` (None: the glyphs counted)."""
    import threading

    lock = threading.Lock()
    reported, finished = {}, set()

    def part(index, units):
        with lock:
            if index in finished:   # a late message of a chunk done already
                return
            reported[index] = reported.get(index, 0.0) + units
            in_flight(units)

    def done(index, results):
        if in_flight is not None:
            with lock:
                finished.add(index)
                units = reported.pop(index, 0.0)
                if units:
                    in_flight(-units)
        if each is not None:
            for r in results:
                each(r)

    chunks = glyph_chunks(work, weights=weights)
    if prepare is not None:
        chunks = (prepare(c) for c in chunks)
    chunks = run_jobs(func, chunks, jobs=jobs, keep=keep, progress=done,
                      partial=part if in_flight is not None else None, preload=preload)
    return [r for rs in chunks for r in rs] if keep else None


# =========================================================================== fallback

def error_text(exc):
    """``Type: message`` on one line: how a fallback names the error it recovered
    from."""
    from ..errors import one_line

    return "%s: %s" % (type(exc).__name__, one_line(exc))


def fallback_ladder(rungs, error=None):
    """The first rung that succeeds: ``rungs`` yields ``(kind, thunk)``; each thunk is
    called in turn until one returns.  Returns ``(kind, value, error)``: ``error``
    the text of the first :class:`morph.errors.MorphError` met (the one given when
    earlier rungs failed already; None when the first rung succeeded);
    ``(None, None, error)`` when every rung raised, the last rung's error appended.
    Only a MorphError moves down the ladder: any other exception is a programming
    error and propagates."""
    from ..errors import MorphError

    last = None
    for kind, thunk in rungs:
        try:
            return kind, thunk(), error
        except MorphError as exc:
            last = "%s fallback: %s" % (kind, error_text(exc))
            error = error_text(exc) if error is None else error
    return None, None, error if last is None else "%s; %s" % (error, last)


def _clipper_paths(polylines):
    return [[(int(round(x * _SCALE)), int(round(y * _SCALE))) for x, y in p]
            for p in polylines]


def polygon_sum(loops_a, loops_b, tol, closed=True):
    """Polygon Minkowski sum A ⊕ B with pyclipper: closed polylines, outer
    counter-clockwise, holes clockwise (y up), in the operands' units.

    ``loops_a``: a region (loops of pieces), or with ``closed=False`` a list of open
    paths (lists of pieces, e.g. a stroke skeleton); ``loops_b``: a region (the nib).
    Each operand is flattened within ``POLYGON_SHARE * tol``; the sum of the polygons is exact
    up to the 1/16 unit grid, so the result is within tol + 1/8 of the exact sum
    (Hausdorff distance).  Slivers that Clipper's union leaves (polygons of mean
    width 2 area / perimeter below tol) are dropped.  Returns a list of (m, 2) arrays.
    """
    import pyclipper

    if closed:
        pa = _clipper_paths(region_polylines(loops_a, POLYGON_SHARE * tol))
    else:
        from .. import polyline as pl

        pa = []
        for path in loops_a:
            flat = pl.flatten_many(path, POLYGON_SHARE * tol)
            pts = np.concatenate([f[0][:-1] for f in flat] + [flat[-1][0][-1:]])
            pa.extend(_clipper_paths([pts]))
    pb = _clipper_paths(region_polylines(loops_b, POLYGON_SHARE * tol))
    if not pa or not pb:
        return []
    pieces = []
    for path_b in pb:
        for path_a in pa:
            pieces.extend(pyclipper.MinkowskiSum(path_b, path_a, closed))
        if closed:  # the interiors: A + (a point of B), B + (a point of A)
            bx, by = path_b[0]
            pieces.extend([[(x + bx, y + by) for x, y in p] for p in pa])
    if closed:
        for path_a in pa:
            ax, ay = path_a[0]
            pieces.extend([[(x + ax, y + ay) for x, y in p] for p in pb])
    else:
        for path_a in pa:  # the pen at the start of each open path
            ax, ay = path_a[0]
            pieces.extend([[(x + ax, y + ay) for x, y in p] for p in pb])
    clip = pyclipper.Pyclipper()
    try:
        clip.AddPaths([p for p in pieces if len(p) >= 3], pyclipper.PT_SUBJECT, True)
        paths = clip.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
    except pyclipper.ClipperException as exc:  # paths Clipper cannot take: the ladder's end
        from ..errors import MorphError

        raise MorphError("Clipper cannot unite the polygon sum: %s" % exc) from exc
    out = []
    for p in paths:
        p = np.asarray(p, float) / _SCALE
        if len(p) < 3:
            continue
        a, b = polyline_edges([p])
        area = 0.5 * abs(np.sum(a[:, 0] * b[:, 1] - b[:, 0] * a[:, 1]))
        perimeter = np.sum(np.hypot(*(b - a).T))
        if 2.0 * area > tol * perimeter:  # mean width 2 area / perimeter: not a sliver
            out.append(p)
    return out


def polylines_to_contours(polylines, reverse=False, offset=(0.0, 0.0)):
    """Closed polylines -> contours of line segments (see :mod:`morph.fonts.tables`),
    translated by ``offset``, reversed when ``reverse`` (TrueType direction), cleaned
    on the integer grid."""
    from .tables import clean_contour

    off = np.asarray(offset, float)
    out = []
    for p in polylines:
        p = np.asarray(p, float) + off
        if reverse:
            p = p[::-1]
        segs = [np.array([p[k], p[(k + 1) % len(p)]]) for k in range(len(p))]
        contour = clean_contour(segs)
        if contour:
            out.append(contour)
    return out

"""Per-glyph work for font commands (brush, stroke): a process pool, and a polygon
fallback so that one failing glyph never loses the font.

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

import os

import numpy as np

from ..budget import POLYGON_SHARE
from ..region import polyline_edges, region_polylines

__all__ = ["default_jobs", "run_jobs", "polygon_sum", "polylines_to_contours"]

_SCALE = 16.0  # Clipper integer units per font unit


def default_jobs():
    """The number of processes to use by default: the CPUs this process may use."""
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except (AttributeError, OSError):  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


def run_jobs(func, args, jobs=1, progress=None):
    """``[func(a) for a in args]``, computed by ``jobs`` processes, in input order.

    ``func`` must be a module-level function (it is pickled by reference) and its
    arguments and results picklable.  ``jobs <= 1`` (or one job) runs in this
    process.  ``progress(index, result)`` is called in this process as each job
    finishes (in completion order).  An exception raised by ``func`` propagates;
    a job whose worker process died is run again here, and all of them when no
    process pool can be started.
    """
    args = list(args)
    results = [None] * len(args)
    jobs = int(jobs or 1)
    if jobs <= 1 or len(args) <= 1:
        for k, a in enumerate(args):
            results[k] = func(a)
            if progress is not None:
                progress(k, results[k])
        return results
    from concurrent.futures import ProcessPoolExecutor, as_completed
    from concurrent.futures.process import BrokenProcessPool

    lost = []
    try:
        pool = ProcessPoolExecutor(max_workers=min(jobs, len(args)))
    except (OSError, NotImplementedError, ImportError):  # no process pool here: serially
        return run_jobs(func, args, jobs=1, progress=progress)
    with pool:
        futures = {pool.submit(func, a): k for k, a in enumerate(args)}
        for fut in as_completed(futures):
            k = futures[fut]
            try:
                results[k] = fut.result()
            except BrokenProcessPool:
                lost.append(k)
                continue
            if progress is not None:
                progress(k, results[k])
    for k in sorted(lost):
        results[k] = func(args[k])
        if progress is not None:
            progress(k, results[k])
    return results


# =========================================================================== fallback

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
    clip.AddPaths([p for p in pieces if len(p) >= 3], pyclipper.PT_SUBJECT, True)
    paths = clip.Execute(pyclipper.CT_UNION, pyclipper.PFT_NONZERO, pyclipper.PFT_NONZERO)
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

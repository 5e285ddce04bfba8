"""Loops and regions to cubics: loops split at their corners, cubics spanning the
smooth joins, the searches of all loops batched.

**Loops.**  A sum splits one smooth convolution curve into many pieces; fitting
piece by piece spends one cubic or more on each.  :func:`loop_to_beziers` splits a
loop at its corners only (:func:`smooth_runs`) and lets cubics span the smooth joins
(:func:`chain_segments`): the certificate cuts the cubic at the feet of the join
points and certifies each part against its piece, phi mapping the cut to the join.
Writers of whole outlines (SVG, fonts) call the loop functions with ``wrap=True`` (a
smooth closing join is spanned as well) and the export share of the user's
tolerance (:func:`morph.budget.plan`, or :meth:`morph.budget.Budget.after` when the
geometry has a certified error below its share).
"""

import math

import numpy as np

from .. import bernstein as bz
from .bank import RunArrays, plan_run_arrays, plan_runs
from .corners import cut_corners
from .search import runs_segments, ufunc_buffer


#: Joins whose tangent directions differ by less than this angle (radians) are smooth:
#: the loop exporters let cubics span them.
JOIN_ANGLE = 1e-6


def smooth_runs(pieces, join_angle=JOIN_ANGLE):
    """Consecutive pieces split at corners into maximal runs of smooth (G1) joins.

    A join is smooth when the pieces meet (within 1e-12 of the coordinates) and their
    tangent directions there differ by less than ``join_angle`` radians.  A straight
    polynomial piece (a line) is a run of its own: written as a line it costs one
    point, which no cubic spanning it beats (brushed M: 46 points instead of 78).
    ``join_angle <= 0``: every piece is a run of its own (fitting piece by piece:
    about 4 times less CPU than spanning joins, about twice the cubics).
    Returns a list of lists of pieces, in order (a closed loop is not wrapped
    around: its first run starts at its first piece).  :func:`morph.export.bank.
    plan_runs` does this for every loop of a batch at once.
    """
    pieces = [np.asarray(p, float) for p in pieces]
    if not pieces:
        return []
    _, (runs,) = plan_runs([pieces], join_angle, wrap=False)
    return [[pieces[g] for g in run] for run, _ in runs]


def loop_to_beziers(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Polynomial Béziers within ``tol`` of a loop (or any chain of consecutive pieces).

    Returns (2, 2) lines, (3, 2) quadratics and (4, 2) cubics in order, end to start,
    the first starting at the loop's start.  The loop is split into runs at its
    corners (:func:`smooth_runs`).  With ``wrap`` (a closed loop, the last piece
    ending where the first starts, written by a caller that does not need the output
    to start at the loop's start: SVG subpaths, font contours) a smooth closing join
    is spanned too: the last run and the first are one, and the output starts at
    the start of the loop's last run (at the loop's start when a corner is there).
    A run of polynomial pieces of degree <= 3 is returned
    exactly (lines stay lines, quadratics quadratics: no fitting time is spent on
    what is exact already, e.g. TrueType glyph sums), every other run becomes
    certified cubics (:func:`chain_segments`) that may span its smooth joins: each
    cubic is within ``tol`` of the run in Fréchet, hence Hausdorff, distance, so the
    whole output is within ``tol`` of the loop.  This is what writers of whole
    outlines should call: a smooth curve that the sum split into many pieces needs
    far fewer cubics than the pieces one by one (:func:`piece_to_cubics`).  Writers
    of several loops call :func:`loops_to_beziers` (the same, all loops' runs
    fitted in one batch).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics.
    """
    return loops_to_beziers([loop], tol, max_depth, join_angle, wrap)[0]


def loops_to_beziers(loops, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """:func:`loop_to_beziers` of every loop of a region (a list per loop), with the
    segment searches of all their runs in lockstep: each round's fits of the whole
    region are fitted and certified in one batch (the numerical work is a few array
    calls per round, not per loop; callers batch the loops of many glyphs too).
    Every curve is certified within tol as loop by loop; the curves themselves may
    differ from loop-by-loop ones by rounding (batched array calls).

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    with ufunc_buffer():                  # the pieces' arrays and the corners too
        return _loops_to_beziers(loops, tol, max_depth, join_angle, wrap)


def _loops_to_beziers(loops, tol, max_depth, join_angle, wrap):
    """:func:`loops_to_beziers`, its arguments checked."""
    bank, runs = plan_run_arrays(loops, join_angle, wrap)
    keep = cut_corners(bank, runs, tol, wrap)    # short arcs between lines: their corner
    runs = RunArrays(runs.order[np.repeat(keep, runs.sizes)], runs.sizes[keep],
                     runs.exact[keep], runs.loop[keep])
    piece_exact = np.repeat(runs.exact, runs.sizes)
    fit = ~runs.exact
    fitted = runs_segments(bank, RunArrays(runs.order[~piece_exact], runs.sizes[fit],
                                           runs.exact[fit], runs.loop[fit]),
                           tol, max_depth, cubics_only=True)
    # exact already: no fitting (lines stay lines, quadratics quadratics); each run's
    # curves in one list, the runs of a loop concatenated in order
    written = bank.cartesian(runs.order[piece_exact])
    ends = runs.sizes[runs.exact].cumsum().tolist()
    curves = [None] * runs.exact.shape[0]                  # each run's curves, in order
    for r, a, b in zip(runs.exact.nonzero()[0].tolist(), [0] + ends[:-1], ends):
        curves[r] = written[a:b]
    for r, c in zip((~runs.exact).nonzero()[0].tolist(), fitted):
        curves[r] = c
    out = [[] for _ in loops]
    for i, c in zip(runs.loop.tolist(), curves):
        out[i] += c
    return out


def loop_to_cubics(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Cubics within ``tol`` of a loop, in order: :func:`loop_to_beziers` with every
    line and quadratic degree-elevated (exactly)."""
    return [bz.to_degree(b, 3)
            for b in loop_to_beziers(loop, tol, max_depth, join_angle, wrap)]

"""TrueType export: certified cubics converted to quadratic splines with cu2qu's
algorithm (:mod:`.cu2qu`, every cubic of a batch at once), the export tolerance
split between the two (:data:`morph.budget.QUADRATIC_CUBIC_SHARE`).
"""

import math
from itertools import chain

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..budget import QUADRATIC_CUBIC_SHARE
from .certify import check_piece
from .cu2qu import cubic_splines, spline_quadratics
from .loops import JOIN_ANGLE, loops_to_beziers
from .search import piece_to_cubics, ufunc_buffer


def _cubics_to_quadratics(cubics, tol, splines=False):
    """cu2qu's conversion of each cubic within tol, all in one batch
    (:func:`.cu2qu.cubic_splines`): a list of (3, 2) quadratics with explicit
    on-curve points, each cubic's in order, or with ``splines`` one (n + 2, 2)
    TrueType spline per cubic: its end points and its n off-curve points, the
    on-curve points between them implied (midpoints)."""
    return _with_quadratics(list(cubics), tol, splines)[0]


def _with_quadratics(curves, tol, splines=False):
    """``curves`` (lines, quadratics and cubics) in order with every cubic replaced by
    its conversion (:func:`_cubics_to_quadratics`): the cubics converted in one
    batch, the list put together with a few array calls (no loop over curves);
    and (len(curves),) the number of output curves of each."""
    sizes = np.fromiter(map(len, curves), np.int64, len(curves))
    cubic = (sizes == 4).nonzero()[0]
    kept = (sizes != 4).nonzero()[0]
    cubics = np.array(list(map(curves.__getitem__, cubic.tolist())), float)
    counts, blocks = cubic_splines(cubics.reshape(-1, 4, 2), tol)
    per = np.ones(len(curves), np.int64)
    per[cubic] = 1 if splines else counts
    start = per.cumsum() - per                   # each curve's first output position
    parts = [(start[kept], list(map(curves.__getitem__, kept.tolist())))]
    for index, spline in blocks:                 # one block per number of segments
        if splines:
            parts.append((start[cubic[index]], list(spline)))
            continue
        quads = spline_quadratics(spline)        # (k, n, 3, 2)
        at = start[cubic[index]][:, None] + np.arange(quads.shape[1])
        parts.append((at.ravel(), list(quads.reshape(-1, 3, 2))))
    items = list(chain.from_iterable(part for _, part in parts))
    order = np.empty(len(items), np.int64)
    order[np.concatenate([at for at, _ in parts])] = np.arange(len(items))
    return list(map(items.__getitem__, order.tolist())), per


def piece_to_quadratics(piece, tol, max_depth=16):
    """Polynomial quadratics within ``tol`` of a piece, list of (3, 2) arrays.

    The budget is split: cubics within ``QUADRATIC_CUBIC_SHARE * tol``
    (:func:`piece_to_cubics`, certified Fréchet bound), then each cubic to a
    quadratic spline within the rest by cu2qu's algorithm (:mod:`.cu2qu`, the
    splines of ``fontTools.cu2qu.curve_to_quadratic``, all cubics in one batch).
    cu2qu's check is on a common parameter and certified up to rounding: it tests
    the difference curve's control points against the tolerance disk (convex hull)
    and subdivides.  The two errors add (Fréchet distance obeys the triangle
    inequality): the quadratics are within tol of the piece (Fréchet, hence
    Hausdorff).  Polynomial pieces of degree <= 2 are returned exactly.

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_cubics; also when cu2qu finds
            no spline within its limit of segments.
    """
    if not (tol > 0 and math.isfinite(tol)):
        raise ValueError("tol must be positive and finite, got %r" % (tol,))
    piece = check_piece(piece)
    if len(piece) <= 3 and pc.is_polynomial(piece):
        return [bz.to_degree(pc.cartesian(piece), 2)]
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    return _cubics_to_quadratics(piece_to_cubics(piece, cubic_tol, max_depth),
                                 tol - cubic_tol)


def loop_to_quadratics(loop, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False):
    """Quadratics (and lines) within ``tol`` of a loop, for TrueType outlines.

    :func:`loop_to_beziers` within ``QUADRATIC_CUBIC_SHARE * tol`` (certified Fréchet
    bound; cubics may span smooth joins), then every cubic to quadratics with cu2qu
    within the rest (its own certified same-parameter bound): the errors add, so
    every returned curve is within ``tol`` of the loop (Fréchet, hence Hausdorff).
    Lines come back as (2, 2) arrays and polynomial quadratics exactly; the rest
    are (3, 2) quadratics with explicit on-curve points (a TrueType writer may drop
    the implied midpoints).  :func:`loops_to_quadratics` does several loops in one
    batch.

    Raises:
        ValueError, ToleranceNotMetError: as piece_to_quadratics.
    """
    return loops_to_quadratics([loop], tol, max_depth, join_angle, wrap)[0]


def loops_to_quadratics(loops, tol, max_depth=16, join_angle=JOIN_ANGLE, wrap=False,
                        splines=False):
    """:func:`loop_to_quadratics` of every loop (a list per loop), the cubic stage
    batched over all loops as in :func:`loops_to_beziers` and the cubics of all loops
    converted in one batch; with ``splines`` each converted cubic is one TrueType
    spline (:func:`_cubics_to_quadratics`)."""
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    beziers = loops_to_beziers(loops, cubic_tol, max_depth, join_angle, wrap)
    curves = list(chain.from_iterable(beziers))
    with ufunc_buffer():
        out, per = _with_quadratics(curves, tol - cubic_tol, splines)
    loop = np.repeat(np.arange(len(beziers)), np.fromiter(map(len, beziers), np.int64,
                                                          len(beziers)))
    ends = np.bincount(loop, per, len(beziers)).astype(np.int64).cumsum().tolist()
    return [out[a:b] for a, b in zip([0] + ends[:-1], ends)]

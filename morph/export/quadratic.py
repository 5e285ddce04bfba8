"""TrueType export: certified cubics converted to quadratic splines with cu2qu, the
export tolerance split between the two (:data:`morph.budget.QUADRATIC_CUBIC_SHARE`).
"""

import math

import numpy as np

from .. import bernstein as bz
from .. import piece as pc
from ..budget import QUADRATIC_CUBIC_SHARE
from ..errors import ToleranceNotMetError
from .certify import check_piece
from .loops import JOIN_ANGLE, loops_to_beziers
from .search import piece_to_cubics


def _cubics_to_quadratics(cubics, tol, splines=False):
    """cu2qu on each cubic within tol; (3, 2) quadratics with explicit on-curve points,
    or with ``splines`` one (n + 2, 2) TrueType spline per cubic: its end points and
    its n off-curve points, the on-curve points between them implied (midpoints)."""
    from fontTools.cu2qu import curve_to_quadratic
    from fontTools.cu2qu.errors import Error as Cu2QuError

    out = []
    for cubic in cubics:
        try:        # Python floats: cu2qu converts numpy scalars slowly, one by one
            spline = curve_to_quadratic(np.asarray(cubic, float).tolist(), tol,
                                        all_quadratic=True)
        except Cu2QuError as exc:
            raise ToleranceNotMetError("cu2qu found no quadratic spline within %.3g"
                                       % tol, piece=cubic) from exc
        spline = np.asarray(spline, float)
        if splines:
            out.append(spline)
            continue
        offs = spline[1:-1]
        ons = np.concatenate([spline[:1], 0.5 * (offs[:-1] + offs[1:]), spline[-1:]])
        out.extend(np.stack([ons[:-1], offs, ons[1:]], axis=1))
    return out


def piece_to_quadratics(piece, tol, max_depth=16):
    """Polynomial quadratics within ``tol`` of a piece, list of (3, 2) arrays.

    The budget is split: cubics within ``QUADRATIC_CUBIC_SHARE * tol``
    (:func:`piece_to_cubics`, certified Fréchet bound), then each cubic to a
    quadratic spline within the rest with ``fontTools.cu2qu.curve_to_quadratic``.
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
    batched over all loops as in :func:`loops_to_beziers`; with ``splines`` each
    converted cubic is one TrueType spline (:func:`_cubics_to_quadratics`)."""
    cubic_tol = QUADRATIC_CUBIC_SHARE * tol
    out = []
    for beziers in loops_to_beziers(loops, cubic_tol, max_depth, join_angle, wrap):
        quads = []
        for b in beziers:
            if len(b) <= 3:
                quads.append(b)
            else:
                quads.extend(_cubics_to_quadratics([b], tol - cubic_tol, splines))
        out.append(quads)
    return out
